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
