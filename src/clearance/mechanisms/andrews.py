r"""Andrews' squeezing mechanism (seven-body mechanism), a validation problem with public data.

Source of every number: the Test Set for IVP Solvers (Univ. Bari), problem ``andrews``
(``andrews.f`` rev. 1.2, 2006; the same values are in the R deTestSet ``ex_andrews.R`` and in
pySDC), reproduced in ``/work/shared/reference/mechanisms.md`` section 3.1. The original is
Schiehlen (ed.) 1990, "Multibody Systems Handbook", and Hairer & Wanner, "Solving ODEs II",
section VII.7. The test set writes the mechanism in 7 relative angles
``q = (beta, Theta, gamma, Phi, delta, Omega, epsilon)`` with 6 loop-closure equations.
This module rebuilds it in the Cartesian body coordinates of `clearance`: 7 bodies in the
z = 0 plane, revolute joints about z, no gravity.

Sketch at the initial pose (plane z = 0; not to scale; ground points O = (0, 0),
A = (xa, ya), B = (xb, yb), C = (xc, yc); bodies numbered as the test set's angles)::

                                                   C o  ground anchor of the spring
                                                    /
                B o                                /  spring c0, free length l0
                  | \_                            /
                  |    \_   3 (triangle BDE)     /
       G o        |       o D ------------------
        / \       |      /
     5 /   \ 4    |    /
      /     \     |  /          2                    1
   A o       \    | /                                      (crank, torque mom)
      \        \ E o----------------------------- F o----o O
     7 \        /
        \     / 6
         o H

Point E is common to bodies 2, 3, 4 and 6 (three revolute joints E23, E24, E26); the
loop-closure equations g1..g6 of the test set state exactly these three coincidences.

Body frames. Every body frame is the world frame rotated about z by the body's absolute
angle (beta, beta + Theta, gamma, Phi + delta, delta, Omega + epsilon, epsilon). Body-fixed
points, written relative to the body's pivot (then shifted to the mass centre, because
`clearance` markers are relative to the mass centre). They follow from the loop-closure
equations and the mass matrix of the test set (``andrews.f``: ``m(1,1) = m1 ra^2 + m2 (rr^2 -
2 da rr cos Theta + da^2) + i1 + i2`` etc.):

=====  ===========  =======================================================================
body   pivot        points in the body frame (relative to the pivot)
=====  ===========  =======================================================================
1 OF   O            F (rr, 0); mass centre (ra, 0)
2 FE   F            E (-d, 0); mass centre (-da, 0)
3 BDE  B            D (sd, -sc); E (0, -ss); mass centre (sb, -sa)
4 EG   G            E (0, -e); mass centre (0, -(e - ea))
5 AG   A            G (zt, 0); mass centre (ta, tb)
6 HE   H            E (zf, 0); mass centre (zf - fa, 0)
7 AH   A            H (0, -u); mass centre (-ub, -ua)
=====  ===========  =======================================================================

For the bodies 1, 3, 5, 7 (pivoted on the ground, no gravity) only the distance of the mass
centre from the pivot enters the dynamics (``m1 ra^2``, ``m3 (sa^2 + sb^2)``, ...); the
coordinates above are those of the IFToMM A03 body table (mechanisms.md 3.1) up to the choice
of the frame origin (that table's frame for AH is only shown in a figure). For the bodies 2,
4 and 6 the mass centre lies on the joint line at the distances da from F, ea from E and fa
from E, which the off-diagonal mass-matrix entries ``m2 (da^2 - da rr cos Theta)``,
``m4 ((e-ea)^2 + zt (e-ea) sin Phi)`` and ``m6 ((zf-fa)^2 - u (zf-fa) sin Omega)`` fix. The
inertias i1..i7 are the moments about z; the in-plane moments are not given by the source
and do not influence the planar motion, so (PROPOSED) the bodies are thin plates:
J = diag(i/2, i/2, i).

Joint sets (``joints=``):

* ``"revolute"`` (default, the literal model): 10 revolutes, 50 rows on 42 velocity
  coordinates. The planar mechanism has one degree of freedom, so rank = 41 and 9 rows are
  redundant (3 out-of-plane rows per independent loop; 3 loops). `simulate(solver="auto")`
  detects this with `rank_check` and uses least-squares multipliers.
* ``"nonredundant"``: per loop one revolute becomes a spherical joint and one a universal
  joint (41 rows, full rank, DOF 1): loop O-F-E-B: E23 spherical, B universal; loop
  O-F-E-G-A: G spherical, E24 universal; loop O-F-E-H-A: H spherical, E26 universal. The
  universal cross axes are in the plane, perpendicular to the link lines (BE, EG, HE), so no
  link can spin about its own line. With no out-of-plane loads the planar motion is an exact
  solution of both models, so the motion is identical; only the multipliers differ.

Validation (tests/test_andrews.py): from Q0 to t = 0.03 s (DOPRI5, rtol 1e-11, projection)
the relative errors against the published reference are q <= 3e-10 and q_dot <= 5.2e-8 in
every component; q_ddot and the multipliers (`loop_multipliers`) agree to 1.4e-6. The
Cartesian model agrees with a float64 integration of the test set's own equations to
<= 4e-10 in every component, and those equations, evaluated at the published (q, q_dot),
already differ from the published q_ddot and lam by up to 1.3e-6: that is the accuracy of
the published y15..y27, not of this model.

Applied loads: the spring c0 between point D of body 3 and the ground point C (a
`SpringDamper`, stiffness c0, free length l0, no damping) and the constant driving torque
mom about +z on the crank (a `Torque`). No gravity.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from clearance.model import (
    GROUND,
    Body,
    Marker,
    Mechanism,
    Revolute,
    Spherical,
    SpringDamper,
    Torque,
    Universal,
)

if TYPE_CHECKING:
    from clearance.store.result import Result

# --------------------------------------------------------------------------- parameters
# Test Set for IVP Solvers, andrews.f (mechanisms.md 3.1); SI units.
MASS = (0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498)  # m1..m7 [kg]
INERTIA = (2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5)  # i1..i7
XA, YA = -0.06934, -0.00227  # ground point A [m]
XB, YB = -0.03635, 0.03273  # ground point B [m]
XC, YC = 0.014, 0.072  # ground point C (spring anchor) [m]
D, DA, E, EA = 28e-3, 115e-4, 2e-2, 1421e-5
RR, RA = 7e-3, 92e-5
SS, SA, SB, SC, SD = 35e-3, 1874e-5, 1043e-5, 18e-3, 2e-2
TA, TB = 2308e-5, 916e-5
U, UA, UB = 4e-2, 1228e-5, 449e-5
ZF, ZT, FA = 2e-2, 4e-2, 1421e-5
C0, L0 = 4530.0, 7785e-5  # spring stiffness [N/m] and free length [m]
MOM = 0.033  # driving torque on the crank [N m]

BODY_NAMES = ("OF", "FE", "BDE", "EG", "AG", "HE", "AH")
ANGLE_NAMES = ("beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon")

# Consistent initial values of the test set (q_dot0 = 0).
Q0 = np.array(
    [
        -0.0617138900142764496358948458001,
        0.0,
        0.455279819163070380255912382449,
        0.222668390165885884674473185609,
        0.487364979543842550225598953530,
        -0.222668390165885884674473185609,
        1.23054744454982119249735015568,
    ]
)
QDDOT0 = np.array(
    [14222.4439199541138705911625887, -10666.8329399655854029433719415, 0, 0, 0, 0, 0]
)
LAM0 = np.array([98.5668703962410896057654982170, -6.12268834425566265503114393122, 0, 0, 0, 0])

# Reference solution at t = 0.03 s (PSIDE, rtol = atol = 1e-14): y1..7 = q, y8..14 = q_dot,
# y15..21 = q_ddot, y22..27 = the test set's multipliers.
T_REFERENCE = 0.03
Y_REFERENCE = np.array(
    [
        0.1581077119629904e2,
        -0.1575637105984298e2,
        0.4082224013073101e-1,
        -0.5347301163226948e0,
        0.5244099658805304e0,
        0.5347301163226948e0,
        0.1048080741042263e1,
        0.1139920302151208e4,
        -0.1424379294994111e4,
        0.1103291221937134e2,
        0.1929337464421385e2,
        0.5735699284790808e0,
        -0.1929337464421385e2,
        0.3231791658026955e0,
        -0.2463176316945196e5,
        0.5185037701610329e5,
        0.3241025686413781e6,
        0.5667493645176213e6,
        0.1674362929479361e5,
        -0.5667493645176222e6,
        0.9826520791458422e4,
        0.1991753333731910e3,
        -0.2975531228015052e2,
        0.2306654119098399e2,
        0.3145271365475927e2,
        0.2264249232082739e2,
        0.1161740700019673e2,
    ]
)

# Body-fixed points relative to each body's pivot, body frame (see the module docstring).
_PIVOT_POINTS = {
    "OF": {"O": (0.0, 0.0), "F": (RR, 0.0), "cm": (RA, 0.0)},
    "FE": {"F": (0.0, 0.0), "E": (-D, 0.0), "cm": (-DA, 0.0)},
    "BDE": {"B": (0.0, 0.0), "D": (SD, -SC), "E": (0.0, -SS), "cm": (SB, -SA)},
    "EG": {"G": (0.0, 0.0), "E": (0.0, -E), "cm": (0.0, -(E - EA))},
    "AG": {"A": (0.0, 0.0), "G": (ZT, 0.0), "cm": (TA, TB)},
    "HE": {"H": (0.0, 0.0), "E": (ZF, 0.0), "cm": (ZF - FA, 0.0)},
    "AH": {"A": (0.0, 0.0), "H": (0.0, -U), "cm": (-UB, -UA)},
}

JOINT_SETS = ("revolute", "nonredundant")


# --------------------------------------------------------------------------- planar kinematics
def _rot(th: float) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s], [s, c]])


def absolute_angles(q: np.ndarray) -> np.ndarray:
    """Absolute body angles (bodies 1..7) from the test set's relative angles q (7,)."""
    be, th, ga, ph, de, om, ep = (float(x) for x in q)
    return np.array([be, be + th, ga, ph + de, de, om + ep, ep])


def planar_state(q: np.ndarray, qdot: np.ndarray | None = None) -> dict:
    """Planar pose of every body for relative angles q and rates qdot.

    Returns {body: (angle, angular rate, mass-centre position (2,), mass-centre velocity (2,))}.
    The pivots follow the test set's loop-closure equations; q must satisfy them (e.g. Q0).
    """
    q = np.asarray(q, dtype=float)
    qd = np.zeros(7) if qdot is None else np.asarray(qdot, dtype=float)
    th = absolute_angles(q)
    w = absolute_angles(qd)  # the map is linear, so it also maps the rates
    names = BODY_NAMES

    def point(k: int, pivot: np.ndarray, pivot_v: np.ndarray, key: str):
        sb = np.array(_PIVOT_POINTS[names[k]][key])
        s = _rot(th[k]) @ sb
        return pivot + s, pivot_v + w[k] * np.array([-s[1], s[0]])

    z = np.zeros(2)
    O, A, B = z, np.array([XA, YA]), np.array([XB, YB])
    F, Fv = point(0, O, z, "F")
    G, Gv = point(4, A, z, "G")
    H, Hv = point(6, A, z, "H")
    pivots = {
        "OF": (O, z),
        "FE": (F, Fv),
        "BDE": (B, z),
        "EG": (G, Gv),
        "AG": (A, z),
        "HE": (H, Hv),
        "AH": (A, z),
    }
    out = {}
    for k, nm in enumerate(names):
        c, cv = point(k, *pivots[nm], "cm")
        out[nm] = (th[k], w[k], c, cv)
    return out


def loop_closure(q: np.ndarray) -> np.ndarray:
    """The test set's six loop-closure residuals g1..g6 (``andfunc``) [m]."""
    be, th, ga, ph, de, om, ep = (float(x) for x in q)
    ex = RR * math.cos(be) - D * math.cos(be + th)
    ey = RR * math.sin(be) - D * math.sin(be + th)
    return np.array(
        [
            ex - SS * math.sin(ga) - XB,
            ey + SS * math.cos(ga) - YB,
            ex - E * math.sin(ph + de) - ZT * math.cos(de) - XA,
            ey + E * math.cos(ph + de) - ZT * math.sin(de) - YA,
            ex - ZF * math.cos(om + ep) - U * math.sin(ep) - XA,
            ey - ZF * math.sin(om + ep) + U * math.cos(ep) - YA,
        ]
    )


# --------------------------------------------------------------------------- the mechanism
def _rz(th: float) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def andrews_squeezer(
    q: np.ndarray | None = None,
    qdot: np.ndarray | None = None,
    *,
    joints: str = "revolute",
) -> Mechanism:
    """Andrews' squeezing mechanism as a `Mechanism` (see the module docstring).

    q, qdot: the test set's relative angles and rates for the initial pose (default Q0 and
    zero, the test set's consistent initial values). joints: "revolute" (10 revolutes,
    9 redundant rows) or "nonredundant" (spherical/universal at one joint pair per loop).
    """
    if joints not in JOINT_SETS:
        raise ValueError(f"joints must be one of {JOINT_SETS}, got {joints!r}")
    q = Q0 if q is None else np.asarray(q, dtype=float)
    st = planar_state(q, qdot)
    mech = Mechanism("andrews_squeezer", gravity=(0.0, 0.0, 0.0))

    for k, nm in enumerate(BODY_NAMES):
        th, w, c, cv = st[nm]
        i = INERTIA[k]
        mech.add(
            Body(
                nm,
                MASS[k],
                inertia=(0.5 * i, 0.5 * i, i),
                position=(c[0], c[1], 0.0),
                orientation=_rz(th),
                velocity=(cv[0], cv[1], 0.0),
                angular_velocity=(0.0, 0.0, w),
            )
        )

    def body_point(body: str, key: str) -> tuple:
        p = np.array(_PIVOT_POINTS[body][key]) - np.array(_PIVOT_POINTS[body]["cm"])
        return (p[0], p[1], 0.0)

    def mk(name: str, body: str, key: str, axis=(0.0, 0.0, 1.0), f_hint=None) -> str:
        if body == GROUND:
            pos = {"O": (0.0, 0.0, 0.0), "A": (XA, YA, 0.0), "B": (XB, YB, 0.0)}[key]
        else:
            pos = body_point(body, key)
        mech.add(Marker.on_axis(name, body, pos, axis=axis, f_hint=f_hint))
        return name

    def perp(body: str, a: str, b: str) -> tuple:
        """In-plane body-frame unit vector perpendicular to the line a-b of `body`."""
        d = np.array(_PIVOT_POINTS[body][b]) - np.array(_PIVOT_POINTS[body][a])
        n = np.array([-d[1], d[0]]) / np.hypot(*d)
        return (n[0], n[1], 0.0)

    # (joint name, body i, point key on i, body j, point key on j)
    table = [
        ("O", GROUND, "O", "OF", "O"),
        ("F", "OF", "F", "FE", "F"),
        ("B", GROUND, "B", "BDE", "B"),
        ("E23", "FE", "E", "BDE", "E"),
        ("A5", GROUND, "A", "AG", "A"),
        ("G", "AG", "G", "EG", "G"),
        ("E24", "FE", "E", "EG", "E"),
        ("A7", GROUND, "A", "AH", "A"),
        ("H", "AH", "H", "HE", "H"),
        ("E26", "FE", "E", "HE", "E"),
    ]
    # nonredundant variant: which joints change, and the universal cross axis on body j
    spherical = {"E23", "G", "H"}
    universal = {
        "B": perp("BDE", "B", "E"),
        "E24": perp("EG", "G", "E"),
        "E26": perp("HE", "H", "E"),
    }
    for jn, bi, ki, bj, kj in table:
        mi = mk(f"{jn}_i", bi, ki)
        if joints == "nonredundant" and jn in universal:
            mj = mk(f"{jn}_j", bj, kj, axis=universal[jn], f_hint=(0.0, 0.0, 1.0))
            mech.add(Universal(jn, mi, mj))
        elif joints == "nonredundant" and jn in spherical:
            mj = mk(f"{jn}_j", bj, kj)
            mech.add(Spherical(jn, mi, mj))
        else:
            mj = mk(f"{jn}_j", bj, kj)
            mech.add(Revolute(jn, mi, mj))

    mech.add(
        Marker("C", GROUND, (XC, YC, 0.0)),
        Marker("D", "BDE", body_point("BDE", "D")),
        SpringDamper("spring", "D", "C", stiffness=C0, free_length=L0),
        Marker("crank", "OF", (0.0, 0.0, 0.0)),
        Torque("mom", "crank", (0.0, 0.0, 1.0), MOM),
    )
    return mech.validate()


# --------------------------------------------------------------------------- output
def _unwrap(raw: np.ndarray, rate: np.ndarray, t: np.ndarray, start: float) -> np.ndarray:
    """Continuous angle from wrapped samples, choosing each 2 pi branch by the trapezoid
    integral of the rate (robust for sparse output as long as that integral errs < pi)."""
    out = np.empty_like(raw)
    out[0] = raw[0] + 2 * math.pi * round((start - raw[0]) / (2 * math.pi))
    for k in range(1, raw.size):
        pred = out[k - 1] + 0.5 * (rate[k] + rate[k - 1]) * (t[k] - t[k - 1])
        out[k] = raw[k] + 2 * math.pi * round((pred - raw[k]) / (2 * math.pi))
    return out


def relative_coordinates(result: Result, q_start: np.ndarray | None = None) -> dict:
    """The test set's coordinates from a `Result` of `andrews_squeezer`.

    Returns {"q": (n, 7), "qdot": (n, 7), "qddot": (n, 7), "out_of_plane": (n,)}: the
    relative angles (beta, Theta, gamma, Phi, delta, Omega, epsilon) with every absolute
    angle unwrapped continuously (so beta and Theta accumulate turns like the test set's
    y1, y2), their rates and accelerations (from the world z components of the angular
    velocities and accelerations), and the largest out-of-plane tilt |R[2, 0:2]| of any body
    at each sample. q_start (default Q0) picks the 2 pi branch at the first sample.
    """
    q_start = Q0 if q_start is None else np.asarray(q_start, dtype=float)
    th0 = absolute_angles(q_start)
    n = result.t.size
    th = np.empty((n, 7))
    w = np.empty((n, 7))
    al = np.empty((n, 7))
    tilt = np.zeros(n)
    for k, nm in enumerate(BODY_NAMES):
        R = result.rotation(nm)
        wz = result.angular_velocity(nm)[:, 2]
        kb = result.compiled.body_names.index(nm)
        alz = np.einsum("nij,nj->ni", R, result.a[:, 6 * kb + 3 : 6 * kb + 6])[:, 2]
        raw = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        th[:, k] = _unwrap(raw, wz, result.t, th0[k])
        w[:, k] = wz
        al[:, k] = alz
        tilt = np.maximum(tilt, np.hypot(R[:, 2, 0], R[:, 2, 1]))

    def rel(x: np.ndarray) -> np.ndarray:
        return np.column_stack(
            [
                x[:, 0],
                x[:, 1] - x[:, 0],
                x[:, 2],
                x[:, 3] - x[:, 4],
                x[:, 4],
                x[:, 5] - x[:, 6],
                x[:, 6],
            ]
        )

    return {"q": rel(th), "qdot": rel(w), "qddot": rel(al), "out_of_plane": tilt}


def energy_balance(result: Result, coords: dict | None = None) -> np.ndarray:
    """IFToMM A03 balance T + V_spring - E0 - mom (beta - beta0) [J] at every sample."""
    coords = relative_coordinates(result) if coords is None else coords
    T = result.energy["kinetic"]
    V = result.energy["potential"]
    beta = coords["q"][:, 0]
    return T + V - (T[0] + V[0]) - MOM * (beta - beta[0])


def loop_multipliers(result: Result) -> np.ndarray:
    """The test set's multipliers lam1..lam6 (n, 6) [N] from the joint reactions at E.

    In the test set ``M q_ddot = f - G^T lam`` with ``g = E_2 - E_k``, so (lam1, lam2),
    (lam3, lam4), (lam5, lam6) are the in-plane forces that body 2 exerts at E on bodies 3, 4
    and 6: the reaction forces of the joints E23, E24, E26 on their body j.
    """
    return np.concatenate([result.reaction(n)[0][:, :2] for n in ("E23", "E24", "E26")], axis=1)


__all__ = [
    "ANGLE_NAMES",
    "BODY_NAMES",
    "JOINT_SETS",
    "LAM0",
    "Q0",
    "QDDOT0",
    "T_REFERENCE",
    "Y_REFERENCE",
    "absolute_angles",
    "andrews_squeezer",
    "energy_balance",
    "loop_closure",
    "loop_multipliers",
    "planar_state",
    "relative_coordinates",
]
