"""The 3-D viewer (issue 15): frames in the result file, the scene read from it, and the
self-contained HTML page tested in headless Chromium (tests/browser.py): it renders, its
bodies stand where the file says, the slider moves them, and no JavaScript error occurs."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from browser import chrome, project, screenshot, severe_logs, wait_for
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from clearance.cli.main import app
from clearance.io.frames import EVENT_BUDGET, contact_runs, frame_samples
from clearance.pipeline import run_scenario
from clearance.scenario import default_scenario_path, load_scenario, with_overrides
from clearance.view import SceneError, load_scene
from clearance.view.html import write_viewer
from clearance.view.shapes import nice_magnification


@pytest.fixture(scope="module")
def default_run(tmp_path_factory):
    """The default 4UPS-UPU scenario, as `clearance run` writes it (no figures)."""
    out = tmp_path_factory.mktemp("view")
    s = with_overrides(load_scenario(default_scenario_path("ups_upu")), {"output.figures": False})
    run_scenario(s, out_dir=out, log=None, figures=False)
    return out / "ups_upu.nc"


@pytest.fixture(scope="module")
def page(default_run):
    return write_viewer(default_run, default_run.with_suffix(".html"))


def _rot(q) -> np.ndarray:
    """Rotation matrix of Euler parameters (e0 scalar), written here for the checks."""
    e0, e1, e2, e3 = (float(x) for x in np.asarray(q) / np.linalg.norm(q))
    return np.array(
        [
            [1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
            [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
            [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)],
        ]
    )


def _open(path, group):
    return xr.open_dataset(path, group=group, engine="netcdf4")


# ---- frames ---------------------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(2, 3000),
    max_frames=st.integers(1, 400),
    runs=st.lists(st.tuples(st.integers(0, 2999), st.integers(1, 40)), max_size=12),
)
def test_frames_keep_every_contact_interval_and_its_peak(n, max_frames, runs):
    """Whatever the decimation, each run of contact samples has a frame at its largest
    force, the first and last samples are frames, and the uniform part has at most
    max_frames + 1 samples."""
    t = np.linspace(0.0, 1.0, n)
    flag = np.zeros((n, 1), dtype=np.int8)
    rng = np.random.default_rng(n)
    force = rng.random((n, 1))
    for a, w in runs:
        if a < n:
            flag[a : min(a + w, n), 0] = 1
    k = frame_samples(t, contact_flag=flag, contact_force=force, max_frames=max_frames)
    assert k[0] == 0 and k[-1] == n - 1 and np.all(np.diff(k) > 0)
    stride = max(1, -(-(n - 1) // max_frames))
    assert set(range(0, n, stride)) <= set(k.tolist())  # the uniform part
    assert k.size <= (1 + EVENT_BUDGET) * max_frames + 2  # bounded, however many contacts
    peaks = sorted(
        (
            (
                force[a + int(np.argmax(force[a : b + 1, 0])), 0],
                a + int(np.argmax(force[a : b + 1, 0])),
            )
            for a, b in contact_runs(flag[:, 0])
        ),
        reverse=True,
    )
    kept = peaks if stride == 1 else peaks[: EVENT_BUDGET * max_frames]  # the largest peaks
    assert {m for _, m in kept} <= set(k.tolist())


def test_frames_are_bounded_with_many_events():
    """100 000 impacts in 2 million samples: at most (1 + EVENT_BUDGET) x max_frames + 1
    frames, events outside the samples' span ignored."""
    t = np.linspace(0.0, 10.0, 2_000_001)
    ev = np.sort(np.random.default_rng(1).uniform(-1.0, 11.0, 100_000))
    k = frame_samples(t, event_times=ev, max_frames=2000)
    assert 2001 < k.size <= (1 + EVENT_BUDGET) * 2000 + 1
    few = frame_samples(t, event_times=np.array([-5.0, 20.0]), max_frames=2000)
    assert few.size == 2001  # only the uniform frames


def test_frames_refine_around_events():
    t = np.linspace(0.0, 1.0, 10001)
    k = frame_samples(t, event_times=np.array([0.50005]), max_frames=100, window=3)
    near = k[(t[k] > 0.495) & (t[k] < 0.505)]
    assert np.allclose(np.diff(t[near]), 1e-4)  # the output resolution near the event
    assert np.allclose(t[near[[0, -1]]], [0.4998, 0.5004])  # 3 samples either side of 0.5001


def test_contact_runs():
    assert contact_runs(np.array([0, 1, 1, 0, 1, 0, 0, 1])) == [(1, 2), (4, 4), (7, 7)]
    assert contact_runs(np.zeros(5)) == []


def test_the_default_file_keeps_every_body_at_frames_and_every_impact(default_run):
    """The frames group has every body; every contact interval of the full-rate contact
    flag has a frame in contact; the platform's frame poses equal its full-rate ones."""
    with _open(default_run, "clearance") as ds:
        names = [str(b) for b in ds.frame_body.values]
        assert len(names) == 11 and "tele_3" in names
        k = ds.frame_sample.values
        assert np.array_equal(ds.time.values[k], ds.frame_time.values)
        flag = ds.contact_flag.values
        frames_in_contact = flag[k]
        for j in range(flag.shape[1]):
            for a, b in contact_runs(flag[:, j]):
                assert np.any((k >= a) & (k <= b)), f"contact {a}..{b} has no frame"
        assert frames_in_contact.any()
        p = ds.frame_position.values[:, names.index("platform")]
        assert np.max(np.abs(p - ds.position.values[k, 0])) < 1e-6  # float32 of the same
        geo = json.loads(ds.attrs["geometry"])
        assert {c["name"] for c in geo["clearances"]} == {"S_1", "S_3"}
        assert ds.sizes["frame"] < 4000


# ---- scene ----------------------------------------------------------------------------


def test_scene_of_the_default_run(default_run):
    sc = load_scene(default_run)
    assert [r.name for r in sc.runs] == ["ideal", "clearance"]
    assert sc.magnification == 10.0  # 0.3 mm in a 15.3 mm socket: 0.3 * 15.3 / 0.3 = 15.3
    assert sc.shapes["platform"][0]["type"] == "mesh"
    assert {p["type"] for b in sc.bodies if b != "platform" for p in sc.shapes[b]} == {"rod"}
    # the rod of a leg: from its joint through its mass centre, the leg's 0.4 m
    a, b = (np.array(sc.shapes["tele_1"][0][k]) for k in "ab")
    assert np.linalg.norm(a - b) == pytest.approx(0.4)
    # the force arrow in the socket frame is the world force rotated back
    with _open(default_run, "clearance") as ds:
        k = ds.frame_sample.values
        c = sc.clearances[0]
        j = [str(x) for x in ds.clearance.values].index(c.info["name"])
        m = int(np.argmax(c.fn))
        fw = ds.normal_force.values[k[m], j] + ds.friction_force.values[k[m], j]
        q = ds.frame_euler_parameters.values[m, list(ds.frame_body.values).index("platform")]
        T = np.array(
            json.loads(ds.attrs["geometry"])["markers"][c.info["outer_marker"]]["orientation"]
        )
        assert np.allclose(_rot(q) @ T @ c.force[m], fw, rtol=1e-5, atol=1e-6 * abs(fw).max())
        assert np.array_equal(c.e, ds.eccentricity.values[k, j])


def test_nice_magnification():
    assert nice_magnification(0.0153, 0.0003) == 10.0
    assert nice_magnification(0.01, 1e-5) == 200.0
    assert nice_magnification(0.01, 0.01) == 1.0


def test_bad_inputs_are_named(tmp_path, default_run):
    bad = tmp_path / "bad.nc"
    bad.write_text("not netcdf")
    with pytest.raises(SceneError, match="bad.nc: not a NetCDF"):
        load_scene(bad)
    with pytest.raises(SceneError, match="no such file"):
        load_scene(tmp_path / "none.nc")
    with pytest.raises(SceneError, match="no run 'x'"):
        load_scene(default_run, runs=["x"])
    r = CliRunner().invoke(app, ["view", str(bad)])
    assert r.exit_code == 2 and "bad.nc" in r.output and "Traceback" not in r.output
    r = CliRunner().invoke(app, ["view", str(default_run), "--magnification", "-1"])
    assert r.exit_code == 2 and "magnification" in r.output


def test_cli_view_writes_a_small_self_contained_page(default_run, tmp_path):
    out = tmp_path / "v.html"
    r = CliRunner().invoke(app, ["view", str(default_run), "-o", str(out)])
    assert r.exit_code == 0, r.output
    text = out.read_text()
    assert out.stat().st_size < 10e6
    assert "<script src" not in text and "<link" not in text  # nothing fetched
    assert "fetch(" not in text and "XMLHttpRequest" not in text
    assert "three.js 0.187.0 subset (MIT" in text  # the vendored library, credited


# ---- in the browser ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def browser():
    d = chrome()
    yield d
    d.quit()


@pytest.fixture(scope="module")
def loaded(browser, page):
    browser.get(page.as_uri())
    wait_for(browser, "window.viewer && window.viewer.ready && window.viewer.renders > 0")
    return browser


def _canvas(browser, img):
    r = browser.execute_script("return window.viewer.canvasRect()")
    x0, y0 = int(r["left"]), int(r["top"])
    return img[y0 : y0 + int(r["height"]), x0 : x0 + int(r["width"])], (x0, y0)


def test_page_renders_without_errors(loaded):
    img, _ = _canvas(loaded, screenshot(loaded))
    background = np.array([0xF4, 0xF6, 0xF8])
    drawn = np.any(np.abs(img.astype(int) - background) > 12, axis=2)
    assert drawn.mean() > 0.03, "the canvas is (almost) blank"
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 200  # shaded bodies, not one fill
    assert loaded.execute_script("return window.viewer.errors") == []
    assert severe_logs(loaded) == []


def test_poses_in_the_page_equal_the_file(loaded, default_run):
    """Read back from the scene graph (three.js world matrices), not from the page's data:
    every body of both runs at several frames, and the clearance balls."""
    v = loaded
    with _open(default_run, "clearance") as ds, _open(default_run, "ideal") as di:
        names = [str(b) for b in ds.frame_body.values]
        nf = ds.sizes["frame"]
        fn = np.abs(ds.contact_force.values[ds.frame_sample.values]).max(axis=1)
        ideal_t = di.frame_time.values
        for k in sorted({0, nf // 3, int(np.argmax(fn)), nf - 1}):
            assert v.execute_script(f"return window.viewer.setFrame({k})") == k
            assert v.execute_script("return window.viewer.time") == float(ds.frame_time.values[k])
            for b in names:
                p = v.execute_script(f"return window.viewer.pose('clearance', '{b}')")
                i = names.index(b)
                assert np.allclose(p["position"], ds.frame_position.values[k, i], atol=1e-7)
                e, e_file = np.array(p["euler"]), ds.frame_euler_parameters.values[k, i]
                assert min(np.abs(e - e_file).max(), np.abs(e + e_file).max()) < 1e-6
            m = np.flatnonzero(np.isclose(ideal_t, ds.frame_time.values[k], rtol=0, atol=1e-12))
            if m.size:  # a frame of the ideal run too: its poses without interpolation
                for b in ("platform", "tele_1"):
                    p = v.execute_script(f"return window.viewer.pose('ideal', '{b}')")
                    i = names.index(b)
                    assert np.allclose(p["position"], di.frame_position.values[m[0], i], atol=1e-7)
            mag = v.execute_script("return window.viewer.magnification")
            geo = json.loads(ds.attrs["geometry"])
            for j, c in enumerate(str(x) for x in ds.clearance.values):
                s = ds.frame_sample.values[k]
                ball = v.execute_script(f"return window.viewer.ball('{c}')")
                e = ds.eccentricity.values[s, j]
                assert np.allclose(ball, mag * e, atol=1e-9)  # spherical: all of e magnified
                arrow = v.execute_script(f"return window.viewer.arrow('{c}')")
                fn_j = abs(float(ds.contact_force.values[s, j]))
                assert arrow["visible"] == bool(ds.contact_flag.values[s, j] and fn_j > 0)
                if not arrow["visible"]:
                    continue
                # the force on the ball and the normal in the socket frame, from the file:
                # R = A(platform) T(socket marker)
                mk = geo["markers"][
                    [g for g in geo["clearances"] if g["name"] == c][0]["outer_marker"]
                ]
                q = ds.frame_euler_parameters.values[k, names.index(mk["body"])]
                R = _rot(q) @ np.array(mk["orientation"])
                f = R.T @ (ds.normal_force.values[s, j] + ds.friction_force.values[s, j])
                n = R.T @ ds.contact_normal.values[s, j]
                assert np.allclose(arrow["direction"], f / np.linalg.norm(f), atol=1e-5)
                r = v.execute_script(f"return window.viewer.clearance('{c}').socketRadius")
                assert np.allclose(arrow["head"], r * n, atol=1e-6 * r)  # on the socket wall
                assert float(np.dot(f, n)) < 0  # pushes the ball inward


def test_ideal_run_is_interpolated_onto_the_frames(loaded, default_run):
    """At clearance frames between the ideal run's frames, the drawn ideal platform equals
    the ideal run's full-rate platform at that sample (interpolation error < 1 um)."""
    v = loaded
    with _open(default_run, "clearance") as ds, _open(default_run, "ideal") as di:
        k_clr, t_ideal = ds.frame_time.values, di.frame_time.values
        between = [k for k in range(len(k_clr)) if not np.isclose(t_ideal, k_clr[k]).any()]
        assert len(between) > 100
        for k in between[:: len(between) // 5][:5]:
            v.execute_script(f"window.viewer.setFrame({k})")
            p = v.execute_script("return window.viewer.pose('ideal', 'platform')")
            s = ds.frame_sample.values[k]
            assert np.allclose(p["position"], di.position.values[s, 0], atol=1e-6)


def test_platform_is_drawn_where_the_file_says(loaded, default_run):
    """A camera set from the test; the platform's mass centre projected with a pinhole model
    written here: hiding the platform changes the pixels there, not those far from it."""
    v = loaded
    k = v.execute_script("return window.viewer.setFrame(0)")
    with _open(default_run, "clearance") as ds:
        c = ds.frame_position.values[k, list(ds.frame_body.values).index("platform")]
    cam, fov = c + np.array([0.25, -1.0, 0.9]), 40.0
    size = v.execute_script(
        "return window.viewer.setCamera(arguments[0], arguments[1], arguments[2])",
        cam.tolist(),
        c.tolist(),
        fov,
    )
    rect = v.execute_script("return window.viewer.canvasRect()")
    assert size["width"] == pytest.approx(rect["width"], abs=1)
    with_platform = screenshot(v)
    v.execute_script("window.viewer.setVisible('clearance', 'platform', false)")
    v.execute_script("window.viewer.setVisible('ideal', 'platform', false)")
    without = screenshot(v)
    v.execute_script("window.viewer.setVisible('clearance', 'platform', true)")
    v.execute_script("window.viewer.setVisible('ideal', 'platform', true)")
    x, y = project(c, cam, c, fov, rect["width"], rect["height"])
    px, py = int(rect["left"] + x), int(rect["top"] + y)
    patch = (slice(py - 3, py + 4), slice(px - 3, px + 4))
    diff = np.abs(with_platform.astype(int) - without.astype(int)).sum(axis=2)
    assert diff[patch].min() > 30, "the platform is not drawn at its projected centre"
    # 0.45 m beside the platform (nothing of the mechanism there): unchanged
    x2, y2 = project(c + np.array([0.0, 0.0, 0.45]), cam, c, fov, rect["width"], rect["height"])
    far = (
        slice(int(rect["top"] + y2) - 3, int(rect["top"] + y2) + 4),
        slice(int(rect["left"] + x2) - 3, int(rect["left"] + x2) + 4),
    )
    assert diff[far].max() == 0


def test_slider_moves_the_scene(loaded):
    """The slider driven from the keyboard, as a user would: the frame advances and the
    picture changes."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    v = loaded
    v.execute_script("window.viewer.setFrame(0)")
    v.execute_script("window.viewer.setCamera([1.2, -1.6, 1.4], [0, 0, 0.5], 40)")
    before = screenshot(v)
    slider = v.find_element(By.ID, "time")
    slider.send_keys(Keys.END)
    wait_for(v, "window.viewer.frame > 0")
    assert v.execute_script("return window.viewer.frame") == v.execute_script(
        "return window.viewer.frames - 1"
    )
    after = screenshot(v)
    assert np.abs(before.astype(int) - after.astype(int)).sum(axis=2).max() > 60
    assert v.execute_script("return window.viewer.errors") == []


def test_play_mode_and_controls(loaded, default_run):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    v = loaded
    v.execute_script("window.viewer.setFrame(0)")
    Select(v.find_element(By.ID, "speed")).select_by_value("0.1")  # 2 s of motion in 20 s
    v.find_element(By.ID, "play").click()
    wait_for(v, "window.viewer.frame > 20", timeout=20)
    assert v.execute_script("return window.viewer.playing") is True
    v.find_element(By.ID, "play").click()
    assert v.execute_script("return window.viewer.playing") is False
    k = v.execute_script("return window.viewer.frame")
    assert 20 < k < v.execute_script("return window.viewer.frames - 1")
    shots = {}
    for m in ("clearance", "side", "overlay", "ideal"):
        Select(v.find_element(By.ID, "mode")).select_by_value(m)
        assert v.execute_script("return window.viewer.mode") == m
        v.execute_script("window.viewer.setFrame(window.viewer.frame)")
        shots[m] = screenshot(v)
    assert np.abs(shots["side"].astype(int) - shots["clearance"].astype(int)).max() > 60
    assert np.abs(shots["ideal"].astype(int) - shots["clearance"].astype(int)).max() > 60
    Select(v.find_element(By.ID, "mode")).select_by_value("overlay")
    # "next impact" from the start: to the first frame after the first contact onset
    v.execute_script("window.viewer.setFrame(0)")
    v.find_element(By.ID, "impact").click()
    with _open(default_run, "clearance") as ds:
        onset = float(ds.event_time.values[ds.event_kind.values > 0].min())
    k = v.execute_script("return window.viewer.frame")
    assert v.execute_script(f"return window.viewer.frameTime({k - 1})") <= onset
    assert v.execute_script("return window.viewer.time") > onset
    assert v.execute_script("return window.viewer.errors") == []
    assert severe_logs(v) == []


# ---- videos -----------------------------------------------------------------------------


def _background_fraction(img: np.ndarray) -> float:
    return float(np.mean(np.all(img > 245, axis=2)))


def test_mp4_has_the_expected_frames_size_and_content(default_run, tmp_path):
    """fps 10 at real time over the 2 s run: 21 frames, 2.1 s; a decoded frame at a
    known time is the scene drawn at that time (to the codec's loss), not blank, and
    differs from the first."""
    import imageio_ffmpeg

    from clearance.view.video import _Drawing, render_video

    sc = load_scene(default_run)
    info = render_video(sc, tmp_path / "a.mp4", fps=10, speed=1.0, size=(640, 360))
    assert info.frames == 21 and info.duration == pytest.approx(2.1)
    assert imageio_ffmpeg.count_frames_and_secs(str(info.path)) == (21, 2.1)
    gen = imageio_ffmpeg.read_frames(str(info.path))
    meta = gen.send(None)
    assert meta["size"] == (640, 360) and meta["fps"] == 10.0
    frames = [np.frombuffer(f, np.uint8).reshape(360, 640, 3) for f in gen]
    assert len(frames) == 21
    j = 10  # t = 1.0 s
    assert info.times[j] == pytest.approx(1.0)
    k = int(np.searchsorted(sc.time, 1.0, side="right") - 1)
    assert info.scene_frames[j] == k
    expected = _Drawing(sc, (640, 360), 100.0, True).draw(k, 1.0).astype(float)
    err = np.abs(frames[j].astype(float) - expected)
    assert err.mean() < 4.0  # H.264 loss, a few grey levels
    for other in (0, 20):  # a frame at another time is farther from it
        assert np.abs(frames[other].astype(float) - expected).mean() > err.mean()
    assert _background_fraction(frames[j]) < 0.9  # the mechanism and the insets are drawn


def test_gif_and_the_cli_without_a_display(default_run, tmp_path):
    """`clearance animate` in a process with no DISPLAY: a GIF of the expected frames,
    size and frame time; a bad extension is refused by name."""
    import os
    import subprocess
    import sys

    from PIL import Image

    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.pop("MPLBACKEND", None)
    out = tmp_path / "a.gif"
    cmd = [
        sys.executable,
        "-m",
        "clearance.cli.main",
        "animate",
        str(default_run),
        "-o",
        str(out),
        "--fps",
        "5",
        "--speed",
        "1",
        "--size",
        "320x180",
    ]
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "11 frames" in r.stdout
    with Image.open(out) as im:
        assert im.n_frames == 11 and im.size == (320, 180)
        assert im.info["duration"] == 200
        im.seek(5)
        assert _background_fraction(np.asarray(im.convert("RGB"))) < 0.95
    bad = CliRunner().invoke(app, ["animate", str(default_run), "-o", str(tmp_path / "a.avi")])
    assert bad.exit_code == 2 and "a.avi" in bad.output and ".mp4" in bad.output
    bad = CliRunner().invoke(app, ["animate", str(default_run), "--size", "big"])
    assert bad.exit_code == 2 and "--size" in bad.output


# ---- [view] in scenario files -------------------------------------------------------------


def test_view_table_is_validated_kept_and_used(tmp_path):
    from clearance.scenario import ScenarioError, loads_scenario, scenario_to_toml

    base = scenario_to_toml(load_scenario(default_scenario_path("ups_upu")))
    good = base + "\n[view]\nmagnification = 20\nframes = 300\n[view.bodies.platform]\n"
    good += 'shape = "sphere"\ncolour = "#112233"\n'
    s = loads_scenario(good)
    assert s.view.magnification == 20 and s.view.frames == 300
    assert s.view.bodies == {"platform": {"shape": "sphere", "colour": "#112233"}}
    assert loads_scenario(scenario_to_toml(s)).view == s.view  # round trip
    bad = base + "\n[view]\nmagnification = -1\nfoo = 1\n[view.bodies.platform]\n"
    bad += 'shape = "cube"\ncolour = "red"\n'
    with pytest.raises(ScenarioError) as e:
        loads_scenario(bad)
    text = str(e.value)
    for field in ("view.magnification", "view.foo", "view.bodies.platform.shape", "colour"):
        assert field in text
    # kept in the file, read by the viewer: magnification, shapes, frames
    s = with_overrides(s, {"trajectory.duration": 0.1})
    run_scenario(s, out_dir=tmp_path, log=None, figures=False)
    sc = load_scene(tmp_path / "ups_upu.nc")
    assert sc.magnification == 20.0
    assert sc.shapes["platform"][0]["type"] == "sphere"
    assert sc.shapes["platform"][0]["colour"] == "#112233"
    assert load_scene(tmp_path / "ups_upu.nc", magnification=5).magnification == 5
    with _open(tmp_path / "ups_upu.nc", "ideal") as di:
        assert di.sizes["time"] == 1001  # 0.1 s at 0.1 ms: stride ceil(1000 / 300) = 4
        assert di.sizes["frame"] == len(range(0, 1001, 4))  # no contacts in the ideal run
    # a body the mechanism does not have: refused before the runs, named
    wrong = loads_scenario(base + '\n[view.bodies.platfrm]\nshape = "rod"\n')
    with pytest.raises(ScenarioError, match="view.bodies.platfrm"):
        run_scenario(wrong, out_dir=tmp_path / "w", log=None, figures=False)


# ---- other clearance kinds, names, fallbacks -----------------------------------------------


@pytest.fixture(scope="module")
def slider_crank(tmp_path_factory):
    """Flores' slider-crank (library): the cylindrical journal-bearing clearance 'wrist',
    plus a prismatic clearance on the slider's guide: 4 ms."""
    from clearance.scenario import library_path, scenario_from_dict, scenario_to_dict

    d = scenario_to_dict(load_scenario(library_path("slider_crank")))
    d["clearance"]["joints"]["slide"] = {
        "width": 0.02,
        "length": 0.04,
        "clearance": 2e-4,
        "guide": "i",
        # (the bearing's steel K: plausible, a warning for 0.22 c of penetration at 5000 rpm)
        "normal": {"law": "lankarani_nikravesh", "stiffness": 6.61e10, "restitution": 0.9},
    }
    d["trajectory"]["duration"] = 0.004
    d["scenario"]["name"] = "crank <!--<script>"  # (a name that could break a page)
    out = tmp_path_factory.mktemp("crank")
    run_scenario(scenario_from_dict(d, source="crank.toml"), out_dir=out, log=None, figures=False)
    return next(out.glob("*.nc"))


def _world(ds, names, k, mk, local):
    """World point of `local` (marker frame) of marker `mk` at frame k, from the file."""
    if mk["body"] == "ground":
        return np.array(mk["position"]) + np.array(mk["orientation"]) @ local
    p = ds.frame_position.values[k, names.index(mk["body"])]
    A = _rot(ds.frame_euler_parameters.values[k, names.index(mk["body"])])
    return p + A @ (np.array(mk["position"]) + np.array(mk["orientation"]) @ local)


def test_sliding_joints_magnify_only_the_clearance(slider_crank, browser):
    """Cylindrical and prismatic clearances: the travel along the axis is drawn true, the
    transverse eccentricity magnified; so the drawn slider stays on the slider body. The
    page survives a scenario name with '<!--<script>'."""
    page = write_viewer(slider_crank, slider_crank.with_suffix(".html"))
    browser.get(page.as_uri())
    wait_for(browser, "window.viewer && window.viewer.ready && window.viewer.renders > 0")
    v = browser
    with _open(slider_crank, "clearance") as ds:
        names = [str(b) for b in ds.frame_body.values]
        geo = json.loads(ds.attrs["geometry"])
        mag = v.execute_script("return window.viewer.magnification")
        kinds = {c["name"]: c for c in geo["clearances"]}
        assert {c["kind"] for c in kinds.values()} == {"cylindrical", "prismatic"}
        nf = ds.sizes["frame"]
        for k in (0, nf // 2, nf - 1):
            v.execute_script(f"window.viewer.setFrame({k})")
            s = ds.frame_sample.values[k]
            for j, c in enumerate(str(x) for x in ds.clearance.values):
                e = ds.eccentricity.values[s, j]
                ball = np.array(v.execute_script(f"return window.viewer.ball('{c}')"))
                assert np.allclose(ball, [mag * e[0], mag * e[1], e[2]], atol=1e-9)
                # in the world: the drawn inner part is within M c of the inner body's marker
                info = kinds[c]
                mk_o, mk_i = (
                    geo["markers"][info["outer_marker"]],
                    geo["markers"][info["inner_marker"]],
                )

                drawn = _world(ds, names, k, mk_o, ball)
                inner = _world(ds, names, k, mk_i, np.zeros(3))
                assert np.linalg.norm(drawn - inner) < 3 * mag * info["c"] + 1e-6
    assert v.execute_script("return window.viewer.errors") == []
    assert severe_logs(v) == []


def test_video_of_sliding_joints(slider_crank, tmp_path):
    """The video draws the journal's and the slider's transverse eccentricity (not the
    slide) in their insets: a GIF of the expected frames, none blank."""
    from PIL import Image

    from clearance.view.video import render_video

    info = render_video(slider_crank, tmp_path / "c.gif", fps=5, speed=0.001, size=(480, 270))
    assert info.frames == 21  # 4 ms at 1 ms of motion per video second, 5 fps
    with Image.open(info.path) as im:
        assert im.n_frames == 21 and im.size == (480, 270)
    with pytest.raises(SceneError, match="at most"):
        render_video(slider_crank, tmp_path / "d.gif", fps=25, speed=1e-9)


def test_files_without_frames_or_geometry(default_run, tmp_path):
    """Files without the geometry attribute are drawn from the scenario they hold (the same
    shapes); files with every body but no frames are drawn from those, with the frames
    chosen as the file writer would (contacts kept)."""
    import shutil

    import netCDF4

    from clearance.io.dataset import result_to_dataset, save_results

    ref = load_scene(default_run)
    nogeo = tmp_path / "nogeo.nc"
    shutil.copy(default_run, nogeo)
    with netCDF4.Dataset(nogeo, "a") as d:
        for g in d.groups.values():
            g.delncattr("geometry")
    sc = load_scene(nogeo)
    assert sc.shapes == ref.shapes and sc.geometry["clearances"] == ref.geometry["clearances"]

    s = with_overrides(
        load_scenario(default_scenario_path("ups_upu")), {"trajectory.duration": 0.1}
    )
    o = run_scenario(s, out_dir=tmp_path / "run", log=None, figures=False, defer_write=True)
    groups = ("bodies", "clearance", "actuators", "energy")  # no "frames"
    ds = {
        k: result_to_dataset(r, outputs=groups)
        for k, r in (("ideal", o.ideal), ("clearance", o.clearance))
    }
    f = save_results(tmp_path / "bodies.nc", ds)
    sc = load_scene(f)
    r = o.clearance
    k = frame_samples(
        r.t,
        event_times=r.events[:, 0],
        contact_flag=r.contact_state[:, :, 0],
        contact_force=_point_force(r),
    )
    assert np.array_equal(sc.time, r.t[k])
    nb = len(sc.bodies)
    q = r.q[k].reshape(k.size, nb, 7)
    assert np.allclose(sc.runs[-1].poses, q, atol=1e-6)


def _point_force(r):
    from clearance.io.dataset import _POINT_FORCE

    return _POINT_FORCE.take(r.contact_points)


def test_bodies_a_run_lacks_are_hidden(default_run, browser, tmp_path):
    """A body only the clearance run has (a universal clearance's cross) is not drawn as
    a ghost of the ideal run at the origin."""
    sc = load_scene(default_run)
    sc.runs[0].present = [0 if b == "tele_2" else 1 for b in sc.bodies]
    page = write_viewer(sc, tmp_path / "p.html")
    browser.get(page.as_uri())
    wait_for(browser, "window.viewer && window.viewer.ready")
    assert browser.execute_script("return window.viewer.visible('ideal', 'tele_2')") is False
    assert browser.execute_script("return window.viewer.visible('ideal', 'tele_1')") is True
    assert browser.execute_script("return window.viewer.visible('clearance', 'tele_2')") is True
