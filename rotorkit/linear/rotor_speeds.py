"""Rotor spin speeds at a time, and models with every speed profile frozen to a constant speed.

:func:`rotor_spin_speeds` gives each rotor's spin (rad/s) at a time, profiles evaluated there and speed ratios
applied; :func:`frozen_speed_model` replaces each speed-profile (or driven) rotor by a constant-speed one, so
that the linear analyses can sweep ``<rotor>_speed``. :func:`expression_namespace` holds the names generated
float expressions are evaluated with (:mod:`math`, ``min``, ``max``, ``abs``).
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import ParameterError

__all__ = ["expression_namespace", "frozen_speed_model", "rotor_spin_speeds"]


def expression_namespace():
    """The names a generated float expression runs with: :mod:`math`, ``max``, ``min`` and ``abs``."""
    namespace = dict(vars(math))
    namespace.update({"max": max, "min": min, "abs": abs})
    return namespace



def _profile_speed(rotor, t):
    """A profile rotor's speed (rad/s) at time ``t`` (a driven rotor's: its initial speed)."""
    import sympy as sp

    if rotor.drive is not None:
        return rotor.drive.initial_speed

    from ..codegen.printer import RhsPrinter

    profile = rotor.profile
    ts = sp.Symbol("t", real=True)
    p = {k: sp.Float(v) for k, v in profile.values().items()}
    code = RhsPrinter().doprint(profile.speed(ts, p).xreplace({ts: sp.Float(float(t))}))
    return float(eval(code, {"__builtins__": {}}, expression_namespace()))


def rotor_spin_speeds(model, t=0.0, values=None):
    """Rotor name -> spin speed (rad/s) at time ``t`` (profiles evaluated there, ratios applied)."""
    values = model.parameters if values is None else values
    rotors = model.rotors
    out = {}
    for name in rotors:
        factor, r = 1.0, rotors[name]
        while r.speed is None:
            factor *= values[f"{r.name}_speed_ratio"]
            r = rotors[r.reference]
        if r.drive is not None:
            out[name] = factor * values[f"{r.name}_speed_initial"]
            continue
        out[name] = factor * (_profile_speed(r, t) if r.profile is not None else values[f"{r.name}_speed"])
    return out


def frozen_speed_model(model, t=0.0, speeds=None):
    """``model`` with every speed-profile rotor turned into a constant-speed one (itself if there is none).

    A rotor whose speed is a :class:`~rotorkit.elements.drive.Drive` (a
    degree of freedom) is frozen at its ``initial_speed``: the linear
    analyses hold the spin constant.

    Parameters
    ----------
    model : rotorkit.Model
    t : float
        Time (s) at which each profile gives its speed.
    speeds : dict, optional
        Rotor name -> speed (rad/s) to use instead of the profile's at ``t``.

    Raises
    ------
    ParameterError
        If ``speeds`` names a rotor without a speed profile.
    """
    speeds = dict(speeds or {})
    profiles = {name: r for name, r in model.rotors.items() if r.profile is not None or r.drive is not None}
    unknown = set(speeds) - set(profiles)
    if unknown:
        raise ParameterError(
            f"speeds={speeds!r}: {sorted(unknown)} have no speed profile; expected rotors among "
            f"{sorted(profiles) or 'none'} (set the speed of a constant-speed rotor with <rotor>_speed)")
    if not profiles:
        return model
    elements = []
    for e in model.elements:
        if e.owned_stations() and e.label() in profiles:
            value = speeds.get(e.label())
            value = _profile_speed(e, t) if value is None else float(value)
            e = dataclasses.replace(e, speed=value)
        elements.append(e)
    return type(model)(elements, name=model.name)
