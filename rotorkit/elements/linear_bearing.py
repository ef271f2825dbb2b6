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

Tabulated coefficients (:meth:`LinearBearing.tabulated`,
:meth:`LinearBearing.frequency_table`, :meth:`LinearBearing.from_csv`) against
the rotor speed, the whirl frequency or both, their interpolation, parameter
names and CSV form: :mod:`rotorkit.elements.bearing_tables`. The modal
analysis that reads each mode's coefficients at that mode's own frequency is
:func:`rotorkit.linear.matched_whirl.matched_whirl_modes`.

Moment (tilt) coefficients ``ktxx, ktxy, ktyx, ktyy`` (N m/rad) and
``ctxx, ctxy, ctyx, ctyy`` (N m s/rad) act on the tilts ``(thx, thy)`` the
same way: the moment on the journal is ``M = -K_t theta - C_t theta'``
(``theta = (thx, thy)``, relative to the housing station for an
inter-shaft bearing, to the ground otherwise). They need tilt coordinates at
the station (a beam element there); a bearing without them adds no tilt
terms.

Added-mass coefficients ``mxx, mxy, myx, myy`` (kg; fluid inertia of a
squeeze film or seal) add the force ``-M_a d''``, contributed as kinetic
energy ``T = d'^T M_a d' / 2`` (so they enter the mass matrix); the model's
mass matrix is symmetric, so ``mxy`` must equal ``myx``.

With a :class:`~rotorkit.elements.pedestal.Pedestal` the housing is a
support mass with its own springs to the ground: ``d`` is the journal
displacement minus the pedestal's (``px<station>``, ``py<station>``).
"""

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import ParameterError, TopologyError
from .base import Element, loaded_types
from .bearing_tables import (EXTRAPOLATIONS, INTERPOLATIONS, WHIRL_PARAMETERS, check_tables, interpolated_coefficient,
                             read_csv_table, replace_entries, split_entry, table_parameters, write_csv_table)
from .rotor import check_station

__all__ = ["LinearBearing"]

_STIFF = ("kxx", "kxy", "kyx", "kyy")
_DAMP = ("cxx", "cxy", "cyx", "cyy")
_TILT_STIFF = ("ktxx", "ktxy", "ktyx", "ktyy")
_TILT_DAMP = ("ctxx", "ctxy", "ctyx", "ctyy")
_TILT = _TILT_STIFF + _TILT_DAMP
_MASS = ("mxx", "mxy", "myx", "myy")
DIRECT_COEFFICIENTS = ("kxx", "kyy", "cxx", "cyy", "ktxx", "ktyy", "ctxx", "ctyy", "mxx", "myy")
_COEFFS = _STIFF + _DAMP + _TILT + _MASS
_PEDESTAL = "pedestal_"

if TYPE_CHECKING:  # for the annotation only: the module loads when a bearing has a pedestal
    from .pedestal import Pedestal


def _pedestal_axes():
    """The pedestal's coordinate axes (``px``, ``py``), from its module (imported when a bearing has one)."""
    from .pedestal import PEDESTAL_AXES

    return PEDESTAL_AXES


@dataclass(frozen=True, slots=True, kw_only=True)
class LinearBearing(Element):
    """A linear bearing with 2x2 stiffness and damping, to ground, to a pedestal or between two stations.

    Parameters
    ----------
    station : int or str
        Journal station.
    other_station : int or str, optional
        Station of the housing for an inter-shaft bearing (another rotor);
        None: the housing is the ground (or the pedestal).
    kxx, kxy, kyx, kyy : float or pint.Quantity
        Stiffness coefficients (N/m). ``kxx`` and ``kyy`` are required and
        >= 0; a cross term left None adds no term.
    cxx, cxy, cyx, cyy : float or pint.Quantity
        Damping coefficients (N s/m); direct ones >= 0. None adds no term.
    ktxx, ktxy, ktyx, ktyy : float or pint.Quantity, optional
        Moment (tilt) stiffness coefficients (N m/rad) on ``(thx, thy)``;
        direct ones >= 0. Need tilt coordinates at the station(s).
    ctxx, ctxy, ctyx, ctyy : float or pint.Quantity, optional
        Moment damping coefficients (N m s/rad).
    mxx, mxy, myx, myy : float or pint.Quantity, optional
        Added-mass coefficients (kg); direct ones >= 0, ``mxy == myx``.
    interpolation : {"linear", "pchip"}
        How a table is interpolated between its speeds (tables only).
    extrapolation : {"hold", "linear"}
        Outside the table: end values held, or continued along the end
        slopes (tables only).
    frequencies : sequence of float, optional
        Whirl frequencies (rad/s, increasing) of a table against frequency:
        each coefficient is then a list over them, or with ``speeds`` a
        list of rows (one per speed) over them.
    whirl : float or pint.Quantity, optional
        Frequency (rad/s) at which a frequency table is read in the
        equations; None (default): the rotor speed (synchronous).
    pedestal : Pedestal, optional
        The housing is a support mass on its own springs to the ground
        (coordinates ``px<station>``, ``py<station>``); only with
        ``other_station=None``.

    Examples
    --------
    >>> LinearBearing(station=1, kxx=1e6, kyy=0.8e6, kxy=2e5, kyx=-2e5, cxx=100.0, cyy=100.0).label()
    'linearbearing1'
    >>> b = LinearBearing.tabulated(station=1, speeds=[0.0, 500.0], kxx=[1e6, 2e6], kyy=[1e6, 2e6])
    >>> sorted(b.parameters())[:3]
    ['kxx0', 'kxx1', 'kyy0']
    >>> from rotorkit.elements import Pedestal
    >>> b = LinearBearing(station=1, kxx=1e8, kyy=1e8, pedestal=Pedestal(mass=40.0, kxx=5e7, kyy=2e7))
    >>> sorted(b.parameters())
    ['kxx', 'kyy', 'pedestal_kxx', 'pedestal_kyy', 'pedestal_mass']
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
    ktxx: float | None = None
    ktxy: float | None = None
    ktyx: float | None = None
    ktyy: float | None = None
    ctxx: float | None = None
    ctxy: float | None = None
    ctyx: float | None = None
    ctyy: float | None = None
    mxx: float | None = None
    mxy: float | None = None
    myx: float | None = None
    myy: float | None = None
    speeds: tuple | None = None
    frequencies: tuple | None = None
    whirl: float | None = None
    interpolation: str = "linear"
    extrapolation: str = "hold"
    pedestal: "Pedestal | None" = None

    _units = {
        "kxx": ("N/m", "nonnegative"), "kxy": ("N/m", None), "kyx": ("N/m", None), "kyy": ("N/m", "nonnegative"),
        "cxx": ("N*s/m", "nonnegative"), "cxy": ("N*s/m", None), "cyx": ("N*s/m", None),
        "cyy": ("N*s/m", "nonnegative"),
        **{f: ("N*m/rad", "nonnegative" if f in DIRECT_COEFFICIENTS else None) for f in _TILT_STIFF},
        **{f: ("N*m*s/rad", "nonnegative" if f in DIRECT_COEFFICIENTS else None) for f in _TILT_DAMP},
        **{f: ("kg", "nonnegative" if f in DIRECT_COEFFICIENTS else None) for f in _MASS},
    }
    #: direct coefficients checked >= 0 in a table (a Seal allows a negative direct stiffness)
    _direct_checked = DIRECT_COEFFICIENTS
    #: how the required direct stiffness is described in messages
    _direct_rule = ", >= 0"
    _latex_names = {**{f: f"{f[0]}_{{{f[1:]}}}" for f in _STIFF + _DAMP + _MASS},
                    **{f: rf"{f[0]}_{{\theta {f[2:]}}}" for f in _TILT},
                    **{_PEDESTAL + f: rf"{f[0]}_{{p,{f[1:]}}}" for f in ("kxx", "kyy", "cxx", "cyy")},
                    _PEDESTAL + "mass": "m_{p}"}

    @classmethod
    def tabulated(cls, *, station, speeds, other_station=None, name=None, pedestal=None, interpolation="linear",
                  extrapolation="hold", **coefficients):
        """Coefficients tabulated against rotor speed: ``speeds`` (rad/s, increasing) and one list per coefficient.

        Interpolated in the speed of the rotor of ``station``
        (``interpolation="linear"`` or ``"pchip"``); below the first and
        above the last speed the end values hold (``extrapolation="hold"``)
        or continue along the end slopes (``"linear"``).
        """
        return cls(station=station, other_station=other_station, name=name, speeds=speeds, pedestal=pedestal,
                   interpolation=interpolation, extrapolation=extrapolation, **coefficients)

    @classmethod
    def frequency_table(cls, *, station, frequencies, speeds=None, whirl=None, other_station=None, name=None,
                        pedestal=None, interpolation="linear", extrapolation="hold", **coefficients):
        """Coefficients against the whirl frequency: ``frequencies`` (rad/s, increasing), optionally ``speeds`` too.

        Without ``speeds`` each coefficient is a list, one value per
        frequency; with ``speeds`` a list of rows, ``kxx[i][j]`` at
        ``speeds[i]`` and ``frequencies[j]``. ``whirl``: the fixed frequency
        (rad/s) at which the equations read the table (None: the rotor
        speed). See the module docstring.

        Examples
        --------
        >>> b = LinearBearing.frequency_table(station=1, frequencies=[0.0, 1000.0], kxx=[1e6, 2e6], kyy=[1e6, 2e6])
        >>> sorted(b.parameters())
        ['frequency0', 'frequency1', 'kxx0', 'kxx1', 'kyy0', 'kyy1', 'whirl_frequency', 'whirl_ratio']
        """
        return cls(station=station, other_station=other_station, name=name, speeds=speeds,
                   frequencies=frequencies, whirl=whirl, pedestal=pedestal, interpolation=interpolation,
                   extrapolation=extrapolation, **coefficients)

    @classmethod
    def from_csv(cls, path, *, station, **options):
        """A tabulated bearing read from a CSV file, one row per speed.

        The header names the columns: ``speed`` and any coefficients
        (``kxx``, ``kxy``, ..., ``cyy``, ``mxx``..``myy``, tilt ones), each
        optionally with its unit in brackets, e.g.
        ``speed [rpm], kxx [N/m], kxy [MN/m], cxx [N*s/m]`` (default: SI,
        rad/s for the speed). Blank lines and lines starting with ``#`` are
        skipped. ``options`` go to :meth:`tabulated` (``other_station``,
        ``name``, ``interpolation``, ``extrapolation``, ``pedestal``).

        Examples
        --------
        >>> import pathlib, tempfile
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "bearing.csv"
        >>> _ = path.write_text("# journal bearing\\nspeed [rpm], kxx [MN/m], kyy [MN/m]\\n0, 10, 12\\n3000, 20, 25\\n")
        >>> b = LinearBearing.from_csv(path, station=1, interpolation="pchip")
        >>> b.speeds[1], b.kyy
        (314.1592653589793, (12000000.0, 25000000.0))
        """
        speeds, frequencies, table = read_csv_table(path, {f: cls._units[f][0] for f in _COEFFS},
                                                    f"LinearBearing.from_csv({str(path)!r})")
        if frequencies is None:
            return cls.tabulated(station=station, speeds=speeds, **table, **options)
        if speeds is None:
            return cls.frequency_table(station=station, frequencies=frequencies, **table, **options)
        return cls.frequency_table(station=station, speeds=speeds, frequencies=frequencies, **table, **options)

    def to_csv(self, path):
        """Write the table (SI units in the header) for :meth:`from_csv`; a grid one row per (speed, frequency)."""
        if not self._tabulated():
            raise ParameterError(f"{type(self).__name__} {self.label()!r}: to_csv needs a table (speeds=... or "
                                 "frequencies=...)")
        write_csv_table(path, self.speeds, self.frequencies, self._tables(),
                        {f: self._units[f][0] for f in self._present()})

    def _who(self):
        return f"{type(self).__name__} at station {self.station!r}"

    def _tabulated(self):
        return self.speeds is not None or self.frequencies is not None

    def _grid(self):
        """True for a table against speed and frequency (rows per speed of values per frequency)."""
        return self.speeds is not None and self.frequencies is not None

    def __post_init__(self):
        if not self._tabulated():
            if self.whirl is not None:
                raise ParameterError(f"{self._who()}: whirl = {self.whirl!r} is only used with a table against "
                                     "frequency (frequencies=...)")
            Element.__post_init__(self)
            return
        who = self._who()
        tables = {}
        for f in _COEFFS:
            values = getattr(self, f)
            if values is None:
                continue
            tables[f] = values
            object.__setattr__(self, f, None)  # hidden from the scalar unit checks
        Element.__post_init__(self)
        speeds, frequencies, tables = check_tables(self.speeds, self.frequencies, tables,
                                                   {f: self._units[f][0] for f in tables}, who)
        object.__setattr__(self, "speeds", speeds)
        object.__setattr__(self, "frequencies", frequencies)
        if self.whirl is not None:
            if frequencies is None:
                raise ParameterError(f"{who}: whirl = {self.whirl!r} is only used with a table against frequency "
                                     "(frequencies=...)")
            from ..units import to_si

            object.__setattr__(self, "whirl", to_si(self.whirl, "rad/s", f"{who} whirl"))
        for f, ys in tables.items():
            object.__setattr__(self, f, ys)
        self._check_direct()
        self._check_added_mass()

    def _validate(self):
        who = self._who()
        object.__setattr__(self, "station", check_station(type(self).__name__, self.station, "station"))
        if self.other_station is not None:
            object.__setattr__(self, "other_station", check_station(who, self.other_station, "other_station"))
            if self.other_station == self.station:
                raise ParameterError(f"{who}: other_station = {self.other_station!r} is the journal station itself; "
                                     "give the housing's station (or None for the ground)")
        if not self._tabulated():
            for f in ("kxx", "kyy"):
                if getattr(self, f) is None:
                    raise ParameterError(f"{who}: {f} is required (N/m{self._direct_rule})")
        for f, allowed in (("interpolation", INTERPOLATIONS), ("extrapolation", EXTRAPOLATIONS)):
            value = getattr(self, f)
            if not isinstance(value, str) or value not in allowed:
                raise ParameterError(f"{who}: {f} = {value!r}: expected one of {allowed}")
            if not self._tabulated() and value != allowed[0]:
                raise ParameterError(f"{who}: {f} = {value!r} is only used with a table (speeds=... or "
                                     "frequencies=...)")
        if not self._tabulated():
            self._check_added_mass()
        if self.pedestal is not None:
            if not isinstance(self.pedestal, loaded_types("pedestal.Pedestal")):  # (loaded if there is one)
                raise ParameterError(f"{who}: pedestal = {self.pedestal!r}: expected a Pedestal(mass=..., kxx=..., "
                                     "kyy=...)")
            if self.other_station is not None:
                raise ParameterError(f"{who}: pedestal with other_station = {self.other_station!r}: an inter-shaft "
                                     "bearing's housing is the other rotor; put the pedestal on a bearing to ground")

    def _check_direct(self):
        who = self._who()
        for f in ("kxx", "kyy"):
            if getattr(self, f) is None:
                raise ParameterError(f"{who}: {f} is required (a list of N/m values, one per table entry)")
        for f in self._direct_checked:
            values = getattr(self, f)
            if values is None:
                continue
            flat = [(f"{i}][{j}", v) for i, row in enumerate(values) for j, v in enumerate(row)] if self._grid() \
                else list(enumerate(values))
            for i, v in flat:
                if v < 0:
                    raise ParameterError(f"{who}: {f}[{i}] = {v!r} is negative; direct coefficients must be >= 0 "
                                         "(a negative direct stiffness or damping is a destabilising support)")

    def _check_added_mass(self):
        if self.mxy != self.myx:
            raise ParameterError(f"{self._who()}: mxy = {self.mxy!r} and myx = "
                                 f"{self.myx!r} differ; expected a symmetric added mass (mxy == myx, both given or "
                                 "neither): the model's mass matrix is symmetric")

    # -- parameters -------------------------------------------------------
    def _present(self):
        return [f for f in _COEFFS if getattr(self, f) is not None]

    def _tables(self):
        """Coefficient -> its table, for the coefficients given (a table bearing)."""
        return {f: getattr(self, f) for f in self._present()}

    def _tilted(self):
        return any(getattr(self, f) is not None for f in _TILT)

    def parameters(self):
        if not self._tabulated():
            out = Element.parameters(self)
        else:
            out = table_parameters(self.speeds, self.frequencies, self.whirl, self._tables())
        if self.pedestal is not None:
            out.update({_PEDESTAL + f: v for f, v in self.pedestal.parameters().items()})
        return out

    def unit_of(self, field_name):
        if field_name.startswith(_PEDESTAL):
            return self.pedestal.unit_of(field_name[len(_PEDESTAL):])
        if field_name in WHIRL_PARAMETERS:
            return "" if field_name == "whirl_ratio" else "rad/s"
        if not self._tabulated() or field_name in self._units:
            return Element.unit_of(self, field_name)
        base = split_entry(field_name)[0]
        return "rad/s" if base in ("speed", "frequency") else self._units[base][0]

    def parameter_units(self):
        return {f: self.unit_of(f) for f in self.parameters()}

    def parameter_sign(self, field_name):
        if field_name.startswith(_PEDESTAL):
            from .pedestal import Pedestal

            return Pedestal._units[field_name[len(_PEDESTAL):]][1]
        if not self._tabulated():
            return Element.parameter_sign(self, field_name)
        base = split_entry(field_name)[0]
        return None if base in ("speed", "frequency") or field_name in WHIRL_PARAMETERS else self._units[base][1]

    def replace_parameters(self, **fields):
        pedestal = self.pedestal
        own = {k: v for k, v in fields.items() if not k.startswith(_PEDESTAL)}
        mine = {k[len(_PEDESTAL):]: v for k, v in fields.items() if k.startswith(_PEDESTAL)}
        if mine:
            pedestal = pedestal.replace(**mine)
        if not self._tabulated():
            return dataclasses.replace(self, pedestal=pedestal, **own)
        speeds, frequencies, whirl, tables = replace_entries(self.speeds, self.frequencies, self.whirl,
                                                             self._tables(), own, self._who())
        return type(self)(station=self.station, other_station=self.other_station, name=self.name,
                          speeds=speeds, frequencies=frequencies, whirl=whirl, pedestal=pedestal,
                          interpolation=self.interpolation, extrapolation=self.extrapolation, **tables)

    def structure(self):
        present = tuple(self._present())
        n = None if self.speeds is None else len(self.speeds)
        pedestal = None if self.pedestal is None else self.pedestal.structure()
        # the interpolation only when not the default: the keys of existing models stay the same
        table = n if (self.interpolation, self.extrapolation) == ("linear", "hold") else (
            n, self.interpolation, self.extrapolation)
        if self.frequencies is not None:  # a frequency table: its own key (tables against speed keep theirs)
            table = ("frequency", n, len(self.frequencies), self.interpolation, self.extrapolation)
        return (type(self).__name__, self.label(), (("station", repr(self.station)),
                                                    ("other_station", repr(self.other_station)),
                                                    ("coefficients", present), ("table", table),
                                                    ("pedestal", pedestal)))

    # -- topology ---------------------------------------------------------
    def attached_stations(self):
        return (self.station,) if self.other_station is None else (self.station, self.other_station)

    def coordinates(self):
        return tuple((self.station, a) for a in _pedestal_axes()) if self.pedestal is not None else ()

    def inertia(self):
        return self.coordinates()

    def requires(self):
        if not self._tilted():
            return ()
        return tuple((s, a) for s in self.attached_stations() for a in ("thx", "thy"))

    def grounds(self):
        if self.other_station is not None:
            return ()
        tilts = ((self.station, "thx"), (self.station, "thy")) if self._tilted() else ()
        if self.pedestal is not None:
            return tuple((self.station, a) for a in _pedestal_axes()) + tilts
        return ((self.station, "x"), (self.station, "y")) + tilts

    def stiffness_links(self):
        s = self.station
        if self.pedestal is not None:
            return (((s, "x"), (s, "px")), ((s, "y"), (s, "py")))
        if self.other_station is None:
            return ()
        axes = ("x", "y") + (("thx", "thy") if self._tilted() else ())
        return tuple(((s, a), (self.other_station, a)) for a in axes)

    def check(self, model):
        if self.pedestal is None:
            return
        for e in model.elements_at(self.station):
            if e is not self and any(pair in e.coordinates() for pair in self.coordinates()):
                raise TopologyError(
                    f"LinearBearing {self.label()!r}: station {self.station!r} has a second pedestal "
                    f"(from {type(e).__name__} {e.label()!r}); one pedestal per station: put both bearings on one "
                    "pedestal station with other_station, or on different stations")

    def rigid_body_mass(self, ctx):
        import sympy as sp

        if self.pedestal is None:
            return {}
        m = ctx.p[_PEDESTAL + "mass"]
        px, py = ctx.coord(self.station, "px")[0], ctx.coord(self.station, "py")[0]
        return {px: (m, sp.S.Zero), py: (sp.S.Zero, m)}

    def _default_label(self):
        other = "" if self.other_station is None else f"_{self.other_station}"
        return f"linearbearing{self.station}{other}"

    # -- physics ----------------------------------------------------------
    def coefficient(self, ctx, f):
        """Coefficient ``f`` as an expression (0 if absent): a symbol, or the table at the rotor speed."""
        import sympy as sp

        if getattr(self, f) is None:
            return sp.S.Zero
        if not self._tabulated():
            return ctx.p[f]
        return interpolated_coefficient(ctx.p, f, ctx.speed(self.station),
                                        None if self.speeds is None else len(self.speeds),
                                        None if self.frequencies is None else len(self.frequencies),
                                        self.interpolation, self.extrapolation)

    def _pair(self, ctx, axes, housing_axes, stiff, damp, mass=None):
        """(V, D, loads, T) of ``F = -K d - C d' - M_a d''`` on the journal's ``axes`` against the housing's."""
        (xa, xad), (ya, yad) = ctx.coord(self.station, axes[0]), ctx.coord(self.station, axes[1])
        housing = None
        if housing_axes is not None:
            station = self.station if self.other_station is None else self.other_station
            housing = (ctx.coord(station, housing_axes[0]), ctx.coord(station, housing_axes[1]))
        if housing is None:
            d, dd = (xa, ya), (xad, yad)
        else:
            (xb, xbd), (yb, ybd) = housing
            d, dd = (xa - xb, ya - yb), (xad - xbd, yad - ybd)
        k = [self.coefficient(ctx, f) for f in stiff]
        c = [self.coefficient(ctx, f) for f in damp]
        potential = (k[0] * d[0] ** 2 + (k[1] + k[2]) * d[0] * d[1] + k[3] * d[1] ** 2) / 2
        dissipation = (c[0] * dd[0] ** 2 + (c[1] + c[2]) * dd[0] * dd[1] + c[3] * dd[1] ** 2) / 2
        # skew (circulatory) parts: F_x = -(kxy - kyx)/2 dy, F_y = -(kyx - kxy)/2 dx (likewise damping)
        ka, ca = (k[1] - k[2]) / 2, (c[1] - c[2]) / 2
        fx = -ka * d[1] - ca * dd[1]
        fy = ka * d[0] + ca * dd[0]
        loads = {}
        if fx != 0 or fy != 0:
            loads = {xa: fx, ya: fy}
            if housing is not None:
                loads[xb], loads[yb] = -fx, -fy
        kinetic = 0
        if mass is not None:  # added mass: symmetric (mxy == myx), T = d'^T M_a d' / 2
            m = [self.coefficient(ctx, f) for f in mass]
            kinetic = (m[0] * dd[0] ** 2 + (m[1] + m[2]) * dd[0] * dd[1] + m[3] * dd[1] ** 2) / 2
        return potential, dissipation, loads, kinetic

    def contribute(self, ctx):
        import sympy as sp

        from .terms import Terms

        if self.pedestal is not None:
            housing = _pedestal_axes()
        else:
            housing = None if self.other_station is None else ("x", "y")
        added = _MASS if any(getattr(self, f) is not None for f in _MASS) else None
        potential, dissipation, loads, kinetic = self._pair(ctx, ("x", "y"), housing, _STIFF, _DAMP, added)
        if self._tilted():  # the pedestal translates only: moments act against the ground there
            tilt_housing = None if self.other_station is None else ("thx", "thy")
            v, d, q, _ = self._pair(ctx, ("thx", "thy"), tilt_housing, _TILT_STIFF, _TILT_DAMP)
            potential, dissipation = potential + v, dissipation + d
            for key, value in q.items():
                loads[key] = loads.get(key, sp.S.Zero) + value
        if self.pedestal is not None:
            p = {f[len(_PEDESTAL):]: s for f, s in ctx.p.items() if f.startswith(_PEDESTAL)}
            t, v, d = self.pedestal.terms(p, ctx.coord(self.station, "px"), ctx.coord(self.station, "py"))
            kinetic, potential, dissipation = kinetic + t, potential + v, dissipation + d
            from .base_motion import base_frame, point_mass_loads

            frame = base_frame(ctx)
            if frame is not None:  # the pedestal mass in a turning base
                (px, pxd), (py, pyd) = ctx.coord(self.station, "px"), ctx.coord(self.station, "py")
                for key, value in point_mass_loads(p["mass"], (px, py), (pxd, pyd), frame.z(self.station),
                                                   frame).items():
                    loads[key] = loads.get(key, sp.S.Zero) + value
        return Terms(kinetic=kinetic, potential=potential, dissipation=dissipation, loads=loads)
