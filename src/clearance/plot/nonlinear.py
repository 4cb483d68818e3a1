"""Figures of a nonlinear-dynamics analysis (`clearance.nonlinear.analyze`): phase
portraits with the Poincare points, Poincare maps, spectra with the drive frequency and its
harmonics marked, a spectrogram, Rosenstein's divergence curve, and bifurcation diagrams."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure

from clearance.nonlinear.analyze import Analysis, rate_name
from clearance.nonlinear.spectra import harmonics, spectrogram
from clearance.plot.figures import STYLE, save_figure

__all__ = [
    "analysis_figures",
    "bifurcation_figure",
    "phase_portrait_figure",
    "poincare_figure",
    "spectrum_figure",
]


def _fig(rows: int, cols: int, w: float = 3.4, h: float = 2.8) -> Figure:
    return Figure(figsize=(w * cols, h * rows), layout="constrained")


def phase_portrait_figure(a: Analysis) -> Figure:
    """Per channel: the steady orbit (x, dx/dt) with the Poincare points on it."""
    n = len(a.channels)
    cols = min(n, 3)
    rows = -(-n // cols)
    with mpl.rc_context(STYLE):
        fig = _fig(rows, cols)
        axs = np.atleast_1d(fig.subplots(rows, cols)).ravel()
        i0 = int(a.steady.strobe(a.t.size)[0])
        strobe = a.steady.strobe(a.t.size)
        for ax, ch in zip(axs, a.channels, strict=False):
            x, v = a.series[ch], a.rates[ch]
            ax.plot(x[i0:], v[i0:], lw=0.5, color="C0", alpha=0.7)
            ax.plot(x[strobe], v[strobe], "o", ms=3, color="C3", label="Poincare")
            ax.set_xlabel(ch)
            ax.set_ylabel(rate_name(ch))
        for ax in axs[n:]:
            ax.set_visible(False)
        fig.suptitle(
            f"phase portraits after {a.steady.transient_periods} periods: {a.classification.kind}"
        )
    return fig


def poincare_figure(a: Analysis) -> Figure:
    """Stroboscopic Poincare maps: each channel against its rate, and consecutive pairs of
    channels (e.g. a joint's eccentricity x against y)."""
    pairs = [(ch, None) for ch in a.channels]
    pairs += [(a.channels[k], a.channels[k + 1]) for k in range(1, len(a.channels) - 1, 2)]
    n = len(pairs)
    cols = min(n, 3)
    rows = -(-n // cols)
    strobe = a.steady.strobe(a.t.size)
    with mpl.rc_context(STYLE):
        fig = _fig(rows, cols)
        axs = np.atleast_1d(fig.subplots(rows, cols)).ravel()
        for ax, (c1, c2) in zip(axs, pairs, strict=False):
            x = a.series[c1][strobe]
            y = a.rates[c1][strobe] if c2 is None else a.series[c2][strobe]
            ax.plot(x, y, ".", ms=3, color="C3")
            ax.set_xlabel(c1)
            ax.set_ylabel(rate_name(c1) if c2 is None else c2)
            ax.ticklabel_format(style="sci", scilimits=(-3, 3))
        for ax in axs[n:]:
            ax.set_visible(False)
        fig.suptitle(
            f"Poincare maps (once per {a.steady.period:g} s): {a.classification.kind}, "
            f"{a.classification.distinct} distinct of {a.classification.points} points"
        )
    return fig


def spectrum_figure(a: Analysis) -> Figure:
    """Amplitude spectra (log scale) with the drive frequency's harmonics dashed and the
    dominant lines marked, and the first channel's spectrogram."""
    n = len(a.channels)
    f0 = 1.0 / a.steady.period
    with mpl.rc_context(STYLE):
        fig = _fig(n + 1, 1, w=7.0, h=2.0)
        axs = fig.subplots(n + 1, 1)
        for ax, ch in zip(axs, a.channels, strict=False):
            sp = a.spectra[ch]
            fmax = min(sp["f"][-1], 20 * f0)
            keep = sp["f"] <= fmax
            ax.semilogy(sp["f"][keep], np.maximum(sp["A"][keep], 1e-300), lw=0.7, color="C0")
            for h in harmonics(f0, fmax):
                ax.axvline(h, color="0.6", lw=0.5, ls="--")
            for p in a.peaks.get(ch, [])[:5]:
                ax.plot(p.frequency, p.amplitude, "v", color="C3", ms=4)
            ax.set_ylabel(ch, fontsize="small")
            top = np.max(sp["A"][keep][1:]) if keep.sum() > 1 else 1.0
            ax.set_ylim(top * 1e-5, top * 3)
        axs[n - 1].set_xlabel("frequency [Hz] (dashed: harmonics of the drive)")
        ch = a.channels[0]
        i0 = int(a.steady.strobe(a.t.size)[0])
        dt = float(a.t[1] - a.t[0])
        x = a.series[ch][i0:]
        f, ts, S = spectrogram(
            x, dt, nperseg=max(16, min(x.size // 4, 4 * a.steady.samples_per_period))
        )
        keep = f <= min(f[-1], 20 * f0)
        ax = axs[n]
        ax.pcolormesh(ts + a.t[i0], f[keep], np.log10(S[keep] + 1e-300), shading="auto")
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"f [Hz], {ch}", fontsize="small")
    return fig


def analysis_figures(
    a: Analysis, out_dir: str | os.PathLike, stem: str, formats: Sequence[str] = ("png",)
) -> list[Path]:
    """Write the phase portraits, Poincare maps, spectra and (when estimated) Rosenstein's
    divergence curve as out_dir/stem_<name>.<fmt>."""
    figs = {
        "phase_portraits": phase_portrait_figure(a),
        "poincare": poincare_figure(a),
        "spectra": spectrum_figure(a),
    }
    if a.lyapunov is not None:
        with mpl.rc_context(STYLE):
            fig = _fig(1, 1, w=4.5)
            ax = fig.subplots()
            d = a.lyapunov
            ax.plot(d.time, d.log_divergence, lw=0.8)
            s0, s1 = d.fit
            slope_line = d.log_divergence[s0] + d.exponent * (d.time[s0:s1] - d.time[s0])
            ax.plot(
                d.time[s0:s1], slope_line, "--", color="C3", label=f"slope {d.exponent:.4g} 1/s"
            )
            ax.set_xlabel("time ahead [s]")
            ax.set_ylabel("<ln divergence>")
            ax.legend()
        figs["divergence"] = fig
    out: list[Path] = []
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    for name, fig in figs.items():
        out += save_figure(fig, out_dir, f"{stem}_{name}", formats)
    return out


def bifurcation_figure(
    parameter: np.ndarray,
    points: Sequence[np.ndarray],
    *,
    parameter_name: str,
    channel: str,
    kinds: Sequence[str] | None = None,
) -> Figure:
    """Bifurcation diagram: the Poincare points of `channel` of each case against the
    parameter (one column of dots per case), the case's classification below."""
    with mpl.rc_context(STYLE):
        fig = _fig(1, 1, w=6.5, h=3.6)
        ax = fig.subplots()
        for p, pts in zip(parameter, points, strict=True):
            pts = np.asarray(pts)
            ax.plot(np.full(pts.size, p), pts, ",", color="k", alpha=0.8)
            ax.plot(np.full(pts.size, p), pts, ".", ms=1.5, color="k")
        ax.set_xlabel(parameter_name)
        ax.set_ylabel(f"{channel} (Poincare)")
        ax.ticklabel_format(style="sci", scilimits=(-3, 3))
        if kinds is not None:
            for p, k in zip(parameter, kinds, strict=True):
                ax.annotate(
                    k.replace("period-", "P")
                    .replace("quasi-periodic", "QP")
                    .replace("chaotic", "C")
                    .replace("undetermined", "?"),
                    (p, 0),
                    xycoords=("data", "axes fraction"),
                    xytext=(0, 2),
                    textcoords="offset points",
                    ha="center",
                    fontsize="x-small",
                    color="C3",
                )
    return fig
