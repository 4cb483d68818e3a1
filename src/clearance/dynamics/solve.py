"""The constrained solve of physics.md d.1/d.3, compiled.

    [ M      phi_q^T ] [ v_dot ]   [ Q       ]
    [ phi_q  0       ] [ lam   ] = [ gamma_B ]

SCHUR (default): S = phi_q M^-1 phi_q^T assembled body by body from the row-block Jacobian
(each row touches at most two bodies), factorised in a row order chosen at compile time
(reverse Cuthill-McKee) by an envelope Cholesky (contiguous inner loops over each row's
envelope) or, where that does far more products, a sparse Cholesky over the factor's
structural non-zeros (fill included); both give the same bits. So the cost follows the
mechanism's sparsity, not m^3. The envelope or pattern and the list of assembly terms are
computed at compile time (Model.sch_*; compile/compiled.py, _schur_structure).
DENSE: the full augmented matrix with LU (np.linalg.solve): the checked fallback.
LSTSQ: minimum-norm multipliers from S by least squares, for redundant but consistent
constraint sets (physics.md c.5): v_dot is unique, lam is not.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_NONNEG = 0x7FFFFFFFFFFFFFFF


@njit(cache=True, inline="always", error_model="numpy", _nrt=False)
def nn(k):
    """k itself for k >= 0, visibly non-negative to the compiler. numba lets a negative index
    count from the end, which costs three instructions per access in inner loops; with an
    index known to be non-negative LLVM drops them (about 30 % of the Cholesky time). Never
    use it where an index may be negative on purpose (the ground slot -1)."""
    return k & _NONNEG


@njit(cache=True, error_model="numpy", _nrt=False)
def _minv_blocks(model, Jinv, J, JM, Q, MiQ):
    """JM = M^-1 J^T (row blocks) and MiQ = M^-1 Q."""
    m = model.nrow
    for r in range(m):
        for side in range(2):
            b = model.row_bi[r] if side == 0 else model.row_bj[r]
            o = 6 * side
            if b < 0:
                for k in range(6):
                    JM[r, nn(o + k)] = 0.0
                continue
            im = 1.0 / model.body_mass[b]
            JM[r, nn(o)] = im * J[r, nn(o)]
            JM[r, nn(o + 1)] = im * J[r, nn(o + 1)]
            JM[r, nn(o + 2)] = im * J[r, nn(o + 2)]
            j3 = J[r, nn(o + 3)]
            j4 = J[r, nn(o + 4)]
            j5 = J[r, nn(o + 5)]
            for a in range(3):
                JM[r, nn(o + 3 + a)] = Jinv[b, a, 0] * j3 + Jinv[b, a, 1] * j4 + Jinv[b, a, 2] * j5
    for b in range(model.nb):
        im = 1.0 / model.body_mass[b]
        Ji = Jinv[b]
        MiQ[b, 0] = im * Q[b, 0]
        MiQ[b, 1] = im * Q[b, 1]
        MiQ[b, 2] = im * Q[b, 2]
        for a in range(3):
            MiQ[b, 3 + a] = Ji[a, 0] * Q[b, 3] + Ji[a, 1] * Q[b, 4] + Ji[a, 2] * Q[b, 5]


@njit(cache=True, error_model="numpy", _nrt=False)
def assemble_schur(model, J, JM, S, full):
    """Lower triangle of S = J M^-1 J^T in factor order (row r at position row_pos[r]).

    Runs over the compile-time term list (Model.sch_pair, sch_grp): first terms set an entry,
    second terms add to it, fill entries of the factor (envelope or pattern) are cleared.
    full: clear the whole triangle first (least squares reads it all)."""
    m = model.nrow
    if full:
        for a in range(m):
            for c in range(a + 1):
                S[a, c] = 0.0
    Jf = J.reshape(-1)
    JMf = JM.reshape(-1)
    Sf = S.reshape(-1)
    fill = model.sch_fill
    for q in range(fill.shape[0]):
        Sf[fill[q]] = 0.0
    g = model.sch_grp
    pr = model.sch_pair
    _terms(Jf, JMf, Sf, pr, g[0], g[1], 3, False)
    _terms(Jf, JMf, Sf, pr, g[1], g[2], 6, False)
    _terms(Jf, JMf, Sf, pr, g[2], g[3], 3, True)
    _terms(Jf, JMf, Sf, pr, g[3], g[4], 6, True)


@njit(cache=True, inline="always", error_model="numpy", _nrt=False)
def _terms(Jf, JMf, Sf, pr, q0, q1, n, add):
    """Assembly terms q0:q1 of pr, each a dot product of length n (see assemble_schur)."""
    for q in range(q0, q1):
        ja = pr[q, 0]
        jc = pr[q, 1]
        v = 0.0
        for k in range(n):
            v += Jf[ja + k] * JMf[jc + k]
        if add:
            Sf[pr[q, 2]] += v
        else:
            Sf[pr[q, 2]] = v


@njit(cache=True, inline="always", error_model="numpy", _nrt=False)
def _pivot(S, j, s, d0, dinv):
    """The diagonal entry L[j, j] = sqrt(s) of both Cholesky kernels, stored with its
    reciprocal in dinv[j]; 0.0 (nothing stored) if the pivot s is not positive relative
    to the diagonal d0 = S[j, j] (singular or redundant constraints)."""
    if not (s > 1e-12 * abs(d0)) or d0 == 0.0:
        return 0.0
    ljj = math.sqrt(s)
    S[j, j] = ljj
    dinv[j] = 1.0 / ljj
    return ljj


@njit(cache=True, error_model="numpy", _nrt=False)
def envelope_cholesky(S, m, first, colptr, colidx, dinv):
    """In-place lower Cholesky of the envelope of S (first[i] = first non-zero column of row
    i; colidx[colptr[j]:colptr[j+1]] = rows i > j with first[i] <= j). Only the envelope is
    touched, and fill-in stays inside it. Column by column: the entries of a column are
    independent, which keeps the processor busy (row by row, each entry waits for the one
    before it).

    dinv[j] = 1 / L[j, j] for the triangular solves. Returns False if a pivot is not positive
    relative to its diagonal (singular or redundant constraints).
    """
    for j in range(m):
        fj = first[j]
        d0 = S[j, j]
        s = d0
        for k in range(fj, j):
            s -= S[j, nn(k)] * S[j, nn(k)]
        ljj = _pivot(S, j, s, d0, dinv)
        if ljj == 0.0:
            return False
        for a in range(colptr[j], colptr[j + 1]):
            i = colidx[a]
            fi = first[i]
            s = S[i, j]
            for k in range(fi if fi > fj else fj, j):
                s -= S[i, nn(k)] * S[j, nn(k)]
            S[i, j] = s / ljj
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def envelope_solve(L, m, first, dinv, x):
    """Solve L L^T x = b in place (x holds b on entry); dinv = 1 / diag(L).

    Each unknown waits for the one before it, so the solves are latency-bound: multiplying
    by the reciprocal instead of dividing shortens that chain (0.9 -> 0.65 us; the result
    changes in the last bit)."""
    for i in range(m):
        s = x[i]
        for k in range(first[i], i):
            s -= L[i, nn(k)] * x[nn(k)]
        x[i] = s * dinv[i]
    for i in range(m - 1, -1, -1):
        xi = x[i] * dinv[i]
        x[i] = xi
        for k in range(first[i], i):
            x[nn(k)] -= L[i, nn(k)] * xi


@njit(cache=True, error_model="numpy", _nrt=False)
def sparse_cholesky(S, m, rowptr, rowidx, colptr, colidx, dotptr, dotidx, dinv):
    """In-place lower Cholesky of S over the symbolic factor's pattern (Model.sch_*: the
    columns k < i of row i, the rows i > j of column j, and per entry (i, j) the columns k
    where both L[i, k] and L[j, k] are non-zero). Column by column: the entries of a
    column are independent, which keeps the processor busy (row by row, each entry waits
    for the one before it).

    The entries outside the pattern stay exact zeros in a dense factorisation, so skipping
    them leaves every sum with the same terms in the same order: the factor is bit for bit
    that of `envelope_cholesky`. Chosen at compile time where it does far fewer products
    (Model.sch_sparse; compile/compiled.py, SPARSE_RATIO): the ideal 4UPS-UPU, 1949
    against 8816 (five legs joined at the platform make the envelope nearly full there),
    integration loop 11.4 -> 8.7 us per rhs. On the default clearance model (1272 against
    2088) the indirect indexing costs more than it saves: 7.6 -> 8.2 us in the loop.
    (Bit for bit for finite S; a non-finite right-hand side can spread NaN differently,
    0 * inf, into a solution that is not finite either way.)

    dinv[j] = 1 / L[j, j] for the triangular solves. Returns False if a pivot is not positive
    relative to its diagonal (singular or redundant constraints).
    """
    for j in range(m):
        d0 = S[j, j]
        s = d0
        for p in range(rowptr[j], rowptr[j + 1]):
            k = rowidx[p]
            s -= S[j, k] * S[j, k]
        ljj = _pivot(S, j, s, d0, dinv)
        if ljj == 0.0:
            return False
        for a in range(colptr[j], colptr[j + 1]):
            i = colidx[a]
            s = S[i, j]
            for p in range(dotptr[a], dotptr[a + 1]):
                k = dotidx[p]
                s -= S[i, k] * S[j, k]
            S[i, j] = s / ljj
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def sparse_solve(L, m, rowptr, rowidx, dinv, x):
    """Solve L L^T x = b in place (x holds b on entry) over L's row pattern; dinv = 1 /
    diag(L).

    Each unknown waits for the one before it, so the solves are latency-bound: multiplying
    by the reciprocal instead of dividing shortens that chain (0.9 -> 0.65 us; the result
    changes in the last bit)."""
    for i in range(m):
        s = x[i]
        for p in range(rowptr[i], rowptr[i + 1]):
            k = rowidx[p]
            s -= L[i, k] * x[k]
        x[i] = s * dinv[i]
    for i in range(m - 1, -1, -1):
        xi = x[i] * dinv[i]
        x[i] = xi
        for p in range(rowptr[i], rowptr[i + 1]):
            k = rowidx[p]
            x[k] -= L[i, k] * xi


@njit(cache=True, error_model="numpy", _nrt=False)
def solve_constrained(model, wk, solver):
    """Solve for v_dot (wk.vd) and lam (wk.lam) from wk.J, wk.gB, wk.Q with the current
    inertia wk.bJ / wk.bJinv; return 0, or 1 if the constraint matrix is singular."""
    return _solve(
        model,
        wk.bJ,
        wk.bJinv,
        wk.J,
        wk.gB,
        wk.Q,
        solver,
        wk.JM,
        wk.S,
        wk.dinv,
        wk.rl,
        wk.lam,
        wk.MiQ,
        wk.vd,
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def _solve(model, Jb, Jinv, J, gB, Q, solver, JM, S, dinv, rl, lam, MiQ, vd):
    """Solve the augmented system for v_dot (vd, (nb, 6)) and lam; return 0 or 1 (singular)."""
    m = model.nrow
    nb = model.nb
    _minv_blocks(model, Jinv, J, JM, Q, MiQ)
    for b in range(nb):
        for k in range(6):
            vd[b, k] = MiQ[b, k]
    if m == 0:
        return 0
    if solver == 1:
        return _solve_dense(model, Jb, J, gB, Q, lam, vd)
    # right-hand side J M^-1 Q - gamma_B, in factor order
    for r in range(m):
        s = -gB[r]
        for side in range(2):
            b = model.row_bi[r] if side == 0 else model.row_bj[r]
            if b >= 0:
                o = 6 * side
                for k in range(6):
                    s += J[r, nn(o + k)] * MiQ[b, k]
        rl[nn(model.row_pos[r])] = s
    assemble_schur(model, J, JM, S, solver != 0)
    if solver == 0:
        cp, ci = model.sch_colptr, model.sch_colidx
        if model.sch_sparse:
            rp, ri = model.sch_rowptr, model.sch_rowidx
            if not sparse_cholesky(S, m, rp, ri, cp, ci, model.sch_dotptr, model.sch_dotidx, dinv):
                return 1
            sparse_solve(S, m, rp, ri, dinv, rl)
        else:
            if not envelope_cholesky(S, m, model.sch_first, cp, ci, dinv):
                return 1
            envelope_solve(S, m, model.sch_first, dinv, rl)
    else:
        _lstsq(S, m, rl, lam)
    for r in range(m):
        lam[r] = rl[nn(model.row_pos[r])]
    for r in range(m):
        lr = lam[r]
        for side in range(2):
            b = model.row_bi[r] if side == 0 else model.row_bj[r]
            if b >= 0:
                o = 6 * side
                for k in range(6):
                    vd[b, k] -= JM[r, nn(o + k)] * lr
    return 0


@njit(cache=True, error_model="numpy", _nrt=True)
def _lstsq(S, m, rl, lam):
    """rl <- minimum-norm least-squares solution of S x = rl (S: lower triangle filled in
    full here); lam is scratch. Allocates (compiled with reference counting)."""
    # Symmetric Jacobi scaling D S D, D = diag(S)^-1/2, before least squares: rows of
    # very different physical scale (light links, small inertias) otherwise cost ~1e-9
    # relative accuracy, and the rank cut rcond would act on units, not on dependence.
    # lam serves as scratch for D (it is filled from rl afterwards).
    for a in range(m):
        lam[a] = 1.0 / math.sqrt(S[a, a]) if S[a, a] > 0.0 else 0.0
    for a in range(m):
        for c in range(a + 1):
            S[a, c] *= lam[a] * lam[c]
            S[c, a] = S[a, c]
        rl[a] *= lam[a]
    Ss = S  # (m, m)
    b = rl[:m].copy()
    sol = np.linalg.lstsq(Ss, b, 1e-10)[0]
    # one step of iterative refinement: the SVD solve is ~10x less accurate than the
    # Cholesky one, and light bodies amplify multiplier errors in v_dot
    res = b - Ss @ sol
    sol += np.linalg.lstsq(Ss, res, 1e-10)[0]
    for a in range(m):
        rl[a] = sol[a] * lam[a]


@njit(cache=True, error_model="numpy", _nrt=True)
def _solve_dense(model, Jb, J, gB, Q, lam, vd):
    """Dense augmented LU (the fallback and validator)."""
    nb = model.nb
    m = model.nrow
    nv = 6 * nb
    n = nv + m
    K = np.zeros((n, n))
    rhs = np.zeros(n)
    for b in range(nb):
        o = 6 * b
        for a in range(3):
            K[o + a, o + a] = model.body_mass[b]
            for c in range(3):
                K[o + 3 + a, o + 3 + c] = Jb[b, a, c]
        for k in range(6):
            rhs[o + k] = Q[b, k]
    for r in range(m):
        for side in range(2):
            b = model.row_bi[r] if side == 0 else model.row_bj[r]
            if b >= 0:
                for k in range(6):
                    K[nv + r, 6 * b + k] += J[r, 6 * side + k]
                    K[6 * b + k, nv + r] += J[r, 6 * side + k]
        rhs[nv + r] = gB[r]
    try:
        x = np.linalg.solve(K, rhs)
    except Exception:  # singular augmented matrix: report, never raise in the hot loop
        return 1
    for b in range(nb):
        for k in range(6):
            vd[b, k] = x[6 * b + k]
    for r in range(m):
        lam[r] = x[nv + r]
    if not np.all(np.isfinite(x)):
        return 1
    return 0


@njit(cache=True, error_model="numpy")
def dense_jacobian(model, J, out):
    """Scatter the row-block Jacobian (m, 12) into a dense (m, 6 nb) matrix."""
    out[:, :] = 0.0
    for r in range(model.nrow):
        b = model.row_bi[r]
        if b >= 0:
            for k in range(6):
                out[r, 6 * b + k] += J[r, k]
        b = model.row_bj[r]
        if b >= 0:
            for k in range(6):
                out[r, 6 * b + k] += J[r, 6 + k]
