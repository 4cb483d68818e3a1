"""`Result`: everything a simulation produced, with names for every column."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from clearance.compile.compiled import Compiled
from clearance.model.bodies import quaternion_to_rotation


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
    of drivers W_d, of applied non-conservative forces W_a, and the balance residual
    T + V - (T + V)(0) - W_c - W_a [J] (physics.md j).
    stats: nfev, naccept, nreject, nproject, hmin, hmax, wall_time [s].
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
        return np.array([quaternion_to_rotation(p) for p in self.euler_parameters(body)])

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

    def summary(self) -> str:
        st = self.stats
        e = self.energy
        lines = [
            f"status: {'ok' if self.success else 'FAILED'}: {self.message}",
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
        if self.t.size:
            scale = max(1e-300, float(np.max(np.abs(e["kinetic"]) + np.abs(e["potential"]))))
            lines.append(
                f"energy residual max {np.max(np.abs(e['residual'])):.3e} J "
                f"(relative {np.max(np.abs(e['residual'])) / scale:.2e})"
            )
        return "\n".join(lines)
