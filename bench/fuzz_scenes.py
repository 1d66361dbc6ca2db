"""The long fuzz run: thousands of random scenes from the whole envelope, every law checked.

Scenes come from ``tests/scenes_random.py`` with ``wide=True`` (sizes from 0.3 mm to
200 m around a scale drawn from 3 mm to 20 m, masses anywhere in 1 mg - 1000 t with up to
6 decades within a scene, speeds up to 200 m/s, dt from 0.1 ms to 0.1 s, 1-8 substeps),
in four families, each checked for the laws that apply to it (``tests/scene_laws.py``):

* ``any``: every kind of body, planes, springs, gravity: the state stays finite; world
  0 of a batch of 3 is bitwise the world alone; snapshot, step, restore, step repeats;
* ``planes``: at least one plane, fixed and kinematic bodies and springs: no dynamic
  body's centre gets behind a plane;
* ``conservative``: no gravity, springs or kinematic bodies, no overlap at the start:
  kinetic energy never more than 1 % above the start;
* ``free``: dynamic bodies only, no planes, gravity or springs, sleeping off: linear and
  angular momentum kept to 1e-9 of their scale (beyond what impacts may exert,
  ``scene_laws.impact_torque_bound``: none without bounces or two discs);
* ``free boxes``: the same with boxes only, and springs;
* ``edge``: scenes made to leave the envelope by themselves (restitution 1-2, kinematic
  pushers, two or three planes, overlapping starts): every step finite, and a refused
  step (``EnvelopeError``) leaves the state bitwise as it was.

Run: ``python bench/fuzz_scenes.py --scenes 10000`` (about 3 minutes here; Ctrl-C
prints what it has so far). Prints a progress line every few seconds (also into a log),
then a table of scenes and failures by family and law, and writes the first failing
scenes of each law as stand-alone snippets to ``--out`` (default
``fuzz_failures.py``). Exit status 1 if anything failed.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hypothesis import HealthCheck, Phase, given, seed, settings

import scene_laws as laws
import scenes_random as sr

STEPS = 200
FAMILIES = laws.FAMILIES


class Tally:
    def __init__(self, total: int, out: Path) -> None:
        self.total, self.out, self.done, self.start = total, out, 0, time.time()
        self.scenes: Counter = Counter()
        self.failures: Counter = Counter()
        self.examples: dict[tuple[str, str], list[str]] = {}
        self.last_print = 0.0

    def record(self, family: str, scene: sr.Scene, broken: list[str]) -> None:
        self.done += 1
        self.scenes[family] += 1
        for law in broken:
            self.failures[(family, law)] += 1
            kept = self.examples.setdefault((family, law), [])
            snippet = sr.code(scene)
            if len(kept) < 20 and snippet not in kept:
                kept.append(snippet)
        now = time.time()
        if now - self.last_print > 5.0 or self.done == self.total:
            self.last_print = now
            rate = self.done / (now - self.start)
            print(
                f"[{self.done}/{self.total}] {rate:.1f} scenes/s, "
                f"{self.broken()} failures, "
                f"about {(self.total - self.done) / rate / 60:.0f} min left",
                flush=True,
            )

    def broken(self) -> int:
        return sum(v for (_, law), v in self.failures.items() if law != laws.LEFT_THE_ENVELOPE)

    def report(self) -> int:
        print("\n| family | scenes | law | failures |\n|---|---|---|---|")
        laws_of = {
            "any": ["finite", "batch == single", "snapshot replay", laws.LEFT_THE_ENVELOPE],
            "planes": ["finite", "in front of planes", laws.LEFT_THE_ENVELOPE],
            "conservative": ["finite", "energy", laws.LEFT_THE_ENVELOPE],
            "free": ["finite", "linear momentum", "angular momentum", laws.LEFT_THE_ENVELOPE],
            "free boxes": ["finite", "linear momentum", "angular momentum", laws.LEFT_THE_ENVELOPE],
            "edge": ["finite", "refusal changes nothing", laws.LEFT_THE_ENVELOPE],
        }
        for family, names in laws_of.items():
            for law in names:
                count = self.failures[(family, law)]
                print(f"| {family} | {self.scenes[family]} | {law} | {count} |")
        total = self.broken()
        refused = sum(self.failures.values()) - total
        print(f"\n{self.done} scenes, {STEPS} steps each, {total} failures")
        print(f"{refused} scenes refused by a step for leaving the envelope (not failures)")
        if self.examples:
            lines = []
            for (family, law), snippets in self.examples.items():
                for snippet in snippets:
                    lines += [f"# {family}: {law}", snippet, ""]
            self.out.write_text("\n".join(lines))
            print(f"failing scenes written to {self.out}")
        return 1 if total else 0


def run_family(family: str, count: int, run_seed: int, tally: Tally) -> None:
    strategy = sr.scenes(wide=True, **FAMILIES[family])

    @seed(run_seed)
    @settings(
        max_examples=count,
        database=None,
        deadline=None,
        phases=[Phase.generate],  # count failures; no time on shrinking them
        suppress_health_check=list(HealthCheck),
    )
    @given(scene=strategy)
    def scenes(scene: sr.Scene) -> None:
        tally.record(family, scene, laws.check(family, scene, STEPS))

    scenes()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", type=int, default=2000, help="scenes in all (default 2000)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--out", type=Path, default=Path("fuzz_failures.py"))
    args = parser.parse_args()
    families = args.families.split(",")
    each = max(1, args.scenes // len(families))
    tally = Tally(each * len(families), args.out)
    try:
        for i, family in enumerate(families):
            run_family(family, each, args.seed * 100 + i, tally)
    except KeyboardInterrupt:
        print("interrupted")
    return tally.report()


if __name__ == "__main__":
    sys.exit(main())
