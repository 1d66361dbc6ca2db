"""Every wrong input the catalog knows, given to every public entry: counts by outcome.

Runs ``tests/inputs_catalog.py`` (the same entries and values as
``tests/test_validation_catalog.py``) and prints, for each kind of value, how many calls
were made and how they ended: refused with a ``ValueError`` naming the parameter (the
contract), refused some other way, or accepted. Extreme but finite numbers may also be
accepted, provided 30 steps later every number is still finite.

Run: ``python bench/fuzz_inputs.py`` (about 10 s). Exit status 1 if any call broke the
contract.
"""

from __future__ import annotations

import re
import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import inputs_catalog as cat


def outcome(entry: cat.Entry, value, extreme: bool) -> str:
    try:
        world = entry.give(value)
        if extreme and world is not None and not cat.finite_after_steps(world):
            return "accepted, then non-finite"
    except ValueError as error:
        named = re.search(rf"(?<![\w]){re.escape(entry.name)}(?![\w])", str(error))
        return "refused, naming it" if named else "ValueError not naming it"
    except Exception as error:  # the wrong exception type is an outcome to count
        return f"{type(error).__name__}"
    return "accepted" if extreme else "accepted (wrong)"


def main() -> int:
    table: dict[str, Counter] = {}
    for entry in cat.ENTRIES:
        for kind, values in cat.BAD[entry.shape].items():
            for value in values:
                legal = (value is None and entry.none_is_legal) or (
                    entry.inf_is_legal and isinstance(value, float) and value == float("inf")
                )
                if not legal:
                    table.setdefault(kind, Counter())[outcome(entry, value, False)] += 1
        for value in cat.extreme_values(entry):
            table.setdefault("extreme finite", Counter())[outcome(entry, value, True)] += 1
    columns = ["refused, naming it", "accepted", "ValueError not naming it"]
    print(f"{len(cat.ENTRIES)} entries (constructor keywords, attributes, method arguments)\n")
    print(f"| kind of value | calls | {' | '.join(columns)} | other |")
    print("|---|---|" + "---|" * (len(columns) + 1))
    broken = 0
    for kind, counts in table.items():
        other = {k: v for k, v in counts.items() if k not in columns}
        cells = [str(counts.get(c, 0)) for c in columns]
        print(f"| {kind} | {sum(counts.values())} | {' | '.join(cells)} | {other or ''} |")
        broken += sum(other.values()) + counts.get("ValueError not naming it", 0)
    total = sum(sum(c.values()) for c in table.values())
    print(f"\n{total} calls, {broken} broke the contract")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
