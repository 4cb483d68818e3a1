"""How long a run will take, before it starts: a step count from the stiffest time scale.

An explicit integrator's step is bounded by the fastest time scale of the motion: the
oscillation of a body on the stiffness of its contact, the decay of a LuGre bristle, the
viscous slope of a regularised friction law, the Baumgarte stabilisation. `estimate_cost`
finds each of them from the compiled model (the laws' own compiled force functions, so every
law is covered), at a load and a slip speed set by the motion (gravity and the prescribed
platform acceleration), and turns the fastest into a step count and a wall time:

* an oscillation of angular frequency omega (a body on its contact) is followed to the
  tolerance: h = KAPPA rtol^(1/5) / omega (an error per step ~ (omega h)^5 for the 5(4)
  pairs); KAPPA is calibrated on the shipped 4UPS-UPU scenario (PROPOSED: 30 reproduces its
  7181 steps within 10 %, rtol 1e-6, the balls in contact 93-95 % of the time);
* a decay of rate lambda (bristle decay and damping, friction slopes, Baumgarte) only has
  to stay stable:
  h = STABILITY / lambda (the 5(4) pairs' real stability boundary, ~3.3);
* rk4 takes exactly duration / step steps; dop853 follows an oscillation to
  h = kappa rtol^(1/8) / omega and stays stable to 6.39 / lambda, vern7 to
  h = kappa rtol^(1/7) / omega and 4.64 / lambda (`HIGHER_ORDER`).

Contact is assumed all the time (the balls of the shipped scenarios ride their sockets), so
the estimate is of the order of the real count, not a bound. Measured: the shipped scenario
7181 steps (estimate 8.9e3); its period 0.2 s 3762 (5.8e3); Baumgarte alpha 1e4 12 498
(1.2e4); LuGre sigma0 1e8 ~1.3e6 (5.8e6: slip is slower than a tenth of the platform's
speed); a Hertz ball resting in its socket 1.3-1.7x the estimate; a dissipative law resting
without an impact up to 7x (its damping at the impact-velocity floor is stiffer than at the
assumed approach speed). Impacts add short bursts of small steps. It is for warnings ("this
run will take about 3 h"), not for scheduling; `clearance run` also warns from the pace of
the run itself.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from clearance.kinds import CG_C, PI_CLR, PI_FRIC, PI_LAW, FrictionLaw

if TYPE_CHECKING:
    from clearance.compile.compiled import Compiled

KAPPA = 30.0  # PROPOSED, calibrated (module docstring)
STABILITY = 3.3  # real stability boundary of DOPRI5 / Tsit5 (Hairer & Wanner I, IV.2)
LONG_RUN_SECONDS = 600.0  # PROPOSED: warn above this integration time ([checks] long_run)
RHS_PER_STEP = {
    "dopri5": 6.5,
    "tsit5": 6.5,
    "rk4": 4.0,
    "dop853": 15.0,
    "vern7": 15.0,
}  # incl. rejected
#: per adaptive method other than the 5(4) pairs: (order, kappa, real stability boundary);
#: dop853 (PROPOSED, calibrated like KAPPA: 4272 steps on the shipped scenario at rtol 1e-6,
#: estimate 4.7e3; boundary 6.39 computed from its stability function); vern7 (PROPOSED, the
#: same way: 4822 steps, estimate 4.8e3; boundary 4.64 from its stability function)
HIGHER_ORDER = {"dop853": (8, 20.0, 6.39), "vern7": (7, 25.0, 4.64)}


@dataclass
class CostEstimate:
    """steps: estimated steps; step: the step the fastest time scale allows [s];
    limit: what sets it; wall: estimated integration time [s] (seconds_per_rhs measured
    on this machine); scales: every time scale found, (what, step it allows [s])."""

    steps: float
    step: float
    limit: str
    wall: float
    seconds_per_rhs: float
    scales: list = field(default_factory=list)

    def text(self) -> str:
        return (
            f"about {self.steps:.2g} steps of ~{self.step:.2g} s (set by {self.limit}), "
            f"~{_duration(self.wall)} of integration on this machine"
        )


def _duration(s: float) -> str:
    if s < 120:
        return f"{s:.2g} s"
    if s < 7200:
        return f"{s / 60:.2g} min"
    if s < 2 * 86400:
        return f"{s / 3600:.2g} h"
    return f"{s / 86400:.2g} days"


def _mass(c: Compiled, body: str) -> float:
    b = c.mechanism.bodies.get(body)
    return b.mass if b is not None else math.inf


def _load_penetration(law: int, par: np.ndarray, force: float, c: float) -> float:
    """The penetration at which the law's elastic force equals `force` (bisection in log
    delta; the laws increase with delta)."""
    from clearance.contact.laws import normal_force

    lo, hi = -18.0, 0.0  # log10 delta [m]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if normal_force(law, par, 10.0**mid, 0.0, 1.0, c)[1] < force:
            lo = mid
        else:
            hi = mid
    return 10.0**hi


def contact_scales(
    c: Compiled, *, acceleration: float, slip_speed: float, approach_speed: float
) -> list[tuple[str, float, str]]:
    """(what, rate [1/s], "oscillation" or "decay") of every contact point of `c` at the
    load m_eff * acceleration and the given slip and approach speeds."""
    from clearance.contact.laws import friction_steady, normal_force

    m = c.model
    out = []
    for p, pt in enumerate(c.contact_points):
        k = int(m.cp_ix[p, PI_CLR])
        info = c.clearances[k]
        m1, m2 = _mass(c, info.socket_body), _mass(c, info.ball_body)
        meff = m1 * m2 / (m1 + m2) if math.isfinite(m1) and math.isfinite(m2) else min(m1, m2)
        law, par = int(m.cp_ix[p, PI_LAW]), m.cp_par[p, 0]
        cc = float(m.clr_geo[k, CG_C])
        force = meff * acceleration
        d = _load_penetration(law, par, force, cc)
        f0 = normal_force(law, par, d, 0.0, approach_speed, cc)[1]
        f1 = normal_force(law, par, d * (1 + 1e-6), 0.0, approach_speed, cc)[1]
        stiff = max(f1 - f0, 0.0) / (d * 1e-6)
        what = f"the contact stiffness of {pt.name} ({info.normal}) at ~{force:.2g} N"
        out.append((what, math.sqrt(stiff / meff), "oscillation"))
        # damping: dF/d(delta_dot) at the approach speed, a decay rate over the mass
        dv = 1e-6 * max(approach_speed, 1e-6)
        g0 = normal_force(law, par, d, approach_speed, approach_speed, cc)[0]
        g1 = normal_force(law, par, d, approach_speed + dv, approach_speed, cc)[0]
        out.append((f"the contact damping of {pt.name}", max(g1 - g0, 0.0) / dv / meff, "decay"))
        fric, fpar = int(m.cp_ix[p, PI_FRIC]), m.cp_par[p, 1]
        if fric == int(FrictionLaw.NONE):
            continue
        # the steepest slope of mu(v) up to the slip speed: a viscous damping F dmu/dv
        vs = np.geomspace(1e-9, max(slip_speed, 1e-6), 400)
        mu = np.array([friction_steady(fric, fpar, v) for v in vs])
        slope = float(np.max(np.diff(mu) / np.diff(vs)))
        out.append(
            (f"the friction slope of {pt.name} ({info.friction})", force * slope / meff, "decay")
        )
        if fric == int(FrictionLaw.LUGRE):
            sigma0 = fpar[0]
            g = friction_steady(fric, fpar, slip_speed) - fpar[2] * slip_speed
            out.append((f"the LuGre bristles of {pt.name}", sigma0 * slip_speed / g, "decay"))
            # sticking, the bristle damping F_N sigma1 z_dot acts on the body: F sigma1 / m
            out.append((f"the LuGre bristle damping of {pt.name}", fpar[1] * force / meff, "decay"))
            out.append(
                (
                    f"the LuGre bristle stiffness of {pt.name}",
                    math.sqrt(sigma0 * force / meff),
                    "oscillation",
                )
            )
    return out


def seconds_per_rhs(c: Compiled, repeat: int = 50) -> float:
    """Wall time of one right-hand side evaluation of `c` at its initial state [s]."""
    from clearance.contact.element import make_contact_state
    from clearance.dynamics.rhs import make_work, rhs

    wk, cs = make_work(c.model), make_contact_state(c.model)
    y = np.array(c.y0, dtype=float)
    out = np.empty_like(y)
    rhs(0.0, y, c.model, wk, cs, 5.0, 5.0, 0, out)
    t0 = time.perf_counter()
    for _ in range(repeat):
        rhs(0.0, y, c.model, wk, cs, 5.0, 5.0, 0, out)
    return (time.perf_counter() - t0) / repeat


def estimate_cost(
    c: Compiled,
    duration: float,
    *,
    method: str = "dopri5",
    rtol: float = 1e-6,
    step: float = 1e-3,
    max_step: float = math.inf,
    baumgarte: tuple = (5.0, 5.0),
    acceleration: float | None = None,
    speed: float = 0.1,
    rhs_seconds: float | None = None,
) -> CostEstimate:
    """Estimated steps and integration time of `simulate(c, duration, ...)` (module
    docstring). acceleration: the motion's acceleration scale [m/s^2] (default: gravity;
    a scenario adds its platform's peak acceleration); speed: its velocity scale [m/s]
    (slip speeds are taken as a tenth of it, PROPOSED; impacts at sqrt(2 a c)). method: a
    method's name ("auto" resolved first: `clearance.integrate.methods.resolve_method`)."""
    g = float(np.linalg.norm(c.mechanism.gravity))
    acc = max(g if acceleration is None else acceleration, 1e-3)
    scales = []  # (what, step it allows)
    if method == "rk4":
        scales.append(("the fixed step", step))
    else:
        order, kappa, stability = HIGHER_ORDER.get(method, (5, KAPPA, STABILITY))
        if math.isfinite(max_step):
            scales.append(("max_step", max_step))
        alpha, beta = baumgarte
        if c.nrow:
            lam = alpha + math.sqrt(max(alpha * alpha - beta * beta, 0.0)) if alpha > beta else beta
            if lam > 0:
                scales.append(
                    (
                        f"the Baumgarte stabilisation (alpha {alpha:g}, beta {beta:g})",
                        stability / lam,
                    )
                )
        cmin = min((ci.c for ci in c.clearances), default=0.0)
        for what, rate, kind in contact_scales(
            c,
            acceleration=acc,
            slip_speed=0.1 * max(speed, 1e-3),
            approach_speed=math.sqrt(2 * acc * max(cmin, 1e-9)),
        ):
            if rate > 0 and math.isfinite(rate):
                if kind == "oscillation":
                    h = kappa * rtol ** (1.0 / order) / rate
                else:
                    h = stability / rate
                scales.append((what, h))
            elif not math.isfinite(rate):
                scales.append((what, 0.0))
    limit, h = min(scales, key=lambda s: s[1]) if scales else ("the duration", duration)
    h = min(h, duration)
    steps = duration / max(h, 1e-300)
    per = seconds_per_rhs(c) if rhs_seconds is None else rhs_seconds
    wall = steps * RHS_PER_STEP.get(method, 6.5) * per
    return CostEstimate(steps, h, limit, wall, per, scales)


def motion_scales(c: Compiled, info) -> tuple[float, float]:
    """(speed [m/s], acceleration [m/s^2]) scales of a scenario run: the peak speed and
    acceleration of the platform's points (the trajectory's translations, and its angular
    rates times the farthest platform marker), with gravity added to the acceleration.
    info: the scenario's `BuildInfo`."""
    f = info.pose_functions()
    # (a periodic trajectory sampled at least 40 times per period: no aliasing)
    scale = getattr(info.trajectory, "time_scale", info.trajectory.period)
    n = int(min(max(2001, 40 * info.t_end / scale), 200_001))
    ts = np.linspace(0.0, info.t_end, n)
    lever = max(
        (
            float(np.linalg.norm(mk.position))
            for mk in c.mechanism.markers.values()
            if mk.body == info.platform_body
        ),
        default=0.0,
    )
    d = np.stack([f[k].evaluate(ts)[:, 1:] for k in f], axis=1)  # (t, coord, (d1, d2))
    lin, ang = d[:, :3], d[:, 3:]
    speed = np.max(np.linalg.norm(lin[:, :, 0], axis=1) + lever * np.abs(ang[:, :, 0]).sum(axis=1))
    acc = np.max(np.linalg.norm(lin[:, :, 1], axis=1) + lever * np.abs(ang[:, :, 1]).sum(axis=1))
    return float(speed), float(acc) + float(np.linalg.norm(c.mechanism.gravity))
