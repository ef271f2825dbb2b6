"""Steady unbalance response in the frequency domain: amplitude, phase, whirl, orbit ellipse.

An unbalance ``U = m e`` (kg m) at a station, at angle ``phi`` on a rotor
spinning at ``w`` (x towards y), loads the station with::

    Fx = U w^2 cos(w t + phi),   Fy = U w^2 sin(w t + phi)

i.e. complex amplitudes ``Fx = U w^2 e^{i phi}``, ``Fy = -i U w^2 e^{i phi}``
(``f(t) = Re(F e^{i w t})``). Each rotor's unbalances excite at that rotor's
own spin speed (dual rotors: two frequencies at every swept speed), so the
response is kept per rotor. The steady response of every coordinate solves
``(K + W H - w^2 M + i w (C + W G)) Q = F`` at each swept speed ``W`` (see
:mod:`rotorkit.analysis.harmonic`: direct banded or batched solve).

A coordinate then moves as ``|Q| cos(w t + arg Q)``: :meth:`UnbalanceResponse.phase`
is ``arg Q`` and the phase lag behind the unbalance is ``phi - arg Q``
(90 degrees at a Jeffcott rotor's resonance).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["Unbalance", "UnbalanceResponse", "unbalance_response"]


@dataclass(frozen=True, slots=True)
class Unbalance:
    """An unbalance ``magnitude`` (kg m) at ``station``, at ``angle`` (rad) from x at t = 0.

    Both accept SI floats, pint quantities or strings: ``Unbalance(station=2,
    magnitude="100 g*mm", angle="90 deg")`` (stored in kg m and rad).
    """

    station: object
    magnitude: float
    angle: float = 0.0

    def __post_init__(self):
        from ..units import to_si

        magnitude = to_si(self.magnitude, "kg*m", "Unbalance magnitude")
        if magnitude < 0:
            raise ParameterError(f"Unbalance magnitude={self.magnitude!r} is invalid: expected >= 0 (kg m)")
        object.__setattr__(self, "magnitude", magnitude)
        object.__setattr__(self, "angle", to_si(self.angle, "rad", "Unbalance angle"))


@dataclass(frozen=True, eq=False)
class UnbalanceResponse:
    """Complex steady amplitudes of every coordinate against the swept speed.

    Attributes
    ----------
    speeds : numpy.ndarray, shape (n_speeds,)
        Swept speed (rad/s).
    coordinate_names : tuple of str
    components : dict of str to numpy.ndarray of complex, shape (n_speeds, n)
        Rotor -> amplitudes (m, rad) of the response at that rotor's spin.
    frequencies : dict of str to numpy.ndarray, shape (n_speeds,)
        Rotor -> excitation frequency (rad/s): its spin speed.
    speed_parameter : str
    unbalances : tuple of Unbalance
    method : str
        ``"banded"`` or ``"dense"``: how the harmonic systems were solved.
    """

    speeds: np.ndarray
    coordinate_names: tuple
    components: dict
    frequencies: dict
    speed_parameter: str
    unbalances: tuple
    method: str

    def _rotor(self, rotor):
        if rotor is None:
            if len(self.components) == 1:
                return next(iter(self.components))
            raise ParameterError(f"rotor=None is ambiguous: the unbalances excite {list(self.components)}; "
                                 "pick one (each spool responds at its own speed)")
        if rotor not in self.components:
            raise ParameterError(f"rotor={rotor!r} has no unbalance response: expected one of {list(self.components)}")
        return rotor

    def response(self, coordinate, rotor=None):
        """Complex amplitude (m, rad) of ``coordinate`` (e.g. ``"x2"``), shape (n_speeds,)."""
        rotor = self._rotor(rotor)
        try:
            i = self.coordinate_names.index(str(coordinate))
        except ValueError:
            raise ParameterError(f"coordinate={coordinate!r} is unknown: expected one of "
                                 f"{', '.join(self.coordinate_names)}") from None
        return self.components[rotor][:, i]

    def amplitude(self, coordinate, rotor=None):
        """``|Q|`` (m, rad) of ``coordinate``, shape (n_speeds,)."""
        return np.abs(self.response(coordinate, rotor))

    def phase(self, coordinate, rotor=None):
        """``arg Q`` (rad): the coordinate moves as ``|Q| cos(w t + arg Q)``."""
        return np.angle(self.response(coordinate, rotor))

    def orbit(self, station, rotor=None):
        """:class:`~rotorkit.analysis.whirl.Orbit` of ``station`` at each speed: forward/backward radii,
        semi-axes (m) and inclination (rad) of the ellipse."""
        from .whirl import orbit

        return orbit(self.response(f"x{station}", rotor), self.response(f"y{station}", rotor))

    def _station_or_path(self, value):
        """``(station, path)`` from to_csv's first argument: a station of the model (the old call), else a path."""
        import os

        if value is None:
            return None, None
        if isinstance(value, bool):
            raise ParameterError(f"path={value!r} is invalid: expected a file path or None")
        if isinstance(value, int) or (isinstance(value, str) and f"x{value}" in self.coordinate_names
                                      and not value.lower().endswith(".csv")):
            return value, None
        if isinstance(value, (str, os.PathLike)):
            return None, value
        raise ParameterError(f"path={value!r} is invalid: expected a file path (str or pathlib.Path) or None")

    def _csv_rows(self, station, rotor, fs, fl):
        o = self.orbit(station, rotor)
        x, y = self.response(f"x{station}", rotor), self.response(f"y{station}", rotor)
        for i, w in enumerate(self.speeds):
            yield (w * fs, self.frequencies[rotor][i] * fs, abs(x[i]) * fl, np.degrees(np.angle(x[i])),
                   abs(y[i]) * fl, np.degrees(np.angle(y[i])), o.forward[i] * fl, o.backward[i] * fl,
                   o.major[i] * fl, o.minor[i] * fl, np.degrees(o.inclination[i]))

    def to_csv(self, path=None, rotor=None, *, station=None, units="rad/s", length_units="m"):
        """CSV: speed, x and y amplitude and phase (deg), forward/backward radii, ellipse axes and inclination.

        ``path`` (None: the text; a station given here, as in ``to_csv(2)``,
        is read as ``station=2``), ``units`` and ``length_units`` as for every
        linear result (:func:`~rotorkit.analysis.tables.csv_output`).

        Parameters
        ----------
        rotor : str, optional
            Whose response (needed when several spools carry unbalance and a
            station is given).
        station : str or int, optional
            One station's table; None: every station of every excited rotor,
            with ``rotor`` and ``station`` columns first.
        """
        from ..units import display_factor
        from .modal_result import unit_slug
        from .tables import csv_output

        given, path = self._station_or_path(path)
        station = given if station is None else station
        fs, fl = display_factor(units, "speed"), display_factor(length_units, "length")
        u, lu = unit_slug(units), unit_slug(length_units)
        head = (f"{self.speed_parameter}_{u},frequency_{u},x_amplitude_{lu},x_phase_deg,y_amplitude_{lu},"
                f"y_phase_deg,forward_{lu},backward_{lu},major_{lu},minor_{lu},inclination_deg")
        if station is not None:
            rotor = self._rotor(rotor)
            rows = [head] + [",".join(f"{v:.10g}" for v in row) for row in self._csv_rows(station, rotor, fs, fl)]
        else:
            from .stations import station_pairs

            rows = ["rotor,station," + head]
            rotors = [self._rotor(rotor)] if rotor is not None else list(self.components)
            for r in rotors:
                for s, _, _ in station_pairs(self.coordinate_names):
                    rows += [f"{r},{s}," + ",".join(f"{v:.10g}" for v in row)
                             for row in self._csv_rows(s, r, fs, fl)]
        return csv_output("\n".join(rows) + "\n", path)

    def to_xarray(self):
        """Amplitudes (m, rad) and phases (rad) as an :class:`xarray.Dataset` over (speed, coordinate), per rotor."""
        import xarray as xr

        data = {}
        for rotor, Q in self.components.items():
            data[f"{rotor}_amplitude"] = (("speed", "coordinate"), np.abs(Q),
                                          {"units": "m or rad", "long_name": f"amplitude at the spin of {rotor}"})
            data[f"{rotor}_phase"] = (("speed", "coordinate"), np.angle(Q),
                                      {"units": "rad", "long_name": f"phase at the spin of {rotor}"})
            data[f"{rotor}_frequency"] = ("speed", self.frequencies[rotor],
                                          {"units": "rad/s", "long_name": f"spin speed of {rotor}"})
        coords = {"speed": ("speed", self.speeds, {"units": "rad/s", "long_name": self.speed_parameter}),
                  "coordinate": list(self.coordinate_names)}
        return xr.Dataset(data, coords=coords, attrs={"method": self.method})

    def plot_bode(self, coordinate, rotor=None, axes=None, **kwargs):
        """Amplitude and phase against speed (:func:`rotorkit.plotting.response.plot_bode`)."""
        from ..plotting.response import plot_unbalance_bode

        return plot_unbalance_bode(self, coordinate, rotor=rotor, axes=axes, **kwargs)

    def plot_polar(self, coordinate, rotor=None, ax=None, **kwargs):
        """Polar (Nyquist) plot of the response (:func:`rotorkit.plotting.response.plot_polar`)."""
        from ..plotting.response import plot_unbalance_polar

        return plot_unbalance_polar(self, coordinate, rotor=rotor, ax=ax, **kwargs)


def _unbalances(items):
    if isinstance(items, Unbalance):
        items = [items]
    out = []
    try:
        for u in items:
            if isinstance(u, Unbalance):
                out.append(u)
            elif isinstance(u, dict):
                out.append(Unbalance(**u))
            else:
                out.append(Unbalance(*u))
    except TypeError as exc:
        raise ParameterError(f"unbalances={items!r} is invalid: expected Unbalance(station, magnitude kg m, "
                             f"angle rad) items or (station, magnitude, angle) tuples") from exc
    if not out:
        raise ParameterError("unbalances is empty: expected at least one Unbalance(station, magnitude, angle)")
    return tuple(out)


def _singular(model, W, w, rotor, method):
    """The ParameterError for a dynamic stiffness that is singular (an undamped critical speed): names the speed
    (the first singular one) and the mode (its frequency and largest coordinates)."""
    from .harmonic import solve_harmonic

    n = model.n
    for k in range(W.size):  # the first speed whose solve fails: at most one more solve per speed
        try:
            ok = np.all(np.isfinite(solve_harmonic(model, W[k:k + 1], w[k:k + 1], np.ones((n, 1)), method=method)))
        except np.linalg.LinAlgError:
            ok = False
        if not ok:
            break
    M, C, K = model.matrices(W[k])  # speed terms included, exact at this speed
    D = K - w[k] ** 2 * M + 1j * w[k] * C
    shape = np.abs(np.linalg.svd(D)[2][-1].conj())  # the null vector: the mode at this frequency
    largest = [model.coordinate_names[i] for i in np.argsort(-shape)[:2] if shape[i] > 1e-3 * shape.max()]
    return ParameterError(
        f"unbalance_response: at speed {W[k]:.6g} rad/s ({W[k] * 30 / np.pi:.6g} rpm) rotor {rotor!r} excites at "
        f"{w[k]:.6g} rad/s, an undamped critical speed: the dynamic stiffness is singular there (the mode at "
        f"{w[k]:.6g} rad/s moving {', '.join(largest)} has no damping), so the response is infinite; "
        "add damping to the model or leave this speed out of speeds")


def unbalance_response(model, unbalances, speeds, *, method="auto", **linearisation):
    """Steady response to a set of unbalances over a range of the swept speed.

    Parameters
    ----------
    model : LinearModel or rotorkit.System
        A system is linearised first (:func:`~rotorkit.analysis.linear_model.linear_model`
        with ``**linearisation``: speed, speed_parameter, ...).
    unbalances : Unbalance or sequence of Unbalance or (station, magnitude, angle)
        Magnitudes in kg m, angles in rad (or quantities, ``"100 g*mm"``);
        each belongs to its station's rotor.
    speeds : array_like, pint.Quantity or sequence of str, shape (n_speeds,)
        Swept speed: rad/s as plain numbers, or with a unit
        (``Q_(np.linspace(0, 15000, 301), "rpm")``).
    method : {"auto", "banded", "dense"}
        See :mod:`rotorkit.analysis.harmonic`.

    Returns
    -------
    UnbalanceResponse

    Examples
    --------
    >>> import numpy as np
    >>> from rotorkit.analysis.linear_model import LinearModel
    >>> jeffcott = LinearModel(mass=2.0 * np.eye(2), damping=4.0 * np.eye(2), stiffness=2e4 * np.eye(2),
    ...                        coordinate_names=("x1", "y1"))
    >>> r = unbalance_response(jeffcott, [Unbalance(station=1, magnitude=1e-4)], [100.0])
    >>> round(float(r.amplitude("x1")[0]), 9), round(float(np.degrees(r.phase("x1")[0])), 6)
    (0.0025, -90.0)
    """
    from .harmonic import solve_harmonic
    from .linear_model import LinearModel, linear_model

    from ..units import to_si_array

    if not isinstance(model, LinearModel):
        if linearisation.get("speed") is not None:
            from ..units import to_si

            linearisation["speed"] = to_si(linearisation["speed"], "rad/s", "speed")
        model = linear_model(model, **linearisation)
    elif linearisation:
        raise TypeError(f"unbalance_response: unexpected keywords {sorted(linearisation)} for a LinearModel")
    items = _unbalances(unbalances)
    W = to_si_array(speeds, "rad/s", "speeds").reshape(-1)
    if W.size == 0 or not np.all(np.isfinite(W)):
        raise ParameterError("speeds is empty or not finite: expected finite speeds (rad/s)")
    if method not in ("auto", "banded", "dense"):
        raise ParameterError(f"method={method!r} is unknown: expected 'auto', 'banded' or 'dense'")
    n = model.n
    by_rotor = {}
    for u in items:
        ix, iy = model.station_index(u.station)
        rotor = model.station_rotors[str(u.station)]
        F = by_rotor.setdefault(rotor, np.zeros(n, dtype=complex))
        F[ix] += u.magnitude * np.exp(1j * u.angle)
        F[iy] += -1j * u.magnitude * np.exp(1j * u.angle)
    spins = model.spin_speeds(W)
    from .harmonic import harmonic_method

    used = harmonic_method(model, method)
    components, frequencies = {}, {}
    for rotor, F in by_rotor.items():
        w = np.abs(spins[rotor])
        forces = (w * w)[:, None, None] * F[None, :, None]
        if np.any(spins[rotor] < 0):
            raise ParameterError(f"rotor {rotor!r} spins backwards at some speeds: expected non-negative spin")
        try:
            Q = solve_harmonic(model, W, w, forces, method=used)[:, :, 0]
        except np.linalg.LinAlgError:
            Q = None
        if Q is None or not np.all(np.isfinite(Q)):
            raise _singular(model, W, w, rotor, used)
        Q.setflags(write=False)
        components[rotor] = Q
        frequencies[rotor] = w
    W.setflags(write=False)
    return UnbalanceResponse(speeds=W, coordinate_names=model.coordinate_names, components=components,
                             frequencies=frequencies, speed_parameter=model.speed_parameter, unbalances=items,
                             method=used)
