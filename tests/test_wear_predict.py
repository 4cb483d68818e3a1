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

import clearance as cl
from clearance.io.dataset import result_to_dataset
from clearance.scenario import default_scenario_path
from clearance.scenario.wear import JointWear, WearSettings
from clearance.wear.history import socket_wear
from clearance.wear.predict import CycleWear, WearLoop, run_wear_loop
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
    def cycle(worn):
        r = cl.simulate(spinning_ball(worn), T, dt_out=T / 50)
        assert r.success
        m, work = socket_wear(result_to_dataset(r), "J", k_w=KW, e_star=E_STAR, n=n)
        return CycleWear({"J": m.depth}, {"J": work}, {"J": {}})

    return cycle


def test_constant_load_and_slip_give_archards_closed_form():
    """Ball-in-socket under a constant load F = M g sliding at v = OMEGA R_b: after N cycles
    of length T (in 4 iterations of the loop, each run on the socket worn so far) the worn
    volume is k_w F v N T (Archard), and the depth at the centre of the wear is
    k_w p0 v N T with p0 = 3 F / (2 pi a^2), a = (3 F R* / (4 E*))^(1/3) (Hertz, conformal
    R* = R_b R_s / c), to the grid's discretisation, converging with it."""
    F, v = M * G, OMEGA * RB
    N = 1e4
    rs = RB + C
    a = (3 * F * (RB * rs / C) / (4 * E_STAR)) ** (1 / 3)
    p0 = 3 * F / (2 * math.pi * a * a)
    depth, volume, first_order = [], [], []
    for n in (48, 96, 192):
        st = WearLoop({"J": SphereWearMap(rs, n)}, {"J": C})
        settings = WearSettings({"J": JointWear(KW, n)}, N, update_factor=N / 4)
        run_wear_loop(spinning_cycle(n), settings, st, log=None)
        assert st.done and len(st.rows) == 5 and st.cycles == pytest.approx(N)
        volume.append(st.maps["J"].volume())
        first_order.append(float(np.sum(st.maps["J"].depth * st.maps["J"].areas)))
        depth.append(float(st.maps["J"].depth_at(np.array([0.0, 0.0, -1.0]))))
        h = st.history()
        assert h["cycles"].values.tolist() == pytest.approx([0, N / 4, N / 2, 3 * N / 4, N])
        # each run's wear work is F v T: the ball stays at rest in its deepening pocket
        assert h["wear_work"].values[:, 0] == pytest.approx(F * v * T, rel=1e-6)
    # sum h A is exactly Archard's volume on every grid; the material removed, a shell
    # ((R + h)^3 - R^3) / 3 per solid angle, exceeds it by up to h / R (3.6e-3 here)
    assert first_order == pytest.approx([KW * F * v * N * T] * 3, rel=1e-9)
    assert volume == pytest.approx([KW * F * v * N * T] * 3, rel=max(depth) / rs)
    err = [abs(d / (KW * p0 * v * N * T) - 1) for d in depth]
    assert err[-1] < 0.03, err  # (measured 23 %, 6.7 %, 1.8 %: second order)
    assert err[-1] < err[0] / 8, err
    assert depth[-1] > 0.3 * C  # 36 um: the ball sank into its pocket run after run


def test_the_update_factor_does_not_change_the_result():
    """The wear loop is Euler's method in the cycle count: on a swinging pendulum whose ball
    wears a groove in its socket (the groove changes the contact and so the next cycles'
    wear), the worn volume and depth after 2e5 cycles agree for 4, 8 and 16 iterations,
    and the difference shrinks as the factor does (first order). Measured: volume
    1.7046, 1.7168, 1.7056e-11 m^3; max depth 29.4, 32.1, 33.3 um (c = 100 um)."""
    from models import rod_on_clearance_joint

    base = rod_on_clearance_joint(
        cl.Flores(restitution=0.5), cl.Coulomb(mu=0.2), theta=0.4, spin=(0.0, 0.0, 0.0)
    ).mechanism

    def cycle(worn):
        mech = base
        for j, w in worn.items():
            mech = mech.with_wear(j, w)
        r = cl.simulate(cl.compile_mechanism(mech), 0.2, dt_out=2e-4)
        assert r.success
        m, work = socket_wear(result_to_dataset(r), "S", k_w=4e-15, e_star=E_STAR, n=32)
        return CycleWear({"S": m.depth}, {"S": work}, {"S": {}})

    out = {}
    for iters in (4, 8, 16):
        st = WearLoop({"S": SphereWearMap(0.01 + 1e-4, 32)}, {"S": 1e-4})
        run_wear_loop(
            cycle, WearSettings({"S": JointWear(4e-15, 32)}, 2e5, 2e5 / iters), st, log=None
        )
        out[iters] = (st.maps["S"].volume(), st.maps["S"].max_depth())
    v4, v8, v16 = (out[k][0] for k in (4, 8, 16))
    d4, d8, d16 = (out[k][1] for k in (4, 8, 16))
    assert d16 > 0.2 * 1e-4  # the groove is deep enough to change the contact
    assert abs(v4 / v16 - 1) < 0.02 and abs(v8 / v16 - 1) < 0.02
    assert abs(d8 / d16 - 1) < 0.05
    assert abs(d8 - d16) < abs(d4 - d8)  # converging


def _wear_scenario(tmp_path):
    text = default_scenario_path("ups_upu").read_text()
    text = re.sub(r"(?m)^duration = [0-9.]+", "duration = 0.1", text)
    text += """
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
"""
    path = tmp_path / "wear.toml"
    path.write_text(text)
    return path


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
        assert np.all(np.diff(eff) > 0) and eff[-1] > 3e-4
        assert np.all(da["max_depth"].values[-1] > 0)
    for f in ("wear_map_S_1.png", "wear_surface_S_3.png", "wear_history.png"):
        assert (a / f).stat().st_size > 10_000
