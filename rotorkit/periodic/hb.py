"""Harmonic balance of a compiled system, the nonlinear forces by alternating frequency-time (AFT) evaluation.

Conventions
-----------
The base frequency is ``w = Omega / nu`` (``Omega`` the spin speed named by
``speed_parameter``, ``nu`` the sub-harmonic order) and ``tau = w t``. A
coordinate is ``q(t) = a_0 + sum_k (a_k cos(k tau) + b_k sin(k tau))``,
``k = 1 ... H``; the unknowns ``z`` are these real coefficients, harmonic
first: ``z = [a_0 (n), a_1 (n), b_1 (n), ..., a_H (n), b_H (n)]``. The
complex amplitude of harmonic ``k`` is ``a_k - i b_k`` (``q = Re(Q e^{ik tau})``,
the convention of :func:`rotorkit.linear.unbalance.unbalance_response`).

The equations ``M (q'' - a(t, q, q')) = 0``, with ``a`` the accelerations of
the compiled right-hand side, are split as ``a = A_q q + A_v q' + g(t, q, q')``
with ``A`` the system's analytic Jacobian at the undeflected axis, so that the
linear part ``M q'' + C q' + K q`` (``K = -M A_q``, ``C = -M A_v``: damping,
gyroscopic, speed-dependent bearings at the current parameters) is exact per
harmonic in the frequency domain. The rest, ``M g`` (contacts, Hertzian
bearings, unbalance and gravity), is sampled at ``N`` instants of one period
and projected back (AFT); its Jacobian comes from the system's analytic
Jacobian at the same instants, projected the same way. The residual is a
force (N) per coordinate and harmonic.
"""

from __future__ import annotations

import functools
import math
import numbers

import numpy as np

from ..errors import ParameterError
from .errors import ConvergenceError, NoOscillatingInput

__all__ = ["HarmonicBalance", "Frame", "fourier_basis", "default_samples", "DEFAULT_TOLERANCE", "newton",
           "newton_from_linear"]

#: Newton stops when max |R| (N) <= DEFAULT_TOLERANCE * scale, scale the largest oscillating force amplitude at rest
DEFAULT_TOLERANCE = 1e-10


def default_samples(harmonics, contact):
    """``N``: the power of two >= ``4 (H + 1)`` (smooth forces), ``>= 8 (H + 1)`` with contacts (kinks alias more)."""
    return 1 << math.ceil(math.log2((8 if contact else 4) * (harmonics + 1)))


@functools.lru_cache(maxsize=32)
def fourier_basis(harmonics, samples):
    """``(E, P, D)``: synthesis (N, 2H+1), analysis (2H+1, N) and d/dtau (2H+1, 2H+1) of the real coefficients.

    Made once per ``(H, N)`` and shared by every caller: read them, do not change them in place."""
    H, N = harmonics, samples
    tau = 2.0 * np.pi * np.arange(N) / N
    E = np.ones((N, 2 * H + 1))
    D = np.zeros((2 * H + 1, 2 * H + 1))
    for k in range(1, H + 1):
        E[:, 2 * k - 1], E[:, 2 * k] = np.cos(k * tau), np.sin(k * tau)
        D[2 * k - 1, 2 * k], D[2 * k, 2 * k - 1] = k, -k
    P = E.T * (2.0 / N)
    P[0] *= 0.5
    return E, P, D


def _check_int(value, name, low):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
        raise ParameterError(f"{name}={value!r} is invalid: expected an integer >= {low}")
    return int(value)


class Frame:
    """The harmonic-balance problem at one set of parameter values (built by :meth:`HarmonicBalance.frame`).

    Attributes
    ----------
    values : dict
        The parameter values (SI) changed from the system's.
    omega : float
        Base frequency ``w = Omega / nu`` (rad/s).
    mass, damping, stiffness : numpy.ndarray, shape (n, n)
        ``M``, ``C = -M A_v`` and ``K = -M A_q`` of the linear part (SI).
    times : numpy.ndarray, shape (N,)
        The AFT instants ``2 pi j / (N w)`` (s).
    forcing, scale
        See the properties (computed on use).
    """

    def __init__(self, hb, values):
        self.values = dict(values)
        self.evaluator = hb.evaluator
        self.point = hb.evaluator.point(self.values)
        merged = dict(hb._parameters)
        merged.update(self.values)
        speed = float(merged[hb.speed_parameter])
        if not math.isfinite(speed) or speed <= 0.0:
            raise ParameterError(f"{hb.speed_parameter}={speed!r} is invalid: the periodic response needs a "
                                 "positive spin speed (rad/s)")
        n = hb.n
        self.omega = speed / hb.subharmonic
        self.period = 2.0 * np.pi / self.omega
        self.times = self.period * np.arange(hb.samples) / hb.samples
        A = self.jacobian_at(0.0, np.zeros((1, 2 * n)))[0]
        self.Aq, self.Av = A[n:, :n].copy(), A[n:, n:].copy()
        self.A = np.ascontiguousarray(A[n:])  # (n, 2n): g = a - y @ A.T
        self.mass = hb.mass_matrix(merged)
        self.stiffness, self.damping = -self.mass @ self.Aq, -self.mass @ self.Av
        self._linear = self._kron_operators = None
        self._hb, self._speed, self._scale, self._forcing = hb, speed, None, None

    @property
    def forcing(self):
        """Coefficients of the forces at rest ``M a(t, 0, 0)``, shape (2H+1, n) (N, N m)."""
        if self._forcing is None:
            n = self._hb.n
            rest = self.accelerations(np.zeros((self._hb.samples, 2 * n)))[:, n:] @ self.mass.T
            self._forcing = self._hb.P @ rest
        return self._forcing

    @property
    def scale(self):
        """Largest amplitude of an oscillating harmonic of :attr:`forcing` (N): the residual's scale.

        Raises
        ------
        NoOscillatingInput
            If it is zero.
        """
        if self._scale is None:
            forcing = self.forcing
            amplitudes = np.hypot(forcing[1::2], forcing[2::2])
            scale = float(np.max(amplitudes)) if amplitudes.size else 0.0
            if not scale > 1e-300:
                raise NoOscillatingInput(
                    f"{self._hb.system.name}: nothing drives a periodic response at {self._hb.speed_parameter}="
                    f"{self._speed:g} rad/s (no unbalance, no periodic force: every disk eccentricity is 0?); the "
                    "steady state is static (rotorkit.linear.static)")
            self._scale = scale
        return self._scale

    @property
    def _inertia(self):
        """``M (w D)^2`` per harmonic, (size, size)."""
        return self._operators()[0]

    @property
    def _derivative(self):
        """``w D`` per coordinate, (size, size)."""
        return self._operators()[1]

    @property
    def _blocks(self):
        """``(K, C)`` per harmonic, block diagonal, (size, size) each."""
        return self._operators()[2]

    def _operators(self):
        if self._kron_operators is None:
            hb, w = self._hb, self.omega
            I = np.eye(2 * hb.harmonics + 1)
            self._kron_operators = (block_kron(w * w * (hb.D @ hb.D), self.mass), block_kron(w * hb.D, np.eye(hb.n)),
                                    (block_kron(I, self.stiffness), block_kron(I, self.damping)))
        return self._kron_operators

    def accelerations(self, Y):
        """``rhs`` at the AFT instants for the states ``Y`` (N, 2n): shape (N, 2n)."""
        return self.evaluator.rhs(self.point, self.times, Y)

    def jacobians(self, Y):
        """The analytic Jacobian of ``rhs`` at the AFT instants for the states ``Y`` (N, 2n): (N, 2n, 2n)."""
        return self.evaluator.jacobian(self.point, self.times, Y)

    def accelerations_and_jacobians(self, Y):
        """:meth:`accelerations` and :meth:`jacobians` of the same states together."""
        return self.evaluator.rhs_and_jacobian(self.point, self.times, Y)

    def jacobian_block(self, Y, rows, cols):
        """Rows ``rows`` and columns ``cols`` of :meth:`jacobians`, (N, len(rows), len(cols))."""
        return self.evaluator.jacobian_block(self.point, self.times, Y, rows, cols)

    def rhs_at(self, times, Y):
        """``rhs`` at any instants ``times`` (s, broadcast to the rows of ``Y``)."""
        return self.evaluator.rhs(self.point, times, Y)

    def jacobian_at(self, times, Y):
        """The analytic Jacobian at any instants."""
        return self.evaluator.jacobian(self.point, times, Y)

    def switches(self, Y):
        """Contact switch functions at the AFT instants, shape (N, n_switches)."""
        return self.evaluator.switches(self.point, self.times, Y)


def block_kron(a, b):
    """``numpy.kron`` of two 2-D arrays without its generality (called per frame)."""
    return (a[:, None, :, None] * b[None, :, None, :]).reshape(a.shape[0] * b.shape[0], a.shape[1] * b.shape[1])


class HarmonicBalance:
    """Residual and Jacobian of the harmonic-balance equations of a compiled system.

    Parameters
    ----------
    system : rotorkit.System
        A compiled model with an analytic Jacobian.
    speed_parameter : str
        The parameter holding the spin speed ``Omega`` (rad/s) that sets the base frequency.
    harmonics : int
        ``H >= 1``.
    subharmonic : int
        ``nu >= 1``: the base frequency is ``Omega / nu``.
    samples : int, optional
        AFT samples per period ``N >= 2H + 1``; default :func:`default_samples`.
    """

    def __init__(self, system, *, speed_parameter, harmonics, subharmonic=1, samples=None):
        if not (hasattr(system, "rhs") and hasattr(system, "jacobian") and hasattr(system, "coordinate_names")):
            raise TypeError(f"HarmonicBalance: expected a compiled rotorkit System, got {type(system).__name__}")
        from ..linear.modal_damping import refuse_time_run

        refuse_time_run(getattr(system, "model", None), "HarmonicBalance")  # its rhs leaves a ModalDamping out
        self.system = system
        self.harmonics = _check_int(harmonics, "harmonics", 1)
        self.subharmonic = _check_int(subharmonic, "subharmonic", 1)
        if speed_parameter not in system.parameters:
            raise ParameterError(f"speed_parameter={speed_parameter!r} is not a parameter of {system.name!r}: "
                                 f"expected one of {sorted(system.parameters)}")
        self.speed_parameter = speed_parameter
        self.contact = system.n_switches > 0
        default = default_samples(self.harmonics, self.contact)
        self.samples = default if samples is None else _check_int(samples, "samples", 2 * self.harmonics + 1)
        self.n = len(system.coordinate_names)
        self.coordinate_names = tuple(system.coordinate_names)
        self.E, self.P, self.D = fourier_basis(self.harmonics, self.samples)
        self.ED = self.E @ self.D
        self._mass = _mass_function(system.model)
        self._parameters = system.parameters
        self._grids = {}
        from .evaluate import Evaluator

        self.evaluator = Evaluator(system)

    @property
    def size(self):
        """Number of unknowns ``n (2H + 1)``."""
        return self.n * (2 * self.harmonics + 1)

    def mass_matrix(self, values):
        """The constant part of the derived mass matrix at ``values`` (eccentricities 0), shape (n, n)."""
        return self._mass(values)

    def frame(self, values=None):
        """The :class:`Frame` at the system's parameters with ``values`` (name -> SI value) changed."""
        return Frame(self, values or {})

    def states(self, z, frame):
        """Coordinates and velocities at the AFT instants, shape (N, 2n)."""
        Z = np.reshape(z, (-1, self.n))
        Y = np.empty((self.samples, 2 * self.n))
        np.matmul(self.E, Z, out=Y[:, :self.n])
        np.matmul(self.ED, Z, out=Y[:, self.n:])
        Y[:, self.n:] *= frame.omega
        return Y

    def linear_operator(self, frame):
        """The exact linear part ``K - (k w)^2 M`` and ``k w C`` per harmonic, as one (size, size) matrix."""
        if frame._linear is None:
            n, H, w = self.n, self.harmonics, frame.omega
            L = np.zeros((2 * H + 1, n, 2 * H + 1, n))
            L[0, :, 0, :] = frame.stiffness
            k = np.arange(1, H + 1)
            a, b = 2 * k - 1, 2 * k
            # rows (a_k, b_k): (K - (kw)^2 M) a_k + kw C b_k and -kw C a_k + (K - (kw)^2 M) b_k, i.e. kron(w D, C)
            # with D[a_k, b_k] = k, D[b_k, a_k] = -k
            diagonal = frame.stiffness[None] - ((k * w) ** 2)[:, None, None] * frame.mass[None]
            coupling = (k * w)[:, None, None] * frame.damping[None]
            L[a, :, a, :] = diagonal
            L[b, :, b, :] = diagonal
            L[a, :, b, :] = coupling
            L[b, :, a, :] = -coupling
            frame._linear = L.reshape((2 * H + 1) * n, (2 * H + 1) * n)
        return frame._linear

    def residual(self, z, frame, jacobian=True):
        """``(R, dR/dz)``: the residual (N, N m) of every coordinate and harmonic, and its Jacobian (or None).

        ``R = L(w) z - P [M g(t_j, q_j, q'_j)]`` with ``L`` :meth:`linear_operator`.
        """
        n = self.n
        Y = self.states(z, frame)
        if jacobian:
            a, A = frame.accelerations_and_jacobians(Y)
        else:
            a = frame.accelerations(Y)
        g = a[:, n:] - Y @ frame.A.T
        R = self.linear_operator(frame) @ z - (self.P @ (g @ frame.mass.T)).ravel()
        if not math.isfinite(float(R @ R)):
            raise ConvergenceError(f"the residual is not finite at the amplitudes {np.max(np.abs(z)):.3g}: "
                                   "the iteration diverged", residual=math.inf)
        if not jacobian:
            return R, None
        # J = L - P [Fq E + Fv (w E D)]: the AFT-projected force Jacobians, one product for both
        Fq = frame.mass @ (A[:, n:, :n] - frame.Aq)
        Fv = frame.mass @ (A[:, n:, n:] - frame.Av)
        return R, self.linear_operator(frame) - self._project(Fq, Fv, frame.omega)

    def tangent(self, z, frame, states=None):
        """Stiffness and damping operators ``(Kt, Ct)`` (size, size) of the linearised equations about ``z``.

        ``Kt`` and ``Ct`` hold the linear part plus the AFT-projected analytic
        Jacobian of the nonlinear forces with respect to the coordinates and
        to the velocities; the Jacobian of the residual is
        ``Kt + Ct (w D) + M (w D)^2`` and Hill's method uses them as they are.
        """
        n = self.n
        Y = self.states(z, frame) if states is None else states
        A = frame.jacobians(Y)
        Jq = A[:, n:, :n] - frame.Aq
        Jv = A[:, n:, n:] - frame.Av
        Fq = frame.mass @ Jq  # force Jacobians (N/m ...) at the samples, (N, n, n)
        Fv = frame.mass @ Jv
        K0, C0 = frame._blocks
        Kt = K0 - self._project(Fq)
        Ct = C0 - self._project(Fv)
        return Kt, Ct

    def _project(self, F, Fv=None, omega=0.0):
        """``sum_j P[c, j] F[j, i, l] E[j, d]`` as a (size, size) matrix (rows c n + i, columns d n + l);
        with ``Fv``, ``omega`` also ``+ sum_j P[c, j] Fv[j, i, l] omega (E D)[j, d]``."""
        n, H2, N = F.shape[1], 2 * self.harmonics + 1, self.samples
        A = self.E[:, :, None] * F.reshape(N, 1, n * n)  # (j, d, i l)
        if Fv is not None:
            A += (omega * self.ED)[:, :, None] * Fv.reshape(N, 1, n * n)
        out = (self.P @ A.reshape(N, -1)).reshape(H2, H2, n, n)  # (c, d, i, l): one product
        return out.transpose(0, 2, 1, 3).reshape(H2 * n, H2 * n)

    def time_residual(self, z, frame, samples):
        """``M (q'' - a(t, q, q'))`` (N, N m) on ``samples`` instants of one period, shape (samples, n)."""
        found = self._grids.get(samples)
        if found is None:
            E, _, D = fourier_basis(self.harmonics, samples)
            found = self._grids[samples] = (E, E @ D, E @ D @ D)
        E, ED, EDD = found
        Z = np.reshape(z, (-1, self.n))
        w = frame.omega
        times = 2.0 * np.pi * np.arange(samples) / (samples * w)
        Y = np.hstack([E @ Z, w * (ED @ Z)])
        acc = w * w * (EDD @ Z)
        a = frame.rhs_at(times, Y)[:, self.n:]
        return (acc - a) @ frame.mass.T


_MASS_FUNCTIONS = {}


def _mass_function(model):
    """``values -> M`` from the derived constant mass matrix (eccentricities 0); one per model structure."""
    found = _MASS_FUNCTIONS.get(model.structure_key)
    if found is None:
        if len(_MASS_FUNCTIONS) > 16:
            _MASS_FUNCTIONS.clear()
        found = _MASS_FUNCTIONS[model.structure_key] = _new_mass_function(model)
    return found


def _new_mass_function(model):
    """The constant part of the derived mass matrix (:meth:`EquationsOfMotion.linear_mass_matrix`'s rule) as a
    function of the parameters, from its non-zero entries generated once per structure
    (:func:`rotorkit.periodic.derived.periodic_module`, cached on disk)."""
    from .derived import periodic_module

    module = periodic_module(model)
    n = module.N_COORDINATES
    names = module.MASS_NAMES
    f = module.mass_entries
    rows, cols = np.array(module.MASS_ROWS, dtype=np.int64), np.array(module.MASS_COLS, dtype=np.int64)

    found = {}

    def mass(values):
        args = tuple(0.0 if name.endswith("_eccentricity") else float(values[name]) for name in names)
        if args not in found:
            if len(found) > 32:
                found.clear()
            M = np.zeros((n, n))
            np.add.at(M, (rows, cols), np.array(f(*args), dtype=float))
            found[args] = M
        return found[args]

    return mass


def newton(fun, z0, *, tol, scale, max_iterations=30, what="harmonic balance", lazy_jacobian=False):
    """Damped Newton: ``fun(z, jacobian) -> (R, J)``; stops when ``max |R| <= tol * scale``.

    The damping factor ``s`` (1, 1/2, ... down to 1/128) is the first that
    passes the natural monotonicity test (Deuflhard): the simplified Newton
    correction at ``z + s dz``, ``J(z)^-1 R(z + s dz)``, is shorter than
    ``(1 - s / 4) |dz|``. It measures progress in the unknowns rather than
    in the forces, whose size changes by the contact stiffness across a
    contact boundary.

    With ``lazy_jacobian`` the trial points are evaluated without their
    Jacobian, which is asked for only where another step follows: the
    converged point's Jacobian is then the last one evaluated (at the
    iterate before it, or at ``z0``).

    Returns
    -------
    z : numpy.ndarray
    iterations : int
    norm : float
        The final ``max |R| / scale``.
    J : numpy.ndarray
        The Jacobian at ``z`` (with ``lazy_jacobian``: the last one evaluated).

    Raises
    ------
    ConvergenceError
        If ``max_iterations`` pass first.
    """
    lu_factor, lu_solve = _lu_functions()
    z = np.array(z0, dtype=float)
    R, J = fun(z, True)
    current = True  # J is the Jacobian at z
    norm = float(np.max(np.abs(R))) / scale
    for iteration in range(max_iterations + 1):
        if norm <= tol:
            return z, iteration, norm, J
        if iteration == max_iterations:
            break
        if not current:
            R, J = fun(z, True)
        lu = lu_factor(J)
        dz = lu_solve(lu, -R)
        size = float(np.linalg.norm(dz))
        step = 1.0
        J_new = None
        while True:
            try:
                # the full step is nearly always taken: its Jacobian is evaluated with its residual
                R_new, J_new = fun(z + step * dz, step == 1.0 and not lazy_jacobian)
                ok = float(np.linalg.norm(lu_solve(lu, -R_new))) <= (1.0 - step / 4.0) * size
            except ConvergenceError:
                ok = False
            if ok or step < 1.0 / 128.0:
                break
            step *= 0.5
        z = z + step * dz
        if ok and lazy_jacobian:
            R, current = R_new, False
        elif ok and J_new is not None:
            R, J = R_new, J_new
        else:
            R, J = fun(z, True)
            current = True
        norm = float(np.max(np.abs(R))) / scale
    raise ConvergenceError(f"{what}: no convergence in {max_iterations} Newton iterations (residual {norm:.3g} "
                           f"relative; tolerance {tol:g})", residual=norm)


def newton_from_linear(fun, z0, *, tol, scale, max_iterations=30, what="harmonic balance", min_step=1e-4):
    """:func:`newton`, and if it fails from ``z0``, a homotopy from the linearised problem at ``z0``.

    ``R_s(z) = (1 - s) (R(z0) + J(z0) (z - z0)) + s R(z)``: at ``s = 0`` its
    solution is one Newton step from ``z0`` (from zero: the linear response);
    ``s`` is raised to 1 in adaptive steps (from 0.1, times 1.5 after a
    success, halved after a failure down to ``min_step``), each solved by
    :func:`newton` from the previous solution extrapolated along ``s`` (to
    ``max(tol, 1e-6)`` on the way). At ``s = 1`` it is the problem itself,
    solved to ``tol``.

    Returns and raises as :func:`newton` with ``lazy_jacobian`` (no Jacobian at the converged point: a solution
    at a fixed parameter needs none; the iterates are the same), the iteration count summed.
    """
    try:
        return newton(fun, z0, tol=tol, scale=scale, max_iterations=max_iterations, what=what, lazy_jacobian=True)
    except ConvergenceError as exc:
        first = exc
    z0 = np.array(z0, dtype=float)
    R0, J0 = fun(z0, True)

    def blended(s):
        def f(z, jacobian):
            R, J = fun(z, jacobian)
            Rs = (1.0 - s) * (R0 + J0 @ (z - z0)) + s * R
            return Rs, (None if J is None else (1.0 - s) * J0 + s * J)
        return f

    z = z0 - np.linalg.solve(J0, R0)
    s, ds, total, previous = 0.0, 0.1, 0, None
    while s < 1.0:
        target = min(1.0, s + ds)
        guess = z if previous is None else z + (z - previous[0]) * (target - s) / (s - previous[1])
        try:
            z_new, iterations = newton(blended(target), guess, tol=tol if target == 1.0 else max(tol, 1e-6),
                                       scale=scale, max_iterations=max_iterations, what=what,
                                       lazy_jacobian=True)[:2]
        except (ConvergenceError, np.linalg.LinAlgError):
            ds *= 0.5
            if ds < min_step:
                raise ConvergenceError(f"{first}; the homotopy from the linear response stalled at s = {s:.4g}",
                                       residual=first.residual) from None
            continue
        total += iterations
        previous, z, s = (z, s), z_new, target
        ds *= 1.5
    R, J = fun(z, True)
    return z, total, float(np.max(np.abs(R))) / scale, J


_LU = []


def _lu_functions():
    """``(factor, solve)``: LAPACK's getrf/getrs without scipy's per-call checks (the matrices are small)."""
    if not _LU:
        from scipy.linalg import LinAlgError
        from scipy.linalg.lapack import get_lapack_funcs

        getrf, getrs = get_lapack_funcs(("getrf", "getrs"), (np.zeros((1, 1)),))

        def factor(A):
            lu, piv, info = getrf(A, overwrite_a=False)
            if info < 0:
                raise ValueError(f"getrf: illegal value in argument {-info}")
            if info > 0:  # singular: as scipy's lu_factor, warn-free; the solve gives inf/nan, caught by callers
                pass
            return lu, piv

        def solve(lu, b):
            x, info = getrs(lu[0], lu[1], b)
            if info != 0:
                raise LinAlgError(f"getrs: info {info}")
            return x

        _LU.append((factor, solve))
    return _LU[0]
