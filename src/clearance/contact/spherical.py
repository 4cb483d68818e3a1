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
"""

from __future__ import annotations

import math

from numba import njit

from clearance.contact.frames import centres
from clearance.kinds import CG_C, CG_K0, CI_BB, CI_BS
from clearance.kinematics.rotations import add, cross, dot, scale, sub

_RS, _RB = CG_K0, CG_K0 + 1  # socket and ball radii in clr_geo


@njit(cache=True, inline="always", error_model="numpy")
def gap(model, p, k, bA, br, fval):
    """delta of the ball in its socket (f.1)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    arm_s, arm_b, _, _ = centres(model, k, bA, fval)
    Ps = add((br[s, 0], br[s, 1], br[s, 2]), arm_s)
    Pb = add((br[b, 0], br[b, 1], br[b, 2]), arm_b)
    e = sub(Pb, Ps)
    return math.sqrt(dot(e, e)) - model.clr_geo[k, CG_C]


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
    return delta, ddot, n, arm_s, arm_b, us, ub, nd
