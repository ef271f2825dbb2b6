"""One mode followed to a nearby speed by Newton's method, instead of a new full eigen-solution.

A Campbell diagram locates its critical speeds and instability onsets by
root finding between two grid speeds, where each step needs the tracked
mode at a new speed. A dense eigen-solution of the ``2n x 2n`` state matrix
gives all modes at once (``O(n^3)`` with a large constant, about 15 ms for
``n = 80``), and the mode is then picked among them by its shape. Between
two grid points the mode is already known closely: its eigenvalue is
interpolated and its shape is the grid one. Newton's method on the
quadratic eigen-problem

    T(lambda) x = (lambda^2 M + lambda C + K) x = 0,   v^H x = 1

(the bordered ``(n + 1) x (n + 1)`` system ``[[T, T' x], [v^H, 0]]``,
``T' = 2 lambda M + C``) converges to that eigenpair in a few complex
solves of size ``n + 1`` (a fraction of a millisecond each), to rounding.

It is only used where it cannot pick another mode: the result must lie
within a quarter of the distance from the predicted eigenvalue to every
other eigenvalue of both grid points, and its shape must still resemble the
grid one (MAC >= 0.5); otherwise (or without convergence) the caller solves
the full eigen-problem and tracks the mode by its shape as on the grid.
"""

from __future__ import annotations

import numpy as np

__all__ = ["newton_eigenpair", "follow_mode"]

#: relative size of the last Newton step at which the eigenpair counts as converged
NEWTON_RTOL = 1e-13
#: most Newton steps
NEWTON_MAXITER = 25
#: the result must be within this fraction of the gap to every other eigenvalue (of both grid points)
GAP_FRACTION = 0.25
#: and its shape at least this MAC with the grid shape it started from
MIN_MAC = 0.5


def newton_eigenpair(M, C, K, lam, x, rtol=NEWTON_RTOL, maxiter=NEWTON_MAXITER):
    """An eigenpair of ``lambda^2 M + lambda C + K`` near ``(lam, x)``, or None if Newton does not converge.

    Parameters
    ----------
    M, C, K : numpy.ndarray, shape (n, n)
        Mass, damping (gyroscopics included) and stiffness at one speed.
    lam : complex
        Starting eigenvalue (1/s).
    x : numpy.ndarray of complex, shape (n,)
        Starting right vector.

    Returns
    -------
    (complex, numpy.ndarray) or None
        The eigenvalue and its right vector (scaled so that ``v^H x = 1``
        for the normalised start ``v``).
    """
    x = np.array(x, dtype=complex)
    n = x.size
    v = x / np.vdot(x, x)  # v^H x0 = 1
    lam = complex(lam)
    J = np.zeros((n + 1, n + 1), dtype=complex)
    J[n, :n] = v.conj()
    r = np.empty(n + 1, dtype=complex)
    for _ in range(maxiter):
        T = (lam * lam) * M + lam * C + K
        J[:n, :n] = T
        J[:n, n] = (2.0 * lam * M + C) @ x
        r[:n] = T @ x
        r[n] = np.vdot(v, x) - 1.0
        try:
            step = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(step)):
            return None
        x = x + step[:n]
        lam = lam + step[n]
        if abs(step[n]) <= rtol * abs(lam) and np.linalg.norm(step[:n]) <= 1e3 * rtol * np.linalg.norm(x):
            return lam, x
    return None


def follow_mode(matrices, lam_a, lam_b, shape_a, shape_b, spectrum_a, spectrum_b, speed_a, speed_b, speed):
    """The tracked mode at ``speed`` between two grid speeds by :func:`newton_eigenpair`, or None if unsure.

    Parameters
    ----------
    matrices : callable
        ``matrices(speed)`` -> dense ``(M, C, K)`` there.
    lam_a, lam_b : complex
        The mode's eigenvalue at the grid speeds ``speed_a`` and ``speed_b`` (NaN where lost).
    shape_a, shape_b : numpy.ndarray of complex, shape (n,)
        Its shapes there.
    spectrum_a, spectrum_b : numpy.ndarray of complex
        All eigenvalues of the two grid points (the gap to the others).
    speed : float
        Where the mode is wanted (rad/s), between the two.

    Returns
    -------
    (complex, numpy.ndarray) or None
        Eigenvalue and right vector (largest entry 1), or None: solve the
        full eigen-problem instead.
    """
    if not (np.isfinite(lam_a) and np.isfinite(lam_b)) or speed_b <= speed_a:
        return None
    f = (speed - speed_a) / (speed_b - speed_a)
    predicted = lam_a + f * (lam_b - lam_a)
    gap = np.inf
    for lam, spectrum in ((lam_a, spectrum_a), (lam_b, spectrum_b)):
        spectrum = np.asarray(spectrum)
        others = np.abs(spectrum - lam) > 1e-12 * max(abs(lam), 1e-300)  # all but the mode itself
        if np.count_nonzero(~others) > 1:
            return None  # a double or repeated eigenvalue: the shape decides, not the distance
        if others.any():
            gap = min(gap, float(np.min(np.abs(spectrum[others] - predicted))))
    start = shape_a if f <= 0.5 else shape_b
    M, C, K = matrices(speed)
    solved = newton_eigenpair(M, C, K, predicted, start)
    if solved is None:
        return None
    lam, x = solved
    if not abs(lam - predicted) < GAP_FRACTION * gap:
        return None
    mac = abs(np.vdot(start, x)) ** 2 / (np.vdot(start, start).real * np.vdot(x, x).real)
    if mac < MIN_MAC:
        return None
    return lam, x / x[int(np.argmax(np.abs(x)))]
