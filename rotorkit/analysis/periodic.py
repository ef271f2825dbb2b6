"""Periodic response of a nonlinear rotor: harmonic balance, continuation, Floquet stability, bifurcations.

:func:`periodic_response` follows the periodic steady state of a model with
rub, Hertzian bearings or other local nonlinearities over a range of its
speed; :func:`continuation` does the same in any other parameter
(clearance, friction coefficient, unbalance, a bearing coefficient). Both
return a :class:`~rotorkit.periodic.branch.Branch` with the Fourier
coefficients, the stability (Floquet multipliers), bifurcations and error
estimates of each point. The method and its conventions are in
:mod:`rotorkit.periodic` and on the documentation page *Periodic response*.

Examples
--------
>>> from rotorkit import Disk, ElasticSupport, Model, Rotor
>>> model = Model([Rotor(name="R", stations=(1,), speed=50.0),
...                Disk(station=1, mass=2.0, radius=0.1, eccentricity=1e-5, torsion=False),
...                ElasticSupport(station=1, stiffness=2e4, damping=4.0)])
>>> branch = periodic_response(model, speeds=(50.0, 150.0), harmonics=1, backend="python")
>>> bool(branch.stable.all()), round(float(branch.max_radius(1).max() / 1e-5), 1)   # peak e / (2 zeta)
(True, 50.0)
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError
from ..periodic.errors import ConvergenceError, NoOscillatingInput

__all__ = ["periodic_response", "continuation", "periodic_solution", "period_doubled_branch", "ConvergenceError",
           "NoOscillatingInput"]

#: truncation-error grid: this many times the AFT samples
ERROR_GRID_FACTOR = 4
STABILITY_METHODS = ("hill", "monodromy", "none")


def _system(model_or_system, backend):
    if hasattr(model_or_system, "compile") and hasattr(model_or_system, "equations"):
        return model_or_system.compile(backend=backend)
    if not (hasattr(model_or_system, "rhs") and hasattr(model_or_system, "jacobian")):
        raise TypeError(f"expected a rotorkit Model or System, got {type(model_or_system).__name__}")
    return model_or_system


def _speed_parameter(system, speed_parameter):
    model = system.model
    available = [f"{name}_speed" for name, r in model.rotors.items() if r.speed is not None and r.profile is None]
    if speed_parameter is None:
        if not available:
            raise ParameterError(f"{system.name!r} has no rotor with a constant speed of its own: the periodic "
                                 "response needs one (freeze a speed profile with "
                                 "rotorkit.analysis.linear_matrices.frozen_speed_model)")
        return available[0]
    if speed_parameter not in available:
        raise ParameterError(f"speed_parameter={speed_parameter!r} is not a constant rotor speed: expected one of "
                             f"{available}")
    return speed_parameter


def _check_parameter(system, name):
    if not isinstance(name, str) or name not in system.parameters:
        import difflib

        near = difflib.get_close_matches(str(name), list(system.parameters), n=3)
        hint = f" (did you mean {', '.join(near)}?)" if near else ""
        raise ParameterError(f"parameter {name!r} is unknown{hint}: expected one of "
                             f"{', '.join(sorted(system.parameters))}")
    return name


def _range(system, name, values, what):
    from ..units import to_si

    unit = system.model.parameter_units.get(name, "")
    try:
        start, stop = values
    except (TypeError, ValueError):
        raise ParameterError(f"{what}={values!r} is invalid: expected (start, stop)") from None
    start, stop = (to_si(v, unit, f"{what} of {name}") for v in (start, stop))
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise ParameterError(f"{what}={values!r} is invalid: expected finite values")
    if start == stop:
        raise ParameterError(f"{what}=({start:g}, {stop:g}) has zero width: expected start != stop")
    current = system.parameters.get(name)
    for v in (start, stop):
        if v != current:  # the element checks its value (sign, range); the current one it has checked
            _check_value(system.model, name, v)
    return start, stop


_CHECKED = {}


def _check_value(model, name, value):
    """``model.with_values(name=value)``'s checks (the element's and the model's), once per model and value: a
    model is immutable, so a value it accepted stays accepted (a few recent ones kept)."""
    key = (id(model), name, value)
    if _CHECKED.get(key) is model:
        return
    model.with_values(**{name: value})
    if len(_CHECKED) >= 64:
        _CHECKED.pop(next(iter(_CHECKED)))
    _CHECKED[key] = model


def _count(value, name, low):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
        raise ParameterError(f"{name}={value!r} is invalid: expected an integer >= {low}")
    return int(value)


def _positive(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not (math.isfinite(value) and value > 0):
        raise ParameterError(f"{name}={value!r} is invalid: expected a positive number")
    return float(value)


def _linear_scale(problem, start, stop):
    """Largest amplitude of the response with the nonlinear forces as at rest, over 33 parameter values."""
    from ..periodic.fastpath import linear_scale_compiled

    hb = problem.hb
    biggest = linear_scale_compiled(problem, np.linspace(start, stop, 33))
    if biggest is not None:
        return biggest if biggest > 0 else 1.0
    biggest = 0.0
    z = np.zeros(hb.size)
    for lam in np.linspace(start, stop, 33):
        frame = problem.frame(lam)
        R, J = hb.residual(z, frame)
        try:
            biggest = max(biggest, float(np.max(np.abs(np.linalg.solve(J, -R)))))
        except np.linalg.LinAlgError:
            continue
    return biggest if biggest > 0 else 1.0


def continuation(model_or_system, parameter, values, *, speed_parameter=None, harmonics=5, subharmonic=1,
                 samples=None, start=None, stability="hill", tol=None, step=0.02, min_step=1e-6, max_step=0.1,
                 max_points=500, amplitude_scale=None, condense="auto", backend="auto", progress=None):
    """Follow the periodic steady state of a model as ``parameter`` goes from ``values[0]`` to ``values[1]``.

    Parameters
    ----------
    model_or_system : rotorkit.Model or rotorkit.System
        A model is compiled (``backend``). Every rotor speed is constant.
    parameter : str
        Any parameter of the model (``R_speed``, ``rub1_clearance``, ``disk1_eccentricity``, ...).
    values : (start, stop)
        Range of ``parameter`` (SI floats, pint quantities or strings with units); the branch starts at
        ``start`` and may turn back at folds; it ends when it leaves the range.
    speed_parameter : str, optional
        The rotor speed that sets the base frequency ``w = Omega / nu`` (default: the first rotor's).
    harmonics : int
        ``H >= 1`` harmonics of ``w``.
    subharmonic : int
        ``nu >= 1``: 1 for synchronous solutions, 2, 3, ... for sub-harmonic ones.
    samples : int, optional
        AFT samples per period, ``>= 2H + 1``; default the power of two ``>= 4 (H + 1)``, ``>= 8 (H + 1)``
        with contacts.
    start : array_like, shape (2H + 1, n), optional
        Fourier coefficients to start Newton from at ``values[0]`` (default zero: the linear response). If
        Newton fails from there, a homotopy from the problem linearised at the start to the full one is
        followed (:func:`rotorkit.periodic.hb.newton_from_linear`).
    stability : {"hill", "monodromy", "none"}
        How the Floquet multipliers are computed (:mod:`rotorkit.periodic.stability`).
    tol : float, optional
        Newton tolerance on ``max |R|`` (N) relative to the largest oscillating force at rest (default 1e-10).
    step, min_step, max_step : float
        Arclength steps in scaled units (amplitudes over ``amplitude_scale``, the parameter over the range).
    max_points : int
        Point budget.
    amplitude_scale : float, optional
        Typical amplitude (m, rad); default the largest amplitude of the response with the nonlinear forces
        frozen at rest over the range.
    condense : {"auto", True, False} or sequence of str
        Solve for the coordinates where nonlinear forces act only (exact condensation through the dynamic
        stiffness of the linear part, :mod:`rotorkit.periodic.condensed`), then expand to all coordinates.
        ``"auto"``: when the model has at least ``CONDENSE_FROM`` coordinates and nonlinear forces on at most
        half of them; a sequence names the coordinates kept.
    backend : str
        For a model: how to compile it (``"c"`` is the fast path).
    progress : callable, optional
        ``progress(count, value)`` after each point.

    Returns
    -------
    rotorkit.periodic.branch.Branch

    Raises
    ------
    ParameterError
        An unknown parameter, a range of zero width, ``H < 1``, bad options.
    NoOscillatingInput
        Nothing periodic drives the model (no unbalance, no periodic force).
    ConvergenceError
        Newton does not converge at ``values[0]``.
    """
    from ..periodic.continuation import ContinuationOptions, ContinuationProblem, continue_branch
    from ..periodic.hb import DEFAULT_TOLERANCE

    system = _system(model_or_system, backend)
    speed_parameter = _speed_parameter(system, speed_parameter)
    parameter = _check_parameter(system, parameter)
    harmonics = _count(harmonics, "harmonics", 1)
    subharmonic = _count(subharmonic, "subharmonic", 1)
    lo, hi = _range(system, parameter, values, "values")
    if stability not in STABILITY_METHODS:
        raise ParameterError(f"stability={stability!r} is unknown: expected one of {STABILITY_METHODS}")
    tol = DEFAULT_TOLERANCE if tol is None else _positive(tol, "tol")
    options = ContinuationOptions(step=_positive(step, "step"), min_step=_positive(min_step, "min_step"),
                                  max_step=_positive(max_step, "max_step"),
                                  max_points=_count(max_points, "max_points", 2), tol=tol)
    hb = _harmonic_balance(system, condense, speed_parameter=speed_parameter, harmonics=harmonics,
                           subharmonic=subharmonic, samples=samples)
    problem = ContinuationProblem(hb, parameter)
    z0 = _start_solution(problem, np.zeros(hb.size) if start is None else _start(start, hb), lo, tol)
    scale = _linear_scale(problem, lo, hi) if amplitude_scale is None else _positive(amplitude_scale,
                                                                                      "amplitude_scale")
    points = continue_branch(problem, z0, lo, (lo, hi), z_scale=scale, options=options, progress=progress)
    return _branch(problem, points, stability)


def _start_solution(problem, z0, lam, tol):
    """The solution at ``parameter = lam`` from ``z0``: Newton (:func:`~rotorkit.periodic.hb.newton`, by the
    compiled kernel where :mod:`rotorkit.periodic.fastpath` applies: the same iteration), else, or if it does not
    converge, :func:`~rotorkit.periodic.hb.newton_from_linear`'s Newton and homotopy."""
    from ..periodic.fastpath import solve_compiled
    from ..periodic.hb import newton_from_linear

    found = solve_compiled(problem, z0, lam, tol=tol, max_iterations=50)
    if found is not None and found[1] and np.all(np.isfinite(found[0])):
        return found[0]
    hb, frame = problem.hb, problem.frame(lam)
    try:
        return newton_from_linear(lambda z, jac: hb.residual(z, frame, jacobian=jac), z0, tol=tol,
                                  scale=frame.scale, max_iterations=50,
                                  what=f"the solution at {problem.parameter}={lam:g}")[0]
    except ConvergenceError as exc:
        raise ConvergenceError(f"{exc}; give start=... coefficients near a solution, or start the range where the "
                               "response is nearly linear", residual=exc.residual, parameter=lam) from None


#: ``condense="auto"`` condenses models with at least this many coordinates
CONDENSE_FROM = 12


def _harmonic_balance(system, condense, **options):
    """The plain or the condensed harmonic balance of ``system`` (see ``condense`` in :func:`continuation`),
    kept for the next call with the same system and settings (a few kept): it depends on nothing else, and a
    system never changes (its ``parameters`` are a copy)."""
    try:
        key = (id(system), tuple(condense) if isinstance(condense, list) else condense, tuple(sorted(options.items())))
        found = _KEPT.get(key)
    except TypeError:  # an unhashable setting: checked (and named) when the harmonic balance is made
        key, found = None, None
    if found is not None and found[0] is system:
        return found[1]
    hb = _new_harmonic_balance(system, condense, **options)
    if key is not None:
        if len(_KEPT) >= 8:
            _KEPT.pop(next(iter(_KEPT)))
        _KEPT[key] = (system, hb)
    return hb


_KEPT = {}


def _new_harmonic_balance(system, condense, **options):
    from ..periodic.condensed import CondensedHarmonicBalance, nonlinear_coordinates
    from ..periodic.hb import HarmonicBalance

    n = len(system.coordinate_names)
    if isinstance(condense, str) and condense == "auto":
        if n < CONDENSE_FROM:
            return HarmonicBalance(system, **options)
        kept = nonlinear_coordinates(system.model)
        if not kept or len(kept) > n // 2:
            return HarmonicBalance(system, **options)
        return CondensedHarmonicBalance(system, coordinates=kept, **options)
    if condense is False or condense is None:
        return HarmonicBalance(system, **options)
    if condense is True:
        return CondensedHarmonicBalance(system, **options)
    if isinstance(condense, str) or not all(isinstance(c, str) for c in condense):
        raise ParameterError(f"condense={condense!r} is invalid: expected 'auto', True, False or coordinate names")
    return CondensedHarmonicBalance(system, coordinates=tuple(condense), **options)


def _start(start, hb):
    try:
        z = np.array(start, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("start is invalid: expected Fourier coefficients of shape (2H + 1, n)") from None
    if z.shape != (2 * hb.harmonics + 1, hb.n):
        raise ParameterError(f"start has shape {z.shape}: expected ({2 * hb.harmonics + 1}, {hb.n})")
    kept = getattr(hb, "kept", None)
    return (z if kept is None else z[:, kept]).ravel()


def periodic_response(model_or_system, *, speeds, speed_parameter=None, harmonics=5, **options):
    """The periodic response of a rotor over a range of its speed: :func:`continuation` in ``speed_parameter``.

    Parameters
    ----------
    model_or_system : rotorkit.Model or rotorkit.System
    speeds : (start, stop)
        Speed range (rad/s, or quantities such as ``"3000 rpm"``).
    speed_parameter : str, optional
        ``<rotor>_speed`` (default: the first rotor's).
    harmonics : int
        ``H >= 1``.
    **options
        As for :func:`continuation` (``subharmonic``, ``stability``, ``samples``, ``tol``, ``max_points``, ...).

    Returns
    -------
    rotorkit.periodic.branch.Branch
    """
    system = _system(model_or_system, options.pop("backend", "auto"))
    speed_parameter = _speed_parameter(system, speed_parameter)
    return continuation(system, speed_parameter, speeds, speed_parameter=speed_parameter, harmonics=harmonics,
                        **options)


def periodic_solution(model_or_system, *, harmonics=5, speed_parameter=None, subharmonic=1, samples=None,
                      start=None, stability="hill", tol=None, error_tol=None, max_harmonics=64, condense="auto",
                      backend="auto", **values):
    """One periodic solution at the model's parameters (``values``: some changed, SI), as a one-point Branch.

    Parameters
    ----------
    harmonics : int
        ``H >= 1`` (the first one tried when ``error_tol`` is given).
    error_tol : float, optional
        Raise ``H`` (by half, at least by 2, up to ``max_harmonics``) until the share of the highest
        harmonic (:attr:`~rotorkit.periodic.branch.Branch.harmonic_share`) is below ``error_tol``; each
        solve starts from the previous solution.
    max_harmonics : int
        Upper limit of ``H`` for ``error_tol``.
    Other parameters as in :func:`continuation`; ``values``: parameter name -> value (SI).

    Raises
    ------
    ConvergenceError
        If Newton does not converge from ``start`` (default: zero, i.e. the linear response), nor the homotopy
        from the problem linearised there (:func:`rotorkit.periodic.hb.newton_from_linear`), or ``error_tol``
        is not met with ``max_harmonics``.
    """
    if error_tol is not None:
        error_tol = _positive(error_tol, "error_tol")
        H = _count(harmonics, "harmonics", 1)
        max_harmonics = _count(max_harmonics, "max_harmonics", H)
        while True:
            branch = periodic_solution(model_or_system, harmonics=H, speed_parameter=speed_parameter,
                                       subharmonic=subharmonic, samples=None, start=start, stability=stability,
                                       tol=tol, condense=condense, backend=backend, **values)
            if branch.harmonic_share[0] <= error_tol:
                return branch
            if H >= max_harmonics:
                raise ConvergenceError(f"the share of harmonic {H} is {branch.harmonic_share[0]:.3g} > error_tol="
                                       f"{error_tol:g} with max_harmonics={max_harmonics}", residual=None)
            new = min(max_harmonics, max(H + 2, int(1.5 * H)))
            start = np.vstack([branch.coefficients[0], np.zeros((2 * (new - H), branch.coefficients.shape[2]))])
            H = new
    from ..periodic.continuation import BranchPoints, ContinuationProblem
    from ..periodic.hb import DEFAULT_TOLERANCE, newton_from_linear

    system = _system(model_or_system, backend)
    if values:
        for name in values:
            _check_parameter(system, name)
        system = system.with_parameters(**values)
    speed_parameter = _speed_parameter(system, speed_parameter)
    if stability not in STABILITY_METHODS:
        raise ParameterError(f"stability={stability!r} is unknown: expected one of {STABILITY_METHODS}")
    tol = DEFAULT_TOLERANCE if tol is None else _positive(tol, "tol")
    hb = _harmonic_balance(system, condense, speed_parameter=speed_parameter,
                           harmonics=_count(harmonics, "harmonics", 1),
                           subharmonic=_count(subharmonic, "subharmonic", 1), samples=samples)
    problem = ContinuationProblem(hb, speed_parameter)
    lam = system.parameters[speed_parameter]
    frame = problem.frame(lam)
    z0 = np.zeros(hb.size) if start is None else _start(start, hb)
    z = newton_from_linear(lambda z, jac: hb.residual(z, frame, jacobian=jac), z0, tol=tol, scale=frame.scale,
                           max_iterations=50)[0]
    points = BranchPoints(parameter=[lam], coefficients=[z], tangents=[np.zeros(hb.size + 1)], residuals=[0.0],
                          reason="single solution")
    return _branch(problem, points, stability)


def period_doubled_branch(model_or_system, branch, *, stop=None, bifurcation=None, step=0.05, backend="auto",
                          **options):
    """Switch at a period doubling of ``branch`` onto the period-doubled branch and follow it.

    The synchronous solution at the doubling is recomputed there; the critical Floquet mode (multiplier
    ``-1``, from the monodromy matrix and the variational equations over one period) gives the direction in
    which the doubled branch leaves it in the harmonic balance of half the base frequency
    (:mod:`rotorkit.periodic.switching`); one predictor-corrector step along it finds the first doubled point,
    from which :func:`continuation` follows the branch with sub-harmonic order ``2 nu`` and ``2 H`` harmonics.

    Parameters
    ----------
    model_or_system : rotorkit.Model or rotorkit.System
        The model of ``branch``.
    branch : rotorkit.periodic.branch.Branch
        A branch with a ``"period doubling"`` among its bifurcations (stability not ``"none"``).
    stop : float, optional
        Where the doubled branch ends (SI or a quantity; default: the end of ``branch``'s range on the side
        where the doubled branch leaves the doubling). It starts next to the doubling.
    bifurcation : rotorkit.periodic.branch.Bifurcation, optional
        Which period doubling (default the first).
    step : float
        Predictor length, in amplitudes over the largest amplitude of the synchronous solution.
    **options
        As for :func:`continuation` (``stability``, ``max_points``, ``tol``, ...).

    Returns
    -------
    rotorkit.periodic.branch.Branch
        With ``subharmonic == 2 * branch.subharmonic`` and ``2 * branch.harmonics`` harmonics; its first
        point lies next to the doubling (one predictor step along the critical mode). The switch and the
        doubled branch use the full (not condensed) harmonic balance.

    Raises
    ------
    ParameterError
        If ``branch`` has no period doubling.
    ConvergenceError
        If no doubled solution is found next to the doubling.
    """
    from ..periodic.continuation import ContinuationProblem
    from ..periodic.hb import DEFAULT_TOLERANCE, HarmonicBalance, newton
    from ..periodic.switching import critical_direction, embed, first_doubled_point

    system = _system(model_or_system, backend)
    if bifurcation is None:
        found = [b for b in branch.bifurcations if b.kind == "period doubling"]
        if not found:
            raise ParameterError("branch has no period doubling among its bifurcations "
                                 f"{[b.kind for b in branch.bifurcations]}: expected a branch computed with "
                                 "stability='hill' or 'monodromy' that crosses one")
        bifurcation = found[0]
    elif bifurcation.kind != "period doubling":
        raise ParameterError(f"bifurcation is a {bifurcation.kind!r}: expected a 'period doubling'")
    parameter, H, nu = branch.parameter_name, branch.harmonics, branch.subharmonic
    tol = options.get("tol") or DEFAULT_TOLERANCE
    hb1 = HarmonicBalance(system, speed_parameter=branch.speed_parameter, harmonics=H, subharmonic=nu,
                          samples=branch.samples)
    problem1 = ContinuationProblem(hb1, parameter)
    lam = float(bifurcation.parameter)
    frame1 = problem1.frame(lam)
    i = bifurcation.index
    w = (lam - branch.parameter[i]) / (branch.parameter[i + 1] - branch.parameter[i])
    guess = ((1 - w) * branch.coefficients[i] + w * branch.coefficients[i + 1]).ravel()
    z1 = newton(lambda z, jac: hb1.residual(z, frame1, jacobian=jac), guess, tol=tol, scale=frame1.scale,
                max_iterations=50, what=f"the synchronous solution at the period doubling {parameter}={lam:g}",
                lazy_jacobian=True)[0]
    samples, multiplier = critical_direction(hb1, z1, frame1)
    hb2 = HarmonicBalance(system, speed_parameter=branch.speed_parameter, harmonics=2 * H, subharmonic=2 * nu,
                          samples=2 * hb1.samples)
    problem2 = ContinuationProblem(hb2, parameter)
    z_scale = float(np.max(np.abs(z1))) or 1.0
    l_scale = float(np.ptp(branch.parameter)) or abs(lam) or 1.0
    step = _positive(step, "step")
    z2, lam2 = first_doubled_point(problem2, embed(z1, hb1.n, H), lam, samples, z_scale=z_scale, l_scale=l_scale,
                                   step=step, tol=tol)
    # the side the doubled branch leaves on: where a point twice as far from the old branch lies
    lam3 = first_doubled_point(problem2, embed(z1, hb1.n, H), lam, samples, z_scale=z_scale, l_scale=l_scale,
                               step=2 * step, tol=tol)[1]
    if stop is None:
        stop = float(np.max(branch.parameter) if lam3 >= lam2 else np.min(branch.parameter))
    else:
        stop = _range(system, parameter, (lam2, stop), "stop")[1]
    options.setdefault("amplitude_scale", z_scale)
    return continuation(system, parameter, (lam2, stop), speed_parameter=branch.speed_parameter, harmonics=2 * H,
                        subharmonic=2 * nu, samples=2 * hb1.samples, start=z2.reshape(4 * H + 1, hb1.n),
                        condense=False, **options)


def _branch(problem, points, stability):
    """The :class:`Branch` of the raw continuation output: error estimates, stability and bifurcations."""
    from ..periodic.branch import Bifurcation, Branch
    from ..periodic.crossings import crossing_point
    from ..periodic.fastpath import point_data
    from ..periodic.folds import grazing_point, turning_point
    from ..periodic.stability import STABILITY_TOL, classify_crossing, hill_multipliers, monodromy_multipliers

    hb = problem.hb
    full = getattr(hb, "full", hb)  # the condensed problem's full harmonic balance
    n, H = hb.n, hb.harmonics
    # (the compiled continuation's points are arrays, the Python loop's lists; ndarray methods rather than numpy's
    # functions below: a branch of a small system spends a good part of its time in such calls)
    lam = np.array(points.parameter, dtype=float)
    count = len(lam)
    raw = np.array(points.coefficients, dtype=float).reshape(count, -1)  # one row per point
    if full is not hb:
        Z = np.array([hb.expand(z, problem.frame(v)) for z, v in zip(raw, lam)]).reshape(count, 2 * H + 1, n)
    else:
        Z = raw.reshape(count, 2 * H + 1, n)
    omega, errors, multipliers = [], [], []
    squares = Z[:, 1:] ** 2
    squares = squares[:, 0::2] + squares[:, 1::2]  # (points, H, n): amplitudes squared (m^2: no overflow)
    top = squares.reshape(count, -1).max(axis=1)
    shares = np.sqrt(squares[:, -1].max(axis=1) / np.where(top > 0, top, 1.0))
    given = len(points.scales) == count  # the continuation kernel's scales and accelerations
    compiled = None if full is not hb else point_data(
        problem, lam, Z, stability, ERROR_GRID_FACTOR, points.scales if given else None,
        points.accelerations if given else None)
    if compiled is not None:  # the same quantities by the compiled kernel (rotorkit.periodic.fastpath)
        omega, errors, mu = compiled
    else:
        for value, z in zip(lam, Z):
            frame = problem.frame(value)
            omega.append(frame.omega)
            r = full.time_residual(z.ravel(), frame, ERROR_GRID_FACTOR * hb.samples)
            errors.append(float(np.max(np.abs(r))) / frame.scale)
            if stability == "hill":
                multipliers.append(hill_multipliers(full, z.ravel(), frame))
            elif stability == "monodromy":
                multipliers.append(monodromy_multipliers(full, z.ravel(), frame)[0])
        mu = np.array(multipliers) if multipliers else None
    stable, unstable = None, None
    if mu is not None:
        magnitude = np.abs(mu)
        stable = (magnitude <= 1.0 + STABILITY_TOL).all(axis=1)  # is_stable per point
        unstable = (magnitude > 1.0 + STABILITY_TOL).sum(axis=1)  # classify_crossing's count

    def multipliers_at(z, value):  # of a solution between two points (the problem's unknowns), as above
        frame = problem.frame(value)
        z = np.ravel(z) if full is hb else np.ravel(hb.expand(z, frame))
        return hill_multipliers(full, z, frame) if stability == "hill" else monodromy_multipliers(full, z, frame)[0]

    bifurcations = []
    along = np.asarray(points.tangents)[:, -1]  # the parameter's component of each tangent
    turns = along[:-1] * along[1:] < 0
    changes = None if unstable is None else unstable[:-1] != unstable[1:]
    events = turns if changes is None else turns | changes
    for i in np.flatnonzero(events).tolist():
        fold = None
        if turns[i]:
            grazing = hb.contact and not np.array_equal(problem.contact_state(raw[i], lam[i]),
                                                         problem.contact_state(raw[i + 1], lam[i + 1]))
            extreme = fold = grazing_point(problem, lam, raw, i) if grazing else turning_point(lam, Z, i)
            bifurcations.append(Bifurcation("grazing fold" if grazing else "fold", i,
                                            extreme))
        if changes is not None and changes[i]:
            kind = classify_crossing(mu[i], mu[i + 1])  # None unless the count of unstable multipliers changes
            if kind in ("period doubling", "Neimark-Sacker"):
                where = crossing_point(problem, lam, raw, i, mu[i], mu[i + 1], multipliers_at, fold=fold)
                bifurcations.append(Bifurcation(kind, i, where))
    return Branch(
        parameter_name=problem.parameter, parameter=lam, coefficients=Z, omega=np.array(omega),
        coordinate_names=hb.coordinate_names, speed_parameter=hb.speed_parameter, harmonics=H,
        subharmonic=hb.subharmonic, samples=hb.samples, multipliers=mu, stable=stable,
        bifurcations=tuple(bifurcations), residual_error=np.array(errors), harmonic_share=np.array(shares),
        reason=points.reason, stability_method=stability,
    )
