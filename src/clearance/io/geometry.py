"""What a result file records of a mechanism's geometry, for drawing it (`clearance view`,
`clearance animate`) without the scenario or the code that built it.

`mechanism_geometry(mech)` is a JSON-able dict, stored as the `geometry` attribute of each
run's group:

    {"format": 1,
     "markers": {name: {"body", "position" (body frame; world for ground),
                        "orientation" (3x3, columns f, g, h in body components)}},
     "joints": [{"name", "kind", "marker_i", "marker_j", "body_i", "body_j",
                 "clearance" (its kind or null)}],
     "clearances": [{"name", "kind", "model", "outer_marker", "inner_marker",
                     "outer_body", "inner_body", "c", "inner_radius", "outer_radius",
                     "length", "width", "height"}],
     "bodies": {name: {"mass"}}}

Only markers that joints use are listed (drivers and forces act between them). A marker
that slides on its body (`Marker.slide`) is recorded at its initial place.
"""

from __future__ import annotations

import json

import numpy as np

from clearance.model import GROUND, Mechanism
from clearance.model.clearance import PrismaticClearance, RevoluteClearance

FORMAT = 1

__all__ = ["FORMAT", "geometry_from_attrs", "mechanism_geometry"]


def _marker(mech: Mechanism, name: str) -> dict:
    mk = mech.markers[name]
    p = np.array(mk.position, dtype=float)
    if mk.slide is not None:
        p = p + np.array(mk.slide_axis, dtype=float) * float(mk.slide(0.0))
    return {
        "body": mk.body,
        "position": p.tolist(),
        "orientation": np.asarray(mk.orientation, dtype=float).tolist(),
    }


def _clearance(jt, cl) -> dict:
    outer, inner = (jt.marker_i, jt.marker_j) if cl.outer == "i" else (jt.marker_j, jt.marker_i)
    d = {"name": jt.name, "outer_marker": outer, "inner_marker": inner, "c": float(cl.c)}
    if isinstance(cl, PrismaticClearance):
        h = cl.height if cl.height is not None else cl.width
        ch = cl.clearance_height if cl.clearance_height is not None else cl.clearance
        d.update(
            kind="prismatic",
            model=cl.model,
            inner_radius=0.5 * cl.width,
            outer_radius=0.5 * cl.width + cl.clearance,
            width=float(cl.width),
            height=float(h),
            height_clearance=float(ch),
            length=float(cl.length),
        )
    elif isinstance(cl, RevoluteClearance):
        r = float(cl.journal_radius)
        d.update(
            kind="cylindrical" if type(jt).__name__ == "Cylindrical" else "revolute",
            model=cl.model,
            inner_radius=r,
            outer_radius=r + float(cl.c),
            length=float(cl.length) if cl.length is not None else 2.0 * r,
        )
    else:
        r = float(cl.ball_radius)
        d.update(kind="spherical", model="spatial", inner_radius=r, outer_radius=r + float(cl.c))
    return d


def mechanism_geometry(mech: Mechanism) -> dict:
    """The drawing geometry of `mech` (module docstring)."""
    markers: dict = {}
    joints, clearances = [], []
    for jt in mech.joints.values():
        for m in (jt.marker_i, jt.marker_j):
            markers.setdefault(m, _marker(mech, m))
        cl = getattr(jt, "clearance", None)
        d = None if cl is None else _clearance(jt, cl)
        joints.append(
            {
                "name": jt.name,
                "kind": type(jt).__name__.lower(),
                "marker_i": jt.marker_i,
                "marker_j": jt.marker_j,
                "body_i": mech.markers[jt.marker_i].body,
                "body_j": mech.markers[jt.marker_j].body,
                "clearance": None if d is None else d["kind"],
            }
        )
        if d is not None:
            d["outer_body"] = mech.markers[d["outer_marker"]].body
            d["inner_body"] = mech.markers[d["inner_marker"]].body
            clearances.append(d)
    bodies = {n: {"mass": float(b.mass)} for n, b in mech.bodies.items()}
    return {
        "format": FORMAT,
        "ground": GROUND,
        "bodies": bodies,
        "markers": markers,
        "joints": joints,
        "clearances": clearances,
    }


def geometry_from_attrs(attrs) -> dict | None:
    """The geometry stored in a group's attributes, or None (files before it was kept)."""
    raw = attrs.get("geometry")
    if raw is None:
        return None
    g = json.loads(raw) if isinstance(raw, str) else raw
    if int(g.get("format", 0)) > FORMAT:
        raise ValueError(
            f"geometry format {g.get('format')} is newer than this clearance reads ({FORMAT})"
        )
    return g
