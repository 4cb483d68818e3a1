"""Slider in guide (prismatic clearance joint), compiled.

Guide (outer) on body s: centre P_s, marker triad (f_s, g_s, h_s), h_s the sliding axis, a
rectangular channel with walls at f_s . (x - P_s) = +-(a_f + c_f) and, in the spatial
model, g_s . (x - P_s) = +-(a_g + c_g). Slider (inner) on body b: a box centred at P_b with
half-sizes a_f, a_g, l along its marker axes (f_b, g_b, h_b). Contact points are corner-wall
pairs (Flores et al. 2008 check the slider corners against the guide surfaces): corner
X = P_b + s_h l h_b + s_f a_f f_b + s_g a_g g_b (a material point of b) against the wall of
its side, outward normal m = s_f f_s (or s_g g_s):

    delta = m . (X - P_s) - (a_f + c_f),   n = m,   Q_b = X,   Q_s = X - delta n

(point-plane, `clearance.contact.frames.point_plane`: the forces are the exact gradient of
the elastic energy). The planar model (motion in the f-h plane, g the plane normal) uses the
4 corners s_g = 0 against the two f walls; the spatial model the 8 corners, each against its
f wall and its g wall (16 points). Model.cp_geo[p] (from column kinds.PG_K0) = [s_h, s_f,
s_g, wall (0: f, 1: g)]; Model.clr_geo[k] (from kinds.CG_K0) = [a_f, a_g, l, c_f, c_g].

Neglected: edge-edge contact between guide edges and slider faces (the guide is taken
longer than the slider's travel), rounding of the corners, lubrication.
"""

from __future__ import annotations

from numba import njit

from clearance.contact.frames import axis, centres, gap_rate, outer_rate, point_plane
from clearance.kinds import CG_K0, CI_BB, CI_BS, PG_K0
from clearance.kinematics.rotations import add, scale


@njit(cache=True, error_model="numpy", _nrt=False)
def _corner(model, p, k, bA, br, arm_s0, arm_b0):
    """Geometry of corner-wall pair p: (delta, n, arm_s, arm_b)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    g = model.clr_geo[k, CG_K0:]
    q = model.cp_geo[p, PG_K0:]
    Tb = model.clr_T[k, 1]
    arm_x = add(
        add(arm_b0, scale(q[0] * g[2], axis(bA[b], Tb, 2))),
        add(scale(q[1] * g[0], axis(bA[b], Tb, 0)), scale(q[2] * g[1], axis(bA[b], Tb, 1))),
    )
    if q[3] == 0.0:
        m = scale(q[1], axis(bA[s], model.clr_T[k, 0], 0))
        half_gap = g[0] + g[3]
    else:
        m = scale(q[2], axis(bA[s], model.clr_T[k, 0], 1))
        half_gap = g[1] + g[4]
    return point_plane(model, k, br, arm_s0, arm_x, m, -half_gap)


@njit(cache=True, error_model="numpy", _nrt=False)
def corner_gap(model, p, k, bA, br, fval):
    arm_s0, arm_b0, _, _ = centres(model, k, bA, fval)
    return _corner(model, p, k, bA, br, arm_s0, arm_b0)[0]


@njit(cache=True, error_model="numpy", _nrt=False)
def corner_contact(model, p, k, bA, br, brd, bw, fval):
    arm_s0, arm_b0, us, ub = centres(model, k, bA, fval)
    delta, n, arm_s, arm_b = _corner(model, p, k, bA, br, arm_s0, arm_b0)
    ddot = gap_rate(model, k, brd, bw, n, arm_s, arm_b, us, ub)
    return delta, ddot, n, arm_s, arm_b, us, ub, outer_rate(model, k, bw, n), 1.0  # n: a wall
