"""Helpers shared by the benchmark scripts (bench_core.py, bench_scenario.py).

Import this module before numpy: it pins OpenMP/BLAS/numba to one thread each, which only
takes effect before numpy is first imported (a value set in the environment wins).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import platform  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numba  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402

from clearance.dynamics.rhs import rhs  # noqa: E402


# Not cached on disk: this module lives outside the package, so the package's source-keyed
# kernel cache (clearance/_kernel_cache.py) does not cover it, and a disk-cached caller of
# `rhs` would keep running an old kernel after the package changes. Compiling it costs a
# few seconds per run, reported apart as first-call time.
@numba.njit(cache=False)
def rhs_loop(n, t, y, model, wk, cs, alpha, beta, solver, out):  # pragma: no cover - compiled
    """Call the kernel n times from compiled code: its cost without Python dispatch."""
    s = 0
    for _ in range(n):
        s += rhs(t, y, model, wk, cs, alpha, beta, solver, out)
    return s


def median_time(fn: Callable[[], object], repeats: int, n_inner: int = 1) -> tuple[float, float]:
    """(median, best) wall time [s] of one `fn()` call; each of `repeats` samples is the
    mean over a loop of `n_inner` calls."""
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n_inner):
            fn()
        samples.append((time.perf_counter() - t0) / n_inner)
    return statistics.median(samples), min(samples)


def fmt_time(s: float) -> str:
    if s < 1e-3:
        return f"{s * 1e6:9.1f} us"
    if s < 1.0:
        return f"{s * 1e3:9.2f} ms"
    return f"{s:9.3f} s "


def print_environment(title: str) -> None:
    """The title, library versions, CPU affinity and thread settings; warn when the process
    is not pinned to one core."""
    print(title)
    aff = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else "?"
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"numba {numba.__version__}; CPU affinity {aff}; "
        f"NUMBA_NUM_THREADS={os.environ.get('NUMBA_NUM_THREADS')}, "
        f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, "
        f"NUMBA_DISABLE_JIT={os.environ.get('NUMBA_DISABLE_JIT', '0')}"
    )
    if aff != "?" and len(aff) > 1:
        print("note: not pinned to one core; use `taskset -c 0` for stable numbers")
