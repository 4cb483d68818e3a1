"""`Result`: everything a simulation produced, with names for every column."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from clearance.compile.compiled import Compiled
from clearance.kinds import Status
from clearance.layout import CO_DELTA, CO_FN, EV_KIND, EV_POINT, JOINT_COLUMNS, POINT_COLUMNS
from clearance.model.bodies import rotation_matrices


@dataclass(frozen=True)
class Result:
    """Simulation output at the requested times (n = number of samples reached).

    t (n,) [s]; q (n, 7 nb) positions and Euler parameters; v (n, 6 nb) r_dot [m/s] and
    omega' (body frame) [rad/s]; a (n, 6 nb) r_ddot [m/s^2] and omega'_dot [rad/s^2];
    lam (n, m) multipliers; phi, phi_dot (n, m) constraint violation and its rate.
    reaction_force / reaction_moment (n, nblock, 3): force [N] and moment about the joint
    point [N m], world frame, exerted by each joint/driver (names in `blocks`) on its
    reporting body (`reaction_body`: body j of the joint, or body i when j is the ground).
    driver_force (n, ndriver_rows): actuator force/torque, F_act = -lam (positive pushes body
    j along the driver's positive direction; see each driver's docstring); for a squared
    DistanceDriver (phi = d.d - l^2) it is -2 l lam, the same pushing force.
    energy: kinetic T, potential V (gravity + springs), work of all constraint forces W_c,
    of drivers W_d, of applied non-conservative forces W_a, of contact forces through moving
    attachment points W_m ("work_moving"), the lumped-limb inertia power integral W_L
    ("work_inertia"), and the balance residual [J] (physics.md j).
    stats: nfev, naccept, nreject, nproject, nevents (steps cut at a contact event), hmin,
    hmax, wall_time [s].
    Clearance joints (names in `clearance_names`): per-joint accessors eccentricity(),
    penetration(), normal_force(), friction_force(), in_contact(), dissipated(), and any
    channel of `clearance.layout.JOINT_COLUMNS` by `channel(name, joint)`; their contact
    points (`contact_point_names`, each of joint `contact_point_joints[k]`) have the
    channels of POINT_COLUMNS (`channel("point_penetration", point)`, `contact_points`
    (n, ncp, NPOUT)), the contact state (flag, impact velocity) and the LuGre bristles
    (n, ncp, 3). `events` is the contact event log (t, contact point index, +1 onset / -1
    separation, delta_dot [m/s], the joint's e (3) in the outer marker frame [m]); energy
    adds the contact elastic energy V_c ("contact"), the normal damping dissipation D_n
    ("damping") and the friction work D_t ("friction"), and the residual is
    T + V + V_c - (.)(0) - W_c - W_a - W_m - W_L + D_n + D_t (physics.md j).
    status 0 means success; otherwise `message` says why it stopped and the arrays hold
    everything computed up to then.
    """

    compiled: Compiled = field(repr=False)
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    phi: np.ndarray
    phi_dot: np.ndarray
    reaction_force: np.ndarray
    reaction_moment: np.ndarray
    reaction_body: tuple
    blocks: tuple
    driver_force: np.ndarray
    driver_names: tuple
    energy: dict
    stats: dict
    status: int
    message: str
    settings: dict
    clearance_names: tuple = ()
    contact: np.ndarray = field(default=None, repr=False)  # (n, nclr, NCOUT) per joint
    contact_state: np.ndarray = field(default=None, repr=False)  # (n, ncp, 2) flag, ddm
    dissipation: np.ndarray = field(default=None, repr=False)  # (n, nclr, 2) D_n, D_t [J]
    bristle: np.ndarray = field(default=None, repr=False)  # (n, ncp, 3) LuGre z [m]
    events: np.ndarray = field(default=None, repr=False)  # (nevents, 7) contact event log
    # (nclr, 4) largest F_N [N], its time [s], largest delta [m], its time, over the accepted
    # integration steps and the samples: impacts shorter than the output interval are
    # resolved here, not on the output grid
    contact_peaks: np.ndarray = field(default=None, repr=False)
    contact_points: np.ndarray = field(default=None, repr=False)  # (n, ncp, NPOUT) per point
    contact_point_names: tuple = ()
    contact_point_joints: tuple = ()  # clearance joint of each contact point
    # Poincare section of `simulate(section=...)`: crossing times (k,) [s] and the states
    # there (k, ny), located on the dense output; section_label says which section
    section_time: np.ndarray = field(default=None, repr=False)
    section_state: np.ndarray = field(default=None, repr=False)
    section_label: str = ""

    @property
    def success(self) -> bool:
        return self.status == 0

    def _k(self, body: str) -> int:
        return self.compiled.body_names.index(body)

    def position(self, body: str) -> np.ndarray:
        """(n, 3) mass-centre position [m]."""
        k = self._k(body)
        return self.q[:, 7 * k : 7 * k + 3]

    def euler_parameters(self, body: str) -> np.ndarray:
        k = self._k(body)
        p = self.q[:, 7 * k + 3 : 7 * k + 7]
        return p / np.linalg.norm(p, axis=1, keepdims=True)

    def rotation(self, body: str) -> np.ndarray:
        """(n, 3, 3) rotation matrices body -> world."""
        return rotation_matrices(self.euler_parameters(body))

    def velocity(self, body: str) -> np.ndarray:
        k = self._k(body)
        return self.v[:, 6 * k : 6 * k + 3]

    def angular_velocity(self, body: str, *, frame: str = "world") -> np.ndarray:
        """(n, 3) angular velocity [rad/s], world (default) or body components."""
        k = self._k(body)
        wb = self.v[:, 6 * k + 3 : 6 * k + 6]
        if frame == "body":
            return wb
        return np.einsum("nij,nj->ni", self.rotation(body), wb)

    def acceleration(self, body: str) -> np.ndarray:
        k = self._k(body)
        return self.a[:, 6 * k : 6 * k + 3]

    def point_position(self, body: str, point_b: object) -> np.ndarray:
        """(n, 3) world position of a body-fixed point given in body components."""
        return self.position(body) + self.rotation(body) @ np.asarray(point_b, dtype=float)

    def reaction(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """(force, moment) histories of one joint or driver, see class docstring."""
        k = self.blocks.index(name)
        return self.reaction_force[:, k], self.reaction_moment[:, k]

    def actuator_force(self, name: str) -> np.ndarray:
        """(n,) actuator force of a one-row driver (or (n, rows) for multi-row drivers)."""
        cols = [i for i, nm in enumerate(self.driver_names) if nm == name]
        if not cols:
            raise KeyError(f"no driver named {name!r}; drivers: {sorted(set(self.driver_names))}")
        out = self.driver_force[:, cols]
        return out[:, 0] if len(cols) == 1 else out

    # ------------------------------------------------------------ clearance joints
    def _c(self, name: str) -> int:
        if name not in self.clearance_names:
            raise KeyError(
                f"no clearance joint named {name!r}; clearance joints: {list(self.clearance_names)}"
            )
        return self.clearance_names.index(name)

    def channel(self, channel: str, name: str) -> np.ndarray:
        """(n, width) or (n,) history of an output channel by its dataset name, for a
        clearance joint (channels of layout.JOINT_COLUMNS, e.g. "penetration") or a contact
        point (POINT_COLUMNS, e.g. "point_penetration"), with the dataset's signs."""
        for table, data, names in (
            (JOINT_COLUMNS, self.contact, self.clearance_names),
            (POINT_COLUMNS, self.contact_points, self.contact_point_names),
        ):
            for col in table:
                if col.name == channel:
                    if name not in names:
                        raise KeyError(f"no element named {name!r}; known: {list(names)}")
                    return col.take(data[:, names.index(name)])
        known = [c.name for c in JOINT_COLUMNS + POINT_COLUMNS]
        raise KeyError(f"no output channel {channel!r}; channels: {known}")

    def points(self, name: str) -> tuple[str, ...]:
        """Names of the contact points of clearance joint `name`."""
        self._c(name)
        return tuple(
            p
            for p, j in zip(self.contact_point_names, self.contact_point_joints, strict=True)
            if j == name
        )

    def eccentricity(self, name: str) -> np.ndarray:
        """(n, 3) ball / journal / slider centre relative to the socket / bearing / guide
        centre, outer marker frame [m]."""
        return self.channel("eccentricity", name)

    def penetration(self, name: str) -> np.ndarray:
        """(n,) delta [m] (negative: free flight inside the clearance); for a joint with
        several contact points the largest."""
        return self.channel("penetration", name)

    def contact_force(self, name: str) -> np.ndarray:
        """(n,) normal contact force magnitude F_N [N] (summed over the contact points)."""
        return self.channel("contact_force", name)

    def normal_force(self, name: str) -> np.ndarray:
        """(n, 3) normal force on the ball (journal, slider), -sum F_N n, world frame [N]."""
        return self.channel("normal_force", name)

    def friction_force(self, name: str) -> np.ndarray:
        """(n, 3) friction force on the ball (journal, slider), opposing slip, world [N]."""
        return self.channel("friction_force", name)

    def slip_velocity(self, name: str) -> np.ndarray:
        """(n, 3) tangential slip velocity v_t of the ball relative to the socket [m/s]
        (the deepest contact point's)."""
        return self.channel("slip_velocity", name)

    def _peak(self, name: str, col: int, src: int) -> tuple[float, float]:
        k = self._c(name)
        if self.contact_peaks is not None:
            return float(self.contact_peaks[k, col]), float(self.contact_peaks[k, col + 1])
        x = self.contact[:, k, src]  # results saved without peaks: the output grid only
        if x.size == 0:
            return 0.0, math.nan
        i = int(np.argmax(x))
        return float(x[i]), float(self.t[i])

    def peak_contact_force(self, name: str) -> tuple[float, float]:
        """(F_N, t): the largest normal contact force [N] and its time [s], over the accepted
        integration steps as well as the samples (an impact can be shorter than dt_out);
        with the adaptive methods, the force's own peak between two steps is found on the
        dense output (a damped law's force peaks before the penetration)."""
        return self._peak(name, 0, CO_FN)

    def peak_penetration(self, name: str) -> tuple[float, float]:
        """(delta, t): the largest penetration [m] (negative if never in contact) and its
        time, over the accepted steps and the samples; with the adaptive methods, the
        maximum between two steps is found on the dense output."""
        return self._peak(name, 2, CO_DELTA)

    def in_contact(self, name: str) -> np.ndarray:
        """(n,) bool: delta > 0 at the sample."""
        return self.penetration(name) > 0.0

    def dissipated(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """(D_n, D_t): cumulative normal-damping dissipation and friction work [J]."""
        k = self._c(name)
        return self.dissipation[:, k, 0], self.dissipation[:, k, 1]

    def impacts(self, name: str | None = None) -> np.ndarray:
        """Onset rows of the event log (t, contact point, +1, impact velocity, e (3)) of all
        joints or of clearance joint `name` (each of its contact points' onsets)."""
        ev = self.events if self.events is not None else np.zeros((0, 7))
        ev = ev[ev[:, EV_KIND] > 0]
        if name is not None:
            self._c(name)
            own = [p for p, j in enumerate(self.contact_point_joints) if j == name]
            ev = ev[np.isin(ev[:, EV_POINT], own)]
        return ev

    def _state(self) -> str:
        """ "ok", "STOPPED" (from outside: Ctrl-C, a stop request, max_wall_time) or
        "FAILED"."""
        if self.success:
            return "ok"
        return "STOPPED" if self.status in (Status.INTERRUPTED, Status.WALL_TIME) else "FAILED"

    def summary(self) -> str:
        st = self.stats
        e = self.energy
        lines = [
            f"status: {self._state()}: {self.message}",
            f"samples {self.t.size}, t = {self.t[0]:.4g} .. {self.t[-1]:.4g} s"
            if self.t.size
            else "no samples",
            f"steps {int(st['naccept'])} accepted, {int(st['nreject'])} rejected, "
            f"{int(st['nfev'])} rhs evaluations, wall {st['wall_time']:.3f} s",
        ]
        if self.phi.size:
            lines.append(
                f"max |phi| = {np.max(np.abs(self.phi)):.3e}, "
                f"max |phi_dot| = {np.max(np.abs(self.phi_dot)):.3e}"
            )
        for name in self.clearance_names:
            fn, tf = self.peak_contact_force(name)
            d, _ = self.peak_penetration(name)
            lines.append(
                f"clearance {name}: peak F_N {fn:.4g} N at t = {tf:.6g} s, "
                f"{len(self.impacts(name))} impacts, max penetration {max(0.0, d):.3g} m"
            )
        if self.t.size:
            scale = max(1e-300, float(np.max(np.abs(e["kinetic"]) + np.abs(e["potential"]))))
            lines.append(
                f"energy residual max {np.max(np.abs(e['residual'])):.3e} J "
                f"(relative {np.max(np.abs(e['residual'])) / scale:.2e})"
            )
        return "\n".join(lines)
