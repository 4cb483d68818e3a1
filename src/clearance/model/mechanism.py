"""The `Mechanism` builder: bodies, markers, joints, drivers, forces, gravity.

Elements are added with `add` (any number, any kind). Each addition is validated against
what is already there (duplicate names, references to unknown elements), so an error names
the element and field where it arises. `validate()` re-checks the whole description.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from clearance.model.bodies import GROUND, Body, Marker
from clearance.model.clearance import UniversalClearance, pair_joint_name
from clearance.model.drivers import (
    DistanceDriver,
    OffsetDriver,
    OrientationDriver,
    PositionDriver,
    PrismaticDriver,
    RevoluteDriver,
)
from clearance.model.errors import ModelError
from clearance.model.forces import PointForce, SpringDamper, Torque
from clearance.model.joints import Cylindrical, Joint, Prismatic, Revolute, Universal

_DRIVERS = (
    PrismaticDriver,
    DistanceDriver,
    PositionDriver,
    OrientationDriver,
    OffsetDriver,
    RevoluteDriver,
)
_FORCES = (PointForce, Torque, SpringDamper)


@dataclass
class Mechanism:
    """A multibody system under construction.

    name: label used in results.  gravity: (3,) world gravity vector [m/s^2].
    wear: joint name -> `clearance.model.wear.SocketWear`, the worn sockets of spherical
    clearance joints (`with_wear`; empty: unworn).
    """

    name: str = "mechanism"
    gravity: tuple = (0.0, 0.0, -9.81)
    bodies: dict = field(default_factory=dict)
    markers: dict = field(default_factory=dict)
    joints: dict = field(default_factory=dict)
    drivers: dict = field(default_factory=dict)
    forces: dict = field(default_factory=dict)
    wear: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        g = np.asarray(self.gravity, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise ModelError(
                f"Mechanism '{self.name}'",
                "gravity",
                self.gravity,
                "expected 3 finite numbers [m/s^2]",
            )
        self.gravity = tuple(float(x) for x in g)

    # ------------------------------------------------------------------ building
    def add(self, *elements: object) -> Mechanism:
        """Add bodies, markers, joints, drivers or forces (validated one by one)."""
        for e in elements:
            if isinstance(e, Iterable) and not isinstance(e, (str, bytes)):
                self.add(*e)
                continue
            self._add_one(e)
        return self

    def _all_names(self) -> dict[str, str]:
        out = {}
        for kind, d in (
            ("body", self.bodies),
            ("marker", self.markers),
            ("joint", self.joints),
            ("driver", self.drivers),
            ("force", self.forces),
        ):
            for n in d:
                out[n] = kind
        return out

    def _check_new_name(self, who: str, name: str) -> None:
        names = self._all_names()
        if name in names or name == GROUND:
            raise ModelError(
                who,
                "name",
                name,
                f"the name is already used by a {names.get(name, 'ground')}; "
                "names must be unique across the mechanism",
            )

    def _need_marker(self, who: str, fieldname: str, name: str) -> Marker:
        if name not in self.markers:
            raise ModelError(
                who, fieldname, name, f"unknown marker; known markers: {sorted(self.markers)}"
            )
        return self.markers[name]

    def _add_one(self, e: object) -> None:
        who = f"{type(e).__name__} '{getattr(e, 'name', '?')}'"
        if isinstance(e, Body):
            self._check_new_name(who, e.name)
            self.bodies[e.name] = e
        elif isinstance(e, Marker):
            self._check_new_name(who, e.name)
            if e.body != GROUND and e.body not in self.bodies:
                raise ModelError(
                    who, "body", e.body, f"unknown body; known bodies: {[GROUND, *self.bodies]}"
                )
            self.markers[e.name] = e
        elif isinstance(e, Joint):
            self._check_new_name(who, e.name)
            mi = self._need_marker(who, "marker_i", e.marker_i)
            mj = self._need_marker(who, "marker_j", e.marker_j)
            if mi.body == mj.body:
                raise ModelError(
                    who,
                    "marker_j",
                    e.marker_j,
                    f"both markers are on body '{mi.body}'; a joint connects two different bodies",
                )
            self.joints[e.name] = e
        elif isinstance(e, _DRIVERS):
            self._check_new_name(who, e.name)
            self._check_driver(who, e)
            self.drivers[e.name] = e
        elif isinstance(e, _FORCES):
            self._check_new_name(who, e.name)
            if isinstance(e, SpringDamper):
                self._need_marker(who, "marker_i", e.marker_i)
                self._need_marker(who, "marker_j", e.marker_j)
            else:
                m = self._need_marker(who, "marker", e.marker)
                if m.body == GROUND:
                    raise ModelError(
                        who,
                        "marker",
                        e.marker,
                        "a force on the ground has no effect; use a moving body",
                    )
            self.forces[e.name] = e
        else:
            raise ModelError(
                "Mechanism.add", "element", e, "expected a Body, Marker, joint, driver or force"
            )

    def _check_driver(self, who: str, d: object) -> None:
        if isinstance(d, PrismaticDriver):
            if d.joint not in self.joints:
                raise ModelError(
                    who, "joint", d.joint, f"unknown joint; known joints: {sorted(self.joints)}"
                )
            if not isinstance(self.joints[d.joint], (Prismatic, Cylindrical)):
                raise ModelError(
                    who,
                    "joint",
                    d.joint,
                    f"is a {type(self.joints[d.joint]).__name__}; a prismatic "
                    "driver needs a Prismatic or Cylindrical joint",
                )
        elif isinstance(d, RevoluteDriver):
            if d.joint not in self.joints:
                raise ModelError(
                    who, "joint", d.joint, f"unknown joint; known joints: {sorted(self.joints)}"
                )
            jt = self.joints[d.joint]
            if not isinstance(jt, (Revolute, Cylindrical)):
                raise ModelError(
                    who,
                    "joint",
                    d.joint,
                    f"is a {type(jt).__name__}; a revolute driver needs a Revolute or "
                    "Cylindrical joint",
                )
            if self.markers[jt.marker_i].body != GROUND:
                raise ModelError(
                    who,
                    "joint",
                    d.joint,
                    f"its marker i '{jt.marker_i}' is on body "
                    f"'{self.markers[jt.marker_i].body}'; a revolute driver needs marker i on "
                    "the ground (a base-mounted motor)",
                )
        elif isinstance(d, (DistanceDriver, OffsetDriver)):
            mi = self._need_marker(who, "marker_i", d.marker_i)
            mj = self._need_marker(who, "marker_j", d.marker_j)
            if mi.body == mj.body:
                raise ModelError(who, "marker_j", d.marker_j, "both markers are on the same body")
        else:
            m = self._need_marker(who, "marker", d.marker)
            if m.body == GROUND:
                raise ModelError(
                    who, "marker", d.marker, "a pose driver acts on a moving body, not the ground"
                )

    # ------------------------------------------------------------------ queries
    def validate(self) -> Mechanism:
        """Re-validate the whole description; raise ModelError naming the first problem."""
        if not self.bodies:
            raise ModelError(
                f"Mechanism '{self.name}'",
                "bodies",
                [],
                "a mechanism needs at least one moving body",
            )
        fresh = Mechanism(self.name, self.gravity)
        for d in (self.bodies, self.markers, self.joints, self.drivers, self.forces):
            for e in d.values():
                fresh._add_one(e)
        return self

    @property
    def nbody(self) -> int:
        return len(self.bodies)

    def body_index(self, name: str) -> int:
        """Index of a moving body (0-based), -1 for the ground."""
        if name == GROUND:
            return -1
        return list(self.bodies).index(name)

    def copy(self) -> Mechanism:
        """A shallow copy (elements are immutable; the containers are new)."""
        return Mechanism(
            self.name,
            self.gravity,
            dict(self.bodies),
            dict(self.markers),
            dict(self.joints),
            dict(self.drivers),
            dict(self.forces),
            dict(self.wear),
        )

    def replace(self, **changes: object) -> Mechanism:
        """A copy with some elements replaced by name (the original is not mutated)."""
        m = self.copy()
        for name, e in changes.items():
            for d in (m.bodies, m.markers, m.joints, m.drivers, m.forces):
                if name in d:
                    d[name] = e
                    break
            else:
                raise ModelError(f"Mechanism '{self.name}'", "replace", name, "unknown element")
        return m.validate()

    def with_clearance(self, joint: str, clearance: object) -> Mechanism:
        """A copy in which joint `joint` has `clearance` (None: ideal again): a Clearance on a
        Spherical joint, a RevoluteClearance on a Revolute or Cylindrical joint, a
        PrismaticClearance on a Prismatic joint, a UniversalClearance on a Universal joint
        (which then becomes its cross, a body, and two revolute joints, one of them with the
        clearance: `clearance.model.clearance.UniversalClearance`)."""
        from dataclasses import replace

        jt = self.joints.get(joint)
        if isinstance(jt, Universal) and clearance is not None:
            if not isinstance(clearance, UniversalClearance):
                raise ModelError(
                    f"Universal '{joint}'",
                    "clearance",
                    clearance,
                    "expected UniversalClearance(pair='i' or 'j', cross_mass=..., "
                    "cross_inertia=..., journal_radius=..., ...): a clearance in one of its "
                    "revolute pairs",
                )
            return self._with_cross(jt, clearance)
        if not hasattr(jt, "clearance"):
            able = [n for n, j in self.joints.items() if hasattr(j, "clearance")]
            able += [n for n, j in self.joints.items() if isinstance(j, Universal)]
            raise ModelError(
                f"Mechanism '{self.name}'",
                "with_clearance",
                joint,
                "expected the name of a spherical, universal, revolute, cylindrical or "
                f"prismatic joint; joints that can have clearance: {able}",
            )
        return self.replace(**{joint: replace(jt, clearance=clearance)})

    def with_wear(self, joint: str, wear: object) -> Mechanism:
        """A copy in which the socket of spherical clearance joint `joint` is worn as `wear`
        (a `clearance.model.wear.SocketWear`), or the bearing of a revolute or cylindrical
        one (a `BearingWear` with one row per station); None: unworn again."""
        from clearance.model.clearance import Clearance, RevoluteClearance
        from clearance.model.wear import BearingWear, SocketWear

        def able():
            return [
                n
                for n, j in self.joints.items()
                if isinstance(getattr(j, "clearance", None), (Clearance, RevoluteClearance))
            ]

        jt = self.joints.get(joint)
        cl = getattr(jt, "clearance", None)
        if not isinstance(cl, (Clearance, RevoluteClearance)):
            raise ModelError(
                f"Mechanism '{self.name}'",
                "with_wear",
                joint,
                "expected a spherical, revolute or cylindrical clearance joint; these have "
                f"one: {able()}",
            )
        want = SocketWear if isinstance(cl, Clearance) else BearingWear
        if wear is not None and not isinstance(wear, want):
            raise ModelError(
                f"Mechanism '{self.name}'",
                f"wear.{joint}",
                wear,
                f"expected a {want.__name__} or None ({joint} is a {cl.kind.name.lower()} "
                "clearance joint)",
            )
        if isinstance(wear, BearingWear):
            n = 1 if cl.model == "planar" else cl.stations
            if wear.stations != n:
                raise ModelError(
                    f"Mechanism '{self.name}'",
                    f"wear.{joint}.depths",
                    f"{wear.stations} stations",
                    f"expected one row per station of the joint ({n})",
                )
        m = self.copy()
        if wear is None:
            m.wear.pop(joint, None)
        else:
            m.wear[joint] = wear
        return m

    def _marker_world(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """(point, triad) of marker `name` in the world at the description's pose (t = 0)."""
        mk = self.markers[name]
        s = np.array(mk.position, dtype=float)
        if mk.slide is not None:
            s = s + np.array(mk.slide_axis) * float(mk.slide(0.0))
        if mk.body == GROUND:
            return s, mk.triad
        b = self.bodies[mk.body]
        A = b.rotation
        return np.array(b.position) + A @ s, A @ mk.triad

    def _point_velocity(self, marker: str, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(velocity of the point P moving with marker's body, its angular velocity), world,
        at the description's state."""
        body = self.markers[marker].body
        if body == GROUND:
            return np.zeros(3), np.zeros(3)
        b = self.bodies[body]
        w = b.rotation @ np.array(b.angular_velocity)
        return np.array(b.velocity) + np.cross(w, P - np.array(b.position)), w

    def _with_cross(self, jt: Universal, cl: UniversalClearance) -> Mechanism:
        """Replace universal joint `jt` by its cross (a body) and two revolute joints, the
        one of pair `cl.pair` with the clearance (UniversalClearance)."""
        who = f"Universal '{jt.name}'"
        P, Ti = self._marker_world(jt.marker_i)
        _, Tj = self._marker_world(jt.marker_j)
        a = Ti[:, 2]
        b = Tj[:, 2] - (Tj[:, 2] @ a) * a
        if np.linalg.norm(b) < 1e-6:
            raise ModelError(who, "marker_j", jt.marker_j, "h_j is parallel to h_i at the start")
        b = b / np.linalg.norm(b)
        R = np.column_stack((a, b, np.cross(a, b)))  # cross frame: h_i, h_j, h_i x h_j
        cross = f"{jt.name}.cross"
        vel, w_c = self._point_velocity(jt.marker_i, P)
        w_j = self._point_velocity(jt.marker_j, P)[1]
        # the cross turns with yoke i plus a rate about h_i; yoke j with the cross plus a
        # rate about h_j: w_j - w_i = u a + s b (least squares; exact for a consistent state
        # of the universal joint). Mass and inertia were checked by UniversalClearance.
        (u, _), *_ = np.linalg.lstsq(np.column_stack((a, b)), w_j - w_c, rcond=None)
        w_c = w_c + u * a
        body = Body(cross, cl.cross_mass, cl.cross_inertia, tuple(P), R, tuple(vel), R.T @ w_c)
        # cross markers: h along the pair's axis (cross x = h_i, y = h_j)
        mi = Marker(f"{jt.name}.cross_i", cross, orientation=np.eye(3)[:, [1, 2, 0]])
        mj = Marker(f"{jt.name}.cross_j", cross, orientation=np.eye(3)[:, [2, 0, 1]])
        rev = cl.revolute()
        pairs = [
            Revolute(
                pair_joint_name(jt.name, pair),
                yoke,
                trunnion.name,
                clearance=rev if pair == cl.pair else None,
            )
            for pair, yoke, trunnion in (("i", jt.marker_i, mi), ("j", jt.marker_j, mj))
        ]
        m = self.copy()
        m.joints = {}
        for name, other in self.joints.items():  # the new joints where the old one was
            if name == jt.name:
                m.joints.update({p.name: p for p in pairs})
            else:
                m.joints[name] = other
        for e in (body, mi, mj):
            m._check_new_name(who, e.name)
        m.bodies[cross] = body
        m.markers[mi.name] = mi
        m.markers[mj.name] = mj
        return m.validate()

    def without(self, *names: str) -> Mechanism:
        """A copy without the named joints, drivers or forces."""
        m = self.copy()
        for name in names:
            for d in (m.joints, m.drivers, m.forces):
                if name in d:
                    del d[name]
                    break
            else:
                raise ModelError(
                    f"Mechanism '{self.name}'",
                    "without",
                    name,
                    "not a joint, driver or force of this mechanism",
                )
        return m.validate()
