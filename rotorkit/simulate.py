"""The front door: ``simulate(system, t_span, ...)``.

Integration runs segment by segment between the system's time
discontinuities (manoeuvre start and end), restarting the integrator at
each, so no step straddles a jump in the equations. Inside a segment the
equations see time clamped just inside it (:meth:`System.within`), so each
segment sees its own side of a jump.

Two engines run a segment (both with scipy's error control):

``"compiled"``
    rotorkit's Dormand-Prince loop, RK45 and DOP853, the whole adaptive
    loop in compiled code: in C with the c back end
    (:mod:`rotorkit.engines.rk_c`), in numba with the numba back end
    (:mod:`rotorkit.engines.rk_numba`).
``"scipy"``
    :func:`scipy.integrate.solve_ivp`, every scipy method.

``engine="auto"`` takes the compiled engine when it applies.
"""

import math
import numbers
import sys
import time as _time
from dataclasses import dataclass

import numpy as np

from . import interrupts
from .errors import ParameterError, SimulationError
from .run_checks import (MAX_STEP_COUNT, auto_bound, bending_rows, check_arguments, check_start, check_system,
                         checked_times, raise_if_ran_away, warn_if_stiff)
from .system import COMPILED_BACKENDS

__all__ = ["simulate", "SCIPY_METHODS", "COMPILED_METHODS", "ENGINES"]

SCIPY_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
COMPILED_METHODS = ("RK45", "DOP853")
#: a state beyond this magnitude has diverged (SI rotor states are many orders smaller)
DIVERGED = 1e10
#: consecutive steps below (span / MAX_STEP_COUNT) after which a scipy run stops as collapsed
COLLAPSED_STEPS = 2000
#: methods that use the analytic Jacobian generated from the symbolic equations
IMPLICIT_METHODS = ("Radau", "BDF", "LSODA")
ENGINES = ("auto", "compiled", "scipy")


@dataclass
class _Segment:
    """What a segment runner returns."""

    t: np.ndarray
    y: np.ndarray
    y_end: np.ndarray
    t_reached: float
    nfev: int
    njev: int = 0
    nlu: int = 0
    events: int = 0
    success: bool = True
    message: str = ""


def uniform_times(t0, t1, sample_rate):
    """t0, t0 + 1/fs, ... and t1 itself (a last sample within 1e-6/fs of t1 is put on it)."""
    n = int(math.floor((t1 - t0) * sample_rate + 1e-6)) + 1
    t = t0 + np.arange(n) / sample_rate
    if abs(t[-1] - t1) <= 1e-6 / sample_rate:
        t[-1] = t1
    elif t[-1] < t1:
        t = np.append(t, t1)
    return t


def _segments(t0, t1, events):
    cuts = [t0] + sorted(e for e in events if t0 < e < t1) + [t1]
    return list(zip(cuts[:-1], cuts[1:]))


def _print_progress(fraction, t):
    bar = "#" * int(30 * fraction)
    sys.stderr.write(f"\r  simulating [{bar:<30}] {100 * fraction:5.1f} %  t = {t:.3f} s")
    sys.stderr.flush()
    if fraction >= 1:
        sys.stderr.write("\n")


def _escaped(system, samples, bound):
    """A run-away message if a bending displacement in ``samples`` exceeds ``bound`` (m), else ''."""
    if bound is None or samples.size == 0:
        return ""
    rows = bending_rows(system)
    values = np.abs(samples[rows])
    if not (values > bound).any():
        return ""
    i, j = np.unravel_index(np.argmax(values), values.shape)
    return (f"run-away: |{system.coordinate_names[rows[i]]}| = {values[i, j]:.3g} m exceeds the bound {bound:g} m "
            "(likely dry-friction whirl or a lost support)")


def _run_scipy(system, a, b, y, t_eval, options, tick, deadline, bound=None):
    """One segment with a scipy OdeSolver, stepped here (as solve_ivp does) to keep
    every sample on failure, check states, honour the wall-time limit and, with
    ``contact_events``, restart at every contact onset and loss."""
    import scipy.integrate as si
    from scipy.optimize import brentq

    segment = system.within(a, b)
    rhs = segment.rhs

    def fun(t, yy):
        tick(t)
        return rhs(t, yy)

    opts = {k: v for k, v in options.items() if k not in ("method", "contact_events")}
    if options["method"] in IMPLICIT_METHODS and getattr(segment, "has_jacobian", False):
        opts["jac"] = segment.jacobian
    solver_class = getattr(si, options["method"])
    events = options.get("contact_events") and segment.n_switches > 0
    solver = solver_class(fun, a, y, b, **opts)
    counts = {"nfev": 0, "njev": 0, "nlu": 0, "events": 0}
    g_old = segment.switch_values(a, y) if events else None
    ts, ys = [], []
    if t_eval.size and t_eval[0] == a:
        ts.append(np.array([a]))
        ys.append(y[:, None].copy())
    k = int(ts[0].size) if ts else 0
    message = "success"

    def take_samples(dense, t_upto):
        """Samples up to t_upto; ``dense`` is called (and, for DOP853, paid for) only if there are any."""
        nonlocal k
        stop = np.searchsorted(t_eval, t_upto, side="right")
        if stop > k:
            values = dense()(t_eval[k:stop]).reshape(len(y), -1)  # before any append: an interrupt here
            ts.append(t_eval[k:stop])                             # leaves ts and ys the same length
            ys.append(values)
            k = stop

    tiny_step = (b - a) / MAX_STEP_COUNT  # steps this small all the way would exceed the step budget
    tiny_run = 0
    try:
        while solver.status == "running":
            t_old = solver.t
            step_message = solver.step()
            if solver.status == "failed":
                message = step_message
                break
            tiny_run = tiny_run + 1 if 0 < solver.t - t_old < tiny_step else 0
            if tiny_run > COLLAPSED_STEPS:
                message = (f"the step size collapsed to {solver.t - t_old:.3g} s for {COLLAPSED_STEPS} steps at "
                           f"t = {solver.t:.6g} s: the rest of the run would take more than {MAX_STEP_COUNT:.0e} "
                           "steps (an expression of the model growing without bound, e.g. a speed such as "
                           "exp(1000 t), or an extremely stiff contact)")
                break
            if not np.all(np.isfinite(solver.y)) or np.abs(solver.y).max() > DIVERGED:
                message = f"non-finite or diverging state (NaN, inf or |y| > {DIVERGED:g}) after a step"
                break
            if events:
                g_new = segment.switch_values(solver.t, solver.y)
                crossed = np.flatnonzero(np.sign(g_old) * np.sign(g_new) < 0)
                if crossed.size:
                    dense = solver.dense_output()
                    switch = lambda tt, i: segment.switch_values(tt, dense(tt))[i]  # noqa: E731
                    # only crossings the step's own interpolant brackets (g is ~0 right after a restart)
                    bracketed = [i for i in crossed if np.sign(switch(t_old, i)) * np.sign(switch(solver.t, i)) < 0]
                    if bracketed:
                        t_event = min(brentq(switch, t_old, solver.t, args=(i,), xtol=1e-14,
                                             rtol=4 * np.finfo(float).eps) for i in bracketed)
                        take_samples(lambda: dense, t_event)
                        y_event = dense(t_event)
                        for key in ("nfev", "njev", "nlu"):
                            counts[key] += getattr(solver, key)
                        counts["events"] += 1
                        solver = solver_class(fun, t_event, y_event, b, **opts)
                        g_old = segment.switch_values(t_event, y_event)
                        g_old[crossed] = g_new[crossed]  # the crossings that stopped us are behind
                        continue
                g_old = g_new
            take_samples(solver.dense_output, solver.t)
            escaped = _escaped(system, solver.y[:, None], bound)
            if escaped:
                message = escaped
                break
            if deadline is not None and _time.perf_counter() > deadline:
                message = "wall-time limit reached"
                break
    except KeyboardInterrupt:  # Ctrl-C: stop here, keep the samples so far
        message = f"interrupted (Ctrl-C) at t = {solver.t:.6g} s"
        del ts[len(ys):]  # an interrupt between the two appends of take_samples
    ok = solver.status == "finished" and not message.startswith(("run-away", "interrupted"))
    for key in ("nfev", "njev", "nlu"):
        counts[key] += getattr(solver, key)
    t_out = np.concatenate(ts) if ts else np.empty(0)
    y_out = np.concatenate(ys, axis=1) if ys else np.empty((len(y), 0))
    return _Segment(t=t_out, y=y_out, y_end=solver.y.copy(), t_reached=float(solver.t), nfev=counts["nfev"],
                    njev=counts["njev"], nlu=counts["nlu"], events=counts["events"], success=ok,
                    message=message if not ok else "success")


#: the compiled engine returns to Python about this often (s of wall time): to honour Ctrl-C, a wall-time
#: limit and a displacement bound between pieces; each piece continues the previous one's steps exactly
PIECE_SECONDS = 0.25
#: accepted steps and sample columns of the first compiled piece (later pieces are sized from its wall time)
FIRST_PIECE_STEPS = 2_000
FIRST_PIECE_SAMPLES = 4_096


def _run_compiled(system, a, b, y, t_eval, options, tick, deadline, bound=None):
    """One segment in the compiled loop, run in pieces of about :data:`PIECE_SECONDS` of wall time.

    Between pieces Python looks at Ctrl-C, the wall-time limit and the
    displacement bound. A piece ends between two steps and the next starts
    with the step size the controller proposed (``first_step=h_next``), so
    the steps, and the result, are those of one uninterrupted run.
    """
    if system.backend == "c":
        from .engines.rk_c import STATUS_PAUSED, integrate

        core = system.core.address
    else:
        from .engines.rk_numba import STATUS_PAUSED, integrate

        core = system.core
    p = system.within(a, b).prepared_parameters
    ts, ys, nfev, start, first_step = [], [], 0, a, None
    steps, capacity = FIRST_PIECE_STEPS, FIRST_PIECE_SAMPLES

    def segment(success, message, t_reached):
        t_done = np.concatenate(ts) if ts else np.empty(0)
        y_done = np.concatenate(ys, axis=1) if ys else np.empty((len(y), 0))
        return _Segment(t=t_done, y=y_done, y_end=y, t_reached=t_reached, nfev=nfev, success=success,
                        message=message)

    while True:
        try:
            rest = t_eval[np.searchsorted(t_eval, start, side="right" if ts else "left"):]  # a view: no copy
            began = _time.perf_counter()
            sol = integrate(core, start, b, y, p, rest, first_step=first_step, pause_after=steps,
                            sample_capacity=capacity, **options)
            n = sol.n_samples_done
            ts.append(sol.t[:n].copy())
            ys.append(sol.y[:, :n].copy())  # copies: the piece's buffer is not kept alive
            nfev += sol.nfev
            y = sol.y_reached
            escaped = _escaped(system, ys[-1], bound)
            late = deadline is not None and _time.perf_counter() > deadline
            if sol.status != STATUS_PAUSED or escaped or late:
                if escaped:
                    return segment(False, escaped, sol.t_reached)
                if late and sol.status == STATUS_PAUSED:
                    return segment(False, "wall-time limit reached", sol.t_reached)
                return segment(sol.success, sol.message if not sol.success else "success", sol.t_reached)
            start, first_step = sol.t_reached, min(sol.h_next, b - sol.t_reached)
            tick(start, every=1)
            grow = min(max(PIECE_SECONDS / max(_time.perf_counter() - began, 1e-4), 0.1), 10.0)
            steps = int(min(max(steps * grow, 100), 10_000_000))
            capacity = int(max(FIRST_PIECE_SAMPLES, 4 * grow * n))
        except KeyboardInterrupt:  # Ctrl-C, in the compiled loop or here: keep the samples of the finished pieces
            del ts[len(ys):], ys[len(ts):]
            reached = float(ts[-1][-1]) if ts and ts[-1].size else start
            return segment(False, f"interrupted (Ctrl-C) at t = {reached:.6g} s", reached)


def _choose_engine(engine, system, method):
    if engine not in ENGINES:
        raise ParameterError(f"engine={engine!r} is unknown; expected one of {', '.join(ENGINES)}")
    compiled_ok = system.backend in COMPILED_BACKENDS and method in COMPILED_METHODS
    if engine == "auto":
        return "compiled" if compiled_ok else "scipy"
    if engine == "compiled" and not compiled_ok:
        why = (f"method {method!r} (it runs {', '.join(COMPILED_METHODS)})" if method not in COMPILED_METHODS
               else f"the {system.backend!r} back end (compile with backend='c' or 'numba')")
        raise ParameterError(f"engine='compiled' cannot run {why}; use engine='scipy'")
    return engine


def simulate(system, t_span, *, y0=None, method="DOP853", rtol=1e-6, atol=1e-9, sample_rate=10_000.0,
             max_step=np.inf, engine="auto", progress=None, time_limit=None, contact_events=False, bound="auto",
             sample_times=None, check_convergence="auto"):
    """Integrate a compiled system over ``t_span``.

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
        RK45 or DOP853 (both engines); RK23, Radau, BDF, LSODA (scipy).
    rtol, atol : float
        Relative and absolute tolerances (``atol`` may be an array).
    sample_rate : float
        Output samples per second (Hz); samples come from dense output.
    max_step : float
        Largest step (s).
    engine : {"auto", "compiled", "scipy"}
        See the module docstring. ``auto``: compiled when the system has the
        numba back end and the method is RK45 or DOP853.
    progress : None, bool or callable
        ``True`` prints a progress bar to stderr; a callable is called as
        ``progress(fraction, t)`` (per segment with the compiled engine).
    time_limit : float, optional
        Wall-time limit (s). When reached, the run stops cleanly with a
        :class:`SimulationError` holding the samples computed so far.
    bound : float, "auto" or None
        Largest bending displacement |x|, |y| (m) before a run counts as a
        run-away (e.g. dry-friction whirl): a float stops the run there with a
        :class:`SimulationError` (early, by checking as it goes). ``"auto"``
        (default): for a scene with a rub stator, max(1 cm, 100 x the largest
        rub clearance), checked on the samples after the run, so a run-away
        never comes back as a result (the numerics are those of an unbounded
        run); no bound without a stator. ``None``: no check.
    sample_times : array_like, optional
        Explicit output instants (s), sorted, inside ``t_span``, taken from
        dense output instead of the ``sample_rate`` grid (used by
        :func:`rotorkit.sensors.measure` to sample each sensor at its own
        instants).
    check_convergence : bool or "auto"
        Also run with both tolerances 100 times tighter and compare
        (:mod:`rotorkit.convergence`): ``result.stats["convergence"]`` holds
        the outcome, and a :class:`~rotorkit.convergence.ConvergenceWarning`
        says when the trajectory differs by more than 1 % of a coordinate's
        amplitude. Costs the reference run (about 2x). ``"auto"`` (default):
        only for stiff contact, a contact stiffness of at least
        :data:`~rotorkit.convergence.STIFF_CONTACT` (1e10 N/m), where the
        step size collapses at every contact and the result often depends on
        the tolerance.
    contact_events : bool
        Locate every contact onset and loss (the elements' switch functions:
        rub gap, each ball's deformation) and restart the integrator there,
        so no step straddles a kink. scipy engine only (``auto`` picks it);
        ``stats["events"]`` counts the restarts.

    Returns
    -------
    Result

    Raises
    ------
    SimulationError
        The integration failed; ``err.partial`` holds the samples before the
        failure and ``err.time`` the time reached.
    """
    check_system(system)
    from .linear.modal_damping import check_time_run

    check_time_run(system, "simulate")  # a reduced system leaves a rotor's ModalDamping out
    from .reference_run import resolve_check

    check_convergence, stiff_contact = resolve_check(system, check_convergence)
    if method not in SCIPY_METHODS:
        raise ParameterError(f"method={method!r} is unknown; expected one of {', '.join(SCIPY_METHODS)}")
    t0, t1, sample_rate, rtol, atol, max_step, time_limit = check_arguments(
        system, t_span, sample_rate, rtol, atol, max_step, time_limit, progress)
    if contact_events and engine == "compiled":
        raise ParameterError("contact_events=True needs engine='scipy' (the compiled engine does not locate events)")
    engine = "scipy" if contact_events and engine == "auto" else engine
    engine = _choose_engine(engine, system, method)
    try:
        y = np.zeros(system.n_states) if y0 is None else np.array(y0, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"y0={y0!r} is not a vector of {system.n_states} real numbers") from exc
    if y.shape != (system.n_states,):
        raise ParameterError(f"y0 has shape {y.shape}; expected ({system.n_states},) in the order {system.state_names}")
    if not np.all(np.isfinite(y)):
        raise ParameterError("y0 holds non-finite values")
    report = _print_progress if progress is True else (progress or None)
    count = [0]

    def tick(t, every=20000):
        """Progress after every ``every`` calls (scipy: per step; compiled: per piece, ``every=1``); a Ctrl-C
        that other code swallowed is raised again here (:mod:`rotorkit.interrupts`)."""
        if interrupts.received:
            raise KeyboardInterrupt
        count[0] += 1
        if report is not None and count[0] % every == 0:
            report((t - t0) / (t1 - t0), t)

    checked_after = None
    if isinstance(bound, str) and bound == "auto":
        bound, checked_after = None, auto_bound(system)
    if bound is not None:
        if isinstance(bound, (bool, str)) or not isinstance(bound, numbers.Real) or not math.isfinite(bound) \
                or not bound > 0:
            raise ParameterError(f"bound={bound!r} must be a finite length > 0 (m), 'auto' or None")
        bound = float(bound)  # numpy scalars (np.float32(1e-3)) included
    check_start(system, t0, y)
    if method not in IMPLICIT_METHODS and getattr(system, "has_jacobian", False):
        warn_if_stiff(system, t0, t1, y, sample_rate)
    options = {"method": method, "rtol": rtol, "atol": atol, "max_step": max_step}
    if contact_events:
        options["contact_events"] = True
    run = _run_compiled if engine == "compiled" else _run_scipy
    samples = uniform_times(t0, t1, sample_rate) if sample_times is None else checked_times(sample_times, t0, t1, system)
    out_t, out_y = [], []
    stats = {"nfev": 0, "njev": 0, "nlu": 0, "segments": 0, "events": 0}
    start_wall = _time.perf_counter()
    deadline = None if time_limit is None else start_wall + time_limit
    y_start = y.copy()
    for k, (a, b) in enumerate(_segments(t0, t1, system.time_events)):
        try:
            seg = _run_segment(run, system, k, a, b, y, samples, options, tick, deadline, bound, stats, out_t, out_y)
        except KeyboardInterrupt:  # Ctrl-C between the engine's own checks (between segments, in bookkeeping)
            del out_t[len(out_y):], out_y[len(out_t):]  # the lists stay even
            reached = float(out_t[-1][-1]) if out_t and out_t[-1].size else a
            seg = _Segment(t=np.empty(0), y=np.empty((system.n_states, 0)), y_end=y, t_reached=reached, nfev=0,
                           success=False, message=f"interrupted (Ctrl-C) at t = {reached:.6g} s")
        except (OverflowError, ZeroDivisionError, FloatingPointError, ValueError) as exc:
            if isinstance(exc, ValueError) and "math domain" not in str(exc):
                raise
            # the Python back end's math raises where compiled code gives inf: an expression of the model (a speed
            # such as exp(1000 t)) left the range of doubles
            del out_t[len(out_y):], out_y[len(out_t):]
            reached = float(out_t[-1][-1]) if out_t and out_t[-1].size else a
            seg = _Segment(t=np.empty(0), y=np.empty((system.n_states, 0)), y_end=y, t_reached=reached, nfev=0,
                           success=False, message=f"the equations overflowed or left their domain between "
                                                  f"t = {reached:.6g} s and {b:.6g} s ({type(exc).__name__}: {exc}); "
                                                  "an expression of the model (e.g. a speed profile) grows beyond "
                                                  "1e308 or is undefined there")
        if not seg.success:
            partial = _result(system, out_t, out_y, stats, options, engine, start_wall, False, seg.message)
            raise SimulationError(_failure_message(system, seg, a, b), partial=partial, time=seg.t_reached)
        y = seg.y_end
        if report is not None:
            report((b - t0) / (t1 - t0), b)
    result = _result(system, out_t, out_y, stats, options, engine, start_wall, True, "success")
    if checked_after is not None:
        raise_if_ran_away(system, result, checked_after)
    if check_convergence:
        from .reference_run import compare_with_reference, warn_if_not_converged

        outcome = compare_with_reference(simulate, system, result, y0=y_start, engine=engine, max_step=max_step,
                                         contact_events=contact_events,
                                         bound="auto" if checked_after is not None else bound)
        result.stats["convergence"] = outcome.as_dict()
        if stiff_contact:
            result.stats["convergence"]["checked_because"] = stiff_contact
        warn_if_not_converged(outcome, stiff_contact)
    return result


def _run_segment(run, system, k, a, b, y, samples, options, tick, deadline, bound, stats, out_t, out_y):
    """Run segment ``k`` = (a, b), add its samples to ``out_t``/``out_y`` and its counts to ``stats``."""
    mask = (samples >= a) & (samples <= b) if k == 0 else (samples > a) & (samples <= b)
    seg = run(system, a, b, y, samples[mask], options, tick, deadline, bound)
    for key in ("nfev", "njev", "nlu", "events"):
        stats[key] += getattr(seg, key)
    stats["segments"] += 1
    out_t.append(seg.t)
    out_y.append(seg.y)
    if seg.success and seg.y.size and not (np.all(np.isfinite(seg.y)) and np.abs(seg.y).max() <= DIVERGED):
        seg.success = False  # dense output between accepted steps past the divergence limit: no result
        seg.message = f"a sample is non-finite or past the divergence limit |y| > {DIVERGED:g}"
    return seg


def _result(system, out_t, out_y, stats, options, engine, start_wall, success, message):
    t = np.concatenate(out_t) if out_t else np.empty(0)
    y = np.concatenate(out_y, axis=1) if out_y else np.empty((system.n_states, 0))
    atol = options["atol"]
    full = dict(stats, method=options["method"], rtol=options["rtol"], atol=atol if np.isscalar(atol) else list(atol),
                contact_events=bool(options.get("contact_events", False)),
                wall_time=_time.perf_counter() - start_wall, backend=system.backend, engine=engine,
                success=success, message=message)
    from .result import Result  # here: ``import rotorkit`` imports this module, not the result class

    return Result(t=t, y=y, state_names=system.state_names, parameters=system.parameters, stats=full,
                  name=system.name)


def _failure_message(system, seg, a, b):
    lines = [f"{system.name}: integration failed at t = {seg.t_reached:.6g} s (segment {a:g}-{b:g} s): {seg.message}"]
    if seg.t.size:
        y_last = seg.y[:, -1]
        lines.append(f"last sample at t = {seg.t[-1]:.6g} s")
        bad = [system.state_names[i] for i in np.flatnonzero(~np.isfinite(y_last))]
        if bad:
            lines.append(f"non-finite states: {', '.join(bad)}")
        else:
            big = np.argsort(-np.abs(y_last))[:3]
            lines.append("largest states at the last sample: "
                         + ", ".join(f"{system.state_names[i]} = {y_last[i]:.3g}" for i in big))
    if seg.message.startswith("interrupted"):
        return "\n".join(lines + ["The samples up to the interruption are in err.partial."])
    lines.append("Likely causes: a run-away response (e.g. dry-friction whirl at high friction), contact "
                 "stiffness too high for an explicit method, or too loose a tolerance. Try a tighter rtol, "
                 "method='Radau' for very stiff contact, or check the parameters.")
    return "\n".join(lines)
