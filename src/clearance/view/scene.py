"""A result file's motion, ready to draw: `load_scene(path)`.

The scene holds one time line (the frames of the run with clearance, `clearance.io.frames`),
every body's pose at those times for each run (a run with other frames, the ideal one, is
interpolated onto them: positions linearly, Euler parameters normalised-linearly), the
shapes to draw (`clearance.view.shapes`) and, per clearance joint, the eccentricity, the
contact force and normal in the outer (socket) marker frame, the contact state and the
event times. The HTML viewer (`clearance.view.html`) and the video (`clearance.view.video`)
draw from it.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from clearance.io.frames import MAX_FRAMES, frame_samples
from clearance.io.geometry import geometry_from_attrs, mechanism_geometry
from clearance.model.bodies import rotation_matrices
from clearance.view.shapes import body_shapes, joint_glyphs, mechanism_size
from clearance.view.shapes import nice_magnification as _nice

__all__ = [
    "ClearanceTrack",
    "RunMotion",
    "Scene",
    "SceneError",
    "load_scene",
    "scene_from_datasets",
]


class SceneError(ValueError):
    """A result file that cannot be drawn; the message names the file and what is missing."""


@dataclass
class RunMotion:
    """One run on the scene's time line: name, status text, poses (nframes, nbodies, 7) as
    (x, y, z, e0, e1, e2, e3), float32, bodies in `Scene.bodies` order."""

    name: str
    message: str
    success: bool
    poses: np.ndarray
    t_end: float
    present: list = field(default_factory=list)  # per body: 1 if this run has it


@dataclass
class ClearanceTrack:
    """One clearance joint at the frames. e: eccentricity (nframes, 3) and normal:
    contact normal (nframes, 3), force: contact force on the inner body (nframes, 3), all
    in the outer marker frame; fn: |F_N| (nframes,); contact: (nframes,) 0/1; events:
    (time, kind) of its contact events (kind +1 onset, -1 separation)."""

    info: dict
    e: np.ndarray
    force: np.ndarray
    normal: np.ndarray
    fn: np.ndarray
    contact: np.ndarray
    events: np.ndarray
    peak: float


@dataclass
class Scene:
    """Everything a viewer draws (module docstring)."""

    title: str
    source: str
    version: str
    time: np.ndarray
    bodies: list
    runs: list
    geometry: dict
    shapes: dict
    glyphs: dict
    size: float
    clearances: list = field(default_factory=list)
    magnification: float = 1.0
    scenario: str = ""
    attrs: dict = field(default_factory=dict)

    @property
    def primary(self) -> RunMotion:
        """The run whose frames the time line is (the clearance run when there is one)."""
        return self.runs[-1]


def _groups(path: Path) -> tuple[list[str], dict]:
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        root = {k: nc.getncattr(k) for k in nc.ncattrs()}
        groups = list(nc.groups)
    if "groups" in root:
        try:
            order = json.loads(root["groups"])
            groups = [g for g in order if g in groups] + [g for g in groups if g not in order]
        except (TypeError, ValueError):
            pass
    return groups, root


def read_file_layout(path: Path) -> tuple[list[str], dict]:
    """(run groups in order, root attributes) of a result file; a SceneError naming the
    file when it is missing or not NetCDF."""
    if not path.is_file():
        raise SceneError(f"{path}: no such file")
    try:
        return _groups(path)
    except OSError as e:
        raise SceneError(f"{path}: not a NetCDF result file ({e})") from None


def _open(path: Path, group: str):
    import xarray as xr

    return xr.open_dataset(path, group=group, engine="netcdf4")


def _geometry(path: Path, ds, root: dict, group: str) -> dict:
    try:
        g = geometry_from_attrs(ds.attrs)
    except ValueError as e:
        raise SceneError(f"{path}: group {group!r}: {e}") from None
    if g is not None:
        return g
    text = root.get("scenario")
    if not text:
        raise SceneError(
            f"{path}: group {group!r} records no geometry (attribute 'geometry') and the file "
            "holds no scenario to rebuild it from; re-run the scenario with this version"
        )
    from clearance.scenario import build_mechanisms, loads_scenario

    s = loads_scenario(text)
    ideal, clr, _ = build_mechanisms(s)
    return mechanism_geometry(clr if group != "ideal" else ideal)


def _poses(path: Path, ds, group: str, max_frames: int) -> tuple[np.ndarray, np.ndarray, list]:
    """(times, poses (n, nb, 7), body names) of every body from the frames group, or from
    the 'bodies' group of older files."""
    if "frame_position" in ds:
        names = [str(b) for b in ds["frame_body"].values]
        p = np.asarray(ds["frame_position"].values, dtype=np.float64)
        e = np.asarray(ds["frame_euler_parameters"].values, dtype=np.float64)
        return np.asarray(ds["frame_time"].values, dtype=float), np.concatenate([p, e], 2), names
    if "euler_parameters" in ds and "angular_velocity_body" in ds:  # every body stored
        t = np.asarray(ds["time"].values, dtype=float)
        ev = np.asarray(ds["event_time"].values) if "event_time" in ds else None
        flag = np.asarray(ds["contact_flag"].values) if "contact_flag" in ds else None
        force = (
            np.asarray(ds["point_contact_force"].values) if "point_contact_force" in ds else None
        )
        if force is None and flag is not None and "contact_force" in ds:
            force = np.asarray(ds["contact_force"].values)
            force = force if force.shape == flag.shape else None
        k = frame_samples(
            t, event_times=ev, contact_flag=flag, contact_force=force, max_frames=max_frames
        )
        p = np.asarray(ds["position"].values[k], dtype=np.float64)
        e = np.asarray(ds["euler_parameters"].values[k], dtype=np.float64)
        return t[k], np.concatenate([p, e], 2), [str(b) for b in ds["body"].values]
    raise SceneError(
        f"{path}: group {group!r} has no frames (the 'frames' output, which this version "
        "writes by default) and not every body's pose; re-run the scenario to draw it"
    )


def _resample(t_src: np.ndarray, poses: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Poses (n_src, nb, 7) at the times t: linear in position, normalised-linear in the
    Euler parameters (sign-aligned); held at the ends."""
    if t_src.size == t.size and np.array_equal(t_src, t):
        return poses
    k = np.clip(np.searchsorted(t_src, t, side="right") - 1, 0, max(t_src.size - 2, 0))
    if t_src.size == 1:
        return np.repeat(poses[:1], t.size, axis=0)
    t0, t1 = t_src[k], t_src[k + 1]
    w = np.clip((t - t0) / np.where(t1 > t0, t1 - t0, 1.0), 0.0, 1.0)[:, None, None]
    a, b = poses[k], poses[k + 1].copy()
    flip = np.sum(a[:, :, 3:] * b[:, :, 3:], axis=2) < 0
    b[:, :, 3:][flip] *= -1
    out = (1 - w) * a + w * b
    out[:, :, 3:] /= np.linalg.norm(out[:, :, 3:], axis=2, keepdims=True)
    return out


def _track(ds, info: dict, j: int, sample: np.ndarray, R_outer: np.ndarray, T_marker):
    """A ClearanceTrack of joint j (its index on the dataset's clearance dimension)."""
    R = R_outer @ np.asarray(T_marker, dtype=float)  # outer marker frame -> world (nf, 3, 3)
    Rt = np.transpose(R, (0, 2, 1))
    e = np.asarray(ds["eccentricity"].values[sample, j], dtype=float)
    fw = np.asarray(ds["normal_force"].values[sample, j], dtype=float)
    if "friction_force" in ds:
        fw = fw + np.asarray(ds["friction_force"].values[sample, j], dtype=float)
    nw = np.asarray(ds["contact_normal"].values[sample, j], dtype=float)
    fn = np.abs(np.asarray(ds["contact_force"].values[sample, j], dtype=float))
    name = info["name"]
    if "contact_flag" in ds and "contact_clearance" in ds:
        cols = [k for k, c in enumerate(ds["contact_clearance"].values) if str(c) == name]
        flag = np.asarray(ds["contact_flag"].values)[sample][:, cols]
        contact = (flag != 0).any(axis=1).astype(np.int8)
    else:
        contact = (fn > 0).astype(np.int8)
    ev = np.zeros((0, 2))
    if "event_time" in ds and ds.sizes.get("event", 0):
        mine = np.array([str(c) == name for c in ds["event_clearance"].values])
        ev = np.column_stack(
            [ds["event_time"].values[mine], ds["event_kind"].values[mine].astype(float)]
        )
    peak = float(ds["peak_contact_force"].values[j]) if "peak_contact_force" in ds else 0.0
    return ClearanceTrack(
        info=info,
        e=e,
        force=np.einsum("nij,nj->ni", Rt, fw),
        normal=np.einsum("nij,nj->ni", Rt, nw),
        fn=fn,
        contact=contact,
        events=ev,
        peak=max(peak, float(fn.max(initial=0.0))),
    )


def load_scene(
    path: str | os.PathLike,
    *,
    magnification: float | None = None,
    runs: list[str] | None = None,
    max_frames: int = MAX_FRAMES,
    view: dict | None = None,
) -> Scene:
    """Read a result file (`clearance run`'s NetCDF) into a Scene.

    magnification: factor the clearances are drawn with (default: a round number that
    makes the largest magnified clearance 30 % of its socket radius). runs: the groups to
    draw (default: all, in the file's order; the last one's frames are the time line).
    view: the scenario's [view] table (magnification, body overrides; default: the one the
    file keeps in its `view` attribute).
    """
    path = Path(path)
    groups, root = read_file_layout(path)
    if not groups:
        raise SceneError(f"{path}: no run groups; expected a result file of `clearance run`")
    if runs is not None:
        bad = [r for r in runs if r not in groups]
        if bad:
            raise SceneError(f"{path}: no run {bad[0]!r}; the file holds {', '.join(groups)}")
        groups = list(runs)
    opened: dict = {}
    try:
        for g in groups:
            opened[g] = _open(path, g)
        return scene_from_datasets(
            path, root, opened, magnification=magnification, max_frames=max_frames, view=view
        )
    finally:
        for ds in opened.values():
            ds.close()


def scene_from_datasets(
    source: str | os.PathLike,
    root: dict,
    datasets: dict,
    *,
    magnification: float | None = None,
    max_frames: int = MAX_FRAMES,
    view: dict | None = None,
) -> Scene:
    """The Scene of run datasets in memory ({group: xarray.Dataset}, in order; `root`: the
    file's root attributes), as `load_scene` reads them from a file (`clearance run` draws
    its report from the datasets it writes)."""
    path = Path(source)
    loaded = []
    for g, ds in datasets.items():
        t, poses, names = _poses(path, ds, g, max_frames)
        if t.size == 0:
            raise SceneError(f"{path}: group {g!r} has no frames (a run that stored no sample)")
        loaded.append((g, ds, t, poses, names, _geometry(path, ds, root, g)))
    if view is None and root.get("view"):  # the scenario's [view], kept by `clearance run`
        try:
            view = json.loads(root["view"])
        except (TypeError, ValueError):
            view = None
    if magnification is None and view:
        magnification = view.get("magnification")
    return _scene(path, root, loaded, magnification, view)


def _scene(path: Path, root: dict, loaded: list, magnification, view) -> Scene:
    g, ds, t, poses, names, geo = loaded[-1]  # the time line: the last run (clearance)
    bodies = names
    motions = []
    for gname, dsk, tk, pk, nk, _ in loaded:
        idx = [nk.index(b) if b in nk else -1 for b in bodies]
        full = np.zeros((pk.shape[0], len(bodies), 7))
        full[:, :, 3] = 1.0
        for col, k in enumerate(idx):
            if k >= 0:
                full[:, col] = pk[:, k]
        motions.append(
            RunMotion(
                name=gname,
                message=str(dsk.attrs.get("message", "")),
                success=bool(int(dsk.attrs.get("success", 1))),
                poses=_resample(tk, full, t).astype(np.float32),
                t_end=float(tk[-1]) if tk.size else 0.0,
                present=[int(k >= 0) for k in idx],
            )
        )
    pose0 = {b: (poses[0, k, :3], poses[0, k, 3:]) for k, b in enumerate(bodies)}
    size = mechanism_size(geo, pose0)
    overrides = (view or {}).get("bodies", {})
    tracks = []
    if geo["clearances"] and "eccentricity" in ds:
        names_c = [str(c) for c in ds["clearance"].values]
        if "frame_sample" in ds:
            sample = np.asarray(ds["frame_sample"].values, dtype=np.int64)
        else:  # files with every body instead of frames: the chosen samples
            sample = np.searchsorted(np.asarray(ds["time"].values), t)
        for info in geo["clearances"]:
            if info["name"] not in names_c:
                continue
            mk = geo["markers"][info["outer_marker"]]
            if mk["body"] in bodies:
                q = poses[:, bodies.index(mk["body"]), 3:]
                R_outer = rotation_matrices(q)
            else:  # on the ground
                R_outer = np.repeat(np.eye(3)[None], t.size, axis=0)
            tracks.append(
                _track(ds, info, names_c.index(info["name"]), sample, R_outer, mk["orientation"])
            )
    if magnification is None:
        ms = [_nice(c.info["outer_radius"], c.info["c"]) for c in tracks]
        magnification = min(ms) if ms else 1.0
    if magnification <= 0 or not np.isfinite(magnification):
        raise SceneError(f"magnification = {magnification}: expected a positive number")
    return Scene(
        title=str(root.get("scenario_name") or ds.attrs.get("mechanism", path.stem)),
        source=str(path),
        version=str(root.get("clearance_version", "")),
        time=np.asarray(t, dtype=float),
        bodies=bodies,
        runs=motions,
        geometry=geo,
        shapes=body_shapes(geo, size, overrides),
        glyphs=joint_glyphs(geo, size),
        size=size,
        clearances=tracks,
        magnification=float(magnification),
        scenario=str(root.get("scenario", "")),
        attrs={k: v for k, v in root.items() if isinstance(v, (str, int, float))},
    )
