"""What a run may ask, checked before anything runs; and the run-away bound checked after.

:func:`rotorkit.simulate` calls these: the system and every setting
(:func:`check_system`, :func:`check_arguments`, :func:`checked_times`, with
the limits below and the memory the samples need), the start state
(:func:`check_start`) and, for an explicit method, the fastest time scale
there (:func:`warn_if_stiff`); after the run, the default bound of a scene
with a rub stator (:func:`auto_bound`, :func:`raise_if_ran_away`). Each
refusal is a ParameterError (or SimulationError) naming the argument, the
value and what to do.
"""

import math

import numpy as np

from .errors import ParameterError, SimulationError
from .memory import available_memory as _available_memory  # a module global: tests patch it here

__all__ = ["check_system", "check_arguments", "checked_times", "check_start", "warn_if_stiff", "auto_bound",
           "raise_if_ran_away", "sample_memory", "bending_rows", "number", "check_memory", "raise_non_finite_start",
           "MAX_SAMPLES", "MAX_SAMPLE_BYTES", "MAX_RTOL", "MAX_ATOL", "MAX_STEP_COUNT", "NOT_DISPLACEMENTS"]

#: most samples one run may be asked for (a sample_rate over the span, or sample_times)
MAX_SAMPLES = 1e8
#: most memory the samples of one run may take (also at most half the free memory)
MAX_SAMPLE_BYTES = 16e9
#: loosest tolerances that still control the error of a rotor response (larger ones are refused)
MAX_RTOL = 0.1
#: most steps a run may be asked for by max_step (the compiled engine's own limit on step attempts)
MAX_STEP_COUNT = 5e7
MAX_ATOL = 1e-2


#: coordinate name prefixes that are not lateral displacements in m: torsion angles, tilts, modal coordinates
NOT_DISPLACEMENTS = ("alpha", "thx", "thy", "eta", "spin")  # spin: a driven rotor's spin angle (rad)


def bending_rows(system):
    """Rows of the lateral displacements (x, y, pedestals; not angles or modal coordinates) in a state vector."""
    return [i for i, name in enumerate(system.coordinate_names) if not name.startswith(NOT_DISPLACEMENTS)]


def check_system(system):
    """ArgumentTypeError unless ``system`` is a compiled system, or duck-typed like one (a Model must be compiled
    first)."""
    from .errors import ArgumentTypeError
    from .model import Model

    if not isinstance(system, Model) and all(hasattr(system, a) for a in ("n_states", "rhs", "within", "state_names")):
        return
    if isinstance(system, Model):
        raise ArgumentTypeError(f"simulate: got the Model {system.name!r}; expected a compiled system: "
                                "simulate(model.compile(), ...)")
    raise ArgumentTypeError(f"simulate: got {type(system).__name__}; expected a compiled system "
                            "(rotorkit.Model(...).compile() or rotorkit.reduce(...))")


def checked_times(times, t0, t1, system=None):
    """Explicit sample instants: finite, sorted, inside [t0, t1]; at most MAX_SAMPLES of them, fitting in memory."""
    size = getattr(times, "size", None) if not isinstance(times, (list, tuple)) else len(times)
    if isinstance(size, int) and size >= MAX_SAMPLES:  # before any copy of them is made
        need = 2 * 8 * ((system.n_states if system is not None else 1) + 1) * size
        raise ParameterError(f"sample_times: {size} times, more than {MAX_SAMPLES - 1:.0f} (the samples would take "
                             f"about {need / 1e9:.3g} GB and an interpolation each): give fewer sample times")
    try:
        t = np.asarray(times, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ParameterError(f"sample_times: expected an array of times in s, got {type(times).__name__}") from None
    if not t.size or not np.all(np.isfinite(t)) or np.any(np.diff(t) < 0) or t[0] < t0 or t[-1] > t1:
        raise ParameterError(f"sample_times: expected finite, sorted times inside t_span = ({t0:g}, {t1:g}) s")
    return t


AUTO_BOUND_FLOOR = 0.01  # m
AUTO_BOUND_FACTOR = 100.0


def auto_bound(system):
    """The default run-away bound: for a scene with a rub stator, max(1 cm, 100 x its largest clearance)."""
    from .elements import RubStator

    model = getattr(system, "model", None)
    clearances = [e.clearance for e in getattr(model, "elements", ()) if isinstance(e, RubStator)]
    return max(AUTO_BOUND_FLOOR, AUTO_BOUND_FACTOR * max(clearances)) if clearances else None


def raise_if_ran_away(system, result, bound):
    """A run that passed the bound comes back as an error, with the samples before it."""
    rows = bending_rows(system)
    over = np.abs(result.y[rows]) > bound
    if not over.any():
        return
    first = int(np.argmax(over.any(axis=0)))
    row = rows[int(np.argmax(over[:, first]))]
    partial = result.window(result.t[0], result.t[max(first - 1, 0)])
    raise SimulationError(
        f"{system.name}: run-away at t = {result.t[first]:.6g} s: |{system.coordinate_names[row]}| = "
        f"{abs(result.y[row, first]):.3g} m exceeds the bound {bound:g} m (default for a scene with a rub stator: "
        "100 x its clearance, at least 1 cm). Likely dry-friction whirl; the samples before it are in err.partial. "
        "Pass bound=<m> to stop such runs early, or bound=None to accept them.",
        partial=partial, time=float(result.t[first]))


def number(value, name, expected, *, positive=True, allow_inf=False):
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"{name}={value!r} is not a number: expected {expected}") from None
    if np.isnan(v) or (np.isinf(v) and not allow_inf) or (positive and not v > 0):
        raise ParameterError(f"{name}={value!r}: expected {expected}")
    return v


def sample_memory(n_states, duration, sample_rate):
    """Bytes the samples of a run take at their peak: (n_states + 1) x n_samples float64, twice
    (the per-segment pieces and the joined array exist together for a moment)."""
    n_samples = math.floor(duration * sample_rate) + 2
    return 2 * 8 * (n_states + 1) * n_samples


def check_memory(system, duration, sample_rate):
    """Refuse a run whose samples cannot fit in memory, before allocating anything."""
    need = sample_memory(system.n_states, duration, sample_rate)
    free = _available_memory()
    limit = min(MAX_SAMPLE_BYTES, 0.5 * free) if free else MAX_SAMPLE_BYTES
    if need > limit:
        fitting = sample_rate * limit / need
        raise ParameterError(
            f"sample_rate={sample_rate:g} Hz over {duration:g} s of {system.n_states} states needs about "
            f"{need / 1e9:.3g} GB for the samples (limit {limit / 1e9:.3g} GB: half the free memory, at most "
            f"{MAX_SAMPLE_BYTES / 1e9:g} GB); lower sample_rate to {fitting:.3g} Hz or less, or simulate a shorter span")


def check_arguments(system, t_span, sample_rate, rtol, atol, max_step, time_limit, progress):
    """Every run setting checked before anything runs: ParameterError naming the argument."""
    try:
        t0, t1 = t_span
    except (TypeError, ValueError):
        raise ParameterError(f"t_span={t_span!r}: expected (start, end) in s") from None
    t0 = number(t0, "t_span start", "a finite time in s", positive=False)
    t1 = number(t1, "t_span end", "a finite time in s", positive=False)
    if not t1 > t0:
        raise ParameterError(f"t_span={t_span!r}: the end time must be after the start time")
    sample_rate = number(sample_rate, "sample_rate", "a rate > 0 in Hz")
    if (t1 - t0) * sample_rate > 1e9:  # absurd counts (a span of 1e300 s): named by the span, before any estimate
        raise ParameterError(f"t_span=({t0:g}, {t1:g}) at sample_rate={sample_rate!r} gives more than 1e9 samples; "
                             "lower the sample rate or the span")
    check_memory(system, t1 - t0, sample_rate)  # then the memory the samples need, then their count
    if (t1 - t0) * sample_rate > MAX_SAMPLES:
        n, need = (t1 - t0) * sample_rate, sample_memory(system.n_states, t1 - t0, sample_rate)
        raise ParameterError(f"t_span=({t0:g}, {t1:g}) at sample_rate={sample_rate!r} gives {n:.3g} samples, more "
                             f"than {MAX_SAMPLES:.0e} (about {need / 1e9:.3g} GB and an interpolation per sample); "
                             "lower the sample rate or the span")
    rtol = number(rtol, "rtol", "a relative tolerance > 0 (e.g. 1e-6)")
    if rtol > MAX_RTOL:
        raise ParameterError(f"rtol={rtol!r} cannot give an answer: a relative error above {MAX_RTOL:g} controls "
                             "nothing; use e.g. rtol=1e-6 (check a result with check_convergence=True)")
    try:
        atol_arr = np.asarray(atol, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"atol={atol!r}: expected a tolerance > 0 or one per state") from None
    if atol_arr.ndim > 1 or (atol_arr.ndim == 1 and atol_arr.shape != (system.n_states,)) or \
            not np.all(np.isfinite(atol_arr)) or not np.all(atol_arr > 0):
        raise ParameterError(f"atol={atol!r}: expected a tolerance > 0, or {system.n_states} of them (one per state)")
    if np.any(atol_arr > MAX_ATOL):
        raise ParameterError(f"atol={atol!r} cannot give an answer: an absolute error above {MAX_ATOL:g} (SI: "
                             "1 cm, 0.01 rad) is larger than the responses rotorkit computes; use e.g. atol=1e-9")
    max_step = number(max_step, "max_step", "a step > 0 in s (inf: unbounded)", allow_inf=True)
    if (t1 - t0) / max_step > MAX_STEP_COUNT:
        raise ParameterError(f"max_step={max_step!r} over t_span=({t0:g}, {t1:g}) asks for at least "
                             f"{(t1 - t0) / max_step:.2g} steps, more than the {MAX_STEP_COUNT:.0e} any run may take "
                             "(hours of wall time); raise max_step, or shorten the span")
    if time_limit is not None:
        time_limit = number(time_limit, "time_limit", "a wall time > 0 in s, or None", allow_inf=True)
    if progress is not None and progress is not True and progress is not False and not callable(progress):
        raise ParameterError(f"progress={progress!r}: expected None, True or a function progress(fraction, t)")
    return t0, t1, sample_rate, rtol, atol, max_step, time_limit


def check_start(system, t0, y):
    """The derivative at the start state must be finite (a subnormal mass gives inf, then LinAlgError)."""
    with np.errstate(all="ignore"):
        try:
            dydt = np.asarray(system.within(t0, t0 + 1.0).rhs(t0, y), dtype=float)
            ok = bool(np.all(np.isfinite(dydt)))
        except (np.linalg.LinAlgError, ZeroDivisionError, OverflowError, FloatingPointError):
            ok = False
    if not ok:
        raise_non_finite_start(system)


def raise_non_finite_start(system):
    """ParameterError: the equations are not finite at the start (naming masses too small to invert)."""
    masses = {k: v for k, v in system.parameters.items() if k.endswith(("_mass", "_inertia")) and abs(v) < 1e-100}
    hint = f" ({', '.join(f'{k} = {v:g}' for k, v in masses.items())})" if masses else ""
    raise ParameterError(
        f"{system.name}: the equations give a non-finite acceleration or Jacobian at the start state{hint}: a mass "
        "or inertia too small (below about 1e-100 kg) or a parameter too large; check the model's values")


def warn_if_stiff(system, t0, t1, y, sample_rate):
    """Warn an explicit run whose steps the fastest time scale will hold far below the output interval."""
    import warnings

    from .analysis.stiffness import explicit_step, explicit_step_warning

    try:
        message = explicit_step_warning(system, t0, t1, y, sample_rate)
        step = explicit_step(system, t0, y)
    except (np.linalg.LinAlgError, ValueError):  # a non-finite Jacobian (a subnormal mass, say)
        raise_non_finite_start(system)
    if step is not None and (t1 - t0) / step > MAX_STEP_COUNT:  # hours to days: refused before the first step
        raise ParameterError(
            f"{system.name}: the fastest time scale at the start state limits an explicit method to steps of about "
            f"{step:.3g} s, so ({t0:g}, {t1:g}) s takes about {(t1 - t0) / step:.3g} steps, more than the "
            f"{MAX_STEP_COUNT:.0e} any run may take (hours of wall time). Check the model's values (a tiny mass, "
            "a huge stiffness), or use method='Radau' (implicit, analytic Jacobian)")
    if message:
        warnings.warn(message, RuntimeWarning, stacklevel=3)
