"""`simulate`: consistent initial conditions, the compiled integrator loop, post-processing
into a `Result`; and `scipy_rhs`, the same right-hand side for `scipy.integrate.solve_ivp`.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from collections.abc import Callable

import numpy as np

from clearance.analysis.assembly import assemble, rank_check, velocity_analysis
from clearance.compile.compiled import Compiled, compile_mechanism
from clearance.contact.element import ContactState, make_contact_state
from clearance.dynamics.rhs import make_work, rhs
from clearance.integrate.buffers import prefaulted_zeros, prefaulted_zeros_many
from clearance.integrate.methods import METHODS, method_loop, resolve_method
from clearance.integrate.post import Blocks, PostArrays, post_process
from clearance.integrate.sections import Section
from clearance.integrate.state import Options, Outputs
from clearance.kinds import (
    CT_BUDGET,
    CT_IOUT,
    CT_NLOG,
    CT_STATUS,
    CT_T,
    NCTL,
    NSTATS,
    STAT_NAMES,
    STATUS_MESSAGE,
    Solver,
    Status,
)
from clearance.layout import CO_DELTA, CO_FN, NCOUT, NLOG, NPOUT, WORK
from clearance.model.drivers import DistanceDriver
from clearance.model.errors import ModelError, finite_real
from clearance.model.mechanism import Mechanism
from clearance.store.result import Result

_SOLVER_CODES = {"schur": Solver.SCHUR, "dense": Solver.DENSE, "lstsq": Solver.LSTSQ}
_SOLVERS = ("auto", *_SOLVER_CODES)


def _solver_code(c: Compiled, solver: str, y: np.ndarray, t: float) -> int:
    if solver == "auto":
        if c.nrow == 0:
            return int(Solver.SCHUR)
        rep = rank_check(c, t, y)
        return int(Solver.LSTSQ if rep.redundant else Solver.SCHUR)
    if solver not in _SOLVER_CODES:
        raise ModelError("simulate", "solver", solver, "allowed: 'auto', 'schur', 'dense', 'lstsq'")
    return int(_SOLVER_CODES[solver])


def scipy_rhs(
    c: Compiled,
    *,
    baumgarte: tuple = (5.0, 5.0),
    solver: str = "schur",
    contact_state: ContactState | None = None,
):
    """f(t, y) for `scipy.integrate.solve_ivp`, calling the same compiled right-hand side.

    A mechanism with clearance joints has a discrete contact state (contact flags and the
    impact velocities latched at the onsets, `ContactState`) that the own integrators update
    on accepted steps only; `solve_ivp` has no such hook, so f would integrate a different
    model. Such mechanisms are refused unless `contact_state` is given: f then evaluates with
    that state held fixed (the caller latches it, e.g. stepping a scipy `OdeSolver` by hand
    and calling `latch_contacts(c, contact_state, t, y)` after each accepted step).
    """
    if c.nclr and contact_state is None:
        raise ModelError(
            "scipy_rhs",
            "mechanism",
            c.mechanism.name,
            f"has {c.nclr} clearance joint(s), whose contact state must be latched on "
            "accepted steps, which solve_ivp cannot do: use clearance.simulate, or pass "
            "contact_state=clearance.contact_state(c) and latch it yourself "
            "(clearance.latch_contacts after each accepted step)",
        )
    cs = make_contact_state(c.model) if contact_state is None else contact_state
    wk = make_work(c.model)
    y_check = initial_state(c) if solver == "auto" else c.y0
    code = _solver_code(c, solver, y_check, 0.0)
    alpha, beta = (float(x) for x in baumgarte)
    model = c.model

    ny = c.ny

    def f(t: float, y: np.ndarray) -> np.ndarray:
        if y.shape != (ny,):  # the kernel does not bounds-check: refuse wrong layouts here
            raise ValueError(
                f"scipy_rhs: state of shape {y.shape}, expected ({ny},) "
                f"(Compiled.describe() shows the layout)"
            )
        out = np.empty_like(y)
        y = np.ascontiguousarray(y, dtype=float)
        st = rhs(float(t), y, model, wk, cs, alpha, beta, code, out)
        if st != 0:
            raise FloatingPointError(STATUS_MESSAGE[Status.SINGULAR] + f" at t = {t}")
        return out

    return f


def initial_state(
    c: Compiled, *, t: float = 0.0, y0: np.ndarray | None = None, assemble_positions: bool = True
) -> np.ndarray:
    """Consistent initial state: assembled positions and projected velocities."""
    y = np.array(c.y0 if y0 is None else y0, dtype=float)
    if y.shape != (c.ny,):
        raise ModelError("simulate", "y0", y.shape, f"expected a state of length {c.ny}")
    if assemble_positions and c.nrow:
        y = assemble(c, y, t=t)
        y = velocity_analysis(c, y, t=t)
    y[c.layout.iw :] = 0.0  # work integrals start at zero
    return y


def contact_state(c: Compiled) -> ContactState:
    """A contact state for `c` with every contact point out of contact (see `scipy_rhs`)."""
    return make_contact_state(c.model)


def latch_contacts(c: Compiled, cs: ContactState, t: float, y: np.ndarray) -> bool:
    """The discrete update of the own integrators at an accepted state (t, y): latch onsets
    and clear separations in cs, reset LuGre bristles in y at separations (in place). Returns
    True if cs or y changed."""
    from clearance.integrate.events import update_contacts

    log = np.zeros((0, NLOG))
    changed, _ = update_contacts(c.model, make_work(c.model), cs, float(t), y, log, 0, False)
    return bool(changed)


def simulate(
    system: Mechanism | Compiled,
    t_end: float,
    *,
    t_start: float = 0.0,
    dt_out: float | None = None,
    t_out: np.ndarray | None = None,
    method: str = "auto",
    rtol: float = 1e-6,
    atol: float = 1e-9,
    first_step: float = 0.0,
    max_step: float = math.inf,
    min_step: float = 1e-14,
    max_steps: int = 10_000_000,
    step: float = 1e-3,
    baumgarte: tuple = (5.0, 5.0),
    solver: str = "auto",
    projection: bool = False,
    projection_tol: float = 1e-10,
    y0: np.ndarray | None = None,
    assemble_positions: bool = True,
    max_events: int = 100_000,
    max_wall_time: float = math.inf,
    progress: Callable[[float], object] | None = None,
    stop: object | None = None,
    post_tol: float | None = None,
    section: Section | None = None,
) -> Result:
    """Simulate a mechanism from t_start to t_end.

    Output at `t_out`, or every `dt_out` (default: 201 samples). method: "tsit5" (Tsitouras
    5(4)), "dopri5" (Dormand-Prince 5(4)), "dop853" (Dormand-Prince 8(5,3)) or "vern7"
    (Verner 7(6)), adaptive
    (rtol/atol, first_step, max_step, min_step, max_steps) with dense output; "auto" (the
    default): tsit5 for rtol >= 1e-10, vern7 below (`methods.AUTO_RTOL`;
    settings["method"] says which ran); or "rk4" (fixed `step`).
    baumgarte: (alpha, beta) [1/s]; solver: "auto" (Schur; least squares if the constraints
    are redundant), "schur", "dense", "lstsq"; projection: mass-weighted coordinate
    projection after every accepted step. Contact onsets and separations of clearance joints
    are located (adaptive methods: on the dense output) and logged (up to max_events). The
    initial state is assembled and its velocities made consistent unless
    assemble_positions=False. A failure returns the partial result with status != 0 and a
    message.

    The compiled loop hands control back every ~0.1 s of wall time (`SLICE_SECONDS`), so:
    progress(t) is called then with the simulated time reached; a run still integrating
    after max_wall_time seconds stops with status WALL_TIME; a run whose `stop` (any
    object with is_set(), e.g. a threading.Event) is set stops with status INTERRUPTED;
    Ctrl-C (KeyboardInterrupt) stops it within a slice and raises `Interrupted`, a
    KeyboardInterrupt carrying the partial result (`.result`). Each stops with the samples
    computed so far. Slicing does not change the run: the steps are those of one call.

    What is derived from the states at the samples (accelerations, multipliers, violations,
    energies, reactions, clearance diagnostics) is evaluated exactly on a subset of the
    samples and interpolated in between where the interpolant is verified to agree with the
    exact values within post_tol |x| + atol (default post_tol: rtol; the constraint
    violations phi, phi_dot: within their own size; 0: every sample evaluated exactly;
    `clearance.integrate.post`). `stats["post_exact"]` counts the exact
    evaluations.

    section: a Poincare section (`Section`: a body's state coordinate = value, crossed in a
    direction), located on the dense output of every accepted step as contact onsets are
    (adaptive methods only); the crossings' times and states are `Result.section_time`,
    `Result.section_state` (and `stats["section_crossings"]` counts them all).
    """
    c = system if isinstance(system, Compiled) else compile_mechanism(system)
    if not isinstance(method, str) or (method != "auto" and method not in METHODS):
        raise ModelError(
            "simulate", "method", method, f"allowed: 'auto', {', '.join(map(repr, METHODS))}"
        )
    if not isinstance(solver, str) or solver not in _SOLVERS:
        raise ModelError("simulate", "solver", solver, f"allowed: {', '.join(_SOLVERS)}")
    if not finite_real(t_start):
        raise ModelError("simulate", "t_start", t_start, "expected a finite number")
    for name, val, lo in (
        ("t_end", t_end, t_start),
        ("rtol", rtol, 0.0),
        ("atol", atol, 0.0),
        ("step", step, 0.0),
        ("min_step", min_step, 0.0),
        ("projection_tol", projection_tol, 0.0),
    ):
        if not (finite_real(val) and val > lo):
            raise ModelError("simulate", name, val, f"expected a finite number > {lo}")
    # a NaN here used to pass every comparison and burn max_steps before a wrong message
    if not (finite_real(first_step) and first_step >= 0.0):
        raise ModelError("simulate", "first_step", first_step, "expected a finite number >= 0")
    if not (_number(max_step) and max_step > 0.0):  # inf: no cap
        raise ModelError("simulate", "max_step", max_step, "expected a number > 0 (inf allowed)")
    if not (
        isinstance(baumgarte, (tuple, list, np.ndarray))
        and len(baumgarte) == 2
        and all(finite_real(x) and x >= 0.0 for x in baumgarte)
    ):
        raise ModelError(
            "simulate", "baumgarte", baumgarte, "expected (alpha, beta): two finite numbers >= 0"
        )
    for name, val, lo in (("max_steps", max_steps, 1), ("max_events", max_events, 0)):
        # an integral float (max_steps = 1e7) is the integer it names, as before
        integral = finite_real(val) and float(val).is_integer()
        if not integral or not lo <= int(val) < 2**62:
            raise ModelError("simulate", name, val, f"expected an integer in [{lo}, 2**62)")
    max_steps, max_events = int(max_steps), int(max_events)
    requested, method = method, resolve_method(method, rtol)
    if not (_number(max_wall_time) and max_wall_time > 0.0):  # inf: no limit
        raise ModelError(
            "simulate", "max_wall_time", max_wall_time, "expected seconds > 0 (inf: no limit)"
        )
    if post_tol is None:
        post_tol = rtol
    if not (finite_real(post_tol) and post_tol >= 0.0):
        raise ModelError(
            "simulate", "post_tol", post_tol, "expected a finite number >= 0 (0: no interpolation)"
        )
    if progress is not None and not callable(progress):
        raise ModelError("simulate", "progress", progress, "expected a function of t, or None")
    if stop is not None and not callable(getattr(stop, "is_set", None)):
        raise ModelError(
            "simulate", "stop", stop, "expected an object with is_set() (threading.Event)"
        )
    if c.nclr and max_events * NLOG * 8 > memory_budget():
        raise ModelError(
            "simulate",
            "max_events",
            max_events,
            f"the event log would take {max_events * NLOG * 8 / 2**30:.3g} GiB, above the "
            "memory budget (half of this machine's memory, or CLEARANCE_MEMORY_BUDGET [GiB])",
        )
    if t_out is None:
        if dt_out is None:
            t_out = np.linspace(t_start, t_end, 201)
        else:
            count = (t_end - t_start) / dt_out if finite_real(dt_out) and dt_out > 0 else math.nan
            if not math.isfinite(count):  # (1e-310: the count overflows)
                raise ModelError("simulate", "dt_out", dt_out, "expected a finite number > 0")
            n = int(math.floor(count + 1e-9))
            check_output_size(c, n + 2, t_end - t_start)  # before np.arange allocates
            t_out = t_start + dt_out * np.arange(n + 1)
            if t_out[-1] < t_end - 1e-12 * max(1.0, abs(t_end)):
                t_out = np.append(t_out, t_end)
    sec = None
    if section is not None:
        if not isinstance(section, Section):
            raise ModelError("simulate", "section", section, "expected a clearance.Section")
        if not METHODS[method].adaptive:
            raise ModelError(
                "simulate",
                "section",
                section.label(),
                f"located on the dense output: needs an adaptive method, not {method!r}",
            )
        sec = (section.weights_for(c), section.value, section.direction, section.max_crossings)
    t_out = np.ascontiguousarray(t_out, dtype=float)
    if (
        t_out.ndim != 1
        or t_out.size == 0
        or not np.all(np.isfinite(t_out))
        or np.any(np.diff(t_out) <= 0)
        or t_out[0] < t_start
    ):
        raise ModelError("simulate", "t_out", t_out[:5], "expected increasing times >= t_start")
    check_output_size(c, t_out.size, float(t_out[-1] - t_out[0]), "t_out")
    y = initial_state(c, t=t_start, y0=y0, assemble_positions=assemble_positions)
    code = _solver_code(c, solver, y, t_start)
    alpha, beta = (float(x) for x in baumgarte)
    opts, out = loop_inputs(
        c,
        t_out,
        alpha=alpha,
        beta=beta,
        solver=code,
        rtol=rtol,
        atol=atol,
        h0=first_step,
        hmax=max_step,
        hmin=min_step,
        max_steps=max_steps,
        proj_tol=projection_tol if projection else 0.0,
        step=step,
        max_events=max_events,
        stages=METHODS[method].stages,
        section=sec,
    )
    wk = make_work(c.model)
    cs = make_contact_state(c.model)
    wall0 = _time.perf_counter()
    (status, nout, t_reached, nlog), ctrl_c = _run_loop(
        method,
        c.model,
        wk,
        cs,
        opts,
        out,
        t_start,
        y,
        deadline=wall0 + max_wall_time,
        progress=progress,
        stop=stop,
    )
    wall = _time.perf_counter() - wall0
    message = STATUS_MESSAGE[Status(status)]
    if status == Status.WALL_TIME:
        message = f"the wall-time limit max_wall_time = {max_wall_time:g} s was reached"
    elif status == Status.INTERRUPTED:
        message = "interrupted (Ctrl-C)" if ctrl_c else "interrupted (stop requested)"
    if status != 0:
        message += f" (stopped at t = {t_reached:.6g} s; {nout} of {t_out.size} samples kept)"
    log = out.log
    if nlog > log.shape[0]:
        message += f"; the event log kept the first {log.shape[0]} of {nlog} contact events"
    result = _build_result(
        c,
        t_out[:nout],
        out.Y[:nout],
        out.CS[:nout],
        out.piece[:nout],
        log[: min(nlog, log.shape[0])],
        out.PK,
        wk,
        cs,
        alpha,
        beta,
        code,
        out.stats,
        wall,
        int(status),
        message,
        dict(
            method=method,
            method_requested=requested,
            rtol=rtol,
            atol=atol,
            max_step=max_step,
            step=step,
            baumgarte=(alpha, beta),
            solver=solver,
            solver_used=Solver(code).name.lower(),
            projection=projection,
            projection_tol=projection_tol,
            max_wall_time=max_wall_time,
            post_tol=post_tol,
        ),
        ptol=post_tol,
        pabs=atol if post_tol > 0.0 else 0.0,
    )
    if sec is not None:
        ns = int(out.sec[2])
        kept = min(ns, out.sec_t.size)
        result = dataclasses.replace(
            result,
            section_time=out.sec_t[:kept].copy(),
            section_state=out.sec_Y[:kept].copy(),
            section_label=section.label(),
        )
        result.stats["section_crossings"] = ns
        if ns > kept:
            result = dataclasses.replace(
                result,
                message=result.message + f"; the section kept the first {kept} of {ns} crossings",
            )
    if ctrl_c:
        raise Interrupted(result)
    return result


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during `simulate`: the run stopped within a slice; `.result` holds what it
    computed (status INTERRUPTED). A KeyboardInterrupt, so a script still stops unless it
    asks for the partial result."""

    def __init__(self, result: Result) -> None:
        super().__init__(f"simulate: {result.message}")
        self.result = result

    def __reduce__(self):  # (pickles: its argument is the result, not the message)
        return type(self), (self.result,)


def _number(x: object) -> bool:
    """A real number (not a bool, not a string): infinities included."""
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(
        x, (bool, np.bool_)
    )


def sample_bytes(c: Compiled) -> int:
    """Bytes one output sample of `c` takes in a run's arrays: the state and contact state
    the loop writes, and what the post-processing derives (accelerations, multipliers,
    violations, energies, reactions, clearance diagnostics)."""
    nbk = len(c.joints) + len(c.drivers)
    floats = (
        1  # t
        + c.ny
        + 2 * c.ncp
        + c.nv
        + 3 * c.nrow
        + 3
        + 6 * nbk
        + c.nclr * NCOUT
        + c.ncp * NPOUT
    )
    return 8 * floats


def memory_budget() -> int:
    """Bytes a run's arrays may take: CLEARANCE_MEMORY_BUDGET [GiB] if set, else half of
    this machine's physical memory (8 GiB where it cannot be read)."""
    import os

    env = os.environ.get("CLEARANCE_MEMORY_BUDGET")
    if env:
        try:
            gib = float(env)
        except ValueError:
            gib = math.nan
        if not (math.isfinite(gib) and gib > 0):
            raise ModelError(
                "environment", "CLEARANCE_MEMORY_BUDGET", env, "expected a number of GiB > 0"
            )
        return int(gib * 2**30)
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") // 2
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


def check_output_size(
    c: Compiled, n: int, span: float, field: str = "dt_out", *, copies: int = 1
) -> None:
    """ModelError before anything is allocated when `n` output samples over `span`
    seconds (`copies` times: a scenario run holds two runs and their datasets) would not
    fit in `memory_budget()`: says how much, and an output interval that fits."""
    per = copies * sample_bytes(c)
    need, budget = n * per, memory_budget()
    if need <= budget:
        return
    # n = floor(span / dt) + 2 samples must fit: dt >= span / (budget // per - 2), rounded
    # up to 2 significant digits so that the printed value fits too
    fits = span / max(budget // per - 3, 1)
    scale = 10.0 ** (math.floor(math.log10(fits)) - 1)
    fits = math.ceil(fits / scale) * scale
    raise ModelError(
        "simulate",
        field,
        f"{n} samples",
        f"the run's arrays would take about {need / 2**30:.3g} GiB, above the memory budget "
        f"of {budget / 2**30:.3g} GiB (half of this machine's memory, or "
        f"CLEARANCE_MEMORY_BUDGET [GiB]); use an output interval of at least {fits:.3g} s "
        "or a shorter run",
    )


def loop_inputs(
    c: Compiled,
    t_out: np.ndarray,
    *,
    max_events: int,
    stages: int = 7,
    section: tuple | None = None,
    **opts,
) -> tuple:
    """(Options, Outputs) of a compiled loop run of `c` sampled at `t_out`: the options
    (alpha, beta, solver code, rtol, atol, h0, hmax, hmin, max_steps, proj_tol, step) as
    the numbers the loops are compiled for, and zeroed output buffers."""
    kinds = {"solver": int, "max_steps": int}
    opts = Options(**{k: kinds.get(k, float)(v) for k, v in opts.items()})
    out = Outputs(
        t_out=t_out,
        Y=prefaulted_zeros((t_out.size, c.ny)),
        CS=prefaulted_zeros((t_out.size, c.ncp, 2)),  # per contact point: can be MBs
        piece=np.full(t_out.size, -1, dtype=np.int64),  # (-1 unless written by accept.sample)
        log=np.zeros((max_events if c.nclr else 0, NLOG)),
        stats=np.zeros(NSTATS),
        PK=np.zeros((c.nclr, 4)),
        ctl=np.zeros(NCTL),
        ys=np.zeros(c.ny),
        ks=np.zeros((stages, c.ny)),  # the method's stages (methods.Method.stages)
        # section: (weights (ny,), value, direction, max_crossings) or None
        sec=np.array([0.0, 0.0, 0.0] if section is None else [section[1], section[2], 0.0]),
        sec_w=np.zeros(0) if section is None else np.asarray(section[0], dtype=float),
        sec_t=np.zeros(0 if section is None else section[3]),
        sec_Y=np.zeros((0, c.ny) if section is None else (section[3], c.ny)),
    )
    return opts, out


#: wall time of one call of a compiled loop [s]: how soon Ctrl-C, a stop request,
#: max_wall_time and the progress callback act (0: the whole run in one call)
SLICE_SECONDS = 0.1


def _run_loop(
    method, model, wk, cs, opts, out, t0, y, *, deadline=math.inf, progress=None, stop=None
) -> tuple[tuple[int, int, float, int], bool]:
    """Run the compiled loop of `method` (methods.METHODS) in slices of ~SLICE_SECONDS of
    wall time (state.py, item 4): ((status, outputs written, last time, events), whether
    Ctrl-C stopped it). Between slices: progress(t), the stop request, the deadline."""
    loop = method_loop(method)
    data = METHODS[method].data
    ctl = out.ctl
    ctl[:] = 0.0
    ctl[CT_T] = t0
    budget = 64 if SLICE_SECONDS > 0 else 0  # steps in the first slice; then sized to
    # the measured time per step (0: no limit)
    try:
        while True:
            ctl[CT_BUDGET] = budget
            ctl[CT_STATUS] = -1.0
            a = _time.perf_counter()
            res = loop(model, wk, cs, opts, out, *data, float(t0), y)
            if res[0] != Status.PAUSED:
                return res, False
            now = _time.perf_counter()
            budget = max(1, min(4 * budget, int(budget * SLICE_SECONDS / max(now - a, 1e-9))))
            if progress is not None:
                progress(float(res[2]))
            if stop is not None and stop.is_set():
                return (int(Status.INTERRUPTED), *res[1:]), False
            if now > deadline:
                return (int(Status.WALL_TIME), *res[1:]), False
    except KeyboardInterrupt:  # between two slices: the state kept at the last return
        st = int(ctl[CT_STATUS])
        if st in (-1, int(Status.PAUSED)):  # (-1: before the first call returned)
            st = int(Status.INTERRUPTED)
        return (st, int(ctl[CT_IOUT]), float(ctl[CT_T]), int(ctl[CT_NLOG])), True


def _build_result(
    c: Compiled,
    ts,
    Y,
    CS,
    PC,
    log,
    PK,
    wk,
    cs,
    alpha,
    beta,
    code,
    stats,
    wall,
    status,
    message,
    settings,
    ptol=0.0,
    pabs=0.0,
) -> Result:
    """The Result of a loop run: the post-processed quantities (post.py; PC: the dense-output
    piece of each sample, Outputs.piece; ptol, pabs: the interpolation tolerance, 0: every
    sample evaluated) and the energy balance."""
    n = ts.size
    m = c.nrow
    blocks = c.joints + c.drivers
    nbk = len(blocks)
    blk_row0 = np.array([b.row0 for b in blocks], dtype=np.int64)
    blk_nrow = np.array([b.nrows for b in blocks], dtype=np.int64)
    blk_side = np.array([1 if b.body_j != "ground" else 0 for b in blocks], dtype=np.int64)
    blk_pt = np.zeros((nbk, 3))
    mech = c.mechanism
    for k, b in enumerate(blocks):
        blk_pt[k] = _block_point(mech, b.name, blk_side[k])
    # one mapping for the post-processed outputs (buffers.prefaulted_zeros_many), another
    # for q and v (copied out of Y below), which a script may keep alone
    VD, LAM, PHI, PHID, EN, RF, RM, COUT, POUT = prefaulted_zeros_many(
        [
            (n, c.nv),
            (n, m),
            (n, m),
            (n, m),
            (n, 3),
            (n, nbk, 3),
            (n, nbk, 3),
            (n, c.nclr, NCOUT),
            (n, c.ncp, NPOUT),
        ]
    )
    QS, VS = prefaulted_zeros_many([(n, c.nq), (n, c.nv)])
    nexact = 0
    if n:
        nexact = post_process(
            c.model,
            wk,
            cs,
            alpha,
            beta,
            code,
            ts,
            Y,
            CS,
            PC,
            n,
            Blocks(blk_row0, blk_nrow, blk_side, blk_pt),
            PostArrays(  # (2-D views: one row per sample)
                VD,
                LAM,
                PHI,
                PHID,
                EN,
                RF.reshape(n, -1),
                RM.reshape(n, -1),
                COUT.reshape(n, -1),
                POUT.reshape(n, -1),
            ),
            float(ptol),
            float(pabs),
        )
    np.copyto(QS, Y[:, : c.nq])
    np.copyto(VS, Y[:, c.nq : c.nq + c.nv])
    lay = c.layout
    W = Y[:, lay.iw : lay.idn]
    Dn = Y[:, lay.idn : lay.idt]
    Dt = Y[:, lay.idt : lay.ny]
    T, V, Vc = EN[:, 0], EN[:, 1], EN[:, 2]
    # physics.md j: residual = (T + V + V_c) - (.)(0) - W_c - W_a - W_m - W_L + D_n + D_t
    resid = (
        (
            T
            + V
            + Vc
            - (T[0] + V[0] + Vc[0])
            - W[:, 0]
            - W[:, 2]
            - W[:, 3]
            - W[:, 4]
            + Dn.sum(axis=1)
            + Dt.sum(axis=1)
        )
        if n
        else np.zeros(0)
    )
    drv_rows, drv_names, drv_scale = [], [], []
    for b in c.drivers:
        d = mech.drivers[b.name]
        # squared distance rows (phi = d.d - l^2) carry lam = F/(2 l): report the force
        if isinstance(d, DistanceDriver) and d.squared:
            sc = 2.0 * np.array([d.function(tk) for tk in ts])
        else:
            sc = np.ones(n)
        for r in range(b.row0, b.row0 + b.nrows):
            drv_rows.append(r)
            drv_names.append(b.name)
            drv_scale.append(sc)
    energy = dict(
        kinetic=T,
        potential=V,
        **{name: W[:, k] for k, (name, _) in enumerate(WORK)},
        contact=Vc,
        damping=Dn.sum(axis=1),
        friction=Dt.sum(axis=1),
        residual=resid,
    )
    # peaks over the accepted steps and the output samples (interpolated states)
    peaks = PK.copy()
    for k in range(c.nclr if n else 0):
        for col, src in ((0, CO_FN), (2, CO_DELTA)):
            i = int(np.argmax(COUT[:, k, src]))
            if COUT[i, k, src] > peaks[k, col]:
                peaks[k, col] = COUT[i, k, src]
                peaks[k, col + 1] = ts[i]
    st: dict = {
        name: (float(stats[k]) if name.startswith("h") else int(stats[k]))
        for k, name in enumerate(STAT_NAMES)
    }
    st["wall_time"] = wall
    st["post_exact"] = int(nexact)  # samples evaluated exactly (the rest interpolated)
    return Result(
        compiled=c,
        t=ts.copy(),
        q=QS,
        v=VS,
        a=VD,
        lam=LAM,
        phi=PHI,
        phi_dot=PHID,
        reaction_force=RF,
        reaction_moment=RM,
        reaction_body=tuple(
            b.body_j if s else b.body_i for b, s in zip(blocks, blk_side, strict=True)
        ),
        blocks=tuple(b.name for b in blocks),
        driver_force=(
            -LAM[:, drv_rows] * np.column_stack(drv_scale) if drv_rows else np.zeros((n, 0))
        ),
        driver_names=tuple(drv_names),
        energy=energy,
        stats=st,
        status=status,
        message=message,
        settings=settings,
        clearance_names=tuple(ci.name for ci in c.clearances),
        contact=COUT,
        contact_state=CS.copy(),
        dissipation=np.stack([Dn, Dt], axis=-1),
        bristle=Y[:, lay.iz : lay.iw].reshape(n, c.ncp, 3).copy(),
        contact_points=POUT,
        contact_point_names=tuple(cp.name for cp in c.contact_points),
        contact_point_joints=tuple(cp.joint for cp in c.contact_points),
        events=log.copy(),
        contact_peaks=peaks,
    )


def _block_point(mech: Mechanism, name: str, side: int) -> np.ndarray:
    """Body-frame point of the reporting body about which a block's moment is reported."""
    el = mech.joints.get(name) or mech.drivers.get(name)
    mi = getattr(el, "marker_i", None)
    mj = getattr(el, "marker_j", None)
    if mi is None and hasattr(el, "joint"):  # prismatic driver: its joint's markers
        jt = mech.joints[el.joint]
        mi, mj = jt.marker_i, jt.marker_j
    if mi is None:  # pose drivers: the driven marker
        return np.array(mech.markers[el.marker].position)
    return np.array(mech.markers[mj if side == 1 else mi].position)
