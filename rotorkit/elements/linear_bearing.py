"""General linear bearing: full 2x2 stiffness and damping, constant or against rotor speed.

The bearing force on the journal (station ``station``) is ::

    F = -K d - C d',   d = (x_a - x_b, y_a - y_b),
    K = [[kxx, kxy], [kyx, kyy]],   C = [[cxx, cxy], [cyx, cyy]]

where ``b`` is the ground (``other_station=None``) or a station of another
(or the same) rotor (inter-shaft bearing), which gets ``-F``.

K and C split into a symmetric part, contributed as potential energy
``V = d^T K_s d / 2`` and Rayleigh function ``D = d'^T C_s d' / 2`` (so they
appear in ``model.equations().stiffness``/``damping``), and a skew part
``K_a = (K - K^T) / 2`` (likewise C), which is not conservative and is
contributed as a generalised load ``-K_a d - C_a d'`` (listed under the
bearing in ``equations().forces``). Their sum is exactly ``-K d - C d'``.

Tabulated coefficients (:meth:`LinearBearing.tabulated`) are piecewise
linear in the speed of the rotor of ``station`` and held at the end values
outside the table (no linear extrapolation). The table entries are
parameters ``<label>_speed<i>``, ``<label>_kxx<i>``, ...; a rotor whose speed
follows a :class:`~rotorkit.elements.speed.SpeedProfile` sees the
coefficients change along the run.
"""

from dataclasses import dataclass

import sympy as sp

from ..errors import ParameterError
from .base import Element, Terms
from .rotor import check_station
from .speed import check_table, interpolate_table

__all__ = ["LinearBearing"]

_STIFF = ("kxx", "kxy", "kyx", "kyy")
_DAMP = ("cxx", "cxy", "cyx", "cyy")
_DIRECT = ("kxx", "kyy", "cxx", "cyy")
_COEFFS = _STIFF + _DAMP


@dataclass(frozen=True, slots=True, kw_only=True)
class LinearBearing(Element):
    """A linear bearing with 2x2 stiffness and damping, to ground or between two stations.

    Parameters
    ----------
    station : int or str
        Journal station.
    other_station : int or str, optional
        Station of the housing for an inter-shaft bearing (another rotor);
        None: the housing is the ground.
    kxx, kxy, kyx, kyy : float or pint.Quantity
        Stiffness coefficients (N/m). ``kxx`` and ``kyy`` are required and
        >= 0; a cross term left None adds no term.
    cxx, cxy, cyx, cyy : float or pint.Quantity
        Damping coefficients (N s/m); direct ones >= 0. None adds no term.

    Examples
    --------
    >>> LinearBearing(station=1, kxx=1e6, kyy=0.8e6, kxy=2e5, kyx=-2e5, cxx=100.0, cyy=100.0).label()
    'linearbearing1'
    >>> b = LinearBearing.tabulated(station=1, speeds=[0.0, 500.0], kxx=[1e6, 2e6], kyy=[1e6, 2e6])
    >>> sorted(b.parameters())[:3]
    ['kxx0', 'kxx1', 'kyy0']
    """

    station: int | str = None
    other_station: int | str | None = None
    kxx: float = None
    kxy: float | None = None
    kyx: float | None = None
    kyy: float = None
    cxx: float | None = None
    cxy: float | None = None
    cyx: float | None = None
    cyy: float | None = None
    speeds: tuple | None = None

    _units = {
        "kxx": ("N/m", "nonnegative"), "kxy": ("N/m", None), "kyx": ("N/m", None), "kyy": ("N/m", "nonnegative"),
        "cxx": ("N*s/m", "nonnegative"), "cxy": ("N*s/m", None), "cyx": ("N*s/m", None),
        "cyy": ("N*s/m", "nonnegative"),
    }
    _latex_names = {f: f"{f[0]}_{{{f[1:]}}}" for f in _COEFFS}

    @classmethod
    def tabulated(cls, *, station, speeds, other_station=None, name=None, **coefficients):
        """Coefficients tabulated against rotor speed: ``speeds`` (rad/s, increasing) and one list per coefficient.

        Piecewise-linear interpolation in the speed of the rotor of
        ``station``; below the first and above the last speed the end values
        hold.
        """
        return cls(station=station, other_station=other_station, name=name, speeds=speeds, **coefficients)

    def __post_init__(self):
        if self.speeds is None:
            Element.__post_init__(self)
            return
        who = f"LinearBearing at station {self.station!r}"
        tables = {}
        speeds = None
        for f in _COEFFS:
            values = getattr(self, f)
            if values is None:
                continue
            unit = self._units[f][0]
            xs, ys = check_table(self.speeds, "speeds", f, values, unit_x="rad/s", unit_y=unit, owner=who)
            speeds = xs
            tables[f] = ys
            object.__setattr__(self, f, None)  # hidden from the scalar unit checks
        Element.__post_init__(self)
        if speeds is None:
            speeds = check_table(self.speeds, "speeds", "speeds", self.speeds, unit_x="rad/s", unit_y="rad/s",
                                 owner=who)[0]
        object.__setattr__(self, "speeds", speeds)
        for f, ys in tables.items():
            object.__setattr__(self, f, ys)
        self._check_direct()

    def _validate(self):
        who = f"LinearBearing at station {self.station!r}"
        object.__setattr__(self, "station", check_station("LinearBearing", self.station, "station"))
        if self.other_station is not None:
            object.__setattr__(self, "other_station", check_station(who, self.other_station, "other_station"))
            if self.other_station == self.station:
                raise ParameterError(f"{who}: other_station = {self.other_station!r} is the journal station itself; "
                                     "give the housing's station (or None for the ground)")
        if self.speeds is None:
            for f in ("kxx", "kyy"):
                if getattr(self, f) is None:
                    raise ParameterError(f"{who}: {f} is required (N/m, >= 0)")

    def _check_direct(self):
        who = f"LinearBearing at station {self.station!r}"
        for f in ("kxx", "kyy"):
            if getattr(self, f) is None:
                raise ParameterError(f"{who}: {f} is required (a list of N/m values, one per speed)")
        for f in _DIRECT:
            values = getattr(self, f)
            for i, v in enumerate(values or ()):
                if v < 0:
                    raise ParameterError(f"{who}: {f}[{i}] = {v!r} is negative; direct coefficients must be >= 0 "
                                         "(a negative direct stiffness or damping is a destabilising support)")

    # -- parameters -------------------------------------------------------
    def _present(self):
        return [f for f in _COEFFS if getattr(self, f) is not None]

    def parameters(self):
        if self.speeds is None:
            return Element.parameters(self)
        out = {f"speed{i}": v for i, v in enumerate(self.speeds)}
        for f in self._present():
            out.update({f"{f}{i}": v for i, v in enumerate(getattr(self, f))})
        return out

    def _split(self, field_name):
        base = field_name.rstrip("0123456789")
        return base, int(field_name[len(base):])

    def unit_of(self, field_name):
        if self.speeds is None or field_name in self._units:
            return Element.unit_of(self, field_name)
        base, _ = self._split(field_name)
        return "rad/s" if base == "speed" else self._units[base][0]

    def parameter_units(self):
        return {f: self.unit_of(f) for f in self.parameters()}

    def parameter_sign(self, field_name):
        if self.speeds is None:
            return Element.parameter_sign(self, field_name)
        base, _ = self._split(field_name)
        return None if base == "speed" else self._units[base][1]

    def replace_parameters(self, **fields):
        if self.speeds is None:
            return Element.replace_parameters(self, **fields)
        tables = {f: list(getattr(self, f)) for f in self._present()}
        tables["speed"] = list(self.speeds)
        for name, value in fields.items():
            base, i = self._split(name)
            tables[base][i] = value
        speeds = tables.pop("speed")
        return LinearBearing(station=self.station, other_station=self.other_station, name=self.name,
                             speeds=speeds, **tables)

    def structure(self):
        present = tuple(self._present())
        n = None if self.speeds is None else len(self.speeds)
        return (type(self).__name__, self.label(), (("station", repr(self.station)),
                                                    ("other_station", repr(self.other_station)),
                                                    ("coefficients", present), ("table", n)))

    # -- topology ---------------------------------------------------------
    def attached_stations(self):
        return (self.station,) if self.other_station is None else (self.station, self.other_station)

    def grounds(self):
        return () if self.other_station is not None else ((self.station, "x"), (self.station, "y"))

    def stiffness_links(self):
        if self.other_station is None:
            return ()
        return (((self.station, "x"), (self.other_station, "x")), ((self.station, "y"), (self.other_station, "y")))

    def _default_label(self):
        other = "" if self.other_station is None else f"_{self.other_station}"
        return f"linearbearing{self.station}{other}"

    # -- physics ----------------------------------------------------------
    def coefficient(self, ctx, f):
        """Coefficient ``f`` as an expression (0 if absent): a symbol, or the table at the rotor speed."""
        if getattr(self, f) is None:
            return sp.S.Zero
        if self.speeds is None:
            return ctx.p[f]
        n = len(self.speeds)
        return interpolate_table(ctx.speed(self.station), [ctx.p[f"speed{i}"] for i in range(n)],
                                 [ctx.p[f"{f}{i}"] for i in range(n)])

    def contribute(self, ctx):
        (xa, xad), (ya, yad) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        if self.other_station is None:
            d, dd = (xa, ya), (xad, yad)
        else:
            (xb, xbd), (yb, ybd) = ctx.coord(self.other_station, "x"), ctx.coord(self.other_station, "y")
            d, dd = (xa - xb, ya - yb), (xad - xbd, yad - ybd)
        k = {f: self.coefficient(ctx, f) for f in _STIFF}
        c = {f: self.coefficient(ctx, f) for f in _DAMP}
        potential = (k["kxx"] * d[0] ** 2 + (k["kxy"] + k["kyx"]) * d[0] * d[1] + k["kyy"] * d[1] ** 2) / 2
        dissipation = (c["cxx"] * dd[0] ** 2 + (c["cxy"] + c["cyx"]) * dd[0] * dd[1] + c["cyy"] * dd[1] ** 2) / 2
        # skew (circulatory) parts: F_x = -(kxy - kyx)/2 dy, F_y = -(kyx - kxy)/2 dx (likewise damping)
        ka, ca = (k["kxy"] - k["kyx"]) / 2, (c["cxy"] - c["cyx"]) / 2
        fx = -ka * d[1] - ca * dd[1]
        fy = ka * d[0] + ca * dd[0]
        loads = {}
        if fx != 0 or fy != 0:
            loads = {xa: fx, ya: fy}
            if self.other_station is not None:
                loads[xb], loads[yb] = -fx, -fy
        return Terms(potential=potential, dissipation=dissipation, loads=loads)

