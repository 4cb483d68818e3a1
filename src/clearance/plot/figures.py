"""The papers' figures, drawn from result datasets only (never simulates).

`plot_all(datasets, out_dir)` takes the groups of a results file ({"ideal": ds, "clearance":
ds, ...}, see `clearance.io.dataset`; in `clearance run` the datasets in memory) and writes,
in the formats asked for (PNG by default; each file atomically):

* `platform_displacement`, `platform_velocity`, `platform_acceleration`: x, y, z of the
  platform's mass centre and the angular components about the world x, y, z axes, every
  run overlaid (the run named "ideal" dashed black), each with a panel of run - ideal
  under it. Displacement: r(t) - r_ref(0) [mm], and the rotation vector of R(t) R_ref(0)^T
  [mrad] (world components, exact for any angle; for small angles the small-angle
  rotations about x, y, z), ref the "ideal" run (else the first one), so all runs share
  one reference pose. Velocity: r_dot [m/s] and the world angular velocity [rad/s].
  Acceleration: r_ddot [m/s^2] and the world angular acceleration R omega'_dot [rad/s^2].
* `contact_force`: |F_N| [N] vs time, one panel per clearance joint, runs overlaid, the
  step-resolved peak (`peak_contact_force`, over the accepted integration steps) marked.
* per clearance joint, by its kind (`clearance_kind`; files without it are spherical):
  `ball_trajectory_<joint>`: ball centre relative to the socket centre in the socket frame
  [mm]: a 3-D curve inside the wire sphere of radius c, and the x-y, x-z, y-z projections
  inside the clearance circle, coloured by time (colour bar), start and end marked;
  `journal_trajectory_<joint>` (revolute, cylindrical): the journal centre in the
  bearing's cross-section (f-g plane of the bearing marker) the same way, and its axial
  offset (h) against time; `slider_offset_<joint>` (prismatic): the slider centre's offset
  in the guide against time, width direction (f) within the clearance band, and height (g)
  in the spatial model, the stretches in contact in red.
* `actuator_forces`: the actuator force of each driver row [N], panels named by leg,
  runs overlaid with run - ideal under each; F = -lambda, positive pushes along the
  driver's positive direction (extends the leg).

Choices, and why:
* Impact spikes (10^3 times the ideal signal in accelerations and actuator forces) would
  flatten the ideal curves: those overlays are clipped to a robust range (the reference
  curves in full, the other runs' 0.5..99.5 percentiles) only when the full range is more
  than CLIP_FACTOR times it, with the spikes' extent written in the panel; the difference
  panel under each shows the spikes in full. An inset of the impact phase was the other
  option; it needs a choice of window that fails for runs with impacts throughout.
* A panel whose values (or run - ideal differences) never exceed NOISE_FACTOR x rtol x the
  largest value of its row is integration noise: it is not drawn, the panel says so.
* A run that stopped early turns the figure's title red and says where and why.
* Plain tick labels and Unicode symbols (no mathtext), fixed margins on the 2-D panel grids
  (no layout engine) and a paused garbage collector: the default set of 7 figures renders
  in ~2.6 s on one core, ~1.4 s in two processes (`jobs`), against ~9 s before.

Uses the Figure API (no pyplot), so no global backend is changed and nothing opens a window.
"""

from __future__ import annotations

import functools
import gc
import json
import os
import re
import threading
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import matplotlib as mpl
import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from clearance.io.dataset import rotation_matrices
from clearance.io.files import atomic_path
from clearance.io.forks import forked_worker_signals

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
    # plain tick labels: mathtext ticks ("$\\mathdefault{0.5}$") cost ~1 s per figure set
    "axes.formatter.use_mathtext": False,
}
AXES = ("x", "y", "z")
# a panel whose values (or clearance-minus-ideal differences) stay below NOISE_FACTOR x the
# solver's rtol x the panel row's scale shows a note instead of plotting integration noise
NOISE_FACTOR = 1.0
# overlays whose full range exceeds the robust range (ideal curves + 0.5..99.5 percentiles
# of the other runs) by more than this factor are clipped to it, the spikes' extent noted
CLIP_FACTOR = 1.5


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
    """Save `fig` as out_dir/stem.<fmt> for each format, each file atomically. The figures
    are laid out by their layout engine, so no second ("tight") draw is needed."""
    out = []
    for fmt in formats:
        p = Path(out_dir) / f"{stem}.{fmt}"
        with atomic_path(p) as tmp, mpl.rc_context(STYLE):
            fig.savefig(tmp, format=fmt, dpi=STYLE["savefig.dpi"])
        out.append(p)
    return out


def _reference(datasets: Mapping[str, xr.Dataset]) -> str:
    return "ideal" if "ideal" in datasets else next(iter(datasets))


def _rtol(datasets: Mapping[str, xr.Dataset]) -> float:
    """The loosest relative tolerance of the runs (settings attribute; 1e-6 if absent)."""
    tol = []
    for ds in datasets.values():
        try:
            tol.append(float(json.loads(ds.attrs.get("settings", "{}")).get("rtol", 1e-6)))
        except (TypeError, ValueError):
            tol.append(1e-6)
    return max(tol, default=1e-6)


def _on_grid(t: np.ndarray, t_ref: np.ndarray, x_ref: np.ndarray) -> np.ndarray:
    """x_ref (n_ref, ...) at the times t: itself on the same grid, else linear interpolation."""
    if t.shape == t_ref.shape and np.array_equal(t, t_ref):
        return x_ref
    flat = x_ref.reshape(x_ref.shape[0], -1)
    out = np.column_stack([np.interp(t, t_ref, flat[:, k]) for k in range(flat.shape[1])])
    return out.reshape(t.shape[0], *x_ref.shape[1:])


def _note(ax, text: str, color: str = "0.35") -> None:
    ax.text(
        0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", color=color, fontsize=7
    )


def _robust_limits(ax, curves: Sequence[tuple[np.ndarray, bool]], unit: str) -> None:
    """Clip the y-range of an overlay to what the eye needs: the full range of the reference
    curves (flag True) and the 0.5..99.5 percentile range of the others, padded by 8 %; only
    when the full range is more than CLIP_FACTOR times that. The clipped extent is noted in
    the panel (impact spikes must not flatten the ideal curve)."""
    ref = [c for c, is_ref in curves if is_ref and c.size]
    other = [c for c, is_ref in curves if not is_ref and c.size]
    if not other:
        return
    lo = min(
        [float(np.nanmin(c)) for c in ref]
        + [float(np.nanpercentile(c, 0.5, method="nearest")) for c in other]
    )
    hi = max(
        [float(np.nanmax(c)) for c in ref]
        + [float(np.nanpercentile(c, 99.5, method="nearest")) for c in other]
    )
    full_lo = min(float(np.nanmin(c)) for c, _ in curves if c.size)
    full_hi = max(float(np.nanmax(c)) for c, _ in curves if c.size)
    span = hi - lo
    if span <= 0 or (full_hi - full_lo) <= CLIP_FACTOR * span:
        return
    pad = 0.08 * span
    ax.set_ylim(lo - pad, hi + pad)
    ax.text(
        0.99,
        0.97,
        f"clipped; spikes {full_lo:.3g} .. {full_hi:.3g} {unit}",
        transform=ax.transAxes,
        ha="right",
        va="top",
        fontsize=6.5,
        color="C3",
        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8},
    )


def _frame(
    fig: Figure,
    nrows: int,
    ncols: int,
    *,
    left: float = 0.72,
    right: float = 0.12,
    top: float = 0.5,
    bottom: float = 0.72,
    wgap: float = 0.72,
    hgap: float = 0.3,
) -> None:
    """Fixed margins and gaps in inches for a grid of 2-D panels. No layout engine: the
    constrained layout measured every tick label once more per draw (~0.2 s per figure of
    12 panels); plain tick labels of at most ~6 characters fit these margins."""
    w, h = fig.get_size_inches()
    aw = (w - left - right - (ncols - 1) * wgap) / ncols
    ah = (h - top - bottom - (nrows - 1) * hgap) / nrows
    fig.subplots_adjust(
        left=left / w,
        right=1 - right / w,
        top=1 - top / h,
        bottom=bottom / h,
        wspace=wgap / aw,
        hspace=hgap / ah,
    )


def _pair_grid(
    fig: Figure, npairs: int, ncols: int, n: int, diff: bool, *, spacer: float = 0.42
) -> tuple[np.ndarray, np.ndarray]:
    """Panels in pairs (an overlay and, with `diff`, a shorter difference panel right under
    it), `n` pairs over `npairs` rows of `ncols` columns, one shared time axis; a gap of
    `spacer` inches between pairs holds the next pair's title. Returns (overlays,
    differences) as (npairs, ncols) object arrays, None where no panel is."""
    per = (2.0, 1.0) if diff else (1.0,)
    ratios: list[float] = []
    w, h = fig.get_size_inches()
    unit = (h - 1.25 - (npairs - 1) * spacer) / (npairs * sum(per))  # inches per ratio 1
    for r in range(npairs):
        ratios += list(per) + ([spacer / unit] if r < npairs - 1 else [])
    gs = fig.add_gridspec(len(ratios), ncols, height_ratios=ratios, hspace=0.12 / unit)
    step = len(per) + 1
    over = np.full((npairs, ncols), None, dtype=object)
    under = np.full((npairs, ncols), None, dtype=object)
    first = None
    for k in range(n):
        r, c = divmod(k, ncols)
        over[r, c] = fig.add_subplot(gs[r * step, c], sharex=first)
        first = first or over[r, c]
        if diff:
            under[r, c] = fig.add_subplot(gs[r * step + 1, c], sharex=first)
    for c in range(ncols):  # time labels under the lowest panel of each column
        col = [ax for r in range(npairs) for ax in (over[r, c], under[r, c]) if ax is not None]
        for ax in col[:-1]:
            ax.tick_params(labelbottom=False)
        if col:
            col[-1].set_xlabel("time [s]")
    return over, under


def _handles(fig: Figure) -> tuple[list, list[str]]:
    """The distinct legend entries of all panels of fig, in order."""
    h, lab = [], []
    for ax in fig.get_axes():
        for hh, ll in zip(*ax.get_legend_handles_labels(), strict=True):
            if ll not in lab:
                h.append(hh)
                lab.append(ll)
    return h, lab


def _legend_below(fig: Figure, handles, labels) -> None:
    fig.legend(
        handles,
        labels,
        loc="lower center",
        bbox_to_anchor=(0.5, 0.0),
        ncols=max(1, len(labels)),
        frameon=False,
    )


def _stop_notes(datasets: Mapping[str, xr.Dataset]) -> str:
    """One line per run that stopped early ("" when every run reached its final time)."""
    lines = []
    for name, ds in datasets.items():
        if int(ds.attrs.get("status", 0)) != 0:
            t = ds["time"].values
            end = f"{t[-1]:.4g} s" if t.size else "the start"
            msg = str(ds.attrs.get("message", ""))
            lines.append(f"run '{name}' STOPPED EARLY at t = {end}: {msg}")
    return "\n".join(lines)


def _title(fig: Figure, datasets: Mapping[str, xr.Dataset], title: str) -> None:
    """Figure title; when a run stopped early, the title turns red and says so."""
    notes = _stop_notes(datasets)
    if notes:
        fig.suptitle(f"{title}\n{notes}", fontsize=9, color="C3")
    else:
        fig.suptitle(title, fontsize=10)


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
    "displacement": ("Δ{a}", 1e3, "mm", "θ{a}", 1e3, "mrad"),
    "velocity": ("v{a}", 1.0, "m/s", "ω{a}", 1.0, "rad/s"),
    "acceleration": ("a{a}", 1.0, "m/s²", "α{a}", 1.0, "rad/s²"),
}


def _overlay_and_difference(
    ax,
    dax,
    datasets: Mapping[str, xr.Dataset],
    values: Mapping[str, np.ndarray],
    *,
    ref: str,
    noise: float,
    unit: str,
    robust: bool,
    what: str,
) -> None:
    """One component: the runs overlaid in `ax` and run - reference in `dax` (None: no
    difference panel). Curves that never leave the numerical noise are not drawn: the
    panel says so instead (integration noise plotted at 1e-12 looks like signal)."""
    sty = _styles(datasets)
    if all(np.nanmax(np.abs(v)) <= noise for v in values.values() if v.size):
        _note(ax, f"{what} = 0 to numerical noise\n(every |value| <= {noise:.1e} {unit})")
    else:
        for name, ds in datasets.items():
            ax.plot(ds["time"].values, values[name], label=name, **sty[name])
        if robust:
            _robust_limits(ax, [(values[n], n == ref) for n in datasets], unit)
    if dax is None:
        return
    t_ref = datasets[ref]["time"].values
    drawn = False
    largest = 0.0
    for name, ds in datasets.items():
        if name == ref:
            continue
        t = ds["time"].values
        d = values[name] - _on_grid(t, t_ref, values[ref])
        m = float(np.nanmax(np.abs(d))) if d.size else 0.0
        largest = max(largest, m)
        if m > noise:
            dax.plot(t, d, color=sty[name]["color"], linewidth=0.8, label=name)
            drawn = True
    if not drawn:
        _note(dax, f"difference below numerical noise\n(max {largest:.1e} <= {noise:.1e} {unit})")


@_styled
def plot_platform(
    datasets: Mapping[str, xr.Dataset], kind: str, *, platform: str = "platform"
) -> Figure:
    """Platform `kind` ("displacement", "velocity", "acceleration"): x, y, z of the mass
    centre and the angular components about the world axes, every run overlaid; below each
    row, every run minus the reference run ("ideal"), when there is more than one run.

    Acceleration overlays are clipped to a robust range when impact spikes would flatten
    the ideal curve (the spikes' extent is noted; the difference rows show them in full).
    A component (or difference) that stays below the numerical noise (NOISE_FACTOR x rtol x
    the row's largest value) is not drawn: the panel says so.
    """
    lab_t, sc_t, u_t, lab_r, sc_r, u_r = _MOTION[kind]
    refname = _reference(datasets)
    ref = datasets[refname]
    diff = len(datasets) > 1
    fig = Figure(figsize=(7.5, 6.8 if diff else 4.2))
    over, under = _pair_grid(fig, 2, 3, 6, diff, spacer=0.3)
    _frame(fig, 1, 3, bottom=0.75, wgap=0.78)
    motion = {name: platform_motion(ds, ref, platform)[kind] for name, ds in datasets.items()}
    rtol = _rtol(datasets)
    for part, (lab, sc, unit) in enumerate(((lab_t, sc_t, u_t), (lab_r, sc_r, u_r))):
        row, drow = over[part], under[part]
        vals = {name: motion[name][part] * sc for name in datasets}
        scale = max((float(np.nanmax(np.abs(v))) for v in vals.values() if v.size), default=0.0)
        for j, a in enumerate(AXES):
            symbol = lab.format(a=a)
            _overlay_and_difference(
                row[j],
                drow[j],
                datasets,
                {n: v[:, j] for n, v in vals.items()},
                ref=refname,
                noise=NOISE_FACTOR * rtol * scale,
                unit=unit,
                robust=kind == "acceleration",
                what=symbol,
            )
            row[j].set_ylabel(f"{symbol} [{unit}]")
            if drow[j] is not None:
                drow[j].set_ylabel(f"{symbol} − {refname} [{unit}]", fontsize=8)
    h, lab = _handles(fig)
    _legend_below(fig, h, lab)
    _title(fig, datasets, f"Platform {kind} ({platform})")
    return fig


def _clearance_runs(datasets: Mapping[str, xr.Dataset]) -> list[str]:
    names: list[str] = []
    for ds in datasets.values():
        if "clearance" in ds.dims:
            names += [str(c) for c in ds["clearance"].values if str(c) not in names]
    return names


@_styled
def plot_contact_force(datasets: Mapping[str, xr.Dataset]) -> Figure | None:
    """|F_N| per clearance joint vs time (None when no run has a clearance joint), with the
    step-resolved peak (`peak_contact_force`: over the accepted integration steps, so an
    impact shorter than the output interval is not missed) marked and stated."""
    sty = _styles(datasets)
    joints = _clearance_runs(datasets)
    if not joints:
        return None
    fig = Figure(figsize=(7.0, 1.3 + 1.7 * len(joints)))
    axs = np.atleast_1d(fig.subplots(len(joints), 1, sharex=True, squeeze=False)[:, 0])
    _frame(fig, len(joints), 1, bottom=0.5, top=0.45, hgap=0.35)
    for ax, jn in zip(axs, joints, strict=True):
        for name, ds in datasets.items():
            if jn in ds["clearance"].values:
                f = ds["contact_force"].sel(clearance=jn).values
                ax.plot(ds["time"].values, f, label=name, **sty[name])
                if "peak_contact_force" in ds:
                    pk = float(ds["peak_contact_force"].sel(clearance=jn))
                    tp = float(ds["peak_contact_force_time"].sel(clearance=jn))
                    if pk > 0 and np.isfinite(tp):
                        ax.plot(
                            [tp],
                            [pk],
                            "v",
                            color=sty[name]["color"],
                            mec="k",
                            mew=0.5,
                            markersize=6,
                            zorder=5,
                            gid=f"peak:{name}:{jn}",
                            label=f"peak {pk:.4g} N at t = {tp:.5g} s (integration steps)",
                        )
        ax.set_ylabel("normal force [N]")
        ax.set_title(f"clearance joint {jn}", loc="left")
        ax.legend(loc="upper right", frameon=False, fontsize=7)
    axs[-1].set_xlabel("time [s]")
    _title(fig, datasets, "Normal contact force")
    return fig


def _time_path(ax, x: np.ndarray, t: np.ndarray, cmap: str, norm, *, three_d: bool = False):
    """The path x (n, 2 or 3) coloured by time: ~1500 polylines (each exact, a few samples
    long) in one collection, so a 20 000-sample path draws in milliseconds."""
    from matplotlib.collections import LineCollection

    n = x.shape[0]
    if n < 2:
        return None
    k = max(1, -(-n // 1500))
    starts = np.arange(0, n - 1, k)
    segs = [x[i : min(i + k, n - 1) + 1] for i in starts]
    if three_d:
        from mpl_toolkits.mplot3d.art3d import Line3DCollection

        lc = Line3DCollection(segs, cmap=cmap, norm=norm, linewidths=1.0)
        ax.add_collection3d(lc)
    else:
        lc = LineCollection(segs, cmap=cmap, norm=norm, linewidths=1.0)
        ax.add_collection(lc)
    lc.set_array(t[np.minimum(starts + k // 2, n - 1)])
    return lc


_CMAPS = ("viridis", "plasma", "cividis", "magma")


def _path_keys(fig: Figure, runs, t_span: tuple[float, float], clearance: str) -> None:
    """Legend below the data: start and end markers, the clearance circle; a time colour
    bar per run."""
    from matplotlib.lines import Line2D

    h = [
        Line2D([], [], marker="o", mfc="white", mec="k", linestyle="none"),
        Line2D([], [], marker="s", color="k", linestyle="none"),
        Line2D([], [], color="0.4", linestyle="--"),
    ]
    lab = [f"start (t = {t_span[0]:.4g} s)", f"end (t = {t_span[1]:.4g} s)", clearance]
    fig.legend(h, lab, loc="outside lower center", ncols=3, frameon=False)


def _ends(ax, x: np.ndarray) -> None:
    if x.shape[0]:
        ax.plot(*x[0].reshape(-1, 1), "o", mfc="white", mec="k", markersize=5, zorder=6)
        ax.plot(*x[-1].reshape(-1, 1), "s", color="k", markersize=4, zorder=6)


@_styled
def plot_ball_trajectory(datasets: Mapping[str, xr.Dataset], joint: str) -> Figure:
    """Ball-centre path in the socket of `joint` [mm]: 3-D view and the three projections,
    coloured by time (colour bar), start and end marked, inside the clearance sphere /
    circles of radius c (in contact on them)."""
    from matplotlib.colors import Normalize
    from matplotlib.ticker import MaxNLocator
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
        color="0.8",
        linewidth=0.3,
    )
    t_all = np.concatenate([ds["time"].values for _, ds in runs])
    span = (float(t_all.min()), float(t_all.max())) if t_all.size else (0.0, 0.0)
    norm = Normalize(*span) if span[1] > span[0] else Normalize(0.0, 1.0)
    for k, (name, ds) in enumerate(runs):
        e = 1e3 * ds["eccentricity"].sel(clearance=joint).transpose("time", "axis").values
        t = ds["time"].values
        cmap = _CMAPS[k % len(_CMAPS)]
        lc = _time_path(ax3, e, t, cmap, norm, three_d=True)
        _ends(ax3, e)
        for ax, i0, i1 in proj:
            _time_path(ax, e[:, [i0, i1]], t, cmap, norm)
            _ends(ax, e[:, [i0, i1]])
        if lc is not None:
            label = "time [s]" if len(runs) == 1 else f"time [s], {name}"
            fig.colorbar(lc, ax=[ax for ax, _, _ in proj] + [ax3], shrink=0.6, label=label)
    for ax, i0, i1 in proj:
        _clearance_circle(ax, c)
        ax.set_xlabel(f"{AXES[i0]} [mm]")
        ax.set_ylabel(f"{AXES[i1]} [mm]")
    for setlim in (ax3.set_xlim, ax3.set_ylim, ax3.set_zlim):
        setlim(-lim, lim)
    for axis in (ax3.xaxis, ax3.yaxis, ax3.zaxis):
        axis.set_major_locator(MaxNLocator(4))
    ax3.set_box_aspect((1, 1, 1))
    ax3.set_xlabel("x [mm]", labelpad=0)
    ax3.set_ylabel("y [mm]", labelpad=0)
    ax3.set_zlabel("z [mm]", labelpad=0)
    ax3.tick_params(labelsize=7, pad=0)
    fig.get_layout_engine().set(w_pad=0.15, wspace=0.12)  # room for the 3-D z label
    _path_keys(fig, runs, span, f"clearance c = {c:.3g} mm")
    _title(fig, datasets, f"Ball centre in the socket of {joint} (socket frame)")
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
    the cross-section (bearing marker f, g axes) inside the clearance circle, coloured by
    time, start and end marked; and, if the journal moves axially (cylindrical joint,
    thrust clearance), its axial offset (h) against time."""
    from matplotlib.colors import Normalize

    sty = _styles(datasets)
    runs = _joint_runs(datasets, joint)
    c = 1e3 * float(runs[0][1]["radial_clearance"].sel(clearance=joint))
    ecc = {
        name: 1e3 * ds["eccentricity"].sel(clearance=joint).transpose("time", "axis").values
        for name, ds in runs
    }
    axial = max(float(np.ptp(e[:, 2])) if e.size else 0.0 for e in ecc.values()) > 1e-6 * c
    fig = Figure(figsize=(7.5 if axial else 4.6, 4.0), layout="constrained")
    ax, axh = fig.subplots(1, 2, width_ratios=(1.0, 1.3)) if axial else (fig.subplots(), None)
    t_all = np.concatenate([ds["time"].values for _, ds in runs])
    span = (float(t_all.min()), float(t_all.max())) if t_all.size else (0.0, 0.0)
    norm = Normalize(*span) if span[1] > span[0] else Normalize(0.0, 1.0)
    for k, (name, ds) in enumerate(runs):
        e = ecc[name]
        t = ds["time"].values
        lc = _time_path(ax, e[:, :2], t, _CMAPS[k % len(_CMAPS)], norm)
        _ends(ax, e[:, :2])
        if lc is not None:
            label = "time [s]" if len(runs) == 1 else f"time [s], {name}"
            fig.colorbar(lc, ax=ax, shrink=0.8, label=label)
        if axh is not None:
            st = {kk: v for kk, v in sty[name].items() if kk != "zorder"}
            axh.plot(t, e[:, 2], label=name, **st)
    _clearance_circle(ax, c)
    ax.set_xlabel("f [mm]")
    ax.set_ylabel("g [mm]")
    if axh is not None:
        axh.set_xlabel("time [s]")
        axh.set_ylabel("axial offset h [mm]")
    _path_keys(fig, runs, span, f"clearance c = {c:.3g} mm")
    _title(fig, datasets, f"Journal centre in the bearing of {joint} (bearing frame)")
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
    for ax, lab in zip(axs, ("f (width)", "g (height)"), strict=False):
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


def _leg_name(row: str) -> str:
    """Panel title of an actuator row: "leg k (drive_k)" for the legs of the parallel
    mechanisms (drivers named drive_k), else the row's name."""
    m = re.fullmatch(r"drive_(\d+)(\[\d+\])?", row)
    return f"leg {m.group(1)} ({row})" if m else row


@_styled
def plot_actuator_forces(datasets: Mapping[str, xr.Dataset]) -> Figure | None:
    """Actuator force of each driver row vs time (None without drivers), runs overlaid
    (clipped to a robust range when impact spikes would flatten the ideal curve, the spikes'
    extent noted) and, with more than one run, every run minus the reference run below.
    Panels are named by leg; sign convention: F = -lambda, positive pushes along the
    driver's positive direction (extends a leg)."""
    rows: list[str] = []
    for ds in datasets.values():
        if "driver_row" in ds.dims:
            rows += [str(r) for r in ds["driver_row"].values if str(r) not in rows]
    if not rows:
        return None
    refname = _reference(datasets)
    diff = len(datasets) > 1
    ncol = 1 if len(rows) <= 3 else 2
    nrow = -(-len(rows) // ncol)
    fig = Figure(figsize=(7.0, 1.25 + (2.35 if diff else 1.7) * nrow))
    over, under = _pair_grid(fig, nrow, ncol, len(rows), diff)
    _frame(fig, 1, ncol, bottom=0.75, top=0.62, wgap=0.78)
    rtol = _rtol(datasets)
    for i, rn in enumerate(rows):
        ax, dax = over.flat[i], under.flat[i]
        unit = "N"
        runs = {n: ds for n, ds in datasets.items() if rn in ds.get("driver_row", [])}
        vals = {n: ds["actuator_force"].sel(driver_row=rn).values for n, ds in runs.items()}
        for ds in runs.values():
            unit = str(ds["driver_units"].sel(driver_row=rn).values)
        scale = max((float(np.nanmax(np.abs(v))) for v in vals.values() if v.size), default=0.0)
        ref = refname if refname in runs else next(iter(runs))
        _overlay_and_difference(
            ax,
            dax if len(runs) > 1 else None,
            runs,
            vals,
            ref=ref,
            noise=NOISE_FACTOR * rtol * scale,
            unit=unit,
            robust=True,
            what="F",
        )
        ax.set_ylabel(f"F [{unit}]")
        ax.set_title(_leg_name(rn), loc="left")
        if dax is not None:
            dax.set_ylabel(f"F − {ref} [{unit}]", fontsize=8)
    h, lab = _handles(fig)
    _legend_below(fig, h, lab)
    _title(
        fig,
        datasets,
        "Actuator forces (F = −λ; F > 0 drives the actuator forward: extends a leg, "
        "turns a motor's angle)",
    )
    return fig


def plot_all(
    datasets: Mapping[str, xr.Dataset],
    out_dir: str | os.PathLike,
    *,
    platform: str = "platform",
    formats: Sequence[str] = ("png",),
    jobs: int | None = None,
) -> list[Path]:
    """Write every figure of the module docstring into `out_dir`; return the file paths.

    datasets: group name -> Dataset (e.g. `load_results(path)`), drawn in this order.
    Figures that do not apply (no clearance joint, no driver) are skipped. jobs: processes
    drawing the figures (None: one per available core, at most 4; 1: this process only).
    """
    return start_figures(datasets, out_dir, platform=platform, formats=formats, jobs=jobs).result()


def start_figures(
    datasets: Mapping[str, xr.Dataset],
    out_dir: str | os.PathLike,
    *,
    platform: str = "platform",
    formats: Sequence[str] = ("png",),
    jobs: int | None = None,
) -> PendingFigures:
    """`plot_all`, begun: with more than one job the forked processes start drawing at
    once and the caller goes on (`clearance run` writes the result file meanwhile);
    `.result()` waits for them and returns the paths. With one job (or no fork here) the
    figures are drawn in `.result()`."""
    if not datasets:
        raise ValueError("no datasets to plot")
    for name, ds in datasets.items():
        if "case" in ds.dims:
            raise ValueError(
                f"group {name!r} is a collected study (dimension 'case'), not a run result: "
                "plot one case's file (cases/<case>.nc), or see the study plots that "
                "`clearance collect` draws"
            )
    out_dir = Path(out_dir)
    has_platform = all(
        "position" in ds and platform in ds["body"].values for ds in datasets.values()
    )
    builders: list[tuple[str, Callable[[], Figure | None]]] = [
        (f"platform_{kind}", functools.partial(plot_platform, datasets, kind, platform=platform))
        for kind in (("displacement", "velocity", "acceleration") if has_platform else ())
    ]
    builders.append(("contact_force", functools.partial(plot_contact_force, datasets)))
    for j, kind in _joint_kinds(datasets).items():
        stem, fn = _KIND_FIGURES[kind]
        builders.append((f"{stem}_{j}", functools.partial(fn, datasets, j)))
    builders.append(("actuator_forces", functools.partial(plot_actuator_forces, datasets)))
    return PendingFigures(builders, out_dir, tuple(formats), _jobs(jobs, len(builders)))


def _render(builders, out_dir: Path, formats: Sequence[str]) -> list[Path]:
    """Build and save each figure. The cyclic garbage collector is paused meanwhile: the
    artists of a figure are thousands of small objects in reference cycles, and its
    repeated passes over them took ~15 % of the rendering time."""
    written: list[Path] = []
    paused = gc.isenabled()
    gc.disable()
    try:
        for stem, build in builders:
            fig = build()
            if fig is not None:
                written += save_figure(fig, out_dir, _safe(stem), formats)
    finally:
        if paused:
            gc.enable()
    return written


def _jobs(jobs: int | None, n: int) -> int:
    """Worker processes for n figures: `jobs`, or (None) one per available core, at most
    4; 1 where processes cannot be forked safely (no fork on the platform, or other
    threads running in this process): the figures then render in this process."""
    import multiprocessing

    if jobs is None:
        try:
            cores = len(os.sched_getaffinity(0))
        except AttributeError:  # not Linux
            cores = os.cpu_count() or 1
        jobs = min(cores, 4)
    if "fork" not in multiprocessing.get_all_start_methods():
        return 1
    if threading.active_count() > 1:  # forking a threaded process (Jupyter, Dask) can
        return 1  # deadlock a child on a lock another thread held: draw them here
    return max(1, min(int(jobs), n))


# what a fork can fail with (no fork here, a daemonic process): draw in this process then
_NO_FORK = (OSError, AssertionError, ImportError, RuntimeError)


class PendingFigures:
    """Figures being drawn (`start_figures`); `result()` returns their paths."""

    def __init__(self, builders, out_dir: Path, formats: tuple, jobs: int) -> None:
        self._serial = (builders, out_dir, formats)
        self._pool = self._running = self._paths = None
        if jobs > 1:
            try:
                self._fork(builders, out_dir, formats, jobs)
            except _NO_FORK:
                self._close()

    def _fork(self, builders, out_dir: Path, formats: tuple, jobs: int) -> None:
        """Render the figures in `jobs` forked processes (each inherits the datasets
        without copying them); every figure is independent and written atomically by its
        process."""
        import multiprocessing

        global _FORKED
        # the larger figures first, handed out one at a time: the processes finish together
        order = sorted(range(len(builders)), key=lambda i: builders[i][0].startswith("contact"))
        _FORKED = self._serial
        self._pool = multiprocessing.get_context("fork").Pool(
            jobs, initializer=forked_worker_signals
        )
        self._running = self._pool.imap_unordered(_render_one, order)

    def result(self) -> list[Path]:
        if self._paths is None:
            self._paths = self._collect()
        return self._paths

    def _collect(self) -> list[Path]:
        builders = self._serial[0]
        if self._running is not None:
            try:
                done = dict(self._running)
                return [p for i in range(len(builders)) for p in done[i]]
            except _NO_FORK:
                pass  # drawn again below, in this process
            finally:
                self._close()
        return _render(*self._serial)

    def cancel(self) -> None:
        """Stop the drawing processes (what they wrote stays)."""
        self._close()

    def _close(self) -> None:
        global _FORKED
        if self._pool is not None:
            self._pool.terminate()
        self._pool = self._running = None
        _FORKED = None


_FORKED = None  # (builders, out_dir, formats) of the running PendingFigures, for its forks


def _render_one(i: int) -> tuple[int, list[Path]]:
    builders, out_dir, formats = _FORKED
    return i, _render([builders[i]], out_dir, formats)


def _safe(stem: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)
