"""Borrowed arrays (rotorkit.periodic.compiled_borrow): the same data, shape and strides, no reference count.

The kernels borrow their work arrays for the hot calls; a borrowed array must read and write the owner's data
(whole arrays, views with strides, members of nested tuples) and leave other values as they are. (That numba
skips its reference count is what makes the kernels faster: bench/bench_periodic.py section a.)
"""

from __future__ import annotations

import numpy as np
import pytest

numba = pytest.importorskip("numba")


def test_borrowed_arrays_share_the_owners_data_shape_and_strides():
    from rotorkit.periodic.compiled_borrow import borrowed

    @numba.njit
    def fill(a, b, c):
        x, (y, k), s = borrowed((a, (b[::2, 1:], 3), 2.5))
        for i in range(x.shape[0]):
            x[i] = s * i
        for i in range(y.shape[0]):
            for j in range(y.shape[1]):
                y[i, j] = 10 * i + j + k
        z = borrowed(c)
        z[1] = -1
        return x.shape[0], y.shape[0], y.shape[1], y.strides[0], y.strides[1], x.sum()

    a, b, c = np.zeros(4), np.zeros((5, 3)), np.zeros(3, dtype=np.int64)
    out = fill(a, b, c)
    assert out == (4, 3, 2, 2 * 3 * 8, 8, 2.5 * 6)
    assert np.array_equal(a, 2.5 * np.arange(4))
    expected = np.zeros((5, 3))
    expected[::2, 1:] = 10 * np.arange(3)[:, None] + np.arange(2)[None, :] + 3
    assert np.array_equal(b, expected)
    assert np.array_equal(c, [0, -1, 0])

