"""Seeing a result move: a self-contained 3-D viewer in the browser (`write_viewer`,
`clearance view`) and videos for talks (`clearance animate`), drawn from a result file's
frames (`clearance.io.frames`) and geometry (`clearance.io.geometry`)."""

from clearance.view.scene import Scene, SceneError, load_scene

__all__ = ["Scene", "SceneError", "load_scene"]
