"""Time functions f(t) with exact f_dot and f_ddot (placeholder; being completed)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from clearance.model.errors import ModelError


class FnKind(IntEnum):
    CONSTANT = 0


@dataclass(frozen=True)
class TimeFunction:
    """Base class of time functions used by drivers and applied forces."""

    def derivatives(self, t: float) -> tuple[float, float, float]:
        raise NotImplementedError

    def __call__(self, t: float) -> float:
        return self.derivatives(t)[0]

    def encode(self) -> tuple[int, np.ndarray]:
        raise NotImplementedError


@dataclass(frozen=True)
class Constant(TimeFunction):
    value: float = 0.0

    def derivatives(self, t: float) -> tuple[float, float, float]:
        return (float(self.value), 0.0, 0.0)

    def encode(self) -> tuple[int, np.ndarray]:
        return int(FnKind.CONSTANT), np.array([float(self.value)])


def as_function(x: object, *, owner: str = "function", field: str = "function") -> TimeFunction:
    if isinstance(x, TimeFunction):
        return x
    if isinstance(x, (int, float)) and np.isfinite(x):
        return Constant(float(x))
    raise ModelError(owner, field, x, "expected a number or a TimeFunction")
