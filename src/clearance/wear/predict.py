"""Wear prediction over many cycles (issue 16): the update-factor loop.

    from clearance.wear.predict import predict_wear
    w = predict_wear("scenario.toml", out_dir="wear-run")   # the scenario's [wear] table
    w.history          # xarray Dataset: volume, max depth, forces ... against cycles

Each iteration runs the dynamics once with the sockets and bearings worn as they are
(`Mechanism.with_wear`: the worn gap and its forces, contact/spherical.py and
contact/journal.py), takes the wear of one cycle from that run (Archard with the elastic
foundation's pressure over the ball's or journal's overlap with the worn surface,
`clearance.wear.history.socket_wear` and `clearance.wear.bearing.bearing_history`, over
the samples after `warmup`, scaled to one `cycle_time`), multiplies it by the update
factor N (cycles per iteration) and adds it to the depth maps. N is fixed
(`update_factor`) or chosen so that no socket or bearing deepens by more than `max_step`
x its clearance (and, if set,
`max_step_penetration` x the run's mean penetration) in one iteration (the usual scheme:
docs/notes/wear-literature.md section 5); the loop ends when `cycles` are reached, and one
last run measures the worn mechanism. The explicit update is Euler's method in the cycle
count: its error shrinks with N (first order), which `docs/wear.md` and the tests show.

State after every iteration is written atomically to `wear.nc` in the output folder; a
call with the same scenario resumes from it (`restart=True` starts again).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from clearance.compile.calibration import effective_modulus
from clearance.model.clearance import RevoluteClearance
from clearance.scenario.wear import JointWear, WearSettings
from clearance.wear.bearing import BearingWearMap, bearing_history
from clearance.wear.history import socket_wear
from clearance.wear.surface import SphereWearMap

__all__ = [
    "CycleWear",
    "JointWear",
    "WearLoop",
    "WearRunError",
    "WearStateError",
    "WearSettings",
    "predict_wear",
    "run_wear_loop",
]

#: per-iteration quantities of the history, per joint (name: long name, units)
JOINT_VARS = {
    "volume": ("worn volume of the socket or bearing", "m3"),
    "max_depth": ("maximum wear depth", "m"),
    "effective_clearance": ("clearance plus the maximum wear depth", "m"),
    "wear_work": ("integral of F_N |v_slip| dt over one cycle", "N m"),
    "peak_contact_force": ("peak contact force of the iteration's run after warmup", "N"),
    "rms_contact_force": ("RMS contact force of the iteration's run after warmup", "N"),
    "impacts": ("contact onsets of the iteration's run after warmup", "1"),
    "max_penetration": ("largest penetration of the iteration's run after warmup", "m"),
    "mean_penetration": ("force-weighted mean penetration in contact, after warmup", "m"),
}


@dataclass
class CycleWear:
    """What one run gives per joint: the depth added in one cycle (6, n, n) [m], the wear
    work per cycle [N m], and metrics (JOINT_VARS' run quantities); and the platform's RMS
    deviation from the ideal run [m] (nan: none)."""

    increment: dict
    work: dict
    metrics: dict
    platform_deviation: float = math.nan


@dataclass
class WearLoop:
    """The loop's state: the maps, and one history row per iteration."""

    maps: dict  # joint -> SphereWearMap (socket) or BearingWearMap (bearing)
    clearances: dict  # joint -> c [m]
    rows: list = field(default_factory=list)
    done: bool = False
    depths: list = field(default_factory=list)  # per row: {joint: depth (6, n, n)} of its run

    @property
    def cycles(self) -> float:
        return float(sum(r["factor"] for r in self.rows))

    def worn(self, smoothing: Mapping[str, float]) -> dict:
        """{joint: SocketWear or BearingWear} of the current maps, as the dynamics sees them
        (unworn joints left out)."""
        return {
            j: m.wear_model(self.clearances[j], smoothing[j])
            for j, m in self.maps.items()
            if m.max_depth() > 0.0
        }

    def history(self):
        """The history as an xarray Dataset (dims iteration, joint, face, i, j)."""
        import xarray as xr

        joints = list(self.maps)
        it = np.arange(len(self.rows))
        data = {
            "cycles": (("iteration",), [r["cycles"] for r in self.rows]),
            "update_factor": (("iteration",), [r["factor"] for r in self.rows]),
            "platform_deviation": (("iteration",), [r["platform"] for r in self.rows]),
        }
        for name in JOINT_VARS:
            data[name] = (
                ("iteration", "joint"),
                np.array([[r[name][j] for j in joints] for r in self.rows], dtype=float).reshape(
                    len(self.rows), len(joints)
                ),
            )
        ds = xr.Dataset(data, coords={"iteration": it, "joint": joints})
        for name, (long, units) in JOINT_VARS.items():
            ds[name].attrs.update(long_name=long, units=units)
        ds["cycles"].attrs.update(long_name="cycles before the iteration", units="1")
        ds["update_factor"].attrs.update(long_name="cycles the iteration stands for", units="1")
        ds["platform_deviation"].attrs.update(
            long_name="RMS platform position deviation from the ideal run", units="m"
        )
        for j, m in self.maps.items():
            if self.depths and len(self.depths) == len(self.rows):
                ds[f"depth_history_{j}"] = (
                    ("iteration", *_dims(m, j)),
                    np.array([d[j] for d in self.depths], dtype=np.float32),
                )
                ds[f"depth_history_{j}"].attrs.update(
                    long_name=f"wear depth of {j} in each iteration's run",
                    units="m",
                )
            ds[f"depth_{j}"] = (_dims(m, j), m.depth)
            ds[f"depth_{j}"].attrs.update(_map_attrs(m, j))
        ds.attrs["done"] = int(self.done)
        ds.attrs["clearances"] = json.dumps(self.clearances)
        return ds


def _dims(m, j: str) -> tuple:
    """A map's dimension names in the history, per joint (grids may differ)."""
    return tuple(f"{d}_{j}" for d in m.dims)


def _map_attrs(m, j: str) -> dict:
    if isinstance(m, BearingWearMap):
        return dict(
            long_name=f"wear depth of the bearing of {j} (bearing marker frame)",
            units="m",
            radius=m.radius,
            length=m.length,
            grid="per station, equal cells of the angle about h from f (clearance.wear.bearing)",
        )
    return dict(
        long_name=f"wear depth of the socket of {j} (socket marker frame)",
        units="m",
        radius=m.radius,
        grid="equiangular cubed sphere (clearance.wear.surface)",
    )


def _row(state: WearLoop, factor: float, cw: CycleWear) -> dict:
    state.depths.append({j: m.depth.copy() for j, m in state.maps.items()})
    row = {"cycles": state.cycles, "factor": factor, "platform": cw.platform_deviation}
    for name in JOINT_VARS:
        row[name] = {}
    for j, m in state.maps.items():
        row["volume"][j] = m.volume()
        row["max_depth"][j] = m.max_depth()
        row["effective_clearance"][j] = state.clearances[j] + m.max_depth()
        row["wear_work"][j] = cw.work[j]
        for name in list(JOINT_VARS)[4:]:  # the run quantities (run_metrics)
            row[name][j] = cw.metrics[j].get(name, math.nan)
    return row


def run_wear_loop(
    cycle: Callable[[dict, dict], CycleWear],
    settings: WearSettings,
    state: WearLoop,
    *,
    log: Callable[[str], None] | None = print,
    save: Callable[[WearLoop], None] | None = None,
    max_iterations: int | None = None,
) -> WearLoop:
    """Iterate: run `cycle(worn, maps)` with the current worn joints (worn: {joint:
    SocketWear or BearingWear} for the dynamics, maps: {joint: SphereWearMap or
    BearingWearMap}, the depth maps they come
    from, not to be changed), extrapolate its wear by the update factor, save.
    `max_iterations`: stop after that many runs (resumable)."""
    smoothing = {j: s.smoothing for j, s in settings.joints.items()}
    runs = 0
    while not state.done:
        if max_iterations is not None and runs >= max_iterations:
            break
        cw = cycle(state.worn(smoothing), state.maps)
        runs += 1
        remaining = settings.cycles - state.cycles
        if (
            remaining <= 1e-9 * settings.cycles
        ):  # the last run: the worn mechanism measured, no wear added
            state.rows.append(_row(state, 0.0, cw))
            state.done = True
        else:
            if settings.update_factor is not None:
                factor = min(settings.update_factor, remaining)
            else:  # each socket deepens by <= max_step c and max_step_penetration delta
                rate = 0.0  # the largest fraction of its bound a socket wears per cycle
                for j in state.maps:
                    bound = settings.max_step * state.clearances[j]
                    pen = cw.metrics.get(j, {}).get("mean_penetration", 0.0)
                    if pen > 0.0:
                        bound = min(bound, settings.max_step_penetration * pen)
                    rate = max(rate, float(np.max(cw.increment[j])) / bound)
                factor = min(remaining, settings.max_factor)
                if rate > 0.0:
                    factor = min(factor, 1.0 / rate)
                if factor < min(1.0, remaining):  # one cycle at least: say max_step is exceeded
                    factor = min(1.0, remaining)
                    if log is not None:
                        log(
                            f"[wear] one cycle deepens a joint by {rate:.3g} x the step "
                            "bound (max_step, max_step_penetration): the iteration stands "
                            "for one cycle"
                        )
            state.rows.append(_row(state, factor, cw))
            for j, m in state.maps.items():
                m.depth += factor * cw.increment[j]
            if log is not None:
                parts = [
                    f"{j}: V {m.volume():.3g} m3, h_max {m.max_depth() * 1e6:.3g} um"
                    for j, m in state.maps.items()
                ]
                log(
                    f"[wear] iteration {len(state.rows)}: {state.cycles:.6g} of "
                    f"{settings.cycles:.6g} cycles (x{factor:.4g}); " + "; ".join(parts)
                )
        if save is not None:
            save(state)
    return state


# ------------------------------------------------------------------ scenarios


def _cycle_of_scenario(s, settings: WearSettings, e_star: dict, run_log, out_dir=None):
    """The `cycle` callable of a scenario: one run of its clearance mechanism, worn (its
    files are not written; out_dir: the folder the run checks instead of the scenario's
    [output] folder, which it would create)."""
    import dataclasses

    from clearance.io.dataset import result_to_dataset
    from clearance.pipeline import run_scenario

    s = dataclasses.replace(s, solver=dataclasses.replace(s.solver, dt_out=settings.dt_out))

    def cycle(worn: dict, maps: dict) -> CycleWear:
        o = run_scenario(
            s,
            out_dir=out_dir,
            figures=False,
            log=run_log,
            reuse_ideal=True,
            defer_write=True,
            wear=worn,
        )
        r = o.clearance
        if not r.success:
            raise WearRunError(f"the run with the worn joints stopped: {r.message}", o)
        ds = result_to_dataset(r, outputs=("clearance",))
        t = np.asarray(ds["time"].values)
        keep = np.flatnonzero(t >= t[0] + settings.warmup)
        if keep.size < 2:
            raise WearRunError(f"warmup {settings.warmup} s leaves no samples to count", o)
        ds = ds.isel({ds["time"].dims[0]: keep})
        counted = float(t[keep[-1]] - t[keep[0]])
        per = (settings.cycle_time or counted) / counted
        inc, work, metrics = {}, {}, {}
        for j, js in settings.joints.items():
            if isinstance(maps[j], BearingWearMap):
                m, w = bearing_history(
                    r, j, k_w=js.coefficient, keep=keep, surface=maps[j].empty(), worn=maps[j]
                )
            else:
                m, w = socket_wear(
                    ds, j, k_w=js.coefficient, e_star=e_star[j], n=js.grid, worn=maps[j]
                )
            inc[j] = per * m.depth
            work[j] = per * w
            metrics[j] = run_metrics(ds, j)
        dev = o.summary.get("deviation_rms", {}).get("position", math.nan)
        return CycleWear(inc, work, metrics, float(dev))

    return cycle


def run_metrics(ds, joint: str) -> dict:
    """A joint's contact over a run's samples (a dataset of `result_to_dataset`; the wear
    loop passes those after warmup): peak and RMS contact force [N], contact onsets,
    largest penetration and the force-weighted mean penetration in contact [m] (the
    elastic approach: the scale the adaptive update factor keeps each iteration's wear
    below, `WearSettings.max_step_penetration`)."""
    k = [str(c) for c in ds["clearance"].values].index(joint)
    f = np.abs(np.asarray(ds["contact_force"].values[:, k], dtype=float))
    on = f > 0.0
    pen = np.asarray(ds["penetration"].values[:, k], dtype=float) if "penetration" in ds else f * 0
    fsum = float(f.sum())
    return {
        "mean_penetration": float(np.sum(f * np.clip(pen, 0, None)) / fsum) if fsum else 0.0,
        "peak_contact_force": float(f.max()) if f.size else 0.0,
        "rms_contact_force": float(np.sqrt(np.mean(f**2))) if f.size else 0.0,
        "impacts": int(np.count_nonzero(on[1:] & ~on[:-1])),
        "max_penetration": max(0.0, float(pen.max())) if pen.size else 0.0,
    }


class WearStateError(ValueError):
    """The output folder's wear.nc belongs to another scenario."""


class WearRunError(RuntimeError):
    """A run inside the wear loop failed; `output` is its RunOutput."""

    def __init__(self, message: str, output=None):
        super().__init__(message)
        self.output = output


def _e_star(cl) -> float:
    if isinstance(cl, RevoluteClearance):
        a, b = cl.journal_material, cl.bearing_material
    else:
        a, b = cl.ball_material, cl.socket_material
    return effective_modulus(a.E, a.nu, b.E, b.nu)


def _load_state(path: Path, key: str, maps: dict, clearances: dict) -> WearLoop | None:
    """The loop state saved at `path` for the same scenario (`key`), or None."""
    import xarray as xr

    if not path.exists():
        return None
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds = ds.load()
    if ds.attrs.get("key") != key:
        raise WearStateError(
            f"{path} holds the wear prediction of another scenario (or other [wear] "
            "settings): run with --restart (restart=True) to replace it, or choose another "
            "output folder"
        )
    st = WearLoop(maps, clearances, done=bool(ds.attrs.get("done", 0)))
    joints = [str(j) for j in ds["joint"].values]
    for i in range(ds.sizes["iteration"]):
        row = {
            "cycles": float(ds["cycles"][i]),
            "factor": float(ds["update_factor"][i]),
            "platform": float(ds["platform_deviation"][i]),
        }
        for name in JOINT_VARS:
            row[name] = {j: float(ds[name][i, k]) for k, j in enumerate(joints)}
        st.rows.append(row)
    for j, m in maps.items():
        m.depth[:] = ds[f"depth_{j}"].values
    if all(f"depth_history_{j}" in ds for j in maps):
        st.depths = [
            {j: ds[f"depth_history_{j}"].values[i].astype(float) for j in maps}
            for i in range(ds.sizes["iteration"])
        ]
    return st


def _new_map(cl, js: JointWear):
    """The unworn depth map of a joint's wearing part: the socket of a spherical clearance
    joint (grid cells per cube face), the bearing of a revolute or cylindrical one (4 grid
    cells around each station: the socket's angular resolution)."""
    if isinstance(cl, RevoluteClearance):
        stations = 1 if cl.model == "planar" else cl.stations
        length = js.length if js.length is not None else cl.length
        return BearingWearMap(cl.bearing_radius, float(length), stations, 4 * js.grid)
    return SphereWearMap(cl.ball_radius + cl.c, js.grid)


@dataclass
class WearPrediction:
    """What `predict_wear` produced: the loop state, its history and the files."""

    state: WearLoop
    history: object
    files: list


def predict_wear(
    scenario,
    *,
    out_dir: str | Path | None = None,
    restart: bool = False,
    figures: bool = True,
    log: Callable[[str], None] | None = print,
    max_iterations: int | None = None,
) -> WearPrediction:
    """Run the wear loop of a scenario's [wear] table (module docstring); write `wear.nc`
    (history and maps, after every iteration) and the figures into `out_dir` (default:
    the scenario's output folder)."""
    from clearance.io.files import atomic_path
    from clearance.scenario import load_scenario
    from clearance.scenario.serialize import scenario_to_dict

    s = scenario if not isinstance(scenario, (str, Path)) else load_scenario(scenario)
    settings = s.wear
    if settings is None:
        from clearance.scenario.errors import ScenarioError

        raise ScenarioError(str(s.source), "wear", "(missing)", "a [wear] table is needed")
    out = Path(out_dir if out_dir is not None else s.output.folder)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "wear.nc"
    key = json.dumps(scenario_to_dict(s), sort_keys=True, default=str)
    joints = s.clearance.joints
    maps = {j: _new_map(joints[j], js) for j, js in settings.joints.items()}
    clearances = {j: float(joints[j].c) for j in settings.joints}
    state = None if restart else _load_state(path, key, maps, clearances)
    if state is not None and log is not None:
        log(f"[wear] resuming from {path}: {len(state.rows)} iterations, {state.cycles:.6g} cycles")
    if state is None:
        state = WearLoop(maps, clearances)

    def save(st: WearLoop) -> None:
        ds = st.history()
        ds.attrs["key"] = key
        ds.attrs["wear"] = json.dumps(settings.to_dict())
        with atomic_path(path) as tmp:
            ds.to_netcdf(tmp, engine="netcdf4")

    e_star = {j: _e_star(joints[j]) for j in settings.joints}
    cycle = _cycle_of_scenario(s, settings, e_star, None, out_dir=out)
    run_wear_loop(cycle, settings, state, log=log, save=save, max_iterations=max_iterations)
    files = [path]
    hist = state.history()
    if figures and state.rows:
        from clearance.wear.figures import wear_figures

        files += wear_figures(state, out)
    return WearPrediction(state, hist, files)
