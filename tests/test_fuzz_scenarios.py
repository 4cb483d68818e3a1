"""A fuzzer of the scenario format (issue 11): mutated copies of the shipped scenarios.

Each example takes a shipped file's dict and changes one to three things: a value
replaced (NaN, inf, huge, tiny, negative, zero, wrong types), a value scaled (relations
between fields), a key removed, or an unknown key added. Validation must then either
accept a physically valid scenario or refuse it with problems that each name the file,
the field and the value: never another exception (a traceback for the user).
"""

from __future__ import annotations

import copy
import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import clearance as cl
from clearance.scenario import ScenarioError, default_scenario_path, scenario_from_dict
from clearance.scenario.toml_io import read_toml

SOURCE = "fuzz.toml"
BASES = {name: read_toml(default_scenario_path(name)) for name in ("ups_upu", "sps_cu")}
BAD = [
    math.nan,
    math.inf,
    -math.inf,
    -1.0,
    0.0,
    1e300,
    -1e300,
    1e-300,
    10**30,
    -3,
    "abc",
    "",
    True,
    [],
    [1.0, 2.0],
    {"a": 1},
]


def leaves(d: object, prefix: tuple = ()) -> list[tuple]:
    """Key paths of every non-table value of a nested dict."""
    if isinstance(d, dict):
        return [p for k, v in d.items() for p in leaves(v, (*prefix, k))]
    return [prefix]


def parent(d: dict, path: tuple) -> dict:
    for k in path[:-1]:
        d = d[k]
    return d


@st.composite
def mutants(draw):
    name = draw(st.sampled_from(sorted(BASES)))
    d = copy.deepcopy(BASES[name])
    for _ in range(draw(st.integers(1, 3))):
        paths = leaves(d)
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        box, key = parent(d, path), path[-1]
        how = draw(st.sampled_from(["replace", "scale", "remove", "unknown"]))
        if how == "replace":
            box[key] = draw(st.sampled_from(BAD))
        elif (
            how == "scale" and isinstance(box[key], (int, float)) and not isinstance(box[key], bool)
        ):
            box[key] = box[key] * draw(st.sampled_from([1e-18, 1e-6, 1e-3, -1.0, 1e3, 1e6]))
        elif how == "remove":
            del box[key]
        else:
            box[f"{key}x"] = 1.0  # a near miss of a real key
    return d


def physically_valid(s) -> None:
    """What an accepted scenario must hold (relations included)."""
    assert s.trajectory.duration >= 1e-9 and math.isfinite(s.trajectory.duration)
    assert 0 < s.solver.rtol and math.isfinite(s.solver.rtol)
    for j in s.clearance.joints.values():
        c, r = j.radial_clearance, getattr(j, "ball_radius", getattr(j, "journal_radius", None))
        assert 0 < c and math.isfinite(c)
        if r is not None:
            assert c < r
        for m in (getattr(j, a) for a in dir(j) if a.endswith("_material")):
            if isinstance(m, cl.Material):
                assert m.E > 0 and math.isfinite(m.E) and -1 < m.nu <= 0.5
        f = getattr(j, "friction", None)
        if isinstance(f, cl.LuGre):
            assert f.mu_s >= f.mu_c > 0
        n = getattr(j, "normal", None)
        e = getattr(n, "restitution", None)
        if e is not None:
            assert 0 < e <= 1
    # what `check` accepts, `run` builds: the mechanisms, and the contact laws encoded for
    # the joints' geometry (a 1e-20 m clearance once passed check, then failed the run
    # with an internal field name: R_socket)
    from clearance.scenario import BUILDERS, build_mechanisms

    if s.mechanism.type in BUILDERS:
        _, clr, _ = build_mechanisms(s)
        cl.compile_mechanism(clr)


@settings(
    max_examples=300,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,  # the same examples on every run: a failure reproduces
)
@given(mutants())
def test_mutated_scenarios_are_refused_clearly_or_valid(d):
    try:
        s = scenario_from_dict(d, source=SOURCE)
    except ScenarioError as e:
        assert e.problems
        for p in e.problems:
            assert p.file == SOURCE and isinstance(p.field, str) and p.field
            line = str(p)
            assert line.startswith(f"{SOURCE}: field '{p.field}' = ") and "invalid" in line
        return
    physically_valid(s)
