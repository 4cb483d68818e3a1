"""Study throughput: the same small study on a LocalCluster of 1 and of 2 workers.

The study is the shipped example (`clearance/data/studies/example.toml`: 4UPS-UPU, radial
clearance x LuGre mu_c), widened to --cases cases (clearances between 0.1 and 0.5 mm x mu_c
0.05 / 0.15) and shortened to --duration simulated seconds. For each cluster size:

* a LocalCluster of single-threaded worker processes is started and every worker is warmed
  up (imports and numba's on-disk cache loaded by one tiny run), timed separately;
* the study runs into a fresh folder with `run_study(..., scheduler=client)`; the
  throughput is cases per minute of that wall time.

The ratio of the 2-worker to the 1-worker throughput is the speed-up (at most 2 on two
cores). A serial in-process run of the same cases is the reference without Dask.
Run: `python bench/bench_sweep.py [--cases 8] [--duration 0.2] [--workers 1 2]`.
"""

from __future__ import annotations

import os

# One BLAS/numba thread per process (must precede the numpy import); Dask's nanny does the
# same for its workers, so the serial reference and the workers compute alike.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402


def _warm() -> float:
    """Load the compiled kernels on a worker: one tiny run (duration 0.01 s), discarded."""
    t0 = time.perf_counter()
    from clearance.pipeline import run_scenario
    from clearance.scenario import default_scenario_path, load_scenario, with_overrides

    s = load_scenario(default_scenario_path("ups_upu"))
    s = with_overrides(s, {"trajectory.duration": 0.01, "solver.dt_out": 1e-3})
    with tempfile.TemporaryDirectory() as d:
        run_scenario(s, out_dir=d, figures=False, log=None)
    return time.perf_counter() - t0


def _integrating(rep, workers: int) -> float:
    """Share of the workers' time (wall x workers) in the clearance runs' simulate()."""
    import json

    total = 0.0
    for cid in rep.finished:
        side = json.loads((rep.folder / "cases" / f"{cid}.json").read_text())
        total += float(side.get("timings", {}).get("clearance", 0.0))
    return total / max(rep.wall_time * workers, 1e-12)


def study_text(n_cases: int, duration: float, folder: Path) -> str:
    """The example study with n_cases cases (n_cases / 2 clearances x 2 mu_c values)."""
    from clearance.sweep.study import example_study_path

    n_c = max(1, n_cases // 2)
    text = example_study_path().read_text()
    text = text.replace("duration = 0.2 ", f"duration = {duration!r} ")
    text = text.replace(
        "values = [1e-4, 3e-4, 5e-4]", f"range = {{ start = 1e-4, stop = 5e-4, num = {n_c} }}"
    )
    text = text.replace('# folder = "studies/ups_upu_clearance_friction"', f'folder = "{folder}"')
    return text


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=8, help="number of cases (even)")
    ap.add_argument("--duration", type=float, default=0.2, help="simulated time per case [s]")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2], help="cluster sizes")
    ap.add_argument("--no-serial", action="store_true", help="skip the serial reference")
    args = ap.parse_args()

    import dask
    import distributed
    from distributed import Client, LocalCluster

    from clearance.sweep import loads_study, run_study

    print(f"study throughput: {args.cases} cases of {args.duration:g} s (4UPS-UPU, example study)")
    print(
        f"python {platform.python_version()}, dask {dask.__version__}, distributed "
        f"{distributed.__version__}, {os.cpu_count()} cores visible"
    )
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        if not args.no_serial:
            _warm()
            s = loads_study(study_text(args.cases, args.duration, Path(tmp) / "serial"))
            rep = run_study(s, scheduler="serial", progress=False)
            rows.append(("serial (in process)", 0.0, rep, _integrating(rep, 1)))
        for n in args.workers:
            t0 = time.perf_counter()
            cluster = LocalCluster(
                n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
            )
            client = Client(cluster)
            warm = client.run(_warm)
            startup = time.perf_counter() - t0
            s = loads_study(study_text(args.cases, args.duration, Path(tmp) / f"w{n}"))
            rep = run_study(s, scheduler=client, progress=False)
            share = _integrating(rep, n)
            client.close()
            cluster.close()
            assert rep.complete, rep.summary()
            per_worker = np.mean(list(warm.values()))
            rows.append((f"LocalCluster, {n} worker{'s' * (n > 1)}", startup, rep, share))
            print(
                f"  {n} worker(s): cluster start + warm-up {startup:.1f} s "
                f"(warm-up run {per_worker:.1f} s per worker)"
            )
    print()
    print(
        f"  {'executor':<26s} {'wall [s]':>9s} {'cases/min':>10s} {'s/case':>8s} "
        f"{'integrating':>12s}"
    )
    for label, _, rep, share in rows:
        n_done = len(rep.finished)
        print(
            f"  {label:<26s} {rep.wall_time:9.2f} {rep.throughput:10.1f} "
            f"{rep.wall_time / max(n_done, 1):8.2f} {100 * share:11.0f}%"
        )
    print(
        "  (integrating: the clearance simulate() calls' share of the workers' time, "
        "wall x workers; issue 10: at least 80 %)"
    )
    tput = {label: rep.throughput for label, _, rep, _ in rows}
    one, two = "LocalCluster, 1 worker", "LocalCluster, 2 workers"
    if one in tput and two in tput and tput[one] > 0:
        print(f"\n  throughput ratio 2 workers / 1 worker: {tput[two] / tput[one]:.2f}")


if __name__ == "__main__":
    main()
