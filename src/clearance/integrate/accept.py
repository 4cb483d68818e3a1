"""The hooks every integration loop shares (the contract is in `state.py`), compiled:
start of a run, samples on the output grid, the on-accept update after each accepted step,
peak tracking; and the coordinate projection and quaternion normalisation they apply.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.dynamics.rhs import constraint_rows
from clearance.dynamics.solve import solve_constrained
from clearance.integrate.events import interpolate, update_contacts
from clearance.kinds import (
    CT_IOUT,
    CT_NLOG,
    CT_STATUS,
    CT_T,
    NSTATS,
    ST_HMIN,
    ST_NACC,
    ST_NPROJ,
    Status,
)
from clearance.kinematics.rotations import quat_rotate_body
from clearance.layout import CO_DELTA, CO_FN

_SUCCESS = int(Status.SUCCESS)
_SINGULAR = int(Status.SINGULAR)
_NONFINITE = int(Status.NONFINITE)


@njit(cache=True, error_model="numpy", _nrt=False)
def _correction(model, wk, err, solver):
    """wk.vd <- -M^-1 J^T (J M^-1 J^T)^-1 err: the kinetic-energy-closest change that removes
    the (linearised) violation err; the constrained solve with Q = 0 and gamma_B = -err."""
    for b in range(model.nb):
        for k in range(6):
            wk.Q[b, k] = 0.0
    for r in range(model.nrow):
        wk.gB[r] = -err[r]
    return solve_constrained(model, wk, solver)


@njit(cache=True, error_model="numpy", _nrt=True)
def project(model, wk, t, y, solver, tol, maxit):
    """Mass-weighted projection of positions then velocities onto the constraint manifold
    (physics.md d.4). Position: dx = -M^-1 J^T (J M^-1 J^T)^-1 phi (Newton iterations);
    velocity: the same with phi_dot. Reuses the constrained solve with Q = 0. Returns the
    status of the solves."""
    nb = model.nb
    m = model.nrow
    if m == 0:
        return _SUCCESS
    pnew = np.empty(4)
    for _ in range(maxit):
        constraint_rows(model, t, y, wk)
        err = 0.0
        for r in range(m):
            err = max(err, abs(wk.phi[r]))
        if err <= tol:
            break
        st = _correction(model, wk, wk.phi, solver)
        if st != 0:
            return st
        for b in range(nb):
            q = 7 * b
            for k in range(3):
                y[q + k] += wk.vd[b, k]
            quat_rotate_body(y[q + 3 : q + 7], wk.vd[b, 3:6], pnew)
            nrm = math.sqrt(pnew[0] ** 2 + pnew[1] ** 2 + pnew[2] ** 2 + pnew[3] ** 2)
            for k in range(4):
                y[q + 3 + k] = pnew[k] / nrm
    constraint_rows(model, t, y, wk)
    st = _correction(model, wk, wk.phid, solver)
    if st != 0:
        return st
    off = model.y_iv
    for b in range(nb):
        for k in range(6):
            y[off + 6 * b + k] += wk.vd[b, k]
    return _SUCCESS


@njit(cache=True, error_model="numpy", _nrt=False)
def normalise_quaternions(model, y, k):
    """p <- p/|p| for every body (physics.md b.2), scaling the p-rows of the derivative k by
    the same factor: p_dot = (1/2) p (x) (0, omega') is linear in p, so (y, k) stay an exact
    state-derivative pair (FSAL remains valid). Pass k of length 0 to skip it."""
    for b in range(model.nb):
        q = 7 * b + 3
        n = math.sqrt(y[q] ** 2 + y[q + 1] ** 2 + y[q + 2] ** 2 + y[q + 3] ** 2)
        for i in range(4):
            y[q + i] /= n
            if k.shape[0] > 0:
                k[q + i] /= n


@njit(cache=True, error_model="numpy", _nrt=False)
def finite(y):
    for i in range(y.shape[0]):
        if not np.isfinite(y[i]):
            return False
    return True


@njit(cache=True, inline="always", error_model="numpy")
def returned(ctl, st, iout, t, nlog):
    """What a loop call returns, also kept in its control array (kinds.CT_STATUS)."""
    ctl[CT_STATUS] = st
    ctl[CT_T] = t
    ctl[CT_IOUT] = iout
    ctl[CT_NLOG] = nlog
    return st, iout, t, nlog


@njit(cache=True, inline="always", error_model="numpy")
def record(cs, out, i):
    """The discrete contact state valid at output i."""
    for p in range(cs.flag.shape[0]):
        out.CS[i, p, 0] = cs.flag[p]
        out.CS[i, p, 1] = cs.ddm[p]


@njit(cache=True, error_model="numpy", _nrt=False)
def _g(w, y, c):
    acc = 0.0
    for i in range(w.shape[0]):
        acc += w[i] * y[i]
    return acc - c


@njit(cache=True, error_model="numpy", _nrt=False)
def section(model, out, t, y, ynew, K, P, h, w, ytmp):
    """A Poincare section crossed within the accepted step from (t, y) to (t + h, ynew):
    g(y) = out.sec_w . y - out.sec[0] changes sign in the direction out.sec[1] (+1 upward,
    -1 downward, 0 both) between the step's ends. The crossing is located on the step's
    dense output (y, the stages K, weights P: `events.interpolate`) by the Illinois method
    to |g| <= 1e-13 (|g| scale) or 1e-14 of the step, as contact onsets are, and the state
    there (quaternions normalised) written to out.sec_t / out.sec_Y; out.sec[2] counts the
    crossings (beyond the buffer too). Two crossings within one step are not seen: the
    step must resolve the motion of the section's coordinate (it does, at the tolerances
    that resolve the motion itself)."""
    sw = out.sec_w
    if sw.shape[0] == 0:
        return
    c = out.sec[0]
    d = out.sec[1]
    ga = _g(sw, y, c)
    gb = _g(sw, ynew, c)
    up = ga < 0.0 and gb >= 0.0
    down = ga > 0.0 and gb <= 0.0
    if not ((up and d >= 0.0) or (down and d <= 0.0)):
        return
    scale = 0.0
    for i in range(sw.shape[0]):
        scale += abs(sw[i] * y[i]) + abs(sw[i] * ynew[i])
    gtol = 1e-13 * max(scale, abs(c), 1e-300)
    xa, xb = 0.0, 1.0
    x = 1.0
    kept = 0  # Illinois: halve the value kept twice on one side
    if gb == 0.0:
        for i in range(y.shape[0]):
            ytmp[i] = ynew[i]
    else:
        for _ in range(100):
            x = xb - gb * (xb - xa) / (gb - ga)
            if not (xa < x < xb):
                x = 0.5 * (xa + xb)
            interpolate(y, K, P, h, x, ytmp, w)
            g = _g(sw, ytmp, c)
            if abs(g) <= gtol or xb - xa <= 1e-14:
                break
            if (g > 0.0) == (gb > 0.0):
                xb, gb = x, g
                if kept == -1:
                    ga *= 0.5
                kept = -1
            else:
                xa, ga = x, g
                if kept == 1:
                    gb *= 0.5
                kept = 1
    n = int(out.sec[2])
    if n < out.sec_t.shape[0]:
        out.sec_t[n] = t + x * h
        for i in range(y.shape[0]):
            out.sec_Y[n, i] = ytmp[i]
        normalise_quaternions(model, out.sec_Y[n], out.sec_Y[n, :0])
    out.sec[2] = n + 1


@njit(cache=True, error_model="numpy")
def start(model, wk, cs, opts, out, t0, y):
    """Begin a run at (t0, y): reset the statistics, project y if asked, set the contact
    state of y (points already in contact start latched at their approach velocity) and
    write the samples at t <= t0. Returns (status, outputs written, events logged)."""
    for k in range(NSTATS):
        out.stats[k] = 0.0
    out.stats[ST_HMIN] = np.inf
    out.sec[2] = 0.0
    if opts.proj_tol > 0.0:
        st = project(model, wk, t0, y, opts.solver, opts.proj_tol, np.int64(5))
        if st != 0:
            return _SINGULAR, 0, 0
    nlog = np.int64(0)
    if model.nclr > 0:
        _, nlog = update_contacts(model, wk, cs, t0, y, out.log, nlog, np.bool_(False))
    iout = 0
    while iout < out.t_out.shape[0] and out.t_out[iout] <= t0:
        out.Y[iout, :] = y
        record(cs, out, iout)
        iout += 1
    return _SUCCESS, iout, nlog


@njit(cache=True, error_model="numpy", _nrt=False)
def sample(model, wk, cs, opts, out, i):
    """Finish output i, interpolated into out.Y[i] from the step's dense output: project it
    (the interpolant is off the manifold by its own error) or normalise its quaternions,
    record the contact state and note the step (out.piece[i]: the accepted steps so far,
    this one included). Returns the status of the projection."""
    if opts.proj_tol > 0.0:
        st = project(model, wk, out.t_out[i], out.Y[i], opts.solver, opts.proj_tol, np.int64(3))
        if st != 0:
            return st
    else:
        normalise_quaternions(model, out.Y[i], out.Y[i, :0])
    record(cs, out, i)
    out.piece[i] = np.int64(out.stats[ST_NACC])
    return _SUCCESS


@njit(cache=True, error_model="numpy", _nrt=False)
def after_step(model, wk, cs, opts, out, t, y, kfsal, nlog, cut):
    """The on-accept hook, after a step to (t, y) (cut: the step was cut at an event): the
    discrete contact update and event log, quaternion normalisation (scaling the stage kfsal
    = f(t, y) along, see `normalise_quaternions`; length 0 if none) and projection.
    Returns (status, changed, nlog); changed: y or the discrete state changed, so kfsal no
    longer equals f(t, y)."""
    if not finite(y):
        return _NONFINITE, False, nlog
    changed = cut
    if model.nclr > 0:
        ch, nlog = update_contacts(model, wk, cs, t, y, out.log, nlog, cut)
        changed = changed or ch
    normalise_quaternions(model, y, kfsal)
    if opts.proj_tol > 0.0:
        st = project(model, wk, t, y, opts.solver, opts.proj_tol, np.int64(3))
        out.stats[ST_NPROJ] += 1
        if st != 0:
            return _SINGULAR, changed, nlog
        changed = True
    return _SUCCESS, changed, nlog


@njit(cache=True, error_model="numpy", _nrt=False)
def track_peaks(wk, t, PK, first):
    """PK[k] = (largest F_N, its time, largest delta, its time) of clearance joint k over the
    states seen so far, from the diagnostics wk.cout of the last evaluation, which must be
    f(t, y) on the solution. Impacts last ~10-20 steps, so the accepted steps resolve a peak
    that an output grid coarser than the impact can miss entirely. first: reset."""
    for k in range(wk.cout.shape[0]):
        fn = wk.cout[k, CO_FN]
        d = wk.cout[k, CO_DELTA]
        if first or fn > PK[k, 0]:
            PK[k, 0] = fn
            PK[k, 1] = t
        if first or d > PK[k, 2]:
            PK[k, 2] = d
            PK[k, 3] = t
