"""The integration methods by name: what `simulate(method=...)` and scenario files accept.

Each entry is a `Method`: its compiled loop, named "module:function" (so that reading this
table stays free of numba; the package imports every loop at its own import, while the
source-keyed kernel cache is set: `clearance._kernel_cache`), the loop's method data (the
erk54 loop takes a 7-stage FSAL 5(4) tableau of tableau.py; rk4 none) and whether it is
adaptive (error control and dense output: rtol / atol steer it and contact events are
located). Every loop is called `loop(model, wk, cs, opts, out, *data, t0, y)` (the
contract: state.py). A new 7-stage FSAL pair is its tableau plus one line here; another
method is its loop module plus one line here.
"""

from __future__ import annotations

import importlib
from typing import NamedTuple

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


_ERK54 = "clearance.integrate.erk:erk54"

METHODS: dict[str, Method] = {
    "dopri5": Method(_ERK54, (DP5_A, DP5_C, DP5_E, DP5_P), True),  # Dormand & Prince 1980
    "tsit5": Method(_ERK54, (TS5_A, TS5_C, TS5_E, TS5_P), True),  # Tsitouras 2011
    "rk4": Method("clearance.integrate.rk4:rk4", (), False),  # classical, fixed step
}

#: methods with error control and dense output (rtol/atol steer them; events are located)
ADAPTIVE = tuple(name for name, m in METHODS.items() if m.adaptive)


def method_loop(name: str):
    """The compiled loop of method `name`."""
    module, function = METHODS[name].loop.split(":")
    return getattr(importlib.import_module(module), function)
