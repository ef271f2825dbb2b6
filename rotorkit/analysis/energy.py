"""Energy balance of a simulated model: the Jacobi integral and the work done on it.

For a Lagrangian system with ``L = T(q, q', t) - V(q, t)``, Rayleigh
dissipation ``D(q')`` and generalised loads ``Q(q, q', t)``, the Jacobi
integral ::

    h = q' . dT/dq' - T + V

changes at the rate ::

    dh/dt = -dL/dt|explicit  -  q' . dD/dq'  +  Q . q'
            (drive)             (damping)       (loads, per element)

(from Lagrange's equations ``d/dt dL/dq' - dL/dq = -dD/dq' + Q``). Rotors
spinning at a prescribed speed make ``T`` depend on ``t`` explicitly (the
unbalance centroid turns with ``Omega t``): ``-dL/dt`` is the power the
constant-speed drive puts into the vibration. So, with ``W(t)`` the work of
all three power terms since the first sample,

    residual(t) = h(t) - h(t0) - W(t)

is zero for the exact solution. For a numerical solution it holds the
solver's error (the states are only as good as ``rtol``/``atol``) plus the
quadrature error of ``W`` on the samples. :func:`energy_balance` computes it
from a :class:`~rotorkit.result.Result`; :func:`energy_terms` gives the
symbolic pieces.

Quadrature
----------
``W`` integrates the power on the samples with a piecewise-cubic rule: each
interval integrates the cubic through the 4 samples around it (fourth order;
``(-1, 13, 13, -1) h / 24`` on a uniform grid). Two things in the models are
not smooth, and both are handled:

- contact switches: ``ramp(g)``, ``step(g)`` and ``contact_ratio(r, delta)``
  in a power channel give it a kink (or a jump) where ``g`` (``r - delta``)
  changes sign. Where that happens between two samples, the interval is split
  at the (linearly interpolated) crossing, each part integrated with samples
  from its own side only, and the neighbouring intervals' stencils keep to
  their side. Hertzian contacts ``ramp(g)**n`` with ``n > 1`` are once
  continuously differentiable and integrated as smooth; with many balls they
  set the quadrature's floor (order about 2, see ``quadrature_error``);
- time events: the manoeuvre's loads jump at the model's time events (the
  same ones :func:`~rotorkit.simulate` restarts at), so the integration is
  split there and each side evaluated with time clamped inside its own
  segment, as the solver saw it (an event between two samples is handled by
  extrapolating each side's cubic to it).

``quadrature_error`` is a bound on what the sampling adds to the residual:
``max|W - W_2h|``, the difference between the work on all samples and on
every second one. It also picks up the sampled states' own roughness (the
solver's dense output), so it levels off near the solver's error. Choose the
sample rate so that it stays well below the residual you want to resolve:
for the AL-31F preset about 100 kHz at ``rtol = 1e-6`` and 400 kHz at
``rtol = 1e-9``; very stiff contact (``k_r = 1e9 N/m``: short grazes)
needs several times more.

Scale of the relative residual
------------------------------
``relative_residual = max|residual| / scale`` with the mechanical energy
scale ::

    scale = max( max_t |h(t) - h(t0)|,  max_t q'^T M(q, t) q' / 2 )

the larger of the largest change of ``h`` and the largest kinetic energy of
the motion relative to the prescribed spin (``M`` the mass matrix): the
energy the motion holds. Neither grows with the length of the run, so the
ratio says how large the worst energy error along the run is against the
energy of the motion itself: on a conservative or bouncing-contact run it
is the relative energy error, whatever the run length. (Dividing by the
energy that flowed through all channels, which keeps growing, understated
long runs' errors.) Errors that accumulate, per cycle of drive in and
damping out, make it grow with run length, as they should. ``flow``, the
total energy that passed through all power channels counted without
cancellation, is kept for comparison; only a run with no motion at all
(``scale`` 0) is measured against it. ``h`` itself is only defined up to a
constant (its part free of ``q``, ``q'`` and ``t``, such as
``-J Omega^2 / 2``, is dropped), so ``|h|`` is no scale.

Examples
--------
>>> import rotorkit as rk
>>> from rotorkit.analysis.energy import energy_balance
>>> model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0),
...                   rk.Disk(station=1, mass=2.0, radius=0.1),
...                   rk.ElasticSupport(station=1, stiffness=2e4, damping=4.0)])
>>> system = model.compile()
>>> result = rk.simulate(system, (0.0, 0.5), y0=system.initial_state(x1=1e-3),
...                      rtol=1e-10, atol=1e-13, sample_rate=20_000)
>>> balance = energy_balance(model, result)
>>> round(float(balance.h[0]), 6)              # k x^2 / 2 (J)
0.01
>>> bool(balance.relative_residual < 1e-8)
True
>>> bool(balance.dissipated.min() >= 0.0)      # damping takes energy out
True
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import sympy as sp

from ..errors import ParameterError
from ..plotting.energy import plot_energy_balance
from .energy_numeric import EnergyEvaluator
from .work_quadrature import Piece, cumulative_work, kinks_of, quadrature_error

__all__ = ["EnergyTerms", "EnergyBalance", "energy_terms", "energy_balance", "plot_energy_balance"]


#: power channels that are not element loads
DRIVE, DAMPING = "drive", "damping"


# -- symbolic terms ---------------------------------------------------------
@dataclass(frozen=True)
class EnergyTerms:
    """The symbolic pieces of the energy balance of one model structure.

    Attributes
    ----------
    t : sympy.Symbol
    coordinates, speeds, parameters : tuple of sympy.Symbol
        As in :class:`~rotorkit.symbolic.lagrange.EquationsOfMotion`.
    jacobi : sympy.Expr
        ``h = q' . dT/dq' - T + V`` without its constant part (J).
    power : dict
        Name -> power flowing into the system (W), as sympy expressions:
        ``"drive"`` (``-dL/dt`` at fixed ``q, q'``), ``"damping"``
        (``-q' . dD/dq'``, <= 0) and one entry per element with loads (its
        label, ``Q_e . q'``). ``dh/dt`` is their sum.
    motion : sympy.Expr
        ``q'^T M(q, t) q' / 2``: the kinetic energy of the motion relative
        to the prescribed spin (J), used for the scale of the residual.
    """

    t: sp.Symbol
    coordinates: tuple
    speeds: tuple
    parameters: tuple
    jacobi: sp.Expr
    power: dict = field(default_factory=dict)
    motion: sp.Expr = sp.S.Zero

    @property
    def names(self):
        """Names of the power channels, in order."""
        return tuple(self.power)


_TERMS = {}
_FUNCTIONS = {}


def _as_model(model):
    from ..model import Model

    inner = getattr(model, "model", None)  # a compiled System
    if isinstance(inner, Model):
        return inner
    if isinstance(model, Model):
        return model
    raise ParameterError(f"energy balance: expected a rotorkit Model or System, got {type(model).__name__}")


def _drop_constant(expr, dynamic):
    """``expr`` without its additive terms that are free of the dynamic symbols."""
    expr = sp.expand(expr)
    return sp.Add(*[a for a in sp.Add.make_args(expr) if a.free_symbols & dynamic])


def _element_loads(model, eom):
    """Element label -> {coordinate symbol: load expression} of every element with loads."""
    from ..context import Context
    from ..symbolic.lagrange import Symbols

    ctx = Context(model, Symbols(model))
    out = {}
    for element in model.elements:
        loads = element.contribute(ctx.bind(element)).loads
        loads = {q: sp.sympify(v) for q, v in loads.items() if sp.sympify(v) != 0}
        if loads:
            out[element.label()] = loads
    return out


def energy_terms(model):
    """The symbolic Jacobi integral and power channels of ``model`` (cached per structure).

    Parameters
    ----------
    model : rotorkit.Model or rotorkit.System

    Returns
    -------
    EnergyTerms

    Raises
    ------
    ParameterError
        A power channel would be named like an element (``"drive"``, ``"damping"``).
    """
    model = _as_model(model)
    key = model.structure_key
    if key in _TERMS:
        return _TERMS[key]
    eom = model.equations()
    qs, us, t = tuple(eom.coordinates), tuple(eom.speeds), eom.t
    T, V, D = sp.sympify(eom.kinetic), sp.sympify(eom.potential), sp.sympify(eom.dissipation)
    momentum = sum((u * sp.diff(T, u) for u in us if u in T.free_symbols), sp.S.Zero)
    dynamic = set(qs) | set(us) | {t}
    jacobi = _drop_constant(momentum - T + V, dynamic)
    power = {
        DRIVE: sp.expand(-sp.diff(T - V, t)),
        DAMPING: sp.expand(-sum((u * sp.diff(D, u) for u in us if u in D.free_symbols), sp.S.Zero)),
    }
    index = {q: i for i, q in enumerate(qs)}
    for label, loads in _element_loads(model, eom).items():
        if label in power:
            raise ParameterError(f"energy balance: an element is labelled {label!r}, the name of a power channel; "
                                 "give it another name=...")
        power[label] = sum((load * us[index[q]] for q, load in loads.items()), sp.S.Zero)
    u = sp.Matrix(us)
    motion = sp.expand((u.T * eom.mass_matrix * u)[0, 0] / 2)
    terms = EnergyTerms(t=t, coordinates=qs, speeds=us, parameters=tuple(eom.parameters), jacobi=jacobi,
                        power=power, motion=motion)
    _TERMS[key] = terms
    return terms


def _evaluator(model):
    key = model.structure_key
    if key not in _FUNCTIONS:
        _FUNCTIONS[key] = EnergyEvaluator(energy_terms(model))
    return _FUNCTIONS[key]


# -- quadrature ---------------------------------------------------------------
#: weights of the cubic through 4 equally spaced samples, integrated over one spacing, by the
#: position of the interval: after the 1st sample (nodes -1, 0, 1, 2: the centred stencil), at the
#: start of the samples (0, 1, 2, 3) and at their end (-2, -1, 0, 1)
# -- the balance --------------------------------------------------------------
@dataclass(frozen=True)
class EnergyBalance:
    """The energy balance of a simulated run (see the module docstring).

    Attributes
    ----------
    t : numpy.ndarray
        Sample times (s), shape (n,).
    h : numpy.ndarray
        Jacobi integral ``q' . dT/dq' - T + V`` (J), shape (n,), up to a constant.
    power_in : mapping of str to numpy.ndarray
        Power flowing into the system (W), each shape (n,): ``"drive"``
        (``-dL/dt`` at fixed ``q, q'``: the constant-speed drive), ``"damping"``
        (``-q' . dD/dq'``, <= 0) and one entry per element with loads, by
        label (``"rub2"``, ``"bearing4_7"``, ``"maneuver"``: ``Q_e . q'``).
        At a sample on a time event the value is the one after the event.
    work : mapping of str to numpy.ndarray
        ``int_t0^t`` of each ``power_in`` entry (J), each shape (n,).
    residual : numpy.ndarray
        ``h - h(t0) - sum(work)`` (J), shape (n,).
    scale : float
        The mechanical energy scale ``max(max|h - h0|, max q'^T M q' / 2)``
        (J), which does not grow with run length; see the module docstring.
    relative_residual : float
        ``max|residual| / scale``: the largest excursion of the residual
        along the run against the energy of the motion.
    quadrature_error : float
        Bound (J) on the part of ``max|residual|`` due to integrating the
        power on the samples: ``max|W - W_(every 2nd sample)|``. It also
        picks up the sampled states' own roughness, so it levels off near
        the solver's error (see the module docstring).
    events : tuple of float
        Time events (s) the integration was split at.
    flow : float
        ``sum_k int |P_k| dt`` (J): the energy that passed through all power
        channels, counted without cancellation (grows with run length).
    """

    t: np.ndarray
    h: np.ndarray
    power_in: Mapping
    work: Mapping
    residual: np.ndarray
    scale: float
    relative_residual: float
    quadrature_error: float
    events: tuple = ()
    flow: float = 0.0

    @property
    def dissipated(self):
        """Power taken out by the Rayleigh dissipation, ``q' . dD/dq'`` (W), >= 0, shape (n,)."""
        return -self.power_in[DAMPING]

    @property
    def loads(self):
        """Element label -> power of its loads (W), shape (n,) each."""
        return {k: v for k, v in self.power_in.items() if k not in (DRIVE, DAMPING)}

    @property
    def total_work(self):
        """``W(t)``: the work of all power channels since ``t0`` (J), shape (n,)."""
        return sum(self.work.values(), np.zeros_like(self.t))

    @property
    def relative_quadrature_error(self):
        """``quadrature_error / scale``."""
        return self.quadrature_error / self.scale if self.scale > 0 else 0.0

    def summary(self):
        """A few lines: the change of ``h``, the work per channel and the residual."""
        lines = [f"energy balance over t = {self.t[0]:g} .. {self.t[-1]:g} s ({self.t.size} samples)",
                 f"  h(t_end) - h(t0)   {self.h[-1] - self.h[0]: .6e} J"]
        for name, w in self.work.items():
            lines.append(f"  work {name:<13s} {w[-1]: .6e} J")
        lines += [f"  max |residual|     {np.max(np.abs(self.residual)): .3e} J",
                  f"  scale              {self.scale: .3e} J",
                  f"  relative residual  {self.relative_residual: .3e} "
                  f"(quadrature part ~ {self.relative_quadrature_error:.1e})"]
        return "\n".join(lines)

    def plot(self, ax=None, **kwargs):
        """Plot ``h - h0``, the work per channel and the residual; returns the matplotlib Axes."""
        return plot_energy_balance(self, ax=ax, **kwargs)


def _events(model, parameters, t0, t1):
    times = [parameters[n] for n in model.time_event_parameters()] + list(model.fixed_time_events())
    return tuple(sorted({float(e) for e in times if t0 < e < t1}))


def _parameter_vector(terms, parameters):
    names = [str(p) for p in terms.parameters]
    missing = [n for n in names if n not in parameters]
    if missing:
        raise ParameterError(f"energy balance: result.parameters lacks {', '.join(missing)}; "
                             "use the Result of a simulation of this model")
    return [float(parameters[n]) for n in names]


def _states(terms, result):
    names = [str(q) for q in terms.coordinates]
    missing = [n for n in names + [f"{n}_dot" for n in names] if n not in result.state_names]
    if missing:
        raise ParameterError(f"energy balance: the result has no states {', '.join(missing[:4])} "
                             f"(states: {', '.join(result.state_names)}); is it a run of this model?")
    q = np.array([result[n] for n in names], dtype=float)
    u = np.array([result[f"{n}_dot"] for n in names], dtype=float)
    return q, u


def _balance_on(evaluator, t, q, u, p, cuts):
    """h and energy in motion at the samples, and the samples of each segment as pieces."""
    pieces = []
    h, motion = np.empty(t.size), np.empty(t.size)
    switches = np.empty((len(evaluator.switches), t.size))
    for k, (a, b) in enumerate(zip(cuts[:-1], cuts[1:])):
        idx = np.flatnonzero((t >= a) & (t <= b))
        # time as the solver saw it inside this segment (clamped just inside, like System.within)
        lo = np.nextafter(a, b) if k > 0 else a
        hi = np.nextafter(b, a) if k < len(cuts) - 2 else b
        ts = np.clip(t[idx], lo, hi)
        hs, ms, powers, sw = evaluator(ts, q[:, idx], u[:, idx], p)
        h[idx] = hs  # a boundary sample takes the later segment's value (h is continuous)
        motion[idx] = ms
        pieces.append(Piece(idx=idx, powers=powers, kinks=kinks_of(t[idx], sw)))
        switches[:, idx] = sw
    return h, motion, pieces, switches


def _add_modal_damping(model, parameters, terms, u, pieces):
    """Add the power ``-q' . C q'`` of a rotor's ModalDamping (a numeric matrix, no term of ``D``) to "damping"."""
    from ..linear.modal_damping import coordinate_damping_matrix, modal_damping_spec

    if modal_damping_spec(model) is None:  # the usual case: no model rebuilt at the run's values
        return
    own = set(model.parameters)
    C = coordinate_damping_matrix(model.with_values(**{k: v for k, v in parameters.items() if k in own}),
                                  terms.coordinates)
    if C is None:
        return
    for piece in pieces:
        us = u[:, piece.idx]
        piece.powers[DAMPING] = piece.powers[DAMPING] - np.einsum("it,ij,jt->t", us, C, us)


def energy_balance(model, result):
    """The energy balance of ``result``, a run of ``model``.

    Parameters
    ----------
    model : rotorkit.Model or rotorkit.System
        The model that was simulated (only its structure is used; parameter
        values come from ``result.parameters``).
    result : rotorkit.Result
        Samples of the run (a failed run's ``err.partial`` works too), at
        least 2 samples; states ``q`` and ``q_dot`` by name.

    Returns
    -------
    EnergyBalance

    Raises
    ------
    ParameterError
        The result does not belong to the model (states or parameters
        missing), has fewer than 2 samples or non-finite states, or the
        energy or power overflows (a run-away to absurd amplitudes).

    Notes
    -----
    The symbolic terms are derived once per model structure and the numeric
    functions built once (sympy ``lambdify``; a few seconds for the AL-31F
    preset); later calls only evaluate them.
    """
    model = _as_model(model)
    t = np.array(result.t, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ParameterError(f"energy balance: the result has {t.size} samples; at least 2 are needed")
    if np.any(np.diff(t) <= 0):
        raise ParameterError("energy balance: the result's sample times must increase strictly")
    terms = energy_terms(model)
    evaluator = _evaluator(model)
    p = _parameter_vector(terms, result.parameters)
    q, u = _states(terms, result)
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(u))):
        raise ParameterError("energy balance: the result holds non-finite states (NaN or inf)")
    events = _events(model, result.parameters, t[0], t[-1])
    cuts = [float(t[0]), *events, float(t[-1])]
    h, motion, pieces, switches = _balance_on(evaluator, t, q, u, p, cuts)
    _add_modal_damping(model, result.parameters, terms, u, pieces)
    names = terms.names
    bad = ~np.isfinite(h) | ~np.isfinite(motion)
    for piece in pieces:
        for values in piece.powers.values():
            bad[piece.idx] |= ~np.isfinite(values)
    if np.any(bad):
        first = int(np.argmax(bad))
        raise ParameterError(
            f"energy balance: the energy or power overflows from t = {t[first]:.6g} s on (largest state "
            f"{np.max(np.abs(np.concatenate([q[:, first], u[:, first]]))):.3g}); evaluate it on the samples "
            "before, e.g. energy_balance(model, result.window(t0, t1))")
    flow = "\0|P|"  # the sum of |P_k| over the channels, for the scale (integrated with the same rule)
    for piece in pieces:
        piece.powers[flow] = sum((np.abs(piece.powers[name]) for name in names), np.zeros(piece.idx.size))
    work = cumulative_work(t, pieces, cuts, [*names, flow])
    absolute = work.pop(flow)[-1]
    for piece in pieces:
        del piece.powers[flow]
    total = sum(work.values(), np.zeros_like(t))
    residual = h - h[0] - total
    power_in = {name: np.empty(t.size) for name in names}
    for piece in pieces:
        for name, values in piece.powers.items():
            power_in[name][piece.idx] = values
    scale = max(float(np.max(np.abs(h - h[0]))), float(np.max(motion)))
    if not scale > 0:  # no motion at all: only the flow is left to compare with
        scale = float(absolute)
    quad = quadrature_error(t, pieces, switches, cuts, total) if names else 0.0
    rel = float(np.max(np.abs(residual)) / scale) if scale > 0 else 0.0
    for arr in (t, h, residual, *power_in.values(), *work.values()):
        arr.setflags(write=False)
    return EnergyBalance(t=t, h=h, power_in=MappingProxyType(power_in), work=MappingProxyType(work),
                         residual=residual, scale=scale,
                         relative_residual=rel, quadrature_error=quad, events=events, flow=float(absolute))
