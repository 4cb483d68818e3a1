"""Applied generalised forces (physics.md d.1): gravity, gyroscopic terms, point forces,
torques and spring-damper-actuators. Q per body = [F (world) ; n' (body frame)].
"""

from __future__ import annotations

import math

from numba import njit

from clearance.kinds import ForceType
from clearance.kinematics.points import add_force
from clearance.kinematics.rotations import add, cross, dot, mattvec, matvec, scale, sub

_POINT = int(ForceType.POINT_FORCE)
_TORQUE = int(ForceType.TORQUE)


@njit(cache=True, error_model="numpy")
def applied_forces(model, y, wk):
    """Fill wk.Q (nb, 6); return (power of the non-conservative applied forces, lumped-limb
    power P_L) [W].

    Gravity and spring elasticity are conservative (their energy is in V); the first power
    covers point forces, torques, dampers and actuators (the W_a rate). A body with a
    time-dependent inertia gets -J'_dot omega' in its Euler equation (physics.md i), whose
    effect on the kinetic energy is P_L = -1/2 omega'^T J'_dot omega' (physics.md j).
    """
    nb = model.nb
    off = model.y_iv
    Q = wk.Q
    bA, br, brd, bw, fval = wk.bA, wk.br, wk.brd, wk.bw, wk.fval
    p_limb = 0.0
    for b in range(nb):
        m = model.body_mass[b]
        w = (y[off + 6 * b + 3], y[off + 6 * b + 4], y[off + 6 * b + 5])
        Jw = matvec(wk.bJ[b], w)
        gyro = cross(w, Jw)
        Q[b, 0] = m * model.gravity[0]
        Q[b, 1] = m * model.gravity[1]
        Q[b, 2] = m * model.gravity[2]
        Q[b, 3] = -gyro[0]
        Q[b, 4] = -gyro[1]
        Q[b, 5] = -gyro[2]
        if model.body_vfn[b] >= 0:
            on = model.body_var[b, 4]  # 1: exact Euler equation with J'_dot omega'
            for a in range(3):
                Q[b, 3 + a] -= on * wk.bJd[b, a] * w[a]
                # d/dt (1/2 w J w) = w . n' + (1/2 - on) w J_dot w  (physics.md i, j)
                p_limb += (0.5 - on) * wk.bJd[b, a] * w[a] * w[a]
    power = 0.0
    for k in range(model.frc_kind.shape[0]):
        kind = model.frc_kind[k]
        i = model.frc_bi[k]
        mag = fval[model.frc_fn[k], 0]
        if kind == _POINT or kind == _TORQUE:
            u = (model.frc_v[k, 2, 0], model.frc_v[k, 2, 1], model.frc_v[k, 2, 2])
            if model.frc_par[k, 3] > 0.5:
                u = matvec(bA[i], u)
            F = scale(mag, u)
            if kind == _POINT:
                s = matvec(bA[i], model.frc_v[k, 0])
                add_force(Q, i, bA, F, s)
                vp = add(
                    (brd[i, 0], brd[i, 1], brd[i, 2]), cross((bw[i, 0], bw[i, 1], bw[i, 2]), s)
                )
                power += dot(F, vp)
            else:
                n = mattvec(bA[i], F)
                Q[i, 3] += n[0]
                Q[i, 4] += n[1]
                Q[i, 5] += n[2]
                power += dot(F, (bw[i, 0], bw[i, 1], bw[i, 2]))
        else:  # spring-damper-actuator
            j = model.frc_bj[k]
            si = matvec(bA[i], model.frc_v[k, 0])
            sj = matvec(bA[j], model.frc_v[k, 1])
            d = sub(
                add((br[j, 0], br[j, 1], br[j, 2]), sj), add((br[i, 0], br[i, 1], br[i, 2]), si)
            )
            dd = sub(
                add((brd[j, 0], brd[j, 1], brd[j, 2]), cross((bw[j, 0], bw[j, 1], bw[j, 2]), sj)),
                add((brd[i, 0], brd[i, 1], brd[i, 2]), cross((bw[i, 0], bw[i, 1], bw[i, 2]), si)),
            )
            ln = math.sqrt(dot(d, d))
            u = scale(1.0 / ln, d)
            ldot = dot(u, dd)
            k_, c_, l0 = model.frc_par[k, 0], model.frc_par[k, 1], model.frc_par[k, 2]
            tension_nc = c_ * ldot + mag
            tension = k_ * (ln - l0) + tension_nc
            add_force(Q, j, bA, scale(-tension, u), sj)
            add_force(Q, i, bA, scale(tension, u), si)
            power -= tension_nc * ldot
    return power, p_limb


@njit(cache=True, error_model="numpy")
def potential_energy(model, y, bA, br):
    """V = gravity + spring elastic energy [J] (ground level at z = 0)."""
    nb = model.nb
    V = 0.0
    for b in range(nb):
        V -= model.body_mass[b] * (
            model.gravity[0] * y[7 * b]
            + model.gravity[1] * y[7 * b + 1]
            + model.gravity[2] * y[7 * b + 2]
        )
    for k in range(model.frc_kind.shape[0]):
        if model.frc_kind[k] == _POINT or model.frc_kind[k] == _TORQUE:
            continue
        i = model.frc_bi[k]
        j = model.frc_bj[k]
        si = matvec(bA[i], model.frc_v[k, 0])
        sj = matvec(bA[j], model.frc_v[k, 1])
        d = sub(add((br[j, 0], br[j, 1], br[j, 2]), sj), add((br[i, 0], br[i, 1], br[i, 2]), si))
        e = math.sqrt(dot(d, d)) - model.frc_par[k, 2]
        V += 0.5 * model.frc_par[k, 0] * e * e
    return V


@njit(cache=True, error_model="numpy")
def kinetic_energy(model, y, bJ):
    """T = sum 1/2 m |r_dot|^2 + 1/2 omega'^T J' omega' [J], with the current inertia bJ."""
    nb = model.nb
    off = model.y_iv
    T = 0.0
    for b in range(nb):
        v = (y[off + 6 * b], y[off + 6 * b + 1], y[off + 6 * b + 2])
        w = (y[off + 6 * b + 3], y[off + 6 * b + 4], y[off + 6 * b + 5])
        T += 0.5 * model.body_mass[b] * dot(v, v) + 0.5 * dot(w, matvec(bJ[b], w))
    return T
