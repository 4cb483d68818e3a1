"""Shared geometry of the contact kinds, compiled: the centres of a clearance joint, marker
axes in world components, point-plane contact, the gap rate of material contact points, and
vectors between world and outer-marker components.
"""

from __future__ import annotations

from numba import njit

from clearance.kinds import CI_BB, CI_BS, CI_MVB, CI_MVS, CV_AXB, CV_AXS, CV_PB, CV_PS
from clearance.kinematics.points import moving_point
from clearance.kinematics.rotations import add, cross, dot, mattvec, matvec, scale, sub


@njit(cache=True, inline="always", error_model="numpy")
def centres(model, k, bA, fval):
    """Arms (world) of the outer and inner centres P_s, P_b of clearance joint k from their
    bodies' mass centres, and their velocities relative to the bodies (A sb_dot, world)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    v = model.clr_vec[k]
    sbs, us_b, _ = moving_point(v[CV_PS], v[CV_AXS], model.clr_ix[k, CI_MVS], fval)
    sbb, ub_b, _ = moving_point(v[CV_PB], v[CV_AXB], model.clr_ix[k, CI_MVB], fval)
    return (matvec(bA[s], sbs), matvec(bA[b], sbb), matvec(bA[s], us_b), matvec(bA[b], ub_b))


@njit(cache=True, inline="always", error_model="numpy")
def axis(A, T, j):
    """World components of column j (0: f, 1: g, 2: h) of the marker triad T (body frame)
    of a body with rotation A."""
    return matvec(A, (T[0, j], T[1, j], T[2, j]))


@njit(cache=True, inline="always", error_model="numpy")
def perp(x, h):
    """x minus its component along the unit vector h."""
    return sub(x, scale(dot(x, h), h))


@njit(cache=True, inline="always", error_model="numpy")
def point_plane(model, k, br, arm_s0, arm_x, m, d0):
    """A point X of the inner body (arm arm_x from the mass centre of b) against a plane of
    the outer body: delta = m . (X - P_s) + d0, m the unit normal pointing from the plane
    towards the outside of the joint. Returns (delta, n = m, arm_s, arm_b): Q_b = X and
    Q_s = X - delta n, the foot of X on the plane, a material point of s; so
    delta = n . (Q_b - Q_s) and its variation is n . (dQ_b - dQ_s) exactly."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    x = sub(
        add((br[b, 0], br[b, 1], br[b, 2]), arm_x), add((br[s, 0], br[s, 1], br[s, 2]), arm_s0)
    )  # X - P_s
    delta = dot(m, x) + d0
    return delta, m, sub(add(arm_s0, x), scale(delta, m)), arm_x


@njit(cache=True, inline="always", error_model="numpy")
def outer_rate(model, k, bw, x):
    """Rate omega_s x x of a vector x fixed in the outer body s (e.g. the normal of a face of
    s: point-plane contacts)."""
    s = model.clr_ix[k, CI_BS]
    return cross((bw[s, 0], bw[s, 1], bw[s, 2]), x)


@njit(cache=True, inline="always", error_model="numpy")
def gap_rate(model, k, brd, bw, n, arm_s, arm_b, us, ub):
    """delta_dot = n . (v_Q_b - v_Q_s) of the material contact points (u: moving
    attachments)."""
    s = model.clr_ix[k, CI_BS]
    b = model.clr_ix[k, CI_BB]
    ws = (bw[s, 0], bw[s, 1], bw[s, 2])
    wb = (bw[b, 0], bw[b, 1], bw[b, 2])
    vQs = add(add((brd[s, 0], brd[s, 1], brd[s, 2]), cross(ws, arm_s)), us)
    vQb = add(add((brd[b, 0], brd[b, 1], brd[b, 2]), cross(wb, arm_b)), ub)
    return dot(n, sub(vQb, vQs))


@njit(cache=True, inline="always", error_model="numpy")
def to_marker(A, T, x):
    """Outer-marker components T^T A^T x of the world vector x."""
    es = mattvec(A, x)
    return (
        T[0, 0] * es[0] + T[1, 0] * es[1] + T[2, 0] * es[2],
        T[0, 1] * es[0] + T[1, 1] * es[1] + T[2, 1] * es[2],
        T[0, 2] * es[0] + T[1, 2] * es[1] + T[2, 2] * es[2],
    )


@njit(cache=True, inline="always", error_model="numpy")
def to_world(A, T, x):
    """World components A T x of the outer-marker vector x."""
    return matvec(
        A,
        (
            T[0, 0] * x[0] + T[0, 1] * x[1] + T[0, 2] * x[2],
            T[1, 0] * x[0] + T[1, 1] * x[1] + T[1, 2] * x[2],
            T[2, 0] * x[0] + T[2, 1] * x[1] + T[2, 2] * x[2],
        ),
    )
