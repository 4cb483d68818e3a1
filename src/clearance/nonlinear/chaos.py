"""Chaos indicators: the largest Lyapunov exponent by the two-trajectory method (Benettin
et al. 1980) for any system that can be advanced in time, from a time series by delay
embedding (Rosenstein, Collins & De Luca 1993), and the 0-1 test for chaos (Gottwald &
Melbourne 2004; the modified, regression-free form of Gottwald & Melbourne 2009).

`largest_lyapunov` needs two `Trajectory` objects: a reference and a perturbed copy that
it renormalises. `OdeTrajectory` advances y' = f(t, y) with SciPy; the mechanism one
(`clearance.nonlinear.mechanism.MechanismTrajectory`) runs the compiled loop of
`simulate`, carrying its own contact state through impacts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial import cKDTree

from clearance.model.errors import ModelError

__all__ = [
    "LyapunovEstimate",
    "OdeTrajectory",
    "Trajectory",
    "ZeroOne",
    "largest_lyapunov",
    "rosenstein",
    "zero_one_test",
]


class Trajectory(Protocol):
    """What `largest_lyapunov` advances: a time t, a state y (1-D array) and

    advance(tau): integrate from (t, y) over tau seconds (in place);
    place(y): set the state (same t), made consistent (constraints, contact state) if the
        system has such conditions; returns the state actually set;
    distance_state(): the coordinates the separation is measured in (1-D array);
    optionally adopt(reference): after each `place`, take the reference's discrete state
        (a mechanism's contact flags and latched impact velocities), so that the pulled-back
        copy differs from the reference by d0 in every part of its state."""

    t: float
    y: np.ndarray

    def advance(self, tau: float) -> None: ...

    def place(self, y: np.ndarray) -> np.ndarray: ...

    def distance_state(self) -> np.ndarray: ...


@dataclass
class OdeTrajectory:
    """A trajectory of y' = f(t, y), advanced by scipy.integrate.solve_ivp (DOP853 by
    default) with tight tolerances."""

    f: Callable
    t: float
    y: np.ndarray
    rtol: float = 1e-10
    atol: float = 1e-12
    method: str = "DOP853"
    nfev: int = 0

    def __post_init__(self) -> None:
        self.y = np.array(self.y, dtype=float)

    def advance(self, tau: float) -> None:
        s = solve_ivp(
            self.f,
            (self.t, self.t + tau),
            self.y,
            method=self.method,
            rtol=self.rtol,
            atol=self.atol,
        )
        if s.status != 0:
            raise ModelError("OdeTrajectory", "f", self.f, f"integration failed: {s.message}")
        self.nfev += s.nfev
        self.t += tau
        self.y = s.y[:, -1].copy()

    def place(self, y: np.ndarray) -> np.ndarray:
        self.y = np.array(y, dtype=float)
        return self.y

    def distance_state(self) -> np.ndarray:
        return self.y


@dataclass(frozen=True)
class LyapunovEstimate:
    """Largest Lyapunov exponent [1/s] from `largest_lyapunov`.

    exponent: mean log stretch per unit time after the transient; standard_error: of the
    mean, from the spread of block means (10 blocks); running: the estimate after each
    interval (convergence history); times: the end time of each interval; d0: the
    separation renormalised to; intervals: how many were averaged."""

    exponent: float
    standard_error: float
    running: np.ndarray = field(repr=False)
    times: np.ndarray = field(repr=False)
    d0: float = 0.0
    intervals: int = 0

    def __str__(self) -> str:
        return f"{self.exponent:.4g} +- {self.standard_error:.2g} 1/s"


def largest_lyapunov(
    reference: Trajectory,
    perturbed: Trajectory,
    *,
    interval: float,
    intervals: int,
    transient_intervals: int = 0,
    d0: float = 1e-8,
    direction: np.ndarray | None = None,
    seed: int = 0,
) -> LyapunovEstimate:
    """Largest Lyapunov exponent by the two-trajectory method (Benettin, Galgani, Giorgilli &
    Strelcyn, Meccanica 15, 1980): the perturbed trajectory starts d0 away from the reference
    (along `direction`, default a random one), both are advanced over `interval` seconds,
    the separation d is measured in `distance_state()` and the perturbed state pulled back
    to d0 along the separation; lambda = mean of ln(d / d0) / interval over `intervals`
    intervals, after `transient_intervals` not counted (the separation aligns with the most
    expanding direction there).

    The perturbed trajectory's `place` keeps it a valid state (for a mechanism: on the
    constraint manifold, with its own contact state), so the method holds through impacts
    as long as d0 stays small against the gap dynamics (the exponent is then that of the
    compliant-contact model). d0 should be far above the integration error (rtol |y|) and
    far below the attractor's size."""
    if not (isinstance(intervals, (int, np.integer)) and intervals >= 10):
        raise ModelError(
            "largest_lyapunov",
            "intervals",
            intervals,
            "expected an integer >= 10 (the standard error comes from 10 blocks of them)",
        )
    if not (isinstance(transient_intervals, (int, np.integer)) and transient_intervals >= 0):
        raise ModelError(
            "largest_lyapunov", "transient_intervals", transient_intervals, "expected >= 0"
        )
    for name, v in (("interval", interval), ("d0", d0)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ModelError("largest_lyapunov", name, v, "expected a finite number > 0")
    y0 = reference.distance_state()
    if direction is None:
        direction = np.random.default_rng(seed).standard_normal(np.asarray(reference.y).size)
    u = np.asarray(direction, dtype=float)
    if u.shape != np.shape(reference.y) or not np.any(u):
        raise ModelError(
            "largest_lyapunov", "direction", u.shape, f"expected {np.shape(reference.y)}, not 0"
        )
    perturbed.t = reference.t
    sep = _renormalise(reference, perturbed, reference.y + d0 * u / np.linalg.norm(u), d0, y0)
    logs = []
    times = []
    for k in range(transient_intervals + intervals):
        reference.advance(interval)
        perturbed.advance(interval)
        if perturbed.t != reference.t:
            raise ModelError("largest_lyapunov", "perturbed", perturbed.t, "out of step")
        a, b = reference.distance_state(), perturbed.distance_state()
        d = float(np.linalg.norm(b - a))
        if not (math.isfinite(d) and d > 0):
            raise ModelError(
                "largest_lyapunov",
                "d0",
                d0,
                f"the separation became {d:g} at t = {reference.t:g}: choose a larger d0 "
                "(above the integration error)",
            )
        if k >= transient_intervals:
            logs.append(math.log(d / sep))
            times.append(reference.t)
        # pull back along the separation, in the full state
        pull = reference.y + (d0 / d) * (perturbed.y - reference.y)
        sep = _renormalise(reference, perturbed, pull, d0, a)
    logs = np.asarray(logs)
    running = np.cumsum(logs) / (interval * np.arange(1, logs.size + 1))
    lam = float(running[-1])
    nb = 10
    blocks = np.array([b.mean() for b in np.array_split(logs, nb)]) / interval
    se = float(blocks.std(ddof=1) / math.sqrt(nb))
    return LyapunovEstimate(lam, se, running, np.asarray(times), float(d0), int(logs.size))


def _renormalise(reference, perturbed, y: np.ndarray, d0: float, a: np.ndarray) -> float:
    """Place the perturbed state y and return its separation from the reference (in
    distance coordinates), which the consistency conditions may have changed from d0."""
    perturbed.place(y)
    adopt = getattr(perturbed, "adopt", None)  # a discrete state taken from the reference
    if adopt is not None:
        adopt(reference)
    sep = float(np.linalg.norm(perturbed.distance_state() - a))
    if not (sep > 0.01 * d0):
        raise ModelError(
            "largest_lyapunov",
            "d0",
            d0,
            f"the consistent perturbed state is only {sep:.3g} from the reference "
            "(the perturbation left the admissible states): choose another direction",
        )
    return sep


def _autocorrelation_lag(x: np.ndarray) -> int:
    """First lag at which the autocorrelation falls below 1 - 1/e (Rosenstein's choice)."""
    a = x - x.mean()
    n = a.size
    spec = np.fft.rfft(a, 2 * n)
    ac = np.fft.irfft(spec * np.conj(spec))[:n]
    ac /= ac[0]
    below = np.flatnonzero(ac < 1.0 - 1.0 / math.e)
    return int(below[0]) if below.size else 1


def _mean_period(x: np.ndarray) -> float:
    """Mean period in samples: the reciprocal of the power spectrum's mean frequency."""
    a = x - x.mean()
    p = np.abs(np.fft.rfft(a)) ** 2
    f = np.fft.rfftfreq(a.size)
    fm = float((f[1:] * p[1:]).sum() / p[1:].sum())
    return 1.0 / fm if fm > 0 else float(a.size)


@dataclass(frozen=True)
class Divergence:
    """Rosenstein's estimate: exponent [1/s], the divergence curve <ln d(i)> against
    i dt, the fitted range (start, stop) in samples, the embedding used, and whether the
    curve rises by more than ln 10 at all (else there is no exponential divergence to fit:
    a regular signal; the slope is then not an exponent)."""

    exponent: float
    time: np.ndarray = field(repr=False)
    log_divergence: np.ndarray = field(repr=False)
    fit: tuple = (0, 0)
    dimension: int = 0
    lag: int = 0
    theiler: int = 0
    diverges: bool = True  # the neighbours' separation grows > 10x over the horizon

    def __float__(self) -> float:
        return self.exponent


def rosenstein(
    x: object,
    dt: float,
    *,
    dimension: int = 5,
    lag: int | None = None,
    theiler: int | None = None,
    horizon: int | None = None,
    fit: tuple | None = None,
    max_points: int = 20_000,
) -> Divergence:
    """Largest Lyapunov exponent [1/s] of a scalar time series by delay embedding
    (Rosenstein, Collins & De Luca, Physica D 65:117-134, 1993): embed in `dimension`
    with delay `lag` samples (default: where the autocorrelation falls below 1 - 1/e), pair
    each point with its nearest neighbour at least `theiler` samples apart in time (default:
    the mean period from the power spectrum), average ln of the pairs' separation over
    `horizon` samples ahead and fit a line over the `fit` range of that curve (default:
    from 10 % to 70 % of its rise, as (start, stop) samples). The method is biased low on
    short or noisy series and high for too small an embedding; Rosenstein's Table reports
    it within a few per cent for the Lorenz system with 5000 points. A series longer than
    max_points is decimated to at most that many samples (the neighbour search holds all
    pairs of the k nearest: memory grows with the length)."""
    a = np.asarray(x, dtype=float)
    if a.ndim != 1 or a.size < 100 or not np.all(np.isfinite(a)):
        raise ModelError("rosenstein", "x", a.shape, "expected >= 100 finite samples")
    if a.size > max_points:
        k = -(-a.size // max_points)
        a, dt = a[::k], dt * k
    if not (isinstance(dimension, (int, np.integer)) and dimension >= 1):
        raise ModelError("rosenstein", "dimension", dimension, "expected an integer >= 1")
    J = _autocorrelation_lag(a) if lag is None else int(lag)
    W = int(math.ceil(_mean_period(a))) if theiler is None else int(theiler)
    M = a.size - (dimension - 1) * J
    if J < 1 or M < 2 * W + 20:
        raise ModelError(
            "rosenstein", "x", a.size, f"too short for dimension {dimension}, lag {J}, window {W}"
        )
    X = np.column_stack([a[i * J : i * J + M] for i in range(dimension)])
    H = min(M // 4, 8 * W) if horizon is None else int(horizon)
    tree = cKDTree(X)
    k = min(M, 2 * W + 2)
    dist, idx = tree.query(X, k=k)
    far = np.abs(idx - np.arange(M)[:, None]) > W
    usable = far & (dist > 0)
    first = np.argmax(usable, axis=1)
    ok = usable[np.arange(M), first]
    # points with no neighbour among the k nearest outside the window: query them all
    nn = np.where(ok, idx[np.arange(M), first], -1)
    for i in np.flatnonzero(~ok):
        d = np.linalg.norm(X - X[i], axis=1)
        d[max(0, i - W) : i + W + 1] = np.inf
        d[d == 0] = np.inf
        nn[i] = int(np.argmin(d))
    i0 = np.arange(M)
    curve = np.empty(H)
    for h in range(H):
        valid = (i0 + h < M) & (nn + h < M)
        dd = np.linalg.norm(X[i0[valid] + h] - X[nn[valid] + h], axis=1)
        dd = dd[dd > 0]
        curve[h] = np.log(dd).mean()
    rise = float(curve.max() - curve[0])
    if fit is None:
        # the linear region: from 10 % to 70 % of the curve's rise (the first samples are
        # biased low by choosing the nearest neighbour; the end is the plateau)
        start = int(np.argmax(curve >= curve[0] + 0.1 * rise))
        stop = int(np.argmax(curve >= curve[0] + 0.7 * rise))
        stop = min(max(stop, start + 3), H)
        start = min(start, stop - 3)
        fit = (start, stop)
    s0, s1 = int(fit[0]), int(fit[1])
    if not 0 <= s0 < s1 - 1 <= H - 1:
        raise ModelError("rosenstein", "fit", fit, f"expected 0 <= start < stop - 1 < {H}")
    tt = dt * np.arange(H)
    slope = float(np.polyfit(tt[s0:s1], curve[s0:s1], 1)[0])
    return Divergence(slope, tt, curve, (s0, s1), int(dimension), J, W, rise >= math.log(10.0))


@dataclass(frozen=True)
class ZeroOne:
    """The 0-1 test: K near 0 regular, near 1 chaotic; K_c per frequency c."""

    K: float
    Kc: np.ndarray = field(repr=False)
    c: np.ndarray = field(repr=False)

    def __float__(self) -> float:
        return self.K


def zero_one_test(x: object, *, nc: int = 100, seed: int = 0, ncut: int | None = None) -> ZeroOne:
    """Gottwald-Melbourne 0-1 test for chaos, modified form (Gottwald & Melbourne, SIAM J.
    Appl. Dyn. Syst. 8:129-145, 2009, eqs. (2.1)-(2.7)): translation variables
    p_c, q_c of the observable, the mean-square displacement with its oscillatory term
    removed, K_c its correlation with n, K the median over nc random c in (pi/5, 4 pi/5).

    x must not be oversampled: feed it Poincare (once per drive period) samples or a
    series decimated to about one sample per mean period; 500-5000 samples."""
    a = np.asarray(x, dtype=float)
    if a.ndim != 1 or a.size < 100 or not np.all(np.isfinite(a)):
        raise ModelError("zero_one_test", "x", a.shape, "expected >= 100 finite samples")
    N = a.size
    nc_ = N // 10 if ncut is None else int(ncut)
    if not 2 <= nc_ <= N // 2:
        raise ModelError("zero_one_test", "ncut", ncut, f"expected an integer in [2, {N // 2}]")
    rng = np.random.default_rng(seed)
    cs = rng.uniform(math.pi / 5, 4 * math.pi / 5, int(nc))
    a = a - a.mean()
    if not np.any(a):
        return ZeroOne(0.0, np.zeros(cs.size), cs)
    j = np.arange(1, N + 1)
    n = np.arange(1, nc_ + 1)
    Kc = np.empty(cs.size)
    for m, c in enumerate(cs):
        p = np.cumsum(a * np.cos(j * c))
        q = np.cumsum(a * np.sin(j * c))
        M = np.array(
            [np.mean((p[k:] - p[:-k]) ** 2 + (q[k:] - q[:-k]) ** 2) for k in n]
        )  # (2.4) with the average over N - n terms
        # (2.5)'s oscillatory term (E phi)^2 (1 - cos nc) / (1 - cos c) is zero: the mean
        # of x was removed above, which removes that term's cause
        D = M
        if np.std(D) == 0:
            Kc[m] = 0.0
            continue
        Kc[m] = np.corrcoef(n, D)[0, 1]
    return ZeroOne(float(np.median(Kc)), Kc, cs)
