"""Axial positions of the stations of a model, from the lengths of its beam and shaft segments.

:func:`station_positions` places each rotor's stations along it (its first station at 0);
:func:`shaft_edges` and :func:`walk_positions` are the graph of segment lengths it walks, also used to
draw a rotor.
"""

from __future__ import annotations

__all__ = ["shaft_edges", "station_positions", "walk_positions"]


def station_positions(model):
    """Station -> axial position (m) along each rotor from its beam and shaft lengths, or None.

    Each rotor's first station is at 0; a beam segment's nodes are equally
    spaced over its length. Stations no length reaches are left out.
    """
    edges = shaft_edges(model)
    if not edges:
        return None
    positions = {}
    for station in map(str, model.stations):
        if station not in positions and station in edges:
            positions[station] = 0.0
            walk_positions(station, edges, positions)
    return positions


def shaft_edges(model):
    """Station (str) -> ``[(neighbour, signed length m)]`` of every beam or shaft segment with a length."""
    edges = {}
    for e in model.elements:
        length = getattr(e, "length", None)
        if length is None or not hasattr(e, "start") or not hasattr(e, "end"):
            continue
        nodes = e.nodes() if hasattr(e, "nodes") else (e.start, e.end)
        step = float(length) / (len(nodes) - 1)
        for a, b in zip(nodes, nodes[1:]):
            edges.setdefault(str(a), []).append((str(b), step))
            edges.setdefault(str(b), []).append((str(a), -step))
    return edges


def walk_positions(start, edges, positions):
    """Place every station reachable from ``start`` (already in ``positions``) along ``edges``; the list of them."""
    stack, reached = [start], []
    while stack:
        a = stack.pop()
        for b, step in edges.get(a, ()):
            if b not in positions:
                positions[b] = positions[a] + step
                reached.append(b)
                stack.append(b)
    return reached
