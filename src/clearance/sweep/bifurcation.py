"""Bifurcation diagrams from a one-parameter study of steady-state runs: the Poincare points
of a channel after the transient, for each case, against the parameter.

    out = bifurcation("bifurcation.toml")         # runs the unfinished cases (Dask), then draws
    out = bifurcation(folder, run=False)           # from a finished (or partly finished) study

The study is an ordinary study file (docs/sweeps.md) with exactly one numeric parameter and
a base scenario with [steady_state] (the stroboscopic samples are exact samples of the
dense output). Writes <folder>/collected/bifurcation.nc (Poincare points (case, point) of
every analysed channel, the parameter, the classification and its evidence per case),
bifurcation.csv (one row per case) and bifurcation.png.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from clearance.nonlinear.analyze import analyze
from clearance.sweep.collect import COLLECTED
from clearance.sweep.store import case_files, is_finished, read_manifest
from clearance.sweep.study import Study, StudyError, load_study

__all__ = ["BifurcationOutput", "bifurcation", "check_bifurcation_study"]


@dataclass
class BifurcationOutput:
    """What `bifurcation` wrote and found: the parameter name and values (finished cases,
    in parameter order), the Poincare points per case of the plotted channel, the
    classification per case, the files, and the report of the study run (None if not run)."""

    folder: Path
    parameter: str
    values: np.ndarray
    channel: str
    points: list = field(default_factory=list)
    kinds: list = field(default_factory=list)
    files: list = field(default_factory=list)
    report: Any = None
    missing: list = field(default_factory=list)


def check_bifurcation_study(study: Study) -> str:
    """The varied parameter's name, or StudyError: one numeric parameter, steady state."""
    src = study.source
    if len(study.parameters) != 1:
        raise StudyError(
            src,
            "parameter",
            [p.name for p in study.parameters],
            "a bifurcation study varies exactly one parameter",
        )
    p = study.parameters[0]
    vals = [c.values[p.name] for c in study.cases]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals):
        raise StudyError(src, "parameter[0].values", vals, "expected numbers")
    if "steady_state" not in study.base:
        raise StudyError(
            src,
            "study.base",
            study.base_name,
            "a bifurcation diagram needs steady-state runs: give the base scenario a "
            "[steady_state] section (or set steady_state.transient_periods in [set])",
        )
    return p.name


def bifurcation(
    study: str | os.PathLike | Study,
    *,
    run: bool = True,
    channel: str | None = None,
    channels: Sequence[str] | None = None,
    transient_periods: int | None = None,
    scheduler: Any = None,
    n_workers: int | None = None,
    progress: bool | Callable[[str], None] = True,
    folder: str | os.PathLike | None = None,
    figure: bool = True,
    continuation: bool = False,
) -> BifurcationOutput:
    """Run (run=True: the unfinished cases, resumably, on Dask as `run_study`) or collect a
    one-parameter steady-state study and draw its bifurcation diagram.

    study: a study file, a `Study`, or (run=False) a study folder. channels: the
    channels analysed per case (default: `clearance.nonlinear.analyze.default_channels`);
    channel: the one plotted (default: the first of them).

    continuation: run the cases one after the other in the order of the values (give them
    increasing, or decreasing, to follow a branch either way), in this process,
    each starting from the previous case's final state (`clearance_final_state` of its
    file; whole drive periods, so the drive's phase matches) instead of the scenario's
    initial placement: a branch is followed as the parameter changes, and coexisting
    attractors show by running the study up and down. The first
    case starts as the scenario says; a resumed study starts from the last finished case."""
    from clearance.sweep.run import run_study

    report = None
    if isinstance(study, (str, os.PathLike)) and Path(study).is_dir():
        if run:
            raise StudyError(str(study), "study", str(study), "give the study file to run it")
        fold = Path(study)
        man = read_manifest(fold)
        pname = man["parameters"][0]["name"] if len(man["parameters"]) == 1 else None
        if pname is None:
            raise StudyError(str(fold), "parameter", man["parameters"], "expected one parameter")
        cases = [(c["id"], c["values"][pname], c) for c in man["cases"]]
    else:
        st = study if isinstance(study, Study) else load_study(study)
        pname = check_bifurcation_study(st)
        fold = Path(folder).expanduser().resolve() if folder is not None else st.folder
        if run and continuation:
            report = _continue(st, fold, progress)
        elif run:
            report = run_study(
                st, scheduler=scheduler, n_workers=n_workers, progress=progress, folder=fold
            )
        cases = [(c.id, c.values[pname], c) for c in st.cases]
    if not continuation:
        cases.sort(key=lambda c: c[1])
    from clearance.sweep.study import Case

    values, points, kinds, rows, strobes, missing = [], [], [], [], [], []
    chans = list(channels) if channels else None
    for cid, val, c in cases:
        case = c if isinstance(c, Case) else Case(c["id"], c["index"], c["values"], c["overrides"])
        nc, _ = case_files(fold, cid)
        if not is_finished(fold, case):
            missing.append(cid)
            continue
        a = analyze(nc, channels=chans, transient_periods=transient_periods)
        if chans is None:
            chans = a.channels
        plot_ch = channel or chans[0]
        k = a.channels.index(plot_ch) if plot_ch in a.channels else None
        if k is None:
            raise StudyError(str(fold), "channel", plot_ch, f"analysed channels: {a.channels}")
        values.append(float(val))
        points.append(a.strobe[:, k])
        strobes.append(a.strobe)
        kinds.append(a.classification.kind)
        rows.append(
            {
                "case": cid,
                pname: val,
                "response": a.classification.kind,
                "distinct_points": a.classification.distinct,
                "points": a.classification.points,
                "zero_one_K": a.zero_one,
                "evidence": "; ".join(a.classification.reasons),
            }
        )
    out = BifurcationOutput(
        fold,
        pname,
        np.array(values),
        channel or (chans[0] if chans else ""),
        points,
        kinds,
        report=report,
        missing=missing,
    )
    if not values:
        return out
    out.files = _write(fold / COLLECTED, out, chans, strobes, rows, figure)
    return out


def _continue(st: Study, folder: Path, progress) -> Any:
    """Run the unfinished cases in the study's order, each from the previous one's end."""
    import time

    from clearance.sweep.run import StudyReport, _task, start_case
    from clearance.sweep.store import prepare_folder

    say = print if progress is True else (progress or (lambda _m: None))
    t0 = time.perf_counter()
    prepare_folder(st, folder)
    rep = StudyReport(st.name, folder, len(st.cases), "continuation (serial)")
    start = None
    for c in st.cases:
        nc, _ = case_files(folder, c.id)
        if is_finished(folder, c):
            rep.skipped.append(c.id)
            start = _end_state(nc)
            continue
        task = _task(st, c, folder, None)
        if start is not None and start.ndim == 1 and start.size:
            task["start_state"] = start.tolist()
        rep.submitted.append(c.id)
        try:
            side = start_case(task)()
        except Exception as e:  # (recorded in the case's sidecar by start_case)
            side = {"status": "failed", "reason": f"{type(e).__name__}: {e}"}
        if side.get("status") != "finished":
            rep.failed[c.id] = str(side.get("reason", ""))
            say(f"{c.id} failed: {side.get('reason', '')}; the branch stops here")
            break
        rep.finished.append(c.id)
        src = "the previous case's end" if "start_state" in task else "the scenario's start"
        say(f"[{len(rep.skipped) + len(rep.finished)}/{len(st.cases)}] {c.label()} from {src}")
        start = _end_state(nc)
        if start is None:
            say(f"  {c.id} stopped early: the next case starts as the scenario says")
    rep.wall_time = time.perf_counter() - t0
    return rep


def _end_state(nc: Path) -> np.ndarray | None:
    """The clearance run's final state of a finished case, or None when the run stopped
    early or not after whole periods (the drive's phase would not match)."""
    from clearance.io.dataset import load_results

    rf = load_results(nc)
    a = rf.attrs
    y = a.get("clearance_final_state")
    T = a.get("steady_period")
    t_end = float(a.get("clearance_final_time", 0.0))
    ok = rf["clearance"].attrs.get("success", 0)
    if y is None or T is None or not ok:
        return None
    if abs(t_end / float(T) - round(t_end / float(T))) > 1e-6 or t_end <= 0:
        return None
    return np.asarray(y, dtype=float)


def _write(out_dir: Path, out: BifurcationOutput, chans, strobes, rows, figure) -> list[Path]:
    import pandas as pd
    import xarray as xr

    from clearance.io.dataset import save_results
    from clearance.io.files import atomic_path

    out_dir.mkdir(parents=True, exist_ok=True)
    npt = max(s.shape[0] for s in strobes)
    P = np.full((len(strobes), npt, len(chans)), np.nan)
    for i, s in enumerate(strobes):
        P[i, : s.shape[0]] = s
    ds = xr.Dataset(
        {
            "poincare": (("case", "point", "channel"), P),
            "response": (("case",), np.array([r["response"] for r in rows])),
            "distinct_points": (("case",), np.array([r["distinct_points"] for r in rows])),
        },
        coords={
            "case": [r["case"] for r in rows],
            out.parameter: (("case",), out.values),
            "channel": list(chans),
        },
        attrs={"parameter": out.parameter, "evidence": json.dumps([r["evidence"] for r in rows])},
    )
    ds["poincare"].attrs.update(long_name="stroboscopic Poincare points after the transient")
    files = [save_results(out_dir / "bifurcation.nc", {"bifurcation": ds})]
    csv = out_dir / "bifurcation.csv"
    with atomic_path(csv) as tmp:
        pd.DataFrame(rows).to_csv(tmp, index=False)
    files.append(csv)
    if figure:
        from clearance.plot.figures import save_figure
        from clearance.plot.nonlinear import bifurcation_figure

        fig = bifurcation_figure(
            out.values,
            out.points,
            parameter_name=out.parameter,
            channel=out.channel,
            kinds=out.kinds,
        )
        files += save_figure(fig, out_dir, "bifurcation", ("png",))
    return files
