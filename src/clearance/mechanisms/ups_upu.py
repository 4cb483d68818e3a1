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

Parameters (`UpsUpuParams`, every field overridable and validated): the PROPOSED
reconstruction of mechanisms.md 1.4 with the NON-singular layout (base angles 45, 135, 225,
315 deg; platform angles 75, 165, 195, 285 deg). Body frames:
every rod has its axis as body z (pointing from A_k to B_k), the platform is aligned with
the world at home. Initial poses are the exact home pose; `clearance.assemble` polishes them
at t = 0 if the drives do not start at the home lengths.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import ClassVar

import numpy as np

from clearance.mechanisms.params import (
    BASE_ANGLES_DEG,
    DISC_INERTIA,
    PLATFORM_ANGLES_DEG,
    ParamSet,
    param,
)
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
from clearance.parallel.legs import rod_frame

__all__ = ["UPS_UPU_PARAMS", "UpsUpuParams", "home_leg_lengths", "ups_upu_ideal"]


@dataclass(frozen=True)
class UpsUpuParams(ParamSet):
    """4UPS-UPU parameter set (mechanisms.md 1.4, PROPOSED reconstruction; validated).

    Base points A_k = R_A (cos theta_k, sin theta_k, 0) (world), platform points
    B_k = R_B (cos phi_k, sin phi_k, 0) (platform frame, origin = platform mass centre),
    k = 1..4; leg 5 from A_5 = O to the platform centre, vertical at home. Inertias are
    about the mass centre in body components (rod axis = body z). The rod lengths only
    bound the mass-centre positions (they do not enter the dynamics otherwise).
    """

    OWNER: ClassVar[str] = "4ups-upu parameters"

    R_A: float = param(0.40, "positive", "m", "base hinge circle radius")
    R_B: float = param(0.20, "positive", "m", "platform hinge circle radius")
    theta_deg: tuple = param(BASE_ANGLES_DEG, "angles4", "deg", "base hinge angles, legs 1-4")
    phi_deg: tuple = param(
        PLATFORM_ANGLES_DEG, "angles4", "deg", "platform hinge angles, legs 1-4 (non-singular)"
    )
    home_height: float = param(0.70, "positive", "m", "platform centre height at home, A_p = I")
    swing_length: float = param(0.40, "positive", "m", "swing rod length L_s")
    swing_com: float = param(0.20, "positive", "m", "swing rod mass centre from U, l_s")
    tele_length: float = param(0.40, "positive", "m", "telescopic rod length L_t")
    tele_com: float = param(0.20, "positive", "m", "telescopic rod mass centre from S/U', l_t")
    swing_mass: float = param(2.0, "positive", "kg", "swing rod mass m_s")
    swing_inertia: tuple = param(
        (0.028, 0.028, 0.001), "inertia3", "kg m^2", "swing rod inertia J_s (axis = body z)"
    )
    tele_mass: float = param(1.5, "positive", "kg", "telescopic rod mass m_t")
    tele_inertia: tuple = param(
        (0.021, 0.021, 0.0005), "inertia3", "kg m^2", "telescopic rod inertia J_t (axis = body z)"
    )
    platform_mass: float = param(10.0, "positive", "kg", "platform mass m_p (disc r = 0.25 m)")
    platform_inertia: tuple = param(
        DISC_INERTIA, "inertia3", "kg m^2", "platform inertia J_p about its centre (disc)"
    )
    gravity: tuple = param((0.0, 0.0, -9.81), "vector3", "m/s^2", "gravity, world frame")

    def _check_cross(self) -> None:
        for com, length in (("swing_com", "swing_length"), ("tele_com", "tele_length")):
            if not getattr(self, com) < getattr(self, length):
                raise ModelError(
                    self.OWNER,
                    com,
                    getattr(self, com),
                    f"the mass centre must lie on the rod: < {length} = {getattr(self, length)} m",
                )


# The default parameter set as a read-only mapping (mechanisms.md 1.4).
UPS_UPU_PARAMS: Mapping[str, object] = MappingProxyType(UpsUpuParams().to_dict())


def _params(params: UpsUpuParams | Mapping[str, object] | None) -> UpsUpuParams:
    if params is None:
        return UpsUpuParams()
    if isinstance(params, UpsUpuParams):
        return params
    if isinstance(params, Mapping):
        return UpsUpuParams.from_mapping(params)
    raise ModelError("ups_upu_ideal", "params", params, "expected UpsUpuParams or a mapping")


def _geometry(par: UpsUpuParams) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Base points A_k (world), platform points B_k (platform body frame), centre C (world)."""
    ra, rb = par.R_A, par.R_B
    A = [ra * np.array([math.cos(a), math.sin(a), 0.0]) for a in np.radians(par.theta_deg)]
    B = [rb * np.array([math.cos(a), math.sin(a), 0.0]) for a in np.radians(par.phi_deg)]
    A.append(np.zeros(3))  # A_5 = O
    B.append(np.zeros(3))  # B_5 = platform centre
    return A, B, np.array([0.0, 0.0, par.home_height])


def home_leg_lengths(
    params: UpsUpuParams | Mapping[str, object] | None = None,
) -> tuple[float, ...]:
    """Leg lengths |A_k B_k| [m] at the home pose, legs 1..5 (leg 5: the home height)."""
    A, B, C = _geometry(_params(params))
    return tuple(float(np.linalg.norm(C + b - a)) for a, b in zip(A, B, strict=True))


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


def ups_upu_ideal(
    params: UpsUpuParams | Mapping[str, object] | None = None,
    *,
    drives: Sequence[TimeFunction | float] | None = None,
    name: str = "4UPS-UPU ideal",
) -> Mechanism:
    """Build the ideal 4UPS-UPU mechanism with leg-length drivers (mechanisms.md 1.2-1.4).

    params: an `UpsUpuParams`, or a mapping of field overrides merged over the defaults
    (e.g. {"R_A": 0.45, "platform_mass": 12.0}); None = mechanisms.md 1.4.
    drives: five time functions (or constant numbers) giving the leg lengths l_k(t) [m] of
    legs 1..5; default: small sinusoids around the home lengths (see `_default_drives`).
    Returns an uncompiled `Mechanism` with 11 moving bodies ("platform", "swing_k",
    "tele_k"), joints "U_k", "P_k", "S_k" (k = 1..4), "U_5", "P_5", "U5p", and drivers
    "drive_k". Constraint rows: 66, DOF 0. The spherical joints S_k have the platform
    marker as marker i (socket side of a later `Clearance`) and the rod marker as j.
    """
    par = _params(params)
    A, B, C = _geometry(par)
    lengths = home_leg_lengths(par)
    if drives is None:
        fns = _default_drives(lengths)
    else:
        if isinstance(drives, (str, bytes)) or not isinstance(drives, Sequence):
            raise ModelError("ups_upu_ideal", "drives", drives, "expected 5 leg-length functions")
        drives = list(drives)
        if len(drives) != 5:
            raise ModelError("ups_upu_ideal", "drives", drives, "expected 5 leg-length functions")
        fns = [
            as_function(f, owner="ups_upu_ideal", field=f"drives[{k}]")
            for k, f in enumerate(drives)
        ]

    mech = Mechanism(name, gravity=par.gravity)
    mech.add(
        Body(
            "platform",
            par.platform_mass,
            par.platform_inertia,
            position=tuple(C),
        )
    )
    eye = np.eye(3)
    for k in range(5):
        n = k + 1
        a_w, b_w = A[k], C + B[k]  # world points of the leg at home
        u = (b_w - a_w) / np.linalg.norm(b_w - a_w)  # leg axis, A_k -> B_k
        if k < 4:
            th = math.radians(par.theta_deg[k])
            t_ax = np.array([-math.sin(th), math.cos(th), 0.0])  # tangential U axis
            R = rod_frame(u, t_ax)  # body x = t_k projected, body z = u
            u_ground, u_swing = t_ax, np.cross(u, t_ax) / np.linalg.norm(np.cross(u, t_ax))
        else:
            R = eye.copy()  # leg 5 is vertical at home: rod frames = world
            u_ground, u_swing = eye[0], eye[1]
        swing, tele = f"swing_{n}", f"tele_{n}"
        ls, lt = par.swing_com, par.tele_com
        mech.add(
            Body(
                swing,
                par.swing_mass,
                par.swing_inertia,
                position=tuple(a_w + ls * u),
                orientation=R,
            ),
            Body(
                tele,
                par.tele_mass,
                par.tele_inertia,
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
