"""The contact cache's store alone (``contacts.store``), on hand-built caches and points.

The store merges this step's points, in key order, with the cached points of pairs that
rest this step (dormant: both bodies enabled and still), dropping the rest. Checked
against a plain merge written here: the rows, their order, the count and the zeroed
rows after it, for caches that keep their keys, gain points, lose them, or both.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from impulse2d.core import contacts, workspace
from impulse2d.core.state import (
    APPROACH,
    BODY_I,
    CONTACT_COUNT,
    CONTACT_F,
    CONTACT_I,
    CONTACT_NX,
    CONTACT_NY,
    ENABLED,
    GROSS_IMPULSE,
    KEPT_TORQUE,
    NORMAL_IMPULSE,
    POINT_X,
    POINT_Y,
    SEPARATION,
    STEP_IMPULSE,
    TANGENT_IMPULSE,
    WORLD_I,
)
from impulse2d.core.workspace import (
    APPROACH_SPEED,
    DRIFT,
    GROSS_J,
    MOVING,
    NX,
    NY,
    POINT_F,
    RAX,
    RAY,
    SEP0,
    STEP_J,
    TERMS,
    X0,
    Y0,
)
from impulse2d.core.workspace import NORMAL_J as POINT_NORMAL_J
from impulse2d.core.workspace import TANGENT_J as POINT_TANGENT_J

SLOTS, CAPACITY = 8, 48


def _key(row) -> int:
    return int(contacts.point_key(int(row[0]), int(row[1]), int(row[2])))


def _point_row(points, terms, k, a) -> np.ndarray:
    """What the cache holds for point ``k`` of this step (body A ``a``)."""
    row = np.zeros(CONTACT_F)
    row[NORMAL_IMPULSE], row[TANGENT_IMPULSE] = (
        points[k, POINT_NORMAL_J],
        points[k, POINT_TANGENT_J],
    )
    row[STEP_IMPULSE], row[GROSS_IMPULSE] = points[k, STEP_J], points[k, GROSS_J]
    row[KEPT_TORQUE] = points[k, DRIFT] * points[k, GROSS_J]
    row[APPROACH] = points[k, APPROACH_SPEED]
    row[POINT_X], row[POINT_Y] = terms[a, X0] + points[k, RAX], terms[a, Y0] + points[k, RAY]
    row[CONTACT_NX], row[CONTACT_NY], row[SEPARATION] = (
        points[k, NX],
        points[k, NY],
        points[k, SEP0],
    )
    return row


def _expected(cache, cache_ids, count, points, ids, n, terms, enabled):
    """The plain merge: every point of this step, and each cached row not replaced whose
    two bodies are enabled and still, with nothing pushed this step; by key."""
    rows = {}
    for j in range(count):
        a, b = cache_ids[j, 0], cache_ids[j, 1]
        if terms[a, MOVING] == 0.0 and terms[b, MOVING] == 0.0 and enabled[a] and enabled[b]:
            row = cache[j].copy()
            row[[STEP_IMPULSE, GROSS_IMPULSE, KEPT_TORQUE]] = 0.0
            rows[_key(cache_ids[j])] = (row, cache_ids[j].copy())
    for k in range(n):
        rows[_key(ids[k])] = (_point_row(points, terms, k, ids[k, 0]), ids[k].copy())
    ordered = [rows[key] for key in sorted(rows)]
    return [r for r, _ in ordered], [i for _, i in ordered]


@st.composite
def caches(draw):
    """A cache and this step's points over ``SLOTS`` bodies: keys drawn from the same few
    pairs, so points replace, join and leave cached rows."""
    moving = draw(st.lists(st.booleans(), min_size=SLOTS, max_size=SLOTS))
    enabled = draw(st.lists(st.booleans(), min_size=SLOTS, max_size=SLOTS))
    key = st.tuples(st.integers(0, SLOTS - 2), st.integers(1, SLOTS - 1), st.integers(0, 2))
    keys = st.lists(key.filter(lambda t: t[0] < t[1]), max_size=CAPACITY // 2, unique=True)
    old, new = draw(keys), draw(keys)
    # Points only between bodies that move (the narrowphase makes no other).
    new = [t for t in new if moving[t[0]] or moving[t[1]]]
    return (
        moving,
        enabled,
        sorted(old, key=lambda t: contacts.point_key(*t)),
        sorted(new, key=lambda t: contacts.point_key(*t)),
        draw(st.integers(0, 2**32 - 1)),
    )


@settings(max_examples=300, deadline=None)
@given(caches())
def test_store_is_the_plain_merge_of_points_and_dormant_rows(case):
    moving, enabled, old, new, seed = case
    rng = np.random.default_rng(seed)
    body_i = np.zeros((1, SLOTS, BODY_I), np.int64)
    body_i[0, :, ENABLED] = enabled
    terms = np.zeros((SLOTS, TERMS))
    terms[:, MOVING] = moving
    terms[:, [X0, Y0]] = rng.normal(size=(SLOTS, 2))
    contact = np.zeros((1, CAPACITY, CONTACT_F))
    contact_i = np.zeros((1, CAPACITY, CONTACT_I), np.int64)
    contact[0, : len(old)] = rng.normal(size=(len(old), CONTACT_F))
    contact_i[0, : len(old)] = np.array(old, np.int64).reshape(-1, CONTACT_I)
    world_i = np.zeros((1, WORLD_I), np.int64)
    world_i[0, CONTACT_COUNT] = len(old)
    points = rng.normal(size=(CAPACITY, POINT_F))
    ids = np.zeros((CAPACITY, 3), np.int64)
    ids[: len(new)] = np.array(new, np.int64).reshape(-1, 3)
    rows, row_ids = _expected(contact[0], contact_i[0], len(old), points, ids, len(new), terms,
                              enabled)  # fmt: skip
    merged = np.full((CAPACITY, workspace.MERGED_F), np.nan)  # scratch: written before read
    merged_ids = np.full((CAPACITY, 3), -7, np.int64)
    contacts.store(body_i, contact, contact_i, world_i, 0, terms, points, ids, len(new), merged,
                   merged_ids)  # fmt: skip
    m = len(rows)
    assert world_i[0, CONTACT_COUNT] == m
    np.testing.assert_array_equal(contact[0, :m], np.array(rows).reshape(m, CONTACT_F))
    np.testing.assert_array_equal(contact_i[0, :m], np.array(row_ids).reshape(m, CONTACT_I))
    assert not contact[0, m:].any() and not contact_i[0, m:].any()  # zero past the count
