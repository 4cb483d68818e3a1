"""Reference right-hand side in plain NumPy, read straight from the `Mechanism` description.

This is a second, independent implementation of the equations of motion of physics.md
b.2/c/d/j. It never touches the compiled arrays or kernels (only `clearance.model` is
imported), loops over joints, drivers and forces in Python, builds the dense constraint
Jacobian phi_q (m x 6 nb), gamma and Q, and solves the dense augmented system with
`np.linalg.solve`. It serves two purposes:

* an oracle for the compiled kernel in tests (same state layout, same row order);
* the "typical user code" baseline of the benchmark (`bench/bench_core.py`).

Derivation style (different from the compiled primitives on purpose): every constraint is
written in terms of a few *kinematic atoms* (physics.md c.1), each carrying its value, its
dense Jacobian w.r.t. v and its velocity-quadratic acceleration term:

* a marker point      x = r + A sb       x_dot = J_x v,   x_ddot = J_x v_dot + w x (w x s)
* a body-fixed vector a = A ab           a_dot = J_a v,   a_ddot = J_a v_dot + w x (w x a)

and each constraint row is obtained from them by the product rule, e.g. for phi = a . b:
phi_q = b^T J_a + a^T J_b and gamma = -(acc_a . b + 2 a_dot . b_dot + a . acc_b) + f_ddot.

State layout (same as the compiled model):
y = [q (7 nb): r (3), p (4) per body | v (6 nb): r_dot (3), omega' (3) per body |
     W_c, W_d, W_a]; rows: joints in insertion order, then drivers in insertion order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clearance.kinds import JointType
from clearance.model.bodies import GROUND
from clearance.model.drivers import (
    DistanceDriver,
    OrientationDriver,
    PositionDriver,
    PrismaticDriver,
    RevoluteDriver,
)
from clearance.model.forces import PointForce, SpringDamper, Torque
from clearance.model.mechanism import Mechanism

__all__ = ["constraint_rows", "reference_rhs"]


def _skew(x: np.ndarray) -> np.ndarray:
    """x~ with x~ y = x x y (physics.md a)."""
    return np.array([[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]])


def _rotation(p: np.ndarray) -> np.ndarray:
    """A(p) body -> world from Euler parameters, evaluated at p/|p| (physics.md b.1, b.2)."""
    p = p / np.linalg.norm(p)
    e0, e = p[0], p[1:]
    return (e0 * e0 - e @ e) * np.eye(3) + 2.0 * (np.outer(e, e) + e0 * _skew(e))


def _G(p: np.ndarray) -> np.ndarray:
    """G(p) = [-e, -e~ + e0 I3] (3x4), physics.md b.1."""
    e0, e = p[0], p[1:]
    return np.column_stack([-e, -_skew(e) + e0 * np.eye(3)])


@dataclass
class _BodyState:
    """Kinematics of one body (or the ground) at the current state."""

    col: int  # first column of the body in v, -1 for the ground
    r: np.ndarray  # (3,) mass-centre position, world [m]
    A: np.ndarray  # (3, 3) rotation body -> world
    r_dot: np.ndarray  # (3,) [m/s]
    w: np.ndarray  # (3,) angular velocity, world components [rad/s]


@dataclass
class _Atom:
    """A point or vector: value (3,), x_dot (3,), dense Jacobian J (3, nv), acc (3,)."""

    x: np.ndarray
    xd: np.ndarray
    J: np.ndarray
    acc: np.ndarray


class _Kin:
    """Body states and kinematic atoms (physics.md c.1) for one evaluation."""

    def __init__(self, mech: Mechanism, y: np.ndarray) -> None:
        nb = mech.nbody
        self.nv = 6 * nb
        self.mech = mech
        self.bodies: dict[str, _BodyState] = {
            GROUND: _BodyState(-1, np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3))
        }
        for k, name in enumerate(mech.bodies):
            q = y[7 * k : 7 * k + 7]
            v = y[7 * nb + 6 * k : 7 * nb + 6 * k + 6]
            A = _rotation(q[3:7])
            # omega = A omega' (physics.md a)
            self.bodies[name] = _BodyState(6 * k, q[0:3].copy(), A, v[0:3].copy(), A @ v[3:6])

    def point(self, body: str, sb: np.ndarray) -> _Atom:
        """Marker point r + A sb: J = [I3, -A sb~], acc = w x (w x s) (physics.md c.1)."""
        b = self.bodies[body]
        s = b.A @ sb
        J = np.zeros((3, self.nv))
        if b.col >= 0:
            J[:, b.col : b.col + 3] = np.eye(3)
            J[:, b.col + 3 : b.col + 6] = -b.A @ _skew(sb)
        return _Atom(b.r + s, b.r_dot + np.cross(b.w, s), J, np.cross(b.w, np.cross(b.w, s)))

    def vector(self, body: str, ab: np.ndarray) -> _Atom:
        """Body vector A ab: J = [0, -A ab~], acc = w x (w x a) (physics.md c.1)."""
        b = self.bodies[body]
        a = b.A @ ab
        J = np.zeros((3, self.nv))
        if b.col >= 0:
            J[:, b.col + 3 : b.col + 6] = -b.A @ _skew(ab)
        return _Atom(a, np.cross(b.w, a), J, np.cross(b.w, np.cross(b.w, a)))

    def marker_point(self, marker: str) -> _Atom:
        m = self.mech.markers[marker]
        return self.point(m.body, np.array(m.position))

    def marker_axis(self, marker: str, col: int) -> _Atom:
        """Triad column col (0 = f, 1 = g, 2 = h) of a marker, as a body vector."""
        m = self.mech.markers[marker]
        return self.vector(m.body, np.array(m.orientation)[:, col])


def _diff(a: _Atom, b: _Atom) -> _Atom:
    """b - a (e.g. d = x_j - x_i)."""
    return _Atom(b.x - a.x, b.xd - a.xd, b.J - a.J, b.acc - a.acc)


def _const(c: np.ndarray, nv: int) -> _Atom:
    """A constant world vector (ground body vector)."""
    z = np.zeros(3)
    return _Atom(np.asarray(c, dtype=float), z, np.zeros((3, nv)), z)


# A row: (phi, phi_q (nv,), phi_t, gamma). phi_ddot = phi_q v_dot - gamma (physics.md c.1).
Row = tuple[float, np.ndarray, float, float]


def _dot_row(a: _Atom, b: _Atom, f: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Row:
    """phi = a . b - f(t): dot-1 / dot-2 / coordinate rows (physics.md c.2).

    phi_dot = a_dot . b + a . b_dot - f_dot;
    phi_ddot = (J_a v_dot + acc_a) . b + 2 a_dot . b_dot + a . (J_b v_dot + acc_b) - f_ddot.
    """
    fv, fd, fdd = f
    phi = float(a.x @ b.x) - fv
    jac = b.x @ a.J + a.x @ b.J
    gamma = -(a.acc @ b.x + 2.0 * a.xd @ b.xd + a.x @ b.acc) + fdd
    return phi, jac, -fd, float(gamma)


def _length_row(d: _Atom, f: tuple[float, float, float]) -> Row:
    """phi = |d| - l(t) (physics.md c.2, distance, length form), u = d/|d|.

    phi_dot = u . d_dot - l_dot;  phi_ddot = u . d_ddot + (|d_dot|^2 - (u . d_dot)^2)/|d| - l_ddot.
    """
    ln = float(np.linalg.norm(d.x))
    u = d.x / ln
    ud = float(u @ d.xd)
    gamma = -((d.xd @ d.xd - ud * ud) / ln + u @ d.acc) + f[2]
    return ln - f[0], u @ d.J, -f[1], float(gamma)


def _squared_row(d: _Atom, f: tuple[float, float, float]) -> Row:
    """phi = d . d - l(t)^2 (physics.md c.2, distance, squared form)."""
    l, ld, ldd = f
    phi, jac, _, gamma = _dot_row(d, d)
    return phi - l * l, jac, -2.0 * l * ld, gamma + 2.0 * (ld * ld + l * ldd)


def _rot_axis(axis: int, th: float) -> tuple[np.ndarray, np.ndarray]:
    """Elementary rotation R = exp(th e~) about world axis `axis` and the generator e~."""
    e = np.zeros(3)
    e[axis] = 1.0
    E = _skew(e)
    R = np.eye(3) + np.sin(th) * E + (1.0 - np.cos(th)) * (E @ E)  # Rodrigues
    return R, E


def _target_rotation(d: OrientationDriver, t: float) -> tuple[np.ndarray, ...]:
    """R(t) = R_a(t1) R_b(t2) R_c(t3) and its first and second time derivatives.

    dR_k/dt = R_k E_k th_k_dot;  d2R_k/dt2 = R_k (E_k th_k_ddot + E_k E_k th_k_dot^2);
    the product rule gives R_dot and R_ddot (with the 2 R_k_dot R_l_dot cross terms).
    """
    R, Rd, Rdd = [], [], []
    for fn, axis in zip(d.angles, d.axes, strict=True):
        th, thd, thdd = fn.derivatives(t)
        Rk, E = _rot_axis(axis, th)
        R.append(Rk)
        Rd.append(Rk @ E * thd)
        Rdd.append(Rk @ (E * thdd + E @ E * thd * thd))
    R0 = R[0] @ R[1] @ R[2]
    R1 = Rd[0] @ R[1] @ R[2] + R[0] @ Rd[1] @ R[2] + R[0] @ R[1] @ Rd[2]
    R2 = (
        Rdd[0] @ R[1] @ R[2]
        + R[0] @ Rdd[1] @ R[2]
        + R[0] @ R[1] @ Rdd[2]
        + 2.0 * (Rd[0] @ Rd[1] @ R[2] + Rd[0] @ R[1] @ Rd[2] + R[0] @ Rd[1] @ Rd[2])
    )
    return R0, R1, R2


def _moving_dot_row(c: np.ndarray, cd: np.ndarray, cdd: np.ndarray, a: _Atom) -> Row:
    """phi = c(t) . a with a rheonomic ground vector c(t) (orientation driver rows)."""
    phi = float(c @ a.x)
    jac = c @ a.J
    phi_t = float(cd @ a.x)
    gamma = -(cdd @ a.x + 2.0 * cd @ a.xd + c @ a.acc)
    return phi, jac, phi_t, float(gamma)


def _joint_rows(kin: _Kin, jt) -> list[Row]:
    """Rows of a joint (physics.md c.3), in the order of the compiled model."""
    mi, mj = jt.marker_i, jt.marker_j
    Pi, Pj = kin.marker_point(mi), kin.marker_point(mj)
    fi, gi, hi = (kin.marker_axis(mi, c) for c in range(3))
    fj, gj, hj = (kin.marker_axis(mj, c) for c in range(3))
    d = _diff(Pi, Pj)
    rows: list[Row] = []
    k = jt.kind
    if k in (JointType.SPHERICAL, JointType.UNIVERSAL, JointType.REVOLUTE, JointType.FIXED):
        # spherical: phi = d (3 rows), phi_q = J_d, gamma = -acc_d (physics.md c.2)
        for a in range(3):
            rows.append((float(d.x[a]), d.J[a].copy(), 0.0, float(-d.acc[a])))
    if k == JointType.UNIVERSAL:
        rows.append(_dot_row(hi, hj))
    elif k == JointType.REVOLUTE:
        rows += [_dot_row(fi, hj), _dot_row(gi, hj)]
    elif k in (JointType.CYLINDRICAL, JointType.PRISMATIC):
        rows += [_dot_row(fi, hj), _dot_row(gi, hj), _dot_row(fi, d), _dot_row(gi, d)]
        if k == JointType.PRISMATIC:
            rows.append(_dot_row(fi, gj))
    elif k == JointType.FIXED:
        rows += [_dot_row(fi, gj), _dot_row(gi, hj), _dot_row(hi, fj)]
    return rows


def _driver_rows(kin: _Kin, mech: Mechanism, drv, t: float) -> list[Row]:
    """Rows of a driver (physics.md c.3 driver rows; OrientationDriver: see its docstring)."""
    if isinstance(drv, PrismaticDriver):
        jt = mech.joints[drv.joint]
        d = _diff(kin.marker_point(jt.marker_i), kin.marker_point(jt.marker_j))
        return [_dot_row(kin.marker_axis(jt.marker_i, 2), d, drv.function.derivatives(t))]
    if isinstance(drv, DistanceDriver):
        d = _diff(kin.marker_point(drv.marker_i), kin.marker_point(drv.marker_j))
        f = drv.function.derivatives(t)
        return [_squared_row(d, f) if drv.squared else _length_row(d, f)]
    if isinstance(drv, PositionDriver):
        # coordinate row c . r_P - f(t), c a constant world unit vector (physics.md c.2)
        c = _const(np.array(drv.axis), kin.nv)
        return [_dot_row(c, kin.marker_point(drv.marker), drv.function.derivatives(t))]
    if isinstance(drv, OrientationDriver):
        R, Rd, Rdd = _target_rotation(drv, t)
        # full: f . R e_y, g . R e_z, h . R e_x;  axis: h . R e_x, h . R e_y
        pairs = [(0, 1), (1, 2), (2, 0)] if drv.mode == "full" else [(2, 0), (2, 1)]
        return [
            _moving_dot_row(R[:, m], Rd[:, m], Rdd[:, m], kin.marker_axis(drv.marker, col))
            for col, m in pairs
        ]
    if isinstance(drv, RevoluteDriver):
        # f_j normal to c(t) = T_i Rz(theta) e_y = T_i (-sin theta, cos theta, 0): written
        # with the marker triad directly (the kernel goes through z-x-z angles)
        jt = mech.joints[drv.joint]
        T = np.array(mech.markers[jt.marker_i].orientation)
        th, thd, thdd = drv.function.derivatives(t)
        s, co = math.sin(th), math.cos(th)
        c = T @ np.array([-s, co, 0.0])
        dc = T @ np.array([-co, -s, 0.0])  # dc/dtheta
        cd = dc * thd
        cdd = dc * thdd - c * thd * thd
        return [_moving_dot_row(c, cd, cdd, kin.marker_axis(jt.marker_j, 0))]
    raise TypeError(f"unknown driver type {type(drv).__name__}")


def _applied(kin: _Kin, mech: Mechanism, y: np.ndarray, t: float) -> tuple[np.ndarray, float]:
    """Q (6 nb) and the power of the non-conservative applied forces [W] (physics.md d.1, j).

    A world force F at a point with Jacobian J_x contributes J_x^T F = [F ; sb x (A^T F)];
    a world torque n contributes [0 ; A^T n].
    """
    nb = mech.nbody
    Q = np.zeros(6 * nb)
    g = np.array(mech.gravity)
    for k, body in enumerate(mech.bodies.values()):
        Jb = body.inertia_matrix
        w_b = y[7 * nb + 6 * k + 3 : 7 * nb + 6 * k + 6]
        Q[6 * k : 6 * k + 3] = body.mass * g
        Q[6 * k + 3 : 6 * k + 6] = -np.cross(w_b, Jb @ w_b)  # gyroscopic term, d.1
    power = 0.0
    for frc in mech.forces.values():
        if isinstance(frc, (PointForce, Torque)):
            m = mech.markers[frc.marker]
            bs = kin.bodies[m.body]
            u = np.array(frc.direction if isinstance(frc, PointForce) else frc.axis)
            if frc.frame == "marker":
                u = bs.A @ np.array(m.orientation) @ u  # marker triad -> world
            F = frc.magnitude.derivatives(t)[0] * u
            if isinstance(frc, PointForce):
                P = kin.marker_point(frc.marker)
                Q += P.J.T @ F
                power += float(F @ P.xd)
            else:
                Q[bs.col + 3 : bs.col + 6] += bs.A.T @ F
                power += float(F @ bs.w)
        elif isinstance(frc, SpringDamper):
            Pi, Pj = kin.marker_point(frc.marker_i), kin.marker_point(frc.marker_j)
            d = _diff(Pi, Pj)
            ln = float(np.linalg.norm(d.x))
            u = d.x / ln
            ldot = float(u @ d.xd)
            # tension T > 0 pulls the points together: -T u on j, +T u on i
            t_nc = frc.damping * ldot + frc.actuator.derivatives(t)[0]
            tension = frc.stiffness * (ln - frc.free_length) + t_nc
            Q += Pj.J.T @ (-tension * u) + Pi.J.T @ (tension * u)
            power -= t_nc * ldot  # elastic part is in V, not W_a (physics.md j)
        else:  # pragma: no cover - Mechanism.add rejects other types
            raise TypeError(type(frc).__name__)
    return Q, power


def _mass_matrix(mech: Mechanism) -> np.ndarray:
    """Dense M = diag(m_k I3, J'_k) (physics.md b.2), 6 nb x 6 nb [kg, kg m^2]."""
    nb = mech.nbody
    M = np.zeros((6 * nb, 6 * nb))
    for k, body in enumerate(mech.bodies.values()):
        M[6 * k : 6 * k + 3, 6 * k : 6 * k + 3] = body.mass * np.eye(3)
        M[6 * k + 3 : 6 * k + 6, 6 * k + 3 : 6 * k + 6] = body.inertia_matrix
    return M


def constraint_rows(
    mech: Mechanism, t: float, y: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """phi (m,), dense phi_q (m, 6 nb), phi_t (m,), gamma (m,), driver-row mask (m,).

    Rows: joints in insertion order (a clearance joint has none: it is a force element), then
    drivers in insertion order (physics.md c.3).
    """
    return _rows(_Kin(mech, np.asarray(y, dtype=float)), mech, t)


def _rows(
    kin: _Kin, mech: Mechanism, t: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    rows: list[Row] = []
    is_drv: list[bool] = []
    for jt in mech.joints.values():
        if getattr(jt, "clearance", None) is not None:
            if jt.clearance.kept_rows(jt.kind):
                raise NotImplementedError(
                    f"reference: clearance joint {jt.name!r} keeps ideal rows; this oracle "
                    "covers clearance joints without rows (spherical) only"
                )
            continue  # a clearance joint is a force element, no rows (physics.md f)
        r = _joint_rows(kin, jt)
        rows += r
        is_drv += [False] * len(r)
    for drv in mech.drivers.values():
        r = _driver_rows(kin, mech, drv, t)
        rows += r
        is_drv += [True] * len(r)
    nv = kin.nv
    if not rows:
        z = np.zeros(0)
        return z, np.zeros((0, nv)), z, z, np.zeros(0, dtype=bool)
    phi = np.array([r[0] for r in rows])
    phi_q = np.array([r[1] for r in rows]).reshape(len(rows), nv)
    phi_t = np.array([r[2] for r in rows])
    gamma = np.array([r[3] for r in rows])
    return phi, phi_q, phi_t, gamma, np.array(is_drv)


def refuse_moving_parts(mech: Mechanism, who: str) -> None:
    """NotImplementedError for what the NumPy oracles do not model: sliding attachment
    points and time-varying inertia (those have their own oracles, see reference_rhs)."""
    for mk in mech.markers.values():
        if mk.slide is not None:
            raise NotImplementedError(f"{who}: marker {mk.name!r} slides")
    for bd in mech.bodies.values():
        if bd.inertia_variation is not None:
            raise NotImplementedError(f"{who}: body {bd.name!r} has varying inertia")


def reference_rhs(
    mech: Mechanism,
    t: float,
    y: np.ndarray,
    *,
    alpha: float,
    beta: float,
) -> tuple[np.ndarray, np.ndarray]:
    """y_dot and lam of the augmented equations of motion, plain NumPy (physics.md d.1).

    mech: the description (bodies, markers, joints, drivers, forces, gravity).
    t: time [s].  y: (13 nb + 5,) state (q | v | W_c, W_d, W_a, W_m, W_L), the compiled
    layout of a mechanism without clearance joints. alpha, beta: Baumgarte parameters [1/s]
    (physics.md d.2). Returns (y_dot, lam (m,)); lam in N or N m per row (Q_c = -phi_q^T lam).
    Clearance joints, sliding markers and varying inertias are outside this reference (they
    have their own oracles: virtual work, energy balance, finite differences; the clearance
    joint's NumPy twin is clearance.dynamics.reference_contact).
    """
    y = np.asarray(y, dtype=float)
    nb = mech.nbody
    for jt in mech.joints.values():
        if getattr(jt, "clearance", None) is not None:
            raise NotImplementedError(f"reference_rhs: joint {jt.name!r} has a clearance")
    refuse_moving_parts(mech, "reference_rhs")
    nv = 6 * nb
    kin = _Kin(mech, y)
    phi, phi_q, phi_t, gamma, is_drv = _rows(kin, mech, t)
    m = phi.size
    v = y[7 * nb : 7 * nb + nv]
    Q, power = _applied(kin, mech, y, t)
    # Baumgarte: gamma_B = gamma - 2 alpha phi_dot - beta^2 phi (physics.md d.1, d.2)
    phi_dot = phi_q @ v + phi_t
    gamma_b = gamma - 2.0 * alpha * phi_dot - beta * beta * phi
    # dense augmented system [M phi_q^T; phi_q 0] [v_dot; lam] = [Q; gamma_B] (d.1)
    K = np.zeros((nv + m, nv + m))
    K[:nv, :nv] = _mass_matrix(mech)
    K[:nv, nv:] = phi_q.T
    K[nv:, :nv] = phi_q
    x = np.linalg.solve(K, np.concatenate([Q, gamma_b]))
    v_dot, lam = x[:nv], x[nv:]
    ydot = np.zeros(13 * nb + 5)  # W_m = W_L = 0 without sliding markers/varying inertia
    for k in range(nb):
        p = y[7 * k + 3 : 7 * k + 7]
        w_b = v[6 * k + 3 : 6 * k + 6]
        ydot[7 * k : 7 * k + 3] = v[6 * k : 6 * k + 3]
        ydot[7 * k + 3 : 7 * k + 7] = 0.5 * _G(p).T @ w_b  # p_dot = G^T omega' / 2 (b.1)
    ydot[7 * nb : 7 * nb + nv] = v_dot
    # work rates (physics.md j): constraint power -lam^T phi_q v, its driver part, W_a
    p_rows = -lam * (phi_q @ v)
    ydot[13 * nb] = float(p_rows.sum())
    ydot[13 * nb + 1] = float(p_rows[is_drv].sum())
    ydot[13 * nb + 2] = power
    return ydot, lam
