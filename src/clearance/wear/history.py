"""Wear of a spherical clearance joint's socket from a run's contact history (issue 16:
the output samples of one run; `clearance.wear.predict` loops over runs).

    from clearance.wear.history import socket_wear
    m = socket_wear(dataset, "S_1", k_w=1e-14, e_star=113.7e9, n=64)   # a SphereWearMap
    m.volume(), m.max_depth()

At each output sample in contact, Archard's law adds k_w p |v_slip| dt to the socket's
cells, in the socket (outer marker) frame: p the Hertz patch around the contact
direction (`hertz_patch`), or, given the socket's wear during the run (`worn`), the
elastic foundation's pressure over the ball's overlap with it (`overlap_patch`); both
vectorised by `archard_samples`. For a spherical joint
the contact direction is the eccentricity's, e / |e|, which the file holds in that frame.
dt is the trapezoid weight of the sample. The slip speed is the deepest point's
(`slip_velocity`); the pressure patch is centred on the contact point, so the slip is
taken as uniform over it (spin about the normal is neglected).

The samples are what the file holds: an impact shorter than the output step is missed,
and the volume converges as the output step shrinks. The integral of F_N |v_slip| dt over
the same samples is returned too, for the volume balance k_w * that.
"""

from __future__ import annotations

import numpy as np

from clearance.wear.surface import SphereWearMap, archard_samples, conformal_radius

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
    worn: SphereWearMap | None = None,
) -> tuple[SphereWearMap, float]:
    """(wear map of the socket of spherical clearance joint `joint`, integral of
    F_N |v_slip| dt over the samples [N m]) from a run's dataset (`clearance run`'s
    clearance group, or `result_to_dataset`). k_w: k / H [m^2 / N]; e_star: contact
    modulus [Pa]; n: cells per cube face; surface: a map to add to (default: a new one).
    worn: the socket's wear during the run (the map the run's SocketWear came from): the
    pressure is then the elastic foundation's over the ball's overlap with the worn
    surface (`overlap_patch`), else the Hertz patch at e / |e| of the unworn socket.
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
    if worn is not None and (worn.n != m.n or worn.depth.shape != m.depth.shape):
        raise ValueError(f"worn has {worn.n} cells per face, the map {m.n}: expected the same grid")
    t = np.asarray(ds["time"].values, dtype=float)
    w = trapezoid_weights(t)
    e = np.asarray(ds["eccentricity"].values[:, j], dtype=float)
    fn = np.abs(np.asarray(ds["contact_force"].values[:, j], dtype=float))
    slip = np.linalg.norm(np.asarray(ds["slip_velocity"].values[:, j], dtype=float), axis=1)
    use = np.flatnonzero((fn > 0) & (slip > 0) & (w > 0) & (np.linalg.norm(e, axis=1) > 0))
    ds_k = slip[use] * w[use]
    radius = conformal_radius(fn[use], r_in, r_out, e_star)
    archard_samples(m, e[use], fn[use], ds_k, radius, k_w, worn=worn, clearance=r_out - r_in)
    work = float(np.sum(fn[use] * ds_k))
    return m, work
