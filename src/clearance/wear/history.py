"""Wear of a spherical clearance joint's socket from a run's contact history (issue 16,
second step: post-processing of the output samples; not yet fed back into the dynamics).

    from clearance.wear.history import socket_wear
    m = socket_wear(dataset, "S_1", k_w=1e-14, e_star=113.7e9, n=64)   # a SphereWearMap
    m.volume(), m.max_depth()

At each output sample in contact, Archard's law with a Hertz patch
(`clearance.wear.surface.archard_hertz`) adds k_w p |v_slip| dt to the socket's cells
around the contact direction, in the socket (outer marker) frame. For a spherical joint
the contact direction is the eccentricity's, e / |e|, which the file holds in that frame.
dt is the trapezoid weight of the sample. The slip speed is the deepest point's
(`slip_velocity`); the pressure patch is centred on the contact point, so the slip is
taken as uniform over it (spin about the normal is neglected).

The samples are what the file holds: an impact shorter than the output step is missed,
and the volume converges as the output step shrinks. The integral of F_N |v_slip| dt over
the same samples is returned too, for the volume balance k_w * that.
"""

from __future__ import annotations

import math

import numpy as np

from clearance.wear.surface import SphereWearMap, hertz_conformal

__all__ = ["socket_wear", "trapezoid_weights"]


def trapezoid_weights(t: np.ndarray) -> np.ndarray:
    """Weights w with sum(w f) the trapezoid rule of samples f at times t."""
    t = np.asarray(t, dtype=float)
    w = np.zeros_like(t)
    if t.size > 1:
        d = np.diff(t)
        w[:-1] += 0.5 * d
        w[1:] += 0.5 * d
    return w


def socket_wear(
    ds,
    joint: str,
    *,
    k_w: float,
    e_star: float,
    n: int = 64,
    surface: SphereWearMap | None = None,
) -> tuple[SphereWearMap, float]:
    """(wear map of the socket of spherical clearance joint `joint`, integral of
    F_N |v_slip| dt over the samples [N m]) from a run's dataset (`clearance run`'s
    clearance group, or `result_to_dataset`). k_w: k / H [m^2 / N]; e_star: contact
    modulus [Pa]; n: cells per cube face; surface: a map to add to (default: a new one).
    """
    names = [str(c) for c in ds["clearance"].values]
    if joint not in names:
        raise ValueError(f"no clearance joint {joint!r}; the dataset has {', '.join(names)}")
    j = names.index(joint)
    kind = str(ds["clearance_kind"].values[j]) if "clearance_kind" in ds else "spherical"
    if kind != "spherical":
        raise ValueError(f"{joint} is a {kind} clearance joint; socket_wear is for spherical ones")
    r_in = float(ds["ball_radius"].values[j])
    r_out = float(ds["socket_radius"].values[j])
    m = surface if surface is not None else SphereWearMap(r_out, n)
    t = np.asarray(ds["time"].values, dtype=float)
    w = trapezoid_weights(t)
    e = np.asarray(ds["eccentricity"].values[:, j], dtype=float)
    fn = np.abs(np.asarray(ds["contact_force"].values[:, j], dtype=float))
    slip = np.linalg.norm(np.asarray(ds["slip_velocity"].values[:, j], dtype=float), axis=1)
    work = 0.0
    centres = m.centres.reshape(-1, 3)
    areas = m.areas.reshape(-1)
    depth = m.depth.reshape(-1)  # (a view: adds go to the map)
    cos_min = 1.0
    for k in np.flatnonzero((fn > 0) & (slip > 0) & (w > 0)):
        norm = float(np.linalg.norm(e[k]))
        if norm == 0.0:
            continue
        u = e[k] / norm
        a, p0 = hertz_conformal(float(fn[k]), r_in, r_out, e_star)
        cos_min = math.cos(min(a / r_out, math.pi))
        near = np.flatnonzero(centres @ u > cos_min - 1e-12)
        r = r_out * np.arccos(np.clip(centres[near] @ u, -1.0, 1.0))
        p = np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
        total = float(np.sum(p * areas[near]))
        ds_k = float(slip[k] * w[k])
        if total <= 0.0:  # the patch misses every cell centre: the cell holding u
            f, i, jj = m.cell_of(u)
            flat = np.ravel_multi_index((f, i, jj), m.depth.shape)
            depth[flat] += k_w * fn[k] * ds_k / areas[flat]
        else:
            depth[near] += k_w * fn[k] * ds_k * p / total
        work += float(fn[k]) * ds_k
    return m, work
