"""The study folder: manifest, base scenario, one result file and one sidecar per case.

    <folder>/study.json          manifest: study, base scenario hash, parameters, cases
    <folder>/base_scenario.toml  the base scenario every case starts from (canonical)
    <folder>/study.toml          the study as given
    <folder>/cases/<id>.nc       the case's results (NetCDF, groups ideal and clearance)
    <folder>/cases/<id>.json     the case's sidecar: status, attempts, reason, metrics, ...
    <folder>/collected/          written by `collect_study`

Every file is written atomically (`clearance.io.dataset.atomic_path`). A case is finished
only when its sidecar says "finished", names this case's overrides, and its result file
exists with the size the sidecar recorded: a case interrupted at any point is redone, a
finished case never is.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from clearance.io.files import atomic_path
from clearance.sweep.design import canonical_json
from clearance.sweep.study import Case, Study, StudyError

__all__ = [
    "CASES",
    "RUNNING",
    "FINISHED",
    "FAILED",
    "case_files",
    "is_finished",
    "now",
    "prepare_folder",
    "read_json",
    "read_manifest",
    "remove_temporaries",
    "STALE_TMP",
    "write_json",
]

CASES = "cases"
MANIFEST = "study.json"
RUNNING, FINISHED, FAILED = "running", "finished", "failed"


def now() -> str:
    """UTC time stamp with microseconds (sidecar times)."""
    return _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="microseconds")


def _jsonable(obj: object) -> object:
    """numpy scalars and arrays -> Python (NaN and inf are kept: Python's JSON reads them)."""
    if isinstance(obj, Mapping):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if hasattr(obj, "tolist"):
        return _jsonable(obj.tolist())
    return obj


def write_json(path: str | os.PathLike, data: Mapping[str, Any]) -> Path:
    """Write `data` as JSON, atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(_jsonable(data), indent=1, allow_nan=True), encoding="utf-8")
    return Path(path)


def read_json(path: str | os.PathLike) -> dict | None:
    """The JSON object in `path`, or None if the file is missing or unreadable."""
    try:
        d = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return d if isinstance(d, dict) else None


def case_files(folder: str | os.PathLike, cid: str) -> tuple[Path, Path]:
    """(result file, sidecar) of case `cid`."""
    d = Path(folder) / CASES
    return d / f"{cid}.nc", d / f"{cid}.json"


def is_finished(folder: str | os.PathLike, case: Case) -> bool:
    """True if the case's sidecar says finished, for these overrides, and its result file is
    there with the recorded size."""
    nc, side = case_files(folder, case.id)
    s = read_json(side)
    if s is None or s.get("status") != FINISHED or s.get("case") != case.id:
        return False
    if canonical_json(s.get("overrides")) != canonical_json(case.overrides):
        return False
    try:
        return nc.stat().st_size == s.get("result_bytes")
    except OSError:
        return False


def read_manifest(folder: str | os.PathLike) -> dict:
    """The manifest (study.json) of a study folder; StudyError if there is none."""
    m = read_json(Path(folder) / MANIFEST)
    if m is None:
        raise StudyError(
            str(folder), "(folder)", str(folder), f"not a study folder: no readable {MANIFEST}"
        )
    return m


def prepare_folder(study: Study, folder: Path) -> None:
    """Create the folder and write the manifest, base scenario and study file.

    A folder that already holds a study with a different base scenario is refused (its
    cases would silently mix two studies); the same base with other parameters is fine:
    cases with the same overrides are reused, the manifest lists the current cases.
    """
    from clearance.scenario.toml_io import dumps_toml

    old = read_json(folder / MANIFEST)
    if old is not None and old.get("base_sha256") != study.base_sha:
        raise StudyError(
            study.source,
            "study.folder",
            str(folder),
            f"this folder holds cases of study '{old.get('name')}' with a different base "
            "scenario (or [set] values); choose another folder or delete it",
        )
    (folder / CASES).mkdir(parents=True, exist_ok=True)
    remove_temporaries(folder)
    write_json(folder / MANIFEST, study.manifest())
    with atomic_path(folder / "base_scenario.toml") as tmp:
        tmp.write_text(dumps_toml(study.base), encoding="utf-8")
    src = Path(study.source)
    text = src.read_text(encoding="utf-8") if src.is_file() else dumps_toml(study.document)
    with atomic_path(folder / "study.toml") as tmp:
        tmp.write_text(text, encoding="utf-8")


def remove_temporaries(folder: Path, *, older_than: float = 0.0) -> int:
    """Delete the half-written files an interrupted or killed study left in `folder` and
    its cases (the `.<name>.<random>.tmp` files of `atomic_path`; a result file's can be
    100 MB), those not modified for `older_than` seconds; return how many. A study that
    starts or resumes removes them all (two studies must not run into one folder at
    once); collect only those older than `STALE_TMP` (a running study's writes are
    younger: collect may watch a running study)."""
    import time

    n, now_ = 0, time.time()
    for d in (Path(folder), Path(folder) / CASES):
        for p in d.glob(".*.tmp"):
            with contextlib.suppress(FileNotFoundError):
                if now_ - p.stat().st_mtime >= older_than:
                    p.unlink()
                    n += 1
    return n


STALE_TMP = 600.0  # [s] a temporary file untouched this long belongs to no running write
