"""DOP853 (Dormand & Prince 8(5,3), Hairer's dop853.f) in a compiled loop (the contract:
state.py): for tight tolerances, where an 8th-order method takes far fewer steps than the
5(4) pairs of `erk.erk54`.

Per step: 12 stages, the 8th-order solution, then f(t + h, y_new) (first same as last:
stage 12, the next step's stage 0). The error estimate is dop853.f's: the 5th- and
3rd-order embedded differences err5, err3 (scaled like erk54's norm),
err = |h| |err5|^2 / sqrt(n (|err5|^2 + 0.01 |err3|^2)); step control as in dop853.f
(exponent 1/8, no PI term, safety 0.9, a new step between 1/3 and 6 times the old one).
The 7th-order dense output needs three more stages (13..15); they are evaluated only for a
step that has output samples or clearance joints whose contact events are searched on it,
so a step costs 12 right-hand sides, or 15 with the dense output (tableau_dop853.py).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.dynamics.rhs import rhs
from clearance.integrate.accept import after_step, returned, sample, start, track_peaks
from clearance.integrate.erk import initial_step
from clearance.integrate.events import interpolate, locate_event
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

_NS = 12  # stages of a step (0..11); stage 12 is f(t + h, y_new), 13..15 the dense output's


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


@njit(cache=True, error_model="numpy", _nrt=False)
def _err_norm(K, E3, E5, y, ynew, n, h, rtol, atol):
    """dop853.f's error norm of the step (scaled by atol + rtol max(|y|, |y_new|))."""
    e5 = 0.0
    e3 = 0.0
    for i in range(n):
        sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        a5 = 0.0
        a3 = 0.0
        for k in range(_NS):
            a5 += E5[k] * K[k, i]
            a3 += E3[k] * K[k, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True, error_model="numpy", nogil=True)
def dop853(model, wk, cs, opts, out, A, C, B, E3, E5, P, t0, y0):
    """Integrate from (t0, y0), writing the samples at out.t_out (contract: state.py);
    see `_dop853`. Returns (status, outputs written, last time, events), also kept in
    out.ctl (kinds.CT_STATUS)."""
    st, iout, t, nlog = _dop853(model, wk, cs, opts, out, A, C, B, E3, E5, P, t0, y0)
    return returned(out.ctl, st, iout, t, nlog)


@njit(cache=True, error_model="numpy", nogil=True)
def _dop853(model, wk, cs, opts, out, A, C, B, E3, E5, P, t0, y0):
    """The loop (module docstring); out.ks holds the 16 stages between calls."""
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
        raise ValueError("dop853: out.ks needs a row per stage (loop_inputs(stages=16))")
    ynew = np.empty(ny)
    ytmp = np.empty(ny)
    w = np.empty(K.shape[0])
    cout = np.empty_like(wk.cout)  # f(t + h, y_new)'s diagnostics, for track_peaks
    t_end = t_out[-1]
    nout = t_out.shape[0]
    expo1 = 1.0 / 8.0
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
        h = initial_step(model, wk, cs, opts, stats, t, y, K[0], K[1], ytmp, t_end - t0, 8.0)
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
        bad = False
        for s in range(1, _NS):
            _stage(A, K, s, y, h, ytmp)
            st = rhs(t + C[s] * h, ytmp, model, wk, cs, alpha, beta, solver, K[s])
            stats[ST_NFEV] += 1
            if st != 0:
                bad = True
                break
        nsteps += 1
        en = 0.0
        if not bad:
            b = B[0]
            for i in range(ny):
                ynew[i] = b * K[0, i]
            for k in range(1, _NS):
                b = B[k]
                if b != 0.0:
                    for i in range(ny):
                        ynew[i] += b * K[k, i]
            for i in range(ny):
                ynew[i] = y[i] + h * ynew[i]
            en = _err_norm(K, E3, E5, y, ynew, nerr, h, rtol, atol)
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
        # passed: stage 12 = f(t + h, y_new) (the next step's stage 0 unless y changes); a
        # failure here or in the dense stages rejects the step, as a stage of erk54 does
        st = rhs(t + h, ynew, model, wk, cs, alpha, beta, solver, K[_NS])
        stats[ST_NFEV] += 1
        if st == 0 and (model.nclr > 0 or (iout < nout and t_out[iout] <= t + h)):
            for a in range(cout.shape[0]):
                for c in range(cout.shape[1]):
                    cout[a, c] = wk.cout[a, c]
            for s in range(_NS + 1, K.shape[0]):  # the dense output's extra stages
                _stage(A, K, s, y, h, ytmp)
                st = rhs(t + C[s] * h, ytmp, model, wk, cs, alpha, beta, solver, K[s])
                stats[ST_NFEV] += 1
                if st != 0:
                    break
            for a in range(cout.shape[0]):  # as if f(t + h, y_new) were the last evaluation
                for c in range(cout.shape[1]):
                    wk.cout[a, c] = cout[a, c]
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
        if model.nclr > 0:
            xev, _ = locate_event(model, wk, cs, t, y, K, P, h, rtol)
        if xev <= 1.0:
            interpolate(y, K, P, h, xev, ynew, w)
            tnew = t + xev * h
            stats[ST_NEVT] += 1
        else:
            tnew = t + h
        while iout < nout and t_out[iout] <= tnew:
            interpolate(y, K, P, h, (t_out[iout] - t) / h, out.Y[iout], w)
            if sample(model, wk, cs, opts, out, iout) != _SUCCESS:
                return _SINGULAR, iout, t, nlog
            iout += 1
        t = tnew
        for i in range(ny):
            y[i] = ynew[i]
        st, changed, nlog = after_step(model, wk, cs, opts, out, t, y, K[_NS], nlog, xev <= 1.0)
        if st != _SUCCESS:
            return st, iout, t, nlog
        if changed:
            st = rhs(t, y, model, wk, cs, alpha, beta, solver, K[0])
            stats[ST_NFEV] += 1
            if st != 0:
                return _SINGULAR, iout, t, nlog
        else:
            for i in range(ny):
                K[0, i] = K[_NS, i]
        track_peaks(wk, t, out.PK, np.bool_(False))
        if rejected:
            hnew = min(hnew, h)
        rejected = False
        h = min(hnew, hmax)
        stats[ST_HLAST] = h
    return _SUCCESS, iout, t, nlog
