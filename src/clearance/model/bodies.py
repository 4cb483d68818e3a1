"""Rigid bodies and markers.

`Body` holds mass, inertia about the mass centre in body components, and the initial pose and
velocity. `Marker` is a point and an orthonormal triad (f, g, h) fixed on a body; joints see
markers, never bodies (EXUDYN style). The ground is the reserved body name ``"ground"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clearance.model.errors import ModelError
from clearance.model.functions import TimeFunction, as_function

GROUND = "ground"

_ORTHO_TOL = 1e-9


def _vec3(owner: str, name: str, value: object) -> tuple[float, float, float]:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(owner, name, value, "expected 3 real numbers") from None
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ModelError(owner, name, value, "expected 3 finite real numbers")
    return (float(a[0]), float(a[1]), float(a[2]))


def _mat3(owner: str, name: str, value: object) -> tuple[tuple[float, ...], ...]:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(owner, name, value, "expected a 3x3 real matrix") from None
    if a.shape != (3, 3) or not np.all(np.isfinite(a)):
        raise ModelError(owner, name, value, "expected a 3x3 matrix of finite numbers")
    return tuple(tuple(float(x) for x in row) for row in a)


def rotation_to_quaternion(R: np.ndarray) -> np.ndarray:
    """Euler parameters [e0, e1, e2, e3] (e0 >= 0) of a proper rotation matrix (Shepperd)."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R)
    cands = np.array([tr, R[0, 0], R[1, 1], R[2, 2]])
    k = int(np.argmax(cands))
    if k == 0:
        e0 = 0.5 * math.sqrt(max(1.0 + tr, 0.0))
        p = [
            e0,
            (R[2, 1] - R[1, 2]) / (4 * e0),
            (R[0, 2] - R[2, 0]) / (4 * e0),
            (R[1, 0] - R[0, 1]) / (4 * e0),
        ]
    elif k == 1:
        e1 = 0.5 * math.sqrt(max(1.0 + 2 * R[0, 0] - tr, 0.0))
        p = [
            (R[2, 1] - R[1, 2]) / (4 * e1),
            e1,
            (R[0, 1] + R[1, 0]) / (4 * e1),
            (R[0, 2] + R[2, 0]) / (4 * e1),
        ]
    elif k == 2:
        e2 = 0.5 * math.sqrt(max(1.0 + 2 * R[1, 1] - tr, 0.0))
        p = [
            (R[0, 2] - R[2, 0]) / (4 * e2),
            (R[0, 1] + R[1, 0]) / (4 * e2),
            e2,
            (R[1, 2] + R[2, 1]) / (4 * e2),
        ]
    else:
        e3 = 0.5 * math.sqrt(max(1.0 + 2 * R[2, 2] - tr, 0.0))
        p = [
            (R[1, 0] - R[0, 1]) / (4 * e3),
            (R[0, 2] + R[2, 0]) / (4 * e3),
            (R[1, 2] + R[2, 1]) / (4 * e3),
            e3,
        ]
    p = np.array(p)
    if p[0] < 0:
        p = -p
    return p / np.linalg.norm(p)


def quaternion_to_rotation(p: np.ndarray) -> np.ndarray:
    """Rotation matrix A(p), body -> world (physics.md b.1); p is normalised first."""
    p = np.asarray(p, dtype=float)
    p = p / np.linalg.norm(p)
    e0, e = p[0], p[1:]
    et = np.array([[0.0, -e[2], e[1]], [e[2], 0.0, -e[0]], [-e[1], e[0], 0.0]])
    return (e0 * e0 - e @ e) * np.eye(3) + 2.0 * (np.outer(e, e) + e0 * et)


def rotation_matrices(p: np.ndarray) -> np.ndarray:
    """(..., 4) Euler parameters -> (..., 3, 3) rotation matrices (normalised first)."""
    p = p / np.linalg.norm(p, axis=-1, keepdims=True)
    e0, e1, e2, e3 = np.moveaxis(p, -1, 0)
    return (
        np.stack(
            [
                np.stack([e0**2 + e1**2 - 0.5, e1 * e2 - e0 * e3, e1 * e3 + e0 * e2], -1),
                np.stack([e1 * e2 + e0 * e3, e0**2 + e2**2 - 0.5, e2 * e3 - e0 * e1], -1),
                np.stack([e1 * e3 - e0 * e2, e2 * e3 + e0 * e1, e0**2 + e3**2 - 0.5], -1),
            ],
            -2,
        )
        * 2.0
    )


def _orientation(owner: str, value: object) -> tuple[float, float, float, float]:
    """Accept Euler parameters (4,) or a rotation matrix (3,3); return unit Euler parameters."""
    a = np.asarray(value, dtype=float)
    if a.shape == (4,):
        n = float(np.linalg.norm(a))
        if not np.isfinite(n) or abs(n - 1.0) > 1e-6:
            raise ModelError(
                owner,
                "orientation",
                value,
                "Euler parameters must have unit norm (|p| = 1 within 1e-6)",
            )
        a = a / n
        return (float(a[0]), float(a[1]), float(a[2]), float(a[3]))
    if a.shape == (3, 3):
        _check_rotation(owner, "orientation", a)
        return tuple(float(x) for x in rotation_to_quaternion(a))  # type: ignore[return-value]
    raise ModelError(
        owner, "orientation", value, "expected 4 Euler parameters or a 3x3 rotation matrix"
    )


def _check_rotation(owner: str, name: str, a: np.ndarray) -> None:
    err = float(np.max(np.abs(a.T @ a - np.eye(3))))
    if not np.isfinite(err) or err > _ORTHO_TOL * 1e3:
        raise ModelError(
            owner,
            name,
            a.tolist(),
            f"columns must be orthonormal (max |A^T A - I| = {err:.2e} > 1e-6)",
        )
    if np.linalg.det(a) < 0:
        raise ModelError(owner, name, a.tolist(), "must be a right-handed triad (det = +1)")


@dataclass(frozen=True)
class InertiaVariation:
    """Body inertia that changes with a prescribed length (lumped limb, physics.md i).

    J'(t) = J'_0 + diag(moments) (length(t) - offset)^2, body components: for a cylinder and
    piston lumped by the mass-moment method, moments = (m1 m2/m, m1 m2/m, 0) and
    offset = a1 + a2 (parallel-axis theorem). The rate term J'_dot omega' enters the Euler
    equation exactly and its power -1/2 omega'^T J'_dot omega' the energy audit.
    rate_term=False drops J'_dot omega' from the Euler equation (to reproduce models that
    omit it; physics.md i shows the angular momentum of a free limb then drifts).
    """

    moments: tuple
    offset: float
    length: TimeFunction
    rate_term: bool = True

    def __post_init__(self) -> None:
        who = "InertiaVariation"
        k = _vec3(who, "moments", self.moments)
        if min(k) < 0:
            raise ModelError(
                who,
                "moments",
                self.moments,
                "must be >= 0 (the inertia must stay positive definite)",
            )
        object.__setattr__(self, "moments", k)
        try:
            a = float(self.offset)
        except (TypeError, ValueError):
            raise ModelError(who, "offset", self.offset, "expected a number [m]") from None
        object.__setattr__(self, "offset", a)
        object.__setattr__(self, "length", as_function(self.length, owner=who, field="length"))
        object.__setattr__(self, "rate_term", bool(self.rate_term))


@dataclass(frozen=True)
class Body:
    """A rigid body.

    mass: [kg] > 0.  inertia: about the mass centre in body components [kg m^2], either the
    three principal moments (body axes = principal axes) or a full symmetric 3x3 tensor.
    position: (3,) initial mass-centre position, world [m].  orientation: initial Euler
    parameters (4,) or rotation matrix body -> world (3, 3).  velocity: (3,) initial
    mass-centre velocity, world [m/s].  angular_velocity: (3,) initial angular velocity in
    BODY components [rad/s] (physics.md b.2).
    """

    name: str
    mass: float
    inertia: tuple = (1.0, 1.0, 1.0)
    position: tuple = (0.0, 0.0, 0.0)
    orientation: tuple = (1.0, 0.0, 0.0, 0.0)
    velocity: tuple = (0.0, 0.0, 0.0)
    angular_velocity: tuple = (0.0, 0.0, 0.0)
    inertia_variation: InertiaVariation | None = None

    def __post_init__(self) -> None:
        who = f"Body '{self.name}'"
        if not isinstance(self.name, str) or not self.name:
            raise ModelError("Body", "name", self.name, "expected a non-empty string")
        if self.name == GROUND:
            raise ModelError(who, "name", self.name, f"'{GROUND}' is reserved for the ground")
        try:
            m = float(self.mass)
        except (TypeError, ValueError):
            raise ModelError(who, "mass", self.mass, "expected a positive number [kg]") from None
        if not np.isfinite(m) or m <= 0.0:
            raise ModelError(who, "mass", self.mass, "mass must be a finite number > 0 [kg]")
        object.__setattr__(self, "mass", m)
        J = np.asarray(self.inertia, dtype=float)
        if J.shape == (3,):
            J = np.diag(J)
        elif J.shape != (3, 3):
            raise ModelError(
                who,
                "inertia",
                self.inertia,
                "expected 3 principal moments or a symmetric 3x3 tensor [kg m^2]",
            )
        _check_inertia(who, J, self.inertia)
        object.__setattr__(self, "inertia", _mat3(who, "inertia", J))
        object.__setattr__(self, "position", _vec3(who, "position", self.position))
        object.__setattr__(self, "orientation", _orientation(who, self.orientation))
        object.__setattr__(self, "velocity", _vec3(who, "velocity", self.velocity))
        object.__setattr__(
            self, "angular_velocity", _vec3(who, "angular_velocity", self.angular_velocity)
        )
        if self.inertia_variation is not None and not isinstance(
            self.inertia_variation, InertiaVariation
        ):
            raise ModelError(
                who,
                "inertia_variation",
                self.inertia_variation,
                "expected an InertiaVariation or None",
            )

    @property
    def inertia_matrix(self) -> np.ndarray:
        return np.array(self.inertia)

    @property
    def rotation(self) -> np.ndarray:
        return quaternion_to_rotation(np.array(self.orientation))


def _check_inertia(who: str, J: np.ndarray, raw: object) -> None:
    if not np.all(np.isfinite(J)):
        raise ModelError(who, "inertia", raw, "entries must be finite")
    if np.max(np.abs(J - J.T)) > 1e-12 * max(1.0, float(np.max(np.abs(J)))):
        raise ModelError(who, "inertia", raw, "the inertia tensor must be symmetric")
    ev = np.linalg.eigvalsh(J)
    if ev[0] <= 0.0:
        raise ModelError(
            who, "inertia", raw, f"must be positive definite (principal moments {ev.tolist()})"
        )
    # Triangle inequality of principal moments: I1 + I2 >= I3 for every permutation.
    tol = 1e-9 * float(ev.sum())
    if ev[0] + ev[1] < ev[2] - tol:
        raise ModelError(
            who,
            "inertia",
            raw,
            f"principal moments {ev.tolist()} violate the triangle inequality "
            "I1 + I2 >= I3 (no real mass distribution has them)",
        )


def triad_from_axis(h: object, f_hint: object | None = None) -> np.ndarray:
    """Right-handed orthonormal triad [f g h] (columns) with h along `h`.

    f is `f_hint` made perpendicular to h; without a hint, the world axis least parallel to h.
    """
    h = np.asarray(h, dtype=float)
    n = np.linalg.norm(h)
    if not np.isfinite(n) or n == 0.0:
        raise ModelError("triad", "axis", h.tolist(), "expected a non-zero finite vector")
    h = h / n
    if f_hint is None:
        f_hint = np.eye(3)[int(np.argmin(np.abs(h)))]
    f = np.asarray(f_hint, dtype=float)
    f = f - (f @ h) * h
    nf = np.linalg.norm(f)
    if nf < 1e-9:
        raise ModelError(
            "triad", "f_hint", np.asarray(f_hint).tolist(), "must not be parallel to the axis"
        )
    f = f / nf
    g = np.cross(h, f)
    return np.column_stack([f, g, h])


@dataclass(frozen=True)
class Marker:
    """A point and an orthonormal triad fixed on a body.

    body: body name (``"ground"`` for the fixed frame).  position: (3,) point in body
    components, relative to the mass centre [m] (world coordinates for ground).
    orientation: 3x3 matrix whose columns are the triad (f, g, h) in body components; h is
    the joint axis by convention.  Use `Marker.on_axis` to build the triad from an axis.
    slide_axis, slide: a moving attachment point (rheonomic, physics.md c.2 and i): the
    point is position + slide_axis * slide(t) (body components, slide a TimeFunction [m]).
    """

    name: str
    body: str
    position: tuple = (0.0, 0.0, 0.0)
    orientation: tuple = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    slide_axis: tuple | None = None
    slide: TimeFunction | None = None

    def __post_init__(self) -> None:
        who = f"Marker '{self.name}'"
        if (self.slide_axis is None) != (self.slide is None):
            raise ModelError(
                who,
                "slide",
                self.slide,
                "give both slide_axis and slide (a moving attachment) or neither",
            )
        if self.slide_axis is not None:
            ax = np.asarray(_vec3(who, "slide_axis", self.slide_axis))
            if np.linalg.norm(ax) == 0:
                raise ModelError(who, "slide_axis", self.slide_axis, "expected a non-zero vector")
            object.__setattr__(self, "slide_axis", tuple(float(x) for x in ax / np.linalg.norm(ax)))
            object.__setattr__(self, "slide", as_function(self.slide, owner=who, field="slide"))
        if not isinstance(self.name, str) or not self.name:
            raise ModelError("Marker", "name", self.name, "expected a non-empty string")
        if not isinstance(self.body, str) or not self.body:
            raise ModelError(who, "body", self.body, "expected a body name")
        object.__setattr__(self, "position", _vec3(who, "position", self.position))
        a = np.asarray(self.orientation, dtype=float)
        if a.shape != (3, 3):
            raise ModelError(
                who, "orientation", self.orientation, "expected a 3x3 matrix with columns (f, g, h)"
            )
        err = float(np.max(np.abs(a.T @ a - np.eye(3))))
        if not np.isfinite(err) or err > 1e-6:
            raise ModelError(
                who,
                "orientation",
                a.tolist(),
                f"triad must be orthonormal (max |T^T T - I| = {err:.2e} > 1e-6)",
            )
        if np.linalg.det(a) < 0:
            raise ModelError(
                who, "orientation", a.tolist(), "triad must be right-handed (f x g = h)"
            )
        object.__setattr__(self, "orientation", _mat3(who, "orientation", a))

    @classmethod
    def on_axis(
        cls,
        name: str,
        body: str,
        position: object = (0.0, 0.0, 0.0),
        *,
        axis: object = (0.0, 0.0, 1.0),
        f_hint: object | None = None,
    ) -> Marker:
        """Marker whose h axis is `axis` (body components); f follows `f_hint` if given."""
        return cls(name, body, position, triad_from_axis(axis, f_hint))

    @property
    def triad(self) -> np.ndarray:
        return np.array(self.orientation)


__all__ = [
    "GROUND",
    "Body",
    "Marker",
    "triad_from_axis",
    "quaternion_to_rotation",
    "rotation_matrices",
    "rotation_to_quaternion",
]
