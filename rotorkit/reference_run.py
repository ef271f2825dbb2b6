"""The reference run of a convergence check: the same run at tighter tolerances, compared with the run.

The procedure behind :func:`rotorkit.convergence.check_convergence` (see that
module for the criterion), given the function that runs a simulation, so that
:func:`rotorkit.simulate` can check its own runs without the two modules
importing each other.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import asdict, dataclass

import numpy as np

from .errors import ParameterError, SimulationError

__all__ = ["Convergence", "ConvergenceWarning", "compare_with_reference", "warn_if_not_converged", "TRUSTED",
           "FACTOR", "TIGHTEST_RTOL", "STIFF_CONTACT", "stiff_contacts", "resolve_check"]

#: a run whose relative difference to the tighter run stays below this is trusted point by point
TRUSTED = 1e-2
#: default ratio of the run's tolerances to the reference run's
FACTOR = 100.0
#: tightest relative tolerance a reference run is given (a few hundred times machine epsilon)
TIGHTEST_RTOL = 1e-13
#: contact stiffness (N/m) from which ``simulate(check_convergence="auto")`` checks the run
STIFF_CONTACT = 1e10


def stiff_contacts(system):
    """``"name = value N/m, ..."`` of the system's contact stiffnesses (N/m) >= STIFF_CONTACT; '' if none."""
    model = getattr(system, "model", None)
    units = getattr(model, "parameter_units", None) or {}
    values = getattr(system, "parameters", None) or {}
    stiff = [(name, value) for name, value in values.items()
             if name.endswith("contact_stiffness") and units.get(name) == "N/m" and value >= STIFF_CONTACT]
    return ", ".join(f"{name} = {value:.3g} N/m" for name, value in sorted(stiff))


def resolve_check(system, check):
    """(whether to check, why: the stiff contacts or '') for ``simulate(check_convergence=check)``."""
    if isinstance(check, str) and check == "auto":
        why = stiff_contacts(system)
        return bool(why), why
    if not isinstance(check, (bool, np.bool_)):
        raise ParameterError(f"check_convergence={check!r}: expected True, False or 'auto'")
    return bool(check), ""


class ConvergenceWarning(UserWarning):
    """A run differs from the same run at a tighter tolerance by more than :data:`TRUSTED`."""


@dataclass(frozen=True)
class Convergence:
    """Outcome of :func:`rotorkit.convergence.check_convergence`.

    Attributes
    ----------
    rtol, reference_rtol : float
        The run's relative tolerance and the reference run's.
    relative_difference : float
        The largest, over the coordinates, of ``max|q - q_ref| / max(max|q_ref|, 1000 atol)``;
        ``inf`` when the reference run failed.
    worst : str
        The coordinate where it is largest.
    difference, amplitude : float
        ``max|q - q_ref|`` and ``max|q_ref|`` of that coordinate (SI).
    reference_wall_time : float
        Wall time of the reference run (s).
    message : str
        One line for the user.
    """

    rtol: float
    reference_rtol: float
    relative_difference: float
    worst: str
    difference: float
    amplitude: float
    reference_wall_time: float
    message: str

    @property
    def converged(self):
        """Whether the run is trusted point by point (``relative_difference <= TRUSTED``)."""
        return bool(self.relative_difference <= TRUSTED)

    def as_dict(self):
        """A JSON-ready dict (stored in ``result.stats["convergence"]``)."""
        return {**asdict(self), "converged": self.converged}


def compare_with_reference(run, system, result, *, factor=FACTOR, **options):
    """:func:`rotorkit.convergence.check_convergence` (same arguments and result) with ``run`` the simulation
    function, called as :func:`rotorkit.simulate` is."""
    if not (isinstance(factor, (int, float)) and factor > 1 and np.isfinite(factor)):
        raise ParameterError(f"factor={factor!r} must be a finite number > 1 (e.g. 100)")
    rtol = float(result.stats["rtol"])
    atol = np.asarray(result.stats["atol"], dtype=float)
    reference_rtol = max(rtol / factor, TIGHTEST_RTOL)
    began = time.perf_counter()
    n = len(system.coordinate_names)
    try:
        reference = run(system, (float(result.t[0]), float(result.t[-1])), method=result.stats["method"],
                        rtol=reference_rtol, atol=atol * (reference_rtol / rtol), sample_times=result.t,
                        check_convergence=False, **options)
    except SimulationError as err:
        return Convergence(rtol, reference_rtol, float("inf"), "", float("nan"), float("nan"),
                           time.perf_counter() - began,
                           f"not converged: the reference run at rtol {reference_rtol:.0e} failed ({err.args[0]})")
    wall = time.perf_counter() - began
    q, q_ref = result.y[:n], reference.y[:n]
    difference = np.max(np.abs(q - q_ref), axis=1)
    amplitude = np.max(np.abs(q_ref), axis=1)
    floor = 1000.0 * (atol[:n] if atol.ndim else np.full(n, float(atol)))
    relative = difference / np.maximum(amplitude, floor)
    worst = int(np.argmax(relative))
    name = system.coordinate_names[worst]
    verdict = "converged" if relative[worst] <= TRUSTED else "NOT converged"
    message = (f"{verdict}: against rtol {reference_rtol:.0e}, {name} differs by {difference[worst]:.3g} "
               f"({100 * relative[worst]:.3g} % of its amplitude {amplitude[worst]:.3g})")
    return Convergence(rtol, reference_rtol, float(relative[worst]), name, float(difference[worst]),
                       float(amplitude[worst]), wall, message)


def warn_if_not_converged(convergence, stiff_contact=""):
    """A :class:`ConvergenceWarning` for a run that is not trusted point by point (``stiff_contact``: why the check
    ran on its own)."""
    if not convergence.converged:
        why = (f"stiff contact ({stiff_contact}): the result depends on the tolerance; "
               if stiff_contact else "")
        warnings.warn(f"{why}{convergence.message}; tighten rtol, or trust only statistics (spectra, amplitudes) "
                      "of this run (see docs/envelope.md)", ConvergenceWarning, stacklevel=3)
