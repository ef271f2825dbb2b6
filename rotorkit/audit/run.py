"""``api617_audit``: every API 617 lateral check of a model, gathered in one result.

For a model of one rotor on linear bearings with gravity: the static
deflection, bearing loads and shear-force and bending-moment diagrams; the
undamped critical speed map with the bearing stiffness curves; the
unbalance response of each forward mode up to 125 % of the trip speed
(``2 x 6350 W / N`` placed by the mode shape) with its amplification
factor and separation margin, the amplitudes at the vibration probes
against ``A_vl`` and the scaled amplitudes at the close clearances; and
the Level I stability at the maximum continuous speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ParameterError

__all__ = ["Api617Audit", "api617_audit", "STANDARD_GRAVITY"]

#: gravity (m/s^2) turning bearing loads into journal masses when the model has no load field
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True, eq=False)
class Api617Audit:
    """Results of :func:`api617_audit` (SI units).

    Attributes
    ----------
    model : rotorkit.Model
    inputs : dict
        What the audit was given (name -> text), for the report.
    operating : (float, float)
        Minimum operating and maximum continuous speeds (rad/s).
    trip_speed, top_speed : float
        Trip speed and the top of the analysis range, 1.25 x trip (rad/s).
    journal_loads : dict
        Bearing label -> static load (kg).
    bearings : dict
        Bearing label -> station.
    static : StaticDeflection
    shear_moment : ShearMoment
    critical_map : CriticalSpeedMap
    modes : tuple of ModeCheck
    stability : Level1Stability
    wachel : numpy.ndarray or None
        ``q_A`` per impeller (N/m) when ``Q_A`` came from the Wachel formula.
    """

    model: object
    inputs: dict
    operating: tuple
    trip_speed: float
    top_speed: float
    journal_loads: dict
    bearings: dict
    static: object
    shear_moment: object
    critical_map: object
    modes: tuple
    stability: object
    wachel: object = None
    version: str = field(default="")

    @property
    def passed(self):
        """Every mode's separation margin and amplitude checks, and the Level I screening, met."""
        return all(m.passed for m in self.modes) and self.stability.passed

    def summary(self):
        """Rows ``(check, value, requirement, passed)`` of the pass/fail summary (text)."""
        rows = []
        for m in self.modes:
            af = m.amplification
            where = "above" if m.above else "below"
            af_text = "critically damped (no peak)" if af.factor == 0 else f"AF = {af.factor:.2f}"
            rows.append((f"mode {m.mode}: critical speed {af.critical_speed * 30 / math.pi:.0f} rpm",
                         f"{af_text}; margin {m.margin:.1f} % ({where})",
                         "AF < 2.5 or margin >= " + f"{m.required:.1f} %", m.margin_passed))
            a = m.amplitude
            rows.append((f"mode {m.mode}: probe amplitude (st. {a.probe}, operating range)",
                         f"{a.max_amplitude * 1e6:.3g} um pk-pk", f"< A_vl = {a.vibration_limit * 1e6:.3g} um",
                         a.probes_passed))
            for c in a.clearances:
                rows.append((f"mode {m.mode}: close clearance at st. {c.station} (x S_cc = {a.scale_factor:.3g})",
                             f"{c.amplitude * 1e6:.3g} um pk-pk", f"< 75 % of {c.clearance * 1e6:.4g} um = "
                             f"{c.limit * 1e6:.4g} um", c.passed))
        s = self.stability
        rows.append(("Level I stability: Q_0 / Q_A", f"{s.q_ratio:.2f}", ">= 2.0", s.q_ratio >= 2.0))
        rows.append(("Level I stability: log decrement at Q_A", f"{s.log_decrement_a:.3f}", ">= 0.1",
                     s.log_decrement_a >= 0.1))
        return rows

    def write_report(self, path):
        """The self-contained HTML report (:func:`rotorkit.audit.report.write_report`); the path."""
        from .report import write_report

        return write_report(self, path)

    def write_csv(self, folder):
        """``stability.csv``, ``shear_moment.csv``, ``critical_map.csv``, ``modes.csv``, ``unbalances.csv``
        and ``clearances.csv`` in ``folder``."""
        from pathlib import Path

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        self.stability.to_csv(folder / "stability.csv")
        self.shear_moment.to_csv(folder / "shear_moment.csv")
        self.critical_map.to_csv(folder / "critical_map.csv")
        from ..linear.tables import csv_output

        rows = ["mode,critical_speed_rad_s,peak_speed_rad_s,amplification_factor,half_power_low_rad_s,"
                "half_power_high_rad_s,margin_percent,required_percent,above,margin_passed,max_probe_amplitude_m_pkpk,"
                "vibration_limit_m_pkpk,probes_passed,scale_factor,passed"]
        for m in self.modes:
            a, p = m.amplification, m.amplitude
            rows.append(f"{m.mode},{m.critical_speed:.10g},{a.critical_speed:.10g},{a.factor:.10g},{a.lower:.10g},"
                        f"{a.upper:.10g},{m.margin:.10g},{m.required:.10g},{m.above},{m.margin_passed},"
                        f"{p.max_amplitude:.10g},{p.vibration_limit:.10g},{p.probes_passed},{p.scale_factor:.10g},"
                        f"{m.passed}")
        csv_output("\n".join(rows) + "\n", folder / "modes.csv")
        rows = ["mode,station,magnitude_kg_m,angle_rad,journal_load_kg,kind"]
        for m in self.modes:
            for u, w, kind in zip(m.placement.unbalances, m.placement.loads, m.placement.kinds):
                rows.append(f"{m.mode},{u.station},{u.magnitude:.10g},{u.angle:.10g},{w:.10g},{kind}")
        csv_output("\n".join(rows) + "\n", folder / "unbalances.csv")
        rows = ["mode,station,diametral_clearance_m,limit_m,scaled_amplitude_m_pkpk,speed_rad_s,passed"]
        for m in self.modes:
            for c in m.amplitude.clearances:
                rows.append(f"{m.mode},{c.station},{c.clearance:.10g},{c.limit:.10g},{c.amplitude:.10g},"
                            f"{c.speed:.10g},{c.passed}")
        csv_output("\n".join(rows) + "\n", folder / "clearances.csv")
        return folder


def _bearing_loads(model, static, gravity):
    """(bearing label -> station, bearing label -> journal load kg) from the static reactions (seals left out)."""
    from ..linear.whirl import station_pairs

    seals = {e.label() for e in model.elements if type(e).__name__ == "Seal"}
    bearings, loads = {}, {}
    for label, forces in static.reactions.items():
        if label in seals:
            continue
        pairs = station_pairs(tuple(forces)) or [(name[1:], None, None) for name in forces
                                                 if name[:1] in "xy" and name[1:]]
        if not pairs:
            continue
        station = pairs[0][0]
        fx, fy = forces.get(f"x{station}", 0.0), forces.get(f"y{station}", 0.0)
        bearings[label] = str(station)
        loads[label] = math.hypot(fx, fy) / gravity
    return bearings, loads


def api617_audit(model, operating_range, *, q_a=None, wachel=None, trip_speed=None, cross_coupling_stations=None,
                 speed_parameter=None, journal_loads=None, probes=None, close_clearances=None, points=241,
                 unbalance_multiple=None, scale_factor_limits=None):
    """Run the API 617 lateral checks on ``model``.

    Parameters
    ----------
    model : rotorkit.Model
        One rotor of beam segments and disks on linear bearings (equations
        linear), with gravity (the bearing loads give the journal loads).
    operating_range : (speed, speed)
        Minimum operating speed and maximum continuous speed (rad/s, or
        ``("8000 rpm", "10500 rpm")``).
    q_a : float, str or pint.Quantity, optional
        Anticipated cross-coupling ``Q_A`` (N/m); or give ``wachel``.
    wachel : dict, optional
        Keywords of :func:`~rotorkit.audit.formulas.wachel_cross_coupling`
        (``power``, ``impeller_diameter``, ``restrictive_width``,
        ``density_ratio``, ``stage_factor``), evaluated at the maximum
        continuous speed.
    trip_speed : speed, optional
        Default 105 % of the maximum continuous speed.
    cross_coupling_stations : sequence of station, optional
        Where ``Q`` acts (default: the station nearest the mid-span between
        the outermost bearings).
    speed_parameter : str, optional
        The rotor speed swept (default: the first rotor's).
    journal_loads : dict, optional
        Bearing label -> static load (kg), instead of the gravity reactions.
    probes : sequence of station, optional
        Vibration probe stations, where the peak-to-peak amplitude within
        the operating range is checked against ``A_vl`` (default: the
        bearing stations).
    close_clearances : dict, optional
        Station -> minimum design diametral running clearance (m, or e.g.
        ``"0.4 mm"``): seals and other close clearances, where the scaled
        amplitude from zero to the trip speed is checked against 75 % of it.
    points : int
        Speeds of each unbalance response sweep.
    unbalance_multiple : float, optional
        Multiple of the residual unbalance ``U_r = 6350 W / N`` applied by
        the response analysis; default
        :data:`~rotorkit.audit.formulas.ANALYSIS_UNBALANCE_MULTIPLE`, 2, as
        API 617 says (8th ed. 4.8.2.7). The amplification factors,
        separation margins and scaled close-clearance amplitudes do not
        depend on it; the probe amplitudes do.
    scale_factor_limits : (float, float), optional
        Bounds of the close-clearance scale factor ``S_cc = A_vl / A_max``;
        default :data:`~rotorkit.audit.formulas.SCALE_FACTOR_LIMITS`
        (0.5, 6).

    Returns
    -------
    Api617Audit
    """
    import rotorkit

    from ..linear.linear_model import linear_model
    from ..linear.static import static_deflection
    from ..units import to_si
    from .checks import undamped_critical_map, unbalance_checks
    from .clearance import close_clearances_si, probe_stations
    from .formulas import ANALYSIS_UNBALANCE_MULTIPLE, SCALE_FACTOR_LIMITS, operating_bounds, wachel_cross_coupling
    from .shear_moment import gravity_field, shear_moment
    from .stability import level1_stability

    model = getattr(model, "model", model)
    low, mcs = operating_bounds(operating_range)
    trip = 1.05 * mcs if trip_speed is None else to_si(trip_speed, "rad/s", "trip_speed")
    if not (math.isfinite(trip) and trip >= mcs):
        raise ParameterError(f"trip_speed={trip_speed!r} is invalid: expected a speed >= the maximum continuous "
                             f"speed ({mcs:g} rad/s)")
    if (q_a is None) == (wachel is None):
        raise ParameterError("api617_audit: give exactly one of q_a (the anticipated cross-coupling Q_A, N/m) and "
                             "wachel (the inputs of the Wachel formula: power, impeller_diameter, "
                             "restrictive_width, density_ratio)")
    multiple = ANALYSIS_UNBALANCE_MULTIPLE if unbalance_multiple is None else unbalance_multiple
    if isinstance(multiple, bool) or not isinstance(multiple, (int, float)) or not (
            math.isfinite(multiple) and multiple > 0):
        raise ParameterError(f"unbalance_multiple={unbalance_multiple!r} is invalid: expected a positive multiple of "
                             f"U_r = 6350 W / N (the standard's is {ANALYSIS_UNBALANCE_MULTIPLE:g})")
    limits = SCALE_FACTOR_LIMITS if scale_factor_limits is None else tuple(float(v) for v in scale_factor_limits)
    if len(limits) != 2 or not (0 < limits[0] <= limits[1] and math.isfinite(limits[1])):
        raise ParameterError(f"scale_factor_limits={scale_factor_limits!r} is invalid: expected (low, high) with "
                             "0 < low <= high")
    known = [str(s) for s in model.stations]
    probe_list = None if probes is None else probe_stations(probes, known)
    clearances = None if close_clearances is None else close_clearances_si(close_clearances, known)
    q_each = None
    if wachel is not None:
        if not isinstance(wachel, dict):
            raise ParameterError(f"wachel={wachel!r} is invalid: expected a dict of wachel_cross_coupling keywords")
        q_each, q_a = wachel_cross_coupling(speed=mcs, **wachel)
    top = 1.25 * trip
    from ..codegen.linear_cache import linear_module

    if not linear_module(model).LINEAR:
        raise ParameterError(f"api617_audit: {model.name!r} is not linear (contacts, Hertzian or fluid-film "
                             "bearings solved in time): expected beams, disks and linear bearings")
    static = static_deflection(model)
    g = math.hypot(*gravity_field(model, 0.0)) or STANDARD_GRAVITY
    bearings, loads = _bearing_loads(model, static, g)
    if journal_loads is not None:
        unknown = set(journal_loads) - set(bearings)
        if unknown:
            raise ParameterError(f"journal_loads names {sorted(unknown)}: expected bearings among {sorted(bearings)}")
        loads.update({k: to_si(v, "kg", f"journal_loads[{k!r}]") for k, v in journal_loads.items()})
    if len(bearings) == 0:
        raise ParameterError(f"api617_audit: {model.name!r} has no bearing carrying the rotor")
    if sum(loads.values()) <= 0:
        raise ParameterError(f"api617_audit: the journal static loads of {model.name!r} are zero (no gravity?): "
                             "add a Maneuver (gravity) or give journal_loads in kg")
    linear = linear_model(model, speed_parameter=speed_parameter)
    positions = linear.station_positions or {}
    if cross_coupling_stations is None:
        zb = [positions[s] for s in bearings.values() if s in positions]
        if len(zb) < 1:
            raise ParameterError("api617_audit: the bearings have no axial positions; give cross_coupling_stations")
        middle = 0.5 * (min(zb) + max(zb))
        named = [str(s) for s in model.stations if str(s) in positions]
        cross_coupling_stations = [min(named, key=lambda s: abs(positions[s] - middle))]
    stations = [str(s) for s in (cross_coupling_stations if isinstance(cross_coupling_stations, (list, tuple))
                                 else [cross_coupling_stations])]
    lateral = [s for s in known if f"x{s}" in linear.coordinate_names and f"y{s}" in linear.coordinate_names]
    probe_list = probe_stations(list(dict.fromkeys(bearings.values())) if probes is None else probe_list, lateral)
    if clearances is not None:
        clearances = close_clearances_si(clearances, lateral)
    cmap = undamped_critical_map(model, linear, bearings, top)
    modes = unbalance_checks(model, linear, (low, mcs), top, loads, bearings, trip_speed=trip, probes=probe_list,
                             close_clearances=clearances, points=points, unbalance_multiple=float(multiple),
                             scale_factor_limits=limits)
    stability = level1_stability(linear, mcs, q_a, stations)
    shear = shear_moment(model, deflection=static)
    rpm = 30.0 / math.pi
    inputs = {"model": model.name, "minimum operating speed": f"{low * rpm:.6g} rpm",
              "maximum continuous speed": f"{mcs * rpm:.6g} rpm", "trip speed": f"{trip * rpm:.6g} rpm",
              "analysis range": f"0 to {top * rpm:.6g} rpm (125 % of trip)",
              "Q_A": f"{stability.q_a:.6g} N/m" + (" (Wachel)" if q_each is not None else " (given)"),
              "cross-coupling stations": ", ".join(stations),
              "unbalance": f"{multiple:g} x U_r (API 617 8th ed. 4.8.2.7: 2 x U_r)",
              "vibration probes": ", ".join(probe_list),
              "close clearances (diametral)": "none given" if not clearances else ", ".join(
                  f"st. {k}: {v * 1e3:.4g} mm" for k, v in clearances.items()),
              "scale factor bounds": f"{limits[0]:g} to {limits[1]:g}",
              "journal static loads": ", ".join(f"{k}: {v:.4g} kg" for k, v in loads.items())}
    if wachel is not None:
        inputs.update({f"Wachel {k}": ", ".join(map(str, v)) if isinstance(v, (list, tuple)) else str(v)
                       for k, v in wachel.items()})
    return Api617Audit(model=model, inputs=inputs, operating=(low, mcs), trip_speed=trip, top_speed=top,
                       journal_loads=loads, bearings=bearings, static=static, shear_moment=shear, critical_map=cmap,
                       modes=modes, stability=stability, wachel=q_each, version=rotorkit.__version__)
