"""Legs of parallel mechanisms from joint-type strings (base to platform): the geometry.

A leg is a serial chain from a base point A (world) to a platform point B (platform frame),
written as the joint letters read from the base: R (revolute), P (prismatic), C
(cylindrical), U (universal), S (spherical). Supported shapes (n joints, n - 1 links; names
of the links in brackets)::

    2 joints  X Y     one link from A to B                     [link]   SS, US, CU, PS, PU
              (X = P or C: the link slides along `rail` at A)
    3 joints  X P Y   the sliding joint in the middle, on the    [lower, upper]
              X C Y   line A-B (the actuated leg of a Stewart    UPS, SPS, RPS, UPU, SPU
                      platform)
              P X Y   a carriage on a rail through A, a rod of   [slider, rod]
              C X Y   fixed length from the knee to B            PRS, PUS, PSS
              R X Y   a crank about an axis through A, a rod of  [crank, rod]
                      fixed length from the knee to B            RSS, RUS, RRS
                      (parallelogram: two rods)                  [crank, rod_a, rod_b]

Conventions (all at the home pose, where the platform is parallel to the base):

* The leg's reference axis t (`Leg.axis`): tangent to the base circle at A,
  t = (-sin theta, cos theta, 0) for A at angle theta, or e_x for A on the z axis.
* Axes of the joints (world components; `Leg.axes` overrides any of them):
  R: t. U at the base or the knee: first axis t (on the body nearer the base), second axis
  (the link above) x t normalised. U at the platform: first axis (the link below) x t (on
  the link), second axis t (on the platform): a U-P-U leg's two U joints have parallel
  axes, which blocks the twist. P or C in the middle: the line A-B. P or C at the base:
  `Leg.rail` (default: vertical for a carriage; the line A-B for a 2-joint leg).
* Link frames: body z along the link from its lower to its upper joint (a carriage: along
  the rail); body x along t made normal to z when the base joint has an axis (R, U), else
  horizontal, e_z x z (e_x for a vertical link). Inertias are principal moments about the
  mass centre in these axes.
* Mass centres (`Link.com`): on the link's z axis, at `com` from its lower joint, or from
  its upper joint when the lower joint slides (the upper link of an X-P-Y leg, a carriage,
  a 2-joint link on a sliding base).
* Markers: i on the body nearer the base, j on the body nearer the platform, except the
  spherical joint at the platform, whose marker i is on the platform (the socket side of a
  later clearance, as in the seed papers).
* Actuator values: an X-P-Y leg's prismatic driver measures the leg length |A B|; a sliding
  base joint's driver the travel from home (0 at home); a crank's revolute driver the angle
  from the outward horizontal direction t x e_z about t (positive turns the crank down).
* Names: `<leg>.<joint>` with the letter of the joint, numbered from the base where a
  letter repeats (`leg5.U1`, `leg5.U2`; parallelogram rods add a / b: `leg1.S1a`); bodies
  `<leg>.<link>`; markers `<leg>.<joint>.i` / `.j`; the driver `<leg>.drive`.

`docs/parallel-mechanisms.md` has a picture of each shape.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from clearance.model import (
    GROUND,
    Body,
    Cylindrical,
    Marker,
    ModelError,
    Prismatic,
    Revolute,
    Spherical,
    Universal,
)
from clearance.model.bodies import InertiaVariation, triad_from_axis
from clearance.model.functions import Scaled, TimeFunction
from clearance.model.values import check_value

__all__ = [
    "JOINT_FREEDOMS",
    "LETTERS",
    "Leg",
    "LegPlan",
    "Link",
    "leg_shape",
    "horizontal_frame",
    "plan_leg",
    "rod_frame",
]

LETTERS = {"R": Revolute, "P": Prismatic, "C": Cylindrical, "U": Universal, "S": Spherical}
JOINT_FREEDOMS = {"R": 1, "P": 1, "C": 2, "U": 2, "S": 3}
SLIDING = "PC"
ENDS = "RUS"  # joints allowed at a link end that does not slide
LINK_ROLES = {
    "link": ("link",),
    "axial": ("lower", "upper"),
    "rail": ("slider", "rod"),
    "crank": ("crank", "rod"),
}
SHAPES_TEXT = (
    "2 joints (SS, US, CU, PS, ...), 3 joints with P or C in the middle (UPS, SPS, RPS, "
    "UPU, ...), with P or C at the base (PRS, PUS, PSS, ...) or with an R crank at the "
    "base (RSS, RUS, ...)"
)
E_Z = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class Link:
    """One body of a leg: mass [kg], inertia (3 principal moments about the mass centre in
    the link frame, link axis = body z) [kg m^2], com: distance of the mass centre along
    the link from its lower joint, or from its upper joint when the lower one slides [m];
    length [m]: required for a crank and for the rod of a carriage or crank leg (it fixes
    the home pose), else optional (it bounds `com`)."""

    mass: float
    inertia: tuple
    com: float = 0.0
    length: float | None = None

    def __post_init__(self) -> None:
        who = "Link"
        object.__setattr__(self, "mass", check_value(who, "mass", "positive", self.mass))
        object.__setattr__(self, "inertia", check_value(who, "inertia", "inertia3", self.inertia))
        object.__setattr__(self, "com", check_value(who, "com", "nonneg", self.com))
        if self.length is not None:
            L = check_value(who, "length", "positive", self.length)
            object.__setattr__(self, "length", L)
            if self.com > L:
                raise ModelError(who, "com", self.com, f"must lie on the link: <= length = {L} m")


def _vec(who: str, name: str, v: object) -> np.ndarray:
    return np.array(check_value(who, name, "vector3", v))


def _floats(a: np.ndarray) -> tuple[float, ...]:
    return tuple(float(x) for x in a)


def _unit(who: str, name: str, v: object) -> np.ndarray:
    a = _vec(who, name, v)
    n = float(np.linalg.norm(a))
    if n == 0.0:
        raise ModelError(who, name, v, "expected a non-zero direction")
    return a / n


def _drivable(jname: str, k: int) -> bool:
    """A P or C joint anywhere, an R joint at the base (a motor: RevoluteDriver)."""
    return jname[0] in SLIDING or (jname[0] == "R" and k == 0)


def leg_shape(joints: object, who: str = "Leg") -> str:
    """'link', 'axial', 'rail' or 'crank' for a joint string, or ModelError."""
    if not isinstance(joints, str) or not joints:
        raise ModelError(who, "joints", joints, "expected a string of joint letters R P C U S")
    bad = [c for c in joints if c not in LETTERS]
    if bad:
        raise ModelError(
            who, "joints", joints, f"unknown joint letter {bad[0]!r}; allowed: R, P, C, U, S"
        )
    n = len(joints)
    if n == 2 and joints[1] in ENDS:
        return "link"
    if n == 3 and joints[0] in ENDS and joints[1] in SLIDING and joints[2] in ENDS:
        return "axial"
    if n == 3 and joints[0] in SLIDING and joints[1] in ENDS and joints[2] in ENDS:
        return "rail"
    if n == 3 and joints[0] == "R" and joints[1] in ENDS and joints[2] in ENDS:
        return "crank"
    raise ModelError(who, "joints", joints, f"not a supported leg; supported: {SHAPES_TEXT}")


def joint_names(joints: str) -> list[str]:
    """Joint names of a leg string: the letter, numbered from the base where it repeats."""
    out, seen = [], {}
    for c in joints:
        seen[c] = seen.get(c, 0) + 1
        out.append(c if joints.count(c) == 1 else f"{c}{seen[c]}")
    return out


@dataclass(frozen=True)
class Leg:
    """One leg: joint string (base to platform), attachment points, links, options.

    joints: e.g. "UPS" (see the module docstring); "U_PS" marks the actuated joint as the
    literature's underline does (= actuated "P"). base: A, world [m]. platform: B,
    platform frame [m] (origin = platform mass centre, axes = world at home). links: one
    `Link` per body, base to platform (a parallelogram leg: crank and rod; both rods get
    the rod's link). actuated: the joint driven ("P", "R", ...: a P or C anywhere, or the R
    at the base), "auto" (the P of the leg; else a crank's R; else none) or None (passive).
    name: "" = numbered by the mechanism ("leg1", ...). axis: the reference axis t (world;
    default tangential at A). axes: per joint name, its axis (R, P, C: one vector) or axes
    (U: two vectors, first on the body nearer the base), world at home. rail: sliding axis
    of a base P or C (default: vertical; for a 2-joint leg the line A-B). knee: the home
    branch of a carriage ("down": the knee before the foot of B along the rail, "up") or of
    a crank ("out": the knee farther from the z axis, "in"). parallelogram: width [m] of the
    parallelogram of an RSS leg (two rods, spaced along t: the Delta robot's). lumped:
    X-P-Y leg as ONE body with the mass-moment method (physics.md i; Paper A's limbs).
    """

    joints: str
    base: tuple
    platform: tuple
    links: tuple
    actuated: str | None = "auto"
    name: str = ""
    axis: tuple | None = None
    axes: Mapping = field(default_factory=dict)
    rail: tuple | None = None
    knee: str | None = None
    parallelogram: float | None = None
    lumped: bool = False

    def __post_init__(self) -> None:
        who = f"Leg '{self.name}'" if self.name else f"Leg {self.joints!r}"
        self._underline(who)
        shape = leg_shape(self.joints, who)
        if not isinstance(self.name, str):
            raise ModelError(who, "name", self.name, "expected a string")
        if "." in self.name or " " in self.name:
            raise ModelError(who, "name", self.name, "a leg name has no '.' and no spaces")
        object.__setattr__(self, "base", tuple(_vec(who, "base", self.base)))
        object.__setattr__(self, "platform", tuple(_vec(who, "platform", self.platform)))
        links = self.links
        if isinstance(links, Link):
            links = (links,)
        if isinstance(links, (str, bytes)) or not isinstance(links, Sequence):
            raise ModelError(who, "links", links, "expected a list of Link")
        links = tuple(links)
        need = len(LINK_ROLES[shape])
        roles = ", ".join(LINK_ROLES[shape])
        if len(links) != need or not all(isinstance(x, Link) for x in links):
            raise ModelError(
                who, "links", links, f"a {self.joints} leg has {need} link(s): {roles}"
            )
        object.__setattr__(self, "links", links)
        if shape in ("rail", "crank"):
            for k, role in enumerate(LINK_ROLES[shape]):
                if links[k].length is None and (role == "rod" or shape == "crank"):
                    raise ModelError(
                        who,
                        f"links[{k}].length",
                        None,
                        f"the {role} of a {self.joints} leg "
                        "needs its length (it fixes the home pose)",
                    )
        if self.axis is not None:
            object.__setattr__(self, "axis", _floats(_unit(who, "axis", self.axis)))
        if self.rail is not None:
            object.__setattr__(self, "rail", _floats(_unit(who, "rail", self.rail)))
        names = joint_names(self.joints)
        if not isinstance(self.axes, Mapping):
            raise ModelError(who, "axes", self.axes, "expected a mapping joint name -> axis")
        axes = {}
        for jn, v in self.axes.items():
            if jn not in names:
                raise ModelError(who, f"axes.{jn}", v, f"unknown joint; joints: {names}")
            letter = jn[0]
            if letter == "S":
                raise ModelError(who, f"axes.{jn}", v, "a spherical joint has no axis")
            if letter == "U":
                try:
                    a1, a2 = v
                except (TypeError, ValueError):
                    raise ModelError(
                        who, f"axes.{jn}", v, "expected two axes of the universal joint"
                    ) from None
                a1, a2 = _unit(who, f"axes.{jn}[0]", a1), _unit(who, f"axes.{jn}[1]", a2)
                if abs(float(a1 @ a2)) > 1e-9:
                    raise ModelError(who, f"axes.{jn}", v, "the two axes must be orthogonal")
                axes[jn] = (_floats(a1), _floats(a2))
            else:
                axes[jn] = (_floats(_unit(who, f"axes.{jn}", v)),)
        object.__setattr__(self, "axes", axes)
        knees = {"rail": ("down", "up"), "crank": ("out", "in")}.get(shape, ())
        if self.knee is not None and self.knee not in knees:
            allowed = f"allowed: {', '.join(map(repr, knees))}" if knees else "only for carriage "
            raise ModelError(who, "knee", self.knee, allowed + ("" if knees else "and crank legs"))
        if self.parallelogram is not None:
            if self.joints != "RSS":
                raise ModelError(
                    who, "parallelogram", self.parallelogram, "only for RSS legs (the Delta's)"
                )
            w = check_value(who, "parallelogram", "positive", self.parallelogram)
            object.__setattr__(self, "parallelogram", w)
        if not isinstance(self.lumped, bool):
            raise ModelError(who, "lumped", self.lumped, "expected true or false")
        if self.lumped and self.joints != "SPS":
            raise ModelError(who, "lumped", True, "only for SPS legs (physics.md i)")
        object.__setattr__(self, "actuated", self._actuated(who, names, shape))

    def _underline(self, who: str) -> None:
        """The literature's underlined actuated joint, written '_' before its letter
        ("U_PS": the P; "_RSS": the R): the string without it, `actuated` set."""
        j = self.joints
        if not isinstance(j, str) or "_" not in j:
            return
        k = j.find("_")
        if j.count("_") != 1 or k == len(j) - 1 or j[k + 1] not in LETTERS:
            raise ModelError(
                who, "joints", j, "'_' marks the actuated joint once, before its letter: 'U_PS'"
            )
        plain = j.replace("_", "")
        marked = joint_names(plain)[k] if all(c in LETTERS for c in plain) else j[k + 1]
        if self.actuated not in ("auto", marked):
            raise ModelError(
                who, "actuated", self.actuated, f"the joint string marks '{marked}' actuated"
            )
        object.__setattr__(self, "joints", plain)
        object.__setattr__(self, "actuated", marked)

    def _actuated(self, who: str, names: list[str], shape: str) -> str | None:
        a = self.actuated
        if a is None or a == "none":
            return None
        if a == "auto":
            if self.joints.count("P") == 1:
                return names[self.joints.index("P")]
            return names[0] if shape == "crank" else None
        if a not in names:
            raise ModelError(who, "actuated", a, f"not a joint of the leg; joints: {names}")
        if _drivable(a, names.index(a)):
            return a
        raise ModelError(
            who,
            "actuated",
            a,
            "an actuator drives a P or C joint, or an R joint on the base; "
            f"candidates: {[n for i, n in enumerate(names) if _drivable(n, i)]}",
        )

    @property
    def shape(self) -> str:
        return leg_shape(self.joints)

    @property
    def joint_names(self) -> list[str]:
        """Joint names in the leg (without the leg prefix), base to platform."""
        names = joint_names(self.joints)
        if self.parallelogram is None:
            return names
        return [names[0], names[1] + "a", names[2] + "a", names[1] + "b", names[2] + "b"]


# --------------------------------------------------------------------------- geometry


def rod_frame(z: np.ndarray, hint: np.ndarray) -> np.ndarray:
    """Rotation body -> world: z, x = hint made normal to z (the 4UPS-UPU rod frame)."""
    x = hint - (hint @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def horizontal_frame(z: np.ndarray) -> np.ndarray:
    """Rotation body -> world: z, x = e_z x z normalised, e_x if z is vertical (the 4-SPS/CU
    limb frame)."""
    x = np.cross([0.0, 0.0, 1.0], z)
    if np.linalg.norm(x) < 1e-9:
        x = np.array([1.0, 0.0, 0.0])
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _cross_unit(a: np.ndarray, b: np.ndarray, who: str, what: str) -> np.ndarray:
    c = np.cross(a, b)
    n = np.linalg.norm(c)
    if n < 1e-9:
        raise ModelError(who, "axes", what, "the axis is parallel to the link: no U joint")
    return c / n


@dataclass
class LegPlan:
    """The model elements of one leg (bodies, markers, joints in order) and its actuator:
    driver name, joint name (None: a lumped limb, no driver row), kind ("prismatic",
    "revolute" or "lumped") and value at home."""

    elements: list
    actuator: tuple | None


class _Emit:
    """Marker/joint emission of one leg (names prefixed with the leg's)."""

    def __init__(self, leg: Leg, name: str) -> None:
        self.leg, self.p, self.out = leg, name, []
        self.who = f"leg '{name}' ({leg.joints})"
        t = np.array(leg.axis) if leg.axis is not None else None
        A = np.array(leg.base)
        if t is None:
            r = math.hypot(A[0], A[1])
            t = np.array([-A[1] / r, A[0] / r, 0.0]) if r > 1e-12 else np.array([1.0, 0.0, 0.0])
        self.t = t

    def axes(self, jname: str, default: tuple) -> tuple:
        given = self.leg.axes.get(jname)
        return tuple(np.array(a) for a in given) if given is not None else default

    def lower_axes(self, jname: str, z: np.ndarray) -> tuple:
        """Axes of a joint below a link of axis z (at the base, at the knee): R t; U t on
        the body below, z x t on the link (unless `Leg.axes` gives them)."""
        t = self.t
        return self.axes(
            jname, (t, _cross_unit(z, t, self.who, jname)) if jname[0] == "U" else (t,)
        )

    def upper_axes(self, jname: str, z: np.ndarray) -> tuple:
        """Axes of the platform joint above a link of axis z: R t; U z x t on the link, t
        on the platform (parallel to a U-P-U's base U)."""
        t = self.t
        return self.axes(
            jname, (_cross_unit(z, t, self.who, jname), t) if jname[0] == "U" else (t,)
        )

    def joint(self, jname: str, bi: str, pi, Ri, bj: str, pj, Rj, axes: tuple) -> None:
        """Markers i (on bi at body point pi, frame Ri) and j, then the joint. axes: world
        axes (R, P, C: (h,); U: (h_i, h_j))."""
        letter = jname[0]
        mi, mj = f"{self.p}.{jname}.i", f"{self.p}.{jname}.j"
        if letter == "S":
            self.out += [Marker(mi, bi, tuple(pi)), Marker(mj, bj, tuple(pj))]
        else:
            ai, aj = (axes[0], axes[0]) if letter != "U" else axes
            self.out += [
                Marker.on_axis(mi, bi, tuple(pi), axis=_body_axis(Ri, ai)),
                Marker.on_axis(mj, bj, tuple(pj), axis=_body_axis(Rj, aj)),
            ]
        self.out.append(LETTERS[letter](f"{self.p}.{jname}", mi, mj))


def _body_axis(R: np.ndarray | None, a: np.ndarray) -> tuple:
    """World axis a in body components (R None: the ground or the platform at home)."""
    return tuple(a) if R is None else tuple(R.T @ a)


def _body(name: str, link: Link, position, R, **kw) -> Body:
    return Body(name, link.mass, link.inertia, position=tuple(position), orientation=R, **kw)


def plan_leg(
    leg: Leg, name: str, home: np.ndarray, drive: TimeFunction | None, *, lumped: bool
) -> LegPlan:
    """The elements of leg `name` with the platform centre at `home` (world, platform
    parallel to the base). drive: the actuator's function where the geometry needs it
    (a lumped limb's length); lumped: build a lumped leg as one body (else two)."""
    em = _Emit(leg, name)
    A = np.array(leg.base)
    B = np.array(leg.platform)
    Bw = home + B
    shape = leg.shape
    names = joint_names(leg.joints)
    build = {"axial": _axial, "rail": _rail, "crank": _crank, "link": _link}[shape]
    actuator_value = build(em, leg, names, A, B, Bw, drive, lumped and leg.lumped)
    act = None
    if leg.actuated is not None and not (lumped and leg.lumped):
        kind = "revolute" if leg.actuated[0] == "R" else "prismatic"
        act = (f"{name}.drive", f"{name}.{leg.actuated}", kind, actuator_value)
    elif leg.actuated is not None:  # lumped: the length is in the geometry, no driver row
        act = (f"{name}.drive", None, "lumped", actuator_value)
    return LegPlan(em.out, act)


def _axial(em: _Emit, leg: Leg, names, A, B, Bw, drive, lumped: bool) -> float:
    """X-P-Y / X-C-Y: the sliding joint on the line A-B; the value is the length |A B|."""
    p, t = em.p, em.t
    x, m, y = names
    u = (Bw - A) / np.linalg.norm(Bw - A)  # leg axis, A -> B
    length = float(np.linalg.norm(Bw - A))
    if leg.joints[0] in "RU":
        if abs(float(t @ u)) > 1 - 1e-9:
            raise ModelError(em.who, "axis", tuple(t), "the reference axis is along the leg")
        R = rod_frame(u, t)
    else:
        R = horizontal_frame(u)
    lo, up = leg.links
    a_x, a_y = em.lower_axes(x, u), em.upper_axes(y, u)
    if lumped:  # physics.md i: one body, the S points slide with the length l(t)
        m1, m2, a1, a2 = lo.mass, up.mass, lo.com, up.com
        mt = m1 + m2
        l0 = drive(0.0)
        c0 = (m1 * a1 + m2 * (l0 - a2)) / mt
        off = (m1 * a1 - m2 * a2) / mt  # c(l) = (m2/m) l + off: sb_A = -c(l), sb_B = l - c(l)
        var = InertiaVariation((m1 * m2 / mt, m1 * m2 / mt, 0.0), a1 + a2, drive)
        J = tuple(np.array(lo.inertia) + np.array(up.inertia))
        limb = f"{p}.limb"
        em.out.append(
            Body(limb, mt, J, position=tuple(A + c0 * u), orientation=R, inertia_variation=var)
        )
        zax = (0.0, 0.0, 1.0)
        mk_a = Marker(f"{p}.{x}.j", limb, slide_axis=zax, slide=Scaled(drive, -m2 / mt, -off))
        mk_b = Marker(f"{p}.{y}.j", limb, slide_axis=zax, slide=Scaled(drive, m1 / mt, -off))
        _sliding_s(em, x, GROUND, A, mk_a)
        _sliding_s(em, y, "platform", B, mk_b)
        return length
    lower, upper = f"{p}.lower", f"{p}.upper"
    em.out += [
        _body(lower, lo, A + lo.com * u, R),
        _body(upper, up, Bw - up.com * u, R),
    ]
    pa, pb = (0.0, 0.0, -lo.com), (0.0, 0.0, up.com)
    em.joint(x, GROUND, A, None, lower, pa, R, a_x)
    # the sliding joint along the rod axis (body z): identical triads on both links, so the
    # rotation lock f_i . g_j = 0 of a P holds at home (physics.md c.3)
    mi, mj = f"{p}.{m}.i", f"{p}.{m}.j"
    em.out += [
        Marker(mi, lower, pa),
        Marker(mj, upper, pb),
        LETTERS[leg.joints[1]](f"{p}.{m}", mi, mj),
    ]
    _top(em, y, upper, pb, R, B, a_y)
    return length


def _sliding_s(em: _Emit, jname: str, bi: str, pi, mk_j: Marker) -> None:
    """A spherical joint whose marker j slides on a lumped limb (physics.md i)."""
    mi = f"{em.p}.{jname}.i"
    em.out += [Marker(mi, bi, tuple(pi)), mk_j, Spherical(f"{em.p}.{jname}", mi, mk_j.name)]


def _top(em: _Emit, y: str, link: str, p_link, R_link, B, axes) -> None:
    """The platform joint: S with marker i on the platform (socket), else i on the link."""
    if y[0] == "S":
        em.joint(y, "platform", B, None, link, p_link, R_link, axes)
    else:
        em.joint(y, link, p_link, R_link, "platform", B, None, axes)


def _rail(em: _Emit, leg: Leg, names, A, B, Bw, drive, lumped: bool) -> float:
    """P-X-Y / C-X-Y: a carriage on a rail through A, a rod of fixed length to B."""
    p, t = em.p, em.t
    d0, x, y = names
    d = np.array(leg.rail) if leg.rail is not None else E_Z
    d = em.axes(d0, (d,))[0]
    sl, rod = leg.links
    L = rod.length
    w = Bw - A
    along = float(d @ w)
    perp2 = max(float(w @ w) - along * along, 0.0)
    if L * L < perp2:
        raise ModelError(
            em.who,
            "links[1].length",
            L,
            f"the rod cannot reach B from the rail: B is {math.sqrt(perp2):.6g} m from the "
            "rail line",
        )
    root = math.sqrt(L * L - perp2)
    s0 = along - root if (leg.knee or "down") == "down" else along + root
    C = A + s0 * d
    r = (Bw - C) / np.linalg.norm(Bw - C)
    Rs, Rr = horizontal_frame(d), horizontal_frame(r)
    if abs(float(t @ r)) > 1 - 1e-9 and x[0] in "RU":
        raise ModelError(em.who, "axis", tuple(t), "the reference axis is along the rod")
    slider, rb = f"{p}.slider", f"{p}.rod"
    em.out += [_body(slider, sl, C - sl.com * d, Rs), _body(rb, rod, C + rod.com * r, Rr)]
    # the carriage's marker at its point that lies at A at home: the value is the travel
    em.joint(d0, GROUND, A, None, slider, (0.0, 0.0, sl.com - s0), Rs, (d,))
    em.joint(x, slider, (0.0, 0.0, sl.com), Rs, rb, (0.0, 0.0, -rod.com), Rr, em.lower_axes(x, r))
    _top(em, y, rb, (0.0, 0.0, L - rod.com), Rr, B, em.upper_axes(y, r))
    return 0.0


def _crank(em: _Emit, leg: Leg, names, A, B, Bw, drive, lumped: bool) -> float:
    """R-X-Y: a crank about t through A, a rod (or a parallelogram of two) to B."""
    p = em.p
    r0, x, y = names
    t = em.t = em.axes(r0, (em.t,))[0]  # (the R's axis: the leg's reference from here)
    e1 = np.cross(t, E_Z)
    if np.linalg.norm(e1) < 1e-9:  # vertical crank axis: angle from e_x
        e1 = np.array([1.0, 0.0, 0.0]) - t[0] * t
    e1 = e1 / np.linalg.norm(e1)
    e2 = np.cross(t, e1)
    cr, rod = leg.links
    a, b = cr.length, rod.length
    w = Bw - A
    K = (a * a + float(w @ w) - b * b) / (2.0 * a)
    c1, c2 = float(e1 @ w), float(e2 @ w)
    rho = math.hypot(c1, c2)
    if rho == 0.0 or abs(K) > rho:
        raise ModelError(
            em.who,
            "links",
            (a, b),
            f"crank {a:g} m and rod {b:g} m cannot reach B ({float(np.linalg.norm(w)):.6g} m "
            "from A, out of the crank's plane as it is)",
        )
    phi0, dphi = math.atan2(c2, c1), math.acos(K / rho)
    cands = [phi0 + dphi, phi0 - dphi]
    out = [math.cos(ph) for ph in cands]  # radial (e1) component of the crank
    k = int(np.argmax(out)) if (leg.knee or "out") == "out" else int(np.argmin(out))
    phi = math.atan2(math.sin(cands[k]), math.cos(cands[k]))
    cdir = math.cos(phi) * e1 + math.sin(phi) * e2
    C = A + a * cdir
    Rc = rod_frame(cdir, t)
    crank = f"{p}.crank"
    em.out.append(_body(crank, cr, A + cr.com * cdir, Rc))
    mi, mj = f"{p}.{r0}.i", f"{p}.{r0}.j"
    em.out += [
        Marker(mi, GROUND, tuple(A), triad_from_axis(t, e1)),
        Marker(mj, crank, (0.0, 0.0, -cr.com), triad_from_axis(Rc.T @ t, Rc.T @ cdir)),
        Revolute(f"{p}.{r0}", mi, mj),
    ]
    w_half = 0.0 if leg.parallelogram is None else 0.5 * leg.parallelogram
    sides = [("", 0.0)] if leg.parallelogram is None else [("a", w_half), ("b", -w_half)]
    for tag, off in sides:
        Ck, Bk, Bp = C + off * t, Bw + off * t, B + off * t
        r = (Bk - Ck) / np.linalg.norm(Bk - Ck)
        Rr = rod_frame(r, t)
        rb = f"{p}.rod{'_' + tag if tag else ''}"
        em.out.append(_body(rb, rod, Ck + rod.com * r, Rr))
        em.joint(
            x + tag,
            crank,
            (0.0, 0.0, a - cr.com) + Rc.T @ (off * t),
            Rc,
            rb,
            (0.0, 0.0, -rod.com),
            Rr,
            em.lower_axes(x, r),
        )
        _top(em, y + tag, rb, (0.0, 0.0, b - rod.com), Rr, Bp, em.upper_axes(y, r))
    return phi


def _link(em: _Emit, leg: Leg, names, A, B, Bw, drive, lumped: bool) -> float:
    """X-Y: one link from A to B; a sliding X lets it slide along the rail through A."""
    p, t = em.p, em.t
    x, y = names
    (lk,) = leg.links
    link = f"{p}.link"
    if leg.joints[0] in SLIDING:
        d = np.array(leg.rail) if leg.rail is not None else (Bw - A) / np.linalg.norm(Bw - A)
        d = em.axes(x, (d,))[0]
        R = horizontal_frame(d)
        em.out.append(_body(link, lk, Bw - lk.com * d, R))
        w = Bw - A
        if float(np.linalg.norm(np.cross(w, d))) <= 1e-12 * float(np.linalg.norm(w)):
            pa = (0.0, 0.0, -(float(np.linalg.norm(w)) - lk.com))  # A on the axis
        else:
            pa = tuple(R.T @ (A - (Bw - lk.com * d)))
        em.joint(x, GROUND, A, None, link, pa, R, (d,))
        z = d
    else:
        z = (Bw - A) / np.linalg.norm(Bw - A)
        R = rod_frame(z, t) if leg.joints[0] in "RU" else horizontal_frame(z)
        em.out.append(_body(link, lk, A + lk.com * z, R))
        em.joint(x, GROUND, A, None, link, (0.0, 0.0, -lk.com), R, em.lower_axes(x, z))
    top = (
        (0.0, 0.0, lk.com)
        if leg.joints[0] in SLIDING
        else (0.0, 0.0, float(np.linalg.norm(Bw - A)) - lk.com)
    )
    _top(em, y, link, top, R, B, em.upper_axes(y, z))
    return 0.0
