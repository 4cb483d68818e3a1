"""The `clearance` command line: a thin layer over library calls."""

from __future__ import annotations

import contextlib
import importlib
import os
import sys
import time
from pathlib import Path

_T_START = time.perf_counter()  # the CLI module's import: start-up for `run --timings`

import numpy as np  # noqa: E402
import typer  # noqa: E402

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Dynamics of spatial mechanisms with clearance joints.",
)

# name -> (factory "module:function", end time [s], description)
EXAMPLES = {
    "ups-upu": (
        "clearance.mechanisms.ups_upu:ups_upu_ideal",
        2.0,
        "4UPS-UPU parallel mechanism, ideal joints, 5 driven legs (11 bodies)",
    ),
    "pendulum": (
        "clearance.mechanisms.examples:spatial_pendulum",
        2.0,
        "rod pendulum on a spherical joint",
    ),
    "double-pendulum": (
        "clearance.mechanisms.examples:double_pendulum",
        2.0,
        "spatial double pendulum",
    ),
    "slider-crank": (
        "clearance.mechanisms.examples:slider_crank",
        1.0,
        "slider-crank driven at constant crank speed",
    ),
    "andrews": (
        "clearance.mechanisms.andrews:andrews_squeezer",
        0.03,
        "Andrews' squeezing mechanism (IFToMM A03)",
    ),
}


def _factory(name: str):
    if name not in EXAMPLES:
        typer.echo(f"error: unknown example {name!r}; allowed: {', '.join(EXAMPLES)}", err=True)
        raise typer.Exit(2)
    mod, fn = EXAMPLES[name][0].split(":")
    return getattr(importlib.import_module(mod), fn)


@app.command()
def examples() -> None:
    """List the library of shipped scenarios and the validation examples."""
    from clearance.scenario import library

    typer.echo("scenarios (`clearance new NAME` writes an editable copy; `clearance run FILE`):")
    for name, desc in library().items():
        typer.echo(f"  {name:<14s} {desc}")
    typer.echo("validation examples (`clearance example NAME` simulates one):")
    for k, (_, t_end, desc) in EXAMPLES.items():
        typer.echo(f"  {k:<16s} {t_end:>6g} s  {desc}")


@app.command()
def new(
    name: str = typer.Argument(..., help="a library scenario (see `clearance examples`)"),
    dest: Path = typer.Argument(None, help="file to write (default: ./NAME.toml)"),
    force: bool = typer.Option(False, "--force", help="overwrite an existing file"),
) -> None:
    """Write an editable copy of a library scenario (with the files it reads)."""
    from clearance.io.files import atomic_path
    from clearance.scenario import ScenarioError, library_path

    try:
        src = library_path(name)
    except ScenarioError as e:
        typer.echo(f"error: {e}", err=True)
        raise typer.Exit(2) from None
    dest = Path(dest) if dest is not None else Path(f"{name}.toml")
    if dest.is_dir():
        dest = dest / f"{name}.toml"
    # the scenario and the tables it names (trajectory.table file), next to each other
    files = [(src, dest)] + [(src.parent / f, dest.parent / f) for f in _referenced_files(src)]
    for _, d in files:
        if d.exists() and not force:
            typer.echo(f"error: {d} exists (use --force to overwrite)", err=True)
            raise typer.Exit(2)
    for s, d in files:
        try:
            with atomic_path(d) as tmp:
                tmp.write_bytes(s.read_bytes())
        except OSError as e:
            typer.echo(f"error: cannot write {d}: {e}", err=True)
            raise typer.Exit(2) from None
    typer.echo(f"wrote {dest}" + "".join(f", {d}" for _, d in files[1:]))
    typer.echo(f"edit it, then: clearance check {dest}; clearance run {dest}")


@app.command()
def draw(
    file: Path = typer.Argument(..., help="scenario file (TOML)"),
    out: Path = typer.Option(None, help="image to write (default: FILE with .png)"),
    labels: bool = typer.Option(True, "--labels/--no-labels", help="name the joints"),
) -> None:
    """Sketch a scenario's mechanism at its home pose (3-D, joints by kind and named), to
    check a geometry before running it."""
    from clearance.model.errors import ModelError
    from clearance.plot.sketch import sketch
    from clearance.scenario import ScenarioError, build_mechanisms, load_scenario

    try:
        s = load_scenario(file)
        ideal, _, _ = build_mechanisms(s)
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    except ModelError as e:
        typer.echo(f"error: {e}", err=True)
        raise typer.Exit(2) from None
    from clearance.io.files import atomic_path

    dest = out if out is not None else Path(file).with_suffix(".png")
    fig = sketch(ideal, labels=labels, titles=[f"{s.name}: {ideal.name}"], columns=1)
    with atomic_path(dest) as tmp:
        fig.savefig(tmp, format=dest.suffix.lstrip(".") or "png", dpi=120)
    typer.echo(f"wrote {dest}")


def _referenced_files(path: Path) -> list[str]:
    """Files a scenario reads besides itself (its trajectory table), relative to it."""
    from clearance.scenario.toml_io import read_toml

    t = read_toml(path).get("trajectory", {}).get("table", {})
    f = t.get("file") if isinstance(t, dict) else None
    return [f] if isinstance(f, str) else []


@app.command("example")
def run_example(
    example: str = typer.Argument("ups-upu", help="example mechanism (see `clearance examples`)"),
    t_end: float = typer.Option(None, help="end time [s] (default: the example's)"),
    rtol: float = typer.Option(1e-6, help="relative tolerance of DOPRI5"),
    atol: float = typer.Option(1e-9, help="absolute tolerance of DOPRI5"),
    dt_out: float = typer.Option(1e-3, help="output interval [s]"),
    out: Path = typer.Option(Path("out"), help="output folder"),
) -> None:
    """Simulate a shipped example mechanism, print a summary and save the result (.npz)."""
    from clearance import compile_mechanism, simulate
    from clearance.io.npz import save_npz

    mech = _factory(example)()
    t_end = EXAMPLES[example][1] if t_end is None else t_end
    typer.echo(f"compiling '{mech.name}' ({len(mech.bodies)} bodies) ...")
    t0 = time.perf_counter()
    comp = compile_mechanism(mech)
    typer.echo(comp.describe().splitlines()[0])
    from clearance import Interrupted

    interrupted = False
    try:
        res = simulate(comp, t_end, dt_out=dt_out, rtol=rtol, atol=atol)
    except Interrupted as e:  # Ctrl-C: the run stopped; keep what it computed
        res, interrupted = e.result, True
    wall = time.perf_counter() - t0
    typer.echo(res.summary())
    sim = res.stats["wall_time"]
    typer.echo(
        f"integration {sim:.3f} s for {t_end:g} s simulated "
        f"(real-time factor {t_end / max(sim, 1e-12):.1f}); total incl. JIT {wall:.1f} s"
    )
    if res.driver_force.size:
        peak = np.max(np.abs(res.driver_force), axis=0)
        names = ", ".join(f"{n} {p:.1f}" for n, p in zip(res.driver_names, peak, strict=True))
        typer.echo(f"peak |actuator force|: {names}")
    path = save_npz(res, out / f"{example}.npz")
    typer.echo(f"result written to {path}")
    if interrupted:
        raise typer.Exit(130)
    if not res.success:
        raise typer.Exit(1)


@app.command()
def describe(example: str = typer.Argument(..., help="example mechanism")) -> None:
    """Print the compiled state layout of an example mechanism."""
    from clearance import assemble, compile_mechanism, rank_check

    comp = compile_mechanism(_factory(example)())
    typer.echo(comp.describe())
    typer.echo(str(rank_check(comp, 0.0, assemble(comp))))


@app.command()
def check(file: Path = typer.Argument(..., help="scenario file (TOML)")) -> None:
    """Validate a scenario file without running it (exit 0: valid; 2: errors on stderr)."""
    from clearance.scenario import BUILDERS, ScenarioError, load_scenario

    try:
        s = load_scenario(file)
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    note = "" if s.mechanism.type in BUILDERS else " (validates; no builder in this version)"
    ik_line = _check_trajectory(s, file) if s.mechanism.type in BUILDERS else ""
    if ik_line is None:
        raise typer.Exit(2)
    typer.echo(f"OK {file}: {s.summary()}{note}")
    if ik_line:
        typer.echo(ik_line)
    if s.mechanism.type in BUILDERS:
        _check_cost(s)


def _check_trajectory(s, file: Path) -> str | None:
    """`check`: the inverse kinematics along the whole trajectory (singular or unreachable
    poses are refused naming the time and the legs), when the kernels are compiled
    already (else it would compile them: the first run's ~1 min). The line to print, or
    None when the file is refused (the reason printed to stderr)."""
    from clearance.model.errors import KinematicsError, ModelError
    from clearance.pipeline import _kernels_cached
    from clearance.scenario import build_mechanisms

    try:
        ideal, _, info = build_mechanisms(s)
    except (KinematicsError, ModelError) as e:
        typer.echo(f"{file}: {e}", err=True)
        return None
    if not info.actuators:  # (a general mechanism's own drivers: no inverse kinematics)
        return "inverse kinematics: none (the drivers of the file run as given)"
    if not _kernels_cached():
        return "inverse kinematics: checked by the first run (the kernels are not compiled)"
    from clearance.analysis.ik import inverse_kinematics

    try:
        ik = inverse_kinematics(
            info.ik_mechanism or ideal,
            info.platform_trajectory(),
            platform_marker=info.platform_marker,
            actuators=info.actuators,
            times=s.trajectory.ik_times(),
        )
    except (KinematicsError, ModelError) as e:
        typer.echo(f"{file}: the trajectory cannot be followed: {e}", err=True)
        return None
    return (
        f"inverse kinematics: {ik.times.size} poses, drive Jacobian condition <= "
        f"{ik.max_condition:.3g}"
    )


def _check_cost(s) -> None:
    """`check`: the estimated cost of the clearance run and its warnings, when the kernels
    are compiled already (else it would compile them: the first run's ~1 min)."""
    from clearance.compile.compiled import compile_mechanism
    from clearance.model.errors import KinematicsError, ModelError
    from clearance.pipeline import _kernels_cached, cost_warnings, estimate_run
    from clearance.scenario import build_mechanisms

    if not _kernels_cached():
        typer.echo("cost estimate: after the first run has compiled the kernels")
        return
    try:
        _, clr, info = build_mechanisms(s)
        est = estimate_run(compile_mechanism(clr), info)
    except (KinematicsError, ModelError) as e:  # `run` reports these with their context
        typer.echo(f"cost estimate: not available ({e})")
        return
    typer.echo(f"estimated clearance run: {est.text()}")
    for w in cost_warnings(est, info, s.checks.long_run):
        typer.echo(f"warning: {w}")


@app.command()
def run(
    file: Path = typer.Argument(None, help="scenario file (default: the shipped 4UPS-UPU)"),
    out: Path = typer.Option(
        None, help="output folder (default: the scenario's \\[output] folder)"
    ),
    figures: bool = typer.Option(None, "--figures/--no-figures", help="draw the figures"),
    outputs: str = typer.Option(
        None,
        "--outputs",
        help="result groups besides the lean default, comma-separated: "
        "bodies, contact_points, multipliers, reactions or all "
        "(default: the scenario's \\[output] outputs)",
    ),
    timings: bool = typer.Option(False, "--timings", help="print the wall time of each stage"),
) -> None:
    """Run a scenario: ideal and clearance mechanism on the same IK drives; save and plot.
    Exit 0: done; 1: a run stopped early (also [solver] max_wall_time); 2: invalid input;
    3: implausible results (the summary says why); 130: Ctrl-C or SIGTERM (the results
    computed until then are written)."""
    from clearance.io.outputs import check_outputs
    from clearance.model.errors import KinematicsError, ModelError
    from clearance.pipeline import (
        STAGES,
        RunInterrupted,
        format_summary,
        implausible,
        run_scenario,
    )
    from clearance.scenario import ScenarioError

    extra = None
    if outputs is not None:
        try:
            extra = check_outputs([x.strip() for x in outputs.split(",") if x.strip()])
        except ValueError as e:
            typer.echo(f"error: --{e}", err=True)
            raise typer.Exit(2) from None
    import signal

    live = LiveProgress()
    interrupted = False
    previous = signal.signal(signal.SIGTERM, _terminate)  # (keeps what was computed)
    try:
        o = run_scenario(
            file, out_dir=out, figures=figures, outputs=extra, log=live.say, progress=live.update
        )
    except ScenarioError as e:
        live.clear()
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    except (KinematicsError, ModelError) as e:
        live.clear()
        typer.echo(f"error: {e}", err=True)
        raise typer.Exit(2) from None
    except RunInterrupted as e:  # the runs stopped; what they computed is written
        live.clear()
        o, interrupted = e.run, True
        typer.echo(f"{e}: the results up to then are written (no figures: `clearance plot`)")
    except KeyboardInterrupt:  # before or after the integration: nothing half-written
        live.clear()
        typer.echo("interrupted (outside the integration; no half-written file)", err=True)
        raise typer.Exit(130) from None
    finally:
        signal.signal(signal.SIGTERM, previous)
    typer.echo(f"summary of '{o.scenario.name}':")
    typer.echo(format_summary(o.summary))
    typer.echo(
        f"total wall time {o.timings['total']:.2f} s "
        f"(inverse kinematics {o.timings['inverse_kinematics']:.2f} s)"
    )
    if timings:
        typer.echo("timings [s]:")
        for k in (*STAGES, "total"):
            if k in o.timings:
                typer.echo(f"  {k:<20s} {o.timings[k]:8.3f}")
        typer.echo(f"  {'process':<20s} {time.perf_counter() - _T_START:8.3f}  (since start-up)")
    typer.echo("files:")
    for f in o.files:
        typer.echo(f"  {f}")
    if interrupted:
        raise typer.Exit(130)
    if not (o.ideal.success and o.clearance.success):
        raise typer.Exit(1)
    if implausible(o.summary):  # reached the end, but not a motion physics allows
        raise typer.Exit(3)


@app.command()
def warmup() -> None:
    """Compile every kernel ahead of time (for cluster nodes and images): later runs start
    at once. The kernel cache is $CLEARANCE_CACHE_DIR, else ~/.cache/clearance."""
    from clearance.pipeline import warmup as _warmup

    _warmup(log=typer.echo)


@app.command()
def plot(
    result: Path = typer.Argument(..., help="result file (.nc) written by `clearance run`"),
    out: Path = typer.Option(None, help="figure folder (default: <result folder>/figures)"),
    fmt: list[str] = typer.Option(["png"], "--format", help="figure format (repeatable)"),
) -> None:
    """Redraw the figures of a saved result, without simulating."""
    from clearance.io.dataset import load_results
    from clearance.plot import plot_all

    data = _load(result, load_results)
    try:
        files = plot_all(dict(data), out or result.parent / "figures", formats=tuple(fmt))
    except (KeyError, ValueError) as e:
        typer.echo(f"error: {result}: {e.args[0] if e.args else e}", err=True)
        raise typer.Exit(2) from None
    for f in files:
        typer.echo(str(f))


@app.command()
def analyze(
    result: Path = typer.Argument(..., help="result file (.nc) written by `clearance run`"),
    channel: list[str] = typer.Option(
        None,
        "--channel",
        help="channel, e.g. 'position[platform,z]', 'eccentricity[S_1,x]' (repeatable; "
        "default: the platform's z and each clearance joint's eccentricity x, y)",
    ),
    group: str = typer.Option("clearance", help="the run in the file: clearance or ideal"),
    period: float = typer.Option(
        None, help="drive period [s] (default: the file's [steady_state] period)"
    ),
    transient: int = typer.Option(None, help="periods discarded (default: the file's)"),
    section: str = typer.Option(None, help="Poincare section: the channel that crosses"),
    section_value: float = typer.Option(0.0, help="the value it crosses"),
    section_direction: int = typer.Option(1, help="+1 upward, -1 downward, 0 both"),
    tol: float = typer.Option(1e-3, help="recurrence tolerance, x each channel's range"),
    out: Path = typer.Option(None, help="output folder (default: next to the result)"),
    figures: bool = typer.Option(True, "--figures/--no-figures", help="write figures"),
    fmt: list[str] = typer.Option(["png"], "--format", help="figure format (repeatable)"),
) -> None:
    """Nonlinear dynamics of a steady-state run: Poincare map, spectrum, phase portrait,
    Lyapunov estimate, 0-1 test and the response's classification (a table, figures and
    RESULT_analysis.nc)."""
    from clearance.io.dataset import load_results
    from clearance.model.errors import ModelError
    from clearance.nonlinear.analyze import analyze as run_analysis
    from clearance.nonlinear.analyze import save_analysis

    _load(result, load_results)  # clear error for a missing or invalid file
    sec = (section, section_value, section_direction) if section else None
    try:
        a = run_analysis(
            result,
            group=group,
            channels=channel or None,
            period=period,
            transient_periods=transient,
            section=sec,
            tol=tol,
        )
    except ModelError as e:
        typer.echo(f"error: {result}: {e}", err=True)
        raise typer.Exit(2) from None
    folder = out or result.parent
    typer.echo(f"analysis of {result} ({group}):")
    rows = a.table()
    w = max(len(k) for k, _ in rows)
    for k, v in rows:
        typer.echo(f"  {k:<{w}s}  {v}")
    typer.echo(f"  evidence: {'; '.join(a.classification.reasons)}")
    files = [save_analysis(folder / f"{result.stem}_analysis.nc", a, attrs={"result": str(result)})]
    if figures:
        from clearance.plot.nonlinear import analysis_figures

        files += analysis_figures(a, folder, f"{result.stem}_{group}", tuple(fmt))
    typer.echo("files:")
    for f in files:
        typer.echo(f"  {f}")


@app.command()
def view(
    result: Path = typer.Argument(..., help="result file (.nc) written by `clearance run`"),
    out: Path = typer.Option(
        None, "-o", "--out", help="HTML file to write (default: RESULT with .html)"
    ),
    magnification: float = typer.Option(
        None,
        help="factor the clearances are drawn with (default: a round number that makes "
        "the magnified clearance about 30 % of the socket radius)",
    ),
    runs: str = typer.Option(
        None, help="runs to draw, comma-separated (default: all in the file, e.g. ideal,clearance)"
    ),
) -> None:
    """A 3-D viewer of a result: one self-contained HTML file (no network needed) with the
    mechanism in motion, each clearance joint magnified with its contact force and a
    close-up, ideal and clearance runs overlaid or side by side."""
    from clearance.view.html import write_viewer

    if magnification is not None and not magnification > 0:
        typer.echo(
            f"error: --magnification = {magnification}: expected a positive number", err=True
        )
        raise typer.Exit(2)
    names = [r.strip() for r in runs.split(",") if r.strip()] if runs else None
    with _view_errors(result):
        path = write_viewer(result, out, magnification=magnification, runs=names)
    typer.echo(f"viewer: {path} ({path.stat().st_size / 1e6:.1f} MB); open it in a browser")


@app.command()
def animate(
    result: Path = typer.Argument(..., help="result file (.nc) written by `clearance run`"),
    out: Path = typer.Option(
        None, "-o", "--out", help="video to write, .mp4 or .gif (default: RESULT with .mp4)"
    ),
    fps: float = typer.Option(25.0, help="video frames per second"),
    speed: float = typer.Option(
        None, help="simulated seconds per video second (default: the whole run in 20 s)"
    ),
    size: str = typer.Option(None, help="WIDTHxHEIGHT in pixels (default 1280x720, GIF 800x450)"),
    ideal: bool = typer.Option(True, "--ideal/--no-ideal", help="draw the ideal run as a ghost"),
) -> None:
    """The mechanism in motion as a video for talks (MP4 or GIF): the 3-D scene with a time
    stamp and a close-up of each clearance joint. No display needed; ffmpeg comes with the
    imageio-ffmpeg package."""
    from clearance.view.video import render_video

    wh = None
    if size is not None:
        try:
            wh = tuple(int(x) for x in size.lower().split("x"))
            if len(wh) != 2:
                raise ValueError
        except ValueError:
            typer.echo(f"error: --size = {size!r}: expected WIDTHxHEIGHT, e.g. 1280x720", err=True)
            raise typer.Exit(2) from None
    step = [0]

    def progress(i, n):
        if i * 10 // n > step[0] or i == n:
            step[0] = i * 10 // n
            typer.echo(f"  frame {i}/{n}")

    with _view_errors(result):
        info = render_video(
            result, out, fps=fps, speed=speed, size=wh, ghost=ideal, progress=progress
        )
    typer.echo(
        f"video: {info.path} ({info.frames} frames, {info.duration:.1f} s at {info.fps:g} fps, "
        f"{info.size[0]}x{info.size[1]}, {info.speed:g} x real time)"
    )


@app.command()
def wear(
    file: Path = typer.Argument(..., help="scenario file (TOML) with a \\[wear] table"),
    out: Path = typer.Option(
        None, "-o", "--out", help="output folder (default: the scenario's \\[output] folder)"
    ),
    restart: bool = typer.Option(
        False, "--restart", help="start again instead of resuming from OUT/wear.nc"
    ),
    figures: bool = typer.Option(True, "--figures/--no-figures", help="draw the figures"),
    iterations: int = typer.Option(
        None, "--iterations", min=1, help="stop after this many runs (resume later)"
    ),
) -> None:
    """Predict the wear of the scenario's spherical clearance joints over many cycles
    (Archard's law, the worn sockets fed back into the dynamics, the update-factor loop;
    docs/wear.md). Resumes from OUT/wear.nc when it holds the same scenario. Exit 0: done
    (or --iterations reached); 1: a run failed (the iterations before it are kept);
    2: invalid input; 130: Ctrl-C (the iterations done are kept)."""
    from clearance.model.errors import KinematicsError, ModelError
    from clearance.scenario import ScenarioError
    from clearance.wear.predict import WearRunError, WearStateError, predict_wear

    try:
        w = predict_wear(
            file, out_dir=out, restart=restart, figures=figures, max_iterations=iterations
        )
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    except (KinematicsError, ModelError, WearStateError) as e:
        typer.echo(f"error: {e}", err=True)
        raise typer.Exit(2) from None
    except WearRunError as e:
        typer.echo(f"error: {e}; the iterations before it are kept (run again to resume)", err=True)
        raise typer.Exit(1) from None
    except KeyboardInterrupt:
        typer.echo("interrupted: the iterations done are kept (run again to resume)", err=True)
        raise typer.Exit(130) from None
    st = w.state
    typer.echo(
        f"wear: {st.cycles:.6g} cycles in {len(st.rows)} runs"
        + ("" if st.done else " (not finished: run again to resume)")
    )
    for j, m in st.maps.items():
        typer.echo(
            f"  {j}: worn volume {m.volume() * 1e9:.4g} mm^3, max depth "
            f"{m.max_depth() * 1e6:.4g} um, effective clearance "
            f"{(st.clearances[j] + m.max_depth()) * 1e3:.4g} mm"
        )
    typer.echo("files:")
    for f in w.files:
        typer.echo(f"  {f}")


@app.command()
def report(
    path: Path = typer.Argument(
        ..., help="result file (.nc) of `clearance run`, or a study folder of `clearance sweep`"
    ),
    out: Path = typer.Option(
        None, "-o", "--out", help="HTML file to write (default: report.html next to it / in it)"
    ),
) -> None:
    """(Re)build a report: one self-contained HTML page with the summary table, the figures,
    the 3-D viewer, the scenario and the version; for a study, the table of cases, the
    summary plots and a viewer per case."""
    with _view_errors(path):
        if path.is_dir():
            from clearance.scenario import ScenarioError
            from clearance.sweep.report import study_report

            try:
                written = study_report(path, out)
            except ScenarioError as e:
                for line in e.lines():
                    typer.echo(line, err=True)
                raise typer.Exit(2) from None
        else:
            from clearance.view.report import write_report

            written = write_report(path, out)
    typer.echo(f"report: {written} ({written.stat().st_size / 1e6:.1f} MB)")


@app.command()
def export(
    result: Path = typer.Argument(..., help="result file (.nc) written by `clearance run`"),
    csv: bool = typer.Option(True, "--csv/--no-csv", help="write CSV tables"),
    mat: bool = typer.Option(True, "--mat/--no-mat", help="write a MATLAB .mat file"),
    out: Path = typer.Option(None, help="output folder (default: next to the result)"),
) -> None:
    """Export a saved result to CSV and/or MATLAB .mat."""
    from clearance.io.dataset import load_results
    from clearance.io.export import export_csv, export_mat

    _load(result, load_results)  # clear error for a missing or invalid file
    folder = out or result.parent
    files = export_csv(result, folder) if csv else []
    if mat:
        files.append(export_mat(result, folder / f"{result.stem}.mat"))
    for f in files:
        typer.echo(str(f))


@app.command()
def sweep(
    study: Path = typer.Argument(..., help="study file (TOML, see docs/sweeps.md)"),
    scheduler: str = typer.Option(
        None,
        "--scheduler",
        help="'serial' (in this process), a Dask scheduler address (tcp://host:8786) or a "
        "scheduler file; default: a local cluster sized to this machine",
    ),
    workers: int = typer.Option(
        None, "--workers", help="local cluster size; with --scheduler: wait for this many"
    ),
    out: Path = typer.Option(None, "--out", help="study folder (default: the study's folder)"),
    retries: int = typer.Option(2, help="extra attempts of a failing case"),
    check_only: bool = typer.Option(False, "--check", help="validate the study, run nothing"),
) -> None:
    """Run a parameter study on Dask (resumable: finished cases are skipped).

    Exit status: 0 all cases finished; 1 some case failed; 2 invalid study; 130 interrupted.
    """
    import signal

    from clearance.scenario import ScenarioError
    from clearance.sweep import load_study, run_study

    try:
        s = load_study(study)
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    if check_only:
        typer.echo(
            f"OK {study}: study '{s.name}', {len(s.cases)} cases, parameters "
            f"{', '.join(p.name for p in s.parameters)}; folder {out or s.folder}"
        )
        return

    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        report = run_study(
            s,
            scheduler=scheduler,
            n_workers=workers,
            retries=retries,
            progress=typer.echo,
            folder=out,
        )
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    except KeyboardInterrupt:
        raise typer.Exit(130) from None
    finally:
        signal.signal(signal.SIGTERM, previous)
    if report.failed or not report.complete:
        raise typer.Exit(1)


@app.command()
def bifurcation(
    study: Path = typer.Argument(
        ..., help="one-parameter study file (TOML) of steady-state runs, or its study folder"
    ),
    channel: list[str] = typer.Option(
        None,
        "--channel",
        help="channel(s) analysed per case (repeatable; the first is plotted; default: the "
        "platform's z and each clearance joint's eccentricity x, y)",
    ),
    transient: int = typer.Option(None, help="periods discarded (default: the scenario's)"),
    scheduler: str = typer.Option(None, "--scheduler", help="as `clearance sweep`"),
    workers: int = typer.Option(None, "--workers", help="local cluster size"),
    out: Path = typer.Option(None, "--out", help="study folder (default: the study's folder)"),
    no_run: bool = typer.Option(False, "--collect", help="only draw from finished cases"),
    continuation: bool = typer.Option(
        False,
        "--continuation",
        help="run the cases in the file's order, each from the previous case's final state "
        "(follows a branch; one after the other, in this process)",
    ),
) -> None:
    """Bifurcation diagram: run (resumably, on Dask) or collect a one-parameter study of
    steady-state runs, and plot each case's Poincare points against the parameter.

    Exit status: 0 drawn from every case; 1 some case not finished; 2 invalid study."""
    import signal

    from clearance.model.errors import ModelError
    from clearance.scenario import ScenarioError
    from clearance.sweep.bifurcation import bifurcation as run_bifurcation

    if not study.exists():
        typer.echo(f"error: {study}: no such study file or folder", err=True)
        raise typer.Exit(2)
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        o = run_bifurcation(
            study,
            run=not no_run and not study.is_dir(),
            channels=channel or None,
            transient_periods=transient,
            scheduler=scheduler,
            n_workers=workers,
            progress=typer.echo,
            folder=out,
            continuation=continuation,
        )
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    except ModelError as e:
        typer.echo(f"error: {study}: {e}", err=True)
        raise typer.Exit(2) from None
    except KeyboardInterrupt:
        raise typer.Exit(130) from None
    finally:
        signal.signal(signal.SIGTERM, previous)
    typer.echo(f"bifurcation over {o.parameter} ({len(o.values)} cases), {o.channel}:")
    for v, k, p in zip(o.values, o.kinds, o.points, strict=True):
        typer.echo(f"  {o.parameter} = {v:<12.6g} {k:<16s} {np.unique(p).size} distinct values")
    for f in o.files:
        typer.echo(f"  {f}")
    if o.missing:
        typer.echo(f"not finished: {', '.join(o.missing)}", err=True)
        raise typer.Exit(1)


@app.command()
def collect(
    folder: Path = typer.Argument(..., help="study folder written by `clearance sweep`"),
    dataset: bool = typer.Option(True, "--dataset/--no-dataset", help="write the merged NetCDF"),
    plots: bool = typer.Option(True, "--plots/--no-plots", help="draw the summary plots"),
    variables: list[str] = typer.Option(
        None, "--variable", help="keep only these data variables in the merged dataset"
    ),
) -> None:
    """Merge a study's cases: dataset with a `case` dimension, summary table, plots."""
    from clearance.scenario import ScenarioError
    from clearance.sweep import collect_study

    try:
        o = collect_study(folder, dataset=dataset, plots=plots, variables=variables or None)
    except ScenarioError as e:
        for line in e.lines():
            typer.echo(line, err=True)
        raise typer.Exit(2) from None
    counts = o.table["status"].value_counts().to_dict()
    typer.echo(f"{len(o.table)} cases: " + ", ".join(f"{n} {k}" for k, n in sorted(counts.items())))
    for f in (o.dataset, o.parquet, o.csv, *o.plots):
        if f is not None:
            typer.echo(str(f))
    typer.echo(f"the study's report, with a 3-D viewer per case: clearance report {folder}")


def _terminate(signum, frame):  # SIGTERM (a batch system's time limit) stops like Ctrl-C
    raise KeyboardInterrupt


class LiveProgress:
    """The simulated time of the runs while they integrate: a bar redrawn in place on a
    terminal (stderr), a line every `every` seconds otherwise (logs of batch jobs).
    `update(run, t, t_end)` may be called from several threads; `say(msg)` prints a
    message line (clearing the bar first)."""

    def __init__(self, stream=None, *, every: float = 10.0) -> None:
        import threading

        self.stream = stream if stream is not None else sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.every = every if not self.tty else 0.2
        self.lock = threading.RLock()  # (say: clear and print under one hold)
        self.reached: dict[str, float] = {}
        self.t0 = self.last = 0.0
        self.shown = 0  # characters of the bar on screen

    def update(self, run: str, t: float, t_end: float) -> None:
        with self.lock:
            now = time.perf_counter()
            if not self.reached:  # (a first line: at once on a terminal, else after `every`)
                self.t0 = now
                self.last = 0.0 if self.tty else now
            self.reached[run] = t / t_end if t_end > 0 else 1.0
            if now - self.last < self.every:
                return
            self.last = now
            parts = ", ".join(f"{k} {100 * f:3.0f} %" for k, f in self.reached.items())
            slow = min(self.reached.values())
            el = now - self.t0
            left = f", ~{el * (1 - slow) / slow:.0f} s left" if 0.01 < slow < 1 else ""
            text = f"      integrating: {parts} ({el:.0f} s{left})"
            if self.tty:
                width = 30
                fill = int(width * slow)
                text = f"\r      [{'#' * fill}{'.' * (width - fill)}] " + text.strip()
                self.stream.write(text.ljust(self.shown))
                self.shown = len(text)
            else:
                self.stream.write(text + "\n")
            self.stream.flush()

    def clear(self) -> None:
        with self.lock:
            if self.shown:
                self.stream.write("\r" + " " * self.shown + "\r")
                self.stream.flush()
                self.shown = 0

    def say(self, msg: str) -> None:
        with self.lock:  # (no redraw from the other run's thread in between)
            self.clear()
            typer.echo(msg)


@contextlib.contextmanager
def _view_errors(path: Path):
    """`view`, `animate`, `report`: a SceneError or an unreadable file is exit 2 with its
    message (no traceback)."""
    from clearance.view import SceneError

    try:
        yield
    except SceneError as e:
        typer.echo(f"error: {e}", err=True)
        raise typer.Exit(2) from None
    except OSError as e:
        typer.echo(f"error: {path}: {e}", err=True)
        raise typer.Exit(2) from None


def _load(path: Path, loader):
    if not path.is_file():
        typer.echo(f"error: {path}: no such result file", err=True)
        raise typer.Exit(2)
    try:
        return loader(path)
    except (OSError, ValueError) as e:
        typer.echo(f"error: {path}: not a clearance result file ({e})", err=True)
        raise typer.Exit(2) from None


# commands that leave nothing running when they return (no Dask cluster, no threads)
_FAST_EXIT = {
    "run",
    "plot",
    "analyze",
    "export",
    "check",
    "describe",
    "example",
    "examples",
    "new",
    "draw",
    "warmup",
    "view",
    "animate",
    "report",
}


def main() -> None:  # pragma: no cover - the console script; tests call `app`
    """The `clearance` console script. After run/plot/export/check, whose files are all
    written and closed when the command returns, the process exits without the
    interpreter's teardown: freeing the loaded numba kernels and the rest took 0.5-0.8 s,
    a sixth of a warm `clearance run`."""
    try:
        app()
        code = 0
    except SystemExit as e:
        code = e.code
    if len(sys.argv) > 1 and sys.argv[1] in _FAST_EXIT:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code if isinstance(code, int) else (0 if code is None else 1))
    sys.exit(code)


if __name__ == "__main__":  # python -m clearance.cli.main
    main()
