"""Scenario files of type "parallel" (clearance.scenario.parallel) and the library.

Oracles: the library's builder versions of the two seeds against the seed-type files
(type "4ups-upu" / "4sps-cu", the hand-written factories): both runs, ideal and
clearance, bit for bit; files against Python (the same compiled arrays); the canonical
TOML round trip; study paths; every bad file refused naming file, field and value.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import clearance as cl
from clearance.pipeline import run_scenario
from clearance.scenario import (
    ScenarioError,
    build_mechanisms,
    default_scenario_path,
    library,
    library_path,
    load_scenario,
    loads_scenario,
    scenario_to_toml,
    with_overrides,
)


def _same_arrays(m1: cl.Mechanism, m2: cl.Mechanism) -> None:
    c1, c2 = cl.compile_mechanism(m1), cl.compile_mechanism(m2)
    for k in c1.model._fields:
        a, b = getattr(c1.model, k), getattr(c2.model, k)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), k


@pytest.mark.parametrize("name", ["ups_upu", "sps_cu"])
def test_builder_seed_runs_equal_the_seed_type_runs(name: str, tmp_path) -> None:
    """The library file (builder) and the shipped seed-type file (factory) give the same
    inverse kinematics, ideal run and clearance run, bit for bit (0.3 s: ~30 impacts)."""
    short = {"trajectory.duration": 0.3}
    a = with_overrides(load_scenario(default_scenario_path(name)), short)
    b = with_overrides(load_scenario(library_path(name)), short)
    ra = run_scenario(a, out_dir=tmp_path / "a", log=None, figures=False, defer_write=True)
    rb = run_scenario(b, out_dir=tmp_path / "b", log=None, figures=False, defer_write=True)
    assert np.array_equal(ra.ik.s, rb.ik.s)
    for run in ("ideal", "clearance"):
        x, y = getattr(ra, run), getattr(rb, run)
        assert x.success and y.success
        assert np.array_equal(x.q, y.q), run
        assert np.array_equal(x.driver_force, y.driver_force), run
    assert ra.clearance.stats["nevents"] == rb.clearance.stats["nevents"] > 10


@pytest.mark.parametrize("name", ["ups_upu", "sps_cu"])
def test_file_and_python_give_the_same_model(name: str) -> None:
    """Library file -> build_mechanisms against the Python builder with the same numbers,
    and the canonical TOML round trip."""
    from test_parallel import sps_cu_builder, ups_upu_builder

    s = load_scenario(library_path(name))
    ideal, _, info = build_mechanisms(s)
    pm = ups_upu_builder() if name == "ups_upu" else sps_cu_builder(True)
    _same_arrays(ideal, pm.build())
    assert info.actuators == pm.actuators
    assert loads_scenario(scenario_to_toml(s)) == s


def test_library_lists_every_file_and_each_validates() -> None:
    lib = library()
    assert {"ups_upu", "sps_cu"} <= set(lib)
    for name, desc in lib.items():
        assert desc, name
        load_scenario(library_path(name))
    with pytest.raises(ScenarioError, match="did you mean 'ups_upu'"):
        library_path("upsupu")


def test_study_paths_address_the_file_groups() -> None:
    s = load_scenario(library_path("ups_upu"))
    s2 = with_overrides(
        s,
        {
            "mechanism.legs[0].links[1].mass": 1.7,  # the four U-P-S legs
            "clearance.joints.leg1.S.radial_clearance": 2e-4,
            "mechanism.platform.mass": 12.0,
        },
    )
    pm = s2.mechanism.params.mechanism
    assert [lg.links[1].mass for lg in pm.legs] == [1.7, 1.7, 1.7, 1.7, 1.5]
    assert pm.platform.mass == 12.0
    assert s2.clearance.joints["leg1.S"].radial_clearance == pytest.approx(2e-4)
    with pytest.raises(ScenarioError, match="unknown key 'linkz'.*did you mean 'links'"):
        with_overrides(s, {"mechanism.legs[0].linkz[1].mass": 1.0})
    with pytest.raises(ScenarioError, match="unknown key 'Q' in clearance.joints.leg1"):
        with_overrides(s, {"clearance.joints.leg1.Q.ball_radius": 0.01})


STEWART = """
format_version = 1
[scenario]
name = "bad"
[mechanism]
type = "parallel"
[mechanism.platform]
mass = 5.0
inertia = [0.05, 0.05, 0.1]
position = [0.0, 0.0, 0.6]
[[mechanism.legs]]
joints = "UPS"
base = { radius = 0.4, angles_deg = [-10, 10, 110, 130, 230, 250] }
platform = { radius = 0.2, angles_deg = [310, 50, 70, 170, 190, 290] }
links = [{ mass = 1.0, inertia = [0.01, 0.01, 1e-5], com = 0.2 },
         { mass = 1.0, inertia = [0.01, 0.01, 1e-5], com = 0.2 }]
[trajectory]
duration = 0.5
[trajectory.amplitude]
z = 0.02
"""


def _errors(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as e:
        loads_scenario(text, source="bad.toml")
    return e.value.lines()


def test_a_good_file_validates() -> None:
    s = loads_scenario(STEWART, source="good.toml")
    assert s.mechanism.params.mobility.platform == 6
    assert s.trajectory.orientation == "full" and s.trajectory.positions == ("x", "y", "z")


@pytest.mark.parametrize(
    "old, new, field, says",
    [
        ('joints = "UPS"', 'joints = "UPX"', "mechanism.legs[0].joints", "unknown joint letter"),
        ('joints = "UPS"', 'joints = "SSS"', "mechanism.legs[0].joints", "not a supported leg"),
        ("com = 0.2 },", "com = 0.2 }, { mass = 1.0, inertia = [1, 1, 1] },", "links", "2 link"),
        ("mass = 5.0", "mass = -5.0", "mechanism.platform.mass", "finite number > 0"),
        (
            "inertia = [0.05, 0.05, 0.1]",
            "inertia = [0.05, 0.05, 1.0]",
            "platform.inertia",
            "triangle",
        ),
        ('joints = "UPS"', 'joints = "UPS"\nactuated = "S"', "legs[0].actuated", "P or C"),
        ("angles_deg = [310, 50,", "angles_deg = [310,", "legs[0].platform", "as many platform"),
        ("radius = 0.4,", "radius = 0.4, points = [[0, 0, 0]],", "base.radius", "points or"),
        ("[trajectory]", '[trajectory]\norientation = "axis"', "trajectory.orientation", "6 DOF"),
        ("z = 0.02", "z = 0.02\ngamma = 0.1\n", None, None),
    ],
)
def test_bad_parallel_files_are_refused(old: str, new: str, field, says) -> None:
    text = STEWART.replace(old, new, 1)
    assert text != STEWART
    if field is None:  # (a valid variant: the gamma amplitude is prescribed)
        loads_scenario(text)
        return
    lines = _errors(text)
    assert any(field in ln and says in ln and "bad.toml" in ln for ln in lines), lines


def test_mobility_and_singular_layouts_are_refused_naming_joints() -> None:
    # a 6-UPS with all legs passive but one: the platform has 6 DOF for 1 actuator
    text = STEWART.replace('joints = "UPS"', 'joints = "UPS"\nactuated = "none"')
    text += """
[[mechanism.legs]]
joints = "UPS"
base = { points = [[0.5, 0.0, 0.0]] }
platform = { points = [[0.2, 0.0, 0.0]] }
links = [{ mass = 1.0, inertia = [0.01, 0.01, 1e-5], com = 0.2 },
         { mass = 1.0, inertia = [0.01, 0.01, 1e-5], com = 0.2 }]
"""
    lines = _errors(text)
    assert any(
        "field 'mechanism.legs'" in ln and "6 DOF" in ln and "leg7.drive" in ln for ln in lines
    )
    # a centrally symmetric 6-UPS (base and platform points at the same angles, pairwise
    # parallel legs... ): an actuation singularity at home, the legs named
    sym = STEWART.replace("[310, 50, 70, 170, 190, 290]", "[-10, 10, 110, 130, 230, 250]")
    lines = _errors(sym)
    assert any("do not determine the platform at home" in ln and "leg1" in ln for ln in lines)


def test_clearance_on_a_leg_joint_by_name() -> None:
    text = (
        STEWART
        + """
[clearance.joints.leg2.S]
ball_radius = 0.01
radial_clearance = 1e-4
[clearance.joints."leg5.P"]
width = 0.02
length = 0.05
clearance = 1e-4
normal = { law = "lankarani_nikravesh", stiffness = 1e9 }
"""
    )
    s = loads_scenario(text)
    assert set(s.clearance.joints) == {"leg2.S", "leg5.P"}
    _, clr, info = build_mechanisms(s)
    assert clr.joints["leg2.S"].clearance is not None
    assert info.clearance_joints == ("leg2.S", "leg5.P")
    bad = STEWART + "\n[clearance.joints.leg2.Q]\nball_radius = 0.01\nradial_clearance = 1e-4\n"
    lines = _errors(bad)
    assert any("clearance.joints.leg2.Q" in ln and "leg2.S" in ln for ln in lines), lines


def test_cli_new_and_examples(tmp_path) -> None:
    out = subprocess.run(
        [sys.executable, "-m", "clearance.cli.main", "examples"], capture_output=True, text=True
    )
    assert out.returncode == 0
    for name in library():
        assert name in out.stdout
    dest = tmp_path / "mine.toml"
    cmd = [sys.executable, "-m", "clearance.cli.main", "new", "sps_cu", str(dest)]
    assert subprocess.run(cmd, capture_output=True, text=True).returncode == 0
    assert dest.read_text() == library_path("sps_cu").read_text()
    again = subprocess.run(cmd, capture_output=True, text=True)
    assert again.returncode == 2 and "exists" in again.stderr
    bad = subprocess.run(cmd[:4] + ["stewrt"], capture_output=True, text=True)
    assert bad.returncode == 2 and "unknown scenario" in bad.stderr


def test_cli_draw_sketches_the_home_pose(tmp_path) -> None:
    """`clearance draw` writes a PNG of the mechanism; the sketch puts one glyph per joint
    at its marker i (P and C: between their markers) and one line per body-joint pair."""
    from clearance.plot.sketch import sketch

    s = load_scenario(library_path("ups_upu"))
    ideal, _, _ = build_mechanisms(s)
    fig = sketch(ideal)
    ax = fig.axes[0]
    glyphs = [c for c in ax.collections if len(c.get_offsets()) == 1]
    assert len(glyphs) == len(ideal.joints) + len(ideal.bodies)  # joints + mass centres
    dest = tmp_path / "m.png"
    cmd = [sys.executable, "-m", "clearance.cli.main", "draw", str(library_path("sps_cu"))]
    out = subprocess.run([*cmd, "--out", str(dest)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert dest.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_study_on_a_library_mechanism(tmp_path) -> None:
    """Studies address a parallel mechanism's joints by name ("leg1.S"), nested paths and
    joint sets, on a library scenario as base."""
    from clearance.sweep.study import case_scenario_dict, loads_study

    text = """
format_version = 1
[study]
name = "rps"
base = "rps3"
metrics = ["peak_contact_force@leg1.S", "impacts"]
[set]
trajectory.duration = 0.05
[[parameter]]
name = "c"
path = "clearance.joints.leg1.S.radial_clearance"
values = [5e-5, 1e-4]
[[parameter]]
name = "joints"
path = "clearance.joints"
values = [["leg1.S"], ["leg1.S", "leg3.S"]]
"""
    st = loads_study(text, root=tmp_path)
    assert len(st.cases) == 4
    for case in st.cases:
        d = case_scenario_dict(st.base, case.overrides, joint_template=st.joint_template)
        s = loads_scenario(scenario_to_toml(loads_scenario_dict(d)))
        assert set(s.clearance.joints) == set(case.overrides["clearance.joints"])
        assert s.clearance.joints["leg1.S"].radial_clearance == pytest.approx(
            case.overrides["clearance.joints.leg1.S.radial_clearance"]
        )
    bad = text.replace("@leg1.S", "@leg1.Q")
    with pytest.raises(ScenarioError, match="unknown joint 'leg1.Q'"):
        loads_study(bad, root=tmp_path)


def loads_scenario_dict(d):
    from clearance.scenario import scenario_from_dict

    return scenario_from_dict(d)


def test_a_singular_trajectory_is_refused_before_the_run_naming_legs(tmp_path) -> None:
    """A 3-RPS tilted 1.2 rad passes a singular configuration: the inverse kinematics (run
    by `clearance run` before it integrates, and by `clearance check`) refuses it with
    the time and the legs and joints involved."""
    from clearance.pipeline import _kernels_cached

    text = (
        library_path("rps3")
        .read_text()
        .replace("alpha = { amplitude = 0.03 }", "alpha = { amplitude = 1.2 }")
    )
    f = tmp_path / "sing.toml"
    f.write_text(text)
    with pytest.raises(
        cl.KinematicsError, match=r"singular configuration.*leg1\.drive \(joint leg1\.P"
    ):
        run_scenario(load_scenario(f), out_dir=tmp_path / "out", log=None, figures=False)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
    if _kernels_cached():  # (`check` runs the IK once the kernels are compiled)
        cmd = [sys.executable, "-m", "clearance.cli.main", "check", str(f)]
        out = subprocess.run(cmd, capture_output=True, text=True)
        assert out.returncode == 2 and "leg1.P" in out.stderr, out.stderr
