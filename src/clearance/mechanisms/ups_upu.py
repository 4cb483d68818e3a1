"""The ideal 4UPS-UPU spatial parallel mechanism (mechanisms.md 1.2-1.4), leg-length driven.

Topology (ground z up, origin at the base centre; all joints ideal)::

                         platform (body 1, centre C = (0, 0, 0.70) m at home)
          B1 (S)     B2 (S)      B5 = C (U')     B3 (S)     B4 (S)
            |          |              |             |          |
         tele_1     tele_2         tele_5        tele_3     tele_4     telescopic rods
            P          P              P             P          P       actuated prismatic
         swing_1    swing_2        swing_5       swing_3    swing_4    swing rods
            |          |              |             |          |
          A1 (U)     A2 (U)      A5 = O (U)      A3 (U)     A4 (U)
      ===================== ground (static platform) ======================

* Legs k = 1..4 are U-P-S: U_k (ground - swing_k) at A_k with the tangential ground axis
  t_k = (-sin th_k, cos th_k, 0) and the swing-rod cross axis u_k x t_k; P_k (swing_k -
  tele_k) along the leg axis u_k with the rotation about it locked; S_k (platform -
  tele_k) at B_k. The platform carries the socket (body i), the rod the ball (body j), as
  in mechanisms.md 1.3 for the later clearance variant.
* Leg 5 is U-P-U: U_5 (ground - swing_5) at A_5 = O with ground axis x and swing-rod axis y;
  P_5 along z; U'_5 (tele_5 - platform) at the platform centre with rod axis y and platform
  axis x. The platform orientation is then Rx Ry Rx: two tilts, no twist.
* Drivers: one `PrismaticDriver` per prismatic joint, value = leg length |A_k B_k| [m]
  (phi = h_i . d - l_k(t), d from the swing-rod marker at A_k to the rod marker at B_k).

Rows: 4 x (4 + 5 + 3) + (4 + 5 + 4) = 61 joint rows + 5 drivers = 66 = 6 x 11: DOF 0.

Parameters: the PROPOSED reconstruction of mechanisms.md 1.4 with the NON-singular layout
(base angles 45, 135, 225, 315 deg; platform angles 75, 165, 195, 285 deg). Body frames:
every rod has its axis as body z (pointing from A_k to B_k), the platform is aligned with
the world at home. Initial poses are the exact home pose; `clearance.assemble` polishes them
at t = 0 if the drives do not start at the home lengths.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from clearance.model import (
    GROUND,
    Body,
    Marker,
    Mechanism,
    ModelError,
    Prismatic,
    PrismaticDriver,
    Spherical,
    TimeFunction,
    Universal,
)
from clearance.model.functions import Sinusoid, as_function

__all__ = ["UPS_UPU_PARAMS", "home_leg_lengths", "ups_upu_ideal"]

# mechanisms.md 1.4 (PROPOSED reconstruction). Lengths m, masses kg, inertias kg m^2 about
# the mass centre in body components (rod axis = body z).
UPS_UPU_PARAMS: dict = {
    "R_A": 0.40,  # base hinge circle radius
    "R_B": 0.20,  # platform hinge circle radius
    "theta_deg": (45.0, 135.0, 225.0, 315.0),  # base hinge angles, legs 1-4
    "phi_deg": (75.0, 165.0, 195.0, 285.0),  # platform hinge angles (non-singular layout)
    "home_centre": (0.0, 0.0, 0.70),  # platform centre at home, A_p = I
    "swing_com": 0.20,  # swing-rod mass centre from U (rod length 0.40)
    "tele_com": 0.20,  # telescopic-rod mass centre from S/U' (rod length 0.40)
    "swing_mass": 2.0,
    "swing_inertia": (0.028, 0.028, 0.001),
    "tele_mass": 1.5,
    "tele_inertia": (0.021, 0.021, 0.0005),
    "platform_mass": 10.0,
    # thin disc r = 0.25 m: m r^2/4, m r^2/2. mechanisms.md rounds 0.15625 to 0.156, which
    # violates I1 + I2 >= I3 (0.312 < 0.3125) and is rejected by Body; use the exact values.
    "platform_inertia": (0.15625, 0.15625, 0.3125),
    "gravity": (0.0, 0.0, -9.81),
}


def _geometry(par: dict) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Base points A_k (world), platform points B_k (platform body frame), centre C (world)."""
    ra, rb = par["R_A"], par["R_B"]
    A = [ra * np.array([math.cos(a), math.sin(a), 0.0]) for a in np.radians(par["theta_deg"])]
    B = [rb * np.array([math.cos(a), math.sin(a), 0.0]) for a in np.radians(par["phi_deg"])]
    A.append(np.zeros(3))  # A_5 = O
    B.append(np.zeros(3))  # B_5 = platform centre
    return A, B, np.array(par["home_centre"], dtype=float)


def home_leg_lengths() -> tuple[float, ...]:
    """Leg lengths |A_k B_k| [m] at the home pose, legs 1..5 (leg 5: 0.70 m)."""
    A, B, C = _geometry(UPS_UPU_PARAMS)
    return tuple(float(np.linalg.norm(C + b - a)) for a, b in zip(A, B, strict=True))


def _rod_frame(u: np.ndarray, x_hint: np.ndarray) -> np.ndarray:
    """Rotation body -> world of a rod: body z along u, body x along x_hint made normal to u."""
    x = x_hint - (x_hint @ u) * u
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(u, x), u])


def _default_drives(lengths: Sequence[float]) -> list[TimeFunction]:
    """Smooth leg-length drives: l_k(t) = l_k(0) + a_k (sin(pi t + ph_k) - sin ph_k).

    Starts at the home length (the home pose is assembled at t = 0), amplitudes 3-5 mm,
    different phases per leg, period 2 s: a genuine closed-loop spatial motion.
    """
    amp = (0.004, 0.003, 0.005, 0.0035, 0.004)  # [m]
    phase = (0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi, 0.25 * math.pi)  # [rad]
    return [
        Sinusoid(a, math.pi, ph, length - a * math.sin(ph))
        for a, ph, length in zip(amp, phase, lengths, strict=True)
    ]


def ups_upu_ideal(*, drives: Sequence[TimeFunction | float] | None = None) -> Mechanism:
    """Build the ideal 4UPS-UPU mechanism with leg-length drivers (mechanisms.md 1.2-1.4).

    drives: five time functions (or constant numbers) giving the leg lengths l_k(t) [m] of
    legs 1..5; default: small sinusoids around the home lengths (see `_default_drives`).
    Returns an uncompiled `Mechanism` with 11 moving bodies ("platform", "swing_k",
    "tele_k"), joints "U_k", "P_k", "S_k" (k = 1..4), "U_5", "P_5", "U5p", and drivers
    "drive_k". Constraint rows: 66, DOF 0.
    """
    par = UPS_UPU_PARAMS
    A, B, C = _geometry(par)
    lengths = home_leg_lengths()
    if drives is None:
        fns = _default_drives(lengths)
    else:
        drives = list(drives)
        if len(drives) != 5:
            raise ModelError("ups_upu_ideal", "drives", drives, "expected 5 leg-length functions")
        fns = [
            as_function(f, owner="ups_upu_ideal", field=f"drives[{k}]")
            for k, f in enumerate(drives)
        ]

    mech = Mechanism("4UPS-UPU ideal", gravity=par["gravity"])
    mech.add(
        Body(
            "platform",
            par["platform_mass"],
            par["platform_inertia"],
            position=tuple(C),
        )
    )
    eye = np.eye(3)
    for k in range(5):
        n = k + 1
        a_w, b_w = A[k], C + B[k]  # world points of the leg at home
        u = (b_w - a_w) / np.linalg.norm(b_w - a_w)  # leg axis, A_k -> B_k
        if k < 4:
            th = math.radians(par["theta_deg"][k])
            t_ax = np.array([-math.sin(th), math.cos(th), 0.0])  # tangential U axis
            R = _rod_frame(u, t_ax)  # body x = t_k projected, body z = u
            u_ground, u_swing = t_ax, np.cross(u, t_ax) / np.linalg.norm(np.cross(u, t_ax))
        else:
            R = eye.copy()  # leg 5 is vertical at home: rod frames = world
            u_ground, u_swing = eye[0], eye[1]
        swing, tele = f"swing_{n}", f"tele_{n}"
        ls, lt = par["swing_com"], par["tele_com"]
        mech.add(
            Body(
                swing,
                par["swing_mass"],
                par["swing_inertia"],
                position=tuple(a_w + ls * u),
                orientation=R,
            ),
            Body(
                tele,
                par["tele_mass"],
                par["tele_inertia"],
                position=tuple(b_w - lt * u),
                orientation=R,
            ),
            # U at A_k: h on the ground = ground axis, h on the swing rod = cross axis
            Marker.on_axis(f"A{n}_ground", GROUND, tuple(a_w), axis=u_ground),
            Marker.on_axis(f"A{n}_swing_u", swing, (0.0, 0.0, -ls), axis=R.T @ u_swing),
            Universal(f"U_{n}", f"A{n}_ground", f"A{n}_swing_u"),
            # P along the rod axis (body z); identical triads (x, y, z) on both rods, so the
            # rotation lock f_i . g_j = 0 holds at home (physics.md c.3)
            Marker(f"A{n}_swing_p", swing, (0.0, 0.0, -ls)),
            Marker(f"B{n}_tele_p", tele, (0.0, 0.0, lt)),
            Prismatic(f"P_{n}", f"A{n}_swing_p", f"B{n}_tele_p"),
        )
        if k < 4:
            mech.add(
                Marker(f"B{n}_platform", "platform", tuple(B[k])),
                Marker(f"B{n}_tele_s", tele, (0.0, 0.0, lt)),
                Spherical(f"S_{n}", f"B{n}_platform", f"B{n}_tele_s"),
            )
        else:
            # U'_5 at the platform centre: rod axis y (body i = tele_5), platform axis x
            mech.add(
                Marker.on_axis("B5_tele_u", tele, (0.0, 0.0, lt), axis=(0.0, 1.0, 0.0)),
                Marker.on_axis("B5_platform", "platform", tuple(B[k]), axis=(1.0, 0.0, 0.0)),
                Universal("U5p", "B5_tele_u", "B5_platform"),
            )
    for k in range(5):
        mech.add(PrismaticDriver(f"drive_{k + 1}", f"P_{k + 1}", fns[k]))
    return mech.validate()
