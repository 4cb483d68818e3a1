"""Describe: bodies, markers, joints, drivers, forces, time functions, the Mechanism."""

from clearance.kinds import JointType
from clearance.model.bodies import GROUND, Body, Marker, triad_from_axis
from clearance.model.drivers import (
    DistanceDriver,
    OffsetDriver,
    OrientationDriver,
    PositionDriver,
    PrismaticDriver,
    RevoluteDriver,
)
from clearance.model.errors import KinematicsError, ModelError
from clearance.model.forces import PointForce, SpringDamper, Torque
from clearance.model.functions import Constant, TimeFunction
from clearance.model.joints import (
    Cylindrical,
    Fixed,
    Joint,
    Prismatic,
    Revolute,
    Spherical,
    Universal,
)
from clearance.model.mechanism import Mechanism

__all__ = [
    "GROUND",
    "Body",
    "Marker",
    "triad_from_axis",
    "DistanceDriver",
    "OffsetDriver",
    "OrientationDriver",
    "PositionDriver",
    "PrismaticDriver",
    "RevoluteDriver",
    "KinematicsError",
    "ModelError",
    "PointForce",
    "SpringDamper",
    "Torque",
    "Constant",
    "TimeFunction",
    "Cylindrical",
    "Fixed",
    "Joint",
    "JointType",
    "Prismatic",
    "Revolute",
    "Spherical",
    "Universal",
    "Mechanism",
]
