"""Compiled evaluation of encoded time functions f(t), f_dot, f_ddot (t in s).

`clearance.compile.functions.encode_functions` flattens TimeFunctions into three arrays:
fn_kind[k] (FnKind code), fn_ptr[k] : fn_ptr[k + 1] (the slice of fn_data holding function
k's parameters) and fn_data.
Per-kind layouts (see FnKind):

    CONSTANT    [value]
    POLYNOMIAL  [t0, c_0, ..., c_n]                    f = sum c_k (t - t0)^k
    SINUSOID    [amplitude, omega, phase, offset]
    RAMP        [start_value, end_value, t_start, t_end, profile]  0 quintic, 1 cycloidal,
                                                                   2 cosine
    TABULATED   [m, x_0..x_m, (c3, c2, c1, c0) for each of the m segments]
                f = c3 u^3 + c2 u^2 + c1 u + c0 with u = t - x_i on [x_i, x_{i+1}]; the end
                value is held with zero derivatives outside [x_0, x_m]
    PPOLY       [m, k, x_0..x_m, (c_k, ..., c_0) for each of the m segments]
                f = sum c_j u^j (degree k) with u = t - x_i on [x_i, x_{i+1}]; the end
                value is held with zero derivatives outside [x_0, x_m] (HermiteSpline)
    SUM         [offset, n_terms, (kind, weight, length, leaf data) per term]
                f = offset + sum weight * leaf(t); leaves are never SUM

The evaluators are plain Python under NUMBA_DISABLE_JIT=1.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.kinds import FnKind

# Plain ints: numba freezes module globals as compile-time constants.
_CONSTANT = int(FnKind.CONSTANT)
_POLYNOMIAL = int(FnKind.POLYNOMIAL)
_SINUSOID = int(FnKind.SINUSOID)
_RAMP = int(FnKind.RAMP)
_TABULATED = int(FnKind.TABULATED)
_SUM = int(FnKind.SUM)
_PPOLY = int(FnKind.PPOLY)


@njit(cache=True, inline="always")
def _segment(data: np.ndarray, xb: int, m: int, t: float):
    """(tc, i): t clamped to the breakpoints data[xb:xb+m+1], and the largest segment i in
    [0, m-1] with x_i <= tc (scipy's convention at breakpoints), by bisection."""
    tc = min(max(t, data[xb]), data[xb + m])
    lo, hi = 0, m - 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if data[xb + mid] <= tc:
            lo = mid
        else:
            hi = mid - 1
    return tc, lo


@njit(cache=True)
def _eval_leaf(kind: int, data: np.ndarray, start: int, stop: int, t: float):
    if kind == _CONSTANT:
        return data[start], 0.0, 0.0
    if kind == _POLYNOMIAL:
        # Horner for p, p', p'' together; each update uses the previous (higher) partials.
        u = t - data[start]
        f = fd = fdd = 0.0
        for j in range(stop - 1, start, -1):
            fdd = fdd * u + 2.0 * fd
            fd = fd * u + f
            f = f * u + data[j]
        return f, fd, fdd
    if kind == _SINUSOID:
        a, w = data[start], data[start + 1]
        arg = w * t + data[start + 2]
        s, c = math.sin(arg), math.cos(arg)
        return data[start + 3] + a * s, a * w * c, -a * w * w * s
    if kind == _RAMP:
        y0, y1, t0, t1 = data[start], data[start + 1], data[start + 2], data[start + 3]
        if t < t0:
            return y0, 0.0, 0.0
        if t > t1:
            return y1, 0.0, 0.0
        code = int(data[start + 4])
        dur = t1 - t0
        s = (t - t0) / dur
        if code == 0:
            p = s**3 * (10.0 - 15.0 * s + 6.0 * s * s)
            dp = 30.0 * (s * (1.0 - s)) ** 2
            ddp = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)
        elif code == 1:
            w = 2.0 * math.pi
            p = s - math.sin(w * s) / w
            dp = 1.0 - math.cos(w * s)
            ddp = w * math.sin(w * s)
        else:
            p = (1.0 - math.cos(math.pi * s)) / 2.0
            dp = math.pi / 2.0 * math.sin(math.pi * s)
            ddp = math.pi**2 / 2.0 * math.cos(math.pi * s)
        rise = y1 - y0
        return y0 + rise * p, rise * dp / dur, rise * ddp / (dur * dur)
    if kind == _TABULATED:
        m = int(data[start])
        xb = start + 1  # breakpoints x_0..x_m
        cb = xb + m + 1  # coefficients, 4 per segment
        tc, lo = _segment(data, xb, m, t)
        u = tc - data[xb + lo]
        c3, c2, c1, c0 = (
            data[cb + 4 * lo],
            data[cb + 4 * lo + 1],
            data[cb + 4 * lo + 2],
            data[cb + 4 * lo + 3],
        )
        f = ((c3 * u + c2) * u + c1) * u + c0
        if tc != t:
            return f, 0.0, 0.0
        return f, (3.0 * c3 * u + 2.0 * c2) * u + c1, 6.0 * c3 * u + 2.0 * c2
    if kind == _PPOLY:
        m = int(data[start])
        k = int(data[start + 1])
        xb = start + 2  # breakpoints x_0..x_m
        cb = xb + m + 1  # coefficients, k + 1 per segment, highest power first
        tc, lo = _segment(data, xb, m, t)
        u = tc - data[xb + lo]
        f = fd = fdd = 0.0
        c0 = cb + (k + 1) * lo
        for j in range(c0, c0 + k + 1):  # Horner for f, f', f'' together
            fdd = fdd * u + 2.0 * fd
            fd = fd * u + f
            f = f * u + data[j]
        if tc != t:
            return f, 0.0, 0.0
        return f, fd, fdd
    raise ValueError("unknown time-function kind")


@njit(cache=True)
def eval_timefn(kind: int, data: np.ndarray, start: int, stop: int, t: float):
    """(f, f_dot, f_ddot) at t [s] of the function encoded as kind, data[start:stop]."""
    if kind != _SUM:
        return _eval_leaf(kind, data, start, stop, t)
    f, fd, fdd = data[start], 0.0, 0.0
    p = start + 2
    for _ in range(int(data[start + 1])):
        size = int(data[p + 2])
        a, b, c = _eval_leaf(int(data[p]), data, p + 3, p + 3 + size, t)
        w = data[p + 1]
        f += w * a
        fd += w * b
        fdd += w * c
        p += 3 + size
    return f, fd, fdd


@njit(cache=True)
def eval_all(
    fn_kind: np.ndarray, fn_ptr: np.ndarray, fn_data: np.ndarray, t: float, fval: np.ndarray
) -> None:
    """Write fval[k] = (f, f_dot, f_ddot) at t [s] for every encoded function k (no allocation)."""
    for k in range(fn_kind.shape[0]):
        f, fd, fdd = eval_timefn(fn_kind[k], fn_data, fn_ptr[k], fn_ptr[k + 1], t)
        fval[k, 0] = f
        fval[k, 1] = fd
        fval[k, 2] = fdd
