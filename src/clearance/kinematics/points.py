"""Points and forces on rigid bodies, compiled: the moving attachment point of physics.md c.2
(rheonomic, lumped limbs of physics.md i) and the transfer of a force to a body's mass
centre (physics.md d.1, f.4). Shared by the constraint primitives, the contact elements and
the applied forces.
"""

from __future__ import annotations

from numba import njit

from clearance.kinematics.rotations import cross, mattvec


@njit(cache=True, inline="always", error_model="numpy")
def moving_point(sb0, ax, fn, fval):
    """(sb, sb_dot, sb_ddot) of an attachment point sb(t) = sb0 + ax f(t) (body frame);
    fn < 0: a fixed point."""
    if fn < 0:
        return (sb0[0], sb0[1], sb0[2]), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    f = fval[fn, 0]
    fd = fval[fn, 1]
    fdd = fval[fn, 2]
    return (
        (sb0[0] + ax[0] * f, sb0[1] + ax[1] * f, sb0[2] + ax[2] * f),
        (ax[0] * fd, ax[1] * fd, ax[2] * fd),
        (ax[0] * fdd, ax[1] * fdd, ax[2] * fdd),
    )


@njit(cache=True, error_model="numpy")
def add_force(Q, b, bA, F, s_w):
    """Add world force F applied at arm s_w (world, from the CoM) to body b (skip ground)."""
    if b < 0:
        return
    Q[b, 0] += F[0]
    Q[b, 1] += F[1]
    Q[b, 2] += F[2]
    n = mattvec(bA[b], cross(s_w, F))
    Q[b, 3] += n[0]
    Q[b, 4] += n[1]
    Q[b, 5] += n[2]
