"""Slingshot2D-v0: Angry-Birds-style destruction, side view, one launch per step."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import impulse2d as p2
from impulse2d import _checks
from impulse2d import _raster as raster
from impulse2d.pixels import Frames
from impulse2d.render import Camera, Renderer, Style

from . import _levels, _templates
from ._core import (
    Info,
    ShotGame,
    action_to_range,
    check_num_envs,
    range_to_action,
    shot_steps,
)
from ._gym import ShotEnv, ShotVectorEnv
from ._levels import MATERIALS, PIG_HEALTH, PIG_MASS, PIG_RADIUS

SLING = (0.0, 1.2)  # where a bird leaves the sling (m)
BIRD_RADIUS = 0.2  # m
BIRD_MASS = 4.0  # kg
ANGLE_RANGE = (0.0, math.pi / 2)  # launch angle (rad) at action[0] = -1 and +1
SPEED_RANGE = (6.0, 20.0)  # launch speed (m/s) at action[1] = -1 and +1
FULL_PULL = 3.0  # m: a drag this long (or longer) in the play command is full speed
IMPACT_SPEED = 0.5  # m/s: contacts closing slower than this do no damage (resting stacks)
ARENA_X = (-3.0, 19.0)  # a body whose centre leaves this span is gone (off the screen)
VIEW = (-1.5, -0.5, 17.0, 9.9)  # what the renderer shows (m), 16:9
# Round bodies would roll on for ever on flat ground. A spin drag d (1/s) makes a rolling
# disc (I = m r^2 / 2) lose speed as exp(-d t / 3): with the friction that keeps it
# rolling, m dv/dt = -F and I dw/dt = F r - d I w with v = w r give dv/dt = -(d / 3) v.
# So d = 6 stops a bird rolling at 5 m/s within about 2.5 s.
ROLL_DRAG = 6.0
MAX_PIGS = 4
MAX_BLOCKS = 20
PIG_REWARD, BLOCK_REWARD, BIRD_BONUS = 1.0, 0.1, 0.5
DT = 1.0 / 60.0
FEATURES = 9  # numbers per pig or block slot in the observation
# Built levels kept for reuse (hand-made ones, and generated ones from a fixed set of
# num_levels seeds): building one takes ~7 ms in Python, more than stepping it; each
# kept level is a ~14 kB snapshot. The oldest goes first beyond this many.
LEVEL_CACHE = 4096
LEVELS = ("random", "handmade", "templates", *_levels.HANDMADE)
_MATERIAL_COLOURS = np.array([(170, 220, 245), (196, 140, 80), (140, 140, 150)], np.float32)


def slot_positions(slots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The centres ``x, y`` (m) of observation slots ``(..., FEATURES)``: the inverse of
    the observation's scaling (``y`` is clipped at 10 m there)."""
    middle, half = (ARENA_X[0] + ARENA_X[1]) / 2, (ARENA_X[1] - ARENA_X[0]) / 2
    return slots[..., 3] * half + middle, slots[..., 4] * 10.0


class SlingshotGame(ShotGame):
    """Slingshot on ``batch_size`` worlds at once (see ``Slingshot2DEnv`` for the rules).

    Slots: 0 is the bird, 1..MAX_PIGS the pigs, then MAX_BLOCKS blocks; a level uses the
    first ones and leaves the rest disabled, so every world has the same slots whatever
    its level (the batched engine needs that) and the observation has a fixed size.
    A subclass with other blocks (``slingshot_blocks``) changes ``_add_blocks``,
    ``_place_blocks``, ``_random_level`` and the level names.
    """

    level_names = LEVELS
    handmade = _levels.HANDMADE
    template_library, template_splits = _templates.TEMPLATES, _templates.SPLITS
    per_world = ("max_health", "_in_level", "material", "birds_left", "_alive_before")

    def __init__(
        self,
        batch_size: int = 1,
        level: str = "random",
        num_birds: int = 3,
        max_shot_seconds: float = 10.0,
        num_levels: int = 0,
        start_level: int = 0,
        device: str = "cpu",
        templates: Any = None,
    ) -> None:
        batch_size = check_num_envs(batch_size)
        self.level = _checks.word("level", level, self.level_names)
        self.num_levels, self.start_level = _level_seeds(self.level, num_levels, start_level)
        self.templates = _template_choice(self.level, templates, self.template_library,
                                          self.template_splits)  # fmt: skip
        self.num_birds = _checks.int_in("num_birds", num_birds, 1, 10)
        max_shot_steps = shot_steps(max_shot_seconds, DT)
        world, self.bird, self.pigs, self.blocks = self._build(batch_size, device)
        template, *self._template_bodies = self._build(
            1, "cpu"
        )  # resets copy its state from the host
        self._parked = template.snapshot()  # every slot parked: where each build starts
        slots = MAX_PIGS + len(self.blocks)
        low = np.array([0, 0, 0, -1, 0, -1, 0, 0, 0], np.float32)
        super().__init__(
            world=world,
            template=template,
            dt=DT,
            max_shot_steps=max_shot_steps,
            observation_low=np.append(np.tile(low, slots), np.float32(0.0)),
            observation_high=np.ones(slots * FEATURES + 1, np.float32),
        )
        self.max_health = np.ones((batch_size, slots))
        self._in_level = np.zeros((batch_size, slots), dtype=bool)
        self._built: dict[tuple, tuple] = {}  # levels built once (see LEVEL_CACHE)
        self.material = np.zeros((batch_size, slots), np.int64)  # blocks only
        self.birds_left = np.zeros(batch_size, np.int64)
        self._bird_patches: dict[int, list] = {}  # decorate(): by frame size
        self._targets = np.array([body.slot for body in (*self.pigs, *self.blocks)])
        self._alive_before = self.alive

    @property
    def alive(self) -> np.ndarray:
        """(B, slots) bool: which pigs and blocks are still there (not destroyed)."""
        return self.world.array("enabled")[:, self._targets].copy()

    @property
    def health(self) -> np.ndarray:
        """(B, slots): the health (N s) each pig and block of the level has left (below 0 for
        one that broke: the impact took more); 0 for slots the level does not use."""
        return np.where(self._in_level, self.world.array("health")[:, self._targets], 0.0)

    @classmethod
    def _build(cls, batch: int, device: str) -> tuple[p2.World, p2.Circle, list[p2.Circle], list]:
        # Impacts closing slower than IMPACT_SPEED do no damage (resting stacks); a body that
        # leaves the arena is gone: a sensor outside which bodies are switched off.
        world = p2.World(
            gravity=(0.0, -9.81),
            batch_size=batch,
            substeps=4,
            damage_speed=IMPACT_SPEED,
            device=device,
        )
        bird = world.add(
            p2.Circle(
                radius=BIRD_RADIUS,
                mass=BIRD_MASS,
                restitution=0.3,
                friction=0.6,
                angular_drag=ROLL_DRAG,
            )
        )
        pigs = [
            world.add(
                p2.Circle(
                    radius=PIG_RADIUS,
                    mass=PIG_MASS,
                    restitution=0.2,
                    friction=0.6,
                    angular_drag=ROLL_DRAG,
                )
            )
            for _ in range(MAX_PIGS)
        ]
        blocks = cls._add_blocks(world)
        world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0), friction=0.8, restitution=0.1))
        middle, width = (ARENA_X[0] + ARENA_X[1]) / 2, ARENA_X[1] - ARENA_X[0]
        world.add(
            p2.Sensor(position=(middle, 0.0), width=width, height=1e4, outside=True, disables=True)
        )
        for body in (bird, *pigs, *blocks):
            _park(body)
        world.stop()
        return world, bird, pigs, blocks

    @staticmethod
    def _add_blocks(world: p2.World) -> list:
        """The block slots, after the pigs' (v0: ``MAX_BLOCKS`` boxes)."""
        return [world.add(p2.Box()) for _ in range(MAX_BLOCKS)]

    # -- episodes ----------------------------------------------------------------------------------
    @staticmethod
    def _random_level(rng: np.random.Generator) -> _levels.Level:
        return _levels.random_level(rng, MAX_BLOCKS, MAX_PIGS)

    def _pick_level(self, rng: np.random.Generator) -> _levels.Level:
        if self.level == "templates":
            seed = self.start_level + int(rng.integers(self.num_levels or 2**62))
            return _templates.template_level(self.templates, seed, self.template_library)
        if self.level == "random" and self.num_levels:
            seed = self.start_level + int(rng.integers(self.num_levels))
            return self._random_level(np.random.default_rng(seed))
        if self.level == "random":
            return self._random_level(rng)
        if self.level == "handmade":
            names = list(self.handmade)
            return self.handmade[names[int(rng.integers(len(names)))]]()
        return self.handmade[self.level]()

    def _new_episode(self, world: int, rng: np.random.Generator) -> None:
        level = self._pick_level(rng)
        key = (level.name, *map(tuple, (level.blocks, level.pigs, level.triangles, level.stones)))
        built = self._built.get(key)
        if built is None:
            built = self._build_level(level)
            # A level's build is a function of the level alone, so keeping it changes no
            # result; only levels that come back are kept (hand-made, or a fixed set).
            if self.num_levels or self.level not in ("random", "templates"):
                if len(self._built) >= LEVEL_CACHE:
                    del self._built[next(iter(self._built))]
                self._built[key] = built
        snapshot, max_health, in_level, material = built
        self.world.restore(snapshot, worlds=[world])
        self.max_health[world], self._in_level[world] = max_health, in_level
        self.material[world] = material
        self.birds_left[world] = self.num_birds

    def _build_level(self, level: _levels.Level) -> tuple:
        """The template set up for ``level``: its snapshot, and the per-slot max health,
        in-level flags and materials. A function of the level alone."""
        _, pigs, _ = self._template_bodies
        slots = MAX_PIGS + len(self.blocks)
        max_health, in_level = np.ones(slots), np.zeros(slots, dtype=bool)
        material = np.zeros(slots, np.int64)
        # Every build starts from every slot parked as _build left them, so a build is a
        # function of the level alone, down to the sizes and masses an unused slot holds;
        # and only the level's own bodies are written (each write costs microseconds).
        self.template.restore(self._parked)
        for i, pig in enumerate(pigs[: len(level.pigs)]):
            pig.position = level.pigs[i]
            pig.enabled = True
            pig.health = max_health[i] = PIG_HEALTH
            in_level[i] = True
        self._place_blocks(level, max_health, in_level, material)
        self.template.stop()  # everything asleep: the level stands as built until hit
        return self.template.snapshot(), max_health, in_level, material

    def _place_blocks(self, level: _levels.Level, max_health, in_level, material) -> None:
        """Put ``level``'s blocks into the template's block slots, each with its
        material's mass, friction, bounce and health (into the per-slot arrays)."""
        if level.triangles or level.stones:
            raise ValueError(
                f"level {level.name!r} has triangles or stones: they need Slingshot2DBlocks"
            )
        self._place_boxes(level, max_health, in_level, material)

    def _place_boxes(self, level: _levels.Level, max_health, in_level, material) -> None:
        """``level``'s boxes into the first box slots (``_place_blocks``)."""
        boxes = self._template_bodies[2]
        for i, (x, y, width, height, kind_index) in enumerate(level.blocks):
            block, kind = boxes[i], MATERIALS[kind_index]
            block.width, block.height = width, height
            block.mass = kind.density * width * height
            self._set_block(block, MAX_PIGS + i, kind_index, (x, y), max_health, in_level, material)

    @staticmethod
    def _set_block(block, k, kind_index, position, max_health, in_level, material) -> None:
        """What every block slot ``k`` takes from its material once its size is set."""
        kind = MATERIALS[kind_index]
        block.friction, block.restitution = kind.friction, kind.restitution
        block.position = position
        block.enabled = True
        block.health = max_health[k] = kind.health
        in_level[k], material[k] = True, kind_index

    # -- a shot ------------------------------------------------------------------------------------
    def _launch(self, worlds: np.ndarray, actions: np.ndarray) -> None:
        """``actions[:, 0]``: the launch angle, linear on ``ANGLE_RANGE`` (0 to 90 degrees
        above the horizontal); ``actions[:, 1]``: the speed, linear on ``SPEED_RANGE``. The
        bird leaves the sling at ``SLING``. A world with no bird left does nothing."""
        ready = self.birds_left[worlds] > 0
        launch, actions = worlds[ready], actions[ready]
        self._alive_before = self.alive
        if launch.size == 0:
            return
        angle = action_to_range(actions[:, 0], ANGLE_RANGE)
        speed = action_to_range(actions[:, 1], SPEED_RANGE)
        bird = self.bird
        enabled = np.atleast_1d(bird.enabled).copy()
        position = np.atleast_2d(bird.position).copy()
        velocity = np.atleast_2d(bird.velocity).copy()
        enabled[launch] = True
        position[launch] = SLING
        velocity[launch, 0] = speed * np.cos(angle)
        velocity[launch, 1] = speed * np.sin(angle)
        bird.enabled, bird.position, bird.velocity = enabled, position, velocity
        self.birds_left[launch] -= 1

    def _score(self, worlds: np.ndarray, steps: np.ndarray) -> tuple[np.ndarray, np.ndarray, Info]:
        # The bird leaves the level once its shot is over.
        enabled = np.atleast_1d(self.bird.enabled).copy()
        if enabled[worlds].any():
            enabled[worlds] = False
            self.bird.enabled = enabled
        alive = self.alive
        destroyed = self._alive_before[worlds] & ~alive[worlds]
        pigs = destroyed[:, :MAX_PIGS].sum(axis=1)
        blocks = destroyed[:, MAX_PIGS:].sum(axis=1)
        pigs_left = alive[worlds, :MAX_PIGS].sum(axis=1)
        birds_left = self.birds_left[worlds]
        cleared = pigs_left == 0
        reward = PIG_REWARD * pigs + BLOCK_REWARD * blocks + BIRD_BONUS * birds_left * cleared
        info = {
            "pigs_destroyed": pigs.astype(np.int64),
            "blocks_destroyed": blocks.astype(np.int64),
            "pigs_left": pigs_left.astype(np.int64),
            "birds_left": birds_left.copy(),
            "cleared": cleared,
            "physics_steps": steps,
        }
        return reward.astype(np.float64), cleared | (birds_left == 0), info

    def drag_action(self, world: int, start: Any, end: Any) -> np.ndarray:
        """A sling: pull back from where you press and let go. The bird flies opposite to
        the pull, at full speed for a pull of ``FULL_PULL`` metres; the angle is kept in
        ``ANGLE_RANGE``."""
        pull = np.asarray(start, np.float64) - np.asarray(end, np.float64)
        length = float(np.hypot(*pull))
        angle = math.atan2(pull[1], pull[0]) if length > 1e-3 else 0.0
        lo, hi = ANGLE_RANGE
        angle = min(max(angle, lo), hi)
        power = min(length / FULL_PULL, 1.0)
        return np.array([range_to_action(angle, ANGLE_RANGE), 2.0 * power - 1.0])

    # -- observation and pictures ------------------------------------------------------------------
    def observe(self) -> np.ndarray:
        world = self.world
        pose = world.array("pose")[:, :, self._targets]
        half_w = world.array("half_width")[:, self._targets]
        half_h = world.array("half_height")[:, self._targets]
        obs = np.zeros((self.batch_size, len(self._targets), FEATURES), np.float32)
        alive = self.alive
        obs[:, :, 0] = alive
        obs[:, MAX_PIGS:, 1] = 1.0
        obs[:, :, 2] = self.material / 2.0
        middle, half = (ARENA_X[0] + ARENA_X[1]) / 2, (ARENA_X[1] - ARENA_X[0]) / 2
        obs[:, :, 3] = np.clip((pose[0] - middle) / half, -1.0, 1.0)
        obs[:, :, 4] = np.clip(pose[1] / 10.0, 0.0, 1.0)
        obs[:, :, 5] = np.remainder(pose[2] + math.pi, 2 * math.pi) / math.pi - 1.0
        obs[:, :, 6] = np.minimum(half_w, 1.0)  # widths (m) / 2 m: blocks are under 2 m
        obs[:, :, 7] = np.minimum(half_h, 1.0)
        obs[:, :, 8] = np.clip(self.health / self.max_health, 0.0, 1.0)
        obs[~alive] = 0.0
        birds = (self.birds_left / self.num_birds).astype(np.float32)[:, None]
        return np.concatenate([obs.reshape(self.batch_size, -1), birds], axis=1)

    def make_renderer(self, width: int, height: int) -> Renderer:
        style = Style(
            background=(150, 205, 235),
            plane_fill=(90, 150, 70),
            plane_line=(60, 110, 50),
            body_colours={
                self.bird.slot: (210, 40, 40),
                **{pig.slot: (110, 200, 60) for pig in self.pigs},
            },
        )
        return Renderer(
            width,
            height,
            Camera.fit_view(VIEW, width, height),
            style,
            underlay=_draw_sling,
            overlay=self._draw_materials,
        )

    def make_frames(self, size: int) -> Frames:
        """From the side, the renderer's view: sky, ground and sling in the background,
        the bird red, pigs green, blocks in their material's colour (``paint``), the
        birds left as red dots at the top left (``decorate``)."""
        (x0, y0, x1, y1), ground = VIEW, np.array((90, 150, 70), np.float32)
        frames = Frames(self.world, size, size, view=((x0, y0), (x1, y1)))
        canvas = np.empty((size, size, 3), np.float32)
        canvas[:] = (150, 205, 235)
        top = frames.to_pixels(0.0, 0.0)[1]  # the ground's surface; below it, all ground
        raster.box(canvas, size / 2, (top + size + 2) / 2, 0.0, size / 2 + 2,
                   (size + 2 - top) / 2, ground)  # fmt: skip
        _sling(canvas, frames.to_pixels, frames.scale)
        frames.background = np.clip(np.rint(canvas), 0, 255).astype(np.uint8)
        frames.colour(self.bird, (210, 40, 40))
        for pig in self.pigs:
            frames.colour(pig, (110, 200, 60))
        return frames

    def paint(self, frames: Frames) -> None:
        """Each block in its material's colour, darker as it loses health (per world)."""
        health, most = self.health, self.max_health
        for k, block in enumerate(self.blocks, start=MAX_PIGS):
            left = np.divide(health[:, k], most[:, k], out=np.zeros(self.batch_size),
                             where=most[:, k] > 0)  # fmt: skip
            shade = 0.55 + 0.45 * np.maximum(left, 0.0)
            frames.colour(block, _MATERIAL_COLOURS[self.material[:, k]] * shade[:, None])

    def decorate(self, images: np.ndarray, size: int) -> None:
        """A red dot for each bird left, in a row at the top left of the sky (beside the
        sling, as the renderer puts them, the third would be out of the frame): one
        patch of the background per count, pasted (no body flies that high there)."""
        patches = self._bird_patches.get(size)
        if patches is None:
            patches = self._bird_patches[size] = self._make_bird_patches(size)
        rows, cols, by_count = patches
        for count, patch in enumerate(by_count):
            images[self.birds_left == count, rows, cols] = patch

    def _make_bird_patches(self, size: int) -> tuple[slice, slice, list[np.ndarray]]:
        frames = self._frames[size]
        radius = max(BIRD_RADIUS * frames.scale, 1.5)  # pixels: a dot, however small
        step = 2.0 * radius + 1.0
        centres = [(2.0 + radius + i * step, 2.0 + radius) for i in range(self.num_birds)]
        xs, ys = [x for x, _ in centres], [y for _, y in centres]
        rows = slice(max(int(min(ys) - radius) - 2, 0), min(int(max(ys) + radius) + 3, size))
        cols = slice(max(int(min(xs) - radius) - 2, 0), min(int(max(xs) + radius) + 3, size))
        canvas = frames.background.astype(np.float32)
        by_count = [frames.background[rows, cols].copy()]
        for x, y in centres:
            raster.disc(canvas, x, y, radius, np.array((210, 40, 40), np.float32))
            by_count.append(np.clip(np.rint(canvas[rows, cols]), 0, 255).astype(np.uint8))
        return rows, cols, by_count

    def _draw_materials(self, canvas: np.ndarray, renderer: Renderer, world: int) -> None:
        """Blocks in their material's colour, darker as they lose health; birds left."""
        pose = self.world.array("pose")[:, world]
        half_w = self.world.array("half_width")[world]
        half_h = self.world.array("half_height")[world]
        scale = renderer.camera.pixels_per_metre
        alive, health = self.alive[world], self.health[world]
        for k, block in enumerate(self.blocks, start=MAX_PIGS):
            if not alive[k]:
                continue
            slot = block.slot
            shade = 0.55 + 0.45 * max(health[k] / self.max_health[world, k], 0.0)
            colour = _MATERIAL_COLOURS[self.material[world, k]] * shade
            x, y = renderer.to_pixels(pose[0, slot], pose[1, slot])
            if isinstance(block, p2.Box):
                hw, hh = half_w[slot] * scale, half_h[slot] * scale
                raster.box(canvas, x, y, float(pose[2, slot]), hw, hh, colour)
            elif isinstance(block, p2.Circle):
                raster.disc(canvas, x, y, half_w[slot] * scale, colour)
            else:  # an outline: its corners turned and placed, in pixels
                c, s = math.cos(pose[2, slot]), math.sin(pose[2, slot])
                corners = [renderer.to_pixels(pose[0, slot] + c * u - s * v,
                                              pose[1, slot] + s * u + c * v)
                           for u, v in block.vertices]  # fmt: skip
                raster.polygon(canvas, np.array(corners), block.radius * scale, colour)
        for i in range(self.birds_left[world]):
            x, y = renderer.to_pixels(SLING[0] - 0.6 - 0.5 * i, BIRD_RADIUS)
            raster.disc(canvas, x, y, BIRD_RADIUS * scale, np.array((210, 40, 40), np.float32))


def _park(body: p2.Circle | p2.Box) -> None:
    """Switch a slot off in a canonical state, so that a world's state depends only on
    its own episode (not on what an unused slot held before)."""
    body.enabled = False
    body.position = (0.0, -5.0)
    body.velocity = (0.0, 0.0)
    body.angle = 0.0
    body.angular_velocity = 0.0


def _draw_sling(canvas: np.ndarray, renderer: Renderer) -> None:
    """The sling, for the renderer."""
    _sling(canvas, renderer.to_pixels, renderer.camera.pixels_per_metre)


def _sling(canvas: np.ndarray, to_pixels: Any, scale: float) -> None:
    """The sling: a fork on a post, from the ground to the launch point."""
    wood = np.array((110, 70, 35), np.float32)
    width = 0.12 * scale
    x0, y0 = to_pixels(SLING[0], 0.0)
    x1, y1 = to_pixels(SLING[0], SLING[1] - 0.3)
    raster.segment(canvas, x0, y0, x1, y1, width, wood)
    for side in (-1.0, 1.0):
        x2, y2 = to_pixels(SLING[0] + side * 0.25, SLING[1] + 0.1)
        raster.segment(canvas, x1, y1, x2, y2, width, wood)


def _template_choice(level: str, templates: Any, library: dict, splits: dict) -> tuple[str, ...]:
    """The templates of ``level="templates"`` (``None``: the train split) from the game's
    ``library`` and ``splits``; none for the other levels, where naming templates is
    refused rather than ignored."""
    if level != "templates":
        if templates is not None:
            raise ValueError(f"templates needs level='templates', got level={level!r}")
        return ()
    return _templates.template_names("train" if templates is None else templates, library, splits)


def _level_seeds(level: str, num_levels: Any, start_level: Any) -> tuple[int, int]:
    """Checked ``(num_levels, start_level)``: Procgen's two numbers for the set of
    generated levels, ``start_level ... start_level + num_levels - 1`` (0 levels: no set,
    each level drawn from the episode's own generator)."""
    for name, value in (("num_levels", num_levels), ("start_level", start_level)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
            raise ValueError(f"{name} must be an int >= 0, got {value!r}")
    if (num_levels or start_level) and level not in ("random", "templates"):
        raise ValueError(
            f"num_levels and start_level need level='random' or 'templates', got level={level!r}"
        )
    if start_level and not num_levels:
        raise ValueError(f"start_level needs num_levels > 0, got start_level={start_level}")
    if num_levels >= 2**63:  # the draw is an int64
        raise ValueError(f"num_levels must be < 2**63, got {num_levels}")
    return int(num_levels), int(start_level)


class Slingshot2DEnv(ShotEnv):
    """Angry-Birds-style destruction seen from the side: one step is one bird, played until
    everything has settled.

    ## Description
    A sling at the left (the bird leaves it at x = 0, y = 1.2 m) and, 7-16 m to its right,
    structures of boxes in three materials with round "pigs" among them, on the ground,
    under gravity (9.81 m/s^2). The materials differ in density, friction and strength:

    | material | density (kg/m^2) | friction | health (N s) |
    |----------|------------------|----------|--------------|
    | ice      | 40               | 0.3      | 12           |
    | wood     | 60               | 0.6      | 30           |
    | stone    | 150              | 0.8      | 80           |

    Pigs: radius 0.25 m, 3 kg, health 12 N s. The bird: radius 0.2 m, 4 kg. A pig or block
    loses health equal to the contact impulse of every impact it takes (contacts closing
    faster than 0.5 m/s, so a resting stack does not wear itself out) and is destroyed
    at zero, or when it leaves the arena (x outside [-3, 19] m). A bird hitting a wooden
    post (0.2 x 1.0 m, 12 kg) head-on at 15 m/s delivers (1 + e) m M / (m + M) v = 58 N s;
    a pig falling 0.5 m onto the ground takes m v (1 + e) = 11.3 N s and just survives.

    ## Action Space
    `Box(-1, 1, (2,), float32)`: `action[0]` sets the launch angle, linear from 0 (at -1)
    to 90 degrees (at +1) above the horizontal; `action[1]` sets the launch speed, linear
    from 6 m/s (at -1) to 20 m/s (at +1). Values outside [-1, 1] are clipped; NaN or
    infinite values raise `ValueError`.

    ## Observation Space
    `Box(low, high, (9 * 24 + 1,), float32)`: nine numbers for each of 24 slots (4 pigs,
    then 20 blocks; a level uses the first ones, the others read as destroyed), then the
    birds left. A destroyed slot is all zeros.

    | index      | observation (slot k)                               | min | max |
    |------------|----------------------------------------------------|-----|-----|
    | 9 k        | 1 if it exists (not destroyed), else 0             | 0   | 1   |
    | 9 k + 1    | 0 for a pig, 1 for a block                         | 0   | 1   |
    | 9 k + 2    | material: 0 ice (and pigs), 0.5 wood, 1 stone      | 0   | 1   |
    | 9 k + 3    | (x - 8 m) / 11 m                                   | -1  | 1   |
    | 9 k + 4    | y / 10 m (clipped)                                 | 0   | 1   |
    | 9 k + 5    | angle / pi, in [-1, 1)                             | -1  | 1   |
    | 9 k + 6    | width / 2 m (a pig's diameter)                     | 0   | 1   |
    | 9 k + 7    | height / 2 m                                       | 0   | 1   |
    | 9 k + 8    | health left, as a fraction of the full health      | 0   | 1   |
    | 216        | birds left / `num_birds`                           | 0   | 1   |

    With `obs_type="pixels"`: `Box(0, 255, (pixel_size, pixel_size, 3), uint8)`, the
    level from the side (see Arguments).

    ## Rewards
    +1 per pig destroyed, +0.1 per block destroyed, and when the last pig goes, +0.5 per
    bird not used. The spent bird is removed when its launch has settled; anything left
    resting on it falls at the start of the next launch, and what that destroys counts
    for the next launch (as in the original game, where the bird vanishes too).

    ## Starting State
    `level="random"`: a procedural level from the episode's generator (one to three
    towers, pyramids or columns in random materials, one to four pigs on, in or behind
    them). `level="handmade"`: one of the hand-made levels at random; or a hand-made level
    by name: `"table"`, `"tower"`, `"fortress"`, `"wall"`, `"twin-towers"`.
    `level="templates"`: a level of one of the level templates `templates` (families of
    structure with their own generators, `impulse2d.envs._templates`: `"train"`, the
    seven an agent may train on, by default; `"held-out"`, the three kept from training;
    `"all"`; or template names); level seed `k` is template `k mod n` of them, its
    parameters drawn from a generator seeded `k`. Everything starts at rest.

    Generated levels as in Procgen: with `num_levels=n > 0`, each episode draws a level
    seed `k` from `start_level ... start_level + n - 1` and plays the level that a
    generator seeded `k` gives, so the set of levels is fixed and two disjoint ranges
    never share a level: train on `start_level=0, num_levels=10_000`, test on
    `start_level=1_000_000` to score levels never seen in training. `num_levels=0` (the
    default): no fixed set, the level comes from the episode's own generator.

    ## Episode End
    Terminated when every pig is destroyed or the birds run out. Truncated after 10
    steps (`max_episode_steps`; a launch itself is stopped after `max_shot_seconds` of
    simulated time).

    `info`: `pigs_destroyed`, `blocks_destroyed` (this step), `pigs_left`, `birds_left`,
    `cleared` (no pig left), `physics_steps` (engine steps of the launch at dt = 1/60 s).

    ## Arguments
    ```python
    gym.make("Slingshot2D-v0", level="random", num_birds=3, max_shot_seconds=10.0,
             num_levels=0, start_level=0, templates=None, render_mode=None)
    gym.make_vec("Slingshot2D-v0", num_envs=256, vectorization_mode="vector_entry_point",
                 threads=None, device="cpu", obs_type="state", pixel_size=84)
    ```
    * `level`: `"random"`, `"handmade"`, a hand-made level's name or `"templates"` (see
      Starting State).
    * `templates` (with `level="templates"`): a split, `"train"` (default), `"held-out"`
      or `"all"`, or a sequence of template names.
    * `num_birds` (1-10): birds per level.
    * `num_levels`, `start_level` (ints >= 0, with `level="random"` or `"templates"`): the
      generated levels to draw from, seeds `start_level` to `start_level + num_levels - 1`
      (see Starting State); 0 levels: any.
    * `max_shot_seconds` (in (0, 3600] s): simulated time after which a launch is
      stopped where it stands (at least one physics step).
    * `num_envs` (vector env, 1 to 1,000,000): worlds stepped together.
    * `max_episode_steps` (vector env, None or an int >= 1): launches before truncation.
    * `threads` (vector env): threads the batch is stepped on; default every core. The
      results do not depend on it.
    * `device`: `"cpu"`, or `"cuda"` to play every world's launch in one GPU launch (the
      `gpu` extra and an NVIDIA GPU; see the docs' "On a GPU", `docs/gpu.md`).
    * `obs_type`: `"state"` (the vector above) or `"pixels"`: the level seen from the
      side, `pixel_size` x `pixel_size` RGB uint8 (16 to 1024, default 84): sky, ground
      and sling, the bird red, pigs green, blocks in their material's colour (darker as
      they lose health), a red dot at the top left for each bird left.
    * `render_mode`: `"rgb_array"` (480x270 frame after the launch), `"rgb_array_list"`
      (frames at 30 per simulated second during the launches), `"human"` (pygame-ce
      window; without a display the env says so once, at the first frame, and plays on
      without one).

    A value outside its rule (a wrong type, NaN, infinity, a huge number) raises
    `ValueError` naming the argument and its rule when the env is made.

    ## Saving and restoring
    `env.unwrapped.save_state()` and `restore_state(state)` save and bring back a level's
    position, bitwise (see `ShotEnv`); the vector env restores chosen `worlds=[...]`.

    ## Version History
    * v0: first version (`num_levels` and `start_level` added later; their defaults play
      the levels v0 always played).
    """

    game_class = SlingshotGame


class Slingshot2DVectorEnv(ShotVectorEnv):
    """``num_envs`` Slingshot2D worlds stepped in one batched engine (see
    ``Slingshot2DEnv``)."""

    game_class = SlingshotGame
