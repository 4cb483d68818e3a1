"""The compiled loops hand control back every ~0.1 s (integrate/state.py, item 4): a run in
slices is the same run to the last bit; Ctrl-C, a stop request and max_wall_time stop it
with what it computed; progress reports the simulated time while it integrates."""

from __future__ import annotations

import io
import math
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from models import rod_on_clearance_joint

import clearance as cl
import clearance.integrate.simulate as sim
from clearance.kinds import Status
from clearance.model.contact_laws import Flores, LuGre


@pytest.fixture(scope="module")
def comp():
    """Impacts, friction (LuGre bristle states) and located events within 0.1 s."""
    return rod_on_clearance_joint(Flores(restitution=0.9), LuGre())


def arrays(r):
    """Every array of a result that the loop's state determines."""
    out = [r.t, r.q, r.v, r.a, r.lam, r.contact, r.contact_state, r.events, r.bristle]
    out += [r.energy[k] for k in sorted(r.energy)]
    return out


def same(r1, r2, n=None):
    """r1's arrays equal r2's (its first n samples) bit for bit."""
    a1, a2 = arrays(r1), arrays(r2)
    for x, y in zip(a1, a2, strict=True):
        if n is not None and x.ndim and x.shape[0] == r1.t.size and y.shape[0] == r2.t.size:
            y = y[:n]
        if x is r1.events:
            y = y[: x.shape[0]]
        np.testing.assert_array_equal(x, y)


KW = {
    "dopri5": dict(rtol=1e-7, atol=1e-10),
    "tsit5": dict(rtol=1e-7, atol=1e-10),
    "dop853": dict(rtol=1e-7, atol=1e-10),
    "vern7": dict(rtol=1e-7, atol=1e-10),
    "rk4": dict(step=2e-6),
}


@pytest.mark.parametrize("method", ["dopri5", "tsit5", "dop853", "vern7", "rk4"])
def test_a_run_in_one_step_slices_is_the_same_run(comp, method, monkeypatch):
    """Slices of one step each (the budget's floor) against one call for the whole run:
    every array identical, events and step statistics included."""
    kw = dict(dt_out=1e-3, method=method, **KW[method])
    monkeypatch.setattr(sim, "SLICE_SECONDS", 0.0)  # the whole run in one call
    whole = cl.simulate(comp, 0.05, **kw)
    calls = []
    monkeypatch.setattr(sim, "SLICE_SECONDS", 1e-12)  # one step per call
    sliced = cl.simulate(comp, 0.05, progress=calls.append, **kw)
    assert whole.success and sliced.success
    assert len(whole.impacts("S")) >= 1  # the slices cut through impacts
    steps = whole.stats["naccept"] + whole.stats["nreject"]
    assert len(calls) >= steps - 64  # one step per call after the first slice's 64
    same(sliced, whole)
    for k in ("nfev", "naccept", "nreject", "nevents", "hmin", "hmax", "hlast"):
        assert sliced.stats[k] == whole.stats[k], k


def test_progress_reports_increasing_simulated_time(comp, monkeypatch):
    monkeypatch.setattr(sim, "SLICE_SECONDS", 1e-4)
    seen = []
    r = cl.simulate(comp, 0.05, dt_out=1e-3, progress=seen.append)
    assert r.success and len(seen) > 10
    assert all(0.0 <= t <= 0.05 for t in seen)
    assert np.all(np.diff(seen) >= 0.0) and seen[-1] > 0.02


def test_a_stop_request_keeps_an_exact_prefix_of_the_run(comp, monkeypatch):
    """Stopped by its `stop` event, a run keeps the samples computed so far, and they are
    the full run's first samples, bit for bit."""
    monkeypatch.setattr(sim, "SLICE_SECONDS", 1e-4)
    full = cl.simulate(comp, 0.05, dt_out=1e-3)
    stop = threading.Event()

    def watch(t):
        if t > 0.02:
            stop.set()

    r = cl.simulate(comp, 0.05, dt_out=1e-3, progress=watch, stop=stop)
    assert r.status == Status.INTERRUPTED and not r.success
    assert "stop requested" in r.message and "samples kept" in r.message
    n = r.t.size
    assert 20 <= n < full.t.size
    same(r, full, n)


def test_ctrl_c_raises_interrupted_with_the_partial_result(comp, monkeypatch):
    """A KeyboardInterrupt between two slices (where Python delivers Ctrl-C) stops the run
    and raises `clearance.Interrupted`, a KeyboardInterrupt carrying the partial result."""
    monkeypatch.setattr(sim, "SLICE_SECONDS", 1e-4)
    full = cl.simulate(comp, 0.05, dt_out=1e-3)

    def ctrl_c(t):
        if t > 0.02:
            raise KeyboardInterrupt

    with pytest.raises(cl.Interrupted) as e:
        cl.simulate(comp, 0.05, dt_out=1e-3, progress=ctrl_c)
    assert isinstance(e.value, KeyboardInterrupt)
    import pickle  # (a study's worker sends exceptions back pickled)

    assert pickle.loads(pickle.dumps(e.value)).result.t.size == e.value.result.t.size
    r = e.value.result
    assert "status: STOPPED: interrupted (Ctrl-C)" in r.summary()
    assert r.status == Status.INTERRUPTED and "Ctrl-C" in r.message
    assert 20 <= r.t.size < full.t.size
    same(r, full, r.t.size)


def test_max_wall_time_stops_a_long_run(comp):
    """A run of ~10 million steps stops at its wall-time limit with what it computed."""
    t0 = time.perf_counter()
    r = cl.simulate(comp, 10.0, dt_out=1e-3, max_step=1e-6, max_wall_time=0.3)
    wall = time.perf_counter() - t0
    assert r.status == Status.WALL_TIME and "max_wall_time = 0.3 s" in r.message
    assert 0 < r.t.size < 10_001 and r.t[-1] > 0
    assert 0.3 <= r.stats["wall_time"] < 0.3 + 1.0  # a slice is ~0.1 s
    assert wall < 5.0  # post-processing the partial result included


@pytest.mark.parametrize(
    "kw",
    [
        dict(max_wall_time=0.0),
        dict(max_wall_time=-1.0),
        dict(max_wall_time=math.nan),
        dict(max_wall_time="10"),
        dict(progress=3),
        dict(stop=True),
    ],
)
def test_run_control_arguments_are_validated(comp, kw):
    name = next(iter(kw))
    with pytest.raises(cl.ModelError, match=name):
        cl.simulate(comp, 0.01, **kw)


# --------------------------------------------------------------------------- command line


def slow_scenario(tmp_path: Path, extra: str = "") -> Path:
    from clearance.scenario import default_scenario_path

    text = default_scenario_path().read_text(encoding="utf-8")
    text = re.sub(r"^rtol\s*=.*$", "rtol = 1e-6\nmax_step = 1e-6" + extra, text, flags=re.M)
    p = tmp_path / "slow.toml"
    p.write_text(text, encoding="utf-8")
    return p


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_ctrl_c_stops_clearance_run_within_a_second_and_writes_the_partial_result(tmp_path, sig):
    """`clearance run` interrupted mid-integration (SIGINT, as Ctrl-C sends it; SIGTERM, as
    a batch system's time limit does): both runs stop within a second, the partial results
    are written, exit code 130."""
    import xarray as xr

    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "clearance.cli.main", "run", str(slow_scenario(tmp_path))]
    p = subprocess.Popen(
        [*cmd, "--out", str(out), "--no-figures"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        bufsize=1,
        # a suite started in the background of a non-interactive shell has SIGINT (and
        # SIGQUIT) ignored, as POSIX has it for asynchronous commands; the child would
        # inherit that, and Python then installs no Ctrl-C handler (it happened here)
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    lines = []
    try:
        for line in p.stdout:  # (a cold kernel cache compiles first: no time limit here)
            lines.append(line)
            if line.startswith("[4/5]"):
                break
        time.sleep(1.0)  # well inside the integration (minutes of it)
        sent = time.perf_counter()
        p.send_signal(sig)
        stopped = None
        for line in p.stdout:
            lines.append(line)
            if stopped is None and "interrupted (Ctrl-C)" in line:
                stopped = time.perf_counter() - sent  # both runs stopped, post-processed
        rc = p.wait(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
    text = "".join(lines)
    assert rc == 130, text
    assert stopped is not None and stopped < 1.0, text
    assert "ideal: interrupted (stop requested)" in text, text
    assert "STOPPED: interrupted" in text and "the results up to then are written" in text
    nc = out / "ups_upu.nc"
    assert nc.is_file(), text
    with xr.open_dataset(nc, group="clearance") as d:
        assert d.attrs["status"] == int(Status.INTERRUPTED)
        t = d["time"].values
        assert 0.0 < t[-1] < 0.5 and t.size > 10


def test_max_wall_time_in_a_scenario_stops_both_runs_and_writes(tmp_path):
    from clearance.pipeline import run_scenario

    path = slow_scenario(tmp_path, "\nmax_wall_time = 0.5")
    msgs, seen = [], []
    o = run_scenario(
        path,
        out_dir=tmp_path / "o",
        figures=False,
        log=msgs.append,
        progress=lambda run, t, t_end: seen.append((run, t, t_end)),
    )
    for r in (o.ideal, o.clearance):
        assert r.status == Status.WALL_TIME and 0 < r.t[-1] < 2.0
    assert {run for run, _, _ in seen} == {"ideal", "clearance"}
    assert all(t_end == 2.0 for _, _, t_end in seen)
    assert [f.name for f in o.files] == ["ups_upu.nc", "report.html"]
    assert o.files[1].read_text().count('class="bad">stopped</span>') == 2  # says why
    from clearance.pipeline import format_summary

    assert "clearance: STOPPED: the wall-time limit max_wall_time = 0.5 s" in format_summary(
        o.summary
    )


def test_live_progress_redraws_on_a_terminal_and_prints_lines_in_logs():
    from clearance.cli.main import LiveProgress

    class Tty(io.StringIO):
        def isatty(self):
            return True

    tty = Tty()
    bar = LiveProgress(tty)
    bar.every = 0.0
    bar.update("ideal", 0.5, 2.0)
    bar.update("clearance", 1.0, 2.0)
    bar.clear()
    s = tty.getvalue()
    assert s.count("\r") >= 3 and "\n" not in s
    assert "ideal  25 %, clearance  50 %" in s  # the bar follows the slower run
    assert "[" + "#" * 7 + "." * 23 + "]" in s
    log = io.StringIO()
    lines = LiveProgress(log, every=0.0)
    lines.update("clearance", 0.1, 0.4)
    lines.update("clearance", 0.2, 0.4)
    out = log.getvalue().splitlines()
    assert len(out) == 2 and "clearance  50 %" in out[-1] and "\r" not in log.getvalue()


def test_ctrl_c_just_as_the_loop_returns_keeps_what_it_returned(comp, monkeypatch):
    """Ctrl-C delivered right after the loop's last call returned (before Python stored
    what it returned): the loop also kept it in its control array, so the run is reported
    as it ended (complete here), not rebuilt from the last pause."""
    full = cl.simulate(comp, 0.05, dt_out=1e-3)
    real = sim.method_loop("dopri5")

    def loop(*args):
        res = real(*args)
        if res[0] != Status.PAUSED:
            raise KeyboardInterrupt  # lands where `res` would have been stored
        return res

    monkeypatch.setattr(sim, "method_loop", lambda name: loop)
    monkeypatch.setattr(sim, "SLICE_SECONDS", 1e-4)
    with pytest.raises(cl.Interrupted) as e:
        cl.simulate(comp, 0.05, dt_out=1e-3)
    r = e.value.result
    assert r.status == Status.SUCCESS and r.t.size == full.t.size
    same(r, full)
