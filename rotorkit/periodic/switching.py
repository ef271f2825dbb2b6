"""Branch switching at a period doubling: from a synchronous branch (``nu``) onto the period-doubled one (``2 nu``).

At a period doubling of a solution ``q1`` (base period ``T``) a Floquet multiplier crosses ``-1``: the
variational equations have a solution ``dy(t) = Phi(t) v`` (``v`` the monodromy matrix's eigenvector of that
multiplier) with ``dy(t + T) = -dy(t)``, a periodic function of period ``2T`` holding only the odd harmonics of
``w / 2``. In the harmonic balance of base frequency ``w / 2`` (sub-harmonic order ``2 nu``, ``2H``
harmonics), ``q1`` is the solution with only even harmonics, and the period-doubled branch leaves it along
``phi``, the Fourier coefficients of ``dq``. The first point of that branch is found by a predictor
``(z1 + s phi, lambda)`` and a Newton corrector on the hyperplane normal to ``phi`` through it (the parameter
free); ``q1`` itself has no odd harmonics, so it does not lie on that hyperplane and the corrector cannot fall
back onto the old branch.
"""

from __future__ import annotations

import numpy as np

from .errors import ConvergenceError
from .hb import fourier_basis, newton

__all__ = ["critical_direction", "embed", "first_doubled_point"]


def critical_direction(hb, z, frame):
    """The critical Floquet mode of a solution near a period doubling, sampled over one base period.

    Parameters
    ----------
    hb : rotorkit.periodic.hb.HarmonicBalance
        The problem of the solution (base period ``T = frame.period``).
    z : numpy.ndarray, shape (size,)
    frame : rotorkit.periodic.hb.Frame

    Returns
    -------
    samples : numpy.ndarray, shape (hb.samples, n)
        ``dq(t_j)``, ``t_j = j T / N``, of the mode ``Phi(t) v`` (``|v| = 1``).
    multiplier : complex
        The Floquet multiplier nearest ``-1``.
    """
    from scipy.integrate import solve_ivp

    from .stability import orbit_state, monodromy_multipliers

    _, Phi = monodromy_multipliers(hb, z, frame)
    values, vectors = np.linalg.eig(Phi)
    k = int(np.argmin(np.abs(values + 1.0)))
    v = np.real(vectors[:, k] * np.exp(-1j * np.angle(vectors[np.argmax(np.abs(vectors[:, k])), k])))
    v /= np.linalg.norm(v)
    state = orbit_state(hb, z, frame)

    def variational(t, dy):
        return frame.jacobian_at(t, state(t)[None, :])[0] @ dy

    times = frame.period * np.arange(hb.samples) / hb.samples
    sol = solve_ivp(variational, (0.0, frame.period), v, method="DOP853", t_eval=times, rtol=1e-10, atol=1e-12)
    if not sol.success:
        raise ConvergenceError(f"the critical mode's integration failed: {sol.message}")
    return sol.y[:hb.n].T, complex(values[k])


def embed(z1, n, harmonics):
    """Coefficients ``z1`` (``H`` harmonics of ``w``) as those of base frequency ``w / 2`` (``2H`` harmonics)."""
    Z1 = np.reshape(z1, (2 * harmonics + 1, n))
    Z2 = np.zeros((4 * harmonics + 1, n))
    Z2[0] = Z1[0]
    for j in range(1, harmonics + 1):
        Z2[4 * j - 1], Z2[4 * j] = Z1[2 * j - 1], Z1[2 * j]
    return Z2.ravel()


def first_doubled_point(problem2, z2, lam, direction_samples, *, z_scale, l_scale, step=0.05, tol=1e-10):
    """The first point of the period-doubled branch next to the period doubling ``(z2, lam)``.

    Parameters
    ----------
    problem2 : rotorkit.periodic.continuation.ContinuationProblem
        The doubled problem (base frequency ``w / 2``, ``2H`` harmonics, ``samples`` even).
    z2 : numpy.ndarray
        The synchronous solution at the doubling, embedded (:func:`embed`).
    lam : float
        The parameter at the doubling.
    direction_samples : numpy.ndarray, shape (samples / 2, n)
        The critical mode over one period of ``w`` (:func:`critical_direction`), continued antiperiodically.
    z_scale, l_scale : float
        Scales of the amplitudes (m) and of the parameter.
    step : float
        Predictor length in scaled units (amplitudes over ``z_scale``).

    Returns
    -------
    z : numpy.ndarray
    lam : float
    """
    hb2 = problem2.hb
    _, P, _ = fourier_basis(hb2.harmonics, hb2.samples)
    phi = (P @ np.vstack([direction_samples, -direction_samples])).ravel()
    phi /= np.linalg.norm(phi)
    scales = np.concatenate([np.full(len(z2), z_scale), [l_scale]])
    t = np.append(phi, 0.0)
    u_pred = np.append(z2 / z_scale, lam / l_scale) + step * t
    scale = problem2.frame(lam).scale
    d_lam = 1e-7 * max(l_scale, abs(lam))

    def fun(u, jacobian):
        x = u * scales
        R, Jz = problem2.residual(x[:-1], float(x[-1]), jacobian=jacobian)
        F = np.append(R, scale * float(t @ (u - u_pred)))
        if not jacobian:
            return F, None
        column = problem2.parameter_derivative(x[:-1], float(x[-1]), d_lam)[:, None] * l_scale
        return F, np.vstack([np.hstack([Jz * z_scale, column]), scale * t[None, :]])

    u = newton(fun, u_pred, tol=tol, scale=scale, max_iterations=40, what="the first period-doubled point")[0]
    x = u * scales
    return x[:-1], float(x[-1])
