"""Ball in spherical socket: one point contact (physics.md f), compiled.

Socket (outer, radius R_s) on body s centred at P_s, ball (inner, radius R_b) on body b
centred at P_b; e = P_b - P_s, n = e/|e|, delta = |e| - c (f.1). Contact points: the ball
surface point P_b + R_b n and the socket surface point P_s + R_s n, so that
delta = n . (Q_b - Q_s) and, both being surface points with normals along n, the variation
of delta is n . (dQ_b - dQ_s) of the material points: the contact force is the exact
gradient of the elastic energy (virtual work, f.4). delta_dot = n . (v_b^P - v_s^P) (f.2).

Joint geometry (Model.clr_geo[k], from column kinds.CG_K0): [R_s, R_b].
Every contact kind has the same two functions (see `clearance.contact.element`):

    contact(model, p, k, bA, br, brd, bw, fval)
        -> (delta, delta_dot, n, arm_s, arm_b, u_s, u_b, n_dot)
    gap(model, p, k, bA, br, fval) -> delta

with arm_s / arm_b the world arms from the mass centres of s and b to the contact points,
u_s / u_b the velocities of moving attachment points (A sb_dot, physics.md i) and n_dot
the rate of the unit normal (the LuGre bristles are carried with it, element.py). Here
n_dot = (e_dot - n (n . e_dot)) / |e|.

Worn socket (issue 16; `clearance.model.wear.SocketWear`, rows clr_ix[k, CI_W0] ..
+ CI_NW of Model.clr_wear, each [c_x, c_y, c_z, h Omega, Omega] in the outer marker frame,
and the smoothing radius rho = clr_geo[k, CG_K0 + 2]). The gap is measured along the line
of centres, with the depth the smooth field

    h(u) = sum_i h_i Omega_i phi_i(u) / sum_i Omega_i phi_i(u),  phi_i = phi(|u - c_i| / rho)

(Shepard's partition of unity with Wendland's C2 function phi(r) = (1 - r)^4 (4 r + 1),
r < 1: the samples' depths h_i, solid angles Omega_i; h is C2 and reproduces a uniform
depth exactly):

    delta = |e| - c - h(u),  u = T^T A_s^T n.

The samples are not the worn depth itself but the reachable depth
(`clearance.wear.surface.SphereWearMap.reachable_depth`): how far beyond c the ball's
centre can move along u before it touches the worn surface anywhere. With the worn depth
the line-of-centres gap would let the ball sink into a pocket narrower than itself; with
the reachable depth delta = 0 where the ball first touches the worn surface (to the
smoothing), at the pocket's rim, and the tangential part of the force below holds the ball
in a pocket it fits.

The force is its exact gradient (virtual work, f.4): with g_t the world gradient of h
w.r.t. the direction, tangent to n, d delta = (n - g_t / |e|) . de + dphi_s . (n x g_t)
(dphi_s: a rotation of the socket, which turns its worn surface). Its direction is the
worn surface's normal n' = nu / m, nu = n - g_t / |e|, m = |nu|, and it acts at one line
through P_b along n': Q_b = P_b + R_b n', Q_s = Q_b - delta n' (so delta = n' . (Q_b -
Q_s); unworn, Q_s would be the socket's surface point P_s + R_s n; worn, the points are
on the line of action, not the true contact point, which the wear's overlap finds). The
normal law is evaluated at (delta, delta_dot) and the force on b is -m F_N n' (element.py: the ninth
entry m of the geometry; 1 for every unworn contact). delta_dot is the exact rate,
n . e_dot - g . (n_dot - omega_s x n), and n_dot the exact rate of n' (the field's Hessian
along u_dot).
"""

from __future__ import annotations

import math

from numba import njit

from clearance.contact.field import depth_field
from clearance.contact.frames import centres, to_marker, to_world
from clearance.kinds import CG_C, CG_K0, CI_BB, CI_BS, CI_NW, CI_W0
from clearance.kinematics.rotations import add, cross, dot, scale, sub

_RS, _RB, _RHO = CG_K0, CG_K0 + 1, CG_K0 + 2  # socket, ball radii; wear smoothing radius


@njit(cache=True, inline="always", error_model="numpy")
def gap(model, p, k, bA, br, fval):
    """delta of the ball in its socket (f.1)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    arm_s, arm_b, _, _ = centres(model, k, bA, fval)
    Ps = add((br[s, 0], br[s, 1], br[s, 2]), arm_s)
    Pb = add((br[b, 0], br[b, 1], br[b, 2]), arm_b)
    e = sub(Pb, Ps)
    el = math.sqrt(dot(e, e))
    if model.clr_ix[k, CI_NW] == 0 or el == 0.0:
        return el - model.clr_geo[k, CG_C]
    u = to_marker(bA[s], model.clr_T[k, 0], scale(1.0 / el, e))
    h, _, _ = _depth(model, k, u, (0.0, 0.0, 0.0))
    return el - model.clr_geo[k, CG_C] - h


@njit(cache=True, inline="always", error_model="numpy")
def contact(model, p, k, bA, br, brd, bw, fval):
    """(delta, delta_dot, n, arm_s, arm_b, u_s, u_b, n_dot) of the ball in its socket (f.1,
    f.2)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    arm_s0, arm_b0, us, ub = centres(model, k, bA, fval)
    Ps = add((br[s, 0], br[s, 1], br[s, 2]), arm_s0)
    Pb = add((br[b, 0], br[b, 1], br[b, 2]), arm_b0)
    e = sub(Pb, Ps)
    el = math.sqrt(dot(e, e))
    if model.clr_ix[k, CI_NW] > 0 and el > 0.0:
        return _worn_contact(model, k, bA, brd, bw, arm_s0, arm_b0, us, ub, e, el)
    delta = el - model.clr_geo[k, CG_C]
    # centre velocities, including the moving-attachment terms A sb_dot (f.2)
    ws = (bw[s, 0], bw[s, 1], bw[s, 2])
    wb = (bw[b, 0], bw[b, 1], bw[b, 2])
    vPs = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s0)), us)
    vPb = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b0)), ub)
    n = scale(1.0 / el, e) if el > 0.0 else (0.0, 0.0, 0.0)
    ed = sub(vPb, vPs)
    ddot = dot(n, ed)  # f.2: n . (v_b^P - v_s^P), > 0 compressing
    nd = scale(1.0 / el, sub(ed, scale(ddot, n))) if el > 0.0 else (0.0, 0.0, 0.0)
    arm_s = add(arm_s0, scale(model.clr_geo[k, _RS], n))  # socket surface point (f.1)
    arm_b = add(arm_b0, scale(model.clr_geo[k, _RB], n))  # ball surface point
    return delta, ddot, n, arm_s, arm_b, us, ub, nd, 1.0


@njit(cache=True, inline="always", error_model="numpy")
def _depth(model, k, u, du):
    """(h, g, H du) of joint k's worn socket at the direction u (outer marker frame, unit):
    `depth_field` over the joint's rows with its smoothing radius."""
    return depth_field(
        model, model.clr_ix[k, CI_W0], model.clr_ix[k, CI_NW], model.clr_geo[k, _RHO], u, du
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def _worn_contact(model, k, bA, brd, bw, arm_s0, arm_b0, us, ub, e, el):
    """`contact` of a worn socket (module docstring), e = P_b - P_s (el = |e| > 0)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    A = bA[s]
    T = model.clr_T[k, 0]
    ws = (bw[s, 0], bw[s, 1], bw[s, 2])
    wb = (bw[b, 0], bw[b, 1], bw[b, 2])
    vPs = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s0)), us)
    vPb = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b0)), ub)
    ed = sub(vPb, vPs)
    n = scale(1.0 / el, e)
    eld = dot(n, ed)
    nd = scale(1.0 / el, sub(ed, scale(eld, n)))  # rate of n = e / |e|
    rel = sub(nd, cross(ws, n))  # rate of n seen from the socket
    h, gm, qm = _depth(model, k, to_marker(A, T, n), to_marker(A, T, rel))
    g = to_world(A, T, gm)
    gd = add(to_world(A, T, qm), cross(ws, g))  # rate of g (world)
    delta = el - model.clr_geo[k, CG_C] - h
    ddot = eld - dot(g, rel)
    gn = dot(g, n)
    gt = sub(g, scale(gn, n))
    gtd = sub(sub(gd, scale(dot(gd, n) + dot(g, nd), n)), scale(gn, nd))  # rate of gt
    nu = sub(n, scale(1.0 / el, gt))
    m = math.sqrt(dot(nu, nu))
    nn = scale(1.0 / m, nu)
    nud = add(sub(nd, scale(1.0 / el, gtd)), scale(eld / (el * el), gt))
    nnd = scale(1.0 / m, sub(nud, scale(dot(nn, nud), nn)))
    arm_b = add(arm_b0, scale(model.clr_geo[k, _RB], nn))
    arm_s = add(add(arm_s0, e), scale(model.clr_geo[k, _RB] - delta, nn))
    return delta, ddot, nn, arm_s, arm_b, us, ub, nnd, m
