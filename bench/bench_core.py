"""Core benchmark: right-hand-side cost and whole 2 s runs of the ideal 4UPS-UPU.

Mechanism: `clearance.mechanisms.ups_upu.ups_upu_ideal()` (11 moving bodies, 66 velocity
coordinates, 66 constraint rows, 5 leg-length drivers). Measured, on the state assembled at
t = 0, each as the median of several repeats with `time.perf_counter`:

* per right-hand side: the compiled kernel with the Schur solve, with the dense augmented LU
  fallback, the `scipy_rhs` wrapper (what `solve_ivp` calls), and the plain-NumPy reference
  `clearance.dynamics.reference.reference_rhs` (the "typical user code" baseline);
* whole runs over t_end (default 2 s) at rtol 1e-6 / atol 1e-9: the own compiled DOPRI5
  (`clearance.simulate`), SciPy `solve_ivp` RK45 with the compiled right-hand side, and
  SciPy `solve_ivp` RK45 with the NumPy reference (the baseline; if that would take longer
  than --baseline-budget seconds, a shorter interval is integrated and the time scaled).

Numba is warmed up first; compile (or cache-load) time is reported separately.
Run: `taskset -c 0 python bench/bench_core.py` (see bench/README.md).
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
from scipy.integrate import solve_ivp

import clearance as cl
from clearance.contact.element import make_contact_state
from clearance.dynamics.reference import reference_rhs
from clearance.dynamics.rhs import make_work, rhs
from clearance.kinds import Solver
from clearance.mechanisms.ups_upu import ups_upu_ideal

ALPHA, BETA = 5.0, 5.0  # Baumgarte [1/s] (physics.md d.2)
RTOL, ATOL = 1e-6, 1e-9


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=2.0, help="simulated time [s] (default 2)")
    ap.add_argument("--repeats", type=int, default=7, help="repeats for medians (default 7)")
    ap.add_argument(
        "--baseline-budget",
        type=float,
        default=60.0,
        help="max seconds for one NumPy/solve_ivp baseline run before it is shortened",
    )
    ap.add_argument(
        "--baseline-repeats", type=int, default=3, help="repeats of the baseline run (default 3)"
    )
    args = ap.parse_args(argv)
    t_end, reps = args.t_end, args.repeats

    print_environment("clearance core benchmark: ideal 4UPS-UPU, leg-length drivers")

    # ------------------------------------------------------------ build, compile, warm up
    t0 = time.perf_counter()
    mech = ups_upu_ideal()
    c = cl.compile_mechanism(mech)
    t_build = time.perf_counter() - t0
    y0 = cl.initial_state(c, t=0.0)  # assembled positions, consistent velocities
    model = c.model
    wk = make_work(model)
    cs = make_contact_state(model)
    out = np.zeros_like(y0)
    rep = cl.rank_check(c, 0.0, y0)
    print(
        f"mechanism: {c.nb} moving bodies, {c.nv} velocity coordinates, {c.nrow} constraint "
        f"rows, rank {rep.rank}, DOF {rep.dof}; t_end = {t_end} s, rtol {RTOL:g}, "
        f"atol {ATOL:g}, Baumgarte ({ALPHA:g}, {BETA:g})"
    )

    warm = {}
    t0 = time.perf_counter()
    rhs(0.0, y0, model, wk, cs, ALPHA, BETA, int(Solver.SCHUR), out)
    warm["rhs, Schur (first call)"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rhs(0.0, y0, model, wk, cs, ALPHA, BETA, int(Solver.DENSE), out)
    warm["rhs, dense (first call)"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rhs_loop(1, 0.0, y0, model, wk, cs, ALPHA, BETA, 0, out)
    warm["rhs called from an @njit loop (first call)"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    cl.simulate(c, min(t_end, 0.01), rtol=RTOL, atol=ATOL, baumgarte=(ALPHA, BETA), solver="schur")
    warm["simulate, DOPRI5 loop + post (first call)"] = time.perf_counter() - t0

    # ------------------------------------------------------------ per right-hand side
    def k_schur() -> None:
        rhs(0.0, y0, model, wk, cs, ALPHA, BETA, 0, out)

    def k_dense() -> None:
        rhs(0.0, y0, model, wk, cs, ALPHA, BETA, 1, out)

    f_scipy = cl.scipy_rhs(c, baumgarte=(ALPHA, BETA), solver="schur")

    def f_ref(t: float, y: np.ndarray) -> np.ndarray:
        return reference_rhs(mech, t, y, alpha=ALPHA, beta=BETA)[0]

    # sanity: the implementations agree on this state
    yd_ref = f_ref(0.0, y0)
    agree = float(np.max(np.abs(f_scipy(0.0, y0) - yd_ref)) / max(1.0, np.max(np.abs(yd_ref))))

    t_ref1 = median_time(lambda: f_ref(0.0, y0), 1, 3)[0]
    n_ref = max(3, int(0.5 / t_ref1))  # about 0.5 s per repeat

    def in_loop(solver: int, n: int) -> tuple[float, float]:
        fn = lambda: rhs_loop(n, 0.0, y0, model, wk, cs, ALPHA, BETA, solver, out)  # noqa: E731
        med, best = median_time(fn, reps)
        return med / n, best / n

    rhs_times = {
        "compiled Schur, in an @njit loop (no dispatch)": in_loop(0, 5000),
        "compiled dense LU, in an @njit loop": in_loop(1, 1000),
        "compiled kernel, Schur, called from Python": median_time(k_schur, reps, 5000),
        "compiled kernel, dense LU, called from Python": median_time(k_dense, reps, 1000),
        "scipy_rhs wrapper (Schur) from Python": median_time(lambda: f_scipy(0.0, y0), reps, 2000),
        "NumPy reference_rhs (baseline)": median_time(
            lambda: f_ref(0.0, y0), max(3, reps // 2), n_ref
        ),
    }
    base_rhs = rhs_times["NumPy reference_rhs (baseline)"][0]

    # ------------------------------------------------------------ whole runs
    runs = {}
    res: dict = {}

    def own() -> None:
        res["own"] = cl.simulate(
            c, t_end, rtol=RTOL, atol=ATOL, baumgarte=(ALPHA, BETA), solver="schur"
        )

    t_own = median_time(own, reps)
    r = res["own"]
    assert r.status == 0, r.message
    loop_times = []
    for _ in range(reps):
        own()
        loop_times.append(res["own"].stats["wall_time"])
    runs["own DOPRI5 (simulate, total call)"] = (t_own, r.stats["nfev"], t_end, "")
    runs["own DOPRI5 (integration loop only)"] = (
        (statistics.median(loop_times), min(loop_times)),
        r.stats["nfev"],
        t_end,
        "",
    )

    def ivp_compiled() -> None:
        res["ivp_c"] = solve_ivp(f_scipy, (0.0, t_end), y0, method="RK45", rtol=RTOL, atol=ATOL)

    t_ivp_c = median_time(ivp_compiled, reps)
    sol_c = res["ivp_c"]
    assert sol_c.success, sol_c.message
    runs["solve_ivp RK45 + compiled rhs"] = (t_ivp_c, sol_c.nfev, t_end, "")

    # baseline: shorten if a full run would exceed the budget (estimate from nfev)
    est = base_rhs * sol_c.nfev * 1.1
    t_base_end = t_end
    note = ""
    if est > args.baseline_budget:
        t_base_end = t_end * args.baseline_budget / est
        note = f"integrated to {t_base_end:.3g} s only and scaled by {t_end / t_base_end:.3g}"

    def ivp_ref() -> None:
        res["ivp_r"] = solve_ivp(f_ref, (0.0, t_base_end), y0, method="RK45", rtol=RTOL, atol=ATOL)

    t_ivp_r = median_time(ivp_ref, max(1, args.baseline_repeats))
    sol_r = res["ivp_r"]
    assert sol_r.success, sol_r.message
    scale = t_end / t_base_end
    runs["solve_ivp RK45 + NumPy reference (baseline)"] = (
        (t_ivp_r[0] * scale, t_ivp_r[1] * scale),
        int(round(sol_r.nfev * scale)),
        t_end,
        note,
    )
    base_run = t_ivp_r[0] * scale

    # agreement of the final platform positions (m)
    k = c.body_names.index("platform")
    p_own = r.q[-1, 7 * k : 7 * k + 3]
    p_c = sol_c.y[7 * k : 7 * k + 3, -1]
    diff_c = float(np.max(np.abs(p_own - p_c)))
    diff_r = (
        float(np.max(np.abs(sol_r.y[7 * k : 7 * k + 3, -1] - p_c)))
        if t_base_end == t_end
        else float("nan")
    )

    # ------------------------------------------------------------ report
    print()
    print("compile / cache-load time of the first calls (excluded from everything below):")
    for name, s in warm.items():
        print(f"  {name:<46s} {fmt_time(s)}")
    print(f"  {'build + compile_mechanism (Python)':<46s} {fmt_time(t_build)}")
    print(
        "  (numba cache=True: well under 1 s means the on-disk cache was loaded; a cold cache\n"
        "   compiles the kernel and the integrator loops for several seconds; the benchmark's\n"
        "   own @njit loop is compiled on every run, ~3 s)"
    )
    print()
    print(f"per right-hand side (state at t = 0; compiled vs NumPy agree to {agree:.1e} rel.)")
    print(f"  {'variant':<46s} {'median/call':>12s} {'best':>12s} {'speed-up vs NumPy':>18s}")
    for name, (s, best) in rhs_times.items():
        print(f"  {name:<46s} {fmt_time(s):>12s} {fmt_time(best):>12s} {base_rhs / s:>17.1f}x")
    print()
    print(
        f"whole run, t_end = {t_end} s, rtol {RTOL:g} / atol {ATOL:g} "
        "(medians of repeats; the factors use the medians)"
    )
    print(
        f"  {'integrator':<46s} {'median wall':>12s} {'best':>12s} {'RHS evals':>10s} "
        f"{'real-time factor':>17s} {'speed-up vs baseline':>21s}"
    )
    for name, ((s, best), nfev, te, nt) in runs.items():
        print(
            f"  {name:<46s} {fmt_time(s):>12s} {fmt_time(best):>12s} {nfev:>10d} "
            f"{te / s:>17.1f} {base_run / s:>20.1f}x"
        )
        if nt:
            print(f"    ({nt})")
    print()
    print(
        f"final platform position: own DOPRI5 vs solve_ivp+compiled max diff {diff_c:.1e} m; "
        f"solve_ivp+NumPy vs solve_ivp+compiled {diff_r:.1e} m"
    )
    print(f"own DOPRI5 steps: {r.stats['naccept']} accepted, {r.stats['nreject']} rejected")
    return 0


if __name__ == "__main__":
    sys.exit(main())
