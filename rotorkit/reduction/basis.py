"""The Craig-Bampton basis: static constraint modes of the boundary plus fixed-interface modes of the interior.

With ``B`` the boundary coordinates (kept physical) and ``I`` the interior,
``q = T z`` with

``T = [[I_B, 0], [Psi, Phi]]``, ``Psi = -K_II^-1 K_IB``, ``Phi``: the lowest
``m`` modes of ``(K_II, M_II)`` (the interior with the boundary held fixed).

``Psi`` makes the reduced model statically exact for any load on the
boundary; ``Phi`` adds the interior's dynamics up to its ``m``-th
fixed-interface frequency. A constant load on the interior (gravity) gets
one more vector, its static response ``K_II^-1 f_I`` orthogonalised against
``Phi``, so the static deflection stays exact too. With every interior mode
kept ``T`` is square and invertible: a change of coordinates, the full model.
"""

from dataclasses import dataclass

import numpy as np
import scipy.linalg as la

from ..errors import ParameterError

__all__ = ["CraigBampton", "craig_bampton"]


@dataclass(frozen=True)
class CraigBampton:
    """A Craig-Bampton basis (numbers for one parameter set).

    Attributes
    ----------
    T : numpy.ndarray, shape (n, R)
        ``q = T z``.
    frequencies : numpy.ndarray
        All fixed-interface natural frequencies of the interior (rad/s),
        ascending; the first ``modes`` are kept.
    modes : int
    static_vector : bool
        Whether the constant-load vector was added (last column of ``T``).
    """

    T: np.ndarray
    frequencies: np.ndarray
    modes: int
    static_vector: bool


def _scale_to_displacement(phi, translational):
    """Columns scaled to a largest translational entry of 1 (eta in m), sign fixed."""
    rows = translational if translational.size else np.arange(phi.shape[0])
    for k in range(phi.shape[1]):
        col = phi[rows, k] if rows.size else phi[:, k]
        j = int(np.argmax(np.abs(col)))
        if col[j] != 0.0:
            phi[:, k] /= col[j]
    return phi


def craig_bampton(m0, k0, f0, boundary, modes, translational, name="model"):
    """The :class:`CraigBampton` basis of ``(M0, K0)`` for ``boundary`` (indices, in order) and ``modes``.

    Parameters
    ----------
    m0, k0 : numpy.ndarray, shape (n, n)
        Constant mass and stiffness (SI). ``k0`` may be non-symmetric: the
        constraint modes use it as is, the fixed-interface modes its
        symmetric part.
    f0 : numpy.ndarray, shape (n,)
        Constant load (N).
    boundary : sequence of int
    modes : int
    translational : numpy.ndarray of int
        Interior positions (within the interior) of displacement coordinates,
        used to scale the modes.
    """
    n = m0.shape[0]
    b = np.asarray(boundary, dtype=int)
    i = np.setdiff1d(np.arange(n), b)
    nb, ni = b.size, i.size
    kii, kib = k0[np.ix_(i, i)], k0[np.ix_(i, b)]
    mii = m0[np.ix_(i, i)]
    try:
        lu = la.lu_factor(kii, check_finite=True)
        cond_ok = np.all(np.abs(np.diag(lu[0])) > 1e-12 * max(np.abs(np.diag(kii)).max(), 1e-300))
    except (ValueError, la.LinAlgError):
        cond_ok = False
    if not cond_ok:
        raise ParameterError(f"{name}: the interior (every coordinate but the boundary) is not held by a stiffness "
                             "(a free rigid-body or torsional motion): its stiffness matrix is singular; keep a "
                             "coordinate of the free motion physical (keep=[...]) or add a support")
    psi = -la.lu_solve(lu, kib)
    ks = 0.5 * (kii + kii.T)
    try:
        w2, phi = la.eigh(ks, 0.5 * (mii + mii.T))
    except la.LinAlgError as exc:
        raise ParameterError(f"{name}: the interior mass matrix is not positive definite ({exc})") from None
    frequencies = np.sqrt(np.clip(w2, 0.0, None))
    phi = _scale_to_displacement(phi[:, :modes].copy(), translational)
    fi = f0[i]
    static = False
    if modes < ni and np.any(fi != 0.0):
        a = la.lu_solve(lu, fi)
        if modes:
            a = a - phi @ np.linalg.solve(phi.T @ mii @ phi, phi.T @ (mii @ a))
        if np.linalg.norm(a) > 1e-8 * np.linalg.norm(la.lu_solve(lu, fi)):
            phi = np.column_stack([phi, _scale_to_displacement(a[:, None], translational)])
            static = True
    T = np.zeros((n, nb + phi.shape[1]))
    T[b, np.arange(nb)] = 1.0
    T[np.ix_(i, np.arange(nb))] = psi
    T[np.ix_(i, np.arange(nb, T.shape[1]))] = phi
    for arr in (T, frequencies):
        arr.setflags(write=False)
    return CraigBampton(T=T, frequencies=frequencies, modes=int(modes), static_vector=static)
