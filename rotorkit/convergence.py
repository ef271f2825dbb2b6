"""Is a run converged? The same run at a tighter tolerance, and how far apart the two are.

A run that reports ``success`` has kept its *local* error estimate within
``rtol``/``atol`` at every step; it says nothing about how far the computed
trajectory is from the true one. With very stiff contact (rub stiffness
1e10-1e12 N/m on the AL-31F preset) or chaotic rubbing, two successful runs at
rtol 1e-6 and 1e-9 can differ by more than the response amplitude within a
second. :func:`check_convergence` measures it: it repeats the run with both
tolerances divided by ``factor`` (100 by default), samples it at the same
instants and reports, per coordinate, the largest difference against that
coordinate's amplitude::

    relative_difference = max_i  max_t |q_i - q_i,ref| / max(max_t |q_i,ref|, 1000 atol)

(the floor ``1000 atol`` keeps coordinates the run barely moves from
dominating). Below :data:`TRUSTED` (1 %) the run's trajectory is trusted
point by point; above it the trajectory is not (its statistics, such as
spectra or amplitudes, may still be: compare them the same way).
``simulate(..., check_convergence=True)`` runs it and stores the outcome in
``result.stats["convergence"]``, with a :class:`ConvergenceWarning` when the
run is not converged. By default (``check_convergence="auto"``) the check
runs on its own for stiff contact: a model whose contact stiffness (N/m: rub
stators, intershaft rubs) is at least :data:`STIFF_CONTACT`. The check costs the reference run: about
``factor ** (1/8)`` (1.8 for DOP853) to ``factor ** (1/5)`` (2.5 for RK45)
times the run itself.
"""

from .reference_run import (
    FACTOR,
    STIFF_CONTACT,
    TIGHTEST_RTOL,
    TRUSTED,
    Convergence,
    ConvergenceWarning,
    compare_with_reference,
    warn_if_not_converged,
)
from .simulate import simulate

__all__ = ["Convergence", "ConvergenceWarning", "check_convergence", "warn_if_not_converged", "TRUSTED", "FACTOR",
           "TIGHTEST_RTOL", "STIFF_CONTACT"]


def check_convergence(system, result, *, factor=FACTOR, **options):
    """Repeat the run of ``result`` with tolerances divided by ``factor``; compare the coordinates.

    Parameters
    ----------
    system : rotorkit.System
        The system ``result`` was computed from.
    result : rotorkit.Result
        The run to check (its ``stats`` give method, rtol and atol).
    factor : float
        Tolerance ratio (> 1).
    **options
        Other arguments of :func:`rotorkit.simulate` the run used (``engine``,
        ``max_step``, ``bound``, ``contact_events``, ``y0``).

    Returns
    -------
    Convergence
    """
    return compare_with_reference(simulate, system, result, factor=factor, **options)
