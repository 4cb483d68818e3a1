"""Wear of a journal bearing: the revolute and cylindrical clearance joints (issue 16, after
the spherical socket; docs/wear.md).

The bearing is worn per contact station (the joint's equal slices of the bearing length;
one for a planar joint), on n equal cells of the angle theta about the bearing marker's h
axis from its f axis (cell i centred at 2 pi (i + 1/2) / n): `BearingWearMap.depth`
(stations, n) [m], material removed radially outward. A cell's area is R dtheta L / N
(R the bearing radius, L its length, N stations), its worn volume dtheta (L / N)
((R + h)^2 - R^2) / 2. Only the bearing wears (the journal is taken as the harder part).

What the dynamics sees (`BearingWearMap.bearing_wear`, `clearance.model.wear.BearingWear`)
is not the depth h itself but its support depth H: per station, with the journal's offset
x in the section (small-clearance form), the set of offsets the journal reaches without
touching the worn surface is S = {x : x . u_i <= c + h_i for every cell i} (a convex
polygon), and c + H_i = max_{x in S} x . u_i, its support function at the cells'
directions. H = h where the cell bounds S (the journal can touch it); H < h in a pocket
narrower than the journal (it rests on the pocket's rims, and the kernel's minimum
distance to the rim c + H is the distance to S: smooth, with no jump between the rims).

Archard's law per station and output sample (`ring_archard`): the pressure is the elastic
foundation's, proportional to the overlap d_i = R_J - D_i > 0 of the journal (D_i: the
distance of the cell's worn surface point X_i = (R + h_i) u_i from the journal axis, which
meets the station's plane at e; about e . u_i - c - h_i) with the worn surface as it was
during the run, scaled
so that sum(p A) equals the station's normal force; where fewer than MIN_RING_CELLS cells
overlap, the journal is taken as pushed further until that many do (the same rule as the
socket's, `clearance.wear.surface.overlap_patch`). The depth added is k_w p |v_slip| dt,
so the volume is k_w F_N |v_slip| dt per station.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from clearance.model.wear import BearingWear, ring_angles
from clearance.wear.surface import overlap_floor

__all__ = [
    "MIN_RING_CELLS",
    "BearingWearMap",
    "bearing_history",
    "ring_archard",
    "station_sections",
]

#: fewest cells of a station's ring in the overlap (`ring_archard`)
MIN_RING_CELLS = 3


@dataclass
class BearingWearMap:
    """Wear depth of a journal bearing (module docstring): radius R [m], length L [m] (the
    contact length the stations share), stations N, n cells per station."""

    radius: float
    length: float
    stations: int
    n: int = 256
    depth: np.ndarray = field(default=None, repr=False)  # (stations, n) [m]

    dims = ("station", "angle")

    def __post_init__(self) -> None:
        for name in ("radius", "length"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"BearingWearMap.{name} = {v!r}: expected a number > 0 [m]")
        if int(self.stations) < 1 or int(self.n) < 4:
            raise ValueError(
                f"BearingWearMap: stations = {self.stations!r}, n = {self.n!r}: expected "
                ">= 1 station and >= 4 cells"
            )
        self.stations, self.n = int(self.stations), int(self.n)
        if self.depth is None:
            self.depth = np.zeros((self.stations, self.n))
        elif np.shape(self.depth) != (self.stations, self.n):
            raise ValueError(f"depth has shape {np.shape(self.depth)}, expected (stations, n)")

    @property
    def angles(self) -> np.ndarray:
        return ring_angles(self.n)

    @property
    def directions(self) -> np.ndarray:
        """(n, 2) unit directions u_i of the cells in the bearing marker's f-g plane."""
        a = self.angles
        return np.column_stack([np.cos(a), np.sin(a)])

    @property
    def cell_area(self) -> float:
        return self.radius * 2.0 * np.pi / self.n * self.length / self.stations

    def volume(self) -> float:
        """Worn volume [m^3] (the annular shell removed: per cell its area times
        h (1 + h / 2R))."""
        return self.cell_area * float(np.sum(self.depth * (1.0 + 0.5 * self.depth / self.radius)))

    def max_depth(self) -> float:
        return float(self.depth.max())

    def empty(self) -> BearingWearMap:
        """An unworn map of the same bearing and grid."""
        return BearingWearMap(self.radius, self.length, self.stations, self.n)

    def support_depth(self, clearance: float) -> np.ndarray:
        """H (stations, n) [m] >= 0: per station, the support function of the reachable
        set S = {x : x . u_i <= c + h_i} at the cells' directions, less c (module
        docstring); by the half-plane intersection (scipy.spatial.HalfspaceIntersection,
        Qhull): the support at u_i is the largest u_i . v over S's vertices v."""
        from scipy.spatial import HalfspaceIntersection

        c = float(clearance)
        U = self.directions
        out = np.zeros_like(self.depth)
        for j in range(self.stations):
            h = self.depth[j]
            if not np.any(h > 0.0):
                continue
            hs = np.column_stack([U, -(c + h)])  # u . x - (c + h) <= 0
            verts = HalfspaceIntersection(hs, np.zeros(2)).intersections
            out[j] = np.clip(np.max(U @ verts.T, axis=1) - c, 0.0, h)
        return out

    def bearing_wear(self, clearance: float, smoothing: float | None = None) -> BearingWear:
        """The worn bearing as the dynamics sees it (`Mechanism.with_wear`): the support
        depth. `smoothing` is the socket's parameter, unused (the ring's field is a
        cubic B-spline over its cells, `BearingWear`)."""
        return BearingWear(self.support_depth(clearance))

    wear_model = bearing_wear  # the loop's common name (SphereWearMap.wear_model)

    def overlap(
        self, station: int, e: np.ndarray, clearance: float, axis: np.ndarray | None = None
    ) -> np.ndarray:
        """d (k, n) = R_J - D_i: how far the cells' worn surface points X_i = (R + h_i) u_i
        of one station lie inside the journal (radius R_J = R - c), D_i their distance from
        its axis: the line through e (k, 2), the axis' point in the station's plane, along
        the unit `axis` (k, 3) in the bearing marker frame (None: along h, an aligned
        journal: D_i = |X_i - e|). The contact kernel's geometry; about e . u_i - c - h_i for
        a small clearance and tilt."""
        e = np.atleast_2d(np.asarray(e, dtype=float))
        X = (self.radius + self.depth[station])[:, None] * self.directions
        w = X[None, :, :] - e[:, None, :2]  # (k, n, 2), in the station's plane
        d2 = np.sum(w * w, axis=2)
        if axis is not None:
            a = np.atleast_2d(np.asarray(axis, dtype=float))
            d2 = d2 - np.einsum("knj,kj->kn", w, a[:, :2]) ** 2
        return (self.radius - clearance) - np.sqrt(np.clip(d2, 0.0, None))


def ring_archard(
    surface: BearingWearMap,
    station: int,
    e: np.ndarray,
    force: np.ndarray,
    slip: np.ndarray,
    k_w: float,
    clearance: float,
    *,
    worn: BearingWearMap | None = None,
    axis: np.ndarray | None = None,
) -> None:
    """Add Archard's wear of samples (journal offsets e (k, 2) in the station's section,
    normal forces (k,) [N], slip distances |v_slip| dt (k,) [m]) to one station of
    `surface` (module docstring); the overlap is taken with `worn` (the bearing as it was
    during the run; default: `surface` itself) and the journal axes `axis` (k, 3) (None:
    aligned; `BearingWearMap.overlap`)."""
    worn = surface if worn is None else worn
    if worn.depth.shape != surface.depth.shape:
        raise ValueError(
            f"worn has {worn.stations} stations x {worn.n} cells, the map "
            f"{surface.stations} x {surface.n}: expected the same grid"
        )
    force = np.asarray(force, dtype=float)
    slip = np.asarray(slip, dtype=float)
    use = np.flatnonzero((force > 0) & (slip > 0))
    for lo in range(0, use.size, 4096):
        idx = use[lo : lo + 4096]
        ax = None if axis is None else np.asarray(axis, dtype=float)[idx]
        d = worn.overlap(station, np.asarray(e, dtype=float)[idx], clearance, ax)
        tau = overlap_floor(d, MIN_RING_CELLS)
        p = np.clip(d - tau[:, None], 0.0, None)
        scale = k_w * force[idx] * slip[idx] / (np.sum(p, axis=1) * surface.cell_area)
        surface.depth[station] += scale @ p


def _bearing_joint(result, joint: str):
    """(index, ClearanceInfo) of revolute or cylindrical clearance joint `joint` of a run
    (ValueError for another name or kind)."""
    infos = result.compiled.clearances
    names = [ci.name for ci in infos]
    if joint not in names:
        raise ValueError(f"no clearance joint {joint!r}; the run has {', '.join(names)}")
    k = names.index(joint)
    if infos[k].kind not in ("revolute", "cylindrical"):
        raise ValueError(
            f"{joint} is a {infos[k].kind} clearance joint; bearing wear is for revolute and "
            "cylindrical ones"
        )
    return k, infos[k]


def station_sections(result, joint: str, keep: np.ndarray | None = None):
    """The journal in each station's section of revolute or cylindrical clearance joint
    `joint` over a Result's samples `keep` (default: all): (contact point names, their
    axial coordinates sigma, offsets e (stations, k, 2) of the journal axis' point in each
    station's plane, the journal axis (k, 3)), in the bearing marker frame: from the joint's
    eccentricity (P_b - P_s) and the journal axis turned by the bodies' rotations. Samples
    where the journal axis lies in a station's plane (no section) have e = nan."""
    from clearance.kinds import PG_K0, PI_KIND, ContactKind
    from clearance.model.bodies import GROUND

    comp = result.compiled
    k, info = _bearing_joint(result, joint)
    model = comp.model
    pts = [
        p
        for p in range(len(result.contact_point_names))
        if result.contact_point_joints[p] == joint
        and model.cp_ix[p, PI_KIND] == int(ContactKind.JOURNAL_STATION)
    ]
    keep = np.arange(result.t.size) if keep is None else np.asarray(keep)

    def frame(body, T):  # (k, 3, 3) marker triad in the world
        if body == GROUND:
            return np.broadcast_to(T, (keep.size, 3, 3))
        return result.rotation(body)[keep] @ T

    Rs = frame(info.socket_body, model.clr_T[k, 0])
    hb = frame(info.ball_body, model.clr_T[k, 1])[:, :, 2]
    h = np.einsum("kji,kj->ki", Rs, hb)  # journal axis in the bearing marker frame
    e = np.asarray(result.eccentricity(joint), dtype=float)[keep]
    sig = np.array([float(model.cp_geo[p, PG_K0]) for p in pts])
    hz = np.where(np.abs(h[:, 2]) > 1e-9, h[:, 2], np.nan)
    lam = (sig[:, None] - e[None, :, 2]) / hz[None, :]
    ek = e[None, :, :2] + lam[:, :, None] * h[None, :, :2]
    return [result.contact_point_names[p] for p in pts], sig, ek, h


def bearing_history(
    result,
    joint: str,
    *,
    k_w: float,
    n: int = 256,
    keep: np.ndarray | None = None,
    surface: BearingWearMap | None = None,
    worn: BearingWearMap | None = None,
    length: float | None = None,
) -> tuple[BearingWearMap, float]:
    """(wear map of the bearing of revolute or cylindrical clearance joint `joint`, the
    integral of F_N |v_slip| dt over its stations [N m]) from a run's Result over the
    samples `keep` (default: all): per station, the journal axis' offset in the station's
    section (the joint's eccentricity, and the journal axis in the bearing marker frame
    from the bodies' rotations), the station's normal force and slip (`ring_archard`).
    surface: a map to add to (default: a new one of n cells per station, over `length` or
    the clearance's length); worn: the bearing as worn during the run."""
    from clearance.wear.history import trapezoid_weights

    pts, _, ek, h = station_sections(result, joint, keep)
    _, info = _bearing_joint(result, joint)
    if surface is None:
        cl = result.compiled.mechanism.joints[joint].clearance
        length = length if length is not None else cl.length
        if length is None:
            raise ValueError(
                f"{joint}: bearing wear needs the bearing's contact length (its clearance has "
                "none: pass length)"
            )
        surface = BearingWearMap(info.socket_radius, length, len(pts), n)
    m = surface
    if m.stations != len(pts):
        raise ValueError(f"the map has {m.stations} stations, {joint} {len(pts)}")
    keep = np.arange(result.t.size) if keep is None else np.asarray(keep)
    w = trapezoid_weights(np.asarray(result.t)[keep])
    work = 0.0
    for j, name in enumerate(pts):
        f = np.abs(np.asarray(result.channel("point_contact_force", name), dtype=float)[keep])
        v = np.linalg.norm(np.asarray(result.channel("point_slip_velocity", name))[keep], axis=1)
        ds = np.where(np.isfinite(ek[j, :, 0]), v * w, 0.0)
        ring_archard(m, j, np.nan_to_num(ek[j]), f, ds, k_w, info.c, worn=worn, axis=h)
        work += float(np.sum(f * ds))
    return m, work
