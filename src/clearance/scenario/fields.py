"""Field specifications of the scenario sections and their checks (collecting problems).

A section is a dict name -> `Field`. `parse_table(table, spec, path, problems)` checks a
TOML table against it: unknown keys (with a "did you mean"), missing required fields, and
each value's kind. It returns the valid values with defaults filled in; invalid values are
reported to `problems` and left out.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass

from clearance.scenario.errors import MISSING, Problems

__all__ = ["REQUIRED", "Field", "check_kind", "parse_table", "plain", "table_at"]

REQUIRED = MISSING  # default of a required field

# kind -> the "allowed" text of its error message
_ALLOWED = {
    "text": "expected a string",
    "name": "expected a non-empty string",
    "positive": "expected a finite number > 0",
    "positive_inf": "expected a number > 0 (inf allowed)",
    "nonneg": "expected a finite number >= 0",
    "count": "expected an integer >= 1",
    "count0": "expected an integer >= 0",
    "bool": "expected true or false",
    "positive3": "expected a list of 3 finite numbers > 0",
    "list": "expected a list of distinct names",
    "table": "expected a table { key = value, ... }",
}


@dataclass(frozen=True)
class Field:
    """One scenario field: kind (see `check_kind`), default (REQUIRED if none), unit, doc.

    kind "choice": one of `choices`; "choices": a list of distinct values from `choices`.
    minimum: the smallest value a "positive" field takes (None: any number > 0).
    """

    kind: str
    default: object = REQUIRED
    unit: str = ""
    doc: str = ""
    choices: tuple[str, ...] = ()
    minimum: float | None = None

    @property
    def required(self) -> bool:
        return self.default is REQUIRED


def _real(x: object) -> bool:
    return not isinstance(x, bool) and isinstance(x, numbers.Real)


def check_kind(f: Field, value: object) -> tuple[bool, object, str]:
    """(ok, normalised value, allowed text) of `value` for field spec `f`."""
    unit = f" [{f.unit}]" if f.unit else ""
    k = f.kind
    if k in ("choice", "choices"):
        allowed = ", ".join(repr(c) for c in f.choices)
        if k == "choice":
            return value in f.choices, value, f"allowed: {allowed}"
        ok = (
            isinstance(value, list)
            and all(v in f.choices for v in value)
            and len(set(map(str, value))) == len(value)
        )
        return ok, tuple(value) if ok else value, f"expected a list of distinct values: {allowed}"
    allowed = _ALLOWED[k] + unit
    if k == "positive" and f.minimum is not None:
        allowed = f"expected a finite number >= {f.minimum:g}{unit}"
    if k == "text":
        return isinstance(value, str), value, allowed
    if k == "name":
        return isinstance(value, str) and bool(value.strip()), value, allowed
    if k == "bool":
        return isinstance(value, bool), value, allowed
    if k in ("count", "count0"):
        lo = 1 if k == "count" else 0
        ok = isinstance(value, int) and not isinstance(value, bool) and value >= lo
        return ok, value, allowed
    if k == "list":
        ok = (
            isinstance(value, list)
            and all(isinstance(v, str) and v for v in value)
            and len(set(value)) == len(value)
        )
        return ok, tuple(value) if ok else value, allowed
    if k == "table":
        return isinstance(value, dict), value, allowed
    if k == "positive3":
        ok = (
            isinstance(value, list)
            and len(value) == 3
            and all(_real(x) and math.isfinite(x) and x > 0 for x in value)
        )
        return ok, tuple(float(x) for x in value) if ok else value, allowed
    if not _real(value) or math.isnan(value):  # type: ignore[arg-type]
        return False, value, allowed
    v = float(value)  # type: ignore[arg-type]
    if k == "positive":
        return math.isfinite(v) and v > 0.0 and v >= (f.minimum or 0.0), v, allowed
    if k == "positive_inf":
        return v > 0.0, v, allowed
    if k == "nonneg":
        return math.isfinite(v) and v >= 0.0, v, allowed
    raise ValueError(f"unknown field kind {k!r}")


def table_at(value: object, path: str, problems: Problems) -> dict | None:
    """`value` if it is a table (dict), else report it and return None."""
    if isinstance(value, dict):
        return value
    problems.add(path, value, "expected a table (a [section] or {key = value, ...})")
    return None


def parse_table(
    table: Mapping[str, object],
    spec: Mapping[str, Field],
    path: str,
    problems: Problems,
    *,
    extra: tuple[str, ...] = (),
) -> dict[str, object]:
    """Check `table` against `spec`; return the valid values with defaults filled in.

    Keys in `extra` are allowed but not checked here (the caller handles them).
    """
    out: dict[str, object] = {}
    allowed = [*spec, *extra]
    for key, value in table.items():
        if key in extra:
            continue
        if key not in spec:
            problems.unknown(f"{path}.{key}", key, value, allowed)
            continue
        ok, v, msg = check_kind(spec[key], value)
        if ok:
            out[key] = v
        else:
            problems.add(f"{path}.{key}", value, msg)
    for key, f in spec.items():
        if key not in table:
            if f.required:
                problems.add(f"{path}.{key}", MISSING, f"required field is missing ({f.doc})")
            else:
                out[key] = f.default
    return out


def plain(d: object) -> object:
    """A deep copy with tuples as lists (the plain data of a TOML document)."""
    if isinstance(d, dict):
        return {k: plain(v) for k, v in d.items()}
    if isinstance(d, (list, tuple)):
        return [plain(v) for v in d]
    return d
