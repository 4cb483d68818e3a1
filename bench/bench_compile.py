"""Where a cold compile goes: the kernels `clearance run` needs, compiled in ONE process
with an empty kernel cache (a fresh CLEARANCE_CACHE_DIR), from numba's compile events.

Prints the total, the number of functions and of compiles (a function compiled twice has
two signatures: look for literal arguments), the functions by exclusive compile time (a
function's own compile, without the callees it triggered) and the critical path of the
call graph (the longest chain of nested compiles: the lower bound of any parallel
compile). The pipeline compiles the same kernels on two cores (pipeline.ColdCompile);
`bench_run.py --cold` measures that, end to end.

Run: `python bench/bench_compile.py [--top 30]` (about 2 minutes).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--top", type=int, default=30, help="functions to list (default 30)")
    args = ap.parse_args(argv)
    os.environ["CLEARANCE_CACHE_DIR"] = tempfile.mkdtemp()
    import numpy as np
    from numba.core import event

    from clearance.analysis.ik import drives_from_ik, inverse_kinematics
    from clearance.compile.compiled import compile_mechanism
    from clearance.integrate.simulate import simulate
    from clearance.scenario import build_mechanisms, default_scenario_path, load_scenario

    s = load_scenario(default_scenario_path())
    ideal, clr, info = build_mechanisms(s)
    t0 = time.perf_counter()
    with event.install_recorder("numba:compile") as rec:
        ik = inverse_kinematics(
            info.ik_mechanism or ideal,
            info.platform_trajectory(),
            platform_marker=info.platform_marker,
            actuators=info.actuators,
            times=np.linspace(0.0, info.t_end, 11),
        )
        ideal, clr, info = build_mechanisms(s, drives=drives_from_ik(ik))
        kw = {k: v for k, v in info.simulate_kwargs.items() if k not in ("dt_out", "t_out")}
        for c in (compile_mechanism(ideal), compile_mechanism(clr)):
            simulate(c, 1e-9, t_out=np.array([0.0, 1e-9]), **kw)
    total = time.perf_counter() - t0
    roots: list = []
    stack: list = []
    excl: dict[str, float] = {}
    count: dict[str, int] = {}
    for ts, ev in rec.buffer:
        f = ev.data["dispatcher"].py_func
        name = f.__module__.removeprefix("clearance.") + "." + f.__qualname__
        if ev.is_start:
            node = {"name": name, "t": ts, "children": []}
            (stack[-1]["children"] if stack else roots).append(node)
            stack.append(node)
        else:
            node = stack.pop()
            node["incl"] = ts - node["t"]
            node["excl"] = node["incl"] - sum(c["incl"] for c in node["children"])
            excl[name] = excl.get(name, 0.0) + node["excl"]
            count[name] = count.get(name, 0) + 1

    def critical(n: dict) -> tuple[float, list[str]]:
        best = max((critical(c) for c in n["children"]), default=(0.0, []), key=lambda x: x[0])
        return n["excl"] + best[0], [n["name"].rsplit(".", 1)[-1], *best[1]]

    print(
        f"cold compile in one process: {total:.1f} s, {len(excl)} functions, "
        f"{sum(count.values())} compiles"
    )
    for n in sorted(roots, key=lambda n: -n["incl"])[:5]:
        length, path = critical(n)
        print(f"  {n['name']}: {n['incl']:.1f} s, critical path {length:.1f} s:")
        print(f"    {' > '.join(path)}")
    print(f"\n  {'exclusive [s]':>13s} {'compiles':>8s}  function")
    for name in sorted(excl, key=lambda k: -excl[k])[: args.top]:
        print(f"  {excl[name]:13.2f} {count[name]:8d}  {name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
