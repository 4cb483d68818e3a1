"""Poincare maps and what they tell: section crossings located on a cubic Hermite
interpolant, stroboscopic samples of a SciPy-integrated ODE, the period of a sequence of
Poincare points, and their number of distinct points.

For mechanisms, `clearance.nonlinear.steady_state` samples the stroboscopic map exactly on
the integrator's dense output; the section crossings of a run are located here on its
output samples (a channel and its rate: the cubic through two samples and their slopes,
error O(dt^4) of the output interval dt).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from clearance.model.errors import ModelError

__all__ = [
    "distinct_points",
    "ode_stroboscopic",
    "periodic_grid",
    "recurrence_period",
    "section_crossings",
    "spline_rate",
    "strobe_indices",
]


def periodic_grid(
    period: float, periods: int, samples_per_period: int, t_start: float = 0.0
) -> np.ndarray:
    """The output grid of a steady-state run: t_start + period k / m, k = 0 .. periods m.
    k / m is exact for k = j m, so the stroboscopic times t_start + j period are grid
    points computed exactly (their samples are the dense output at exactly those times)."""
    m = samples_per_period
    return t_start + period * (np.arange(periods * m + 1) / m)


def strobe_indices(
    n: int, samples_per_period: int, transient_periods: int = 0, phase: float = 0.0
) -> np.ndarray:
    """Indices of the stroboscopic samples, once per period at `phase` (a fraction of the
    period, rounded to the grid and wrapped: 0.999 on a grid of 40 is the next period's 0),
    after `transient_periods`, among the first n samples of `periodic_grid`."""
    m = samples_per_period
    return np.arange(transient_periods * m + int(round(phase * m)) % m, n, m)


def spline_rate(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """dx/dt at the samples: the derivative of the not-a-knot cubic spline through them
    (for a channel whose rate the run does not have)."""
    from scipy.interpolate import CubicSpline

    return CubicSpline(t, x)(t, 1)


def _hermite(h, x0, x1, d0, d1, s):
    """Cubic Hermite on [0, h] at s in [0, 1] (value)."""
    h00 = (1 + 2 * s) * (1 - s) ** 2
    h10 = s * (1 - s) ** 2
    h01 = s * s * (3 - 2 * s)
    h11 = s * s * (s - 1)
    return h00 * x0 + h10 * h * d0 + h01 * x1 + h11 * h * d1


def section_crossings(
    t: np.ndarray,
    x: np.ndarray,
    xdot: np.ndarray | None = None,
    *,
    value: float = 0.0,
    direction: int = 1,
    others: dict | None = None,
) -> tuple[np.ndarray, dict]:
    """Times where the channel x crosses `value` in `direction` (+1 upward, -1 downward, 0
    both) and the other channels there.

    Located as the root of the cubic Hermite interpolant through the two samples around a
    sign change and their slopes xdot (default: the derivative of a cubic spline through
    x; give the channel's true rate where the run has it, e.g. a velocity); others:
    name -> (values, rates or None) interpolated at the crossing the same way (linearly
    when no rate is given). Returns (times, {name: values})."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.ndim != 1 or x.shape != t.shape or t.size < 2:
        raise ModelError("section_crossings", "x", x.shape, f"expected the shape of t {t.shape}")
    if direction not in (-1, 0, 1):
        raise ModelError("section_crossings", "direction", direction, "allowed: -1, 0, 1")
    if xdot is None:
        xdot = spline_rate(t, x)
    g = x - value
    s0, s1 = g[:-1], g[1:]
    up = (s0 < 0) & (s1 >= 0)
    down = (s0 > 0) & (s1 <= 0)
    sel = up if direction == 1 else down if direction == -1 else (up | down)
    idx = np.flatnonzero(sel)
    times = np.empty(idx.size)
    frac = np.empty(idx.size)
    for n, i in enumerate(idx):
        h = t[i + 1] - t[i]
        args = (h, g[i], g[i + 1], xdot[i], xdot[i + 1])
        if g[i + 1] == 0.0:
            s = 1.0
        else:
            s = brentq(lambda s, a=args: _hermite(*a, s), 0.0, 1.0, xtol=1e-15)
        frac[n] = s
        times[n] = t[i] + s * h
    out = {}
    for name, (vals, rates) in (others or {}).items():
        v = np.asarray(vals, dtype=float)
        h = t[idx + 1] - t[idx]
        if rates is None:
            out[name] = v[idx] + frac * (v[idx + 1] - v[idx])
        else:
            r = np.asarray(rates, dtype=float)
            out[name] = _hermite(h, v[idx], v[idx + 1], r[idx], r[idx + 1], frac)
    return times, out


def ode_stroboscopic(
    f: Callable,
    y0: np.ndarray,
    *,
    period: float,
    periods: int,
    transient_periods: int = 0,
    t0: float = 0.0,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    method: str = "DOP853",
) -> tuple[np.ndarray, np.ndarray]:
    """Stroboscopic samples of y' = f(t, y) at t0 + k period, k = transient_periods ..
    periods, integrated by scipy.integrate.solve_ivp (the samples are evaluations of its
    dense output at those times, t_eval). Returns (times, states (n, len(y0)))."""
    ts = t0 + period * np.arange(transient_periods, periods + 1)
    s = solve_ivp(
        f, (t0, ts[-1]), np.asarray(y0, dtype=float), method=method, rtol=rtol, atol=atol, t_eval=ts
    )
    if s.status != 0:
        raise ModelError("ode_stroboscopic", "f", f, f"integration failed: {s.message}")
    return s.t, s.y.T


def _points(who: str, points: object) -> np.ndarray:
    P = np.asarray(points, dtype=float)
    if P.ndim == 1:
        P = P[:, None]
    if P.ndim != 2 or P.shape[0] < 1 or not np.all(np.isfinite(P)):
        raise ModelError(who, "points", P.shape, "expected finite points, an (n, d) array")
    return P


def recurrence_period(points: object, *, tol: float, max_period: int = 32) -> int | None:
    """The smallest p <= max_period with |P[k + p] - P[k]| <= tol for every k (max norm,
    over all points given: pass the points after the transient), or None. Needs at least
    2 p + 1 points to call a sequence period-p."""
    P = _points("recurrence_period", points)
    n = P.shape[0]
    for p in range(1, min(max_period, (n - 1) // 2) + 1):
        if np.max(np.abs(P[p:] - P[:-p])) <= tol:
            return p
    return None


def distinct_points(points: object, *, tol: float) -> int:
    """Number of distinct points (greedy clusters of max-norm radius tol)."""
    P = _points("distinct_points", points)
    centres: list[np.ndarray] = []
    for p in P:
        if not any(np.max(np.abs(p - c)) <= tol for c in centres):
            centres.append(p)
            if len(centres) > 10_000:
                break
    return len(centres)


def default_tolerance(points: np.ndarray, scale: np.ndarray | float | None = None) -> float:
    """A tolerance for `recurrence_period` / `distinct_points`: 1e-4 of the scale (default:
    the largest magnitude among the points, or 1 if they are all zero)."""
    P = _points("default_tolerance", points)
    s = float(np.max(np.abs(P))) if scale is None else float(np.max(scale))
    return 1e-4 * (s if s > 0 and math.isfinite(s) else 1.0)
