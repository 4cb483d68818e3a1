"""Wear of clearance joints (issue 16, in progress): a wear-depth map on a spherical
surface and Archard's law spread with a Hertz patch (`clearance.wear.surface`), the
socket wear of a spherical clearance joint from a run's samples
(`clearance.wear.history.socket_wear`). Not yet fed back into the dynamics;
docs/notes/wear-literature.md has the background."""

from clearance.wear.surface import SphereWearMap, archard_hertz, hertz_conformal

__all__ = ["SphereWearMap", "archard_hertz", "hertz_conformal"]
