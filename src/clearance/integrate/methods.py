"""The integration methods by name: what `simulate(method=...)` and scenario files accept.

Each entry is (loop, method data): "erk54" loops take a 7-stage FSAL 5(4) tableau
(tableau.py); "rk4" the classical fixed-step method. A new 7-stage FSAL pair is its tableau
plus one line here; another explicit method is its loop module (see state.py) plus one line
here and its call in `simulate._run_loop`.
"""

from __future__ import annotations

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

METHODS: dict[str, tuple[str, tuple]] = {
    "dopri5": ("erk54", (DP5_A, DP5_C, DP5_E, DP5_P)),  # Dormand & Prince 1980
    "tsit5": ("erk54", (TS5_A, TS5_C, TS5_E, TS5_P)),  # Tsitouras 2011
    "rk4": ("rk4", ()),  # classical, fixed step
}

#: methods with error control and dense output (rtol/atol steer them; events are located)
ADAPTIVE = tuple(name for name, (loop, _) in METHODS.items() if loop == "erk54")
