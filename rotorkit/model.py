"""A model: a checked, immutable set of elements and the effects it holds."""

from collections import defaultdict

from .context import Context  # noqa: F401  (its former home; the derivation imports it from rotorkit.context)
from .elements.base import AXES, Element
from .errors import ParameterError, TopologyError
from .units import to_si

__all__ = ["Model"]

#: bump when the derivation or generated code changes, to invalidate caches
FORMAT_VERSION = "7"


def _check_station_names(stations):
    """Stations name coordinates (``x<station>``): two that are the same identifier are refused (``'ﬁ'`` and
    ``'fi'``, full-width ``'ａ'`` and ``'a'``: Python identifiers are NFKC-normalised; ``1`` and ``'1'``)."""
    import unicodedata

    seen = {}
    for s in stations:
        key = unicodedata.normalize("NFKC", str(s))
        if key in seen:
            raise TopologyError(
                f"Model: stations {seen[key]!r} and {s!r} name the same coordinates (x{key}, y{key}, ...: the same "
                f"identifier {key!r} after Unicode normalisation); rename one of them")
        seen[key] = s


class Model:
    """A rotor system assembled from elements.

    The model only gathers: it knows no concrete element type. Each element
    declares the coordinates it creates, needs, gives inertia to and ties
    elastically (see :mod:`rotorkit.elements.base`) and checks its own
    attachments; the model orders the coordinates, checks generically that
    each one has inertia and an elastic path to the ground, and collects the
    effects the elements bring.

    Parameters
    ----------
    elements : iterable of Element
        Rotors, masses, shaft segments, supports, bearings, stators and at
        most one manoeuvre. Order does not matter except that it sets the
        order of stations (rotor by rotor) and of parameters.
    name : str
        Model name (used in outputs).

    Raises
    ------
    TopologyError
        Unknown or duplicate stations, a coordinate without inertia (a
        station without mass), a rotor with no support, a torsional or tilt
        coordinate with no stiffness path, a coordinate an element needs
        but no element creates, and each element's own rules (a bearing
        within one rotor, ...).

    Examples
    --------
    A Jeffcott rotor:

    >>> from rotorkit import Rotor, Disk, ElasticSupport
    >>> m = Model([Rotor(name="R", stations=(1,), speed=100.0),
    ...            Disk(station=1, mass=2.0, radius=0.1, eccentricity=1e-5),
    ...            ElasticSupport(station=1, stiffness=2e4, damping=4.0)])
    >>> m.coordinate_names
    ('x1', 'y1')
    """

    def __init__(self, elements, *, name="model"):
        if isinstance(elements, (str, bytes, Element)) or not hasattr(elements, "__iter__"):
            raise TopologyError(f"Model: elements = {elements!r}: expected a list of rotorkit elements")
        elements = tuple(elements)
        for e in elements:
            if not isinstance(e, Element):
                raise TopologyError(f"Model: {e!r} is not a rotorkit element (Rotor, Disk, ShaftSegment, ...)")
        self.name = name
        self.elements = elements
        self._check_labels()
        self.rotors = {e.label(): e for e in elements if e.owned_stations()}
        self._station_rotor = self._map_stations()
        self._check_attachments()
        self._by_station = defaultdict(list)
        for e in elements:
            for s in dict.fromkeys(e.attached_stations()):
                self._by_station[s].append(e)
        self.coordinates, self._creators = self._gather_coordinates()
        self._coordinate_set = set(self.coordinates)
        self.coordinate_names = tuple(f"{axis}{station}" for station, axis in self.coordinates)
        self._check_required()
        self._check_inertia()  # a station without mass first: the other checks assume every station has one
        for e in elements:
            e.check(self)
        self._check_stiffness_paths()
        self._check_symbol_names()

    # -- topology -------------------------------------------------------
    @property
    def stations(self):
        """All stations, rotor by rotor in axial order."""
        return tuple(self._station_rotor)

    def rotor_of(self, station):
        """The :class:`Rotor` a station belongs to."""
        return self._station_rotor[station]

    def elements_at(self, station):
        """The elements attached to ``station``, in model order."""
        return tuple(self._by_station.get(station, ()))

    def has_coordinate(self, station, axis):
        """Whether the model has the coordinate ``<axis><station>``."""
        return (station, axis) in self._coordinate_set

    @property
    def disks(self):
        """Station -> the rigid disk there (an element with a ``polar_inertia`` field), in station order."""
        return {s: e for s in self.stations for e in self.elements_at(s)
                if hasattr(e, "polar_inertia") and e.attached_stations() == (s,)}

    @property
    def torsion_stations(self):
        """Stations with a torsional coordinate ``alpha``."""
        return tuple(s for s, axis in self.coordinates if axis == "alpha")

    @property
    def tilt_stations(self):
        """Stations with tilt coordinates ``thx``, ``thy``."""
        return tuple(s for s, axis in self.coordinates if axis == "thx")

    def _check_labels(self):
        import unicodedata

        seen = {}
        for e in self.elements:
            label = e.label()
            key = unicodedata.normalize("NFKC", str(label))  # Python identifiers are NFKC-normalised: "ℛ" is "R"
            if key in seen:
                same = "" if key == label else f" (the same identifier {key!r} after Unicode normalisation)"
                raise TopologyError(
                    f"Model: two elements are labelled {label!r}{same} ({seen[key]!r} and {e!r}); "
                    "give one of them a distinct name=..."
                )
            seen[key] = e

    def _map_stations(self):
        if not self.rotors:
            raise TopologyError("Model: no Rotor given; add Rotor(name=..., stations=..., speed=...)")
        mapping = {}
        for rotor in self.rotors.values():
            for s in rotor.owned_stations():
                if s in mapping:
                    raise TopologyError(
                        f"Model: station {s!r} is on rotor {mapping[s].name!r} and rotor {rotor.name!r}; "
                        "a station belongs to one rotor"
                    )
                mapping[s] = rotor
        order = list(mapping)
        for e in self.elements:  # internal stations (beam nodes) follow their host station
            added = []
            for s, host in e.internal_stations():
                if host not in mapping:
                    raise TopologyError(f"{type(e).__name__} {e.label()!r}: station {host!r} is not on any rotor "
                                        f"(known stations: {order})")
                if s in mapping:
                    raise TopologyError(f"{type(e).__name__} {e.label()!r}: internal station {s!r} exists already; "
                                        "rename the element (name=...) or the station")
                mapping[s] = mapping[host]
                at = order.index(added[-1] if added else host) + 1
                order.insert(at, s)
                added.append(s)
        _check_station_names(order)
        return {s: mapping[s] for s in order}

    def _check_attachments(self):
        for e in self.elements:
            pairs = tuple(e.coordinates()) + tuple(e.requires())
            for s in tuple(e.attached_stations()) + tuple(s for s, _ in pairs):
                if s not in self._station_rotor:
                    raise TopologyError(
                        f"{type(e).__name__} {e.label()!r}: station {s!r} is not on any rotor "
                        f"(known stations: {list(self._station_rotor)})"
                    )
            for _, axis in pairs:
                if not isinstance(axis, str) or not axis.isidentifier():
                    raise TopologyError(f"{type(e).__name__} {e.label()!r}: coordinate axis {axis!r} must be an "
                                        f"identifier such as {AXES}")

    def _gather_coordinates(self):
        creators = defaultdict(list)
        extra_axes = []
        for e in self.elements:
            for pair in e.coordinates():
                creators[pair].append(e)
                if pair[1] not in AXES and pair[1] not in extra_axes:
                    extra_axes.append(pair[1])
        axis_rank = {a: i for i, a in enumerate(AXES + tuple(extra_axes))}
        station_rank = {s: i for i, s in enumerate(self._station_rotor)}
        ordered = sorted(creators, key=lambda pair: (axis_rank[pair[1]], station_rank[pair[0]]))
        return tuple(ordered), dict(creators)

    def _check_required(self):
        for e in self.elements:
            missing = [p for p in e.requires() if p not in self._coordinate_set]
            if missing:
                names = ", ".join(f"{a}{s}" for s, a in missing)
                tilt = any(a in ("thx", "thy") for _, a in missing)
                hint = ("tilt coordinates come from elements that bend with slope, e.g. a BeamSegment ending "
                        "at that station (or drop the tilt-only part)" if tilt else "add an element that creates them")
                raise TopologyError(
                    f"{type(e).__name__} {e.label()!r}: needs the coordinates {names}, which the model does not "
                    f"have; {hint}"
                )

    def _fail(self, problem, failing):
        """Raise for the first failing coordinate, explained by the element that created it."""
        first = failing[0]
        creator = self._creators[first][0]
        mine = [p for p in failing if creator in self._creators[p]]
        message = creator.explain(self, problem, mine)
        if message is None:
            names = ", ".join(f"{a}{s}" for s, a in mine)
            what = ("no element gives them mass or inertia, so the mass matrix is singular" if problem == "inertia"
                    else "no elastic path to a support, so they would drift freely")
            message = f"{type(creator).__name__} {creator.label()!r}: coordinates {names}: {what}"
        raise TopologyError(message)

    def _check_inertia(self):
        given = set()
        for e in self.elements:
            given.update(e.inertia())
        failing = [p for p in self.coordinates if p not in given]
        if failing:
            self._fail("inertia", failing)

    def _check_stiffness_paths(self):
        """Every coordinate has an elastic path to the ground (or to a prescribed motion)."""
        links = defaultdict(set)
        reached = set()
        for e in self.elements:
            for group in e.stiffness_links():
                group = tuple(group)
                present = [p for p in group if p in self._coordinate_set]
                if len(present) < len(group):  # tied to a prescribed motion (e.g. the drive)
                    reached.update(present)
                for a in present:
                    links[a].update(present)
            reached.update(p for p in e.grounds() if p in self._coordinate_set)
        todo = list(reached)
        while todo:
            for n in links[todo.pop()] - reached:
                reached.add(n)
                todo.append(n)
        failing = [p for p in self.coordinates if p not in reached]
        if failing:
            self._fail("support", failing)

    def _check_symbol_names(self):
        """Names are glued from labels, fields and stations: they must not collide."""
        owner = {}
        names = [(n, f"state {n}") for n in self.coordinate_names]
        names += [(f"{n}_dot", f"state {n}_dot") for n in self.coordinate_names]
        names += [(f"{e.label()}_{f}", f"parameter {f!r} of {type(e).__name__} {e.label()!r}")
                  for e in self.elements for f in e.parameters()]
        for name, what in names:
            if name in owner:
                raise TopologyError(
                    f"Model: the name {name!r} stands for both {owner[name]} and {what}; rename an element "
                    "(name=...) or a station so that the generated names differ"
                )
            owner[name] = what

    # -- parameters and effects -------------------------------------------
    @property
    def parameters(self):
        """Parameter name -> SI value, in model order."""
        return {f"{e.label()}_{f}": v for e in self.elements for f, v in e.parameters().items()}

    def with_values(self, **values):
        """A copy with some parameters changed (``support1_stiffness=2e6``, SI or pint).

        The changed elements are rebuilt, so each value goes through its
        element's full validation (units, signs, cross-field rules such as a
        roll that ends before it starts). The structure, hence the derived
        equations and generated code, stays the same.
        """
        owners = {f"{e.label()}_{f}": (i, f) for i, e in enumerate(self.elements) for f in e.parameters()}
        changes = defaultdict(dict)
        for name, value in values.items():
            if name not in owners:
                import difflib

                near = difflib.get_close_matches(name, list(owners), n=3)
                hint = f"did you mean {', '.join(near)}?" if near else f"parameters are: {', '.join(owners)}"
                raise ParameterError(f"{self.name}: unknown parameter {name!r}; {hint}")
            index, field_name = owners[name]
            element = self.elements[index]
            sign = element.parameter_sign(field_name)
            changes[index][field_name] = to_si(value, element.unit_of(field_name), name, sign=sign)
        elements = list(self.elements)
        for index, fields in changes.items():
            try:
                elements[index] = elements[index].replace_parameters(**fields)
            except ParameterError as err:
                label = elements[index].label()
                names = ", ".join(f"{label}_{f} = {v!r}" for f, v in fields.items())
                raise type(err)(f"{names}: {err}") from err
        return Model(elements, name=self.name)

    @property
    def parameter_units(self):
        """Parameter name -> SI unit string (a new dict each time)."""
        known = self.__dict__.get("_parameter_units")  # elements are frozen: gathered once per elements tuple
        if known is None or known[0] is not self.elements:
            known = (self.elements,
                     {f"{e.label()}_{f}": u for e in self.elements for f, u in e.parameter_units().items()})
            self.__dict__["_parameter_units"] = known
        return dict(known[1])

    def parameter_table(self):
        """The parameters as text: name, SI value, unit, element (one line each)."""
        units = self.parameter_units
        owner = {f"{e.label()}_{f}": type(e).__name__ for e in self.elements for f in e.parameters()}
        width = max(len(n) for n in units)
        lines = [f"{'parameter':<{width}s}  {'value':>12s}  {'unit':<10s}  element"]
        for name, value in self.parameters.items():
            lines.append(f"{name:<{width}s}  {value:12.6g}  {units[name] or '-':<10s}  {owner[name]}")
        return "\n".join(lines)

    @property
    def effects(self):
        """The effects this model holds (only these contribute terms and states)."""
        out = set()
        for e in self.elements:
            out |= set(e.effects())
        return frozenset(out)

    def masses(self):
        """(station, [point-mass elements]) in station order: elements with a ``mass`` giving x inertia there."""
        return [(s, [e for e in self.elements_at(s) if (s, "x") in e.inertia() and getattr(e, "mass", None) is not None])
                for s in self.stations]

    def time_event_parameters(self):
        """Names of parameters whose values are times at which the equations jump."""
        return tuple(f"{e.label()}_{f}" for e in self.elements for f in e.time_event_fields())

    def fixed_time_events(self):
        """Event times that are fixed numbers (not parameters)."""
        out = []
        for e in self.elements:
            out.extend(e.fixed_time_events())
        return tuple(out)

    @property
    def structure_key(self):
        """Hash of everything the equations' form depends on (not parameter values)."""
        known = self.__dict__.get("_structure_key")  # elements are frozen: computed once per elements tuple
        if known is not None and known[0] is self.elements and known[1] == FORMAT_VERSION:
            return known[2]
        import hashlib  # here, not at import: a model that is only read and built needs no hash

        text = repr((FORMAT_VERSION, tuple(e.structure() for e in self.elements)))
        key = hashlib.sha256(text.encode()).hexdigest()[:20]
        self.__dict__["_structure_key"] = (self.elements, FORMAT_VERSION, key)
        return key

    # -- actions ----------------------------------------------------------
    def equations(self):
        """Derive (once per structure) the :class:`~rotorkit.symbolic.lagrange.EquationsOfMotion`."""
        from .symbolic.lagrange import derive

        return derive(self)

    def save(self, path, **options):
        """Write the model to ``path`` as a TOML model file (see :mod:`rotorkit.modelfile`); returns the path."""
        from .modelformat import save_model

        return save_model(self, path, **options)

    def compile(self, backend="auto", codegen="auto"):
        """Compile into a numeric :class:`~rotorkit.system.System` (see :func:`~rotorkit.system.compile_model`)."""
        from .system import compile_model

        return compile_model(self, backend=backend, codegen=codegen)

    def _repr_html_(self):
        """Jupyter display: elements and parameters as tables."""
        from .display import model_html

        return model_html(self)

    def __repr__(self):
        return (f"Model({self.name!r}: {len(self.elements)} elements, {len(self.coordinate_names)} coordinates, "
                f"effects={sorted(self.effects)})")
