"""[wear]: the wear prediction of `clearance wear SCENARIO` (`clearance.wear.predict`).

    [wear]
    cycles = 1e6              # cycles to predict (one cycle: the run after warmup)
    update_factor = "auto"    # cycles per iteration, or "auto": each iteration deepens a
    max_step = 0.01           # socket by at most max_step x its clearance, and by at
    max_step_penetration = 1  # most this x the run's mean penetration (default: inf)
    warmup = 0.05             # [s] the start of each run not counted (default 0)
    cycle_time = 0.4          # [s] length of one cycle (default: the counted run)
    dt_out = 2e-5             # [s] output step of the wear runs (default 2e-5)

    [wear.joints.S_1]         # a spherical, revolute or cylindrical clearance joint
    coefficient = 1e-15       # Archard's k / H [m^2/N]; or k = ..., hardness = ... [Pa]
    grid = 64                 # cells per cube face of the socket's depth map (a bearing:
                              # 4 grid cells around each station, the same resolution)
    smoothing = 2.0           # the worn socket's smoothing radius [cells] (sockets only)
    length = 0.02             # [m] a bearing's contact length, only where its clearance
                              # has none (a planar joint)

The wear coefficient has no default: it depends on the materials, the lubrication and the
regime, and published values span orders of magnitude (docs/notes/wear-literature.md).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from clearance.model.clearance import RevoluteClearance
from clearance.scenario.errors import Problems
from clearance.scenario.fields import Field, parse_table, table_at

__all__ = ["JOINT_WEAR_FIELDS", "WEAR_FIELDS", "JointWear", "WearSettings", "parse_wear"]

WEAR_FIELDS = {
    "cycles": Field("positive", doc="cycles to predict"),
    "max_step": Field("positive", 0.01, doc="auto: largest depth per iteration / clearance"),
    "max_step_penetration": Field(
        "positive_inf", math.inf, doc="auto: largest depth per iteration / mean penetration"
    ),
    "max_factor": Field("positive", None, doc="auto: most cycles per iteration"),
    "warmup": Field("nonneg", 0.0, "s", "start of each run not counted"),
    "cycle_time": Field("positive", None, "s", "length of one cycle; default: the counted run"),
    "dt_out": Field("positive", 2e-5, "s", "output step of the wear runs"),
    "joints": Field(
        "table",
        doc="per spherical, revolute or cylindrical clearance joint: { coefficient | k, "
        "hardness, grid, smoothing, length }",
    ),
}
JOINT_WEAR_FIELDS = {
    "coefficient": Field("positive", None, "m2 N-1", "Archard's k / H"),
    "k": Field("positive", None, "", "Archard's dimensionless wear coefficient"),
    "hardness": Field("positive", None, "Pa", "hardness H of the softer surface"),
    "grid": Field("count", 64, doc="cells per cube face of the depth map"),
    "smoothing": Field(
        "positive", 2.0, doc="smoothing radius of a worn socket's gap [cells]", minimum=1.0
    ),
    "length": Field(
        "positive", None, "m", "a bearing's contact length, where its clearance has none"
    ),
}


@dataclass(frozen=True)
class JointWear:
    """Wear settings of one clearance joint: the socket of a spherical one, the bearing of a
    revolute or cylindrical one.

    coefficient: k_w = k / H [m^2/N] (Archard's dimensionless k over the softer surface's
    hardness H); grid: cells per cube face of a socket's depth map (6 grid^2 cells), and
    4 grid cells around each station of a bearing (the same angular resolution);
    smoothing: a worn socket's smoothing radius in cells (`SphereWearMap.socket_wear`; a
    bearing's field is a cubic B-spline over its cells); length: a bearing's contact
    length [m] for its cells' areas (None: the clearance's `length`)."""

    coefficient: float
    grid: int = 64
    smoothing: float = 2.0
    length: float | None = None


@dataclass(frozen=True)
class WearSettings:
    """The loop: total `cycles`; update_factor: cycles per iteration (None: adaptive, each
    iteration at most `max_step` x c and `max_step_penetration` x the run's force-weighted
    mean penetration deeper, and at most `max_factor` cycles); warmup [s]:
    the start of each run not counted (the ball settling from its initial placement);
    cycle_time [s]: the length of one cycle (None: the counted part of the run is one);
    dt_out [s]: the runs' output step (the wear is summed over the output samples: on the
    4UPS-UPU the sampled F_N |v| dt differs from the kernel's step-by-step friction work
    by 3e-4 and 2e-5 at 20 us, 1.8 and 4.6 % at the scenario's 100 us)."""

    joints: Mapping[str, JointWear]
    cycles: float
    update_factor: float | None = None
    max_step: float = 0.01
    max_factor: float = math.inf
    warmup: float = 0.0
    cycle_time: float | None = None
    dt_out: float = 2e-5
    max_step_penetration: float = math.inf

    def to_dict(self) -> dict:
        """The plain [wear] table."""
        d: dict = {
            "cycles": self.cycles,
            "update_factor": "auto" if self.update_factor is None else self.update_factor,
            "max_step": self.max_step,
            "warmup": self.warmup,
            "dt_out": self.dt_out,
            "joints": {
                k: {f: x for f, x in vars(v).items() if x is not None}
                for k, v in self.joints.items()
            },
        }
        if math.isfinite(self.max_factor):
            d["max_factor"] = self.max_factor
        if math.isfinite(self.max_step_penetration):
            d["max_step_penetration"] = self.max_step_penetration
        if self.cycle_time is not None:
            d["cycle_time"] = self.cycle_time
        return d


def parse_wear(t: dict, wearable: Mapping, problems: Problems) -> WearSettings | None:
    """The WearSettings of a [wear] table (wearable: the scenario's clearance joints that
    can wear, name -> clearance: spherical, revolute and cylindrical ones), or None with
    the problems reported."""
    n0 = len(problems)
    kw = parse_table(t, WEAR_FIELDS, "wear", problems, extra=("update_factor",))
    uf = t.get("update_factor", "auto")
    if uf != "auto" and not (
        isinstance(uf, (int, float)) and not isinstance(uf, bool) and math.isfinite(uf) and uf > 0
    ):
        problems.add("wear.update_factor", uf, "expected 'auto' or a finite number of cycles > 0")
    joints: dict = {}
    raw = t.get("joints")
    if raw is not None and (tb := table_at(raw, "wear.joints", problems)) is not None:
        if not tb:
            problems.add("wear.joints", tb, "expected at least one joint")
        for name, body in tb.items():
            path = f"wear.joints.{name}"
            if name not in wearable:
                problems.add(
                    path,
                    name,
                    "expected a spherical, revolute or cylindrical clearance joint of "
                    "[clearance.joints]: " + (", ".join(wearable) or "(none)"),
                )
                continue
            if (b := table_at(body, path, problems)) is None:
                continue
            n1 = len(problems)
            v = parse_table(b, JOINT_WEAR_FIELDS, path, problems)
            if len(problems) > n1:
                continue
            coef = v.get("coefficient")
            if coef is None and v.get("k") is not None and v.get("hardness") is not None:
                coef = v["k"] / v["hardness"]
            elif coef is not None and ("k" in b or "hardness" in b):
                problems.add(
                    f"{path}.coefficient", coef, "give coefficient or k and hardness, not both"
                )
            if coef is None:
                problems.add(
                    f"{path}.coefficient",
                    "(missing)",
                    "expected coefficient = k / H [m^2/N], or k and hardness [Pa]",
                )
                continue
            if v["grid"] > 512:
                problems.add(f"{path}.grid", v["grid"], "expected an integer from 1 to 512")
                continue
            bearing = isinstance(wearable[name], RevoluteClearance)
            length = v.get("length")
            own = getattr(wearable[name], "length", None) if bearing else None
            if not bearing and "length" in b:
                problems.add(f"{path}.length", b["length"], "expected none: only bearings have one")
                continue
            if bearing and "smoothing" in b:
                problems.add(
                    f"{path}.smoothing",
                    b["smoothing"],
                    "expected none: a bearing's worn surface is a cubic B-spline over its cells",
                )
                continue
            if bearing and length is not None and own is not None:
                problems.add(
                    f"{path}.length",
                    length,
                    f"expected none: the clearance has its length ({own:g} m), which the "
                    "stations and the wear share",
                )
                continue
            if bearing and length is None and own is None:
                problems.add(
                    f"{path}.length",
                    "(missing)",
                    "expected the bearing's contact length [m] (the clearance has no length)",
                )
                continue
            joints[name] = JointWear(
                float(coef),
                int(v["grid"]),
                float(v["smoothing"]),
                None if length is None else float(length),
            )
    if len(problems) > n0:
        return None
    return WearSettings(
        joints,
        float(kw["cycles"]),
        None if uf == "auto" else float(uf),
        float(kw["max_step"]),
        math.inf if kw.get("max_factor") is None else float(kw["max_factor"]),
        float(kw["warmup"]),
        None if kw.get("cycle_time") is None else float(kw["cycle_time"]),
        float(kw["dt_out"]),
        float(kw["max_step_penetration"]),
    )
