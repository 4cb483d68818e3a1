"""`Clearance`: turns a spherical joint into a ball-in-socket force element (physics.md f).

    Spherical("S1", "platform_B1", "leg1_B", clearance=Clearance(ball_radius=0.015,
              radial_clearance=0.3e-3, normal=Flores(restitution=0.9), friction=LuGre()))

The joint's three constraint rows are removed and the contact force element is added: the
ball (centre = one marker's point) moves freely inside the socket (centre = the other
marker's point) until they touch. `socket` says which marker's body holds the socket.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from clearance.model.contact_laws import (
    FRICTION_LAWS,
    NORMAL_LAWS,
    STEEL,
    Flores,
    FrictionContactLaw,
    Material,
    NoFriction,
    NormalContactLaw,
)
from clearance.model.errors import ModelError


def _pos(who: str, field: str, v: object, *, allow_zero: bool = False) -> float:
    try:
        x = float(v)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ModelError(who, field, v, "expected a positive number") from None
    if not np.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        raise ModelError(who, field, v, "expected a finite number > 0")
    return x


@dataclass(frozen=True)
class Clearance:
    """Spherical clearance joint parameters.

    ball_radius R_b [m]; give either socket_radius R_s [m] or radial_clearance c = R_s - R_b
    [m] (> 0). socket: "i" or "j", the marker whose body holds the socket (default "i").
    normal: normal contact law; friction: friction law (see clearance.model.contact_laws).
    ball_material / socket_material: used when a law's stiffness is computed from materials.
    velocity_floor: floor of the impact velocity delta_dot_minus captured at onset [m/s]
    (physics.md f.5, PROPOSED 1e-4). onset_tolerance: the contact onset is localised so that
    the penetration at the recorded onset is below onset_tolerance * c.
    """

    ball_radius: float
    socket_radius: float | None = None
    radial_clearance: float | None = None
    socket: str = "i"
    normal: object = Flores()
    friction: object = NoFriction()
    ball_material: Material = STEEL
    socket_material: Material = STEEL
    velocity_floor: float = 1e-4
    onset_tolerance: float = 1e-3
    # which of socket_radius / radial_clearance the user gave (files write that one back)
    given: str = field(default="radial_clearance", init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        who = "Clearance"
        rb = _pos(who, "ball_radius", self.ball_radius)
        if (self.socket_radius is None) == (self.radial_clearance is None):
            raise ModelError(
                who,
                "socket_radius",
                self.socket_radius,
                "give exactly one of socket_radius and radial_clearance",
            )
        if self.socket_radius is not None:
            rs = _pos(who, "socket_radius", self.socket_radius)
            if rs <= rb:
                raise ModelError(
                    who,
                    "socket_radius",
                    self.socket_radius,
                    f"must exceed ball_radius = {rb} (clearance > 0)",
                )
            c = rs - rb
        else:
            c = _pos(who, "radial_clearance", self.radial_clearance)  # kept exactly as given
            rs = rb + c
        object.__setattr__(
            self, "given", "socket_radius" if self.radial_clearance is None else "radial_clearance"
        )
        object.__setattr__(self, "ball_radius", rb)
        object.__setattr__(self, "socket_radius", rs)
        object.__setattr__(self, "radial_clearance", c)
        if self.socket not in ("i", "j"):
            raise ModelError(who, "socket", self.socket, "allowed: 'i' or 'j'")
        if not isinstance(self.normal, NormalContactLaw):
            raise ModelError(
                who,
                "normal",
                self.normal,
                f"expected a normal contact law, one of {sorted(NORMAL_LAWS)} "
                "(e.g. Flores(restitution=0.9))",
            )
        if not isinstance(self.friction, FrictionContactLaw):
            raise ModelError(
                who,
                "friction",
                self.friction,
                f"expected a friction law, one of {sorted(FRICTION_LAWS)} (e.g. LuGre())",
            )
        object.__setattr__(self, "velocity_floor", _pos(who, "velocity_floor", self.velocity_floor))
        tol = _pos(who, "onset_tolerance", self.onset_tolerance)
        if tol >= 0.5:
            raise ModelError(who, "onset_tolerance", tol, "expected a fraction < 0.5 of c")
        object.__setattr__(self, "onset_tolerance", tol)

    @property
    def c(self) -> float:
        """Radial clearance R_s - R_b [m]."""
        return float(self.radial_clearance)  # type: ignore[arg-type]
