"""Compile: `Mechanism -> Compiled` (frozen arrays + index maps), never mutating the input.

Array names carry element prefixes (`body_mass[nbody]`, `prim_kind[nprim]`, `frc_kind[nfrc]`,
`fn_kind[nfn]`); `Model` is the namedtuple of arrays the compiled kernel reads. The state
layout is `clearance.layout.StateLayout` (offsets in Model.y_*):

    y = [q (7 nb) | v (6 nb) | z (3 ncp) | W_c, W_d, W_a, W_m, W_L | D_n (nclr) | D_t (nclr)]

Clearance joints (Model.clr_*, nclr) own contact points (Model.cp_*, ncp), encoded by
`clearance.compile.clearances`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

from clearance.compile.clearances import clearance_arrays, clearance_rows
from clearance.compile.functions import encode_functions
from clearance.kinds import (
    AB_I,
    AB_J,
    AX_I,
    AX_J,
    NPV,
    PRIM_ROWS,
    ROTATION_ONLY,
    SB_I,
    SB_J,
    JointType,
    PrimKind,
)
from clearance.layout import WORK, StateLayout
from clearance.model.bodies import GROUND
from clearance.model.drivers import (
    DistanceDriver,
    OffsetDriver,
    OrientationDriver,
    PositionDriver,
    PrismaticDriver,
    RevoluteDriver,
    zxz_angles,
)
from clearance.model.errors import ModelError
from clearance.model.forces import PointForce, SpringDamper, Torque
from clearance.model.functions import Constant, Scaled
from clearance.model.mechanism import Mechanism


class Model(NamedTuple):
    """Arrays read by the compiled kernel (all frozen; see module docstring)."""

    nb: int
    nrow: int
    body_mass: np.ndarray  # (nb,) [kg]
    body_J: np.ndarray  # (nb, 3, 3) inertia about CoM, body frame [kg m^2]
    body_Jinv: np.ndarray  # (nb, 3, 3)
    gravity: np.ndarray  # (3,) [m/s^2]
    prim_kind: np.ndarray  # (nprim,) PrimKind
    prim_bi: np.ndarray  # (nprim,) body index, -1 = ground
    prim_bj: np.ndarray
    prim_row: np.ndarray  # (nprim,) first row
    prim_fn: np.ndarray  # (nprim,) time function index or -1
    prim_v: np.ndarray  # (nprim, 6, 3) sb_i, sb_j, ab_i, ab_j, slide axis i, slide axis j
    prim_mv: np.ndarray  # (nprim, 2) slide function of the i / j point, -1: fixed point
    prim_ix: np.ndarray  # (nprim, 8) int parameters (orientation driver)
    row_bi: np.ndarray  # (nrow,) body of J columns 0:6
    row_bj: np.ndarray  # (nrow,) body of J columns 6:12
    row_drv: np.ndarray  # (nrow,) 1 if the row belongs to a driver
    row_pos: np.ndarray  # (nrow,) position of row r in the Schur factor order
    # Structure of S = J M^-1 J^T in factor order, fixed at compile time. Index arrays are
    # uint32: numba then knows they are not negative and drops its wraparound code (~30 %
    # of the assembly time).
    sch_sparse: int  # 1: sparse Cholesky over L's pattern, 0: envelope Cholesky (SPARSE_RATIO)
    sch_first: np.ndarray  # (nrow,) uint32 first structural non-zero column of each row: the
    # envelope, which contains the Cholesky fill
    sch_colptr: np.ndarray  # (nrow+1,) rows i > j of column j: of the envelope (first[i] <= j),
    # or where L[i, j] is structurally non-zero (sparse; fill included): CSR pointers
    sch_colidx: np.ndarray  # uint32 row indices, increasing
    # sparse only (empty otherwise):
    sch_rowptr: np.ndarray  # (nrow+1,) columns k < i with L[i, k] non-zero: CSR by row
    sch_rowidx: np.ndarray  # uint32 column indices, increasing
    sch_dotptr: np.ndarray  # (len(sch_colidx)+1,) per entry (i, j) of sch_colidx, the columns
    sch_dotidx: np.ndarray  # k < j where L[i, k] and L[j, k] are both non-zero (uint32,
    # increasing): the terms of the dot product that computes L[i, j]
    sch_pair: np.ndarray  # (npair, 3) uint32 assembly terms (a, c, s) in flat indices of J, JM
    # (m*12) and S (m*m): S.flat[s] (+)= J.flat[a:a+n] . JM.flat[c:c+n], in four groups
    sch_grp: np.ndarray  # (5,) group bounds in sch_pair: first term of an entry with n = 3
    # (a rotation-only row: its translational products vanish) and n = 6, then second terms
    # (added) with n = 3 and n = 6. An entry gets at most two terms (two rows share at most
    # two bodies), and a + b = b + a, so this order gives the bits of any other.
    sch_fill: np.ndarray  # uint32 flat indices of factor entries without a term (fill)
    brow_ptr: np.ndarray  # (nb+1,) rows touching each body: CSR pointers
    brow_idx: np.ndarray  # row indices
    brow_slot: np.ndarray  # 0: body is i of the row (cols 0:6), 1: body is j (cols 6:12)
    frc_kind: np.ndarray  # (nfrc,) ForceType
    frc_bi: np.ndarray  # (nfrc,) body of marker i (or the marker for point force/torque)
    frc_bj: np.ndarray  # (nfrc,) body of marker j (spring-damper) else -1
    frc_v: np.ndarray  # (nfrc, 3, 3) sb_i, sb_j, direction (body frame if frc_par[3] == 1)
    frc_par: np.ndarray  # (nfrc, 4) stiffness, damping, free length, frame (0 world, 1 body)
    frc_fn: np.ndarray  # (nfrc,) time function index
    fn_kind: np.ndarray
    fn_ptr: np.ndarray
    fn_data: np.ndarray
    # state layout (clearance.layout.StateLayout)
    y_iv: int
    y_iz: int
    y_iw: int
    y_idn: int
    y_idt: int
    y_ny: int
    # clearance joints and their contact points (compile.clearances), packed: column layouts
    # in clearance.kinds (CI_*, CG_*, CV_*, PI_*, PG_*), kind columns in the contact kernels
    nclr: int
    clr_ix: np.ndarray  # (nclr, NCLRI) int: kind, outer / inner body, slides, points
    clr_geo: np.ndarray  # (nclr, NCLRG): clearance, velocity floor, onset tolerance, geometry
    clr_vec: np.ndarray  # (nclr, 4, 3): outer / inner centre, their slide axes (body frames)
    clr_T: np.ndarray  # (nclr, 2, 3, 3): outer / inner marker triads (body frames)
    clr_wear: np.ndarray  # (nw, 5): worn sockets' depth fields (contact/spherical.py)
    ncp: int
    cp_ix: np.ndarray  # (ncp, NCPI) int: contact kind, clearance joint, normal, friction law
    cp_geo: np.ndarray  # (ncp, NCPG): share of the law, event tolerance [m], geometry
    cp_par: np.ndarray  # (ncp, 2, NPAR): normal and friction law parameters
    cp_kptr: np.ndarray  # (len(ContactKind) + 1,) index sets per kind (kinds.PI_ORDER)
    body_vfn: np.ndarray  # (nb,) length function of an InertiaVariation, -1: constant inertia
    body_var: np.ndarray  # (nb, 5) moments (3), offset, rate term on (1) / off (0)


@dataclass(frozen=True)
class Block:
    """A named slice of the constraint rows (one joint or driver)."""

    name: str
    kind: str
    row0: int
    nrows: int
    body_i: str
    body_j: str


@dataclass(frozen=True)
class Compiled:
    """A compiled mechanism: kernel arrays plus names and index maps."""

    mechanism: Mechanism
    model: Model
    body_names: tuple
    joints: tuple  # Blocks of joint rows
    drivers: tuple  # Blocks of driver rows
    y0: np.ndarray = field(repr=False)
    clearances: tuple = ()  # ClearanceInfo per clearance joint
    contact_points: tuple = ()  # ContactPointInfo per contact point

    @property
    def nb(self) -> int:
        return self.model.nb

    @property
    def nq(self) -> int:
        return 7 * self.model.nb

    @property
    def nv(self) -> int:
        return 6 * self.model.nb

    @property
    def nrow(self) -> int:
        return self.model.nrow

    @property
    def nclr(self) -> int:
        return self.model.nclr

    @property
    def ncp(self) -> int:
        return self.model.ncp

    @property
    def layout(self) -> StateLayout:
        """Offsets of the parts of the state vector y."""
        return StateLayout(self.model.nb, self.model.ncp, self.model.nclr)

    @property
    def iz(self) -> int:
        """Start of the LuGre bristle states in y."""
        return self.layout.iz

    @property
    def iw(self) -> int:
        """Start of the work integrals W_c, W_d, W_a, W_m, W_L, D_n..., D_t... in y."""
        return self.layout.iw

    @property
    def ny(self) -> int:
        return self.layout.ny

    def q_slice(self, body: str) -> slice:
        k = self.body_names.index(body)
        return slice(7 * k, 7 * k + 7)

    def v_slice(self, body: str) -> slice:
        k = self.body_names.index(body)
        return slice(6 * k, 6 * k + 6)

    def rows(self, name: str) -> slice:
        for b in self.joints + self.drivers:
            if b.name == name:
                return slice(b.row0, b.row0 + b.nrows)
        raise KeyError(f"no joint or driver named {name!r}")

    def describe(self) -> str:
        """Human-readable layout of y (q, v, z, work integrals) and lam."""
        nb = self.nb
        lay = self.layout
        work = ", ".join(n.split("_", 1)[1] for n, _ in WORK)
        lines = [
            f"Compiled mechanism '{self.mechanism.name}': {nb} moving bodies, "
            f"{self.nrow} constraint rows, {self.nv} velocity coordinates, "
            f"{self.nclr} clearance joint(s) with {self.ncp} contact point(s), "
            f"DOF (structural) = {self.nv - self.nrow}",
            f"state y ({lay.ny}) = [q (0:{self.nq}) | v ({self.nq}:{self.nq + self.nv}) "
            f"| z ({lay.iz}:{lay.iw}) | work {work} ({lay.iw}:{lay.idn}) "
            f"| D_n ({lay.idn}:{lay.idt}) | D_t ({lay.idt}:{lay.ny})]",
            "bodies:",
        ]
        for k, n in enumerate(self.body_names):
            lines.append(
                f"  {n:<20s} q[{7 * k}:{7 * k + 3}] r, q[{7 * k + 3}:{7 * k + 7}] p; "
                f"v[{6 * k}:{6 * k + 3}] r_dot, v[{6 * k + 3}:{6 * k + 6}] omega'"
            )
        lines.append("constraints (lam rows):")
        for b in self.joints + self.drivers:
            if b.nrows:
                lines.append(
                    f"  lam[{b.row0}:{b.row0 + b.nrows}] {b.kind:<18s} {b.name} "
                    f"({b.body_i} -> {b.body_j})"
                )
        if self.clearances:
            lines.append("clearance joints (force elements; their remaining rows are above):")
            p = 0
            for k, ci in enumerate(self.clearances):
                n = len(ci.points)
                lines.append(
                    f"  [{k}] {ci.name}: {ci.kind} ({ci.model}), outer part on "
                    f"{ci.socket_body}, inner on {ci.ball_body}, c = {ci.c:.4g} m, {ci.normal}, "
                    f"{ci.friction}; {n} contact point(s), z = y[{lay.iz + 3 * p}:"
                    f"{lay.iz + 3 * (p + n)}]"
                )
                p += n
        return "\n".join(lines)


class _Builder:
    def __init__(self, mech: Mechanism) -> None:
        self.mech = mech
        self.bidx = {n: k for k, n in enumerate(mech.bodies)}
        self.prims: list = []  # (kind, bi, bj, fn, v(4,3), ix(8))
        self.nrow = 0
        self.row_drv: list = []
        self.funcs: list = []
        self.slide_fn: dict = {}

    def body(self, name: str) -> int:
        return -1 if name == GROUND else self.bidx[name]

    def fn(self, f) -> int:
        self.funcs.append(f)
        return len(self.funcs) - 1

    def prim(
        self,
        kind,
        bi,
        bj,
        *,
        sbi=None,
        sbj=None,
        abi=None,
        abj=None,
        fn=-1,
        ix=None,
        driver=False,
        mi=None,
        mj=None,
    ) -> None:
        """Add a primitive; mi/mj name the markers of its points (for sliding markers)."""
        v = np.zeros((NPV, 3))
        for slot, x in ((SB_I, sbi), (SB_J, sbj), (AB_I, abi), (AB_J, abj)):
            if x is not None:
                v[slot] = x
        mv = np.array([-1, -1], dtype=np.int64)
        for side, (slot, name) in enumerate(((AX_I, mi), (AX_J, mj))):
            if name is not None:
                mv[side], ax = self.slide(name)
                v[slot] = ax
        ixa = np.zeros(8, dtype=np.int64) if ix is None else np.asarray(ix, dtype=np.int64)
        self.prims.append((int(kind), bi, bj, self.nrow, fn, v, ixa, mv))
        n = PRIM_ROWS[kind]
        self.row_drv.extend([1 if driver else 0] * n)
        self.nrow += n

    def marker(self, name: str):
        m = self.mech.markers[name]
        return self.body(m.body), np.array(m.position), np.array(m.orientation)

    def slide(self, name: str) -> tuple[int, np.ndarray]:
        """(function index or -1, body-frame axis) of a marker's moving attachment."""
        m = self.mech.markers[name]
        if m.slide is None:
            return -1, np.zeros(3)
        if name not in self.slide_fn:
            self.slide_fn[name] = self.fn(m.slide)
        return self.slide_fn[name], np.array(m.slide_axis)


def _joint_prims(b: _Builder, jt) -> None:
    bi, pi, Ti = b.marker(jt.marker_i)
    bj, pj, Tj = b.marker(jt.marker_j)
    fi, gi, hi = Ti[:, 0], Ti[:, 1], Ti[:, 2]
    fj, gj, hj = Tj[:, 0], Tj[:, 1], Tj[:, 2]
    k = jt.kind
    if getattr(jt, "clearance", None) is not None:
        clearance_rows(b, jt)  # the rows its clearance keeps ideal
        return
    if k in (JointType.SPHERICAL, JointType.UNIVERSAL, JointType.REVOLUTE, JointType.FIXED):
        b.prim(PrimKind.SPHERICAL, bi, bj, sbi=pi, sbj=pj, mi=jt.marker_i, mj=jt.marker_j)
    if k == JointType.UNIVERSAL:
        b.prim(PrimKind.DOT1, bi, bj, abi=hi, abj=hj)
    elif k == JointType.REVOLUTE:
        b.prim(PrimKind.DOT1, bi, bj, abi=fi, abj=hj)
        b.prim(PrimKind.DOT1, bi, bj, abi=gi, abj=hj)
    elif k in (JointType.CYLINDRICAL, JointType.PRISMATIC):
        b.prim(PrimKind.DOT1, bi, bj, abi=fi, abj=hj)
        b.prim(PrimKind.DOT1, bi, bj, abi=gi, abj=hj)
        b.prim(PrimKind.DOT2, bi, bj, sbi=pi, sbj=pj, abi=fi, mi=jt.marker_i, mj=jt.marker_j)
        b.prim(PrimKind.DOT2, bi, bj, sbi=pi, sbj=pj, abi=gi, mi=jt.marker_i, mj=jt.marker_j)
        if k == JointType.PRISMATIC:
            b.prim(PrimKind.DOT1, bi, bj, abi=fi, abj=gj)
    elif k == JointType.FIXED:
        b.prim(PrimKind.DOT1, bi, bj, abi=fi, abj=gj)
        b.prim(PrimKind.DOT1, bi, bj, abi=gi, abj=hj)
        b.prim(PrimKind.DOT1, bi, bj, abi=hi, abj=fj)


def _offset_row(b: _Builder, mi: str, mj: str, function) -> tuple[str, str]:
    """h_i . (P_j - P_i) - f(t): the row of PrismaticDriver (its joint's markers) and of
    OffsetDriver (dot-2 primitive, c.3)."""
    mech = b.mech
    bi, pi, Ti = b.marker(mi)
    bj, pj, _ = b.marker(mj)
    b.prim(
        PrimKind.DOT2,
        bi,
        bj,
        sbi=pi,
        sbj=pj,
        abi=Ti[:, 2],
        fn=b.fn(function),
        driver=True,
        mi=mi,
        mj=mj,
    )
    return mech.markers[mi].body, mech.markers[mj].body


def _driver_prims(b: _Builder, d) -> tuple[str, str]:
    mech = b.mech
    if isinstance(d, PrismaticDriver):
        jt = mech.joints[d.joint]
        return _offset_row(b, jt.marker_i, jt.marker_j, d.function)
    if isinstance(d, OffsetDriver):
        return _offset_row(b, d.marker_i, d.marker_j, d.function)
    if isinstance(d, DistanceDriver):
        bi, pi, _ = b.marker(d.marker_i)
        bj, pj, _ = b.marker(d.marker_j)
        kind = PrimKind.DISTANCE2 if d.squared else PrimKind.DISTANCE
        b.prim(
            kind,
            bi,
            bj,
            sbi=pi,
            sbj=pj,
            fn=b.fn(d.function),
            driver=True,
            mi=d.marker_i,
            mj=d.marker_j,
        )
        return mech.markers[d.marker_i].body, mech.markers[d.marker_j].body
    if isinstance(d, PositionDriver):
        bj, pj, _ = b.marker(d.marker)
        b.prim(
            PrimKind.DOT2,
            -1,
            bj,
            sbi=np.zeros(3),
            sbj=pj,
            abi=np.array(d.axis),
            fn=b.fn(d.function),
            driver=True,
            mj=d.marker,
        )
        return GROUND, mech.markers[d.marker].body
    if isinstance(d, RevoluteDriver):
        # f_j . c(t) with c = T_i Rz(theta(t)) e_y, T_i = Rz(psi) Rx(phi) Rz(chi): the
        # orientation driver's moving dot-1 row with the angles (psi, phi, chi + theta(t))
        jt = mech.joints[d.joint]
        bj, _, Tj = b.marker(jt.marker_j)
        psi, phi, chi = zxz_angles(mech.markers[jt.marker_i].orientation)
        fns = [b.fn(Constant(psi)), b.fn(Constant(phi)), b.fn(Scaled(d.function, 1.0, chi))]
        b.prim(PrimKind.DOT1_MOVING, -1, bj, abj=Tj[:, 0], ix=[*fns, 2, 0, 2, 1, 0], driver=True)
        return GROUND, mech.markers[jt.marker_j].body
    if isinstance(d, OrientationDriver):
        bj, _, Tj = b.marker(d.marker)
        fns = [b.fn(a) for a in d.angles]
        ax = list(d.axes)
        # full: f.R ey, g.R ez, h.R ex (fixed-joint triple, c.3); axis: h.R ex, h.R ey
        pairs = [(0, 1), (1, 2), (2, 0)] if d.mode == "full" else [(2, 0), (2, 1)]
        for col, m in pairs:
            b.prim(PrimKind.DOT1_MOVING, -1, bj, abj=Tj[:, col], ix=[*fns, *ax, m, 0], driver=True)
        return GROUND, mech.markers[d.marker].body
    raise TypeError(f"unknown driver type {type(d).__name__}")


def _force_arrays(b: _Builder):
    mech = b.mech
    kinds, bis, bjs, vs, pars, fns = [], [], [], [], [], []
    for f in mech.forces.values():
        for mname in (
            getattr(f, "marker", None),
            getattr(f, "marker_i", None),
            getattr(f, "marker_j", None),
        ):
            if mname is not None and mech.markers[mname].slide is not None:
                raise ModelError(
                    f"{type(f).__name__} '{f.name}'",
                    "marker",
                    mname,
                    "forces at sliding (moving-attachment) markers are not "
                    "supported; attach the force to a fixed marker",
                )
        v = np.zeros((3, 3))
        par = np.zeros(4)
        bj = -1
        if isinstance(f, (PointForce, Torque)):
            bi, pi, Ti = b.marker(f.marker)
            direction = np.array(f.direction if isinstance(f, PointForce) else f.axis)
            if f.frame == "marker":
                direction = Ti @ direction  # into body components
                par[3] = 1.0
            v[0] = pi
            v[2] = direction
            fn = b.fn(f.magnitude)
        elif isinstance(f, SpringDamper):
            bi, pi, _ = b.marker(f.marker_i)
            bj, pj, _ = b.marker(f.marker_j)
            v[0], v[1] = pi, pj
            par[:3] = (f.stiffness, f.damping, f.free_length)
            fn = b.fn(f.actuator)
        else:  # pragma: no cover - Mechanism.add rejects other types
            raise TypeError(type(f).__name__)
        kinds.append(int(f.kind))
        bis.append(bi)
        bjs.append(bj)
        vs.append(v)
        pars.append(par)
        fns.append(fn)
    n = len(kinds)
    return (
        np.array(kinds, dtype=np.int64),
        np.array(bis, dtype=np.int64),
        np.array(bjs, dtype=np.int64),
        np.array(vs).reshape(n, 3, 3),
        np.array(pars).reshape(n, 4),
        np.array(fns, dtype=np.int64),
    )


def _factor_order(nrow: int, lists: list) -> np.ndarray:
    """Row order for the Cholesky factor of S: reverse Cuthill-McKee on the graph of rows
    that share a body (scipy). On the 4UPS-UPU a minimum-degree order was tried and gives
    the same fill (ideal: 507 non-zeros of L, 1949 products in the factorisation)."""
    if nrow == 0:
        return np.zeros(0, dtype=np.int64)
    ri, ci = [], []
    for rows in lists:
        rs = [r for r, _ in rows]
        for a in rs:
            for c in rs:
                ri.append(a)
                ci.append(c)
    g = sp.csr_matrix((np.ones(len(ri)), (ri, ci)), shape=(nrow, nrow))
    order = reverse_cuthill_mckee(g, symmetric_mode=True)
    pos = np.empty(nrow, dtype=np.int64)
    pos[order] = np.arange(nrow)
    return pos


#: the sparse Cholesky is compiled in where its products (dot-product terms over L's
#: pattern) are at most this fraction of the envelope Cholesky's. Measured in the
#: integration loop (dynamics/solve.py, sparse_cholesky): the ideal 4UPS-UPU (0.22) runs
#: 24 % faster sparse, the default clearance model (0.61) 8 % slower; 0: never sparse
SPARSE_RATIO = 0.5


def _symbolic_cholesky(nrow: int, entries: set) -> list:
    """Row patterns of the Cholesky factor L of a symmetric matrix whose lower-triangle
    non-zeros are the flat indices nrow * i + j in `entries` (factor order): for each row i,
    the columns k < i with L[i, k] structurally non-zero, increasing. L[i, c] (c < i) is
    non-zero where the matrix is, and where L[i, k] and L[c, k] are both non-zero for some
    k < c (fill): so row i's pattern is closed under "k in it -> every c < i of column k of
    L in it". Every entry outside it is an exact zero during the numeric factorisation: it
    starts at zero and each of its products has a zero factor."""
    rows: list[set] = [set() for _ in range(nrow)]
    for d in entries:
        i, j = divmod(int(d), nrow)
        if j < i:
            rows[i].add(j)
    cols: list[list] = [[] for _ in range(nrow)]  # rows below k seen so far, per column k
    out = []
    for i in range(nrow):
        pat = set(rows[i])
        todo = sorted(pat, reverse=True)
        while todo:
            k = todo.pop()
            for c in cols[k]:  # (rows c < i with L[c, k] != 0)
                if c not in pat:
                    pat.add(c)
                    todo.append(c)
        out.append(sorted(pat))
        for k in pat:
            cols[k].append(i)
    return out


def _schur_structure(nrow: int, lists: list, pos: np.ndarray, rot_only: np.ndarray) -> dict:
    """Model.sch_* arrays: the envelope of S = J M^-1 J^T in factor order and its columns,
    or, where the sparse Cholesky does far fewer products (SPARSE_RATIO), the pattern of
    its factor L (by row, by column, and per entry the terms of its dot product); and the
    assembly terms (one per pair of rows sharing a body), grouped so that the run-time
    assembly does no index searching, no clearing of assembled entries and no products
    with structural zeros. Rows sharing no body are structural zeros; the envelope contains
    L's pattern, which adds the fill (`_symbolic_cholesky`); the fill is cleared before each
    assembly. rot_only[r]: row r has no translational Jacobian columns."""
    first = np.arange(nrow, dtype=np.int64)
    groups: list[list] = [[], [], [], []]
    seen = set()
    for rows in lists:
        for a in range(len(rows)):
            ra, sa = rows[a]
            for c in range(a + 1):
                rc, sc = rows[c]
                pa, pc = pos[ra], pos[rc]
                hi, lo = (pa, pc) if pa >= pc else (pc, pa)
                dst = nrow * hi + lo
                short = bool(rot_only[ra] or rot_only[rc])
                off = 3 if short else 0  # skip the translational products
                g = (2 if dst in seen else 0) + (0 if short else 1)
                seen.add(dst)
                groups[g].append((12 * ra + 6 * sa + off, 12 * rc + 6 * sc + off, dst))
                first[hi] = min(first[hi], lo)
    rowpat = _symbolic_cholesky(nrow, seen)
    ecols = [[i for i in range(j + 1, nrow) if first[i] <= j] for j in range(nrow)]
    env_products = sum(
        j - first[j] + sum(j - max(first[i], first[j]) for i in ecols[j]) for j in range(nrow)
    )
    rowsets = [set(r) for r in rowpat]
    pcols: list[list] = [[] for _ in range(nrow)]
    for i in range(nrow):
        for k in rowpat[i]:
            pcols[k].append(i)
    dots = [[k for k in rowpat[j] if k in rowsets[i]] for j in range(nrow) for i in pcols[j]]
    sp_products = sum(len(r) for r in rowpat) + sum(len(d) for d in dots)
    sparse = env_products > 0 and SPARSE_RATIO > 0.0 and sp_products <= SPARSE_RATIO * env_products
    if sparse:
        cols = pcols
        fill = [nrow * p + c for p in range(nrow) for c in (*rowpat[p], p)]
    else:
        cols = ecols
        fill = [nrow * p + c for p in range(nrow) for c in range(first[p], p + 1)]
        rowpat, dots = [[] for _ in range(nrow)], []
    colptr = np.zeros(nrow + 1, dtype=np.int64)
    colptr[1:] = np.cumsum([len(c) for c in cols])
    rowptr = np.zeros(nrow + 1, dtype=np.int64)
    rowptr[1:] = np.cumsum([len(r) for r in rowpat])
    dotptr = np.zeros(len(dots) + 1, dtype=np.int64)
    dotptr[1:] = np.cumsum([len(d) for d in dots])
    pairs = [t for g in groups for t in g]
    return dict(
        sch_sparse=int(sparse),
        sch_first=first.astype(np.uint32),
        sch_colptr=colptr,
        sch_colidx=np.array([i for c in cols for i in c], dtype=np.uint32),
        sch_rowptr=rowptr,
        sch_rowidx=np.array([k for r in rowpat for k in r], dtype=np.uint32),
        sch_dotptr=dotptr,
        sch_dotidx=np.array([k for d in dots for k in d], dtype=np.uint32),
        sch_pair=np.array(pairs, dtype=np.uint32).reshape(len(pairs), 3),
        sch_grp=np.concatenate([[0], np.cumsum([len(g) for g in groups])]).astype(np.int64),
        sch_fill=np.array([d for d in fill if d not in seen], dtype=np.uint32),
    )


def compile_mechanism(mech: Mechanism) -> Compiled:
    """Validate and compile a mechanism into kernel arrays (the input is not modified)."""
    mech.validate()
    b = _Builder(mech)
    joints, drivers = [], []
    for jt in mech.joints.values():
        r0 = b.nrow
        _joint_prims(b, jt)
        joints.append(
            Block(
                jt.name,
                type(jt).__name__,
                r0,
                b.nrow - r0,
                mech.markers[jt.marker_i].body,
                mech.markers[jt.marker_j].body,
            )
        )
    for d in mech.drivers.values():
        r0 = b.nrow
        bi_name, bj_name = _driver_prims(b, d)
        drivers.append(Block(d.name, type(d).__name__, r0, b.nrow - r0, bi_name, bj_name))
    frc = _force_arrays(b)
    clr, clr_info, cp_info = clearance_arrays(b, mech)
    nb = mech.nbody
    npr = len(b.prims)
    prim_kind = np.array([p[0] for p in b.prims], dtype=np.int64)
    prim_bi = np.array([p[1] for p in b.prims], dtype=np.int64)
    prim_bj = np.array([p[2] for p in b.prims], dtype=np.int64)
    prim_row = np.array([p[3] for p in b.prims], dtype=np.int64)
    prim_fn = np.array([p[4] for p in b.prims], dtype=np.int64)
    prim_v = np.array([p[5] for p in b.prims]).reshape(npr, NPV, 3)
    prim_mv = np.array([p[7] for p in b.prims], dtype=np.int64).reshape(npr, 2)
    prim_ix = np.array([p[6] for p in b.prims], dtype=np.int64).reshape(npr, 8)
    row_bi = np.empty(b.nrow, dtype=np.int64)
    row_bj = np.empty(b.nrow, dtype=np.int64)
    for k in range(npr):
        n = PRIM_ROWS[PrimKind(prim_kind[k])]
        row_bi[prim_row[k] : prim_row[k] + n] = prim_bi[k]
        row_bj[prim_row[k] : prim_row[k] + n] = prim_bj[k]
    lists = [[] for _ in range(nb)]
    for r in range(b.nrow):
        if row_bi[r] >= 0:
            lists[row_bi[r]].append((r, 0))
        if row_bj[r] >= 0:
            lists[row_bj[r]].append((r, 1))
    brow_ptr = np.zeros(nb + 1, dtype=np.int64)
    brow_ptr[1:] = np.cumsum([len(x) for x in lists])
    flat = [e for x in lists for e in x]
    brow_idx = np.array([e[0] for e in flat], dtype=np.int64)
    brow_slot = np.array([e[1] for e in flat], dtype=np.int64)
    bodies = list(mech.bodies.values())
    # functions must all be registered before encoding
    body_vfn = np.array(
        [
            -1 if bd.inertia_variation is None else b.fn(bd.inertia_variation.length)
            for bd in bodies
        ],
        dtype=np.int64,
    )
    body_var = np.array(
        [
            (0.0, 0.0, 0.0, 0.0, 0.0)
            if bd.inertia_variation is None
            else (
                *bd.inertia_variation.moments,
                bd.inertia_variation.offset,
                float(bd.inertia_variation.rate_term),
            )
            for bd in bodies
        ]
    ).reshape(len(bodies), 5)
    fn_kind, fn_ptr, fn_data = encode_functions(b.funcs)
    row_pos = _factor_order(b.nrow, lists)
    rot_only = np.zeros(b.nrow, dtype=bool)
    for k in range(npr):
        if PrimKind(prim_kind[k]) in ROTATION_ONLY:
            rot_only[prim_row[k] : prim_row[k] + PRIM_ROWS[PrimKind(prim_kind[k])]] = True
    schur = _schur_structure(b.nrow, lists, row_pos, rot_only)
    body_J = np.array([bd.inertia_matrix for bd in bodies]).reshape(nb, 3, 3)
    model = Model(
        nb=nb,
        nrow=b.nrow,
        body_mass=np.array([bd.mass for bd in bodies]),
        body_J=body_J,
        body_Jinv=np.linalg.inv(body_J) if nb else body_J.copy(),
        body_vfn=body_vfn,
        body_var=body_var,
        gravity=np.array(mech.gravity, dtype=float),
        prim_kind=prim_kind,
        prim_bi=prim_bi,
        prim_bj=prim_bj,
        prim_row=prim_row,
        prim_fn=prim_fn,
        prim_v=prim_v,
        prim_mv=prim_mv,
        prim_ix=prim_ix,
        row_bi=row_bi,
        row_bj=row_bj,
        row_drv=np.array(b.row_drv, dtype=np.int64),
        row_pos=row_pos,
        **schur,
        brow_ptr=brow_ptr,
        brow_idx=brow_idx,
        brow_slot=brow_slot,
        frc_kind=frc[0],
        frc_bi=frc[1],
        frc_bj=frc[2],
        frc_v=frc[3],
        frc_par=frc[4],
        frc_fn=frc[5],
        fn_kind=fn_kind,
        fn_ptr=fn_ptr,
        fn_data=fn_data,
        **clr,
        **StateLayout(nb, clr["ncp"], clr["nclr"]).model_fields(),
    )
    for a in model:
        if isinstance(a, np.ndarray):
            a.setflags(write=False)
    y0 = np.zeros(model.y_ny)
    for k, bd in enumerate(bodies):
        y0[7 * k : 7 * k + 3] = bd.position
        y0[7 * k + 3 : 7 * k + 7] = bd.orientation
        y0[7 * nb + 6 * k : 7 * nb + 6 * k + 3] = bd.velocity
        y0[7 * nb + 6 * k + 3 : 7 * nb + 6 * k + 6] = bd.angular_velocity
    return Compiled(
        mechanism=mech,
        model=model,
        body_names=tuple(mech.bodies),
        joints=tuple(joints),
        drivers=tuple(drivers),
        y0=y0,
        clearances=clr_info,
        contact_points=cp_info,
    )
