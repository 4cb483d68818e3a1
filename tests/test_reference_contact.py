"""The plain-NumPy clearance joint (clearance.dynamics.reference_contact) against the compiled
kernel: a second implementation of physics.md f/g.2/h.4 as an oracle, on random states in
and out of contact, with and without the latched impact velocity."""

import numpy as np
import pytest

import clearance as cl
from clearance.compile.compiled import compile_mechanism
from clearance.dynamics.reference_contact import (
    clearance_joints,
    contact_state_update,
    reference_rhs_clearance,
    solve_ivp_clearance,
)
from clearance.dynamics.rhs import make_work, rhs
from clearance.model.clearance import Clearance
from clearance.model.contact_laws import Hertz, HuntCrossley, LuGre, NoFriction
from clearance.scenario import build_mechanisms, default_scenario_path, load_scenario

ALPHA, BETA = 5.0, 5.0
RTOL = 1e-9


def _rot(p):
    p = p / np.linalg.norm(p)
    e0, e = p[0], p[1:]
    et = np.array([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
    return (e0**2 - e @ e) * np.eye(3) + 2 * (np.outer(e, e) + e0 * et)


@pytest.fixture(scope="module")
def scenario():
    """The default 4UPS-UPU scenario's clearance mechanism (two joints, Flores + LuGre);
    drives held at the home lengths (the right-hand side does not care)."""
    _, clr, _ = build_mechanisms(load_scenario(default_scenario_path()))
    c = compile_mechanism(clr)
    return clr, c, cl.initial_state(c)


def _pendulum(normal, friction):
    """A rod on a ground socket (socket = marker j, on the ground) plus a revolute-jointed
    second link: ground-side socket, the other socket assignment, another law pair."""
    m = cl.Mechanism("pend", gravity=(0, 0, -9.81))
    m.add(
        cl.Body("rod", 1.2, (0.01, 0.012, 0.002), position=(0, 0, -0.2)),
        cl.Body("link", 0.5, (0.002, 0.003, 0.001), position=(0.1, 0, -0.4)),
        cl.Marker("ball", "rod", (0, 0, 0.2)),
        cl.Marker("sock", "ground", (0, 0, 0)),
        cl.Marker.on_axis("r_end", "rod", (0, 0, -0.2), axis=(0, 1, 0)),
        cl.Marker.on_axis("l_end", "link", (-0.1, 0, 0), axis=(0, 1, 0)),
        cl.Spherical(
            "S",
            "ball",
            "sock",
            clearance=Clearance(
                ball_radius=0.01,
                radial_clearance=0.2e-3,
                socket="j",
                normal=normal,
                friction=friction,
            ),
        ),
        cl.Revolute("R", "r_end", "l_end"),
    )
    c = compile_mechanism(m)
    return m, c, cl.initial_state(c)


def _place(mech, c, y, k, delta, rng):
    """Move the ball body of clearance joint k so that its penetration is delta [m], in a
    random direction (constraints are violated on purpose: Baumgarte covers it)."""
    cj = clearance_joints(mech)[k]
    ms, mb = mech.markers[cj.socket_marker], mech.markers[cj.ball_marker]
    names = list(mech.bodies)

    def centre(mk):
        if mk.body == "ground":
            return np.array(mk.position, float)
        i = names.index(mk.body)
        return y[7 * i : 7 * i + 3] + _rot(y[7 * i + 3 : 7 * i + 7]) @ np.array(mk.position)

    n = rng.standard_normal(3)
    n /= np.linalg.norm(n)
    i = names.index(mb.body)
    A = _rot(y[7 * i + 3 : 7 * i + 7])
    y[7 * i : 7 * i + 3] = centre(ms) + (cj.c + delta) * n - A @ np.array(mb.position)


def _random_state(mech, c, y0, rng, deltas):
    y = y0.copy()
    nb = c.nb
    y[7 * nb : 13 * nb] += 0.05 * rng.standard_normal(6 * nb)
    for k, d in enumerate(deltas):
        _place(mech, c, y, k, d, rng)
    y[c.iz : c.iw] = 1e-6 * rng.standard_normal(3 * c.nclr)
    return y


def _compiled(c, t, y, in_contact, ddm):
    wk = make_work(c.model)
    cs = cl.contact_state(c)
    cs.flag[:] = np.asarray(in_contact, dtype=np.int64)
    cs.ddm[:] = ddm
    out = np.empty_like(y)
    assert rhs(t, y, c.model, wk, cs, ALPHA, BETA, 0, out) == 0
    return out, wk.lam.copy()


def _close(a, b):
    return np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300)


DELTAS = [(-1e-4, -5e-5), (1e-6, -2e-5), (-3e-5, 4e-6), (2e-5, 1e-6), (3e-7, 1e-5)]


@pytest.mark.parametrize("case", range(len(DELTAS)))
def test_scenario_unlatched_equals_scipy_rhs(scenario, case):
    """Before the impact velocity is latched (in_contact False): NumPy == scipy_rhs with an
    explicit (unlatched) contact state."""
    mech, c, y0 = scenario
    deltas = DELTAS[case]
    rng = np.random.default_rng(case)
    f = cl.scipy_rhs(c, baumgarte=(ALPHA, BETA), solver="schur", contact_state=cl.contact_state(c))
    for _ in range(3):
        y = _random_state(mech, c, y0, rng, deltas)
        t = float(rng.uniform(0, 2))
        yd_ref, _ = reference_rhs_clearance(mech, t, y, alpha=ALPHA, beta=BETA)
        yd = f(t, y)
        assert _close(yd, yd_ref) < RTOL
        # contact terms present exactly for the penetrating joints
        for k, d in enumerate(deltas):
            dn = yd_ref[c.layout.idn + k]
            z_rate = yd_ref[c.iz + 3 * k : c.iz + 3 * k + 3]
            assert (np.any(z_rate != 0.0) or dn != 0.0) == (d > 0)


@pytest.mark.parametrize("case", range(1, len(DELTAS)))
def test_scenario_latched_equals_kernel(scenario, case):
    """With the discrete state latched (in_contact True, delta_dot_minus given)."""
    mech, c, y0 = scenario
    deltas = DELTAS[case]
    rng = np.random.default_rng(100 + case)
    for _ in range(3):
        y = _random_state(mech, c, y0, rng, deltas)
        t = float(rng.uniform(0, 2))
        flags = np.array([d > 0 for d in deltas])
        ddm = rng.uniform(1e-4, 0.05, size=len(deltas))
        yd_ref, lam_ref = reference_rhs_clearance(
            mech, t, y, alpha=ALPHA, beta=BETA, in_contact=flags, delta_dot_minus=ddm
        )
        yd, lam = _compiled(c, t, y, flags, ddm)
        assert _close(yd, yd_ref) < RTOL
        assert _close(lam, lam_ref) < RTOL


@pytest.mark.parametrize(
    "normal, friction",
    [
        (HuntCrossley(restitution=0.7), LuGre(velocity_damping=False, mu_c=0.2, mu_s=0.3)),
        (Hertz(stiffness=5e10), NoFriction()),
    ],
)
def test_ground_socket_other_laws(normal, friction):
    """Socket on the ground, socket = marker j, other laws; in and out of contact."""
    mech, c, y0 = _pendulum(normal, friction)
    rng = np.random.default_rng(3)
    for d, flag in [(-1e-5, False), (5e-6, False), (5e-6, True), (2e-5, True)]:
        y = _random_state(mech, c, y0, rng, [d])
        yd_ref, lam_ref = reference_rhs_clearance(
            mech, 0.1, y, alpha=ALPHA, beta=BETA, in_contact=[flag], delta_dot_minus=[0.02]
        )
        yd, lam = _compiled(c, 0.1, y, [flag], [0.02])
        assert _close(yd, yd_ref) < RTOL
        assert _close(lam, lam_ref) < RTOL


def test_contact_state_update_and_solve_ivp():
    """Onset latches max(delta_dot, floor); a short solve_ivp run through two impacts
    matches the compiled DOPRI5 (different event handling: first-order capture vs located
    events, so only to the integration accuracy)."""
    mech, c, y0 = _pendulum(HuntCrossley(restitution=0.7), LuGre())
    y = y0.copy()
    rng = np.random.default_rng(5)
    _place(mech, c, y, 0, 1e-6, rng)
    flags, ddm = np.zeros(1, bool), np.zeros(1)
    assert contact_state_update(mech, y, flags, ddm)
    assert flags[0] and ddm[0] >= 1e-4
    # free fall of the rod into the socket wall (no initial contact), through the impact
    t_end = 0.02
    r = cl.simulate(c, t_end, rtol=1e-8, atol=1e-11, baumgarte=(ALPHA, BETA), t_out=[0, t_end])
    assert r.status == 0 and r.stats["nevents"] >= 1
    sol = solve_ivp_clearance(mech, (0, t_end), y0, alpha=ALPHA, beta=BETA, rtol=1e-8, atol=1e-11)
    assert sol.success
    yq = sol.y[: c.nq, -1]
    assert np.max(np.abs(yq - r.q[-1])) < 1e-6  # measured 1.2e-8 m (two impacts)
