"""Independent oracle: 1-DOF two-sided impact oscillator with a compliant (Hertz) contact law.

A stand-alone second implementation (numpy + scipy only), written from a specification
without looking at the ``clearance`` package sources.

Model (SI units: m, kg, s, N)
-----------------------------
State ``y = (x, v)``; ``x`` is the position of a ball centre inside a socket, the radial
clearance is ``c`` on both sides::

    m x'' = -k x - d x' + F0 sin(w t) + f_contact,        T = 2 pi / w.

Penetration ``delta = |x| - c``; with ``s = sign(x)`` the penetration rate is
``delta_dot = s v`` (> 0 compressing). In contact (hybrid state, see below)::

    F_N = max(0, K delta^n (1 + xi delta_dot / delta_dot_minus)),   n = 1.5,
    f_contact = -s F_N,

and ``f_contact = 0`` out of contact (and also in contact while ``delta <= 0``).
``xi = 8 (1 - c_r) / (5 c_r)`` (Flores et al. 2011). ``delta_dot_minus`` is latched at the
onset: ``max(delta_dot(onset), v_floor)``, held for the whole contact and cleared at the
separation.

Hertz internal contact (ball in a socket, ``R_s = R_b + c``)::

    K = (4/3) E* sqrt(R*),  1/E* = (1 - nu_b^2)/E_b + (1 - nu_s^2)/E_s,
    R* = R_b R_s / (R_s - R_b).

Hybrid integration
------------------
The time axis is split into *pieces* with a fixed discrete state: ``free``, or ``contact``
on side ``s`` with a latched ``delta_dot_minus``. Each piece is one ``solve_ivp`` call
(``DOP853`` by default: the contact only lasts ~1e-4 s but is not stiff on that time scale,
the explicit 8th order method resolves it with a few dozen steps) with ``dense_output``.

* free: two terminal events ``x - c`` and ``-x - c``, both with direction +1 (onset on side
  +1 / -1). The next piece starts at the located event state (``delta_dot_minus`` latched
  there) with first step ``0.02 t_H``, ``t_H = (m^2 / (K^2 delta_dot))^(1/5)`` the Hertz time
  scale (scipy's automatic guess sees no contact force at ``delta = 0``).
* contact on side ``s``: one terminal event ``s x - c + h_sep`` with direction -1, where
  ``h_sep = H_SEP_REL * c`` (1e-14 m for c = 1 mm) is a tiny hysteresis: the onset state has
  ``|delta| ~ 1e-16 .. 1e-14 m`` (root-finding round-off), so the contact event function starts
  strictly positive and cannot fire at the restart time, and the following free piece starts at
  ``delta = -h_sep`` strictly below its (upward) onset surface. The force is identically zero
  for ``delta <= 0`` in both states, so the hysteresis changes no force and the trajectory is
  the same; only the recorded separation time is late by ``h_sep / |delta_dot|`` (~1e-13 s).
  (A grazing re-touch that stays within ``h_sep`` of the surface would keep the old latched
  value: physically irrelevant.)

Energy bookkeeping (``track_energy=True``): with ``E = m v^2/2 + k x^2/2 + U``,
``U = K delta_+^(n+1) / (n+1)``::

    dE/dt = F0 sin(w t) v - d v^2 - (F_N - K delta_+^n) delta_dot   (in contact)

The integrals ``W = int F0 sin(wt) v``, ``D_d = int d v^2`` and
``D_c = int (F_N - K delta^n) delta_dot`` are integrated with the state and
``residual = E(t) - E(t0) - W + D_d + D_c`` should stay at round-off level.

Stroboscopic map / Lyapunov exponent
------------------------------------
``t_j = t0 + j T``. The period map ``P`` integrates ``periods`` drive periods from ``t0``
with a *fresh* hybrid state (``free`` if ``|x| <= c``). For a start point out of contact and an
orbit whose impacts are transversal (no grazing) ``P`` is smooth near the orbit, and its
Jacobian (monodromy matrix) is obtained by central finite differences. A start point in contact
needs the latched value ``vminus`` (held fixed for all perturbed starts), otherwise a
``ValueError`` is raised; shift ``t0`` to an out-of-contact phase instead.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_ivp

#: Hertz exponent.
N_HERTZ = 1.5
#: Separation hysteresis relative to the clearance (see the module docstring).
H_SEP_REL = 1.0e-11


# --------------------------------------------------------------------------------------
# Parameters
# --------------------------------------------------------------------------------------
def hertz_internal_stiffness(
    R_b: float,
    c: float,
    E_b: float = 207e9,
    nu_b: float = 0.3,
    E_s: float = 207e9,
    nu_s: float = 0.3,
) -> float:
    """Hertz stiffness ``K = (4/3) E* sqrt(R*)`` [N/m^1.5] of a ball (R_b) in a socket (R_b + c).

    Steel, ``R_b = 15 mm``, ``c = 0.3 mm`` gives ``K ~ 1.326e11``.
    """
    R_s = R_b + c
    E_star = 1.0 / ((1.0 - nu_b**2) / E_b + (1.0 - nu_s**2) / E_s)
    R_star = R_b * R_s / (R_s - R_b)
    return 4.0 / 3.0 * E_star * math.sqrt(R_star)


def flores_xi(c_r: float) -> float:
    """Flores et al. (2011) hysteresis factor ``xi = 8 (1 - c_r) / (5 c_r)``."""
    return 8.0 * (1.0 - c_r) / (5.0 * c_r)


@dataclass(frozen=True)
class ImpactOscillator:
    """Parameters of the two-sided impact oscillator (SI units)."""

    m: float  # mass [kg]
    k: float  # spring stiffness [N/m]
    d: float  # viscous damping [N s/m]
    F0: float  # forcing amplitude [N]
    w: float  # forcing angular frequency [rad/s]
    c: float  # radial clearance [m]
    K: float  # Hertz stiffness [N/m^1.5]
    c_r: float  # coefficient of restitution [-]
    v_floor: float = 1.0e-4  # floor of the latched onset speed [m/s]

    @property
    def T(self) -> float:
        """Drive period ``2 pi / w`` [s]."""
        return 2.0 * math.pi / self.w

    @property
    def xi(self) -> float:
        """Flores hysteresis factor."""
        return flores_xi(self.c_r)

    @property
    def h_sep(self) -> float:
        """Separation hysteresis [m]."""
        return H_SEP_REL * self.c


# --------------------------------------------------------------------------------------
# Right-hand side
# --------------------------------------------------------------------------------------
def _contact(osc: ImpactOscillator, x: float, v: float, side: int, vminus: float):
    """``(F_N, F_elastic, delta, delta_dot)`` in the contact state on ``side`` (0 = free)."""
    if side == 0:
        return 0.0, 0.0, abs(x) - osc.c, (v if x >= 0.0 else -v)
    delta = side * x - osc.c
    ddot = side * v
    if delta <= 0.0:
        return 0.0, 0.0, delta, ddot
    fel = osc.K * delta * math.sqrt(delta)  # n = 1.5 (inf instead of OverflowError)
    fn = fel * (1.0 + osc.xi * ddot / vminus)
    return (fn if fn > 0.0 else 0.0), fel, delta, ddot


def _make_rhs(osc: ImpactOscillator, side: int, vminus: float, track_energy: bool):
    m, k, d, F0, w = osc.m, osc.k, osc.d, osc.F0, osc.w

    if not track_energy:

        def rhs(t, y):
            x, v = y[0], y[1]
            fn = _contact(osc, x, v, side, vminus)[0]
            return np.array([v, (-k * x - d * v + F0 * math.sin(w * t) - side * fn) / m])

        return rhs

    def rhs_e(t, y):
        x, v = y[0], y[1]
        fn, fel, _, ddot = _contact(osc, x, v, side, vminus)
        fd = F0 * math.sin(w * t)
        a = (-k * x - d * v + fd - side * fn) / m
        return np.array([v, a, fd * v, d * v * v, (fn - fel) * ddot])

    return rhs_e


def energy(osc: ImpactOscillator, x, v):
    """Mechanical energy ``m v^2/2 + k x^2/2 + K delta_+^2.5 / 2.5`` [J] (vectorised)."""
    x = np.asarray(x, dtype=float)
    v = np.asarray(v, dtype=float)
    dp = np.maximum(np.abs(x) - osc.c, 0.0)
    return 0.5 * osc.m * v**2 + 0.5 * osc.k * x**2 + osc.K * dp ** (N_HERTZ + 1) / (N_HERTZ + 1)


# --------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------
class Onset(NamedTuple):
    """A contact onset: time, position, penetration rate, side, latched ``delta_dot_minus``."""

    t: float
    x: float
    delta_dot: float
    side: int
    vminus: float


class Separation(NamedTuple):
    """A separation (located at ``delta = -h_sep``): time, penetration rate (< 0), side."""

    t: float
    delta_dot: float
    side: int


@dataclass
class Piece:
    """One integration piece with fixed discrete state (``side`` 0 = free)."""

    t0: float
    t1: float
    sol: object  # scipy OdeSolution on [t0, t1]
    side: int
    vminus: float


@dataclass
class SimulationResult:
    """Hybrid trajectory with dense output.

    ``pieces``: list of :class:`Piece` covering ``[t_start, t_end]`` contiguously;
    ``onsets`` / ``separations``: located events; ``t`` / ``y``: samples at ``t_eval``
    (``y`` shape (len, 2)) or ``None``; ``stats``: pieces, RHS calls, wall time [s].
    """

    osc: ImpactOscillator
    t_start: float
    t_end: float
    pieces: list = field(default_factory=list)
    onsets: list = field(default_factory=list)
    separations: list = field(default_factory=list)
    t: np.ndarray | None = None
    y: np.ndarray | None = None
    track_energy: bool = False
    stats: dict = field(default_factory=dict)

    @property
    def n_impacts(self) -> int:
        """Number of contact onsets."""
        return len(self.onsets)

    def _piece_index(self, t: np.ndarray) -> np.ndarray:
        starts = np.array([p.t0 for p in self.pieces])
        idx = np.searchsorted(starts, t, side="right") - 1
        return np.clip(idx, 0, len(self.pieces) - 1)

    def _full(self, t) -> np.ndarray:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if np.any(t < self.t_start - 1e-12 * max(1.0, abs(self.t_start))) or np.any(
            t > self.t_end + 1e-12 * max(1.0, abs(self.t_end))
        ):
            raise ValueError("t outside the simulated interval")
        idx = self._piece_index(t)
        nc = 5 if self.track_energy else 2
        out = np.empty((t.size, nc))
        for i in np.unique(idx):
            sel = idx == i
            out[sel] = np.asarray(self.pieces[i].sol(t[sel])).T.reshape(-1, nc)
        return out

    def state(self, t) -> np.ndarray:
        """``(x, v)`` at the times ``t`` from the dense output: shape (len(t), 2), or (2,).

        A time equal to an event time is taken from the piece that starts there (the state is
        continuous, both pieces agree to the integration tolerance).
        """
        scalar = np.ndim(t) == 0
        out = self._full(t)[:, :2]
        return out[0] if scalar else out

    def discrete_state(self, t):
        """``(side, vminus)`` arrays of the hybrid state at times ``t`` (side 0 = free)."""
        idx = self._piece_index(np.atleast_1d(np.asarray(t, dtype=float)))
        side = np.array([self.pieces[i].side for i in idx])
        vm = np.array([self.pieces[i].vminus for i in idx])
        return side, vm

    def contact_force(self, t) -> np.ndarray:
        """Normal force magnitude ``F_N`` [N] at the times ``t``."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        y = self._full(t)
        side, vm = self.discrete_state(t)
        rows = zip(y, side, vm, strict=True)
        return np.array([_contact(self.osc, yy[0], yy[1], int(s), v)[0] for yy, s, v in rows])

    def energy_balance(self, t) -> dict:
        """Energy terms at the times ``t`` (needs ``track_energy=True``).

        Returns ``E`` (mechanical energy incl. contact potential), ``W`` (forcing work),
        ``D_d`` (viscous dissipation), ``D_c`` (contact hysteresis dissipation) and
        ``residual = E - E(t_start) - W + D_d + D_c``.
        """
        if not self.track_energy:
            raise ValueError("simulate(..., track_energy=True) is needed")
        y = self._full(t)
        E = energy(self.osc, y[:, 0], y[:, 1])
        E0 = float(energy(self.osc, *self.pieces[0].sol(self.t_start)[:2]))
        W, Dd, Dc = y[:, 2], y[:, 3], y[:, 4]
        return {"E": E, "W": W, "D_d": Dd, "D_c": Dc, "residual": E - E0 - W + Dd + Dc}


# --------------------------------------------------------------------------------------
# Simulation
# --------------------------------------------------------------------------------------
def _hertz_time(osc: ImpactOscillator, vin: float) -> float:
    """Hertz contact time scale ``(m^2 / (K^2 vin))^(1/5)`` [s] (duration ~ 3.2 of these)."""
    return (osc.m**2 / (osc.K**2 * max(vin, osc.v_floor))) ** 0.2


def simulate(
    osc: ImpactOscillator,
    t_end: float,
    x0: float = 0.0,
    v0: float = 0.0,
    rtol: float = 1e-11,
    atol: float = 1e-14,
    t_eval=None,
    *,
    t0: float = 0.0,
    vminus0: float | None = None,
    method: str = "DOP853",
    track_energy: bool = False,
    max_pieces: int = 1_000_000,
) -> SimulationResult:
    """Integrate the hybrid system from ``(x0, v0)`` at ``t0`` to ``t_end``.

    Initial discrete state: contact on side ``sign(x0)`` if ``|x0| > c`` (latched value
    ``vminus0`` if given, else ``max(delta_dot(t0), v_floor)``, i.e. ``t0`` is treated as
    the onset, which is not recorded in ``onsets``), otherwise free.
    ``atol`` applies to ``x`` and ``v`` (and the energy integrals if ``track_energy``).
    ``method``: ``"DOP853"`` (default) or ``"Radau"`` etc.
    """
    tic = time.perf_counter()
    if t_end < t0:
        raise ValueError("t_end < t0")
    res = SimulationResult(osc=osc, t_start=float(t0), t_end=float(t_end))
    res.track_energy = track_energy
    h_sep = osc.h_sep
    y = np.array([x0, v0] + ([0.0, 0.0, 0.0] if track_energy else []), dtype=float)
    if abs(x0) > osc.c:
        side = 1 if x0 > 0.0 else -1
        vminus = float(vminus0 if vminus0 is not None else max(side * v0, osc.v_floor))
    else:
        side, vminus = 0, 0.0

    def ev_on_plus(t, yy):
        return yy[0] - osc.c

    def ev_on_minus(t, yy):
        return -yy[0] - osc.c

    for ev in (ev_on_plus, ev_on_minus):
        ev.terminal = True
        ev.direction = 1.0

    def ev_sep_plus(t, yy):
        return yy[0] - osc.c + h_sep

    def ev_sep_minus(t, yy):
        return -yy[0] - osc.c + h_sep

    for ev in (ev_sep_plus, ev_sep_minus):
        ev.terminal = True
        ev.direction = -1.0

    t = float(t0)
    nfev = 0
    first_step = None
    if side != 0:
        first_step = 0.02 * _hertz_time(osc, abs(v0))
    if t_end == t:
        y_keep = y.copy()

        def _const(tt):
            return np.repeat(y_keep[:, None], np.size(tt), axis=1).reshape(y_keep.size, -1)

        res.pieces.append(Piece(t, t, _const, side, vminus))
    while t < t_end:
        if len(res.pieces) >= max_pieces:
            raise RuntimeError("too many pieces")
        if side == 0:
            events = [ev_on_plus, ev_on_minus]
        else:
            events = [ev_sep_plus if side > 0 else ev_sep_minus]
        rhs = _make_rhs(osc, side, vminus, track_energy)
        if first_step is not None:
            first_step = min(first_step, max(t_end - t, 0.0)) or None
        with np.errstate(over="ignore", invalid="ignore"):
            sol = solve_ivp(
                rhs,
                (t, t_end),
                y,
                method=method,
                rtol=rtol,
                atol=atol,
                dense_output=True,
                events=events,
                first_step=first_step,
            )
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed at t = {t}: {sol.message}")
        nfev += sol.nfev
        t_new = float(sol.t[-1])
        res.pieces.append(Piece(t, t_new, sol.sol, side, vminus))
        if sol.status == 0:
            break
        # Terminal event.
        fired = [i for i, te in enumerate(sol.t_events) if te.size]
        i_ev = fired[0]
        t_ev = float(sol.t_events[i_ev][-1])
        y = np.array(sol.y_events[i_ev][-1], dtype=float)
        if side == 0:
            side = 1 if i_ev == 0 else -1
            ddot = side * y[1]
            vminus = float(max(ddot, osc.v_floor))
            res.onsets.append(Onset(t_ev, float(y[0]), float(ddot), side, vminus))
            first_step = 0.02 * _hertz_time(osc, ddot)
        else:
            res.separations.append(Separation(t_ev, float(side * y[1]), side))
            side, vminus = 0, 0.0
            first_step = None
        t = t_ev
    if t_eval is not None:
        te = np.asarray(t_eval, dtype=float)
        res.t = te
        res.y = res.state(te).reshape(-1, 2)
    res.stats = {
        "pieces": len(res.pieces),
        "nfev": nfev,
        "wall": time.perf_counter() - tic,
    }
    return res


# --------------------------------------------------------------------------------------
# Stroboscopic map and impacts
# --------------------------------------------------------------------------------------
def strobe_points(result: SimulationResult, j_from: int, j_to: int) -> np.ndarray:
    """``(x, v)`` at ``t_j = t_start + j T`` for ``j = j_from .. j_to`` (inclusive)."""
    T = result.osc.T
    tj = result.t_start + np.arange(j_from, j_to + 1) * T
    tj = np.minimum(tj, result.t_end)  # round-off at the last point
    return result.state(tj).reshape(-1, 2)


def strobe(
    osc: ImpactOscillator,
    periods: int,
    transient_periods: int,
    x0: float = 0.0,
    v0: float = 0.0,
    **kw,
) -> np.ndarray:
    """Stroboscopic points ``(x, v)`` at ``t = j T``, ``j = transient_periods .. periods``.

    Integrates ``[0, periods T]`` with :func:`simulate` (``**kw`` passed on) and evaluates
    the dense output exactly at ``t_j = j * (2 pi / w)``. Returns an array of shape
    ``(periods - transient_periods + 1, 2)`` (both ends included).
    """
    res = simulate(osc, periods * osc.T, x0, v0, **kw)
    return strobe_points(res, transient_periods, periods)


@dataclass
class ImpactTable:
    """Onsets in ``[t_from, t_to)``; all arrays have one entry per onset.

    ``t``: onset times; ``phase``: ``(t - t_start) mod T`` in ``[0, T)`` [s];
    ``phase_rad``: ``w * phase``; ``delta_dot``: onset penetration rates (> 0); ``side``: +1/-1;
    ``x``: onset positions; ``period_index``: ``floor((t - t_start) / T)``; ``counts``:
    onsets per period for the periods ``j_from .. j_to - 1``; ``periods``: those indices.
    """

    t: np.ndarray
    phase: np.ndarray
    phase_rad: np.ndarray
    delta_dot: np.ndarray
    side: np.ndarray
    x: np.ndarray
    period_index: np.ndarray
    counts: np.ndarray
    periods: np.ndarray


def impact_table(result: SimulationResult, j_from: int, j_to: int | None = None) -> ImpactTable:
    """Onsets of ``result`` in the periods ``j_from .. j_to - 1`` (``t_j = t_start + j T``)."""
    T = result.osc.T
    if j_to is None:
        j_to = int(round((result.t_end - result.t_start) / T))
    ons = [o for o in result.onsets if j_from * T <= o.t - result.t_start < j_to * T]
    t = np.array([o.t for o in ons], dtype=float)
    rel = t - result.t_start
    pidx = np.floor(rel / T).astype(int)
    phase = rel - pidx * T
    periods = np.arange(j_from, j_to)
    counts = np.array([int(np.sum(pidx == j)) for j in periods], dtype=int)
    return ImpactTable(
        t=t,
        phase=phase,
        phase_rad=result.osc.w * phase,
        delta_dot=np.array([o.delta_dot for o in ons], dtype=float),
        side=np.array([o.side for o in ons], dtype=int),
        x=np.array([o.x for o in ons], dtype=float),
        period_index=pidx,
        counts=counts,
        periods=periods,
    )


def impacts_per_period(
    osc: ImpactOscillator,
    periods: int,
    transient_periods: int,
    x0: float = 0.0,
    v0: float = 0.0,
    **kw,
) -> ImpactTable:
    """Simulate ``[0, periods T]`` and tabulate the onsets of periods ``transient .. periods-1``.

    For a periodic impacting orbit, ``counts`` is constant and ``phase`` / ``delta_dot``
    repeat with the orbit's period (compare e.g. ``table.phase[-q:]``, ``table.delta_dot[-q:]``
    for ``q`` impacts per period).
    """
    res = simulate(osc, periods * osc.T, x0, v0, **kw)
    return impact_table(res, transient_periods, periods)


def detect_period(points, rtol: float = 1e-6, max_period: int | None = None) -> int:
    """Smallest ``p`` with ``points[j + p] ~ points[j]`` for all ``j`` (0 if none found).

    ``points``: stroboscopic points, shape (N, 2); the tolerance is relative to the per-column
    range (or absolute magnitude) of the points.
    """
    P = np.asarray(points, dtype=float)
    n = P.shape[0]
    scale = np.maximum(np.max(np.abs(P), axis=0), 1e-300)
    max_period = max_period or n // 2
    for p in range(1, max_period + 1):
        if n - p < 1:
            break
        if np.all(np.abs(P[p:] - P[:-p]) <= rtol * scale):
            return p
    return 0


# --------------------------------------------------------------------------------------
# Period map, fixed points, Lyapunov exponent
# --------------------------------------------------------------------------------------
def period_map(
    osc: ImpactOscillator,
    y,
    t0: float = 0.0,
    periods: int = 1,
    *,
    vminus: float | None = None,
    rtol: float = 1e-12,
    atol: float = 1e-16,
    method: str = "DOP853",
) -> np.ndarray:
    """``P(y)``: state after ``periods`` drive periods from ``y`` at ``t0`` (fresh hybrid state).

    A start point in contact (``|x| > c``) needs the latched ``vminus`` (else ``ValueError``).
    """
    y = np.asarray(y, dtype=float)
    if abs(y[0]) > osc.c and vminus is None:
        raise ValueError(
            "start point in contact: pass the latched vminus or choose an out-of-contact t0"
        )
    res = simulate(
        osc,
        t0 + periods * osc.T,
        y[0],
        y[1],
        rtol=rtol,
        atol=atol,
        t0=t0,
        vminus0=vminus,
        method=method,
    )
    return res.state(res.t_end)


def _state_scale(osc: ImpactOscillator, y) -> np.ndarray:
    return np.array([max(abs(y[0]), osc.c), max(abs(y[1]), osc.w * osc.c)])


def monodromy_fd(
    osc: ImpactOscillator,
    y_star,
    t0: float = 0.0,
    periods: int = 1,
    *,
    eps: float = 1e-6,
    scale=None,
    vminus: float | None = None,
    **kw,
) -> tuple[np.ndarray, np.ndarray]:
    """Central-difference Jacobian of the ``periods``-period map at ``y_star``.

    Perturbation of component ``i``: ``h_i = eps * scale_i`` with the default state scale
    ``(max(|x|, c), max(|v|, w c))``. The FD noise is ~ ``rtol / eps``: with the default
    ``rtol = 1e-12`` of :func:`period_map`, ``eps = 1e-6`` gives ~1e-7 relative accuracy of the
    exponent (``eps = 1e-7``: ~3e-6). Returns ``(J, P(y_star))``.
    """
    y_star = np.asarray(y_star, dtype=float)
    sc = _state_scale(osc, y_star) if scale is None else np.asarray(scale, dtype=float)
    J = np.empty((2, 2))
    for i in range(2):
        h = eps * sc[i]
        yp, ym = y_star.copy(), y_star.copy()
        yp[i] += h
        ym[i] -= h
        fp = period_map(osc, yp, t0, periods, vminus=vminus, **kw)
        fm = period_map(osc, ym, t0, periods, vminus=vminus, **kw)
        J[:, i] = (fp - fm) / (2.0 * h)
    return J, period_map(osc, y_star, t0, periods, vminus=vminus, **kw)


def find_fixed_point(
    osc: ImpactOscillator,
    y_guess,
    t0: float = 0.0,
    periods: int = 1,
    *,
    tol: float = 1e-12,
    maxiter: int = 20,
    **kw,
) -> tuple[np.ndarray, dict]:
    """Newton iteration on ``P(y) - y = 0`` (FD Jacobian) from ``y_guess``.

    ``tol`` is relative to the state scale. Returns ``(y_star, info)`` with ``info`` keys
    ``converged``, ``iterations``, ``residual`` (scaled ``|P(y*) - y*|``), ``J``.
    """
    y = np.asarray(y_guess, dtype=float).copy()
    sc = _state_scale(osc, y)
    info = {"converged": False, "iterations": 0, "residual": np.inf, "J": None}
    for it in range(1, maxiter + 1):
        J, Py = monodromy_fd(osc, y, t0, periods, **kw)
        r = Py - y
        info.update(iterations=it, residual=float(np.max(np.abs(r) / sc)), J=J)
        if info["residual"] < tol:
            info["converged"] = True
            break
        y = y - np.linalg.solve(J - np.eye(2), r)
    return y, info


class LyapunovResult(NamedTuple):
    """Largest Lyapunov exponent of a periodic orbit from its monodromy matrix."""

    lambda_max: float  # ln(max |eig|) / (periods T) [1/s]
    eigenvalues: np.ndarray  # Floquet multipliers
    monodromy: np.ndarray  # 2x2 Jacobian of the periods-period map
    fixed_point_residual: float  # max_i |P(y*) - y*|_i / scale_i
    determinant: float


def lyapunov_fd(
    osc: ImpactOscillator,
    y_star,
    t0: float = 0.0,
    periods: int = 1,
    *,
    eps: float = 1e-6,
    scale=None,
    vminus: float | None = None,
    **kw,
) -> LyapunovResult:
    """Largest Lyapunov exponent of the periodic orbit through ``y_star`` at ``t0``.

    ``lambda_max = ln(max |eig(M)|) / (periods T)``, ``M`` the central-difference monodromy
    matrix of the ``periods``-period stroboscopic map (see :func:`monodromy_fd`; ``**kw``:
    ``rtol``, ``atol``, ``method`` of :func:`period_map`). ``y_star`` should be a fixed point
    (see :func:`find_fixed_point`); the residual is reported. A start point in contact needs
    ``vminus`` (the latched value, held fixed for the perturbed starts).
    """
    y_star = np.asarray(y_star, dtype=float)
    J, Py = monodromy_fd(osc, y_star, t0, periods, eps=eps, scale=scale, vminus=vminus, **kw)
    eig = np.linalg.eigvals(J)
    sc = _state_scale(osc, y_star)
    return LyapunovResult(
        lambda_max=float(np.log(np.max(np.abs(eig))) / (periods * osc.T)),
        eigenvalues=eig,
        monodromy=J,
        fixed_point_residual=float(np.max(np.abs(Py - y_star) / sc)),
        determinant=float(np.linalg.det(J)),
    )


# --------------------------------------------------------------------------------------
# Self-checks
# --------------------------------------------------------------------------------------
def free_impact_restitution(
    c_r: float = 0.9,
    v_in: float = 0.1,
    m: float = 1.0,
    K: float = 5.0e10,
    c: float = 1.0e-3,
    v_floor: float = 1.0e-4,
    **kw,
) -> float:
    """Apparent restitution ``|v_out| / v_in`` of one free impact (``k = d = F0 = 0``).

    The ball starts at the centre with speed ``v_in`` toward ``+c`` and the run stops well
    after the first separation. For ``v_in >> v_floor`` the ratio only depends on ``c_r``.
    """
    osc = ImpactOscillator(m=m, k=0.0, d=0.0, F0=0.0, w=1.0, c=c, K=K, c_r=c_r, v_floor=v_floor)
    t_end = c / v_in + 50.0 * _hertz_time(osc, v_in) + 0.5 * c / v_in
    res = simulate(osc, t_end, 0.0, v_in, **kw)
    if not res.separations:
        raise RuntimeError("no separation")
    return -res.separations[0].delta_dot / res.onsets[0].delta_dot
