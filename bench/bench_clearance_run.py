"""Benchmark: the default 4UPS-UPU clearance scenario (2 s, two clearance joints).

Reports, in one run and as ratios against a plain NumPy/solve_ivp implementation of the SAME
model (the NumPy reference rhs of the ideal joints plus a NumPy ball-in-socket element with
the same Flores contact and LuGre friction), the per-rhs time and the whole-run wall time and
real-time factor of the compiled engine at the scenario's default tolerances.

    taskset -c 0 python bench/bench_clearance_run.py [--baseline-interval 0.02]

The NumPy baseline is ~1000x slower, so it integrates a short interval that includes the
first impacts and the result is scaled to 2 s by its rhs count per simulated second (said
in the output). Compile time is excluded (the kernel is warmed up first) and reported.
"""

from __future__ import annotations

import argparse
import os
import time

for _v in ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import clearance as cl  # noqa: E402
from clearance.dynamics.reference import reference_rhs  # noqa: E402
from clearance.kinematics.ik import drives_from_ik, inverse_kinematics  # noqa: E402
from clearance.scenario import build_mechanisms, default_scenario_path, load_scenario  # noqa: E402


def quat_rot(p: np.ndarray) -> np.ndarray:
    p = p / np.linalg.norm(p)
    e0, e = p[0], p[1:]
    et = np.array([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
    return (e0 * e0 - e @ e) * np.eye(3) + 2.0 * (np.outer(e, e) + e0 * et)


class NumpyContact:
    """Plain-NumPy ball-in-socket element (physics.md f, g.2 Flores, h.4 LuGre)."""

    def __init__(self, c: cl.Compiled) -> None:
        m = c.model
        self.nb, self.n = c.nb, m.nclr
        self.bs, self.bb = np.array(m.clr_bs), np.array(m.clr_bb)
        self.ps, self.pb = np.array(m.clr_ps), np.array(m.clr_pb)
        self.geo, self.par, self.fpar = (
            np.array(m.clr_geo),
            np.array(m.clr_par),
            np.array(m.clr_fpar),
        )
        self.in_contact = np.zeros(self.n, dtype=bool)
        self.ddm = np.zeros(self.n)

    def forces(self, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nb = self.nb
        Q = np.zeros(6 * nb)
        zdot = np.zeros_like(z)
        for k in range(self.n):
            s, b = self.bs[k], self.bb[k]
            Rs, Rb, c, vfloor = self.geo[k, :4]
            As = quat_rot(y[7 * s + 3 : 7 * s + 7]) if s >= 0 else np.eye(3)
            Ab = quat_rot(y[7 * b + 3 : 7 * b + 7])
            rs = y[7 * s : 7 * s + 3] if s >= 0 else np.zeros(3)
            rb = y[7 * b : 7 * b + 3]
            vs = y[7 * nb + 6 * s : 7 * nb + 6 * s + 6] if s >= 0 else np.zeros(6)
            vb = y[7 * nb + 6 * b : 7 * nb + 6 * b + 6]
            ws, wb = As @ vs[3:], Ab @ vb[3:]
            arm_s, arm_b = As @ self.ps[k], Ab @ self.pb[k]
            e = rb + arm_b - rs - arm_s
            el = np.linalg.norm(e)
            delta = el - c
            if delta <= 0:
                self.in_contact[k] = False
                continue
            n = e / el
            ddot = n @ (vb[:3] + np.cross(wb, arm_b) - vs[:3] - np.cross(ws, arm_s))
            if not self.in_contact[k]:  # latch the impact velocity at the first evaluation
                self.in_contact[k] = True
                self.ddm[k] = max(ddot, vfloor)
            K, nexp, cr = self.par[k, :3]
            fn = max(0.0, K * delta**nexp * (1 + 8 * (1 - cr) / (5 * cr) * ddot / self.ddm[k]))
            qs, qb = arm_s + Rs * n, arm_b + Rb * n
            vrel = vb[:3] + np.cross(wb, qb) - vs[:3] - np.cross(ws, qs)
            vt = vrel - (n @ vrel) * n
            v = np.linalg.norm(vt)
            s0, s1, s2, muc, mus, vsr, vd, vdamp = self.fpar[k]
            g = muc + (mus - muc) * np.exp(-((v / vsr) ** 2))
            zk = z[3 * k : 3 * k + 3]
            zd = vt - s0 * v * zk / g
            sig1 = s1 * np.exp(-((v / vd) ** 2)) if vdamp > 0.5 else s1
            ft = fn * (s0 * zk + sig1 * zd + s2 * vt)
            ft = ft - (ft @ n) * n
            zdot[3 * k : 3 * k + 3] = zd
            fb = -fn * n - ft
            Q[6 * b : 6 * b + 3] += fb
            Q[6 * b + 3 : 6 * b + 6] += Ab.T @ np.cross(qb, fb)
            if s >= 0:
                Q[6 * s : 6 * s + 3] -= fb
                Q[6 * s + 3 : 6 * s + 6] -= As.T @ np.cross(qs, fb)
        return Q, zdot


def setup():
    s = load_scenario(default_scenario_path())
    ideal, clr, info = build_mechanisms(s)
    ik = inverse_kinematics(
        ideal,
        info.platform_trajectory(),
        platform_marker=info.platform_marker,
        actuators=info.actuators,
        times=np.linspace(0, info.t_end, 101),
    )
    ideal, clr, info = build_mechanisms(s, drives=drives_from_ik(ik))
    return ideal, clr, info


def median_time(f, n: int, repeats: int = 5) -> float:
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            f()
        ts.append((time.perf_counter() - t0) / n)
    return float(np.median(ts))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline-interval", type=float, default=0.02)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    ideal, clr, info = setup()
    c = cl.compile_mechanism(clr)
    kw = dict(info.simulate_kwargs)
    t0 = time.perf_counter()
    cl.simulate(c, 1e-3, **kw)
    t_compile = time.perf_counter() - t0
    y0 = cl.initial_state(c, y0=None)
    r_ideal = cl.simulate(cl.compile_mechanism(ideal), 1e-6, t_out=np.array([0.0, 1e-6]))
    y0[: c.nq + c.nv] = np.r_[r_ideal.q[0], r_ideal.v[0]]
    alpha, beta = kw.get("baumgarte", (5.0, 5.0))

    # ---- per rhs, at a state in contact (after the ball has dropped)
    r = cl.simulate(c, 0.05, y0=y0, **kw)
    y_c = np.r_[r.q[-1], r.v[-1], np.zeros(c.ny - c.nq - c.nv)]
    f_c = cl.scipy_rhs(c, baumgarte=(alpha, beta))
    base_mech = clr.without(*c.mechanism.joints.keys() & {ci.name for ci in c.clearances})
    contact = NumpyContact(c)
    nq, nv, nz = c.nq, c.nv, 3 * c.nclr
    n_ref = 13 * c.nb + 5

    def f_numpy(t: float, Y: np.ndarray) -> np.ndarray:
        yr = np.zeros(n_ref)
        yr[: nq + nv] = Y[: nq + nv]
        z = Y[nq + nv : nq + nv + nz]
        Qc, zdot = contact.forces(yr, z)
        ydr, _ = reference_rhs(base_mech, t, yr, alpha=alpha, beta=beta, extra_q=Qc)
        return np.r_[ydr[: nq + nv], zdot]

    Y_c = np.r_[y_c[: nq + nv], y_c[c.iz : c.iw]]
    contact.in_contact[:] = True
    contact.ddm[:] = 0.1
    t_rhs_c = median_time(lambda: f_c(0.05, y_c), 2000)
    t_rhs_np = median_time(lambda: f_numpy(0.05, Y_c), 20)
    # cross-check: the two implementations agree at this state (v_dot part)
    wk_state = f_c(0.05, y_c)[nq : nq + nv]
    np_state = f_numpy(0.05, Y_c)[nq : nq + nv]
    agree = np.max(np.abs(wk_state - np_state)) / np.max(np.abs(wk_state))

    # ---- whole run, compiled, default tolerances
    walls, res = [], None
    for _ in range(a.repeats):
        res = cl.simulate(c, info.t_end, y0=y0, **kw)
        walls.append(res.stats["wall_time"])
    wall = float(np.median(walls))

    # ---- NumPy + solve_ivp baseline over a short interval, scaled to the full run
    contact.in_contact[:] = False
    Y0 = np.r_[y0[: nq + nv], np.zeros(nz)]
    tb = a.baseline_interval
    t0 = time.perf_counter()
    sol = solve_ivp(
        f_numpy, (0.0, tb), Y0, method="RK45", rtol=kw.get("rtol", 1e-6), atol=kw.get("atol", 1e-9)
    )
    wall_b = time.perf_counter() - t0
    res_short = cl.simulate(c, tb, y0=y0, **kw)
    # scale by the compiled run's rhs count per second of motion (contact persists after the
    # drop, so the first interval is representative or pessimistic for the baseline)
    scale_nfev = res.stats["nfev"] / max(res_short.stats["nfev"], 1)
    wall_b_full = wall_b * scale_nfev

    T = info.t_end
    print(
        f"default 4UPS-UPU clearance scenario: {T:g} s, {c.nb} bodies, {c.nrow} rows, "
        f"{c.nclr} clearance joints; rtol {kw.get('rtol')}, atol {kw.get('atol')}"
    )
    print(f"kernel compile/load before timing: {t_compile:.2f} s (excluded)")
    print(f"compiled vs NumPy rhs at a contact state agree to {agree:.1e} (relative v_dot)")
    print(f"{'':34s}{'compiled':>14s}{'NumPy baseline':>16s}{'ratio':>9s}")
    print(
        f"{'rhs (from Python) [us]':34s}{t_rhs_c * 1e6:14.1f}{t_rhs_np * 1e6:16.1f}"
        f"{t_rhs_np / t_rhs_c:9.0f}"
    )
    print(f"{'whole run wall [s]':34s}{wall:14.3f}{wall_b_full:16.1f}{wall_b_full / wall:9.0f}")
    print(f"{'real-time factor':34s}{T / wall:14.2f}{T / wall_b_full:16.4f}")
    print(
        f"compiled run: {res.stats['naccept']} steps, {res.stats['nfev']} rhs "
        f"({wall / res.stats['nfev'] * 1e6:.1f} us per rhs incl. events and output), "
        f"{len(res.impacts())} impacts"
    )
    print(
        f"baseline: solve_ivp RK45 over {tb:g} s ({sol.nfev} rhs, {wall_b:.1f} s), scaled by "
        f"the compiled run's rhs count ratio {scale_nfev:.0f} to {T:g} s"
    )
    print(f"target: real-time factor >= 5 -> {'MET' if T / wall >= 5 else 'NOT MET'}")


if __name__ == "__main__":
    main()
