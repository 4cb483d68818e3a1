"""Contact events of clearance joints, compiled (physics.md d.5, f.5).

Onset (delta of a contact point crosses 0 upward) and separation (downward) are located on
the dense output of an accepted step, given as data: the continuous extension
y(t + x h) = y + h sum_k K[k] b_k(x), b_k(x) = P[k, 0] x + P[k, 1] x^2 + ... of the method
that made the step (tableau.py layout; any explicit Runge-Kutta method has one). delta is
sampled at interior points of the step, and a sign change is bracketed and refined (Illinois
regula falsi) until the bracket is narrower than the integrator's rtol times the step (a
time tolerance: event times and latched impact velocities converge with rtol) and
|delta| <= the point's tolerance (cp_geo[p, PG_TOL]: onset_tolerance times the joint's
clearance), on the far side of the crossing. A graze (a contact that begins and ends
between two probes, every probe on the same side) is looked for on the quartic through the
five probes, bump by bump in time, and confirmed by a probe of the gap at its extremum; it
is found when one of the quartic's evaluation points (8 per probe interval) falls inside
it. Every joint's probes are taken even after an earlier joint's event in the step. The
step is then cut at the event, and `update_contacts` applies the discrete update (contact
flag; impact velocity latched, floored; LuGre bristles zeroed at onset and separation) and
logs the event.

A probe of delta needs only the joint's two bodies: it interpolates their 7 + 7 position
entries and evaluates only the slide functions of moving centres (the full state and all
bodies cost ~10x more per probe). The arithmetic is that of `interpolate` + `body_states`
+ the contact kernels, so the events found are bit-for-bit those of full-state probes.

Event log columns (layout.EVENT_COLUMNS): t [s], contact point index, kind (+1 onset, -1
separation), delta_dot [m/s], the joint's eccentricity (3) in the outer marker frame [m].
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.contact.element import eccentricity, gap_of, point_contact, point_gap
from clearance.contact.laws import normal_force
from clearance.dynamics.rhs import rhs
from clearance.kinds import (
    CG_C,
    CG_VFLOOR,
    CI_BB,
    CI_BS,
    CI_MVS,
    CI_NP,
    CI_P0,
    PG_TOL,
    PG_W,
    PI_LAW,
    ST_NFEV,
)
from clearance.kinematics.rotations import quat_to_rot
from clearance.kinematics.timefn import eval_timefn
from clearance.layout import CO_DELTA, CO_FN

# interior samples of a step at which delta is checked before bracketing a crossing
# (4: the graze search fits a quartic through the 5 probes)
_NSAMPLE = 4
# points per probe interval at which the graze search evaluates the quartic
_NGRAZE = 8


@njit(cache=True, error_model="numpy", _nrt=False)
def dense_weights(P, x, w):
    """Dense-output weights w[k] = b_k(x) = P[k, 0] x + P[k, 1] x^2 + ... of the stages
    (P: (stages, degree), tableau.py layout; w: (>= stages,) scratch)."""
    for k in range(P.shape[0]):
        xp = x
        acc = P[k, 0] * xp
        for j in range(1, P.shape[1]):
            xp = xp * x
            acc = acc + P[k, j] * xp
        w[k] = acc


@njit(cache=True, error_model="numpy", _nrt=False)
def interpolate(y, K, P, h, x, out, w):
    """Dense output at t + x h into out: y + h sum_k K[k] b_k(x), the continuous extension P
    of the method whose stages K made the step from y (tableau.py layout; w: scratch of
    the weights). Summed over the stages in order for each entry (the loops over the
    entries vectorise; out must not alias y or K)."""
    dense_weights(P, x, w)
    a = w[0]
    for i in range(y.shape[0]):
        out[i] = K[0, i] * a
    for k in range(1, P.shape[0]):
        a = w[k]
        for i in range(y.shape[0]):
            out[i] += K[k, i] * a
    for i in range(y.shape[0]):
        out[i] = y[i] + h * out[i]


@njit(cache=True, error_model="numpy", _nrt=False)
def _set_body(model, wk, b, y, r0, r1, r2, p0, p1, p2, p3, vel):
    """wk.bA[b], wk.br[b] from (r, p) and, if vel, wk.brd[b], wk.bw[b] from y's velocities:
    the operations of `body_states` for one body. The ground (b < 0) keeps its fixed slot."""
    if b < 0:
        return
    A = wk.bA[b]
    quat_to_rot(p0, p1, p2, p3, A)
    wk.br[b, 0] = r0
    wk.br[b, 1] = r1
    wk.br[b, 2] = r2
    if vel:
        v = model.y_iv + 6 * b
        for a in range(3):
            wk.brd[b, a] = y[v + a]
            wk.bw[b, a] = A[a, 0] * y[v + 3] + A[a, 1] * y[v + 4] + A[a, 2] * y[v + 5]


@njit(cache=True, error_model="numpy", _nrt=False)
def _pose_at(model, wk, b, y, vel):
    """Body b at the state y (see _set_body)."""
    if b < 0:
        return
    q = 7 * b
    _set_body(
        model, wk, b, y, y[q], y[q + 1], y[q + 2], y[q + 3], y[q + 4], y[q + 5], y[q + 6], vel
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def _pose_interp(model, wk, b, y, K, P, h, x):
    """Body b at t + x h on the dense output: `interpolate` restricted to its 7 entries."""
    if b < 0:
        return
    q = 7 * b
    w = wk.dw
    dense_weights(P, x, w)
    nk = P.shape[0]
    _set_body(
        model,
        wk,
        b,
        y,
        _interp1(y, K, h, q, w, nk),
        _interp1(y, K, h, q + 1, w, nk),
        _interp1(y, K, h, q + 2, w, nk),
        _interp1(y, K, h, q + 3, w, nk),
        _interp1(y, K, h, q + 4, w, nk),
        _interp1(y, K, h, q + 5, w, nk),
        _interp1(y, K, h, q + 6, w, nk),
        np.bool_(False),
    )


@njit(cache=True, inline="always", error_model="numpy")
def _interp1(y, K, h, i, w, nk):
    """Entry i of the dense output with the weights w of its nk stages (the arithmetic of
    `interpolate`, to the bit)."""
    acc = K[0, i] * w[0]
    for k in range(1, nk):
        acc += K[k, i] * w[k]
    return y[i] + h * acc


@njit(cache=True, error_model="numpy", _nrt=False)
def _slides(model, wk, k, t):
    """wk.fval of the slide functions of joint k's moving centres (if any) at t."""
    for side in range(2):
        fn = model.clr_ix[k, CI_MVS + side]
        if fn >= 0:
            f, fd, fdd = eval_timefn(
                model.fn_kind[fn], model.fn_data, model.fn_ptr[fn], model.fn_ptr[fn + 1], t
            )
            wk.fval[fn, 0] = f
            wk.fval[fn, 1] = fd
            wk.fval[fn, 2] = fdd


@njit(cache=True, inline="always", error_model="numpy")
def _place(model, wk, k, t, y, K, P, h, x):
    """The two bodies of clearance joint k at t + x h on the dense output (x = 0: y)."""
    if x == 0.0:
        _pose_at(model, wk, model.clr_ix[k, CI_BS], y, np.bool_(False))
        _pose_at(model, wk, model.clr_ix[k, CI_BB], y, np.bool_(False))
        _slides(model, wk, k, t)
    else:
        _pose_interp(model, wk, model.clr_ix[k, CI_BS], y, K, P, h, x)
        _pose_interp(model, wk, model.clr_ix[k, CI_BB], y, K, P, h, x)
        _slides(model, wk, k, t + x * h)


@njit(cache=True, error_model="numpy", _nrt=False)
def _wants(flag, d):
    """True if delta d contradicts the contact flag (an event happened)."""
    return (flag == 0 and d > 0.0) or (flag == 1 and d < 0.0)


@njit(cache=True, error_model="numpy", _nrt=False)
def _refine(model, wk, cs, p, k, t, y, K, P, h, xlo, dlo, xhi, dhi, xtol):
    """Illinois regula falsi on delta_p(x) over [xlo, xhi] (a crossing inside); returns x
    on the far side, the bracket narrower than xtol (the time tolerance, in steps) and
    |delta| <= the point's tolerance (or a bracket below 1e-14)."""
    flag = cs.flag[p]
    tol = model.cp_geo[p, PG_TOL]
    xtol = max(xtol, 1e-14)
    side = 0
    for _ in range(100):
        if (abs(dhi) <= tol and xhi - xlo <= xtol) or xhi - xlo < 1e-14:
            break
        if dhi != dlo:
            xm = xhi - dhi * (xhi - xlo) / (dhi - dlo)
        else:
            xm = 0.5 * (xlo + xhi)
        if not (xlo < xm < xhi):
            xm = 0.5 * (xlo + xhi)
        _place(model, wk, k, t, y, K, P, h, xm)
        dm = point_gap(model, p, wk.bA, wk.br, wk.fval)
        if _wants(flag, dm):
            xhi = xm
            dhi = dm
            if side == 1:
                dlo *= 0.5
            side = 1
        else:
            xlo = xm
            dlo = dm
            if side == -1:
                dhi *= 0.5
            side = -1
    return xhi


@njit(cache=True, error_model="numpy", _nrt=False)
def locate_event(model, wk, cs, t, y, K, P, h, xtol):
    """Earliest contact event inside the step (x in (0, 1]) and its contact point, or
    (2.0, -1); delta is probed on the dense output (y, K, P, h) of the step's method.

    The returned x is on the far side of the crossing, at most xtol (a fraction of the
    step: the integrator's rtol, so that event times converge with it) past the root, with
    |delta| <= the point's tolerance (or the bracket is below 1e-14 of the step), so the
    discrete update applies there, with the approach velocity of the crossing.
    """
    xbest = 2.0
    pbest = -1
    d = wk.ev_d  # (ncp, _NSAMPLE + 1): the gaps at the probes x = j / _NSAMPLE
    for k in range(model.nclr):
        p0 = model.clr_ix[k, CI_P0]
        p1 = p0 + model.clr_ix[k, CI_NP]
        # every probe of every joint (an event of an earlier joint does not end the search:
        # this joint's may come first, between probes); one call site of the inlined
        # point_gap (each inlined copy costs seconds of cold compile)
        for j in range(_NSAMPLE + 1):
            _place(model, wk, k, t, y, K, P, h, j / _NSAMPLE)
            for p in range(p0, p1):
                d[p, j] = point_gap(model, p, wk.bA, wk.br, wk.fval)
        for p in range(p0, p1):
            flag = cs.flag[p]
            # the first probe interval whose end contradicts the flag (a crossing)
            jc = _NSAMPLE + 1
            for j in range(1, _NSAMPLE + 1):
                if _wants(flag, d[p, j]):
                    jc = j
                    break
            # a graze (in and out between two probes) before it, on the quartic
            xs = 0.0
            xend = min((jc - 1) / _NSAMPLE, xbest)
            for _ in range(_NSAMPLE * _NGRAZE):
                xg = _graze(d[p], flag, xs, xend)
                if xg >= xend:
                    break
                _place(model, wk, k, t, y, K, P, h, xg)
                dg = point_gap(model, p, wk.bA, wk.br, wk.fval)
                if _wants(flag, dg):
                    jlo = int(xg * _NSAMPLE)
                    xlo = jlo / _NSAMPLE
                    xp = _refine(model, wk, cs, p, k, t, y, K, P, h, xlo, d[p, jlo], xg, dg, xtol)
                    if xp < xbest:
                        xbest = xp
                        pbest = p
                    jc = _NSAMPLE + 1  # (found before any crossing)
                    break
                xs = xg  # the quartic's bump, not the gap's: look further on
            if jc <= _NSAMPLE and (jc - 1) / _NSAMPLE < xbest:
                xlo, xhi = (jc - 1) / _NSAMPLE, jc / _NSAMPLE
                xp = _refine(
                    model, wk, cs, p, k, t, y, K, P, h, xlo, d[p, jc - 1], xhi, d[p, jc], xtol
                )
                if xp < xbest:
                    xbest = xp
                    pbest = p
    return xbest, pbest


@njit(cache=True, error_model="numpy", _nrt=False)
def _graze(s, flag, xstart, xend):
    """The first bump of the quartic through the probes s (at x = j / _NSAMPLE) after
    xstart and before xend that contradicts the flag (flag 0: above zero, 1: below), at
    its extremum; xend if none. A contact that begins and ends between two probes (a
    graze) leaves every probe on the same side; the quartic, exact for gaps that are
    quartic in x, finds such bumps when the evaluation points (_NGRAZE per probe interval)
    fall inside them."""
    n = _NSAMPLE * _NGRAZE
    inside, best, xb = False, 0.0, xend
    for i in range(1, n):
        x = i / n
        if x <= xstart or i % _NGRAZE == 0:
            continue  # (before the start, or a probe)
        if x >= xend:
            break
        q = 0.0
        for j in range(_NSAMPLE + 1):  # Lagrange basis on the probes
            q += _LAGRANGE[i, j] * s[j]
        v = q if flag == 0 else -q
        if v > 0.0:
            if not inside or v > best:
                inside, best, xb = True, v, x
        elif inside:  # past the first bump: its extremum
            break
    return xb


def _lagrange_tables(n_sample: int, n_graze: int) -> tuple[np.ndarray, np.ndarray]:
    """L[i, j] and dL[i, j]: the Lagrange basis polynomial of probe j and its derivative
    d/dx (x in steps) at x = i / (n_sample n_graze), the product and its product rule."""
    n = n_sample * n_graze
    L = np.zeros((n + 1, n_sample + 1))
    dL = np.zeros((n + 1, n_sample + 1))
    for i in range(n + 1):
        x = i / n
        for j in range(n_sample + 1):
            w = 1.0
            dw = 0.0
            for m in range(n_sample + 1):
                if m != j:
                    f = (n_sample * x - m) / (j - m)
                    dw = dw * f + w * n_sample / (j - m)
                    w *= f
            L[i, j] = w
            dL[i, j] = dw
    return L, dL


# (compile-time constants of _graze, refine_peaks and _fn_estimate)
_LAGRANGE, _DLAGRANGE = _lagrange_tables(_NSAMPLE, _NGRAZE)
# the quartic's slope (times a positive factor) at x = 0 and x = 1 from the 5 probes
_SLOPE0 = np.array([-25.0, 48.0, -36.0, 16.0, -3.0])
_SLOPE1 = np.array([3.0, -16.0, 36.0, -48.0, 25.0])

# golden-section iterations of the peak search: its bracket, two of the quartic's evaluation
# intervals (1/16 of the step), shrinks to 6e-7 of the step
_NPEAK = 24
_GOLD = 0.6180339887498949  # (sqrt(5) - 1) / 2
# golden-section iterations of the force's peak: its bracket (1/16 of the step) shrinks to
# 2e-5 of the step
_NFORCE = 18


@njit(cache=True, error_model="numpy", _nrt=False)
def _dot5(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4]


@njit(cache=True, error_model="numpy", _nrt=False)
def _gap_on_step(model, wk, k, p, t, y, K, P, h, x):
    _place(model, wk, k, t, y, K, P, h, x)
    return gap_of(model, p, wk.bA, wk.br, wk.fval)


@njit(cache=True, error_model="numpy", _nrt=False)
def _f_on_step(model, wk, cs, opts, t, y, K, P, h, x, ys, yds, stats):
    """f at t + x h on the dense output (unit quaternions, as at the samples), for its
    diagnostics wk.cout; False if the constrained solve failed. Counted in stats."""
    interpolate(y, K, P, h, x, ys, wk.dw)
    for bd in range(model.nb):
        q = 7 * bd + 3
        nq = math.sqrt(ys[q] ** 2 + ys[q + 1] ** 2 + ys[q + 2] ** 2 + ys[q + 3] ** 2)
        for i in range(4):
            ys[q + i] /= nq
    stats[ST_NFEV] += 1
    return rhs(t + x * h, ys, model, wk, cs, opts.alpha, opts.beta, opts.solver, yds) == 0


@njit(cache=True, error_model="numpy", _nrt=False)
def _fn_on_step(model, wk, cs, opts, k, t, y, K, P, h, x, ys, yds, stats):
    """Joint k's contact force F_N at t + x h on the dense output (-inf if f failed)."""
    if _f_on_step(model, wk, cs, opts, t, y, K, P, h, x, ys, yds, stats):
        return wk.cout[k, CO_FN]
    return -np.inf


@njit(cache=True, error_model="numpy", _nrt=False)
def _fn_estimate(model, cs, k, d, i, h):
    """Joint k's F_N at quartic point i from the gap quartics of its points and their
    slopes (the approach velocity), through each point's normal law."""
    F = 0.0
    for p in range(model.clr_ix[k, CI_P0], model.clr_ix[k, CI_P0] + model.clr_ix[k, CI_NP]):
        q = 0.0
        r = 0.0
        for j in range(_NSAMPLE + 1):
            q += _LAGRANGE[i, j] * d[p, j]
            r += _DLAGRANGE[i, j] * d[p, j]
        if not q > 0.0:
            continue
        r /= h
        ddm = cs.ddm[p] if cs.flag[p] == 1 else max(r, model.clr_geo[k, CG_VFLOOR])
        fn, _ = normal_force(
            model.cp_ix[p, PI_LAW], model.cp_par[p, 0], q, r, ddm, model.clr_geo[k, CG_C]
        )
        F += model.cp_geo[p, PG_W] * fn
    return F


@njit(cache=True, error_model="numpy", _nrt=False)
def _force_peak(model, wk, cs, opts, k, t, y, K, P, h, xend, PK, stats, ys, yds):
    """The largest F_N of joint k inside the step, if it can raise PK[k, 0]: located on
    the estimate of `_fn_estimate` at the quartic's points (a force still rising at the
    step's end is left to the next step), refined by golden section on f's own F_N within
    the quartic's interval on either side."""
    n = _NSAMPLE * _NGRAZE
    d = wk.ev_d
    if PK[k, 0] > 0.0:  # first at the probes only: far below the record, nothing to do
        top = 0.0
        for i in range(0, n + 1, _NGRAZE):
            if i / n > xend:
                break
            top = max(top, _fn_estimate(model, cs, k, d, i, h))
        if top < 0.8 * PK[k, 0]:
            return
    best, ib = -1.0, -1
    for i in range(n + 1):
        if i / n > xend:
            break
        F = _fn_estimate(model, cs, k, d, i, h)
        if F > best:
            best, ib = F, i
    if ib < 0 or not best > 0.0 or best < PK[k, 0]:
        return
    if ib == n and n > 0 and _fn_estimate(model, cs, k, d, n - 1, h) < best:
        return  # still rising at the end: the next step has the peak
    a = max((ib - 1) / n, 0.0)
    b = min((ib + 1) / n, xend)
    c1 = b - _GOLD * (b - a)
    c2 = a + _GOLD * (b - a)
    g1 = _fn_on_step(model, wk, cs, opts, k, t, y, K, P, h, c1, ys, yds, stats)
    g2 = _fn_on_step(model, wk, cs, opts, k, t, y, K, P, h, c2, ys, yds, stats)
    for _ in range(_NFORCE):
        if g1 >= g2:
            b, c2, g2 = c2, c1, g1
            c1 = b - _GOLD * (b - a)
            g1 = _fn_on_step(model, wk, cs, opts, k, t, y, K, P, h, c1, ys, yds, stats)
        else:
            a, c1, g1 = c1, c2, g2
            c2 = a + _GOLD * (b - a)
            g2 = _fn_on_step(model, wk, cs, opts, k, t, y, K, P, h, c2, ys, yds, stats)
    xf, gf = (c1, g1) if g1 >= g2 else (c2, g2)
    if gf > PK[k, 0]:
        PK[k, 0] = gf
        PK[k, 1] = t + xf * h


@njit(cache=True, error_model="numpy", _nrt=False)
def refine_peaks(model, wk, cs, opts, t, y, K, P, h, xend, PK, stats, ys, yds, cout):
    """Contact peaks between the ends of an accepted step (t, y) -> t + xend h, after
    `locate_event` (its probes of every point's gap, wk.ev_d). `track_peaks` sees the
    states at the ends of the steps only, and an impact resolved by a few long steps of a
    high-order method peaks between them (vern7 at rtol 1e-10 on a head-on Hertz impact:
    2.4e-3 low). For each clearance joint, the quartic through the probes of its points'
    gaps is evaluated on _NGRAZE points per probe interval; where its largest value is a
    maximum inside the step (or at an end the quartic leaves or reaches falling: the peak
    lies within one of its intervals of that end) and can raise the joint's largest
    penetration so far (PK[k, 2]), the maximum of that point's gap on the dense output is
    found by golden section within the interval on either side, and f is evaluated there:
    its diagnostics raise PK[k] (largest F_N and delta, their times) as `track_peaks`
    would. A damped law's force peaks earlier, on the approach, often in an earlier step:
    `_force_peak` looks for it in every step, on an estimate of F_N from the gap quartics
    and their slopes through the law. A gap or force still rising at the step's end is
    left to the next step. So a search runs about once per impact that raises a record
    (delta: 26 gap probes and one right-hand side; F_N: 20 right-hand sides; counted in
    stats[ST_NFEV]). ys, yds: scratch (ny,); cout: scratch like wk.cout, which is kept (the
    next `track_peaks` reads it)."""
    n = _NSAMPLE * _NGRAZE
    d = wk.ev_d
    for a_ in range(cout.shape[0]):
        for c in range(cout.shape[1]):
            cout[a_, c] = wk.cout[a_, c]
    for k in range(model.nclr):
        _force_peak(model, wk, cs, opts, k, t, y, K, P, h, xend, PK, stats, ys, yds)
        p0 = model.clr_ix[k, CI_P0]
        # (np.int64: a literal -1 made numba compile _gap_on_step and every gap kernel a
        # second time for the argument type Literal[int](-1): 30 s of each cold compile)
        best, ib, pb = 0.0, 0, np.int64(-1)
        for p in range(p0, p0 + model.clr_ix[k, CI_NP]):
            for i in range(n + 1):  # the quartic's points up to xend
                if i / n > xend:
                    break
                q = 0.0
                for j in range(_NSAMPLE + 1):
                    q += _LAGRANGE[i, j] * d[p, j]
                if q > best:
                    best, ib, pb = q, i, p
        if pb < 0 or best < PK[k, 2]:
            continue  # not in contact, or below the record
        xb = ib / n
        if ib == 0:  # the start: a peak just after it if the quartic leaves it rising
            if _dot5(_SLOPE0, d[pb]) <= 0.0:
                continue
        elif ib == n:  # the end (uncut step): a peak just before it if reached falling
            if _dot5(_SLOPE1, d[pb]) >= 0.0:
                continue  # still rising: the next step has it
        elif best == PK[k, 2]:
            continue
        a = max(xb - 1.0 / n, 0.0)
        b = min(xb + 1.0 / n, xend)
        c1 = b - _GOLD * (b - a)
        c2 = a + _GOLD * (b - a)
        f1 = _gap_on_step(model, wk, k, pb, t, y, K, P, h, c1)
        f2 = _gap_on_step(model, wk, k, pb, t, y, K, P, h, c2)
        for _ in range(_NPEAK):
            if f1 >= f2:
                b, c2, f2 = c2, c1, f1
                c1 = b - _GOLD * (b - a)
                f1 = _gap_on_step(model, wk, k, pb, t, y, K, P, h, c1)
            else:
                a, c1, f1 = c1, c2, f2
                c2 = a + _GOLD * (b - a)
                f2 = _gap_on_step(model, wk, k, pb, t, y, K, P, h, c2)
        xs = c1 if f1 >= f2 else c2
        if _f_on_step(model, wk, cs, opts, t, y, K, P, h, xs, ys, yds, stats):
            if wk.cout[k, CO_FN] > PK[k, 0]:
                PK[k, 0] = wk.cout[k, CO_FN]
                PK[k, 1] = t + xs * h
            if wk.cout[k, CO_DELTA] > PK[k, 2]:
                PK[k, 2] = wk.cout[k, CO_DELTA]
                PK[k, 3] = t + xs * h
    for a_ in range(cout.shape[0]):
        for c in range(cout.shape[1]):
            wk.cout[a_, c] = cout[a_, c]


@njit(cache=True, error_model="numpy", _nrt=False)
def update_contacts(model, wk, cs, t, y, log, nlog, located):
    """Discrete update at an accepted state: an onset latches delta_dot_minus (floored) and
    sets the flag, a separation clears it and zeroes the LuGre bristles. Returns (changed,
    nlog). (The bristles of points in contact need no update: the right-hand side carries
    them with the turning tangent plane, contact/element.py.)

    located: the state is a step cut at a located event. An onset there zeroes the LuGre
    bristles too (see below); elsewhere (the start of a run, rk4's steps, SciPy's
    `latch_contacts`: onsets seen up to a step late) z is kept: it is y0's, or what the
    contact built up since it began.

    changed is True if y or the discrete state changed (the FSAL stage is then invalid).
    """
    changed = False
    iz = model.y_iz
    for k in range(model.nclr):
        s = model.clr_ix[k, CI_BS]
        b = model.clr_ix[k, CI_BB]
        _pose_at(model, wk, s, y, np.bool_(True))
        _pose_at(model, wk, b, y, np.bool_(True))
        _slides(model, wk, k, t)
        for p in range(model.clr_ix[k, CI_P0], model.clr_ix[k, CI_P0] + model.clr_ix[k, CI_NP]):
            # the gap alone (positions) decides; the rate only at an event
            if not _wants(cs.flag[p], gap_of(model, p, wk.bA, wk.br, wk.fval)):
                continue
            ddot = point_contact(model, p, wk.bA, wk.br, wk.brd, wk.bw, wk.fval)[1]
            zi = iz + 3 * p
            if cs.flag[p] == 0:
                cs.flag[p] = 1
                cs.ddm[p] = max(ddot, model.clr_geo[k, CG_VFLOOR])
                # LuGre bristles touch unloaded: z = 0 all through the flight (reset at
                # the separation, z_dot = 0 out of contact), but the step cut at this
                # onset interpolates z from stages beyond it, where z_dot = v_t already
                # acts (up to ~1e-7 m against z ~ 1e-6 m), which made the default
                # scenario's early error erratic in rtol
                if located:
                    y[zi] = 0.0
                    y[zi + 1] = 0.0
                    y[zi + 2] = 0.0
                kind = 1.0
            else:
                cs.flag[p] = 0
                cs.ddm[p] = 0.0
                y[zi] = 0.0
                y[zi + 1] = 0.0
                y[zi + 2] = 0.0
                kind = -1.0
            changed = True
            if nlog < log.shape[0]:
                e, _ = eccentricity(model, k, wk.bA, wk.br, wk.fval)
                log[nlog, 0] = t
                log[nlog, 1] = p
                log[nlog, 2] = kind
                log[nlog, 3] = ddot
                for a in range(3):
                    log[nlog, 4 + a] = e[a]
            nlog += 1
    return changed, nlog
