"""The dict form of a validated scenario: `scenario_to_dict(s)`, the inverse of
`scenario_from_dict`. Every default is written out, enums become their strings, tuples
become lists, law objects become {law = name, field = value} tables.
"""

from __future__ import annotations

import dataclasses
from enum import Enum

from clearance.model.clearance import Clearance
from clearance.model.contact_laws import FrictionContactLaw, NormalContactLaw, law_to_dict
from clearance.scenario.schema import AUTO, Scenario

__all__ = ["law_dict", "scenario_to_dict"]


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


def _joint_dict(j: Clearance) -> dict[str, object]:
    out: dict[str, object] = {"ball_radius": j.ball_radius, j.given: getattr(j, j.given)}
    out.update(socket=j.socket, velocity_floor=j.velocity_floor, onset_tolerance=j.onset_tolerance)
    out["normal"] = law_dict(j.normal)
    out["friction"] = law_dict(j.friction)
    for key in ("ball_material", "socket_material"):
        m = getattr(j, key)
        out[key] = {"E": m.E, "nu": m.nu}
    return out


def scenario_to_dict(s: Scenario) -> dict[str, object]:
    """The complete, canonical dict of a scenario (every default written out)."""

    def fields_of(obj: object) -> dict[str, object]:
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}  # type: ignore[arg-type]

    return {
        "format_version": s.format_version,
        "scenario": fields_of(s.scenario),
        "mechanism": {"type": s.mechanism.type.value, **fields_of(s.mechanism.params)},
        "trajectory": {
            "shape": s.trajectory.shape.value,
            "duration": s.trajectory.duration,
            "period": s.trajectory.period,
            "amplitude": dict(s.trajectory.amplitude),
        },
        "clearance": {
            "initial": s.clearance.initial.value,
            "joints": {n: _joint_dict(j) for n, j in s.clearance.joints.items()},
        },
        "solver": fields_of(s.solver),
        "output": fields_of(s.output),
    }
