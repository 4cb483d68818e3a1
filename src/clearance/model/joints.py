"""Ideal joints between two markers (physics.md c.3).

Each joint names a marker on body i and a marker on body j; the markers coincide at assembly.
Rows (Newton-Euler velocity form): Spherical 3, Universal 4, Revolute 5, Cylindrical 4,
Prismatic 5, Fixed 6. Axis conventions (marker triad columns f, g, h):

- Universal: h_i is the U axis on body i, h_j the cross axis on body j (h_i . h_j = 0).
- Revolute: the rotation axis is h_i = h_j.
- Cylindrical / Prismatic: the sliding axis is h_i = h_j; Prismatic also locks rotation
  about it (f_i . g_j = 0).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from clearance.kinds import JOINT_ROWS, JointType
from clearance.model.clearance import Clearance
from clearance.model.errors import ModelError


@dataclass(frozen=True)
class Joint:
    """Base class: an ideal joint between `marker_i` and `marker_j` (marker names)."""

    name: str
    marker_i: str
    marker_j: str

    kind: ClassVar[JointType]

    def __post_init__(self) -> None:
        who = f"{type(self).__name__} '{self.name}'"
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(type(self).__name__, "name", self.name, "expected a non-empty string")
        for f in ("marker_i", "marker_j"):
            v = getattr(self, f)
            if not isinstance(v, str) or not v:
                raise ModelError(who, f, v, "expected a marker name")
        if self.marker_i == self.marker_j:
            raise ModelError(who, "marker_j", self.marker_j, "must differ from marker_i")

    @property
    def nrows(self) -> int:
        return JOINT_ROWS[self.kind]


@dataclass(frozen=True)
class Spherical(Joint):
    """Ball joint: marker points coincide (3 rows).

    With `clearance=Clearance(...)` the three rows are removed and a ball-in-socket contact
    force element acts instead (physics.md f); see `clearance.model.clearance.Clearance`.
    """

    clearance: object = None

    kind: ClassVar[JointType] = JointType.SPHERICAL

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.clearance is not None and not isinstance(self.clearance, Clearance):
            raise ModelError(
                f"Spherical '{self.name}'",
                "clearance",
                self.clearance,
                "expected a Clearance(...) or None",
            )

    @property
    def nrows(self) -> int:
        return 0 if self.clearance is not None else 3


@dataclass(frozen=True)
class Universal(Joint):
    """Cardan joint: spherical + h_i perpendicular to h_j (4 rows)."""

    kind: ClassVar[JointType] = JointType.UNIVERSAL


@dataclass(frozen=True)
class Revolute(Joint):
    """Hinge about h_i = h_j (5 rows)."""

    kind: ClassVar[JointType] = JointType.REVOLUTE


@dataclass(frozen=True)
class Cylindrical(Joint):
    """Slides along and rotates about h_i = h_j (4 rows)."""

    kind: ClassVar[JointType] = JointType.CYLINDRICAL


@dataclass(frozen=True)
class Prismatic(Joint):
    """Slides along h_i = h_j, no relative rotation (5 rows)."""

    kind: ClassVar[JointType] = JointType.PRISMATIC


@dataclass(frozen=True)
class Fixed(Joint):
    """Rigid connection: markers coincide and triads align (6 rows)."""

    kind: ClassVar[JointType] = JointType.FIXED
