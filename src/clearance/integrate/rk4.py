"""Classical fixed-step RK4 in a compiled loop (the contract: state.py).

Between consecutive output times the step is dt/ceil(dt/h) <= h, so the samples are steps'
end points. Contact events are not located: the discrete contact state is updated at the
end of each step (first-order capture of delta_dot_minus, physics.md f.5), which is what
makes RK4 a reference for papers that integrate with a fixed step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.dynamics.rhs import rhs
from clearance.integrate.accept import after_step, record, returned, start, track_peaks
from clearance.kinds import (
    CT_BUDGET,
    CT_IOUT,
    CT_NLOG,
    CT_STARTED,
    CT_SUBSTEP,
    CT_T,
    CT_TPREV,
    ST_HMAX,
    ST_HMIN,
    ST_NACC,
    ST_NFEV,
    Status,
)

_SUCCESS = int(Status.SUCCESS)
_SINGULAR = int(Status.SINGULAR)
_PAUSED = int(Status.PAUSED)


@njit(cache=True, error_model="numpy", nogil=True)
def rk4(model, wk, cs, opts, out, t0, y0):
    """Integrate from (t0, y0) with the fixed step opts.step (see `_rk4`). Returns
    (status, outputs written, last time, events), also kept in out.ctl (kinds.CT_STATUS)."""
    st, iout, t, nlog = _rk4(model, wk, cs, opts, out, t0, y0)
    return returned(out.ctl, st, iout, t, nlog)


@njit(cache=True, error_model="numpy", nogil=True)
def _rk4(model, wk, cs, opts, out, t0, y0):
    """Integrate from (t0, y0) with the fixed step opts.step; peaks (out.PK) at the step
    starts (the last state is covered by the outputs). Returns (status, outputs written,
    last time, events); Status.PAUSED after out.ctl[CT_BUDGET] steps, resumed by the next
    call (state.py, item 4)."""
    alpha, beta, solver, h = opts.alpha, opts.beta, opts.solver, opts.step
    stats = out.stats
    t_out = out.t_out
    ctl = out.ctl
    ny = y0.shape[0]
    y = out.ys  # the state lives in `out` between calls
    k1 = np.empty(ny)
    k2 = np.empty(ny)
    k3 = np.empty(ny)
    k4 = np.empty(ny)
    ytmp = np.empty(ny)
    nout = t_out.shape[0]
    if ctl[CT_STARTED] != 0.0:  # resume where the last call handed control back
        t, tprev, j = ctl[CT_T], ctl[CT_TPREV], int(ctl[CT_SUBSTEP])
        iout, nlog = int(ctl[CT_IOUT]), np.int64(ctl[CT_NLOG])
    else:
        t = t0
        for i in range(ny):
            y[i] = y0[i]
        st, iout, nlog = start(model, wk, cs, opts, out, t, y)
        if st != _SUCCESS:
            return st, iout, t, nlog
        tprev = t  # the start of the current output interval
        j = 0  # steps done in it
        ctl[CT_STARTED] = 1.0
    budget = int(ctl[CT_BUDGET])
    nsteps = 0
    while iout < nout:
        dt = t_out[iout] - tprev
        n = max(1, int(math.ceil(dt / h - 1e-9)))
        hs = dt / n
        while j < n:
            if budget > 0 and nsteps >= budget:  # hand control back (resumed exactly)
                ctl[CT_T], ctl[CT_TPREV], ctl[CT_SUBSTEP] = t, tprev, j
                ctl[CT_IOUT], ctl[CT_NLOG] = iout, nlog
                return _PAUSED, iout, t, nlog
            st = rhs(t, y, model, wk, cs, alpha, beta, solver, k1)
            track_peaks(wk, t, out.PK, stats[ST_NFEV] == 0.0)
            for i in range(ny):
                ytmp[i] = y[i] + 0.5 * hs * k1[i]
            st |= rhs(t + 0.5 * hs, ytmp, model, wk, cs, alpha, beta, solver, k2)
            for i in range(ny):
                ytmp[i] = y[i] + 0.5 * hs * k2[i]
            st |= rhs(t + 0.5 * hs, ytmp, model, wk, cs, alpha, beta, solver, k3)
            for i in range(ny):
                ytmp[i] = y[i] + hs * k3[i]
            st |= rhs(t + hs, ytmp, model, wk, cs, alpha, beta, solver, k4)
            stats[ST_NFEV] += 4
            if st != 0:
                return _SINGULAR, iout, t, nlog
            for i in range(ny):
                y[i] += hs / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            t += hs
            stats[ST_NACC] += 1
            # (np.bool_: a literal False made numba compile after_step and update_contacts a
            # second time, for Literal[bool])
            st, _, nlog = after_step(model, wk, cs, opts, out, t, y, k4[:0], nlog, np.bool_(False))
            if st != _SUCCESS:
                return st, iout, t, nlog
            j += 1
            nsteps += 1
        t = t_out[iout]
        tprev = t
        j = 0
        out.Y[iout, :] = y
        record(cs, out, iout)
        iout += 1
    stats[ST_HMIN] = h
    stats[ST_HMAX] = h
    return _SUCCESS, iout, t, nlog
