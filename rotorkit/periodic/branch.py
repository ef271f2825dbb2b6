"""The result of a continuation: periodic solutions along a branch, their stability and bifurcations."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["Branch", "Bifurcation", "load_branch"]


@dataclass(frozen=True)
class Bifurcation:
    """A bifurcation located between two points of a branch.

    Attributes
    ----------
    kind : str
        ``"fold"`` (a smooth turning point of the parameter: a multiplier through +1), ``"grazing fold"``
        (the branch turns back at a corner where the contact set changes: an orbit grazing a stator),
        ``"period doubling"`` (a multiplier through -1) or ``"Neimark-Sacker"`` (a complex pair).
    index : int
        The point after which it lies.
    parameter : float
        Its location (SI) between points ``index`` and ``index + 1``: a fold at the vertex of the parabola
        through the points around it, a grazing fold and a multiplier crossing solved on the branch
        (:mod:`rotorkit.periodic.folds`, :mod:`rotorkit.periodic.crossings`).
    """

    kind: str
    index: int
    parameter: float


@dataclass(frozen=True, eq=False)
class Branch:
    """Periodic steady states along a branch (harmonic balance and continuation).

    Attributes
    ----------
    parameter_name : str
        The continuation parameter.
    parameter : numpy.ndarray, shape (n_points,)
        Its values along the branch (SI), in arclength order (may turn back at folds).
    coefficients : numpy.ndarray, shape (n_points, 2H + 1, n)
        Fourier coefficients ``a_0, a_1, b_1, ..., a_H, b_H`` of each coordinate (m, rad):
        ``q(t) = a_0 + sum_k a_k cos(k w t) + b_k sin(k w t)``.
    omega : numpy.ndarray, shape (n_points,)
        Base frequency ``w = Omega / nu`` (rad/s).
    coordinate_names : tuple of str
    speed_parameter : str
    harmonics, subharmonic, samples : int
        ``H``, ``nu`` and the AFT samples ``N``.
    multipliers : numpy.ndarray of complex, shape (n_points, 2n), or None
        Floquet multipliers (None if stability was not computed).
    stable : numpy.ndarray of bool, shape (n_points,), or None
    bifurcations : tuple of Bifurcation
    residual_error : numpy.ndarray, shape (n_points,)
        Truncation error estimate: max |M (q'' - a)| on a grid 4 times finer than the AFT one, relative to
        the residual scale (the largest oscillating force at rest).
    harmonic_share : numpy.ndarray, shape (n_points,)
        Largest amplitude of harmonic ``H`` over the largest amplitude of any harmonic >= 1.
    reason : str
        Why the continuation stopped.
    stability_method : str
        ``"hill"``, ``"monodromy"`` or ``"none"``.
    """

    parameter_name: str
    parameter: np.ndarray
    coefficients: np.ndarray
    omega: np.ndarray
    coordinate_names: tuple
    speed_parameter: str
    harmonics: int
    subharmonic: int
    samples: int
    multipliers: np.ndarray | None
    stable: np.ndarray | None
    bifurcations: tuple
    residual_error: np.ndarray
    harmonic_share: np.ndarray
    reason: str
    stability_method: str = "none"

    def __len__(self):
        return len(self.parameter)

    def _point(self, i):
        n = len(self.parameter)
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise ParameterError(f"i={i!r} is invalid: expected a point index in [{-n}, {n})")
        return int(i) % n

    def coordinate_index(self, name):
        try:
            return self.coordinate_names.index(str(name))
        except ValueError:
            raise ParameterError(f"coordinate {name!r} is unknown: expected one of "
                                 f"{', '.join(self.coordinate_names)}") from None

    def _station(self, station):
        return self.coordinate_index(f"x{station}"), self.coordinate_index(f"y{station}")

    def signal(self, i, coordinate, samples=256):
        """``(t, q)``: one base period of ``coordinate`` at point ``i`` (s; m or rad), ``samples`` instants."""
        i = self._point(i)
        c = self.coordinate_index(coordinate)
        t = 2.0 * np.pi * np.arange(samples + 1) / (samples * self.omega[i])
        return t, self._synthesis(self.omega[i] * t) @ self.coefficients[i, :, c]

    def _synthesis(self, tau):
        E = np.ones((len(tau), 2 * self.harmonics + 1))
        for k in range(1, self.harmonics + 1):
            E[:, 2 * k - 1], E[:, 2 * k] = np.cos(k * tau), np.sin(k * tau)
        return E

    def orbit(self, i, station, samples=256):
        """``(x, y)`` of ``station`` over one base period at point ``i`` (m), ``samples + 1`` points (closed)."""
        i = self._point(i)
        ix, iy = self._station(station)
        tau = 2.0 * np.pi * np.arange(samples + 1) / samples
        E = self._synthesis(tau)
        return E @ self.coefficients[i, :, ix], E @ self.coefficients[i, :, iy]

    def max_radius(self, station, samples=512):
        """Largest ``sqrt(x^2 + y^2)`` of ``station`` over the orbit at each point (m), shape (n_points,)."""
        ix, iy = self._station(station)
        E = self._synthesis(2.0 * np.pi * np.arange(samples) / samples)
        x = np.einsum("jc,pc->pj", E, self.coefficients[:, :, ix])
        y = np.einsum("jc,pc->pj", E, self.coefficients[:, :, iy])
        return np.max(np.hypot(x, y), axis=1)

    def harmonic_amplitude(self, coordinate, k):
        """``|a_k - i b_k|`` of harmonic ``k`` (0 ... H) of ``coordinate`` at each point (m, rad)."""
        c = self.coordinate_index(coordinate)
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k <= self.harmonics:
            raise ParameterError(f"k={k!r} is invalid: expected a harmonic 0 ... {self.harmonics}")
        if k == 0:
            return np.abs(self.coefficients[:, 0, c])
        return np.hypot(self.coefficients[:, 2 * k - 1, c], self.coefficients[:, 2 * k, c])

    def complex_amplitude(self, coordinate, k):
        """``a_k - i b_k``: the coordinate's harmonic ``k`` is ``Re(Q e^{i k w t})`` (m, rad)."""
        c = self.coordinate_index(coordinate)
        if k == 0:
            return self.coefficients[:, 0, c].astype(complex)
        self.harmonic_amplitude(coordinate, k)
        return self.coefficients[:, 2 * k - 1, c] - 1j * self.coefficients[:, 2 * k, c]

    def to_xarray(self):
        """An :class:`xarray.Dataset` with dimensions ``point``, ``coefficient``, ``coordinate``, ``multiplier``."""
        import xarray as xr

        names = ["a0"] + [f"{ab}{k}" for k in range(1, self.harmonics + 1) for ab in "ab"]
        data = {
            self.parameter_name: ("point", np.asarray(self.parameter), {"long_name": "continuation parameter"}),
            "omega": ("point", np.asarray(self.omega), {"units": "rad/s", "long_name": "base frequency"}),
            "coefficients": (("point", "coefficient", "coordinate"), np.asarray(self.coefficients),
                             {"long_name": "Fourier coefficients (m, rad)"}),
            "residual_error": ("point", np.asarray(self.residual_error), {"units": "1"}),
            "harmonic_share": ("point", np.asarray(self.harmonic_share), {"units": "1"}),
        }
        if self.multipliers is not None:
            data["multipliers_real"] = (("point", "multiplier"), self.multipliers.real)
            data["multipliers_imag"] = (("point", "multiplier"), self.multipliers.imag)
            data["stable"] = ("point", self.stable.astype(np.int8))
        attrs = {
            "parameter_name": self.parameter_name, "speed_parameter": self.speed_parameter,
            "harmonics": self.harmonics, "subharmonic": self.subharmonic, "samples": self.samples,
            "reason": self.reason, "stability_method": self.stability_method,
            "bifurcation_kinds": ";".join(b.kind for b in self.bifurcations),
            "bifurcation_indices": np.array([b.index for b in self.bifurcations], dtype=np.int64),
            "bifurcation_parameters": np.array([b.parameter for b in self.bifurcations], dtype=float),
        }
        return xr.Dataset(data, coords={"coefficient": names, "coordinate": list(self.coordinate_names)},
                          attrs=attrs)

    def save(self, path):
        """Write the branch to a netCDF file (:meth:`to_xarray`); read it back with :func:`load_branch`."""
        self.to_xarray().to_netcdf(path, engine="netcdf4", format="NETCDF4")

    # plots -------------------------------------------------------------------------------------------------

    def plot_response(self, station=None, *, coordinate=None, ax=None, units="mm", **kwargs):
        """Response curve: max orbit radius of ``station`` (or harmonic-1 amplitude of ``coordinate``) against
        the parameter; stable solid, unstable dashed, bifurcations marked. Returns the axes."""
        from .plotting import plot_branch_response

        return plot_branch_response(self, station=station, coordinate=coordinate, ax=ax, units=units, **kwargs)

    def plot_orbit(self, i, station, *, ax=None, units="mm", **kwargs):
        """The orbit of ``station`` at point ``i``. Returns the axes."""
        from .plotting import plot_branch_orbit

        return plot_branch_orbit(self, i, station, ax=ax, units=units, **kwargs)

    def plot_harmonics(self, coordinate, *, ax=None, units="mm", **kwargs):
        """Amplitude of each harmonic of ``coordinate`` along the branch. Returns the axes."""
        from .plotting import plot_branch_harmonics

        return plot_branch_harmonics(self, coordinate, ax=ax, units=units, **kwargs)


def load_branch(path):
    """Read a :class:`Branch` written by :meth:`Branch.save`."""
    import xarray as xr

    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds = ds.load()
    a = ds.attrs
    name = a["parameter_name"]
    multipliers = stable = None
    if "multipliers_real" in ds:
        multipliers = ds["multipliers_real"].values + 1j * ds["multipliers_imag"].values
        stable = ds["stable"].values.astype(bool)
    kinds = [k for k in str(a.get("bifurcation_kinds", "")).split(";") if k]
    indices = np.atleast_1d(a.get("bifurcation_indices", []))
    params = np.atleast_1d(a.get("bifurcation_parameters", []))
    bifurcations = tuple(Bifurcation(k, int(i), float(p)) for k, i, p in zip(kinds, indices, params))
    return Branch(
        parameter_name=name, parameter=ds[name].values, coefficients=ds["coefficients"].values,
        omega=ds["omega"].values, coordinate_names=tuple(str(c) for c in ds["coordinate"].values),
        speed_parameter=a["speed_parameter"], harmonics=int(a["harmonics"]), subharmonic=int(a["subharmonic"]),
        samples=int(a["samples"]), multipliers=multipliers, stable=stable, bifurcations=bifurcations,
        residual_error=ds["residual_error"].values, harmonic_share=ds["harmonic_share"].values,
        reason=str(a["reason"]), stability_method=str(a["stability_method"]),
    )
