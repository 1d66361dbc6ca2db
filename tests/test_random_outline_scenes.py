"""The random-scene laws (``scene_laws.check``) over scenes with polygons and capsules among
the circles and boxes (``scenes_random``'s "triangle" and "capsule" kinds: 0.05-2 m):
the state stays finite, world 0 of a batch is bitwise the world alone, a snapshot replays
bitwise; no dynamic centre gets behind a plane; kinetic energy never grows where nothing
adds it; momentum is kept in free scenes. Derandomized, as ``test_random_scenes.py``."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

import scene_laws as laws
import scenes_random as sr

KINDS = ("circle", "box", "triangle", "capsule")
OUTLINES = settings(
    deadline=None,
    derandomize=True,
    database=None,
    print_blob=False,
    max_examples=40,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
FAMILIES = {name: laws.FAMILIES[name] for name in ("any", "planes", "conservative", "free")}


@pytest.mark.parametrize("family", list(FAMILIES))
@OUTLINES
@given(data=st.data())
def test_scenes_with_outlines_obey_every_law(family, data):
    scene = data.draw(sr.scenes(kinds=KINDS, max_bodies=8, **FAMILIES[family]))
    if not any(body.kind in ("triangle", "capsule") for body in scene.bodies):
        scene = data.draw(
            sr.scenes(kinds=("triangle", "capsule"), max_bodies=8, **FAMILIES[family])
        )
    note(sr.code(scene))
    broken = laws.check(family, scene, 100)
    assert broken in ([], [laws.LEFT_THE_ENVELOPE]), f"{family}: broke {broken}"
