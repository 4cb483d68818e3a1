"""Figures of a wear prediction (`clearance.wear.predict`): per socket the depth map
unwrapped (longitude and latitude in the socket's marker frame) and drawn on the sphere;
per bearing the map unwrapped (angle against axial position) and the worn profile of
each station; and the history against cycles (worn volume, maximum depth and effective
clearance, peak contact force, platform deviation)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from clearance.wear.bearing import BearingWearMap

__all__ = ["wear_figures"]


def _lonlat(nlon: int, nlat: int):
    lon = np.linspace(-np.pi, np.pi, nlon)
    lat = np.linspace(-np.pi / 2, np.pi / 2, nlat)
    LON, LAT = np.meshgrid(lon, lat)
    u = np.stack([np.cos(LAT) * np.cos(LON), np.cos(LAT) * np.sin(LON), np.sin(LAT)], axis=-1)
    return lon, lat, u


def _bearing_figures(plt, j: str, m: BearingWearMap, cycles: float):
    """A bearing's map unwrapped (angle about the bearing axis against the stations'
    axial positions) and its worn profile per station (polar, the depth exaggerated)."""
    z = (np.arange(m.stations) + 0.5) / m.stations * m.length - 0.5 * m.length
    h = m.depth * 1e6
    fig, ax = plt.subplots(figsize=(8, 3.6), layout="constrained")
    edges_th = np.linspace(0.0, 360.0, m.n + 1)
    edges_z = np.linspace(-0.5, 0.5, m.stations + 1) * m.length * 1e3
    im = ax.pcolormesh(edges_th, edges_z, h, cmap="magma_r", shading="flat")
    ax.set(
        xlabel="angle about the bearing axis from its f axis [deg]",
        ylabel="axial position [mm]",
        title=f"{j}: bearing wear depth after {cycles:.4g} cycles",
    )
    fig.colorbar(im, ax=ax, label="depth [um]")
    yield fig, f"wear_map_{j}"
    fig = plt.figure(figsize=(5.5, 5), layout="constrained")
    ax = fig.add_subplot(projection="polar")
    top = max(float(h.max()), 1e-300)
    closed = np.r_[m.angles, m.angles[:1]]
    for k in range(m.stations):
        r = np.r_[h[k], h[k, :1]]
        ax.plot(closed, 1.0 + 0.5 * r / top, label=f"z = {z[k] * 1e3:.3g} mm")
    ax.plot(closed, np.ones_like(closed), "k:", lw=0.8, label="unworn")
    ax.set_rticks([])
    ax.set_title(
        f"{j}: worn bearing profile per station\n(radius 1: unworn; the deepest, "
        f"{top:.3g} um, drawn as 0.5)"
    )
    if m.stations <= 8:
        ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.15, -0.12))
    yield fig, f"wear_surface_{j}"


def wear_figures(state, out: Path, fmt: str = "png") -> list[Path]:
    """Write the figures of a WearLoop into `out`; return their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from clearance.io.files import atomic_path

    files = []

    def save(fig, name):
        path = out / f"{name}.{fmt}"
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=fmt, dpi=120)
        plt.close(fig)
        files.append(path)

    for j, m in state.maps.items():
        if isinstance(m, BearingWearMap):
            for fig, name in _bearing_figures(plt, j, m, state.cycles):
                save(fig, name)
            continue
        lon, lat, u = _lonlat(361, 181)
        h = m.depth_at(u) * 1e6
        fig, ax = plt.subplots(figsize=(8, 4.2), layout="constrained")
        im = ax.pcolormesh(np.degrees(lon), np.degrees(lat), h, cmap="magma_r", shading="auto")
        ax.set(
            xlabel="longitude in the socket frame [deg]",
            ylabel="latitude [deg]",
            title=f"{j}: socket wear depth after {state.cycles:.4g} cycles",
            aspect="equal",
        )
        fig.colorbar(im, ax=ax, label="depth [um]", shrink=0.8)
        save(fig, f"wear_map_{j}")

        lon, lat, u = _lonlat(121, 61)
        h = m.depth_at(u)
        top = max(float(h.max()), 1e-300)
        fig = plt.figure(figsize=(5.5, 5), layout="constrained")
        ax = fig.add_subplot(projection="3d")
        colours = plt.get_cmap("magma_r")(h / top)
        ax.plot_surface(
            u[..., 0],
            u[..., 1],
            u[..., 2],
            facecolors=colours,
            rstride=1,
            cstride=1,
            linewidth=0,
            antialiased=False,
            shade=False,
        )
        ax.set(
            xlabel="x", ylabel="y", zlabel="z", title=f"{j}: wear depth (max {top * 1e6:.3g} um)"
        )
        ax.set_box_aspect((1, 1, 1))
        save(fig, f"wear_surface_{j}")

    ds = state.history()
    cyc = ds["cycles"].values  # cycles at each run
    fig, axs = plt.subplots(2, 2, figsize=(10, 7), layout="constrained", sharex=True)
    for j in ds["joint"].values:
        sel = ds.sel(joint=j)
        axs[0, 0].plot(cyc, sel["volume"] * 1e9, "o-", label=str(j))
        axs[0, 1].plot(cyc, sel["max_depth"] * 1e6, "o-", label=f"{j} max depth")
        axs[0, 1].plot(cyc, sel["effective_clearance"] * 1e6, "s--", label=f"{j} c + max depth")
        axs[1, 0].plot(cyc, sel["peak_contact_force"], "o-", label=str(j))
    axs[1, 1].plot(cyc, ds["platform_deviation"] * 1e6, "o-")
    axs[0, 0].set(ylabel="worn volume [mm^3]")
    axs[0, 1].set(ylabel="[um]")
    axs[1, 0].set(ylabel="peak contact force [N]", xlabel="cycles")
    axs[1, 1].set(ylabel="platform RMS deviation [um]", xlabel="cycles")
    for ax in axs.flat:
        ax.grid(alpha=0.3)
    for ax in (axs[0, 0], axs[0, 1], axs[1, 0]):
        ax.legend(fontsize=8)
    fig.suptitle("Wear against cycles (each point: one run of the worn mechanism)")
    save(fig, "wear_history")
    return files
