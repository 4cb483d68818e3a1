"""Integrators that own the hot loop (compiled; no Python per step).

`erk54`: adaptive explicit 7-stage FSAL Runge-Kutta 5(4) pair given by its tableau
(tableau.py: Dormand-Prince "dopri5" or Tsitouras "tsit5"), PI step-size control (Hairer &
Wanner, DOPRI5 constants, for both pairs), dense output at the requested times (steps are
never shortened to hit the output grid). `rk4`: classical fixed step, with the step fitted to
the output grid. Both can apply mass-weighted coordinate projection (physics.md d.4) after
accepted steps.

Status codes (also in `Status`): 0 done, 1 singular constraint matrix, 2 step size
underflow, 3 too many steps, 4 non-finite state.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.contact.joint import CO_DELTA, CO_FN
from clearance.dynamics.rhs import constraint_rows, rhs
from clearance.dynamics.solve import solve_constrained
from clearance.integrate.events import interpolate, locate_event, update_contacts
from clearance.kinds import (
    NSTATS,
    ST_HLAST,
    ST_HMAX,
    ST_HMIN,
    ST_NACC,
    ST_NEVT,
    ST_NFEV,
    ST_NPROJ,
    ST_NREJ,
)
from clearance.kinematics.rotations import quat_rotate_body


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


@njit(cache=True, error_model="numpy")
def project(model, wk, t, y, solver, tol, maxit):
    """Mass-weighted projection of positions then velocities onto the constraint manifold.

    Position: dx = -M^-1 J^T (J M^-1 J^T)^-1 phi (Newton iterations); velocity: the same with
    phi_dot. Reuses the constrained solve with Q = 0. Returns the status of the solves.
    """
    nb = model.nb
    m = model.nrow
    if m == 0:
        return 0
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
    off = 7 * nb
    for b in range(nb):
        for k in range(6):
            y[off + 6 * b + k] += wk.vd[b, k]
    return 0


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
def _err_norm(e, y, ynew, n, rtol, atol):
    s = 0.0
    for i in range(n):
        sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        s += (e[i] / sc) ** 2
    return math.sqrt(s / n)


@njit(cache=True, error_model="numpy", _nrt=False)
def _finite(y):
    for i in range(y.shape[0]):
        if not np.isfinite(y[i]):
            return False
    return True


@njit(cache=True, error_model="numpy")
def erk54(
    model,
    wk,
    alpha,
    beta,
    solver,
    A,
    C,
    E,
    P,
    t0,
    y0,
    t_out,
    rtol,
    atol,
    h0,
    hmax,
    hmin,
    max_steps,
    proj_tol,
    Y,
    CS,
    log,
    stats,
    PK,
):
    """Integrate from (t0, y0) and write y at the times t_out into Y (n_out, ny).

    (A, C, E, P): the pair's tableau (tableau.py layout; A[6] = b, b_7 = 0, so stage 7 is
    f at the new solution, FSAL); E gives the error estimate, P the dense output.

    proj_tol > 0 enables coordinate projection after each accepted step. Contact events of
    clearance joints are located on the dense output and the step is cut there (events.py);
    CS (n_out, nclr, 2) receives the discrete contact state (flag, delta_dot_minus) valid at
    each output, `log` the events, PK (nclr, 4) the largest normal force and penetration
    at the accepted steps (see _track_peaks). Returns (status, outputs written, last time,
    events).
    """
    ny = y0.shape[0]
    nerr = 13 * model.nb + 3 * model.nclr  # the work integrals do not steer the step size
    K = np.zeros((7, ny))
    y = y0.copy()
    ynew = np.empty(ny)
    ytmp = np.empty(ny)
    err = np.empty(ny)
    empty = np.empty(0)
    t = t0
    t_end = t_out[-1]
    nout = t_out.shape[0]
    iout = 0
    nlog = 0
    for k in range(NSTATS):
        stats[k] = 0.0
    stats[ST_HMIN] = np.inf
    if proj_tol > 0.0:
        st = project(model, wk, t, y, solver, proj_tol, 5)
        if st != 0:
            return 1, iout, t, nlog
    if model.nclr > 0:
        _, nlog = update_contacts(model, wk, t, y, log, nlog)
    while iout < nout and t_out[iout] <= t0:
        Y[iout, :] = y
        _record(wk, CS, iout)
        iout += 1
    st = rhs(t, y, model, wk, alpha, beta, solver, K[0])
    stats[ST_NFEV] += 1
    if st != 0:
        return 1, iout, t, nlog
    _track_peaks(wk, t, PK, True)
    # initial step (Hairer & Wanner I, II.4)
    h = h0
    if h <= 0.0:
        d0 = 0.0
        d1 = 0.0
        for i in range(nerr):
            sc = atol + rtol * abs(y[i])
            d0 += (y[i] / sc) ** 2
            d1 += (K[0, i] / sc) ** 2
        d0 = math.sqrt(d0 / nerr)
        d1 = math.sqrt(d1 / nerr)
        h = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h = min(h, hmax, t_end - t0)
        for i in range(ny):
            ytmp[i] = y[i] + h * K[0, i]
        rhs(t + h, ytmp, model, wk, alpha, beta, solver, K[1])
        stats[ST_NFEV] += 1
        d2 = 0.0
        for i in range(nerr):
            sc = atol + rtol * abs(y[i])
            d2 += ((K[1, i] - K[0, i]) / sc) ** 2
        d2 = math.sqrt(d2 / nerr) / h
        if max(d1, d2) <= 1e-15:
            h1 = max(1e-6, h * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** 0.2
        h = min(100 * h, h1, hmax, t_end - t0)
    # PI controller constants (DOPRI5's, used for both pairs): expo1 = 0.2 - 0.75 beta_pi
    beta_pi = 0.04
    expo1 = 0.2 - 0.75 * beta_pi
    safe = 0.9
    facold = 1e-4
    rejected = False
    nsteps = 0
    while t < t_end:
        if nsteps >= max_steps:
            return 3, iout, t, nlog
        if h < hmin:
            return 2, iout, t, nlog
        if t + 1.01 * h >= t_end:
            h = t_end - t
        # stages 2..7
        bad = False
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
            st = rhs(t + C[s] * h, ytmp, model, wk, alpha, beta, solver, K[s])
            stats[ST_NFEV] += 1
            if st != 0:
                bad = True
                break
        nsteps += 1
        if not bad:
            for i in range(ny):
                ynew[i] = ytmp[i]  # stage 7 is evaluated at the 5th-order solution (FSAL)
                err[i] = E[0] * K[0, i]
            for k in range(1, 7):
                e = E[k]
                for i in range(ny):
                    err[i] += e * K[k, i]
            for i in range(ny):
                err[i] *= h
            en = _err_norm(err, y, ynew, nerr, rtol, atol)
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
            if model.nclr > 0:
                xev, _ = locate_event(model, wk, t, y, K, P, h)
            if xev <= 1.0:
                interpolate(y, K, P, h, xev, ynew)
                tnew = t + xev * h
                stats[ST_NEVT] += 1
            else:
                tnew = t + h
            # dense output for every requested time in (t, tnew]
            while iout < nout and t_out[iout] <= tnew:
                interpolate(y, K, P, h, (t_out[iout] - t) / h, Y[iout])
                if proj_tol > 0.0:
                    # the interpolant is off the manifold by its own error: project samples too
                    st = project(model, wk, t_out[iout], Y[iout], solver, proj_tol, 3)
                    if st != 0:
                        return 1, iout, t, nlog
                else:
                    normalise_quaternions(model, Y[iout], empty)
                _record(wk, CS, iout)
                iout += 1
            t = tnew
            for i in range(ny):
                y[i] = ynew[i]
            if not _finite(y):
                return 4, iout, t, nlog
            changed = xev <= 1.0
            if model.nclr > 0:
                ch, nlog = update_contacts(model, wk, t, y, log, nlog)
                changed = changed or ch
            normalise_quaternions(model, y, K[6])
            if proj_tol > 0.0:
                st = project(model, wk, t, y, solver, proj_tol, 3)
                stats[ST_NPROJ] += 1
                if st != 0:
                    return 1, iout, t, nlog
                changed = True
            if changed:  # the FSAL stage no longer matches (y, discrete state)
                st = rhs(t, y, model, wk, alpha, beta, solver, K[0])
                stats[ST_NFEV] += 1
                if st != 0:
                    return 1, iout, t, nlog
            else:
                for i in range(ny):
                    K[0, i] = K[6, i]  # FSAL
            # the last evaluation was f(t, y): stage 7 at the new solution, or the re-evaluation
            _track_peaks(wk, t, PK, False)
            if rejected:
                hnew = min(hnew, h)
            rejected = False
            h = min(hnew, hmax)
            stats[ST_HLAST] = h
        else:
            stats[ST_NREJ] += 1
            h = h / min(5.0, fac11 / safe)
            rejected = True
    return 0, iout, t, nlog


@njit(cache=True, error_model="numpy", _nrt=False)
def _track_peaks(wk, t, PK, first):
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


@njit(cache=True, error_model="numpy", _nrt=False)
def _record(wk, CS, iout):
    for k in range(wk.cflag.shape[0]):
        CS[iout, k, 0] = wk.cflag[k]
        CS[iout, k, 1] = wk.cddm[k]


@njit(cache=True, error_model="numpy")
def rk4(model, wk, alpha, beta, solver, t0, y0, t_out, h, proj_tol, Y, CS, log, stats, PK):
    """Classical RK4; between consecutive output times the step is dt/ceil(dt/h) <= h.
    PK: peaks at the step starts (see _track_peaks; the last state is covered by the
    outputs).

    Contact events are not localised: the discrete contact state is updated at the end of
    each step (first-order capture of delta_dot_minus, physics.md f.5)."""
    ny = y0.shape[0]
    y = y0.copy()
    k1 = np.empty(ny)
    k2 = np.empty(ny)
    k3 = np.empty(ny)
    k4 = np.empty(ny)
    ytmp = np.empty(ny)
    for k in range(NSTATS):
        stats[k] = 0.0
    t = t0
    nout = t_out.shape[0]
    iout = 0
    nlog = 0
    if proj_tol > 0.0:
        if project(model, wk, t, y, solver, proj_tol, 5) != 0:
            return 1, iout, t, nlog
    if model.nclr > 0:
        _, nlog = update_contacts(model, wk, t, y, log, nlog)
    while iout < nout and t_out[iout] <= t0:
        Y[iout, :] = y
        _record(wk, CS, iout)
        iout += 1
    while iout < nout:
        dt = t_out[iout] - t
        n = max(1, int(math.ceil(dt / h - 1e-9)))
        hs = dt / n
        for _ in range(n):
            st = rhs(t, y, model, wk, alpha, beta, solver, k1)
            _track_peaks(wk, t, PK, stats[ST_NFEV] == 0.0)
            for i in range(ny):
                ytmp[i] = y[i] + 0.5 * hs * k1[i]
            st |= rhs(t + 0.5 * hs, ytmp, model, wk, alpha, beta, solver, k2)
            for i in range(ny):
                ytmp[i] = y[i] + 0.5 * hs * k2[i]
            st |= rhs(t + 0.5 * hs, ytmp, model, wk, alpha, beta, solver, k3)
            for i in range(ny):
                ytmp[i] = y[i] + hs * k3[i]
            st |= rhs(t + hs, ytmp, model, wk, alpha, beta, solver, k4)
            stats[ST_NFEV] += 4
            if st != 0:
                return 1, iout, t, nlog
            for i in range(ny):
                y[i] += hs / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            t += hs
            stats[ST_NACC] += 1
            if not _finite(y):
                return 4, iout, t, nlog
            normalise_quaternions(model, y, k4[:0])
            if proj_tol > 0.0:
                if project(model, wk, t, y, solver, proj_tol, 3) != 0:
                    return 1, iout, t, nlog
                stats[ST_NPROJ] += 1
            if model.nclr > 0:
                _, nlog = update_contacts(model, wk, t, y, log, nlog)
        t = t_out[iout]
        Y[iout, :] = y
        _record(wk, CS, iout)
        iout += 1
    stats[ST_HMIN] = h
    stats[ST_HMAX] = h
    return 0, iout, t, nlog
