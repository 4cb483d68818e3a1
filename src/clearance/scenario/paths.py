"""Addressing scenario fields by dotted path: get, set, override (the basis of studies).

A path is the dotted key path of the file: `mechanism.R_A`, `trajectory.amplitude.z`,
`clearance.joints.S_1.radial_clearance`, `clearance.joints.S_1.normal.restitution`,
`solver.rtol`; a list element is addressed as `mechanism.theta_deg[0]`. A path is valid if
the format allows it for this scenario (mechanism type, clearance joint names and law
names are taken from the document), whether or not the document writes the key out.

    d = scenario_to_dict(s)
    get_path(d, "clearance.joints.S_1.radial_clearance")        # 0.0003
    d2 = set_path(d, "clearance.joints.S_1.radial_clearance", 2e-4)   # a new dict
    s2 = with_overrides(s, {"solver.rtol": 1e-8, "mechanism.R_A": 0.45})  # validated

Setting one of a joint's exclusive radius fields (radial_clearance / socket_radius, or
radial_clearance / bearing_radius) removes the other from that joint.
"""

from __future__ import annotations

import copy
import dataclasses
import re
from collections.abc import Mapping

from clearance.model.contact_laws import law_name
from clearance.scenario.errors import MISSING, Problems, ScenarioError, did_you_mean
from clearance.scenario.general import (
    FUNCTION_TYPES,
    GENERAL_KEYS,
    SECTIONS,
    element_keys,
    parse_general,
)
from clearance.scenario.parallel import (
    ATTACH_KEYS,
    LEG_KEYS,
    LINK_KEYS,
    MECHANISM_KEYS,
    PLATFORM_KEYS,
    parse_parallel,
)
from clearance.scenario.schema import (
    CHECKS_FIELDS,
    CLEARANCE_FIELDS,
    CLEARANCE_KINDS,
    MATERIAL_FIELDS,
    MECHANISMS,
    OUTPUT_FIELDS,
    SCENARIO_FIELDS,
    SHAPE_TABLES,
    SOLVER_FIELDS,
    TOP_KEYS,
    TRAJECTORY_FIELDS,
    MechanismType,
    Scenario,
    general_kind,
    leg_groups,
    parallel_kind,
    scenario_from_dict,
)
from clearance.scenario.serialize import scenario_to_dict
from clearance.scenario.steady import STEADY_FIELDS
from clearance.scenario.trajectories import HARMONIC_KEYS
from clearance.scenario.view import VIEW_FIELDS
from clearance.scenario.wear import WEAR_FIELDS

__all__ = [
    "allowed_keys",
    "flat_joints",
    "get_path",
    "mechanism_kind",
    "set_path",
    "split_path",
    "with_overrides",
]

_SEGMENT = re.compile(r"^([^\[\]]+)((?:\[\d+\])*)$")


def split_path(path: str, *, source: str = "<path>") -> list[str | int]:
    """'a.b[1].c' -> ['a', 'b', 1, 'c']; ScenarioError for a malformed path."""
    if not isinstance(path, str) or not path:
        raise ScenarioError(source, str(path), path, "expected a dotted path such as 'solver.rtol'")
    out: list[str | int] = []
    for seg in path.split("."):
        m = _SEGMENT.match(seg.strip())
        if not m:
            raise ScenarioError(
                source, path, seg, "malformed path segment; expected name or name[index]"
            )
        out.append(m.group(1))
        out.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    return out


def _get(d: object, key: str) -> object:
    return d.get(key, MISSING) if isinstance(d, Mapping) else MISSING


def flat_joints(d: Mapping) -> dict[str, object]:
    """{joint name: table} of a scenario dict's [clearance.joints], a parallel mechanism's
    joints nested by leg ([clearance.joints.leg1.S]) named "leg1.S"."""
    joints = _get(_get(d, "clearance"), "joints")
    out: dict[str, object] = {}
    for k, v in (joints if isinstance(joints, Mapping) else {}).items():
        group = (
            isinstance(v, Mapping)
            and bool(v)
            and "kind" not in v
            and all(isinstance(x, Mapping) for x in v.values())
        )
        if group:
            out.update({f"{k}.{sub}": t for sub, t in v.items()})
        else:
            out[k] = v
    return out


def mechanism_kind(d: Mapping):
    """The MechanismKind of a scenario dict (None if its mechanism does not validate)."""
    return _mechanism_kind(d)


def _mechanism_kind(d: Mapping):
    """The MechanismKind of document d's mechanism.type, or None if it names none (or a
    parallel mechanism that does not validate)."""
    mech = _get(d, "mechanism")
    mtype = _get(mech, "type")
    if mtype not in [m.value for m in MechanismType]:
        return None
    if mtype == MechanismType.PARALLEL.value:
        problems = Problems("<paths>")
        pp = parse_parallel(mech, problems, default_name="mechanism", mobility=False)  # type: ignore[arg-type]
        return parallel_kind(pp) if pp is not None else None
    if mtype == MechanismType.GENERAL.value:
        problems = Problems("<paths>")
        gp = parse_general(mech, problems, default_name="mechanism")  # type: ignore[arg-type]
        return general_kind(gp) if gp is not None else None
    return MECHANISMS.get(MechanismType(mtype))


# keys of a parallel mechanism's [mechanism] below `mechanism` (list indices left out)
_PARALLEL_TABLES = {
    ("platform",): PLATFORM_KEYS,
    ("legs",): LEG_KEYS,
    ("legs", "base"): ATTACH_KEYS,
    ("legs", "platform"): ATTACH_KEYS,
    ("legs", "links"): LINK_KEYS,
    # a leg's joints, whatever its string: R, R1, R2, ...
    ("legs", "axes"): tuple(f"{c}{k}" for c in "RPCUS" for k in ("", "1", "2", "3")),
}


def _general_keys(mech: object, keys: list[str]) -> tuple[str, ...] | None:
    """Keys below [mechanism] of a general mechanism: element names, element fields, the
    fields of a time-function table."""
    if not keys or keys[0] not in SECTIONS:
        return None
    tables = _get(mech, keys[0])
    if len(keys) == 1:
        return tuple(tables) if isinstance(tables, Mapping) else ()
    t = _get(tables, keys[1])
    if len(keys) == 2:
        return element_keys(keys[0], _get(t, "type") if isinstance(t, Mapping) else None)
    if len(keys) == 3:  # a function field's table
        fn = _get(_get(t, keys[2]), "type")
        cls = FUNCTION_TYPES.get(fn) if isinstance(fn, str) else None
        if cls is None:
            return ("type",)
        return ("type", *(f.name for f in dataclasses.fields(cls) if f.init))
    return None


def allowed_keys(d: Mapping, keys: list[str], *, kind: object = MISSING) -> tuple[str, ...] | None:
    """Keys the format allows below the table at `keys` of document d (None: a leaf).
    kind: d's MechanismKind when the caller has it (else derived from d: for a parallel
    or general mechanism a validation of its [mechanism], ~40 ms)."""
    if kind is MISSING:
        kind = _mechanism_kind(d)
    mtype = _get(_get(d, "mechanism"), "type")
    parallel = mtype == MechanismType.PARALLEL.value
    general = mtype == MechanismType.GENERAL.value
    n = len(keys)
    if n == 0:
        return TOP_KEYS
    head = keys[0]
    if n == 1:
        if parallel or general:
            mech_keys = MECHANISM_KEYS if parallel else GENERAL_KEYS
        else:
            mech_keys = ("type", *(kind.params.spec() if kind else ()))
        sections = {
            "scenario": tuple(SCENARIO_FIELDS),
            "trajectory": (*TRAJECTORY_FIELDS, *SHAPE_TABLES),
            "clearance": (*CLEARANCE_FIELDS, "joints"),
            "solver": tuple(SOLVER_FIELDS),
            "output": tuple(OUTPUT_FIELDS),
            "checks": tuple(CHECKS_FIELDS),
            "steady_state": tuple(STEADY_FIELDS),
            "view": tuple(VIEW_FIELDS),
            "wear": (*WEAR_FIELDS, "update_factor"),
            "mechanism": mech_keys,
        }
        return sections.get(head)
    if head == "mechanism":
        if general:
            return _general_keys(_get(d, "mechanism"), keys[1:])
        return _PARALLEL_TABLES.get(tuple(keys[1:])) if parallel else None
    if head == "trajectory" and n >= 2:
        coords = kind.coordinates if kind else ()
        if n == 2 and keys[1] in ("amplitude", "periodic"):
            return coords
        if n == 2 and keys[1] in ("via_points", "table"):
            return ("t", *coords, *(("file",) if keys[1] == "table" else ()))
        if n == 3 and keys[1] == "periodic":
            return HARMONIC_KEYS
        return None
    if head != "clearance" or keys[1] != "joints":
        return None
    groups = leg_groups(kind)
    if n == 2:
        return (*kind.clearance_joints, *sorted(groups)) if kind else ()
    if keys[2] in groups and (kind is None or keys[2] not in kind.clearance_joints):
        # [clearance.joints.<leg>.<joint>]: the leg's joints, then as for "<leg>.<joint>"
        if n == 3:
            pre = keys[2] + "."
            return tuple(j[len(pre) :] for j in kind.clearance_joints if j.startswith(pre))
        keys = ["clearance", "joints", f"{keys[2]}.{keys[3]}", *keys[4:]]
        n = len(keys)
    spec = CLEARANCE_KINDS.get(kind.clearance_joints.get(keys[2], "")) if kind else None
    if spec is None:
        return None
    if n == 3:
        return ("kind", *spec.fields, *spec.tables)
    if n == 4 and keys[3] in spec.materials:
        return MATERIAL_FIELDS
    if n == 4 and keys[3] in spec.laws:
        registry, default = spec.laws[keys[3]]
        law = _get(_get(_joint_table(d, keys[2]), keys[3]), "law")
        name = law if isinstance(law, str) else law_name(default) if default else None
        cls = registry.get(name) if name else None
        return ("law", *(f.name for f in dataclasses.fields(cls) if f.init)) if cls else ("law",)
    return None


def _joint_table(d: Mapping, name: str) -> object:
    """The file table of clearance joint `name` ("leg1.S" also nested by leg)."""
    joints = _get(_get(d, "clearance"), "joints")
    t = _get(joints, name)
    if t is MISSING and "." in name:
        leg, sub = name.split(".", 1)
        t = _get(_get(joints, leg), sub)
    return t


def _check(d: Mapping, parts: list[str | int], path: str, source: str, value: object = MISSING):
    """Raise ScenarioError unless every name segment of `parts` is allowed by the format.
    The error names the path, the value to set (or the bad segment) and what is allowed.
    Returns d's MechanismKind (derived once, for every segment)."""
    keys: list[str] = []
    kind = _mechanism_kind(d)
    for p in parts:
        if isinstance(p, int):
            continue
        allowed = allowed_keys(d, keys, kind=kind)
        if allowed is None or p not in allowed:
            where = ".".join(keys) or "the top level"
            if allowed is None:
                msg = f"'{'.'.join(keys)}' is a value, not a table"
            else:
                msg = (
                    f"unknown key '{p}' in {where};{did_you_mean(p, allowed)} "
                    f"allowed: {', '.join(allowed)}"
                )
            raise ScenarioError(source, path, p if value is MISSING else value, msg)
        keys.append(p)
    return kind


def _radii(kind, parts: list) -> tuple[str, ...]:
    """The exclusive radius pair of the joint at clearance.joints.<J>.<field>, or ()."""
    if len(parts) not in (4, 5) or parts[:2] != ["clearance", "joints"]:
        return ()
    if kind is None:
        return ()
    name = parts[2] if len(parts) == 4 else f"{parts[2]}.{parts[3]}"  # (nested by leg)
    spec = CLEARANCE_KINDS.get(kind.clearance_joints.get(name, ""))
    return spec.radii if spec is not None and spec.radii is not None else ()


def get_path(d: Mapping, path: str, *, source: str = "<dict>") -> object:
    """The value at a dotted path of a scenario dict; ScenarioError if the path is not
    allowed by the format or not present in d."""
    parts = split_path(path, source=source)
    _check(d, parts, path, source)
    node: object = d
    for p in parts:
        if isinstance(p, int):
            if not isinstance(node, list) or not -len(node) <= p < len(node):
                raise ScenarioError(source, path, node, f"index {p} out of range or not a list")
            node = node[p]
            continue
        if not isinstance(node, Mapping) or p not in node:
            raise ScenarioError(source, path, MISSING, "allowed, but not set in this scenario")
        node = node[p]
    return node


def set_path(d: Mapping, path: str, value: object, *, source: str = "<dict>") -> dict:
    """A deep copy of d with `value` at `path` (tables created as needed). The path must be
    allowed by the format; the value is checked when the result is validated
    (`scenario_from_dict`)."""
    parts = split_path(path, source=source)
    kind = _check(d, parts, path, source, value)  # (a path below clearance.joints leaves
    out = copy.deepcopy(dict(d))  # the mechanism, so its kind, as it is)
    node: object = out
    for i, p in enumerate(parts):
        last = i == len(parts) - 1
        nxt = None if last else parts[i + 1]
        if isinstance(p, int):
            if not isinstance(node, list) or not -len(node) <= p < len(node):
                raise ScenarioError(source, path, node, f"index {p} out of range or not a list")
            if last:
                node[p] = value
            else:
                node = node[p]
            continue
        assert isinstance(node, dict)
        if last:
            node[p] = value
            radii = _radii(kind, parts)
            if p in radii:  # clearance.joints.<J>.<one of its radius fields>: drop the other
                node.pop(radii[1 - radii.index(p)], None)
        else:
            if p not in node:
                if isinstance(nxt, int):
                    raise ScenarioError(source, path, MISSING, f"no list '{p}' to index")
                node[p] = {}
            node = node[p]
    return out


def with_overrides(s: Scenario, overrides: Mapping[str, object]) -> Scenario:
    """A validated copy of scenario s with values set at dotted paths. All path problems
    are reported together, then the values are validated like a file."""
    d = scenario_to_dict(s)
    problems = []
    for path, value in overrides.items():
        try:
            d = set_path(d, path, value, source=s.source)
        except ScenarioError as e:
            problems.append(e)
    if problems:
        raise ScenarioError.from_problems(problems)
    tag = " (overrides)"  # (once, however often overrides are applied)
    return scenario_from_dict(d, source=s.source if s.source.endswith(tag) else s.source + tag)
