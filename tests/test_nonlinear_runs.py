"""Steady-state scenarios ([steady_state]), `clearance analyze` on their result files and
`clearance bifurcation` over a one-parameter study on a LocalCluster of 2 workers (short
runs: the full diagram is `bench/bench_bifurcation.py`)."""

from __future__ import annotations

import numpy as np
import pytest
import tomllib
import xarray as xr
from typer.testing import CliRunner

from clearance.cli.main import app
from clearance.model.errors import ModelError
from clearance.nonlinear.analyze import analyze
from clearance.scenario import ScenarioError, default_scenario_path, scenario_from_dict
from clearance.scenario.serialize import scenario_to_dict
from clearance.scenario.toml_io import dumps_toml


def _base() -> dict:
    d = tomllib.loads(default_scenario_path().read_text())
    d["trajectory"].update(duration=0.25, period=0.05)  # 5 periods of a 20 Hz drive
    d["solver"].pop("dt_out")
    d["steady_state"] = {"transient_periods": 1, "samples_per_period": 40}
    return d


def test_steady_state_section_validation_and_round_trip():
    s = scenario_from_dict(_base())
    st = s.steady_state
    assert (st.period, st.periods, st.transient_periods, st.samples_per_period) == (
        0.05,
        5,
        1,
        40,
    )
    assert s.solver.dt_out == pytest.approx(0.05 / 40, rel=1e-15)
    t = st.t_out()
    assert t.size == 201 and t[-1] == 0.25
    assert np.array_equal(t[st.strobe_indices(t.size)], 0.05 * np.arange(1, 6))  # exact
    again = scenario_from_dict(scenario_to_dict(s))
    assert again.steady_state == st and again.solver == s.solver
    d = _base()
    d["steady_state"]["section"] = {"body": "platform", "coordinate": "vz", "value": 0}
    st = scenario_from_dict(d).steady_state
    assert st.section == {"body": "platform", "coordinate": "vz", "value": 0.0, "direction": 1}
    assert scenario_from_dict(scenario_to_dict(scenario_from_dict(d))).steady_state == st
    d = _base()
    d["steady_state"]["phase"] = 0.999  # rounds to the next period's 0 on a grid of 40
    st = scenario_from_dict(d).steady_state
    assert st.phase == 0.0 and st.strobe_indices(201)[0] == 40
    bad = {
        "steady_state.lyapunov_periods": ({"lyapunov_periods": 3}, ">= 10 renormalisations"),
        "steady_state.section.coordinate": (
            {"section": {"body": "platform", "coordinate": "h"}},
            "allowed: x, y, z",
        ),
        "steady_state.section.direction": (
            {"section": {"body": "platform", "direction": 2}},
            "allowed: 1",
        ),
        "steady_state.section.body": ({"section": {"value": 0.7}}, "required"),
        "steady_state.section": ({"section": 1.0}, "expected a table"),
        "steady_state.transient_periods": ({"transient_periods": 5}, "fewer than the run's 5"),
        "steady_state.period": ({"period": 0.07}, "not periodic with this period"),
        "steady_state.phase": ({"phase": 1.0}, "[0, 1)"),
        "steady_state.samples_per_period": ({"samples_per_period": 0}, ">= 1"),
        "steady_state.periods": ({"periods": 3}, "did you mean"),
    }
    for field, (table, allowed) in bad.items():
        d = _base()
        d["steady_state"] = table
        with pytest.raises(ScenarioError) as e:
            scenario_from_dict(d, source="s.toml")
        msg = str(e.value)
        assert f"'{field}'" in msg and allowed in msg and "s.toml" in msg, msg
    d = _base()
    d["trajectory"]["duration"] = 0.26
    with pytest.raises(ScenarioError, match=r"trajectory.duration.*whole number"):
        scenario_from_dict(d)
    d = _base()
    d["solver"]["dt_out"] = 1e-3  # samples_per_period replaces it
    assert scenario_from_dict(d).solver.dt_out == pytest.approx(0.05 / 40, rel=1e-15)
    d["steady_state"].pop("samples_per_period")  # else dt_out sets it
    assert scenario_from_dict(d).steady_state.samples_per_period == 50
    d = _base()
    d["trajectory"] = {**d["trajectory"], "shape": "via-points", "period": None}
    d["trajectory"].pop("period")
    d["trajectory"].pop("amplitude")
    d["trajectory"]["via_points"] = {"t": [0.0, 0.25], "z": [0.0, 0.01]}
    with pytest.raises(ScenarioError, match="needs a periodic drive"):
        scenario_from_dict(d)


@pytest.fixture(scope="module")
def steady_file(tmp_path_factory):
    """A steady-state run of the default mechanism written by `clearance run`."""
    folder = tmp_path_factory.mktemp("steady")
    d = _base()
    d["output"] = {**d["output"], "folder": str(folder / "res"), "figures": False}
    d["steady_state"]["section"] = {"body": "platform", "coordinate": "vz", "direction": -1}
    f = folder / "steady.toml"
    f.write_text(dumps_toml(d))
    r = CliRunner().invoke(app, ["run", str(f), "--no-figures"])
    assert r.exit_code == 0, r.output
    return folder / "res" / "ups_upu.nc", f


def test_analyze_command_on_a_steady_state_run(steady_file):
    nc, _ = steady_file
    ds = xr.load_dataset(nc, engine="netcdf4", group="clearance")
    root = xr.load_dataset(nc, engine="netcdf4")
    assert root.attrs["steady_period"] == 0.05 and root.attrs["steady_transient_periods"] == 1
    t = ds["time"].values
    assert np.array_equal(t[::40], 0.05 * np.arange(6))  # the strobe times, exactly
    runner = CliRunner()
    r = runner.invoke(app, ["analyze", str(nc), "--section", "eccentricity[S_1,x]"])
    assert r.exit_code == 0, r.output
    for what in ("response", "distinct Poincare points", "section crossings", "evidence"):
        assert what in r.output
    out = nc.parent / "ups_upu_analysis.nc"
    a = xr.load_dataset(out, engine="netcdf4", group="analysis")
    assert a.sizes["point"] == 5 and a.sizes["channel"] == 5
    assert np.array_equal(a["poincare_time"].values, 0.05 * np.arange(1, 6))
    z = ds["position"].sel(body="platform", axis="z").values
    assert np.array_equal(a["poincare"].sel(channel="position[platform,z]").values, z[40::40])
    assert a.attrs["classification"] in ("period-1", "undetermined", "quasi-periodic", "chaotic")
    for name in ("phase_portraits", "poincare", "spectra"):
        assert (nc.parent / f"ups_upu_clearance_{name}.png").stat().st_size > 10_000
    # the run's own section (platform vz = 0 downward, located in the integration loop):
    # the file's crossings, used by analyze without --section
    vz = ds["section_velocity"].sel(body="platform", axis="z").values
    assert ds.sizes["crossing"] >= 4 and np.max(np.abs(vz)) < 1e-12
    r = runner.invoke(app, ["analyze", str(nc), "--no-figures"])
    assert r.exit_code == 0 and "(located in the integration loop)" in r.output, r.output
    a2 = xr.load_dataset(out, engine="netcdf4", group="analysis")
    ts = a2["section_time"].values
    assert np.array_equal(ts, ds["section_time"].values[ds["section_time"].values >= 0.05])
    z_sec = ds["section_position"].sel(body="platform", axis="z").values
    got = a2["section_points"].sel(channel="position[platform,z]").values
    assert np.array_equal(got, z_sec[-got.size :])
    # the Hermite-located crossings of --section lie on the section
    sec = a["section_points"].sel(channel="eccentricity[S_1,x]").values
    assert sec.size > 0 and np.max(np.abs(sec)) < 1e-3 * np.ptp(
        ds["eccentricity"].sel(clearance="S_1", axis="x").values
    )


def test_analyze_says_when_a_run_stopped_early(steady_file, tmp_path):
    """A run stopped by its step budget is not a steady state: analyze says so instead of
    classifying it."""
    d = _base()
    d["output"] = {**d["output"], "folder": str(tmp_path / "res"), "figures": False}
    d["solver"]["max_steps"] = 20_000  # (about 3 of the 5 periods)
    f = tmp_path / "short.toml"
    f.write_text(dumps_toml(d))
    r = CliRunner().invoke(app, ["run", str(f), "--no-figures"])
    assert r.exit_code != 0 and "steady state (" not in r.output
    nc = tmp_path / "res" / "ups_upu.nc"
    a = analyze(nc, transient_periods=0)
    assert a.classification.kind == "undetermined"
    assert "stopped early" in a.classification.reasons[0]


def test_analyze_refuses_what_it_cannot_do(steady_file, tmp_path):
    nc, _ = steady_file
    runner = CliRunner()
    for args, text in (
        (["--channel", "position[base,z]"], "body 'base' not in"),
        (["--channel", "oops"], "no time history 'oops'"),
        (["--transient", "5"], "fewer than 2 periods"),
        (["--period", "0.0333"], "not a whole multiple of the output interval"),
    ):
        r = runner.invoke(app, ["analyze", str(nc), "--no-figures", *args])
        assert r.exit_code == 2, (args, r.output)
        assert text in r.output and "Traceback" not in r.output, r.output
    ds = analyze(nc, period=0.1)  # a whole multiple of the grid: exact samples, 0 transient
    assert ds.strobe.shape[0] == 3 and ds.steady.source == "option"
    r = runner.invoke(app, ["analyze", str(tmp_path / "none.nc")])
    assert r.exit_code == 2 and "no such result file" in r.output


def test_bifurcation_over_clearance_on_a_local_cluster(steady_file, tmp_path):
    """`clearance bifurcation STUDY --workers 2` runs the cases on a LocalCluster, draws the
    diagram and writes its NetCDF and table; a second call finds every case finished;
    --collect on the folder draws from the files alone."""
    _, scenario = steady_file
    study = tmp_path / "bif.toml"
    folder = tmp_path / "study"
    study.write_text(
        f"""format_version = 1
[study]
name = "bif"
base = "{scenario}"
folder = "{folder}"
[set]
trajectory.duration = 0.2
[[parameter]]
name = "radial_clearance"
path = ["clearance.joints.S_1.radial_clearance", "clearance.joints.S_3.radial_clearance"]
values = [5e-4, 1e-4, 3e-4]
"""
    )
    runner = CliRunner()
    r = runner.invoke(app, ["bifurcation", str(study), "--workers", "2"])
    assert r.exit_code == 0, r.output
    assert "LocalCluster, 2 workers" in r.output
    b = xr.load_dataset(
        folder / "collected" / "bifurcation.nc", engine="netcdf4", group="bifurcation"
    )
    assert list(b["radial_clearance"].values) == [1e-4, 3e-4, 5e-4]  # in parameter order
    assert b["poincare"].shape == (3, 4, 5)  # cases, points (periods 1..4), channels
    assert (folder / "collected" / "bifurcation.png").stat().st_size > 10_000
    # each case's points are its own file's stroboscopic samples
    for cid, c in zip(b["case"].values, b["radial_clearance"].values, strict=True):
        ds = xr.load_dataset(folder / "cases" / f"{cid}.nc", engine="netcdf4", group="clearance")
        z = ds["position"].sel(body="platform", axis="z").values[40::40]
        got = b["poincare"].sel(case=cid, channel="position[platform,z]").values
        assert np.array_equal(got, z), c
    r = runner.invoke(app, ["bifurcation", str(study), "--scheduler", "serial"])
    assert r.exit_code == 0 and "3 already finished" in r.output, r.output
    r = runner.invoke(app, ["bifurcation", str(folder), "--channel", "eccentricity[S_1,x]"])
    assert r.exit_code == 0 and "eccentricity[S_1,x]" in r.output, r.output
    two = study.read_text().replace(
        "values = [5e-4, 1e-4, 3e-4]",
        'values = [5e-4, 1e-4]\n[[parameter]]\npath = "solver.rtol"\nvalues = [1e-6]',
    )
    study.write_text(two)
    r = runner.invoke(app, ["bifurcation", str(study)])
    assert r.exit_code == 2 and "exactly one parameter" in r.output, r.output


def test_bifurcation_continuation_starts_each_case_from_the_previous_end(steady_file, tmp_path):
    """--continuation runs the cases in order, each clearance run starting from the previous
    case's final state (whole periods: the drive's phase matches), not from the centred
    placement; a state of the wrong layout is refused with a message."""
    from clearance.io.dataset import load_results
    from clearance.pipeline import run_scenario

    _, scenario = steady_file
    study = tmp_path / "cont.toml"
    folder = tmp_path / "cont"
    study.write_text(
        f"""format_version = 1
[study]
name = "cont"
base = "{scenario}"
folder = "{folder}"
[set]
trajectory.duration = 0.1
[[parameter]]
path = "clearance.joints.S_1.friction.mu_c"
values = [0.1, 0.05]
"""
    )
    r = CliRunner().invoke(app, ["bifurcation", str(study), "--continuation"])
    assert r.exit_code == 0, r.output
    assert "from the scenario's start" in r.output and "from the previous case's end" in r.output
    man = {c["values"]["clearance.joints.S_1.friction.mu_c"]: c["id"] for c in _cases(folder)}
    first = load_results(folder / "cases" / f"{man[0.1]}.nc")
    second = load_results(folder / "cases" / f"{man[0.05]}.nc")
    e_end = first["clearance"]["eccentricity"].sel(clearance="S_1").values[-1]
    e_start = second["clearance"]["eccentricity"].sel(clearance="S_1").values[0]
    assert np.linalg.norm(e_end) > 1e-5  # (not centred)
    assert np.max(np.abs(e_start - e_end)) < 1e-9, (e_start, e_end)
    y = np.asarray(first.attrs["clearance_final_state"])
    with pytest.raises(ModelError, match=r"y0.*expected \d+ finite numbers"):
        run_scenario(scenario, out_dir=tmp_path / "x", y0=y[:-1], log=None, figures=False)


def _cases(folder):
    import json

    return json.loads((folder / "study.json").read_text())["cases"]


def test_shipped_bifurcation_study_is_valid():
    from pathlib import Path

    import clearance
    from clearance.sweep.bifurcation import check_bifurcation_study
    from clearance.sweep.study import load_study

    s = load_study(Path(clearance.__file__).parent / "data" / "studies" / "bifurcation.toml")
    assert check_bifurcation_study(s) == "radial_clearance" and len(s.cases) == 10
    v = sorted(c.values["radial_clearance"] for c in s.cases)
    assert v[0] == pytest.approx(5e-5) and v[-1] == pytest.approx(5e-4)
    assert s.base["steady_state"]["transient_periods"] == 20


IMPACT_OSCILLATOR = """
format_version = 1
[scenario]
name = "impact_oscillator"
[mechanism]
type = "general"
gravity = [0.0, 0.0, 0.0]
platform = "ball"
[mechanism.bodies.ball]
mass = 1.0
inertia = [0.01, 0.01, 0.01]
[mechanism.markers.g]
body = "ground"
axis = [1.0, 0.0, 0.0]
[mechanism.markers.b]
body = "ball"
axis = [1.0, 0.0, 0.0]
[mechanism.markers.anchor]
body = "ground"
position = [-0.5, 0.0, 0.0]
[mechanism.joints.p]
type = "prismatic"
marker_i = "g"
marker_j = "b"
[mechanism.joints.S]
type = "spherical"
marker_i = "g"
marker_j = "b"
[mechanism.forces.k]
type = "spring_damper"
marker_i = "anchor"
marker_j = "b"
stiffness = 1000.0
damping = 2.0
free_length = 0.5
[mechanism.forces.F]
type = "point_force"
marker = "b"
direction = [1.0, 0.0, 0.0]
magnitude = { type = "sinusoid", amplitude = 2.0, omega = 25.0 }
[trajectory]
duration = 15.079644737231007   # 60 periods of 2 pi / 25
[clearance.joints.S]
ball_radius = 0.01
radial_clearance = 0.001
normal = { law = "flores", restitution = 0.9 }
friction = { law = "none" }
[solver]
method = "tsit5"
rtol = 1e-10
atol = 1e-13
[output]
folder = "OUT"
figures = false
[steady_state]
period = 0.25132741228718345    # 2 pi / 25
transient_periods = 50
samples_per_period = 50
lyapunov_periods = 150
"""


def test_general_scenario_with_steady_state_and_lyapunov_in_the_summary(tmp_path):
    """The impact oscillator of tests/test_nonlinear.py as a file (type general, its own
    force as the drive, so steady_state.period is required): `clearance run` classifies it
    period-1 and reports the two-trajectory exponent of [steady_state] lyapunov_periods
    against the independent oracle's monodromy value -1.8936 1/s."""
    from clearance.io.dataset import load_results

    f = tmp_path / "impact.toml"
    f.write_text(IMPACT_OSCILLATOR.replace("OUT", str(tmp_path / "res")))
    r = CliRunner().invoke(app, ["run", str(f)])
    assert r.exit_code == 0, r.output
    assert "steady state (11 Poincare points after the transient): period-1" in r.output
    assert "largest Lyapunov exponent" in r.output
    attrs = load_results(tmp_path / "res" / "impact_oscillator.nc").attrs
    assert attrs["lyapunov_exponent"] == pytest.approx(-1.8936358, rel=0.03), attrs
    bad = IMPACT_OSCILLATOR.replace("period = 0.25132741228718345", "")
    with pytest.raises(ScenarioError, match=r"steady_state.period.*required"):
        scenario_from_dict(tomllib.loads(bad))


def test_a_section_of_an_unknown_body_is_refused_before_the_run(tmp_path):
    from clearance.pipeline import run_scenario

    d = _base()
    d["steady_state"]["section"] = {"body": "plattform", "coordinate": "vz"}
    d["output"] = {**d["output"], "folder": str(tmp_path / "res")}
    with pytest.raises(ScenarioError, match=r"steady_state.section.body.*'platform'"):
        run_scenario(scenario_from_dict(d, source="s.toml"), log=None, figures=False)
    assert not (tmp_path / "res" / "ups_upu.nc").exists()
