"""Prefaulted output buffers: same contents and semantics as np.zeros, memory released with
the array, plain np.zeros where the OS has no MAP_POPULATE or refuses the mapping."""

from __future__ import annotations

import gc
import mmap
import pickle
import weakref

import numpy as np
import pytest

from clearance.integrate import buffers
from clearance.integrate.buffers import POPULATE_MIN_BYTES, prefaulted_copy, prefaulted_zeros

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


def test_copy_is_contiguous_and_equal():
    rng = np.random.default_rng(0)
    src = rng.normal(size=(BIG[0], 2 * BIG[1]))[:, ::2]  # a strided view
    c = prefaulted_copy(src)
    assert c.flags.c_contiguous and np.array_equal(c, src)


def test_falls_back_without_populate_or_when_the_mapping_fails(monkeypatch):
    monkeypatch.delattr(mmap, "MAP_POPULATE", raising=False)
    a = prefaulted_zeros(BIG)
    assert a.base is None and not a.any()
    monkeypatch.setattr(mmap, "MAP_POPULATE", 0x8000, raising=False)

    def refuse(*args, **kw):
        raise OSError("no memory")

    monkeypatch.setattr(buffers.mmap, "mmap", refuse)
    b = prefaulted_zeros(BIG)
    assert b.base is None and b.shape == BIG and not b.any()
