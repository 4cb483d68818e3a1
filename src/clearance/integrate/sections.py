"""`Section`: a Poincare section for `simulate`, g(y) = value crossed in a direction, where
g is a state coordinate of a body (or any linear combination of the state: `weights`).
The loops locate each crossing on the dense output of the accepted steps
(`accept.section`) and keep the state there: `Result.section_time`, `Result.section_state`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from clearance.model.errors import ModelError

__all__ = ["COORDINATES", "Section"]

#: state coordinates of a body: position (world), Euler parameters, velocity (world),
#: angular velocity (body frame, omega')
COORDINATES = {
    "x": ("q", 0),
    "y": ("q", 1),
    "z": ("q", 2),
    "e0": ("q", 3),
    "e1": ("q", 4),
    "e2": ("q", 5),
    "e3": ("q", 6),
    "vx": ("v", 0),
    "vy": ("v", 1),
    "vz": ("v", 2),
    "wx": ("v", 3),
    "wy": ("v", 4),
    "wz": ("v", 5),
}


@dataclass(frozen=True)
class Section:
    """The section `coordinate` of `body` = value (x, y, z [m], vx, vy, vz [m/s] in the
    world frame; wx, wy, wz [rad/s] in the body frame; e0..e3), crossed upward (direction
    +1), downward (-1) or both (0); or, with `weights` ((ny,) array), weights . y = value.
    max_crossings: states kept (the count goes on)."""

    body: str | None = None
    coordinate: str = "z"
    value: float = 0.0
    direction: int = 1
    weights: np.ndarray | None = None
    max_crossings: int = 100_000

    def __post_init__(self) -> None:
        if self.direction not in (-1, 0, 1):
            raise ModelError("Section", "direction", self.direction, "allowed: -1, 0, +1")
        if not (isinstance(self.value, (int, float)) and np.isfinite(self.value)):
            raise ModelError("Section", "value", self.value, "expected a finite number")
        if (self.body is None) == (self.weights is None):
            raise ModelError(
                "Section", "body", self.body, "give a body (and coordinate) or weights"
            )
        if self.body is not None and self.coordinate not in COORDINATES:
            raise ModelError(
                "Section", "coordinate", self.coordinate, f"allowed: {', '.join(COORDINATES)}"
            )
        n = self.max_crossings
        if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and n >= 1):
            raise ModelError("Section", "max_crossings", n, "expected an integer >= 1")

    def weights_for(self, c) -> np.ndarray:
        """The (ny,) weights of g for the compiled mechanism c."""
        if self.weights is not None:
            w = np.asarray(self.weights, dtype=float)
            if w.shape != (c.ny,) or not np.all(np.isfinite(w)) or not np.any(w):
                raise ModelError(
                    "Section", "weights", w.shape, f"expected {c.ny} finite numbers, not all 0"
                )
            return w.copy()
        bodies = list(c.body_names)
        if self.body not in bodies:
            raise ModelError("Section", "body", self.body, f"a moving body: {bodies}")
        b = bodies.index(self.body)
        part, k = COORDINATES[self.coordinate]
        w = np.zeros(c.ny)
        w[7 * b + k if part == "q" else c.layout.iv + 6 * b + k] = 1.0
        return w

    def label(self) -> str:
        where = f"{self.body}.{self.coordinate}" if self.body is not None else "weights . y"
        way = "both ways" if self.direction == 0 else ("upward", "downward")[self.direction < 0]
        return f"{where} = {self.value:g}, {way}"
