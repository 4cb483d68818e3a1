"""[steady_state]: a run over whole periods of a periodic drive, sampled so that the
stroboscopic (once-per-period) samples are exact samples of the integrator's dense output,
with the transient to discard stated in periods.

    [steady_state]
    period = 0.5              # [s] drive period; default: trajectory.period
    transient_periods = 20    # periods discarded before Poincare points, spectra, ...
    samples_per_period = 200  # output samples per period (replaces solver.dt_out by
                              # period / this; default: period / solver.dt_out, rounded)
    phase = 0.0               # stroboscopic phase, a fraction of the period in [0, 1)
    lyapunov_periods = 0      # > 0: largest Lyapunov exponent by two trajectories over this
                              # many periods, from the run's end (clearance.nonlinear)
    lyapunov_intervals = 1    # renormalisations per period

The number of periods is trajectory.duration / period (a whole number). The drive must be
periodic with this period: shapes rest-to-rest and sin (trajectory.period divides it) and
periodic (every harmonic's period divides it); a general mechanism without inverse
kinematics runs its own drivers, whose periodicity is the author's to state.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from clearance.scenario.errors import Problems
from clearance.scenario.fields import Field, parse_table

__all__ = ["STEADY_FIELDS", "SteadyStateSpec", "parse_steady_state"]

STEADY_FIELDS = {
    "period": Field("positive", None, "s", "drive period; default: trajectory.period"),
    "transient_periods": Field("count0", 0, doc="periods discarded as transient"),
    "samples_per_period": Field(
        "count", None, doc="output samples per period; default: period / solver.dt_out"
    ),
    "phase": Field("nonneg", 0.0, doc="stroboscopic phase, fraction of a period in [0, 1)"),
    "lyapunov_periods": Field(
        "count0", 0, doc="periods of the two-trajectory Lyapunov estimate after the run (0: none)"
    ),
    "lyapunov_intervals": Field("count", 1, doc="renormalisations per period"),
    "section": Field("table", None, doc="Poincare section { body, coordinate, value, direction }"),
}
SECTION_KEYS = ("body", "coordinate", "value", "direction")
_WHOLE = 1e-9  # relative tolerance of "a whole number of periods"


@dataclass(frozen=True)
class SteadyStateSpec:
    """A validated [steady_state]: period [s], periods (of the run), transient_periods,
    samples_per_period, phase (a multiple of 1 / samples_per_period)."""

    period: float
    periods: int
    transient_periods: int = 0
    samples_per_period: int = 100
    phase: float = 0.0
    lyapunov_periods: int = 0
    lyapunov_intervals: int = 1
    section: dict | None = None  # {body, coordinate, value, direction}: `section_spec()`

    def section_spec(self):
        """The `clearance.Section` of the clearance run, or None."""
        if self.section is None:
            return None
        from clearance.integrate.sections import Section

        return Section(**self.section)

    def t_out(self, t_start: float = 0.0) -> np.ndarray:
        """The output grid (`clearance.nonlinear.periodic_grid`): the stroboscopic times
        t_start + (j + phase) period are grid points, computed exactly."""
        from clearance.nonlinear.poincare import periodic_grid

        return periodic_grid(self.period, self.periods, self.samples_per_period, t_start)

    def strobe_indices(self, n: int) -> np.ndarray:
        """Indices of the stroboscopic samples after the transient among n samples."""
        from clearance.nonlinear.poincare import strobe_indices

        return strobe_indices(n, self.samples_per_period, self.transient_periods, self.phase)

    def attrs(self) -> dict:
        """The file attributes `clearance analyze` reads (steady_*)."""
        return {f"steady_{f.name}": getattr(self, f.name) for f in dataclasses.fields(self)}


def _whole(x: float) -> int | None:
    k = round(x)
    return int(k) if k >= 1 and abs(x - k) <= _WHOLE * max(1.0, x) else None


def parse_steady_state(t: dict, trajectory, solver, general_own: bool, problems: Problems):
    """(SteadyStateSpec, solver with dt_out = period / samples_per_period) or (None, solver)
    with the problems reported. trajectory, solver: the parsed sections (None if invalid);
    general_own: a general mechanism running its own drivers (no IK)."""
    n0, kw = len(problems), parse_table(t, STEADY_FIELDS, "steady_state", problems)
    if len(problems) > n0 or trajectory is None or solver is None:
        return None, solver
    shape = trajectory.shape.value
    period = kw["period"]
    if period is None:
        if general_own:
            problems.add(
                "steady_state.period",
                None,
                "required for a mechanism that runs its own drivers: the drive period [s]",
            )
            return None, solver
        period = trajectory.period
    if not general_own:
        if shape in ("rest-to-rest", "sin"):
            base = [("trajectory.period", trajectory.period)]
        elif shape == "periodic":
            base = [
                (f"trajectory.periodic.{c}", p)
                for c, hs in trajectory.harmonics.items()
                for _, p, _ in hs
            ]
        else:
            problems.add(
                "trajectory.shape",
                shape,
                "[steady_state] needs a periodic drive: shape 'periodic', 'rest-to-rest' or 'sin'",
            )
            return None, solver
        for where, p in base:
            if _whole(period / p) is None:
                problems.add(
                    "steady_state.period",
                    period,
                    f"the drive is not periodic with this period: {where} has period {p:g} s, "
                    "which must divide it a whole number of times",
                )
                return None, solver
    periods = _whole(trajectory.duration / period)
    if periods is None:
        n = max(1, round(trajectory.duration / period))
        problems.add(
            "trajectory.duration",
            trajectory.duration,
            f"expected a whole number of steady-state periods of {period:g} s (e.g. "
            f"{n * period:g} s = {n} periods)",
        )
        return None, solver
    ntr = kw["transient_periods"]
    if ntr >= periods:
        problems.add(
            "steady_state.transient_periods",
            ntr,
            f"expected fewer than the run's {periods} periods (trajectory.duration / period)",
        )
        return None, solver
    phase = kw["phase"]
    if not phase < 1.0:
        problems.add("steady_state.phase", phase, "expected a fraction of a period in [0, 1)")
        return None, solver
    m = kw["samples_per_period"]
    if m is None:
        m = max(1, round(period / solver.dt_out))
    # (samples_per_period, when given, replaces solver.dt_out: a study's base is a canonical
    # scenario, which always holds a dt_out, so "both given" cannot be told from a conflict)
    sec = kw["section"]
    if sec is not None:
        sec = _section(sec, problems)
        if sec is None:
            return None, solver
    nl = kw["lyapunov_periods"] * kw["lyapunov_intervals"]
    if 0 < nl < 10:
        problems.add(
            "steady_state.lyapunov_periods",
            kw["lyapunov_periods"],
            "expected lyapunov_periods x lyapunov_intervals >= 10 renormalisations (the "
            "exponent's standard error comes from 10 blocks of them), or 0 for none",
        )
        return None, solver
    spec = SteadyStateSpec(
        float(period),
        periods,
        ntr,
        m,
        (round(phase * m) % m) / m,  # (0.999 on a grid of 40: the next period's 0)
        kw["lyapunov_periods"],
        kw["lyapunov_intervals"],
        sec,
    )
    return spec, dataclasses.replace(solver, dt_out=float(period) / m)


def _section(t: dict, problems: Problems) -> dict | None:
    """[steady_state.section]: a body's state coordinate crossing a value (the body is
    checked when the mechanism is built)."""
    from clearance.integrate.sections import COORDINATES

    path = "steady_state.section"
    n0 = len(problems)
    for k, v in t.items():
        if k not in SECTION_KEYS:
            problems.unknown(f"{path}.{k}", k, v, SECTION_KEYS)
    body = t.get("body")
    if not (isinstance(body, str) and body):
        problems.add(f"{path}.body", body, "required: the moving body whose coordinate crosses")
    coord = t.get("coordinate", "z")
    if coord not in COORDINATES:
        problems.add(f"{path}.coordinate", coord, f"allowed: {', '.join(COORDINATES)}")
    value = t.get("value", 0.0)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value:
        problems.add(f"{path}.value", value, "expected a number (the section's value)")
    direction = t.get("direction", 1)
    if direction not in (-1, 0, 1) or isinstance(direction, bool):
        problems.add(f"{path}.direction", direction, "allowed: 1 (upward), -1, 0 (both)")
    if len(problems) > n0:
        return None
    return {"body": body, "coordinate": coord, "value": float(value), "direction": int(direction)}
