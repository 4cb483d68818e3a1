"""The cost estimate before a run (clearance.analysis.cost): its time scales against closed
forms, its step count against real runs, its warnings in `clearance check` and `run`."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from typer.testing import CliRunner

import clearance as cl
from clearance.analysis.cost import KAPPA, STABILITY, contact_scales, estimate_cost
from clearance.cli.main import app
from clearance.mechanisms.examples import double_pendulum
from clearance.model.contact_laws import Hertz, KelvinVoigt, LuGre, NoFriction

RB, C, M = 0.01, 1e-4, 2.0


def ball_in_socket(normal, friction=None, *, spin=(0.0, 0.0, 0.0)):
    """A 2 kg body hanging by a spherical clearance joint from the ground (a short rod: the
    ball sits in its socket under its weight)."""
    m = cl.Mechanism("ball in socket")
    m.add(
        cl.Body("rod", M, (0.002, 0.002, 0.0002), position=(0, 0, -0.05), angular_velocity=spin),
        cl.Marker("socket", "ground"),
        cl.Marker("ball", "rod", (0, 0, 0.05)),
        cl.Spherical(
            "S",
            "socket",
            "ball",
            clearance=cl.Clearance(
                ball_radius=RB,
                radial_clearance=C,
                normal=normal,
                friction=friction or NoFriction(),
            ),
        ),
    )
    return cl.compile_mechanism(m)


def scales(c, **kw):
    return {what.split(" of ")[0]: (rate, kind) for what, rate, kind in contact_scales(c, **kw)}


def test_hertz_contact_frequency_is_the_linearised_closed_form():
    """omega = sqrt(dF/ddelta / m) at the penetration where K delta^1.5 carries m a."""
    K, a = 1e10, 9.81
    c = ball_in_socket(Hertz(stiffness=K))
    s = scales(c, acceleration=a, slip_speed=0.01, approach_speed=0.01)
    delta = (M * a / K) ** (2 / 3)
    omega = math.sqrt(1.5 * K * math.sqrt(delta) / M)  # ground: m_eff = the body's mass
    rate, kind = s["the contact stiffness"]
    assert kind == "oscillation" and rate == pytest.approx(omega, rel=1e-5)
    assert s["the contact damping"][0] == 0.0  # Hertz has none


def test_kelvin_voigt_frequency_and_damping_rate():
    k, d = 2e7, 3e3
    c = ball_in_socket(KelvinVoigt(stiffness=k, damping=d))
    s = scales(c, acceleration=9.81, slip_speed=0.01, approach_speed=0.1)
    assert s["the contact stiffness"][0] == pytest.approx(math.sqrt(k / M), rel=1e-5)
    assert s["the contact damping"][0] == pytest.approx(d / M, rel=1e-5)


def test_lugre_bristle_rate_and_stiffness():
    """z_dot = v - sigma0 |v| z / g(v): decay rate sigma0 v / g(v); the bristles are a
    spring sigma0 F_N on the body: omega = sqrt(sigma0 m a / m), and a damper sigma1 F_N."""
    law = LuGre(sigma0=1e6, mu_c=0.1, mu_s=0.15, v_s=1e-3)
    c = ball_in_socket(Hertz(stiffness=1e10), law)
    v, a = 0.02, 9.81
    s = scales(c, acceleration=a, slip_speed=v, approach_speed=0.01)
    g = 0.1 + 0.05 * math.exp(-((v / 1e-3) ** 2))
    assert s["the LuGre bristles"][0] == pytest.approx(1e6 * v / g, rel=1e-9)
    assert s["the LuGre bristle stiffness"][0] == pytest.approx(math.sqrt(1e6 * a), rel=1e-9)
    # sticking, F_N sigma1 z_dot is a damper sigma1 F_N on the body: rate sigma1 m a / m
    assert s["the LuGre bristle damping"][0] == pytest.approx(316.0 * a, rel=1e-9)


def test_coulomb_ramp_is_a_viscous_slope():
    """mu(v) rising from 0 to mu over [v0, v1]: a damping rate F mu / ((v1 - v0) m)."""
    c = ball_in_socket(Hertz(stiffness=1e10), cl.Coulomb(mu=0.2, v0=1e-4, v1=1e-3))
    s = scales(c, acceleration=9.81, slip_speed=0.01, approach_speed=0.01)
    want = M * 9.81 * 0.2 / (1e-3 - 1e-4) / M
    assert s["the friction slope"][0] == pytest.approx(want, rel=0.02)  # (a sampled slope)


def test_baumgarte_rate_sets_the_step_of_a_stiff_stabilisation():
    c = cl.compile_mechanism(double_pendulum())
    e = estimate_cost(c, 1.0, baumgarte=(1e6, 5.0), rhs_seconds=1e-5)
    assert "Baumgarte" in e.limit
    lam = 1e6 + math.sqrt(1e12 - 25.0)
    assert e.step == pytest.approx(STABILITY / lam) and e.steps == pytest.approx(lam / STABILITY)
    assert e.wall == pytest.approx(e.steps * 6.5 * 1e-5)


def test_rk4_steps_are_counted_exactly():
    c = ball_in_socket(Hertz(stiffness=1e10))
    e = estimate_cost(c, 0.5, method="rk4", step=1e-5, rhs_seconds=1e-5)
    assert e.steps == pytest.approx(5e4) and e.wall == pytest.approx(5e4 * 4 * 1e-5)


@pytest.mark.parametrize("K", [1e9, 1e11])
def test_estimate_is_of_the_order_of_the_real_count_in_persistent_contact(K):
    """The ball resting in its socket at its static penetration, spinning: the estimate
    (omega from the static load, contact all the time) within a factor 2 of the steps
    taken (1.4 and 1.7 measured: the estimate is not a bound)."""
    c = ball_in_socket(Hertz(stiffness=K), spin=(0.0, 0.0, 3.0))
    y0 = cl.initial_state(c)
    y0[2] -= C + (M * 9.81 / K) ** (2 / 3)  # the ball on the bottom of its socket
    r = cl.simulate(c, 0.2, dt_out=1e-3, y0=y0, assemble_positions=False)
    assert r.success and np.all(r.contact_force("S") > 0)
    taken = r.stats["naccept"] + r.stats["nreject"]
    e = estimate_cost(c, 0.2, rhs_seconds=1e-5)
    assert "contact stiffness" in e.limit
    assert taken / 2 < e.steps < 2 * taken, (taken, e.steps)
    omega = math.sqrt(1.5 * K * math.sqrt((M * 9.81 / K) ** (2 / 3)) / M)
    assert e.steps == pytest.approx(0.2 * omega / (KAPPA * 1e-6**0.2), rel=1e-4)


def test_pace_warns_once_about_a_run_that_will_take_very_long():
    from clearance.pipeline import _Pace

    said = []
    pace = _Pace(said.append, 2.0)
    pace(0.001)  # before `after` seconds: no judgement yet
    assert said == []
    pace.t0 -= 10.0  # 10 s for 1 ms of 2 s: ~5.5 h left
    pace(0.001)
    pace(0.002)
    assert len(said) == 1 and "needs ~5.6 h more" in said[0] and "max_wall_time" in said[0]
    quick = _Pace(said.append, 2.0)
    quick.t0 -= 10.0
    quick(1.0)  # 10 s more: no warning
    assert len(said) == 1


def scenario(tmp_path, **subs):
    from clearance.scenario import default_scenario_path

    text = default_scenario_path().read_text(encoding="utf-8")
    for key, value in subs.items():
        text = re.sub(rf"^{key}\s*=.*$", f"{key} = {value}", text, flags=re.M)
    p = tmp_path / "s.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_check_estimates_the_clearance_run_and_warns(tmp_path):
    r = CliRunner().invoke(app, ["check", str(scenario(tmp_path))])
    assert r.exit_code == 0, r.output
    m = re.search(r"estimated clearance run: about ([0-9.e+]+) steps", r.output)
    assert m and 3e3 < float(m.group(1)) < 3e4  # the default takes 7181
    assert "warning" not in r.output
    r = CliRunner().invoke(app, ["check", str(scenario(tmp_path, baumgarte_alpha="1e9"))])
    assert r.exit_code == 0, r.output  # valid, but:
    assert "warning: the estimated 1.2e+09 steps exceed [solver] max_steps" in r.output
    assert "Baumgarte stabilisation (alpha 1e+09" in r.output
    assert re.search(r"warning: this run may take ~[0-9.]+ (h|days)", r.output)


def test_rk4_gets_no_step_budget_warning():
    """rk4 has no max_steps: 2e5 fixed steps with max_steps = 1e5 is not 'stopping early'."""
    from types import SimpleNamespace

    from clearance.pipeline import cost_warnings

    c = ball_in_socket(Hertz(stiffness=1e10))
    est = estimate_cost(c, 2.0, method="rk4", step=1e-5, rhs_seconds=1e-9)
    kw = {"method": "rk4", "max_steps": 100_000}
    assert cost_warnings(est, SimpleNamespace(simulate_kwargs=kw)) == []
    kw = {"method": "dopri5", "max_steps": 100_000}
    assert "exceed [solver] max_steps" in cost_warnings(est, SimpleNamespace(simulate_kwargs=kw))[0]


@pytest.mark.parametrize("method", ["dopri5", "tsit5", "dop853", "vern7"])
def test_stability_boundaries_match_the_tableaux(method):
    """The real stability boundary the estimate uses against the method's stability
    function R(z) = 1 + z b^T (I - z A)^-1 1 from its tableau (the first x > 0 with
    |R(-x)| > 1, on a grid of 1e-3). HIGHER_ORDER's: to 0.01 (measured dop853 6.394,
    vern7 4.640). STABILITY (3.3) serves both 5(4) pairs: DOPRI5's (3.307), conservative
    for Tsit5 (3.507)."""
    from clearance.analysis.cost import HIGHER_ORDER
    from clearance.integrate.methods import METHODS

    A = METHODS[method].data[0]
    b = METHODS[method].data[2] if method in HIGHER_ORDER else A[6]  # (5(4): A's last row)
    s = b.shape[0]
    A = A[:s, :s]

    def R(z):
        return 1.0 + z * b @ np.linalg.solve(np.eye(s) - z * A, np.ones(s))

    xs = np.arange(0.0, 10.0, 1e-3)
    bound = xs[np.argmax([abs(R(-x)) > 1.0 + 1e-12 for x in xs])]
    if method in HIGHER_ORDER:
        assert abs(bound - HIGHER_ORDER[method][2]) < 0.01, bound
    else:
        assert STABILITY <= bound < 1.07 * STABILITY, bound
