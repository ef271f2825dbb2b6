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

__all__ = ["StiffnessReport", "stiffness_report", "probe_states", "fastest_rate", "explicit_step_warning",
           "finite_difference_jacobian"]

#: above this ratio of fastest to slowest time scale, an implicit method is suggested
STIFF_RATIO = 1e3
#: DOP853's stability boundary along the negative real axis (|lambda| h), about
STABILITY_LIMIT = 3.3
#: warn an explicit run when stability forces this many steps per output interval ...
STEPS_PER_OUTPUT = 100.0
#: ... and at least this many steps over the whole span (shorter runs are cheap whatever limits them)
MIN_FORCED_STEPS = 1e4
#: above this many states the spectral radius comes from ARPACK (a few matrix-vector products), not a full eig
DENSE_EIG_STATES = 200


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


def fastest_rate(jacobian):
    """Spectral radius ``max |lambda|`` of a Jacobian (1/s).

    A full eigenvalue problem (O(n^3)) only for small systems; above
    :data:`DENSE_EIG_STATES` states ARPACK finds the largest-magnitude
    eigenvalue from matrix-vector products.
    """
    J = np.asarray(jacobian, dtype=float)
    if J.shape[0] <= DENSE_EIG_STATES:
        return float(np.abs(np.linalg.eigvals(J)).max())
    from scipy.sparse.linalg import ArpackNoConvergence, eigs

    try:
        # a few of the largest, from a fixed start vector: the top of a chain's spectrum is clustered, and
        # one eigenvalue from ARPACK's random start may be a neighbour of the largest (seen: 0.6 % low)
        n = J.shape[0]
        lam = eigs(J, k=min(6, n - 2), which="LM", tol=0, v0=np.ones(n), return_eigenvectors=False,
                   maxiter=50 * n)
    except ArpackNoConvergence as err:
        lam = err.eigenvalues
        if lam.size == 0:
            return float(np.abs(np.linalg.eigvals(J)).max())
    return float(np.abs(lam).max())


#: relative step of the finite-difference Jacobian (about the cube root of the machine epsilon: central differences)
RELATIVE_STEP = 2.0**-20


def finite_difference_jacobian(system, t, y):
    """``d rhs / d y`` by central differences of ``system.rhs`` (compiled where the system is), shape (2n, 2n).

    Column by column (``2 * 2n`` right-hand sides); the step of state ``j``
    is :data:`RELATIVE_STEP` ``* max(|y_j|, s)`` with ``s = 1e-3`` for
    coordinates (a step of about 1e-9 m or rad at rest, well inside contact
    clearances) and ``1`` for velocities. Enough for a spectral radius (the
    analytic Jacobian's to about 1e-8 on the preset); :meth:`System.jacobian`
    gives the exact one.

    Parameters
    ----------
    system : rotorkit.System
    t : float
        Time (s).
    y : array_like, shape (2n,)
        State, in ``system.state_names`` order.
    """
    y = np.asarray(y, dtype=float)
    size = y.size
    floor = np.r_[np.full(size // 2, 1e-3), np.ones(size - size // 2)]
    steps = RELATIVE_STEP * np.maximum(np.abs(y), floor)
    J = np.empty((size, size))
    rhs = system.rhs
    for j in range(size):
        up, down = y.copy(), y.copy()
        up[j] += steps[j]
        down[j] -= steps[j]
        J[:, j] = (rhs(t, up) - rhs(t, down)) / (up[j] - down[j])
    return J


def explicit_step(system, t0, y):
    """The largest stable explicit step (s) at state ``y`` and time ``t0``: ``3.3 / |lambda_max|``; None if there is
    no fast scale. Remembered per system, time and state."""
    key = (float(t0), np.asarray(y, dtype=float).tobytes())
    memo = system.__dict__.setdefault("_fastest_rate_memo", {})
    if key not in memo:
        if len(memo) > 64:
            memo.clear()
        memo[key] = fastest_rate(finite_difference_jacobian(system.within(t0, t0 + 1.0), t0, y))
    rate = memo[key]
    return STABILITY_LIMIT / rate if rate > 0 else None


def explicit_step_warning(system, t0, t1, y, sample_rate):
    """Why an explicit run over ``[t0, t1]`` sampled at ``sample_rate`` would crawl, or None.

    What limits an explicit Runge-Kutta step is the fastest time scale of the
    linearised system (``|lambda_max| h`` inside the stability region), not
    the ratio to the slowest one: a slow scale (a spool floating in a bearing
    clearance, a soft support) costs an explicit method nothing. So the check
    compares the stability-limited step ``3.3 / |lambda_max|`` with the
    output interval ``1 / sample_rate`` and the span: it warns when stability
    forces more than :data:`STEPS_PER_OUTPUT` steps per output sample (the
    fastest scale is far above anything the output resolves) and at least
    :data:`MIN_FORCED_STEPS` steps in all.

    Cost: one finite-difference Jacobian (:func:`finite_difference_jacobian`,
    so an explicit run never generates the analytic one) and its spectral
    radius (:func:`fastest_rate`), remembered per system, time and state, so
    repeated runs (sweeps) pay once.
    """
    step = explicit_step(system, t0, y)
    if step is None:
        return None
    rate = STABILITY_LIMIT / step
    per_output = 1.0 / (sample_rate * step)
    forced = (t1 - t0) / step
    if per_output < STEPS_PER_OUTPUT or forced < MIN_FORCED_STEPS:
        return None
    return (f"{system.name}: the fastest time scale at the start state, {1 / rate:.3g} s, limits an explicit method "
            f"to steps of about {step:.3g} s: {per_output:.3g} steps per output interval ({1 / sample_rate:.3g} s), "
            f"{forced:.3g} over the span. If that time scale is not of interest (very stiff contact or links), "
            "method='Radau' (analytic Jacobian) may take far fewer steps; "
            "rotorkit.analysis.stiffness.stiffness_report scans a whole run.")
