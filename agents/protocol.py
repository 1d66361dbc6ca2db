"""The protocols: the numbers a player of each game is judged by, for any policy.

    python -m agents.protocol --policies random ghost planner --episodes 20
    python -m agents.protocol --game slingshot --level handmade --episodes 20

plays ``Pool2D-v0``'s full game (the 15-ball rack, broken by the first shot; at most 30
shots) from the same seeded racks (env seeds ``--seed`` on) with each policy and prints,
per policy:

* reward: the game's return an episode (+1 a ball potted, -1 a scratch, -0.1 a shot that
  touches no ball), mean ± standard deviation over episodes;
* pot rate: shots that pot at least one object ball; foul rate: shots with a foul (a
  scratch or no ball touched); both per shot;
* cleared: racks with all 15 balls down within the 30 shots; run-out: cleared without a
  foul (misses allowed); break-and-run: cleared with every shot, the break included,
  potting a ball and no foul (the turn never passes);
* shots an episode, and the time a policy takes to choose a shot (ms; the planner plays
  its candidates then).

Policies: ``random`` (uniform actions from a generator seeded ``--seed``), ``ghost``
(``baselines.pool_ghost_ball``, the scripted player), ``planner``
(``planner.PoolPlanner`` with ``--candidates`` simulated shots a shot). A trained agent
needs a model trained on ``Pool2D-v0``'s own actions; the published ones play the
call-shot tasks (``Pool2DRackCallShot-v0``), scored by ``python -m agents.evaluate``.

``--game slingshot`` plays ``Slingshot2D-v0`` (``--level random`` or ``handmade``, three
birds) with ``random``, ``ballistic`` (``baselines.slingshot_ballistic``) and
``planner`` (``planner.SlingshotPlanner``), and prints the reward, the levels cleared
(every pig down), pigs destroyed a launch, launches an episode and the time a launch.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import gymnasium as gym
import numpy as np

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.envs.baselines import pool_ghost_ball, slingshot_ballistic
from impulse2d.envs.planner import PoolPlanner, SlingshotPlanner

BALLS, MAX_SHOTS = 15, 30
POLICIES = ("random", "ghost", "planner")
SLINGSHOT_POLICIES = ("random", "ballistic", "planner")


@dataclass
class Record:
    """What one policy did over the episodes."""

    rewards: list[float] = field(default_factory=list)
    shots: int = 0
    potting_shots: int = 0
    fouls: int = 0
    cleared: int = 0
    run_outs: int = 0
    break_and_runs: int = 0
    seconds_choosing: float = 0.0

    def row(self, name: str) -> list[str]:
        episodes, shots = len(self.rewards), max(self.shots, 1)
        return [
            name,
            f"{np.mean(self.rewards):.2f} ± {np.std(self.rewards):.2f}",
            f"{self.potting_shots / shots:.3f}",
            f"{self.fouls / shots:.3f}",
            f"{self.cleared}/{episodes}",
            f"{self.run_outs}/{episodes}",
            f"{self.break_and_runs}/{episodes}",
            f"{self.shots / episodes:.1f}",
            f"{1e3 * self.seconds_choosing / shots:.1f}",
        ]


def make_policy(name: str, env: gym.Env, seed: int, candidates: int) -> Callable:
    slingshot = env.spec is not None and env.spec.id.startswith("Slingshot2D")
    if name == "ghost":
        return pool_ghost_ball
    if name == "ballistic":
        return slingshot_ballistic
    if name == "planner":
        planner = SlingshotPlanner if slingshot else PoolPlanner
        return planner(env, candidates=candidates, seed=seed)
    rng = np.random.default_rng(seed)
    return lambda _obs: rng.uniform(-1.0, 1.0, 2).astype(np.float32)


@dataclass
class LaunchRecord:
    """What one policy did over Slingshot2D episodes."""

    rewards: list[float] = field(default_factory=list)
    launches: int = 0
    pigs: int = 0
    cleared: int = 0
    seconds_choosing: float = 0.0

    def row(self, name: str) -> list[str]:
        episodes, launches = len(self.rewards), max(self.launches, 1)
        return [
            name,
            f"{np.mean(self.rewards):.2f} ± {np.std(self.rewards):.2f}",
            f"{self.cleared}/{episodes}",
            f"{self.pigs / launches:.3f}",
            f"{self.launches / episodes:.2f}",
            f"{1e3 * self.seconds_choosing / launches:.1f}",
        ]


def play_slingshot(env: gym.Env, policy: Callable, seed: int, record: LaunchRecord) -> None:
    """One Slingshot2D episode from env seed ``seed``, into ``record``."""
    obs, _ = env.reset(seed=seed)
    total, done, info = 0.0, False, {}
    while not done:
        t0 = time.perf_counter()
        action = policy(obs)
        record.seconds_choosing += time.perf_counter() - t0
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        record.launches += 1
        record.pigs += int(info["pigs_destroyed"])
        done = terminated or truncated
    record.rewards.append(total)
    record.cleared += bool(info["cleared"])


def play(env: gym.Env, policy: Callable, seed: int, record: Record) -> None:
    """One episode from the rack of env seed ``seed``, into ``record``."""
    obs, _ = env.reset(seed=seed)
    total, potted, fouls, every_shot_pots, done = 0.0, 0, 0, True, False
    while not done:
        t0 = time.perf_counter()
        action = policy(obs)
        record.seconds_choosing += time.perf_counter() - t0
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        record.shots += 1
        pots, foul = int(info["potted"]), int(info["fouls"]) > 0
        record.potting_shots += pots > 0
        record.fouls += foul
        potted, fouls = potted + pots, fouls + foul
        every_shot_pots &= pots > 0
        done = terminated or truncated
    record.rewards.append(total)
    cleared = potted == BALLS
    record.cleared += cleared
    record.run_outs += cleared and fouls == 0
    record.break_and_runs += cleared and fouls == 0 and every_shot_pots


POOL_HEADER = ["policy", "reward", "pot rate", "foul rate", "cleared", "run-out",
               "break-and-run", "shots", "ms/shot"]  # fmt: skip
SLINGSHOT_HEADER = ["policy", "reward", "cleared", "pigs/launch", "launches", "ms/launch"]


def table(rows: list[list[str]], header: list[str] = POOL_HEADER) -> str:
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) for r in [header, *rows]]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(line.rstrip() for line in lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--game", choices=("pool", "slingshot"), default="pool")
    parser.add_argument("--policies", nargs="+", choices=sorted({*POLICIES, *SLINGSHOT_POLICIES}))
    parser.add_argument("--episodes", type=int, default=20, help="episodes (racks, levels)")
    parser.add_argument("--seed", type=int, default=1000, help="env seed of the first episode")
    parser.add_argument("--candidates", type=int, default=128, help="the planner's budget")
    parser.add_argument("--level", choices=("random", "handmade"), default="random",
                        help="Slingshot2D-v0's levels")  # fmt: skip
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes must be >= 1, got {args.episodes}")
    allowed = POLICIES if args.game == "pool" else SLINGSHOT_POLICIES
    policies = args.policies or list(allowed)
    if not set(policies) <= set(allowed):
        parser.error(f"--policies for {args.game} must be among {', '.join(allowed)}")
    seeds = f"env seeds {args.seed}-{args.seed + args.episodes - 1}"
    if args.game == "pool":
        rows = [_run(name, args, Record, play) for name in policies]
        print(f"Pool2D-v0, the 15-ball rack, at most {MAX_SHOTS} shots; {args.episodes} "
              f"racks, {seeds}")  # fmt: skip
        print(table(rows))
        return
    rows = [_run(name, args, LaunchRecord, play_slingshot) for name in policies]
    print(f"Slingshot2D-v0, {args.level} levels, 3 birds; {args.episodes} levels, {seeds}")
    print(table(rows, SLINGSHOT_HEADER))


def _run(name: str, args: argparse.Namespace, kind: type, play_one: Callable) -> list[str]:
    if args.game == "pool":
        env = gym.make("Pool2D-v0", max_episode_steps=MAX_SHOTS)
    else:
        env = gym.make("Slingshot2D-v0", level=args.level)
    policy, record = make_policy(name, env, args.seed, args.candidates), kind()
    for k in range(args.episodes):
        play_one(env, policy, args.seed + k, record)
        print(f"{name}: episode {k + 1}/{args.episodes}, reward {record.rewards[-1]:.2f}",
              file=sys.stderr, flush=True)  # fmt: skip
    return record.row(name)


if __name__ == "__main__":
    main()
