"""Checks of single parameter values by kind, with messages naming owner, field and value.

    check_value("Link", "mass", "positive", 2.0)            # -> 2.0
    check_value("Leg", "base", "vector3", [0.4, 0, 0])      # -> (0.4, 0.0, 0.0)
    check_value("Link", "inertia", "inertia3", (1, 1, 3))   # ModelError: triangle inequality

The kinds (`KINDS`) and their "allowed" texts are shared by the parameter sets of the seed
mechanisms (`clearance.mechanisms.params`), the parallel-mechanism builder and the scenario
files, so every layer says the same thing about the same mistake.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping

from clearance.model.errors import ModelError

__all__ = ["KINDS", "check_value"]

# kind -> what is allowed (the text of the error message)
KINDS: dict[str, str] = {
    "positive": "expected a finite number > 0",
    "nonneg": "expected a finite number >= 0",
    "real": "expected a finite real number",
    "vector3": "expected a list of 3 finite numbers",
    "inertia3": (
        "expected 3 principal moments of inertia > 0 (body x, y, z) that satisfy the "
        "triangle inequalities I1 + I2 >= I3 etc."
    ),
    "angles4": "expected a list of 4 finite angles in degrees (legs 1..4), all different",
}


def _is_real(x: object) -> bool:
    return not isinstance(x, bool) and isinstance(x, numbers.Real) and math.isfinite(x)


def _reals(x: object, n: int) -> tuple[float, ...] | None:
    if isinstance(x, (str, bytes, Mapping)) or not isinstance(x, Iterable):
        return None
    xs = list(x)
    if len(xs) != n or not all(_is_real(v) for v in xs):
        return None
    return tuple(float(v) for v in xs)


def check_value(owner: str, name: str, kind: str, value: object, choices=()) -> object:
    """The validated (normalised) value of one parameter, or ModelError."""
    bad = ModelError(owner, name, value, KINDS.get(kind, ""))
    if kind in ("positive", "nonneg", "real"):
        if not _is_real(value):
            raise bad
        v = float(value)  # type: ignore[arg-type]
        if (kind == "positive" and v <= 0.0) or (kind == "nonneg" and v < 0.0):
            raise bad
        return v
    if kind == "vector3":
        v3 = _reals(value, 3)
        if v3 is None:
            raise bad
        return v3
    if kind == "inertia3":
        j = _reals(value, 3)
        if j is None or min(j) <= 0.0:
            raise bad
        tol = 1e-12 * sum(j)
        if any(j[k] > j[(k + 1) % 3] + j[(k + 2) % 3] + tol for k in range(3)):
            raise bad
        return j
    if kind == "angles4":
        a = _reals(value, 4)
        if a is None:
            raise bad
        wrapped = [round(x % 360.0, 9) for x in a]
        if len(set(wrapped)) != 4:
            raise ModelError(owner, name, value, "the 4 hinge angles must be different")
        return a
    if kind == "choice":
        if value not in choices:
            raise ModelError(owner, name, value, f"allowed: {', '.join(map(repr, choices))}")
        return value
    raise ValueError(f"unknown parameter kind {kind!r}")
