"""General inverse kinematics of parallel mechanisms and actuator drives (physics.md e.2).

A prescribed platform trajectory becomes actuator displacement histories by the package's own
kinematic analysis (physics.md e.1), never by a mechanism-specific formula:

1. the actuator drivers (`PrismaticDriver`s of the legs, `RevoluteDriver`s of base-mounted
   motors) are removed (`Mechanism.without`);
2. pose drivers are put on a platform marker: three `PositionDriver`s x(t), y(t), z(t)
   (world coordinates of the marker point) and one `OrientationDriver` (mode "axis": only
   the marker's h axis = platform normal, two tilts, twist left to the mechanism, as the
   UPU leg of the 4UPS-UPU imposes it; mode "full": all three angles, e.g. the
   Rz(psi) Rx(t1) Ry(t2) of the 4-SPS/CU, sequence "zxy");
3. at each time the position (minimum-norm Newton, warm-started from a second-order
   prediction of the previous sample), velocity and acceleration analyses are solved;
4. each actuator's displacement s = h_i . d is read with the removed driver's own row
   (the original mechanism compiled with f = 0), and its rates with the read-out formulas
   s_dot = g_q v + g_t, s_ddot = g_q v_dot - gamma_g (physics.md e.1): exact, no finite
   differences; a motor angle (RevoluteDriver) is read from the triads, theta =
   atan2(g_i . f_j, f_i . f_j), with theta_dot = h_i . omega_j, theta_ddot = h_i . alpha_j;
5. `drives_from_ik` turns (s, s_dot, s_ddot) into C2 quintic `HermiteSpline`s and
   `apply_drives` puts them into the (ideal or clearance) mechanism.

Along the way the drive Jacobian (the constraint Jacobian of the ideal mechanism WITH the
actuator drivers, platform pose free) is checked: its smallest singular value and condition
number are recorded, and a scenario whose drive Jacobian is (nearly) singular, or whose
determinant changes sign between two samples (a singular configuration passed in between),
is refused with a `KinematicsError` naming the time and the legs (actuators) that take part
in the dependency (mechanisms.md 1.4 singularity note).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from clearance.analysis.assembly import (
    acceleration_analysis,
    apply_position_increment,
    assemble,
    evaluate_rows,
    velocity_analysis,
)
from clearance.compile.compiled import Compiled, compile_mechanism
from clearance.model.bodies import GROUND, Marker, quaternion_to_rotation
from clearance.model.drivers import (
    OrientationDriver,
    PositionDriver,
    PrismaticDriver,
    RevoluteDriver,
)
from clearance.model.errors import KinematicsError, ModelError
from clearance.model.functions import Constant, HermiteSpline, Sinusoid, TimeFunction, as_function
from clearance.model.mechanism import Mechanism

__all__ = [
    "IKResult",
    "PlatformTrajectory",
    "apply_drives",
    "drives_from_ik",
    "inverse_kinematics",
    "rest_to_rest",
    "rotation_from_angles",
]

_AXES = {"x": 0, "y": 1, "z": 2}
SHAPES = ("cosine", "sin")
ORIENTATION_MODES = ("full", "axis", "none")


def _rot(axis: int, th: float) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def rotation_from_angles(sequence: str, angles: Sequence[float]) -> np.ndarray:
    """R = R_a(t1) R_b(t2) R_c(t3) for sequence "abc" (rotations about moving axes) [rad]."""
    R = np.eye(3)
    for c, th in zip(sequence, angles, strict=True):
        R = R @ _rot(_AXES[c], float(th))
    return R


@dataclass(frozen=True)
class PlatformTrajectory:
    """Prescribed pose of a platform marker (physics.md e.2 step 2).

    x, y, z: world coordinates [m] of the marker point. angles: three angle functions [rad]
    giving the target rotation R(t) = R_a(t1) R_b(t2) R_c(t3) for sequence "abc". mode
    "axis": only the marker's h axis is prescribed, h = R(t) e_z (two tilts; the rotation
    about h, the twist, is left to the mechanism, e.g. the 4UPS-UPU's UPU leg; for
    sequence "xyz" and angles (alpha, beta, 0) this is the normal of Rx(alpha) Ry(beta)).
    mode "full": the marker triad is R(t) (e.g. 4-SPS/CU: sequence "zxy", angles
    (psi, t1, t2)); mode "none": the orientation is left to the mechanism (a Delta robot's
    platform translates). positions: the coordinates of the point that are prescribed
    (default all three); the others are left to the mechanism (a 3-RPS prescribes z and
    the two tilts; its x, y and twist follow). Numbers are accepted for constant functions.
    """

    x: TimeFunction
    y: TimeFunction
    z: TimeFunction
    angles: tuple = (0.0, 0.0, 0.0)
    sequence: str = "xyz"
    mode: str = "axis"
    positions: tuple = ("x", "y", "z")

    def __post_init__(self) -> None:
        who = "PlatformTrajectory"
        for name in ("x", "y", "z"):
            object.__setattr__(self, name, as_function(getattr(self, name), owner=who, field=name))
        if self.mode not in ORIENTATION_MODES:
            raise ModelError(who, "mode", self.mode, f"allowed: {ORIENTATION_MODES}")
        # OrientationDriver validates sequence and angles with named messages
        mode = "full" if self.mode == "none" else self.mode
        od = OrientationDriver("trajectory", "platform", self.angles, self.sequence, mode)
        object.__setattr__(self, "angles", od.angles)
        pos = self.positions
        if isinstance(pos, str) or not all(p in _AXES for p in pos) or len(set(pos)) != len(pos):
            raise ModelError(who, "positions", pos, "expected distinct names from 'x', 'y', 'z'")
        object.__setattr__(self, "positions", tuple(p for p in "xyz" if p in pos))

    @property
    def nrows(self) -> int:
        """Number of prescribed pose coordinates (the platform DOF it drives)."""
        return len(self.positions) + {"full": 3, "axis": 2, "none": 0}[self.mode]

    def position(self, t: float) -> np.ndarray:
        """(3,) prescribed marker point, world frame [m]."""
        return np.array([self.x(t), self.y(t), self.z(t)])

    def velocity(self, t: float) -> np.ndarray:
        """(3,) prescribed point velocity [m/s]."""
        return np.array([f.derivatives(t)[1] for f in (self.x, self.y, self.z)])

    def rotation(self, t: float) -> np.ndarray:
        """(3, 3) target rotation R(t) of the angle functions (full triad, even in "axis")."""
        return rotation_from_angles(self.sequence, [a(t) for a in self.angles])

    def normal(self, t: float) -> np.ndarray:
        """(3,) prescribed marker h axis R(t) e_z (platform normal), world frame."""
        return self.rotation(t)[:, 2]


def _shape_fn(shape: str, center: float, amplitude: float, omega: float) -> TimeFunction:
    if amplitude == 0.0:
        return Constant(center)
    if shape == "cosine":  # center + amplitude (1 - cos(omega t)) / 2
        return Sinusoid(-0.5 * amplitude, omega, 0.5 * math.pi, center + 0.5 * amplitude)
    return Sinusoid(amplitude, omega, 0.0, center)  # center + amplitude sin(omega t)


def rest_to_rest(
    center: Sequence[float],
    amplitudes: Sequence[float],
    angles: Sequence[float],
    duration: float = 2.0,
    *,
    shape: str = "cosine",
    sequence: str = "xyz",
    mode: str = "axis",
    angle_offsets: Sequence[float] = (0.0, 0.0, 0.0),
) -> PlatformTrajectory:
    """Trajectory p(t) = center + amplitudes g(t), angles_k(t) = offset_k + angles_k g(t).

    center: (3,) [m] pose at g = 0; amplitudes: (3,) [m]; angles: (3,) angle amplitudes
    [rad] for `sequence`/`mode` (see PlatformTrajectory). The period is `duration` T [s]:

    * shape "cosine" (default, rest to rest): g(t) = (1 - cos(2 pi t / T)) / 2: at rest at
      the center for t = 0 and t = T, at the extreme pose (g = 1) at t = T / 2;
    * shape "sin": g(t) = sin(2 pi t / T) (starts with velocity 2 pi / T * amplitude).

    With T = 2 s these are the reference's g(t) = (1 - cos(pi t)) / 2 and sin(pi t) over
    t in [0, 2] s (mechanisms.md 1.5 and 2.3). Outside [0, T] the motion repeats.
    """
    who = "rest_to_rest"
    if shape not in SHAPES:
        raise ModelError(who, "shape", shape, f"allowed: {SHAPES}")
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
        raise ModelError(who, "duration", duration, "expected a finite period > 0 [s]")
    vals = {}
    for name, v in (
        ("center", center),
        ("amplitudes", amplitudes),
        ("angles", angles),
        ("angle_offsets", angle_offsets),
    ):
        a = np.asarray(v, dtype=float)
        if a.shape != (3,) or not np.all(np.isfinite(a)):
            raise ModelError(who, name, v, "expected 3 finite numbers")
        vals[name] = a
    w = 2.0 * math.pi / duration
    pos = [
        _shape_fn(shape, float(c), float(a), w)
        for c, a in zip(vals["center"], vals["amplitudes"], strict=True)
    ]
    ang = tuple(
        _shape_fn(shape, float(c), float(a), w)
        for c, a in zip(vals["angle_offsets"], vals["angles"], strict=True)
    )
    return PlatformTrajectory(*pos, angles=ang, sequence=sequence, mode=mode)


@dataclass(frozen=True)
class IKResult:
    """Inverse kinematics along a trajectory (n samples, na actuators).

    times (n,) [s]; actuators: names of the replaced PrismaticDrivers; s, s_dot, s_ddot
    (n, na): actuator displacements h_i . d [m] and their exact rates [m/s, m/s^2].
    position (n, 3) [m] and rotation (n, 3, 3) (columns f, g, h, world frame) of the
    platform marker; twist (n,) [rad]: rotation about the platform normal from the
    trajectory's full target R(t) to the solved triad, R(t)^T R_solved = Rz(twist) (the
    parasitic twist in mode "axis", ~0 in mode "full"). y (n, ny): assembled states of the
    ideal mechanism (q, v; layout of `compiled`); a (n, nv): accelerations (r_ddot, omega'
    dot). sigma_min, condition (n,): smallest singular value and 2-norm condition number of
    the drive Jacobian (constraint Jacobian with the actuator drivers, idle DOF such as S-S
    limb spins excluded); idle_dof: their number. compiled: the ideal mechanism with the
    actuator drivers (functions set to 0: its driver rows read s).
    """

    times: np.ndarray
    actuators: tuple
    s: np.ndarray
    s_dot: np.ndarray
    s_ddot: np.ndarray
    position: np.ndarray
    rotation: np.ndarray
    twist: np.ndarray
    y: np.ndarray = field(repr=False)
    a: np.ndarray = field(repr=False)
    sigma_min: np.ndarray = field(repr=False)
    condition: np.ndarray = field(repr=False)
    idle_dof: int = 0
    compiled: Compiled | None = field(default=None, repr=False)

    @property
    def min_sigma(self) -> float:
        """Smallest singular value of the drive Jacobian along the trajectory."""
        return float(np.min(self.sigma_min))

    @property
    def max_condition(self) -> float:
        """Largest condition number of the drive Jacobian along the trajectory."""
        return float(np.max(self.condition))

    def actuator(self, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(s, s_dot, s_ddot) histories of one actuator."""
        k = self.actuators.index(name)
        return self.s[:, k], self.s_dot[:, k], self.s_ddot[:, k]

    def summary(self) -> str:
        lines = [
            f"inverse kinematics: {self.times.size} samples in [{self.times[0]:.6g}, "
            f"{self.times[-1]:.6g}] s; drive Jacobian sigma_min >= {self.min_sigma:.4g}, "
            f"condition <= {self.max_condition:.4g}; idle DOF {self.idle_dof}; "
            f"max |twist| {np.max(np.abs(self.twist)):.4g} rad"
        ]
        for k, name in enumerate(self.actuators):
            lines.append(
                f"  {name}: s in [{self.s[:, k].min():.6f}, {self.s[:, k].max():.6f}] m, "
                f"max |s_dot| {np.abs(self.s_dot[:, k]).max():.4g} m/s, "
                f"max |s_ddot| {np.abs(self.s_ddot[:, k]).max():.4g} m/s^2"
            )
        return "\n".join(lines)


def _ideal(mech: Mechanism) -> Mechanism:
    """A copy whose spherical clearance joints are ideal again (IK is on the ideal model)."""
    m = mech.copy()
    for name, jt in mech.joints.items():
        if getattr(jt, "clearance", None) is not None:
            m = m.with_clearance(name, None)
    return m


def _unique(mech: Mechanism, base: str) -> str:
    names = {*mech.bodies, *mech.markers, *mech.joints, *mech.drivers, *mech.forces, GROUND}
    name, k = base, 1
    while name in names:
        name, k = f"{base}_{k}", k + 1
    return name


# drivers that can be actuators: a joint coordinate (slider travel, motor angle)
ACTUATOR_DRIVERS = (PrismaticDriver, RevoluteDriver)


def _check_actuators(mech: Mechanism, actuators: Sequence[str]) -> tuple[str, ...]:
    who = "inverse_kinematics"
    if isinstance(actuators, str) or not len(actuators):
        raise ModelError(
            who, "actuators", actuators, "expected a list of PrismaticDriver / RevoluteDriver names"
        )
    acts = tuple(actuators)
    prism = [n for n, d in mech.drivers.items() if isinstance(d, ACTUATOR_DRIVERS)]
    for a in acts:
        if a not in prism:
            raise ModelError(
                who, "actuators", a, f"not a PrismaticDriver or RevoluteDriver; known: {prism}"
            )
    if len(set(acts)) != len(acts):
        raise ModelError(who, "actuators", acts, "names must not repeat")
    return acts


def _platform_marker(mech: Mechanism, name: str) -> tuple[Mechanism, str]:
    """(mechanism, marker name): a body name gets a marker at its origin with its axes."""
    who = "inverse_kinematics"
    if name in mech.markers:
        mk = mech.markers[name]
        if mk.body == GROUND:
            raise ModelError(who, "platform_marker", name, "is on the ground")
        if getattr(mk, "slide", None) is not None:
            raise ModelError(who, "platform_marker", name, "must be a fixed (non-sliding) point")
        return mech, name
    if name in mech.bodies:
        mname = _unique(mech, f"{name}_ik_origin")
        return mech.copy().add(Marker(mname, name)), mname
    raise ModelError(
        who, "platform_marker", name, "expected a marker (or body) name of the moving platform"
    )


def _drive_blocks(c: Compiled, actuators: tuple[str, ...]) -> np.ndarray:
    rows = []
    for a in actuators:
        sl = c.rows(a)
        rows.append(sl.start)
    return np.array(rows, dtype=np.int64)


def _involved(c: Compiled, U: np.ndarray, act_rows: np.ndarray, actuators) -> str:
    """Actuators (legs) with a large weight in the left singular vectors U (physics.md c.5):
    the combination of their rows that the other rows cannot balance."""
    w = np.sqrt(np.sum(U[act_rows] ** 2, axis=1))
    top = float(np.max(w)) if w.size else 0.0
    names = []
    for k in np.argsort(-w):
        if w[k] >= 0.1 * top and top > 0:
            jt = c.mechanism.drivers[actuators[k]].joint
            names.append(f"{actuators[k]} (joint {jt}, weight {w[k]:.2f})")
    return ", ".join(names) if names else "none of the actuators (a joint-only dependency)"


def _revolute_readout(
    c: Compiled, d: RevoluteDriver, y: np.ndarray, a: np.ndarray
) -> tuple[float, float, float, int, np.ndarray]:
    """Motor angle theta (from f_i to f_j about h_i, marker i on the ground), its rates
    h_i . omega_j and h_i . omega_dot_j, and its Jacobian row (body j's omega' columns:
    A_j^T h_i): the read-out of a RevoluteDriver, whose row is not theta itself."""
    mech = c.mechanism
    jt = mech.joints[d.joint]
    Ti = np.array(mech.markers[jt.marker_i].orientation)
    mj = mech.markers[jt.marker_j]
    k = c.body_names.index(mj.body)
    A = quaternion_to_rotation(y[7 * k + 3 : 7 * k + 7])
    fj = A @ np.array(mj.orientation)[:, 0]
    h = Ti[:, 2]
    th = math.atan2(float(Ti[:, 1] @ fj), float(Ti[:, 0] @ fj))
    w = y[c.nq + 6 * k + 3 : c.nq + 6 * k + 6]
    row = A.T @ h
    return th, float(row @ w), float(row @ a[6 * k + 3 : 6 * k + 6]), 6 * k + 3, row


def _revolute_rows(c: Compiled, rows, y, a, revolute, act_rows) -> list:
    """Replace the rows of the revolute actuators by their exact angle rows (in place);
    [(actuator index, [theta, theta_dot, theta_ddot])]."""
    out = []
    for i, name in revolute:
        th, thd, thdd, col, row = _revolute_readout(c, c.mechanism.drivers[name], y, a)
        rows.phi_q[act_rows[i]] = 0.0
        rows.phi_q[act_rows[i], col : col + 3] = row
        out.append((i, [th, thd, thdd]))
    return out


def _marker_pose(c: Compiled, mk: Marker, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    k = c.body_names.index(mk.body)
    A = quaternion_to_rotation(y[7 * k + 3 : 7 * k + 7])
    return y[7 * k : 7 * k + 3] + A @ np.array(mk.position), A @ mk.triad


def _aligned_null(Vt: np.ndarray, rank: int, prev: np.ndarray | None) -> np.ndarray:
    """Orthonormal null-space basis (n, n - rank), rotated to be closest to `prev` (so that
    det [J_d; N^T] is continuous along the trajectory)."""
    N = Vt[rank:].T
    if prev is None or prev.shape != N.shape:
        return N
    u, _, vt = np.linalg.svd(N.T @ prev)
    return N @ (u @ vt)


def inverse_kinematics(
    mech: Mechanism,
    trajectory: PlatformTrajectory,
    *,
    platform_marker: str,
    actuators: Sequence[str],
    times: Sequence[float] | np.ndarray,
    max_condition: float = 1e6,
    check_crossing: bool = True,
    rank_rtol: float = 1e-9,
    tol: float = 1e-12,
    y0: np.ndarray | None = None,
) -> IKResult:
    """Actuator histories for a prescribed platform trajectory (physics.md e.2 steps 1-4).

    mech: the mechanism with its actuator drivers (clearance joints are made ideal first).
    platform_marker: marker whose point follows (x, y, z)(t) and whose triad follows the
    angles (a body name is accepted: a marker at its mass centre with the body axes).
    actuators: names of the PrismaticDrivers replaced by the pose drivers. times: strictly
    increasing sample times [s]; the first sample is assembled from y0 (default: the
    mechanism's initial poses), every later one from the previous one.
    max_condition: refuse (KinematicsError) a sample whose drive Jacobian has a condition
    number above this (equivalently sigma_min < sigma_max / max_condition). The default
    1e6 is far above the ~1e2 of the mechanisms.md layouts and far below the ~1e16 of an
    exact singularity; the centrally symmetric 4UPS-UPU layout stays above 1e6 along the
    whole mechanisms.md 1.5 trajectory. The Jacobian mixes units (rows in m and 1, columns
    in m and rad), so the number is meaningful for mechanisms of ~0.1-1 m size.
    check_crossing: also refuse when det of the drive Jacobian (idle DOF locked) changes
    sign between two samples: a singular configuration lies between them.
    rank_rtol: relative tolerance that counts the idle DOF (null space of the IK Jacobian).
    tol: assembly tolerance on max |phi| [m or 1].
    y0: initial guess of the ideal mechanism's state (its layout: no clearance states).
    """
    ts = np.asarray(times, dtype=float).ravel()
    if ts.size == 0 or not np.all(np.isfinite(ts)) or np.any(np.diff(ts) <= 0):
        raise ModelError("inverse_kinematics", "times", ts[:5], "expected increasing times")
    if not isinstance(trajectory, PlatformTrajectory):
        raise ModelError(
            "inverse_kinematics", "trajectory", trajectory, "expected a PlatformTrajectory"
        )
    ideal = _ideal(mech)
    acts = _check_actuators(ideal, actuators)
    ideal, mname = _platform_marker(ideal, platform_marker)
    mk = ideal.markers[mname]

    # 1-2: actuator drivers out, pose drivers in (physics.md e.2)
    ik = ideal.without(*acts)
    for axis, fn, tag in ((0, trajectory.x, "x"), (1, trajectory.y, "y"), (2, trajectory.z, "z")):
        if tag not in trajectory.positions:
            continue
        e = [0.0, 0.0, 0.0]
        e[axis] = 1.0
        ik.add(PositionDriver(_unique(ik, f"ik_{tag}"), mname, tuple(e), fn))
    if trajectory.mode != "none":
        ik.add(
            OrientationDriver(
                _unique(ik, "ik_orientation"),
                mname,
                trajectory.angles,
                trajectory.sequence,
                trajectory.mode,
            )
        )
    c_ik = compile_mechanism(ik)
    # the original drivers with f = 0: their rows are g(q) = s, g_q, gamma_g (physics.md e.1)
    zero = {a: replace(ideal.drivers[a], function=Constant(0.0)) for a in acts}
    c_dr = compile_mechanism(ideal.replace(**zero))
    act_rows = _drive_blocks(c_dr, acts)
    revolute = [(i, a) for i, a in enumerate(acts) if isinstance(ideal.drivers[a], RevoluteDriver)]

    n, na, nq, nv = ts.size, len(acts), c_ik.nq, c_ik.nv
    y = np.array(c_ik.y0 if y0 is None else y0, dtype=float)
    if y.shape != (c_ik.ny,):
        raise ModelError("inverse_kinematics", "y0", y.shape, f"expected length {c_ik.ny}")
    Y = np.zeros((n, c_ik.ny))
    A = np.zeros((n, nv))
    S = np.zeros((n, na, 3))
    P = np.zeros((n, 3))
    R = np.zeros((n, 3, 3))
    twist = np.zeros(n)
    smin = np.zeros(n)
    cond = np.zeros(n)
    N_prev: np.ndarray | None = None
    det_sign_prev = 0.0
    idle0 = -1
    a = np.zeros(nv)
    for k, t in enumerate(ts):
        if k:  # second-order predictor from the previous sample (physics.md e.1 warm start)
            h = t - ts[k - 1]
            apply_position_increment(c_ik, y, h * y[nq : nq + nv] + 0.5 * h * h * a)
        # 3: position, velocity, acceleration analysis of the pose-driven mechanism
        y = assemble(c_ik, y, t=float(t), tol=tol)
        y[nq : nq + nv] = 0.0  # idle DOF (limb spins) get the kinetic-energy-least velocity
        y = velocity_analysis(c_ik, y, t=float(t))
        a = acceleration_analysis(c_ik, y, t=float(t))
        Y[k], A[k] = y, a
        # 4: read-out of the actuator coordinates with the original driver rows
        rows = evaluate_rows(c_dr, float(t), y)
        g_q = rows.phi_q[act_rows]
        S[k, :, 0] = rows.phi[act_rows]
        S[k, :, 1] = rows.phi_dot[act_rows]  # g_q v + g_t
        S[k, :, 2] = g_q @ a - rows.gamma[act_rows]
        for i, th in _revolute_rows(c_dr, rows, y, a, revolute, act_rows):
            if k:  # continuous along the trajectory (atan2 wraps at +-pi)
                th[0] += 2.0 * math.pi * round((S[k - 1, i, 0] - th[0]) / (2.0 * math.pi))
            S[k, i] = th
        P[k], R[k] = _marker_pose(c_ik, mk, y)
        M = trajectory.rotation(float(t)).T @ R[k]
        twist[k] = math.atan2(M[1, 0] - M[0, 1], M[0, 0] + M[1, 1])

        # conditioning: idle DOF = null space of the IK Jacobian (platform held)
        J_ik = evaluate_rows(c_ik, float(t), y).phi_q
        s_ik = np.linalg.svd(J_ik, compute_uv=False)
        rank_ik = int(np.sum(s_ik > rank_rtol * max(1.0, s_ik[0])))
        idle = nv - rank_ik
        if idle0 < 0:
            idle0 = idle
        elif idle != idle0:
            raise KinematicsError(
                f"inverse kinematics of '{mech.name}': the pose drivers stop determining the "
                f"mechanism at t = {t:.6g} s ({idle} idle DOF instead of {idle0}): the legs "
                "reach a serial (inverse-kinematic) singularity or the pose is unreachable"
            )
        J_d = rows.phi_q
        s_d = np.linalg.svd(J_d, compute_uv=False)
        r_eff = nv - idle
        if J_d.shape[0] < r_eff:
            raise KinematicsError(
                f"inverse kinematics of '{mech.name}': the {na} actuators leave "
                f"{r_eff - J_d.shape[0]} DOF of the mechanism undriven (under-actuated)"
            )
        smin[k] = s_d[r_eff - 1]
        cond[k] = s_d[0] / smin[k] if smin[k] > 0 else math.inf
        if cond[k] > max_condition:
            bad = [i for i in range(r_eff) if s_d[i] * max_condition < s_d[0]]
            U = np.linalg.svd(J_d)[0]
            raise KinematicsError(
                f"inverse kinematics of '{mech.name}': the drive Jacobian is singular at "
                f"t = {t:.6g} s (sample {k}): condition number {cond[k]:.3g} > "
                f"{max_condition:.3g}, sigma_min = {smin[k]:.3g}, {len(bad)} near-dependent "
                f"direction(s); the legs cannot hold the platform there. Actuators involved: "
                f"{_involved(c_dr, U[:, bad], act_rows, acts)}"
            )
        if check_crossing and J_d.shape[0] + idle == nv:
            N = _aligned_null(np.linalg.svd(J_ik)[2], rank_ik, N_prev) if idle else None
            sign, _ = np.linalg.slogdet(np.vstack([J_d, N.T]) if idle else J_d)
            if det_sign_prev and sign and sign != det_sign_prev:
                kk = k if smin[k] <= smin[k - 1] else k - 1
                if kk == k:
                    Jk = J_d
                else:
                    rk = evaluate_rows(c_dr, float(ts[kk]), Y[kk])
                    _revolute_rows(c_dr, rk, Y[kk], A[kk], revolute, act_rows)
                    Jk = rk.phi_q
                Uk = np.linalg.svd(Jk)[0][:, [r_eff - 1]]
                raise KinematicsError(
                    f"inverse kinematics of '{mech.name}': the trajectory passes through a "
                    f"singular configuration between t = {ts[k - 1]:.6g} s and t = {t:.6g} s "
                    f"(the drive Jacobian's determinant changes sign; sampled sigma_min "
                    f"{smin[k - 1]:.3g} and {smin[k]:.3g}). Actuators involved: "
                    f"{_involved(c_dr, Uk, act_rows, acts)}"
                )
            N_prev, det_sign_prev = N, sign or det_sign_prev
    return IKResult(
        times=ts,
        actuators=acts,
        s=S[:, :, 0].copy(),
        s_dot=S[:, :, 1].copy(),
        s_ddot=S[:, :, 2].copy(),
        position=P,
        rotation=R,
        twist=twist,
        y=Y,
        a=A,
        sigma_min=smin,
        condition=cond,
        idle_dof=max(idle0, 0),
        compiled=c_dr,
    )


def drives_from_ik(ik: IKResult) -> dict[str, TimeFunction]:
    """Actuator drives (physics.md e.2 step 5): per actuator a C2 quintic HermiteSpline
    through (s, s_dot, s_ddot) at the IK samples [m, m/s, m/s^2]; needs >= 2 samples.

    Between samples the interpolation error is O(h^6 s^(6)) (h the sample spacing); outside
    the sampled interval the end value is held (see HermiteSpline).
    """
    if ik.times.size < 2:
        raise ModelError("drives_from_ik", "ik.times", ik.times, "need at least 2 samples")
    return {
        name: HermiteSpline(ik.times, ik.s[:, k], ik.s_dot[:, k], ik.s_ddot[:, k])
        for k, name in enumerate(ik.actuators)
    }


def apply_drives(mech: Mechanism, drives: Mapping[str, TimeFunction | float]) -> Mechanism:
    """A copy of `mech` whose named PrismaticDrivers / RevoluteDrivers get the given
    functions (the input is not modified); use with `drives_from_ik` on the ideal or the
    clearance mechanism."""
    changes = {}
    for name, fn in drives.items():
        d = mech.drivers.get(name)
        if not isinstance(d, ACTUATOR_DRIVERS):
            known = [n for n, x in mech.drivers.items() if isinstance(x, ACTUATOR_DRIVERS)]
            raise ModelError(
                "apply_drives",
                "drives",
                name,
                f"not a PrismaticDriver or RevoluteDriver; known: {known}",
            )
        changes[name] = replace(d, function=as_function(fn, owner="apply_drives", field=name))
    return mech.replace(**changes)
