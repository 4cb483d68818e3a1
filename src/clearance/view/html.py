"""The viewer as one self-contained HTML file: `write_viewer(scene_or_path, out)`.

The page holds the scene as JSON (arrays as base64 of little-endian float32, times as
float64), three.js (vendored in `static/`, MIT, see `static/THREE_LICENSE` and
`tools/three/`) and `static/viewer.js`; it opens from `file://` with no network. The
page's state is readable through `window.viewer` (see viewer.js).
"""

from __future__ import annotations

import base64
import html
import json
import os
from importlib import resources
from pathlib import Path

import numpy as np

from clearance.io.files import atomic_path
from clearance.view.scene import Scene, load_scene

__all__ = ["SPEEDS", "viewer_html", "write_viewer"]

SPEEDS = (1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001)
MODES = (
    ("overlay", "ideal overlaid"),
    ("side", "side by side"),
    ("clearance", "clearance only"),
    ("ideal", "ideal only"),
)


def _b64(a: np.ndarray, dtype) -> str:
    return base64.b64encode(
        np.ascontiguousarray(a, dtype=np.dtype(dtype).newbyteorder("<")).tobytes()
    ).decode()


def _static(name: str) -> str:
    return resources.files("clearance.view").joinpath("static", name).read_text(encoding="utf-8")


def _view_axes(e: np.ndarray) -> tuple[list, list]:
    """A close-up camera direction along the eccentricity's least spread (the trace is
    seen flattest-side on) and an up vector; the socket's h axis when there is no motion."""
    x = e - e.mean(axis=0)
    if e.shape[0] < 3 or not np.any(np.abs(x) > 0):
        return [0.35, -0.5, 1.0], [0.0, 0.0, 1.0]
    _, _, vt = np.linalg.svd(x, full_matrices=False)
    d = vt[2] if vt[2][2] >= 0 else -vt[2]
    up = vt[1]
    return (d + 0.15 * vt[0]).tolist(), up.tolist()


def _colormap(name: str = "plasma", n: int = 9) -> list:
    from matplotlib import colormaps

    cm = colormaps[name]
    return [[round(float(c), 4) for c in cm(k / (n - 1))[:3]] for k in range(n)]


def _payload(scene: Scene) -> dict:
    rod = 0.012 * scene.size
    clearances = []
    for c in scene.clearances:
        info = dict(c.info)
        draw_outer = max(float(info["outer_radius"]), 1.6 * rod)
        if info["kind"] == "spherical":
            direction, up = _view_axes(c.e)
        else:  # journals and sliders: the bearing plane / the guide's cross-section
            direction, up = [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]
        info.update(
            draw_outer=draw_outer,
            arrow_length=4.0 * draw_outer,
            outer_marker=scene.geometry["markers"][info["outer_marker"]],
            e=_b64(c.e, np.float32),
            force=_b64(c.force, np.float32),
            normal=_b64(c.normal, np.float32),
            fn=_b64(c.fn, np.float32),
            contact=_b64(c.contact, np.uint8),
            events=np.round(c.events, 12).tolist(),
            peak=float(c.peak),
            view_direction=direction,
            view_up=up,
        )
        clearances.append(info)
    return {
        "title": scene.title,
        "source": scene.source,
        "version": scene.version,
        "ground": scene.geometry.get("ground", "ground"),
        "bodies": list(scene.bodies),
        "time": _b64(scene.time, np.float64),
        "runs": [
            {
                "name": r.name,
                "message": r.message,
                "success": r.success,
                "t_end": r.t_end,
                "present": r.present or [1] * len(scene.bodies),
                "poses": _b64(r.poses, np.float32),
            }
            for r in scene.runs
        ],
        "shapes": scene.shapes,
        "glyphs": scene.glyphs,
        "size": scene.size,
        "magnification": scene.magnification,
        "clearances": clearances,
        "colormap": _colormap(),
    }


_CSS = """
* { box-sizing: border-box; }
html, body { margin: 0; height: 100%; font: 13px/1.35 system-ui, sans-serif; color: #1c2833;
  background: #f4f6f8; }
header { padding: 6px 12px; display: flex; gap: 14px; align-items: baseline; }
header h1 { font-size: 16px; margin: 0; }
header .meta { color: #5d6d7e; font-size: 12px; }
#wrap { display: flex; height: calc(100% - 96px); padding: 0 8px; gap: 8px; }
#main { flex: 1; min-width: 0; position: relative; background: #f4f6f8;
  border: 1px solid #d5dbe1; }
#main .hud { position: absolute; left: 8px; top: 6px; pointer-events: none; color: #34495e; }
#closeups { width: 260px; overflow-y: auto; display: flex; flex-direction: column; gap: 8px; }
.closeup { background: #fff; border: 1px solid #d5dbe1; }
.closeup .label { font-size: 11px; padding: 3px 6px; color: #34495e; }
.closeup canvas { display: block; width: 100%; }
#bar { display: flex; align-items: center; gap: 8px; padding: 6px 12px; flex-wrap: wrap; }
#bar .slider { flex: 1; min-width: 200px; display: flex; flex-direction: column; }
#bar input[type=range] { width: 100%; margin: 0; }
#ticks { width: 100%; height: 6px; }
#tlabel { font-variant-numeric: tabular-nums; min-width: 110px; }
button, select { font: inherit; }
"""


def viewer_html(scene: Scene) -> str:
    """The page (module docstring) for a Scene."""
    # (every "<" escaped: no "</script>" or "<!--" in a name can end or hide the block)
    data = json.dumps(_payload(scene), separators=(",", ":")).replace("<", "\\u003c")
    speeds = "".join(
        f'<option value="{s:g}"{" selected" if s == 0.1 else ""}>{s:g}\u00d7</option>'
        for s in SPEEDS
    )
    modes = "".join(f'<option value="{k}">{html.escape(v)}</option>' for k, v in MODES)
    runs = ", ".join(
        f"{r.name}{'' if r.success else ' (stopped: ' + r.message + ')'}" for r in scene.runs
    )
    title = html.escape(f"{scene.title}: clearance viewer")
    meta = html.escape(
        f"{Path(scene.source).name} \u00b7 runs: {runs} \u00b7 clearance {scene.version}"
    )
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="clearance {html.escape(scene.version)}">
<title>{title}</title>
<style>{_CSS}</style>
</head>
<body>
<header><h1>{html.escape(scene.title)}</h1><span class="meta">{meta}</span></header>
<div id="wrap">
  <div id="main"><div class="hud"><span id="mag"></span></div></div>
  <aside id="closeups"></aside>
</div>
<div id="bar">
  <button id="play" title="play / pause (space)">\u25b6 play</button>
  <button id="prev" title="previous frame">\u25c0</button>
  <button id="next" title="next frame">\u25b6</button>
  <div class="slider"><input type="range" id="time" min="0" max="0" step="1" value="0"
    aria-label="time"><canvas id="ticks" title="contact onsets"></canvas></div>
  <span id="tlabel"></span>
  <label>speed <select id="speed">{speeds}</select></label>
  <select id="mode" aria-label="runs">{modes}</select>
  <label><input type="checkbox" id="arrows" checked> contact forces</label>
  <button id="impact" title="to the next contact onset">next impact</button>
</div>
<script type="application/json" id="clearance-data">{data}</script>
<script>{_static("three.min.js")}</script>
<script>{_static("viewer.js")}</script>
</body>
</html>
"""


def write_viewer(
    scene: Scene | str | os.PathLike, out: str | os.PathLike | None = None, **load
) -> Path:
    """Write the viewer of a Scene (or of a result file, read with `load_scene(**load)`)
    to `out` (default: the result file's name with .html), atomically; returns the path."""
    if not isinstance(scene, Scene):
        scene = load_scene(scene, **load)
    out = Path(out) if out is not None else Path(scene.source).with_suffix(".html")
    text = viewer_html(scene)
    with atomic_path(out) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return out
