"""Independent oracle: planar slider-crank with a revolute clearance joint (coupler/slider).

This module is a stand-alone second implementation (numpy + scipy only) written without
looking at the ``clearance`` package sources. It integrates the planar slider-crank in
minimal coordinates and is meant to be compared against the package's 3-D model.

Geometry and bodies (SI units: m, kg, s, rad, N, N m, J)
--------------------------------------------------------
Plane x-y, gravity ``(0, -g)``. Unit vectors: ``u(a) = (cos a, sin a)``,
``u'(a) = (-sin a, cos a)``; 2-D cross product ``a x b = a_x b_y - a_y b_x``.

* Crank O-B (body 1): ``theta(t) = theta0 + omega t`` is prescribed (``theta_ddot = 0``),
  ``B = r u(theta)``; mass centre ``G1 = B / 2``; ``J1`` about ``G1``.
* Coupler B-C (body 2): angle ``phi`` from the x axis, ``C = B + l u(phi)``, mass centre
  ``G2 = B + (l/2) u(phi)``; ``J2`` about ``G2``; ideal revolute with the crank at ``B``.
* Slider (body 3): ``S = (x, 0)`` (ideal prismatic along x, no rotation), mass ``m3``.

Kinematics (``omega = theta_dot``)::

    v_B  = r omega u'(theta),              a_B = -r omega^2 u(theta)
    v_C  = v_B + l phi_dot u'(phi)
    v_G2 = v_B + (l/2) phi_dot u'(phi)
    a_G2 = a_B + (l/2) (phi_ddot u'(phi) - phi_dot^2 u(phi))

Clearance joint force element
-----------------------------
``e = C - S``, ``delta = |e| - c`` (``c = R_B - R_J``), ``n = e / |e|``;
contact points ``Q_J = C + R_J n`` (coupler), ``Q_B = S + R_B n`` (slider);
``delta_dot = n . (v_C - v_S)`` with ``v_S = (x_dot, 0)``.

Lankarani-Nikravesh normal force (contact state only, ``delta > 0``)::

    F_N = max(0, K delta^1.5 (1 + 3 (1 - c_r^2) / 4 * delta_dot / delta_dot_minus))

``delta_dot_minus = max(delta_dot(onset), v_floor)`` is latched at the located onset event
and held until the located separation event.

Friction (Ambrosio): ``v_rel = v(Q_J) - v(Q_B) = v_C + phi_dot R_J n_perp - v_S``
(``n_perp = (-n_y, n_x)``), ``v_t = v_rel - (n . v_rel) n``, ``F_T = mu c_d(|v_t|) F_N`` with
``c_d = 0`` (``|v_t| < v0``), ``(|v_t| - v0) / (v1 - v0)`` (between), ``1`` (``|v_t| > v1``),
``t = v_t / |v_t|``. Force on the coupler at ``Q_J``: ``f = -F_N n - F_T t``; on the slider at
``Q_B``: ``-f`` (its y part and its moment go into the prismatic reaction).

Equations of motion (Newton-Euler; equivalently Lagrange with ``q = (phi, x)``)
-----------------------------------------------------------------------------
Coupler, moment balance about the moving pin ``B`` (whose acceleration ``a_B`` is
prescribed), which eliminates the unknown pin force::

    J_B phi_ddot = -m2 g (l/2) cos(phi) + (Q_J - B) x f + m2 (l/2) r omega^2 sin(theta - phi),
    J_B = J2 + m2 l^2 / 4.

(The last term is ``-m2 (G2 - B) x a_B``; Lagrange with
``T2 = m2/2 |v_G2|^2 + J2/2 phi_dot^2`` gives the same equation since
``d/dt dT2/dphi_dot - dT2/dphi = J_B phi_ddot - m2 (l/2) r omega^2 sin(theta - phi)``, and the
generalised force of ``f`` is ``f . dv_QJ/dphi_dot = (Q_J - B) x f``.)

Slider, x direction::

    m3 x_ddot = -f_x.

Pin force exerted by the crank on the coupler (coupler translation)::

    P = m2 a_G2 + (0, m2 g) - f.

Driving moment (crank rotation about the fixed pivot O with ``theta_ddot = 0``; the coupler
acts on the crank with ``-P`` at ``B``)::

    0 = M + B x (-P) + G1 x (0, -m1 g)   =>   M = B x P + m1 g (r/2) cos(theta).

Energies
--------
``T = (J1 + m1 r^2/4) omega^2 / 2 + m2 |v_G2|^2 / 2 + J2 phi_dot^2 / 2 + m3 x_dot^2 / 2``,
``V = m1 g (r/2) sin(theta) + m2 g G2_y`` (slider height is constant), ``U = K delta^2.5 / 2.5``.
Power balance: ``d(T + V + U)/dt = M omega - (F_N - K delta^1.5) delta_dot - F_T |v_t|``
(the normal part of ``v_rel`` equals ``delta_dot``). The three integrals
``W = int M omega dt``, ``D_N = int (F_N - K delta^1.5) delta_dot dt`` and
``D_T = int F_T |v_t| dt`` are integrated together with the state, and
``residual = (T + V + U)(t) - (T + V + U)(0) - W + D_N + D_T``.

Event handling
--------------
The integration is split into segments with a fixed discrete state (free / contact and the
latched ``delta_dot_minus``). In the free state a terminal event on ``delta`` (direction +1)
locates the onset; in the contact state a terminal event on ``delta + h_sep`` (direction -1)
locates the separation, where ``h_sep = 1e-14 m`` is a tiny hysteresis so that the restart
point of either state lies strictly on the correct side of its event surface (no spurious
event at the restart point, no missed separation right after a grazing onset). The force is
exactly zero for ``delta <= 0`` in either state, so the hysteresis changes no force.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

RPM = 2.0 * math.pi / 60.0  # rad/s per rpm

#: Separation hysteresis [m] (see the module docstring).
H_SEP = 1.0e-14


@dataclass
class SliderCrankParams:
    """Parameters of the planar slider-crank (SI units)."""

    r: float = 0.05  # crank length O-B [m]
    l: float = 0.12  # coupler length B-C [m]
    m1: float = 0.30  # crank mass [kg]
    m2: float = 0.21  # coupler mass [kg]
    m3: float = 0.14  # slider mass [kg]
    J1: float = 1.0e-4  # crank inertia about its mass centre [kg m^2]
    J2: float = 2.5e-4  # coupler inertia about its mass centre [kg m^2]
    J3: float = 1.0e-4  # slider inertia [kg m^2] (unused: the slider does not rotate)
    omega: float = field(default=5000.0 * RPM)  # crank speed [rad/s]
    theta0: float = 0.0  # crank angle at t = 0 [rad]
    R_B: float = 0.010  # bearing radius [m]
    R_J: float = 0.0095  # journal radius [m]
    K: float = 6.61e10  # contact stiffness [N/m^1.5]
    c_r: float = 0.9  # coefficient of restitution [-]
    mu: float = 0.0  # friction coefficient [-]
    v0: float = 1.0e-4  # friction: no friction below this tangential speed [m/s]
    v1: float = 1.0e-3  # friction: full Coulomb above this tangential speed [m/s]
    v_floor: float = 1.0e-4  # floor of the latched onset speed delta_dot_minus [m/s]
    g: float = 9.81  # gravity magnitude, acting along -y [m/s^2]

    @property
    def c(self) -> float:
        """Radial clearance ``R_B - R_J`` [m]."""
        return self.R_B - self.R_J


# --------------------------------------------------------------------------------------
# Closed-form ideal mechanism
# --------------------------------------------------------------------------------------
def ideal_slider(params: SliderCrankParams, t):
    """Ideal (c = 0) slider position, velocity and acceleration for the prescribed crank.

    With ``s = r sin(theta)``, ``D = sqrt(l^2 - s^2)``::

        x       = r cos(theta) + D
        x_dot   = -r omega sin(theta) - s s_dot / D
        x_ddot  = -r omega^2 cos(theta) - (s_dot^2 + s s_ddot) / D - s^2 s_dot^2 / D^3

    where ``s_dot = r omega cos(theta)`` and ``s_ddot = -r omega^2 sin(theta)``.
    Returns ``(x [m], x_dot [m/s], x_ddot [m/s^2])`` with the shape of ``t``.
    """
    p = params
    t = np.asarray(t, dtype=float)
    th = p.theta0 + p.omega * t
    w = p.omega
    s = p.r * np.sin(th)
    sd = p.r * w * np.cos(th)
    sdd = -p.r * w * w * np.sin(th)
    D = np.sqrt(p.l * p.l - s * s)
    x = p.r * np.cos(th) + D
    xd = -p.r * w * np.sin(th) - s * sd / D
    xdd = -p.r * w * w * np.cos(th) - (sd * sd + s * sdd) / D - s * s * sd * sd / D**3
    return x, xd, xdd


def initial_state(params: SliderCrankParams) -> np.ndarray:
    """Ideal configuration and velocities at ``theta0`` with the journal centred (e = 0).

    ``C_y = 0``: ``phi = -asin(r sin(theta0) / l)`` (branch with the slider to the right of
    the crank pin), ``x = r cos(theta0) + l cos(phi)``; ``C_y_dot = 0``:
    ``phi_dot = -r omega cos(theta0) / (l cos(phi))``,
    ``x_dot = -r omega sin(theta0) - l phi_dot sin(phi)`` (so ``e_dot = 0``).
    Returns ``[phi, x, phi_dot, x_dot]``.
    """
    p = params
    th = p.theta0
    phi = -math.asin(p.r * math.sin(th) / p.l)
    x = p.r * math.cos(th) + p.l * math.cos(phi)
    phid = -p.r * p.omega * math.cos(th) / (p.l * math.cos(phi))
    xd = -p.r * p.omega * math.sin(th) - p.l * phid * math.sin(phi)
    return np.array([phi, x, phid, xd])


# --------------------------------------------------------------------------------------
# Model evaluation
# --------------------------------------------------------------------------------------
def _evaluate(p: SliderCrankParams, t: float, y, in_contact: bool, vminus: float) -> dict:
    """All model quantities at one instant for a given discrete state.

    ``y = [phi, x, phi_dot, x_dot, W, D_N, D_T]`` (the last three entries are not used here).
    Returns a dict with the accelerations, the driving moment, the contact quantities and
    the power terms (``dW``, ``dDN``, ``dDT``) for the energy integrals.
    """
    phi, x, phid, xd = float(y[0]), float(y[1]), float(y[2]), float(y[3])
    w = p.omega
    th = p.theta0 + w * t
    cth, sth = math.cos(th), math.sin(th)
    cph, sph = math.cos(phi), math.sin(phi)
    hl = 0.5 * p.l

    # Positions and velocities.
    Bx, By = p.r * cth, p.r * sth
    Cx, Cy = Bx + p.l * cph, By + p.l * sph
    vBx, vBy = -p.r * w * sth, p.r * w * cth
    vCx, vCy = vBx - p.l * phid * sph, vBy + p.l * phid * cph
    ex, ey = Cx - x, Cy
    emag = math.hypot(ex, ey)
    delta = emag - p.c

    # Contact force on the coupler (f) applied at Q_J.
    FN = FT = vt_mag = ddelta = 0.0
    fx = fy = 0.0
    QJx, QJy = Cx, Cy
    dDN = 0.0
    if emag > 0.0:
        nx, ny = ex / emag, ey / emag
        ddelta = nx * (vCx - xd) + ny * vCy
    else:
        nx, ny = 1.0, 0.0
    if in_contact and delta > 0.0:
        # delta * sqrt(delta) instead of delta**1.5: a wild trial stage then gives inf
        # (the step is rejected) instead of raising OverflowError.
        fel = p.K * delta * math.sqrt(delta)
        FN = fel * (1.0 + 0.75 * (1.0 - p.c_r**2) * ddelta / vminus)
        if FN < 0.0:
            FN = 0.0
        QJx, QJy = Cx + p.R_J * nx, Cy + p.R_J * ny
        fx, fy = -FN * nx, -FN * ny
        dDN = (FN - fel) * ddelta
        if p.mu != 0.0:
            # Relative velocity of the contact points (slider translates only).
            vrx = vCx - phid * p.R_J * ny - xd
            vry = vCy + phid * p.R_J * nx
            vn = nx * vrx + ny * vry
            vtx, vty = vrx - vn * nx, vry - vn * ny
            vt_mag = math.hypot(vtx, vty)
            if vt_mag <= p.v0:
                cd = 0.0
            elif vt_mag >= p.v1:
                cd = 1.0
            else:
                cd = (vt_mag - p.v0) / (p.v1 - p.v0)
            FT = p.mu * cd * FN
            if FT > 0.0:
                fx -= FT * vtx / vt_mag
                fy -= FT * vty / vt_mag

    # Coupler: moment balance about the moving pin B.
    JB = p.J2 + p.m2 * hl * hl
    dx, dy = QJx - Bx, QJy - By
    Mf = dx * fy - dy * fx
    phidd = (-p.m2 * p.g * hl * cph + Mf + p.m2 * hl * p.r * w * w * math.sin(th - phi)) / JB
    # Slider: x direction.
    xdd = -fx / p.m3

    # Pin force from the crank on the coupler and the driving moment.
    aBx, aBy = -p.r * w * w * cth, -p.r * w * w * sth
    aGx = aBx + hl * (-phidd * sph - phid * phid * cph)
    aGy = aBy + hl * (phidd * cph - phid * phid * sph)
    Px = p.m2 * aGx - fx
    Py = p.m2 * aGy + p.m2 * p.g - fy
    M = Bx * Py - By * Px + p.m1 * p.g * 0.5 * p.r * cth

    return {
        "phi_ddot": phidd,
        "x_ddot": xdd,
        "M": M,
        "ex": ex,
        "ey": ey,
        "delta": delta,
        "delta_dot": ddelta,
        "F_N": FN,
        "F_T": FT,
        "dW": M * w,
        "dDN": dDN,
        "dDT": FT * vt_mag,
    }


def _energies(p: SliderCrankParams, t, phi, phid, xd, delta):
    """Kinetic, gravitational potential and elastic energy [J] (vectorised over samples)."""
    w = p.omega
    th = p.theta0 + w * np.asarray(t)
    hl = 0.5 * p.l
    vGx = -p.r * w * np.sin(th) - hl * phid * np.sin(phi)
    vGy = p.r * w * np.cos(th) + hl * phid * np.cos(phi)
    T = (
        0.5 * (p.J1 + p.m1 * (0.5 * p.r) ** 2) * w * w
        + 0.5 * p.m2 * (vGx**2 + vGy**2)
        + 0.5 * p.J2 * phid**2
        + 0.5 * p.m3 * xd**2
    )
    V = p.m1 * p.g * 0.5 * p.r * np.sin(th) + p.m2 * p.g * (p.r * np.sin(th) + hl * np.sin(phi))
    U = p.K * np.maximum(delta, 0.0) ** 2.5 / 2.5
    return T, V, U


# --------------------------------------------------------------------------------------
# Simulation with located contact events
# --------------------------------------------------------------------------------------
def simulate(
    params: SliderCrankParams,
    t_end: float,
    t_eval,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-13,
    method: str = "DOP853",
    max_segments: int = 1_000_000,
) -> dict:
    """Integrate the clearance slider-crank from ``initial_state(params)`` on ``[0, t_end]``.

    The state is ``[phi, x, phi_dot, x_dot, W, D_N, D_T]`` (the last three are the energy
    integrals). Contact onset / separation are located by terminal ``solve_ivp`` events and
    the integration is restarted from the event state with the new discrete state.
    ``t_eval`` (within ``[0, t_end]``) is sampled from each segment's dense output; a sample
    that coincides with an event time is taken from the segment that starts there.

    Returns a dict of arrays (see the module docstring for the definitions): ``t``,
    ``theta``, ``phi``, ``x``, ``phi_dot``, ``x_dot``, ``phi_ddot``, ``x_ddot``, ``M``,
    ``e`` (n, 2), ``delta``, ``F_N``, ``F_T``, ``in_contact``; ``events`` (list of
    ``(t, kind, delta_dot)``, kind +1 onset / -1 separation); ``energy`` (dict with
    ``kinetic``, ``potential``, ``elastic``, ``work_drive``, ``dissipated_normal``,
    ``dissipated_friction``, ``residual``); and ``stats`` (segments, RHS calls, runtime).
    """
    p = params
    t_eval = np.asarray(t_eval, dtype=float)
    if np.any(np.diff(t_eval) < 0.0):
        raise ValueError("t_eval must be sorted")
    if t_eval.size and (t_eval[0] < 0.0 or t_eval[-1] > t_end):
        raise ValueError("t_eval must lie within [0, t_end]")
    n_s = t_eval.size
    Y = np.empty((n_s, 7))  # states at the samples
    flags = np.zeros(n_s, dtype=bool)
    vms = np.ones(n_s)

    y = np.concatenate([initial_state(p), np.zeros(3)])
    t0 = 0.0
    # Discrete state at t = 0 (normally free: the journal starts centred).
    ev0 = _evaluate(p, 0.0, y, False, 1.0)
    in_contact = ev0["delta"] > 0.0
    vminus = max(ev0["delta_dot"], p.v_floor)
    events: list[tuple[float, int, float]] = []
    nfev = 0
    n_seg = 0
    tic = time.perf_counter()

    def delta_of(t, yy):
        ex = p.r * math.cos(p.theta0 + p.omega * t) + p.l * math.cos(yy[0]) - yy[1]
        ey = p.r * math.sin(p.theta0 + p.omega * t) + p.l * math.sin(yy[0])
        return math.hypot(ex, ey) - p.c

    def ev_onset(t, yy):
        return delta_of(t, yy)

    ev_onset.terminal = True
    ev_onset.direction = 1.0

    def ev_separation(t, yy):
        return delta_of(t, yy) + H_SEP

    ev_separation.terminal = True
    ev_separation.direction = -1.0

    i_s = 0  # next sample index to fill
    # Initial step of a restarted segment: the last step size of the previous segment
    # (scipy's automatic guess sees no contact force at delta = 0 and is far too large).
    h_prev = None
    n_stall = 0  # consecutive events without progress in time (guard against loops)
    while True:
        if t0 >= t_end:  # an event exactly at t_end: remaining samples from the event state
            Y[i_s:] = y
            flags[i_s:] = in_contact
            vms[i_s:] = vminus
            break
        n_seg += 1
        if n_seg > max_segments:
            raise RuntimeError("too many contact segments")
        flag, vm = in_contact, vminus

        def rhs(t, yy, flag=flag, vm=vm):
            d = _evaluate(p, t, yy, flag, vm)
            return np.array([yy[2], yy[3], d["phi_ddot"], d["x_ddot"], d["dW"], d["dDN"], d["dDT"]])

        # A too large trial step into a stiff contact can overflow inside the RK stages; the
        # step is then rejected by the error control (inf/nan error norm), so the floating
        # point warnings of that trial are silenced here. Failures still surface via status.
        with np.errstate(over="ignore", invalid="ignore"):
            res = solve_ivp(
                rhs,
                (t0, t_end),
                y,
                method=method,
                rtol=rtol,
                atol=atol,
                dense_output=True,
                events=[ev_separation if flag else ev_onset],
                first_step=h_prev,
            )
        if res.status < 0:
            raise RuntimeError(f"solve_ivp failed at t = {t0}: {res.message}")
        nfev += res.nfev
        hit = res.status == 1
        if hit:
            t_stop = float(res.t_events[0][0])
            y_stop = np.array(res.y_events[0][0], dtype=float)
        else:
            t_stop = float(res.t[-1])
            y_stop = res.y[:, -1].copy()

        # Samples of this segment: [t0, t_stop) for an event stop, [t0, t_end] at the end.
        i_e = i_s
        while i_e < n_s and (t_eval[i_e] < t_stop or (not hit and t_eval[i_e] <= t_stop)):
            i_e += 1
        if i_e > i_s:
            Y[i_s:i_e] = res.sol(t_eval[i_s:i_e]).T
            flags[i_s:i_e] = flag
            vms[i_s:i_e] = vm
            i_s = i_e

        if not hit:
            break
        if res.t.size >= 2:
            h_prev = min(float(res.t[-1] - res.t[-2]), t_end - t_stop)
            if h_prev <= 0.0:
                h_prev = None
        n_stall = n_stall + 1 if t_stop <= t0 else 0
        if n_stall > 3:
            raise RuntimeError(f"event loop without progress at t = {t_stop}")
        ddelta = _evaluate(p, t_stop, y_stop, flag, vm)["delta_dot"]
        if flag:  # separation: release the latch
            events.append((t_stop, -1, ddelta))
            in_contact = False
        else:  # onset: latch delta_dot_minus
            events.append((t_stop, +1, ddelta))
            in_contact = True
            vminus = max(ddelta, p.v_floor)
            # First step into the contact: a small fraction of the time needed to cross
            # the clearance at the impact speed (the error control enlarges it quickly).
            h_imp = 0.01 * p.c / vminus
            h_prev = h_imp if h_prev is None else min(h_prev, h_imp)
        t0, y = t_stop, y_stop
    runtime = time.perf_counter() - tic

    # Post-processing at the samples.
    keys = ("phi_ddot", "x_ddot", "M", "ex", "ey", "delta", "F_N", "F_T")
    out = {k: np.empty(n_s) for k in keys}
    for i in range(n_s):
        d = _evaluate(p, t_eval[i], Y[i], bool(flags[i]), vms[i])
        for k in keys:
            out[k][i] = d[k]
    phi, x, phid, xd = Y[:, 0], Y[:, 1], Y[:, 2], Y[:, 3]
    W, DN, DT = Y[:, 4], Y[:, 5], Y[:, 6]
    T, V, U = _energies(p, t_eval, phi, phid, xd, out["delta"])
    # Reference energy at t = 0 (independent of whether t = 0 is sampled).
    y_init = initial_state(p)
    T0, V0, U0 = _energies(p, 0.0, y_init[0], y_init[2], y_init[3], ev0["delta"])
    E0 = T0 + V0 + U0
    residual = T + V + U - E0 - W + DN + DT

    return {
        "t": t_eval.copy(),
        "theta": p.theta0 + p.omega * t_eval,
        "phi": phi.copy(),
        "x": x.copy(),
        "phi_dot": phid.copy(),
        "x_dot": xd.copy(),
        "phi_ddot": out["phi_ddot"],
        "x_ddot": out["x_ddot"],
        "M": out["M"],
        "e": np.column_stack([out["ex"], out["ey"]]),
        "delta": out["delta"],
        "F_N": out["F_N"],
        "F_T": out["F_T"],
        "in_contact": flags,
        "events": events,
        "energy": {
            "kinetic": T,
            "potential": V,
            "elastic": U,
            "work_drive": W.copy(),
            "dissipated_normal": DN.copy(),
            "dissipated_friction": DT.copy(),
            "residual": residual,
        },
        "stats": {"segments": n_seg, "nfev": nfev, "runtime_s": runtime},
    }


# --------------------------------------------------------------------------------------
# Self-checks
# --------------------------------------------------------------------------------------
def _self_checks() -> None:  # pragma: no cover - manual run
    base = SliderCrankParams()
    period = 2.0 * math.pi / base.omega
    t_end = 2.0 * period
    t_eval = np.linspace(0.0, t_end, 24001)  # 1e-6 s spacing at 5000 rpm

    # 1. Nearly ideal joint: tiny clearance, very stiff contact.
    p1 = SliderCrankParams(R_J=base.R_B - 1e-7, K=1e13, c_r=0.9)
    tic = time.perf_counter()
    s1 = simulate(p1, t_end, t_eval)
    rt1 = time.perf_counter() - tic
    _, _, xdd_id = ideal_slider(p1, t_eval)
    scale = np.max(np.abs(xdd_id))
    err = np.abs(s1["x_ddot"] - xdd_id) / scale
    ev_t = np.array([e[0] for e in s1["events"]])
    # Exclude the first half revolution (transient) and +-2 % of a period around events.
    mask = t_eval > 0.5 * period
    for te in ev_t:
        mask &= np.abs(t_eval - te) > 0.02 * period
    print("check 1 (c = 1e-7 m, K = 1e13): events =", len(ev_t), f"runtime = {rt1:.2f} s")
    print(
        f"  max|x_ddot - ideal| / max|ideal| (away from events, t > T/2) = "
        f"{err[mask].max():.3e}  (over {mask.sum()} of {mask.size} samples); "
        f"median = {np.median(err[mask]):.3e}; overall max = {err.max():.3e}"
    )

    # 1b. Driving moment of the nearly ideal joint against the ideal mechanism's power
    # balance: M_ideal omega = d(T + V)/dt along the closed-form ideal motion.
    th = p1.theta0 + p1.omega * t_eval
    phi_id = -np.arcsin(p1.r * np.sin(th) / p1.l)
    phid_id = -p1.r * p1.omega * np.cos(th) / (p1.l * np.cos(phi_id))
    _, xd_id, _ = ideal_slider(p1, t_eval)
    T_id, V_id, _ = _energies(p1, t_eval, phi_id, phid_id, xd_id, np.zeros_like(t_eval))
    M_id = np.gradient(T_id + V_id, t_eval, edge_order=2) / p1.omega
    errM = np.abs(s1["M"] - M_id) / np.max(np.abs(M_id))
    print(
        f"  driving moment: max|M - M_ideal| / max|M_ideal| (same mask) = {errM[mask].max():.3e}"
        f" (max|M_ideal| = {np.max(np.abs(M_id)):.3f} N m)"
    )

    # 2. Conservative contact: c_r = 1, mu = 0.
    p2 = SliderCrankParams(c_r=1.0, mu=0.0)
    s2 = simulate(p2, t_end, t_eval)
    Tscale = np.max(s2["energy"]["kinetic"])
    res2 = np.max(np.abs(s2["energy"]["residual"]))
    n_imp2 = sum(1 for e in s2["events"] if e[1] == 1)
    print(
        f"check 2 (c_r = 1): impacts = {n_imp2}, max|residual| = {res2:.3e} J, "
        f"relative to max T = {Tscale:.3f} J: {res2 / Tscale:.3e}; "
        f"max dissipated_normal = {np.max(np.abs(s2['energy']['dissipated_normal'])):.3e} J; "
        f"runtime = {s2['stats']['runtime_s']:.2f} s"
    )

    # 3. Default parameters.
    s3 = simulate(base, t_end, t_eval)
    n_imp3 = sum(1 for e in s3["events"] if e[1] == 1)
    Tscale3 = np.max(s3["energy"]["kinetic"])
    res3 = np.max(np.abs(s3["energy"]["residual"]))
    on = [e for e in s3["events"] if e[1] == 1]
    print(
        f"check 3 (defaults): impacts = {n_imp3}, segments = {s3['stats']['segments']}, "
        f"nfev = {s3['stats']['nfev']}, runtime = {s3['stats']['runtime_s']:.2f} s"
    )
    print(
        f"  peak F_N (samples) = {np.max(s3['F_N']):.4e} N, "
        f"peak |x_ddot| (samples) = {np.max(np.abs(s3['x_ddot'])):.4e} m/s^2, "
        f"max|residual| = {res3:.3e} J (rel. {res3 / Tscale3:.3e}), "
        f"dissipated_normal(t_end) = {s3['energy']['dissipated_normal'][-1]:.4e} J"
    )
    if on:
        print(
            f"  onset speeds: max = {max(e[2] for e in on):.4e} m/s, "
            f"min = {min(e[2] for e in on):.4e} m/s"
        )


if __name__ == "__main__":  # pragma: no cover
    _self_checks()
