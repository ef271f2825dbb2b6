"""A 1-D slice of a sweep as a spectrum cascade (the paper's Figs. 13-15)."""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..errors import ParameterError

__all__ = ["Cascade", "load_cascade"]


@dataclass(frozen=True, eq=False)
class Cascade:
    """Spectra over a swept parameter (a spectrum cascade).

    Attributes
    ----------
    parameter : str
        The swept parameter (e.g. ``"rub_stiffness"``).
    values : numpy.ndarray, shape (n_values,)
        Its values (SI), in sweep order.
    frequency : numpy.ndarray, shape (n_freq,)
        Frequencies (rad/s); empty if no point succeeded.
    amplitude : mapping of str to numpy.ndarray
        Signal name (``"x2"``, ``"alpha2-alpha5"``) -> amplitudes, shape
        (n_values, n_freq), same unit as the signal (m, rad). Rows of points
        whose status is not ``"ok"`` are NaN.
    status : numpy.ndarray of str, shape (n_values,)
        ``"ok"``, ``"failed"``, ``"runaway"`` or ``"missing"`` per point.
    failure_time : numpy.ndarray, shape (n_values,)
        Time (s) a point failed or ran away; NaN otherwise.
    max_displacement : numpy.ndarray, shape (n_values,)
        Largest radial displacement of any station over the run (m); NaN for
        missing points.
    messages : tuple of str
        Per point: why it failed or ran away (empty when ``ok``).
    preset : str
        Preset name, or ``"module:function"`` of the build function.
    window : (float, float)
        Time window of the spectra (s).
    highpass_hz : float or None
        Cut-off (Hz) of the high-pass filter applied before the spectra.
    units : str
        Units of ``frequency`` (``"rad/s"``).
    extra : mapping
        ``t_end``, ``overrides`` and ``simulate_options`` of the sweep, and
        ``spectrum``: the taper and lengths of the spectra (used by
        :meth:`spectrum` for exact peak interpolation).

    Arrays are read-only.
    """

    parameter: str
    values: np.ndarray
    frequency: np.ndarray
    amplitude: Mapping
    status: np.ndarray
    failure_time: np.ndarray
    max_displacement: np.ndarray
    messages: tuple = ()
    preset: str = ""
    window: tuple = (0.0, 0.0)
    highpass_hz: float | None = None
    units: str = "rad/s"
    extra: Mapping = field(default_factory=dict, repr=False)

    def __post_init__(self):
        for arr in (self.values, self.frequency, self.status, self.failure_time, self.max_displacement,
                    *self.amplitude.values()):
            arr.setflags(write=False)
        object.__setattr__(self, "amplitude", MappingProxyType(dict(self.amplitude)))

    @property
    def signals(self):
        """Names of the signals (tuple of str)."""
        return tuple(self.amplitude)

    @property
    def ok(self):
        """Boolean mask (n_values,) of the points with a spectrum."""
        return self.status == "ok"

    def spectrum(self, signal, index):
        """The :class:`~rotorkit.signals.Spectrum` of one point (``index`` into ``values``)."""
        from ..signals import Spectrum

        rows = self._rows(signal)
        if self.status[index] != "ok":
            raise ParameterError(
                f"point {index} ({self.parameter} = {self.values[index]:g}) has status "
                f"{str(self.status[index])!r} and no spectrum: {self.messages[index]}"
            )
        info = self.extra.get("spectrum") or {}
        return Spectrum(self.frequency, rows[index], self.units, info.get("taper"), info.get("n_samples"),
                        info.get("n_fft"))

    def _rows(self, signal):
        try:
            return self.amplitude[signal]
        except KeyError:
            raise ParameterError(
                f"the cascade has no signal {signal!r}; signals are {', '.join(self.amplitude)}"
            ) from None

    def plot(self, signal, ax=None, **kwargs):
        """Spectra of ``signal`` stacked along the parameter; see :func:`rotorkit.plotting.spectra.plot_cascade`."""
        from ..plotting.spectra import plot_cascade

        return plot_cascade(self, signal, ax=ax, **kwargs)


    @classmethod
    def from_dataset(cls, ds):
        """The cascade of a sweep Dataset with one swept parameter (select the others first: ``ds.sel(lp_speed=1500)``)."""
        names = [n for n in ds.attrs.get("parameters", []) if n in ds.coords]
        dims = [d for d in ds.status.dims]
        if len(dims) != 1:
            raise ParameterError(f"the sweep has the dimensions {dims}; select all but one parameter first, "
                                 "e.g. ds.sel(lp_speed=1500.0)")
        dim = dims[0]
        if dim == "point":
            varying = [n for n in names if ds[n].ndim == 1 and np.unique(ds[n].values).size > 1]
            if len(varying) != 1:
                raise ParameterError(f"a cascade needs one parameter varying along the points; {varying} vary")
            parameter = varying[0]
        else:
            parameter = dim
        values = np.asarray(ds[parameter].values, dtype=float)
        manifest = json.loads(ds.attrs["manifest"])
        s = manifest["settings"]
        spectrum = json.loads(ds.attrs.get("spectrum", "null"))
        amplitude = {str(sig): np.asarray(ds.amplitude.sel(signal=sig).values, dtype=float)
                     for sig in ds.signal.values}
        return cls(parameter=parameter, values=values, frequency=np.asarray(ds.frequency.values, dtype=float),
                   amplitude=amplitude, status=np.asarray(ds.status.values).astype("<U8"),
                   failure_time=np.asarray(ds.failure_time.values, dtype=float),
                   max_displacement=np.asarray(ds.max_displacement.values, dtype=float),
                   messages=tuple(str(m) for m in ds.message.values), preset=manifest["scene_name"],
                   window=tuple(s["window"]), highpass_hz=s["highpass_hz"],
                   extra={"t_end": s["t_end"], "overrides": manifest["scene"].get("overrides"),
                          "simulate_options": s["simulate_options"], "spectrum": spectrum})


def load_cascade(out_dir, **selection):
    """:meth:`Cascade.from_dataset` of :func:`~rotorkit.sweep.load_sweep` (``selection``: ``ds.sel`` of the others)."""
    from .storage import load_sweep

    ds = load_sweep(out_dir)
    return Cascade.from_dataset(ds.sel(**selection) if selection else ds)
