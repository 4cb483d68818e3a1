"""The high-order explicit pairs, DOP853 and Vern7, in one compiled loop (the contract:
state.py): for tight tolerances, where they take far fewer steps than the 5(4) pairs of
`erk.erk54`. Both have a stage at the new solution (f(t + h, y_new): the next step's stage
0) and a 7th-order dense output that needs more stages, evaluated only for a step that has
output samples or clearance joints whose contact events are searched on it.

* dop853 (Dormand & Prince 8(5,3), Hairer's dop853.f; tableau_dop853.py): 12 stages and
  f(t + h, y_new) per step, 3 more for the dense output (15). Error estimate dop853.f's:
  the 5th- and 3rd-order embedded differences err5, err3 (scaled like erk54's norm),
  err = |h| |err5|^2 / sqrt(n (|err5|^2 + 0.01 |err3|^2)), exponent 1/8.
* vern7 (Verner's 7(6) "most efficient" pair; tableau_vern7.py): 9 new stages and
  f(t + h, y_new) per step (10), 5 more for the interpolant (15). Error estimate erk54's
  norm of h sum_k E_k K_k, exponent 1/7.

Step control as in dop853.f for both (safety 0.9, no PI term, a new step between 1/3 and 6
times the old one). The method data: (A, C, B, E3, E5, P, order); E3 empty selects the
plain norm of E5.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.dynamics.rhs import rhs
from clearance.integrate.accept import (
    after_step,
    returned,
    sample,
    section,
    start,
    track_peaks,
)
from clearance.integrate.erk import initial_step
from clearance.integrate.events import interpolate, locate_event, refine_peaks
from clearance.kinds import (
    CT_BUDGET,
    CT_FACOLD,
    CT_H,
    CT_IOUT,
    CT_NLOG,
    CT_NSTEPS,
    CT_REJECTED,
    CT_STARTED,
    CT_T,
    ST_HLAST,
    ST_HMAX,
    ST_HMIN,
    ST_NACC,
    ST_NEVT,
    ST_NFEV,
    ST_NREJ,
    Status,
)

_SUCCESS = int(Status.SUCCESS)
_SINGULAR = int(Status.SINGULAR)
_STEP_UNDERFLOW = int(Status.STEP_UNDERFLOW)
_MAX_STEPS = int(Status.MAX_STEPS)
_PAUSED = int(Status.PAUSED)


@njit(cache=True, error_model="numpy", _nrt=False)
def _stage(A, K, s, y, h, ytmp):
    """ytmp = y + h sum_{k < s} A[s, k] K[k] (summed over k in order for each entry)."""
    ny = y.shape[0]
    a = A[s, 0]
    for i in range(ny):
        ytmp[i] = a * K[0, i]
    for k in range(1, s):
        a = A[s, k]
        if a != 0.0:
            for i in range(ny):
                ytmp[i] += a * K[k, i]
    for i in range(ny):
        ytmp[i] = y[i] + h * ytmp[i]


@njit(cache=True, error_model="numpy", nogil=True)
def _stages(model, wk, cs, alpha, beta, solver, A, C, K, s0, s1, t, y, h, ytmp, stats):
    """Stages s0 .. s1 - 1 of a step of size h from (t, y) into K. Returns the first failing
    rhs status, 0 if none failed."""
    for s in range(s0, s1):
        _stage(A, K, s, y, h, ytmp)
        st = rhs(t + C[s] * h, ytmp, model, wk, cs, alpha, beta, solver, K[s])
        stats[ST_NFEV] += 1
        if st != 0:
            return st
    return 0


@njit(cache=True, error_model="numpy", _nrt=False)
def _solution(B, K, ns, y, h, ynew):
    """ynew = y + h sum_k B[k] K[k] over the ns stages (zero weights skipped)."""
    ny = y.shape[0]
    b = B[0]
    for i in range(ny):
        ynew[i] = b * K[0, i]
    for k in range(1, ns):
        b = B[k]
        if b != 0.0:
            for i in range(ny):
                ynew[i] += b * K[k, i]
    for i in range(ny):
        ynew[i] = y[i] + h * ynew[i]


@njit(cache=True, error_model="numpy", nogil=True)
def _end_stages(
    model, wk, cs, alpha, beta, solver, A, C, K, P, ns, t, y, h, ynew, ytmp, cout, stats, dense
):
    """Stage ns = f(t + h, y_new) and, if dense, the dense output's extra stages, leaving
    wk.cout as f(t + h, y_new) made it (cout: scratch). Returns the first failing rhs
    status, 0 if none failed."""
    st = rhs(t + h, ynew, model, wk, cs, alpha, beta, solver, K[ns])
    stats[ST_NFEV] += 1
    if st == 0 and dense:
        for a in range(cout.shape[0]):
            for c in range(cout.shape[1]):
                cout[a, c] = wk.cout[a, c]
        st = _stages(
            model, wk, cs, alpha, beta, solver, A, C, K, ns + 1, P.shape[0], t, y, h, ytmp, stats
        )
        for a in range(cout.shape[0]):  # as if f(t + h, y_new) were the last evaluation
            for c in range(cout.shape[1]):
                wk.cout[a, c] = cout[a, c]
    return st


@njit(cache=True, error_model="numpy", _nrt=False)
def _err_norm(K, E3, E5, ns, y, ynew, n, h, rtol, atol):
    """The error norm of a step over its ns stages (scaled by atol + rtol max(|y|,
    |y_new|)): dop853.f's from E5 and E3, or, with E3 empty, erk54's RMS norm of
    h sum_k E5[k] K[k]."""
    e5 = 0.0
    e3 = 0.0
    both = E3.shape[0] > 0
    for i in range(n):
        sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        a5 = 0.0
        a3 = 0.0
        for k in range(ns):
            a5 += E5[k] * K[k, i]
            if both:
                a3 += E3[k] * K[k, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if not both:
        return abs(h) * math.sqrt(e5 / n)
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True, error_model="numpy", nogil=True)
def erk_high(model, wk, cs, opts, out, A, C, B, E3, E5, P, order, t0, y0):
    """Integrate from (t0, y0), writing the samples at out.t_out (contract: state.py);
    see `_erk_high`. Returns (status, outputs written, last time, events), also kept in
    out.ctl (kinds.CT_STATUS)."""
    st, iout, t, nlog = _erk_high(model, wk, cs, opts, out, A, C, B, E3, E5, P, order, t0, y0)
    return returned(out.ctl, st, iout, t, nlog)


@njit(cache=True, error_model="numpy", nogil=True)
def _erk_high(model, wk, cs, opts, out, A, C, B, E3, E5, P, order, t0, y0):
    """The loop (module docstring): B has the ns stages of a step, stage ns is
    f(t + h, y_new), ns + 1 .. P.shape[0] - 1 the dense output's; out.ks holds them all
    between calls. order: the error estimate's (its exponent 1 / order; the first step's)."""
    ny = y0.shape[0]
    nerr = model.y_iw  # the work integrals do not steer the step size
    alpha, beta, solver = opts.alpha, opts.beta, opts.solver
    rtol, atol, hmax = opts.rtol, opts.atol, opts.hmax
    stats = out.stats
    t_out = out.t_out
    ctl = out.ctl
    y = out.ys
    K = out.ks
    if K.shape[0] < P.shape[0]:
        raise ValueError("erk_high: out.ks needs a row per stage (loop_inputs(stages=16))")
    ns = B.shape[0]
    ynew = np.empty(ny)
    ytmp = np.empty(ny)
    w = np.empty(K.shape[0])
    cout = np.empty_like(wk.cout)  # f(t + h, y_new)'s diagnostics; refine_peaks' scratch
    yd2 = np.empty(ny)  # refine_peaks' scratch
    t_end = t_out[-1]
    nout = t_out.shape[0]
    expo1 = 1.0 / order
    safe = 0.9
    if ctl[CT_STARTED] != 0.0:
        t, h, facold = ctl[CT_T], ctl[CT_H], ctl[CT_FACOLD]
        rejected = ctl[CT_REJECTED] != 0.0
        nsteps, iout, nlog = int(ctl[CT_NSTEPS]), int(ctl[CT_IOUT]), np.int64(ctl[CT_NLOG])
    else:
        t = t0
        for i in range(ny):
            y[i] = y0[i]
        st, iout, nlog = start(model, wk, cs, opts, out, t, y)
        if st != _SUCCESS:
            return st, iout, t, nlog
        st = rhs(t, y, model, wk, cs, alpha, beta, solver, K[0])
        stats[ST_NFEV] += 1
        if st != 0:
            return _SINGULAR, iout, t, nlog
        track_peaks(wk, t, out.PK, np.bool_(True))
        h = initial_step(model, wk, cs, opts, stats, t, y, K[0], K[1], ytmp, t_end - t0, order)
        facold = 1e-4
        rejected = False
        nsteps = 0
        ctl[CT_STARTED] = 1.0
    budget = int(ctl[CT_BUDGET])
    pause_at = nsteps + budget if budget > 0 else opts.max_steps + 1
    while t < t_end:
        if nsteps >= pause_at:
            ctl[CT_T], ctl[CT_H], ctl[CT_FACOLD] = t, h, facold
            ctl[CT_REJECTED] = 1.0 if rejected else 0.0
            ctl[CT_NSTEPS], ctl[CT_IOUT], ctl[CT_NLOG] = nsteps, iout, nlog
            return _PAUSED, iout, t, nlog
        if nsteps >= opts.max_steps:
            return _MAX_STEPS, iout, t, nlog
        if h < opts.hmin:
            return _STEP_UNDERFLOW, iout, t, nlog
        if t + 1.01 * h >= t_end:
            h = t_end - t
        first = np.int64(1)  # (not the literal 1: numba would compile _stages twice)
        bad = (
            _stages(model, wk, cs, alpha, beta, solver, A, C, K, first, ns, t, y, h, ytmp, stats)
            != 0
        )
        nsteps += 1
        en = 0.0
        if not bad:
            _solution(B, K, ns, y, h, ynew)
            en = _err_norm(K, E3, E5, ns, y, ynew, nerr, h, rtol, atol)
            if not np.isfinite(en):
                bad = True
        if bad:
            stats[ST_NREJ] += 1
            h *= 0.25
            rejected = True
            continue
        fac11 = en**expo1
        fac = max(1.0 / 6.0, min(3.0, fac11 / safe))
        hnew = h / fac
        if en > 1.0:
            stats[ST_NREJ] += 1
            h = h / min(3.0, fac11 / safe)
            rejected = True
            continue
        # passed: stage ns = f(t + h, y_new) (the next step's stage 0 unless y changes); a
        # failure here or in the dense stages rejects the step, as a stage of erk54 does
        dense = model.nclr > 0 or out.sec_w.shape[0] > 0 or (iout < nout and t_out[iout] <= t + h)
        st = _end_stages(
            model,
            wk,
            cs,
            alpha,
            beta,
            solver,
            A,
            C,
            K,
            P,
            ns,
            t,
            y,
            h,
            ynew,
            ytmp,
            cout,
            stats,
            dense,
        )
        if st != 0:
            stats[ST_NREJ] += 1
            h *= 0.25
            rejected = True
            continue
        facold = max(en, 1e-4)
        stats[ST_NACC] += 1
        stats[ST_HMIN] = min(stats[ST_HMIN], h)
        stats[ST_HMAX] = max(stats[ST_HMAX], h)
        xev = 2.0
        hstep = h
        if model.nclr > 0:
            xev, _ = locate_event(model, wk, cs, t, y, K, P, h, rtol)
            if xev <= 1.0:  # redo the step up to the event (erk.py's module docstring)
                h = xev * h
                while True:
                    st = _stages(
                        model, wk, cs, alpha, beta, solver, A, C, K, 1, ns, t, y, h, ytmp, stats
                    )
                    if st != 0:
                        return _SINGULAR, iout, t, nlog
                    _solution(B, K, ns, y, h, ynew)
                    e_ev = _err_norm(K, E3, E5, ns, y, ynew, nerr, h, rtol, atol)
                    if e_ev <= 1.0:
                        break
                    xev = 2.0  # a shorter step, short of the event (erk.py)
                    h *= max(0.2, 0.9 * e_ev**-expo1) if np.isfinite(e_ev) else 0.25
                    if h < opts.hmin:
                        return _STEP_UNDERFLOW, iout, t, nlog
                st = _end_stages(
                    model,
                    wk,
                    cs,
                    alpha,
                    beta,
                    solver,
                    A,
                    C,
                    K,
                    P,
                    ns,
                    t,
                    y,
                    h,
                    ynew,
                    ytmp,
                    cout,
                    stats,
                    np.bool_(True),
                )
                if st != 0:
                    return _SINGULAR, iout, t, nlog
                if xev <= 1.0:
                    stats[ST_NEVT] += 1
                # the peak search reads the gap probes of the step it is given: probe the
                # redone one (its event, at x = 1, needs no new location)
                locate_event(model, wk, cs, t, y, K, P, h, rtol)
            refine_peaks(model, wk, cs, opts, t, y, K, P, h, 1.0, out.PK, stats, ytmp, yd2, cout)
        tnew = t + h
        section(model, out, t, y, ynew, K, P, h, w, ytmp)
        while iout < nout and t_out[iout] <= tnew:
            interpolate(y, K, P, h, (t_out[iout] - t) / h, out.Y[iout], w)
            if sample(model, wk, cs, opts, out, iout) != _SUCCESS:
                return _SINGULAR, iout, t, nlog
            iout += 1
        t = tnew
        for i in range(ny):
            y[i] = ynew[i]
        st, changed, nlog = after_step(model, wk, cs, opts, out, t, y, K[ns], nlog, xev <= 1.0)
        if st != _SUCCESS:
            return st, iout, t, nlog
        if changed:
            st = rhs(t, y, model, wk, cs, alpha, beta, solver, K[0])
            stats[ST_NFEV] += 1
            if st != 0:
                return _SINGULAR, iout, t, nlog
        else:
            for i in range(ny):
                K[0, i] = K[ns, i]
        track_peaks(wk, t, out.PK, np.bool_(False))
        if rejected:
            hnew = min(hnew, hstep)
        rejected = False
        h = min(hnew, hmax)
        stats[ST_HLAST] = h
    return _SUCCESS, iout, t, nlog
