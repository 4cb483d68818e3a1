"""Tsitouras 5(4) ("tsit5") beside Dormand-Prince 5(4) ("dopri5").

The tableau: rooted-tree order conditions of the 5th-order weights (all 17 trees of order
<= 5: Tsit5 satisfies only the first-column simplifying assumption, so none may be skipped),
of the embedded 4th-order weights and of the dense output for every x. The dense output's
local order on a smooth nonlinear ODE through the compiled `interpolate`; global orders of
the compiled loop (fixed steps, tolerance sweep) on the spatial double pendulum, also at
dense-output samples inside the steps; the scenario schema. Closed-form mechanism checks and
clearance joints with contact events run with method="tsit5" in test_validation_analytic.py
and test_clearance_joint.py (parametrised over both pairs).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import clearance as cl
from clearance.integrate import tableau as tb
from clearance.integrate.events import interpolate
from clearance.mechanisms.examples import double_pendulum
from clearance.scenario import default_scenario_path, load_scenario, with_overrides

PAIRS = {"dopri5": "DP5", "tsit5": "TS5"}


def _tableau(method):
    p = PAIRS[method]
    return tuple(getattr(tb, f"{p}_{k}") for k in "ACBEP")


# ---------------------------------------------------------------------------- rooted trees
@functools.cache
def _trees(n: int) -> tuple:
    """Rooted trees with n nodes, each a sorted tuple of its children's subtrees."""
    if n == 1:
        return ((),)
    found = set()

    def grow(rem, children):
        if rem == 0:
            found.add(tuple(sorted(children)))
            return
        for m in range(1, rem + 1):
            for t in _trees(m):
                grow(rem - m, [*children, t])

    grow(n - 1, [])
    return tuple(sorted(found))


def _order(t) -> int:
    return 1 + sum(_order(s) for s in t)


def _gamma(t) -> int:
    return _order(t) * math.prod(_gamma(s) for s in t)


def _u(t, A) -> np.ndarray:
    """u_i(t) = prod over children s of (A u(s))_i: the elementary weight is b . u(t)."""
    v = np.ones(A.shape[0])
    for s in t:
        v = v * (A @ _u(s, A))
    return v


TREES = [t for n in range(1, 6) for t in _trees(n)]


def _full(A) -> np.ndarray:
    """The 7 x 7 stage matrix from the (7, 6) layout."""
    return np.hstack([A, np.zeros((7, 1))])


def test_rooted_tree_counts():
    assert [len(_trees(n)) for n in range(1, 7)] == [1, 1, 2, 4, 9, 20]
    assert sorted(_gamma(t) for t in _trees(4)) == [4, 8, 12, 24]


@pytest.mark.parametrize("method", list(PAIRS))
def test_tableau_order_conditions(method):
    """b . u(t) = 1/gamma(t) for |t| <= 5; (b - E) for |t| <= 4 but not 5; the dense output
    b(x) = P [x, x^2, x^3, x^4] satisfies b(x) . u(t) = x^|t| / gamma(t), |t| <= 4, for all x.
    c_i = sum_j a_ij as in the conditions. Measured (TS5): weights 1.4e-14, embedded 9.2e-15,
    dense 1.9e-14, row sums - c 7.8e-16; DP5 <= 1e-15. A coefficient recalled wrong by one
    digit fails by orders of magnitude."""
    A, C, B, E, P = _tableau(method)
    Af = _full(A)
    assert A.shape == (7, 6) and C.shape == B.shape == E.shape == (7,) and P.shape == (7, 4)
    np.testing.assert_allclose(Af.sum(axis=1), C, rtol=0, atol=2e-15)
    # FSAL layout: the last row of A is b and b_7 = 0, so stage 7 is f(t + h, y_new)
    np.testing.assert_array_equal(A[6], B[:6])
    assert B[6] == 0.0 and C[6] == 1.0
    bhat = B - E
    for t in TREES:
        n, u, g = _order(t), _u(t, Af), _gamma(t)
        assert abs(B @ u - 1.0 / g) < 3e-14, (t, B @ u - 1.0 / g)
        if n <= 4:
            assert abs(bhat @ u - 1.0 / g) < 3e-14, (t, bhat @ u - 1.0 / g)
    # the embedded pair is genuinely 4th order: some order-5 condition fails clearly
    # (measured 8.7e-4 for TS5, 8.1e-4 for DP5), so E estimates the 4th-order local error
    worst5 = max(abs(bhat @ _u(t, Af) - 1.0 / _gamma(t)) for t in _trees(5))
    assert worst5 > 1e-5
    assert abs(E.sum()) < 1e-15
    # dense output: order <= 4 conditions for every x
    for x in np.linspace(0.0, 1.0, 21):
        bx = P @ np.array([x, x**2, x**3, x**4])
        for t in TREES:
            if _order(t) <= 4:
                res = bx @ _u(t, Af) - x ** _order(t) / _gamma(t)
                assert abs(res) < 5e-14, (x, t, res)
    # it ends at y_new (measured 2.7e-15 for TS5) with the slope f(y_new) = K[6]
    # (C^1 across steps)
    np.testing.assert_allclose(P.sum(axis=1), B, rtol=0, atol=5e-15)
    np.testing.assert_allclose(P @ np.array([1.0, 2.0, 3.0, 4.0]), np.eye(7)[6], atol=5e-14)
    # and starts with the slope f(y) = K[0]
    np.testing.assert_array_equal(P[:, 0], np.eye(7)[0])


def test_tsit5_is_not_dopri5():
    """The two pairs really differ (a copy-paste of the DP5 arrays would pass the above)."""
    ts, dp = _tableau("tsit5"), _tableau("dopri5")
    for a, b in zip(ts, dp, strict=True):
        assert np.max(np.abs(a - b)) > 1e-3
    assert tb.TS5_C[1] == 0.161 and tb.TS5_E[6] == pytest.approx(-1.0 / 66.0, rel=1e-15)


# ---------------------------------------------------------------------------- dense output
def _f(t, y):
    return np.array([1.0 + y[0] ** 2, -y[0] * y[1]])


def _exact(t):
    return np.array([math.tan(t), math.cos(t)])


@pytest.mark.parametrize("method", list(PAIRS))
def test_dense_output_local_order(method):
    """One step from the exact y(0.3) of y1' = 1 + y1^2, y2' = -y1 y2 (y = (tan t, cos t)).
    The compiled `interpolate` with the pair's P: local error O(h^5) over the step (a 4th-order
    continuous extension), the step end O(h^6), and the interpolant ends at the step's y_new.
    Measured TS5 (h = 0.2 .. 0.0125): dense 1.4e-6 .. 8.0e-13, pairwise orders 5.43, 5.20,
    5.10, 5.05; end 6.6, 6.4, 6.3 (the last pair at the rounding level); x = 1 vs y_new
    <= 3.3e-16. DP5: 5.36 .. 5.04 and 6.3 .. 6.15."""
    A, C, B, _, P = _tableau(method)
    t0 = 0.3
    xs = np.linspace(0.0, 1.0, 41)
    hs = np.array([0.2, 0.1, 0.05, 0.025, 0.0125])
    dense, end = [], []
    out = np.empty(2)
    for h in hs:
        y0 = _exact(t0)
        K = np.zeros((7, 2))
        K[0] = _f(t0, y0)
        for s in range(1, 7):
            K[s] = _f(t0 + C[s] * h, y0 + h * (A[s, :s] @ K[:s]))
        y1 = y0 + h * (B @ K)
        err = 0.0
        for x in xs:
            interpolate(y0, K, P, h, x, out, np.empty(7))
            err = max(err, np.max(np.abs(out - _exact(t0 + x * h))))
        dense.append(err)
        end.append(np.max(np.abs(y1 - _exact(t0 + h))))
        interpolate(y0, K, P, h, 1.0, out, np.empty(7))
        assert np.max(np.abs(out - y1)) < 1e-15
    dense, end = np.array(dense), np.array(end)
    pairwise = np.log2(dense[:-1] / dense[1:])
    assert np.all((pairwise > 4.8) & (pairwise < 5.6)), pairwise
    assert abs(pairwise[-1] - 5.0) < 0.15, pairwise
    assert np.all(np.log2(end[:-2] / end[1:-1]) > 5.8), end


# ---------------------------------------------------------------------------- the loop
T_END = 1.0
BAUMGARTE = (5.0, 5.0)
# dense-output samples strictly inside steps of every h below (and T_END, a step end)
T_INNER = np.append(0.0137 + 0.1 * np.arange(10), T_END)


@pytest.fixture(scope="module")
def compiled() -> cl.Compiled:
    return cl.compile_mechanism(double_pendulum())


@pytest.fixture(scope="module")
def reference(compiled):
    """y at T_INNER from scipy DOP853 at rtol 1e-13 (independent integrator and controller)."""
    f = cl.scipy_rhs(compiled, baumgarte=BAUMGARTE)
    y0 = cl.initial_state(compiled)
    sol = solve_ivp(f, (0.0, T_END), y0, method="DOP853", rtol=1e-13, atol=1e-15, t_eval=T_INNER)
    assert sol.success
    return sol.y.T[:, : compiled.nq + compiled.nv]


def _slope(x, err) -> float:
    return float(np.polyfit(np.log(x), np.log(err), 1)[0])


def fixed_step_errors(compiled, reference, method, h):
    """A run of `method` at the fixed step h (rtol = atol = 1e3 accept every step;
    first_step = max_step = h) sampled at T_INNER: (its stats, the error at T_END, the
    largest at the samples inside). Shared by the fixed-step order tests of the pairs."""
    r = cl.simulate(
        compiled,
        T_END,
        t_out=T_INNER,
        method=method,
        rtol=1e3,
        atol=1e3,
        first_step=h,
        max_step=h,
    )
    assert r.success, r.message
    st = r.stats
    assert st["nreject"] == 0 and st["naccept"] == round(T_END / h)
    own = np.hstack([r.q, r.v])
    return st, np.max(np.abs(own[-1] - reference[-1])), np.max(np.abs(own[:-1] - reference[:-1]))


def test_dopri5_order_five_at_fixed_steps(compiled, reference):
    """rtol = atol = 1e3 accepts every step; first_step = max_step = h fixes the step.
    Pairwise orders measured 5.5, 5.3, 5.15 (h = 0.02 .. 0.0025; h = 0.04 is still
    pre-asymptotic at 5.8); errors 1.2e-6 .. 1.9e-11, the reference's is ~1e-13."""
    hs = np.array([0.02, 0.01, 0.005, 0.0025])
    err = []
    for h in hs:
        # (method given: the default "auto" takes tsit5 here)
        st, e_end, _ = fixed_step_errors(compiled, reference, "dopri5", h)
        assert st["hmin"] == pytest.approx(h, rel=1e-9) and st["hmax"] == pytest.approx(h, rel=1e-9)
        err.append(e_end)
    err = np.array(err)
    assert err[-1] > 1e-11 and np.all(np.diff(err) < 0)  # above the reference error
    slope = _slope(hs, err)
    assert 4.5 < slope < 5.5, (slope, err)


def test_tsit5_order_five_at_fixed_steps(compiled, reference):
    """rtol = atol = 1e3 accepts every step; first_step = max_step = h fixes the step.
    Measured (h = 0.02 .. 0.0025): final state 4.9e-7, 9.2e-9, 1.9e-10, 4.3e-12, pairwise
    orders 5.73, 5.63, 5.42 (more pre-asymptotic than DOPRI5's 5.51, 5.30, 5.15, at ~1/3 of
    its error). The 10 samples inside steps (dense output, O(h^5) locally on top of the O(h^5)
    global error): max 1.8e-6, 7.0e-8, 1.7e-9, 2.8e-11, pairwise 4.71, 5.37, 5.94 (the worst
    sample moves between h), fitted slope 5.34 (DOPRI5: 4.27, 6.09, 4.69, fit 5.12). The
    reference's error is ~1e-13 (vs DOP853 at rtol 3e-14)."""
    hs = np.array([0.02, 0.01, 0.005, 0.0025])
    err_end, err_inner = [], []
    for h in hs:
        st, e_end, e_inner = fixed_step_errors(compiled, reference, "tsit5", h)
        assert st["nfev"] == 6 * st["naccept"] + 1  # FSAL: 6 new stages per step
        err_end.append(e_end)
        err_inner.append(e_inner)
    err_end, err_inner = np.array(err_end), np.array(err_inner)
    for err in (err_end, err_inner):
        assert err[-1] > 1e-12 and np.all(np.diff(err) < 0)  # above the reference error
        pairwise = np.log2(err[:-1] / err[1:])
        assert np.all(pairwise > 4.3) and np.all(pairwise < 6.5), (pairwise, err)
        assert 4.7 < _slope(hs, err) < 5.8, err
    pairwise = np.log2(err_end[:-1] / err_end[1:])
    assert np.all(np.diff(pairwise) < 0) and pairwise[-1] < 5.5, pairwise  # -> 5 from above


def test_tsit5_global_error_proportional_to_tolerance(compiled, reference):
    """PI control: the global error ~ rtol. Measured (max over the samples, most inside
    steps) for rtol 1e-5 .. 1e-9: 4.5e-5 .. 2.7e-9, slope 1.08, error/rtol 1.5 .. 4.5;
    25 .. 151 accepted steps (DOPRI5: 7.3e-5 .. 4.1e-9, slope 1.06, 25 .. 155 steps)."""
    c = compiled
    tols = np.array([1e-5, 1e-6, 1e-7, 1e-8, 1e-9])
    err, steps = [], []
    for tol in tols:
        r = cl.simulate(c, T_END, t_out=T_INNER, method="tsit5", rtol=tol, atol=1e-2 * tol)
        assert r.success, r.message
        err.append(np.max(np.abs(np.hstack([r.q, r.v]) - reference)))
        steps.append(r.stats["naccept"])
    err = np.array(err)
    assert 0.8 < _slope(tols, err) < 1.4, err
    assert np.all(err < 100.0 * tols)
    assert 3.0 < steps[-1] / steps[0] < 12.0, steps


def test_method_switches_the_pair(compiled):
    """Same problem, both pairs: different steps and results that agree to the tolerance."""
    runs = {
        m: cl.simulate(compiled, T_END, t_out=T_INNER, method=m, rtol=1e-8, atol=1e-10)
        for m in PAIRS
    }
    a, b = runs["dopri5"], runs["tsit5"]
    assert b.settings["method"] == "tsit5" and a.settings["method"] == "dopri5"
    assert not np.array_equal(a.q, b.q)
    # measured 3.0e-9 (DOPRI5 3.8e-9, Tsit5 8.2e-10 from the reference; 608 and 584 rhs)
    assert np.max(np.abs(a.q - b.q)) < 1e-7


# ---------------------------------------------------------------------------- scenario
def test_scenario_accepts_tsit5():
    s = with_overrides(load_scenario(default_scenario_path()), {"solver.method": "tsit5"})
    kw = s.solver.simulate_kwargs()
    assert kw["method"] == "tsit5" and kw["rtol"] == 1e-6 and kw["atol"] == 1e-9
    assert "tsit5 rtol 1e-06, atol 1e-09" in s.summary()
    rk4 = with_overrides(s, {"solver.method": "rk4", "solver.step": 1e-5})
    assert "rk4 h 1e-05" in rk4.summary()
