"""Modes of a linear second-order system: frequencies, log decrement, whirl, left/right shapes.

The system is ``M q'' + C q' + K q = 0`` (``C`` holding damping and the
speed-scaled gyroscopic matrix, ``K`` the stiffness and any cross-coupled,
circulatory part). Its state matrix ``A = [[0, I], [-M^-1 K, -M^-1 C]]``
has eigenvalues ``lambda`` in conjugate pairs; a mode is one pair, kept by
its member with ``Im(lambda) > 0``.

- natural frequency ``|lambda|`` (the undamped one for viscous damping),
- damped natural frequency ``Im(lambda)``,
- damping ratio ``zeta = -Re(lambda) / |lambda|``,
- logarithmic decrement ``delta = -2 pi Re(lambda) / Im(lambda)`` (the
  log of the ratio of successive peaks of a free decay; negative: unstable),
- right shape ``x``: ``(lambda^2 M + lambda C + K) x = 0``; left shape
  ``y``: ``y^H (lambda^2 M + lambda C + K) = 0``, normalised so that
  ``y^H (2 lambda M + C) x = 1`` (they differ when ``C`` or ``K`` is not
  symmetric: gyroscopics, cross-coupled bearings),
- whirl per station and per mode (:mod:`rotorkit.analysis.whirl`).

A double eigenvalue (an isotropic rotor at rest) has no preferred basis;
the pair is rotated into its backward and forward circular combinations,
backward first.

Mode numbers are 1-based in every method (mode 1 is the lowest); arrays
are plain numpy arrays indexed from 0.

This module solves the modes; the result type :class:`Modes` (with its
tables and outputs) lives in :mod:`rotorkit.linear.modal_result` and is
importable from here.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError
from .modal_result import Modes, frequency_factor, unit_slug  # noqa: F401 (re-exported)
from .whirl import station_pairs

__all__ = ["Modes", "modes_from_matrices", "modes_from_state_matrix", "oscillatory_order", "sparse_pays",
           "state_matrix"]

#: A pair is oscillatory when Im(lambda) exceeds this fraction of |lambda|.
OSCILLATORY_RTOL = 1e-9
#: Two eigenvalues closer than this fraction of |lambda| form a double one.
DOUBLE_RTOL = 1e-7


def _readonly(array):
    array = np.array(array)
    array.setflags(write=False)
    return array


def _circularise_pairs(lam, vec, names):
    """Rotate each double eigenvalue's two vectors into backward and forward circular whirl (backward first)."""
    pairs = station_pairs(names)
    if not pairs:
        return vec
    ix = np.array([p[1] for p in pairs])
    iy = np.array([p[2] for p in pairs])
    k = lam.size
    i = 0
    while i < k - 1:
        if abs(lam[i + 1] - lam[i]) > DOUBLE_RTOL * abs(lam[i]):
            i += 1
            continue
        V = vec[:, i:i + 2].copy()
        fwd = (V[ix] + 1j * V[iy]) / 2.0  # forward circle of each station, per basis vector
        bwd = (V[ix] - 1j * V[iy]) / 2.0
        combos = []
        for part in (fwd, bwd):  # kill the forward part -> backward vector, and vice versa
            _, s, vh = np.linalg.svd(part)  # vh is 2 x 2: its last row spans the (near) null space
            s = np.concatenate([s, np.zeros(2 - s.size)])
            combos.append(vh.conj()[-1] if s[-1] <= 1e-6 * max(s[0], 1e-300) else None)
        if all(c is not None for c in combos):
            vec[:, i] = V @ combos[0]
            vec[:, i + 1] = V @ combos[1]
        i += 2
    return vec


def modes_from_state_matrix(A, names, *, mass=None, left=True, n_modes=None, sparse=None, spectrum=None, **fields):
    """:class:`Modes` from a state matrix ``A = [[0, I], [-M^-1 K, -M^-1 C]]``.

    Parameters
    ----------
    A : numpy.ndarray, shape (2n, 2n)
    names : tuple of str, length n
    mass : numpy.ndarray, shape (n, n), optional
        ``M``, for the normalisation of the left shapes (default identity).
    left : bool
        Compute the left eigenvectors too.
    n_modes : int, optional
        Only the ``n_modes`` modes of smallest ``|lambda|``: for large models
        found by shift-invert Arnoldi iteration about 0
        (:func:`scipy.sparse.linalg.eigs`, a sparse LU of ``A``) instead of
        the full dense eigen-solution; :attr:`Modes.all_eigenvalues` then
        holds only the computed ones.
    sparse : bool, optional
        With ``n_modes``: True for the Arnoldi iteration, False for the
        dense eigenvalues (all of them) with the vectors of the ``n_modes``
        modes alone; None (default) chooses the Arnoldi iteration when
        more than :data:`DENSE_SIZE` coordinates and ``2 n > 4 n_modes + 20``.
    spectrum : numpy.ndarray of complex, shape (2n,), optional
        Every eigenvalue of ``A``, when already known (the dense solution
        with few vectors then computes the vectors alone).
    **fields
        Further :class:`Modes` fields (operating point, sample times, speed ...).

    Notes
    -----
    The dense solution computes the eigenvalues alone
    (:func:`numpy.linalg.eigvals`) and the vectors of the modes kept by
    inverse iteration (:func:`~rotorkit.linear.inverse_iteration.state_eigenvectors`)
    when they are few (``n_modes <= n / 5``: then cheaper than all the
    vectors); otherwise, with left vectors, :func:`scipy.linalg.eig` (left
    and right vectors in one solve) when scipy is imported already or
    ``n^4 > LEFT_ITERATION_WORK`` (about ``n > 119``), else every right
    vector by :func:`numpy.linalg.eig` and the left ones by inverse
    iteration: no 0.4 s import of :mod:`scipy.linalg` in a process that has
    no other use for it (``rotorkit modes FILE``). All agree with the full
    eigen-solution to rounding (``tests/test_inverse_iteration.py``).
    """
    n = len(names)
    n_modes = check_count(n_modes)
    if sparse is None:
        sparse = n_modes is not None and sparse_pays(n, n_modes)
    Mm = np.eye(n) if mass is None else np.asarray(mass, dtype=float)
    damping = (-A[n:, n:] if mass is None else Mm @ -A[n:, n:]) if left else None  # C: for the left shapes
    if sparse and n_modes is not None:
        eigenvalues, vr, wl = _lowest_eigenpairs(A, int(n_modes), left)
        index = oscillatory_order(eigenvalues)
        X, W = vr[:, index], None if wl is None else wl[:, index]
    elif n_modes is not None and _few(n_modes, n):
        from .inverse_iteration import state_eigenvectors

        eigenvalues = np.linalg.eigvals(A) if spectrum is None else np.asarray(spectrum, dtype=complex)
        index = oscillatory_order(eigenvalues)
        index = index[:_with_partner(eigenvalues[index], n_modes)]
        X = state_eigenvectors(A, eigenvalues[index], eigenvalues)
        W = state_eigenvectors(A, eigenvalues[index], eigenvalues, left=True) if left else None
    elif left and (float(n) ** 4 > LEFT_ITERATION_WORK or scipy_linalg_loaded()):  # scipy: both in one solve
        from scipy import linalg

        eigenvalues, wl, vr = linalg.eig(A, left=True, right=True)
        index = oscillatory_order(eigenvalues)
        X, W = vr[:, index], wl[:, index]
    else:
        eigenvalues, vr = np.linalg.eig(A)
        index = oscillatory_order(eigenvalues)
        X, W = vr[:, index], None
        if left:
            from .inverse_iteration import state_eigenvectors

            W = state_eigenvectors(A, eigenvalues[index], eigenvalues, left=True)
    Y = None
    if W is not None:  # the lower half of a left state vector is M^H y (y: left coordinate vector)
        Y = np.linalg.solve(Mm.conj().T, W[n:]) if mass is not None else W[n:]
    return _modes(eigenvalues, eigenvalues[index], X[:n], Y, names, Mm, damping, fields, n_modes)


#: models with at most this many coordinates solve all eigenvalues densely, also for a few modes (n_modes)
DENSE_SIZE = 100


def sparse_pays(n, n_modes):
    """Whether the ``n_modes`` lowest modes of ``n`` coordinates are solved by shift-invert Arnoldi iteration.

    For more than :data:`DENSE_SIZE` coordinates and ``2 n > 4 n_modes + 20``; below, the dense eigenvalues
    (milliseconds, no scipy import) with the vectors of the modes kept.
    """
    return n > DENSE_SIZE and 2 * n > 4 * int(n_modes) + 20


#: the dense solution finds the kept modes' vectors by inverse iteration when they are at most n / FEW_VECTORS
FEW_VECTORS = 5
#: left vectors of all modes by inverse iteration (no scipy) while n^4 (modes x the cost of a solve) is below
#: this, else scipy.linalg.eig: about n = 119
LEFT_ITERATION_WORK = 2e8


def scipy_linalg_loaded():
    """Whether :mod:`scipy.linalg` is imported already (then its eigen-solution with left vectors is the cheaper)."""
    import sys

    return "scipy.linalg" in sys.modules


def _few(n_modes, n):
    return int(n_modes) <= n // FEW_VECTORS


def oscillatory_order(eigenvalues):
    """Indices of the oscillatory eigenvalues (``Im(lambda) > OSCILLATORY_RTOL |lambda|``), by ascending ``|lambda|``.

    The modes of :class:`Modes`, in their order (a stable sort: equal moduli keep the solver's order).
    """
    eigenvalues = np.asarray(eigenvalues)
    index = np.flatnonzero(eigenvalues.imag > OSCILLATORY_RTOL * np.abs(eigenvalues))
    return index[np.argsort(np.abs(eigenvalues[index]), kind="stable")]


def double_pairs(lam):
    """Start indices ``i`` of the double eigenvalues ``(lam[i], lam[i + 1])`` of ascending ``lam``, as paired for
    the circular combinations (scanning up: a member of a pair is not paired again)."""
    pairs = []
    i = 0
    while i < lam.size - 1:
        if abs(lam[i + 1] - lam[i]) > DOUBLE_RTOL * abs(lam[i]):
            i += 1
            continue
        pairs.append(i)
        i += 2
    return pairs


def _with_partner(lam, n_modes):
    """``n_modes``, or one more when mode ``n_modes`` is the first member of a double eigenvalue (both are needed)."""
    k = min(int(n_modes), lam.size)
    return k + 1 if k < lam.size and k - 1 in double_pairs(lam[:k + 1]) else k


def modes_from_matrices(mass, damping, stiffness, names, *, left=True, n_modes=None, sparse=None, **fields):
    """:class:`Modes` of ``M q'' + C q' + K q = 0`` from its matrices.

    Parameters
    ----------
    mass, damping, stiffness : numpy.ndarray or scipy sparse matrix, shape (n, n)
        ``M``, ``C`` (damping plus speed-scaled gyroscopics) and ``K``
        (cross-coupled and circulatory parts included), SI units.
    names : tuple of str, length n
    left : bool
        Compute the left shapes too.
    n_modes : int, optional
        Only the ``n_modes`` modes of smallest ``|lambda|``. For large models
        (:func:`sparse_pays`: more than :data:`DENSE_SIZE` coordinates and
        ``2 n > 4 n_modes + 20``) they are found by shift-invert Arnoldi
        iteration (:func:`scipy.sparse.linalg.eigs`) on the pencil of the
        first-order form, each step one sparse LU solve with
        ``K + s C + s^2 M`` (``n x n``, factored once; the dense
        ``M^-1 K`` is never formed), so the cost grows with the bandwidth,
        not with ``n^3``. Otherwise, and when the iteration fails, they come
        from the dense eigen-solution of the state matrix
        (:func:`modes_from_state_matrix`).
    sparse : bool, optional
        As in :func:`modes_from_state_matrix`: False for the dense
        eigenvalues with the vectors of the ``n_modes`` modes alone.
    **fields
        Further :class:`Modes` fields.
    """
    n = len(names)
    n_modes = check_count(n_modes)
    dense = [np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=float)
             for A in (mass, damping, stiffness)]
    if n_modes is not None and (sparse_pays(n, n_modes) if sparse is None else sparse):
        solved = _lowest_pencil_eigenpairs(mass, damping, stiffness, int(n_modes), left)
        if solved is not None:
            eigenvalues, X, Y = solved
            index = oscillatory_order(eigenvalues)
            return _modes(eigenvalues, eigenvalues[index], X[:, index], None if Y is None else Y[:, index], names,
                          dense[0], dense[1], fields, n_modes)
    M, C, K = dense
    A = state_matrix(M, C, K)
    return modes_from_state_matrix(A, names, mass=M, left=left, n_modes=n_modes, sparse=sparse, **fields)


def state_matrix(mass, damping, stiffness):
    """``A = [[0, I], [-M^-1 K, -M^-1 C]]`` (shape (2n, 2n)) of dense ``M``, ``C``, ``K`` (one LU of ``M``, numpy)."""
    M, C, K = (np.asarray(X, dtype=float) for X in (mass, damping, stiffness))
    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:] = -np.linalg.solve(M, np.hstack([K, C]))
    return A


def check_count(n_modes):
    if n_modes is None:
        return None
    if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral) or n_modes < 1:
        raise ParameterError(f"n_modes={n_modes!r} is invalid: expected an integer >= 1 or None (all modes)")
    return int(n_modes)


def _modes(eigenvalues, lam, vec, Y, names, M, C, fields, n_modes=None):
    """:class:`Modes` from the oscillatory eigenvalues ``lam`` (ascending ``|lambda|``, as
    :func:`oscillatory_order`) with right (and left) coordinate vectors of ``lambda^2 M + lambda C + K``.

    ``eigenvalues``: every computed one (:attr:`Modes.all_eigenvalues`). ``n_modes``: keep the lowest
    ``n_modes`` modes (the sparse solvers compute a few more to converge, and the dense one may give all of
    them, or the ``n_modes`` and the partner of a double one).
    """
    n = len(names)
    vec = np.array(vec, dtype=complex)
    vec = _circularise_pairs(lam, vec, names)
    if n_modes is not None:  # after the circular combinations, which need both members of a double root
        lam, vec = lam[:n_modes], vec[:, :n_modes]
        Y = None if Y is None else Y[:, :n_modes]
    k = lam.size
    shapes = np.empty((n, k), dtype=complex)
    for i in range(k):
        v = vec[:, i]
        shapes[:, i] = v / v[int(np.argmax(np.abs(v)))]
    left_shapes = None
    if Y is not None:
        left_shapes = np.empty((n, k), dtype=complex)
        i = 0
        while i < k:
            N = 2.0 * lam[i] * M + C
            width = 2 if i + 1 < k and abs(lam[i + 1] - lam[i]) <= DOUBLE_RTOL * abs(lam[i]) else 1
            Xi, Yi = shapes[:, i:i + width], Y[:, i:i + width]
            P = Yi.conj().T @ N @ Xi  # bi-orthonormalise within a double root's eigenspace
            try:
                left_shapes[:, i:i + width] = Yi @ np.linalg.inv(P).conj().T
            except np.linalg.LinAlgError:
                left_shapes[:, i:i + width] = np.nan  # defective (coalescing) eigenvalue
            i += width
    frequencies = np.abs(lam)
    damping = -lam.real / frequencies if k else np.empty(0)
    fields = dict(fields)
    fields.setdefault("frequency_range", np.column_stack([frequencies, frequencies]) if k else np.empty((0, 2)))
    fields.setdefault("sample_times", np.array([0.0]))
    fields.setdefault("operating_point", np.zeros(n))
    return Modes(
        frequencies=_readonly(frequencies),
        damping_ratios=_readonly(damping),
        eigenvalues=_readonly(lam),
        shapes=_readonly(shapes),
        coordinate_names=tuple(names),
        all_eigenvalues=_readonly(eigenvalues[np.argsort(np.abs(eigenvalues), kind="stable")]),
        left_shapes=None if left_shapes is None else _readonly(left_shapes),
        **{key: (_readonly(v) if isinstance(v, np.ndarray) else v) for key, v in fields.items()},
    )


def _lowest_eigenpairs(A, n_modes, left):
    """Eigenvalues of smallest modulus, right (and left) vectors, by shift-invert Arnoldi about 0."""
    from scipy import sparse
    from scipy.sparse.linalg import eigs

    k = min(2 * n_modes + 4, A.shape[0] - 2)
    S = sparse.csc_matrix(A)
    lam, vr = eigs(S, k=k, sigma=0.0, which="LM")
    wl = None
    if left:
        mu, wv = eigs(S.T.tocsc(), k=k, sigma=0.0, which="LM")
        wl = np.empty_like(vr)
        for i, value in enumerate(lam):  # left vector of lambda: eigenvector of A^T for lambda, conjugated
            wl[:, i] = np.conj(wv[:, int(np.argmin(np.abs(mu - value)))])
    return lam, vr, wl


def _pencil_operator(M, C, K):
    """``(op, shift)``: ``z -> (A - s B)^-1 B z`` for ``A = [[0, I], [-K, -C]]``, ``B = diag(I, M)``.

    Eigenvalues ``mu`` of the operator give ``lambda = s + 1 / mu`` with the
    same eigenvectors ``[x, lambda x]``. The shift ``s`` is 0 unless ``K``
    is singular (a free rigid-body coordinate), then a small negative number.
    """
    from scipy import sparse
    from scipy.sparse.linalg import LinearOperator, splu

    n = M.shape[0]
    M, C, K = (sparse.csc_matrix(A) for A in (M, C, K))
    scale = math.sqrt(max(abs(K.diagonal()).max(), 1e-300) / max(abs(M.diagonal()).max(), 1e-300))
    for shift in (0.0, -1e-3 * scale, -1e-1 * scale):
        try:
            with np.errstate(all="ignore"):
                lu = splu((K + shift * C + shift * shift * M).tocsc())
        except RuntimeError:  # exactly singular
            continue
        if np.all(np.isfinite(lu.U.diagonal())) and np.min(np.abs(lu.U.diagonal())) > 1e-13 * np.max(
                np.abs(lu.U.diagonal())):
            break
    else:
        return None
    CsM = (C + shift * M).tocsr()
    M = M.tocsr()

    def matvec(z):
        z = np.asarray(z).reshape(-1)
        a, b = z[:n], M @ z[n:]
        u = lu.solve(np.asarray(-b - CsM @ a))
        return np.concatenate([u, a + shift * u])

    dtype = np.result_type(M.dtype, C.dtype, K.dtype)
    return LinearOperator((2 * n, 2 * n), matvec=matvec, dtype=dtype), shift


def _lowest_pencil_eigenpairs(M, C, K, n_modes, left):
    """``(eigenvalues, X, Y)`` of the ``2 n_modes + 4`` smallest ``|lambda|``, or None if the iteration fails.

    ``X`` holds right coordinate vectors, ``Y`` left ones (``y^H (lambda^2 M
    + lambda C + K) = 0``: right vectors of the transposed problem, conjugated).
    """
    from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, eigs

    n = M.shape[0]
    k = min(2 * n_modes + 4, 2 * n - 2)

    def solve(M, C, K):
        built = _pencil_operator(M, C, K)
        if built is None:
            return None
        op, shift = built
        for ncv in (None, min(2 * n, 4 * k + 20)):
            try:
                mu, z = eigs(op, k=k, which="LM", ncv=ncv, maxiter=20 * 2 * n)
            except (ArpackNoConvergence, ArpackError):
                continue
            with np.errstate(divide="ignore"):
                return shift + 1.0 / mu, z[:n]
        return None

    right = solve(M, C, K)
    if right is None:
        return None
    lam, X = right
    Y = None
    if left:
        transposed = solve(M.T, C.T, K.T)
        if transposed is None:
            return None
        mu, Z = transposed
        Y = np.empty_like(X)
        for i, value in enumerate(lam):
            Y[:, i] = np.conj(Z[:, int(np.argmin(np.abs(mu - value)))])
    return lam, X, Y
