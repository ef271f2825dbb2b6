"""The front door: ``simulate(system, t_span, ...)``.

Integration runs segment by segment between the system's time
discontinuities (manoeuvre start and end), restarting the integrator at
each, so no step straddles a jump in the equations. Inside a segment the
right-hand side is evaluated with the time nudged inside the segment at its
ends, so each segment sees its own side of a jump.
"""

import math
import sys
import time as _time

import numpy as np

from .errors import ParameterError, SimulationError
from .result import Result

__all__ = ["simulate", "SCIPY_METHODS"]

SCIPY_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _sample_times(t0, t1, sample_rate):
    n = int(math.floor((t1 - t0) * sample_rate + 1e-9)) + 1
    t = t0 + np.arange(n) / sample_rate
    if t[-1] < t1 - 1e-12:
        t = np.append(t, t1)
    return t


def _segments(t0, t1, events):
    cuts = [t0] + sorted(e for e in events if t0 < e < t1) + [t1]
    return list(zip(cuts[:-1], cuts[1:]))


class _Progress:
    """Counts RHS evaluations; reports the time reached now and then."""

    def __init__(self, t0, t1, report, every=20000):
        self.t0, self.t1, self.report, self.every = t0, t1, report, every
        self.count = 0
        self.last_t = t0

    def tick(self, t):
        self.count += 1
        self.last_t = t
        if self.report is not None and self.count % self.every == 0:
            self.report((t - self.t0) / (self.t1 - self.t0), t)


def _print_progress(fraction, t):
    bar = "#" * int(30 * fraction)
    sys.stderr.write(f"\r  simulating [{bar:<30}] {100 * fraction:5.1f} %  t = {t:.3f} s")
    sys.stderr.flush()
    if fraction >= 1:
        sys.stderr.write("\n")


def simulate(system, t_span, *, y0=None, method="DOP853", rtol=1e-6, atol=1e-9, sample_rate=10_000.0,
             max_step=np.inf, progress=None):
    """Integrate a compiled system over ``t_span`` with scipy's ``solve_ivp``.

    Parameters
    ----------
    system : rotorkit.System
        From ``model.compile()``.
    t_span : (float, float)
        Start and end time (s).
    y0 : array_like, optional
        Initial state, shape (n_states,) in ``system.state_names`` order;
        default: all zeros (at rest on the undeflected axis).
    method : str
        A ``solve_ivp`` method: RK45, RK23, DOP853, Radau, BDF, LSODA.
    rtol, atol : float
        Relative and absolute tolerances (``atol`` may be an array).
    sample_rate : float
        Output samples per second (Hz); samples come from dense output.
    max_step : float
        Largest step (s).
    progress : None, bool or callable
        ``True`` prints a progress bar to stderr; a callable is called as
        ``progress(fraction, t)``.

    Returns
    -------
    Result

    Raises
    ------
    SimulationError
        The integration failed; ``err.partial`` holds the samples before the
        failure and ``err.time`` the time reached.
    """
    from scipy.integrate import solve_ivp

    if method not in SCIPY_METHODS:
        raise ParameterError(f"method={method!r} is unknown; expected one of {', '.join(SCIPY_METHODS)}")
    t0, t1 = (float(v) for v in t_span)
    if not t1 > t0:
        raise ParameterError(f"t_span={t_span!r}: the end time must be after the start time")
    if not sample_rate > 0:
        raise ParameterError(f"sample_rate={sample_rate!r} must be > 0 (Hz)")
    y = np.zeros(system.n_states) if y0 is None else np.array(y0, dtype=float)
    if y.shape != (system.n_states,):
        raise ParameterError(f"y0 has shape {y.shape}; expected ({system.n_states},) in the order {system.state_names}")
    if not np.all(np.isfinite(y)):
        raise ParameterError("y0 holds non-finite values")
    report = _print_progress if progress is True else (progress or None)
    counter = _Progress(t0, t1, report)
    samples = _sample_times(t0, t1, sample_rate)
    out_t, out_y, stats = [], [], {"nfev": 0, "njev": 0, "nlu": 0, "segments": 0}
    rhs = system.rhs
    start_wall = _time.perf_counter()
    for k, (a, b) in enumerate(_segments(t0, t1, system.time_events)):
        a_in, b_in = np.nextafter(a, b), np.nextafter(b, a)

        def fun(t, yy, a=a, b=b, a_in=a_in, b_in=b_in):
            counter.tick(t)
            return rhs(a_in if t <= a else (b_in if t >= b else t), yy)

        mask = (samples >= a) & (samples <= b) if k == 0 else (samples > a) & (samples <= b)
        sol = solve_ivp(fun, (a, b), y, method=method, rtol=rtol, atol=atol, t_eval=samples[mask],
                        max_step=max_step)
        stats["nfev"] += sol.nfev
        stats["njev"] += sol.njev
        stats["nlu"] += sol.nlu
        stats["segments"] += 1
        out_t.append(sol.t)
        out_y.append(sol.y)
        if sol.status != 0 or not np.all(np.isfinite(sol.y)):
            partial = _result(system, out_t, out_y, stats, method, rtol, atol, start_wall, False, sol.message)
            reached = counter.last_t
            raise SimulationError(_failure_message(system, sol, reached, a, b), partial=partial, time=reached)
        y = sol.y[:, -1]
    if report is not None:
        report(1.0, t1)
    return _result(system, out_t, out_y, stats, method, rtol, atol, start_wall, True, "success")


def _result(system, out_t, out_y, stats, method, rtol, atol, start_wall, success, message):
    t = np.concatenate(out_t) if out_t else np.empty(0)
    y = np.concatenate(out_y, axis=1) if out_y else np.empty((system.n_states, 0))
    full = dict(stats, method=method, rtol=rtol, atol=atol if np.isscalar(atol) else list(atol),
                wall_time=_time.perf_counter() - start_wall, backend=system.backend, engine="scipy",
                success=success, message=message)
    return Result(t=t, y=y, state_names=system.state_names, parameters=system.parameters, stats=full,
                  name=system.name)


def _failure_message(system, sol, reached, a, b):
    y_last = sol.y[:, -1] if sol.t.size else None
    lines = [f"{system.name}: integration failed at t = {reached:.6g} s (segment {a:g}-{b:g} s): {sol.message}"]
    if y_last is not None:
        lines.append(f"last sample at t = {sol.t[-1]:.6g} s")
        bad = [system.state_names[i] for i in np.flatnonzero(~np.isfinite(y_last))]
        if bad:
            lines.append(f"non-finite states: {', '.join(bad)}")
        else:
            big = np.argsort(-np.abs(y_last))[:3]
            lines.append("largest states at the last sample: "
                         + ", ".join(f"{system.state_names[i]} = {y_last[i]:.3g}" for i in big))
    lines.append("Likely causes: a run-away response (e.g. dry-friction whirl at high friction), contact "
                 "stiffness too high for an explicit method, or too loose a tolerance. Try a tighter rtol, "
                 "method='Radau' for very stiff contact, or check the parameters.")
    return "\n".join(lines)
