"""Bitwise equality of what envs return, through their tuples, lists, dicts and object
arrays (``final_obs``), for the tests that compare two runs."""

from __future__ import annotations

from typing import Any

import numpy as np


def same_bitwise(a: Any, b: Any) -> bool:
    """Equal structure, dtypes and bytes at every leaf (``None`` only equals ``None``)."""
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same_bitwise(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_bitwise(a[k], b[k]) for k in a)
    if isinstance(a, np.ndarray) and a.dtype == object:
        return len(a) == len(b) and all(same_bitwise(x, y) for x, y in zip(a, b, strict=True))
    if a is None or b is None:
        return a is b
    x, y = np.asarray(a), np.asarray(b)
    return x.dtype == y.dtype and x.tobytes() == y.tobytes()
