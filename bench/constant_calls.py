"""The best blind player of a call-shot task: every constant call, one pocket (or pig) at a
few speeds, played on the evaluation episodes. A trained agent that does no better than
this has not learned to use its observation.

    python bench/constant_calls.py --env Pool2DCallShot-v0   # about 20 s on 2 cores

plays, for each of the task's named targets (Pool: the six pockets; Slingshot: the four
pig slots) and each speed ``s`` of ``--speeds``, the action with that preference at 1,
the others, the trim and the arc at 0, over ``--episodes`` episodes from env seed
``--seed`` (agents.evaluate's episodes), and prints the best few by mean reward.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # agents/, run from anywhere
from agents import _tasks

from impulse2d.envs import CALL_SHOT_IDS


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--env", default="Pool2DCallShot-v0", choices=list(CALL_SHOT_IDS))
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, default=1000)
    parser.add_argument("--speeds", type=float, nargs="+", default=[-0.8, -0.5, -0.2])
    parser.add_argument("--top", type=int, default=5)
    args = parser.parse_args(argv)
    pool = CALL_SHOT_IDS[args.env][0] == "Pool2D-v0"
    targets, size = (6, 8) if pool else (4, 7)
    rows = []
    for target in range(targets):
        for speed in args.speeds:

            def policy(obs: np.ndarray, target: int = target, speed: float = speed) -> np.ndarray:
                action = np.zeros((len(obs), size), np.float32)
                action[:, target], action[:, -1] = 1.0, speed
                return action

            record = _tasks.play_episodes(args.env, {}, policy, args.episodes, args.seed)
            rows.append(
                (float(record["return"].mean()), float(record["return"].std()), target, speed)
            )
            print(
                f"target {target}, s = {speed:+.1f}: {rows[-1][0]:.3f}", file=sys.stderr, flush=True
            )
    print(f"{args.env}: constant calls, {args.episodes} episodes from env seed {args.seed}")
    print("| target | s | reward / episode |\n|---|---|---|")
    for mean, std, target, speed in sorted(rows, reverse=True)[: args.top]:
        print(f"| {target} | {speed:+.1f} | {mean:.2f} ± {std:.2f} |")


if __name__ == "__main__":
    main()
