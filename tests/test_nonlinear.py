"""The nonlinear-dynamics toolkit against known results: spectra of sums of sinusoids, the
Duffing oscillator's period-doubling cascade, the Lorenz system's largest Lyapunov exponent,
the 0-1 test on regular and chaotic series, section crossings of analytic signals, and a
forced linear oscillator built as a mechanism (stroboscopic fixed point and Lyapunov
exponent against the closed form)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

import clearance as cl
from clearance.model.errors import ModelError
from clearance.nonlinear import (
    OdeTrajectory,
    amplitude_spectrum,
    classify,
    distinct_points,
    dominant_frequencies,
    harmonics,
    largest_lyapunov,
    mechanism_lyapunov,
    ode_stroboscopic,
    power_spectral_density,
    recurrence_period,
    rosenstein,
    section_crossings,
    spectrogram,
    steady_state,
    zero_one_test,
)

# ---------------------------------------------------------------- spectra


def _sines(t, lines, offset=0.0):
    return offset + sum(a * np.sin(2 * np.pi * f * t + p) for f, a, p in lines)


def test_spectrum_of_known_sinusoids():
    """Three lines off the bin grid, a mean: frequencies, amplitudes and phases recovered
    (least-squares refinement exact to the data's rounding; the raw spectral estimate
    within the window's scalloping)."""
    lines = [(3.3, 2.0, 0.4), (11.7, 0.5, -1.0), (27.05, 0.1, 2.0)]
    dt = 1e-3
    t = dt * np.arange(4000)
    x = _sines(t, lines, offset=0.7)
    peaks = dominant_frequencies(x, dt, count=3)
    assert len(peaks) == 3
    for p, (f, a, ph) in zip(peaks, lines, strict=True):
        assert p.frequency == pytest.approx(f, rel=1e-9)
        assert p.amplitude == pytest.approx(a, rel=1e-8)
        assert math.remainder(p.phase - ph, 2 * math.pi) == pytest.approx(0.0, abs=1e-7)
    raw = dominant_frequencies(x, dt, count=3, refine=False)
    for p, (f, a, _) in zip(raw, lines, strict=True):
        assert abs(p.frequency - f) < 0.05 / (t.size * dt)  # 1/20 of a bin
        assert p.amplitude == pytest.approx(a, rel=0.01)
    # on-bin line: the plain spectrum's peak height is the amplitude (scaling)
    f, A = amplitude_spectrum(np.sin(2 * np.pi * 5.0 * t) * 1.5, dt, window="boxcar")
    i = int(np.argmax(A))
    assert f[i] == pytest.approx(5.0) and A[i] == pytest.approx(1.5, rel=1e-12)


def test_psd_integrates_to_variance_and_spectrogram_tracks_a_chirp():
    rng = np.random.default_rng(1)
    dt = 1e-3
    x = rng.standard_normal(50_000) * 0.3 + np.sin(2 * np.pi * 40 * dt * np.arange(50_000))
    f, P = power_spectral_density(x, dt)
    assert np.trapezoid(P, f) == pytest.approx(np.var(x), rel=0.02)
    assert f[np.argmax(P)] == pytest.approx(40.0, abs=f[1])
    t = dt * np.arange(20_000)
    chirp = np.sin(2 * np.pi * (10 * t + 5 * t**2))  # f(t) = 10 + 10 t
    fs, ts, S = spectrogram(chirp, dt, nperseg=1024)
    fpk = fs[np.argmax(S, axis=0)]
    assert np.max(np.abs(fpk - (10 + 10 * ts))) < 2 * fs[1]
    assert np.allclose(harmonics(2.0, 9.0), [2, 4, 6, 8])
    assert np.allclose(harmonics(2.0, 3.5, subharmonics=2), [1, 2, 3])


def test_spectra_refuse_bad_input():
    with pytest.raises(ModelError, match="dt"):
        amplitude_spectrum(np.ones(100), 0.0)
    with pytest.raises(ModelError, match="finite"):
        dominant_frequencies(np.r_[np.ones(50), np.nan], 1e-3)


# ---------------------------------------------------------------- Poincare sections


def test_section_crossings_of_a_sinusoid():
    """x = sin(w t) crosses 0.5 upward at asin(0.5)/w + k 2 pi / w: located on a coarse grid
    (20 samples per period) to the cubic's O(dt^4), with the velocity interpolated."""
    w = 3.0
    t = np.linspace(0, 10, 201)
    x, xd = np.sin(w * t), w * np.cos(w * t)
    times, other = section_crossings(t, x, xd, value=0.5, direction=1, others={"v": (xd, None)})
    exact = (math.asin(0.5) + 2 * np.pi * np.arange(times.size)) / w
    assert times.size == 5
    assert np.max(np.abs(times - exact)) < 2e-5
    assert np.max(np.abs(other["v"] - w * math.cos(math.asin(0.5)))) < 0.02
    down, _ = section_crossings(t, x, xd, value=0.5, direction=-1)
    assert np.allclose(np.sin(w * down), 0.5, atol=1e-4) and np.all(np.cos(w * down) < 0)
    tf = np.linspace(0, 10, 20001)
    fine, _ = section_crossings(tf, np.sin(w * tf), w * np.cos(w * tf), value=0.5)
    assert np.max(np.abs(fine - exact)) < 1e-12  # converges as dt^4


def test_recurrence_and_distinct_points():
    P = np.array([[1.0, 0.0], [2.0, 1.0], [1.0, 0.0], [2.0, 1.0], [1.0, 0.0]])
    assert recurrence_period(P, tol=1e-9) == 2
    assert distinct_points(P, tol=1e-9) == 2
    assert recurrence_period(P[:2], tol=1e-9) is None  # too few points to tell
    rng = np.random.default_rng(0)
    assert recurrence_period(rng.random((50, 2)), tol=1e-6) is None


# ---------------------------------------------------------------- Duffing


W_DUFFING = 1.2
T_DUFFING = 2 * math.pi / W_DUFFING


def _duffing(g):
    def f(t, y):
        return [y[1], -0.3 * y[1] + y[0] - y[0] ** 3 + g * math.cos(W_DUFFING * t)]

    return f


# x'' + 0.3 x' - x + x^3 = g cos(1.2 t) from (x, x') = (1, 0): the Poincare sections of
# Jordan & Smith, "Nonlinear Ordinary Differential Equations", 4th ed., Oxford 2007, sec.
# 13.3 (reproduced in Wikipedia's "Duffing equation", Examples): period 1 at g = 0.20, 2 at
# 0.28, 4 at 0.29 (the doubling cascade), 5 at 0.37, chaos at 0.50, period 2 at 0.65
# (RECALLED from those sources; the cascade points agree with this integration)
DUFFING = [(0.20, 1), (0.28, 2), (0.29, 4), (0.37, 5), (0.65, 2)]


@pytest.mark.parametrize(("g", "period"), DUFFING)
def test_duffing_periodic_responses(g, period):
    _, P = ode_stroboscopic(
        _duffing(g), [1.0, 0.0], period=T_DUFFING, periods=260, transient_periods=200
    )
    c = classify(P, zero_one=False)
    assert c.kind == f"period-{period}" and c.distinct == period, str(c)


def test_duffing_chaos_at_g_05():
    """g = 0.5: no recurrence in 500 periods, the 0-1 test says chaotic and the two-trajectory
    Lyapunov exponent is positive (the cascade's period-2 orbit at 0.28: negative)."""
    f = _duffing(0.5)
    _, P = ode_stroboscopic(f, [1.0, 0.0], period=T_DUFFING, periods=600, transient_periods=100)
    ref = OdeTrajectory(f, 100 * T_DUFFING, P[0], rtol=1e-9, atol=1e-11)
    pert = OdeTrajectory(f, 100 * T_DUFFING, P[0], rtol=1e-9, atol=1e-11)
    lam = largest_lyapunov(ref, pert, interval=T_DUFFING, intervals=120, transient_intervals=5)
    c = classify(P, lyapunov=lam)
    assert c.kind == "chaotic" and c.period is None, str(c)
    assert c.zero_one > 0.9 and c.distinct > 400
    assert lam.exponent > 5 * lam.standard_error > 0
    g = _duffing(0.28)
    _, P2 = ode_stroboscopic(g, [1.0, 0.0], period=T_DUFFING, periods=201, transient_periods=200)
    ref = OdeTrajectory(g, 200 * T_DUFFING, P2[0])
    pert = OdeTrajectory(g, 200 * T_DUFFING, P2[0])
    lam2 = largest_lyapunov(ref, pert, interval=T_DUFFING, intervals=30, transient_intervals=3)
    assert lam2.exponent < -3 * lam2.standard_error


# ---------------------------------------------------------------- Lorenz


@njit(cache=True)
def _lorenz_rk4(y, tau, h):
    """Classical RK4 of the Lorenz system (sigma 10, rho 28, beta 8/3) over tau."""

    def f(y):
        return np.array(
            [10.0 * (y[1] - y[0]), y[0] * (28.0 - y[2]) - y[1], y[0] * y[1] - 8.0 / 3.0 * y[2]]
        )

    for _ in range(int(round(tau / h))):
        k1 = f(y)
        k2 = f(y + 0.5 * h * k1)
        k3 = f(y + 0.5 * h * k2)
        k4 = f(y + h * k3)
        y = y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return y


class _Lorenz:
    """A `Trajectory` of the Lorenz system written directly (compiled RK4, h = 2 ms)."""

    def __init__(self, y, t=0.0):
        self.y, self.t = np.array(y, dtype=float), t

    def advance(self, tau):
        self.y = _lorenz_rk4(self.y, tau, 0.002)
        self.t += tau

    def place(self, y):
        self.y = np.array(y, dtype=float)
        return self.y

    def distance_state(self):
        return self.y


LORENZ_LLE = 0.9056  # Sprott, "Chaos and Time-Series Analysis", Oxford 2003, table A.1


def _lorenz(t, y):
    return [10 * (y[1] - y[0]), y[0] * (28 - y[2]) - y[1], y[0] * y[1] - 8 / 3 * y[2]]


def test_lorenz_lyapunov_two_trajectories():
    ref = _Lorenz([1.0, 1.0, 20.0])
    ref.advance(100.0)  # onto the attractor
    pert = _Lorenz(ref.y, ref.t)
    lam = largest_lyapunov(ref, pert, interval=1.0, intervals=5000, transient_intervals=10)
    assert abs(lam.exponent - LORENZ_LLE) < 0.01, str(lam)
    assert lam.standard_error < 0.004
    # the same with SciPy's DOP853 (OdeTrajectory), shorter: within its statistical error
    r2 = OdeTrajectory(_lorenz, ref.t, ref.y, rtol=1e-9, atol=1e-10)
    p2 = OdeTrajectory(_lorenz, ref.t, ref.y, rtol=1e-9, atol=1e-10)
    lam2 = largest_lyapunov(r2, p2, interval=1.0, intervals=300, transient_intervals=5)
    assert abs(lam2.exponent - LORENZ_LLE) < 4 * lam2.standard_error + 0.01, str(lam2)


def test_lorenz_time_series_methods():
    """Rosenstein's delay-embedding estimate from x(t) alone (10 000 samples, dt 0.01)
    within its known bias (a few to ~10 % low or high with embedding dimension; Rosenstein
    et al. 1993, Table 3), and the 0-1 test: K ~ 1 for x sampled every 0.5 (600 samples),
    K ~ 0 for a
    quasi-periodic signal."""
    from scipy.integrate import solve_ivp

    s = solve_ivp(
        _lorenz, (0, 350), [1, 1, 20], rtol=1e-10, atol=1e-10, dense_output=True, method="DOP853"
    )
    x = s.sol(50 + 0.01 * np.arange(10_000))[0]
    est = rosenstein(x, 0.01, dimension=5)
    assert abs(est.exponent - LORENZ_LLE) < 0.1 * LORENZ_LLE, est.exponent
    assert zero_one_test(s.sol(50 + 0.5 * np.arange(600))[0]).K > 0.95
    t = np.arange(1500)
    quasi = np.sin(0.7 * t) + 0.5 * np.sin(0.7 * math.sqrt(2) * t)
    assert abs(zero_one_test(quasi).K) < 0.1
    logistic = np.empty(1500)
    logistic[0] = 0.3
    for i in range(1499):
        logistic[i + 1] = 3.97 * logistic[i] * (1 - logistic[i])
    assert zero_one_test(logistic[200:]).K > 0.95


# ---------------------------------------------------------------- mechanisms


def _forced_oscillator(m_=2.0, k=200.0, c=4.0, F=5.0, w=7.0) -> cl.Mechanism:
    """A mass on a prismatic joint along x, a spring-damper to ground (anchored 0.5 m
    behind, free length 0.5 m: linear along the slide) and a force F sin(w t)."""
    mech = cl.Mechanism("forced oscillator", gravity=(0, 0, 0))
    mech.add(
        cl.Body("mass", m_, (0.01, 0.01, 0.01)),
        cl.Marker.on_axis("g", "ground", axis=(1, 0, 0)),
        cl.Marker.on_axis("b", "mass", axis=(1, 0, 0)),
        cl.Marker("anchor", "ground", (-0.5, 0, 0)),
        cl.Prismatic("p", "g", "b"),
        cl.SpringDamper("k", "anchor", "b", stiffness=k, damping=c, free_length=0.5),
        cl.PointForce("F", "b", (1, 0, 0), cl.Sinusoid(F, w)),
    )
    return mech


def test_linear_oscillator_stroboscopic_fixed_point():
    """m x'' + c x' + k x = F sin(w t): the stroboscopic map's fixed point is the steady state
    X sin(w t - phi) at t = j T, X = F / sqrt((k - m w^2)^2 + (c w)^2), tan phi = c w /
    (k - m w^2), to 1e-8 (the transient has decayed to e^{-50 c T / 2m} ~ 3e-20)."""
    m_, k, c, F, w = 2.0, 200.0, 4.0, 5.0, 7.0
    T = 2 * math.pi / w
    ss = steady_state(
        _forced_oscillator(m_, k, c, F, w),
        period=T,
        periods=55,
        transient_periods=50,
        samples_per_period=40,
        rtol=1e-11,
        atol=1e-13,
    )
    assert ss.result.success and ss.strobe.size == 6
    assert np.allclose(ss.strobe_times, T * np.arange(50, 56), rtol=0, atol=1e-13)
    X = F / math.hypot(k - m_ * w * w, c * w)
    phi = math.atan2(c * w, k - m_ * w * w)
    x = ss.result.position("mass")[ss.strobe, 0]
    v = ss.result.velocity("mass")[ss.strobe, 0]
    assert np.max(np.abs(x - X * math.sin(-phi))) < 1e-8 * X
    assert np.max(np.abs(v - X * w * math.cos(-phi))) < 1e-8 * X * w
    c_ = classify(np.column_stack([x, v]), zero_one=False)
    assert c_.kind == "period-1"
    # phase 1/4: the samples a quarter period later, X sin(pi/2 - phi)
    q = steady_state(
        _forced_oscillator(m_, k, c, F, w),
        period=T,
        periods=52,
        transient_periods=50,
        samples_per_period=40,
        phase=0.25,
        rtol=1e-11,
        atol=1e-13,
    )
    xq = q.result.position("mass")[q.strobe, 0]
    assert np.max(np.abs(xq - X * math.sin(math.pi / 2 - phi))) < 1e-8 * X


def test_linear_oscillator_lyapunov_exponent():
    """Both exponents of the underdamped linear oscillator are -c / (2 m): the two-trajectory
    method through the compiled loop finds it (per period the separation shrinks by exactly
    e^{-c T / 2m} once aligned... up to the rotation within the period, averaged out)."""
    m_, c = 2.0, 4.0
    T = 2 * math.pi / 7.0
    lam = mechanism_lyapunov(
        _forced_oscillator(m_=m_, c=c), interval=T, intervals=60, transient_intervals=2
    )
    assert lam.exponent == pytest.approx(-c / (2 * m_), rel=0.03), str(lam)


def test_steady_state_refuses_bad_options():
    mech = _forced_oscillator()
    with pytest.raises(ModelError, match="transient_periods"):
        steady_state(mech, period=1.0, periods=3, transient_periods=3)
    with pytest.raises(ModelError, match="period"):
        steady_state(mech, period=-1.0, periods=3)
    with pytest.raises(ModelError, match="dt_out"):
        steady_state(mech, period=1.0, periods=3, dt_out=0.1)


# ---------------------------------------------------------------- impact oscillator


def _impact_oscillator(m_=1.0, k=1000.0, d=2.0, F0=2.0, w=25.0, c=1e-3, R_b=0.01):
    """A 1 kg ball on a prismatic joint along x inside a ground socket with 1 mm radial
    clearance (Flores contact, c_r 0.9, steel; no friction), a linear spring-damper and a
    force F0 sin(w t): a two-sided impact oscillator."""
    mech = cl.Mechanism("impact oscillator", gravity=(0, 0, 0))
    mech.add(
        cl.Body("ball", m_, (0.01, 0.01, 0.01)),
        cl.Marker.on_axis("g", "ground", axis=(1, 0, 0)),
        cl.Marker.on_axis("b", "ball", axis=(1, 0, 0)),
        cl.Marker("anchor", "ground", (-0.5, 0, 0)),
        cl.Prismatic("p", "g", "b"),
        cl.Spherical(
            "S",
            "g",
            "b",
            clearance=cl.Clearance(
                ball_radius=R_b, radial_clearance=c, normal=cl.Flores(restitution=0.9)
            ),
        ),
        cl.SpringDamper("k", "anchor", "b", stiffness=k, damping=d, free_length=0.5),
        cl.PointForce("F", "b", (1, 0, 0), cl.Sinusoid(F0, w)),
    )
    return mech


def test_impact_oscillator_periodic_orbit_against_independent_oracle():
    """The period-1 impacting orbit (F0 = 2 N, w = 25 rad/s: one impact on each side per
    period) against tests/oracles/impact_oscillator.py, a hybrid SciPy integration written
    separately from the specification (events located by solve_ivp, Newton on the period
    map): the stroboscopic fixed point, the impact phases and onset velocities, and the
    largest Lyapunov exponent from the oracle's monodromy matrix (-1.8936 1/s)."""
    from oracles import impact_oscillator as ref

    w, T, c = 25.0, 2 * math.pi / 25.0, 1e-3
    osc = ref.ImpactOscillator(
        m=1.0, k=1000.0, d=2.0, F0=2.0, w=w, c=c,
        K=ref.hertz_internal_stiffness(0.01, c), c_r=0.9,
    )  # fmt: skip
    y_star, info = ref.find_fixed_point(osc, ref.strobe(osc, 40, 40)[0])
    assert info["converged"]
    ss = steady_state(
        _impact_oscillator(),
        period=T,
        periods=60,
        transient_periods=50,
        samples_per_period=50,
        rtol=1e-10,
        atol=1e-13,
    )
    r = ss.result
    assert r.success
    x = r.position("ball")[ss.strobe, 0]
    v = r.velocity("ball")[ss.strobe, 0]
    assert np.max(np.abs(x - y_star[0])) < 1e-8 * c, (x, y_star)  # (measured: 1e-9)
    assert np.max(np.abs(v - y_star[1])) < 1e-8 * w * c
    assert classify(np.column_stack([x / c, v / (w * c)]), zero_one=False).kind == "period-1"
    table = ref.impact_table(ref.simulate(osc, 60 * T), 50, 60)
    ev = r.impacts("S")
    onsets = ev[ev[:, 0] >= 50 * T]
    assert onsets.shape[0] == 2 * 10 == len(table.t)
    assert np.max(np.abs(onsets[:, 0] - np.asarray(table.t))) < 1e-9  # (2e-11 s)
    assert np.max(np.abs(onsets[:, 3] - np.asarray(table.delta_dot))) < 1e-8 * 0.0632
    lam = ref.lyapunov_fd(osc, y_star)
    est = mechanism_lyapunov(
        _impact_oscillator(), interval=T, intervals=200, transient_intervals=2, rtol=1e-9
    )
    # the multipliers are complex (the separation turns within a period): the estimate
    # converges as 1 / (intervals T); 200 periods give 0.1 % (40 gave 5 %)
    assert est.exponent == pytest.approx(lam.lambda_max, rel=0.02), (str(est), lam.lambda_max)


# ---------------------------------------------------------------- sections in the loop


def test_section_located_in_the_loop_on_the_dense_output():
    """The linear oscillator's velocity crosses 0 downward where x = X at
    t = (pi/2 + phi)/w + n T: located on the dense output of the accepted steps (coarse
    output grid, 10 samples per period) to 1e-12 s, the state there to 1e-12 X; both
    directions give twice as many crossings; vern7 (erk_high) and tsit5 (erk54) alike."""
    m_, k, c, F, w = 2.0, 200.0, 4.0, 5.0, 7.0
    T = 2 * math.pi / w
    X = F / math.hypot(k - m_ * w * w, c * w)
    phi = math.atan2(c * w, k - m_ * w * w)
    t0 = (math.pi / 2 + phi) / w
    for method in ("vern7", "tsit5"):
        r = cl.simulate(
            _forced_oscillator(),
            55 * T,
            dt_out=T / 10,
            method=method,
            rtol=1e-11,
            atol=1e-13,
            section=cl.Section("mass", "vx", 0.0, -1),
        )
        assert r.success and r.section_label == "mass.vx = 0, downward"
        ts, ys = r.section_time, r.section_state
        assert ts.size == 55 and r.stats["section_crossings"] == 55
        late = ts > 50 * T  # the transient has decayed (e^-50: 1e-22)
        n = np.round((ts[late] - t0) / T)
        assert np.max(np.abs(ts[late] - (t0 + n * T))) < 1e-12 * 50 * T, method
        assert np.max(np.abs(ys[late, 0] - X)) < 1e-12 * X
        assert np.max(np.abs(ys[:, 7])) < 1e-12  # vx at the crossing (q: 7, then v)
    both = cl.simulate(
        _forced_oscillator(),
        10 * T,
        rtol=1e-10,
        atol=1e-13,
        section=cl.Section("mass", "vx", 0.0, 0),
    )
    assert both.section_time.size in (19, 20, 21)
    few = cl.simulate(
        _forced_oscillator(),
        10 * T,
        rtol=1e-10,
        atol=1e-13,
        section=cl.Section("mass", "x", 0.0, 1, max_crossings=3),
    )
    full = cl.simulate(
        _forced_oscillator(), 10 * T, rtol=1e-10, atol=1e-13, section=cl.Section("mass", "x")
    )
    n = full.section_time.size  # (9: it starts on the section, at rest)
    assert few.section_time.size == 3 and few.stats["section_crossings"] == n > 3
    assert np.array_equal(few.section_time, full.section_time[:3])
    assert f"kept the first 3 of {n} crossings" in few.message


def test_section_of_the_impact_oscillator_against_the_oracle():
    """The ball crossing the socket centre upward (x = 0, +1) between its impacts: times
    and velocities against the independent hybrid oracle's dense output."""
    from oracles import impact_oscillator as ref
    from scipy.optimize import brentq

    w, c = 25.0, 1e-3
    T = 2 * math.pi / w
    osc = ref.ImpactOscillator(
        m=1.0, k=1000.0, d=2.0, F0=2.0, w=w, c=c,
        K=ref.hertz_internal_stiffness(0.01, c), c_r=0.9,
    )  # fmt: skip
    sim = ref.simulate(osc, 20 * T)
    r = cl.simulate(
        _impact_oscillator(),
        20 * T,
        rtol=1e-11,
        atol=1e-13,
        section=cl.Section("ball", "x", 0.0, 1),
    )
    # (at rtol 1e-10 one slow crossing, 0.86 s, differs by 2.6e-9 s; at 1e-11 by 4e-11 s:
    # the trajectories' error, not the location's)
    # the oracle's upward crossings: sign changes on a fine grid, refined by brentq
    grid = np.linspace(1e-9, 20 * T, 200_001)
    x = sim.state(grid)[:, 0]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    te = np.array([brentq(lambda s: sim.state(s)[0], grid[i], grid[i + 1], xtol=1e-15) for i in up])
    assert r.success and r.section_time.size == te.size > 20  # (the transient crosses more)
    assert np.max(np.abs(r.section_time - te)) < 1e-10
    ve = sim.state(te)[:, 1]
    assert np.max(np.abs(r.section_state[:, 7] - ve)) < 1e-7 * np.max(np.abs(ve))


def test_section_refuses_what_it_cannot_do():
    mech = _forced_oscillator()
    with pytest.raises(ModelError, match="adaptive method"):
        cl.simulate(mech, 1.0, method="rk4", section=cl.Section("mass", "x"))
    with pytest.raises(ModelError, match="a moving body"):
        cl.simulate(mech, 1.0, section=cl.Section("platform", "x"))
    with pytest.raises(ModelError, match="coordinate"):
        cl.Section("mass", "q7")
    with pytest.raises(ModelError, match="direction"):
        cl.Section("mass", "x", direction=2)


# ---------------------------------------------------------------- review findings


def test_lyapunov_of_a_clearance_mechanism_that_stays_out_of_contact():
    """F0 = 0.1 N never reaches the 1 mm gap: a linear oscillator, both exponents -d/2m =
    -1 1/s. (The friction states of the contact points do not move out of contact: in the
    separation they were a neutral direction that held the estimate at 0.)"""
    T = 2 * math.pi / 25.0
    lam = mechanism_lyapunov(
        _impact_oscillator(F0=0.1), interval=T, intervals=240, transient_intervals=2
    )
    assert lam.exponent == pytest.approx(-1.0, rel=0.05), str(lam)


def test_classification_does_not_mistake_a_transient_or_noise():
    """A spiral converging to a fixed point is not quasi-periodic (its K is ~0 too); a
    channel that varies at round-off next to a period-1 one does not make it chaotic."""
    k = np.arange(300)
    spiral = np.column_stack([0.97**k * np.cos(0.9 * k) + 1.0, 0.97**k * np.sin(0.9 * k)])
    c = classify(spiral[50:])
    assert c.kind == "undetermined" and "converge" in str(c), str(c)
    quasi = np.column_stack([np.cos(0.9 * math.sqrt(2) * k), np.sin(0.9 * math.sqrt(2) * k)])
    assert classify(quasi).kind == "quasi-periodic"
    from clearance.nonlinear.analyze import _scale

    rng = np.random.default_rng(0)
    z = 0.7 + 1e-16 * rng.standard_normal(300)  # period-1 at round-off
    e = np.full(300, 1e-4)
    P = np.column_stack([z / _scale(z), e / _scale(e)])
    assert classify(P, tol=1e-3).kind == "period-1"


def test_rosenstein_finds_no_divergence_in_a_periodic_signal():
    t = 0.01 * np.arange(20_000)
    x = np.sin(2 * np.pi * t) + 1e-9 * np.random.default_rng(1).standard_normal(t.size)
    d = rosenstein(x, 0.01)
    assert not d.diverges, (d.exponent, d.fit)
