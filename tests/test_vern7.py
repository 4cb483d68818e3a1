"""Vern7 (Verner's 7(6) "most efficient" pair with its 7th-order interpolant) beside DOP853.

The tableau: rooted-tree order conditions of the 7th-order weights (all 85 trees of order
<= 7), of the 6th-order embedded weights behind the error estimate, and of the interpolant
for every x. The compiled `interpolate` with P: local order over a step. The compiled loop
(erk_high.py, shared with dop853): global order 7 at fixed steps with the exact count of
right-hand sides, and error proportional to the tolerance on the spatial double pendulum,
against SciPy's DOP853 at rtol 1e-13 (another method and implementation). Contact events
with vern7 in test_events.py and test_clearance_joint.py; the sliced loop in
test_run_control.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_tsit5 import (
    T_END,
    T_INNER,
    _exact,
    _f,
    _gamma,
    _order,
    _slope,
    _trees,
    _u,
    fixed_step_errors,
)

import clearance as cl
from clearance.integrate import tableau_vern7 as v7
from clearance.integrate.events import interpolate
from clearance.integrate.methods import METHODS
from clearance.mechanisms.examples import double_pendulum

TREES7 = [t for n in range(1, 8) for t in _trees(n)]


def _residual(w, t, A):
    return abs(w @ _u(t, A) - 1.0 / _gamma(t))


def test_tree_count():
    assert len(TREES7) == 85  # 1 + 1 + 2 + 4 + 9 + 20 + 48


def test_weights_are_seventh_order():
    """b . u(t) = 1/gamma(t) for the 85 trees of order <= 7 (measured <= 3.9e-15), not for
    order 8 (1.7e-5): the weights are genuinely 7th order. Stage 10 is f(t + h, y_new)."""
    A = v7.A[: v7.N_STAGES, : v7.N_STAGES]
    np.testing.assert_allclose(v7.A.sum(axis=1), v7.C, rtol=0, atol=2e-14)
    for t in TREES7:
        assert _residual(v7.B, t, A) < 1e-14, t
    assert max(_residual(v7.B, t, A) for t in _trees(8)) > 1e-6
    np.testing.assert_array_equal(v7.A[v7.N_STAGES, : v7.N_STAGES], v7.B)
    assert v7.B[-1] == 0.0  # stage 9 serves the error estimate only


def test_embedded_weights_are_sixth_order():
    """bh = b - E: order 6 (measured <= 2.1e-16), not 7 (4.3e-4)."""
    A = v7.A[: v7.N_STAGES, : v7.N_STAGES]
    bh = v7.B - v7.E
    np.testing.assert_allclose(bh, v7.BH, rtol=0, atol=1e-16)
    for n in range(1, 7):
        for t in _trees(n):
            assert _residual(bh, t, A) < 1e-14, t
    assert max(_residual(bh, t, A) for t in _trees(7)) > 1e-4


def test_interpolant_order_conditions():
    """b(x) = P [x .. x^7]: b(x) . u(t) = x^|t| / gamma(t) for |t| <= 6 at every x (measured
    <= 1.1e-13), ends at b (7.3e-14) and at 0. Of the 48 trees of order 7, 36 hold to
    rounding and 12 to 2.7e-7: so the coefficients read (Verner's file, and the same digits
    in DifferentialEquations.jl's Vern7 interpolant). The interpolant is of order 6 with
    order-7 error coefficients of at most 2.7e-7, smaller than the order-8 ones of the step
    itself (1.7e-5): test_interpolant_local_order sees order 8 over a step."""
    worst7 = np.zeros(len(_trees(7)))
    for x in np.linspace(0.0, 1.0, 11):
        bx = v7.P @ x ** np.arange(1, 8)
        for t in TREES7:
            res = abs(bx @ _u(t, v7.A) - x ** _order(t) / _gamma(t))
            if _order(t) <= 6:
                assert res < 5e-13, (x, t, res)
        for i, t in enumerate(_trees(7)):
            worst7[i] = max(worst7[i], abs(bx @ _u(t, v7.A) - x**7 / _gamma(t)))
    assert worst7.max() < 3e-7 and np.sum(worst7 > 1e-12) == 12, worst7
    np.testing.assert_allclose(v7.P.sum(axis=1)[: v7.N_STAGES], v7.B, rtol=0, atol=2e-13)
    assert np.all(np.abs(v7.P.sum(axis=1)[v7.N_STAGES :]) < 1e-13)


def test_interpolant_local_order():
    """One step from the exact y(0.3) of y1' = 1 + y1^2, y2' = -y1 y2 (y = (tan t, cos t)),
    the 16 stages by hand: the dense output's error over the step (41 points) falls as
    h^8 or faster until rounding. Measured (h = 0.4, 0.2, 0.1): 3.2e-7, 4.8e-10, 7.8e-13,
    pairwise 9.4, 9.3 (the step end's own error, 7.8e-13 at h = 0.1, dominates)."""
    A, C, B, P = v7.A, v7.C, v7.B, v7.P
    t0 = 0.3
    out = np.empty(2)
    hs = np.array([0.4, 0.2, 0.1])
    dense = []
    for h in hs:
        y0 = _exact(t0)
        K = np.zeros((16, 2))
        K[0] = _f(t0, y0)
        for s in range(1, 16):
            K[s] = _f(t0 + C[s] * h, y0 + h * (A[s, :s] @ K[:s]))
        assert np.allclose(K[10], _f(t0 + h, y0 + h * (B @ K[:10])), rtol=0, atol=1e-15)
        err = 0.0
        for x in np.linspace(0.0, 1.0, 41):
            interpolate(y0, K, P, h, x, out, np.empty(16))
            err = max(err, np.max(np.abs(out - _exact(t0 + x * h))))
        dense.append(err)
    pairwise = np.log2(np.array(dense[:-1]) / np.array(dense[1:]))
    assert np.all(pairwise > 7.5), (pairwise, dense)


# ---------------------------------------------------------------------------- the loop
@pytest.fixture(scope="module")
def compiled() -> cl.Compiled:
    return cl.compile_mechanism(double_pendulum())


@pytest.fixture(scope="module")
def reference(compiled):
    """y at T_INNER (test_tsit5's times) from SciPy's DOP853 at rtol 1e-13."""
    f = cl.scipy_rhs(compiled, baumgarte=(5.0, 5.0))
    y0 = cl.initial_state(compiled)
    sol = solve_ivp(f, (0.0, T_END), y0, method="DOP853", rtol=1e-13, atol=1e-15, t_eval=T_INNER)
    assert sol.success
    return sol.y.T[:, : compiled.nq + compiled.nv]


def test_order_seven_at_fixed_steps(compiled, reference):
    """rtol = atol = 1e3 accepts every step; first_step = max_step = h fixes it. 10 right-hand
    sides per step (9 stages and f at the new solution), 5 more where the step holds samples.
    Measured (h = 0.1 .. 0.0125): final state 1.9e-3, 4.0e-6, 1.3e-8, 5.6e-11, pairwise
    8.9, 8.2, 7.9 (pre-asymptotic from above), fit 8.3."""
    hs = np.array([0.1, 0.05, 0.025, 0.0125])
    err_end, err_inner = [], []
    for h in hs:
        st, e_end, e_inner = fixed_step_errors(compiled, reference, "vern7", h)
        n = round(T_END / h)
        with_samples = len({int((tk + 1e-12) / h - 1e-9) for tk in T_INNER[1:]}) + 1
        assert st["nfev"] == 1 + 10 * n + 5 * min(with_samples, n), (st["nfev"], n)
        err_end.append(e_end)
        err_inner.append(e_inner)
    for err in (np.array(err_end), np.array(err_inner)):
        assert err[-1] > 1e-13 and np.all(np.diff(err) < 0), err
        assert 6.5 < _slope(hs, err) < 9.5, err


def test_global_error_proportional_to_tolerance(compiled, reference):
    """The global error follows rtol, with fewer right-hand sides than tsit5 at tight
    tolerances. Measured for rtol 1e-6 .. 1e-12: 1.0e-6, 4.0e-9, 2.0e-11, 1.6e-13 (285 ..
    1526 rhs; tsit5 at 1e-12: 3650 rhs, error 2.6e-12)."""
    tols = np.array([1e-6, 1e-8, 1e-10, 1e-12])
    err, nfev = [], []
    for tol in tols:
        r = cl.simulate(compiled, T_END, t_out=T_INNER, method="vern7", rtol=tol, atol=1e-2 * tol)
        assert r.success, r.message
        err.append(np.max(np.abs(np.hstack([r.q, r.v]) - reference)))
        nfev.append(r.stats["nfev"])
    err = np.array(err)
    assert 0.9 < _slope(tols, err) < 1.4, err
    assert np.all(err < 100.0 * tols), err
    ts5 = cl.simulate(compiled, T_END, t_out=T_INNER, method="tsit5", rtol=1e-12, atol=1e-14)
    assert nfev[-1] < 0.5 * ts5.stats["nfev"], (nfev, ts5.stats["nfev"])


def test_method_table_and_scenario():
    """vern7 is adaptive, keeps its 16 stages and runs from a scenario file."""
    from clearance.scenario import default_scenario_path, load_scenario, with_overrides

    m = METHODS["vern7"]
    assert m.adaptive and m.stages == 16 == v7.P.shape[0]
    s = with_overrides(load_scenario(default_scenario_path()), {"solver.method": "vern7"})
    assert s.solver.simulate_kwargs()["method"] == "vern7"
