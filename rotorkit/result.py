"""Simulation results: named signals, metadata, save/load, thin plot methods."""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import ParameterError

__all__ = ["Result", "load_result"]

FILE_FORMAT = "rotorkit-result-1"


@dataclass(frozen=True)
class Result:
    """Sampled states of a simulation.

    Attributes
    ----------
    t : numpy.ndarray
        Sample times (s), shape (n_samples,).
    y : numpy.ndarray
        States (SI: m, rad, m/s, rad/s), shape (n_states, n_samples).
    state_names : tuple of str
        Names of the rows of ``y`` (``x2``, ``alpha2``, ``x2_dot``, ...).
    parameters : dict
        Parameter name -> SI value used in the run.
    stats : dict
        Solver statistics: ``nfev``, ``method``, ``rtol``, ``atol``,
        ``wall_time``, ``segments``, ``backend``, ``engine``, ``success``, ``message``.
    name : str
        Model name.

    Signals are read by name: ``result["x2"]``; a difference of two states
    reads ``result["alpha2-alpha5"]``.
    """

    t: np.ndarray
    y: np.ndarray
    state_names: tuple
    parameters: dict = field(default_factory=dict)
    stats: dict = field(default_factory=dict)
    name: str = "model"

    def __post_init__(self):
        for arr in (self.t, self.y):
            arr.setflags(write=False)

    def __repr__(self):
        """One line a reader can take in: model, span, samples, signals (shortened), method and outcome."""
        names = self.state_names
        shown = ", ".join(names[:6]) + (f", ... ({len(names)} signals)" if len(names) > 6 else "")
        span = f"t = {self.t[0]:g} .. {self.t[-1]:g} s, " if self.t.size else ""
        stats = self.stats
        run = ", ".join(f"{k}={stats[k]}" for k in ("method", "backend", "message") if k in stats)
        return f"Result({self.name!r}: {span}{self.t.size} samples; {shown}{'; ' + run if run else ''})"

    def _repr_html_(self):
        """Jupyter display: span, samples, signals and run statistics."""
        from .display import result_html

        return result_html(self)

    def __getitem__(self, name):
        if not isinstance(name, str):
            from .errors import ArgumentTypeError

            raise ArgumentTypeError(
                f"result[{name!r}]: index a result by signal name, e.g. result['x2'] or result['alpha2-alpha5']; "
                "for samples use result.t and result.y (shape n_states x n_samples)"
            )
        if name in self.state_names:
            return self.y[self.state_names.index(name)]
        if "-" in name:
            a, b = (s.strip() for s in name.split("-", 1))
            return self[a] - self[b]
        raise ParameterError(
            f"result has no signal {name!r}; signals are {', '.join(self.state_names)} "
            "or a difference such as 'alpha2-alpha5'"
        )

    def __contains__(self, name):
        return name in self.state_names

    @property
    def sample_rate(self):
        """Samples per second (Hz)."""
        return (len(self.t) - 1) / (self.t[-1] - self.t[0]) if len(self.t) > 1 else float("nan")

    def window(self, start, end):
        """A copy holding only the samples with ``start <= t <= end``."""
        keep = (self.t >= start) & (self.t <= end)
        return Result(t=self.t[keep].copy(), y=self.y[:, keep].copy(), state_names=self.state_names,
                      parameters=self.parameters, stats=self.stats, name=self.name)

    def spectrum(self, name, window=None, highpass=None, units="rad/s"):
        """Amplitude spectrum of a signal over ``window`` (s), after an optional zero-phase high-pass (Hz).

        See :func:`rotorkit.signals.amplitude_spectrum`; returns a ``Spectrum``.
        """
        from .signals import amplitude_spectrum, highpass as high_pass

        x = self[name] if highpass is None else high_pass(self.t, self[name], highpass)
        return amplitude_spectrum(self.t, x, window=window, units=units)

    # -- plots (thin: see rotorkit.plotting) --------------------------------
    def plot_orbit(self, station, ax=None, **kwargs):
        """Axis orbit ``y<station>`` against ``x<station>``; returns the matplotlib Axes."""
        from .plotting.basic import plot_orbit

        return plot_orbit(self, station, ax=ax, **kwargs)

    def plot_signals(self, names, ax=None, **kwargs):
        """Time histories of the named signals; returns the matplotlib Axes."""
        from .plotting.basic import plot_signals

        return plot_signals(self, names, ax=ax, **kwargs)

    # -- files ------------------------------------------------------------
    def save(self, path):
        """Write a ``.npz`` file (atomically): arrays ``t``, ``y`` and JSON ``meta``.

        The format is documented in ``docs/results.md``; it holds no pickled
        objects and is read back with :func:`load_result`.
        """
        from .files import atomic_write_bytes

        meta = {"format": FILE_FORMAT, "name": self.name, "state_names": list(self.state_names),
                "parameters": self.parameters, "stats": _jsonable(self.stats)}
        import io
        import json

        buf = io.BytesIO()
        np.savez(buf, t=self.t, y=self.y, meta=np.array(json.dumps(meta)))
        path = Path(path)
        atomic_write_bytes(path, buf.getvalue())
        return path


def _jsonable(d):
    out = {}
    for k, v in d.items():
        if isinstance(v, (np.floating, np.integer)):
            v = v.item()
        elif isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, (list, tuple)):
            v = [x.item() if isinstance(x, (np.floating, np.integer)) else x for x in v]
        out[k] = v
    return out


#: largest result (all arrays, uncompressed) load_result reads without max_bytes
MAX_LOAD_BYTES = 8e9


def _declared_bytes(path, fh):
    """Bytes the arrays of an ``.npz`` declare (read from each .npy header, nothing decompressed beyond it)."""
    import zipfile

    total = 0
    with zipfile.ZipFile(fh) as archive:
        members = archive.infolist()
        if len(members) > 16:
            raise ParameterError(f"{path}: {len(members)} arrays; a rotorkit result holds t, y and meta")
        for info in members:
            with archive.open(info) as fh:
                major, _minor = np.lib.format.read_magic(fh)
                read_header = np.lib.format.read_array_header_1_0 if major == 1 else np.lib.format.read_array_header_2_0
                shape, _fortran, dtype = read_header(fh, max_header_size=10_000)
            if dtype.hasobject:
                raise ParameterError(f"{path}: {info.filename} holds Python objects; a result holds numbers only")
            total += int(np.prod(shape, dtype=object)) * dtype.itemsize
    return total


def load_result(path, *, max_bytes=None):
    """Read a file written by :meth:`Result.save` (parsed as data, never executed).

    The sizes the arrays declare are checked before anything is read: a
    small file that would expand to more than ``max_bytes`` (default: the
    smaller of 8 GB and half the free memory) is refused.

    Raises
    ------
    ParameterError
        The file is not a rotorkit result file (or is damaged).
    FileNotFoundError
        There is no such file.
    """
    from .files import LIMITS, check_path, open_data

    path = check_path(path, "result file")
    if not path.exists():
        raise FileNotFoundError(path)
    if max_bytes is None:
        from .memory import available_memory

        free = available_memory()
        max_bytes = min(MAX_LOAD_BYTES, 0.5 * free) if free else MAX_LOAD_BYTES
    # the kind and size of the file first (a FIFO, a device or a huge file is refused unread)
    fh = open_data(path, what="result file", max_bytes=min(LIMITS["result file"], max_bytes + 2**20))
    try:
        with fh:
            declared = _declared_bytes(path, fh)
            if declared > max_bytes:
                raise ParameterError(f"{path}: its arrays declare {declared / 1e9:.3g} GB, more than the "
                                     f"{max_bytes / 1e9:.3g} GB limit; pass load_result(..., max_bytes=...) if the "
                                     "file is yours and that memory is free")
            fh.seek(0)
            import json

            with np.load(fh, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                t, y = data["t"].copy(), data["y"].copy()
        if not isinstance(meta, dict) or meta.get("format") != FILE_FORMAT:
            raise ParameterError(f"{path}: not a rotorkit result file (format "
                                 f"{meta.get('format') if isinstance(meta, dict) else None!r})")
        names = tuple(meta["state_names"])
        if not all(isinstance(n, str) for n in names):
            raise ParameterError(f"{path}: its state names {list(names)[:5]!r} are not all text")
        if t.ndim != 1 or y.shape != (len(names), t.size):
            raise ParameterError(f"{path}: t {t.shape} and y {y.shape} do not fit {len(names)} state names")
        return Result(t=t, y=y, state_names=names, parameters=dict(meta["parameters"]), stats=dict(meta["stats"]),
                      name=str(meta["name"]))
    except ParameterError:
        raise
    except Exception as exc:  # damaged or foreign content of any kind
        raise ParameterError(f"{path}: not a readable rotorkit result file ({type(exc).__name__}: {exc})") from exc
