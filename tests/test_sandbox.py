"""The sandbox window, driven headless (SDL's dummy video driver) with real pygame events."""

import os
import subprocess
import sys

import numpy as np
import pytest

os.environ["SDL_VIDEODRIVER"] = "dummy"
pygame = pytest.importorskip("pygame")

from impulse2d.apps.sandbox import CUE_GAIN, Sandbox  # noqa: E402


@pytest.fixture
def sandbox():
    box = Sandbox("m09-circle-circle", width=320, height=180)
    yield box
    pygame.quit()


def _pixel(box: Sandbox, point) -> tuple[int, int]:
    x, y = box.renderer.camera.to_pixels(point[0], point[1], box.width, box.height)
    return round(float(x)), round(float(y))


def _drag(start: tuple[int, int], end: tuple[int, int]) -> None:
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=start, button=1))
    pygame.event.post(
        pygame.event.Event(pygame.MOUSEMOTION, pos=end, rel=(0, 0), buttons=(1, 0, 0))
    )
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP, pos=end, button=1))


def _key(key: int, mod: int = 0) -> None:
    pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=key, mod=mod, unicode=""))


def test_mouse_drag_is_the_cue(sandbox):
    """Dragging from a body and releasing gives it CUE_GAIN x drag (m/s) along the drag."""
    sandbox.paused = True
    body = next(b for b in sandbox.world.bodies if not b.fixed and hasattr(b, "radius"))
    before = body.velocity.copy()
    start = _pixel(sandbox, body.position)
    end = (start[0] + 40, start[1] - 20)  # right and up on screen
    _drag(start, end)
    sandbox.run(max_frames=1)
    drag = sandbox.world_point(end) - sandbox.world_point(start)
    change = body.velocity - before
    np.testing.assert_allclose(change, CUE_GAIN * drag, rtol=1e-6, atol=1e-9)
    assert change[0] > 0 and change[1] > 0  # screen up is world up


def test_cue_is_drawn_while_dragging(sandbox):
    """Between press and release the cue line appears in the frame."""
    sandbox.paused = True
    plain = sandbox.frame()
    sandbox.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=(50, 50), button=1))
    sandbox.handle(
        pygame.event.Event(pygame.MOUSEMOTION, pos=(150, 120), rel=(0, 0), buttons=(1, 0, 0))
    )
    dragging = sandbox.frame()
    assert np.any(dragging[85, 100] != plain[85, 100])  # on the line from (50,50) to (150,120)


def _fresh() -> Sandbox:
    pygame.event.clear()
    return Sandbox("m09-circle-circle", width=320, height=180)


def test_keys_pause_step_restart_and_switch(sandbox):
    """Space pauses, '.' steps once, P restarts the scene, Tab moves to the next scene."""
    sandbox.run(max_frames=3)
    assert sandbox.world.time > 0
    box = _fresh()
    _key(pygame.K_SPACE)
    box.run(max_frames=2)
    assert box.paused and box.world.time == 0.0
    _key(pygame.K_PERIOD)
    box.run(max_frames=1)
    assert box.world.time == pytest.approx(box.scene.dt)
    box = _fresh()
    start = [b.position for b in box.world.bodies]
    box.run(max_frames=20)
    assert not np.array_equal([b.position for b in box.world.bodies], start)
    _key(pygame.K_p)
    _key(pygame.K_SPACE)
    box.run(max_frames=1)
    np.testing.assert_array_equal([b.position for b in box.world.bodies], start)
    names = box.names
    _key(pygame.K_TAB)
    box.run(max_frames=1)
    assert box.scene.name == names[(names.index("m09-circle-circle") + 1) % len(names)]
    _key(pygame.K_TAB, pygame.KMOD_LSHIFT)
    box.run(max_frames=1)
    assert box.scene.name == "m09-circle-circle"


def test_quit_key_ends_the_loop(sandbox):
    """Q stops the loop before the frame budget is spent."""
    _key(pygame.K_q)
    sandbox.run(max_frames=50)
    assert sandbox.world.time == 0.0


def test_energy_readout_is_drawn(sandbox):
    """The window shows text over the frame (the energy readout in the corner)."""
    sandbox.paused = True
    sandbox.draw()
    shown = pygame.surfarray.array3d(sandbox.surface).swapaxes(0, 1)
    frame = sandbox.frame()
    assert np.any(shown[40:60, 8:300] != frame[40:60, 8:300])


def test_without_a_display_it_says_so():
    """With no display and no SDL driver chosen, the command exits with a clear message."""
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")
    }
    done = subprocess.run(
        [sys.executable, "-m", "impulse2d.apps.sandbox"],
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    if sys.platform.startswith("linux"):
        assert done.returncode != 0
        assert "no display" in done.stderr


def test_right_drag_holds_a_body_with_a_mouse_joint(sandbox):
    """Pressing the right button on a body holds it with a MouseJoint; moving the mouse
    moves the joint's target and the body follows it (within 5 cm after 1.5 s); letting
    go removes the joint."""
    body = next(b for b in sandbox.world.bodies if not b.fixed and hasattr(b, "radius"))
    start = _pixel(sandbox, body.position)
    end = (start[0] + 30, start[1] - 25)
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=start, button=3))
    pygame.event.post(
        pygame.event.Event(pygame.MOUSEMOTION, pos=end, rel=(0, 0), buttons=(0, 0, 1))
    )
    sandbox.run(max_frames=1)
    joint = sandbox.held
    assert joint is not None and joint.body is body and sandbox.world.joints == [joint]
    target = sandbox.world_point(end)
    np.testing.assert_allclose(joint.target, target)
    sandbox.run(max_frames=round(1.5 / sandbox.scene.dt))
    assert np.hypot(*(np.asarray(body.position) - target)) < 0.05
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP, pos=end, button=3))
    sandbox.run(max_frames=1)
    assert sandbox.held is None and sandbox.world.joints == []
