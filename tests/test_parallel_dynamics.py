"""Actuator forces of the builder's mechanisms against an independent oracle.

tests/oracles/parallel_dynamics.py (numpy + scipy only, written from a specification
without the package sources) computes them by virtual power from closed-form leg inverse
kinematics: the static forces from the gradient of the potential energy (virtual work),
the forces along a motion from d'Alembert's principle (Kane). The package computes them as
Lagrange multipliers of the drivers in a forward simulation driven by its own inverse
kinematics. The oracle is given the platform's motion (pose, twist, accelerations) as the
package's result has it (the IK kinematics, which tests/test_parallel.py checks against the
prescribed trajectory).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import parallel_dynamics as oracle
from test_parallel import CARRIAGE, delta, pss_upu, rod, sps_cu_builder, three, ups_upu_builder

import clearance as cl
from clearance.analysis.ik import PlatformTrajectory, drives_from_ik, inverse_kinematics
from clearance.parallel import Leg, ParallelMechanism

# Tsai's 6-UPS example (L.-W. Tsai, J. Mech. Des. 122(1):3-9, 2000), as read in the public
# MATLAB code houchangmeng/Stewart-Platform-Related-Code (example_inverse_dynamics.m, which
# cites the paper): base points B_i, platform points P_i (from the platform's mass centre),
# platform 1.5 kg, diag(0.08) kg m^2; each leg two parts of 0.1 kg, diag(1/160) kg m^2,
# mass centres 0.5 m from the U and from the S; g = 9.80665 m/s^2; motion pattern 1:
# centre (-1.5 + 0.2 sin 3t, 0.2 sin 3t, 1 + 0.2 sin 3t). The paper's printed force
# curves could not be read here: the comparison is with the oracle (Tsai's own method,
# virtual work, implemented independently).
TSAI_BASE = [
    (-2.12, 1.374, 0.0),
    (-2.38, 1.224, 0.0),
    (-2.38, -1.224, 0.0),
    (-2.12, -1.374, 0.0),
    (0.0, -0.15, 0.0),
    (0.0, 0.15, 0.0),
]
TSAI_PLATFORM = [
    (0.17, 0.595, -0.4),
    (-0.6, 0.15, -0.4),
    (-0.6, -0.15, -0.4),
    (0.17, -0.595, -0.4),
    (0.43, -0.445, -0.4),
    (0.43, 0.445, -0.4),
]


def tsai_stewart() -> ParallelMechanism:
    part = cl.Link(0.1, (1 / 160, 1 / 160, 1 / 160), com=0.5)
    return ParallelMechanism(
        "6-UPS (Tsai 2000)",
        cl.Platform(1.5, (0.08, 0.08, 0.08), position=(-1.5, 0.0, 1.0)),
        cl.legs("UPS", base=TSAI_BASE, platform=TSAI_PLATFORM, links=(part, part)),
        gravity=(0.0, 0.0, -9.80665),
    )


def _axis(leg: Leg) -> np.ndarray:
    """The leg's reference axis t by the documented convention."""
    if leg.axis is not None:
        return np.array(leg.axis)
    A = np.array(leg.base)
    r = math.hypot(A[0], A[1])
    return np.array([-A[1] / r, A[0] / r, 0.0]) if r > 1e-12 else np.array([1.0, 0.0, 0.0])


def oracle_spec(pm: ParallelMechanism) -> dict:
    """The oracle's plain description of a builder mechanism (two-body limbs)."""
    legs = []
    for leg in pm.legs:
        d = {
            "type": leg.joints,
            "A": leg.base,
            "B": leg.platform,
            "t": tuple(_axis(leg)),
            "links": [
                {"mass": k.mass, "inertia": k.inertia, "com": k.com, "length": k.length}
                for k in leg.links
            ],
            "actuated": leg.actuated is not None,
            "parallelogram": leg.parallelogram,
            "knee": leg.knee or ("out" if leg.shape == "crank" else "down"),
        }
        if leg.shape == "rail":
            d["rail"] = leg.rail or (0.0, 0.0, 1.0)
            d["home_travel"] = 0.0  # (an offset of q: no effect on its force)
        if leg.joints == "CU":
            d["rail"] = (0.0, 0.0, 1.0)
        legs.append(d)
    return {
        "gravity": pm.gravity,
        "platform": {"mass": pm.platform.mass, "inertia": pm.platform.inertia},
        "legs": legs,
    }


def _g(amplitude: float, centre: float = 0.0) -> cl.Sinusoid:
    return cl.Sinusoid(-0.5 * amplitude, math.pi, 0.5 * math.pi, centre + 0.5 * amplitude)


def _s(amplitude: float, centre: float = 0.0, omega: float = 3.0) -> cl.Sinusoid:
    return cl.Sinusoid(amplitude, omega, 0.0, centre)


# mechanism, trajectory (x, y, z, angles, sequence, mode, positions)
CASES = {
    "6-UPS Tsai": (
        tsai_stewart,
        (_s(0.2, -1.5), _s(0.2), _s(0.2, 1.0), (0, 0, 0), "xyz", "full", "xyz"),
    ),
    "4UPS-UPU": (
        ups_upu_builder,
        (_g(0.02), _g(0.02), _g(0.03, 0.7), (_g(0.05), _g(0.05), 0), "xyz", "axis", "xyz"),
    ),
    "4-SPS/CU": (
        lambda: sps_cu_builder(False),
        (0, 0, _g(0.05, 0.6), (_g(0.1), _g(0.05), _g(0.05)), "zxy", "full", "xyz"),
    ),
    "3-RPS": (
        lambda: three("RPS", (rod(0.3), rod(0.3))),
        (0, 0, _g(0.03, 0.5), (_g(0.05), _g(0.05), 0), "xyz", "axis", "z"),
    ),
    "3-PRS": (
        lambda: three("PRS", (CARRIAGE, rod(0.45))),
        (0, 0, _g(0.03, 0.5), (_g(0.05), _g(-0.04), 0), "xyz", "axis", "z"),
    ),
    "5-PSS/UPU": (
        pss_upu,
        (_g(0.02), _g(-0.01), _g(0.02, 0.6), (_g(0.05), _g(0.03), 0), "xyz", "axis", "xyz"),
    ),
    "Delta": (
        lambda: delta(parallelogram=0.06),
        (_g(0.03), _g(0.02), _g(0.02, -0.45), (0, 0, 0), "xyz", "none", "xyz"),
    ),
}


def _platform_motion(r: cl.Result, k: int):
    """(p, R, v, w, a, alpha) of the platform at sample k, world frame."""
    R = r.rotation("platform")[k]
    kb = r.compiled.body_names.index("platform")
    alpha = R @ r.a[k, 6 * kb + 3 : 6 * kb + 6]
    return (
        r.position("platform")[k],
        R,
        r.velocity("platform")[k],
        r.angular_velocity("platform")[k],
        r.acceleration("platform")[k],
        alpha,
    )


@pytest.mark.parametrize("name", list(CASES))
def test_static_actuator_forces_equal_virtual_work(name: str) -> None:
    """At rest at home: the drivers' multipliers = the gradient of the potential energy
    along the admissible motions (virtual work), in the actuator coordinates."""
    pm = CASES[name][0]()
    r = cl.simulate(pm.build(), 1e-6, t_out=np.array([0.0]), rtol=1e-10, atol=1e-12)
    F = np.array([r.actuator_force(a)[0] for a in pm.actuators])
    p = np.array(pm.platform.position)
    F_ref = oracle.static_actuator_forces(oracle_spec(pm), p, np.eye(3))
    assert np.max(np.abs(F - F_ref)) < 1e-7 * np.max(np.abs(F_ref)), (F, F_ref)


@pytest.mark.parametrize("name", list(CASES))
def test_actuator_forces_along_a_motion_equal_inverse_dynamics(name: str) -> None:
    """Forward dynamics driven by the IK drives: the actuator forces at 5 instants equal the
    oracle's inverse dynamics (d'Alembert) for the platform motion of the result."""
    make, (x, y, z, angles, seq, mode, pos) = CASES[name]
    pm = make()
    tr = PlatformTrajectory(x, y, z, angles=angles, sequence=seq, mode=mode, positions=tuple(pos))
    T = 1.0
    ik = inverse_kinematics(
        pm.build(),
        tr,
        platform_marker=pm.platform_marker,
        actuators=pm.actuators,
        times=np.linspace(0.0, T, 101),
    )
    r = cl.simulate(pm.build(drives_from_ik(ik)), T, dt_out=0.05, rtol=1e-11, atol=1e-13)
    assert r.success, r.message
    spec = oracle_spec(pm)
    for k in range(0, r.t.size, 4):
        F = np.array([r.actuator_force(a)[k] for a in pm.actuators])
        F_ref = oracle.actuator_forces(spec, *_platform_motion(r, k))
        scale = np.max(np.abs(F_ref))
        assert np.max(np.abs(F - F_ref)) < 1e-7 * scale, (r.t[k], F, F_ref)
