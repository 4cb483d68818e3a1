"""Post-processing by verified interpolation (clearance.integrate.post) against the exact
evaluation of every sample (post_tol = 0): the oracle is the same quantity evaluated at
each sample's state, and the bound is the documented one, post_tol |x| + atol, with |x| the
channel's largest magnitude over the run (the code's window maximum is at most that)."""

from __future__ import annotations

import numpy as np
import pytest
from models import rod_on_clearance_joint

import clearance as cl


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


def channels(r: cl.Result) -> np.ndarray:
    n = r.t.size
    e = r.energy
    return np.column_stack(
        [
            r.a,
            r.lam,
            r.phi,
            r.phi_dot,
            e["kinetic"],
            e["potential"],
            e["contact"],
            r.reaction_force.reshape(n, -1),
            r.reaction_moment.reshape(n, -1),
            r.contact.reshape(n, -1),
            r.contact_points.reshape(n, -1),
        ]
    )


def assert_within_bound(interp: cl.Result, exact: cl.Result, post_tol: float, atol: float):
    assert interp.settings["post_tol"] == post_tol  # (the default: rtol)
    np.testing.assert_array_equal(interp.q, exact.q)  # the states are not touched
    np.testing.assert_array_equal(interp.v, exact.v)
    X, X0 = channels(interp), channels(exact)
    bound = post_tol * np.abs(X0).max(axis=0) + atol
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


def test_contact_changes_split_the_windows() -> None:
    """A rattling clearance joint: the quantities jump at every onset and separation (the
    recorded contact state changes there); interpolation never reaches across one."""
    c = rod_on_clearance_joint(cl.HuntCrossley(restitution=0.8), cl.Coulomb(0.1))
    kw = dict(dt_out=2e-6, rtol=1e-7, atol=1e-10)
    interp, exact = cl.simulate(c, 0.02, **kw), cl.simulate(c, 0.02, post_tol=0.0, **kw)
    assert interp.success and len(interp.impacts("S")) >= 3
    assert interp.stats["post_exact"] < exact.t.size / 2
    assert_within_bound(interp, exact, 1e-7, 1e-10)
    np.testing.assert_array_equal(interp.contact_peaks, exact.contact_peaks)


@pytest.mark.parametrize("bad", [-1e-6, float("nan"), float("inf"), "1e-6"])
def test_post_tol_is_validated(crane_runs, bad) -> None:
    c = crane_runs[0]
    with pytest.raises(cl.ModelError, match="post_tol"):
        cl.simulate(c, 0.1, post_tol=bad)
