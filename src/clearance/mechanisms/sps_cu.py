"""The 4-SPS/CU spatial parallel mechanism (mechanisms.md 2.2-2.3; Paper A), limb-length driven.

Topology (ground z up, origin at the base centre; platform centre = U centre)::

                    platform (body "platform", centre (0, 0, 0.60) m at home)
        B1 (SB_1)    B2 (SB_2)       U (column x, platform y)    B3 (SB_3)    B4 (SB_4)
            |            |                   |                       |            |
         limb 1       limb 2              column                  limb 3       limb 4
        (S - P - S: cylinder from A_k, piston to B_k; lumped into one body or two bodies)
            |            |                   |                       |            |
        A1 (SA_1)    A2 (SA_2)         C (axis z through O)      A3 (SA_3)    A4 (SA_4)
      ========================== ground (base) ==========================

* C joint "C": ground marker at the origin with axis z, column marker on the column axis
  (coincident with the origin at home). The column translates along and rotates about z.
* U joint "U": column top (column_top above the column mass centre), U axis = column x
  (marker i), cross axis = platform y (marker j). Platform orientation
  R = Rz(psi) Rx(t1) Ry(t2), centre (0, 0, z): 4 DOF (mechanisms.md 2.2).
* Limb k = 1..4 (S-P-S): base point A_k = R_A (cos theta_k, sin theta_k, 0) (world),
  platform point B_k = R_B (cos phi_k, sin phi_k, 0) (platform frame). "SA_k": ground
  (marker i) - limb (marker j) at A_k; "SB_k": platform (marker i, socket side of a later
  `Clearance`) - limb (marker j, the ball) at B_k. Limb body frames: z along u = (B - A)/|B - A|
  pointing from the base to the platform, x = e_z x u normalised (horizontal).

``limbs="lumped"`` (Paper A, physics.md i): limb k is ONE body "limb_k" of mass m = m1 + m2 at
the lumped mass centre G on the axis, c(l) = (m1 a1 + m2 (l - a2)) / m from A; inertia
J'(l) = J1 + J2 + diag(m1 m2/m, m1 m2/m, 0) (l - a1 - a2)^2 (`InertiaVariation`, with the
J'_dot omega' term). Its S markers SLIDE along body z with the prescribed length l_k(t):
sb_A(t) = (0, 0, -c(l)), sb_B(t) = (0, 0, l - c(l)), both affine in l (`Scaled`). No P joint,
no driver row: the length enters only through the attachments and the inertia. Rows:
C 4 + U 4 + 8 S x 3 = 32 for 36 velocity unknowns: DOF 4 = the idle spins of the four S-S
limbs (J_a = J1_a + J2_a > 0, harmless in dynamics; assembly uses minimum-norm steps).
The actuator force is not a multiplier: `lumped_actuator_force` recovers it.

``limbs="two-body"`` (validation, Paper B style): "cylinder_k" (S at A_k, mass centre a1 from
A_k) and "piston_k" (S at B_k, mass centre a2 from B_k), prismatic joint "P_k" along the limb
axis (rotation about it locked), `PrismaticDriver` "drive_k" whose value is the limb length
|A_k B_k| (phi = h_i . d - l_k(t), d from the cylinder's point A_k to the piston's point B_k);
`Result.actuator_force("drive_k")` is the pushing (extending) force. Rows: 4 + 4 +
4 x (3 + 5 + 3) = 52 joint rows + 4 driver rows for 60 unknowns: DOF 4 (limb spins).

Numbers (`SPS_CU_PARAMS`, validated by `clearance.mechanisms.params.SpsCuParams`; every one
overridable through `params`): all PROPOSED reconstructions of mechanisms.md 2.3 (Paper A's
values are unknown), except:

* hinge angles: the NON-singular layout (platform = base +30/+30/-30/-30 deg): the centrally
  symmetric same-angle layout is singular (mechanisms.md 1.4 note); PROPOSED;
* platform inertia (0.15625, 0.15625, 0.3125) kg m^2: the exact thin disc m r^2/4, m r^2/2
  (m = 10 kg, r = 0.25 m); mechanisms.md's rounded 0.156 violates I1 + I2 >= I3; DERIVED;
* home limb length 0.649181 m for all four limbs (|A_k B_k| is the same for every limb of
  this layout; `sps_cu_home_lengths`) and the lumped limb there: c = 0.30679 m,
  J_t = 0.10222 kg m^2, J_a = 0.0015 kg m^2, sb_A = -0.30679 m, sb_B = 0.34239 m
  (`lumped_limb_numbers`): DERIVED. mechanisms.md 2.3's 0.63246 m (and its c = 0.29963 m,
  J_t = 0.09532 kg m^2, sb_B = 0.33283 m; its maximum lengths along the trajectory) belong to
  the singular same-angle layout (horizontal offset R_A - R_B = 0.2 m, sqrt(0.2^2 + 0.6^2));
  the tests reproduce them from that length with the same formulas.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from clearance.mechanisms.params import SpsCuParams
from clearance.model import (
    GROUND,
    Body,
    Cylindrical,
    Marker,
    Mechanism,
    ModelError,
    Prismatic,
    PrismaticDriver,
    Spherical,
    TimeFunction,
    Universal,
)
from clearance.model.bodies import InertiaVariation
from clearance.model.functions import Scaled, as_function
from clearance.parallel.legs import horizontal_frame
from clearance.parallel.lumped import limb_actuator_force

__all__ = [
    "LIMB_MODELS",
    "SPS_CU_PARAMS",
    "SpsCuNames",
    "SpsCuParams",
    "lumped_actuator_force",
    "lumped_limb_numbers",
    "sps_cu",
    "sps_cu_home_lengths",
    "sps_cu_names",
]

LIMB_MODELS = ("lumped", "two-body")

# Defaults of every parameter (mechanisms.md 2.3), equal to `SpsCuParams()` (checked by the
# tests); the status of each number is given in the comment. SI units.
SPS_CU_PARAMS: Mapping[str, object] = MappingProxyType(
    {
        "R_A": 0.40,  # m, base hinge radius: PROPOSED
        "R_B": 0.20,  # m, platform hinge radius: PROPOSED
        "theta_deg": (45.0, 135.0, 225.0, 315.0),  # deg, base hinge angles: PROPOSED
        # deg, platform hinge angles, non-singular layout (mechanisms.md 1.4 note): PROPOSED
        "phi_deg": (75.0, 165.0, 195.0, 285.0),
        "home_height": 0.60,  # m, platform centre = U centre at home: PROPOSED
        "cylinder_mass": 2.0,  # kg, m1: PROPOSED
        "cylinder_com": 0.20,  # m, a1 (cylinder mass centre from the base S): PROPOSED
        "cylinder_inertia": (0.028, 0.028, 0.001),  # kg m^2, J1 (axis = z): PROPOSED
        "piston_mass": 1.5,  # kg, m2: PROPOSED
        "piston_com": 0.20,  # m, a2 (piston mass centre from the platform S): PROPOSED
        "piston_inertia": (0.021, 0.021, 0.0005),  # kg m^2, J2 (axis = z): PROPOSED
        "column_mass": 2.0,  # kg: PROPOSED
        "column_length": 0.8,  # m, mass centre at mid-length: PROPOSED
        "column_top": 0.4,  # m, U centre above the column mass centre: PROPOSED
        "column_inertia": (0.1067, 0.1067, 0.001),  # kg m^2: PROPOSED
        "platform_mass": 10.0,  # kg, disc r = 0.25 m: PROPOSED
        # kg m^2, exact disc values (mechanisms.md's 0.156 breaks I1 + I2 >= I3): DERIVED
        "platform_inertia": (0.15625, 0.15625, 0.3125),
        "gravity": (0.0, 0.0, -9.81),  # m/s^2, -z: PROPOSED
        "limb_model": "lumped",  # Paper A's mass-moment lumped limbs: SOURCED (team brief)
    }
)


@dataclass(frozen=True)
class SpsCuNames:
    """Element names of the mechanism built by `sps_cu` (for the IK, results, scenarios).

    platform_body: the moving platform; platform_marker: marker at the platform centre with
    the platform axes (the marker whose pose `PlatformTrajectory` prescribes: sequence
    "zxy", mode "full"). drives: names of the limb lengths l_k (keys of `lengths`) and, in
    the two-body model, of the PrismaticDrivers. prismatic_joints: the P_k (two-body only).
    base_joints / platform_joints: SA_k / SB_k. limb_bodies: per limb, ("limb_k",) lumped or
    ("cylinder_k", "piston_k") two-body; the body that carries SB_k's marker j is the last.
    """

    limbs: str
    platform_body: str
    platform_marker: str
    column_body: str
    drives: tuple[str, ...]
    prismatic_joints: tuple[str, ...]
    base_joints: tuple[str, ...]
    platform_joints: tuple[str, ...]
    limb_bodies: tuple[tuple[str, ...], ...]


def _check_limbs(who: str, limbs: object) -> str:
    if limbs not in LIMB_MODELS:
        raise ModelError(who, "limbs", limbs, f"allowed: {', '.join(map(repr, LIMB_MODELS))}")
    return str(limbs)


def sps_cu_names(limbs: str = "lumped") -> SpsCuNames:
    """The element names of `sps_cu(limbs=limbs)` (see `SpsCuNames`)."""
    limbs = _check_limbs("sps_cu_names", limbs)
    ks = range(1, 5)
    lumped = limbs == "lumped"
    return SpsCuNames(
        limbs=limbs,
        platform_body="platform",
        platform_marker="platform_centre",
        column_body="column",
        drives=tuple(f"drive_{k}" for k in ks),
        prismatic_joints=() if lumped else tuple(f"P_{k}" for k in ks),
        base_joints=tuple(f"SA_{k}" for k in ks),
        platform_joints=tuple(f"SB_{k}" for k in ks),
        limb_bodies=tuple(
            (f"limb_{k}",) if lumped else (f"cylinder_{k}", f"piston_{k}") for k in ks
        ),
    )


def _params(params: SpsCuParams | Mapping[str, object] | None, who: str) -> SpsCuParams:
    """The validated parameter set: the defaults with `params` merged over them."""
    if params is None:
        return SpsCuParams()
    if isinstance(params, SpsCuParams):
        return params
    if isinstance(params, Mapping):
        return SpsCuParams.from_mapping(params)  # ModelError naming an unknown/bad key
    raise ModelError(who, "params", params, "expected a mapping of parameter overrides or None")


def _geometry(par: SpsCuParams) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Base points A_k (world), platform points B_k (platform frame), centre C (world)."""
    A = [par.R_A * np.array([math.cos(a), math.sin(a), 0.0]) for a in np.radians(par.theta_deg)]
    B = [par.R_B * np.array([math.cos(a), math.sin(a), 0.0]) for a in np.radians(par.phi_deg)]
    return A, B, np.array([0.0, 0.0, par.home_height])


def sps_cu_home_lengths(
    params: SpsCuParams | Mapping[str, object] | None = None,
) -> tuple[float, float, float, float]:
    """Limb lengths |A_k B_k| [m] at the home pose (platform level at home_height), k = 1..4."""
    A, B, C = _geometry(_params(params, "sps_cu_home_lengths"))
    return tuple(float(np.linalg.norm(C + b - a)) for a, b in zip(A, B, strict=True))  # type: ignore[return-value]


def lumped_limb_numbers(
    length: float, params: SpsCuParams | Mapping[str, object] | None = None
) -> dict[str, float]:
    """Mass-moment lumped limb at length l [m] (physics.md i): m [kg], c = |A G| [m],
    sb_A, sb_B (body z of the S points from G) [m], J_t, J_a [kg m^2]."""
    par = _params(params, "lumped_limb_numbers")
    m1, m2, a1, a2 = par.cylinder_mass, par.piston_mass, par.cylinder_com, par.piston_com
    m = m1 + m2
    c = (m1 * a1 + m2 * (length - a2)) / m
    return {
        "m": m,
        "c": c,
        "sb_A": -c,
        "sb_B": length - c,
        "J_t": par.cylinder_inertia[0]
        + par.piston_inertia[0]
        + m1 * m2 / m * (length - a1 - a2) ** 2,
        "J_a": par.cylinder_inertia[2] + par.piston_inertia[2],
    }


def _lengths(
    lengths: Mapping[str, TimeFunction | float] | Sequence[TimeFunction | float] | None,
    home: Sequence[float],
    drives: tuple[str, ...],
) -> list[TimeFunction]:
    who = "sps_cu"
    if lengths is None:
        return [as_function(float(x)) for x in home]
    if isinstance(lengths, Mapping):
        unknown = [k for k in lengths if k not in drives]
        missing = [k for k in drives if k not in lengths]
        if unknown or missing:
            raise ModelError(
                who,
                "lengths",
                sorted(map(str, lengths)),
                f"expected one limb length per key {list(drives)} "
                f"(unknown {unknown}, missing {missing})",
            )
        seq = [lengths[k] for k in drives]
    elif isinstance(lengths, (str, bytes)) or not isinstance(lengths, Sequence):
        raise ModelError(who, "lengths", lengths, f"expected a mapping with keys {list(drives)}")
    else:
        seq = list(lengths)
        if len(seq) != 4:
            raise ModelError(who, "lengths", lengths, "expected 4 limb length functions [m]")
    fns = [
        as_function(f, owner=who, field=f"lengths[{d!r}]") for f, d in zip(seq, drives, strict=True)
    ]
    for f, d in zip(fns, drives, strict=True):
        if not f(0.0) > 0.0:
            raise ModelError(
                who, f"lengths[{d!r}]", f(0.0), "the limb length at t = 0 must be > 0 m"
            )
    return fns


def sps_cu(
    params: SpsCuParams | Mapping[str, object] | None = None,
    *,
    limbs: str | None = None,
    lengths: Mapping[str, TimeFunction | float] | Sequence[TimeFunction | float] | None = None,
    name: str | None = None,
) -> Mechanism:
    """Build the ideal 4-SPS/CU mechanism (mechanisms.md 2.2-2.3; see the module docstring).

    params: a mapping of parameter overrides merged over `SPS_CU_PARAMS` (validated by
    `SpsCuParams`; a bad or unknown key raises ModelError naming it), or an `SpsCuParams`.
    limbs: "lumped" (one body per limb, sliding S points, no driver rows) or "two-body"
    (cylinder + piston, prismatic joint, PrismaticDriver "drive_k"); None = the parameter
    `limb_model` (default "lumped").
    lengths: the limb lengths l_k(t) [m], a mapping {"drive_1": f1, ..., "drive_4": f4}
    (e.g. `clearance.analysis.ik.drives_from_ik` of the two-body model) or a sequence of
    4; TimeFunctions or numbers. Default: the constant home lengths (the mechanism rests at
    home). Initial poses are the home pose; `clearance.assemble` (run by `simulate`)
    polishes them when l_k(0) differs from the home length.
    Returns the validated, uncompiled `Mechanism` (names: `sps_cu_names(limbs)`).
    """
    who = "sps_cu"
    par = _params(params, who)
    limbs = _check_limbs(who, par.limb_model if limbs is None else limbs)
    names = sps_cu_names(limbs)
    A, B, C = _geometry(par)
    home = sps_cu_home_lengths(par)
    fns = _lengths(lengths, home, names.drives)

    mech = Mechanism(name or f"4-SPS/CU ({limbs} limbs)", gravity=par.gravity)
    zc = par.home_height - par.column_top  # column mass centre height at home
    mech.add(
        Body("platform", par.platform_mass, par.platform_inertia, position=tuple(C)),
        Body("column", par.column_mass, par.column_inertia, position=(0.0, 0.0, zc)),
        Marker("platform_centre", "platform"),
        # C: vertical axis through the origin (h = z on both markers)
        Marker("C_ground", GROUND),
        Marker("C_column", "column", (0.0, 0.0, -zc)),
        Cylindrical("C", "C_ground", "C_column"),
        # U: column top, axes column x (i) and platform y (j): R = Rz(psi) Rx(t1) Ry(t2)
        Marker.on_axis("U_column", "column", (0.0, 0.0, par.column_top), axis=(1.0, 0.0, 0.0)),
        Marker.on_axis("U_platform", "platform", axis=(0.0, 1.0, 0.0)),
        Universal("U", "U_column", "U_platform"),
    )
    m1, m2, a1, a2 = par.cylinder_mass, par.piston_mass, par.cylinder_com, par.piston_com
    m = m1 + m2
    J1, J2 = np.array(par.cylinder_inertia), np.array(par.piston_inertia)
    for k in range(4):
        n = k + 1
        l0 = fns[k](0.0)
        a_w, b_w = A[k], C + B[k]  # world points at home
        u = (b_w - a_w) / np.linalg.norm(b_w - a_w)
        R = horizontal_frame(u)
        mech.add(
            Marker(f"A{n}_ground", GROUND, tuple(a_w)),
            Marker(f"B{n}_platform", "platform", tuple(B[k])),
        )
        if limbs == "lumped":
            limb = f"limb_{n}"
            c0 = (m1 * a1 + m2 * (l0 - a2)) / m
            # c(l) = (m2/m) l + (m1 a1 - m2 a2)/m: sb_A = -c(l), sb_B = l - c(l)
            off = (m1 * a1 - m2 * a2) / m
            var = InertiaVariation((m1 * m2 / m, m1 * m2 / m, 0.0), a1 + a2, fns[k])
            mech.add(
                Body(
                    limb,
                    m,
                    tuple(J1 + J2),
                    position=tuple(a_w + c0 * u),
                    orientation=R,
                    inertia_variation=var,
                ),
                Marker(
                    f"A{n}_limb",
                    limb,
                    slide_axis=(0.0, 0.0, 1.0),
                    slide=Scaled(fns[k], -m2 / m, -off),
                ),
                Marker(
                    f"B{n}_limb",
                    limb,
                    slide_axis=(0.0, 0.0, 1.0),
                    slide=Scaled(fns[k], m1 / m, -off),
                ),
                Spherical(f"SA_{n}", f"A{n}_ground", f"A{n}_limb"),
                Spherical(f"SB_{n}", f"B{n}_platform", f"B{n}_limb"),
            )
        else:
            cyl, pis = f"cylinder_{n}", f"piston_{n}"
            mech.add(
                Body(cyl, m1, par.cylinder_inertia, position=tuple(a_w + a1 * u), orientation=R),
                Body(pis, m2, par.piston_inertia, position=tuple(b_w - a2 * u), orientation=R),
                Marker(f"A{n}_cylinder", cyl, (0.0, 0.0, -a1)),
                Spherical(f"SA_{n}", f"A{n}_ground", f"A{n}_cylinder"),
                # P along body z (identical triads on both bodies: rotation lock holds)
                Marker(f"P{n}_cylinder", cyl, (0.0, 0.0, -a1)),
                Marker(f"P{n}_piston", pis, (0.0, 0.0, a2)),
                Prismatic(f"P_{n}", f"P{n}_cylinder", f"P{n}_piston"),
                Marker(f"B{n}_piston", pis, (0.0, 0.0, a2)),
                Spherical(f"SB_{n}", f"B{n}_platform", f"B{n}_piston"),
                PrismaticDriver(f"drive_{n}", f"P_{n}", fns[k]),
            )
    return mech.validate()


def lumped_actuator_force(
    result: object,
    limb: int,
    length_fn: TimeFunction | float | None = None,
    params: SpsCuParams | Mapping[str, object] | None = None,
    *,
    platform_joint: str | None = None,
) -> np.ndarray:
    """(n,) actuator force [N] of lumped limb `limb` (1..4), positive pushing (extending),
    recovered from the piston's axial balance (physics.md i; `clearance.parallel.lumped.
    limb_actuator_force`, with the body "limb_<limb>", the joint `platform_joint`
    (default "SB_<limb>") and m1, m2, a1, a2 of `params` (None = defaults)).

    result: a `Result` of `sps_cu(limbs="lumped")`. length_fn: the limb length l(t) [m];
    None = read it from the limb body's InertiaVariation.
    """
    who = "lumped_actuator_force"
    if isinstance(limb, bool) or limb not in (1, 2, 3, 4):
        raise ModelError(who, "limb", limb, "expected a limb number 1..4")
    par = _params(params, who)
    body = f"limb_{limb}"
    if body not in result.compiled.body_names:  # type: ignore[attr-defined]
        raise ModelError(
            who,
            "result",
            result.compiled.mechanism.name,
            f"no body {body!r}: not a lumped 4-SPS/CU",  # type: ignore[attr-defined]
        )
    try:
        return limb_actuator_force(
            result,
            body,
            platform_joint or f"SB_{limb}",
            par.cylinder_mass,
            par.piston_mass,
            par.cylinder_com,
            par.piston_com,
            length_fn,
        )
    except ModelError as e:  # (named as before: "params" for the masses)
        field = "params" if e.field == "m1, m2" else e.field
        raise ModelError(who, field, e.value, e.allowed) from None
