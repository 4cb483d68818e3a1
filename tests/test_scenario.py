"""Scenario files: shipped files, round trip, error messages, paths, CLI check, building."""

from __future__ import annotations

import dataclasses
import math
import pickle
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

import clearance as cl
from clearance.cli.main import app
from clearance.mechanisms.params import SpsCuParams
from clearance.mechanisms.ups_upu import (
    UPS_UPU_PARAMS,
    UpsUpuParams,
    home_leg_lengths,
    ups_upu_ideal,
)
from clearance.model.contact_laws import FRICTION_LAWS, NORMAL_LAWS
from clearance.pipeline import run_scenario
from clearance.scenario import (
    MECHANISMS,
    InitialPlacement,
    MechanismType,
    ScenarioError,
    TrajectoryShape,
    build_mechanisms,
    default_scenario_path,
    default_scenarios,
    get_path,
    load_scenario,
    loads_scenario,
    scenario_from_dict,
    scenario_to_dict,
    scenario_to_toml,
    set_path,
    with_overrides,
)
from clearance.scenario.general import (
    DRIVER_TYPES,
    FORCE_TYPES,
    FUNCTION_TYPES,
    GENERAL_KEYS,
    JOINT_TYPES,
    SECTIONS,
    element_keys,
)
from clearance.scenario.parallel import (
    ATTACH_KEYS,
    LEG_KEYS,
    LINK_KEYS,
    MECHANISM_KEYS,
    PLATFORM_KEYS,
)
from clearance.scenario.schema import (
    CLEARANCE_FIELDS,
    CLEARANCE_KINDS,
    JOINT_FIELDS,
    OUTPUT_FIELDS,
    SCENARIO_FIELDS,
    SOLVER_FIELDS,
    TRAJECTORY_FIELDS,
    ChecksSpec,
)

DOCS = Path(__file__).parents[1] / "docs" / "scenario-format.md"

MINIMAL = """\
format_version = 1

[scenario]
name = "minimal"

[mechanism]
type = "4ups-upu"

[clearance.joints.S_1]
ball_radius = 0.015
radial_clearance = 0.0003
normal = { law = "flores", restitution = 0.9 }
friction = { law = "lugre", mu_c = 0.1 }

[solver]
rtol = 1e-6
"""


@pytest.fixture(scope="module")
def default():
    return load_scenario(default_scenario_path())


# --------------------------------------------------------------------------- shipped files


def test_shipped_files_validate() -> None:
    assert {"ups_upu", "sps_cu"} <= set(default_scenarios())
    s = load_scenario(default_scenario_path("ups_upu"))
    assert s.mechanism.type is MechanismType.UPS_UPU
    assert s.mechanism.params == UpsUpuParams()  # the file states the factory defaults
    assert list(s.clearance.joints) == ["S_1", "S_3"]
    assert s.clearance.initial is InitialPlacement.CENTRED
    for c in s.clearance.joints.values():
        assert c.ball_radius == 0.015 and c.c == 0.3e-3 and c.socket == "i"
        assert isinstance(c.normal, cl.Flores) and c.normal.restitution == 0.9
        assert c.friction == cl.LuGre()  # physics.md h.4 defaults
    tr = s.trajectory
    assert tr.shape is TrajectoryShape.REST_TO_REST and tr.duration == 2.0 == tr.period
    assert tr.amplitude == {"x": 0.02, "y": 0.02, "z": 0.03, "alpha": 0.05, "beta": 0.05}
    kw = s.solver.simulate_kwargs()
    assert kw["method"] == "tsit5" and kw["rtol"] == 1e-6 and kw["atol"] == 1e-9
    assert kw["baumgarte"] == (5.0, 5.0) and kw["dt_out"] == 1e-4

    p = load_scenario(default_scenario_path("sps_cu"))
    assert p.mechanism.type is MechanismType.SPS_CU and p.mechanism.params == SpsCuParams()
    (name, j), = p.clearance.joints.items()  # fmt: skip
    assert name == "SB_1" and j.ball_radius == 0.010 and j.radial_clearance == 0.3e-3
    assert j.normal == cl.NonlinearStiffness(form=1, restitution=0.9)
    assert j.friction == cl.Coulomb(mu=0.1, v0=1e-4, v1=1e-3, ramp="linear")
    assert p.trajectory.amplitude == {"z": 0.05, "psi": 0.10, "t1": 0.05, "t2": 0.05}


def test_shipped_files_mark_every_value_with_its_status() -> None:
    """Every numeric assignment in the shipped files carries a status label, on its line
    or in the comment block right above it."""
    labels = ("PROPOSED", "SOURCED", "RECALLED", "DERIVED", "INFERRED")
    for name in ("ups_upu", "sps_cu"):
        lines = default_scenario_path(name).read_text().splitlines()
        for i, line in enumerate(lines):
            m = re.match(r"^\s*(\w+)\s*=\s*[-\[{0-9]", line)
            if not m or m.group(1) in ("format_version", "formats"):
                continue
            block = [line]
            k = i - 1
            while k >= 0 and lines[k].lstrip().startswith("#"):
                block.append(lines[k])
                k -= 1
            assert any(lab in b for b in block for lab in labels), f"{name}.toml:{i + 1}: {line}"


@pytest.mark.parametrize("name", ["ups_upu", "sps_cu"])
def test_round_trip(name: str) -> None:
    s = load_scenario(default_scenario_path(name))
    text = scenario_to_toml(s)
    s2 = loads_scenario(text)
    assert s2 == s
    assert scenario_to_toml(s2) == text
    assert scenario_from_dict(scenario_to_dict(s)) == s


def test_scenario_pickles(default) -> None:
    """Study tasks receive the validated scenario (plain data, no compiled objects)."""
    s = pickle.loads(pickle.dumps(default))
    assert s == default and s.source == default.source


def test_round_trip_of_defaults_auto_and_socket_radius() -> None:
    text = MINIMAL.replace("radial_clearance = 0.0003", "socket_radius = 0.0153").replace(
        '{ law = "flores", restitution = 0.9 }', '{ law = "impact", stiffness = "auto" }'
    )
    s = loads_scenario(text)
    j = s.clearance.joints["S_1"]
    assert j.socket_radius == 0.0153 and j.given == "socket_radius"  # written back as given
    assert j.normal == cl.Impact(stiffness=None)
    out = scenario_to_toml(s)
    assert 'stiffness = "auto"' in out and "socket_radius = 0.0153" in out
    assert loads_scenario(out) == s
    # period defaults to duration; max_step inf survives
    assert s.trajectory.period == s.trajectory.duration and s.solver.max_step == math.inf
    assert "max_step = inf" in out


# --------------------------------------------------------------------------- errors

BROKEN = [
    # (description, old text, new text, dotted field, value text, allowed text)
    (
        "unknown key",
        "radial_clearance = 0.0003",
        "radial_clearence = 0.0003",
        "clearance.joints.S_1.radial_clearence",
        "0.0003",
        "did you mean 'radial_clearance'?",
    ),
    ("wrong type", "rtol = 1e-6", 'rtol = "1e-6"', "solver.rtol", "'1e-6'", "> 0"),
    (
        "negative clearance",
        "radial_clearance = 0.0003",
        "radial_clearance = -0.0003",
        "clearance.joints.S_1.radial_clearance",
        "-0.0003",
        "> 0 [m]",
    ),
    (
        "unknown law",
        'law = "flores"',
        'law = "florez"',
        "clearance.joints.S_1.normal.law",
        "'florez'",
        "did you mean 'flores'?",
    ),
    (
        "unknown law field",
        "mu_c = 0.1",
        "mu = 0.1",
        "clearance.joints.S_1.friction.mu",
        "0.1",
        "allowed: law, sigma0",
    ),
    (
        "bad law value",
        "restitution = 0.9",
        "restitution = 1.5",
        "clearance.joints.S_1.normal.restitution",
        "1.5",
        "0 < restitution <= 1",
    ),
    (
        "unknown joint",
        "[clearance.joints.S_1]",
        "[clearance.joints.S1]",
        "clearance.joints.S1",
        "'S1'",
        "did you mean 'S_1'?",
    ),
    (
        "missing required",
        "ball_radius = 0.015\n",
        "",
        "clearance.joints.S_1.ball_radius",
        "<missing>",
        "required",
    ),
    ("missing name", 'name = "minimal"', "", "scenario.name", "<missing>", "required"),
    (
        "bad format_version",
        "format_version = 1",
        "format_version = 7",
        "format_version",
        "7",
        "format_version = 1",
    ),
    (
        "bad mechanism type",
        'type = "4ups-upu"',
        'type = "4ups_upu"',
        "mechanism.type",
        "'4ups_upu'",
        "did you mean '4ups-upu'?",
    ),
    (
        "bad parameter",
        'type = "4ups-upu"',
        'type = "4ups-upu"\ntheta_deg = [45, 135, 225]',
        "mechanism.theta_deg",
        "[45, 135, 225]",
        "4 finite angles",
    ),
    (
        "socket not larger than ball",
        "radial_clearance = 0.0003",
        "socket_radius = 0.01",
        "clearance.joints.S_1.socket_radius",
        "0.01",
        "must exceed ball_radius",
    ),
    (
        "unknown trajectory coordinate",
        "[solver]",
        "[trajectory.amplitude]\npsi = 0.1\n\n[solver]",
        "trajectory.amplitude.psi",
        "0.1",
        "allowed: x, y, z, alpha, beta",
    ),
    (
        "bad choice",
        "[solver]",
        '[solver]\nmethod = "rk45"',
        "solver.method",
        "'rk45'",
        "'dopri5', 'tsit5', 'rk4'",
    ),
    (
        "zero Young's modulus",
        'friction = { law = "lugre", mu_c = 0.1 }',
        'friction = { law = "lugre", mu_c = 0.1 }\nball_material = { E = 0.0, nu = 0.3 }',
        "clearance.joints.S_1.ball_material.E",
        "0.0",
        "> 0",
    ),
    (
        "Poisson ratio above 0.5",
        'friction = { law = "lugre", mu_c = 0.1 }',
        'friction = { law = "lugre", mu_c = 0.1 }\nsocket_material = { E = 2e11, nu = 0.7 }',
        "clearance.joints.S_1.socket_material.nu",
        "0.7",
        "-1 < nu <= 0.5",
    ),
    (
        "static friction below Coulomb",
        "mu_c = 0.1",
        "mu_c = 0.2, mu_s = 0.1",
        "clearance.joints.S_1.friction.mu_s",
        "0.1",
        "mu_s >= mu_c",
    ),
    (
        "clearance as large as the ball",
        "radial_clearance = 0.0003",
        "radial_clearance = 1.0",
        "clearance.joints.S_1.radial_clearance",
        "1.0",
        "below ball_radius = 0.015 m",
    ),
    (
        "a period the inverse kinematics cannot follow (aliased: a platform standing still)",
        "[solver]",
        "[trajectory]\nperiod = 0.001\n\n[solver]",
        "trajectory.period",
        "0.001",
        "needs 100001 inverse-kinematics poses (50 per period",
    ),
    (
        "an amplitude that rounds the home pose away (IK blamed a singularity at t = 0)",
        "[solver]",
        "[trajectory.amplitude]\nz = 1e300\n\n[solver]",
        "trajectory.amplitude.z",
        "1e+300",
        "expected at most 100 m in magnitude",
    ),
    (
        "clearance below floating point (check passed, the run failed on R_socket)",
        "radial_clearance = 0.0003",
        "radial_clearance = 1e-20",
        "clearance.joints.S_1.radial_clearance",
        "1e-20",
        "at least 1.5e-11 m (1e-09 of ball_radius = 0.015 m",
    ),
    (
        "invalid TOML syntax",
        "radial_clearance = 0.0003",
        "radial_clearance = 0.3 mm",
        "clearance.joints.S_1.radial_clearance",
        "'0.3 mm'",
        "invalid TOML at line 11",
    ),
]


@pytest.mark.parametrize(
    "old,new,field,value,allowed", [b[1:] for b in BROKEN], ids=[b[0] for b in BROKEN]
)
def test_broken_files_name_file_field_value(
    tmp_path: Path, old: str, new: str, field: str, value: str, allowed: str
) -> None:
    assert old in MINIMAL
    path = tmp_path / "broken.toml"
    path.write_text(MINIMAL.replace(old, new, 1))
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    e = info.value
    assert isinstance(e, cl.ModelError) and isinstance(e, ValueError)
    msg = str(e)
    assert msg.startswith(str(path)), msg
    assert f"field '{field}' = {value} is invalid" in msg, msg
    assert allowed in msg, msg
    assert e.problems[0].field == field


def test_a_byte_order_mark_is_skipped(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_text("\ufeff" + MINIMAL, encoding="utf-8")
    assert load_scenario(path) == loads_scenario(MINIMAL, source=str(path))


def test_rk4_with_clearance_joints_needs_a_step_that_resolves_impacts() -> None:
    """'rk4' (fixed step, no event location) with its default 1 ms step failed on the
    shipped scenario with advice about the linear solver; the file is now refused with
    the reason, and accepted with a step that resolves the impacts."""
    text = MINIMAL.replace("rtol = 1e-6", 'rtol = 1e-6\nmethod = "rk4"')
    with pytest.raises(ScenarioError) as info:
        loads_scenario(text, source="rk4.toml")
    e = info.value
    assert e.field == "solver.step" and "does not locate contact events" in e.allowed
    assert "(the default)" in str(e.value)
    s = loads_scenario(text.replace('method = "rk4"', 'method = "rk4"\nstep = 1e-5'))
    assert s.solver.method == "rk4" and s.solver.step == 1e-5


def test_minimal_file_is_valid() -> None:
    s = loads_scenario(MINIMAL)
    assert s.name == "minimal" and list(s.clearance.joints) == ["S_1"]
    assert s.trajectory.amplitude == dict.fromkeys(("x", "y", "z", "alpha", "beta"), 0.0)


def test_all_errors_reported_together(tmp_path: Path) -> None:
    text = (
        MINIMAL.replace("rtol = 1e-6", "rtol = -1.0\nmax_stepp = 1e-5")
        .replace('name = "minimal"', 'name = "minimal"\ncolour = "red"')
        .replace("radial_clearance = 0.0003", "radial_clearance = 0.0")
        .replace('law = "lugre", mu_c = 0.1', 'law = "lugre", mu_c = -0.1, sigma9 = 1.0')
    )
    path = tmp_path / "many.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    e = info.value
    fields = [p.field for p in e.problems]
    assert fields == [
        "scenario.colour",
        "clearance.joints.S_1.radial_clearance",
        "clearance.joints.S_1.friction.sigma9",
        "clearance.joints.S_1.friction.mu_c",
        "solver.rtol",
        "solver.max_stepp",
    ], fields
    lines = e.lines()
    assert len(lines) == 6 and str(e).splitlines() == lines
    assert all(line.startswith(str(path)) for line in lines)
    assert "did you mean 'max_step'?" in lines[-1]


def test_missing_file_and_non_table() -> None:
    with pytest.raises(ScenarioError, match="file not found"):
        load_scenario("/nonexistent/x.toml")
    with pytest.raises(ScenarioError, match="expected a table"):
        text = MINIMAL.replace("[solver]\nrtol = 1e-6", "")
        loads_scenario(text.replace("format_version = 1", "format_version = 1\nsolver = 3"))


# --------------------------------------------------------------------------- paths


def test_get_and_set_path(default) -> None:
    d = scenario_to_dict(default)
    assert get_path(d, "clearance.joints.S_1.radial_clearance") == 0.3e-3
    assert get_path(d, "clearance.joints.S_3.normal.restitution") == 0.9
    assert get_path(d, "mechanism.theta_deg[2]") == 225.0
    assert get_path(d, "trajectory.amplitude.z") == 0.03
    d2 = set_path(d, "clearance.joints.S_1.radial_clearance", 0.1e-3)
    assert get_path(d2, "clearance.joints.S_1.radial_clearance") == 0.1e-3
    assert get_path(d, "clearance.joints.S_1.radial_clearance") == 0.3e-3  # not mutated
    d3 = set_path(d, "clearance.joints.S_1.socket_radius", 0.0155)  # replaces c
    assert "radial_clearance" not in d3["clearance"]["joints"]["S_1"]
    assert scenario_from_dict(d3).clearance.joints["S_1"].socket_radius == 0.0155
    d4 = set_path(d, "mechanism.phi_deg[0]", 80.0)
    assert scenario_from_dict(d4).mechanism.params.phi_deg[0] == 80.0


@pytest.mark.parametrize(
    "path,match",
    [
        ("clearance.joints.S_1.radial_clearence", "did you mean 'radial_clearance'"),
        ("clearance.joints.S_9.radial_clearance", "allowed: S_1, S_2, S_3, S_4"),
        ("clearance.joints.S_1.normal.mu", "allowed: law, stiffness, exponent, restitution"),
        ("solver.rtol.x", "is a value, not a table"),
        ("mechanism.R_AA", "did you mean 'R_A'"),
        ("solvers.rtol", "did you mean 'solver'"),
        ("trajectory.amplitude.psi", "allowed: x, y, z, alpha, beta"),
        ("solver..rtol", "malformed path"),
    ],
)
def test_invalid_paths(default, path: str, match: str) -> None:
    d = scenario_to_dict(default)
    with pytest.raises(ScenarioError, match=re.escape(match)):
        set_path(d, path, 1.0)
    with pytest.raises(ScenarioError):
        get_path(d, path)


def test_law_fields_follow_the_law_in_the_document(default) -> None:
    d = scenario_to_dict(default)
    with pytest.raises(ScenarioError):
        set_path(d, "clearance.joints.S_1.friction.mu", 0.2)  # LuGre has mu_c, mu_s
    d2 = set_path(d, "clearance.joints.S_1.friction", {"law": "coulomb"})
    d3 = set_path(d2, "clearance.joints.S_1.friction.mu", 0.2)
    assert scenario_from_dict(d3).clearance.joints["S_1"].friction == cl.Coulomb(mu=0.2)


def test_with_overrides(default) -> None:
    s = with_overrides(
        default, {"clearance.joints.S_1.radial_clearance": 0.1e-3, "solver.rtol": 1e-8}
    )
    assert s.clearance.joints["S_1"].radial_clearance == 0.1e-3 and s.solver.rtol == 1e-8
    assert s.clearance.joints["S_3"] == default.clearance.joints["S_3"]
    with pytest.raises(ScenarioError) as info:
        with_overrides(default, {"solver.rtoll": 1.0, "mechanism.R_X": 1.0})
    assert len(info.value.problems) == 2
    with pytest.raises(ScenarioError, match=r"clearance.joints.S_1.radial_clearance' = -1"):
        with_overrides(default, {"clearance.joints.S_1.radial_clearance": -1})


# --------------------------------------------------------------------------- CLI


def test_cli_check() -> None:
    runner = CliRunner()
    path = default_scenario_path()
    r = runner.invoke(app, ["check", str(path)])
    assert r.exit_code == 0, r.output
    lines = r.stdout.splitlines()
    assert lines[0].startswith(f"OK {path}") and len(lines) == 3
    assert lines[1].startswith("inverse kinematics: ")  # (the IK along the trajectory)
    assert lines[2].startswith(("estimated clearance run: about", "cost estimate: after"))
    assert "4ups-upu" in r.stdout and "S_1, S_3" in r.stdout
    r = runner.invoke(app, ["check", str(default_scenario_path("sps_cu"))])
    assert r.exit_code == 0 and "4sps-cu" in r.stdout and "no builder" not in r.stdout


def test_cli_check_errors(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(MINIMAL.replace("rtol = 1e-6", "rtol = 0").replace("0.0003", "-1.0"))
    r = CliRunner().invoke(app, ["check", str(path)])
    assert r.exit_code == 2
    lines = r.stderr.splitlines()
    assert len(lines) == 2 and r.stdout == ""
    assert "field 'clearance.joints.S_1.radial_clearance' = -1.0" in lines[0]
    assert lines[1].startswith(f"{path}: field 'solver.rtol' = 0 is invalid")
    r = CliRunner().invoke(app, ["check", str(tmp_path / "missing.toml")])
    assert r.exit_code == 2 and "file not found" in r.stderr


# --------------------------------------------------------------------------- building


def test_build_default(default) -> None:
    ideal, clr, info = build_mechanisms(default)
    ci, cc = cl.compile_mechanism(ideal), cl.compile_mechanism(clr)
    assert ci.nrow == 66 and ci.nclr == 0
    assert cc.nrow == 60 and cc.nclr == 2
    assert clr.joints["S_1"].clearance == default.clearance.joints["S_1"]
    assert ideal.joints["S_1"].clearance is None  # the ideal mechanism is not modified
    assert info.actuators == tuple(f"drive_{k}" for k in range(1, 6))
    assert all(d in ideal.drivers for d in info.actuators)
    assert info.platform_body in ideal.bodies and info.clearance_joints == ("S_1", "S_3")
    assert info.home_drives == home_leg_lengths() and info.t_end == 2.0
    assert info.simulate_kwargs == default.solver.simulate_kwargs()
    # pose functions: home at t = 0 and t = period, home + amplitude at period / 2
    f = info.pose_functions()
    assert f["z"](0.0) == pytest.approx(0.70) and f["z"](2.0) == pytest.approx(0.70)
    assert f["x"](1.0) == pytest.approx(0.02) and f["angle_1"](1.0) == pytest.approx(0.05)
    assert f["angle_2"](1.0) == pytest.approx(0.05) and f["angle_3"](1.0) == 0.0
    # drives: constant home lengths by default; a mapping by actuator name is accepted
    assert ideal.drivers["drive_5"].function(1.0) == pytest.approx(0.70)
    ideal2, _, _ = build_mechanisms(default, drives={a: 0.75 for a in info.actuators})
    assert ideal2.drivers["drive_3"].function(0.0) == 0.75
    with pytest.raises(ScenarioError, match="missing"):
        build_mechanisms(default, drives={"drive_1": 0.75})


def test_build_platform_trajectory(default) -> None:
    pytest.importorskip("clearance.analysis.ik")
    _, _, info = build_mechanisms(default)
    tr = info.platform_trajectory()
    assert tr.position(1.0) == pytest.approx([0.02, 0.02, 0.73])


def test_build_uses_mechanism_parameters(default) -> None:
    s = with_overrides(default, {"mechanism.platform_mass": 12.0, "mechanism.home_height": 0.65})
    ideal, clr, info = build_mechanisms(s)
    assert ideal.bodies["platform"].mass == 12.0 and info.home_position == (0.0, 0.0, 0.65)
    assert clr.bodies["platform"].mass == 12.0


def test_build_sps_cu_lumped_with_two_body_ik_model() -> None:
    import clearance as cl

    s = load_scenario(default_scenario_path("sps_cu"))
    ideal, clr, info = build_mechanisms(s)
    ci, cc, ck = (cl.compile_mechanism(m) for m in (ideal, clr, info.ik_mechanism))
    assert (ci.nv, ci.nrow) == (36, 32)  # lumped: no driver rows (mechanisms.md 2.2)
    assert cc.nclr == 1 and cc.nrow == 29
    assert (ck.nv, ck.nrow) == (60, 56) and info.actuators == tuple(
        f"drive_{k}" for k in range(1, 5)
    )


def test_build_unregistered_type_is_a_clear_error(monkeypatch) -> None:
    from clearance.scenario import build as b

    s = load_scenario(default_scenario_path("sps_cu"))
    monkeypatch.delitem(b.BUILDERS, s.mechanism.type)
    with pytest.raises(ScenarioError) as info:
        build_mechanisms(s)
    msg = str(info.value)
    assert "field 'mechanism.type' = '4sps-cu'" in msg and "builder not available" in msg


def test_registry_matches_the_factory() -> None:
    """The joint names a file may use are the factory's spherical joints."""
    mech = ups_upu_ideal()
    spherical = [n for n, j in mech.joints.items() if isinstance(j, cl.Spherical)]
    assert spherical == list(MECHANISMS[MechanismType.UPS_UPU].spherical_joints)


# --------------------------------------------------------------------------- parameters


def test_ups_upu_params_overrides() -> None:
    assert dict(UPS_UPU_PARAMS) == UpsUpuParams().to_dict()
    with pytest.raises(TypeError):
        UPS_UPU_PARAMS["R_A"] = 1.0  # type: ignore[index]
    p = UpsUpuParams(R_A=0.45)
    assert home_leg_lengths(p)[0] > home_leg_lengths()[0]
    assert cl.compile_mechanism(ups_upu_ideal({"R_A": 0.45})).nrow == 66
    for bad in (
        {"swing_mass": -1.0},
        {"theta_deg": [0, 90, 180]},
        {"theta_deg": [0, 90, 180, 360]},
        {"swing_inertia": (0.01, 0.01, 0.05)},
        {"tele_com": 0.5},
        {"unknown": 1.0},
    ):
        with pytest.raises(cl.ModelError, match=next(iter(bad))):
            ups_upu_ideal(bad)


# --------------------------------------------------------------------------- docs


def _keys(section: str, t: str | None) -> tuple[str, ...]:
    try:
        return element_keys(section, t)
    except (KeyError, TypeError):
        return ()


def test_docs_document_every_field() -> None:
    text = DOCS.read_text()
    names = [
        *SCENARIO_FIELDS,
        *TRAJECTORY_FIELDS,
        *CLEARANCE_FIELDS,
        *JOINT_FIELDS,
        *SOLVER_FIELDS,
        *OUTPUT_FIELDS,
        *UpsUpuParams.spec(),
        *SpsCuParams.spec(),
        *MECHANISM_KEYS,
        *PLATFORM_KEYS,
        *LEG_KEYS,
        *LINK_KEYS,
        *ATTACH_KEYS,
        *GENERAL_KEYS,
        *(
            f'"{t}"'
            for reg in (JOINT_TYPES, DRIVER_TYPES, FORCE_TYPES, FUNCTION_TYPES)
            for t in reg
        ),
        *(
            k
            for sec in SECTIONS
            for t in (None, *JOINT_TYPES, *DRIVER_TYPES, *FORCE_TYPES)
            if sec in ("bodies", "markers") or t
            for k in _keys(sec, t)
        ),
    ]
    for spec in CLEARANCE_KINDS.values():
        names += [*spec.fields, *spec.tables]
    for cls in (*NORMAL_LAWS.values(), *FRICTION_LAWS.values()):
        names += [f.name for f in dataclasses.fields(cls) if f.init]
    names += [f'"{n}"' for n in (*NORMAL_LAWS, *FRICTION_LAWS)]
    missing = sorted({n for n in names if f"`{n}`" not in text})
    assert not missing, missing


def test_docs_example_validates() -> None:
    blocks = re.findall(r"```toml\n(.*?)```", DOCS.read_text(), flags=re.S)
    s = loads_scenario(blocks[0], source="docs")
    assert s.mechanism.params.platform_mass == 12.0


def test_sps_cu_params_checks() -> None:
    assert SpsCuParams.from_mapping({"column_length": 1.0, "column_top": 0.5}).column_top == 0.5
    with pytest.raises(cl.ModelError, match="column_top"):
        SpsCuParams(column_top=0.5)  # column_length 0.8: the top end is 0.4 above the centre
    with pytest.raises(cl.ModelError, match="limb_model"):
        SpsCuParams(limb_model="three-body")


def test_joint_spec_is_a_deprecated_clearance() -> None:
    """Scenarios hold the model's Clearance; the old JointSpec name still works, warned."""
    from clearance.scenario import JointSpec

    with pytest.warns(DeprecationWarning):
        j = JointSpec(ball_radius=0.015, radial_clearance=0.3e-3)
    assert j.clearance() == cl.Clearance(ball_radius=0.015, radial_clearance=0.3e-3)


# --------------------------------------------------------------------------- clearance kinds

KINDS_TEXT = (
    MINIMAL
    + """
[clearance.joints.P_2]
kind = "prismatic"
width = 0.03
length = 0.06
clearance = 1e-4
model = "planar"
normal = { law = "lankarani_nikravesh", stiffness = 1e10, restitution = 0.8 }
friction = { law = "coulomb", mu = 0.05 }
"""
)


def test_clearance_on_a_prismatic_joint_by_name() -> None:
    """Any clearance-capable joint of a shipped mechanism takes a clearance of its kind; the
    file round-trips and builds; `kind` may be written and must match the joint."""
    s = loads_scenario(KINDS_TEXT)
    p2 = s.clearance.joints["P_2"]
    assert isinstance(p2, cl.PrismaticClearance) and p2.width == 0.03 and p2.model == "planar"
    assert scenario_from_dict(scenario_to_dict(s)) == s
    assert scenario_to_dict(s)["clearance"]["joints"]["P_2"]["kind"] == "prismatic"
    _, clr, _ = build_mechanisms(s)
    assert clr.joints["P_2"].clearance == p2
    c = cl.compile_mechanism(clr)
    assert [ci.kind for ci in c.clearances] == ["spherical", "prismatic"]  # mech.joints order
    assert c.nrow == 66 - 3 - 5 + 3  # S_1 keeps none of its 3 rows, P_2 keeps 3 of its 5
    r = cl.simulate(c, 0.005, dt_out=1e-3)
    assert r.success, r.message


def test_clearance_in_a_universal_joints_revolute_pair() -> None:
    """A universal joint's revolute pair takes a clearance by the joint's name: the cross
    becomes a body and the pair a revolute clearance joint `U_1.j`; the file round-trips."""
    text = (
        MINIMAL
        + """
[clearance.joints.U_1]
pair = "j"
cross_mass = 0.05
cross_inertia = [2e-6, 2e-6, 3e-6]
journal_radius = 0.004
radial_clearance = 5e-5
normal = { law = "lankarani_nikravesh", stiffness = 1e10, restitution = 0.8 }
"""
    )
    s = loads_scenario(text)
    u1 = s.clearance.joints["U_1"]
    assert isinstance(u1, cl.UniversalClearance) and u1.pair == "j"
    assert scenario_to_dict(s)["clearance"]["joints"]["U_1"]["kind"] == "universal"
    assert scenario_from_dict(scenario_to_dict(s)) == s
    ideal, clr, _ = build_mechanisms(s)
    assert "U_1" in ideal.joints and "U_1" not in clr.joints
    assert clr.joints["U_1.j"].clearance == u1.revolute()
    assert clr.joints["U_1.i"].clearance is None and "U_1.cross" in clr.bodies
    c = cl.compile_mechanism(clr)
    assert [ci.name for ci in c.clearances] == ["U_1.j", "S_1"]  # mech.joints order
    assert c.nrow == 66 - 3 - 4 + 5 + 3  # S_1 keeps none; U_1 -> revolute + planar clearance
    r = cl.simulate(c, 0.005, dt_out=1e-3)
    assert r.success, r.message


@pytest.mark.parametrize(
    ("text", "field", "allowed"),
    [
        (
            '[clearance.joints.P_2]\nkind = "revolute"\nwidth = 0.03',
            "kind",
            "its clearance kind is 'prismatic'",
        ),
        ("[clearance.joints.Q_1]\nwidth = 0.03", "clearance.joints.Q_1", "can have clearance: S_1"),
        (
            '[clearance.joints.U_1]\npair = "j"\ncross_inertia = [1e-6, 1e-6, 2e-6]\n'
            "journal_radius = 0.005\nradial_clearance = 1e-4",
            "clearance.joints.U_1.cross_mass",
            "required",
        ),
        (
            '[clearance.joints.U_1]\npair = "j"\ncross_mass = 0.02\ncross_inertia = [1e-6, 0]\n'
            "journal_radius = 0.005\nradial_clearance = 1e-4",
            "clearance.joints.U_1.cross_inertia",
            "3 finite numbers > 0",
        ),
        ("[clearance.joints.P_2]\nwidth = 0.03\nlength = 0.06", "clearance", "required"),
        ("[clearance.joints.P_2]\nwidht = 0.03", "widht", "did you mean 'width'"),
    ],
)
def test_clearance_kind_errors_name_the_field(text, field, allowed) -> None:
    with pytest.raises(ScenarioError) as err:
        loads_scenario(MINIMAL + "\n" + text + "\n")
    assert any(field in p.field and allowed in p.allowed for p in err.value.problems), err.value


def test_sps_cu_cylindrical_and_two_body_prismatic_clearance() -> None:
    text = default_scenario_path("sps_cu").read_text()
    extra = """
[clearance.joints.C]
journal_radius = 0.02
radial_clearance = 1e-4
model = "spatial"
length = 0.05
normal = { law = "johnson", restitution = 0.9 }
"""
    s = loads_scenario(text + extra)
    assert isinstance(s.clearance.joints["C"], cl.RevoluteClearance)
    assert scenario_to_dict(s)["clearance"]["joints"]["C"]["kind"] == "cylindrical"
    assert scenario_from_dict(scenario_to_dict(s)) == s
    with pytest.raises(ScenarioError, match="limb_model = 'two-body'"):
        loads_scenario(
            text + "\n[clearance.joints.P_1]\nwidth = 0.02\nlength = 0.05\nclearance = 1e-4\n"
        )


def test_paths_know_the_fields_of_each_kind() -> None:
    d = scenario_to_dict(loads_scenario(KINDS_TEXT))
    d2 = set_path(d, "clearance.joints.P_2.clearance", 2e-4)
    assert get_path(d2, "clearance.joints.P_2.clearance") == 2e-4
    assert with_overrides(loads_scenario(KINDS_TEXT), {"clearance.joints.P_2.width": 0.04})
    with pytest.raises(ScenarioError, match="allowed: kind, width, length"):
        set_path(d, "clearance.joints.P_2.ball_radius", 0.01)


def test_registry_lists_every_clearance_capable_joint_with_its_kind() -> None:
    mech = ups_upu_ideal()
    kinds = {
        cl.Spherical: "spherical",
        cl.Prismatic: "prismatic",
        cl.Revolute: "revolute",
        cl.Universal: "universal",
    }
    expected = {n: kinds[type(j)] for n, j in mech.joints.items() if type(j) in kinds}
    assert dict(MECHANISMS[MechanismType.UPS_UPU].clearance_joints) == expected


@pytest.mark.parametrize(
    "change,field,value",
    [
        ({"radial_clearance": 1.0}, "clearance.joints.S_1.radial_clearance", "1.0"),
        ({"friction": {"law": "lugre", "mu_c": -1.0, "mu_s": 0.05}}, "friction.mu_c", "-1.0"),
        ({"friction": {"law": "lugre", "mu_c": 0.2}}, "friction.mu_s", "(the default)"),
    ],
)
def test_one_mistake_one_problem(change, field, value) -> None:
    """A relation refused on one field is reported once: not again through the retry
    without that field (socket_radius 'give exactly one of ...', mu_s against the default
    mu_c); a default that breaks a relation with a written value says it is the default."""
    d = scenario_to_dict(load_scenario(default_scenario_path()))
    d["clearance"]["joints"]["S_1"].update(change)
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict(d, source="one.toml")
    (p,) = info.value.problems
    assert p.field.endswith(field) and value in str(p), str(p)


# --------------------------------------------------------------------------- [checks]


def test_checks_section_sets_the_thresholds_and_round_trips(tmp_path: Path) -> None:
    """[checks] (optional): the plausibility thresholds, the rk4 step limit and the long-run
    threshold, validated, written back, and reachable by study overrides."""
    s = loads_scenario(MINIMAL)
    assert s.checks == ChecksSpec()  # absent: the PROPOSED defaults
    text = MINIMAL + "\n[checks]\npenetration_implausible = 0.5\nlong_run = inf\n"
    s = loads_scenario(text)
    assert s.checks.penetration_implausible == 0.5 and s.checks.long_run == math.inf
    assert s.checks.plausibility_kwargs()["penetration_implausible"] == 0.5
    again = loads_scenario(scenario_to_toml(s))
    assert again == s and "[checks]" in scenario_to_toml(s)
    s2 = with_overrides(s, {"checks.energy_warning": 1e-4})
    assert s2.checks.energy_warning == 1e-4
    for bad, field, allowed in (
        ("penetration_warning = 2.0", "checks.penetration_warning", "at most penetration_impl"),
        ("energy_implausible = -1", "checks.energy_implausible", "> 0"),
        ("radius_implausibel = 0.1", "checks.radius_implausibel", "radius_implausible"),
    ):
        with pytest.raises(ScenarioError) as e:
            loads_scenario(MINIMAL + f"\n[checks]\n{bad}\n", source="c.toml")
        assert e.value.problems[0].field == field and allowed in str(e.value), str(e.value)


def test_rk4_step_limit_comes_from_checks() -> None:
    rk4 = MINIMAL.replace("rtol = 1e-6", 'method = "rk4"\nstep = 1e-4')
    with pytest.raises(ScenarioError, match=r"step <= 1e-05 s .*rk4_clearance_step"):
        loads_scenario(rk4)
    s = loads_scenario(rk4 + "\n[checks]\nrk4_clearance_step = 1e-4\n")
    assert s.solver.step == 1e-4


def test_checks_thresholds_reach_the_run_summary_and_check(tmp_path: Path) -> None:
    """The default scenario's 0.014 c of penetration is plausible by default; with
    penetration_implausible = 1e-3 the same run is implausible (exit code 3); long_run = 1e-6
    makes `check` warn about the cost."""
    from clearance.pipeline import implausible

    s = with_overrides(
        load_scenario(default_scenario_path()),
        {"trajectory.duration": 0.1, "solver.dt_out": 1e-3, "output.figures": False},
    )
    strict = with_overrides(
        s, {"checks.penetration_implausible": 1e-3, "checks.penetration_warning": 1e-4}
    )
    o = run_scenario(strict, out_dir=tmp_path, log=None)
    assert implausible(o.summary) == ["clearance"]
    p = o.summary["clearance"]["plausibility"]
    assert "times the clearance" in p["findings"][0]
    path = tmp_path / "s.toml"
    text = default_scenario_path().read_text(encoding="utf-8")
    path.write_text(re.sub(r"^long_run = .*$", "long_run = 1e-6", text, flags=re.M))
    r = CliRunner().invoke(app, ["check", str(path)])
    assert r.exit_code == 0 and "warning: this run may take" in r.output, r.output


def test_a_material_with_both_fields_wrong_reports_both(tmp_path: Path) -> None:
    text = MINIMAL.replace(
        'normal = { law = "flores"',
        'ball_material = { E = -1.0, nu = 0.7 }\nnormal = { law = "flores"',
        1,
    )
    with pytest.raises(ScenarioError) as e:
        loads_scenario(text, source="m.toml")
    fields = [p.field for p in e.value.problems]
    assert fields == [
        "clearance.joints.S_1.ball_material.E",
        "clearance.joints.S_1.ball_material.nu",
    ], str(e.value)
    assert "expected -1 < nu <= 0.5" in str(e.value)


def test_long_runs_are_not_capped_by_the_ik_pose_limit() -> None:
    """The IK pose limit is for periods that force dense sampling: a 300 s run with a
    300 s period (15 001 poses at 0.02 s) is accepted, as before; a 300 s run whose 0.5 s
    period needs 30 001 poses is refused on the period, with a bound that is accepted."""
    ok = MINIMAL.replace("[solver]", "[trajectory]\nduration = 300.0\nperiod = 300.0\n\n[solver]")
    assert loads_scenario(ok).trajectory.duration == 300.0
    bad = ok.replace("period = 300.0", "period = 0.5")
    with pytest.raises(ScenarioError, match=r"use a period of at least 1.5 s") as e:
        loads_scenario(bad)
    assert e.value.problems[0].field == "trajectory.period"
    assert loads_scenario(ok.replace("period = 300.0", "period = 1.5")).trajectory.period == 1.5
