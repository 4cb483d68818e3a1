"""Large output arrays allocated with their memory already mapped.

A long run writes tens of megabytes of output (states at 20 001 samples: 25 MB; the
post-processed accelerations, multipliers and reactions: about 75 MB more). Fresh memory is
mapped page by page on first write, and each page fault costs microseconds: in a virtual
machine (the project machine is one) about 8 us per 4 KiB page, i.e. ~50 ms for the 25 MB of
states alone, paid inside the integration loop whenever the allocator cannot reuse freed
memory (for instance while an earlier result is still alive). An anonymous mapping with
MAP_POPULATE maps all pages in one system call (~7 ms for the same 25 MB there).

Platforms without MAP_POPULATE (macOS, Windows) and small arrays get plain `np.zeros`.
"""

from __future__ import annotations

import mmap

import numpy as np

#: below this size (bytes) page faults do not matter and np.zeros is used
POPULATE_MIN_BYTES = 1 << 20


def prefaulted_zeros(shape: tuple, dtype: type = np.float64) -> np.ndarray:
    """np.zeros(shape, dtype), with all pages mapped at allocation where the OS allows it.

    The array owns its mapping (through `.base`); it is released with the array."""
    shape = tuple(int(s) for s in shape)
    dt = np.dtype(dtype)
    nbytes = int(np.prod(shape, dtype=np.int64)) * dt.itemsize
    populate = getattr(mmap, "MAP_POPULATE", None)
    if nbytes < POPULATE_MIN_BYTES or populate is None:
        return np.zeros(shape, dt)
    try:
        buf = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS | populate)
    except (OSError, ValueError):  # e.g. a locked-memory or overcommit limit: page on demand
        return np.zeros(shape, dt)
    return np.frombuffer(buf, dtype=dt).reshape(shape)  # anonymous memory is zero-filled


def prefaulted_copy(a: np.ndarray) -> np.ndarray:
    """A C-contiguous copy of `a` in a prefaulted array."""
    out = prefaulted_zeros(a.shape, a.dtype)
    np.copyto(out, a)
    return out
