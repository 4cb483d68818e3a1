"""Scenario files of type "general": any mechanism, element by element (clearance.scenario.
general).

Oracles: the same mechanism written in Python compiles to the same arrays; the canonical
round trip; a run with the file's own drivers (no inverse kinematics); the inverse
kinematics of a general mechanism follows its prescribed coordinate (1e-9 m); every bad
element is refused at its file path with the element's own message.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import clearance as cl
from clearance.pipeline import run_scenario
from clearance.scenario import (
    ScenarioError,
    build_mechanisms,
    loads_scenario,
    scenario_to_toml,
    with_overrides,
)

R, L = 0.05, 0.12  # crank, coupler [m]


def python_slider_crank(theta0: float = 0.3) -> cl.Mechanism:
    """A slider-crank in the x-y plane: crank about z (a motor), coupler, slider on x."""
    c, s = math.cos(theta0), math.sin(theta0)
    B = np.array([R * c, R * s, 0.0])
    S = math.sqrt(L * L - (R * s) ** 2)
    C = np.array([R * c + S, 0.0, 0.0])
    phi = math.atan2(C[1] - B[1], C[0] - B[0])
    m = cl.Mechanism("slider-crank", gravity=(0.0, -9.81, 0.0))
    m.add(
        cl.Body(
            "crank",
            0.3,
            (2e-5, 1e-4, 1e-4),
            position=tuple(B / 2),
            orientation=(math.cos(theta0 / 2), 0.0, 0.0, math.sin(theta0 / 2)),
        ),
        cl.Body(
            "coupler",
            0.21,
            (2e-5, 2.5e-4, 2.5e-4),
            position=tuple((B + C) / 2),
            orientation=(math.cos(phi / 2), 0.0, 0.0, math.sin(phi / 2)),
        ),
        cl.Body("slider", 0.14, (1e-4, 1e-4, 1e-4), position=tuple(C)),
        cl.Marker("O", cl.GROUND),
        cl.Marker("crank_O", "crank", (-R / 2, 0.0, 0.0)),
        cl.Revolute("bearing", "O", "crank_O"),
        cl.Marker("crank_B", "crank", (R / 2, 0.0, 0.0)),
        cl.Marker("coupler_B", "coupler", (-L / 2, 0.0, 0.0)),
        cl.Revolute("pin", "crank_B", "coupler_B"),
        cl.Marker("coupler_C", "coupler", (L / 2, 0.0, 0.0)),
        cl.Marker.on_axis("slider_C", "slider", axis=(0.0, 0.0, 1.0)),
        cl.Spherical("wrist", "coupler_C", "slider_C"),
        cl.Marker.on_axis("rail", cl.GROUND, axis=(1.0, 0.0, 0.0)),
        cl.Marker.on_axis("slider_rail", "slider", axis=(1.0, 0.0, 0.0)),
        cl.Cylindrical("slide", "rail", "slider_rail"),
        cl.RevoluteDriver("motor", "bearing", cl.Polynomial((theta0, 2.0 * math.pi))),
    )
    return m


def general_text(theta0: float = 0.3, extra: str = "") -> str:
    c, s = math.cos(theta0), math.sin(theta0)
    B = np.array([R * c, R * s, 0.0])
    S = math.sqrt(L * L - (R * s) ** 2)
    C = np.array([R * c + S, 0.0, 0.0])
    phi = math.atan2(C[1] - B[1], C[0] - B[0])
    v = lambda a: "[" + ", ".join(repr(float(x)) for x in a) + "]"  # noqa: E731
    return f"""
format_version = 1
[scenario]
name = "slider_crank"
[mechanism]
type = "general"
name = "slider-crank"
gravity = [0.0, -9.81, 0.0]
platform = "slider"
[mechanism.bodies.crank]
mass = 0.3
inertia = [2e-5, 1e-4, 1e-4]
position = {v(B / 2)}
orientation = {v([math.cos(theta0 / 2), 0.0, 0.0, math.sin(theta0 / 2)])}
[mechanism.bodies.coupler]
mass = 0.21
inertia = [2e-5, 2.5e-4, 2.5e-4]
position = {v((B + C) / 2)}
orientation = {v([math.cos(phi / 2), 0.0, 0.0, math.sin(phi / 2)])}
[mechanism.bodies.slider]
mass = 0.14
inertia = [1e-4, 1e-4, 1e-4]
position = {v(C)}
[mechanism.markers.O]
body = "ground"
[mechanism.markers.crank_O]
body = "crank"
position = {v([-R / 2, 0, 0])}
[mechanism.markers.crank_B]
body = "crank"
position = {v([R / 2, 0, 0])}
[mechanism.markers.coupler_B]
body = "coupler"
position = {v([-L / 2, 0, 0])}
[mechanism.markers.coupler_C]
body = "coupler"
position = {v([L / 2, 0, 0])}
[mechanism.markers.slider_C]
body = "slider"
axis = [0.0, 0.0, 1.0]
[mechanism.markers.rail]
body = "ground"
axis = [1.0, 0.0, 0.0]
[mechanism.markers.slider_rail]
body = "slider"
axis = [1.0, 0.0, 0.0]
[mechanism.joints.bearing]
type = "revolute"
marker_i = "O"
marker_j = "crank_O"
[mechanism.joints.pin]
type = "revolute"
marker_i = "crank_B"
marker_j = "coupler_B"
[mechanism.joints.wrist]
type = "spherical"
marker_i = "coupler_C"
marker_j = "slider_C"
[mechanism.joints.slide]
type = "cylindrical"
marker_i = "rail"
marker_j = "slider_rail"
[mechanism.drivers.motor]
type = "revolute"
joint = "bearing"
function = {{ type = "polynomial", coefficients = [{theta0!r}, {2.0 * math.pi!r}] }}
[trajectory]
duration = 0.2
{extra}
"""


def test_file_and_python_give_the_same_model() -> None:
    s = loads_scenario(general_text())
    ideal, _, info = build_mechanisms(s)
    c1, c2 = cl.compile_mechanism(python_slider_crank()), cl.compile_mechanism(ideal)
    for k in c1.model._fields:
        a, b = getattr(c1.model, k), getattr(c2.model, k)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), k
    assert info.actuators == () and info.platform_body == "slider"
    assert loads_scenario(scenario_to_toml(s)) == s


def test_a_run_with_the_files_own_drivers(tmp_path) -> None:
    """No inverse kinematics: the motor turns at 2 pi rad/s; a journal clearance on the
    crank pin; the slider's x follows the closed form of the ideal run."""
    clr = """
[clearance.joints.pin]
journal_radius = 0.005
radial_clearance = 1e-4
"""
    s = loads_scenario(general_text() + clr)
    run = run_scenario(s, out_dir=tmp_path, log=None, figures=False, defer_write=True)
    assert run.ik is None and run.ideal.success and run.clearance.success
    th = 0.3 + 2.0 * math.pi * run.ideal.t
    x = R * np.cos(th) + np.sqrt(L * L - (R * np.sin(th)) ** 2)
    assert np.max(np.abs(run.ideal.position("slider")[:, 0] - x)) < 1e-6
    assert "pin" in run.clearance.clearance_names


def test_inverse_kinematics_of_a_general_mechanism() -> None:
    """trajectory.actuators = ["motor"]: the slider's x prescribed (rest to rest, 10 mm);
    the ideal mechanism driven by the IK's motor angle follows it to 1e-9 m."""
    from clearance.analysis.ik import drives_from_ik, inverse_kinematics

    extra = """orientation = "none"
positions = ["x"]
actuators = ["motor"]
[trajectory.amplitude]
x = -0.01
"""
    s = loads_scenario(general_text(extra=extra))
    ideal, _, info = build_mechanisms(s)
    assert info.actuators == ("motor",) and info.platform_marker == "slider"
    tr = info.platform_trajectory()
    ik = inverse_kinematics(
        ideal, tr, platform_marker="slider", actuators=info.actuators, times=s.trajectory.ik_times()
    )
    ideal, _, _ = build_mechanisms(s, drives=drives_from_ik(ik))
    r = cl.simulate(ideal, 0.2, dt_out=0.01, rtol=1e-11, atol=1e-13)
    assert r.success, r.message
    assert np.max(np.abs(r.position("slider")[:, 0] - tr.x.evaluate(r.t)[:, 0])) < 1e-9


def test_study_paths_of_a_general_mechanism() -> None:
    s = loads_scenario(general_text())
    s2 = with_overrides(
        s,
        {
            "mechanism.bodies.slider.mass": 0.2,
            "mechanism.drivers.motor.function.coefficients": [0.3, 1.0],
        },
    )
    m = s2.mechanism.params.mechanism
    assert m.bodies["slider"].mass == 0.2
    assert m.drivers["motor"].function.coefficients == (0.3, 1.0)
    with pytest.raises(ScenarioError, match="unknown key 'mas'.*did you mean 'mass'"):
        with_overrides(s, {"mechanism.bodies.slider.mas": 1.0})


@pytest.mark.parametrize(
    "old, new, field, says",
    [
        ("mass = 0.14", "mass = -0.14", "mechanism.bodies.slider.mass", "> 0"),
        (
            "inertia = [1e-4, 1e-4, 1e-4]",
            "inertia = [1e-4, 1e-4, 1e-2]",
            "slider.inertia",
            "triangle",
        ),
        ('marker_j = "coupler_B"', 'marker_j = "coupler_Q"', "joints.pin.marker_j", "coupler_Q"),
        (
            'type = "revolute"\nmarker_i = "O"',
            'type = "hinge"\nmarker_i = "O"',
            "joints.bearing.type",
            "revolute",
        ),
        ('body = "crank"', 'body = "cranks"', "markers.crank_O.body", "cranks"),
        ('joint = "bearing"', 'joint = "wrist"', "drivers.motor.joint", "Revolute or Cylindrical"),
        ('type = "polynomial"', 'type = "polynom"', "motor.function.type", "polynomial"),
        (
            "[mechanism.bodies.slider]\nmass = 0.14",
            "[mechanism.bodies.slider]\nmas = 0.14",
            "slider.mass",
            "missing",
        ),
        (
            'platform = "slider"',
            'platform = "slidr"',
            "mechanism.platform",
            "did you mean 'slider'",
        ),
        (
            "duration = 0.2",
            'duration = 0.2\nactuators = ["moter"]',
            "trajectory.actuators",
            "motor",
        ),
        (
            "duration = 0.2",
            "duration = 0.2\n[trajectory.amplitude]\nx = 0.01",
            "amplitude.x",
            "must not move",
        ),
    ],
)
def test_bad_general_files_are_refused(old: str, new: str, field: str, says: str) -> None:
    text = general_text()
    assert old in text
    with pytest.raises(ScenarioError) as e:
        loads_scenario(text.replace(old, new, 1), source="bad.toml")
    lines = e.value.lines()
    assert any(field in ln and says in ln and "bad.toml" in ln for ln in lines), lines


def test_library_slider_crank_is_the_benchmark_model(tmp_path) -> None:
    """The library's slider_crank.toml (type general) is tests/test_slider_crank_clearance.
    py's model of Flores' benchmark, bit for bit, ideal and with the clearance (which that
    file compares with an independent planar implementation); its run is plausible."""
    from test_slider_crank_clearance import P, slider_crank

    from clearance.scenario import library_path, load_scenario

    s = load_scenario(library_path("slider_crank"))
    ideal, clr, _ = build_mechanisms(s)
    for a, b in ((ideal, slider_crank(P, clearance=False)), (clr, slider_crank(P))):
        c1, c2 = cl.compile_mechanism(a), cl.compile_mechanism(b)
        for k in c1.model._fields:
            x, y = getattr(c1.model, k), getattr(c2.model, k)
            if isinstance(x, np.ndarray):
                assert x.shape == y.shape and np.array_equal(x, y, equal_nan=True), k
    run = run_scenario(s, out_dir=tmp_path, log=None, figures=False, defer_write=True)
    assert run.clearance.success and len(run.clearance.impacts("wrist")) > 3


def test_cli_check_and_new_of_library_files(tmp_path) -> None:
    """`clearance check` accepts a general file (no inverse kinematics: said so);
    `clearance new prs3` copies the scenario and the CSV table it reads, and the copy
    checks."""
    import subprocess
    import sys

    from clearance.scenario import library_path

    base = [sys.executable, "-m", "clearance.cli.main"]
    out = subprocess.run(
        [*base, "check", str(library_path("slider_crank"))], capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    assert "general" in out.stdout and "inverse kinematics: none" in out.stdout
    dest = tmp_path / "copy" / "prs3.toml"
    out = subprocess.run([*base, "new", "prs3", str(dest)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "copy" / "prs3_motion.csv").is_file()
    out = subprocess.run([*base, "check", str(dest)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
