"""Frequency response functions at a rotor speed: receptance, mobility, accelerance.

The receptance ``H(w)`` from a force on coordinate ``j`` to the motion of
coordinate ``i`` is entry ``(i, j)`` of ``(K + W H - w^2 M + i w (C + W G))^-1``
at the swept speed ``W``; mobility is ``i w H`` and accelerance ``-w^2 H``.
A force ``Re(F e^{i w t})`` gives the motion ``Re(H F e^{i w t})``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["FRF", "frequency_response"]

KINDS = {"receptance": ("m/N", 0), "mobility": ("m/(N s)", 1), "accelerance": ("m/(N s^2)", 2)}


@dataclass(frozen=True, eq=False)
class FRF:
    """Frequency response functions between force inputs and response outputs.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (m,)
        Excitation frequency (rad/s).
    values : numpy.ndarray of complex, shape (m, n_out, n_in)
        ``H`` of :attr:`kind` (m/N, or rad/(N m) for angles; mobility per s,
        accelerance per s^2).
    outputs, inputs : tuple of str
        Coordinate names of the rows and columns.
    kind : {"receptance", "mobility", "accelerance"}
    speed : float
        Swept speed (rad/s).
    """

    frequencies: np.ndarray
    values: np.ndarray
    outputs: tuple
    inputs: tuple
    kind: str
    speed: float

    @property
    def units(self):
        return KINDS[self.kind][0]

    def __call__(self, output, input):
        """``H`` from ``input`` to ``output`` (coordinate names), shape (m,)."""
        try:
            i, j = self.outputs.index(str(output)), self.inputs.index(str(input))
        except ValueError:
            raise ParameterError(f"({output!r}, {input!r}) is not an FRF pair: outputs {self.outputs}, "
                                 f"inputs {self.inputs}") from None
        return self.values[:, i, j]

    def as_kind(self, kind):
        """The same FRF as receptance, mobility or accelerance."""
        if kind not in KINDS:
            raise ParameterError(f"kind={kind!r} is unknown: expected one of {list(KINDS)}")
        power = KINDS[kind][1] - KINDS[self.kind][1]
        factor = (1j * self.frequencies) ** power
        return FRF(frequencies=self.frequencies, values=self.values * factor[:, None, None], outputs=self.outputs,
                   inputs=self.inputs, kind=kind, speed=self.speed)

    def to_xarray(self):
        """The FRFs as an :class:`xarray.DataArray` over (frequency, output, input), complex."""
        import xarray as xr

        return xr.DataArray(self.values, dims=("frequency", "output", "input"), name=self.kind,
                            coords={"frequency": ("frequency", self.frequencies, {"units": "rad/s"}),
                                    "output": list(self.outputs), "input": list(self.inputs)},
                            attrs={"units": self.units, "speed": self.speed})

    def plot(self, output, input, axes=None, **kwargs):
        """Magnitude and phase (:func:`rotorkit.plotting.response.plot_frf`); returns the two Axes."""
        from ..plotting.response import plot_frf

        return plot_frf(self, output, input, axes=axes, **kwargs)


def frequency_response(model, frequencies, *, inputs=None, outputs=None, speed=0.0, kind="receptance",
                       method="auto"):
    """FRFs of a :class:`~rotorkit.analysis.linear_model.LinearModel` at one speed.

    Parameters
    ----------
    model : LinearModel
    frequencies : array_like, pint.Quantity or sequence of str, shape (m,)
        Excitation frequencies: rad/s as plain numbers, or with a unit
        (``Q_(f, "rpm")``; a cyclic frequency in Hz as ``"turn/s"``, see
        :func:`rotorkit.units.to_si`).
    inputs, outputs : sequence of str, optional
        Coordinate names where forces act and responses are read (default all).
    speed : float, str or pint.Quantity
        Swept speed (rad/s) at which ``G`` and ``H`` are taken.
    kind : {"receptance", "mobility", "accelerance"}
    method : {"auto", "banded", "dense"}
        See :mod:`rotorkit.analysis.harmonic`.

    Returns
    -------
    FRF

    Examples
    --------
    >>> import numpy as np
    >>> from rotorkit.analysis.linear_model import LinearModel
    >>> model = LinearModel(mass=[[2.0]], damping=[[0.0]], stiffness=[[2e4]], coordinate_names=("x1",))
    >>> frequency_response(model, [0.0, 50.0]).values[:, 0, 0].real.round(8).tolist()   # 1 / (k - m w^2)
    [5e-05, 6.667e-05]
    """
    from ..units import to_si, to_si_array
    from .harmonic import solve_harmonic

    if kind not in KINDS:
        raise ParameterError(f"kind={kind!r} is unknown: expected one of {list(KINDS)}")
    w = to_si_array(frequencies, "rad/s", "frequencies").reshape(-1)
    if w.size == 0 or not np.all(np.isfinite(w)):
        raise ParameterError("frequencies is empty or not finite: expected finite frequencies (rad/s)")
    speed = to_si(speed, "rad/s", "speed")
    inputs = model.coordinate_names if inputs is None else tuple(str(s) for s in inputs)
    outputs = model.coordinate_names if outputs is None else tuple(str(s) for s in outputs)
    cols = [model.coordinate_index(s) for s in inputs]
    rows = [model.coordinate_index(s) for s in outputs]
    F = np.zeros((model.n, len(cols)), dtype=complex)
    F[cols, np.arange(len(cols))] = 1.0
    Q = solve_harmonic(model, np.full(w.size, speed), w, F, method=method)[:, rows, :]
    Q = Q * ((1j * w) ** KINDS[kind][1])[:, None, None]
    Q.setflags(write=False)
    w.setflags(write=False)
    return FRF(frequencies=w, values=Q, outputs=outputs, inputs=inputs, kind=kind, speed=speed)
