"""The full bifurcation diagram of the shipped study `clearance/data/studies/bifurcation.toml`
(4UPS-UPU at 4 Hz, 40 periods per case, radial clearance 0.05 .. 0.5 mm in 10 cases) on a
LocalCluster of --workers workers, and optionally with continuation (--continuation: the
cases one after the other, each from the previous case's final state).

Prints the study's wall time, the classification of each case and writes the diagram to
<folder>/collected/bifurcation.png (and, with --docs, to docs/img/bifurcation_ups_upu.png).
The test suite runs the same path with 3 cases of 4 periods
(tests/test_nonlinear_runs.py::test_bifurcation_over_clearance_on_a_local_cluster).

Run: `python bench/bench_bifurcation.py [--workers 2] [--cases 10] [--periods 40]
[--channel "eccentricity[S_1,x]"] [--continuation] [--docs]`.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cases", type=int, default=10)
    ap.add_argument("--periods", type=int, default=40)
    ap.add_argument("--transient", type=int, default=20)
    ap.add_argument("--channel", default=None, help="the plotted channel")
    ap.add_argument("--continuation", action="store_true")
    ap.add_argument("--folder", default=None, help="study folder (default: a temporary one)")
    ap.add_argument("--docs", action="store_true", help="copy the diagram into docs/img")
    args = ap.parse_args()

    import clearance
    from clearance.sweep.bifurcation import bifurcation
    from clearance.sweep.study import load_study, study_from_dict

    shipped = Path(clearance.__file__).parent / "data" / "studies"
    study = load_study(shipped / "bifurcation.toml")
    doc = dict(study.document)
    doc["set"] = {
        **doc["set"],
        "trajectory": {"period": 0.25, "duration": 0.25 * args.periods},
        "steady_state": {"transient_periods": args.transient, "samples_per_period": 100},
    }
    doc["parameter"] = [
        {**doc["parameter"][0], "range": {**doc["parameter"][0]["range"], "num": args.cases}}
    ]
    folder = Path(args.folder or tempfile.mkdtemp(prefix="bifurcation_"))
    doc["study"] = {**doc["study"], "folder": str(folder)}
    st = study_from_dict(doc, source=str(shipped / "bifurcation.toml"))
    t0 = time.perf_counter()
    out = bifurcation(
        st,
        n_workers=args.workers,
        channel=args.channel,
        continuation=args.continuation,
        progress=print,
    )
    wall = time.perf_counter() - t0
    print(
        f"{len(out.values)} cases of {args.periods} periods in {wall:.1f} s "
        f"({'continuation, serial' if args.continuation else f'{args.workers} workers'})"
    )
    for v, k in zip(out.values, out.kinds, strict=True):
        print(f"  c = {v * 1e3:.3f} mm: {k}")
    for f in out.files:
        print(f"  {f}")
    if args.docs:
        dst = Path(__file__).resolve().parent.parent / "docs" / "img" / "bifurcation_ups_upu.png"
        shutil.copy(folder / "collected" / "bifurcation.png", dst)
        print(f"  {dst}")


if __name__ == "__main__":
    main()
