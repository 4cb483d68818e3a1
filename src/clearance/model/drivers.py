"""Drivers: rheonomic constraints that prescribe a motion (physics.md c.3, e.2).

Every driver is one or more constraint rows `g(q) - f(t) = 0`. Its multiplier gives the
actuator force or torque; signs are documented on each class (Q_c = -phi_q^T lam).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clearance.kinds import DriverType
from clearance.model.errors import ModelError
from clearance.model.functions import TimeFunction, as_function


def _name(cls: str, name: object) -> str:
    if not isinstance(name, str) or not name:
        raise ModelError(cls, "name", name, "expected a non-empty string")
    return f"{cls} '{name}'"


@dataclass(frozen=True)
class _JointDriver:
    """A joint coordinate driven by a time function: one row (the subclasses say which)."""

    name: str
    joint: str
    function: TimeFunction

    def __post_init__(self) -> None:
        who = _name(type(self).__name__, self.name)
        if not isinstance(self.joint, str) or not self.joint:
            raise ModelError(who, "joint", self.joint, "expected a joint name")
        object.__setattr__(self, "function", as_function(self.function, owner=who))

    @property
    def nrows(self) -> int:
        return 1


@dataclass(frozen=True)
class PrismaticDriver(_JointDriver):
    """Relative displacement s(t) along the axis of a prismatic or cylindrical joint.

    phi = h_i . d - s(t), d from the joint's marker point on i to its point on j. The
    actuator force reported is F_act = -lam: positive when the actuator pushes body j along
    +h_i (extends the joint).
    """

    kind = DriverType.PRISMATIC


@dataclass(frozen=True)
class DistanceDriver:
    """Distance l(t) between the points of two markers.

    Length form (default) phi = |d| - l(t): the reported actuator force F_act = -lam pushes
    the points apart when positive. squared=True uses phi = d.d - l^2 (lam scaled by 1/(2l);
    the reported force is still the pushing force).
    """

    name: str
    marker_i: str
    marker_j: str
    function: TimeFunction
    squared: bool = False

    kind = DriverType.DISTANCE

    def __post_init__(self) -> None:
        who = _name("DistanceDriver", self.name)
        for f in ("marker_i", "marker_j"):
            v = getattr(self, f)
            if not isinstance(v, str) or not v:
                raise ModelError(who, f, v, "expected a marker name")
        object.__setattr__(self, "function", as_function(self.function, owner=who))
        object.__setattr__(self, "squared", bool(self.squared))

    @property
    def nrows(self) -> int:
        return 1


@dataclass(frozen=True)
class PositionDriver:
    """World coordinate of a marker point along a fixed unit axis: c . r_P - f(t) = 0.

    F_act = -lam is the force applied to the body along +axis to impose the motion.
    """

    name: str
    marker: str
    axis: tuple
    function: TimeFunction

    kind = DriverType.POSITION

    def __post_init__(self) -> None:
        who = _name("PositionDriver", self.name)
        if not isinstance(self.marker, str) or not self.marker:
            raise ModelError(who, "marker", self.marker, "expected a marker name")
        a = np.asarray(self.axis, dtype=float)
        if a.shape != (3,) or not np.all(np.isfinite(a)) or np.linalg.norm(a) == 0:
            raise ModelError(who, "axis", self.axis, "expected a non-zero 3-vector")
        a = a / np.linalg.norm(a)
        object.__setattr__(self, "axis", tuple(float(x) for x in a))
        object.__setattr__(self, "function", as_function(self.function, owner=who))

    @property
    def nrows(self) -> int:
        return 1


@dataclass(frozen=True)
class OffsetDriver:
    """Displacement of marker j's point along marker i's h axis: h_i . (P_j - P_i) - f(t).

    The prismatic driver's row without a joint: e.g. to place a ball at a chosen offset in its
    socket during assembly. F_act = -lam is the force on body j along +h_i.
    """

    name: str
    marker_i: str
    marker_j: str
    function: TimeFunction

    kind = DriverType.OFFSET

    def __post_init__(self) -> None:
        who = _name("OffsetDriver", self.name)
        for f in ("marker_i", "marker_j"):
            v = getattr(self, f)
            if not isinstance(v, str) or not v:
                raise ModelError(who, f, v, "expected a marker name")
        object.__setattr__(self, "function", as_function(self.function, owner=who))

    @property
    def nrows(self) -> int:
        return 1


_SEQ = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class OrientationDriver:
    """Orientation of a marker triad prescribed by three angle functions.

    Target R(t) = R_a(t1) R_b(t2) R_c(t3) for sequence "abc" (successive rotations about the
    moving axes, e.g. "xyz" = Rx Ry Rz). mode="full" makes the marker triad equal R(t)
    (3 rows: f.R ey = 0, g.R ez = 0, h.R ex = 0); mode="axis" prescribes only the marker's h
    axis to be R(t) ez (2 rows, rotation about h left free: the two-tilt driver of
    physics.md e.2). The reference frame is the ground. Rows are dot-1 products with
    moving ground vectors; the multipliers are the imposing torques' components.
    """

    name: str
    marker: str
    angles: tuple
    sequence: str = "xyz"
    mode: str = "full"

    kind = DriverType.ORIENTATION

    def __post_init__(self) -> None:
        who = _name("OrientationDriver", self.name)
        if not isinstance(self.marker, str) or not self.marker:
            raise ModelError(who, "marker", self.marker, "expected a marker name")
        if (
            not isinstance(self.sequence, str)
            or len(self.sequence) != 3
            or any(c not in _SEQ for c in self.sequence)
        ):
            raise ModelError(
                who,
                "sequence",
                self.sequence,
                "expected three axis letters from 'x', 'y', 'z', e.g. 'xyz'",
            )
        if self.mode not in ("full", "axis"):
            raise ModelError(who, "mode", self.mode, "allowed: 'full' or 'axis'")
        try:
            angles = tuple(self.angles)
        except TypeError:
            raise ModelError(who, "angles", self.angles, "expected three functions") from None
        if len(angles) != 3:
            raise ModelError(who, "angles", self.angles, "expected three functions (or numbers)")
        object.__setattr__(
            self, "angles", tuple(as_function(a, owner=who, field="angles") for a in angles)
        )

    @property
    def axes(self) -> tuple[int, int, int]:
        return tuple(_SEQ[c] for c in self.sequence)  # type: ignore[return-value]

    @property
    def nrows(self) -> int:
        return 3 if self.mode == "full" else 2


@dataclass(frozen=True)
class RevoluteDriver(_JointDriver):
    """Rotation angle theta(t) [rad] of a revolute (or cylindrical) joint: the angle from
    f_i to f_j about h_i (right hand), marker i on the ground (a base-mounted motor: the
    cranks of a Delta robot, an RUS or RSS leg).

    One row: f_j . c(t) = 0 with the ground vector c(t) = T_i Rz(theta(t)) e_y, T_i the
    triad of marker i (a moving dot-1 row, physics.md c.2, as the orientation driver's), so
    f_j = T_i Rz(theta) e_x on the solution. Its Jacobian there is h_i (rotation of body j
    about h_i), so F_act = -lam is the motor torque [N m] on body j about +h_i: positive
    when it drives theta forward.
    """

    kind = DriverType.REVOLUTE


def zxz_angles(T: object) -> tuple[float, float, float]:
    """(psi, phi, chi) [rad] with T = Rz(psi) Rx(phi) Rz(chi) (rotations about moving axes);
    phi in [0, pi]; psi = 0 where phi is 0 or pi (the decomposition is not unique there)."""
    R = np.asarray(T, dtype=float)
    s = math.hypot(R[0, 2], R[1, 2])
    phi = math.atan2(s, R[2, 2])
    if s > 1e-12:
        return math.atan2(R[0, 2], -R[1, 2]), phi, math.atan2(R[2, 0], R[2, 1])
    if R[2, 2] > 0.0:  # Rz(chi)
        return 0.0, 0.0, math.atan2(R[1, 0], R[0, 0])
    return 0.0, math.pi, -math.atan2(R[1, 0], R[0, 0])  # Rx(pi) Rz(chi) = Rz(-chi) Rx(pi)


Driver = (
    PrismaticDriver
    | DistanceDriver
    | PositionDriver
    | OrientationDriver
    | OffsetDriver
    | RevoluteDriver
)
