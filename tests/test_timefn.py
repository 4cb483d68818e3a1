"""Time functions: exact derivatives, compiled evaluator, spline agreement, validation."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from dataclasses import FrozenInstanceError, dataclass

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.interpolate import BPoly, CubicSpline

from clearance.compile.functions import encode_functions
from clearance.kinds import RAMP_PROFILES, FnKind
from clearance.kinematics.timefn import eval_all, eval_timefn
from clearance.model.errors import ModelError
from clearance.model.functions import (
    SPLINE_BC_TYPES,
    Constant,
    HermiteSpline,
    Polynomial,
    Ramp,
    Scaled,
    Sinusoid,
    Sum,
    Tabulated,
    TimeFunction,
    as_function,
)

EPS = np.finfo(float).eps
T_LO, T_HI = -3.0, 3.0  # every sampled time lies here; the bounds below hold on it
H = 1e-4  # FD step [s]; the shortest time scale generated (ramp duration, knot gap) is 0.2 s


@dataclass
class Case:
    """A function with bounds valid on [T_LO, T_HI] used to set tolerances.

    s[k]: magnitude of the terms summed to form the k-th derivative, so rounding in it is a
    few EPS * s[k] (the condition scale, not |f^(k)|, which may cancel to 0); m3, m4: bounds
    on |f'''| and |f''''| between knots; knots: times where f is only C^1 or C^2.
    """

    fn: TimeFunction
    s: tuple[float, float, float]
    m3: float
    m4: float
    knots: tuple[float, ...] = ()


def fl(lo: float, hi: float) -> st.SearchStrategy[float]:
    # No subnormals: rounding there is absolute, not relative, and breaks every EPS bound.
    return st.floats(lo, hi, allow_subnormal=False)


real = fl(-10.0, 10.0)


@st.composite
def constants(draw: st.DrawFn) -> Case:
    v = draw(real)
    return Case(Constant(v), (abs(v), 0.0, 0.0), 0.0, 0.0)


@st.composite
def polynomials(draw: st.DrawFn) -> Case:
    c = draw(st.lists(fl(-3.0, 3.0), min_size=1, max_size=6))
    t0 = draw(fl(-1.0, 1.0))
    u = max(abs(T_LO - t0), abs(T_HI - t0))

    def bound(j: int) -> float:  # sum_k k!/(k-j)! |c_k| u^(k-j) >= |f^(j)| on the window
        return sum(math.perm(k, j) * abs(ck) * u ** (k - j) for k, ck in enumerate(c) if k >= j)

    return Case(Polynomial(c, t0), (bound(0), bound(1), bound(2)), bound(3), bound(4))


@st.composite
def sinusoids(draw: st.DrawFn) -> Case:
    a, off = draw(real), draw(real)
    w, ph = draw(fl(-5.0, 5.0)), draw(fl(-math.pi, math.pi))
    # The argument w t + phase carries an error ~EPS |w t|, amplified by |a|.
    arg = 1.0 + abs(w) * max(abs(T_LO), abs(T_HI)) + abs(ph)
    s = (abs(off) + abs(a) * arg, abs(a * w) * arg, abs(a) * w * w * arg)
    return Case(Sinusoid(a, w, ph, off), s, abs(a) * abs(w) ** 3, abs(a) * w**4)


@st.composite
def ramps(draw: st.DrawFn) -> Case:
    y0, y1 = draw(real), draw(real)
    t0, dur = draw(fl(-2.0, 1.0)), draw(fl(0.2, 2.0))
    prof = draw(st.sampled_from(RAMP_PROFILES))
    fn = Ramp(y0, y1, t0, t0 + dur, prof)
    # |p^(k)(s)| <= (2 pi)^k for all three profiles (quintic: 1.9, 5.8, 60, 360).
    r = abs(y1 - y0)
    s = (abs(y0) + r, r * 2 * math.pi / dur, r * (2 * math.pi / dur) ** 2)
    return Case(fn, s, r * (2 * math.pi / dur) ** 3, r * (2 * math.pi / dur) ** 4, (t0, fn.t_end))


@st.composite
def tabulated(draw: st.DrawFn) -> Case:
    gaps = draw(st.lists(fl(0.2, 1.0), min_size=1, max_size=6))
    x = np.concatenate([[draw(fl(-2.5, 0.0))], gaps]).cumsum()
    y = draw(st.lists(real, min_size=x.size, max_size=x.size))
    fn = Tabulated(tuple(x), tuple(y), draw(st.sampled_from(SPLINE_BC_TYPES)))
    c, h = fn._spline.c, np.diff(x)  # on each segment f is the cubic sum c[3-k] u^k, u <= h
    s0 = np.max(np.abs(c[3]) + np.abs(c[2]) * h + np.abs(c[1]) * h**2 + np.abs(c[0]) * h**3)
    s1 = np.max(np.abs(c[2]) + 2 * np.abs(c[1]) * h + 3 * np.abs(c[0]) * h**2)
    s2 = np.max(2 * np.abs(c[1]) + 6 * np.abs(c[0]) * h)
    return Case(fn, (s0, s1, s2), 6 * np.max(np.abs(c[0])), 0.0, tuple(x))


def _pp_case(fn: HermiteSpline) -> Case:
    """Bounds from the power-basis coefficients: c[j, i] multiplies u^(k - j), u <= h_i."""
    c, x = fn._pp.c, np.array(fn.times)
    h = np.diff(x)
    k = c.shape[0] - 1

    def bound(d: int) -> float:
        return float(
            np.max(
                sum(
                    math.perm(k - j, d) * np.abs(c[j]) * h ** max(k - j - d, 0)
                    for j in range(k + 1)
                    if k - j >= d
                )
            )
        )

    return Case(fn, (bound(0), bound(1), bound(2)), bound(3), bound(4), tuple(x))


@st.composite
def hermite(draw: st.DrawFn) -> Case:
    gaps = draw(st.lists(fl(0.2, 1.0), min_size=1, max_size=6))
    x = np.concatenate([[draw(fl(-2.5, 0.0))], gaps]).cumsum()
    n = x.size
    y, d1 = (draw(st.lists(real, min_size=n, max_size=n)) for _ in range(2))
    d2 = draw(st.one_of(st.none(), st.lists(real, min_size=n, max_size=n)))
    return _pp_case(HermiteSpline(tuple(x), y, d1, d2))


leaves = st.one_of(constants(), polynomials(), sinusoids(), ramps(), tabulated(), hermite())


@st.composite
def combos(draw: st.DrawFn) -> Case:
    parts = draw(st.lists(leaves, min_size=1, max_size=3))
    k, off = draw(fl(-3.0, 3.0)), draw(real)
    s = tuple(abs(k) * sum(p.s[i] for p in parts) for i in range(3))
    knots = tuple(t for p in parts for t in p.knots)
    fn = Scaled(Sum([p.fn for p in parts]), k, off)
    m3, m4 = abs(k) * sum(p.m3 for p in parts), abs(k) * sum(p.m4 for p in parts)
    return Case(fn, (s[0] + abs(off), s[1], s[2]), m3, m4, knots)


any_case = st.one_of(leaves, combos())
times = fl(T_LO, T_HI)


@settings(max_examples=300, deadline=None)
@given(any_case, times)
def test_derivatives_match_central_differences(case: Case, t: float) -> None:
    # Keep the stencil [t - H, t + H] inside one smooth piece.
    assume(all(abs(t - k) > 2 * H for k in case.knots))
    fm, f0, fp = case.fn(t - H), case.fn(t), case.fn(t + H)
    _, fd, fdd = case.fn.derivatives(t)
    s0, s1, s2 = case.s
    # Central difference: truncation H^2 f'''/6 (resp. H^2 f''''/12), round-off of the f
    # values (each off by a few EPS s0) divided by 2H (resp. H^2), plus the rounding in the
    # exact derivative itself; x10 margin for the "few".
    tol1 = 10 * (H**2 * case.m3 / 6 + 4 * EPS * s0 / H + 4 * EPS * s1)
    tol2 = 10 * (H**2 * case.m4 / 12 + 8 * EPS * s0 / H**2 + 4 * EPS * s2)
    assert abs((fp - fm) / (2 * H) - fd) <= tol1
    assert abs((fp - 2 * f0 + fm) / H**2 - fdd) <= tol2


@settings(max_examples=300, deadline=None)
@given(st.lists(any_case, min_size=1, max_size=4), st.lists(times, min_size=1, max_size=4))
def test_compiled_matches_python(cases: list[Case], ts: list[float]) -> None:
    fn_kind, fn_ptr, fn_data = encode_functions([c.fn for c in cases])
    fval = np.full((len(cases), 3), np.nan)
    for t in ts:
        eval_all(fn_kind, fn_ptr, fn_data, t, fval)
        for k, c in enumerate(cases):
            ref = np.array(c.fn.derivatives(t))
            # 1e-12 relative; the absolute part is relative to the condition scale s, for
            # when the result cancels to ~0 (e.g. a polynomial near a root).
            np.testing.assert_allclose(fval[k], ref, rtol=1e-12, atol=1e-12 * max(c.s))


@settings(max_examples=200, deadline=None)
@given(any_case, st.lists(fl(T_LO - 1.0, T_HI + 1.0), min_size=1, max_size=6))
def test_vectorised_evaluate_equals_derivatives(case: Case, ts: list[float]) -> None:
    """evaluate(t) (splines vectorised) gives exactly the scalar derivatives, outside the
    knot range too (end values held)."""
    got = case.fn.evaluate(np.array(ts))
    want = np.array([case.fn.derivatives(t) for t in ts])
    assert got.shape == (len(ts), 3)
    np.testing.assert_array_equal(got, want)


@settings(max_examples=200, deadline=None)
@given(tabulated(), fl(0.0, 1.0))
def test_tabulated_matches_scipy(case: Case, frac: float) -> None:
    fn = case.fn
    assert isinstance(fn, Tabulated)
    # min(): x0 + 1.0 * (xm - x0) can round one ulp past xm, where the end value is held.
    t = min(fn.times[0] + frac * (fn.times[-1] - fn.times[0]), fn.times[-1])
    cs = CubicSpline(np.array(fn.times), np.array(fn.values), bc_type=fn.bc_type)
    kind, data = fn.encode()
    got = eval_timefn(kind, data, 0, data.size, t)
    for nu in range(3):
        want = float(cs(t, nu))
        # (1e-300: values of the smallest normal size, ~2e-308, have subnormal derivatives,
        # whose last bits differ between the two orders of evaluation: 3.5e-323 vs 4e-323)
        tol = max(1e-12 * case.s[nu], 1e-300)
        assert fn.derivatives(t)[nu] == pytest.approx(want, rel=1e-12, abs=tol)
        assert got[nu] == pytest.approx(want, rel=1e-12, abs=tol)


@pytest.mark.parametrize("profile", RAMP_PROFILES)
def test_ramp_spot_values(profile: str) -> None:
    r = Ramp(2.0, 5.0, 1.0, 3.0, profile)
    assert r(2.0) == pytest.approx(3.5, abs=1e-14)  # every profile is symmetric: mean at mid
    assert r.derivatives(0.0) == (2.0, 0.0, 0.0)
    assert r.derivatives(9.0) == (5.0, 0.0, 0.0)
    for t_end, y in ((1.0, 2.0), (3.0, 5.0)):
        f, fd, fdd = r.derivatives(t_end)
        assert f == pytest.approx(y, abs=1e-14)
        assert fd == pytest.approx(0.0, abs=1e-13)
        # quintic and cycloidal start and stop with zero acceleration; cosine with pi^2/2 *
        # rise / duration^2 = pi^2 * 3 / 8, sign flipped at the end.
        want = 0.0 if profile != "cosine" else (3 * math.pi**2 / 8) * (1 if t_end == 1 else -1)
        assert fdd == pytest.approx(want, abs=1e-12)
    # Peak velocity at mid-ramp: quintic 15/8, cycloidal 2, cosine pi/2 times rise/duration.
    peak = {"quintic": 15 / 8, "cycloidal": 2.0, "cosine": math.pi / 2}[profile]
    assert r.derivatives(2.0)[1] == pytest.approx(peak * 1.5, rel=1e-14)


@pytest.mark.parametrize("t", [-0.7, 0.0, 0.25, 0.5, 1.0, 1.6])
def test_sinusoid_rest_to_rest_form(t: float) -> None:
    f = Sinusoid(-0.5, math.pi, math.pi / 2, 0.5).derivatives(t)
    want = ((1 - math.cos(math.pi * t)) / 2, math.pi / 2 * math.sin(math.pi * t))
    assert f[0] == pytest.approx(want[0], abs=1e-15)
    assert f[1] == pytest.approx(want[1], abs=1e-15)
    assert f[2] == pytest.approx(math.pi**2 / 2 * math.cos(math.pi * t), abs=1e-14)


def test_polynomial_and_constant_spot_values() -> None:
    # 1 + 2u + 3u^2 at u = t - t0 = 2: 17, 2 + 6u = 14, 6.
    assert Polynomial([1, 2, 3], t0=1.0).derivatives(3.0) == (17.0, 14.0, 6.0)
    assert Polynomial((4.0,)).derivatives(-2.0) == (4.0, 0.0, 0.0)
    assert Constant(-1.5).derivatives(7.0) == (-1.5, 0.0, 0.0)


def test_tabulated_reproduces_cubic_and_holds_ends() -> None:
    x = np.linspace(0.0, 2.0, 6)
    fn = Tabulated(x, x**3 - x, "not-a-knot")  # not-a-knot is exact on a single cubic
    kind, data = fn.encode()
    for t in (0.1, 0.4, 1.0, 1.9):
        want = (t**3 - t, 3 * t**2 - 1, 6 * t)
        assert fn.derivatives(t) == pytest.approx(want, abs=1e-12)
        assert eval_timefn(kind, data, 0, data.size, t) == pytest.approx(want, abs=1e-12)
    assert fn.derivatives(-1.0) == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    assert fn.derivatives(5.0) == pytest.approx((6.0, 0.0, 0.0), abs=1e-12)
    assert eval_timefn(kind, data, 0, data.size, 5.0) == pytest.approx((6.0, 0.0, 0.0))
    # Clamped: f_dot = 0 at both ends; natural: f_ddot = 0 at both ends.
    y = [0.0, 1.0, -1.0, 2.0]
    assert Tabulated([0, 1, 2, 3], y, "clamped").derivatives(3.0)[1] == pytest.approx(0, abs=1e-13)
    assert Tabulated([0, 1, 2, 3], y, "natural").derivatives(0.0)[2] == pytest.approx(0, abs=1e-13)
    # Two points: the not-a-knot spline degenerates to the straight line.
    assert Tabulated([0, 2], [1, 5]).derivatives(0.5) == pytest.approx((2.0, 2.0, 0.0))


def test_encoding_layout() -> None:
    assert [int(k) for k in FnKind] == [0, 1, 2, 3, 4, 5, 6]
    fns = [Constant(3), Ramp(0, 1, 0, 1, "cosine"), Tabulated([0, 1, 3], [0, 1, 0])]
    fn_kind, fn_ptr, fn_data = encode_functions(fns)
    assert fn_kind.dtype == np.int64 and fn_ptr.dtype == np.int64 and fn_data.dtype == float
    assert fn_kind.tolist() == [0, 3, 4]
    # Constant 1, Ramp 5, Tabulated with m = 2 segments: 1 + (m + 1) + 4 m = 12.
    assert fn_ptr.tolist() == [0, 1, 6, 18]
    assert fn_data[1:6].tolist() == [0.0, 1.0, 0.0, 1.0, 2.0]
    assert fn_data[6:10].tolist() == [2.0, 0.0, 1.0, 3.0]
    kind, data = Scaled(Constant(2.0), 3.0, 1.0).encode()
    assert kind == FnKind.SUM and data.tolist() == [1.0, 1.0, 0.0, 3.0, 1.0, 2.0]
    empty = encode_functions([])
    assert [a.shape for a in empty] == [(0,), (1,), (0,)] and empty[1][0] == 0
    fval = np.zeros((0, 3))
    eval_all(*empty, 0.0, fval)  # no functions: nothing to do, must not fail


def test_functions_are_immutable_and_hashable() -> None:
    a, b = Tabulated([0, 1, 2], [0, 1, 4]), Tabulated((0.0, 1.0, 2.0), np.array([0, 1, 4.0]))
    assert a == b and hash(a) == hash(b) and len({a, b, Polynomial([1, 2])}) == 2
    with pytest.raises(FrozenInstanceError):
        a.bc_type = "natural"  # type: ignore[misc]
    assert as_function(2) == Constant(2.0) and as_function(np.float64(0.5)) == Constant(0.5)
    assert as_function(a) is a


@pytest.mark.parametrize(
    ("make", "field", "value"),
    [
        (lambda: Ramp(0, 1, 2.0, 1.0), "t_end", "1.0"),
        (lambda: Ramp(0, 1, 0, 1, "linear"), "profile", "'linear'"),
        (lambda: Ramp(0, float("inf"), 0, 1), "end_value", "inf"),
        (lambda: Sinusoid(float("nan"), 1.0), "amplitude", "nan"),
        (lambda: Polynomial([]), "coefficients", "[]"),
        (lambda: Polynomial(["1"]), "coefficients[0]", "'1'"),
        (lambda: Polynomial(3.0), "coefficients", "3.0"),
        (lambda: Constant(True), "value", "True"),
        (lambda: Tabulated([0, 1, 1], [0, 1, 2]), "times[2]", "1.0"),
        (lambda: Tabulated([0, 1], [0, 1, 2]), "values", "[0, 1, 2]"),
        (lambda: Tabulated([0], [0]), "times", "[0]"),
        (lambda: Tabulated([0, 1], [0, float("inf")]), "values[1]", "inf"),
        (lambda: Tabulated([0, 1], [0, 1], "periodic"), "bc_type", "'periodic'"),
        (lambda: Scaled(Constant(1), factor=float("inf")), "factor", "inf"),
        (lambda: Sum([]), "functions", "[]"),
        (lambda: Sum([Constant(1), "x"]), "functions[1]", "'x'"),
        (lambda: as_function("1.0", owner="Driver 'd'", field="function"), "function", "'1.0'"),
        (lambda: as_function(float("nan")), "function", "nan"),
    ],
)
def test_validation_errors_name_field_and_value(make, field: str, value: str) -> None:
    with pytest.raises(ModelError) as err:
        make()
    assert f"'{field}'" in str(err.value) and value in str(err.value)


def test_evaluator_runs_without_jit() -> None:
    # The same evaluator must work as plain Python (NUMBA_DISABLE_JIT=1, e.g. for debugging).
    code = """
import numpy as np
from clearance.compile.functions import encode_functions
from clearance.kinematics.timefn import eval_all
from clearance.model.functions import *
fns = [Constant(1), Polynomial([1, -2, 3], 0.5), Sinusoid(2, 3, 0.1, 1), Ramp(0, 2, 0, 1),
       Tabulated([0, 1, 2, 4], [1, 0, 2, 1], "natural"), Scaled(Sum([Ramp(0, 1, 0, 2), 1]), 2)]
enc = encode_functions(fns)
fval = np.zeros((len(fns), 3))
for t in (-1.0, 0.3, 0.5, 1.7, 5.0):
    eval_all(*enc, t, fval)
    ref = np.array([f.derivatives(t) for f in fns])
    assert np.allclose(fval, ref, rtol=1e-12, atol=1e-12), (t, fval, ref)
print("ok")
"""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"


# ------------------------------------------------------------------ HermiteSpline (PPOLY)
def _hermite_atol(case: Case, nu: int) -> float:
    """Rounding scale of the nu-th derivative: the power-basis conversion spreads a few eps of
    every coefficient over the segment, amplified by 1 / h^nu (h >= 0.2 s here)."""
    h = float(np.min(np.diff(case.fn.times)))
    return 1e-11 * sum(case.s) / h**nu


@settings(max_examples=200, deadline=None)
@given(hermite(), fl(0.0, 1.0))
def test_hermite_matches_scipy(case: Case, frac: float) -> None:
    """Python and compiled evaluation equal scipy's own BPoly.from_derivatives (before the
    power-basis conversion) to rounding, for f, f_dot and f_ddot."""
    fn = case.fn
    assert isinstance(fn, HermiteSpline)
    t = min(fn.times[0] + frac * (fn.times[-1] - fn.times[0]), fn.times[-1])
    cols = [fn.values, fn.d1] + ([fn.d2] if fn.d2 is not None else [])
    bp = BPoly.from_derivatives(np.array(fn.times), np.column_stack(cols))
    kind, data = fn.encode()
    assert kind == FnKind.PPOLY
    got = eval_timefn(kind, data, 0, data.size, t)
    for nu in range(3):
        want = float(bp(t, nu))
        tol = _hermite_atol(case, nu)
        assert fn.derivatives(t)[nu] == pytest.approx(want, rel=1e-11, abs=tol)
        assert got[nu] == pytest.approx(want, rel=1e-11, abs=tol)


@settings(max_examples=100, deadline=None)
@given(hermite())
def test_hermite_interpolates_knot_data(case: Case) -> None:
    """Values, first and (quintic) second derivatives at every knot, to rounding; C2."""
    fn = case.fn
    assert isinstance(fn, HermiteSpline)
    kind, data = fn.encode()
    nd = 3 if fn.d2 is not None else 2
    assert fn.degree == 2 * nd - 1
    for i, t in enumerate(fn.times):
        want = (fn.values[i], fn.d1[i], fn.d2[i] if fn.d2 is not None else None)
        for got in (fn.derivatives(t), eval_timefn(kind, data, 0, data.size, t)):
            for nu in range(nd):
                assert got[nu] == pytest.approx(want[nu], rel=1e-11, abs=_hermite_atol(case, nu))
    # continuity of f'' across interior knots (C2 quintic; the cubic is only C1)
    for t in fn.times[1:-1]:
        lo, hi = fn._pp(t - 1e-12, 2), fn._pp(t + 1e-12, 2)
        if fn.d2 is not None:
            tol = _hermite_atol(case, 2) + 4e-12 * case.m3  # f''' over the 2e-12 s gap
            assert float(lo) == pytest.approx(float(hi), rel=1e-8, abs=tol)


def test_hermite_reproduces_quintic_and_holds_ends() -> None:
    """Exact on a single quintic polynomial (any knots); end value held outside the range."""
    p = np.polynomial.Polynomial([0.3, -1.0, 0.5, 2.0, -0.7, 0.2])
    x = np.array([0.0, 0.3, 1.1, 2.0])
    fn = HermiteSpline(x, p(x), p.deriv(1)(x), p.deriv(2)(x))
    kind, data = fn.encode()
    assert data[:2].tolist() == [3.0, 5.0] and data.size == 2 + 4 + 3 * 6
    for t in (0.0, 0.1, 0.7, 1.5, 2.0):
        want = (p(t), p.deriv(1)(t), p.deriv(2)(t))
        assert fn.derivatives(t) == pytest.approx(want, rel=1e-12, abs=1e-12)
        assert eval_timefn(kind, data, 0, data.size, t) == pytest.approx(want, rel=1e-12, abs=1e-12)
    assert fn.derivatives(-1.0) == pytest.approx((p(0.0), 0.0, 0.0), abs=1e-14)
    assert eval_timefn(kind, data, 0, data.size, 3.0) == pytest.approx((p(2.0), 0.0, 0.0))
    # d2 = None: the cubic Hermite (C1) reproduces a cubic
    q = np.polynomial.Polynomial([1.0, -2.0, 0.5, 0.25])
    cub = HermiteSpline(x, q(x), q.deriv(1)(x), None)
    assert cub.degree == 3
    assert cub.derivatives(1.4) == pytest.approx((q(1.4), q.deriv(1)(1.4), q.deriv(2)(1.4)))
    # immutable, hashable, usable in sums and as a driver function (compiled through SUM)
    same = HermiteSpline(tuple(x), tuple(p(x)), tuple(p.deriv(1)(x)), tuple(p.deriv(2)(x)))
    assert fn == same and hash(fn) == hash(same) and fn != cub
    enc = encode_functions([Scaled(fn, 2.0, 1.0)])
    fval = np.zeros((1, 3))
    eval_all(*enc, 0.7, fval)
    assert fval[0] == pytest.approx([2 * p(0.7) + 1, 2 * p.deriv(1)(0.7), 2 * p.deriv(2)(0.7)])


@pytest.mark.parametrize(
    ("make", "field", "value"),
    [
        (lambda: HermiteSpline([0, 1, 1], [0, 1, 2], [0, 0, 0], None), "times[2]", "1.0"),
        (lambda: HermiteSpline([0, 1], [0, 1, 2], [0, 0], None), "values", "[0, 1, 2]"),
        (lambda: HermiteSpline([0, 1], [0, 1], [0], None), "d1", "[0]"),
        (lambda: HermiteSpline([0, 1], [0, 1], [0, 0], [0, 0, 1]), "d2", "[0, 0, 1]"),
        (lambda: HermiteSpline([0, 1], [0, 1], [0, float("nan")], None), "d1[1]", "nan"),
        (lambda: HermiteSpline([0], [0], [0], [0]), "times", "[0]"),
    ],
)
def test_hermite_validation(make, field: str, value: str) -> None:
    with pytest.raises(ModelError) as err:
        make()
    assert f"'{field}'" in str(err.value) and value in str(err.value)


def test_hermite_runs_without_jit() -> None:
    code = """
import numpy as np
from clearance.compile.functions import encode_functions
from clearance.kinematics.timefn import eval_all
from clearance.model.functions import HermiteSpline
x = np.array([0.0, 0.4, 1.0, 1.3])
fns = [HermiteSpline(x, np.sin(x), np.cos(x), -np.sin(x)), HermiteSpline(x, x**2, 2 * x, None)]
enc = encode_functions(fns)
fval = np.zeros((2, 3))
for t in (-1.0, 0.0, 0.3, 0.4, 1.29, 1.3, 2.0):
    eval_all(*enc, t, fval)
    ref = np.array([f.derivatives(t) for f in fns])
    assert np.allclose(fval, ref, rtol=1e-12, atol=1e-12), (t, fval, ref)
print("ok")
"""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"
