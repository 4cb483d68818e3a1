"""Constraint primitives of physics.md c.2 (angular-velocity form), compiled.

Each primitive writes its rows together: phi, phi_t, gamma and the Jacobian row blocks.
Jacobian storage is row-block compressed: `J[r, 0:12]` holds the columns
(r_i, omega'_i, r_j, omega'_j) of row r; the bodies are `prim_bi`, `prim_bj` (index -1 is the
ground, stored as the last slot of the body arrays, so ground terms vanish naturally).
Convention: phi_dot = phi_q v + phi_t; phi_ddot = phi_q v_dot - gamma (gamma = minus the
velocity-quadratic and explicit-time terms).
"""

from __future__ import annotations

import math

from numba import njit

from clearance.kinds import AB_I, AB_J, AX_I, AX_J, SB_I, SB_J, PrimKind
from clearance.kinematics.points import moving_point
from clearance.kinematics.rotations import (
    add,
    cross,
    dot,
    mattvec,
    matvec,
    rot_axis_apply,
    scale,
    sub,
    ww,
)


@njit(cache=True, inline="always", error_model="numpy")
def _put(J, r, k, v):
    J[r, k] = v[0]
    J[r, k + 1] = v[1]
    J[r, k + 2] = v[2]


@njit(cache=True, error_model="numpy", _nrt=False)
def _target_vectors(fval, ix):
    """c, c_dot, c_ddot of c(t) = R1(t1) R2(t2) R3(t3) e_m (orientation driver).

    ix = [fn1, fn2, fn3, ax1, ax2, ax3, m]. dR/dtk replaces factor k by Rk ek~, the second
    derivative by Rk ek~ ek~ (mixed terms: two first-derivative factors).
    """
    th = (fval[ix[0], 0], fval[ix[1], 0], fval[ix[2], 0])
    thd = (fval[ix[0], 1], fval[ix[1], 1], fval[ix[2], 1])
    thdd = (fval[ix[0], 2], fval[ix[1], 2], fval[ix[2], 2])
    ax = (ix[3], ix[4], ix[5])
    m = ix[6]
    em = (1.0 if m == 0 else 0.0, 1.0 if m == 1 else 0.0, 1.0 if m == 2 else 0.0)
    c = (0.0, 0.0, 0.0)
    cd = (0.0, 0.0, 0.0)
    cdd = (0.0, 0.0, 0.0)
    # enumerate the factor-kind triples (k1, k2, k3) with total derivative order <= 2
    for k1 in range(3):
        for k2 in range(3):
            for k3 in range(3):
                order = k1 + k2 + k3
                if order > 2:
                    continue
                x = rot_axis_apply(ax[2], th[2], em, k3)
                x = rot_axis_apply(ax[1], th[1], x, k2)
                x = rot_axis_apply(ax[0], th[0], x, k1)
                if order == 0:
                    c = x
                elif order == 1:
                    k = 0 if k1 == 1 else (1 if k2 == 1 else 2)
                    cd = add(cd, scale(thd[k], x))
                    cdd = add(cdd, scale(thdd[k], x))
                else:
                    if k1 == 2 or k2 == 2 or k3 == 2:
                        k = 0 if k1 == 2 else (1 if k2 == 2 else 2)
                        cdd = add(cdd, scale(thd[k] * thd[k], x))
                    else:
                        # two distinct first-derivative factors: appears twice in R_ddot
                        coef = 1.0
                        if k1 == 1:
                            coef *= thd[0]
                        if k2 == 1:
                            coef *= thd[1]
                        if k3 == 1:
                            coef *= thd[2]
                        cdd = add(cdd, scale(2.0 * coef, x))
    return c, cd, cdd


@njit(cache=True, error_model="numpy", _nrt=False)
def eval_primitives(model, bA, br, brd, bw, fval, phi, phit, gam, J):
    """Evaluate every primitive of `model` into phi, phi_t, gamma and J (row blocks).

    bA: (nb+1, 3, 3) rotation matrices; br, brd, bw: (nb+1, 3) position, velocity, world
    angular velocity (last slot = ground). fval: (nfn, 3) time functions (f, f_dot, f_ddot).
    """
    for k in range(model.prim_kind.shape[0]):
        kind = model.prim_kind[k]
        i = model.prim_bi[k]
        j = model.prim_bj[k]
        r = model.prim_row[k]
        fn = model.prim_fn[k]
        f, fd, fdd = 0.0, 0.0, 0.0
        if fn >= 0:
            f, fd, fdd = fval[fn, 0], fval[fn, 1], fval[fn, 2]
        Ai = bA[i]
        Aj = bA[j]
        wi = (bw[i, 0], bw[i, 1], bw[i, 2])
        wj = (bw[j, 0], bw[j, 1], bw[j, 2])
        for c in range(12):
            J[r, c] = 0.0
        if kind == PrimKind.DOT1_MOVING:
            aj = matvec(Aj, model.prim_v[k, AB_J])
            cv, cvd, cvdd = _target_vectors(fval, model.prim_ix[k])
            phi[r] = dot(cv, aj)
            _put(J, r, 9, mattvec(Aj, cross(aj, cv)))
            phit[r] = dot(cvd, aj)
            gam[r] = -(dot(cvdd, aj) + 2.0 * dot(cvd, cross(wj, aj)) + dot(cv, ww(wj, aj)))
            continue
        if kind == PrimKind.DOT1:
            ai = matvec(Ai, model.prim_v[k, AB_I])
            aj = matvec(Aj, model.prim_v[k, AB_J])
            phi[r] = dot(ai, aj) - f
            _put(J, r, 3, mattvec(Ai, cross(ai, aj)))
            _put(J, r, 9, mattvec(Aj, cross(aj, ai)))
            phit[r] = -fd
            gam[r] = (
                -(
                    dot(aj, ww(wi, ai))
                    + dot(ai, ww(wj, aj))
                    + 2.0 * dot(cross(wi, ai), cross(wj, aj))
                )
                + fdd
            )
            continue
        # point-based primitives; attachment points may slide along a body axis with a time
        # function (rheonomic, physics.md c.2 "moving attachment point")
        sbi, ui_b, ai_b = moving_point(
            model.prim_v[k, SB_I], model.prim_v[k, AX_I], model.prim_mv[k, 0], fval
        )
        sbj, uj_b, aj_b = moving_point(
            model.prim_v[k, SB_J], model.prim_v[k, AX_J], model.prim_mv[k, 1], fval
        )
        si = matvec(Ai, sbi)
        sj = matvec(Aj, sbj)
        d = sub(add((br[j, 0], br[j, 1], br[j, 2]), sj), add((br[i, 0], br[i, 1], br[i, 2]), si))
        if model.prim_mv[k, 0] >= 0 or model.prim_mv[k, 1] >= 0:
            ui = matvec(Ai, ui_b)  # A sb_dot: velocity of the point relative to its body
            uj = matvec(Aj, uj_b)
            dd = sub(
                add((brd[j, 0], brd[j, 1], brd[j, 2]), add(cross(wj, sj), uj)),
                add((brd[i, 0], brd[i, 1], brd[i, 2]), add(cross(wi, si), ui)),
            )
            du = sub(uj, ui)  # explicit-time part of d_dot
            # velocity-quadratic and explicit-time part of d_ddot:
            # w x (w x s) + 2 w x u + A sb_ddot
            acc = sub(
                add(ww(wj, sj), add(scale(2.0, cross(wj, uj)), matvec(Aj, aj_b))),
                add(ww(wi, si), add(scale(2.0, cross(wi, ui)), matvec(Ai, ai_b))),
            )
        else:
            # fixed points (the common case): the same values without the vanishing u and
            # A sb_ddot terms (adding zeros), about a third of the flops of a point primitive
            dd = sub(
                add((brd[j, 0], brd[j, 1], brd[j, 2]), cross(wj, sj)),
                add((brd[i, 0], brd[i, 1], brd[i, 2]), cross(wi, si)),
            )
            du = (0.0, 0.0, 0.0)
            acc = sub(ww(wj, sj), ww(wi, si))
        if kind == PrimKind.SPHERICAL:
            for a in range(3):
                ra = r + a
                phi[ra] = d[a]
                phit[ra] = du[a]
                gam[ra] = -acc[a]
                J[ra, a] = -1.0
                J[ra, 6 + a] = 1.0
                # row a of A sb~ is (A[a, :] x sb)
                _put(J, ra, 3, cross((Ai[a, 0], Ai[a, 1], Ai[a, 2]), sbi))
                _put(J, ra, 9, scale(-1.0, cross((Aj[a, 0], Aj[a, 1], Aj[a, 2]), sbj)))
        elif kind == PrimKind.DOT2:
            ai = matvec(Ai, model.prim_v[k, AB_I])
            phi[r] = dot(ai, d) - f
            _put(J, r, 0, scale(-1.0, ai))
            _put(J, r, 3, mattvec(Ai, cross(ai, add(d, si))))
            _put(J, r, 6, ai)
            _put(J, r, 9, mattvec(Aj, cross(sj, ai)))
            phit[r] = -fd + dot(ai, du)
            gam[r] = -(dot(d, ww(wi, ai)) + 2.0 * dot(cross(wi, ai), dd) + dot(ai, acc)) + fdd
        elif kind == PrimKind.DISTANCE:
            ln = math.sqrt(dot(d, d))
            u = scale(1.0 / ln, d)
            phi[r] = ln - f
            _put(J, r, 0, scale(-1.0, u))
            _put(J, r, 3, mattvec(Ai, cross(u, si)))
            _put(J, r, 6, u)
            _put(J, r, 9, mattvec(Aj, cross(sj, u)))
            phit[r] = -fd + dot(u, du)
            ud = dot(u, dd)
            gam[r] = -((dot(dd, dd) - ud * ud) / ln + dot(u, acc)) + fdd
        else:  # DISTANCE2
            phi[r] = dot(d, d) - f * f
            _put(J, r, 0, scale(-2.0, d))
            _put(J, r, 3, scale(2.0, mattvec(Ai, cross(d, si))))
            _put(J, r, 6, scale(2.0, d))
            _put(J, r, 9, scale(2.0, mattvec(Aj, cross(sj, d))))
            phit[r] = -2.0 * f * fd + 2.0 * dot(d, du)
            gam[r] = -2.0 * (dot(dd, dd) + dot(d, acc)) + 2.0 * (fd * fd + f * fdd)
