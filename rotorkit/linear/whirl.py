"""Whirl of a station: forward and backward circular components, orbit ellipse.

A station moving as ``x = Re(X e^{i w t})``, ``y = Re(Y e^{i w t})`` (``X``,
``Y`` complex amplitudes, ``w > 0``) traces an ellipse. Written as a complex
position ``z = x + i y`` it is the sum of two circles::

    z = F e^{i w t} + B e^{-i w t},   F = (X + i Y) / 2,   B = conj(X - i Y) / 2

``|F|`` is the forward component (whirling from x towards y, the direction
of a positive spin), ``|B|`` the backward one. The ellipse has semi-major
axis ``|F| + |B|``, semi-minor axis ``||F| - |B||`` and its major axis at
the angle ``(arg F + arg B) / 2`` from x. The whirl is forward when
``|F| > |B|``, backward when ``|B| > |F|`` and a straight line when they are
equal.

A station that tilts (``thx<s>``, ``thy<s>``: beam nodes, gyroscopic
disks) also whirls in its slope: the shaft axis there points along
``(dx/dz, dy/dz) = (thy, -thx)``, an orbit like the displacement one
(:func:`tilt_pairs`). It is what shows the whirl of a station that only
tilts (a disk at the node of a conical mode). The whirl of a mode counts
the displacement orbits and the slope orbits times a reference length
(the span of the station positions, else 1 m) together; the ones below
:data:`SIGNIFICANT` of the largest are ignored.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .stations import station_pairs, tilt_pairs  # their home; given here as before

__all__ = ["Orbit", "orbit", "whirl_direction", "station_pairs", "tilt_pairs", "shape_whirl", "reference_length",
           "FORWARD", "BACKWARD", "MIXED", "LINEAR"]

FORWARD, BACKWARD, MIXED, LINEAR = "forward", "backward", "mixed", "linear"
#: |F| and |B| within this relative margin: a straight-line (planar) orbit
LINEAR_RTOL = 1e-6
#: stations whose orbit is below this fraction of the largest are ignored for a mode's whirl
SIGNIFICANT = 1e-2


@dataclass(frozen=True, slots=True)
class Orbit:
    """Elliptic orbit(s) of a station (arrays broadcast over speeds or modes).

    Attributes
    ----------
    forward, backward : numpy.ndarray
        Radii ``|F|``, ``|B|`` of the forward and backward circles (m, or
        relative for a mode shape).
    major, minor : numpy.ndarray
        Semi-axes ``|F| + |B|`` and ``||F| - |B||``.
    inclination : numpy.ndarray
        Angle of the major axis from x (rad), in (-pi/2, pi/2].
    """

    forward: np.ndarray
    backward: np.ndarray
    major: np.ndarray
    minor: np.ndarray
    inclination: np.ndarray

    @property
    def direction(self):
        """``"forward"``, ``"backward"`` or ``"linear"`` (str, or an array of them)."""
        return whirl_direction(self.forward, self.backward)

    def points(self, n=100):
        """``(x, y)`` of the orbit sampled over one period, shapes ``(..., n)``."""
        tau = np.linspace(0.0, 2.0 * np.pi, n)
        a = np.asarray(self.major)[..., None]
        b = np.asarray(self.minor)[..., None] * np.where(
            np.asarray(self.forward) >= np.asarray(self.backward), 1.0, -1.0)[..., None]
        th = np.asarray(self.inclination)[..., None]
        u, v = a * np.cos(tau), b * np.sin(tau)
        return u * np.cos(th) - v * np.sin(th), u * np.sin(th) + v * np.cos(th)


def _amplitudes(X, Y):
    """``X``, ``Y`` as complex arrays in SI units: pint quantities of one dimension are converted (µm -> m)."""
    from ..units import is_quantity

    if is_quantity(X) or is_quantity(Y):
        from ..errors import UnitError

        if not (is_quantity(X) and is_quantity(Y)) or X.dimensionality != Y.dimensionality:
            raise UnitError(f"orbit: X = {X!r} and Y = {Y!r} must be quantities of one dimension (or both numbers)")
        X, Y = X.to_base_units().magnitude, Y.to_base_units().magnitude
    return np.asarray(X, dtype=complex), np.asarray(Y, dtype=complex)


def orbit(X, Y):
    """The :class:`Orbit` of complex amplitudes ``X``, ``Y`` (arrays broadcast).

    Numbers (m, rad, or relative for a mode shape) or pint quantities of one
    dimension, converted to SI (the orbit is then in m or rad).
    """
    X, Y = _amplitudes(X, Y)
    F = (X + 1j * Y) / 2.0
    B = np.conj(X - 1j * Y) / 2.0
    f, b = np.abs(F), np.abs(B)
    inclination = (np.angle(F) + np.angle(B)) / 2.0
    inclination = np.where(inclination > np.pi / 2, inclination - np.pi, inclination)
    inclination = np.where(inclination <= -np.pi / 2, inclination + np.pi, inclination)
    return Orbit(forward=f, backward=b, major=f + b, minor=np.abs(f - b), inclination=inclination)


def whirl_direction(forward, backward, rtol=LINEAR_RTOL):
    """``"forward"``, ``"backward"`` or ``"linear"`` from the circle radii (scalars or arrays)."""
    f, b = np.asarray(forward, dtype=float), np.asarray(backward, dtype=float)
    margin = rtol * np.maximum(f + b, np.finfo(float).tiny)
    out = np.where(f - b > margin, FORWARD, np.where(b - f > margin, BACKWARD, LINEAR))
    return str(out) if out.ndim == 0 else out


def slope_orbit(thx, thy):
    """The :class:`Orbit` of the shaft slope ``(dx/dz, dy/dz) = (thy, -thx)`` from tilt amplitudes (rad)."""
    return orbit(np.asarray(thy, dtype=complex), -np.asarray(thx, dtype=complex))


def reference_length(positions):
    """The length (m) that weighs a tilt (rad) against a displacement: the span of the station positions, else 1 m."""
    if positions:
        span = max(positions.values()) - min(positions.values())
        if span > 0:
            return float(span)
    return 1.0


def shape_whirl(shapes, names, positions=None):
    """Whirl of each mode and of each station, from mode shapes.

    Parameters
    ----------
    shapes : numpy.ndarray of complex, shape (n, k)
        Mode shapes (columns), coordinates in ``names`` order.
    names : tuple of str, length n
    positions : dict, optional
        Station -> axial position (m); their span is the reference length
        that weighs slopes against displacements (default 1 m).

    Returns
    -------
    modes : tuple of str, length k
        ``"forward"``, ``"backward"``, ``"mixed"`` or ``"linear"``.
    stations : dict of str to numpy.ndarray of str, shape (k,)
        Station -> the whirl of its displacement orbit in each mode, or of
        its slope orbit where the displacement is insignificant and the
        slope is not.
    """
    shapes = np.asarray(shapes, dtype=complex)
    k = shapes.shape[1]
    pairs, tilts = station_pairs(names), tilt_pairs(names)
    length = reference_length(positions)
    kinds, sizes, owners = [], [], []
    for group, scale, make in ((pairs, 1.0, orbit), (tilts, length, slope_orbit)):
        if group:
            i1 = np.array([p[1] for p in group])
            i2 = np.array([p[2] for p in group])
            o = make(shapes[i1], shapes[i2])
            kinds.append(np.atleast_2d(whirl_direction(o.forward, o.backward)))
            sizes.append(o.major * scale)
            owners.append([p[0] for p in group])
        else:
            kinds.append(np.empty((0, k), dtype="<U8"))
            sizes.append(np.empty((0, k)))
            owners.append([])
    allsize = np.vstack(sizes) if k else np.empty((0, 0))
    allkind = np.vstack(kinds) if k else np.empty((0, 0), dtype="<U8")
    largest = allsize.max(axis=0) if allsize.size else np.zeros(k)
    significant = (allsize >= SIGNIFICANT * largest) & (allsize > 0) & (allkind != LINEAR)
    fwd = np.any(significant & (allkind == FORWARD), axis=0)
    bwd = np.any(significant & (allkind == BACKWARD), axis=0)
    modes = tuple(MIXED if f and b else FORWARD if f else BACKWARD if b else LINEAR for f, b in zip(fwd, bwd))
    stations = {s: kinds[0][i] for i, s in enumerate(owners[0])}
    n_disp = len(owners[0])
    for j, s in enumerate(owners[1]):
        if s not in stations:
            continue
        use_tilt = ~significant[owners[0].index(s)] & significant[n_disp + j]
        stations[s] = np.where(use_tilt, kinds[1][j], stations[s])
    return modes, stations
