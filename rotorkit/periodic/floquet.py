"""The monodromy matrix of a periodic solution by exponential collocation in the modal coordinates of its linear part.

Along a periodic orbit ``y(t)`` the variational equations are
``dy' = J(t) dy`` with ``J(t) = A + N(t)``: ``A`` the state matrix of the
linear part (the system's analytic Jacobian at rest, constant) and ``N(t)``
what the local nonlinear forces (contacts, Hertzian bearings, films) add.
``N`` depends on few states (the contact coordinates and their velocities):
``N(t) = N_c(t) S``, ``S`` selecting those ``r`` states (found from the
Jacobian samples, exactly zero columns elsewhere), ``N_c`` of shape
``(2n, r)``. In the modal coordinates of ``A = V diag(lambda) V^-1``
(``x = V^-1 dy``)::

    x' = diag(lambda) x + G(t) w,   w = S V x (r rows),   G(t) = V^-1 N_c(t)

and over a step ``[t, t + h]`` (variation of constants)::

    x(t + s) = e^{lambda s} x(t) + int_0^s e^{lambda (s - u)} G(t + u) w(t + u) du.

The integrand's ``G w`` is interpolated by its values at ``q`` Gauss-Legendre
nodes ``c_i h`` (exponential collocation): the integrals of
``e^{lambda (s - u)}`` times the Lagrange polynomials are exact through the
``phi`` functions of ``lambda h``, so the linear part, however stiff (the
high bending modes of a beam rotor), is propagated exactly; the ``q r``
node values ``w_i`` solve a small linear system per step, for all ``2n``
columns of the monodromy matrix at once. A step costs two products of
``(q r, 2n) x (2n, 2n)`` and ``q`` Jacobian evaluations.

The contact forces' Jacobian jumps where an orbit meets or leaves a
stator: the steps end at those instants (roots of the system's switch
functions along the orbit, located to round-off), so each step sees a
smooth ``N`` and the scheme keeps its order (the switch functions are
scanned on 128 instants of the period: a contact shorter than that between
two of them is not seen, and its step converges at a lower order). The
multipliers are the eigenvalues of the (real) monodromy matrix
``Phi(T) = V X(T) V^-1``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["exponential_monodromy", "phi_functions", "DEFAULT_STEPS", "NODES"]

#: steps per base period (more where the period is cut by contact switches)
DEFAULT_STEPS = 32
#: Gauss-Legendre collocation nodes per step
NODES = 6


def phi_functions(z, jmax):
    """``phi_0 ... phi_jmax`` of ``z``, shape (jmax+1, *z.shape): ``phi_0 = e^z``, ``phi_{j+1} = (phi_j - 1/j!) / z``.

    The recursion for ``|z| >= 1/2``, the Taylor series ``sum_k z^k / (k + j)!`` below.
    """
    z = np.asarray(z, dtype=complex)
    out = np.empty((jmax + 1,) + z.shape, dtype=complex)
    out[0] = np.exp(z)
    small = np.abs(z) < 0.5
    with np.errstate(all="ignore"):
        for j in range(1, jmax + 1):
            out[j] = (out[j - 1] - 1.0 / math.factorial(j - 1)) / z
    if np.any(small):
        zs = z[small]
        for j in range(1, jmax + 1):
            term = np.full(zs.shape, 1.0 / math.factorial(j), dtype=complex)
            total = term.copy()
            for k in range(1, 24):
                term = term * zs / (k + j)
                total += term
            out[j][small] = total
    return out


def _orbit_states(hb, z, frame, times):
    """``y(t)`` of the harmonic-balance solution at ``times`` (s), shape (len(times), 2n)."""
    n, H = hb.n, hb.harmonics
    Z = np.reshape(z, (-1, n))
    k = np.arange(1, H + 1)
    phase = np.outer(np.asarray(times, dtype=float), k * frame.omega)
    basis = np.empty((len(times), 2 * H + 1))
    basis[:, 0], basis[:, 1::2], basis[:, 2::2] = 1.0, np.cos(phase), np.sin(phase)
    return np.hstack([basis @ Z, frame.omega * (basis @ (hb.D @ Z))])


def _switch_times(hb, z, frame, samples=128):
    """Instants in (0, T) where a switch function of the system changes sign along the orbit (s), sorted.

    Sign changes on ``samples`` instants of the period, each refined by the Illinois variant of regula falsi
    on the switch function along the (trigonometric) orbit to round-off.
    """
    if not hb.system.n_switches:
        return np.zeros(0)
    T = frame.period

    def switch(times):
        return frame.evaluator.switches(frame.point, times, _orbit_states(hb, z, frame, times))

    times = T * np.arange(samples + 1) / samples
    values = switch(times)
    found = []
    for col in range(values.shape[1]):
        v = values[:, col]
        for j in np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0):
            a, b, fa, fb = times[j], times[j + 1], v[j], v[j + 1]
            side = 0
            for _ in range(100):
                t = (a * fb - b * fa) / (fb - fa)
                if not a < t < b or b - a <= 4e-16 * T:
                    break
                ft = switch(np.array([t]))[0, col]
                if ft == 0.0:
                    a = b = t
                    break
                if np.sign(ft) == np.sign(fa):
                    a, fa = t, ft
                    fb = fb * 0.5 if side == -1 else fb
                    side = -1
                else:
                    b, fb = t, ft
                    fa = fa * 0.5 if side == 1 else fa
                    side = 1
            found.append(0.5 * (a + b))
    found = np.unique(np.array(found))
    return found[(found > 1e-12 * T) & (found < T * (1 - 1e-12))]


def _grid(T, events, steps):
    """Stretches between events as ``(start, step length, count)``: ``steps`` per period, at least one each."""
    cuts = np.concatenate([[0.0], np.sort(events), [T]])
    stretches = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        if b - a <= 1e-14 * T:
            continue
        count = max(1, math.ceil(steps * (b - a) / T - 1e-9))
        stretches.append((float(a), float(b - a) / count, count))
    return stretches


def _nonlinear_columns(frame, times, Y, A, chunk=32):
    """``(cols, N_c)``: the states on which ``J - A`` has non-zero columns along the orbit and those columns
    ``(len(times), 2n, r)``, the Jacobian evaluated ``chunk`` instants at a time (a full set would be large)."""
    m = A.shape[0]
    scale = max(float(np.max(np.abs(A))), 1e-300)
    parts = []
    for start in range(0, len(times), chunk):
        N = frame.jacobian_at(times[start:start + chunk], Y[start:start + chunk]) - A[None]
        used = np.flatnonzero(np.max(np.abs(N), axis=(0, 1)) > 1e-14 * scale)
        parts.append((used, N[:, :, used]))
    cols = np.unique(np.concatenate([used for used, _ in parts])) if parts else np.zeros(0, dtype=int)
    Nc = np.zeros((len(times), m, cols.size))
    for k, (used, block) in enumerate(parts):
        Nc[k * chunk:k * chunk + block.shape[0], :, np.searchsorted(cols, used)] = block
    return cols, Nc


def _collocation_weights(lam, h, c):
    """Per mode: ``E_k = e^{lam c_k h}`` (q+1 rows: the nodes and the step's end) and
    ``D[k, i] = int_0^{c_k h} e^{lam (c_k h - u)} l_i(u / h) du`` (q+1, q, m), ``l_i`` the Lagrange basis."""
    q = len(c)
    ends = np.append(c, 1.0)
    V = np.vander(c, q, increasing=True)  # V[i, p] = c_i^p
    coeff = np.linalg.inv(V).T  # l_i(s) = sum_p coeff[i, p] s^p
    D = np.zeros((q + 1, q, len(lam)), dtype=complex)
    E = np.zeros((q + 1, len(lam)), dtype=complex)
    for k, ck in enumerate(ends):
        phis = phi_functions(lam * ck * h, q)
        E[k] = phis[0]
        # int_0^{tau} e^{lam (tau - u)} (u/h)^p du = h c^{p+1} p! phi_{p+1}(lam c h), tau = c h
        moments = np.array([h * ck ** (p + 1) * math.factorial(p) * phis[p + 1] for p in range(q)])  # (q, m)
        D[k] = coeff @ moments
    return E, D


def exponential_monodromy(hb, z, frame, *, steps=DEFAULT_STEPS, nodes=NODES, rank_limit=None):
    """Floquet multipliers and the monodromy matrix by exponential collocation (module notes).

    Parameters
    ----------
    hb : rotorkit.periodic.hb.HarmonicBalance
        The (full, uncondensed) problem of the solution.
    z : numpy.ndarray, shape (n (2H+1),)
        Its Fourier coefficients.
    frame : rotorkit.periodic.hb.Frame
    steps : int
        Steps per base period (each period stretch between contact switches gets its share, at least one).
    nodes : int
        Gauss-Legendre nodes per step (order ``2 nodes`` on smooth stretches for the node values, at least
        ``nodes`` overall).
    rank_limit : int, optional
        Give up (return None) when the nonlinear part depends on more than this many states (default: no limit;
        with ``r`` states a step costs about ``2 nodes r / (2n)`` dense products of ``(2n, 2n)`` matrices).

    Returns
    -------
    (multipliers (2n,) complex, monodromy (2n, 2n) real) or None
        None when the linear part is not diagonalisable to a useful accuracy or the nonlinear part is not of
        low rank (the caller integrates the full variational equations instead).
    """
    n = hb.n
    m = 2 * n
    T = frame.period
    A0 = frame.jacobian_at(0.0, np.zeros((1, m)))[0]
    stretches = _grid(T, _switch_times(hb, z, frame), steps)
    c, b = np.polynomial.legendre.leggauss(nodes)
    c, b = 0.5 * (c + 1.0), 0.5 * b
    starts = np.concatenate([a + h * np.arange(count) for a, h, count in stretches])
    h_all = np.concatenate([np.full(count, h) for _, h, count in stretches])
    which = np.concatenate([np.full(count, i) for i, (_, _, count) in enumerate(stretches)])
    times = (starts[:, None] + h_all[:, None] * c[None, :]).ravel()
    cols, Nc = _nonlinear_columns(frame, times, _orbit_states(hb, z, frame, times), A0)
    if rank_limit is not None and cols.size > rank_limit:
        return None
    r = cols.size
    # the period mean of N joins the exact linear part (an averaged contact stiffness): what is left oscillates
    mean = np.einsum("t,tmr->mr", (h_all[:, None] * b[None, :]).ravel() / T, Nc)
    A = A0.copy()
    A[:, cols] += mean
    Nc -= mean[None]
    lam, V = np.linalg.eig(A)
    if not np.all(np.isfinite(lam)):
        return None
    try:
        Vinv = np.linalg.inv(V)
    except np.linalg.LinAlgError:
        return None
    if np.linalg.norm(V, 1) * np.linalg.norm(Vinv, 1) > 1e8 * m:  # the 1-norm condition (<= 2n times the
        return None  # 2-norm one, for which 1e8 is the limit) without an SVD
    X = np.eye(m, dtype=complex)
    if r:
        G = (Vinv @ Nc.transpose(1, 0, 2).reshape(m, -1)).reshape(m, len(h_all), nodes, r).transpose(1, 2, 0, 3)
        SV = V[cols]  # (r, m)
        weights = []
        for _, h, _ in stretches:
            E, D = _collocation_weights(lam, h, c)
            Q = (SV[None, :, :] * E[:nodes, None, :]).reshape(nodes * r, m)  # S V e^{lam c_k h}
            weights.append((E[nodes], D, Q))
        eye = np.eye(nodes * r)
        for s in range(len(h_all)):
            E_end, D, Q = weights[which[s]]
            Gs = G[s]  # (q, m, r)
            # K[k, i] = S V D[k, i] G_i (r x r): node values w_k = Q_k x + sum_i K[k, i] w_i
            K = np.einsum("am,kim,imb->kaib", SV, D[:nodes], Gs).reshape(nodes * r, nodes * r)
            W = np.linalg.solve(eye - K, Q @ X)  # (q r, m)
            L = (D[nodes][:, :, None] * Gs).transpose(1, 0, 2).reshape(m, nodes * r)  # step end: sum_i D_i G_i w_i
            X = E_end[:, None] * X + L @ W
    else:
        X = np.diag(np.exp(lam * T))
    Phi = (V @ X @ Vinv).real
    return np.linalg.eigvals(Phi), Phi  # real: a cheaper eigenvalue problem than X's, the same multipliers
