"""Every scenario of the library (clearance/data/library), as shipped.

For each: the mobility its header states; the ideal mechanism, driven by the inverse
kinematics of the scenario's own trajectory, follows the prescribed coordinates (1e-9 m,
1e-9 rad); the static actuator forces equal the independent virtual-work oracle; the forces
along the motion equal its inverse dynamics (tests/oracles/parallel_dynamics.py); and a
short clearance run of the file is plausible. A lumped limb (Paper A's mass-moment model,
physics.md i) is compared as the two-body limb it lumps (the same file with lumped =
false; lumped against two-body: tests/test_pipeline.py, tests/test_sps_cu.py).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_parallel_dynamics import _platform_motion, oracle, oracle_spec, tsai_stewart

import clearance as cl
from clearance.analysis.ik import drives_from_ik, inverse_kinematics
from clearance.pipeline import implausible, run_scenario
from clearance.scenario import (
    build_mechanisms,
    library,
    library_path,
    load_scenario,
    with_overrides,
)

# name -> (Grubler-Kutzbach, idle spins, platform DOF), by hand (docs/parallel-mechanisms.md)
MOBILITY = {
    "ups_upu": (5, 0, 5),
    "sps_cu": (8, 4, 4),  # (its two-body model: 6 x 10 - 52)
    "stewart": (6, 0, 6),
    "rps3": (3, 0, 3),
    "prs3": (3, 0, 3),
    "pss_upu5": (10, 5, 5),
    "delta": (9, 6, 3),
}


# entries written element by element (type "general"): tests/test_general_scenarios.py
GENERAL = {"slider_crank"}


def test_every_library_entry_is_covered() -> None:
    assert set(library()) == set(MOBILITY) | GENERAL


def _two_body(name: str):
    s = load_scenario(library_path(name))
    pm = s.mechanism.params.mechanism
    if pm.lumped:
        k = next(i for i, g in enumerate(s.mechanism.params.document["legs"]) if g["lumped"])
        s = with_overrides(s, {f"mechanism.legs[{k}].lumped": False})
    return s


@pytest.mark.parametrize("name", sorted(MOBILITY))
def test_mobility(name: str) -> None:
    mob = load_scenario(library_path(name)).mechanism.params.mobility
    assert (mob.grubler, mob.rank_dof, mob.idle, mob.platform) == (
        MOBILITY[name][0],
        MOBILITY[name][0],
        *MOBILITY[name][1:],
    )
    assert mob.actuators == MOBILITY[name][2]


@pytest.mark.parametrize("name", sorted(MOBILITY))
def test_ideal_follows_the_trajectory_and_forces_match_the_oracle(name: str) -> None:
    s = _two_body(name)
    T = min(s.trajectory.duration, 1.0)
    s = with_overrides(s, {"trajectory.duration": T})
    ideal, _, info = build_mechanisms(s)
    tr = info.platform_trajectory()
    ik = inverse_kinematics(
        info.ik_mechanism or ideal,
        tr,
        platform_marker=info.platform_marker,
        actuators=info.actuators,
        times=s.trajectory.ik_times(),
    )
    ideal, _, _ = build_mechanisms(s, drives=drives_from_ik(ik))
    r = cl.simulate(ideal, T, dt_out=T / 20, rtol=1e-11, atol=1e-13)
    assert r.success, r.message
    # the prescribed coordinates, 1e-9 m and 1e-9 rad
    pos = r.position("platform")
    for c in tr.positions:
        ref = getattr(tr, c).evaluate(r.t)[:, 0]
        assert np.max(np.abs(pos[:, "xyz".index(c)] - ref)) < 1e-9, c
    R = r.rotation("platform")
    if tr.mode == "full":
        err = max(np.max(np.abs(R[k] - tr.rotation(t))) for k, t in enumerate(r.t))
    elif tr.mode == "axis":
        err = max(np.max(np.abs(R[k][:, 2] - tr.normal(t))) for k, t in enumerate(r.t))
    else:  # (the Delta's platform keeps its orientation)
        err = max(np.max(np.abs(R[k] - np.eye(3))) for k in range(r.t.size))
    assert err < 1e-9
    # the actuator forces against the oracle: at rest at home (virtual work) and along
    # the motion (inverse dynamics)
    pm = s.mechanism.params.mechanism
    spec = oracle_spec(pm)
    r0 = cl.simulate(pm.build(), 1e-6, t_out=np.array([0.0]), rtol=1e-10, atol=1e-12)
    F0 = np.array([r0.actuator_force(a)[0] for a in pm.actuators])
    F0_ref = oracle.static_actuator_forces(spec, np.array(pm.platform.position), np.eye(3))
    assert np.max(np.abs(F0 - F0_ref)) < 1e-7 * np.max(np.abs(F0_ref)), (F0, F0_ref)
    for k in range(0, r.t.size, 5):
        F = np.array([r.actuator_force(a)[k] for a in pm.actuators])
        F_ref = oracle.actuator_forces(spec, *_platform_motion(r, k))
        assert np.max(np.abs(F - F_ref)) < 1e-7 * np.max(np.abs(F_ref)), (r.t[k], F, F_ref)


@pytest.mark.parametrize("name", sorted(MOBILITY))
def test_a_short_clearance_run_of_the_file_is_plausible(name: str, tmp_path) -> None:
    s = with_overrides(load_scenario(library_path(name)), {"trajectory.duration": 0.05})
    run = run_scenario(s, out_dir=tmp_path, log=None, figures=False, defer_write=True)
    assert run.clearance.success and run.ideal.success
    assert not implausible(run.summary), run.summary
    for k in ("ideal", "clearance"):
        assert run.summary[k]["plausibility"]["status"] == "ok", run.summary[k]


# ---------------------------------------------------------------- the same in Python
def _rod(m: float, jt: float, com: float, length: float, ja: float = 1e-5) -> cl.Link:
    return cl.Link(m, (jt, jt, ja), com=com, length=length)


def python_delta() -> cl.ParallelMechanism:
    ang = [-90.0, 30.0, 150.0]
    return cl.ParallelMechanism(
        "delta",
        cl.Platform(0.5, (0.00045, 0.00045, 0.0009), position=(0.0, 0.0, -1.0644517)),
        cl.legs(
            "RSS",
            base=cl.circle(0.1636788013152589, ang),
            platform=cl.circle(0.04387862045841156, ang),
            links=(
                _rod(1.0, 0.022881333333333337, 0.262, 0.524, 1e-4),
                _rod(0.15, 0.0193442, 0.622, 1.244),
            ),
            parallelogram=0.10,
        ),
        dof=3,
    )


def python_three(joints: str) -> cl.ParallelMechanism:
    ang = [90.0, 210.0, 330.0]
    if joints == "RPS":
        links, opts = (_rod(1.0, 0.0075, 0.15, 0.3), _rod(1.0, 0.0075, 0.15, 0.3)), {}
    else:
        links = (cl.Link(1.0, (0.01, 0.01, 0.01)), _rod(1.0, 0.016875, 0.225, 0.45))
        opts = {"rail": (0.0, 0.0, 1.0)}
    return cl.ParallelMechanism(
        f"{joints.lower()}3",
        cl.Platform(5.0, (0.05, 0.05, 0.1), position=(0.0, 0.0, 0.5)),
        cl.legs(
            joints, base=cl.circle(0.3, ang), platform=cl.circle(0.15, ang), links=links, **opts
        ),
    )


def python_pss_upu5() -> cl.ParallelMechanism:
    rod = _rod(1.0, 0.013333333333333334, 0.2, 0.4)
    o = (0.0, 0.0, 0.0)
    return cl.ParallelMechanism(
        "pss_upu5",
        cl.Platform(5.0, (0.05, 0.05, 0.1), position=(0.0, 0.0, 0.6)),
        (
            cl.legs(
                "PSS",
                base=cl.circle(0.35, [90.0, 162.0, 234.0, 306.0, 18.0]),
                platform=cl.circle(0.15, [120.0, 192.0, 204.0, 276.0, 18.0]),
                links=(cl.Link(1.0, (0.01, 0.01, 0.01)), rod),
                rail=(0.0, 0.0, 1.0),
            ),
            cl.Leg("UPU", o, o, (rod, rod), actuated=None, name="centre"),
        ),
        dof=5,
    )


PYTHON = {
    "stewart": tsai_stewart,  # (tests/test_parallel_dynamics.py: Tsai's set, as the file)
    "delta": python_delta,
    "rps3": lambda: python_three("RPS"),
    "prs3": lambda: python_three("PRS"),
    "pss_upu5": python_pss_upu5,
}


@pytest.mark.parametrize("name", sorted(PYTHON))
def test_file_and_python_give_the_same_model(name: str) -> None:
    """The library file and the Python builder with the same numbers compile to the same
    arrays (the seeds: tests/test_parallel_scenarios.py; slider_crank:
    tests/test_general_scenarios.py)."""
    ideal, _, info = build_mechanisms(load_scenario(library_path(name)))
    pm = PYTHON[name]()
    c1, c2 = cl.compile_mechanism(ideal), cl.compile_mechanism(pm.build())
    for k in c1.model._fields:
        a, b = getattr(c1.model, k), getattr(c2.model, k)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), k
    assert info.actuators == pm.actuators
