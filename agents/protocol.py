"""The Pool protocol: the numbers a pool player is judged by, for any policy, as a table.

    python -m agents.protocol --policies random ghost planner --episodes 20

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
from impulse2d.envs.baselines import pool_ghost_ball
from impulse2d.envs.planner import PoolPlanner

BALLS, MAX_SHOTS = 15, 30
POLICIES = ("random", "ghost", "planner")


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
    if name == "ghost":
        return pool_ghost_ball
    if name == "planner":
        return PoolPlanner(env, candidates=candidates, seed=seed)
    rng = np.random.default_rng(seed)
    return lambda _obs: rng.uniform(-1.0, 1.0, 2).astype(np.float32)


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


def table(rows: list[list[str]]) -> str:
    header = ["policy", "reward", "pot rate", "foul rate", "cleared", "run-out",
              "break-and-run", "shots", "ms/shot"]  # fmt: skip
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) for r in [header, *rows]]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(line.rstrip() for line in lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--policies", nargs="+", choices=POLICIES, default=list(POLICIES))
    parser.add_argument("--episodes", type=int, default=20, help="racks, one episode each")
    parser.add_argument("--seed", type=int, default=1000, help="env seed of the first rack")
    parser.add_argument("--candidates", type=int, default=128, help="the planner's budget")
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes must be >= 1, got {args.episodes}")
    rows = []
    for name in args.policies:
        env = gym.make("Pool2D-v0", max_episode_steps=MAX_SHOTS)
        policy, record = make_policy(name, env, args.seed, args.candidates), Record()
        for k in range(args.episodes):
            play(env, policy, args.seed + k, record)
            print(f"{name}: rack {k + 1}/{args.episodes}, reward {record.rewards[-1]:.1f}",
                  file=sys.stderr, flush=True)  # fmt: skip
        rows.append(record.row(name))
    print(f"Pool2D-v0, the 15-ball rack, at most {MAX_SHOTS} shots; {args.episodes} racks, "
          f"env seeds {args.seed}-{args.seed + args.episodes - 1}")  # fmt: skip
    print(table(rows))


if __name__ == "__main__":
    main()
