"""Proportional (Rayleigh) structural damping of a rotor: ``C = alpha M + beta K`` on its shaft and disks.

``Rotor(name="R", stations=..., speed=..., damping=Rayleigh(alpha, beta))``
adds, to the rotor's equations, the viscous damping matrix
``C = alpha M_r + beta K_r`` where ``M_r`` is the mass matrix of the
rotor's own structure (beam elements, tapered beams, disks, lumped masses)
and ``K_r`` the stiffness matrix of its shaft (beam elements and shaft
segments), both at rest; bearings, seals, supports and pedestals are not
part of it. The damping is *non-rotating* (it acts in the fixed frame,
like material damping measured on the shaft at rest): it adds no
circulatory terms. A mode ``k`` of ``M_r``, ``K_r`` of natural frequency
``w_k`` then has the damping ratio ::

    zeta_k = alpha / (2 w_k) + beta w_k / 2

(exact when the supports are part of ``K_r`` or negligible in that mode).
:meth:`Rayleigh.from_damping_ratios` picks ``alpha``, ``beta`` from two
modal damping ratios, the usual way engineers give it.

Rotating internal damping (hysteretic or viscous damping of the spinning
shaft material) would add, besides ``beta K``, the circulatory matrix
``-beta Omega K_skew`` (the rotating-frame damping seen in the fixed frame,
destabilising above the first critical speed); it is *not* included here.

The two coefficients are parameters of the rotor, ``<rotor>_damping_alpha``
(1/s) and ``<rotor>_damping_beta`` (s): they stay symbols in the derived
equations, so a sweep over them does not re-derive.

The rotor's structure is every element of the rotor whose class lists
``"mass"`` or ``"stiffness"`` in its ``structure_matrices``
(:class:`~rotorkit.elements.base.Element`): beams both, disks and lumped
masses their mass, shaft segments their stiffness. A new element type joins
it by setting that class attribute; this module imports no element type.

:class:`ModalDamping` is the other damping spec a rotor takes: damping
ratios of the model's undamped non-rotating modes, a numeric matrix that
the linear analyses add to their damping and the compiled equations take as
run-time parameters (:mod:`rotorkit.linear.modal_damping`); it contributes
no terms here.

Source: Rayleigh, *The Theory of Sound* (1877), section 97; Friswell et al.,
*Dynamics of Rotating Machines* (2010), section 2.5.5 (proportional damping)
and section 5.7 (internal damping).
"""

import math
import numbers
from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..errors import ParameterError
from ..units import to_si

__all__ = ["Rayleigh", "ModalDamping", "PREFIX"]

#: rotor parameter names of the damping: ``<rotor>_damping_alpha``, ``<rotor>_damping_beta``
PREFIX = "damping_"
_UNITS = {"alpha": "1/s", "beta": "s"}


@dataclass(frozen=True, slots=True)
class Rayleigh:
    """Proportional damping ``C = alpha M + beta K`` of a rotor's structure (non-rotating).

    Parameters
    ----------
    alpha : float or pint.Quantity
        Mass-proportional coefficient (1/s), >= 0.
    beta : float or pint.Quantity
        Stiffness-proportional coefficient (s), >= 0.

    Examples
    --------
    >>> d = Rayleigh.from_damping_ratios((0.02, "100 rad/s"), (0.02, "1000 rad/s"))
    >>> round(d.damping_ratio(100.0), 6), round(d.damping_ratio(1000.0), 6)
    (0.02, 0.02)
    >>> Rayleigh(alpha=-1.0)
    Traceback (most recent call last):
    ...
    rotorkit.errors.ParameterError: Rayleigh.alpha = -1.0: expected a value >= 0
    """

    alpha: float = 0.0
    beta: float = 0.0

    #: field -> (SI unit, sign rule), as for elements (model files write the units)
    _units: ClassVar[Mapping[str, tuple]] = {"alpha": ("1/s", "nonnegative"), "beta": ("s", "nonnegative")}

    def __post_init__(self):
        for name, unit in _UNITS.items():
            value = getattr(self, name)
            if value is None or isinstance(value, bool):
                raise ParameterError(f"Rayleigh.{name} = {value!r}: expected a number in {unit}, >= 0")
            si = to_si(value, unit, f"Rayleigh.{name}")
            if not si >= 0:
                raise ParameterError(f"Rayleigh.{name} = {si!r}: expected a value >= 0")
            object.__setattr__(self, name, si)

    @classmethod
    def from_damping_ratios(cls, first, second):
        """The ``alpha``, ``beta`` that give two modes the damping ratios asked for.

        Solves ``zeta_i = alpha / (2 w_i) + beta w_i / 2`` for both modes;
        a pair that needs a negative coefficient is a ParameterError.

        Parameters
        ----------
        first, second : tuple
            ``(zeta, w)``: damping ratio (-) at a natural frequency ``w``
            (rad/s, or a quantity such as ``"50 turn/s"``); two different
            frequencies.
        """
        (z1, w1), (z2, w2) = first, second
        w1 = to_si(w1, "rad/s", "Rayleigh.from_damping_ratios: first frequency", sign="positive")
        w2 = to_si(w2, "rad/s", "Rayleigh.from_damping_ratios: second frequency", sign="positive")
        if math.isclose(w1, w2):
            raise ParameterError(f"Rayleigh.from_damping_ratios: frequencies {w1:g} and {w2:g} rad/s are equal; "
                                 "give two different modes")
        z1 = to_si(z1, "", "Rayleigh.from_damping_ratios: first damping ratio", sign="nonnegative")
        z2 = to_si(z2, "", "Rayleigh.from_damping_ratios: second damping ratio", sign="nonnegative")
        beta = 2 * (z2 * w2 - z1 * w1) / (w2**2 - w1**2)
        alpha = 2 * w1 * w2 * (z1 * w2 - z2 * w1) / (w2**2 - w1**2)
        if alpha < -1e-15 * abs(beta) * w1 * w2 or beta < 0:
            raise ParameterError(f"Rayleigh.from_damping_ratios: zeta = {z1:g} at {w1:g} rad/s and {z2:g} at "
                                 f"{w2:g} rad/s need alpha = {alpha:.4g} 1/s, beta = {beta:.4g} s; expected ratios "
                                 "that Rayleigh damping can give (both coefficients >= 0)")
        return cls(alpha=max(alpha, 0.0), beta=beta)

    def damping_ratio(self, frequency):
        """``alpha / (2 w) + beta w / 2`` at the natural frequency ``w`` (rad/s, float or array)."""
        return self.alpha / (2 * frequency) + self.beta * frequency / 2

    # -- as parameters of the rotor --------------------------------------------
    def parameters(self):
        """Rotor field -> SI value: ``{"damping_alpha": ..., "damping_beta": ...}``."""
        return {PREFIX + name: getattr(self, name) for name in _UNITS}

    @staticmethod
    def unit_of(field_name):
        """SI unit of ``alpha``/``beta`` or of the rotor fields ``damping_alpha``/``damping_beta``."""
        return _UNITS[field_name[len(PREFIX):] if field_name.startswith(PREFIX) else field_name]

    def replace(self, **fields):
        """A copy with rotor fields (``damping_alpha=...``) changed (SI floats)."""
        values = {name: getattr(self, name) for name in _UNITS}
        values.update({k[len(PREFIX):]: v for k, v in fields.items()})
        return Rayleigh(**values)


@dataclass(frozen=True, slots=True)
class ModalDamping:
    """Modal damping ratios of a model's undamped, non-rotating modes.

    ``Rotor(..., damping=ModalDamping(ratios=(0.01, 0.02), remaining=0.0))``
    gives the ``k``-th lowest undamped mode of the model at rest (every
    rotor at speed 0, symmetric part of the stiffness, bearings and supports
    included) the damping ratio ``ratios[k]``, and every further mode
    ``remaining``, by the viscous matrix ``C = M Phi diag(2 zeta_k w_k) Phi^T M``
    (:mod:`rotorkit.linear.modal_damping`). The matrix depends on every
    parameter through the modes, so it is numeric: the linear analyses
    (modes, Campbell, unbalance and frequency responses) add it to their
    damping at the parameter values of the call, and a compiled system
    (time simulation, ``natural_frequencies``) holds the force ``-C q'``
    with ``C``'s entries as run-time parameters, computed once per parameter
    set (:func:`~rotorkit.linear.modal_damping.with_modal_damping`); it adds
    no term to the derived equations. The ratios are part of the spec, not
    parameters: change them with ``dataclasses.replace`` (no re-derivation).
    At most one rotor of a model holds it (the modes are the model's).

    Parameters
    ----------
    ratios : sequence of float
        Damping ratios (-) of the lowest modes, in ascending frequency; each
        finite, in [0, 1); at least one.
    remaining : float
        Damping ratio (-) of every further mode, in [0, 1); default 0.

    Examples
    --------
    >>> ModalDamping(ratios=(0.01, 0.02)).ratios
    (0.01, 0.02)
    >>> ModalDamping(ratios=(0.01, 1.2))
    Traceback (most recent call last):
    ...
    rotorkit.errors.ParameterError: ModalDamping.ratios[1] = 1.2: expected a damping ratio in [0, 1)
    """

    ratios: tuple = ()
    remaining: float = 0.0

    def __post_init__(self):
        ratios = self.ratios
        if isinstance(ratios, (str, bytes)) or not hasattr(ratios, "__len__") or len(ratios) == 0:
            raise ParameterError(f"ModalDamping.ratios = {ratios!r}: expected a non-empty sequence of damping "
                                 "ratios (-), e.g. (0.01, 0.02)")
        checked = []
        for i, z in enumerate(list(ratios) + [self.remaining]):
            name = f"ratios[{i}]" if i < len(ratios) else "remaining"
            if isinstance(z, bool) or not isinstance(z, numbers.Real) or not 0 <= float(z) < 1:
                raise ParameterError(f"ModalDamping.{name} = {z!r}: expected a damping ratio in [0, 1)")
            checked.append(float(z))
        object.__setattr__(self, "ratios", tuple(checked[:-1]))
        object.__setattr__(self, "remaining", checked[-1])

    def parameters(self):
        """No rotor parameters: the ratios are part of the spec (``{}``)."""
        return {}

    def replace(self, **fields):
        if fields:
            raise ParameterError(f"ModalDamping has no parameters; got {sorted(fields)}")
        return self


def _hessian(expr, variables, zero):
    """``{(a, b): d^2 expr / da db}`` at rest (``zero`` substituted) over the ``variables`` it holds."""
    import sympy as sp

    expr = sp.sympify(expr)
    present = [v for v in variables if v in expr.free_symbols]
    out = {}
    for a in present:
        da = sp.diff(expr, a)
        for b in present:
            value = sp.diff(da, b).xreplace(zero)
            if value != 0:
                out[(a, b)] = value
    return out


def rayleigh_terms(rotor, ctx):
    """:class:`~rotorkit.elements.base.Terms` of ``rotor.damping``: ``C = alpha M_r + beta K_r`` as quadratic forms.

    ``M_r`` and ``K_r`` are taken from the contributions of the rotor's
    structural elements (their finite-element forms, and the Hessians of
    their kinetic and potential energies at rest with zero unbalance).
    """
    import sympy as sp

    from .base import QuadraticForm, Terms

    alpha, beta = ctx.p[PREFIX + "alpha"], ctx.p[PREFIX + "beta"]
    model = ctx.model
    pairs = [ctx.coord(s, a) for s, a in model.coordinates]
    qs, us = [q for q, _ in pairs], [u for _, u in pairs]
    speed_of, rate_of = dict(zip(us, qs)), dict(zip(qs, us))
    forms = []
    for e in model.elements:
        makes_mass, makes_stiffness = ("mass" in e.structure_matrices), ("stiffness" in e.structure_matrices)
        if not (makes_mass or makes_stiffness):  # the rotor's structure: beams, disks, lumped masses, shafts
            continue
        if any(model.rotor_of(s) is not rotor for s in e.attached_stations()):
            continue
        bound = ctx.bind(e)
        terms = e.contribute(bound)
        for form in terms.quadratic:
            C = None
            if makes_mass and form.mass is not None:
                C = alpha * sp.Matrix(form.mass)
            if makes_stiffness and form.stiffness is not None:
                C = beta * sp.Matrix(form.stiffness) if C is None else C + beta * sp.Matrix(form.stiffness)
            if C is not None:
                forms.append(QuadraticForm(coordinates=form.coordinates, speeds=form.speeds, damping=C))
        zero = {s: 0 for s in qs + us}
        zero.update({sym: 0 for f, sym in bound.p.items() if f == "eccentricity"})
        entries = {}
        if makes_mass:
            for (a, b), v in _hessian(terms.kinetic, us, zero).items():
                entries[(a, b)] = entries.get((a, b), 0) + alpha * v
        if makes_stiffness:
            rest = _hessian(terms.potential, qs, zero)
            for (a, b), v in rest.items():
                ua, ub = rate_of[a], rate_of[b]
                entries[(ua, ub)] = entries.get((ua, ub), 0) + beta * v
        if entries:
            speeds = sorted({a for a, _ in entries} | {b for _, b in entries}, key=us.index)
            C = sp.Matrix(len(speeds), len(speeds), lambda i, j: entries.get((speeds[i], speeds[j]), 0))
            forms.append(QuadraticForm(coordinates=tuple(speed_of[u] for u in speeds), speeds=tuple(speeds),
                                       damping=C))
    return Terms(quadratic=tuple(forms))

