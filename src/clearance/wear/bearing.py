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
foundation's, proportional to the overlap d_i = R_J - |X_i - e| > 0 of the journal (centre
offset e in the station's section, the cells' worn surface points X_i = (R + h_i) u_i; about
e . u_i - c - h_i) with the worn surface as it was during the run, scaled
so that sum(p A) equals the station's normal force; where fewer than MIN_RING_CELLS cells
overlap, the journal is taken as pushed further until that many do (the same rule as the
socket's, `clearance.wear.surface.overlap_patch`). The depth added is k_w p |v_slip| dt,
so the volume is k_w F_N |v_slip| dt per station.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from clearance.model.wear import BearingWear
from clearance.wear.surface import overlap_floor

__all__ = ["MIN_RING_CELLS", "BearingWearMap", "bearing_history", "ring_archard"]

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
        return 2.0 * np.pi * (np.arange(self.n) + 0.5) / self.n

    @property
    def directions(self) -> np.ndarray:
        """(n, 2) unit directions u_i of the cells in the bearing marker's f-g plane."""
        a = self.angles
        return np.column_stack([np.cos(a), np.sin(a)])

    @property
    def cell_area(self) -> float:
        return self.radius * 2.0 * np.pi / self.n * self.length / self.stations

    def volume(self) -> float:
        """Worn volume [m^3] (the annular shell removed)."""
        cell = (2.0 * np.pi / self.n) * (self.length / self.stations)
        return float(np.sum(cell * (self.radius * self.depth + 0.5 * self.depth**2)))

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

    def overlap(self, station: int, e: np.ndarray, clearance: float) -> np.ndarray:
        """d (k, n) = R_J - |X_i - e|: how far the cells' worn surface points X_i = (R + h_i)
        u_i lie inside the journal circle (radius R_J = R - c, centre e (k, 2)) at one
        station; the exact circle geometry of the contact kernel (about e . u_i - c - h_i
        for a small clearance)."""
        e = np.atleast_2d(np.asarray(e, dtype=float))
        X = (self.radius + self.depth[station])[:, None] * self.directions
        return (self.radius - clearance) - np.linalg.norm(X[None, :, :] - e[:, None, :], axis=2)


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
) -> None:
    """Add Archard's wear of samples (journal offsets e (k, 2) in the station's section,
    normal forces (k,) [N], slip distances |v_slip| dt (k,) [m]) to one station of
    `surface` (module docstring); the overlap is taken with `worn` (the bearing as it was
    during the run; default: `surface` itself)."""
    worn = surface if worn is None else worn
    force = np.asarray(force, dtype=float)
    slip = np.asarray(slip, dtype=float)
    use = np.flatnonzero((force > 0) & (slip > 0))
    for lo in range(0, use.size, 4096):
        idx = use[lo : lo + 4096]
        d = worn.overlap(station, np.asarray(e, dtype=float)[idx], clearance)
        tau = overlap_floor(d, MIN_RING_CELLS)
        p = np.clip(d - tau[:, None], 0.0, None)
        scale = k_w * force[idx] * slip[idx] / (np.sum(p, axis=1) * surface.cell_area)
        surface.depth[station] += scale @ p


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
    from clearance.kinds import PG_K0, PI_KIND, ContactKind
    from clearance.model.bodies import GROUND
    from clearance.wear.history import trapezoid_weights

    comp = result.compiled
    names = [ci.name for ci in comp.clearances]
    if joint not in names:
        raise ValueError(f"no clearance joint {joint!r}; the run has {', '.join(names)}")
    k = names.index(joint)
    info = comp.clearances[k]
    if info.kind not in ("revolute", "cylindrical"):
        raise ValueError(
            f"{joint} is a {info.kind} clearance joint; bearing wear is for revolute and "
            "cylindrical ones"
        )
    model = comp.model
    pts = [
        p
        for p, name in enumerate(result.contact_point_names)
        if result.contact_point_joints[p] == joint
        and model.cp_ix[p, PI_KIND] == int(ContactKind.JOURNAL_STATION)
    ]
    if surface is None:
        length = length if length is not None else comp.mechanism.joints[joint].clearance.length
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
    t = np.asarray(result.t)[keep]
    w = trapezoid_weights(t)

    def frame(body, T):  # (k, 3, 3) marker triad in the world
        if body == GROUND:
            return np.broadcast_to(T, (t.size, 3, 3))
        return result.rotation(body)[keep] @ T

    Rs = frame(info.socket_body, model.clr_T[k, 0])
    hb = frame(info.ball_body, model.clr_T[k, 1])[:, :, 2]
    h = np.einsum("kji,kj->ki", Rs, hb)  # journal axis in the bearing marker frame
    e = np.asarray(result.eccentricity(joint), dtype=float)[keep]
    work = 0.0
    for j, p in enumerate(pts):
        name = result.contact_point_names[p]
        sigma = float(model.cp_geo[p, PG_K0])
        lam = (sigma - e[:, 2]) / h[:, 2]
        ek = e[:, :2] + lam[:, None] * h[:, :2]
        f = np.abs(np.asarray(result.channel("point_contact_force", name), dtype=float)[keep])
        v = np.linalg.norm(np.asarray(result.channel("point_slip_velocity", name))[keep], axis=1)
        ds = v * w
        ring_archard(m, j, ek, f, ds, k_w, info.c, worn=worn)
        work += float(np.sum(f * ds))
    return m, work
