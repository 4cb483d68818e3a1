"""Small mechanisms shared by several test modules."""

from __future__ import annotations

import numpy as np

import clearance as cl


def rod_on_clearance_joint(
    normal, friction, *, ball_radius=0.01, clearance=1e-4, theta=0.5, spin=(0.3, 0.0, 0.5)
) -> cl.Compiled:
    """A 1 kg, 0.5 m rod hanging from a spherical clearance joint at the origin, tilted by
    theta about y and spinning: it swings and rattles (tens of impacts in 0.05 s)."""
    L = 0.5
    R = np.array([[np.cos(theta), 0, np.sin(theta)], [0, 1, 0], [-np.sin(theta), 0, np.cos(theta)]])
    m = cl.Mechanism("rod on a clearance joint")
    m.add(
        cl.Body(
            "rod",
            1.0,
            (0.0209, 0.0209, 0.0002),
            position=R @ [0, 0, -L / 2],
            orientation=R,
            angular_velocity=spin,
        ),
        cl.Marker("socket", "ground"),
        cl.Marker("ball", "rod", (0, 0, L / 2)),
        cl.Spherical(
            "S",
            "socket",
            "ball",
            clearance=cl.Clearance(
                ball_radius=ball_radius,
                radial_clearance=clearance,
                normal=normal,
                friction=friction,
            ),
        ),
    )
    return cl.compile_mechanism(m)
