"""Where API 617 puts the unbalance of each mode, and how large: chosen from the mode shape.

API 617 (8th ed. 4.8.2.7 and its figure of typical mode shapes with their
unbalance locations; API 684 SP6.8.2.7) places the unbalance so that it
excites the mode analysed: at mid-span for the first (translatory) mode of
a rotor between bearings, at the two ends out of phase for a conical or
second bending mode, at the overhung disk or coupling for a mode whose
largest deflection is at a shaft end (in phase or out of phase at the two
ends as the mode moves them). Its magnitude is ``2 x U_r``,
``U_r = 6350 W / N`` g mm, with ``W`` the journal static load the
unbalance acts on, or for an overhung end the mass outboard of the bearing.

The rule applied to a mode shape (:func:`placements`):

1. the shape at the critical speed is turned real (phase of its largest
   entry removed) and its dominant bending plane taken (x or y, the larger);
2. it is cut at its sign changes into lobes along the shaft (stations in
   axial order); lobes smaller than 30 % of the largest are dropped;
3. each lobe gets one unbalance at its largest displacement, at 0 degrees
   for a lobe of the sign of the largest one and 180 for one of the other (so two lobes of opposite
   sign are out of phase, of one sign in phase);
4. an end is overhung when a disk or lumped mass (impeller, coupling hub)
   sits outboard of its bearing; a lobe peaking on an end that is not
   (a bare shaft stub) takes its largest displacement between the bearings;
5. ``W`` of a lobe on an overhung end is the mass outboard of that bearing
   (shaft, disks and lumped masses); of the only lobe
   between the bearings (and no other lobe) the sum of the journal loads;
   of every other lobe the load of the nearest journal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["Placement", "placements", "outboard_masses", "LOBE_THRESHOLD"]

#: lobes of a mode shape smaller than this fraction of its largest get no unbalance
LOBE_THRESHOLD = 0.3


@dataclass(frozen=True, slots=True)
class Placement:
    """The API 617 unbalances of one mode.

    Attributes
    ----------
    unbalances : tuple of Unbalance
        ``multiple x 6350 W / N`` (kg m) at each lobe, 0 or pi rad.
    loads : tuple of float
        ``W`` (kg) of each unbalance.
    kinds : tuple of str
        Where each lobe is: ``"mid-span"`` (the only lobe between the
        bearings), ``"between bearings"``, ``"overhung"``.
    rule : str
        The placement in words, for the report.
    """

    unbalances: tuple
    loads: tuple
    kinds: tuple
    rule: str


def outboard_masses(model, positions, bearing_positions, tolerance=1e-9):
    """Rotor mass (kg) outboard of the first and of the last bearing: ``(left, right)``.

    Beam and shaft segments lying wholly outboard of the bearing (their
    ``mass_value()``), and disks and lumped masses at stations outboard of
    it; what sits at the bearing station itself is not outboard. An end
    counts as overhung only when a disk or lumped mass (an impeller, a
    coupling hub) is outboard of its bearing: the mass of an end without
    one is returned as 0 (a bare shaft stub gets no overhung unbalance).

    Parameters
    ----------
    model : rotorkit.Model
    positions : dict
        Station (str) -> axial position (m).
    bearing_positions : dict
        Bearing label -> axial position (m).
    """
    if not bearing_positions:
        raise ParameterError("outboard_masses: bearing_positions is empty: expected the bearings' axial positions")
    z_lo, z_hi = min(bearing_positions.values()), max(bearing_positions.values())
    left = right = 0.0
    carried = [False, False]
    for e in model.elements:
        if hasattr(e, "start") and hasattr(e, "end") and hasattr(e, "mass_value"):
            ends = [positions.get(str(s)) for s in (e.start, e.end)]
            if None in ends:
                continue
            if max(ends) <= z_lo + tolerance:
                left += float(e.mass_value())
            elif min(ends) >= z_hi - tolerance:
                right += float(e.mass_value())
        elif hasattr(e, "station") and isinstance(getattr(e, "mass", None), (int, float)):
            z = positions.get(str(e.station))
            if z is None:
                continue
            if z < z_lo - tolerance:
                left += float(e.mass)
                carried[0] = True
            elif z > z_hi + tolerance:
                right += float(e.mass)
                carried[1] = True
    return (left if carried[0] else 0.0), (right if carried[1] else 0.0)


def _lobes(v):
    """``(start, stop)`` index ranges of the runs of one sign of ``v`` (zeros join the run they are in)."""
    lobes, start, sign = [], 0, 0.0
    for i, x in enumerate(v):
        s = np.sign(x)
        if s != 0 and sign != 0 and s != sign:
            lobes.append((start, i))
            start = i
        if s != 0:
            sign = s
    lobes.append((start, len(v)))
    return lobes


def _peak(v, candidates):
    return max(candidates, key=lambda i: abs(v[i]))


def placements(shape, names, stations, positions, journal_loads, bearing_positions, max_continuous_speed, *,
               multiple=2.0, outboard=(0.0, 0.0), tolerance=1e-9):
    """The API 617 unbalances of one mode shape (see the module's rule).

    Parameters
    ----------
    shape : array_like of complex, shape (n,)
        Mode shape over the coordinates ``names``.
    names : sequence of str
        Coordinate names (``x<station>``, ``y<station>``, ...).
    stations : sequence of str
        Stations that may carry an unbalance; sorted here by position.
    positions : dict
        Station -> axial position (m).
    journal_loads : dict
        Bearing label -> journal static load (kg).
    bearing_positions : dict
        Bearing label -> axial position (m).
    max_continuous_speed : float
        ``N`` (rad/s).
    multiple : float
        Of ``U_r = 6350 W / N`` (2 by the standard).
    outboard : (float, float)
        Mass (kg) outboard of the first and of the last bearing
        (:func:`outboard_masses`).

    Returns
    -------
    Placement
    """
    from ..linear.unbalance import Unbalance
    from .formulas import analysis_unbalance

    missing = [s for s in stations if s not in positions]
    if missing:
        raise ParameterError(f"placements: stations {missing} have no axial position")
    if set(journal_loads) != set(bearing_positions) or not journal_loads:
        raise ParameterError(f"placements: journal_loads {sorted(journal_loads)} and bearing_positions "
                             f"{sorted(bearing_positions)}: expected the same bearings, at least one")
    stations = sorted(stations, key=lambda s: positions[s])
    shape = np.asarray(shape, dtype=complex)
    k = int(np.argmax(np.abs(shape)))
    real = (shape * np.exp(-1j * np.angle(shape[k]))).real
    index = {n: i for i, n in enumerate(names)}
    xs = np.array([real[index[f"x{s}"]] for s in stations])
    ys = np.array([real[index[f"y{s}"]] for s in stations])
    v = xs if np.sum(xs**2) >= np.sum(ys**2) else ys
    v = v if v[int(np.argmax(np.abs(v)))] >= 0 else -v   # the largest lobe at 0 degrees
    z_lo, z_hi = min(bearing_positions.values()), max(bearing_positions.values())

    def side(j):
        z = positions[stations[j]]
        return "left" if z < z_lo - tolerance else "right" if z > z_hi + tolerance else "between"

    # the peak of each lobe; on an end that is not overhung (no disk outboard) the peak between the bearings
    peaks = []
    for start, stop in _lobes(v):
        j = _peak(v, range(start, stop))
        where = side(j)
        if where != "between" and outboard[0 if where == "left" else 1] <= 0:
            inside = [i for i in range(start, stop) if side(i) == "between"]
            if not inside:
                continue
            j = _peak(v, inside)
        peaks.append(j)
    big = max((abs(v[j]) for j in peaks), default=0.0)
    if big <= 0:
        raise ParameterError("placements: the mode shape does not move the stations between the bearings or on an "
                             "overhung end: no place for an unbalance")
    lobes = [j for j in peaks if abs(v[j]) >= LOBE_THRESHOLD * big]
    sides = [side(j) for j in lobes]
    only_between = sides == ["between"]
    unbalances, loads, kinds, words = [], [], [], []
    for j, where in zip(lobes, sides):
        z = positions[stations[j]]
        nearest = min(bearing_positions, key=lambda label: abs(bearing_positions[label] - z))
        if where != "between":
            w, kind, text = outboard[0 if where == "left" else 1], "overhung", "overhung mass outboard of the bearing"
        elif only_between:
            w, kind, text = sum(journal_loads.values()), "mid-span", "sum of the journal loads"
        else:
            w, kind, text = journal_loads[nearest], "between bearings", f"load of the nearest journal ({nearest})"
            if w <= 0:   # an unloaded journal (an overhung rotor can lift one): the rotor's whole weight instead
                w, text = sum(journal_loads.values()), f"sum of the journal loads ({nearest} carries none)"
        angle = 0.0 if v[j] > 0 else math.pi
        unbalances.append(Unbalance(station=stations[j], magnitude=analysis_unbalance(w, max_continuous_speed,
                                                                                        multiple), angle=angle))
        loads.append(float(w))
        kinds.append(kind)
        words.append(f"st. {stations[j]} ({kind}, {math.degrees(angle):.0f} deg): W = {w:.4g} kg, {text}")
    if len(lobes) == 1:
        head = "one lobe: at its largest displacement"
    else:
        same = len({u.angle for u in unbalances}) == 1
        head = f"{len(lobes)} lobes, {'in phase' if same else 'out of phase'}: one unbalance at each lobe's largest " \
               "displacement"
    rule = f"{head}; " + "; ".join(words)
    return Placement(unbalances=tuple(unbalances), loads=tuple(loads), kinds=tuple(kinds), rule=rule)
