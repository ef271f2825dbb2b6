"""A model: a checked, immutable set of elements and the effects it holds."""

import dataclasses
import difflib
import hashlib
from collections import defaultdict

import sympy as sp

from .elements import BallBearing, Disk, Element, ElasticSupport, LumpedMass, Maneuver, Rotor, RubStator, ShaftSegment
from .errors import ParameterError, TopologyError
from .units import to_si

__all__ = ["Model"]

#: bump when the derivation or generated code changes, to invalidate caches
FORMAT_VERSION = "4"


class Model:
    """A rotor system assembled from elements.

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
        Unknown or duplicate stations, a station without mass, a rotor with
        no support, a bearing within one rotor, a torsional coordinate with
        no torsional stiffness path.

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
        self.rotors = {e.name: e for e in elements if isinstance(e, Rotor)}
        self._station_rotor = self._map_stations()
        self._check_speeds()
        self._check_attachments()
        self.disks = {e.station: e for e in elements if isinstance(e, Disk)}
        self.torsion_stations = tuple(s for s in self.stations if s in self.disks and self.disks[s].torsion)
        self._check_masses()
        self._check_elements()
        self._check_bending_support()
        self._check_torsion_paths()
        self.coordinate_names = tuple(
            [f"x{s}" for s in self.stations] + [f"y{s}" for s in self.stations]
            + [f"alpha{s}" for s in self.torsion_stations]
        )
        self._check_symbol_names()

    # -- topology -------------------------------------------------------
    @property
    def stations(self):
        """All stations, rotor by rotor in axial order."""
        return tuple(self._station_rotor)

    def rotor_of(self, station):
        """The :class:`Rotor` a station belongs to."""
        return self._station_rotor[station]

    def _check_labels(self):
        seen = {}
        for e in self.elements:
            label = e.label()
            if label in seen:
                raise TopologyError(
                    f"Model: two elements are labelled {label!r} ({seen[label]!r} and {e!r}); "
                    "give one of them a distinct name=..."
                )
            seen[label] = e

    def _map_stations(self):
        if not self.rotors:
            raise TopologyError("Model: no Rotor given; add Rotor(name=..., stations=..., speed=...)")
        mapping = {}
        for rotor in self.rotors.values():
            for s in rotor.stations:
                if s in mapping:
                    raise TopologyError(
                        f"Model: station {s!r} is on rotor {mapping[s].name!r} and rotor {rotor.name!r}; "
                        "a station belongs to one rotor"
                    )
                mapping[s] = rotor
        return mapping

    def _check_speeds(self):
        for rotor in self.rotors.values():
            seen, r = [rotor.name], rotor
            while r.speed is None:
                if r.reference not in self.rotors:
                    raise TopologyError(
                        f"Rotor {r.name!r}: reference={r.reference!r} is not a rotor of the model "
                        f"(rotors: {sorted(self.rotors)})"
                    )
                r = self.rotors[r.reference]
                if r.name in seen:
                    raise TopologyError(f"Rotor speeds refer to each other in a loop: {seen + [r.name]}")
                seen.append(r.name)

    def _check_attachments(self):
        for e in self.elements:
            for s in e.attached_stations():
                if s not in self._station_rotor:
                    raise TopologyError(
                        f"{type(e).__name__} {e.label()!r}: station {s!r} is not on any rotor "
                        f"(known stations: {list(self._station_rotor)})"
                    )

    def _check_masses(self):
        mass_stations = defaultdict(list)
        for e in self.elements:
            if isinstance(e, (Disk, LumpedMass)):
                mass_stations[e.station].append(e)
        for s, items in mass_stations.items():
            if sum(isinstance(e, Disk) for e in items) > 1:
                raise TopologyError(f"Model: station {s!r} has more than one Disk; merge them into one")
        for s in self.stations:
            if s not in mass_stations:
                raise TopologyError(
                    f"Model: station {s!r} (rotor {self.rotor_of(s).name!r}) has no mass, so its equations "
                    "are singular; add LumpedMass(station=..., mass=...) or a Disk there"
                )
        self._mass_elements = mass_stations

    def _check_elements(self):
        maneuvers = [e for e in self.elements if isinstance(e, Maneuver)]
        if len(maneuvers) > 1:
            raise TopologyError("Model: more than one Maneuver; a scene has one load field (gravity included)")
        for e in self.elements:
            if isinstance(e, ShaftSegment):
                ra, rb = self.rotor_of(e.start), self.rotor_of(e.end)
                if ra is not rb:
                    raise TopologyError(
                        f"ShaftSegment {e.label()!r}: stations {e.start!r} (rotor {ra.name!r}) and {e.end!r} "
                        f"(rotor {rb.name!r}) are on different rotors; couple rotors with a BallBearing"
                    )
                if e.has_torsion() and not {e.start, e.end} & set(self.torsion_stations):
                    raise TopologyError(
                        f"ShaftSegment {e.label()!r}: torsional stiffness between stations with no torsional "
                        "coordinate has no effect; give a Disk at one end torsion=True, or drop the torsion"
                    )
            if isinstance(e, BallBearing):
                ri, ro = self.rotor_of(e.inner_station), self.rotor_of(e.outer_station)
                if ri is ro:
                    raise TopologyError(
                        f"BallBearing {e.label()!r}: inner_station {e.inner_station!r} and outer_station "
                        f"{e.outer_station!r} are both on rotor {ri.name!r}; an inter-rotor bearing joins "
                        "stations of two different rotors"
                    )
            if isinstance(e, RubStator) and e.station in self.torsion_stations and e.contact_radius is None:
                if self.disks[e.station].radius is None:
                    raise TopologyError(
                        f"RubStator {e.label()!r}: the disk at station {e.station!r} has no radius for the "
                        "friction torque; give contact_radius=... (m)"
                    )

    def _check_bending_support(self):
        neighbours = defaultdict(set)
        grounded = set()
        for e in self.elements:
            if isinstance(e, ShaftSegment) and e.has_bending():
                neighbours[e.start].add(e.end)
                neighbours[e.end].add(e.start)
            elif isinstance(e, BallBearing):
                neighbours[e.inner_station].add(e.outer_station)
                neighbours[e.outer_station].add(e.inner_station)
            elif isinstance(e, ElasticSupport):
                grounded.add(e.station)
        reached, todo = set(grounded), list(grounded)
        while todo:
            for n in neighbours[todo.pop()] - reached:
                reached.add(n)
                todo.append(n)
        for rotor in self.rotors.values():
            loose = [s for s in rotor.stations if s not in reached]
            if loose:
                what = "has no support" if len(loose) == len(rotor.stations) else f"has stations {loose} with no stiffness path to a support"
                raise TopologyError(
                    f"Rotor {rotor.name!r} {what}: it would drift freely; add an ElasticSupport, a "
                    "ShaftSegment with bending stiffness, or a BallBearing to a supported rotor"
                )

    def _check_torsion_paths(self):
        links = defaultdict(set)
        for e in self.elements:
            if isinstance(e, ShaftSegment) and e.has_torsion():
                links[e.start].add(e.end)
                links[e.end].add(e.start)
        torsion = set(self.torsion_stations)
        for s in self.torsion_stations:
            reached, todo = {s}, [s]
            while todo:
                for n in links[todo.pop()] - reached:
                    reached.add(n)
                    if n in torsion:
                        todo.append(n)
            if not reached - torsion:
                raise TopologyError(
                    f"Disk at station {s!r} has torsion=True but no torsional stiffness path to the drive "
                    "(a station without torsional coordinate); add a ShaftSegment with torsional_stiffness "
                    "(or shear_modulus, polar_area_moment, length) from it towards the drive"
                )

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
                near = difflib.get_close_matches(name, list(owners), n=3)
                hint = f"did you mean {', '.join(near)}?" if near else f"parameters are: {', '.join(owners)}"
                raise ParameterError(f"{self.name}: unknown parameter {name!r}; {hint}")
            index, field_name = owners[name]
            element = self.elements[index]
            sign = element._units[field_name][1]
            changes[index][field_name] = to_si(value, element.unit_of(field_name), name, sign=sign)
        elements = list(self.elements)
        for index, fields in changes.items():
            try:
                elements[index] = dataclasses.replace(elements[index], **fields)
            except ParameterError as err:
                label = elements[index].label()
                names = ", ".join(f"{label}_{f} = {v!r}" for f, v in fields.items())
                raise type(err)(f"{names}: {err}") from err
        return Model(elements, name=self.name)

    @property
    def parameter_units(self):
        """Parameter name -> SI unit string."""
        return {f"{e.label()}_{f}": u for e in self.elements for f, u in e.parameter_units().items()}

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
        if any(d.eccentricity is not None for d in self.disks.values()):
            out.add("unbalance")
        if self.torsion_stations:
            out.add("torsion")
        for e in self.elements:
            if isinstance(e, RubStator):
                out.add("rub")
            elif isinstance(e, BallBearing):
                out.add("bearing_nonlinearity")
            elif isinstance(e, Maneuver):
                out.add("gravity" if e.kind == "steady" else "maneuver")
                if e.kind == "barrel_roll" and e.gravity:
                    out.add("gravity")
        return frozenset(out)

    def masses(self):
        """(station, [mass elements]) in station order."""
        return [(s, self._mass_elements[s]) for s in self.stations]

    def time_event_parameters(self):
        """Names of parameters whose values are times at which the equations jump."""
        return tuple(f"{e.label()}_{f}" for e in self.elements for f in e.time_event_fields())

    def fixed_time_events(self):
        """Event times that are fixed numbers (not parameters)."""
        out = []
        for e in self.elements:
            if isinstance(e, Maneuver):
                out.extend(e.fixed_time_events())
        return tuple(out)

    @property
    def structure_key(self):
        """Hash of everything the equations' form depends on (not parameter values)."""
        text = repr((FORMAT_VERSION, tuple(e.structure() for e in self.elements)))
        return hashlib.sha256(text.encode()).hexdigest()[:20]

    # -- actions ----------------------------------------------------------
    def equations(self):
        """Derive (once per structure) the :class:`~rotorkit.symbolic.lagrange.EquationsOfMotion`."""
        from .symbolic.lagrange import derive

        return derive(self)

    def save(self, path, **options):
        """Write the model to ``path`` as a TOML model file (see :mod:`rotorkit.modelfile`); returns the path."""
        from .modelfile import save_model

        return save_model(self, path, **options)

    def compile(self, backend="auto"):
        """Compile into a numeric :class:`~rotorkit.system.System` (see there)."""
        from .system import compile_model

        return compile_model(self, backend=backend)

    def _repr_html_(self):
        """Jupyter display: elements and parameters as tables."""
        from .display import model_html

        return model_html(self)

    def __repr__(self):
        return (f"Model({self.name!r}: {len(self.elements)} elements, {len(self.coordinate_names)} coordinates, "
                f"effects={sorted(self.effects)})")


class Context:
    """The model as an element sees it while contributing terms.

    ``ctx.p`` maps the bound element's fields to its parameter symbols.
    """

    def __init__(self, model, symbols):
        self.model = model
        self.t = symbols.t
        self._symbols = symbols
        self.p = {}
        self._element = None

    def bind(self, element):
        """A copy of the context bound to ``element`` (its parameter symbols in ``p``)."""
        ctx = Context(self.model, self._symbols)
        ctx.p = {f: self._symbols.parameter(f"{element.label()}_{f}") for f in element.parameters()}
        ctx._element = element
        return ctx

    def coord(self, station, axis, drive=False):
        """(q, q') symbols of a station's ``"x"``, ``"y"`` or ``"alpha"`` coordinate.

        With ``drive=True`` a missing torsional coordinate gives ``(0, 0)``:
        the station turns exactly at the rotor speed.
        """
        name = f"{axis}{station}"
        if name not in self._symbols.coordinates:
            if drive and axis == "alpha":
                return sp.S.Zero, sp.S.Zero
            raise TopologyError(f"{self._element!r}: station {station!r} has no coordinate {name}")
        return self._symbols.coordinates[name], self._symbols.speeds[name]

    def speed(self, station):
        """Spin speed (rad/s) of the station's rotor, as an expression."""
        rotor = self.model.rotor_of(station)
        expr = sp.S.One
        while rotor.speed is None:
            expr *= self._symbols.parameter(f"{rotor.name}_speed_ratio")
            rotor = self.model.rotors[rotor.reference]
        return expr * self._symbols.parameter(f"{rotor.name}_speed")

    def masses(self):
        """(station, total mass expression) for every station."""
        out = []
        for station, items in self.model.masses():
            out.append((station, sum(self._symbols.parameter(f"{e.label()}_mass") for e in items)))
        return out

    def disk_radius(self, station):
        """Radius symbol of the disk at ``station``."""
        disk = self.model.disks.get(station)
        if disk is None or disk.radius is None:
            raise TopologyError(f"station {station!r} has no disk with a radius")
        return self._symbols.parameter(f"{disk.label()}_radius")
