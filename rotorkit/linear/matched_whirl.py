"""Modes of a rotor whose bearing or seal coefficients depend on the whirl frequency ("matched whirl").

A :class:`~rotorkit.elements.LinearBearing` (or :class:`~rotorkit.elements.Seal`)
tabulated against the whirl frequency ``nu`` (``frequencies=...``) has
matrices ``K(nu)``, ``C(nu)``, ``M_a(nu)``: a mode of frequency ``w`` is a
solution of ``(lambda^2 M(nu) + lambda C(nu) + K(nu)) x = 0`` with
``|Im lambda| = nu``, the coefficients read at the mode's own frequency.
Each mode therefore has its own ``nu``; they are found one mode at a time
(the "matched whirl" of ROSS's frequency-dependent bearings, San Andres'
"synchronous versus non-synchronous" coefficients):

1. the modes of the model as given (its tables read at ``whirl_ratio *
   Omega + whirl_frequency``, the synchronous frequency by default) give
   the start ``nu_0 = |Im lambda_k|`` of mode ``k``;
2. ``g(nu) = |Im lambda_k(nu)| - nu`` is driven to zero: the first step is
   the fixed-point step ``nu_1 = |Im lambda_k(nu_0)|``, the next ones secant
   steps on ``g`` (a fixed-point step where the secant is not defined or
   leaves ``nu > 0``);
3. mode ``k`` converged when ``|g(nu)| <= rtol * nu + atol``; the reported
   eigenvalue, shape and damping ratio are those of the matrices at that
   ``nu``, so its damped frequency equals ``nu`` within the tolerance.

A mode is followed by its rank ``k`` (ascending ``|lambda|``, as in
:class:`~rotorkit.analysis.modal.Modes`): where two modes exchange ranks
between ``nu_0`` and the solution, the iteration settles on the other one.
Backward whirl is read at ``|Im lambda|`` too (tables are given for
positive frequencies, as ROSS's).

A mode that does not converge in ``max_iterations`` steps, or that stops
being oscillatory on the way, is reported: its ``converged`` flag is False,
``residuals`` holds its last ``|g| / nu``, a :class:`MatchedWhirlWarning`
names it, and ``strict=True`` raises :class:`~rotorkit.errors.SimulationError`
instead.

Every step evaluates the cached linear matrices of the model with the
speed and the bearings' ``whirl_ratio`` (0) and ``whirl_frequency`` (``nu``)
as free parameters (:func:`~rotorkit.analysis.linear_matrices.linear_evaluator`):
no derivation, no re-linearisation.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, SimulationError

__all__ = ["MatchedWhirl", "MatchedWhirlCampbell", "MatchedWhirlWarning", "matched_whirl_modes",
           "matched_whirl_campbell", "frequency_tables"]

#: default relative tolerance on |Im lambda(nu)| - nu
DEFAULT_RTOL = 1e-10
#: default largest number of steps per mode
DEFAULT_MAX_ITERATIONS = 50


class MatchedWhirlWarning(RuntimeWarning):
    """A mode's whirl frequency did not converge in the matched-whirl iteration."""


@dataclass(frozen=True, slots=True, eq=False)
class MatchedWhirl:
    """Modes whose frequency-dependent coefficients are read at their own frequency.

    Attributes
    ----------
    eigenvalues : numpy.ndarray of complex, shape (k,)
        ``lambda`` of mode ``i + 1`` at its matched frequency (1/s).
    whirl_frequencies : numpy.ndarray, shape (k,)
        The frequency ``nu`` (rad/s) each mode's coefficients are read at.
    converged : numpy.ndarray of bool, shape (k,)
    iterations : numpy.ndarray of int, shape (k,)
        Matrix evaluations and eigen-solutions per mode (beyond the first, shared).
    residuals : numpy.ndarray, shape (k,)
        ``| |Im lambda| - nu | / nu`` at the end.
    modes : tuple of rotorkit.analysis.modal.Modes
        The full modes at each mode's ``nu`` (mode ``i + 1`` is
        ``modes[i]`` 's mode ``i + 1``: its shape, whirl, left shape).
    speed : float
        Rotor speed (rad/s).
    """

    eigenvalues: np.ndarray
    whirl_frequencies: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    residuals: np.ndarray
    modes: tuple
    speed: float

    def __len__(self):
        return int(self.eigenvalues.size)

    @property
    def frequencies(self):
        """Natural frequencies ``|lambda|`` (rad/s)."""
        return np.abs(self.eigenvalues)

    @property
    def damped_frequencies(self):
        """``Im lambda`` (rad/s): equal to :attr:`whirl_frequencies` within the tolerance."""
        return self.eigenvalues.imag

    @property
    def damping_ratios(self):
        """``-Re lambda / |lambda|``."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def log_decrements(self):
        """``-2 pi Re lambda / Im lambda``."""
        return -2 * math.pi * self.eigenvalues.real / self.eigenvalues.imag

    def table(self, units="rad/s"):
        """A text table: mode, matched frequency, damping ratio, log decrement, iterations, converged."""
        from .modal_result import frequency_factor

        factor = frequency_factor(units)
        lines = [f"{'mode':>4} {'frequency [' + units + ']':>20} {'damping ratio':>14} {'log dec':>10} "
                 f"{'iterations':>10} {'converged':>9}"]
        for i in range(len(self)):
            zeta, delta = self.damping_ratios[i] + 0.0, self.log_decrements[i] + 0.0  # no "-0"
            lines.append(f"{i + 1:>4} {self.damped_frequencies[i] * factor:>20.6g} {zeta:>14.5g} "
                         f"{delta:>10.5g} {int(self.iterations[i]):>10} "
                         f"{'yes' if self.converged[i] else 'NO':>9}")
        return "\n".join(lines)


def frequency_tables(model):
    """The elements of ``model`` with coefficients tabulated against the whirl frequency."""
    return tuple(e for e in model.elements if getattr(e, "frequencies", None) is not None)


def matched_whirl_modes(model, speed=None, *, n_modes=6, speed_parameter=None, t=0.0, rtol=DEFAULT_RTOL,
                        atol=1e-9, max_iterations=DEFAULT_MAX_ITERATIONS, strict=False):
    """The lowest ``n_modes`` modes, each with its coefficients read at its own whirl frequency.

    Parameters
    ----------
    model : rotorkit.Model
        A linear model (linear bearings, seals, beams, disks...).
    speed : float, str or pint.Quantity, optional
        Rotor speed (rad/s, or e.g. ``"3000 rpm"``) of ``speed_parameter``;
        default the model's value.
    n_modes : int
        How many modes (ascending ``|lambda|``).
    speed_parameter : str, optional
        ``<rotor>_speed`` (default: the first rotor with its own speed).
    t : float
        Time (s) of a speed profile's speed.
    rtol, atol : float
        Converged when ``| |Im lambda(nu)| - nu | <= rtol * nu + atol`` (atol in rad/s).
    max_iterations : int
        Steps per mode before it is reported as not converged.
    strict : bool
        Raise :class:`~rotorkit.errors.SimulationError` instead of warning
        when a mode does not converge.

    Returns
    -------
    MatchedWhirl

    Raises
    ------
    ParameterError
        If the model is not linear (contacts, Hertzian bearings) or an option is invalid.
    """
    from .linear_matrices import linear_evaluator
    from .linear_model import frozen_system, speed_si
    from .modal import check_count, modes_from_matrices

    n_modes = check_count(n_modes)
    if n_modes is None:
        raise ParameterError("n_modes=None is invalid: expected an integer >= 1")
    for name, value in (("rtol", rtol), ("atol", atol)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value >= 0:
            raise ParameterError(f"{name}={value!r} is invalid: expected a number >= 0")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, int) or max_iterations < 1:
        raise ParameterError(f"max_iterations={max_iterations!r} is invalid: expected an integer >= 1")
    model, speed_parameter = frozen_system(model, speed_parameter, None if speed is None else speed_si(speed), t,
                                           who="matched_whirl_modes")
    values = dict(model.parameters)
    w = values[speed_parameter] if speed is None else speed_si(speed)
    tables = frequency_tables(model)
    knobs = [(f"{e.label()}_whirl_ratio", f"{e.label()}_whirl_frequency") for e in tables]
    free = (speed_parameter,) + tuple(name for pair in knobs for name in pair)
    evaluator = linear_evaluator(model, t, values, free=free)
    if evaluator is None:
        raise ParameterError(f"matched_whirl_modes: {model.name!r} has forces that are not linear (contacts, "
                             "Hertzian bearings); expected a linear model")
    names = tuple(model.coordinate_names)

    def solve(nu):
        """Modes with every table read at ``nu`` (None: as the model gives, e.g. synchronous)."""
        given = {speed_parameter: w}
        for ratio, frequency in knobs:
            given[ratio] = values[ratio] if nu is None else 0.0
            given[frequency] = values[frequency] if nu is None else float(nu)
        M, C, K = evaluator(**given)
        return modes_from_matrices(M, C, K, names, left=True, n_modes=n_modes, speed=w)

    start = solve(None)
    count = min(n_modes, len(start))
    eigenvalues = np.empty(count, dtype=complex)
    nus, residuals = np.empty(count), np.empty(count)
    converged, iterations = np.zeros(count, dtype=bool), np.zeros(count, dtype=np.int64)
    chosen = []
    for k in range(count):
        if not knobs:  # nothing depends on the frequency: the modes as they are
            lam = start.eigenvalues[k]
            eigenvalues[k], nus[k], residuals[k], converged[k] = lam, abs(lam.imag), 0.0, True
            chosen.append(start)
            continue
        nu = abs(start.eigenvalues[k].imag)
        previous = None  # (nu, g) of the last step
        modes, lam, g = None, None, math.inf
        for step in range(1, max_iterations + 1):
            modes = solve(nu)
            iterations[k] = step
            if k >= len(modes):
                lam = None
                break
            lam = modes.eigenvalues[k]
            g = abs(lam.imag) - nu
            if abs(g) <= rtol * nu + atol:
                converged[k] = True
                break
            new = nu + g  # fixed-point step
            if previous is not None and g != previous[1]:
                secant = nu - g * (nu - previous[0]) / (g - previous[1])
                if math.isfinite(secant) and secant > 0:
                    new = secant
            previous = (nu, g)
            nu = new
        if lam is None:
            eigenvalues[k], residuals[k] = complex(math.nan, math.nan), math.nan
            chosen.append(modes)
        else:
            eigenvalues[k], residuals[k] = lam, abs(g) / nu if nu else abs(g)
            chosen.append(modes)
        nus[k] = nu
    result = MatchedWhirl(eigenvalues=_readonly(eigenvalues), whirl_frequencies=_readonly(nus),
                          converged=_readonly(converged), iterations=_readonly(iterations),
                          residuals=_readonly(residuals), modes=tuple(chosen), speed=float(w))
    failed = [i + 1 for i in range(count) if not converged[i]]
    if failed:
        message = (f"matched_whirl_modes: mode(s) {failed} of {model.name!r} at {w:g} rad/s did not converge in "
                   f"{max_iterations} steps (last relative residuals "
                   f"{[float(f'{residuals[i - 1]:.3g}') for i in failed]}; a mode that stops being oscillatory has "
                   "residual nan); raise max_iterations, loosen rtol, or check the tables for a frequency range "
                   "the modes leave")
        if strict:
            raise SimulationError(message)
        warnings.warn(message, MatchedWhirlWarning, stacklevel=2)
    return result


@dataclass(frozen=True, slots=True, eq=False)
class MatchedWhirlCampbell:
    """Matched-whirl modes over a range of speeds (a Campbell diagram with each mode at its own frequency).

    Attributes
    ----------
    speeds : numpy.ndarray, shape (m,)
        Rotor speeds (rad/s).
    eigenvalues : numpy.ndarray of complex, shape (m, k)
        ``lambda`` of mode ``j + 1`` at speed ``i`` (nan where the mode does not exist).
    converged : numpy.ndarray of bool, shape (m, k)
    """

    speeds: np.ndarray
    eigenvalues: np.ndarray
    converged: np.ndarray

    @property
    def frequencies(self):
        """Damped (whirl) frequencies ``Im lambda`` (rad/s), shape (m, k)."""
        return self.eigenvalues.imag

    @property
    def damping_ratios(self):
        """``-Re lambda / |lambda|``, shape (m, k)."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    def plot(self, ax=None, units="rad/s", **kwargs):
        """Frequencies against speed, one line per mode rank, both in ``units``; the Line2D objects."""
        import matplotlib.pyplot as plt

        from .modal_result import frequency_factor

        ax = plt.gca() if ax is None else ax
        factor = frequency_factor(units)
        lines = [ax.plot(self.speeds * factor, self.frequencies[:, j] * factor, label=f"mode {j + 1}", **kwargs)[0]
                 for j in range(self.frequencies.shape[1])]
        ax.plot(self.speeds * factor, self.speeds * factor, "k--", linewidth=0.8, label="1x")
        ax.set_xlabel(f"speed [{units}]")
        ax.set_ylabel(f"whirl frequency (matched) [{units}]")
        ax.legend()
        return lines


def matched_whirl_campbell(model, speeds, *, n_modes=6, speed_parameter=None, **options):
    """:func:`matched_whirl_modes` at each of ``speeds`` (rad/s, or quantities): a :class:`MatchedWhirlCampbell`.

    ``options`` go to :func:`matched_whirl_modes` (``rtol``, ``atol``,
    ``max_iterations``, ``strict``, ``t``); a mode that does not converge
    at a speed is flagged there and warned about.
    """
    from .linear_model import speed_si

    if isinstance(speeds, (str, bytes)) or not hasattr(speeds, "__len__") or len(speeds) == 0:
        raise ParameterError(f"speeds={speeds!r} is invalid: expected a non-empty sequence of speeds (rad/s)")
    values = np.array([speed_si(w, "speeds") for w in speeds])
    eigenvalues = np.full((values.size, n_modes), complex(math.nan, math.nan))
    converged = np.zeros((values.size, n_modes), dtype=bool)
    for i, w in enumerate(values):
        result = matched_whirl_modes(model, w, n_modes=n_modes, speed_parameter=speed_parameter, **options)
        eigenvalues[i, :len(result)] = result.eigenvalues
        converged[i, :len(result)] = result.converged
    return MatchedWhirlCampbell(speeds=_readonly(values), eigenvalues=_readonly(eigenvalues),
                                converged=_readonly(converged))


def _readonly(array):
    array = np.array(array)
    array.setflags(write=False)
    return array
