"""The figures of ``rotorkit run`` (and the files of ``rotorkit periodic``), drawn in a helper process that
imports matplotlib while the run simulates.

Importing matplotlib and drawing the first figure take about 0.5 s, as long
as a warm run's simulation. :class:`FigureProcess` is forked at the very
start of ``rotorkit run`` (before any thread exists): it imports matplotlib
and the plotting functions on the second core while this process loads the
model and simulates, then waits for the job. The result goes over a pipe
(only the signals the figures show, about 2 MB for a preset), the figures are
written into the run's staging folder, and the paths come back.

- An exception in the helper is raised again here, with the helper's
  traceback as a note; a helper that dies (killed, crashed) is an error
  naming its exit code. Either way the run fails as a figure error in the
  same process would.
- Ctrl-C reaches both processes (same process group); the helper exits
  quietly, this process stops it on its way out whatever ends the run, and
  a helper whose parent disappears sees the pipe close and exits.
- Without ``fork`` (Windows), with one core, with threads running (a
  caller that is not the command line), or with ``ROTORKIT_FIGURE_PROCESS=0``,
  no helper is started and the figures are drawn here, with the same
  functions; the same if the job cannot be pickled.
"""

import os
import sys

__all__ = ["write_figures", "figure_signals", "FigureProcess", "PROCESS_VARIABLE", "warm_up_figures",
           "warm_up_netcdf"]

#: environment variable: ``0`` draws the figures in the run's own process
PROCESS_VARIABLE = "ROTORKIT_FIGURE_PROCESS"


def write_figures(result, outputs, out, measurement=None):
    """Draw the figures a preset's ``OUTPUTS`` asks for (and its sensor records) into the folder ``out``.

    Returns
    -------
    list of pathlib.Path
        The files written, in a fixed order: orbit, bending, torsion, then the sensors' files.
    """
    from ..plotting.basic import plot_orbit, plot_signals
    from .common import save_figure

    written = []
    station = outputs.get("orbit_station")
    clearance = result.parameters.get(outputs.get("clearance_parameter", ""), None)
    if station is not None:
        ax = plot_orbit(result, station, clearance=clearance)
        written.append(save_figure(ax.figure, out / _figure_name(result, f"orbit_station{station}", f"x{station}")))
    for key, scale, unit in (("bending", 1e6, "µm"), ("torsion", 1e6, "µrad")):
        name = outputs.get(key)
        if name:
            ax = plot_signals(result, name, scale=scale, unit_label=unit)
            written.append(save_figure(ax.figure, out / _figure_name(result, name.replace('-', '_minus_'), name)))
    if measurement is not None:
        from ..plotting.sensors import write_sensor_outputs

        written += write_sensor_outputs(measurement, outputs, out, save_figure)
    return written


def _figure_name(result, stem, signal):
    """``<stem>.png``, built only from ``signal`` once it is known to be a signal of ``result`` (never a path)."""
    from ..errors import ParameterError
    from ..modelfile import check_signal

    check_signal(signal, tuple(result.state_names), "figure signal")
    if not stem.isidentifier():  # no separator, no dot: a name inside the folder
        raise ParameterError(f"figure name {stem!r}: built from signal {signal!r}, it must be an identifier")
    return f"{stem}.png"


def figure_signals(outputs):
    """Names of the states :func:`write_figures` reads for ``outputs`` (sensor records aside)."""
    names = []
    station = outputs.get("orbit_station")
    if station is not None:
        names += [f"x{station}", f"y{station}"]
    for key in ("bending", "torsion"):
        if outputs.get(key):
            names += [part.strip() for part in outputs[key].split("-")]
    return list(dict.fromkeys(names))


def _slim(result, outputs):
    """``result`` holding only the states the figures show (what is sent to the helper)."""
    from ..result import Result

    names = [n for n in figure_signals(outputs) if n in result.state_names]
    rows = [result.state_names.index(n) for n in names]
    return Result(t=result.t, y=result.y[rows], state_names=tuple(names), parameters=result.parameters,
                  stats=result.stats, name=result.name)


class FigureProcess:
    """A forked helper that imports matplotlib now and draws a run's figures later (see the module docstring).

    Use :meth:`start` (None when no helper can help), then :meth:`submit` the
    job once, :meth:`collect` its files, and :meth:`close` in any case (a
    context manager does it).
    """

    def __init__(self, process, connection):
        self._process, self._connection = process, connection
        self._answered = False

    @classmethod
    def start(cls, warm_ups=None):
        """Fork the helper, or return None: no ``fork``, one core, ``$ROTORKIT_FIGURE_PROCESS`` = 0, or other
        threads running here (forking them could copy a lock one of them holds; the command line has none).

        ``warm_ups``: what the helper runs while it waits for the job (default: the imports and a small figure
        of :func:`write_figures`'s kinds); an exception in one is raised once the job comes."""
        import multiprocessing
        import threading

        if os.environ.get(PROCESS_VARIABLE, "").strip() == "0" or threading.active_count() > 1:
            return None
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
        if cores < 2 or "fork" not in multiprocessing.get_all_start_methods():
            return None
        context = multiprocessing.get_context("fork")
        here, there = context.Pipe()
        for stream in (sys.stdout, sys.stderr):  # nothing buffered may be written twice
            stream.flush()
        process = context.Process(target=_serve, args=(there, here, warm_ups or (warm_up_figures,)),
                                  name="rotorkit-figures", daemon=True)
        process.start()
        there.close()
        return cls(process, here)

    def submit(self, result, outputs, out, measurement=None):
        """Send the job: draw into the folder ``out``. False (nothing sent: draw here) if it cannot be pickled or
        the helper is gone."""
        return self.call("write_figures", result if measurement is not None else _slim(result, outputs), outputs,
                         out, measurement)

    def call(self, function, *args):
        """Send the job ``function(*args)`` (a module-level function, or the name of one of this module, looked up
        in the helper); :meth:`collect` returns its value. False (nothing sent: run it here) if it cannot be
        pickled or the helper is gone."""
        import pickle

        try:
            self._connection.send((function, args))  # pickled whole before anything is written to the pipe
        except (pickle.PicklingError, TypeError, AttributeError, BrokenPipeError):  # e.g. a lambda in OUTPUTS
            return False
        return True

    def collect(self):
        """The job's value (the paths of the figures the helper wrote); its exception raised here if it failed."""
        try:
            status, value, trace = self._connection.recv()
        except (EOFError, OSError):
            self._process.join(timeout=5)
            raise RuntimeError(f"the figure process ended without drawing the figures (exit code "
                               f"{self._process.exitcode}); run again with {PROCESS_VARIABLE}=0 to draw them "
                               "in the run's own process") from None
        self._answered = True
        if status == "ok":
            return value
        value.add_note(f"raised in rotorkit's figure process:\n{trace}")
        raise value

    def close(self):
        """Stop the helper: it exits by itself once it has answered; else (the run failed or was interrupted
        before) it is terminated."""
        self._connection.close()
        if self._answered:
            self._process.join(timeout=5)
        if self._process.is_alive():
            self._process.terminate()
            self._process.join(timeout=5)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _serve(connection, parent_end, warm_ups):
    """The helper's life: import the plotting stack (``warm_ups``), wait for one job, run it, send back its value
    (the paths drawn) or the error."""
    parent_end.close()  # else the pipe would never report that the parent is gone
    try:
        failed = None
        for warm_up in warm_ups:
            try:
                warm_up()
            except Exception as exc:  # reported once the job comes, as drawing it here would
                failed = failed or exc
        function, args = connection.recv()
        try:
            if failed is not None:
                raise failed
            reply = ("ok", (globals()[function] if isinstance(function, str) else function)(*args), None)
        except Exception as exc:
            reply = ("error", _portable(exc), _traceback(exc))
        connection.send(reply)
    except (EOFError, KeyboardInterrupt, BrokenPipeError):  # the run ended or was interrupted: nothing to say
        pass


def warm_up_figures():
    """Import what drawing the figures imports, and draw a small figure of the same kinds once (fonts, text
    layout, colour bar, PNG encoder): in the helper, while the run simulates, so that the job finds all of it
    loaded. About 0.4 s of the helper's time, none of the run's."""
    import numpy as np
    from matplotlib.collections import LineCollection

    from ..plotting.basic import legend_beside, new_axes
    from .common import save_figure_bytes

    ax = new_axes()
    ax.plot([0.0, 1.0], [0.0, 1.0], lw=0.5, label="x")
    ax.axvspan(0.2, 0.4, color="0.9", zorder=0, label="span")
    lines = LineCollection([np.zeros((2, 2))], array=np.zeros(1))
    ax.add_collection(lines)
    ax.figure.colorbar(lines, ax=ax, label="t (s)")
    legend_beside(ax)
    ax.set(xlabel="x (µm)", ylabel="y (µrad)", title="warm-up")
    save_figure_bytes(ax.figure, dpi=10)


def warm_up_netcdf():
    """Import what writing a netCDF file with xarray imports (with dask installed, xarray imports dask.array and
    distributed then: about 1.5 s), by writing a small dataset into memory."""
    import numpy as np
    import xarray as xr

    try:  # in memory (scipy's netCDF 3 writer); the job's own writer reports its errors
        xr.Dataset({"a": ("x", np.zeros(2))}, attrs={"b": np.zeros(2)}).to_netcdf()
    except Exception:  # noqa: BLE001 - only a warm-up
        pass


def _portable(exc):
    """``exc`` if it survives pickling, else a RuntimeError with its type and text."""
    import pickle

    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        return RuntimeError(f"{type(exc).__name__}: {exc}")


def _traceback(exc):
    import traceback

    return "".join(traceback.format_exception(exc))
