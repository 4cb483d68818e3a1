"""Actuator force of a mass-moment lumped limb (physics.md i), from a Result.

A lumped S-P-S limb (`Leg(..., lumped=True)`, the 4-SPS/CU factory's "lumped" limbs) has
no driver row: its length l(t) enters through the sliding attachments and the inertia.
`limb_actuator_force` recovers the actuator force from the piston's axial balance.
"""

from __future__ import annotations

import numpy as np

from clearance.model.errors import ModelError
from clearance.model.functions import as_function

__all__ = ["limb_actuator_force"]


def limb_actuator_force(
    result: object,
    body: str,
    platform_joint: str,
    m1: float,
    m2: float,
    a1: float,
    a2: float,
    length_fn: object = None,
) -> np.ndarray:
    """(n,) actuator force [N] of the lumped limb `body`, positive pushing (extending):

        F_act = m2 u . a_2 - u . f_(platform->piston) - m2 u . g_vec,

    u = limb axis (body z), a_2 = acceleration of the piston's mass centre
    r_2 = r_G + k(l) u, k(l) = l - a2 - c(l) = m1 (l - a1 - a2)/m, so
    a_2 = r_ddot_G + k_ddot u + 2 k_dot u_dot + k u_ddot (u_dot = w x u,
    u_ddot = alpha x u + w x (w x u)). f_(platform->piston): the force of `platform_joint`
    on the limb: its reaction when ideal, the contact force on the ball (normal + friction,
    sign flipped if the limb holds the socket) when it has clearance. m1, a1: cylinder
    mass [kg] and mass centre from the base joint [m]; m2, a2: piston's, from the platform
    joint. length_fn: l(t) [m]; None = the limb body's InertiaVariation length.
    """
    who = "limb_actuator_force"
    c = result.compiled  # type: ignore[attr-defined]
    mech = c.mechanism
    if body not in c.body_names:
        raise ModelError(who, "body", body, f"no such body in '{mech.name}'")
    if length_fn is None:
        var = mech.bodies[body].inertia_variation
        if var is None:
            raise ModelError(who, "length_fn", None, f"{body} has no InertiaVariation; pass l(t)")
        fn = var.length
    else:
        fn = as_function(length_fn, owner=who, field="length_fn")
    m = m1 + m2
    if abs(mech.bodies[body].mass - m) > 1e-12 * m:
        raise ModelError(
            who, "m1, m2", (m1, m2), f"m1 + m2 = {m} kg differs from the mass of {body}"
        )

    t = result.t  # type: ignore[attr-defined]
    L = fn.evaluate(t)
    l, ld, ldd = L[:, 0], L[:, 1], L[:, 2]
    R = result.rotation(body)  # type: ignore[attr-defined]
    u = R[:, :, 2]
    w = result.angular_velocity(body)  # type: ignore[attr-defined]
    kb = c.body_names.index(body)
    alpha = np.einsum("nij,nj->ni", R, result.a[:, 6 * kb + 3 : 6 * kb + 6])  # type: ignore[attr-defined]
    a_g = result.acceleration(body)  # type: ignore[attr-defined]
    k, kd, kdd = m1 * (l - a1 - a2) / m, m1 * ld / m, m1 * ldd / m
    ud = np.cross(w, u)
    udd = np.cross(alpha, u) + np.cross(w, ud)
    a2_vec = a_g + kdd[:, None] * u + 2.0 * kd[:, None] * ud + k[:, None] * udd

    jname = platform_joint
    if jname in result.clearance_names:  # type: ignore[attr-defined]
        info = c.clearances[list(result.clearance_names).index(jname)]  # type: ignore[attr-defined]
        f_ball = result.normal_force(jname) + result.friction_force(jname)  # type: ignore[attr-defined]
        if info.ball_body == body:
            f = f_ball
        elif info.socket_body == body:
            f = -f_ball
        else:
            raise ModelError(who, "platform_joint", jname, f"does not act on {body}")
    else:
        if jname not in result.blocks:  # type: ignore[attr-defined]
            raise ModelError(who, "platform_joint", jname, "unknown joint of the result")
        kblk = result.blocks.index(jname)  # type: ignore[attr-defined]
        f = result.reaction(jname)[0]  # type: ignore[attr-defined]
        rep = result.reaction_body[kblk]  # type: ignore[attr-defined]
        jt = mech.joints[jname]
        bodies = {mech.markers[jt.marker_i].body, mech.markers[jt.marker_j].body}
        if body not in bodies:
            raise ModelError(who, "platform_joint", jname, f"does not act on {body}")
        if rep != body:  # reported on the other body: action = - reaction
            f = -f
    g = np.asarray(mech.gravity, dtype=float)
    return m2 * np.einsum("ni,ni->n", u, a2_vec) - np.einsum("ni,ni->n", u, f) - m2 * (u @ g)
