"""Figures from saved results (never simulates): see `clearance.plot.figures`."""

from clearance.plot.figures import (
    platform_motion,
    plot_actuator_forces,
    plot_all,
    plot_ball_trajectory,
    plot_contact_force,
    plot_journal_trajectory,
    plot_platform,
    plot_slider_offset,
    rotation_vector,
    save_figure,
    start_figures,
)

__all__ = [
    "platform_motion",
    "plot_actuator_forces",
    "plot_all",
    "plot_ball_trajectory",
    "plot_contact_force",
    "plot_journal_trajectory",
    "plot_slider_offset",
    "plot_platform",
    "rotation_vector",
    "save_figure",
    "start_figures",
]
