"""[view]: how `clearance view` (and the run's report) draws the mechanism.

    [view]
    magnification = 20        # clearances drawn x20 (default: automatic, docs/viewer.md)
    frames = 2000             # uniform frames kept for the viewer in each run's group
                              # (the 'frames' output; contact events are added to them)

    [view.bodies.platform]    # per body, every key optional
    shape = "plate"           # auto, rod, plate, sphere or none
    colour = "#4a6fa5"
    radius = 0.01             # [m] rod radius (sphere: half its radius)
    thickness = 0.02          # [m] plate thickness

Body names are checked against the mechanism before the runs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from clearance.scenario.errors import Problems
from clearance.scenario.fields import Field, parse_table, table_at

__all__ = ["BODY_VIEW_FIELDS", "VIEW_FIELDS", "ViewSpec", "parse_view"]

SHAPES = ("auto", "rod", "plate", "sphere", "none")
VIEW_FIELDS = {
    "magnification": Field(
        "positive", None, doc="factor the clearances are drawn with; default: automatic"
    ),
    "frames": Field("count", 2000, doc="uniform frames kept for the viewer per run"),
    "bodies": Field("table", None, doc="per body: { shape, colour, radius, thickness }"),
}
BODY_VIEW_FIELDS = {
    "shape": Field("choice", "auto", choices=SHAPES, doc="how the body is drawn"),
    "colour": Field("text", None, doc="#rrggbb"),
    "radius": Field("positive", None, "m", "rod radius"),
    "thickness": Field("positive", None, "m", "plate thickness"),
}
_COLOUR = re.compile(r"^#[0-9a-fA-F]{6}$")


@dataclass(frozen=True)
class ViewSpec:
    """A validated [view]: magnification (None: automatic), frames, bodies {name: {...}}
    with only the keys given."""

    magnification: float | None = None
    frames: int = 2000
    bodies: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The plain table (for the result file's `view` attribute and the TOML)."""
        d: dict = {"frames": self.frames}
        if self.magnification is not None:
            d["magnification"] = self.magnification
        if self.bodies:
            d["bodies"] = {k: dict(v) for k, v in self.bodies.items()}
        return d


def parse_view(t: dict, problems: Problems) -> ViewSpec | None:
    """The ViewSpec of a [view] table, or None with the problems reported."""
    n0 = len(problems)
    kw = parse_table(t, VIEW_FIELDS, "view", problems)
    bodies: dict = {}
    raw = t.get("bodies")
    if raw is not None and (tb := table_at(raw, "view.bodies", problems)) is not None:
        for name, body in tb.items():
            path = f"view.bodies.{name}"
            if (b := table_at(body, path, problems)) is None:
                continue
            vals = parse_table(b, BODY_VIEW_FIELDS, path, problems)
            colour = vals.get("colour")
            if colour is not None and not _COLOUR.match(str(colour)):
                problems.add(f"{path}.colour", colour, "expected a colour '#rrggbb'")
            bodies[name] = {k: v for k, v in vals.items() if k in b}
    if len(problems) > n0:
        return None
    return ViewSpec(kw["magnification"], kw["frames"], bodies)
