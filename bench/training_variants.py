"""Does a training result hold on another machine? Train it as another CPU would round it.

A trained agent's score is a claim about a recipe, not about one machine's bits: torch's
kernels, oneMKL's code path and torch's thread count round differently on other CPUs,
and over thousands of PPO updates two runs part (``agents/README.md``, Determinism).
This script trains one YAML entry under several training seeds and, for seed 0, under
rounding variants that stand in for other CPUs, each with ``python -m agents.train``
(train, then evaluate on the same 100 seeded episodes), and prints every run's reward
beside the scripted player's::

    python bench/training_variants.py --env Pool2DCallShot-v0 --seeds 0-4
    python bench/training_variants.py --env Slingshot2DCallShot-v0 --seeds 0-4 --out t.md

The variants (each changes one thing from the pinned default):

* ``pinned``: what ``agents.train`` does by default (ATen's AVX2 kernels, oneMKL's AVX2
  path, torch on one thread);
* ``aten-default``: ``ATEN_CPU_CAPABILITY=default`` (ATen's kernels without AVX2);
* ``mkl-compatible``: ``MKL_CBWR=COMPATIBLE`` (oneMKL's portable code path);
* ``torch-2-threads``: ``--torch-threads 2``.

Runs are kept in ``runs/variants/<entry>/<variant>_seed<k>`` and reused when their
``results.json`` exists (``--fresh`` trains them again).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VARIANTS: dict[str, tuple[dict[str, str], list[str]]] = {
    # name: (environment variables, extra agents.train arguments)
    "pinned": ({}, []),
    "aten-default": ({"ATEN_CPU_CAPABILITY": "default"}, []),
    "mkl-compatible": ({"MKL_CBWR": "COMPATIBLE"}, []),
    "torch-2-threads": ({}, ["--torch-threads", "2"]),
}


def parse_seeds(text: str) -> list[int]:
    """``0-4`` or ``0,2,7`` (or both) as a sorted list of seeds."""
    seeds: set[int] = set()
    for part in text.split(","):
        low, sep, high = part.partition("-")
        if not low.isdigit() or (sep and not high.isdigit()):
            raise ValueError(f"seeds must be like 0-4 or 0,2,7, got {text!r}")
        seeds.update(range(int(low), int(high if sep else low) + 1))
    return sorted(seeds)


def run(entry: str, variant: str, seed: int, out: Path, fresh: bool) -> dict:
    """Train and evaluate one run (unless its results exist); returns its results."""
    run_dir = out / f"{variant}_seed{seed}"
    results = run_dir / "results.json"
    if results.is_file() and not fresh:
        return json.loads(results.read_text())
    env, extra = VARIANTS[variant]
    command = [sys.executable, "-m", "agents.train", "--env", entry, "--seed", str(seed),
               "--run-dir", str(run_dir), *extra]  # fmt: skip
    start = time.perf_counter()
    print(f"{variant}, seed {seed}: {' '.join(command[1:])}", flush=True)
    log = out / f"{variant}_seed{seed}.log"
    with open(log, "w") as file:
        done = subprocess.run(
            command, cwd=ROOT, env={**os.environ, **env}, stdout=file, stderr=subprocess.STDOUT
        )
    if done.returncode != 0:
        raise RuntimeError(f"{variant}, seed {seed} failed: see {log}")
    print(f"  done in {time.perf_counter() - start:.0f} s", flush=True)
    return json.loads(results.read_text())


def table(entry: str, rows: list[tuple[str, int, dict]]) -> str:
    """One Markdown row per run: its reward, the scripted player's, the margin."""
    lines = [
        f"# {entry}: every run against the scripted player on the same episodes",
        "",
        "| variant | seed | trained reward | scripted reward | margin | at least scripted |",
        "|---|---|---|---|---|---|",
    ]
    rewards = []
    for variant, seed, results in rows:
        trained = results["policies"]["trained"]["reward"]["mean"]
        scripted = results["policies"]["scripted"]["reward"]["mean"]
        rewards.append(trained)
        verdict = "yes" if trained >= scripted else "**no**"
        lines.append(
            f"| {variant} | {seed} | {trained:.3f} | {scripted:.3f} | {trained - scripted:+.3f} "
            f"| {verdict} |"
        )
    mean = sum(rewards) / len(rewards)
    std = (sum((r - mean) ** 2 for r in rewards) / len(rewards)) ** 0.5
    lines += ["", f"All {len(rows)} runs: trained reward {mean:.3f} ± {std:.3f} (mean ± std)."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--env", default="Pool2DCallShot-v0", help="a YAML entry of ppo.yml")
    parser.add_argument("--seeds", default="0-4", help="training seeds (default 0-4)")
    parser.add_argument(
        "--variants",
        default=",".join(name for name in VARIANTS if name != "pinned"),
        help="rounding variants for seed 0 (default: all of them)",
    )
    parser.add_argument("--out", default=None, help="also write the table to this file")
    parser.add_argument("--fresh", action="store_true", help="train runs again that exist")
    args = parser.parse_args(argv)
    variants = [v for v in args.variants.split(",") if v]
    unknown = sorted(set(variants) - set(VARIANTS))
    if unknown:
        raise ValueError(f"variants must be among {list(VARIANTS)}, got {unknown}")
    out = ROOT / "runs" / "variants" / args.env.replace("/", "-")
    out.mkdir(parents=True, exist_ok=True)
    plan = [("pinned", seed) for seed in parse_seeds(args.seeds)]
    plan += [(variant, 0) for variant in variants]
    rows = [(v, s, run(args.env, v, s, out, args.fresh)) for v, s in plan]
    text = table(args.env, rows)
    if args.out:
        Path(args.out).write_text(text)
    print(text, end="")
    return text


if __name__ == "__main__":
    try:
        main()
    except (ValueError, RuntimeError) as error:
        sys.exit(f"error: {error}")
