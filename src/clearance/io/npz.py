"""Save a `Result` as a compressed NumPy archive, atomically (temporary file, then rename).

NetCDF/xarray output with named dimensions arrives with the scenario files; this is the
minimal, dependency-free format of the core.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from clearance.io.files import atomic_path
from clearance.store.result import Result


def save_npz(result: Result, path: str | os.PathLike) -> Path:
    """Write `result` to `path` (.npz) atomically; return the final path."""
    path = Path(path)
    c = result.compiled
    arrays = dict(
        t=result.t,
        q=result.q,
        v=result.v,
        a=result.a,
        lam=result.lam,
        phi=result.phi,
        phi_dot=result.phi_dot,
        reaction_force=result.reaction_force,
        reaction_moment=result.reaction_moment,
        driver_force=result.driver_force,
    )
    arrays.update({f"energy_{k}": v for k, v in result.energy.items()})
    meta = dict(
        mechanism=c.mechanism.name,
        bodies=list(c.body_names),
        blocks=list(result.blocks),
        reaction_body=list(result.reaction_body),
        driver_names=list(result.driver_names),
        stats=result.stats,
        status=result.status,
        message=result.message,
        settings={
            k: (v if isinstance(v, (str, int, float, bool, type(None))) else str(v))
            for k, v in result.settings.items()
        },
        layout=c.describe(),
    )
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez_compressed(fh, meta=np.array(json.dumps(meta)), **arrays)
    return path


def load_npz(path: str | os.PathLike) -> dict:
    """Read back the arrays and the metadata dict (key 'meta') of `save_npz`."""
    with np.load(path, allow_pickle=False) as z:
        out = {k: z[k] for k in z.files if k != "meta"}
        out["meta"] = json.loads(str(z["meta"]))
    return out
