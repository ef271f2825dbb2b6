"""Shear force and bending moment along the shaft, from the static solution.

The static deflection ``q`` (:func:`~rotorkit.linear.static.static_deflection`,
``K q = F``) gives the force every element that is not a beam exerts on
the shaft's stations at rest, ``F_e = F_e(0) - K_e q``
(:func:`~rotorkit.linear.linear_matrices.element_forces`: a bearing's
reaction, a disk's weight), and each beam segment's own weight, a uniform
load ``q_w`` per unit length (its consistent loads summed over its length).
Walking the shaft from its free left end, per bending plane ``(w, beta)``
(``(x, thy)`` and ``(y, -thx)``, see :mod:`rotorkit.elements.beam`)::

    V(z+) = V(z-) + F_w          at a station loaded by F_w (N) along w
    M(z+) = M(z-) - C_beta       and by a couple C_beta (N m) on beta
    V' = q_w,   M' = V           between stations

so that ``M = EI w''`` (positive sagging: a simply supported beam loaded
towards ``-w`` has ``M > 0``) and ``V = dM/dz``; these are the element end
forces ``K_e u_e - F_e(0)`` of virtual work on ``1/2 int EI beta'^2 dz``
(``V(a+) = -f_w(a)``, ``M(a+) = f_beta(a)`` at an element's left end ``a``).
The right end closes to zero when the loads balance (checked: the
residual is :attr:`ShearMoment.closure`). A tapered segment's weight is
taken as uniform over its length (an approximation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["ShearMoment", "shear_moment"]

_AXES = ("thx", "thy", "x", "y")


def _split(name):
    for axis in _AXES:
        if name.startswith(axis) and len(name) > len(axis):
            return axis, name[len(axis):]
    return None, None


@dataclass(frozen=True, eq=False)
class ShearMoment:
    """Shear force and bending moment along the shaft in the two bending planes.

    Attributes
    ----------
    positions : numpy.ndarray, shape (3 m,)
        Axial position (m) of the left end, the middle and the right end of
        each of the ``m`` intervals between consecutive stations along the
        shaft (a station between two intervals appears twice: the diagram
        jumps there under a concentrated load).
    shear : numpy.ndarray, shape (3 m, 2)
        Shear force (N) in the x-z and y-z planes, ``V = dM/dz``.
    moment : numpy.ndarray, shape (3 m, 2)
        Bending moment (N m), ``M = EI w''`` (positive sagging).
    elements : tuple of str
        The beam segment of each interval between stations.
    closure : (float, float)
        ``|V|`` (N) and ``|M|`` (N m) left past the shaft's right end: zero
        when the static loads balance (rounding only).
    """

    positions: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    elements: tuple
    closure: tuple = (0.0, 0.0)

    @property
    def shear_magnitude(self):
        """``sqrt(Vx^2 + Vy^2)`` (N), shape (3 m,)."""
        return np.hypot(self.shear[:, 0], self.shear[:, 1])

    @property
    def moment_magnitude(self):
        """``sqrt(Mx^2 + My^2)`` (N m), shape (3 m,)."""
        return np.hypot(self.moment[:, 0], self.moment[:, 1])

    def max_moment(self):
        """``(position m, |M| N m)`` of the largest bending moment."""
        k = int(np.argmax(self.moment_magnitude))
        return float(self.positions[k]), float(self.moment_magnitude[k])

    def to_csv(self, path=None):
        """One row per point: position (m), Vx, Vy (N), Mx, My (N m); text, or written to ``path``."""
        from ..linear.tables import csv_output

        rows = ["element,position_m,shear_x_N,shear_y_N,moment_x_N_m,moment_y_N_m"]
        for i, z in enumerate(self.positions):
            rows.append(f"{self.elements[i // 3]},{z:.10g},{self.shear[i, 0]:.10g},{self.shear[i, 1]:.10g},"
                        f"{self.moment[i, 0]:.10g},{self.moment[i, 1]:.10g}")
        return csv_output("\n".join(rows) + "\n", path)

    def plot(self, axes=None):
        """Shear (top) and moment (bottom) diagrams of both planes; the two axes."""
        import matplotlib.pyplot as plt

        if axes is None:
            _, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        for j, plane in enumerate(("x-z", "y-z")):
            axes[0].plot(self.positions, self.shear[:, j], label=f"{plane} plane")
            axes[1].plot(self.positions, self.moment[:, j], label=f"{plane} plane")
        for ax in axes:
            ax.axhline(0.0, color="0.6", lw=0.6)
            ax.legend(fontsize=8)
        axes[0].set_ylabel("shear force V (N)")
        axes[1].set_ylabel("bending moment M (N m)")
        axes[1].set_xlabel("axial position (m)")
        return axes


def gravity_field(model, t):
    """The uniform load field ``(a_x, a_y)`` (m/s^2) of the model's Maneuver at ``t`` (zero without one)."""
    import sympy as sp

    for e in model.elements:
        if hasattr(e, "acceleration") and hasattr(e, "kind"):
            p = {name: getattr(e, name) for name in ("gravity", "roll_rate", "roll_radius", "roll_start", "roll_end")
                 if isinstance(getattr(e, name, None), (int, float))}
            ts = sp.Symbol("t", real=True)
            return tuple(float(sp.sympify(a).subs(ts, t).evalf()) for a in e.acceleration(ts, p))
    return 0.0, 0.0


def shear_moment(model, t=0.0, deflection=None):
    """Shear force and bending moment diagrams of the shaft of a linear ``model`` at rest.

    Parameters
    ----------
    model : rotorkit.Model
        One rotor of beam segments, with disks and linear bearings (a
        model whose equations are linear), and a static load (gravity, a
        manoeuvre).
    t : float, str or pint.Quantity
        Time (s) of the loads.
    deflection : rotorkit.linear.static.StaticDeflection, optional
        The static solution, if computed already (default: solved here).

    Returns
    -------
    ShearMoment

    Raises
    ------
    ParameterError
        If the model is not linear, has no beam segment, or its beams are
        on more than one rotor.
    """
    from ..linear.linear_matrices import element_forces, station_positions
    from ..linear.static import static_deflection
    from ..codegen.linear_cache import linear_module, template_function
    from ..units import to_si

    model = getattr(model, "model", model)
    t = float(to_si(t, "s", "t"))
    module = linear_module(model)
    if not module.LINEAR:
        raise ParameterError(f"shear_moment: {model.name!r} is not linear (contacts, Hertzian bearings); "
                             "expected a model of beams, disks and linear bearings")
    beams = [e for e in model.elements if getattr(e, "length", None) is not None
             and hasattr(e, "start") and hasattr(e, "end")]
    if not beams:
        raise ParameterError(f"shear_moment: {model.name!r} has no beam segment; expected BeamSegment elements")
    rotors = {model.rotor_of(e.start).name for e in beams}
    if len(rotors) > 1:
        raise ParameterError(f"shear_moment: {model.name!r} has beams on the rotors {sorted(rotors)}; expected one")
    if deflection is None:
        deflection = static_deflection(model, t)
    names = tuple(model.coordinate_names)
    q = np.array([deflection.deflection[n] for n in names], dtype=float)
    positions = station_positions(model) or {}
    labels = {e.label() for e in beams}
    # the load field (gravity, a manoeuvre) on the beams: each segment's consistent share at its nodes
    # (its mass matrix times the rigid-body field, as the Maneuver loads it) is replaced by a uniform load
    values = model.parameters
    p = [0.0 if name.endswith("_eccentricity") else float(values[name]) for name in module.PARAMETERS]
    field = gravity_field(model, t)
    a_vec = np.array([field[0] if _split(n)[0] == "x" else field[1] if _split(n)[0] == "y" else 0.0 for n in names])
    beam_share = {}
    spans = []
    for template, params, coords, label in module.ELEMENTS:
        if label not in labels:
            continue
        matrix, lrows, lcols = module.TEMPLATES[template][:3]
        mass = [e for e, w in enumerate(matrix) if w == 0]
        total = {"x": 0.0, "y": 0.0}
        if mass and np.any(a_vec):
            for e, v in zip(mass, template_function(module, template, tuple(mass))([p[k] for k in params], t)):
                force = float(v) * a_vec[coords[lcols[e]]]
                key = _split(names[coords[lrows[e]]])
                beam_share[key] = beam_share.get(key, 0.0) + force
                if key[0] in total:
                    total[key[0]] += force
        zs = [positions[s] for s in {_split(names[c])[1] for c in coords} if s in positions]
        if len(zs) < 2:
            raise ParameterError(f"shear_moment: beam segment {label!r} has no axial positions; expected its "
                                 "stations placed along the shaft")
        lo, hi = min(zs), max(zs)
        spans.append((lo, hi, label, total["x"] / (hi - lo), total["y"] / (hi - lo)))
    # what the other elements (bearings, disks under the load field) exert on each station at rest
    others = [e for e in model.elements if e.label() not in labels]
    external = {key: -value for key, value in beam_share.items()}
    for forces in (element_forces(model, q, t, None, others) or {}).values():
        for name, value in forces.items():
            axis, station = _split(name)
            if axis is not None:
                external[(axis, station)] = external.get((axis, station), 0.0) + value
    stations = sorted({s for lo, hi, *_ in spans for s, z in positions.items() if lo - 1e-12 <= z <= hi + 1e-12},
                      key=lambda s: positions[s])
    V, M = np.zeros(2), np.zeros(2)
    z_out, v_out, m_out, owners = [], [], [], []

    def jump(station):
        for j, (w, beta, sign) in enumerate((("x", "thy", 1.0), ("y", "thx", -1.0))):
            V[j] += external.get((w, station), 0.0)
            M[j] -= sign * external.get((beta, station), 0.0)

    for left, right in zip(stations, stations[1:]):
        za, zb = positions[left], positions[right]
        if zb - za <= 0:
            continue
        jump(left)
        middle = 0.5 * (za + zb)
        span = next((s for s in spans if s[0] - 1e-12 <= middle <= s[1] + 1e-12), None)
        if span is None:
            raise ParameterError(f"shear_moment: no beam segment between stations {left!r} and {right!r}")
        load = np.array(span[3:5])
        length = zb - za
        for dz in (0.0, 0.5 * length, length):
            z_out.append(za + dz)
            v_out.append(V + load * dz)
            m_out.append(M + V * dz + 0.5 * load * dz * dz)
        owners.append(span[2])
        M += V * length + 0.5 * load * length * length
        V += load * length
    jump(stations[-1])
    z = np.array(z_out)
    shear, moment = np.array(v_out), np.array(m_out)
    for arr in (z, shear, moment):
        arr.setflags(write=False)
    return ShearMoment(positions=z, shear=shear, moment=moment, elements=tuple(owners),
                       closure=(float(np.max(np.abs(V))), float(np.max(np.abs(M)))))
