"""Pseudo-arclength continuation of harmonic-balance solutions in one parameter, through folds and grazing corners.

The unknowns ``u = (z / z_s, lambda / l_s)`` are scaled (``z_s`` a typical
amplitude in m or rad, ``l_s`` the width of the parameter range). From a
solution ``u_0`` with unit tangent ``t_0`` a step of length ``h`` predicts
``u_0 + h t_0 + h^2 a``, ``a = (t_0 - t_{-1}) / (2 d)`` half the second
derivative in arclength estimated from the tangent ``t_{-1}`` at the point
before, ``d`` from it; ``a`` is left out where ``h^2 |a|`` exceeds
:data:`CURVATURE_SHARE` of ``h`` (a kink between the two points: a contact
sample switching on), at the first step, after a grazing corner and, as the
compiled kernel runs in calls of :data:`rotorkit.periodic.fastpath.CHUNK` points when a progress
callback is given, at the first step of each such call. Where the step before had its
``a`` too, the cubic term of the tangents' parabola through the last three points joins it
(:func:`_cubic`: ``a`` becomes ``(f_01 + b d_1) / 2`` and ``h^3 b / 3`` is added, ``f_01``, ``f_12``
the tangents' differences over the last two steps, ``d_1``, ``d_2`` their lengths, ``b = (f_01 -
f_12) / (d_1 + d_2)``), unless ``h^3 |b|`` exceeds :data:`CURVATURE_SHARE` of ``h``: more
corrections converge in one Newton iteration. The corrector solves ``R(u) = 0`` on the hyperplane through the
prediction normal to ``t_0`` (damped Newton, :func:`rotorkit.periodic.hb.newton`
with its ``lazy_jacobian``: a trial point's Jacobian is evaluated only where
another step follows, and the tangent at the corrected point is taken with
the last one evaluated, as ``dR/dlambda`` is the one at the prediction).
Its residual scale (the convergence test's and the hyperplane row's weight) is the last point's, the forces
at rest at its parameter: computed once per point, and the point's error estimate reuses it.
The step grows by 1.5 after an easy correction (<= 3 iterations), shrinks
after a hard one, and halves after a failure, down to ``min_step``. A
corrected point farther than ``h`` from its prediction counts as a failure
(it jumped to another part of the branch).

Small speed branches run the same loop compiled (:mod:`rotorkit.periodic.fastpath` says when; the
Python loop here is the reference and the fallback).

Smooth folds need nothing more: the tangent, from the bordered system
``[dR/du; t_0^T] t = [0; 1]``, keeps its orientation through them.

Grazing corners: where an orbit just touches a stator all its contact
samples switch at once and the branch may turn back at an angle (the contact
and no-contact pieces meet at the grazing orbit with different tangents).
The step then fails whatever its length. When a failing prediction lies on
the other side of a grazing than ``u_0`` (a contact switch,
:meth:`rotorkit.System.switch_values`, positive at some AFT sample on one
side and at none on the other), the tangent
of the other piece is taken from the Jacobian at the prediction (the
analytic Jacobian there is the other side's), oriented so that it moves
into the other side as ``t_0`` did, and the step is tried along it.

The derivative of the residual with respect to the parameter is a forward
difference (the parameter enters through the base frequency, the forcing
and the matrices); the Jacobian with respect to the unknowns is the
analytic AFT one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError
from .errors import ConvergenceError
from .fastpath import CHUNK
from .hb import newton

#: the predictor's quadratic term is used where it moves the prediction by at most this share of the step:
#: a larger one comes from a kink between the last two points (a contact sample switching on), where the
#: tangents' difference is no curvature
CURVATURE_SHARE = 0.03

__all__ = ["ContinuationProblem", "ContinuationOptions", "continue_branch", "BranchPoints"]


class ContinuationProblem:
    """The harmonic-balance residual as a function of ``(z, lambda)``, ``lambda`` a model parameter.

    Parameters
    ----------
    hb : rotorkit.periodic.hb.HarmonicBalance
    parameter : str
        The continuation parameter (a name of ``hb.system.parameters``).
    """

    def __init__(self, hb, parameter):
        if parameter not in hb.system.parameters:
            import difflib

            near = difflib.get_close_matches(parameter, list(hb.system.parameters), n=3)
            hint = f" (did you mean {', '.join(near)}?)" if near else ""
            raise ParameterError(f"parameter={parameter!r} is not a parameter of {hb.system.name!r}{hint}: "
                                 f"expected one of {', '.join(sorted(hb.system.parameters))}")
        self.hb = hb
        self.parameter = parameter
        self._frames = {}

    def frame(self, lam):
        """The :class:`~rotorkit.periodic.hb.Frame` at ``parameter = lam`` (a few kept).

        Raises ConvergenceError where the model refuses the value (a spin speed at or below zero): a predictor
        or a Newton trial that lands there fails as one that does not converge, and the step is shortened
        (the values a user gives are checked before, with their own errors)."""
        lam = float(lam)
        found = self._frames.get(lam)
        if found is None:
            try:
                frame = self.hb.frame({self.parameter: lam})
            except ParameterError as exc:
                raise ConvergenceError(f"a solution at {self.parameter}={lam:g} cannot be sought: {exc}",
                                       parameter=lam) from None
            if len(self._frames) >= 16:
                self._frames.pop(next(iter(self._frames)))
            found = self._frames[lam] = frame
        return found

    def residual(self, z, lam, jacobian=True):
        return self.hb.residual(z, self.frame(lam), jacobian=jacobian)

    def parameter_derivative(self, z, lam, step):
        """``dR/dlambda`` by a forward difference of step ``step``."""
        plus = self.residual(z, lam + step, jacobian=False)[0]
        return (plus - self.residual(z, lam, jacobian=False)[0]) / step

    def solve(self, guess, lam, *, tol, max_iterations):
        """A solution at ``parameter = lam`` by :func:`~rotorkit.periodic.hb.newton` from ``guess`` (compiled
        where :mod:`rotorkit.periodic.fastpath` applies). Raises ConvergenceError."""
        from .fastpath import solve_compiled

        found = solve_compiled(self, guess, lam, tol=tol, max_iterations=max_iterations)
        if found is None:
            frame = self.frame(lam)
            return newton(lambda z, jac: self.hb.residual(z, frame, jacobian=jac), guess, tol=tol,
                          scale=frame.scale, max_iterations=max_iterations, lazy_jacobian=True)[0]
        z, converged = found
        if not converged:
            raise ConvergenceError(f"harmonic balance: no convergence in {max_iterations} Newton iterations at "
                                   f"{self.parameter}={lam:g}", residual=None)
        return z

    def contact_state(self, z, lam):
        """Per contact switch: whether it is in contact (switch function > 0) at any AFT sample, shape
        (n_switches,). A change of this state is a grazing: an orbit entering or leaving a contact."""
        from .fastpath import switches_compiled

        found = switches_compiled(self, z, lam)
        if found is not None:
            return found[1]
        frame = self.frame(lam)
        return np.any(frame.switches(self.hb.states(z, frame)) > 0.0, axis=0)

    def gap(self, z, lam):
        """Largest sampled switch value (m for a rub: the deepest penetration, negative when clear)."""
        from .fastpath import switches_compiled

        found = switches_compiled(self, z, lam)
        if found is not None:
            return found[0]
        frame = self.frame(lam)
        values = frame.switches(self.hb.states(z, frame))
        return float(np.max(values)) if values.size else 0.0


@dataclass
class ContinuationOptions:
    """Step control of :func:`continue_branch` (steps in scaled arclength, see the module notes)."""

    step: float = 0.02
    min_step: float = 1e-6
    max_step: float = 0.1
    max_points: int = 500
    tol: float = 1e-10
    max_iterations: int = 12
    #: run the compiled kernel where it applies (:mod:`rotorkit.periodic.fastpath`); False: always the Python loop
    compiled: bool = True


@dataclass
class BranchPoints:
    """Raw output of :func:`continue_branch`: solutions in order along the branch and why it stopped.

    ``parameter``, ``coefficients``, ``tangents`` and ``residuals`` hold one entry (a row) per point: lists
    from the Python loop, arrays from the compiled kernel (:func:`rotorkit.periodic.fastpath.continue_compiled`),
    which also gives ``scales``, each point's residual scale (the start's too; empty from the Python loop), and
    ``accelerations`` (n_points, N, n), each point's accelerations at its AFT samples (its last residual's; nan
    first where unknown: the start's), which the point's error estimate reuses."""

    parameter: list = field(default_factory=list)
    coefficients: list = field(default_factory=list)
    tangents: list = field(default_factory=list)
    residuals: list = field(default_factory=list)
    corners: list = field(default_factory=list)  # indices of points reached through a grazing corner
    scales: list = field(default_factory=list)
    accelerations: list = field(default_factory=list)
    reason: str = ""


def continue_branch(problem, z0, lam0, bounds, *, z_scale, options=None, progress=None):
    """Follow the branch through ``(z0, lam0)`` towards the upper bound until it leaves ``bounds``.

    Parameters
    ----------
    problem : ContinuationProblem
    z0 : numpy.ndarray, shape (size,)
        A solution at ``lam0`` (converged).
    lam0 : float
    bounds : (float, float)
        ``(start, stop)``; the branch starts towards ``stop``.
    z_scale : float
        Typical amplitude (m, rad) of the unknowns.
    options : ContinuationOptions, optional
    progress : callable, optional
        ``progress(count, lam)`` after each point.

    Returns
    -------
    BranchPoints
        The points (the start included) and the reason the branch stopped.
    """
    opts = options or ContinuationOptions()
    if opts.compiled:
        from .fastpath import continue_compiled

        out = BranchPoints()
        if continue_compiled(problem, z0, lam0, bounds, z_scale=z_scale, options=opts, out=out, progress=progress):
            return out
    start, stop = (float(b) for b in bounds)
    lo, hi = min(start, stop), max(start, stop)
    l_scale = abs(stop - start)
    scales = np.concatenate([np.full(len(z0), z_scale), [l_scale]])
    d_lam = 1e-7 * max(l_scale, abs(lam0))
    out = BranchPoints()

    def unscale(u):
        x = u * scales
        return x[:-1], float(x[-1])

    def augmented(u, jacobian):
        z, lam = unscale(u)
        R, Jz = problem.residual(z, lam, jacobian=jacobian)
        return R, Jz, z, lam

    def full_jacobian(u):
        z, lam = unscale(u)
        R, Jz = problem.residual(z, lam)
        return np.hstack([Jz * z_scale, problem.parameter_derivative(z, lam, d_lam)[:, None] * l_scale])

    def tangent(A, reference):
        t = np.linalg.solve(np.vstack([A, reference[None, :]]), np.concatenate([np.zeros(A.shape[0]), [1.0]]))
        return t / np.linalg.norm(t)

    def correct(u_pred, t, scale):
        """Newton on the hyperplane normal to ``t`` through ``u_pred``; dR/dlambda frozen at the prediction;
        ``scale`` the residual scale of the last point."""
        zp, lp = unscale(u_pred)
        column = problem.parameter_derivative(zp, lp, d_lam)[:, None] * l_scale

        def fun(u, jacobian):
            R, Jz, z, lam = augmented(u, jacobian)
            F = np.append(R, scale * float(t @ (u - u_pred)))
            if not jacobian:
                return F, None
            return F, np.vstack([np.hstack([Jz * z_scale, column]), scale * t[None, :]])

        u, iterations, norm, J = newton(fun, u_pred, tol=opts.tol, scale=scale, max_iterations=opts.max_iterations,
                                        what="continuation corrector", lazy_jacobian=True)
        return u, iterations, norm, J

    u0 = np.append(z0 / z_scale, lam0 / l_scale)
    direction = 1.0 if stop >= start else -1.0
    t0 = tangent(full_jacobian(u0), np.append(np.zeros(len(z0)), direction))
    if t0[-1] * direction < 0:
        t0 = -t0
    out.parameter.append(lam0)
    out.coefficients.append(np.array(z0))
    out.tangents.append(t0 * scales)
    out.residuals.append(0.0)
    h = opts.step
    curve = cubic = u_before = t_before = None
    scale = problem.frame(unscale(u0)[1]).scale  # the last point's residual scale: the corrector's

    def correct_here(u_pred, t):
        return correct(u_pred, t, scale)

    while True:
        if len(out.parameter) >= opts.max_points:
            out.reason = f"point budget of {opts.max_points} points reached"
            return out
        accepted = None
        try:
            if progress is not None and (len(out.parameter) - 1) % CHUNK == 0:
                curve = None  # as the compiled kernel, which runs in calls of CHUNK points and starts each afresh
            u_pred = u0 + h * t0
            if curve is not None and h * h * float(np.linalg.norm(curve)) <= CURVATURE_SHARE * h:
                u_pred = u_pred + h * h * curve
                if cubic is not None and h * h * h * float(np.linalg.norm(cubic[0])) <= CURVATURE_SHARE * h:
                    b, d1 = cubic
                    u_pred = u_pred + h * h * b * d1 / 2.0
                    u_pred = u_pred + h * h * h * b / 3.0
            u1, iterations, norm, J1 = correct_here(u_pred, t0)
            if np.linalg.norm(u1 - u_pred) <= h:
                t1 = _corrected_tangent(J1)
                if float(t1 @ t0) > 0.7 or h <= 4.0 * opts.min_step:
                    accepted = (u1, t1, iterations, norm, False)
        except (ConvergenceError, np.linalg.LinAlgError):
            pass
        if accepted is None and problem.hb.contact:
            accepted = _corner(problem, unscale, u0, t0, h, full_jacobian, tangent, correct_here)
        if accepted is None:
            h *= 0.5
            if h < opts.min_step:
                z, lam = unscale(u0)
                out.reason = (f"no convergence at the minimum step {opts.min_step:g} at {problem.parameter}="
                              f"{lam:.6g} (a branch point or a non-smooth point the corner rule does not pass)")
                return out
            continue
        u1, t1, iterations, norm, corner = accepted
        z1, lam1 = unscale(u1)
        if lam1 > hi or lam1 < lo:
            bound = hi if lam1 > hi else lo
            z_end = _at_bound(problem, unscale(u0), (z1, lam1), bound, opts)
            if z_end is not None:
                out.parameter.append(bound)
                out.coefficients.append(z_end)
                out.tangents.append(t1 * scales)
                out.residuals.append(float(np.max(np.abs(problem.residual(z_end, bound, False)[0])))
                                     / problem.frame(bound).scale)
            out.reason = f"parameter bound {problem.parameter}={bound:g} reached"
            return out
        out.parameter.append(lam1)
        out.coefficients.append(z1)
        out.tangents.append(t1 * scales)
        out.residuals.append(norm)
        scale = problem.frame(lam1).scale
        if corner:
            out.corners.append(len(out.parameter) - 1)
        if progress is not None:
            progress(len(out.parameter), lam1)
        smooth = None if corner else _curvature(u0, u1, t1, t0)
        cubic = _cubic(u_before, t_before, u0, t0, u1, t1) if smooth is not None and curve is not None else None
        curve = smooth
        u_before, t_before = u0, t0
        u0, t0 = u1, t1
        h = min(opts.max_step, h * 1.5) if iterations <= 3 else (h * 0.6 if iterations >= 7 else h)


def _curvature(before, u0, t0, t_before):
    """Half the second derivative in arclength at ``u0`` from the tangents there and at the point ``before`` it,
    ``(t0 - t_before) / (2 d)`` with ``d = |u0 - before|`` (None if ``d`` is zero): the predictor's quadratic
    term. From the tangents rather than the positions, which the corrector leaves on the branch only to its
    tolerance (extrapolating them would amplify their scatter along the branch)."""
    d = float(np.linalg.norm(u0 - before))
    if d == 0.0:
        return None
    return (t0 - t_before) / (2.0 * d)


def _cubic(before, t_before, u0, t0, u1, t1):
    """The predictor's cubic term at ``u1`` from the tangents at the last three points: ``(b, d_1)``, ``b = (f_01 -
    f_12) / (d_1 + d_2)`` the second divided difference of the tangents in arclength (``f_01 = (t1 - t0) / d_1``,
    ``f_12 = (t0 - t_before) / d_2``, ``d_1 = |u1 - u0|``, ``d_2 = |u0 - before|``, both nonzero where the
    quadratic terms of the two steps exist): the tangents' parabola ``t(s) = t1 + (f_01 + b d_1) s + b s^2``
    integrated over a step ``h`` gives ``h t1 + h^2 (f_01 + b d_1) / 2 + h^3 b / 3``, whose ``h^2 f_01 / 2`` is the
    quadratic term."""
    d1 = float(np.linalg.norm(u1 - u0))
    d2 = float(np.linalg.norm(u0 - before))
    return ((t1 - t0) / d1 - (t0 - t_before) / d2) / (d1 + d2), d1


def _corrected_tangent(J):
    """The unit tangent at a corrected point from the corrector's Newton matrix ``J = [A; s t^T]`` (``A`` the
    residual's Jacobian rows as the corrector last evaluated them, ``s > 0`` the residual scale, ``t`` the
    step's tangent): ``J^-1 [0; 1]`` normalised, which solves ``[A; t^T] t_1 = [0; 1]`` up to its length."""
    t = np.linalg.solve(J, np.append(np.zeros(J.shape[0] - 1), 1.0))
    return t / np.linalg.norm(t)


def _corner(problem, unscale, u0, t0, h, full_jacobian, tangent, correct):
    """A step along the other piece's tangent when the prediction crosses a contact switch (None if not)."""
    u_pred = u0 + h * t0
    z0, lam0 = unscale(u0)
    zp, lamp = unscale(u_pred)
    if np.array_equal(problem.contact_state(z0, lam0), problem.contact_state(zp, lamp)):
        return None
    try:
        t1 = tangent(full_jacobian(u_pred), t0)
    except np.linalg.LinAlgError:
        return None
    g0 = problem.gap(z0, lam0)
    into = problem.gap(zp, lamp) - g0
    along = problem.gap(*unscale(u0 + h * t1)) - g0
    if along * into < 0:
        t1 = -t1
    try:
        u1, iterations, norm, J1 = correct(u0 + h * t1, t1)
    except (ConvergenceError, np.linalg.LinAlgError):
        return None
    if np.linalg.norm(u1 - (u0 + h * t1)) > h:
        return None
    z1, lam1 = unscale(u1)
    if np.array_equal(problem.contact_state(z1, lam1), problem.contact_state(z0, lam0)):
        return None  # back on the piece it came from
    t_new = _corrected_tangent(J1)
    return u1, t_new, iterations, norm, True


def _at_bound(problem, before, after, bound, opts):
    """The solution at ``lambda = bound`` from the two points either side of it (linear interpolation, Newton)."""
    (za, la), (zb, lb) = before, after
    w = 0.0 if lb == la else (bound - la) / (lb - la)
    guess = za + w * (zb - za)
    frame = problem.frame(bound)
    try:
        z = newton(lambda z, jac: problem.hb.residual(z, frame, jacobian=jac), guess, tol=opts.tol,
                   scale=frame.scale, max_iterations=opts.max_iterations, what="solution at the bound",
                   lazy_jacobian=True)[0]
    except ConvergenceError:
        return None
    return z if math.isfinite(float(np.max(np.abs(z)))) else None
