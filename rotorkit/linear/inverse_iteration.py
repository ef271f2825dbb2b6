"""Eigenvectors of chosen eigenvalues of a state matrix by inverse iteration (numpy alone).

A dense eigen-solution of the ``2n x 2n`` state matrix
``A = [[0, I], [A21, A22]]`` with its vectors costs about 1.4 times one of
its eigenvalues alone (:func:`numpy.linalg.eigvals`; 10.3 against 7.4 ms
for ``n = 80`` on the project's machine), and its left vectors need
:func:`scipy.linalg.eig` (a 0.4 s import in a fresh process). A Campbell
diagram or a table of the lowest modes needs the vectors of a few modes
only. Given the eigenvalues ``lambda``, each vector is found by inverse
iteration, ``z <- (A - lambda I)^-1 z`` from a fixed pseudo-random start.
With ``A``'s upper blocks ``0`` and ``I`` each step is one complex solve of
size ``n`` (about 0.1 ms for ``n = 80``)::

    (A - s I) [u; v] = [b1; b2]:  (A21 + s A22 - s^2 I) u = b2 - (A22 - s I) b1,  v = b1 + s u

and for the left vectors (``w^H A = lambda w^H``) one with the conjugate
transpose of the same ``n x n`` matrix.

A backward-stable solver gives ``lambda`` within about ``eps ||A||`` of an
exact eigenvalue, so each step leaves of another eigenvector's part about
``eps ||A|| / gap`` (``gap`` its distance to ``lambda``): the size of the
rounding error of any eigenvector computed in floating point. One step is
taken where ``ROUNDING eps rho / gap <= TOL`` (``rho`` the spectral radius,
``ROUNDING = 100`` a generous bound of the solver's error), as many as make
``(ROUNDING eps rho / gap)^steps <= TOL`` below that (at most
``MAX_STEPS``), and one more where a step did not grow the vector as an
eigenvector's does (a start nearly without it).

Eigenvalues closer than ``CLUSTER`` times that error bound (a double
eigenvalue, as the forward and backward modes of an isotropic rotor at
rest, or a near-double one) are iterated together: a block for the
cluster's invariant subspace, then its Rayleigh-Ritz vectors, or an
orthonormal basis of it where the Ritz vectors are degenerate (an exactly
double eigenvalue, whose every basis is one of eigenvectors).
"""

from __future__ import annotations

import numpy as np

__all__ = ["state_eigenvectors", "is_state_form"]

#: eigenvalue error of a backward-stable solver, in units of eps times the spectral radius (a generous bound)
ROUNDING = 1e2
#: eigenvalues closer than this many times that error to another one form a cluster (one block iteration)
CLUSTER = 1e3
#: fewest inverse-iteration steps (each one n x n solve per vector) ...
STEPS = 1
#: ... and most, for a small gap to the nearest other eigenvalue: steps until (error / gap)^steps < TOL
MAX_STEPS = 8
TOL = 1e-9
#: a last step that did not grow the vector to this over the eigenvalue error bound gets one more
GROWTH = 1e-3
#: Ritz vectors of a cluster more ill-conditioned than this: a multiple eigenvalue, given an orthonormal basis
RITZ_COND = 1e8
#: vectors iterated in one batch of solves
CHUNK = 8
_SEED = 20261126


def is_state_form(A):
    """Whether ``A`` (shape (2n, 2n)) is ``[[0, I], [A21, A22]]`` exactly (the size-n solves apply)."""
    A = np.asarray(A)
    N = A.shape[0]
    if A.ndim != 2 or N != A.shape[1] or N % 2:
        return False
    n = N // 2
    return not np.any(A[:n, :n]) and np.array_equal(A[:n, n:], np.eye(n))


class _Shifted:
    """Solves with ``A - s I`` (or its conjugate transpose) for several shifts at once."""

    def __init__(self, A, left):
        self.A = A
        self.left = left
        N = A.shape[0]
        self.structured = is_state_form(A)
        if self.structured:
            n = N // 2
            self.A21, self.A22 = A[n:, :n], A[n:, n:]
            if left:
                self.A21, self.A22 = self.A21.conj().T, self.A22.conj().T
            self.A21, self.A22 = np.ascontiguousarray(self.A21), np.ascontiguousarray(self.A22)

    def matrices(self, shifts):
        """The matrices factored at each shift, shape (k, m, m): ``A21 + s A22 - s^2 I`` or ``A - s I``."""
        s = np.asarray(shifts, dtype=complex)
        if self.structured:
            s = np.conj(s) if self.left else s
            T = s[:, None, None] * self.A22  # (A21 + s A22 - s^2 I)^H = A21^H + conj(s) A22^H - conj(s)^2 I
            T += self.A21
            diagonal = -(s * s)
        else:
            T = np.repeat((self.A.conj().T if self.left else self.A)[None].astype(complex), s.size, axis=0)
            diagonal = -s
        m = T.shape[1]
        T.reshape(s.size, m * m)[:, ::m + 1] += (diagonal.conj() if self.left and not self.structured
                                                 else diagonal)[:, None]
        return T

    def solve(self, T, shifts, B):
        """``(A - s I)^-1 B`` (left: ``^-H``) for each shift; T from :meth:`matrices`, B of shape (k, 2n, m)."""
        try:
            if not self.structured:
                return np.linalg.solve(T, B)
            n = self.A21.shape[0]
            s = np.asarray(shifts, dtype=complex)[:, None, None]
            b1, b2 = B[:, :n], B[:, n:]
            if not self.left:  # (A21 + s A22 - s^2 I) u = b2 - (A22 - s I) b1,  v = b1 + s u
                u = np.linalg.solve(T, b2 - self.A22 @ b1 + s * b1)
                return np.concatenate([u, b1 + s * u], axis=1)
            sc = np.conj(s)  # (A21 + s A22 - s^2 I)^H w2 = b1 + conj(s) b2,  w1 = b2 - (A22 - s I)^H w2
            w2 = np.linalg.solve(T, b1 + sc * b2)
            return np.concatenate([b2 - self.A22 @ w2 + sc * w2, w2], axis=1)
        except np.linalg.LinAlgError:  # a shift is an eigenvalue to the last bit: one at a time, moved by a rounding
            if len(shifts) > 1:
                return np.concatenate([self.solve(T[j:j + 1], shifts[j:j + 1], B[j:j + 1])
                                       for j in range(len(shifts))])
            moved = np.asarray(shifts, dtype=complex) * (1.0 + 8.0 * np.finfo(float).eps) + np.finfo(float).tiny
            return self.solve(self.matrices(moved), moved, B)


def _orthonormal(Z):
    """Columns of each (2n, m) block of ``Z`` (shape (k, 2n, m)) orthonormalised, and the smallest column norm."""
    norms = np.linalg.norm(Z, axis=1)
    if Z.shape[2] == 1:
        return Z / norms[:, None, :], norms[:, 0]
    return np.linalg.qr(Z)[0], norms.min(axis=1)


def state_eigenvectors(A, targets, spectrum, *, left=False):
    """Right (or left) eigenvectors of ``A`` for the eigenvalues ``targets``, by inverse iteration.

    Parameters
    ----------
    A : numpy.ndarray, shape (2n, 2n)
        A state matrix (solves of size ``n`` when it is ``[[0, I], [A21, A22]]``,
        of size ``2n`` otherwise).
    targets : array_like of complex, shape (k,)
        Eigenvalues of ``A`` (members of ``spectrum``) whose vectors are wanted.
    spectrum : array_like of complex, shape (2n,)
        Every eigenvalue of ``A`` (the gaps that decide the clusters).
    left : bool
        Left vectors ``w`` with ``w^H A = lambda w^H`` instead of right ones.

    Returns
    -------
    numpy.ndarray of complex, shape (2n, k)
        Unit vectors, column ``j`` for ``targets[j]``; two targets of one
        double eigenvalue get two orthonormal vectors of its eigenspace.
    """
    A = np.asarray(A)
    targets = np.asarray(targets, dtype=complex).reshape(-1)
    spectrum = np.asarray(spectrum, dtype=complex).reshape(-1)
    N = A.shape[0]
    shifted = _Shifted(A, left)
    rho = float(np.max(np.abs(spectrum))) if spectrum.size else 0.0
    delta = ROUNDING * np.finfo(float).eps * max(rho, np.finfo(float).tiny)  # error bound of an eigenvalue
    rng = np.random.default_rng(_SEED)
    out = np.empty((N, targets.size), dtype=complex)
    done = np.zeros(targets.size, dtype=bool)
    singles, steps_of = [], []
    for i, lam in enumerate(targets):
        if done[i]:
            continue
        d = np.abs(spectrum - lam)
        inside = d <= CLUSTER * delta
        inside[np.argmin(d)] = True  # lam itself (the nearest member of the spectrum)
        values = spectrum[inside]
        m = values.size
        gap = float(d[~inside].min()) if m < d.size else np.inf
        ratio = (float(d[inside].max()) + delta) / gap  # what each step leaves of the nearest other vector
        steps = STEPS if ratio <= 0 else int(min(MAX_STEPS, max(STEPS, np.ceil(np.log(TOL) / np.log(ratio)))))
        if m == 1:
            singles.append(i)
            steps_of.append(steps)
            done[i] = True
            continue
        mine = [i] + [j for j in range(i + 1, targets.size)
                      if not done[j] and np.min(np.abs(values - targets[j])) <= delta][:m - 1]
        Z = _iterate(shifted, targets[[i]], rng.standard_normal((1, N, m)) + 1j * rng.standard_normal((1, N, m)),
                     steps, delta)
        out[:, mine] = _cluster_vectors(A, Z[0], values, targets[mine], left)
        done[mine] = True
    singles, steps_of = np.array(singles, dtype=int), np.array(steps_of, dtype=int)
    start = rng.standard_normal((singles.size, N, 1)) + 1j * rng.standard_normal((singles.size, N, 1))
    for chunk in range(0, singles.size, CHUNK):  # batches of solves that stay in the cache
        part = slice(chunk, chunk + CHUNK)
        out[:, singles[part]] = _iterate(shifted, targets[singles[part]], start[part], steps_of[part],
                                         delta)[:, :, 0].T
    return out


def _iterate(shifted, shifts, start, steps, delta):
    """Inverse-iteration steps of the blocks ``start`` (shape (k, 2n, m)): ``steps[j]`` of block ``j``
    (an int: all alike), one more where the last one did not grow."""
    T = shifted.matrices(shifts)
    Z, _ = _orthonormal(start)
    steps = np.broadcast_to(np.asarray(steps, dtype=int), (len(shifts),))
    grown = np.full(len(shifts), np.inf)
    for step in range(int(steps.max())):
        if step < steps.min():  # every block: no copies
            Z, grown = _orthonormal(shifted.solve(T, shifts, Z))
            continue
        active = np.flatnonzero(steps > step)
        Z[active], grown[active] = _orthonormal(shifted.solve(T[active], shifts[active], Z[active]))
    again = np.flatnonzero(grown * delta < GROWTH)  # the start nearly lacked the vector: one more step
    if again.size:
        Z[again] = _orthonormal(shifted.solve(T[again], shifts[again], Z[again]))[0]
    return Z


def _cluster_vectors(A, Z, values, wanted, left):
    """Vectors for the ``wanted`` eigenvalues from an orthonormal basis ``Z`` of their cluster's subspace."""
    m = Z.shape[1]
    if m == 1:
        return Z
    H = Z.conj().T @ ((A.conj().T if left else A) @ Z)  # Rayleigh-Ritz in the invariant subspace
    ritz, Y = np.linalg.eig(H)
    if np.linalg.cond(Y) > RITZ_COND:  # one multiple eigenvalue (to rounding): any basis is of eigenvectors
        return Z[:, :wanted.size]
    if left:
        ritz = ritz.conj()
    taken = []
    for lam in wanted:  # the Ritz vector of each wanted eigenvalue, each one used once
        free = [j for j in range(m) if j not in taken]
        taken.append(free[int(np.argmin(np.abs(ritz[free] - lam)))])
    V = Z @ Y[:, taken]
    return V / np.linalg.norm(V, axis=0)
