"""A wear-depth map on a spherical surface (a socket, or a ball) in its body's frame.

Issue 16 (wear; docs/wear.md): the surface grid, its exact cell areas and worn volume;
Archard's law spread over the grid with a Hertz pressure patch (unworn) or the elastic
foundation's pressure over the ball's overlap with the worn socket; the reachable depth
and the smooth field the dynamics sees (`SphereWearMap.socket_wear`).

The grid is an equiangular cubed sphere: 6 faces of n x n cells, a face's points at
normalize(N + tan(xi) U + tan(eta) V) for xi, eta in [-pi/4, pi/4]. Unlike a
latitude-longitude grid it has no poles (a socket's load axis, where the wear is, would
be one) and its cells differ in area by at most a factor of about 1.3. Exact cell areas
follow from the area of a gnomonic rectangle, atan(X Y / sqrt(1 + X^2 + Y^2)) on the unit
sphere for X = tan(xi), Y = tan(eta) measured from the face centre; they sum to 4 pi R^2.

Depth h >= 0 [m] is stored per cell (material removed along the surface normal). The
volume removed is the shell volume, per cell Omega ((R + h)^3 - R^3) / 3 with Omega the
cell's solid angle, for a socket (material removed outward) and
Omega (R^3 - (R - h)^3) / 3 for a ball.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from clearance.model.wear import SocketWear

__all__ = [
    "SphereWearMap",
    "archard_hertz",
    "archard_samples",
    "hertz_conformal",
    "hertz_patch",
    "overlap_patch",
]

#: fewest cells in the overlap for its pressure distribution to be used (`overlap_patch`)
MIN_OVERLAP_CELLS = 7

# face k: (N, U, V) with U x V = N
_FACES = np.array(
    [
        [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        [[-1, 0, 0], [0, -1, 0], [0, 0, 1]],
        [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],
        [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
        [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
        [[0, 0, -1], [0, 1, 0], [1, 0, 0]],
    ],
    dtype=float,
)
_Q = math.pi / 4


def _corner_area(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Unit-sphere area of the gnomonic rectangle [0, X] x [0, Y] (signed)."""
    return np.arctan(X * Y / np.sqrt(1.0 + X * X + Y * Y))


@dataclass
class SphereWearMap:
    """Wear depth on a sphere of `radius` [m]: n x n cells per cube face (6 n^2 cells).

    outer: True for a socket (the surface is concave seen from the centre, material is
    removed outward); False for a ball. depth: (6, n, n) [m].
    """

    radius: float
    n: int = 32
    outer: bool = True
    depth: np.ndarray = field(default=None, repr=False)  # type: ignore[assignment]

    dims = ("face", "i", "j")  # of depth

    def __post_init__(self) -> None:
        if not (self.radius > 0 and math.isfinite(self.radius)):
            raise ValueError(f"radius = {self.radius}: expected a finite number > 0")
        if int(self.n) != self.n or self.n < 1:
            raise ValueError(f"n = {self.n}: expected an integer >= 1")
        self.n = int(self.n)
        if self.depth is None:
            self.depth = np.zeros((6, self.n, self.n))
        elif self.depth.shape != (6, self.n, self.n):
            raise ValueError(
                f"depth has shape {self.depth.shape}, expected (6, {self.n}, {self.n})"
            )
        edges = np.tan(np.linspace(-_Q, _Q, self.n + 1))
        X0, Y0 = np.meshgrid(edges[:-1], edges[:-1], indexing="ij")
        X1, Y1 = np.meshgrid(edges[1:], edges[1:], indexing="ij")
        omega = _corner_area(X1, Y1) - _corner_area(X0, Y1) - _corner_area(X1, Y0)
        omega += _corner_area(X0, Y0)
        self.solid_angle = np.broadcast_to(omega, (6, self.n, self.n)).copy()
        mid = np.tan(np.linspace(-_Q, _Q, 2 * self.n + 1)[1::2])
        Xc, Yc = np.meshgrid(mid, mid, indexing="ij")
        d = _FACES[:, 0, None, None, :] + Xc[None, :, :, None] * _FACES[:, 1, None, None, :]
        d = d + Yc[None, :, :, None] * _FACES[:, 2, None, None, :]
        self.centres = d / np.linalg.norm(d, axis=-1, keepdims=True)  # (6, n, n, 3)

    @property
    def areas(self) -> np.ndarray:
        """Cell areas on the unworn surface [m^2], (6, n, n)."""
        return self.solid_angle * self.radius**2

    def volume(self) -> float:
        """Volume of material removed [m^3] (module docstring)."""
        R, h = self.radius, np.clip(self.depth, 0.0, None)
        shell = (R + h) ** 3 - R**3 if self.outer else R**3 - np.clip(R - h, 0.0, None) ** 3
        return float(np.sum(self.solid_angle * shell) / 3.0)

    def max_depth(self) -> float:
        return float(self.depth.max())

    def cell_of(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(face, i, j) of the cells holding directions u (..., 3) (any length)."""
        u = np.asarray(u, dtype=float)
        proj = np.einsum("fk,...k->...f", _FACES[:, 0], u)
        f = np.argmax(proj, axis=-1)
        N, U, V = _FACES[f, 0], _FACES[f, 1], _FACES[f, 2]
        dn = np.sum(N * u, axis=-1)
        xi = np.arctan2(np.sum(U * u, axis=-1), dn)
        eta = np.arctan2(np.sum(V * u, axis=-1), dn)
        i = np.clip(((xi + _Q) / (2 * _Q) * self.n).astype(np.int64), 0, self.n - 1)
        j = np.clip(((eta + _Q) / (2 * _Q) * self.n).astype(np.int64), 0, self.n - 1)
        return f, i, j

    def reachable_depth(self, clearance: float) -> np.ndarray:
        """H (6, n, n) [m]: how far beyond the clearance c the ball's centre can move along
        each cell's direction u before it touches the worn socket anywhere,

            c + H(u) = min over v with u . v > 0 of (c + h(v)) / (u . v),

        the overlap of the ball (centre e) with the socket being e . v - c - h(v) in the
        direction v (to first order in c / R). So 0 <= H <= h; H = h for a surface the ball
        fits (its imprint, a wide shallow wear), and H < h at the bottom of a pocket
        narrower than the ball, which the ball cannot reach: it rests on the rim. The
        gap along the line of centres with H, |e| - c - H(e / |e|), is then zero exactly
        where the ball first touches the worn surface (contact/spherical.py)."""
        c = float(clearance)
        h = self.depth.reshape(-1)
        H = np.zeros_like(h)
        worn = np.flatnonzero(h > 0.0)
        if worn.size == 0:
            return H.reshape(self.depth.shape)
        from scipy.spatial import cKDTree

        # An unworn u has H = 0 (v = u gives c). For a worn u the unworn v give at least
        # c / (u . v) for the nearest of them, and only v with u . v > c / (c + h_max) can
        # go below c + h(u): so the worn cells and the nearest unworn one suffice.
        cells = self.centres.reshape(-1, 3)
        W, hw = cells[worn], h[worn]
        cos_n = c / (c + float(hw.max()))
        bound = np.full(worn.size, np.inf)
        unworn = np.flatnonzero(h <= 0.0)
        if unworn.size:
            d, _ = cKDTree(cells[unworn]).query(W)
            cos_u = 1.0 - 0.5 * d * d  # chord -> cosine
            bound = np.where(cos_u > 0.0, c / np.where(cos_u > 0.0, cos_u, 1.0), np.inf)
        step = max(1, 4_000_000 // worn.size)
        for i in range(0, worn.size, step):
            cos = W[i : i + step] @ W.T
            ratio = np.where(cos > cos_n, (c + hw) / np.where(cos > cos_n, cos, 1.0), np.inf)
            H[worn[i : i + step]] = np.minimum(ratio.min(axis=1), bound[i : i + step]) - c
        return np.clip(H, 0.0, h).reshape(self.depth.shape)

    def socket_wear(self, clearance: float, smoothing: float = 2.0) -> SocketWear:
        """The worn socket as the dynamics sees it (`clearance.model.wear.SocketWear`): the
        reachable depth H (`reachable_depth`) interpolated by Shepard's method with a
        Wendland weight of radius rho = smoothing x the cells' mean width (pi / 2 / n on
        the unit sphere; smoothing >= 1, else the weights leave holes), over the cells
        with H > 0 and those within 2 rho of them."""
        from scipy.spatial import cKDTree

        if not self.outer:
            raise ValueError("socket_wear: this map is a ball's (outer=False)")
        if not smoothing >= 1.0:
            raise ValueError(f"smoothing = {smoothing}: expected a number >= 1 (cell widths)")
        rho = min(2.0, smoothing * 0.5 * math.pi / self.n)
        c = self.centres.reshape(-1, 3)
        h = self.reachable_depth(clearance).reshape(-1)
        worn = h > 0.0
        if not worn.any():
            return SocketWear(np.zeros((0, 3)), np.zeros(0), np.zeros(0), rho)
        dist, _ = cKDTree(c[worn]).query(c, distance_upper_bound=2.0 * rho)
        keep = np.isfinite(dist)
        return SocketWear(c[keep], h[keep], self.solid_angle.reshape(-1)[keep], rho)

    def wear_model(self, clearance: float, smoothing: float = 2.0) -> SocketWear:
        """`socket_wear` (the wear loop's name for any map: `BearingWearMap.wear_model`)."""
        return self.socket_wear(clearance, smoothing)

    def overlap(self, e: np.ndarray, clearance: float) -> np.ndarray:
        """(6 n^2,) the overlap e . v - c - h(v) [m] of the ball centred at e (socket
        frame, from the socket's centre) with each cell v (> 0: the ball is inside the
        worn surface there; to first order in c / R)."""
        return (
            self.centres.reshape(-1, 3) @ np.asarray(e, float) - clearance - self.depth.reshape(-1)
        )

    def depth_at(self, u: np.ndarray) -> np.ndarray:
        """The depth of the cells holding directions u (piecewise constant; the smooth
        interpolant the worn gap function needs comes with that step)."""
        f, i, j = self.cell_of(u)
        return self.depth[f, i, j]


def hertz_conformal(
    force: float, r_inner: float, r_outer: float, e_star: float
) -> tuple[float, float]:
    """Hertz contact of a ball (r_inner) in a socket (r_outer > r_inner): (a, p0), the
    contact radius [m] and peak pressure [Pa] under `force` [N]; e_star [Pa] the contact
    modulus 1 / ((1 - nu1^2) / E1 + (1 - nu2^2) / E2). R* = r_inner r_outer / (r_outer -
    r_inner), a = (3 F R* / (4 E*))^(1/3), p0 = 3 F / (2 pi a^2) (Johnson, Contact
    Mechanics ch. 4; valid while a << R: docs/notes/wear-literature.md section 2)."""
    if force <= 0:
        conformal_radius(np.zeros(0), r_inner, r_outer, e_star)  # (checks the radii)
        return 0.0, 0.0
    a = float(conformal_radius(np.asarray(force, float), r_inner, r_outer, e_star))
    return a, 3.0 * force / (2.0 * math.pi * a * a)


def conformal_radius(
    force: np.ndarray, r_inner: float, r_outer: float, e_star: float
) -> np.ndarray:
    """Hertz's contact radius a = (3 F R* / (4 E*))^(1/3) [m] of `hertz_conformal`, for an
    array of forces > 0 [N]."""
    if not r_outer > r_inner > 0:
        raise ValueError(f"radii {r_inner}, {r_outer}: expected 0 < inner < outer")
    r_star = r_inner * r_outer / (r_outer - r_inner)
    return (3.0 * force * r_star / (4.0 * e_star)) ** (1.0 / 3.0)


def archard_hertz(
    surface: SphereWearMap,
    normal: np.ndarray,
    force: float,
    contact_radius: float,
    slip: float,
    k_w: float,
) -> np.ndarray:
    """Archard's law for one contact over a slip distance: the depth added to each cell
    (6, n, n) [m], also added to `surface.depth`.

    normal: the contact direction from the sphere's centre (surface frame); force: normal
    force F [N]; contact_radius: a [m] (`hertz_conformal`); slip: sliding distance s [m]
    (|v_slip| dt); k_w: wear coefficient k / H [m^2/N]. The pressure is Hertz's,
    p0 sqrt(1 - r^2 / a^2) with r the arc length from the contact point, sampled at the
    cell centres and scaled so that sum(p A) = F: the volume removed is k_w F s exactly
    (to first order in h / R), whatever the grid; the depth profile converges with it. A
    patch smaller than the cells falls into the cell holding the contact point.
    """
    dh = np.zeros_like(surface.depth)
    cells, values = hertz_patch(surface, normal, force, contact_radius, slip, k_w)
    dh.reshape(-1)[cells] = values
    surface.depth += dh
    return dh


def hertz_patch(
    surface: SphereWearMap,
    normal: np.ndarray,
    force: float,
    contact_radius: float,
    slip: float,
    k_w: float,
) -> tuple[np.ndarray, np.ndarray]:
    """(flat cell indices, depth increments [m]) of `archard_hertz`, without adding them:
    only the cells whose centres lie in the patch (or the one cell holding the contact
    point when the patch misses every centre)."""
    if force <= 0 or slip <= 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0)
    u = np.asarray(normal, dtype=float)
    u = u / np.linalg.norm(u)
    R = surface.radius
    centres = surface.centres.reshape(-1, 3)
    areas = surface.areas.reshape(-1)
    cos_min = math.cos(min(contact_radius / R, math.pi))
    near = np.flatnonzero(centres @ u > cos_min - 1e-12)
    r = R * np.arccos(np.clip(centres[near] @ u, -1.0, 1.0))
    p = np.sqrt(np.clip(1.0 - (r / contact_radius) ** 2, 0.0, None))
    keep = p > 0
    near, p = near[keep], p[keep]
    total = float(np.sum(p * areas[near]))
    if total <= 0.0:  # the patch misses every cell centre: the cell holding u
        f, i, j = surface.cell_of(u)
        cell = int(np.ravel_multi_index((int(f), int(i), int(j)), surface.depth.shape))
        return np.array([cell]), np.array([k_w * force * slip / areas[cell]])
    return near, k_w * force * slip * p / total


def overlap_floor(d: np.ndarray, K: int = MIN_OVERLAP_CELLS) -> np.ndarray:
    """Per row of overlaps d (k, m): 0 where K (default MIN_OVERLAP_CELLS) or more are
    positive, else the largest value below the K-th largest (so that at least K lie above
    it; equal values, a symmetric ring of cells, all do or all do not)."""
    m = d.shape[1]
    if m <= K:
        return np.minimum(0.0, d.min(axis=1) - 1e-12)
    top = -np.sort(-np.partition(d, m - min(m, 8 * K), axis=1)[:, m - min(m, 8 * K) :], axis=1)
    below = top < top[:, K - 1 : K]  # strictly below the K-th largest
    below[:, :K] = False
    j = np.where(below.any(axis=1), np.argmax(below, axis=1), top.shape[1] - 1)
    floor = top[np.arange(top.shape[0]), j]
    floor = np.where(below.any(axis=1), floor, floor - 1e-12)  # (all tied: just below them)
    return np.minimum(0.0, floor)


def overlap_patch(
    surface: SphereWearMap,
    e: np.ndarray,
    clearance: float,
    force: float,
    slip: float,
    k_w: float,
) -> tuple[np.ndarray, np.ndarray]:
    """(flat cell indices, depth increments [m]) of Archard's law for one contact of the
    ball centred at e (socket frame) with the socket as worn in `surface`: the pressure is
    the elastic foundation's, proportional to the overlap d(v) = e . v - c - h(v) > 0 of
    each cell (SphereWearMap.overlap), scaled so that sum(p A) = force; so the wear goes
    where the ball presses into the worn surface (its seat; the rim of a pocket narrower
    than the ball). Where fewer than MIN_OVERLAP_CELLS cells overlap (an elastic contact
    short of the cells), the ball is taken as pushed further until that many do:
    p ~ (d - d_K)+ with d_K the largest overlap below the MIN_OVERLAP_CELLS-th, which keeps
    the distribution's shape and symmetry (a Hertz patch at the one deepest cell put a
    rim's ring of equal cells' wear on one of them). The volume is k_w F s."""
    if force <= 0 or slip <= 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0)
    d = surface.overlap(e, clearance)
    tau = float(overlap_floor(d[None, :])[0])
    inside = np.flatnonzero(d > tau)
    w = (d[inside] - tau) * surface.areas.reshape(-1)[inside]
    return inside, k_w * force * slip * (d[inside] - tau) / float(np.sum(w))


def archard_samples(
    target: SphereWearMap,
    e: np.ndarray,
    force: np.ndarray,
    slip: np.ndarray,
    contact_radius: np.ndarray,
    k_w: float,
    *,
    worn: SphereWearMap | None = None,
    clearance: float = 0.0,
    chunk: int = 256,
) -> None:
    """Add to target.depth the wear of many contact samples at once: rows of e (k, 3) [m]
    (ball centre from the socket's centre, socket frame), force (k,) [N], slip (k,) slip
    distance [m], contact_radius (k,) Hertz radius [m]. Each sample is deposited as
    `overlap_patch` (worn given: the socket's wear during the run, same grid) or
    `hertz_patch` at e / |e| (worn None, radius contact_radius) would deposit it;
    vectorised over chunks of consecutive samples, each over the cells near that chunk's
    contact directions."""
    e = np.asarray(e, float).reshape(-1, 3)
    force, slip = np.asarray(force, float), np.asarray(slip, float)
    a = np.asarray(contact_radius, float)
    cells = target.centres.reshape(-1, 3)
    areas = target.areas.reshape(-1)
    out = target.depth.reshape(-1)  # (a view)
    R = target.radius
    width = 0.5 * math.pi / target.n  # a cell's mean width [rad]
    h = worn.depth.reshape(-1) if worn is not None else np.zeros(cells.shape[0])
    if worn is not None and h.shape != out.shape:
        raise ValueError(f"worn has {worn.n} cells per face, the target {target.n}")
    worn_any = bool(worn is not None and h.any())
    use = np.flatnonzero((force > 0) & (slip > 0) & (np.linalg.norm(e, axis=1) > 0))
    for i in range(0, use.size, chunk):
        k = use[i : i + chunk]
        E = e[k]
        el = np.linalg.norm(E, axis=1)
        n = E / el[:, None]
        mean = n.sum(axis=0)
        norm = float(np.linalg.norm(mean))
        mean = mean / norm if norm > 1e-9 else n[0]
        dev = float(np.max(np.arccos(np.clip(n @ mean, -1.0, 1.0))))
        a_k = a[k]
        cap = reach = 0.0
        if worn is not None:  # the overlap lies in the unworn one's cap around e / |e|
            cap = float(np.max(np.arccos(np.clip(clearance / el, -1.0, 1.0))))
        if worn_any:  # and the deepest overlap where e . v - c >= |e| - c - h_max
            reach = math.acos(max(-1.0, 1.0 - float(h.max()) / float(el.min())))
        # the overlap lies within cap of e / |e| and the largest overlaps within reach of
        # it (worn); a Hertz patch within a / R of e / |e| (unworn)
        ang = dev + (max(cap, reach) if worn is not None else float(np.max(a_k)) / R)
        ang += 4.0 * width
        local = np.flatnonzero(cells @ mean > math.cos(min(ang, math.pi)))
        C, A = cells[local], areas[local]
        fs = k_w * force[k] * slip[k]
        dep = np.zeros((k.size, local.size))
        centre = n
        hertz = np.ones(k.size, dtype=bool)  # (worn None: Hertz patches at e / |e|)
        if worn is not None:  # (overlap_patch)
            D = E @ C.T - clearance - h[local]
            tau = overlap_floor(D)
            W = np.clip(D - tau[:, None], 0.0, None)
            dep = fs[:, None] * W / (W @ A)[:, None]
            hertz[:] = False
        if hertz.any():
            cosr = np.clip(centre[hertz] @ C.T, -1.0, 1.0)
            P = np.sqrt(np.clip(1.0 - (R * np.arccos(cosr) / a_k[hertz, None]) ** 2, 0.0, None))
            tot = P @ A
            ok = tot > 0.0
            rows = np.flatnonzero(hertz)
            dep[rows[ok]] = fs[rows[ok], None] * P[ok] / tot[ok, None]
            for r in rows[~ok]:  # the patch misses every cell centre: the cell holding it
                f, ii, jj = target.cell_of(centre[r])
                cell = int(np.ravel_multi_index((int(f), int(ii), int(jj)), target.depth.shape))
                out[cell] += fs[r] / areas[cell]
        out[local] += dep.sum(axis=0)
