"""How each body, joint and clearance joint is drawn: primitives in body frames, from the
geometry a result file records (`clearance.io.geometry`). The HTML viewer and the video
renderer draw the same primitives.

Default shapes (a scenario's `[view]` table overrides them per body):

- a body with three or more joint points that are not on one line (a platform): a flat
  prism through the convex hull of its points, in their best-fit plane;
- a body with two distinct joint points: a rod between them;
- a body with one joint point: a rod from it through the mass centre, as far again on the
  other side (the legs of the seed mechanisms: the joint at one end, the mass centre
  halfway); a body whose only point is its mass centre: a sphere;
- the outer body of a prismatic or cylindrical joint (a sleeve) is drawn thicker;
- joints: spheres (spherical), a short cylinder along each axis (universal: h_i on body i,
  h_j on body j; revolute and cylindrical: h_i); prismatic and fixed joints are shown by
  their bodies;
- clearance joints: the socket (bearing, guide) transparent on the outer body, the ball
  (journal, slider) inside it at the magnified eccentricity, the contact force as an arrow.

Every primitive is a dict: {"type": "rod", "a", "b", "radius"}, {"type": "sphere",
"centre", "radius"}, {"type": "mesh", "vertices", "faces"}, with "colour" ("#rrggbb");
coordinates in the body frame [m].
"""

from __future__ import annotations

import math

import numpy as np

from clearance.model.bodies import rotation_matrices

__all__ = ["PALETTE", "body_shapes", "joint_glyphs", "mechanism_size", "nice_magnification"]

# matplotlib's tab10, for bodies in order; the ground is drawn grey
PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)
PLATFORM_COLOUR = "#4a6fa5"


def _points(geometry: dict) -> dict[str, list[np.ndarray]]:
    """Body name -> its joint points (body frame), markers of every joint."""
    pts: dict[str, list[np.ndarray]] = {}
    for mk in geometry["markers"].values():
        pts.setdefault(mk["body"], []).append(np.array(mk["position"], dtype=float))
    return pts


def mechanism_size(geometry: dict, pose: dict[str, tuple]) -> float:
    """The largest extent [m] of the joint points at a pose {body: (r, e)}."""
    world = []
    for mk in geometry["markers"].values():
        p = np.array(mk["position"], dtype=float)
        if mk["body"] in pose:
            r, e = pose[mk["body"]]
            p = np.asarray(r, dtype=float) + rotation_matrices(np.asarray(e, dtype=float)) @ p
        world.append(p)
    if not world:
        return 1.0
    w = np.array(world)
    return float(max(np.max(w.max(axis=0) - w.min(axis=0)), 1e-3))


def _distinct(points: list[np.ndarray], tol: float) -> list[np.ndarray]:
    out: list[np.ndarray] = []
    for p in points:
        if all(np.linalg.norm(p - q) > tol for q in out):
            out.append(p)
    return out


def _hull2(xy: np.ndarray) -> list[int]:
    """Indices of the convex hull of 2-D points, counter-clockwise (monotone chain)."""
    order = sorted(range(len(xy)), key=lambda k: (xy[k, 0], xy[k, 1]))

    def cross(o, a, b):
        return (xy[a, 0] - xy[o, 0]) * (xy[b, 1] - xy[o, 1]) - (xy[a, 1] - xy[o, 1]) * (
            xy[b, 0] - xy[o, 0]
        )

    lower: list[int] = []
    for k in order:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], k) <= 0:
            lower.pop()
        lower.append(k)
    upper: list[int] = []
    for k in reversed(order):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], k) <= 0:
            upper.pop()
        upper.append(k)
    return lower[:-1] + upper[:-1]


def _prism(points: list[np.ndarray], thickness: float, colour: str) -> dict | None:
    """A flat prism through the convex hull of `points` in their best-fit plane, or None
    when they lie on a line."""
    P = np.array(points)
    c = P.mean(axis=0)
    _, s, vt = np.linalg.svd(P - c)
    if s.size < 2 or s[1] <= 1e-9 * max(s[0], 1e-12):
        return None
    u, v, n = vt[0], vt[1], np.cross(vt[0], vt[1])
    xy = np.column_stack([(P - c) @ u, (P - c) @ v])
    hull = _hull2(xy)
    if len(hull) < 3:
        return None
    ring = [c + xy[k, 0] * u + xy[k, 1] * v for k in hull]
    h = 0.5 * thickness * n
    verts = [p + h for p in ring] + [p - h for p in ring]
    m = len(ring)
    faces = []
    for k in range(1, m - 1):  # top (counter-clockwise about n) and bottom fans
        faces.append([0, k, k + 1])
        faces.append([m, m + k + 1, m + k])
    for k in range(m):  # sides
        a, b = k, (k + 1) % m
        faces.append([a, m + a, m + b])
        faces.append([a, m + b, b])
    return {
        "type": "mesh",
        "vertices": np.round(np.array(verts), 9).tolist(),
        "faces": faces,
        "colour": colour,
    }


def body_shapes(
    geometry: dict, size: float, overrides: dict | None = None
) -> dict[str, list[dict]]:
    """Body name -> its primitives (module docstring). size: the mechanism's extent [m];
    overrides: {body: {"shape": "auto" | "rod" | "sphere" | "plate" | "none",
    "radius", "colour", "thickness"}}."""
    overrides = overrides or {}
    ground = geometry.get("ground", "ground")
    pts = _points(geometry)
    r0 = 0.012 * size
    sleeves = {
        j["body_i"]
        for j in geometry["joints"]
        if j["kind"] in ("prismatic", "cylindrical") and j["body_i"] != ground
    }
    out: dict[str, list[dict]] = {}
    for k, name in enumerate(geometry["bodies"]):
        o = overrides.get(name, {})
        ps = _distinct(pts.get(name, []), 1e-9 * size)
        colour = o.get("colour") or (PLATFORM_COLOUR if len(ps) >= 3 else PALETTE[k % 10])
        radius = float(o.get("radius", r0 * (1.5 if name in sleeves else 1.0)))
        shape = o.get("shape", "auto")
        prims: list[dict] = []
        if shape == "none":
            out[name] = prims
            continue
        if shape in ("auto", "plate") and len(ps) >= 3:
            plate = _prism(ps, float(o.get("thickness", 0.05 * size)), colour)
            if plate is not None:
                out[name] = [plate]
                continue
        if shape == "sphere" or not ps:
            prims.append(
                {
                    "type": "sphere",
                    "centre": [0.0, 0.0, 0.0],
                    "radius": 2 * radius,
                    "colour": colour,
                }
            )
        elif len(ps) == 1:
            p = ps[0]
            if np.linalg.norm(p) <= 1e-9 * size:  # the joint at the mass centre
                prims.append(
                    {"type": "sphere", "centre": p.tolist(), "radius": 2 * radius, "colour": colour}
                )
            else:
                prims.append(
                    {
                        "type": "rod",
                        "a": p.tolist(),
                        "b": (-p).tolist(),
                        "radius": radius,
                        "colour": colour,
                    }
                )
        else:  # two or more points on a line: the longest segment
            P = np.array(ps)
            d = np.linalg.norm(P[:, None] - P[None], axis=2)
            a, b = np.unravel_index(int(np.argmax(d)), d.shape)
            prims.append(
                {
                    "type": "rod",
                    "a": P[a].tolist(),
                    "b": P[b].tolist(),
                    "radius": radius,
                    "colour": colour,
                }
            )
        out[name] = prims
    return out


def joint_glyphs(geometry: dict, size: float) -> dict[str, list[dict]]:
    """Body name (or the ground) -> the glyphs of the ideal joints on it (module
    docstring). Clearance joints are drawn by the viewer from their own data."""
    r = 0.02 * size
    out: dict[str, list[dict]] = {}
    markers = geometry["markers"]

    def axis_rod(marker: str, length: float, radius: float, colour: str) -> None:
        mk = markers[marker]
        p = np.array(mk["position"], dtype=float)
        h = np.array(mk["orientation"], dtype=float)[:, 2]
        out.setdefault(mk["body"], []).append(
            {
                "type": "rod",
                "a": (p - 0.5 * length * h).tolist(),
                "b": (p + 0.5 * length * h).tolist(),
                "radius": radius,
                "colour": colour,
            }
        )

    for j in geometry["joints"]:
        if j["clearance"] is not None:
            continue
        kind = j["kind"]
        if kind == "spherical":
            mk = markers[j["marker_i"]]
            out.setdefault(mk["body"], []).append(
                {"type": "sphere", "centre": mk["position"], "radius": r, "colour": "#c0392b"}
            )
        elif kind == "universal":
            axis_rod(j["marker_i"], 3 * r, 0.45 * r, "#2c3e50")
            axis_rod(j["marker_j"], 3 * r, 0.45 * r, "#2c3e50")
        elif kind in ("revolute", "cylindrical"):
            axis_rod(j["marker_i"], 3 * r, 0.7 * r, "#27ae60")
    return out


def nice_magnification(radius: float, clearance: float, fraction: float = 0.3) -> float:
    """The largest of 1, 2, 5 x 10^k with magnified clearance <= fraction * radius (at
    least 1): the factor the viewer draws a clearance with."""
    if clearance <= 0 or radius <= 0:
        return 1.0
    target = fraction * radius / clearance
    if target <= 1:
        return 1.0
    k = math.floor(math.log10(target))
    best = 1.0
    for m in (1, 2, 5, 10):
        v = m * 10.0**k
        if v <= target * (1 + 1e-12):
            best = v
    return float(best)
