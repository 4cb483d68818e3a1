"""Scenario format version 1: the validated `Scenario` and its dict form.

A scenario file (TOML, see docs/scenario-format.md) has `format_version = 1` and the
sections [scenario], [mechanism], [trajectory], [clearance] (with [clearance.joints.<joint>]
tables), [solver] and [output]. `scenario_from_dict(d, source=...)` checks everything and
returns frozen dataclasses in which strings have become enums, law objects and parameter
sets; every problem of the file is collected and raised together as one `ScenarioError`
(file, dotted field path, value, what is allowed). `scenario_to_dict(s)` is the inverse: a
complete, canonical dict (every default written out, `clearance.scenario.serialize`) that
validates to an equal Scenario.

Field paths are the dotted key paths of the file (`mechanism.R_A`,
`clearance.joints.S_1.normal.restitution`, `solver.rtol`); studies address parameters by them
(`clearance.scenario.paths`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from clearance.analysis import plausibility as _pl
from clearance.analysis.cost import LONG_RUN_SECONDS
from clearance.analysis.ik import ACTUATOR_DRIVERS
from clearance.integrate.methods import ADAPTIVE, METHODS
from clearance.io.outputs import ALL as ALL_OUTPUTS
from clearance.io.outputs import OUTPUTS
from clearance.mechanisms.params import ParamSet, SpsCuParams
from clearance.mechanisms.ups_upu import UpsUpuParams
from clearance.model.clearance import (
    Clearance,
    PrismaticClearance,
    RevoluteClearance,
    UniversalClearance,
)
from clearance.model.contact_laws import (
    FRICTION_LAWS,
    NORMAL_LAWS,
    STEEL,
    Flores,
    LankaraniNikravesh,
    Material,
    NoFriction,
)
from clearance.model.errors import ModelError
from clearance.model.mechanism import Mechanism
from clearance.scenario.errors import MISSING, Problems, ScenarioError, did_you_mean
from clearance.scenario.fields import REQUIRED, Field, parse_table, table_at
from clearance.scenario.general import GeneralParams, parse_general
from clearance.scenario.parallel import ParallelParams, parse_parallel
from clearance.scenario.steady import SteadyStateSpec, parse_steady_state
from clearance.scenario.trajectories import (  # (IK_SPACING: re-exported)
    IK_PER_PERIOD,
    IK_SPACING,
    MAX_IK_POSES,
    ik_count,
    ik_times,
    parse_harmonics,
    parse_samples,
    time_scale,
)
from clearance.scenario.view import ViewSpec, parse_view
from clearance.scenario.wear import WearSettings, parse_wear

__all__ = [
    "FORMAT_VERSION",
    "IK_SPACING",
    "MECHANISMS",
    "CLEARANCE_KINDS",
    "ClearanceKindSpec",
    "ClearanceSpec",
    "InitialPlacement",
    "JointSpec",
    "MechanismKind",
    "ChecksSpec",
    "MechanismSpec",
    "MechanismType",
    "OutputSpec",
    "Scenario",
    "ScenarioMeta",
    "SolverSpec",
    "TrajectoryShape",
    "TrajectorySpec",
    "parse_law",
    "scenario_from_dict",
]

FORMAT_VERSION = 1
SECTIONS = (
    "scenario",
    "mechanism",
    "trajectory",
    "clearance",
    "solver",
    "output",
    "checks",
    "steady_state",
    "view",
    "wear",
)
TOP_KEYS = ("format_version", *SECTIONS)
AUTO = "auto"  # in a law table: the field's computed value (None in Python)


class MechanismType(str, Enum):
    UPS_UPU = "4ups-upu"
    SPS_CU = "4sps-cu"
    PARALLEL = "parallel"  # any parallel mechanism from leg types (clearance.parallel)
    GENERAL = "general"  # any mechanism, element by element (clearance.scenario.general)


class TrajectoryShape(str, Enum):
    REST_TO_REST = "rest-to-rest"  # g = (1 - cos(2 pi t / period)) / 2
    SIN = "sin"  # g = sin(2 pi t / period)
    PERIODIC = "periodic"  # sums of sinusoids per coordinate ([trajectory.periodic])
    VIA_POINTS = "via-points"  # quintic spline through points, rest to rest
    TABLE = "table"  # cubic spline through tabulated values (a CSV file or inline)


class InitialPlacement(str, Enum):
    CENTRED = "centred"  # ball centre at the socket centre (mechanisms.md 1.6 option A)
    REACTION = "reaction"  # e = c n0 along the ideal reaction (option B)


@dataclass(frozen=True)
class MechanismKind:
    """What a mechanism type offers to a scenario file.

    params: its parameter set class; spherical_joints: its spherical joints, with the body
    of marker i (the default socket side); clearance_joints: every joint that may get
    clearance, with its clearance kind ("spherical", "revolute", "cylindrical",
    "prismatic", "universal": a revolute pair of a universal joint; `CLEARANCE_KINDS`);
    two_body_joints: those that exist only with two-body
    limbs (4-SPS/CU `limb_model`); positions / angles: trajectory
    amplitude coordinates [m] / [rad]; sequence, mode: the platform-pose description of
    `clearance.analysis.ik` (angles map onto the sequence, missing ones are 0).
    """

    params: type[ParamSet]
    spherical_joints: Mapping[str, str]
    positions: tuple[str, ...]
    angles: tuple[str, ...]
    sequence: str
    mode: str
    description: str
    clearance_joints: Mapping[str, str] = field(default_factory=dict)
    two_body_joints: tuple[str, ...] = ()

    @property
    def coordinates(self) -> tuple[str, ...]:
        return (*self.positions, *self.angles)


MECHANISMS: Mapping[MechanismType, MechanismKind] = {
    MechanismType.UPS_UPU: MechanismKind(
        params=UpsUpuParams,
        spherical_joints={f"S_{k}": "platform" for k in range(1, 5)},
        positions=("x", "y", "z"),
        angles=("alpha", "beta"),
        sequence="xyz",
        mode="axis",
        description="4UPS-UPU parallel mechanism (mechanisms.md 1)",
        clearance_joints={
            **{f"S_{k}": "spherical" for k in range(1, 5)},
            **{f"P_{k}": "prismatic" for k in range(1, 6)},
            **{f"U_{k}": "universal" for k in range(1, 6)},
            "U5p": "universal",
        },
    ),
    # 4-SPS/CU: SA_k base side, SB_k platform side; C the central leg's cylindrical joint;
    # P_k the limbs' prismatic joints (two-body limbs only)
    MechanismType.SPS_CU: MechanismKind(
        params=SpsCuParams,
        spherical_joints={
            **{f"SA_{k}": "ground" for k in range(1, 5)},
            **{f"SB_{k}": "platform" for k in range(1, 5)},
        },
        positions=("z",),
        angles=("psi", "t1", "t2"),
        sequence="zxy",
        mode="full",
        description="4-SPS/CU parallel mechanism (mechanisms.md 2)",
        clearance_joints={
            **{f"SA_{k}": "spherical" for k in range(1, 5)},
            **{f"SB_{k}": "spherical" for k in range(1, 5)},
            "C": "cylindrical",
            "U": "universal",
            **{f"P_{k}": "prismatic" for k in range(1, 5)},
        },
        two_body_joints=tuple(f"P_{k}" for k in range(1, 5)),
    ),
}

_ENUMS = {
    "method": ("auto", *METHODS),
    "linear_solver": ("auto", "schur", "dense", "lstsq"),
    "formats": ("netcdf", "csv", "mat", "npz"),
    "figure_format": ("png", "pdf", "svg"),
}

SCENARIO_FIELDS = {
    "name": Field("name", REQUIRED, doc="scenario name (result file names, labels)"),
    "description": Field("text", "", doc="free text"),
}
ORIENTATIONS = ("full", "axis", "none")
TRAJECTORY_FIELDS = {
    "shape": Field(
        "choice", "rest-to-rest", doc="g(t)", choices=tuple(s.value for s in TrajectoryShape)
    ),
    # below a nanosecond the inverse kinematics' spline knots underflow (1e-300 s: LAPACK
    # 'DLASCL illegal value', then 'SVD did not converge')
    "duration": Field("positive", 2.0, "s", "simulated time t_end", minimum=1e-9),
    "period": Field("positive", None, "s", "period of g(t); default: duration"),
    # type = "parallel" only: which pose coordinates the trajectory prescribes
    "orientation": Field(
        "choice", None, doc="full, axis (the normal) or none", choices=ORIENTATIONS
    ),
    "sequence": Field("text", None, doc="rotation sequence of alpha, beta, gamma"),
    "positions": Field("choices", None, doc="prescribed coordinates", choices=("x", "y", "z")),
    # type = "general" only: the drivers the inverse kinematics replaces (none: no IK)
    "actuators": Field("list", None, doc="drivers replaced by the inverse kinematics"),
}
PARALLEL_ONLY = ("orientation", "sequence", "positions")
SHAPE_TABLES = ("amplitude", "periodic", "via_points", "table")  # one per shape
CLEARANCE_FIELDS = {
    "initial": Field(
        "choice",
        "centred",
        doc="ball placement at t = 0",
        choices=tuple(p.value for p in InitialPlacement),
    ),
}
JOINT_FIELDS = {
    "ball_radius": Field("positive", REQUIRED, "m", "ball radius R_b"),
    "radial_clearance": Field("positive", None, "m", "c = R_s - R_b (or socket_radius)"),
    "socket_radius": Field("positive", None, "m", "R_s (or radial_clearance)"),
    "socket": Field("choice", "i", doc="marker whose body holds the socket", choices=("i", "j")),
    "velocity_floor": Field("positive", 1e-4, "m/s", "floor of delta_dot_minus"),
    "onset_tolerance": Field("positive", 1e-3, doc="onset penetration / c (< 0.5)"),
}
MATERIAL_FIELDS = ("E", "nu")
_COMMON = {
    "velocity_floor": JOINT_FIELDS["velocity_floor"],
    "onset_tolerance": JOINT_FIELDS["onset_tolerance"],
}
_MODEL = Field("choice", "planar", doc="planar or spatial model", choices=("planar", "spatial"))
REVOLUTE_FIELDS = {
    "journal_radius": Field("positive", REQUIRED, "m", "journal radius R_J"),
    "radial_clearance": Field("positive", None, "m", "c = R_B - R_J (or bearing_radius)"),
    "bearing_radius": Field("positive", None, "m", "R_B (or radial_clearance)"),
    "model": _MODEL,
    "length": Field("positive", None, "m", "bearing (contact) length; spatial model"),
    "stations": Field("count", 5, doc="bearing cross-sections of the spatial model (>= 2)"),
    "axial_clearance": Field("positive", None, "m", "gap at each thrust face; spatial"),
    "thrust_radius": Field("positive", None, "m", "radius of the thrust points"),
    "thrust_points": Field("count", 4, doc="thrust points per face (>= 3)"),
    "bearing": Field("choice", "i", doc="marker whose body holds the bearing", choices=("i", "j")),
    **_COMMON,
}
CYLINDRICAL_FIELDS = {
    k: v
    for k, v in REVOLUTE_FIELDS.items()
    if k not in ("axial_clearance", "thrust_radius", "thrust_points")
}
UNIVERSAL_FIELDS = {
    "pair": Field(
        "choice", REQUIRED, doc="pair with clearance: about h_i or h_j", choices=("i", "j")
    ),
    "cross_mass": Field("positive", REQUIRED, "kg", "mass of the cross (it becomes a body)"),
    "cross_inertia": Field(
        "positive3", REQUIRED, "kg m2", "principal moments of the cross about h_i, h_j, h_i x h_j"
    ),
    **REVOLUTE_FIELDS,
}
PRISMATIC_FIELDS = {
    "width": Field("positive", REQUIRED, "m", "slider width (guide marker's f axis)"),
    "length": Field("positive", REQUIRED, "m", "slider length (sliding axis h)"),
    "clearance": Field("positive", REQUIRED, "m", "gap per side, width direction"),
    "height": Field("positive", None, "m", "slider height (g axis); spatial model"),
    "clearance_height": Field("positive", None, "m", "gap per side, height direction"),
    "model": _MODEL,
    "corner_radius": Field("positive", None, "m", "rounded corners: Hertz stiffness"),
    "guide": Field("choice", "i", doc="marker whose body holds the guide", choices=("i", "j")),
    **_COMMON,
}


@dataclass(frozen=True)
class ClearanceKindSpec:
    """A clearance kind in files: its class, fields, law tables (with their defaults),
    material tables and the pair of exclusive radius fields (if any)."""

    cls: type
    fields: Mapping[str, Field]
    laws: Mapping[str, tuple[Mapping[str, type], object]]
    materials: tuple[str, ...]
    radii: tuple[str, str] | None

    @property
    def tables(self) -> tuple[str, ...]:
        return (*self.laws, *self.materials)


# journals and sliders: Lankarani-Nikravesh (Flores & Ambrosio 2004, Flores et al. 2008)
_LN_LAWS = {
    "normal": (NORMAL_LAWS, LankaraniNikravesh()),
    "friction": (FRICTION_LAWS, NoFriction()),
}
_REVOLUTE_LAWS = {**_LN_LAWS, "thrust_normal": (NORMAL_LAWS, None)}
CLEARANCE_KINDS: Mapping[str, ClearanceKindSpec] = {
    "spherical": ClearanceKindSpec(
        Clearance,
        JOINT_FIELDS,
        {"normal": (NORMAL_LAWS, Flores()), "friction": (FRICTION_LAWS, NoFriction())},
        ("ball_material", "socket_material"),
        ("radial_clearance", "socket_radius"),
    ),
    "revolute": ClearanceKindSpec(
        RevoluteClearance,
        REVOLUTE_FIELDS,
        _REVOLUTE_LAWS,
        ("journal_material", "bearing_material"),
        ("radial_clearance", "bearing_radius"),
    ),
    "cylindrical": ClearanceKindSpec(
        RevoluteClearance,
        CYLINDRICAL_FIELDS,
        _LN_LAWS,
        ("journal_material", "bearing_material"),
        ("radial_clearance", "bearing_radius"),
    ),
    "universal": ClearanceKindSpec(
        UniversalClearance,
        UNIVERSAL_FIELDS,
        _REVOLUTE_LAWS,
        ("journal_material", "bearing_material"),
        ("radial_clearance", "bearing_radius"),
    ),
    "prismatic": ClearanceKindSpec(
        PrismaticClearance,
        PRISMATIC_FIELDS,
        _LN_LAWS,
        ("slider_material", "guide_material"),
        None,
    ),
}


SOLVER_FIELDS = {
    "method": Field("choice", "dopri5", doc="integrator", choices=_ENUMS["method"]),
    "rtol": Field("positive", 1e-6, doc="relative tolerance (dopri5, tsit5, dop853, vern7)"),
    "atol": Field("positive", 1e-9, doc="absolute tolerance (dopri5, tsit5, dop853, vern7)"),
    "first_step": Field("nonneg", 0.0, "s", "first step (0: automatic)"),
    "max_step": Field("positive_inf", math.inf, "s", "largest step (inf: no limit)"),
    "min_step": Field("positive", 1e-14, "s", "smallest step before failure"),
    "max_steps": Field("count", 10_000_000, doc="step budget"),
    "step": Field("positive", 1e-3, "s", "fixed step (rk4)"),
    "baumgarte_alpha": Field("nonneg", 5.0, "1/s", "Baumgarte alpha"),
    "baumgarte_beta": Field("nonneg", 5.0, "1/s", "Baumgarte beta"),
    "linear_solver": Field(
        "choice", "auto", doc="constraint solve", choices=_ENUMS["linear_solver"]
    ),
    "projection": Field("bool", False, doc="coordinate projection after each step"),
    "projection_tol": Field("positive", 1e-10, doc="projection tolerance"),
    "dt_out": Field("positive", 1e-4, "s", "output interval"),
    "max_events": Field("count", 100_000, doc="contact event log size"),
    "max_wall_time": Field(
        "positive_inf", math.inf, "s", "stop a run after this wall time (inf: no limit)"
    ),
}
# largest fixed step of "rk4" with clearance joints: measured on the shipped scenarios, 1e-5 s
# reproduces tsit5's penetrations (4.2 / 3.8 um) and 1e-4 s lets the ball sink 3 mm into the
# socket until the run fails; PROPOSED for other stiffnesses and masses ([checks])
RK4_CLEARANCE_STEP = 1e-5  # [s]

CHECKS_FIELDS = {
    "penetration_implausible": Field(
        "positive", _pl.PENETRATION_IMPLAUSIBLE, doc="implausible: penetration > this x c"
    ),
    "penetration_warning": Field(
        "positive", _pl.PENETRATION_WARNING, doc="warning: penetration > this x c"
    ),
    "radius_implausible": Field(
        "positive", _pl.RADIUS_IMPLAUSIBLE, doc="implausible: penetration > this x the radius"
    ),
    "energy_implausible": Field(
        "positive", _pl.ENERGY_IMPLAUSIBLE, doc="implausible: energy residual > this x scale"
    ),
    "energy_warning": Field(
        "positive", _pl.ENERGY_WARNING, doc="warning: energy residual > this x scale"
    ),
    "rk4_clearance_step": Field(
        "positive", RK4_CLEARANCE_STEP, "s", "largest rk4 step with clearance joints"
    ),
    "long_run": Field(
        "positive_inf", LONG_RUN_SECONDS, "s", "warn above this integration time (inf: never)"
    ),
}
OUTPUT_FIELDS = {
    "folder": Field("name", "results", doc="output folder"),
    "figures": Field("bool", True, doc="write figures"),
    "figure_format": Field("choice", "png", choices=_ENUMS["figure_format"]),
    "formats": Field("choices", ("netcdf",), doc="result files", choices=_ENUMS["formats"]),
    "outputs": Field(
        "choices",
        (),
        doc="result groups beyond the lean default (clearance.io.outputs)",
        choices=(*OUTPUTS, ALL_OUTPUTS),
    ),
    "report": Field("bool", True, doc="write report.html (summary, figures, 3-D viewer)"),
}


# --------------------------------------------------------------------------- dataclasses


@dataclass(frozen=True)
class ScenarioMeta:
    name: str
    description: str = ""


@dataclass(frozen=True)
class MechanismSpec:
    type: MechanismType
    params: ParamSet | ParallelParams | GeneralParams

    @property
    def kind(self) -> MechanismKind:
        if self.type is MechanismType.PARALLEL:
            return parallel_kind(self.params)  # type: ignore[arg-type]
        if self.type is MechanismType.GENERAL:
            return general_kind(self.params)  # type: ignore[arg-type]
        return MECHANISMS[self.type]


PARALLEL_POSITIONS = ("x", "y", "z")
PARALLEL_ANGLES = ("alpha", "beta", "gamma")  # the angles of `trajectory.sequence`, in order


_CLEARANCE_KIND_OF = {
    "Spherical": "spherical",
    "Revolute": "revolute",
    "Cylindrical": "cylindrical",
    "Prismatic": "prismatic",
    "Universal": "universal",
}


def _model_kind(params_cls: type, mech: Mechanism, description: str) -> MechanismKind:
    """What a mechanism built from a file offers to it: each of its S, R, C, P, U joints
    may get clearance (its kind by its class; a spherical joint's socket by default on the
    body of marker i); trajectory coordinates x, y, z [m] and alpha, beta, gamma [rad]
    (the angles of `trajectory.sequence`)."""
    joints = {
        n: _CLEARANCE_KIND_OF[type(j).__name__]
        for n, j in mech.joints.items()
        if type(j).__name__ in _CLEARANCE_KIND_OF
    }
    return MechanismKind(
        params=params_cls,  # type: ignore[arg-type]
        spherical_joints={
            n: mech.markers[mech.joints[n].marker_i].body
            for n, k in joints.items()
            if k == "spherical"
        },
        positions=PARALLEL_POSITIONS,
        angles=PARALLEL_ANGLES,
        sequence="xyz",
        mode="full",
        description=description,
        clearance_joints=joints,
    )


def general_kind(params: GeneralParams) -> MechanismKind:
    """A general mechanism's kind (`_model_kind`)."""
    m = params.mechanism
    return _model_kind(GeneralParams, m, f"mechanism '{m.name}' ({len(m.bodies)} bodies)")


def parallel_kind(params: ParallelParams) -> MechanismKind:
    """A parallel mechanism's kind (`_model_kind` of its built ideal mechanism: a lumped
    limb has no P)."""
    pm = params.mechanism
    desc = f"parallel mechanism '{pm.name}' ({len(pm.legs)} legs)"
    return _model_kind(ParallelParams, params.ideal, desc)


@dataclass(frozen=True)
class TrajectorySpec:
    """Platform pose = home + amplitude[coord] * g(t); g = 0 at t = 0 (mechanisms.md 1.5, 2.3).

    amplitude: coordinate -> amplitude ([m] for positions, [rad] for angles), every
    coordinate of the mechanism type present (0 = not moved; shapes rest-to-rest and sin).
    harmonics (shape periodic) and samples (via-points, table): the displacements from home
    (`clearance.scenario.trajectories`). orientation, sequence,
    positions (type "parallel" only, else None): the platform pose the trajectory
    prescribes (`clearance.analysis.ik.PlatformTrajectory` mode, sequence, positions).
    """

    shape: TrajectoryShape = TrajectoryShape.REST_TO_REST
    duration: float = 2.0
    period: float = 2.0
    amplitude: dict = field(default_factory=dict)
    orientation: str | None = None  # type = "parallel": "full", "axis" or "none"
    sequence: str | None = None  # type = "parallel": rotation sequence of alpha, beta, gamma
    positions: tuple | None = None  # type = "parallel": prescribed x, y, z
    harmonics: dict | None = None  # periodic: coordinate -> ((amplitude, period, phase), ...)
    samples: dict | None = None  # via-points, table: {"t": times, coordinate: values}
    actuators: tuple | None = None  # type = "general": the drivers the IK replaces

    def ik_times(self) -> np.ndarray:
        """Sample times of the inverse kinematics (clearance.scenario.trajectories)."""
        return ik_times(self)

    @property
    def time_scale(self) -> float:
        """Shortest period or sample interval of the motion [s]."""
        return time_scale(self)

    @property
    def omega(self) -> float:
        """Angular frequency 2 pi / period [rad/s]."""
        return 2.0 * math.pi / self.period


class JointSpec(Clearance):
    """Deprecated: a scenario's clearance joint is the model's `Clearance` itself
    (`ClearanceSpec.joints` maps joint names to Clearance objects)."""

    def __post_init__(self) -> None:
        warnings.warn(
            "JointSpec is deprecated; use clearance.Clearance", DeprecationWarning, stacklevel=3
        )
        super().__post_init__()

    def clearance(self) -> Clearance:
        kw = {f.name: getattr(self, f.name) for f in dataclasses.fields(Clearance) if f.init}
        kw["socket_radius" if self.given == "radial_clearance" else "radial_clearance"] = None
        return Clearance(**kw)


@dataclass(frozen=True)
class ClearanceSpec:
    initial: InitialPlacement = InitialPlacement.CENTRED
    joints: dict = field(default_factory=dict)  # joint name -> its clearance (model object)


@dataclass(frozen=True)
class SolverSpec:
    method: str = "dopri5"
    rtol: float = 1e-6
    atol: float = 1e-9
    first_step: float = 0.0
    max_step: float = math.inf
    min_step: float = 1e-14
    max_steps: int = 10_000_000
    step: float = 1e-3
    baumgarte_alpha: float = 5.0
    baumgarte_beta: float = 5.0
    linear_solver: str = "auto"
    projection: bool = False
    projection_tol: float = 1e-10
    dt_out: float = 1e-4
    max_events: int = 100_000
    max_wall_time: float = math.inf

    def simulate_kwargs(self) -> dict[str, object]:
        """Keyword arguments of `clearance.simulate` (without t_end)."""
        kw = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        kw["baumgarte"] = (kw.pop("baumgarte_alpha"), kw.pop("baumgarte_beta"))
        kw["solver"] = kw.pop("linear_solver")
        return kw


@dataclass(frozen=True)
class OutputSpec:
    folder: str = "results"
    figures: bool = True
    figure_format: str = "png"
    formats: tuple = ("netcdf",)
    outputs: tuple = ()  # groups written besides clearance.io.outputs.LEAN
    report: bool = True  # report.html (clearance.view.report)


@dataclass(frozen=True)
class ChecksSpec:
    """Thresholds of the checks around a run (all PROPOSED defaults): the plausibility of
    its results (`clearance.analysis.plausibility`), the largest rk4 step with clearance
    joints, and the integration time above which a run is announced as long."""

    penetration_implausible: float = _pl.PENETRATION_IMPLAUSIBLE
    penetration_warning: float = _pl.PENETRATION_WARNING
    radius_implausible: float = _pl.RADIUS_IMPLAUSIBLE
    energy_implausible: float = _pl.ENERGY_IMPLAUSIBLE
    energy_warning: float = _pl.ENERGY_WARNING
    rk4_clearance_step: float = RK4_CLEARANCE_STEP
    long_run: float = LONG_RUN_SECONDS

    def plausibility_kwargs(self) -> dict[str, float]:
        """Keyword arguments of `clearance.analysis.plausibility.plausibility`."""
        names = ("penetration_implausible", "penetration_warning", "radius_implausible")
        names += ("energy_implausible", "energy_warning")
        return {n: getattr(self, n) for n in names}


@dataclass(frozen=True)
class Scenario:
    """A validated scenario (format version 1). `source`: the file it came from."""

    scenario: ScenarioMeta
    mechanism: MechanismSpec
    trajectory: TrajectorySpec
    clearance: ClearanceSpec
    solver: SolverSpec
    output: OutputSpec
    format_version: int = FORMAT_VERSION
    source: str = field(default="<dict>", compare=False)
    checks: ChecksSpec = field(default_factory=ChecksSpec)
    steady_state: SteadyStateSpec | None = None  # [steady_state] (clearance.scenario.steady)
    view: ViewSpec = field(default_factory=ViewSpec)  # [view] (clearance.scenario.view)
    wear: WearSettings | None = None  # [wear] (clearance.scenario.wear)

    @property
    def name(self) -> str:
        return self.scenario.name

    def summary(self) -> str:
        """One line: name, mechanism, clearance joints, trajectory, integrator."""
        joints = self.clearance.joints
        jt = f"{len(joints)} clearance joint{'s' * (len(joints) != 1)}"
        if joints:
            jt += f" ({', '.join(joints)})"
        sv = self.solver
        adaptive = sv.method in (*ADAPTIVE, "auto")
        tol = f"rtol {sv.rtol:g}, atol {sv.atol:g}" if adaptive else f"h {sv.step:g}"
        tr = self.trajectory
        general = self.mechanism.type is MechanismType.GENERAL and not tr.actuators
        motion = "own drivers" if general else tr.shape.value
        return (
            f"scenario '{self.name}': {self.mechanism.type.value}, {jt}, "
            f"{motion} {tr.duration:g} s, {sv.method} {tol}"
        )


# --------------------------------------------------------------------------- parsing


def _optional(f: dataclasses.Field) -> bool:
    return "None" in str(f.type)


def _construct(cls: type, kwargs: dict, path: str, problems: Problems) -> Any:
    """cls(**kwargs); on ModelError report it at path.<field>, drop that field and retry so
    that further bad fields are reported too. None if anything was wrong.

    A retry runs without the fields already reported, so what it finds about a field the
    file does not give, or about a relation to a dropped field (`mu_s >= mu_c = <the
    default mu_c>`), is a consequence, not a problem of the file: the retries end there.
    A first problem on a field the file does not give is a default's: it says so."""
    kw, dropped = dict(kwargs), []
    for _ in range(len(kw) + 1):
        try:
            obj = cls(**kw)
        except TypeError:
            if dropped:  # a required field was dropped above
                return None
            raise
        except ModelError as e:
            top = e.field.split(".")[0]  # (a law's field: "normal.stiffness")
            given = top in kw
            if dropped and (not given or any(f in str(e.allowed) for f in dropped)):
                return None
            value = e.value if given or top in kwargs else f"{e.value!r} (the default)"
            problems.add(f"{path}.{e.field}", value, e.allowed)
            if not given:
                return None
            del kw[top]
            dropped.append(top)
            continue
        return None if dropped else obj
    return None


def _law(value: object, registry: Mapping[str, type], path: str, problems: Problems) -> Any:
    """A normal or friction law from {law = "name", field = value, ...}."""
    t = table_at(value, path, problems)
    if t is None:
        return None
    names = sorted(registry)
    name = t.get("law", MISSING)
    if name is MISSING:
        problems.add(f"{path}.law", MISSING, f"required field is missing; laws: {', '.join(names)}")
        return None
    if not isinstance(name, str) or name not in registry:
        hint = did_you_mean(name, names)
        problems.add(f"{path}.law", name, f"unknown law;{hint} allowed: {', '.join(names)}")
        return None
    cls = registry[name]
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    kwargs, ok = {}, True
    for key, v in t.items():
        if key == "law":
            continue
        if key not in fields:
            problems.unknown(f"{path}.{key}", key, v, ["law", *fields])
            continue
        kwargs[key] = None if (v == AUTO and _optional(fields[key])) else v
    for fname, f in fields.items():
        no_default = f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
        if no_default and fname not in kwargs:
            problems.add(f"{path}.{fname}", MISSING, f"required field of law '{name}' is missing")
            ok = False
    if not ok:  # a required field is missing: the other fields are not checked against it
        return None
    return _construct(cls, kwargs, path, problems)


def parse_law(d: object, kind: str, *, source: str = "<dict>") -> Any:
    """A normal (kind "normal") or friction (kind "friction") law from its file table
    {law = "name", field = value, ...}; ScenarioError naming every problem (field paths
    start with `kind`, e.g. "normal.restitution"). The one parser of law tables: scenario
    files use it for their [clearance.joints.*] laws."""
    registries = {"normal": NORMAL_LAWS, "friction": FRICTION_LAWS}
    if kind not in registries:
        raise ValueError(f"parse_law: kind = {kind!r}; expected 'normal' or 'friction'")
    problems = Problems(source)
    law = _law(d, registries[kind], kind, problems)
    problems.raise_if_any()
    return law


def _material(value: object, path: str, problems: Problems) -> Material | None:
    t = table_at(value, path, problems)
    if t is None:
        return None
    for key, v in t.items():
        if key not in MATERIAL_FIELDS:
            problems.unknown(f"{path}.{key}", key, v, MATERIAL_FIELDS)
    for key in MATERIAL_FIELDS:
        if key not in t:
            problems.add(f"{path}.{key}", MISSING, "required field is missing (E [Pa], nu [-])")
            return None
    # each field against valid values of the others: both of a wrong E and nu reported
    probe, n0 = {"E": STEEL.E, "nu": STEEL.nu}, len(problems)
    for key in MATERIAL_FIELDS:
        try:
            Material(**{**probe, key: t[key]})
        except ModelError as e:
            problems.add(f"{path}.{key}", t[key], e.allowed)
    if len(problems) > n0:
        return None
    return _construct(Material, {k: t[k] for k in MATERIAL_FIELDS}, path, problems)


def _joint(value: object, path: str, kind_name: str, problems: Problems) -> object | None:
    """The clearance of one joint of kind `kind_name` from its file table."""
    t = table_at(value, path, problems)
    if t is None:
        return None
    spec = CLEARANCE_KINDS[kind_name]
    n0 = len(problems)
    given_kind = t.get("kind", kind_name)
    if given_kind != kind_name:
        problems.add(
            f"{path}.kind",
            given_kind,
            f"this joint is {kind_name}: its clearance kind is '{kind_name}'",
        )
    body = {k: v for k, v in t.items() if k != "kind"}
    kw = parse_table(body, spec.fields, path, problems, extra=spec.tables)
    for key, (registry, default) in spec.laws.items():
        kw[key] = _law(t[key], registry, f"{path}.{key}", problems) if key in t else default
    for key in spec.materials:
        kw[key] = _material(t[key], f"{path}.{key}", problems) if key in t else STEEL
    if spec.radii is not None:
        first, second = spec.radii
        given = [k for k in spec.radii if kw.get(k) is not None]
        if not given and not any(k in t for k in spec.radii):
            problems.add(f"{path}.{first}", MISSING, f"required: give {first} or {second}")
        elif len(given) == 2:
            problems.add(
                f"{path}.{second}",
                kw[second],
                f"give only one of {first} (= {kw[first]}) and {second}",
            )
    if len(problems) > n0:
        return None
    return _construct(spec.cls, kw, path, problems)  # with the cross checks of the class


def leg_groups(kind: MechanismKind | None) -> set[str]:
    """Names that group joints "<leg>.<joint>" (a parallel mechanism's legs)."""
    if kind is None:
        return set()
    return {n.split(".", 1)[0] for n in kind.clearance_joints if "." in n}


def _joint_tables(jt: dict, kind: MechanismKind | None):
    """(path, joint name, table) of [clearance.joints]: a parallel mechanism's joints may be
    written "leg1.S" (quoted) or nested by leg, [clearance.joints.leg1.S]."""
    groups = leg_groups(kind)
    for name, value in jt.items():
        known = kind is not None and name in kind.clearance_joints
        if not known and name in groups and isinstance(value, dict):
            for sub, v in value.items():
                yield f"clearance.joints.{name}.{sub}", f"{name}.{sub}", v
        else:
            yield f"clearance.joints.{name}", name, value


def _clearance(
    t: dict, kind: MechanismKind | None, params: ParamSet | None, problems: Problems
) -> ClearanceSpec | None:
    n0 = len(problems)
    kw = parse_table(t, CLEARANCE_FIELDS, "clearance", problems, extra=("joints",))
    joints: dict[str, object] = {}
    jt = table_at(t.get("joints", {}), "clearance.joints", problems)
    for path, name, value in _joint_tables(jt or {}, kind):
        if kind is None:
            continue
        if name not in kind.clearance_joints:
            allowed = list(kind.clearance_joints)
            problems.add(
                path,
                name,
                f"unknown joint '{name}';{did_you_mean(name, allowed)} joints of this "
                f"mechanism that can have clearance: {', '.join(allowed)}",
            )
            continue
        if name in kind.two_body_joints and getattr(params, "limb_model", None) != "two-body":
            problems.add(path, name, "this joint exists with mechanism.limb_model = 'two-body'")
            continue
        clr = _joint(value, path, kind.clearance_joints[name], problems)
        if clr is not None:
            joints[name] = clr
    if len(problems) > n0:
        return None
    return ClearanceSpec(InitialPlacement(kw["initial"]), joints)


def _mechanism(
    t: dict, problems: Problems, default_name: str = "mechanism"
) -> tuple[MechanismSpec | None, MechanismKind | None]:
    types = [m.value for m in MechanismType]
    mtype = t.get("type", MISSING)
    if mtype is MISSING:
        allowed = f"required field is missing; allowed: {', '.join(types)}"
        problems.add("mechanism.type", MISSING, allowed)
        return None, None
    if mtype not in types:
        allowed = f"unknown type;{did_you_mean(mtype, types)} allowed: {', '.join(types)}"
        problems.add("mechanism.type", mtype, allowed)
        return None, None
    mt = MechanismType(mtype)
    if mt in (MechanismType.PARALLEL, MechanismType.GENERAL):
        parse = parse_parallel if mt is MechanismType.PARALLEL else parse_general
        pp = parse(t, problems, default_name=default_name)
        if pp is None:
            return None, None
        ms = MechanismSpec(mt, pp)
        return ms, ms.kind
    kind = MECHANISMS[mt]
    spec = kind.params.spec()
    n0, values = len(problems), {}
    for key, v in t.items():
        if key == "type":
            continue
        if key not in spec:
            problems.unknown(f"mechanism.{key}", key, v, ["type", *spec])
            continue
        try:
            values[key] = kind.params.check_field(key, v)
        except ModelError as e:
            problems.add(f"mechanism.{key}", v, e.allowed)
    if len(problems) > n0:
        return None, kind
    params = _construct(kind.params, values, "mechanism", problems)
    return (MechanismSpec(mt, params) if params is not None else None), kind


def _pose_fields(
    kw: dict, mech: MechanismSpec | None, mtype: str | None, problems: Problems
) -> tuple[str | None, str | None, tuple | None, tuple | None]:
    """(orientation, sequence, positions, actuators) of the trajectory of a parallel or a
    general mechanism, checked against the platform DOF (the number of actuators of a
    general one); Nones for the seed types (which fix them) and for a general mechanism
    without actuators (its drivers run as given: no inverse kinematics)."""
    given = [k for k in (*PARALLEL_ONLY, "actuators") if kw.get(k) is not None]
    pose_types = (MechanismType.PARALLEL.value, MechanismType.GENERAL.value)
    for k in given:
        if mtype not in pose_types or (k == "actuators" and mtype != "general"):
            allowed = "'general'" if k == "actuators" else "'parallel' or 'general'"
            problems.add(f"trajectory.{k}", kw[k], f"only for mechanism.type = {allowed}")
    if mtype not in pose_types or mech is None:  # (a bad [mechanism]: reported there)
        return None, None, None, None
    actuators = None
    if mtype == MechanismType.GENERAL.value:
        m = mech.params.mechanism  # type: ignore[union-attr]
        if not kw.get("actuators"):
            for k in given:
                problems.add(
                    f"trajectory.{k}",
                    kw[k],
                    "no trajectory.actuators: the drivers of the file run as given (give the "
                    "drivers that the inverse kinematics replaces to prescribe a motion)",
                )
            return None, None, None, None
        drives = [n for n, d in m.drivers.items() if isinstance(d, ACTUATOR_DRIVERS)]
        for a in kw["actuators"]:
            if a not in drives:
                problems.add(
                    "trajectory.actuators",
                    a,
                    f"not a prismatic or revolute driver of the mechanism;"
                    f"{did_you_mean(a, drives)} drivers: {', '.join(drives) or '(none)'}",
                )
        actuators = tuple(kw["actuators"])
        dof = len(actuators)
    else:
        dof = mech.params.mobility.platform  # type: ignore[union-attr]
    orientation = kw["orientation"] or "full"
    sequence = kw["sequence"] or "xyz"
    if len(sequence) != 3 or any(c not in "xyz" for c in sequence):
        problems.add("trajectory.sequence", sequence, "expected 3 axis letters, e.g. 'xyz'")
    positions = tuple(p for p in "xyz" if p in (kw["positions"] or ("x", "y", "z")))
    n = len(positions) + {"full": 3, "axis": 2, "none": 0}[orientation]
    if n < dof:  # (more is allowed: the extra ones must follow the mechanism, e.g.
        # x = y = 0 on a CU column; the inverse kinematics refuses them otherwise)
        what = "platform has" if actuators is None else "trajectory.actuators drive"
        problems.add(
            "trajectory.positions" if "positions" in given else "trajectory.orientation",
            list(positions) if "positions" in given else orientation,
            f"the trajectory prescribes {n} coordinates ({', '.join(positions) or 'no position'}"
            f"; orientation '{orientation}'), the {what} {dof} DOF: prescribe at least "
            f"{dof} (positions = [...]; orientation 'full' 3, 'axis' 2 (the normal), "
            "'none' 0)",
        )
    return orientation, sequence, positions, actuators


def _trajectory(
    t: dict,
    kind: MechanismKind | None,
    problems: Problems,
    mech: MechanismSpec | None = None,
    mtype: str | None = None,
    base_dir: Path | None = None,
) -> TrajectorySpec | None:
    n0 = len(problems)
    kw = parse_table(t, TRAJECTORY_FIELDS, "trajectory", problems, extra=SHAPE_TABLES)
    orientation, sequence, positions, actuators = _pose_fields(kw, mech, mtype, problems)
    shape = kw.get("shape")
    own = {"periodic": "periodic", "via-points": "via_points", "table": "table"}.get(
        shape, "amplitude"
    )
    for key in SHAPE_TABLES:
        if key in t and key != own:
            problems.add(
                f"trajectory.{key}",
                t[key],
                f"not used by shape = '{shape}' (it reads [trajectory.{own}])",
            )
    if own != "amplitude" and own not in t:
        problems.add(f"trajectory.{own}", MISSING, f"required by shape = '{shape}'")
    amp: dict[str, float] = {}
    at = table_at(t.get("amplitude", {}), "trajectory.amplitude", problems)
    units = {}  # coordinate -> unit
    if kind is not None:
        units = {**dict.fromkeys(kind.positions, "m"), **dict.fromkeys(kind.angles, "rad")}
    if at is not None and kind is not None:
        for key, v in at.items():
            path = f"trajectory.amplitude.{key}"
            if key not in units:
                problems.unknown(path, key, v, units)
            elif isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                problems.add(path, v, f"expected a finite number [{units[key]}]")
            elif abs(v) > MAX_AMPLITUDE[units[key]]:  # (1e300 m rounded the home pose away)
                problems.add(
                    path,
                    v,
                    f"expected at most {MAX_AMPLITUDE[units[key]]:g} {units[key]} in magnitude "
                    "(beyond any mechanism of this kind)",
                )
            else:
                amp[key] = float(v)
        amp = {c: amp.get(c, 0.0) for c in units}
    if len(problems) > n0 or kind is None:
        return None
    period = kw["period"] if kw["period"] is not None else kw["duration"]
    harmonics = samples = None
    if own == "periodic":
        harmonics = parse_harmonics(t["periodic"], units, period, MAX_AMPLITUDE, problems)
    elif own in ("via_points", "table"):
        samples = parse_samples(
            t[own],
            f"trajectory.{own}",
            units,
            duration=kw["duration"],
            table=own == "table",
            base_dir=base_dir,
            max_amplitude=MAX_AMPLITUDE,
            problems=problems,
        )
    if len(problems) > n0:
        return None
    free = [c for c in PARALLEL_POSITIONS if positions is not None and c not in positions]
    if orientation == "none":
        free += list(PARALLEL_ANGLES)
    elif orientation == "axis" and sequence and sequence[-1] == "z":
        free.append(PARALLEL_ANGLES[2])  # (a last turn about z leaves the normal R e_z)
    moved = {**{c: a for c, a in amp.items() if a != 0.0}, **(harmonics or {})}
    moved.update({c: v for c, v in (samples or {}).items() if c != "t"})
    if mtype == MechanismType.GENERAL.value and actuators is None:
        free = list(units)  # (no inverse kinematics: nothing follows a motion)
    for c in free:
        if c in moved and any(x != 0.0 for x in np.ravel(moved[c])):
            problems.add(
                f"trajectory.{own}.{c}",
                moved[c],
                "this coordinate is left to the mechanism (trajectory.positions / "
                "orientation): it must not move",
            )
    spec = TrajectorySpec(
        TrajectoryShape(kw["shape"]),
        kw["duration"],
        period,
        amp if own == "amplitude" else {c: 0.0 for c in units},
        orientation,
        sequence,
        positions,
        harmonics,
        samples,
        actuators,
    )
    n, scale = ik_times(spec).size, spec.time_scale
    if samples is not None:  # (the rows and via points themselves: long runs at 0.02 s are
        forced = sum(1 for x in samples["t"] if 0.0 < x < kw["duration"])  # not limited)
    else:
        forced = n if scale / IK_PER_PERIOD < IK_SPACING else 0
    if forced > MAX_IK_POSES:  # (aliased, the IK would see a platform at rest)
        problems.add(
            "trajectory.period" if own == "amplitude" else f"trajectory.{own}",
            period if own == "amplitude" else scale,
            f"a motion this fast (time scale {scale:.3g} s) over duration = {kw['duration']:g} "
            f"s needs {n} inverse-kinematics poses ({IK_PER_PERIOD} per period, so that the "
            f"drives follow the motion); at most {MAX_IK_POSES} (about 40 s of IK): use a "
            f"period of at least {kw['duration'] * IK_PER_PERIOD / (MAX_IK_POSES - 1):.3g} s "
            "or a shorter duration",
        )
    if len(problems) > n0:
        return None
    return spec


# largest trajectory amplitude by unit (PROPOSED): metres of platform travel and radians of
# tilt no parallel mechanism of this field comes near
MAX_AMPLITUDE = {"m": 100.0, "rad": 100.0}


def ik_poses(duration: float, period: float) -> int:
    """Number of inverse-kinematics poses of a periodic trajectory (`ik_count`)."""
    return ik_count(duration, period)


def _base_dir(source: str) -> Path:
    """The folder that a file's relative paths (a trajectory table) start from."""
    try:
        p = Path(source)
        return p.parent if p.is_file() else Path.cwd()
    except (OSError, ValueError):  # (a source that is no path: "<string>", too long, ...)
        return Path.cwd()


def _section(d: Mapping, name: str, problems: Problems, *, required: bool = False) -> dict | None:
    if name not in d:
        if required:
            problems.add(name, MISSING, f"required section [{name}] is missing")
            return None
        return {}
    return table_at(d[name], name, problems)


def _rk4_with_clearance(solver, clr, given: bool, limit: float, problems: Problems) -> None:
    """rk4 has a fixed step and no contact event location: with clearance joints the step
    must resolve every impact (a contact lasts ~1e-4 s with steel balls)."""
    if solver.method != "rk4" or not clr.joints or solver.step <= limit:
        return
    problems.add(
        "solver.step",
        solver.step if given else f"{solver.step} (the default)",
        f"'rk4' has a fixed step and does not locate contact events: with clearance joints "
        f"use step <= {limit:g} s (the shipped scenarios' impacts last ~1e-4 s; "
        "[checks] rk4_clearance_step), or an adaptive method (events located): "
        + ", ".join(repr(m) for m in ADAPTIVE),
    )


def _checks(t: dict, problems: Problems) -> ChecksSpec | None:
    n0, kw = len(problems), parse_table(t, CHECKS_FIELDS, "checks", problems)
    if len(problems) > n0:
        return None
    for warn, bad in (
        ("penetration_warning", "penetration_implausible"),
        ("energy_warning", "energy_implausible"),
    ):
        if kw[warn] > kw[bad]:
            problems.add(
                f"checks.{warn}",
                kw[warn],
                f"expected at most {bad} = {kw[bad]:g} (a warning comes before implausible)",
            )
    return ChecksSpec(**kw) if len(problems) == n0 else None


def scenario_from_dict(d: Mapping[str, object], *, source: str = "<dict>") -> Scenario:
    """Validate a scenario dict (as read from TOML); raise ScenarioError with all problems."""
    problems = Problems(source)
    if not isinstance(d, Mapping):
        raise ScenarioError(source, "(document)", d, "expected a table of sections")
    version = d.get("format_version", MISSING)
    if version is MISSING:
        problems.add("format_version", MISSING, f"required; this version reads {FORMAT_VERSION}")
    elif isinstance(version, bool) or version != FORMAT_VERSION:
        raise ScenarioError(
            source,
            "format_version",
            version,
            f"unknown format version; this version of clearance reads format_version = "
            f"{FORMAT_VERSION}",
        )
    for key, v in d.items():
        if key not in TOP_KEYS:
            problems.unknown(key, key, v, TOP_KEYS)

    meta = mech = traj = clr = solver = output = None
    kind = None
    if (t := _section(d, "scenario", problems, required=True)) is not None:
        n0, kw = len(problems), parse_table(t, SCENARIO_FIELDS, "scenario", problems)
        meta = ScenarioMeta(**kw) if len(problems) == n0 else None
    if (t := _section(d, "mechanism", problems, required=True)) is not None:
        mech, kind = _mechanism(t, problems, meta.name if meta is not None else "mechanism")
    if (t := _section(d, "trajectory", problems)) is not None:
        mtype = d["mechanism"].get("type") if isinstance(d.get("mechanism"), dict) else None
        base_dir = _base_dir(source)
        traj = _trajectory(t, kind, problems, mech, mtype, base_dir)
    if (t := _section(d, "clearance", problems)) is not None:
        clr = _clearance(t, kind, mech.params if mech is not None else None, problems)
    if (t := _section(d, "solver", problems)) is not None:
        n0, kw = len(problems), parse_table(t, SOLVER_FIELDS, "solver", problems)
        solver = SolverSpec(**kw) if len(problems) == n0 else None
    step_given = "step" in (t or {})
    if (t := _section(d, "output", problems)) is not None:
        n0, kw = len(problems), parse_table(t, OUTPUT_FIELDS, "output", problems)
        output = OutputSpec(**kw) if len(problems) == n0 else None
    checks = None
    if (t := _section(d, "checks", problems)) is not None:
        checks = _checks(t, problems)
    if solver is not None and clr is not None and checks is not None:
        _rk4_with_clearance(solver, clr, step_given, checks.rk4_clearance_step, problems)
    steady = None
    if "steady_state" in d and (t := _section(d, "steady_state", problems)) is not None:
        own = mech is not None and mech.type is MechanismType.GENERAL
        own = own and traj is not None and not traj.actuators
        steady, solver = parse_steady_state(t, traj, solver, own, problems)
    view = ViewSpec()
    if "view" in d and (t := _section(d, "view", problems)) is not None:
        view = parse_view(t, problems)
    wear = None
    if "wear" in d and (t := _section(d, "wear", problems)) is not None:
        wearable = {
            n: j
            for n, j in (clr.joints.items() if clr is not None else ())
            if isinstance(j, (Clearance, RevoluteClearance))
        }
        wear = parse_wear(t, wearable, problems)
        if wear is not None and traj is not None and wear.warmup >= traj.duration:
            problems.add(
                "wear.warmup",
                wear.warmup,
                f"expected less than the run's duration ({traj.duration:g} s, [trajectory])",
            )
    problems.raise_if_any()
    return Scenario(
        meta,  # type: ignore[arg-type]
        mech,  # type: ignore[arg-type]
        traj,  # type: ignore[arg-type]
        clr,  # type: ignore[arg-type]
        solver,  # type: ignore[arg-type]
        output,  # type: ignore[arg-type]
        FORMAT_VERSION,
        source,
        checks,  # type: ignore[arg-type]
        steady,
        view,  # type: ignore[arg-type]
        wear,
    )
