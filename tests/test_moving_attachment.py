"""Moving attachment points (sliding markers) and length-dependent inertia: the kernel
features of the mass-moment lumped limb (physics.md c.2 "moving attachment point", i, j).

Oracles: finite differences of phi along a motion (c.6 recipe) for phi_q, phi_t and gamma
with sliding points; conservation of the world angular momentum A J'(l) omega' of a free
limb whose inertia changes (physics.md i: exact with the J'_dot omega' term, drifting
without it); the energy balance with the W_L and W_m terms (j)."""

import numpy as np
import pytest

import clearance as cl
from clearance.model.bodies import InertiaVariation


def qmul(p, q):
    return np.r_[p[0] * q[0] - p[1:] @ q[1:], p[0] * q[1:] + q[0] * p[1:] + np.cross(p[1:], q[1:])]


def qexp(w):
    a = np.linalg.norm(w)
    return np.r_[np.cos(a / 2), np.sin(a / 2) / a * w] if a > 0 else np.r_[1.0, 0, 0, 0]


def sliding_mechanism():
    """Two free bodies joined by a spherical joint, a prismatic-driver-like dot-2 row and a
    distance row, all at points that slide along body axes with time functions."""
    m = cl.Mechanism("slide", gravity=(0, 0, 0))
    s1, s2 = cl.Sinusoid(0.05, 3.0, 0.2, 0.1), cl.Sinusoid(-0.04, 2.0, 0.5, 0.3)
    m.add(
        cl.Body("A", 2.0, (0.02, 0.03, 0.04)),
        cl.Body("B", 1.0, (0.01, 0.02, 0.025)),
        cl.Marker("a1", "A", (0.1, 0.0, 0.2), slide_axis=(0, 0, 1), slide=s1),
        cl.Marker("b1", "B", (0.0, -0.1, 0.0), slide_axis=(1, 1, 0), slide=s2),
        cl.Marker.on_axis("a2", "A", (0.0, 0.1, 0.0), axis=(1, 2, 3)),
        cl.Marker("b2", "B", (0.2, 0.0, 0.1), slide_axis=(0, 1, 0), slide=s1),
        cl.Marker("g", "ground", (0.5, 0.5, 0.5), slide_axis=(1, 0, 0), slide=s2),
        cl.Spherical("S", "a1", "b1"),
        cl.DistanceDriver("D", "g", "b2", cl.Sinusoid(0.1, 1.0, 0.0, 0.8)),
        cl.Cylindrical("C", "a2", "b2"),
    )
    return cl.compile_mechanism(m)


def rows_at(c, y, t):
    r = cl.evaluate_rows(c, t, y)
    return r.phi, r.phi_q, r.phi_dot, r.gamma


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_sliding_points_finite_differences(seed):
    rng = np.random.default_rng(seed)
    c = sliding_mechanism()
    y = np.zeros(c.ny)
    for b in range(c.nb):
        y[7 * b : 7 * b + 3] = rng.normal(size=3)
        p = rng.normal(size=4)
        y[7 * b + 3 : 7 * b + 7] = p / np.linalg.norm(p)
    v = rng.normal(size=c.nv)
    y[c.nq : c.nq + c.nv] = v
    t0 = rng.uniform(-1, 1)
    phi, J, phid, gam = rows_at(c, y, t0)

    def moved(s):
        yy = y.copy()
        for b in range(c.nb):
            yy[7 * b : 7 * b + 3] += s * v[6 * b : 6 * b + 3]
            yy[7 * b + 3 : 7 * b + 7] = qmul(
                y[7 * b + 3 : 7 * b + 7], qexp(s * v[6 * b + 3 : 6 * b + 6])
            )
        return rows_at(c, yy, t0 + s)[0]

    h = 1e-4
    d1 = (moved(h) - moved(-h)) / (2 * h)
    d2 = (moved(h) - 2 * phi + moved(-h)) / h**2
    scale1 = max(1.0, np.max(np.abs(J) @ np.abs(v)))
    assert np.max(np.abs(d1 - phid)) < 1e-6 * scale1  # phi_q v + phi_t
    assert np.max(np.abs(d2 + gam)) < 1e-5 * max(1.0, np.max(np.abs(gam)))  # -gamma
    # phi_q columns by central differences (time fixed)
    hq = 1e-6
    for b in range(c.nb):
        for k in range(6):
            yp, ym = y.copy(), y.copy()
            if k < 3:
                yp[7 * b + k] += hq
                ym[7 * b + k] -= hq
            else:
                w = np.zeros(3)
                w[k - 3] = hq
                yp[7 * b + 3 : 7 * b + 7] = qmul(y[7 * b + 3 : 7 * b + 7], qexp(w))
                ym[7 * b + 3 : 7 * b + 7] = qmul(y[7 * b + 3 : 7 * b + 7], qexp(-w))
            col = (rows_at(c, yp, t0)[0] - rows_at(c, ym, t0)[0]) / (2 * hq)
            assert np.max(np.abs(col - J[:, 6 * b + k])) < 1e-6 * max(1.0, np.max(np.abs(J)))


def free_limb(rate_term=True):
    """A lumped limb (cylinder m1 + piston m2) whose length follows l(t); no gravity."""
    m1, m2, a1, a2 = 2.0, 1.5, 0.2, 0.2
    m_ = m1 + m2
    l = cl.Sinusoid(0.08, 6.0, 0.0, 0.7)
    J0 = (0.028 + 0.021, 0.028 + 0.021, 0.0015)
    var = InertiaVariation((m1 * m2 / m_, m1 * m2 / m_, 0.0), a1 + a2, l, rate_term=rate_term)
    m = cl.Mechanism("free limb", gravity=(0, 0, 0))
    m.add(cl.Body("limb", m_, J0, angular_velocity=(2.0, -1.0, 5.0), inertia_variation=var))
    return m, l, var, J0


@pytest.mark.parametrize("rate_term", [True, False])
def test_free_limb_angular_momentum(rate_term):
    m, l, var, J0 = free_limb(rate_term)
    r = cl.simulate(m, 2.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    assert r.success
    R = r.rotation("limb")
    wb = r.angular_velocity("limb", frame="body")
    H = []
    for k, t in enumerate(r.t):
        J = np.diag(J0) + np.diag(var.moments) * (l(t) - var.offset) ** 2
        H.append(R[k] @ J @ wb[k])
    H = np.array(H)
    drift = np.max(np.linalg.norm(H - H[0], axis=1)) / np.linalg.norm(H[0])
    if rate_term:
        assert drift < 1e-8  # exact equations: H conserved (physics.md i: 1e-11 in its check)
    else:
        assert drift > 1e-2  # dropping J'_dot omega' breaks conservation (physics.md i: 40 %)
    # the energy audit closes in both cases through W_L
    e = r.energy
    assert np.max(np.abs(e["residual"])) < 1e-8 * np.max(e["kinetic"])
    assert np.max(np.abs(e["work_inertia"])) > 1e-3 * np.max(e["kinetic"])  # W_L matters


def test_clearance_at_moving_attachment_energy_audit():
    """A ball centre that slides along its body axis (lumped-limb ball) rattles in a ground
    socket: the audit closes only with W_m, the work through the moving attachment."""
    m = cl.Mechanism("sliding ball", gravity=(0, 0, -9.81))
    slide = cl.Sinusoid(2e-4, 40.0, 0.0, 0.0)
    clr = cl.Clearance(
        ball_radius=0.01,
        radial_clearance=0.2e-3,
        normal=cl.Flores(restitution=0.8),
        friction=cl.Coulomb(mu=0.1),
    )
    m.add(
        cl.Body(
            "rod",
            1.0,
            (0.02, 0.02, 0.001),
            position=(0, 0, -0.25),
            angular_velocity=(1.0, 0.5, 0.0),
        ),
        cl.Marker("socket", "ground"),
        cl.Marker("ball", "rod", (0, 0, 0.25), slide_axis=(0, 0, 1), slide=slide),
        cl.Spherical("S", "socket", "ball", clearance=clr),
    )
    r = cl.simulate(m, 0.3, dt_out=1e-3, rtol=1e-9, atol=1e-12)
    assert r.success and len(r.impacts("S")) >= 1
    e = r.energy
    scale = np.max(np.abs(e["kinetic"]) + np.abs(e["potential"]))
    assert np.max(np.abs(e["residual"])) < 1e-6 * scale
    # without W_m the balance would be off by |W_m| ~ 2e-3 J, six decades above the residual
    assert np.max(np.abs(e["work_moving"])) > 1e3 * np.max(np.abs(e["residual"]))


def test_force_at_sliding_marker_is_refused():
    m = cl.Mechanism("x")
    m.add(
        cl.Body("b", 1.0),
        cl.Marker("s", "b", slide_axis=(0, 0, 1), slide=0.1),
        cl.PointForce("f", "s", (0, 0, 1)),
    )
    with pytest.raises(cl.ModelError, match="sliding"):
        cl.compile_mechanism(m)
