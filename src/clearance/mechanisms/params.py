"""Validated parameter sets of the seed mechanisms (frozen dataclasses with documented fields).

A parameter set is a frozen dataclass whose fields carry their meaning in the field
metadata (`param(default, kind, unit, doc, status)`): the kind of value (a positive number,
a 3-vector, an inertia diagonal, four hinge angles, a choice), its unit, a one-line
description and the status label of its value in mechanisms.md (PROPOSED, DERIVED, ...).
Every field is checked on construction (`ModelError` naming the set, the field, the value
and what is allowed), so the mechanism factories, the scenario files and `clearance check`
share one set of rules:

    p = UpsUpuParams(R_A=0.45)                    # the other fields keep their defaults
    p = UpsUpuParams.from_mapping({"R_A": 0.45})  # unknown keys raise ModelError
    UpsUpuParams.check_field("swing_mass", -1.0)  # raises ModelError (one field alone)

`SpsCuParams` (mechanisms.md 2.3) lives here until the 4-SPS/CU factory exists; it is
validated by the scenario files already.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from clearance.model.errors import ModelError
from clearance.model.values import KINDS, check_value

__all__ = [
    "BASE_ANGLES_DEG",
    "DISC_INERTIA",
    "KINDS",
    "PLATFORM_ANGLES_DEG",
    "ParamSet",
    "SpsCuParams",
    "check_value",
    "param",
]


def param(
    default: object,
    kind: str,
    unit: str,
    doc: str,
    status: str = "PROPOSED",
    *,
    choices: tuple[str, ...] = (),
) -> Any:
    """A dataclass field with its kind, unit [SI], description and mechanisms.md status."""
    if kind not in KINDS and kind != "choice":
        raise ValueError(f"unknown parameter kind {kind!r}")
    meta = {"kind": kind, "unit": unit, "doc": doc, "status": status, "choices": choices}
    return dataclasses.field(default=default, metadata=meta)


class ParamSet:
    """Mixin of the frozen parameter dataclasses: per-field checks, cross checks, mapping."""

    OWNER: ClassVar[str] = "parameters"

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            v = type(self).check_field(f.name, getattr(self, f.name))
            object.__setattr__(self, f.name, v)
        self._check_cross()

    def _check_cross(self) -> None:
        """Checks that involve more than one field (override; raise ModelError)."""

    @classmethod
    def spec(cls) -> dict[str, dataclasses.Field]:
        """Field name -> dataclass field (metadata: kind, unit, doc, status, choices)."""
        return {f.name: f for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def check_field(cls, name: str, value: object) -> object:
        """Validate one field alone (no cross checks); unknown names raise ModelError."""
        spec = cls.spec()
        if name not in spec:
            raise ModelError(cls.OWNER, name, value, f"unknown parameter; allowed: {list(spec)}")
        m = spec[name].metadata
        try:
            return check_value(cls.OWNER, name, m["kind"], value, m["choices"])
        except ModelError as e:
            if not m["unit"]:
                raise
            raise ModelError(cls.OWNER, name, value, f"{e.allowed} [{m['unit']}]") from None

    @classmethod
    def from_mapping(cls, values: Mapping[str, object] | None = None) -> Any:
        """The defaults with `values` (name -> value) merged over them, validated."""
        values = dict(values or {})
        spec = cls.spec()
        for k, v in values.items():
            if k not in spec:
                raise ModelError(cls.OWNER, k, v, f"unknown parameter; allowed: {list(spec)}")
        return cls(**values)

    def to_dict(self) -> dict[str, object]:
        """name -> value (tuples for vectors)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}  # type: ignore[arg-type]


def _check_com(owner: str, p: object, com: str, length: str) -> None:
    c, L = getattr(p, com), getattr(p, length)
    if not c < L:
        raise ModelError(owner, com, c, f"the mass centre must lie on the rod: < {length} = {L} m")


BASE_ANGLES_DEG = (45.0, 135.0, 225.0, 315.0)
# Platform angle = base angle + 30 deg (legs 1, 2) and - 30 deg (legs 3, 4): breaks the
# central symmetry that makes the layout singular (mechanisms.md 1.4 singularity note).
PLATFORM_ANGLES_DEG = (75.0, 165.0, 195.0, 285.0)
# Thin disc m = 10 kg, r = 0.25 m: m r^2/4, m r^2/2. mechanisms.md rounds 0.15625 to 0.156,
# which violates I1 + I2 >= I3 (0.312 < 0.3125) and is rejected by Body; use the exact values.
DISC_INERTIA = (0.15625, 0.15625, 0.3125)


@dataclass(frozen=True)
class SpsCuParams(ParamSet):
    """4-SPS/CU parameter set (mechanisms.md 2.2-2.3; PROPOSED reconstruction of Paper A).

    Four S-P-S limbs between base points A_k = R_A (cos theta_k, sin theta_k, 0) and platform
    points B_k = R_B (cos phi_k, sin phi_k, 0) (platform frame, origin at the platform
    centre = U centre); a central C-U column. Each driving limb is a cylinder (from the base
    S) and a piston (from the platform S), lumped into one body (physics.md i) when
    limb_model = "lumped", two bodies with a prismatic joint when "two-body".
    """

    OWNER: ClassVar[str] = "4sps-cu parameters"

    R_A: float = param(0.40, "positive", "m", "base hinge circle radius")
    R_B: float = param(0.20, "positive", "m", "platform hinge circle radius")
    theta_deg: tuple = param(BASE_ANGLES_DEG, "angles4", "deg", "base hinge angles, limbs 1-4")
    phi_deg: tuple = param(
        PLATFORM_ANGLES_DEG, "angles4", "deg", "platform hinge angles, limbs 1-4 (non-singular)"
    )
    home_height: float = param(0.60, "positive", "m", "platform centre (U centre) height at home")
    cylinder_mass: float = param(2.0, "positive", "kg", "cylinder mass m1")
    cylinder_com: float = param(0.20, "positive", "m", "cylinder mass centre from the base S, a1")
    cylinder_inertia: tuple = param(
        (0.028, 0.028, 0.001), "inertia3", "kg m^2", "cylinder inertia J1 (axis = body z)"
    )
    piston_mass: float = param(1.5, "positive", "kg", "piston mass m2")
    piston_com: float = param(0.20, "positive", "m", "piston mass centre from the platform S, a2")
    piston_inertia: tuple = param(
        (0.021, 0.021, 0.0005), "inertia3", "kg m^2", "piston inertia J2 (axis = body z)"
    )
    column_mass: float = param(2.0, "positive", "kg", "central column mass")
    column_length: float = param(0.8, "positive", "m", "central column length")
    column_top: float = param(
        0.4, "positive", "m", "U centre above the column mass centre (mass centre mid-length)"
    )
    column_inertia: tuple = param(
        (0.1067, 0.1067, 0.001), "inertia3", "kg m^2", "column inertia (axis = body z)"
    )
    platform_mass: float = param(10.0, "positive", "kg", "platform mass (disc r = 0.25 m)")
    platform_inertia: tuple = param(
        DISC_INERTIA, "inertia3", "kg m^2", "platform inertia about its centre (disc r = 0.25 m)"
    )
    gravity: tuple = param((0.0, 0.0, -9.81), "vector3", "m/s^2", "gravity, world frame")
    limb_model: str = param(
        "lumped",
        "choice",
        "",
        "driving limbs: one lumped body (mass-moment method) or cylinder + piston",
        choices=("lumped", "two-body"),
    )

    def _check_cross(self) -> None:
        # the column's mass centre is at mid-length: the U centre is at most at its top end
        half = 0.5 * self.column_length
        if not self.column_top <= half * (1.0 + 1e-12):
            raise ModelError(
                self.OWNER,
                "column_top",
                self.column_top,
                f"the U centre must lie on the column: <= column_length / 2 = {half} m "
                "(mass centre at mid-length)",
            )
