"""The field's classic benchmark: a planar slider-crank with a revolute clearance joint
between connecting rod and slider (Flores & Ambrosio 2004: crank 0.05 m, rod 0.12 m,
masses 0.30 / 0.21 / 0.14 kg, inertias 1e-4 / 2.5e-4 / 1e-4 kg m^2, 5000 rpm, bearing 10 mm,
journal 9.5 mm (c = 0.5 mm), Lankarani-Nikravesh, c_r = 0.9, steel; RECALLED values, see
shared/reference/mechanisms.md 3.3 and docs/clearance-joints.md), built from the package's
3-D joints and compared with an independent planar implementation in minimal coordinates
(tests/oracles/planar_slider_crank.py: NumPy + solve_ivp, located onsets, written without
the package's code): slider acceleration, driving moment, journal trajectory and contact
force over the first crank revolution.

The clearance joint is the revolute joint's planar model; in the 3-D model of a planar
mechanism its axial row repeats what the crank pin and the slide already impose, so the
joint is built as a cylindrical joint with the same planar clearance (the same contact, the
two alignment rows, no redundant row); `test_revolute_and_cylindrical_agree` checks that a
revolute joint (redundant row, least-squares multipliers) gives the same motion.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles.planar_slider_crank import SliderCrankParams, ideal_slider, initial_state
from oracles.planar_slider_crank import simulate as oracle_simulate

import clearance as cl

P = SliderCrankParams()  # K = 6.61e10 N/m^1.5: the internal Hertz K of the radii (steel)
T_REV = 2.0 * math.pi / P.omega  # one crank revolution [s]


def rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def slider_crank(p: SliderCrankParams, joint=cl.Cylindrical, clearance=True) -> cl.Mechanism:
    """The oracle's mechanism in 3-D: crank on a ground spherical joint with its angle
    prescribed (full orientation driver), rod pinned to the crank (spherical), slider on a
    ground prismatic joint along x, and the rod-slider joint (bearing on the slider)."""
    phi, x, phid, xd = initial_state(p)
    th, w = p.theta0, p.omega
    B = p.r * np.array([math.cos(th), math.sin(th), 0.0])
    C = B + p.l * np.array([math.cos(phi), math.sin(phi), 0.0])
    vB = p.r * w * np.array([-math.sin(th), math.cos(th), 0.0])
    vC = vB + p.l * phid * np.array([-math.sin(phi), math.cos(phi), 0.0])
    m = cl.Mechanism("slider-crank", gravity=(0.0, -p.g, 0.0))
    m.add(
        cl.Body("crank", p.m1, (1e-5, p.J1, p.J1), B / 2, rz(th), vB / 2, (0, 0, w)),
        cl.Body("rod", p.m2, (1e-5, p.J2, p.J2), (B + C) / 2, rz(phi), (vB + vC) / 2, (0, 0, phid)),
        cl.Body("slider", p.m3, (p.J3, p.J3, p.J3), (x, 0, 0), velocity=(xd, 0, 0)),
        cl.Marker("O", "ground"),
        cl.Marker("crank_O", "crank", (-p.r / 2, 0, 0)),
        cl.Marker("crank_B", "crank", (p.r / 2, 0, 0)),
        cl.Marker("rod_B", "rod", (-p.l / 2, 0, 0)),
        cl.Marker("rod_C", "rod", (p.l / 2, 0, 0), rz(-phi)),  # triad aligned with the world
        cl.Marker("bearing", "slider"),
        cl.Marker.on_axis("guide", "ground", axis=(1, 0, 0), f_hint=(0, 1, 0)),
        cl.Marker.on_axis("slider_axis", "slider", axis=(1, 0, 0), f_hint=(0, 1, 0)),
        cl.Spherical("crank_bearing", "O", "crank_O"),
        cl.OrientationDriver("drive", "crank_O", (0.0, 0.0, cl.Polynomial((th, w))), "xyz"),
        cl.Spherical("pin", "crank_B", "rod_B"),
        cl.Prismatic("slide", "guide", "slider_axis"),
    )
    clr = None
    if clearance:
        clr = cl.RevoluteClearance(
            journal_radius=p.R_J,
            bearing_radius=p.R_B,
            model="planar",
            bearing="i",
            normal=cl.LankaraniNikravesh(stiffness=p.K, restitution=p.c_r),
            friction=cl.Coulomb(mu=p.mu, v0=p.v0, v1=p.v1) if p.mu else cl.NoFriction(),
            velocity_floor=p.v_floor,
            # onsets located to 1e-8 c like the oracle's (the default 1e-3 c latches the
            # impact velocity up to 0.5 um into the contact; over this revolution that moves
            # the journal by 5e-5 m at rtol 1e-10: the accuracy issue of onset location)
            onset_tolerance=1e-8,
        )
    m.add(joint("wrist", "bearing", "rod_C", clearance=clr))
    return m.validate()


@pytest.fixture(scope="module")
def runs():
    t_eval = np.linspace(0.0, T_REV, 2001)
    ref = oracle_simulate(P, T_REV, t_eval, rtol=1e-12, atol=1e-15)
    r = cl.simulate(slider_crank(P), T_REV, t_out=t_eval, rtol=1e-12, atol=1e-15)
    assert r.success, r.message
    return ref, r


def test_ideal_joint_matches_the_closed_form():
    """Sanity of the 3-D model: with an ideal joint the slider follows the closed form."""
    t = np.linspace(0.0, T_REV, 401)
    m = slider_crank(P, joint=cl.Revolute, clearance=False)
    r = cl.simulate(m, T_REV, t_out=t, rtol=1e-10, atol=1e-13)
    assert r.success, r.message
    x, _, xdd = ideal_slider(P, t)
    assert np.max(np.abs(r.position("slider")[:, 0] - x)) < 1e-9
    assert np.max(np.abs(r.acceleration("slider")[:, 0] - xdd)) < 1e-5 * np.max(np.abs(xdd))


def test_journal_trajectory_and_impacts(runs):
    """Journal centre in the bearing (e = C - S) and the contact events."""
    ref, r = runs
    e = r.eccentricity("wrist")
    assert np.max(np.abs(e[:, 2])) < 1e-12  # stays in the plane
    err = np.max(np.linalg.norm(e[:, :2] - ref["e"], axis=1))
    assert err < 1e-3 * P.c, f"journal trajectory off by {err:.3g} m"
    onsets_ref = [t for t, kind, _ in ref["events"] if kind > 0]
    onsets = r.impacts("wrist")[:, 0]
    assert len(onsets) == len(onsets_ref) >= 5
    assert np.max(np.abs(onsets - onsets_ref)) < 1e-8  # [s]; one revolution is 12 ms


def test_slider_acceleration_driving_moment_and_contact_force(runs):
    """The quantities the papers plot, sample by sample against the oracle: slider
    acceleration (impact spikes of order 1e4-1e5 m/s^2), driving moment and contact force,
    to 1e-4 of each signal's peak."""
    ref, r = runs
    xdd = r.acceleration("slider")[:, 0]
    M = r.reaction("drive")[1][:, 2]  # the moment the drive exerts on the crank, about z
    FN = r.contact_force("wrist")
    for name, got, want in (
        ("x_ddot", xdd, ref["x_ddot"]),
        ("M", M, ref["M"]),
        ("F_N", FN, ref["F_N"]),
    ):
        peak = np.max(np.abs(want))
        err = np.max(np.abs(got - want))
        assert err < 1e-4 * peak, f"{name}: max error {err:.3g} against a peak of {peak:.3g}"
    assert np.max(np.abs(xdd)) > 1e4  # the clearance spikes of the literature


def test_revolute_and_cylindrical_agree():
    """The joint as a Revolute (its axial row repeats the pin's and the slide's: least-squares
    multipliers) gives the same motion over the first impacts."""
    t = np.linspace(0.0, 0.25 * T_REV, 101)
    a = cl.simulate(slider_crank(P, joint=cl.Revolute), t[-1], t_out=t, rtol=1e-10, atol=1e-13)
    b = cl.simulate(slider_crank(P), t[-1], t_out=t, rtol=1e-10, atol=1e-13)
    assert a.success and b.success
    assert a.settings["solver_used"] == "lstsq"
    assert np.max(np.abs(a.eccentricity("wrist") - b.eccentricity("wrist"))) < 1e-3 * P.c
