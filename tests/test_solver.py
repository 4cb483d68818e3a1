"""The constrained solve: Schur complement with a sparse Cholesky vs dense augmented LU vs
least squares, and the rank check that names redundant joints (physics.md c.5, d.3)."""

import numpy as np
import pytest

import clearance as cl
from clearance.dynamics.rhs import make_work, rhs


def _door(redundant: bool):
    """A door hinged to the ground by two revolute joints on one axis (redundant: 10 rows for
    5 independent constraints) or by one."""
    m = cl.Mechanism("door", gravity=(0, 0, -9.81))
    m.add(cl.Body("door", 20.0, (1.5, 1.2, 0.3), position=(0.4, 0, 0.0)))
    m.add(
        cl.Marker.on_axis("g1", "ground", (0, 0, 0.5), axis=(0, 0, 1)),
        cl.Marker.on_axis("d1", "door", (-0.4, 0, 0.5), axis=(0, 0, 1)),
        cl.Revolute("hinge_top", "g1", "d1"),
    )
    if redundant:
        m.add(
            cl.Marker.on_axis("g2", "ground", (0, 0, -0.5), axis=(0, 0, 1)),
            cl.Marker.on_axis("d2", "door", (-0.4, 0, -0.5), axis=(0, 0, 1)),
            cl.Revolute("hinge_bottom", "g2", "d2"),
        )
    # tilt gravity so that the door swings: gravity along -x in the hinge frame
    m.gravity = (-1.0, 0.5, -9.81)
    return m


def _eval(c, y, solver):
    wk = make_work(c.model)
    yd = np.empty_like(y)
    st = rhs(0.3, y, c.model, wk, cl.contact_state(c), 5.0, 5.0, solver, yd)
    return st, yd, wk.lam.copy()


def test_schur_equals_dense_on_random_states():
    from clearance.mechanisms.examples import double_pendulum

    c = cl.compile_mechanism(double_pendulum())
    rng = np.random.default_rng(0)
    for _ in range(5):
        y = c.y0.copy()
        y[: c.nq] += 0.1 * rng.normal(size=c.nq)
        y[c.nq : c.nq + c.nv] = rng.normal(size=c.nv)
        s0, yd0, l0 = _eval(c, y, 0)
        s1, yd1, l1 = _eval(c, y, 1)
        assert s0 == s1 == 0
        assert np.allclose(yd0, yd1, rtol=1e-10, atol=1e-10)
        assert np.allclose(l0, l1, rtol=1e-10, atol=1e-10)


def test_redundant_hinges_detected_and_simulated():
    c1 = cl.compile_mechanism(_door(False))
    c2 = cl.compile_mechanism(_door(True))
    y1 = cl.assemble(c1)
    y2 = cl.assemble(c2)
    rep = cl.rank_check(c2, 0.0, y2)
    assert rep.nrow == 10 and rep.rank == 5 and rep.dof == 1 and rep.redundant == 5
    assert set(rep.involved) == {"hinge_top", "hinge_bottom"}
    assert cl.rank_check(c1, 0.0, y1).full_rank
    # Schur Cholesky refuses the singular S; least squares gives the unique v_dot
    st, _, _ = _eval(c2, y2, 0)
    assert st == 1
    st, yd2, lam2 = _eval(c2, y2, 2)
    _, yd1, _ = _eval(c1, y1, 0)
    assert st == 0
    assert np.allclose(yd2[c2.nq : c2.nq + c2.nv], yd1[c1.nq : c1.nq + c1.nv], atol=1e-9)
    # auto picks least squares, and the redundant door moves like the single-hinge door
    r1 = cl.simulate(c1, 1.0, rtol=1e-9, atol=1e-12)
    r2 = cl.simulate(c2, 1.0, rtol=1e-9, atol=1e-12)
    assert r2.success and r2.settings["solver_used"] == "lstsq"
    assert np.max(np.abs(r1.q - r2.q)) < 1e-7
    # total reaction (sum of both hinges) equals the single hinge reaction
    f1 = r1.reaction("hinge_top")[0]
    f2 = r2.reaction("hinge_top")[0] + r2.reaction("hinge_bottom")[0]
    assert np.allclose(f1, f2, atol=1e-6 * np.max(np.abs(f1)))


def test_singular_failure_returns_partial_result():
    c = cl.compile_mechanism(_door(True))
    r = cl.simulate(c, 0.5, solver="schur")
    assert not r.success and r.status == 1
    assert "singular" in r.message
    assert r.t.size >= 1  # what was computed is kept


def test_inertia_inverse_by_cofactors_matches_lapack():
    """The 3x3 inverse of the time-varying inertias (cofactors, no LAPACK in the kernel)
    against numpy's LU inverse, on random symmetric positive definite matrices spanning
    four decades of scale and conditioning: error within cond(A) x a few eps."""
    from clearance.dynamics.rhs import _inverse

    rng = np.random.default_rng(7)
    out = np.empty((3, 3))
    for _ in range(500):
        b = rng.normal(size=(3, 3))
        a = (b @ b.T + np.diag(rng.uniform(1e-3, 1.0, 3))) * 10.0 ** rng.uniform(-4, 2)
        _inverse(a, out)
        ref = np.linalg.inv(a)
        err = np.abs(out - ref).max() / np.abs(ref).max()
        assert err <= 8 * np.finfo(float).eps * np.linalg.cond(a)
        np.testing.assert_allclose(a @ out, np.eye(3), atol=8e-16 * np.linalg.cond(a))


def test_symbolic_cholesky_pattern_equals_lapack_factors_nonzeros():
    """The compile-time pattern of L (fill included) is exactly the set of non-zeros of
    LAPACK's Cholesky factor of random sparse SPD matrices (random values: no exact
    cancellation), so the sparse factorisation skips only exact zeros."""
    from clearance.compile.compiled import _symbolic_cholesky

    rng = np.random.default_rng(11)
    for _ in range(300):
        n = int(rng.integers(1, 30))
        a = np.zeros((n, n))
        mask = np.tril(rng.random((n, n)) < rng.uniform(0.03, 0.4), -1)
        a[mask] = rng.normal(size=mask.sum())
        a = a + a.T
        a += np.diag(np.abs(a).sum(axis=1) + 1.0)  # diagonally dominant: SPD
        entries = {n * i + j for i in range(n) for j in range(i + 1) if a[i, j] != 0.0}
        pattern = _symbolic_cholesky(n, entries)
        low = np.linalg.cholesky(a)
        for i in range(n):
            assert pattern[i] == [k for k in range(i) if low[i, k] != 0.0]


def _seed(which: str, sparse: bool, monkeypatch) -> cl.Compiled:
    """A seed mechanism compiled with the sparse (or the envelope) Cholesky forced."""
    from clearance.compile import compiled
    from clearance.mechanisms.sps_cu import sps_cu
    from clearance.mechanisms.ups_upu import ups_upu_ideal

    monkeypatch.setattr(compiled, "SPARSE_RATIO", float("inf") if sparse else 0.0)
    c = cl.compile_mechanism(ups_upu_ideal() if which == "ups_upu" else sps_cu(limbs="two-body"))
    assert c.model.sch_sparse == int(sparse)
    return c


def _random_states(c: cl.Compiled, seed: int, n: int = 3):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        y = c.y0.copy()
        y[: c.nq] += 0.01 * rng.normal(size=c.nq)
        y[c.nq : c.nq + c.nv] = rng.normal(size=c.nv)
        yield y


@pytest.mark.parametrize("which", ["ups_upu", "sps_cu"])
def test_sparse_factor_of_parallel_mechanisms_equals_lapack(which, monkeypatch):
    """On the seed mechanisms (legs closing loops through the platform), the sparse
    kernel's factor of S = phi_q M^-1 phi_q^T equals LAPACK's Cholesky of S formed densely
    here (phi_q from evaluate_rows, M from the bodies) at random states, entries outside
    the pattern are zero in LAPACK's factor too, and the solve equals the dense one."""
    c = _seed(which, True, monkeypatch)
    md = c.model
    m = c.nrow
    pos = np.asarray(md.row_pos)
    rowptr, rowidx = np.asarray(md.sch_rowptr), np.asarray(md.sch_rowidx)
    inpat = np.eye(m, dtype=bool)
    for i in range(m):
        inpat[i, rowidx[rowptr[i] : rowptr[i + 1]]] = True
    assert inpat.sum() < m * (m + 1) / 2 / 2  # sparse: under half of the triangle
    for y in _random_states(c, 12):
        wk = make_work(md)
        yd = np.empty_like(y)
        assert rhs(0.3, y, md, wk, cl.contact_state(c), 5.0, 5.0, 0, yd) == 0
        phi_q = cl.evaluate_rows(c, 0.3, y).phi_q  # (m, 6 nb), world translations
        minv = np.zeros((6 * c.nb, 6 * c.nb))
        for b in range(c.nb):
            minv[6 * b : 6 * b + 3, 6 * b : 6 * b + 3] = np.eye(3) / md.body_mass[b]
            minv[6 * b + 3 : 6 * b + 6, 6 * b + 3 : 6 * b + 6] = wk.bJinv[b]
        s_dense = phi_q @ minv @ phi_q.T
        perm = np.argsort(pos)  # factor order
        low = np.linalg.cholesky(s_dense[np.ix_(perm, perm)])
        scale = np.abs(low).max()
        assert np.abs(low[~inpat & np.tri(m, dtype=bool)]).max() <= 1e-12 * scale
        got = np.where(inpat, wk.S[:m, :m], 0.0)
        np.testing.assert_allclose(got, low, rtol=0, atol=1e-10 * scale)
        yd1 = np.empty_like(y)
        rhs(0.3, y, md, make_work(md), cl.contact_state(c), 5.0, 5.0, 1, yd1)
        np.testing.assert_allclose(yd, yd1, rtol=1e-9, atol=1e-9 * np.abs(yd1).max())


@pytest.mark.parametrize("which", ["ups_upu", "sps_cu"])
def test_sparse_and_envelope_cholesky_give_the_same_bits(which, monkeypatch):
    """The two factorisations skip only exact zeros of each other's sums, so the right-hand
    side and the multipliers agree bit for bit; and the automatic choice takes the sparse
    one for the ideal 4UPS-UPU, whose envelope does four times its products."""
    from clearance.compile import compiled
    from clearance.mechanisms.ups_upu import ups_upu_ideal

    cs = _seed(which, True, monkeypatch)
    ce = _seed(which, False, monkeypatch)
    for y in _random_states(cs, 13):
        out = []
        for c in (cs, ce):
            wk = make_work(c.model)
            yd = np.empty_like(y)
            assert rhs(0.3, y, c.model, wk, cl.contact_state(c), 5.0, 5.0, 0, yd) == 0
            out.append((yd, wk.lam.copy()))
        assert out[0][0].tobytes() == out[1][0].tobytes()  # (bits: also the signs of zeros)
        assert out[0][1].tobytes() == out[1][1].tobytes()
    monkeypatch.undo()
    assert compiled.SPARSE_RATIO == 0.5
    assert cl.compile_mechanism(ups_upu_ideal()).model.sch_sparse == 1


def _ring(n: int = 5) -> cl.Mechanism:
    """n bars joined end to end into a closed ring by spherical joints, the first one hung
    from the ground: a loop of moving bodies, whose Schur complement has Cholesky fill
    (the seed mechanisms' row graphs are chordal in their factor order: none)."""
    m = cl.Mechanism("ring", gravity=(0, 0, -9.81))
    ang = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    pts = np.column_stack([np.cos(ang), np.sin(ang), np.zeros(n)])
    for k in range(n):
        a, b = pts[k], pts[(k + 1) % n]
        mid = 0.5 * (a + b)
        m.add(cl.Body(f"b{k}", 1.0 + 0.1 * k, (0.1, 0.2, 0.3), position=tuple(mid)))
        m.add(cl.Marker(f"b{k}_a", f"b{k}", tuple(a - mid)))
        m.add(cl.Marker(f"b{k}_b", f"b{k}", tuple(b - mid)))
    for k in range(n):
        m.add(cl.Spherical(f"s{k}", f"b{k}_b", f"b{(k + 1) % n}_a"))
    m.add(cl.Marker("g", cl.GROUND, tuple(pts[0])), cl.Spherical("hang", "g", "b0_a"))
    return m


def test_fill_is_cleared_and_both_factorisations_agree_on_a_loop(monkeypatch):
    """On a ring of bodies (fill in the factor: entries neither assembled nor structurally
    zero), a work buffer whose S holds NaN from before gives the same bits as a fresh one
    in both modes, and the modes agree bit for bit and with the dense solve."""
    from clearance.compile import compiled

    res = {}
    for sparse in (True, False):
        monkeypatch.setattr(compiled, "SPARSE_RATIO", float("inf") if sparse else 0.0)
        c = cl.compile_mechanism(_ring())
        assert c.model.sch_sparse == int(sparse) and c.model.sch_fill.size > 0
        out = []
        for y in _random_states(c, 14):
            runs = []
            for stale in (False, True):
                wk = make_work(c.model)
                if stale:
                    wk.S[...] = np.nan
                yd = np.empty_like(y)
                assert rhs(0.3, y, c.model, wk, cl.contact_state(c), 5.0, 5.0, 0, yd) == 0
                runs.append(yd.tobytes() + wk.lam.tobytes())
            assert runs[0] == runs[1]
            yd1 = np.empty_like(y)
            rhs(0.3, y, c.model, make_work(c.model), cl.contact_state(c), 5.0, 5.0, 1, yd1)
            np.testing.assert_allclose(yd, yd1, rtol=1e-9, atol=1e-9 * np.abs(yd1).max())
            out.append(runs[0])
        res[sparse] = out
    assert res[True] == res[False]
