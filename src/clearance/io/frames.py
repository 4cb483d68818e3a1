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

An impact shorter than the output step has no sample in contact at all; the event log
still lists it (the viewer marks every event on its time line).
"""

from __future__ import annotations

import numpy as np

MAX_FRAMES = 2000
WINDOW = 6

__all__ = ["MAX_FRAMES", "WINDOW", "contact_runs", "frame_samples"]


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
    if event_times is not None and np.size(event_times) and stride > 1:
        k = np.searchsorted(t, np.asarray(event_times, dtype=float))
        offs = np.arange(-window, window + 1)
        keep.append(np.clip((k[:, None] + offs[None, :]).ravel(), 0, n - 1))
    if contact_flag is not None and stride > 1:
        flag = np.asarray(contact_flag).reshape(n, -1)
        force = (
            np.abs(np.asarray(contact_force, dtype=float).reshape(n, -1))
            if contact_force is not None
            else np.zeros(flag.shape)
        )
        peaks = []
        for j in range(flag.shape[1]):
            for a, b in contact_runs(flag[:, j]):
                peaks.append(a + int(np.argmax(force[a : b + 1, j])))
        keep.append(np.asarray(peaks, dtype=np.int64))
    return np.unique(np.concatenate(keep).astype(np.int64))
