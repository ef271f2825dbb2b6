"""Stations of a coordinate list: which coordinates are the ``x``/``y`` (or tilt) pair of one station.

Kept apart from :mod:`~rotorkit.linear.whirl` (which gives them as before) so that a linear model, an
unbalance response or a static deflection, which need the pairs but no orbit, do not load the whirl
module and its :class:`~rotorkit.linear.whirl.Orbit` class.
"""

from __future__ import annotations

import functools
import re

__all__ = ["station_pairs", "tilt_pairs"]


def station_pairs(names):
    """``[(station, i_x, i_y)]`` of the stations with both an ``x<s>`` and a ``y<s>`` coordinate, in order."""
    return list(_axis_pairs(tuple(names), "x", "y"))


def tilt_pairs(names):
    """``[(station, i_thx, i_thy)]`` of the stations with both tilts ``thx<s>`` and ``thy<s>``, in order."""
    return list(_axis_pairs(tuple(names), "thx", "thy"))


@functools.lru_cache(maxsize=64)
def _axis_pairs(names, first, second):
    index = {name: i for i, name in enumerate(names)}
    pattern = re.compile(rf"{first}(.+)")
    out = []
    for name in names:
        m = pattern.fullmatch(name)
        if m and f"{second}{m.group(1)}" in index:
            out.append((m.group(1), index[name], index[f"{second}{m.group(1)}"]))
    return tuple(out)
