"""Slingshot2D level templates: families of structure, each with its own generator, and
the fixed split the evaluation protocol uses (PHYRE's and Phy-Q's idea).

A template is a kind of puzzle: "a pig on top of a tower", "a pig sheltering behind a
wall". Its generator draws the free parameters (where the structure stands, how many
storeys or rows, spans, materials, where the pigs sit) from a random generator, so one
template gives endless *tasks* (levels) that share a structure. Level seed ``k`` plays
template ``names[k % len(names)]`` with its parameters from ``np.random.default_rng(k)``:
consecutive seeds cycle through the templates, so any run of ``len(names)`` seeds holds
each template once and a test set is balanced across them.

The split (``SPLITS``) is fixed, so numbers mean the same in every report:

* ``"train"``: seven templates an agent may train on;
* ``"held-out"``: three templates no training may see, each a new arrangement of the
  structures (a thick wall, a pyramid guarding a tower, a staircase of columns);
  scoring on them measures *broad* generalisation (Phy-Q's term); scoring on unseen
  seeds of the train templates measures *local* generalisation.

Every generator keeps to the game's slots (at most ``max_pigs`` pigs and ``max_blocks``
blocks: the largest templates use 12 blocks and 2 pigs) and to the span the generated
levels use (structures between x = 7.5 and 15 m), and places structures apart.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ._levels import POST, SQUARE, Level

Template = Callable[[np.random.Generator], Level]


def _materials(rng: np.random.Generator, count: int) -> list[int]:
    return [int(m) for m in rng.integers(3, size=count)]


def _tower(rng: np.random.Generator) -> Level:
    """A tower of one to three storeys, a pig on top."""
    level = Level("tower")
    x = float(rng.uniform(8.5, 12.5))
    span, storeys = float(rng.uniform(0.8, 1.4)), int(rng.integers(1, 4))
    top = level.tower(x, 0.0, span, _materials(rng, storeys))
    level.pig(x, top)
    return level


def _bunker(rng: np.random.Generator) -> Level:
    """A pig inside a tower of one to three storeys (its inside, span - post width >= 0.6
    m, fits a pig), and half the time a second on the roof."""
    level = Level("bunker")
    x = float(rng.uniform(8.5, 12.5))
    span, storeys = float(rng.uniform(0.8, 1.4)), int(rng.integers(1, 4))
    top = level.tower(x, 0.0, span, _materials(rng, storeys))
    level.pig(x, 0.0)
    if rng.random() < 0.5:
        level.pig(x, top)
    return level


def _pyramid(rng: np.random.Generator) -> Level:
    """A pyramid of two to four rows of squares of one material, a pig on top."""
    level = Level("pyramid")
    x = float(rng.uniform(9.0, 12.5))
    level.pig(x, level.pyramid(x, int(rng.integers(2, 5)), int(rng.integers(3))))
    return level


def _shelter(rng: np.random.Generator) -> Level:
    """A column of two to four squares, a pig on the ground behind it."""
    level = Level("shelter")
    x = float(rng.uniform(8.0, 11.5))
    level.column(x, int(rng.integers(2, 5)), int(rng.integers(3)))
    level.pig(x + SQUARE / 2 + 0.35 + float(rng.uniform(0.0, 1.0)), 0.0)
    return level


def _perch(rng: np.random.Generator) -> Level:
    """A pig on top of a column of two to five squares."""
    level = Level("perch")
    x = float(rng.uniform(9.0, 13.5))
    level.pig(x, level.column(x, int(rng.integers(2, 6)), int(rng.integers(3))))
    return level


def _twin(rng: np.random.Generator) -> Level:
    """Two towers of one or two storeys, 2.5-4 m apart, a pig on each."""
    level = Level("twin")
    x = float(rng.uniform(8.5, 10.0))
    for _ in range(2):
        span = float(rng.uniform(0.8, 1.2))
        level.pig(x, level.tower(x, 0.0, span, _materials(rng, int(rng.integers(1, 3)))))
        x += float(rng.uniform(2.5, 4.0))
    return level


def _pyramids(rng: np.random.Generator) -> Level:
    """Two pyramids of two or three rows, 2.2-3.5 m apart, a pig on each."""
    level = Level("pyramids")
    x = float(rng.uniform(8.5, 10.0))
    for _ in range(2):
        level.pig(x, level.pyramid(x, int(rng.integers(2, 4)), int(rng.integers(3))))
        x += float(rng.uniform(2.2, 3.5))
    return level


def _wall(rng: np.random.Generator) -> Level:
    """Held out. A wall two columns thick, three or four squares high, and one or two
    pigs on the ground 1-3 m behind it."""
    level = Level("wall")
    x, height = float(rng.uniform(8.0, 10.0)), int(rng.integers(3, 5))
    for k in range(2):
        level.column(x + k * (SQUARE + 0.2), height, int(rng.integers(3)))
    behind = x + SQUARE + 0.2 + SQUARE / 2
    for _ in range(int(rng.integers(1, 3))):
        behind += float(rng.uniform(1.0, 1.5))
        level.pig(behind, 0.0)
    return level


def _castle(rng: np.random.Generator) -> Level:
    """Held out. A pyramid of two or three rows guarding a tower of one or two storeys,
    with a pig inside the tower and one on its roof."""
    level = Level("castle")
    rows = int(rng.integers(2, 4))
    x = float(rng.uniform(8.6, 9.6))
    level.pyramid(x, rows, int(rng.integers(3)))
    span = float(rng.uniform(0.8, 1.2))
    tower = x + rows * SQUARE / 2 + float(rng.uniform(0.8, 1.8)) + span / 2 + POST[0]
    top = level.tower(tower, 0.0, span, _materials(rng, int(rng.integers(1, 3))))
    level.pig(tower, 0.0)
    level.pig(tower, top)
    return level


def _stairs(rng: np.random.Generator) -> Level:
    """Held out. Three columns rising left to right (one step higher each, from one or two
    squares), a pig on the top step and one on the ground beyond it."""
    level = Level("stairs")
    x, first = float(rng.uniform(8.5, 10.5)), int(rng.integers(1, 3))
    step = float(rng.uniform(0.7, 1.1))
    for k in range(3):
        top = level.column(x + k * step, first + k, int(rng.integers(3)))
    last = x + 2 * step
    level.pig(last, top)
    level.pig(last + SQUARE / 2 + 0.35 + float(rng.uniform(0.3, 1.2)), 0.0)
    return level


TEMPLATES: dict[str, Template] = {
    "tower": _tower,
    "bunker": _bunker,
    "pyramid": _pyramid,
    "shelter": _shelter,
    "perch": _perch,
    "twin": _twin,
    "pyramids": _pyramids,
    "wall": _wall,
    "castle": _castle,
    "stairs": _stairs,
}
"""Every template by name: the seven train templates, then the three held out."""

SPLITS: dict[str, tuple[str, ...]] = {
    "train": ("tower", "bunker", "pyramid", "shelter", "perch", "twin", "pyramids"),
    "held-out": ("wall", "castle", "stairs"),
    "all": tuple(TEMPLATES),
}
"""The fixed split: templates to train on, templates held out, and all of them."""


def template_names(
    templates: Any,
    library: dict[str, Template] = TEMPLATES,
    splits: dict[str, tuple[str, ...]] = SPLITS,
) -> tuple[str, ...]:
    """Checked template names: a split's name (``"train"``, ``"held-out"``, ``"all"``) or a
    non-empty sequence of distinct template names, of ``library`` and its ``splits``
    (v0's by default; Slingshot2DBlocks-v0 passes its own, ``_block_templates``)."""
    if isinstance(templates, str):
        if templates in splits:
            return splits[templates]
        if templates in library:
            return (templates,)
        raise ValueError(
            f"templates must be a split ({', '.join(splits)}), a template name "
            f"({', '.join(library)}) or a sequence of template names, got {templates!r}"
        )
    names = tuple(templates) if isinstance(templates, Sequence) else None
    if not names or any(not isinstance(n, str) or n not in library for n in names):
        raise ValueError(
            f"templates must be a split ({', '.join(splits)}) or a non-empty sequence of "
            f"template names ({', '.join(library)}), got {templates!r}"
        )
    if len(set(names)) != len(names):
        raise ValueError(f"templates must name each template once, got {templates!r}")
    return names


def template_level(
    names: tuple[str, ...], seed: int, library: dict[str, Template] = TEMPLATES
) -> Level:
    """Level seed ``seed`` of the templates ``names`` (of ``library``): template
    ``names[seed % n]``, its parameters drawn from ``np.random.default_rng(seed)``."""
    return library[names[seed % len(names)]](np.random.default_rng(seed))
