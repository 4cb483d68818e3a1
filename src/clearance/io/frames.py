"""The frames a viewer draws: which output samples carry every body's pose.

A run's output grid is fine (0.1 ms for 2 s in the default scenario: 20 001 samples); a
viewer needs far fewer frames for the motion, but every impact must stay visible. The
frames are

- a uniform subset of the samples, at most `max_frames` of them (stride
  ceil((n - 1) / max_frames)), first and last sample included;
- every sample within `window` samples of each contact event (onset or separation), so an
  impact is seen at the output resolution;
- the sample of the largest contact force of each contact interval (consecutive samples
  with a contact flag), so no interval is missed and its peak is drawn.

The contact frames have a budget of `EVENT_BUDGET` x max_frames (runs with thousands of
impacts): over it, the window shrinks (down to the event's own sample), then only the
largest peaks and an even subset of the events are kept, so a file never holds more than
(1 + EVENT_BUDGET) x max_frames + 1 frames per run. Events outside the samples' time span
are ignored.

An impact shorter than the output step has no sample in contact at all; the event log
still lists it (the viewer marks every event on its time line).
"""

from __future__ import annotations

import numpy as np

MAX_FRAMES = 2000
WINDOW = 6
EVENT_BUDGET = 2  # contact frames: at most this many times max_frames

__all__ = ["EVENT_BUDGET", "MAX_FRAMES", "WINDOW", "contact_runs", "frame_samples"]


def contact_runs(flag: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample of each run of consecutive nonzero entries of `flag` (n,)."""
    on = np.asarray(flag) != 0
    if not on.any():
        return []
    d = np.diff(np.r_[0, on.astype(np.int8), 0])
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    return list(zip(starts.tolist(), ends.tolist(), strict=True))


def frame_samples(
    t: np.ndarray,
    *,
    event_times: np.ndarray | None = None,
    contact_flag: np.ndarray | None = None,
    contact_force: np.ndarray | None = None,
    max_frames: int = MAX_FRAMES,
    window: int = WINDOW,
) -> np.ndarray:
    """Sorted indices into the samples `t` (n,) to draw as frames (module docstring).

    event_times: (m,) contact event times; contact_flag, contact_force: (n, k) per joint or
    contact point (the flag marks contact, the force picks each interval's peak).
    """
    t = np.asarray(t, dtype=float)
    n = t.size
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    if max_frames < 1:
        raise ValueError(f"max_frames = {max_frames}: expected at least 1")
    stride = max(1, -(-(n - 1) // max_frames))
    keep = [np.arange(0, n, stride), np.array([n - 1])]
    if stride == 1:  # every sample is a frame already
        return np.unique(np.concatenate(keep)).astype(np.int64)
    budget = EVENT_BUDGET * max_frames
    peaks = np.zeros(0, dtype=np.int64)
    if contact_flag is not None:
        flag = np.asarray(contact_flag).reshape(n, -1)
        force = (
            np.abs(np.asarray(contact_force, dtype=float).reshape(n, -1))
            if contact_force is not None
            else np.zeros(flag.shape)
        )
        found = []  # (peak force, sample)
        for j in range(flag.shape[1]):
            for a, b in contact_runs(flag[:, j]):
                m = a + int(np.argmax(force[a : b + 1, j]))
                found.append((force[m, j], m))
        if len(found) > budget:  # the largest peaks
            found.sort(key=lambda x: -x[0])
            found = found[:budget]
        peaks = np.array([m for _, m in found], dtype=np.int64)
    left = budget - peaks.size
    if event_times is not None and np.size(event_times) and left > 0:
        te = np.asarray(event_times, dtype=float).ravel()
        te = te[(te >= t[0]) & (te <= t[-1])]
        k = np.unique(np.searchsorted(t, te).clip(0, n - 1))
        w = window
        while w > 0 and k.size * (2 * w + 1) > left:  # narrower windows first
            w //= 2
        if k.size > left:  # then an even subset of the events
            k = k[np.linspace(0, k.size - 1, left).round().astype(np.int64)]
        offs = np.arange(-w, w + 1)
        keep.append(np.clip((k[:, None] + offs[None, :]).ravel(), 0, n - 1))
    keep.append(peaks)
    return np.unique(np.concatenate(keep).astype(np.int64))
