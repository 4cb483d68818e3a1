"""DOP853 (Dormand & Prince 8(5,3), dense output of order 7) beside the 5(4) pairs.

The tableau: rooted-tree order conditions of the 8th-order weights (all 200 trees of order
<= 8), of the 5th- and 3rd-order embedded weights behind the error estimate, and of the
dense output (order 7) for every x; the power form P against SciPy's nested form of the
same interpolant. The compiled `interpolate` with P: local orders 8 (dense) and 9 (step
end). The compiled loop: global order 8 at fixed steps and error proportional to the
tolerance on the spatial double pendulum, against SciPy's DOP853 at rtol 1e-13 (another
implementation of the same method, its own controller); fewer right-hand sides than the
5(4) pairs at tight tolerances. Clearance joints with contact events run with dop853 in
test_clearance_joint.py and test_events.py; the sliced loop in test_run_control.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.integrate._ivp.rk import Dop853DenseOutput
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
from clearance.integrate import tableau_dop853 as d8
from clearance.integrate.events import interpolate
from clearance.mechanisms.examples import double_pendulum

TREES8 = [t for n in range(1, 9) for t in _trees(n)]


def test_tree_count():
    assert len(TREES8) == 200  # 1 + 1 + 2 + 4 + 9 + 20 + 48 + 115


def test_weights_are_eighth_order():
    """b . u(t) = 1/gamma(t) for the 200 trees of order <= 8 (measured <= 1.0e-15), and
    not for order 9 (2.7e-5): the weights are genuinely 8th order."""
    A = d8.A[: d8.N_STAGES, : d8.N_STAGES]
    np.testing.assert_allclose(d8.A.sum(axis=1), d8.C, rtol=0, atol=2e-15)
    for t in TREES8:
        assert abs(d8.B @ _u(t, A) - 1.0 / _gamma(t)) < 1e-14, t
    assert max(abs(d8.B @ _u(t, A) - 1.0 / _gamma(t)) for t in _trees(9)) > 1e-6
    # stage 12 is f(t + h, y_new): its row of A is b (first same as last)
    np.testing.assert_array_equal(d8.A[d8.N_STAGES, : d8.N_STAGES], d8.B)


@pytest.mark.parametrize(("E", "order"), [("E5", 5), ("E3", 3)])
def test_embedded_orders(E, order):
    """b - E are the 5th- and 3rd-order embedded weights the error estimate differences
    (measured: <= 6.7e-16 up to their order, >= 4.5e-4 / 2.5e-2 one order above)."""
    A = d8.A[: d8.N_STAGES + 1, : d8.N_STAGES + 1]
    bh = np.append(d8.B, 0.0) - getattr(d8, E)
    for n in range(1, order + 1):
        for t in _trees(n):
            assert abs(bh @ _u(t, A) - 1.0 / _gamma(t)) < 1e-14, t
    assert max(abs(bh @ _u(t, A) - 1.0 / _gamma(t)) for t in _trees(order + 1)) > 1e-4


def test_dense_output_order_conditions_and_scipy_form():
    """b(x) = P [x .. x^7] satisfies b(x) . u(t) = x^|t| / gamma(t) for |t| <= 7 at every x
    (measured <= 1.4e-13: the power form's coefficients reach 545), ends at b, and equals
    SciPy's nested Dop853DenseOutput built from the same stages."""
    A = d8.A
    for x in np.linspace(0.0, 1.0, 11):
        bx = d8.P @ x ** np.arange(1, 8)
        for t in TREES8:
            if _order(t) <= 7:
                res = bx @ _u(t, A) - x ** _order(t) / _gamma(t)
                assert abs(res) < 5e-13, (x, t, res)
    # ends at b: to 2.0e-13 measured, the power form's rounding (coefficients up to 545,
    # ~6e-14 each; SciPy's nested form ends at b exactly): below rtol at any tolerance used
    np.testing.assert_allclose(d8.P.sum(axis=1)[: d8.N_STAGES], d8.B, rtol=0, atol=4e-13)
    # SciPy's form (F from y_new - y, f(y), f(y_new) and D K) on random stages
    rng = np.random.default_rng(7)
    K = rng.normal(size=(d8.N_STAGES_EXTENDED, 3))
    y, h = rng.normal(size=3), 0.3
    dy = h * d8.B @ K[: d8.N_STAGES]
    F = np.empty((7, 3))
    F[0] = dy
    F[1] = h * K[0] - dy
    F[2] = 2 * dy - h * (K[d8.N_STAGES] + K[0])
    F[3:] = h * d8.D @ K
    nested = Dop853DenseOutput(0.0, h, y, F)
    out = np.empty(3)
    for x in np.linspace(0.0, 1.0, 9):
        interpolate(y, K, d8.P, h, x, out, np.empty(16))
        np.testing.assert_allclose(out, nested(x * h), rtol=0, atol=1e-13)


def test_dense_output_local_order():
    """One step from the exact y(0.3) of y1' = 1 + y1^2, y2' = -y1 y2 (y = (tan t, cos t)),
    the 15 stages by hand: dense output O(h^8) over the step, step end O(h^9).
    Measured (h = 0.4 .. 0.05): dense 3.5e-7, 4.4e-10, 1.3e-12, 8.6e-15, pairwise 9.6, 8.4,
    7.2 (pre-asymptotic from above, then the power form's rounding), fitted slope 8.4; end
    pairwise 9.0, 9.0 (then rounding)."""
    A, C, B, P = d8.A, d8.C, d8.B, d8.P
    t0 = 0.3
    xs = np.linspace(0.0, 1.0, 41)
    hs = np.array([0.4, 0.2, 0.1, 0.05])
    dense, end = [], []
    out = np.empty(2)
    for h in hs:
        y0 = _exact(t0)
        K = np.zeros((16, 2))
        K[0] = _f(t0, y0)
        for s in range(1, 12):
            K[s] = _f(t0 + C[s] * h, y0 + h * (A[s, :s] @ K[:s]))
        y1 = y0 + h * (B @ K[:12])
        K[12] = _f(t0 + h, y1)
        for s in range(13, 16):
            K[s] = _f(t0 + C[s] * h, y0 + h * (A[s, :s] @ K[:s]))
        err = 0.0
        for x in xs:
            interpolate(y0, K, P, h, x, out, np.empty(16))
            err = max(err, np.max(np.abs(out - _exact(t0 + x * h))))
        dense.append(err)
        end.append(np.max(np.abs(y1 - _exact(t0 + h))))
    dense, end = np.array(dense), np.array(end)
    pairwise = np.log2(dense[:-1] / dense[1:])
    assert np.all((pairwise > 6.8) & (pairwise < 10.0)), (pairwise, dense)
    assert 7.6 < _slope(hs, dense) < 9.2, dense
    assert np.all(np.log2(end[:-2] / end[1:-1]) > 8.5), end


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


def test_order_eight_at_fixed_steps(compiled, reference):
    """rtol = atol = 1e3 accepts every step; first_step = max_step = h fixes it. 12 new
    right-hand sides per step, 3 more where the step holds samples. Measured (h = 0.1 ..
    0.0125): final state 2.6e-5, 1.1e-7, 2.4e-10, 9.1e-13, pairwise 7.9, 8.9, 8.0, fit 8.3;
    the 10 samples inside steps 3.6e-5 .. 1.4e-12, pairwise 7.3, 6.8, 10.4 (the worst
    sample moves between h), fit 8.1."""
    hs = np.array([0.1, 0.05, 0.025, 0.0125])
    err_end, err_inner = [], []
    for h in hs:
        st, e_end, e_inner = fixed_step_errors(compiled, reference, "dop853", h)
        n = round(T_END / h)
        # 1 (f(y0)) + 12 per step + 3 per step with samples (10 inside, the last at the end)
        with_samples = len({int((tk + 1e-12) / h - 1e-9) for tk in T_INNER[1:]}) + 1
        assert st["nfev"] == 1 + 12 * n + 3 * min(with_samples, n), (st["nfev"], n)
        err_end.append(e_end)
        err_inner.append(e_inner)
    for err in (np.array(err_end), np.array(err_inner)):
        assert err[-1] > 1e-13 and np.all(np.diff(err) < 0), err
        assert 7.0 < _slope(hs, err) < 9.5, err


def test_global_error_proportional_to_tolerance(compiled, reference):
    """The global error follows rtol (dop853.f's controller), with far fewer right-hand
    sides than tsit5 at tight tolerances. Measured for rtol 1e-6 .. 1e-12: 1.8e-5, 1.0e-8,
    1.7e-10, 2.1e-12 (16 .. 78 steps, 271 .. 1048 rhs; tsit5 at 1e-12: 3650 rhs)."""
    tols = np.array([1e-6, 1e-8, 1e-10, 1e-12])
    err, nfev = [], []
    for tol in tols:
        r = cl.simulate(compiled, T_END, t_out=T_INNER, method="dop853", rtol=tol, atol=1e-2 * tol)
        assert r.success, r.message
        err.append(np.max(np.abs(np.hstack([r.q, r.v]) - reference)))
        nfev.append(r.stats["nfev"])
    err = np.array(err)
    assert 0.8 < _slope(tols, err) < 1.4, err
    assert np.all(err < 100.0 * tols), err
    ts5 = cl.simulate(compiled, T_END, t_out=T_INNER, method="tsit5", rtol=1e-12, atol=1e-14)
    assert nfev[-1] < 0.5 * ts5.stats["nfev"], (nfev, ts5.stats["nfev"])


# ---------------------------------------------------------------------------- "auto"
@pytest.mark.parametrize(
    ("rtol", "expected"), [(1e-6, "tsit5"), (1e-10, "tsit5"), (1e-11, "vern7")]
)
def test_auto_picks_the_method_by_tolerance(compiled, rtol, expected):
    """The default method "auto": tsit5 down to rtol 1e-10 (methods.AUTO_RTOL), vern7
    below; the result says which ran and what was asked."""
    r = cl.simulate(compiled, 0.05, rtol=rtol, atol=rtol * 1e-2)
    assert r.success
    assert r.settings["method"] == expected and r.settings["method_requested"] == "auto"
    same = cl.simulate(compiled, 0.05, rtol=rtol, atol=rtol * 1e-2, method=expected)
    np.testing.assert_array_equal(r.q, same.q)


def test_unknown_method_lists_auto(compiled):
    with pytest.raises(cl.ModelError, match="'auto', 'dopri5', 'tsit5', 'rk4', 'dop853'"):
        cl.simulate(compiled, 0.05, method="dop85")


def test_scenario_accepts_dop853_and_auto():
    from clearance.scenario import default_scenario_path, load_scenario, with_overrides

    base = load_scenario(default_scenario_path())
    for m in ("dop853", "auto"):
        s = with_overrides(base, {"solver.method": m})
        assert s.solver.simulate_kwargs()["method"] == m
        assert f"{m} rtol 1e-06" in s.summary()
