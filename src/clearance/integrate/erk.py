"""Adaptive explicit Runge-Kutta 5(4) pairs in one compiled loop (the contract: state.py).

`erk54`: any 7-stage FSAL 5(4) pair given by its tableau (tableau.py: Dormand-Prince
"dopri5" or Tsitouras "tsit5"), PI step-size control (Hairer & Wanner, DOPRI5 constants, for
both pairs), dense output at the requested times (steps are never shortened to hit the
output grid), contact events located on the pair's own continuous extension.

A step with a contact event in it is redone up to the event: the step is accepted as a
whole, the event located on its dense output, and then one step of the pair from the same
start to the event gives the state there (and the dense output of the samples before it).
Its stages all lie before the event, where the right-hand side is smooth; the dense output
of the whole step also carries the stages beyond the event, where forces switch on or off,
which made the state at the event (from which the next step starts) carry an error the
step's estimate never saw (rattling rod, Flores + LuGre, velocity after the first impact,
rtol 1e-9: 5e-9 m/s interpolated, 5e-11 m/s redone). Six more right-hand sides per event.
The redone step's own error is estimated too: where it is too large (the force of a
separating contact, F ~ delta^1.5, is not smooth at the separation), a shorter step is
taken instead and the event found again from there.
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
def _err_norm(e, y, ynew, n, rtol, atol):
    s = 0.0
    for i in range(n):
        sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        s += (e[i] / sc) ** 2
    return math.sqrt(s / n)


@njit(cache=True, error_model="numpy", _nrt=False)
def initial_step(model, wk, cs, opts, stats, t, y, f0, f1, ytmp, span, order):
    """First step size: opts.h0, or Hairer & Wanner I, II.4 for a method of that order
    (f0 = f(t, y); f1 and ytmp: scratch; one more right-hand side, counted in stats)."""
    h = opts.h0
    if h > 0.0:
        return h
    ny = y.shape[0]
    nerr = model.y_iw
    rtol, atol = opts.rtol, opts.atol
    d0 = 0.0
    d1 = 0.0
    for i in range(nerr):
        sc = atol + rtol * abs(y[i])
        d0 += (y[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = math.sqrt(d0 / nerr)
    d1 = math.sqrt(d1 / nerr)
    h = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h = min(h, opts.hmax, span)
    for i in range(ny):
        ytmp[i] = y[i] + h * f0[i]
    rhs(t + h, ytmp, model, wk, cs, opts.alpha, opts.beta, opts.solver, f1)
    stats[ST_NFEV] += 1
    d2 = 0.0
    for i in range(nerr):
        sc = atol + rtol * abs(y[i])
        d2 += ((f1[i] - f0[i]) / sc) ** 2
    d2 = math.sqrt(d2 / nerr) / h
    if max(d1, d2) <= 1e-15:
        h1 = max(1e-6, h * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / order)
    return min(100 * h, h1, opts.hmax, span)


@njit(cache=True, error_model="numpy", nogil=True)
def erk54(model, wk, cs, opts, out, A, C, E, P, t0, y0):
    """Integrate from (t0, y0), writing the samples at out.t_out (contract: state.py);
    see `_erk54`. Returns (status, outputs written, last time, events), also kept in
    out.ctl (kinds.CT_STATUS)."""
    st, iout, t, nlog = _erk54(model, wk, cs, opts, out, A, C, E, P, t0, y0)
    return returned(out.ctl, st, iout, t, nlog)


@njit(cache=True, error_model="numpy", _nrt=False)
def _error(E, K, h, y, ynew, err, nerr, rtol, atol):
    """The error estimate err = h sum_k E[k] K[k] of a step from y to ynew, and its norm."""
    ny = y.shape[0]
    for i in range(ny):
        err[i] = E[0] * K[0, i]
    for k in range(1, 7):
        e = E[k]
        for i in range(ny):
            err[i] += e * K[k, i]
    for i in range(ny):
        err[i] *= h
    return _err_norm(err, y, ynew, nerr, rtol, atol)


@njit(cache=True, error_model="numpy", nogil=True)
def _stages(model, wk, cs, alpha, beta, solver, A, C, K, t, y, h, ytmp, stats):
    """Stages 2..7 of a step of size h from (t, y) into K (K[0] = f(t, y)); ytmp ends as
    stage 7's argument, the 5th-order solution (FSAL). Returns the first failing rhs
    status, 0 if none failed."""
    ny = y.shape[0]
    for s in range(1, 7):
        # ytmp = y + h sum_k a_sk K_k, summed over k in order for each entry (the loops
        # over the entries vectorise; the sums are those of a per-entry loop to the bit)
        a = A[s, 0]
        for i in range(ny):
            ytmp[i] = a * K[0, i]
        for k in range(1, s):
            a = A[s, k]
            for i in range(ny):
                ytmp[i] += a * K[k, i]
        for i in range(ny):
            ytmp[i] = y[i] + h * ytmp[i]
        st = rhs(t + C[s] * h, ytmp, model, wk, cs, alpha, beta, solver, K[s])
        stats[ST_NFEV] += 1
        if st != 0:
            return st
    return 0


@njit(cache=True, error_model="numpy", nogil=True)
def _erk54(model, wk, cs, opts, out, A, C, E, P, t0, y0):
    """Integrate from (t0, y0), writing the samples at out.t_out (contract: state.py).

    (A, C, E, P): the pair's tableau (tableau.py layout; A[6] = b, b_7 = 0, so stage 7 is
    f at the new solution, FSAL); E gives the error estimate, P the dense output.
    Returns (status, outputs written, last time, events); Status.PAUSED after
    out.ctl[CT_BUDGET] attempted steps, resumed by the next call (state.py, item 4).
    """
    ny = y0.shape[0]
    nerr = model.y_iw  # the work integrals do not steer the step size
    alpha, beta, solver = opts.alpha, opts.beta, opts.solver
    rtol, atol, hmax = opts.rtol, opts.atol, opts.hmax
    stats = out.stats
    t_out = out.t_out
    ctl = out.ctl
    y = out.ys  # the state and the stages live in `out` between calls
    K = out.ks
    ynew = np.empty(ny)
    ytmp = np.empty(ny)
    err = np.empty(ny)
    w = np.empty(K.shape[0])  # dense-output weights
    cout = np.empty_like(wk.cout)  # scratch of refine_peaks
    t_end = t_out[-1]
    nout = t_out.shape[0]
    # PI controller constants (DOPRI5's, used for both pairs): expo1 = 0.2 - 0.75 beta_pi
    beta_pi = 0.04
    expo1 = 0.2 - 0.75 * beta_pi
    safe = 0.9
    if ctl[CT_STARTED] != 0.0:  # resume where the last call handed control back
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
        h = initial_step(model, wk, cs, opts, stats, t, y, K[0], K[1], ytmp, t_end - t0, 5.0)
        facold = 1e-4
        rejected = False
        nsteps = 0
        ctl[CT_STARTED] = 1.0
    budget = int(ctl[CT_BUDGET])
    pause_at = nsteps + budget if budget > 0 else opts.max_steps + 1
    while t < t_end:
        if nsteps >= pause_at:  # hand control back (the caller resumes this very state)
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
        # stages 2..7
        bad = _stages(model, wk, cs, alpha, beta, solver, A, C, K, t, y, h, ytmp, stats) != 0
        nsteps += 1
        if not bad:
            for i in range(ny):
                ynew[i] = ytmp[i]  # stage 7 is evaluated at the 5th-order solution (FSAL)
            en = _error(E, K, h, y, ynew, err, nerr, rtol, atol)
            if not np.isfinite(en):
                bad = True
        if bad:
            stats[ST_NREJ] += 1
            h *= 0.25
            rejected = True
            continue
        fac11 = en**expo1
        fac = fac11 / facold**beta_pi
        fac = max(0.1, min(5.0, fac / safe))  # 1/fac in Hairer's notation: h/10 .. 5h
        hnew = h / fac
        if en <= 1.0:
            facold = max(en, 1e-4)
            stats[ST_NACC] += 1
            stats[ST_HMIN] = min(stats[ST_HMIN], h)
            stats[ST_HMAX] = max(stats[ST_HMAX], h)
            # contact events inside the step: cut the step at the earliest one
            xev = 2.0
            hstep = h
            if model.nclr > 0:
                xev, _ = locate_event(model, wk, cs, t, y, K, P, h, rtol)
                if xev <= 1.0:  # redo the step up to the event (module docstring)
                    h = xev * h
                    while True:
                        if _stages(
                            model, wk, cs, alpha, beta, solver, A, C, K, t, y, h, ytmp, stats
                        ):
                            return _SINGULAR, iout, t, nlog
                        for i in range(ny):
                            ynew[i] = ytmp[i]
                        e_ev = _error(E, K, h, y, ynew, err, nerr, rtol, atol)
                        if e_ev <= 1.0:
                            break
                        # too large an error for the step to the event: a shorter one, short
                        # of the event, which the next step then finds again
                        xev = 2.0
                        h *= max(0.2, 0.9 * e_ev**-0.2) if np.isfinite(e_ev) else 0.25
                        if h < opts.hmin:
                            return _STEP_UNDERFLOW, iout, t, nlog
                    if xev <= 1.0:
                        stats[ST_NEVT] += 1
                    # the peak search reads the gap probes of the step it is given: probe the
                    # redone one (its event, at x = 1, needs no new location)
                    locate_event(model, wk, cs, t, y, K, P, h, rtol)
                refine_peaks(
                    model, wk, cs, opts, t, y, K, P, h, 1.0, out.PK, stats, ytmp, err, cout
                )
            tnew = t + h
            section(model, out, t, y, ynew, K, P, h, w, ytmp)
            # dense output for every requested time in (t, tnew]
            while iout < nout and t_out[iout] <= tnew:
                interpolate(y, K, P, h, (t_out[iout] - t) / h, out.Y[iout], w)
                if sample(model, wk, cs, opts, out, iout) != _SUCCESS:
                    return _SINGULAR, iout, t, nlog
                iout += 1
            t = tnew
            for i in range(ny):
                y[i] = ynew[i]
            st, changed, nlog = after_step(model, wk, cs, opts, out, t, y, K[6], nlog, xev <= 1.0)
            if st != _SUCCESS:
                return st, iout, t, nlog
            if changed:  # the FSAL stage no longer matches (y, discrete state)
                st = rhs(t, y, model, wk, cs, alpha, beta, solver, K[0])
                stats[ST_NFEV] += 1
                if st != 0:
                    return _SINGULAR, iout, t, nlog
            else:
                for i in range(ny):
                    K[0, i] = K[6, i]  # FSAL
            # the last evaluation was f(t, y): stage 7 at the new solution, or the re-evaluation
            track_peaks(wk, t, out.PK, np.bool_(False))
            if rejected:
                hnew = min(hnew, hstep)
            rejected = False
            h = min(hnew, hmax)
            stats[ST_HLAST] = h
        else:
            stats[ST_NREJ] += 1
            h = h / min(5.0, fac11 / safe)
            rejected = True
    return _SUCCESS, iout, t, nlog
