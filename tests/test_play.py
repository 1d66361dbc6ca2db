"""``python -m impulse2d.apps.play``, driven headless (SDL's dummy video driver) with real
pygame events: the drag is the move, the shot plays in the window, P restarts, Esc quits."""

import importlib.util
import os
import sys

import numpy as np
import pytest

os.environ["SDL_VIDEODRIVER"] = "dummy"
pygame = pytest.importorskip("pygame")

from impulse2d.apps.play import HUD_HEIGHT, Player, load_game, main  # noqa: E402

SIZE = (320, 180)


def _slingshot_missing() -> bool:
    try:
        return importlib.util.find_spec("impulse2d.envs.slingshot") is None
    except ImportError:
        return True


GAME_NAMES = [
    "pool",
    pytest.param(
        "slingshot",
        marks=pytest.mark.skipif(_slingshot_missing(), reason="impulse2d.envs.slingshot not there"),
    ),
]
OPTIONS = {"pool": {"num_balls": 1}, "slingshot": {}}


def _player(name: str, width: int = SIZE[0], height: int = SIZE[1], seed: int = 0) -> Player:
    game = load_game(name)(batch_size=1, **OPTIONS[name])
    player = Player(game, name, width, height, seed=seed, realtime=False)
    pygame.event.clear()
    return player


@pytest.fixture(autouse=True)
def _close_window():
    yield
    pygame.quit()


def _window_pixel(player: Player, point) -> tuple[int, int]:
    x, y = player.renderer.to_pixels(float(point[0]), float(point[1]))
    return round(x), round(y) + HUD_HEIGHT


def _drag(start: tuple[int, int], end: tuple[int, int]) -> None:
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=start, button=1))
    pygame.event.post(
        pygame.event.Event(pygame.MOUSEMOTION, pos=end, rel=(0, 0), buttons=(1, 0, 0))
    )
    pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP, pos=end, button=1))


def _key(key: int) -> None:
    pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=key, mod=0, unicode=""))


def test_pixels_map_back_to_the_world():
    """A window pixel maps to the world point the renderer draws there."""
    player = _player("pool")
    for point in ([0.0, 0.0], [1.0, -0.5], [-1.2, 0.6]):
        pixel = player.renderer.to_pixels(*point)
        back = player.point((pixel[0], pixel[1] + HUD_HEIGHT))
        np.testing.assert_allclose(back, point, atol=1e-12)


@pytest.mark.parametrize("sign", [1, -1])
def test_pool_drag_shoots_along_the_drag(sign):
    """A gentle mouse drag to the right (left) sends the cue ball right (left), and the
    shot is shown in the window while it runs."""
    player = _player("pool", 640, 360)
    cue = player.game.balls[0]
    before = cue.position.copy()
    start = _window_pixel(player, before)
    _drag(start, (start[0] + 4 * sign, start[1]))
    player.run(max_frames=1)
    assert player.shots == 1
    assert sign * (cue.position[0] - before[0]) > 0.1
    assert player.frames_drawn > 10  # frames during the shot, not just the one after


def test_stroke_and_power_are_shown_while_dragging():
    """Between press and release: the stroke is drawn, the bar gives drag and power."""
    player = _player("pool")
    plain = player.frame().copy()
    player.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=(50, 50 + HUD_HEIGHT), button=1))
    player.handle(
        pygame.event.Event(
            pygame.MOUSEMOTION, pos=(150, 120 + HUD_HEIGHT), rel=(0, 0), buttons=(1, 0, 0)
        )
    )
    assert np.any(player.frame()[85, 100] != plain[85, 100])  # on the line
    assert "power" in player.hud()[1] and "drag" in player.hud()[1]
    player.draw()
    shown = pygame.surfarray.array3d(player.surface).swapaxes(0, 1)
    assert np.any(shown[:HUD_HEIGHT] != shown[0, 0])  # text in the bar
    np.testing.assert_array_equal(shown[HUD_HEIGHT:], player.frame())


@pytest.mark.parametrize("name", GAME_NAMES)
def test_a_drag_is_a_move_and_p_restarts(name):
    """Press, drag, release plays a shot (counted, scored, described); P starts the next
    episode: shot count and score back to 0, the world as the next seed sets it up."""
    player = _player(name, seed=3)
    middle = (SIZE[0] // 2, SIZE[1] // 2 + HUD_HEIGHT)
    _drag(middle, (middle[0] - 25, middle[1] + 10))
    player.run(max_frames=1)
    assert player.shots == 1
    assert player.last_reward is not None and player.score == player.last_reward
    assert player.last_info and "last shot" in player.hud()[0]
    _key(pygame.K_p)
    player.run(max_frames=1)
    assert (player.shots, player.score, player.over) == (0, 0.0, False)
    fresh = load_game(name)(batch_size=1, **OPTIONS[name])
    fresh.seed([0], [4])
    fresh.reset([0])
    np.testing.assert_array_equal(player.game.world.array("pose"), fresh.world.array("pose"))


def test_episode_over_waits_for_p():
    """After the last ball drops the bar says so and drags do nothing until P."""
    player = _player("pool")
    player.over = True
    assert "P to restart" in player.hud()[1]
    _drag((100, 100), (140, 100))
    player.run(max_frames=1)
    assert player.shots == 0
    _key(pygame.K_p)
    player.run(max_frames=1)
    assert not player.over


@pytest.mark.parametrize("key", ["escape", "quit"])
def test_esc_or_closing_ends_the_loop(key):
    player = _player("pool")
    if key == "escape":
        _key(pygame.K_ESCAPE)
    else:
        pygame.event.post(pygame.event.Event(pygame.QUIT))
    assert player.run(max_frames=50) == 0
    assert player.quitting


def test_closing_the_window_mid_shot():
    """The window is pumped during a shot: closing it stops the shot cleanly."""
    player = _player("pool")
    cue = player.game.balls[0].position
    start = _window_pixel(player, cue)
    pygame.event.post(pygame.event.Event(pygame.QUIT))  # waiting in the queue during the shot
    player.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=start, button=1))
    going = player.handle(
        pygame.event.Event(pygame.MOUSEBUTTONUP, pos=(start[0] + 60, start[1]), button=1)
    )
    assert not going and player.quitting
    assert player.shots == 0 and player.frames_drawn == 1


def test_main_plays_until_esc(capsys):
    """The command opens the window and returns 0 when Esc is pressed."""
    pygame.display.init()
    _key(pygame.K_ESCAPE)
    assert main(["pool", "--balls", "1", "--width", "160", "--height", "90", "--seed", "1"]) == 0


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (["snooker"], "game"),
        (["pool", "--balls", "many"], "--balls"),
        (["pool", "--balls", "0"], "--balls"),
        (["pool", "--layout", "diamond"], "--layout"),
        (["pool", "--level", "1"], "--level"),
        (["pool", "--width", "10"], "--width"),
        pytest.param(
            ["slingshot", "--level", "no-such-level"],
            "--level",
            marks=pytest.mark.skipif(_slingshot_missing(), reason="no slingshot yet"),
        ),
        pytest.param(
            ["slingshot", "--balls", "3"],
            "--balls",
            marks=pytest.mark.skipif(_slingshot_missing(), reason="no slingshot yet"),
        ),
    ],
)
def test_bad_arguments_are_named(argv, named, capsys):
    with pytest.raises(SystemExit) as raised:
        main(argv)
    assert raised.value.code == 2
    assert f"argument {named}" in capsys.readouterr().err


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="display check is for Linux")
def test_without_a_display_it_says_so(monkeypatch, capsys):
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(name, raising=False)
    assert main(["pool", "--balls", "1"]) == 1
    err = capsys.readouterr().err
    assert "no display" in err and "render_mode='rgb_array'" in err


def test_without_pygame_it_says_how_to_install(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "pygame", None)  # import pygame now raises ImportError
    assert main(["pool", "--balls", "1"]) == 1
    assert "pip install 'impulse2d[play]'" in capsys.readouterr().err


def test_p_during_a_shot_restarts_after_it():
    """P pressed while a shot runs is kept, and starts the next episode once it ends."""
    player = _player("pool")
    start = _window_pixel(player, player.game.balls[0].position)
    _key(pygame.K_p)  # waiting in the queue during the shot
    player.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, pos=start, button=1))
    assert player.handle(
        pygame.event.Event(pygame.MOUSEBUTTONUP, pos=(start[0] + 2, start[1]), button=1)
    )
    assert (player.episode, player.shots, player.last_reward) == (1, 0, None)
