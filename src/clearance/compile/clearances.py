"""Encode clearance joints: each joint's description -> one row of the joint arrays
(Model.clr_ix, clr_geo, clr_vec, clr_T) and one row per contact point (Model.cp_ix, cp_geo,
cp_par), plus their names (column layouts in `clearance.kinds`), and the rows of the joint
that its clearance keeps ideal (`clearance_rows`).

Per kind (kinds.ClearanceKind) an encoder gives the joint's geometry row (clr_geo), its
clearance c, and its contact points (kind, geometry row cp_geo, share w of the normal law,
event tolerance, law); the rest is common. The kernels read these layouts
(`clearance.contact.spherical`, `journal`, `slider`). Adding a clearance kind: its encoder
here with its entry in ENCODERS, and its kept rows in ROWS.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clearance.compile.laws import ContactGeometry, encode_friction, encode_normal
from clearance.kinds import (
    CG_C,
    CG_K0,
    CG_OTOL,
    CG_VFLOOR,
    CI_BB,
    CI_BS,
    CI_KIND,
    CI_MVB,
    CI_MVS,
    CI_NP,
    CI_NW,
    CI_P0,
    CI_W0,
    CV_AXB,
    CV_AXS,
    CV_PB,
    CV_PS,
    NCLRG,
    NCLRI,
    NCPG,
    NCPI,
    NPAR,
    PG_K0,
    PG_TOL,
    PG_W,
    PI_CLR,
    PI_FRIC,
    PI_KIND,
    PI_LAW,
    PI_ORDER,
    ClearanceKind,
    ContactKind,
    JointType,
    PrimKind,
)
from clearance.model.bodies import GROUND
from clearance.model.clearance import Clearance, PrismaticClearance, RevoluteClearance
from clearance.model.contact_laws import law_name
from clearance.model.errors import ModelError
from clearance.model.mechanism import Mechanism
from clearance.model.wear import BearingWear


@dataclass(frozen=True)
class ClearanceInfo:
    """Names and key numbers of one compiled clearance joint.

    kind: "spherical", "revolute", "cylindrical" or "prismatic"; model: "spatial" or
    "planar"; socket_body / ball_body: bodies of the outer part (socket, bearing, guide) and
    the inner one (ball, journal, slider); c: radial clearance (prismatic: per side, width
    direction) [m]; ball_radius / socket_radius: inner / outer radius [m] (prismatic: half
    width of the slider and of the guide channel); normal, friction: registry names of the
    laws; points: names of its contact points.
    """

    name: str
    socket_body: str
    ball_body: str
    c: float
    ball_radius: float
    socket_radius: float
    normal: str
    friction: str
    kind: str = "spherical"
    model: str = "spatial"
    points: tuple = ()


@dataclass(frozen=True)
class ContactPointInfo:
    """One contact point: its name, its clearance joint, its kind (kinds.ContactKind)."""

    name: str
    joint: str
    kind: str


@dataclass
class _Point:
    name: str
    kind: ContactKind
    geo: tuple
    w: float
    scale: float  # length the event tolerance is a fraction of [m]
    thrust: bool = False  # uses the thrust law


def _effective_mass(mech: Mechanism, ms: str, mb: str) -> float:
    """m_s m_b / (m_s + m_b) of the two bodies (ground: infinite mass), for laws that need
    an effective mass (Kelvin-Voigt damping from restitution, physics.md g.3)."""
    ms_ = mech.markers[ms].body
    mb_ = mech.markers[mb].body
    m1 = mech.bodies[ms_].mass if ms_ != GROUND else np.inf
    m2 = mech.bodies[mb_].mass if mb_ != GROUND else np.inf
    if np.isinf(m1):
        return float(m2)
    if np.isinf(m2):
        return float(m1)
    return float(m1 * m2 / (m1 + m2))


def _spherical(name: str, cl: Clearance, joint: JointType):
    geo = (cl.socket_radius, cl.ball_radius)
    pts = [_Point(name, ContactKind.SPHERE, (), 1.0, cl.c)]
    return geo, pts, (cl.ball_radius, cl.socket_radius), (cl.ball_material, cl.socket_material)


def _revolute(name: str, cl: RevoluteClearance, joint: JointType):
    L = cl.length if cl.length is not None else 0.0
    ca = cl.axial_clearance if cl.axial_clearance is not None else 0.0
    geo = (cl.bearing_radius, cl.journal_radius, L, ca, cl.thrust_radius)
    pts = []
    if cl.model == "planar":
        pts.append(_Point(name, ContactKind.JOURNAL_STATION, (0.0,), 1.0, cl.c))
    else:
        n = cl.stations
        for j in range(n):  # midpoints of n equal slices of the bearing length
            sigma = L * (-0.5 + (j + 0.5) / n)
            pts.append(
                _Point(
                    f"{name}/station{j + 1}", ContactKind.JOURNAL_STATION, (sigma,), 1.0 / n, cl.c
                )
            )
        if cl.axial_clearance is not None:
            m = cl.thrust_points
            for side, tag in ((1.0, "+"), (-1.0, "-")):
                for j in range(m):
                    psi = 2.0 * math.pi * j / m
                    pts.append(
                        _Point(
                            f"{name}/thrust{tag}{j + 1}",
                            ContactKind.THRUST_POINT,
                            (side, math.cos(psi), math.sin(psi)),
                            1.0 / m,
                            ca,
                            thrust=True,
                        )
                    )
    radii = (cl.journal_radius, cl.bearing_radius)
    return geo, pts, radii, (cl.journal_material, cl.bearing_material)


def _prismatic(name: str, cl: PrismaticClearance, joint: JointType):
    af, ln = 0.5 * cl.width, 0.5 * cl.length
    ag = 0.5 * cl.height if cl.height is not None else 0.0
    cg = cl.clearance_height if cl.clearance_height is not None else cl.clearance
    geo = (af, ag, ln, cl.clearance, cg)
    pts = []
    sg_values = (0.0,) if cl.model == "planar" else (1.0, -1.0)
    for sh in (1.0, -1.0):
        for sf in (1.0, -1.0):
            for sg in sg_values:
                corner = f"{'+' if sh > 0 else '-'}{'+' if sf > 0 else '-'}"
                if cl.model == "spatial":
                    corner += "+" if sg > 0 else "-"
                walls = ((0.0, "f", cl.clearance),)
                if cl.model == "spatial":
                    walls += ((1.0, "g", cg),)
                for wall, wname, cw in walls:
                    pts.append(
                        _Point(
                            f"{name}/corner{corner}{wname}",
                            ContactKind.SLIDER_CORNER,
                            (sh, sf, sg, wall),
                            1.0,
                            cw,
                        )
                    )
    R = cl.corner_radius if cl.corner_radius is not None else 1.0  # only if no stiffness
    return geo, pts, (R, math.inf), (cl.slider_material, cl.guide_material)


# per kind: its joint geometry row, contact points, radii and materials
ENCODERS = {
    ClearanceKind.SPHERICAL: _spherical,
    ClearanceKind.REVOLUTE: _revolute,
    ClearanceKind.PRISMATIC: _prismatic,
}


def _revolute_rows(b, cl: RevoluteClearance, joint: JointType, ms, mb, bs, bb, Ts, Tb, ps, pb):
    """A planar journal stays aligned with its bearing (h_b normal to f_s and g_s); a
    revolute one stays axially in place (h_s . d = 0) unless it has an axial clearance."""
    if cl.model == "planar":
        b.prim(PrimKind.DOT1, bs, bb, abi=Ts[:, 0], abj=Tb[:, 2])
        b.prim(PrimKind.DOT1, bs, bb, abi=Ts[:, 1], abj=Tb[:, 2])
    if joint == JointType.REVOLUTE and cl.axial_clearance is None:
        b.prim(PrimKind.DOT2, bs, bb, sbi=ps, sbj=pb, abi=Ts[:, 2], mi=ms, mj=mb)


def _prismatic_rows(b, cl: PrismaticClearance, joint: JointType, ms, mb, bs, bb, Ts, Tb, ps, pb):
    """A planar slider stays in the guide's f-h plane: g_s . d = 0, g_s . h_b = 0,
    g_s . f_b = 0."""
    if cl.model == "planar":
        b.prim(PrimKind.DOT2, bs, bb, sbi=ps, sbj=pb, abi=Ts[:, 1], mi=ms, mj=mb)
        b.prim(PrimKind.DOT1, bs, bb, abi=Ts[:, 1], abj=Tb[:, 2])
        b.prim(PrimKind.DOT1, bs, bb, abi=Ts[:, 1], abj=Tb[:, 0])


# per kind: the rows of the joint its clearance keeps ideal (model.clearance `kept_rows`)
ROWS = {
    ClearanceKind.SPHERICAL: lambda *args: None,  # the ball moves freely: no rows
    ClearanceKind.REVOLUTE: _revolute_rows,
    ClearanceKind.PRISMATIC: _prismatic_rows,
}


def clearance_rows(b, jt) -> None:
    """Add the rows of clearance joint `jt` that stay ideal, written from the outer marker
    (socket, bearing, guide) to the inner one. `b`: the compile builder."""
    cl = jt.clearance
    ms, mb = (jt.marker_i, jt.marker_j) if cl.outer == "i" else (jt.marker_j, jt.marker_i)
    bs, ps, Ts = b.marker(ms)
    bb, pb, Tb = b.marker(mb)
    n0 = b.nrow
    ROWS[cl.kind](b, cl, jt.kind, ms, mb, bs, bb, Ts, Tb, ps, pb)
    assert b.nrow - n0 == cl.kept_rows(jt.kind), "kept_rows out of step with the rows"


def _kind_name(cl: object, joint: JointType) -> str:
    if isinstance(cl, RevoluteClearance) and joint == JointType.CYLINDRICAL:
        return "cylindrical"
    return ClearanceKind(cl.kind).name.lower()  # type: ignore[attr-defined]


def clearance_arrays(b, mech: Mechanism) -> tuple[dict, tuple, tuple]:
    """Model arrays (clr_*, cp_*, nclr, ncp) of the joints of `mech` that have a clearance,
    and their ClearanceInfo / ContactPointInfo. `b`: the compile builder (markers, slides)."""
    jrows, prows, infos, pinfos = [], [], [], []
    wear_rows: list[np.ndarray] = []  # Model.clr_wear rows of worn sockets
    nw = 0
    for jt in mech.joints.values():
        cl = getattr(jt, "clearance", None)
        if cl is None:
            continue
        k = len(jrows)
        mi, mj = jt.marker_i, jt.marker_j
        ms, mb = (mi, mj) if cl.outer == "i" else (mj, mi)
        bs, ps, Ts = b.marker(ms)
        bb, pb, Tb = b.marker(mb)
        geo, pts, (r_in, r_out), (mat_in, mat_out) = ENCODERS[cl.kind](jt.name, cl, jt.kind)
        m_eff = _effective_mass(mech, ms, mb)
        laws = {}
        for thrust in sorted({pt.thrust for pt in pts}):
            law = cl.normal
            if thrust and getattr(cl, "thrust_normal", None) is not None:
                law = cl.thrust_normal
            try:
                length = cl.length if isinstance(cl, RevoluteClearance) and not thrust else None
                laws[thrust] = encode_normal(
                    law, ContactGeometry(r_in, r_out, mat_in, mat_out, m_eff, length)
                )
            except ModelError as e:
                raise ModelError(
                    f"{type(jt).__name__} '{jt.name}'", f"clearance.{e.field}", e.value, e.allowed
                ) from e
        fric, fpar = encode_friction(cl.friction)
        fs, axs = b.slide(ms)
        fb, axb = b.slide(mb)
        geo_row = np.zeros(NCLRG)
        geo_row[[CG_C, CG_VFLOOR, CG_OTOL]] = (cl.c, cl.velocity_floor, cl.onset_tolerance)
        geo_row[CG_K0 : CG_K0 + len(geo)] = geo
        ix = np.zeros(NCLRI, dtype=np.int64)
        ix[[CI_KIND, CI_BS, CI_BB, CI_MVS, CI_MVB]] = (int(cl.kind), bs, bb, fs, fb)
        ix[[CI_P0, CI_NP]] = (len(prows), len(pts))
        worn = mech.wear.get(jt.name)
        ring = {}  # station index -> (first row, rows) of a worn bearing's ring
        if isinstance(worn, BearingWear) and worn.max_depth() > 0.0:  # (contact/journal.py)
            first = nw
            for j in range(worn.stations):
                r = worn.ring_rows(j)
                if r.shape[0]:
                    ring[j] = (nw, r.shape[0])
                    wear_rows.append(r)
                    nw += r.shape[0]
            ix[[CI_W0, CI_NW]] = (first, nw - first)
        elif worn is not None and worn.max_depth() > 0.0:  # (contact/spherical.py)
            geo_row[CG_K0 + 2] = worn.smoothing
            ix[[CI_W0, CI_NW]] = (nw, worn.weights.size)
            wear_rows.append(worn.rows())
            nw += worn.weights.size
        vec = np.zeros((4, 3))
        vec[[CV_PS, CV_PB, CV_AXS, CV_AXB]] = (ps, pb, axs, axb)
        jrows.append((ix, geo_row, vec, np.array([Ts, Tb])))
        stations = [i for i, pt in enumerate(pts) if pt.kind == ContactKind.JOURNAL_STATION]
        for i, pt in enumerate(pts):
            code, par = laws[pt.thrust]
            pix = np.zeros(NCPI, dtype=np.int64)
            pix[[PI_KIND, PI_CLR, PI_LAW, PI_FRIC]] = (int(pt.kind), k, code, fric)
            q = np.zeros(NCPG)
            q[[PG_W, PG_TOL]] = (pt.w, cl.onset_tolerance * pt.scale)
            q[PG_K0 : PG_K0 + len(pt.geo)] = pt.geo
            if i in stations and stations.index(i) in ring:  # its ring's rows
                q[PG_K0 + 1 : PG_K0 + 3] = ring[stations.index(i)]
            prows.append((pix, q, np.array([par, fpar], dtype=float)))
            pinfos.append(ContactPointInfo(pt.name, jt.name, ContactKind(pt.kind).name.lower()))
        inner = (r_in, r_out) if cl.kind != ClearanceKind.PRISMATIC else (geo[0], geo[0] + geo[3])
        infos.append(
            ClearanceInfo(
                jt.name,
                mech.markers[ms].body,
                mech.markers[mb].body,
                cl.c,
                inner[0],
                inner[1],
                law_name(cl.normal),
                law_name(cl.friction),
                _kind_name(cl, jt.kind),
                getattr(cl, "model", "spatial"),
                tuple(p.name for p in pts),
            )
        )
    n, npt = len(jrows), len(prows)

    def stack(rows, i, shape, dtype=float):
        return np.array([r[i] for r in rows], dtype=dtype).reshape((len(rows), *shape))

    arrays = dict(
        nclr=n,
        clr_ix=stack(jrows, 0, (NCLRI,), np.int64),
        clr_geo=stack(jrows, 1, (NCLRG,)),
        clr_vec=stack(jrows, 2, (4, 3)),
        clr_T=stack(jrows, 3, (2, 3, 3)),
        ncp=npt,
        cp_ix=stack(prows, 0, (NCPI,), np.int64),
        cp_geo=stack(prows, 1, (NCPG,)),
        cp_par=stack(prows, 2, (2, NPAR)),
        clr_wear=np.concatenate(wear_rows) if wear_rows else np.zeros((0, 5)),
    )
    # the index sets per contact kind: points in kind order and the range of each kind
    kinds = arrays["cp_ix"][:, PI_KIND]
    arrays["cp_ix"][:, PI_ORDER] = np.argsort(kinds, kind="stable")
    arrays["cp_kptr"] = np.searchsorted(np.sort(kinds), np.arange(len(ContactKind) + 1))
    return arrays, tuple(infos), tuple(pinfos)
