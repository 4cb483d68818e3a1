"""Trajectory shapes of scenario files: periodic, via-points, table (CSV).

Oracles: the sums of sinusoids written out; the rest-to-rest quintic 10 s^3 - 15 s^4 +
6 s^5 (two via points); interpolation through the via points and table rows, zero rates at
the via path's ends, continuity of the second derivative across via points; the ideal
3-RPS, driven by the inverse kinematics of each shape, follows it (1e-9 m, 1e-9 rad).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import clearance as cl
from clearance.scenario import (
    ScenarioError,
    build_mechanisms,
    load_scenario,
    loads_scenario,
    scenario_to_toml,
)

RPS = """
format_version = 1
[scenario]
name = "rps"
[mechanism]
type = "parallel"
[mechanism.platform]
mass = 5.0
inertia = [0.05, 0.05, 0.1]
position = [0.0, 0.0, 0.5]
[[mechanism.legs]]
joints = "RPS"
base = { radius = 0.3, angles_deg = [90, 210, 330] }
platform = { radius = 0.15, angles_deg = [90, 210, 330] }
links = [{ mass = 1.0, inertia = [0.0075, 0.0075, 1e-5], com = 0.15, length = 0.3 },
         { mass = 1.0, inertia = [0.0075, 0.0075, 1e-5], com = 0.15, length = 0.3 }]
[trajectory]
orientation = "axis"
positions = ["z"]
"""

PERIODIC = """shape = "periodic"
duration = 1.0
period = 0.5
[trajectory.periodic]
z = { amplitude = 0.01 }
alpha = [{ amplitude = 0.02, period = 0.25 }, { amplitude = 0.01, phase = 1.0 }]
"""
VIA = """shape = "via-points"
duration = 1.2
[trajectory.via_points]
t = [0.0, 0.3, 0.7, 1.0]
z = [0.0, 0.01, 0.012, 0.0]
beta = [0.0, 0.02, -0.02, 0.0]
"""
TABLE = """shape = "table"
duration = 0.5
[trajectory.table]
file = "motion.csv"
"""
CSV = """# t [s], z [m], alpha [rad]
t,z,alpha
0.0,0.0,0.0
0.1,0.001,0.002
0.2,0.004,0.006
0.3,0.008,0.01
0.4,0.011,0.012
0.5,0.012,0.012
"""


def _scenario(body: str, tmp_path=None, csv: str = CSV):
    if tmp_path is None:
        return loads_scenario(RPS + body, source="rps.toml")
    (tmp_path / "motion.csv").write_text(csv)
    f = tmp_path / "rps.toml"
    f.write_text(RPS + body)
    return load_scenario(f)


def test_periodic_is_the_sum_of_its_sinusoids() -> None:
    s = _scenario(PERIODIC)
    f = build_mechanisms(s)[2].pose_functions()
    t = np.linspace(0.0, 1.0, 37)
    z = f["z"].evaluate(t)
    w1, w2 = 2 * math.pi / 0.5, 2 * math.pi / 0.25
    assert np.allclose(z[:, 0], 0.5 + 0.01 * np.sin(w1 * t), atol=1e-15)
    assert np.allclose(z[:, 2], -0.01 * w1**2 * np.sin(w1 * t), atol=1e-12)
    a = f["angle_1"].evaluate(t)
    ref = 0.02 * np.sin(w2 * t) + 0.01 * np.sin(w1 * t + 1.0)
    assert np.allclose(a[:, 0], ref, atol=1e-15)
    # the IK samples at least 50 times per shortest period (0.25 s)
    assert np.max(np.diff(s.trajectory.ik_times())) <= 0.25 / 50 + 1e-15
    assert loads_scenario(scenario_to_toml(s)) == s


def test_two_via_points_are_the_rest_to_rest_quintic() -> None:
    body = """shape = "via-points"
duration = 2.0
[trajectory.via_points]
t = [0.0, 1.5]
z = [0.0, 0.03]
"""
    f = build_mechanisms(_scenario(body))[2].pose_functions()["z"]
    t = np.linspace(0.0, 2.0, 41)
    s = np.clip(t / 1.5, 0.0, 1.0)
    ref = 0.5 + 0.03 * (10 * s**3 - 15 * s**4 + 6 * s**5)
    assert np.max(np.abs(f.evaluate(t)[:, 0] - ref)) < 1e-15


def test_via_points_are_passed_at_rest_at_the_ends_and_c2() -> None:
    s = _scenario(VIA)
    f = build_mechanisms(s)[2].pose_functions()
    for name, col in (("z", "z"), ("angle_2", "beta")):
        v = f[name].evaluate(np.array(s.trajectory.samples["t"]))
        home = 0.5 if name == "z" else 0.0
        assert np.allclose(v[:, 0] - home, s.trajectory.samples[col], atol=1e-15)
        assert np.allclose(v[[0, -1], 1:], 0.0, atol=1e-12)  # at rest at both ends
        for tk in (0.3, 0.7):  # second derivative continuous across the via points
            lo, hi = f[name].derivatives(tk - 1e-9), f[name].derivatives(tk + 1e-9)
            assert abs(lo[2] - hi[2]) < 1e-6 * max(1.0, abs(lo[2]))
    assert f["z"](1.1) == pytest.approx(0.5)  # held after the last point
    ts = s.trajectory.ik_times()
    assert {0.3, 0.7} <= {round(float(x), 12) for x in ts}
    assert loads_scenario(scenario_to_toml(s)) == s


def test_table_from_csv_interpolates_its_rows(tmp_path) -> None:
    s = _scenario(TABLE, tmp_path)
    t = np.array(s.trajectory.samples["t"])
    f = build_mechanisms(s)[2].pose_functions()
    assert np.allclose(f["z"].evaluate(t)[:, 0] - 0.5, [0, 0.001, 0.004, 0.008, 0.011, 0.012])
    # the canonical form carries the columns (no file needed to run it again)
    text = scenario_to_toml(s)
    assert "motion.csv" not in text and loads_scenario(text) == s


@pytest.mark.parametrize(
    "body, csv, field, says",
    [
        (TABLE.replace("motion.csv", "nope.csv"), CSV, "trajectory.table.file", "cannot read"),
        (TABLE, CSV.replace("t,z,alpha", "time,z,alpha"), "trajectory.table.time", "unknown"),
        (TABLE, CSV.replace("0.3,0.008", "0.3,abc"), "table.file", "row 5, column 'z': 'abc'"),
        (TABLE, CSV.replace("0.3,", "0.25,", 1).replace("0.2,", "0.3,", 1), "table.t", "increase"),
        (TABLE.replace("duration = 0.5", "duration = 0.8"), CSV, "table.t", "cover [0, duration"),
        (TABLE, CSV.replace(",alpha", ",gamma", 1), "trajectory.table.gamma", "must not move"),
        (TABLE + "t = [0.0, 0.5]\n", CSV, "trajectory.table.t", "give the file or"),
        (VIA.replace("t = [0.0,", "t = [0.1,"), CSV, "via_points.t", "first via point"),
        (VIA.replace("0.012, 0.0]", "0.012]"), CSV, "via_points.z", "4 finite"),
        (
            PERIODIC.replace("{ amplitude = 0.01", "{ amplitud = 0.01"),
            CSV,
            "periodic.z",
            "amplitud",
        ),
        (PERIODIC.replace("period = 0.25", "period = -1"), CSV, "periodic.alpha[0].period", "> 0"),
        (PERIODIC + "[trajectory.amplitude]\nz = 0.01\n", CSV, "trajectory.amplitude", "not used"),
        (PERIODIC.replace("periodic]", "other]"), CSV, "trajectory.periodic", "required"),
    ],
)
def test_bad_trajectory_tables_are_refused(body, csv, field, says, tmp_path) -> None:
    with pytest.raises(ScenarioError) as e:
        _scenario(body, tmp_path, csv)
    lines = e.value.lines()
    assert any(field in ln and says in ln for ln in lines), lines


@pytest.mark.parametrize("body", [PERIODIC, VIA, TABLE], ids=["periodic", "via", "table"])
def test_the_ideal_mechanism_follows_each_shape(body: str, tmp_path) -> None:
    """IK of the scenario's samples -> quintic drives -> forward dynamics: z and the
    normal follow the prescribed functions to 1e-9 (the x, y and twist are parasitic)."""
    from clearance.analysis.ik import drives_from_ik, inverse_kinematics

    s = _scenario(body, tmp_path)
    ideal, _, info = build_mechanisms(s)
    tr = info.platform_trajectory()
    ik = inverse_kinematics(
        ideal,
        tr,
        platform_marker=info.platform_marker,
        actuators=info.actuators,
        times=s.trajectory.ik_times(),
    )
    ideal, _, _ = build_mechanisms(s, drives=drives_from_ik(ik))
    T = s.trajectory.duration
    r = cl.simulate(ideal, T, dt_out=T / 40, rtol=1e-11, atol=1e-13)
    assert r.success, r.message
    z = r.position("platform")[:, 2]
    assert np.max(np.abs(z - tr.z.evaluate(r.t)[:, 0])) < 1e-9
    n = r.rotation("platform")[:, :, 2]
    ref = np.array([tr.normal(t) for t in r.t])
    assert np.max(np.abs(n - ref)) < 1e-9
