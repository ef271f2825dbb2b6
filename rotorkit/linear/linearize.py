"""Operating point and linearisation of a compiled system: static equilibrium and Jacobian.

Everything works on a compiled :class:`~rotorkit.system.System` (its
``rhs(t, y)``), so it covers whatever the model holds, contacts included,
without re-deriving anything:

- :func:`static_equilibrium` finds the coordinates ``q*`` where the
  accelerations vanish with zero velocities (the gravity-loaded rest
  position); unbalance forcing is periodic, not static, so it is switched
  off by default.
- :func:`linearize` returns the ``2n x 2n`` Jacobian ``A = d rhs / d y`` at
  ``(q*, q' = 0)``: the analytic one when the system has it, else central
  finite differences.

The private helpers (parameter checks, rotor speeds, cage sampling) are
shared by the modal, Campbell and frequency-response modules.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError

__all__ = ["static_equilibrium", "linearize", "check_system", "check_time", "check_coordinates", "without_unbalance",
           "sample_times", "rub_stators", "difference_steps", "DEFAULT_RELATIVE_STEP", "DEFAULT_CAGE_SAMPLES",
           "DEFAULT_EQUILIBRIUM_TOL"]

#: Default relative finite-difference step (about the cube root of the machine epsilon).
DEFAULT_RELATIVE_STEP = 1e-6
#: Smallest typical magnitude of a displacement (m) or an angle (rad) used to scale the steps.
_FLOOR_SCALE = 1e-6
#: Default number of cage positions averaged over one ball-passing period.
DEFAULT_CAGE_SAMPLES = 16
#: Equilibrium residual tolerance, relative to the load acceleration at q = 0.
DEFAULT_EQUILIBRIUM_TOL = 1e-9
#: Units of rounding (machine epsilon times the size of the terms that cancel, |J| |q| + |a(0)|) within which an
#: equilibrium residual counts as converged even above ``tol``: a stiff model's floor.
ROUNDING_FACTOR = 16


def check_system(system, who):
    if not (hasattr(system, "rhs") and hasattr(system, "coordinate_names") and hasattr(system, "state_names")):
        hint = "; compile it first: model.compile()" if hasattr(system, "compile") else ""
        raise TypeError(f"{who}: expected a compiled rotorkit System, got {type(system).__name__}{hint}")


def check_time(t, name="t"):
    if isinstance(t, bool) or not isinstance(t, numbers.Real) or not math.isfinite(t):
        raise ParameterError(f"{name}={t!r} is invalid: expected a finite time (s)")
    return float(t)


def check_coordinates(q, n, name="q"):
    try:
        arr = np.array(q, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name}={q!r} is invalid: expected {n} coordinates (m, rad)") from exc
    if arr.shape != (n,):
        raise ParameterError(f"{name} has shape {arr.shape}: expected ({n},), one value per coordinate")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} contains NaN or inf: expected finite coordinates (m, rad)")
    return arr


def _is_angle(name):
    return name.startswith("alpha")


def without_unbalance(system):
    """``system`` with every disk eccentricity (``*_eccentricity``) set to 0 (itself if all are 0)."""
    zeros = {name: 0.0 for name, v in system.parameters.items() if name.endswith("_eccentricity") and v != 0.0}
    return system.with_parameters(**zeros) if zeros else system


def _accelerations(system, t, q):
    n = q.size
    return system.rhs(t, np.concatenate([q, np.zeros(n)]))[n:]


def _typical_scales(names, q):
    """Typical magnitude of each coordinate (m or rad): the largest |q| of its kind, floored."""
    angle = np.array([_is_angle(s) for s in names], dtype=bool)
    scales = np.empty(len(names))
    for mask in (angle, ~angle):
        if mask.any():
            scales[mask] = max(float(np.max(np.abs(q[mask]))), _FLOOR_SCALE)
    return scales


def _position_steps(names, q, relative):
    return relative * np.maximum(np.abs(q), _typical_scales(names, q))


def _coordinate_jacobian(system, t, q, steps):
    """d(accelerations)/dq (n x n) by central differences."""
    n = q.size
    J = np.empty((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = steps[j]
        J[:, j] = (_accelerations(system, t, q + e) - _accelerations(system, t, q - e)) / (2.0 * steps[j])
    return J


def _rotor_speeds(system, t=0.0):
    """Rotor name -> spin speed (rad/s) at time ``t`` (a speed profile evaluated there)."""
    from .rotor_speeds import rotor_spin_speeds

    return rotor_spin_speeds(system.model, t, system.parameters)


def _ball_pass_period(system, t=0.0):
    """Longest ball-passing period (s) of the model's ball bearings at time ``t``, or None if no cage turns."""
    from ..elements import BallBearing

    bearings = [e for e in system.model.elements if isinstance(e, BallBearing)]
    if not bearings:
        return None
    speeds = _rotor_speeds(system, t)
    values = system.parameters
    periods = []
    for b in bearings:
        label = b.label()
        ri, ro = values[f"{label}_inner_race_radius"], values[f"{label}_outer_race_radius"]
        wi = speeds[system.model.rotor_of(b.inner_station).name]
        wo = speeds[system.model.rotor_of(b.outer_station).name]
        cage = (wi * ri + wo * ro) / (ri + ro)
        if cage != 0.0:
            periods.append(2.0 * math.pi / (b.n_balls * abs(cage)))
    return max(periods) if periods else None


def sample_times(system, t, count):
    """``count`` times over one ball-passing period from ``t``, on ``t``'s side of any time event."""
    period = _ball_pass_period(system, t)
    if period is None or count == 1:
        return np.array([t])
    events = [e for e in system.time_events if np.isfinite(e)]
    after = [e for e in events if e > t]
    before = [e for e in events if e <= t]
    offsets = period * np.arange(count) / count
    if not after or t + offsets[-1] < min(after):
        return t + offsets
    if not before or t - offsets[-1] >= max(before):
        return t - offsets
    return t + offsets * (min(after) - t) / period  # segment shorter than a period: sample what there is


def rub_stators(system):
    from ..elements import RubStator

    return [e for e in system.model.elements if isinstance(e, RubStator)]


# ---------------------------------------------------------------------------
# Static equilibrium
# ---------------------------------------------------------------------------


def static_equilibrium(system, t=0.0, *, unbalance=False, q0=None, tol=DEFAULT_EQUILIBRIUM_TOL,
                       max_evaluations=None):
    """Coordinates where the accelerations vanish with zero velocities.

    Solves ``a(q) = rhs(t, [q, 0])[n:] = 0``: the rest position under the
    static loads at time ``t`` (gravity, a steady manoeuvre load, contact
    and bearing forces), e.g. the gravity sag of a rotor.

    Parameters
    ----------
    system : rotorkit.System
    t : float
        Time (s) at which the loads are evaluated (the ball angles of a
        bearing and the manoeuvre depend on it).
    unbalance : bool
        False (default): evaluate with every disk eccentricity (parameters
        ending in ``_eccentricity``) set to zero, since unbalance forcing is
        periodic, not static. True: keep it, as a frozen snapshot at ``t``.
    q0 : array_like, shape (n,), optional
        Starting guess (m, rad). Default: the linear solution
        ``-J0^-1 a(0)`` (``K^-1 F`` with the contacts as they are at q = 0).
    tol : float
        Convergence: ``max |a_i(q*)|`` below ``tol`` times the largest load
        acceleration at ``q = 0`` (m/s^2, rad/s^2), or, where that lies
        below the rounding of the terms that cancel in ``a_i`` (stiff
        beams: ``K q / M`` much larger than the loads), within
        ``ROUNDING_FACTOR`` machine epsilons of them.
    max_evaluations : int, optional
        Most residual evaluations of each root-finder attempt (scipy's
        ``maxfev``; default scipy's).

    Returns
    -------
    numpy.ndarray, shape (n,)
        ``q*`` in :attr:`~rotorkit.System.coordinate_names` order (m, rad).

    Raises
    ------
    ParameterError
        If the solver does not converge; the message names the coordinate
        with the largest residual acceleration.

    Notes
    -----
    The residual is piecewise smooth (ramp contacts, Hertzian bearings), so
    the solve starts from the linear solution and uses scipy's ``hybr``
    (Powell's dog-leg trust region) with a central-difference Jacobian, in
    coordinates scaled by their typical magnitude; if that fails it retries
    with Levenberg-Marquardt (``lm``).

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Maneuver, Model
    >>> system = Model([Rotor(name="R", stations=(1,), speed=0.0),
    ...                 Disk(station=1, mass=2.0, radius=0.1),
    ...                 ElasticSupport(station=1, stiffness=2e4),
    ...                 Maneuver.steady(gravity=9.81)]).compile(backend="python")
    >>> q = static_equilibrium(system)
    >>> round(float(q[1]) / (-2.0 * 9.81 / 2e4), 9)   # y1 = -m g / k
    1.0
    """
    from scipy import optimize

    check_system(system, "static_equilibrium")
    t = check_time(t)
    driven = [r.name for r in getattr(getattr(system, "model", None), "rotors", {}).values()
              if getattr(r, "drive", None) is not None]
    if driven:
        raise ParameterError(
            f"static_equilibrium: the speed of rotor {driven[0]!r} is a degree of freedom (Drive), whose spin has no "
            "static equilibrium; analyse the model at a frozen speed: "
            "rotorkit.analysis.linear_matrices.frozen_speed_model(model).compile() (the campbell and linear_model "
            "analyses freeze it at its initial_speed themselves)")
    if not isinstance(unbalance, bool):
        raise ParameterError(f"unbalance={unbalance!r} is invalid: expected True or False")
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real) or not 0 < tol < 1:
        raise ParameterError(f"tol={tol!r} is invalid: expected a number in (0, 1)")
    if max_evaluations is not None and (isinstance(max_evaluations, bool)
                                        or not isinstance(max_evaluations, numbers.Integral)
                                        or max_evaluations < 1):
        raise ParameterError(f"max_evaluations={max_evaluations!r} is invalid: expected an integer >= 1")
    names = tuple(system.coordinate_names)
    n = len(names)
    if q0 is not None:
        q0 = check_coordinates(q0, n, "q0")
    if not unbalance:
        system = without_unbalance(system)

    zero = np.zeros(n)
    a_zero = _accelerations(system, t, zero)
    _check_finite(a_zero, names, "the accelerations at q = 0")
    load = float(np.max(np.abs(a_zero)))
    if q0 is None and load == 0.0:
        return zero  # nothing loads the rotor: the undeflected axis is at rest
    if q0 is None:
        J0 = _coordinate_jacobian(system, t, zero, _position_steps(names, zero, DEFAULT_RELATIVE_STEP))
        q0 = -np.linalg.lstsq(J0, a_zero, rcond=None)[0]
    a_start = _accelerations(system, t, q0)
    _check_finite(a_start, names, "the accelerations at the starting point")
    reference = load if load > 0.0 else float(np.max(np.abs(a_start)))
    if reference == 0.0:
        return q0  # q0 is an equilibrium of an unloaded rotor
    threshold = tol * reference
    scale = _typical_scales(names, q0)

    def residual(z):
        return _accelerations(system, t, z * scale) / reference

    def jacobian(z):
        q = z * scale
        return _coordinate_jacobian(system, t, q, _position_steps(names, q, DEFAULT_RELATIVE_STEP)) * scale / reference

    def converged(q, res):
        if np.max(res) <= threshold:
            return True
        # a stiff model's accelerations are differences of terms much larger than the loads (K q / M): below the
        # rounding of those terms no solver gets closer, so that floor counts as converged too
        J = _coordinate_jacobian(system, t, q, _position_steps(names, q, DEFAULT_RELATIVE_STEP))
        floor = ROUNDING_FACTOR * np.finfo(float).eps * (np.abs(J) @ np.abs(q) + np.abs(a_zero))
        return bool(np.all(res <= np.maximum(threshold, floor)))

    limit = {"hybr": "maxfev", "lm": "maxiter"}
    best, best_res = q0, np.abs(a_start)
    if converged(best, best_res):
        return best
    for solver in ("hybr", "lm"):
        start = best / scale
        with np.errstate(all="ignore"):
            options = {} if max_evaluations is None else {limit[solver]: int(max_evaluations)}
            sol = optimize.root(residual, start, jac=jacobian, method=solver, options=options)
        q = sol.x * scale
        res = np.abs(_accelerations(system, t, q))
        if np.all(np.isfinite(res)) and np.max(res) < np.max(best_res):
            best, best_res = q, res
        if converged(best, best_res):
            return best
    worst = int(np.argmax(best_res))
    raise ParameterError(
        f"static_equilibrium did not converge at t={t:g} s: the largest residual acceleration is "
        f"d2({names[worst]})/dt2 = {best_res[worst]:.3g} (tolerance {threshold:.3g}; load scale "
        f"{load:.3g}); the contacts may make the equilibrium non-smooth or not unique, or the model "
        "may have no static equilibrium (a rotor without stiffness path to a support?); try another "
        "q0=..., a larger max_evaluations or a looser tol"
    )


def _check_finite(values, names, what):
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise ParameterError(f"{what} are not finite at {', '.join(names[i] for i in bad[:5])}: check the parameters")


# ---------------------------------------------------------------------------
# Linearisation
# ---------------------------------------------------------------------------


def linearize(system, q, t=0.0, *, eps=None, method="auto"):
    """Jacobian of ``system.rhs`` at ``(q, q' = 0)``.

    Parameters
    ----------
    system : rotorkit.System
    q : array_like, shape (n,)
        Coordinates (m, rad), in :attr:`~rotorkit.System.coordinate_names` order.
    t : float
        Time (s).
    eps : None, float or array_like of shape (2n,)
        Finite-difference steps. None: relative step ``1e-6`` (see Notes);
        a float: that relative step; an array: the absolute step of each
        state (m, rad, m/s, rad/s).
    method : {"fd", "analytic", "auto"}
        ``"fd"``: central finite differences of ``system.rhs``.
        ``"analytic"``: the system's own Jacobian ``system.jacobian(t, y)``
        (generated from the symbolic equations, where available).
        ``"auto"`` (default): analytic if the system has one
        (``system.has_jacobian``), else finite differences.

    Returns
    -------
    A : numpy.ndarray, shape (2n, 2n)
        ``d rhs / d y`` (1/s and 1/s^2 blocks): ``A[:n, n:]`` is the identity,
        ``A[n:, :n]`` is ``-M^-1 K_eff`` and ``A[n:, n:]`` is ``-M^-1 C_eff``.
    state_names : tuple of str, length 2n
        The order of rows and columns (:attr:`~rotorkit.System.state_names`).

    Notes
    -----
    Central differences, one state at a time. The step of a coordinate is
    ``eps * max(|q_i|, L)`` with ``L`` the largest ``|q|`` of its kind
    (displacements in m or angles in rad), at least ``1e-6``; the step of a
    velocity is the step of its coordinate times ``omega_ref``, the square
    root of the largest entry of ``|A[n:, :n]|`` (so that ``h_v / h_q`` is a
    typical frequency). The right-hand side is affine in the velocities at
    ``q' = 0`` apart from terms even in them, so these columns are exact up
    to rounding. At a contact kink (a ramp at exactly its clearance) the
    difference straddles the kink and gives the mean of the two slopes.

    At a contact kink the analytic Jacobian differentiates a ramp
    one-sidedly (its step is 0 exactly at the kink) while finite differences
    average the two slopes; away from kinks the two agree. A disk centred in
    a stator of zero clearance is no kink: the force ``-k_r (x, y)`` is
    linear there and both give its stiffness.

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Model
    >>> system = Model([Rotor(name="R", stations=(1,), speed=0.0),
    ...                 Disk(station=1, mass=2.0, radius=0.1),
    ...                 ElasticSupport(station=1, stiffness=2e4, damping=4.0)]).compile(backend="python")
    >>> A, names = linearize(system, [0.0, 0.0])
    >>> names
    ('x1', 'y1', 'x1_dot', 'y1_dot')
    >>> A[2].round(6).tolist()   # x1'' = -k/m x1 - c/m x1'
    [-10000.0, 0.0, -2.0, 0.0]
    """
    check_system(system, "linearize")
    t = check_time(t)
    names = tuple(system.coordinate_names)
    n = len(names)
    q = check_coordinates(q, n)
    y0 = np.concatenate([q, np.zeros(n)])
    state_names = tuple(system.state_names)

    if method not in ("fd", "analytic", "auto"):
        raise ParameterError(f"method={method!r} is unknown; expected 'fd', 'analytic' or 'auto'")
    has_exact = bool(getattr(system, "has_jacobian", False)) and callable(getattr(system, "jacobian", None))
    if method == "analytic" and not has_exact:
        raise ParameterError(f"method='analytic': system {system.name!r} has no analytic Jacobian; use method='fd'")
    steps = difference_steps(names, q, eps)  # validates eps whatever the method
    if method == "analytic" or (method == "auto" and has_exact):
        A = np.array(system.jacobian(t, y0), dtype=float)
        if A.shape != (2 * n, 2 * n):
            raise ParameterError(f"system.jacobian returned shape {A.shape}: expected ({2 * n}, {2 * n})")
        _check_finite(A.ravel(), [f"d({a})/d({b})" for a in state_names for b in state_names], "Jacobian entries")
        return A, state_names

    f0 = system.rhs(t, y0)
    _check_finite(f0, state_names, f"rhs at t={t:g} s")
    A = np.empty((2 * n, 2 * n))
    for j in range(n):
        e = np.zeros(2 * n)
        e[j] = steps[j]
        A[:, j] = (system.rhs(t, y0 + e) - system.rhs(t, y0 - e)) / (2.0 * steps[j])
    if steps.size == n:  # velocity steps from the position block
        omega_ref = math.sqrt(max(float(np.max(np.abs(A[n:, :n]))), 1.0))
        steps = np.concatenate([steps, steps * omega_ref])
    for j in range(n, 2 * n):
        e = np.zeros(2 * n)
        e[j] = steps[j]
        A[:, j] = (system.rhs(t, y0 + e) - system.rhs(t, y0 - e)) / (2.0 * steps[j])
    _check_finite(A.ravel(), [f"d({a})/d({b})" for a in state_names for b in state_names], "Jacobian entries")
    return A, state_names


def difference_steps(names, q, eps):
    """Coordinate steps (n,) from a relative ``eps``, or all 2n steps from an array."""
    n = len(names)
    if eps is None:
        return _position_steps(names, q, DEFAULT_RELATIVE_STEP)
    if isinstance(eps, numbers.Real) and not isinstance(eps, bool):
        if not (math.isfinite(eps) and 0 < eps < 1):
            raise ParameterError(f"eps={eps!r} is invalid: expected a relative step in (0, 1), e.g. 1e-6")
        return _position_steps(names, q, float(eps))
    try:
        steps = np.array(eps, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"eps={eps!r} is invalid: expected None, a relative step or {2 * n} steps") from exc
    if steps.shape != (2 * n,) or not np.all(np.isfinite(steps)) or np.any(steps <= 0):
        raise ParameterError(
            f"eps has shape {steps.shape}: expected a relative step or ({2 * n},) positive absolute steps "
            "(m, rad for coordinates, m/s, rad/s for velocities)"
        )
    return steps
