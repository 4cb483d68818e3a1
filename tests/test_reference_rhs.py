"""Compiled right-hand side vs the independent NumPy reference (`reference_rhs`).

Mechanisms: a spatial double pendulum (spherical joints), a chain using every joint type
with prismatic/distance drivers, a set of pose drivers (position, orientation full/axis) with
forces and torques in both frames and a spring-damper-actuator; bodies with full
non-diagonal inertia; random non-assembled states and random velocities. The reference is
itself checked by finite differences (physics.md c.6), and the compiled kernel is run once
in pure Python (NUMBA_DISABLE_JIT=1) in a subprocess.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import zlib
from pathlib import Path

import numpy as np
import pytest

import clearance as cl
from clearance.dynamics.reference import constraint_rows, reference_rhs
from clearance.dynamics.rhs import make_work, rhs
from clearance.kinds import Solver

RTOL = 1e-9
BAUMGARTE = [(5.0, 5.0), (12.0, 3.0)]


# --------------------------------------------------------------------------- mechanisms
def _inertia(rng: np.random.Generator, scale: float = 0.1) -> np.ndarray:
    """A random full (non-diagonal) inertia tensor satisfying the triangle inequality."""
    a, b = scale * rng.uniform(0.5, 1.5, size=2)
    c = rng.uniform(abs(a - b) + 0.1 * scale, a + b)  # I1 + I2 >= I3 for every permutation
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    J = q @ np.diag([a, b, c]) @ q.T
    return 0.5 * (J + J.T)


def _rot(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def double_pendulum() -> cl.Mechanism:
    """Two bars hanging by spherical joints (ground - b1 - b2), non-diagonal inertia."""
    m = cl.Mechanism("double_pendulum")
    m.add(
        cl.Body("b1", 1.3, (0.04, 0.05, 0.02), position=(0.0, 0.0, -0.5)),
        cl.Body(
            "b2",
            2.1,
            [[0.07, 0.004, -0.006], [0.004, 0.06, 0.005], [-0.006, 0.005, 0.03]],
            position=(0.0, 0.0, -1.5),
        ),
        cl.Marker("g0", cl.GROUND, (0.0, 0.0, 0.0)),
        cl.Marker("b1_top", "b1", (0.0, 0.0, 0.5)),
        cl.Marker("b1_bot", "b1", (0.0, 0.0, -0.5)),
        cl.Marker("b2_top", "b2", (0.01, 0.0, 0.5)),
        cl.Spherical("s1", "g0", "b1_top"),
        cl.Spherical("s2", "b1_bot", "b2_top"),
    )
    return m


def all_joints(seed: int = 1) -> cl.Mechanism:
    """ground -R- b1 -U- b2 -C- b3 -P- b4 -Fixed- b5 -S- b6, with prismatic drivers on C and
    P, a length and a squared distance driver, a spring-damper-actuator, gravity along a
    skew direction. 36 velocity coordinates, 27 joint + 4 driver rows."""
    rng = np.random.default_rng(seed)
    m = cl.Mechanism("all_joints", gravity=(0.5, -1.0, -9.81))
    names = [f"b{k}" for k in range(1, 7)]
    for n in names:
        m.add(
            cl.Body(
                n,
                float(rng.uniform(0.5, 3.0)),
                _inertia(rng),
                position=tuple(rng.standard_normal(3)),
                orientation=_rot(rng),
            )
        )
    kinds = [cl.Revolute, cl.Universal, cl.Cylindrical, cl.Prismatic, cl.Fixed, cl.Spherical]
    prev = cl.GROUND
    for k, (n, J) in enumerate(zip(names, kinds, strict=True)):
        mi, mj = f"j{k}_i", f"j{k}_j"
        m.add(
            cl.Marker(mi, prev, tuple(0.3 * rng.standard_normal(3)), _rot(rng)),
            cl.Marker(mj, n, tuple(0.3 * rng.standard_normal(3)), _rot(rng)),
            J(f"joint{k}", mi, mj),
        )
        prev = n
    m.add(
        cl.PrismaticDriver("drv_c", "joint2", cl.Sinusoid(0.1, 2.0, 0.3, 0.2)),
        cl.PrismaticDriver("drv_p", "joint3", cl.Polynomial((0.1, 0.05, -0.2, 0.3))),
        cl.Marker("g_dist", cl.GROUND, (0.4, -0.2, 0.1)),
        cl.Marker("b6_dist", "b6", (0.1, 0.2, -0.3)),
        cl.Marker("b1_dist", "b1", (-0.1, 0.05, 0.2)),
        cl.DistanceDriver("drv_len", "g_dist", "b6_dist", cl.Sinusoid(0.2, 1.5, 0.0, 1.2)),
        cl.DistanceDriver(
            "drv_sq", "b1_dist", "b6_dist", cl.Polynomial((0.9, 0.2, 0.1)), squared=True
        ),
        cl.SpringDamper(
            "spring",
            "b1_dist",
            "b6_dist",
            stiffness=300.0,
            damping=4.0,
            free_length=0.5,
            actuator=cl.Sinusoid(3.0, 4.0, 0.1),
        ),
    )
    return m


def pose_drivers(seed: int = 2) -> cl.Mechanism:
    """Pose drivers of every kind, point forces and torques in both frames, a spring to the
    ground. p1: free body with OrientationDriver 'full' + PositionDriver x, y; p2: spherical
    to ground + OrientationDriver 'axis'; p3 -C- p4 with a prismatic driver, distance drivers
    (length to the ground, squared to p1)."""
    rng = np.random.default_rng(seed)
    m = cl.Mechanism("pose_drivers", gravity=(0.0, 0.0, -9.81))
    for n in ("p1", "p2", "p3", "p4"):
        m.add(
            cl.Body(
                n,
                float(rng.uniform(0.5, 3.0)),
                _inertia(rng),
                position=tuple(rng.standard_normal(3)),
                orientation=_rot(rng),
            )
        )
    ang = (
        cl.Sinusoid(0.3, 1.1, 0.2),
        cl.Polynomial((0.1, -0.4, 0.5)),
        cl.Sinusoid(0.2, 2.3, 1.0, 0.05),
    )
    m.add(
        cl.Marker("p1_m", "p1", (0.1, -0.2, 0.05), _rot(rng)),
        cl.OrientationDriver("or_full", "p1_m", ang, sequence="zyx", mode="full"),
        cl.PositionDriver("pos_x", "p1_m", (1.0, 0.2, 0.0), cl.Sinusoid(0.1, 3.0)),
        cl.PositionDriver("pos_y", "p1_m", (0.0, 1.0, 0.3), cl.Polynomial((0.2, 0.1))),
        cl.Marker("g_s", cl.GROUND, (0.2, 0.1, 0.5)),
        cl.Marker("p2_s", "p2", (0.0, 0.1, 0.3)),
        cl.Spherical("s_p2", "g_s", "p2_s"),
        cl.Marker("p2_ax", "p2", (0.0, 0.0, 0.0), _rot(rng)),
        cl.OrientationDriver(
            "or_axis",
            "p2_ax",
            (cl.Sinusoid(0.2, 1.7), 0.3, cl.Polynomial((0.0, 0.2, -0.1))),
            sequence="xyx",
            mode="axis",
        ),
        cl.Marker("p3_c", "p3", (0.1, 0.0, -0.2), _rot(rng)),
        cl.Marker("p4_c", "p4", (-0.05, 0.1, 0.1), _rot(rng)),
        cl.Cylindrical("cyl", "p3_c", "p4_c"),
        cl.PrismaticDriver("drv_cyl", "cyl", cl.Sinusoid(0.05, 2.0, 0.0, 0.3)),
        cl.Marker("g_d", cl.GROUND, (-0.3, 0.2, 0.0)),
        cl.Marker("p3_d", "p3", (0.2, 0.1, 0.0)),
        cl.Marker("p4_d", "p4", (0.0, -0.1, 0.2)),
        cl.Marker("p1_d", "p1", (0.05, 0.05, -0.1)),
        cl.DistanceDriver("dist_len", "g_d", "p3_d", cl.Polynomial((1.0, 0.1, -0.05))),
        cl.DistanceDriver("dist_sq", "p1_d", "p4_d", cl.Sinusoid(0.1, 1.0, 0.0, 1.1), squared=True),
        cl.PointForce("f_world", "p3_d", (0.3, -1.0, 2.0), cl.Sinusoid(5.0, 2.0, 0.5)),
        cl.PointForce("f_marker", "p2_ax", (1.0, 0.5, -0.2), 4.0, frame="marker"),
        cl.Marker("p4_f", "p4", (0.2, -0.1, 0.1), _rot(rng)),
        cl.PointForce("f_marker4", "p4_f", (0.0, 2.0, 1.0), cl.Polynomial((1.0, 2.0)), "marker"),
        cl.Torque("t_world", "p1_m", (0.0, 0.3, 1.0), cl.Sinusoid(1.5, 3.0)),
        cl.Torque("t_marker", "p4_f", (1.0, 0.0, 0.5), -2.0, frame="marker"),
        cl.SpringDamper(
            "sd_ground",
            "g_d",
            "p4_d",
            stiffness=150.0,
            damping=3.0,
            free_length=0.4,
            actuator=cl.Polynomial((0.5, -1.0)),
        ),
    )
    return m


def ground_as_j(seed: int = 3) -> cl.Mechanism:
    """Every joint type with the GROUND as body j (marker_j on the ground), prismatic and
    distance drivers ending on the ground, a spring-damper to the ground, Ramp/Tabulated
    drive functions."""
    rng = np.random.default_rng(seed)
    m = cl.Mechanism("ground_as_j", gravity=(0.0, -9.81, 0.0))
    kinds = [cl.Revolute, cl.Universal, cl.Cylindrical, cl.Prismatic, cl.Fixed, cl.Spherical]
    for k, J in enumerate(kinds):
        n = f"q{k}"
        m.add(
            cl.Body(
                n,
                float(rng.uniform(0.5, 3.0)),
                _inertia(rng),
                position=tuple(rng.standard_normal(3)),
                orientation=_rot(rng),
            ),
            cl.Marker(f"{n}_m", n, tuple(0.3 * rng.standard_normal(3)), _rot(rng)),
            cl.Marker(f"g{k}", cl.GROUND, tuple(rng.standard_normal(3)), _rot(rng)),
            J(f"joint_{n}", f"{n}_m", f"g{k}"),
        )
    m.add(
        cl.PrismaticDriver("drv_c", "joint_q2", cl.Ramp(0.1, 0.4, 0.0, 1.5)),
        cl.PrismaticDriver(
            "drv_p", "joint_q3", cl.Tabulated((0.0, 0.5, 1.0, 2.0), (0.2, 0.3, 0.1, 0.25))
        ),
        cl.Marker("q1_d", "q1", (0.2, -0.1, 0.3)),
        cl.Marker("g_d", cl.GROUND, (1.0, 0.5, -0.5)),
        cl.DistanceDriver("dist", "q1_d", "g_d", cl.Ramp(1.0, 1.3, 0.2, 1.8, "cycloidal")),
        cl.Marker("q5_d", "q5", (0.1, 0.1, -0.2)),
        cl.SpringDamper("sd", "q5_d", "g_d", stiffness=80.0, damping=2.0, free_length=0.3),
    )
    return m


def revolute_drivers(seed: int = 4) -> cl.Mechanism:
    """Two cranks on revolute joints with random ground triads, driven by RevoluteDrivers
    (a Sinusoid, a Ramp), one on a cylindrical joint; a rod joins them by spherical
    joints. The reference writes the row with the ground triad directly, the kernel
    through z-x-z angles."""
    rng = np.random.default_rng(seed)
    m = cl.Mechanism("revolute_drivers", gravity=(0.0, -9.81, 0.0))
    fns = (cl.Sinusoid(0.4, 2.1, 0.3, 0.2), cl.Ramp(-0.2, 0.9, 0.1, 1.7, "cycloidal"))
    for k, (J, fn) in enumerate(zip((cl.Revolute, cl.Cylindrical), fns, strict=True)):
        n = f"c{k}"
        m.add(
            cl.Body(
                n,
                float(rng.uniform(0.5, 2.0)),
                _inertia(rng),
                position=tuple(rng.standard_normal(3)),
                orientation=_rot(rng),
            ),
            cl.Marker(f"g{k}", cl.GROUND, tuple(rng.standard_normal(3)), _rot(rng)),
            cl.Marker(f"{n}_h", n, tuple(0.3 * rng.standard_normal(3)), _rot(rng)),
            J(f"j{k}", f"g{k}", f"{n}_h"),
            cl.RevoluteDriver(f"motor{k}", f"j{k}", fn),
        )
    m.add(
        cl.Body("rod", 1.0, _inertia(rng), position=(0.1, 0.2, 0.3), orientation=_rot(rng)),
        cl.Marker("c0_s", "c0", (0.2, 0.0, 0.1)),
        cl.Marker("rod_a", "rod", (0.0, 0.0, -0.3)),
        cl.Spherical("sa", "c0_s", "rod_a"),
        cl.Marker("c1_s", "c1", (0.1, -0.1, 0.0)),
        cl.Marker("rod_b", "rod", (0.0, 0.0, 0.3)),
        cl.Spherical("sb", "c1_s", "rod_b"),
    )
    return m


MECHANISMS = {
    "revolute_drivers": revolute_drivers,
    "double_pendulum": double_pendulum,
    "all_joints": all_joints,
    "pose_drivers": pose_drivers,
    "ground_as_j": ground_as_j,
}


# --------------------------------------------------------------------------- helpers
def random_state(c: cl.Compiled, rng: np.random.Generator, *, unit_p: bool = True) -> np.ndarray:
    """Non-assembled positions near y0, random orientations and velocities."""
    nb = c.nb
    y = c.y0.copy()
    for k in range(nb):
        y[7 * k : 7 * k + 3] += 0.2 * rng.standard_normal(3)
        p = y[7 * k + 3 : 7 * k + 7] + 0.3 * rng.standard_normal(4)
        y[7 * k + 3 : 7 * k + 7] = p / np.linalg.norm(p) if unit_p else p
    y[7 * nb : 13 * nb] = rng.standard_normal(6 * nb)
    y[13 * nb :] = rng.standard_normal(y.size - 13 * nb)  # work integrals: not in the rates
    return y


def compiled_eval(c: cl.Compiled, t: float, y: np.ndarray, ab, solver: Solver):
    """(ydot, lam) from the compiled kernel called directly."""
    wk = make_work(c.model)
    out = np.zeros_like(y)
    cs = cl.contact_state(c)
    status = rhs(float(t), y, c.model, wk, cs, float(ab[0]), float(ab[1]), int(solver), out)
    assert status == 0
    return out, wk.lam.copy()


def assert_close(a: np.ndarray, b: np.ndarray, rtol: float = RTOL, what: str = "") -> None:
    scale = max(1.0, float(np.max(np.abs(b)))) if b.size else 1.0
    err = float(np.max(np.abs(a - b))) if a.size else 0.0
    assert err <= rtol * scale, f"{what}: max |diff| = {err:.3e}, scale {scale:.3e}"


# --------------------------------------------------------------------------- tests
@pytest.mark.parametrize("name", list(MECHANISMS))
def test_constraint_rows_match_compiled(name: str) -> None:
    """phi, phi_q, phi_t, gamma of the reference equal the compiled kernel's rows."""
    mech = MECHANISMS[name]()
    c = cl.compile_mechanism(mech)
    rng = np.random.default_rng(10)
    for _ in range(3):
        y = random_state(c, rng)
        t = float(rng.uniform(0.0, 2.0))
        rows = cl.evaluate_rows(c, t, y)
        phi, phi_q, phi_t, gamma, is_drv = constraint_rows(mech, t, y)
        assert phi.shape == (c.nrow,)
        assert_close(phi, rows.phi, what="phi")
        assert_close(phi_q, rows.phi_q, what="phi_q")
        assert_close(phi_t, rows.phi_t, what="phi_t")
        assert_close(gamma, rows.gamma, what="gamma")
        assert_close(phi_q @ y[c.nq : c.nq + c.nv] + phi_t, rows.phi_dot, what="phi_dot")
        assert np.array_equal(is_drv, np.asarray(c.model.row_drv) == 1)


@pytest.mark.parametrize("ab", BAUMGARTE)
@pytest.mark.parametrize("solver", ["schur", "dense"])
@pytest.mark.parametrize("name", list(MECHANISMS))
def test_compiled_rhs_equals_reference(name: str, solver: str, ab) -> None:
    """ydot (incl. work rates) via scipy_rhs and lam via the kernel equal the reference."""
    mech = MECHANISMS[name]()
    c = cl.compile_mechanism(mech)
    f = cl.scipy_rhs(c, baumgarte=ab, solver=solver)
    # a seed that is the same in every process (hash() of a str is salted per process)
    rng = np.random.default_rng(zlib.crc32(f"{name}/{solver}".encode()))
    for _ in range(4):
        y = random_state(c, rng)
        t = float(rng.uniform(0.0, 2.0))
        yd_ref, lam_ref = reference_rhs(mech, t, y, alpha=ab[0], beta=ab[1])
        yd = f(t, y)
        assert_close(yd, yd_ref, what=f"{name} {solver} ydot")
        # the work rates separately, at their own scale
        assert_close(yd[-3:], yd_ref[-3:], what="work rates")
        yd2, lam = compiled_eval(c, t, y, ab, Solver[solver.upper()])
        assert_close(yd2, yd, rtol=1e-12, what="scipy_rhs vs rhs")
        assert_close(lam, lam_ref, what=f"{name} {solver} lam")


def test_non_unit_euler_parameters() -> None:
    """|p| != 1: A is evaluated at p/|p| and p_dot = G(p)^T omega'/2 with the raw p (b.2)."""
    mech = pose_drivers()
    c = cl.compile_mechanism(mech)
    rng = np.random.default_rng(3)
    y = random_state(c, rng, unit_p=False)
    yd_ref, lam_ref = reference_rhs(mech, 0.7, y, alpha=5.0, beta=5.0)
    yd, lam = compiled_eval(c, 0.7, y, (5.0, 5.0), Solver.SCHUR)
    assert_close(yd, yd_ref, what="ydot")
    assert_close(lam, lam_ref, what="lam")


def test_free_body_newton_euler() -> None:
    """No rows: m r_ddot = F + m g, J' w'_dot = n' - w' x J' w' (physics.md b.2, d.1),
    with a world point force and a marker-frame torque, both implementations."""
    rng = np.random.default_rng(4)
    T = _rot(rng)
    sb = np.array([0.1, 0.2, 0.3])
    m = cl.Mechanism("free", gravity=(0.0, 0.0, -9.81))
    m.add(
        cl.Body("a", 1.5, _inertia(rng), position=(0.0, 0.0, 1.0), orientation=_rot(rng)),
        cl.Marker("a_m", "a", tuple(sb), T),
        cl.PointForce("fa", "a_m", (1.0, 2.0, 3.0), cl.Sinusoid(1.0, 1.0)),
        cl.Torque("ta", "a_m", (0.0, 1.0, 0.0), 0.5, frame="marker"),
    )
    c = cl.compile_mechanism(m)
    y = random_state(c, rng)
    t = 0.4
    yd_ref, lam_ref = reference_rhs(m, t, y, alpha=5.0, beta=5.0)
    yd, lam = compiled_eval(c, t, y, (5.0, 5.0), Solver.SCHUR)
    assert lam_ref.size == 0 and lam.size == 0
    assert_close(yd, yd_ref, what="ydot")
    # by hand
    p = y[3:7] / np.linalg.norm(y[3:7])
    A = cl.Body("tmp", 1.0, orientation=p).rotation
    J = m.bodies["a"].inertia_matrix
    v, w = y[7:10], y[10:13]
    F = np.sin(t) * np.array([1.0, 2.0, 3.0])
    n_b = np.cross(sb, A.T @ F) + T @ np.array([0.0, 0.5, 0.0])
    assert np.allclose(yd_ref[7:10], F / 1.5 + np.array([0.0, 0.0, -9.81]), rtol=1e-12)
    assert np.allclose(J @ yd_ref[10:13], n_b - np.cross(w, J @ w), rtol=1e-12, atol=1e-12)
    # W_a rate = F . v_P + n . w (physics.md j)
    power = F @ (v + np.cross(A @ w, A @ sb)) + (A @ T @ np.array([0.0, 0.5, 0.0])) @ (A @ w)
    assert np.isclose(yd_ref[c.iw + 2], power, rtol=1e-12, atol=1e-12)  # W_a rate


# ---------------------------------------------------------------- reference checked by FD
def _quat_mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """p (x) q (physics.md b.1)."""
    return np.concatenate(
        [[p[0] * q[0] - p[1:] @ q[1:]], p[0] * q[1:] + q[0] * p[1:] + np.cross(p[1:], q[1:])]
    )


def _expq(th: np.ndarray) -> np.ndarray:
    a = float(np.linalg.norm(th))
    if a == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[np.cos(a / 2)], np.sin(a / 2) * th / a])


def _moved(y: np.ndarray, nb: int, dv: np.ndarray, s: float) -> np.ndarray:
    """r += s dr, p <- p (x) exp(s dth'/2) for every body (physics.md c.6)."""
    z = y.copy()
    for k in range(nb):
        z[7 * k : 7 * k + 3] += s * dv[6 * k : 6 * k + 3]
        z[7 * k + 3 : 7 * k + 7] = _quat_mul(
            y[7 * k + 3 : 7 * k + 7], _expq(s * dv[6 * k + 3 :][:3])
        )
    return z


@pytest.mark.parametrize("name", list(MECHANISMS))
def test_reference_rows_finite_differences(name: str) -> None:
    """physics.md c.6 on the reference itself: phi_q by central differences per direction,
    phi_t and gamma along the motion with v_dot = 0 (dphi/ds = phi_q v + phi_t,
    d2phi/ds2 = -gamma)."""
    mech = MECHANISMS[name]()
    c = cl.compile_mechanism(mech)
    nb = c.nb
    rng = np.random.default_rng(20)
    y = random_state(c, rng)
    t0 = 0.37
    phi0, phi_q, phi_t, gamma, _ = constraint_rows(mech, t0, y)
    h = 1e-6
    fd = np.zeros_like(phi_q)
    for k in range(c.nv):
        e = np.zeros(c.nv)
        e[k] = 1.0
        fd[:, k] = (
            constraint_rows(mech, t0, _moved(y, nb, e, h))[0]
            - constraint_rows(mech, t0, _moved(y, nb, e, -h))[0]
        ) / (2 * h)
    assert np.max(np.abs(fd - phi_q)) < 1e-6 * max(1.0, np.max(np.abs(phi_q)))
    v = y[c.nq : c.nq + c.nv]
    h = 1e-4
    fp = constraint_rows(mech, t0 + h, _moved(y, nb, v, h))[0]
    fm = constraint_rows(mech, t0 - h, _moved(y, nb, v, -h))[0]
    d1 = (fp - fm) / (2 * h)
    d2 = (fp - 2 * phi0 + fm) / h**2
    assert np.max(np.abs(d1 - (phi_q @ v + phi_t))) < 1e-6 * max(1.0, np.max(np.abs(d1)))
    assert np.max(np.abs(d2 + gamma)) < 1e-5 * max(1.0, np.max(np.abs(gamma)))


# ---------------------------------------------------------------- pure-Python kernel run
_SUBPROCESS = textwrap.dedent(
    """
    import sys
    import numpy as np
    sys.path.insert(0, sys.argv[1])
    import numba
    assert numba.config.DISABLE_JIT, "NUMBA_DISABLE_JIT was not honoured"
    import clearance as cl
    from clearance.dynamics.rhs import make_work, rhs
    from test_reference_rhs import double_pendulum
    d = np.load(sys.argv[2])
    c = cl.compile_mechanism(double_pendulum())
    outs, lams = [], []
    for solver in (0, 1):
        wk = make_work(c.model)
        out = np.zeros_like(d["y"])
        st = rhs(float(d["t"]), d["y"], c.model, wk, cl.contact_state(c), float(d["alpha"]),
                 float(d["beta"]), solver, out)
        assert st == 0
        outs.append(out)
        lams.append(wk.lam.copy())
    np.savez(sys.argv[3], ydot=np.array(outs), lam=np.array(lams))
    """
)


def test_pure_python_kernel_matches_compiled(tmp_path: Path) -> None:
    """The same kernel functions under NUMBA_DISABLE_JIT=1 give the compiled result."""
    c = cl.compile_mechanism(double_pendulum())
    rng = np.random.default_rng(5)
    y = random_state(c, rng)
    t, alpha, beta = 0.8, 6.0, 4.0
    inp, outp = tmp_path / "in.npz", tmp_path / "out.npz"
    np.savez(inp, y=y, t=t, alpha=alpha, beta=beta)
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    proc = subprocess.run(
        [sys.executable, "-c", _SUBPROCESS, str(Path(__file__).parent), str(inp), str(outp)],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    res = np.load(outp)
    for k, solver in enumerate((Solver.SCHUR, Solver.DENSE)):
        yd, lam = compiled_eval(c, t, y, (alpha, beta), solver)
        assert_close(res["ydot"][k], yd, rtol=1e-12, what=f"pure Python {solver.name} ydot")
        assert_close(res["lam"][k], lam, rtol=1e-12, what=f"pure Python {solver.name} lam")


# ---------------------------------------------------------------- bugs found (not my files)
@pytest.mark.parametrize("length", [1.0, 2.0])
def test_squared_distance_driver_reports_pushing_force(length: float) -> None:
    """A 1 kg body hanging at rest from a distance driver: the pushing force is -m g in both
    forms (length form: lam; squared form: the row is 2 l times stiffer in lam)."""
    forces = {}
    for squared in (False, True):
        m = cl.Mechanism("hang")
        m.add(
            cl.Body("b", 1.0, (0.1, 0.1, 0.1), position=(0.0, 0.0, -length)),
            cl.Marker("g", cl.GROUND),
            cl.Marker("bm", "b"),
            cl.DistanceDriver("dist", "g", "bm", length, squared=squared),
        )
        r = cl.simulate(m, 0.05)
        forces[squared] = r.actuator_force("dist")
        # the reference agrees on lam: the discrepancy is in the reporting only
        _, lam_ref = reference_rhs(m, 0.0, cl.initial_state(r.compiled), alpha=5.0, beta=5.0)
        assert np.isclose(r.lam[0, 0], lam_ref[0], rtol=1e-9)
    assert np.allclose(forces[False], -9.81, rtol=1e-9)
    assert np.allclose(forces[True], -9.81, rtol=1e-9)
