"""Figures of a wear prediction (`clearance.wear.predict`): per socket the depth map
unwrapped (longitude and latitude in the socket's marker frame) and drawn on the sphere,
and the history against cycles (worn volume, maximum depth and effective clearance, peak
contact force, platform deviation)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["wear_figures"]


def _lonlat(nlon: int, nlat: int):
    lon = np.linspace(-np.pi, np.pi, nlon)
    lat = np.linspace(-np.pi / 2, np.pi / 2, nlat)
    LON, LAT = np.meshgrid(lon, lat)
    u = np.stack([np.cos(LAT) * np.cos(LON), np.cos(LAT) * np.sin(LON), np.sin(LAT)], axis=-1)
    return lon, lat, u


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
