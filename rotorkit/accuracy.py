"""The price of accuracy: methods, engines and tolerances against a tight reference.

Each run is measured by its wall time and by two errors against a
reference solution (DOP853 at ``rtol = 1e-12`` with restarts at the time
discontinuities):

``pointwise``
    ``max_t |s(t) - s_ref(t)| / max_t |s_ref(t)|`` over the whole run, for
    each signal (bending ``x2``, torsion ``alpha2-alpha5``);
``spectral``
    the largest difference of the amplitude spectra over the analysis
    window (2.2-3.8 s, after a 5 Hz zero-phase high-pass), relative to the
    reference spectrum's peak: the quantity the paper's conclusions rest on.

In rub, pointwise errors grow with time even for accurate solvers (the
trajectory is sensitive) while spectra converge; the study shows both.
"""

import time
from dataclasses import asdict, dataclass, field

import numpy as np

from .errors import ParameterError, SimulationError
from .simulate import COMPILED_METHODS, simulate
from .system import COMPILED_BACKENDS

__all__ = ["AccuracyRun", "study", "reference_run", "errors", "DEFAULT_TOLERANCES", "DEFAULT_CASES"]

DEFAULT_TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
#: (engine, method) pairs of the default study
DEFAULT_CASES = (("compiled", "DOP853"), ("compiled", "RK45"), ("scipy", "DOP853"), ("scipy", "RK45"),
                 ("scipy", "LSODA"), ("scipy", "Radau"), ("scipy", "BDF"))
#: atol = ATOL_PER_RTOL * rtol (displacements are ~1e-4 m: atol 1e-9 m at rtol 1e-6)
ATOL_PER_RTOL = 1e-3


@dataclass(frozen=True)
class AccuracyRun:
    """One point of the work-precision study."""

    engine: str
    method: str
    rtol: float
    atol: float
    wall_time: float
    nfev: int
    success: bool
    pointwise: dict = field(default_factory=dict)
    spectral: dict = field(default_factory=dict)
    message: str = ""


def errors(result, reference, signals, window, highpass_hz=5.0):
    """Pointwise and spectral relative errors of ``result`` against ``reference``.

    Returns
    -------
    (dict, dict)
        Signal name -> pointwise error, signal name -> spectral error.
    """
    if result.t.shape != reference.t.shape or np.abs(result.t - reference.t).max() > 1e-12:
        raise ParameterError("result and reference must have the same sample times")
    pointwise, spectral = {}, {}
    for name in signals:
        s, r = result[name], reference[name]
        pointwise[name] = float(np.abs(s - r).max() / np.abs(r).max())
        spec = result.spectrum(name, window, highpass_hz or None).amplitude
        spec_ref = reference.spectrum(name, window, highpass_hz or None).amplitude
        spectral[name] = float(np.abs(spec - spec_ref).max() / spec_ref.max())
    return pointwise, spectral


def reference_run(system, t_span, rtol=1e-12, sample_rate=10_000.0):
    """The tight reference: DOP853 at ``rtol`` (compiled engine when available)."""
    engine = "compiled" if system.backend in COMPILED_BACKENDS else "scipy"
    return simulate(system, t_span, method="DOP853", rtol=rtol, atol=rtol * ATOL_PER_RTOL, engine=engine,
                    sample_rate=sample_rate, check_convergence=False)  # it is the reference


def study(system, t_span, *, cases=DEFAULT_CASES, tolerances=DEFAULT_TOLERANCES, signals=("x2", "alpha2-alpha5"),
          window=(2.2, 3.8), reference=None, budget=60.0, sample_rate=10_000.0, report=None):
    """Run every (engine, method) at every tolerance and measure its errors.

    Parameters
    ----------
    system : rotorkit.System
    t_span : (float, float)
    cases : sequence of (engine, method)
        Engines ``"compiled"`` (RK45, DOP853; numba back end), ``"scipy"``,
        and ``"scipy+events"`` (scipy with contact event location and restarts).
    tolerances : sequence of float
        rtol values; ``atol = 1e-3 * rtol``.
    signals : sequence of str
        Signals to compare.
    window : (float, float)
        Spectral window (s).
    reference : Result, optional
        Default: :func:`reference_run`.
    budget : float
        Once a run of a case takes longer than this (s), its tighter
        tolerances are skipped (they would take longer still).
    report : callable, optional
        Called with each :class:`AccuracyRun` as it finishes.

    Returns
    -------
    (list of AccuracyRun, Result)
        The runs and the reference.
    """
    if reference is None:
        reference = reference_run(system, t_span, sample_rate=sample_rate)
    runs = []
    for engine, method in cases:
        if engine == "compiled" and (system.backend not in COMPILED_BACKENDS or method not in COMPILED_METHODS):
            continue
        for rtol in sorted(tolerances, reverse=True):
            atol = rtol * ATOL_PER_RTOL
            start = time.perf_counter()
            events = engine == "scipy+events"
            try:
                res = simulate(system, t_span, method=method, rtol=rtol, atol=atol,
                               engine="scipy" if events else engine, contact_events=events, sample_rate=sample_rate,
                               check_convergence=False)  # compared with the reference here
            except SimulationError as err:
                run = AccuracyRun(engine, method, rtol, atol, time.perf_counter() - start, 0, False,
                                  message=str(err).splitlines()[0])
            else:
                pointwise, spectral = errors(res, reference, signals, window)
                run = AccuracyRun(engine, method, rtol, atol, res.stats["wall_time"], res.stats["nfev"], True,
                                  pointwise, spectral)
            runs.append(run)
            if report is not None:
                report(run)
            if run.wall_time > budget:
                break
    return runs, reference


def to_rows(runs, signals):
    """Flat dict rows (for a table or CSV)."""
    rows = []
    for run in runs:
        row = {k: v for k, v in asdict(run).items() if k not in ("pointwise", "spectral")}
        for name in signals:
            row[f"pointwise_{name}"] = run.pointwise.get(name, float("nan"))
            row[f"spectral_{name}"] = run.spectral.get(name, float("nan"))
        rows.append(row)
    return rows
