"""Socket wear from a run's contact history (issue 16, second step): in a 4UPS-UPU run
with Coulomb friction, the integral of F_N |v_slip| dt over the output samples, which the
wear volume is k_w times, equals the friction work the kernel integrates at every step
divided by mu (an independent account of the same integral); the worn volume is k_w
times it, and the wear sits where the ball presses."""

from __future__ import annotations

import numpy as np
import pytest

from clearance.io.dataset import result_to_dataset
from clearance.pipeline import run_scenario
from clearance.scenario import default_scenario_path, load_scenario, with_overrides
from clearance.wear.history import socket_wear, trapezoid_weights

MU = 0.1


@pytest.fixture(scope="module")
def coulomb_run(tmp_path_factory):
    over = {"trajectory.duration": 0.3, "solver.dt_out": 2e-5}
    for jn in ("S_1", "S_3"):  # (the ramp below 1e-6 m/s: friction = mu F_N in practice)
        over[f"clearance.joints.{jn}.friction"] = {
            "law": "coulomb",
            "mu": MU,
            "v0": 1e-7,
            "v1": 1e-6,
        }
    s = with_overrides(load_scenario(default_scenario_path("ups_upu")), over)
    o = run_scenario(
        s, out_dir=tmp_path_factory.mktemp("wear"), log=None, figures=False, defer_write=True
    )
    return result_to_dataset(o.clearance)


@pytest.mark.parametrize("joint", ["S_1", "S_3"])
def test_volume_balance_against_the_kernels_friction_work(coulomb_run, joint):
    ds = coulomb_run
    k_w = 1e-14
    m, work = socket_wear(ds, joint, k_w=k_w, e_star=113.7e9, n=32)
    j = [str(c) for c in ds.clearance.values].index(joint)
    d_t = float(ds.dissipation_friction.values[-1, j])  # integrated at every step
    assert d_t > 0
    # measured: 3e-4 (S_1) and 2e-5 (S_3) at 20 us samples; 1.8 % and 4.6 % at 100 us
    assert work == pytest.approx(d_t / MU, rel=5e-3)
    assert m.volume() == pytest.approx(k_w * work, rel=1e-6)  # (first order in h / R)
    # the wear sits where the ball pressed: around the mean contact direction
    e = ds.eccentricity.values[:, j]
    on = np.abs(ds.contact_force.values[:, j]) > 0
    mean_dir = (e[on] / np.linalg.norm(e[on], axis=1)[:, None]).mean(axis=0)
    deepest = m.centres[np.unravel_index(np.argmax(m.depth), m.depth.shape)]
    assert deepest @ mean_dir / np.linalg.norm(mean_dir) > 0.9


def test_trapezoid_weights():
    t = np.array([0.0, 0.1, 0.3, 0.6])
    assert np.sum(trapezoid_weights(t) * t**1) == pytest.approx(0.6**2 / 2)
    assert trapezoid_weights(np.array([1.0])).tolist() == [0.0]


def test_refuses_other_kinds_and_names(coulomb_run):
    with pytest.raises(ValueError, match="no clearance joint 'S_9'"):
        socket_wear(coulomb_run, "S_9", k_w=1e-14, e_star=1e11)
