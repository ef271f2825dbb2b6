"""The API 617 lateral checks of a model: critical speed map with its bearings, unbalance response per mode.

:func:`bearing_stiffness` evaluates the stiffness each bearing adds to the
rotor at a speed (its entries of the cached linear matrices),
:func:`undamped_critical_map` removes the bearings and maps the undamped
critical speeds against a support stiffness, with the bearings' ``kxx`` and
``kyy`` against speed drawn over it (where a bearing curve crosses a
critical speed line the rotor has that critical speed on that bearing).
:func:`unbalance_checks` runs, for every forward critical speed up to the
top of the analysis range, the API 617 unbalance response: unbalances of
``6350 W / N`` g mm placed by the mode shape, the amplification factor of
the resulting peak and the separation margin it requires.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["bearing_stiffness", "undamped_critical_map", "ModeCheck", "unbalance_checks", "placements"]


def _parameter_vector(module, values):
    return [0.0 if name.endswith("_eccentricity") else float(values[name]) for name in module.PARAMETERS]


def bearing_stiffness(model, labels, speed_parameter, speed, t=0.0):
    """The stiffness matrix (N/m ..., shape (n, n)) elements ``labels`` add to ``model`` at ``speed`` (rad/s)."""
    from ..codegen.linear_cache import linear_module, template_function

    module = linear_module(model)
    if not module.LINEAR:
        raise ParameterError(f"audit: {model.name!r} is not linear; expected beams, disks and linear bearings")
    values = dict(model.parameters)
    values[speed_parameter] = float(speed)
    p = _parameter_vector(module, values)
    n = int(module.N_COORDINATES)
    K = np.zeros((n, n))
    for template, params, coords, label in module.ELEMENTS:
        if label not in labels:
            continue
        matrix, lrows, lcols = module.TEMPLATES[template][:3]
        stiff = [e for e, w in enumerate(matrix) if w == 2]
        if stiff:
            for e, v in zip(stiff, template_function(module, template, tuple(stiff))([p[k] for k in params], float(t))):
                K[coords[lrows[e]], coords[lcols[e]]] += float(v)
    return K


def undamped_critical_map(model, linear, bearings, top_speed, *, points=25, n_critical=4, decades=(2, 1)):
    """:class:`~rotorkit.linear.critical_map.CriticalSpeedMap` of the rotor without its bearings.

    Parameters
    ----------
    model : rotorkit.Model
    linear : LinearModel
        Of ``model`` (on its bearings).
    bearings : dict
        Bearing label -> station (str).
    top_speed : float
        Top of the speed range (rad/s).
    points : int
        Support stiffness values, log-spaced.
    n_critical : int
        Critical speeds kept per whirl direction.
    decades : (float, float)
        The stiffness axis spans from ``decades[0]`` decades below the
        softest bearing's direct stiffness to ``decades[1]`` above the
        stiffest's.
    """
    from ..linear.critical_map import critical_speed_map
    from ..linear.linear_model import LinearModel

    labels = set(bearings)
    K0 = bearing_stiffness(model, labels, linear.speed_parameter, 0.0)
    _, _, K = linear.matrices(0.0)
    # G of a linear model also holds the speed slope of speed-dependent bearing damping (symmetric): keep the
    # rotor's gyroscopic coupling, the skew-symmetric part
    G = 0.5 * (linear.gyroscopic - linear.gyroscopic.T)
    free = LinearModel(mass=linear.mass, damping=np.zeros_like(K), stiffness=K - K0, gyroscopic=G,
                       coordinate_names=linear.coordinate_names, rotor_speeds=linear.rotor_speeds,
                       station_rotors=linear.station_rotors, station_positions=linear.station_positions,
                       speed_parameter=linear.speed_parameter)
    speeds = np.linspace(0.0, top_speed, 21)
    curves, direct = {}, []
    for label, station in bearings.items():
        ix, iy = linear.station_index(station)
        kxx, kyy = [], []
        for w in speeds:
            Kb = bearing_stiffness(model, {label}, linear.speed_parameter, w)
            kxx.append(Kb[ix, ix])
            kyy.append(Kb[iy, iy])
        curves[f"{label} kxx"] = (speeds, np.array(kxx))
        curves[f"{label} kyy"] = (speeds, np.array(kyy))
        direct += kxx + kyy
    direct = np.array([k for k in direct if k > 0])
    if direct.size == 0:
        raise ParameterError("audit: the bearings have no positive direct stiffness to map critical speeds against")
    stiffnesses = np.logspace(np.log10(direct.min()) - decades[0], np.log10(direct.max()) + decades[1], points)
    return critical_speed_map(free, sorted(set(bearings.values()), key=str), stiffnesses, (1e-3 * top_speed, top_speed),
                              n_critical=n_critical, bearing_curves=curves)


@dataclass(frozen=True, eq=False)
class ModeCheck:
    """The API 617 unbalance check of one mode.

    Attributes
    ----------
    mode : int
        1-based, by critical speed.
    critical_speed : float
        Where the mode crosses the 1x line (rad/s, Campbell diagram).
    unbalances : tuple of Unbalance
        The API placement (kg m, rad).
    probe : str
        Station with the largest peak response (its orbit's major semi-axis).
    amplification : AmplificationFactor
        Of that station's response.
    margin : float
        Separation margin from the operating range (percent; negative inside).
    required : float
        Separation margin required for the amplification factor (percent).
    above : bool
        Whether the peak is above the operating range.
    speeds : numpy.ndarray
        Speeds of the response (rad/s).
    response : numpy.ndarray
        Major semi-axis (m) at ``probe`` at each speed.
    """

    mode: int
    critical_speed: float
    unbalances: tuple
    probe: str
    amplification: object
    margin: float
    required: float
    above: bool
    speeds: np.ndarray
    response: np.ndarray

    @property
    def passed(self):
        """Critically damped (``AF < 2.5``) or separated by at least the required margin."""
        return self.amplification.critically_damped or self.margin >= self.required


def _major_axes(response, stations):
    """Station -> orbit major semi-axis ``|F| + |B|`` (m) at each speed."""
    out = {}
    for s in stations:
        X, Y = response.response(f"x{s}"), response.response(f"y{s}")
        out[s] = 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))
    return out


def placements(shape, names, stations, positions, journal_loads, bearing_positions, mcs, factor=1.0):
    """API 617 unbalances for one mode shape.

    One unbalance of ``6350 (sum W) / N`` at the largest displacement when
    the shape has one lobe; otherwise one at each lobe's largest
    displacement (lobes smaller than 30 % of the largest ignored), of
    ``6350 W / N`` with ``W`` the load of the nearest journal, at 0 or 180
    degrees with the sign of the lobe. ``factor`` multiplies every magnitude.
    """
    from ..linear.unbalance import Unbalance
    from .formulas import unbalance_magnitude

    shape = np.asarray(shape, dtype=complex)
    k = int(np.argmax(np.abs(shape)))
    real = (shape * np.exp(-1j * np.angle(shape[k]))).real
    index = {n: i for i, n in enumerate(names)}
    xs = np.array([real[index[f"x{s}"]] for s in stations])
    ys = np.array([real[index[f"y{s}"]] for s in stations])
    v = xs if np.sum(xs**2) >= np.sum(ys**2) else ys
    lobes, start = [], 0
    for i in range(1, len(v) + 1):
        if i == len(v) or np.sign(v[i]) != np.sign(v[i - 1]) and v[i] != 0:
            j = start + int(np.argmax(np.abs(v[start:i])))
            lobes.append(j)
            start = i
    big = max(abs(v[j]) for j in lobes)
    lobes = [j for j in lobes if abs(v[j]) >= 0.3 * big]
    total = sum(journal_loads.values())
    if len(lobes) == 1:
        j = lobes[0]
        return (Unbalance(station=stations[j], magnitude=factor * unbalance_magnitude(total, mcs), angle=0.0),)
    out = []
    for j in lobes:
        z = positions[stations[j]]
        nearest = min(bearing_positions, key=lambda label: abs(bearing_positions[label] - z))
        out.append(Unbalance(station=stations[j], magnitude=factor * unbalance_magnitude(journal_loads[nearest], mcs),
                             angle=0.0 if v[j] > 0 else math.pi))
    return tuple(out)


def unbalance_checks(model, linear, operating, top_speed, journal_loads, bearings, *, points=241, n_modes=8,
                     unbalance_factor=1.0):
    """The API 617 unbalance check of every forward critical speed up to ``top_speed``.

    Parameters
    ----------
    model : rotorkit.Model
    linear : LinearModel
    operating : (float, float)
        Minimum operating and maximum continuous speeds (rad/s).
    top_speed : float
        Top of the analysis range (rad/s): 125 % of the trip speed.
    journal_loads : dict
        Bearing label -> static load (kg).
    bearings : dict
        Bearing label -> station.
    points : int
        Speeds of the sweep (a finer grid is added around each critical speed).
    n_modes : int
        Lowest modes computed for the Campbell diagram and the mode shapes.
    unbalance_factor : float
        Multiplies ``6350 W / N`` (the amplification factors and margins do
        not depend on it: the response is linear).

    Returns
    -------
    tuple of ModeCheck
    """
    from ..linear.campbell import campbell
    from ..linear.unbalance import unbalance_response
    from .formulas import amplification_factor, required_separation_margin, separation_margin
    from .stability import forward_fraction

    low, mcs = operating
    grid = np.linspace(0.02 * top_speed, top_speed, 25)
    diagram = campbell(linear, grid, n_modes=n_modes)
    criticals = sorted(c.speed for c in diagram.crossings if c.whirl != "backward" and c.speed <= top_speed)
    merged = []
    for c in criticals:
        if not merged or c > 1.05 * merged[-1]:
            merged.append(c)
    positions = linear.station_positions or {}
    stations = [str(s) for s in model.stations if str(s) in positions and f"x{s}" in linear.coordinate_names]
    bearing_positions = {label: positions[str(s)] for label, s in bearings.items()}
    checks = []
    for number, nc in enumerate(merged, start=1):
        modes = linear.modes(nc, n_modes=n_modes, left=False)
        fwd = forward_fraction(modes.shapes, modes.coordinate_names)
        candidates = [j for j in range(len(modes)) if fwd[j] > 0.5] or list(range(len(modes)))
        j = min(candidates, key=lambda i: abs(modes.damped_frequencies[i] - nc))
        unb = placements(modes.shapes[:, j], modes.coordinate_names, stations, positions, journal_loads,
                         bearing_positions, mcs, unbalance_factor)
        speeds = np.union1d(np.linspace(0.02 * top_speed, top_speed, points),
                            np.linspace(nc / 1.4, min(1.4 * nc, top_speed), points))
        response = unbalance_response(linear, unb, speeds)
        majors = _major_axes(response, stations)
        window = (nc / 1.25, 1.25 * nc)
        best = max(stations, key=lambda s: float(np.max(majors[s][(speeds >= window[0]) & (speeds <= window[1])])))
        af = amplification_factor(speeds, majors[best], window)
        margin, above = separation_margin(af.critical_speed, (low, mcs))
        required = required_separation_margin(af.factor, above)
        speeds.setflags(write=False)
        checks.append(ModeCheck(mode=number, critical_speed=float(nc), unbalances=unb, probe=best, amplification=af,
                                margin=margin, required=required, above=above, speeds=speeds,
                                response=majors[best]))
    return tuple(checks)
