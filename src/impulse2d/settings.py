"""A world's settings, validated on every assignment, and the step context built from them.

``Settings`` holds what ``World(...)`` takes; each property checks its value on
construction and on every later assignment, so ``world.contact_hertz = float("nan")``
fails where it is written, naming the parameter, instead of turning the state to NaN at
the next step.

``step_context(dt)`` turns the settings and one ``dt`` into the float64 array every
kernel reads (Box2D v3's ``b2StepContext``): ``dt``, the substep ``h = dt / substeps``,
``1 / h``, the contact softness for that ``h``, gravity and the thresholds, at the
indices ``DT``, ``H``, ... below. It is rebuilt only when a setting or ``dt`` changes.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _checks, envelope
from .core import colouring
from .core.context import (
    COLOUR_FROM,
    CONTEXT_SIZE,
    DAMAGE_SPEED,
    DT,
    FRICTION_RULE,
    GRAVITY_X,
    GRAVITY_Y,
    HARD_IMPULSE,
    HARD_RATE,
    INV_H,
    JOINT_DAMPING_RATIO,
    JOINT_IMPULSE,
    JOINT_RATE,
    MIXING_RULES,
    PUSH_SPEED,
    RESTITUTION_RULE,
    RESTITUTION_THRESHOLD,
    SLEEP_SPEED,
    SLEEPING,
    SOFT_IMPULSE,
    SOFT_RATE,
    SPECULATIVE,
    SUBSTEPS,
    TIME_TO_SLEEP,
    H,
    soft_constraint,
)


def _number(rule: str) -> Any:
    return {"> 0": _checks.positive, ">= 0": _checks.non_negative}[rule]


class _Setting:
    """A validated float setting: ``rule`` is ``'> 0'`` or ``'>= 0'``; ``high`` (with its
    ``unit``) is the envelope's bound, if the setting has one."""

    def __init__(self, rule: str, doc: str, high: float | None = None, unit: str = "") -> None:
        self.rule, self.__doc__, self.high, self.unit = rule, doc, high, unit

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: Any, owner: type | None = None) -> Any:
        return self if obj is None else obj._values[self.name]

    def __set__(self, obj: Any, value: Any) -> None:
        number = _number(self.rule)(self.name, value)
        if self.high is not None:
            _checks.within(self.name, number, 0.0, self.high, self.unit)
        obj._values[self.name] = number
        obj._context = None


class Settings:
    """What a ``World`` is set up with (see ``World`` for each one's meaning)."""

    restitution_threshold = _Setting(">= 0", "Impacts slower than this (m/s) do not bounce.")
    contact_hertz = _Setting(
        "> 0", "Stiffness of the overlap correction (Hz).", envelope.RATE, " Hz"
    )
    contact_damping_ratio = _Setting(
        ">= 0", "Damping ratio of the overlap correction.", envelope.RATE
    )
    contact_push_speed = _Setting(
        "> 0", "Fastest push out of an overlap per contact (m/s).", envelope.SPEED, " m/s"
    )
    speculative_distance = _Setting(
        ">= 0", "Contacts are made this far (m) before touching.", envelope.SIZE[1], " m"
    )
    time_to_sleep = _Setting("> 0", "Seconds an island must be slow before it sleeps.")
    sleep_speed = _Setting(">= 0", "Bodies slower than this (m/s) count as resting.")
    damage_speed = _Setting(">= 0", "Impacts slower than this (m/s) do no damage.")

    def __init__(self, **values: Any) -> None:
        self._values: dict[str, Any] = {}
        self._context: tuple[float, np.ndarray] | None = None
        self.restitution_mixing = values.pop("restitution_mixing")
        self.friction_mixing = values.pop("friction_mixing")
        for name, value in values.items():
            setattr(self, name, value)

    @property
    def gravity(self) -> np.ndarray:
        """Gravitational acceleration (m/s^2), shape (2,)."""
        return self._values["gravity"].copy()

    @gravity.setter
    def gravity(self, value: Any) -> None:
        gravity = _checks.vector2("gravity", value)
        _checks.magnitude_at_most("gravity", gravity, envelope.ACCELERATION, " m/s^2")
        self._values["gravity"] = gravity
        self._context = None

    @property
    def substeps(self) -> int:
        return self._values["substeps"]

    @substeps.setter
    def substeps(self, value: Any) -> None:
        self._values["substeps"] = _checks.positive_int("substeps", value)
        self._context = None

    @property
    def sleeping(self) -> bool:
        return self._values["sleeping"]

    @sleeping.setter
    def sleeping(self, value: Any) -> None:
        if not isinstance(value, (bool, np.bool_)):
            raise ValueError(f"sleeping must be a bool, got {value!r}")
        self._values["sleeping"] = bool(value)
        self._context = None

    @property
    def restitution_mixing(self) -> str:
        return self._values["restitution_mixing"]

    @restitution_mixing.setter
    def restitution_mixing(self, value: Any) -> None:
        self._values["restitution_mixing"] = _checks.choice(
            "restitution_mixing", value, MIXING_RULES
        )
        self._context = None

    @property
    def friction_mixing(self) -> str:
        return self._values["friction_mixing"]

    @friction_mixing.setter
    def friction_mixing(self, value: Any) -> None:
        self._values["friction_mixing"] = _checks.choice("friction_mixing", value, MIXING_RULES)
        self._context = None

    def copy(self) -> Settings:
        twin = Settings.__new__(Settings)
        twin._values = {
            k: v.copy() if isinstance(v, np.ndarray) else v for k, v in self._values.items()
        }
        twin._context = None
        return twin

    def step_context(self, dt: Any) -> np.ndarray:
        """The context array for a step of ``dt`` seconds (cached until a setting changes);
        ``dt`` is checked here, against ``impulse2d.envelope.DT``."""
        cached = self._context
        if cached is not None and cached[0] == dt and type(dt) is float:
            return cached[1]
        dt = _checks.positive("dt", dt)
        _checks.within("dt", dt, *envelope.DT, unit=" s")
        v = self._values
        h = dt / v["substeps"]
        # Box2D caps the contact stiffness at a quarter of the substep rate: stiffer than
        # that, the implicit spring cannot be resolved within a substep.
        hertz = min(v["contact_hertz"], 0.25 / h)
        ctx = np.zeros(CONTEXT_SIZE)
        ctx[[DT, H, INV_H, SUBSTEPS]] = dt, h, 1.0 / h, v["substeps"]
        ctx[[GRAVITY_X, GRAVITY_Y]] = v["gravity"]
        ctx[SOFT_RATE : SOFT_IMPULSE + 1] = soft_constraint(hertz, v["contact_damping_ratio"], h)
        ctx[HARD_RATE : HARD_IMPULSE + 1] = soft_constraint(
            2.0 * hertz, v["contact_damping_ratio"], h
        )
        ctx[JOINT_RATE : JOINT_IMPULSE + 1] = soft_constraint(2.0 * hertz, JOINT_DAMPING_RATIO, h)
        ctx[PUSH_SPEED] = v["contact_push_speed"]
        ctx[RESTITUTION_THRESHOLD] = v["restitution_threshold"]
        ctx[SPECULATIVE] = v["speculative_distance"]
        ctx[[SLEEPING, TIME_TO_SLEEP, SLEEP_SPEED]] = (
            float(v["sleeping"]),
            v["time_to_sleep"],
            v["sleep_speed"],
        )
        ctx[DAMAGE_SPEED] = v["damage_speed"]
        ctx[RESTITUTION_RULE] = MIXING_RULES.index(v["restitution_mixing"])
        ctx[FRICTION_RULE] = MIXING_RULES.index(v["friction_mixing"])
        ctx[COLOUR_FROM] = colouring.COLOUR_FROM_POINTS  # read here: a test may set it
        self._context = (dt, ctx)
        return ctx
