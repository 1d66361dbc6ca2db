"""Pool2D-v0: top-down pool on a regulation 9-ft table, one cue stroke per step."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import impulse2d as p2
from impulse2d import _checks
from impulse2d import _raster as raster
from impulse2d.pixels import Frames
from impulse2d.render import Camera, Renderer, Style

from ._core import Info, ShotGame, action_to_range, check_num_envs, shot_steps
from ._gym import ShotEnv, ShotVectorEnv

# -- the table: published constants, SI units (pooltool's and the WPA's figures) --------------
TABLE_LENGTH = 2.54  # play area along x (m), centred on the origin
TABLE_WIDTH = 1.27  # along y (m)
BALL_RADIUS = 0.028575  # m (2.25 in)
BALL_MASS = 0.170  # kg
RESTITUTION_BALL = 0.95  # ball-ball
RESTITUTION_CUSHION = 0.75  # ball-cushion; the world mixes restitution by min
FRICTION_BALL = 0.06  # ball-ball (a little throw on cut shots)
FRICTION_CUSHION = 0.2  # mixed by sqrt: ball-cushion sqrt(0.06 * 0.2) = 0.11
ROLLING_RESISTANCE = 0.1  # m/s^2: rolling-resistance coefficient 0.01 times g
SPIN_DRAG = 3.0  # 1/s: decay of the sideways spin (about the vertical axis) on the cloth
CORNER_MOUTH = 0.118  # m, between the cushion noses, measured across the pocket
SIDE_MOUTH = 0.137  # m
CUSHION_THICKNESS = 0.05  # m (only its face matters)
HEAD_SPOT = (-TABLE_LENGTH / 4, 0.0)  # where a potted cue ball goes back
FOOT_SPOT = (TABLE_LENGTH / 4, 0.0)  # the rack's apex
SPEED_RANGE = (0.25, 6.0)  # cue-ball speed (m/s) at action[1] = -1 and +1
DT = 1.0 / 120.0  # physics step (s)
# The largest shaping weight (see Pool2DEnv, Rewards): the potential moves by at most ~8 a
# shot, so at 1000 the game's own +1 a ball is already lost in the shaping term.
MAX_SHAPING = 1000.0
# Colours: the cue ball, then object balls 1..15 (the stripes 9..15 drawn as their solids).
_SOLIDS = [
    (235, 200, 40),
    (40, 80, 200),
    (210, 40, 40),
    (110, 40, 150),
    (240, 120, 30),
    (30, 130, 70),
    (130, 30, 40),
]
BALL_COLOURS = [(240, 240, 232), *_SOLIDS, (20, 20, 20), *_SOLIDS]


def pockets() -> tuple[np.ndarray, np.ndarray]:
    """Centres (6, 2) and radii (6,) of the pocket circles: a ball is potted when its
    centre enters one. Each circle is as wide as its mouth and sits one ball radius
    beyond the mouth's midpoint, so a ball whose centre crosses the mouth line between
    the jaws drops in, and one that only grazes a jaw stays out."""
    half_l, half_w, r = TABLE_LENGTH / 2, TABLE_WIDTH / 2, BALL_RADIUS
    cut = CORNER_MOUTH / math.sqrt(2.0)  # each rail stops this far from the corner
    centres, radii = [], []
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            mid = np.array([sx * (half_l - cut / 2), sy * (half_w - cut / 2)])
            centres.append(mid + r * np.array([sx, sy]) / math.sqrt(2.0))
            radii.append(CORNER_MOUTH / 2)
    for sy in (-1.0, 1.0):
        centres.append(np.array([0.0, sy * (half_w + r)]))
        radii.append(SIDE_MOUTH / 2)
    return np.array(centres), np.array(radii)


def ball_positions(observation: Any) -> tuple[np.ndarray, np.ndarray]:
    """The inverse of the observation's scaling: ``(n, 3 (k + 1))`` observations (or one
    row) -> ball centres ``(n, k + 1, 2)`` in metres and on-table flags ``(n, k + 1)``;
    ball 0 is the cue ball. A potted ball's centre reads (0, 0)."""
    rows = np.asarray(observation, np.float64)
    rows = rows.reshape(-1, rows.shape[-1] // 3, 3) if rows.ndim else rows.reshape(-1, 1, 3)
    xy = rows[..., :2] * np.array([TABLE_LENGTH / 2, TABLE_WIDTH / 2])
    return xy, rows[..., 2] < 0.5


def cushions() -> list[tuple[float, float, float, float]]:
    """The six cushions as fixed boxes ``(x, y, width, height)``, each ending at its jaws."""
    half_l, half_w, t = TABLE_LENGTH / 2, TABLE_WIDTH / 2, CUSHION_THICKNESS
    cut = CORNER_MOUTH / math.sqrt(2.0)
    long = half_l - cut - SIDE_MOUTH / 2  # each long rail is split by its side pocket
    boxes = []
    for sy in (-1.0, 1.0):
        for sx in (-1.0, 1.0):
            boxes.append((sx * (SIDE_MOUTH / 2 + long / 2), sy * (half_w + t / 2), long, t))
    for sx in (-1.0, 1.0):
        boxes.append((sx * (half_l + t / 2), 0.0, t, 2 * (half_w - cut)))
    return boxes


def rack_positions() -> np.ndarray:
    """The 15-ball triangle (15, 2), apex on the foot spot, rows away from the cue ball.
    Balls sit 0.1 mm apart so the rack starts without overlaps."""
    spacing = 2 * BALL_RADIUS + 1e-4
    rows = [
        (FOOT_SPOT[0] + row * spacing * math.sqrt(3) / 2, (k - row / 2) * spacing)
        for row in range(5)
        for k in range(row + 1)
    ]
    return np.array(rows)


class PoolGame(ShotGame):
    """Pool on ``batch_size`` tables at once (see ``Pool2DEnv`` for the rules)."""

    per_world = ("potted", "_potted_before", "_potential_before")

    def __init__(
        self,
        batch_size: int = 1,
        num_balls: int = 15,
        layout: str | None = None,
        max_shot_seconds: float = 20.0,
        shaping: float = 0.0,
        device: str = "cpu",
    ) -> None:
        batch_size = check_num_envs(batch_size)
        self.shaping = _checks.number_in("shaping", shaping, 0.0, MAX_SHAPING)
        self.num_balls = _checks.int_in("num_balls", num_balls, 1, 15)
        if layout is None:
            layout = "rack" if self.num_balls == 15 else "random"
        self.layout = _checks.word("layout", layout, ("rack", "random"))
        max_shot_steps = shot_steps(max_shot_seconds, DT)
        world, self.balls = self._build(batch_size, device)
        template, self._template_balls = self._build(
            1, "cpu"
        )  # resets copy its state from the host
        count = self.num_balls + 1
        super().__init__(
            world=world,
            template=template,
            dt=DT,
            max_shot_steps=max_shot_steps,
            observation_low=np.tile(np.array([-1.0, -1.0, 0.0], np.float32), count),
            observation_high=np.ones(3 * count, np.float32),
        )
        self.pocket_centres, self.pocket_radii = pockets()
        self.potted = np.zeros((batch_size, count), dtype=bool)
        self._potted_before = self.potted.copy()
        self._potential_before = np.zeros(batch_size)

    def _build(self, batch: int, device: str) -> tuple[p2.World, list[p2.Circle]]:
        world = p2.World(
            gravity=(0.0, 0.0),
            batch_size=batch,
            device=device,
            substeps=2,
            restitution_mixing="min",
            restitution_threshold=0.02,  # m/s: gentle kisses still bounce
            sleep_speed=0.01,
            time_to_sleep=0.1,
        )
        balls = [
            world.add(
                p2.Circle(
                    position=(0.0, 0.0),
                    radius=BALL_RADIUS,
                    mass=BALL_MASS,
                    restitution=RESTITUTION_BALL,
                    friction=FRICTION_BALL,
                    angular_drag=SPIN_DRAG,
                    rolling_resistance=ROLLING_RESISTANCE,
                )
            )
            for _ in range(self.num_balls + 1)
        ]
        for x, y, w, h in cushions():
            world.add(
                p2.Box(
                    position=(x, y),
                    width=w,
                    height=h,
                    fixed=True,
                    restitution=RESTITUTION_CUSHION,
                    friction=FRICTION_CUSHION,
                )
            )
        # A ball is potted when its centre enters a pocket circle, or, as a safeguard,
        # leaves the table past a cushion line: sensors that switch it off.
        centres, radii = pockets()
        for centre, radius in zip(centres, radii, strict=True):
            world.add(p2.Sensor(position=centre, radius=radius, disables=True))
        reach = 2 * BALL_RADIUS
        world.add(
            p2.Sensor(
                width=TABLE_LENGTH + reach, height=TABLE_WIDTH + reach, outside=True, disables=True
            )
        )
        return world, balls

    # -- episodes ----------------------------------------------------------------------------------
    def _new_episode(self, world: int, rng: np.random.Generator) -> None:
        positions = self._layout(rng)
        for ball, position in zip(self._template_balls, positions, strict=True):
            ball.position = position
            ball.velocity = (0.0, 0.0)
            ball.angular_velocity = 0.0
            ball.angle = 0.0
            ball.enabled = True
        self.template.stop()  # every ball asleep: the first stroke wakes what it touches
        self._install(world)
        self.potted[world] = False

    def _layout(self, rng: np.random.Generator) -> np.ndarray:
        """Start positions (cue ball first): the rack (its first ``num_balls`` balls) with
        the cue ball anywhere behind the head string, or every ball at random."""
        r = BALL_RADIUS
        half_l, half_w = TABLE_LENGTH / 2 - 2 * r, TABLE_WIDTH / 2 - 2 * r
        placed: list[np.ndarray] = []
        if self.layout == "rack":
            placed = list(rack_positions()[: self.num_balls])
            cue = self._free_spot(rng, placed, (-half_l, HEAD_SPOT[0]), (-half_w, half_w))
            return np.array([cue, *placed])
        for _ in range(self.num_balls + 1):
            placed.append(self._free_spot(rng, placed, (-half_l, half_l), (-half_w, half_w)))
        return np.array(placed)

    def _free_spot(
        self, rng: np.random.Generator, placed: list, xs: tuple, ys: tuple
    ) -> np.ndarray:
        """A uniform random point in the box ``xs x ys`` clear of the balls in ``placed``
        (1 mm gap) and of the pockets."""
        centres, radii = self.pocket_centres, self.pocket_radii
        others = np.array(placed).reshape(-1, 2)
        while True:
            point = np.array([rng.uniform(*xs), rng.uniform(*ys)])
            clear = np.all(np.hypot(*(others - point).T) > 2 * BALL_RADIUS + 1e-3)
            if clear and np.all(np.hypot(*(centres - point).T) > radii + 2 * BALL_RADIUS):
                return point

    # -- a shot ------------------------------------------------------------------------------------
    def _launch(self, worlds: np.ndarray, actions: np.ndarray) -> None:
        """``actions[:, 0]``: direction, angle ``pi * a`` from +x; ``actions[:, 1]``:
        speed, mapped linearly onto ``SPEED_RANGE``. The cue ball's velocity is set in
        the chosen worlds (at rest between shots, so the others keep theirs, zero, and
        stay asleep)."""
        angle = math.pi * actions[:, 0]
        speed = action_to_range(actions[:, 1], SPEED_RANGE)
        cue = self.balls[0]
        velocity = np.atleast_2d(cue.velocity).copy()
        velocity[worlds, 0] = speed * np.cos(angle)
        velocity[worlds, 1] = speed * np.sin(angle)
        self.world.reset_events(worlds)
        cue.velocity = velocity  # wakes the ball only where its velocity changed
        self._potted_before[worlds] = self.potted[worlds]
        if self.shaping:
            self._potential_before[worlds] = self._potential(worlds)

    def _potential(self, worlds: np.ndarray) -> np.ndarray:
        """Phi = -(sum over object balls still on the table of the distance from the ball
        to its nearest pocket) / table length: 0 once every ball is down."""
        pose = self.world.array("pose")
        count = self.num_balls + 1
        x, y = pose[0][worlds, 1:count], pose[1][worlds, 1:count]
        dx = x[..., None] - self.pocket_centres[:, 0]
        dy = y[..., None] - self.pocket_centres[:, 1]
        nearest = np.sqrt(dx * dx + dy * dy).min(axis=-1)
        on_table = ~self.potted[worlds, 1:]
        return -(nearest * on_table).sum(axis=1) / TABLE_LENGTH

    def _score(self, worlds: np.ndarray, steps: np.ndarray) -> tuple[np.ndarray, np.ndarray, Info]:
        count = self.num_balls + 1
        world = self.world
        # What the engine recorded during the shot: the balls its sensors switched off,
        # and the first body each ball pushed against.
        self.potted[worlds] |= world.array("sensed")[worlds, :count] >= 0
        first = world.array("first_contact")[worlds, :count]
        cue_first = first[:, 0]
        touched = ((cue_first >= 1) & (cue_first < count)) | (first[:, 1:] == 0).any(axis=1)
        new = self.potted[worlds] & ~self._potted_before[worlds]
        objects = new[:, 1:].sum(axis=1)
        scratch = new[:, 0]
        no_touch = ~touched
        if scratch.any():
            self._respot(worlds[scratch])
        reward = objects - 1.0 * scratch - 0.1 * no_touch
        shaped = np.zeros(worlds.size)
        if self.shaping:
            shaped = self.shaping * (self._potential(worlds) - self._potential_before[worlds])
            reward = reward + shaped
        left = (~self.potted[worlds, 1:]).sum(axis=1)
        info = {
            "potted": objects.astype(np.int64),
            "cue_potted": scratch,
            "no_touch": no_touch,
            "fouls": scratch.astype(np.int64) + no_touch,
            "balls_left": left.astype(np.int64),
            "physics_steps": steps,
            "shaping": shaped,
        }
        return reward.astype(np.float64), left == 0, info

    def _respot(self, worlds: np.ndarray) -> None:
        """Put potted cue balls back: on the head spot, or the nearest free point to it
        behind the head string."""
        cue = self.balls[0]
        position, velocity = np.atleast_2d(cue.position), np.atleast_2d(cue.velocity)
        enabled = np.atleast_1d(cue.enabled).copy()
        pose = self.world.array("pose")
        on = self.world.array("enabled")
        for w in worlds:
            live = np.flatnonzero(on[w, 1 : self.num_balls + 1]) + 1
            others = np.stack([pose[0, w, live], pose[1, w, live]], axis=1)
            position[w] = self._spot_near_head(others)
        velocity[worlds] = 0.0
        enabled[worlds] = True
        cue.velocity, cue.position, cue.enabled = velocity, position, enabled
        self.world.stop(worlds)
        self.potted[worlds, 0] = False

    @staticmethod
    def _spot_near_head(others: np.ndarray) -> np.ndarray:
        """The free point nearest the head spot on rings of growing radius (a quarter ball
        radius apart), only behind the head string (x <= the head spot's) and on the
        cloth; a ball touching no other ball, with 1 mm to spare."""
        step = BALL_RADIUS / 4
        x_min = -TABLE_LENGTH / 2 + BALL_RADIUS
        y_max = TABLE_WIDTH / 2 - BALL_RADIUS
        for ring in range(0, 200):
            count = max(1, 16 * ring)
            angle = 2 * math.pi * np.arange(count) / count
            x = HEAD_SPOT[0] + ring * step * np.cos(angle)
            y = HEAD_SPOT[1] + ring * step * np.sin(angle)
            # Nearest to the table's long axis first, so the choice is symmetric and fixed.
            order = np.argsort(np.abs(y), kind="stable")
            for px, py in zip(x[order], y[order], strict=True):
                if px > HEAD_SPOT[0] + 1e-12 or px < x_min or abs(py) > y_max:
                    continue
                if np.all(np.hypot(others[:, 0] - px, others[:, 1] - py) > 2 * BALL_RADIUS + 1e-3):
                    return np.array([px, py])
        # 15 balls cannot cover the 0.6 m x 1.2 m area behind the head string.
        raise RuntimeError("no free spot for the cue ball")

    def drag_action(self, world: int, start: Any, end: Any) -> np.ndarray:
        """The tutorial's cue stick: the drag from press to release is the stroke. Its
        direction is the shot's, and its length sets the speed, full speed at half the
        table's width (0.635 m). A drag shorter than 1 mm is the gentlest stroke."""
        stroke = np.asarray(end, np.float64) - np.asarray(start, np.float64)
        length = float(np.hypot(*stroke))
        angle = math.atan2(stroke[1], stroke[0]) if length > 1e-3 else 0.0
        power = min(length / (TABLE_WIDTH / 2), 1.0)
        return np.array([angle / math.pi, 2.0 * power - 1.0])

    # -- observation and pictures ------------------------------------------------------------------
    def observe(self) -> np.ndarray:
        count = self.num_balls + 1
        pose = self.world.array("pose")
        obs = np.zeros((self.batch_size, count, 3), np.float32)
        obs[:, :, 0] = np.clip(pose[0, :, :count] / (TABLE_LENGTH / 2), -1.0, 1.0)
        obs[:, :, 1] = np.clip(pose[1, :, :count] / (TABLE_WIDTH / 2), -1.0, 1.0)
        obs[self.potted] = (0.0, 0.0, 1.0)
        return obs.reshape(self.batch_size, -1)

    def make_renderer(self, width: int, height: int) -> Renderer:
        margin = CUSHION_THICKNESS + 0.03
        view = (
            -TABLE_LENGTH / 2 - margin,
            -TABLE_WIDTH / 2 - margin,
            TABLE_LENGTH / 2 + margin,
            TABLE_WIDTH / 2 + margin,
        )
        style = Style(
            background=(40, 28, 22),
            fixed=(22, 96, 58),
            body_colours={ball.slot: BALL_COLOURS[i] for i, ball in enumerate(self.balls)},
        )
        return Renderer(
            width, height, Camera.fit_view(view, width, height), style, underlay=self._cloth
        )

    def make_frames(self, size: int) -> Frames:
        """Top down, the table filling the frame's width: the rails, cloth, pockets and
        cushions drawn once into the background, each ball in its own colour (a potted
        ball is switched off and not drawn)."""
        margin = CUSHION_THICKNESS + 0.03
        half_l, half_w = TABLE_LENGTH / 2 + margin, TABLE_WIDTH / 2 + margin
        frames = Frames(self.world, size, size, view=((-half_l, -half_w), (half_l, half_w)))
        canvas = np.empty((size, size, 3), np.float32)
        canvas[:] = (40, 28, 22)
        scale = frames.scale
        x, y = frames.to_pixels(0.0, 0.0)
        half = (0.5 * TABLE_LENGTH * scale, 0.5 * TABLE_WIDTH * scale)
        raster.box(canvas, x, y, 0.0, *half, np.array((30, 120, 70), np.float32))
        for (cx, cy), radius in zip(self.pocket_centres, self.pocket_radii, strict=True):
            px, py = frames.to_pixels(cx, cy)
            raster.disc(canvas, px, py, radius * scale, np.array((8, 8, 8), np.float32))
        for cx, cy, w, h in cushions():
            px, py = frames.to_pixels(cx, cy)
            colour = np.array((22, 96, 58), np.float32)
            raster.box(canvas, px, py, 0.0, 0.5 * w * scale, 0.5 * h * scale, colour)
        frames.background = np.clip(np.rint(canvas), 0, 255).astype(np.uint8)
        balls = {id(ball) for ball in self.balls}
        for body in self.world.bodies:
            if id(body) not in balls:
                frames.hide(body)  # the cushions: in the background
        for ball, colour in zip(self.balls, BALL_COLOURS, strict=False):
            frames.colour(ball, colour)
        return frames

    def _cloth(self, canvas: np.ndarray, renderer: Renderer) -> None:
        """The cloth and the pockets, under everything."""
        x0, y0 = renderer.to_pixels(-TABLE_LENGTH / 2, TABLE_WIDTH / 2)
        x1, y1 = renderer.to_pixels(TABLE_LENGTH / 2, -TABLE_WIDTH / 2)
        raster.box(
            canvas,
            (x0 + x1) / 2,
            (y0 + y1) / 2,
            0.0,
            (x1 - x0) / 2,
            (y1 - y0) / 2,
            np.array((30, 120, 70), np.float32),
        )
        scale = renderer.camera.pixels_per_metre
        for (cx, cy), radius in zip(self.pocket_centres, self.pocket_radii, strict=True):
            px, py = renderer.to_pixels(cx, cy)
            raster.disc(canvas, px, py, radius * scale, np.array((8, 8, 8), np.float32))


class Pool2DEnv(ShotEnv):
    """Top-down pool: one step is one cue stroke, played until every ball is at rest.

    ## Description
    A regulation 9-ft table (play area 2.54 x 1.27 m) with six pockets (corner mouths
    0.118 m, side mouths 0.137 m) and cushions that end at the pocket jaws. The balls
    have the published size and mass (radius 28.575 mm, 0.170 kg); ball-ball restitution
    0.95, ball-cushion 0.75; they roll to a stop under a rolling resistance of 0.1 m/s^2
    (coefficient 0.01). Seen from above the balls are discs: sliding versus rolling, and
    cue-ball spin (follow, draw, english), are not modelled. A ball is potted when its
    centre enters a pocket circle (as wide as the mouth, one ball radius behind it).

    ## Action Space
    `Box(-1, 1, (2,), float32)`: `action[0]` sets the cue direction, angle `pi * action[0]`
    from the +x axis (the foot of the table); `action[1]` sets the cue-ball speed, mapped
    linearly from 0.25 m/s (at -1) to 6 m/s (at +1). Values outside [-1, 1] are clipped;
    NaN or infinite values raise `ValueError`.

    ## Observation Space
    `Box(low, high, (3 * (num_balls + 1),), float32)`, three numbers per ball, the cue
    ball first, then object balls 1, 2, ...; potted balls stay in the vector:

    | index       | observation                             | min | max |
    |-------------|-----------------------------------------|-----|-----|
    | 3 i         | x of ball i / 1.27 m (0 when potted)    | -1  | 1   |
    | 3 i + 1     | y of ball i / 0.635 m (0 when potted)   | -1  | 1   |
    | 3 i + 2     | 1 if ball i is potted, else 0           | 0   | 1   |

    With `obs_type="pixels"`: `Box(0, 255, (pixel_size, pixel_size, 3), uint8)`, the
    table from above (see Arguments).

    ## Rewards
    +1 per object ball potted; -1 if the cue ball is potted (a scratch: it comes back on
    the head spot, or the nearest free point to it behind the head string); -0.1 if the
    cue ball touches no ball.

    With `shaping=k > 0`, a learning aid: each shot also earns `k (Phi(after) -
    Phi(before))`, where `Phi = -(sum over object balls on the table of the distance to
    the nearest pocket) / 2.54 m`: moving a ball towards a pocket pays a little before
    it drops. The term is potential-based (Ng, Harada and Russell, 1999), so it does not
    change which play is best; `info["shaping"]` holds it, so the game's own score is
    `reward - info["shaping"]`.

    ## Starting State
    `layout="rack"`: the object balls in the standard triangle (apex on the foot spot;
    with fewer balls, its first rows), the cue ball at a uniform random point behind the
    head string. `layout="random"`: every ball at a uniform random point on the table,
    clear of the others and of the pockets.

    ## Episode End
    Terminated when every object ball is potted. Truncated after 30 shots
    (`max_episode_steps`; a shot itself stops after `max_shot_seconds` of simulated time).

    `info`: `potted` (object balls potted this shot), `cue_potted`, `no_touch`, `fouls`
    (the two counted), `balls_left`, `physics_steps` (engine steps of the shot at
    dt = 1/120 s), `shaping` (the shaping term in the reward; 0 unless `shaping` is set).

    ## Arguments
    ```python
    gym.make("Pool2D-v0", num_balls=15, layout=None, max_shot_seconds=20.0, shaping=0.0,
             render_mode=None)
    gym.make_vec("Pool2D-v0", num_envs=256, vectorization_mode="vector_entry_point",
                 threads=None, device="cpu", obs_type="state", pixel_size=84)
    ```
    * `num_balls` (1-15): object balls. `num_balls=1` with a random layout, one ball to
      pot from anywhere, is the natural first task for learning.
    * `layout`: `"rack"` or `"random"`; default `"rack"` for 15 balls, else `"random"`.
    * `max_shot_seconds` (in (0, 3600] s): simulated time after which a shot is stopped
      where it stands (at least one physics step).
    * `shaping` (in [0, 1000]): weight of the potential-based shaping term (see Rewards).
    * `num_envs` (vector env, 1 to 1,000,000): tables stepped together.
    * `max_episode_steps` (vector env, None or an int >= 1): shots before truncation.
    * `threads` (vector env): threads the batch is stepped on; default every core. The
      results do not depend on it.
    * `device`: `"cpu"`, or `"cuda"` to play every table's shot in one GPU launch (the
      `gpu` extra and an NVIDIA GPU; see the docs' "On a GPU", `docs/gpu.md`).
    * `obs_type`: `"state"` (the vector above) or `"pixels"`: the table seen from above,
      `pixel_size` x `pixel_size` RGB uint8 (16 to 1024, default 84): cloth, cushions
      and pockets, each ball in its colour (a potted ball gone), drawn for every table
      at once in compiled code (`impulse2d.pixels`).
    * `render_mode`: `"rgb_array"` (480x270 frame after the shot), `"rgb_array_list"`
      (frames at 30 per simulated second during the shots), `"human"` (pygame-ce window;
      without a display the env says so once, at the first frame, and plays on without
      one).

    A value outside its rule (a wrong type, NaN, infinity, a huge number) raises
    `ValueError` naming the argument and its rule when the env is made.

    ## Saving and restoring
    `env.unwrapped.save_state()` and `restore_state(state)` save and bring back a table's
    position, bitwise (see `ShotEnv`); the vector env restores chosen `worlds=[...]`.

    ## Version History
    * v0: first version.
    """

    game_class = PoolGame


class Pool2DVectorEnv(ShotVectorEnv):
    """``num_envs`` Pool2D tables stepped in one batched engine (see ``Pool2DEnv``)."""

    game_class = PoolGame
