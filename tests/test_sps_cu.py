"""The 4-SPS/CU factory (mechanisms.md 2.2-2.3; physics.md i): lumped and two-body limbs.

What is proved here, and against which oracle:

* structure (mechanisms.md 2.2 table): lumped ideal 36 velocity unknowns, 32 rows; two-body
  60 unknowns, 52 joint + 4 driver rows; both full rank with DOF 4 (the idle limb spins).
* trajectory: driven by the limb lengths from the general IK (clearance.analysis.ik, mode
  "full", sequence "zxy", platform centre) of the mechanisms.md 2.3 trajectory, both models
  follow z(t), R = Rz(psi) Rx(t1) Ry(t2) to 1e-9 m / 1e-9 rad, between IK knots too.
* LUMPED vs TWO-BODY with the same l_k(t) (the issue's proof of the mass-moment method).
  With ideal joints the platform pose is fixed by the four lengths alone (DOF 4 = spins), so
  the agreement of the platform motion checks only the sliding attachments
  sb_A(t) = -c(l), sb_B(t) = l - c(l). What checks the DYNAMICS (m, c(l), J_t(l), the
  J'_dot omega' term) is:
  (a) the lumped limb's mass centre and angular velocity equal the two-body limb's combined
      mass centre (m1 r_1 + m2 r_2)/m and the common angular velocity of cylinder and piston;
  (b) the actuator forces: `Result.actuator_force("drive_k")` (a multiplier) of the two-body
      model equals `lumped_actuator_force` (piston axial balance) of the lumped model, to
      ~1e-10 of the force; dropping J'_dot omega' (rate_term=False) changes them by ~1e-2 N,
      six decades above the agreement, so the comparison sees that term;
  (c) with a clearance at SB_1 the motion is no longer kinematic: the ball moves freely in
      the socket and the platform moves with it. The two models then give the same ball
      eccentricity and platform motion to integration accuracy.
  The lumped model is exact here because the relative motion of cylinder and piston is
  axial, the limbs are axisymmetric (J_x = J_y) and the prismatic joint locks the relative
  spin: both spins stay at 0 (no moment about the axis from forces at points on it).
* statics: the two-body actuator forces at rest at home equal F_k = +dV/dl_k, V the
  gravity potential of the mechanism assembled (position analysis only, no multipliers) at
  l + h e_k (virtual work: sum F_k dl_k = dV, an extending actuator raises the platform);
  the lumped recovery gives the same forces.
* a clearance run (SB_1, lumped): succeeds, ball within c + micrometres, energy residual.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import clearance as cl
from clearance.analysis.ik import (
    IKResult,
    apply_drives,
    drives_from_ik,
    inverse_kinematics,
    rest_to_rest,
)
from clearance.mechanisms.params import SpsCuParams
from clearance.mechanisms.sps_cu import (
    SPS_CU_PARAMS,
    lumped_actuator_force,
    lumped_limb_numbers,
    sps_cu,
    sps_cu_home_lengths,
    sps_cu_names,
)

# mechanisms.md 2.3: z = 0.60 + 0.05 g, (psi, t1, t2) = (0.10, 0.05, 0.05) g, g = (1-cos pi t)/2
TRAJ = rest_to_rest(
    (0.0, 0.0, 0.60), (0.0, 0.0, 0.05), (0.10, 0.05, 0.05), 2.0, sequence="zxy", mode="full"
)
KNOTS = np.linspace(0.0, 2.0, 41)  # IK samples, h = 0.05 s
T_OUT = np.union1d(KNOTS, np.linspace(0.0, 2.0, 67))  # knots and points between them
TOL = dict(rtol=1e-10, atol=1e-12)
NAMES2 = sps_cu_names("two-body")
CLR = cl.Clearance(
    ball_radius=0.010,
    radial_clearance=0.3e-3,
    normal=cl.NonlinearStiffness(form=1, restitution=0.9),
    friction=cl.Coulomb(mu=0.1),
)


def _rot_angle(R: np.ndarray) -> float:
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2
    return float(math.atan2(np.linalg.norm(w), (np.trace(R) - 1) / 2))


@pytest.fixture(scope="module")
def ik() -> IKResult:
    return inverse_kinematics(
        sps_cu(limbs="two-body"),
        TRAJ,
        platform_marker=NAMES2.platform_marker,
        actuators=NAMES2.drives,
        times=KNOTS,
    )


@pytest.fixture(scope="module")
def drives(ik: IKResult) -> dict:
    return drives_from_ik(ik)


@pytest.fixture(scope="module")
def runs(drives: dict) -> dict[str, cl.Result]:
    two = cl.simulate(apply_drives(sps_cu(limbs="two-body"), drives), 2.0, t_out=T_OUT, **TOL)
    lumped_mech = sps_cu(limbs="lumped", lengths=drives)
    lumped = cl.simulate(lumped_mech, 2.0, t_out=T_OUT, **TOL)
    # the same lumped model without the J'_dot omega' term (sensitivity of the comparison)
    off = {}
    for k in range(1, 5):
        b = lumped_mech.bodies[f"limb_{k}"]
        var = dataclasses.replace(b.inertia_variation, rate_term=False)
        off[b.name] = dataclasses.replace(b, inertia_variation=var)
    no_rate = cl.simulate(lumped_mech.replace(**off), 2.0, t_out=T_OUT, **TOL)
    for r in (two, lumped, no_rate):
        assert r.success, r.message
    return {"two-body": two, "lumped": lumped, "no-rate": no_rate}


# ------------------------------------------------------------------ parameters, structure
def test_parameters_and_errors() -> None:
    assert dict(SPS_CU_PARAMS) == SpsCuParams().to_dict()
    home = sps_cu_home_lengths()
    # non-singular layout: |A_k B_k| is the same for all limbs, sqrt(0.06144 + 0.36) at home
    r_h = math.sqrt(0.4**2 + 0.2**2 - 2 * 0.4 * 0.2 * math.cos(math.radians(30)))
    assert np.allclose(home, math.hypot(r_h, 0.60), rtol=0, atol=1e-15)
    assert home[0] == pytest.approx(0.649181, abs=1e-6)
    # mechanisms.md 2.3's lumped numbers belong to its l = 0.63246 m (same-angle layout)
    md = lumped_limb_numbers(0.63246)
    assert md["m"] == 3.5 and md["J_a"] == pytest.approx(0.0015)
    assert md["c"] == pytest.approx(0.29963, abs=1e-5) and md["J_t"] == pytest.approx(0.09532, 1e-4)
    assert md["sb_A"] == pytest.approx(-0.29963, abs=1e-5)
    assert md["sb_B"] == pytest.approx(0.33283, abs=1e-5)
    assert sps_cu_home_lengths({"phi_deg": (45, 135, 225, 315)})[0] == pytest.approx(0.63246, 1e-5)
    # overrides reach the mechanism
    m = sps_cu({"R_A": 0.45, "piston_mass": 2.0})
    assert m.markers["A1_ground"].position[0] == pytest.approx(0.45 * math.cos(math.pi / 4))
    assert m.bodies["limb_1"].mass == 4.0
    assert sps_cu({"limb_model": "two-body"}).drivers.keys() == set(NAMES2.drives)
    # errors name the key
    for bad, field in (
        ({"R_A": -0.4}, "R_A"),
        ({"radius": 0.4}, "radius"),
        ({"platform_inertia": (0.156, 0.156, 0.3125)}, "platform_inertia"),  # triangle
        ({"column_top": 0.9}, "column_top"),
        ({"limb_model": "three-body"}, "limb_model"),
    ):
        with pytest.raises(cl.ModelError) as err:
            sps_cu(bad)
        assert err.value.field == field, str(err.value)
    with pytest.raises(cl.ModelError, match="limbs"):
        sps_cu(limbs="rigid")
    with pytest.raises(cl.ModelError, match="missing"):
        sps_cu(lengths={"drive_1": 0.65})
    with pytest.raises(cl.ModelError, match="lengths"):
        sps_cu(lengths=[0.65, 0.65, 0.65])
    with pytest.raises(cl.ModelError, match="limb"):
        lumped_actuator_force(None, 5)


@pytest.mark.parametrize(
    ("limbs", "nv", "nrow", "ndrv"), [("lumped", 36, 32, 0), ("two-body", 60, 56, 4)]
)
def test_structure_rank_and_home(limbs: str, nv: int, nrow: int, ndrv: int) -> None:
    """mechanisms.md 2.2 table; DOF 4 = the idle spins; the initial poses are consistent."""
    names = sps_cu_names(limbs)
    c = cl.compile_mechanism(sps_cu(limbs=limbs))
    assert (c.nv, c.nrow, len(c.mechanism.drivers)) == (nv, nrow, ndrv)
    assert sum(b.nrows for b in c.drivers) == ndrv
    y = cl.initial_state(c)
    assert np.max(np.abs(y[: c.nq] - c.y0[: c.nq])) < 1e-14  # home needs no polishing
    rep = cl.rank_check(c, 0.0, y)
    print(limbs, rep)
    assert rep.full_rank and rep.dof == 4
    # the null space is the four limb spins: angular velocity about each limb axis
    N = np.linalg.svd(cl.evaluate_rows(c, 0.0, y).phi_q)[2][rep.rank :]
    for bodies in names.limb_bodies:
        spin = np.zeros(c.nv)
        for b in bodies:
            spin[6 * c.body_names.index(b) + 5] = 1.0  # omega' z = about the limb axis
        assert np.linalg.norm(N @ spin) == pytest.approx(math.sqrt(len(bodies)), 1e-12)
    if limbs == "lumped":
        num = lumped_limb_numbers(sps_cu_home_lengths()[0])
        mk = c.mechanism.markers
        assert mk["A1_limb"].slide(0.0) == pytest.approx(num["sb_A"], abs=1e-15)
        assert mk["B1_limb"].slide(0.0) == pytest.approx(num["sb_B"], abs=1e-15)
        var = c.mechanism.bodies["limb_1"].inertia_variation
        J_t = 0.049 + var.moments[0] * (var.length(0.0) - var.offset) ** 2
        assert J_t == pytest.approx(num["J_t"], 1e-14) and var.rate_term


# ------------------------------------------------------------------ trajectory
@pytest.mark.parametrize("limbs", ["two-body", "lumped"])
def test_follows_prescribed_trajectory(ik: IKResult, runs: dict, limbs: str) -> None:
    assert ik.idle_dof == 4 and np.max(np.abs(ik.twist)) < 1e-12
    assert ik.max_condition < 1e3  # the non-singular layout
    r = runs[limbs]
    P = r.position("platform")
    pos = max(np.max(np.abs(p - TRAJ.position(t))) for p, t in zip(P, r.t, strict=True))
    rot = max(
        _rot_angle(TRAJ.rotation(t).T @ R) for R, t in zip(r.rotation("platform"), r.t, strict=True)
    )
    print(f"{limbs}: platform position {pos:.2e} m, orientation {rot:.2e} rad")
    assert pos < 1e-9 and rot < 1e-9
    scale = np.max(np.abs(r.energy["kinetic"]) + np.abs(r.energy["potential"]))
    assert np.max(np.abs(r.energy["residual"])) < 1e-9 * scale


# ------------------------------------------------------------------ lumped == two-body
def test_lumped_equals_two_body(runs: dict) -> None:
    two, lum, no_rate = runs["two-body"], runs["lumped"], runs["no-rate"]
    par = SpsCuParams()
    m1, m2 = par.cylinder_mass, par.piston_mass
    d_plat = np.max(np.abs(two.q[:, :14] - lum.q[:, :14]))  # platform and column, r and p
    d_com = d_w = d_spin = 0.0
    for k in range(1, 5):
        com2 = (m1 * two.position(f"cylinder_{k}") + m2 * two.position(f"piston_{k}")) / (m1 + m2)
        d_com = max(d_com, np.max(np.abs(com2 - lum.position(f"limb_{k}"))))
        w_c, w_p = two.angular_velocity(f"cylinder_{k}"), two.angular_velocity(f"piston_{k}")
        d_w = max(d_w, np.max(np.abs(w_c - lum.angular_velocity(f"limb_{k}"))))
        d_w = max(d_w, np.max(np.abs(w_p - w_c)))
        d_spin = max(d_spin, np.max(np.abs(lum.angular_velocity(f"limb_{k}", frame="body")[:, 2])))
    print(f"platform/column q {d_plat:.2e}, limb CoM {d_com:.2e} m, omega {d_w:.2e} rad/s")
    assert d_plat < 1e-10 and d_com < 1e-10 and d_w < 1e-9 and d_spin < 1e-12

    for k in range(1, 5):
        F2 = two.actuator_force(f"drive_{k}")
        FL = lumped_actuator_force(lum, k, params=par)
        F0 = lumped_actuator_force(no_rate, k, params=par)
        err, err0 = np.max(np.abs(F2 - FL)), np.max(np.abs(F2 - F0))
        print(
            f"drive_{k}: |F| <= {np.max(np.abs(F2)):.4g} N, lumped - two-body {err:.2e} N, "
            f"without J'_dot omega' {err0:.2e} N"
        )
        assert err < 1e-9 * np.max(np.abs(F2))
        assert err0 > 1e4 * err  # the comparison resolves the rate term
        # the same with the length function passed explicitly
        fn = lum.compiled.mechanism.bodies[f"limb_{k}"].inertia_variation.length
        assert np.array_equal(lumped_actuator_force(lum, k, fn, par), FL)


# ------------------------------------------------------------------ statics
def _potential(lengths: np.ndarray) -> float:
    """Gravity potential sum m g z of the two-body mechanism assembled at these lengths."""
    m = sps_cu(limbs="two-body", lengths=list(lengths))
    c = cl.compile_mechanism(m)
    y = cl.assemble(c, c.y0, tol=1e-14)
    g = np.array(m.gravity)
    return -sum(c.model.body_mass[k] * g @ y[7 * k : 7 * k + 3] for k in range(c.nb))


def test_static_forces_by_virtual_work() -> None:
    home = np.array(sps_cu_home_lengths())
    h = 1e-4
    F_vw = np.zeros(4)
    for k in range(4):
        e = np.zeros(4)
        e[k] = h
        d1 = _potential(home + e) - _potential(home - e)
        d2 = _potential(home + 2 * e) - _potential(home - 2 * e)
        F_vw[k] = (8 * d1 - d2) / (12 * h)  # dV/dl_k, fourth order
    r2 = cl.simulate(sps_cu(limbs="two-body"), 0.01, t_out=[0.0, 0.01], **TOL)
    rl = cl.simulate(sps_cu(limbs="lumped"), 0.01, t_out=[0.0, 0.01], **TOL)
    F2 = np.array([r2.actuator_force(d)[0] for d in NAMES2.drives])
    FL = np.array([lumped_actuator_force(rl, k)[0] for k in range(1, 5)])
    rel2 = np.max(np.abs(F2 - F_vw)) / np.max(np.abs(F_vw))
    relL = np.max(np.abs(FL - F2)) / np.max(np.abs(F2))
    print(
        f"static actuator forces {F_vw} N (virtual work); two-body - virtual work {rel2:.1e}, "
        f"lumped - two-body {relL:.1e} (relative)"
    )
    assert np.all(F_vw > 0)  # the actuators hold the weight: they push
    assert np.max(np.abs(F2 - F_vw)) < 1e-6 * np.max(np.abs(F_vw))
    assert np.max(np.abs(FL - F2)) < 1e-10 * np.max(np.abs(F2))
    # total weight 10 + 2 + 4 x 3.5 = 26 kg: the legs and the column share it
    assert 0.2 * 26 * 9.81 < np.sum(F_vw) < 26 * 9.81 * 2


# ------------------------------------------------------------------ clearance
def test_clearance_at_sb1(drives: dict) -> None:
    """SB_1 with a clearance (mechanisms.md 2.3; socket on the platform, ball on the limb at
    the SLIDING point sb_B(t)), the first 0.2 s of the trajectory: the lumped run succeeds,
    the ball stays within c + micrometres, the energy audit closes (W_m, W_L included); the
    two-body model with the same clearance gives the same motion (exactness of the lumped
    limb with a dynamic, non-kinematic platform motion)."""
    t_out = np.linspace(0.0, 0.2, 201)
    lum = sps_cu(limbs="lumped", lengths=drives).with_clearance("SB_1", CLR)
    two = apply_drives(sps_cu(limbs="two-body"), drives).with_clearance("SB_1", CLR)
    rl = cl.simulate(lum, 0.2, t_out=t_out, **TOL)
    r2 = cl.simulate(two, 0.2, t_out=t_out, **TOL)
    print(rl.summary())
    assert rl.success and r2.success, (rl.message, r2.message)
    e = np.linalg.norm(rl.eccentricity("SB_1"), axis=1)
    assert np.max(e) < CLR.c + 10e-6  # micrometres of penetration at most
    assert len(rl.impacts("SB_1")) >= 3 and np.max(rl.contact_force("SB_1")) > 100.0
    en = rl.energy
    scale = np.max(np.abs(en["kinetic"]) + np.abs(en["potential"]))
    lost = en["damping"][-1] + en["friction"][-1]
    res = np.max(np.abs(en["residual"]))
    print(f"energy residual {res:.2e} J, scale {scale:.3g} J, dissipated {lost:.3g} J")
    assert lost > 1e-3 and res < 1e-6 * lost and res < 1e-9 * scale

    d_plat = np.max(np.abs(rl.position("platform") - r2.position("platform")))
    d_ecc = np.max(np.abs(rl.eccentricity("SB_1") - r2.eccentricity("SB_1")))
    F2, FL = r2.actuator_force("drive_1"), lumped_actuator_force(rl, 1)
    late = rl.t >= 0.15
    d_F = np.max(np.abs(F2 - FL)[late]) / np.max(np.abs(F2))
    print(
        f"clearance lumped vs two-body: platform {d_plat:.2e} m, eccentricity {d_ecc:.2e} m, "
        f"F_1 (t >= 0.15 s) {d_F:.2e} relative, all t {np.max(np.abs(F2 - FL)):.3g} N"
    )
    assert d_plat < 1e-7 and d_ecc < 1e-6 and d_F < 1e-5
    # in contact the limb carries about its ideal load again
    F_ideal = cl.simulate(sps_cu(limbs="lumped", lengths=drives), 0.2, t_out=t_out, **TOL)
    F_id = lumped_actuator_force(F_ideal, 1)
    assert np.max(np.abs(FL - F_id)[late]) < 0.05 * np.max(np.abs(F_id))
