"""Kinematic analysis (physics.md e.1): assembly, velocity and acceleration analysis, DOF
count and a rank check that names the joints of singular or redundant constraint sets.

These run once per simulation or per IK sample, so they are plain NumPy over the compiled
constraint kernel (dense SVD/lstsq from numpy/scipy rather than hand-written solvers).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from clearance.compile.compiled import Compiled
from clearance.dynamics.rhs import constraint_rows, make_work
from clearance.dynamics.solve import dense_jacobian
from clearance.kinematics.rotations import quat_rotate_body
from clearance.model.errors import KinematicsError


@dataclass(frozen=True)
class Rows:
    """Constraint quantities at one state: phi, phi_t, phi_dot, gamma, dense phi_q."""

    phi: np.ndarray
    phi_t: np.ndarray
    phi_dot: np.ndarray
    gamma: np.ndarray
    phi_q: np.ndarray


def evaluate_rows(c: Compiled, t: float, y: np.ndarray, wk=None) -> Rows:
    wk = make_work(c.model) if wk is None else wk
    constraint_rows(c.model, float(t), np.ascontiguousarray(y, dtype=float), wk)
    Jd = np.empty((c.nrow, c.nv))
    dense_jacobian(c.model, wk.J, Jd)
    return Rows(wk.phi.copy(), wk.phit.copy(), wk.phid.copy(), wk.gam.copy(), Jd)


def apply_position_increment(c: Compiled, y: np.ndarray, dx: np.ndarray) -> None:
    """y <- y (+) dx: r += dr, p <- p (x) exp(dth'/2) per body (physics.md b.1), in place."""
    pn = np.empty(4)
    for b in range(c.nb):
        q = 7 * b
        y[q : q + 3] += dx[6 * b : 6 * b + 3]
        quat_rotate_body(y[q + 3 : q + 7].copy(), dx[6 * b + 3 : 6 * b + 6].copy(), pn)
        y[q + 3 : q + 7] = pn / np.linalg.norm(pn)


def _blocks_of_rows(c: Compiled, rows: np.ndarray) -> list[str]:
    names = []
    for b in c.joints + c.drivers:
        if np.any((rows >= b.row0) & (rows < b.row0 + b.nrows)):
            names.append(b.name)
    return names


@dataclass(frozen=True)
class RankReport:
    """Rank of phi_q at a configuration and what it means for the mechanism.

    dof: 6 nb - rank (mobility at this configuration).  redundant: number of dependent rows.
    involved: joints/drivers whose rows take part in the dependencies (left null space).
    """

    nrow: int
    ncol: int
    rank: int
    dof: int
    redundant: int
    singular_values: np.ndarray
    involved: tuple

    @property
    def full_rank(self) -> bool:
        return self.redundant == 0

    def __str__(self) -> str:
        s = (
            f"{self.nrow} constraint rows, {self.ncol} velocity coordinates, rank {self.rank}, "
            f"DOF {self.dof}"
        )
        if self.redundant:
            s += (
                f"; {self.redundant} dependent row(s) involving: {', '.join(self.involved)} "
                f"(smallest singular values {self.singular_values[-self.redundant :]})"
            )
        return s


def rank_check(c: Compiled, t: float, y: np.ndarray, *, rtol: float = 1e-9) -> RankReport:
    """SVD of phi_q: DOF count and the joints in any dependent (redundant/singular) set."""
    rows = evaluate_rows(c, t, y)
    Jd = rows.phi_q
    m, n = Jd.shape
    if m == 0:
        return RankReport(0, n, 0, n, 0, np.zeros(0), ())
    s = np.linalg.svd(Jd, compute_uv=False)  # (the vectors only when rows are dependent:
    tol = rtol * max(1.0, s[0]) if s.size else rtol  # 0.25 against 0.7 ms on 66 x 66)
    rank = int(np.sum(s > tol))
    red = m - rank
    involved: tuple = ()
    if red:
        U = np.linalg.svd(Jd)[0]
        null = U[:, rank:]  # left null space: combinations of dependent rows
        weight = np.sqrt(np.sum(null**2, axis=1))
        involved = tuple(_blocks_of_rows(c, np.nonzero(weight > 1e-6)[0]))
    sv = np.concatenate([s, np.zeros(max(0, m - s.size))])
    return RankReport(m, n, rank, n - rank, red, sv, involved)


def assemble(
    c: Compiled,
    y: np.ndarray | None = None,
    *,
    t: float = 0.0,
    tol: float = 1e-12,
    max_iter: int = 50,
) -> np.ndarray:
    """Position analysis: Newton-Raphson on phi(q, t) = 0 from a rough pose.

    Steps are minimum-norm (lstsq), so free DOF stay near the initial guess and idle or
    redundant directions do not break the iteration. Returns the assembled state y (velocity
    part untouched). Raises KinematicsError naming the largest violated joint on failure.
    """
    y = np.array(c.y0 if y is None else y, dtype=float)
    if c.nrow == 0:
        return y
    wk = make_work(c.model)
    for _ in range(max_iter):
        rows = evaluate_rows(c, t, y, wk)
        err = float(np.max(np.abs(rows.phi)))
        if err < tol:
            return y
        dx = np.linalg.lstsq(rows.phi_q, -rows.phi, rcond=1e-12)[0]
        apply_position_increment(c, y, dx)
        if float(np.max(np.abs(dx))) < 1e-15 and err < 1e3 * tol:
            return y
    rows = evaluate_rows(c, t, y, wk)
    worst = int(np.argmax(np.abs(rows.phi)))
    raise KinematicsError(
        f"assembly of '{c.mechanism.name}' at t = {t} did not converge in {max_iter} Newton "
        f"iterations: max |phi| = {np.max(np.abs(rows.phi)):.3e} at row {worst} "
        f"({', '.join(_blocks_of_rows(c, np.array([worst])))}); the pose may be "
        "unreachable or the initial guess too far from it"
    )


def _mass_diag(c: Compiled) -> np.ndarray:
    """Dense M (6 nb x 6 nb), block diagonal."""
    M = np.zeros((c.nv, c.nv))
    for b in range(c.nb):
        M[6 * b : 6 * b + 3, 6 * b : 6 * b + 3] = c.model.body_mass[b] * np.eye(3)
        M[6 * b + 3 : 6 * b + 6, 6 * b + 3 : 6 * b + 6] = c.model.body_J[b]
    return M


def velocity_analysis(c: Compiled, y: np.ndarray, *, t: float = 0.0) -> np.ndarray:
    """Make the velocities consistent: phi_q v = -phi_t.

    The given velocities are corrected by the kinetic-energy-closest change (mass-weighted
    projection, physics.md d.4), so prescribed initial velocities of free DOF are kept.
    Returns a new y.
    """
    y = np.array(y, dtype=float)
    if c.nrow == 0:
        return y
    rows = evaluate_rows(c, t, y)
    J = rows.phi_q
    M = _mass_diag(c)
    MiJt = np.linalg.solve(M, J.T)
    S = J @ MiJt
    lam = np.linalg.lstsq(S, rows.phi_dot, rcond=1e-12)[0]
    y[c.nq : c.nq + c.nv] -= MiJt @ lam
    return y


def acceleration_analysis(c: Compiled, y: np.ndarray, *, t: float = 0.0) -> np.ndarray:
    """Accelerations of a kinematically determined system (phi_q square): phi_q v_dot = gamma.

    Minimum-norm for under-determined systems (then it is not the dynamic answer).
    """
    rows = evaluate_rows(c, t, y)
    return np.linalg.lstsq(rows.phi_q, rows.gamma, rcond=1e-12)[0]
