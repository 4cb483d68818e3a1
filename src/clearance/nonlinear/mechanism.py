"""The nonlinear-dynamics tools on mechanisms: steady-state runs with stroboscopic samples
exactly on the integrator's dense output, and the largest Lyapunov exponent of a mechanism
by two trajectories advanced through the compiled loop of `simulate`, each carrying its own
contact state (so the estimate holds through impacts).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from clearance.analysis.assembly import assemble, velocity_analysis
from clearance.compile.compiled import Compiled, compile_mechanism
from clearance.contact.element import make_contact_state
from clearance.dynamics.rhs import make_work
from clearance.integrate.methods import METHODS, resolve_method
from clearance.integrate.simulate import (
    _run_loop,
    _solver_code,
    initial_state,
    loop_inputs,
    simulate,
)
from clearance.kinds import STATUS_MESSAGE, Status
from clearance.model.errors import ModelError
from clearance.model.mechanism import Mechanism
from clearance.nonlinear.chaos import LyapunovEstimate, largest_lyapunov
from clearance.nonlinear.poincare import periodic_grid, strobe_indices
from clearance.store.result import Result

__all__ = ["MechanismTrajectory", "SteadyState", "mechanism_lyapunov", "steady_state"]


def _count(who: str, name: str, v: object, lo: int) -> int:
    if not (isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= lo):
        raise ModelError(who, name, v, f"expected an integer >= {lo}")
    return int(v)


def _positive(who: str, name: str, v: object) -> float:
    ok = isinstance(v, (int, float, np.floating, np.integer)) and not isinstance(v, bool)
    if not (ok and math.isfinite(v) and v > 0):
        raise ModelError(who, name, v, "expected a finite number > 0")
    return float(v)


@dataclass(frozen=True)
class SteadyState:
    """A run over `periods` drive periods sampled `samples_per_period` times per period:
    `result` holds every sample; `strobe` the indices of the stroboscopic samples (one per
    period, at phase `phase` of it, after `transient_periods`), which are samples of the
    dense output at exactly t_start + (k + phase) period, not the nearest output."""

    result: Result
    period: float
    periods: int
    transient_periods: int
    samples_per_period: int
    phase: float
    strobe: np.ndarray = field(repr=False)

    @property
    def strobe_times(self) -> np.ndarray:
        return self.result.t[self.strobe]

    @property
    def steady(self) -> np.ndarray:
        """Indices of the samples after the transient (for spectra and phase portraits)."""
        i0 = self.transient_periods * self.samples_per_period
        return np.arange(i0, self.result.t.size)


def steady_state(
    system: Mechanism | Compiled,
    *,
    period: float,
    periods: int,
    transient_periods: int = 0,
    samples_per_period: int = 100,
    phase: float = 0.0,
    t_start: float = 0.0,
    **simulate_options,
) -> SteadyState:
    """Simulate `periods` periods of a periodic drive (period [s]) and mark the stroboscopic
    samples after `transient_periods`. The output grid is t_start + period k /
    samples_per_period, so that the stroboscopic times are grid points computed exactly;
    phase (fraction of a period in [0, 1)) is rounded to the grid: phase = round(phase m) / m.
    simulate_options go to `simulate` (method, rtol, atol, y0, ...)."""
    who = "steady_state"
    T = _positive(who, "period", period)
    n = _count(who, "periods", periods, 1)
    ntr = _count(who, "transient_periods", transient_periods, 0)
    m = _count(who, "samples_per_period", samples_per_period, 1)
    if ntr >= n:
        raise ModelError(who, "transient_periods", ntr, f"expected fewer than periods = {n}")
    if not (isinstance(phase, (int, float)) and 0.0 <= phase < 1.0):
        raise ModelError(who, "phase", phase, "expected a fraction of a period in [0, 1)")
    for k in ("t_out", "dt_out", "t_end"):
        if k in simulate_options:
            raise ModelError(who, k, simulate_options[k], "set by period and samples_per_period")
    t_out = periodic_grid(T, n, m, t_start)
    r = simulate(system, float(t_out[-1]), t_start=t_start, t_out=t_out, **simulate_options)
    # (a failed run keeps what it computed: its samples only)
    idx = strobe_indices(r.t.size, m, ntr, phase)
    return SteadyState(r, T, n, ntr, m, (int(round(phase * m)) % m) / m, idx)


class MechanismTrajectory:
    """A trajectory of a compiled mechanism advanced by the compiled loop of `simulate`
    (the `Trajectory` protocol of `clearance.nonlinear.chaos`): the state, the contact state
    (flags and latched impact velocities) and the time are carried from one `advance` to
    the next; `place` assembles a state onto the constraint manifold (positions, then
    velocities) at the current time, its quaternions normalised; `adopt(other)` takes the
    other trajectory's contact state. The separation is measured in the positions and
    velocities, scaled by `scale` (per coordinate; default 1): not in the friction states
    (a bristle state does not move out of contact, and its normal part not in contact:
    neutral directions that held the estimate at 0) nor in the work integrals."""

    def __init__(
        self,
        c: Compiled,
        y: np.ndarray,
        t: float = 0.0,
        *,
        method: str = "auto",
        rtol: float = 1e-8,
        atol: float = 1e-11,
        baumgarte: tuple = (5.0, 5.0),
        solver: str = "auto",
        max_step: float = math.inf,
        scale: np.ndarray | None = None,
    ) -> None:
        self.c = c
        self.t = float(t)
        self.y = np.array(y, dtype=float)
        self.method = resolve_method(method, rtol)
        self.code = _solver_code(c, solver, self.y, self.t)
        self.alpha, self.beta = (float(x) for x in baumgarte)
        self.rtol, self.atol, self.hmax = float(rtol), float(atol), float(max_step)
        self.wk = make_work(c.model)
        self.cs = make_contact_state(c.model)
        n = c.layout.iz
        self.scale = np.ones(n) if scale is None else np.asarray(scale, dtype=float)
        if self.scale.shape != (n,) or not np.all(self.scale > 0):
            raise ModelError(
                "MechanismTrajectory", "scale", self.scale.shape, f"expected ({n},) numbers > 0"
            )
        self.nfev = 0

    def advance(self, tau: float) -> None:
        t1 = self.t + tau
        opts, out = loop_inputs(
            self.c,
            np.array([t1]),
            alpha=self.alpha,
            beta=self.beta,
            solver=self.code,
            rtol=self.rtol,
            atol=self.atol,
            h0=0.0,
            hmax=self.hmax,
            hmin=1e-14,
            max_steps=10_000_000,
            proj_tol=0.0,
            step=1e-3,
            max_events=0,
            stages=METHODS[self.method].stages,
        )
        (status, nout, t_reached, _), _ = _run_loop(
            self.method, self.c.model, self.wk, self.cs, opts, out, self.t, self.y
        )
        self.nfev += int(out.stats[0])
        if status != 0 or nout != 1:
            raise ModelError(
                "MechanismTrajectory",
                "advance",
                f"t = {self.t:g} .. {t1:g}",
                f"{STATUS_MESSAGE[Status(status)]} at t = {t_reached:g}",
            )
        self.y = out.ys.copy()  # the step's end (exactly t1), after the contact update
        self.t = t1

    def place(self, y: np.ndarray) -> np.ndarray:
        y = np.array(y, dtype=float)
        p = y[: 7 * self.c.nb].reshape(-1, 7)[:, 3:]
        p /= np.linalg.norm(p, axis=1)[:, None]  # (a view: normalised in y)
        if self.c.nrow:
            y = assemble(self.c, y, t=self.t)
            y = velocity_analysis(self.c, y, t=self.t)
        self.y = y
        return y

    def adopt(self, other: MechanismTrajectory) -> None:
        """Take the other trajectory's contact flags and latched impact velocities (a
        pulled-back copy within d0 of it: its own could be far off)."""
        self.cs.flag[:] = other.cs.flag
        self.cs.ddm[:] = other.cs.ddm

    def distance_state(self) -> np.ndarray:
        return self.y[: self.c.layout.iz] / self.scale


def mechanism_lyapunov(
    system: Mechanism | Compiled,
    *,
    interval: float,
    intervals: int,
    transient_intervals: int = 0,
    t_start: float = 0.0,
    y0: np.ndarray | None = None,
    d0: float = 1e-7,
    seed: int = 0,
    scale: np.ndarray | None = None,
    **options,
) -> LyapunovEstimate:
    """Largest Lyapunov exponent [1/s] of a mechanism (clearance joints included) by the
    two-trajectory method (`clearance.nonlinear.chaos.largest_lyapunov`): two
    `MechanismTrajectory`s from the consistent initial state (or y0) at t_start, the second
    d0 away along a random admissible direction, renormalised every `interval` seconds.
    Drive the mechanism periodically and take `interval` a fraction of the period (or the
    period). options: method, rtol, atol, baumgarte, solver, max_step of the trajectories;
    rtol must keep the integration error far below d0 (default rtol 1e-8, d0 1e-7)."""
    c = system if isinstance(system, Compiled) else compile_mechanism(system)
    y = initial_state(c, t=t_start, y0=y0)
    ref = MechanismTrajectory(c, y, t_start, scale=scale, **options)
    pert = MechanismTrajectory(c, y, t_start, scale=scale, **options)
    rng = np.random.default_rng(seed)
    u = np.zeros(c.ny)
    u[: c.layout.iz] = rng.standard_normal(c.layout.iz) * ref.scale  # positions, velocities
    return largest_lyapunov(
        ref,
        pert,
        interval=interval,
        intervals=intervals,
        transient_intervals=transient_intervals,
        d0=d0,
        direction=u,
    )
