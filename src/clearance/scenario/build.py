"""From a validated scenario to mechanisms: `build_mechanisms(s) -> (ideal, clearance, info)`.

Dispatch is by mechanism type through `BUILDERS` ({MechanismType: builder}); a builder
makes the ideal mechanism with the factory of its type and the clearance mechanism with
`Mechanism.with_clearance` for every joint of [clearance.joints]. The 4-SPS/CU builder is
added to `BUILDERS` together with its factory; until then its scenarios validate
(`clearance check`) but do not build.

The actuator drives are not computed here: `info` carries the platform trajectory
(`info.pose_functions()`, `info.platform_trajectory()`), the platform marker and the
actuator driver names that the general inverse kinematics (physics.md e.2,
`clearance.analysis.ik`) needs; pass its drives back through `drives=`. Without them the
actuators hold the home lengths (the platform rests at home).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from clearance.mechanisms.ups_upu import home_leg_lengths, ups_upu_ideal
from clearance.model.clearance import UniversalClearance, pair_joint_name
from clearance.model.errors import ModelError
from clearance.model.functions import Constant, Sinusoid, TimeFunction
from clearance.model.mechanism import Mechanism
from clearance.scenario.errors import ScenarioError
from clearance.scenario.schema import (
    InitialPlacement,
    MechanismType,
    Scenario,
    TrajectoryShape,
    TrajectorySpec,
)
from clearance.scenario.trajectories import pose_function

__all__ = ["BUILDERS", "BuildInfo", "build_mechanisms", "shape_function", "with_clearances"]

Drives = Sequence[TimeFunction | float] | Mapping[str, TimeFunction | float] | None


def shape_function(
    shape: TrajectoryShape, center: float, amplitude: float, omega: float
) -> TimeFunction:
    """center + amplitude g(t): rest-to-rest g = (1 - cos(omega t))/2, sin g = sin(omega t)."""
    if amplitude == 0.0:
        return Constant(center)
    if shape is TrajectoryShape.REST_TO_REST:
        return Sinusoid(-0.5 * amplitude, omega, 0.5 * math.pi, center + 0.5 * amplitude)
    return Sinusoid(amplitude, omega, 0.0, center)


@dataclass(frozen=True)
class BuildInfo:
    """What a run needs besides the two mechanisms.

    platform_body / platform_marker: the moving platform and the marker (here a body name:
    its mass centre with the body axes) whose pose the trajectory prescribes. actuators:
    driver names, one per actuated leg, in order; actuator_joints: their prismatic joints;
    home_drives: actuator values at home [m]. clearance_joints: names of the clearance
    joints in the clearance mechanism (a universal joint's pair: "<joint>.<pair>").
    home_position (3,) [m]: platform centre at home, where g(t) = 0.
    pose_sequence / pose_mode: rotation sequence and mode of the prescribed orientation
    (`clearance.analysis.ik.PlatformTrajectory`); angle_coordinates: trajectory
    coordinates mapped onto that sequence (missing ones are 0). t_end [s]: the scenario's
    duration. simulate_kwargs: keyword arguments of `clearance.simulate`.
    """

    mechanism_type: MechanismType
    platform_body: str
    platform_marker: str
    actuators: tuple[str, ...]
    actuator_joints: tuple[str, ...]
    home_drives: tuple[float, ...]
    clearance_joints: tuple[str, ...]
    home_position: tuple[float, float, float]
    trajectory: TrajectorySpec
    pose_sequence: str
    pose_mode: str
    angle_coordinates: tuple[str, ...]
    initial: InitialPlacement
    t_end: float
    simulate_kwargs: dict = field(default_factory=dict)
    ik_mechanism: Mechanism | None = None  # model with driver rows for the IK (default: ideal)
    pose_positions: tuple[str, ...] = ("x", "y", "z")  # prescribed position coordinates

    def pose_functions(self) -> dict[str, TimeFunction]:
        """x, y, z [m] of the platform marker and the angles [rad] of `pose_sequence`
        (keys "angle_1".."angle_3") as time functions: home + amplitude g(t)."""
        tr, w = self.trajectory, self.trajectory.omega
        if tr.shape in (TrajectoryShape.REST_TO_REST, TrajectoryShape.SIN):

            def fn(c: str, home: float) -> TimeFunction:
                return shape_function(tr.shape, home, tr.amplitude.get(c, 0.0), w)
        else:

            def fn(c: str, home: float) -> TimeFunction:
                return pose_function(tr, c, home)

        out = {c: fn(c, h) for c, h in zip(("x", "y", "z"), self.home_position, strict=True)}
        for k in range(3):
            name = self.angle_coordinates[k] if k < len(self.angle_coordinates) else ""
            out[f"angle_{k + 1}"] = fn(name, 0.0)
        return out

    def platform_trajectory(self) -> Any:
        """The trajectory as a `clearance.analysis.ik.PlatformTrajectory`."""
        from clearance.analysis.ik import PlatformTrajectory

        f = self.pose_functions()
        angles = (f["angle_1"], f["angle_2"], f["angle_3"])
        return PlatformTrajectory(
            f["x"],
            f["y"],
            f["z"],
            angles=angles,
            sequence=self.pose_sequence,
            mode=self.pose_mode,
            positions=self.pose_positions,
        )


def _drive_list(drives: Drives, actuators: tuple[str, ...], source: str) -> list | None:
    if drives is None or not isinstance(drives, Mapping):
        return None if drives is None else list(drives)
    unknown = [k for k in drives if k not in actuators]
    missing = [a for a in actuators if a not in drives]
    if unknown or missing:
        raise ScenarioError(
            source,
            "drives",
            sorted(drives),
            f"expected one drive per actuator {list(actuators)} (unknown {unknown}, "
            f"missing {missing})",
        )
    return [drives[a] for a in actuators]


def with_clearances(ideal: Mechanism, s: Scenario) -> Mechanism:
    """The scenario's clearance mechanism: the ideal one with its clearance joints."""
    clr = ideal.copy()
    for name, joint in s.clearance.joints.items():
        clr = clr.with_clearance(name, joint)
    clr.name = f"{s.name} (clearance)"
    return clr


def _info(s: Scenario, mtype: MechanismType, home: float | tuple, **specific) -> BuildInfo:
    """BuildInfo fields shared by every mechanism type, plus the type-specific ones. home:
    the platform centre's height (on the z axis) or its position at home [m]."""
    kind = s.mechanism.kind
    tr = s.trajectory
    return BuildInfo(
        mechanism_type=mtype,
        clearance_joints=tuple(
            pair_joint_name(n, j.pair) if isinstance(j, UniversalClearance) else n
            for n, j in s.clearance.joints.items()
        ),
        home_position=(0.0, 0.0, home) if isinstance(home, float) else tuple(home),
        trajectory=tr,
        pose_sequence=tr.sequence or kind.sequence,
        pose_mode=tr.orientation or kind.mode,
        pose_positions=tr.positions or ("x", "y", "z"),
        angle_coordinates=kind.angles,
        initial=s.clearance.initial,
        t_end=s.trajectory.duration,
        simulate_kwargs=s.solver.simulate_kwargs(),
        **specific,
    )


def _build_ups_upu(s: Scenario, drives: Drives) -> tuple[Mechanism, Mechanism, BuildInfo]:
    par = s.mechanism.params
    actuators = tuple(f"drive_{k}" for k in range(1, 6))
    home = home_leg_lengths(par)  # type: ignore[arg-type]
    fns = _drive_list(drives, actuators, s.source)
    ideal = ups_upu_ideal(par, drives=home if fns is None else fns, name=f"{s.name} (ideal)")  # type: ignore[arg-type]
    info = _info(
        s,
        MechanismType.UPS_UPU,
        par.home_height,  # type: ignore[attr-defined]
        platform_body="platform",
        platform_marker="platform",
        actuators=actuators,
        actuator_joints=tuple(f"P_{k}" for k in range(1, 6)),
        home_drives=home,
    )
    return ideal, with_clearances(ideal, s), info


def _build_sps_cu(s: Scenario, drives: Drives) -> tuple[Mechanism, Mechanism, BuildInfo]:
    """4-SPS/CU (mechanisms.md 2): limbs lumped (mass-moment method, physics.md i) or
    two-body per the `limb_model` parameter. Lumped limbs have no driver rows (the length
    enters through the attachments), so the IK runs on the two-body model with the same
    parameters (`info.ik_mechanism`): both give the same platform motion for the same
    lengths (tests/test_sps_cu.py)."""
    from clearance.mechanisms.sps_cu import sps_cu, sps_cu_home_lengths, sps_cu_names

    par = s.mechanism.params
    names = sps_cu_names("two-body")
    home = tuple(sps_cu_home_lengths(par))  # type: ignore[arg-type]
    fns = _drive_list(drives, names.drives, s.source)
    lengths = list(home) if fns is None else fns
    limbs = par.limb_model  # type: ignore[attr-defined]
    ideal = sps_cu(par, limbs=limbs, lengths=lengths, name=f"{s.name} (ideal)")  # type: ignore[arg-type]
    info = _info(
        s,
        MechanismType.SPS_CU,
        par.home_height,  # type: ignore[attr-defined]
        platform_body=names.platform_body,
        platform_marker=names.platform_marker,
        actuators=names.drives,
        actuator_joints=names.prismatic_joints,
        home_drives=home,
        ik_mechanism=sps_cu(par, limbs="two-body", lengths=lengths, name=f"{s.name} (IK)"),  # type: ignore[arg-type]
    )
    return ideal, with_clearances(ideal, s), info


def _build_parallel(s: Scenario, drives: Drives) -> tuple[Mechanism, Mechanism, BuildInfo]:
    """Any parallel mechanism from leg types (clearance.parallel); lumped limbs run their
    inverse kinematics on the two-body model (`info.ik_mechanism`)."""
    pm = s.mechanism.params.mechanism  # type: ignore[union-attr]
    fns = _drive_list(drives, pm.actuators, s.source)  # (a mapping: checked, in order)
    ideal = pm.build(fns, check=False, name=f"{s.name} (ideal)")
    info = _info(
        s,
        MechanismType.PARALLEL,
        pm.platform.position,
        platform_body=pm.platform_body,
        platform_marker=pm.platform_marker,
        actuators=pm.actuators,
        actuator_joints=pm.actuator_joints,
        home_drives=tuple(pm.home_drives().values()),
        ik_mechanism=pm.ik_mechanism(fns) if pm.lumped else None,
    )
    return ideal, with_clearances(ideal, s), info


def _build_general(s: Scenario, drives: Drives) -> tuple[Mechanism, Mechanism, BuildInfo]:
    """A mechanism written element by element (clearance.scenario.general): the file's
    drivers run as given; those in `trajectory.actuators` get the inverse kinematics'
    drives (`drives`), the home value of their function until then."""
    from clearance.analysis.ik import apply_drives
    from clearance.scenario.general import platform_body

    params = s.mechanism.params
    mech = params.mechanism.copy()  # type: ignore[union-attr]
    acts = tuple(s.trajectory.actuators or ())
    fns = _drive_list(drives, acts, s.source)
    if fns is not None:
        mech = apply_drives(mech, dict(zip(acts, fns, strict=True)))
    mech.name = f"{s.name} (ideal)"
    body = platform_body(params)  # type: ignore[arg-type]
    pname = params.platform  # type: ignore[union-attr]
    info = _info(
        s,
        MechanismType.GENERAL,
        _home_point(mech, pname),
        platform_body=body,
        platform_marker=pname,
        actuators=acts,
        actuator_joints=tuple(mech.drivers[a].joint for a in acts),
        home_drives=tuple(float(mech.drivers[a].function(0.0)) for a in acts),
    )
    return mech, with_clearances(mech, s), info


def _home_point(mech: Mechanism, name: str) -> tuple[float, float, float]:
    """World position at t = 0 of a body's mass centre or a marker's point."""
    import numpy as np

    if name in mech.bodies:
        return tuple(float(x) for x in mech.bodies[name].position)  # type: ignore[return-value]
    mk = mech.markers[name]
    if mk.body == "ground":
        return tuple(float(x) for x in mk.position)  # type: ignore[return-value]
    b = mech.bodies[mk.body]
    p = np.array(b.position) + np.asarray(b.rotation) @ np.array(mk.position)
    return tuple(float(x) for x in p)  # type: ignore[return-value]


Builder = Callable[[Scenario, Drives], tuple[Mechanism, Mechanism, BuildInfo]]

# Mechanism type -> builder
BUILDERS: dict[MechanismType, Builder] = {
    MechanismType.UPS_UPU: _build_ups_upu,
    MechanismType.SPS_CU: _build_sps_cu,
    MechanismType.PARALLEL: _build_parallel,
    MechanismType.GENERAL: _build_general,
}


def build_mechanisms(
    s: Scenario, *, drives: Drives = None
) -> tuple[Mechanism, Mechanism, BuildInfo]:
    """(ideal mechanism, clearance mechanism, info) of a validated scenario.

    drives: actuator drives (time functions or numbers [m]), a sequence in the order of
    `info.actuators` or a mapping actuator name -> function (e.g. from the inverse
    kinematics of `info.platform_trajectory()`); None = hold the home lengths.
    Raises ScenarioError naming `mechanism.type` when no builder exists for the type.
    """
    if not isinstance(s, Scenario):
        raise ScenarioError("<build>", "scenario", s, "expected a validated Scenario")
    builder = BUILDERS.get(s.mechanism.type)
    if builder is None:
        raise ScenarioError(
            s.source,
            "mechanism.type",
            s.mechanism.type.value,
            "builder not available in this version",
        )
    try:
        return builder(s, drives)
    except ScenarioError:
        raise
    except ModelError as e:
        raise ScenarioError(s.source, e.field, e.value, f"{e.element}: {e.allowed}") from e
