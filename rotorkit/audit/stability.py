"""API 617 Level I stability: log decrement of the first forward mode against an applied cross-coupling.

A cross-coupled stiffness ``Q`` (``Fx = -Q y``, ``Fy = +Q x``: a force
along the forward whirl, destabilising) is added at the chosen stations
(the rotor mid-span, or the impellers, ``Q`` shared equally) of the rotor
at its maximum continuous speed; the log decrement of the first forward
mode is followed from ``Q = 0`` to ``10 Q_A`` (API 617 8th ed., 4.8) and
``Q_0``, where it reaches zero, is located by root finding. The screening
criteria (API 617, API 684): Level II is required when
``Q_0 / Q_A < 2`` or the log decrement at ``Q_A`` is below 0.1; the critical
speed ratio / gas density region chart is not evaluated here.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["Level1Stability", "level1_stability", "forward_fraction", "MIN_LOG_DECREMENT", "MIN_Q_RATIO"]

#: the log decrement at Q_A below which API 617 asks a Level II analysis
MIN_LOG_DECREMENT = 0.1
#: the Q_0 / Q_A below which API 617 asks a Level II analysis
MIN_Q_RATIO = 2.0


def forward_fraction(shapes, names):
    """Per mode (column of ``shapes``): ``sum |F|^2 / sum (|F|^2 + |B|^2)`` over the stations' orbits.

    ``F = (X + i Y) / 2`` and ``B = conj(X - i Y) / 2`` are the forward and
    backward circular components of each station's orbit; above 0.5 the
    mode whirls mostly forward.
    """
    from ..linear.whirl import station_pairs

    shapes = np.asarray(shapes, dtype=complex)
    fwd = np.zeros(shapes.shape[1])
    bwd = np.zeros(shapes.shape[1])
    for _, ix, iy in station_pairs(tuple(names)):
        X, Y = shapes[ix], shapes[iy]
        fwd += np.abs(X + 1j * Y) ** 2
        bwd += np.abs(X - 1j * Y) ** 2
    total = fwd + bwd
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total > 0, fwd / total, 0.5)


@dataclass(frozen=True, eq=False)
class Level1Stability:
    """Log decrement of the first forward mode against the applied cross-coupling.

    Attributes
    ----------
    cross_coupling : numpy.ndarray, shape (n,)
        Applied ``Q`` (N/m), from 0 to ``10 Q_A``.
    log_decrements : numpy.ndarray, shape (n,)
        Log decrement of the first forward mode at each ``Q``.
    frequencies : numpy.ndarray, shape (n,)
        Its damped natural frequency (rad/s).
    q_a : float
        Anticipated cross-coupling ``Q_A`` (N/m).
    log_decrement_a : float
        Log decrement at ``Q_A``.
    q_0 : float
        ``Q`` (N/m) where the log decrement is zero (``inf`` if it never is,
        0 if the mode is unstable already).
    speed : float
        Rotor speed (rad/s) of the analysis.
    stations : tuple of str
        Where ``Q`` is applied (shared equally).
    """

    cross_coupling: np.ndarray
    log_decrements: np.ndarray
    frequencies: np.ndarray
    q_a: float
    log_decrement_a: float
    q_0: float
    speed: float
    stations: tuple

    @property
    def q_ratio(self):
        """``Q_0 / Q_A`` (inf when ``Q_A`` is 0)."""
        return math.inf if self.q_a == 0 else self.q_0 / self.q_a

    @property
    def passed(self):
        """Level I screening met: ``Q_0 / Q_A >= 2`` and log decrement at ``Q_A`` >= 0.1 (else Level II)."""
        return self.q_ratio >= MIN_Q_RATIO and self.log_decrement_a >= MIN_LOG_DECREMENT

    def to_csv(self, path=None):
        """``Q`` (N/m), log decrement and frequency (rad/s) per row; text, or written to ``path``."""
        from ..linear.tables import csv_output

        rows = ["cross_coupling_N_m,log_decrement,frequency_rad_s"]
        rows += [f"{q:.10g},{d:.10g},{f:.10g}" for q, d, f in
                 zip(self.cross_coupling, self.log_decrements, self.frequencies)]
        return csv_output("\n".join(rows) + "\n", path)

    def plot(self, ax=None):
        """Log decrement against ``Q`` with ``Q_A`` and ``Q_0`` marked; the axes."""
        import matplotlib.pyplot as plt

        ax = plt.gca() if ax is None else ax
        ax.plot(self.cross_coupling / 1e6, self.log_decrements, "-o", ms=3, label="first forward mode")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.axhline(MIN_LOG_DECREMENT, color="tab:red", lw=0.8, ls=":", label="0.1 (API 617)")
        ax.plot([self.q_a / 1e6], [self.log_decrement_a], "s", color="tab:orange",
                label=f"Q_A = {self.q_a / 1e6:.3g} MN/m")
        if math.isfinite(self.q_0):
            ax.plot([self.q_0 / 1e6], [0.0], "D", color="tab:red", label=f"Q_0 = {self.q_0 / 1e6:.3g} MN/m")
        ax.set_xlabel("applied cross-coupling Q (MN/m)")
        ax.set_ylabel("log decrement")
        ax.legend(fontsize=8)
        return ax


def _coupling(n, indices, q):
    K = np.zeros((n, n))
    share = q / len(indices)
    for ix, iy in indices:
        K[ix, iy] += share
        K[iy, ix] -= share
    return K


def level1_stability(linear, speed, q_a, stations, *, points=11, n_modes=8, rtol=1e-6):
    """Level I stability of ``linear`` at ``speed`` (API 617 8th ed., 4.8).

    Parameters
    ----------
    linear : rotorkit.linear.linear_model.LinearModel
        The rotor on its bearings (seals and aerodynamic terms left out, as
        Level I asks).
    speed : float, str or pint.Quantity
        Maximum continuous speed (rad/s or e.g. ``"10000 rpm"``).
    q_a : float, str or pint.Quantity
        Anticipated cross-coupling ``Q_A`` (N/m), e.g. from
        :func:`~rotorkit.audit.formulas.wachel_cross_coupling`; >= 0.
    stations : sequence of station
        Where ``Q`` is applied: the mid-span station of a between-bearing
        rotor, or the impeller stations (``Q`` shared equally).
    points : int
        Values of ``Q`` from 0 to ``10 Q_A`` (>= 2).
    n_modes : int
        Lowest modes computed at each ``Q``.
    rtol : float
        Relative tolerance of ``Q_0``.

    Returns
    -------
    Level1Stability

    Notes
    -----
    The first forward mode is the lowest one at ``Q = 0`` whose orbits whirl
    mostly forward (:func:`forward_fraction` > 0.5), followed as ``Q`` grows
    by its modal assurance criterion with the previous shape.
    """
    from scipy.optimize import brentq

    from ..linear.campbell import mac
    from ..linear.linear_model import LinearModel
    from ..units import to_si

    if not isinstance(linear, LinearModel):
        raise TypeError(f"level1_stability: expected a LinearModel, got {type(linear).__name__}")
    w = to_si(speed, "rad/s", "speed")
    qa = to_si(q_a, "N/m", "q_a")
    if not (math.isfinite(qa) and qa >= 0):
        raise ParameterError(f"q_a={q_a!r} is invalid: expected a cross-coupling >= 0 (N/m)")
    stations = tuple(str(s) for s in (stations if isinstance(stations, (list, tuple)) else [stations]))
    if not stations:
        raise ParameterError("stations=() is empty: expected the station(s) where the cross-coupling acts")
    indices = [linear.station_index(s) for s in stations]
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise ParameterError(f"points={points!r} is invalid: expected an integer >= 2")
    k = min(int(n_modes), linear.n)
    base = linear.modes(w, n_modes=k, left=False)
    forward = np.flatnonzero(forward_fraction(base.shapes, base.coordinate_names) > 0.5)
    if forward.size == 0:
        raise ParameterError(f"level1_stability: no forward-whirling mode among the {k} lowest at {w:g} rad/s; "
                             "give a larger n_modes")
    state = {"shape": base.shapes[:, forward[0]]}

    def first_forward(q):
        model = dataclasses.replace(linear, stiffness=linear.stiffness + _coupling(linear.n, indices, q))
        modes = model.modes(w, n_modes=k, left=False)
        j = int(np.argmax(mac(state["shape"][:, None], modes.shapes)[0]))
        return modes, j

    def log_dec(q, keep=False):
        modes, j = first_forward(q)
        if keep:
            state["shape"] = modes.shapes[:, j]
        return float(modes.log_decrements[j]), float(modes.damped_frequencies[j])

    top = 10.0 * qa
    grid = np.linspace(0.0, top, points) if top > 0 else np.zeros(1)
    values, shapes = [], []
    for q in grid:
        values.append(log_dec(q, keep=True))
        shapes.append(state["shape"])
    deltas = np.array([v[0] for v in values])
    freqs = np.array([v[1] for v in values])
    on_grid = np.flatnonzero(np.isclose(grid, qa, rtol=1e-12, atol=0.0))
    if on_grid.size:
        delta_a = float(deltas[on_grid[0]])
    else:  # Q_A between grid points (points chosen so): from the shape at the point below
        state["shape"] = shapes[int(np.searchsorted(grid, qa)) - 1]
        delta_a = log_dec(qa)[0]
    # Q_0: the first sign change on the grid, else extend by doubling
    if deltas[0] <= 0:
        q0 = 0.0
    else:
        change = np.flatnonzero(deltas <= 0)
        if change.size:
            lo, hi = grid[change[0] - 1], grid[change[0]]
            state["shape"] = shapes[change[0] - 1]
        else:
            state["shape"] = base.shapes[:, forward[0]]
            lo = grid[-1]
            scale = np.max(np.abs(np.diag(linear.stiffness)))
            hi = max(2.0 * lo, 1e-3 * scale)
            for _ in range(60):
                if log_dec(hi, keep=True)[0] <= 0:
                    break
                lo, hi = hi, 2.0 * hi
            else:
                hi = math.inf
        q0 = math.inf if math.isinf(hi) else float(brentq(lambda q: log_dec(q)[0], lo, hi, rtol=rtol,
                                                            xtol=1e-12 * max(hi, 1.0)))
    for a in (grid, deltas, freqs):
        a.setflags(write=False)
    return Level1Stability(cross_coupling=grid, log_decrements=deltas, frequencies=freqs, q_a=float(qa),
                           log_decrement_a=float(delta_a), q_0=q0, speed=w, stations=stations)
