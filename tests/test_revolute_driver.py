"""RevoluteDriver: a motor angle on a base revolute joint (the cranks of Delta / RUS legs).

Oracles: the z-x-z decomposition reproduces the triad (random rotations); a rod driven about
a horizontal axis needs the analytic motor torque I_O theta_ddot - m g (L/2) cos(theta); the
inverse kinematics reads the angle and its rates back exactly; the model refuses a driver
whose joint is not a revolute on the ground. (Rows and rhs against the NumPy reference:
test_reference_rhs.py, mechanism "revolute_drivers".)
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import clearance as cl
from clearance.analysis.ik import PlatformTrajectory, inverse_kinematics
from clearance.model.drivers import zxz_angles
from clearance.model.functions import HermiteSpline


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4))
def test_zxz_angles_reproduce_the_triad(q: list[float]) -> None:
    p = np.array(q) + np.array([1e-3, 0, 0, 0])
    p /= np.linalg.norm(p)
    T = cl.Body("b", 1.0, position=(0, 0, 0), orientation=tuple(p)).rotation
    psi, phi, chi = zxz_angles(T)
    assert np.allclose(_rz(psi) @ _rx(phi) @ _rz(chi), T, atol=1e-12)


@pytest.mark.parametrize("T", [np.eye(3), np.diag([1.0, -1.0, -1.0]), _rz(0.7) @ _rx(math.pi)])
def test_zxz_angles_on_the_z_axis(T: np.ndarray) -> None:
    psi, phi, chi = zxz_angles(T)
    assert np.allclose(_rz(psi) @ _rx(phi) @ _rz(chi), T, atol=1e-14)


M, L, G = 1.3, 0.4, 9.81
J_YY = M * L * L / 12.0  # about the mass centre, normal to the rod


def _driven_rod(theta) -> cl.Mechanism:
    """A rod of length L hinged at one end about world y, its angle from +x prescribed."""
    triad = np.column_stack([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])  # f = x, h = y
    th0 = theta(0.0) if callable(theta) else float(theta)
    R = triad @ _rz(th0)  # rod body axes: f along the rod, h along the hinge
    m = cl.Mechanism("driven rod", gravity=(0.0, 0.0, -G))
    m.add(
        cl.Body("rod", M, (1e-4, J_YY, J_YY), position=tuple(R @ [L / 2, 0, 0]), orientation=R),
        cl.Marker("hinge_g", cl.GROUND, (0, 0, 0), triad),
        # body x along the rod, body z along the hinge: the marker triad is the body's
        cl.Marker("hinge_r", "rod", (-L / 2, 0, 0)),
        cl.Revolute("R", "hinge_g", "hinge_r"),
        cl.RevoluteDriver("motor", "R", theta),
    )
    return m


def test_motor_torque_of_a_driven_rod() -> None:
    """F_act = I_O theta_ddot - m g (L/2) cos(theta): theta from +x towards -z (down)."""
    theta = cl.Sinusoid(0.8, 3.0, 0.2, 0.3)
    r = cl.simulate(_driven_rod(theta), 1.5, dt_out=0.01, rtol=1e-10, atol=1e-12)
    assert r.success, r.message
    th = theta.evaluate(r.t)
    expect = (J_YY + M * (L / 2) ** 2) * th[:, 2] - M * G * (L / 2) * np.cos(th[:, 0])
    got = r.actuator_force("motor")
    assert np.max(np.abs(got - expect)) < 1e-7 * np.max(np.abs(expect))
    # the rod follows the angle: its direction is (cos th, 0, -sin th)
    d = r.rotation("rod")[:, :, 0]
    assert (
        np.max(np.abs(d - np.column_stack([np.cos(th[:, 0]), 0 * th[:, 0], -np.sin(th[:, 0])])))
        < 1e-9
    )


def test_inverse_kinematics_reads_the_angle() -> None:
    """Prescribing the rod tip's height z = -L sin(theta(t)) (a quintic Hermite spline
    through its exact values and rates) gives theta and its rates back at the knots."""
    theta = cl.Sinusoid(0.3, 2.0, 0.0, 0.6)
    mech = _driven_rod(0.6)
    mech.add(cl.Marker("tip", "rod", (L / 2, 0, 0)))
    ts = np.linspace(0.0, 1.0, 21)
    th = theta.evaluate(ts)
    a, ad, add = th[:, 0], th[:, 1], th[:, 2]
    z = HermiteSpline(
        tuple(ts),
        tuple(-L * np.sin(a)),
        tuple(-L * np.cos(a) * ad),
        tuple(L * np.sin(a) * ad**2 - L * np.cos(a) * add),
    )
    tr = PlatformTrajectory(0.0, 0.0, z, mode="none", positions=("z",))
    ik = inverse_kinematics(mech, tr, platform_marker="tip", actuators=["motor"], times=ts)
    assert np.max(np.abs(ik.s[:, 0] - a)) < 1e-10
    assert np.max(np.abs(ik.s_dot[:, 0] - ad)) < 1e-9
    assert np.max(np.abs(ik.s_ddot[:, 0] - add)) < 1e-8


def test_revolute_driver_refusals() -> None:
    m = _driven_rod(0.3)
    m.add(
        cl.Body("b", 1.0, position=(0, 0, 1)),
        cl.Marker("b1", "b"),
        cl.Marker("r1", "rod"),
        cl.Revolute("R2", "r1", "b1"),
    )
    with pytest.raises(cl.ModelError, match="marker i on the ground"):
        m.copy().add(cl.RevoluteDriver("m2", "R2", 0.0))
    m.add(cl.Marker("g2", cl.GROUND), cl.Spherical("S2", "g2", "b1"))
    with pytest.raises(cl.ModelError, match="needs a Revolute or Cylindrical"):
        m.copy().add(cl.RevoluteDriver("m3", "S2", 0.0))
    with pytest.raises(cl.ModelError, match="unknown joint"):
        m.copy().add(cl.RevoluteDriver("m4", "nope", 0.0))
