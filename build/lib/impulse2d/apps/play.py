"""Play the games yourself: ``python -m impulse2d.apps.play pool`` or ``... play slingshot``.

The tutorial's last milestone: its shot games in a pygame-ce window (the ``play`` extra),
one move at a time, as the Gymnasium environments play them. Controls:

* press the left mouse button, drag and release: the move. Each game says what a drag
  means (``ShotGame.drag_action``): in pool the drag from press to release is the cue
  stroke, its direction the shot's and its length the speed (full speed at 0.635 m); in
  the slingshot it is the sling pulled back. The stroke is drawn while you drag, with its
  length and the power it gives; the shot then plays in the window at about real time;
* ``P`` restarts: a new episode, from the next seed (``--seed N`` makes episode ``k``
  start from seed ``N + k``; without it every episode is random);
* ``Esc``, ``Q`` or closing the window quits, also in the middle of a shot.

The bar at the top shows the game, the shots played, the total score, what the last shot
did, and ``episode over - P to restart`` once the episode has ended (only ``P`` goes on).

Options: ``--seed N``, ``--width W --height H`` (the playing area, pixels) and the
games' own, ``--balls N`` and ``--layout rack|random`` for pool, ``--level NAME`` and
``--birds N`` for the slingshot. Without a display (or without pygame-ce) it says so and
exits; the games also play headless as Gymnasium environments
(``gym.make("Pool2D-v0", render_mode="rgb_array")``).
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import math
import sys
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _raster as raster
from .sandbox import CUE_COLOUR, display_problem

if TYPE_CHECKING:
    from ..envs._core import ShotGame

GAMES = {
    "pool": "impulse2d.envs.pool:PoolGame",
    "slingshot": "impulse2d.envs.slingshot:SlingshotGame",
}
# Command-line game options: flag -> (keyword of the game's constructor, type, help). A
# game is given only the options its constructor takes.
OPTIONS = {
    "--balls": ("num_balls", int, "pool: object balls, 1-15"),
    "--layout": ("layout", str, "pool: 'rack' or 'random' (default: rack for 15 balls)"),
    "--level": ("level", str, "slingshot: 'random', 'handmade' or a level's name"),
    "--birds": ("num_birds", int, "slingshot: birds per episode, 1-10"),
}
FPS = 60  # frames per second, in the window and during a shot (at about real time)
HUD_HEIGHT = 44  # pixels of the text bar above the playing area
HUD_COLOUR = (18, 20, 26)
TEXT_COLOUR = (235, 235, 235)
INSTALL = "pip install 'impulse2d[play]'"
HEADLESS = "the games also play headless: gym.make('Pool2D-v0', render_mode='rgb_array')"


class _Quit(Exception):
    """Raised from inside a shot when the person closes the window."""


def load_game(name: str) -> type[ShotGame]:
    """The game class registered in ``GAMES`` under ``name`` (imported now)."""
    module, _, attribute = GAMES[name].partition(":")
    return getattr(importlib.import_module(module), attribute)


def describe(info: dict[str, Any]) -> str:
    """A shot's info as words: ``potted 1, fouls 0, balls left 0, cue potted``. Counts
    are shown always, flags only when set; the engine's step count is left out."""
    words = []
    for key, value in info.items():
        if key == "physics_steps":
            continue
        label = key.replace("_", " ")
        if isinstance(value, bool):
            if value:
                words.append(label)
        elif isinstance(value, int):
            words.append(f"{label} {value}")
        else:
            words.append(f"{label} {value:.3g}")
    return ", ".join(words)


class Player:
    """A person playing world 0 of a ``ShotGame`` in a pygame-ce window. Events go in
    through ``handle``, pictures come out of ``frame`` (the playing area) and ``draw``
    (the window with its text bar), so tests can drive it with real pygame events.

    ``fps``: frames per second shown during a shot (every ``1 / (fps dt)`` physics
    steps); with ``realtime`` the window is capped at that rate, so shots play at about
    real time. ``seed``: episode ``k`` starts from seed ``seed + k`` (None: random).
    """

    def __init__(
        self,
        game: ShotGame,
        name: str,
        width: int = 960,
        height: int = 540,
        seed: int | None = None,
        fps: float = FPS,
        realtime: bool = True,
    ) -> None:
        import pygame

        self.pygame = pygame
        pygame.display.init()  # not pygame.init(): no sound, so no audio device is needed
        pygame.font.init()
        self.surface = pygame.display.set_mode((width, height + HUD_HEIGHT))
        pygame.display.set_caption(f"impulse2d: {name}")
        self.font = pygame.font.Font(None, 22)
        self.clock = pygame.time.Clock()
        self.game, self.name, self.width, self.height = game, name, width, height
        self.fps, self.realtime, self.seed = fps, realtime, seed
        self.renderer = game.make_renderer(width, height)
        self.frame_every = max(1, round(1.0 / (fps * game.dt)))  # physics steps a frame
        self.episode = -1
        self.press: tuple[float, float] | None = None  # window pixel where a drag started
        self.mouse = (0.0, 0.0)
        self.quitting = False
        self.frames_drawn = 0
        self.restart()

    # -- episodes and shots ----------------------------------------------------------------
    def restart(self) -> None:
        """A new episode in world 0, from the next seed (what ``P`` does)."""
        self.episode += 1
        seed = None if self.seed is None else self.seed + self.episode
        self.game.seed([0], [seed])
        self.game.reset([0])
        self.shots, self.score = 0, 0.0
        self.last_reward: float | None = None
        self.last_info: dict[str, Any] = {}
        self.over = False
        self.shooting = False
        self._restart_after_shot = False
        self.press = None
        self._picture: np.ndarray | None = None
        self.renderer.render(self.game.world, 0)  # fixes the camera before a click maps

    def point(self, pixel: tuple[float, float]) -> np.ndarray:
        """The world point (m) under a window pixel (the bar above the playing area
        shifts it down by ``HUD_HEIGHT``)."""
        return self.renderer.to_world(pixel[0], pixel[1] - HUD_HEIGHT)

    def action(self, press: tuple[float, float], release: tuple[float, float]) -> np.ndarray:
        """The game's action for a drag between two window pixels."""
        return np.asarray(self.game.drag_action(0, self.point(press), self.point(release)))

    def shoot(self, press: tuple[float, float], release: tuple[float, float]) -> None:
        """Play the move meant by a drag, showing the shot as it runs. Closing the window
        during it sets ``quitting`` and leaves the shot unfinished and uncounted."""
        action = self.action(press, release)
        self.shooting = True
        try:
            reward, terminated, info = self.game.shoot(
                [0], action[None], on_frame=self._during_shot, every=self.frame_every
            )
        except _Quit:
            self.quitting = True
            return
        finally:
            self.shooting = False
            self._picture = None
        self.shots += 1
        self.last_reward = float(reward[0])
        self.score += self.last_reward
        self.last_info = {key: value[0].item() for key, value in info.items()}
        self.over = bool(terminated[0])
        if self._restart_after_shot:
            self.restart()

    def _during_shot(self) -> None:
        """``shoot``'s ``on_frame``: show the frame, and keep the window responsive."""
        pygame = self.pygame
        self._picture = None
        self.draw()
        self.clock.tick(self.fps if self.realtime else 0)
        for event in pygame.event.get():
            if self._is_quit(event):
                raise _Quit
            if event.type == pygame.KEYDOWN and event.key == pygame.K_p:
                self._restart_after_shot = True

    # -- input -----------------------------------------------------------------------------
    def _is_quit(self, event: Any) -> bool:
        pygame = self.pygame
        return event.type == pygame.QUIT or (
            event.type == pygame.KEYDOWN and event.key in (pygame.K_ESCAPE, pygame.K_q)
        )

    def handle(self, event: Any) -> bool:
        """React to one pygame event; returns False when the person asked to quit."""
        pygame = self.pygame
        if self._is_quit(event):
            self.quitting = True
        elif event.type == pygame.KEYDOWN and event.key == pygame.K_p:
            self.restart()
        elif event.type == pygame.MOUSEBUTTONDOWN and event.button == 1 and not self.over:
            self.press = self.mouse = tuple(map(float, event.pos))
        elif event.type == pygame.MOUSEMOTION:
            self.mouse = tuple(map(float, event.pos))
        elif event.type == pygame.MOUSEBUTTONUP and event.button == 1 and self.press:
            self.mouse, press = tuple(map(float, event.pos)), self.press
            self.press = None
            self.shoot(press, self.mouse)
        return not self.quitting

    # -- pictures --------------------------------------------------------------------------
    def frame(self) -> np.ndarray:
        """The playing area, ``(height, width, 3)`` uint8: the world, and the stroke from
        the press to the mouse while dragging."""
        if self._picture is None:
            self._picture = self.renderer.render(self.game.world, 0)
        if self.press is None:
            return self._picture
        canvas = self._picture.astype(np.float32)
        (x0, y0), (x1, y1) = self.press, self.mouse
        raster.disc(canvas, x0, y0 - HUD_HEIGHT, 4.0, CUE_COLOUR)
        raster.segment(canvas, x0, y0 - HUD_HEIGHT, x1, y1 - HUD_HEIGHT, 3.0, CUE_COLOUR)
        return (canvas + 0.5).astype(np.uint8)

    def hud(self) -> list[str]:
        """The two lines of the text bar."""
        top = f"{self.name}    shot {self.shots}    score {self.score:g}"
        if self.last_reward is not None:
            top += f"    last shot {self.last_reward:+g}: {describe(self.last_info)}"
        if self.press is not None:
            start, end = self.point(self.press), self.point(self.mouse)
            power = 50.0 * (float(self.action(self.press, self.mouse)[-1]) + 1.0)
            length = math.hypot(*(end - start))
            bottom = f"drag {length:.2f} m    power {power:.0f}%    release to shoot"
        elif self.shooting:
            bottom = "shooting...    Esc quit"
        elif self.over:
            bottom = "episode over \N{EM DASH} P to restart"
        else:
            bottom = "drag with the mouse and release to shoot    P restart    Esc quit"
        return [top, bottom]

    def draw(self) -> None:
        """The window: the text bar, then the playing area under it."""
        pygame = self.pygame
        self.surface.fill(HUD_COLOUR, (0, 0, self.width, HUD_HEIGHT))
        for row, text in enumerate(self.hud()):
            self.surface.blit(self.font.render(text, True, TEXT_COLOUR), (8, 5 + 19 * row))
        picture = pygame.surfarray.make_surface(np.ascontiguousarray(self.frame().swapaxes(0, 1)))
        self.surface.blit(picture, (0, HUD_HEIGHT))
        pygame.display.flip()
        self.frames_drawn += 1

    def run(self, max_frames: int | None = None) -> int:
        """The event loop, at most ``fps`` frames per second; returns the frames drawn
        (``max_frames``: stop after that many, for tests)."""
        pygame = self.pygame
        frames = 0
        while max_frames is None or frames < max_frames:
            if not all(self.handle(event) for event in pygame.event.get()):
                break
            self.draw()
            self.clock.tick(self.fps if self.realtime else 0)
            frames += 1
        return frames


# -- the command ---------------------------------------------------------------------------
def parser() -> argparse.ArgumentParser:
    """The command line of ``python -m impulse2d.apps.play``."""
    cli = argparse.ArgumentParser(
        prog="python -m impulse2d.apps.play",
        description="Play the impulse2d games with the mouse: drag and release to shoot, "
        "P restarts, Esc quits.",
    )
    cli.add_argument("game", choices=list(GAMES), help="the game to play")
    cli.add_argument("--seed", type=int, default=None, help="seed of the first episode")
    cli.add_argument("--width", type=_size, default=960, help="playing area width (pixels)")
    cli.add_argument("--height", type=_size, default=540, help="playing area height (pixels)")
    for flag, (_, kind, text) in OPTIONS.items():
        cli.add_argument(flag, type=kind, default=argparse.SUPPRESS, help=text)
    return cli


def _size(text: str) -> int:
    value = int(text)
    if value < 64:
        raise argparse.ArgumentTypeError(f"must be at least 64 pixels, got {value}")
    return value


def _make_game(cli: argparse.ArgumentParser, args: argparse.Namespace) -> ShotGame:
    """The chosen game with its options, or an argparse error naming the argument."""
    try:
        game_class = load_game(args.game)
    except ImportError as error:
        raise SystemExit(f"cannot load the {args.game} game ({error}); {INSTALL}") from None
    accepted = inspect.signature(game_class).parameters
    options: dict[str, Any] = {}
    for flag, (keyword, _, _) in OPTIONS.items():
        if not hasattr(args, flag[2:]):
            continue
        if keyword not in accepted:
            takes = [f for f, (k, _, _) in OPTIONS.items() if k in accepted]
            cli.error(
                f"argument {flag}: the {args.game} game has no such option"
                f" (its options: {', '.join(takes) or 'none'})"
            )
        options[keyword] = getattr(args, flag[2:])
    try:
        return game_class(batch_size=1, **options)
    except ValueError as error:
        named = [f for f, (k, _, _) in OPTIONS.items() if k in options and k in str(error)]
        cli.error(f"argument {named[0]}: {error}" if named else str(error))


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns its exit status (argparse errors exit with status 2)."""
    cli = parser()
    args = cli.parse_args(argv)
    game = _make_game(cli, args)
    try:
        import pygame
    except ImportError:
        print(f"playing needs pygame-ce: {INSTALL}; or {HEADLESS}", file=sys.stderr)
        return 1
    problem = display_problem()
    if problem is not None:
        print(f"{problem}; {HEADLESS}", file=sys.stderr)
        return 1
    try:
        player = Player(game, args.game, args.width, args.height, seed=args.seed)
    except pygame.error as error:
        print(f"cannot open a window ({error}); {HEADLESS}", file=sys.stderr)
        pygame.quit()
        return 1
    try:
        player.run()
    finally:
        pygame.quit()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
