"""Clearance joints as force elements, compiled: the family's shared part (physics.md f, j).

A clearance joint k (Model.clr_*, packed as described in `clearance.kinds`) connects an
outer body s (socket, bearing, guide) and an inner body b (ball, journal, slider) and owns
the contact points p = clr_ix[k, CI_P0] ... + clr_ix[k, CI_NP] - 1 (Model.cp_*). Each point
has a contact kind (kinds.ContactKind) whose kernel module gives its geometry with one
signature:

    contact(model, p, k, bA, br, brd, bw, fval)
        -> (delta, delta_dot, n, arm_s, arm_b, u_s, u_b, n_dot, m)
    gap(model, p, k, bA, br, fval) -> delta

(delta > 0 in contact; n the contact normal, pointing outwards from the joint's centre;
arm_s / arm_b the world arms from the mass centres to the contact points Q_s, Q_b with
delta = n . (Q_b - Q_s); u_s / u_b the velocities of moving attachment points; n_dot the
rate of n; m the normal force per unit of the law's force: 1, but |d delta / d e| for a
worn socket, whose gap is not a distance along n (contact/spherical.py)).
With m != 1 the law's F_N works on delta_dot (D_n) and the force m F_N acts along n.
Everything else is common and lives here: the normal law (weighted by the point's share,
cp_geo[p, PG_W]), friction with its bristle state, the forces -F_N n - F_T on b at Q_b and
the opposite on s at Q_s (Flores convention, f.3-f.4), the energy audit rates (D_n, D_t,
W_m; physics.md j) and the diagnostics (layout.JOINT_COLUMNS per joint, POINT_COLUMNS per
point).

Discrete state (`ContactState`, updated only on accepted steps by the integrator, never in
the right-hand side): flag[p] = 1 while point p is in contact, ddm[p] the impact velocity
delta_dot_minus latched at its onset (floored, f.5). Before the integrator has latched an
onset (trial stages beyond it) the current approach velocity stands in for it.

LuGre bristles (physics.md h.4) live in the tangent plane, which turns with n. The plane is
followed in the right-hand side, not by projecting z after accepted steps (f.5). With
z = z_t + a n (z_t tangent, a = n . z; a = 0 from the onset, where z = 0, but integration
error makes it drift slightly), the law sees z_t only and z_dot gets the transport terms
-n (n_dot . z_t) + a n_dot: z_t follows the turning plane, a n turns with n, so a keeps its
value and z_t evolves as if a were zero (without the second term a would leak into z_t
as n turns, -a n_dot). A projection after each step is the first term's splitting,
done only when |n . z| > 1e-3 |z| as before: the friction force then depended on the step
sequence (1e-3 of z), and on the default scenario the error of dop853 and vern7 levelled
off at 2-6e-9 m of eccentricity (rtol 1e-9 .. 1e-10; tsit5 4e-10 m), projecting at every
step 2-9e-9 m for all three; with the transport term, 2-4e-11 m at rtol 1e-10 for all.

The bristle rate follows the contact state, not the sign of delta: a latched contact
(flag 1) integrates z_dot = v_t - ... also where delta <= 0 (the forces are zero there).
The state of a located onset can sit a rounding below delta = 0 (-7e-18 m), and a rate
that jumped from 0 there to v_t a moment later made the first step after the onset start
z late: on a rattling rod (Flores + LuGre) z lagged by 1.2e-9 m (1.4 %) from the first
contact on, and the rod's velocity after it was off by up to 5e-5 m/s at rtol 1e-7.

Adding a contact kind: its kernel module with `contact` and `gap` (e.g. contact/journal.py),
its ContactKind member (kinds.py) and its two dispatch lines below.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from clearance.contact import journal, slider, spherical
from clearance.contact.frames import centres, to_marker
from clearance.contact.laws import elastic_energy, friction_force, normal_force
from clearance.kinds import (
    CG_C,
    CG_VFLOOR,
    CI_BB,
    CI_BS,
    PG_W,
    PI_CLR,
    PI_FRIC,
    PI_KIND,
    PI_LAW,
    PI_ORDER,
    ContactKind,
    FrictionLaw,
)
from clearance.kinematics.points import add_force
from clearance.kinematics.rotations import add, dot, scale, sub
from clearance.layout import (
    CO_DDOT,
    CO_DELTA,
    CO_E,
    CO_FEL,
    CO_FN,
    CO_FNV,
    CO_FT,
    CO_N,
    CO_PB,
    CO_VT,
    PO_DDOT,
    PO_DELTA,
    PO_FEL,
    PO_FN,
    PO_FT,
    PO_N,
    PO_Q,
    PO_VT,
)

_LUGRE = int(FrictionLaw.LUGRE)
_SPHERE = int(ContactKind.SPHERE)
_STATION = int(ContactKind.JOURNAL_STATION)
_THRUST = int(ContactKind.THRUST_POINT)
_CORNER = int(ContactKind.SLIDER_CORNER)


class ContactState(NamedTuple):
    """Discrete contact state of the contact points (see module docstring)."""

    flag: np.ndarray  # (ncp,) int64: 1 while in contact
    ddm: np.ndarray  # (ncp,) impact velocity delta_dot_minus latched at the onset [m/s]


def make_contact_state(model) -> ContactState:
    """All points out of contact."""
    return ContactState(np.zeros(model.ncp, dtype=np.int64), np.zeros(model.ncp))


@njit(cache=True, inline="always", error_model="numpy")
def point_gap(model, p, bA, br, fval):
    """delta of contact point p (positions only: bA, br of its two bodies set). Inlined:
    the event search probes it ~10 times per accepted step and, called, took twice as long
    (default scenario: 9.6 us vs 5.0 us per step); `gap_of` is the called form for the
    paths that are not hot."""
    k = model.cp_ix[p, PI_CLR]
    kind = model.cp_ix[p, PI_KIND]
    if kind == _SPHERE:
        return spherical.gap(model, p, k, bA, br, fval)
    if kind == _STATION:
        return journal.station_gap(model, p, k, bA, br, fval)
    if kind == _THRUST:
        return journal.thrust_gap(model, p, k, bA, br, fval)
    return slider.corner_gap(model, p, k, bA, br, fval)


@njit(cache=True, error_model="numpy", _nrt=False)
def gap_of(model, p, bA, br, fval):
    """`point_gap`, called (one inlined copy serves every caller that is not hot)."""
    return point_gap(model, p, bA, br, fval)


@njit(cache=True, error_model="numpy", _nrt=False)
def point_contact(model, p, bA, br, brd, bw, fval):
    """(delta, delta_dot, n, arm_s, arm_b, u_s, u_b, n_dot, m) of contact point p."""
    k = model.cp_ix[p, PI_CLR]
    kind = model.cp_ix[p, PI_KIND]
    if kind == _SPHERE:
        return spherical.contact(model, p, k, bA, br, brd, bw, fval)
    if kind == _STATION:
        return journal.station_contact(model, p, k, bA, br, brd, bw, fval)
    if kind == _THRUST:
        return journal.thrust_contact(model, p, k, bA, br, brd, bw, fval)
    return slider.corner_contact(model, p, k, bA, br, brd, bw, fval)


@njit(cache=True, error_model="numpy", _nrt=False)
def eccentricity(model, k, bA, br, fval):
    """(e in the outer marker frame, inner centre P_b in the world) of clearance joint k:
    e = P_b - P_s, the ball / journal / slider centre relative to the socket / bearing /
    guide centre."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    arm_s, arm_b, _, _ = centres(model, k, bA, fval)
    Ps = add((br[s, 0], br[s, 1], br[s, 2]), arm_s)
    Pb = add((br[b, 0], br[b, 1], br[b, 2]), arm_b)
    return to_marker(bA[s], model.clr_T[k, 0], sub(Pb, Ps)), Pb


@njit(cache=True, error_model="numpy", _nrt=False)
def _apply(model, y, wk, cs, ydot, p, geometry):
    """The common part of contact point p, given its geometry (delta, delta_dot, n, arm_s,
    arm_b, u_s, u_b, n_dot, m; see the module docstring): diagnostics, normal law, friction,
    forces on both bodies, bristle and dissipation rates. Returns the point's power through
    moving attachments (the W_m rate, physics.md j)."""
    delta, ddot, n, arm_s, arm_b, us, ub, nd, m = geometry
    k = model.cp_ix[p, PI_CLR]
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    bA, br, brd, bw = wk.bA, wk.br, wk.brd, wk.bw
    cout = wk.cout
    pout = wk.pout
    zi = model.y_iz + 3 * p
    ydot[zi] = 0.0
    ydot[zi + 1] = 0.0
    ydot[zi + 2] = 0.0
    pout[p, PO_DELTA] = delta
    pout[p, PO_DDOT] = ddot
    pout[p, PO_FN] = 0.0
    pout[p, PO_FEL] = 0.0
    for a in range(3):
        pout[p, PO_N + a] = n[a]
        pout[p, PO_FT + a] = 0.0
        pout[p, PO_VT + a] = 0.0
        pout[p, PO_Q + a] = br[s, a] + arm_s[a]
    deepest = delta > cout[k, CO_DELTA]
    if deepest:
        cout[k, CO_DELTA] = delta
        cout[k, CO_DDOT] = ddot
        for a in range(3):
            cout[k, CO_N + a] = n[a]
            cout[k, CO_VT + a] = 0.0
    lugre = model.cp_ix[p, PI_FRIC] == _LUGRE
    if delta <= 0.0 and not (lugre and cs.flag[p] == 1):
        return 0.0
    # (a latched LuGre contact keeps its bristle rate at delta <= 0, where the forces are
    # zero: the state of a located onset can sit a rounding below delta = 0, and a rate
    # jumping from 0 to v_t there spoilt the first step after every onset; module docstring)
    # velocities of the material points at the contact points (f.2)
    vQs = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), _cross_w(bw, s, arm_s)), us)
    vQb = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), _cross_w(bw, b, arm_b)), ub)
    vrel = sub(vQb, vQs)
    vt = sub(vrel, scale(dot(n, vrel), n))
    # impact velocity: latched at onset on accepted steps; before the integrator has
    # latched it (trial stages beyond an onset) use the current approach velocity
    ddm = cs.ddm[p] if cs.flag[p] == 1 else max(ddot, model.clr_geo[k, CG_VFLOOR])
    fn, fel = 0.0, 0.0
    if delta > 0.0:
        fn, fel = normal_force(
            model.cp_ix[p, PI_LAW], model.cp_par[p, 0], delta, ddot, ddm, model.clr_geo[k, CG_C]
        )
    wgt = model.cp_geo[p, PG_W]
    fn = wgt * fn
    fel = wgt * fel
    dn_rate = (fn - fel) * ddot  # D_n rate: normal damping dissipation (j)
    fn = m * fn  # the normal force (m = 1 but for a worn socket; module docstring)
    fel = m * fel
    zw = (y[zi], y[zi + 1], y[zi + 2])
    zn = dot(zw, n)
    z = sub(zw, scale(zn, n))  # the bristles' tangent part (module docstring)
    ft, zd = friction_force(model.cp_ix[p, PI_FRIC], model.cp_par[p, 1], fn, vt, z)
    ft = sub(ft, scale(dot(ft, n), n))  # keep the friction force tangent (f.3)
    if lugre:
        # carried with the turning plane: d(n . z)/dt = 0, d z_t/dt = P zd (module docstring)
        tr = dot(nd, z)
        ydot[zi] = zd[0] - tr * n[0] + zn * nd[0]
        ydot[zi + 1] = zd[1] - tr * n[1] + zn * nd[1]
        ydot[zi + 2] = zd[2] - tr * n[2] + zn * nd[2]
    fb = sub(scale(-fn, n), ft)  # on the inner body, at Q_b
    add_force(wk.Q, b, bA, fb, arm_b)
    add_force(wk.Q, s, bA, scale(-1.0, fb), arm_s)
    ydot[model.y_idn + k] += dn_rate
    ydot[model.y_idt + k] += dot(ft, vt)  # D_t rate: friction work (j)
    pout[p, PO_FN] = fn
    pout[p, PO_FEL] = fel
    cout[k, CO_FN] += fn
    cout[k, CO_FEL] += fel
    for a in range(3):
        pout[p, PO_FT + a] = ft[a]
        pout[p, PO_VT + a] = vt[a]
        cout[k, CO_FT + a] += ft[a]
        cout[k, CO_FNV + a] += fn * n[a]
        if deepest:
            cout[k, CO_VT + a] = vt[a]
    # work through the moving attachments: -(f_b . u_b + f_s . u_s), f_s = -f_b (j)
    return -dot(fb, sub(ub, us))


@njit(cache=True, inline="always", error_model="numpy")
def clearance_forces(model, y, wk, cs, ydot):
    """Add the contact forces of all clearance joints to wk.Q; write the bristle rates and
    the D_n, D_t rates into ydot; fill the diagnostics wk.pout (ncp, NPOUT) and wk.cout
    (nclr, NCOUT) but for the joint positions (eccentricity, inner centre: `joint_outputs`,
    only needed at the output samples). cs: the discrete contact state. Returns the power
    of the contact forces through moving attachment points, -sum f . (A sb_dot) (the W_m
    rate)."""
    bA, br, brd, bw = wk.bA, wk.br, wk.brd, wk.bw
    cout = wk.cout
    for k in range(model.nclr):
        for a in range(3):
            cout[k, CO_FT + a] = 0.0
            cout[k, CO_VT + a] = 0.0
            cout[k, CO_FNV + a] = 0.0
        cout[k, CO_DELTA] = -math.inf
        cout[k, CO_FN] = 0.0
        cout[k, CO_FEL] = 0.0
        ydot[model.y_idn + k] = 0.0
        ydot[model.y_idt + k] = 0.0
    # one loop per contact kind over its points (Model.cp_kptr ranges of the kind-ordered
    # points cp_ix[:, PI_ORDER]): each loop's geometry is inlined, without a per-point branch
    p_moving = 0.0
    kp = model.cp_kptr
    order = model.cp_ix[:, PI_ORDER]
    fval = wk.fval
    for i in range(kp[_SPHERE], kp[_SPHERE + 1]):
        p = order[i]
        g = spherical.contact(model, p, model.cp_ix[p, PI_CLR], bA, br, brd, bw, fval)
        p_moving += _apply(model, y, wk, cs, ydot, p, g)
    for i in range(kp[_STATION], kp[_STATION + 1]):
        p = order[i]
        g = journal.station_contact(model, p, model.cp_ix[p, PI_CLR], bA, br, brd, bw, fval)
        p_moving += _apply(model, y, wk, cs, ydot, p, g)
    for i in range(kp[_THRUST], kp[_THRUST + 1]):
        p = order[i]
        g = journal.thrust_contact(model, p, model.cp_ix[p, PI_CLR], bA, br, brd, bw, fval)
        p_moving += _apply(model, y, wk, cs, ydot, p, g)
    for i in range(kp[_CORNER], kp[_CORNER + 1]):
        p = order[i]
        g = slider.corner_contact(model, p, model.cp_ix[p, PI_CLR], bA, br, brd, bw, fval)
        p_moving += _apply(model, y, wk, cs, ydot, p, g)
    return p_moving


@njit(cache=True, error_model="numpy", _nrt=False)
def joint_outputs(model, wk):
    """wk.cout eccentricity and inner centre of every clearance joint, for the bodies and
    time functions in wk (after an evaluation)."""
    for k in range(model.nclr):
        e, Pb = eccentricity(model, k, wk.bA, wk.br, wk.fval)
        for a in range(3):
            wk.cout[k, CO_E + a] = e[a]
            wk.cout[k, CO_PB + a] = Pb[a]


@njit(cache=True, inline="always", error_model="numpy")
def _cross_w(bw, b, arm):
    """omega_b x arm (world)."""
    w0, w1, w2 = bw[b, 0], bw[b, 1], bw[b, 2]
    return (w1 * arm[2] - w2 * arm[1], w2 * arm[0] - w0 * arm[2], w0 * arm[1] - w1 * arm[0])


@njit(cache=True, error_model="numpy", _nrt=False)
def contact_energy(model, bA, br, fval):
    """V_c = sum of the elastic energies stored in the contacts [J]."""
    V = 0.0
    for p in range(model.ncp):
        delta = gap_of(model, p, bA, br, fval)
        if delta > 0.0:
            k = model.cp_ix[p, PI_CLR]
            V += model.cp_geo[p, PG_W] * elastic_energy(
                model.cp_ix[p, PI_LAW], model.cp_par[p, 0], delta, model.clr_geo[k, CG_C]
            )
    return V
