"""The model as an element sees it while contributing terms (:class:`Context`).

Used by the derivation (:mod:`rotorkit.symbolic.lagrange`), the static and
energy analyses and the elements; lower than :mod:`rotorkit.model` so that
none of them imports the model module.
"""

from .errors import TopologyError

__all__ = ["Context"]


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
        """(q, q') symbols of a station's coordinate.

        ``axis`` is ``"x"``, ``"y"`` (lateral displacement, m), ``"alpha"``
        (torsion angle about +z, rad), ``"thx"``, ``"thy"`` (small rotations
        of the cross-section about +x and +y, rad; ``thy = dx/dz``,
        ``thx = -dy/dz``) or any axis an element created. With
        ``drive=True`` a missing torsional coordinate gives ``(0, 0)``: the
        station turns exactly at the rotor speed.
        """
        name = f"{axis}{station}"
        if name not in self._symbols.coordinates:
            if drive and axis == "alpha":
                import sympy as sp

                return sp.S.Zero, sp.S.Zero
            raise TopologyError(f"{self._element!r}: station {station!r} has no coordinate {name}")
        return self._symbols.coordinates[name], self._symbols.speeds[name]

    def _root(self, station):
        import sympy as sp

        rotor = self.model.rotor_of(station)
        expr = sp.S.One
        while rotor.speed is None:
            expr *= self._symbols.parameter(f"{rotor.name}_speed_ratio")
            rotor = self.model.rotors[rotor.reference]
        return expr, rotor

    def speed(self, station):
        """Spin speed (rad/s) of the station's rotor, as an expression (of ``t`` for a speed profile)."""
        ratio, rotor = self._root(station)
        return ratio * rotor.speed_expression(self.t, self._symbols.parameter)

    def spin_angle(self, station):
        """Spin angle (rad) of the station's rotor, ``integral_0^t speed``: ``Omega t`` at constant speed."""
        ratio, rotor = self._root(station)
        return ratio * rotor.angle_expression(self.t, self._symbols.parameter)

    def speed_is_constant(self, station):
        """Whether the station's rotor spins at a constant speed (no speed profile, no speed degree of freedom)."""
        rotor = self._root(station)[1]
        return rotor.profile is None and rotor.drive is None

    def parameter(self, element, field_name):
        """The parameter symbol of another element's field."""
        return self._symbols.parameter(f"{element.label()}_{field_name}")

    def rigid_body_masses(self):
        """Coordinate symbol -> ``(Q_x, Q_y)`` summed over all elements (see ``Element.rigid_body_mass``)."""
        out = {}
        for e in self.model.elements:
            for q, (qx, qy) in e.rigid_body_mass(self.bind(e)).items():
                if q in out:
                    out[q] = (out[q][0] + qx, out[q][1] + qy)
                else:
                    out[q] = (qx, qy)
        return out

    def masses(self):
        """(station, total point-mass expression) for every station."""
        out = []
        for station, items in self.model.masses():
            out.append((station, sum(self._symbols.parameter(f"{e.label()}_mass") for e in items)))
        return out

    def disk_radius(self, station):
        """Radius symbol of the element at ``station`` that has a ``radius`` (a disk)."""
        for e in self.model.elements_at(station):
            if getattr(e, "radius", None) is not None and "radius" in e.parameters():
                return self._symbols.parameter(f"{e.label()}_radius")
        raise TopologyError(f"station {station!r} has no disk with a radius")
