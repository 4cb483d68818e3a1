"""The integration methods by name: what `simulate(method=...)` and scenario files accept.

Each entry is a `Method`: its compiled loop, named "module:function" (so that reading this
table stays free of numba; the package imports every loop at its own import, while the
source-keyed kernel cache is set: `clearance._kernel_cache`), the loop's method data (the
erk54 loop takes a 7-stage FSAL 5(4) tableau of tableau.py, erk_high a high-order pair with
its dense output's extra stages and its order; rk4 none) and whether it is adaptive (error
control and dense output: rtol / atol steer it and contact events are located). Every loop
is called `loop(model, wk, cs, opts, out, *data, t0, y)` (the contract: state.py). A new
7-stage FSAL pair is its tableau plus one line here, as is a high-order pair of at most 16
stages; another method is its loop module plus one line here.
"""

from __future__ import annotations

import importlib
from typing import NamedTuple

import numpy as np

from clearance.integrate import tableau_dop853 as _d8
from clearance.integrate import tableau_vern7 as _v7
from clearance.integrate.tableau import (
    DP5_A,
    DP5_C,
    DP5_E,
    DP5_P,
    TS5_A,
    TS5_C,
    TS5_E,
    TS5_P,
)


class Method(NamedTuple):
    loop: str  # "module:function" of the compiled loop
    data: tuple  # method data passed to the loop before t0, y
    adaptive: bool
    stages: int = 7  # rows of the stage array the loop keeps (out.ks), dense output's included


_ERK54 = "clearance.integrate.erk:erk54"
_HIGH = "clearance.integrate.erk_high:erk_high"

METHODS: dict[str, Method] = {
    "dopri5": Method(_ERK54, (DP5_A, DP5_C, DP5_E, DP5_P), True),  # Dormand & Prince 1980
    "tsit5": Method(_ERK54, (TS5_A, TS5_C, TS5_E, TS5_P), True),  # Tsitouras 2011
    "rk4": Method("clearance.integrate.rk4:rk4", (), False),  # classical, fixed step
    # Dormand & Prince 8(5,3) with Hairer's 7th-order dense output (dop853.f)
    "dop853": Method(
        _HIGH,
        (_d8.A, _d8.C, _d8.B, _d8.E3, _d8.E5, _d8.P, 8.0),
        True,
        stages=_d8.N_STAGES_EXTENDED,
    ),
    # Verner's 7(6) "most efficient" pair with its 7th-order interpolant
    "vern7": Method(
        _HIGH,
        (_v7.A, _v7.C, _v7.B, np.zeros(0), _v7.E, _v7.P, 7.0),
        True,
        stages=_v7.N_STAGES_EXTENDED,
    ),
}

#: methods with error control and dense output (rtol/atol steer them; events are located)
ADAPTIVE = tuple(name for name, m in METHODS.items() if m.adaptive)

#: "auto" takes tsit5 for rtol >= AUTO_RTOL and vern7 below (bench/README.md, work-precision:
#: at a given rtol from 1e-5 to 1e-10 tsit5 costs the least on every case, clearance or
#: ideal: contact oscillations and impacts limit the step, and 20 001 samples weigh more than
#: the steps; the higher orders deliver more accuracy than asked at more cost. Below 1e-10
#: no method wins everywhere (dop853 on smooth persistent contact and at 1e-12 on the
#: frictionless rattling case, vern7 per rtol at 1e-11 there, tsit5 for the ideal
#: mechanism's forces); vern7 for robustness: never worse than ~2x the best there, while
#: dop853's forces on the ideal mechanism stall at ~5e-8 N (its dense output in long steps)
#: where vern7's reach 1e-9 N)
AUTO_RTOL = 1e-10


def resolve_method(name: str, rtol: float) -> str:
    """The method `simulate(method=name, rtol=rtol)` runs: "auto" by tolerance (AUTO_RTOL),
    any other name itself."""
    if name == "auto":
        return "tsit5" if rtol >= AUTO_RTOL else "vern7"
    return name


def method_loop(name: str):
    """The compiled loop of method `name`."""
    module, function = METHODS[name].loop.split(":")
    return getattr(importlib.import_module(module), function)
