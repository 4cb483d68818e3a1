"""A worn socket or bearing as the dynamics sees it (issue 16): the smooth depth field the
contact kernels read (`clearance.contact.field`, used by `clearance.contact.spherical` and
`clearance.contact.journal`), described here and packed by the compiler into
Model.clr_wear. A socket (`SocketWear`) is one field on the sphere; a bearing
(`BearingWear`) one per station, on the circle of its cross-section (a cubic B-spline
over the ring's equal cells, `BearingWear`).

    h(u) = sum_i h_i a_i phi(|u - c_i| / rho) / sum_i a_i phi(|u - c_i| / rho)

with phi(r) = (1 - r)^4 (4 r + 1) for r < 1, else 0 (Wendland's C2 function); u: a unit
direction from the socket's centre in the joint's outer (socket) marker frame; c_i: the
unit directions of the depth samples (the cells of a depth map), h_i >= 0 their depths [m],
a_i > 0 their solid angles (weights); rho: the smoothing radius, a chord length on the unit
sphere. This is Shepard's interpolation with a compactly supported weight: a partition of
unity, so a uniform depth is reproduced exactly, a smooth profile to second order in rho on
a regular grid, and h is twice continuously differentiable, so that the integrator sees a
smooth gap. Where no sample lies within rho the depth is 0; samples of depth 0 must
therefore be given around the worn ones (to 2 rho) for the denominator to be complete
(`clearance.wear.surface.SphereWearMap.socket_wear` does this).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from clearance.model.errors import ModelError

__all__ = ["BearingWear", "SocketWear", "ring_angles", "wendland_c2"]


def ring_angles(n: int) -> np.ndarray:
    """Centres theta_i = 2 pi (i + 1/2) / n [rad] of a bearing ring's n equal cells."""
    return 2.0 * np.pi * (np.arange(n) + 0.5) / n


def wendland_c2(r: np.ndarray) -> np.ndarray:
    """phi(r) = (1 - r)^4 (4 r + 1) for 0 <= r < 1, 0 beyond."""
    r = np.asarray(r, dtype=float)
    om = np.clip(1.0 - r, 0.0, None)
    return om**4 * (4.0 * r + 1.0)


@dataclass(frozen=True, eq=False)
class SocketWear:
    """Worn depth of a spherical clearance joint's socket (module docstring).

    directions: (N, 3) unit vectors c_i in the socket's marker frame; depths: (N,) h_i >= 0
    [m]; weights: (N,) a_i > 0 (solid angles of the samples' cells); smoothing: rho, a
    chord on the unit sphere in (0, 2].
    """

    directions: np.ndarray
    depths: np.ndarray
    weights: np.ndarray
    smoothing: float

    def __post_init__(self) -> None:
        who = "SocketWear"
        d = np.array(self.directions, dtype=float).reshape(-1, 3)
        h = np.array(self.depths, dtype=float).reshape(-1)
        w = np.array(self.weights, dtype=float).reshape(-1)
        for name, x in (("depths", h), ("weights", w)):
            if x.size != d.shape[0]:
                raise ModelError(
                    who, name, x.size, f"expected one value per direction ({d.shape[0]})"
                )
        if not np.all(np.isfinite(d)) or (
            d.size and np.max(np.abs(np.linalg.norm(d, axis=1) - 1.0)) > 1e-9
        ):
            raise ModelError(who, "directions", "(array)", "expected finite unit vectors")
        if not np.all(np.isfinite(h)) or np.any(h < 0):
            raise ModelError(who, "depths", "(array)", "expected finite numbers >= 0 [m]")
        if not np.all(np.isfinite(w)) or np.any(w <= 0):
            raise ModelError(who, "weights", "(array)", "expected finite numbers > 0")
        rho = float(self.smoothing)
        if not (0.0 < rho <= 2.0):
            raise ModelError(who, "smoothing", self.smoothing, "expected a chord length in (0, 2]")
        for name, x in (("directions", d), ("depths", h), ("weights", w)):
            x.setflags(write=False)
            object.__setattr__(self, name, x)
        object.__setattr__(self, "smoothing", rho)

    def rows(self) -> np.ndarray:
        """The kernel's rows (N, 5): c_x, c_y, c_z, h a, a (contact/spherical.py)."""
        return np.column_stack([self.directions, self.depths * self.weights, self.weights])

    def depth(self, u: np.ndarray) -> np.ndarray:
        """h at unit directions u (..., 3) [m]."""
        u = np.asarray(u, dtype=float)
        phi = wendland_c2(
            np.linalg.norm(u[..., None, :] - self.directions, axis=-1) / self.smoothing
        )
        num = phi @ (self.depths * self.weights)
        den = phi @ self.weights
        return np.where(num > 0, num / np.where(den > 0, den, 1.0), 0.0)

    def max_depth(self) -> float:
        """The largest sample depth [m] (h never exceeds it)."""
        return float(self.depths.max()) if self.depths.size else 0.0


@dataclass(frozen=True, eq=False)
class BearingWear:
    """Worn bearing of a revolute or cylindrical clearance joint, as its contact stations
    see it (`clearance.contact.journal`).

    depths: (stations, n) [m] >= 0, per station (in the order of the joint's stations
    along the bearing marker's h axis; one for a planar joint) the depth beyond the bearing
    radius of n equal cells, cell i centred at theta_i = 2 pi (i + 1/2) / n about h from the
    marker's f axis. Between them the depth is the uniform cubic B-spline smoother
    H(theta) = sum_i H_i B(theta / dtheta - 1/2 - i), dtheta = 2 pi / n (periodic; C2, 4
    cells wide, a profile's value shifted by H'' dtheta^2 / 6 and its slope by
    H''' dtheta^2 / 6). The depths are what the gap uses: `clearance.wear.bearing` passes
    the support depth of the worn surface (`BearingWearMap.bearing_wear`), whose reachable
    set is convex, so that the kernel's Newton iteration on the rim finds the global
    minimum of the distance; with other depths (a raw pocket narrower than the journal) it
    may stop at a rim's local minimum.
    """

    depths: np.ndarray

    def __post_init__(self) -> None:
        who = "BearingWear"
        h = np.array(self.depths, dtype=float)
        if h.ndim == 1:
            h = h[None, :]
        if h.ndim != 2 or h.shape[0] < 1 or h.shape[1] < 4:
            raise ModelError(
                who, "depths", f"shape {np.shape(self.depths)}", "expected (stations, n >= 4)"
            )
        if not np.all(np.isfinite(h)) or np.any(h < 0):
            raise ModelError(who, "depths", "(array)", "expected finite numbers >= 0 [m]")
        h.setflags(write=False)
        object.__setattr__(self, "depths", h)

    @property
    def stations(self) -> int:
        return int(self.depths.shape[0])

    @property
    def angles(self) -> np.ndarray:
        """theta_i [rad] of the n cells of each station."""
        return ring_angles(self.depths.shape[1])

    def ring_rows(self, station: int) -> np.ndarray:
        """The kernel's rows (n, 5) of one station, the depth in column 0 (the rest 0);
        (0, 5) for an unworn station (it keeps the unworn contact)."""
        h = self.depths[station]
        if not np.any(h > 0.0):
            return np.zeros((0, 5))
        rows = np.zeros((h.size, 5))
        rows[:, 0] = h
        return rows

    def depth(self, station: int, theta) -> np.ndarray:
        """The field H at angles theta [rad] of one station [m]."""
        h = self.depths[station]
        n = h.size
        x = np.asarray(theta, dtype=float) % (2.0 * np.pi) * n / (2.0 * np.pi) - 0.5
        i0 = np.floor(x).astype(int)
        out = np.zeros(x.shape)
        for j in range(-1, 3):
            r = np.abs(x - (i0 + j))
            b = np.where(
                r < 1.0, 2.0 / 3.0 - r**2 + 0.5 * r**3, np.clip(2.0 - r, 0.0, None) ** 3 / 6.0
            )
            out += h[(i0 + j) % n] * b
        return out

    def max_depth(self) -> float:
        """The largest cell depth [m]."""
        return float(self.depths.max())
