"""Clearance joints: a joint whose ideal constraint is replaced by contact forces.

One argument turns a joint into a clearance joint, for every kind of the family:

    Spherical("S1", "platform_B1", "leg1_B", clearance=Clearance(ball_radius=0.015,
              radial_clearance=0.3e-3, normal=Flores(restitution=0.9), friction=LuGre()))
    Revolute("R1", "crank_pin", "rod_end", clearance=RevoluteClearance(journal_radius=0.0095,
             radial_clearance=0.5e-3, model="planar"))
    Cylindrical("C1", ..., clearance=RevoluteClearance(..., model="spatial", length=0.03))
    Prismatic("P1", "guide", "slider", clearance=PrismaticClearance(width=0.05, length=0.1,
              clearance=1e-3, normal=LankaraniNikravesh(stiffness=1e10)))
    mech = mech.with_clearance("S1", Clearance(...))     # or on an existing mechanism

Geometry kinds (kinds.ClearanceKind), each with its contact kernel in `clearance.contact`:

* `Clearance` (alias `SphericalClearance`): ball in socket, one point contact (physics.md
  f). The joint's 3 rows are removed.
* `RevoluteClearance`: journal in bearing, on a Revolute or a Cylindrical joint.
  model="planar": the classic planar model (Flores & Ambrosio 2004): one contact in the
  bearing's mid-plane; the rows that keep the journal aligned with the bearing (and, for a
  revolute joint, axially in place) stay ideal, only the 2 radial rows are removed.
  model="spatial": the journal may also tilt (and slide axially): `stations` bearing
  cross-sections along its length carry the line contact (edge loading of a tilted journal
  follows); a revolute joint keeps its axial row ideal unless `axial_clearance` is given,
  in which case the journal's collars meet the bearing's end faces at `thrust_points`
  points each (thrust contact). See `clearance.contact.journal` for the geometry.
* `PrismaticClearance`: slider in guide (Flores et al. 2008), corners against walls.
  model="planar": motion in the plane of the guide marker's f and h axes (g normal to it;
  the rows that keep it there stay ideal), 4 corners against the two f walls;
  model="spatial": the 8 corners of the slider box against all four walls.

The contact laws are those of `clearance.model.contact_laws`; `socket` / `bearing` / `guide`
say which marker's body holds the outer part ("i", default, or "j").
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import ClassVar

import numpy as np

from clearance.kinds import ClearanceKind, JointType
from clearance.model.bodies import Body
from clearance.model.contact_laws import (
    FRICTION_LAWS,
    NORMAL_LAWS,
    STEEL,
    Flores,
    FrictionContactLaw,
    LankaraniNikravesh,
    Material,
    NoFriction,
    NonlinearStiffness,
    NormalContactLaw,
    _LineLaw,
)
from clearance.model.errors import ModelError

MODELS = ("planar", "spatial")


def _pos(who: str, field: str, v: object, *, allow_zero: bool = False) -> float:
    try:
        x = float(v)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        raise ModelError(who, field, v, "expected a positive number") from None
    if not np.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        raise ModelError(who, field, v, "expected a finite number > 0")
    return x


def _count(who: str, field: str, v: object, lo: int) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < lo:
        raise ModelError(who, field, v, f"expected an integer >= {lo}")
    return int(v)


def _set(obj: object, name: str, value: object) -> None:
    object.__setattr__(obj, name, value)


#: the smallest radial clearance, relative to the inner radius (a sub-nanometre gap on a
#: centimetre ball; the conformal Hertz radius R_b R_s / c stays finite)
MIN_RELATIVE_CLEARANCE = 1e-9


def _up3(x: float) -> str:
    """x rounded up to 3 significant digits, as text (a bound printed that way holds)."""
    scale = 10.0 ** (np.floor(np.log10(x)) - 2)
    return f"{np.ceil(x / scale) * scale:.3g}"


def _radii(obj: object, who: str, inner: str, outer: str) -> None:
    """Exactly one of the outer radius and radial_clearance; both stored, `given` says which
    the user gave (files write that one back)."""
    ri = _pos(who, inner, getattr(obj, inner))
    ro_given, c_given = getattr(obj, outer), obj.radial_clearance  # type: ignore[attr-defined]
    if ro_given is not None and c_given is not None:
        # both: accepted when they agree (a copy made with dataclasses.replace carries both)
        ro, c = _pos(who, outer, ro_given), _pos(who, "radial_clearance", c_given)
        if not abs(ro - ri - c) <= 1e-9 * c:
            raise ModelError(
                who,
                outer,
                ro_given,
                f"give exactly one of {outer} and radial_clearance (or both agreeing: "
                f"{outer} - {inner} = {ro - ri!r} != radial_clearance = {c!r})",
            )
        # `given` cannot survive the copy (an init=False field is reset to its default
        # before __post_init__): the clearance, kept exactly, is recorded as given
        ro_given = None
    if (ro_given is None) == (c_given is None):
        raise ModelError(who, outer, ro_given, f"give exactly one of {outer} and radial_clearance")
    if ro_given is not None:
        ro = _pos(who, outer, ro_given)
        if ro <= ri:
            raise ModelError(who, outer, ro_given, f"must exceed {inner} = {ri} (clearance > 0)")
        c = ro - ri
    else:
        c = _pos(who, "radial_clearance", c_given)  # kept exactly as given
        ro = ri + c
    if not (c if c_given is not None else ro - ri) >= MIN_RELATIVE_CLEARANCE * ri:
        field = outer if c_given is None else "radial_clearance"
        raise ModelError(
            who,
            field,
            ro_given if c_given is None else c_given,
            f"expected a radial clearance of at least {_up3(MIN_RELATIVE_CLEARANCE * ri)} m "
            f"({MIN_RELATIVE_CLEARANCE:g} of {inner} = {ri} m: below it the two radii are "
            "the same number; for no clearance, remove the clearance)",
        )
    if c >= ri:  # a gap as large as the radius: a ball loose in a hollow, not a joint
        field = outer if c_given is None else "radial_clearance"
        raise ModelError(
            who,
            field,
            ro_given if c_given is None else c_given,
            f"expected a radial clearance below {inner} = {ri} m (c = {c} m)",
        )
    _set(obj, "given", outer if c_given is None else "radial_clearance")
    _set(obj, inner, ri)
    _set(obj, outer, ro)
    _set(obj, "radial_clearance", c)


def _side(who: str, name: str, v: object) -> None:
    if v not in ("i", "j"):
        raise ModelError(who, name, v, "allowed: 'i' or 'j' (the marker whose body holds it)")


def _laws(obj: object, who: str, normals: tuple[str, ...] = ("normal",)) -> None:
    for name in normals:
        law = getattr(obj, name)
        if name != "normal" and law is None:
            continue
        if not isinstance(law, NormalContactLaw):
            raise ModelError(
                who,
                name,
                law,
                f"expected a normal contact law, one of {sorted(NORMAL_LAWS)} "
                "(e.g. Flores(restitution=0.9))",
            )
    if not isinstance(obj.friction, FrictionContactLaw):  # type: ignore[attr-defined]
        raise ModelError(
            who,
            "friction",
            obj.friction,  # type: ignore[attr-defined]
            f"expected a friction law, one of {sorted(FRICTION_LAWS)} (e.g. LuGre())",
        )


# the effective moduli E* a given Hertz stiffness may stand for (PROPOSED): from softer than
# any solid (gels are ~1e4 Pa) to 2000 times diamond on diamond (E* ~ 5e11 Pa)
E_STAR_RANGE = (1e3, 1e15)  # [Pa]


def _hertz_stiffness_in_range(obj: object, who: str) -> None:
    """A stiffness given to a power law with Hertz's exponent 1.5 for a ball in a socket
    stands for an effective modulus E* = 3 K / (4 sqrt(R*)), R* = R_b R_s / c (physics.md
    g.1, conformal contact): refuse one no material has (K = 1 N/m^1.5, a typo for 1e10,
    let the ball sink 26 mm into its socket; K = 1e30 made 2.3e10 N look plausible)."""
    law = obj.normal  # type: ignore[attr-defined]
    k = getattr(law, "stiffness", None)
    if k is None or getattr(law, "exponent", None) != 1.5:
        return
    rb, rs, c = obj.ball_radius, obj.socket_radius, obj.radial_clearance  # type: ignore[attr-defined]
    sq = float(np.sqrt(rb * rs / c))
    lo, hi = (4.0 / 3.0 * e * sq for e in E_STAR_RANGE)
    if lo <= k <= hi:
        return
    raise ModelError(
        who,
        "normal.stiffness",
        k,
        f"a Hertz stiffness for this ball and socket (conformal radius R* = {sq * sq:.3g} m) "
        f"means an effective modulus E* = 3 K / (4 sqrt(R*)) = {0.75 * k / sq:.3g} Pa, which "
        f"no material has: expected K between {lo:.3g} and {hi:.3g} N/m^1.5 (E* from "
        f"{E_STAR_RANGE[0]:g} to {E_STAR_RANGE[1]:g} Pa), or 'auto' for the materials' Hertz "
        "stiffness",
    )


def _common(obj: object, who: str, materials: tuple[str, str]) -> None:
    for name in materials:
        if not isinstance(getattr(obj, name), Material):
            raise ModelError(who, name, getattr(obj, name), "expected a Material(E, nu)")
    _set(obj, "velocity_floor", _pos(who, "velocity_floor", obj.velocity_floor))  # type: ignore[attr-defined]
    tol = _pos(who, "onset_tolerance", obj.onset_tolerance)  # type: ignore[attr-defined]
    if tol >= 0.5:
        raise ModelError(who, "onset_tolerance", tol, "expected a fraction < 0.5 of c")
    _set(obj, "onset_tolerance", tol)


def _no_line_law(obj: object, who: str, where: str) -> None:
    if isinstance(obj.normal, _LineLaw):  # type: ignore[attr-defined]
        raise ModelError(
            who,
            "normal",
            obj.normal,  # type: ignore[attr-defined]
            f"{type(obj.normal).__name__} is a line-contact law of a journal in its bearing; "  # type: ignore[attr-defined]
            f"use a point-contact law for {where}",
        )


def _model(obj: object, who: str) -> None:
    if obj.model not in MODELS:  # type: ignore[attr-defined]
        raise ModelError(who, "model", obj.model, f"allowed: {', '.join(MODELS)}")  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Clearance:
    """Spherical clearance joint (ball in socket, physics.md f).

    ball_radius R_b [m]; give either socket_radius R_s [m] or radial_clearance c = R_s - R_b
    [m] (> 0) (both are accepted when they agree, as in a copy by dataclasses.replace).
    socket: "i" or "j", the marker whose body holds the socket (default "i").
    normal: normal contact law; friction: friction law (see clearance.model.contact_laws).
    ball_material / socket_material: used when a law's stiffness is computed from materials.
    velocity_floor: floor of the impact velocity delta_dot_minus captured at onset [m/s]
    (physics.md f.5, PROPOSED 1e-4). onset_tolerance: the contact onset is localised so that
    the penetration at the recorded onset is below onset_tolerance * c, and (always) to a
    time within the integrator's rtol times the step of the crossing.
    """

    ball_radius: float
    socket_radius: float | None = None
    radial_clearance: float | None = None
    socket: str = "i"
    normal: object = Flores()
    friction: object = NoFriction()
    ball_material: Material = STEEL
    socket_material: Material = STEEL
    velocity_floor: float = 1e-4
    onset_tolerance: float = 1e-3
    # which of socket_radius / radial_clearance the user gave (files write that one back)
    given: str = field(default="radial_clearance", init=False, repr=False, compare=False)

    kind: ClassVar[ClearanceKind] = ClearanceKind.SPHERICAL
    joints: ClassVar[tuple[JointType, ...]] = (JointType.SPHERICAL,)

    def __post_init__(self) -> None:
        who = "Clearance"
        _radii(self, who, "ball_radius", "socket_radius")
        _side(who, "socket", self.socket)
        _laws(self, who)
        _no_line_law(self, who, "a ball in a socket")
        _common(self, who, ("ball_material", "socket_material"))
        _hertz_stiffness_in_range(self, who)

    @property
    def c(self) -> float:
        """Radial clearance R_s - R_b [m]."""
        return float(self.radial_clearance)  # type: ignore[arg-type]

    @property
    def outer(self) -> str:
        """The marker ("i" or "j") whose body holds the socket."""
        return self.socket

    def kept_rows(self, joint: JointType) -> int:
        """Constraint rows of the joint that stay ideal (none: the ball moves freely)."""
        return 0


SphericalClearance = Clearance


@dataclass(frozen=True)
class RevoluteClearance:
    """Journal in bearing: a Revolute or Cylindrical joint with radial clearance.

    journal_radius R_J [m]; bearing_radius R_B [m] or radial_clearance c = R_B - R_J (> 0).
    model: "planar" (one contact in the bearing mid-plane; alignment and, for a revolute
    joint, the axial position stay ideal) or "spatial" (the journal tilts; `stations` >= 2
    bearing cross-sections over `length`, the bearing (contact) length [m], carry the line
    contact). axial_clearance c_a [m] (spatial revolute only): gap between each journal
    collar and the bearing's end face; None keeps the axial position ideal. thrust_radius
    [m] (default 1.25 R_B) and thrust_points (per face) place the thrust contact points.
    bearing: the marker ("i" or "j") whose body holds the bearing.
    normal: law of the radial contact, for the whole bearing length (a station takes its
    share of it); thrust_normal: law of the thrust faces (None: `normal`), for a whole face.
    Stiffness from the materials: the internal Hertz K of the radii (Flores & Ambrosio
    2004). Default normal law: Lankarani-Nikravesh, c_r = 0.9 (the revolute literature's).
    """

    journal_radius: float
    bearing_radius: float | None = None
    radial_clearance: float | None = None
    model: str = "planar"
    length: float | None = None
    stations: int = 5
    axial_clearance: float | None = None
    thrust_radius: float | None = None
    thrust_points: int = 4
    bearing: str = "i"
    normal: object = LankaraniNikravesh()
    thrust_normal: object = None
    friction: object = NoFriction()
    journal_material: Material = STEEL
    bearing_material: Material = STEEL
    velocity_floor: float = 1e-4
    onset_tolerance: float = 1e-3
    given: str = field(default="radial_clearance", init=False, repr=False, compare=False)

    kind: ClassVar[ClearanceKind] = ClearanceKind.REVOLUTE
    joints: ClassVar[tuple[JointType, ...]] = (JointType.REVOLUTE, JointType.CYLINDRICAL)

    def __post_init__(self) -> None:
        who = "RevoluteClearance"
        _radii(self, who, "journal_radius", "bearing_radius")
        _model(self, who)
        _side(who, "bearing", self.bearing)
        _laws(self, who, ("normal", "thrust_normal"))
        _common(self, who, ("journal_material", "bearing_material"))
        for law_field in ("normal", "thrust_normal"):
            if isinstance(getattr(self, law_field), NonlinearStiffness):
                raise ModelError(
                    who,
                    law_field,
                    getattr(self, law_field),
                    "NonlinearStiffness is the conformal ball-in-socket law; use a point or "
                    "line contact law for a journal",
                )
        if self.length is None and isinstance(self.normal, _LineLaw):
            raise ModelError(
                who, "length", None, f"the line-contact law {type(self.normal).__name__} needs it"
            )
        if isinstance(self.thrust_normal, _LineLaw):
            raise ModelError(
                who, "thrust_normal", self.thrust_normal, "a thrust face is not a line contact"
            )
        if self.axial_clearance is not None and self.thrust_normal is None:
            if isinstance(self.normal, _LineLaw):
                raise ModelError(
                    who,
                    "thrust_normal",
                    None,
                    "give the thrust faces a point-contact law (the radial law is a line law)",
                )
        if self.model == "spatial":
            if self.length is None:
                raise ModelError(who, "length", None, "the spatial model needs the bearing length")
            _set(self, "stations", _count(who, "stations", self.stations, 2))
        else:
            for name, default in (("axial_clearance", None), ("thrust_normal", None)):
                if getattr(self, name) is not default:
                    raise ModelError(
                        who,
                        name,
                        getattr(self, name),
                        "only for model='spatial' (planar keeps the journal axially in place)",
                    )
            _set(self, "stations", _count(who, "stations", self.stations, 1))
        if self.length is not None:
            _set(self, "length", _pos(who, "length", self.length))
        if self.axial_clearance is not None:
            _set(self, "axial_clearance", _pos(who, "axial_clearance", self.axial_clearance))
            _set(self, "thrust_points", _count(who, "thrust_points", self.thrust_points, 3))
        rt = 1.25 * float(self.bearing_radius) if self.thrust_radius is None else self.thrust_radius  # type: ignore[arg-type]
        _set(self, "thrust_radius", _pos(who, "thrust_radius", rt))

    @property
    def c(self) -> float:
        """Radial clearance R_B - R_J [m]."""
        return float(self.radial_clearance)  # type: ignore[arg-type]

    @property
    def outer(self) -> str:
        return self.bearing

    def kept_rows(self, joint: JointType) -> int:
        """Rows of the joint that stay ideal: planar 2 alignment rows (+ the axial row of a
        revolute joint); spatial the axial row of a revolute joint without axial clearance."""
        axial = joint == JointType.REVOLUTE and self.axial_clearance is None
        return (2 if self.model == "planar" else 0) + (1 if axial else 0)


@dataclass(frozen=True)
class PrismaticClearance:
    """Slider in guide: a Prismatic joint with clearance (Flores et al. 2008).

    The slider is a box with its centre at its marker's point: width (along the marker's f
    axis), height (along g; spatial model), length (along h, the sliding axis) [m]; the
    guide's walls leave `clearance` [m] on each side in f and `clearance_height` (default
    `clearance`) in g. model: "planar" (motion in the guide marker's f-h plane, kept there by
    ideal rows; 4 corners against the f walls) or "spatial" (8 corners, 4 walls).
    guide: the marker ("i" or "j") whose body holds the guide. normal: law of one
    corner-wall contact; its stiffness must be given, or corner_radius [m], the radius of
    the rounded corners, gives the Hertz stiffness of a sphere on a flat (materials).
    """

    width: float
    length: float
    clearance: float
    height: float | None = None
    clearance_height: float | None = None
    model: str = "planar"
    corner_radius: float | None = None
    guide: str = "i"
    normal: object = LankaraniNikravesh()
    friction: object = NoFriction()
    slider_material: Material = STEEL
    guide_material: Material = STEEL
    velocity_floor: float = 1e-4
    onset_tolerance: float = 1e-3

    kind: ClassVar[ClearanceKind] = ClearanceKind.PRISMATIC
    joints: ClassVar[tuple[JointType, ...]] = (JointType.PRISMATIC,)

    def __post_init__(self) -> None:
        who = "PrismaticClearance"
        for name in ("width", "length", "clearance"):
            _set(self, name, _pos(who, name, getattr(self, name)))
        _model(self, who)
        if self.model == "spatial":
            if self.height is None:
                raise ModelError(who, "height", None, "the spatial model needs the slider height")
            _set(self, "height", _pos(who, "height", self.height))
            ch = self.clearance if self.clearance_height is None else self.clearance_height
            _set(self, "clearance_height", _pos(who, "clearance_height", ch))
        if self.corner_radius is not None:
            _set(self, "corner_radius", _pos(who, "corner_radius", self.corner_radius))
        _side(who, "guide", self.guide)
        _laws(self, who)
        _no_line_law(self, who, "slider corners")
        if isinstance(self.normal, NonlinearStiffness):
            raise ModelError(
                who, "normal", self.normal, "NonlinearStiffness is the ball-in-socket law"
            )
        if getattr(self.normal, "stiffness", 0.0) is None and self.corner_radius is None:
            raise ModelError(
                who,
                "normal",
                self.normal,
                "a slider corner has no radius for a Hertz stiffness: give the law's "
                "stiffness, or corner_radius",
            )
        _common(self, who, ("slider_material", "guide_material"))

    @property
    def c(self) -> float:
        """Clearance per side in the width direction [m]."""
        return self.clearance

    @property
    def outer(self) -> str:
        return self.guide

    def kept_rows(self, joint: JointType) -> int:
        """Planar: 3 rows keep the slider in the guide's f-h plane; spatial: none."""
        return 3 if self.model == "planar" else 0


def pair_joint_name(universal: str, pair: str) -> str:
    """Name of the revolute joint of pair "i" or "j" of an expanded universal joint
    (`UniversalClearance`): "<universal>.<pair>"."""
    return f"{universal}.{pair}"


@dataclass(frozen=True)
class UniversalClearance(RevoluteClearance):
    """A journal-in-bearing clearance in one revolute pair of a Universal joint.

    A universal joint is a cross between two yokes: a revolute pair about h_i (yoke on body
    i) and one about h_j (yoke on body j). A clearance in one pair needs the cross as a body
    of its own, so `Mechanism.with_clearance(name, UniversalClearance(...))` replaces the
    joint by: body "<name>.cross" (`cross_mass` [kg], `cross_inertia` [kg m^2]: 3 principal
    moments about the cross axes h_i, h_j, h_i x h_j, or a 3x3 tensor in those axes), an ideal
    Revolute "<name>.<other pair>" and a Revolute "<name>.<pair>" with this clearance (all the
    RevoluteClearance fields; the bearing is on the yoke, marker i of the new revolutes, the
    journals are the cross's trunnions). pair: "i" (the pair about h_i) or "j". The cross
    is placed from the mechanism's description state (the bodies' position, orientation and
    velocities): at the joint point, its axes along h_i and h_j (h_j orthogonalised), moving
    with yoke i plus the rate about h_i that yoke j's motion needs (exact for a consistent
    state; the run's initial assembly corrects the rest). To start a clearance run from a
    given state, describe the bodies at that state before adding the clearance.
    """

    pair: str | None = None
    cross_mass: float | None = None
    cross_inertia: object = None

    joints: ClassVar[tuple[JointType, ...]] = (JointType.UNIVERSAL,)

    def __post_init__(self) -> None:
        super().__post_init__()
        who = "UniversalClearance"
        if self.pair not in ("i", "j"):
            raise ModelError(
                who,
                "pair",
                self.pair,
                "allowed: 'i' (the revolute pair about h_i, yoke on body i) or 'j' (about h_j)",
            )
        if self.cross_mass is None:
            raise ModelError(who, "cross_mass", None, "the cross is a body: give its mass [kg]")
        _set(self, "cross_mass", _pos(who, "cross_mass", self.cross_mass))
        if self.cross_inertia is None:
            raise ModelError(
                who,
                "cross_inertia",
                None,
                "the cross becomes a body: give its inertia [kg m^2] (3 principal moments "
                "about h_i, h_j, h_i x h_j, or a 3x3 tensor)",
            )
        try:  # the body's own checks of the inertia
            Body("cross", self.cross_mass, self.cross_inertia)
        except ModelError as e:
            raise ModelError(who, "cross_inertia", self.cross_inertia, e.allowed) from None
        J = np.asarray(self.cross_inertia, dtype=float)
        _set(self, "cross_inertia", tuple(J.tolist()) if J.ndim == 1 else tuple(map(tuple, J)))

    def revolute(self) -> RevoluteClearance:
        """The clearance of the pair's revolute joint (the RevoluteClearance fields)."""
        names = [f.name for f in fields(RevoluteClearance) if f.init]
        kw = {n: getattr(self, n) for n in names}
        if self.given == "bearing_radius":
            kw["radial_clearance"] = None
        else:
            kw["bearing_radius"] = None
        return RevoluteClearance(**kw)


CLEARANCE_TYPES = (Clearance, RevoluteClearance, PrismaticClearance)
