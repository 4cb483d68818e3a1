"""Compiled normal-contact and friction laws of the ball-in-socket joint (physics.md g, h).

Pure `@njit` functions selected by an integer code (`NormalLaw`, `FrictionLaw`), with the
law's parameters in a float64 array `par` of length NPAR = 8 (unused slots are 0). Nothing
is read from globals except the law codes and fixed quadrature nodes, so a parameter sweep
never recompiles. No heap allocation: vectors are 3-tuples (`clearance.kinematics.rotations`).

Sign conventions (physics.md a, f): delta = |e| - c > 0 in contact [m]; delta_dot > 0 while
compressing [m/s]; delta_dot_minus = delta_dot latched at contact onset, floored by the
caller (f.5); F_N >= 0 always (no adhesion). Friction returns F_T_vec, the force on the
ball is -F_T_vec (f.3), so for Coulomb-type laws F_T_vec = F_T t_hat points along +v_t.

Normal laws, `normal_force(law, par, delta, delta_dot, delta_dot_minus, c) -> (f_n, f_el)`:

    code  law                   par[0]        par[1]      par[2]   par[3]
    0     HERTZ                 K [N/m^n]     n           -        -
    1     KELVIN_VOIGT          K_l [N/m]     D [N s/m]   -        -
    2-9   dissipative family    K [N/m^n]     n           c_r      -
    10    IMPACT                K [N/m^e]     e           cmax     d [m]
                                                          [N s/m]
    11    WINKLER_FORM1         k_f [N/m^3]   R [m]       c_r      -
    12    WINKLER_FORM2         k_f [N/m^3]   R [m]       c_r      -
    13    POWER                 K [N/m^n]     n           xi       -
    14    JOHNSON               E* [Pa]       dR [m]      L [m]    xi
    15    LIU                   E* [Pa]       dR [m]      L [m]    xi

  Line contact of a journal (length L, radial clearance dR, E* = 1/sum (1 - nu^2)/E), laws
  per unit length q(delta) times L, with the hysteresis factor xi of a g.2 family member
  given in par (the apparent restitution of F_el(delta) [1 + xi delta_dot/delta_dot_minus]
  does not depend on the elastic law: the g.2 table holds; DERIVED, docs/clearance-joints.md):
  JOHNSON: delta = (q/(pi E*)) [ln(4 pi E* dR / q) - 1] (Johnson 1985, ESDU 78035), solved
  explicitly: q = pi E* delta/(x - 1), x > 2 the root of e^-x (x - 1) = delta/(4 dR); valid
  below delta = 4 dR e^-2 = 0.54 dR, continued linearly (C1) beyond half of that.
  LIU: q = (pi/2) E* delta sqrt(delta/(2 (dR + delta))) (Liu, Zhang & Yang 2007).

  Dissipative family (g.2), codes 2-9: HUNT_CROSSLEY, LANKARANI_NIKRAVESH, FLORES,
  GONTHIER, HU_GUO, HERBERT_MCWHANNELL, LEE_WANG, ZHIYING_QISHAO.

  f_el is the non-dissipative (elastic) part used by the energy audit (physics.md j):
  K delta^n (Hertz, dissipative family, IMPACT with n = e), K_l delta (Kelvin-Voigt),
  F_el(delta) (Winkler Form 1), K_n(delta) delta^1.5 (Winkler Form 2, PROPOSED choice).
  `elastic_energy(law, par, delta, c)` is the integral of f_el from 0 to delta, in closed
  form for every law except Form 2 with delta <= c, where its closed form cancels badly and
  16-point Gauss-Legendre quadrature is used instead (error ~1e-20 relative).
  Both Winkler forms use the Flores factor xi = 8(1 - c_r)/(5 c_r) (g.6).

Friction laws, `friction_force(law, par, f_n, vt, z) -> (ft, zdot)`:

    code  law              par layout
    0     NONE             -
    1     COULOMB          [mu, v0, v1]                 linear c_d ramp (h.1)
    2     COULOMB_SMOOTH   [mu, v0, v1]                 cubic STEP c_d ramp (h.1)
    3     THRELFALL        [mu, v0]                     (h.2)
    4     STRIBECK         [mu_s, mu_d, v_s, v_tr]      ADAMS-style (h.3)
    5     LUGRE            [sigma0, sigma1, sigma2, mu_c, mu_s, v_s, v_d, vdamp]   (h.4)
                           vdamp = 1: sigma1(v) = sigma1 exp(-(v/v_d)^2); 0: constant

  The caller passes z's tangent part, carries z with the turning tangent plane (the term
  -n_hat (n_hat_dot . z) in z_dot, contact/element.py) and sets it to zero at onset and
  separation (f.5); friction_force does not know n_hat.

Adding a law: (1) an enum member in `clearance.kinds` with the next code, (2) one pure njit
function of (par, delta, delta_dot, delta_dot_minus, c) -> (f_n, f_el) (and its energy) here
plus the one `if` line that dispatches to it (numba cannot index a table of functions
without losing `cache=True`), (3) a frozen dataclass in `clearance.model.contact_laws` with
its entry in NORMAL_LAWS / FRICTION_LAWS, (4) its encoder in `clearance.compile.laws`. A new
member of the dissipative family only needs its xi(c_r) line in `hysteresis_factor`, the
dataclass and the encoder line. Parameters computed from geometry and materials (Hertz
stiffness, Kelvin-Voigt damping, Winkler modulus) are in `clearance.compile.calibration`.

Under NUMBA_DISABLE_JIT=1 everything runs as plain Python.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.kinds import FrictionLaw, NormalLaw
from clearance.kinematics.rotations import dot, scale

# Plain ints: numba freezes module globals as compile-time constants.
_HERTZ = int(NormalLaw.HERTZ)
_KELVIN_VOIGT = int(NormalLaw.KELVIN_VOIGT)
_HUNT_CROSSLEY = int(NormalLaw.HUNT_CROSSLEY)
_LANKARANI_NIKRAVESH = int(NormalLaw.LANKARANI_NIKRAVESH)
_FLORES = int(NormalLaw.FLORES)
_GONTHIER = int(NormalLaw.GONTHIER)
_HU_GUO = int(NormalLaw.HU_GUO)
_HERBERT_MCWHANNELL = int(NormalLaw.HERBERT_MCWHANNELL)
_LEE_WANG = int(NormalLaw.LEE_WANG)
_ZHIYING_QISHAO = int(NormalLaw.ZHIYING_QISHAO)
_IMPACT = int(NormalLaw.IMPACT)
_WINKLER_FORM1 = int(NormalLaw.WINKLER_FORM1)
_WINKLER_FORM2 = int(NormalLaw.WINKLER_FORM2)
_POWER = int(NormalLaw.POWER)
_JOHNSON = int(NormalLaw.JOHNSON)
_LIU = int(NormalLaw.LIU)

_NONE = int(FrictionLaw.NONE)
_COULOMB = int(FrictionLaw.COULOMB)
_COULOMB_SMOOTH = int(FrictionLaw.COULOMB_SMOOTH)
_THRELFALL = int(FrictionLaw.THRELFALL)
_STRIBECK = int(FrictionLaw.STRIBECK)
_LUGRE = int(FrictionLaw.LUGRE)

# Only to keep the damping term finite if a caller forgets to floor delta_dot_minus (f.5).
_TINY_SPEED = 1e-12

# 16-point Gauss-Legendre on [0, 1] (fixed constants, not parameters).
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
_GL_U = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W


# --------------------------------------------------------------------------- STEP


@njit(cache=True, error_model="numpy")
def step(x, x0, h0, x1, h1):
    """ADAMS STEP: h0 + (h1 - h0) D^2 (3 - 2 D), D = (x - x0)/(x1 - x0) clamped to [0, 1].

    physics.md g.4 (RECALLED). C1: zero slope at both ends; h0 for x <= x0, h1 for x >= x1.
    """
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    d = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)


# --------------------------------------------------------------------------- normal laws


@njit(cache=True, error_model="numpy")
def hysteresis_factor(law, c_r):
    """xi(c_r) of the dissipative family F = K delta^n [1 + xi delta_dot/delta_dot_minus].

    physics.md g.2 table (SOURCED: DyS code, except Hu-Guo RECALLED). Winkler forms use the
    Flores factor (g.6). Returns 0 for laws outside the family.
    """
    if law == _HUNT_CROSSLEY:  # Hunt & Crossley 1975
        return 1.5 * (1.0 - c_r)
    if law == _LANKARANI_NIKRAVESH:  # Lankarani & Nikravesh 1990
        return 0.75 * (1.0 - c_r * c_r)
    if law == _FLORES or law == _WINKLER_FORM1 or law == _WINKLER_FORM2:  # Flores et al. 2011
        return 8.0 * (1.0 - c_r) / (5.0 * c_r)
    if law == _GONTHIER:  # Gonthier et al. 2004
        return (1.0 - c_r * c_r) / c_r
    if law == _HU_GUO:  # Hu & Guo 2015; physics.md g.2: 3(1-c)/(2c), not DyS's 3(1-c)/(4c)
        return 3.0 * (1.0 - c_r) / (2.0 * c_r)
    if law == _HERBERT_MCWHANNELL:  # Herbert & McWhannell 1977
        a = 2.0 * c_r - 1.0
        return 6.0 * (1.0 - c_r) / (a * a + 3.0)
    if law == _LEE_WANG:  # Lee & Wang 1983
        return 0.75 * (1.0 - c_r)
    if law == _ZHIYING_QISHAO:  # Zhiying & Qishao 2006 (RECALLED)
        return 0.75 * (1.0 - c_r * c_r) * math.exp(2.0 * (1.0 - c_r))
    return 0.0


@njit(cache=True, error_model="numpy")
def winkler_fel(k_f, R, c, delta):
    """Elastic-foundation force F_el(delta) [N] of the conformal ball in socket (g.6, DERIVED).

    F_el = pi R^2 k_f delta^2 (3c + 2 delta) / (3 (c + delta)^2); k_f [N/m^3], R, c [m].
    """
    if delta <= 0.0:
        return 0.0
    s = c + delta
    return math.pi * R * R * k_f * delta * delta * (3.0 * c + 2.0 * delta) / (3.0 * s * s)


@njit(cache=True, error_model="numpy")
def winkler_kn(k_f, R, c, delta):
    """Tangent stiffness K_n = dF_el/d delta [N/m] (g.6, DERIVED).

    K_n = pi R^2 k_f delta (6c^2 + 6 c delta + 2 delta^2) / (3 (c + delta)^3).
    """
    if delta <= 0.0:
        return 0.0
    s = c + delta
    poly = 6.0 * c * c + 6.0 * c * delta + 2.0 * delta * delta
    return math.pi * R * R * k_f * delta * poly / (3.0 * s * s * s)


@njit(cache=True, error_model="numpy")
def _damped(f_el, xi, delta_dot, delta_dot_minus):
    """max(0, f_el [1 + xi delta_dot / delta_dot_minus]) (g.2; the clamp: no adhesion, g)."""
    dm = delta_dot_minus if delta_dot_minus > _TINY_SPEED else _TINY_SPEED
    f = f_el * (1.0 + xi * delta_dot / dm)
    return f if f > 0.0 else 0.0


# Johnson: the linear continuation starts at s = delta/(4 dR) = e^-2 / 2 (delta = 0.27 dR)
_JOHNSON_S_CAP = 0.5 * math.exp(-2.0)


@njit(cache=True, error_model="numpy")
def _johnson_x(s):
    """x > 2 with e^-x (x - 1) = s, 0 < s < e^-2: Newton on ln(x - 1) - x + ln(1/s) (well
    conditioned; from x0 = L + ln L + 1, L = ln(1/s) > 2, 3-6 steps to machine precision)."""
    lam = -math.log(s)
    x = lam + math.log(lam) + 1.0
    for _ in range(12):
        g = math.log(x - 1.0) - x + lam
        dx = g / (1.0 / (x - 1.0) - 1.0)
        x -= dx
        if abs(dx) <= 1e-15 * x:
            break
    return x


@njit(cache=True, error_model="numpy")
def johnson_line(Es, dR, delta):
    """(q [N/m], u [J/m]): Johnson's internal-cylinder line load per unit length and its
    energy per unit length at penetration delta (explicit form, see the module docstring;
    u = q^2 (x - 3/2)/(2 pi E*), DERIVED), continued linearly beyond s = e^-2/2."""
    if not delta > 0.0:
        return 0.0, 0.0
    s = delta / (4.0 * dR)
    if s <= _JOHNSON_S_CAP:
        x = _johnson_x(s)
        q = math.pi * Es * delta / (x - 1.0)
        return q, q * q * (x - 1.5) / (2.0 * math.pi * Es)
    dc = 4.0 * dR * _JOHNSON_S_CAP
    x = _johnson_x(_JOHNSON_S_CAP)
    qc = math.pi * Es * dc / (x - 1.0)
    kc = math.pi * Es / (x - 2.0)  # dq/d delta at the cap
    d = delta - dc
    return qc + kc * d, qc * qc * (x - 1.5) / (2.0 * math.pi * Es) + qc * d + 0.5 * kc * d * d


@njit(cache=True, error_model="numpy")
def liu_line(Es, dR, delta):
    """(q [N/m], u [J/m]): Liu, Zhang & Yang (2007) line load q = (pi/2) E* delta
    sqrt(delta/(2 (dR + delta))) and its energy per unit length (closed form, DERIVED; a
    series below delta/dR = 1e-3, where the closed form cancels)."""
    if not delta > 0.0:
        return 0.0, 0.0
    a = math.pi * Es / (2.0 * math.sqrt(2.0))
    q = a * delta * math.sqrt(delta / (dR + delta))
    r = delta / dR
    if r < 1e-3:  # a delta^2.5 dR^-0.5 (2/5 - r/7 + r^2/12 - 5 r^3/88): error ~ r^4
        u = a * delta**2.5 / math.sqrt(dR) * (0.4 - r / 7.0 + r * r / 12.0 - 5.0 * r**3 / 88.0)
    else:
        sq = math.sqrt(dR + delta)
        u = (
            a
            * (
                2.0 * delta**2.5
                - dR * delta**1.5
                - 3.0 * dR * dR * math.sqrt(delta)
                + 3.0 * dR * dR * sq * math.asinh(math.sqrt(r))
            )
            / (4.0 * sq)
        )
    return q, u


@njit(cache=True, error_model="numpy")
def normal_force(law, par, delta, delta_dot, delta_dot_minus, c):
    """(f_n, f_el) [N] of normal law `law` (NormalLaw code) with parameters par (NPAR,).

    delta: penetration [m] (> 0 in contact); delta_dot: approach velocity [m/s] (> 0
    compressing); delta_dot_minus: delta_dot at onset [m/s], already floored by the caller
    (f.5; values below 1e-12 are raised to 1e-12 only to stay finite); c: radial clearance
    [m] (used by the Winkler forms). f_n >= 0 is the force magnitude (clamped, no adhesion);
    f_el is its elastic part (see the module docstring). (0, 0) for delta <= 0.
    """
    if not delta > 0.0:
        return 0.0, 0.0
    if law == _KELVIN_VOIGT:
        # g.3: F = max(0, K_l delta + D delta_dot); it jumps at onset (comparison only)
        f_el = par[0] * delta
        f = f_el + par[1] * delta_dot
        return (f if f > 0.0 else 0.0), f_el
    if law == _IMPACT:
        # g.4 ADAMS IMPACT(-|e|, -|e|_dot, -c, K, e, cmax, d): K delta^e + damping ramped by
        # STEP(delta, 0, 0, d, cmax) (equal to STEP(x, x1 - d, cmax, x1, 0) by symmetry)
        f_el = par[0] * delta ** par[1]
        f = f_el + step(delta, 0.0, 0.0, par[3], par[2]) * delta_dot
        return (f if f > 0.0 else 0.0), f_el
    if law == _POWER:
        # K delta^n [1 + xi delta_dot / delta_dot_minus], xi given (Pereira et al. 2011)
        f_el = par[0] * delta ** par[1]
        return _damped(f_el, par[2], delta_dot, delta_dot_minus), f_el
    if law == _JOHNSON:
        # line contact: L q(delta) [1 + xi ...] (Johnson 1985, explicit form)
        f_el = par[2] * johnson_line(par[0], par[1], delta)[0]
        return _damped(f_el, par[3], delta_dot, delta_dot_minus), f_el
    if law == _LIU:
        # line contact: L q(delta) [1 + xi ...] (Liu, Zhang & Yang 2007)
        f_el = par[2] * liu_line(par[0], par[1], delta)[0]
        return _damped(f_el, par[3], delta_dot, delta_dot_minus), f_el
    if law == _WINKLER_FORM1:
        # g.6 Form 1 (PROPOSED default, reconstruction): F_el(delta) [1 + xi_Flores ...]
        f_el = winkler_fel(par[0], par[1], c, delta)
        return _damped(f_el, hysteresis_factor(law, par[2]), delta_dot, delta_dot_minus), f_el
    if law == _WINKLER_FORM2:
        # g.6 Form 2 ("stiffness swap", reconstruction, not dimensionally homogeneous):
        # K_n(delta) delta^1.5 [1 + xi_Flores ...]
        f_el = winkler_kn(par[0], par[1], c, delta) * delta**1.5
        return _damped(f_el, hysteresis_factor(law, par[2]), delta_dot, delta_dot_minus), f_el
    # g.1 Hertz K delta^n and the g.2 dissipative family K delta^n [1 + xi ...]
    f_el = par[0] * delta ** par[1]
    if law == _HERTZ:
        return f_el, f_el
    return _damped(f_el, hysteresis_factor(law, par[2]), delta_dot, delta_dot_minus), f_el


@njit(cache=True, error_model="numpy")
def _winkler2_shape(r):
    """I(r) = int_0^1 u^6 (6 r^2 + 6 r u^2 + 2 u^4) / (r + u^2)^3 du, r = c/delta >= 0.

    U_2(delta) = (2/3) pi R^2 k_f delta^2.5 I(c/delta) (substitution s = delta u^2 in the
    integral of K_n(s) s^1.5). Closed form (sympy, checked against quadrature in the
    tests) 2/5 + (15 r^4 + 25 r^3)/(20 (1 + r)^2) - (3/4) r^2.5 atan(1/sqrt r) for r < 1;
    for r >= 1 it cancels, and 16-point Gauss-Legendre on the positive integrand is used
    (its poles u = +-i sqrt(r) are far from [0, 1]: error ~ 1e-20).
    """
    if r <= 0.0:
        return 0.4
    if r < 1.0:
        s = 1.0 + r
        return (
            0.4
            + (15.0 * r**4 + 25.0 * r**3) / (20.0 * s * s)
            - 0.75 * r**2.5 * math.atan(1.0 / math.sqrt(r))
        )
    acc = 0.0
    for k in range(_GL_U.shape[0]):
        u2 = _GL_U[k] * _GL_U[k]
        den = r + u2
        acc += (
            _GL_W[k]
            * u2
            * u2
            * u2
            * (6.0 * r * r + 6.0 * r * u2 + 2.0 * u2 * u2)
            / (den * den * den)
        )
    return acc


@njit(cache=True, error_model="numpy")
def elastic_energy(law, par, delta, c):
    """U(delta) = int_0^delta f_el [J]: energy stored at penetration delta (physics.md j).

    Power laws K delta^(n+1)/(n+1) (Hertz, dissipative family, IMPACT, POWER); line laws
    L u(delta) (JOHNSON, LIU; see their functions); K_l delta^2/2
    (Kelvin-Voigt); Winkler Form 1 pi R^2 k_f delta^3 / (3 (c + delta)) (DERIVED: with
    x = c + delta, F_el = (pi R^2 k_f/3)(2x - 3c + c^3/x^2), integrated from c to c + delta);
    Form 2 see `_winkler2_shape`. 0 for delta <= 0.
    """
    if not delta > 0.0:
        return 0.0
    if law == _KELVIN_VOIGT:
        return 0.5 * par[0] * delta * delta
    if law == _WINKLER_FORM1:
        return math.pi * par[1] * par[1] * par[0] * delta**3 / (3.0 * (c + delta))
    if law == _WINKLER_FORM2:
        a = math.pi * par[1] * par[1] * par[0] / 3.0
        return 2.0 * a * delta**2.5 * _winkler2_shape(c / delta)
    if law == _JOHNSON:
        return par[2] * johnson_line(par[0], par[1], delta)[1]
    if law == _LIU:
        return par[2] * liu_line(par[0], par[1], delta)[1]
    n = par[1]
    return par[0] * delta ** (n + 1.0) / (n + 1.0)


# --------------------------------------------------------------------------- friction laws


@njit(cache=True, error_model="numpy")
def _lugre_g(par, v):
    """Stribeck curve g(v) = mu_c + (mu_s - mu_c) exp(-(v/v_s)^2) (h.4, Canudas de Wit 1995)."""
    q = v / par[5]
    return par[3] + (par[4] - par[3]) * math.exp(-q * q)


@njit(cache=True, error_model="numpy")
def friction_steady(law, par, v):
    """Steady-sliding friction coefficient mu_eff = F_T / F_N at slip speed v = |v_t| [m/s]."""
    v = abs(v)
    if law == _COULOMB:
        # h.1 Ambrosio c_d, linear ramp (RECALLED: Ambrosio 2003; Flores et al.)
        v0, v1 = par[1], par[2]
        if v < v0:
            return 0.0
        if v > v1:
            return par[0]
        return par[0] * (v - v0) / (v1 - v0)
    if law == _COULOMB_SMOOTH:
        # h.1 variant: c_d = STEP(v, v0, 0, v1, 1)
        return par[0] * step(v, par[1], 0.0, par[2], 1.0)
    if law == _THRELFALL:
        # h.2 Threlfall 1978 (RECALLED, verify): 95 % at v0, then mu (5 % step at v0)
        if v <= par[1]:
            return par[0] * (1.0 - math.exp(-3.0 * v / par[1]))
        return par[0]
    if law == _STRIBECK:
        # h.3 ADAMS: step(v, -v_s, -1, v_s, 1) step(v, v_s, mu_s, v_tr, mu_d) at v = |v_t|:
        # the upper half of the symmetric cubic (0.6875 at v_s/2), as ADAMS has it
        v_s = par[2]
        return step(v, -v_s, -1.0, v_s, 1.0) * step(v, v_s, par[0], par[3], par[1])
    if law == _LUGRE:
        # h.4 steady state z_dot = 0: F_T = F_N (g(v) + sigma2 v)
        return _lugre_g(par, v) + par[2] * v
    return 0.0


@njit(cache=True, error_model="numpy")
def friction_force(law, par, f_n, vt, z):
    """(ft, zdot): friction vector F_T_vec [N] and bristle rate z_dot [m/s], both 3-tuples.

    law: FrictionLaw code; par: (NPAR,); f_n: normal force [N] (>= 0); vt: tangential slip
    velocity of the ball relative to the socket [m/s] (3-tuple or array, tangent); z: LuGre
    bristle deflection [m] (zeros for other laws). The force on the ball is -ft (f.3); for
    Coulomb-type laws ft = mu(|vt|) f_n t_hat, so ft . vt >= 0. zdot is zero except for
    LuGre. |vt| = 0 gives ft = 0 (Coulomb-type) without NaN.
    """
    zero = (0.0, 0.0, 0.0)
    v = math.sqrt(dot(vt, vt))
    if law == _LUGRE:
        # h.4 (SOURCED scalar form, Canudas de Wit 1995; vector form DERIVED/PROPOSED):
        # z_dot = v_t - sigma0 |v_t| z / g(|v_t|);
        # F_T_vec = F_N (sigma0 z + sigma1(v) z_dot + sigma2 v_t)
        sigma0, sigma1, sigma2 = par[0], par[1], par[2]
        if par[7] != 0.0:  # sigma1(v) = sigma1 exp(-(v/v_d)^2) (Astrom & Canudas de Wit 2008)
            q = v / par[6]
            sigma1 = sigma1 * math.exp(-q * q)
        k = sigma0 * v / _lugre_g(par, v)
        zd = (vt[0] - k * z[0], vt[1] - k * z[1], vt[2] - k * z[2])
        ft = (
            f_n * (sigma0 * z[0] + sigma1 * zd[0] + sigma2 * vt[0]),
            f_n * (sigma0 * z[1] + sigma1 * zd[1] + sigma2 * vt[1]),
            f_n * (sigma0 * z[2] + sigma1 * zd[2] + sigma2 * vt[2]),
        )
        return ft, zd
    if law == _NONE or not v > 0.0:
        return zero, zero
    # Coulomb-type: F_T_vec = mu(|v_t|) F_N t_hat (h.1-h.3); t_hat = v_t/|v_t| is bounded
    ft_mag = friction_steady(law, par, v) * f_n
    return scale(ft_mag / v, (float(vt[0]), float(vt[1]), float(vt[2]))), zero
