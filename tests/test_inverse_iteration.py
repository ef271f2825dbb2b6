"""Eigenvectors by inverse iteration against the full dense eigen-solution (numpy/scipy ``eig``).

The rotor is a chain of stations with ``x, y, theta_x, theta_y`` (springs
between neighbours, supports at the ends, disks with polar inertia: the
gyroscopic matrix couples the tilts); isotropic, it has exactly double
eigenvalues at rest (forward and backward whirl coincide) and a pair split
by ``Omega Ip`` above. Eigenvalues must agree to 1e-10 relative, vectors up
to normalisation and phase (MAC > 1 - 1e-10), left vectors the same, and
the Campbell diagram computed with the shapes of a few modes must equal the
one computed with all of them.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import linalg

from rotorkit.analysis.linear_model import LinearModel
from rotorkit.linear.inverse_iteration import is_state_form, state_eigenvectors
from rotorkit.linear.modal import modes_from_state_matrix, oscillatory_order, state_matrix


def rotor_chain(stations=8, kx=4e6, ky=4e6, support_damping=60.0, cross=0.0):
    """A LinearModel of a shaft of Euler-Bernoulli beams with disks (x, y, tx, ty per station), on two supports.

    Each plane has the beam stiffness ``EI/L^3 [[12, 6L, -12, 6L], [6L, 4L^2, -6L, 2L^2], ...]`` on ``(x, ty)``
    and ``(y, tx)``; ``kx != ky``: anisotropic supports; ``cross``: a cross-coupled support stiffness.
    """
    n = 4 * stations
    EI, L = 2e4, 0.15
    beam = EI / L**3 * np.array([[12.0, 6 * L, -12.0, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                 [-12.0, -6 * L, 12.0, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
    K = np.zeros((n, n))
    for s in range(stations - 1):
        for translation, tilt in ((0, 3), (1, 2)):  # plane (x, ty) and plane (y, tx)
            dofs = [4 * s + translation, 4 * s + tilt, 4 * (s + 1) + translation, 4 * (s + 1) + tilt]
            K[np.ix_(dofs, dofs)] += beam
    C = np.zeros((n, n))
    for s in (1, stations - 2):  # the supports
        K[4 * s, 4 * s] += kx
        K[4 * s + 1, 4 * s + 1] += ky
        K[4 * s, 4 * s + 1] += cross
        K[4 * s + 1, 4 * s] -= cross
        C[4 * s, 4 * s] += support_damping
        C[4 * s + 1, 4 * s + 1] += support_damping
    masses = 3.0 + np.arange(stations) % 3
    inertia = 0.02 * masses
    M = np.diag(np.column_stack([masses, masses, inertia, inertia]).reshape(-1))
    G = np.zeros((n, n))
    for s in range(stations):
        G[4 * s + 2, 4 * s + 3], G[4 * s + 3, 4 * s + 2] = 2.0 * inertia[s], -2.0 * inertia[s]
    names = [f"{a}{s + 1}" for s in range(stations) for a in ("x", "y", "tx", "ty")]
    return LinearModel(mass=M, damping=C, stiffness=K, gyroscopic=G, coordinate_names=names,
                       rotor_speeds={"R": (0.0, 1.0)})


def mac(a, b):
    return abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)


def test_right_and_left_vectors_equal_the_full_eigen_solution():
    model = rotor_chain(kx=5e6, ky=3e6, cross=1e6)
    A = model.state_matrix(800.0)
    assert is_state_form(A)
    lam, wl, vr = linalg.eig(A, left=True, right=True)
    index = oscillatory_order(lam)
    X = state_eigenvectors(A, lam[index], lam)
    W = state_eigenvectors(A, lam[index], lam, left=True)
    for j, i in enumerate(index):
        assert mac(X[:, j], vr[:, i]) > 1.0 - 1e-10
        assert mac(W[:, j], wl[:, i]) > 1.0 - 1e-10
    scale = np.abs(lam).max()
    assert np.max(np.linalg.norm(A @ X - X * lam[index], axis=0)) < 1e-12 * scale
    assert np.max(np.linalg.norm(W.conj().T @ A - lam[index][:, None] * W.conj().T, axis=1)) < 1e-12 * scale


@pytest.mark.parametrize("speed, kx, ky, damping", [
    (800.0, 5e6, 3e6, 60.0),  # anisotropic, damped, gyroscopic
    (0.0, 4e6, 4e6, 60.0),  # isotropic at rest: exactly double eigenvalues
    (0.0, 4e6, 4e6, 0.0),  # and undamped
    (1e-4, 4e6, 4e6, 60.0),  # nearly double: split by the speed alone
    (800.0, 4e6, 4e6, 6e4),  # heavily damped supports: overdamped real eigenvalues among the modes
])
def test_modes_from_a_few_vectors_equal_those_from_all(speed, kx, ky, damping):
    model = rotor_chain(kx=kx, ky=ky, support_damping=damping)
    A = model.state_matrix(speed)
    full = modes_from_state_matrix(A, model.coordinate_names, mass=model.mass)
    k = 6
    few = modes_from_state_matrix(A, model.coordinate_names, mass=model.mass, n_modes=k, sparse=False)
    assert len(few) == k
    np.testing.assert_allclose(few.eigenvalues, full.eigenvalues[:k], rtol=1e-10)
    np.testing.assert_allclose(np.sort(np.abs(few.all_eigenvalues)), np.sort(np.abs(full.all_eigenvalues)),
                               rtol=1e-10)
    assert few.whirl == full.whirl[:k]
    M, C, K = model.matrices(speed)
    for i in range(k):
        assert mac(few.shapes[:, i], full.shapes[:, i]) > 1.0 - 1e-10
        lam, x, y = few.eigenvalues[i], few.shapes[:, i], few.left_shapes[:, i]
        Q = lam**2 * M + lam * C + K
        assert np.linalg.norm(y.conj() @ Q) < 1e-9 * np.linalg.norm(Q) * np.linalg.norm(y)
        normalised = abs(y.conj() @ (2 * lam * M + C) @ x - 1.0)
        reference = abs(full.left_shapes[:, i].conj() @ (2 * lam * M + C) @ full.shapes[:, i] - 1.0)
        assert normalised < 1e-9 + 10.0 * reference  # a near-double pair is bi-orthonormalised as one
    if speed == 0.0 and kx == ky:  # the doubles are split into backward and forward circular whirl
        assert np.any(np.abs(np.diff(few.eigenvalues)) <= 1e-7 * np.abs(few.eigenvalues[1:]))
        assert few.whirl[:2] == ("backward", "forward")


@pytest.mark.parametrize("scipy_loaded", [False, True])
def test_all_modes_with_left_vectors_equal_scipy(monkeypatch, scipy_loaded):
    """The dense path of all modes: numpy's right vectors, left ones by inverse iteration (no scipy import),
    or scipy's eig with both where scipy.linalg is imported anyway."""
    import rotorkit.linear.modal as modal

    monkeypatch.setattr(modal, "scipy_linalg_loaded", lambda: scipy_loaded)
    model = rotor_chain(kx=5e6, ky=3e6, cross=1e6)
    A, M = model.state_matrix(500.0), model.mass
    modes = modes_from_state_matrix(A, model.coordinate_names, mass=M)
    lam, wl, vr = linalg.eig(A, left=True, right=True)
    index = oscillatory_order(lam)
    np.testing.assert_allclose(modes.eigenvalues, lam[index], rtol=1e-10)
    n = M.shape[0]
    for i, j in enumerate(index):
        y = np.linalg.solve(M.T, wl[n:, j])  # left coordinate vector of scipy's left state vector
        assert mac(modes.left_shapes[:, i], y) > 1.0 - 1e-10
        assert mac(modes.shapes[:, i], vr[:n, j]) > 1.0 - 1e-10


def test_a_real_overdamped_eigenvalue():
    """m x'' + c x' + k x = 0 with c > 2 sqrt(k m): two real roots (-c -+ sqrt(c^2 - 4 k m)) / 2 m."""
    model = rotor_chain(stations=4, kx=5e6, ky=3e6, support_damping=4e5)
    A = model.state_matrix(0.0)
    lam, vr = np.linalg.eig(A)
    real = np.flatnonzero(np.abs(lam.imag) <= 1e-12 * np.abs(lam))
    assert real.size >= 2
    X = state_eigenvectors(A, lam[real], lam)
    for j, i in enumerate(real):
        assert mac(X[:, j], vr[:, i]) > 1.0 - 1e-10


def test_a_matrix_not_in_state_form():
    rng = np.random.default_rng(3)
    A = rng.standard_normal((14, 14))
    assert not is_state_form(A)
    lam, vr = np.linalg.eig(A)
    X = state_eigenvectors(A, lam, lam)
    W = state_eigenvectors(A, lam, lam, left=True)
    for j in range(lam.size):
        assert mac(X[:, j], vr[:, j]) > 1.0 - 1e-10
        assert abs(W[:, j].conj() @ A @ X[:, j] - lam[j] * (W[:, j].conj() @ X[:, j])) < 1e-12 * np.abs(lam).max()


def test_state_matrix_of_the_matrices():
    model = rotor_chain(stations=3)
    np.testing.assert_allclose(state_matrix(*model.matrices(300.0)), model.state_matrix(300.0), rtol=1e-13,
                               atol=1e-9)


@pytest.mark.parametrize("extra", [0, 2])
def test_campbell_with_the_shapes_of_a_few_modes_equals_all_shapes(monkeypatch, extra):
    """The tracking computes a few shapes per speed (more when the assignment is uncertain): the same diagram."""
    import rotorkit.linear.campbell as campbell_module

    model = rotor_chain(kx=5e6, ky=3e6, cross=2e5)
    speeds = np.linspace(0.0, 3000.0, 25)
    monkeypatch.setattr(campbell_module, "EXTRA_SHAPES", extra)
    few = campbell_module.campbell(model, speeds, n_modes=6)
    monkeypatch.setattr(campbell_module, "EXTRA_SHAPES", 10**6)  # every mode's shape at every speed
    full = campbell_module.campbell(model, speeds, n_modes=6)
    np.testing.assert_allclose(few.frequencies, full.frequencies, rtol=1e-10)
    np.testing.assert_allclose(few.log_decrements, full.log_decrements, rtol=1e-7, atol=1e-10)
    np.testing.assert_array_equal(few.whirl, full.whirl)
    assert [(c.rotor, c.mode, c.whirl) for c in few.crossings] == [(c.rotor, c.mode, c.whirl) for c in full.crossings]
    np.testing.assert_allclose([c.speed for c in few.crossings], [c.speed for c in full.crossings], rtol=1e-9)


def test_modes_with_left_shapes_need_no_scipy():
    """A fresh process (``rotorkit modes FILE``) gets left shapes without importing scipy (0.4 s)."""
    import subprocess
    import sys
    import textwrap
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    script = textwrap.dedent("""
        import sys
        import numpy as np
        from rotorkit.linear.modal import modes_from_state_matrix, state_matrix
        n = 6
        K = 2e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
        C = 3.0 * np.eye(n) + 0.5 * (np.eye(n, k=1) - np.eye(n, k=-1))
        modes = modes_from_state_matrix(state_matrix(np.eye(n), C, K), tuple(f"q{i}" for i in range(n)))
        few = modes_from_state_matrix(state_matrix(np.eye(n), C, K), tuple(f"q{i}" for i in range(n)), n_modes=1,
                                      sparse=False)
        assert modes.left_shapes is not None and few.left_shapes is not None
        print(sorted({m.split(".")[0] for m in sys.modules} & {"scipy"}))
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=root,
                         env={**__import__("os").environ, "PYTHONPATH": str(root)}, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"
