"""The main job end to end: `clearance run` of the default scenario, as a user runs it.

Each repeat starts a fresh process (`python -m clearance.cli.main run --timings`), so the
times include start-up and imports. Reported, per repeat and as medians:

* wall: the process, measured from outside;
* the stages `run --timings` prints (build, inverse kinematics, kernels, the two
  `simulate()` calls "ideal" and "clearance", summary, datasets, write, export, figures);
* the ratio wall / (ideal + clearance), the issue-10 target being <= 2 (and wall < 3 s);
* the size of the result file.

`--cold` first runs once with an empty kernel cache (a fresh CLEARANCE_CACHE_DIR), which
is what the first run after `pip install` does, and reports its wall time and its
"kernels" stage (the compile).

Run: `python bench/bench_run.py [--repeats 3] [--cold] [--no-figures]` (see
bench/README.md). It does not pin the process to one core: the figures are drawn in one
process per available core, as for a user.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def run_once(out: Path, env: dict, figures: bool) -> tuple[float, dict, str]:
    """(wall [s], stage timings [s], stdout) of one `clearance run` in a new process."""
    cmd = [sys.executable, "-m", "clearance.cli.main", "run", "--out", str(out), "--timings"]
    if not figures:
        cmd.append("--no-figures")
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"clearance run failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    stages = {
        m.group(1): float(m.group(2))
        for m in re.finditer(r"^  (\w+)\s+([0-9.]+)", p.stdout, flags=re.MULTILINE)
    }
    return wall, stages, p.stdout


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="warm runs (default 3)")
    ap.add_argument("--cold", action="store_true", help="first a run with an empty cache")
    ap.add_argument("--no-figures", dest="figures", action="store_false")
    args = ap.parse_args(argv)
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        if args.cold:
            cold_env = {**env, "CLEARANCE_CACHE_DIR": str(Path(tmp) / "cache")}
            wall, st, text = run_once(out, cold_env, args.figures)
            note = [ln for ln in text.splitlines() if "compil" in ln]
            print(
                f"cold run (empty kernel cache): wall {wall:.1f} s, kernels stage "
                f"{st.get('kernels', float('nan')):.1f} s"
            )
            for ln in note:
                print(f"  | {ln.strip()}")
        run_once(out, env, args.figures)  # the cache is warm from here on
        walls, stages = [], []
        for _ in range(args.repeats):
            wall, st, _ = run_once(out, env, args.figures)
            walls.append(wall)
            stages.append(st)
        size = sum(f.stat().st_size for f in out.glob("*.nc"))
    keys = [k for k in stages[0] if k not in ("total", "process")]
    med = {k: statistics.median(s[k] for s in stages) for k in keys + ["total"]}
    sim = med["ideal"] + med["clearance"]
    wall = statistics.median(walls)
    print(f"warm runs: {args.repeats}, figures {'on' if args.figures else 'off'}; medians [s]")
    for k in keys:
        print(f"  {k:<20s} {med[k]:7.3f}")
    print(f"  {'run_scenario total':<20s} {med['total']:7.3f}")
    print(f"  {'process wall':<20s} {wall:7.3f}   (min {min(walls):.3f}, max {max(walls):.3f})")
    print(f"wall / simulate() calls = {wall:.2f} / {sim:.2f} = {wall / sim:.2f} (target <= 2)")
    print(f"result file {size / 1e6:.1f} MB (target <= 15)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
