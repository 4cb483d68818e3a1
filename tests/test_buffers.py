"""Prefaulted output buffers: same contents and semantics as np.zeros, memory released with
the array (the last of them, for several in one mapping), huge pages where the kernel has
them, MAP_POPULATE where it cannot populate by madvise, plain np.zeros where the OS has no
MAP_POPULATE or refuses the mapping."""

from __future__ import annotations

import gc
import mmap
import pickle
import weakref

import numpy as np
import pytest

from clearance.integrate import buffers
from clearance.integrate.buffers import (
    POPULATE_MIN_BYTES,
    prefaulted_zeros,
    prefaulted_zeros_many,
)

BIG = (POPULATE_MIN_BYTES // 8 // 100 + 1, 100)  # just above the threshold (float64)


def _mapping(a: np.ndarray):
    b = a
    while getattr(b, "base", None) is not None:
        b = b.base
    return b.obj if isinstance(b, memoryview) else b


@pytest.mark.skipif(not hasattr(mmap, "MAP_POPULATE"), reason="no MAP_POPULATE here")
def test_big_array_is_a_zeroed_writable_mapping_released_with_the_array():
    a = prefaulted_zeros(BIG)
    m = _mapping(a)
    assert isinstance(m, mmap.mmap)
    assert a.shape == BIG and a.dtype == np.float64 and a.flags.c_contiguous
    assert a.flags.writeable and not a.any()
    a[3, 4] = 7.0
    assert pickle.loads(pickle.dumps(a))[3, 4] == 7.0
    ref = weakref.ref(m)
    del a, m
    gc.collect()
    assert ref() is None  # unmapped with the array


def test_small_arrays_and_dtypes_are_plain_zeros():
    a = prefaulted_zeros((3, 4), np.int64)
    assert isinstance(a.base, type(None)) and a.dtype == np.int64 and not a.any()
    assert prefaulted_zeros((0, 7)).shape == (0, 7)


def test_many_arrays_share_one_mapping_aligned_and_independent():
    shapes = [(1000, 66), (1000, 0, 5), (0, 3), (1000, 7, 3), (999, 77)]
    arrs = prefaulted_zeros_many(shapes)
    assert [a.shape for a in arrs] == shapes
    maps = {id(_mapping(a)) for a in arrs}
    assert len(maps) == 1 and isinstance(_mapping(arrs[0]), mmap.mmap)
    for k, a in enumerate(arrs):
        assert a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable
        assert a.ctypes.data % 64 == 0 and not a.any()
        a[...] = k + 1.0  # no overlap: each keeps its own value
    assert all(np.all(a == k + 1.0) for k, a in enumerate(arrs))
    ref = weakref.ref(_mapping(arrs[0]))
    last = arrs[-1]
    del arrs, a
    gc.collect()
    assert ref() is not None and last.sum() == 5.0 * 999 * 77  # alive with its last array
    del last
    gc.collect()
    assert ref() is None
    small = prefaulted_zeros_many([(3, 4), (2,)], np.int64)
    assert [a.base for a in small] == [None, None] and small[0].dtype == np.int64


def test_falls_back_to_map_populate_without_madvise_populate(monkeypatch):
    """A kernel older than 5.14 refuses MADV_POPULATE_WRITE: MAP_POPULATE instead."""
    if not (hasattr(mmap, "MAP_POPULATE") and hasattr(mmap, "MADV_HUGEPAGE")):
        pytest.skip("no MAP_POPULATE / madvise here")
    calls = []
    real = mmap.mmap

    class Old(real):
        def madvise(self, advice, *args):
            if advice == buffers.MADV_POPULATE_WRITE:
                raise OSError(22, "Invalid argument")
            return super().madvise(advice, *args)

    def make(*args, **kw):
        calls.append(kw.get("flags", 0))
        return Old(*args, **kw)

    monkeypatch.setattr(buffers.mmap, "mmap", make)
    a = prefaulted_zeros(BIG)
    assert a.shape == BIG and not a.any()
    assert len(calls) == 2 and calls[1] & mmap.MAP_POPULATE and not calls[0] & mmap.MAP_POPULATE


def test_falls_back_without_populate_or_when_the_mapping_fails(monkeypatch):
    monkeypatch.delattr(mmap, "MAP_POPULATE", raising=False)
    monkeypatch.delattr(mmap, "MADV_HUGEPAGE", raising=False)  # (the madvise path's marker)
    a = prefaulted_zeros(BIG)
    assert a.base is None and not a.any()
    monkeypatch.setattr(mmap, "MAP_POPULATE", 0x8000, raising=False)

    def refuse(*args, **kw):
        raise OSError("no memory")

    monkeypatch.setattr(buffers.mmap, "mmap", refuse)
    b = prefaulted_zeros(BIG)
    assert b.base is None and b.shape == BIG and not b.any()


def test_windows_like_platform_gets_plain_zeros(monkeypatch):
    """No MAP_PRIVATE / MAP_ANONYMOUS (Windows): np.zeros, never an AttributeError."""
    for name in ("MAP_PRIVATE", "MAP_ANONYMOUS", "MAP_POPULATE", "MADV_HUGEPAGE"):
        monkeypatch.delattr(mmap, name, raising=False)
    monkeypatch.setattr(buffers.sys, "platform", "win32")
    a = prefaulted_zeros(BIG)
    many = prefaulted_zeros_many([BIG, (3, 2)])
    assert a.base is None and not a.any() and a.shape == BIG
    assert [m.shape for m in many] == [BIG, (3, 2)] and not many[0].any()
