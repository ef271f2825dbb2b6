"""Static analysis: deflection under gravity or a steady manoeuvre load, and the support reactions.

:func:`static_deflection` solves the static equilibrium of a compiled
system at a time ``t`` (:func:`~rotorkit.analysis.linearize.static_equilibrium`:
gravity, a manoeuvre's load at ``t``, bearings and contacts as they are)
and evaluates, element by element, the force each element that holds the
rotor exerts on it there: ``-dV_e/dq + Q_e`` at zero velocity, from the
element's own energy terms. Which elements hold the rotor is read from the
element contract (:func:`holds_rotor`: what an element grounds or links
across rotors, and contacts), not from class names.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["StaticDeflection", "static_deflection", "holds_rotor"]

def holds_rotor(element, model):
    """Whether ``element`` carries load from the rotor to the ground or to another rotor (element contract).

    True when it declares coordinates it ties to the ground
    (:meth:`~rotorkit.elements.base.Element.grounds`: supports, bearings),
    when one of its :meth:`~rotorkit.elements.base.Element.stiffness_links`
    joins stations of different rotors (inter-shaft and casing bearings) or
    a coordinate the model does not have (a prescribed motion, the ground),
    or when it brings a contact (``"rub"`` in its
    :meth:`~rotorkit.elements.base.Element.effects`). Shafts, beams, disks
    and load fields declare none of these.
    """
    if element.grounds():
        return True
    if "rub" in element.effects():
        return True
    for group in element.stiffness_links():
        stations = {station for station, _ in group}
        if any(not model.has_coordinate(station, axis) for station, axis in group):
            return True
        if len({model.rotor_of(station).name for station in stations}) > 1:
            return True
    return False


@dataclass(frozen=True, eq=False)
class StaticDeflection:
    """Static deflection and support reactions.

    Attributes
    ----------
    deflection : dict of str to float
        Coordinate -> static value (m, rad).
    reactions : dict of str to dict
        Element label -> ``{coordinate: generalised force}`` (N, N m): the
        force the element exerts on the rotor (the load it carries is its
        negative); only nonzero entries.
    t : float
        Time (s) of the loads.
    station_positions : dict or None
    layout : rotorkit.plotting.rotor.RotorLayout or None
        The rotor drawn under the deflection (shaft outline, disks,
        bearings), when the result comes from a model.
    """

    deflection: dict
    reactions: dict
    t: float
    station_positions: dict | None = None
    layout: object = None

    @property
    def stations(self):
        from .stations import station_pairs

        return tuple(s for s, _, _ in station_pairs(tuple(self.deflection)))

    def reaction(self, label, station):
        """``(Fx, Fy)`` (N) of element ``label`` on ``station``."""
        from ..errors import ParameterError

        if label not in self.reactions:
            raise ParameterError(f"label={label!r} carries no load: expected one of {list(self.reactions)}")
        forces = self.reactions[label]
        return forces.get(f"x{station}", 0.0), forces.get(f"y{station}", 0.0)

    def table(self, length_units="um"):
        """Deflection per station and the reactions, as plain text (deflections in ``length_units``)."""
        from ..units import display_factor

        f = display_factor(length_units, "length", "length_units")
        lines = [f"{'station':>8}  {f'x ({length_units})':>14}  {f'y ({length_units})':>14}"]
        for s in self.stations:
            lines.append(f"{s:>8}  {self.deflection[f'x{s}'] * f:>14.5g}  {self.deflection[f'y{s}'] * f:>14.5g}")
        lines.append("")
        lines.append(f"{'element':>14}  {'coordinate':>10}  {'force on rotor (N)':>18}")
        for label, forces in self.reactions.items():
            for name, value in forces.items():
                lines.append(f"{label:>14}  {name:>10}  {value:>18.6g}")
        return "\n".join(lines)

    def to_csv(self, path=None):
        """The deflection (m, rad) per coordinate, then the reactions (N, N m).

        ``path`` (None: the text) as for every linear result (:func:`~rotorkit.analysis.tables.csv_output`).
        """
        from .tables import csv_output

        rows = ["coordinate,deflection_m_or_rad"] + [f"{k},{v:.10g}" for k, v in self.deflection.items()]
        rows += ["", "element,coordinate,force_on_rotor_N"]
        rows += [f"{label},{k},{v:.10g}" for label, forces in self.reactions.items() for k, v in forces.items()]
        return csv_output("\n".join(rows) + "\n", path)

    def to_dataframe(self):
        """``(deflection, reactions)`` as two :class:`pandas.DataFrame` (by coordinate; by element and coordinate)."""
        import pandas as pd

        deflection = pd.DataFrame({"deflection": list(self.deflection.values())},
                                  index=pd.Index(list(self.deflection), name="coordinate"))
        rows = [(label, k, v) for label, forces in self.reactions.items() for k, v in forces.items()]
        reactions = pd.DataFrame(rows, columns=["element", "coordinate", "force_on_rotor"]).set_index(
            ["element", "coordinate"])
        return deflection, reactions

    def plot(self, ax=None, **kwargs):
        """Deflection along the shaft (:func:`rotorkit.plotting.response.plot_static_deflection`)."""
        from ..plotting.response import plot_static_deflection

        return plot_static_deflection(self, ax=ax, **kwargs)


def _evaluate(expr):
    """A number from an expression whose symbols are all replaced (rotorkit's contact functions included)."""
    import math

    from ..codegen.printer import RhsPrinter

    code = RhsPrinter().doprint(expr)
    return float(eval(code, {"__builtins__": {"max": max, "min": min, "abs": abs}}, vars(math)))


def _symbolic_reactions(system, model, holding, q, t):
    """Element label -> force on the rotor at rest at ``q``, from each element's energy terms (any model)."""
    import sympy as sp

    from ..context import Context
    from ..symbolic.lagrange import Symbols

    names = tuple(system.coordinate_names)
    symbols = Symbols(model)
    ctx = Context(model, symbols)
    values = {symbols.parameters[k]: sp.Float(v) for k, v in system.parameters.items()}
    values.update({sym: sp.Float(0) for name, sym in symbols.parameters.items() if name.endswith("_eccentricity")})
    values.update({symbols.coordinates[n]: sp.Float(float(v)) for n, v in zip(names, q)})
    values.update({s: sp.Float(0) for s in symbols.speeds.values()})
    values[symbols.t] = sp.Float(float(t))
    reactions = {}
    for element in holding:
        terms = element.contribute(ctx.bind(element))
        V = sp.sympify(terms.potential)
        forces = {}
        for name in names:
            sym = symbols.coordinates[name]
            expr = -sp.diff(V, sym) if V != 0 and sym in V.free_symbols else sp.S.Zero
            expr += terms.loads.get(sym, sp.S.Zero)
            if expr != 0:
                value = _evaluate(sp.sympify(expr).xreplace(values))
                if value != 0.0:
                    forces[name] = value
        if forces:
            reactions[element.label()] = forces
    return reactions


def static_deflection(system, t=0.0, **equilibrium):
    """Static deflection under the loads at ``t`` and the reactions of the supports.

    Parameters
    ----------
    system : rotorkit.System or rotorkit.Model
        A model whose equations are linear (beams, disks, linear bearings)
        is solved directly, ``K q = F``, from its cached matrices
        (:func:`~rotorkit.analysis.linear_matrices.linear_static_deflection`:
        nothing compiled); any other model is compiled first.
    t : float, str or pint.Quantity
        Time (s) of the load (a manoeuvre's load at that instant; gravity).
    **equilibrium
        Passed to :func:`~rotorkit.analysis.linearize.static_equilibrium`
        (a compiled system, or a model that is not linear or is given
        any of these options).

    Returns
    -------
    StaticDeflection

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Maneuver, Model
    >>> system = Model([Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=2.0, radius=0.1),
    ...                 ElasticSupport(station=1, stiffness=2e4), Maneuver.steady(gravity=9.81)]).compile(
    ...                 backend="python")
    >>> s = static_deflection(system)
    >>> round(s.deflection["y1"] * 1e6, 3), round(s.reaction("support1", 1)[1], 6)   # -m g / k, m g
    (-981.0, 19.62)
    """
    from ..units import to_si
    from .element_loads import element_forces
    from .linear_matrices import linear_static_deflection

    t = to_si(t, "s", "t")
    q = None
    if not hasattr(system, "rhs") and hasattr(system, "compile") and hasattr(system, "elements"):  # a Model
        t = float(t)
        q = None if equilibrium else linear_static_deflection(system, t)
        if q is None:
            system = system.compile()
        else:
            model, parameters, names = system, system.parameters, tuple(system.coordinate_names)
    if q is None:  # not a linear model (or options for the solver): the compiled system's equilibrium
        from .linearize import check_system, static_equilibrium

        check_system(system, "static_deflection")
        q = static_equilibrium(system, t, **equilibrium)
        model, parameters, names = system.model, system.parameters, tuple(system.coordinate_names)

    holding = [e for e in model.elements if holds_rotor(e, model)]
    reactions = element_forces(model, q, t, parameters, holding)  # linear model: the cached matrices
    if reactions is None:
        reactions = _symbolic_reactions(system, model, holding, q, t)
    from ..plotting.rotor import rotor_layout  # plain numbers: no matplotlib
    from .station_positions import station_positions

    return StaticDeflection(deflection=dict(zip(names, (float(v) for v in q))), reactions=reactions, t=float(t),
                            station_positions=station_positions(model), layout=rotor_layout(model))
