"""A study's report: `study_report(folder)`, `clearance report STUDY_FOLDER`.

One HTML page (<folder>/report.html) with the table of cases (parameters, status, the
study's metrics, plausibility), the summary plots of `clearance collect` (drawn when
missing) and, per finished case, a link to its viewer page (the case's result file with
.html, written when missing or older than the result; `clearance.view.html`).
"""

from __future__ import annotations

import os
from pathlib import Path

from clearance.io.files import atomic_path
from clearance.view.html import write_viewer
from clearance.view.report import CSS, REPORT, _e, _num, figure_files, figures_html, table_html
from clearance.view.scene import SceneError

__all__ = ["study_report"]


def study_report(folder: str | os.PathLike, out: str | os.PathLike | None = None) -> Path:
    """The report of a study folder (written by `clearance sweep`): the table of cases
    (parameters, status, the summary metrics), the summary plots (collected/plots, drawn
    when missing) and a viewer page per finished case (cases' result file with .html),
    linked from the table. Written to <folder>/report.html unless `out`."""
    import pandas as pd

    from clearance.sweep.collect import collect_study, study_table
    from clearance.sweep.store import FINISHED, case_files

    folder = Path(folder)
    table = study_table(folder)
    plots_dir = folder / "collected" / "plots"
    if not figure_files(plots_dir):
        collect_study(folder, dataset=False, plots=True)
    out = Path(out) if out is not None else folder / REPORT
    links = []
    for _, row in table.iterrows():
        nc = case_files(folder, str(row["case"]))[0]
        link = ""
        if row["status"] == FINISHED and nc.is_file():
            page = nc.with_suffix(".html")
            try:
                if not page.is_file() or page.stat().st_mtime < nc.stat().st_mtime:
                    write_viewer(nc, page)
                link = f'<a href="{_e(os.path.relpath(page, out.parent))}">viewer</a>'
            except (SceneError, OSError) as e:
                link = f"no viewer ({_e(e)})"
        links.append(link)
    cols = [c for c in table.columns if c not in ("result_file", "worker")]
    rows = []
    for (_, row), link in zip(table.iterrows(), links, strict=True):
        cells = []
        for c in cols:
            v = row[c]
            cells.append(_num(v) if isinstance(v, float) and not pd.isna(v) else _e(v))
        rows.append([*cells, link])
    name = folder.name
    body = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{_e(name)}: clearance study report</title>
<style>{CSS}</style></head><body>
<h1>Study {_e(name)}</h1>
<p class="meta">{len(table)} cases &middot; {
        _e(
            ", ".join(
                f"{n} {k}" for k, n in sorted(table["status"].value_counts().to_dict().items())
            )
        )
    }</p>
<h2>Cases</h2>
{table_html([*(_e(c) for c in cols), "motion"], rows, left=2)}
<h2>Summary plots</h2>
{figures_html(figure_files(plots_dir), out.parent)}
</body></html>
"""
    with atomic_path(out) as tmp:
        Path(tmp).write_text(body, encoding="utf-8")
    return out
