"""A 3-D sketch of a mechanism's initial pose (never simulates): bodies as lines between
their joints, joints by kind, joint axes as short arrows, optional labels.

    from clearance.plot.sketch import sketch
    fig = sketch(pm.build(), labels=True)          # a Mechanism (e.g. from a scenario)
    fig.savefig("mechanism.png")

`clearance draw FILE` writes the sketch of a scenario's mechanism, to check a geometry
before running it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from clearance.model import GROUND, Mechanism

__all__ = ["sketch", "sketch_axes"]

# joint class name -> (marker, colour)
_STYLE = {
    "Spherical": ("o", "tab:red"),
    "Universal": ("s", "tab:blue"),
    "Revolute": ("^", "tab:green"),
    "Prismatic": ("D", "tab:purple"),
    "Cylindrical": ("h", "tab:orange"),
    "Fixed": ("x", "k"),
}


def _rotation(body) -> np.ndarray:
    return np.asarray(body.rotation)


def _marker_world(mech: Mechanism, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(point, triad) of a marker at the initial pose, world frame (slides at t = 0)."""
    mk = mech.markers[name]
    p = np.array(mk.position, dtype=float)
    if mk.slide is not None:
        p = p + np.array(mk.slide_axis) * mk.slide(0.0)
    T = np.array(mk.orientation)
    if mk.body == GROUND:
        return p, T
    b = mech.bodies[mk.body]
    R = _rotation(b)
    return np.array(b.position) + R @ p, R @ T


def sketch_axes(
    ax, mech: Mechanism, *, labels: bool = False, axis_length: float | None = None
) -> None:
    """Draw `mech` at its initial pose on a 3-D Axes `ax`."""
    pts: dict[str, list[np.ndarray]] = {b: [] for b in mech.bodies}
    ground: list[np.ndarray] = []
    size = max(
        (float(np.linalg.norm(np.array(b.position))) for b in mech.bodies.values()), default=1.0
    )
    L = axis_length if axis_length is not None else 0.08 * max(size, 1e-3)
    for jn, jt in mech.joints.items():
        pi, Ti = _marker_world(mech, jt.marker_i)
        pj, _ = _marker_world(mech, jt.marker_j)
        kind = type(jt).__name__
        marker, colour = _STYLE.get(kind, ("o", "k"))
        at = pi
        if kind in ("Prismatic", "Cylindrical"):  # the slide: a bar from point i to point j
            ax.plot(*np.column_stack([pi, pj]), color=colour, lw=3.0, alpha=0.6)
            at = 0.5 * (pi + pj)
        ax.scatter(*at, marker=marker, color=colour, s=28, depthshade=False)
        for mname, p in ((jt.marker_i, pi), (jt.marker_j, pj)):
            body = mech.markers[mname].body
            (ground if body == GROUND else pts[body]).append(p)
        if kind in ("Revolute", "Universal"):  # the joint axis h_i
            h = Ti[:, 2] * L
            ax.plot(*np.column_stack([pi - 0.5 * h, pi + 0.5 * h]), color=colour, lw=1.2)
        if kind == "Universal":  # and the cross axis h_j
            _, Tj = _marker_world(mech, jt.marker_j)
            h = Tj[:, 2] * L
            ax.plot(*np.column_stack([pj - 0.5 * h, pj + 0.5 * h]), color=colour, lw=1.2)
        if labels:
            ax.text(*(at + 0.02 * size), jn, fontsize=6, color="0.25")
    for name, ps in pts.items():
        body = mech.bodies[name]
        c = np.array(body.position)
        ax.scatter(*c, marker=".", color="k", s=8, depthshade=False)
        for p in ps:  # a star from the mass centre: any number of joints per body
            ax.plot(*np.column_stack([c, p]), color="0.3", lw=1.6)
    if len(ground) >= 3:  # the base outline through its joints, by angle
        g = np.array(ground)
        ctr = g.mean(axis=0)
        order = np.argsort(np.arctan2(g[:, 1] - ctr[1], g[:, 0] - ctr[0]))
        loop = g[np.r_[order, order[:1]]]
        ax.plot(*loop.T, color="0.6", lw=0.8, ls="--")
    allp = [p for ps in pts.values() for p in ps] + ground
    if allp:
        a = np.array(allp)
        lo, hi = a.min(axis=0), a.max(axis=0)
        mid, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo)) * 1.1 + 1e-9
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")


def sketch(
    mechanisms: Mechanism | Sequence[Mechanism],
    *,
    labels: bool = False,
    titles: Sequence[str] | None = None,
    columns: int = 3,
) -> Figure:
    """A figure with one 3-D sketch per mechanism (initial pose)."""
    mechs = [mechanisms] if isinstance(mechanisms, Mechanism) else list(mechanisms)
    n = len(mechs)
    cols = min(columns, n)
    rows = (n + cols - 1) // cols
    fig = Figure(figsize=(4.2 * cols, 4.0 * rows))
    for k, m in enumerate(mechs):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        sketch_axes(ax, m, labels=labels)
        ax.set_title(titles[k] if titles else m.name, fontsize=9)
    fig.tight_layout()
    return fig
