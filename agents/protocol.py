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
(``planner.PoolPlanner`` with ``--candidates`` simulated shots a shot) and ``agent``
(below).

``--game slingshot`` plays ``Slingshot2D-v0`` (``--level random`` or ``handmade``, three
birds) with ``random``, ``ballistic`` (``baselines.slingshot_ballistic``) and
``planner`` (``planner.SlingshotPlanner``), and prints the reward, the levels cleared
(every pig down), pigs destroyed a launch, launches an episode and the time a launch.

``--level templates`` is PHYRE's protocol on the level templates (``envs/_templates.py``):
a task is one level, an *attempt* is one bird launched at it from the start, and a task
is solved by an attempt that brings every pig down. Each policy gets ``--attempts`` (10)
attempts a task and stops at the first success; the table gives success@1, success@k
(tasks solved within k attempts) and AUCCESS, PHYRE's area under the success curve,
``sum_k w_k s_k / sum_k w_k`` with ``w_k = log(k + 1) - log(k)`` over ``k = 1 ...
attempts`` (PHYRE takes 100 attempts; 10 here), which weights solving in few attempts.
``--split seen`` scores the seven train templates on levels from seed 1,000,000 on
(seeds an agent trained on ``Slingshot2DTemplatesCallShot-v0``, levels 0-3,999, never
saw: local generalisation); ``--split held-out`` the three held-out templates (broad
generalisation). Level ``k`` of a split is template ``k mod n``, so ``--episodes`` a
multiple of the split's templates scores each equally. A deterministic policy repeats
its launch (the ballistic player: its success@k is its success@1); random play draws
anew; the planner's candidates past its listed launches are random, so they change.

``--policies agent --model RUN_DIR ...`` plays trained agents (``agents.train``'s run
directories, one row each and, with several, their mean ± std): on Pool agents of the
rack (``Pool2DRackBestShots-v0`` or ``Pool2DRackCallShot-v0``), on Slingshot of
``Slingshot2DCallShot-v0`` or ``Slingshot2DGeneratedCallShot-v0``, on the templates of
``Slingshot2DTemplatesCallShot-v0``; each on the id it trained on (the same game and
episodes under its call-shot wrapper). Its first attempt at a template task is its
deterministic action, later ones are sampled from its policy.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import gymnasium as gym
import numpy as np

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.envs import _templates
from impulse2d.envs.baselines import pool_ghost_ball, slingshot_ballistic
from impulse2d.envs.planner import PoolPlanner, SlingshotPlanner

BALLS, MAX_SHOTS = 15, 30
POLICIES = ("random", "ghost", "planner", "agent")
SLINGSHOT_POLICIES = ("random", "ballistic", "planner", "agent")
# The template splits: (the templates, the first level seed). Training levels are seeds
# 0-3,999 of the train templates (Slingshot2DTemplatesCallShot-v0), so tests start far off.
TEMPLATE_SPLITS = {"seen": ("train", 1_000_000), "held-out": ("held-out", 1_000_000)}
AGENT_IDS = {
    "pool": ("Pool2DRackBestShots-v0", "Pool2DRackCallShot-v0"),
    "slingshot": ("Slingshot2DCallShot-v0", "Slingshot2DGeneratedCallShot-v0"),
    "templates": ("Slingshot2DTemplatesCallShot-v0",),
}


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
        episodes = len(self.rewards)
        _, pots, fouls, _, _, _, shots, ms = self.values()
        return [
            name,
            f"{np.mean(self.rewards):.2f} ± {np.std(self.rewards):.2f}",
            f"{pots:.3f}",
            f"{fouls:.3f}",
            f"{self.cleared}/{episodes}",
            f"{self.run_outs}/{episodes}",
            f"{self.break_and_runs}/{episodes}",
            f"{shots:.1f}",
            f"{ms:.1f}",
        ]

    def values(self) -> list[float]:
        """The row's numbers (counts of episodes as fractions), for a mean over seeds."""
        episodes, shots = len(self.rewards), max(self.shots, 1)
        return [float(np.mean(self.rewards)), self.potting_shots / shots, self.fouls / shots,
                self.cleared / episodes, self.run_outs / episodes,
                self.break_and_runs / episodes, self.shots / episodes,
                1e3 * self.seconds_choosing / shots]  # fmt: skip


def make_policy(name: str, env: gym.Env, seed: int, candidates: int, agent: Any = None) -> Callable:
    """Policy ``name`` for one env: a callable from an observation to an action."""
    slingshot = env.spec is not None and env.spec.id.startswith("Slingshot2D")
    if name == "agent":
        return AgentPolicy(agent, seed, explore=slingshot)
    if name == "ghost":
        return pool_ghost_ball
    if name == "ballistic":
        return slingshot_ballistic
    if name == "planner":
        planner = SlingshotPlanner if slingshot else PoolPlanner
        return planner(env, candidates=candidates, seed=seed)
    rng = np.random.default_rng(seed)
    return lambda _obs: rng.uniform(-1.0, 1.0, 2).astype(np.float32)


class AgentPolicy:
    """A trained SB3 agent (``Agent``, loaded once) as a policy of one env: its
    deterministic action, or with ``explore`` its deterministic action at the first call
    and actions sampled from its policy (torch seeded ``seed``) after it."""

    def __init__(self, agent: Agent, seed: int, explore: bool) -> None:
        self.agent, self.explore, self.calls = agent, explore, 0
        agent.model.set_random_seed(seed)

    def __call__(self, observation: Any) -> np.ndarray:
        obs = np.asarray(observation, np.float32)[None]
        if self.agent.normalizer is not None:
            obs = self.agent.normalizer.normalize_obs(obs)
        deterministic = not (self.explore and self.calls > 0)
        self.calls += 1
        action, _ = self.agent.model.predict(obs, deterministic=deterministic)
        return np.asarray(action, np.float32)[0]


@dataclass(frozen=True)
class Agent:
    """A trained model, its normalizer (or None), the env id and seed it trained with."""

    model: Any
    normalizer: Any
    env_id: str
    seed: int


def load_agent(run_dir: str, wanted: tuple[str, ...]) -> Agent:
    """The agent of an ``agents.train`` run directory, refused unless it trained on one of
    the ids ``wanted`` (its observations and actions are those ids')."""
    from agents.evaluate import load_model

    model, normalizer, config = load_model(run_dir)
    if config["env_id"] not in wanted:
        raise ValueError(
            f"--model must be a run trained on {' or '.join(wanted)}, got one trained on "
            f"{config['env_id']} ({run_dir})"
        )
    return Agent(model, normalizer, config["env_id"], int(config["seed"]))


@dataclass
class LaunchRecord:
    """What one policy did over Slingshot2D episodes."""

    rewards: list[float] = field(default_factory=list)
    launches: int = 0
    pigs: int = 0
    cleared: int = 0
    seconds_choosing: float = 0.0

    def row(self, name: str) -> list[str]:
        _, _, pigs, launches, ms = self.values()
        return [
            name,
            f"{np.mean(self.rewards):.2f} ± {np.std(self.rewards):.2f}",
            f"{self.cleared}/{len(self.rewards)}",
            f"{pigs:.3f}",
            f"{launches:.2f}",
            f"{ms:.1f}",
        ]

    def values(self) -> list[float]:
        episodes, launches = len(self.rewards), max(self.launches, 1)
        return [float(np.mean(self.rewards)), self.cleared / episodes, self.pigs / launches,
                self.launches / episodes, 1e3 * self.seconds_choosing / launches]  # fmt: skip


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


def auccess(solved_at: list[int], attempts: int) -> float:
    """PHYRE's AUCCESS over ``k = 1 ... attempts``: ``sum_k w_k s_k / sum_k w_k``, with
    ``s_k`` the fraction of tasks solved within ``k`` attempts (``solved_at``: the
    attempt that solved each task, 1-based; 0 for unsolved) and ``w_k = log(k + 1) -
    log(k)``."""
    k = np.arange(1, attempts + 1)
    weights = np.log(k + 1) - np.log(k)
    solved = np.asarray(solved_at)
    success = np.array([np.mean((solved >= 1) & (solved <= j)) for j in k])
    return float(np.sum(weights * success) / np.sum(weights))


@dataclass
class AttemptRecord:
    """What one policy did on template tasks: per task, its template, the attempt that
    solved it (0: none) and the first attempt's reward."""

    attempts: int
    templates: list[str] = field(default_factory=list)
    solved_at: list[int] = field(default_factory=list)
    first_rewards: list[float] = field(default_factory=list)
    launches: int = 0
    seconds_choosing: float = 0.0

    def success(self, k: int, template: str | None = None) -> float:
        rows = [s for s, t in zip(self.solved_at, self.templates, strict=True)
                if template in (None, t)]  # fmt: skip
        return float(np.mean([1 <= s <= k for s in rows]))

    def row(self, name: str) -> list[str]:
        first, within, area, _, launches, ms = self.values()
        return [
            name,
            f"{first:.3f}",
            f"{within:.3f}",
            f"{area:.3f}",
            f"{np.mean(self.first_rewards):.2f} ± {np.std(self.first_rewards):.2f}",
            f"{launches:.2f}",
            f"{ms:.1f}",
        ]

    def values(self) -> list[float]:
        return [self.success(1), self.success(self.attempts),
                auccess(self.solved_at, self.attempts), float(np.mean(self.first_rewards)),
                self.launches / len(self.solved_at),
                1e3 * self.seconds_choosing / max(self.launches, 1)]  # fmt: skip

    def template_row(self, name: str, names: tuple[str, ...]) -> list[str]:
        return [name, *(f"{self.success(1, t):.2f} / {self.success(self.attempts, t):.2f}"
                        for t in names)]  # fmt: skip


def play_task(
    env: gym.Env, policy: Callable, template: str, seed: int, record: AttemptRecord
) -> None:
    """Up to ``record.attempts`` one-bird attempts at ``env``'s one level (each from the
    start), stopping at the first that brings every pig down; into ``record``."""
    solved = 0
    for attempt in range(1, record.attempts + 1):
        obs, _ = env.reset(seed=seed)
        t0 = time.perf_counter()
        action = policy(obs)
        record.seconds_choosing += time.perf_counter() - t0
        _, reward, _, _, info = env.step(action)
        record.launches += 1
        if attempt == 1:
            record.first_rewards.append(float(reward))
        if info["cleared"]:
            solved = attempt
            break
    record.templates.append(template)
    record.solved_at.append(solved)


def run_templates(name: str, args: argparse.Namespace, agent: Agent | None) -> AttemptRecord:
    """Policy ``name`` on ``args.episodes`` tasks of ``args.split``: level seeds from the
    split's first on, one env (and policy) a task, so a task is exactly one level."""
    split, first = TEMPLATE_SPLITS[args.split]
    names = _templates.template_names(split)
    record = AttemptRecord(args.attempts)
    for k in range(args.episodes):
        kwargs = {"level": "templates", "templates": split, "num_levels": 1,
                  "start_level": first + k, "num_birds": 1}  # fmt: skip
        env = _make_env(name, "Slingshot2D-v0", agent, kwargs)
        policy = make_policy(name, env, args.seed + k, args.candidates, agent)
        play_task(env, policy, names[(first + k) % len(names)], args.seed + k, record)
        env.close()
        print(f"{name}: task {k + 1}/{args.episodes}, solved at attempt "
              f"{record.solved_at[-1] or '-'}", file=sys.stderr, flush=True)  # fmt: skip
    return record


POOL_HEADER = ["policy", "reward", "pot rate", "foul rate", "cleared", "run-out",
               "break-and-run", "shots", "ms/shot"]  # fmt: skip
SLINGSHOT_HEADER = ["policy", "reward", "cleared", "pigs/launch", "launches", "ms/launch"]


def seeds_row(name: str, records: list[Any]) -> list[str]:
    """Mean ± std over training seeds of each number of the records' rows (a count of
    episodes as a fraction of them)."""
    values = np.array([record.values() for record in records])
    return [
        name,
        *(f"{m:.3f} ± {s:.3f}" for m, s in zip(values.mean(0), values.std(0), strict=True)),
    ]


def table(rows: list[list[str]], header: list[str] = POOL_HEADER) -> str:
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) for r in [header, *rows]]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(line.rstrip() for line in lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--game", choices=("pool", "slingshot"), default="pool")
    parser.add_argument("--policies", nargs="+", choices=sorted({*POLICIES, *SLINGSHOT_POLICIES}))
    parser.add_argument("--episodes", type=int, default=20, help="episodes (racks, levels, tasks)")
    parser.add_argument("--seed", type=int, default=1000, help="env seed of the first episode")
    parser.add_argument("--candidates", type=int, default=128, help="the planner's budget")
    parser.add_argument("--level", choices=("random", "handmade", "templates"), default="random",
                        help="Slingshot2D-v0's levels")  # fmt: skip
    parser.add_argument("--split", choices=tuple(TEMPLATE_SPLITS), default="seen",
                        help="with --level templates: seen templates' unseen levels, or "
                        "held-out templates")  # fmt: skip
    parser.add_argument("--attempts", type=int, default=10, help="attempts a template task")
    parser.add_argument("--model", nargs="+", default=None,
                        help="the agent's run directories (agents.train): one row each, and "
                        "with several, their mean ± std")  # fmt: skip
    args = parser.parse_args(argv)
    for option in ("episodes", "attempts"):
        if getattr(args, option) < 1:
            parser.error(f"--{option} must be >= 1, got {getattr(args, option)}")
    allowed = POLICIES if args.game == "pool" else SLINGSHOT_POLICIES
    policies = args.policies or [p for p in allowed if p != "agent" or args.model]
    if not set(policies) <= set(allowed):
        parser.error(f"--policies for {args.game} must be among {', '.join(allowed)}")
    if ("agent" in policies) != (args.model is not None):
        parser.error("--model RUN_DIR and the policy 'agent' go together")
    kind = "templates" if args.level == "templates" and args.game == "slingshot" else args.game
    agents = [load_agent(run, AGENT_IDS[kind]) for run in args.model or []]
    trained_seeds = [agent.seed for agent in agents]
    if len(set(trained_seeds)) < len(trained_seeds):
        parser.error(f"--model runs must have different training seeds, got {trained_seeds}")
    players = [(name, None) for name in policies if name != "agent"]
    players += [(name, agent) for name in policies if name == "agent" for agent in agents]
    records: dict[str, Any] = {}
    for name, agent in players:
        label = name if agent is None else f"agent, seed {agent.seed}"
        if kind == "templates":
            records[label] = run_templates(name, args, agent)
        else:
            play_one = play if kind == "pool" else play_slingshot
            records[label] = _run(name, args, Record if kind == "pool" else LaunchRecord,
                                  play_one, agent)  # fmt: skip
    rows = [record.row(label) for label, record in records.items()]
    if len(agents) > 1:
        trained = [record for label, record in records.items() if label.startswith("agent, ")]
        rows.append(seeds_row(f"agent, {len(agents)} seeds", trained))
    seeds = f"env seeds {args.seed}-{args.seed + args.episodes - 1}"
    if kind == "pool":
        print(f"Pool2D-v0, the 15-ball rack, at most {MAX_SHOTS} shots; {args.episodes} "
              f"racks, {seeds}")  # fmt: skip
        print(table(rows))
    elif kind == "slingshot":
        print(f"Slingshot2D-v0, {args.level} levels, 3 birds; {args.episodes} levels, {seeds}")
        print(table(rows, SLINGSHOT_HEADER))
    else:
        _print_templates(args, records, rows)


def _print_templates(
    args: argparse.Namespace, records: dict[str, AttemptRecord], rows: list[list[str]]
) -> None:
    split, first = TEMPLATE_SPLITS[args.split]
    names = _templates.template_names(split)
    k = args.attempts
    print(f"Slingshot2D-v0 templates, split {args.split} ({', '.join(names)}): {args.episodes} "
          f"tasks, level seeds {first}-{first + args.episodes - 1}, one bird an attempt, "
          f"up to {k} attempts")  # fmt: skip
    header = ["policy", "success@1", f"success@{k}", f"AUCCESS@{k}", "reward@1", "launches",
              "ms/launch"]  # fmt: skip
    print(table(rows, header))
    print(f"\nsuccess@1 / success@{k} by template")
    rows = [r.template_row(name, names) for name, r in records.items()]
    print(table(rows, ["policy", *names]))


def _make_env(name: str, game_id: str, agent: Agent | None, kwargs: dict[str, Any]) -> gym.Env:
    """The env policy ``name`` plays: the game itself, or for the agent the id it trained
    on (its call-shot wrapper around the same game), with the same arguments on top."""
    return gym.make(game_id if name != "agent" else agent.env_id, **kwargs)


def _run(
    name: str, args: argparse.Namespace, kind: type, play_one: Callable, agent: Agent | None
) -> Any:
    if args.game == "pool":
        env = _make_env(name, "Pool2D-v0", agent, {"max_episode_steps": MAX_SHOTS})
    else:
        levels = {"level": args.level, "num_levels": 0, "start_level": 0}  # not the agent's set
        env = _make_env(name, "Slingshot2D-v0", agent, levels)
    policy, record = make_policy(name, env, args.seed, args.candidates, agent), kind()
    for k in range(args.episodes):
        play_one(env, policy, args.seed + k, record)
        print(f"{name}: episode {k + 1}/{args.episodes}, reward {record.rewards[-1]:.2f}",
              file=sys.stderr, flush=True)  # fmt: skip
    return record


if __name__ == "__main__":
    main()
