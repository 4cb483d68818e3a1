"""clearance: dynamics of spatial mechanisms and parallel robots with clearance joints.

Public API (re-exports only). Pipeline: describe (`Mechanism` of bodies, markers, joints,
drivers, forces) -> `compile_mechanism` -> `simulate` -> `Result`.
"""

from clearance import _kernel_cache

# the compiled-kernel cache is keyed by the kernel sources (see _kernel_cache); every module
# with a kernel is imported below, while the cache location is set
_prev_cache_dir = _kernel_cache.configure()

from clearance.analysis.assembly import (
    acceleration_analysis,
    assemble,
    evaluate_rows,
    rank_check,
    velocity_analysis,
)
from clearance.compile.compiled import Compiled, compile_mechanism
from clearance.integrate.methods import METHODS as _METHODS
from clearance.integrate.methods import method_loop as _method_loop
from clearance.integrate.sections import Section
from clearance.integrate.simulate import (
    Interrupted,
    contact_state,
    initial_state,
    latch_contacts,
    scipy_rhs,
    simulate,
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
    OffsetDriver,
    OrientationDriver,
    PointForce,
    PositionDriver,
    Prismatic,
    PrismaticDriver,
    Revolute,
    RevoluteDriver,
    Spherical,
    SpringDamper,
    TimeFunction,
    Torque,
    Universal,
    triad_from_axis,
)
from clearance.model.clearance import (
    Clearance,
    PrismaticClearance,
    RevoluteClearance,
    SphericalClearance,
    UniversalClearance,
)
from clearance.model.contact_laws import (
    STEEL,
    Coulomb,
    Flores,
    Gonthier,
    HerbertMcWhannell,
    Hertz,
    HuGuo,
    HuntCrossley,
    Impact,
    Johnson,
    KelvinVoigt,
    LankaraniNikravesh,
    LeeWang,
    Liu,
    LuGre,
    Material,
    NoFriction,
    NonlinearStiffness,
    Pereira,
    Stribeck,
    Threlfall,
    ZhiyingQishao,
)
from clearance.model.functions import Polynomial, Ramp, Sinusoid, Tabulated
from clearance.model.wear import BearingWear, SocketWear
from clearance.parallel import (
    Leg,
    Link,
    Mobility,
    ParallelMechanism,
    Platform,
    circle,
    legs,
)
from clearance.store.result import Result

__version__ = "0.1.0"

__all__ = [
    "Compiled",
    "compile_mechanism",
    "Result",
    "initial_state",
    "scipy_rhs",
    "simulate",
    "Section",
    "Interrupted",
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
    "OffsetDriver",
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
    "RevoluteDriver",
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
    "Clearance",
    "SphericalClearance",
    "SocketWear",
    "BearingWear",
    "RevoluteClearance",
    "PrismaticClearance",
    "UniversalClearance",
    "contact_state",
    "latch_contacts",
    "Material",
    "STEEL",
    "Hertz",
    "KelvinVoigt",
    "HuntCrossley",
    "LankaraniNikravesh",
    "Flores",
    "Gonthier",
    "HuGuo",
    "HerbertMcWhannell",
    "LeeWang",
    "ZhiyingQishao",
    "Impact",
    "NonlinearStiffness",
    "Johnson",
    "Pereira",
    "Liu",
    "NoFriction",
    "Coulomb",
    "Threlfall",
    "Stribeck",
    "LuGre",
    "ParallelMechanism",
    "Platform",
    "Leg",
    "Link",
    "Mobility",
    "circle",
    "legs",
    "__version__",
]

for _name in _METHODS:  # the integration loops are imported by name: here, under the cache
    _method_loop(_name)
_kernel_cache.restore(_prev_cache_dir)
