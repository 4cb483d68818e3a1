"""`[mechanism] type = "parallel"`: any parallel mechanism from leg types, in a file.

    [mechanism]
    type = "parallel"
    gravity = [0.0, 0.0, -9.81]
    dof = 6                                     # optional: the platform's DOF, checked

    [mechanism.platform]
    mass = 10.0
    inertia = [0.15625, 0.15625, 0.3125]
    position = [0.0, 0.0, 0.7]                  # mass centre at home [m]

    [[mechanism.legs]]                          # a group of alike legs
    joints = "UPS"                              # base to platform
    base = { radius = 0.4, angles_deg = [0, 60, 120, 180, 240, 300] }
    platform = { radius = 0.2, angles_deg = [30, 30, 150, 150, 270, 270] }
    links = [{ mass = 2.0, inertia = [0.028, 0.028, 0.001], com = 0.2, length = 0.4 },
             { mass = 1.5, inertia = [0.021, 0.021, 0.0005], com = 0.2, length = 0.4 }]

The keys mirror `clearance.parallel` one to one (`legs(...)`: joints, base, platform,
links, name, actuated, axis, axes, rail, knee, parallelogram, lumped; `Platform`,
`ParallelMechanism`), and every error is reported at its file path
(`mechanism.legs[1].links[0].mass`). The validated form keeps the file's groups (so that a
study's path `mechanism.legs[0].links[1].mass` changes every leg of the group) together
with the built `ParallelMechanism`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from clearance.model.errors import ModelError
from clearance.model.mechanism import Mechanism
from clearance.model.values import check_value
from clearance.parallel import (
    Attachments,
    Link,
    Mobility,
    ParallelMechanism,
    Platform,
    circle,
    legs,
)
from clearance.scenario.errors import MISSING, Problems
from clearance.scenario.fields import plain

__all__ = [
    "ATTACH_KEYS",
    "LEG_KEYS",
    "LINK_KEYS",
    "MECHANISM_KEYS",
    "PLATFORM_KEYS",
    "ParallelParams",
    "parse_parallel",
]

MECHANISM_KEYS = ("type", "name", "gravity", "dof", "platform", "legs")
PLATFORM_KEYS = ("mass", "inertia", "position")
LEG_KEYS = (
    "joints",
    "base",
    "platform",
    "links",
    "name",
    "actuated",
    "axis",
    "axes",
    "rail",
    "knee",
    "parallelogram",
    "lumped",
)
ATTACH_KEYS = ("radius", "angles_deg", "z", "points")
LINK_KEYS = ("mass", "inertia", "com", "length")


@dataclass(frozen=True)
class ParallelParams:
    """The validated [mechanism] of a parallel mechanism: the canonical document (every
    field written out, the file's leg groups kept) and the built `ParallelMechanism`."""

    document: dict
    mechanism: ParallelMechanism = field(compare=False)
    mobility: Mobility | None = field(default=None, compare=False)
    ideal: Mechanism | None = field(default=None, compare=False)  # built at home

    def to_dict(self) -> dict:
        return plain(self.document)  # type: ignore[return-value]


def _unknown(t: Mapping, allowed: tuple[str, ...], path: str, problems: Problems) -> None:
    for k, v in t.items():
        if k not in allowed:
            problems.unknown(f"{path}.{k}", k, v, allowed)


def _value(kind: str, v: object, path: str, problems: Problems) -> object:
    try:
        return check_value(path, path.rsplit(".", 1)[-1], kind, v)
    except ModelError as e:
        problems.add(path, v, e.allowed)
        return MISSING


def _table(v: object, path: str, problems: Problems) -> dict | None:
    if isinstance(v, dict):
        return v
    problems.add(path, v, "expected a table ({key = value, ...})")
    return None


def _platform(v: object, problems: Problems) -> tuple[Platform | None, dict]:
    path = "mechanism.platform"
    t = _table(v, path, problems)
    if t is None:
        return None, {}
    _unknown(t, PLATFORM_KEYS, path, problems)
    n0 = len(problems)
    doc = {}
    for k, kind in (("mass", "positive"), ("inertia", "inertia3"), ("position", "vector3")):
        if k not in t:
            if k == "position":
                doc[k] = (0.0, 0.0, 0.0)
                continue
            problems.add(f"{path}.{k}", MISSING, "required field is missing")
            continue
        doc[k] = _value(kind, t[k], f"{path}.{k}", problems)
    if len(problems) > n0:
        return None, {}
    return Platform(doc["mass"], doc["inertia"], position=doc["position"]), plain(doc)


def _attachments(v: object, path: str, problems: Problems) -> tuple[Attachments | None, dict]:
    t = _table(v, path, problems)
    if t is None:
        return None, {}
    _unknown(t, ATTACH_KEYS, path, problems)
    n0 = len(problems)
    if "points" in t:
        extra = [k for k in ("radius", "angles_deg", "z") if k in t]
        if extra:
            problems.add(f"{path}.{extra[0]}", t[extra[0]], "give points or radius + angles_deg")
            return None, {}
        pts = t["points"]
        if not isinstance(pts, list) or not pts:
            problems.add(f"{path}.points", pts, "expected a list of points [x, y, z] [m]")
            return None, {}
        out = [_value("vector3", p, f"{path}.points[{i}]", problems) for i, p in enumerate(pts)]
        if len(problems) > n0:
            return None, {}
        return Attachments(tuple(out)), {"points": plain(out)}
    for k in ("radius", "angles_deg"):
        if k not in t:
            problems.add(f"{path}.{k}", MISSING, "required: radius and angles_deg, or points")
    if len(problems) > n0:
        return None, {}
    angles = t["angles_deg"]
    if not isinstance(angles, list) or not angles:
        problems.add(f"{path}.angles_deg", angles, "expected a list of angles [deg]")
        return None, {}
    r = _value("positive", t["radius"], f"{path}.radius", problems)
    z = _value("real", t.get("z", 0.0), f"{path}.z", problems)
    angs = [_value("real", a, f"{path}.angles_deg[{i}]", problems) for i, a in enumerate(angles)]
    if len(problems) > n0:
        return None, {}
    return circle(r, angs, z), {"radius": r, "angles_deg": list(angs), "z": z}


def _links(v: object, path: str, problems: Problems) -> tuple[list[Link] | None, list]:
    if not isinstance(v, list) or not v:
        problems.add(path, v, "expected a list of links [{mass, inertia, com, length}, ...]")
        return None, []
    out, doc, n0 = [], [], len(problems)
    for i, lt in enumerate(v):
        p = f"{path}[{i}]"
        t = _table(lt, p, problems)
        if t is None:
            continue
        _unknown(t, LINK_KEYS, p, problems)
        for k in ("mass", "inertia"):
            if k not in t:
                problems.add(f"{p}.{k}", MISSING, "required field is missing")
        if len(problems) > n0:
            continue
        kw = {k: t[k] for k in LINK_KEYS if k in t}
        try:
            link = Link(**kw)
        except ModelError as e:
            problems.add(f"{p}.{e.field}", e.value, e.allowed)
            continue
        out.append(link)
        d = {"mass": link.mass, "inertia": list(link.inertia), "com": link.com}
        if link.length is not None:
            d["length"] = link.length
        doc.append(d)
    if len(problems) > n0:
        return None, []
    return out, doc


def _leg_group(v: object, k: int, problems: Problems) -> tuple[tuple | None, dict]:
    path = f"mechanism.legs[{k}]"
    t = _table(v, path, problems)
    if t is None:
        return None, {}
    _unknown(t, LEG_KEYS, path, problems)
    n0 = len(problems)
    for key in ("joints", "base", "platform", "links"):
        if key not in t:
            problems.add(f"{path}.{key}", MISSING, "required field is missing")
    if len(problems) > n0:
        return None, {}
    base, base_doc = _attachments(t["base"], f"{path}.base", problems)
    plat, plat_doc = _attachments(t["platform"], f"{path}.platform", problems)
    links, links_doc = _links(t["links"], f"{path}.links", problems)
    opts: dict = {}
    for key in ("axis", "rail"):
        if key in t:
            opts[key] = _value("vector3", t[key], f"{path}.{key}", problems)
    if "axes" in t:
        ax = _table(t["axes"], f"{path}.axes", problems)
        if ax is not None:
            opts["axes"] = ax
    if "actuated" in t:
        opts["actuated"] = None if t["actuated"] == "none" else t["actuated"]
    for key in ("name", "knee", "parallelogram", "lumped"):
        if key in t:
            opts[key] = t[key]
    if len(problems) > n0:
        return None, {}
    try:
        group = legs(t["joints"], base=base, platform=plat, links=links, **opts)
    except ModelError as e:
        problems.add(f"{path}.{e.field}", e.value, e.allowed)
        return None, {}
    first = group[0]
    doc = {"joints": first.joints, "base": base_doc, "platform": plat_doc, "links": links_doc}
    doc["name"] = opts.get("name", "")
    doc["actuated"] = first.actuated if first.actuated is not None else "none"
    for key in ("axis", "rail"):
        if key in opts:
            doc[key] = list(opts[key])
    if "axes" in opts:
        doc["axes"] = {j: plain(a[0] if len(a) == 1 else a) for j, a in first.axes.items()}
    for key in ("knee", "parallelogram"):
        if getattr(first, key) is not None:
            doc[key] = getattr(first, key)
    doc["lumped"] = first.lumped
    return group, doc


def parse_parallel(
    t: Mapping, problems: Problems, *, default_name: str, mobility: bool = True
) -> ParallelParams | None:
    """The [mechanism] table of type "parallel" (validated; its mobility checked unless
    `mobility` is False: the names and kinds of its joints are all a path check needs)."""
    _unknown(t, MECHANISM_KEYS, "mechanism", problems)
    n0 = len(problems)
    doc: dict = {}
    name = t.get("name", default_name)
    if not isinstance(name, str) or not name.strip():
        problems.add("mechanism.name", name, "expected a non-empty string")
    doc["name"] = name
    gravity = _value("vector3", t.get("gravity", [0.0, 0.0, -9.81]), "mechanism.gravity", problems)
    doc["gravity"] = plain(gravity)
    dof = t.get("dof")
    if dof is not None:
        if isinstance(dof, bool) or not isinstance(dof, int) or not 1 <= dof <= 6:
            problems.add("mechanism.dof", dof, "expected an integer 1..6 (the platform's DOF)")
        doc["dof"] = dof
    if "platform" not in t:
        problems.add("mechanism.platform", MISSING, "required section [mechanism.platform]")
        platform = None
    else:
        platform, doc["platform"] = _platform(t["platform"], problems)
    raw = t.get("legs", MISSING)
    groups: list = []
    if raw is MISSING or not isinstance(raw, list) or not raw:
        problems.add("mechanism.legs", raw, "expected one or more [[mechanism.legs]] tables")
    else:
        docs = []
        for k, v in enumerate(raw):
            g, d = _leg_group(v, k, problems)
            groups.append(g)
            docs.append(d)
        doc["legs"] = docs
    if len(problems) > n0:
        return None
    try:
        pm = ParallelMechanism(name, platform, tuple(groups), gravity=gravity, dof=dof)
        mob = pm.check_mobility() if mobility else None
    except ModelError as e:
        problems.add(f"mechanism.{e.field}", e.value, e.allowed)
        return None
    return ParallelParams(doc, pm, mob, pm.build(check=False))
