"""Sleeping by islands, as the tutorial's extra asks and Box2D does.

A dynamic body whose speed stays below ``sleep_speed`` (with rotation counted as the
speed of its bounding circle's rim, ``R |w|``) accumulates ``sleep_time``. An *island*
is a set of dynamic bodies joined by contacts or springs; an island falls asleep when
all its bodies have been slow for ``time_to_sleep`` seconds, and wakes as a whole when
something awake touches any of its bodies. Sleeping bodies cost nothing: their pairs
are skipped by the narrowphase, and they are neither integrated nor solved.

Putting a single slow body to sleep while a neighbour still moves would leave it
floating when the neighbour slides away; islands prevent that.
"""

from __future__ import annotations

import numpy as np


def components(nodes: int, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Connected components of an undirected graph: each node's label is the smallest
    node of its component. Vectorised label propagation with pointer jumping."""
    label = np.arange(nodes)
    if first.size == 0:
        return label
    while True:
        la, lb = label[first], label[second]
        if np.array_equal(la, lb):
            return label
        low = np.minimum(la, lb)
        # Hook the root of each side onto the smaller root, then flatten the trees.
        np.minimum.at(label, la, low)
        np.minimum.at(label, lb, low)
        while True:
            jumped = label[label]
            if np.array_equal(jumped, label):
                break
            label = jumped


def islands(total: int, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Island label (a flat body index) of every body, joined by the edges given."""
    touched = np.unique(np.concatenate([first, second]))
    label = np.arange(total)
    if touched.size == 0:
        return label
    local = components(
        touched.size, np.searchsorted(touched, first), np.searchsorted(touched, second)
    )
    label[touched] = touched[local]
    return label


def fall_asleep(
    awake: np.ndarray,
    candidate: np.ndarray,
    sleep_time: np.ndarray,
    time_to_sleep: float,
    edges: tuple[np.ndarray, np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """Bodies whose whole island has been slow long enough, and their island labels.

    ``candidate`` marks awake dynamic bodies (the only ones that can sleep); ``edges``
    join bodies that must sleep together.
    """
    label = islands(awake.size, *edges)
    # An island is as restless as its most restless body; non-candidates in an island
    # (none, since edges only join candidates) would keep it awake.
    restless = np.where(candidate, sleep_time, -np.inf)
    island_time = np.full(awake.size, np.inf)
    np.minimum.at(island_time, label, restless)
    sleepy = candidate & (island_time[label] >= time_to_sleep)
    return np.flatnonzero(sleepy), label
