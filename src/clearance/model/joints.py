"""Joints between two markers (physics.md c.3), ideal or with clearance.

Each joint names a marker on body i and a marker on body j; the markers coincide at assembly.
Rows (Newton-Euler velocity form): Spherical 3, Universal 4, Revolute 5, Cylindrical 4,
Prismatic 5, Fixed 6. Axis conventions (marker triad columns f, g, h):

- Universal: h_i is the U axis on body i, h_j the cross axis on body j (h_i . h_j = 0).
- Revolute: the rotation axis is h_i = h_j.
- Cylindrical / Prismatic: the sliding axis is h_i = h_j; Prismatic also locks rotation
  about it (f_i . g_j = 0).

Spherical, Revolute, Cylindrical and Prismatic joints take `clearance=` (a clearance of
their kind, `clearance.model.clearance`): the rows the clearance frees are removed and its
contact force element acts instead.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from clearance.kinds import JOINT_ROWS, JointType
from clearance.model.clearance import CLEARANCE_TYPES, RevoluteClearance
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
        clr = getattr(self, "clearance", None)
        return JOINT_ROWS[self.kind] if clr is None else clr.kept_rows(self.kind)

    def _check_clearance(self) -> None:
        """A clearance of a kind that fits this joint, or None."""
        clr = getattr(self, "clearance", None)
        if clr is None:
            return
        fits = [c.__name__ for c in CLEARANCE_TYPES if self.kind in c.joints]
        if not isinstance(clr, CLEARANCE_TYPES) or self.kind not in clr.joints:
            raise ModelError(
                f"{type(self).__name__} '{self.name}'",
                "clearance",
                clr,
                f"expected {' or '.join(fits)}(...) or None",
            )
        if self.kind == JointType.CYLINDRICAL and isinstance(clr, RevoluteClearance):
            if clr.axial_clearance is not None:
                raise ModelError(
                    f"Cylindrical '{self.name}'",
                    "clearance.axial_clearance",
                    clr.axial_clearance,
                    "a cylindrical joint slides freely along its axis: no thrust faces",
                )


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
        self._check_clearance()


@dataclass(frozen=True)
class Universal(Joint):
    """Cardan joint: spherical + h_i perpendicular to h_j (4 rows)."""

    kind: ClassVar[JointType] = JointType.UNIVERSAL


@dataclass(frozen=True)
class Revolute(Joint):
    """Hinge about h_i = h_j (5 rows); clearance: a RevoluteClearance (journal in bearing)."""

    clearance: object = None

    kind: ClassVar[JointType] = JointType.REVOLUTE

    def __post_init__(self) -> None:
        super().__post_init__()
        self._check_clearance()


@dataclass(frozen=True)
class Cylindrical(Joint):
    """Slides along and rotates about h_i = h_j (4 rows); clearance: a RevoluteClearance
    without axial clearance (journal sliding in a bearing)."""

    clearance: object = None

    kind: ClassVar[JointType] = JointType.CYLINDRICAL

    def __post_init__(self) -> None:
        super().__post_init__()
        self._check_clearance()


@dataclass(frozen=True)
class Prismatic(Joint):
    """Slides along h_i = h_j, no relative rotation (5 rows); clearance: a
    PrismaticClearance (slider in guide)."""

    clearance: object = None

    kind: ClassVar[JointType] = JointType.PRISMATIC

    def __post_init__(self) -> None:
        super().__post_init__()
        self._check_clearance()


@dataclass(frozen=True)
class Fixed(Joint):
    """Rigid connection: markers coincide and triads align (6 rows)."""

    kind: ClassVar[JointType] = JointType.FIXED
