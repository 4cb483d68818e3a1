"""The depth field of a worn surface (issue 16), compiled: Shepard's interpolation of
depth samples with Wendland's C2 weight (`clearance.model.wear`), with its gradient and
Hessian, shared by the worn socket (contact/spherical.py) and the worn bearing
(contact/journal.py).

Rows of Model.clr_wear: [c_x, c_y, c_z, h a, a] (a sample's point c, its depth h times its
weight a, the weight), and

    h(u) = sum_i h_i a_i phi_i(u) / sum_i a_i phi_i(u),  phi_i = phi(|u - c_i| / rho),

phi(r) = (1 - r)^4 (4 r + 1) for r < 1: twice continuously differentiable in u, and a
uniform depth is reproduced exactly. Where no sample lies within rho, h = 0.
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, error_model="numpy", _nrt=False)
def depth_field(model, r0, nr, rho, u, du):
    """(h, g, H du): the depth h(u) [m] of rows r0 .. r0 + nr - 1 of Model.clr_wear at the
    point u (module docstring), its gradient g = dh/du and the derivative of g along du
    (the Hessian times du), in the rows' frame; rho: the smoothing radius."""
    r2 = rho * rho
    W = model.clr_wear
    num = den = 0.0
    n0 = n1 = n2 = d0 = d1 = d2 = 0.0  # gradients of the numerator and denominator
    p0 = p1 = p2 = q0 = q1 = q2 = 0.0  # their Hessians times du
    for i in range(r0, r0 + nr):
        x0, x1, x2 = u[0] - W[i, 0], u[1] - W[i, 1], u[2] - W[i, 2]
        s2 = x0 * x0 + x1 * x1 + x2 * x2
        if s2 >= r2:
            continue
        sd = math.sqrt(s2)
        om = 1.0 - sd / rho
        phi = om * om * om * om * (4.0 * sd / rho + 1.0)
        a = -20.0 * om * om * om / r2  # grad phi = a x
        # Hessian of phi times du: a du + x (da/ds) (x . du) / s
        c = (
            60.0 * om * om / (r2 * rho * sd) * (x0 * du[0] + x1 * du[1] + x2 * du[2])
            if sd > 0.0
            else 0.0
        )
        hv0, hv1, hv2 = a * du[0] + c * x0, a * du[1] + c * x1, a * du[2] + c * x2
        wn, wd = W[i, 3], W[i, 4]
        num += wn * phi
        den += wd * phi
        n0 += wn * a * x0
        n1 += wn * a * x1
        n2 += wn * a * x2
        d0 += wd * a * x0
        d1 += wd * a * x1
        d2 += wd * a * x2
        p0 += wn * hv0
        p1 += wn * hv1
        p2 += wn * hv2
        q0 += wd * hv0
        q1 += wd * hv1
        q2 += wd * hv2
    if num <= 0.0 or den <= 0.0:
        return 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    h = num / den
    g = ((n0 - h * d0) / den, (n1 - h * d1) / den, (n2 - h * d2) / den)
    gdu = g[0] * du[0] + g[1] * du[1] + g[2] * du[2]
    ddu = d0 * du[0] + d1 * du[1] + d2 * du[2]
    H = (
        (p0 - gdu * d0 - h * q0 - g[0] * ddu) / den,
        (p1 - gdu * d1 - h * q1 - g[1] * ddu) / den,
        (p2 - gdu * d2 - h * q2 - g[2] * ddu) / den,
    )
    return h, g, H
