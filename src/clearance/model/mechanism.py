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
from clearance.model.drivers import (
    DistanceDriver,
    OffsetDriver,
    OrientationDriver,
    PositionDriver,
    PrismaticDriver,
)
from clearance.model.errors import ModelError
from clearance.model.forces import PointForce, SpringDamper, Torque
from clearance.model.joints import Cylindrical, Joint, Prismatic

_DRIVERS = (PrismaticDriver, DistanceDriver, PositionDriver, OrientationDriver, OffsetDriver)
_FORCES = (PointForce, Torque, SpringDamper)


@dataclass
class Mechanism:
    """A multibody system under construction.

    name: label used in results.  gravity: (3,) world gravity vector [m/s^2].
    """

    name: str = "mechanism"
    gravity: tuple = (0.0, 0.0, -9.81)
    bodies: dict = field(default_factory=dict)
    markers: dict = field(default_factory=dict)
    joints: dict = field(default_factory=dict)
    drivers: dict = field(default_factory=dict)
    forces: dict = field(default_factory=dict)

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
        PrismaticClearance on a Prismatic joint (`clearance.model.clearance`)."""
        from dataclasses import replace

        jt = self.joints.get(joint)
        if not hasattr(jt, "clearance"):
            able = [n for n, j in self.joints.items() if hasattr(j, "clearance")]
            raise ModelError(
                f"Mechanism '{self.name}'",
                "with_clearance",
                joint,
                "expected the name of a spherical, revolute, cylindrical or prismatic joint; "
                f"joints that can have clearance: {able}",
            )
        return self.replace(**{joint: replace(jt, clearance=clearance)})

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
