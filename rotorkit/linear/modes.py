"""Modal analysis of a compiled system at its operating point (linearised contacts included).

:func:`natural_frequencies` linearises a compiled :class:`~rotorkit.system.System`
at its static equilibrium (Hertzian bearings averaged over the cage
positions, rub contacts engaged on request) and returns a
:class:`~rotorkit.linear.modal.Modes`: natural and damped frequencies,
damping ratios, logarithmic decrements, whirl direction per mode and per
station, right and left mode shapes.

Related modules of :mod:`rotorkit.linear`:

- :mod:`rotorkit.linear.linearize`: :func:`static_equilibrium`, :func:`linearize`;
- :mod:`rotorkit.linear.modal`: :class:`Modes` and the eigen-solution of
  a second-order system;
- :mod:`rotorkit.linear.linear_model`: :class:`LinearModel` (``M``, ``C``,
  ``G``, ``K``, ``H``) and :func:`linear_model`;
- :mod:`rotorkit.linear.campbell`: :class:`Campbell`, :func:`campbell`.

(The old path ``rotorkit.analysis.modes`` still re-exports all of these.)

Conventions: frequencies in rad/s, displacements in m, angles in rad; mode
numbers are 1-based. Real eigenvalues (overdamped or diverging motions) are
not modes; they stay in :attr:`Modes.all_eigenvalues`.

Typical use::

    system = rotorkit.preset("al31f").compile()
    modes = natural_frequencies(system)
    print(modes.table(units="Hz"))
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError
from .linearize import (
    DEFAULT_CAGE_SAMPLES,
    check_coordinates,
    check_system,
    check_time,
    difference_steps,
    linearize,
    rub_stators,
    sample_times,
    static_equilibrium,
    without_unbalance,
)
from .modal import OSCILLATORY_RTOL, modes_from_state_matrix

__all__ = [
    "natural_frequencies",
    "averaged_jacobian",
]


def _oscillatory(eigenvalues):
    """Eigenvalues with Im > 0 (one per conjugate pair), sorted by |lambda|."""
    lam = eigenvalues[eigenvalues.imag > OSCILLATORY_RTOL * np.abs(eigenvalues)]
    return lam[np.argsort(np.abs(lam), kind="stable")]


def _engage_rub(system, q, stators, steps):
    """A system whose rub clearances sit just below the disks' static radial displacement.

    The contact then engages at ``q`` with a negligible preload: radial
    stiffness k_r along the static displacement, friction coupling mu k_r.
    """
    names = system.coordinate_names
    values = system.parameters
    overrides = {}
    for stator in stators:
        label = stator.label()
        ix, iy = names.index(f"x{stator.station}"), names.index(f"y{stator.station}")
        r = math.hypot(q[ix], q[iy])
        clearance = values[f"{label}_clearance"]
        margin = 2.0 * max(steps[ix], steps[iy])
        if r - margin < clearance:
            overrides[f"{label}_clearance"] = max(r - margin, 0.0)
    return system.with_parameters(**overrides) if overrides else system


def _rub_is_engaged(system, q, stators):
    names = system.coordinate_names
    values = system.parameters
    for stator in stators:
        label = stator.label()
        if values[f"{label}_contact_stiffness"] == 0.0:
            continue
        r = math.hypot(q[names.index(f"x{stator.station}")], q[names.index(f"y{stator.station}")])
        if r >= values[f"{label}_clearance"]:
            return True
    return False




def _check_options(system, t, rub_engaged, unbalance, cage_samples, method, equilibrium):
    t = check_time(t)
    n = len(system.coordinate_names)
    if rub_engaged not in (None, True, False):
        raise ParameterError(f"rub_engaged={rub_engaged!r} is invalid: expected None, True or False")
    if not isinstance(unbalance, bool):
        raise ParameterError(f"unbalance={unbalance!r} is invalid: expected True or False")
    if isinstance(cage_samples, bool) or not isinstance(cage_samples, numbers.Integral) or cage_samples < 1:
        raise ParameterError(f"cage_samples={cage_samples!r} is invalid: expected an integer >= 1")
    if cage_samples > 10_000:  # each sample is an equilibrium and a Jacobian of the model
        raise ParameterError(f"cage_samples={cage_samples!r} is too many: each is an equilibrium and a Jacobian "
                             "of the model (milliseconds to seconds each); expected at most 10000 (default 16)")
    if method not in ("fd", "analytic", "auto"):
        raise ParameterError(f"method={method!r} is unknown; expected 'fd', 'analytic' or 'auto'")
    given = None
    if isinstance(equilibrium, bool):
        pass
    elif isinstance(equilibrium, (np.ndarray, list, tuple)):
        given = check_coordinates(equilibrium, n, "equilibrium")
    else:
        raise ParameterError(
            f"equilibrium={equilibrium!r} is invalid: expected True, False or {n} coordinates (m, rad)"
        )
    return t, given


def averaged_jacobian(system, *, t=0.0, equilibrium=True, rub_engaged=None, unbalance=False,
                      cage_samples=DEFAULT_CAGE_SAMPLES, eps=None, method="auto"):
    """The state matrix of the linearised system, averaged over the cage positions.

    Parameters are those of :func:`natural_frequencies`.

    Returns
    -------
    A : numpy.ndarray, shape (2n, 2n)
    per_sample : list of numpy.ndarray
        The natural frequencies (rad/s) of each sample's own Jacobian.
    operating_point : numpy.ndarray, shape (n,)
    times : numpy.ndarray
        Sample times (s).
    engaged : bool
        Whether a rub contact was engaged.
    """
    from ..units import to_si

    check_system(system, "averaged_jacobian")
    t = to_si(t, "s", "t")
    t, given = _check_options(system, t, rub_engaged, unbalance, cage_samples, method, equilibrium)
    names = tuple(system.coordinate_names)
    n = len(names)
    if not unbalance:
        system = without_unbalance(system)
    stators = rub_stators(system)
    if rub_engaged is False and stators:
        values = system.parameters
        off = {f"{s.label()}_contact_stiffness": 0.0 for s in stators}
        if any(values[name] != 0.0 for name in off):
            system = system.with_parameters(**off)
    from .modal_damping import modal_state_term

    modal = modal_state_term(system, t)  # Rotor(damping=ModalDamping(...)): numeric, not in the compiled rhs
    times = sample_times(system, t, int(cage_samples))
    jacobians, per_sample, operating_point, engaged = [], [], None, False
    for ti in times:
        if given is not None:
            q = given
        elif equilibrium:
            q = static_equilibrium(system, ti, unbalance=True)
        else:
            q = np.zeros(n)
        target = system
        if rub_engaged and stators:
            steps = difference_steps(names, q, eps)
            target = _engage_rub(system, q, stators, steps)
        engaged = engaged or _rub_is_engaged(target, q, stators)
        A, _ = linearize(target, q, ti, eps=eps, method=method)
        if modal is not None:
            A = A.copy()
            A[n:2 * n, n:2 * n] -= modal
        jacobians.append(A)
        per_sample.append(np.abs(_oscillatory(np.linalg.eigvals(A))))
        if operating_point is None:
            operating_point = q.copy()
    return np.mean(jacobians, axis=0), per_sample, operating_point, times, engaged


def natural_frequencies(system, *, t=0.0, equilibrium=True, rub_engaged=None, unbalance=False,
                        cage_samples=DEFAULT_CAGE_SAMPLES, eps=None, method="auto"):
    """Natural frequencies, damping ratios and mode shapes of the linearised system.

    Parameters
    ----------
    system : rotorkit.System
    t : float, str or pint.Quantity
        Time (s) of the operating point (manoeuvre loads, ball angles).
    equilibrium : bool or array_like of shape (n,)
        True (default): linearise at the static equilibrium
        (:func:`static_equilibrium`, gravity sag included); False: at the
        undeflected axis ``q = 0``; an array: at these coordinates (m, rad).
    rub_engaged : bool or None
        None (default): the rub contacts as they are at the operating point
        (engaged only if the static displacement exceeds the clearance).
        True: engaged (see Notes). False: disengaged (contact stiffness set
        to 0, for the equilibrium too).
    unbalance : bool
        False (default): disk eccentricities set to zero (a periodic forcing
        is not part of a modal analysis). True: kept, and the system is
        linearised as a frozen snapshot at ``t`` (the eccentric disks' mass
        matrix then depends on their angle; a rigorous treatment would be
        Floquet analysis).
    cage_samples : int
        Number of cage positions averaged over one ball-passing period (see
        Notes); 1 linearises at ``t`` only.
    eps : None, float or array_like
        Finite-difference steps, as in :func:`linearize`.
    method : {"fd", "analytic", "auto"}
        How the Jacobian is computed, as in :func:`linearize`.

    Returns
    -------
    Modes
        With log decrements, whirl per mode and station, and left shapes of
        the mass-normalised problem.

    Notes
    -----
    *Bearing.* The balls of a :class:`~rotorkit.BallBearing` sit at angles
    that turn with the cage, so the bearing's linearised stiffness depends on
    time, with the ball-passing period ``2 pi / (N_b omega_c)``. The
    equilibrium and the Jacobian are computed at ``cage_samples`` equally
    spaced times over one such period from ``t`` (backwards if a time event
    of the system lies in between) and the Jacobians are averaged: since the
    ball-passing frequency is far above the low modes (17,900 rad/s for the
    AL-31F preset), the method of averaging makes the averaged stiffness the
    relevant one. The frequencies of each single sample give
    :attr:`Modes.frequency_range`, the spread over the cage angle. Without a
    bearing, or at zero cage speed, one sample is used.

    *Rub.* With ``rub_engaged=True`` the clearance of each rub stator whose
    disk does not already touch is lowered, for the linearisation only, to
    just below the disk's static radial displacement ``r*`` (by a margin of
    a few finite-difference steps): the contact engages at the operating
    point with negligible preload. Its linearisation is then a radial spring
    ``k_r`` along the static displacement (the contact point of a sagging
    disk), the friction coupling ``mu k_r`` and, with a torsional disk, the
    friction torque's dependence on the displacement; the tangential
    stiffness ``k_r (r - delta) / r`` is about zero (a grazing contact). If
    the disk has no static displacement (``r*`` below the margin) the
    clearance becomes 0: contact all around, ``k_r`` in every direction.

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Model
    >>> system = Model([Rotor(name="R", stations=(1,), speed=100.0),
    ...                 Disk(station=1, mass=2.0, radius=0.1),
    ...                 ElasticSupport(station=1, stiffness=2e4, damping=4.0)]).compile(backend="python")
    >>> modes = natural_frequencies(system)
    >>> modes.frequencies.round(6).tolist(), modes.damping_ratios.round(6).tolist()
    ([100.0, 100.0], [0.01, 0.01])
    """
    check_system(system, "natural_frequencies")
    A, per_sample, operating_point, times, engaged = averaged_jacobian(
        system, t=t, equilibrium=equilibrium, rub_engaged=rub_engaged, unbalance=unbalance,
        cage_samples=cage_samples, eps=eps, method=method)
    modes = modes_from_state_matrix(A, tuple(system.coordinate_names), left=True,
                                    operating_point=operating_point, sample_times=times,
                                    rub_engaged=bool(engaged), speed=None)
    k = len(modes)
    spread = np.full((k, len(times)), np.nan)
    for j, f in enumerate(per_sample):
        m = min(k, f.size)
        spread[:m, j] = f[:m]
    with np.errstate(all="ignore"):
        frange = np.column_stack([np.min(spread, axis=1), np.max(spread, axis=1)]) if k else np.empty((0, 2))
    if k and np.isnan(spread).any():
        frange[np.isnan(spread).any(axis=1)] = np.nan
    frange.setflags(write=False)
    object.__setattr__(modes, "frequency_range", frange)
    from ..plotting.rotor import rotor_layout

    object.__setattr__(modes, "layout", rotor_layout(system.model))  # for the mode-shape plots
    return modes
