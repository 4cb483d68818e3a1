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

Worn bearing (issue 16; `clearance.model.wear.BearingWear`): station p's rim is the worn
cross-section X(phi) = Y + (R_B + H(phi)) u(phi), phi the material angle of u about h_s in
the outer marker frame, H >= 0 its ring's depth field: the uniform cubic B-spline
smoother H(phi) = sum_i H_i B(phi / dphi - 1/2 - i) of the ring's n cells (depths H_i in
column 0 of the rows cp_geo[p, PG_K0 + 1] .. + cp_geo[p, PG_K0 + 2] - 1 of Model.clr_wear,
cell i centred at (i + 1/2) dphi, dphi = 2 pi / n, periodic). It is C2, local (4 cells), and
reproduces cubic profiles up to the shift H'' dphi^2 / 6, so the slope converges with the
grid (the Wendland-weighted Shepard field of the socket ripples in slope by ~9 % at a
smoothing of 2 cells, uniformly in the grid). The gap is the same minimisation,
delta = R_J - min_phi D(X(phi)), by Newton on phi with H, H', H'' (safeguarded: steps of
at most 0.25 rad, halved until the distance does not grow). The envelope argument above
holds for any rim, so the force is again the exact gradient of the elastic energy (along n,
normal to the journal axis, at the worn rim point Q_s = X*), delta_dot = n . (v_Q_b -
v_Q_s), and n_dot follows as above with X' = H' u + rho t, X'' = H'' u + 2 H' t - rho u
(rho = R_B + H) in place of the circle's.
H is not the worn depth h itself but its support depth (`clearance.wear.bearing`): the rim
whose minimum distance is the journal centre's distance from the set of offsets it can
reach without touching the worn surface (small-clearance form: max_phi (e . u - c - H)
with c + H the support function of {x : x . u(psi) <= c + h(psi) for all psi}). With h the
minimum would jump between the two rims of a pocket narrower than the journal; with H it
is the distance to a convex set, continuously differentiable, and zero where the journal
first touches the worn surface.

Neglected (documented in docs/clearance-joints.md): the finite length of the journal (the
bearing stations always see journal), the axial variation of the bearing between stations
(quadrature of the line load with one station per slice), lubrication, and face contact
between thrust sample points.
"""

from __future__ import annotations

import math

from numba import njit

from clearance.contact.frames import (
    axis,
    centres,
    gap_rate,
    outer_rate,
    perp,
    point_plane,
    to_marker,
)
from clearance.kinds import CG_K0, CI_BB, CI_BS, PG_K0
from clearance.kinematics.rotations import add, cross, dot, scale, sub

_RB, _RJ, _L, _CA, _RT = range(CG_K0, CG_K0 + 5)  # clr_geo columns
_SIG = _SIDE = PG_K0  # cp_geo columns: station coordinate / thrust face side
_COS, _SIN = PG_K0 + 1, PG_K0 + 2
_W0, _NW = PG_K0 + 1, PG_K0 + 2  # a worn station's ring: first row, cells
_NEWTON = 3  # Newton steps on the rim angle (quadratic convergence from an O(R theta^2/c) start)
_NEWTON_WORN = 30  # at most, on a worn rim
_STEP = 0.25  # largest step on a worn rim [rad]


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


@njit(cache=True, inline="always", error_model="numpy")
def _rim_rate(model, k, br, brd, bw, arm_s, arm_b0, us, ub, hb):
    """(v, v_dot|phi) of a station's rim point X* = P_s + arm_s (world arm from s's mass
    centre): v = P_b (X* - P_b), and its rate at a fixed angle phi, with X* a point of s,
    P_b a point of b and h_b turning with b."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    ws = (bw[s, 0], bw[s, 1], bw[s, 2])
    wb = (bw[b, 0], bw[b, 1], bw[b, 2])
    w = sub(
        add((br[s, 0], br[s, 1], br[s, 2]), arm_s), add((br[b, 0], br[b, 1], br[b, 2]), arm_b0)
    )  # X* - P_b
    vx = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s)), us)
    vp = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b0)), ub)
    hbd = cross(wb, hb)
    vd = sub(perp(sub(vx, vp), hb), add(scale(dot(w, hb), hbd), scale(dot(w, hbd), hb)))
    return perp(w, hb), vd


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
    ys = add(arm_s0, scale(model.cp_geo[p, _SIG], hs))  # arm of the station centre Y
    u = scale(1.0 / RB, sub(arm_s, ys))  # X* = Y + R_B u
    t = cross(hs, u)
    v, vd = _rim_rate(model, k, br, brd, bw, arm_s, arm_b0, us, ub, hb)
    tp = perp(t, hb)
    curv = RB * dot(tp, tp) - dot(v, u)
    if curv > 0.0:
        phid = -(dot(vd, t) + dot(v, cross(ws, t))) / curv
        vd = add(vd, scale(RB * phid, tp))
    D = math.sqrt(dot(v, v))
    return scale(1.0 / D, sub(vd, scale(dot(n, vd), n)))


@njit(cache=True, inline="always", error_model="numpy")
def _bspline(r):
    """The uniform cubic B-spline B(r) (support |r| < 2) and its first two derivatives."""
    a = abs(r)
    if a < 1.0:
        return 2.0 / 3.0 - r * r + 0.5 * a * a * a, -2.0 * r + 1.5 * r * a, -2.0 + 3.0 * a
    if a < 2.0:
        w = 2.0 - a
        return w * w * w / 6.0, (-0.5 if r > 0.0 else 0.5) * w * w, w
    return 0.0, 0.0, 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
def _rim(model, p, A, T, u):
    """(H, H', H'') of worn station p's rim at the world direction u (normal to h_s): its
    ring's depth field at the material angle phi of u in the outer marker frame (module
    docstring), and its first two derivatives in phi."""
    um = to_marker(A, T, u)
    r0 = int(model.cp_geo[p, _W0])
    n = int(model.cp_geo[p, _NW])
    x = math.atan2(um[1], um[0]) * n / (2.0 * math.pi) - 0.5  # cell i's centre at x = i
    i0 = int(math.floor(x))
    f = x - i0
    H = H1 = H2 = 0.0
    for j in range(-1, 3):
        b, b1, b2 = _bspline(f - j)
        h = model.clr_wear[r0 + ((i0 + j) % n + n) % n, 0]
        H += h * b
        H1 += h * b1
        H2 += h * b2
    sc = n / (2.0 * math.pi)
    return H, H1 * sc, H2 * sc * sc


@njit(cache=True, error_model="numpy", _nrt=False)
def _worn_station(model, p, k, bA, br, arm_s0, arm_b0):
    """`_station` of a worn bearing (module docstring): the rim X(phi) = Y + (R_B + H(phi))
    u(phi). Returns (delta, n, arm_s, arm_b, u, R_B + H, H', H'') at the optimal angle."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    RB = model.clr_geo[k, _RB]
    RJ = model.clr_geo[k, _RJ]
    A = bA[s]
    T = model.clr_T[k, 0]
    hs = axis(A, T, 2)
    hb = axis(bA[b], model.clr_T[k, 1], 2)
    ys = add(arm_s0, scale(model.cp_geo[p, _SIG], hs))
    a = sub(
        add((br[s, 0], br[s, 1], br[s, 2]), ys), add((br[b, 0], br[b, 1], br[b, 2]), arm_b0)
    )  # Y - P_b
    u = perp(scale(-1.0, perp(a, hb)), hs)  # start: the journal's offset in the bearing plane
    nu = math.sqrt(dot(u, u))
    u = scale(1.0 / nu, u) if nu > 0.0 else axis(A, T, 0)
    H, H1, H2 = _rim(model, p, A, T, u)
    rho = RB + H
    v = perp(add(a, scale(rho, u)), hb)
    f = 0.5 * dot(v, v)
    for _ in range(_NEWTON_WORN):
        # f(phi) = |P_b (X - P_b)|^2 / 2, X' = H' u + rho t, X'' = H'' u + 2 H' t - rho u
        # (rho = R_B + H, t = h_s x u): f' = v . X', f'' = |P_b X'|^2 + v . X''; Newton,
        # else (f'' <= 0, far from contact) downhill, steps halved until f does not grow
        t = cross(hs, u)
        xp = add(scale(H1, u), scale(rho, t))
        xpp = add(scale(H2 - rho, u), scale(2.0 * H1, t))
        xp_p = perp(xp, hb)
        f1 = dot(v, xp)
        f2 = dot(xp_p, xp_p) + dot(v, xpp)
        step = -f1 / f2 if f2 > 0.0 else (-_STEP if f1 > 0.0 else _STEP)
        step = min(_STEP, max(-_STEP, step))
        for _ in range(60):
            un = add(scale(math.cos(step), u), scale(math.sin(step), t))
            Hn, H1n, H2n = _rim(model, p, A, T, un)
            vn = perp(add(a, scale(RB + Hn, un)), hb)
            fn = 0.5 * dot(vn, vn)
            if fn <= f * (1.0 + 1e-15):
                break
            step *= 0.5
        u, H, H1, H2, rho, v, f = un, Hn, H1n, H2n, RB + Hn, vn, fn
        if abs(step) < 1e-12:
            break
    rho = RB + H
    w = add(a, scale(rho, u))  # X* - P_b
    v = perp(w, hb)
    D = math.sqrt(dot(v, v))
    n = scale(1.0 / D, v)
    arm_s = add(ys, scale(rho, u))  # Q_s = X*, on the worn rim
    arm_b = add(add(arm_b0, scale(dot(w, hb), hb)), scale(RJ, n))
    return RJ - D, n, arm_s, arm_b, u, rho, H1, H2


@njit(cache=True, error_model="numpy", _nrt=False)
def _worn_station_contact(model, p, k, bA, br, brd, bw, arm_s0, arm_b0, us, ub):
    """`station_contact` of a worn bearing: delta_dot = n . (v_Q_b - v_Q_s) of the material
    points (the optimum's envelope property holds on any rim); n_dot as in
    `_station_normal_rate`, with the worn rim's X' and f''."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    delta, n, arm_s, arm_b, u, rho, H1, H2 = _worn_station(model, p, k, bA, br, arm_s0, arm_b0)
    ddot = gap_rate(model, k, brd, bw, n, arm_s, arm_b, us, ub)
    hs = axis(bA[s], model.clr_T[k, 0], 2)
    hb = axis(bA[b], model.clr_T[k, 1], 2)
    ws = (bw[s, 0], bw[s, 1], bw[s, 2])
    t = cross(hs, u)
    xp = add(scale(H1, u), scale(rho, t))
    xpp = add(scale(H2 - rho, u), scale(2.0 * H1, t))
    v, vd = _rim_rate(model, k, br, brd, bw, arm_s, arm_b0, us, ub, hb)
    xp_p = perp(xp, hb)
    f2 = dot(xp_p, xp_p) + dot(v, xpp)
    if f2 > 0.0:
        phid = -(dot(vd, xp) + dot(v, cross(ws, xp))) / f2
        vd = add(vd, scale(phid, xp_p))
    D = math.sqrt(dot(v, v))
    nd = scale(1.0 / D, sub(vd, scale(dot(n, vd), n)))
    return delta, ddot, n, arm_s, arm_b, us, ub, nd, 1.0


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
    if model.cp_geo[p, _NW] > 0.0:
        return _worn_station(model, p, k, bA, br, arm_s0, arm_b0)[0]
    return _station(model, p, k, bA, br, arm_s0, arm_b0)[0]


@njit(cache=True, error_model="numpy", _nrt=False)
def station_contact(model, p, k, bA, br, brd, bw, fval):
    arm_s0, arm_b0, us, ub = centres(model, k, bA, fval)
    if model.cp_geo[p, _NW] > 0.0:
        return _worn_station_contact(model, p, k, bA, br, brd, bw, arm_s0, arm_b0, us, ub)
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
