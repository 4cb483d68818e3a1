"""Time functions f(t) for drivers and applied forces, with exact f_dot and f_ddot.

Time t is in seconds; f carries the units of whatever it drives (m, rad, N, N m), so f_dot is
in those units per second and f_ddot per second squared. Every function is an immutable,
hashable frozen dataclass. `derivatives` is analytic (no finite differences) and `encode`
gives the flat (kind, float64 parameters) form evaluated by the compiled
`clearance.kinematics.timefn` (layouts documented there and on `FnKind`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.polynomial.polynomial as npoly
from scipy.interpolate import BPoly, CubicSpline, PPoly

from clearance.kinds import RAMP_PROFILES, FnKind
from clearance.model.errors import ModelError, finite_real

SPLINE_BC_TYPES = ("not-a-knot", "natural", "clamped")


def _real(owner: str, name: str, x: object) -> float:
    # bool is an int subclass, but True as a displacement is almost surely a mistake.
    if not finite_real(x):
        raise ModelError(owner, name, x, "expected a finite real number")
    return float(x)


def _reals(owner: str, name: str, xs: object, min_len: int) -> tuple[float, ...]:
    if isinstance(xs, (str, bytes)) or not isinstance(xs, Iterable):
        raise ModelError(owner, name, xs, "expected a sequence of finite real numbers")
    out = tuple(_real(owner, f"{name}[{i}]", x) for i, x in enumerate(xs))
    if len(out) < min_len:
        raise ModelError(owner, name, xs, f"expected at least {min_len} values")
    return out


@dataclass(frozen=True)
class TimeFunction:
    """Base class of time functions used by drivers and applied forces."""

    kind: ClassVar[FnKind]

    def derivatives(self, t: float) -> tuple[float, float, float]:
        """(f, f_dot, f_ddot) at time t [s], exact."""
        raise NotImplementedError

    def __call__(self, t: float) -> float:
        return self.derivatives(t)[0]

    def evaluate(self, t: object) -> np.ndarray:
        """(n, 3) array of (f, f_dot, f_ddot) at the times t (n,), the values of
        `derivatives` (vectorised where the kind allows, e.g. splines; else a loop)."""
        t = np.asarray(t, dtype=float).reshape(-1)
        return np.array([self.derivatives(float(tk)) for tk in t], dtype=float).reshape(-1, 3)

    def _leaf_data(self) -> np.ndarray:
        raise NotImplementedError

    def _terms(self) -> tuple[float, tuple[tuple[float, TimeFunction], ...]]:
        """self = offset + sum weight * leaf, with leaves of a non-SUM kind."""
        return 0.0, ((1.0, self),)

    def encode(self) -> tuple[int, np.ndarray]:
        """(FnKind code, float64 parameter array) for the compiled evaluator."""
        offset, terms = self._terms()
        if offset == 0.0 and len(terms) == 1 and terms[0][0] == 1.0:
            leaf = terms[0][1]
            return int(leaf.kind), np.asarray(leaf._leaf_data(), dtype=np.float64)
        parts = [np.array([offset, len(terms)], dtype=np.float64)]
        for weight, leaf in terms:
            data = np.asarray(leaf._leaf_data(), dtype=np.float64)
            parts += [np.array([int(leaf.kind), weight, data.size], dtype=np.float64), data]
        return int(FnKind.SUM), np.concatenate(parts)


@dataclass(frozen=True)
class Constant(TimeFunction):
    """f(t) = value."""

    value: float = 0.0
    kind: ClassVar[FnKind] = FnKind.CONSTANT

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _real("Constant", "value", self.value))

    def derivatives(self, t: float) -> tuple[float, float, float]:
        return (self.value, 0.0, 0.0)

    def _leaf_data(self) -> np.ndarray:
        return np.array([self.value])


@dataclass(frozen=True)
class Polynomial(TimeFunction):
    """f(t) = sum_k c_k (t - t0)^k, coefficients in ascending order (c_k in units / s^k)."""

    coefficients: tuple[float, ...]
    t0: float = 0.0
    kind: ClassVar[FnKind] = FnKind.POLYNOMIAL

    def __post_init__(self) -> None:
        c = _reals("Polynomial", "coefficients", self.coefficients, 1)
        object.__setattr__(self, "coefficients", c)
        object.__setattr__(self, "t0", _real("Polynomial", "t0", self.t0))

    def derivatives(self, t: float) -> tuple[float, float, float]:
        u, c = t - self.t0, np.array(self.coefficients)
        d = [float(npoly.polyval(u, npoly.polyder(c, k))) for k in range(3)]
        return d[0], d[1], d[2]

    def _leaf_data(self) -> np.ndarray:
        return np.array((self.t0, *self.coefficients))


@dataclass(frozen=True)
class Sinusoid(TimeFunction):
    """f(t) = offset + amplitude * sin(omega t + phase); omega in rad/s, phase in rad.

    The rest-to-rest shape (1 - cos(pi t)) / 2 is Sinusoid(-0.5, pi, pi / 2, 0.5).
    """

    amplitude: float
    omega: float
    phase: float = 0.0
    offset: float = 0.0
    kind: ClassVar[FnKind] = FnKind.SINUSOID

    def __post_init__(self) -> None:
        for name in ("amplitude", "omega", "phase", "offset"):
            object.__setattr__(self, name, _real("Sinusoid", name, getattr(self, name)))

    def derivatives(self, t: float) -> tuple[float, float, float]:
        a, w = self.amplitude, self.omega
        s, c = math.sin(w * t + self.phase), math.cos(w * t + self.phase)
        return self.offset + a * s, a * w * c, -a * w * w * s

    def _leaf_data(self) -> np.ndarray:
        return np.array([self.amplitude, self.omega, self.phase, self.offset])


def _ramp_profile(code: int, s: float) -> tuple[float, float, float]:
    """Normalised rest-to-rest profile p(s), p'(s), p''(s) for s in [0, 1] (dimensionless)."""
    if code == 0:  # quintic: p' = p'' = 0 at both ends
        return (
            s**3 * (10.0 - 15.0 * s + 6.0 * s * s),
            30.0 * (s * (1.0 - s)) ** 2,
            60.0 * s * (1.0 - s) * (1.0 - 2.0 * s),
        )
    if code == 1:  # cycloidal: p' = p'' = 0 at both ends
        w = 2.0 * math.pi
        return s - math.sin(w * s) / w, 1.0 - math.cos(w * s), w * math.sin(w * s)
    # cosine: p' = 0 at both ends, p'' jumps to +-pi^2/2 there
    return (
        (1.0 - math.cos(math.pi * s)) / 2.0,
        math.pi / 2.0 * math.sin(math.pi * s),
        math.pi**2 / 2.0 * math.cos(math.pi * s),
    )


@dataclass(frozen=True)
class Ramp(TimeFunction):
    """Rest-to-rest transition from start_value to end_value over [t_start, t_end] (s).

    Constant start_value before t_start and end_value after t_end. With s = (t - t_start) /
    (t_end - t_start): "quintic" 10s^3 - 15s^4 + 6s^5 and "cycloidal" s - sin(2 pi s)/(2 pi)
    have zero velocity and acceleration at both ends; "cosine" (1 - cos(pi s))/2 has zero
    velocity there but an acceleration step of (pi^2 / 2) (end - start) / (t_end - t_start)^2.
    """

    start_value: float
    end_value: float
    t_start: float
    t_end: float
    profile: str = "quintic"
    kind: ClassVar[FnKind] = FnKind.RAMP

    def __post_init__(self) -> None:
        for name in ("start_value", "end_value", "t_start", "t_end"):
            object.__setattr__(self, name, _real("Ramp", name, getattr(self, name)))
        if not self.t_end > self.t_start:
            raise ModelError("Ramp", "t_end", self.t_end, f"must exceed t_start={self.t_start}")
        if self.profile not in RAMP_PROFILES:
            raise ModelError("Ramp", "profile", self.profile, f"expected one of {RAMP_PROFILES}")

    def derivatives(self, t: float) -> tuple[float, float, float]:
        if t < self.t_start:
            return self.start_value, 0.0, 0.0
        if t > self.t_end:
            return self.end_value, 0.0, 0.0
        dur, rise = self.t_end - self.t_start, self.end_value - self.start_value
        p, dp, ddp = _ramp_profile(RAMP_PROFILES.index(self.profile), (t - self.t_start) / dur)
        return self.start_value + rise * p, rise * dp / dur, rise * ddp / (dur * dur)

    def _leaf_data(self) -> np.ndarray:
        code = RAMP_PROFILES.index(self.profile)
        return np.array([self.start_value, self.end_value, self.t_start, self.t_end, code])


@dataclass(frozen=True)
class Tabulated(TimeFunction):
    """Cubic-spline interpolation (scipy CubicSpline) of values at strictly increasing times.

    bc_type: "not-a-knot", "natural" (f_ddot = 0 at the ends) or "clamped" (f_dot = 0 at the
    ends). Outside [times[0], times[-1]] the end value is held with zero derivatives, so f_dot
    and f_ddot jump there unless the spline already has them zero at that end.
    """

    times: tuple[float, ...]
    values: tuple[float, ...]
    bc_type: str = "not-a-knot"
    kind: ClassVar[FnKind] = FnKind.TABULATED
    _spline: Any = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        x = _reals("Tabulated", "times", self.times, 2)
        y = _reals("Tabulated", "values", self.values, 2)
        if len(y) != len(x):
            raise ModelError("Tabulated", "values", self.values, f"expected {len(x)} values")
        for i in range(1, len(x)):
            if not x[i] > x[i - 1]:
                raise ModelError("Tabulated", f"times[{i}]", x[i], "times must strictly increase")
        if self.bc_type not in SPLINE_BC_TYPES:
            raise ModelError("Tabulated", "bc_type", self.bc_type, f"one of {SPLINE_BC_TYPES}")
        object.__setattr__(self, "times", x)
        object.__setattr__(self, "values", y)
        object.__setattr__(self, "_spline", CubicSpline(x, y, bc_type=self.bc_type))

    def derivatives(self, t: float) -> tuple[float, float, float]:
        tc = min(max(t, self.times[0]), self.times[-1])
        f = float(self._spline(tc))
        if tc != t:
            return f, 0.0, 0.0
        return f, float(self._spline(tc, 1)), float(self._spline(tc, 2))

    def evaluate(self, t: object) -> np.ndarray:
        return _spline_evaluate(self._spline, self.times, t)

    def _leaf_data(self) -> np.ndarray:
        cs = self._spline  # cs.c[k, i] multiplies (t - x_i)^(3 - k)
        return np.concatenate([[cs.c.shape[1]], cs.x, cs.c.T.ravel()])


@dataclass(frozen=True)
class HermiteSpline(TimeFunction):
    """Piecewise Hermite interpolation of values and derivatives at strictly increasing times.

    On each interval [t_i, t_(i+1)] f is the polynomial of degree 5 that takes the given
    value, first and second derivative at both ends (degree 3 and values plus first
    derivatives only if d2 is None), so f is C2 (C1) and reproduces the knot data exactly up
    to rounding. Built with scipy `BPoly.from_derivatives` and converted to the local power
    basis (`PPoly.from_bernstein_basis`); encoded as the general FnKind.PPOLY (any degree).
    Units: values in the units of f, d1 per second, d2 per second squared.

    Outside [times[0], times[-1]] the end value is held with zero derivatives (as for
    `Tabulated`), so f_dot and f_ddot jump there unless the data already end at rest.
    Used for the actuator histories of the inverse kinematics (physics.md e.2 step 5).
    """

    times: tuple[float, ...]
    values: tuple[float, ...]
    d1: tuple[float, ...]
    d2: tuple[float, ...] | None = None
    kind: ClassVar[FnKind] = FnKind.PPOLY
    _pp: Any = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        who = "HermiteSpline"
        x = _reals(who, "times", self.times, 2)
        for i in range(1, len(x)):
            if not x[i] > x[i - 1]:
                raise ModelError(who, f"times[{i}]", x[i], "times must strictly increase")
        cols = [_reals(who, "values", self.values, 2), _reals(who, "d1", self.d1, 2)]
        if self.d2 is not None:
            cols.append(_reals(who, "d2", self.d2, 2))
        for name, col in zip(("values", "d1", "d2"), cols, strict=False):
            if len(col) != len(x):
                raise ModelError(who, name, getattr(self, name), f"expected {len(x)} values")
        object.__setattr__(self, "times", x)
        object.__setattr__(self, "values", cols[0])
        object.__setattr__(self, "d1", cols[1])
        object.__setattr__(self, "d2", cols[2] if self.d2 is not None else None)
        bp = BPoly.from_derivatives(np.array(x), np.column_stack(cols))
        object.__setattr__(self, "_pp", PPoly.from_bernstein_basis(bp))

    @property
    def degree(self) -> int:
        return int(self._pp.c.shape[0]) - 1

    def derivatives(self, t: float) -> tuple[float, float, float]:
        tc = min(max(t, self.times[0]), self.times[-1])
        f = float(self._pp(tc))
        if tc != t:
            return f, 0.0, 0.0
        return f, float(self._pp(tc, 1)), float(self._pp(tc, 2))

    def evaluate(self, t: object) -> np.ndarray:
        return _spline_evaluate(self._pp, self.times, t)

    def _leaf_data(self) -> np.ndarray:
        pp = self._pp  # pp.c[j, i] multiplies (t - x_i)^(k - j)
        m, k = pp.c.shape[1], pp.c.shape[0] - 1
        return np.concatenate([[m, k], pp.x, pp.c.T.ravel()])


@dataclass(frozen=True)
class Scaled(TimeFunction):
    """f(t) = factor * function(t) + offset."""

    function: TimeFunction
    factor: float = 1.0
    offset: float = 0.0

    def __post_init__(self) -> None:
        fn = as_function(self.function, owner="Scaled", field="function")
        object.__setattr__(self, "function", fn)
        object.__setattr__(self, "factor", _real("Scaled", "factor", self.factor))
        object.__setattr__(self, "offset", _real("Scaled", "offset", self.offset))

    def derivatives(self, t: float) -> tuple[float, float, float]:
        f, fd, fdd = self.function.derivatives(t)
        return self.factor * f + self.offset, self.factor * fd, self.factor * fdd

    def evaluate(self, t: object) -> np.ndarray:
        out = self.function.evaluate(t) * self.factor
        out[:, 0] += self.offset
        return out

    def _terms(self) -> tuple[float, tuple[tuple[float, TimeFunction], ...]]:
        off, terms = self.function._terms()
        k = self.factor
        return k * off + self.offset, tuple((k * w, leaf) for w, leaf in terms)


@dataclass(frozen=True)
class Sum(TimeFunction):
    """f(t) = sum of functions(t); numbers in `functions` become Constants."""

    functions: tuple[TimeFunction, ...]

    def __post_init__(self) -> None:
        fs = self.functions
        if isinstance(fs, (str, bytes)) or not isinstance(fs, Iterable):
            raise ModelError("Sum", "functions", fs, "expected a sequence of time functions")
        fs = tuple(as_function(f, owner="Sum", field=f"functions[{i}]") for i, f in enumerate(fs))
        if not fs:
            raise ModelError("Sum", "functions", self.functions, "expected at least one function")
        object.__setattr__(self, "functions", fs)

    def derivatives(self, t: float) -> tuple[float, float, float]:
        f = fd = fdd = 0.0
        for fn in self.functions:
            a, b, c = fn.derivatives(t)
            f, fd, fdd = f + a, fd + b, fdd + c
        return f, fd, fdd

    def evaluate(self, t: object) -> np.ndarray:
        out = self.functions[0].evaluate(t)
        for fn in self.functions[1:]:
            out = out + fn.evaluate(t)
        return out

    def _terms(self) -> tuple[float, tuple[tuple[float, TimeFunction], ...]]:
        parts = [f._terms() for f in self.functions]
        return sum(p[0] for p in parts), tuple(t for p in parts for t in p[1])


def _spline_evaluate(pp: Any, times: tuple[float, ...], t: object) -> np.ndarray:
    """(n, 3) values and two derivatives of a piecewise polynomial at t, the end values
    held with zero derivatives outside [times[0], times[-1]] (as `derivatives` does)."""
    t = np.asarray(t, dtype=float).reshape(-1)
    tc = np.clip(t, times[0], times[-1])
    inside = tc == t
    out = np.zeros((t.size, 3))
    out[:, 0] = pp(tc)
    out[:, 1] = np.where(inside, pp(tc, 1), 0.0)
    out[:, 2] = np.where(inside, pp(tc, 2), 0.0)
    return out


def as_function(x: object, *, owner: str = "function", field: str = "function") -> TimeFunction:
    """Pass a TimeFunction through; turn a finite real number into a Constant."""
    if isinstance(x, TimeFunction):
        return x
    if isinstance(x, numbers.Real) and not isinstance(x, bool) and math.isfinite(x):
        return Constant(float(x))
    raise ModelError(owner, field, x, "expected a finite number or a TimeFunction")
