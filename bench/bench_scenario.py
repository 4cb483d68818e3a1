"""Scenario benchmark: the default 4UPS-UPU clearance scenario, compiled engine vs plain NumPy.

Model: the shipped default scenario (`clearance.scenario.default_scenario_path()`): 4UPS-UPU,
11 moving bodies, 66 velocity coordinates, 60 constraint rows, two spherical clearance
joints (Flores contact, LuGre friction), drives from the inverse kinematics of the platform
trajectory, 2 s, the scenario's solver settings (tsit5, rtol 1e-6, atol 1e-9).

Measured in one run, each as the median of repeats with `time.perf_counter`, and reported as
RATIOS against the plain-NumPy implementation of the same model
(`clearance.dynamics.reference_contact`: the clearance force element and the constraint
machinery of `reference.py`, dense augmented LU):

* per right-hand side, on a state in contact taken from the run: the compiled kernel in an
  @njit loop and from Python, the `scipy_rhs` wrapper, the NumPy `reference_rhs_clearance`;
* whole run: the own compiled integrator (`clearance.simulate` with the scenario's method:
  the whole call, and the integration loop alone; the integration loop with DOPRI5 too),
  and SciPy `solve_ivp` RK45 with the NumPy right-hand side (the
  contact state latched on accepted steps). A full baseline run would take hours, so it
  integrates a short interval that includes the first impacts and is scaled to the full
  duration; the output says so, and also gives a second estimate (the own run's RHS count
  times the NumPy per-RHS time).

Numba is warmed up first; compile (or cache-load) time is reported separately.
Run: `taskset -c 0 python bench/bench_scenario.py` (see bench/README.md).
"""

from __future__ import annotations

# isort: off
# _common first: it pins the thread counts, which only works before numpy is imported
from _common import fmt_time, median_time, print_environment, rhs_loop

# isort: on
import argparse
import statistics
import sys
import time

import numpy as np

import clearance as cl
from clearance.analysis.ik import apply_drives, drives_from_ik, inverse_kinematics
from clearance.contact.element import make_contact_state
from clearance.dynamics.reference_contact import (
    reference_rhs_clearance,
    solve_ivp_clearance,
)
from clearance.dynamics.rhs import make_work, rhs
from clearance.layout import CO_FN
from clearance.scenario import (
    build_mechanisms,
    default_scenario_path,
    load_scenario,
)


def build():
    """The default scenario's clearance mechanism with drives from the inverse kinematics."""
    s = load_scenario(default_scenario_path())
    ideal, clr, info = build_mechanisms(s)
    ik = inverse_kinematics(
        ideal,
        info.platform_trajectory(),
        platform_marker=info.platform_marker,
        actuators=info.actuators,
        times=np.linspace(0.0, info.t_end, 101),
    )
    return apply_drives(clr, drives_from_ik(ik)), info


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="repeats for medians (default 5)")
    ap.add_argument(
        "--baseline-interval",
        type=float,
        default=0.03,
        help="simulated time of the NumPy/solve_ivp run [s] (default 0.03: the first impacts)",
    )
    ap.add_argument(
        "--baseline-repeats", type=int, default=1, help="repeats of the baseline run (default 1)"
    )
    args = ap.parse_args(argv)
    reps = args.repeats

    print_environment(
        "clearance scenario benchmark: default 4UPS-UPU scenario with two clearance joints"
    )

    # ------------------------------------------------------------ build, compile, warm up
    t0 = time.perf_counter()
    mech, info = build()
    c = cl.compile_mechanism(mech)
    t_build = time.perf_counter() - t0
    kw = dict(info.simulate_kwargs)
    t_end = float(info.t_end)
    alpha, beta = (float(x) for x in kw["baumgarte"])
    model = c.model
    print(
        f"mechanism: {c.nb} moving bodies, {c.nv} velocity coordinates, {c.nrow} constraint "
        f"rows, {c.nclr} clearance joints; t_end = {t_end} s, {kw['method']}, "
        f"rtol {kw['rtol']:g}, atol {kw['atol']:g}, Baumgarte ({alpha:g}, {beta:g}), "
        f"output every {kw.get('dt_out')} s"
    )

    warm = {}
    y0 = cl.initial_state(c)
    wk = make_work(model)
    cs = make_contact_state(model)
    out = np.zeros_like(y0)
    t0 = time.perf_counter()
    rhs(0.0, y0, model, wk, cs, alpha, beta, 0, out)
    warm["rhs kernel (first call)"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rhs_loop(1, 0.0, y0, model, wk, cs, alpha, beta, 0, out)
    warm["rhs called from an @njit loop (first call)"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    cl.simulate(c, 0.005, **kw)
    warm[f"simulate, {kw['method']} loop + post (first call)"] = time.perf_counter() - t0
    other = "dopri5" if kw["method"] != "dopri5" else None
    if other:
        cl.simulate(c, 0.005, **{**kw, "method": other})

    # ------------------------------------------------------------ whole run, own engine
    res: dict = {}

    def own() -> None:
        res["own"] = cl.simulate(c, t_end, **kw)

    t_own = median_time(own, reps)
    r = res["own"]
    assert r.status == 0, r.message
    loops = []
    for _ in range(reps):
        own()
        loops.append(res["own"].stats["wall_time"])
    t_loop = (statistics.median(loops), min(loops))
    nfev = r.stats["nfev"]
    other_row = []
    if other:
        loops_o = []
        for _ in range(reps):
            ro = cl.simulate(c, t_end, **{**kw, "method": other})
            loops_o.append(ro.stats["wall_time"])
        other_row = [
            (
                f"own {other} (integration loop only)",
                (statistics.median(loops_o), min(loops_o)),
                ro.stats["nfev"],
            )
        ]

    # ------------------------------------------------------------ per right-hand side
    # a state in contact from the run: the sample with the largest normal force
    k = int(np.argmax(r.contact[:, :, CO_FN].max(axis=1)))
    y = np.zeros(c.ny)
    y[: c.nq] = r.q[k]
    y[c.nq : c.nq + c.nv] = r.v[k]
    y[c.iz : c.iw] = r.bristle[k].reshape(-1)
    tk = float(r.t[k])
    flags = r.contact_state[k, :, 0].astype(bool)
    ddm = r.contact_state[k, :, 1].copy()
    cs.flag[:] = flags
    cs.ddm[:] = ddm

    def kernel() -> None:
        rhs(tk, y, model, wk, cs, alpha, beta, 0, out)

    def numpy_rhs() -> np.ndarray:
        return reference_rhs_clearance(
            mech, tk, y, alpha=alpha, beta=beta, in_contact=flags, delta_dot_minus=ddm
        )[0]

    f_scipy = cl.scipy_rhs(c, baumgarte=(alpha, beta), solver="schur", contact_state=cs)
    kernel()
    yd_ref = numpy_rhs()
    agree = float(np.max(np.abs(out - yd_ref)) / np.max(np.abs(yd_ref)))
    t_np1 = median_time(numpy_rhs, 1, 3)[0]
    n_np = max(3, int(0.5 / t_np1))

    def in_loop(n: int) -> tuple[float, float]:
        fn = lambda: rhs_loop(n, tk, y, model, wk, cs, alpha, beta, 0, out)  # noqa: E731
        med, best = median_time(fn, reps)
        return med / n, best / n

    rhs_times = {
        "compiled kernel, in an @njit loop (no dispatch)": in_loop(20000),
        "compiled kernel, called from Python": median_time(kernel, reps, 5000),
        "scipy_rhs wrapper from Python": median_time(lambda: f_scipy(tk, y), reps, 5000),
        "NumPy reference_rhs_clearance (baseline)": median_time(numpy_rhs, reps, n_np),
    }
    base_rhs = rhs_times["NumPy reference_rhs_clearance (baseline)"][0]

    # ------------------------------------------------------------ baseline run
    t_b = min(args.baseline_interval, t_end)

    def baseline() -> None:
        res["base"] = solve_ivp_clearance(
            mech, (0.0, t_b), y0, alpha=alpha, beta=beta, rtol=kw["rtol"], atol=kw["atol"]
        )

    t_base = median_time(baseline, max(1, args.baseline_repeats))
    sol = res["base"]
    assert sol.success, sol.message
    # Two ways to scale the short run to t_end: by simulated time (the first interval is
    # mostly free flight with few, cheap steps, so this underestimates the persistent-contact
    # phase), and by RHS count: the baseline's wall time per RHS evaluation (solve_ivp
    # overhead included) times the own run's RHS count (RK45 and DOPRI5 at the same
    # tolerances take about as many evaluations, performance-notes.md 3; tsit5 takes ~5 %
    # fewer, so this slightly flatters the baseline). The speed-ups use the second.
    scale = t_end / t_b
    base_time_scaled = (t_base[0] * scale, t_base[1] * scale)
    base_run = t_base[0] / sol.nfev * nfev
    base_best = t_base[1] / sol.nfev * nfev
    # agreement: platform position at t_b, own run (dense output) vs baseline
    ip = c.body_names.index(info.platform_body)
    kb = int(np.argmin(np.abs(r.t - t_b)))
    diff = float(np.max(np.abs(r.q[kb, 7 * ip : 7 * ip + 3] - sol.y[7 * ip : 7 * ip + 3, -1])))

    # ------------------------------------------------------------ report
    print()
    print("compile / cache-load time of the first calls (excluded from everything below):")
    for name, s in warm.items():
        print(f"  {name:<48s} {fmt_time(s)}")
    print(f"  {'scenario, inverse kinematics, compile_mechanism':<48s} {fmt_time(t_build)}")
    print(
        "  (a warm numba cache loads in well under 1 s; seconds mean numba compiled; the\n"
        "   benchmark's own @njit loop is compiled on every run, ~3 s)"
    )
    print()
    print(
        f"per right-hand side (state in contact at t = {tk:.4f} s, F_N = "
        f"{r.contact[k, :, CO_FN].max():.0f} N; compiled vs NumPy agree to {agree:.1e} rel.)"
    )
    print(f"  {'variant':<48s} {'median/call':>12s} {'best':>12s} {'speed-up vs NumPy':>18s}")
    for name, (s, best) in rhs_times.items():
        print(f"  {name:<48s} {fmt_time(s):>12s} {fmt_time(best):>12s} {base_rhs / s:>17.1f}x")
    print()
    print(f"whole run, t_end = {t_end} s (medians of {reps} repeats; the factors use the medians)")
    print(
        f"  {'integrator':<48s} {'median wall':>12s} {'best':>12s} {'RHS evals':>10s} "
        f"{'real-time factor':>17s} {'speed-up vs baseline':>21s}"
    )
    rows = [
        (f"own {kw['method']} (simulate, total call)", t_own, nfev),
        (f"own {kw['method']} (integration loop only)", t_loop, nfev),
        *other_row,
        ("solve_ivp RK45 + NumPy rhs, scaled by RHS count", (base_run, base_best), nfev),
        (
            "solve_ivp RK45 + NumPy rhs, scaled by sim. time",
            base_time_scaled,
            int(round(sol.nfev * scale)),
        ),
    ]
    for name, (s, best), n in rows:
        print(
            f"  {name:<48s} {fmt_time(s):>12s} {fmt_time(best):>12s} {n:>10d} "
            f"{t_end / s:>17.3g} {base_run / s:>20.1f}x"
        )
    print(
        f"    (baseline = solve_ivp RK45 + NumPy rhs integrated to {t_b:g} s only, which "
        f"includes the first impacts: {sol.nfev} RHS evaluations in "
        f"{fmt_time(t_base[0]).strip()}. Scaled to {t_end:g} s by RHS count: its time per "
        f"evaluation x the own run's {nfev} evaluations (the speed-ups use this); scaled by "
        f"simulated time: x {scale:.3g}. The two agree when the short interval has the "
        "run's step density; after the first impacts the joints stay in contact and the "
        "steps are stability-bound)"
    )
    print()
    st = r.stats
    print(
        f"own {kw['method']}: {st['naccept']} accepted, {st['nreject']} rejected steps, "
        f"{st['nevents']} event cuts; platform position at {t_b:g} s, own vs baseline: "
        f"max diff {diff:.1e} m (different event handling: located events vs first-order "
        "capture at accepted steps)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
