"""Stability of periodic solutions: Floquet multipliers by the monodromy matrix and by Hill's method; bifurcations.

Monodromy matrix
    ``Phi' = J(t, y(t)) Phi``, ``Phi(0) = I`` over one period
    ``T = 2 pi / w``, ``J`` the system's analytic Jacobian along the
    harmonic-balance orbit ``y(t)``. By default by exponential collocation in
    the modal coordinates of the linear part, the local forces' Jacobian of
    low rank, steps ending at the contact switches
    (:mod:`rotorkit.periodic.floquet`); ``method="dop853"`` integrates the
    full variational equations (scipy's DOP853, ``rtol`` 1e-10). The
    multipliers are the eigenvalues of ``Phi(T)``.

Hill's method
    A perturbation ``e^{lambda t} p(t)`` with ``p`` periodic, expanded on the
    same ``H`` harmonics, gives the quadratic eigenproblem
    ``(lambda^2 M + lambda (2 M wD + Ct) + J_HB) p = 0`` with ``Kt``, ``Ct``
    the linearised stiffness and damping operators of the harmonic balance
    (:meth:`~rotorkit.periodic.hb.HarmonicBalance.tangent`) and ``J_HB`` its
    Jacobian. Its ``2 n (2H + 1)`` eigenvalues are the Floquet exponents
    repeated at ``lambda + i k w``; the ``2 n`` kept are those whose
    eigenvectors are most centred on harmonic 0: the weighted mean
    harmonic ``sum k |c_k|^2 / sum |c_k|^2`` of the complex harmonics
    ``c_k`` (``k = -H ... H``) of ``p`` is closest to 0 (the copy at
    ``lambda + i k w`` has its eigenvector shifted by ``-k`` harmonics, and
    the copies near ``+-H`` are the ones truncation spoils), taking one
    exponent per family ``lambda + i k w``: a real negative multiplier has
    two equally centred exponents ``a +- i w / 2``, copies of each other. The
    multipliers are ``exp(lambda T)``.

A solution is stable when every multiplier lies inside the unit circle
(``|mu| <= 1 + tol``).
"""

from __future__ import annotations

import numpy as np

from .hb import block_kron

__all__ = ["monodromy_multipliers", "hill_multipliers", "is_stable", "classify_crossing", "STABILITY_TOL"]

#: |mu| above 1 + STABILITY_TOL counts as unstable
STABILITY_TOL = 1e-6


def orbit_state(hb, z, frame):
    """``y(t)`` of the harmonic-balance solution, a function of the time (s)."""
    n, H = hb.n, hb.harmonics
    Z = np.reshape(z, (-1, n))
    Zd = hb.D @ Z
    k = np.arange(1, H + 1)
    w = frame.omega

    def state(t):
        c, s = np.cos(k * w * t), np.sin(k * w * t)
        basis = np.empty(2 * H + 1)
        basis[0], basis[1::2], basis[2::2] = 1.0, c, s
        return np.concatenate([basis @ Z, w * (basis @ Zd)])

    return state


def monodromy_multipliers(hb, z, frame, *, method="collocation", rtol=1e-10, atol=1e-12, steps=None):
    """Floquet multipliers (complex, shape (2n,)) from the monodromy matrix over one base period.

    Parameters
    ----------
    method : {"collocation", "dop853"}
        ``"collocation"`` (default): exponential collocation in the modal coordinates of the linear part, the
        nonlinear part's Jacobian of low rank (:mod:`rotorkit.periodic.floquet`; ``steps`` per period, default
        :data:`~rotorkit.periodic.floquet.DEFAULT_STEPS`); it falls back to ``"dop853"`` when the linear part
        is not diagonalisable or the nonlinear part depends on more than half the coordinates.
        ``"dop853"``: the full variational equations ``Phi' = J Phi`` by scipy's DOP853 (``rtol``, ``atol``).

    Returns
    -------
    multipliers : numpy.ndarray of complex, shape (2n,)
    monodromy : numpy.ndarray, shape (2n, 2n)
    """
    from scipy.integrate import solve_ivp

    if method not in ("collocation", "dop853"):
        from ..errors import ParameterError

        raise ParameterError(f"method={method!r} is unknown: expected 'collocation' or 'dop853'")
    if method == "collocation":
        from .floquet import DEFAULT_STEPS, exponential_monodromy

        found = exponential_monodromy(hb, z, frame, steps=DEFAULT_STEPS if steps is None else steps)
        if found is not None:
            return found

    m = 2 * hb.n
    state = orbit_state(hb, z, frame)

    def variational(t, phi):
        J = frame.jacobian_at(t, state(t)[None, :])[0]
        return (J @ phi.reshape(m, m)).ravel()

    sol = solve_ivp(variational, (0.0, frame.period), np.eye(m).ravel(), method="DOP853", rtol=rtol, atol=atol)
    if not sol.success:
        from .errors import ConvergenceError

        raise ConvergenceError(f"the monodromy integration failed: {sol.message}")
    Phi = sol.y[:, -1].reshape(m, m)
    return np.linalg.eigvals(Phi), Phi


def hill_exponents(hb, z, frame):
    """All Hill eigenvalues and the centring measure of their eigenvectors: ``(lambda (2n(2H+1),), centre)``."""
    n, H2 = hb.n, 2 * hb.harmonics + 1
    size = n * H2
    Kt, Ct = hb.tangent(z, frame)
    wD = frame.omega * hb.D
    Minv = np.linalg.inv(frame.mass)

    def right_derivative(X):  # X @ kron(w D, I_n), without the dense product
        return np.einsum("acl,cd->adl", X.reshape(size, H2, n), wD).reshape(size, size)

    def left_mass_inverse(X):  # kron(I, M^-1) @ X, block by block
        return np.einsum("ij,hjs->his", Minv, X.reshape(H2, n, -1)).reshape(size, -1)

    # J_HB = Kt + Ct (w D) + M (w D)^2 and 2 M (w D) + Ct, each of them per harmonic block
    J = Kt + right_derivative(Ct) + block_kron(wD @ wD, frame.mass)
    D1 = 2.0 * block_kron(wD, frame.mass) + Ct
    A = np.zeros((2 * size, 2 * size))
    A[:size, size:] = np.eye(size)
    A[size:, :size] = -left_mass_inverse(J)
    A[size:, size:] = -left_mass_inverse(D1)
    lam, vectors = np.linalg.eig(A)
    P = vectors[:size].reshape(H2, n, -1)  # real-basis coefficients of p, per eigenvector
    a, b = P[1::2], P[2::2]
    power = np.zeros((2 * hb.harmonics + 1, vectors.shape[1]))
    power[hb.harmonics] = np.sum(np.abs(P[0]) ** 2, axis=0)
    power[hb.harmonics + 1:] = np.sum(np.abs(a - 1j * b) ** 2, axis=1) / 4.0  # c_k = (a_k - i b_k) / 2
    power[:hb.harmonics] = (np.sum(np.abs(a + 1j * b) ** 2, axis=1) / 4.0)[::-1]  # c_-k
    k = np.arange(-hb.harmonics, hb.harmonics + 1)[:, None]
    centre = np.sum(k * power, axis=0) / np.maximum(np.sum(power, axis=0), 1e-300)
    return lam, centre


def hill_multipliers(hb, z, frame):
    """Floquet multipliers (complex, shape (2n,)) by Hill's method (see the module notes for the selection)."""
    lam, centre = hill_exponents(hb, z, frame)
    w = frame.omega
    kept = []
    for i in np.argsort(np.abs(centre), kind="stable"):
        shift = [(lam[i] - lam[j]) / (1j * w) for j in kept]
        # a copy lambda + i k w (k != 0) of an exponent already kept is the same Floquet multiplier: skip it
        # (a real negative multiplier's exponents a +- i w / 2 are copies of each other, equally centred)
        if any(abs(d.imag) < 1e-6 and round(d.real) != 0 and abs(d.real - round(d.real)) < 1e-6 for d in shift):
            continue
        kept.append(i)
        if len(kept) == 2 * hb.n:
            break
    return np.exp(lam[kept] * frame.period)


def is_stable(multipliers, tol=STABILITY_TOL):
    """Whether every multiplier lies inside the unit circle (``|mu| <= 1 + tol``)."""
    return bool(np.all(np.abs(multipliers) <= 1.0 + tol))


def classify_crossing(before, after, tol=STABILITY_TOL):
    """The kind of bifurcation between two consecutive multiplier sets, or None if stability did not change.

    Returns ``"fold"`` (a real multiplier through +1), ``"period doubling"`` (through -1) or
    ``"Neimark-Sacker"`` (a complex pair), judged on the multiplier nearest the unit circle
    among those outside it on the unstable side.
    """
    limit = 1.0 + tol
    out_before = np.abs(before) > limit
    out_after = np.abs(after) > limit
    unstable_before, unstable_after = int(out_before.sum()), int(out_after.sum())
    if unstable_before == unstable_after:
        return None
    side, out = (after, out_after) if unstable_after > unstable_before else (before, out_before)
    outside = np.asarray(side)[out]
    mu = outside[np.abs(outside).argmin()]
    if abs(mu.imag) > 1e-6 * abs(mu):
        return "Neimark-Sacker"
    return "fold" if mu.real > 0 else "period doubling"
