"""Post-processing by verified interpolation (clearance.integrate.post) against the exact
evaluation of every sample (post_tol = 0): the oracle is the same quantity evaluated at
each sample's state, and the bound is the documented one, post_tol |x| + atol, with |x| the
channel's largest magnitude over the run (the code's window maximum is at most that)."""

from __future__ import annotations

import numpy as np
import pytest
from models import rod_on_clearance_joint

import clearance as cl
from clearance.contact.element import make_contact_state
from clearance.dynamics.rhs import make_work
from clearance.integrate.post import VIOLATION_RTOL, Blocks, PostArrays, post_process
from clearance.layout import NCOUT, NPOUT
from clearance.mechanisms.examples import double_pendulum


def crane(profile: str) -> cl.Mechanism:
    """A 2 kg cart on a horizontal rail, driven 0.1 m over [0.2, 0.7] s by a rest-to-rest
    ramp, with a 0.4 m, 1 kg pendulum on a hinge: "cosine" makes the cart's acceleration
    jump at both ends of the ramp (a kink the interpolation must not smooth over),
    "quintic" keeps it continuous."""
    L = 0.4
    m = cl.Mechanism("crane", gravity=(0.0, 0.0, -9.81))
    m.add(
        cl.Body("cart", 2.0, (0.01, 0.01, 0.01)),
        cl.Body(
            "pendulum",
            1.0,
            (L * L / 12, L * L / 12, 1e-4),
            position=(0.0, 0.0, -L / 2),
            angular_velocity=(0.0, 1.0, 0.0),
        ),
        cl.Marker.on_axis("rail", "ground", axis=(1, 0, 0)),
        cl.Marker.on_axis("carriage", "cart", axis=(1, 0, 0)),
        cl.Marker.on_axis("hinge_c", "cart", axis=(0, 1, 0)),
        cl.Marker.on_axis("hinge_p", "pendulum", (0.0, 0.0, L / 2), axis=(0, 1, 0)),
        cl.Prismatic("rail_joint", "rail", "carriage"),
        cl.Revolute("hinge", "hinge_c", "hinge_p"),
        cl.PrismaticDriver("drive", "rail_joint", cl.Ramp(0.0, 0.1, 0.2, 0.7, profile)),
    )
    return m


def channels(r: cl.Result) -> tuple[np.ndarray, np.ndarray]:
    """Every post-processed channel as columns, and which of them are constraint
    violations (phi, phi_dot: held to VIOLATION_RTOL of their size instead of post_tol)."""
    n = r.t.size
    e = r.energy
    parts = [
        r.a,
        r.lam,
        r.phi,
        r.phi_dot,
        np.column_stack([e["kinetic"], e["potential"], e["contact"]]),
        r.reaction_force.reshape(n, -1),
        r.reaction_moment.reshape(n, -1),
        r.contact.reshape(n, -1),
        r.contact_points.reshape(n, -1),
    ]
    violation = np.concatenate([np.full(p.shape[1], k in (2, 3)) for k, p in enumerate(parts)])
    return np.column_stack(parts), violation


def assert_within_bound(interp: cl.Result, exact: cl.Result, post_tol: float, atol: float):
    assert interp.settings["post_tol"] == post_tol  # (the default: rtol)
    np.testing.assert_array_equal(interp.q, exact.q)  # the states are not touched
    np.testing.assert_array_equal(interp.v, exact.v)
    (X, violation), (X0, _) = channels(interp), channels(exact)
    rel = np.where(violation, max(post_tol, VIOLATION_RTOL), post_tol)
    bound = rel * np.abs(X0).max(axis=0) + atol
    excess = np.abs(X - X0) / bound
    k, c = np.unravel_index(np.argmax(excess), excess.shape)
    assert excess.max() <= 1.0, (excess.max(), interp.t[k], c)


@pytest.fixture(scope="module")
def crane_runs():
    c = cl.compile_mechanism(crane("cosine"))
    kw = dict(dt_out=1e-4, rtol=1e-7, atol=1e-9)
    return c, cl.simulate(c, 1.0, **kw), cl.simulate(c, 1.0, post_tol=0.0, **kw)


def test_interpolated_outputs_match_exact_evaluation_across_kinks(crane_runs) -> None:
    c, interp, exact = crane_runs
    assert interp.success and exact.success
    assert exact.stats["post_exact"] == exact.t.size
    assert interp.stats["post_exact"] < exact.t.size / 4  # it did interpolate
    assert_within_bound(interp, exact, 1e-7, 1e-9)
    # the drive force jumps with the cart's acceleration at both ends of the ramp: the
    # samples next to the jumps carry the jump, not a smoothed version of it
    F, F0 = interp.actuator_force("drive"), exact.actuator_force("drive")
    for tk in (0.2, 0.7):
        k = int(round(tk / 1e-4))
        jump = abs(F0[k + 2] - F0[k - 2])
        assert jump > 0.1  # N: the oracle shows the jump ...
        assert abs(F[k + 2] - F[k - 2] - (F0[k + 2] - F0[k - 2])) < 1e-6 * jump  # ... kept


def test_uneven_output_times() -> None:
    """User output times at uneven spacing: the interpolation is in time, not in index."""
    c = cl.compile_mechanism(crane("quintic"))
    rng = np.random.default_rng(3)
    t_out = np.sort(np.concatenate([[0.0, 1.0], rng.uniform(0.0, 1.0, 4000)]))
    t_out = t_out[np.concatenate([[True], np.diff(t_out) > 1e-9])]
    kw = dict(t_out=t_out, rtol=1e-7, atol=1e-9)
    interp, exact = cl.simulate(c, 1.0, **kw), cl.simulate(c, 1.0, post_tol=0.0, **kw)
    assert interp.stats["post_exact"] < 0.75 * t_out.size  # (even grid: 0.29)
    assert_within_bound(interp, exact, 1e-7, 1e-9)


def test_bound_holds_on_a_rattling_joint() -> None:
    """A rattling clearance joint: contact forces switch on and off and jump at every onset
    and separation; the bound still holds, and the peaks are those of the exact path."""
    c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.8), cl.Coulomb(0.1))
    kw = dict(dt_out=2e-6, rtol=1e-7, atol=1e-10)
    interp, exact = cl.simulate(c, 0.02, **kw), cl.simulate(c, 0.02, post_tol=0.0, **kw)
    assert interp.success and len(interp.impacts("S")) >= 3
    assert interp.stats["post_exact"] < exact.t.size / 2
    assert_within_bound(interp, exact, 1e-7, 1e-10)
    np.testing.assert_array_equal(interp.contact_peaks, exact.contact_peaks)


def direct(c: cl.Compiled, r: cl.Result, CS: np.ndarray, Y=None, ptol: float = 1e-7, PC=None):
    """post_process on r's samples with a made-up contact state CS (and states Y, and
    dense-output pieces PC; default none known): the number of exact evaluations and the
    outputs (no reaction blocks)."""
    n, m = r.t.size, c.model
    if Y is None:
        Y = np.column_stack([r.q, r.v, np.zeros((n, c.ny - c.nq - c.nv))])
    widths = (c.nv, c.nrow, c.nrow, c.nrow, 3, 0, 0, c.nclr * NCOUT, c.ncp * NPOUT)
    out = PostArrays(*(np.zeros((n, w)) for w in widths))
    none = np.zeros(0, dtype=np.int64)
    blk = Blocks(none, none, none, np.zeros((0, 3)))
    args = (m, make_work(m), make_contact_state(m), 5.0, 5.0, 0, np.ascontiguousarray(r.t))
    if PC is None:
        PC = np.full(n, -1, dtype=np.int64)
    k = post_process(*args, np.ascontiguousarray(Y), CS, PC, n, blk, out, ptol, 1e-10)
    return k, out


def test_windows_never_span_a_change_of_contact_state() -> None:
    """The same smooth samples (a ball swinging free in a 5 mm gap) twice: with one contact
    state throughout most are interpolated; with a recorded state that changes at every
    sample every one is evaluated (a window may not reach across a change, whatever its
    checks would say)."""
    c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.8), cl.Coulomb(0.1), clearance=5e-3)
    r = cl.simulate(c, 0.01, dt_out=1e-5, rtol=1e-7, atol=1e-10)
    assert len(r.impacts("S")) == 0  # (a 5 mm gap: the ball swings free)
    n = r.t.size
    CS = np.zeros((n, c.ncp, 2))
    k_const, _ = direct(c, r, CS)
    # a latched impact velocity that changes at every other sample: out of contact it does
    # not change any value (so the checks alone would interpolate), only the state differs
    CS[1::2, 0, 1] = 0.5
    k_alt, _ = direct(c, r, CS)
    assert k_alt == n
    assert k_const < n / 2
    for few in (1, 2, 3, 9):  # short runs: every sample, no window
        rr = cl.simulate(c, 1e-5 * (few - 1) if few > 1 else 1e-9, t_out=r.t[:few])
        assert direct(c, rr, np.zeros((few, c.ncp, 2)))[0] == few


@pytest.mark.parametrize("case", ["crane tsit5", "crane vern7", "rattling dopri5"])
def test_samples_note_the_step_whose_dense_output_gave_them(monkeypatch, case) -> None:
    """Outputs.piece, which the windows follow: -1 for the start sample, else the count of
    the accepted step whose dense output gave the sample (steps cut at contact events
    included). Oracle: the same run stopped after k attempted steps (max_steps) keeps
    exactly the samples of the pieces up to its accepted count; fixed steps (rk4) sample
    on the solution and have no pieces."""
    import clearance.integrate.simulate as sim

    seen = {}
    build = sim._build_result

    def spy(c_, ts, Y, CS, PC, *a, **kw):
        seen["PC"] = PC.copy()
        return build(c_, ts, Y, CS, PC, *a, **kw)

    monkeypatch.setattr(sim, "_build_result", spy)
    model, method = case.split()
    if model == "crane":
        c, T, kw = cl.compile_mechanism(crane("quintic")), 1.0, dict(dt_out=1e-3, rtol=1e-7)
    else:  # impacts: steps cut at onsets and separations
        c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.8), cl.Coulomb(0.1))
        T, kw = 0.02, dict(dt_out=2e-5, rtol=1e-7)
    kw.update(method=method, atol=kw["rtol"] * 1e-3)
    r = cl.simulate(c, T, **kw)
    PC = seen["PC"]
    assert PC[0] == -1 and PC[1] >= 1 and PC[-1] == r.stats["naccept"]
    assert np.all(np.diff(PC[1:]) >= 0)
    if model != "crane":
        assert r.stats["nevents"] > 0 and len(r.impacts("S")) >= 3
    for k in (1, 2, 3, 5, 8, r.stats["naccept"] // 3, r.stats["naccept"] // 2):
        rk = cl.simulate(c, T, max_steps=k, **kw)
        assert rk.t.size == np.count_nonzero(PC <= rk.stats["naccept"])
    cl.simulate(c, 0.01, method="rk4", step=1e-4, dt_out=1e-3)
    assert np.all(seen["PC"] == -1)


def test_windows_follow_the_steps() -> None:
    """Smooth samples (a ball swinging free in a 5 mm gap): with one piece throughout the
    windows are those with no pieces known; pieces of one sample each (steps shorter than
    the output interval) leave every sample exact; pieces of 25 samples (windows inside
    each) keep the bound against the exact evaluation."""
    c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.8), cl.Coulomb(0.1), clearance=5e-3)
    r = cl.simulate(c, 0.01, dt_out=1e-5, rtol=1e-7, atol=1e-10)
    n = r.t.size
    CS = np.zeros((n, c.ncp, 2))
    k_none, _ = direct(c, r, CS)
    assert k_none < n / 2
    assert direct(c, r, CS, PC=np.ones(n, dtype=np.int64))[0] == k_none
    assert direct(c, r, CS, PC=np.arange(n, dtype=np.int64))[0] == n
    PC = np.concatenate([[-1], 1 + np.arange(n - 1) // 25])
    k_pieces, out = direct(c, r, CS, PC=PC)
    assert k_pieces < n / 2
    _, exact = direct(c, r, CS, ptol=0.0)
    for X, X0 in zip(out[:2] + out[4:], exact[:2] + exact[4:], strict=True):  # (not phi)
        big = np.abs(X0).max(axis=0)
        assert np.all(np.abs(X - X0) <= 1e-7 * big + 1e-10)


def test_a_non_finite_state_is_never_interpolated_over() -> None:
    """A sample whose state is NaN gets NaN outputs, on both paths (the contact diagnostics
    used to keep the previous sample's values); its window is evaluated sample by sample."""
    c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.8), cl.Coulomb(0.1))
    r = cl.simulate(c, 0.01, dt_out=1e-5, rtol=1e-7, atol=1e-10)
    n = r.t.size
    Y = np.column_stack([r.q, r.v, np.zeros((n, c.ny - c.nq - c.nv))])
    Y[500] = np.nan
    CS = np.zeros((n, c.ncp, 2))
    _, out = direct(c, r, CS, Y)
    _, out0 = direct(c, r, CS, Y, ptol=0.0)  # every sample exact
    for X, X0 in zip(out, out0, strict=True):  # NaN everywhere, on both paths
        assert np.all(np.isnan(X[500])) and np.all(np.isnan(X0[500]))
    assert np.all(np.isfinite(np.delete(out.VD, 500, axis=0)))


def test_constraint_violations_do_not_block_interpolation() -> None:
    """phi and phi_dot are drift of the size of atol around zero, kinked where steps meet:
    held to their own size (VIOLATION_RTOL) they no longer fail every window (at atol
    alone: 993 of 1001 samples exact on this double pendulum, whatever post_tol; now
    613), and the other channels keep the post_tol bound."""
    c = cl.compile_mechanism(double_pendulum())
    kw = dict(dt_out=1e-3, rtol=1e-6, atol=1e-9)
    interp, exact = cl.simulate(c, 1.0, **kw), cl.simulate(c, 1.0, post_tol=0.0, **kw)
    assert interp.stats["post_exact"] < 0.7 * interp.t.size
    assert_within_bound(interp, exact, 1e-6, 1e-9)


@pytest.mark.parametrize("bad", [-1e-6, float("nan"), float("inf"), "1e-6"])
def test_post_tol_is_validated(crane_runs, bad) -> None:
    c = crane_runs[0]
    with pytest.raises(cl.ModelError, match="post_tol"):
        cl.simulate(c, 0.1, post_tol=bad)
