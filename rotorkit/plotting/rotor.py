"""The rotor drawn along its axis: where stations are, shaft outline, disks, bearings.

:func:`rotor_layout` reads a :class:`~rotorkit.Model` once into a small
:class:`RotorLayout` (plain numbers, no matplotlib): the axial position of
every station, spool by spool, each spool placed where it is (a spool
joined to another by an inter-shaft bearing is shifted so the bearing's two
stations share one axial position), the shaft segments with their radii,
the disks and the bearings. :func:`draw_rotor` draws it in a band of an
existing axes, under a mode shape or a deflection.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["RotorLayout", "rotor_layout", "draw_rotor"]


@dataclass(frozen=True)
class RotorLayout:
    """What a drawing of the rotor needs.

    Attributes
    ----------
    positions : dict of str to float
        Station -> axial position (m) of the stations beam or shaft lengths
        reach (spools aligned by their inter-shaft bearings).
    rotors : dict of str to str
        Station -> name of its rotor (spool).
    shafts : tuple of (float, float, float, float)
        ``(z_start, z_end, outer_radius, inner_radius)`` (m) of each beam
        element; radius 0 for a lumped shaft (drawn as a line).
    disks : tuple of (float, float)
        ``(z, outer_radius)`` (m); radius 0 when the disk has none.
    bearings : tuple of (float, str, bool)
        ``(z, label, inter_shaft)`` of each element holding the rotor.
    """

    positions: dict
    rotors: dict
    shafts: tuple = ()
    disks: tuple = ()
    bearings: tuple = ()

    @property
    def span(self):
        """Largest minus smallest axial position (m), 0 without positions."""
        return max(self.positions.values()) - min(self.positions.values()) if self.positions else 0.0


def _rotor_name(model, station):
    for candidate in (station, _as_int(station)):
        try:
            return model.rotor_of(candidate).name
        except (KeyError, TypeError):
            continue
    return None


def _as_int(text):
    try:
        return int(text)
    except (TypeError, ValueError):
        return text


def rotor_layout(model):
    """The :class:`RotorLayout` of a :class:`~rotorkit.Model` (a System's ``.model``)."""
    model = getattr(model, "model", model)
    from ..linear.linear_matrices import shaft_edges, walk_positions

    edges = shaft_edges(model)
    stations = [str(s) for s in model.stations]
    positions, component = {}, {}
    for s in stations + sorted(edges):
        if s in positions or s not in edges:
            continue
        index = len(set(component.values()))
        positions[s], component[s] = 0.0, index
        component.update(dict.fromkeys(walk_positions(s, edges, positions), index))
    # place the pieces: an element linking stations of two pieces (an inter-shaft bearing) puts them together
    links = []
    for e in model.elements:
        for group in e.stiffness_links():
            linked = [str(st) for st, _ in group if str(st) in component]
            for a, b in zip(linked, linked[1:]):
                if component[a] != component[b]:
                    links.append((a, b))
    placed = {component[stations[0]] if stations and stations[0] in component else 0}
    changed = True
    while changed:
        changed = False
        for a, b in links:
            ca, cb = component[a], component[b]
            if (ca in placed) == (cb in placed):
                continue
            if cb in placed:
                a, b, ca, cb = b, a, cb, ca
            shift = positions[a] - positions[b]
            for s, c in component.items():
                if c == cb:
                    positions[s] += shift
            placed.add(cb)
            changed = True
    rotors = {s: _rotor_name(model, s) for s in positions}
    rotors.update({str(s): model.rotor_of(s).name for s in model.stations})
    shafts, disks, bearings = [], [], []
    for e in model.elements:
        length = getattr(e, "length", None)
        if length is not None and hasattr(e, "start") and hasattr(e, "end"):
            a, b = str(e.start), str(e.end)
            if a in positions and b in positions:
                outer = getattr(e, "outer_diameter", None)
                inner = getattr(e, "inner_diameter", None) or 0.0
                shafts.append((positions[a], positions[b], 0.5 * float(outer) if outer else 0.0, 0.5 * float(inner)))
            continue
        if type(e).__name__ == "Disk" and str(e.station) in positions:
            disks.append((positions[str(e.station)], float(e.radius or 0.0)))
            continue
        grounded = [str(st) for st, _ in e.grounds() if str(st) in positions]
        linked = [str(st) for group in e.stiffness_links() for st, _ in group if str(st) in positions]
        inter = len({rotors.get(s) for s in linked}) > 1
        where = grounded or (linked if inter else [])
        if where:
            bearings.append((positions[where[0]], e.label(), bool(inter and not grounded)))
    return RotorLayout(positions=positions, rotors=rotors, shafts=tuple(shafts), disks=tuple(disks),
                       bearings=tuple(bearings))


def draw_rotor(ax, layout, *, bottom=-0.55, top=-0.1, scale=1.0, color="0.55"):
    """Draw ``layout`` in the band ``bottom`` .. ``top`` of ``ax``'s y axis (data units), axial positions as x.

    The largest radius (disk or shaft) fills half the band's height; shafts
    are outlined, disks filled, bearings drawn as triangles under the shaft
    (inter-shaft bearings as diamonds on it). ``scale`` multiplies the x
    coordinates (m -> the axis unit). Returns ``ax``.
    """
    from matplotlib.patches import Polygon, Rectangle

    centre, half = 0.5 * (bottom + top), 0.5 * (top - bottom)
    radii = [r for *_, r, _ in layout.shafts] + [r for _, r in layout.disks]
    largest = max(radii) if radii and max(radii) > 0 else 1.0
    k = 0.9 * half / largest
    span = max(layout.span, 1e-9) * scale
    for z0, z1, ro, ri in layout.shafts:
        a, b = sorted((z0 * scale, z1 * scale))
        if ro > 0:
            ax.add_patch(Rectangle((a, centre - ro * k), b - a, 2 * ro * k, facecolor="0.88", edgecolor=color, lw=0.6))
            if ri > 0:
                ax.add_patch(Rectangle((a, centre - ri * k), b - a, 2 * ri * k, facecolor="white", edgecolor=color,
                                       lw=0.4))
        else:
            ax.plot([a, b], [centre, centre], color=color, lw=2.0)
    width = 0.012 * span
    for z, r in layout.disks:
        r = r if r > 0 else 0.5 * largest
        ax.add_patch(Rectangle((z * scale - width / 2, centre - r * k), width, 2 * r * k, facecolor=color,
                               edgecolor="0.3", lw=0.5))
    tri = 0.025 * span
    for z, _, inter in layout.bearings:
        x = z * scale
        if inter:
            ax.plot([x], [centre], marker="D", color="0.25", ms=5, ls="none")
        else:
            apex = centre - 0.55 * half
            ax.add_patch(Polygon([(x, apex), (x - tri / 2, bottom), (x + tri / 2, bottom)], closed=True,
                                 facecolor="0.25", edgecolor="none"))
    ax.axhline(centre, color=color, lw=0.4, ls="-.", zorder=0)
    return ax
