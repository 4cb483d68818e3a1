"""A worn socket as the dynamics sees it (issue 16): the smooth depth field the spherical
contact kernel reads (`clearance.contact.spherical`), described here and packed by the
compiler into Model.clr_wear.

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

__all__ = ["SocketWear", "wendland_c2"]


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
