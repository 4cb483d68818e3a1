"""The papers' figures, drawn from saved datasets only (never simulates).

`plot_all(datasets, out_dir)` takes the groups of a results file ({"ideal": ds, "clearance":
ds, ...}, see `clearance.io.dataset`) and writes, each as PNG and PDF (atomically):

* `platform_displacement`, `platform_velocity`, `platform_acceleration`: 2 x 3 panels, top
  row x, y, z of the platform's mass centre, bottom row the angular components about the
  world x, y, z axes; every run overlaid (the run named "ideal" dashed black).
  Displacement: r(t) - r_ref(0) [mm], and the rotation vector of R(t) R_ref(0)^T [mrad]
  (world components, exact for any angle; for small angles these are the small-angle
  rotations about x, y, z), where ref is the "ideal" run (else the first one), so that
  all runs share one reference pose. Velocity: r_dot [m/s] and the world angular
  velocity [rad/s]. Acceleration: r_ddot [m/s^2] and the world angular acceleration
  R omega'_dot [rad/s^2].
* `contact_force`: |F_N| [N] vs time, one panel per clearance joint, runs overlaid.
* per clearance joint, by its kind (`clearance_kind`; files without it are spherical):
  `ball_trajectory_<joint>`: ball centre relative to the socket centre in the socket frame
  [mm]: a 3-D curve inside the wire sphere of radius c, and the x-y, x-z, y-z projections
  with the clearance circle; `journal_trajectory_<joint>` (revolute, cylindrical): the
  journal centre in the bearing's cross-section (f-g plane of the bearing marker) inside the
  clearance circle, and its axial offset (h) against time; `slider_offset_<joint>`
  (prismatic): the slider centre's offset in the guide against time, width direction (f)
  within the clearance band, and height (g) in the spatial model. The stretches in contact
  are drawn in red.
* `actuator_forces`: the actuator force of each driver row [N], runs overlaid.

Uses the Figure API (no pyplot), so no global backend is changed and nothing opens a window.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import matplotlib as mpl
import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from clearance.io.dataset import rotation_matrices
from clearance.io.files import atomic_path

STYLE = {
    "font.size": 9,
    "axes.labelsize": 9,
    "axes.titlesize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "lines.linewidth": 1.1,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.5,
    "savefig.dpi": 200,
    "axes.formatter.limits": (-3, 4),
    "axes.formatter.use_mathtext": True,
}
AXES = ("x", "y", "z")


def _styled(fn: Callable) -> Callable:
    """Run a figure builder under the publication style `STYLE`."""

    @functools.wraps(fn)
    def wrapper(*args, **kw):
        with mpl.rc_context(STYLE):
            return fn(*args, **kw)

    return wrapper


def _styles(datasets: Mapping[str, xr.Dataset]) -> dict[str, dict]:
    """Line style per run: "ideal" dashed black on top, the others solid C0, C1, ..."""
    out, k = {}, 0
    for name in datasets:
        if name == "ideal":
            out[name] = {"color": "k", "linestyle": "--", "zorder": 3}
        else:
            out[name] = {"color": f"C{k}", "linestyle": "-", "zorder": 2}
            k += 1
    return out


def save_figure(
    fig: Figure, out_dir: str | os.PathLike, stem: str, formats: Sequence[str]
) -> list[Path]:
    """Save `fig` as out_dir/stem.<fmt> for each format, each file atomically."""
    out = []
    for fmt in formats:
        p = Path(out_dir) / f"{stem}.{fmt}"
        with atomic_path(p) as tmp, mpl.rc_context(STYLE):
            fig.savefig(tmp, format=fmt, dpi=STYLE["savefig.dpi"], bbox_inches="tight")
        out.append(p)
    return out


def _reference(datasets: Mapping[str, xr.Dataset]) -> str:
    return "ideal" if "ideal" in datasets else next(iter(datasets))


def rotation_vector(R: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotation matrices -> (..., 3) rotation vectors theta * axis [rad]."""
    from scipy.spatial.transform import Rotation

    shape = R.shape[:-2]
    return Rotation.from_matrix(R.reshape(-1, 3, 3)).as_rotvec().reshape(*shape, 3)


def platform_motion(
    ds: xr.Dataset, ref: xr.Dataset, platform: str = "platform"
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """(translational, angular) (n, 3) histories of `platform` in run `ds`, world frame.

    Keys: "displacement" (r - r_ref(0) [m], rotation vector of R R_ref(0)^T [rad]),
    "velocity" ([m/s], [rad/s]), "acceleration" ([m/s^2], [rad/s^2]); ref is the run whose
    initial pose is the origin of the displacement.
    """
    for d in (ds, ref):
        if platform not in d["body"].values:
            raise KeyError(f"no body named {platform!r}; bodies: {list(d['body'].values)}")

    def sel(d: xr.Dataset, v: str) -> np.ndarray:
        return np.asarray(d[v].sel(body=platform).transpose("time", "axis").values)

    r0 = sel(ref, "position")[0]
    R0 = rotation_matrices(_euler_parameters(ref, platform)[0])
    R = rotation_matrices(_euler_parameters(ds, platform))
    return {
        "displacement": (sel(ds, "position") - r0, rotation_vector(R @ R0.T)),
        "velocity": (sel(ds, "velocity"), sel(ds, "angular_velocity")),
        "acceleration": (sel(ds, "acceleration"), sel(ds, "angular_acceleration")),
    }


def _euler_parameters(ds: xr.Dataset, body: str) -> np.ndarray:
    """(n, 4) Euler parameters of `body`."""
    return np.asarray(ds["euler_parameters"].sel(body=body).transpose("time", "quat").values)


_MOTION = {
    # key: (translation label, scale, unit, angular label, scale, unit)
    "displacement": ("\\Delta {a}", 1e3, "mm", "\\theta_{a}", 1e3, "mrad"),
    "velocity": ("\\dot{{{a}}}", 1.0, "m/s", "\\omega_{a}", 1.0, "rad/s"),
    "acceleration": ("\\ddot{{{a}}}", 1.0, "m/s$^2$", "\\alpha_{a}", 1.0, "rad/s$^2$"),
}


@_styled
def plot_platform(
    datasets: Mapping[str, xr.Dataset], kind: str, *, platform: str = "platform"
) -> Figure:
    """2 x 3 figure of platform `kind` ("displacement", "velocity", "acceleration")."""
    sty = _styles(datasets)
    lab_t, sc_t, u_t, lab_r, sc_r, u_r = _MOTION[kind]
    ref = datasets[_reference(datasets)]
    fig = Figure(figsize=(7.5, 4.2), layout="constrained")
    axs = fig.subplots(2, 3, sharex=True)
    for name, ds in datasets.items():
        tr, rot = platform_motion(ds, ref, platform)[kind]
        t = ds["time"].values
        for j in range(3):
            axs[0, j].plot(t, tr[:, j] * sc_t, label=name, **sty[name])
            axs[1, j].plot(t, rot[:, j] * sc_r, label=name, **sty[name])
    for j, a in enumerate(AXES):
        axs[0, j].set_ylabel(f"${lab_t.format(a=a)}$ [{u_t}]")
        axs[1, j].set_ylabel(f"${lab_r.format(a=a)}$ [{u_r}]")
        axs[1, j].set_xlabel("time [s]")
    h, lab = axs[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, loc="outside lower center", ncols=max(1, len(lab)), frameon=False)
    fig.suptitle(f"Platform {kind} ({platform})", fontsize=10)
    return fig


def _clearance_runs(datasets: Mapping[str, xr.Dataset]) -> list[str]:
    names: list[str] = []
    for ds in datasets.values():
        if "clearance" in ds.dims:
            names += [str(c) for c in ds["clearance"].values if str(c) not in names]
    return names


@_styled
def plot_contact_force(datasets: Mapping[str, xr.Dataset]) -> Figure | None:
    """|F_N| per clearance joint vs time (None when no run has a clearance joint)."""
    sty = _styles(datasets)
    joints = _clearance_runs(datasets)
    if not joints:
        return None
    fig = Figure(figsize=(7.0, 1.2 + 1.6 * len(joints)), layout="constrained")
    axs = np.atleast_1d(fig.subplots(len(joints), 1, sharex=True, squeeze=False)[:, 0])
    for ax, jn in zip(axs, joints, strict=True):
        for name, ds in datasets.items():
            if jn in ds["clearance"].values:
                f = ds["contact_force"].sel(clearance=jn).values
                ax.plot(ds["time"].values, f, label=name, **sty[name])
        ax.set_ylabel("$F_N$ [N]")
        ax.set_title(f"clearance joint {jn}", loc="left")
        ax.legend(loc="upper right", frameon=False)
    axs[-1].set_xlabel("time [s]")
    fig.suptitle("Normal contact force", fontsize=10)
    return fig


@_styled
def plot_ball_trajectory(datasets: Mapping[str, xr.Dataset], joint: str) -> Figure:
    """Ball-centre path in the socket of `joint`: 3-D view and three projections [mm]."""
    sty = _styles(datasets)
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3-D projection)

    runs = _joint_runs(datasets, joint)
    c = 1e3 * float(runs[0][1]["radial_clearance"].sel(clearance=joint))
    lim = 1.15 * c
    fig = Figure(figsize=(7.0, 6.6), layout="constrained")
    ax3 = fig.add_subplot(2, 2, 1, projection="3d")
    proj = [
        (fig.add_subplot(2, 2, i), i0, i1) for i, (i0, i1) in zip((2, 3, 4), _PAIRS, strict=True)
    ]
    u, v = np.mgrid[0 : 2 * np.pi : 25j, 0 : np.pi : 13j]
    ax3.plot_wireframe(
        c * np.cos(u) * np.sin(v),
        c * np.sin(u) * np.sin(v),
        c * np.cos(v),
        color="0.75",
        linewidth=0.3,
    )
    for name, ds in runs:
        e = 1e3 * ds["eccentricity"].sel(clearance=joint).transpose("time", "axis").values
        on = ds["penetration"].sel(clearance=joint).values > 0
        st = dict(sty[name])
        st.pop("zorder")
        # the in-contact stretches as one red path with breaks (NaN) between them: a dot per
        # sample in contact (~19 000 of 20 001 in the default scenario) made 0.8 MB PDFs;
        # a contact seen by one sample only has no stretch to draw: a dot marks it
        _trace(ax3, e, on, name, st)
        for ax, i0, i1 in proj:
            _trace(ax, e[:, [i0, i1]], on, name, st)
            if e.shape[0]:
                ax.plot(e[0, i0], e[0, i1], "o", color=st["color"], markersize=4, mfc="none")
    for ax, i0, i1 in proj:
        _clearance_circle(ax, c)
        ax.set_xlabel(f"$e_{AXES[i0]}$ [mm]")
        ax.set_ylabel(f"$e_{AXES[i1]}$ [mm]")
    for setlim in (ax3.set_xlim, ax3.set_ylim, ax3.set_zlim):
        setlim(-lim, lim)
    ax3.set_box_aspect((1, 1, 1))
    ax3.set_xlabel("$e_x$ [mm]", labelpad=-2)
    ax3.set_ylabel("$e_y$ [mm]", labelpad=-2)
    ax3.set_zlabel("$e_z$ [mm]", labelpad=-4)
    fig.get_layout_engine().set(w_pad=0.15, wspace=0.12)
    ax3.tick_params(labelsize=7, pad=0)
    _contact_legend(proj[0][0], "in contact", f"clearance c = {c:.3g} mm")
    fig.suptitle(f"Ball centre in the socket of {joint} (socket frame)", fontsize=10)
    return fig


_PAIRS = ((0, 1), (0, 2), (1, 2))


def _contact_path(e: np.ndarray, on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(e with the free stretches blanked, the samples that are lone contacts): the red
    in-contact path as one line with NaN breaks, and dots for contacts one sample long."""
    ec = np.where(on[:, None], e, np.nan)
    alone = on & ~np.r_[False, on[:-1]] & ~np.r_[on[1:], False]
    return ec, alone


def _trace(ax, x: np.ndarray, on: np.ndarray, name: str, st: dict) -> None:
    """A run's path x (n, 2 or 3 plotted coordinates) with its in-contact stretches in red
    (one line with NaN breaks, see `_contact_path`) and its one-sample contacts as dots."""
    ec, alone = _contact_path(x, on)
    ax.plot(*x.T, label=name, **st)
    ax.plot(*ec.T, "-", color="C3", linewidth=1.6, label="_")
    ax.plot(*x[alone].T, ".", color="C3", markersize=3, label="_")


def _clearance_circle(ax, c: float) -> None:
    """The clearance circle of radius c, dashed, in equal axes of half-width 1.15 c."""
    ax.add_patch(Circle((0, 0), c, fill=False, color="0.4", linestyle="--", linewidth=0.8))
    lim = 1.15 * c
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")


def _contact_legend(ax, contact: str, clearance: str) -> None:
    """Legend of the runs plus keys for the red in-contact path and the dashed clearance."""
    ax.plot([], [], "-", color="C3", linewidth=1.6, label=contact)
    ax.plot([], [], "--", color="0.4", label=clearance)
    ax.legend(loc="upper right", frameon=True, fontsize=7, framealpha=0.8)


def _joint_runs(datasets: Mapping[str, xr.Dataset], joint: str) -> list[tuple[str, xr.Dataset]]:
    runs = [(n, ds) for n, ds in datasets.items() if joint in ds["clearance"].values]
    if not runs:
        raise KeyError(f"no run has a clearance joint named {joint!r}")
    return runs


@_styled
def plot_journal_trajectory(datasets: Mapping[str, xr.Dataset], joint: str) -> Figure:
    """Journal centre in the bearing of revolute / cylindrical clearance joint `joint` [mm]:
    the cross-section (bearing marker f, g axes) with the clearance circle, and, if the
    journal moves axially (cylindrical joint, thrust clearance), its axial offset (h)."""
    sty = _styles(datasets)
    runs = _joint_runs(datasets, joint)
    c = 1e3 * float(runs[0][1]["radial_clearance"].sel(clearance=joint))
    ecc = {
        name: 1e3 * ds["eccentricity"].sel(clearance=joint).transpose("time", "axis").values
        for name, ds in runs
    }
    axial = max(float(np.ptp(e[:, 2])) if e.size else 0.0 for e in ecc.values()) > 1e-6 * c
    fig = Figure(figsize=(7.5 if axial else 4.0, 3.6), layout="constrained")
    ax, axh = fig.subplots(1, 2, width_ratios=(1.0, 1.3)) if axial else (fig.subplots(), None)
    for name, ds in runs:
        e = ecc[name]
        on = ds["penetration"].sel(clearance=joint).values > 0
        st = {k: v for k, v in sty[name].items() if k != "zorder"}
        _trace(ax, e[:, :2], on, name, st)
        if axh is not None:
            axh.plot(ds["time"].values, e[:, 2], label=name, **st)
    _clearance_circle(ax, c)
    ax.set_xlabel("$e_f$ [mm]")
    ax.set_ylabel("$e_g$ [mm]")
    _contact_legend(ax, "in contact", f"clearance c = {c:.3g} mm")
    if axh is not None:
        axh.set_xlabel("time [s]")
        axh.set_ylabel("axial offset $e_h$ [mm]")
    fig.suptitle(f"Journal centre in the bearing of {joint} (bearing frame)", fontsize=10)
    return fig


@_styled
def plot_slider_offset(datasets: Mapping[str, xr.Dataset], joint: str) -> Figure:
    """Slider centre's offset in the guide of prismatic clearance joint `joint` [mm] against
    time: width direction (guide f axis) within the clearance band, and the height
    direction (g) when the model lets it move."""
    sty = _styles(datasets)
    runs = _joint_runs(datasets, joint)
    c = 1e3 * float(runs[0][1]["radial_clearance"].sel(clearance=joint))
    spatial = any(
        "clearance_model" in ds.coords
        and str(ds["clearance_model"].sel(clearance=joint).values) == "spatial"
        for _, ds in runs
    )
    fig = Figure(figsize=(7.0, 2.0 + 1.6 * (2 if spatial else 1)), layout="constrained")
    axs = np.atleast_1d(fig.subplots(2 if spatial else 1, 1, sharex=True, squeeze=False)[:, 0])
    for name, ds in runs:
        e = 1e3 * ds["eccentricity"].sel(clearance=joint).transpose("time", "axis").values
        on = ds["penetration"].sel(clearance=joint).values > 0
        t = ds["time"].values
        st = {k: v for k, v in sty[name].items() if k != "zorder"}
        for ax, k in zip(axs, (0, 1), strict=False):
            _trace(ax, np.column_stack([t, e[:, k]]), on, name, st)
    for ax, lab in zip(axs, ("$e_f$ (width)", "$e_g$ (height)"), strict=False):
        for sgn in (-1, 1):
            ax.axhline(sgn * c, color="0.4", linestyle="--", linewidth=0.8)
        ax.set_ylabel(f"{lab} [mm]")
    _contact_legend(
        axs[0], "joint in contact (any corner)", f"clearance {c:.3g} mm (centre offset)"
    )
    axs[-1].set_xlabel("time [s]")
    fig.suptitle(f"Slider centre in the guide of {joint} (guide frame)", fontsize=10)
    return fig


# figure and file stem per clearance kind
_KIND_FIGURES: dict[str, tuple[str, Callable]] = {
    "spherical": ("ball_trajectory", plot_ball_trajectory),
    "revolute": ("journal_trajectory", plot_journal_trajectory),
    "cylindrical": ("journal_trajectory", plot_journal_trajectory),
    "prismatic": ("slider_offset", plot_slider_offset),
}


def _joint_kinds(datasets: Mapping[str, xr.Dataset]) -> dict[str, str]:
    """Clearance joint -> its kind (files written before the kinds existed: spherical)."""
    out: dict[str, str] = {}
    for ds in datasets.values():
        if "clearance" not in ds.dims:
            continue
        kinds = (
            ds["clearance_kind"].values
            if "clearance_kind" in ds.coords
            else ["spherical"] * ds.sizes["clearance"]
        )
        for j, k in zip(ds["clearance"].values, kinds, strict=True):
            out.setdefault(str(j), str(k))
    return out


@_styled
def plot_actuator_forces(datasets: Mapping[str, xr.Dataset]) -> Figure | None:
    """Actuator force of each driver row vs time, runs overlaid (None without drivers)."""
    sty = _styles(datasets)
    rows: list[str] = []
    for ds in datasets.values():
        rows += [str(r) for r in ds["driver_row"].values if str(r) not in rows]
    if not rows:
        return None
    ncol = 1 if len(rows) <= 3 else 2
    nrow = -(-len(rows) // ncol)
    fig = Figure(figsize=(7.0, 1.0 + 1.7 * nrow), layout="constrained")
    axs = fig.subplots(nrow, ncol, sharex=True, squeeze=False).ravel()
    for ax, rn in zip(axs, rows, strict=False):
        unit = "N"
        for name, ds in datasets.items():
            if rn in ds["driver_row"].values:
                da = ds["actuator_force"].sel(driver_row=rn)
                unit = str(ds["driver_units"].sel(driver_row=rn).values)
                ax.plot(ds["time"].values, da.values, label=name, **sty[name])
        ax.set_ylabel(f"$F$ [{unit}]")
        ax.set_title(rn, loc="left")
    for ax in axs[len(rows) :]:
        ax.axis("off")
    for ax in axs[max(0, len(rows) - ncol) : len(rows)]:
        ax.set_xlabel("time [s]")
        ax.xaxis.set_tick_params(labelbottom=True)
    h, lab = axs[0].get_legend_handles_labels()
    if len(axs) > len(rows):  # a spare panel holds the legend
        axs[-1].legend(h, lab, loc="center", frameon=False)
    else:
        fig.legend(h, lab, loc="outside lower center", ncols=max(1, len(lab)), frameon=False)
    fig.suptitle("Actuator forces", fontsize=10)
    return fig


def plot_all(
    datasets: Mapping[str, xr.Dataset],
    out_dir: str | os.PathLike,
    *,
    platform: str = "platform",
    formats: Sequence[str] = ("png", "pdf"),
) -> list[Path]:
    """Write every figure of the module docstring into `out_dir`; return the file paths.

    datasets: group name -> Dataset (e.g. `load_results(path)`), drawn in this order.
    Figures that do not apply (no clearance joint, no driver) are skipped.
    """
    if not datasets:
        raise ValueError("no datasets to plot")
    out_dir = Path(out_dir)
    written: list[Path] = []
    builders: list[tuple[str, Callable[[], Figure | None]]] = [
        (f"platform_{kind}", functools.partial(plot_platform, datasets, kind, platform=platform))
        for kind in ("displacement", "velocity", "acceleration")
    ]
    builders.append(("contact_force", functools.partial(plot_contact_force, datasets)))
    for j, kind in _joint_kinds(datasets).items():
        stem, fn = _KIND_FIGURES[kind]
        builders.append((f"{stem}_{j}", functools.partial(fn, datasets, j)))
    builders.append(("actuator_forces", functools.partial(plot_actuator_forces, datasets)))
    for stem, build in builders:
        fig = build()
        if fig is not None:
            written += save_figure(fig, out_dir, _safe(stem), formats)
    return written


def _safe(stem: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)
