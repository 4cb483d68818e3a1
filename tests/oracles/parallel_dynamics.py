"""Independent oracle: inverse dynamics and statics of parallel mechanisms by virtual power.

A stand-alone second implementation (numpy + scipy only), written from a specification
without looking at the ``clearance`` package sources. It is meant to be compared with the
package's actuator forces for Stewart-Gough, 3-RPS, Delta, 5-PSS + UPU, 4-UPS + UPU,
4-SPS + CU ... mechanisms.

Conventions (SI units, world z up, fixed base)
----------------------------------------------
``spec = {"gravity": g, "platform": {"mass": m, "inertia": (Jx, Jy, Jz)}, "legs": [leg, ...]}``.
The platform frame origin is its mass centre ``p``; ``R`` maps platform to world axes;
``v, w, a, alpha`` are the mass centre's velocity / acceleration and the angular velocity /
acceleration, all in world axes. A leg is a dict with ``type`` (UPS, SPS, RPS, UPU, PRS, PSS,
RSS, CU, letters read from the base), base point ``A`` (world), platform point ``B`` (platform
frame, relative to the mass centre), reference axis ``t`` (world), ``rail`` (PRS, PSS: rail
direction; CU: the C axis), ``links`` (base to platform; each ``{"mass", "inertia": (Jt, Jt, Ja),
"com", "length"}``, the third moment about the link's own axis), ``actuated``, and for RSS
``parallelogram`` (bar width or None) and ``knee`` ("out"/"in"), for PRS/PSS ``home_travel`` and
``knee`` ("down"/"up"). ``B_w = p + R B``.

Closed-form inverse kinematics (one function, ``_leg``)
* UPS, SPS, RPS, UPU: ``u = (B_w - A)/|B_w - A|``; lower link mass centre ``A + c_lo u``, upper
  ``B_w - c_up u``; actuator coordinate ``q = |B_w - A|``. Link frames: UPS/UPU
  ``(n x u, n, u)`` with ``n = unit(u x t)``; RPS ``(x, u x x, u)`` with ``x = t`` (made normal
  to ``u``); SPS: idle spin (below). Constraints: RPS ``t.(B_w - A) = 0``; UPU
  ``(R t).n = 0`` (the platform U axis is ``t`` in platform axes).
* PRS, PSS: ``w = B_w - A``, ``s = d.w -/+ sqrt(L^2 - |w_perp|^2)`` (knee down/up),
  ``C = A + s d``, ``r = (B_w - C)/L``; slider (no rotation) at ``C - c_sl d``, rod at
  ``C + c_rod r``; ``q = s - home_travel``. PRS rod frame ``(x, r x x, r)``, ``x = t`` made
  normal to ``r``, constraint ``t.(B_w - A) = 0``; PSS rod: idle spin.
* RSS: ``e1 = unit(t x e_z)``, ``e2 = t x e1``, ``c(phi) = cos(phi) e1 + sin(phi) e2``,
  ``C = A + a c``, ``phi`` from ``|B_w - C| = b``: ``phi = beta +/- acos(K/rho)``; "out" takes the
  root with the larger ``cos(phi)`` AT THE POSE EVALUATED ("in" the smaller); ``q = phi``. Crank
  at ``A + c_cr c``, frame ``(t, c x t, c)``. One rod ``C -> B_w`` (idle spin), or with a
  parallelogram of width ``w`` two rods ``C +/- (w/2) t -> B_w +/- (w/2) R t``, each with the rod
  link's data, mass centre ``start + c_rod * unit axis``, idle spin; constraint ``R t // t``
  (``(R t).e1 = (R t).e2 = 0``).
* CU: constraint ``(B_w - A).e_i = 0`` for the two unit vectors ``e_i`` normal to ``d``; the
  column's mass centre ``B_w - c d``, frame ``(a1, d x a1, d)`` with
  ``a1 = unit((R e) x d)``, ``e`` the platform's U axis (leg key ``platform_axis``, default
  ``e_y``): for ``R = Rz(psi) Rx Ry`` and ``d = e_z`` this is ``Rz(psi)``. Never actuated.
* Idle-spin links (SPS links, PSS rod, RSS rods): axisymmetric, zero spin about their axis ``u``:
  angular velocity ``u x u_dot``, angular acceleration ``u x u_ddot``, virtual angular velocity
  ``u x du``, world inertia ``Jt (1 - u u^T) + Ja u u^T``.

Method (``actuator_forces``)
1. Local platform motion ``p(s) = p + v s + a s^2/2``, ``R(s) = expm(skew(w s + alpha s^2/2)) R``
   (so ``R' = skew(w) R``, ``R'' = (skew(alpha) + skew(w)^2) R`` at ``s = 0``); link poses from the
   closed-form IK at ``s = -2h..2h``; 5-point stencils (error ``O(h^4)``) give link velocities,
   accelerations, ``w_b = vee(asym(R_b' R_b^T))``, ``alpha_b = vee(asym(R_b'' R_b^T))``.
2. Admissible twists ``xi = (v, w)``: null space (SVD) of the 5-point finite-difference
   Jacobian of ``leg_constraints`` along ``(p + v s, expm(skew(w s)) R)``; its dimension must be
   the number of actuators (else ``ValueError``).
3. For each basis twist ``xi_k``: body virtual velocities ``(dv_b, dw_b)`` and ``dq_a/ds_k`` by
   the same stencil; then ``sum_a F_a dq_a/ds_k = sum_b [m_b (a_b - g).dv_b +
   (I_b alpha_b + w_b x I_b w_b).dw_b]`` (platform included) is solved for ``F``.
``F_a`` is the generalized force the actuator applies, conjugate to ``q_a`` (power ``F_a q_a_dot``).

``static_actuator_forces``: ``V = -sum_b m_b g.r_b``; ``dV/ds_k`` and ``dq_a/ds_k`` by central
differences of the closed-form poses along each admissible twist; ``sum_a F_a dq_a/ds_k = dV/ds_k``.

``power_balance_residual``: ``sum_a F_a q_a_dot - d(T + V)/dt`` along a given motion (energy-rate
check). Also public: ``admissible_twists`` (the (6, k) basis) and ``energy`` (T, V).
Branch/sign choices not fixed by the specification: the RSS root is picked at each evaluated pose
("out": larger cos(phi)); parallelogram rods and every S-S rod have zero spin about their axis;
the CU platform U axis is ``e_y`` unless the leg gives ``platform_axis``.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

_OFF = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
_D1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 12.0
_D2 = np.array([-1.0, 16.0, -30.0, 16.0, -1.0]) / 12.0
_EZ = np.array([0.0, 0.0, 1.0])


# ----------------------------------------------------------------------------- small helpers
def _unit(x):
    x = np.asarray(x, float)
    return x / np.linalg.norm(x)


def _vee_asym(M):
    """vee of the antisymmetric part of a 3x3 matrix."""
    S = 0.5 * (M - M.T)
    return np.array([S[2, 1], S[0, 2], S[1, 0]])


def _expso3(phi):
    return Rotation.from_rotvec(np.asarray(phi, float)).as_matrix()


def _perp_pair(d):
    h = np.eye(3)[np.argmin(np.abs(d))]
    e1 = _unit(np.cross(d, h))
    return e1, np.cross(d, e1)


def _frame(x_hint, z):
    """Right-handed frame with third axis z and first axis x_hint made normal to z."""
    x = _unit(x_hint - (x_hint @ z) * z)
    return np.column_stack([x, np.cross(z, x), z])


def _rot(link, r, M):
    return (float(link["mass"]), np.asarray(link["inertia"], float), "R", r, M)


def _axis(link, r, u):
    return (float(link["mass"]), np.asarray(link["inertia"], float), "u", r, u)


# ----------------------------------------------------------------------------- closed-form IK
def _leg(leg, p, R):
    """Bodies [(mass, J, kind, r, M or u)], actuator coordinate (or None), constraints list."""
    typ = leg["type"]
    A = np.asarray(leg["A"], float)
    Bw = p + R @ np.asarray(leg["B"], float)
    t = _unit(leg["t"]) if leg.get("t") is not None else None
    links = leg["links"]
    bodies, cons, q = [], [], None
    if typ in ("UPS", "SPS", "RPS", "UPU"):
        wv = Bw - A
        ell = np.linalg.norm(wv)
        u = wv / ell
        lo, up = links
        r_lo, r_up = A + lo["com"] * u, Bw - up["com"] * u
        if typ == "SPS":
            bodies = [_axis(lo, r_lo, u), _axis(up, r_up, u)]
        else:
            if typ == "RPS":
                M = _frame(t, u)
            else:
                n = _unit(np.cross(u, t))
                M = np.column_stack([np.cross(n, u), n, u])
            bodies = [_rot(lo, r_lo, M), _rot(up, r_up, M)]
        if typ == "RPS":
            cons = [t @ wv]
        elif typ == "UPU":
            cons = [(R @ t) @ n]
        q = ell
    elif typ in ("PRS", "PSS"):
        d = _unit(leg["rail"])
        wv = Bw - A
        dw = d @ wv
        wp = wv - dw * d
        L = float(links[1]["length"])
        disc = L * L - wp @ wp
        if disc < 0:
            raise ValueError("PRS/PSS leg out of reach")
        s = dw - np.sqrt(disc) if (leg.get("knee") or "down") == "down" else dw + np.sqrt(disc)
        C = A + s * d
        r = (Bw - C) / L
        bodies = [_rot(links[0], C - links[0]["com"] * d, np.eye(3))]
        r_rod = C + links[1]["com"] * r
        if typ == "PRS":
            bodies.append(_rot(links[1], r_rod, _frame(t, r)))
            cons = [t @ wv]
        else:
            bodies.append(_axis(links[1], r_rod, r))
        q = s - float(leg.get("home_travel", 0.0) or 0.0)
    elif typ == "RSS":
        a, b = float(links[0]["length"]), float(links[1]["length"])
        e1 = _unit(np.cross(t, _EZ))
        e2 = np.cross(t, e1)
        wv = Bw - A
        K = (wv @ wv + a * a - b * b) / (2.0 * a)
        w1, w2 = wv @ e1, wv @ e2
        rho, beta = np.hypot(w1, w2), np.arctan2(w2, w1)
        if abs(K) > rho:
            raise ValueError("RSS leg out of reach")
        gam = np.arccos(K / rho)
        r1, r2 = beta + gam, beta - gam
        hi, lo_ = (r1, r2) if np.cos(r1) >= np.cos(r2) else (r2, r1)
        phi = hi if (leg.get("knee") or "out") == "out" else lo_
        c = np.cos(phi) * e1 + np.sin(phi) * e2
        C = A + a * c
        crank_frame = np.column_stack([t, np.cross(c, t), c])
        bodies = [_rot(links[0], A + links[0]["com"] * c, crank_frame)]
        wpar = leg.get("parallelogram")
        if wpar:
            tp = R @ t
            for sg in (1.0, -1.0):
                P0, P1 = C + sg * 0.5 * wpar * t, Bw + sg * 0.5 * wpar * tp
                ur = _unit(P1 - P0)
                bodies.append(_axis(links[1], P0 + links[1]["com"] * ur, ur))
            cons = [tp @ e1, tp @ e2]
        else:
            ur = _unit(Bw - C)
            bodies.append(_axis(links[1], C + links[1]["com"] * ur, ur))
        q = phi
    elif typ == "CU":
        if leg.get("actuated"):
            raise ValueError("a CU leg cannot be actuated")
        d = _unit(leg["rail"])
        f1, f2 = _perp_pair(d)
        wv = Bw - A
        cons = [wv @ f1, wv @ f2]
        e_pl = np.asarray(leg.get("platform_axis", (0.0, 1.0, 0.0)), float)
        a1 = _unit(np.cross(R @ e_pl, d))
        col_frame = np.column_stack([a1, np.cross(d, a1), d])
        bodies = [_rot(links[0], Bw - links[0]["com"] * d, col_frame)]
    else:
        raise ValueError(f"unknown leg type {typ!r}")
    return bodies, (q if leg.get("actuated") else None), cons


def _evaluate(spec, p, R):
    p, R = np.asarray(p, float), np.asarray(R, float)
    pl = spec["platform"]
    bodies = [(float(pl["mass"]), np.asarray(pl["inertia"], float), "R", p, R)]
    qs, cons = [], []
    for leg in spec["legs"]:
        b, q, c = _leg(leg, p, R)
        bodies += b
        cons += c
        if q is not None:
            qs.append(q)
    return bodies, np.array(qs, float), np.array(cons, float)


def actuator_coordinates(spec, p, R) -> np.ndarray:
    """Actuator coordinates q_a (n_act,), actuated legs in order."""
    return _evaluate(spec, p, R)[1]


def leg_constraints(spec, p, R) -> np.ndarray:
    """Holonomic constraints the legs put on the platform pose (zero when kept; may be empty)."""
    return _evaluate(spec, p, R)[2]


# ----------------------------------------------------------------------------- differentiation
def _flat(bodies, q):
    return np.concatenate([np.concatenate([r, np.ravel(M)]) for (_, _, _, r, M) in bodies] + [q])


def _stencil(spec, curve, h, second=True):
    """Flat states (bodies + q) and their 1st (and 2nd) derivatives along s -> curve(s) at 0."""
    X = np.array([_flat(*_evaluate(spec, *curve(o * h))[:2]) for o in _OFF])
    bodies, q, _ = _evaluate(spec, *curve(0.0))
    return bodies, len(q), _D1 @ X / h, (_D2 @ X / h**2 if second else None)


def _body_rates(bodies, X1, X2=None):
    """Per body: (v, w) and, if X2 is given, (a, alpha); then the q slice of X1 and X2."""
    out, i = [], 0
    for _, _, kind, _, M in bodies:
        n = 3 + np.size(M)
        v, Md = X1[i : i + 3], X1[i + 3 : i + n]
        a = alpha = None
        if kind == "R":
            Md = Md.reshape(3, 3)
            w = _vee_asym(Md @ M.T)
            if X2 is not None:
                a, Mdd = X2[i : i + 3], X2[i + 3 : i + n].reshape(3, 3)
                alpha = _vee_asym(Mdd @ M.T)
        else:
            w = np.cross(M, Md)
            if X2 is not None:
                a = X2[i : i + 3]
                alpha = np.cross(M, X2[i + 3 : i + n])
        out.append((v, w, a, alpha))
        i += n
    return out, X1[i:], (X2[i:] if X2 is not None else None)


def _world_inertia(J, kind, M):
    if kind == "R":
        return M @ np.diag(J) @ M.T
    return J[0] * (np.eye(3) - np.outer(M, M)) + J[2] * np.outer(M, M)


def admissible_twists(spec, p, R, *, h=1e-4, rtol=1e-7) -> np.ndarray:
    """(6, k) orthonormal basis of the platform twists (v, w) that keep the leg constraints."""
    p, R = np.asarray(p, float), np.asarray(R, float)
    g0 = leg_constraints(spec, p, R)
    if g0.size == 0:
        return np.eye(6)
    G = np.zeros((g0.size, 6))
    for j in range(6):
        e = np.eye(6)[j]
        gs = np.array(
            [leg_constraints(spec, p + e[:3] * o * h, _expso3(e[3:] * o * h) @ R) for o in _OFF]
        )
        G[:, j] = _D1 @ gs / h
    _, S, Vt = np.linalg.svd(G)
    rank = int(np.sum(S > rtol * max(S[0], 1.0)))
    return Vt[rank:].T


def _line(p, R, v, w):
    """Platform pose along the twist (v, w): s -> (p + v s, expm(skew(w s)) R)."""
    return lambda s: (p + v * s, _expso3(w * s) @ R)


def _basis_checked(spec, p, R, n_act):
    Xi = admissible_twists(spec, p, R)
    if Xi.shape[1] != n_act:
        raise ValueError(f"{Xi.shape[1]} admissible platform twists but {n_act} actuators")
    return Xi


# ----------------------------------------------------------------------------- public oracles
def actuator_forces(spec, p, R, v, w, a, alpha, *, h=1e-4) -> np.ndarray:
    """(n_act,) actuator forces/torques (actuated legs in order) for the platform motion
    (p, R, v, w, a, alpha), by the principle of virtual power."""
    p, R, v, w, a, alpha = (np.asarray(x, float) for x in (p, R, v, w, a, alpha))
    g = np.asarray(spec.get("gravity", (0.0, 0.0, -9.81)), float)

    def motion(s):
        return p + v * s + 0.5 * a * s * s, _expso3(w * s + 0.5 * alpha * s * s) @ R

    bodies, n_act, X1, X2 = _stencil(spec, motion, h)
    rates, _, _ = _body_rates(bodies, X1, X2)
    # generalized inertia-and-gravity force per body: (force, torque)
    loads = []
    for (m, J, kind, _, M), (_, wb, ab, alb) in zip(bodies, rates, strict=True):
        I = _world_inertia(J, kind, M)
        loads.append((m * (ab - g), I @ alb + np.cross(wb, I @ wb)))
    Xi = _basis_checked(spec, p, R, n_act)
    A = np.zeros((n_act, n_act))
    rhs = np.zeros(n_act)
    for k in range(n_act):
        vk, wk = Xi[:3, k], Xi[3:, k]
        _, _, Y1, _ = _stencil(spec, _line(p, R, vk, wk), h, second=False)
        vrates, dq, _ = _body_rates(bodies, Y1)
        A[k] = dq
        pairs = zip(loads, vrates, strict=True)
        rhs[k] = sum(f @ dv + tau @ dw for (f, tau), (dv, dw, _, _) in pairs)
    return np.linalg.solve(A, rhs)


def static_actuator_forces(spec, p, R, *, h=1e-6) -> np.ndarray:
    """(n_act,) actuator forces holding the platform at rest at (p, R) against gravity, by
    virtual work: dV/ds_k = sum_a F_a dq_a/ds_k along every admissible twist."""
    p, R = np.asarray(p, float), np.asarray(R, float)
    g = np.asarray(spec.get("gravity", (0.0, 0.0, -9.81)), float)

    def V_and_q(pp, RR):
        bodies, q, _ = _evaluate(spec, pp, RR)
        return -sum(m * (g @ r) for (m, _, _, r, _) in bodies), q

    n_act = actuator_coordinates(spec, p, R).size
    Xi = _basis_checked(spec, p, R, n_act)
    A = np.zeros((n_act, n_act))
    rhs = np.zeros(n_act)
    for k in range(n_act):
        vk, wk = Xi[:3, k], Xi[3:, k]
        Vp, qp = V_and_q(p + vk * h, _expso3(wk * h) @ R)
        Vm, qm = V_and_q(p - vk * h, _expso3(-wk * h) @ R)
        A[k] = (qp - qm) / (2 * h)
        rhs[k] = (Vp - Vm) / (2 * h)
    return np.linalg.solve(A, rhs)


def energy(spec, p, R, v, w, *, h=1e-4):
    """(T, V): kinetic energy of all bodies for platform twist (v, w), potential energy."""
    p, R, v, w = (np.asarray(x, float) for x in (p, R, v, w))
    g = np.asarray(spec.get("gravity", (0.0, 0.0, -9.81)), float)
    bodies, _, X1, _ = _stencil(spec, _line(p, R, v, w), h, second=False)
    rates, _, _ = _body_rates(bodies, X1)
    T = V = 0.0
    for (m, J, kind, r, M), (vb, wb, _, _) in zip(bodies, rates, strict=True):
        T += 0.5 * m * vb @ vb + 0.5 * wb @ _world_inertia(J, kind, M) @ wb
        V -= m * g @ r
    return T, V


def power_balance_residual(spec, motion, t, *, h=1e-3) -> float:
    """sum_a F_a q_a_dot - d(T + V)/dt at time t (should vanish). motion(t) returns
    (p, R, v, w, a, alpha) of an admissible smooth platform motion; dE/dt by a 5-point
    stencil of step h in time, q_a_dot from the closed-form IK along the local model."""
    p, R, v, w, a, alpha = (np.asarray(x, float) for x in motion(t))
    F = actuator_forces(spec, p, R, v, w, a, alpha)
    _, _, X1, _ = _stencil(spec, _line(p, R, v, w), 1e-4, second=False)
    qdot = X1[X1.size - F.size :]
    E = [sum(energy(spec, *motion(t + o * h)[:4])) for o in _OFF]
    return float(F @ qdot - _D1 @ np.array(E) / h)
