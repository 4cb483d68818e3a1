"""Parallel mechanisms from leg types: a fixed base, a moving platform, legs given by their
joint strings read from the base ("UPS", "RSS", "PRS", ...).

`legs` holds the leg shapes, their axes, frames and names (the conventions, documented
there and in docs/parallel-mechanisms.md); `mechanism` the platform, the assembly of the
legs into a `Mechanism` and the mobility check.
"""

from clearance.parallel.legs import Leg, Link
from clearance.parallel.mechanism import (
    Attachments,
    Mobility,
    ParallelMechanism,
    Platform,
    circle,
    legs,
)

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
