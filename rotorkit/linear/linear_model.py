"""A linear rotor model ``M q'' + (C + W G) q' + (K + W H) q = F`` at a swept speed ``W``.

Every frequency-domain analysis (modes at a speed, Campbell diagram,
unbalance response, frequency response functions) works on a
:class:`LinearModel`: mass ``M``, damping ``C``, gyroscopic ``G`` (scaled by
the swept speed), stiffness ``K`` (cross-coupled entries allowed) and a
speed-proportional circulatory stiffness ``H``. Build one

- from matrices (``LinearModel(mass=..., damping=..., stiffness=...)``),
  e.g. a finite-element assembly or a textbook example; or
- from a compiled :class:`~rotorkit.system.System` with
  :func:`linear_model`: the system is linearised (its analytic Jacobian, at
  the static equilibrium, ball-bearing cage positions averaged) at the speed
  ``W0`` and at ``W0 + dW``; the velocity and coordinate blocks give
  ``C + W G`` and ``K + W H`` to first order in the speed, and the mass
  matrix is the constant part of the derived ``M(q)`` (one symbolic
  derivation).

A linear model from a model whose equations are linear keeps the entries
that are not affine in the speed (tabulated, speed-dependent bearing
coefficients) as :class:`SpeedTerms`, evaluated exactly at every speed
where the matrices are used (modes, Campbell, harmonic solves): no
expansion in the speed unless asked for (``speed_dependence="first-order"``).

Each rotor spins at ``offset + ratio * W`` (:attr:`LinearModel.rotor_speeds`):
both spools of a dual rotor follow the swept speed with their own ratio.
"""

from __future__ import annotations

import functools
import numbers
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError
from .stations import station_pairs

__all__ = ["LinearModel", "SpeedTerms", "linear_model"]


def _matrix(value, n, name, default_zero=False):
    if value is None:
        if default_zero:
            return np.zeros((n, n))
        raise ParameterError(f"{name} is required: expected an ({n}, {n}) matrix")
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name}={value!r} is invalid: expected a real ({n}, {n}) matrix") from exc
    if arr.shape != (n, n):
        raise ParameterError(f"{name} has shape {arr.shape}: expected ({n}, {n}), one row per coordinate")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} contains NaN or inf: expected finite entries")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class SpeedTerms:
    """Entries of ``C`` and ``K`` that are not affine in the swept speed, evaluated exactly at each speed.

    A linear model is ``M q'' + (C + W G + dC(W)) q' + (K + W H + dK(W)) q = F``:
    ``dC`` and ``dK`` are zero except at a few entries (a tabulated
    bearing coefficient, piecewise linear in the speed), where they are
    the exact coefficient minus its affine part ``C + W G`` (``K + W H``).

    Parameters
    ----------
    n : int
        Number of coordinates.
    matrix : numpy.ndarray of int, shape (m,)
        1 for an entry of ``C``, 2 for one of ``K``.
    rows, cols : numpy.ndarray of int, shape (m,)
        Positions (an entry may repeat: values at one position add up).
    values : callable
        ``values(W)`` -> numpy.ndarray, shape (m,): the remainders (SI) at
        the swept speed ``W`` (rad/s).
    many : callable, optional
        ``many(W)`` -> numpy.ndarray, shape (k, m): the same at k speeds
        ``W`` (shape (k,)) at once, row ``i`` equal to ``values(W[i])``
        (default: ``values`` at each speed).
    """

    n: int
    matrix: np.ndarray
    rows: np.ndarray
    cols: np.ndarray
    values: object
    many: object = None

    def values_at(self, speeds):
        """The remainders at each of ``speeds`` (rad/s, shape (k,)), shape (k, m); a repeated speed is evaluated once."""
        speeds = np.asarray(speeds, dtype=float).reshape(-1)
        unique, inverse = np.unique(speeds, return_inverse=True)
        if self.many is not None:
            out = np.asarray(self.many(unique), dtype=float)
        else:
            out = np.array([np.asarray(self.values(float(w)), dtype=float) for w in unique])
        return out.reshape(unique.size, self.matrix.size)[inverse.reshape(-1)]

    def __call__(self, speed):
        """``(dC, dK)`` at the swept speed ``speed`` (rad/s), dense, shape (n, n)."""
        v = np.asarray(self.values(float(speed)), dtype=float)
        out = []
        for which in (1, 2):
            A = np.zeros((self.n, self.n))
            mask = self.matrix == which
            np.add.at(A, (self.rows[mask], self.cols[mask]), v[mask])
            out.append(A)
        return tuple(out)

    def pattern(self):
        """Boolean (n, n): where ``dC`` or ``dK`` may be nonzero."""
        P = np.zeros((self.n, self.n), dtype=bool)
        P[self.rows, self.cols] = True
        return P

    def stiffness_only(self):
        """The same terms without the damping entries (None if none are left)."""
        keep = self.matrix == 2
        if not keep.any():
            return None
        values, many = self.values, self.many
        return SpeedTerms(n=self.n, matrix=self.matrix[keep], rows=self.rows[keep], cols=self.cols[keep],
                          values=lambda w: np.asarray(values(w))[keep],
                          many=None if many is None else lambda w: np.asarray(many(w))[:, keep])


@dataclass(frozen=True, eq=False)
class LinearModel:
    """Matrices of ``M q'' + (C + W G) q' + (K + W H) q = F`` (SI units).

    Parameters
    ----------
    mass, damping, stiffness : array_like, shape (n, n)
        ``M`` (kg, kg m^2), ``C`` (N s/m ...), ``K`` (N/m ...); ``K`` may be
        non-symmetric (cross-coupled bearings).
    gyroscopic, circulatory : array_like, shape (n, n), optional
        ``G`` and ``H`` per unit swept speed (default zero).
    coordinate_names : tuple of str, optional
        Default ``q1 ... qn``; bending coordinates named ``x<s>``, ``y<s>``
        make ``<s>`` a station (whirl, orbits, unbalance).
    rotor_speeds : dict, optional
        Rotor name -> ``(offset, ratio)``: spin speed ``offset + ratio * W``
        (rad/s). Default ``{"rotor": (0.0, 1.0)}``.
    station_rotors : dict, optional
        Station -> rotor name (default: every station on the first rotor).
    station_positions : dict, optional
        Station -> axial position (m), for plots along the shaft.
    speed_parameter : str
        Name of the swept speed (for labels), default ``"speed"``.
    speed_terms : SpeedTerms, optional
        Entries not affine in the speed, added exactly at each speed (see
        :class:`SpeedTerms`); None: the matrices are affine in ``W``.
    """

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    gyroscopic: np.ndarray | None = None
    circulatory: np.ndarray | None = None
    coordinate_names: tuple | None = None
    rotor_speeds: dict = field(default_factory=lambda: {"rotor": (0.0, 1.0)})
    station_rotors: dict | None = None
    station_positions: dict | None = None
    speed_parameter: str = "speed"
    speed_terms: SpeedTerms | None = None

    def __post_init__(self):
        try:
            n = int(np.shape(self.mass)[0])
        except (IndexError, TypeError):
            raise ParameterError(f"mass={self.mass!r} is invalid: expected an (n, n) matrix") from None
        set_ = object.__setattr__
        set_(self, "mass", _matrix(self.mass, n, "mass"))
        set_(self, "damping", _matrix(self.damping, n, "damping", default_zero=True))
        set_(self, "stiffness", _matrix(self.stiffness, n, "stiffness"))
        set_(self, "gyroscopic", _matrix(self.gyroscopic, n, "gyroscopic", default_zero=True))
        set_(self, "circulatory", _matrix(self.circulatory, n, "circulatory", default_zero=True))
        if np.linalg.cond(self.mass) > 1e14:
            raise ParameterError("mass is singular: every coordinate needs inertia (a massless station?)")
        names = self.coordinate_names
        if names is None:
            names = tuple(f"q{i + 1}" for i in range(n))
        names = tuple(str(s) for s in names)
        if len(names) != n or len(set(names)) != n:
            raise ParameterError(f"coordinate_names={names!r}: expected {n} distinct names")
        set_(self, "coordinate_names", names)
        speeds = {}
        for rotor, value in dict(self.rotor_speeds).items():
            try:
                offset, ratio = (float(v) for v in value)
            except (TypeError, ValueError):
                raise ParameterError(
                    f"rotor_speeds[{rotor!r}]={value!r} is invalid: expected (offset rad/s, ratio)") from None
            speeds[str(rotor)] = (offset, ratio)
        if not speeds:
            raise ParameterError("rotor_speeds is empty: expected at least one rotor, e.g. {'rotor': (0.0, 1.0)}")
        set_(self, "rotor_speeds", speeds)
        first = next(iter(speeds))
        stations = {s: first for s in self.stations}
        if self.station_rotors is not None:
            for s, r in dict(self.station_rotors).items():
                if str(r) not in speeds:
                    raise ParameterError(f"station_rotors[{s!r}]={r!r} is not a rotor: expected one of {list(speeds)}")
                stations[str(s)] = str(r)
        set_(self, "station_rotors", stations)
        if self.station_positions is not None:
            set_(self, "station_positions", {str(s): float(z) for s, z in dict(self.station_positions).items()})
        if self.speed_terms is not None and not (isinstance(self.speed_terms, SpeedTerms) and self.speed_terms.n == n):
            raise ParameterError(f"speed_terms={self.speed_terms!r} is invalid: expected a SpeedTerms of {n} "
                                 "coordinates or None")

    @property
    def n(self):
        return len(self.coordinate_names)

    @property
    def stations(self):
        """Stations with an ``x<s>`` and a ``y<s>`` coordinate (str), in order."""
        return tuple(s for s, _, _ in station_pairs(self.coordinate_names))

    def station_index(self, station):
        """``(i_x, i_y)`` of a station's coordinates."""
        for s, ix, iy in station_pairs(self.coordinate_names):
            if s == str(station):
                return ix, iy
        raise ParameterError(f"station={station!r} is unknown: expected one of {list(self.stations)}")

    def coordinate_index(self, name):
        try:
            return self.coordinate_names.index(str(name))
        except ValueError:
            raise ParameterError(
                f"coordinate {name!r} is unknown: expected one of {', '.join(self.coordinate_names)}") from None

    def spin_speeds(self, speed):
        """Rotor -> spin speed (rad/s) at the swept speed ``speed`` (scalar or array)."""
        return {r: off + ratio * np.asarray(speed, dtype=float) for r, (off, ratio) in self.rotor_speeds.items()}

    def matrices(self, speed=0.0):
        """``(M, C + W G, K + W H)`` at the swept speed ``W`` (rad/s), plus any :attr:`speed_terms` there."""
        w = speed_si(speed)
        C, K = self.damping + w * self.gyroscopic, self.stiffness + w * self.circulatory
        if self.speed_terms is not None:
            dC, dK = self.speed_terms(w)
            C, K = C + dC, K + dK
        return self.mass, C, K

    def state_matrix(self, speed=0.0):
        """``A = [[0, I], [-M^-1 K, -M^-1 C]]`` at speed ``W``, shape (2n, 2n)."""
        w = speed_si(speed)
        minv_k, minv_h, minv_c, minv_g = self._mass_normalised
        n = self.n
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -(minv_k + w * minv_h) if w else -minv_k
        A[n:, n:] = -(minv_c + w * minv_g) if w else -minv_c
        if self.speed_terms is not None:
            from scipy.linalg import lu_solve

            dC, dK = self.speed_terms(w)
            A[n:, :n] -= lu_solve(self._mass_lu, dK)
            A[n:, n:] -= lu_solve(self._mass_lu, dC)
        return A

    @functools.cached_property
    def _mass_lu(self):
        from scipy.linalg import lu_factor

        return lu_factor(self.mass)

    @functools.cached_property
    def _mass_normalised(self):
        """``M^-1 K, M^-1 H, M^-1 C, M^-1 G``, computed once (one LU of M)."""
        from scipy.linalg import lu_solve

        lu = self._mass_lu
        return tuple(lu_solve(lu, A) for A in (self.stiffness, self.circulatory, self.damping, self.gyroscopic))

    def modes(self, speed=0.0, *, left=True, n_modes=None):
        """:class:`~rotorkit.analysis.modal.Modes` at the swept speed ``speed`` (rad/s).

        ``n_modes``: only the lowest ones (sparse shift-invert solve for large models:
        :func:`~rotorkit.linear.modal.sparse_pays`; dense eigenvalues with the kept modes' vectors below).
        """
        from .modal import modes_from_matrices, modes_from_state_matrix, sparse_pays

        w = speed_si(speed)
        if n_modes is not None and sparse_pays(self.n, n_modes):
            M, C, K, G, H = self._sparse
            C, K = C + w * G, K + w * H
            if self.speed_terms is not None:
                from scipy import sparse

                dC, dK = self.speed_terms(w)
                C, K = C + sparse.csc_matrix(dC), K + sparse.csc_matrix(dK)
            return modes_from_matrices(M, C, K, self.coordinate_names, left=left,
                                       n_modes=n_modes, speed=w, station_positions=self.station_positions)
        return modes_from_state_matrix(self.state_matrix(w), self.coordinate_names, mass=self.mass, left=left,
                                       n_modes=n_modes, speed=w, station_positions=self.station_positions)

    @functools.cached_property
    def _sparse(self):
        """``M, C, K, G, H`` as scipy sparse (CSC) matrices, built once."""
        from scipy import sparse

        return tuple(sparse.csc_matrix(A) for A in (self.mass, self.damping, self.stiffness, self.gyroscopic,
                                                     self.circulatory))


def speed_si(speed, name="speed"):
    """A swept speed in rad/s from a float (rad/s), a pint quantity or a string such as ``"3000 rpm"``."""
    if isinstance(speed, str) or hasattr(speed, "units"):
        from ..units import to_si

        speed = to_si(speed, "rad/s", name)
    if isinstance(speed, bool) or not isinstance(speed, numbers.Real) or not np.isfinite(speed):
        raise ParameterError(f"{name}={speed!r} is invalid: expected a finite speed (rad/s, a pint quantity or a "
                             "string such as '3000 rpm')")
    return float(speed)


def _mass_matrix(system):
    """The constant part of the derived mass matrix at the system's parameters (eccentricities 0)."""
    import sympy as sp

    eqs = system.model.equations()
    M = eqs.linear_mass_matrix()
    values = system.parameters
    subs = {}
    for sym in M.free_symbols:
        name = str(sym)
        subs[sym] = 0.0 if name.endswith("_eccentricity") else values[name]
    return np.array(M.subs(subs).evalf(), dtype=float) if subs else np.array(sp.N(M), dtype=float)


def _speed_parameters(model):
    """``<rotor>_speed`` of every rotor that has its own speed (constant or a speed profile)."""
    return [f"{name}_speed" for name, r in model.rotors.items() if r.speed is not None]


def frozen_system(system, speed_parameter=None, speed=None, t=0.0, who="linear_model"):
    """``(model, speed_parameter)``: the model of a system (or a model) with speed profiles frozen at ``t``.

    A rotor with a :class:`~rotorkit.elements.speed.SpeedProfile` spins at
    its speed at ``t`` (``speed`` instead, if it is the swept rotor), so that
    its ``<rotor>_speed`` becomes a parameter that can be swept.
    """
    from .rotor_speeds import frozen_speed_model

    model = getattr(system, "model", system)
    available = _speed_parameters(model)
    if speed_parameter is None:
        if not available:
            raise ParameterError(f"{who}: {model.name!r} has no rotor with its own speed to sweep")
        speed_parameter = available[0]
    if speed_parameter not in available:
        raise ParameterError(f"{who}: speed_parameter={speed_parameter!r} is not a rotor speed: expected one of "
                             f"{available} (a rotor with a speed profile is swept by <rotor>_speed too)")
    rotor = speed_parameter[: -len("_speed")]
    frozen = model.rotors[rotor].profile is not None or model.rotors[rotor].drive is not None
    given = {rotor: speed} if speed is not None and frozen else None
    return frozen_speed_model(model, t, given), speed_parameter


def linear_model(system, *, speed_parameter=None, speed=None, speed_step=None, t=0.0, equilibrium=True,
                 rub_engaged=None, cage_samples=None, method="auto", speed_dependence="exact"):
    """The :class:`LinearModel` of a compiled system about a swept speed.

    Parameters
    ----------
    system : rotorkit.System or rotorkit.Model
        A model is compiled only if its equations are not linear.
    speed_parameter : str, optional
        The swept rotor speed, ``<rotor>_speed`` (default: the first rotor's).
        A rotor whose speed is a :class:`~rotorkit.elements.speed.SpeedProfile`
        is swept by ``<rotor>_speed`` too: its speed is frozen (see ``speed``).
    speed : float, optional
        Speed ``W0`` (rad/s) of the linearisation. Default: the system's value,
        or for a speed profile its speed at time ``t``.
    speed_step : float, optional
        ``dW`` for the speed derivatives (default ``max(1, 0.01 |W0|)`` rad/s).
    t, equilibrium, rub_engaged, cage_samples, method
        As in :func:`rotorkit.analysis.modes.natural_frequencies` (``t`` also
        picks the speed of a speed profile).
    speed_dependence : {"exact", "first-order"}
        For a model whose equations are linear: ``"exact"`` (default) keeps
        the entries that are not affine in the speed (tabulated bearing
        coefficients) as :class:`SpeedTerms`, evaluated exactly at every
        speed; ``"first-order"`` drops them for the expansion
        ``C(W0) + (W - W0) dC/dW`` (``K`` likewise) about ``W0``, an
        approximation away from ``W0``. A linearised model (contacts,
        Hertzian bearings) is always first order in the speed.

    Returns
    -------
    LinearModel
        When every force of the model is linear in the coordinates and
        their rates, the matrices are the derived symbolic ones evaluated
        numerically (:func:`~rotorkit.analysis.linear_matrices.linear_evaluator`,
        no equilibrium or Jacobian needed): ``G`` and ``H`` are their exact
        speed derivatives for gyroscopics and constant bearings, and
        speed-dependent coefficients are exact at every speed
        (:attr:`LinearModel.speed_terms`). Otherwise (contacts, Hertzian
        bearings) the system is linearised at its static equilibrium at
        ``W0`` and ``W0 + dW``: ``G = dC/dW`` and ``H = dK/dW`` at ``W0``, a
        first-order model for speed-dependent bearings (re-linearise far
        from ``W0``).
    """
    from .linear_matrices import linear_evaluator
    from .rotor_speeds import rotor_spin_speeds
    from .station_positions import station_positions

    if not (hasattr(system, "compile") and hasattr(system, "equations")):
        from .linearize import check_system

        check_system(system, "linear_model")
    model, speed_parameter = frozen_system(system, speed_parameter, speed, t)
    values = model.parameters
    w0 = values[speed_parameter] if speed is None else speed_si(speed)
    dw = max(1.0, 0.01 * abs(w0)) if speed_step is None else speed_si(speed_step, "speed_step")
    if dw <= 0:
        raise ParameterError(f"speed_step={speed_step!r} is invalid: expected a positive speed step (rad/s)")
    if speed_dependence not in ("exact", "first-order"):
        raise ParameterError(f"speed_dependence={speed_dependence!r} is unknown: expected 'exact' or 'first-order'")
    points = [dict(values, **{speed_parameter: float(w)}) for w in (w0, w0 + dw)]
    spins = [rotor_spin_speeds(model, t, v) for v in points]
    evaluator = linear_evaluator(model, t, values, free=(speed_parameter,))
    terms = None
    if evaluator is not None:
        (M, C0, K0), (_, C1, K1) = (evaluator.dense(**{speed_parameter: w}) for w in (w0, w0 + dw))
        G, H = (C1 - C0) / dw, (K1 - K0) / dw
        C, K = C0 - w0 * G, K0 - w0 * H
        if speed_dependence == "exact":
            terms = _speed_terms(evaluator, speed_parameter, w0, dw)
    else:  # not linear: the compiled system linearised at its equilibrium (modes imported only here)
        from .modes import DEFAULT_CAGE_SAMPLES, averaged_jacobian

        source = getattr(system, "model", system)
        target = system if model is source and hasattr(system, "rhs") else model.compile(
            backend=getattr(system, "backend", "auto"))
        samples = DEFAULT_CAGE_SAMPLES if cage_samples is None else cage_samples
        n = len(target.coordinate_names)
        blocks = []
        for w in (w0, w0 + dw):
            point = target.with_parameters(**{speed_parameter: float(w)})
            A = averaged_jacobian(point, t=t, equilibrium=equilibrium, rub_engaged=rub_engaged, unbalance=False,
                                  cage_samples=samples, eps=None, method=method)[0]
            blocks.append((-A[n:, :n], -A[n:, n:]))
        M = _mass_matrix(target)
        (K0, C0), (K1, C1) = blocks
        G, H = M @ (C1 - C0) / dw, M @ (K1 - K0) / dw
        C, K = M @ C0 - w0 * G, M @ K0 - w0 * H
    rotor_speeds = {}
    for r in spins[0]:
        ratio = (spins[1][r] - spins[0][r]) / dw
        rotor_speeds[r] = (spins[0][r] - ratio * w0, ratio)
    names = tuple(model.coordinate_names)
    bending = {p[0] for p in station_pairs(names)}
    return LinearModel(
        mass=M, damping=C, stiffness=K, gyroscopic=G, circulatory=H, coordinate_names=names,
        rotor_speeds=rotor_speeds,
        station_rotors={str(s): model.rotor_of(s).name for s in model.stations if str(s) in bending},
        station_positions=station_positions(model), speed_parameter=speed_parameter, speed_terms=terms,
    )


def _speed_terms(evaluator, speed_parameter, w0, dw):
    """:class:`SpeedTerms` of the entries of ``evaluator`` not affine in the speed, or None if there are none.

    Each such entry ``v(W)`` went into ``C + W G`` (``K + W H``) as
    ``v(W0) + (W - W0) (v(W0 + dW) - v(W0)) / dW``; the remainder is ``v(W)``
    minus that, so that the sum is ``v(W)`` exactly.
    """
    mask = evaluator.nonaffine & (evaluator.variable_entries[0] > 0)
    if not mask.any():
        return None
    which, rows, cols = (a[mask] for a in evaluator.variable_entries)
    values = evaluator.entries_function(mask)
    many = evaluator.entries_function_many(mask)
    v0 = values([w0])
    slope = (values([w0 + dw]) - v0) / dw

    def remainder(w):
        return values([w]) - v0 - (w - w0) * slope

    def remainders(speeds):
        speeds = np.asarray(speeds, dtype=float).reshape(-1)
        return many([speeds]) - v0 - (speeds[:, None] - w0) * slope

    return SpeedTerms(n=evaluator.n, matrix=which, rows=rows, cols=cols, values=remainder, many=remainders)
