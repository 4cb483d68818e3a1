"""Run a study on Dask: a local cluster, an existing scheduler, or serially for debugging.

    report = run_study("study.toml")                          # LocalCluster sized to the machine
    report = run_study(study, scheduler="tcp://10.0.0.5:8786")  # an existing Dask cluster
    report = run_study(study, scheduler="serial")             # in this process, one by one

Each task is `run_case(task)`: plain data only (the base scenario dict, the case's overrides,
the study folder, the metric names). The worker builds and validates the scenario, runs
`run_scenario(..., figures=False)` (the compiled kernels come from numba's on-disk cache, so
only a worker's first task pays for loading them), writes `cases/<id>.nc` and then the
sidecar `cases/<id>.json`, both atomically. Cases already finished are skipped; an
exception is retried `retries` times (Dask `retries`), a worker that dies (crash, OOM
kill) makes the scheduler run the task elsewhere (`distributed.scheduler.allowed-failures`,
set to `retries` on the local cluster); a case that still fails is recorded as failed in its
sidecar with the reason, and the study goes on.
"""

from __future__ import annotations

import contextlib
import functools
import os
import socket
import time
import traceback
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from clearance.model.errors import KinematicsError, ModelError
from clearance.sweep.metrics import CaseData, compute_metrics
from clearance.sweep.store import (
    CASES,
    FAILED,
    FINISHED,
    RUNNING,
    case_files,
    is_finished,
    now,
    prepare_folder,
    read_json,
    write_json,
)
from clearance.sweep.study import Case, Study, case_scenario_dict, load_study

__all__ = ["StudyReport", "default_workers", "run_case", "run_study", "start_case"]

SERIAL = "serial"
# deterministic failures of a case's input (a scenario value, an unreachable trajectory):
# recorded as failed at once instead of retried on other workers
INPUT_ERRORS = (ModelError, KinematicsError)
FAULT_EXIT_ONCE, FAULT_RAISE, FAULT_INPUT = "exit-once", "raise", "input"


@dataclass
class StudyReport:
    """Outcome of `run_study`. Case ids: skipped (finished before this run), submitted,
    finished and failed (id -> reason) in this run, lost (not finished: interrupted or
    cancelled; they run again next time)."""

    study: str
    folder: Path
    n_cases: int
    executor: str
    skipped: list[str] = field(default_factory=list)
    submitted: list[str] = field(default_factory=list)
    finished: list[str] = field(default_factory=list)
    failed: dict[str, str] = field(default_factory=dict)
    lost: list[str] = field(default_factory=list)
    wall_time: float = 0.0

    @property
    def complete(self) -> bool:
        """Every case of the study is finished."""
        return len(self.skipped) + len(self.finished) == self.n_cases

    @property
    def throughput(self) -> float:
        """Cases finished per minute of this run's wall time."""
        return 60.0 * len(self.finished) / self.wall_time if self.wall_time > 0 else 0.0

    def summary(self) -> str:
        return (
            f"study '{self.study}' ({self.executor}): {self.n_cases} cases; "
            f"{len(self.skipped)} already finished, {len(self.finished)} finished now, "
            f"{len(self.failed)} failed, {len(self.lost)} not run; wall {self.wall_time:.1f} s "
            f"({self.throughput:.1f} cases/min); folder {self.folder}"
        )


# --------------------------------------------------------------------------- the task


def _fault(spec: Mapping[str, Any] | None) -> None:
    """Test hook: make this case fail. {"kind": "exit-once", "marker": path} kills the
    worker process on the first attempt only (the marker file records it); {"kind":
    "raise"} raises on every attempt; {"kind": "input"} raises an input error (ModelError)."""
    if not spec:
        return
    if spec["kind"] == FAULT_EXIT_ONCE:
        marker = Path(spec["marker"])
        if not marker.exists():
            marker.write_text(str(os.getpid()))
            os._exit(1)
    elif spec["kind"] == FAULT_RAISE:
        raise RuntimeError(spec.get("message", "injected failure (test hook)"))
    elif spec["kind"] == FAULT_INPUT:
        raise ModelError("case", "fault", spec["kind"], "an injected input error (test hook)")


def run_case(task: Mapping[str, Any]) -> dict:
    """Run one case from plain data; return its sidecar (also written to the folder).

    task: study (name), case (id), index, values, overrides, base (scenario dict), folder,
    metrics (names), joint_template, and optionally start_state (the clearance run's
    initial state, a list of floats: continuation) and fault (a test hook, see `_fault`).
    The sidecar says "running" (with the attempt number) while the case runs, then
    "finished" (metrics, summary, timings, result file size) or "failed" (reason and
    traceback; the exception is re-raised so that Dask retries it).
    """
    return start_case(task)()


def start_case(task: Mapping[str, Any], *, defer_write: bool = False) -> Callable[[], dict]:
    """`run_case` in two parts: this call runs the case (its sidecar says "running"); the
    function it returns writes the result file, then the sidecar "finished", and returns
    the sidecar. With defer_write the result file is written by that function (a serial
    study calls it in a second thread while the next case integrates); without, by this
    call. A failure in either part writes the sidecar "failed" and raises, except an
    input error (`INPUT_ERRORS`: it would fail the same way again), whose function
    returns that sidecar instead: it is not retried."""
    import dask

    from clearance.pipeline import run_scenario
    from clearance.scenario.schema import scenario_from_dict

    folder, cid = Path(task["folder"]), task["case"]
    nc, side = case_files(folder, cid)
    prev = read_json(side) or {}
    attempts = int(prev.get("attempts", 0)) + 1 if prev.get("case") == cid else 1
    info: dict[str, Any] = {
        "case": cid,
        "index": task["index"],
        "study": task["study"],
        "status": RUNNING,
        "attempts": attempts,
        "reason": "",
        "values": task["values"],
        "overrides": task["overrides"],
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "started": now(),
    }
    write_json(side, info)

    def failed(e: Exception, elapsed: float) -> None:
        info.update(
            status=FAILED,
            reason=f"{type(e).__name__}: {e}",
            traceback=traceback.format_exc(limit=8),
            ended=now(),
            elapsed=elapsed,
        )
        write_json(side, info)

    # a local lock for a NetCDF write through xarray: inside a Dask worker xarray would
    # otherwise take a cluster-wide lock, a scheduler round trip that fails while the
    # cluster shuts down
    local = functools.partial(dask.config.set, scheduler="synchronous")
    t0 = time.perf_counter()
    try:
        _fault(task.get("fault"))
        source = f"{task['study']}:{cid}"
        d = case_scenario_dict(
            task["base"], task["overrides"], joint_template=task["joint_template"], source=source
        )
        d["scenario"] = {**d["scenario"], "name": cid}
        # (no report per case: the study's report links a viewer page per case)
        d["output"] = {
            **d.get("output", {}),
            "figures": False,
            "formats": ["netcdf"],
            "report": False,
        }
        s = scenario_from_dict(d, source=source)
        # (a deferred write leaves this part no NetCDF to write, and a second thread may
        # be writing the previous case under `local()`: dask's config is process-wide)
        with contextlib.nullcontext() if defer_write else local():
            out = run_scenario(
                s,
                out_dir=folder / CASES,
                figures=False,
                reuse_ideal=True,
                defer_write=defer_write,
                log=None,
                y0=task.get("start_state"),
            )
    except INPUT_ERRORS as e:  # the same input fails the same way: no retry
        failed(e, time.perf_counter() - t0)
        if getattr(e, "transient", False):  # the machine's, not the input's: retried
            raise
        return lambda: read_json(side) or info
    except Exception as e:
        failed(e, time.perf_counter() - t0)
        raise
    ran = time.perf_counter() - t0

    def finish() -> dict:
        import clearance

        t1 = time.perf_counter()
        try:
            with local():
                out.write()
            # after the write: the timings (the wall_time metric) include it either way
            metrics = compute_metrics(CaseData.from_run(out), task["metrics"])
        except Exception as e:
            failed(e, ran + time.perf_counter() - t1)
            raise
        info.update(
            status=FINISHED,
            ended=now(),
            elapsed=ran + time.perf_counter() - t1,
            result_file=nc.name,
            result_bytes=nc.stat().st_size,
            success=bool(out.ideal.success and out.clearance.success),
            message=out.clearance.message,
            metrics=metrics,
            summary=out.summary,
            timings=out.timings,
            clearance_version=clearance.__version__,
        )
        write_json(side, info)
        return read_json(side) or info  # as collect will read it (JSON-normalised)

    return finish


# --------------------------------------------------------------------------- the study


def default_workers() -> int:
    """Cores available to this process (the default size of the local cluster)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover (macOS, Windows)
        return os.cpu_count() or 1


def _task(study: Study, case: Case, folder: Path, fault: Mapping | None) -> dict:
    return {
        "study": study.name,
        "case": case.id,
        "index": case.index,
        "values": case.values,
        "overrides": case.overrides,
        "base": study.base,
        "folder": str(folder),
        "metrics": list(study.metrics),
        "joint_template": study.joint_template,
        "fault": (fault or {}).get(case.id),
    }


class _Tracker:
    """Progress lines and the report's bookkeeping."""

    def __init__(self, report: StudyReport, say: Callable[[str], None] | None, total: int):
        self.report, self.say, self.total, self.t0 = report, say, total, time.perf_counter()
        self.before: dict[str, int] = {}  # case -> attempts recorded by earlier sessions

    def attempts(self, info: Mapping[str, Any]) -> int:
        """Attempts of a case in this session, from its sidecar's running count."""
        return int(info.get("attempts", 1)) - self.before.get(str(info.get("case")), 0)

    def _line(self, msg: str) -> None:
        if self.say is None:
            return
        r = self.report
        n = len(r.finished) + len(r.failed)
        el = time.perf_counter() - self.t0
        eta = el / n * (self.total - n) if n else float("nan")
        self.say(f"[{n}/{self.total}] {msg}  (elapsed {el:.0f} s, ETA {eta:.0f} s)")

    def done(self, info: Mapping[str, Any], label: str) -> None:
        """A case's sidecar came back: finished, or failed on its input (not retried)."""
        if info.get("status") == FAILED:
            self.failed(info["case"], info.get("reason", ""), label)
        else:
            self.finished(info, label)

    def finished(self, info: Mapping[str, Any], label: str) -> None:
        self.report.finished.append(info["case"])
        ok = "" if info.get("success", True) else f"; run stopped: {info.get('message')}"
        p = info.get("summary", {}).get("clearance", {}).get("plausibility", {})
        if p.get("status") == "implausible":  # finished, but not a motion physics allows
            ok += "; IMPLAUSIBLE: " + "; ".join(p.get("findings", []))
        n = self.attempts(info)
        tries = f" after {n} attempts" if n > 1 else ""
        self._line(f"{info['case']} finished in {info.get('elapsed', 0):.1f} s{tries}: {label}{ok}")

    def failed(self, cid: str, reason: str, label: str, attempts: int = 1) -> None:
        self.report.failed[cid] = reason
        tries = f" after {attempts} attempts" if attempts > 1 else ""
        self._line(f"{cid} FAILED{tries} ({label}): {reason}")

    def note(self, msg: str) -> None:
        """A line about the executor (a lost worker, a retried case)."""
        self._line(msg)


class _Watch:
    """Watches a Dask study between results: workers leaving or joining the cluster, and
    the cases a worker runs again (a retry after an exception, or a rerun after its worker
    died), from the scheduler's worker list and the running cases' sidecars."""

    def __init__(self, client, futures: dict, retries: int, tr: _Tracker) -> None:
        self.client, self.retries, self.tr = client, retries, tr
        self.case_of = {f.key: t for f, t in futures.items()}
        self.seen: dict[str, dict] = {}  # case -> its sidecar as last read
        self.workers = self._workers()

    def _workers(self) -> set:
        try:
            return set(self.client.scheduler_info().get("workers", {}))
        except Exception:  # a scheduler going away: the futures will say why
            return set()

    def poll(self) -> None:
        now = self._workers()
        for w in sorted(self.workers - now):
            self.tr.note(
                f"worker {w} left the cluster (died, killed or stopped); its case is "
                f"rescheduled (up to {self.retries} extra attempts per case)"
            )
        for w in sorted(now - self.workers):
            self.tr.note(f"worker {w} joined the cluster")
        self.workers = now
        try:
            running = [k for keys in self.client.processing().values() for k in keys]
        except Exception:
            return
        for key in running:
            t = self.case_of.get(key)
            if t is not None:
                self.check(t)

    def check(self, t: dict) -> None:
        """Compare a running case's sidecar with the last one read: a new attempt?"""
        cid = t["case"]
        info = read_json(case_files(Path(t["folder"]), cid)[1]) or {}
        if info.get("case") != cid:
            return
        before = self.seen.get(cid)
        self.seen[cid] = info
        attempt = self.tr.attempts(info)  # (in this session: a resumed study starts at 1)
        if attempt < 2 or (before is not None and self.tr.attempts(before) >= attempt):
            return
        if before is None:
            why = "an earlier attempt did not finish"
        elif before.get("status") == FAILED:
            why = f"attempt {self.tr.attempts(before)} failed: {before.get('reason', '')}"
        else:
            why = (
                f"attempt {self.tr.attempts(before)} on {before.get('worker', '?')} ended "
                "without a result: its worker died"
            )
        self.tr.note(
            f"{cid}: attempt {attempt} of {self.retries + 1} on {info.get('worker', '?')} ({why})"
        )


def _record_failure(folder: Path, task: Mapping[str, Any], exc: BaseException) -> str:
    """Make the sidecar say failed (a worker that died never wrote it); return the reason."""
    _, side = case_files(folder, task["case"])
    info = read_json(side) or {"case": task["case"], "attempts": 0}
    if info.get("status") == FAILED and info.get("reason"):
        return str(info["reason"])
    reason = f"{type(exc).__name__}: {exc}"
    info.update(
        case=task["case"],
        index=task["index"],
        study=task["study"],
        values=task["values"],
        overrides=task["overrides"],
        status=FAILED,
        reason=reason,
        ended=now(),
    )
    write_json(side, info)
    return reason


def warm_worker() -> float:
    """Imports and loads the compiled kernels in this process (a 5 ms run of the default
    scenario into a temporary folder, discarded); returns its wall time [s]. Run on every
    worker before the cases, so the first case of each worker does not carry the one-time
    warm-up in its timings (and the study's timing trends show the cases only). A process
    that has already run a scenario is warm: nothing to do (0.0)."""
    import tempfile

    from clearance import pipeline
    from clearance.pipeline import run_scenario
    from clearance.scenario import default_scenario_path, load_scenario, with_overrides

    if pipeline._RAN:
        return 0.0
    t0 = time.perf_counter()
    s = load_scenario(default_scenario_path())
    s = with_overrides(
        s, {"trajectory.duration": 0.005, "solver.dt_out": 1e-3, "output.report": False}
    )
    with tempfile.TemporaryDirectory() as d:
        run_scenario(s, out_dir=d, figures=False, log=None)
    return time.perf_counter() - t0


def _run_serial(tasks: list[dict], labels: dict, retries: int, tr: _Tracker) -> None:
    """The cases one after the other in this process; each case's result file is written
    in a second thread while the next case integrates (one write at a time; the kernels
    and most of the write release the GIL). A case whose write fails runs again, here,
    with the attempts it has left."""
    from clearance.pipeline import _Background

    warm = warm_worker()
    if tr.say is not None:
        tr.say(f"warmed up in {warm:.1f} s (imports, kernels), not counted in the cases")
    behind: list = []  # [(task, attempts used, write)] of the write in flight

    def settle(rerun: bool = True) -> None:
        if not behind:
            return
        t, used, write = behind[0]
        write.join()  # (before forgetting it: an interrupt here still finds it below)
        behind.clear()
        try:
            info = write.result()
        except Exception as e:  # recorded in the sidecar by the case
            if rerun and used <= retries:  # that write was an attempt: the rest, here
                _run_one(t, labels, retries - used, tr, defer=False)
            else:
                tr.failed(t["case"], _record_failure(Path(t["folder"]), t, e), labels[t["case"]])
            return
        tr.done(info, labels[t["case"]])

    done = False
    try:
        for t in tasks:
            fn, used = _run_one(t, labels, retries, tr, defer=True)
            settle()
            if fn is not None:
                behind.append((t, used, _Background(fn, name="clearance-case-write")))
        done = True
    finally:  # an interrupted study still finishes the write in flight, and no more
        settle(rerun=done)


def _run_one(t: dict, labels: dict, retries: int, tr: _Tracker, *, defer: bool):
    """Run case t with up to `retries` retries: (its finishing function, attempts used)
    with defer, else (None, attempts used) once it is finished (reported) or failed for
    good (recorded and reported)."""
    for attempt in range(retries + 1):
        try:
            fn = start_case(t, defer_write=defer)
            if defer:
                return fn, attempt + 1
            info = fn()
        except Exception as e:  # recorded in the sidecar by start_case
            if attempt == retries:
                reason = _record_failure(Path(t["folder"]), t, e)
                tr.failed(t["case"], reason, labels[t["case"]], attempt + 1)
            else:
                tr.note(
                    f"{t['case']}: attempt {attempt + 2} of {retries + 1} (attempt "
                    f"{attempt + 1} failed: {type(e).__name__}: {e})"
                )
            continue
        tr.done(info, labels[t["case"]])
        return None, attempt + 1
    return None, retries + 1


def _client(scheduler: Any, n_workers: int | None, retries: int, n_tasks: int):
    """(client, what to close afterwards, executor description)."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    if isinstance(scheduler, Client):
        return scheduler, [], f"Dask client {scheduler.scheduler.address}"
    if scheduler is None:
        n = n_workers or max(1, min(default_workers(), n_tasks))
        with dask.config.set({"distributed.scheduler.allowed-failures": retries}):
            cluster = LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=logging.ERROR,
            )
        client = Client(cluster)
        return client, [client, cluster], f"LocalCluster, {n} workers"
    if Path(scheduler).is_file():
        client = Client(scheduler_file=str(scheduler))
    else:
        client = Client(scheduler)
    if n_workers:
        client.wait_for_workers(n_workers)
    return client, [client], f"Dask scheduler {client.scheduler.address}"


#: how often a Dask study looks at its workers and running cases between results [s]
WATCH_SECONDS = 0.5


def _run_dask(
    tasks: list[dict],
    labels: dict,
    scheduler: Any,
    n_workers: int | None,
    retries: int,
    tr: _Tracker,
) -> None:
    from distributed import as_completed

    client, to_close, desc = _client(scheduler, n_workers, retries, len(tasks))
    tr.report.executor = desc
    if tr.say is not None:
        tr.say(f"executor: {desc}")
    futures: dict = {}
    try:
        try:
            warm = client.run(warm_worker)  # every worker, before its first case
        except Exception as e:  # the cases will fail with their own reasons
            warm = {}
            if tr.say is not None:
                tr.say(f"warm-up failed on a worker ({type(e).__name__}: {e})")
        if tr.say is not None and warm:
            tr.say(
                f"workers warmed up in {max(warm.values()):.1f} s (imports, kernels), "
                "not counted in the cases"
            )
        for t in tasks:
            key = f"clearance-case-{t['case']}-{uuid.uuid4().hex[:8]}"
            futures[client.submit(run_case, t, key=key, retries=retries, pure=False)] = t
        watch = _Watch(client, futures, retries, tr)
        ac = as_completed(list(futures))
        while not ac.is_empty():
            if not ac.has_ready():  # between results: lost workers, retried cases
                time.sleep(WATCH_SECONDS)
                watch.poll()
                continue
            for fut in ac.next_batch(block=False):
                t = futures[fut]
                label = labels[t["case"]]
                if fut.status == "finished":
                    tr.done(fut.result(), label)
                elif fut.status == "error":
                    exc = fut.exception()
                    reason = _record_failure(Path(t["folder"]), t, exc)
                    side = read_json(case_files(Path(t["folder"]), t["case"])[1]) or {}
                    tr.failed(t["case"], reason, label, tr.attempts(side))
                fut.release()
    finally:
        for fut in futures:
            if not fut.done():
                fut.cancel()
        for obj in to_close:
            with contextlib.suppress(Exception):
                obj.close()


def run_study(
    study: Study | str | os.PathLike,
    *,
    scheduler: Any = None,
    n_workers: int | None = None,
    retries: int = 2,
    progress: bool | Callable[[str], None] = True,
    folder: str | os.PathLike | None = None,
    _fault: Mapping[str, Mapping[str, Any]] | None = None,
) -> StudyReport:
    """Run every unfinished case of a study; return a `StudyReport`.

    study: a `Study` or a study file (validated completely before anything is written).
    scheduler: None = a `distributed.LocalCluster` with `n_workers` single-threaded worker
    processes (default: the cores available, at most one per case); "serial" = in this
    process, one case after the other (for debugging: breakpoints work); an address
    ("tcp://host:8786") or a scheduler file of an existing Dask cluster (`n_workers`: wait
    until that many workers are connected); or a `distributed.Client`.
    retries: extra attempts of a case that raises (and, on the local cluster, the allowed
    worker deaths per case). progress: print a line per case (or a callable taking each
    line). folder: the study folder (default: the study's). _fault: test hook, case id ->
    {"kind": "exit-once", "marker": path} or {"kind": "raise"}.
    KeyboardInterrupt stops the study; finished cases stay finished, the others run on the
    next call.
    """
    t0 = time.perf_counter()
    if not isinstance(study, Study):
        study = load_study(study)
    folder = Path(folder).expanduser().resolve() if folder is not None else study.folder
    say = print if progress is True else (progress or None)
    prepare_folder(study, folder)  # (removes what an interrupted run left half-written)
    report = StudyReport(study.name, folder, len(study.cases), str(scheduler or "LocalCluster"))
    pending = [c for c in study.cases if not is_finished(folder, c)]
    todo = {c.id for c in pending}
    report.skipped = [c.id for c in study.cases if c.id not in todo]
    if say is not None:
        say(
            f"study '{study.name}': {len(study.cases)} cases, {len(report.skipped)} already "
            f"finished, {len(pending)} to run; folder {folder}"
        )
    tasks = [_task(study, c, folder, _fault) for c in pending]
    report.submitted = [t["case"] for t in tasks]
    labels = {c.id: c.label() for c in pending}
    tr = _Tracker(report, say, len(tasks))
    for c in pending:  # attempts of earlier, interrupted sessions: not this session's
        prior = read_json(case_files(folder, c.id)[1]) or {}
        if prior.get("case") == c.id:
            tr.before[c.id] = int(prior.get("attempts", 0))
    try:
        if tasks and scheduler == SERIAL:
            report.executor = SERIAL
            _run_serial(tasks, labels, retries, tr)
        elif tasks:
            _run_dask(tasks, labels, scheduler, n_workers, retries, tr)
    except KeyboardInterrupt:
        # count from the folder: a case a worker finished is finished, reported or not
        on_disk = [c.id for c in pending if is_finished(folder, c)]
        report.finished += [cid for cid in on_disk if cid not in report.finished]
        if say is not None:
            done = len(report.skipped) + len(report.finished)
            say(f"interrupted: {done} of {len(study.cases)} cases finished; rerun to resume")
        raise
    finally:
        done = set(report.finished) | set(report.failed)
        report.lost = [cid for cid in report.submitted if cid not in done]
        report.wall_time = time.perf_counter() - t0
    if say is not None:
        say(report.summary())
        for cid, reason in report.failed.items():
            say(f"  failed {cid}: {reason}")
    return report
