"""Drivers: prescribed motion is followed, and actuator forces have the documented sign and
the value Newton's law demands (independent oracle: m (a - g) of the driven body)."""

import numpy as np

import clearance as cl


def Rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def Rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def test_prismatic_lift_force_sign_and_value():
    """A 3 kg slider on a vertical prismatic joint, driven s(t) = 0.2 + 0.05 sin(4t):
    F_act = m (g + s_ddot) > 0 pushes it up along +h."""
    m_, g = 3.0, 9.81
    s = cl.Sinusoid(0.05, 4.0, 0.0, 0.2)
    mech = cl.Mechanism("lift", gravity=(0, 0, -g))
    mech.add(
        cl.Body("slider", m_, (0.01, 0.01, 0.01), position=(0, 0, 0.2)),
        cl.Marker.on_axis("g", "ground", axis=(0, 0, 1)),
        cl.Marker.on_axis("b", "slider", axis=(0, 0, 1)),
        cl.Prismatic("p", "g", "b"),
        cl.PrismaticDriver("lift", "p", s),
    )
    r = cl.simulate(mech, 1.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    assert r.success
    sdd = np.array([s.derivatives(t)[2] for t in r.t])
    z = np.array([s(t) for t in r.t])
    assert np.max(np.abs(r.position("slider")[:, 2] - z)) < 1e-9
    F = r.actuator_force("lift")
    assert np.max(np.abs(F - m_ * (g + sdd))) < 1e-7 * m_ * g
    # the driver does the work that raises the slider: W_d = Delta(T + V)
    e = r.energy
    dE = e["kinetic"] + e["potential"] - e["kinetic"][0] - e["potential"][0]
    assert np.max(np.abs(e["work_drivers"] - dE)) < 1e-8


def test_pose_drivers_follow_trajectory_and_hold_weight():
    """Position + full orientation drivers prescribe all 6 DOF of a free body: the body
    follows (x, y, z)(t) and Rx Ry Rz(t) exactly; the position-driver forces equal m (a - g)."""
    m_, g = 2.0, 9.81
    xs = [
        cl.Sinusoid(0.1, 2.0, 0.0, 0.0),
        cl.Sinusoid(0.05, 3.0, 0.5, 0.1),
        cl.Sinusoid(0.02, 5.0, 0.0, 1.0),
    ]
    angs = [
        cl.Sinusoid(0.3, 2.0, 0.0, 0.1),
        cl.Sinusoid(0.2, 1.5, 0.3, 0.0),
        cl.Sinusoid(0.4, 1.0, 0.0, 0.2),
    ]
    mech = cl.Mechanism("pose", gravity=(0, 0, -g))
    mech.add(cl.Body("b", m_, (0.02, 0.03, 0.04), position=(0, 0.1, 1.0)), cl.Marker("m", "b"))
    for k, ax in enumerate(np.eye(3)):
        mech.add(cl.PositionDriver(f"x{k}", "m", ax, xs[k]))
    mech.add(cl.OrientationDriver("rot", "m", angs, sequence="xyz", mode="full"))
    c = cl.compile_mechanism(mech)
    y0 = cl.assemble(c)
    assert cl.rank_check(c, 0.0, y0).dof == 0
    r = cl.simulate(c, 1.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    assert r.success
    pos = np.array([[f(t) for f in xs] for t in r.t])
    acc = np.array([[f.derivatives(t)[2] for f in xs] for t in r.t])
    assert np.max(np.abs(r.position("b") - pos)) < 1e-9
    R_target = np.array([Rx(angs[0](t)) @ Ry(angs[1](t)) @ Rz(angs[2](t)) for t in r.t])
    assert np.max(np.abs(r.rotation("b") - R_target)) < 1e-9
    F = np.column_stack([r.actuator_force(f"x{k}") for k in range(3)])
    assert np.allclose(F, m_ * (acc - np.array([0, 0, -g])), atol=1e-6)


def test_orientation_axis_mode_leaves_twist_free():
    """mode='axis' prescribes only h = R(t) e_z (2 rows): the spin about h keeps its initial
    rate (no torque about h for an axisymmetric body) while h follows the target."""
    mech = cl.Mechanism("tilt", gravity=(0, 0, 0))
    a1, a2 = cl.Sinusoid(0.2, 2.0, 0.0, 0.0), cl.Sinusoid(0.1, 3.0, 0.0, 0.0)
    mech.add(
        cl.Body("b", 1.0, (0.02, 0.02, 0.01), angular_velocity=(0, 0, 1.5)), cl.Marker("m", "b")
    )
    for k, ax in enumerate(np.eye(3)):
        mech.add(cl.PositionDriver(f"x{k}", "m", ax, 0.0))
    mech.add(cl.OrientationDriver("tilt", "m", (a1, a2, 0.0), mode="axis"))
    c = cl.compile_mechanism(mech)
    assert c.nrow == 5
    r = cl.simulate(c, 1.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    h = r.rotation("b")[:, :, 2]
    h_target = np.array([Rx(a1(t)) @ Ry(a2(t)) @ [0, 0, 1] for t in r.t])
    assert np.max(np.abs(h - h_target)) < 1e-9
    # the twist is free: the dot-1 rows exert torques perpendicular to h only, and Euler's
    # equation of an axisymmetric body about its axis gives I3 w3_dot = 0, so w3 stays 1.5
    assert np.max(np.abs(r.angular_velocity("b", frame="body")[:, 2] - 1.5)) < 1e-8
