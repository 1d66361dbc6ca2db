"""The World: a scene, or a batch of scenes stepped together, over plain arrays.

A ``World`` holds three things and the objects that view them:

* ``settings`` (``Settings``): what it was set up with, validated on every assignment;
* ``state`` (``WorldState``): every array that evolves, with a leading world axis;
* ``layout`` (``Layout``): what the worlds share, the kind of each slot.

``step`` is one compiled call into ``pipeline``; ``run_until_rest`` runs a whole shot
the same way. A snapshot is a copy of the state and
the settings.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import _checks, edit, envelope, readouts, structure
from .core import pipeline, refusal
from .core.runner import Runner, available_threads
from .core.state import (
    BODY_F,
    BODY_I,
    FIRST_CONTACT,
    JOINT_LIST,
    SENSED,
    STEPS,
    Layout,
    WorldState,
)
from .joints import Joint
from .readouts import ContactPoints, Energy
from .settings import Settings
from .springs import Spring

# Readable names for ``World.array``: name -> (array, columns).
ARRAYS: dict[str, tuple[str, Any]] = {
    "pose": ("body", slice(0, 3)),
    "vel": ("body", slice(3, 6)),
    "force": ("body", slice(6, 9)),
    **{
        name: ("body", column)
        for column, name in enumerate(
            [
                "x",
                "y",
                "angle",
                "vx",
                "vy",
                "angular_velocity",
                "fx",
                "fy",
                "torque",
                "mass",
                "inv_mass",
                "moment",
                "inv_moment",
                "half_width",
                "half_height",
                "bound",
                "normal_x",
                "normal_y",
                "restitution",
                "friction",
                "linear_drag",
                "angular_drag",
                "rolling_resistance",
                "sleep_time",
                "health",
                "cos",
                "sin",
                "damp_linear",
                "damp_angular",
                "damp_h",
            ]
        )
    },
    **{
        name: ("body_i", column)
        for column, name in enumerate(["enabled", "awake", "island", "sensed", "first_contact"])
    },
    "joint_list": ("body_i", JOINT_LIST),  # after the broadphase's cache, SAP_ORDER
}
assert len([n for n, (a, _) in ARRAYS.items() if a == "body" and isinstance(_, int)]) == BODY_F
assert len([n for n, (a, _) in ARRAYS.items() if a == "body_i"]) == BODY_I - 1


@dataclass(frozen=True)
class Snapshot:
    """Everything a World (or batch) steps from, at one moment: ``World.restore`` brings
    it back, and the restored world steps bitwise as the original did.

    * ``state``: every array that evolves (bodies, springs, sensors, the last step's
      contacts, which warm-start the next step and which ``impulses()``, ``touches()``
      and ``contacts()`` read, time and step counts);
    * ``settings``: gravity, substeps, the contact and sleep settings;
    * ``layout``: which objects it belongs to (it restores only into the same objects).

    Not held: ``threads`` (results do not depend on it) and the objects' Python
    attributes (a Spring's bodies, a Sensor's flags), which cannot change."""

    state: WorldState
    layout: Layout
    settings: Settings

    @property
    def batch_size(self) -> int:
        return self.state.batch_size


def _setting(name: str, doc: str) -> property:
    return property(
        lambda self: getattr(self.settings, name),
        lambda self, value: setattr(self.settings, name, value),
        doc=doc,
    )


def _device(device: Any) -> str:
    """``device`` checked: ``'cpu'``, or ``'cuda'`` where numba-cuda finds a GPU (or runs
    its simulator, ``NUMBA_ENABLE_CUDASIM=1``)."""
    device = _checks.word("device", device, ("cpu", "cuda"))
    if device == "cuda":
        try:
            import numba_cuda  # noqa: F401  (numba's own numba.cuda is deprecated)
            from numba import cuda
        except ImportError as missing:
            raise ValueError(
                "device='cuda' needs numba-cuda: pip install 'impulse2d[gpu]'"
            ) from missing
        if not cuda.is_available():
            raise ValueError(
                "device='cuda' needs an NVIDIA GPU that numba-cuda can use, and found none "
                "(numba.cuda.is_available() is False: no GPU, no driver, or one too old)"
            )
    return device


class World:
    """A 2D physics world, or a batch of ``batch_size`` worlds stepped together.

    Arguments (SI units):

    * ``gravity`` (m/s^2): settable; zero for a top-down table.
    * ``batch_size``: number of worlds. Every object added is added to all of them; its
      properties then read and write one value per world.
    * ``substeps``: solver substeps per ``step`` (Box2D v3 uses 4). More substeps make
      stacks stiffer and springs more accurate; cost grows linearly.
    * ``restitution_mixing`` / ``friction_mixing``: how a contact combines the two
      shapes' values: ``'max'``, ``'min'``, ``'mean'``, ``'product'`` or ``'sqrt'``
      (``sqrt(a b)``). Defaults are Box2D's (max, sqrt). A pool table uses
      ``restitution_mixing='min'``: balls 0.95 and cushions 0.75 give ball-ball 0.95 and
      ball-cushion 0.75.
    * ``restitution_threshold`` (m/s): slower impacts do not bounce (stops resting
      contacts from jittering). Box2D uses 1 m/s for metre-sized bodies.
    * ``contact_hertz``, ``contact_damping_ratio``: stiffness of the soft position
      correction of overlaps (capped at a quarter of the substep rate; twice as stiff
      against immovable bodies). ``contact_push_speed`` (m/s) caps how fast each contact
      pushes overlapping bodies apart, so a heavily overlapping start does not explode.
    * ``speculative_distance`` (m): contacts are made this much before shapes touch, on
      top of how far the pair can close in the step (at most a quarter of a body's size,
      so small bodies get proportionally smaller distances).
    * ``sleeping``: let islands of slow bodies sleep (``time_to_sleep`` s below
      ``sleep_speed`` m/s). Sleeping bodies cost nothing until something touches them.
    * ``damage_speed`` (m/s): impacts closing slower than this do not drain a body's
      ``health`` (the steady push of a resting stack does no damage).
    * ``threads``: threads a batch is stepped on (default: every core numba sees); a
      single world always uses one. Results do not depend on it.
    * ``device``: ``'cpu'`` (the default) or ``'cuda'``: every world of a call stepped by
      a GPU thread of its own, in one launch of the same kernels (``impulse2d.core.gpu``;
      needs the ``gpu`` extra and an NVIDIA GPU). The state is copied to the GPU and back
      at each call, so everything else works as on the CPU.
    """

    gravity = property(lambda self: self.settings.gravity, doc="Gravity (m/s^2), shape (2,).")
    substeps = _setting("substeps", "Solver substeps per step.")
    restitution_threshold = _setting("restitution_threshold", "Slower impacts do not bounce (m/s).")
    contact_hertz = _setting("contact_hertz", "Stiffness of the overlap correction (Hz).")
    contact_damping_ratio = _setting("contact_damping_ratio", "Its damping ratio.")
    contact_push_speed = _setting("contact_push_speed", "Fastest push out of an overlap (m/s).")
    speculative_distance = _setting("speculative_distance", "Contacts this far early (m).")
    sleeping = _setting("sleeping", "Whether slow islands fall asleep.")
    time_to_sleep = _setting("time_to_sleep", "Seconds slow before sleeping.")
    sleep_speed = _setting("sleep_speed", "Slower than this (m/s) counts as resting.")
    damage_speed = _setting("damage_speed", "Slower impacts do no damage (m/s).")
    restitution_mixing = property(lambda self: self.settings.restitution_mixing)
    friction_mixing = property(lambda self: self.settings.friction_mixing)

    def __init__(
        self,
        gravity: Any = (0.0, -9.81),
        *,
        batch_size: int = 1,
        substeps: int = 4,
        restitution_mixing: str = "max",
        friction_mixing: str = "sqrt",
        restitution_threshold: float = 1.0,
        contact_hertz: float = 30.0,
        contact_damping_ratio: float = 10.0,
        contact_push_speed: float = 3.0,
        speculative_distance: float = 0.02,
        sleeping: bool = True,
        time_to_sleep: float = 0.5,
        sleep_speed: float = 0.05,
        damage_speed: float = 1.0,
        threads: int | None = None,
        device: str = "cpu",
    ) -> None:
        batch = _checks.positive_int("batch_size", batch_size)
        device = _device(device)
        self.settings = Settings(
            gravity=gravity,
            substeps=substeps,
            restitution_mixing=restitution_mixing,
            friction_mixing=friction_mixing,
            restitution_threshold=restitution_threshold,
            contact_hertz=contact_hertz,
            contact_damping_ratio=contact_damping_ratio,
            contact_push_speed=contact_push_speed,
            speculative_distance=speculative_distance,
            sleeping=sleeping,
            time_to_sleep=time_to_sleep,
            sleep_speed=sleep_speed,
            damage_speed=damage_speed,
        )
        self.state = WorldState.empty(batch, 8, 4, 2, 16)
        self.layout = Layout(8, 4, 2)
        self.objects: dict[str, list] = {
            "bodies": [None] * 8,
            "springs": [None] * 4,
            "sensors": [None] * 2,
        }
        self._runner = Runner(1, device)
        self.threads = threads

    # -- settings -----------------------------------------------------------------------------
    @gravity.setter
    def gravity(self, value: Any) -> None:
        """Setting gravity wakes every body (a resting body must feel the change)."""
        self.settings.gravity = value
        everywhere = np.arange(self.batch_size)
        for slot, obj in enumerate(self.objects["bodies"]):
            if obj is not None:
                edit.wake(self.state, self.layout, everywhere, slot)

    @property
    def threads(self) -> int:
        """Threads a batch is stepped on (settable; ``None`` sets every core)."""
        return self._runner.threads

    @threads.setter
    def threads(self, value: int | None) -> None:
        most = available_threads()
        count = most if value is None else _checks.positive_int("threads", value)
        if count > most:
            raise ValueError(f"threads must be in [1, {most}] (the cores numba sees), got {count}")
        self._runner.threads = count

    @property
    def device(self) -> str:
        """Where the steps run: ``'cpu'`` or ``'cuda'`` (set when the world is made)."""
        return self._runner.device

    @property
    def batch_size(self) -> int:
        """Number of worlds stepped together (1 for a plain world)."""
        return self.state.batch_size

    @property
    def time(self) -> Any:
        """Simulated time (s): a float, or one per world."""
        return float(self.state.time[0]) if self.batch_size == 1 else self.state.time.copy()

    @property
    def steps(self) -> Any:
        """Steps taken: an int, or one per world."""
        steps = self.state.world_i[:, STEPS]
        return int(steps[0]) if self.batch_size == 1 else steps.copy()

    # -- objects ------------------------------------------------------------------------------
    @property
    def bodies(self) -> list:
        """Every body and plane in the world, in slot order."""
        return [obj for obj in self.objects["bodies"] if obj is not None]

    @property
    def springs(self) -> list:
        """Every Spring in the world, in slot order."""
        return [obj for obj in self.objects["springs"] if isinstance(obj, Spring)]

    @property
    def joints(self) -> list:
        """Every joint in the world (``impulse2d.joints``), in slot order."""
        return [obj for obj in self.objects["springs"] if isinstance(obj, Joint)]

    @property
    def sensors(self) -> list:
        """Every Sensor in the world, in slot order."""
        return [obj for obj in self.objects["sensors"] if obj is not None]

    def add(self, obj: Any) -> Any:
        """Add a body (Circle, Box, Polygon, Capsule, Segment), Plane, Spring or Sensor to
        every world of the batch; returns ``obj``."""
        return structure.add(self, obj)

    def remove(self, obj: Any) -> None:
        """Take an object out of every world. It keeps its values and can be added again."""
        structure.remove(self, obj)

    # -- stepping -----------------------------------------------------------------------------
    def step(self, dt: float, steps: int = 1) -> None:
        """Advance every world by ``dt`` seconds (``substeps`` solver substeps inside), or
        ``steps`` times by ``dt`` in one compiled call."""
        context = self.settings.step_context(dt)
        if steps.__class__ is int and steps == 1:  # an RL loop's call: the runner's fast path
            plan, status = self._runner.step_once(self.state, self.layout, context)
        else:
            count = _checks.positive_int("steps", steps)
            every = self._runner.every_world(self.batch_size)
            plan, status = self._runner.run(self.state, self.layout, context, every, count, False)
        if status:
            self._check_refusals(plan, context)

    def run_until_rest(
        self,
        dt: float,
        max_steps: int,
        worlds: Any = None,
        *,
        every: int | None = None,
        callback: Any = None,
    ) -> np.ndarray:
        """Step each of ``worlds`` (indices; default all) by ``dt`` until it is at rest or
        has taken ``max_steps`` steps, in compiled code; returns the steps each took, in
        the order given. A world at rest costs nothing while the others go on, and worlds
        not named do not move. With ``callback``, the run pauses every ``every`` steps to
        call ``callback(steps_so_far)`` (frames of a shot), then goes on."""
        context = self.settings.step_context(dt)
        cap = _checks.positive_int("max_steps", max_steps)
        chosen = self._worlds(worlds)
        if callback is None:
            plan, _ = self._runner.run(self.state, self.layout, context, chosen, cap, True)
            self._check_refusals(plan, context)
            return plan[:, pipeline.PLAN_STEPS].copy()
        if not callable(callback):
            raise ValueError(f"callback must be callable, got {callback!r}")
        every = _checks.positive_int("every", 1 if every is None else every)
        taken = np.zeros(chosen.size, np.int64)
        going = np.arange(chosen.size)
        before = self.state.copy()  # a refusal after some frames undoes the whole call
        while going.size:
            chunk = min(every, cap - int(taken[going].min()))
            plan, status = self._runner.run(
                self.state, self.layout, context, chosen[going], chunk, True
            )
            if status >= pipeline.UNSTABLE_SPRING:
                everyone = np.arange(self.batch_size)
                self.state.put(before, everyone, everyone)
                self._check_refusals(plan, context)
            moved = plan[:, pipeline.PLAN_STEPS]
            taken[going] += moved
            if moved.max() == chunk:  # a frame boundary was reached
                callback(taken.copy())
            # A world goes on while it used its whole chunk (it did not come to rest).
            going = going[(moved == chunk) & (taken[going] < cap)]
        return taken

    def _check_refusals(self, plan: np.ndarray, context: np.ndarray) -> None:
        """Raise for the first refused world of ``plan`` (the runner has already put every
        world back as it was before the call)."""
        status = plan[:, pipeline.PLAN_STATUS]
        bad = np.flatnonzero(status >= pipeline.UNSTABLE_SPRING)
        if bad.size == 0:
            return
        world, slot = int(plan[bad[0], pipeline.PLAN_WORLD]), int(plan[bad[0], pipeline.BAD_SLOT])
        if status[bad[0]] == pipeline.LEFT_ENVELOPE:
            raise self._left_envelope(plan[bad[0]], world, slot)
        spring = self.objects["springs"][slot]
        stiffness = np.atleast_1d(spring.stiffness)[world]
        damping = np.atleast_1d(spring.damping)[world]
        where = f" in world {world}" if self.batch_size > 1 else ""
        if status[bad[0]] == pipeline.FAST_SPRING:
            raise ValueError(
                f"spring stiffness {stiffness} N/m with damping {damping} N s/m pulls its "
                f"anchors apart at more than {envelope.ACCELERATION:g} m/s^2{where} (the "
                "supported range, see impulse2d.envelope: (k |L - L0| + c |v|) w, w the "
                "inverse effective mass along the spring); lower stiffness or stretch, or "
                "use heavier bodies. No world stepped."
            )
        raise ValueError(
            f"spring stiffness {stiffness} N/m with damping {damping} N s/m is unstable at "
            f"substep h = {context[1]:.3g} s{where} (needs h^2 k w + 2 h c w < 4, w the inverse "
            "effective mass along the spring); lower stiffness or damping, use more substeps "
            "or a smaller dt. No world stepped."
        )

    def _left_envelope(self, row: np.ndarray, world: int, slot: int) -> envelope.EnvelopeError:
        what = refusal.WHAT[int(row[pipeline.BAD_WHAT])]
        limit = {
            "speed": f"its speed passed {envelope.SPEED:g} m/s",
            "angular speed": f"its angular speed passed {envelope.ANGULAR_SPEED:g} rad/s",
            "position": f"its centre went beyond {envelope.COORDINATE:g} m on an axis",
            "not finite": "its position or velocity stopped being a number",
        }[what]
        where = f"world {world}, " if self.batch_size > 1 else ""
        step = int(row[pipeline.PLAN_STEPS]) + 1
        return envelope.EnvelopeError(
            f"{where}{self.objects['bodies'][slot]!r} left the supported range at its "
            f"step {step} of this call: {limit} (see impulse2d.envelope). A scene can leave "
            "it by itself: bounces with restitution above 1 and kinematic bodies add energy "
            "without bound, and a small body struck hard spins fast. The step was refused "
            "and every world is as it was before the call.",
            world=world, body=slot, quantity=what,
        )  # fmt: skip

    def _all(self) -> np.ndarray:
        return self._runner.every_world(self.batch_size)

    def _worlds(self, worlds: Any) -> np.ndarray:
        """World indices from ``None`` (all), an int or a sequence of ints."""
        if worlds is None:
            return self._all()
        rows = np.asarray(worlds).reshape(-1)
        if rows.size == 0:
            return rows.astype(np.int64)
        if rows.dtype.kind not in "iu" or np.any(rows < 0) or np.any(rows >= self.batch_size):
            raise ValueError(f"worlds must be indices in [0, {self.batch_size}), got {worlds!r}")
        return rows.astype(np.int64)

    # -- readouts and queries -------------------------------------------------------------------
    def energy(self) -> Energy:
        """Kinetic (linear, rotational), gravitational potential and spring energy (J).

        Potential energy is ``-m g . position``, zero at the origin. Fixed and kinematic
        bodies are excluded (they are driven, not part of the system)."""
        return readouts.energy(self.state, self.layout, self.settings.gravity)

    def at_rest(self) -> Any:
        """True for a world in which nothing moves (every body asleep or fixed): a bool,
        or one per world."""
        state, shapes = self.state, self.layout.shapes
        rest = np.array([pipeline.at_rest(state.body_i, shapes, w) for w in range(self.batch_size)])
        return bool(rest[0]) if self.batch_size == 1 else rest

    def stop(self, worlds: Any = None) -> None:
        """Bring every body of the given worlds (default: all) to rest at once: velocities
        zero, dynamic bodies asleep. A game that caps how long a move may run uses this to
        end it the same way whether a world is stepped alone or in a batch."""
        edit.stop(self.state, self.layout, self._worlds(worlds))

    def reset_events(self, worlds: Any = None) -> None:
        """Forget what the bodies of the given worlds (default: all) sensed and touched
        first (``body.sensed``, ``body.first_contact``)."""
        rows = self._worlds(worlds)
        self.state.body_i[rows[:, None], :, [SENSED, FIRST_CONTACT]] = -1

    def impulses(self, approach_speed: float = 0.0) -> Any:
        """The contact impulse each body received in the last step (N s): the sum over its
        contact points of the normal impulses, shape ``(slots,)`` or ``(batch, slots)``
        (index by ``body.slot``). Games use it for damage: how hard was it hit.

        ``approach_speed`` (m/s) keeps only the points whose bodies were closing faster
        than that along the normal at the start of the step: impacts, not the steady
        push of a resting stack (whose points close at no more than about ``g dt``)."""
        speed = _checks.non_negative("approach_speed", approach_speed)
        total = readouts.impulses(self.state, speed)
        return total[0] if self.batch_size == 1 else total

    def touches(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The contact points that pushed in the last step: ``(world, slot_a, slot_b,
        impulse)`` arrays, one entry per point, with the normal impulse it applied over
        the step (N s). Speculative points that never touched are left out."""
        return readouts.touches(self.state)

    def contacts(self, world: int = 0) -> ContactPoints:
        """The contact points of world ``world`` at its last step (``ContactPoints``)."""
        return readouts.contact_points(self.state, self._world_index(world))

    def array(self, name: str) -> np.ndarray:
        """A read-only array of one body field in every world, for vectorised readouts:
        ``'pose'``, ``'vel'`` and ``'force'`` have shape ``(3, batch, slots)`` (x, y,
        angle and their rates), the others ``(batch, slots)`` (``ARRAYS`` lists them;
        ``state.py`` gives their units). Index slots by ``body.slot``. Writes go through
        the objects, which keep derived values consistent and wake what they touch."""
        if name not in ARRAYS:
            raise ValueError(f"name must be one of {', '.join(ARRAYS)}, got {name!r}")
        array, columns = ARRAYS[name]
        if array == "body_i":
            view = (
                self.state.body_i[:, :, columns] == 1
                if name in ("enabled", "awake")
                else (self.state.body_i[:, :, columns].copy())
            )
        else:
            view = self.state.body[:, :, columns]
            view = view.transpose(2, 0, 1) if view.ndim == 3 else view.view()
        view.flags.writeable = False
        return view

    def query_point(self, point: Any, world: int = 0) -> list:
        """The circles and boxes that contain a world point (in world ``world`` of the
        batch), in slot order. Planes are left out: they are the scenery."""
        p = _checks.vector2("point", point)
        slots = readouts.containing(self.state, self.layout, p, self._world_index(world))
        return [self.objects["bodies"][i] for i in slots]

    def _world_index(self, world: Any) -> int:
        if isinstance(world, bool) or not isinstance(world, (int, np.integer)):
            raise ValueError(f"world must be an int in [0, {self.batch_size}), got {world!r}")
        if not 0 <= world < self.batch_size:
            raise ValueError(f"world must be in [0, {self.batch_size}), got {world}")
        return int(world)

    # -- snapshots and copies -----------------------------------------------------------------
    def snapshot(self) -> Snapshot:
        """A copy of the full state and the settings; ``restore`` brings them back."""
        return Snapshot(self.state.copy(), self.layout.copy(), self.settings.copy())

    def restore(self, snapshot: Snapshot, worlds: Any = None) -> None:
        """Bring back a snapshot: into every world, or only into ``worlds`` (indices).

        The snapshot must come from a world with the same objects in the same slots (this
        one, a copy from ``replicate``, or one built by the same code). A snapshot of one
        world can be restored into any number of worlds; a snapshot of a batch of the same
        size restores world ``i`` from its world ``i``; otherwise it must have one world per
        named world, taken in order."""
        if not isinstance(snapshot, Snapshot):
            raise ValueError(f"snapshot must be a Snapshot, got {type(snapshot).__name__}")
        if not snapshot.layout.same_as(self.layout):
            raise ValueError(
                "snapshot does not match this world's objects: it was taken before "
                "objects were added or removed, or from a different scene"
            )
        targets = self._worlds(worlds)
        count = snapshot.batch_size
        if count == 1:
            sources = np.zeros(targets.size, np.int64)
        elif count == self.batch_size:
            sources = targets
        elif count == targets.size:
            sources = np.arange(targets.size)
        else:
            raise ValueError(
                f"snapshot has {count} worlds; it can fill any worlds of a batch of {count}, "
                f"or exactly {count} named worlds, not {targets.size} of {self.batch_size}"
            )
        self.state.put(snapshot.state, targets, sources)
        self.settings = snapshot.settings.copy()

    def replicate(self, batch_size: int) -> World:
        """A new batch of ``batch_size`` copies of this (single) world, state included.

        Its objects are new facades, in the same slots: ``new.bodies[i]`` is the copy of
        ``self.bodies[i]``; springs and sensors likewise."""
        batch = _checks.positive_int("batch_size", batch_size)
        if self.batch_size != 1:
            raise ValueError(f"replicate needs a single world, this one has {self.batch_size}")
        clone = copy.copy(self)
        clone.settings = self.settings.copy()
        clone.state = self.state.repeat(batch)
        clone.layout = self.layout.copy()
        clone._runner = Runner(self._runner.threads, self._runner.device)
        twins: dict[int, Any] = {}
        clone.objects = {}
        for kind, objects in self.objects.items():
            clone.objects[kind] = []
            for obj in objects:
                twin = None if obj is None else copy.copy(obj)
                if twin is not None:
                    twin._world = clone
                    twins[id(obj)] = twin
                clone.objects[kind].append(twin)
        for link in clone.springs + clone.joints:
            link.body1, link.body2 = twins[id(link.body1)], twins[id(link.body2)]
        return clone
