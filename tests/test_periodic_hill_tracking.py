"""Hill's exponents followed along a branch (rotorkit.periodic.compiled_hill.hill_branch) against the full
method at every point and against numpy/LAPACK.

The full method (all eigenvalues of Hill's companion matrix, the centre of every eigenvector, the selection of
rotorkit.periodic.stability.hill_multipliers) is the reference; following the previous point's exponents by
shifted inverse iteration (rotorkit.periodic.eigen.quadratic_eigenpair) must give the same multipliers, and
fall back to the full method where it cannot vouch for the same selection (points far apart, a change in
the number of unstable multipliers); the double exponents of an isotropic rotor are followed as pairs.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Model, Rotor, RubStator
from rotorkit.analysis.periodic import periodic_response
from rotorkit.periodic import fastpath
from rotorkit.periodic.continuation import ContinuationProblem
from rotorkit.periodic.hb import HarmonicBalance

numba = pytest.importorskip("numba")

M, K, C, E = 2.0, 2.0e4, 4.0, 2.0e-5  # kg, N/m, N s/m, m
DELTA, KR = 1.0e-4, 2.0e4


def test_quadratic_eigenpair_against_lapack():
    from rotorkit.periodic.eigen import quadratic_eigenpair

    @numba.njit
    def run(A1, A0, sigma, u, max_shifts):
        return quadratic_eigenpair(A1, A0, sigma, u, max_shifts)

    rng = np.random.default_rng(7)
    m = 9
    for _ in range(30):
        A0 = 100.0 * rng.standard_normal((m, m))
        A1 = rng.standard_normal((m, m))
        lam, V = np.linalg.eig(np.block([[np.zeros((m, m)), np.eye(m)], [A0, A1]]))
        k = rng.integers(2 * m)
        gap = np.sort(np.abs(lam - lam[k]))[1]
        sigma = complex(lam[k] + 0.1 * gap * np.exp(2j * np.pi * rng.random()))
        u = (V[:m, k] + 0.3 * rng.standard_normal(m)).astype(complex)
        got, ok = run(A1, A0, sigma, u, 3)
        assert ok
        assert abs(got - lam[k]) < 1e-12 * np.max(np.abs(lam))
        residual = (A0 + got * A1 - got**2 * np.eye(m)) @ u
        assert np.linalg.norm(residual) < 1e-9 * np.linalg.norm(A0) * np.linalg.norm(u)
    # one shift of one step cannot confirm convergence (two agreeing estimates): not converged
    u = (V[:m, k] + 0.3 * rng.standard_normal(m)).astype(complex)

    @numba.njit
    def once(A1, A0, sigma, u):
        return quadratic_eigenpair(A1, A0, sigma, u, 1, 1)

    assert not once(A1, A0, sigma, u)[1]



def test_a_real_shift_is_followed_in_real_arithmetic():
    """A real exponent (an overdamped pair: lam^2 + 30 lam + 100 ~ 0 per coordinate) followed from a real shift
    and a real start vector in real arithmetic (eigen.eigenpair_near on real arrays) gives the complex
    iteration's eigenpair (whose imaginary parts stay zero) and LAPACK's eigenvalue."""
    from rotorkit.periodic.eigen import eigenpair_near, quadratic_eigenpair, row_norms

    @numba.njit
    def complex_run(A1, A0, sigma, u):
        return quadratic_eigenpair(A1, A0, sigma, u)

    @numba.njit
    def real_run(A1, A0, sigma, u):
        m = A0.shape[0]
        n0, n1 = row_norms(A1, A0)
        return eigenpair_near(A1, A0, n0, n1, sigma, u, np.empty((m, m)), np.empty(m, dtype=np.int64),
                              np.empty(m), np.empty(m), np.empty(m))

    rng = np.random.default_rng(3)
    m = 8
    A1 = -30.0 * np.eye(m) + rng.standard_normal((m, m))
    A0 = -100.0 * np.eye(m) + 3.0 * rng.standard_normal((m, m))
    lam, V = np.linalg.eig(np.block([[np.zeros((m, m)), np.eye(m)], [A0, A1]]))
    real = np.flatnonzero(np.abs(lam.imag) < 1e-12)
    assert len(real) >= 2
    for k in real:
        gap = np.sort(np.abs(lam - lam[k]))[1]
        sigma = float(lam[k].real + 0.05 * gap)
        u = np.real(V[:m, k]) + 0.1 * rng.standard_normal(m)
        got, ok = real_run(A1, A0, sigma, u.copy())
        uc = u.astype(complex)
        expected, ok_c = complex_run(A1, A0, complex(sigma), uc)
        assert ok and ok_c
        assert isinstance(got, float)
        assert abs(got - expected.real) <= 1e-14 * abs(expected) and expected.imag == 0.0
        assert abs(got - lam[k].real) < 1e-12 * np.max(np.abs(lam))


def jeffcott(anisotropy=1.0):
    from rotorkit.elements import LinearBearing

    support = (ElasticSupport(station=1, stiffness=K, damping=C) if anisotropy == 1.0 else
               LinearBearing(station=1, kxx=K * anisotropy, kyy=K, cxx=C, cyy=C))
    return Model([Rotor(name="R", stations=(1,), speed=60.0),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=E, torsion=False), support,
                  RubStator(station=1, clearance=DELTA, contact_stiffness=KR, friction_coefficient=0.0)],
                 name="jeffrub").compile(backend="c")


def hill_both(system, lam, Z, harmonics, monkeypatch):
    """Multipliers of the points (lam, Z) in the given order, followed and by the full method at every point."""
    from rotorkit.periodic.compiled_hill import hill_branch

    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "1")
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=harmonics)
    setup = fastpath.compiled_setup(ContinuationProblem(hb, "R_speed"))
    assert setup is not None
    args = (setup.jac, setup.ints(hill=1), np.array([setup.s0]), setup.E, setup.P, setup.ED, setup.mass,
            np.ascontiguousarray(np.linalg.inv(setup.mass)), setup.base, setup.varying, setup.coef, setup.window)
    lam = np.ascontiguousarray(lam, dtype=float)
    Z = np.ascontiguousarray(np.reshape(Z, (len(lam), -1)), dtype=float)
    out = []
    for track in (True, False):
        mu_re, mu_im = np.zeros((len(lam), 2 * hb.n)), np.zeros((len(lam), 2 * hb.n))
        ok, tracked = np.zeros(len(lam), dtype=np.bool_), np.zeros(len(lam), dtype=np.bool_)
        hill_branch(*args, lam, Z, mu_re, mu_im, ok, track, tracked)
        assert ok.all()
        out.append((mu_re + 1j * mu_im, tracked))
    (followed, tracked), (full, none) = out
    assert not none.any()
    return followed, full, tracked


def same_sets(a, b, tol):
    return all(np.max(np.min(np.abs(x[:, None] - y[None, :]), axis=1)) < tol for x, y in zip(a, b)) and \
        all(np.max(np.min(np.abs(y[:, None] - x[None, :]), axis=1)) < tol for x, y in zip(a, b))


@pytest.mark.slow  # compiles the Hill kernel (~40 s on a loaded machine)
@pytest.mark.parametrize("anisotropy", [1.0, 1.3])
def test_followed_multipliers_equal_the_full_method_along_a_branch(anisotropy, monkeypatch):
    from rotorkit.periodic.compiled_hill import ANCHOR_EVERY

    system = jeffcott(anisotropy)
    with monkeypatch.context() as patch:
        patch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
        reference = periodic_response(system, speeds=(60.0, 200.0), harmonics=3, stability="hill")
    followed, full, tracked = hill_both(system, reference.parameter, reference.coefficients, 3, monkeypatch)
    assert same_sets(followed, full, 1e-10)
    assert same_sets(followed, reference.multipliers, 1e-8)  # the Python path's Hill multipliers
    assert (~reference.stable).any() and reference.stable.any()  # through the folds: crossings included
    assert tracked.sum() > len(tracked) // 2  # mostly followed ...
    assert not tracked[0]  # ... after a full solve at the first point, and at least every ANCHOR_EVERY points
    runs = np.diff(np.flatnonzero(np.concatenate([[True], ~tracked, [True]])))
    assert runs.max() <= ANCHOR_EVERY
    # where the number of unstable multipliers changes, the full method decides
    unstable = np.sum(np.abs(full) > 1.0 + 1e-6, axis=1)
    changed = np.flatnonzero(np.diff(unstable)) + 1
    assert len(changed) >= 2 and not tracked[changed].any()
    if anisotropy == 1.0:
        # no contact below the clearance: the isotropic rotor's exponents are double (x and y alike), kept
        # twice by the full method with independent eigenvectors, and followed as such
        r = reference.harmonic_amplitude("x1", 1)
        free = np.flatnonzero(r < DELTA)
        assert len(free) > 3
        assert np.all(np.abs(full[free, 0] - full[free, 2]) < 1e-10 * np.abs(full[free, 0]))  # double
        assert tracked[free[1:]].sum() >= len(free) - 3


@pytest.mark.slow
def test_points_far_apart_fall_back_to_the_full_method(monkeypatch):
    """The branch's points in a scrambled order: consecutive points far apart, the followed exponents no
    longer near their predecessors'; every multiplier must still be the full method's."""
    system = jeffcott(1.3)
    with monkeypatch.context() as patch:
        patch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
        reference = periodic_response(system, speeds=(60.0, 200.0), harmonics=3, stability="none")
    order = np.random.default_rng(5).permutation(len(reference))
    followed, full, tracked = hill_both(system, reference.parameter[order], reference.coefficients[order], 3,
                                        monkeypatch)
    assert same_sets(followed, full, 1e-10)
    assert (~tracked[1:]).sum() > len(order) // 4  # many fallbacks
