"""The force each element exerts at rest, from the cached linear matrices of a linear model.

:func:`element_forces` gives, per element, ``F_e(q) = F_e(0) - K_e q`` at rest (the shear and moment of the
shaft, the support reactions of a static deflection); :func:`loads_at_rest` the sum of every element's force
at rest ``F(0)`` (gravity, preloads), the right-hand side of the static deflection ``K q = F(0)``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["element_forces", "loads_at_rest"]


def element_forces(model, q, t=0.0, values=None, elements=None):
    """Force each element exerts on the coordinates at rest at ``q``, from the cached linear matrices.

    ``F_e(q) = F_e(0) - K_e q`` with zero velocities, ``K_e`` the element's
    own stiffness (cross-coupled part included) and ``F_e(0)`` its force at
    rest (gravity on its mass, a preload); disk eccentricities count as 0.

    Parameters
    ----------
    model : rotorkit.Model
        Rotors with constant speeds.
    q : array_like, shape (n,)
        Coordinates (m, rad) in ``model.coordinate_names`` order.
    t : float
        Time (s).
    values : dict, optional
        Parameter name -> value (SI), default ``model.parameters``.
    elements : sequence of Element, optional
        The elements wanted (default all).

    Returns
    -------
    dict or None
        Element label -> ``{coordinate name: force (N, N m)}`` (nonzero
        entries only), or None if the model is not linear.
    """
    from ..codegen.linear_cache import linear_module, template_function

    module = linear_module(model)
    if not module.LINEAR:
        return None
    values = model.parameters if values is None else values
    names = module.PARAMETERS
    p = [0.0 if name.endswith("_eccentricity") else float(values[name]) for name in names]
    q = np.asarray(q, dtype=float)
    coordinate_names = tuple(model.coordinate_names)
    wanted = None if elements is None else {e.label() for e in elements}
    out = {}
    for template, params, coords, label in module.ELEMENTS:
        if wanted is not None and label not in wanted:
            continue
        matrix, lrows, lcols = module.TEMPLATES[template][:3]
        load_rows, load_exprs = module.TEMPLATES[template][6:8]
        a = [p[k] for k in params]
        force = np.zeros(len(coords))
        if load_exprs:
            force[list(load_rows)] += template_function(module, template, loads=True)(a, float(t))
        stiff = [e for e, w in enumerate(matrix) if w == 2]
        if stiff:
            vals = template_function(module, template, tuple(stiff))(a, float(t))
            for e, v in zip(stiff, vals):
                force[lrows[e]] -= v * q[coords[lcols[e]]]
        forces = {coordinate_names[c]: float(f) for c, f in zip(coords, force) if f != 0.0}
        if forces:
            out[label] = forces
    return out


def loads_at_rest(module, p, t):
    """Sum of every element's force at rest (N, N m), shape (n,)."""
    from ..codegen.linear_cache import template_function

    F = np.zeros(int(module.N_COORDINATES))
    for template, params, coords, _ in module.ELEMENTS:
        load_rows, load_exprs = module.TEMPLATES[template][6:8]
        if load_exprs:
            values = template_function(module, template, loads=True)([p[k] for k in params], t)
            np.add.at(F, np.asarray(coords)[list(load_rows)], values)
    return F
