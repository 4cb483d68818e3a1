"""What a result file holds: output groups, the lean default and the opt-in extras.

A result file of the default 4UPS-UPU scenario with every channel of every body, row and
block is ~130 MB for 2 s of motion at 0.1 ms; what a paper uses fits in ~10 % of that. The
channels of a `Result` are therefore grouped, and a file holds the groups asked for, each
at the full output resolution:

=================  ===================================================================
group              data variables (see `clearance.io.dataset`)
=================  ===================================================================
frames             every body's position and euler_parameters at the frames a viewer
                   draws (`clearance view`, `animate`): a uniform subset of the samples
                   plus every sample near a contact event (`clearance.io.frames`), with
                   the mechanism's geometry in the group's `geometry` attribute
platform           position, euler_parameters, velocity, angular_velocity,
                   acceleration, angular_acceleration (world frame) of the *selected*
                   bodies (a scenario's platform); on the `body` dimension
bodies             the same for every body, plus the body-frame angular_velocity_body
                   and angular_acceleration_body the integrator uses (opt-in)
actuators          actuator_force
energy             energy_<term> (kinetic, potential, works, dissipation, residual)
clearance          every clearance joint's channels (layout.JOINT_COLUMNS), contact
                   flag, impact velocity, bristles, dissipation, peaks, the event log
contact_points     the channels of every contact point (layout.POINT_COLUMNS); default
                   only where a joint has several points (line contact), since a
                   one-point joint's point channels repeat the joint's
multipliers        multiplier, constraint_violation, constraint_violation_rate (opt-in)
reactions          reaction_force, reaction_moment (opt-in)
=================  ===================================================================

The stored groups are listed in each group's `outputs` attribute (JSON); the bodies that
are stored are the `body` coordinate. `"all"` means every group and every body.
"""

from __future__ import annotations

from collections.abc import Iterable

OUTPUTS: dict[str, str] = {
    "platform": "pose, velocity and acceleration of the platform body",
    "frames": "every body's pose at the frames a viewer draws (decimated, contacts kept)",
    "bodies": "pose, velocity and acceleration of every body",
    "actuators": "actuator forces",
    "energy": "energy terms and the energy-balance residual",
    "clearance": "every clearance joint's channels, contact state, event log and peaks",
    "contact_points": "the channels of every contact point",
    "multipliers": "Lagrange multipliers, constraint violation and its rate",
    "reactions": "joint and driver reaction forces and moments",
}
LEAN = ("platform", "frames", "actuators", "energy", "clearance")
OPT_IN = ("bodies", "contact_points", "multipliers", "reactions")
ALL = "all"


def check_outputs(names: Iterable[str], *, where: str = "outputs") -> tuple[str, ...]:
    """The names, validated (a ValueError names the unknown one and what is allowed)."""
    out = []
    for n in names:
        if n != ALL and n not in OUTPUTS:
            raise ValueError(
                f"{where}: unknown output {n!r}; allowed: {', '.join((*OUTPUTS, ALL))}"
            )
        if n not in out:
            out.append(n)
    return tuple(out)


def resolve_outputs(extra: Iterable[str] = (), *, several_points: bool = False) -> frozenset:
    """The groups a run writes: the lean default plus `extra` ("all": every group).

    several_points: some clearance joint has more than one contact point (its point
    channels carry what the joint's do not), so `contact_points` is written by default.
    """
    extra = check_outputs(extra)
    if ALL in extra:
        return frozenset(OUTPUTS)
    groups = set(LEAN) | set(extra)
    if several_points:
        groups.add("contact_points")
    return frozenset(groups)


__all__ = ["ALL", "LEAN", "OPT_IN", "OUTPUTS", "check_outputs", "resolve_outputs"]
