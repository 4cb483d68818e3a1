"""General inverse kinematics (physics.md e.2) and actuator drives.

Oracles: the forward simulation of the ideal mechanism driven by the IK drives must follow
the prescribed platform trajectory (4UPS-UPU in mode "axis", a 4-SPS/CU built here in mode
"full"); exact rates against finite differences of s; the UPU's own constraint equation for
the parasitic twist; an independent 6x6 pose Jacobian for the conditioning (mechanisms.md
1.4: sigma_min 0.096 at home); refusal of the singular centrally symmetric layout and of a
trajectory that crosses a dead centre.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import clearance as cl
import clearance.mechanisms.ups_upu as ups
from clearance.analysis.ik import (
    IKResult,
    PlatformTrajectory,
    apply_drives,
    drives_from_ik,
    inverse_kinematics,
    rest_to_rest,
    rotation_from_angles,
)
from clearance.model.bodies import quaternion_to_rotation
from clearance.model.functions import HermiteSpline, Polynomial

LEGS = [f"drive_{k}" for k in range(1, 6)]
# mechanisms.md 1.5: rest-to-rest g(t) = (1 - cos(pi t)) / 2 over [0, 2] s
UPU_TRAJ = rest_to_rest((0.0, 0.0, 0.70), (0.02, 0.02, 0.03), (0.05, 0.05, 0.0), 2.0)
TIMES = np.linspace(0.0, 2.0, 41)  # h = 0.05 s: quintic Hermite error ~1e-12 m


def _rot_angle(R: np.ndarray) -> float:
    """Rotation angle [rad] of a rotation matrix close to I (robust near 0)."""
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2
    return float(math.atan2(np.linalg.norm(w), (np.trace(R) - 1) / 2))


def _twist(R_target: np.ndarray, R: np.ndarray) -> float:
    M = R_target.T @ R
    return math.atan2(M[1, 0] - M[0, 1], M[0, 0] + M[1, 1])


@pytest.fixture(scope="module")
def upu() -> cl.Mechanism:
    return ups.ups_upu_ideal()


@pytest.fixture(scope="module")
def upu_ik(upu: cl.Mechanism) -> IKResult:
    return inverse_kinematics(
        upu, UPU_TRAJ, platform_marker="platform", actuators=LEGS, times=TIMES
    )


# ------------------------------------------------------------------ trajectory helpers
@pytest.mark.parametrize("shape", ["cosine", "sin"])
def test_rest_to_rest_shape_and_period(shape: str) -> None:
    tr = rest_to_rest((0.1, 0, 0.7), (0.02, 0, 0.03), (0.05, 0.0, -0.04), 2.0, shape=shape)
    for t in (0.0, 0.3, 1.0, 1.7):
        g = (1 - math.cos(math.pi * t)) / 2 if shape == "cosine" else math.sin(math.pi * t)
        gd = (
            math.pi / 2 * math.sin(math.pi * t)
            if shape == "cosine"
            else math.pi * math.cos(math.pi * t)
        )
        assert np.allclose(tr.position(t), [0.1 + 0.02 * g, 0.0, 0.7 + 0.03 * g], atol=1e-15)
        assert np.allclose(tr.velocity(t), [0.02 * gd, 0.0, 0.03 * gd], atol=1e-15)
        assert tr.angles[2](t) == pytest.approx(-0.04 * g, abs=1e-15)
    if shape == "cosine":  # at rest at both ends, extreme pose at T / 2
        assert np.allclose(tr.velocity(0.0), 0) and np.allclose(tr.velocity(2.0), 0, atol=1e-15)
        assert np.allclose(tr.position(1.0), [0.12, 0.0, 0.73])
    R = tr.rotation(0.4)
    a = [f(0.4) for f in tr.angles]
    assert np.allclose(R, rotation_from_angles("xyz", a))
    # physics.md e.2: the normal of Rx(alpha) Ry(beta) is (sin b, -sin a cos b, cos a cos b)
    n = rotation_from_angles("xy", [0.3, -0.2]) @ [0, 0, 1]
    want = [math.sin(-0.2), -math.sin(0.3) * math.cos(-0.2), math.cos(0.3) * math.cos(-0.2)]
    assert np.allclose(n, want, atol=1e-15)
    with pytest.raises(cl.ModelError, match="shape"):
        rest_to_rest((0, 0, 0), (0, 0, 0), (0, 0, 0), 2.0, shape="linear")
    with pytest.raises(cl.ModelError, match="mode"):
        PlatformTrajectory(0, 0, 0, (0, 0, 0), mode="tilt")


# ------------------------------------------------------------------ (a) 4UPS-UPU, mode "axis"
def test_upu_forward_simulation_follows_trajectory(upu: cl.Mechanism, upu_ik: IKResult) -> None:
    """The ideal mechanism driven by the IK drives follows x, y, z to 1e-9 m and the platform
    normal to 1e-9 rad, also between the IK samples; its twist equals the IK's."""
    driven = apply_drives(upu, drives_from_ik(upu_ik))
    assert upu.drivers["drive_1"].function != driven.drivers["drive_1"].function  # not mutated
    t_out = np.union1d(TIMES, np.linspace(0.0, 2.0, 173))  # knots and points between them
    r = cl.simulate(driven, 2.0, t_out=t_out, rtol=1e-11, atol=1e-13)
    assert r.success, r.message
    P = r.position("platform")
    Rs = [quaternion_to_rotation(p) for p in r.euler_parameters("platform")]
    pos_err = max(np.max(np.abs(p - UPU_TRAJ.position(t))) for p, t in zip(P, r.t, strict=True))
    nrm_err = max(
        math.asin(min(1.0, np.linalg.norm(np.cross(R[:, 2], UPU_TRAJ.normal(t)))))
        for R, t in zip(Rs, r.t, strict=True)
    )
    at_knots = np.isin(r.t, TIMES)
    tw_sim = np.array([_twist(UPU_TRAJ.rotation(t), R) for R, t in zip(Rs, r.t, strict=True)])
    tw_err = np.max(np.abs(tw_sim[at_knots] - upu_ik.twist))
    print(f"4UPS-UPU: position {pos_err:.2e} m, normal {nrm_err:.2e} rad, twist {tw_err:.2e}")
    assert pos_err < 1e-9 and nrm_err < 1e-9 and tw_err < 1e-9
    # the IK itself satisfies the pose drivers to the assembly tolerance
    assert np.max(np.abs(upu_ik.position - [UPU_TRAJ.position(t) for t in TIMES])) < 1e-11


# ------------------------------------------------------------------ (b) exact rates
def test_rates_match_finite_differences(upu: cl.Mechanism, upu_ik: IKResult) -> None:
    """s_dot = g_q v and s_ddot = g_q v_dot - gamma_g (physics.md e.1) against central
    differences of s from separate position analyses."""
    h1, h2 = 1e-4, 1e-3  # truncation ~h^2 s'''/6, round-off ~1e-13 / h (resp. / h^2)
    for t in (0.3, 0.95, 1.55):
        ts = [t - h2, t - h1, t, t + h1, t + h2]
        ik = inverse_kinematics(upu, UPU_TRAJ, platform_marker="platform", actuators=LEGS, times=ts)
        s = ik.s
        fd1 = (s[3] - s[1]) / (2 * h1)
        fd2 = (s[4] - 2 * s[2] + s[0]) / h2**2
        assert np.max(np.abs(fd1 - ik.s_dot[2])) < 1e-8
        assert np.max(np.abs(fd2 - ik.s_ddot[2])) < 1e-6
        assert np.max(np.abs(ik.s_ddot[2])) > 0.01  # a genuine test: accelerations are O(0.1)
    # rest to rest: zero leg velocities at both ends, and the extreme pose at t = 1 s
    assert np.max(np.abs(upu_ik.s_dot[[0, -1]])) < 1e-12
    assert np.max(np.abs(upu_ik.s_dot[20])) < 1e-12
    # the drives reproduce the samples and rates (HermiteSpline interpolates them; the
    # Bernstein -> power basis conversion costs ~1e-11 relative in the second derivative)
    d = drives_from_ik(upu_ik)["drive_3"]
    assert isinstance(d, HermiteSpline)
    for k in (0, 7, 40):
        want = (upu_ik.s[k, 2], upu_ik.s_dot[k, 2], upu_ik.s_ddot[k, 2])
        assert d.derivatives(TIMES[k]) == pytest.approx(want, rel=1e-10, abs=1e-13)


# ------------------------------------------------------------------ (c) parasitic twist
def test_parasitic_twist_and_naive_leg_lengths(upu: cl.Mechanism, upu_ik: IKResult) -> None:
    """The consistent pose differs from the naive Rx(alpha) Ry(beta) by a twist about the
    normal. Mechanism-independent facts: the solved orientation satisfies the UPU condition
    (rod axis y) . (platform axis x) = 0 with the rod aligned by Rx(t1) Ry(t2); the twist is
    0 for alpha = beta = 0 and nonzero otherwise; leg 5 (at the centre) is unaffected."""
    A = [np.array(upu.markers[f"A{k}_ground"].position) for k in range(1, 6)]
    B = [np.array(upu.markers[f"B{k}_platform"].position) for k in range(1, 5)] + [np.zeros(3)]

    def naive(tr: PlatformTrajectory, t: float) -> np.ndarray:
        return np.array(
            [
                np.linalg.norm(tr.position(t) + tr.rotation(t) @ b - a)
                for a, b in zip(A, B, strict=True)
            ]
        )

    for k, t in enumerate(TIMES):
        p, R = upu_ik.position[k], upu_ik.rotation[k]
        u = p / np.linalg.norm(p)  # leg 5 from A_5 = O to the platform centre
        R_leg = rotation_from_angles("xy", [math.atan2(-u[1], u[2]), math.asin(u[0])])
        assert np.allclose(R_leg[:, 2], u, atol=1e-14)
        assert abs(R_leg[:, 1] @ R[:, 0]) < 1e-12  # the UPU twist condition
        R_naive = UPU_TRAJ.rotation(t)
        if UPU_TRAJ.angles[0](t) > 0.01:  # tilted: the naive pose violates the condition
            assert abs(R_leg[:, 1] @ R_naive[:, 0]) > 1e-4 and abs(upu_ik.twist[k]) > 1e-4
    k1 = 20  # t = 1 s: the extreme pose (0.02, 0.02, 0.73, 0.05, 0.05)
    assert np.allclose(upu_ik.position[k1], [0.02, 0.02, 0.73], atol=1e-12)
    psi = upu_ik.twist[k1]
    diff = naive(UPU_TRAJ, 1.0) - upu_ik.s[k1]
    print(f"twist at t = 1 s: {psi:.4e} rad; naive - consistent leg lengths [mm]: {diff * 1e3}")
    # physics.md e.2 table: -3.88e-3 rad (the twist depends only on the UPU leg)
    assert psi == pytest.approx(-3.88e-3, abs=0.01e-3)
    assert np.argmin(upu_ik.twist) == k1
    assert abs(diff[4]) < 1e-12  # the UPU leg ends at the centre: no twist effect
    # our layout (platform = base + -30 deg): the error is first order in the twist
    assert 0.2e-3 < np.max(np.abs(diff)) < 0.3e-3
    worst = max(np.max(np.abs(naive(UPU_TRAJ, t) - upu_ik.s[k])) for k, t in enumerate(TIMES))
    assert worst == pytest.approx(np.max(np.abs(diff)), rel=1e-9)  # largest at the extreme
    # pure translation: no twist, naive = consistent
    tr0 = rest_to_rest((0.0, 0.0, 0.70), (0.03, -0.02, 0.02), (0.0, 0.0, 0.0), 2.0)
    ik0 = inverse_kinematics(upu, tr0, platform_marker="platform", actuators=LEGS, times=[0.5, 1])
    assert np.max(np.abs(ik0.twist)) < 1e-14
    assert np.max(np.abs(naive(tr0, 1.0) - ik0.s[1])) < 1e-12
    # the other two poses of the physics.md e.2 table
    for (x, y, z, a, b), want in (
        ((0.0, 0.0, 0.70, 0.05, 0.05), -2.50e-3),
        ((0.05, -0.03, 0.65, 0.10, -0.08), 4.31e-3),
    ):
        ik = inverse_kinematics(
            upu,
            PlatformTrajectory(x, y, z, (a, b, 0.0)),
            platform_marker="platform",
            actuators=LEGS,
            times=[0.0],
        )
        assert ik.twist[0] == pytest.approx(want, abs=0.01e-3)


# ------------------------------------------------------------------ (d) singular layouts
def test_centrally_symmetric_layout_is_refused() -> None:
    """mechanisms.md 1.4: base and platform angles equal (45/135/225/315) is singular at
    every horizontal pose; the home pose at t = 0 is refused, naming the legs."""
    mech = ups.ups_upu_ideal({"phi_deg": (45.0, 135.0, 225.0, 315.0)})
    with pytest.raises(cl.KinematicsError) as err:
        inverse_kinematics(mech, UPU_TRAJ, platform_marker="platform", actuators=LEGS, times=TIMES)
    msg = str(err.value)
    print(msg)
    assert "singular at t = 0 s" in msg and "2 near-dependent direction(s)" in msg
    assert all(f"drive_{k} (joint P_{k}" in msg for k in range(1, 6))
    # with the check relaxed the IK runs; the layout stays nearly singular along the whole
    # trajectory (condition number >= ~1e6 even at the tilted extreme pose)
    ik = inverse_kinematics(
        mech,
        UPU_TRAJ,
        platform_marker="platform",
        actuators=LEGS,
        times=TIMES[::4],
        max_condition=math.inf,
    )
    assert ik.sigma_min[0] < 1e-14 and ik.max_condition > 1e15
    assert np.min(ik.condition) > 1e6


def _crank(theta0: float) -> cl.Mechanism:
    """A crank (revolute about z at O, pin at r = 0.1 m) pushed by an S-P-S cylinder from
    G = (0.3, 0, 0): dead centres at theta = 0 and pi; the limb spin is an idle DOF."""
    r, G = 0.1, np.array([0.3, 0.0, 0.0])
    pin = r * np.array([math.cos(theta0), math.sin(theta0), 0.0])
    u = (pin - G) / np.linalg.norm(pin - G)
    R = np.column_stack([np.cross([0, 0, 1.0], u), [0, 0, 1.0], u])  # body z along the leg
    mech = cl.Mechanism("crank", gravity=(0, 0, -9.81))
    mech.add(
        cl.Body(
            "crank", 1.0, (0.002, 0.002, 0.003), orientation=rotation_from_angles("z", [theta0])
        ),
        cl.Body("cyl", 0.5, (0.001, 0.001, 0.0005), position=tuple(G + 0.05 * u), orientation=R),
        cl.Body("rod", 0.3, (0.001, 0.001, 0.0005), position=tuple(pin - 0.05 * u), orientation=R),
        cl.Marker("O_g", "ground"),
        cl.Marker("O_c", "crank"),
        cl.Revolute("R0", "O_g", "O_c"),
        cl.Marker("G_g", "ground", tuple(G)),
        cl.Marker("G_c", "cyl", (0, 0, -0.05)),
        cl.Spherical("S_G", "G_g", "G_c"),
        cl.Marker("P_c", "cyl", (0, 0, -0.05)),
        cl.Marker("P_r", "rod", (0, 0, 0.05)),
        cl.Prismatic("P", "P_c", "P_r"),
        cl.Marker("pin_c", "crank", (r, 0, 0)),
        cl.Marker("pin_r", "rod", (0, 0, 0.05)),
        cl.Spherical("S_pin", "pin_c", "pin_r"),
        cl.PrismaticDriver("drive", "P", float(np.linalg.norm(pin - G))),
    )
    return mech


def test_dead_centre_crossing_is_refused() -> None:
    """theta(t) = -0.3 + 0.6 t passes the dead centre theta = 0 at t = 0.5 s between two
    samples; no sample is near-singular, but det of the drive Jacobian changes sign."""
    mech = _crank(-0.3)
    tr = PlatformTrajectory(0, 0, 0, (0.0, 0.0, Polynomial([-0.3, 0.6])), mode="full")
    times = np.linspace(0.0, 1.0, 10)
    with pytest.raises(cl.KinematicsError) as err:
        inverse_kinematics(mech, tr, platform_marker="crank", actuators=["drive"], times=times)
    msg = str(err.value)
    assert "between t = 0.444444 s and t = 0.555556 s" in msg and "drive (joint P" in msg
    ik = inverse_kinematics(
        mech, tr, platform_marker="crank", actuators=["drive"], times=times, check_crossing=False
    )
    assert ik.idle_dof == 1 and ik.max_condition < 1e3  # the samples alone look harmless
    # away from the dead centre the same mechanism is accepted; s = |pin - G| exactly
    tr2 = PlatformTrajectory(0, 0, 0, (0.0, 0.0, Polynomial([-0.3, -0.5])), mode="full")
    ik2 = inverse_kinematics(mech, tr2, platform_marker="crank", actuators=["drive"], times=times)
    th = -0.3 - 0.5 * times
    L = np.hypot(0.1 * np.cos(th) - 0.3, 0.1 * np.sin(th))
    assert np.max(np.abs(ik2.s[:, 0] - L)) < 1e-12
    Ld = 0.03 * np.sin(th) * -0.5 / L  # d/dt sqrt(0.1 - 0.06 cos th)
    assert np.max(np.abs(ik2.s_dot[:, 0] - Ld)) < 1e-12


# ------------------------------------------------------------------ (e) conditioning report
def test_conditioning_report(upu: cl.Mechanism, upu_ik: IKResult) -> None:
    """Full drive Jacobian (66 x 66): sigma_min ~0.022, condition ~113 along the trajectory;
    cross-check with the 6 x 6 Jacobian of (5 leg lengths, UPU twist condition) w.r.t. the
    platform pose, whose sigma_min mechanisms.md 1.4 gives as 0.096 (condition ~22)."""
    print(upu_ik.summary())
    assert upu_ik.idle_dof == 0
    assert 0.02 < upu_ik.min_sigma < 0.03 and 100 < upu_ik.max_condition < 130
    assert upu_ik.sigma_min.shape == TIMES.shape and np.all(upu_ik.condition >= 1)
    A = [np.array(upu.markers[f"A{k}_ground"].position) for k in range(1, 6)]
    B = [np.array(upu.markers[f"B{k}_platform"].position) for k in range(1, 5)] + [np.zeros(3)]

    def f(p: np.ndarray, R: np.ndarray) -> np.ndarray:
        u = p / np.linalg.norm(p)
        R_leg = rotation_from_angles("xy", [math.atan2(-u[1], u[2]), math.asin(u[0])])
        lengths = [np.linalg.norm(p + R @ b - a) for a, b in zip(A, B, strict=True)]
        return np.array([*lengths, R_leg[:, 1] @ R[:, 0]])

    def rotvec(w: np.ndarray) -> np.ndarray:
        th = np.linalg.norm(w)
        return rotation_from_angles("z", [0.0]) if th == 0 else _axis_angle(w / th, th)

    p0, h = np.array([0.0, 0.0, 0.70]), 1e-6
    J = np.zeros((6, 6))
    for i in range(6):
        e = np.zeros(6)
        e[i] = h
        J[:, i] = (f(p0 + e[:3], rotvec(e[3:])) - f(p0 - e[:3], rotvec(-e[3:]))) / (2 * h)
    sv = np.linalg.svd(J, compute_uv=False)
    assert sv[-1] == pytest.approx(0.096, abs=0.001) and sv[0] / sv[-1] == pytest.approx(22, 0.05)


def _axis_angle(k: np.ndarray, th: float) -> np.ndarray:
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K


# ------------------------------------------------------------------ 4-SPS/CU, mode "full"
def _sps_cu() -> cl.Mechanism:
    """4-SPS/CU with two-body limbs (mechanisms.md 2.2-2.3, validation variant): C on the
    ground (axis z), U at the platform centre (column x, platform y), limbs S-P-S."""
    RA, RB, z0 = 0.40, 0.20, 0.60
    th = np.radians([45.0, 135.0, 225.0, 315.0])
    ph = np.radians([75.0, 165.0, 195.0, 285.0])
    C = np.array([0.0, 0.0, z0])
    mech = cl.Mechanism("4-SPS/CU", gravity=(0, 0, -9.81))
    mech.add(
        cl.Body("platform", 10.0, (0.15625, 0.15625, 0.3125), position=tuple(C)),
        cl.Body("column", 2.0, (0.1067, 0.1067, 0.001), position=(0.0, 0.0, z0 - 0.4)),
        cl.Marker("C_g", "ground"),
        cl.Marker("C_c", "column", (0.0, 0.0, -(z0 - 0.4))),
        cl.Cylindrical("C", "C_g", "C_c"),
        cl.Marker.on_axis("U_c", "column", (0.0, 0.0, 0.4), axis=(1, 0, 0)),
        cl.Marker.on_axis("U_p", "platform", axis=(0, 1, 0)),
        cl.Universal("U", "U_c", "U_p"),
    )
    for k in range(4):
        n = k + 1
        a = RA * np.array([math.cos(th[k]), math.sin(th[k]), 0.0])
        b = RB * np.array([math.cos(ph[k]), math.sin(ph[k]), 0.0])
        u = (C + b - a) / np.linalg.norm(C + b - a)
        x = np.cross([0.0, 0.0, 1.0], u)
        x /= np.linalg.norm(x)
        R = np.column_stack([x, np.cross(u, x), u])
        mech.add(
            cl.Body(
                f"cyl_{n}", 2.0, (0.028, 0.028, 0.001), position=tuple(a + 0.2 * u), orientation=R
            ),
            cl.Body(
                f"pis_{n}",
                1.5,
                (0.021, 0.021, 0.0005),
                position=tuple(C + b - 0.2 * u),
                orientation=R,
            ),
            cl.Marker(f"A{n}_g", "ground", tuple(a)),
            cl.Marker(f"A{n}_c", f"cyl_{n}", (0, 0, -0.2)),
            cl.Spherical(f"SA_{n}", f"A{n}_g", f"A{n}_c"),
            cl.Marker(f"B{n}_c", f"cyl_{n}", (0, 0, -0.2)),
            cl.Marker(f"B{n}_p", f"pis_{n}", (0, 0, 0.2)),
            cl.Prismatic(f"P_{n}", f"B{n}_c", f"B{n}_p"),
            cl.Marker(f"B{n}_plat", "platform", tuple(b)),
            cl.Marker(f"B{n}_s", f"pis_{n}", (0, 0, 0.2)),
            cl.Spherical(f"SB_{n}", f"B{n}_plat", f"B{n}_s"),
            cl.PrismaticDriver(f"limb_{n}", f"P_{n}", float(np.linalg.norm(C + b - a))),
        )
    return mech


def test_sps_cu_full_orientation_follows_trajectory() -> None:
    """mechanisms.md 2.3: z = 0.60 + 0.05 g, (psi, t1, t2) = (0.10, 0.05, 0.05) g with
    R = Rz(psi) Rx(t1) Ry(t2), consistent with the CU by construction: the general method
    reaches it exactly (twist 0) and the driven mechanism follows it to 1e-9 m / rad."""
    mech = _sps_cu()
    tr = rest_to_rest(
        (0.0, 0.0, 0.60), (0.0, 0.0, 0.05), (0.10, 0.05, 0.05), 2.0, sequence="zxy", mode="full"
    )
    limbs = [f"limb_{n}" for n in range(1, 5)]
    ik = inverse_kinematics(mech, tr, platform_marker="platform", actuators=limbs, times=TIMES)
    print(ik.summary())
    assert ik.idle_dof == 4  # the spins of the four S-P-S limbs
    assert np.max(np.abs(ik.twist)) < 1e-12
    assert np.allclose(ik.s.min(axis=0), ik.s[0], atol=1e-12)  # home is the shortest
    r = cl.simulate(
        apply_drives(mech, drives_from_ik(ik)),
        2.0,
        t_out=np.linspace(0.0, 2.0, 131),
        rtol=1e-11,
        atol=1e-13,
    )
    assert r.success, r.message
    pos_err = max(
        np.max(np.abs(p - tr.position(t))) for p, t in zip(r.position("platform"), r.t, strict=True)
    )
    rot_err = max(
        _rot_angle(tr.rotation(t).T @ quaternion_to_rotation(q))
        for q, t in zip(r.euler_parameters("platform"), r.t, strict=True)
    )
    print(f"4-SPS/CU: position {pos_err:.2e} m, orientation {rot_err:.2e} rad")
    assert pos_err < 1e-9 and rot_err < 1e-9


# ------------------------------------------------------------------ input validation
def test_input_errors(upu: cl.Mechanism, upu_ik: IKResult) -> None:
    kw = dict(platform_marker="platform", times=[0.0])
    with pytest.raises(cl.ModelError, match="PrismaticDriver"):
        inverse_kinematics(upu, UPU_TRAJ, actuators=["U_1"], **kw)
    with pytest.raises(cl.ModelError, match="platform_marker"):
        inverse_kinematics(upu, UPU_TRAJ, actuators=LEGS, platform_marker="nope", times=[0.0])
    with pytest.raises(cl.ModelError, match="times"):
        inverse_kinematics(upu, UPU_TRAJ, actuators=LEGS, platform_marker="platform", times=[1, 0])
    with pytest.raises(cl.ModelError, match="drives"):
        apply_drives(upu, {"U_1": 0.7})
    d = apply_drives(upu, {"drive_1": 0.75})
    assert d.drivers["drive_1"].function == cl.Constant(0.75)
    # a marker with the body's axes at its origin gives the same answer as the body name
    m2 = upu.copy().add(cl.Marker("centre", "platform"))
    ik = inverse_kinematics(m2, UPU_TRAJ, actuators=LEGS, platform_marker="centre", times=TIMES[:3])
    assert np.allclose(ik.s, upu_ik.s[:3], atol=1e-12)
