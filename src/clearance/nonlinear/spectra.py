"""Spectra of sampled signals: amplitude spectrum, power spectral density (Welch),
spectrogram, dominant frequencies, and the harmonics of a drive frequency.

All take a uniformly sampled signal `x` (n,) and its sample interval `dt` [s]; frequencies
are in Hz. The amplitude spectrum is scaled so that a sinusoid a sin(2 pi f t + phi) whose
frequency falls on a bin shows a peak of height a (single-sided, window's coherent gain
removed); `dominant_frequencies` interpolates between bins and, by default, refines the
peaks by a least-squares fit of the sinusoids to the signal, which recovers the frequencies
and amplitudes of a sum of sinusoids to the precision of the data.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize, signal

from clearance.model.errors import ModelError

__all__ = [
    "Peak",
    "amplitude_spectrum",
    "dominant_frequencies",
    "harmonics",
    "power_spectral_density",
    "spectrogram",
]


def _signal(who: str, x: object, dt: object, *, min_samples: int = 8) -> tuple[np.ndarray, float]:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1 or a.size < min_samples:
        raise ModelError(
            who, "x", getattr(a, "shape", x), f"expected a 1-D signal of >= {min_samples} samples"
        )
    if not np.all(np.isfinite(a)):
        i = int(np.flatnonzero(~np.isfinite(a))[0])
        raise ModelError(who, "x", a[i], f"expected finite samples (sample {i} is not)")
    d = float(dt) if isinstance(dt, (int, float, np.floating, np.integer)) else np.nan
    if not (np.isfinite(d) and d > 0):
        raise ModelError(who, "dt", dt, "expected the sample interval [s], a finite number > 0")
    return a, d


def amplitude_spectrum(
    x: object, dt: float, *, window: str = "hann", detrend: bool = True, pad: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """(f [Hz], amplitude [units of x]): single-sided amplitude spectrum of x.

    window: a scipy.signal window name ("hann", "flattop" for the most accurate peak
    heights between bins, "boxcar" for none); detrend: remove the mean first; pad: zero
    padding factor (>= 1; interpolates the spectrum between bins)."""
    a, d = _signal("amplitude_spectrum", x, dt)
    if not (isinstance(pad, (int, np.integer)) and 1 <= pad <= 64):
        raise ModelError("amplitude_spectrum", "pad", pad, "expected an integer in [1, 64]")
    n = a.size
    if detrend:
        a = a - a.mean()
    w = signal.get_window(window, n, fftbins=False)
    spec = np.fft.rfft(a * w, n=pad * n)
    amp = np.abs(spec) * 2.0 / w.sum()
    amp[0] /= 2.0  # the mean is not doubled
    if (pad * n) % 2 == 0:
        amp[-1] /= 2.0  # nor the Nyquist bin
    return np.fft.rfftfreq(pad * n, d), amp


def power_spectral_density(
    x: object, dt: float, *, nperseg: int | None = None, window: str = "hann"
) -> tuple[np.ndarray, np.ndarray]:
    """(f [Hz], PSD [units^2/Hz]) by Welch's method (scipy.signal.welch, one-sided,
    segments of nperseg samples, default min(n, 4096), half overlapping). Integrating the
    PSD over f gives the variance of x."""
    a, d = _signal("power_spectral_density", x, dt)
    nps = min(a.size, 4096) if nperseg is None else nperseg
    if not (isinstance(nps, (int, np.integer)) and 8 <= nps <= a.size):
        raise ModelError(
            "power_spectral_density", "nperseg", nperseg, f"expected an integer in [8, {a.size}]"
        )
    return signal.welch(a, fs=1.0 / d, window=window, nperseg=int(nps), detrend="constant")


def spectrogram(
    x: object, dt: float, *, nperseg: int | None = None, window: str = "hann"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(f [Hz], t [s] of the segment centres, PSD (f, t) [units^2/Hz]):
    scipy.signal.spectrogram with segments of nperseg samples (default n // 8, at least
    16), overlapping by 7/8."""
    a, d = _signal("spectrogram", x, dt, min_samples=16)
    nps = max(16, a.size // 8) if nperseg is None else nperseg
    if not (isinstance(nps, (int, np.integer)) and 8 <= nps <= a.size):
        raise ModelError("spectrogram", "nperseg", nperseg, f"expected an integer in [8, {a.size}]")
    return signal.spectrogram(
        a, fs=1.0 / d, window=window, nperseg=int(nps), noverlap=int(nps) * 7 // 8
    )


@dataclass(frozen=True)
class Peak:
    """A spectral line: frequency [Hz], amplitude [units of x], phase [rad] of
    amplitude sin(2 pi frequency t + phase) with t counted from the first sample."""

    frequency: float
    amplitude: float
    phase: float


def dominant_frequencies(
    x: object,
    dt: float,
    *,
    count: int = 5,
    min_relative: float = 0.01,
    refine: bool = True,
) -> list[Peak]:
    """The `count` largest spectral lines of x, largest first, those at least min_relative
    of the largest one.

    Peaks are picked on a Blackman-Harris spectrum padded 8x and located between bins by a
    parabola through the log amplitudes; refine: then fit the sum of these sinusoids and a
    constant to x by least squares (scipy.optimize.least_squares), which makes frequencies
    and amplitudes exact for a signal that is such a sum. Lines closer than four bins
    (4/(n dt)) are not resolved."""
    a, d = _signal("dominant_frequencies", x, dt)
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise ModelError("dominant_frequencies", "count", count, "expected an integer >= 1")
    pad = 8
    # Blackman-Harris: side lobes at -92 dB (Hann's at -31 dB were picked as lines next to
    # a strong one), main lobe +-4 bins
    f, amp = amplitude_spectrum(a, d, pad=pad, window="blackmanharris")
    df = f[1] - f[0]
    resolution = 1.0 / (a.size * d)
    idx, _ = signal.find_peaks(amp, distance=4 * pad)
    idx = idx[idx > 4 * pad]  # not the mean's lobe
    if idx.size == 0:
        return []
    idx = idx[np.argsort(amp[idx])[::-1]]
    idx = idx[amp[idx] >= min_relative * amp[idx[0]]][:count]
    peaks = []
    for i in idx:
        fi, ai = f[i], amp[i]
        if 0 < i < amp.size - 1 and min(amp[i - 1], amp[i + 1]) > 0:
            la, lb, lc = np.log(amp[i - 1 : i + 2])
            den = la - 2 * lb + lc
            if den < 0:
                p = 0.5 * (la - lc) / den
                fi = f[i] + p * df
                ai = float(np.exp(lb - 0.25 * (la - lc) * p))
        peaks.append([fi, ai, 0.0])
    if refine:
        peaks = _refine(a, d, np.array(peaks), resolution)
    return [Peak(float(p[0]), float(abs(p[1])), float(p[2])) for p in peaks]


def _refine(x: np.ndarray, dt: float, peaks: np.ndarray, resolution: float) -> np.ndarray:
    """Least-squares fit of sum_k A_k sin(2 pi f_k t + phi_k) + c to x, starting from the
    spectral estimates (phases from a linear fit at the estimated frequencies)."""
    t = dt * np.arange(x.size)
    k = len(peaks)
    basis = np.column_stack(
        [g(2 * np.pi * fk * t) for fk in peaks[:, 0] for g in (np.sin, np.cos)] + [np.ones_like(t)]
    )
    coef = np.linalg.lstsq(basis, x, rcond=None)[0]
    s, c = coef[0 : 2 * k : 2], coef[1 : 2 * k : 2]
    p0 = np.concatenate([peaks[:, 0], s, c, coef[-1:]])

    def resid(p):
        fr, sa, ca = p[:k], p[k : 2 * k], p[2 * k : 3 * k]
        ph = 2 * np.pi * np.outer(t, fr)
        return np.sin(ph) @ sa + np.cos(ph) @ ca + p[-1] - x

    lo = np.concatenate([peaks[:, 0] - resolution, np.full(2 * k + 1, -np.inf)])
    hi = np.concatenate([peaks[:, 0] + resolution, np.full(2 * k + 1, np.inf)])
    p0[:k] = np.clip(p0[:k], lo[:k] + 1e-15, hi[:k] - 1e-15)
    sol = optimize.least_squares(resid, p0, bounds=(lo, hi), x_scale="jac", xtol=1e-15, ftol=1e-15)
    p = sol.x
    fr, sa, ca = p[:k], p[k : 2 * k], p[2 * k : 3 * k]
    out = np.column_stack([fr, np.hypot(sa, ca), np.arctan2(ca, sa)])
    return out[np.argsort(out[:, 1])[::-1]]


def harmonics(f0: float, f_max: float, *, subharmonics: int = 1) -> np.ndarray:
    """Multiples k f0 / subharmonics up to f_max (k = 1, 2, ...): the drive frequency's
    harmonics (subharmonics = 2, 3, ...: also the fractions of a period-n response)."""
    if not (np.isfinite(f0) and f0 > 0):
        raise ModelError("harmonics", "f0", f0, "expected a frequency > 0 [Hz]")
    step = f0 / int(subharmonics)
    return step * np.arange(1, int(np.floor(f_max / step + 1e-9)) + 1)
