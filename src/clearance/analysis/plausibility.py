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
        for where, d, gap, g in _gaps(result, name, depth, c):
            um = f"{d * 1e6:.4g} um"
            if d > penetration_implausible * g or d > radius_implausible * r:
                than = (
                    f"{d / g:.3g} times {gap} = {g * 1e6:.4g} um"
                    if d > penetration_implausible * g
                    else f"{d / r:.3g} of the inner radius {r * 1e3:.4g} mm"
                )
                out.add(
                    IMPLAUSIBLE,
                    f"{name}: penetration {um}{where} into the outer part's wall, {than}: "
                    "far beyond any elastic contact (is the contact stiffness too small, or "
                    "the step too large?)",
                )
            elif d > penetration_warning * g:
                out.add(
                    WARNING,
                    f"{name}: penetration {um}{where} is {d / g:.2g} of {gap}; contact "
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


def _gaps(result, name: str, depth: float, c: float) -> list[tuple[str, float, str, float]]:
    """(where, penetration, gap name, gap) to check for joint `name`: its peak penetration
    (over the steps) against the radial clearance c; for a revolute joint with thrust
    points (collars against the bearing's end faces), the radial and the thrust points
    apart, each against its own gap (the axial clearance c_a for the thrust faces), the
    peak going to the kind whose sampled penetration is deeper."""
    ca = _axial_clearance(result, name) if hasattr(result, "points") else None
    if not ca:  # (no thrust faces; or a stand-in without contact points)
        return [("", depth, "the clearance c", c)]
    kinds = {p.name: p.kind for p in result.compiled.contact_points}
    deepest = {False: 0.0, True: 0.0}  # thrust point? -> deepest sampled penetration
    for p in result.points(name):
        d = result.channel("point_penetration", p)
        thrust = kinds.get(p) == "thrust_point"
        deepest[thrust] = max(deepest[thrust], float(np.max(d)) if d.size else 0.0)
    at_thrust = deepest[True] > deepest[False]
    radial = deepest[False] if at_thrust else max(depth, deepest[False])
    thrust = max(depth, deepest[True]) if at_thrust else deepest[True]
    return [
        (" (radial)", radial, "the clearance c", c),
        (" at a thrust face", thrust, "the axial clearance c_a", float(ca)),
    ]


def _axial_clearance(result, name: str) -> float | None:
    joint = result.compiled.mechanism.joints.get(name)
    return getattr(getattr(joint, "clearance", None), "axial_clearance", None)
