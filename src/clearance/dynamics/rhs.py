"""The right-hand side y -> y_dot of the augmented equations of motion (physics.md d).

Pipeline, readable top to bottom: body kinematics -> time functions -> constraint rows ->
applied forces -> clearance-joint contact forces -> Baumgarte (the one place it is applied)
-> constrained solve -> y_dot.

Hot-path kernels (here, in solve, primitives, contact and the integrator loops) are
compiled with `_nrt=False`, i.e. without numba's reference counting. With it, every call
that passes the Model / Work named tuples increfs and decrefs each of their ~70 arrays
(atomic operations), and every array view (`bA[b]`) does the same: that cost about 40 % of
a right-hand side. The kernels never allocate, so they need no reference counting; the few
helpers that do allocate (dense LU, least squares) are compiled with
`_nrt=True` and called from the kernels as usual. Callees without the option inherit it from
the first caller that compiles them, which only changes their speed, never their results.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from clearance.constraints.primitives import eval_primitives
from clearance.contact.element import clearance_forces
from clearance.dynamics.forces import applied_forces
from clearance.dynamics.solve import nn, solve_constrained
from clearance.kinematics.rotations import quat_rate, quat_to_rot
from clearance.kinematics.timefn import eval_all
from clearance.layout import NCOUT, NPOUT, W_A, W_C, W_D, W_L, W_M

#: most stages (with the dense output's extra ones) of an integration method (tableau.py)
MAX_STAGES = 16


class Work(NamedTuple):
    """Preallocated scratch arrays of one right-hand-side evaluation (no allocation inside)."""

    bA: np.ndarray  # (nb+1, 3, 3) rotation matrices, last = ground
    br: np.ndarray  # (nb+1, 3) positions
    brd: np.ndarray  # (nb+1, 3) velocities
    bw: np.ndarray  # (nb+1, 3) world angular velocities
    fval: np.ndarray  # (nfn, 3)
    phi: np.ndarray  # (m,)
    phit: np.ndarray
    gam: np.ndarray
    phid: np.ndarray
    gB: np.ndarray
    J: np.ndarray  # (m, 12)
    JM: np.ndarray  # (m, 12)
    S: np.ndarray  # (m, m)
    dinv: np.ndarray  # (m,) 1 / diag of the Cholesky factor
    rl: np.ndarray  # (m,)
    lam: np.ndarray  # (m,)
    Q: np.ndarray  # (nb, 6)
    MiQ: np.ndarray  # (nb, 6)
    vd: np.ndarray  # (nb, 6)
    cout: np.ndarray  # (nclr, NCOUT) clearance-joint diagnostics of the last evaluation
    pout: np.ndarray  # (ncp, NPOUT) contact-point diagnostics of the last evaluation
    ev_d: np.ndarray  # (ncp, 5) scratch of the event search: the gaps at the step's probes
    bJ: np.ndarray  # (nb, 3, 3) current inertia J'(t) (constant unless InertiaVariation)
    bJinv: np.ndarray  # (nb, 3, 3) its inverse
    bJd: np.ndarray  # (nb, 3) diagonal of J'_dot (the variation is diagonal in body axes)
    dw: np.ndarray  # (MAX_STAGES,) scratch of the event search: the dense-output weights


def make_work(model) -> Work:
    nb, m = model.nb, model.nrow
    bA = np.zeros((nb + 1, 3, 3))
    bA[nb] = np.eye(3)
    return Work(
        bA=bA,
        br=np.zeros((nb + 1, 3)),
        brd=np.zeros((nb + 1, 3)),
        bw=np.zeros((nb + 1, 3)),
        fval=np.zeros((model.fn_kind.shape[0], 3)),
        phi=np.zeros(m),
        phit=np.zeros(m),
        gam=np.zeros(m),
        phid=np.zeros(m),
        gB=np.zeros(m),
        J=np.zeros((m, 12)),
        JM=np.zeros((m, 12)),
        S=np.zeros((m, m)),
        dinv=np.zeros(m),
        rl=np.zeros(m),
        lam=np.zeros(m),
        Q=np.zeros((nb, 6)),
        MiQ=np.zeros((nb, 6)),
        vd=np.zeros((nb, 6)),
        cout=np.zeros((model.nclr, NCOUT)),
        pout=np.zeros((model.ncp, NPOUT)),
        ev_d=np.zeros((model.ncp, 5)),
        bJ=np.array(model.body_J, dtype=float).reshape(nb, 3, 3),
        bJinv=np.array(model.body_Jinv, dtype=float).reshape(nb, 3, 3),
        bJd=np.zeros((nb, 3)),
        dw=np.zeros(MAX_STAGES),
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def body_states(model, y, wk):
    """Rotation matrices, positions, velocities and world angular velocities of all bodies."""
    nb = model.nb
    off = model.y_iv
    for b in range(nb):
        q = 7 * b
        quat_to_rot(y[q + 3], y[q + 4], y[q + 5], y[q + 6], wk.bA[b])
        v = off + 6 * b
        A = wk.bA[b]
        for a in range(3):
            wk.br[b, a] = y[q + a]
            wk.brd[b, a] = y[v + a]
            wk.bw[b, a] = A[a, 0] * y[v + 3] + A[a, 1] * y[v + 4] + A[a, 2] * y[v + 5]


@njit(cache=True, error_model="numpy", _nrt=False)
def update_inertia(model, wk):
    """J'(t) = J'_0 + diag(k) (l(t) - a)^2 and J'_dot for InertiaVariation bodies (physics.md
    i); needs wk.fval evaluated at t."""
    for b in range(model.nb):
        fn = model.body_vfn[b]
        if fn < 0:
            continue
        x = wk.fval[fn, 0] - model.body_var[b, 3]
        xd = wk.fval[fn, 1]
        for a in range(3):
            for c in range(3):
                wk.bJ[b, a, c] = model.body_J[b, a, c]
            k = model.body_var[b, a]
            wk.bJ[b, a, a] += k * x * x
            wk.bJd[b, a] = 2.0 * k * x * xd
        _inverse(wk.bJ[b], wk.bJinv[b])


@njit(cache=True, error_model="numpy", _nrt=False)
def _inverse(A, out):
    """out = A^-1 of a 3x3 matrix by its cofactors (adjugate / determinant). For the
    symmetric positive definite inertias it inverts, the relative error is of the order
    cond(A) x machine epsilon, as with LAPACK's LU; `np.linalg.inv` here cost ~3.5 s of
    every cold compile (its LAPACK wrapper and error machinery) for nine products."""
    c00 = A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1]
    c01 = A[1, 2] * A[2, 0] - A[1, 0] * A[2, 2]
    c02 = A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]
    r = 1.0 / (A[0, 0] * c00 + A[0, 1] * c01 + A[0, 2] * c02)
    out[0, 0] = c00 * r
    out[1, 0] = c01 * r
    out[2, 0] = c02 * r
    out[0, 1] = (A[0, 2] * A[2, 1] - A[0, 1] * A[2, 2]) * r
    out[1, 1] = (A[0, 0] * A[2, 2] - A[0, 2] * A[2, 0]) * r
    out[2, 1] = (A[0, 1] * A[2, 0] - A[0, 0] * A[2, 1]) * r
    out[0, 2] = (A[0, 1] * A[1, 2] - A[0, 2] * A[1, 1]) * r
    out[1, 2] = (A[0, 2] * A[1, 0] - A[0, 0] * A[1, 2]) * r
    out[2, 2] = (A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]) * r


@njit(cache=True, error_model="numpy", _nrt=False)
def constraint_rows(model, t, y, wk):
    """Kinematics of all constraint rows: phi, phi_t, gamma, J and phi_dot = J v + phi_t.

    Also evaluates the time functions and the time-dependent inertias at t (every later
    stage of the evaluation reads them from wk)."""
    body_states(model, y, wk)
    eval_all(model.fn_kind, model.fn_ptr, model.fn_data, t, wk.fval)
    update_inertia(model, wk)
    eval_primitives(model, wk.bA, wk.br, wk.brd, wk.bw, wk.fval, wk.phi, wk.phit, wk.gam, wk.J)
    off = model.y_iv
    for r in range(model.nrow):
        s = wk.phit[r]
        for side in range(2):
            b = model.row_bi[r] if side == 0 else model.row_bj[r]
            if b >= 0:
                for k in range(6):
                    s += wk.J[r, nn(6 * side + k)] * y[nn(off + 6 * b + k)]
        wk.phid[r] = s


@njit(cache=True, error_model="numpy", _nrt=False)
def rhs(t, y, model, wk, cs, alpha, beta, solver, ydot):
    """Write y_dot; return 0 on success, 1 if the constraint matrix is singular.

    cs: the discrete contact state (`clearance.contact.element.ContactState`, read only);
    alpha, beta: Baumgarte parameters [1/s] (physics.md d.2); solver: Solver enum value.
    """
    nb = model.nb
    m = model.nrow
    constraint_rows(model, t, y, wk)
    p_applied, p_limb = applied_forces(model, y, wk)
    p_moving = 0.0
    if model.nclr > 0:
        p_moving = clearance_forces(model, y, wk, cs, ydot)
    # Baumgarte stabilisation: the only place it enters (physics.md d.2)
    b2 = beta * beta
    for r in range(m):
        wk.gB[r] = wk.gam[r] - 2.0 * alpha * wk.phid[r] - b2 * wk.phi[r]
    status = solve_constrained(model, wk, solver)
    off = model.y_iv
    for b in range(nb):
        q = nn(7 * b)
        v = nn(off + 6 * b)
        ydot[q] = y[v]
        ydot[q + 1] = y[v + 1]
        ydot[q + 2] = y[v + 2]
        pd = quat_rate((y[q + 3], y[q + 4], y[q + 5], y[q + 6]), (y[v + 3], y[v + 4], y[v + 5]))
        ydot[q + 3] = pd[0]
        ydot[q + 4] = pd[1]
        ydot[q + 5] = pd[2]
        ydot[q + 6] = pd[3]
        for k in range(6):
            ydot[v + k] = wk.vd[b, k]
    # power of the constraint forces -lam^T phi_q v (physics.md j), all rows and drivers only
    pc = 0.0
    pd_ = 0.0
    for r in range(m):
        p = -wk.lam[r] * (wk.phid[r] - wk.phit[r])
        pc += p
        if model.row_drv[r] == 1:
            pd_ += p
    w0 = model.y_iw
    ydot[w0 + W_C] = pc
    ydot[w0 + W_D] = pd_
    ydot[w0 + W_A] = p_applied
    ydot[w0 + W_M] = p_moving
    ydot[w0 + W_L] = p_limb
    return status
