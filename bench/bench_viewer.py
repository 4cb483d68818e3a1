"""The viewer, the video and the report of the default scenario: sizes and times.

    python bench/bench_viewer.py [--result FILE.nc] [--repeats 3] [--video-frames 50]

Runs the default 4UPS-UPU scenario (unless --result is given), then measures:

- the result file's size and the share of its `frames` groups;
- `write_viewer` (read the file, build the page) and the page's size;
- the page's load time in headless Chromium: from navigation to the first drawn frame
  (`window.viewer.renders > 0`), median of repeats, each in a fresh browser;
- the report (`write_report` from the file, figures drawn if missing) and its load time;
- `render_video` per frame at 1280x720 (MP4).

Needs Debian's chromium and chromedriver (tests/browser.py); prints a table.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))


def _load_time(page: Path, script: str, frame_css: str | None = None) -> float:
    from browser import chrome, wait_for

    d = chrome()
    try:
        t0 = time.perf_counter()
        d.get(page.as_uri())
        if frame_css:
            d.switch_to.frame(d.find_element("css selector", frame_css))
        wait_for(d, script, timeout=60)
        return time.perf_counter() - t0
    finally:
        d.quit()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--result", type=Path, default=None)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--video-frames", type=int, default=50)
    a = ap.parse_args()

    from clearance.view import load_scene
    from clearance.view.html import write_viewer
    from clearance.view.report import write_report
    from clearance.view.video import render_video

    tmp = Path(tempfile.mkdtemp(prefix="bench_viewer_"))
    result = a.result
    if result is None:
        from clearance.pipeline import run_scenario
        from clearance.scenario import default_scenario_path, load_scenario

        run_scenario(load_scenario(default_scenario_path()), out_dir=tmp, figures=True, log=None)
        result = tmp / "ups_upu.nc"
    rows = [("result file", f"{result.stat().st_size / 1e6:.2f} MB")]

    import netCDF4

    with netCDF4.Dataset(result) as nc:
        nframes = {g: len(nc.groups[g].dimensions["frame"]) for g in nc.groups}
    rows.append(("frames per run", ", ".join(f"{g} {n}" for g, n in nframes.items())))

    times = []
    for _ in range(a.repeats):
        t0 = time.perf_counter()
        page = write_viewer(result, tmp / "view.html")
        times.append(time.perf_counter() - t0)
    rows.append(("write_viewer (median)", f"{statistics.median(times):.3f} s"))
    rows.append(("viewer page", f"{page.stat().st_size / 1e6:.2f} MB"))
    loads = [
        _load_time(page, "window.viewer && window.viewer.renders > 0") for _ in range(a.repeats)
    ]
    rows.append(
        (
            "viewer load to first frame",
            f"median {statistics.median(loads):.2f} s, max {max(loads):.2f} s",
        )
    )

    t0 = time.perf_counter()
    rep = write_report(result, tmp / "report.html")
    rows.append(("write_report (from the file)", f"{time.perf_counter() - t0:.3f} s"))
    rows.append(("report page", f"{rep.stat().st_size / 1e6:.2f} MB"))
    loads = [
        _load_time(rep, "window.viewer && window.viewer.renders > 0", "iframe.viewer")
        for _ in range(a.repeats)
    ]
    rows.append(
        (
            "report load to the viewer's first frame",
            f"median {statistics.median(loads):.2f} s, max {max(loads):.2f} s",
        )
    )

    sc = load_scene(result)
    fps = 25.0
    speed = (sc.time[-1] - sc.time[0]) / (a.video_frames - 1) * fps
    t0 = time.perf_counter()
    info = render_video(sc, tmp / "video.mp4", fps=fps, speed=speed)
    dt = time.perf_counter() - t0
    rows.append(
        (
            "video 1280x720 MP4",
            f"{info.frames} frames in {dt:.1f} s: "
            f"{dt / info.frames:.3f} s per frame, {info.path.stat().st_size / 1e6:.2f} MB",
        )
    )

    w = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"{k:<{w}s}  {v}")
    print(f"(files in {tmp})")


if __name__ == "__main__":
    main()
