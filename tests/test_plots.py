"""Figures from saved results: files, axis limits, the angular displacement, atomic saves."""

from __future__ import annotations

import os

import numpy as np
import pytest
from matplotlib.figure import Figure

import clearance
from clearance.io.dataset import load_results, result_to_dataset, save_results
from clearance.mechanisms.ups_upu import ups_upu_ideal
from clearance.plot import (
    platform_motion,
    plot_all,
    plot_ball_trajectory,
    plot_platform,
    save_figure,
)


@pytest.fixture(scope="module")
def loaded(tmp_path_factory):
    """Both runs saved to NetCDF and read back: the figures see only the file."""
    m = ups_upu_ideal()
    law = clearance.Clearance(
        ball_radius=0.015,
        radial_clearance=0.3e-3,
        normal=clearance.Flores(),
        friction=clearance.LuGre(),
    )
    runs = {
        "ideal": clearance.simulate(m, 0.03, dt_out=2e-4),
        "clearance": clearance.simulate(m.with_clearance("S_1", law), 0.03, dt_out=2e-4),
    }
    path = tmp_path_factory.mktemp("res") / "results.nc"
    save_results(path, {k: result_to_dataset(r) for k, r in runs.items()})
    return load_results(path)


def test_plot_all_writes_every_figure(loaded, tmp_path, monkeypatch):
    def no_simulation(*a, **k):
        raise AssertionError("plots must not simulate")

    monkeypatch.setattr(clearance, "simulate", no_simulation)
    paths = plot_all(loaded, tmp_path / "fig")
    stems = [
        "platform_displacement",
        "platform_velocity",
        "platform_acceleration",
        "contact_force",
        "ball_trajectory_S_1",
        "actuator_forces",
    ]
    assert [p.name for p in paths] == [f"{s}.{x}" for s in stems for x in ("png", "pdf")]
    for p in paths:
        data = p.read_bytes()
        assert len(data) > 5000, p
        assert data.startswith(b"\x89PNG" if p.suffix == ".png" else b"%PDF"), p
    assert sorted(os.listdir(tmp_path / "fig")) == sorted(p.name for p in paths)  # no temp


def test_ideal_only_skips_clearance_figures(loaded, tmp_path):
    paths = plot_all({"ideal": loaded["ideal"]}, tmp_path, formats=("png",))
    assert [p.stem for p in paths] == [
        "platform_displacement",
        "platform_velocity",
        "platform_acceleration",
        "actuator_forces",
    ]


def test_ball_trajectory_limits_include_clearance_circle(loaded):
    ds = loaded["clearance"]
    c_mm = 1e3 * float(ds["radial_clearance"].sel(clearance="S_1"))
    e = 1e3 * ds["eccentricity"].sel(clearance="S_1").values
    assert np.linalg.norm(e, axis=1).max() > 0.9 * c_mm  # the ball reached the wall
    fig = plot_ball_trajectory(loaded, "S_1")
    axes = fig.get_axes()
    assert len(axes) == 4
    for ax in axes:
        lims = [ax.get_xlim(), ax.get_ylim()] + ([ax.get_zlim()] if hasattr(ax, "get_zlim") else [])
        for lo, hi in lims:
            assert lo <= -c_mm and hi >= c_mm
    circles = [p for ax in axes for p in ax.patches if hasattr(p, "radius")]
    assert len(circles) == 3 and all(np.isclose(p.radius, c_mm) for p in circles)
    with pytest.raises(KeyError, match="S_9"):
        plot_ball_trajectory(loaded, "S_9")


def test_angular_displacement_is_the_integral_of_omega(loaded):
    ds = loaded["ideal"]
    mo = platform_motion(ds, ds)
    dr, th = mo["displacement"]
    v, w = mo["velocity"]
    assert np.abs(dr[0]).max() == 0.0 and np.abs(th[0]).max() == 0.0
    t = ds["time"].values
    for x, xdot in ((dr, v), (th, w)):  # small angles: d(theta)/dt ~ omega (world)
        d = np.gradient(x, t, axis=0)[1:-1]
        scale = np.abs(xdot).max()
        assert scale > 0
        assert np.abs(d - xdot[1:-1]).max() < 0.02 * scale


def test_platform_figure_overlays_runs(loaded):
    fig = plot_platform(loaded, "velocity")
    axs = fig.get_axes()
    assert len(axs) == 6
    assert all(len(ax.get_lines()) == 2 for ax in axs)
    assert axs[0].get_ylabel().endswith("[m/s]") and axs[3].get_ylabel().endswith("[rad/s]")
    with pytest.raises(KeyError, match="nobody"):
        plot_platform(loaded, "velocity", platform="nobody")


def test_save_figure_is_atomic(tmp_path, monkeypatch):
    fig = Figure()
    fig.add_subplot().plot([0, 1], [0, 1])
    (old,) = save_figure(fig, tmp_path, "f", ("png",))
    before = old.read_bytes()

    def broken(self, *a, **k):
        raise OSError("simulated")

    monkeypatch.setattr(Figure, "savefig", broken)
    with pytest.raises(OSError, match="simulated"):
        save_figure(fig, tmp_path, "f", ("png",))
    assert old.read_bytes() == before
    assert os.listdir(tmp_path) == ["f.png"]


def test_journal_and_slider_figures(tmp_path):
    """Revolute and prismatic clearance joints get their own figures from the saved file:
    the journal centre inside the clearance circle of its bearing, the slider offset within
    the clearance band of its guide (plot_all picks them by the joint's kind)."""
    from clearance.plot import plot_journal_trajectory, plot_slider_offset

    law = clearance.LankaraniNikravesh(stiffness=1e10, restitution=0.7)
    T = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # h = x, f = y, g = z
    m = clearance.Mechanism("two joints", gravity=(0.0, -9.81, 0.0))
    m.add(
        clearance.Body(
            "rod",
            0.6,
            (0.008, 0.0005, 0.008),
            position=(0, -0.2, 0),
            velocity=(0.6, 0, 0),
            angular_velocity=(0, 0, 3.0),
        ),
        clearance.Body(
            "slider", 0.4, (2e-4, 3e-4, 3e-4), position=(0, -0.5, 0), velocity=(0.5, 0, 0)
        ),
        clearance.Marker("pivot_g", "ground"),
        clearance.Marker("pivot_r", "rod", (0, 0.2, 0)),
        clearance.Marker("guide", "ground", (0, -0.5, 0), T),
        clearance.Marker("slide", "slider", (0, 0, 0), T),
        clearance.Revolute(
            "R",
            "pivot_g",
            "pivot_r",
            clearance=clearance.RevoluteClearance(
                0.01, radial_clearance=2e-4, model="spatial", length=0.02, normal=law
            ),
        ),
        clearance.Prismatic(
            "P",
            "guide",
            "slide",
            clearance=clearance.PrismaticClearance(
                width=0.02, length=0.04, clearance=2e-4, normal=law
            ),
        ),
    )
    r = clearance.simulate(m, 0.05, dt_out=2e-4)
    assert r.success, r.message
    path = tmp_path / "kinds.nc"
    save_results(path, {"clearance": r})
    ds = dict(load_results(path))
    assert list(ds["clearance"]["clearance_kind"].values) == ["revolute", "prismatic"]
    fig = plot_journal_trajectory(ds, "R")
    circle = [p for p in fig.axes[0].patches][0]
    assert circle.get_radius() == pytest.approx(0.2)  # c in mm
    fig2 = plot_slider_offset(ds, "P")
    assert len(fig2.axes) == 1  # planar: the width direction only
    for f, stem in ((fig, "j"), (fig2, "s")):
        (p,) = save_figure(f, tmp_path, stem, ("png",))
        assert p.stat().st_size > 5000
