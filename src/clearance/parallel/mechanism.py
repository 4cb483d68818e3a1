"""Parallel mechanisms from leg types: a fixed base, a moving platform and legs.

    import clearance as cl
    up = cl.Link(1.5, (0.021, 0.021, 0.0005), com=0.2, length=0.4)
    lo = cl.Link(2.0, (0.028, 0.028, 0.001), com=0.2, length=0.4)
    stewart = cl.ParallelMechanism(
        "6-UPS",
        cl.Platform(10.0, (0.15625, 0.15625, 0.3125), position=(0, 0, 0.7)),
        cl.legs("UPS", base=cl.circle(0.4, [0, 60, ...]), platform=cl.circle(0.2, [...]),
                links=(lo, up)),
    )
    mech = stewart.build()              # the ideal Mechanism, drives at their home values
    stewart.mobility()                  # Grubler-Kutzbach against the rank check
    stewart.actuators                   # ("leg1.drive", ..., "leg6.drive")

Legs are described in `clearance.mechanisms.legs` (shapes, axes, frames, names). The
platform is the body "platform" with its mass centre at `Platform.position` at home and
its axes parallel to the world's there; its marker "platform.centre" (at the mass centre,
platform axes) is the one a platform trajectory prescribes (`clearance.analysis.ik`).

The mobility check (`ParallelMechanism.mobility`, run by `build`): the Grubler-Kutzbach
count 6 n - sum(6 - f) assumes independent joint constraints; the rank of the constraint
Jacobian at home says how many are. The two must agree (else the constraints are
dependent at home: an over-constrained design or a singular home pose, refused naming the
joints involved), and the platform's DOF (the mechanism's DOF less the idle ones, such as
the spin of a rod between two spherical joints) must equal the number of actuators (and
`dof` when given).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from clearance.model import (
    GROUND,
    Body,
    Fixed,
    Marker,
    Mechanism,
    ModelError,
    PrismaticDriver,
    RevoluteDriver,
    TimeFunction,
)
from clearance.model.functions import as_function
from clearance.model.values import check_value
from clearance.parallel.legs import JOINT_FREEDOMS, Leg, LegPlan, Link, plan_leg

__all__ = [
    "Attachments",
    "Leg",
    "Link",
    "Mobility",
    "ParallelMechanism",
    "Platform",
    "circle",
    "legs",
]

PLATFORM = "platform"
PLATFORM_MARKER = "platform.centre"


@dataclass(frozen=True)
class Attachments:
    """Attachment points (world for the base, platform frame for the platform) [m]; when
    made by `circle`, the angles [deg] they came from (the legs' tangents are exact)."""

    points: tuple
    angles_deg: tuple | None = None

    def __len__(self) -> int:
        return len(self.points)

    def tangent(self, k: int) -> tuple | None:
        """(-sin theta, cos theta, 0) of point k on a circle, else None."""
        if self.angles_deg is None:
            return None
        th = math.radians(self.angles_deg[k])
        return (-math.sin(th), math.cos(th), 0.0)


def circle(radius: float, angles_deg: Sequence[float], z: float = 0.0) -> Attachments:
    """Points radius (cos theta, sin theta, 0) + (0, 0, z) for theta in angles_deg [deg]."""
    who = "circle"
    r = check_value(who, "radius", "positive", radius)
    zz = check_value(who, "z", "real", z)
    if isinstance(angles_deg, (str, bytes)) or not isinstance(angles_deg, Sequence):
        raise ModelError(who, "angles_deg", angles_deg, "expected a list of angles [deg]")
    angs = tuple(check_value(who, f"angles_deg[{k}]", "real", a) for k, a in enumerate(angles_deg))
    if not angs:
        raise ModelError(who, "angles_deg", angles_deg, "expected at least one angle")
    pts = tuple(
        (r * math.cos(a), r * math.sin(a), zz) for a in np.radians(np.array(angs, dtype=float))
    )
    return Attachments(pts, angs)


def _attachments(who: str, name: str, v: object) -> Attachments:
    if isinstance(v, Attachments):
        return v
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or not len(v):
        raise ModelError(who, name, v, "expected circle(...) or a list of points [x, y, z]")
    return Attachments(tuple(tuple(check_value(who, name, "vector3", p)) for p in v))


def legs(
    joints: str,
    *,
    base: Attachments | Sequence,
    platform: Attachments | Sequence,
    links: Sequence[Link],
    name: str = "",
    **options: object,
) -> tuple[Leg, ...]:
    """One `Leg` per attachment pair (base[k], platform[k]), all alike (options: those of
    `Leg`). name: "" = numbered by the mechanism; a name for a single leg (e.g. "centre");
    for several, legs "<name>1", "<name>2", ... A base on a circle gives each leg its
    tangent as reference axis (unless `axis` is given)."""
    who = f"legs {joints!r}"
    a = _attachments(who, "base", base)
    b = _attachments(who, "platform", platform)
    if len(a) != len(b):
        raise ModelError(
            who, "platform", len(b), f"expected as many platform points as base points ({len(a)})"
        )
    out = []
    for k in range(len(a)):
        nm = name if (not name or len(a) == 1) else f"{name}{k + 1}"
        opts = dict(options)
        if opts.get("axis") is None and a.tangent(k) is not None:
            opts["axis"] = a.tangent(k)
        out.append(Leg(joints, a.points[k], b.points[k], tuple(links), name=nm, **opts))
    return tuple(out)


@dataclass(frozen=True)
class Platform:
    """The moving platform: mass [kg], inertia (principal moments about the mass centre,
    platform axes) [kg m^2], position: its mass centre at home, world [m]. At home the
    platform axes are the world's."""

    mass: float
    inertia: tuple
    position: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        who = "Platform"
        object.__setattr__(self, "mass", check_value(who, "mass", "positive", self.mass))
        object.__setattr__(self, "inertia", check_value(who, "inertia", "inertia3", self.inertia))
        object.__setattr__(self, "position", check_value(who, "position", "vector3", self.position))


@dataclass(frozen=True)
class Mobility:
    """Mobility of a parallel mechanism at home (no drivers).

    grubler: 6 n - sum(6 - f) (Grubler-Kutzbach, independent constraints assumed);
    rank_dof: 6 n - rank of the constraint Jacobian; idle: DOF left with the platform held
    (rod spins); platform: rank_dof - idle; actuators: number of actuators; dependent:
    joints whose constraints are dependent (rank_dof > grubler). driven_dof: DOF left with
    the actuators' drivers (= idle unless the home pose is an actuation singularity);
    driven_dependent: the joints and drivers of that singularity.
    """

    grubler: int
    rank_dof: int
    idle: int
    platform: int
    actuators: int
    dependent: tuple = ()
    driven_dof: int = 0
    driven_dependent: tuple = ()

    def text(self) -> str:
        return (
            f"mobility: Grubler-Kutzbach {self.grubler}, rank check {self.rank_dof} "
            f"({self.idle} idle), platform {self.platform} DOF, {self.actuators} actuators"
        )


@dataclass(frozen=True)
class ParallelMechanism:
    """A parallel mechanism: platform, legs (see `clearance.mechanisms.legs`), gravity.

    Legs without a name are numbered "leg1", "leg2", ... in order. dof: the platform's
    expected DOF (checked by `mobility`; None = the number of actuators).
    """

    name: str
    platform: Platform
    legs: tuple
    gravity: tuple = (0.0, 0.0, -9.81)
    dof: int | None = None
    _names: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        who = f"ParallelMechanism '{self.name}'"
        if not isinstance(self.name, str) or not self.name:
            raise ModelError("ParallelMechanism", "name", self.name, "expected a non-empty string")
        if not isinstance(self.platform, Platform):
            raise ModelError(who, "platform", self.platform, "expected a Platform")
        lg = self.legs
        if isinstance(lg, Leg):
            lg = (lg,)
        if isinstance(lg, (str, bytes)) or not isinstance(lg, Sequence):
            raise ModelError(who, "legs", lg, "expected a list of Leg")
        flat: list[Leg] = []
        for x in lg:  # (legs(...) returns tuples: accept them nested)
            flat.extend(x if isinstance(x, tuple) else [x])
        if not flat or not all(isinstance(x, Leg) for x in flat):
            raise ModelError(who, "legs", lg, "expected at least one Leg")
        object.__setattr__(self, "legs", tuple(flat))
        object.__setattr__(self, "gravity", check_value(who, "gravity", "vector3", self.gravity))
        if self.dof is not None and (
            isinstance(self.dof, bool) or not isinstance(self.dof, int) or not 1 <= self.dof <= 6
        ):
            raise ModelError(who, "dof", self.dof, "expected an integer 1..6 or None")
        names, k = [], 0
        for leg in flat:
            if leg.name:
                names.append(leg.name)
            else:
                k += 1
                names.append(f"leg{k}")
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ModelError(who, "legs", dup, "leg names must be unique")
        if PLATFORM in names:
            raise ModelError(who, "legs", PLATFORM, "'platform' is the platform's name")
        object.__setattr__(self, "_names", tuple(names))

    # ------------------------------------------------------------------ names
    def _named(self) -> list[tuple[str, Leg]]:
        return list(zip(self._names, self.legs, strict=True))

    @property
    def leg_names(self) -> tuple[str, ...]:
        return self._names

    def leg(self, name: str) -> Leg:
        if name not in self._names:
            raise ModelError(self.name, "leg", name, f"unknown leg; legs: {list(self._names)}")
        return self.legs[self._names.index(name)]

    @property
    def actuators(self) -> tuple[str, ...]:
        """Driver names of the actuated legs, in leg order ("<leg>.drive")."""
        return tuple(f"{n}.drive" for n, lg in self._named() if lg.actuated)

    @property
    def actuator_joints(self) -> tuple[str, ...]:
        return tuple(f"{n}.{lg.actuated}" for n, lg in self._named() if lg.actuated)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Every joint "<leg>.<joint>" (two-body legs), leg by leg, base to platform."""
        return tuple(f"{n}.{j}" for n, lg in self._named() for j in lg.joint_names)

    @property
    def lumped(self) -> bool:
        """True if a leg is a mass-moment lumped limb (no driver row: IK on `build(lumped=
        False)`, actuator force by `lumped_actuator_force`)."""
        return any(lg.lumped for lg in self.legs)

    platform_body = PLATFORM
    platform_marker = PLATFORM_MARKER

    # ------------------------------------------------------------------ building
    def _plans(self, drives: Mapping[str, TimeFunction], lumped: bool) -> list[LegPlan]:
        home = np.array(self.platform.position)
        return [
            plan_leg(lg, n, home, drives.get(f"{n}.drive"), lumped=lumped)
            for n, lg in self._named()
        ]

    def home_drives(self) -> dict[str, float]:
        """Actuator values at home: leg lengths [m], travels [m] (0), crank angles [rad]."""
        # (the two-body geometry: its values do not depend on the drives)
        return {p.actuator[0]: p.actuator[3] for p in self._plans({}, False) if p.actuator}

    def _drives(self, drives: Mapping | Sequence | None) -> dict[str, TimeFunction]:
        who = f"ParallelMechanism '{self.name}'"
        acts = self.actuators
        if drives is None:
            return {k: as_function(v) for k, v in self.home_drives().items()}
        if not isinstance(drives, Mapping):
            if isinstance(drives, (str, bytes)) or len(drives) != len(acts):
                raise ModelError(who, "drives", drives, f"expected one drive per {list(acts)}")
            drives = dict(zip(acts, drives, strict=True))
        unknown = [k for k in drives if k not in acts]
        missing = [a for a in acts if a not in drives]
        if unknown or missing:
            raise ModelError(
                who,
                "drives",
                sorted(map(str, drives)),
                f"expected one drive per actuator {list(acts)} (unknown {unknown}, "
                f"missing {missing})",
            )
        return {k: as_function(v, owner=who, field=f"drives[{k!r}]") for k, v in drives.items()}

    def build(
        self,
        drives: Mapping[str, TimeFunction | float] | Sequence | None = None,
        *,
        lumped: bool = True,
        check: bool = True,
        name: str | None = None,
    ) -> Mechanism:
        """The ideal `Mechanism` (validated, uncompiled).

        drives: actuator name -> time function or number (values as `home_drives`), or a
        sequence in the order of `actuators`; None = the home values (the mechanism rests
        at home). lumped: False builds lumped limbs as two bodies with a driver (the
        inverse kinematics' model). check: run `check_mobility` (on the two-body model).
        """
        fns = self._drives(drives)
        mech = self._assemble(fns, lumped, name)
        if check:
            self.check_mobility(mech if not (lumped and self.lumped) else None)
        return mech

    def _assemble(self, fns: dict, lumped: bool, name: str | None) -> Mechanism:
        p = self.platform
        mech = Mechanism(name or self.name, gravity=self.gravity)
        mech.add(Body(PLATFORM, p.mass, p.inertia, position=p.position))
        mech.add(Marker(PLATFORM_MARKER, PLATFORM))
        drivers = []
        for plan in self._plans(fns, lumped):
            mech.add(*plan.elements)
            if plan.actuator is not None and plan.actuator[1] is not None:
                dname, jname, kind, _ = plan.actuator
                cls = RevoluteDriver if kind == "revolute" else PrismaticDriver
                drivers.append(cls(dname, jname, fns[dname]))
        mech.add(*drivers)
        return mech.validate()

    def ik_mechanism(self, drives: Mapping | Sequence | None = None) -> Mechanism:
        """The model of the inverse kinematics: lumped limbs as two bodies with drivers."""
        return self.build(drives, lumped=False, check=False, name=f"{self.name} (IK)")

    # ------------------------------------------------------------------ mobility
    def mobility(self, mech: Mechanism | None = None) -> Mobility:
        """Grubler-Kutzbach and the rank check at home (see the module docstring). The
        ranks come from the NumPy constraint rows (`clearance.dynamics.reference`), so a
        scenario file is checked without compiled kernels."""
        m = mech if mech is not None else self._assemble(self._drives(None), False, None)
        free = m.without(*m.drivers)
        n = len(free.bodies)
        grubler = 6 * n - sum(6 - _freedoms(j) for j in free.joints.values())
        dof, dependent = _rank(free)
        held = free.copy().add(
            Marker("__home", GROUND, self.platform.position),
            Fixed("__hold", "__home", PLATFORM_MARKER),
        )
        idle, _ = _rank(held)
        driven, driven_dep = _rank(m)
        return Mobility(
            grubler=grubler,
            rank_dof=dof,
            idle=idle,
            platform=dof - idle,
            actuators=len(self.actuators),
            dependent=dependent,
            driven_dof=driven,
            driven_dependent=driven_dep,
        )

    def check_mobility(self, mech: Mechanism | None = None) -> Mobility:
        """`mobility`, raising ModelError when the constraints are dependent at home, when
        the actuators do not determine the platform, or when `dof` is not met."""
        mob = self.mobility(mech)
        who = f"ParallelMechanism '{self.name}'"
        if mob.rank_dof != mob.grubler:
            raise ModelError(
                who,
                "legs",
                ", ".join(mob.dependent) or "(no joint named)",
                f"Grubler-Kutzbach gives {mob.grubler} DOF but the rank check finds "
                f"{mob.rank_dof} at home: these joints' constraints are dependent there (an "
                "over-constrained design or a singular home pose; check their axes)",
            )
        want = self.dof if self.dof is not None else mob.actuators
        if mob.platform != want:
            what = f"dof = {self.dof}" if self.dof is not None else f"{mob.actuators} actuators"
            raise ModelError(
                who,
                "legs",
                ", ".join(self.actuators) or "(no actuator)",
                f"the platform has {mob.platform} DOF at home (Grubler-Kutzbach {mob.grubler}, "
                f"{mob.idle} idle) but the mechanism declares {what}",
            )
        if mob.actuators and mob.driven_dof > mob.idle:
            raise ModelError(
                who,
                "legs",
                ", ".join(mob.driven_dependent) or "(none named)",
                f"the actuators do not determine the platform at home: {mob.driven_dof - mob.idle} "
                "DOF stay free with the drives held (an actuation singularity: e.g. rod lines "
                "that all meet one line or lie on one hyperboloid, as in a symmetric layout; "
                "turn the platform attachment angles against the base ones)",
            )
        if self.dof is not None and mob.actuators != self.dof:
            raise ModelError(
                who,
                "legs",
                ", ".join(self.actuators) or "(no actuator)",
                f"{mob.actuators} actuators for a platform of {self.dof} DOF: "
                "each platform DOF needs one actuator",
            )
        return mob

    def with_leg(self, name: str, **changes: object) -> ParallelMechanism:
        """A copy with leg `name` changed (fields of `Leg`)."""
        self.leg(name)  # (ModelError for an unknown name)
        k = self._names.index(name)
        new = list(self.legs)
        new[k] = replace(new[k], **changes)
        return replace(self, legs=tuple(new))


def _rank(mech: Mechanism, rtol: float = 1e-9) -> tuple[int, tuple[str, ...]]:
    """(DOF = 6 nb - rank of phi_q, names of the joints and drivers whose rows are
    dependent) at the bodies' initial poses, from the NumPy constraint rows."""
    from clearance.dynamics.reference import constraint_rows

    nb = len(mech.bodies)
    y = np.zeros(13 * nb)
    for k, b in enumerate(mech.bodies.values()):
        y[7 * k : 7 * k + 3] = b.position
        y[7 * k + 3 : 7 * k + 7] = b.orientation
    J = constraint_rows(mech, 0.0, y)[1]
    if J.shape[0] == 0:
        return 6 * nb, ()
    U, sv, _ = np.linalg.svd(J)
    rank = int(np.sum(sv > rtol * max(1.0, sv[0])))
    if rank == J.shape[0]:
        return 6 * nb - rank, ()
    weight = np.sqrt(np.sum(U[:, rank:] ** 2, axis=1))
    owners = [
        name for name, e in (*mech.joints.items(), *mech.drivers.items()) for _ in range(e.nrows)
    ]
    dep = tuple(dict.fromkeys(owners[r] for r in np.nonzero(weight > 1e-6)[0]))
    return 6 * nb - rank, dep


def _freedoms(joint: object) -> int:
    """Relative freedoms f of an ideal joint (Grubler-Kutzbach)."""
    letter = {
        "Revolute": "R",
        "Prismatic": "P",
        "Cylindrical": "C",
        "Universal": "U",
        "Spherical": "S",
    }.get(type(joint).__name__)
    return JOINT_FREEDOMS[letter] if letter else 0  # (Fixed: 0)
