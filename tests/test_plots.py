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
    paths = plot_all(loaded, tmp_path / "fig", formats=("png", "pdf"))
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
    axes = [ax for ax in fig.get_axes() if ax.get_label() != "<colorbar>"]
    assert len(axes) == 4 and len(fig.get_axes()) == 5  # and one time colour bar
    t = ds["time"].values
    for ax in axes[1:]:  # the path is coloured by time, start and end marked
        (lc,) = ax.collections
        colours = lc.get_array()
        assert colours.min() >= t[0] and colours.max() <= t[-1]
        assert np.all(np.diff(colours) > 0)
        pts = np.concatenate([seg[:-1] for seg in lc.get_segments()])
        assert pts.shape[0] == t.size - 1
        start, end = (ln.get_xydata()[0] for ln in ax.get_lines())
        assert np.allclose(start, pts[0]) and np.allclose(end, lc.get_segments()[-1][-1])
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


def test_platform_figure_overlays_runs_and_their_difference(loaded):
    """Rows: x, y, z overlaid, then clearance - ideal; the difference drawn is the
    difference of the data (independent recomputation from the file's channels)."""
    fig = plot_platform(loaded, "velocity")
    axs = _grid(fig)
    for ax in axs[:, 0].ravel():
        assert len(ax.get_lines()) == 2
    for ax in axs[:, 1].ravel():
        assert len(ax.get_lines()) == 1
    assert axs[0, 0].get_ylabel().endswith("[m/s]") and axs[3, 0].get_ylabel().endswith("[rad/s]")
    v = {k: loaded[k]["velocity"].sel(body="platform").values for k in loaded}
    np.testing.assert_allclose(
        axs[1, 1].get_lines()[0].get_ydata(), v["clearance"][:, 1] - v["ideal"][:, 1]
    )
    only = plot_platform({"ideal": loaded["ideal"]}, "velocity")
    assert len(only.get_axes()) == 6  # one run: no difference rows
    with pytest.raises(KeyError, match="nobody"):
        plot_platform(loaded, "velocity", platform="nobody")


def _grid(fig) -> np.ndarray:
    """Platform figure panels as [component (x, y, z, rot x, rot y, rot z), overlay/diff]."""
    return np.array(fig.get_axes(), dtype=object).reshape(6, 2)


def _texts(fig) -> str:
    out = [t.get_text() for ax in fig.get_axes() for t in ax.texts]
    return "\n".join(out + [fig._suptitle.get_text() if fig._suptitle else ""])


def test_noise_is_noted_not_plotted(loaded):
    """A run equal to the reference up to rounding: every difference panel says it is
    below numerical noise and draws nothing; a component that is zero to rounding in every
    run is not drawn either."""
    ideal = loaded["ideal"]
    twin = ideal.copy(deep=True)
    twin["velocity"] = twin["velocity"] * (1 + 1e-13)
    twin["velocity"].loc[{"axis": "x"}] = 1e-15 * np.sin(ideal["time"].values)[:, None]
    ideal2 = ideal.copy(deep=True)
    ideal2["velocity"].loc[{"axis": "x"}] = 0.0
    fig = plot_platform({"ideal": ideal2, "twin": twin}, "velocity")
    axs = _grid(fig)
    for ax in axs[:3, 1]:
        assert not ax.get_lines() and "below numerical noise" in ax.texts[0].get_text()
    assert not axs[0, 0].get_lines() and "numerical noise" in axs[0, 0].texts[0].get_text()
    assert len(axs[1, 0].get_lines()) == 2  # y: a real signal, drawn


def test_spikes_are_clipped_with_their_extent_noted(loaded):
    """An impact spike 1000x the signal: the overlay keeps the ideal curve readable (its
    range within the axes, the spike outside) and states the spike's extent; the
    difference panel shows the spike in full."""
    clr = loaded["ideal"].copy(deep=True)  # the ideal run plus one spike
    a = clr["acceleration"].values.copy()
    k = list(clr["body"].values).index("platform")
    ideal_z = loaded["ideal"]["acceleration"].sel(body="platform", axis="z").values
    spike = 1000 * np.abs(ideal_z).max()
    a[len(a) // 2, k, 2] = spike
    clr["acceleration"].values = a
    fig = plot_platform({"ideal": loaded["ideal"], "clearance": clr}, "acceleration")
    axs = _grid(fig)
    lo, hi = axs[2, 0].get_ylim()
    assert lo <= ideal_z.min() and hi >= ideal_z.max() and hi < spike / 10
    assert f"{spike:.3g}" in _texts(fig) and "clipped" in axs[2, 0].texts[0].get_text()
    assert axs[2, 1].get_ylim()[1] >= spike - np.abs(ideal_z).max()


def test_contact_force_marks_the_step_resolved_peak(loaded):
    from clearance.plot import plot_contact_force

    ds = loaded["clearance"]
    fig = plot_contact_force(loaded)
    (ax,) = fig.get_axes()
    (m,) = [ln for ln in ax.get_lines() if ln.get_gid() == "peak:clearance:S_1"]
    pk = float(ds["peak_contact_force"].sel(clearance="S_1"))
    tp = float(ds["peak_contact_force_time"].sel(clearance="S_1"))
    assert m.get_ydata()[0] == pk and m.get_xdata()[0] == tp
    assert pk >= ds["contact_force"].sel(clearance="S_1").values.max()
    assert f"{pk:.4g} N" in m.get_label() and ax.get_ylim()[1] >= pk


def test_a_run_that_stopped_early_says_so_on_every_figure(loaded, tmp_path):
    clr = loaded["clearance"].copy()
    clr.attrs = {**clr.attrs, "status": 3, "message": "step size too small"}
    data = {"ideal": loaded["ideal"], "clearance": clr}
    from clearance.plot import plot_actuator_forces, plot_contact_force

    for fig in (
        plot_platform(data, "displacement"),
        plot_contact_force(data),
        plot_ball_trajectory(data, "S_1"),
        plot_actuator_forces(data),
    ):
        title = fig._suptitle.get_text()
        assert "run 'clearance' STOPPED EARLY" in title and "step size too small" in title


def test_actuator_panels_are_named_by_leg_with_the_sign_convention(loaded):
    from clearance.plot import plot_actuator_forces

    fig = plot_actuator_forces(loaded)
    titles = [ax.get_title(loc="left") for ax in fig.get_axes()]
    assert "leg 1 (drive_1)" in titles and "leg 5 (drive_5)" in titles
    assert "extends a leg" in fig._suptitle.get_text()


def test_plot_refuses_a_collected_study_clearly(loaded, tmp_path):
    study = loaded["clearance"].expand_dims(case=["c0", "c1"])
    with pytest.raises(ValueError, match="collected study"):
        plot_all({"clearance": study}, tmp_path)


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


def test_parallel_rendering_writes_the_same_files(loaded, tmp_path):
    serial = plot_all(loaded, tmp_path / "one", jobs=1)
    forked = plot_all(loaded, tmp_path / "two", jobs=2)
    assert [p.name for p in serial] == [p.name for p in forked]
    for a, b in zip(serial, forked, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name
    assert sorted(os.listdir(tmp_path / "two")) == sorted(p.name for p in forked)


def test_figures_render_in_this_process_when_threads_run(loaded, tmp_path, monkeypatch):
    """Forking a process with other threads can deadlock a child: no fork then."""
    import threading

    import clearance.plot.figures as F

    assert F._jobs(2, 7) == 2 or threading.active_count() > 1
    stop = threading.Event()
    t = threading.Thread(target=stop.wait, daemon=True)
    t.start()
    try:
        assert F._jobs(2, 7) == 1
        monkeypatch.setattr(F, "_render_one", None)  # a fork would fail on it
        assert len(plot_all(loaded, tmp_path, jobs=2)) == 6
    finally:
        stop.set()
        t.join()


def test_drawing_processes_end_on_terminate_whatever_handler_the_parent_has(
    loaded, tmp_path, monkeypatch
):
    """`clearance run` turns SIGTERM into KeyboardInterrupt. A forked drawing process that
    inherits that handler can outlive Pool.terminate(), and the pool then waits for it
    forever (seen in the suite). The processes reset both signals: SIGTERM ends them
    wherever they are, Ctrl-C is the parent's."""
    import signal

    import clearance.plot.figures as F
    from clearance.cli.main import _terminate

    if F._jobs(2, 7) < 2:
        pytest.skip("no forked drawing here")

    def handlers(builders, out_dir, formats):  # (runs in the drawing process)
        return [(signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT))]

    monkeypatch.setattr(F, "_render", handlers)
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        seen = F.start_figures(loaded, tmp_path, jobs=2).result()
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert len(seen) == 6
    assert set(seen) == {(signal.SIG_DFL, signal.SIG_IGN)}
