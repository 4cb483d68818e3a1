"""Results as xarray datasets: NetCDF (groups, atomic), CSV and MAT round trips."""

from __future__ import annotations

import csv
import json
import os

import numpy as np
import pytest
import scipy.io
import xarray as xr

import clearance
from clearance.io.dataset import (
    clean_attrs,
    dataset_to_arrays,
    load_results,
    result_to_dataset,
    save_results,
)
from clearance.io.export import export_csv, export_mat
from clearance.mechanisms.ups_upu import ups_upu_ideal

T_END, DT_OUT = 0.03, 2e-4
SCENARIO = 'name = "test"\n[clearance]\njoints = ["S_1"]\nc = 0.3e-3\n'


@pytest.fixture(scope="module")
def results():
    m = ups_upu_ideal()
    law = clearance.Clearance(
        ball_radius=0.015,
        radial_clearance=0.3e-3,
        normal=clearance.Flores(),
        friction=clearance.LuGre(),
    )
    mc = m.with_clearance("S_1", law)
    ri = clearance.simulate(m, T_END, dt_out=DT_OUT)
    rc = clearance.simulate(mc, T_END, dt_out=DT_OUT)
    assert ri.success and rc.success
    assert len(rc.events) > 0  # the short run must contain impacts
    return {"ideal": ri, "clearance": rc}


@pytest.fixture(scope="module")
def datasets(results):
    return {k: result_to_dataset(r, attrs={"scenario": SCENARIO}) for k, r in results.items()}


@pytest.fixture
def saved(tmp_path, datasets):
    path = tmp_path / "run" / "results.nc"
    save_results(path, datasets, attrs={"scenario": SCENARIO, "flag": True})
    return path


def _numeric(da: xr.DataArray) -> bool:
    return da.dtype.kind in "iuf"


# ----------------------------------------------------------------------------- the dataset
def test_dataset_layout(results, datasets):
    ds = datasets["clearance"]
    r = results["clearance"]
    for d in ("time", "body", "axis", "quat", "row", "block", "driver_row", "clearance", "event"):
        assert d in ds.dims
    assert list(ds["body"].values) == list(r.compiled.body_names)
    assert list(ds["axis"].values) == ["x", "y", "z"]
    assert list(ds["quat"].values) == ["e0", "e1", "e2", "e3"]
    assert list(ds["block"].values) == list(r.blocks)
    assert list(ds["driver"].values) == list(r.driver_names)
    assert list(ds["clearance"].values) == ["S_1"]
    assert ds.sizes["row"] == r.lam.shape[1]
    assert ds.sizes["event"] == len(r.events)
    assert float(ds["radial_clearance"].sel(clearance="S_1")) == 0.3e-3
    for name, var in ds.variables.items():
        assert "units" in var.attrs, name
        assert var.attrs.get("long_name"), name
    assert ds["position"].attrs["units"] == "m"
    assert ds["actuator_force"].attrs["units"] == "N"
    assert ds["eccentricity"].dims == ("time", "clearance", "axis")
    for key in r.energy:
        assert ds[f"energy_{key}"].attrs["units"] == "J"
    at = ds.attrs
    assert at["clearance_version"] == clearance.__version__
    assert at["layout"] == r.compiled.describe()
    assert at["scenario"] == SCENARIO
    assert at["status"] == 0 and at["success"] == 1
    assert json.loads(at["settings"])["method"] == r.settings["method"]
    assert at["stats_nfev"] == r.stats["nfev"]


def test_accessors_match_result(results, datasets):
    r, ds = results["clearance"], datasets["clearance"]
    p = ds.sel(body="platform")
    np.testing.assert_array_equal(p["position"].values, r.position("platform"))
    np.testing.assert_allclose(
        p["angular_velocity"].values, r.angular_velocity("platform"), rtol=1e-12, atol=1e-15
    )
    np.testing.assert_array_equal(
        p["angular_velocity_body"].values, r.angular_velocity("platform", frame="body")
    )
    c = ds.sel(clearance="S_1")
    np.testing.assert_array_equal(c["eccentricity"].values, r.eccentricity("S_1"))
    np.testing.assert_array_equal(c["contact_force"].values, r.contact_force("S_1"))
    np.testing.assert_array_equal(c["normal_force"].values, r.normal_force("S_1"))
    np.testing.assert_array_equal(c["friction_force"].values, r.friction_force("S_1"))
    np.testing.assert_array_equal(c["slip_velocity"].values, r.slip_velocity("S_1"))
    np.testing.assert_array_equal(
        ds["actuator_force"].sel(driver_row="drive_3").values, r.actuator_force("drive_3")
    )
    f, mo = r.reaction("S_2")
    np.testing.assert_array_equal(ds["reaction_force"].sel(block="S_2").values, f)
    np.testing.assert_array_equal(ds["reaction_moment"].sel(block="S_2").values, mo)
    assert (ds["event_kind"].values == r.events[:, 2]).all()


@pytest.mark.parametrize("group", ["ideal", "clearance"])
def test_dataset_to_arrays_restores_result(results, datasets, group):
    r = results[group]
    arr = dataset_to_arrays(datasets[group])
    for k in (
        "t q v a lam phi phi_dot reaction_force reaction_moment driver_force "
        "contact contact_state dissipation bristle events contact_peaks"
    ).split():
        np.testing.assert_array_equal(arr[k], getattr(r, k), err_msg=k)
    assert arr["energy"].keys() == r.energy.keys()
    for k, v in r.energy.items():
        np.testing.assert_array_equal(arr["energy"][k], v)
    for k in ("blocks", "reaction_body", "driver_names", "clearance_names"):
        assert arr[k] == tuple(getattr(r, k)), k
    assert arr["stats"] == r.stats
    assert arr["status"] == r.status and arr["message"] == r.message


def test_clean_attrs():
    out = clean_attrs({"b": True, "n": None, "d": {"a": 1}, "v": [1.0, 2.0], "s": "x", "i": 3})
    assert out["b"] == 1 and out["s"] == "x" and out["i"] == 3
    assert json.loads(out["d"]) == {"a": 1} and out["n"] == "null"
    np.testing.assert_array_equal(out["v"], [1.0, 2.0])


# ----------------------------------------------------------------------------- NetCDF
def test_netcdf_roundtrip(saved, datasets):
    files = load_results(saved)
    assert list(files) == ["ideal", "clearance"]
    for g, ds in datasets.items():
        back = files[g]
        assert back.identical(ds), g  # every variable, coordinate and attribute
        assert set(back.variables) == set(ds.variables)
    assert files.attrs["scenario"] == SCENARIO
    assert files.attrs["flag"] == 1
    assert files.attrs["clearance_version"] == clearance.__version__
    assert json.loads(files.attrs["groups"]) == ["ideal", "clearance"]
    assert files["ideal"].sizes["clearance"] == 0  # ideal run: empty clearance channels
    assert files["ideal"].sizes["event"] == 0
    assert sorted(os.listdir(saved.parent)) == ["results.nc"]  # no temporary file left


@pytest.mark.parametrize("level", [0, 1, 6])
def test_netcdf_compression_level(datasets, tmp_path, level):
    """complevel 0 writes no filter; otherwise shuffle + zlib at that level; the data
    round-trips either way; a rewrite of loaded data applies the new level, not the file's."""
    import h5py

    src = tmp_path / "a.nc"
    save_results(src, datasets, complevel=4)
    path = tmp_path / f"l{level}.nc"
    save_results(path, load_results(src), complevel=level)
    with h5py.File(path) as f:
        v = f["clearance/position"]
        assert v.compression == ("gzip" if level else None)
        assert v.compression_opts == (level if level else None) and v.shuffle == bool(level)
    back = load_results(path)
    for g, ds in datasets.items():
        xr.testing.assert_identical(back[g], ds)


@pytest.mark.parametrize("bad", [-1, 10, 1.5, True, "1"])
def test_netcdf_compression_level_validated(datasets, tmp_path, bad):
    with pytest.raises(ValueError, match="complevel"):
        save_results(tmp_path / "x.nc", datasets, complevel=bad)
    assert not os.listdir(tmp_path)


def _netcdf_layout(path) -> dict:
    """Everything of a NetCDF file but its data, as netCDF4 reports it (NaN as a string)."""
    import netCDF4

    def attrs(obj) -> dict:
        return {k: repr(obj.getncattr(k)) for k in obj.ncattrs()}

    with netCDF4.Dataset(path) as nc:
        out = {"/": attrs(nc)}
        for gn, g in nc.groups.items():
            out[gn] = (attrs(g), {d: (len(v), v.isunlimited()) for d, v in g.dimensions.items()})
            for vn, v in g.variables.items():
                out[f"{gn}/{vn}"] = (
                    attrs(v),
                    str(v.dtype),
                    v.dimensions,
                    v.filters(),
                    v.chunking(),
                )
    return out


def test_direct_writer_reads_back_as_xarrays_writer(datasets, tmp_path):
    """The direct netCDF4 writer of plain datasets (numbers, strings) against xarray's own
    writer, the independent reference: the same variables, coordinates, attributes and
    dtypes on reading back, empty dimensions (the ideal run's events) included."""
    import clearance.io.dataset as D

    groups = {k: ds.drop_encoding() for k, ds in datasets.items()}
    assert all(D._plain(ds) for ds in groups.values())
    D._write_plain(tmp_path / "p.nc", {"scenario": SCENARIO}, groups, 1)
    D._write_xarray(tmp_path / "x.nc", {"scenario": SCENARIO}, groups, 1)
    p, x = load_results(tmp_path / "p.nc"), load_results(tmp_path / "x.nc")
    assert p.attrs == x.attrs and list(p) == list(x)
    # and the files themselves, for other readers: attributes (NaN fill values and CF
    # coordinate lists included), types, dimensions, filters and chunks of every variable
    assert _netcdf_layout(tmp_path / "p.nc") == _netcdf_layout(tmp_path / "x.nc")
    for g in p:
        xr.testing.assert_identical(p[g], x[g])
        assert set(p[g].coords) == set(x[g].coords) == set(datasets[g].coords)
        for name, var in p[g].variables.items():
            assert var.dtype == x[g][name].dtype, name


def test_datasets_beyond_plain_go_through_xarray(datasets, tmp_path):
    """A user's dataset with what the direct writer does not encode (booleans, CF
    attributes) is written by xarray and round-trips."""
    import clearance.io.dataset as D

    extra = datasets["ideal"].assign(ok=("time", np.ones(datasets["ideal"].sizes["time"], bool)))
    assert not D._plain(extra)
    save_results(tmp_path / "b.nc", {"ideal": extra})
    back = load_results(tmp_path / "b.nc")["ideal"]
    xr.testing.assert_identical(back, extra)
    assert back["ok"].dtype == bool


@pytest.mark.parametrize("writer", ["direct", "xarray"])
def test_netcdf_write_is_atomic(saved, datasets, monkeypatch, writer):
    import clearance.io.dataset as D

    if writer == "xarray":
        monkeypatch.setattr(D, "_plain", lambda ds: False)
    else:  # fail inside the clearance group, after the root and the ideal group
        real_filters, n_ideal = D._filters, len(datasets["ideal"].variables)
        seen = []

        def failing_filters(var, complevel):
            seen.append(var)
            if len(seen) >= n_ideal + 5:
                raise RuntimeError("disk full (simulated)")
            return real_filters(var, complevel)

        monkeypatch.setattr(D, "_filters", failing_filters)
    before = saved.read_bytes()
    calls = {"n": 0}
    real = xr.Dataset.to_netcdf

    def failing(self, *args, **kw):
        calls["n"] += 1
        if kw.get("group") == "clearance":
            raise RuntimeError("disk full (simulated)")
        return real(self, *args, **kw)

    if writer == "xarray":
        monkeypatch.setattr(xr.Dataset, "to_netcdf", failing)
    with pytest.raises(RuntimeError, match="simulated"):
        save_results(saved, datasets)
    if writer == "xarray":
        assert calls["n"] >= 2  # the failure came after part of the file was written
    assert saved.read_bytes() == before  # the old file is intact
    assert sorted(os.listdir(saved.parent)) == ["results.nc"]
    fresh = saved.parent / "new.nc"
    with pytest.raises(RuntimeError):
        save_results(fresh, datasets)
    assert not fresh.exists()
    assert sorted(os.listdir(saved.parent)) == ["results.nc"]
    monkeypatch.undo()
    assert load_results(saved)["clearance"].identical(datasets["clearance"])


def test_group_names_validated(tmp_path, datasets):
    with pytest.raises(ValueError, match="group"):
        save_results(tmp_path / "x.nc", {"a/b": datasets["ideal"]})
    assert not any(tmp_path.iterdir())


# ----------------------------------------------------------------------------- CSV
def _read_csv(path):
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


def test_csv_roundtrip(saved, datasets, tmp_path):
    out = tmp_path / "csv"
    paths = export_csv(saved, out)
    names = [p.name for p in paths]
    assert names == [
        "results_ideal.csv",
        "results_ideal_events.csv",
        "results_clearance.csv",
        "results_clearance_events.csv",
        "results_metadata.csv",
    ]
    assert sorted(os.listdir(out)) == sorted(names)
    for g, ds in datasets.items():
        header, rows = _read_csv(out / f"results_{g}.csv")
        assert len(header) == len(set(header))
        cols = {h: np.array([float(r[i]) for r in rows]) for i, h in enumerate(header)}
        assert len(rows) == ds.sizes["time"]
        np.testing.assert_array_equal(cols["time [s]"], ds["time"].values)
        n = 1
        for k, da in ds.data_vars.items():
            if "time" not in da.dims or not _numeric(da):
                continue
            flat = da.transpose("time", ...).values.reshape(ds.sizes["time"], -1)
            mine = [h for h in header if h.split(" [")[0].split(".")[0] == k]
            assert len(mine) == flat.shape[1], k
            for j, h in enumerate(mine):
                np.testing.assert_array_equal(cols[h], flat[:, j], err_msg=h)  # exact
            n += len(mine)
        assert n == len(header)
    header, _ = _read_csv(out / "results_clearance.csv")
    for h in (
        "position.platform.x [m]",
        "euler_parameters.platform.e0 [1]",
        "angular_velocity.platform.z [rad s-1]",
        "actuator_force.drive_1 [N]",
        "reaction_force.S_2.z [N]",
        "multiplier.U_1[0] [mixed]",
        "eccentricity.S_1.x [m]",
        "contact_force.S_1 [N]",
        "energy_kinetic [J]",
    ):
        assert h in header, h
    header, rows = _read_csv(out / "results_clearance_events.csv")
    ev = datasets["clearance"]
    assert len(rows) == ev.sizes["event"] > 0
    t = np.array([float(r[header.index("event_time [s]")]) for r in rows])
    np.testing.assert_array_equal(t, ev["event_time"].values)
    assert [r[header.index("event_clearance")] for r in rows] == list(ev["event_clearance"].values)
    ez = np.array([float(r[header.index("event_eccentricity.z [m]")]) for r in rows])
    np.testing.assert_array_equal(ez, ev["event_eccentricity"].sel(axis="z").values)
    header, rows = _read_csv(out / "results_ideal_events.csv")
    assert rows == [] and "event_time [s]" in header
    header, rows = _read_csv(out / "results_metadata.csv")
    assert header == ["group", "name", "value"]
    assert float(dict(((g, k), v) for g, k, v in rows)[("clearance", "stats_nfev")]) > 0
    meta = {(g, k): v for g, k, v in rows}
    assert meta[("", "scenario")] == SCENARIO  # multi-line value survives quoting
    assert float(meta[("clearance", "radial_clearance.S_1 [m]")]) == 0.3e-3
    assert meta[("clearance", "layout")] == datasets["clearance"].attrs["layout"]


def test_csv_streams_in_chunks_with_the_same_bytes(saved, tmp_path, monkeypatch):
    """Blocks of 7 samples formatted 5 rows at a time, from a lazily opened file, write
    the same bytes as one block."""
    import clearance.io.dataset as D
    import clearance.io.export as E

    whole = export_csv(saved, tmp_path / "a", chunk=10**6)
    monkeypatch.setattr(E, "_ROWS", 5)
    monkeypatch.setattr(D, "LAZY_BYTES", 0)
    parts = export_csv(saved, tmp_path / "b", chunk=7)
    for a, b in zip(whole, parts, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name


def test_time_histories_are_chunked_along_time(datasets, tmp_path, monkeypatch):
    """HDF5 chunks of CHUNK_SAMPLES samples: a reader of part of the time range
    decompresses only that part (checked with h5py, an independent reader)."""
    import h5py

    import clearance.io.dataset as D

    monkeypatch.setattr(D, "CHUNK_SAMPLES", 64)
    path = save_results(tmp_path / "c.nc", datasets)
    with h5py.File(path) as f:
        assert f["clearance/position"].chunks[0] == 64
        assert f["clearance/time"].chunks == (64,)
        assert f["clearance/radial_clearance"].chunks is None  # no time axis: contiguous


# ----------------------------------------------------------------------------- MAT
def test_mat_roundtrip(saved, datasets, tmp_path):
    out = export_mat(saved, tmp_path / "mat" / "results.mat")
    assert sorted(os.listdir(out.parent)) == ["results.mat"]
    m = scipy.io.loadmat(out, squeeze_me=False, struct_as_record=True)
    assert [str(np.ravel(g)[0]) for g in m["groups"].ravel()] == ["ideal", "clearance"]
    assert str(m["attrs"]["scenario"][0, 0][0]) == SCENARIO
    for g, ds in datasets.items():
        s = m[g][0, 0]
        for k, var in ds.variables.items():
            got = s[k]
            want = var.values
            if _numeric(var):
                shape = want.shape if want.ndim != 1 else (want.size, 1)
                assert got.shape == shape or (want.size == 0 and got.size == 0), k
                np.testing.assert_array_equal(got.reshape(want.shape), want, err_msg=k)
            else:
                labels = [str(np.ravel(c)[0]) if np.size(c) else "" for c in got.ravel()]
                assert labels == [str(x) for x in want.ravel()], k
            assert str(s["units"][k][0, 0][0]) == var.attrs["units"], k
            assert str(s["dims"][k][0, 0][0]) == ",".join(var.dims), k
        assert str(s["attrs"]["layout"][0, 0][0]) == ds.attrs["layout"]
        nfev = s["attrs"]["stats_nfev"][0, 0]
        assert nfev.dtype.kind in "iuf" and nfev.item() == ds.attrs["stats_nfev"]  # numeric
        assert s["attrs"]["success"][0, 0].item() == 1
        desc = {k: str(s["descriptions"][k][0, 0][0]) for k in ("velocity", "actuator_force")}
        assert desc["velocity"] == "mass-centre velocity [m s-1]: world frame"
        assert "positive pushes body j along the driver's positive" in desc["actuator_force"]


def test_save_results_accepts_a_result(results, datasets, tmp_path):
    path = save_results(tmp_path / "r.nc", {"ideal": results["ideal"]})
    back = load_results(path)["ideal"]
    assert back.equals(datasets["ideal"])  # same variables, coordinates and values
    assert back.attrs["layout"] == datasets["ideal"].attrs["layout"]


def test_npz_roundtrip_and_atomic_write(results, tmp_path, monkeypatch):
    from clearance.io.npz import load_npz, save_npz

    r = results["clearance"]
    path = save_npz(r, tmp_path / "sub" / "r.npz")
    z = load_npz(path)
    for name in ("t", "q", "v", "lam", "reaction_force", "driver_force"):
        np.testing.assert_array_equal(z[name], getattr(r, name))
    assert z["meta"]["bodies"] == list(r.compiled.body_names)
    before = path.read_bytes()

    def failing(*args, **kw):
        raise RuntimeError("disk full (simulated)")

    monkeypatch.setattr(np, "savez_compressed", failing)
    with pytest.raises(RuntimeError, match="simulated"):
        save_npz(r, path)
    assert path.read_bytes() == before  # the old file is intact, no temporary file left
    assert sorted(os.listdir(path.parent)) == ["r.npz"]


# ----------------------------------------------------------------------------- output groups
LEAN_VARS = {
    "position",
    "euler_parameters",
    "velocity",
    "angular_velocity",
    "acceleration",
    "angular_acceleration",
    "actuator_force",
    "energy_kinetic",
    "energy_residual",
    "contact_force",
    "eccentricity",
    "normal_force",
    "friction_force",
    "contact_flag",
    "peak_contact_force",
    "event_time",
}


def test_lean_outputs_hold_what_was_asked_for_and_equal_the_full_dataset(results, datasets):
    """The lean default holds the platform, actuators, energy and every clearance channel,
    each equal to the full dataset's values; bodies, multipliers, reactions and one-point
    contact-point channels are left out; the stored groups are stated in the file."""
    from clearance.io.dataset import stored_outputs
    from clearance.io.outputs import LEAN, resolve_outputs

    full = datasets["clearance"]
    lean = result_to_dataset(results["clearance"], outputs=LEAN, bodies=("platform",))
    assert stored_outputs(lean) == frozenset(LEAN) == resolve_outputs()
    assert stored_outputs(full) == resolve_outputs(["all"])
    assert LEAN_VARS <= set(lean.data_vars)
    for gone in (
        "multiplier",
        "constraint_violation",
        "reaction_force",
        "angular_velocity_body",
        "point_penetration",
    ):
        assert gone in full and gone not in lean
    assert list(lean["body"].values) == ["platform"]
    for k in lean.variables:
        sel = {"body": ["platform"]} if "body" in lean[k].dims else {}
        np.testing.assert_array_equal(lean[k].values, full[k].sel(sel).values, err_msg=k)
    with pytest.raises(ValueError, match="bodies, contact_points, multipliers, reactions"):
        dataset_to_arrays(lean)


def test_opt_in_outputs_and_their_validation(results):
    r = results["clearance"]
    ds = result_to_dataset(r, outputs=("reactions", "multipliers"))
    assert {"reaction_force", "multiplier"} <= set(ds.data_vars)
    assert "position" not in ds.data_vars and ds.sizes["body"] == 0
    assert "row" in ds.coords and "block" in ds.coords and "driver_row" not in ds.coords
    with pytest.raises(ValueError, match="unknown output 'forces'.*allowed: platform"):
        result_to_dataset(r, outputs=("forces",))
    with pytest.raises(ValueError, match="no body named 'plattform'"):
        result_to_dataset(r, outputs=("platform",), bodies=("plattform",))


def test_lazy_load_reads_on_use(saved, datasets):
    with load_results(saved, lazy=True) as files:
        ds = files["clearance"]
        assert not ds["position"].variable._in_memory
        np.testing.assert_array_equal(ds["position"].values, datasets["clearance"]["position"])
    eager = load_results(saved)
    assert eager["clearance"]["position"].variable._in_memory
