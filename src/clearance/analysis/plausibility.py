"""Plausibility of a finished run: results a solver can produce but physics cannot.

An integration that reaches its final time can still describe an impossible motion: a
contact law far too soft lets the ball sink through the socket wall (Hertz K = 1 N/m^1.5 on
the default scenario: 26 mm of penetration in a 0.3 mm clearance), a step too coarse breaks
the energy balance. `plausibility(result)` checks, per clearance joint and for the run:

* penetration deeper than PENETRATION_IMPLAUSIBLE x the radial clearance (the axial one
  when the deepest point is on a thrust face of a revolute joint), or deeper than
  RADIUS_IMPLAUSIBLE x the inner radius (ball, journal, slider half width): implausible
  (the ball is beyond its socket; contact laws hold for deformations small against both);
  deeper than PENETRATION_WARNING x the clearance: a warning (check the stiffness);
* the energy residual (physics.md j) above ENERGY_IMPLAUSIBLE x the energy scale:
  implausible; above ENERGY_WARNING: a warning;
* a clearance joint that never touches: a warning (the clearance had no effect).

All thresholds are PROPOSED defaults (the default scenario reaches 0.014 c of
penetration and a residual of 3e-9 of the energy scale); pass others as arguments.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "ENERGY_IMPLAUSIBLE",
    "ENERGY_WARNING",
    "PENETRATION_IMPLAUSIBLE",
    "PENETRATION_WARNING",
    "RADIUS_IMPLAUSIBLE",
    "Plausibility",
    "plausibility",
]

PENETRATION_IMPLAUSIBLE = 1.0  # x radial clearance; PROPOSED
PENETRATION_WARNING = 0.2  # x radial clearance; PROPOSED
RADIUS_IMPLAUSIBLE = 0.1  # x inner radius; PROPOSED
ENERGY_IMPLAUSIBLE = 1e-1  # x energy scale; PROPOSED
ENERGY_WARNING = 1e-3  # x energy scale; PROPOSED

OK, WARNING, IMPLAUSIBLE = "ok", "warning", "implausible"


@dataclass
class Plausibility:
    """`status`: "ok", "warning" or "implausible"; `findings`: one sentence each."""

    status: str = OK
    findings: list[str] = field(default_factory=list)

    def add(self, status: str, text: str) -> None:
        self.findings.append(text)
        if status == IMPLAUSIBLE or self.status == OK:
            self.status = status

    def as_dict(self) -> dict:
        return {"status": self.status, "findings": list(self.findings)}


def plausibility(
    result,
    *,
    penetration_implausible: float = PENETRATION_IMPLAUSIBLE,
    penetration_warning: float = PENETRATION_WARNING,
    radius_implausible: float = RADIUS_IMPLAUSIBLE,
    energy_implausible: float = ENERGY_IMPLAUSIBLE,
    energy_warning: float = ENERGY_WARNING,
) -> Plausibility:
    """The checks of the module docstring on a `Result` (any run; an ideal one has only
    the energy check)."""
    out = Plausibility()
    infos = list(result.compiled.clearances)
    for name, info in zip(result.clearance_names, infos, strict=True):
        depth = max(0.0, float(result.peak_penetration(name)[0]))
        c, r = float(info.c), float(info.ball_radius)
        gap = "the clearance c"
        if _deepest_at_a_thrust_face(result, name):  # measured against the axial gap
            c, gap = _axial_clearance(result, name) or c, "the axial clearance c_a"
        um = f"{depth * 1e6:.4g} um"
        if depth > penetration_implausible * c or depth > radius_implausible * r:
            than = (
                f"{depth / c:.3g} times {gap} = {c * 1e6:.4g} um"
                if depth > penetration_implausible * c
                else f"{depth / r:.3g} of the inner radius {r * 1e3:.4g} mm"
            )
            out.add(
                IMPLAUSIBLE,
                f"{name}: penetration {um} into the outer part's wall, {than}: far beyond "
                "any elastic contact (is the contact stiffness too small, or the step too "
                "large?)",
            )
        elif depth > penetration_warning * c:
            out.add(
                WARNING,
                f"{name}: penetration {um} is {depth / c:.2g} of {gap}; contact "
                "laws assume deformations small against it (check the stiffness)",
            )
        if result.t.size and not len(result.impacts(name)) and depth <= 0.0:
            out.add(WARNING, f"{name}: never in contact (the clearance had no effect)")
    if result.t.size:
        e = result.energy
        scale = float(np.max(np.abs(e["kinetic"]) + np.abs(e["potential"])))
        rel = float(np.max(np.abs(e["residual"]))) / max(scale, 1e-300)
        if rel > energy_implausible:
            out.add(
                IMPLAUSIBLE,
                f"energy balance off by {rel:.2g} of the energy scale (the integration "
                "is not resolving the motion: lower rtol or max_step)",
            )
        elif rel > energy_warning:
            out.add(WARNING, f"energy balance off by {rel:.2g} of the energy scale")
    return out


def _deepest_at_a_thrust_face(result, name: str) -> bool:
    """Whether the deepest sampled penetration of joint `name` is at one of its thrust
    points (a revolute joint's collars against the bearing's end faces), whose gap is the
    axial clearance, not the radial one."""
    if not hasattr(result, "points"):  # (a stand-in without contact points)
        return False
    kinds = {p.name: p.kind for p in result.compiled.contact_points}
    best, thrust = 0.0, False
    for p in result.points(name):
        d = result.channel("point_penetration", p)
        m = float(np.max(d)) if d.size else 0.0
        if m > best:
            best, thrust = m, kinds.get(p) == "thrust_point"
    return thrust


def _axial_clearance(result, name: str) -> float | None:
    joint = result.compiled.mechanism.joints.get(name)
    return getattr(getattr(joint, "clearance", None), "axial_clearance", None)
