"""A long wear prediction of the default 4UPS-UPU scenario: trends, update-factor
independence and cost (issue 16; docs/wear.md quotes its output).

    python bench/bench_wear.py [--cycles 1e6] [--coefficient 1e-14] [--steps 0.05 0.025]
                               [--grid 32] [--out DIR]

For each max_step (the adaptive update factor: each iteration deepens a socket by at most
max_step x c) it runs `clearance.wear.predict.predict_wear` on the shipped scenario with a
[wear] table for S_1 and S_3 (warmup 0.1 s, one cycle = the rest of the 2 s run), then
prints per iteration: cycles, worn volume, maximum depth, effective clearance, peak and RMS
contact force, platform deviation; the final values of every max_step side by side; where
the deepest wear lies against the mean contact-force direction of the last run; and the
wall time per iteration.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def scenario(text: str, args, step: float) -> str:
    wear = f"""
[wear]
cycles = {args.cycles:g}
update_factor = "auto"
max_step = {step:g}
warmup = 0.1
"""
    for j in ("S_1", "S_3"):
        wear += f"\n[wear.joints.{j}]\ncoefficient = {args.coefficient:g}\ngrid = {args.grid}\n"
    return re.sub(r"(?m)^\[wear\][\s\S]*", "", text) + wear


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=float, default=1e6)
    ap.add_argument("--coefficient", type=float, default=1e-14)
    ap.add_argument("--steps", type=float, nargs="+", default=[0.05, 0.025])
    ap.add_argument("--grid", type=int, default=32)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args()

    from clearance.scenario import default_scenario_path
    from clearance.wear.predict import predict_wear

    base = default_scenario_path("ups_upu").read_text()
    out = args.out or Path(tempfile.mkdtemp(prefix="bench_wear_"))
    finals = {}
    for step in args.steps:
        folder = out / f"max_step_{step:g}"
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / "scenario.toml"
        path.write_text(scenario(base, args, step))
        t0 = time.perf_counter()
        w = predict_wear(path, out_dir=folder, restart=True, log=None)
        wall = time.perf_counter() - t0
        h = w.history
        print(
            f"\nmax_step {step:g}: {len(h.iteration)} runs, {wall:.0f} s "
            f"({wall / len(h.iteration):.1f} s per run); files in {folder}"
        )
        print(
            f"{'cycles':>10} {'joint':>5} {'V [mm3]':>9} {'h_max [um]':>10} "
            f"{'c_eff [mm]':>10} {'F_peak [N]':>10} {'F_rms [N]':>9} {'platform [um]':>13}"
        )
        for i in h.iteration.values:
            for j in h.joint.values:
                r = h.sel(iteration=i, joint=j)
                print(
                    f"{float(r.cycles):10.4g} {j!s:>5} {float(r.volume) * 1e9:9.4f} "
                    f"{float(r.max_depth) * 1e6:10.2f} {float(r.effective_clearance) * 1e3:10.4f} "
                    f"{float(r.peak_contact_force):10.1f} {float(r.rms_contact_force):9.2f} "
                    f"{float(h.platform_deviation[i]) * 1e6:13.1f}"
                )
        finals[step] = {
            j: (float(h.volume.sel(joint=j)[-1]), float(h.max_depth.sel(joint=j)[-1]))
            for j in h.joint.values
        }
        for j, m in w.state.maps.items():  # where the wear is, in the socket frame
            k = int(np.argmax(m.depth))
            print(f"  {j}: deepest cell at {np.round(m.centres.reshape(-1, 3)[k], 3)}")
    # where the ball presses: the force-weighted mean contact direction of an unworn run
    from clearance.io.dataset import result_to_dataset
    from clearance.pipeline import run_scenario

    o = run_scenario(default_scenario_path("ups_upu"), figures=False, log=None, defer_write=True)
    ds = result_to_dataset(o.clearance, outputs=("clearance",))
    names = [str(c) for c in ds["clearance"].values]
    print("\nthe wear against the load (socket frame), last max_step:")
    for j, m in w.state.maps.items():
        k = names.index(j)
        e = ds["eccentricity"].values[:, k]
        f = np.abs(ds["contact_force"].values[:, k])
        load = (f[:, None] * e / np.maximum(np.linalg.norm(e, axis=1), 1e-300)[:, None]).sum(0)
        load /= np.linalg.norm(load)
        d = m.depth.reshape(-1)
        cells = m.centres.reshape(-1, 3)
        deep = cells[int(np.argmax(d))]
        mean = (d[:, None] * m.areas.reshape(-1)[:, None] * cells).sum(0)
        mean /= np.linalg.norm(mean)
        ang = np.degrees(np.arccos(np.clip([deep @ load, mean @ load], -1, 1)))
        print(
            f"  {j}: mean load direction {np.round(load, 3)}; deepest cell {ang[0]:.1f} deg "
            f"and volume-weighted wear direction {ang[1]:.1f} deg from it"
        )
    print("\nfinal worn volume [mm3] / max depth [um] per max_step:")
    for step, f in finals.items():
        print(
            f"  {step:g}: "
            + "; ".join(f"{j} {v * 1e9:.4f} / {d * 1e6:.2f}" for j, (v, d) in f.items())
        )


if __name__ == "__main__":
    sys.exit(main())
