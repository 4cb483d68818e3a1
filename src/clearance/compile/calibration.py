"""Parameters computed from geometry and materials (plain Python, used when encoding laws).

    hertz_stiffness(E_b, nu_b, E_s, nu_s, R_ball, R_socket)   K [N/m^1.5], physics.md g.1
    kelvin_voigt_damping(K_l, m_eff, c_r)                     D [N s/m], g.3
    winkler_kf(K, R, c, delta_ref, form=1)                    k_f [N/m^3], g.6

Each raises ModelError naming the argument that is out of range.
"""

from __future__ import annotations

import math

from clearance.contact.laws import winkler_fel, winkler_kn
from clearance.model.errors import ModelError


def effective_modulus(E_a: float, nu_a: float, E_b: float, nu_b: float) -> float:
    """E* [Pa] of two elastic bodies in contact: 1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b."""
    return 1.0 / ((1.0 - nu_a**2) / E_a + (1.0 - nu_b**2) / E_b)


def hertz_stiffness(
    E_ball: float, nu_ball: float, E_socket: float, nu_socket: float, R_ball: float, R_socket: float
) -> float:
    """Internal (ball-in-socket) Hertz stiffness K [N/m^1.5] (physics.md g.1, RECALLED).

    K = (4/3) E* sqrt(R*), 1/E* = (1 - nu_b^2)/E_b + (1 - nu_s^2)/E_s,
    R* = R_b R_s / (R_s - R_b) (conformal contact). E in Pa, R in m; needs R_socket > R_ball.
    The same formula with the journal and bearing radii is the usual stiffness of a revolute
    clearance joint (Flores & Ambrosio 2004); R_socket = inf gives a sphere of radius R_ball
    on a flat (R* = R_ball), e.g. a rounded slider corner on a guide wall.
    """
    if not R_socket > R_ball > 0.0:
        raise ModelError(
            "hertz_stiffness", "R_socket", R_socket, f"must exceed R_ball = {R_ball!r} > 0"
        )
    e_star = effective_modulus(E_ball, nu_ball, E_socket, nu_socket)
    r_star = R_ball if math.isinf(R_socket) else R_ball * R_socket / (R_socket - R_ball)
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


def kelvin_voigt_damping(K_l: float, m_eff: float, c_r: float) -> float:
    """Damping D [N s/m] giving restitution c_r to the unclamped linear oscillator (g.3).

    D = 2 zeta sqrt(m_eff K_l), zeta = -ln c_r / sqrt(pi^2 + ln^2 c_r) (DERIVED, exact).
    """
    if not 0.0 < c_r <= 1.0:
        raise ModelError("kelvin_voigt_damping", "c_r", c_r, "expected 0 < c_r <= 1")
    lc = math.log(c_r)
    zeta = -lc / math.sqrt(math.pi**2 + lc * lc)
    return 2.0 * zeta * math.sqrt(m_eff * K_l)


def winkler_kf(K: float, R: float, c: float, delta_ref: float, *, form: int = 1) -> float:
    """Winkler modulus k_f [N/m^3] calibrated to Hertz at delta_ref [m] (g.6, PROPOSED).

    form 1: F_el(delta_ref) = K delta_ref^1.5 (physics.md g.6).
    form 2: K_n(delta_ref) = K numerically, i.e. the swapped stiffness equals the Hertz K at
    delta_ref, so Form 2's force K_n delta^1.5 equals K delta^1.5 there (PROPOSED: Form 2
    is not homogeneous, so Form 1's k_f would make it ~delta^0.5 times weaker).
    The equivalent layer thickness is h_eq = E*/k_f.
    """
    if not delta_ref > 0.0:
        raise ModelError("winkler_kf", "delta_ref", delta_ref, "expected a penetration > 0")
    if form == 1:
        return K * delta_ref**1.5 / float(winkler_fel(1.0, R, c, delta_ref))
    if form == 2:
        return K / float(winkler_kn(1.0, R, c, delta_ref))
    raise ModelError("winkler_kf", "form", form, "expected 1 or 2")
