"""Export a results file (`save_results`) to CSV and MATLAB `.mat`, atomically.

CSV (`export_csv`), for a file `STEM.nc` with groups g (wide tables, one row per sample):

* `STEM_g.csv`: column `time [s]` then one column per scalar channel of every time-dependent
  variable, named `variable.label1.label2 [units]`, labels taken from the coordinates,
  e.g. `position.platform.x [m]`, `euler_parameters.platform.e0 [1]`,
  `multiplier.U_1[0] [mixed]`, `reaction_force.S_2.z [N]`, `actuator_force.drive_1 [N]`,
  `eccentricity.S_1.x [m]`, `energy_kinetic [J]`. Variables with a size-zero dimension
  (e.g. the clearance channels of an ideal run) have no columns.
* `STEM_g_events.csv`: the contact event log (`event_time [s]`, `event_clearance`, ...,
  `event_eccentricity.x [m]`), a header only when there were no events.
* `STEM_metadata.csv`: columns `group, name, value`: the root attributes (group empty), each
  group's attributes and its time-independent values (`radial_clearance.S_1 [m]`, ...).

Numbers are written with Python's shortest round-trip repr, so parsing them back gives the
stored float64 values exactly.

MAT (`export_mat`): one struct per group with a field per variable and coordinate (n-d
arrays keep their dimension order, 1-D arrays are columns, names are cell arrays of strings)
plus the sub-structs `units`, `dims` (comma-separated dimension names), `descriptions`
("long name [units]: description", with each variable's frame and sign convention) and
`attrs` (numbers stay numeric: stats_nfev is a double, not the text '46328'); top-level
`attrs` (root attributes) and `groups` (cell array).
"""

from __future__ import annotations

import csv
import itertools
import json
import os
import re
from pathlib import Path

import numpy as np
import xarray as xr

from clearance.io.dataset import CHUNK_SAMPLES, load_results
from clearance.io.files import atomic_path


def _label(ds: xr.Dataset, dim: str, i: int) -> str:
    if dim in ds.coords and ds[dim].dims == (dim,):
        return str(ds[dim].values[i])
    return str(i)


def _channels(ds: xr.Dataset, var: str, lead: str | None) -> list[tuple[str, np.ndarray]]:
    """Flatten variable `var` into (column name, 1-D values) over all dims but `lead`."""
    da = ds[var]
    rest = [d for d in da.dims if d != lead]
    if lead is not None:
        da = da.transpose(lead, *rest)
    vals = np.asarray(da.values)
    units = str(da.attrs.get("units", "")) if vals.dtype.kind in "iuf" else ""
    out = []
    for idx in itertools.product(*(range(ds.sizes[d]) for d in rest)):
        name = ".".join([str(var)] + [_label(ds, d, i) for d, i in zip(rest, idx, strict=True)])
        u = units
        if u == "mixed" and "driver_row" in rest and "driver_units" in ds.coords:
            u = str(ds["driver_units"].values[idx[rest.index("driver_row")]])
        col = vals[(slice(None), *idx)] if lead is not None else vals[idx]
        out.append((f"{name} [{u}]" if u else name, np.atleast_1d(col)))
    return out


def _cell(x: object) -> str:
    if isinstance(x, float):
        return repr(x)
    return str(x)


def _write_table(path: Path, header: list[str], columns: list[np.ndarray]) -> None:
    cols = [[_cell(x) for x in np.asarray(c).tolist()] for c in columns]
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(zip(*cols, strict=True))


def _attr_text(v: object) -> str:
    if isinstance(v, np.ndarray):
        return json.dumps(v.tolist())
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return str(v)


def _write_series(path: Path, ds: xr.Dataset, names: list[str], chunk: int) -> None:
    """The time-dependent variables `names` of ds as one wide table (`time [s]` first),
    `chunk` samples at a time: memory stays bounded by the chunk (ds may be lazy)."""
    header = ["time [s]"]
    for k in names:
        header += [h for h, _ in _channels(ds.isel(time=slice(0, 0)), k, "time")]
    n = ds.sizes.get("time", 0)
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        csv.writer(fh).writerow(header)
        for i0 in range(0, n, chunk):  # read a block (HDF5 chunks whole), format in rows
            part = ds.isel(time=slice(i0, min(n, i0 + chunk)))
            cols = [np.asarray(part["time"].values).reshape(-1, 1)]
            for k in names:
                da = part[k]
                da = da.transpose("time", *[d for d in da.dims if d != "time"])
                cols.append(np.asarray(da.values).reshape(da.shape[0], -1))
            for r0 in range(0, cols[0].shape[0], _ROWS):
                sub = [c[r0 : r0 + _ROWS] for c in cols]
                if all(c.dtype.kind == "f" for c in sub):
                    rows = np.hstack(sub).tolist()
                else:  # integers (contact flags) stay integers
                    per = [c.tolist() for c in sub]
                    rows = [[x for p in row for x in p] for row in zip(*per, strict=True)]
                fh.write("\r\n".join(",".join(map(_cell, r)) for r in rows))
                fh.write("\r\n")


_ROWS = 256  # rows formatted at a time: Python floats and strings cost ~60 bytes per cell


def export_csv(
    path_nc: str | os.PathLike, out_dir: str | os.PathLike, *, chunk: int = CHUNK_SAMPLES
) -> list[Path]:
    """Write the CSV tables of a results file into `out_dir` (layout: module docstring).

    Returns the written paths: per group `STEM_g.csv` and `STEM_g_events.csv`, then
    `STEM_metadata.csv`. The wide tables are written `chunk` samples at a time, and a
    large file (above `LAZY_BYTES`) is read lazily, chunk by chunk: memory stays bounded.
    """
    out_dir = Path(out_dir)
    stem = Path(path_nc).stem
    written: list[Path] = []
    with load_results(path_nc) as files:  # lazily if it is large
        meta: list[tuple[str, str, str]] = [("", k, _attr_text(v)) for k, v in files.attrs.items()]
        for g, ds in files.items():
            series, events = [], []
            for k in ds.variables:
                dims = ds[k].dims
                if k == "time":
                    continue
                if "time" in dims:
                    series.append(str(k))
                elif dims and dims[0] == "event":
                    events += _channels(ds, k, "event")
                elif k not in ds.dims:  # time-independent non-index values
                    meta += [(g, nm, _cell(c.item())) for nm, c in _channels(ds, k, None)]
            meta += [(g, k, _attr_text(v)) for k, v in ds.attrs.items()]
            p = out_dir / f"{stem}_{g}.csv"
            _write_series(p, ds, series, chunk)
            p_ev = out_dir / f"{stem}_{g}_events.csv"
            _write_table(p_ev, [h for h, _ in events], [c for _, c in events])
            written += [p, p_ev]
    p = out_dir / f"{stem}_metadata.csv"
    cols = [np.array([m[i] for m in meta], dtype=object) for i in range(3)]
    _write_table(p, ["group", "name", "value"], cols)
    written.append(p)
    return written


def _mat_name(name: str, used: set) -> str:
    s = re.sub(r"\W", "_", str(name))
    if not s or not s[0].isalpha():
        s = "v_" + s
    s = s[:63]
    while s in used:
        s = s[:62] + "_"
    used.add(s)
    return s


def _mat_value(a: np.ndarray) -> np.ndarray:
    a = np.asarray(a)
    if a.dtype.kind in "USO":
        return np.array([str(x) for x in a.ravel()], dtype=object).reshape(a.shape)
    return a


def _mat_attr(v: object) -> object:
    """An attribute for MATLAB: numbers stay numbers (a double or an integer, numeric
    vectors as row vectors), everything else is text."""
    if isinstance(v, (bool, np.bool_)):
        return int(v)
    if isinstance(v, (int, float, np.integer, np.floating)):
        return v.item() if isinstance(v, np.generic) else v
    if isinstance(v, np.ndarray) and v.dtype.kind in "iuf":
        return v.reshape(1, -1) if v.ndim == 1 else v
    return _attr_text(v)


def _describe(da: xr.DataArray) -> str:
    """'long name [units]: description (frame, sign convention)' of a variable."""
    a = da.attrs
    text = str(a.get("long_name", da.name))
    if a.get("units"):
        text += f" [{a['units']}]"
    if a.get("description"):
        text += f": {a['description']}"
    return text


def export_mat(path_nc: str | os.PathLike, out_file: str | os.PathLike) -> Path:
    """Write a results file as a MATLAB `.mat` (v5, compressed; layout: module docstring)."""
    import scipy.io

    files = load_results(path_nc)
    top: set = {"attrs", "groups"}
    mdict: dict = {}
    for g, ds in files.items():
        used = {"units", "dims", "attrs"}
        s: dict = {}
        units: dict = {}
        dims: dict = {}
        descriptions: dict = {}
        for k in ds.variables:
            f = _mat_name(str(k), used)
            s[f] = _mat_value(ds[k].values)
            units[f] = str(ds[k].attrs.get("units", ""))
            dims[f] = ",".join(str(d) for d in ds[k].dims)
            descriptions[f] = _describe(ds[k])
        s["units"] = units
        s["dims"] = dims
        s["descriptions"] = descriptions
        au: set = set()
        s["attrs"] = {_mat_name(k, au): _mat_attr(v) for k, v in ds.attrs.items()}
        mdict[_mat_name(g, top)] = s
    au = set()
    mdict["attrs"] = {_mat_name(k, au): _mat_attr(v) for k, v in files.attrs.items()}
    mdict["groups"] = np.array(list(files), dtype=object)
    out_file = Path(out_file)
    with atomic_path(out_file) as tmp:
        scipy.io.savemat(
            str(tmp),
            mdict,
            appendmat=False,
            format="5",
            long_field_names=True,
            do_compression=True,
            oned_as="column",
        )
    return out_file
