"""Wear of spherical clearance joints (issue 16; docs/wear.md): a wear-depth map on a
spherical surface, Archard's law and the reachable depth the dynamics sees
(`clearance.wear.surface`), the socket wear of one run from its samples
(`clearance.wear.history.socket_wear`), and the prediction over many cycles with the
worn sockets fed back (`clearance.wear.predict`, `clearance wear`);
docs/notes/wear-literature.md has the background."""

from clearance.wear.surface import SphereWearMap, archard_hertz, hertz_conformal

__all__ = ["SphereWearMap", "archard_hertz", "hertz_conformal"]
