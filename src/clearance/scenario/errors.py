"""`ScenarioError`: what is wrong in a scenario file, and where.

Every problem names the FILE, the dotted FIELD path inside the scenario (the same path a
study uses to vary a parameter, e.g. `clearance.joints.S_1.radial_clearance`), the VALUE
found and what is ALLOWED:

    ups_upu.toml: field 'clearance.joints.S_1.radial_clearance' = -0.0003 is invalid;
    expected a finite number > 0 [m]

All problems of one file are collected (`Problems`) and raised together as one
`ScenarioError` whose `problems` holds one `ScenarioError` per problem and whose message has
one line per problem.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

from clearance.model.errors import ModelError

__all__ = ["MISSING", "Problems", "ScenarioError", "did_you_mean"]


class _Missing:
    """Marker of a required field that is absent (shown as <missing> in messages)."""

    def __repr__(self) -> str:
        return "<missing>"


MISSING = _Missing()


class ScenarioError(ModelError):
    """An invalid scenario: file, dotted field path, value, what is allowed.

    `problems`: all problems found in the file (this error alone when there is one);
    `lines()`: one message line per problem.
    """

    def __init__(self, file: str, field: str, value: object, allowed: str) -> None:
        super().__init__(file, field, value, allowed)
        self.file = file
        self.problems: tuple[ScenarioError, ...] = (self,)

    @classmethod
    def from_problems(cls, problems: Iterable[ScenarioError]) -> ScenarioError:
        """One error carrying several problems (message: one line per problem)."""
        items = tuple(p for e in problems for p in e.problems)
        if not items:
            raise ValueError("no problems to report")
        first = items[0]
        err = cls(first.file, first.field, first.value, first.allowed)
        err.problems = items
        err.args = ("\n".join(str(p.args[0]) for p in items),)
        return err

    def lines(self) -> list[str]:
        """One message per problem."""
        return [str(p.args[0]) for p in self.problems]


def did_you_mean(key: object, allowed: Iterable[str]) -> str:
    """' did you mean 'x'?' for the closest allowed name, or ''."""
    if not isinstance(key, str):
        return ""
    close = difflib.get_close_matches(key, list(allowed), n=1, cutoff=0.6)
    if not close:
        low = {a.lower(): a for a in allowed}
        close = [low[key.lower()]] if key.lower() in low else []
    return f" did you mean '{close[0]}'?" if close else ""


class Problems:
    """Collects the problems of one file; `raise_if_any` raises them together."""

    def __init__(self, file: str) -> None:
        self.file = file
        self.items: list[ScenarioError] = []

    def add(self, field: str, value: object, allowed: str) -> None:
        self.items.append(ScenarioError(self.file, field, value, allowed))

    def unknown(self, field: str, key: str, value: object, allowed: Iterable[str]) -> None:
        """An unknown key, with a suggestion and the list of allowed keys."""
        allowed = list(allowed)
        self.add(
            field,
            value,
            f"unknown key '{key}';{did_you_mean(key, allowed)} allowed: {', '.join(allowed)}",
        )

    def __bool__(self) -> bool:
        return bool(self.items)

    def __len__(self) -> int:
        return len(self.items)

    def raise_if_any(self) -> None:
        if self.items:
            raise ScenarioError.from_problems(self.items)
