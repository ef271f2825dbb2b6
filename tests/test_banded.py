"""The numpy banded solver and ordering (rotorkit.linear.banded) against dense LAPACK and scipy's RCM."""

import numpy as np
import pytest

from rotorkit.linear.banded import band_rows, reverse_cuthill_mckee, solve_banded_many


def _banded(rng, m, n, lower, upper, dtype=complex):
    A = np.zeros((m, n, n), dtype=dtype)
    for d in range(-lower, upper + 1):
        i = np.arange(max(0, -d), min(n, n - d))
        values = rng.standard_normal((m, i.size))
        if dtype is complex:
            values = values + 1j * rng.standard_normal((m, i.size))
        A[:, i, i + d] = values
    return A


@pytest.mark.parametrize("n, lower, upper", [(1, 0, 0), (5, 1, 1), (12, 3, 1), (12, 0, 4), (30, 7, 7), (6, 5, 5)])
def test_many_banded_solves_equal_the_dense_solve(n, lower, upper):
    rng = np.random.default_rng(n + 10 * lower + 100 * upper)
    A = _banded(rng, 40, n, lower, upper)
    b = rng.standard_normal((40, n, 2)) + 1j * rng.standard_normal((40, n, 2))
    x = solve_banded_many(band_rows(A, lower, upper), lower, upper, b)
    ref = np.linalg.solve(A, b)
    np.testing.assert_allclose(x, ref, rtol=0, atol=1e-10 * np.abs(ref).max())


def test_pivoting_is_needed_and_done():
    """A zero leading diagonal entry: elimination without row exchanges would divide by zero."""
    A = np.array([[[0.0, 1.0, 0.0], [2.0, 3.0, 1.0], [0.0, 1.0, 4.0]]], dtype=complex)
    b = np.array([[[1.0], [2.0], [3.0]]], dtype=complex)
    x = solve_banded_many(band_rows(A, 1, 1), 1, 1, b)
    np.testing.assert_allclose(A[0] @ x[0], b[0], atol=1e-14)


def test_a_singular_banded_matrix_is_refused():
    A = np.zeros((1, 3, 3))
    A[0, 0, 0] = A[0, 1, 1] = 1.0  # last row and column zero
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        solve_banded_many(band_rows(A, 1, 1), 1, 1, np.ones((1, 3, 1)))


def test_reverse_cuthill_mckee_reduces_the_bandwidth_as_scipy_does():
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee as scipy_rcm

    rng = np.random.default_rng(3)
    n = 40
    chain = np.eye(n, dtype=bool) | np.eye(n, k=1, dtype=bool) | np.eye(n, k=-1, dtype=bool)
    shuffle = rng.permutation(n)
    pattern = chain[np.ix_(shuffle, shuffle)]  # a chain, scrambled: bandwidth 1 after reordering

    def bandwidth(perm):
        rows, cols = np.nonzero(pattern[np.ix_(perm, perm)])
        return int(np.max(np.abs(rows - cols)))

    mine = reverse_cuthill_mckee(pattern)
    assert sorted(mine.tolist()) == list(range(n))
    assert bandwidth(mine) == 1
    assert bandwidth(mine) <= bandwidth(np.asarray(scipy_rcm(csr_matrix(pattern.astype(np.int8)),
                                                              symmetric_mode=True)))
    two = np.zeros((6, 6), dtype=bool)  # two components
    two[:3, :3] = two[3:, 3:] = True
    assert sorted(reverse_cuthill_mckee(two).tolist()) == list(range(6))


@pytest.mark.parametrize("pivoting", ["auto", "partial"])
@pytest.mark.parametrize("dtype", [complex, float])
def test_both_eliminations_equal_the_dense_solve(pivoting, dtype):
    rng = np.random.default_rng(7)
    n, lower, upper = 25, 4, 3
    A = _banded(rng, 30, n, lower, upper, dtype=dtype)
    A[:, np.arange(n), np.arange(n)] += 8.0  # dominant diagonals: no exchange needed in most systems
    A[:3, 0, 0] = 0.0  # ...but needed in these
    b = rng.standard_normal((30, n, 3)).astype(dtype)
    x = solve_banded_many(band_rows(A, lower, upper), lower, upper, b, pivoting=pivoting)
    ref = np.linalg.solve(A, b)
    np.testing.assert_allclose(x, ref, rtol=0, atol=1e-12 * np.abs(ref).max())


@pytest.mark.parametrize("dtype", [float, complex])
def test_a_tiny_pivot_is_caught_by_the_backward_error_check(dtype):
    """Without row exchanges [[1e-20, 1], [1, 1]] x = [1, 2] gives x = (0, 1); the answer is (1, 1) to 1e-20.

    Also with more right-hand sides (checked together, by one combination of them) and beside a system that
    needs no exchange.
    """
    A = np.array([[[1e-20, 1.0], [1.0, 1.0]], [[4.0, 1.0], [1.0, 3.0]]], dtype=dtype)
    b = np.array([[[1.0], [2.0]]] * 2, dtype=dtype)
    x = solve_banded_many(band_rows(A, 1, 1), 1, 1, b)
    np.testing.assert_allclose(x[0, :, 0], [1.0, 1.0], rtol=1e-15)
    np.testing.assert_allclose(x[1, :, 0], np.linalg.solve(A[1], b[1])[:, 0], rtol=1e-15)
    several = np.concatenate([b, 3 * b, np.array([[[0.0], [1.0]]] * 2, dtype=dtype)], axis=2)
    x = solve_banded_many(band_rows(A, 1, 1), 1, 1, several)
    np.testing.assert_allclose(x, np.linalg.solve(A, several), rtol=1e-14)


def test_an_unknown_pivoting_is_refused():
    with pytest.raises(ValueError, match="pivoting='none' is unknown"):
        solve_banded_many(np.ones((1, 2, 1)), 0, 0, np.ones((1, 2, 1)), pivoting="none")
