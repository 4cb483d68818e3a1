"""Reading and writing scenario files (TOML), and the scenarios shipped with the package.

`load_scenario(path)` reads and validates a file; a TOML syntax error becomes a
`ScenarioError` naming the file, the line, and (when the line is `key = value`) the dotted
field and the text found. `scenario_to_toml(s)` writes the canonical form (every default
explicit, no comments) that loads back to an equal Scenario; it is small enough to be
stored in the attributes of a result file.
"""

from __future__ import annotations

import importlib.resources
import json
import math
import os
import re
import sys
from collections.abc import Mapping
from pathlib import Path

from clearance.scenario.errors import ScenarioError, did_you_mean
from clearance.scenario.schema import Scenario, scenario_from_dict
from clearance.scenario.serialize import scenario_to_dict

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "default_scenario_path",
    "default_scenarios",
    "library",
    "library_path",
    "dumps_toml",
    "load_scenario",
    "loads_scenario",
    "read_toml",
    "scenario_to_toml",
]

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
_HEADER = re.compile(r"^\s*\[\[?\s*([^\]]*?)\s*\]\]?\s*(#.*)?$")
_KEY_LINE = re.compile(r"^\s*([A-Za-z0-9_.\"' -]+?)\s*=(.*)$")
_AT_LINE = re.compile(r"at line (\d+), column (\d+)")
INLINE_DEPTH = 4  # tables this deep (clearance.joints.S_1.normal) are written inline


# --------------------------------------------------------------------------- reading


def _key_path(text: str) -> str:
    """Dotted key of a TOML header or key text: 'a. "b c" .d' -> 'a.b c.d' (simple cases)."""
    return ".".join(p.strip().strip("\"'") for p in text.split("."))


def _syntax_error(text: str, source: str, err: tomllib.TOMLDecodeError) -> ScenarioError:
    """A ScenarioError for a TOML syntax error: file, field at the failing line, its text."""
    msg = str(err)
    m = _AT_LINE.search(msg)
    reason = msg.split(" (at ")[0]
    if m is None:
        return ScenarioError(source, "(end of file)", "", f"invalid TOML: {msg}")
    lineno, col = int(m.group(1)), int(m.group(2))
    lines = text.splitlines()
    table = ""
    for line in lines[: lineno - 1]:
        h = _HEADER.match(line)
        if h:
            table = _key_path(h.group(1))
    line = lines[lineno - 1] if 0 < lineno <= len(lines) else ""
    allowed = f"invalid TOML at line {lineno}, column {col}: {reason}"
    kv = _KEY_LINE.match(line)
    if _HEADER.match(line) or line.lstrip().startswith("["):
        return ScenarioError(source, f"(table header, line {lineno})", line.strip(), allowed)
    if kv:
        key = _key_path(kv.group(1))
        field = f"{table}.{key}" if table else key
        return ScenarioError(source, field, kv.group(2).strip(), allowed)
    return ScenarioError(source, f"{table or '(top level)'} (line {lineno})", line.strip(), allowed)


def read_toml(path: str | os.PathLike) -> dict:
    """The raw dict of a TOML file; ScenarioError for a missing file or bad syntax."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")  # a byte-order mark (Windows editors): skipped
    except FileNotFoundError:
        raise ScenarioError(str(p), "(file)", str(p), "file not found") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(
            str(p), "(file)", str(p), f"cannot read a UTF-8 text file: {e}"
        ) from None
    return _loads(text, str(p))


def _loads(text: str, source: str) -> dict:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise _syntax_error(text, source, e) from None


def loads_scenario(text: str, *, source: str = "<string>") -> Scenario:
    """Validate a scenario given as TOML text."""
    return scenario_from_dict(_loads(text, source), source=source)


def load_scenario(path: str | os.PathLike) -> Scenario:
    """Read and validate a scenario file; ScenarioError lists every problem found."""
    return scenario_from_dict(read_toml(path), source=str(path))


# --------------------------------------------------------------------------- writing


def _key(k: str) -> str:
    return k if _BARE_KEY.fullmatch(k) else json.dumps(k, ensure_ascii=False)


def _value(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # shortest round-trip repr; always a valid TOML float
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} {v!r} to TOML")


def _is_array_of_tables(v: object) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)


def _table(path: list[str], d: Mapping, out: list[str], groups: int = 0) -> None:
    """Write table `d` at `path`. groups: levels of `path` that only group tables (a
    parallel mechanism's legs in [clearance.joints.<leg>.<joint>]): not counted for the
    inline depth. Lists of tables ([[mechanism.legs]]) become arrays of tables, their
    items' own tables inline."""
    inline = len(path) - groups + 1 >= INLINE_DEPTH
    arrays = [(k, v) for k, v in d.items() if _is_array_of_tables(v) and not inline and path]
    in_arrays = {k for k, _ in arrays}
    scalars = [
        (k, v)
        for k, v in d.items()
        if (not isinstance(v, Mapping) or inline) and k not in in_arrays
    ]
    tables = [(k, v) for k, v in d.items() if isinstance(v, Mapping) and not inline]
    if path and (scalars or not (tables or arrays)):
        out.append("")
        out.append("[" + ".".join(_key(p) for p in path) + "]")
    out.extend(f"{_key(k)} = {_value(v)}" for k, v in scalars)
    for k, v in tables:
        group = path[-2:] == ["clearance", "joints"] and all(
            isinstance(x, Mapping) for x in v.values()
        )
        _table([*path, k], v, out, groups + group)
    for k, items in arrays:
        for item in items:
            out.append("")
            out.append("[[" + ".".join(_key(p) for p in [*path, k]) + "]]")
            out.extend(f"{_key(a)} = {_value(b)}" for a, b in item.items())


def dumps_toml(d: Mapping) -> str:
    """TOML text of a dict of scalars, lists and tables (deep tables written inline)."""
    out: list[str] = []
    _table([], d, out)
    return "\n".join(out).lstrip("\n") + "\n"


def scenario_to_toml(s: Scenario) -> str:
    """The canonical TOML text of a scenario (loads back to an equal Scenario)."""
    return dumps_toml(scenario_to_dict(s))


# --------------------------------------------------------------------------- shipped files


def default_scenarios() -> tuple[str, ...]:
    """Names of the scenario files shipped in clearance/data."""
    data = importlib.resources.files("clearance") / "data"
    return tuple(sorted(p.name[:-5] for p in data.iterdir() if p.name.endswith(".toml")))


def default_scenario_path(name: str = "ups_upu") -> Path:
    """Path of a shipped scenario file ("ups_upu": 4UPS-UPU, "sps_cu": 4-SPS/CU)."""
    names = default_scenarios()
    if name not in names:
        raise ScenarioError(
            "clearance/data", "name", name, f"unknown shipped scenario; allowed: {names}"
        )
    return Path(os.fspath(importlib.resources.files("clearance") / "data" / f"{name}.toml"))


def _library_dir() -> Path:
    return Path(os.fspath(importlib.resources.files("clearance") / "data" / "library"))


def library() -> dict[str, str]:
    """The library of shipped scenarios built with the parallel-mechanism builder: name ->
    one-line description (its [scenario] description)."""
    out = {}
    for p in sorted(_library_dir().glob("*.toml")):
        d = read_toml(p)
        out[p.stem] = str(d.get("scenario", {}).get("description", ""))
    return out


def library_path(name: str) -> Path:
    """Path of a library scenario (`library()` lists them)."""
    names = tuple(p.stem for p in sorted(_library_dir().glob("*.toml")))
    if name not in names:
        hint = did_you_mean(name, names)
        raise ScenarioError(
            "clearance/data/library", "name", name, f"unknown scenario;{hint} allowed: {names}"
        )
    return _library_dir() / f"{name}.toml"
