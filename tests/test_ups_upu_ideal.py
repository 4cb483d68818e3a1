"""The ideal 4UPS-UPU factory: structure, assembly, DOF 0, a 2 s run, compiled vs reference."""

from __future__ import annotations

import numpy as np
import pytest

import clearance as cl
from clearance.dynamics.reference import reference_rhs
from clearance.dynamics.rhs import make_work, rhs
from clearance.kinds import Solver
from clearance.mechanisms.ups_upu import UPS_UPU_PARAMS, home_leg_lengths, ups_upu_ideal


@pytest.fixture(scope="module")
def compiled() -> cl.Compiled:
    return cl.compile_mechanism(ups_upu_ideal())


def test_structure(compiled: cl.Compiled) -> None:
    """11 bodies, 61 joint rows + 5 driver rows = 66 (mechanisms.md 1.3)."""
    mech = compiled.mechanism
    assert compiled.nb == 11 and compiled.nv == 66 and compiled.nrow == 66
    kinds = [b.kind for b in compiled.joints]
    assert kinds.count("Universal") == 6 and kinds.count("Prismatic") == 5
    assert kinds.count("Spherical") == 4
    assert sum(b.nrows for b in compiled.joints) == 61
    assert [b.nrows for b in compiled.drivers] == [1] * 5
    assert mech.gravity == (0.0, 0.0, -9.81)
    assert np.isclose(home_leg_lengths()[4], 0.70)


def test_home_pose_consistent_and_full_rank(compiled: cl.Compiled) -> None:
    """The home pose satisfies every row at t = 0 and phi_q is square and regular."""
    rows = cl.evaluate_rows(compiled, 0.0, compiled.y0)
    assert np.max(np.abs(rows.phi)) < 1e-12
    y = cl.assemble(compiled, compiled.y0)
    rep = cl.rank_check(compiled, 0.0, y)
    assert rep.nrow == 66 and rep.rank == 66 and rep.dof == 0 and rep.full_rank
    assert rep.singular_values[-1] > 1e-3  # away from the singular layout of 1.4


def test_drivers_measure_leg_lengths(compiled: cl.Compiled) -> None:
    """Driver rows are |A_k B_k| - l_k(t): with constant drives equal to the home lengths
    every driver row vanishes at home; the default drives start at home."""
    mech = ups_upu_ideal(drives=home_leg_lengths())
    c = cl.compile_mechanism(mech)
    rows = cl.evaluate_rows(c, 0.3, c.y0)
    assert np.max(np.abs(rows.phi)) < 1e-12
    for d, length in zip(compiled.mechanism.drivers.values(), home_leg_lengths(), strict=True):
        assert np.isclose(d.function(0.0), length, atol=1e-15)
    with pytest.raises(cl.ModelError):
        ups_upu_ideal(drives=[0.7] * 4)


def test_layout_is_the_non_singular_one() -> None:
    assert UPS_UPU_PARAMS["theta_deg"] == (45.0, 135.0, 225.0, 315.0)
    assert UPS_UPU_PARAMS["phi_deg"] == (75.0, 165.0, 195.0, 285.0)


def test_two_second_run(compiled: cl.Compiled) -> None:
    """2 s DOPRI5 run with the default drives: success, small drift, legs follow drives."""
    r = cl.simulate(compiled, 2.0, rtol=1e-6, atol=1e-9, baumgarte=(5.0, 5.0))
    assert r.status == 0, r.message
    assert np.max(np.abs(r.phi)) < 1e-7
    assert np.max(np.abs(r.phi_dot)) < 1e-6
    # a genuine spatial motion of the platform (mm scale) with bounded actuator forces
    plat = r.q[:, 0:3]
    assert np.ptp(plat, axis=0).max() > 1e-3
    assert np.all(np.isfinite(r.driver_force)) and np.max(np.abs(r.driver_force)) < 1e3
    # unit Euler parameters preserved
    p = r.q.reshape(r.q.shape[0], 11, 7)[:, :, 3:]
    assert np.max(np.abs(np.linalg.norm(p, axis=2) - 1.0)) < 1e-8


@pytest.mark.parametrize("solver", [Solver.SCHUR, Solver.DENSE])
def test_compiled_equals_reference(compiled: cl.Compiled, solver: Solver) -> None:
    """Compiled rhs (ydot and lam) equals the NumPy reference at an assembled consistent
    state and at a perturbed, non-assembled state with random velocities."""
    mech = compiled.mechanism
    rng = np.random.default_rng(7)
    y_cons = cl.initial_state(compiled, t=0.0)
    y_rand = y_cons.copy()
    nb = compiled.nb
    for k in range(nb):
        y_rand[7 * k : 7 * k + 3] += 1e-3 * rng.standard_normal(3)
        p = y_rand[7 * k + 3 : 7 * k + 7] + 1e-2 * rng.standard_normal(4)
        y_rand[7 * k + 3 : 7 * k + 7] = p / np.linalg.norm(p)
    y_rand[7 * nb : 13 * nb] = 0.1 * rng.standard_normal(6 * nb)
    for t, y in ((0.0, y_cons), (0.6, y_rand)):
        wk = make_work(compiled.model)
        yd = np.zeros_like(y)
        cs = cl.contact_state(compiled)
        assert rhs(t, y, compiled.model, wk, cs, 5.0, 5.0, int(solver), yd) == 0
        yd_ref, lam_ref = reference_rhs(mech, t, y, alpha=5.0, beta=5.0)
        scale = max(1.0, np.max(np.abs(yd_ref)))
        assert np.max(np.abs(yd - yd_ref)) < 1e-9 * scale
        lscale = max(1.0, np.max(np.abs(lam_ref)))
        assert np.max(np.abs(wk.lam - lam_ref)) < 1e-9 * lscale
