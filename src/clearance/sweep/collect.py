"""Collect a study: one dataset with a `case` dimension, a summary table, summary plots.

    out = collect_study("studies/clearance_friction")
    out.table            # pandas DataFrame: one row per case, parameters and metrics
    out.dataset          # collected/<study>.nc: groups summary, ideal, clearance (dim `case`)

Writes into <folder>/collected/: `<study>.nc` (NetCDF4; group "summary" = the table, and one
group per run, "ideal" and "clearance", with every case's results concatenated along
`case`, parameters as `case` coordinates; samples missing in a shorter run are NaN),
`summary.parquet` and `summary.csv`, and `plots/<parameter>.png` (each metric against that
parameter, one line per combination of the other parameters when there are few).
Cases of the manifest that are not finished appear in the table with their status
(pending, running, failed and the reason) and no metrics; they are left out of the dataset.
Zarr output is not provided (zarr is not a dependency); NetCDF is read everywhere.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from clearance.sweep.metrics import METRICS, CaseData, compute_metrics, split_metric
from clearance.sweep.store import (
    FAILED,
    FINISHED,
    STALE_TMP,
    case_files,
    is_finished,
    read_json,
    read_manifest,
    remove_temporaries,
)
from clearance.sweep.study import Case

__all__ = ["CollectOutput", "collect_study", "plot_study", "study_table"]

COLLECTED = "collected"
PENDING = "pending"
MAX_LINES = 8  # more combinations of the other parameters than this: scatter, no lines


@dataclass
class CollectOutput:
    """What `collect_study` wrote: the table, its files, the dataset file, the plots, and
    the ids of the cases that are not finished."""

    folder: Path
    table: Any  # pandas.DataFrame
    parquet: Path
    csv: Path
    dataset: Path | None = None
    plots: list[Path] = field(default_factory=list)
    unfinished: list[str] = field(default_factory=list)


def _cell(v: object) -> object:
    """A table cell: scalars as they are, lists and tables as compact JSON text."""
    if isinstance(v, (list, dict)):
        return json.dumps(v, separators=(",", ":"))
    return v


def _cases(manifest: Mapping) -> list[Case]:
    return [Case(c["id"], c["index"], c["values"], c["overrides"]) for c in manifest["cases"]]


def study_table(folder: str | os.PathLike, *, metrics: Sequence[str] | None = None):
    """The summary table of a study folder (pandas DataFrame, one row per case).

    Columns: case, index, status, one per parameter (its name), one per metric, success
    (finished cases: both runs reached the final time; False: a run stopped early),
    plausibility (finished cases: "ok", "warning" or "implausible", the worse of the two
    runs, `clearance.analysis.plausibility`; "" for cases older than the check),
    attempts, reason, worker, result_file. metrics: default the study's; a metric missing from a
    finished case's sidecar (added to the registry later) is computed from its saved files.
    """
    import pandas as pd

    folder = Path(folder)
    man = read_manifest(folder)
    names = list(metrics) if metrics is not None else list(man["metrics"])
    params = [p["name"] for p in man["parameters"]]
    rows = []
    for c in _cases(man):
        nc, side = case_files(folder, c.id)
        s = read_json(side) or {}
        status = FINISHED if is_finished(folder, c) else str(s.get("status", PENDING))
        if status == FINISHED and not is_finished(folder, c):
            status = PENDING  # the sidecar says finished, but its result file is missing
        row: dict[str, object] = {"case": c.id, "index": c.index, "status": status}
        row.update({p: _cell(c.values[p]) for p in params})
        vals = dict(s.get("metrics", {})) if status == FINISHED else {}
        todo = [m for m in names if m not in vals]
        if status == FINISHED and todo:
            vals.update(compute_metrics(CaseData.from_files(nc, s), todo))
        row.update({m: float(vals.get(m, math.nan)) for m in names})
        row.update(
            success=bool(s.get("success", True)) if status == FINISHED else None,
            plausibility=_plausibility(s) if status == FINISHED else "",
            attempts=int(s.get("attempts", 0)),
            reason=str(s.get("reason", "")) if status != FINISHED else "",
            worker=str(s.get("worker", "")),
            result_file=nc.name if status == FINISHED else "",
        )
        rows.append(row)
    return pd.DataFrame(rows)


def _plausibility(sidecar: Mapping) -> str:
    """The worse plausibility status of a finished case's two runs ("" if not recorded)."""
    states = [
        sidecar.get("summary", {}).get(run, {}).get("plausibility", {}).get("status")
        for run in ("ideal", "clearance")
    ]
    for state in ("implausible", "warning", "ok"):
        if state in states:
            return state
    return ""


def _concat(ids: list[str], parts: list, params: Mapping[str, list]):
    """Datasets of the finished cases -> one, along `case`, parameters as coordinates."""
    import pandas as pd
    import xarray as xr

    # dimensions without an index whose size differs between cases (the contact event log)
    # get a position index, so that the outer join pads the shorter ones
    ragged = {
        d
        for d in set().union(*(p.dims for p in parts))
        if len({p.sizes.get(d, 0) for p in parts}) > 1 and not any(d in p.indexes for p in parts)
    }
    parts = [
        p.assign_coords({d: np.arange(p.sizes[d]) for d in ragged & set(p.dims)}) for p in parts
    ]
    fill = {
        k: "" if v.dtype.kind in "OSU" else xr.core.dtypes.NA
        for p in parts
        for k, v in p.variables.items()
    }
    ds = xr.concat(
        parts,
        dim=pd.Index(ids, name="case"),
        data_vars="all",
        coords="different",
        compat="equals",
        join="outer",
        combine_attrs="drop_conflicts",
        fill_value=fill,
    )
    return ds.assign_coords({name: ("case", vals) for name, vals in params.items()})


def _dataset(folder: Path, man: Mapping, table, variables: Sequence[str] | None) -> Path | None:
    import xarray as xr

    from clearance.io.dataset import load_results, save_results

    done = table[table["status"] == FINISHED]
    if done.empty:
        return None
    ids = list(done["case"])
    groups: dict[str, list] = {}
    for cid in ids:
        data = load_results(case_files(folder, cid)[0])
        for g, ds in data.items():
            if variables is not None:
                ds = ds[[v for v in variables if v in ds.data_vars]]
            groups.setdefault(g, []).append(ds)
    params = {p["name"]: list(done[p["name"]]) for p in man["parameters"]}
    out = {"summary": xr.Dataset.from_dataframe(table.set_index("case"))}
    for g, parts in groups.items():
        if len(parts) == len(ids):
            out[g] = _concat(ids, parts, params)
    for name in man["metrics"]:
        base, _ = split_metric(name)
        if name in out["summary"] and base in METRICS:
            out["summary"][name].attrs.update(units=METRICS[base].unit, long_name=METRICS[base].doc)
    attrs = {
        "study": man["name"],
        "study_description": man.get("description", ""),
        "study_parameters": json.dumps(man["parameters"]),
        "study_metrics": json.dumps(man["metrics"]),
        "base_scenario": (folder / "base_scenario.toml").read_text(encoding="utf-8"),
    }
    return save_results(folder / COLLECTED / f"{man['name']}.nc", out, attrs=attrs)


def _numeric(values: Sequence[object]) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "parameter"


def parameter_unit(path: str) -> str:
    """The unit of a scenario field by its dotted path's last name ("radial_clearance" ->
    "m"), "" when unknown or ambiguous."""
    from clearance.scenario import schema
    from clearance.scenario.fields import Field

    units = set()
    name = path.rsplit(".", 1)[-1]
    for table in vars(schema).values():
        if isinstance(table, dict) and isinstance(table.get(name), Field):
            units.add(table[name].unit)
    return units.pop() if len(units) == 1 else ""


def _positions(rows, name: str, numeric: bool, cats: list[str]) -> np.ndarray:
    """x positions of table rows against parameter `name` (category index if not numeric)."""
    vals = list(rows[name])
    return np.asarray(vals if numeric else [cats.index(str(v)) for v in vals], dtype=float)


def _mark_failed(ax, x: np.ndarray) -> None:
    """Failed cases (no values) at their parameter values x: red x on the lower edge."""
    if x.size == 0:
        return
    tr = ax.get_xaxis_transform()  # x in data, y in axes fraction
    ax.plot(
        x,
        np.full(x.size, 0.03),
        linestyle="none",
        marker="x",
        color="C3",
        label="failed",
        transform=tr,
        clip_on=False,
    )


def plot_study(table, man: Mapping, out_dir: str | os.PathLike, *, fmt: str = "png") -> list[Path]:
    """One figure per varied parameter: a panel per metric against that parameter, one line
    per combination of the other parameters (at most MAX_LINES, else points only). Axes
    carry units; failed cases (no values) are marked with a red x on the lower edge, and
    the values of cases whose runs stopped early are circled in red."""
    from matplotlib.figure import Figure

    from clearance.plot.figures import save_figure

    failed = table[table["status"] == FAILED]
    stopped = table[(table["status"] == FINISHED) & (table.get("success") == False)]  # noqa: E712
    done = table[table["status"] == FINISHED]
    metrics = [m for m in man["metrics"] if m in done]
    if done.empty or not metrics:
        return []
    files = []
    for p in man["parameters"]:
        name = p["name"]
        others = [q["name"] for q in man["parameters"] if q["name"] != name]
        xs_all = list(done[name])
        numeric = _numeric(xs_all)
        cats = sorted({str(x) for x in xs_all + list(failed[name])})
        groups = list(done.groupby(others, sort=True)) if others else [((), done)]
        lines = len(groups) <= MAX_LINES
        ncol = min(3, len(metrics))
        nrow = math.ceil(len(metrics) / ncol)
        fig = Figure(figsize=(3.6 * ncol, 2.7 * nrow + 0.4), layout="constrained")
        axes = fig.subplots(nrow, ncol, squeeze=False).ravel()
        for ax, m in zip(axes, metrics, strict=False):
            for k, (key, g) in enumerate(groups):
                x = np.asarray(
                    g[name] if numeric else [cats.index(str(v)) for v in g[name]], dtype=float
                )
                y = np.asarray(g[m], dtype=float)
                order = np.argsort(x, kind="stable")
                key = key if isinstance(key, tuple) else (key,)
                label = ", ".join(
                    f"{o.rsplit('.', 1)[-1]}={v}" for o, v in zip(others, key, strict=True)
                )
                style = {"marker": "o", "markersize": 3.5, "color": f"C{k % 10}"}
                if lines:
                    ax.plot(x[order], y[order], label=label or None, **style)
                else:
                    ax.plot(x, y, linestyle="none", **style)
            base, joint = split_metric(m)
            unit = METRICS[base].unit if base in METRICS else ""
            ax.set_ylabel(f"{m} [{unit}]" if unit and unit != "1" else m)
            short = name.rsplit(".", 1)[-1] if "." in name else name
            xu = parameter_unit(name)
            ax.set_xlabel(f"{short} [{xu}]" if xu and xu != "1" else short)
            _mark_failed(ax, _positions(failed, name, numeric, cats))
            if not stopped.empty:
                ax.plot(
                    _positions(stopped, name, numeric, cats),
                    np.asarray(stopped[m], dtype=float),
                    linestyle="none",
                    marker="o",
                    markersize=8,
                    mfc="none",
                    color="C3",
                    label="stopped early",
                )
            if p.get("scale") == "log" and numeric:
                ax.set_xscale("log")
            if not numeric:
                ax.set_xticks(range(len(cats)), cats, rotation=30, fontsize="small")
            ax.grid(True, alpha=0.3)
        for ax in axes[len(metrics) :]:
            ax.set_visible(False)
        if (lines and others) or not failed.empty or not stopped.empty:
            axes[0].legend(fontsize="x-small")
        fig.suptitle(f"study '{man['name']}': metrics against {name}", fontsize="medium")
        files += save_figure(fig, out_dir, _safe(name), (fmt,))
    return files


def collect_study(
    folder: str | os.PathLike,
    *,
    metrics: Sequence[str] | None = None,
    variables: Sequence[str] | None = None,
    dataset: bool = True,
    plots: bool = True,
) -> CollectOutput:
    """Merge the cases of a study folder into one dataset, a summary table and plots.

    metrics: columns of the table (default: the study's). variables: data variables kept
    in the merged dataset (default: all; large studies may want e.g. ["contact_force",
    "position"]). dataset / plots: write the merged dataset / the plots.
    """
    from clearance.io.files import atomic_path

    folder = Path(folder)
    man = read_manifest(folder)
    remove_temporaries(folder, older_than=STALE_TMP)  # left half-written by a killed run
    if metrics is not None:
        man = {**man, "metrics": list(metrics)}
    table = study_table(folder, metrics=man["metrics"])
    out_dir = folder / COLLECTED
    out_dir.mkdir(parents=True, exist_ok=True)
    parquet, csv = out_dir / "summary.parquet", out_dir / "summary.csv"
    with atomic_path(parquet) as tmp:
        table.to_parquet(tmp, index=False)
    with atomic_path(csv) as tmp:
        table.to_csv(tmp, index=False)
    res = CollectOutput(folder, table, parquet, csv)
    res.unfinished = list(table.loc[table["status"] != FINISHED, "case"])
    if dataset:
        res.dataset = _dataset(folder, man, table, variables)
    if plots:
        res.plots = plot_study(table, man, out_dir / "plots")
    return res
