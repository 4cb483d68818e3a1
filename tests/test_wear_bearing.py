"""The worn bearing in the dynamics (issue 16, revolute and cylindrical clearance joints): a
journal station whose bearing is worn (`Mechanism.with_wear`, `clearance.model.wear.
BearingWear`) measures its gap to the worn rim R_B + H(phi) (contact/journal.py).

Oracles: central differences of the kernel's own contact energy, gaps and normals (the force
is the energy's gradient for a tilted journal on a sloped worn rim, delta_dot the gap's rate,
the LuGre bristles stay in the tangent plane), and a worn profile in closed form whose
penetration is computed here by brute force from the formula (the journal cylinder against
the worn cross-section, not the package's depth field or Newton iteration)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from test_clearance_kinds import (
    HERTZ,
    LB,
    RJ,
    TS,
    C,
    along_motion,
    assert_force_is_minus_energy_gradient,
    brute_force_station_penetration,
    evaluate,
    gaps,
    place,
    two_bodies,
)

import clearance as cl
from clearance.layout import PO_DDOT, PO_DELTA, PO_FN, PO_N
from clearance.model.errors import ModelError
from clearance.model.wear import BearingWear
from clearance.wear.bearing import MIN_RING_CELLS, BearingWearMap, bearing_history, ring_archard

TH0 = 0.80  # the worn pocket's centre angle (outer marker frame) [rad]


def pocket(theta, depth, width):
    """A smooth worn pocket: depth exp(-(theta - TH0)^2 / (2 width^2)) (periodic)."""
    d = (np.asarray(theta) - TH0 + np.pi) % (2 * np.pi) - np.pi
    return depth * np.exp(-0.5 * (d / width) ** 2)


def worn(stations, n=96, depth=4e-6, width=0.15):
    """BearingWear of the pocket, deeper towards the bearing's +h end (a sloped rim in both
    directions at the contact)."""
    th = 2 * np.pi * (np.arange(n) + 0.5) / n
    d = depth * np.linspace(0.6, 1.0, stations)
    return BearingWear(np.array([pocket(th, dj, width) for dj in d]))


# (joint, clearance, stations, placement: offset in the outer marker frame, relative rotation)
SPATIAL = cl.RevoluteClearance(RJ, radial_clearance=C, model="spatial", length=LB, normal=HERTZ)
WORN_KINDS = {
    "revolute planar": (
        cl.Revolute,
        cl.RevoluteClearance(RJ, radial_clearance=C, normal=HERTZ),
        1,
        ((C + 3.5e-6) * math.cos(TH0 + 0.12), (C + 3.5e-6) * math.sin(TH0 + 0.12), 0.0),
        (0.0, 0.0, 0.3),
    ),
    "revolute spatial": (
        cl.Revolute,
        SPATIAL,
        5,
        (0.99 * C * math.cos(TH0 - 0.1), 0.99 * C * math.sin(TH0 - 0.1), 1e-4),
        (3e-4, -8e-4, 0.7),
    ),
    "cylindrical spatial": (
        cl.Cylindrical,
        SPATIAL,
        5,
        (1.02 * C * math.cos(TH0 + 0.1), 1.02 * C * math.sin(TH0 + 0.1), 0.004),
        (-5e-4, 6e-4, -1.0),
    ),
}


def worn_pair(kind, friction=None):
    joint, clr, st, e, rot = WORN_KINDS[kind]
    if friction is not None:
        clr = dataclasses.replace(clr, friction=friction)
    m = two_bodies(joint, clr).with_wear("J", worn(st))
    return cl.compile_mechanism(m), (e, rot)


@pytest.mark.parametrize("kind", list(WORN_KINDS))
def test_worn_bearing_force_is_minus_the_gradient_of_the_contact_energy(kind):
    """Q = -dV_c/dq over both bodies' 12 velocity directions (central differences), for a
    tilted journal on the sloped flank of a worn pocket; the worn rim changes the force
    (against the unworn bearing at the same placement)."""
    c, placement = worn_pair(kind)
    rng = np.random.default_rng(11)
    y = place(c, rng, *placement)
    Q, po, _ = evaluate(c, y)
    assert 0.0 < np.max(po[:, PO_DELTA]) < 2e-5, po[:, PO_DELTA]
    assert np.max(np.abs(Q)) > 1.0
    assert_force_is_minus_energy_gradient(c, y, Q)
    joint, clr, *_ = WORN_KINDS[kind]
    c0 = cl.compile_mechanism(two_bodies(joint, clr))
    Q0, po0, _ = evaluate(c0, y)
    assert np.max(po0[:, PO_DELTA] - po[:, PO_DELTA]) > 1e-6  # the pocket deepens the gap
    # the worn rim's slope turns the normal (by more than 1e-3 rad, 50x the tolerance above)
    on = (po[:, PO_DELTA] > 0) & (po0[:, PO_DELTA] > 0)
    assert on.any()
    cosines = np.sum(po[on, PO_N : PO_N + 3] * po0[on, PO_N : PO_N + 3], axis=1)
    assert np.min(cosines) < math.cos(1e-3)


@pytest.mark.parametrize("kind", list(WORN_KINDS))
def test_worn_bearing_gap_rate_is_the_derivative_of_the_gap(kind):
    """delta_dot of every station = d delta / dt along the motion (central differences),
    and the pair's power sum Q . v = -sum F_N delta_dot (a conservative law)."""
    c, placement = worn_pair(kind)
    rng = np.random.default_rng(5)
    y = place(c, rng, *placement)
    Q, po, _ = evaluate(c, y)
    h = 1e-8
    fd = (gaps(c, along_motion(y, h)) - gaps(c, along_motion(y, -h))) / (2 * h)
    scale = np.max(np.abs(po[:, PO_DDOT]))
    assert scale > 1e-3
    assert np.allclose(po[:, PO_DDOT], fd, rtol=1e-5, atol=1e-6 * scale)
    power = float(np.sum(Q * y[14:26].reshape(2, 6)))
    pair = -float(np.sum(po[:, PO_FN] * po[:, PO_DDOT]))
    assert power == pytest.approx(pair, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("kind", list(WORN_KINDS))
def test_worn_bearing_lugre_bristles_stay_in_the_tangent_plane(kind):
    """n_dot . z + n . z_dot = 0 at every station in contact, with n_dot from central
    differences of the kernel's normals: the kernel's n_dot is the exact rate of the normal
    on the worn rim (it needs the field's H'')."""
    c, placement = worn_pair(kind, friction=cl.LuGre())
    rng = np.random.default_rng(7)
    y = place(c, rng, *placement)
    iz = slice(c.iz, c.iz + 3 * c.ncp)

    def normals(s):
        return evaluate(c, along_motion(y, s), t=s)[1][:, PO_N : PO_N + 3]

    n = normals(0.0)
    z = 1e-6 * rng.normal(size=(c.ncp, 3))
    z -= np.sum(z * n, axis=1)[:, None] * n
    y[iz] = z.ravel()
    _, po, yd = evaluate(c, y, flag=1)
    zd = yd[iz].reshape(c.ncp, 3)
    inc = po[:, PO_DELTA] > 0.0
    assert inc.any()
    h = 1e-8
    nd = (normals(h) - normals(-h)) / (2 * h)
    turn = np.sum(nd * z, axis=1)[inc]
    assert np.max(np.abs(turn)) > 1e-10 * np.max(np.abs(zd[inc]))
    rate = turn + np.sum(n[inc] * zd[inc], axis=1)
    assert np.max(np.abs(rate)) < 1e-6 * np.max(np.abs(turn))


# ------------------------------------------------------------------ a closed-form worn profile
DEPTH, WIDTH = 20e-6, 0.4  # the pocket: c + h + h'' > 0, so h is its own support depth


def brute_force_worn_penetration(sigma, o, h, RB, RJ, profile):
    """RJ minus the smallest distance from the journal axis (through o along h) of the worn
    cross-section X(phi) = ((RB + profile(phi)) cos phi, (RB + profile(phi)) sin phi, sigma),
    and the direction from the axis to that point (test_clearance_kinds' brute force)."""
    return brute_force_station_penetration(sigma, o, h, RB, RJ, profile, normal=True)


@pytest.mark.parametrize("n", [128, 512])
def test_worn_bearing_matches_the_exact_geometry_of_a_closed_form_profile(n):
    """Offset and tilted journals against a bearing worn by a smooth pocket 20 um deep
    (given at the n cell centres): every station's penetration and normal equal the brute
    force's from the closed form, to the field's smoothing error (second order in the
    cell), and the penetration is the unworn one less up to 20 um."""
    N = 5
    clr = cl.RevoluteClearance(
        RJ, radial_clearance=C, model="spatial", length=LB, stations=N, normal=HERTZ
    )
    th = 2 * np.pi * (np.arange(n) + 0.5) / n
    ring = pocket(th, DEPTH, WIDTH)
    wear = BearingWear(np.tile(ring, (N, 1)))
    c = cl.compile_mechanism(two_bodies(cl.Revolute, clr).with_wear("J", wear))
    sig = LB * (-0.5 + (np.arange(N) + 0.5) / N)
    rng = np.random.default_rng(21)
    worst, deepened, turn = 0.0, 0.0, 0.0
    for ang in (TH0, TH0 + 0.3, TH0 - 0.2, TH0 + 1.5):
        tilt = rng.uniform(-1, 1, size=2) * C / LB
        e = (C + 8e-6) * np.array([math.cos(ang), math.sin(ang)])
        y = place(c, rng, (e[0], e[1], 2e-4), (tilt[0], tilt[1], 0.5), speed=0.0)
        _, po, _ = evaluate(c, y)
        Rrel = Rotation.from_rotvec((tilt[0], tilt[1], 0.5)).as_matrix()
        o, h = np.array([e[0], e[1], 2e-4]), Rrel[:, 2]
        As = Rotation.from_quat(np.r_[y[4:7], y[3]]).as_matrix()
        for j, s in enumerate(sig):
            ref, nref = brute_force_worn_penetration(
                s, o, h, RJ + C, RJ, lambda p: pocket(p, DEPTH, WIDTH)
            )
            unworn, _ = brute_force_worn_penetration(s, o, h, RJ + C, RJ, lambda p: 0.0 * p)
            deepened = max(deepened, unworn - ref)
            worst = max(worst, abs(po[j, PO_DELTA] - ref))
            nk = (As @ TS).T @ po[j, PO_N : PO_N + 3]  # outer marker frame
            turn = max(turn, math.acos(min(1.0, float(nk @ nref))))
    assert deepened > 0.5 * DEPTH
    # the B-spline field's error, second order in the cell: penetration 29 / 1.8 nm and
    # normal 1.1e-3 / 7e-5 rad at 128 / 512 cells (0.11 nm, 5e-6 rad at 2048)
    assert worst < {128: 5e-8, 512: 4e-9}[n], worst
    assert turn < {128: 2e-3, 512: 1.5e-4}[n], turn


def test_with_wear_checks_a_bearing():
    m = two_bodies(cl.Revolute, SPATIAL)
    with pytest.raises(ModelError, match="BearingWear"):
        m.with_wear("J", 1e-6)
    with pytest.raises(ModelError, match="one row per station"):
        m.with_wear("J", BearingWear(np.zeros((3, 16))))
    with pytest.raises(ModelError, match="n >= 4"):
        BearingWear(np.zeros((5, 3)))
    with pytest.raises(ModelError, match=">= 0"):
        BearingWear(-np.ones((5, 16)))
    assert "J" in m.with_wear("J", BearingWear(np.zeros((5, 16)))).wear
    sph = two_bodies(cl.Spherical, cl.SphericalClearance(RJ, radial_clearance=C))
    with pytest.raises(ModelError, match="SocketWear"):
        sph.with_wear("J", BearingWear(np.zeros((1, 16))))


def test_unworn_rings_and_an_unworn_map_take_the_unworn_path():
    """A BearingWear of zeros compiles to no rows and gives the unworn contact bit for bit;
    a worn station next to unworn ones leaves those unchanged."""
    c0 = cl.compile_mechanism(two_bodies(cl.Revolute, SPATIAL))
    cz = cl.compile_mechanism(
        two_bodies(cl.Revolute, SPATIAL).with_wear("J", BearingWear(np.zeros((5, 64))))
    )
    d = np.zeros((5, 64))
    d[4] = pocket(2 * np.pi * (np.arange(64) + 0.5) / 64, 4e-6, 0.3)
    c4 = cl.compile_mechanism(two_bodies(cl.Revolute, SPATIAL).with_wear("J", BearingWear(d)))
    assert cz.model.clr_wear.shape[0] == 0 and c4.model.clr_wear.shape[0] > 0
    rng = np.random.default_rng(4)
    y = place(c0, rng, *WORN_KINDS["revolute spatial"][3:])
    Q0, po0, _ = evaluate(c0, y)
    Qz, poz, _ = evaluate(cz, y)
    _, po4, _ = evaluate(c4, y)
    assert np.array_equal(Q0, Qz) and np.array_equal(po0, poz)
    assert np.array_equal(po4[:4], po0[:4])
    assert po4[4, PO_DELTA] < po0[4, PO_DELTA] - 1e-6


# ------------------------------------------------------------------ the bearing's wear map
def test_support_depth_is_the_reachable_sets_support_function():
    """H_i + c = max x . u_i over S = {x : x . u_j <= c + h_j}, by a linear program per
    cell (scipy's HiGHS, an independent method), for rough random wear and a pocket
    narrower than the journal; H = h on an unworn ring and where h is its own support."""
    from scipy.optimize import linprog

    rng = np.random.default_rng(8)
    n, c = 48, 2e-4
    m = BearingWearMap(RJ + c, LB, 2, n)
    m.depth[0] = 8e-6 * rng.uniform(0, 1, n) ** 3
    m.depth[1] = np.where(np.abs(m.angles - 1.0) < 0.2, 20e-6, 0.0)  # 20 um, 0.4 rad wide
    H = m.support_depth(c)
    U = m.directions
    for j in range(2):
        for i in range(n):
            lp = linprog(-U[i], A_ub=U, b_ub=c + m.depth[j], bounds=[(None, None)] * 2)
            assert H[j, i] == pytest.approx(-lp.fun - c, abs=1e-12)
    assert np.all(H <= m.depth + 1e-15) and np.any(H[1] < m.depth[1] - 1e-6)
    wide = BearingWearMap(RJ + c, LB, 1, 128)
    wide.depth[0] = pocket(wide.angles, DEPTH, WIDTH)
    assert np.allclose(wide.support_depth(c), wide.depth, atol=1e-15)
    assert not np.any(BearingWearMap(RJ + c, LB, 1, 16).support_depth(c))


def _reachable_distance(e, c, profile, m=6000):
    """Distance of the offset e (2,) from S = {x : x . u(phi) <= c + h(phi)} (0 inside),
    S's boundary from its radial function r(theta) = min_phi (c + h(phi)) / cos(theta - phi)
    on dense grids near e's direction (a different construction from the support function
    the package uses)."""
    phi = np.linspace(-np.pi, np.pi, 4001)
    b = c + profile(phi)

    def radial(th):
        cosd = np.cos(np.asarray(th)[:, None] - phi[None, :])
        ok = cosd > 0.05
        return np.min(np.where(ok, b[None, :] / np.where(ok, cosd, 1.0), np.inf), axis=1)

    e = np.asarray(e, dtype=float)
    te = math.atan2(e[1], e[0])
    if np.linalg.norm(e) <= radial([te])[0]:
        return 0.0
    th = te + np.linspace(-0.3, 0.3, m)
    pts = radial(th)[:, None] * np.column_stack([np.cos(th), np.sin(th)])
    return float(np.min(np.linalg.norm(pts - e, axis=1)))


def test_a_journal_rests_on_the_rims_of_a_pocket_narrower_than_itself():
    """A pocket 20 um deep and 0.2 rad wide (the journal, c = 0.2 mm, would need about
    0.9 rad to reach its bottom): with the support depth the planar journal's penetration
    is its distance from the set of offsets it reaches without touching the worn surface,
    zero at the rims, computed independently from the closed-form profile. With the raw
    depth the rim minimisation would take the deeper rim's point alone, and the force would
    jump between the rims as the journal crosses the pocket's axis."""
    c, d0, w = C, 20e-6, 0.1

    def narrow(p):
        x = (np.asarray(p) - TH0 + np.pi) % (2 * np.pi) - np.pi
        return d0 * np.clip(1 - (x / w) ** 2, 0, None) ** 2

    clr = cl.RevoluteClearance(RJ, radial_clearance=c, normal=HERTZ, length=LB)
    m = BearingWearMap(RJ + c, LB, 1, 512)
    m.depth[0] = narrow(m.angles)
    worn_c = cl.compile_mechanism(two_bodies(cl.Revolute, clr).with_wear("J", m.bearing_wear(c)))
    raw_c = cl.compile_mechanism(two_bodies(cl.Revolute, clr).with_wear("J", BearingWear(m.depth)))
    rng = np.random.default_rng(2)
    for dth, extra in ((0.0, 2e-6), (0.0, 0.5e-6), (0.05, 1e-6), (-0.12, 1.5e-6)):
        u = np.array([math.cos(TH0 + dth), math.sin(TH0 + dth)])
        # along u, the first touch of the worn surface (bisection on the oracle's distance)
        lo, hi = 0.0, c + d0
        for _ in range(45):
            mid = 0.5 * (lo + hi)
            if _reachable_distance(mid * u, c, narrow, 1) > 0.0:
                hi = mid
            else:
                lo = mid
        e = (hi + extra) * u
        ref = _reachable_distance(e, c, narrow)
        y = place(worn_c, rng, (e[0], e[1], 0.0), (0.0, 0.0, 0.3), speed=0.0)
        delta = evaluate(worn_c, y)[1][0, PO_DELTA]
        # the B-spline rounds the support function's corner at the pocket's vertex:
        # 0.06-0.08 um at 512 cells (0.005-0.018 um at 2048; measured)
        assert abs(delta - ref) < 0.1e-6, (dth, delta, ref)
    # across the pocket's axis the normal turns continuously; on the raw depth the deepest
    # point jumps from one rim to the other (the force turns by twice the rims' angle)
    for model, smooth in ((worn_c, True), (raw_c, False)):
        ns = []
        for side in (-1e-4, 1e-4):
            u = np.array([math.cos(TH0 + side), math.sin(TH0 + side)])
            y = place(model, rng, (*((c + 6e-6) * u), 0.0), (0.0, 0.0, 0.3), speed=0.0)
            As = Rotation.from_quat(np.r_[y[4:7], y[3]]).as_matrix()
            ns.append((As @ TS).T @ evaluate(model, y)[1][0, PO_N : PO_N + 3])
        turn = math.acos(min(1.0, float(ns[0] @ ns[1])))
        # 0.04 um apart, 5 um beyond the rims' corner: the distance's normal turns by about
        # 0.04 / 5 rad (measured 0.0047); the rims' jump is about 0.2 rad
        assert turn < 0.02 if smooth else turn > 0.1, (smooth, turn)


def test_ring_archard_spreads_k_w_f_s_over_the_overlap():
    """The volume added is k_w F s (to first order in h / R); the pressure is symmetric
    about the journal's offset and covers at least MIN_RING_CELLS cells."""
    m = BearingWearMap(RJ + C, LB, 2, 128)
    th = m.angles[40] + 0.5 * (m.angles[1] - m.angles[0])  # between cells 40 and 41
    e = (C + 1e-7) * np.array([[math.cos(th), math.sin(th)]])
    ring_archard(m, 1, e, [50.0], [0.01], 1e-12, C)
    assert not np.any(m.depth[0])
    assert m.volume() == pytest.approx(1e-12 * 50.0 * 0.01, rel=1e-6)
    worn_cells = np.flatnonzero(m.depth[1])
    assert worn_cells.size >= MIN_RING_CELLS and worn_cells.size % 2 == 0
    assert np.allclose(m.depth[1][40 - 5 : 41 + 6], m.depth[1][40 - 5 : 41 + 6][::-1])
    with pytest.raises(ValueError, match="same grid"):
        ring_archard(m, 0, e, [1.0], [1.0], 1e-12, C, worn=BearingWearMap(RJ + C, LB, 2, 64))


@pytest.fixture(scope="module")
def bearing_run():
    """A pendulum swinging on a spatial revolute clearance joint with Coulomb friction."""
    from test_clearance_kinds import pendulum

    clr = cl.RevoluteClearance(
        RJ,
        radial_clearance=C,
        model="spatial",
        length=LB,
        stations=3,
        normal=HERTZ,
        friction=cl.Coulomb(mu=0.1, v0=1e-7, v1=1e-6),
    )
    return cl.simulate(pendulum(cl.Revolute, clr, spin=6.0), 0.25, dt_out=2e-5)


def test_bearing_wear_volume_balances_the_kernels_friction_work(bearing_run):
    """The integral of F_N |v_slip| dt over the output samples of every station equals the
    friction work the kernel integrates at every step divided by mu (the independent
    account); the worn volume is k_w times it (bookkeeping: ring_archard scales the
    pressure so); the wear sits below the pivot, where the journal hangs."""
    r = bearing_run
    assert r.success
    k_w = 1e-14
    m, work = bearing_history(r, "J", k_w=k_w, n=128)
    d_t = float(r.dissipated("J")[1][-1])
    assert d_t > 0
    assert work == pytest.approx(d_t / 0.1, rel=5e-3)
    assert m.volume() == pytest.approx(k_w * work, rel=1e-6)
    # gravity along -y of the ground (the bearing's frame is the world's): wear around -y
    deepest = m.angles[np.argmax(m.depth.max(axis=0))]
    assert math.cos(deepest - (-np.pi / 2)) > 0.9


# ------------------------------------------------------------------ the wear loop
M, G, OMEGA, T, KW = 2.0, 9.81, 10.0, 0.01, 1e-13  # mass, gravity, spin, cycle, k / H
K = 3e10  # Hertz stiffness [N/m^1.5]


def spinning_journal(worn):
    """A 2 kg journal spinning at OMEGA about the axis of a ground bearing (planar model,
    one station) and resting under gravity at its bottom, worn as `worn`: a constant
    normal load M g and slip speed OMEGA R_J."""
    mech = cl.Mechanism("spinning journal", gravity=(0, -G, 0))
    h = float(worn["J"].depth(0, -np.pi / 2)) if worn else 0.0
    dy = C + h + (M * G / K) ** (2 / 3)
    mech.add(
        cl.Body("b", M, (1e-3, 1e-3, 1e-3), position=(0, -dy, 0), angular_velocity=(0, 0, OMEGA)),
        cl.Marker("s", "ground"),
        cl.Marker("m", "b"),
        cl.Revolute(
            "J",
            "s",
            "m",
            clearance=cl.RevoluteClearance(
                RJ, radial_clearance=C, length=LB, normal=cl.Hertz(stiffness=K)
            ),
        ),
    )
    for j, w in (worn or {}).items():
        mech = mech.with_wear(j, w)
    return cl.compile_mechanism(mech)


def imprint(d0, psi):
    """Depth of a bearing (radius RJ + C) worn to the imprint of the journal (radius RJ)
    pushed d0 beyond contact, at angles psi from the load: the journal circle's distance
    from the bearing centre less the bearing radius (exact circle geometry; about
    (c + d0) cos psi - c for a small clearance)."""
    s = C + d0
    return np.maximum(0.0, s * np.cos(psi) + np.sqrt(RJ**2 - (s * np.sin(psi)) ** 2) - RJ - C)


def imprint_area(d0, R, m=200001):
    """Cross-section of that imprint: R times the integral of its depth over psi."""
    psi = np.linspace(-0.6, 0.6, m)
    return R * float(np.sum(imprint(d0, psi))) * (psi[1] - psi[0])


@pytest.mark.parametrize("n", [128, 256])
def test_constant_load_and_slip_wear_the_bearing_to_the_journals_imprint(n):
    """Journal in bearing under a constant load F = M g sliding at v = OMEGA R_J, 4e5
    cycles of length T in 32 fixed steps, each run on the bearing worn so far: the worn
    volume is k_w F v N T (Archard), and the bearing is worn to the journal's imprint,
    whose depth d0 follows from the volume (the imprint's cross-section times L).
    Measured: deepest 9.525 / 9.588 / 9.596 um at 128 / 256 / 512 cells against
    d0 = 9.606 um (converging with the grid); the seat within 0.2 / 0.1 / 1.7 % of d0 of
    the imprint (at 512 cells the elastic band at the seat's edge shows: it wears beyond
    the rigid imprint). At 1e5 cycles (d0 3.8 um) the elastic approach, 0.75 um, is 20 %
    of d0 and the seat is 1 % shallower and wider than the rigid imprint; at 1.6e6 cycles
    in 32 steps each step deepens the seat by about the elastic approach and the seat
    roughens (25 %): bound the steps (max_step_penetration) there."""
    from scipy.optimize import brentq

    from clearance.io.dataset import result_to_dataset
    from clearance.scenario.wear import JointWear, WearSettings
    from clearance.wear.predict import CycleWear, WearLoop, run_metrics, run_wear_loop

    F, v, N = M * G, OMEGA * RJ, 4e5
    rb = RJ + C

    def cycle(worn, maps):
        r = cl.simulate(spinning_journal(worn), T, dt_out=T / 50)
        assert r.success
        m, work = bearing_history(r, "J", k_w=KW, surface=maps["J"].empty(), worn=maps["J"])
        return CycleWear({"J": m.depth}, {"J": work}, {"J": run_metrics(result_to_dataset(r), "J")})

    st = WearLoop({"J": BearingWearMap(rb, LB, 1, n)}, {"J": C})
    run_wear_loop(cycle, WearSettings({"J": JointWear(KW, n // 4)}, N, N / 32), st, log=None)
    assert st.done and st.cycles == pytest.approx(N)
    m = st.maps["J"]
    assert st.history()["wear_work"].values[:, 0] == pytest.approx(F * v * T, rel=1e-4)
    first_order = float(np.sum(m.depth) * m.cell_area)
    assert first_order == pytest.approx(KW * F * v * N * T, rel=1e-4)
    assert m.volume() == pytest.approx(first_order, rel=m.max_depth() / rb)
    d0 = brentq(lambda d: LB * imprint_area(d, rb) - first_order, 1e-12, 1e-3)
    assert m.max_depth() == pytest.approx(d0, rel=0.01)
    seat = imprint(d0, m.angles + np.pi / 2)
    assert np.max(np.abs(m.depth[0] - seat)) < 0.03 * d0


SLIDER_CRANK_WEAR = """
[wear]
cycles = 2e4
update_factor = 1e4
warmup = 0.012
cycle_time = 0.012

[wear.joints.wrist]
coefficient = 1e-15
length = 0.02
"""


def test_slider_crank_bearing_wear_end_to_end_and_resumed(tmp_path, monkeypatch):
    """The field's revolute-clearance benchmark (Flores' slider-crank, library scenario)
    through `clearance wear`: one iteration by the CLI, then resumed to the end; equal to an
    uninterrupted prediction; the bearing wears where the rod pushes and pulls (along the
    rod, the bearing marker's f axis, as in Flores et al.'s revolute-joint wear studies),
    and the impacts grow with the wear; the figures are written, and nothing lands in the
    working folder."""
    import subprocess
    import sys

    from clearance.scenario.toml_io import library_path
    from clearance.wear.predict import predict_wear

    path = tmp_path / "sc.toml"
    path.write_text(library_path("slider_crank").read_text() + SLIDER_CRANK_WEAR)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "clearance.cli.main", "wear", str(path), "-o", str(out)]
    cwd = tmp_path / "cwd"  # the runs write nothing here (no [output] folder of their own)
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    r = subprocess.run(
        [*cmd, "--iterations", "1", "--no-figures"], capture_output=True, text=True, cwd=cwd
    )
    assert r.returncode == 0, r.stderr
    w = predict_wear(path, out_dir=out, log=None)
    ref = predict_wear(path, out_dir=tmp_path / "ref", log=None, figures=False)
    h = w.history
    assert w.state.done and h["cycles"].values.tolist() == [0.0, 1e4, 2e4]
    for name in ("volume", "max_depth", "depth_wrist", "impacts", "peak_contact_force"):
        np.testing.assert_array_equal(h[name].values, ref.history[name].values)
    v = h["volume"].sel(joint="wrist").values
    assert v[0] == 0.0 and 0.0 < v[1] < v[2]
    imp = h["impacts"].sel(joint="wrist").values
    assert imp[2] > imp[0]
    m = w.state.maps["wrist"]
    deepest = m.angles[np.argmax(m.depth[0])]
    assert abs(math.cos(deepest)) > math.cos(math.radians(30))
    for f in ("wear_map_wrist", "wear_surface_wrist", "wear_history"):
        assert (out / f"{f}.png").stat().st_size > 10_000
    assert not any(cwd.iterdir())  # (the wear runs once created the scenario's results/)


def test_a_bearing_without_a_length_is_refused_naming_the_field(tmp_path):
    """A planar bearing has no length of its own: [wear.joints.<J>] must give one (the
    cells' areas), else the scenario is refused naming the file, the field and the rule."""
    from clearance.scenario import load_scenario
    from clearance.scenario.errors import ScenarioError
    from clearance.scenario.toml_io import library_path

    path = tmp_path / "sc.toml"
    path.write_text(
        library_path("slider_crank").read_text() + SLIDER_CRANK_WEAR.replace("length = 0.02\n", "")
    )
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    msg = str(err.value)
    assert "wear.joints.wrist.length" in msg and str(path) in msg and "contact length" in msg


def test_station_sections_see_the_kernels_penetration_of_a_tilted_journal():
    """A rod hung by a spatial revolute clearance joint (4 stations) in a rotated marker
    frame, its mass centre 5 cm along the axis: the journal tilts (about 0.01 rad) and the
    end stations carry the load. At every sample and station, the deepest overlap of the
    unworn bearing's cells with the journal, taken from `station_sections` (the joint's
    eccentricity and the bodies' rotations, computed here outside the kernel), equals the
    kernel's penetration of that station: frames, axial coordinates and tilt agree (review
    finding: the in-plane overlap missed R_J theta^2 / 2, 0.8 um here)."""
    from clearance.wear.bearing import station_sections

    Ts = Rotation.from_rotvec([0.4, -0.3, 2.5]).as_matrix()
    h = Ts[:, 2]
    clr = cl.RevoluteClearance(
        RJ, radial_clearance=C, model="spatial", length=LB, stations=4, normal=HERTZ
    )
    m = cl.Mechanism("tilted pendulum", gravity=(0, -9.81, 0))
    m.add(
        cl.Body(
            "rod",
            0.6,
            (0.008, 0.0005, 0.008),
            position=tuple(np.array([0.0, -0.2, 0.0]) + 0.05 * h),
            angular_velocity=tuple(6.0 * h),
        ),
        cl.Marker("g", "ground", (0, 0, 0), Ts),
        cl.Marker("r", "rod", tuple(np.array([0.0, 0.2, 0.0]) - 0.05 * h), Ts),
        cl.Revolute("J", "g", "r", clearance=clr),
    )
    r = cl.simulate(m, 0.05, dt_out=5e-4)
    assert r.success
    names, sig, ek, axis = station_sections(r, "J")
    assert np.allclose(sig, LB * (-0.5 + (np.arange(4) + 0.5) / 4))
    tilt = np.arccos(np.clip(np.abs(axis[:, 2]), 0, 1))
    assert tilt.max() > 5e-3
    bm = BearingWearMap(RJ + C, LB, 4, 2048)
    checked = 0
    for j, name in enumerate(names):
        pen = np.asarray(r.channel("point_penetration", name))
        on = pen > 0
        d = bm.overlap(j, ek[j, on], C, axis[on]).max(axis=1)
        # (the cells sample the rim: 2.6e-10 m at 2048 cells, 1.6e-11 at 8192, 1.2e-12 at
        # 32768; the tilt's term alone is 8e-7 m)
        np.testing.assert_allclose(d, pen[on], rtol=0, atol=5e-10)
        checked += int(on.sum())
    assert checked > 50


@pytest.mark.parametrize(
    "text, field",
    [
        ("length = 0.02\n", "wear.joints.wrist.length"),  # the planar one needs it: fine
        ("length = 0.02\nsmoothing = 3.0\n", "wear.joints.wrist.smoothing"),
    ],
)
def test_wear_table_fields_a_bearing_cannot_use_are_refused(tmp_path, text, field):
    """A bearing's [wear.joints] table: `smoothing` is the socket's (refused), `length`
    only where the clearance has none (a planar joint); on a spatial joint with its own
    length, `length` is refused (the stations and the wear share one)."""
    from clearance.scenario import load_scenario
    from clearance.scenario.errors import ScenarioError
    from clearance.scenario.toml_io import library_path

    base = library_path("slider_crank").read_text()
    wear = SLIDER_CRANK_WEAR.replace("length = 0.02\n", text)
    path = tmp_path / "sc.toml"
    path.write_text(base + wear)
    if field.endswith("length"):  # a planar joint: accepted; a spatial one with length: refused
        load_scenario(path)
        spatial = base.replace('model = "planar"', 'model = "spatial"\nlength = 0.02')
        path.write_text(spatial + wear)
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    assert field in str(err.value) and "expected none" in str(err.value)


def test_slider_crank_volume_balance_with_coulomb_friction():
    """Flores' slider-crank (the library scenario, one revolution at 5000 rpm) with Coulomb
    friction at its revolute clearance joint: the sampled integral of F_N |v_slip| dt
    equals the friction work the kernel integrates at every step, over mu (a full mechanism
    run with 70 contact events; measured -8.6e-4 at the scenario's 10 us samples, the
    friction's ramp below 1 mm/s included)."""
    from clearance.scenario import build_mechanisms, load_scenario, with_overrides
    from clearance.scenario.toml_io import library_path

    mu = 0.1
    s = with_overrides(
        load_scenario(library_path("slider_crank")),
        {
            "trajectory.duration": 0.012,
            "clearance.joints.wrist.friction": {"law": "coulomb", "mu": mu},
        },
    )
    _, mech, _ = build_mechanisms(s)
    r = cl.simulate(mech, s.trajectory.duration, **s.solver.simulate_kwargs())
    assert r.success
    _, work = bearing_history(r, "wrist", k_w=1e-15, n=128, length=0.02)
    d_t = float(r.dissipated("wrist")[1][-1])
    assert d_t > 0.0
    assert work == pytest.approx(d_t / mu, rel=5e-3)
