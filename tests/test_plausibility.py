"""Plausibility of finished runs (issue 11): never "ok" for a ball outside its socket."""

import re
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

from clearance.analysis.plausibility import (
    ENERGY_IMPLAUSIBLE,
    ENERGY_WARNING,
    PENETRATION_WARNING,
    plausibility,
)
from clearance.cli.main import app
from clearance.io.dataset import load_results
from clearance.pipeline import format_summary, run_scenario
from clearance.scenario import default_scenario_path, load_scenario, with_overrides


def fake_run(depth: float, impacts: int = 3, residual: float = 0.0, c=3e-4, r=0.015):
    """What `plausibility` reads of a Result: one clearance joint, an energy record."""
    t = np.linspace(0.0, 1.0, 11)
    return SimpleNamespace(
        compiled=SimpleNamespace(clearances=[SimpleNamespace(c=c, ball_radius=r)]),
        clearance_names=["S_1"],
        peak_penetration=lambda name: (depth, 0.5),
        impacts=lambda name: list(range(impacts)),
        t=t,
        energy={
            "kinetic": np.full(11, 2.0),
            "potential": np.full(11, -1.0),
            "residual": np.full(11, residual * 3.0),  # energy scale 3 J
        },
    )


@pytest.mark.parametrize(
    "depth,impacts,residual,status,words",
    [
        (4e-6, 19, 3e-9, "ok", None),  # the default scenario's numbers
        (0.3 * 3e-4, 5, 0.0, "warning", "of the clearance"),
        (26e-3, 5, 0.0, "implausible", "times the clearance"),  # Hertz K = 1
        (2e-4, 5, 0.0, "implausible", "of the inner radius"),  # 0.1 R rule: r = 1.5 mm
        (0.0, 0, 0.0, "warning", "never in contact"),
        (4e-6, 5, 2 * ENERGY_WARNING, "warning", "energy balance"),
        (4e-6, 5, 2 * ENERGY_IMPLAUSIBLE, "implausible", "energy balance"),
    ],
)
def test_thresholds(depth, impacts, residual, status, words):
    r = 0.0015 if depth == 2e-4 else 0.015
    p = plausibility(fake_run(depth, impacts, residual, r=r))
    assert p.status == status, p
    assert (words is None and not p.findings) or any(words in f for f in p.findings)


def test_warning_threshold_is_a_fraction_of_the_clearance():
    just_below = plausibility(fake_run(0.99 * PENETRATION_WARNING * 3e-4))
    assert just_below.status == "ok"


def test_a_ball_through_its_socket_is_never_ok(tmp_path):
    """Hertz K = 2e3 N/m^1.5 (a gel, E* ~ 2 kPa: the softest the input allows; K = 1, a
    typo for 1e10, is refused as input now): the run reaches its end with the ball deep in
    the wall; the summary, the file and the exit code say implausible."""
    s = load_scenario(default_scenario_path())
    s = with_overrides(
        s,
        {
            "trajectory.duration": 0.05,
            "solver.dt_out": 1e-3,
            "output.figures": False,
            "clearance.joints.S_1.normal": {"law": "hertz", "stiffness": 2e3},
        },
    )
    o = run_scenario(s, out_dir=tmp_path, log=None)
    assert o.clearance.success  # the integrator has nothing to object to
    p = o.summary["clearance"]["plausibility"]
    assert p["status"] == "implausible" and any("S_1" in f for f in p["findings"])
    assert "clearance: IMPLAUSIBLE: S_1" in format_summary(o.summary)
    assert load_results(o.files[0]).attrs["implausible"] == "clearance"
    path = tmp_path / "soft.toml"
    from clearance.scenario import scenario_to_toml

    path.write_text(scenario_to_toml(s))
    res = CliRunner().invoke(app, ["run", str(path), "--out", str(tmp_path / "cli")])
    assert res.exit_code == 3, res.output
    assert "IMPLAUSIBLE" in res.output


def test_the_default_scenario_is_plausible(tmp_path):
    s = with_overrides(
        load_scenario(default_scenario_path()),
        {"trajectory.duration": 0.1, "solver.dt_out": 1e-3, "output.figures": False},
    )
    o = run_scenario(s, out_dir=tmp_path, log=None)
    for run in ("ideal", "clearance"):
        assert o.summary[run]["plausibility"] == {"status": "ok", "findings": []}
    assert load_results(o.files[0]).attrs["implausible"] == ""


def test_a_thrust_face_is_measured_against_the_axial_clearance():
    """A revolute joint with a 50 um radial and a 1 mm axial gap, its collar pressed onto
    the bearing's end face by a soft thrust law: ~0.8 mm deep is ~16 radial clearances but
    ~0.8 of the axial gap it is in, a warning, not 'the ball beyond its socket'; the radial
    points are checked against the radial gap on their own (~20 um: ~0.4 c, a warning)."""
    import clearance as cl

    m = cl.Mechanism("collar on a face", gravity=(0.0, -9.81, -4.0))
    m.add(
        cl.Body(
            "rod",
            0.6,
            (0.008, 0.0005, 0.008),
            position=(0.0, -0.2, 0.0),
            velocity=(0.6, 0.0, 0.0),
            angular_velocity=(0.0, 0.0, 3.0),
        ),
        cl.Marker("pivot_g", "ground"),
        cl.Marker("pivot_r", "rod", (0.0, 0.2, 0.0)),
        cl.Revolute(
            "J",
            "pivot_g",
            "pivot_r",
            clearance=cl.RevoluteClearance(
                0.01,
                radial_clearance=5e-5,
                model="spatial",
                length=0.02,
                axial_clearance=1e-3,
                normal=cl.Hertz(stiffness=3e10),
                thrust_normal=cl.Hertz(stiffness=1e6),
            ),
        ),
    )
    r = cl.simulate(m, 0.2, dt_out=1e-3)
    depth = r.peak_penetration("J")[0]
    assert r.success and 0.2e-3 < depth < 1e-3  # deep against c = 50 um, within c_a
    p = plausibility(r)
    assert p.status == "warning", p
    thrust = r"at a thrust face is 0\.[2-9]\d* of the axial clearance c_a"
    assert any(re.search(thrust, f) for f in p.findings), p
    assert any(re.search(r"\(radial\) is 0\.[2-9]\d* of the clearance c", f) for f in p.findings), p


@pytest.mark.parametrize("k", [1.0, 1e30])
def test_a_stiffness_no_material_has_is_refused_as_input(k):
    """K = 1 (the ball sank 26 mm) and K = 1e30 (2.3e10 N looked 'ok') stand for effective
    moduli of ~1 Pa and ~1e30 Pa: refused before any run, naming the field as written."""
    from clearance.scenario import ScenarioError

    s = load_scenario(default_scenario_path())
    with pytest.raises(ScenarioError) as e:
        with_overrides(s, {"clearance.joints.S_1.normal": {"law": "hertz", "stiffness": k}})
    p = e.value.problems[0]
    assert p.field == "clearance.joints.S_1.normal.stiffness", str(e.value)
    assert "which no material has" in str(e.value) and "(the default)" not in str(e.value)
