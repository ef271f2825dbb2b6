"""The compiled AFT residual's reuse of the sampled states (rotorkit.periodic.compiled_aft.residual_same_states).

The continuation kernel's forward difference ``dR/dlambda`` evaluates the residual at the prediction's ``z`` at
``lambda`` and at ``lambda + d``; the second evaluation reuses the sampled displacements and the velocities per
unit base frequency of the first. It must give, bit for bit, what a residual evaluated from nothing at
``(z, lambda + d)`` gives, on an orbit that touches the stator at some samples and not at others.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Model, Rotor, RubStator
from rotorkit.periodic import fastpath
from rotorkit.periodic.continuation import ContinuationProblem
from rotorkit.periodic.hb import HarmonicBalance

pytest.importorskip("numba")

DELTA = 1.0e-4  # m


def test_residual_at_a_new_speed_from_the_same_states_equals_a_fresh_residual(monkeypatch):
    from rotorkit.periodic.compiled_aft import residual, residual_same_states, workspace

    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "1")
    system = Model([Rotor(name="R", stations=(1,), speed=60.0),
                    Disk(station=1, mass=2.0, radius=0.1, eccentricity=2.0e-5, torsion=False),
                    ElasticSupport(station=1, stiffness=2.0e4, damping=4.0),
                    RubStator(station=1, clearance=DELTA, contact_stiffness=2.0e4, friction_coefficient=0.0)],
                   name="jeffrub_aft").compile(backend="c")
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=3)
    setup = fastpath.compiled_setup(ContinuationProblem(hb, "R_speed"))
    assert setup is not None
    n, size = hb.n, hb.size
    z = np.zeros(size)
    z[n:2 * n] = [1.2 * DELTA, 0.0]  # cos: x; sin: y (a circle of radius 1.2 delta) ...
    z[2 * n:3 * n] = [0.0, 1.2 * DELTA]
    z[3 * n] = 0.5 * DELTA  # ... shifted by a second harmonic: in contact over part of the period only
    lam, d = 120.0, 1e-7 * 140.0
    fl = np.zeros(12)
    fl[0] = setup.s0
    ints = setup.ints()

    def fresh():
        return workspace(ints, setup.base, setup.trig, setup.terms, setup.weights)

    args = (setup.rhs, setup.jac, ints, fl, setup.E, setup.P, setup.ED, setup.mass, setup.base, setup.varying,
            setup.coef, setup.window)
    ws = fresh()
    R0, J0 = np.empty(size), np.empty((size, size))
    assert residual(z, lam, True, *args, ws, R0, J0)
    contact = np.hypot(ws[6][:, 0], ws[6][:, 1]) > DELTA
    assert contact.any() and not contact.all()
    shifted = np.empty(size)
    assert residual_same_states(z, lam + d, *args, ws, shifted)
    expected, J = np.empty(size), np.empty((size, size))
    assert residual(z, lam + d, False, *args, fresh(), expected, J)
    assert np.array_equal(shifted, expected)
    assert not np.array_equal(shifted, R0)  # the speed's share is there: a new frame, new velocities


def _compiled_and_reference_jacobians(system, z, lam):
    """The compiled residual's AFT Jacobian and the Python reference's (direct projection), and the largest
    velocity entry of the sampled local force Jacobians."""
    from rotorkit.periodic.compiled_aft import residual, workspace

    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=3)
    setup = fastpath.compiled_setup(ContinuationProblem(hb, "R_speed"))
    assert setup is not None
    size = hb.size
    fl = np.zeros(12)
    fl[0] = setup.s0
    ints = setup.ints()
    ws = workspace(ints, setup.base, setup.trig, setup.terms, setup.weights)
    R, J = np.empty(size), np.empty((size, size))
    assert residual(z, lam, True, setup.rhs, setup.jac, ints, fl, setup.E, setup.P, setup.ED, setup.mass, setup.base,
                    setup.varying, setup.coef, setup.window, ws, R, J)
    frame = hb.frame({"R_speed": lam})
    expected = hb.residual(z, frame, jacobian=True)[1]
    A = frame.accelerations_and_jacobians(hb.states(z, frame))[1]
    velocity = np.max(np.abs(A[:, hb.n:, hb.n:] - frame.Av))
    return J, expected, velocity


@pytest.mark.parametrize("kind", ["rub", "squeeze film"])
def test_compiled_aft_jacobian_equals_the_direct_projection(kind, monkeypatch):
    """The compiled Jacobian (sums up to harmonic 2H; sampled zeros skipped, and the velocity sums not read where
    the local forces depend on the displacements alone: the rub) equals the reference's direct projection, for
    forces of the displacements alone (rub, in contact over part of the period) and of the velocities too
    (squeeze-film damper)."""
    import rotorkit as rk

    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "1")
    if kind == "rub":
        system = Model([Rotor(name="R", stations=(1,), speed=60.0),
                        Disk(station=1, mass=2.0, radius=0.1, eccentricity=2.0e-5, torsion=False),
                        ElasticSupport(station=1, stiffness=2.0e4, damping=4.0),
                        RubStator(station=1, clearance=DELTA, contact_stiffness=2.0e4, friction_coefficient=0.0)],
                       name="jeffrub_aft").compile(backend="c")
        radius, shift, lam = 1.2 * DELTA, 0.5 * DELTA, 120.0
    else:
        clearance = 2.0e-4
        film = rk.SqueezeFilmDamper(station=1, centring_stiffness=1.0e6, radius=0.05, length=0.015,
                                    clearance=clearance, viscosity=0.004)
        system = rk.Model([Rotor(name="R", stations=(1,), speed=316.0),
                           Disk(station=1, mass=10.0, radius=0.1, eccentricity=0.15 * clearance, torsion=False),
                           film], name="sfd_aft").compile(backend="c")
        radius, shift, lam = 0.4 * clearance, 0.1 * clearance, 330.0
    n = 2
    z = np.zeros(7 * n)
    z[n:2 * n] = [radius, 0.0]  # a circle ...
    z[2 * n:3 * n] = [0.0, radius]
    z[3 * n] = shift  # ... with a second harmonic
    J, expected, velocity = _compiled_and_reference_jacobians(system, z, lam)
    assert (velocity == 0.0) == (kind == "rub")  # both assembly paths are exercised
    linear = _compiled_and_reference_jacobians(system, np.zeros(7 * n), lam)[0]
    assert np.max(np.abs(J - linear)) > 1e-3 * np.max(np.abs(J))  # the local forces' share is there
    assert np.max(np.abs(J - expected)) <= 1e-11 * np.max(np.abs(expected))
