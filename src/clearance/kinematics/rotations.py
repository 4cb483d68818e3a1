"""Small allocation-free vector and rotation helpers for the compiled kernel.

Vectors are 3-tuples or length-3 arrays; results are tuples (no heap allocation in nopython
mode). Euler parameters p = [e0, e1, e2, e3] (physics.md b.1).
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, inline="always", error_model="numpy")
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, inline="always", error_model="numpy")
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(cache=True, inline="always", error_model="numpy")
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(cache=True, inline="always", error_model="numpy")
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(cache=True, inline="always", error_model="numpy")
def scale(s, a):
    return (s * a[0], s * a[1], s * a[2])


@njit(cache=True, inline="always", error_model="numpy")
def matvec(A, v):
    """A v for a 3x3 array A."""
    return (
        A[0, 0] * v[0] + A[0, 1] * v[1] + A[0, 2] * v[2],
        A[1, 0] * v[0] + A[1, 1] * v[1] + A[1, 2] * v[2],
        A[2, 0] * v[0] + A[2, 1] * v[1] + A[2, 2] * v[2],
    )


@njit(cache=True, inline="always", error_model="numpy")
def mattvec(A, v):
    """A^T v for a 3x3 array A."""
    return (
        A[0, 0] * v[0] + A[1, 0] * v[1] + A[2, 0] * v[2],
        A[0, 1] * v[0] + A[1, 1] * v[1] + A[2, 1] * v[2],
        A[0, 2] * v[0] + A[1, 2] * v[1] + A[2, 2] * v[2],
    )


@njit(cache=True, inline="always", error_model="numpy")
def ww(w, s):
    """w x (w x s): the centripetal acceleration term of physics.md c.1."""
    return cross(w, cross(w, s))


@njit(cache=True, error_model="numpy")
def quat_to_rot(p0, p1, p2, p3, A):
    """Write A(p/|p|) (body -> world) into the 3x3 array A (physics.md b.1)."""
    n = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3)
    e0 = p0 / n
    e1 = p1 / n
    e2 = p2 / n
    e3 = p3 / n
    A[0, 0] = e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3
    A[1, 1] = e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3
    A[2, 2] = e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3
    A[0, 1] = 2.0 * (e1 * e2 - e0 * e3)
    A[1, 0] = 2.0 * (e1 * e2 + e0 * e3)
    A[0, 2] = 2.0 * (e1 * e3 + e0 * e2)
    A[2, 0] = 2.0 * (e1 * e3 - e0 * e2)
    A[1, 2] = 2.0 * (e2 * e3 - e0 * e1)
    A[2, 1] = 2.0 * (e2 * e3 + e0 * e1)


@njit(cache=True, inline="always", error_model="numpy")
def quat_rate(p, w):
    """p_dot = (1/2) p (x) (0, w') = (1/2) G(p)^T w' (physics.md b.1), as a 4-tuple.

    Keeps |p| constant exactly (p . p_dot = 0), so p is not renormalised inside the ODE.
    """
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    return (
        0.5 * (-e1 * w[0] - e2 * w[1] - e3 * w[2]),
        0.5 * (e0 * w[0] - e3 * w[1] + e2 * w[2]),
        0.5 * (e3 * w[0] + e0 * w[1] - e1 * w[2]),
        0.5 * (-e2 * w[0] + e1 * w[1] + e0 * w[2]),
    )


@njit(cache=True, error_model="numpy")
def quat_rotate_body(p, dth, out):
    """out = p (x) exp(dth'/2): rotate by the body-frame rotation vector dth (b.1)."""
    a = math.sqrt(dth[0] * dth[0] + dth[1] * dth[1] + dth[2] * dth[2])
    if a < 1e-300:
        c, s0, s1, s2 = 1.0, 0.0, 0.0, 0.0
    else:
        c = math.cos(0.5 * a)
        k = math.sin(0.5 * a) / a
        s0, s1, s2 = k * dth[0], k * dth[1], k * dth[2]
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    out[0] = e0 * c - e1 * s0 - e2 * s1 - e3 * s2
    out[1] = e0 * s0 + e1 * c + e2 * s2 - e3 * s1
    out[2] = e0 * s1 + e2 * c + e3 * s0 - e1 * s2
    out[3] = e0 * s2 + e3 * c + e1 * s1 - e2 * s0


@njit(cache=True, inline="always", error_model="numpy")
def rot_axis_apply(axis, th, x, kind):
    """Apply factor `kind` of the elementary rotation about world axis `axis` (0, 1, 2).

    kind 0: R(th) x;  kind 1: dR/dth x = R (e x x);  kind 2: d2R/dth2 x = R (e x (e x x)).
    """
    if kind == 1:
        x = (
            (0.0, -x[2], x[1])
            if axis == 0
            else ((x[2], 0.0, -x[0]) if axis == 1 else (-x[1], x[0], 0.0))
        )
    elif kind == 2:
        x = (
            (0.0, -x[1], -x[2])
            if axis == 0
            else ((-x[0], 0.0, -x[2]) if axis == 1 else (-x[0], -x[1], 0.0))
        )
    c = math.cos(th)
    s = math.sin(th)
    if axis == 0:
        return (x[0], c * x[1] - s * x[2], s * x[1] + c * x[2])
    if axis == 1:
        return (c * x[0] + s * x[2], x[1], -s * x[0] + c * x[2])
    return (c * x[0] - s * x[1], s * x[0] + c * x[1], x[2])
