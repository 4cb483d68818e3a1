"""Study files: a base scenario, the parameters to vary, the metrics to extract.

A study file (TOML, docs/sweeps.md) names a base scenario, fixed overrides (`[set]`), the
parameters to vary by their dotted scenario paths (`[[parameter]]`) and the scalar metrics
per case:

    format_version = 1

    [study]
    name = "clearance_friction"
    base = "ups_upu"                  # a shipped scenario, or a file relative to this one
    metrics = ["peak_contact_force", "impacts", "deviation_position"]

    [set]
    trajectory.duration = 0.2

    [[parameter]]
    path = "clearance.joints.S_1.radial_clearance"
    range = { start = 1e-4, stop = 5e-4, num = 3 }

    [[parameter]]
    path = ["clearance.joints.S_1.friction.mu_c", "clearance.joints.S_3.friction.mu_c"]
    values = [0.05, 0.15]

Parameters combine as a full-factorial grid; parameters sharing a `zip` label are paired;
`sample = {min, max, scale}` parameters are drawn together (`[sampling]`: Latin hypercube
or uniform random, n points, seed) and form one factor of the grid. `load_study` checks
everything (the study's fields, every parameter path and every case's scenario) and
raises one `StudyError` listing every problem before anything runs.

Each case is a plain dict of overrides (path -> value) with a stable id, the hash of those
overrides, so that resumption does not depend on the order of cases.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from clearance.scenario.errors import MISSING, Problems, ScenarioError
from clearance.scenario.paths import flat_joints, mechanism_kind, set_path, split_path
from clearance.scenario.schema import scenario_from_dict
from clearance.scenario.serialize import nest_joints, scenario_to_dict
from clearance.scenario.toml_io import default_scenarios, load_scenario, read_toml
from clearance.sweep.design import (
    Parameter,
    Sampling,
    canonical_json,
    case_values,
    parse_parameter,
    parse_sampling,
)
from clearance.sweep.metrics import METRICS, check_metric

__all__ = [
    "STUDY_FORMAT_VERSION",
    "Case",
    "Parameter",
    "Sampling",
    "Study",
    "StudyError",
    "case_id",
    "case_scenario_dict",
    "example_study_path",
    "load_study",
    "loads_study",
    "study_from_dict",
]

STUDY_FORMAT_VERSION = 1
TOP_KEYS = ("format_version", "study", "set", "parameter", "sampling")
STUDY_KEYS = ("name", "description", "base", "folder", "metrics", "joint_template")
JOINT_SET_PATH = "clearance.joints"  # values: lists of joint names (the set with clearance)
# fields a study may not set: the study decides where and what each case writes
RESERVED = ("scenario", "output", "format_version")
MAX_REPORTED = 25  # problems listed in one StudyError (the rest are counted)


class StudyError(ScenarioError):
    """An invalid study: file, field (a study field or a scenario path), value, allowed."""


@dataclass(frozen=True)
class Case:
    """One simulation of a study: `values` (parameter name -> value), `overrides` (scenario
    path -> value, what the task applies to the base) and the stable `id`."""

    id: str
    index: int
    values: dict
    overrides: dict

    def label(self) -> str:
        """'radial_clearance=0.0003, mu_c=0.05': short names (last path segment)."""
        return ", ".join(f"{_short(k)}={_fmt(v)}" for k, v in self.values.items())


@dataclass(frozen=True)
class Study:
    """A validated study. base: the canonical dict of the base scenario with [set] applied
    (what every case starts from); folder: where cases are written (absolute)."""

    name: str
    base: dict
    parameters: tuple[Parameter, ...]
    cases: tuple[Case, ...]
    metrics: tuple[str, ...]
    folder: Path
    description: str = ""
    base_name: str = ""
    fixed: dict = field(default_factory=dict)
    sampling: Sampling | None = None
    joint_template: str | None = None
    source: str = "<dict>"
    document: dict = field(default_factory=dict, repr=False)

    @property
    def base_sha(self) -> str:
        """sha256 of the base scenario (canonical JSON): a folder holds one base only."""
        return hashlib.sha256(canonical_json(self.base).encode()).hexdigest()

    def manifest(self) -> dict:
        """Plain description stored in the study folder (study.json)."""
        return {
            "study_format_version": STUDY_FORMAT_VERSION,
            "name": self.name,
            "description": self.description,
            "source": self.source,
            "base_name": self.base_name,
            "base_sha256": self.base_sha,
            "fixed": self.fixed,
            "joint_template": self.joint_template,
            "metrics": list(self.metrics),
            "parameters": [
                {"name": p.name, "paths": list(p.paths), "scale": p.scale, "zip": p.zip}
                for p in self.parameters
            ],
            "sampling": None if self.sampling is None else vars(self.sampling),
            "cases": [
                {"id": c.id, "index": c.index, "values": c.values, "overrides": c.overrides}
                for c in self.cases
            ],
        }


# --------------------------------------------------------------------------- helpers


def _short(path: str) -> str:
    return path.rsplit(".", 1)[-1]


def _fmt(v: object) -> str:
    return f"{v:.4g}" if isinstance(v, float) else json.dumps(v) if not isinstance(v, str) else v


def case_id(overrides: Mapping[str, object]) -> str:
    """Stable id of a case: 'c' + 12 hex digits of the sha256 of its overrides."""
    return "c" + hashlib.sha256(canonical_json(dict(overrides)).encode()).hexdigest()[:12]


def _depth(path: str) -> int:
    try:
        return len(split_path(path))
    except ScenarioError:
        return 0


def _joint_tables(base: Mapping, names: Sequence, template: str | None, source: str) -> dict:
    """{joint: table} for a joint set: the base's table of that joint, else the template's."""
    joints = flat_joints(base)
    out: dict = {}
    for name in names:
        if name in joints:
            out[name] = joints[name]
        elif template is not None and template in joints:
            out[name] = joints[template]
        else:
            raise ScenarioError(
                source,
                JOINT_SET_PATH,
                list(names),
                f"joint '{name}' is not in the base scenario and no joint_template is set",
            )
    return nest_joints(out)  # (as the scenario dict writes them: paths below them)


def case_scenario_dict(
    base: Mapping,
    overrides: Mapping[str, object],
    *,
    joint_template: str | None = None,
    source: str = "<study>",
) -> dict:
    """The scenario dict of a case: `base` with every override set (plain data in and out).

    Shorter paths are applied first (a joint set before the fields of its joints). A value
    of `clearance.joints` that is a list of joint names means "these joints have
    clearance": each gets its table from the base, else from `joint_template`.
    ScenarioError for a path the format does not allow.
    """
    d = dict(base)
    for path in sorted(overrides, key=_depth):
        value = overrides[path]
        if path == JOINT_SET_PATH and isinstance(value, list):
            value = _joint_tables(base, value, joint_template, source)
        d = set_path(d, path, value, source=source)
    return d


def _flatten(t: Mapping, prefix: str = "") -> dict[str, object]:
    """[set] table -> {dotted path: value}: nested tables are walked down to their leaves;
    a quoted key containing dots is a full path whose value is used as is."""
    out: dict[str, object] = {}
    for k, v in t.items():
        path = f"{prefix}.{k}" if prefix else k
        if isinstance(v, Mapping) and "." not in k:
            out.update(_flatten(v, path))
        else:
            out[path] = v
    return out


def _shipped() -> tuple[str, ...]:
    """Shipped scenario names: clearance/data's and the library's (studies live apart, in
    clearance/data/studies/)."""
    from clearance.scenario.toml_io import library

    return tuple(dict.fromkeys((*default_scenarios(), *library())))


def example_study_path() -> Path:
    """Path of the shipped example study (clearance/data/studies/example.toml)."""
    import importlib.resources

    return Path(
        os.fspath(importlib.resources.files("clearance") / "data" / "studies" / "example.toml")
    )


def _resolve_base(base: object, root: Path | None, problems: Problems) -> tuple[dict, str] | None:
    """The base scenario as a canonical dict: a shipped name or a file (relative to root)."""
    from clearance.scenario.toml_io import default_scenario_path, library_path

    if not isinstance(base, str) or not base.strip():
        shipped = ", ".join(_shipped())
        problems.add("study.base", base, f"required: a scenario file or a shipped name ({shipped})")
        return None
    p = Path(base).expanduser()
    if not p.is_absolute() and root is not None:
        p = root / p
    if not p.is_file() and base in _shipped():
        p = default_scenario_path(base) if base in default_scenarios() else library_path(base)
    if not p.is_file():
        shipped = ", ".join(_shipped())
        problems.add("study.base", base, f"no such scenario file; shipped scenarios: {shipped}")
        return None
    try:
        s = load_scenario(p)
    except ScenarioError as e:
        problems.items.extend(e.problems)
        return None
    return scenario_to_dict(s), str(p)


def _check_path(
    base: dict, path: str, value: object, where: str, problems: Problems, *, shown: object
) -> bool:
    """Is `path` a scenario path a study may set? If not, report `shown` at `where`."""
    try:
        head = split_path(path, source=problems.file)[0]
    except ScenarioError as e:
        problems.add(where, shown, e.allowed)
        return False
    if head in RESERVED:
        problems.add(where, shown, f"'{head}' fields are set by the study, not varied")
        return False
    try:
        set_path(base, path, value, source=problems.file)
    except ScenarioError as e:
        problems.add(where, shown, f"not a scenario path: {e.allowed}")
        return False
    return True


def _report(problems: Problems) -> None:
    if not problems:
        return
    items = problems.items
    if len(items) > MAX_REPORTED:
        more = len(items) - MAX_REPORTED
        items = [*items[:MAX_REPORTED], ScenarioError(problems.file, "...", more, "more problems")]
    raise StudyError.from_problems(items)


def study_from_dict(
    d: Mapping, *, source: str = "<dict>", root: str | os.PathLike | None = None
) -> Study:
    """Validate a study dict (as read from TOML) and generate its cases.

    root: folder against which a relative `study.base` is resolved (the study file's folder).
    Raises StudyError listing every problem: the study's own fields, unknown scenario paths,
    and every case whose scenario is invalid (field, value, allowed, which case).
    """
    problems = Problems(source)
    if not isinstance(d, Mapping):
        raise StudyError(source, "(document)", d, "expected a table")
    version = d.get("format_version", MISSING)
    if version is MISSING or isinstance(version, bool) or version != STUDY_FORMAT_VERSION:
        problems.add("format_version", version, f"required: {STUDY_FORMAT_VERSION}")
    for k, v in d.items():
        if k not in TOP_KEYS:
            problems.unknown(k, k, v, TOP_KEYS)
    st = d.get("study", MISSING)
    if not isinstance(st, Mapping):
        problems.add("study", st, "required table [study] (name, base, ...)")
        st = {}
    for k, v in st.items():
        if k not in STUDY_KEYS:
            problems.unknown(f"study.{k}", k, v, STUDY_KEYS)
    name = st.get("name", MISSING)
    if not isinstance(name, str) or not name.strip() or "/" in name:
        problems.add("study.name", name, "required: a non-empty name without '/'")
    description = st.get("description", "")
    if not isinstance(description, str):
        problems.add("study.description", description, "expected a string")
    folder = st.get("folder", f"studies/{name}")
    if not isinstance(folder, str) or not folder.strip():
        problems.add("study.folder", folder, "expected a folder path (string)")
    root_p = Path(root) if root is not None else None
    got = _resolve_base(st.get("base", MISSING), root_p, problems)
    base, base_name = got if got is not None else (None, "")

    # fixed overrides
    fixed_t = d.get("set", {})
    fixed: dict[str, object] = {}
    if not isinstance(fixed_t, Mapping):
        problems.add("set", fixed_t, "expected a table of path = value")
    else:
        fixed = _flatten(fixed_t)
    if base is not None:
        ok = all(_check_path(base, p, v, f"set.{p}", problems, shown=v) for p, v in fixed.items())
        if ok:
            try:
                base = scenario_to_dict(
                    scenario_from_dict(case_scenario_dict(base, fixed), source=f"{source} [set]")
                )
            except ScenarioError as e:
                for p in e.problems:
                    problems.add(f"set.{p.field}", p.value, p.allowed)
                base = None

    # parameters and sampling
    raw_params = d.get("parameter", [])
    if not isinstance(raw_params, list):
        problems.add("parameter", raw_params, "expected [[parameter]] tables")
        raw_params = []
    if not raw_params:
        problems.add("parameter", MISSING, "at least one [[parameter]] is required")
    params = [q for i, t in enumerate(raw_params) if (q := parse_parameter(t, i, problems))]
    names = [q.name for q in params]
    for q in params:
        if names.count(q.name) > 1:
            problems.add(f"parameter[{names.index(q.name)}].name", q.name, "name used twice")
            break
    all_paths = [p for q in params for p in q.paths]
    for p in set(all_paths):
        if all_paths.count(p) > 1 or p in fixed:
            problems.add("parameter", p, "path set by two parameters (or also in [set])")
    sampling = parse_sampling(d["sampling"], problems) if "sampling" in d else None
    has_sampled = any(q.sample is not None for q in params)
    if has_sampled and "sampling" not in d:
        problems.add("sampling", MISSING, "required with sampled parameters: {method, n, seed}")
    if not has_sampled and "sampling" in d:
        problems.add("sampling", d["sampling"], "no parameter has sample = {min, max}")

    # metrics and the joint template
    kind = mechanism_kind(base) if base else None
    joints = tuple(kind.clearance_joints) if kind is not None else ()
    metrics = st.get("metrics", list(METRICS))
    if not isinstance(metrics, list) or not metrics:
        problems.add("study.metrics", metrics, f"a non-empty list; allowed: {', '.join(METRICS)}")
        metrics = []
    for i, m in enumerate(metrics):
        msg = check_metric(m, joints)
        if msg:
            problems.add(f"study.metrics[{i}]", m, msg)
    template = st.get("joint_template")
    base_joints = list(flat_joints(base or {}))
    if template is not None and base is not None and template not in base_joints:
        problems.add("study.joint_template", template, f"a joint of the base: {base_joints}")
    template = template if template is not None else (base_joints[0] if base_joints else None)

    if base is not None:
        for i, q in enumerate(params):
            first = q.values[0] if q.values else q.sample[0]  # type: ignore[index]
            if q.paths == (JOINT_SET_PATH,) and isinstance(first, list):
                first = {}
            for p in q.paths:
                _check_path(base, p, first, f"parameter[{i}].path", problems, shown=p)
    _report(problems)

    values = case_values(params, sampling, problems)
    _report(problems)
    cases = []
    for i, vals in enumerate(values):
        over = {p: vals[q.name] for q in params for p in q.paths}
        cases.append(Case(case_id(over), i, vals, over))
    _validate_cases(base, cases, template, source, problems)  # type: ignore[arg-type]
    ids = [c.id for c in cases]
    if len(set(ids)) != len(ids):
        problems.add("parameter", len(ids) - len(set(ids)), "cases repeat (identical overrides)")
    _report(problems)
    return Study(
        name=name.strip(),
        base=base,  # type: ignore[arg-type]
        parameters=tuple(params),
        cases=tuple(cases),
        metrics=tuple(metrics),
        folder=Path(folder).expanduser().resolve(),
        description=description,
        base_name=base_name,
        fixed=fixed,
        sampling=sampling,
        joint_template=template,
        source=source,
        document=dict(d),
    )


def _validate_cases(
    base: dict, cases: Sequence[Case], template: str | None, source: str, problems: Problems
) -> None:
    """Build and validate every case's scenario; report each distinct problem once, naming
    the scenario field, the value and the first case that has it."""
    seen: set[tuple] = set()
    for c in cases:
        try:
            d = case_scenario_dict(base, c.overrides, joint_template=template, source=source)
            scenario_from_dict(d, source=source)
        except ScenarioError as e:
            for p in e.problems:
                key = (p.field, repr(p.value), p.allowed)
                if key not in seen:
                    seen.add(key)
                    problems.add(p.field, p.value, f"{p.allowed} (case {c.index}: {c.label()})")


def loads_study(
    text: str, *, source: str = "<string>", root: str | os.PathLike | None = None
) -> Study:
    """Validate a study given as TOML text (relative `base` files against `root`)."""
    from clearance.scenario.toml_io import _loads

    return study_from_dict(_loads(text, source), source=source, root=root)


def load_study(path: str | os.PathLike) -> Study:
    """Read and validate a study file. One StudyError lists every problem, those of the
    base scenario file included (named with that file). Nothing is written."""
    p = Path(path)
    try:
        d = read_toml(p)
    except ScenarioError as e:
        raise StudyError.from_problems(e.problems) from None
    return study_from_dict(d, source=str(p), root=p.parent)
