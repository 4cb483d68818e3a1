"""Run reports: one self-contained HTML page per run (`report.html` next to the results),
and one per study.

A run's report holds the summary table (each clearance joint's peak contact force, impacts
and penetration; the platform's deviation from the ideal run; each run's status,
plausibility, energy residual and cost), the figures (embedded), the 3-D viewer (embedded
in an iframe, `clearance.view.html`), the scenario file and the version. `clearance run`
writes it; `clearance report RESULT.nc` rebuilds it from the file (and draws the figures
when the figures folder has none). Studies get theirs from `clearance.sweep.report`.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

from clearance.io.files import atomic_path
from clearance.view.scene import Scene, SceneError

__all__ = [
    "CSS",
    "REPORT",
    "figure_files",
    "figures_html",
    "report_html",
    "table_html",
    "write_report",
]

REPORT = "report.html"
_IMG = {".png": "image/png", ".svg": "image/svg+xml", ".jpg": "image/jpeg"}

CSS = """
body { font: 14px/1.45 system-ui, sans-serif; color: #1c2833; margin: 0 auto; max-width: 1280px;
  padding: 12px 20px 40px; }
h1 { font-size: 22px; margin: 8px 0 2px; } h2 { font-size: 17px; margin: 26px 0 8px;
  border-bottom: 1px solid #d5dbe1; padding-bottom: 3px; }
.meta { color: #5d6d7e; font-size: 13px; }
table { border-collapse: collapse; margin: 6px 0 12px; font-size: 13px; }
th, td { border: 1px solid #d5dbe1; padding: 3px 8px; text-align: right; }
th { background: #eef1f4; } td.l, th.l { text-align: left; }
.ok { color: #1e8449; font-weight: 600; } .bad { color: #b03a2e; font-weight: 600; }
.warn { color: #b9770e; font-weight: 600; }
.figs { display: grid; grid-template-columns: repeat(auto-fill, minmax(560px, 1fr)); gap: 12px; }
.figs figure { margin: 0; border: 1px solid #d5dbe1; padding: 6px; background: #fff; }
.figs img { width: 100%; } figcaption { font-size: 12px; color: #5d6d7e; }
iframe.viewer { width: 100%; height: 680px; border: 1px solid #d5dbe1; }
pre { background: #f4f6f8; padding: 8px; overflow-x: auto; font-size: 12px; }
"""


def _e(x: object) -> str:
    return html.escape(str(x))


def _num(x: object, fmt: str = ".4g", scale: float = 1.0) -> str:
    try:
        v = float(x) * scale
    except (TypeError, ValueError):
        return _e(x)
    if math.isinf(v):
        return "inf"
    return "" if math.isnan(v) else format(v, fmt)


def table_html(head: Sequence[str], rows: Sequence[Sequence[str]], left: int = 1) -> str:
    """An HTML table; cells are HTML already (escape them first); `left` first columns
    are left-aligned."""
    h = "".join(f'<th class="{"l" if k < left else ""}">{c}</th>' for k, c in enumerate(head))
    body = "".join(
        "<tr>"
        + "".join(f'<td class="{"l" if k < left else ""}">{c}</td>' for k, c in enumerate(r))
        + "</tr>"
        for r in rows
    )
    return f"<table><thead><tr>{h}</tr></thead><tbody>{body}</tbody></table>"


def _status(run: Mapping) -> str:
    p = run.get("plausibility", {}) or {}
    msg = _e(run.get("message", ""))
    if p.get("status") == "implausible":
        return f'<span class="bad">IMPLAUSIBLE</span>: {_e("; ".join(p.get("findings", [])))}'
    if int(run.get("status", 0)) != 0:
        return f'<span class="bad">stopped</span>: {msg}'
    if p.get("findings"):
        return f'<span class="warn">ok, with warnings</span>: {_e("; ".join(p["findings"]))}'
    return f'<span class="ok">ok</span> {msg}'


def _summary_html(summary: Mapping) -> str:
    parts = []
    joints = summary.get("joints", {})
    if joints:
        rows = [
            [
                _e(n),
                _num(j.get("peak_contact_force"), ".1f"),
                _num(j.get("peak_contact_force_time"), ".5f"),
                _num(j.get("rms_contact_force"), ".1f"),
                _e(j.get("impacts", "")),
                _num(j.get("max_penetration"), ".3g", 1e6),
            ]
            for n, j in joints.items()
        ]
        head = ["clearance joint", "peak F<sub>N</sub> [N]", "at t [s]", "RMS F<sub>N</sub> [N]"]
        parts.append(table_html([*head, "impacts", "max penetration [&micro;m]"], rows))
    dev = summary.get("deviation_rms", {})
    if dev:
        units = {
            "position": ("&micro;m", 1e6),
            "velocity": ("mm/s", 1e3),
            "acceleration": ("m/s<sup>2</sup>", 1.0),
            "angular_velocity": ("rad/s", 1.0),
            "angular_acceleration": ("rad/s<sup>2</sup>", 1.0),
        }
        rows = [
            [
                _e(k.replace("_", " ")),
                _num(v, ".3g", units.get(k, ("", 1.0))[1]),
                units.get(k, ("",))[0],
            ]
            for k, v in dev.items()
        ]
        parts.append("<p>Platform: RMS deviation of the clearance run from the ideal run</p>")
        parts.append(table_html(["channel", "RMS deviation", "unit"], rows, left=1))
    rows = []
    for label in ("ideal", "clearance"):
        r = summary.get(label)
        if not r:
            continue
        rows.append(
            [
                _e(label),
                _status(r),
                _num(r.get("energy_residual"), ".2e"),
                _num(r.get("energy_residual_relative"), ".1e"),
                _e(r.get("steps", "")),
                _e(r.get("rhs_evaluations", "")),
                _num(r.get("wall_time"), ".3f"),
                _num(r.get("real_time_factor"), ".2f"),
            ]
        )
    if rows:
        head = ["run", "status", "energy residual [J]", "relative", "steps", "rhs"]
        parts.append(table_html([*head, "wall [s]", "real-time factor"], rows, left=2))
    st = summary.get("steady_state")
    if st:
        parts.append(
            f"<p><b>Steady state</b> ({_e(st.get('points', ''))} Poincar&eacute; points after "
            f"the transient): {_e(st.get('response', ''))}; {_e(st.get('evidence', ''))}</p>"
        )
    return "\n".join(parts)


def _summary_from_file(path: Path, root: Mapping) -> dict:
    """The summary of a result file: the `summary` attribute `clearance run` writes, else
    what the groups hold (files before 0.2)."""
    raw = root.get("summary")
    if raw:
        try:
            return json.loads(raw)
        except (TypeError, ValueError):
            pass
    import xarray as xr

    out: dict = {"joints": {}, "deviation_rms": {}}
    plaus = {}
    try:
        plaus = json.loads(root.get("plausibility", "{}"))
    except (TypeError, ValueError):
        pass
    for g in ("ideal", "clearance"):
        try:
            ds = xr.open_dataset(path, group=g, engine="netcdf4")
        except OSError:
            continue
        with ds:
            out[g] = {
                "status": int(ds.attrs.get("status", 0)),
                "message": str(ds.attrs.get("message", "")),
                "steps": ds.attrs.get("stats_naccept", ""),
                "rhs_evaluations": ds.attrs.get("stats_nfev", ""),
                "wall_time": ds.attrs.get("stats_wall_time", math.nan),
                "plausibility": plaus.get(g, {}),
            }
            if g == "clearance" and "peak_contact_force" in ds:
                for j, name in enumerate(str(c) for c in ds["clearance"].values):
                    onsets = 0
                    if "event_clearance" in ds:
                        onsets = int(
                            sum(
                                1
                                for c, k in zip(
                                    ds["event_clearance"].values,
                                    ds["event_kind"].values,
                                    strict=True,
                                )
                                if str(c) == name and k > 0
                            )
                        )
                    out["joints"][name] = {
                        "peak_contact_force": float(ds["peak_contact_force"].values[j]),
                        "peak_contact_force_time": float(ds["peak_contact_force_time"].values[j]),
                        "rms_contact_force": math.nan,
                        "impacts": onsets,
                        "max_penetration": max(0.0, float(ds["peak_penetration"].values[j])),
                    }
    return out


def figures_html(figures: Sequence[Path], base: Path) -> str:
    items = []
    for f in figures:
        kind = _IMG.get(f.suffix.lower())
        cap = _e(f.stem.replace("_", " "))
        if kind is None:  # (pdf, ...): linked
            rel = os.path.relpath(f, base)
            items.append(
                f'<figure><a href="{_e(rel)}">{_e(f.name)}</a><figcaption>{cap}'
                "</figcaption></figure>"
            )
            continue
        data = base64.b64encode(f.read_bytes()).decode()
        items.append(
            f'<figure><img alt="{cap}" src="data:{kind};base64,{data}">'
            f"<figcaption>{cap}</figcaption></figure>"
        )
    return f'<div class="figs">{"".join(items)}</div>' if items else "<p>No figures.</p>"


def report_html(
    scene: Scene | None,
    summary: Mapping,
    *,
    title: str,
    description: str = "",
    scenario: str = "",
    version: str = "",
    result: Path | None = None,
    figures: Sequence[Path] = (),
    base: Path | None = None,
    viewer_error: str = "",
) -> str:
    """The page of a run report (module docstring)."""
    from clearance.view.html import viewer_html

    base = base or Path(".")
    created = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    res = ""
    if result is not None:
        res = (
            f' &middot; result <a href="{_e(os.path.relpath(result, base))}">{_e(result.name)}</a>'
        )
    if scene is not None:
        page = viewer_html(scene)
        viewer = (
            f'<iframe class="viewer" title="3-D viewer" srcdoc="{html.escape(page, quote=True)}">'
            '</iframe><p class="meta">Drag to orbit, scroll to zoom; the slider, play and '
            "speed are below the scene (docs/viewer.md).</p>"
        )
    else:
        viewer = f"<p>No viewer: {_e(viewer_error)}</p>"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="clearance {_e(version)}">
<title>{_e(title)}: clearance report</title><style>{CSS}</style></head>
<body>
<h1>{_e(title)}</h1>
<p class="meta">{_e(description)}</p>
<p class="meta">clearance {_e(version)} &middot; report written {created}{res}</p>
<h2 id="summary">Summary</h2>
{_summary_html(summary)}
<h2 id="viewer">Motion</h2>
{viewer}
<h2 id="figures">Figures</h2>
{figures_html(figures, base)}
<h2 id="scenario">Scenario</h2>
<details><summary>the scenario file of this run</summary><pre>{_e(scenario)}</pre></details>
</body></html>
"""


def figure_files(folder: Path) -> list[Path]:
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.suffix.lower() in (*_IMG, ".pdf"))


def write_report(
    result: str | os.PathLike,
    out: str | os.PathLike | None = None,
    *,
    scene: Scene | None = None,
    summary: Mapping | None = None,
    figures: Sequence[Path] | None = None,
    draw: bool = True,
) -> Path:
    """Write the report of a result file to `out` (default: report.html next to it),
    atomically. scene / summary / figures: from the caller's memory (`clearance run`);
    else read from the file, the figures from the `figures` folder next to it, drawn
    there first when it has none and `draw`."""
    from clearance.view.scene import load_scene, read_file_layout

    result = Path(result)
    _, root = read_file_layout(result)
    out = Path(out) if out is not None else result.parent / REPORT
    error = ""
    if scene is None:
        try:
            scene = load_scene(result)
        except SceneError as e:
            error = str(e)
    if summary is None:
        summary = _summary_from_file(result, root)
    if figures is None:
        figures = figure_files(result.parent / "figures")
        if not figures and draw:
            figures = _draw(result)
    title = str(root.get("scenario_name") or result.stem)
    text = report_html(
        scene,
        summary,
        title=title,
        description=_description(root),
        scenario=str(root.get("scenario", "")),
        version=str(root.get("clearance_version", "")),
        result=result,
        figures=[Path(f) for f in figures],
        base=out.parent,
        viewer_error=error,
    )
    with atomic_path(out) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return out


def _description(root: Mapping) -> str:
    text = root.get("scenario", "")
    if not text:
        return ""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib
    try:
        return str(tomllib.loads(text).get("scenario", {}).get("description", ""))
    except (tomllib.TOMLDecodeError, AttributeError):
        return ""


def _draw(result: Path) -> list[Path]:
    from clearance.io.dataset import load_results
    from clearance.plot import plot_all

    try:
        with load_results(result) as data:
            return [Path(p) for p in plot_all(dict(data), result.parent / "figures")]
    except (KeyError, ValueError, OSError):
        return []
