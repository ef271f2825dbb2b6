"""The full method of Hill's multipliers on the compiled path (rotorkit.periodic.compiled_hill) computes the
centre of an eigenvector only where the selection needs it (_select_lazy): its selection, kept eigenvectors and
centres must be those of the plain computation (every eigenvector's centre, then _select), bit for
bit, on Hill matrices with copies lambda + i k w, conjugate pairs, double exponents (an isotropic rotor), real
exponents (overdamped) and a real negative multiplier (a parametric resonance: two equally centred exponents
a +- i w / 2, copies of each other). It computes the eigenvalues per group of coupled harmonics
(compiled_hill_matrix.harmonic_groups: each harmonic alone for a time-invariant system, even and odd harmonics
apart for a stiffness varying at 2 w): the multipliers must be the plain method's (one QR iteration of the whole
companion matrix) to 1e-12, and the eigenvalues numpy's.

The Hill matrices are built here as rotorkit.periodic.stability.hill_exponents builds them (unit mass), from
stiffness and damping matrices of time projected on the harmonics; the eigenvalues of the plain computation are
checked against numpy's, and the selected exponents of an LTI system against its closed form.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit.periodic.hb import fourier_basis

numba = pytest.importorskip("numba")

H, N = 3, 16  # harmonics, samples per period


def hill_blocks(stiffness, damping, omega):
    """``A21``, ``A22`` of Hill's companion matrix ``[[0, I], [A21, A22]]`` of ``q'' + C(t) q' + K(t) q = 0`` (unit
    mass), ``K``, ``C`` functions of ``tau = w t`` (n, n), as rotorkit.periodic.stability.hill_exponents (the
    change from ``tau = 0`` projected on the harmonics, as compiled_hill_matrix.hill_matrix: a constant part
    couples no harmonics, to the last bit)."""
    E, P, D = fourier_basis(H, N)
    tau = 2.0 * np.pi * np.arange(N) / N
    n = stiffness(0.0).shape[0]

    def project(f):  # kron(I, F(0)) + the blocks sum_j P[c, j] (F(tau_j) - F(0)) E[j, d], as hill_matrix
        F = np.array([f(t) - f(0.0) for t in tau])
        return np.kron(np.eye(2 * H + 1), f(0.0)) + np.einsum("cj,jab,jd->cadb", P, F, E).reshape(
            (2 * H + 1) * n, -1)

    Kt, Ct = project(stiffness), project(damping)
    wD = omega * D
    I = np.eye(n)
    J = Kt + Ct @ np.kron(wD, I) + np.kron(wD @ wD, I)
    return np.ascontiguousarray(-J), np.ascontiguousarray(-(2.0 * np.kron(wD, I) + Ct))


def cases():
    rng = np.random.default_rng(11)
    K0 = np.diag([1.0e4, 1.0e4])
    C0 = np.diag([2.0, 2.0])
    R = rng.standard_normal((2, 2))
    out = {
        # x and y alike: every exponent double, every copy exact
        "isotropic": (lambda t: K0, lambda t: C0, 60.0),
        "isotropic, fast": (lambda t: K0, lambda t: C0, 230.0),
        # gyroscopic coupling: forward and backward whirl
        "gyroscopic": (lambda t: np.diag([1.0e4, 1.3e4]), lambda t: np.array([[2.0, 30.0], [-30.0, 2.0]]), 80.0),
        # overdamped: real exponents
        "overdamped": (lambda t: np.diag([1.0e2, 2.0e2]), lambda t: np.diag([40.0, 60.0]), 17.0),
        # principal parametric resonance (w = 2 w0): exponents a +- i w / 2, copies of each other
        "parametric": (lambda t: K0 * (1.0 + 0.2 * np.cos(t)), lambda t: C0, 200.0),
        # a stiffness of harmonics 0 and 2 only (a circular orbit's): even and odd harmonics apart
        "even": (lambda t: K0 + 2.0e3 * np.cos(2.0 * t) * R, lambda t: C0, 90.0),
        # a stiffness varying over several harmonics, coupled: copies no longer exact at the truncation
        "varying": (lambda t: K0 + 3.0e3 * np.cos(t) * R + 1.0e3 * np.sin(2.0 * t) * R.T,
                    lambda t: C0 + np.sin(t) * np.eye(2), 73.0),
    }
    return out


def case_matrices(name):
    """``(A21, A22, n, omega, eigenvalues)`` of case ``name``: Hill's blocks, the coordinates, the base frequency
    and numpy's eigenvalues of the whole companion matrix."""
    stiffness, damping, omega = cases()[name]
    A21, A22 = hill_blocks(stiffness, damping, omega)
    size = A21.shape[0]
    companion = np.block([[np.zeros((size, size)), np.eye(size)], [A21, A22]])
    return A21, A22, size // (2 * H + 1), omega, np.linalg.eigvals(companion)


@pytest.fixture(scope="module")
def kernels():
    from rotorkit.periodic import compiled_hill as ch
    from rotorkit.periodic.compiled_hill_matrix import group_eigenvalues, harmonic_groups
    from rotorkit.periodic.eigen import eigenvalues

    @numba.njit
    def centres(A21, A22, wr, wi, n, H, vectors, centre, Gr, ur, piv, G, x):
        """The plain computation (the full method before _select_lazy): every eigenvalue in turn, its null vector
        and centre, a conjugate's the conjugate vector and minus the centre."""
        size = n * (2 * H + 1)
        count = 2 * size
        done = np.zeros(count, dtype=np.bool_)
        for e in range(count):
            if done[e]:
                continue
            ch._null_vector(A21, A22, complex(wr[e], wi[e]), Gr, ur, piv, G, x)
            centre[e] = ch._centre_of(x, n, H)
            vectors[e, :] = x
            done[e] = True
            if wi[e] != 0.0:
                for f in range(count):
                    if not done[f] and wr[f] == wr[e] and wi[f] == -wi[e]:
                        centre[f] = -centre[e]
                        for r in range(size):
                            vectors[f, r] = x[r].conjugate()
                        done[f] = True
                        break

    @numba.njit
    def both(A21, A22, n, H, omega):
        size = A21.shape[0]
        big = np.zeros((2 * size, 2 * size))
        for i in range(size):
            big[i, size + i] = 1.0
            for c in range(size):
                big[size + i, c] = A21[i, c]
                big[size + i, size + c] = A22[i, c]
        wr, wi = np.empty(2 * size), np.empty(2 * size)
        ok = eigenvalues(big, wr, wi)
        Gr, ur, piv = np.empty((size, size)), np.empty(size), np.empty(size, dtype=np.int64)
        G, x = np.empty((size, size), dtype=np.complex128), np.empty(size, dtype=np.complex128)
        vectors, centre = np.empty((2 * size, size), dtype=np.complex128), np.empty(2 * size)
        centres(A21, A22, wr, wi, n, H, vectors, centre, Gr, ur, piv, G, x)
        kept, runner = ch._select(wr, wi, centre, n, omega)
        lazy_vectors = np.full((2 * size, size), np.nan + 0.0j)
        lazy_centre = np.full(2 * size, np.nan)
        lazy_kept, lazy_runner = ch._select_lazy(A21, A22, wr, wi, n, H, omega, lazy_vectors, lazy_centre, Gr, ur,
                                                 piv, G, x)
        return (ok, wr + 1j * wi, kept, runner, vectors, centre, lazy_kept, lazy_runner, lazy_vectors,
                lazy_centre)

    @numba.njit
    def full(A21, A22, n, H, omega):
        size = A21.shape[0]
        ws = ch.hill_workspace(n, H)
        Gr, ur, piv, G, x = ws[8], ws[9], ws[12], ws[13], ws[15]
        big, re, im, vectors, centres = ws[18], ws[19], ws[20], ws[21], ws[22]
        lam, vec, centre = ws[23], ws[24], ws[25]
        ok, runner = ch._hill_full(A21, A22, n, H, omega, lam, vec, centre, big, re, im, vectors, centres, Gr, ur,
                                   piv, G, x)
        group = np.empty(H + 1, dtype=np.int64)
        count = harmonic_groups(A21, A22, n, H, group)
        wr, wi = np.empty(2 * size), np.empty(2 * size)
        grouped = group_eigenvalues(A21, A22, n, H, group, wr, wi)
        return ok, lam.copy(), count, group, grouped, wr + 1j * wi

    return both, full, ch.RUNNER_CENTRE


@pytest.mark.slow  # compiles the selection (~30 s on a loaded machine)
@pytest.mark.parametrize("name", list(cases()))
def test_the_lazy_selection_is_the_plain_one(name, kernels):
    both, _, runner_centre = kernels
    A21, A22, n, omega, reference = case_matrices(name)
    ok, lam, kept, runner, vectors, centre, lazy_kept, lazy_runner, lazy_vectors, lazy_centre = both(
        A21, A22, n, H, omega)
    assert ok
    assert np.max(np.min(np.abs(lam[:, None] - reference[None, :]), axis=1)) < 1e-9 * np.max(np.abs(reference))
    assert len(kept) == 2 * n
    # the same selection, the kept eigenvectors and centres bit for bit
    assert np.array_equal(kept, lazy_kept)
    assert np.array_equal(vectors[kept].view(np.uint64), lazy_vectors[kept].view(np.uint64))
    assert np.array_equal(centre[kept].view(np.uint64), lazy_centre[kept].view(np.uint64))
    # the runner: the same below RUNNER_CENTRE (where following is refused), else both at least that
    if runner < runner_centre:
        assert lazy_runner == runner
    else:
        assert runner_centre <= lazy_runner <= runner
    # every centre computed is the plain one (same values), and the shortcut skipped most of them
    computed = np.isfinite(lazy_centre)
    assert np.array_equal(lazy_centre[computed], centre[computed])
    if name not in ("varying", "even"):  # (there, copies spoilt by the truncation: no families to skip)
        assert computed.sum() < (len(lam) if name == "parametric" else len(lam) // 2)
    if name.startswith("isotropic") or name == "gyroscopic":
        # an LTI system: the exponents of q'' + C q' + K q = 0 themselves are kept (copies centred at harmonic k)
        stiffness, damping, _ = cases()[name]
        K, C = stiffness(0.0), damping(0.0)
        lti = np.linalg.eigvals(np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]]))
        assert np.max(np.min(np.abs(lam[kept][:, None] - lti[None, :]), axis=1)) < 1e-9 * np.max(np.abs(lti))
    if name == "parametric":
        # inside the tongue: a real negative multiplier's exponents a +- i w / 2, both kept once
        mu = np.exp(lam[kept] * 2.0 * np.pi / omega)
        assert np.any((mu.real < -1.0) & (np.abs(mu.imag) < 1e-6 * np.abs(mu)))


GROUPS = {"isotropic": H + 1, "isotropic, fast": H + 1, "gyroscopic": H + 1, "overdamped": H + 1, "parametric": 1,
          "even": 2, "varying": 1}


@pytest.mark.slow  # compiles the full method (~40 s on a loaded machine)
@pytest.mark.parametrize("name", list(cases()))
def test_the_full_method_per_group_of_harmonics(name, kernels):
    both, full, _ = kernels
    A21, A22, n, omega, reference = case_matrices(name)
    ok, lam, count, group, grouped, eigen = full(A21, A22, n, H, omega)
    assert ok and grouped
    assert count == GROUPS[name]
    if name == "even":
        assert list(group) == [0, 1, 0, 1]
    # all eigenvalues, group by group, are those of the whole companion matrix (numpy's)
    scale = np.max(np.abs(reference))
    assert np.max(np.min(np.abs(eigen[:, None] - reference[None, :]), axis=1)) < 1e-12 * scale
    assert np.max(np.min(np.abs(reference[:, None] - eigen[None, :]), axis=1)) < 1e-12 * scale
    # the multipliers are the plain method's (one QR iteration of the whole matrix, every centre) to 1e-12
    plain = both(A21, A22, n, H, omega)
    period = 2.0 * np.pi / omega
    mu, mu_plain = np.exp(lam * period), np.exp(plain[1][plain[2]] * period)
    assert np.max(np.min(np.abs(mu[:, None] - mu_plain[None, :]), axis=1) / np.abs(mu)) < 1e-12
    assert np.max(np.min(np.abs(mu_plain[:, None] - mu[None, :]), axis=1) / np.abs(mu_plain)) < 1e-12


@pytest.mark.slow  # compiles the full method if run alone
def test_a_coupling_above_rounding_joins_harmonics(kernels):
    """An entry joining harmonics 0 and 1 of a time-invariant system's Hill matrix joins their groups once it
    exceeds eps times the largest absolute row sum, and not below (a perturbation of the QR's rounding)."""
    _, full, _ = kernels
    stiffness, damping, omega = cases()["gyroscopic"]
    A21, A22 = hill_blocks(stiffness, damping, omega)
    n = A21.shape[0] // (2 * H + 1)
    norm = np.max(np.sum(np.abs(A21) + np.abs(A22), axis=1))
    for factor, groups in ((0.5, H + 1), (2.0, H)):
        B = A21.copy()
        B[0, n] = factor * np.finfo(float).eps * norm  # harmonic 0's first row, a_1's first column
        count, group = full(B, A22, n, H, omega)[2:4]
        assert count == groups
        assert (group[1] == 0) == (factor > 1.0)


@pytest.fixture(scope="module")
def follow():
    from rotorkit.periodic.compiled_hill_matrix import follow_exponent, group_of, group_workspace, harmonic_groups
    from rotorkit.periodic.eigen import row_norms

    @numba.njit
    def run(A21, A22, n, H, sigma, u, grouped):
        """follow_exponent from (sigma, u) with the groups of harmonic_groups (grouped) or as one group (the
        whole matrix): (lam, converged, eigenvector, number of groups, group of u, groups)."""
        size = A21.shape[0]
        group, rows, f21, f22, fGr, fG, v = group_workspace(n, H)
        count = harmonic_groups(A21, A22, n, H, group)
        groups = count if grouped else 1
        g = group_of(u, n, group)
        n0, n1 = row_norms(A22, A21)
        Gr, ur, wr, br, invr = np.empty((size, size)), np.empty(size), np.empty(size), np.empty(size), np.empty(size)
        piv = np.empty(size, dtype=np.int64)
        G = np.empty((size, size), dtype=np.complex128)
        w, b, inv = (np.empty(size, dtype=np.complex128), np.empty(size, dtype=np.complex128),
                     np.empty(size, dtype=np.complex128))
        x = u.copy()
        lam, ok = follow_exponent(A21, A22, n, groups, group, rows, f21, f22, fGr, fG, v, n0, n1, sigma, x, Gr, ur,
                                  wr, br, invr, piv, G, w, b, inv)
        return lam, ok, x, count, g, group

    return run


@pytest.mark.slow  # compiles the follow (~20 s on a loaded machine)
@pytest.mark.parametrize("name", ["even", "overdamped", "gyroscopic", "isotropic", "identity"])
def test_a_follow_within_one_group_of_harmonics_is_the_whole_matrix_one(name, follow):
    """An exponent followed on the rows of its group of coupled harmonics only (harmonic_groups: even and odd
    harmonics apart for a stiffness varying at 2 w, each harmonic alone for a time-invariant system) must be
    the one followed on the whole matrix to 1e-12, and numpy's eigenvalue; its eigenvector zero outside the
    group; so from the exponent itself. A real exponent (overdamped) from a real shift and start vector stays
    real. A start vector across groups: the whole matrix's follow, bit for bit."""
    # "identity": exponents -1 +- 2i + i k w, exact in floating point, at which the group's block of
    # A21 + lam A22 - lam^2 I is zero to the last bit (the whole matrix is not)
    exact = dict(identity=(lambda t: 5.0 * np.eye(2), lambda t: 2.0 * np.eye(2), 3.0))
    stiffness, damping, omega = {**cases(), **exact}[name]
    n = stiffness(0.0).shape[0]
    A21, A22 = hill_blocks(stiffness, damping, omega)
    size = A21.shape[0]
    big = np.block([[np.zeros((size, size)), np.eye(size)], [A21, A22]])
    values, vectors = np.linalg.eig(big)
    if name in exact:
        values = np.round(values, 9)
    harmonic = (np.arange(size) // n + 1) // 2
    rng = np.random.default_rng(5)
    checked = real = 0
    order = np.argsort(np.abs(values))
    for e in [e for i, e in enumerate(order) if i % 3 == 0 or values[e].imag == 0.0]:
        lam0 = values[e]
        u = vectors[:size, e] / np.max(np.abs(vectors[:size, e]))
        count, g, group = follow(A21, A22, n, H, complex(lam0), u.astype(complex), True)[3:]
        assert count > 1
        if g < 0:
            continue
        outside = group[harmonic] != g
        assert outside.any()
        start = u + 0.01 * rng.standard_normal(size) * (np.abs(u) > 1e-12)
        if lam0.imag == 0.0:
            start = start.real
            sigma = complex(lam0.real * (1.0 + 1e-3))
        else:
            sigma = lam0 * (1.0 + 1e-3 * (1 + 1j))
        got = follow(A21, A22, n, H, sigma, start.astype(complex), True)
        whole = follow(A21, A22, n, H, sigma, start.astype(complex), False)
        assert got[1] and whole[1]
        assert abs(got[0] - whole[0]) <= 1e-12 * abs(whole[0])
        assert abs(got[0] - lam0) <= 1e-9 * abs(lam0)
        assert np.all(got[2][outside] == 0.0) and got[4] == g
        assert np.max(np.abs(np.abs(np.vdot(got[2], whole[2])) - np.linalg.norm(got[2]) * np.linalg.norm(
            whole[2]))) < 1e-9 * np.linalg.norm(whole[2]) ** 2
        # from the exponent itself: the group's block singular to rounding (a multiple of the identity for the
        # isotropic rotor), the whole matrix not
        at = follow(A21, A22, n, H, complex(lam0), u.astype(complex), True)
        assert at[1] and abs(at[0] - lam0) <= 1e-12 * abs(lam0)
        if lam0.imag == 0.0:
            assert got[0].imag == 0.0 and np.all(got[2].imag == 0.0)
            real += 1
        checked += 1
    assert checked >= 4
    if name == "overdamped":
        assert real >= 2
    # a start vector across groups (harmonics 0 and 1, apart in every case): the whole matrix's follow
    spread = np.where(harmonic <= 1, 1.0 + np.arange(size), 0.0).astype(complex)
    sigma = complex(values[np.argmin(np.abs(values))])
    got, whole = follow(A21, A22, n, H, sigma, spread, True), follow(A21, A22, n, H, sigma, spread, False)
    assert got[4] == -1 and np.array_equal([got[0], *got[2]], [whole[0], *whole[2]], equal_nan=True)
