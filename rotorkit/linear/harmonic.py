"""Harmonic solves ``(K + W H - w^2 M + i w (C + W G)) Q = F`` over many (W, w) pairs.

The steady unbalance response and the frequency response functions both
need the dynamic stiffness solved at many frequencies. The solve is
**direct, not by modal superposition**: it is exact (no truncation of the
basis, nothing to choose), and with gyroscopic, cross-coupled or
speed-dependent matrices a modal basis would change with the speed and
have to be recomputed (complex, non-symmetric, left and right) at each
one, which costs more than the solve it replaces. The cost is kept low by
the structure of the matrices:

- when the coordinates can be ordered so that the matrices are banded
  (beam finite elements, chains of stations: reverse Cuthill-McKee
  ordering of the union of the sparsity patterns), each frequency is a
  banded LU solve, ``O(n b^2)``, all frequencies of a batch in one
  elimination, each step one numpy operation along the frequency axis
  (:mod:`rotorkit.linear.banded`: without row exchanges where the
  residual shows that to be backward stable, partial pivoting elsewhere;
  numpy alone, no scipy import);
- otherwise (small lumped models, dense couplings) the dense systems of
  all frequencies are solved in batches by :func:`numpy.linalg.solve`.

Entries not affine in the speed (tabulated bearing coefficients,
:class:`~rotorkit.linear.linear_model.SpeedTerms`) are evaluated exactly at
every speed, all speeds at once (:meth:`SpeedTerms.values_at`), and added
to the dynamic stiffness of each.

The ordering and bands depend on the model only: they are computed once
per :class:`~rotorkit.linear.linear_model.LinearModel` and kept with it.
"""

from __future__ import annotations

import weakref

import numpy as np

__all__ = ["solve_harmonic", "band_structure", "harmonic_method"]

#: use the banded solver when (lower + upper + 1) is below this fraction of n
BANDED_FRACTION = 0.25
#: at most this many complex entries per batch
_BATCH_ENTRIES = 4_000_000
#: LinearModel -> its banded layout (perm, lower, upper, band matrices), computed once
_LAYOUTS = weakref.WeakKeyDictionary()


def band_structure(*matrices):
    """``(permutation, lower, upper)``: a bandwidth-reducing order of the coordinates and its bands."""
    from .banded import reverse_cuthill_mckee

    pattern = np.zeros(matrices[0].shape, dtype=bool)
    for A in matrices:
        pattern |= A != 0
    pattern |= pattern.T
    np.fill_diagonal(pattern, True)
    perm = reverse_cuthill_mckee(pattern)
    P = pattern[np.ix_(perm, perm)]
    rows, cols = np.nonzero(P)
    return perm, int(np.max(rows - cols, initial=0)), int(np.max(cols - rows, initial=0))


def _layout(model):
    """``(perm, lower, upper, names, B)`` of a linear model: its order, bands, and its matrices in band rows.

    ``B`` (real, shape (n (lower + upper + 1), k)) holds the band rows of
    the k matrices among ``M, C, K, G, H`` that are not zero (``names``), one
    per column: the dynamic stiffness of many points is ``B`` times their
    complex coefficients (one real matrix product on the coefficients' real
    and imaginary parts side by side, see :func:`_coefficients`).
    """
    layout = _LAYOUTS.get(model)
    if layout is None:
        from .banded import band_rows

        matrices = {"M": model.mass, "C": model.damping, "K": model.stiffness, "G": model.gyroscopic,
                    "H": model.circulatory}
        terms = getattr(model, "speed_terms", None)
        perm, lower, upper = band_structure(*matrices.values(), *(() if terms is None else (terms.pattern(),)))
        bands = {name: band_rows(A[np.ix_(perm, perm)], lower, upper).reshape(-1) for name, A in matrices.items()}
        names = tuple(name for name, b in bands.items() if b.any())
        B = np.ascontiguousarray(np.stack([bands[name] for name in names], axis=-1), dtype=float)
        layout = perm, lower, upper, names, B
        _LAYOUTS[model] = layout
    return layout


def _coefficients(names, W, w):
    """Coefficient of each matrix in ``K + W H - w^2 M + i w (C + W G)`` at the points ``(W, w)``, shape (k, m)."""
    factors = {"M": lambda: -(w * w), "C": lambda: 1j * w, "K": lambda: np.ones_like(w), "G": lambda: 1j * (w * W),
               "H": lambda: W}
    out = np.empty((len(names), w.size), dtype=complex)
    for row, name in enumerate(names):
        out[row] = factors[name]()
    return out


def harmonic_method(model, method="auto"):
    """``"banded"`` or ``"dense"``: how :func:`solve_harmonic` solves ``model`` with ``method``."""
    if method != "auto":
        return method
    _, lower, upper, _, _ = _layout(model)
    return "banded" if lower + upper + 1 <= BANDED_FRACTION * model.n else "dense"


def solve_harmonic(model, speeds, frequencies, forces, *, method="auto"):
    """Solve the dynamic stiffness at each ``(speed, frequency)`` for the right-hand sides ``forces``.

    Parameters
    ----------
    model : LinearModel
    speeds, frequencies : numpy.ndarray, shape (m,)
        Swept speed ``W`` and excitation frequency ``w`` (rad/s) of each solve.
    forces : numpy.ndarray of complex, shape (m, n, r) or (n, r)
        Complex force amplitudes (N, N m); ``(n, r)`` is used at every point.
    method : {"auto", "banded", "dense"}

    Returns
    -------
    numpy.ndarray of complex, shape (m, n, r)
        Complex amplitudes of the coordinates (m, rad).
    """
    speeds = np.asarray(speeds, dtype=float).reshape(-1)
    w = np.asarray(frequencies, dtype=float).reshape(-1)
    n = model.n
    F = np.asarray(forces, dtype=complex)
    shared = F.ndim == 2
    r = F.shape[-1]
    out = np.empty((w.size, n, r), dtype=complex)
    terms = getattr(model, "speed_terms", None)  # entries not affine in the speed, exact at each one
    exact = None
    if terms is not None:  # their values at every speed at once, complex: i w times the damping ones
        exact = terms.values_at(speeds).astype(complex)
        damping = terms.matrix == 1
        exact[:, damping] *= 1j * w[:, None]
    method = harmonic_method(model, method)
    if method == "banded":
        from .banded import solve_banded_last

        perm, lower, upper, names, B = _layout(model)
        width = lower + upper + 1
        Fp = F[perm] if shared else F[:, perm]
        if terms is not None:  # band positions of the exact speed terms
            inverse = np.empty(n, dtype=np.int64)
            inverse[perm] = np.arange(n)
            term_rows = inverse[terms.rows]
            term_bands = lower + inverse[terms.cols] - term_rows
        batch = max(1, _BATCH_ENTRIES // max(n * (width + r), 1))
        for start in range(0, w.size, batch):  # all points of a batch in one banded elimination
            sl = slice(start, min(start + batch, w.size))
            W, om = speeds[sl], w[sl]
            # the dynamic stiffness in band rows, the points on the last axis: one matrix product
            # (B real: its product with the real and imaginary parts of the coefficients, read as complex)
            S = (B @ _coefficients(names, W, om).view(float)).view(complex).reshape(n, width, om.size)
            if exact is not None:
                np.add.at(S, (term_rows, term_bands), exact[sl].T)
            y = (np.broadcast_to(Fp[..., None], Fp.shape + (om.size,)) if shared
                 else np.moveaxis(Fp[sl], 0, -1))
            out[sl][:, perm] = np.moveaxis(solve_banded_last(S, lower, upper, y), -1, 0)
        return out
    M, C, K, G, H = model.mass, model.damping, model.stiffness, model.gyroscopic, model.circulatory
    batch = max(1, _BATCH_ENTRIES // max(n * n, 1))
    for start in range(0, w.size, batch):
        sl = slice(start, min(start + batch, w.size))
        W, om = speeds[sl, None, None], w[sl, None, None]
        D = K + W * H - om * om * M + 1j * om * (C + W * G)
        if exact is not None:
            np.add.at(D, (np.arange(D.shape[0])[:, None], terms.rows[None, :], terms.cols[None, :]), exact[sl])
        rhs = np.broadcast_to(F, (D.shape[0], n, r)) if shared else F[sl]
        out[sl] = np.linalg.solve(D, rhs)
    return out
