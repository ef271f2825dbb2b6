"""run_sweep: check everything, then stream the points through an executor and store each as it ends."""

from __future__ import annotations

import json
import math
import numbers
from collections.abc import Mapping

from ..errors import ArgumentTypeError, ParameterError, RotorkitError, SimulationError
from . import storage
from .executors import LocalPool, Progress, as_executor, check_executor, check_start_method, connect, run_tasks
from .point import parse_order, rotor_speeds, run_point
from .scene import as_scene
from .space import MAX_POINTS, as_space

__all__ = ["run_sweep"]

# keyword arguments of rotorkit.simulate a sweep may pass on (plus "backend" for compiling, "reduce" for
# rotorkit.reduce)
_SIMULATE_KEYS = ("method", "rtol", "atol", "sample_rate", "max_step", "engine", "time_limit")


def _positive(value, name, expected):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise ParameterError(f"{name}={value!r}: expected {expected}")
    return float(value)


def _check_window(window):
    try:
        start, end = (float(v) for v in window)
    except (TypeError, ValueError):
        raise ParameterError(f"window={window!r}: expected (t_start, t_end) in s") from None
    if not (math.isfinite(start) and math.isfinite(end) and 0.0 <= start < end):
        raise ParameterError(f"window={window!r}: expected 0 <= t_start < t_end (s)")
    return [start, end]


def _check_simulate_options(options, window):
    if options is None:
        options = {}
    if not isinstance(options, Mapping):
        raise ArgumentTypeError(f"simulate_options={options!r}: expected a dict of rotorkit.simulate keyword arguments")
    unknown = sorted(set(options) - set(_SIMULATE_KEYS) - {"backend", "reduce"})
    if unknown:
        raise ArgumentTypeError(f"simulate_options has unknown keys {unknown}; allowed: {', '.join(_SIMULATE_KEYS)}, backend "
                        "and reduce")
    sample_rate = options.get("sample_rate", 10_000.0)
    if isinstance(sample_rate, numbers.Real) and (window[1] - window[0]) * sample_rate < 16:
        raise ParameterError(f"window={tuple(window)} holds fewer than 16 samples at sample_rate={sample_rate:g} Hz; "
                             "widen the window or raise the sample rate")
    options = dict(options)
    backend = options.pop("backend", "auto")
    reduction = _check_reduce(options.pop("reduce", None))
    return json.loads(json.dumps(options, default=storage.json_default)), backend, reduction


def _check_reduce(value):
    """``simulate_options["reduce"]``: None, a number of modes, or ``{"modes": m, "keep": [...]}`` (rotorkit.reduce)."""
    if value is None:
        return None
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        value = {"modes": int(value)}
    if not isinstance(value, Mapping) or "modes" not in value or set(value) - {"modes", "keep"}:
        raise ParameterError(f"simulate_options['reduce']={value!r}: expected a number of modes or "
                             "{'modes': m, 'keep': [coordinate names or stations]} (see rotorkit.reduce)")
    out = {"modes": value["modes"]}
    if value.get("keep") is not None:
        keep = value["keep"]
        out["keep"] = [keep] if isinstance(keep, (str, numbers.Integral)) else list(keep)
    return json.loads(json.dumps(out))


def _signal_parts(signal):
    return [s.strip() for s in signal.split("-", 1)] if "-" in signal else [signal]


def _check_signals(signals, default, model, who, what="signals"):
    states = set(model.coordinate_names) | {f"{c}_dot" for c in model.coordinate_names}
    if signals is None:
        if not default:
            raise ParameterError(f"{who} names no default output signals; pass {what}=['x1', ...]")
        usable = [s for s in default if all(p in states for p in _signal_parts(s))]
        if not usable:
            raise ParameterError(f"none of the default signals {default} is a state of the model; pass {what}=")
        return usable
    if isinstance(signals, str):
        signals = [signals]
    signals = list(signals)
    if len(set(signals)) != len(signals) or (what == "signals" and not signals):
        raise ParameterError(f"{what}={signals!r}: expected distinct signal names such as 'x2' or 'alpha2-alpha5'")
    for s in signals:
        if not isinstance(s, str) or not all(p in states for p in _signal_parts(s)):
            raise ParameterError(f"signal {s!r} is not a state of the model (or a difference 'a-b' of two): "
                                 f"states are {', '.join(sorted(states))}")
    return signals


def _check_names(scene, space):
    known = scene.parameter_names()
    for name in space.names:
        if name in scene.overrides:
            raise ParameterError(f"{name!r} is both swept and in overrides; remove it from overrides")
        if known is not None and name not in known:
            import difflib

            near = difflib.get_close_matches(name, sorted(known), n=3)
            raise ParameterError(f"{name!r} is not a parameter of {scene.display}"
                                 + (f"; did you mean {', '.join(near)}?" if near else
                                    f" (parameters: {', '.join(sorted(known))})"))


def _warm_up(model, backend, options, reduction=None):
    """Derive, generate and JIT-compile a structure once here, so local workers load it from the disk caches."""
    from ..simulate import simulate

    system = model.compile(backend=backend)
    if reduction:
        from ..reduction import reduce

        system = reduce(system, **reduction)  # bad modes or keep fail here, before any point runs
    try:
        simulate(system, (0.0, 1e-4), **{**options, "sample_rate": 1e5}, check_convergence=False)
    except SimulationError:
        pass


def run_sweep(scene, space, values=None, *, out_dir, overrides=None, t_end=None, window=(2.2, 3.8),
              highpass_hz=5.0, signals=None, orders=(), poincare=None, poincare_revolutions=64, poincare_rotor=None,
              energy=False, workers=2, executor=None, scheduler=None, progress=None, simulate_options=None,
              runaway_limit=None, start_method="spawn", max_points=MAX_POINTS, dataset=True):
    """Simulate a model at every point of a parameter space; store each point as it finishes.

    Parameters
    ----------
    scene : str, callable, rotorkit.Model or Scene
        What a worker rebuilds the model from: a preset name (``"al31f"``),
        a module-level function ``build(**parameters) -> Model``, or a Model
        built from elements (its parameters, e.g. ``rub1_contact_stiffness``,
        are set per point). See :mod:`rotorkit.sweep.scene`.
    space : str, dict, Grid or PointList
        The points: a parameter name with its ``values`` (1-D), a dict
        ``{name: values}`` (a grid, first name slowest), a
        :class:`~rotorkit.sweep.Grid`, a :class:`~rotorkit.sweep.PointList`
        or :func:`~rotorkit.sweep.latin_hypercube`.
    values : sequence of float, optional
        The values of a single parameter ``space`` (SI).
    out_dir : str or pathlib.Path
        Folder of the manifest, the point files and ``sweep.nc``.
    overrides : dict, optional
        Parameters fixed for every point (numbers, bools or pint quantities).
    t_end : float, optional
        Simulated time 0..t_end (s); default the scene's ``OUTPUTS["t_end"]``,
        else the window's end.
    window : (float, float)
        Time window (s) of the spectra, the order amplitudes and the Poincare samples.
    highpass_hz : float or None
        Zero-phase high-pass (Hz) before the spectra; None for none.
    signals : sequence of str, optional
        Signals whose spectra and order amplitudes are stored (``"x2"``,
        ``"alpha2-alpha5"``); default the scene's ``bending`` and ``torsion`` outputs.
    orders : sequence of str
        Speed orders whose peak amplitude is stored: ``"1/2"``, ``"1"``,
        ``"3/2"`` (of the first rotor), ``"HP - LP"``, ``"1/2 LP"``. The peak
        is the largest spectrum amplitude within +-max(2 bins, 1 %) of the
        order's frequency.
    poincare : sequence of str, optional
        Signals sampled once per revolution (default: ``signals``).
    poincare_revolutions : int
        Samples per signal: the last revolutions of the window.
    poincare_rotor : str, optional
        The rotor whose revolutions are counted (default the first).
    energy : bool
        Store the relative energy-balance residual of each point
        (:func:`rotorkit.analysis.energy.energy_balance`; costs a symbolic
        set-up per structure and worker, then an evaluation per point).
    workers : int
        Local worker processes (1: this process, one point after another).
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Run the points there instead of local processes.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``) to connect to.
    progress : callable, optional
        Called with a :class:`~rotorkit.sweep.ProgressEvent` per point
        (done/total, failures, ETA).
    simulate_options : dict, optional
        Keyword arguments of :func:`rotorkit.simulate` (``method``, ``rtol``,
        ``atol``, ``sample_rate``, ``max_step``, ``engine``, ``time_limit``),
        ``backend``, and ``reduce``: a number of modes or ``{"modes": m,
        "keep": [...]}`` to run every point on :func:`rotorkit.reduce` of its
        system (results expanded to physical coordinates).
    runaway_limit : float, optional
        Displacement (m) past which a point counts as run away (default 10
        times the smallest rub clearance; ``math.inf`` disables the check).
    start_method : {"spawn", "forkserver", "fork"}
        How local worker processes start.
    max_points : int
        Refuse a space with more points (default 100,000).
    dataset : bool
        Write ``sweep.nc`` (netCDF-4) when the sweep ends.

    Returns
    -------
    xarray.Dataset
        :func:`load_sweep` of ``out_dir``.

    Raises
    ------
    ParameterError
        Bad arguments (checked on the first point's model before anything
        runs), or ``out_dir`` holding a different sweep.
    RotorkitError
        A point raised something other than a simulation failure or bad
        parameter values (a bug); finished points are kept for a resume.
        Also: an unreachable Dask scheduler, or workers of another version.

    Notes
    -----
    No model is built up front but the first point's. A point whose
    integration fails, runs away or whose parameters are refused is stored
    with its status and reason; a point whose worker process dies is
    retried (3 tries in all). Rerunning with the same arguments resumes: the
    points stored are not recomputed. With the ``spawn`` start method a
    script must guard its entry point with ``if __name__ == "__main__":``.
    """
    from ..files import check_output_folder

    out_dir = check_output_folder(out_dir, "out_dir", ours=False)  # a file, a device, '' or None: refused first
    scene = as_scene(scene, overrides)
    space = as_space(space, values, max_points)
    _check_names(scene, space)
    window = _check_window(window)
    outputs = scene.outputs
    t_end = _positive(outputs.get("t_end", window[1]) if t_end is None else t_end, "t_end", "a duration > 0 (s)")
    if window[1] > t_end:
        raise ParameterError(f"window={tuple(window)} ends after t_end={t_end:g} s; the window must lie in [0, t_end]")
    if highpass_hz is not None:
        highpass_hz = _positive(highpass_hz, "highpass_hz", "a cut-off > 0 (Hz) or None")
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
        raise ParameterError(f"workers={workers!r}: expected an integer >= 1")
    if progress is not None and not callable(progress):
        raise ArgumentTypeError(f"progress={progress!r}: expected a callable progress(event)")
    if isinstance(poincare_revolutions, bool) or not isinstance(poincare_revolutions, numbers.Integral) \
            or not 1 <= poincare_revolutions <= 100_000:
        raise ParameterError(f"poincare_revolutions={poincare_revolutions!r}: expected an integer in 1..100000")
    options, backend, reduction = _check_simulate_options(simulate_options, window)
    if runaway_limit is not None:
        runaway_limit = _positive(runaway_limit, "runaway_limit", "a displacement > 0 (m) or None")
    if executor is not None and scheduler is not None:
        raise ParameterError("give executor= or scheduler=, not both")
    remote = executor is not None or scheduler is not None
    if executor is not None:
        check_executor(executor)
    elif scheduler is None:
        check_start_method(start_method, workers if space.size > 1 else 1)
    if (remote or workers > 1) and scene.kind == "function" and not scene.target["importable"]:
        raise ArgumentTypeError(f"scene={scene.display}: worker processes cannot import a lambda or a nested function; "
                        "define the build function at module level, or use workers=1")

    first = space.point(0)
    try:
        model = scene.build(first)
    except ParameterError as err:
        where = ", ".join(f"{k} = {v:g}" for k, v in first.items())
        raise type(err)(f"sweep point {where}: {err}") from err
    default_signals = [outputs[k] for k in ("bending", "torsion") if outputs.get(k)]
    if not default_signals and scene.kind == "model" and model.stations:
        default_signals = [f"x{model.stations[0]}"]  # a model without run settings: bending of its first station
    signals = _check_signals(signals, default_signals, model, f"scene {scene.display!r}")
    poincare = signals if poincare is None else _check_signals(poincare, [], model, scene.display, "poincare")
    if isinstance(orders, str):
        orders = [orders]
    orders = list(orders)
    if len(set(orders)) != len(orders):
        raise ParameterError(f"orders={orders!r}: an order appears twice")
    speeds = rotor_speeds(model)
    for o in orders:
        parse_order(o, list(speeds))
    if poincare_rotor is not None and poincare_rotor not in speeds:
        raise ParameterError(f"poincare_rotor={poincare_rotor!r}: rotors are {', '.join(speeds) or 'none'}")

    settings = {"t_end": t_end, "window": window, "highpass_hz": highpass_hz, "signals": signals, "orders": orders,
                "poincare_signals": poincare, "poincare_revolutions": int(poincare_revolutions),
                "poincare_rotor": poincare_rotor, "energy": bool(energy), "simulate_options": options,
                "backend": backend, "runaway_limit": runaway_limit}
    if reduction:  # only then: the settings (and the fingerprint of sweeps on disk) stay as they were without it
        settings["reduce"] = reduction
    manifest = json.loads(json.dumps({
        "format": storage.MANIFEST_FORMAT, "scene": scene.describe(), "scene_name": scene.display,
        "space": space.describe(), "settings": settings,
        "parameter_units": {n: scene.parameter_units().get(n, "") for n in space.names},
    }, default=storage.json_default))
    has_manifest = storage.check_manifest(out_dir, manifest)
    fp = storage.fingerprint(manifest)
    shapes = storage.shapes_of(manifest)
    settings = manifest["settings"]

    client = connect(scheduler) if scheduler is not None else None
    try:
        _warm_up(model, backend, options, settings.get("reduce"))
        if not has_manifest:
            storage.write_manifest(out_dir, manifest)
        counter = Progress(space.size, progress)
        written = set()

        def tasks():
            for i in range(space.size):
                point = space.point(i)
                if storage.read_point(out_dir, i, fp, point, shapes) is not None:
                    written.add(i)
                    counter(i, point, "cached")
                    continue
                yield {"scene": scene, "index": i, "point": point, "settings": settings}

        def store(result):
            i = result["index"]
            if i in written:  # a duplicate (a retried point whose first run finished after all): stored once
                return
            storage.write_point(out_dir, fp, result)
            written.add(i)
            counter(i, result["meta"]["point"], result["meta"]["status"])

        def describe(task):
            return ", ".join(f"{k} = {v:g}" for k, v in task["point"].items())

        if client is not None or executor is not None:
            pool, n = as_executor(client if client is not None else executor)
            run_tasks(tasks(), pool, n, run_point, store, describe)
        elif workers == 1 or space.size == 1:
            for task in tasks():
                try:
                    result = run_point(task)
                except Exception as exc:
                    raise RotorkitError(
                        f"sweep point {task['index']} ({describe(task)}) raised {type(exc).__name__}: {exc}; "
                        "the finished points are kept, run the sweep again to resume") from exc
                store(result)
        else:
            pool = LocalPool(min(workers, space.size), start_method)
            try:
                run_tasks(tasks(), pool, pool.workers, run_point, store, describe)
            finally:
                pool.shutdown(wait=True, cancel_futures=True)
    finally:
        if client is not None:
            client.close()
    ds = storage.load_sweep(out_dir)
    if dataset:
        storage.write_dataset(out_dir, ds)
    return ds
