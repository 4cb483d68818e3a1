"""Classic validation mechanisms, built through the public model API.

Each factory returns a `clearance.Mechanism` whose initial pose is assembled and whose
initial velocities are consistent with the joints (computed here in closed form, so
`simulate`'s velocity projection leaves them unchanged). The docstrings sketch the model and
give the closed-form results the validation tests compare against.

Links are solid cylinders (`_rod_inertia`), so every inertia is a physical one (positive,
triangle inequality). Planar linkages lie in the world xy-plane with their joint axes along
world z; their default gravity is (0, -9.81, 0) m/s^2 (in the plane, IFToMM benchmark style).
"""

from __future__ import annotations

import math

import numpy as np

from clearance.model import (
    GROUND,
    Body,
    Marker,
    Mechanism,
    OrientationDriver,
    Prismatic,
    Revolute,
    Spherical,
    Torque,
    Universal,
    triad_from_axis,
)
from clearance.model.errors import ModelError
from clearance.model.functions import Polynomial, TimeFunction

_G_DOWN_Z = (0.0, 0.0, -9.81)
_G_DOWN_Y = (0.0, -9.81, 0.0)


# ---------------------------------------------------------------------------- helpers
def _rod_inertia(mass: float, length: float, radius: float, axis: int) -> tuple:
    """Principal moments [kg m^2] of a solid cylinder about its centre, `axis` = body axis
    (0, 1, 2) of the cylinder: axial m R^2 / 2, transverse m (3 R^2 + L^2) / 12."""
    transverse = mass * (3.0 * radius**2 + length**2) / 12.0
    moments = [transverse, transverse, transverse]
    moments[axis] = 0.5 * mass * radius**2
    return tuple(moments)


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _hanging_rotation(direction: np.ndarray) -> np.ndarray:
    """Rotation body -> world mapping body -z onto the unit vector `direction`."""
    return triad_from_axis(-np.asarray(direction, dtype=float))


def _positive(owner: str, **values: float) -> None:
    for name, x in values.items():
        if not (isinstance(x, (int, float)) and math.isfinite(x) and x > 0):
            raise ModelError(owner, name, x, "expected a finite number > 0")


def _crank_speed(owner: str, drive: str, speed: float) -> None:
    if drive not in ("speed", "torque"):
        raise ModelError(owner, "drive", drive, "allowed: 'speed' or 'torque'")
    if not math.isfinite(speed):
        raise ModelError(owner, "speed", speed, "expected a finite number [rad/s]")


# ---------------------------------------------------------------------------- pendulums
def spatial_pendulum(
    *,
    length: float = 1.0,
    mass: float = 1.0,
    radius: float = 0.01,
    theta0: float = math.pi / 2,
    angular_velocity: tuple = (0.0, 0.0, 0.0),
    joint: str = "spherical",
    pivot: tuple = (0.0, 0.0, 0.0),
    gravity: tuple = _G_DOWN_Z,
) -> Mechanism:
    """A uniform rod hanging from a spherical or revolute joint at its upper end.

    ::

              O  pivot (ground), joint "pivot"; revolute axis = world y
               \\
                \\  rod (body "rod", axis = body z, length L, mass m, radius R)
                 \\
                  *  tip            gravity (0, 0, -g)

    The rod starts at rest unless `angular_velocity` (world components [rad/s]) is given,
    deflected by `theta0` [rad] from the downward vertical by a rotation about world y (the
    swing plane is xz). The mass-centre velocity is w x (r_G - O). For joint="revolute" only
    the y component of w is compatible with the hinge (the rest is removed by the velocity
    projection of `simulate`). Markers: "pivot_ground" (ground), "pivot_rod" (rod end).

    Closed form (plane swing from rest): I_O = J'_yy + m d^2 with d = L/2,
    period T = 4 sqrt(I_O / (m g d)) K(k), k = sin(theta0 / 2) (K = complete elliptic
    integral of the first kind; scipy's ellipk takes k^2).
    """
    _positive("spatial_pendulum", length=length, mass=mass, radius=radius)
    if joint not in ("spherical", "revolute"):
        raise ModelError("spatial_pendulum", "joint", joint, "allowed: 'spherical', 'revolute'")
    o = np.asarray(pivot, dtype=float)
    c, s = math.cos(theta0), math.sin(theta0)
    A = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # Ry(theta0)
    arm = A @ np.array([0.0, 0.0, -0.5 * length])  # pivot -> mass centre, world
    w = np.asarray(angular_velocity, dtype=float)
    rod = Body(
        "rod",
        mass,
        _rod_inertia(mass, length, radius, axis=2),
        position=o + arm,
        orientation=A,
        velocity=np.cross(w, arm),
        angular_velocity=A.T @ w,
    )
    triad_w = triad_from_axis((0.0, 1.0, 0.0), (1.0, 0.0, 0.0))  # hinge axis h = world y
    mech = Mechanism(f"{joint} pendulum", gravity)
    mech.add(
        rod,
        Marker("pivot_ground", GROUND, o, triad_w),
        Marker("pivot_rod", "rod", (0.0, 0.0, 0.5 * length), A.T @ triad_w),  # same at t = 0
    )
    kind = Spherical if joint == "spherical" else Revolute
    mech.add(kind("pivot", "pivot_ground", "pivot_rod"))
    return mech.validate()


def double_pendulum(
    *,
    lengths: tuple = (1.0, 0.8),
    masses: tuple = (1.0, 0.7),
    radius: float = 0.02,
    directions: tuple = ((1.0, 0.0, -1.0), (0.3, 0.6, -1.0)),
    angular_velocities: tuple = ((0.0, 1.0, 0.5), (1.5, -0.5, 0.8)),
    pivot: tuple = (0.0, 0.0, 0.0),
    gravity: tuple = _G_DOWN_Z,
) -> Mechanism:
    """Two uniform rods chained by spherical joints: the spatial double pendulum (6 DOF, two
    of them the spins of the rods about their own axes).

    ::

        O ----S---- rod1 ----S(B)---- rod2 ---- tip       gravity (0, 0, -g)

    Rod k points from its upper joint along `directions[k]` (world, normalised); its body z
    axis points up the rod. `angular_velocities[k]` are world components [rad/s]; the
    mass-centre velocities follow from the joints (v_1 = w_1 x (r_1 - O), v_B = w_1 x (B - O),
    v_2 = v_B + w_2 x (r_2 - B)), so the initial state is exactly consistent. Joints "j1"
    (ground-rod1) and "j2" (rod1-rod2). No dissipation: T + V is conserved.
    """
    _positive("double_pendulum", radius=radius)
    for k in range(2):
        _positive("double_pendulum", **{f"lengths[{k}]": lengths[k], f"masses[{k}]": masses[k]})
    o = np.asarray(pivot, dtype=float)
    mech = Mechanism("spatial double pendulum", gravity)
    top = o
    v_top = np.zeros(3)
    prev = GROUND
    prev_marker_pos = o
    for k in range(2):
        u = np.asarray(directions[k], dtype=float)
        u = u / np.linalg.norm(u)
        A = _hanging_rotation(u)
        L = float(lengths[k])
        w = np.asarray(angular_velocities[k], dtype=float)
        arm = 0.5 * L * u
        name = f"rod{k + 1}"
        mech.add(
            Body(
                name,
                masses[k],
                _rod_inertia(masses[k], L, radius, axis=2),
                position=top + arm,
                orientation=A,
                velocity=v_top + np.cross(w, arm),
                angular_velocity=A.T @ w,
            ),
            Marker(f"{name}_top", name, (0.0, 0.0, 0.5 * L)),
            Marker(f"{name}_bottom", name, (0.0, 0.0, -0.5 * L)),
        )
        if prev == GROUND:
            mech.add(Marker("pivot_ground", GROUND, prev_marker_pos))
            mech.add(Spherical("j1", "pivot_ground", f"{name}_top"))
        else:
            mech.add(Spherical("j2", f"{prev}_bottom", f"{name}_top"))
        v_top = v_top + np.cross(w, 2.0 * arm)
        top = top + 2.0 * arm
        prev = name
    return mech.validate()


# ---------------------------------------------------------------------------- free body
def free_body(
    *,
    mass: float = 1.0,
    inertia: tuple = (1.0, 2.0, 2.5),
    angular_velocity: tuple = (0.3, 2.0, 0.5),
    velocity: tuple = (0.0, 0.0, 0.0),
    orientation: object = (1.0, 0.0, 0.0, 0.0),
    position: tuple = (0.0, 0.0, 0.0),
    gravity: tuple = (0.0, 0.0, 0.0),
) -> Mechanism:
    """One rigid body, no joints (body "body"), torque-free by default.

    ::

              w'   (initial spin, BODY components [rad/s])
              ^
          +---|---+    principal moments `inertia` (I1, I2, I3) along body x, y, z
          |   G   |    (or a full 3x3 tensor)
          +-------+

    Invariants without gravity: kinetic energy (1/2) w'.J'w' and the world angular momentum
    A J' w'. The default spin is near the intermediate axis (tumbling). For a symmetric body
    (I1 = I2) the body-frame spin precesses about body z at Omega = (I3 - I1) / I1 * w3:
    w'_1 + i w'_2 = (w'_1 + i w'_2)(0) exp(i Omega t), w'_3 constant.
    """
    _positive("free_body", mass=mass)
    body = Body(
        "body",
        mass,
        inertia,
        position=position,
        orientation=orientation,
        velocity=velocity,
        angular_velocity=angular_velocity,
    )
    return Mechanism("free body", gravity).add(body).validate()


# ---------------------------------------------------------------------------- linkages
def _planar_link(name: str, length: float, a: np.ndarray, b: np.ndarray) -> tuple:
    """A cylinder link from point a to point b in the xy-plane (body x along a -> b):
    (position, rotation) of its mass centre."""
    d = b - a
    phi = math.atan2(d[1], d[0])
    if abs(math.hypot(d[0], d[1]) - length) > 1e-9 * max(1.0, length):
        raise AssertionError(f"link {name}: end points {a}, {b} are not {length} apart")
    return 0.5 * (a + b), _rz(phi)


def _crank_drive(
    mech: Mechanism, drive: str, theta0: float, speed: float, torque: float | TimeFunction
) -> None:
    if drive == "speed":
        # R(t) = Rx(0) Ry(0) Rz(theta0 + speed t): the crank triad is the driven frame.
        angles = (0.0, 0.0, Polynomial((theta0, speed)))
        mech.add(OrientationDriver("crank_drive", "crank_pivot", angles, "xyz", "full"))
    elif not (isinstance(torque, (int, float)) and torque == 0):
        mech.add(Torque("crank_torque", "crank_pivot", (0.0, 0.0, 1.0), torque))


def _crank_joint(mech: Mechanism, drive: str, crank_joint: str | None) -> str:
    if crank_joint is None:
        crank_joint = "spherical" if drive == "speed" else "revolute"
    if crank_joint not in ("spherical", "revolute"):
        raise ModelError("linkage", "crank_joint", crank_joint, "allowed: 'spherical', 'revolute'")
    if crank_joint == "spherical" and drive != "speed":
        raise ModelError(
            "linkage",
            "crank_joint",
            crank_joint,
            "a spherical crank bearing needs drive='speed' (the driver supplies the hinge)",
        )
    kind = Spherical if crank_joint == "spherical" else Revolute
    mech.add(kind("crank_bearing", "crank_pivot_ground", "crank_pivot"))
    return crank_joint


def slider_crank(
    *,
    crank: float = 0.05,
    rod: float = 0.12,
    masses: tuple = (0.30, 0.21, 0.14),
    radius: float = 0.005,
    slider_size: float = 0.02,
    theta0: float = 0.0,
    speed: float = 2.0 * math.pi,
    drive: str = "speed",
    torque: float | TimeFunction = 0.0,
    crank_joint: str | None = None,
    gravity: tuple = _G_DOWN_Y,
) -> Mechanism:
    """Spatial model of the planar in-line slider-crank (Flores' link lengths and masses).

    ::

                  B (crank pin, S joint "pin")
                 / \\
          crank r   \\ rod l (coupler)
               /     \\
        O =(R)=       [ C ]=slider=  -> x   (P joint "slide" along world x,
                                             U joint "wrist" coupler-slider)

    Crank O-B (body "crank", length r) turns about world z at O = origin; coupler B-C (body
    "coupler", length l); slider (body "slider", cube) at C on the x axis. Joints: crank
    bearing to ground (Revolute, or Spherical, see below), Spherical at B, Universal at C
    (slider axis z, coupler cross axis = coupler body y, which stops the coupler's spin about
    B-C), Prismatic slider-ground. Without the driver this is 17 rows for 18 coordinates:
    1 DOF and no redundant rows.

    drive="speed": the crank angle is theta0 + speed t, imposed by a full `OrientationDriver`
    ("crank_drive") on the crank marker "crank_pivot". With the default
    crank_joint="spherical" the bearing plus driver give exactly 18 independent rows (0 DOF).
    crank_joint="revolute" repeats two rows of the driver (2 redundant rows; `simulate`'s
    solver="auto" then uses least squares).
    drive="torque": Revolute bearing, crank free with initial speed `speed` and an optional
    crank torque `torque` [N m] about +z ("crank_torque").

    Closed form (theta = crank angle): x_C = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta)),
    coupler angle phi = asin(-r sin(theta) / l). Requires l > r.
    """
    _positive("slider_crank", crank=crank, rod=rod, radius=radius, slider_size=slider_size)
    if not rod > crank:
        raise ModelError("slider_crank", "rod", rod, f"must exceed the crank length {crank}")
    _crank_speed("slider_crank", drive, speed)
    m1, m2, m3 = (float(x) for x in masses)
    _positive("slider_crank", **{"masses[0]": m1, "masses[1]": m2, "masses[2]": m3})
    r, L = float(crank), float(rod)
    c, s = math.cos(theta0), math.sin(theta0)
    S = math.sqrt(L * L - (r * s) ** 2)
    O = np.zeros(3)
    B = np.array([r * c, r * s, 0.0])
    C = np.array([r * c + S, 0.0, 0.0])
    # velocities (closed form, d/dt of the above with theta_dot = speed)
    w = float(speed)
    vB = np.array([-r * s * w, r * c * w, 0.0])
    vC = np.array([(-r * s - r * r * s * c / S) * w, 0.0, 0.0])
    w_coupler = -r * c * w / S  # phi_dot, from l sin(phi) = -r sin(theta)

    mech = Mechanism("slider-crank", gravity)
    pos, A1 = _planar_link("crank", r, O, B)
    mech.add(
        Body(
            "crank",
            m1,
            _rod_inertia(m1, r, radius, axis=0),
            position=pos,
            orientation=A1,
            velocity=0.5 * vB,
            angular_velocity=(0.0, 0.0, w),
        )
    )
    pos, A2 = _planar_link("coupler", L, B, C)
    mech.add(
        Body(
            "coupler",
            m2,
            _rod_inertia(m2, L, radius, axis=0),
            position=pos,
            orientation=A2,
            velocity=0.5 * (vB + vC),
            angular_velocity=(0.0, 0.0, w_coupler),
        )
    )
    cube = m3 * slider_size**2 / 6.0
    mech.add(Body("slider", m3, (cube, cube, cube), position=C, velocity=vC))
    x_axis = (1.0, 0.0, 0.0)
    mech.add(
        Marker("crank_pivot_ground", GROUND, O),
        Marker("crank_pivot", "crank", (-0.5 * r, 0.0, 0.0)),
        Marker("crank_pin", "crank", (0.5 * r, 0.0, 0.0)),
        Marker("coupler_B", "coupler", (-0.5 * L, 0.0, 0.0)),
        Marker.on_axis("coupler_C", "coupler", (0.5 * L, 0.0, 0.0), axis=(0.0, 1.0, 0.0)),
        Marker("slider_pin", "slider", (0.0, 0.0, 0.0)),
        Marker.on_axis("slide_ground", GROUND, O, axis=x_axis, f_hint=(0.0, 1.0, 0.0)),
        Marker.on_axis("slide_slider", "slider", (0.0, 0.0, 0.0), axis=x_axis, f_hint=(0, 1, 0)),
    )
    _crank_joint(mech, drive, crank_joint)
    mech.add(
        Spherical("pin", "crank_pin", "coupler_B"),
        Universal("wrist", "slider_pin", "coupler_C"),
        Prismatic("slide", "slide_ground", "slide_slider"),
    )
    _crank_drive(mech, drive, theta0, w, torque)
    return mech.validate()


def four_bar_pose(
    theta: float, crank: float, coupler: float, rocker: float, ground: float
) -> tuple[np.ndarray, np.ndarray]:
    """Open-branch (C above the line O-D) closure of the planar four-bar: points B, C (3,).

    O = origin, D = (ground, 0, 0); B = crank (cos theta, sin theta); C is the intersection of
    the circles |C - B| = coupler and |C - D| = rocker on the left of B -> D.
    Raises ModelError where the loop cannot close.
    """
    B = np.array([crank * math.cos(theta), crank * math.sin(theta), 0.0])
    D = np.array([ground, 0.0, 0.0])
    e = D - B
    dist = float(np.linalg.norm(e))
    a = (coupler**2 - rocker**2 + dist**2) / (2.0 * dist)
    h2 = coupler**2 - a * a
    if dist == 0.0 or h2 < 0.0:
        raise ModelError("four_bar", "theta", theta, "the loop does not close at this angle")
    u = e / dist
    n = np.array([-u[1], u[0], 0.0])
    return B, B + a * u + math.sqrt(h2) * n


def four_bar(
    *,
    crank: float = 0.1,
    coupler: float = 0.3,
    rocker: float = 0.25,
    ground: float = 0.3,
    masses: tuple = (0.2, 0.5, 0.4),
    radius: float = 0.005,
    theta0: float = 0.3,
    speed: float = 2.0 * math.pi,
    drive: str = "speed",
    torque: float | TimeFunction = 0.0,
    crank_joint: str | None = None,
    gravity: tuple = _G_DOWN_Y,
) -> Mechanism:
    """Spatial model of the planar four-bar O-B-C-D (default: Grashof crank-rocker).

    ::

                 B ------ coupler ------ C
                /                         \\
          crank                            rocker
              /                             \\
            O =(R)= - - - - ground - - - - =(R)= D  -> x

    Bodies "crank" (O-B), "coupler" (B-C), "rocker" (D-C); O = origin, D = (ground, 0, 0),
    all axes along world z. Joints: crank bearing (as in `slider_crank`), Spherical at B
    ("pin"), Universal at C ("wrist": rocker axis z, coupler cross axis = coupler body
    y), Revolute at D ("rocker_bearing"): 17 rows for 18 coordinates, 1 DOF, non-redundant.
    Assembled on the open branch of `four_bar_pose`; `drive` / `crank_joint` / `torque` as in
    `slider_crank`. The rocker angle is atan2(C_y, C_x - ground) of the closed form.
    """
    _positive("four_bar", crank=crank, coupler=coupler, rocker=rocker, ground=ground, radius=radius)
    _crank_speed("four_bar", drive, speed)
    m1, m2, m3 = (float(x) for x in masses)
    _positive("four_bar", **{"masses[0]": m1, "masses[1]": m2, "masses[2]": m3})
    B, C = four_bar_pose(theta0, crank, coupler, rocker, ground)
    O = np.zeros(3)
    D = np.array([ground, 0.0, 0.0])
    # velocities: w_b z x (C - B) - w_c z x (C - D) = -v_B (2 in-plane equations)
    w = float(speed)
    vB = np.cross([0.0, 0.0, w], B)
    zb, zc = np.cross([0.0, 0.0, 1.0], C - B), np.cross([0.0, 0.0, 1.0], C - D)
    w_b, w_c = np.linalg.solve(np.column_stack([zb[:2], -zc[:2]]), -vB[:2])
    vC = w_c * zc
    mech = Mechanism("four-bar", gravity)
    for name, m, length, a, b, va, vb, wz in (
        ("crank", m1, crank, O, B, np.zeros(3), vB, w),
        ("coupler", m2, coupler, B, C, vB, vC, w_b),
        ("rocker", m3, rocker, D, C, np.zeros(3), vC, w_c),
    ):
        pos, A = _planar_link(name, length, a, b)
        mech.add(
            Body(
                name,
                m,
                _rod_inertia(m, length, radius, axis=0),
                position=pos,
                orientation=A,
                velocity=0.5 * (va + vb),
                angular_velocity=(0.0, 0.0, wz),
            )
        )
    mech.add(
        Marker("crank_pivot_ground", GROUND, O),
        Marker("crank_pivot", "crank", (-0.5 * crank, 0.0, 0.0)),
        Marker("crank_pin", "crank", (0.5 * crank, 0.0, 0.0)),
        Marker("coupler_B", "coupler", (-0.5 * coupler, 0.0, 0.0)),
        Marker.on_axis("coupler_C", "coupler", (0.5 * coupler, 0.0, 0.0), axis=(0.0, 1.0, 0.0)),
        Marker("rocker_C", "rocker", (0.5 * rocker, 0.0, 0.0)),
        Marker("rocker_D", "rocker", (-0.5 * rocker, 0.0, 0.0)),
        Marker("rocker_pivot_ground", GROUND, D),
    )
    _crank_joint(mech, drive, crank_joint)
    mech.add(
        Spherical("pin", "crank_pin", "coupler_B"),
        Universal("wrist", "rocker_C", "coupler_C"),
        Revolute("rocker_bearing", "rocker_pivot_ground", "rocker_D"),
    )
    _crank_drive(mech, drive, theta0, w, torque)
    return mech.validate()


__all__ = [
    "double_pendulum",
    "four_bar",
    "four_bar_pose",
    "free_body",
    "slider_crank",
    "spatial_pendulum",
]
