"""What Pool2D and Slingshot2D share: turn-based games on a batch of worlds.

A *shot game* is played one move at a time: the agent picks an action (a cue stroke, a
launch), the physics runs until every body has come to rest (or a step cap), and the game
scores what happened. ``ShotGame`` holds ``batch_size`` such games in one batched
``impulse2d.World``; a single Gymnasium environment is a game with a batch of one, and the
vector environment steps all its worlds in the same numpy calls. Because the engine steps
every world of a batch exactly as it would alone, env ``i`` of a vector environment seeded
``seed`` gives bitwise what a single environment seeded ``seed + i`` gives.

A shot runs in compiled code from the stroke to rest (``World.run_until_rest``): a world
whose shot has ended costs nothing while the others are still moving, and what a game
checks during a shot is an engine feature the kernels run (pockets are sensors, blocks
and pigs have health). A shot that reaches the step cap is ended with ``World.stop`` in
that world, alone or in a batch alike.

A new episode is built in a one-world *template* (by the same code that built the batch)
and copied into its world with ``World.restore``: that writes only the chosen world, so a
reset in a vector environment leaves the other worlds exactly as they were.

A game gives ``ShotGame.__init__`` what the loop needs, as keyword arguments (the
contract, checked there): ``world`` (the batch), ``template`` (the same scene with one
world), ``dt`` (physics step, s), ``max_shot_steps`` (the cap of one shot; ``shot_steps``
turns a game's ``max_shot_seconds`` into it) and the bounds of one observation,
``observation_low`` / ``observation_high``. A game checks its own arguments first
(``check_num_envs`` for the number of worlds), builds its worlds, then calls it. It also
fills in ``_new_episode`` (set the template up from a world's own random generator),
``_launch`` (apply the actions), ``_score`` (reward, end of episode and info after a
shot, from what the engine recorded), ``observe``, ``make_renderer``, ``make_frames``
(what ``pixels``, the agent's view, draws; with ``paint`` and ``decorate`` where it
changes) and ``drag_action``;
and ``per_world``, the names of its attributes with one row per world (what a saved
state must hold besides the worlds and the generators).

Frames during a shot are the caller's: ``shoot(worlds, actions, on_frame=f, every=n)``
calls ``f()`` every ``n`` physics steps while the shot runs (the Gymnasium envs' frames,
the play command's window); the game keeps no callback of its own.

``save_state`` and ``restore_state`` are the cheap save and restore planners need (tens
of microseconds for a table, against milliseconds for a ``deepcopy``): the worlds'
snapshot, each world's generator state and the per-world rows; restored into all worlds
or chosen ones, the game then plays bitwise as it did from the saved position.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import impulse2d as p2
from impulse2d import _checks
from impulse2d.pixels import Frames
from impulse2d.render import Renderer

Info = dict[str, np.ndarray]


@dataclass(frozen=True)
class GameState:
    """A saved ``ShotGame``: its worlds' snapshot, each world's random generator state and
    the game's per-world rows (``ShotGame.per_world``), all copies."""

    world: p2.Snapshot
    rngs: tuple[dict[str, Any], ...]
    rows: dict[str, np.ndarray]


# The largest batch a game takes: a world of either game holds about 12 kB of engine
# state, so a million hold some 12 GB; more is a mistake (a count in the wrong place),
# refused before anything is built.
MAX_ENVS = 1_000_000
# The longest shot, in simulated seconds: far longer than any shot takes to come to rest
# (seconds), and its step count (432,000 at 1/120 s) stays a small integer.
MAX_SHOT_SECONDS = 3600.0


def check_num_envs(num_envs: Any) -> int:
    """The number of worlds of a game: an int in [1, ``MAX_ENVS``], named ``num_envs`` (the
    Gymnasium keyword that sets it)."""
    return _checks.int_in("num_envs", num_envs, 1, MAX_ENVS)


def shot_steps(max_shot_seconds: Any, dt: float) -> int:
    """The physics steps of ``max_shot_seconds`` (in (0, ``MAX_SHOT_SECONDS``] s) at ``dt``,
    at least one: the step cap of a shot."""
    seconds = _checks.number_in(
        "max_shot_seconds", max_shot_seconds, 0.0, MAX_SHOT_SECONDS, " s", low_open=True
    )
    return max(1, round(seconds / dt))


class ShotGame:
    """``batch_size`` games, one per world of one batched engine (see the module docstring).

    A subclass builds its worlds and passes them, keyword by keyword, to this constructor:
    ``world`` (the batch; its ``batch_size`` is the game's), ``template`` (the same scene
    in one world), ``dt`` (physics step, s), ``max_shot_steps`` (int >= 1) and
    ``observation_low`` / ``observation_high`` (the bounds of one observation, float32
    vectors of one length). Nothing is set on a game from outside afterwards.
    """

    action_size = 2
    per_world: tuple[str, ...] = ()  # attributes with a leading world axis (saved states)

    def __init__(
        self,
        *,
        world: p2.World,
        template: p2.World,
        dt: float,
        max_shot_steps: int,
        observation_low: np.ndarray,
        observation_high: np.ndarray,
    ) -> None:
        if not isinstance(world, p2.World) or not isinstance(template, p2.World):
            raise ValueError(f"world and template must be Worlds, got {world!r}, {template!r}")
        if template.batch_size != 1:
            raise ValueError(f"template must be one world, got {template.batch_size}")
        low = np.asarray(observation_low)
        high = np.asarray(observation_high)
        if low.dtype != np.float32 or high.dtype != np.float32 or low.shape != high.shape:
            raise ValueError(
                "observation_low and observation_high must be float32 vectors of one shape, "
                f"got {low.dtype}{low.shape} and {high.dtype}{high.shape}"
            )
        self.world: p2.World = world
        self.template: p2.World = template
        self.batch_size = world.batch_size
        self.dt = _checks.positive("dt", dt)
        self.max_shot_steps = _checks.positive_int("max_shot_steps", max_shot_steps)
        self.observation_low, self.observation_high = low, high
        self.rngs: list[np.random.Generator] = [
            np.random.default_rng() for _ in range(self.batch_size)
        ]
        self._frames: dict[int, Frames] = {}  # pixels(): the frames of each size asked for

    # -- for subclasses -----------------------------------------------------------------------
    def _new_episode(self, world: int, rng: np.random.Generator) -> None:
        """Set up a new episode in world ``world`` (draw from ``rng`` only)."""
        raise NotImplementedError

    def _launch(self, worlds: np.ndarray, actions: np.ndarray) -> None:
        """Apply one action per world (rows of ``actions``, already checked and clipped)."""
        raise NotImplementedError

    def _score(self, worlds: np.ndarray, steps: np.ndarray) -> tuple[np.ndarray, np.ndarray, Info]:
        """Rewards (float64), terminated flags and info arrays of the worlds after a shot."""
        raise NotImplementedError

    def observe(self) -> np.ndarray:
        """Observations of every world, shape ``(batch_size, observation_size)`` float32."""
        raise NotImplementedError

    def make_renderer(self, width: int, height: int) -> Renderer:
        """A renderer set up to draw this game (camera, colours, decorations)."""
        raise NotImplementedError

    def make_frames(self, size: int) -> Frames:
        """The agent's view of every world, ``size`` x ``size`` pixels: the game's camera,
        what never moves drawn into the background, the bodies' colours."""
        raise NotImplementedError

    def paint(self, frames: Frames) -> None:
        """Colours that change during a game (a block losing health), set before each
        drawing; none by default."""

    def decorate(self, images: np.ndarray, size: int) -> None:
        """What a frame shows besides the bodies (a count of birds left), drawn into the
        drawn ``images`` (batch_size, size, size, 3); nothing by default."""

    def pixels(self, size: int) -> np.ndarray:
        """Every world as an agent sees it: ``(batch_size, size, size, 3)`` uint8."""
        frames = self._frames.get(size)
        if frames is None:
            frames = self._frames[size] = self.make_frames(size)
        self.paint(frames)
        images = frames()
        self.decorate(images, size)
        return images

    def drag_action(self, world: int, start: Any, end: Any) -> np.ndarray:
        """The action a person means by dragging the mouse from ``start`` to ``end`` (world
        coordinates, m) in world ``world``: how ``python -m impulse2d.apps.play`` turns a drag
        into a move. Returns a float64 action in [-1, 1]."""
        raise NotImplementedError

    # -- saved states ---------------------------------------------------------------------------
    def save_state(self) -> GameState:
        """Everything a shot reads and writes, copied (see the module docstring)."""
        return GameState(
            self.world.snapshot(),
            tuple(copy.deepcopy(rng.bit_generator.state) for rng in self.rngs),
            {name: np.array(getattr(self, name), copy=True) for name in self.per_world},
        )

    def restore_state(self, state: GameState, worlds: Any = None) -> np.ndarray:
        """Put a saved state back into every world, or only into ``worlds`` (indices);
        returns the worlds restored. The state must come from this game (or one built
        with the same arguments and number of worlds)."""
        if not isinstance(state, GameState):
            raise ValueError(f"state must be a saved state, got {type(state).__name__}")
        if len(state.rngs) != self.batch_size or state.rows.keys() != set(self.per_world):
            raise ValueError(
                f"state is of a game with {len(state.rngs)} worlds, not this one's "
                f"{self.batch_size}"
            )
        picked = np.arange(self.batch_size) if worlds is None else np.asarray(worlds)
        self.world.restore(state.world, worlds=picked)  # checks the indices and the scene
        picked = picked.reshape(-1).astype(np.int64)
        for w in picked:
            self.rngs[w].bit_generator.state = copy.deepcopy(state.rngs[w])
        for name, rows in state.rows.items():
            getattr(self, name)[picked] = rows[picked]
        return picked

    # -- the game loop --------------------------------------------------------------------------
    @property
    def observation_size(self) -> int:
        return int(self.observation_low.size)

    def seed(self, worlds: Any, seeds: list[int | None]) -> None:
        """New random generators for some worlds (None: fresh entropy)."""
        for w, s in zip(np.asarray(worlds).reshape(-1), seeds, strict=True):
            self.rngs[int(w)] = np.random.default_rng(s)

    def reset(self, worlds: Any) -> None:
        """Start new episodes in the given worlds, each from its own generator."""
        for w in np.asarray(worlds).reshape(-1):
            self._new_episode(int(w), self.rngs[int(w)])

    def _install(self, world: int) -> None:
        """Copy the template (set up for a new episode) into world ``world``."""
        self.world.restore(self.template.snapshot(), worlds=[world])

    def shoot(
        self,
        worlds: Any,
        actions: Any,
        on_frame: Callable[[], None] | None = None,
        every: int = 0,
    ) -> tuple[np.ndarray, np.ndarray, Info]:
        """Play one shot in each of ``worlds`` (``actions``: one checked row per world) and
        run the physics until they are all at rest. Returns rewards, terminated flags and
        info arrays for those worlds, in the order given. Other worlds do not move.

        ``on_frame``: called with no arguments every ``every`` physics steps while the shot
        runs (frames of the shot; ``every=0`` or no callback: none)."""
        worlds = np.asarray(worlds, dtype=np.int64).reshape(-1)
        self._launch(worlds, np.asarray(actions, dtype=np.float64).reshape(worlds.size, -1))
        steps = self._run(worlds, on_frame if every else None, every)
        return self._score(worlds, steps)

    def _run(
        self, worlds: np.ndarray, on_frame: Callable[[], None] | None = None, every: int = 0
    ) -> np.ndarray:
        """Run the physics until the given worlds are at rest (or the cap); returns each
        one's physics steps. ``on_frame()`` every ``every`` steps, if given."""
        world = self.world
        callback = None if on_frame is None else (lambda _steps: on_frame())
        steps = world.run_until_rest(
            self.dt, self.max_shot_steps, worlds, every=every or None, callback=callback
        )
        capped = worlds[steps >= self.max_shot_steps]
        if capped.size:  # the cap: end the shot where it stands
            still = ~np.atleast_1d(world.at_rest())[capped]
            world.stop(capped[still])
        return steps


def check_action(action: Any, shape: tuple[int, ...]) -> np.ndarray:
    """An action as float64, clipped to [-1, 1] (the action space, as SB3 clips a policy's
    Gaussian sample); NaN, infinity, complex numbers, bools, strings and a wrong shape
    raise ValueError naming ``action``."""
    return np.clip(_checks.real_array("action", action, shape), -1.0, 1.0)


def action_to_range(action: Any, span: tuple[float, float]) -> Any:
    """An action in [-1, 1] mapped linearly onto ``span = (lo, hi)``: -1 -> lo, +1 -> hi.
    The one affine map every action of the games uses (angles, speeds); arrays or floats."""
    lo, hi = span
    return lo + 0.5 * (action + 1.0) * (hi - lo)


def range_to_action(value: Any, span: tuple[float, float]) -> Any:
    """The inverse of ``action_to_range``: ``value`` on ``span`` as an action (not clipped)."""
    lo, hi = span
    return 2.0 * (value - lo) / (hi - lo) - 1.0
