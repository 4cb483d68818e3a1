"""Compile the kernels ahead of their first use, in a process of its own.

The first run after an install (or after the kernel sources change) compiles the kernels
it needs; numba caches them on disk (`clearance._kernel_cache`), and a later process loads
them in a fraction of a second. The compile of one integration loop cannot be split, but
the loops of the other methods and the post-processing can compile on another core while
the first run compiles its own:

    python -m clearance.warmup [METHOD ...]      # default: dop853 rk4 (vern7 shares dop853's)

runs a tiny clearance mechanism through each method's loop (and so through the
post-processing, the initial assembly and the contact kinds' gap functions), and returns
when they are cached. Another process that needs one of them meanwhile compiles its own
copy (numba writes its cache files atomically), so starting it never slows anything but
the shared cores. The test suite starts it in the background (tests/conftest.py): on two
cores a cold suite saves the time of the loops it compiles.
"""

from __future__ import annotations

import sys
import time

__all__ = ["DEFAULT_METHODS", "compile_kernels"]

#: the loops besides the default method's (tsit5 / dopri5 share theirs): erk_high and rk4
DEFAULT_METHODS = ("dop853", "rk4")


def _mechanism():
    """A rod on a spherical clearance joint and a slider on a prismatic one, a revolute
    and a cylindrical one with stations and thrust faces: every contact kind."""
    import clearance as cl

    m = cl.Mechanism("warmup", gravity=(0.0, -9.81, 0.0))
    law = cl.Hertz(stiffness=3e10)
    m.add(
        cl.Body("a", 0.5, (1e-3, 1e-3, 1e-3), position=(0.0, -0.1, 0.0)),
        cl.Body("b", 0.5, (1e-3, 1e-3, 1e-3), position=(0.2, -0.1, 0.0)),
        cl.Body("c", 0.5, (1e-3, 1e-3, 1e-3), position=(0.4, -0.1, 0.0)),
        cl.Marker("g0", "ground"),
        cl.Marker("a0", "a", (0.0, 0.1, 0.0)),
        cl.Marker("g1", "ground", (0.2, 0.0, 0.0)),
        cl.Marker("b1", "b", (0.0, 0.1, 0.0)),
        cl.Marker("g2", "ground", (0.4, 0.0, 0.0)),
        cl.Marker("c2", "c", (0.0, 0.1, 0.0)),
        cl.Spherical(
            "S", "g0", "a0", clearance=cl.Clearance(0.01, radial_clearance=1e-4, normal=law)
        ),
        cl.Revolute(
            "R",
            "g1",
            "b1",
            clearance=cl.RevoluteClearance(
                0.01,
                radial_clearance=1e-4,
                model="spatial",
                length=0.02,
                axial_clearance=1e-4,
                normal=law,
            ),
        ),
        cl.Prismatic(
            "P",
            "g2",
            "c2",
            clearance=cl.PrismaticClearance(
                width=0.02, height=0.02, length=0.04, clearance=1e-4, model="spatial", normal=law
            ),
        ),
    )
    return m


def compile_kernels(methods=DEFAULT_METHODS, *, log=None) -> dict:
    """Run the warm-up mechanism through each method's loop (module docstring); return
    {method: seconds}."""
    import clearance as cl

    c = cl.compile_mechanism(_mechanism())
    times = {}
    for method in methods:
        t0 = time.perf_counter()
        cl.simulate(c, 2e-4, dt_out=1e-4, method=method, step=1e-5)
        times[method] = time.perf_counter() - t0
        if log is not None:
            log(f"{method}: {times[method]:.1f} s")
    return times


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    compile_kernels(tuple(args) or DEFAULT_METHODS, log=print)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
