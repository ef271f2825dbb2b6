"""Loads on a station over time (the paper's Fig. 7: manoeuvre load plus gravity on disk 2)."""

from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..elements import Maneuver
from ..errors import ParameterError

__all__ = ["StationLoad", "maneuver_load"]


@dataclass(frozen=True)
class StationLoad:
    """Force of the load field (manoeuvre and gravity) on one station's mass.

    Attributes
    ----------
    t : numpy.ndarray
        Times (s).
    fx, fy : numpy.ndarray
        Force components in the rotor frame (N); ``y`` points up.
    station : int or str
    """

    t: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    station: object

    @property
    def magnitude(self):
        """|F| (N)."""
        return np.hypot(self.fx, self.fy)

    def plot(self, ax=None):
        """Fx, Fy and |F| against time; returns the Axes."""
        from ..plotting.basic import legend_beside, new_axes

        ax = new_axes(ax, figsize=(7.0, 3.5))
        for values, label in ((self.fx, "$F_x$"), (self.fy, "$F_y$"), (self.magnitude, "$|F|$")):
            ax.plot(self.t, values, label=label)
        ax.set_xlabel("t (s)")
        ax.set_ylabel(f"load on station {self.station} (N)")
        ax.set_title(f"inertial load on station {self.station}: components and magnitude", fontsize=10)
        legend_beside(ax)
        return ax


def maneuver_load(model, station, t):
    """The manoeuvre and gravity force on the mass at ``station`` at times ``t``.

    Parameters
    ----------
    model : rotorkit.Model
    station : int or str
    t : array_like
        Times (s).

    Returns
    -------
    StationLoad
    """
    maneuvers = [e for e in model.elements if isinstance(e, Maneuver)]
    if not maneuvers:
        raise ParameterError(f"{model.name}: holds no Maneuver (no gravity or manoeuvre load)")
    if station not in model.stations:
        raise ParameterError(f"station {station!r} is not in {model.name} (stations: {list(model.stations)})")
    maneuver = maneuvers[0]
    ts = sp.Symbol("t", real=True)
    p = {f: v for f, v in maneuver.parameters().items()}
    ax, ay = maneuver.acceleration(ts, p)
    modules = [{"window": lambda tt, a, b: np.where((tt >= a) & (tt < b), 1.0, 0.0),
                "Min": np.minimum, "Max": np.maximum}, "numpy"]
    t = np.asarray(t, dtype=float)
    mass = sum(e.mass for e in dict(model.masses())[station])
    fx = mass * np.broadcast_to(sp.lambdify(ts, ax, modules=modules)(t), t.shape)
    fy = mass * np.broadcast_to(sp.lambdify(ts, ay, modules=modules)(t), t.shape)
    return StationLoad(t=t, fx=np.array(fx, dtype=float), fy=np.array(fy, dtype=float), station=station)
