"""Scalar metrics of one case: a registry name -> `Metric` (function, unit, description).

A metric function takes a `CaseData` (the run's summary, timings, energy series and, when
needed, the saved datasets) and an optional joint name, and returns a float. The same
function works on a fresh `RunOutput` (`CaseData.from_run`, on the worker) and on a saved
case (`CaseData.from_files`, in `collect`), so a metric added later can be computed for
finished cases without simulating again.

In a study, `"peak_contact_force"` is the largest over the case's clearance joints and
`"peak_contact_force@S_1"` the value of joint S_1 (NaN if S_1 has no clearance in that
case). Per-joint metrics aggregate over the joints as their `aggregate` says (max or sum;
0 when the case has no clearance joint). Platform deviations are RMS over the samples after
`clearance.pipeline.SKIP_SETTLING`; NaN if the run is shorter than that.

Adding a metric: one function `def _my_metric(case: CaseData, joint: str | None) -> float`
and one entry `"my_metric": Metric(_my_metric, "unit", "what it is")` in `METRICS`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from clearance.scenario.errors import did_you_mean

__all__ = ["METRICS", "CaseData", "Metric", "check_metric", "compute_metrics", "split_metric"]


@dataclass(frozen=True)
class CaseData:
    """What a metric sees of one case.

    summary: `clearance.pipeline.summarize` dict (joints, deviation_rms, ideal, clearance);
    timings: the run's timings [s] (total: the whole case on the worker);
    energy(run, term): an energy series [J] of run "ideal" or "clearance" (physics.md j);
    datasets(): {"ideal": Dataset, "clearance": Dataset}, loaded on first use.
    """

    summary: Mapping[str, Any]
    timings: Mapping[str, float]
    _energy: Callable[[str, str], np.ndarray] = field(repr=False)
    _datasets: Callable[[], Mapping[str, Any]] = field(repr=False)

    def energy(self, run: str, term: str) -> np.ndarray:
        return self._energy(run, term)

    def datasets(self) -> Mapping[str, Any]:
        return self._datasets()

    @classmethod
    def from_run(cls, out: Any) -> CaseData:
        """From a `clearance.pipeline.RunOutput` (on the worker, before anything is read)."""
        runs = {"ideal": out.ideal, "clearance": out.clearance}

        @functools.cache
        def datasets() -> Mapping[str, Any]:
            from clearance.io.dataset import result_to_dataset

            return {k: result_to_dataset(r) for k, r in runs.items()}

        return cls(
            out.summary, dict(out.timings), lambda run, term: runs[run].energy[term], datasets
        )

    @classmethod
    def from_files(cls, result_file: str | Path, sidecar: Mapping[str, Any]) -> CaseData:
        """From a finished case: its sidecar (summary, timings) and its NetCDF file."""

        @functools.cache
        def datasets() -> Mapping[str, Any]:
            from clearance.io.dataset import load_results

            return load_results(result_file)

        def energy(run: str, term: str) -> np.ndarray:
            return np.asarray(datasets()[run][f"energy_{term}"].values)

        return cls(sidecar["summary"], sidecar.get("timings", {}), energy, datasets)


@dataclass(frozen=True)
class Metric:
    """func(case, joint) -> float; unit (SI); doc. per_joint: accepts '@JOINT' and then
    aggregates over the case's clearance joints with `aggregate` ("max" or "sum")."""

    func: Callable[[CaseData, str | None], float]
    unit: str
    doc: str
    per_joint: bool = False
    aggregate: str = "max"


# --------------------------------------------------------------------------- functions


def _joint_value(key: str, aggregate: str) -> Callable[[CaseData, str | None], float]:
    def f(case: CaseData, joint: str | None) -> float:
        joints = case.summary.get("joints", {})
        if joint is not None:
            return float(joints[joint][key]) if joint in joints else math.nan
        vals = [float(j[key]) for j in joints.values()]
        if not vals:
            return 0.0
        return float(sum(vals)) if aggregate == "sum" else float(max(vals))

    f.__name__ = f"_{key}"
    return f


def _deviation(key: str) -> Callable[[CaseData, str | None], float]:
    def f(case: CaseData, joint: str | None) -> float:
        return float(case.summary.get("deviation_rms", {}).get(key, math.nan))

    f.__name__ = f"_deviation_{key}"
    return f


def _energy_dissipated(case: CaseData, joint: str | None) -> float:
    """Normal-damping dissipation D_n + friction work D_t of the clearance run at its end."""
    total = 0.0
    for term in ("damping", "friction"):
        e = case.energy("clearance", term)
        total += float(e[-1]) if len(e) else 0.0
    return total


def _energy_residual(case: CaseData, joint: str | None) -> float:
    return float(case.summary["clearance"]["energy_residual_relative"])


def _wall_time(case: CaseData, joint: str | None) -> float:
    return float(case.timings.get("total", math.nan))


def _real_time_factor(case: CaseData, joint: str | None) -> float:
    return float(case.summary["clearance"]["real_time_factor"])


def _success(case: CaseData, joint: str | None) -> float:
    s = case.summary
    return float(s["ideal"]["status"] == 0 and s["clearance"]["status"] == 0)


METRICS: Mapping[str, Metric] = MappingProxyType(
    {
        "peak_contact_force": Metric(
            _joint_value("peak_contact_force", "max"), "N", "peak contact force", True
        ),
        "rms_contact_force": Metric(
            _joint_value("rms_contact_force", "max"),
            "N",
            "RMS contact force after the settling time",
            True,
        ),
        "impacts": Metric(
            _joint_value("impacts", "sum"), "1", "number of impacts (contact onsets)", True, "sum"
        ),
        "max_penetration": Metric(
            _joint_value("max_penetration", "max"), "m", "largest penetration depth", True
        ),
        "deviation_position": Metric(
            _deviation("position"), "m", "RMS platform position deviation from ideal"
        ),
        "deviation_velocity": Metric(
            _deviation("velocity"), "m s-1", "RMS platform velocity deviation from ideal"
        ),
        "deviation_acceleration": Metric(
            _deviation("acceleration"), "m s-2", "RMS platform acceleration deviation from ideal"
        ),
        "deviation_angular_velocity": Metric(
            _deviation("angular_velocity"),
            "rad s-1",
            "RMS platform angular velocity deviation from ideal",
        ),
        "deviation_angular_acceleration": Metric(
            _deviation("angular_acceleration"),
            "rad s-2",
            "RMS platform angular acceleration deviation from ideal",
        ),
        "energy_dissipated": Metric(
            _energy_dissipated, "J", "energy dissipated in contact (damping + friction)"
        ),
        "energy_residual": Metric(
            _energy_residual, "1", "energy balance residual / energy scale (clearance run)"
        ),
        "wall_time": Metric(_wall_time, "s", "wall time of the whole case on its worker"),
        "real_time_factor": Metric(
            _real_time_factor, "1", "simulated / wall time of the clearance run"
        ),
        "success": Metric(_success, "1", "1 if both runs reached t_end, else 0"),
    }
)


# --------------------------------------------------------------------------- use


def split_metric(name: str) -> tuple[str, str | None]:
    """'peak_contact_force@S_1' -> ('peak_contact_force', 'S_1'); 'impacts' -> ('impacts', None)."""
    base, _, joint = name.partition("@")
    return base, (joint or None)


def check_metric(name: object, joints: tuple[str, ...] = ()) -> str:
    """'' if `name` is a valid metric name (joints: the mechanism's spherical joints), else
    what is allowed."""
    if not isinstance(name, str):
        return f"expected a metric name; allowed: {', '.join(METRICS)}"
    base, joint = split_metric(name)
    if base not in METRICS:
        return f"unknown metric;{did_you_mean(base, METRICS)} allowed: {', '.join(METRICS)}"
    if "@" in name:
        if not METRICS[base].per_joint:
            per = [k for k, m in METRICS.items() if m.per_joint]
            return f"'{base}' is not per joint; '@JOINT' works with {', '.join(per)}"
        if joints and joint not in joints:
            return f"unknown joint '{joint}';{did_you_mean(joint, joints)} allowed: {joints}"
    return ""


def compute_metrics(case: CaseData, names: tuple[str, ...] | list[str]) -> dict[str, float]:
    """{name: value} of the requested metrics. A metric whose data the case lacks (a
    KeyError, e.g. an older summary without that entry) is NaN; other errors propagate."""
    out: dict[str, float] = {}
    for name in names:
        base, joint = split_metric(name)
        try:
            out[name] = float(METRICS[base].func(case, joint))
        except KeyError:
            out[name] = math.nan
    return out
