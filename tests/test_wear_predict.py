"""The wear loop (issue 16, `clearance.wear.predict`): Archard's closed form under constant
load and slip, independence of the update factor, and the seed mechanism end to end through
`clearance wear` (resumed after an interruption)."""

from __future__ import annotations

import math
import re
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from scipy.optimize import brentq

import clearance as cl
from clearance.io.dataset import result_to_dataset
from clearance.scenario import default_scenario_path
from clearance.scenario.wear import JointWear, WearSettings
from clearance.wear.history import socket_wear
from clearance.wear.predict import CycleWear, WearLoop, run_metrics, run_wear_loop
from clearance.wear.surface import SphereWearMap

RB, C, M, G = 0.01, 1e-4, 2.0, 9.81
K = 3e10  # Hertz stiffness [N/m^1.5]
E_STAR = 113.7e9  # contact modulus of the wear patch [Pa]
OMEGA, T = 10.0, 0.01  # spin [rad/s] and one cycle [s]
KW = 1e-13  # k / H [m^2/N]


def spinning_ball(worn):
    """A 2 kg ball body spinning at OMEGA about x with its centre of mass at the ball's
    centre, resting under gravity at the bottom of a ground socket worn as `worn`: a
    constant normal load M g and a constant slip speed OMEGA R_b at the contact point."""
    mech = cl.Mechanism("spinning ball", gravity=(0, 0, -G))
    h = float(worn["J"].depth(np.array([0.0, 0.0, -1.0]))) if worn else 0.0
    dz = C + h + (M * G / K) ** (2 / 3)  # at rest on the worn bottom
    mech.add(
        cl.Body("b", M, (1e-3, 1e-3, 1e-3), position=(0, 0, -dz), angular_velocity=(OMEGA, 0, 0)),
        cl.Marker("s", "ground"),
        cl.Marker("m", "b"),
        cl.Spherical(
            "J",
            "s",
            "m",
            clearance=cl.Clearance(RB, radial_clearance=C, normal=cl.Hertz(stiffness=K)),
        ),
    )
    for j, w in (worn or {}).items():
        mech = mech.with_wear(j, w)
    return cl.compile_mechanism(mech)


def spinning_cycle(n):
    def cycle(worn, maps):
        r = cl.simulate(spinning_ball(worn), T, dt_out=T / 50)
        assert r.success
        ds = result_to_dataset(r)
        m, work = socket_wear(ds, "J", k_w=KW, e_star=E_STAR, n=n, worn=maps["J"])
        return CycleWear({"J": m.depth}, {"J": work}, {"J": run_metrics(ds, "J")})

    return cycle


def imprint_depth(volume, R):
    """d0 with pi R^2 d0^2 / (d0 + c) = volume: the depth of the socket worn to the imprint
    of the ball pushed d0 beyond contact (test_wear_surface.test_imprint_volume)."""
    return brentq(lambda d: math.pi * R**2 * d * d / (d + C) - volume, 1e-15, 1e-2)


def test_constant_load_and_slip_give_archards_closed_form():
    """Ball-in-socket under a constant load F = M g sliding at v = OMEGA R_b, N = 1e5 cycles
    of length T, each run on the socket worn so far: the worn volume is k_w F v N T
    (Archard), and the socket is worn to the ball's imprint, whose depth d0 follows from
    the volume in closed form (pi R^2 d0^2 / (d0 + c) = V): the ball sinks into a
    conforming seat. On 96 and 128 cells per face in 32 fixed steps, and on 64 with the
    adaptive factor bounded by the elastic penetration (max_step_penetration 0.5; 32
    fixed steps are too coarse there: a pit deeper than the ball fits forms and the wear
    scatters over its rim). Measured: 8.128, 8.127, 8.090 um against 8.137 um; seat
    within 0.7, 1.2, 2.1 % of d0."""
    F, v = M * G, OMEGA * RB
    N = 1e5
    rs = RB + C
    for n, factor, pen in ((96, N / 32, math.inf), (128, N / 32, math.inf), (64, None, 0.5)):
        st = WearLoop({"J": SphereWearMap(rs, n)}, {"J": C})
        settings = WearSettings(
            {"J": JointWear(KW, n)}, N, factor, max_step=1.0, max_step_penetration=pen
        )
        run_wear_loop(spinning_cycle(n), settings, st, log=None)
        assert st.done and st.cycles == pytest.approx(N)
        m = st.maps["J"]
        first_order = float(np.sum(m.depth * m.areas))
        # each run's wear work is F v T: the ball stays at rest in its deepening seat
        assert st.history()["wear_work"].values[:, 0] == pytest.approx(F * v * T, rel=1e-5)
        assert first_order == pytest.approx(KW * F * v * N * T, rel=1e-5)
        # the material removed, a shell ((R + h)^3 - R^3) / 3 per solid angle: h / R more
        assert m.volume() == pytest.approx(first_order, rel=m.max_depth() / rs)
        d0 = imprint_depth(first_order, rs)
        assert m.max_depth() == pytest.approx(d0, rel=0.01), n
        # the seat is the imprint: depth max(0, (c + d0) cos psi - c) around the load axis
        cos = m.centres @ np.array([0.0, 0.0, -1.0])
        seat = np.maximum(0.0, (C + d0) * cos - C)
        assert np.max(np.abs(m.depth - seat)) < 0.03 * d0, n


def test_the_loop_gives_the_dynamics_the_reachable_depth_with_its_smoothing():
    """WearLoop.worn: each joint's SocketWear is its map's reachable depth for the joint's
    clearance, smoothed over the joint's `smoothing` (review finding: the loop once passed
    the smoothing as the clearance, so the dynamics saw the raw worn depth)."""
    n, c = 48, 2e-4
    m = SphereWearMap(0.0102, n)
    th = np.arccos(np.clip(m.centres @ np.array([0.0, 0.0, -1.0]), -1, 1))
    m.depth = np.where(th < 0.25, 20e-6 * (1 - (th / 0.25) ** 2) ** 2, 0.0)
    st = WearLoop({"J": m}, {"J": c})
    w = st.worn({"J": 3.0})["J"]
    ref = m.socket_wear(c, 3.0)
    assert w.smoothing == pytest.approx(3.0 * 0.5 * math.pi / n)
    u = np.array([[0.0, 0.0, -1.0], [0.1, 0.0, -1.0], [0.0, 0.2, -1.0]])
    u /= np.linalg.norm(u, axis=1)[:, None]
    np.testing.assert_allclose(w.depth(u), ref.depth(u), rtol=1e-12)
    assert w.depth(u[:1])[0] < 0.5 * 20e-6  # the ball stops on the rim, not at the bottom


def test_the_update_factor_does_not_change_the_result():
    """The wear loop is Euler's method in the cycle count. On a pendulum whose ball wears a
    seat into its socket over 2e5 cycles (0.15 s each after the drop; the seat changes the
    contact and so the next cycles' wear), the adaptive update factor with max_step 0.05,
    0.025 and 0.0125 (25, 46, 80 runs) converges: the worn volume agrees to 0.1 % and the
    deepest point to 3 % between the two smallest steps, its change shrinking 9-fold.
    Measured: 10.05, 7.85, 7.61 um; 1.4935, 1.4926, 1.4921e-10 m^3."""
    from models import rod_on_clearance_joint

    base = rod_on_clearance_joint(
        cl.Flores(restitution=0.5), cl.Coulomb(mu=0.2), theta=0.4, spin=(0.0, 0.0, 0.0)
    ).mechanism

    def cycle(worn, maps):
        mech = base
        for j, w in worn.items():
            mech = mech.with_wear(j, w)
        r = cl.simulate(cl.compile_mechanism(mech), 0.2, dt_out=2e-4)
        assert r.success
        ds = result_to_dataset(r)
        ds = ds.isel(time=np.flatnonzero(ds["time"].values >= 0.05))  # the drop: not a cycle
        m, work = socket_wear(ds, "S", k_w=4e-14, e_star=E_STAR, n=32, worn=maps["S"])
        return CycleWear({"S": m.depth}, {"S": work}, {"S": run_metrics(ds, "S")})

    out = {}
    for step in (0.05, 0.025, 0.0125):
        st = WearLoop({"S": SphereWearMap(0.01 + 1e-4, 32)}, {"S": 1e-4})
        settings = WearSettings({"S": JointWear(4e-14, 32)}, 2e5, max_step=step)
        run_wear_loop(cycle, settings, st, log=None)
        out[step] = (st.maps["S"].volume(), st.maps["S"].max_depth(), len(st.rows))
    (v1, d1, n1), (v2, d2, n2), (v3, d3, n3) = out.values()
    assert n1 < n2 < n3  # smaller steps, more runs
    assert d3 > 0.05 * 1e-4  # a seat of several um: it changes the contact
    assert v1 == pytest.approx(v3, rel=2e-3) and v2 == pytest.approx(v3, rel=2e-3)
    assert d2 == pytest.approx(d3, rel=0.05)
    assert abs(d2 - d3) < 0.25 * abs(d1 - d2)  # converging


def short_scenario(tmp_path, name, wear):
    """The shipped scenario `name` cut to 0.1 s runs, with the [wear] table `wear`."""
    text = default_scenario_path(name).read_text()
    path = tmp_path / f"{name}.toml"
    path.write_text(re.sub(r"(?m)^duration = [0-9.]+", "duration = 0.1", text) + wear)
    return path


def _wear_scenario(tmp_path):
    return short_scenario(
        tmp_path,
        "ups_upu",
        """
[wear]
cycles = 1e5
update_factor = 5e4
warmup = 0.02

[wear.joints.S_1]
coefficient = 1e-13
grid = 24

[wear.joints.S_3]
k = 2e-4
hardness = 2e9
grid = 24
""",
    )


def test_seed_mechanism_wear_runs_end_to_end_and_resumes(tmp_path):
    """`clearance wear` on the 4UPS-UPU (0.1 s runs): two iterations, then a second call
    resumes from wear.nc and finishes; the result equals an uninterrupted prediction, and
    the effective clearance grows with cycles. (That the wear sits along the mean contact
    direction is tested on the same mechanism in test_wear_history.)"""
    path = _wear_scenario(tmp_path)
    assert "\nduration = 0.1" in path.read_text()
    cmd = [sys.executable, "-m", "clearance.cli.main", "wear", str(path)]
    a, b = tmp_path / "a", tmp_path / "b"
    r1 = subprocess.run(
        [*cmd, "-o", str(a), "--iterations", "1", "--no-figures"], capture_output=True, text=True
    )
    assert r1.returncode == 0, r1.stderr
    assert "not finished" in r1.stdout
    r2 = subprocess.run([*cmd, "-o", str(a)], capture_output=True, text=True)
    assert r2.returncode == 0, r2.stderr
    assert "resuming" in r2.stdout + r2.stderr
    r3 = subprocess.run([*cmd, "-o", str(b), "--no-figures"], capture_output=True, text=True)
    assert r3.returncode == 0, r3.stderr
    with (
        xr.open_dataset(a / "wear.nc", engine="netcdf4") as da,
        xr.open_dataset(b / "wear.nc", engine="netcdf4") as db,
    ):
        for name in ("cycles", "volume", "max_depth", "depth_S_1", "depth_S_3"):
            np.testing.assert_array_equal(da[name].values, db[name].values)
        assert da.attrs["done"] == 1
        cyc = da["cycles"].values
        assert cyc.tolist() == [0.0, 5e4, 1e5]
        eff = da["effective_clearance"].sel(joint="S_1").values
        assert eff[-1] > 3e-4 + 1e-6  # c + a visible depth
        assert np.all(np.diff(da["volume"].values[:-1], axis=0) > 0)  # each iteration wears
        assert np.all(da["max_depth"].values[-1] > 0)
        # volume balance: sum h A of the final map = k_w x sum over the iterations of the
        # factor times the run's F_N |v_slip| dt per cycle
        for j, kw in (("S_1", 1e-13), ("S_3", 2e-4 / 2e9)):
            m = SphereWearMap(float(da[f"depth_{j}"].attrs["radius"]), 24)
            w = da["wear_work"].sel(joint=j).values * da["update_factor"].values
            assert float(np.sum(da[f"depth_{j}"].values * m.areas)) == pytest.approx(
                kw * float(np.sum(w)), rel=1e-9
            )
            hist = da[f"depth_history_{j}"].values
            assert hist.shape == (3, 6, 24, 24) and not hist[0].any() and hist[-1].any()
        # another scenario in the same folder is refused, not overwritten
        other = path.read_text().replace("cycles = 1e5", "cycles = 2e5")
        path.write_text(other)
    r4 = subprocess.run([*cmd, "-o", str(a)], capture_output=True, text=True)
    assert r4.returncode == 2 and "another scenario" in r4.stderr, r4.stderr
    assert "Traceback" not in r4.stderr
    for f in ("wear_map_S_1.png", "wear_surface_S_3.png", "wear_history.png"):
        assert (a / f).stat().st_size > 10_000


BAD_WEAR = {
    "unknown joint": ("[wear.joints.S_9]\ncoefficient = 1e-13\n", "wear.joints.S_9"),
    "no coefficient": ("[wear.joints.S_1]\ngrid = 16\n", "wear.joints.S_1.coefficient"),
    "both": ("[wear.joints.S_1]\ncoefficient = 1e-13\nk = 1e-4\nhardness = 2e9\n", "both"),
    "negative": ("[wear.joints.S_1]\ncoefficient = -1e-13\n", "wear.joints.S_1.coefficient"),
    "grid": ("[wear.joints.S_1]\ncoefficient = 1e-13\ngrid = 4096\n", "wear.joints.S_1.grid"),
    "factor": ('update_factor = "fast"\n[wear.joints.S_1]\ncoefficient = 1e-13\n', "update_factor"),
    "key": ("cylces = 3\n[wear.joints.S_1]\ncoefficient = 1e-13\n", "wear.cylces"),
}


@pytest.mark.parametrize("case", list(BAD_WEAR))
def test_bad_wear_tables_are_refused_naming_the_field(tmp_path, case):
    """`clearance check` refuses a bad [wear] table with the file, the field, the value and
    what is allowed (exit 2, no traceback)."""
    body, field = BAD_WEAR[case]
    text = default_scenario_path("ups_upu").read_text() + "\n[wear]\ncycles = 10\n" + body
    path = tmp_path / "bad.toml"
    path.write_text(text)
    r = subprocess.run(
        [sys.executable, "-m", "clearance.cli.main", "check", str(path)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2, r.stdout
    assert field in r.stderr and str(path) in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_the_other_seed_mechanism_wears_too(tmp_path):
    """The 4-SPS/CU (its spherical clearance joint SB_1) through predict_wear: 0.1 s runs,
    2e5 cycles in fixed steps of 1e5, the volume and the effective clearance growing, the
    figures written."""
    from clearance.wear.predict import predict_wear

    path = short_scenario(
        tmp_path,
        "sps_cu",
        """
[wear]
cycles = 2e5
update_factor = 1e5
warmup = 0.02

[wear.joints.SB_1]
coefficient = 1e-14
grid = 24
""",
    )
    w = predict_wear(path, out_dir=tmp_path / "out", log=None)
    h = w.history
    assert w.state.done and h["cycles"].values.tolist() == [0.0, 1e5, 2e5]
    v = h["volume"].sel(joint="SB_1").values
    assert v[0] == 0.0 and 0.0 < v[1] < v[2]
    assert np.all(np.diff(h["effective_clearance"].sel(joint="SB_1").values) > 0)
    assert (tmp_path / "out" / "wear_surface_SB_1.png").stat().st_size > 10_000
