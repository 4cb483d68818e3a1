"""Finite-difference proof of every constraint primitive, joint and driver (physics.md c.6).

For a compiled mechanism, `evaluate_rows(c, t, y)` returns phi, phi_t, phi_dot, gamma and the
dense Jacobian phi_q w.r.t. the velocity variables v = [r_dot, omega' (body frame)] per body.
The checks, at random states that need NOT satisfy the constraints (the functions are
defined off the manifold):

* phi_q (c.6 step 2): column 6 b + k of phi_q is the central difference (h = 1e-6) of phi
  along r_b += h e_k (k < 3) or p_b <- p_b (x) exp(h e_(k-3) / 2) (k >= 3; body-frame
  rotation, right quaternion product, physics.md b.1).
  Error max|FD - phi_q| / max(1, max|phi_q|) < 1e-6.
* phi_t and gamma (c.6 step 3): along the motion r(s) = r0 + s r_dot,
  p(s) = p0 (x) exp(s omega' / 2), t = t0 + s (constant v, so v_dot = 0):
  d phi / ds = phi_q v + phi_t and d2 phi / ds2 = -gamma (physics.md c.1: phi_ddot =
  phi_q v_dot - gamma). Central differences with h = 1e-4; errors
  max|FD - (phi_q v + phi_t)| / max(1, max(|phi_q| |v| + |phi_t|)) < 1e-6 (the scale is the
  size of the summed terms, so a cancelling phi_dot does not shrink it) and
  max|FD + gamma| / max(1, max|gamma|) < 1e-5.
* phi_dot returned by evaluate_rows equals phi_q v + phi_t (to rounding).
* phi itself equals an independent NumPy transcription of the joint and driver equations of
  physics.md c.3 (row order included), so the derivatives are derivatives of the right thing.

Random data: r, p (normalised), r_dot, omega' ~ N(0, 1) per body, marker points ~ N(0, 1),
random orthonormal right-handed marker triads, random time t0 in [-1, 1]; hypothesis draws the
seed of the Gaussian generator plus the discrete choices (joint type, which body is i and j,
ground on either side, time functions, Euler sequence). The mechanism always has three moving
bodies, so the columns of the uninvolved body are checked to be zero too.

The mutation tests at the end show that the comparisons fail for a flipped Jacobian column,
for a world-frame instead of body-frame rotation increment, for mutated gamma formulas and for
a wrong sign of phi_t. Quaternion helpers are written here, independent of the package.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import clearance as cl
from clearance.analysis.assembly import Rows, evaluate_rows
from clearance.dynamics.rhs import make_work
from clearance.layout import NWORK

H_Q = 1e-6  # FD step of the Jacobian columns (c.6 step 2)
H_S = 1e-4  # FD step along the motion (c.6 step 3)
TOL_Q = 1e-6
TOL_1 = 1e-6
TOL_2 = 1e-5

NB = 3
BODY_NAMES = ("A", "B", "C")
JOINTS = {
    "Spherical": cl.Spherical,
    "Universal": cl.Universal,
    "Revolute": cl.Revolute,
    "Cylindrical": cl.Cylindrical,
    "Prismatic": cl.Prismatic,
    "Fixed": cl.Fixed,
}
SEQUENCES = tuple("".join(s) for s in itertools.product("xyz", repeat=3))

FD_SETTINGS = settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)


# --------------------------------------------------------------------------- quaternions
def qmul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """p (x) q = [p0 q0 - pv.qv ; p0 qv + q0 pv + pv x qv] (physics.md b.1)."""
    p0, pv, q0, qv = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[p0 * q0 - pv @ qv], p0 * qv + q0 * pv + np.cross(pv, qv)])


def qexp(u: np.ndarray) -> np.ndarray:
    """exp of the pure quaternion (0, u): [cos|u|, sin|u| u/|u|]."""
    a = float(np.linalg.norm(u))
    if a == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[math.cos(a)], math.sin(a) / a * u])


def rotmat(p: np.ndarray) -> np.ndarray:
    """A(p) = (e0^2 - e.e) I + 2 (e e^T + e0 e~) of p/|p| (physics.md b.1)."""
    p = p / np.linalg.norm(p)
    e0, e = p[0], p[1:]
    return (e0 * e0 - e @ e) * np.eye(3) + 2.0 * (np.outer(e, e) + e0 * skew(e))


def skew(x: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]])


def rot_axis(axis: int, th: float) -> np.ndarray:
    """Elementary rotation matrix about world axis 0, 1, 2 (x, y, z)."""
    c, s = math.cos(th), math.sin(th)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def body_increment(p: np.ndarray, dth: np.ndarray) -> np.ndarray:
    """p (x) exp(dth'/2): body-frame rotation increment (what omega' columns mean)."""
    return qmul(p, qexp(0.5 * dth))


def world_increment(p: np.ndarray, dth: np.ndarray) -> np.ndarray:
    """exp(dth/2) (x) p: WORLD-frame increment; used only by a mutation test."""
    return qmul(qexp(0.5 * dth), p)


def random_triad(rng: np.random.Generator) -> np.ndarray:
    """Random orthonormal right-handed triad (columns f, g, h)."""
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    if np.linalg.det(Q) < 0:
        Q[:, 0] = -Q[:, 0]
    return Q


# --------------------------------------------------------------------------- FD machinery
def q_index(b: int) -> int:
    return 7 * b


def v_index(b: int) -> int:
    return 7 * NB + 6 * b


def perturbed(y: np.ndarray, b: int, k: int, h: float, increment=body_increment) -> np.ndarray:
    """y with velocity direction k (0..5) of body b moved by h (r += h e_k, p <- p exp)."""
    y = y.copy()
    q = q_index(b)
    if k < 3:
        y[q + k] += h
    else:
        e = np.zeros(3)
        e[k - 3] = h
        y[q + 3 : q + 7] = increment(y[q + 3 : q + 7], e)
    return y


def fd_jacobian(c: cl.Compiled, t: float, y: np.ndarray, *, increment=body_increment):
    """Central-difference phi_q (m, 6 nb), h = H_Q, columns in the order of v."""
    wk = make_work(c.model)
    J = np.empty((c.nrow, c.nv))
    for b in range(NB):
        for k in range(6):
            fp = evaluate_rows(c, t, perturbed(y, b, k, H_Q, increment), wk).phi
            fm = evaluate_rows(c, t, perturbed(y, b, k, -H_Q, increment), wk).phi
            J[:, 6 * b + k] = (fp - fm) / (2.0 * H_Q)
    return J


def along_motion(y0: np.ndarray, s: float) -> np.ndarray:
    """State at s on r(s) = r0 + s r_dot, p(s) = p0 (x) exp(s omega'/2) (v constant)."""
    y = y0.copy()
    for b in range(NB):
        q, v = q_index(b), v_index(b)
        y[q : q + 3] = y0[q : q + 3] + s * y0[v : v + 3]
        y[q + 3 : q + 7] = body_increment(y0[q + 3 : q + 7], s * y0[v + 3 : v + 6])
    return y


def fd_motion(c: cl.Compiled, t0: float, y0: np.ndarray):
    """First and second central differences (h = H_S) of phi along the motion, t = t0 + s."""
    wk = make_work(c.model)
    fp = evaluate_rows(c, t0 + H_S, along_motion(y0, H_S), wk).phi
    f0 = evaluate_rows(c, t0, y0, wk).phi
    fm = evaluate_rows(c, t0 - H_S, along_motion(y0, -H_S), wk).phi
    return (fp - fm) / (2.0 * H_S), (fp - 2.0 * f0 + fm) / (H_S * H_S)


def rel(err: np.ndarray, ref: np.ndarray) -> float:
    """max|err| / max(1, max|ref|): relative to the analytic magnitude, absolute below 1."""
    if err.size == 0:
        return 0.0
    return float(np.max(np.abs(err)) / max(1.0, float(np.max(np.abs(ref)))))


@dataclass(frozen=True)
class FdErrors:
    """Relative FD errors of phi_q, d phi/ds = phi_q v + phi_t and d2 phi/ds2 = -gamma."""

    phi_q: float
    first: float
    second: float

    def ok(self) -> bool:
        return self.phi_q < TOL_Q and self.first < TOL_1 and self.second < TOL_2


def fd_errors(
    c: cl.Compiled, t0: float, y0: np.ndarray, rows: Rows, *, increment=body_increment
) -> FdErrors:
    """Compare the analytic `rows` (possibly a mutated copy) against finite differences."""
    v = y0[7 * NB : 13 * NB]
    J_fd = fd_jacobian(c, t0, y0, increment=increment)
    d1, d2 = fd_motion(c, t0, y0)
    phid = rows.phi_q @ v + rows.phi_t
    terms = np.abs(rows.phi_q) @ np.abs(v) + np.abs(rows.phi_t)  # size of the summed terms
    return FdErrors(
        phi_q=rel(J_fd - rows.phi_q, rows.phi_q),
        first=rel(d1 - phid, terms),
        second=rel(d2 + rows.gamma, rows.gamma),
    )


# --------------------------------------------------------------------------- scenes
@dataclass(frozen=True)
class MarkerSpec:
    name: str
    body: int  # -1 = ground
    sb: np.ndarray  # point, body components (world for the ground)
    T: np.ndarray  # triad columns f, g, h, body components (world for the ground)

    def marker(self) -> cl.Marker:
        body = cl.GROUND if self.body < 0 else BODY_NAMES[self.body]
        return cl.Marker(self.name, body, self.sb, self.T)

    def world(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Marker point and triad in world components at state y."""
        if self.body < 0:
            return self.sb, self.T
        q = q_index(self.body)
        A = rotmat(y[q + 3 : q + 7])
        return y[q : q + 3] + A @ self.sb, A @ self.T


@dataclass(frozen=True)
class Scene:
    """A compiled mechanism at a random state, with an independent phi(y, t)."""

    compiled: cl.Compiled
    t0: float
    y0: np.ndarray
    ref_phi: Callable[[np.ndarray, float], np.ndarray]


def random_state(rng: np.random.Generator) -> np.ndarray:
    """y = [q | v | work] with r, p (normalised), r_dot, omega' ~ N(0, 1)."""
    y = np.zeros(13 * NB + NWORK)  # no clearance joints: q | v | work integrals
    for b in range(NB):
        q, v = q_index(b), v_index(b)
        y[q : q + 3] = rng.normal(size=3)
        p = rng.normal(size=4)
        y[q + 3 : q + 7] = p / np.linalg.norm(p)
        y[v : v + 6] = rng.normal(size=6)
    return y


def bodies_of(y: np.ndarray) -> list[cl.Body]:
    out = []
    for b, name in enumerate(BODY_NAMES):
        q, v = q_index(b), v_index(b)
        out.append(
            cl.Body(
                name,
                1.0 + b,
                (1.0, 2.0, 2.5),
                position=y[q : q + 3],
                orientation=y[q + 3 : q + 7],
                velocity=y[v : v + 3],
                angular_velocity=y[v + 3 : v + 6],
            )
        )
    return out


def random_marker(rng: np.random.Generator, name: str, body: int) -> MarkerSpec:
    return MarkerSpec(name, body, rng.normal(size=3), random_triad(rng))


def joint_phi(kind: str, mi: MarkerSpec, mj: MarkerSpec, y: np.ndarray) -> list[float]:
    """Rows of physics.md c.3, in the documented order, from world marker data."""
    (pi, Ti), (pj, Tj) = mi.world(y), mj.world(y)
    fi, gi, hi = Ti.T
    fj, gj, hj = Tj.T
    d = pj - pi
    cyl = [fi @ hj, gi @ hj, fi @ d, gi @ d]
    return {
        "Spherical": [*d],
        "Universal": [*d, hi @ hj],
        "Revolute": [*d, fi @ hj, gi @ hj],
        "Cylindrical": cyl,
        "Prismatic": [*cyl, fi @ gj],
        "Fixed": [*d, fi @ gj, gi @ hj, hi @ fj],
    }[kind]


def orientation_target(angles, sequence: str, t: float) -> np.ndarray:
    """R(t) = R_a(t1) R_b(t2) R_c(t3) for the sequence "abc" (moving axes)."""
    R = np.eye(3)
    for fn, ch in zip(angles, sequence, strict=True):
        R = R @ rot_axis("xyz".index(ch), fn(t))
    return R


def build(
    y: np.ndarray, markers: list[MarkerSpec], elements: list, t0: float, phi_parts: list
) -> Scene:
    mech = cl.Mechanism("fd", gravity=(0.0, 0.0, 0.0))
    mech.add(bodies_of(y), [m.marker() for m in markers], elements)
    c = cl.compile_mechanism(mech)
    np.testing.assert_allclose(c.y0, y, rtol=0, atol=1e-15)  # state layout as documented

    def ref_phi(yy: np.ndarray, t: float) -> np.ndarray:
        return np.array([x for part in phi_parts for x in part(yy, t)], dtype=float)

    return Scene(c, t0, y, ref_phi)


# --------------------------------------------------------------------------- strategies
seeds = st.integers(0, 2**32 - 1)
times = st.floats(-1.0, 1.0, allow_subnormal=False)
GROUND_CASES = ("none", "i", "j")


def fl(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_subnormal=False)


# Time functions whose third and fourth derivatives stay below ~1e2 at the sampled times, so
# the truncation errors (h^2/6) f_ddd and (h^2/12) f_dddd of the h = 1e-4 stencils are ~1e-7.
@st.composite
def polynomials(draw: st.DrawFn) -> cl.Polynomial:
    c = draw(st.lists(fl(-1.0, 1.0), min_size=1, max_size=6))
    return cl.Polynomial(tuple(ck / math.factorial(k) for k, ck in enumerate(c)), draw(times))


@st.composite
def ramps(draw: st.DrawFn) -> cl.Ramp:
    t_start = draw(fl(-2.0, 0.5))
    return cl.Ramp(
        draw(fl(-0.5, 0.5)),
        draw(fl(-0.5, 0.5)),
        t_start,
        t_start + draw(fl(1.5, 3.0)),
        draw(st.sampled_from(("quintic", "cycloidal", "cosine"))),
    )


@st.composite
def tabulated(draw: st.DrawFn) -> cl.Tabulated:
    gaps = draw(st.lists(fl(0.5, 1.0), min_size=2, max_size=5))
    x = np.concatenate([[draw(fl(-2.0, -0.5))], gaps]).cumsum()
    yv = draw(st.lists(fl(-0.5, 0.5), min_size=x.size, max_size=x.size))
    bc = draw(st.sampled_from(("not-a-knot", "natural", "clamped")))
    return cl.Tabulated(tuple(x), tuple(yv), bc)


time_functions = st.one_of(
    st.builds(cl.Sinusoid, fl(-1.5, 1.5), fl(0.1, 2.5), fl(-math.pi, math.pi), fl(-1.0, 1.0)),
    polynomials(),
    ramps(),
    tabulated(),
)


def breakpoints(fn) -> tuple[float, ...]:
    """Times where f, f_dot or f_ddot (or f''') is not smooth; the FD stencil must avoid them."""
    if isinstance(fn, cl.Ramp):
        return (fn.t_start, fn.t_end)
    if isinstance(fn, cl.Tabulated):
        return fn.times
    return ()


def assume_smooth(t0: float, *fns) -> None:
    assume(all(abs(t0 - k) > 10 * H_S for f in fns for k in breakpoints(f)))


@st.composite
def body_pairs(draw: st.DrawFn, ground: str) -> tuple[int, int]:
    """(i, j) body indices (-1 = ground) for the ground case "none", "i" or "j"."""
    if ground == "i":
        return -1, draw(st.integers(0, NB - 1))
    if ground == "j":
        return draw(st.integers(0, NB - 1)), -1
    perm = draw(st.permutations(range(NB)))
    return perm[0], perm[1]


def check_scene(sc: Scene) -> None:
    """All c.6 checks plus phi against the independent reference and phi_dot consistency."""
    c, t0, y0 = sc.compiled, sc.t0, sc.y0
    rows = evaluate_rows(c, t0, y0)
    phi_ref = sc.ref_phi(y0, t0)
    assert rows.phi.shape == phi_ref.shape
    np.testing.assert_allclose(rows.phi, phi_ref, rtol=1e-12, atol=1e-12)
    v = y0[7 * NB : 13 * NB]
    phid = rows.phi_q @ v + rows.phi_t
    np.testing.assert_allclose(rows.phi_dot, phid, rtol=1e-12, atol=1e-12)
    err = fd_errors(c, t0, y0, rows)
    assert err.phi_q < TOL_Q, f"phi_q vs FD: {err}"
    assert err.first < TOL_1, f"phi_q v + phi_t vs FD: {err}"
    assert err.second < TOL_2, f"-gamma vs FD: {err}"


# --------------------------------------------------------------------------- joint scenes
def joint_scene(
    kind: str, i: int, j: int, seed: int, t0: float
) -> tuple[Scene, MarkerSpec, MarkerSpec]:
    """One joint of `kind` from a marker on body i to one on body j (-1 = ground)."""
    rng = np.random.default_rng(seed)
    y = random_state(rng)
    mi, mj = random_marker(rng, "Mi", i), random_marker(rng, "Mj", j)
    sc = build(
        y,
        [mi, mj],
        [JOINTS[kind]("jt", "Mi", "Mj")],
        t0,
        [lambda yy, t: joint_phi(kind, mi, mj, yy)],
    )
    return sc, mi, mj


@pytest.mark.parametrize("ground", GROUND_CASES)
@pytest.mark.parametrize("kind", list(JOINTS))
@FD_SETTINGS
@given(data=st.data(), seed=seeds, t0=times)
def test_joint_fd(kind: str, ground: str, data: st.DataObject, seed: int, t0: float) -> None:
    """Joints of c.3 (spherical, dot-1 and dot-2 primitives): phi_q, phi_t, gamma by FD."""
    i, j = data.draw(body_pairs(ground))
    check_scene(joint_scene(kind, i, j, seed, t0)[0])


# --------------------------------------------------------------------------- driver scenes
@pytest.mark.parametrize("ground", GROUND_CASES)
@pytest.mark.parametrize("joint", ["Prismatic", "Cylindrical"])
@FD_SETTINGS
@given(data=st.data(), seed=seeds, t0=times, fn=time_functions)
def test_prismatic_driver_fd(
    joint: str, ground: str, data: st.DataObject, seed: int, t0: float, fn
) -> None:
    """PrismaticDriver phi = h_i . d - s(t) (dot-2 with phi_t = -s_dot, gamma += s_ddot)."""
    assume_smooth(t0, fn)
    i, j = data.draw(body_pairs(ground))
    rng = np.random.default_rng(seed)
    y = random_state(rng)
    mi, mj = random_marker(rng, "Mi", i), random_marker(rng, "Mj", j)

    def drv(yy: np.ndarray, t: float) -> list[float]:
        (pi, Ti), (pj, _) = mi.world(yy), mj.world(yy)
        return [Ti[:, 2] @ (pj - pi) - fn(t)]

    sc = build(
        y,
        [mi, mj],
        [JOINTS[joint]("jt", "Mi", "Mj"), cl.PrismaticDriver("drv", "jt", fn)],
        t0,
        [lambda yy, t: joint_phi(joint, mi, mj, yy), drv],
    )
    check_scene(sc)


@pytest.mark.parametrize("ground", GROUND_CASES)
@pytest.mark.parametrize("squared", [False, True])
@FD_SETTINGS
@given(data=st.data(), seed=seeds, t0=times, fn=time_functions)
def test_distance_driver_fd(
    squared: bool, ground: str, data: st.DataObject, seed: int, t0: float, fn
) -> None:
    """DistanceDriver |d| - l(t) (length form) and d.d - l(t)^2 (squared form)."""
    assume_smooth(t0, fn)
    i, j = data.draw(body_pairs(ground))
    rng = np.random.default_rng(seed)
    y = random_state(rng)
    mi, mj = random_marker(rng, "Mi", i), random_marker(rng, "Mj", j)

    def drv(yy: np.ndarray, t: float) -> list[float]:
        d = mj.world(yy)[0] - mi.world(yy)[0]
        return [d @ d - fn(t) ** 2] if squared else [np.linalg.norm(d) - fn(t)]

    # the length form is singular at |d| = 0 (u = d/|d|); stay clear of it along the stencil
    assume(np.linalg.norm(mj.world(y)[0] - mi.world(y)[0]) > 0.3)
    sc = build(y, [mi, mj], [cl.DistanceDriver("drv", "Mi", "Mj", fn, squared=squared)], t0, [drv])
    check_scene(sc)


@FD_SETTINGS
@given(body=st.integers(0, NB - 1), seed=seeds, t0=times, fn=time_functions)
def test_position_driver_fd(body: int, seed: int, t0: float, fn) -> None:
    """PositionDriver c . r_P - f(t) (coordinate difference with i = ground), random axis c."""
    assume_smooth(t0, fn)
    rng = np.random.default_rng(seed)
    y = random_state(rng)
    mj = random_marker(rng, "Mj", body)
    axis = rng.normal(size=3)
    c_hat = axis / np.linalg.norm(axis)

    def drv(yy: np.ndarray, t: float) -> list[float]:
        return [c_hat @ mj.world(yy)[0] - fn(t)]

    sc = build(y, [mj], [cl.PositionDriver("drv", "Mj", tuple(axis), fn)], t0, [drv])
    check_scene(sc)


@pytest.mark.parametrize("mode", ["full", "axis"])
@FD_SETTINGS
@given(
    body=st.integers(0, NB - 1),
    seed=seeds,
    t0=times,
    angles=st.lists(time_functions, min_size=3, max_size=3),
    sequence=st.sampled_from(SEQUENCES),
)
def test_orientation_driver_fd(
    mode: str, body: int, seed: int, t0: float, angles: list, sequence: str
) -> None:
    """OrientationDriver: dot-1 rows with the moving ground vector c(t) = R(t) e_m
    (DOT1_MOVING): full f.R ey, g.R ez, h.R ex; axis h.R ex, h.R ey (R = R_a R_b R_c)."""
    assume_smooth(t0, *angles)
    rng = np.random.default_rng(seed)
    y = random_state(rng)
    mj = random_marker(rng, "Mj", body)
    pairs = [(0, 1), (1, 2), (2, 0)] if mode == "full" else [(2, 0), (2, 1)]

    def drv(yy: np.ndarray, t: float) -> list[float]:
        T = mj.world(yy)[1]
        R = orientation_target(angles, sequence, t)
        return [T[:, col] @ R[:, m] for col, m in pairs]

    od = cl.OrientationDriver("drv", "Mj", tuple(angles), sequence, mode)
    check_scene(build(y, [mj], [od], t0, [drv]))


# --------------------------------------------------------------------------- everything at once
@FD_SETTINGS
@given(data=st.data(), seed=seeds, t0=times, fns=st.lists(time_functions, min_size=8, max_size=8))
def test_combined_mechanism_fd(data: st.DataObject, seed: int, t0: float, fns: list) -> None:
    """All joint types and drivers in one mechanism on three bodies: the row blocks are
    scattered into the right columns of phi_q and stacked in the declared order."""
    assume_smooth(t0, *fns)
    rng = np.random.default_rng(seed)
    y = random_state(rng)
    markers: list[MarkerSpec] = []
    elements: list = []
    parts: list = []
    for kind in JOINTS:
        i, j = data.draw(body_pairs(data.draw(st.sampled_from(GROUND_CASES))))
        mi = random_marker(rng, f"{kind}_i", i)
        mj = random_marker(rng, f"{kind}_j", j)
        markers += [mi, mj]
        elements.append(JOINTS[kind](kind, mi.name, mj.name))
        parts.append(lambda yy, t, kind=kind, mi=mi, mj=mj: joint_phi(kind, mi, mj, yy))
    pm_i, pm_j = markers[8], markers[9]  # the Prismatic joint's markers
    elements.append(cl.PrismaticDriver("pdrv", "Prismatic", fns[0]))
    parts.append(
        lambda yy, t: [
            pm_i.world(yy)[1][:, 2] @ (pm_j.world(yy)[0] - pm_i.world(yy)[0]) - fns[0](t)
        ]
    )
    da, db = markers[0], markers[3]  # Spherical_i and Universal_j
    assume(da.body != db.body)
    elements.append(cl.DistanceDriver("dist2", da.name, db.name, fns[1], squared=True))
    parts.append(lambda yy, t: [np.sum((db.world(yy)[0] - da.world(yy)[0]) ** 2) - fns[1](t) ** 2])
    mp = random_marker(rng, "pos", data.draw(st.integers(0, NB - 1)))
    markers.append(mp)
    elements.append(cl.PositionDriver("posx", "pos", (1.0, 0.0, 0.0), fns[2]))
    parts.append(lambda yy, t: [mp.world(yy)[0][0] - fns[2](t)])
    for mode, seq, fs in (("full", "zxz", fns[3:6]), ("axis", "yxz", (fns[6], fns[7], 0.3))):
        mo = random_marker(rng, f"M_ori_{mode}", data.draw(st.integers(0, NB - 1)))
        markers.append(mo)
        pairs = [(0, 1), (1, 2), (2, 0)] if mode == "full" else [(2, 0), (2, 1)]
        angles = tuple(cl.Constant(a) if isinstance(a, float) else a for a in fs)
        elements.append(cl.OrientationDriver(f"ori_{mode}", mo.name, angles, seq, mode))

        def ori(yy, t, mo=mo, angles=angles, seq=seq, pairs=pairs):
            T, R = mo.world(yy)[1], orientation_target(angles, seq, t)
            return [T[:, col] @ R[:, m] for col, m in pairs]

        parts.append(ori)
    sc = build(y, markers, elements, t0, parts)
    assert sc.compiled.nrow == 3 + 4 + 5 + 4 + 5 + 6 + 1 + 1 + 1 + 3 + 2
    check_scene(sc)


# --------------------------------------------------------------------------- helper self-checks
@given(seed=seeds)
@settings(max_examples=20, deadline=None)
def test_quaternion_helpers(seed: int) -> None:
    """p (x) exp(dth'/2) rotates in the body frame: A <- A exp(dth'~) (Rodrigues), and the
    world-frame product is A <- exp(dth~) A (b.1); also A(p) is orthonormal."""
    rng = np.random.default_rng(seed)
    p = rng.normal(size=4)
    p /= np.linalg.norm(p)
    dth = rng.normal(size=3)
    a = np.linalg.norm(dth)
    K = skew(dth / a)
    Rod = np.eye(3) + math.sin(a) * K + (1.0 - math.cos(a)) * K @ K
    A = rotmat(p)
    np.testing.assert_allclose(A.T @ A, np.eye(3), atol=1e-14)
    np.testing.assert_allclose(rotmat(body_increment(p, dth)), A @ Rod, atol=1e-13)
    np.testing.assert_allclose(rotmat(world_increment(p, dth)), Rod @ A, atol=1e-13)
    np.testing.assert_allclose(
        rot_axis(2, 0.3) @ [1.0, 0.0, 0.0], [math.cos(0.3), math.sin(0.3), 0]
    )


# --------------------------------------------------------------------------- mutation checks
MUTATION_SEED = 20240611


def test_mutation_flipped_jacobian_column_fails() -> None:
    """Flip the sign of one omega' column of phi_q (test's copy): the FD check must fail."""
    sc = joint_scene("Revolute", 0, 2, MUTATION_SEED, 0.2)[0]
    rows = evaluate_rows(sc.compiled, sc.t0, sc.y0)
    assert fd_errors(sc.compiled, sc.t0, sc.y0, rows).ok()
    col = 6 * 2 + 3 + int(np.argmax(np.abs(rows.phi_q[:, 15:18]).max(axis=0)))
    J = rows.phi_q.copy()
    J[:, col] *= -1.0
    err = fd_errors(
        sc.compiled, sc.t0, sc.y0, Rows(rows.phi, rows.phi_t, rows.phi_dot, rows.gamma, J)
    )
    assert err.phi_q > 1e3 * TOL_Q
    assert err.first > 1e3 * TOL_1  # phi_q v changes as well (omega'_k != 0)


def test_mutation_world_frame_increment_fails() -> None:
    """Perturbing p by exp(h e_k/2) (x) p (world frame) instead of the body-frame product
    must disagree with the omega' columns: the test sees which rotation the columns use."""
    sc = joint_scene("Fixed", -1, 1, MUTATION_SEED, -0.4)[0]
    rows = evaluate_rows(sc.compiled, sc.t0, sc.y0)
    err = fd_errors(sc.compiled, sc.t0, sc.y0, rows, increment=world_increment)
    assert err.phi_q > 1e3 * TOL_Q


def dot1_gamma(
    ai: np.ndarray, aj: np.ndarray, wi: np.ndarray, wj: np.ndarray, *, mutant: str = ""
) -> float:
    """gamma of dot-1 (c.2): -[a_j.ww(w_i,a_i) + a_i.ww(w_j,a_j) + 2 (w_i x a_i).(w_j x a_j)].

    mutant "coef": factor 1 instead of 2 on the cross term; "body": w_i used for body j.
    """

    def ww(w, s):
        return np.cross(w, np.cross(w, s))

    coef = 1.0 if mutant == "coef" else 2.0
    wj_used = wi if mutant == "body" else wj
    return -(
        aj @ ww(wi, ai) + ai @ ww(wj_used, aj) + coef * np.cross(wi, ai) @ np.cross(wj_used, aj)
    )


@pytest.mark.parametrize("mutant", ["coef", "body"])
def test_mutation_gamma_formula_fails(mutant: str) -> None:
    """An independent transcription of the universal joint's dot-1 gamma matches the package;
    replacing it by a mutated formula (wrong factor, wrong body's omega) fails the FD check."""
    sc, mi, mj = joint_scene("Universal", 1, 0, MUTATION_SEED, 0.7)
    c, t0, y0 = sc.compiled, sc.t0, sc.y0
    rows = evaluate_rows(c, t0, y0)
    ai, aj = mi.world(y0)[1][:, 2], mj.world(y0)[1][:, 2]

    def w_world(b: int) -> np.ndarray:
        return rotmat(y0[q_index(b) + 3 : q_index(b) + 7]) @ y0[v_index(b) + 3 : v_index(b) + 6]

    wi, wj = w_world(1), w_world(0)
    assert dot1_gamma(ai, aj, wi, wj) == pytest.approx(rows.gamma[3], rel=1e-12, abs=1e-12)
    assert fd_errors(c, t0, y0, rows).ok()
    gam = rows.gamma.copy()
    gam[3] = dot1_gamma(ai, aj, wi, wj, mutant=mutant)
    err = fd_errors(c, t0, y0, Rows(rows.phi, rows.phi_t, rows.phi_dot, gam, rows.phi_q))
    assert err.second > 1e3 * TOL_2


def test_mutation_phi_t_sign_fails() -> None:
    """A driver's phi_t with the wrong sign (+s_dot instead of -s_dot) fails d phi/ds."""
    fn = cl.Sinusoid(0.8, 2.0, 0.3, 0.1)
    rng = np.random.default_rng(MUTATION_SEED)
    y = random_state(rng)
    mi, mj = random_marker(rng, "Mi", -1), random_marker(rng, "Mj", 2)
    sc = build(
        y,
        [mi, mj],
        [cl.Cylindrical("jt", "Mi", "Mj"), cl.PrismaticDriver("drv", "jt", fn)],
        0.1,
        [],
    )
    rows = evaluate_rows(sc.compiled, sc.t0, sc.y0)
    assert fd_errors(sc.compiled, sc.t0, sc.y0, rows).ok()
    assert rows.phi_t[-1] == pytest.approx(-fn.derivatives(0.1)[1], rel=1e-14)
    phit = rows.phi_t.copy()
    phit[-1] *= -1.0
    err = fd_errors(
        sc.compiled, sc.t0, sc.y0, Rows(rows.phi, phit, rows.phi_dot, rows.gamma, rows.phi_q)
    )
    assert err.first > 1e3 * TOL_1
