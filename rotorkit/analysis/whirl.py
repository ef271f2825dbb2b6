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
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["Orbit", "orbit", "whirl_direction", "station_pairs", "FORWARD", "BACKWARD", "MIXED", "LINEAR"]

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


def orbit(X, Y):
    """The :class:`Orbit` of complex amplitudes ``X``, ``Y`` (arrays broadcast)."""
    X, Y = np.asarray(X, dtype=complex), np.asarray(Y, dtype=complex)
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


def mode_whirl(directions, sizes):
    """One mode's whirl from its stations' directions and orbit sizes."""
    sizes = np.asarray(sizes, dtype=float)
    if sizes.size == 0 or not np.any(sizes > 0):
        return LINEAR
    keep = sizes >= SIGNIFICANT * sizes.max()
    kinds = {d for d, k in zip(directions, keep) if k and d != LINEAR}
    if not kinds:
        return LINEAR
    return kinds.pop() if len(kinds) == 1 else MIXED


def station_pairs(names):
    """``[(station, i_x, i_y)]`` of the stations with both an ``x<s>`` and a ``y<s>`` coordinate, in order."""
    index = {name: i for i, name in enumerate(names)}
    out = []
    for name in names:
        m = re.fullmatch(r"x(.+)", name)
        if m and f"y{m.group(1)}" in index:
            out.append((m.group(1), index[name], index[f"y{m.group(1)}"]))
    return out
