"""`analyze`: the nonlinear-dynamics analysis of a result file (or dataset): stroboscopic
Poincare points, section crossings, phase portraits, spectra, Rosenstein's Lyapunov
estimate, the 0-1 test and a classification with its evidence; saved as NetCDF.

Channels are named after the file's variables with their indices in brackets, in the
order of the variable's dimensions after time: `position[platform,z]`,
`velocity[platform,z]`, `eccentricity[S_1,x]`, `contact_force[S_1]`,
`actuator_force[drive_1]`; `eccentricity[S_1,norm]` is the length of a vector channel.
A channel's rate is the matching velocity (position -> velocity, ...) where the file has
it, else the derivative of a cubic spline through the samples.

Stroboscopic samples need a run over whole periods whose output grid contains the
stroboscopic times (`[steady_state]` in the scenario, recorded in the file's steady_*
attributes); a file without them is analysed with period=... only if the period is a
whole multiple of its output interval (the samples are then exact too), otherwise refused.
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from clearance.model.errors import ModelError
from clearance.nonlinear.chaos import LyapunovEstimate, rosenstein
from clearance.nonlinear.classify import Classification, classify
from clearance.nonlinear.poincare import (
    _hermite,
    section_crossings,
    spline_rate,
    strobe_indices,
)
from clearance.nonlinear.spectra import (
    amplitude_spectrum,
    dominant_frequencies,
    power_spectral_density,
)

__all__ = [
    "Analysis",
    "Steady",
    "analyze",
    "channel",
    "default_channels",
    "response_of_run",
    "steady_of",
]

_RATE_OF = {
    "position": "velocity",
    "velocity": "acceleration",
    "angular_velocity": "angular_acceleration",
    "penetration": "penetration_rate",
}
_SPEC = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\[([^\]]*)\])?\s*$")


def channel(ds: xr.Dataset, spec: str) -> tuple[np.ndarray, np.ndarray | None]:
    """(values (time,), rate (time,) or None) of a channel `var[i, j]` of a run dataset."""
    m = _SPEC.match(spec) if isinstance(spec, str) else None
    if m is None:
        raise ModelError("analyze", "channel", spec, "expected 'variable[index, ...]'")
    var, idx = m.group(1), [s.strip() for s in (m.group(2) or "").split(",") if s.strip()]
    if var not in ds.data_vars or "time" not in ds[var].dims:
        have = sorted(v for v in ds.data_vars if "time" in ds[v].dims)
        raise ModelError("analyze", "channel", spec, f"no time history {var!r}; have: {have}")
    da = ds[var]
    dims = [d for d in da.dims if d != "time"]
    norm = bool(idx) and idx[-1] == "norm" and len(idx) == len(dims)
    if len(idx) != len(dims):
        labels = ", ".join(f"{d}: {list(map(str, ds[d].values))}" for d in dims)
        raise ModelError(
            "analyze", "channel", spec, f"{var} needs {len(dims)} index(es) ({labels})"
        )

    def pick(a: xr.DataArray) -> np.ndarray:
        sel = {}
        for d, i in zip(dims, idx, strict=True):
            if norm and d == dims[-1]:
                continue
            values = list(map(str, ds[d].values))
            if i not in values:
                raise ModelError("analyze", "channel", spec, f"{d} {i!r} not in {values}")
            sel[d] = values.index(i)
        x = a.isel(sel).values
        return np.linalg.norm(x, axis=-1) if norm else np.asarray(x, dtype=float)

    x = pick(da)
    rate = None
    if var in _RATE_OF and _RATE_OF[var] in ds.data_vars and not norm:
        rate = pick(ds[_RATE_OF[var]])
    return x, rate


def _rate(t: np.ndarray, x: np.ndarray, rate: np.ndarray | None) -> np.ndarray:
    return rate if rate is not None else spline_rate(t, x)


def rate_name(spec: str) -> str:
    """The name of a channel's rate: velocity[...] for position[...], else d/dt spec."""
    m = _SPEC.match(spec)
    if m and m.group(1) in _RATE_OF and not spec.rstrip("] ").endswith("norm"):
        return spec.replace(m.group(1), _RATE_OF[m.group(1)], 1)
    return f"d/dt {spec}"


def default_channels(ds: xr.Dataset) -> list[str]:
    """The platform's (first body's) z and, per clearance joint, its eccentricity x and y
    in the socket frame."""
    out = []
    if "position" in ds.data_vars and ds.sizes.get("body", 0):
        out.append(f"position[{ds['body'].values[0]},z]")
    if "eccentricity" in ds.data_vars:
        for j in map(str, ds["clearance"].values):
            out += [f"eccentricity[{j},x]", f"eccentricity[{j},y]"]
    if not out:
        raise ModelError("analyze", "channels", None, "the file has no platform or clearance")
    return out


@dataclass(frozen=True)
class Steady:
    """The steady-state grid of a run: period [s], samples_per_period, transient_periods,
    phase (fraction), and where it came from."""

    period: float
    samples_per_period: int
    transient_periods: int
    phase: float = 0.0
    source: str = "file"

    def strobe(self, n: int) -> np.ndarray:
        return strobe_indices(n, self.samples_per_period, self.transient_periods, self.phase)


def steady_of(
    attrs: Mapping, t: np.ndarray, *, period: float | None = None, transient: int | None = None
) -> Steady:
    """The steady-state grid from the file's steady_* attributes, or from `period` (which
    must then be a whole multiple of a uniform output interval)."""
    if period is None and "steady_period" in attrs:
        st = Steady(
            float(attrs["steady_period"]),
            int(attrs["steady_samples_per_period"]),
            int(attrs["steady_transient_periods"]),
            float(attrs.get("steady_phase", 0.0)),
        )
    else:
        if period is None:
            raise ModelError(
                "analyze",
                "period",
                None,
                "the file records no steady state ([steady_state] in the scenario): give the "
                "drive period",
            )
        dt = np.diff(t)
        if dt.size == 0 or np.ptp(dt) > 1e-9 * dt.mean():
            raise ModelError("analyze", "file", "time", "expected a uniform output grid")
        m = period / dt.mean()
        if not (round(m) >= 1 and abs(m - round(m)) < 1e-6):
            raise ModelError(
                "analyze",
                "period",
                period,
                f"not a whole multiple of the output interval {dt.mean():g} s: the "
                "stroboscopic samples would be interpolated, not exact; rerun with "
                "[steady_state] (clearance.scenario.steady)",
            )
        st = Steady(float(period), int(round(m)), 0, 0.0, "option")
    if transient is not None:
        st = Steady(st.period, st.samples_per_period, int(transient), st.phase, st.source)
    if st.strobe(t.size).size < 2:
        raise ModelError(
            "analyze",
            "transient_periods",
            st.transient_periods,
            f"leaves fewer than 2 periods of the run's {t.size // st.samples_per_period}",
        )
    return st


@dataclass
class Analysis:
    """What `analyze` found: the steady grid, the Poincare points (strobe (n, channels)),
    section crossings, spectra, Rosenstein's estimate, the 0-1 test, the classification,
    and the dominant lines per channel."""

    channels: list[str]
    steady: Steady
    strobe_times: np.ndarray
    strobe: np.ndarray
    classification: Classification
    peaks: dict = field(default_factory=dict)
    spectra: dict = field(default_factory=dict)
    section: dict | None = None
    lyapunov: object | None = None
    zero_one: float | None = None
    t: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    series: dict = field(default_factory=dict, repr=False)
    rates: dict = field(default_factory=dict, repr=False)

    def table(self) -> list[tuple[str, str]]:
        """(quantity, value) rows of the summary."""
        c = self.classification
        f0 = 1.0 / self.steady.period
        rows = [
            ("response", c.kind),
            ("drive period", f"{self.steady.period:g} s ({f0:.4g} Hz)"),
            (
                "Poincare points",
                f"{self.strobe.shape[0]}, after {self.steady.transient_periods} transient periods",
            ),
            ("distinct Poincare points", f"{c.distinct} of {c.points} (tol {c.tol:.3g})"),
        ]
        if self.zero_one is not None:
            rows.append(("0-1 test K", f"{self.zero_one:.3f}"))
        if self.lyapunov is not None:
            rows.append(
                ("Lyapunov (Rosenstein)", f"{self.lyapunov.exponent:.4g} 1/s, {self.channels[0]}")
            )
        for ch, pk in self.peaks.items():
            lines = ", ".join(f"{p.frequency:.4g} Hz ({p.frequency / f0:.3g} f)" for p in pk[:4])
            rows.append((f"dominant {ch}", lines or "-"))
        if self.section is not None:
            rows.append(
                ("section crossings", f"{self.section['times'].size} of {self.section['spec']}")
            )
        return rows

    def to_dataset(self) -> xr.Dataset:
        """The analysis as one dataset (dims point, channel, frequency, crossing, lag)."""
        c = self.classification
        ds = xr.Dataset(
            {
                "poincare": (("point", "channel"), self.strobe),
                "poincare_time": (("point",), self.strobe_times),
            },
            coords={"channel": self.channels},
        )
        ds["poincare"].attrs.update(long_name="stroboscopic Poincare points", units="mixed")
        ds["poincare_time"].attrs.update(units="s", long_name="stroboscopic times")
        if self.spectra:
            f = next(iter(self.spectra.values()))["f"]
            ds = ds.assign_coords(frequency=("frequency", f))
            ds["amplitude_spectrum"] = (
                ("frequency", "channel"),
                np.column_stack([self.spectra[ch]["A"] for ch in self.channels]),
            )
            ds["amplitude_spectrum"].attrs.update(units="mixed", long_name="amplitude spectrum")
            fw = next(iter(self.spectra.values()))["f_psd"]
            ds = ds.assign_coords(frequency_psd=("frequency_psd", fw))
            ds["psd"] = (
                ("frequency_psd", "channel"),
                np.column_stack([self.spectra[ch]["P"] for ch in self.channels]),
            )
            ds["psd"].attrs.update(units="mixed", long_name="power spectral density (Welch)")
        if self.section is not None:
            ds["section_time"] = (("crossing",), self.section["times"])
            ds["section_time"].attrs.update(units="s", long_name=self.section["spec"])
            ds["section_points"] = (
                ("crossing", "channel"),
                np.column_stack([self.section["values"][ch] for ch in self.channels]),
            )
            ds["section_points"].attrs.update(units="mixed", long_name="section crossings")
        if self.lyapunov is not None:
            ds = ds.assign_coords(lag_time=("lag", self.lyapunov.time))
            ds["log_divergence"] = (("lag",), self.lyapunov.log_divergence)
        ds.attrs.update(
            classification=c.kind,
            period_n=-1 if c.period is None else int(c.period),
            evidence=json.dumps(list(c.reasons)),
            drive_period=self.steady.period,
            transient_periods=self.steady.transient_periods,
            samples_per_period=self.steady.samples_per_period,
            zero_one_K=np.nan if self.zero_one is None else self.zero_one,
            lyapunov_rosenstein=np.nan if self.lyapunov is None else self.lyapunov.exponent,
            dominant_frequencies=json.dumps(
                {ch: [[p.frequency, p.amplitude] for p in pk] for ch, pk in self.peaks.items()}
            ),
        )
        return ds


def analyze(
    source: str | Path | xr.Dataset,
    *,
    group: str = "clearance",
    channels: Sequence[str] | None = None,
    period: float | None = None,
    transient_periods: int | None = None,
    section: tuple[str, float, int] | None = None,
    tol: float = 1e-3,
    lyapunov: bool = True,
    max_period: int = 32,
) -> Analysis:
    """Analyse the steady state of a run (a result file's `group`, or a dataset with the
    file's attributes): Poincare points of `channels` (default `default_channels`) once per
    period, their recurrence (tolerance tol x each channel's range over the steady part),
    the 0-1 test on the Poincare points of the channel that spreads most relative to its
    range (>= 100 periods), Rosenstein's
    estimate from the first channel's steady samples (lyapunov), amplitude spectra and
    Welch PSDs with the dominant lines, and a section (channel, value, direction) located
    on the samples with the channel's rate. Classification: `clearance.nonlinear.classify`.
    """
    attrs: dict = {}
    if isinstance(source, xr.Dataset):
        ds = source
        attrs = dict(ds.attrs)
    else:
        from clearance.io.dataset import load_results

        rf = load_results(source)
        if group not in rf:
            raise ModelError("analyze", "group", group, f"the file has {list(rf)}")
        ds = rf[group]
        attrs = {**rf.attrs, **ds.attrs}
    t = np.asarray(ds["time"].values, dtype=float)
    st = steady_of(attrs, t, period=period, transient=transient_periods)
    chans = list(channels) if channels else default_channels(ds)
    series, rates = {}, {}
    for ch in chans:
        x, r = channel(ds, ch)
        series[ch], rates[ch] = x, _rate(t, x, r)
    idx = st.strobe(t.size)
    steady = np.arange(idx[0], idx[-1])  # whole periods (the spectra's lines on bins)
    P = np.column_stack([series[ch][idx] for ch in chans])
    scale = np.array([_scale(series[ch][steady]) for ch in chans])
    lyap = None
    # Rosenstein's estimate needs many mean periods of data (its Theiler window and
    # horizon are several of them): only from 50 periods on
    if lyapunov and steady.size >= 50 * st.samples_per_period:
        try:
            lyap = rosenstein(series[chans[0]][steady], float(t[1] - t[0]))
        except ModelError:
            lyap = None
    # the run's own two-trajectory exponent ([steady_state] lyapunov_periods), if any
    benettin = None
    if "lyapunov_exponent" in attrs:
        benettin = LyapunovEstimate(
            float(attrs["lyapunov_exponent"]),
            float(attrs.get("lyapunov_standard_error", np.nan)),
            np.zeros(0),
            np.zeros(0),
        )
    dt = float(t[1] - t[0])
    peaks, spectra = {}, {}
    for ch in chans:
        x = series[ch][steady]
        f, A = amplitude_spectrum(x, dt)
        fw, Pw = power_spectral_density(x, dt, nperseg=min(x.size, 8 * st.samples_per_period))
        spectra[ch] = {"f": f, "A": A, "f_psd": fw, "P": Pw}
        # lines 4 bins apart are resolved: the drive's harmonics need >= 8 periods
        if idx.size >= 9:
            peaks[ch] = dominant_frequencies(x, dt, count=5, refine=x.size <= 200_000)
    cls = classify(
        P / scale,
        tol=tol,
        max_period=max_period,
        peaks=peaks.get(chans[0], ()),
        drive_frequency=1.0 / st.period,
        zero_one=True,  # (>= 100 points, on the most spreading channel, unless they recur)
        lyapunov=benettin,
    )
    K = cls.zero_one
    if lyap is not None and not lyap.diverges:
        cls = dataclasses.replace(
            cls,
            reasons=(
                *cls.reasons,
                "Rosenstein: no exponential divergence (the neighbours' separation grows "
                "less than 10x)",
            ),
        )
    ok = attrs.get("success", 1)
    if not (ok is True or (isinstance(ok, (int, np.integer)) and ok)):
        cls = dataclasses.replace(
            cls,
            kind="undetermined",
            reasons=(
                f"the run stopped early ({attrs.get('message', '')}): not a steady state",
                *cls.reasons,
            ),
        )
    sec = None
    if section is None and "section_time" in ds.data_vars and ds.sizes.get("crossing", 0):
        sec = _file_section(ds, chans, t, series, rates, steady[0])
    if section is not None:
        spec, value, direction = section
        if spec not in series:
            x, r = channel(ds, spec)
            series[spec], rates[spec] = x, _rate(t, x, r)
        times, vals = section_crossings(
            t[steady],
            series[spec][steady],
            rates[spec][steady],
            value=float(value),
            direction=int(direction),
            others={ch: (series[ch][steady], rates[ch][steady]) for ch in chans},
        )
        sec = {
            "spec": f"{spec} = {value:g}, "
            + ("both ways" if direction == 0 else ("upward", "downward")[direction < 0]),
            "times": times,
            "values": vals,
        }
    return Analysis(chans, st, t[idx], P, cls, peaks, spectra, sec, lyap, K, t, series, rates)


def _file_section(ds, chans, t, series, rates, i0) -> dict:
    """The section crossings the run located in its loop (`section_time`, after the
    transient): positions and velocities of the file's bodies exactly as the integrator
    had them there, other channels by the cubic Hermite at those exact times."""
    ts = np.asarray(ds["section_time"].values, dtype=float)
    keep = ts >= t[i0]
    ts = ts[keep]
    j = np.clip(np.searchsorted(t, ts) - 1, 0, t.size - 2)
    h = t[j + 1] - t[j]
    u = (ts - t[j]) / h
    vals = {}
    for ch in chans:
        m = _SPEC.match(ch)
        var = m.group(1) if m else ""
        exact = {"position": "section_position", "velocity": "section_velocity"}.get(var)
        if exact in ds.data_vars and not ch.rstrip("] ").endswith("norm"):
            b, ax = [x.strip() for x in m.group(2).split(",")]
            vals[ch] = ds[exact].sel(body=b, axis=ax).values[keep]
        else:
            x, r = series[ch], rates[ch]
            vals[ch] = _hermite(h, x[j], x[j + 1], r[j], r[j + 1], u)
    spec = str(ds["section_time"].attrs.get("description", "")).split(";")[0]
    return {"spec": f"{spec} (located in the integration loop)", "times": ts, "values": vals}


def save_analysis(path: str | Path, analysis: Analysis, *, attrs: Mapping | None = None) -> Path:
    """Write the analysis to a NetCDF file (one group "analysis"), atomically."""
    from clearance.io.dataset import save_results

    return save_results(path, {"analysis": analysis.to_dataset()}, attrs=attrs)


def _scale(x: np.ndarray) -> float:
    """A channel's scale for the recurrence test: its range over the steady part, at least
    1e-6 of its magnitude (the integration noise of the default rtol: a channel that
    varies less is taken as constant, not as a scatter of distinct points)."""
    x = np.asarray(x, dtype=float)
    return max(float(np.ptp(x)), 1e-6 * float(np.max(np.abs(x))), 1e-300)


def response_of_run(r, steady: Steady, platform: str, *, tol: float = 1e-3, lyapunov=None) -> dict:
    """The classification of a run's steady state (a `Result` on a steady grid): the
    stroboscopic points of the platform's position and of every clearance joint's
    eccentricity, each coordinate scaled by its range over the steady samples. Returns
    {"response", "period", "distinct_points", "points", "evidence"} (plain data)."""
    t = np.asarray(r.t)
    if t.size < 2:
        return {}
    idx = steady.strobe(t.size)
    if idx.size < 2:
        return {}
    cols = [r.position(platform)]
    cols += [r.eccentricity(name) for name in r.clearance_names]
    X = np.column_stack(cols)
    scale = np.array([_scale(X[idx[0] :, k]) for k in range(X.shape[1])])
    c = classify(
        X[idx] / scale,
        tol=tol,
        zero_one=True,
        lyapunov=lyapunov,
        drive_frequency=1.0 / steady.period,
    )
    return {
        "lyapunov": None if lyapunov is None else lyapunov.exponent,
        "lyapunov_standard_error": None if lyapunov is None else lyapunov.standard_error,
        "response": c.kind,
        "period": c.period,
        "distinct_points": c.distinct,
        "points": c.points,
        "evidence": "; ".join(c.reasons),
    }
