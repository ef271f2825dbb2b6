"""Undamped critical speed map: critical speeds against support stiffness.

For each support stiffness ``k`` the supports' ``x`` and ``y`` stiffness at
the chosen stations is set to ``k`` on top of the rotor's own stiffness,
damping is removed, and the critical speeds are where the forward (and
backward) whirling modes meet the 1x line of their rotor, gyroscopic
stiffening included. For one rotor spinning at the swept speed they are the
roots of one generalised eigenproblem per stiffness, ``K Q = W^2 (M - i G) Q``
(an undamped whirl whose frequency is the speed: exact, no speed grid); any
other linear model is swept with :func:`~rotorkit.analysis.campbell.campbell`
(mode tracking and root finding). A rigid-support asymptote appears at large
``k``, the rigid-body modes ``~ sqrt(k)`` at small ``k``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["CriticalSpeedMap", "critical_speed_map"]


@dataclass(frozen=True, eq=False)
class CriticalSpeedMap:
    """Critical speeds (rad/s) against support stiffness (N/m).

    Attributes
    ----------
    stiffnesses : numpy.ndarray, shape (n_k,)
    speeds : numpy.ndarray, shape (n_k, n_crit)
        The ``n_crit`` lowest forward critical speeds at each stiffness
        (NaN where fewer were found in the speed range).
    backward : numpy.ndarray, shape (n_k, n_crit)
        The same for backward whirl.
    supports : tuple of str
        Stations whose support stiffness was varied.
    bearing_curves : dict
        Label -> ``(speeds rad/s, stiffness N/m)`` drawn over the map.
    """

    stiffnesses: np.ndarray
    speeds: np.ndarray
    backward: np.ndarray
    supports: tuple
    bearing_curves: dict

    def to_csv(self, path=None, *, units="rad/s"):
        """One row per support stiffness (N/m): the forward then the backward critical speeds in ``units``.

        ``path`` (None: the text) and ``units`` as for every linear result
        (:func:`~rotorkit.analysis.tables.csv_output`).
        """
        from ..units import display_factor
        from .modal_result import unit_slug
        from .tables import csv_output

        f, u = display_factor(units, "speed"), unit_slug(units)
        n = self.speeds.shape[1]
        cols = ["stiffness_N_m"] + [f"forward{j + 1}_{u}" for j in range(n)] + [f"backward{j + 1}_{u}"
                                                                                 for j in range(n)]
        rows = [",".join(cols)]
        for a, k in enumerate(self.stiffnesses):
            rows.append(",".join(f"{v:.10g}" for v in (k, *(self.speeds[a] * f), *(self.backward[a] * f))))
        return csv_output("\n".join(rows) + "\n", path)

    def to_xarray(self, units="rad/s"):
        """The map as an :class:`xarray.Dataset` over (stiffness, critical)."""
        import xarray as xr

        from ..units import display_factor

        f = display_factor(units, "speed")
        coords = {"stiffness": ("stiffness", self.stiffnesses, {"units": "N/m", "long_name": "support stiffness"}),
                  "critical": np.arange(1, self.speeds.shape[1] + 1)}
        return xr.Dataset({"forward": (("stiffness", "critical"), self.speeds * f,
                                       {"units": units, "long_name": "forward critical speed"}),
                           "backward": (("stiffness", "critical"), self.backward * f,
                                        {"units": units, "long_name": "backward critical speed"})},
                          coords=coords, attrs={"supports": ", ".join(self.supports)})

    def plot(self, ax=None, **kwargs):
        """Log-log map (:func:`rotorkit.plotting.maps.plot_critical_speed_map`)."""
        from ..plotting.critical_map import plot_critical_speed_map

        return plot_critical_speed_map(self, ax=ax, **kwargs)


def _synchronous_form(rotor):
    """``M - i G`` when the undamped synchronous whirl is one generalised eigenproblem, else None.

    At a critical speed ``W`` an undamped whirl of frequency ``W`` exists: ``q = Re(Q e^{i W t})`` in
    ``M q'' + W G q' + K q = 0`` gives ``K Q = W^2 (M - i G) Q``, linear in ``W^2`` when the rotor spins at
    the swept speed itself and nothing else depends on it.
    """
    speeds = list(rotor.rotor_speeds.values())
    if len(speeds) != 1 or rotor.speed_terms is not None:
        return None
    offset, ratio = (float(v) for v in speeds[0])  # rounding of the numerical spin-speed fit allowed
    if abs(offset) > 1e-6 or abs(ratio - 1.0) > 1e-9:
        return None
    if rotor.circulatory is not None and np.any(np.asarray(rotor.circulatory) != 0):
        return None
    gyroscopic = np.zeros_like(rotor.mass) if rotor.gyroscopic is None else np.asarray(rotor.gyroscopic)
    return np.asarray(rotor.mass, dtype=complex) - 1j * gyroscopic


def _synchronous_criticals(rotor, mass, idx, k, lo, hi, count):
    """(forward, backward) critical speeds in ``[lo, hi]``, the lowest ``count`` of each (NaN-padded)."""
    from scipy import linalg

    from .whirl import shape_whirl

    K = np.array(rotor.stiffness, dtype=float)
    K[idx, idx] += k
    lam, vectors = linalg.eig(K, mass)
    real = np.isfinite(lam) & (np.abs(lam.imag) <= 1e-9 * np.abs(lam)) & (lam.real > 0)
    speeds = np.sqrt(lam.real[real])
    vectors = vectors[:, real]
    keep = (speeds >= lo) & (speeds <= hi)
    speeds, vectors = speeds[keep], vectors[:, keep]
    kinds = shape_whirl(vectors, tuple(rotor.coordinate_names), rotor.station_positions)[0] if speeds.size else []
    order = np.argsort(speeds)
    out = {"forward": [], "backward": []}
    for i in order:
        w = float(speeds[i])
        twin = [j for j in order if j != i and abs(speeds[j] - w) <= 1e-9 * w]
        # a double root (no gyroscopic split) whirls either way: a critical speed of both directions
        for kind in (("forward", "backward") if twin else ("backward" if kinds[i] == "backward" else "forward",)):
            if not any(abs(v - w) <= 1e-9 * w for v in out[kind]):
                out[kind].append(w)
    result = []
    for kind in ("forward", "backward"):
        row = np.full(count, np.nan)
        found = out[kind][:count]
        row[:len(found)] = found
        result.append(row)
    return result


def critical_speed_map(rotor, supports, stiffnesses, speed_range, *, n_critical=4, n_speeds=60,
                       bearing_curves=None, method="auto"):
    """Undamped critical speeds of ``rotor`` on supports of stiffness ``k`` at ``supports``.

    Parameters
    ----------
    rotor : LinearModel
        The rotor without (or with, as a baseline) the supports being varied.
    supports : sequence of station
        Stations whose ``x`` and ``y`` support stiffness is ``k``.
    stiffnesses : array_like or pint.Quantity, shape (n_k,)
        Support stiffness values (N/m, or with a unit: ``Q_(k, "N/mm")``),
        positive (log-spaced for a log-log map).
    speed_range : (float, float), pint.Quantity or (str, str)
        Swept speed range (rad/s, or with a unit: ``("0 rpm", "20000 rpm")``)
        searched for 1x crossings.
    n_critical : int
        Number of critical speeds kept per whirl direction.
    n_speeds : int
        Grid points of each Campbell search (crossings are then located by
        root finding).
    bearing_curves : dict, optional
        Label -> ``(speeds, stiffness)`` of speed-dependent bearings, overlaid.
    method : {"auto", "synchronous", "campbell"}
        ``"synchronous"``: the critical speeds at each stiffness are the roots
        of one generalised eigenproblem, ``K Q = W^2 (M - i G) Q`` (an undamped
        whirl at the frequency ``W`` of the rotor speed ``W``: exact, no speed
        grid; one rotor spinning at the swept speed, no circulatory or
        speed-dependent terms). ``"campbell"``: a Campbell diagram per
        stiffness over ``n_speeds`` speeds, crossings by root finding (any
        linear model). ``"auto"``: synchronous where it applies.

    Returns
    -------
    CriticalSpeedMap
    """
    from .campbell import campbell
    from .linear_model import LinearModel

    if not isinstance(rotor, LinearModel):
        raise TypeError(f"critical_speed_map: expected a LinearModel, got {type(rotor).__name__}")
    from ..units import to_si_array

    k = to_si_array(stiffnesses, "N/m", "stiffnesses").reshape(-1)
    if k.size == 0 or not np.all(np.isfinite(k)) or np.any(k <= 0):
        raise ParameterError(f"stiffnesses={stiffnesses!r} is invalid: expected positive stiffnesses (N/m)")
    bounds = to_si_array(speed_range, "rad/s", "speed_range")
    if bounds.shape != (2,):
        raise ParameterError(f"speed_range={speed_range!r} is invalid: expected (low, high) in rad/s")
    lo, hi = (float(v) for v in bounds)
    if not 0 <= lo < hi:
        raise ParameterError(f"speed_range={speed_range!r} is invalid: expected 0 <= low < high (rad/s)")
    stations = tuple(str(s) for s in supports)
    idx = [i for s in stations for i in rotor.station_index(s)]
    grid = np.linspace(lo, hi, int(n_speeds))
    fwd = np.full((k.size, int(n_critical)), np.nan)
    bwd = np.full((k.size, int(n_critical)), np.nan)
    if method not in ("auto", "synchronous", "campbell"):
        raise ParameterError(f"method={method!r} is unknown: expected 'auto', 'synchronous' or 'campbell'")
    synchronous = _synchronous_form(rotor)
    if method == "synchronous" and synchronous is None:
        raise ParameterError("method='synchronous' needs one rotor spinning at the swept speed (ratio 1, no "
                             "offset), no circulatory terms and no speed-dependent coefficients; use 'campbell'")
    if method != "campbell" and synchronous is not None:
        for a, value in enumerate(k):
            fwd[a], bwd[a] = _synchronous_criticals(rotor, synchronous, idx, value, lo, hi, int(n_critical))
        k.setflags(write=False)
        return CriticalSpeedMap(stiffnesses=k, speeds=fwd, backward=bwd, supports=stations,
                                bearing_curves=dict(bearing_curves or {}))
    n_modes = min(rotor.n, 2 * int(n_critical) + 2)
    for a, value in enumerate(k):
        K = np.array(rotor.stiffness)
        K[idx, idx] += value
        model = LinearModel(mass=rotor.mass, damping=np.zeros_like(K), stiffness=K, gyroscopic=rotor.gyroscopic,
                            circulatory=rotor.circulatory, coordinate_names=rotor.coordinate_names,
                            rotor_speeds=rotor.rotor_speeds, station_rotors=rotor.station_rotors,
                            speed_parameter=rotor.speed_parameter,
                            speed_terms=None if rotor.speed_terms is None else rotor.speed_terms.stiffness_only())
        diagram = campbell(model, grid, n_modes=n_modes)
        for kind, out in (("forward", fwd), ("backward", bwd)):
            found = sorted({round(c.speed, 9) for c in diagram.crossings
                            if (c.whirl == "backward") == (kind == "backward")})
            found = found[: out.shape[1]]
            out[a, : len(found)] = found
    k.setflags(write=False)
    return CriticalSpeedMap(stiffnesses=k, speeds=fwd, backward=bwd, supports=stations,
                            bearing_curves=dict(bearing_curves or {}))
