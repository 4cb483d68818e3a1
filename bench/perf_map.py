"""Profile compiled kernels with Linux `perf`: a perf map of every numba function.

perf cannot name JIT-compiled code by itself. This script compiles the default scenario's
kernels in-process (an empty cache, so that numba keeps each function's LLVM module),
writes `/tmp/perf-<pid>.map` (address, size, name of every compiled function, which perf
reads on its own), prints its pid, waits `--wait` seconds for perf to attach, then runs the
clearance integration `--runs` times.

    python bench/perf_map.py --runs 8 &
    perf record -e cpu-clock -F 4000 -p <pid printed>      # ends when the script ends
    perf report --no-children --sort sym | python bench/perf_map.py --demangle

Sizes are the distance to the next function (LLVM does not report them), so a sample in
the padding after a function counts for it. Names are numba's mangled names
(`_ZN9clearance8dynamics5solve15sparse_cholesky...`); `--demangle` (a filter) shortens
them to the dotted path. The whole `simulate` call is sampled, post-processing included.
"""

from __future__ import annotations

# isort: off
import os
import tempfile

# an empty kernel cache, set before clearance is first imported (by _common): compiled
# in-process, every function keeps the LLVM module that names it
os.environ["CLEARANCE_CACHE_DIR"] = tempfile.mkdtemp(prefix="clearance-perf-")

import _common  # noqa: E402, F401  (pins the thread counts before numpy is imported)

import argparse  # noqa: E402
import re  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

# isort: on


def demangle(sym: str) -> str:
    """`_ZN9clearance8dynamics3rhs3rhsB4v554...` -> `clearance.dynamics.rhs.rhs`."""
    if not sym.startswith("_ZN"):
        return sym
    s, out = sym[3:], []
    while (m := re.match(r"\d+", s)) is not None:
        k = int(m.group(0))
        s = s[len(m.group(0)) :]
        out.append(s[:k])
        s = s[k:]
        if s.startswith("B"):
            break
    return ".".join(out) or sym


def write_perf_map(path: str) -> int:
    """Write the perf map of every compiled overload of every dispatcher in clearance.*;
    returns the number of functions."""
    from numba.core.registry import CPUDispatcher

    syms: dict[int, str] = {}
    for name, mod in list(sys.modules.items()):
        if not name.startswith("clearance"):
            continue
        for obj in list(vars(mod).values()):
            if not isinstance(obj, CPUDispatcher):
                continue
            for cres in obj.overloads.values():
                lib = cres.library
                module = getattr(lib, "_final_module", None)
                if module is None:  # loaded from a cache: no LLVM module to list
                    continue
                for fn in module.functions:
                    if not fn.is_declaration:
                        addr = lib.get_pointer_to_function(fn.name)
                        if addr:
                            syms[addr] = fn.name
    addrs = sorted(syms)
    with open(path, "w") as f:
        for i, a in enumerate(addrs):
            size = min(addrs[i + 1] - a, 1 << 20) if i + 1 < len(addrs) else 1 << 12
            f.write(f"{a:x} {size:x} {syms[a]}\n")
    return len(addrs)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=8, help="integrations to run (default 8)")
    ap.add_argument("--wait", type=float, default=3.0, help="seconds to wait for perf")
    ap.add_argument("--demangle", action="store_true", help="filter stdin: shorten names")
    args = ap.parse_args()
    if args.demangle:
        for line in sys.stdin:
            print(re.sub(r"_ZN\S+", lambda m: demangle(m.group(0)), line), end="")
        return

    from bench_scenario import build

    import clearance as cl

    mech, info = build()
    c = cl.compile_mechanism(mech)
    kw = dict(info.simulate_kwargs)
    print("compiling ...", flush=True)
    cl.simulate(c, 0.01, **kw)
    n = write_perf_map(f"/tmp/perf-{os.getpid()}.map")
    print(f"pid {os.getpid()}: {n} functions in /tmp/perf-{os.getpid()}.map", flush=True)
    time.sleep(args.wait)
    for _ in range(args.runs):
        r = cl.simulate(c, info.t_end, **kw)
    print(f"{args.runs} runs; last loop {r.stats['wall_time']:.3f} s", flush=True)


if __name__ == "__main__":
    main()
