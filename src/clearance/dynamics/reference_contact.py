"""Reference spherical clearance joint and clearance right-hand side in plain NumPy.

A second, independent implementation of the ball-in-socket force element of physics.md f
(geometry f.1, velocities f.2, forces f.3, transfer f.4, discrete state f.5) with the
dissipative normal laws of g.1/g.2 (Hertz stiffness from the materials, the impact velocity
latched at onset) and LuGre friction with its bristle state (h.4). It reads the `Mechanism`
description only (never the compiled arrays or kernels) and is written differently from the
compiled `clearance.contact` kernels on purpose: contact points are kinematic atoms of
`reference.py` (value, dense Jacobian), and the generalised forces are J^T f (virtual work)
instead of [f; A^T (s x f)].

`reference_rhs_clearance` combines it with the constraint machinery of `reference.py`
(dense phi_q, gamma, augmented LU). Uses:

* an oracle for the compiled clearance kernel (tests/test_reference_contact.py);
* the "typical user code" baseline of bench/bench_scenario.py, with `solve_ivp_clearance`
  (SciPy RK45 whose accepted steps update the contact state).

State layout (the compiled one, clearance.layout; a spherical joint has one contact point,
so ncp = nclr): y = [q (7 nb) | v (6 nb) | z (3 nclr) | W_c, W_d, W_a, W_m, W_L | D_n (nclr)
| D_t (nclr)]. Clearance joints are numbered in the
order of `mech.joints`. The discrete state per joint is (in_contact, delta_dot_minus).
Sliding markers and varying inertias are outside this reference, as in reference.py.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import RK45, solve_ivp

from clearance.dynamics.reference import _G, _applied, _Kin, _rows, refuse_moving_parts
from clearance.model.clearance import Clearance
from clearance.model.contact_laws import (
    Flores,
    Gonthier,
    HerbertMcWhannell,
    Hertz,
    HuGuo,
    HuntCrossley,
    LankaraniNikravesh,
    LeeWang,
    LuGre,
    NoFriction,
    ZhiyingQishao,
)
from clearance.model.mechanism import Mechanism

__all__ = [
    "ClearanceJoint",
    "clearance_joints",
    "contact_state_update",
    "reference_rhs_clearance",
    "solve_ivp_clearance",
]

NWORK = 5  # W_c, W_d, W_a, W_m, W_L

# xi(c_r) of F_N = K delta^n [1 + xi delta_dot / delta_dot_minus] (physics.md g.2 table)
_XI = {
    HuntCrossley: lambda r: 1.5 * (1.0 - r),
    LankaraniNikravesh: lambda r: 0.75 * (1.0 - r * r),
    Flores: lambda r: 1.6 * (1.0 - r) / r,
    Gonthier: lambda r: (1.0 - r * r) / r,
    HuGuo: lambda r: 1.5 * (1.0 - r) / r,
    HerbertMcWhannell: lambda r: 6.0 * (1.0 - r) / ((2.0 * r - 1.0) ** 2 + 3.0),
    LeeWang: lambda r: 0.75 * (1.0 - r),
    ZhiyingQishao: lambda r: 0.75 * (1.0 - r * r) * np.exp(2.0 * (1.0 - r)),
}


@dataclass(frozen=True)
class ClearanceJoint:
    """One clearance joint, read from the description (physics.md f, g.1, g.2, h.4)."""

    name: str
    socket_marker: str
    ball_marker: str
    R_s: float  # socket radius [m]
    R_b: float  # ball radius [m]
    c: float  # radial clearance [m]
    v_floor: float  # floor of delta_dot_minus [m/s]
    K: float  # stiffness [N/m^n]
    n: float  # exponent
    xi: float  # hysteresis factor (0: Hertz, no damping)
    friction: LuGre | None  # None: frictionless


def _hertz_k(cl) -> float:
    """Internal (conformal) ball-in-socket Hertz stiffness (physics.md g.1)."""
    bm, sm = cl.ball_material, cl.socket_material
    e_star = 1.0 / ((1.0 - bm.nu**2) / bm.E + (1.0 - sm.nu**2) / sm.E)
    r_star = cl.ball_radius * cl.socket_radius / (cl.socket_radius - cl.ball_radius)
    return 4.0 / 3.0 * e_star * np.sqrt(r_star)


def clearance_joints(mech: Mechanism) -> list[ClearanceJoint]:
    """The clearance joints of mech in `mech.joints` order (the compiled order)."""
    out = []
    for jt in mech.joints.values():
        cl = getattr(jt, "clearance", None)
        if cl is None:
            continue
        if not isinstance(cl, Clearance):
            raise NotImplementedError(
                f"reference_contact: joint {jt.name!r} has a {type(cl).__name__}; this oracle "
                "covers spherical clearance joints only"
            )
        law = cl.normal
        if type(law) is Hertz:
            xi = 0.0
        elif type(law) in _XI:
            xi = float(_XI[type(law)](law.restitution))
        else:
            raise NotImplementedError(f"reference_contact: normal law {type(law).__name__}")
        fr = cl.friction
        if not isinstance(fr, (LuGre, NoFriction)):
            raise NotImplementedError(f"reference_contact: friction law {type(fr).__name__}")
        sock, ball = (jt.marker_i, jt.marker_j) if cl.socket == "i" else (jt.marker_j, jt.marker_i)
        out.append(
            ClearanceJoint(
                name=jt.name,
                socket_marker=sock,
                ball_marker=ball,
                R_s=float(cl.socket_radius),
                R_b=float(cl.ball_radius),
                c=cl.c,
                v_floor=float(cl.velocity_floor),
                K=float(law.stiffness) if law.stiffness is not None else _hertz_k(cl),
                n=float(law.exponent),
                xi=xi,
                friction=fr if isinstance(fr, LuGre) else None,
            )
        )
    return out


@dataclass
class _Contact:
    """Kinematics of one joint at the current state."""

    e: np.ndarray  # ball centre minus socket centre, world [m]
    delta: float  # |e| - c [m]
    n: np.ndarray  # e/|e|
    delta_dot: float  # n . (v_ball centre - v_socket centre) [m/s]
    n_dot: np.ndarray  # d n / dt = (I - n n^T) e_dot / |e| [1/s]


def _centres(kin: _Kin, mech: Mechanism, cj: ClearanceJoint):
    """Kinematic atoms of the socket and ball centres (physics.md f.1)."""
    return kin.marker_point(cj.socket_marker), kin.marker_point(cj.ball_marker)


def _contact(kin: _Kin, mech: Mechanism, cj: ClearanceJoint) -> _Contact:
    Ps, Pb = _centres(kin, mech, cj)
    e = Pb.x - Ps.x
    el = float(np.linalg.norm(e))
    n = e / el if el > 0.0 else np.zeros(3)
    ed = Pb.xd - Ps.xd
    nd = (np.eye(3) - np.outer(n, n)) @ ed / el if el > 0.0 else np.zeros(3)
    return _Contact(e, el - cj.c, n, float(n @ ed), nd)


def _lugre(fr: LuGre, fn: float, vt: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F_T_vec, z_dot) of LuGre normalised by F_N (physics.md h.4)."""
    v = float(np.linalg.norm(vt))
    g = fr.mu_c + (fr.mu_s - fr.mu_c) * np.exp(-((v / fr.v_s) ** 2))
    s1 = fr.sigma1
    if fr.velocity_damping:
        v_d = fr.v_s if fr.v_d is None else fr.v_d
        s1 = s1 * np.exp(-((v / v_d) ** 2))
    zdot = vt - fr.sigma0 * v / g * z
    return fn * (fr.sigma0 * z + s1 * zdot + fr.sigma2 * vt), zdot


def _contact_forces(kin, mech, joints, y, in_contact, ddm):
    """Generalised contact forces Q_c (6 nb), z_dot (3 nclr), D_n and D_t rates (nclr)."""
    nb = mech.nbody
    nc = len(joints)
    Q = np.zeros(6 * nb)
    zdot = np.zeros(3 * nc)
    dn = np.zeros(nc)
    dt = np.zeros(nc)
    for k, cj in enumerate(joints):
        ct = _contact(kin, mech, cj)
        if not ct.delta > 0.0:
            continue
        n = ct.n
        # material points at the contact points r^Q = P + R n (f.1), as atoms of their bodies
        ms, mb = mech.markers[cj.socket_marker], mech.markers[cj.ball_marker]
        As, Ab = kin.bodies[ms.body].A, kin.bodies[mb.body].A
        Qs = kin.point(ms.body, np.array(ms.position) + cj.R_s * (As.T @ n))
        Qb = kin.point(mb.body, np.array(mb.position) + cj.R_b * (Ab.T @ n))
        vrel = Qb.xd - Qs.xd
        vt = vrel - (n @ vrel) * n  # f.2
        # impact velocity: latched at onset; before it is latched, the approach velocity
        dm = ddm[k] if in_contact[k] else max(ct.delta_dot, cj.v_floor)
        f_el = cj.K * ct.delta**cj.n
        fn = max(0.0, f_el * (1.0 + cj.xi * ct.delta_dot / max(dm, 1e-12)))  # g.2, no adhesion
        if cj.friction is not None:
            z = y[13 * nb + 3 * k : 13 * nb + 3 * k + 3]
            a = float(z @ n)
            zt = z - a * n  # the bristles act with their tangent part
            ft, zd = _lugre(cj.friction, fn, vt, zt)
            ft = ft - (ft @ n) * n  # tangent (f.3)
            # z_t carried with the turning tangent plane, a n turned with n: a stays constant
            # (d(n . z)/dt = n_dot . z + n . z_dot = 0) and d z_t/dt does not depend on a
            zdot[3 * k : 3 * k + 3] = zd - (ct.n_dot @ zt) * n + a * ct.n_dot
        else:
            ft = np.zeros(3)
        f_ball = -fn * n - ft  # f.3; the socket gets -f_ball
        Q += Qb.J.T @ f_ball - Qs.J.T @ f_ball  # virtual work: J^T f (f.4)
        dn[k] = (fn - f_el) * ct.delta_dot
        dt[k] = float(ft @ vt)
    return Q, zdot, dn, dt


def reference_rhs_clearance(
    mech: Mechanism,
    t: float,
    y: np.ndarray,
    *,
    alpha: float,
    beta: float,
    in_contact=None,
    delta_dot_minus=None,
    joints: list[ClearanceJoint] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """y_dot and lam of a mechanism with clearance joints, plain NumPy (physics.md d.1, f).

    t: time [s]; y: the compiled state layout (module docstring); alpha, beta: Baumgarte
    [1/s]. in_contact (nclr bools, default all False) and delta_dot_minus (nclr, [m/s]) are
    the discrete contact state (f.5): with in_contact False a penetrating joint uses its
    current approach velocity, floored, as the impact velocity (as the compiled kernel does
    before the integrator latches it). joints: clearance_joints(mech), to skip re-reading.
    Returns (y_dot, lam).
    """
    refuse_moving_parts(mech, "reference_contact")
    y = np.asarray(y, dtype=float)
    joints = clearance_joints(mech) if joints is None else joints
    nb, nc = mech.nbody, len(joints)
    nv = 6 * nb
    in_contact = np.zeros(nc, dtype=bool) if in_contact is None else np.asarray(in_contact)
    ddm = np.zeros(nc) if delta_dot_minus is None else np.asarray(delta_dot_minus, dtype=float)
    kin = _Kin(mech, y)
    phi, phi_q, phi_t, gamma, is_drv = _rows(kin, mech, t)
    m = phi.size
    v = y[7 * nb : 7 * nb + nv]
    Q, power = _applied(kin, mech, y, t)  # W_a: applied forces only, not contact (j)
    Qc, zdot, dn, dt = _contact_forces(kin, mech, joints, y, in_contact, ddm)
    phi_dot = phi_q @ v + phi_t
    gamma_b = gamma - 2.0 * alpha * phi_dot - beta * beta * phi  # d.2
    K = np.zeros((nv + m, nv + m))
    for k, body in enumerate(mech.bodies.values()):
        K[6 * k : 6 * k + 3, 6 * k : 6 * k + 3] = body.mass * np.eye(3)
        K[6 * k + 3 : 6 * k + 6, 6 * k + 3 : 6 * k + 6] = body.inertia_matrix
    K[:nv, nv:] = phi_q.T
    K[nv:, :nv] = phi_q
    x = np.linalg.solve(K, np.concatenate([Q + Qc, gamma_b]))
    v_dot, lam = x[:nv], x[nv:]
    iz = 13 * nb
    iw = iz + 3 * nc
    ydot = np.zeros(iw + NWORK + 2 * nc)
    for k in range(nb):
        p = y[7 * k + 3 : 7 * k + 7]
        ydot[7 * k : 7 * k + 3] = v[6 * k : 6 * k + 3]
        ydot[7 * k + 3 : 7 * k + 7] = 0.5 * _G(p).T @ v[6 * k + 3 : 6 * k + 6]  # b.1
    ydot[7 * nb : 7 * nb + nv] = v_dot
    ydot[iz:iw] = zdot
    p_rows = -lam * (phi_q @ v)  # constraint power (j)
    ydot[iw] = float(p_rows.sum())
    ydot[iw + 1] = float(p_rows[is_drv].sum())
    ydot[iw + 2] = power
    ydot[iw + NWORK : iw + NWORK + nc] = dn
    ydot[iw + NWORK + nc :] = dt
    return ydot, lam


def contact_state_update(
    mech: Mechanism, y: np.ndarray, in_contact: np.ndarray, ddm: np.ndarray, joints=None
) -> bool:
    """Discrete update at an accepted state (physics.md f.5), in place: onset latches
    delta_dot_minus (floored), separation clears it and resets the LuGre bristles (those in
    contact follow the tangent plane in the right-hand side). Returns True if y or the state
    changed.

    First-order event capture (no event location): the state changes at the first accepted
    step beyond a crossing, as physics.md f.5 allows without events."""
    joints = clearance_joints(mech) if joints is None else joints
    kin = _Kin(mech, y)
    iz = 13 * mech.nbody
    changed = False
    for k, cj in enumerate(joints):
        ct = _contact(kin, mech, cj)
        z = y[iz + 3 * k : iz + 3 * k + 3]
        if not in_contact[k] and ct.delta > 0.0:
            in_contact[k], ddm[k] = True, max(ct.delta_dot, cj.v_floor)
            changed = True
        elif in_contact[k] and ct.delta < 0.0:
            in_contact[k], ddm[k] = False, 0.0
            z[:] = 0.0
            changed = True
    return changed


class _LatchingRK45(RK45):
    """SciPy's RK45 that updates the contact state after each accepted step (the closure's
    state lives on the right-hand side object `fun.state`) and restarts FSAL when it
    changed."""

    def __init__(self, fun, t0, y0, t_bound, **kw):
        self._state = kw.pop("contact")
        super().__init__(fun, t0, y0, t_bound, **kw)

    def _step_impl(self):
        ok, msg = super()._step_impl()
        if ok and self._state.accept(self.y):
            self.f = self.fun(self.t, self.y)
        return ok, msg


class _ContactClosure:
    """Right-hand side f(t, y) holding the discrete contact state; rhs(t, y, in_contact,
    ddm) -> y_dot computes the derivative."""

    def __init__(self, mech, rhs):
        self.mech, self.rhs = mech, rhs
        self.joints = clearance_joints(mech)
        self.in_contact = np.zeros(len(self.joints), dtype=bool)
        self.ddm = np.zeros(len(self.joints))

    def __call__(self, t, y):
        return self.rhs(t, y, self.in_contact, self.ddm)

    def accept(self, y) -> bool:
        return contact_state_update(self.mech, y, self.in_contact, self.ddm, self.joints)


def solve_ivp_clearance(
    mech: Mechanism,
    t_span: tuple[float, float],
    y0: np.ndarray,
    *,
    alpha: float,
    beta: float,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    rhs=None,
    **kw,
):
    """`scipy.integrate.solve_ivp` (RK45) of a clearance mechanism; the contact state is
    updated on accepted steps (contact_state_update, first-order capture).

    rhs(t, y, in_contact, delta_dot_minus) -> y_dot: the right-hand side (default: the NumPy
    reference_rhs_clearance with alpha, beta). Further keywords go to solve_ivp. Returns its
    OdeResult with .contact = the final (in_contact, delta_dot_minus)."""
    joints = clearance_joints(mech)
    if rhs is None:

        def rhs(t, y, in_contact, ddm):
            return reference_rhs_clearance(
                mech,
                t,
                y,
                alpha=alpha,
                beta=beta,
                in_contact=in_contact,
                delta_dot_minus=ddm,
                joints=joints,
            )[0]

    closure = _ContactClosure(mech, rhs)
    y = np.array(y0, dtype=float)
    closure.accept(y)  # the state at t0
    sol = solve_ivp(
        closure, t_span, y, method=_LatchingRK45, rtol=rtol, atol=atol, contact=closure, **kw
    )
    sol.contact = (closure.in_contact.copy(), closure.ddm.copy())
    return sol
