"""The API 617 lateral checks of a model: critical speed map with its bearings, unbalance response per mode.

:func:`bearing_stiffness` evaluates the stiffness each bearing adds to the
rotor at a speed (its entries of the cached linear matrices),
:func:`undamped_critical_map` removes the bearings and maps the undamped
critical speeds against a support stiffness, with the bearings' ``kxx`` and
``kyy`` against speed drawn over it (where a bearing curve crosses a
critical speed line the rotor has that critical speed on that bearing).
:func:`unbalance_checks` runs, for every forward critical speed up to the
top of the analysis range, the API 617 unbalance response: unbalances of
``2 x 6350 W / N`` g mm placed by the mode shape
(:mod:`rotorkit.audit.placement`), the amplification factor of the
resulting peak and the separation margin it requires, and the amplitudes
at the probes and the close clearances (:mod:`rotorkit.audit.clearance`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["bearing_stiffness", "undamped_critical_map", "ModeCheck", "unbalance_checks"]


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
    supports = sorted(set(bearings.values()), key=lambda s: (0, int(s), "") if str(s).isdigit() else (1, 0, str(s)))
    return critical_speed_map(free, supports, stiffnesses, (1e-3 * top_speed, top_speed),
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
    placement : Placement
        The API unbalances (kg m, rad), their ``W`` and the rule applied.
    probe : str
        Station with the largest peak response (its orbit's major semi-axis):
        the amplification factor is read there.
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
    amplitude : AmplitudeCheck
        Peak-to-peak amplitudes at the vibration probes against ``A_vl``
        and, scaled, at the close clearances.
    amplitudes : dict
        Station -> peak-to-peak amplitude (m, major axis) at each speed.
    """

    mode: int
    critical_speed: float
    placement: object
    probe: str
    amplification: object
    margin: float
    required: float
    above: bool
    speeds: np.ndarray
    response: np.ndarray
    amplitude: object
    amplitudes: dict

    @property
    def unbalances(self):
        """The API unbalances (tuple of Unbalance)."""
        return self.placement.unbalances

    @property
    def margin_passed(self):
        """Critically damped (``AF < 2.5``) or separated by at least the required margin."""
        return self.amplification.critically_damped or self.margin >= self.required

    @property
    def passed(self):
        """The separation margin, the probes' amplitude limit and the close clearances met."""
        return self.margin_passed and self.amplitude.passed


def _major_axes(response, stations):
    """Station -> orbit major semi-axis ``|F| + |B|`` (m) at each speed."""
    out = {}
    for s in stations:
        X, Y = response.response(f"x{s}"), response.response(f"y{s}")
        out[s] = 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))
    return out


def unbalance_checks(model, linear, operating, top_speed, journal_loads, bearings, *, trip_speed=None, probes=None,
                     close_clearances=None, points=241, n_modes=8, unbalance_multiple=2.0,
                     scale_factor_limits=(0.5, 6.0)):
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
    trip_speed : float, optional
        The close clearances are checked up to it (rad/s; default ``top_speed / 1.25``).
    probes : sequence of str, optional
        Vibration probe stations (default the bearing stations).
    close_clearances : dict, optional
        Station -> minimum diametral running clearance (m).
    points : int
        Speeds of the sweep (a finer grid is added around each critical speed).
    n_modes : int
        Lowest modes computed for the Campbell diagram and the mode shapes.
    unbalance_multiple : float
        Of ``U_r = 6350 W / N`` (2 by the standard). The amplification
        factors, margins and scaled close-clearance amplitudes do not depend
        on it (the response is linear), the probes' amplitudes do.
    scale_factor_limits : (float, float) or None
        Bounds of the close-clearance scale factor ``S_cc``.

    Returns
    -------
    tuple of ModeCheck
    """
    from ..linear.campbell import campbell
    from ..linear.unbalance import unbalance_response
    from .clearance import amplitude_check
    from .formulas import amplification_factor, required_separation_margin, separation_margin
    from .placement import outboard_masses, placements
    from .stability import forward_fraction

    low, mcs = operating
    trip = top_speed / 1.25 if trip_speed is None else float(trip_speed)
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
    outboard = outboard_masses(model, positions, bearing_positions)
    probes = tuple(dict.fromkeys(str(s) for s in bearings.values())) if probes is None else tuple(probes)
    watched = sorted(set(stations) | set(probes) | set(close_clearances or {}), key=lambda s: positions.get(s, 0.0))
    checks = []
    for number, nc in enumerate(merged, start=1):
        modes = linear.modes(nc, n_modes=n_modes, left=False)
        fwd = forward_fraction(modes.shapes, modes.coordinate_names)
        candidates = [j for j in range(len(modes)) if fwd[j] > 0.5] or list(range(len(modes)))
        j = min(candidates, key=lambda i: abs(modes.damped_frequencies[i] - nc))
        placement = placements(modes.shapes[:, j], modes.coordinate_names, stations, positions, journal_loads,
                               bearing_positions, mcs, multiple=unbalance_multiple, outboard=outboard)
        speeds = np.union1d(np.linspace(0.02 * top_speed, top_speed, points),
                            np.linspace(nc / 1.4, min(1.4 * nc, top_speed), points))
        speeds = np.union1d(speeds, [low, mcs, min(trip, top_speed)])
        response = unbalance_response(linear, placement.unbalances, speeds)
        majors = _major_axes(response, watched)
        window = (nc / 1.25, 1.25 * nc)
        best = max(stations, key=lambda s: float(np.max(majors[s][(speeds >= window[0]) & (speeds <= window[1])])))
        af = amplification_factor(speeds, majors[best], window)
        margin, above = separation_margin(af.critical_speed, (low, mcs))
        required = required_separation_margin(af.factor, above)
        amplitudes = {s: 2.0 * a for s, a in majors.items()}
        amplitude = amplitude_check(speeds, amplitudes, probes, (low, mcs), trip, mcs, close_clearances,
                                    scale_factor_limits=scale_factor_limits)
        speeds.setflags(write=False)
        for a in amplitudes.values():
            a.setflags(write=False)
        checks.append(ModeCheck(mode=number, critical_speed=float(nc), placement=placement, probe=best,
                                amplification=af, margin=margin, required=required, above=above, speeds=speeds,
                                response=majors[best], amplitude=amplitude, amplitudes=amplitudes))
    return tuple(checks)
