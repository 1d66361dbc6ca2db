"""The printed side of the benchmarks: table cells, the aligned table, and the revision
of the impulse2d being measured. Shared by ``bench_engine.py`` and ``bench_envs.py``."""

from __future__ import annotations

import math
import os
import subprocess
from typing import Any

import numpy as np

import impulse2d


def fmt(value: Any, digits: int = 3) -> str:
    """A number for the table: thousands separators for big ones, ``digits`` significant
    digits otherwise; ``-`` for a missing value; booleans and strings as they are."""
    if value is None:
        return "-"
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, str):
        return value
    if not math.isfinite(value):
        return str(value)
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    return f"{value:.{digits}g}"


def ratio(a: float | None, b: float | None) -> str:
    """``a / b`` to 3 significant digits, ``-`` if either is missing or ``b`` is 0."""
    return "-" if a is None or not b else f"{a / b:.3g}"


def print_table(
    header: tuple[str, ...], align: tuple[str, ...], rows: list[tuple[str, ...]]
) -> None:
    """Print ``rows`` under ``header`` in columns as wide as their widest cell, each aligned
    by its format character (``<`` or ``>``)."""
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]

    def line(cells: tuple[str, ...]) -> str:
        return "  ".join(f"{c:{a}{w}}" for c, a, w in zip(cells, align, widths, strict=True))

    print(line(header).rstrip())
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print(line(row).rstrip())


def source_version() -> str:
    """Where impulse2d is imported from and its git commit (``+dirty`` with local changes)."""
    root = os.path.dirname(os.path.abspath(impulse2d.__file__))
    try:
        rev = subprocess.run(
            ["git", "-C", root, "describe", "--always", "--dirty=+dirty"],
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        rev = "no git"
    return f"impulse2d from {root} ({rev})"
