"""Spherical clearance joints as force elements, compiled (physics.md f, j).

For each clearance joint k: socket centre P_s on body s, ball centre P_b on body b,
e = P_b - P_s, n_hat = e/|e|, delta = |e| - c. In contact the normal law gives F_N >= 0 and
the friction law F_T_vec; the force on the ball f_b = -F_N n_hat - F_T_vec acts at the ball
surface point r_b^Q = P_b + R_b n_hat, and f_s = -f_b at the socket surface point
r_s^Q = P_s + R_s n_hat (Flores convention, f.3-f.4). The pair's power is
-F_N delta_dot - F_T_vec . v_t (f.4), which the energy audit splits into the elastic energy
V_c, normal damping D_n and friction work D_t (j). A centre may sit at a moving attachment
sb(t) (lumped limb, physics.md f.2, i): its velocity A sb_dot enters delta_dot and v_t, and
the contact forces' work through it is the W_m term of the audit.

Discrete state per joint (updated only on accepted steps by the integrator): cflag (1 while
in contact) and cddm (impact velocity delta_dot_minus latched at onset, floored).
"""

from __future__ import annotations

import math

from numba import njit

from clearance.contact.laws import elastic_energy, friction_force, normal_force
from clearance.kinds import FrictionLaw
from clearance.kinematics.points import add_force, moving_point
from clearance.kinematics.rotations import add, cross, dot, mattvec, matvec, scale, sub

_LUGRE = int(FrictionLaw.LUGRE)
NWORK = 5  # work integrals before D_n in y (see compile.compiled)

# columns of the per-joint diagnostics array wk.cout
CO_E = 0  # e in the socket marker frame (3)
CO_DELTA = 3
CO_DDOT = 4  # delta_dot
CO_FN = 5  # F_N magnitude
CO_FEL = 6  # elastic part
CO_N = 7  # n_hat world (3)
CO_FT = 10  # friction vector F_T_vec world (3); force on the ball is -F_T_vec
CO_VT = 13  # tangential slip velocity world (3)
CO_PB = 16  # ball centre world (3)
NCOUT = 19


@njit(cache=True, error_model="numpy", _nrt=False)
def _centres(model, k, bA, br, fval):
    """Arms (world) of the socket and ball centres from their body's mass centre, the
    centres' velocities relative to their bodies (A sb_dot, world) and A sb_ddot."""
    s = model.clr_bs[k]
    b = model.clr_bb[k]
    sbs, us_b, as_b = moving_point(model.clr_ps[k], model.clr_ax[k, 0], model.clr_mv[k, 0], fval)
    sbb, ub_b, ab_b = moving_point(model.clr_pb[k], model.clr_ax[k, 1], model.clr_mv[k, 1], fval)
    return (matvec(bA[s], sbs), matvec(bA[b], sbb), matvec(bA[s], us_b), matvec(bA[b], ub_b))


@njit(cache=True, error_model="numpy", _nrt=False)
def clearance_geometry(model, k, bA, br, fval):
    """(e (world), |e|, delta) of clearance joint k; fval: time functions at the current t."""
    s = model.clr_bs[k]
    b = model.clr_bb[k]
    arm_s, arm_b, _, _ = _centres(model, k, bA, br, fval)
    Ps = add((br[s, 0], br[s, 1], br[s, 2]), arm_s)
    Pb = add((br[b, 0], br[b, 1], br[b, 2]), arm_b)
    e = sub(Pb, Ps)
    el = math.sqrt(dot(e, e))
    return e, el, el - model.clr_geo[k, 2]


@njit(cache=True, error_model="numpy", _nrt=False)
def clearance_forces(model, y, wk, ydot):
    """Add the contact forces of all clearance joints to wk.Q; write z_dot and the D_n, D_t
    rates into ydot; fill the diagnostics wk.cout (nclr, NCOUT). Returns the power of the
    contact forces through moving attachment points, -sum f . (A sb_dot) (the W_m rate)."""
    nb = model.nb
    bA, br, brd, bw = wk.bA, wk.br, wk.brd, wk.bw
    cout = wk.cout
    iz = 13 * nb
    iw = iz + 3 * model.nclr + NWORK
    p_moving = 0.0
    for k in range(model.nclr):
        s = model.clr_bs[k]
        b = model.clr_bb[k]
        Rs = model.clr_geo[k, 0]
        Rb = model.clr_geo[k, 1]
        c = model.clr_geo[k, 2]
        rs = (br[s, 0], br[s, 1], br[s, 2])
        rb = (br[b, 0], br[b, 1], br[b, 2])
        ws = (bw[s, 0], bw[s, 1], bw[s, 2])
        wb = (bw[b, 0], bw[b, 1], bw[b, 2])
        arm_s0, arm_b0, us, ub = _centres(model, k, bA, br, wk.fval)
        Ps = add(rs, arm_s0)
        Pb = add(rb, arm_b0)
        e = sub(Pb, Ps)
        el = math.sqrt(dot(e, e))
        delta = el - c
        # eccentricity in the socket marker frame (for the ball-centre trajectory plot)
        es = mattvec(bA[s], e)
        Ts = model.clr_Ts[k]
        for a in range(3):
            cout[k, CO_E + a] = Ts[0, a] * es[0] + Ts[1, a] * es[1] + Ts[2, a] * es[2]
            cout[k, CO_PB + a] = Pb[a]
            cout[k, CO_FT + a] = 0.0
            cout[k, CO_VT + a] = 0.0
        # centre velocities, including the moving-attachment terms A sb_dot (f.2)
        vPs = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s0)), us)
        vPb = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b0)), ub)
        cout[k, CO_DELTA] = delta
        cout[k, CO_FN] = 0.0
        cout[k, CO_FEL] = 0.0
        zi = iz + 3 * k
        ydot[zi] = 0.0
        ydot[zi + 1] = 0.0
        ydot[zi + 2] = 0.0
        ydot[iw + k] = 0.0
        ydot[iw + model.nclr + k] = 0.0
        n = scale(1.0 / el, e) if el > 0.0 else (0.0, 0.0, 0.0)
        for a in range(3):
            cout[k, CO_N + a] = n[a]
        ddot = dot(n, sub(vPb, vPs))  # f.2: n . (v_b^P - v_s^P), > 0 compressing
        cout[k, CO_DDOT] = ddot
        if delta <= 0.0:
            continue
        # contact points and the velocities of the material points there (f.1, f.2)
        arm_s = add(arm_s0, scale(Rs, n))
        arm_b = add(arm_b0, scale(Rb, n))
        vQs = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s)), us)
        vQb = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b)), ub)
        vrel = sub(vQb, vQs)
        vt = sub(vrel, scale(dot(n, vrel), n))
        # impact velocity: latched at onset on accepted steps; before the integrator has
        # latched it (trial stages beyond an onset) use the current approach velocity
        ddm = wk.cddm[k] if wk.cflag[k] == 1 else max(ddot, model.clr_geo[k, 3])
        fn, fel = normal_force(model.clr_law[k], model.clr_par[k], delta, ddot, ddm, c)
        z = (y[zi], y[zi + 1], y[zi + 2])
        ft, zd = friction_force(model.clr_fric[k], model.clr_fpar[k], fn, vt, z)
        ft = sub(ft, scale(dot(ft, n), n))  # keep the friction force tangent (f.3)
        if model.clr_fric[k] == _LUGRE:
            ydot[zi] = zd[0]
            ydot[zi + 1] = zd[1]
            ydot[zi + 2] = zd[2]
        fb = sub(scale(-fn, n), ft)  # on the ball, at r_b^Q
        add_force(wk.Q, b, bA, fb, arm_b)
        add_force(wk.Q, s, bA, scale(-1.0, fb), arm_s)
        # work through the moving attachments: -(f_b . u_b + f_s . u_s), f_s = -f_b (j)
        p_moving -= dot(fb, sub(ub, us))
        ydot[iw + k] = (fn - fel) * ddot  # D_n rate: normal damping dissipation (j)
        ydot[iw + model.nclr + k] = dot(ft, vt)  # D_t rate: friction work (j)
        cout[k, CO_FN] = fn
        cout[k, CO_FEL] = fel
        for a in range(3):
            cout[k, CO_FT + a] = ft[a]
            cout[k, CO_VT + a] = vt[a]
    return p_moving


@njit(cache=True, error_model="numpy", _nrt=False)
def contact_energy(model, bA, br, fval):
    """V_c = sum of the elastic energies stored in the contacts [J]."""
    V = 0.0
    for k in range(model.nclr):
        _, _, delta = clearance_geometry(model, k, bA, br, fval)
        if delta > 0.0:
            V += elastic_energy(model.clr_law[k], model.clr_par[k], delta, model.clr_geo[k, 2])
    return V
