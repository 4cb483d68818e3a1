"""Integrators: own DOPRI5 (and Tsit5, test_tsit5.py) against scipy's solve_ivp on the same
compiled right-hand side,
convergence orders from log-log fits (RK4: 4, DOPRI5 at fixed steps: 5, DOPRI5 global error
proportional to the tolerance), and partial results on failure.

Test problem: the spatial double pendulum (`clearance.mechanisms.examples.double_pendulum`,
spherical joints, 3-D initial velocities, Baumgarte 5/5), whose state y = [q | v | work]
has 14 + 12 + 3 entries.
"""

from __future__ import annotations

import numpy as np
import pytest
from models import rod_on_clearance_joint
from scipy.integrate import solve_ivp

import clearance as cl
from clearance.integrate.methods import METHODS
from clearance.mechanisms.examples import double_pendulum, spatial_pendulum

T_END = 1.0
BAUMGARTE = (5.0, 5.0)


@pytest.fixture(scope="module")
def compiled() -> cl.Compiled:
    return cl.compile_mechanism(double_pendulum())


@pytest.fixture(scope="module")
def reference(compiled):
    """y(T_END) from scipy DOP853 at rtol 1e-13 (an independent integrator and controller)."""
    f = cl.scipy_rhs(compiled, baumgarte=BAUMGARTE)
    y0 = cl.initial_state(compiled)
    sol = solve_ivp(f, (0.0, T_END), y0, method="DOP853", rtol=1e-13, atol=1e-15)
    assert sol.success
    return sol.y[:, -1]


def _qv(c: cl.Compiled, r: cl.Result) -> np.ndarray:
    """Final q and v (the work integrals are checked separately)."""
    return np.concatenate([r.q[-1], r.v[-1]])


def _slope(h, err) -> float:
    return float(np.polyfit(np.log(h), np.log(err), 1)[0])


# ---------------------------------------------------------------------------- vs scipy
@pytest.mark.parametrize("pair", ["dopri5", "tsit5"])
@pytest.mark.parametrize(("method", "rtol"), [("DOP853", 1e-10), ("Radau", 1e-10)])
def test_dopri5_matches_solve_ivp(compiled, method, rtol, pair):
    """Same compiled rhs, same initial state: own DOPRI5 / Tsit5 (rtol 1e-10) vs scipy's
    DOP853 (explicit, 8th order) and Radau (implicit, 5th order)."""
    c = compiled
    t_end = 2.0
    t_eval = np.linspace(0.0, t_end, 41)
    y0 = cl.initial_state(c)
    sol = solve_ivp(
        cl.scipy_rhs(c, baumgarte=BAUMGARTE),
        (0.0, t_end),
        y0,
        method=method,
        rtol=rtol,
        atol=1e-2 * rtol,
        t_eval=t_eval,
    )
    assert sol.success
    r = cl.simulate(
        c, t_end, t_out=t_eval, method=pair, rtol=1e-10, atol=1e-12, baumgarte=BAUMGARTE
    )
    assert r.success, r.message
    ys = sol.y.T
    n = c.nq + c.nv
    own = np.hstack([r.q, r.v])
    # Measured: final state 2.6e-10, all 41 samples (own dense output) 9e-10, work integral
    # W_c 1e-10 for both oracles (Tsit5: 1.1e-10, 3e-10, 1.1e-10). 1e-8 leaves 10x over the
    # dense-output error.
    assert np.max(np.abs(own[-1] - ys[-1, :n])) < 1e-8
    assert np.max(np.abs(own - ys[:, :n])) < 1e-8
    assert np.max(np.abs(r.energy["work_constraints"] - ys[:, n])) < 1e-8
    # the motion is far from trivial over the window
    assert np.max(np.abs(own[-1] - own[0])) > 0.5


def test_scipy_rhs_is_the_simulated_ode(compiled):
    """Result.a (post-processed v_dot) equals the v part of scipy_rhs at the saved states."""
    c = compiled
    r = cl.simulate(c, 0.5, dt_out=0.05, rtol=1e-8)
    f = cl.scipy_rhs(c, baumgarte=BAUMGARTE)
    for k in range(r.t.size):
        y = np.concatenate([r.q[k], r.v[k], np.zeros(c.ny - c.nq - c.nv)])  # z, work: unused
        np.testing.assert_allclose(f(r.t[k], y)[c.nq : c.nq + c.nv], r.a[k], rtol=0, atol=1e-12)


# ---------------------------------------------------------------------------- orders
def test_rk4_order_four(compiled, reference):
    c = compiled
    hs = np.array([0.02, 0.01, 0.005, 0.0025])
    err = []
    for h in hs:
        r = cl.simulate(c, T_END, t_out=np.array([T_END]), method="rk4", step=h)
        assert r.success and r.stats["naccept"] == round(T_END / h)
        err.append(np.max(np.abs(_qv(c, r) - reference[: c.nq + c.nv])))
    err = np.array(err)
    # errors 1.1e-4 .. 3.0e-8, far above the reference's (~1e-13); pairwise orders measured
    # 3.88, 3.95, 3.98
    assert err[-1] > 1e3 * 1e-13 and np.all(np.diff(err) < 0)
    slope = _slope(hs, err)
    assert 3.7 < slope < 4.3, (slope, err)


def test_dopri5_global_error_proportional_to_tolerance(compiled, reference):
    """With the PI controller the global error scales ~ rtol (Hairer & Wanner I, II.4):
    measured 1.5e-5 .. 7.8e-10 for rtol 1e-5 .. 1e-9, slope 1.07."""
    c = compiled
    tols = np.array([1e-5, 1e-6, 1e-7, 1e-8, 1e-9])
    err, steps = [], []
    for tol in tols:
        r = cl.simulate(c, T_END, t_out=np.array([T_END]), rtol=tol, atol=1e-2 * tol)
        err.append(np.max(np.abs(_qv(c, r) - reference[: c.nq + c.nv])))
        steps.append(r.stats["naccept"])
    err = np.array(err)
    slope = _slope(tols, err)
    assert 0.8 < slope < 1.3, (slope, err)
    assert np.all(err < 100.0 * tols)  # the tolerance means something in absolute terms
    # work grows like tol^(-1/5) for a 5th-order method: 10^4 in tol -> ~6x the steps
    assert 3.0 < steps[-1] / steps[0] < 12.0, steps


@pytest.mark.parametrize("pair", ["dopri5", "tsit5"])
def test_rk4_and_dopri5_agree_on_the_output_grid(compiled, pair):
    """RK4 fits its step to the output grid; DOPRI5 / Tsit5 interpolate (dense output)."""
    c = compiled
    t_out = np.linspace(0.0, T_END, 11)
    a = cl.simulate(c, T_END, t_out=t_out, method="rk4", step=1e-3)
    b = cl.simulate(c, T_END, t_out=t_out, method=pair, rtol=1e-11, atol=1e-13)
    np.testing.assert_array_equal(a.t, t_out)
    # measured 6.3e-11 (q) and 8.8e-10 (v) (Tsit5: 6.2e-11, 8.6e-10): the RK4 error at
    # h = 1e-3 (C h^4 with the order test's C); a sample misplaced by one step would differ
    # by ~1e-3
    assert np.max(np.abs(a.q - b.q)) < 1e-9
    assert np.max(np.abs(a.v - b.v)) < 1e-8


# ---------------------------------------------------------------------------- failures
def test_max_steps_returns_partial_result(compiled):
    c = compiled
    full = cl.simulate(c, 2.0, dt_out=0.01, rtol=1e-8)
    r = cl.simulate(c, 2.0, dt_out=0.01, rtol=1e-8, max_steps=20)
    assert full.success
    assert r.status == 3 and not r.success
    assert "maximum number of steps" in r.message and "stopped at t =" in r.message
    n = r.t.size
    assert 0 < n < full.t.size
    for arr in (r.q, r.v, r.a, r.lam, r.phi, r.energy["residual"], r.energy["kinetic"]):
        assert arr.shape[0] == n
    # the samples kept are exactly those of the full run (same steps up to the failure)
    np.testing.assert_array_equal(r.t, full.t[:n])
    np.testing.assert_allclose(r.q, full.q[:n], rtol=0, atol=1e-14)
    np.testing.assert_allclose(r.a, full.a[:n], rtol=0, atol=1e-12)
    assert r.stats["naccept"] + r.stats["nreject"] == 20  # max_steps counts attempts


def test_max_steps_before_first_sample():
    """Nothing but the initial sample requested after t0: an empty but well-formed result."""
    c = cl.compile_mechanism(spatial_pendulum())
    r = cl.simulate(c, 1.0, t_out=np.array([1.0]), max_steps=3)
    assert r.status == 3 and r.t.size == 0
    assert r.q.shape == (0, c.nq) and r.energy["residual"].shape == (0,)
    assert "0 of 1 samples kept" in r.message


def test_step_underflow_returns_initial_sample(compiled):
    r = cl.simulate(compiled, 1.0, dt_out=0.01, rtol=1e-8, min_step=0.5)
    assert r.status == 2 and "step size underflow" in r.message
    assert r.t.size == 1 and r.t[0] == 0.0
    np.testing.assert_allclose(r.q[0], cl.initial_state(compiled)[: compiled.nq], atol=0)


@pytest.mark.parametrize("method", list(METHODS))
def test_euler_parameters_stay_unit(method):
    """p is renormalised after every accepted step (physics.md b.2) and in every output
    sample; without it |p| drifts by the truncation error (about 1e-9 over 10 s here).
    Runs every registered method (a new one is tested by its registry line)."""
    from clearance.mechanisms.examples import free_body

    c = cl.compile_mechanism(free_body())
    r = cl.simulate(c, 10.0, dt_out=0.1, rtol=1e-8, method=method, step=1e-3)
    assert r.success
    norms = np.linalg.norm(r.q[:, 3:7], axis=1)
    assert np.max(np.abs(norms - 1.0)) < 1e-14


def test_lugre_contacts_converge_with_rtol():
    """LuGre bristles start every contact unloaded (z = 0, as all through the flight): the
    step cut at an onset used to hand on z interpolated from stages beyond it, where
    z_dot = v_t already acted, so the error stalled. dopri5, Flores + LuGre (ball 15 mm,
    c = 0.3 mm), eccentricity error over 0.1 s (29 events) against rtol 1e-12. Measured at
    rtol 1e-6, 1e-8, 1e-10: 3.0e-8, 1.7e-8, 1.1e-11 (bristles carried with the tangent
    plane); projected after the steps: 5.1e-8, 1.3e-9, 7.0e-12; with z from the
    interpolant: 5.0e-7, 5.4e-8, 2.1e-10 (fails here, each of the three bounds).
    Not monotone between neighbouring tolerances in either bristle model: the rod's
    velocity just after its first impact already converges erratically (rtol 1e-7 .. 1e-9:
    4.6e-7, 6.3e-7, 5.0e-8, 1.4e-8, 4.0e-8, 9.4e-8, 1.6e-8, 1.1e-8, 4.2e-9, 2.0e-6 m/s, the
    same in both models; regular, ~4e-9 m/s, with max_step 2e-5), and the error at rtol
    1e-6 moved from 1.4e-7 to 3.0e-8 with a change of the bristles' normal part of ~1e-5 of
    z; so the test bounds each error, not their ratios."""
    c = rod_on_clearance_joint(
        cl.Flores(restitution=0.8), cl.LuGre(), ball_radius=0.015, clearance=0.3e-3
    )
    kw = dict(dt_out=1e-4, method="dopri5")
    ref = cl.simulate(c, 0.1, rtol=1e-12, atol=1e-15, **kw)
    assert ref.stats["nevents"] >= 20
    err = []
    for rtol in (1e-6, 1e-8, 1e-10):
        r = cl.simulate(c, 0.1, rtol=rtol, atol=rtol * 1e-3, **kw)
        assert r.events.shape == ref.events.shape
        err.append(np.linalg.norm(r.eccentricity("S") - ref.eccentricity("S"), axis=1).max())
    assert err[0] < 2e-7 and err[1] < 3e-8 and err[2] < 5e-11, err


def test_lugre_bristles_start_at_the_located_onset():
    """The state of a located onset can sit a rounding below delta = 0 (here -7e-18 m).
    The bristle rate must follow the latched contact, not the sign of delta: when it
    switched on only at delta > 0, the first step after the onset started z late, and z
    then lagged the reference by 1.2e-9 m (56 % of z 1e-7 s after the onset), which
    spoilt the friction of the whole contact: the rod's velocity after its first impact was
    off by 5e-5 m/s at rtol 1e-7 (max_step 6e-5). Now z is within rounding of the
    reference (measured 1.5e-18 m) and the velocity within 7e-7 m/s."""
    c = rod_on_clearance_joint(
        cl.Flores(restitution=0.8), cl.LuGre(), ball_radius=0.015, clearance=0.3e-3
    )
    T = 0.0045  # the first impact: onset at 3.877 ms, separation at 3.991 ms
    ref = cl.simulate(c, T, rtol=1e-12, atol=1e-15, method="dopri5", t_out=[0.0, T])
    ton = ref.events[0, 0]
    assert ref.events[0, 2] == 1.0 and 0.0038 < ton < 0.0039
    t_out = [0.0, ton + 1e-7, ton + 1e-6, T]
    ref = cl.simulate(c, T, rtol=1e-12, atol=1e-15, method="dopri5", t_out=t_out)
    r = cl.simulate(c, T, rtol=1e-7, atol=1e-10, method="dopri5", t_out=t_out, max_step=6e-5)
    for k in (1, 2):
        z, zr = r.bristle[k, 0], ref.bristle[k, 0]
        assert np.linalg.norm(z - zr) < 1e-3 * np.linalg.norm(zr), (k, z, zr)
    assert np.max(np.abs(r.v[-1] - ref.v[-1])) < 5e-6


def test_the_state_at_an_event_comes_from_a_step_that_ends_there():
    """A step with an onset in it is redone up to the onset (erk.py): its dense output also
    carries the stages beyond the event, where the contact force already acts, and the
    state interpolated from it at the event spoilt the next steps. The rod's velocity after
    its first impact at rtol 1e-9 (dopri5; with max_step limits as well, which change the
    steps through it): 5e-9 .. 9e-9 m/s interpolated, 2e-11 .. 2e-10 redone. The redone
    step's own error is checked too (the separation's force, ~ delta^1.5, is not smooth
    there): at rtol 1e-8 with max_step 1e-4 the redo without the check left 1.4e-7 m/s,
    with it 7e-10 (all limits now within 5e-9)."""
    c = rod_on_clearance_joint(
        cl.Flores(restitution=0.8), cl.LuGre(), ball_radius=0.015, clearance=0.3e-3
    )
    T = 0.0045  # the first impact: onset at 3.877 ms, separation at 3.991 ms
    ref = cl.simulate(c, T, rtol=1e-12, atol=1e-15, method="dopri5", t_out=[0.0, T])
    limits = ({}, {"max_step": 2e-4}, {"max_step": 1e-4}, {"max_step": 6e-5}, {"max_step": 3e-5})
    for rtol, bound in ((1e-9, 1e-9), (1e-8, 1e-8)):
        for limit in limits:
            r = cl.simulate(
                c, T, rtol=rtol, atol=rtol * 1e-3, method="dopri5", t_out=[0.0, T], **limit
            )
            assert r.stats["nevents"] >= 2
            assert np.max(np.abs(r.v[-1] - ref.v[-1])) < bound, (rtol, limit)


def test_lugre_persistent_contact_converges_with_rtol():
    """A pendulum swinging and spinning with its ball pressed into the socket (Flores +
    LuGre, no events): the contact normal turns all the time, and the bristles follow the
    tangent plane in the right-hand side (contact/element.py), so the run is one smooth ODE
    and its error falls with rtol. Projected onto the plane after each accepted step when
    |n . z| > 1e-3 |z| (before), the friction force depended on the steps and the error
    stalled: tsit5 4.0e-9 m at rtol 1e-6, 1.8e-9 m at 1e-8; dopri5 3.6e-9, 1.6e-9. Measured
    now: tsit5 5.5e-11, 8.2e-13; dopri5 3.1e-10, 1.5e-12 (eccentricity over 0.1 s against
    dopri5 at rtol 1e-12). This guards the run being one smooth ODE (no step-dependent
    update); that the transport terms are right is test_clearance_kinds.py's job."""
    L, c, K = 0.25, 1e-4, 1e10
    m = cl.Mechanism("pendulum in its socket")
    m.add(
        cl.Body(
            "rod",
            1.0,
            (0.0052, 0.0052, 0.0002),
            position=(0, 0, -L),
            velocity=(0.3, 0.1, 0),
            angular_velocity=(-0.1 / L, -0.3 / L, 0.5),
        ),
        cl.Marker("socket", "ground"),
        cl.Marker("ball", "rod", (0, 0, L)),
        cl.Spherical(
            "S",
            "socket",
            "ball",
            clearance=cl.Clearance(
                ball_radius=0.01,
                radial_clearance=c,
                normal=cl.Flores(stiffness=K, restitution=0.9),
                friction=cl.LuGre(),
            ),
        ),
    )
    comp = cl.compile_mechanism(m)
    y0 = cl.initial_state(comp)
    y0[2] -= c + (9.81 / K) ** (2 / 3)  # the ball on the bottom of its socket
    kw = dict(dt_out=1e-3, y0=y0, assemble_positions=False)
    ref = cl.simulate(comp, 0.1, method="dopri5", rtol=1e-12, atol=1e-15, **kw)
    assert ref.stats["nevents"] == 0 and np.all(ref.contact_state[:, 0, 0] == 1)  # in contact
    for method in ("tsit5", "dopri5"):
        err = []
        for rtol in (1e-6, 1e-8):
            r = cl.simulate(comp, 0.1, method=method, rtol=rtol, atol=rtol * 1e-3, **kw)
            err.append(np.linalg.norm(r.eccentricity("S") - ref.eccentricity("S"), axis=1).max())
        assert err[1] < 1e-11 and err[0] > 20 * err[1], (method, err)


@pytest.mark.parametrize("method", ["dopri5", "tsit5", "dop853", "vern7"])
def test_contact_events_converge_with_rtol(method):
    """Onsets and separations are located to a time within rtol times the step (not only
    to a penetration of 1e-3 c): the eccentricity error against an rtol 1e-12 run falls
    ~10x per decade down to rtol 1e-10, without the old plateau (with the penetration
    criterion alone: 6.2e-8 m at rtol 1e-8, 7.0e-9 m at 1e-10, 9x over two decades), and
    the logged onset times and impact velocities converge with it."""
    # frictionless Hunt-Crossley, c = 0.1 mm: 36 onsets and separations in 0.05 s
    c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.9), cl.NoFriction())
    kw = dict(dt_out=1e-3, method=method)
    ref = cl.simulate(c, 0.05, rtol=1e-12, atol=1e-15, **kw)
    assert ref.stats["nevents"] >= 30
    err, ev = {}, {}
    for rtol in (1e-8, 1e-10):
        r = cl.simulate(c, 0.05, rtol=rtol, atol=rtol * 1e-3, **kw)
        err[rtol] = np.max(np.abs(r.eccentricity("S") - ref.eccentricity("S")))
        assert r.events.shape == ref.events.shape
        ev[rtol] = np.max(np.abs(r.events[:, [0, 3]] - ref.events[:, [0, 3]]), axis=0)
    assert err[1e-10] < 2e-10 and err[1e-8] > 30 * err[1e-10], err
    assert ev[1e-10][0] < 2e-8 and ev[1e-8][0] > 10 * ev[1e-10][0], ev  # event times [s]
    assert ev[1e-10][1] < 1e-7, ev  # impact velocities [m/s]
