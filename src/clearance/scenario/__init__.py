"""Scenario files: a versioned TOML description of one simulation (format version 1).

    s = load_scenario(default_scenario_path("ups_upu"))     # or any user file
    ideal, clearance, info = build_mechanisms(s)
    text = scenario_to_toml(s)                               # round trip, for result attributes
    s2 = with_overrides(s, {"clearance.joints.S_1.radial_clearance": 0.2e-3})

The format is documented in docs/scenario-format.md. Every problem in a file is reported as
a `ScenarioError` naming the file, the dotted field, the value and what is allowed.
"""

from clearance.scenario.build import BUILDERS, BuildInfo, build_mechanisms
from clearance.scenario.errors import ScenarioError
from clearance.scenario.paths import get_path, set_path, split_path, with_overrides
from clearance.scenario.schema import (
    FORMAT_VERSION,
    MECHANISMS,
    ClearanceSpec,
    InitialPlacement,
    JointSpec,
    MechanismKind,
    MechanismSpec,
    MechanismType,
    OutputSpec,
    Scenario,
    ScenarioMeta,
    SolverSpec,
    TrajectoryShape,
    TrajectorySpec,
    scenario_from_dict,
)
from clearance.scenario.serialize import scenario_to_dict
from clearance.scenario.toml_io import (
    default_scenario_path,
    default_scenarios,
    library,
    library_path,
    load_scenario,
    loads_scenario,
    scenario_to_toml,
)

__all__ = [
    "BUILDERS",
    "FORMAT_VERSION",
    "MECHANISMS",
    "BuildInfo",
    "ClearanceSpec",
    "InitialPlacement",
    "JointSpec",
    "MechanismKind",
    "MechanismSpec",
    "MechanismType",
    "OutputSpec",
    "Scenario",
    "ScenarioError",
    "ScenarioMeta",
    "SolverSpec",
    "TrajectoryShape",
    "TrajectorySpec",
    "build_mechanisms",
    "default_scenario_path",
    "default_scenarios",
    "get_path",
    "library",
    "library_path",
    "load_scenario",
    "loads_scenario",
    "scenario_from_dict",
    "scenario_to_dict",
    "scenario_to_toml",
    "set_path",
    "split_path",
    "with_overrides",
]
