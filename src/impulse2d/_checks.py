"""Validation of user input: every public parameter passes through one of these.

Each function names the parameter and the rule it broke, so a mistake surfaces as
``ValueError: radius must be > 0, got -1.0`` at the call that made it, never as a NaN
several steps later. Nothing is silently clamped or repaired.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

# Arrays of at most this many entries are checked in plain Python: a numpy reduction costs
# about 1.5 us a call whatever the size, and one write of a body's column checks a value
# or two a world several times over (finite, sign, envelope). Both paths refuse the same
# values with the same message (the first bad entry in C order).
FEW_ENTRIES = 8


def _entries(array: np.ndarray) -> list[float] | None:
    """The entries of a small array as Python floats in C order; None for a large one."""
    return array.ravel().tolist() if array.size <= FEW_ENTRIES else None


def _real(name: str, value: Any) -> np.ndarray:
    """``value`` as a float64 array, refusing what is not a real number: strings, None,
    complex numbers (numpy would silently drop the imaginary part), bools (``True`` is
    not a length), ragged lists."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric, got {value!r}") from None
    if raw.dtype.kind == "c":
        raise ValueError(f"{name} must be real, got complex {value!r}")
    if raw.dtype.kind == "b":
        raise ValueError(f"{name} must be a number, not a bool, got {value!r}")
    if raw.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be numeric, got {value!r}")
    return raw.astype(np.float64)


def finite_scalar(name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise if it is not a finite real number."""
    array = _real(name, value)
    if array.shape != ():
        raise ValueError(f"{name} must be a real number, got {value!r}")
    number = float(array)
    if not math.isfinite(number):
        raise ValueError(f"{name} must be finite, got {number}")
    return number


def positive(name: str, value: Any) -> float:
    """A finite number > 0."""
    if type(value) is float and 0.0 < value < math.inf:  # the common case, quickly
        return value
    number = finite_scalar(name, value)
    if number <= 0.0:
        raise ValueError(f"{name} must be > 0, got {number}")
    return number


def non_negative(name: str, value: Any) -> float:
    """A finite number >= 0."""
    number = finite_scalar(name, value)
    if number < 0.0:
        raise ValueError(f"{name} must be >= 0, got {number}")
    return number


def real_array(
    name: str, value: Any, shape: tuple[int, ...] | None = None, finite: bool = True
) -> np.ndarray:
    """A new float64 array with every entry finite (or, with ``finite=False``, +-inf
    allowed but never NaN), optionally of an exact shape."""
    array = _real(name, value)
    if shape is not None and array.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got shape {array.shape}")
    entries = _entries(array)
    if entries is not None:
        ok = all(map(math.isfinite, entries)) if finite else not any(map(math.isnan, entries))
    else:
        ok = not np.any(np.isnan(array) if not finite else ~np.isfinite(array))
    if not ok:
        kind = "a number" if not finite else "finite"
        raise ValueError(f"{name} must be {kind}, got {value!r}")
    return array


def vector2(name: str, value: Any) -> np.ndarray:
    """A finite 2-vector, returned as a new float64 array of shape (2,)."""
    return real_array(name, value, (2,))


def batched(
    name: str, value: Any, batch_size: int, tail: tuple[int, ...], finite: bool = True
) -> np.ndarray:
    """A finite value of shape ``tail`` (same in every world) or ``(batch_size, *tail)``.

    Returns an array of shape ``(batch_size, *tail)``.
    """
    array = real_array(name, value, finite=finite)
    if array.shape == tail:
        out = np.empty((batch_size, *tail))
        out[...] = array
        return out
    if array.shape == (batch_size, *tail):
        return array
    want = f"{tail}" if batch_size == 1 else f"{tail} or {(batch_size, *tail)}"
    raise ValueError(f"{name} must have shape {want}, got shape {array.shape}")


def detached(
    name: str, value: Any, tail: tuple[int, ...], rule: str | None = None, finite: bool = True
) -> Any:
    """A value kept by an object outside a world: one value of shape ``tail`` (returned as
    a float when ``tail`` is ``()``) or one per world, ``(batch, *tail)``."""
    array = real_array(name, value, finite=finite)
    if array.shape != tail and array.shape[1:] != tail:
        raise ValueError(f"{name} must have shape {tail} or (batch, *{tail}), got {array.shape}")
    if rule:
        batched_rule(name, array, rule)
    return float(array) if array.shape == () else array


def batched_rule(name: str, array: np.ndarray, rule: str) -> None:
    """Check ``array`` (already finite) against ``'> 0'`` or ``'>= 0'``, naming the parameter."""
    entries = _entries(array)
    if entries is not None:
        positive = rule == "> 0"
        for value in entries:
            if value <= 0.0 if positive else value < 0.0:
                raise ValueError(f"{name} must be {rule}, got {value}")
        return
    bad = array <= 0.0 if rule == "> 0" else array < 0.0
    if np.any(bad):
        raise ValueError(f"{name} must be {rule}, got {array[bad].flat[0]}")


def within(name: str, array: Any, low: float, high: float, unit: str = "") -> None:
    """Check that every entry of ``array`` (already finite) lies in ``[low, high]``, the
    range ``impulse2d.envelope`` guarantees; the message gives the range and its unit."""
    values = np.asarray(array)
    entries = _entries(values)
    if entries is not None:
        first = next((v for v in entries if v < low or v > high), None)
    else:
        bad = (values < low) | (values > high)
        first = values[bad].flat[0] if np.any(bad) else None
    if first is not None:
        raise ValueError(
            f"{name} must be in [{low:g}, {high:g}]{unit} (the supported range, see "
            f"impulse2d.envelope), got {first:g}"
        )


def magnitude_at_most(name: str, array: Any, high: float, unit: str = "") -> None:
    """Check that every 2-vector along the last axis of ``array`` has a length <= ``high``."""
    values = np.asarray(array)
    entries = _entries(values)
    if entries is not None:  # np.hypot of each pair, as the array path computes it
        lengths = (np.hypot(x, y) for x, y in zip(entries[0::2], entries[1::2], strict=True))
        first = next((length for length in lengths if length > high), None)
    else:
        length = np.hypot(values[..., 0], values[..., 1])
        first = length[length > high].flat[0] if np.any(length > high) else None
    if first is not None:
        raise ValueError(
            f"{name} must have a magnitude <= {high:g}{unit} (the supported range, see "
            f"impulse2d.envelope), got {first:g}"
        )


def choice(name: str, value: Any, options: tuple[str, ...]) -> str:
    """One of a fixed set of strings."""
    if value not in options:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, options))}, got {value!r}")
    return value


def positive_int(name: str, value: Any) -> int:
    """An integer >= 1 (bools are refused: ``True`` is not a count)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < 1:
        raise ValueError(f"{name} must be >= 1, got {value}")
    return int(value)


def number_in(
    name: str, value: Any, low: float, high: float, unit: str = "", low_open: bool = False
) -> float:
    """A real number in ``[low, high]`` (``(low, high]`` with ``low_open``), as a float.
    Every refusal names the parameter and the range, huge and non-finite values alike:
    ``max_shot_seconds must be in (0, 3600] s, got 1e+300``."""
    rule = f"in {'(' if low_open else '['}{low:g}, {high:g}]{unit}"
    try:
        number = finite_scalar(name, value)
    except ValueError:
        raise ValueError(f"{name} must be a real number {rule}, got {value!r}") from None
    if (number <= low if low_open else number < low) or number > high:
        raise ValueError(f"{name} must be {rule}, got {number:g}")
    return number


def int_in(name: str, value: Any, low: int, high: int, high_text: str | None = None) -> int:
    """An integer (Python or numpy) in ``[low, high]``, as an int. Bools, floats (even
    whole ones), strings and None are refused: ``num_balls must be an int in [1, 15], got
    1.5``; ``high_text`` writes the upper bound in the message (``"2**63 - 1"``)."""
    rule = f"[{low}, {high if high_text is None else high_text}]"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an int in {rule}, got {value!r}")
    if not low <= int(value) <= high:
        raise ValueError(f"{name} must be in {rule}, got {value}")
    return int(value)


def word(name: str, value: Any, options: tuple[str, ...]) -> str:
    """One of a fixed set of strings; anything that is not a string (an array, a number)
    is refused by name too, before it is compared (``choice`` would compare a numpy
    array element by element)."""
    if not isinstance(value, str) or value not in options:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, options))}, got {value!r}")
    return str(value)


def rgb(name: str, value: Any) -> tuple[float, float, float]:
    """A colour: three numbers in [0, 255] (red, green, blue)."""
    array = real_array(name, value, (3,))
    if np.any((array < 0.0) | (array > 255.0)):
        raise ValueError(f"{name} must be three numbers in [0, 255], got {value!r}")
    return float(array[0]), float(array[1]), float(array[2])
