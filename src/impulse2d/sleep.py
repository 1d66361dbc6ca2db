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


def fall_asleep(
    ready: np.ndarray,
    edges: tuple[np.ndarray, np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """Bodies whose whole island has been slow long enough, and their island labels.

    ``ready`` lists the bodies (flat indices) slow for long enough; ``edges`` join awake
    dynamic bodies that must sleep together. Only edges that touch a ready body matter:
    an island with a body that is not ready stays awake, and islands of bodies that are
    not ready are of no interest, so the work is proportional to the ready bodies.
    Returns the bodies to put to sleep and an island label for each (a member's index).
    """
    first, second = edges
    is_ready = np.zeros(
        max(int(ready.max()), int(first.max(initial=0)), int(second.max(initial=0))) + 1, dtype=bool
    )
    is_ready[ready] = True
    touching = is_ready[first] | is_ready[second]
    first, second = first[touching], second[touching]
    nodes = np.unique(np.concatenate([ready, first, second]))
    local = components(nodes.size, np.searchsorted(nodes, first), np.searchsorted(nodes, second))
    # An island sleeps only if every member is ready.
    blocked = np.zeros(nodes.size, dtype=bool)
    np.logical_or.at(blocked, local, ~is_ready[nodes])
    sleepy = is_ready[nodes] & ~blocked[local]
    return nodes[sleepy], nodes[local[sleepy]]
