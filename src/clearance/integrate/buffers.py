"""Large output arrays allocated with their memory already mapped.

A long run writes tens of megabytes of output (states at 20 001 samples: 25 MB; the
post-processed accelerations, multipliers and reactions: about 75 MB more). Fresh memory is
mapped page by page on first write, and each page fault costs microseconds: in a virtual
machine (the project machine is one) about 8 us per 4 KiB page, i.e. ~50 ms for the 25 MB of
states alone, paid inside the integration loop whenever the allocator cannot reuse freed
memory (for instance while an earlier result is still alive).

So the arrays are anonymous mappings populated at allocation, in 2 MiB pages where the
kernel offers transparent huge pages (Linux: madvise MADV_HUGEPAGE, then
MADV_POPULATE_WRITE, Linux >= 5.14). Measured there for 8.5 MB (the post-processed outputs
of the ideal 4UPS-UPU at 2001 samples), fresh memory each time: 0.8 ms, against 2.5 ms with
4 KiB pages populated in one call (MAP_POPULATE, the fallback on older kernels) and ~17 ms
page by page. Huge pages change nothing else: the contents are zero either way, and the
memory is released with the array.

Platforms without MAP_POPULATE (macOS, Windows) and small arrays get plain `np.zeros`.
"""

from __future__ import annotations

import mmap
import sys

import numpy as np

#: below this size (bytes) page faults do not matter and np.zeros is used
POPULATE_MIN_BYTES = 1 << 20
#: madvise advice "populate (prefault) page tables writable" (Linux >= 5.14; not yet named
#: in Python's mmap module)
MADV_POPULATE_WRITE = 23


def _populated(nbytes: int) -> mmap.mmap | None:
    """An anonymous mapping of nbytes, populated, in huge pages where possible; None where
    the OS cannot (no MAP_POPULATE, or the mapping refused: the caller pages on demand)."""
    private, anonymous = getattr(mmap, "MAP_PRIVATE", None), getattr(mmap, "MAP_ANONYMOUS", None)
    if private is None or anonymous is None:  # (Windows)
        return None
    flags = private | anonymous
    if sys.platform.startswith("linux") and hasattr(mmap, "MADV_HUGEPAGE"):
        try:
            buf = mmap.mmap(-1, nbytes, flags=flags)
        except (OSError, ValueError):
            return None
        try:
            buf.madvise(mmap.MADV_HUGEPAGE)
        except OSError:  # no transparent huge pages in this kernel: 4 KiB pages
            pass
        try:
            buf.madvise(MADV_POPULATE_WRITE)
            return buf
        except OSError:  # kernel older than 5.14: MAP_POPULATE below
            buf.close()
    populate = getattr(mmap, "MAP_POPULATE", None)
    if populate is None:
        return None
    try:
        return mmap.mmap(-1, nbytes, flags=flags | populate)
    except (OSError, ValueError):  # e.g. a locked-memory or overcommit limit
        return None


def prefaulted_zeros(shape: tuple, dtype: type = np.float64) -> np.ndarray:
    """np.zeros(shape, dtype), with all pages mapped at allocation where the OS allows it.

    The array owns its mapping (through `.base`); it is released with the array."""
    return prefaulted_zeros_many([shape], dtype)[0]


def prefaulted_zeros_many(shapes: list, dtype: type = np.float64) -> list:
    """[prefaulted_zeros(s, dtype) for s in shapes], all in one mapping: one system call,
    and huge pages for arrays that are each smaller than one (the ideal 4UPS-UPU at 2001
    samples: seven arrays of 1-2 MB, 2.8 ms apart against 0.8 ms together). Each array
    starts on a 64-byte boundary; the mapping is released with the last of them, so group
    arrays that live and die together (a Result's post-processed outputs)."""
    dt = np.dtype(dtype)
    shapes = [tuple(int(n) for n in s) for s in shapes]
    sizes = [int(np.prod(s, dtype=np.int64)) * dt.itemsize for s in shapes]
    offsets, total = [], 0
    for nb in sizes:
        offsets.append(total)
        total += -(-nb // 64) * 64
    buf = _populated(total) if total >= POPULATE_MIN_BYTES else None
    if buf is None:
        return [np.zeros(s, dt) for s in shapes]
    return [  # (anonymous memory is zero-filled)
        np.frombuffer(buf, dtype=dt, count=nb // dt.itemsize, offset=o).reshape(s)
        for s, nb, o in zip(shapes, sizes, offsets, strict=True)
    ]
