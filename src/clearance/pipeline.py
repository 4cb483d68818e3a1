"""`run_scenario`: a scenario file end to end (what `clearance run` does).

    scenario -> mechanisms (ideal + clearance) -> inverse kinematics of the prescribed platform
    trajectory (physics.md e.2) -> actuator drives -> ideal run and clearance run on the same
    drives -> one NetCDF file (a group per run, the scenario and version in the attributes)
    -> figures -> summary (contact forces, impacts, deviation from ideal, energy, speed)

Every stage is a library call; this module only wires them together and reports progress.
"""

from __future__ import annotations

import contextlib
import functools
import json
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

import clearance
from clearance.analysis.assembly import assemble, velocity_analysis
from clearance.analysis.ik import IKResult, drives_from_ik, inverse_kinematics
from clearance.analysis.plausibility import plausibility
from clearance.compile.compiled import Compiled, compile_mechanism
from clearance.integrate.methods import ADAPTIVE, resolve_method
from clearance.integrate.simulate import Interrupted, initial_state, latch_contacts, simulate
from clearance.io.forks import forked_worker_signals
from clearance.io.outputs import resolve_outputs
from clearance.kinds import Status
from clearance.model.bodies import Marker, quaternion_to_rotation
from clearance.model.clearance import Clearance
from clearance.model.drivers import OffsetDriver
from clearance.model.errors import ModelError
from clearance.model.mechanism import Mechanism
from clearance.parallel import ParallelMechanism
from clearance.scenario import build_mechanisms, load_scenario, scenario_to_toml
from clearance.scenario.build import with_clearances
from clearance.scenario.schema import InitialPlacement, Scenario
from clearance.scenario.trajectories import IK_SPACING as _IK_SPACING
from clearance.store.result import Result

# what a cold compile (empty kernel cache) takes on the project machine, for the notice
COLD_COMPILE_NOTE = "one time, about 50 s on the project machine (2 cores); cached afterwards"

# RMS comparisons skip the settling of the ball into first contact (mechanisms.md 1.6)
SKIP_SETTLING = 0.05  # [s] PROPOSED
# IK samples: every IK_SPACING s, >= 50 per period, at via points and table rows
# (clearance.scenario.trajectories.ik_times)
IK_SPACING = _IK_SPACING


@dataclass
class RunOutput:
    """What a scenario run produced: the two results, the IK, the summary and the files."""

    scenario: Scenario
    ideal: Result
    clearance: Result
    ik: IKResult | None  # None: no inverse kinematics (a general mechanism's own drivers)
    summary: dict
    files: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    _write: Callable[[], list] | None = field(default=None, repr=False, compare=False)

    def write(self) -> list:
        """Write the files of a `run_scenario(..., defer_write=True)` run (once; a second
        call, or a run that wrote them already, returns them). Its stages ("datasets",
        "write", ...) are added to `timings`, and their time to its "total"."""
        if self._write is not None:
            timer = StageTimer()
            self.files = self._write(timer=timer)
            self._write = None
            self.timings.update(timer)
            self.timings["total"] = self.timings.get("total", 0.0) + sum(timer.values())
        return self.files


class RunInterrupted(KeyboardInterrupt):
    """Ctrl-C during `run_scenario`'s integration: both runs stopped within ~0.1 s, and
    what they computed was written (unless the write was deferred); `.run` is the
    `RunOutput` (status INTERRUPTED). A KeyboardInterrupt: scripts still stop."""

    def __init__(self, run: RunOutput) -> None:
        stopped = [r for r in (run.ideal, run.clearance) if r.status in _STOPPED]
        t = min(_reached(r) for r in stopped or [run.clearance])
        super().__init__(f"interrupted at t = {t:.6g} s")
        self.run = run

    def __reduce__(self):  # (pickles: its argument is the run, not the message)
        return type(self), (self.run,)


def _reached(r: Result) -> float:
    return float(r.t[-1]) if r.t.size else 0.0


def _say(log: Callable[[str], None] | None, msg: str) -> None:
    if log is not None:
        log(msg)


def _platform_channels(r: Result, body: str) -> dict[str, np.ndarray]:
    return {
        "position": r.position(body),
        "velocity": r.velocity(body),
        "acceleration": r.acceleration(body),
        "angular_velocity": r.angular_velocity(body),
        "angular_acceleration": np.einsum(
            "nij,nj->ni", r.rotation(body), r.a[:, 6 * r._k(body) + 3 : 6 * r._k(body) + 6]
        ),
    }


def summarize(
    ideal: Result,
    clr: Result,
    platform: str,
    *,
    skip: float = SKIP_SETTLING,
    thresholds: dict | None = None,
) -> dict:
    """Scalar summary of a scenario run (all SI units).

    Per clearance joint: peak contact force (and its time) and max penetration over the
    integration steps, RMS contact force over the samples, impacts. Platform: RMS
    deviation of position, velocity, acceleration (linear and angular) of the clearance run
    from the ideal run over the common samples after `skip` seconds. Energy residual
    (relative to the energy scale), wall time and real-time factor of both runs, and their
    plausibility (`thresholds`: its keyword arguments, e.g. a scenario's
    `checks.plausibility_kwargs()`).
    """
    out: dict = {"joints": {}, "deviation_rms": {}}
    n = min(ideal.t.size, clr.t.size)
    mask = np.zeros(n, dtype=bool)
    if n:
        same_grid = np.allclose(ideal.t[:n], clr.t[:n], rtol=0, atol=1e-12)
        mask = (clr.t[:n] >= clr.t[0] + skip) & same_grid
    for name in clr.clearance_names:
        fn = clr.contact_force(name)
        sel = fn[: mask.size][mask] if mask.any() else fn
        peak, t_peak = clr.peak_contact_force(name)  # resolved at the steps, not the grid
        out["joints"][name] = {
            "peak_contact_force": peak,
            "peak_contact_force_time": t_peak,
            "rms_contact_force": float(np.sqrt(np.mean(sel**2))) if sel.size else 0.0,
            "impacts": int(len(clr.impacts(name))),
            "max_penetration": max(0.0, clr.peak_penetration(name)[0]),
        }
    if mask.any():
        ci = _platform_channels(ideal, platform)
        cc = _platform_channels(clr, platform)
        for key in ci:
            d = cc[key][:n][mask] - ci[key][:n][mask]
            out["deviation_rms"][key] = float(np.sqrt(np.mean(np.sum(d**2, axis=1))))
    for label, r in (("ideal", ideal), ("clearance", clr)):
        e = r.energy
        scale = float(np.max(np.abs(e["kinetic"]) + np.abs(e["potential"]))) if r.t.size else 1.0
        sim_time = float(r.t[-1] - r.t[0]) if r.t.size else 0.0
        wall = r.stats["wall_time"]
        out[label] = {
            "status": r.status,
            "message": r.message,
            "energy_residual": float(np.max(np.abs(e["residual"]))) if r.t.size else 0.0,
            "energy_residual_relative": (
                float(np.max(np.abs(e["residual"]))) / max(scale, 1e-300) if r.t.size else 0.0
            ),
            "wall_time": wall,
            "real_time_factor": sim_time / wall if wall > 0 else math.inf,
            "steps": r.stats["naccept"],
            "rhs_evaluations": r.stats["nfev"],
            "plausibility": plausibility(r, **(thresholds or {})).as_dict(),
        }
    return out


def implausible(summary: dict) -> list[str]:
    """The runs of a `summarize` summary whose results are physically implausible."""
    return [
        k
        for k in ("ideal", "clearance")
        if summary.get(k, {}).get("plausibility", {}).get("status") == "implausible"
    ]


def format_summary(s: dict) -> str:
    """Human-readable summary lines (the `clearance run` printout)."""
    lines = []
    for name, j in s["joints"].items():
        lines.append(
            f"  {name}: peak F_N {j['peak_contact_force']:.1f} N "
            f"(t = {j['peak_contact_force_time']:.5f} s), "
            f"RMS {j['rms_contact_force']:.1f} N, {j['impacts']} impacts, "
            f"max penetration {j['max_penetration'] * 1e6:.2f} um"
        )
    dev = s["deviation_rms"]
    if dev:
        lines.append(
            "  platform RMS deviation from ideal: "
            f"position {dev['position'] * 1e6:.3g} um, velocity {dev['velocity'] * 1e3:.3g} mm/s, "
            f"acceleration {dev['acceleration']:.3g} m/s^2, angular velocity "
            f"{dev['angular_velocity']:.3g} rad/s, angular acceleration "
            f"{dev['angular_acceleration']:.3g} rad/s^2"
        )
    st = s.get("steady_state")
    if st:
        lines.append(
            f"  steady state ({st['points']} Poincare points after the transient): "
            f"{st['response']}; {st['evidence']}"
        )
    for label in ("ideal", "clearance"):
        r = s[label]
        p = r.get("plausibility", {"status": "ok", "findings": []})
        stopped = r["status"] in _STOPPED  # (from outside: not a failure of the run)
        state = (
            "ok" if r["status"] == 0 else ("STOPPED: " if stopped else "FAILED: ") + r["message"]
        )
        if p["status"] == "implausible":  # (a stopped run keeps its reason in front)
            head = "" if r["status"] == 0 else state + "; "
            state = head + "IMPLAUSIBLE: " + "; ".join(p["findings"])
        elif p["findings"]:
            state += " (warning: " + "; ".join(p["findings"]) + ")"
        lines.append(
            f"  {label}: {state}; "
            f"energy residual {r['energy_residual']:.2e} J ({r['energy_residual_relative']:.1e} "
            f"of the energy scale); {r['steps']} steps, {r['rhs_evaluations']} rhs; wall "
            f"{r['wall_time']:.3f} s (real-time factor {r['real_time_factor']:.2f})"
        )
    return "\n".join(lines)


def place_balls_along_reaction(
    clr: Mechanism, ideal_result: Result, y_ideal: np.ndarray, joints: tuple[str, ...]
) -> np.ndarray:
    """Initial state with each ball at e = c n0 (mechanisms.md 1.6 option B).

    n0 = -f/|f|, f the ideal joint's force of the socket body on the ball body at t = 0, so
    the contact force -F_N n0 starts in the ideal direction. The offset is imposed with three
    temporary OffsetDrivers per joint (socket-frame axes) during assembly, then removed.
    Only ball-in-socket joints are placed; every other clearance joint (journals, sliders,
    a ball with no ideal force) is held ideal during that assembly, so it stays where it is
    in `y_ideal` (centred when that is the ideal start).
    """
    c0 = compile_mechanism(clr)
    placed = [
        jn
        for jn in joints
        if isinstance(getattr(clr.joints.get(jn), "clearance", None), Clearance)
        and np.linalg.norm(ideal_result.reaction(jn)[0][0]) > 0
    ]
    held = {
        jn: replace(jt, clearance=None)
        for jn, jt in clr.joints.items()
        if getattr(jt, "clearance", None) is not None and jn not in placed
    }
    mech = clr.replace(**held) if held else clr.copy()
    names = []
    for jn in placed:
        jt = clr.joints[jn]
        cl = jt.clearance
        socket_marker, ball_marker = (
            (jt.marker_i, jt.marker_j) if cl.socket == "i" else (jt.marker_j, jt.marker_i)
        )
        f_on_body, _ = ideal_result.reaction(jn)
        k = ideal_result.blocks.index(jn)
        ball_body = clr.markers[ball_marker].body
        f_ball = f_on_body[0] if ideal_result.reaction_body[k] == ball_body else -f_on_body[0]
        n0 = -f_ball / np.linalg.norm(f_ball)
        sm = clr.markers[socket_marker]
        A_s = np.eye(3)
        if sm.body != "ground":
            p = y_ideal[c0.q_slice(sm.body)][3:7]
            A_s = quaternion_to_rotation(p)
        for a in range(3):
            mk = Marker.on_axis(
                f"__offset_{jn}_{a}", sm.body, sm.position, axis=A_s.T @ np.eye(3)[a]
            )
            dr = OffsetDriver(f"__offset_{jn}_{a}_drv", mk.name, ball_marker, cl.c * n0[a])
            mech.add(mk, dr)
            names.append(dr.name)
    cb = compile_mechanism(mech)
    y = np.array(y_ideal[: cb.nq + cb.nv].tolist() + [0.0] * (cb.ny - cb.nq - cb.nv))
    y = assemble(cb, y)
    out = np.zeros(c0.ny)
    out[: c0.nq + c0.nv] = y[: c0.nq + c0.nv]
    return velocity_analysis(c0, out)


def _start_from(r_ideal: Result, cc: Compiled, ideal: Mechanism, s: Scenario) -> np.ndarray:
    """Initial state of the clearance mechanism: every body where the ideal run starts. A
    body the ideal mechanism does not have (a universal joint's cross) is placed from that
    state: the clearance mechanism is rebuilt from the ideal one described at its start."""
    y0 = np.zeros(cc.ny)
    ci = r_ideal.compiled
    if cc.body_names == ci.body_names:  # the same bodies: the same q and v
        y0[: cc.nq + cc.nv] = np.concatenate((r_ideal.q[0], r_ideal.v[0]))
        return y0
    at_start = ideal.copy()
    for b in ci.body_names:
        q, sv = r_ideal.q[0, ci.q_slice(b)], ci.v_slice(b)
        v = r_ideal.v[0, sv]
        at_start.bodies[b] = replace(
            ideal.bodies[b],
            position=tuple(q[:3]),
            orientation=tuple(q[3:]),
            velocity=tuple(v[:3]),
            angular_velocity=tuple(v[3:]),
        )
    c0 = compile_mechanism(with_clearances(at_start, s))
    assert c0.body_names == cc.body_names
    y0[: cc.nq + cc.nv] = initial_state(c0, assemble_positions=False)[: cc.nq + cc.nv]
    return y0


def final_state(r: Result) -> np.ndarray:
    """The state vector of a run's last sample (positions, velocities, friction states;
    work integrals 0): a start for `run_scenario(y0=...)`."""
    c = r.compiled
    y = np.zeros(c.ny)
    y[: c.nq] = r.q[-1]
    y[c.nq : c.nq + c.nv] = r.v[-1]
    lay = c.layout
    y[lay.iz : lay.iw] = r.bristle[-1].ravel()
    return y


# the two-trajectory estimate: its integration error must stay far below the separation
LYAPUNOV_RTOL = 1e-9
LYAPUNOV_ATOL = 1e-12
LYAPUNOV_D0 = 1e-7


def steady_lyapunov(cc: Compiled, r: Result, s: Scenario):
    """The largest Lyapunov exponent of the clearance mechanism from the end of a steady-state
    run (`clearance.nonlinear.mechanism_lyapunov`): [steady_state] lyapunov_periods periods,
    renormalised lyapunov_intervals times per period (the first period not counted), at the
    scenario's method with rtol <= LYAPUNOV_RTOL so that the integration error stays far
    below the separation LYAPUNOV_D0."""
    from clearance.nonlinear.mechanism import mechanism_lyapunov

    st = s.steady_state
    sv = s.solver
    k = st.lyapunov_intervals
    return mechanism_lyapunov(
        cc,
        interval=st.period / k,
        intervals=st.lyapunov_periods * k,
        transient_intervals=k,
        t_start=float(r.t[-1]),
        y0=final_state(r),
        d0=LYAPUNOV_D0,
        method=sv.method,
        rtol=min(sv.rtol, LYAPUNOV_RTOL),
        atol=min(sv.atol, LYAPUNOV_ATOL),
        baumgarte=(sv.baumgarte_alpha, sv.baumgarte_beta),
        solver=sv.linear_solver,
        max_step=sv.max_step,
    )


def _given_start(y0: object, cc: Compiled) -> np.ndarray:
    y = np.asarray(y0, dtype=float)
    if y.shape != (cc.ny,) or not np.all(np.isfinite(y)):
        raise ModelError(
            "run_scenario",
            "y0",
            f"shape {y.shape}",
            f"expected {cc.ny} finite numbers: a state of the clearance model "
            "(clearance joints and friction laws as in the run it came from)",
        )
    return y.copy()


def _with_lumped_actuator_forces(r: Result, s: Scenario) -> Result:
    """Lumped limbs have no driver rows (physics.md i): recover their actuator forces from
    the piston's axial balance and attach them as the result's driver channels, so files,
    figures and summaries treat both limb models alike."""
    from dataclasses import replace

    from clearance.mechanisms.sps_cu import lumped_actuator_force

    if r.t.size == 0:
        return r
    params = s.mechanism.params
    pm = getattr(params, "mechanism", None)
    if isinstance(pm, ParallelMechanism):  # its lumped legs ("<leg>.limb")
        if not pm.lumped:
            return r
        from clearance.parallel.lumped import limb_actuator_force

        cols = []  # the drivers in leg order, as pm.actuators
        for leg_name, leg in zip(pm.leg_names, pm.legs, strict=True):
            if leg.actuated is None:
                continue
            if not leg.lumped:  # a driver row of its own
                cols.append(r.actuator_force(f"{leg_name}.drive"))
                continue
            lo, up = leg.links
            cols.append(
                limb_actuator_force(
                    r, f"{leg_name}.limb", f"{leg_name}.S2", lo.mass, up.mass, lo.com, up.com
                )
            )
        return replace(r, driver_force=np.column_stack(cols), driver_names=pm.actuators)
    if pm is not None:  # (a general mechanism: its drivers are its rows)
        return r
    limbs = [b for b in r.compiled.body_names if b.startswith("limb_")]
    if r.driver_names or not limbs:
        return r
    F = np.column_stack([lumped_actuator_force(r, k, params=params) for k in range(1, 5)])
    return replace(r, driver_force=F, driver_names=tuple(f"drive_{k}" for k in range(1, 5)))


class ColdCompile:
    """Two cores for a cold compile (no kernels in the cache yet: the first run).

    numba compiles a kernel with everything it calls, one function after another, in one
    process: ~95 s for what `clearance run` needs, in a chain whose longest path is 23 s.
    While this process does the inverse kinematics (whose own kernels are part of that),
    a forked child compiles the contact-force and contact-event kernels and the contact
    update by calling them on the clearance model, then the loops' on-accept hook; this
    process compiles the applied forces, the projection, the right-hand side and, once
    the child has the contact update, the loops' start (`parent_part`), waits for the
    child (`join`), forks a second one for the post-processing and compiles the
    integration loop meanwhile (`finish` waits for it), loading everything a child
    compiled from the shared on-disk cache. Default scenario, empty cache: 50 s of
    compiling, the first `clearance run` 55 s instead of ~115 s. The compiled code is the
    same either way (the same functions and signatures); only the order and the process
    differ. Nothing happens with a warm cache, without fork, or while other threads run
    (forking a threaded process can deadlock the child); a child that fails costs
    nothing but time, as this process then compiles what is missing.
    """

    def __init__(self, cc: Compiled, method: str) -> None:
        """cc: the compiled clearance model (its layout and kernel types)."""
        import multiprocessing
        import threading

        self.child = self.ready = None
        self.cc = cc
        if _kernels_cached() or threading.active_count() > 1:
            return
        if "fork" not in multiprocessing.get_all_start_methods():
            return
        if not cc.nclr:
            return
        try:
            ctx = multiprocessing.get_context("fork")
            self.ready = ctx.Event()
            self.child = ctx.Process(
                target=_compile_contact_kernels, args=(cc, method, self.ready), daemon=True
            )
            self.child.start()
        except (OSError, AssertionError, RuntimeError):  # e.g. a daemonic process
            self.child = None

    def parent_part(self) -> None:
        """The kernels this process compiles while the child works (after the IK): the
        applied forces, the projection, the right-hand side and, once the child has
        compiled the contact update it calls, the loops' start."""
        if self.child is None:
            return
        from clearance.contact.element import make_contact_state
        from clearance.dynamics.forces import applied_forces
        from clearance.dynamics.rhs import make_work, rhs
        from clearance.integrate.accept import project, start

        m = self.cc.model
        wk, cs = make_work(m), make_contact_state(m)
        y = np.array(self.cc.y0, dtype=float)
        applied_forces(m, y, wk)
        project(m, wk, 0.0, y.copy(), 0, 1e-10, np.int64(1))
        rhs(0.0, y, m, wk, cs, 5.0, 5.0, 0, np.zeros_like(y))
        # the child's contact update, then `start` (which calls it) from the cache; a
        # child that never gets there (killed, failed) only costs this process the
        # compile of both
        give_up = time.monotonic() + 1800  # as `_wait`: never forever
        while not self.ready.wait(timeout=0.5) and self.child.is_alive():
            if time.monotonic() > give_up:
                break
        opts, out = _loop_inputs(self.cc)
        start(m, wk, cs, opts, out, 0.0, y)

    def join(self) -> None:
        """Wait for the contact kernels; then fork a second child for the post-processing,
        which this process would otherwise compile after the integration loop."""
        if self.child is None:
            return
        _wait(self.child)
        import multiprocessing

        try:
            self.child = multiprocessing.get_context("fork").Process(
                target=_compile_post_processing, args=(self.cc,), daemon=True
            )
            self.child.start()
        except (OSError, AssertionError, RuntimeError):
            self.child = None

    def finish(self) -> None:
        if self.child is not None:
            _wait(self.child)
            self.child = None


def _wait(child) -> None:
    child.join(timeout=1800)
    if child.is_alive():  # never wait forever: this process compiles what is missing
        child.terminate()


def _compile_post_processing(cc: Compiled) -> None:  # pragma: no cover - child
    """In the second child of ColdCompile: compile the post-processing kernel by running
    it on one sample, with arrays of the types `simulate` gives it."""
    import os

    forked_worker_signals()
    try:
        from clearance.contact.element import make_contact_state
        from clearance.dynamics.rhs import make_work
        from clearance.integrate.simulate import _build_result
        from clearance.kinds import NSTATS
        from clearance.layout import NLOG

        m = cc.model
        _build_result(
            cc,
            np.zeros(1),
            np.zeros((1, cc.ny)),
            np.zeros((1, cc.ncp, 2)),
            np.full(1, -1, dtype=np.int64),
            np.zeros((0, NLOG)),
            np.zeros((cc.nclr, 4)),
            make_work(m),
            make_contact_state(m),
            5.0,
            5.0,
            0,
            np.zeros(NSTATS),
            0.0,
            0,
            "",
            {},
        )
    finally:
        os._exit(0)


def _kernels_cached() -> bool:
    """Whether the integration loop is in the on-disk kernel cache (numba's index file)."""
    import os

    from clearance.integrate.erk import erk54

    try:
        return os.path.exists(erk54._cache._cache_file._index_path)
    except AttributeError:  # another numba: assume cached (compile in this process)
        return True


def _loop_inputs(cc: Compiled) -> tuple:
    """(Options, Outputs) of the types `simulate` gives the loops, for compiling their
    parts ahead of the loop (ColdCompile)."""
    from clearance.integrate.simulate import loop_inputs

    return loop_inputs(
        cc,
        np.array([0.0, 1e-9]),
        alpha=5.0,
        beta=5.0,
        solver=0,
        rtol=1e-6,
        atol=1e-9,
        h0=0.0,
        hmax=np.inf,
        hmin=1e-14,
        max_steps=10,
        proj_tol=0.0,
        step=1e-3,
        max_events=10,
    )


def _compile_contact_kernels(cc: Compiled, method: str, ready) -> None:  # pragma: no cover
    """In the forked child of ColdCompile: compile the contact forces, the event search and
    the discrete contact update by calling them once on the clearance model, say so
    (`ready`), then compile the loops' on-accept hook, which calls them."""
    import os

    forked_worker_signals()
    try:
        from clearance.contact.element import clearance_forces, make_contact_state
        from clearance.dynamics.rhs import make_work
        from clearance.integrate.accept import after_step
        from clearance.integrate.events import locate_event
        from clearance.integrate.methods import METHODS

        m = cc.model
        wk, cs = make_work(m), make_contact_state(m)
        y = np.array(cc.y0, dtype=float)
        clearance_forces(m, y, wk, cs, np.zeros_like(y))
        data = METHODS[method].data
        if data:  # the adaptive loops: their dense-output matrix P is the last item
            K = np.zeros((data[-1].shape[0], y.size))  # a row per stage of P
            locate_event(m, wk, cs, 0.0, y, K, data[-1], 1e-3, 1e-6)
        latch_contacts(cc, cs, 0.0, y)
        ready.set()
        opts, out = _loop_inputs(cc)
        after_step(m, wk, cs, opts, out, 0.0, y, np.zeros(y.size), np.int64(0), False)
    finally:
        ready.set()
        os._exit(0)


class CompileNotice:
    """Says so when numba compiles kernels (the first run after installing or updating,
    or with a new kernel cache), with progress every `every` seconds, instead of a silent
    wait. Use as a context manager around the first calls of the kernels; `.compiled`
    counts the functions compiled (0: everything came from the cache)."""

    def __init__(self, log: Callable[[str], None] | None, every: float = 10.0) -> None:
        self.log, self.every = log, every
        self.compiled = 0
        self._t0 = self._last = 0.0

    def __enter__(self) -> CompileNotice:
        from numba.core import event

        notice = self

        class _Listener(event.Listener):
            def on_start(self, ev) -> None:
                notice._on_start(ev)

            def on_end(self, ev) -> None:
                pass

        self._cm = event.install_listener("numba:compile", _Listener())
        self._cm.__enter__()
        return self

    def _on_start(self, ev) -> None:
        now = time.perf_counter()
        if self.compiled == 0:
            self._t0 = self._last = now
            _say(self.log, f"      compiling the kernels ({COLD_COMPILE_NOTE}) ...")
        self.compiled += 1
        if now - self._last >= self.every:
            self._last = now
            name = getattr(ev.data["dispatcher"], "__name__", "?")
            _say(
                self.log,
                f"      ... {now - self._t0:4.0f} s, {self.compiled} functions compiled "
                f"(now: {name})",
            )

    def __exit__(self, *exc) -> None:
        self._cm.__exit__(*exc)
        if self.compiled:
            _say(
                self.log,
                f"      compiled {self.compiled} functions in "
                f"{time.perf_counter() - self._t0:.0f} s (cached from now on)",
            )


# the inverse kinematics and the ideal run of the last run_scenario(reuse_ideal=True) in
# this process, keyed by what they depend on (`_ideal_key`)
_IDEAL_MEMO: dict = {}
_RAN = False  # a run_scenario call finished in this process (its imports are loaded)


def _ideal_key(s: Scenario) -> str:
    """What the inverse kinematics and the ideal run depend on: the mechanism, trajectory
    and solver sections (not the clearance joints), and the package version."""
    import hashlib

    from clearance.scenario.serialize import scenario_to_dict

    d = scenario_to_dict(s)
    part = {k: d.get(k) for k in ("mechanism", "trajectory", "solver")}
    part["version"] = clearance.__version__
    return hashlib.sha256(json.dumps(part, sort_keys=True, default=str).encode()).hexdigest()


class _Background:
    """fn() in a second thread, started at once; `result()` joins it and returns its value
    (or raises its exception here); `seconds` is its wall time."""

    def __init__(self, fn: Callable, name: str) -> None:
        import threading

        self._fn, self._value, self._error, self.seconds = fn, None, None, 0.0
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        t0 = time.perf_counter()
        try:
            self._value = self._fn()
        except BaseException as e:  # re-raised by result() in the calling thread
            self._error = e
        self.seconds = time.perf_counter() - t0

    def join(self) -> None:
        self._thread.join()

    def result(self):
        self._thread.join()
        if self._error is not None:
            raise self._error
        return self._value


def _import_writers(figures: bool) -> None:
    """Import what writing the results (and drawing the figures) needs."""
    import clearance.io.dataset  # noqa: F401  (xarray, netCDF4)

    if figures:
        import clearance.plot.figures  # noqa: F401  (matplotlib)


def _fits_in_memory(c_clr: Compiled, info, s: Scenario) -> None:
    """ScenarioError (solver.dt_out) when the clearance run's arrays at the scenario's
    output interval would not fit in memory (`integrate.simulate.check_output_size`)."""
    from clearance.integrate.simulate import check_output_size
    from clearance.scenario import ScenarioError

    dt = info.simulate_kwargs.get("dt_out")
    if dt is None:
        return
    n = int(math.floor(info.t_end / dt + 1e-9)) + 2
    try:  # the two runs, then their datasets: about three clearance runs' arrays
        check_output_size(c_clr, n, info.t_end, copies=3)
    except ModelError as e:
        err = ScenarioError(str(s.source), "solver.dt_out", dt, e.allowed)
        err.transient = True  # another machine (a study's other worker) may have the memory
        raise err from None


def _writable(out: Path, s: Scenario) -> None:
    """Create the output folder and check that it takes files (ScenarioError otherwise)."""
    import tempfile

    from clearance.scenario import ScenarioError

    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=out, prefix=".clearance-probe-"):
            pass
    except OSError as e:
        err = ScenarioError(
            str(s.source),
            "output.folder",
            str(out),
            f"cannot write results there ({e.strerror or e}); choose another folder "
            "([output] folder or --out)",
        )
        err.transient = True  # a full or unreachable disk may recover: a study retries it
        raise err from None


def estimate_run(c_clr: Compiled, info, *, rhs_seconds: float | None = None):
    """The clearance run's `clearance.analysis.cost.CostEstimate` (steps, integration
    time) from the scenario's solver settings and its platform motion."""
    from clearance.analysis.cost import estimate_cost, motion_scales

    kw = info.simulate_kwargs
    speed, acc = motion_scales(c_clr, info)
    return estimate_cost(
        c_clr,
        info.t_end,
        method=resolve_method(kw["method"], kw["rtol"]),
        rtol=kw["rtol"],
        step=kw["step"],
        max_step=kw["max_step"],
        baumgarte=kw["baumgarte"],
        acceleration=acc,
        speed=speed,
        rhs_seconds=rhs_seconds,
    )


def cost_warnings(est, info, long_run: float | None = None) -> list[str]:
    """Warnings about an estimated run (`estimate_run`): one that takes longer than
    `long_run` seconds (default: `LONG_RUN_SECONDS`; a scenario's [checks] long_run), one
    that will exceed its step budget."""
    from clearance.analysis.cost import LONG_RUN_SECONDS, _duration

    long_run = LONG_RUN_SECONDS if long_run is None else long_run
    kw, out = info.simulate_kwargs, []
    adaptive = resolve_method(kw["method"], kw.get("rtol", 1e-6)) in ADAPTIVE
    if est.steps > kw["max_steps"] and adaptive:  # (rk4 has no step budget)
        out.append(
            f"the estimated {est.steps:.2g} steps exceed [solver] max_steps = "
            f"{kw['max_steps']}: the run will likely stop early (set by {est.limit})"
        )
    if est.wall > long_run:
        out.append(
            f"this run may take ~{_duration(est.wall)} (set by {est.limit}); check that "
            "value, or run it anyway: Ctrl-C stops it and writes what it computed, and "
            "[solver] max_wall_time limits it"
        )
    return out


class _Pace:
    """Warns once, from the progress of a run, when its pace so far projects more than
    `long_run` seconds of integration (default `LONG_RUN_SECONDS`; judged after `after`
    seconds; the estimate before the run can be off by a factor of a few, the pace cannot)."""

    def __init__(
        self,
        log: Callable[[str], None] | None,
        t_end: float,
        after: float = 5.0,
        long_run: float | None = None,
    ):
        from clearance.analysis.cost import LONG_RUN_SECONDS

        self.log, self.t_end, self.after = log, t_end, after
        self.long_run = LONG_RUN_SECONDS if long_run is None else long_run
        self.t0 = time.perf_counter()
        self.warned = log is None

    def __call__(self, t: float) -> None:
        from clearance.analysis.cost import _duration

        el = time.perf_counter() - self.t0
        if self.warned or el < self.after or t <= 0.0:
            return
        left = el * (self.t_end - t) / t
        if el + left > self.long_run:
            self.warned = True
            _say(
                self.log,
                f"      warning: at its pace so far this run needs ~{_duration(left)} more "
                f"(t = {t:.3g} of {self.t_end:g} s after {el:.0f} s); Ctrl-C stops it and "
                "writes what it computed, [solver] max_wall_time limits it",
            )


class StageTimer(dict):
    """Wall time per stage [s]: `with timer("write"): ...` adds to timer["write"]."""

    @contextlib.contextmanager
    def __call__(self, stage: str):
        t0 = time.perf_counter()
        try:
            yield
        finally:
            self[stage] = self.get(stage, 0.0) + time.perf_counter() - t0


# the stages of `run_scenario`, in order (RunOutput.timings keys besides "total")
STAGES = (
    "build",
    "inverse_kinematics",
    "kernels",
    "estimate",
    "ideal",
    "clearance",
    "lyapunov",  # ([steady_state] lyapunov_periods > 0)
    "summary",
    "datasets",
    "write",
    "export",
    "figures",
    "report",
)


def run_outputs(s: Scenario, extra: tuple[str, ...] | None, comp: Compiled) -> frozenset:
    """The output groups a run of `s` writes: the lean default, the scenario's [output]
    outputs (or `extra` when given) and per-point channels where a joint has several."""
    joints = [p.joint for p in comp.contact_points]
    several = len(set(joints)) < len(joints)
    return resolve_outputs(s.output.outputs if extra is None else extra, several_points=several)


def _worn(clr: Mechanism, wear: Mapping[str, object] | None) -> Mechanism:
    """The clearance mechanism with the worn sockets `wear` ({joint: SocketWear})."""
    for joint, w in (wear or {}).items():
        clr = clr.with_wear(joint, w)
    return clr


def run_scenario(
    scenario: Scenario | str | Path | None = None,
    *,
    out_dir: str | Path | None = None,
    figures: bool | None = None,
    outputs: tuple[str, ...] | None = None,
    reuse_ideal: bool = False,
    defer_write: bool = False,
    log: Callable[[str], None] | None = print,
    progress: Callable[[str, float, float], object] | None = None,
    y0: np.ndarray | None = None,
    wear: Mapping[str, object] | None = None,
) -> RunOutput:
    """Run a scenario (default: the shipped 4UPS-UPU one) and write its outputs.

    out_dir: output folder (default: the scenario's [output] folder). figures: override the
    scenario's [output] figures flag. outputs: result groups written besides the lean
    default (`clearance.io.outputs`; default: the scenario's [output] outputs).
    reuse_ideal: reuse the inverse kinematics and the ideal run of the previous call in
    this process when they depend on nothing that changed (the mechanism, trajectory and
    solver sections: a study varying only clearance parameters); the timings then say
    reused_ideal = 1. defer_write: return without writing anything; `RunOutput.write()`
    writes the files later (a study writes one case while the next one integrates).
    log: progress messages (None: silent). progress(run, t, t_end): called during the
    integration, about every 0.1 s of wall time, with run "ideal" or "clearance" and the
    simulated time reached (from both runs' threads).
    y0: the clearance run's initial state (the clearance model's layout; its positions are
    assembled at t = 0), e.g. the `final_state` of an earlier run of a periodic drive, to
    continue a branch (`clearance bifurcation --continuation`); default: the initial
    placement of [clearance].
    wear: worn sockets of the clearance run, {joint: `clearance.model.wear.SocketWear`}
    (`Mechanism.with_wear`; `clearance.wear.predict` runs the wear loop with it).
    A run that fails part-way keeps and writes what it computed; its status says why.
    Ctrl-C during the integration stops both runs within ~0.1 s, writes what they computed
    (without figures) and raises `RunInterrupted` (a KeyboardInterrupt) carrying it;
    [solver] max_wall_time stops them the same way, with status WALL_TIME, and returns.
    `RunOutput.timings` holds the wall time of each stage (`STAGES`) and the total.
    """
    from clearance.scenario import default_scenario_path

    t_all = time.perf_counter()
    timer = StageTimer()
    if scenario is None:
        scenario = default_scenario_path()
    with timer("build"):
        s = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
        out = Path(out_dir if out_dir is not None else s.output.folder)
        _writable(out, s)  # before anything runs, not after it
        _say(log, f"[1/5] building '{s.name}' ({s.mechanism.type.value})")
        key = _ideal_key(s) if reuse_ideal else None
        memo = _IDEAL_MEMO.get(key) if key is not None else None
        if memo is not None:  # the drives known: the mechanisms are built once
            ik, ideal, r_ideal, drives = memo
            _, clr, info = build_mechanisms(s, drives=drives)
        else:
            ik = r_ideal = None
            ideal, clr, info = build_mechanisms(s)
        clr = _worn(clr, wear)
    # the clearance model's layout, compiled once: the memory estimate and the cold
    # compile need it before the IK; with reused drives it is also the model that runs
    c_clr = compile_mechanism(clr)
    _fits_in_memory(c_clr, info, s)  # before the inverse kinematics, not after
    sec = s.steady_state.section_spec() if s.steady_state is not None else None
    if sec is not None:  # (its body is known once the mechanism is built)
        try:
            sec.weights_for(c_clr)
        except ModelError as e:
            from clearance.scenario.errors import ScenarioError

            raise ScenarioError(
                str(s.source), "steady_state.section.body", sec.body, e.allowed
            ) from None

    unknown = [b for b in s.view.bodies if b not in c_clr.body_names]
    if unknown:  # [view.bodies.X]: X must be a body of the mechanism
        from clearance.scenario.errors import ScenarioError

        raise ScenarioError(
            str(s.source),
            f"view.bodies.{unknown[0]}",
            unknown[0],
            f"expected a body of the mechanism: {', '.join(c_clr.body_names)}",
        )

    skw = info.simulate_kwargs
    cold = ColdCompile(c_clr, resolve_method(skw["method"], skw.get("rtol", 1e-6)))
    if memo is not None:
        _say(log, "[2/5] inverse kinematics and ideal run: the same as the previous case")
    compiling = contextlib.ExitStack()  # one compile notice over the IK and the kernels
    compiling.enter_context(CompileNotice(log))
    with timer("inverse_kinematics"):
        t_end = info.t_end
        times = info.trajectory.ik_times()
        n_ik = times.size
        if ik is None and not info.actuators:  # (a general mechanism's own drivers)
            _say(log, "[2/5] no inverse kinematics: the drivers of the file run as given")
            drives = None
        elif ik is None:
            _say(log, f"[2/5] inverse kinematics: {n_ik} poses over {t_end:g} s")
            ik = inverse_kinematics(
                info.ik_mechanism or ideal,
                info.platform_trajectory(),
                platform_marker=info.platform_marker,
                actuators=info.actuators,
                times=times,
            )
            drives = drives_from_ik(ik)
            ideal, clr, info = build_mechanisms(s, drives=drives)
            clr = _worn(clr, wear)
    if ik is not None:
        _say(
            log,
            f"      drive Jacobian: min sigma {ik.min_sigma:.3g}, "
            f"max condition {ik.max_condition:.3g}",
        )
    kw = dict(info.simulate_kwargs)
    if s.steady_state is not None:  # whole periods: the stroboscopic times are grid points
        kw.pop("dt_out", None)
        kw["t_out"] = s.steady_state.t_out()
    import threading

    stop = threading.Event()  # Ctrl-C in this thread stops the ideal run's thread too

    def watched(run: str, c: Compiled, **more) -> Result:
        """simulate(c, t_end, ...) reporting its progress as `run`, also at its end; the
        clearance run says so when its pace projects a very long run (once)."""
        pace = _Pace(log, t_end, long_run=s.checks.long_run) if run == "clearance" else None

        def tell(t: float) -> None:
            if progress is not None:
                progress(run, t, t_end)
            if pace is not None:
                pace(t)

        r = simulate(c, t_end, stop=stop, progress=tell, **more, **kw)
        if progress is not None:
            progress(run, _reached(r), t_end)
        return r

    with timer("kernels"), compiling:
        ci = compile_mechanism(ideal) if r_ideal is None else r_ideal.compiled
        cc = c_clr if memo is not None else compile_mechanism(clr)
        cold.parent_part()
        cold.join()
        # load (or, on a fresh install, build once) the compiled kernel before the timed
        # runs, so the reported wall times and real-time factors are integration only
        # (a reused ideal run needs neither: its kernels are loaded, its start known)
        first = [
            simulate(
                c,
                1e-9,
                t_out=np.array([0.0, 1e-9]),
                **{k: v for k, v in kw.items() if k not in ("dt_out", "t_out")},
            )
            for c in ((ci, cc) if r_ideal is None else (cc,))
        ]
        cold.finish()
    # the clearance run starts from the ideal run's first sample (t = 0), which the short
    # run above computed alike: the two runs are independent and integrate at once, the
    # ideal one in a second thread (the loops and the post-processing release the GIL)
    with timer("estimate"):  # (after the kernels: everything it calls is compiled)
        est = estimate_run(cc, info)
    _say(log, f"      estimated: {est.text()}")
    for w in cost_warnings(est, info, s.checks.long_run):
        _say(log, f"      warning: {w}")
    ideal_run = None
    draw = s.output.figures if figures is None else figures
    # the writers' imports (xarray, matplotlib: ~0.5 s) run in a third thread while the
    # runs hold no GIL; joined before anything forks
    imports = _Background(lambda: _import_writers(draw), name="clearance-imports")
    if r_ideal is None:
        start_ref = first[0]
    else:
        timer["ideal"] = 0.0
        timer["reused_ideal"] = 1.0
        start_ref = r_ideal

    def ideal_done() -> Result:
        """The ideal run, joined; remembered for the next case (before the clearance run
        is known to succeed: a retried case reuses it)."""
        r = ideal_run.result()
        timer["ideal"] = ideal_run.seconds
        if key is not None and r.status not in _STOPPED:  # (a stopped run is rerun)
            _IDEAL_MEMO.clear()  # one entry: the memory of one ideal run
            _IDEAL_MEMO[key] = (ik, ideal, r, drives)
        return r

    interrupted = False
    try:  # (from the ideal thread's start: every exit below stops it)
        if r_ideal is None:
            _say(log, "[3/5] ideal mechanism")
            ideal_run = _Background(lambda: watched("ideal", ci), name="clearance-ideal")
        with timer("clearance"):
            _say(
                log,
                f"[4/5] clearance mechanism ({', '.join(info.clearance_joints)}; initial "
                f"placement {s.clearance.initial.value})",
            )
            y_start = None
            if y0 is not None:
                y_start = _given_start(y0, cc)
            elif start_ref.t.size:
                y_start = _start_from(start_ref, cc, ideal, s)
                if s.clearance.initial == InitialPlacement.REACTION:
                    y_start = place_balls_along_reaction(
                        clr, start_ref, y_start, info.clearance_joints
                    )
            r_clr = watched("clearance", cc, y0=y_start, section=sec)
    except Interrupted as e:  # Ctrl-C: keep what was computed, stop the ideal run too
        stop.set()
        r_clr, interrupted = e.result, True
    except BaseException:  # no thread left behind (an interrupt does not wait for it)
        stop.set()
        if ideal_run is not None:
            with contextlib.suppress(Exception):
                ideal_done()
        imports.join()
        raise
    if ideal_run is not None:
        try:
            r_ideal = ideal_done()
        except KeyboardInterrupt:  # Ctrl-C while the ideal run finishes: it stops too
            stop.set()
            r_ideal, interrupted = ideal_done(), True
        _say(log, f"      ideal: {r_ideal.message}; wall {r_ideal.stats['wall_time']:.3f} s")
    _say(log, f"      {r_clr.message}; wall {r_clr.stats['wall_time']:.3f} s")
    imports.result()
    with timer("summary"):
        r_ideal, r_clr = (_with_lumped_actuator_forces(r, s) for r in (r_ideal, r_clr))
        summary = summarize(
            r_ideal, r_clr, info.platform_body, thresholds=s.checks.plausibility_kwargs()
        )
    lam = None
    if s.steady_state is not None and s.steady_state.lyapunov_periods and r_clr.success:
        with timer("lyapunov"):
            _say(log, f"      Lyapunov exponent: {s.steady_state.lyapunov_periods} periods x 2")
            lam = steady_lyapunov(cc, r_clr, s)
    with timer("summary"):
        if s.steady_state is not None and info.platform_body and r_clr.success:
            st = s.steady_state
            # (imported here: scipy.signal and xarray cost `clearance run` 0.8 s of start-up)
            from clearance.nonlinear.analyze import Steady, response_of_run

            grid = Steady(st.period, st.samples_per_period, st.transient_periods, st.phase)
            summary["steady_state"] = response_of_run(r_clr, grid, info.platform_body, lyapunov=lam)
    write = functools.partial(
        write_outputs,
        s,
        {"ideal": r_ideal, "clearance": r_clr},
        out,
        attrs={
            **({"ik_min_sigma": ik.min_sigma, "ik_max_condition": ik.max_condition} if ik else {}),
            **(s.steady_state.attrs() if s.steady_state is not None else {}),
            **({"clearance_final_state": final_state(r_clr)} if r_clr.t.size else {}),
            **(
                {
                    "lyapunov_exponent": lam.exponent,
                    "lyapunov_standard_error": lam.standard_error,
                }
                if lam is not None
                else {}
            ),
            "clearance_final_time": float(r_clr.t[-1]) if r_clr.t.size else 0.0,
            "plausibility": json.dumps(
                {k: summary[k]["plausibility"] for k in ("ideal", "clearance")}
            ),
            "implausible": ",".join(implausible(summary)),
            "summary": json.dumps(summary, default=_plain_json),
        },
        groups=run_outputs(s, outputs, cc),
        platform=info.platform_body,
        figures=draw and not interrupted,  # (Ctrl-C: out promptly; `clearance plot` draws)
    )
    files: list = []
    if not defer_write:
        _say(log, "[5/5] writing results" + (" computed before the interrupt" * interrupted))
        files = write(timer=timer)
    timer["total"] = time.perf_counter() - t_all
    timer["compile"] = timer["kernels"]  # the name before 0.2
    global _RAN
    _RAN = True
    run = RunOutput(s, r_ideal, r_clr, ik, summary, files, dict(timer))
    if defer_write:
        run._write = write
    if interrupted:
        raise RunInterrupted(run)
    return run


# statuses of a run stopped from outside (Ctrl-C, a stop request, max_wall_time)
_STOPPED = (Status.INTERRUPTED, Status.WALL_TIME)


def write_outputs(
    s: Scenario,
    runs: dict[str, Result],
    out: Path,
    *,
    attrs: dict,
    groups: frozenset,
    platform: str,
    figures: bool,
    timer: StageTimer | None = None,
) -> list[Path]:
    """The files of a scenario run: the NetCDF result (the output `groups`, the scenario
    and version in the attributes), the exports its [output] formats ask for and, with
    `figures`, the figures in its figure format, drawn from the datasets in memory."""
    from clearance.io.dataset import result_to_dataset, save_results
    from clearance.io.files import output_stem

    timer = timer if timer is not None else StageTimer()
    with timer("datasets"):
        ds = {
            k: result_to_dataset(r, outputs=groups, bodies=(platform,), max_frames=s.view.frames)
            for k, r in runs.items()
        }
    root = {
        "scenario": scenario_to_toml(s),
        "scenario_name": s.name,
        "scenario_source": str(s.source),
        "clearance_version": clearance.__version__,
        "view": json.dumps(s.view.to_dict()),
        **attrs,
    }
    pending = figure_error = None
    if figures:  # forked processes draw while this one writes (figures: the wait for them)
        from clearance.plot import start_figures

        with timer("figures"):
            try:
                pending = start_figures(
                    ds, out / "figures", platform=platform, formats=(s.output.figure_format,)
                )
            except Exception as e:  # raised once the results are written
                figure_error = e
    try:
        with timer("write"):
            stem = output_stem(s.name)
            files = [save_results(out / f"{stem}.nc", ds, attrs=root)]
        with timer("export"):
            fmts = s.output.formats
            if "csv" in fmts or "mat" in fmts:
                from clearance.io.export import export_csv, export_mat

                if "csv" in fmts:
                    files += export_csv(files[0], out)
                if "mat" in fmts:
                    files.append(export_mat(files[0], out / f"{stem}.mat"))
            if "npz" in fmts:
                from clearance.io.npz import save_npz

                files += [save_npz(r, out / f"{stem}_{k}.npz") for k, r in runs.items()]
    except BaseException:
        if pending is not None:
            pending.cancel()  # no drawing processes left behind
        raise
    if figure_error is not None:
        raise figure_error
    figs: list = []
    if pending is not None:
        with timer("figures"):
            figs = pending.result()
            files += figs
    if s.output.report:
        with timer("report"):
            files.append(_report(files[0], ds, root, figs, out))
    return files


def _plain_json(x: object) -> object:
    """JSON for what `json` does not know in a summary (NumPy scalars and arrays)."""
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


def _report(result: Path, ds: dict, root: dict, figures: list, out: Path) -> Path:
    """report.html of a run (`clearance.view.report`), from the datasets in memory."""
    from clearance.view.report import REPORT, write_report
    from clearance.view.scene import SceneError, scene_from_datasets

    try:
        scene = scene_from_datasets(result, root, ds)
    except SceneError:
        scene = None  # (the report says why it has no viewer)
    summary = json.loads(root.get("summary", "{}"))
    return write_report(
        result, out / REPORT, scene=scene, summary=summary, figures=figures, draw=False
    )


def warmup(log: Callable[[str], None] | None = print) -> dict:
    """Compile (or load from the cache) every kernel a scenario run uses, ahead of time:
    for cluster nodes and containers, so that no run pays the one-time compile. Runs the
    default 4UPS-UPU scenario for 10 ms with each integration method and the 4-SPS/CU one
    with its own (nothing is written but a temporary folder). Returns {"functions": number
    compiled (0: all were cached), "seconds": wall time, "cache": the cache folder}."""
    import tempfile

    from clearance import _kernel_cache
    from clearance.integrate.methods import METHODS
    from clearance.scenario import default_scenario_path, with_overrides
    from clearance.scenario.schema import RK4_CLEARANCE_STEP

    t0 = time.perf_counter()
    short = {"trajectory.duration": 0.01, "solver.dt_out": 1e-3, "output.figures": False}
    jobs = [("ups_upu", m) for m in METHODS] + [("sps_cu", None)]
    n = 0
    with tempfile.TemporaryDirectory() as tmp, CompileNotice(log) as notice:
        for k, (name, method) in enumerate(jobs):
            over = dict(short, **({"solver.method": method} if method else {}))
            if method == "rk4":  # its step must resolve the impacts (RK4_CLEARANCE_STEP)
                over["solver.step"] = RK4_CLEARANCE_STEP
            s = with_overrides(load_scenario(default_scenario_path(name)), over)
            _say(log, f"[{k + 1}/{len(jobs)}] {name}, {s.solver.method}")
            run_scenario(s, out_dir=Path(tmp) / str(k), log=None)
        n = notice.compiled
    out = {
        "functions": n,
        "seconds": time.perf_counter() - t0,
        "cache": str(_kernel_cache.cache_dir()),
    }
    _say(
        log,
        f"kernels ready in {out['seconds']:.0f} s ({n} functions compiled"
        f"{'' if n else ': all were cached'}); cache: {out['cache']}",
    )
    return out
