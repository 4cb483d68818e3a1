"""Platform trajectory shapes of scenario files: their tables, time functions and IK samples.

Every shape gives each pose coordinate as home + a displacement d(t) (d(0) = 0 for the
shapes that start at rest):

* "rest-to-rest" / "sin": d = amplitude g(t), g = (1 - cos(2 pi t / period)) / 2 or
  sin(2 pi t / period) ([trajectory.amplitude]);
* "periodic": d = sum_k a_k sin(2 pi t / T_k + phi_k), per coordinate one sinusoid or a
  list ([trajectory.periodic]: `x = { amplitude, period, phase }`), for steady-state
  studies;
* "via-points": a quintic spline through the points, at rest (zero velocity and
  acceleration) at the first and the last one, held after it ([trajectory.via_points]:
  `t = [...]`, `x = [...]`, ...);
* "table": a cubic spline (not-a-knot) through tabulated values ([trajectory.table]:
  `file = "motion.csv"` next to the scenario, header `t,x,z,...`, or the columns inline);
  the table must cover [0, duration].

The inverse kinematics samples the trajectory (`ik_times`): every IK_SPACING seconds, at
least IK_PER_PERIOD times per period of a periodic shape, and at every via point and table
row, so that the quintic drives through its samples follow the motion.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np
from scipy.interpolate import make_interp_spline

from clearance.model.functions import (
    Constant,
    HermiteSpline,
    Sinusoid,
    Sum,
    Tabulated,
    TimeFunction,
)
from clearance.scenario.errors import MISSING, Problems

__all__ = [
    "HARMONIC_KEYS",
    "IK_PER_PERIOD",
    "IK_SPACING",
    "MAX_IK_POSES",
    "ik_times",
    "parse_harmonics",
    "parse_samples",
    "pose_function",
]

# inverse kinematics samples (run_scenario): every IK_SPACING seconds, and at least
# IK_PER_PERIOD per period of the trajectory; the drives are quintic Hermite splines
# through them (errors ~1e-11 m at the shipped 100 per period; ~(2 pi / 50)^6 = 4e-6 of
# the amplitude at 50). PROPOSED. A trajectory that needs more than MAX_IK_POSES samples is
# refused.
IK_SPACING = 0.02  # [s]
IK_PER_PERIOD = 50
MAX_IK_POSES = 10_000  # ~4 ms per pose on the project machine: ~40 s
HARMONIC_KEYS = ("amplitude", "period", "phase")


def _number(v: object) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v)


def parse_harmonics(
    t: object,
    units: Mapping[str, str],
    default_period: float,
    max_amplitude: Mapping[str, float],
    problems: Problems,
) -> dict[str, tuple[tuple[float, float, float], ...]] | None:
    """[trajectory.periodic]: coordinate -> ((amplitude, period, phase), ...)."""
    path = "trajectory.periodic"
    if not isinstance(t, dict):
        problems.add(path, t, "expected a table: x = { amplitude = .., period = .., phase = .. }")
        return None
    n0, out = len(problems), {}
    for coord, v in t.items():
        p = f"{path}.{coord}"
        if coord not in units:
            problems.unknown(p, coord, v, list(units))
            continue
        items = v if isinstance(v, list) else [v]
        harm = []
        for i, h in enumerate(items):
            q = f"{p}[{i}]" if isinstance(v, list) else p
            if not isinstance(h, dict):
                problems.add(q, h, "expected { amplitude = .., period = .., phase = .. }")
                continue
            for k in h:
                if k not in HARMONIC_KEYS:
                    problems.unknown(f"{q}.{k}", k, h[k], HARMONIC_KEYS)
            a = h.get("amplitude", MISSING)
            per = h.get("period", default_period)
            ph = h.get("phase", 0.0)
            unit = units[coord]
            if a is MISSING:
                problems.add(f"{q}.amplitude", a, f"required: the amplitude [{unit}]")
            elif not _number(a) or abs(a) > max_amplitude[unit]:
                problems.add(
                    f"{q}.amplitude", a, f"expected a finite number, |a| <= {max_amplitude[unit]:g}"
                )
            if not _number(per) or per <= 0:
                problems.add(f"{q}.period", per, "expected a finite number > 0 [s]")
            if not _number(ph):
                problems.add(f"{q}.phase", ph, "expected a finite number [rad]")
            if len(problems) == n0:
                harm.append((float(a), float(per), float(ph)))
        out[coord] = tuple(harm)
    return out if len(problems) == n0 else None


def _read_csv(path: Path, field: str, problems: Problems) -> dict | None:
    """Columns of a CSV table (a header row of names, then numbers; '#' comments)."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as e:
        problems.add(field, str(path), f"cannot read the table: {e.strerror or e}")
        return None
    rows = [
        r for r in csv.reader(ln for ln in text.splitlines() if not ln.lstrip().startswith("#"))
    ]
    rows = [[c.strip() for c in r] for r in rows if any(c.strip() for c in r)]
    if len(rows) < 3:
        problems.add(field, str(path), "expected a header row (t, x, ...) and at least 2 rows")
        return None
    head = rows[0]
    cols: dict[str, list] = {h: [] for h in head}
    if len(cols) != len(head):
        problems.add(field, str(path), f"column names repeat in the header {head}")
        return None
    for i, r in enumerate(rows[1:], start=2):
        if len(r) != len(head):
            problems.add(field, str(path), f"row {i} has {len(r)} values for {len(head)} columns")
            return None
        for h, c in zip(head, r, strict=True):
            try:
                cols[h].append(float(c))
            except ValueError:
                problems.add(field, str(path), f"row {i}, column '{h}': {c!r} is not a number")
                return None
    return cols


def parse_samples(
    t: object,
    path: str,
    units: Mapping[str, str],
    *,
    duration: float,
    table: bool,
    base_dir: Path | None,
    max_amplitude: Mapping[str, float],
    problems: Problems,
) -> dict[str, tuple[float, ...]] | None:
    """[trajectory.via_points] / [trajectory.table]: {"t": times, coordinate: values}."""
    if not isinstance(t, dict):
        problems.add(path, t, "expected a table: t = [...], x = [...], ...")
        return None
    n0 = len(problems)
    cols: dict = {}
    if table and "file" in t:
        extra = [k for k in t if k != "file"]
        if extra:
            problems.add(f"{path}.{extra[0]}", t[extra[0]], "give the file or the columns")
            return None
        f = t["file"]
        if not isinstance(f, str) or not f:
            problems.add(f"{path}.file", f, "expected a file name (CSV, next to the scenario)")
            return None
        p = Path(f)
        if not p.is_absolute() and base_dir is not None:
            p = base_dir / p
        read = _read_csv(p, f"{path}.file", problems)
        if read is None:
            return None
        cols = read
    else:
        cols = dict(t)
    keys = ("t", *units)
    for k in cols:
        if k not in keys:
            problems.unknown(f"{path}.{k}", k, cols[k], keys)
    if "t" not in cols:
        problems.add(f"{path}.t", MISSING, "required: the times [s]")
    if len(problems) > n0:
        return None
    times = cols["t"]
    if not isinstance(times, list) or len(times) < 2 or not all(_number(x) for x in times):
        problems.add(f"{path}.t", times, "expected a list of at least 2 finite times [s]")
        return None
    if any(b <= a for a, b in zip(times, times[1:], strict=False)):
        problems.add(f"{path}.t", times[:8], "times must strictly increase")
    if table:
        if times[0] > 0.0 or times[-1] < duration:
            problems.add(
                f"{path}.t",
                [times[0], times[-1]],
                f"the table must cover [0, duration = {duration:g}] s",
            )
    elif times[0] != 0.0:
        problems.add(f"{path}.t", times[0], "the first via point is at t = 0 (the home pose)")
    out: dict[str, tuple[float, ...]] = {"t": tuple(float(x) for x in times)}
    for k, v in cols.items():
        if k == "t" or k not in units:
            continue
        unit = units[k]
        if not isinstance(v, list) or len(v) != len(times) or not all(_number(x) for x in v):
            problems.add(f"{path}.{k}", v, f"expected {len(times)} finite numbers [{unit}]")
        elif max(abs(x) for x in v) > max_amplitude[unit]:
            problems.add(f"{path}.{k}", v, f"expected |values| <= {max_amplitude[unit]:g} {unit}")
        else:
            out[k] = tuple(float(x) for x in v)
    return out if len(problems) == n0 else None


def pose_function(spec, coord: str, home: float) -> TimeFunction:
    """home + d(t) of one coordinate for a trajectory of shape periodic, via-points or
    table (`spec`: a TrajectorySpec)."""
    shape = spec.shape.value
    if shape == "periodic":
        harm = (spec.harmonics or {}).get(coord, ())
        if not harm:
            return Constant(home)
        fns = [Sinusoid(a, 2.0 * math.pi / per, ph, 0.0) for a, per, ph in harm]
        return Sum((Constant(home), *fns))
    samples = spec.samples or {}
    if coord not in samples:
        return Constant(home)
    t = np.array(samples["t"])
    y = home + np.array(samples[coord])
    if shape == "table":
        return Tabulated(tuple(t), tuple(y), "not-a-knot")
    rest = [(1, 0.0), (2, 0.0)]  # via points: quintic, at rest at both ends (C4 inside)
    sp = make_interp_spline(t, y, k=5, bc_type=(rest, rest))
    return HermiteSpline(tuple(t), tuple(sp(t)), tuple(sp(t, 1)), tuple(sp(t, 2)))


def time_scale(spec) -> float:
    """The shortest time scale of a trajectory [s]: its (shortest) period, or the shortest
    interval between via points or table rows."""
    shape = spec.shape.value
    if shape == "periodic":
        pers = [h[1] for hs in (spec.harmonics or {}).values() for h in hs]
        return min(pers) if pers else spec.period
    if shape in ("via-points", "table"):
        return float(np.min(np.diff(spec.samples["t"])))
    return spec.period


def ik_times(spec) -> np.ndarray:
    """Sample times of the inverse kinematics over [0, duration] (see the module doc)."""
    T = spec.duration
    shape = spec.shape.value
    if shape in ("via-points", "table"):
        base = np.linspace(0.0, T, ik_count(T, math.inf))
        knots = np.array(spec.samples["t"])
        knots = knots[(knots > 0.0) & (knots < T)]
        return np.union1d(base, knots)
    return np.linspace(0.0, T, ik_count(T, time_scale(spec)))


def ik_count(duration: float, period: float) -> int:
    """Evenly spaced IK samples over a duration for a motion of this period."""
    spacing = min(IK_SPACING, period / IK_PER_PERIOD)
    n = duration / spacing
    return max(2, int(round(n)) + 1) if n < 1e15 else 10**15
