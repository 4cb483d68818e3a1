"""The parallel-mechanism builder (clearance.mechanisms.parallel, .legs).

Oracles: the two seed factories (ups_upu_ideal, sps_cu: hand-written, earlier) compile to
the same arrays bit for bit as the builder's legs; the mobility of each leg type against
its hand count (Grubler-Kutzbach and the idle rod spins); the forward dynamics of the ideal
mechanism driven by the inverse kinematics follows the prescribed platform trajectory;
bad legs and mobility mismatches are refused naming the leg and joint.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import clearance as cl
from clearance.analysis.ik import PlatformTrajectory, drives_from_ik, inverse_kinematics
from clearance.mechanisms.sps_cu import SpsCuParams, sps_cu
from clearance.mechanisms.ups_upu import UpsUpuParams, ups_upu_ideal
from clearance.parallel import (
    Leg,
    Link,
    ParallelMechanism,
    Platform,
    circle,
    legs,
)


def rod(length: float, mass: float = 1.0) -> Link:
    """A slender rod, mass centre at mid-length."""
    j = mass * length * length / 12.0
    return Link(mass, (j, j, 1e-5), com=length / 2, length=length)


CARRIAGE = Link(1.0, (0.01, 0.01, 0.01))


def ups_upu_builder(par: UpsUpuParams | None = None) -> ParallelMechanism:
    par = par or UpsUpuParams()
    base, plat = circle(par.R_A, par.theta_deg), circle(par.R_B, par.phi_deg)
    lo = Link(par.swing_mass, par.swing_inertia, com=par.swing_com, length=par.swing_length)
    up = Link(par.tele_mass, par.tele_inertia, com=par.tele_com, length=par.tele_length)
    o = (0, 0, 0)
    return ParallelMechanism(
        "4UPS-UPU",
        Platform(par.platform_mass, par.platform_inertia, position=(0, 0, par.home_height)),
        (legs("UPS", base=base, platform=plat, links=(lo, up)), Leg("UPU", o, o, (lo, up))),
        gravity=par.gravity,
    )


def sps_cu_builder(lumped: bool, par: SpsCuParams | None = None) -> ParallelMechanism:
    par = par or SpsCuParams()
    base, plat = circle(par.R_A, par.theta_deg), circle(par.R_B, par.phi_deg)
    u_axes = {"U": [(1, 0, 0), (0, 1, 0)]}  # the factory's: column x, platform y
    cyl = Link(par.cylinder_mass, par.cylinder_inertia, com=par.cylinder_com)
    pis = Link(par.piston_mass, par.piston_inertia, com=par.piston_com)
    col = Link(par.column_mass, par.column_inertia, com=par.column_top, length=par.column_length)
    o = (0, 0, 0)
    return ParallelMechanism(
        "4-SPS/CU",
        Platform(par.platform_mass, par.platform_inertia, position=(0, 0, par.home_height)),
        (
            Leg("CU", o, o, (col,), actuated=None, name="centre", axes=u_axes),
            legs("SPS", base=base, platform=plat, links=(cyl, pis), lumped=lumped),
        ),
        gravity=par.gravity,
    )


def _same_arrays(m1: cl.Mechanism, m2: cl.Mechanism) -> None:
    c1, c2 = cl.compile_mechanism(m1), cl.compile_mechanism(m2)
    assert c1.nb == c2.nb and c1.nrow == c2.nrow
    for k in c1.model._fields:
        a, b = getattr(c1.model, k), getattr(c2.model, k)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), k


def test_ups_upu_rebuilt_bit_for_bit() -> None:
    pm = ups_upu_builder()
    home = pm.home_drives()
    _same_arrays(ups_upu_ideal(drives=list(home.values())), pm.build())
    drives = [cl.Sinusoid(0.004, math.pi, 0.3 * k, h) for k, h in enumerate(home.values())]
    _same_arrays(ups_upu_ideal(drives=drives), pm.build(drives))
    assert pm.joint_names[:3] == ("leg1.U", "leg1.P", "leg1.S")
    assert pm.joint_names[-3:] == ("leg5.U1", "leg5.P", "leg5.U2")


@pytest.mark.parametrize("lumped", [False, True])
def test_sps_cu_rebuilt_bit_for_bit(lumped: bool) -> None:
    pm = sps_cu_builder(lumped)
    lengths = [cl.Sinusoid(0.01, 2.0, k, 0.65) for k in range(4)]
    limbs = "lumped" if lumped else "two-body"
    _same_arrays(sps_cu(limbs=limbs, lengths=lengths), pm.build(lengths))
    assert pm.leg_names == ("centre", "leg1", "leg2", "leg3", "leg4")
    assert pm.lumped is lumped
    # the inverse kinematics' model of a lumped mechanism is the two-body one
    _same_arrays(sps_cu(limbs="two-body", lengths=lengths), pm.ik_mechanism(lengths))


def delta(**kw) -> ParallelMechanism:
    return ParallelMechanism(
        "Delta",
        Platform(1.0, (0.005, 0.005, 0.01), position=(0, 0, -0.45)),
        legs(
            "RSS",
            base=circle(0.2, [0, 120, 240]),
            platform=circle(0.05, [0, 120, 240]),
            links=(rod(0.2, 0.3), rod(0.5, 0.1)),
            **kw,
        ),
        dof=3,
    )


ANG3 = [90, 210, 330]
ANG5 = [90, 162, 234, 306, 18]
# platform angles of the 5-PSS/UPU: a 5-fold symmetric layout is singular (the five rod
# lines lie on one hyperboloid); turned +30, +30, -30, -30, 0 deg: condition ~90 at home
PSS_TURN = [30, 30, -30, -30, 0]


def three(joints: str, links) -> ParallelMechanism:
    return ParallelMechanism(
        f"3-{joints}",
        Platform(5.0, (0.05, 0.05, 0.1), position=(0, 0, 0.5)),
        legs(
            joints,
            base=circle(0.3, [90, 210, 330]),
            platform=circle(0.15, [90, 210, 330]),
            links=links,
        ),
    )


def pss_upu(turn=PSS_TURN) -> ParallelMechanism:
    plat = circle(0.15, [a + d for a, d in zip(ANG5, turn, strict=True)])
    o = (0, 0, 0)
    return ParallelMechanism(
        "5-PSS/UPU",
        Platform(5.0, (0.05, 0.05, 0.1), position=(0, 0, 0.6)),
        (
            legs("PSS", base=circle(0.35, ANG5), platform=plat, links=(CARRIAGE, rod(0.4))),
            Leg("UPU", o, o, (rod(0.4), rod(0.4)), actuated=None, name="centre"),
        ),
        dof=5,
    )


def stewart() -> ParallelMechanism:
    b = [a + s for a in (0, 120, 240) for s in (-10, 10)]
    p = [a + s for a in (-60, 60, 180) for s in (10, -10)]
    p = p[1:] + p[:1]
    return ParallelMechanism(
        "6-UPS",
        Platform(5.0, (0.05, 0.05, 0.1), position=(0, 0, 0.6)),
        legs("UPS", base=circle(0.4, b), platform=circle(0.2, p), links=(rod(0.4), rod(0.4))),
    )


# (mechanism, Grubler-Kutzbach, idle spins, platform DOF) by hand:
# Delta: 10 bodies, 3 R (5 rows) + 12 S (3 rows) = 51: 60 - 51 = 9; 6 rod spins
# 3-RPS / 3-PRS: 7 bodies, 3 x (5 + 5 + 3) = 39: 3, no idle
# 5-PSS/UPU: 13 bodies, 5 x (5 + 3 + 3) + (4 + 5 + 4) = 68: 78 - 68 = 10; 5 rod spins
# 6-UPS: 13 bodies, 6 x (4 + 5 + 3) = 72: 6; 4UPS-UPU 5; 4-SPS/CU two-body 8 with 4 spins
MOBILITY = [
    (lambda: delta(parallelogram=0.06), 9, 6, 3),
    (lambda: three("RPS", (rod(0.3), rod(0.3))), 3, 0, 3),
    (lambda: three("PRS", (CARRIAGE, rod(0.45))), 3, 0, 3),
    (pss_upu, 10, 5, 5),
    (stewart, 6, 0, 6),
    (ups_upu_builder, 5, 0, 5),
    (lambda: sps_cu_builder(True), 8, 4, 4),
]


@pytest.mark.parametrize("make, grubler, idle, platform", MOBILITY)
def test_mobility(make, grubler: int, idle: int, platform: int) -> None:
    pm = make()
    mob = pm.check_mobility()
    assert (mob.grubler, mob.rank_dof, mob.idle, mob.platform) == (grubler, grubler, idle, platform)
    assert mob.actuators == platform


def _g(amplitude: float, centre: float = 0.0) -> cl.Sinusoid:
    """centre + amplitude (1 - cos(pi t)) / 2: rest to rest over 2 s."""
    return cl.Sinusoid(-0.5 * amplitude, math.pi, 0.5 * math.pi, centre + 0.5 * amplitude)


G3 = (_g(0.03), _g(0.02), _g(0.02, -0.45), (0, 0, 0), "none", "xyz")
FOLLOW = {
    # mechanism, trajectory: (x, y, z, angles, mode, prescribed positions)
    "delta": (lambda: delta(parallelogram=0.06), G3),
    "3-RPS": (
        lambda: three("RPS", (rod(0.3), rod(0.3))),
        (0, 0, _g(0.03, 0.5), (_g(0.05), _g(0.05), 0), "axis", "z"),
    ),
    "3-PRS": (
        lambda: three("PRS", (CARRIAGE, rod(0.45))),
        (0, 0, _g(0.03, 0.5), (_g(0.05), _g(-0.04), 0), "axis", "z"),
    ),
    "5-PSS/UPU": (
        pss_upu,
        (_g(0.02), _g(-0.01), _g(0.02, 0.6), (_g(0.05), _g(0.03), 0), "axis", "xyz"),
    ),
    "6-UPS": (
        stewart,
        (_g(0.02), _g(0.01), _g(0.03, 0.6), (_g(0.05), _g(-0.04), _g(0.06)), "full", "xyz"),
    ),
}


@pytest.mark.parametrize("name", list(FOLLOW))
def test_ideal_mechanism_follows_the_trajectory(name: str) -> None:
    """IK drives -> forward dynamics: the platform follows the prescribed coordinates to
    1e-9 m and 1e-9 rad over 1 s (the IK samples every 0.01 s; quintic drives)."""
    make, (x, y, z, angles, mode, pos) = FOLLOW[name]
    pm = make()
    tr = PlatformTrajectory(x, y, z, angles=angles, mode=mode, positions=tuple(pos))
    ts = np.linspace(0.0, 1.0, 101)
    ik = inverse_kinematics(
        pm.build(), tr, platform_marker=pm.platform_marker, actuators=pm.actuators, times=ts
    )
    r = cl.simulate(pm.build(drives_from_ik(ik)), 1.0, dt_out=0.01, rtol=1e-11, atol=1e-13)
    assert r.success, r.message
    p = r.position("platform")
    ref = np.array([tr.position(t) for t in r.t])
    idx = ["xyz".index(c) for c in tr.positions]
    assert np.max(np.abs(p[:, idx] - ref[:, idx])) < 1e-9
    R = r.rotation("platform")
    if mode == "full":
        err = max(np.linalg.norm(R[k] - tr.rotation(t)) for k, t in enumerate(r.t))
        assert err < 1e-9
    elif mode == "axis":
        err = max(np.linalg.norm(R[k][:, 2] - tr.normal(t)) for k, t in enumerate(r.t))
        assert err < 1e-9


# --------------------------------------------------------------------------- refusals
def test_bad_legs_are_refused_naming_the_leg() -> None:
    with pytest.raises(cl.ModelError, match="unknown joint letter 'X'"):
        Leg("UPX", (1, 0, 0), (0.5, 0, 0), (rod(0.3), rod(0.3)))
    with pytest.raises(cl.ModelError, match="not a supported leg"):
        Leg("SSS", (1, 0, 0), (0.5, 0, 0), (rod(0.3), rod(0.3)))
    with pytest.raises(cl.ModelError, match="has 2 link"):
        Leg("UPS", (1, 0, 0), (0.5, 0, 0), (rod(0.3),))
    with pytest.raises(cl.ModelError, match="needs its length"):
        Leg("PRS", (1, 0, 0), (0.5, 0, 0), (CARRIAGE, Link(1.0, (0.01, 0.01, 0.01))))
    with pytest.raises(cl.ModelError, match="actuator drives a P or C"):
        Leg("UPS", (1, 0, 0), (0.5, 0, 0), (rod(0.3), rod(0.3)), actuated="S")
    with pytest.raises(cl.ModelError, match="only for RSS"):
        Leg("RUS", (1, 0, 0), (0.5, 0, 0), (rod(0.3), rod(0.3)), parallelogram=0.05)
    # a rod too short to reach the platform from its rail: refused naming leg and link
    with pytest.raises(cl.ModelError, match=r"leg 'leg1' \(PRS\).*rod cannot reach"):
        three("PRS", (CARRIAGE, rod(0.1))).build()
    with pytest.raises(cl.ModelError, match=r"leg 'leg1' \(RSS\).*cannot reach"):
        delta(parallelogram=0.06).with_leg("leg1", links=(rod(0.05), rod(0.1))).build()


def test_mobility_mismatches_are_refused() -> None:
    # a Delta without its parallelograms: the platform also tilts (6 DOF, 3 motors)
    with pytest.raises(cl.ModelError, match="platform has 6 DOF.*declares dof = 3"):
        delta().build()
    # three RRR legs with parallel vertical axes: a planar mechanism in space, whose
    # revolute constraints are dependent (Grubler-Kutzbach -3, rank check 3)
    axes = {"R1": (0, 0, 1), "R2": (0, 0, 1), "R3": (0, 0, 1)}
    pm = ParallelMechanism(
        "3-RRR",
        Platform(1.0, (0.01, 0.01, 0.02), position=(0, 0, 0)),
        legs(
            "RRR",
            base=circle(0.5, [0, 120, 240]),
            platform=circle(0.1, [0, 120, 240]),
            links=(rod(0.3), rod(0.3)),
            axes=axes,
        ),
    )
    with pytest.raises(cl.ModelError, match="Grubler-Kutzbach gives -3 DOF but the rank check"):
        pm.build()
    # five PSS legs in a 5-fold symmetric layout: an actuation singularity at home
    with pytest.raises(cl.ModelError, match="do not determine the platform at home: 2 DOF"):
        pss_upu(turn=[0, 0, 0, 0, 0]).build()
    with pytest.raises(cl.ModelError, match="leg names must be unique"):
        a = Leg("UPS", (1, 0, 0), (0.5, 0, 0.5), (rod(0.3), rod(0.3)), name="a")
        ParallelMechanism("x", Platform(1.0, (1, 1, 1)), (a, a))


# Delta robot of ABB IRB 340 size after R. L. Williams II, "The Delta Parallel Robot:
# Kinematics Solutions" (Ohio University, 2016): base triangle side sB = 567 mm, platform
# side sP = 76 mm, upper arm L = 524 mm, parallelogram l = 1244 mm; the pairs (motor angles
# [deg], platform position [mm]) are the example table of the public implementation
# Pieces98/Deltarobot_Kinematics (README.md) of Williams' equations, which a second,
# independent implementation reproduced to 0.01 deg. Williams' crank pivots lie on the
# base triangle's side midpoints, wB = sB / (2 sqrt 3) from the centre, the parallelogram's
# platform ends on its vertices, uP = sP / sqrt 3; his angle is 0 with the arm horizontal
# and positive turning down, as the builder's.
WILLIAMS = [
    ((0.0, 0.0, 0.0), (0.0, 0.0, -1064.4517), 1e-4),
    ((10.0, 20.0, 30.0), (108.1354, -180.3484, -1243.5413), 1e-4),
    ((-20.5, -20.5, -20.5), (0.0, 0.0, -900.3195), 1e-4),
    ((47.5, -11.6, 21.4), (300.4598, 499.9385, -1099.8281), 1e-4),
    ((90.0, 90.0, 90.0), (0.0, 0.0, -1762.22), 5e-3),  # (z given to 10 um only)
]


@pytest.mark.parametrize("theta, position, tol_deg", WILLIAMS)
def test_delta_home_angles_against_williams_table(theta, position, tol_deg) -> None:
    """The crank angles the builder solves for a platform position (its home pose) against
    Williams' inverse kinematics table."""
    wb, up = 0.567 / (2.0 * math.sqrt(3.0)), 0.076 / math.sqrt(3.0)
    ang = [-90.0, 30.0, 150.0]
    pm = ParallelMechanism(
        "Delta (Williams)",
        Platform(1.0, (0.01, 0.01, 0.02), position=tuple(np.array(position) / 1000.0)),
        legs(
            "RSS",
            base=circle(wb, ang),
            platform=circle(up, ang),
            links=(rod(0.524), rod(1.244, 0.1)),
            parallelogram=0.1,
        ),
        dof=3,
    )
    got = np.degrees(list(pm.home_drives().values()))
    assert np.max(np.abs(got - np.array(theta))) < tol_deg, got


def test_the_actuated_joint_marked_in_the_string() -> None:
    """'_' before a letter marks the actuated joint, as the literature's underline."""
    a = Leg("U_PS", (1, 0, 0), (0.5, 0, 0.5), (rod(0.3), rod(0.3)))
    assert a.joints == "UPS" and a.actuated == "P"
    assert Leg("_RSS", (1, 0, 0), (0.5, 0, 0.5), (rod(0.3), rod(0.5))).actuated == "R"
    assert Leg("U_PU", (0, 0, 0), (0, 0, 0), (rod(0.3), rod(0.3))).actuated == "P"
    assert Leg("U_PU", (0, 0, 0), (0, 0, 0), (rod(0.3), rod(0.3)), actuated="P").actuated == "P"
    with pytest.raises(cl.ModelError, match="actuator drives a P or C"):
        Leg("UP_S", (1, 0, 0), (0.5, 0, 0.5), (rod(0.3), rod(0.3)))
    with pytest.raises(cl.ModelError, match="marks the actuated joint once"):
        Leg("U__PS", (1, 0, 0), (0.5, 0, 0.5), (rod(0.3), rod(0.3)))
    with pytest.raises(cl.ModelError, match="marks 'P' actuated"):
        Leg("U_PS", (1, 0, 0), (0.5, 0, 0.5), (rod(0.3), rod(0.3)), actuated=None)
