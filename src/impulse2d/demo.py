"""Moved to :mod:`impulse2d.apps.demo` (``python -m impulse2d.apps.demo``, or the installed
``impulse2d-demo`` command); this alias stays for the 0.3 releases and goes in 0.4.

``python -m impulse2d.demo NAME`` still renders, after a line on stderr saying where the
command went, and ``from impulse2d.demo import SCENES`` (any public name of the demo) still
imports, with a ``FutureWarning`` naming the new place (``FutureWarning`` rather than
``DeprecationWarning``: Python shows it by default, not only to tests).
"""

from __future__ import annotations

import sys
import warnings
from typing import Any

MOVED = (
    "impulse2d.demo moved to impulse2d.apps.demo (python -m impulse2d.apps.demo, or the "
    "impulse2d-demo command); the old name goes in impulse2d 0.4"
)


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    from .apps import demo

    warnings.warn(MOVED, FutureWarning, stacklevel=2)
    return getattr(demo, name)


if __name__ == "__main__":
    print(f"impulse2d: {MOVED}", file=sys.stderr)  # a command's user reads a line, not a warning
    from .apps.demo.__main__ import main

    sys.exit(main())
