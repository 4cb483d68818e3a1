"""clearance: dynamics of spatial mechanisms and parallel robots with clearance joints.

Public API (re-exports only). Pipeline: describe (`Mechanism` of bodies, markers, joints,
drivers, forces) -> `compile_mechanism` -> `simulate` -> `Result`.
"""

from clearance.compile.compiled import Compiled, compile_mechanism
from clearance.integrate.result import Result
from clearance.integrate.simulate import initial_state, scipy_rhs, simulate
from clearance.kinematics.analysis import (
    acceleration_analysis,
    assemble,
    evaluate_rows,
    rank_check,
    velocity_analysis,
)
from clearance.model import (
    GROUND,
    Body,
    Constant,
    Cylindrical,
    DistanceDriver,
    Fixed,
    KinematicsError,
    Marker,
    Mechanism,
    ModelError,
    OrientationDriver,
    PointForce,
    PositionDriver,
    Prismatic,
    PrismaticDriver,
    Revolute,
    Spherical,
    SpringDamper,
    TimeFunction,
    Torque,
    Universal,
    triad_from_axis,
)
from clearance.model.functions import Polynomial, Ramp, Sinusoid, Tabulated

__version__ = "0.1.0"

__all__ = [
    "Compiled",
    "compile_mechanism",
    "Result",
    "initial_state",
    "scipy_rhs",
    "simulate",
    "acceleration_analysis",
    "assemble",
    "evaluate_rows",
    "rank_check",
    "velocity_analysis",
    "GROUND",
    "Body",
    "Constant",
    "Cylindrical",
    "DistanceDriver",
    "Fixed",
    "KinematicsError",
    "Marker",
    "Mechanism",
    "ModelError",
    "OrientationDriver",
    "PointForce",
    "PositionDriver",
    "Prismatic",
    "PrismaticDriver",
    "Revolute",
    "Spherical",
    "SpringDamper",
    "TimeFunction",
    "Torque",
    "Universal",
    "triad_from_axis",
    "Polynomial",
    "Ramp",
    "Sinusoid",
    "Tabulated",
    "__version__",
]
