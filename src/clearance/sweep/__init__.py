"""Parameter studies on Dask: study files, runs (local, cluster, serial), collect.

    study = load_study("study.toml")           # validated; every case's scenario checked
    report = run_study(study)                   # LocalCluster; or scheduler="tcp://..."/"serial"
    out = collect_study(study.folder)           # one dataset with a `case` dimension + table

Formats and semantics: docs/sweeps.md.
"""

from clearance.sweep.collect import CollectOutput, collect_study
from clearance.sweep.metrics import METRICS, CaseData, Metric, compute_metrics
from clearance.sweep.run import StudyReport, run_case, run_study
from clearance.sweep.study import (
    Case,
    Parameter,
    Sampling,
    Study,
    StudyError,
    case_scenario_dict,
    load_study,
    loads_study,
    study_from_dict,
)

__all__ = [
    "METRICS",
    "Case",
    "CaseData",
    "CollectOutput",
    "Metric",
    "Parameter",
    "Sampling",
    "Study",
    "StudyError",
    "StudyReport",
    "case_scenario_dict",
    "collect_study",
    "compute_metrics",
    "load_study",
    "loads_study",
    "run_case",
    "run_study",
    "study_from_dict",
]
