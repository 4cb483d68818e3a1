"""Post-processing at the output times (compiled): accelerations, multipliers, violations,
energies, joint reactions and clearance-joint diagnostics, re-evaluated from the saved
states and the discrete contact state recorded with them."""

from __future__ import annotations

import numpy as np
from numba import njit

from clearance.contact.element import contact_energy, joint_outputs
from clearance.dynamics.forces import kinetic_energy, potential_energy
from clearance.dynamics.rhs import rhs
from clearance.kinematics.rotations import cross, matvec, sub


@njit(cache=True, error_model="numpy", nogil=True)
def post_process(
    model,
    wk,
    cs,
    alpha,
    beta,
    solver,
    ts,
    Y,
    CS,
    n,
    blk_row0,
    blk_nrow,
    blk_side,
    blk_pt,
    VD,
    LAM,
    PHI,
    PHID,
    EN,
    RF,
    RM,
    COUT,
    POUT,
):
    """For each of the first n outputs fill VD (v_dot), LAM, PHI, PHID, EN (T, V, V_c), the
    reaction force RF and moment RM (world, about the joint point) of each block on its
    reporting body (side 1: body j, side 0: body i), and the clearance diagnostics COUT (per
    joint) and POUT (per contact point). cs: scratch for the contact state of each sample,
    taken from CS."""
    nb = model.nb
    yd = np.empty(Y.shape[1])
    for k in range(n):
        y = Y[k]
        for p in range(model.ncp):
            cs.flag[p] = int(CS[k, p, 0])
            cs.ddm[p] = CS[k, p, 1]
        rhs(ts[k], y, model, wk, cs, alpha, beta, solver, yd)
        joint_outputs(model, wk)
        for c in range(model.nclr):
            for a in range(wk.cout.shape[1]):
                COUT[k, c, a] = wk.cout[c, a]
        for p in range(model.ncp):
            for a in range(wk.pout.shape[1]):
                POUT[k, p, a] = wk.pout[p, a]
        for i in range(6 * nb):
            VD[k, i] = yd[model.y_iv + i]
        for r in range(model.nrow):
            LAM[k, r] = wk.lam[r]
            PHI[k, r] = wk.phi[r]
            PHID[k, r] = wk.phid[r]
        EN[k, 0] = kinetic_energy(model, y, wk.bJ)
        EN[k, 1] = potential_energy(model, y, wk.bA, wk.br)
        EN[k, 2] = contact_energy(model, wk.bA, wk.br, wk.fval)
        for bk in range(blk_row0.shape[0]):
            if blk_nrow[bk] == 0:
                continue
            side = blk_side[bk]
            o = 6 * side
            F0, F1, F2, n0, n1, n2 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            for r in range(blk_row0[bk], blk_row0[bk] + blk_nrow[bk]):
                lr = wk.lam[r]
                F0 -= wk.J[r, o] * lr
                F1 -= wk.J[r, o + 1] * lr
                F2 -= wk.J[r, o + 2] * lr
                n0 -= wk.J[r, o + 3] * lr
                n1 -= wk.J[r, o + 4] * lr
                n2 -= wk.J[r, o + 5] * lr
            b = model.row_bj[blk_row0[bk]] if side == 1 else model.row_bi[blk_row0[bk]]
            A = wk.bA[b]
            F = (F0, F1, F2)
            nw = matvec(A, (n0, n1, n2))
            s = matvec(A, blk_pt[bk])
            nP = sub(nw, cross(s, F))
            for a in range(3):
                RF[k, bk, a] = F[a]
                RM[k, bk, a] = nP[a]
