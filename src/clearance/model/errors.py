"""Errors raised while describing or compiling a mechanism.

Every message names the element, the field, the offending value and what is allowed, so that
a user reading a traceback of a model file knows what to change without reading our code.
"""

from __future__ import annotations

import math
import numbers


class ModelError(ValueError):
    """An invalid mechanism description (bad value, unknown or duplicate name)."""

    def __init__(self, element: str, field: str, value: object, allowed: str) -> None:
        self.element = element
        self.field = field
        self.value = value
        self.allowed = allowed
        super().__init__(f"{element}: field '{field}' = {value!r} is invalid; {allowed}")


class KinematicsError(RuntimeError):
    """Position/velocity analysis failed (no assembly, singular or redundant constraints)."""


def finite_real(x: object) -> bool:
    """Whether x is a finite real number: not a bool, not a string, and not an int too
    large for a float (math.isfinite(10**400) raises OverflowError). The one test of the
    validators of the model, the laws, the time functions and `simulate`."""
    if isinstance(x, bool) or not isinstance(x, numbers.Real):
        return False
    try:
        return math.isfinite(x)
    except OverflowError:
        return False
