"""The dict form of a validated scenario: `scenario_to_dict(s)`, the inverse of
`scenario_from_dict`. Every default is written out, enums become their strings, tuples
become lists, law objects become {law = name, field = value} tables.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from enum import Enum

from clearance.model.contact_laws import FrictionContactLaw, NormalContactLaw, law_to_dict
from clearance.scenario.general import GeneralParams
from clearance.scenario.parallel import ParallelParams
from clearance.scenario.schema import AUTO, CLEARANCE_KINDS, Scenario
from clearance.scenario.view import ViewSpec

__all__ = ["law_dict", "nest_joints", "scenario_to_dict"]


def _plain(v: object) -> object:
    if isinstance(v, Enum):
        return v.value
    if isinstance(v, tuple):
        return [_plain(x) for x in v]
    return v


def law_dict(law: NormalContactLaw | FrictionContactLaw) -> dict[str, object]:
    """{law = name, field = value}: None fields are omitted when None is their default,
    written as "auto" otherwise (e.g. Impact(stiffness=None): Hertz from the materials)."""
    out: dict[str, object] = {}
    defaults = {f.name: f.default for f in dataclasses.fields(law)}
    for k, v in law_to_dict(law).items():
        if v is None:
            if defaults.get(k) is not None:
                out[k] = AUTO
        else:
            out[k] = _plain(v)
    return out


def _joint_dict(j: object, kind: str) -> dict[str, object]:
    """The file table of a joint's clearance of kind `kind` (schema.CLEARANCE_KINDS): its
    fields in the spec's order (of a radius pair only the one given; None values left out),
    law tables and material tables."""
    spec = CLEARANCE_KINDS[kind]
    out: dict[str, object] = {"kind": kind}
    for name in spec.fields:
        if spec.radii is not None and name in spec.radii and name != j.given:  # type: ignore[attr-defined]
            continue
        v = getattr(j, name)
        if v is not None:
            out[name] = _plain(v)
    for name in spec.laws:
        if getattr(j, name) is not None:
            out[name] = law_dict(getattr(j, name))
    for name in spec.materials:
        m = getattr(j, name)
        out[name] = {"E": m.E, "nu": m.nu}
    return out


def nest_joints(tables: Mapping[str, object]) -> dict[str, object]:
    """{joint name: table} as [clearance.joints] writes it: a parallel mechanism's
    "leg1.S" nested by leg ([clearance.joints.leg1.S]), so that paths below it
    (clearance.joints.leg1.S.radial_clearance) find it (`paths.flat_joints` undoes it)."""
    out: dict[str, object] = {}
    for n, table in tables.items():
        if "." in n:
            leg, sub = n.split(".", 1)
            out.setdefault(leg, {})[sub] = table  # type: ignore[index]
        else:
            out[n] = table
    return out


def scenario_to_dict(s: Scenario) -> dict[str, object]:
    """The complete, canonical dict of a scenario (every default written out)."""

    def fields_of(obj: object) -> dict[str, object]:
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}  # type: ignore[arg-type]

    params = s.mechanism.params
    if isinstance(params, (ParallelParams, GeneralParams)):
        mechanism = {"type": s.mechanism.type.value, **params.to_dict()}
    else:
        mechanism = {"type": s.mechanism.type.value, **fields_of(params)}
    tr = s.trajectory
    trajectory: dict[str, object] = {
        "shape": tr.shape.value,
        "duration": tr.duration,
        "period": tr.period,
    }
    if tr.harmonics is not None:  # periodic
        trajectory["periodic"] = {
            c: [{"amplitude": a, "period": p, "phase": ph} for a, p, ph in hs]
            for c, hs in tr.harmonics.items()
        }
    elif tr.samples is not None:  # via-points, table (a table's file: its columns inline)
        key = "table" if tr.shape.value == "table" else "via_points"
        trajectory[key] = {c: list(v) for c, v in tr.samples.items()}
    else:
        trajectory["amplitude"] = dict(tr.amplitude)
    for key in ("orientation", "sequence", "positions", "actuators"):  # (parallel, general)
        if getattr(tr, key) is not None:
            trajectory[key] = _plain(getattr(tr, key))
    kinds = s.mechanism.kind.clearance_joints
    joints = nest_joints({n: _joint_dict(j, kinds[n]) for n, j in s.clearance.joints.items()})
    doc = {
        "format_version": s.format_version,
        "scenario": fields_of(s.scenario),
        "mechanism": mechanism,
        "trajectory": trajectory,
        "clearance": {"initial": s.clearance.initial.value, "joints": joints},
        "solver": fields_of(s.solver),
        "output": fields_of(s.output),
        "checks": fields_of(s.checks),
    }
    if s.steady_state is not None:  # (periods: trajectory.duration / period)
        st = fields_of(s.steady_state)
        del st["periods"]
        if st["section"] is None:
            del st["section"]
        doc["steady_state"] = st
    if s.view != ViewSpec():
        doc["view"] = s.view.to_dict()
    if s.wear is not None:
        doc["wear"] = s.wear.to_dict()
    return doc
