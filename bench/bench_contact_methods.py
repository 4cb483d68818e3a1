"""Contact-adapted integrators tried on persistent contact (issue 12): do they beat the
explicit pairs?

Case (c) of bench_work_precision.py, a 1 kg rod resting in its spherical socket (Flores,
K = 1e10, Coulomb mu = 0.1) and swinging, is where an implicit treatment of the contact
should pay most: the ball never leaves the socket, so the contact's stiff modes are there
on every step. This script integrates its first 0.2 s (the contact state stays closed, so
the compiled right-hand side is used with that state frozen: no events) with

* scipy's RK45 and DOP853: the explicit pairs, as the package's dopri5 and dop853 loops;
* ROS34PW2 (Rang & Angermann 2005): a linearly implicit Rosenbrock-W method, order 3(2),
  L-stable, with the full finite-difference Jacobian at every step. A W-method keeps its
  order with any Jacobian, so the full one is the best case for the planned contact-only
  Jacobian (it removes every stiff mode, not only the contact's);
* exprb32 (Hochbruck, Ostermann & Schweitzer 2009): an exponential Rosenbrock method,
  order 3(2), the contact modes integrated by phi-functions of the central-difference
  Jacobian at every step (a forward-difference one already costs it an order);
* scipy's Radau (implicit, order 5) and BDF (orders 1-5), given the central-difference
  Jacobian: what a fully implicit method can gain at most;

and prints, per method and rtol (atol = rtol / 1000), the largest error of the rod's
position on 201 samples against DOP853 at rtol 1e-13, the steps, and the rhs calls outside
the Jacobians. The methods are written here in NumPy (prototypes: compare steps and rhs,
not time). It also prints the Jacobian's eigenvalues at the start, which say why.

    python bench/bench_contact_methods.py [--duration 0.2]

About 2 min. Results and conclusions: bench/README.md.
"""

from __future__ import annotations

# isort: off
# _common first: it pins the thread counts, which only works before numpy is imported
from _common import print_environment

# isort: on
import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm, lu_factor, lu_solve

import clearance as cl
from clearance.contact.element import make_contact_state
from clearance.dynamics.rhs import make_work, rhs

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_work_precision import resting_pendulum  # noqa: E402

# ROS34PW2 (Rang & Angermann, BIT 45, 2005), Hairer-Wanner form:
# (I - h g J) k_i = h f(y + sum_j A_ij k_j) + h J sum_j G_ij k_j, y1 = y + sum_i B_i k_i
ROS_G = 4.3586652150845900e-01
ROS_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0],
        [8.7173304301691801e-01, 0.0, 0.0, 0.0],
        [8.4457060015369423e-01, -1.1299064236484185e-01, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]
)
ROS_GAM = np.array(
    [
        [0.0, 0.0, 0.0, 0.0],
        [-8.7173304301691801e-01, 0.0, 0.0, 0.0],
        [-9.0338057013044082e-01, 5.4180672388095326e-02, 0.0, 0.0],
        [2.4212380706095346e-01, -1.2232505839045147e00, 5.4526025533510214e-01, 0.0],
    ]
)
ROS_B = np.array(
    [2.4212380706095346e-01, -1.2232505839045147e00, 1.5452602553351020e00, 4.3586652150845900e-01]
)
ROS_BH = np.array([3.7810903145819369e-01, -9.6042292212423178e-02, 0.5, 2.1793326075422950e-01])


class Frozen:
    """The compiled right-hand side of case (c) with its contact state frozen, counting calls
    (rhs: the method's own calls; jac: those spent on Jacobians)."""

    def __init__(self):
        comp, self.y0 = resting_pendulum()
        r = cl.simulate(comp, 1e-3, dt_out=1e-4, y0=self.y0, assemble_positions=False)
        self.model = comp.model
        self.cs = make_contact_state(comp.model)
        self.cs.flag[:] = r.contact_state[0, :, 0].astype(np.int64)
        self.cs.ddm[:] = r.contact_state[0, :, 1]
        self.wk = make_work(comp.model)
        self.nrhs = self.njac = 0

    def f(self, t, y):
        self.nrhs += 1
        yd = np.empty_like(y)
        rhs(t, y, self.model, self.wk, self.cs, 5.0, 5.0, 0, yd)
        return yd

    def jac(self, t, y, f0=None):
        """Forward differences with f0 given, else central ones; their calls move from nrhs
        to njac."""
        n0 = self.nrhs
        n = y.size
        J = np.empty((n, n))
        for j in range(n):
            d = (1e-8 if f0 is not None else 1e-9) * max(1.0, abs(y[j]))
            yp = y.copy()
            yp[j] += d
            if f0 is not None:
                J[:, j] = (self.f(t, yp) - f0) / d
            else:
                ym = y.copy()
                ym[j] -= d
                J[:, j] = (self.f(t, yp) - self.f(t, ym)) / (2 * d)
        self.njac += self.nrhs - n0
        self.nrhs = n0
        return J


def _controller(h, en, order):
    return h * min(5.0, max(0.2, 0.9 * max(en, 1e-10) ** (-1.0 / order)))


def _norm(e, y, y1, rtol, atol):
    return float(np.sqrt(np.mean((e / (atol + rtol * np.maximum(np.abs(y), np.abs(y1)))) ** 2)))


def _hermite(y, f0, y1, f1, h, th):
    return (
        (2 * th**3 - 3 * th**2 + 1) * y
        + (th**3 - 2 * th**2 + th) * h * f0
        + (-2 * th**3 + 3 * th**2) * y1
        + (th**3 - th**2) * h * f1
    )


def ros34pw2(sys_, T, ts, rtol, atol):
    """Adaptive ROS34PW2, a new forward-difference Jacobian every step; the samples by cubic
    Hermite interpolation (f at the step's end is not counted: an FSAL-like reuse)."""
    t, y, h = 0.0, sys_.y0.copy(), 1e-5
    out, k, nst = [sys_.y0.copy()], 1, 0
    while t < T * (1 - 1e-14):
        h = min(h, T - t)
        f0 = sys_.f(t, y)
        J = sys_.jac(t, y, f0)
        lu = lu_factor(np.eye(y.size) - h * ROS_G * J)
        K = np.zeros((4, y.size))
        for i in range(4):
            fi = f0 if i == 0 else sys_.f(t, y + ROS_A[i, :i] @ K[:i])
            K[i] = lu_solve(lu, h * fi + h * (J @ (ROS_GAM[i, :i] @ K[:i])))
        y1 = y + ROS_B @ K
        en = _norm((ROS_B - ROS_BH) @ K, y, y1, rtol, atol)
        if en <= 1.0:
            f1 = sys_.f(t + h, y1)
            sys_.nrhs -= 1
            while k < ts.size and ts[k] <= t + h * (1 + 1e-12):
                out.append(_hermite(y, f0, y1, f1, h, (ts[k] - t) / h))
                k += 1
            t, y, nst = t + h, y1, nst + 1
        h = _controller(h, en, 3)
    return np.array(out), nst


def _phi(hJ, v, p):
    """phi_1(hJ) v .. phi_p(hJ) v from one exponential of the augmented matrix."""
    n = v.size
    M = np.zeros((n + p, n + p))
    M[:n, :n] = hJ
    M[:n, n] = v
    for i in range(p - 1):
        M[n + i, n + i + 1] = 1.0
    E = expm(M)
    return [E[:n, n + i] for i in range(p)]


def exprb32(sys_, T, ts, rtol, atol):
    """Adaptive exprb32 with a new central-difference Jacobian every step; it steps onto
    the sample times (no dense output)."""
    t, y, h = 0.0, sys_.y0.copy(), 1e-5
    out, k, nst = [sys_.y0.copy()], 1, 0
    while k < ts.size:
        h = min(h, ts[k] - t)
        f0 = sys_.f(t, y)
        J = sys_.jac(t, y)
        u2 = y + h * _phi(h * J, f0, 1)[0]
        d = sys_.f(t + h, u2) - f0 - J @ (u2 - y)
        e = 2 * h * _phi(h * J, d, 3)[2]
        en = _norm(e, y, u2 + e, rtol, atol)
        if en <= 1.0:
            t, y, nst = t + h, u2 + e, nst + 1
            if t >= ts[k] * (1 - 1e-12):
                out.append(y.copy())
                k += 1
        h = _controller(h, en, 3)
    return np.array(out), nst


def order_check() -> None:
    """The observed orders of ROS34PW2 (exact Jacobian, and J = 0: a W-method keeps its
    order) and exprb32 at fixed steps on van der Pol (mu = 2, 1 s from (2, 0))."""

    def f(t, y):
        return np.array([y[1], 2.0 * (1 - y[0] ** 2) * y[1] - y[0]])

    def jac(y):
        return np.array([[0.0, 1.0], [-4.0 * y[0] * y[1] - 1.0, 2.0 * (1 - y[0] ** 2)]])

    y0 = np.array([2.0, 0.0])
    ref = solve_ivp(f, (0, 1), y0, method="DOP853", rtol=1e-13, atol=1e-14).y[:, -1]
    for name in ("ROS34PW2", "ROS34PW2, J = 0", "exprb32"):
        errs = []
        for n in (20, 40, 80, 160):
            h, y = 1.0 / n, y0.copy()
            for i in range(n):
                t = i * h
                J = np.zeros((2, 2)) if name.endswith("0") else jac(y)
                if name.startswith("ROS"):
                    K = np.zeros((4, 2))
                    M = np.eye(2) - h * ROS_G * J
                    for s in range(4):
                        fs = f(t, y + ROS_A[s, :s] @ K[:s])
                        K[s] = np.linalg.solve(M, h * fs + h * (J @ (ROS_GAM[s, :s] @ K[:s])))
                    y = y + ROS_B @ K
                else:
                    f0 = f(t, y)
                    u2 = y + h * _phi(h * J, f0, 1)[0]
                    d = f(t + h, u2) - f0 - J @ (u2 - y)
                    y = u2 + 2 * h * _phi(h * J, d, 3)[2]
            errs.append(np.abs(y - ref).max())
        p = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
        print(f"order check, {name}: observed orders {', '.join(f'{x:.2f}' for x in p)}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=0.2)
    a = ap.parse_args()
    T = a.duration
    print_environment("Contact-adapted integrators on case (c), persistent contact (issue 12)")
    order_check()
    s = Frozen()
    ts = np.linspace(0.0, T, 201)
    ev = np.linalg.eigvals(s.jac(0.0, s.y0))
    big = ev[np.abs(ev) > 10.0]
    print("eigenvalues of the Jacobian at the start, |lambda| > 10 [1/s]:")
    print("  " + ", ".join(f"{z.real:.4g}{z.imag:+.4g}j" for z in big[np.argsort(-np.abs(big))]))
    ref = solve_ivp(s.f, (0, T), s.y0, method="DOP853", rtol=1e-13, atol=1e-16, t_eval=ts).y.T

    def err(Y):
        return float(np.abs(Y[:, :3] - ref[:, :3]).max())

    rows = []
    runs = [(m, r) for m in ("RK45", "DOP853", "Radau", "BDF") for r in (1e-5, 1e-6, 1e-7, 1e-8)]
    runs += [("ROS34PW2", r) for r in (1e-5, 1e-6, 1e-7)]
    runs += [("exprb32", r) for r in (1e-5, 1e-6)]
    print(
        f"\n{'method':9s} {'rtol':>6s} {'error [m]':>10s} {'steps':>7s} {'rhs':>7s} "
        f"{'jac rhs':>8s} {'time [s]':>8s}"
    )
    for m, rtol in runs:
        s.nrhs = s.njac = 0
        t0 = time.perf_counter()
        if m == "ROS34PW2":
            Y, nst = ros34pw2(s, T, ts, rtol, rtol * 1e-3)
        elif m == "exprb32":
            Y, nst = exprb32(s, T, ts, rtol, rtol * 1e-3)
        else:
            kw = {"jac": s.jac} if m in ("Radau", "BDF") else {}
            sol = solve_ivp(
                s.f, (0, T), s.y0, method=m, rtol=rtol, atol=rtol * 1e-3, dense_output=True, **kw
            )
            Y, nst = sol.sol(ts).T, sol.t.size - 1
        w = time.perf_counter() - t0
        rows.append((m, rtol, err(Y), nst, s.nrhs, s.njac))
        print(
            f"{m:9s} {rtol:6.0e} {err(Y):10.2e} {nst:7d} {s.nrhs:7d} {s.njac:8d} {w:8.2f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
