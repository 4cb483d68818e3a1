"""Parameter studies (issue: `clearance sweep` on Dask): validation, case generation,
LocalCluster == serial, resumption, killed workers and failing cases, interrupt and restart,
collect. Runs are short (0.06 s simulated, output every 1 ms) so the whole file stays near
a minute on 2 cores once numba's on-disk cache is warm."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import dask
import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from clearance.cli.main import app
from clearance.io.dataset import load_results
from clearance.scenario import ScenarioError
from clearance.sweep import (
    CaseData,
    StudyError,
    collect_study,
    compute_metrics,
    load_study,
    loads_study,
    run_study,
)
from clearance.sweep.store import STALE_TMP
from clearance.sweep.study import example_study_path

SHORT = """\
format_version = 1

[study]
name = "{name}"
base = "ups_upu"
folder = "{folder}"
metrics = {metrics}

[set]
trajectory.duration = 0.06
solver.dt_out = 1e-3
{parameters}
"""
METRIC_NAMES = [
    "peak_contact_force",
    "peak_contact_force@S_1",
    "rms_contact_force",
    "impacts",
    "max_penetration",
    "deviation_position",
    "deviation_velocity",
    "deviation_acceleration",
    "deviation_angular_velocity",
    "energy_dissipated",
    "energy_residual",
    "success",
    "wall_time",
]
GRID = """
[[parameter]]
name = "radial_clearance"
path = ["clearance.joints.S_1.radial_clearance", "clearance.joints.S_3.radial_clearance"]
values = [1e-4, 3e-4, 5e-4]

[[parameter]]
name = "mu_c"
path = ["clearance.joints.S_1.friction.mu_c", "clearance.joints.S_3.friction.mu_c"]
values = [0.05, 0.15]
"""
NOT_TIMING = [m for m in METRIC_NAMES if m != "wall_time"]


def study_text(folder: Path, parameters: str = GRID, *, name: str = "t", metrics=None) -> str:
    return SHORT.format(
        name=name,
        folder=folder,
        metrics=json.dumps(metrics or METRIC_NAMES),
        parameters=parameters,
    )


def sidecars(folder: Path) -> dict[str, dict]:
    """Case id -> sidecar (an empty dict if the folder has no cases yet)."""
    return {p.stem: json.loads(p.read_text()) for p in sorted((folder / "cases").glob("*.json"))}


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The 3 x 2 study, run serially in this process."""
    folder = tmp_path_factory.mktemp("serial") / "study"
    study = loads_study(study_text(folder), source="grid.toml")
    report = run_study(study, scheduler="serial", progress=False)
    return study, report


@pytest.fixture(scope="module")
def client():
    """A LocalCluster of 2 single-threaded worker processes (what `clearance sweep` starts
    on a 2-core machine), allowing 2 worker deaths per task."""
    from distributed import Client, LocalCluster

    with dask.config.set({"distributed.scheduler.allowed-failures": 2}):
        cluster = LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        )
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


# --------------------------------------------------------------------------- validation

INVALID = {
    "unknown path": (
        '[[parameter]]\npath = "clearance.joints.S_1.radial_clearence"\nvalues = [1e-4]',
        "parameter[0].path",
        "radial_clearence",
    ),
    "unknown joint": (
        '[[parameter]]\npath = "clearance.joints.S1.radial_clearance"\nvalues = [1e-4]',
        "parameter[0].path",
        "did you mean 'S_1'",
    ),
    "negative clearance": (
        '[[parameter]]\npath = "clearance.joints.S_1.radial_clearance"\nvalues = [1e-4, -3e-4]',
        "clearance.joints.S_1.radial_clearance",
        "-0.0003",
    ),
    "range without num or step": (
        '[[parameter]]\npath = "solver.rtol"\nrange = { start = 1e-6, stop = 1e-4 }',
        "parameter[0].range",
        "exactly one of num",
    ),
    "range num 0": (
        '[[parameter]]\npath = "solver.rtol"\nrange = { start = 1e-6, stop = 1e-4, num = 0 }',
        "parameter[0].range.num",
        "integer >= 1",
    ),
    "zip lengths": (
        '[[parameter]]\npath = "solver.rtol"\nvalues = [1e-6, 1e-7]\nzip = "tol"\n'
        '[[parameter]]\npath = "solver.atol"\nvalues = [1e-9]\nzip = "tol"',
        "parameter[0].zip",
        "same number of values",
    ),
    "invalid law value": (
        '[[parameter]]\npath = "clearance.joints.S_1.friction.mu_c"\nvalues = [0.05, -1.0]',
        "clearance.joints.S_1.friction.mu_c",
        "-1.0",
    ),
    "output is not a parameter": (
        '[[parameter]]\npath = "output.folder"\nvalues = ["x"]',
        "parameter[0].path",
        "set by the study",
    ),
}


@pytest.mark.parametrize("what", list(INVALID))
def test_invalid_study_fails_before_anything_is_written(tmp_path, what):
    body, field, text = INVALID[what]
    folder = tmp_path / "study"
    path = tmp_path / "study.toml"
    path.write_text(study_text(folder, body))
    with pytest.raises(StudyError) as e:
        run_study(path, scheduler="serial", progress=False)
    msg = str(e.value)
    assert f"field '{field}'" in msg and text in msg and "study.toml" in msg, msg
    assert any(p.field == field for p in e.value.problems)
    assert not folder.exists()


def test_unknown_metric_and_cli_check(tmp_path):
    folder = tmp_path / "study"
    path = tmp_path / "study.toml"
    path.write_text(study_text(folder, metrics=["peak_contact_forse", "wall_time@S_1"]))
    with pytest.raises(StudyError) as e:
        load_study(path)
    lines = e.value.lines()
    assert "'study.metrics[0]' = 'peak_contact_forse'" in lines[0]
    assert "did you mean 'peak_contact_force'" in lines[0]
    assert "'study.metrics[1]'" in lines[1] and "not per joint" in lines[1]
    r = CliRunner().invoke(app, ["sweep", str(path)])
    assert r.exit_code == 2 and "peak_contact_forse" in r.output
    assert not folder.exists()
    path.write_text(study_text(folder))
    r = CliRunner().invoke(app, ["sweep", str(path), "--check"])
    assert r.exit_code == 0 and "6 cases" in r.output
    assert not folder.exists()


def test_example_study_is_valid():
    s = load_study(example_study_path())
    assert len(s.cases) == 6 and [p.name for p in s.parameters] == ["radial_clearance", "mu_c"]
    assert isinstance(StudyError("f", "x", 1, "y"), ScenarioError)


# --------------------------------------------------------------------------- case generation


def test_grid_zip_ranges_and_stable_ids(tmp_path):
    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
range = { start = 1e-4, stop = 5e-4, step = 2e-4 }

[[parameter]]
path = "solver.rtol"
range = { start = 1e-7, stop = 1e-5, num = 3 }
scale = "log"

[[parameter]]
path = "clearance.joints.S_1.normal.restitution"
values = [0.5, 0.7, 0.9]
zip = "g"

[[parameter]]
path = "clearance.joints.S_1.friction.mu_c"
values = [0.05, 0.1, 0.15]
zip = "g"

[[parameter]]
path = "clearance.joints"
values = [["S_1"], ["S_1", "S_2"]]
"""
    s = loads_study(study_text(tmp_path, params), source="g.toml")
    assert len(s.cases) == 3 * 3 * 3 * 2  # grid x zip group x joint sets
    vals = [c.values for c in s.cases]
    assert sorted({v["clearance.joints.S_1.radial_clearance"] for v in vals}) == [
        1e-4,
        3e-4,
        5e-4,
    ]
    assert sorted({v["solver.rtol"] for v in vals}) == [1e-7, 1e-6, 1e-5]
    pairs = {
        (v["clearance.joints.S_1.normal.restitution"], v["clearance.joints.S_1.friction.mu_c"])
        for v in vals
    }
    assert pairs == {(0.5, 0.05), (0.7, 0.1), (0.9, 0.15)}
    assert len({c.id for c in s.cases}) == len(s.cases)
    # ids are hashes of the overrides: reordering values keeps them
    rev = params.replace('[["S_1"], ["S_1", "S_2"]]', '[["S_1", "S_2"], ["S_1"]]')
    s2 = loads_study(study_text(tmp_path, rev), source="g.toml")
    assert {c.id for c in s2.cases} == {c.id for c in s.cases}
    assert [c.id for c in s2.cases] != [c.id for c in s.cases]


def test_latin_hypercube_reproducible_and_within_bounds(tmp_path):
    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
sample = { min = 1e-4, max = 5e-4, scale = "log" }

[[parameter]]
path = "clearance.joints.S_1.friction.mu_c"
sample = { min = 0.05, max = 0.15 }

[[parameter]]
path = "solver.rtol"
values = [1e-6, 1e-7]

[sampling]
method = "lhs"
n = 8
seed = {seed}
"""

    def draw(seed: int, method: str = "lhs"):
        text = study_text(tmp_path, params.replace("{seed}", str(seed)))
        s = loads_study(text.replace('"lhs"', f'"{method}"'), source="lhs.toml")
        c = np.array(
            [
                [
                    v["clearance.joints.S_1.radial_clearance"],
                    v["clearance.joints.S_1.friction.mu_c"],
                ]
                for v in (case.values for case in s.cases)
            ]
        )
        return s, c

    s, a = draw(1)
    assert len(s.cases) == 16  # 8 samples x 2 rtol values
    _, b = draw(1)
    _, other = draw(2)
    _, rnd = draw(1, "random")
    assert np.array_equal(a, b) and not np.array_equal(a, other) and not np.array_equal(a, rnd)
    pts = a[::2]  # each sample once (the rtol factor comes last)
    assert np.all((pts[:, 0] >= 1e-4) & (pts[:, 0] <= 5e-4))
    assert np.all((pts[:, 1] >= 0.05) & (pts[:, 1] <= 0.15))
    # Latin hypercube: exactly one point in each of the 8 strata of every coordinate
    u0 = np.log(pts[:, 0] / 1e-4) / np.log(5.0)
    u1 = (pts[:, 1] - 0.05) / 0.1
    for u in (u0, u1):
        assert sorted(np.minimum((u * 8).astype(int), 7)) == list(range(8))


def test_metric_aggregation_over_joints():
    """Per-joint metrics: '@J' is that joint (NaN if it has no clearance in the case);
    without it, max (sum for impacts) over the case's joints, 0 with no clearance joint."""
    joints = {
        "S_1": {"peak_contact_force": 10.0, "impacts": 2, "rms_contact_force": 1.0},
        "S_3": {"peak_contact_force": 30.0, "impacts": 5, "rms_contact_force": 0.5},
    }
    runs = {"status": 0, "energy_residual_relative": 1e-9, "real_time_factor": 2.0}
    summary = {"joints": joints, "deviation_rms": {}, "ideal": runs, "clearance": runs}
    energy = {"damping": np.array([0.0, 0.25]), "friction": np.array([0.0, 0.5])}
    case = CaseData(summary, {"total": 3.0}, lambda run, term: energy[term], dict)
    names = [
        "peak_contact_force",
        "peak_contact_force@S_1",
        "peak_contact_force@S_2",
        "impacts",
        "rms_contact_force",
        "deviation_position",
        "energy_dissipated",
        "wall_time",
        "success",
        "max_penetration",
    ]
    m = compute_metrics(case, names)
    assert m["peak_contact_force"] == 30.0 and m["peak_contact_force@S_1"] == 10.0
    assert math.isnan(m["peak_contact_force@S_2"]) and math.isnan(m["deviation_position"])
    assert m["impacts"] == 7 and m["rms_contact_force"] == 1.0
    assert m["energy_dissipated"] == 0.75 and m["wall_time"] == 3.0 and m["success"] == 1.0
    assert math.isnan(m["max_penetration"])  # not in this summary: NaN, not an error
    empty = CaseData({**summary, "joints": {}}, {}, lambda run, term: energy[term], dict)
    assert compute_metrics(empty, ["peak_contact_force", "impacts"]) == {
        "peak_contact_force": 0.0,
        "impacts": 0.0,
    }


# --------------------------------------------------------------------------- execution


def test_local_cluster_gives_the_serial_results(serial, client, tmp_path):
    """Same code, same inputs: every metric and every saved array is bitwise equal (worker
    processes run the same compiled kernels; BLAS is single-threaded in both)."""
    study, rep_serial = serial
    assert rep_serial.complete and not rep_serial.failed and len(rep_serial.finished) == 6
    folder = tmp_path / "cluster"
    rep = run_study(study, scheduler=client, folder=folder, progress=False)
    assert rep.complete and sorted(rep.finished) == sorted(c.id for c in study.cases)
    a, b = sidecars(study.folder), sidecars(folder)
    assert set(a) == set(b) == {c.id for c in study.cases}
    workers = {s["worker"] for s in b.values()}
    assert len(workers) == 2  # both workers took cases
    for cid in a:
        ma, mb = a[cid]["metrics"], b[cid]["metrics"]
        for m in NOT_TIMING:
            assert ma[m] == mb[m] or (math.isnan(ma[m]) and math.isnan(mb[m])), (cid, m)
        assert all(math.isfinite(ma[m]) for m in NOT_TIMING)
    cid = study.cases[-1].id
    x = load_results(study.folder / "cases" / f"{cid}.nc")
    y = load_results(folder / "cases" / f"{cid}.nc")
    for g in x:
        for v in x[g].data_vars:
            xv, yv = x[g][v].values, y[g][v].values
            assert np.array_equal(xv, yv, equal_nan=xv.dtype.kind == "f"), (g, v)


def test_rerun_skips_finished_cases_and_redoes_a_deleted_one(serial, tmp_path):
    study, _ = serial
    folder = tmp_path / "copy"
    shutil.copytree(study.folder, folder)
    before = sidecars(folder)
    rep = run_study(study, scheduler="serial", folder=folder, progress=False)
    assert rep.submitted == [] and len(rep.skipped) == 6 and rep.complete
    assert sidecars(folder) == before
    victim = study.cases[2].id
    (folder / "cases" / f"{victim}.nc").unlink()
    rep = run_study(study, scheduler="serial", folder=folder, progress=False)
    assert rep.submitted == [victim] == rep.finished
    after = sidecars(folder)
    assert {k: v for k, v in after.items() if k != victim} == {
        k: v for k, v in before.items() if k != victim
    }
    assert after[victim]["attempts"] == 2 and after[victim]["status"] == "finished"
    assert after[victim]["metrics"]["impacts"] == before[victim]["metrics"]["impacts"]


@pytest.mark.parametrize("retries", [0, 1])
def test_serial_study_write_behind_failure_is_retried_or_recorded(tmp_path, monkeypatch, retries):
    """A serial study writes each case's file while the next case integrates; a write that
    fails counts as an attempt: the case runs again (retries left) or is recorded failed,
    and the other cases finish with their files."""
    import clearance.pipeline as P

    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
values = [1e-4, 2e-4, 3e-4]
"""
    study = loads_study(study_text(tmp_path / "wb", params, metrics=["impacts"]))
    victim = study.cases[1].id
    real, calls = P.write_outputs, []

    def flaky(s, *args, **kw):
        calls.append(s.name)
        if s.name == victim and calls.count(victim) == 1:
            raise OSError("disk full (simulated)")
        return real(s, *args, **kw)

    monkeypatch.setattr(P, "write_outputs", flaky)
    before = dask.config.get("scheduler", None)
    rep = run_study(study, scheduler="serial", retries=retries, progress=False)
    assert dask.config.get("scheduler", None) == before  # the writes' local lock undone
    sc = sidecars(study.folder)
    others = [c.id for c in study.cases if c.id != victim]
    assert all(sc[c]["status"] == "finished" and sc[c]["attempts"] == 1 for c in others)
    assert all((study.folder / "cases" / f"{c}.nc").exists() for c in others)
    if retries:
        assert rep.complete and sc[victim]["status"] == "finished"
        assert sc[victim]["attempts"] == 2 and calls.count(victim) == 2
    else:
        assert list(rep.failed) == [victim] and "disk full" in rep.failed[victim]
        assert sc[victim]["status"] == "failed" and "disk full" in sc[victim]["reason"]
        assert not (study.folder / "cases" / f"{victim}.nc").exists()


def test_killed_worker_is_retried_and_failing_case_is_recorded(client, tmp_path):
    """One case kills its worker process on its first attempt (os._exit): the scheduler
    reruns it elsewhere. Another raises on every attempt: recorded as failed with the
    reason after 1 + retries attempts. The others finish."""
    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
values = [1e-4, 3e-4, 5e-4]
"""
    folder = tmp_path / "faults"
    study = loads_study(study_text(folder, params, metrics=["impacts"]), source="f.toml")
    killer, failing, fine = (c.id for c in study.cases)
    marker = tmp_path / "killed-once"
    fault = {
        killer: {"kind": "exit-once", "marker": str(marker)},
        failing: {"kind": "raise", "message": "injected failure"},
    }
    lines = []
    rep = run_study(study, scheduler=client, retries=1, progress=lines.append, _fault=fault)
    assert marker.exists()
    text = "\n".join(lines)
    # the progress says what happened: the lost worker, and each case's second attempt
    assert "left the cluster (died, killed or stopped)" in text, text
    assert re.search(rf"{killer} finished in \S+ s after 2 attempts", text), text
    assert f"{failing} FAILED after 2 attempts" in text, text
    assert sorted(rep.finished) == sorted([killer, fine])
    assert list(rep.failed) == [failing] and "injected failure" in rep.failed[failing]
    sc = sidecars(folder)
    assert sc[killer]["status"] == "finished" and sc[killer]["attempts"] == 2
    assert sc[fine]["status"] == "finished" and sc[fine]["attempts"] == 1
    assert sc[failing]["status"] == "failed" and sc[failing]["attempts"] == 2
    assert "RuntimeError: injected failure" in sc[failing]["reason"]
    table = collect_study(folder, dataset=False, plots=False).table.set_index("case")
    assert table.loc[failing, "status"] == "failed"
    assert "injected failure" in table.loc[failing, "reason"]
    assert math.isnan(table.loc[failing, "impacts"]) and table.loc[fine, "impacts"] > 0


@pytest.mark.parametrize("where", ["serial", "cluster"])
def test_input_errors_are_not_retried(client, tmp_path, where):
    """A case whose input is wrong fails the same way on every attempt: recorded failed
    after one, with the reason, on both schedulers; the other case finishes."""
    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
values = [1e-4, 3e-4]
"""
    folder = tmp_path / where
    study = loads_study(study_text(folder, params, metrics=["impacts"]), source="i.toml")
    bad, fine = (c.id for c in study.cases)
    scheduler = "serial" if where == "serial" else client
    rep = run_study(
        study, scheduler=scheduler, retries=2, progress=False, _fault={bad: {"kind": "input"}}
    )
    assert list(rep.failed) == [bad] and "injected input error" in rep.failed[bad]
    assert rep.finished == [fine]
    sc = sidecars(folder)
    assert sc[bad]["status"] == "failed" and sc[bad]["attempts"] == 1
    assert "ModelError" in sc[bad]["reason"]


def test_progress_says_when_a_case_is_implausible(tmp_path):
    """A study that varies the stiffness over decades: the case whose ball sinks through
    its socket (a gel-soft K = 2e3 N/m^1.5, E* ~ 2 kPa) says IMPLAUSIBLE in its progress
    line, the others do not."""
    params = """
[[parameter]]
path = "clearance.joints.S_1.normal"
values = [{ law = "hertz", stiffness = 2e3 }, { law = "hertz", stiffness = 1e11 }]
"""
    study = loads_study(study_text(tmp_path / "k", params, metrics=["impacts"]), source="k.toml")
    lines: list[str] = []
    rep = run_study(study, scheduler="serial", progress=lines.append)
    assert rep.complete
    soft, stiff = (next(x for x in lines if c.id in x and "finished" in x) for c in study.cases)
    assert "IMPLAUSIBLE: S_1" in soft and "IMPLAUSIBLE" not in stiff
    from clearance.sweep.collect import study_table

    table = study_table(study.folder).set_index("case")
    assert table.loc[study.cases[0].id, "plausibility"] == "implausible"
    assert table.loc[study.cases[1].id, "plausibility"] in ("ok", "warning")


def test_half_written_files_are_removed_on_resume_and_collect(serial, tmp_path):
    """A killed run leaves its atomic writes' temporaries (a result file's can be 100 MB):
    resuming the study removes them, collecting it the stale ones; finished cases stay."""
    study, _ = serial
    folder = tmp_path / "left"
    shutil.copytree(study.folder, folder)
    before = sidecars(folder)
    junk = [folder / "cases" / ".c1.nc.x1y2.tmp", folder / ".manifest.json.abc.tmp"]
    for p in junk:
        p.write_bytes(b"\0" * 1000)
    rep = run_study(study, scheduler="serial", folder=folder, progress=False)
    assert rep.submitted == [] and not any(p.exists() for p in junk)
    assert sidecars(folder) == before
    # collect may watch a running study: it leaves a write in progress (a fresh file)
    # and removes one untouched for longer than STALE_TMP
    fresh, stale = junk[0], folder / "cases" / ".c2.nc.z9.tmp"
    fresh.write_bytes(b"\0")
    stale.write_bytes(b"\0")
    old = time.time() - STALE_TMP - 60
    os.utime(stale, (old, old))
    collect_study(folder, dataset=False, plots=False)
    assert fresh.exists() and not stale.exists()


def test_interrupted_study_resumes_without_redoing_finished_cases(client, tmp_path):
    """`clearance sweep` in a subprocess (its own LocalCluster) is stopped with SIGTERM after
    the first case finishes; the rerun skips every finished case (their sidecars are
    untouched) and finishes the rest. The cases simulate 1 s (~0.3 s each): short cases
    could all finish before the signal lands."""
    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
values = [1e-4, 2e-4, 3e-4, 4e-4, 5e-4, 6e-4, 7e-4, 8e-4]
"""
    folder = tmp_path / "interrupted"
    path = tmp_path / "study.toml"
    text = study_text(folder, params, metrics=["impacts"])
    path.write_text(text.replace("trajectory.duration = 0.06", "trajectory.duration = 1.0"))
    cmd = [sys.executable, "-c", "from clearance.cli.main import app; app()"]
    proc = subprocess.Popen(
        [*cmd, "sweep", str(path), "--workers", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    t0 = time.monotonic()  # generous: a cold numba cache compiles on each worker first
    while time.monotonic() - t0 < 300 and proc.poll() is None:
        if any(s.get("status") == "finished" for s in sidecars(folder).values()):
            break
        time.sleep(0.2)
    proc.send_signal(signal.SIGTERM)
    out, _ = proc.communicate(timeout=120)
    assert proc.returncode == 130, out
    assert "interrupted" in out
    before = {k: v for k, v in sidecars(folder).items() if v["status"] == "finished"}
    assert 1 <= len(before) < 8, out
    study = load_study(path)  # resumed through the scheduler's address, as on a cluster
    rep = run_study(study, scheduler=client.scheduler.address, n_workers=2, progress=False)
    assert rep.complete and sorted(rep.skipped) == sorted(before)
    assert not set(rep.submitted) & set(before)
    after = sidecars(folder)
    assert {k: after[k] for k in before} == before  # finished cases were not touched
    assert all(s["status"] == "finished" for s in after.values()) and len(after) == 8


# --------------------------------------------------------------------------- collect


def test_collect_dataset_table_and_plots(serial):
    study, _ = serial
    out = collect_study(study.folder)
    n = len(study.cases)
    data = load_results(out.dataset)
    assert {"summary", "ideal", "clearance"} <= set(data)
    assert data["clearance"].sizes["case"] == n == data["summary"].sizes["case"]
    assert data["clearance"]["contact_force"].dims[0] == "case"
    assert list(data["clearance"]["mu_c"].values) == [c.values["mu_c"] for c in study.cases]
    for table in (pd.read_parquet(out.parquet), pd.read_csv(out.csv)):
        assert len(table) == n and set(table["status"]) == {"finished"}
        assert {"case", "radial_clearance", "mu_c", *METRIC_NAMES} <= set(table.columns)
        assert table["radial_clearance"].nunique() == 3 and table["mu_c"].nunique() == 2
    assert {p.name for p in out.plots} == {"radial_clearance.png", "mu_c.png"}
    assert all(p.stat().st_size > 1000 for p in out.plots)
    # metrics from the saved files equal those computed on the worker
    cid = study.cases[0].id
    side = json.loads((study.folder / "cases" / f"{cid}.json").read_text())
    again = compute_metrics(
        CaseData.from_files(study.folder / "cases" / f"{cid}.nc", side), METRIC_NAMES
    )
    assert again == side["metrics"]
    r = CliRunner().invoke(app, ["collect", str(study.folder), "--no-dataset", "--no-plots"])
    assert r.exit_code == 0 and "6 finished" in r.output
    r = CliRunner().invoke(app, ["plot", str(out.dataset), "--out", str(study.folder / "f")])
    assert r.exit_code == 2 and "collected study" in r.output and "Traceback" not in r.output


def test_collect_of_a_folder_that_is_not_a_study(tmp_path):
    with pytest.raises(StudyError, match="not a study folder"):
        collect_study(tmp_path)
    assert os.listdir(tmp_path) == []


def test_study_plots_carry_units_and_mark_failed_and_stopped_cases(serial, tmp_path):
    """Parameter axes have units; a failed case is a red x at its parameter value; a case
    whose run stopped early has its values circled in red (the table says success False)."""
    from clearance.sweep.collect import parameter_unit, plot_study, study_table
    from clearance.sweep.store import read_manifest

    study, _ = serial
    table = study_table(study.folder)
    assert table["success"].all()
    man = read_manifest(study.folder)
    table.loc[0, "status"] = "failed"
    table.loc[1, "success"] = False
    assert parameter_unit("clearance.joints.S_1.radial_clearance") == "m"
    assert parameter_unit("no.such.field") == ""

    import unittest.mock as mock

    from clearance.plot import figures as F

    captured = {}
    real = F.save_figure

    def grab(fig, out_dir, stem, formats):
        captured[stem] = fig
        return real(fig, out_dir, stem, formats)

    with mock.patch.object(F, "save_figure", grab):
        files = plot_study(table, man, tmp_path)
    assert len(files) == 2 and all(p.stat().st_size > 1000 for p in files)
    fig = captured["radial_clearance"]
    ax = fig.get_axes()[0]
    assert ax.get_xlabel() == "radial_clearance [m]"
    (x,) = [ln for ln in ax.get_lines() if ln.get_label() == "failed"]
    assert x.get_xdata()[0] == table.loc[0, "radial_clearance"]
    (o,) = [ln for ln in ax.get_lines() if ln.get_label() == "stopped early"]
    metric = man["metrics"][0]
    assert o.get_ydata()[0] == table.loc[1, metric]


def test_watch_reports_lost_workers_and_new_attempts_of_running_cases(tmp_path):
    """Between results, a Dask study says which worker left or joined, and which running
    case started again and why (its worker died, or its last attempt failed), from the
    scheduler's worker list and the running cases' sidecars."""
    from clearance.sweep.run import StudyReport, _Tracker, _Watch
    from clearance.sweep.store import case_files, write_json

    class Fut:
        def __init__(self, key):
            self.key = key

    class Client:
        workers = {"tcp://a": {}, "tcp://b": {}}
        running = {"tcp://a": ["k1"], "tcp://b": ["k2"]}

        def scheduler_info(self):
            return {"workers": dict(self.workers)}

        def processing(self):
            return dict(self.running)

    tasks = {
        Fut("k1"): {"case": "c1", "folder": str(tmp_path)},
        Fut("k2"): {"case": "c2", "folder": str(tmp_path)},
    }
    side = {cid: case_files(tmp_path, cid)[1] for cid in ("c1", "c2")}
    (tmp_path / "cases").mkdir(exist_ok=True)
    write_json(side["c1"], {"case": "c1", "attempts": 1, "status": "running", "worker": "hostA:1"})
    write_json(side["c2"], {"case": "c2", "attempts": 1, "status": "running", "worker": "hostB:2"})
    lines = []
    tr = _Tracker(StudyReport("s", tmp_path, 2, "test"), lines.append, 2)
    client = Client()
    w = _Watch(client, tasks, 2, tr)
    w.poll()
    assert lines == []  # first attempts: nothing to say
    # worker a dies: c1 runs again on c; c2 failed and is retried on b
    client.workers = {"tcp://b": {}, "tcp://c": {}}
    write_json(side["c2"], {"case": "c2", "attempts": 1, "status": "failed", "reason": "E: x"})
    w.poll()
    client.running = {"tcp://c": ["k1"], "tcp://b": ["k2"]}
    write_json(side["c1"], {"case": "c1", "attempts": 2, "status": "running", "worker": "hostC:3"})
    write_json(side["c2"], {"case": "c2", "attempts": 2, "status": "running", "worker": "hostB:2"})
    w.poll()
    w.poll()  # nothing new: nothing said twice
    text = "\n".join(lines)
    assert len(lines) == 4, text
    assert "worker tcp://a left the cluster" in lines[0] and "worker tcp://c joined" in lines[1]
    assert (
        "c1: attempt 2 of 3 on hostC:3 (attempt 1 on hostA:1 ended without a result: its "
        "worker died)" in text
    )
    assert "c2: attempt 2 of 3 on hostB:2 (attempt 1 failed: E: x)" in text


def test_attempts_of_an_earlier_session_are_not_this_sessions(tmp_path):
    """A case left 'running' after two attempts by an interrupted session is counted from 1
    again when the study resumes: its finished line does not say 'after 3 attempts', and
    the sidecar keeps the running total (3)."""
    from clearance.sweep.store import case_files, write_json

    params = """
[[parameter]]
path = "clearance.joints.S_1.radial_clearance"
values = [3e-4]
"""
    folder = tmp_path / "resumed"
    study = loads_study(study_text(folder, params, metrics=["impacts"]), source="r.toml")
    (cid,) = (c.id for c in study.cases)
    (folder / "cases").mkdir(parents=True)
    write_json(case_files(folder, cid)[1], {"case": cid, "attempts": 2, "status": "running"})
    lines = []
    rep = run_study(study, scheduler="serial", progress=lines.append)
    assert rep.finished == [cid]
    done = next(x for x in lines if f"{cid} finished" in x)
    assert "attempts" not in done, done
    assert sidecars(folder)[cid]["attempts"] == 3
