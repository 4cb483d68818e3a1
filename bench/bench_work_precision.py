"""Work-precision diagram: error against cost for each integration method and tolerance.

Cases (issue 12):
  (a) the shipped 4UPS-UPU scenario (Flores, LuGre friction), its 2 s;
  (b) the same with frictionless Hunt-Crossley joints;
  (c) a pendulum resting in its spherical socket (persistent contact, Flores), 1 s;
  (d) the ideal 4UPS-UPU of (a), its 2 s.
Errors against a reference run of the same case (dopri5, rtol 1e-12, atol 1e-15): the
platform (or pendulum) position, max over the first 0.05 s and over the whole run; the
clearance joints' eccentricity likewise; for (d) the actuator forces. Cost: rhs
evaluations, the whole `simulate()` call and its integration loop (`stats["wall_time"]`),
medians of --repeats. Errors are only comparable within a case.

Prints one table per case and draws `work_precision.png` (log-log, error against wall
time and against rhs count). Run from the repository root:

    python bench/bench_work_precision.py [--repeats 3] [--cases abcd] [--rk4] [--out DIR]

About 1-2 min with the defaults (one core; the references take most of it).
"""

from __future__ import annotations

# isort: off
# _common first: it pins the thread counts, which only works before numpy is imported
from _common import print_environment

# isort: on
import argparse
import statistics
import time
from pathlib import Path

import numpy as np

import clearance as cl
from clearance.integrate.methods import ADAPTIVE
from clearance.pipeline import run_scenario
from clearance.scenario import default_scenario_path, load_scenario, with_overrides

EARLY = 0.05  # [s] the first impacts: where most of a run's error comes from (issue 12)
RTOLS = (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
RK4_STEPS = (1e-5, 5e-6, 2.5e-6)
REF = dict(method="dopri5", rtol=1e-12, atol=1e-15)


def scenario_case(frictionless: bool):
    """(compiled clearance model, compiled ideal model, y0 of each, duration, platform)."""
    s = load_scenario(default_scenario_path())
    over = {"output.figures": False}
    if frictionless:
        for j in s.clearance.joints:
            over[f"clearance.joints.{j}.normal"] = {"law": "hunt_crossley", "restitution": 0.9}
            over[f"clearance.joints.{j}.friction"] = {"law": "none"}
    s = with_overrides(s, over)
    import tempfile

    with tempfile.TemporaryDirectory() as d:  # (the IK drives and the start of both runs)
        o = run_scenario(s, out_dir=d, log=None)
    out = []
    for r in (o.clearance, o.ideal):
        c = r.compiled
        y0 = np.concatenate([r.q[0], r.v[0], np.zeros(c.ny - c.nq - c.nv)])
        out.append((c, y0))
    return out, s.trajectory.duration, "platform"


def resting_pendulum():
    """A 1 kg rod hanging 0.25 m below a spherical clearance joint (ball 10 mm, c = 0.1 mm,
    Flores), started at its static penetration and swinging: the ball stays in contact."""
    L, c, K = 0.25, 1e-4, 1e10
    m = cl.Mechanism("resting pendulum")
    m.add(
        cl.Body(  # swinging about the joint: the ball itself starts at rest
            "rod",
            1.0,
            (0.0052, 0.0052, 0.0002),
            position=(0, 0, -L),
            velocity=(0.3, 0, 0),
            angular_velocity=(0, -0.3 / L, 0),
        ),
        cl.Marker("socket", "ground"),
        cl.Marker("ball", "rod", (0, 0, L)),
        cl.Spherical(
            "S",
            "socket",
            "ball",
            clearance=cl.Clearance(
                ball_radius=0.01,
                radial_clearance=c,
                normal=cl.Flores(stiffness=K, restitution=0.9),
                friction=cl.Coulomb(mu=0.1),
            ),
        ),
    )
    comp = cl.compile_mechanism(m)
    y0 = cl.initial_state(comp)
    y0[2] -= c + (9.81 / K) ** (2 / 3)  # the ball on the bottom of its socket
    return comp, y0


def errors(r: cl.Result, ref: cl.Result, body: str) -> dict[str, float]:
    n = min(r.t.size, ref.t.size)
    early = int(np.searchsorted(ref.t, EARLY, side="right"))
    out = {}
    d = np.linalg.norm(r.position(body)[:n] - ref.position(body)[:n], axis=1)
    out["pos_early"], out["pos"] = float(d[:early].max()), float(d.max())
    if r.clearance_names:
        e = np.max(
            [
                np.linalg.norm(r.eccentricity(j)[:n] - ref.eccentricity(j)[:n], axis=1)
                for j in r.clearance_names
            ],
            axis=0,
        )
        out["ecc_early"], out["ecc"] = float(e[:early].max()), float(e.max())
    else:
        f = np.abs(r.driver_force[:n] - ref.driver_force[:n]).max(axis=1)
        out["force_early"], out["force"] = float(f[:early].max()), float(f.max())
    if r.t.size != ref.t.size:  # stopped early: no whole-run error to report
        out = {
            k: (v if k.endswith("early") and n > early else float("nan")) for k, v in out.items()
        }
    return out


def measure(comp, y0, duration, settings, repeats):
    walls, loops, r = [], [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = cl.simulate(comp, duration, dt_out=1e-4, y0=y0, assemble_positions=False, **settings)
        walls.append(time.perf_counter() - t0)
        loops.append(r.stats["wall_time"])
    return r, statistics.median(walls), statistics.median(loops)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--cases", default="abcd")
    ap.add_argument("--rk4", action="store_true", help="add rk4 at fixed steps (slow)")
    ap.add_argument("--out", type=Path, default=Path("."))
    a = ap.parse_args()
    print_environment("work-precision: error against cost per method and tolerance")
    cases = {}
    if "a" in a.cases or "d" in a.cases:
        (clr, ideal), dur, body = scenario_case(False)
        if "a" in a.cases:
            cases["(a) shipped 4UPS-UPU"] = (*clr, dur, body)
        if "d" in a.cases:
            cases["(d) ideal 4UPS-UPU"] = (*ideal, dur, body)
    if "b" in a.cases:
        (clr, _), dur, body = scenario_case(True)
        cases["(b) frictionless Hunt-Crossley"] = (*clr, dur, body)
    if "c" in a.cases:
        cases["(c) pendulum resting in its socket"] = (*resting_pendulum(), 1.0, "rod")
    runs = [(m, dict(method=m, rtol=rt, atol=rt * 1e-3)) for m in ADAPTIVE for rt in RTOLS]
    if a.rk4:
        runs += [("rk4", dict(method="rk4", step=h)) for h in RK4_STEPS]
    table = {}
    for name, (comp, y0, dur, body) in cases.items():
        ref, _, _ = measure(comp, y0, dur, REF, 1)
        if not ref.success:
            raise SystemExit(f"{name}: the reference run stopped: {ref.message}")
        rows = []
        print(f"\n{name}: {dur:g} s, reference dopri5 rtol 1e-12 ({ref.stats['nfev']} rhs)")
        keys = list(errors(ref, ref, body))
        head = f"  {'method':<7} {'setting':>9} {'rhs':>8} {'call [s]':>9} {'loop [s]':>9} "
        print(head + " ".join(f"{k:>11}" for k in keys))
        for method, st in runs:
            r, wall, loop = measure(comp, y0, dur, st, a.repeats)
            e = errors(r, ref, body)
            setting = st.get("rtol", st.get("step"))
            rows.append((method, setting, r.stats["nfev"], wall, loop, e))
            print(
                f"  {method:<7} {setting:>9.0e} {r.stats['nfev']:>8d} {wall:>9.3f} {loop:>9.3f} "
                + " ".join(f"{e[k]:>11.2e}" for k in keys)
            )
        table[name] = (keys, rows)
    draw(table, a.out / "work_precision.png")


def draw(table, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axes = plt.subplots(len(table), 2, figsize=(10, 3.2 * len(table)), squeeze=False)
    for row, (name, (keys, rows)) in enumerate(table.items()):
        key = keys[1]  # whole-run error of the main channel (pos, over the run)
        axes_of = ((3, "simulate() wall time [s]"), (2, "rhs evaluations"))
        for col, (xi, xlabel) in enumerate(axes_of):
            ax = axes[row, col]
            for method in dict.fromkeys(r[0] for r in rows):
                pts = [(r[xi], r[5][key], r[5][keys[0]]) for r in rows if r[0] == method]
                x, y, y0 = (np.array(v) for v in zip(*pts, strict=True))
                ax.loglog(x, y, "o-", label=f"{method}: {key}")
                ax.loglog(x, y0, "x--", label=f"{method}: {keys[0]}", alpha=0.6)
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # (no overlaps)
            ax.set_xlabel(xlabel)
            ax.set_ylabel("max error")
            ax.set_title(name, fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
        axes[row, 0].legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"\ndiagram: {path}")


if __name__ == "__main__":
    main()
