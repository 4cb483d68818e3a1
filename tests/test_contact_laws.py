"""Contact and friction laws (physics.md g, h): formulas, invariants, restitution, energy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp
from scipy.special import gamma

import clearance as cl
from clearance.compile.calibration import hertz_stiffness, kelvin_voigt_damping, winkler_kf
from clearance.compile.laws import ContactGeometry, encode_friction, encode_normal
from clearance.contact.laws import (
    elastic_energy,
    friction_force,
    friction_steady,
    normal_force,
    step,
    winkler_fel,
    winkler_kn,
)
from clearance.kinds import NPAR, FrictionLaw, NormalLaw
from clearance.model.contact_laws import (
    ADAMS_IMPACT_STIFFNESS,
    FRICTION_LAWS,
    NORMAL_LAWS,
    STEEL,
    Coulomb,
    Flores,
    Hertz,
    HuGuo,
    Impact,
    KelvinVoigt,
    LuGre,
    Material,
    NoFriction,
    NonlinearStiffness,
    Stribeck,
    Threlfall,
    law_name,
    law_to_dict,
)
from clearance.model.errors import ModelError
from clearance.scenario.schema import parse_law

NL, FL = NormalLaw, FrictionLaw
DISSIPATIVE = (
    NL.HUNT_CROSSLEY,
    NL.LANKARANI_NIKRAVESH,
    NL.HERBERT_MCWHANNELL,
    NL.LEE_WANG,
    NL.ZHIYING_QISHAO,
    NL.GONTHIER,
    NL.FLORES,
    NL.HU_GUO,
)


def par(*values: float) -> np.ndarray:
    p = np.zeros(NPAR)
    p[: len(values)] = values
    return p


def fn(law, p, delta, ddot, ddm=0.1, c=3e-4):
    return normal_force(int(law), p, delta, ddot, ddm, c)


# ------------------------------------------------------------------ normal laws: formulas

K, DELTA, DDOT, DDM, CR = 1e10, 1e-5, 0.05, 0.1, 0.8
HERTZ_F = 1e10 * 1e-5**1.5  # 316.227766 N


@pytest.mark.parametrize(
    ("law", "factor"),
    [
        # 1 + xi(0.8) * 0.05/0.1, xi from the g.2 table written out with numbers
        (NL.HUNT_CROSSLEY, 1 + 0.5 * 3 * 0.2 / 2),
        (NL.LANKARANI_NIKRAVESH, 1 + 0.5 * 3 * 0.36 / 4),
        (NL.FLORES, 1 + 0.5 * 8 * 0.2 / 4.0),
        (NL.GONTHIER, 1 + 0.5 * 0.36 / 0.8),
        (NL.HU_GUO, 1 + 0.5 * 0.6 / 1.6),
        (NL.HERBERT_MCWHANNELL, 1 + 0.5 * 1.2 / 3.36),
        (NL.LEE_WANG, 1 + 0.5 * 0.15),
        (NL.ZHIYING_QISHAO, 1 + 0.5 * 0.27 * math.exp(0.4)),
    ],
)
def test_dissipative_family_values(law, factor):
    f, f_el = fn(law, par(K, 1.5, CR), DELTA, DDOT, DDM)
    assert f_el == pytest.approx(HERTZ_F, rel=1e-13)
    assert f == pytest.approx(HERTZ_F * factor, rel=1e-13)
    # restitution 1: no damping
    f1, _ = fn(law, par(K, 1.5, 1.0), DELTA, DDOT, DDM)
    assert f1 == pytest.approx(HERTZ_F, rel=1e-13)


def test_hertz_kelvin_voigt_impact_values():
    assert fn(NL.HERTZ, par(K, 1.5), DELTA, -5.0) == pytest.approx((HERTZ_F, HERTZ_F))
    assert fn(NL.HERTZ, par(2.0, 1.0), 0.25, 0.0) == pytest.approx((0.5, 0.5))
    # Kelvin-Voigt 1e7 * 1e-5 + 100 * 0.05, clamped when pulling
    assert fn(NL.KELVIN_VOIGT, par(1e7, 100.0), DELTA, DDOT) == pytest.approx((105.0, 100.0))
    assert fn(NL.KELVIN_VOIGT, par(1e7, 100.0), DELTA, -2.0) == (0.0, pytest.approx(100.0))
    # IMPACT: d = 1e-4, delta/d = 0.1: STEP = 1e4 * 0.1^2 (3 - 0.2) = 280 N s/m
    p = par(K, 1.5, 1e4, 1e-4)
    assert fn(NL.IMPACT, p, DELTA, DDOT) == pytest.approx((HERTZ_F + 280 * 0.05, HERTZ_F))
    f, _ = fn(NL.IMPACT, p, 2e-4, DDOT)  # beyond d: full cmax
    assert f == pytest.approx(1e10 * 2e-4**1.5 + 1e4 * 0.05, rel=1e-13)
    # damping vanishes at onset like 3 (delta/d)^2: no force jump even at 1 km/s
    assert fn(NL.IMPACT, p, 1e-12, 1e3)[0] == pytest.approx(1e-8 + 1e4 * 3e-16 * 1e3, rel=1e-7)


def test_winkler_forms_values():
    kf, R, c, cr = 1e13, 0.015, 3e-4, 0.8
    pi_r2_kf = math.pi * 0.015**2 * 1e13
    fel = pi_r2_kf * 1e-10 * (9e-4 + 2e-5) / (3 * (3.1e-4) ** 2)
    kn = pi_r2_kf * 1e-5 * (6 * 9e-8 + 6 * 3e-9 + 2e-10) / (3 * 3.1e-4**3)
    assert winkler_fel(kf, R, c, DELTA) == pytest.approx(fel, rel=1e-13)
    assert winkler_kn(kf, R, c, DELTA) == pytest.approx(kn, rel=1e-13)
    f1 = fn(NL.WINKLER_FORM1, par(kf, R, cr), DELTA, DDOT, DDM, c)
    assert f1 == pytest.approx((fel * 1.2, fel), rel=1e-13)  # Flores xi(0.8) = 0.4
    f2 = fn(NL.WINKLER_FORM2, par(kf, R, cr), DELTA, DDOT, DDM, c)
    assert f2 == pytest.approx((kn * 1e-5**1.5 * 1.2, kn * 1e-5**1.5), rel=1e-13)


def test_winkler_derivative_and_limits():
    kf, R, c = 1e13, 0.015, 3e-4
    for d in (1e-7, 1e-5, 3e-4, 2e-3):
        h = 1e-6 * d
        fd = (winkler_fel(kf, R, c, d + h) - winkler_fel(kf, R, c, d - h)) / (2 * h)
        assert fd == pytest.approx(winkler_kn(kf, R, c, d), rel=1e-8)
    # delta << c: F_el ~ pi R^2 k_f delta^2 / c (relative error ~ (4/3) delta/c)
    d = 1e-6 * c
    assert winkler_fel(kf, R, c, d) == pytest.approx(math.pi * R**2 * kf * d**2 / c, rel=2e-6)
    # c -> 0: F_el -> (2/3) pi R^2 k_f delta, K_n -> (2/3) pi R^2 k_f
    lin = 2 / 3 * math.pi * R**2 * kf
    assert winkler_fel(kf, R, 0.0, 1e-5) == pytest.approx(lin * 1e-5, rel=1e-14)
    assert winkler_fel(kf, R, 1e-15, 1e-5) == pytest.approx(lin * 1e-5, rel=1e-9)
    assert winkler_kn(kf, R, 1e-15, 1e-5) == pytest.approx(lin, rel=1e-9)


@pytest.mark.parametrize("form", [1, 2])
def test_winkler_calibration(form):
    k, R, c, d_ref = 1.326e11, 0.015, 3e-4, 4e-6
    kf = winkler_kf(k, R, c, d_ref, form=form)
    law = NL.WINKLER_FORM1 if form == 1 else NL.WINKLER_FORM2
    _, f_el = fn(law, par(kf, R, 0.9), d_ref, 0.0, 0.1, c)
    assert f_el == pytest.approx(k * d_ref**1.5, rel=1e-12)
    # the dataclass does the same with the internal Hertz K from the materials
    code, p = encode_normal(
        NonlinearStiffness(form=form, delta_ref=d_ref), ContactGeometry(R, R + c)
    )
    assert code == int(law)
    k_hertz = hertz_stiffness(207e9, 0.3, 207e9, 0.3, R, R + c)
    assert fn(code, p, d_ref, 0.0, 0.1, c)[1] == pytest.approx(k_hertz * d_ref**1.5, rel=1e-12)


ALL_PARS = {
    NL.HERTZ: par(K, 1.5),
    NL.KELVIN_VOIGT: par(1e7, 100.0),
    NL.IMPACT: par(K, 1.5, 1e4, 1e-4),
    NL.WINKLER_FORM1: par(1e13, 0.015, 0.8),
    NL.WINKLER_FORM2: par(1e13, 0.015, 0.8),
    **{law: par(K, 1.5, 0.3) for law in DISSIPATIVE},
}


@settings(max_examples=300, deadline=None)
@given(
    law=st.sampled_from(sorted(ALL_PARS)),
    delta=st.floats(-1e-3, 1e-3, allow_subnormal=False),
    ddot=st.floats(-1e3, 1e3, allow_subnormal=False),
    ddm=st.floats(1e-4, 10.0),
)
def test_normal_force_never_adhesive(law, delta, ddot, ddm):
    f, f_el = fn(law, ALL_PARS[law], delta, ddot, ddm)
    assert math.isfinite(f) and math.isfinite(f_el)
    assert f >= 0.0 and f_el >= 0.0
    if delta <= 0.0:
        assert (f, f_el) == (0.0, 0.0)


@pytest.mark.parametrize("law", sorted(ALL_PARS))
@pytest.mark.parametrize("c", [3e-4, 0.0])
def test_elastic_energy_is_integral_of_elastic_force(law, c):
    p = ALL_PARS[law]
    for delta in (1e-7, 1e-5, 2.9e-4, 3e-4, 3.1e-4, 1e-3, 0.05):
        if c == 0.0 and law == NL.WINKLER_FORM2:
            delta = min(delta, 1e-3)
        ref, _ = quad(lambda s: fn(law, p, s, 0.0, 0.1, c)[1], 0.0, delta, epsabs=0, epsrel=1e-13)
        assert elastic_energy(int(law), p, delta, c) == pytest.approx(ref, rel=1e-10)
    assert elastic_energy(int(law), p, -1e-5, c) == 0.0


def test_hertz_stiffness_table_g1():
    rows = [  # R_b [mm], c [mm], R* [m], K [N/m^1.5] (physics.md g.1, steel)
        (15.0, 0.30, 0.7650, 1.326e11),
        (10.0, 0.30, 0.3433, 8.886e10),
        (15.0, 0.10, 2.2650, 2.282e11),
        (20.0, 0.50, 0.8200, 1.373e11),
        (10.0, 0.50, 0.2100, 6.949e10),
        (10.0, 0.10, 1.0100, 1.524e11),
        (12.5, 0.20, 0.7937, 1.351e11),
    ]
    for rb_mm, c_mm, r_star, k_tab in rows:
        rb, rs = rb_mm * 1e-3, (rb_mm + c_mm) * 1e-3
        k = hertz_stiffness(207e9, 0.3, 207e9, 0.3, rb, rs)
        assert float(f"{k:.3e}") == k_tab
        # K = (4/3) E* sqrt(R*) with E* = 1.1374e11: recover R* to 4 digits
        r_star_k = (k / (4 / 3 * 207e9 / (2 * 0.91))) ** 2
        assert float(f"{r_star_k:.3e}") == pytest.approx(r_star, rel=1e-3)
        code, p = encode_normal(Flores(), ContactGeometry(rb, rs))
        assert p[0] == k and code == int(NL.FLORES)


# ------------------------------------------------------------------ STEP


def test_step_function():
    assert step(-1.0, 0.0, 2.0, 1.0, 5.0) == 2.0
    assert step(0.0, 0.0, 2.0, 1.0, 5.0) == 2.0
    assert step(1.0, 0.0, 2.0, 1.0, 5.0) == 5.0
    assert step(3.0, 0.0, 2.0, 1.0, 5.0) == 5.0
    assert step(0.5, 0.0, 2.0, 1.0, 5.0) == pytest.approx(3.5)
    assert step(0.25, 0.0, 0.0, 1.0, 1.0) == pytest.approx(0.15625)
    x = np.linspace(-0.5, 1.5, 2001)
    y = np.array([step(v, 0.0, 2.0, 1.0, 5.0) for v in x])
    assert np.all(np.diff(y) >= 0.0)
    h = 1e-7  # C1: zero slope at both ends (one-sided differences)
    assert (step(h, 0.0, 2.0, 1.0, 5.0) - 2.0) / h == pytest.approx(0.0, abs=1e-5)
    assert (5.0 - step(1.0 - h, 0.0, 2.0, 1.0, 5.0)) / h == pytest.approx(0.0, abs=1e-5)
    # decreasing step, as in IMPACT's STEP(x, x1 - d, cmax, x1, 0)
    assert step(0.75, 0.0, 1.0, 1.0, 0.0) == pytest.approx(1 - 0.84375)


# ------------------------------------------------------------------ 1-DOF impact


def impact(law, p, *, v=0.1, m=1.0, c=3e-4):
    """Return (restitution, delta_max, contact time) of a mass m hitting at speed v."""
    k_scale = p[0] if law != NL.KELVIN_VOIGT else 1e10
    dmax = (5 * m * v * v / (4 * k_scale)) ** 0.4

    def rhs(t, y):
        return (y[1], -fn(law, p, y[0], y[1], v, c)[0] / m)

    def separation(t, y):
        return y[0]

    def turning(t, y):
        return y[1]

    separation.terminal, separation.direction = True, -1.0
    turning.direction = -1.0
    sol = solve_ivp(
        rhs,
        (0.0, 100.0 * dmax / v),
        (0.0, v),
        method="DOP853",
        rtol=1e-10,
        atol=(1e-12 * dmax, 1e-12 * v),
        events=(separation, turning),
    )
    assert sol.status == 1
    return -sol.y_events[0][0][1] / v, sol.y_events[1][0][0], sol.t_events[0][0]


RESTITUTION_TABLE = {  # physics.md g.2, c_r = 0.3, 0.5, 0.7, 0.8, 0.9, 0.95
    NL.HUNT_CROSSLEY: (0.5813, 0.6630, 0.7680, 0.8329, 0.9090, 0.9524),
    NL.LANKARANI_NIKRAVESH: (0.6842, 0.7252, 0.7960, 0.8471, 0.9132, 0.9535),
    NL.HERBERT_MCWHANNELL: (0.5200, 0.5936, 0.7227, 0.8070, 0.9009, 0.9501),
    NL.LEE_WANG: (0.7390, 0.7992, 0.8693, 0.9090, 0.9524, 0.9756),
    NL.ZHIYING_QISHAO: (0.3267, 0.4826, 0.6796, 0.7874, 0.8959, 0.9489),
    NL.GONTHIER: (0.3042, 0.4877, 0.6696, 0.7680, 0.8764, 0.9359),
    NL.FLORES: (0.2562, 0.4704, 0.6832, 0.7885, 0.8939, 0.9468),
    NL.HU_GUO: (0.2707, 0.4877, 0.6973, 0.7992, 0.8999, 0.9500),
}
C_R = (0.3, 0.5, 0.7, 0.8, 0.9, 0.95)


@pytest.mark.parametrize("law", DISSIPATIVE)
def test_apparent_restitution_table_g2(law):
    # The table has 4 digits (rounding +-5e-5) and our integration is ~1e-9 accurate, so
    # 1e-4 is enough (measured worst 4.5e-5); it is 15x tighter than the brief's +-0.0015.
    for c_r, expected in zip(C_R, RESTITUTION_TABLE[law], strict=True):
        e, _, _ = impact(law, par(1e10, 1.5, c_r))
        assert e == pytest.approx(expected, abs=1e-4), (law.name, c_r)


def test_kelvin_voigt_restitution_clamped_and_unclamped():
    clamped = (0.3971, 0.5503, 0.7182, 0.8081, 0.9020, 0.9505)
    k_l, m = 1e7, 2.0
    for c_r, expected in zip(C_R, clamped, strict=True):
        d = kelvin_voigt_damping(k_l, m, c_r)
        e, _, _ = impact(NL.KELVIN_VOIGT, par(k_l, d), m=m)
        assert e == pytest.approx(expected, abs=1e-4)
        # unclamped oscillator: exp(-zeta pi / sqrt(1 - zeta^2)) = c_r exactly
        zeta = d / (2 * math.sqrt(m * k_l))
        assert math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)) == pytest.approx(c_r, 1e-12)


def test_hertz_impact_elastic_delta_max_and_contact_time():
    k, m, v = 1.33e11, 1.0, 0.1  # physics.md d.5
    e, dmax, tc = impact(NL.HERTZ, par(k, 1.5), v=v, m=m)
    assert e == pytest.approx(1.0, abs=1e-6)
    assert dmax == pytest.approx((5 * m * v * v / (4 * k)) ** 0.4, rel=1e-8)
    assert dmax == pytest.approx(6.2e-6, rel=0.01)
    # t_c = 2 (dmax/v) int_0^1 du / sqrt(1 - u^2.5) = 2.943 dmax / v
    const = 2 * gamma(1.4) * math.sqrt(math.pi) / gamma(0.9)
    assert const == pytest.approx(2.943, abs=5e-4)
    assert tc == pytest.approx(const * dmax / v, rel=1e-7)
    assert tc == pytest.approx(1.8e-4, rel=0.02)


# ------------------------------------------------------------------ friction

COULOMB_P = par(0.1, 1e-4, 1e-3)
STRIBECK_P = par(0.15, 0.1, 1e-3, 1e-2)
THRELFALL_P = par(0.1, 1e-3)
LUGRE_P = encode_friction(LuGre())[1]


def test_coulomb_ramps():
    mu = friction_steady
    assert mu(int(FL.COULOMB), COULOMB_P, 0.5e-4) == 0.0
    assert mu(int(FL.COULOMB), COULOMB_P, 1e-4) == pytest.approx(0.0, abs=1e-15)
    assert mu(int(FL.COULOMB), COULOMB_P, 5.5e-4) == pytest.approx(0.05)
    assert mu(int(FL.COULOMB), COULOMB_P, 3.25e-4) == pytest.approx(0.025)
    assert mu(int(FL.COULOMB), COULOMB_P, 1e-3) == pytest.approx(0.1)
    assert mu(int(FL.COULOMB), COULOMB_P, 1.0) == 0.1
    cub = int(FL.COULOMB_SMOOTH)
    assert mu(cub, COULOMB_P, 1e-4) == 0.0
    assert mu(cub, COULOMB_P, 5.5e-4) == pytest.approx(0.05)
    assert mu(cub, COULOMB_P, 3.25e-4) == pytest.approx(0.1 * 0.15625)  # D = 1/4
    assert mu(cub, COULOMB_P, 1e-3) == pytest.approx(0.1)
    assert encode_friction(Coulomb(ramp="cubic"))[0] == int(FL.COULOMB_SMOOTH)
    assert encode_friction(Coulomb())[0] == int(FL.COULOMB)


def test_threlfall_and_stribeck():
    th = int(FL.THRELFALL)
    assert friction_steady(th, THRELFALL_P, 1e-3) == pytest.approx(0.1 * 0.950213, rel=1e-6)
    assert friction_steady(th, THRELFALL_P, 1.0001e-3) == 0.1
    assert friction_steady(th, THRELFALL_P, 0.0) == 0.0
    sb = int(FL.STRIBECK)
    # h.3: the upper half of the symmetric cubic, 0.6875 at v_s/2 (not 0.5)
    assert friction_steady(sb, STRIBECK_P, 0.5e-3) == pytest.approx(0.6875 * 0.15)
    assert friction_steady(sb, STRIBECK_P, 1e-3) == pytest.approx(0.15)
    assert friction_steady(sb, STRIBECK_P, 5.5e-3) == pytest.approx(0.125)
    assert friction_steady(sb, STRIBECK_P, 1e-2) == pytest.approx(0.1)
    assert friction_steady(sb, STRIBECK_P, 5.0) == pytest.approx(0.1)
    assert friction_steady(sb, STRIBECK_P, 0.0) == 0.0


COULOMB_TYPE = {
    FL.NONE: par(),
    FL.COULOMB: COULOMB_P,
    FL.COULOMB_SMOOTH: COULOMB_P,
    FL.THRELFALL: THRELFALL_P,
    FL.STRIBECK: STRIBECK_P,
}
speed = st.one_of(st.just(0.0), st.floats(-1.0, 1.0), st.floats(-1e-3, 1e-3))


@settings(max_examples=300, deadline=None)
@given(
    law=st.sampled_from(sorted(COULOMB_TYPE)), vx=speed, vy=speed, vz=speed, f_n=st.floats(0.0, 1e5)
)
def test_coulomb_type_friction_dissipates(law, vx, vy, vz, f_n):
    p = COULOMB_TYPE[law]
    vt = (vx, vy, vz)
    ft, zd = friction_force(int(law), p, f_n, vt, (0.0, 0.0, 0.0))
    assert all(math.isfinite(x) for x in ft) and zd == (0.0, 0.0, 0.0)
    assert np.dot(ft, vt) >= 0.0  # D_t rate F_T_vec . v_t >= 0 (physics.md j)
    v = math.sqrt(np.dot(vt, vt))
    assert math.hypot(*ft) == pytest.approx(
        friction_steady(int(law), p, v) * f_n, rel=1e-12, abs=1e-200
    )
    assert np.allclose(np.cross(ft, vt), 0.0, atol=1e-12 * (1.0 + f_n))


def test_friction_zero_slip_and_direction():
    for law, p in COULOMB_TYPE.items():
        ft, _ = friction_force(int(law), p, 10.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        assert ft == (0.0, 0.0, 0.0)
    ft, _ = friction_force(
        int(FL.COULOMB), COULOMB_P, 10.0, np.array([0.0, 0.3, 0.4]), (0.0, 0.0, 0.0)
    )
    assert ft == pytest.approx((0.0, 0.6, 0.8))  # F_T_vec = mu F_N t_hat, along +v_t
    ft, zd = friction_force(int(FL.LUGRE), LUGRE_P, 10.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert ft == (0.0, 0.0, 0.0) and zd == (0.0, 0.0, 0.0)


def lugre_run(p, vt_of_t, t_end, *, f_n=1.0):
    """Integrate z' = zdot(vt(t), z) from z = 0 and the friction impulse along t_hat."""

    def rhs(t, y):
        vt = vt_of_t(t)
        ft, zd = friction_force(int(FL.LUGRE), p, f_n, vt, (y[0], y[1], y[2]))
        v = math.sqrt(np.dot(vt, vt))
        ss = f_n * friction_steady(int(FL.LUGRE), p, v)
        return (zd[0], zd[1], zd[2], np.dot(ft, vt) / v - ss)

    return solve_ivp(
        rhs,
        (0.0, t_end),
        np.zeros(4),
        method="Radau",
        rtol=1e-11,
        atol=(1e-18, 1e-18, 1e-18, 1e-16),
        dense_output=True,
    )


@pytest.mark.parametrize("v", [1e-4, 1e-3, 1e-2, 1e-1])
@pytest.mark.parametrize("vdamp", [True, False])
def test_lugre_steady_state_is_stribeck_curve(v, vdamp):
    p = encode_friction(LuGre(velocity_damping=vdamp))[1]
    t_hat = np.array([0.6, 0.0, 0.8])
    vt = tuple(v * t_hat)
    g = 0.1 + 0.05 * math.exp(-((v / 1e-3) ** 2))
    tau = g / (1e5 * v)
    sol = lugre_run(p, lambda t: vt, 40 * tau)
    z = sol.y[:3, -1]
    ft, _ = friction_force(int(FL.LUGRE), p, 2.0, vt, tuple(z))
    assert np.linalg.norm(ft) == pytest.approx(2.0 * (g + 0.4 * v), rel=1e-6)
    assert np.linalg.norm(np.cross(z, t_hat)) <= 1e-9 * np.linalg.norm(z)


def test_lugre_bristle_stays_in_plane_of_slip():
    p = LUGRE_P
    a, b = np.array([1.0, 2.0, 2.0]) / 3.0, np.array([2.0, 1.0, -2.0]) / 3.0
    n = np.cross(a, b)

    def vt(t):
        return tuple(1e-2 * (math.cos(300 * t) * a + math.sin(300 * t) * b))

    sol = lugre_run(p, vt, 0.02)
    z = sol.y[:3]
    assert np.max(np.abs(n @ z)) <= 1e-10 * np.max(np.linalg.norm(z, axis=0))
    assert np.max(np.linalg.norm(z, axis=0)) > 1e-7


def test_lugre_onset_transient_velocity_damping():
    # h.4 warning: a contact starting to slide at 0.1 m/s with z = 0 gets an excess impulse
    # J = sigma1(v) z_ss - sigma0 z_ss tau (z_ss = g/sigma0, tau = g/(sigma0 v)), F_N = 1
    v, g, s0, s1 = 0.1, 0.1, 1e5, 316.0
    tau = g / (s0 * v)
    vt = (0.0, v, 0.0)
    res = {}
    for vdamp in (False, True):
        p = encode_friction(LuGre(velocity_damping=vdamp))[1]
        sol = lugre_run(p, lambda t, vt=vt: vt, 60 * tau)
        res[vdamp] = sol.y[3, -1]
        ft0, _ = friction_force(int(FL.LUGRE), p, 1.0, vt, (0.0, 0.0, 0.0))
        res[(vdamp, "mu0")] = ft0[1]
    j_const = s1 * g / s0 - g * tau
    assert res[False] == pytest.approx(j_const, rel=1e-4)  # 3.15e-4 N s per N of F_N
    assert res[True] == pytest.approx(-g * tau, rel=1e-3)  # -1e-6 N s
    assert abs(res[True]) < 0.01 * res[False]
    assert res[(False, "mu0")] == pytest.approx(s1 * v + 0.4 * v)  # apparent mu 31.6
    assert res[(True, "mu0")] == pytest.approx(0.4 * v, rel=1e-6)


# ------------------------------------------------------------------ dataclasses, registry


@pytest.mark.parametrize(
    ("make", "field", "value"),
    [
        (lambda: Flores(restitution=0.0), "restitution", 0.0),
        (lambda: HuGuo(restitution=1.2), "restitution", 1.2),
        (lambda: Hertz(stiffness=-1.0), "stiffness", -1.0),
        (lambda: Flores(exponent=float("nan")), "exponent", "nan"),
        (lambda: Material(E=0.0, nu=0.3), "E", 0.0),
        (lambda: Material(E=1e9, nu=0.7), "nu", 0.7),
        (lambda: Impact(penetration_depth=0.0), "penetration_depth", 0.0),
        (lambda: KelvinVoigt(stiffness=True), "stiffness", True),
        (lambda: NonlinearStiffness(form=3), "form", 3),
        (lambda: NonlinearStiffness(k_f=1e13, delta_ref=1e-6), "delta_ref", 1e-6),
        (lambda: Coulomb(v0=1e-3, v1=1e-4), "v1", 1e-4),
        (lambda: Coulomb(ramp="smooth"), "ramp", "smooth"),
        (lambda: Threlfall(v0=0.0), "v0", 0.0),
        (lambda: Stribeck(v_s=1e-2, v_tr=1e-3), "v_tr", 1e-3),
        (lambda: LuGre(mu_c=0.0), "mu_c", 0.0),
        (lambda: LuGre(velocity_damping=1), "velocity_damping", 1),
        (
            lambda: encode_normal(KelvinVoigt(1e8), ContactGeometry(0.01, 0.0101)),
            "effective_mass",
            None,
        ),
        (lambda: encode_normal(Flores(), ContactGeometry(0.01, 0.01)), "R_socket", 0.01),
    ],
)
def test_validation_errors_name_field_and_value(make, field, value):
    with pytest.raises(ModelError) as err:
        make()
    assert err.value.field == field
    assert f"'{field}'" in str(err.value)
    assert str(value) in str(err.value)


def test_encode_defaults():
    rb, rs = 0.015, 0.0153
    code, p = encode_normal(Impact(), ContactGeometry(rb, rs))
    assert code == int(NL.IMPACT) and p.shape == (NPAR,)
    assert p[:4] == pytest.approx((ADAMS_IMPACT_STIFFNESS, 1.5, 1e4, 1e-4))
    assert ADAMS_IMPACT_STIFFNESS == pytest.approx(3.162e9, rel=1e-4)
    k = hertz_stiffness(207e9, 0.3, 207e9, 0.3, rb, rs)
    assert encode_normal(Impact(stiffness=None), ContactGeometry(rb, rs))[1][0] == k
    assert k / ADAMS_IMPACT_STIFFNESS == pytest.approx(42, abs=0.5)  # "42x softer" (g.4)
    soft = Material(70e9, 0.33)
    k2 = encode_normal(Hertz(), ContactGeometry(rb, rs, outer_material=soft))[1][0]
    assert k2 == hertz_stiffness(207e9, 0.3, 70e9, 0.33, rb, rs) and STEEL.E == 207e9
    code, p = encode_normal(KelvinVoigt(1e8, restitution=0.5), ContactGeometry(rb, rs, m_eff=2.0))
    assert p[1] == pytest.approx(kelvin_voigt_damping(1e8, 2.0, 0.5))
    code, p = encode_friction(LuGre())
    assert code == int(FL.LUGRE)
    assert p.tolist() == [1e5, 316.0, 0.4, 0.1, 0.15, 1e-3, 1e-3, 1.0]
    assert encode_friction(LuGre(velocity_damping=False, v_d=2e-3))[1][6:].tolist() == [2e-3, 0.0]
    assert encode_friction(NoFriction())[0] == int(FL.NONE)
    assert encode_friction(Stribeck())[1][:4].tolist() == [0.15, 0.1, 1e-3, 1e-2]
    assert encode_friction(Threlfall())[1][:2].tolist() == [0.1, 1e-3]


def test_parse_law_and_round_trip():
    law = parse_law({"law": "flores", "restitution": 0.8}, "normal")
    assert law == Flores(restitution=0.8)
    assert parse_law({"law": "lugre", "mu_c": 0.05}, "friction") == LuGre(mu_c=0.05)
    for table, kind in ((NORMAL_LAWS, "normal"), (FRICTION_LAWS, "friction")):
        for name, cls in table.items():
            obj = cls(1e8) if cls is KelvinVoigt else cls()
            assert law_name(obj) == name  # one spelling in files, attributes and datasets
            assert parse_law(law_to_dict(obj), kind) == obj


@pytest.mark.parametrize(
    ("d", "field", "text"),
    [
        ({"law": "flor"}, "normal.law", "unknown law"),
        ({"restitution": 0.9}, "normal.law", "missing"),
        ({"law": "flores", "restituton": 0.9}, "normal.restituton", "did you mean 'restitution'"),
        ({"law": "kelvin_voigt"}, "normal.stiffness", "required"),
        (["flores"], "normal", "expected a table"),
    ],
)
def test_parse_law_errors(d, field, text):
    with pytest.raises(ModelError) as err:
        parse_law(d, "normal")
    assert err.value.field == field and text in str(err.value)
    with pytest.raises(ModelError, match="unknown law"):
        parse_law({"law": "viscous"}, "friction")
    with pytest.raises(ModelError, match="unknown key 'mu_s'"):
        parse_law({"law": "coulomb", "mu_s": 0.2}, "friction")


def test_deprecated_law_entry_points_warn_and_agree():
    """The model-level parsers and `encode` keep working (deprecated), with the new results."""
    from clearance.model import contact_laws as m

    with pytest.warns(DeprecationWarning):
        assert m.normal_law_from_dict({"law": "flores"}) == Flores()
    with pytest.warns(DeprecationWarning):
        assert m.friction_law_from_dict({"law": "lugre"}) == LuGre()
    with pytest.warns(DeprecationWarning):
        code, par = Flores().encode(R_ball=0.015, R_socket=0.0153)
    ref = encode_normal(Flores(), ContactGeometry(0.015, 0.0153))
    assert code == ref[0] and np.array_equal(par, ref[1])
    with pytest.warns(DeprecationWarning):
        assert encode_friction(LuGre())[0] == LuGre().encode()[0]


@pytest.mark.parametrize(
    "make,field,allowed",
    [
        (lambda: cl.LuGre(mu_c=0.2, mu_s=0.1), "mu_s", "mu_s >= mu_c = 0.2"),
        (lambda: cl.Stribeck(mu_s=0.05, mu_d=0.1), "mu_s", "mu_s >= mu_d = 0.1"),
        (lambda: cl.Coulomb(v0=1e-3, v1=1e-4), "v1", "must exceed v0"),
        (
            lambda: cl.Clearance(ball_radius=0.015, radial_clearance=0.015),
            "radial_clearance",
            "below ball_radius = 0.015 m",
        ),
        (
            lambda: cl.Clearance(ball_radius=0.015, socket_radius=0.04),
            "socket_radius",
            "below ball_radius",
        ),
        (
            lambda: cl.Clearance(ball_radius=0.015, socket_radius=0.015 + 1e-13),
            "socket_radius",
            "at least 1.5e-11 m",
        ),
        (
            lambda: cl.RevoluteClearance(journal_radius=0.01, radial_clearance=1e-30),
            "radial_clearance",
            "at least 1e-11 m (1e-09 of journal_radius",
        ),
        (
            lambda: cl.RevoluteClearance(journal_radius=0.01, radial_clearance=0.02),
            "radial_clearance",
            "below journal_radius",
        ),
    ],
)
def test_physical_relations_between_fields_are_checked(make, field, allowed):
    """Relations a single field cannot check: static friction at least the sliding level,
    the ramp's end above its start, a clearance gap below the radius it surrounds."""
    with pytest.raises(ModelError) as err:
        make()
    assert err.value.field == field and allowed in err.value.allowed


@pytest.mark.parametrize(
    "make,field",
    [
        (lambda: cl.Hertz(stiffness=10**400), "stiffness"),
        (lambda: cl.Clearance(ball_radius=10**400, radial_clearance=1e-4), "ball_radius"),
        (lambda: cl.Constant(10**400), "value"),
    ],
)
def test_an_int_beyond_a_float_is_refused_not_overflowed(make, field):
    """math.isfinite(10**400) raises OverflowError: every validator shares the one test
    (model.errors.finite_real) that calls it not finite."""
    with pytest.raises(ModelError) as err:
        make()
    assert err.value.field == field
