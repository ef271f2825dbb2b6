"""How stiff is a scene? Time scales from the Jacobian, and the method that fits.

Explicit Runge-Kutta methods take steps limited by the fastest time scale
of the linearised system (``|lambda_max| h`` must stay inside the method's
stability region); implicit methods are not limited by it but pay a linear
solve per step. Stiffness here is the ratio of the fastest time scale that
the dynamics holds to the slowest one that is excited. At the AL-31F
preset's values it is about 40 (MODEL_NOTES): explicit is right. Very stiff
contact (k_r of 1e8-1e9 N/m) pushes it up; then an implicit method with the
analytic Jacobian may pay.
"""

from dataclasses import dataclass

import numpy as np

__all__ = ["StiffnessReport", "stiffness_report", "probe_states"]

#: above this ratio of fastest to slowest time scale, an implicit method is suggested
STIFF_RATIO = 1e3


@dataclass(frozen=True)
class StiffnessReport:
    """Eigenvalue scan of the Jacobian over a set of states.

    Attributes
    ----------
    fastest_time_scale : float
        ``1 / max |lambda|`` over the states (s).
    slowest_time_scale : float
        ``1 / min |lambda|`` over non-zero eigenvalues (s).
    ratio : float
        Stiffness ratio ``max |lambda| / min |lambda|``.
    explicit_step_limit : float
        Largest stable DOP853 step for the fastest eigenvalue (s), about
        ``3.3 / max |lambda|``.
    suggested_method : str
        ``"DOP853"`` (explicit) or ``"Radau"`` (implicit, analytic Jacobian).
    reason : str
    """

    fastest_time_scale: float
    slowest_time_scale: float
    ratio: float
    explicit_step_limit: float
    suggested_method: str
    reason: str


def probe_states(system, result=None, n=40):
    """States to scan: the rest state, and ``n`` samples of a result if given."""
    states = [np.zeros(system.n_states)]
    times = [0.0]
    if result is not None and result.t.size:
        pick = np.linspace(0, result.t.size - 1, min(n, result.t.size)).astype(int)
        states += [result.y[:, i] for i in pick]
        times += [float(result.t[i]) for i in pick]
    return times, states


def stiffness_report(system, result=None, *, n=40):
    """Scan the Jacobian's eigenvalues at rest and along ``result`` (if given).

    Parameters
    ----------
    system : rotorkit.System
    result : rotorkit.Result, optional
        A (short) run whose states are scanned, so contacts that engage in
        the scene are seen engaged.
    n : int
        Number of states taken from ``result``.

    Returns
    -------
    StiffnessReport
    """
    times, states = probe_states(system, result, n)
    largest, smallest = 0.0, np.inf
    for t, y in zip(times, states):
        lam = np.abs(np.linalg.eigvals(system.jacobian(t, y, compiled=False)))
        lam = lam[lam > 1e-9 * max(lam.max(), 1e-300)]
        if lam.size:
            largest, smallest = max(largest, lam.max()), min(smallest, lam.min())
    ratio = largest / smallest
    if ratio > STIFF_RATIO:
        method = "Radau"
        reason = (f"stiffness ratio {ratio:.3g} > {STIFF_RATIO:g}: the fastest time scale {1 / largest:.3g} s "
                  f"limits explicit steps to about {3.3 / largest:.3g} s; an implicit method with the analytic "
                  "Jacobian may take far fewer steps")
    else:
        method = "DOP853"
        reason = (f"stiffness ratio {ratio:.3g} <= {STIFF_RATIO:g}: oscillatory, not stiff; explicit "
                  "Runge-Kutta (compiled engine) is the fastest choice")
    return StiffnessReport(1 / largest, 1 / smallest, ratio, 3.3 / largest, method, reason)
