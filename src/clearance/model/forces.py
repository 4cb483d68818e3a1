"""Applied forces and torques (constant or time functions) and spring-dampers.

Gravity is a field of the mechanism. Forces act at marker points; `frame="world"` keeps the
direction fixed in the world, `frame="marker"` makes it follow the marker triad.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from clearance.kinds import ForceType
from clearance.model.errors import ModelError
from clearance.model.functions import TimeFunction, as_function


def _dir(who: str, field: str, v: object) -> tuple:
    a = np.asarray(v, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ModelError(who, field, v, "expected 3 finite numbers")
    return tuple(float(x) for x in a)


def _frame(who: str, frame: object) -> str:
    if frame not in ("world", "marker"):
        raise ModelError(who, "frame", frame, "allowed: 'world' or 'marker'")
    return str(frame)


@dataclass(frozen=True)
class PointForce:
    """Force `direction * magnitude(t)` [N] at a marker point."""

    name: str
    marker: str
    direction: tuple
    magnitude: TimeFunction = 1.0  # type: ignore[assignment]
    frame: str = "world"

    kind = ForceType.POINT_FORCE

    def __post_init__(self) -> None:
        who = f"PointForce '{self.name}'"
        object.__setattr__(self, "direction", _dir(who, "direction", self.direction))
        object.__setattr__(
            self, "magnitude", as_function(self.magnitude, owner=who, field="magnitude")
        )
        object.__setattr__(self, "frame", _frame(who, self.frame))


@dataclass(frozen=True)
class Torque:
    """Pure torque `axis * magnitude(t)` [N m] on the body of a marker."""

    name: str
    marker: str
    axis: tuple
    magnitude: TimeFunction = 1.0  # type: ignore[assignment]
    frame: str = "world"

    kind = ForceType.TORQUE

    def __post_init__(self) -> None:
        who = f"Torque '{self.name}'"
        object.__setattr__(self, "axis", _dir(who, "axis", self.axis))
        object.__setattr__(
            self, "magnitude", as_function(self.magnitude, owner=who, field="magnitude")
        )
        object.__setattr__(self, "frame", _frame(who, self.frame))


@dataclass(frozen=True)
class SpringDamper:
    """Translational spring-damper-actuator between two marker points.

    Tension T = stiffness (l - free_length) + damping l_dot + actuator(t) [N], l = |d|; a
    positive T pulls the points together. The elastic part is conservative (its energy is in
    V); damping and actuator power go to the applied work W_a.
    """

    name: str
    marker_i: str
    marker_j: str
    stiffness: float = 0.0
    damping: float = 0.0
    free_length: float = 0.0
    actuator: TimeFunction = 0.0  # type: ignore[assignment]

    kind = ForceType.SPRING_DAMPER

    def __post_init__(self) -> None:
        who = f"SpringDamper '{self.name}'"
        for f in ("stiffness", "damping", "free_length"):
            v = getattr(self, f)
            try:
                x = float(v)
            except (TypeError, ValueError):
                raise ModelError(who, f, v, "expected a number >= 0") from None
            if not np.isfinite(x) or x < 0:
                raise ModelError(who, f, v, "expected a finite number >= 0")
            object.__setattr__(self, f, x)
        object.__setattr__(
            self, "actuator", as_function(self.actuator, owner=who, field="actuator")
        )


Force = PointForce | Torque | SpringDamper
