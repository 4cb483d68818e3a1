"""Accuracy per cost of two versions of the package on one case, at matched accuracy.

The work-precision diagram (bench_work_precision.py) compares methods of one version. To
compare a version with an older one (issue 12's targets are ratios to the code before it),
both must run the same case against the same reference, and this script uses only what
both have: `load_scenario`, `with_overrides`, `run_scenario`, `simulate` and the Result's
`position` and `eccentricity`. First a reference, with the current version:

    python bench/bench_versions.py reference --case b --duration 0.5 --out /tmp/ref_b.npz

then each version, in its own process, the old one from a checkout of it (`git worktree
add /tmp/old <rev>`) with a kernel cache of its own:

    taskset -c 0 python bench/bench_versions.py compare --ref /tmp/ref_b.npz --tag new \
        --methods tsit5,vern7 --rtols 1e-5,1e-6,1e-7,1e-8
    PYTHONPATH=/tmp/old/src CLEARANCE_CACHE_DIR=/tmp/cache_old taskset -c 0 \
        python bench/bench_versions.py compare --ref /tmp/ref_b.npz --tag old \
        --methods tsit5,dopri5 --rtols 1e-5,1e-6,1e-7,1e-8

Cases: (a) the shipped 4UPS-UPU scenario, (b) the same with frictionless Hunt-Crossley
joints (as in bench_work_precision.py). Errors: the clearance joints' eccentricity and the
platform position, max over the first 0.05 s and over the whole duration; cost: the whole
`simulate()` call (min of --repeats) and its loop, and the rhs count. atol = rtol / 1000.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

EARLY = 0.05  # [s]
DT_OUT = 1e-4  # [s]


def build(case: str):
    """(compiled clearance mechanism, y0) of case a or b, through the scenario pipeline."""
    import clearance  # noqa: F401  (the version on the path)
    from clearance.pipeline import run_scenario
    from clearance.scenario import default_scenario_path, load_scenario, with_overrides

    s = load_scenario(default_scenario_path())
    over = {"output.figures": False}
    if case == "b":
        for j in s.clearance.joints:
            over[f"clearance.joints.{j}.normal"] = {"law": "hunt_crossley", "restitution": 0.9}
            over[f"clearance.joints.{j}.friction"] = {"law": "none"}
    s = with_overrides(s, over)
    with tempfile.TemporaryDirectory() as d:
        r = run_scenario(s, out_dir=d, log=None).clearance
    c = r.compiled
    return c, np.concatenate([r.q[0], r.v[0], np.zeros(c.ny - c.nq - c.nv)])


def channels(r):
    ecc = np.stack([r.eccentricity(j) for j in r.clearance_names])
    return r.position("platform"), ecc


def run(c, y0, duration, **settings):
    import clearance as cl

    t0 = time.perf_counter()
    r = cl.simulate(c, duration, dt_out=DT_OUT, y0=y0, assemble_positions=False, **settings)
    return r, time.perf_counter() - t0


def reference(a) -> None:
    c, y0 = build(a.case)
    r, wall = run(c, y0, a.duration, method="dopri5", rtol=1e-12, atol=1e-15)
    if not r.success:
        raise SystemExit(f"the reference run stopped: {r.message}")
    p, e = channels(r)
    np.savez(a.out, case=a.case, duration=a.duration, t=r.t, p=p, e=e, qv0=y0[: c.nq + c.nv])
    print(f"reference ({a.case}, {a.duration} s): {r.stats['nfev']} rhs, {wall:.1f} s -> {a.out}")


def compare(a) -> None:
    z = np.load(a.ref)
    case, duration = str(z["case"]), float(z["duration"])
    c, y0 = build(case)
    if not np.array_equal(y0[: c.nq + c.nv], z["qv0"]):
        raise SystemExit("this version starts the case from another state than the reference")
    early = int(np.searchsorted(z["t"], EARLY, side="right"))
    for m in a.methods.split(","):
        for rtol in (float(x) for x in a.rtols.split(",")):
            walls = []
            for _ in range(a.repeats):
                r, wall = run(c, y0, duration, method=m, rtol=rtol, atol=rtol * 1e-3)
                walls.append(wall)
            p, e = channels(r)
            de = np.linalg.norm(e - z["e"], axis=2).max(axis=0)
            dp = np.linalg.norm(p - z["p"], axis=1)
            print(
                f"{a.tag:<5} {m:<7} {rtol:7.0e}  rhs {r.stats['nfev']:8d}  call {min(walls):7.3f} s"
                f"  loop {r.stats['wall_time']:7.3f} s  ecc early {de[:early].max():.2e}"
                f" whole {de.max():.2e}  pos early {dp[:early].max():.2e} whole {dp.max():.2e}",
                flush=True,
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    ref = sub.add_parser("reference", help="the reference run (dopri5, rtol 1e-12)")
    ref.add_argument("--case", choices=("a", "b"), default="b")
    ref.add_argument("--duration", type=float, default=0.5)
    ref.add_argument("--out", type=Path, required=True)
    cmp_ = sub.add_parser("compare", help="methods x tolerances against a reference")
    cmp_.add_argument("--ref", type=Path, required=True)
    cmp_.add_argument("--tag", default="")
    cmp_.add_argument("--methods", default="tsit5")
    cmp_.add_argument("--rtols", default="1e-5,1e-6,1e-7,1e-8")
    cmp_.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    reference(a) if a.cmd == "reference" else compare(a)


if __name__ == "__main__":
    main()
