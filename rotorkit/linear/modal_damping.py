"""Modal damping: a viscous damping matrix that gives each undamped mode the damping ratio asked for.

From the undamped, non-rotating modes of a model (``K phi = w^2 M phi`` with
the symmetric part of the stiffness at rest, no gyroscopics, mass-normalised
so that ``Phi^T M Phi = I``), the matrix ::

    C = M Phi diag(2 zeta_k w_k) Phi^T M

is diagonal in those modes: mode ``k`` of ``M q'' + C q' + K q = 0`` keeps
its shape and has exactly the damping ratio ``zeta_k`` (Caughey and
O'Kelly 1965; Craig and Kurdila, *Fundamentals of Structural Dynamics*,
2006, section 10.3; Friswell et al. 2010, section 2.5.5). Modes beyond the
ratios given (``remaining``, default 0) and rigid-body modes (``w = 0``) get
no damping. The damping is non-rotating: it adds no circulatory terms, and
at speed the gyroscopic coupling mixes the modes, so their ratios then
differ from ``zeta_k``.

The matrix is numeric (it depends on every parameter through the modes):
:func:`modal_damping_matrix` returns it for a model at given parameter
values. A model whose rotor has ``damping=ModalDamping(ratios=...)``
(:class:`~rotorkit.elements.damping.ModalDamping`) gets it in every linear
analysis: :func:`~rotorkit.linear.linear_matrices.linear_evaluator` adds
:func:`model_modal_damping` (built at rest from the values of the call) to
its ``C``.

In time simulation the compiled right-hand side gets the force ``-C q'``
with ``C``'s entries as *run-time parameters*: :func:`with_modal_damping`
adds to the equations a symmetric matrix of symbols ``_modal_c<i>_<j>``
(``i <= j``, indices of the coordinates), appended to the parameters, so the
code is generated once per structure like every other term; each compiled
system (:class:`~rotorkit.system.System`, at every parameter set: a sweep
point, ``with_parameters``) fills their values from
:func:`runtime_values`, the matrix at its parameter values, at rest, at
``t = 0``. Every back end and engine (python, numba, c, the compiled
integration loop, the analytic Jacobian) then runs it as it runs any
parameter. A model without ModalDamping has no such symbols: its code is
unchanged.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..errors import ParameterError
from .linear_matrices import modal_damping_from_modes, modal_damping_spec, model_modal_damping, undamped_modes

__all__ = ["modal_damping_matrix", "modal_damped_modes", "undamped_modes", "modal_damping_spec",
           "model_modal_damping", "modal_state_term", "refuse_time_run", "check_time_run", "with_modal_damping",
           "runtime_values", "coordinate_damping_matrix", "RUNTIME_PREFIX"]

#: name prefix of the run-time parameters holding the modal damping matrix: ``_modal_c<i>_<j>`` is ``C[i, j]``
RUNTIME_PREFIX = "_modal_c"


def _ratios(ratios, remaining):
    if isinstance(ratios, (str, bytes)) or not hasattr(ratios, "__len__") or len(ratios) == 0:
        raise ParameterError(f"ratios={ratios!r} is invalid: expected a non-empty sequence of damping ratios (-)")
    out = []
    for i, z in enumerate(list(ratios) + [remaining]):
        name = f"ratios[{i}]" if i < len(ratios) else "remaining"
        if isinstance(z, bool) or not isinstance(z, numbers.Real) or not 0 <= z < 1:
            raise ParameterError(f"{name}={z!r} is invalid: expected a damping ratio in [0, 1)")
        out.append(float(z))
    return out[:-1], out[-1]


def modal_damping_matrix(model, ratios, *, remaining=0.0, values=None, t=0.0):
    """``C = M Phi diag(2 zeta_k w_k) Phi^T M`` (N s/m, N m s/rad), shape (n, n), in coordinate order.

    Parameters
    ----------
    model : rotorkit.Model
        A linear model; its undamped non-rotating modes are used.
    ratios : sequence of float
        Damping ratios of the lowest modes, in ascending frequency.
    remaining : float
        Damping ratio of every further mode (default 0).
    values : dict, optional
        Parameter values (SI), default ``model.parameters``.
    t : float
        Time (s) of time-dependent parameters.
    """
    ratios, remaining = _ratios(ratios, remaining)
    M, _, w, Phi = undamped_modes(model, values, t)
    return modal_damping_from_modes(M, w, Phi, ratios, remaining)


def modal_damped_modes(model, ratios, *, remaining=0.0, speed=0.0, values=None, n_modes=None):
    """:class:`~rotorkit.analysis.modal.Modes` of ``model`` with the modal damping added to its own damping.

    ``speed`` (rad/s) is the speed of every rotor with its own constant
    speed (the damping itself is always built at rest).
    """
    from .linear_matrices import linear_matrices
    from .modal import modes_from_matrices

    values = dict(model.parameters if values is None else values)
    C_modal = modal_damping_matrix(model, ratios, remaining=remaining, values=values)
    for name, rotor in model.rotors.items():
        if rotor.speed is not None and f"{name}_speed" in values:
            values[f"{name}_speed"] = float(speed)
    M, C, K = (A.toarray() for A in linear_matrices(model, 0.0, values))
    return modes_from_matrices(M, C + C_modal, K, tuple(model.coordinate_names), n_modes=n_modes, speed=float(speed))


def refuse_time_run(model, who):
    """Raise ParameterError if ``model`` holds a ModalDamping: for runs whose equations do not include it.

    :func:`~rotorkit.simulate.simulate` runs it (:func:`check_time_run`);
    analyses that evaluate the equations their own way (harmonic balance)
    call this to refuse such a model by name.
    """
    if modal_damping_spec(model) is not None:
        raise ParameterError(f"{who}: model {getattr(model, 'name', None)!r} has Rotor(damping=ModalDamping(...)), "
                             f"a numeric damping that {who} does not include (simulate and the linear analyses "
                             "do). Use Rayleigh(alpha, beta) (Rayleigh.from_damping_ratios) here, or simulate, or "
                             "the linear analyses (rotorkit.linear_model(model).modes(), campbell, "
                             "unbalance_response, frequency_response)")


def check_time_run(system, who):
    """Raise ParameterError if ``system``'s model holds a ModalDamping that its right-hand side leaves out.

    A system compiled by :func:`~rotorkit.system.compile_model` carries it
    (``system.modal_damping`` is True); a reduced system does not.
    """
    model = getattr(system, "model", None)
    if modal_damping_spec(model) is not None and not getattr(system, "modal_damping", False):
        raise ParameterError(f"{who}: model {getattr(model, 'name', None)!r} has Rotor(damping=ModalDamping(...)), "
                             f"which this {type(system).__name__} leaves out of its equations (a reduced system "
                             "does); simulate model.compile() instead, or use Rayleigh(alpha, beta) "
                             "(Rayleigh.from_damping_ratios)")


def with_modal_damping(eom, model):
    """``eom`` with the modal damping force ``-C q'`` added, ``C``'s entries run-time parameter symbols.

    ``C`` is symmetric: one symbol ``_modal_c<i>_<j>`` (``i <= j``) per pair of
    the coordinates the linear analyses hold (all but a driven rotor's spin
    angle), appended to ``eom.parameters`` (values: :func:`runtime_values`).
    ``damping`` and ``forcing`` change; ``dissipation`` and the element
    forces do not (the energy balance adds its power itself: :func:`coordinate_damping_matrix`).

    Parameters
    ----------
    eom : rotorkit.symbolic.lagrange.EquationsOfMotion
        The model's derived equations.
    model : rotorkit.Model
        The model (its linear coordinates).

    Returns
    -------
    EquationsOfMotion
    """
    import dataclasses

    import sympy as sp

    from .rotor_speeds import frozen_speed_model

    linear = set(frozen_speed_model(model).coordinate_names)
    damped = [i for i, q in enumerate(eom.coordinates) if str(q) in linear]
    symbols, entries = [], {}
    for a, i in enumerate(damped):
        for j in damped[a:]:
            c = sp.Symbol(f"{RUNTIME_PREFIX}{i}_{j}", real=True)
            symbols.append(c)
            entries[(i, j)] = entries[(j, i)] = c
    n = eom.n
    C = sp.ImmutableSparseMatrix(n, n, entries)
    rows = [sp.Add(*[entries[(i, j)] * eom.speeds[j] for j in damped]) if i in damped else sp.S.Zero
            for i in range(n)]
    return dataclasses.replace(eom, damping=sp.ImmutableSparseMatrix(eom.damping + C),
                               forcing=sp.ImmutableMatrix(eom.forcing - sp.Matrix(rows)),
                               parameters=tuple(eom.parameters) + tuple(symbols))


def runtime_values(model, names, coordinate_names):
    """``{name: C[i, j]}`` for the run-time parameters ``names`` (``_modal_c<i>_<j>``) of :func:`with_modal_damping`.

    ``C`` is :func:`model_modal_damping` of ``model`` at its parameter values
    (speed profiles and drives frozen at ``t = 0``, every rotor at rest);
    ``coordinate_names`` are the system's, which ``i``, ``j`` index.
    """
    from .rotor_speeds import frozen_speed_model

    frozen = frozen_speed_model(model)
    C = model_modal_damping(frozen, frozen.parameters, 0.0)
    where = {name: k for k, name in enumerate(frozen.coordinate_names)}
    out = {}
    for name in names:
        i, j = (int(k) for k in name[len(RUNTIME_PREFIX):].split("_"))
        out[name] = float(C[where[coordinate_names[i]], where[coordinate_names[j]]])
    return out


def coordinate_damping_matrix(model, coordinate_names):
    """The modal damping matrix ``C`` (n, n) over ``coordinate_names``, or None without a ModalDamping.

    ``C`` is the one the compiled equations hold (:func:`with_modal_damping`):
    :func:`model_modal_damping` of ``model`` at its parameter values, at rest;
    rows and columns of coordinates the linear analyses do not hold (a
    driven rotor's spin angle) are zero. Used by the energy balance for the
    power ``-q' . C q'`` this damping takes out.
    """
    from .rotor_speeds import frozen_speed_model

    if modal_damping_spec(model) is None:
        return None
    frozen = frozen_speed_model(model)
    C = model_modal_damping(frozen, frozen.parameters, 0.0)
    where = {name: k for k, name in enumerate(frozen.coordinate_names)}
    index = [where.get(str(name)) for name in coordinate_names]
    out = np.zeros((len(index), len(index)))
    for a, i in enumerate(index):
        for b, j in enumerate(index):
            if i is not None and j is not None:
                out[a, b] = C[i, j]
    return out


def modal_state_term(system, t=0.0):
    """``M^-1 C`` (n, n) of a compiled system's modal damping, to subtract from its state matrix; or None.

    ``C`` is :func:`model_modal_damping` of ``system.model`` at the
    system's parameter values (speed profiles frozen at ``t``), ``M`` the
    mass matrix of its linear equations. Used by
    :func:`~rotorkit.linear.modes.averaged_jacobian`, so that
    ``natural_frequencies`` of a system matches the linear analyses. None
    also for a system whose right-hand side holds the damping already
    (``system.modal_damping``: every compiled system of such a model).
    """
    from scipy.linalg import solve

    from .linear_matrices import linear_matrices
    from .rotor_speeds import frozen_speed_model

    model = system.model
    if modal_damping_spec(model) is None or getattr(system, "modal_damping", False):
        return None
    frozen = frozen_speed_model(model, t)
    values = dict(frozen.parameters)
    values.update({k: v for k, v in system.parameters.items() if k in values})
    C = model_modal_damping(frozen, values, t)
    M = linear_matrices(frozen, t, values, modal_damping=False)[0].toarray()
    if C.shape[0] != len(system.coordinate_names):
        raise ParameterError(f"natural_frequencies: the modal damping of {model.name!r} has {C.shape[0]} coordinates, "
                             f"the system {len(system.coordinate_names)} (a Drive's spin coordinate); expected a "
                             "model with constant-speed rotors")
    return solve(M, C)
