"""Study designs: how parameter values are given and combined into cases.

A `[[parameter]]` gives its values as a list (`values`), a range (`range = {start, stop,
num}` or `{start, stop, step}`, `scale = "log"` for geometric spacing) or a sampling
interval (`sample = {min, max, scale}`). Parameters combine as a full-factorial grid;
parameters with the same `zip` label are paired instead (equal lengths); the sampled
parameters are drawn together by `[sampling]` (Latin hypercube or uniform random, n
points, seed) and make one factor of the grid. Parsers report problems with the study
field (`parameter[1].range.num`) and return None for an invalid entry.
"""

from __future__ import annotations

import inspect
import itertools
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from clearance.scenario.errors import MISSING, Problems, did_you_mean

__all__ = [
    "Parameter",
    "canonical_json",
    "Sampling",
    "case_values",
    "parse_parameter",
    "parse_sampling",
]

PARAMETER_KEYS = ("path", "name", "values", "range", "sample", "zip", "scale")
SAMPLING_KEYS = ("method", "n", "seed")
SAMPLING_METHODS = ("lhs", "random")
SCALES = ("linear", "log")


@dataclass(frozen=True)
class Parameter:
    """One varied parameter: the scenario paths it sets (all to the same value) and how its
    values are given. name: its column in tables and plots (default: the path, or the paths
    with the differing segment as '*'). values: explicit or from a range (None if sampled);
    sample: (min, max) if drawn by [sampling]; scale: "linear" or "log" (sampling, ranges and
    plot axes); zip: label of a group of paired parameters."""

    name: str
    paths: tuple[str, ...]
    values: tuple | None = None
    sample: tuple[float, float] | None = None
    scale: str = "linear"
    zip: str | None = None


@dataclass(frozen=True)
class Sampling:
    """Random designs: `method` "lhs" (scipy.stats.qmc.LatinHypercube) or "random"
    (uniform), `n` points, `seed` (same seed, same points)."""

    method: str = "lhs"
    n: int = 10
    seed: int = 0


def canonical_json(obj: object) -> str:
    """JSON with sorted keys; floats by repr (exact), so equal values hash equally."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=True)


def _star_name(paths: Sequence[str]) -> str:
    """Column name of a parameter setting several paths: the segment that differs -> '*'."""
    if len(paths) == 1:
        return paths[0]
    parts = [p.split(".") for p in paths]
    if len({len(p) for p in parts}) == 1:
        diff = [i for i in range(len(parts[0])) if len({p[i] for p in parts}) > 1]
        if len(diff) == 1:
            return ".".join("*" if i == diff[0] else s for i, s in enumerate(parts[0]))
    return "+".join(paths)


def _real(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _clean(v: float) -> float:
    """Range values rounded to 12 significant digits (no 0.30000000000000004 in ids)."""
    return float(f"{v:.12g}")


# --------------------------------------------------------------------------- parsing


def _range(r: object, where: str, scale: str, problems: Problems) -> tuple | None:
    if not isinstance(r, Mapping):
        problems.add(where, r, "expected a table {start, stop, num} or {start, stop, step}")
        return None
    n0 = len(problems)
    for k, v in r.items():
        if k not in ("start", "stop", "num", "step"):
            problems.unknown(f"{where}.{k}", k, v, ("start", "stop", "num", "step"))
    start, stop = r.get("start", MISSING), r.get("stop", MISSING)
    for k, v in (("start", start), ("stop", stop)):
        if not _real(v):
            problems.add(f"{where}.{k}", v, "required: a finite number")
    has_num, has_step = "num" in r, "step" in r
    if has_num == has_step:
        problems.add(where, r, "give exactly one of num (number of values) and step")
    elif has_num and (isinstance(r["num"], bool) or not isinstance(r["num"], int) or r["num"] < 1):
        problems.add(f"{where}.num", r["num"], "expected an integer >= 1")
    elif has_step and (not _real(r["step"]) or r["step"] == 0):
        problems.add(f"{where}.step", r["step"], "expected a finite non-zero number")
    if len(problems) > n0:
        return None
    if scale == "log" and (start <= 0 or stop <= 0 or has_step):
        problems.add(where, r, "scale 'log' needs start > 0, stop > 0 and num (not step)")
        return None
    if has_num:
        num = r["num"]
        if scale == "log":
            vals = np.geomspace(start, stop, num)
        else:
            vals = np.linspace(start, stop, num)
    else:
        step = r["step"]
        count = math.floor((stop - start) / step + 1e-9) + 1
        if count < 1:
            problems.add(f"{where}.step", step, f"no value from {start} towards {stop}")
            return None
        if count > 1_000_000:
            problems.add(f"{where}.step", step, f"{count} values; too many")
            return None
        vals = start + step * np.arange(count)
    return tuple(_clean(float(v)) for v in vals)


def _sample(s: object, where: str, problems: Problems) -> tuple[tuple[float, float], str] | None:
    if not isinstance(s, Mapping):
        problems.add(where, s, "expected a table {min, max, scale}")
        return None
    n0 = len(problems)
    for k, v in s.items():
        if k not in ("min", "max", "scale"):
            problems.unknown(f"{where}.{k}", k, v, ("min", "max", "scale"))
    lo, hi, scale = s.get("min", MISSING), s.get("max", MISSING), s.get("scale", "linear")
    for k, v in (("min", lo), ("max", hi)):
        if not _real(v):
            problems.add(f"{where}.{k}", v, "required: a finite number")
    if scale not in SCALES:
        problems.add(f"{where}.scale", scale, f"allowed: {', '.join(SCALES)}")
    if len(problems) > n0:
        return None
    if not lo < hi:
        problems.add(f"{where}.max", hi, f"expected max > min (= {lo})")
        return None
    if scale == "log" and lo <= 0:
        problems.add(f"{where}.min", lo, "scale 'log' needs min > 0")
        return None
    return (float(lo), float(hi)), scale


def parse_parameter(t: object, i: int, problems: Problems) -> Parameter | None:
    where = f"parameter[{i}]"
    if not isinstance(t, Mapping):
        problems.add(where, t, "expected a table ([[parameter]] with path = ...)")
        return None
    n0 = len(problems)
    for k, v in t.items():
        if k not in PARAMETER_KEYS:
            problems.unknown(f"{where}.{k}", k, v, PARAMETER_KEYS)
    raw = t.get("path", MISSING)
    paths = [raw] if isinstance(raw, str) else raw
    if not isinstance(paths, list) or not paths or not all(isinstance(p, str) for p in paths):
        problems.add(f"{where}.path", raw, "required: a dotted scenario path or a list of them")
        return None
    if len(set(paths)) != len(paths):
        problems.add(f"{where}.path", raw, "the same path is listed twice")
    name = t.get("name", _star_name(paths))
    if not isinstance(name, str) or not name.strip():
        problems.add(f"{where}.name", name, "expected a non-empty string")
    scale = t.get("scale", "linear")
    if scale not in SCALES:
        problems.add(f"{where}.scale", scale, f"allowed: {', '.join(SCALES)}")
        scale = "linear"
    zip_ = t.get("zip")
    if zip_ is not None and not (isinstance(zip_, str) and zip_):
        problems.add(f"{where}.zip", zip_, "expected a group label (string)")
    given = [k for k in ("values", "range", "sample") if k in t]
    if len(given) != 1:
        problems.add(where, given or MISSING, "give exactly one of values, range and sample")
        return None
    values = sample = None
    if "values" in t:
        v = t["values"]
        if not isinstance(v, list) or not v:
            problems.add(f"{where}.values", v, "expected a non-empty list")
        else:
            values = tuple(v)
            dup = [x for k, x in enumerate(v) if canonical_json(x) in map(canonical_json, v[:k])]
            if dup:
                problems.add(f"{where}.values", dup[0], "listed twice (cases must differ)")
    elif "range" in t:
        values = _range(t["range"], f"{where}.range", scale, problems)
    else:
        got = _sample(t["sample"], f"{where}.sample", problems)
        if got is not None:
            sample, scale = got
        if zip_ is not None:
            problems.add(f"{where}.zip", zip_, "sampled parameters are drawn together; no zip")
    if len(problems) > n0:
        return None
    return Parameter(name.strip(), tuple(paths), values, sample, scale, zip_)


def parse_sampling(t: object, problems: Problems) -> Sampling | None:
    if not isinstance(t, Mapping):
        problems.add("sampling", t, "expected a table {method, n, seed}")
        return None
    n0 = len(problems)
    for k, v in t.items():
        if k not in SAMPLING_KEYS:
            problems.unknown(f"sampling.{k}", k, v, SAMPLING_KEYS)
    method, n, seed = t.get("method", "lhs"), t.get("n", MISSING), t.get("seed", MISSING)
    if method not in SAMPLING_METHODS:
        hint = did_you_mean(method, SAMPLING_METHODS)
        problems.add("sampling.method", method, f"{hint} allowed: {', '.join(SAMPLING_METHODS)}")
    for k, v in (("n", n), ("seed", seed)):
        low = 1 if k == "n" else 0
        if isinstance(v, bool) or not isinstance(v, int) or v < low:
            problems.add(f"sampling.{k}", v, f"required: an integer >= {low}")
    return Sampling(method, n, seed) if len(problems) == n0 else None


def _unit_samples(s: Sampling, d: int) -> np.ndarray:
    """(n, d) points in [0, 1): Latin hypercube or uniform random, reproducible by seed."""
    if s.method == "random":
        return np.random.default_rng(s.seed).random((s.n, d))
    from scipy.stats import qmc

    key = "rng" if "rng" in inspect.signature(qmc.LatinHypercube).parameters else "seed"
    return qmc.LatinHypercube(d, **{key: s.seed}).random(s.n)


def case_values(
    params: Sequence[Parameter], sampling: Sampling | None, problems: Problems
) -> list[dict]:
    """Parameter values of every case (name -> value), in a stable order: one factor per
    ungrouped parameter, per zip group, and one for all sampled parameters."""
    factors: list[list[dict]] = []
    seen_zip: set[str] = set()
    sampled = [p for p in params if p.sample is not None]
    for p in params:
        if p.sample is not None:
            if p is sampled[0] and sampling is not None:
                u = _unit_samples(sampling, len(sampled))
                cols = []
                for k, q in enumerate(sampled):
                    lo, hi = q.sample  # type: ignore[misc]
                    if q.scale == "log":
                        col = np.exp(np.log(lo) + u[:, k] * (np.log(hi) - np.log(lo)))
                    else:
                        col = lo + u[:, k] * (hi - lo)
                    cols.append(np.clip(col, lo, hi))
                factors.append(
                    [
                        {q.name: float(c[i]) for q, c in zip(sampled, cols, strict=True)}
                        for i in range(len(u))
                    ]
                )
            continue
        if p.zip is None:
            factors.append([{p.name: v} for v in p.values])  # type: ignore[union-attr]
            continue
        if p.zip in seen_zip:
            continue
        seen_zip.add(p.zip)
        group = [q for q in params if q.zip == p.zip]
        lengths = {q.name: len(q.values) for q in group}  # type: ignore[arg-type]
        if len(set(lengths.values())) > 1:
            i = params.index(p)
            problems.add(
                f"parameter[{i}].zip",
                p.zip,
                f"paired parameters need the same number of values; got {lengths}",
            )
            continue
        factors.append(
            [
                {q.name: q.values[k] for q in group}  # type: ignore[index]
                for k in range(len(p.values))  # type: ignore[arg-type]
            ]
        )
    return [{k: v for f in combo for k, v in f.items()} for combo in itertools.product(*factors)]
