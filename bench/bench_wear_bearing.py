"""Bearing wear of Flores' slider-crank (the library scenario: revolute clearance at the
rod-slider joint, 5000 rpm): trends and update-factor independence (issue 16, revolute;
docs/wear.md quotes its output).

    python bench/bench_wear_bearing.py [--cycles 1e6] [--coefficient 1e-15]
                                       [--steps 0.02 0.01 0.005] [--grid 64]
                                       [--revolutions 1] [--out DIR]

For each max_step (the adaptive update factor: each iteration deepens the bearing by at
most max_step x c) it runs `clearance.wear.predict.predict_wear` with a [wear] table for
the joint `wrist` (warmup: one revolution; then `revolutions` counted, one cycle each) and
prints per iteration: cycles, worn volume, maximum depth, impacts and peak contact force;
then the final values of every max_step side by side, where the deepest wear lies, the
depths along the rod (0 and 180 deg in the bearing frame) and the wall time per iteration.
"""

from __future__ import annotations

import argparse
import re
import tempfile
import time
from pathlib import Path

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=float, default=1e6)
    ap.add_argument("--coefficient", type=float, default=1e-15)
    ap.add_argument("--steps", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    ap.add_argument("--grid", type=int, default=64)
    ap.add_argument("--revolutions", type=int, default=1)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args()

    from clearance.scenario.toml_io import library_path
    from clearance.wear.predict import predict_wear

    base = library_path("slider_crank").read_text()
    out = args.out or Path(tempfile.mkdtemp(prefix="bench_wear_bearing_"))
    finals = {}
    for step in args.steps:
        folder = out / f"max_step_{step:g}"
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / "slider_crank.toml"
        duration = 0.012 * (1 + args.revolutions)
        text = re.sub(r"(?m)^duration = [0-9.]+", f"duration = {duration:g}", base)
        path.write_text(
            text
            + f"""
[wear]
cycles = {args.cycles:g}
update_factor = "auto"
max_step = {step:g}
warmup = 0.012
cycle_time = 0.012

[wear.joints.wrist]
coefficient = {args.coefficient:g}
grid = {args.grid}
length = 0.02
"""
        )
        t0 = time.perf_counter()
        w = predict_wear(path, out_dir=folder, log=None, restart=True)
        wall = time.perf_counter() - t0
        h = w.history.sel(joint="wrist")
        print(f"\nmax_step {step:g}: {h.sizes['iteration']} runs, {wall:.1f} s")
        print("  cycles       volume [mm3]  max depth [um]  impacts  peak F_N [N]")
        for i in range(h.sizes["iteration"]):
            print(
                f"  {float(h['cycles'][i]):10.4g}  {float(h['volume'][i]) * 1e9:12.5g}"
                f"  {float(h['max_depth'][i]) * 1e6:14.5g}  {int(h['impacts'][i]):7d}"
                f"  {float(h['peak_contact_force'][i]):12.5g}"
            )
        m = w.state.maps["wrist"]
        deepest = float(np.degrees(m.angles[np.argmax(m.depth[0])]))
        ends = [float(m.depth[0][np.argmin(np.abs(m.angles - a))]) for a in (0.0, np.pi)]
        finals[step] = (m.volume(), m.max_depth(), deepest, ends, wall / h.sizes["iteration"])
    print(
        "\nfinal   max_step  volume [mm3]  max depth [um]  at [deg]  depth at 0 / 180 deg [um]"
        "  s / iteration"
    )
    for step, (v, d, deepest, ends, per) in finals.items():
        print(
            f"        {step:8g}  {v * 1e9:12.5g}  {d * 1e6:14.5g}  {deepest:8.1f}"
            f"  {ends[0] * 1e6:9.4g} / {ends[1] * 1e6:9.4g}  {per:8.2f}"
        )
    print(f"\n(files in {out})")


if __name__ == "__main__":
    main()
