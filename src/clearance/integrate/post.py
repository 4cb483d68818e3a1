"""Post-processing at the output times (compiled): accelerations, multipliers, violations,
energies, joint reactions and clearance-joint diagnostics, from the saved states and the
discrete contact state recorded with them.

Each quantity is a function of a sample's state (`evaluate`: a full right-hand side plus the
reactions and diagnostics, ~10 us on the seed mechanisms). Evaluated at every one of 20 001
samples that costs far more than the integration of a smooth run (0.26 s against 17 ms for
the ideal 4UPS-UPU), although between the integrator's steps the quantities are smooth
functions of time. So `post_process` evaluates them exactly on a subset and interpolates
the rest, verifying as it goes:

- the samples are split where the recorded contact state changes (contact onsets and
  separations: the quantities jump there) and otherwise handled in windows;
- a window holds samples of one accepted step (Outputs.piece), plus the last sample before
  it as its first node: inside a step the states are the step's dense output, a polynomial
  in time, so the quantities are smooth there; where two steps meet they have a kink of
  the size of the local error, which a window across it must resolve (on the ideal
  4UPS-UPU at rtol 1e-6, windows of 64 samples across a step end failed where windows of
  one step's ~48 passed: 441 exact evaluations of 2001 before, 374 since). A new step is
  tried whole first (up to D MAX_SPACING samples); the samples of a step shorter than 2 D
  are evaluated exactly (letting windows reach across short steps instead cost more
  exact evaluations at every rtol from 1e-5 to 1e-8 on the ideal 4UPS-UPU: 1975 against
  1842 of 2001 at 1e-8). Samples without a step (the start, fixed-step methods, which
  sample on the solution) form one piece;
- in a window the quantities are evaluated at D + 1 nodes and at the D midpoints between
  them (the samples nearest to equally spaced times and to the midpoints between them);
  the degree-D Lagrange interpolant through the nodes (in time) must match every channel
  at every midpoint within half of ptol |x|max + pabs (|x|max: the channel's largest
  magnitude at the nodes), so that the samples between the checks stay within the whole
  (tests/test_post.py; measured on the ideal 4UPS-UPU: at most 0.67 of it with |x|max
  over the whole run); the constraint violations phi, phi_dot are held to their largest
  value in the window instead (VIOLATION_RTOL: they are reported to within their own
  size), and a window with a non-finite state is never interpolated;
- a window that passes is filled by interpolation (its checked midpoints keep their exact
  values) and the next one is twice as long (up to the end of the step, and D MAX_SPACING
  samples; a new contact segment starts again at 2 D); a window that fails is halved;
  below 2 D samples they are evaluated one by one, for 2 D samples, and the window grows
  again. A kink (a driver's corner, a stick-slip transition) or a jump the contact state
  does not show therefore costs exact evaluations around it, not accuracy.

ptol = 0 evaluates every sample (the exact path). What `simulate` passes: post_tol (default
rtol) and atol. The samples' states come from the dense output, whose error inside a step
is of the order of rtol or more (a 4th-order interpolant for the 5(4) pairs), and the
exact values carry it, with kinks where the steps meet; a tighter post_tol mostly fails on
those kinks. Measured on the ideal 4UPS-UPU, 2 s, tsit5 (actuator-force error against an
rtol 1e-12 run; exact evaluations of 2001 samples at dt_out 1e-3; in brackets before the
windows followed the steps):

  rtol   post_tol = rtol          rtol / 10                0 (every sample)
  1e-5   1.02e-4 N, 225 (297)     1.02e-4 N, 393 (369)     1.02e-4 N
  1e-6   7.02e-6 N, 374 (441)     7.09e-6 N, 745 (753)     7.09e-6 N
  1e-7   5.34e-7 N, 915 (857)     5.34e-7 N, 1816 (1897)   5.34e-7 N
  1e-8   5.00e-8 N, 1842 (1953)   5.00e-8 N, 1901 (2001)   5.00e-8 N

so the interpolation error stays far below the integration error. 20 001 samples at rtol
1e-6: 373 exact evaluations (409 before). Runs whose contact state changes every few
samples (a rattling clearance joint sampled at 1e-4 s) are evaluated almost entirely
exactly: nothing smooth is there to interpolate.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from clearance.contact.element import contact_energy, joint_outputs
from clearance.dynamics.forces import kinetic_energy, potential_energy
from clearance.dynamics.rhs import rhs
from clearance.kinematics.rotations import cross, matvec, sub

#: interpolation degree (D + 1 nodes per window; `_fill` is written out for 4)
DEGREE = 4
#: largest node spacing, in samples (a window spans DEGREE * MAX_SPACING samples)
MAX_SPACING = 256
#: relative tolerance of the interpolated constraint violations phi, phi_dot: drift whose
#: size matters, not its digits, kinked wherever two steps' dense outputs meet; held to
#: atol they failed nearly every window (993 of 1001 samples exact on the double pendulum
#: at rtol 1e-6, whatever post_tol), at 0.1 still 795; at 1 (reported to within their own
#: size) 613, as if they were not checked at all
VIOLATION_RTOL = 1.0


class Blocks(NamedTuple):
    """The joints and drivers whose reactions are reported: first constraint row, row count,
    reporting side (1: body j, 0: body i) and the body-frame point of the moment."""

    row0: np.ndarray
    nrow: np.ndarray
    side: np.ndarray
    pt: np.ndarray


class PostArrays(NamedTuple):
    """The post-processed outputs, 2-D, one row per sample: VD (v_dot), LAM, PHI, PHID, EN
    (T, V, V_c), RF and RM (reaction force and moment, 3 per block), COUT (clearance joints,
    NCOUT each), POUT (contact points, NPOUT each)."""

    VD: np.ndarray
    LAM: np.ndarray
    PHI: np.ndarray
    PHID: np.ndarray
    EN: np.ndarray
    RF: np.ndarray
    RM: np.ndarray
    COUT: np.ndarray
    POUT: np.ndarray


@njit(cache=True, error_model="numpy", nogil=True, _nrt=False)
def evaluate(model, wk, cs, alpha, beta, solver, ts, Y, CS, k, blk, yd, out):
    """Fill row k of the PostArrays `out` from sample k: the reaction force and moment
    (world, about the joint point) of each block on its reporting body, the rest as named
    there. cs: scratch for the sample's contact state, taken from CS; yd: scratch (ny,).
    A sample whose state is not finite gets NaN everywhere (not what the kernels leave in
    their scratch from the previous sample)."""
    VD, LAM, PHI, PHID, EN = out.VD, out.LAM, out.PHI, out.PHID, out.EN
    RF, RM, COUT, POUT = out.RF, out.RM, out.COUT, out.POUT
    blk_row0, blk_nrow, blk_side, blk_pt = blk.row0, blk.nrow, blk.side, blk.pt
    nb = model.nb
    y = Y[k]
    if not _finite_rows(Y, k, k):
        for X in out:
            for c in range(X.shape[1]):
                X[k, c] = np.nan
        return
    for p in range(model.ncp):
        cs.flag[p] = int(CS[k, p, 0])
        cs.ddm[p] = CS[k, p, 1]
    rhs(ts[k], y, model, wk, cs, alpha, beta, solver, yd)
    joint_outputs(model, wk)
    nco = wk.cout.shape[1]
    for c in range(model.nclr):
        for a in range(nco):
            COUT[k, c * nco + a] = wk.cout[c, a]
    npo = wk.pout.shape[1]
    for p in range(model.ncp):
        for a in range(npo):
            POUT[k, p * npo + a] = wk.pout[p, a]
    for i in range(6 * nb):
        VD[k, i] = yd[model.y_iv + i]
    for r in range(model.nrow):
        LAM[k, r] = wk.lam[r]
        PHI[k, r] = wk.phi[r]
        PHID[k, r] = wk.phid[r]
    EN[k, 0] = kinetic_energy(model, y, wk.bJ)
    EN[k, 1] = potential_energy(model, y, wk.bA, wk.br)
    EN[k, 2] = contact_energy(model, wk.bA, wk.br, wk.fval)
    for bk in range(blk_row0.shape[0]):
        if blk_nrow[bk] == 0:
            continue
        side = blk_side[bk]
        o = 6 * side
        F0, F1, F2, n0, n1, n2 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        for r in range(blk_row0[bk], blk_row0[bk] + blk_nrow[bk]):
            lr = wk.lam[r]
            F0 -= wk.J[r, o] * lr
            F1 -= wk.J[r, o + 1] * lr
            F2 -= wk.J[r, o + 2] * lr
            n0 -= wk.J[r, o + 3] * lr
            n1 -= wk.J[r, o + 4] * lr
            n2 -= wk.J[r, o + 5] * lr
        b = model.row_bj[blk_row0[bk]] if side == 1 else model.row_bi[blk_row0[bk]]
        # n_P = A n' - (A s') x F (array views are free here: no reference counting)
        A = wk.bA[b]
        F = (F0, F1, F2)
        nP = sub(matvec(A, (n0, n1, n2)), cross(matvec(A, blk_pt[bk]), F))
        for a in range(3):
            RF[k, 3 * bk + a] = F[a]
            RM[k, 3 * bk + a] = nP[a]


@njit(cache=True, error_model="numpy", _nrt=False)
def _weights(ts, nodes, t, w):
    """Lagrange weights w of the nodes' times ts[nodes] at time t."""
    for i in range(nodes.shape[0]):
        ti = ts[nodes[i]]
        x = 1.0
        for j in range(nodes.shape[0]):
            if j != i:
                x *= (t - ts[nodes[j]]) / (ti - ts[nodes[j]])
        w[i] = x


@njit(cache=True, error_model="numpy", _nrt=False)
def _agrees(X, nodes, checks, W, ptol, pabs):
    """Whether the interpolant of X through its rows `nodes` (weights W[k - nodes[0]] at row
    k) matches X at every row of `checks` within (ptol |x|max + pabs) / 2, channel by
    channel (half: between the checks the error can be larger than at them)."""
    for c in range(X.shape[1]):
        big = 0.0
        for i in range(nodes.shape[0]):
            big = max(big, abs(X[nodes[i], c]))
        tol = 0.5 * (ptol * big + pabs)
        for k in range(checks.shape[0]):
            j = checks[k] - nodes[0]
            x = 0.0
            for i in range(nodes.shape[0]):
                x += W[j, i] * X[nodes[i], c]
            if not abs(x - X[checks[k], c]) <= tol:  # (NaN fails)
                return False
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def _all_agree(out, nodes, checks, W, ptol, pabs):
    """`_agrees` for every array of the PostArrays `out`; the constraint violations PHI and
    PHID (drift, noise of the size of atol around zero) to VIOLATION_RTOL of their largest
    value in the window, or ptol if looser."""
    pv = max(ptol, VIOLATION_RTOL)
    return (
        _agrees(out.VD, nodes, checks, W, ptol, pabs)
        and _agrees(out.LAM, nodes, checks, W, ptol, pabs)
        and _agrees(out.PHI, nodes, checks, W, pv, pabs)
        and _agrees(out.PHID, nodes, checks, W, pv, pabs)
        and _agrees(out.EN, nodes, checks, W, ptol, pabs)
        and _agrees(out.RF, nodes, checks, W, ptol, pabs)
        and _agrees(out.RM, nodes, checks, W, ptol, pabs)
        and _agrees(out.COUT, nodes, checks, W, ptol, pabs)
        and _agrees(out.POUT, nodes, checks, W, ptol, pabs)
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def _finite_rows(Y, a, b):
    """Whether the states of samples a..b are all finite (a failed sample is evaluated
    exactly, never interpolated over)."""
    for k in range(a, b + 1):
        for i in range(Y.shape[1]):
            if not np.isfinite(Y[k, i]):
                return False
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def _fill(X, nodes, done, W):
    """Interpolate the rows of X between nodes[0] and nodes[-1] not evaluated exactly
    (DEGREE 4: five nodes, summed in their order; asserted below)."""
    n0, n1, n2, n3, n4 = nodes[0], nodes[1], nodes[2], nodes[3], nodes[4]
    for k in range(n0 + 1, n4):
        if done[k]:
            continue
        j = k - n0
        w0, w1, w2, w3, w4 = W[j, 0], W[j, 1], W[j, 2], W[j, 3], W[j, 4]
        for c in range(X.shape[1]):
            X[k, c] = w0 * X[n0, c] + w1 * X[n1, c] + w2 * X[n2, c] + w3 * X[n3, c] + w4 * X[n4, c]


assert DEGREE == 4, "_fill is written out for five nodes"


@njit(cache=True, error_model="numpy", nogil=True)
def post_process(model, wk, cs, alpha, beta, solver, ts, Y, CS, PC, n, blk, out, ptol, pabs):
    """Fill the first n rows of the output arrays (`evaluate`; 2-D, one row per sample):
    exactly at every sample if ptol <= 0, else exactly on verified windows' nodes and
    checks and interpolated between them (module docstring). PC: the dense-output piece of
    each sample (Outputs.piece; -1: none known). Returns the number of exact evaluations."""
    yd = np.empty(Y.shape[1])
    done = np.zeros(n, dtype=np.bool_)
    nexact = 0
    if ptol <= 0.0:
        for k in range(n):
            evaluate(model, wk, cs, alpha, beta, solver, ts, Y, CS, k, blk, yd, out)
        return n
    D = DEGREE
    LMAX = D * MAX_SPACING
    nodes = np.empty(D + 1, dtype=np.int64)
    checks = np.empty(D, dtype=np.int64)
    W = np.empty((LMAX + 1, D + 1))  # weights of the window's rows
    L = 2 * D
    fresh = -1
    s = np.int64(0)  # (not a literal 0: numba would compile `evaluate` for Literal[int](0))
    e = np.int64(-1)  # last sample of the segment of equal contact state holding s
    while s < n:
        if s > e:  # a new segment: its windows start small (no spacing carried over)
            e = s
            while e + 1 < n and _same_state(CS, e, e + 1):
                e += 1
            L = 2 * D
        if s == e:
            if not done[s]:
                evaluate(model, wk, cs, alpha, beta, solver, ts, Y, CS, s, blk, yd, out)
                done[s] = True
                nexact += 1
            s += 1
            continue
        if PC[s + 1] < 0:  # no step known (fixed steps): the segment is one piece
            p = e
        else:  # p: the last sample of the dense-output piece that s + 1 comes from
            p = s + 1
            while p < e and PC[p + 1] == PC[s + 1]:
                p += 1
            if PC[s] != PC[s + 1] and s != fresh:  # a new piece: try it whole, once
                L = LMAX
                fresh = s
        b = min(s + L, p)
        if b - s < 2 * D:  # too short for a window, or a window failed at 2 D: one by one
            last = p if p - s < 2 * D else s + 2 * D
            for k in range(s, last + 1):
                if not done[k]:
                    evaluate(model, wk, cs, alpha, beta, solver, ts, Y, CS, k, blk, yd, out)
                    done[k] = True
                    nexact += 1
            s = last if last < e else e + 1
            L = 2 * D
            continue
        if not _place(ts, s, b, nodes, checks):  # (uneven times: too few samples)
            L = (b - s) // 2
            continue
        for j in range(2 * D + 1):
            k = nodes[j // 2] if j % 2 == 0 else checks[j // 2]
            if not done[k]:
                evaluate(model, wk, cs, alpha, beta, solver, ts, Y, CS, k, blk, yd, out)
                done[k] = True
                nexact += 1
        for i in range(D):  # the checks' weights first: a failing window needs no more
            _weights(ts, nodes, ts[checks[i]], W[checks[i] - nodes[0]])
        if _finite_rows(Y, s, b) and _all_agree(out, nodes, checks, W, ptol, pabs):
            for j in range(1, b - s):
                if not done[s + j]:
                    _weights(ts, nodes, ts[s + j], W[j])
            for X in out:  # (a tuple of equal types: a plain loop)
                _fill(X, nodes, done, W)
            L = min(2 * (b - s), LMAX)
            s = b if b < e else e + 1  # (the last node starts the next window)
        else:
            L = (b - s) // 2
    return nexact


@njit(cache=True, error_model="numpy", _nrt=False)
def _nearest(ts, lo, hi, t):
    """The index in [lo, hi] whose time is nearest to t (ts increasing)."""
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ts[mid] <= t:
            lo = mid
        else:
            hi = mid
    return lo if t - ts[lo] <= ts[hi] - t else hi


@njit(cache=True, error_model="numpy", _nrt=False)
def _place(ts, a, b, nodes, checks):
    """Nodes at the samples of [a, b] nearest to D + 1 equally spaced times from ts[a] to
    ts[b], checks at the samples nearest to the midpoints between them (on an even grid:
    every m-th sample and the ones halfway). False if samples are too few for that."""
    D = nodes.shape[0] - 1
    nodes[0], nodes[D] = a, b
    for i in range(1, D):
        if nodes[i - 1] + 1 > b - 1:
            return False
        t = ts[a] + (ts[b] - ts[a]) * i / D
        nodes[i] = _nearest(ts, nodes[i - 1] + 1, b - 1, t)
    for i in range(D):
        if nodes[i + 1] - nodes[i] < 2:
            return False
        t = 0.5 * (ts[nodes[i]] + ts[nodes[i + 1]])
        checks[i] = _nearest(ts, nodes[i] + 1, nodes[i + 1] - 1, t)
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def _same_state(CS, a, b):
    """Whether samples a and b share the recorded contact state (flags and latched rates)."""
    for p in range(CS.shape[1]):
        if CS[a, p, 0] != CS[b, p, 0] or CS[a, p, 1] != CS[b, p, 1]:
            return False
    return True
