"""`[mechanism] type = "general"`: any mechanism, element by element, as in Python.

    [mechanism]
    type = "general"
    gravity = [0.0, 0.0, -9.81]
    platform = "slider"                 # the body whose motion the results report (and the
                                        # trajectory prescribes); default: the first body
    [mechanism.bodies.crank]            # cl.Body("crank", mass=..., ...)
    mass = 0.30
    inertia = [1e-4, 1e-4, 1e-4]
    position = [0.025, 0.0, 0.0]
    [mechanism.markers.O]               # cl.Marker("O", "ground", ...) / Marker.on_axis
    body = "ground"
    axis = [0.0, 0.0, 1.0]
    [mechanism.joints.R1]               # cl.Revolute("R1", "O", "crank_O")
    type = "revolute"
    marker_i = "O"
    marker_j = "crank_O"
    [mechanism.drivers.motor]           # cl.RevoluteDriver("motor", "R1", cl.Sinusoid(...))
    type = "revolute"
    joint = "R1"
    function = { type = "polynomial", coefficients = [0.0, 523.6] }

Every table is one element of the Python API, named by its key, with the constructor's
fields (a function field takes a number or a `{ type = ..., <fields> }` table: constant,
polynomial, sinusoid, ramp, tabulated); the element's own checks report at the file path
(`mechanism.bodies.crank.mass`), and so do references (`mechanism.joints.R1.marker_j`).
Elements are added section by section: bodies, markers, joints, drivers, forces.
Clearance joints stay in [clearance.joints.<joint>] (the ideal and the clearance runs
share the rest).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field

from clearance.model import (
    GROUND,
    Body,
    Cylindrical,
    DistanceDriver,
    Fixed,
    Marker,
    Mechanism,
    ModelError,
    OffsetDriver,
    OrientationDriver,
    PointForce,
    PositionDriver,
    Prismatic,
    PrismaticDriver,
    Revolute,
    RevoluteDriver,
    Spherical,
    SpringDamper,
    Torque,
    Universal,
    triad_from_axis,
)
from clearance.model.functions import Constant, Polynomial, Ramp, Sinusoid, Tabulated
from clearance.scenario.errors import MISSING, Problems, did_you_mean
from clearance.scenario.fields import plain

__all__ = [
    "DRIVER_TYPES",
    "FORCE_TYPES",
    "FUNCTION_TYPES",
    "GENERAL_KEYS",
    "GeneralParams",
    "JOINT_TYPES",
    "SECTIONS",
    "element_keys",
    "parse_general",
]

GENERAL_KEYS = (
    "type",
    "name",
    "gravity",
    "platform",
    "bodies",
    "markers",
    "joints",
    "drivers",
    "forces",
)
JOINT_TYPES = {
    "spherical": Spherical,
    "universal": Universal,
    "revolute": Revolute,
    "cylindrical": Cylindrical,
    "prismatic": Prismatic,
    "fixed": Fixed,
}
DRIVER_TYPES = {
    "prismatic": PrismaticDriver,
    "revolute": RevoluteDriver,
    "distance": DistanceDriver,
    "position": PositionDriver,
    "orientation": OrientationDriver,
    "offset": OffsetDriver,
}
FORCE_TYPES = {"point_force": PointForce, "torque": Torque, "spring_damper": SpringDamper}
FUNCTION_TYPES = {
    "constant": Constant,
    "polynomial": Polynomial,
    "sinusoid": Sinusoid,
    "ramp": Ramp,
    "tabulated": Tabulated,
}
# section -> (registry by `type`, or the one class)
SECTIONS = {
    "bodies": Body,
    "markers": Marker,
    "joints": JOINT_TYPES,
    "drivers": DRIVER_TYPES,
    "forces": FORCE_TYPES,
}
# fields that hold time functions (a number or a {type = ...} table); "angles": three
FUNCTION_FIELDS = ("function", "magnitude", "actuator", "slide")
_NOT_IN_FILES = {"inertia_variation"}  # (the lumped limbs' model: the builder makes it)


@dataclass(frozen=True)
class GeneralParams:
    """The validated [mechanism] of a general mechanism: its document (as given, numbers
    as floats) and the built `Mechanism`; platform: the body its results report."""

    document: dict
    mechanism: Mechanism = field(compare=False)
    platform: str = ""

    def to_dict(self) -> dict:
        return plain(self.document)


def element_keys(section: str, type_name: str | None = None) -> tuple[str, ...]:
    """The keys of an element table of `section` (with its `type`)."""
    reg = SECTIONS[section]
    cls = reg if isinstance(reg, type) else reg.get(type_name or "")
    if cls is None:
        return ("type",)
    names = [f.name for f in dataclasses.fields(cls) if f.init and f.name not in _NOT_IN_FILES]
    names.remove("name")
    extra = ("axis", "f_hint") if cls is Marker else ()
    return (*(("type",) if not isinstance(reg, type) else ()), *names, *extra)


def _function(v: object, path: str, problems: Problems):
    """A time function from a number or a {type = ..., fields} table."""
    if not isinstance(v, dict):
        return v  # (a number: the element makes it a Constant and checks it)
    name = v.get("type", MISSING)
    if name not in FUNCTION_TYPES:
        allowed = ", ".join(FUNCTION_TYPES)
        problems.add(
            f"{path}.type",
            name,
            f"expected a time function;{did_you_mean(name, FUNCTION_TYPES)} allowed: {allowed}",
        )
        return None
    cls = FUNCTION_TYPES[name]
    fields = [f.name for f in dataclasses.fields(cls) if f.init]
    kw = {}
    for k, x in v.items():
        if k == "type":
            continue
        if k not in fields:
            problems.unknown(f"{path}.{k}", k, x, ["type", *fields])
            continue
        kw[k] = tuple(x) if isinstance(x, list) else x
    missing = _missing(cls, kw)
    for k in missing:
        problems.add(f"{path}.{k}", MISSING, f"required field of '{name}' is missing")
    if missing:
        return None
    try:
        return cls(**kw)
    except ModelError as e:
        problems.add(f"{path}.{e.field}", e.value, e.allowed)
    return None


def _missing(cls: type, kw: Mapping) -> list[str]:
    """Required constructor fields of `cls` that `kw` lacks (the element's name aside)."""
    return [
        f.name
        for f in dataclasses.fields(cls)
        if f.init
        and f.name != "name"
        and f.default is dataclasses.MISSING
        and f.default_factory is dataclasses.MISSING
        and f.name not in kw
    ]


def _element(section: str, name: str, t: object, problems: Problems):
    path = f"mechanism.{section}.{name}"
    if not isinstance(t, dict):
        problems.add(path, t, "expected a table of the element's fields")
        return None
    reg = SECTIONS[section]
    if isinstance(reg, type):
        cls = reg
    else:
        tname = t.get("type", MISSING)
        if tname not in reg:
            problems.add(
                f"{path}.type", tname, f"allowed:{did_you_mean(tname, reg)} {', '.join(reg)}"
            )
            return None
        cls = reg[tname]
    keys = element_keys(section, t.get("type"))
    n0 = len(problems)
    kw: dict = {}
    for k, v in t.items():
        if k == "type":
            continue
        if k not in keys:
            problems.unknown(f"{path}.{k}", k, v, keys)
            continue
        if k in FUNCTION_FIELDS:
            v = _function(v, f"{path}.{k}", problems)
        elif k == "angles" and isinstance(v, list):
            v = tuple(_function(a, f"{path}.angles[{i}]", problems) for i, a in enumerate(v))
        elif isinstance(v, list):
            v = tuple(tuple(x) if isinstance(x, list) else x for x in v)
        kw[k] = v
    given = {*kw, *(("orientation",) if "axis" in kw else ())}
    for k in _missing(cls, dict.fromkeys(given)):
        problems.add(f"{path}.{k}", MISSING, f"required field of {cls.__name__} is missing")
    if len(problems) > n0:
        return None
    if cls is Marker and "axis" in kw:  # Marker.on_axis: the triad from the h axis
        if "orientation" in kw:
            problems.add(f"{path}.axis", kw["axis"], "give orientation or axis (+ f_hint)")
            return None
        try:
            kw["orientation"] = triad_from_axis(kw.pop("axis"), kw.pop("f_hint", None))
        except ModelError as e:
            problems.add(
                f"{path}.{'f_hint' if e.field == 'f_hint' else 'axis'}", e.value, e.allowed
            )
            return None
    elif cls is Marker and "f_hint" in kw:
        problems.add(f"{path}.f_hint", kw["f_hint"], "only with axis")
        return None
    try:
        return cls(name, **kw)
    except ModelError as e:
        problems.add(f"{path}.{e.field.split('.')[0]}", e.value, e.allowed)
    return None


def parse_general(t: Mapping, problems: Problems, *, default_name: str) -> GeneralParams | None:
    """The [mechanism] table of type "general" (validated)."""
    for k, v in t.items():
        if k not in GENERAL_KEYS:
            problems.unknown(f"mechanism.{k}", k, v, GENERAL_KEYS)
    n0 = len(problems)
    name = t.get("name", default_name)
    try:
        mech = Mechanism(
            name if isinstance(name, str) and name else default_name,
            gravity=t.get("gravity", (0.0, 0.0, -9.81)),
        )
    except ModelError as e:
        problems.add("mechanism.gravity", e.value, e.allowed)
        return None
    doc: dict = {"name": mech.name, "gravity": list(mech.gravity)}
    for section in SECTIONS:
        tables = t.get(section, {})
        if not isinstance(tables, dict):
            problems.add(
                f"mechanism.{section}", tables, "expected tables [mechanism.<section>.<name>]"
            )
            continue
        doc[section] = {}
        for ename, et in tables.items():
            e = _element(section, ename, et, problems)
            if e is None:
                continue
            try:
                mech.add(e)
            except ModelError as err:
                problems.add(f"mechanism.{section}.{ename}.{err.field}", err.value, err.allowed)
                continue
            doc[section][ename] = plain(et)
    if not mech.bodies and len(problems) == n0:
        problems.add("mechanism.bodies", MISSING, "a mechanism needs at least one moving body")
    platform = t.get("platform", next(iter(mech.bodies), ""))
    known = len(problems) == n0  # (an element with problems is not there to be named)
    if known and mech.bodies and platform not in mech.bodies and platform not in mech.markers:
        problems.add(
            "mechanism.platform",
            platform,
            f"expected a body (or marker) name;{did_you_mean(platform, mech.bodies)} "
            f"bodies: {', '.join(mech.bodies)}",
        )
    if len(problems) > n0:
        return None
    doc["platform"] = platform
    return GeneralParams(doc, mech.validate(), platform)


def platform_body(params: GeneralParams) -> str:
    """The body of the general mechanism's `platform` (a body, or a marker's body)."""
    m = params.mechanism
    p = params.platform
    return p if p in m.bodies else m.markers[p].body if p in m.markers else GROUND
