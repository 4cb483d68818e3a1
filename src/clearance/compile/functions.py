"""Encode time functions for the compiled evaluators (`clearance.kinematics.timefn`, whose
docstring gives the per-kind data layouts)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from clearance.model.functions import TimeFunction, as_function


def encode_functions(
    funcs: Sequence[TimeFunction],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Encode functions into (fn_kind int64[n], fn_ptr int64[n + 1], fn_data float64[...])."""
    n = len(funcs)
    fn_kind = np.zeros(n, dtype=np.int64)
    fn_ptr = np.zeros(n + 1, dtype=np.int64)
    chunks = []
    for k, f in enumerate(funcs):
        code, data = as_function(f, owner="encode_functions", field=f"funcs[{k}]").encode()
        fn_kind[k] = code
        fn_ptr[k + 1] = fn_ptr[k] + data.size
        chunks.append(np.asarray(data, dtype=np.float64))
    fn_data = np.concatenate(chunks) if chunks else np.zeros(0, dtype=np.float64)
    return fn_kind, fn_ptr, fn_data
