"""Linearised modal analysis: static equilibrium, Jacobian, natural frequencies, Campbell diagram.

Everything works on a compiled :class:`~rotorkit.system.System` (its
``rhs(t, y)``), so it covers whatever the model holds, contacts included,
without re-deriving anything:

1. :func:`static_equilibrium` finds the coordinates ``q*`` where the
   accelerations vanish with zero velocities (the gravity-loaded rest
   position); unbalance forcing is periodic, not static, so it is switched
   off by default.
2. :func:`linearize` returns the ``2n x 2n`` Jacobian ``A = d rhs / d y`` at
   ``(q*, q' = 0)`` by central finite differences.
3. :func:`natural_frequencies` takes the eigenvalues of ``A``: frequencies,
   damping ratios and mode shapes, as a :class:`Modes` result. Hertzian
   bearings and rub contacts are linearised at the operating point because
   they are in the right-hand side.
4. :func:`campbell` sweeps a rotor speed with
   :meth:`~rotorkit.system.System.with_parameters` and collects the natural
   frequencies and the 1x lines of each rotor, as a :class:`Campbell`.

Typical use::

    system = rotorkit.preset("al31f").compile()
    modes = natural_frequencies(system)
    print(modes.table())
    diagram = campbell(system, np.linspace(0.0, 2000.0, 21))

Conventions: frequencies in rad/s, displacements in m, angles in rad. The
eigenvalues ``lambda`` of ``A`` come in conjugate pairs; a mode is one pair,
kept by its member with positive imaginary part. Its natural frequency is
``|lambda|`` (the undamped natural frequency ``omega_n`` for viscous
damping), its damping ratio ``-Re(lambda) / |lambda|`` and its damped
frequency ``Im(lambda)``. Real eigenvalues (overdamped or diverging motions)
are not modes; they stay in :attr:`Modes.all_eigenvalues`.

Bad input and a failed equilibrium solve raise
:class:`rotorkit.errors.ParameterError` (a ``ValueError``).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = [
    "Modes",
    "Campbell",
    "static_equilibrium",
    "linearize",
    "natural_frequencies",
    "campbell",
]

#: Default relative finite-difference step (about the cube root of the machine epsilon).
DEFAULT_RELATIVE_STEP = 1e-6
#: Smallest typical magnitude of a displacement (m) or an angle (rad) used to scale the steps.
_FLOOR_SCALE = 1e-6
#: Default number of cage positions averaged over one ball-passing period.
DEFAULT_CAGE_SAMPLES = 16
#: A pair is oscillatory when Im(lambda) exceeds this fraction of |lambda|.
_OSCILLATORY_RTOL = 1e-9
#: Equilibrium residual tolerance, relative to the load acceleration at q = 0.
DEFAULT_EQUILIBRIUM_TOL = 1e-9


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class Modes:
    """Natural frequencies and mode shapes of a linearised system.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (k,)
        Natural frequencies ``|lambda|`` (rad/s), ascending.
    damping_ratios : numpy.ndarray, shape (k,)
        ``-Re(lambda) / |lambda|`` (dimensionless); negative for a growing mode.
    eigenvalues : numpy.ndarray of complex, shape (k,)
        ``lambda`` (1/s), the member of each conjugate pair with ``Im > 0``.
    shapes : numpy.ndarray of complex, shape (n, k)
        Column ``i`` is the coordinate part of the eigenvector of mode ``i``,
        in :attr:`coordinate_names` order (m for ``x``/``y``, rad for
        ``alpha``), scaled so that its largest entry is exactly ``1``.
    coordinate_names : tuple of str, length n
    operating_point : numpy.ndarray, shape (n,)
        The coordinates ``q*`` (m, rad) the system was linearised at (at the
        first sample time).
    frequency_range : numpy.ndarray, shape (k, 2)
        Lowest and highest value (rad/s) over the sampled cage positions of
        the k-th lowest frequency of each sample's own Jacobian (see
        :func:`natural_frequencies`); both equal :attr:`frequencies` when a
        single position was used. NaN where a sample had fewer oscillatory
        modes.
    sample_times : numpy.ndarray, shape (m,)
        Times (s) at which the Jacobian was evaluated and averaged.
    all_eigenvalues : numpy.ndarray of complex, shape (2n,)
        Every eigenvalue of the (averaged) Jacobian, real ones included.
    rub_engaged : bool
        Whether a rub contact was engaged in the linearisation.

    Notes
    -----
    The arrays are read-only. ``eq=False``: results compare by identity.
    """

    frequencies: np.ndarray
    damping_ratios: np.ndarray
    eigenvalues: np.ndarray
    shapes: np.ndarray
    coordinate_names: tuple
    operating_point: np.ndarray
    frequency_range: np.ndarray
    sample_times: np.ndarray
    all_eigenvalues: np.ndarray
    rub_engaged: bool = False

    def __len__(self):
        return int(self.frequencies.size)

    @property
    def damped_frequencies(self):
        """``Im(lambda)`` (rad/s), shape (k,): the frequency of free decay."""
        return self.eigenvalues.imag.copy()

    def _index(self, i):
        if isinstance(i, bool) or not isinstance(i, numbers.Integral) or not -len(self) <= i < len(self):
            raise ParameterError(f"mode index {i!r} is invalid: expected an integer from 0 to {len(self) - 1}")
        return int(i) % len(self)

    def shape_of(self, i):
        """Mode shape ``i`` as ``{coordinate name: complex amplitude}`` (largest entry 1)."""
        i = self._index(i)
        return dict(zip(self.coordinate_names, self.shapes[:, i].tolist()))

    def dominant_coordinates(self, i, count=3):
        """Names of the ``count`` largest entries of mode shape ``i``, largest first.

        Entries compare as numbers, m against rad: a bending mode with a
        strong friction coupling to torsion may list an angle first.
        """
        i = self._index(i)
        order = np.argsort(-np.abs(self.shapes[:, i]), kind="stable")
        return tuple(self.coordinate_names[j] for j in order[:count])

    def table(self, units="rad/s"):
        """A plain-text table: frequency, damping ratio, cage spread, dominant coordinates.

        Parameters
        ----------
        units : {"rad/s", "Hz"}
            Units of the frequency columns (the Hz column is always shown).
        """
        factor = _frequency_factor(units, allowed=("rad/s", "Hz"))
        head = (f"{'mode':>4}  {f'frequency ({units})':>18}  {'(Hz)':>9}  {'damping ratio':>13}  "
                f"{f'cage spread ({units})':>24}  dominant coordinates")
        lines = [head, "-" * len(head)]
        for i in range(len(self)):
            f = self.frequencies[i]
            lo, hi = self.frequency_range[i] * factor
            spread = f"{lo:10.4g} - {hi:<10.4g}" if np.isfinite(lo) else f"{'n/a':>23}"
            lines.append(
                f"{i + 1:>4}  {f * factor:>18.6g}  {f / (2 * math.pi):>9.4g}  {self.damping_ratios[i]:>13.4g}  "
                f"{spread:>24}  {', '.join(self.dominant_coordinates(i))}"
            )
        return "\n".join(lines)

    def plot_mode_shape(self, i, ax=None, **kwargs):
        """Bending magnitudes of mode ``i`` along the stations; returns the matplotlib Axes."""
        from ..plotting.campbell import plot_mode_shape

        return plot_mode_shape(self, i, ax=ax, **kwargs)


@dataclass(frozen=True, slots=True, eq=False)
class Campbell:
    """Natural frequencies against a rotor speed (a Campbell diagram).

    Attributes
    ----------
    speeds : numpy.ndarray, shape (n_speeds,)
        Values of :attr:`speed_parameter` (rad/s).
    frequencies : numpy.ndarray, shape (n_speeds, n_modes)
        The ``n_modes`` lowest natural frequencies (rad/s) at each speed,
        ascending (NaN where fewer modes exist).
    damping_ratios : numpy.ndarray, shape (n_speeds, n_modes)
    rotor_speeds : dict of str to numpy.ndarray, shape (n_speeds,)
        Rotor name -> its spin speed (rad/s) at each point: the 1x lines
        (``HP = speed_ratio x LP`` for a rotor given by a ratio).
    speed_parameter : str
        The swept parameter, e.g. ``"LP_speed"``.

    Notes
    -----
    Modes are sorted by frequency at each speed, not tracked by shape: where
    two curves cross, their colours swap. At a speed where a ball bearing's
    cage stands still there is no cage period to average over, so that
    point is linearised at the one ball configuration of time ``t`` and may
    differ from its neighbours (the averaging assumes a ball-passing
    frequency well above the modes).
    """

    speeds: np.ndarray
    frequencies: np.ndarray
    damping_ratios: np.ndarray
    rotor_speeds: dict
    speed_parameter: str

    @property
    def n_modes(self):
        return int(self.frequencies.shape[1])

    def critical_speeds(self, rotor=None):
        """Speeds where a 1x line crosses a natural-frequency curve (linear interpolation).

        Parameters
        ----------
        rotor : str, optional
            Only this rotor's 1x line (default: all rotors).

        Returns
        -------
        list of (str, int, float)
            ``(rotor, mode index, swept speed in rad/s)``, sorted by speed.
        """
        names = list(self.rotor_speeds) if rotor is None else [rotor]
        for name in names:
            if name not in self.rotor_speeds:
                raise ParameterError(f"rotor={name!r} is unknown; rotors: {', '.join(self.rotor_speeds)}")
        out = []
        for name in names:
            line = self.rotor_speeds[name]
            for k in range(self.n_modes):
                d = self.frequencies[:, k] - line
                for j in range(len(d) - 1):
                    a, b = d[j], d[j + 1]
                    if not (np.isfinite(a) and np.isfinite(b)):
                        continue
                    if a == 0.0:
                        out.append((name, k, float(self.speeds[j])))
                    elif a * b < 0.0:
                        s0, s1 = self.speeds[j], self.speeds[j + 1]
                        out.append((name, k, float(s0 + (s1 - s0) * a / (a - b))))
                if len(d) and d[-1] == 0.0:
                    out.append((name, k, float(self.speeds[-1])))
        return sorted(out, key=lambda c: c[2])

    def plot(self, ax=None, **kwargs):
        """Draw the diagram (see :func:`rotorkit.plotting.campbell.plot_campbell`); returns the Axes."""
        from ..plotting.campbell import plot_campbell

        return plot_campbell(self, ax=ax, **kwargs)


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------

_FREQUENCY_FACTORS = {"rad/s": 1.0, "Hz": 1.0 / (2.0 * math.pi), "rpm": 60.0 / (2.0 * math.pi)}


def _frequency_factor(units, allowed=tuple(_FREQUENCY_FACTORS)):
    """Factor from rad/s to ``units``."""
    if not isinstance(units, str) or units not in allowed:
        raise ParameterError(f"units={units!r} is not supported: expected one of {tuple(allowed)}")
    return _FREQUENCY_FACTORS[units]


def _readonly(array):
    array = np.array(array)
    array.setflags(write=False)
    return array


def _check_system(system, who):
    if not (hasattr(system, "rhs") and hasattr(system, "coordinate_names") and hasattr(system, "state_names")):
        hint = "; compile it first: model.compile()" if hasattr(system, "compile") else ""
        raise TypeError(f"{who}: expected a compiled rotorkit System, got {type(system).__name__}{hint}")


def _check_time(t, name="t"):
    if isinstance(t, bool) or not isinstance(t, numbers.Real) or not math.isfinite(t):
        raise ParameterError(f"{name}={t!r} is invalid: expected a finite time (s)")
    return float(t)


def _check_coordinates(q, n, name="q"):
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


def _without_unbalance(system):
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


def _rotor_speeds(system):
    """Rotor name -> spin speed (rad/s) from the system's parameters."""
    values = system.parameters
    rotors = system.model.rotors
    out = {}
    for name in rotors:
        factor, r = 1.0, rotors[name]
        while r.speed is None:
            factor *= values[f"{r.name}_speed_ratio"]
            r = rotors[r.reference]
        out[name] = factor * values[f"{r.name}_speed"]
    return out


def _ball_pass_period(system):
    """Longest ball-passing period (s) of the model's ball bearings, or None if no cage turns."""
    from ..elements import BallBearing

    bearings = [e for e in system.model.elements if isinstance(e, BallBearing)]
    if not bearings:
        return None
    speeds = _rotor_speeds(system)
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


def _sample_times(system, t, count):
    """``count`` times over one ball-passing period from ``t``, on ``t``'s side of any time event."""
    period = _ball_pass_period(system)
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


def _rub_stators(system):
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
        acceleration at ``q = 0`` (m/s^2, rad/s^2).
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

    _check_system(system, "static_equilibrium")
    t = _check_time(t)
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
        q0 = _check_coordinates(q0, n, "q0")
    if not unbalance:
        system = _without_unbalance(system)

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

    limit = {"hybr": "maxfev", "lm": "maxiter"}
    best, best_res = q0, np.abs(a_start)
    if np.max(best_res) <= threshold:
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
        if np.max(best_res) <= threshold:
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
    _check_system(system, "linearize")
    t = _check_time(t)
    names = tuple(system.coordinate_names)
    n = len(names)
    q = _check_coordinates(q, n)
    y0 = np.concatenate([q, np.zeros(n)])
    state_names = tuple(system.state_names)

    if method not in ("fd", "analytic", "auto"):
        raise ParameterError(f"method={method!r} is unknown; expected 'fd', 'analytic' or 'auto'")
    has_exact = bool(getattr(system, "has_jacobian", False)) and callable(getattr(system, "jacobian", None))
    if method == "analytic" and not has_exact:
        raise ParameterError(f"method='analytic': system {system.name!r} has no analytic Jacobian; use method='fd'")
    steps = _steps(names, q, eps)  # validates eps whatever the method
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


def _steps(names, q, eps):
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


# ---------------------------------------------------------------------------
# Natural frequencies
# ---------------------------------------------------------------------------


def _engage_rub(system, q, stators, steps):
    """A system whose rub clearances sit just below the disks' static radial displacement.

    The contact then engages at ``q`` with a negligible preload: radial
    stiffness k_r along the static displacement, friction coupling mu k_r.
    """
    names = system.coordinate_names
    values = system.parameters
    overrides = {}
    for stator in stators:
        label = stator.label()
        ix, iy = names.index(f"x{stator.station}"), names.index(f"y{stator.station}")
        r = math.hypot(q[ix], q[iy])
        clearance = values[f"{label}_clearance"]
        margin = 2.0 * max(steps[ix], steps[iy])
        if r - margin < clearance:
            overrides[f"{label}_clearance"] = max(r - margin, 0.0)
    return system.with_parameters(**overrides) if overrides else system


def _rub_is_engaged(system, q, stators):
    names = system.coordinate_names
    values = system.parameters
    for stator in stators:
        label = stator.label()
        if values[f"{label}_contact_stiffness"] == 0.0:
            continue
        r = math.hypot(q[names.index(f"x{stator.station}")], q[names.index(f"y{stator.station}")])
        if r >= values[f"{label}_clearance"]:
            return True
    return False


def _oscillatory(eigenvalues):
    """Eigenvalues with Im > 0 (one per conjugate pair), sorted by |lambda|."""
    lam = eigenvalues[eigenvalues.imag > _OSCILLATORY_RTOL * np.abs(eigenvalues)]
    return lam[np.argsort(np.abs(lam), kind="stable")]


def natural_frequencies(system, *, t=0.0, equilibrium=True, rub_engaged=None, unbalance=False,
                        cage_samples=DEFAULT_CAGE_SAMPLES, eps=None, method="auto"):
    """Natural frequencies, damping ratios and mode shapes of the linearised system.

    Parameters
    ----------
    system : rotorkit.System
    t : float
        Time (s) of the operating point (manoeuvre loads, ball angles).
    equilibrium : bool or array_like of shape (n,)
        True (default): linearise at the static equilibrium
        (:func:`static_equilibrium`, gravity sag included); False: at the
        undeflected axis ``q = 0``; an array: at these coordinates (m, rad).
    rub_engaged : bool or None
        None (default): the rub contacts as they are at the operating point
        (engaged only if the static displacement exceeds the clearance).
        True: engaged (see Notes). False: disengaged (contact stiffness set
        to 0, for the equilibrium too).
    unbalance : bool
        False (default): disk eccentricities set to zero (a periodic forcing
        is not part of a modal analysis). True: kept, and the system is
        linearised as a frozen snapshot at ``t`` (the eccentric disks' mass
        matrix then depends on their angle; a rigorous treatment would be
        Floquet analysis).
    cage_samples : int
        Number of cage positions averaged over one ball-passing period (see
        Notes); 1 linearises at ``t`` only.
    eps : None, float or array_like
        Finite-difference steps, as in :func:`linearize`.
    method : {"fd", "analytic", "auto"}
        How the Jacobian is computed, as in :func:`linearize`.

    Returns
    -------
    Modes

    Notes
    -----
    *Bearing.* The balls of a :class:`~rotorkit.BallBearing` sit at angles
    that turn with the cage, so the bearing's linearised stiffness depends on
    time, with the ball-passing period ``2 pi / (N_b omega_c)``. The
    equilibrium and the Jacobian are computed at ``cage_samples`` equally
    spaced times over one such period from ``t`` (backwards if a time event
    of the system lies in between) and the Jacobians are averaged: since the
    ball-passing frequency is far above the low modes (17,900 rad/s for the
    AL-31F preset), the method of averaging makes the averaged stiffness the
    relevant one. The frequencies of each single sample give
    :attr:`Modes.frequency_range`, the spread over the cage angle. Without a
    bearing, or at zero cage speed, one sample is used.

    *Rub.* With ``rub_engaged=True`` the clearance of each rub stator whose
    disk does not already touch is lowered, for the linearisation only, to
    just below the disk's static radial displacement ``r*`` (by a margin of
    a few finite-difference steps): the contact engages at the operating
    point with negligible preload. Its linearisation is then a radial spring
    ``k_r`` along the static displacement (the contact point of a sagging
    disk), the friction coupling ``mu k_r`` and, with a torsional disk, the
    friction torque's dependence on the displacement; the tangential
    stiffness ``k_r (r - delta) / r`` is about zero (a grazing contact). If
    the disk has no static displacement (``r*`` below the margin) the
    clearance becomes 0: contact all around, ``k_r`` in every direction.

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Model
    >>> system = Model([Rotor(name="R", stations=(1,), speed=100.0),
    ...                 Disk(station=1, mass=2.0, radius=0.1),
    ...                 ElasticSupport(station=1, stiffness=2e4, damping=4.0)]).compile(backend="python")
    >>> modes = natural_frequencies(system)
    >>> modes.frequencies.round(6).tolist(), modes.damping_ratios.round(6).tolist()
    ([100.0, 100.0], [0.01, 0.01])
    """
    _check_system(system, "natural_frequencies")
    t = _check_time(t)
    names = tuple(system.coordinate_names)
    n = len(names)
    if rub_engaged not in (None, True, False):
        raise ParameterError(f"rub_engaged={rub_engaged!r} is invalid: expected None, True or False")
    if not isinstance(unbalance, bool):
        raise ParameterError(f"unbalance={unbalance!r} is invalid: expected True or False")
    if isinstance(cage_samples, bool) or not isinstance(cage_samples, numbers.Integral) or cage_samples < 1:
        raise ParameterError(f"cage_samples={cage_samples!r} is invalid: expected an integer >= 1")
    if method not in ("fd", "analytic", "auto"):
        raise ParameterError(f"method={method!r} is unknown; expected 'fd', 'analytic' or 'auto'")
    given = None
    if isinstance(equilibrium, bool):
        pass
    elif isinstance(equilibrium, (np.ndarray, list, tuple)):
        given = _check_coordinates(equilibrium, n, "equilibrium")
    else:
        raise ParameterError(
            f"equilibrium={equilibrium!r} is invalid: expected True, False or {n} coordinates (m, rad)"
        )

    if not unbalance:
        system = _without_unbalance(system)
    stators = _rub_stators(system)
    if rub_engaged is False and stators:
        values = system.parameters
        off = {f"{s.label()}_contact_stiffness": 0.0 for s in stators}
        if any(values[name] != 0.0 for name in off):
            system = system.with_parameters(**off)

    times = _sample_times(system, t, int(cage_samples))
    jacobians, per_sample, operating_point, engaged = [], [], None, False
    for ti in times:
        if given is not None:
            q = given
        elif equilibrium:
            q = static_equilibrium(system, ti, unbalance=True)
        else:
            q = np.zeros(n)
        target = system
        if rub_engaged and stators:
            steps = _steps(names, q, eps)
            target = _engage_rub(system, q, stators, steps)
        engaged = engaged or _rub_is_engaged(target, q, stators)
        A, _ = linearize(target, q, ti, eps=eps, method=method)
        jacobians.append(A)
        per_sample.append(np.abs(_oscillatory(np.linalg.eigvals(A))))
        if operating_point is None:
            operating_point = q.copy()

    A = np.mean(jacobians, axis=0)
    eigenvalues, vectors = np.linalg.eig(A)
    keep = eigenvalues.imag > _OSCILLATORY_RTOL * np.abs(eigenvalues)
    lam, vec = eigenvalues[keep], vectors[:, keep]
    order = np.argsort(np.abs(lam), kind="stable")
    lam, vec = lam[order], vec[:n, order]
    k = lam.size
    shapes = np.empty((n, k), dtype=complex)
    for i in range(k):
        v = vec[:, i]
        shapes[:, i] = v / v[int(np.argmax(np.abs(v)))]
    frequencies = np.abs(lam)
    damping = -lam.real / frequencies if k else np.empty(0)
    spread = np.full((k, len(times)), np.nan)
    for j, f in enumerate(per_sample):
        m = min(k, f.size)
        spread[:m, j] = f[:m]
    with np.errstate(all="ignore"):
        frange = np.column_stack([np.min(spread, axis=1), np.max(spread, axis=1)]) if k else np.empty((0, 2))
    if k and np.isnan(spread).any():
        frange[np.isnan(spread).any(axis=1)] = np.nan
    return Modes(
        frequencies=_readonly(frequencies),
        damping_ratios=_readonly(damping),
        eigenvalues=_readonly(lam),
        shapes=_readonly(shapes),
        coordinate_names=names,
        operating_point=_readonly(operating_point),
        frequency_range=_readonly(frange),
        sample_times=_readonly(times),
        all_eigenvalues=_readonly(eigenvalues[np.argsort(np.abs(eigenvalues), kind="stable")]),
        rub_engaged=bool(engaged),
    )


# ---------------------------------------------------------------------------
# Campbell diagram
# ---------------------------------------------------------------------------


def _resolve_system(source, backend):
    """A System from a System, a Model, a preset name or a builder (callable returning either)."""
    if isinstance(source, str):
        from ..presets import preset

        source = preset(source)
    elif callable(source) and not hasattr(source, "rhs") and not hasattr(source, "compile"):
        source = source()
    if hasattr(source, "rhs"):
        return source
    if hasattr(source, "compile"):
        return source.compile(backend=backend)
    raise TypeError(
        f"campbell: expected a System, a Model, a preset name or a function returning one of them, "
        f"got {type(source).__name__}"
    )


def campbell(model_or_preset_builder, speeds, *, n_modes=6, speed_parameter="LP_speed", t=0.0,
             equilibrium=True, rub_engaged=None, unbalance=False, cage_samples=DEFAULT_CAGE_SAMPLES,
             method="auto", backend="auto"):
    """Natural frequencies against a rotor speed.

    The system is compiled once; each speed is set with
    ``system.with_parameters(<speed_parameter>=w)`` (no re-derivation) and
    analysed by :func:`natural_frequencies`.

    Parameters
    ----------
    model_or_preset_builder : System, Model, str or callable
        A compiled system, a model (compiled with ``backend``), a preset
        name (``"al31f"``) or a function of no arguments returning a model
        or system (e.g. ``functools.partial(rotorkit.preset, "al31f", rub=False)``).
    speeds : array_like, shape (n_speeds,)
        Values of ``speed_parameter`` (rad/s).
    n_modes : int
        Number of lowest modes kept at each speed.
    speed_parameter : str
        The swept parameter, ``<rotor>_speed`` (default ``"LP_speed"``);
        rotors given by a speed ratio follow it.
    t, equilibrium, rub_engaged, unbalance, cage_samples, method
        As in :func:`natural_frequencies`.
    backend : {"auto", "python", "numba"}
        Used only when a model has to be compiled.

    Returns
    -------
    Campbell

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Model
    >>> model = Model([Rotor(name="R", stations=(1,), speed=0.0),
    ...                Disk(station=1, mass=2.0, radius=0.1),
    ...                ElasticSupport(station=1, stiffness=2e4)])
    >>> c = campbell(model, [0.0, 50.0, 150.0], n_modes=2, speed_parameter="R_speed", backend="python")
    >>> c.frequencies.round(6).tolist()
    [[100.0, 100.0], [100.0, 100.0], [100.0, 100.0]]
    >>> [(rotor, mode, round(speed, 6)) for rotor, mode, speed in c.critical_speeds()]
    [('R', 0, 100.0), ('R', 1, 100.0)]
    """
    system = _resolve_system(model_or_preset_builder, backend)
    try:
        w = np.array(speeds, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"speeds={speeds!r} is invalid: expected a 1-D array of speeds (rad/s)") from exc
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)):
        raise ParameterError(f"speeds has shape {w.shape}: expected a non-empty 1-D array of finite speeds (rad/s)")
    if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral) or n_modes < 1:
        raise ParameterError(f"n_modes={n_modes!r} is invalid: expected an integer >= 1")
    available = [p for p in system.parameters if p.endswith("_speed") and p[: -len("_speed")] in system.model.rotors]
    if speed_parameter not in available:
        raise ParameterError(
            f"speed_parameter={speed_parameter!r} is not a rotor speed of {system.name!r}: "
            f"expected one of {available}"
        )
    freqs = np.full((w.size, int(n_modes)), np.nan)
    zetas = np.full((w.size, int(n_modes)), np.nan)
    lines = {name: np.empty(w.size) for name in system.model.rotors}
    for i, speed in enumerate(w):
        point = system.with_parameters(**{speed_parameter: float(speed)})
        modes = natural_frequencies(point, t=t, equilibrium=equilibrium, rub_engaged=rub_engaged,
                                    unbalance=unbalance, cage_samples=cage_samples, method=method)
        m = min(int(n_modes), len(modes))
        freqs[i, :m] = modes.frequencies[:m]
        zetas[i, :m] = modes.damping_ratios[:m]
        for name, value in _rotor_speeds(point).items():
            lines[name][i] = value
    return Campbell(
        speeds=_readonly(w),
        frequencies=_readonly(freqs),
        damping_ratios=_readonly(zetas),
        rotor_speeds={name: _readonly(v) for name, v in lines.items()},
        speed_parameter=speed_parameter,
    )
