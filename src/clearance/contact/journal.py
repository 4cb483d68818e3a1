"""Journal in bearing (revolute and cylindrical clearance joints), compiled.

Bearing (outer, radius R_B, length L) on body s: centre P_s, axis h_s (the marker's h);
journal (inner, radius R_J) on body b: axis line through P_b along h_b; c = R_B - R_J.

Radial contact: stations. Station k is the bearing's cross-section circle at the axial
coordinate sigma_k along h_s: centre Y = P_s + sigma h_s, radius R_B,
in the plane normal to h_s (a material circle of s). Its penetration into the journal
cylinder (radius R_J about the journal axis, taken as long: the bush is the shorter part) is

    delta = R_J - min_u D(Y + R_B u),   u a unit vector normal to h_s,

D(X) the distance of X from the journal axis. The minimising rim point X* = Y + R_B u* is
found by Newton on the angle of u (starting from the journal offset projected on the
bearing plane; three steps reach machine precision in contact). With v = the vector from
the journal axis to X* (normal to h_b), n = v/|v|: delta = R_J - |v|; the contact points are
Q_s = X* on the bearing and Q_b = X* - v + R_J n on the journal surface, so
delta = n . (Q_b - Q_s). Because u* is optimal (envelope theorem) and Q_b lies on the line
of the journal-axis foot point along n (n normal to h_b), the variation of delta is
n . (dQ_b - dQ_s) of the material points: the forces are the exact gradient of the elastic
energy, for any tilt of the journal (no small-angle or elliptic-section approximation), and
delta_dot = n . (v_Q_b - v_Q_s). For an aligned journal this is the classic planar gap
|e| - c with e the journal offset (Flores & Ambrosio 2004).

Each station carries the fraction w = L_k / L (Model.cp_w) of the joint's normal law, so an
aligned journal loaded uniformly feels the law's full force (line-contact laws give force
per unit length times L; point laws their usual force).

Thrust (axial) contact, revolute joints with an axial clearance c_a: the journal's collars
face the bearing's end faces. Collar point j (material of b) at
X = P_b + side (L/2 + c_a) h_b + r_t (cos psi f_b + sin psi g_b) against the face plane
h_s . (x - P_s) = side L/2 of s: delta = L/2 - side h_s . (X - P_s), n = -side h_s,
Q_b = X, Q_s = X - delta n (point-plane: exact gradient, delta_dot = n . (v_Q_b - v_Q_s)).
Model.cp_geo[p] (from column kinds.PG_K0) = [side, cos psi, sin psi] (stations: [sigma]);
Model.clr_geo[k] (from kinds.CG_K0) = [R_B, R_J, L, c_a, r_t].

Neglected (documented in docs/clearance-joints.md): the finite length of the journal (the
bearing stations always see journal), the axial variation of the bearing between stations
(quadrature of the line load with one station per slice), lubrication, and face contact
between thrust sample points.
"""

from __future__ import annotations

import math

from numba import njit

from clearance.contact.frames import axis, centres, gap_rate, outer_rate, perp, point_plane
from clearance.kinds import CG_K0, CI_BB, CI_BS, PG_K0
from clearance.kinematics.rotations import add, cross, dot, scale, sub

_RB, _RJ, _L, _CA, _RT = range(CG_K0, CG_K0 + 5)  # clr_geo columns
_SIG = _SIDE = PG_K0  # cp_geo columns: station coordinate / thrust face side
_COS, _SIN = PG_K0 + 1, PG_K0 + 2
_NEWTON = 3  # Newton steps on the rim angle (quadratic convergence from an O(R theta^2/c) start)


@njit(cache=True, error_model="numpy", _nrt=False)
def _station(model, p, k, bA, br, arm_s0, arm_b0):
    """Geometry of station p: (delta, n, arm_s, arm_b) with the arms from the mass centres
    of s and b to Q_s and Q_b (world)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    RB = model.clr_geo[k, _RB]
    RJ = model.clr_geo[k, _RJ]
    hs = axis(bA[s], model.clr_T[k, 0], 2)
    hb = axis(bA[b], model.clr_T[k, 1], 2)
    ys = add(arm_s0, scale(model.cp_geo[p, _SIG], hs))  # arm of the station centre Y
    a = sub(
        add((br[s, 0], br[s, 1], br[s, 2]), ys), add((br[b, 0], br[b, 1], br[b, 2]), arm_b0)
    )  # Y - P_b
    e0 = scale(-1.0, perp(a, hb))  # journal axis offset from Y, normal to h_b
    u = perp(e0, hs)  # start: that offset in the bearing plane
    nu = math.sqrt(dot(u, u))
    if nu > 0.0:
        u = scale(1.0 / nu, u)
    else:
        u = axis(bA[s], model.clr_T[k, 0], 0)
    for _ in range(_NEWTON):
        # h(phi) = |P (a + R_B u(phi))|^2 / 2, P = I - h_b h_b^T; u' = h_s x u, u'' = -u:
        # h' = R_B v . u', h'' = R_B^2 |P u'|^2 - R_B v . u (v = P(a + R_B u), normal to h_b)
        v = perp(add(a, scale(RB, u)), hb)
        t = cross(hs, u)
        tp = perp(t, hb)
        curv = RB * dot(tp, tp) - dot(v, u)
        if not curv > 0.0:  # centred journal (flat minimum), far from contact: keep u
            break
        u = add(u, scale(-dot(v, t) / curv, t))
        u = scale(1.0 / math.sqrt(dot(u, u)), u)
    w = add(a, scale(RB, u))  # X* - P_b
    v = perp(w, hb)
    D = math.sqrt(dot(v, v))
    n = scale(1.0 / D, v)
    arm_s = add(ys, scale(RB, u))  # Q_s = X*
    arm_b = add(add(arm_b0, scale(dot(w, hb), hb)), scale(RJ, n))  # foot point + R_J n
    return RJ - D, n, arm_s, arm_b


@njit(cache=True, error_model="numpy", _nrt=False)
def _station_normal_rate(model, p, k, bA, br, brd, bw, arm_s0, arm_b0, us, ub, n, arm_s):
    """n_dot of station p (n = v/|v|, v = P_b (X* - P_b), P_b = I - h_b h_b^T), given the
    geometry from `_station`. X* = Y + R_B u(phi*) moves with s and along the rim as the
    optimal angle phi* changes; phi*_dot follows from keeping the optimality condition
    v . t = 0 (t = h_s x u): phi*_dot (R_B |P_b t|^2 - v . u) = -(v_dot|phi . t + v . (w_s x t)),
    v_dot|phi the rate at fixed phi. Then n_dot = (I - n n^T) v_dot / |v|."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    RB = model.clr_geo[k, _RB]
    hs = axis(bA[s], model.clr_T[k, 0], 2)
    hb = axis(bA[b], model.clr_T[k, 1], 2)
    ws = (bw[s, 0], bw[s, 1], bw[s, 2])
    wb = (bw[b, 0], bw[b, 1], bw[b, 2])
    ys = add(arm_s0, scale(model.cp_geo[p, _SIG], hs))  # arm of the station centre Y
    u = scale(1.0 / RB, sub(arm_s, ys))  # X* = Y + R_B u
    t = cross(hs, u)
    w = sub(
        add((br[s, 0], br[s, 1], br[s, 2]), arm_s), add((br[b, 0], br[b, 1], br[b, 2]), arm_b0)
    )  # X* - P_b
    v = perp(w, hb)
    # rates at fixed phi: X* as a point of s, P_b as a point of b, h_b turning with b
    vx = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s)), us)
    vp = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b0)), ub)
    hbd = cross(wb, hb)
    vd = sub(perp(sub(vx, vp), hb), add(scale(dot(w, hb), hbd), scale(dot(w, hbd), hb)))
    tp = perp(t, hb)
    curv = RB * dot(tp, tp) - dot(v, u)
    if curv > 0.0:
        phid = -(dot(vd, t) + dot(v, cross(ws, t))) / curv
        vd = add(vd, scale(RB * phid, tp))
    D = math.sqrt(dot(v, v))
    return scale(1.0 / D, sub(vd, scale(dot(n, vd), n)))


@njit(cache=True, error_model="numpy", _nrt=False)
def _thrust(model, p, k, bA, br, arm_s0, arm_b0):
    """Geometry of thrust point p: (delta, n, arm_s, arm_b)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    half = 0.5 * model.clr_geo[k, _L]
    rt = model.clr_geo[k, _RT]
    side = model.cp_geo[p, _SIDE]
    Tb = model.clr_T[k, 1]
    ring = add(
        scale(rt * model.cp_geo[p, _COS], axis(bA[b], Tb, 0)),
        scale(rt * model.cp_geo[p, _SIN], axis(bA[b], Tb, 1)),
    )
    arm_x = add(add(arm_b0, scale(side * (half + model.clr_geo[k, _CA]), axis(bA[b], Tb, 2))), ring)
    n = scale(-side, axis(bA[s], model.clr_T[k, 0], 2))
    return point_plane(model, k, br, arm_s0, arm_x, n, half)


@njit(cache=True, error_model="numpy", _nrt=False)
def station_gap(model, p, k, bA, br, fval):
    arm_s0, arm_b0, _, _ = centres(model, k, bA, fval)
    return _station(model, p, k, bA, br, arm_s0, arm_b0)[0]


@njit(cache=True, error_model="numpy", _nrt=False)
def station_contact(model, p, k, bA, br, brd, bw, fval):
    arm_s0, arm_b0, us, ub = centres(model, k, bA, fval)
    delta, n, arm_s, arm_b = _station(model, p, k, bA, br, arm_s0, arm_b0)
    ddot = gap_rate(model, k, brd, bw, n, arm_s, arm_b, us, ub)
    nd = _station_normal_rate(model, p, k, bA, br, brd, bw, arm_s0, arm_b0, us, ub, n, arm_s)
    return delta, ddot, n, arm_s, arm_b, us, ub, nd, 1.0


@njit(cache=True, error_model="numpy", _nrt=False)
def thrust_gap(model, p, k, bA, br, fval):
    arm_s0, arm_b0, _, _ = centres(model, k, bA, fval)
    return _thrust(model, p, k, bA, br, arm_s0, arm_b0)[0]


@njit(cache=True, error_model="numpy", _nrt=False)
def thrust_contact(model, p, k, bA, br, brd, bw, fval):
    arm_s0, arm_b0, us, ub = centres(model, k, bA, fval)
    delta, n, arm_s, arm_b = _thrust(model, p, k, bA, br, arm_s0, arm_b0)
    ddot = gap_rate(model, k, brd, bw, n, arm_s, arm_b, us, ub)
    return delta, ddot, n, arm_s, arm_b, us, ub, outer_rate(model, k, bw, n), 1.0  # n: -side h_s
