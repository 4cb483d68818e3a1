"""Clearance joints as a family: revolute (journal in bearing, planar and spatial, thrust),
cylindrical and prismatic (slider in guide, planar and spatial) against independent oracles:
finite differences of the gap and of the elastic energy (virtual work = -dV/dq), the exact
circle-cylinder geometry of a tilted journal by brute force, a hand-checked slider corner,
the energy balance with damping and friction, the ideal limit c -> 0 and the restitution of
a single impact. The spherical kind is covered by test_clearance_joint.py; the planar
slider-crank benchmark by test_slider_crank_clearance.py."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import clearance as cl
from clearance.contact.element import (
    clearance_forces,
    contact_energy,
    make_contact_state,
    point_gap,
)
from clearance.dynamics.rhs import body_states, make_work
from clearance.kinematics.timefn import eval_all
from clearance.layout import PO_DDOT, PO_DELTA, PO_FN, PO_N

RJ, C = 0.010, 0.2e-3  # journal radius, radial clearance [m]
LB = 0.02  # bearing length [m]


def quat_exp_right(p, w):
    """p (x) exp(w/2): body-frame rotation increment, written independently of the package."""
    a = np.linalg.norm(w)
    q = np.r_[np.cos(a / 2), (np.sin(a / 2) / a) * w] if a > 0 else np.r_[1.0, 0, 0, 0]
    p0, pv, q0, qv = p[0], p[1:], q[0], q[1:]
    return np.r_[p0 * q0 - pv @ qv, p0 * qv + q0 * pv + np.cross(pv, qv)]


def quat(R):
    x, y, z, w = Rotation.from_matrix(R).as_quat()
    return np.array([w, x, y, z])


TS = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix()  # outer marker triad (body s)
TB = Rotation.from_rotvec([-0.4, 0.1, 0.2]).as_matrix()  # inner marker triad (body b)
PS = np.array([0.02, -0.01, 0.03])  # outer marker point (body s)
PB = np.array([-0.015, 0.02, 0.01])  # inner marker point (body b)


def two_bodies(joint_cls, clearance, slide=False):
    """Free outer body s and inner body b joined only by a clearance joint (no gravity);
    slide: both markers slide along their bodies (0.05 and -0.07 m/s, from t = 0)."""
    ks = dict(slide_axis=(0.3, -0.5, 0.8), slide=cl.Polynomial((0.0, 0.05))) if slide else {}
    kb = dict(slide_axis=(-0.6, 0.2, 0.4), slide=cl.Polynomial((0.0, -0.07))) if slide else {}
    m = cl.Mechanism("pair", gravity=(0, 0, 0))
    m.add(
        cl.Body("s", 2.0, (0.02, 0.03, 0.025)),
        cl.Body("b", 0.5, (0.004, 0.005, 0.006)),
        cl.Marker("ms", "s", PS, TS, **ks),
        cl.Marker("mb", "b", PB, TB, **kb),
        joint_cls("J", "ms", "mb", clearance=clearance),
    )
    return m


def place(c, rng, e_loc, rel_rotvec, speed=0.2):
    """State with the inner marker at e_loc (outer marker frame) from the outer marker and
    rotated by rel_rotvec (outer marker frame); random pose of s, random velocities."""
    y = np.zeros(c.ny)
    As = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    rs = rng.normal(size=3) * 0.1
    Rs = As @ TS  # outer marker frame in the world
    Rb = Rs @ Rotation.from_rotvec(rel_rotvec).as_matrix()
    Ab = Rb @ TB.T
    Xb = rs + As @ PS + Rs @ np.asarray(e_loc, float)
    rb = Xb - Ab @ PB
    y[0:3], y[3:7], y[7:10], y[10:14] = rs, quat(As), rb, quat(Ab)
    y[14:26] = speed * rng.normal(size=12)
    return y


def evaluate(c, y, flag=0, ddm=0.1, t=0.0):
    wk = make_work(c.model)
    cs = make_contact_state(c.model)
    cs.flag[:] = flag
    cs.ddm[:] = ddm
    body_states(c.model, y, wk)
    eval_all(c.model.fn_kind, c.model.fn_ptr, c.model.fn_data, t, wk.fval)  # (slides)
    wk.Q[:] = 0.0
    yd = np.zeros(c.ny)
    clearance_forces(c.model, y, wk, cs, yd)
    return wk.Q.copy(), wk.pout.copy(), yd


def energy(c, y):
    wk = make_work(c.model)
    body_states(c.model, y, wk)
    return contact_energy(c.model, wk.bA, wk.br, wk.fval)


def gaps(c, y):
    wk = make_work(c.model)
    body_states(c.model, y, wk)
    return np.array([point_gap(c.model, p, wk.bA, wk.br, wk.fval) for p in range(c.ncp)])


def perturbed(y, b, k, h):
    """y moved by h along velocity direction k of body b (rotations: body-frame increments)."""
    yy = y.copy()
    if k < 3:
        yy[7 * b + k] += h
    else:
        w = np.zeros(3)
        w[k - 3] = h
        yy[7 * b + 3 : 7 * b + 7] = quat_exp_right(y[7 * b + 3 : 7 * b + 7], w)
    return yy


def along_motion(y, s):
    """The state moved for a time s with its velocities (r += s v, p <- p (x) exp(s w'/2))."""
    yy = y.copy()
    for b in range(2):
        v = y[14 + 6 * b : 17 + 6 * b]
        w = y[17 + 6 * b : 20 + 6 * b]
        yy[7 * b : 7 * b + 3] += s * v
        yy[7 * b + 3 : 7 * b + 7] = quat_exp_right(y[7 * b + 3 : 7 * b + 7], s * w)
    return yy


def assert_force_is_minus_energy_gradient(c, y, Q):
    """Q (2 bodies x 6) = -dV_c/dq by central differences of the contact energy along each
    body's 6 velocity directions (rotations: body-frame increments)."""
    h = 2e-9
    for b in range(2):
        for k in range(6):
            dV = (energy(c, perturbed(y, b, k, h)) - energy(c, perturbed(y, b, k, -h))) / (2 * h)
            assert -dV == pytest.approx(Q[b, k], rel=2e-5, abs=2e-6 * np.max(np.abs(Q)))


HERTZ = cl.Hertz(stiffness=3e10)
KINDS = {
    "revolute planar": (cl.Revolute, cl.RevoluteClearance(RJ, radial_clearance=C, normal=HERTZ)),
    "revolute spatial": (
        cl.Revolute,
        cl.RevoluteClearance(RJ, radial_clearance=C, model="spatial", length=LB, normal=HERTZ),
    ),
    "revolute spatial + thrust": (
        cl.Revolute,
        cl.RevoluteClearance(
            RJ,
            radial_clearance=C,
            model="spatial",
            length=LB,
            axial_clearance=1e-4,
            normal=HERTZ,
            thrust_normal=cl.Hertz(stiffness=1e10),
        ),
    ),
    "cylindrical spatial": (
        cl.Cylindrical,
        cl.RevoluteClearance(RJ, radial_clearance=C, model="spatial", length=LB, normal=HERTZ),
    ),
    "prismatic planar": (
        cl.Prismatic,
        cl.PrismaticClearance(width=0.02, length=0.04, clearance=C, normal=HERTZ),
    ),
    "prismatic spatial": (
        cl.Prismatic,
        cl.PrismaticClearance(
            width=0.02, height=0.015, length=0.04, clearance=C, model="spatial", normal=HERTZ
        ),
    ),
}
# relative placements that put some contact points a few micrometres into contact
PLACEMENTS = {
    "revolute planar": ((C + 3e-6, 0.0, 0.0), (0.0, 0.0, 0.3)),
    "revolute spatial": ((0.75 * C, 0.64 * C, 1e-4), (3e-4, -8e-4, 0.7)),
    "revolute spatial + thrust": ((0.5 * C, -0.6 * C, -1e-4 - 2e-6), (1e-4, 5e-5, 0.1)),
    "cylindrical spatial": ((-0.75 * C, 0.64 * C, 0.004), (-5e-4, 6e-4, -1.0)),
    "prismatic planar": ((C - 2e-6, 0.0, 0.001), (0.0, 3e-4, 0.0)),
    "prismatic spatial": ((0.98 * C, 0.97 * C, 0.002), (2e-4, -3e-4, 1e-4)),
}


@pytest.mark.parametrize("kind", list(KINDS))
def test_virtual_work_is_minus_the_gradient_of_the_contact_energy(kind):
    """Q of a conservative contact = -dV_c/dq over both bodies' 12 velocity directions
    (central differences), i.e. the forces act exactly at the gradient of the gap."""
    rng = np.random.default_rng(11)
    c = cl.compile_mechanism(two_bodies(*KINDS[kind]))
    y = place(c, rng, *PLACEMENTS[kind])
    Q, po, _ = evaluate(c, y)
    assert 0.0 < np.max(po[:, PO_DELTA]) < 2e-5, "the placement: a few um of contact"
    assert np.max(np.abs(Q)) > 1.0
    assert_force_is_minus_energy_gradient(c, y, Q)


@pytest.mark.parametrize("kind", list(KINDS))
def test_gap_rate_is_the_derivative_of_the_gap(kind):
    """delta_dot of every contact point = d delta / dt along the motion (central
    differences), in contact and out of it; and the pair power: sum Q . v equals
    -sum F_N delta_dot for a conservative law (physics.md f.4)."""
    rng = np.random.default_rng(5)
    c = cl.compile_mechanism(two_bodies(*KINDS[kind]))
    y = place(c, rng, *PLACEMENTS[kind])
    Q, po, _ = evaluate(c, y)
    h = 1e-8
    fd = (gaps(c, along_motion(y, h)) - gaps(c, along_motion(y, -h))) / (2 * h)
    scale = np.max(np.abs(po[:, PO_DDOT]))
    assert np.allclose(po[:, PO_DDOT], fd, rtol=1e-5, atol=1e-6 * scale)
    power = float(np.sum(Q * y[14:26].reshape(2, 6)))
    pair = -float(np.sum(po[:, PO_FN] * po[:, PO_DDOT]))
    assert power == pytest.approx(pair, rel=1e-9, abs=1e-12)


# every kind with LuGre friction, and the ball in its socket (n = e/|e| turns with the centres)
LUGRE = cl.LuGre()
LUGRE_KINDS = {
    name: (cls, dataclasses.replace(clr, friction=LUGRE)) for name, (cls, clr) in KINDS.items()
}
LUGRE_KINDS["spherical"] = (
    cl.Spherical,
    cl.SphericalClearance(RJ, radial_clearance=C, normal=HERTZ, friction=LUGRE),
)
LUGRE_PLACEMENTS = dict(
    PLACEMENTS, spherical=((0.6 * (C + 3e-6), 0.8 * (C + 3e-6), 0.0), (0.2, 0.1, -0.3))
)


@pytest.mark.parametrize("slide", [False, True], ids=["fixed", "sliding"])
@pytest.mark.parametrize("kind", list(LUGRE_KINDS))
def test_lugre_bristles_follow_the_turning_tangent_plane(kind, slide):
    """With n_dot from central differences of the kernel's normals along the motion (and
    the markers' slides), at every point in contact: d(n . z)/dt = n_dot . z + n . z_dot = 0,
    so bristles that start in the tangent plane (z = 0 at onset) stay in it however the
    normal turns, with no projection after the steps (contact/element.py); and a normal part
    of z acts nowhere: neither on the force nor on the rate of z's tangent part
    d(P z)/dt (P = I - n n^T), which a normal part fixed in space would leak into as n
    turns."""
    rng = np.random.default_rng(7)
    c = cl.compile_mechanism(two_bodies(*LUGRE_KINDS[kind], slide=slide))
    y = place(c, rng, *LUGRE_PLACEMENTS[kind])
    iz = slice(c.iz, c.iz + 3 * c.ncp)

    def normals(s):
        return evaluate(c, along_motion(y, s), t=s)[1][:, PO_N : PO_N + 3]

    n = normals(0.0)
    z = 1e-6 * rng.normal(size=(c.ncp, 3))
    z -= np.sum(z * n, axis=1)[:, None] * n  # tangent bristles
    y[iz] = z.ravel()
    Q, po, yd = evaluate(c, y, flag=1)
    zd = yd[iz].reshape(c.ncp, 3)
    inc = po[:, PO_DELTA] > 0.0
    assert inc.any()
    h = 1e-8
    n_p, n_m = normals(h), normals(-h)
    nd = (n_p - n_m) / (2 * h)
    turn = np.sum(nd * z, axis=1)[inc]  # what a bristle fixed in space would lose to n
    # the normal turns (|n_dot| ~ 1e3 1/s for journals and balls, ~0.3 1/s for the walls of
    # a turning guide or bearing face): far above the rounding of n . z_dot
    assert np.max(np.abs(turn)) > 1e-10 * np.max(np.abs(zd[inc]))
    rate = turn + np.sum(n[inc] * zd[inc], axis=1)
    assert np.max(np.abs(rate)) < 1e-6 * np.max(np.abs(turn))

    def tangent_rate(zz, zzd):  # d(P z)/dt by central differences
        def zt(nn, x):
            return x - np.sum(x * nn, axis=1)[:, None] * nn

        return (zt(n_p, zz + h * zzd) - zt(n_m, zz - h * zzd)) / (2 * h)

    a = 3e-6  # a normal part: the force and d(P z)/dt stay as they are
    y[iz] = (z + a * n).ravel()
    Q2, _, yd2 = evaluate(c, y, flag=1)
    assert np.allclose(Q2, Q, rtol=1e-12, atol=1e-12 * np.max(np.abs(Q)))
    leak = tangent_rate(z + a * n, yd2[iz].reshape(c.ncp, 3)) - tangent_rate(z, zd)
    scale = a * np.max(np.linalg.norm(nd[inc], axis=1))  # the leak of a fixed normal part
    assert scale > 0.0
    assert np.max(np.abs(leak[inc])) < 1e-6 * scale


def test_planar_journal_is_the_classic_planar_model():
    """Aligned journal: delta = |e| - c with e the in-plane offset, n = e/|e|, the force
    K delta^1.5 (Flores & Ambrosio 2004)."""
    rng = np.random.default_rng(2)
    c = cl.compile_mechanism(two_bodies(*KINDS["revolute planar"]))
    e = np.array([1.2e-4, -1.7e-4, 0.0])  # |e| = 2.08e-4 > c
    y = place(c, rng, e, (0.0, 0.0, 0.4))
    _, po, _ = evaluate(c, y)
    delta = np.linalg.norm(e) - C
    assert po[0, PO_DELTA] == pytest.approx(delta, rel=1e-9)
    assert po[0, PO_FN] == pytest.approx(3e10 * delta**1.5, rel=1e-8)
    As = Rotation.from_quat(np.r_[y[4:7], y[3]]).as_matrix()
    assert np.allclose(po[0, PO_N : PO_N + 3], As @ TS @ e / np.linalg.norm(e), atol=1e-12)


def brute_force_station_penetration(sigma, o, h, RB, RJ, profile=None, normal=False):
    """Exact penetration of the bearing cross-section circle at axial coordinate sigma
    (centre (0, 0, sigma), radius RB, in the plane z = sigma) into a journal cylinder of
    radius RJ about the axis through o with unit direction h: RJ minus the smallest distance
    of a rim point from that axis, by dense sampling and golden-section refinement (written
    without the package's Newton iteration). profile(phi): a worn rim, radius RB +
    profile(phi) (vectorised); normal: also return the unit direction from the axis to the
    nearest rim point."""
    o, h = np.asarray(o, float), np.asarray(h, float) / np.linalg.norm(h)

    def radius(phi):
        return RB + (profile(phi) if profile is not None else 0.0 * phi)

    def vec(phi):
        r = radius(phi)
        X = np.array([r * math.cos(phi), r * math.sin(phi), sigma]) - o
        return X - (X @ h) * h

    def dist(phi):
        return float(np.linalg.norm(vec(phi)))

    phis = np.linspace(0, 2 * np.pi, 20001)
    r = radius(phis)
    X = np.column_stack([r * np.cos(phis), r * np.sin(phis), np.full(phis.size, sigma)]) - o
    k = int(np.argmin(np.linalg.norm(X - np.outer(X @ h, h), axis=1)))
    a, b = phis[k] - 4e-4, phis[k] + 4e-4
    g = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        x1, x2 = b - g * (b - a), a + g * (b - a)
        if dist(x1) < dist(x2):
            b = x2
        else:
            a = x1
    v = vec(0.5 * (a + b))
    pen = RJ - float(np.linalg.norm(v))
    return (pen, v / np.linalg.norm(v)) if normal else pen


def _station_model(N):
    clr = cl.RevoluteClearance(
        RJ, radial_clearance=C, model="spatial", length=LB, stations=N, normal=HERTZ
    )
    return cl.compile_mechanism(two_bodies(cl.Revolute, clr)), LB * (
        -0.5 + (np.arange(N) + 0.5) / N
    )


def test_journal_stations_match_the_exact_circle_cylinder_geometry():
    """Offset and tilted journals (tilts up to 2 c / L, offsets up to c, in every
    direction): every station's penetration equals the brute-force circle-cylinder value to
    1e-12 m, although the tilted journal's section is an ellipse (the small-angle planar
    formula |e| - c is off by about R theta^2 / 2, micrometres here)."""
    c, sig = _station_model(5)
    rng = np.random.default_rng(21)
    worst_planar = 0.0
    for _ in range(6):
        e = rng.uniform(-0.8, 0.8, size=2) * C
        tilt = rng.uniform(-2, 2, size=2) * C / LB
        y = place(c, rng, (e[0], e[1], 3e-4), (tilt[0], tilt[1], 0.5), speed=0.0)
        _, po, _ = evaluate(c, y)
        # the journal axis in the outer (bearing) marker frame
        Rrel = Rotation.from_rotvec((tilt[0], tilt[1], 0.5)).as_matrix()
        o, h = np.array([e[0], e[1], 3e-4]), Rrel[:, 2]
        ref = np.array([brute_force_station_penetration(s, o, h, RJ + C, RJ) for s in sig])
        assert np.allclose(po[:, PO_DELTA], ref, atol=1e-12)
        # the planar formula: the axis offset from the station centre, normal to the axis
        planar = [np.linalg.norm((o - [0, 0, s]) - ((o - [0, 0, s]) @ h) * h) - C for s in sig]
        worst_planar = max(worst_planar, float(np.max(np.abs(np.array(planar) - ref))))
    assert worst_planar > 1e-7  # the test sees the elliptic section


def _tilted(angle):
    """Journal axis tilted by `angle` about the bearing's x axis."""
    return np.array([0.0, -math.sin(angle), math.cos(angle)])


def test_tilted_journal_touches_at_the_bearing_edges():
    """A centred journal tilted about a diameter: by the independent circle-cylinder
    geometry the contact starts at the bearing's end stations, on opposite sides, at the
    tilt where their penetration reaches zero; the model agrees station by station
    (penetration within 1e-12 m) and the two edge forces make a restoring moment."""
    N = 8
    c, sig = _station_model(N)
    # the tilt at which the end stations (|sigma| = 7 LB / 16) first touch, from the oracle
    lo, hi = 0.0, 0.1
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if brute_force_station_penetration(sig[-1], 0, _tilted(mid), RJ + C, RJ) > 0:
            hi = mid
        else:
            lo = mid
    tilt0 = 0.5 * (lo + hi)
    assert tilt0 == pytest.approx(C / sig[-1], rel=0.02)  # about c / sigma for a slender tilt
    rng = np.random.default_rng(3)
    for tilt in (0.98 * tilt0, 1.02 * tilt0, 1.3 * tilt0):
        y = place(c, rng, (0.0, 0.0, 0.0), (tilt, 0.0, 0.0), speed=0.0)
        Q, po, _ = evaluate(c, y)
        ref = [brute_force_station_penetration(s, 0, _tilted(tilt), RJ + C, RJ) for s in sig]
        assert np.allclose(po[:, PO_DELTA], ref, atol=1e-12)
        touching = po[:, PO_DELTA] > 0
        if tilt < tilt0:
            assert not touching.any() and np.all(Q == 0.0)
            continue
        # contact only at the end stations; opposite normals; no net force, a net moment
        assert touching[0] and touching[-1] and not touching[1 : N // 2].any()
        assert po[0, PO_N : PO_N + 3] @ po[-1, PO_N : PO_N + 3] < -0.99
        assert np.allclose(Q[1, :3], 0.0, atol=1e-9 * np.max(np.abs(Q)))
        As = Rotation.from_quat(np.r_[y[11:14], y[10]]).as_matrix()  # body b
        moment_w = As @ Q[1, 3:]  # world moment about b's mass centre
        tilt_axis_w = As @ TB @ np.array([1.0, 0, 0])  # the marker's f axis (the tilt axis)
        # restoring: the moment on the journal opposes its tilt about f
        assert moment_w @ tilt_axis_w < 0


def test_slider_corner_contact_by_hand():
    """Planar slider rotated by theta about the guide's g axis and pushed towards +f: only
    the corner (+l, +a) reaches the +f wall; its penetration, by hand, is
    e_f + l sin(theta) + a cos(theta) - (a + c); the force K delta^1.5 acts along -f_s at
    that corner, so its moment about the slider centre is -(l cos(theta) - a sin(theta))
    K delta^1.5 about g."""
    a, half_l = 0.01, 0.02
    clr = cl.PrismaticClearance(width=2 * a, length=2 * half_l, clearance=C, normal=HERTZ)
    c = cl.compile_mechanism(two_bodies(cl.Prismatic, clr))
    theta, ef = 4e-3, 1.25e-4
    rng = np.random.default_rng(9)
    y = place(c, rng, (ef, 0.0, 0.0), (0.0, theta, 0.0), speed=0.0)
    Q, po, _ = evaluate(c, y)
    names = [p.name for p in c.contact_points]
    # the corner at +h (length) and +f (width); rotating by theta about g moves it by
    # (l sin theta, a cos theta) - a along f
    k = names.index("J/corner++f")
    delta = ef + half_l * math.sin(theta) + a * math.cos(theta) - (a + C)
    assert po[k, PO_DELTA] == pytest.approx(delta, rel=1e-9)
    assert sum(po[:, PO_DELTA] > 0) == 1
    F = 3e10 * delta**1.5
    As = Rotation.from_quat(np.r_[y[4:7], y[3]]).as_matrix()
    fs, gs = As @ TS[:, 0], As @ TS[:, 1]
    assert np.allclose(Q[1, :3], -F * fs, rtol=1e-9, atol=1e-9 * F)  # on the slider
    Ab = Rotation.from_quat(np.r_[y[11:14], y[10]]).as_matrix()
    # the slider centre is its marker point, its mass centre is elsewhere: moment about the
    # marker point = moment about the mass centre + (mass centre - marker) x force
    m_cm = Ab @ Q[1, 3:]
    m_marker = m_cm + np.cross(-Ab @ PB, -F * fs)
    corner = half_l * (Ab @ TB[:, 2]) + a * (Ab @ TB[:, 0])  # from the marker point
    assert np.allclose(m_marker, np.cross(corner, -F * fs), atol=1e-9 * F)
    assert m_marker @ gs == pytest.approx(-F * (half_l * math.cos(theta) - a * math.sin(theta)))


# --------------------------------------------------------------------------- simulations


def pendulum(joint_cls, clearance, *, spin=3.0, gravity=(0.0, -9.81, 0.0)):
    """A rod hanging from a ground joint at the origin (joint axis z, pivot 0.2 m above the
    rod's mass centre), swinging about z; its inertia makes it tilt-stiff but not rigid."""
    m = cl.Mechanism("pendulum", gravity=gravity)
    L = 0.2
    m.add(
        cl.Body(
            "rod",
            0.6,
            (0.008, 0.0005, 0.008),
            position=(0.0, -L, 0.0),
            velocity=(spin * L, 0.0, 0.0),
            angular_velocity=(0.0, 0.0, spin),
        ),
        cl.Marker("pivot_g", "ground"),
        cl.Marker("pivot_r", "rod", (0.0, L, 0.0)),
        joint_cls("J", "pivot_g", "pivot_r", clearance=clearance),
    )
    return m


def slider(clearance, *, speed=0.5, gravity=(0.0, -9.81, 0.0)):
    """A slider in a ground guide along x (guide marker h = x, f = y, g = z), moving along
    x under transverse gravity; prismatic joint, ideal or with clearance."""
    m = cl.Mechanism("slider", gravity=gravity)
    T = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # f = y, g = z, h = x
    m.add(
        cl.Body("s", 0.4, (2e-4, 3e-4, 3e-4), velocity=(speed, 0.0, 0.0)),
        cl.Marker("guide", "ground", (0, 0, 0), T),
        cl.Marker("slide", "s", (0, 0, 0), T),
        cl.Prismatic("J", "guide", "slide", clearance=clearance),
    )
    return m


LN = cl.LankaraniNikravesh(restitution=0.8)
SIM_KINDS = {
    "revolute planar": lambda c, law, fr: (
        cl.Revolute,
        cl.RevoluteClearance(RJ, radial_clearance=c, normal=law, friction=fr),
    ),
    "revolute spatial": lambda c, law, fr: (
        cl.Revolute,
        cl.RevoluteClearance(
            RJ, radial_clearance=c, model="spatial", length=LB, normal=law, friction=fr
        ),
    ),
    "revolute spatial + thrust": lambda c, law, fr: (
        cl.Revolute,
        cl.RevoluteClearance(
            RJ,
            radial_clearance=c,
            model="spatial",
            length=LB,
            axial_clearance=c,
            normal=law,
            friction=fr,
        ),
    ),
    "cylindrical spatial": lambda c, law, fr: (
        cl.Cylindrical,
        cl.RevoluteClearance(
            RJ, radial_clearance=c, model="spatial", length=LB, normal=law, friction=fr
        ),
    ),
    "prismatic planar": lambda c, law, fr: (
        None,
        cl.PrismaticClearance(width=0.02, length=0.04, clearance=c, normal=law, friction=fr),
    ),
    "prismatic spatial": lambda c, law, fr: (
        None,
        cl.PrismaticClearance(
            width=0.02,
            height=0.02,
            length=0.04,
            clearance=c,
            model="spatial",
            normal=law,
            friction=fr,
        ),
    ),
}


def sim_model(kind, c, law, friction=None, **kw):
    joint, clr = SIM_KINDS[kind](c, law, friction or cl.NoFriction())
    if joint is None:
        return slider(clr, **kw)
    if kind == "revolute spatial + thrust":  # gravity along the axis too: the collars work
        kw.setdefault("gravity", (0.0, -9.81, -4.0))
    return pendulum(joint, clr, **kw)


@pytest.mark.parametrize("kind", list(SIM_KINDS))
def test_energy_balance_with_damping_and_friction(kind):
    """physics.md j: T + V + V_c - W + D_n + D_t stays constant through impacts and sliding
    contact with hysteresis damping and Coulomb friction, to 1e-6 of the energy scale."""
    law = cl.LankaraniNikravesh(stiffness=2e10, restitution=0.8)
    m = sim_model(kind, 2e-4, law, cl.Coulomb(mu=0.15))
    r = cl.simulate(m, 0.15, dt_out=5e-4, rtol=1e-9, atol=1e-12)
    assert r.success, r.message
    e = r.energy
    assert len(r.impacts("J")) >= 2 and e["damping"][-1] > 0
    scale = np.max(np.abs(e["kinetic"]) + np.abs(e["potential"]))
    assert np.max(np.abs(e["residual"])) < 1e-6 * scale
    if "prismatic" in kind or kind != "revolute spatial + thrust":
        assert e["friction"][-1] > 0  # the friction worked


def _ideal_model(kind):
    if kind.startswith("prismatic"):
        return slider(None)
    joint = cl.Cylindrical if kind.startswith("cylindrical") else cl.Revolute
    gravity = (0.0, -9.81, -4.0) if "thrust" in kind else (0.0, -9.81, 0.0)
    return pendulum(joint, None, gravity=gravity)


@pytest.mark.parametrize("kind", list(SIM_KINDS))
def test_small_clearance_approaches_the_ideal_joint(kind):
    """c -> 0 (with a stiff contact): the motion approaches that of the ideal joint: the
    largest deviation of the joint point on the inner body is of the order of c (a spatial
    journal's tilt, up to 2c/L, is amplified at points away from the joint)."""
    ideal = cl.simulate(_ideal_model(kind), 0.1, dt_out=1e-3, rtol=1e-9, atol=1e-12)
    errs = []
    for c in (1e-4, 1e-5):
        law = cl.LankaraniNikravesh(stiffness=1e12, restitution=0.5)
        m = sim_model(kind, c, law)
        r = cl.simulate(m, 0.1, dt_out=1e-3, rtol=1e-8, atol=1e-12, max_steps=2_000_000)
        assert r.success, r.message
        mk = m.markers[m.joints["J"].marker_j]  # the joint's point on the inner body
        d = r.point_position(mk.body, mk.position) - ideal.point_position(mk.body, mk.position)
        errs.append(float(np.max(np.linalg.norm(d, axis=1))) / c)
    assert errs[1] < 3.0 and errs[0] < 3.0, errs  # deviation / c


def _restitution_run(kind, v0):
    """Single central impact of a free inner body (its joint marker at its mass centre) on
    its outer part fixed to the ground, without gravity: -(rebound / approach) velocity
    along the impact direction."""
    law = cl.LankaraniNikravesh(stiffness=5e9, restitution=0.9)
    joint, clr = SIM_KINDS[kind](C, law, cl.NoFriction())
    # the guide of a prismatic joint along world x with f = world y (as in `slider`)
    T = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    if joint is None:
        joint, direction = cl.Prismatic, np.array([0.0, 1.0, 0.0])
    else:
        T = np.eye(3)
        direction = np.array([0.0, 0.0, -1.0] if "thrust" in kind else [1.0, 0.0, 0.0])
    m = cl.Mechanism("impact", gravity=(0.0, 0.0, 0.0))
    m.add(
        cl.Body("b", 0.5, (2e-4, 3e-4, 4e-4), velocity=tuple(v0 * direction)),
        cl.Marker("outer", "ground", (0, 0, 0), T),
        cl.Marker("inner", "b", (0, 0, 0), T),
        joint("J", "outer", "inner", clearance=clr),
    )
    r = cl.simulate(m, 2.5 * C / v0 + 2e-3, dt_out=1e-5, rtol=1e-10, atol=1e-14)
    assert r.success, r.message
    v = r.velocity("b") @ direction
    assert len(r.impacts("J")) >= 1 and v[0] == pytest.approx(v0)
    assert np.all(r.penetration("J")[-10:] < 0)  # separated at the end
    return -v[-1] / v0


@pytest.mark.parametrize("kind", list(SIM_KINDS))
def test_single_impact_restitution_matches_the_law(kind):
    """Lankarani-Nikravesh with c_r = 0.9: the apparent restitution of a single impact is
    0.9132 (physics.md g.2 table; independent of the elastic law's form and stiffness), for
    every kind: a journal hitting its bearing (one station, or all stations at once for an
    aligned journal), a collar hitting its thrust face, a slider's edge hitting its wall."""
    e = _restitution_run(kind, 0.05)
    assert e == pytest.approx(0.9132, abs=2e-3)
