"""Checks of the hand-written AL-31F reference (bench/al31f_handwritten.py).

The reference is what rotorkit's generated equations are compared against,
so it is checked here on its own, against closed-form facts only: printed
paper matrices, the contact laws written out by hand, Lagrangian structure
(symmetric positive definite mass matrix, free eccentric disk, energy
conservation) and agreement of the numba kernel with the numpy reference.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

_PATH = Path(__file__).parents[1] / "bench" / "al31f_handwritten.py"
_spec = importlib.util.spec_from_file_location("al31f_handwritten", _PATH)
h = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(h)

# indices in q = [x1..x7, y1..y7, alpha2, alpha5]
X = {i: i - 1 for i in range(1, 8)}
Y = {i: i + 6 for i in range(1, 8)}
A2, A5 = 14, 15

# everything but the conservative linear part switched off
CONSERVATIVE = dict(
    c_support=0.0, c6=0.0, c7=0.0, c8=0.0, c9=0.0, c10=0.0, ct1=0.0, ct2=0.0,
    e2=0.0, e5=0.0, e7=0.0, kr=0.0, Cb=0.0, g=0.0, roll_radius=0.0,
)


def random_state(rng, disp=1e-4):
    """A state of plausible scale: displacements ~disp, torsion ~1e-2 rad."""
    q = np.concatenate([rng.normal(0.0, disp, 14), rng.normal(0.0, 1e-2, 2)])
    qd = np.concatenate([rng.normal(0.0, 1e3 * disp, 14), rng.normal(0.0, 3.0, 2)])
    return q, qd


# ---------------------------------------------------------------------------
# mass matrix
# ---------------------------------------------------------------------------

def test_mass_matrix_symmetric_positive_definite():
    P = h.params(e2=5e-3, e5=2e-3)  # large eccentricity: strong coupling
    rng = np.random.default_rng(1)
    for _ in range(50):
        q, _ = random_state(rng)
        q[A2], q[A5] = rng.uniform(-np.pi, np.pi, 2)
        M = h.mass_matrix(rng.uniform(0.0, 6.0), q, P)
        assert np.array_equal(M, M.T)
        assert np.linalg.eigvalsh(M).min() > 0.0
        np.linalg.cholesky(M)


def test_mass_matrix_eccentric_coupling_entries():
    P = h.params()
    q = np.zeros(16)
    q[A2], q[A5] = 0.3, -0.7
    t = 0.0123
    M = h.mass_matrix(t, q, P)
    phi2 = P["omega_low"] * t + 0.3
    phi5 = P["omega_low"] * t - 0.7
    me2, me5 = P["m2"] * P["e2"], P["m5"] * P["e5"]
    assert M[X[2], A2] == pytest.approx(-me2 * math.sin(phi2), rel=1e-12)
    assert M[Y[2], A2] == pytest.approx(me2 * math.cos(phi2), rel=1e-12)
    assert M[X[5], A5] == pytest.approx(-me5 * math.sin(phi5), rel=1e-12)
    assert M[Y[5], A5] == pytest.approx(me5 * math.cos(phi5), rel=1e-12)
    assert M[A2, A2] == pytest.approx(P["m2"] * P["R2"] ** 2 / 2 + P["m2"] * P["e2"] ** 2)
    # nothing else off the diagonal
    off = M - np.diag(np.diag(M))
    for i, j in [(X[2], A2), (Y[2], A2), (X[5], A5), (Y[5], A5)]:
        off[i, j] = off[j, i] = 0.0
    assert not off.any()


def test_mass_matrix_constant_diagonal_without_eccentricity():
    P = h.params(e2=0.0, e5=0.0)
    m = [P[f"m{i}"] for i in range(1, 8)]
    J2 = P["m2"] * P["R2"] ** 2 / 2
    J5 = P["m5"] * P["R5"] ** 2 / 2
    expected = np.diag(m + m + [J2, J5])
    rng = np.random.default_rng(2)
    for _ in range(10):
        q, _ = random_state(rng)
        M = h.mass_matrix(rng.uniform(0.0, 6.0), q, P)
        np.testing.assert_array_equal(M, expected)
    np.testing.assert_array_equal(h.linear_matrices(P)[0], expected)


# ---------------------------------------------------------------------------
# printed matrices, eqs. 8, 11, 20
# ---------------------------------------------------------------------------

def paper_matrices(P):
    """M0, C, K written out entry by entry from eqs. 8, 9, 11 and 20."""
    E, I, G, Ip = P["E"], P["I"], P["G"], P["Ip"]
    l1, l2, l3, l4, l5 = (P[f"l{i}"] for i in range(1, 6))
    k1, k2, k3, k5 = P["k1"], P["k2"], P["k3"], P["k5"]
    k6 = 3 * E * I / l1**3
    k7 = 12 * E * I / l2**3
    k8 = 12 * E * I / l3**3
    k9 = 12 * E * I / l4**3
    k10 = 3 * E * I / l5**3
    kt1 = G * Ip / l1
    kt2 = G * Ip / (l2 + l3 + l4)
    c1 = c2 = c3 = c5 = P["c_support"]
    c6, c7, c8, c9, c10 = (P[f"c{i}"] for i in range(6, 11))
    ct1, ct2 = P["ct1"], P["ct2"]

    M = np.zeros((16, 16))
    C = np.zeros((16, 16))
    K = np.zeros((16, 16))
    for o in (0, 7):  # K_x = K_y, C_x = C_y
        for i in range(7):
            M[o + i, o + i] = P[f"m{i + 1}"]
        K[o + 0, o + 0] = k1 + k6
        K[o + 0, o + 1] = -k6
        K[o + 1, o + 0] = -k6
        K[o + 1, o + 1] = k6 + k7
        K[o + 1, o + 2] = -k7
        K[o + 2, o + 1] = -k7
        K[o + 2, o + 2] = k2 + k7 + k8
        K[o + 2, o + 3] = -k8
        K[o + 3, o + 2] = -k8
        K[o + 3, o + 3] = k8 + k9
        K[o + 3, o + 4] = -k9
        K[o + 4, o + 3] = -k9
        K[o + 4, o + 4] = k9 + k10
        K[o + 4, o + 5] = -k10
        K[o + 5, o + 4] = -k10
        K[o + 5, o + 5] = k5 + k10
        K[o + 6, o + 6] = k3
        C[o + 0, o + 0] = c1 + c6
        C[o + 0, o + 1] = -c6
        C[o + 1, o + 0] = -c6
        C[o + 1, o + 1] = c6 + c7
        C[o + 1, o + 2] = -c7
        C[o + 2, o + 1] = -c7
        C[o + 2, o + 2] = c2 + c7 + c8
        C[o + 2, o + 3] = -c8
        C[o + 3, o + 2] = -c8
        C[o + 3, o + 3] = c8 + c9
        C[o + 3, o + 4] = -c9
        C[o + 4, o + 3] = -c9
        C[o + 4, o + 4] = c9 + c10
        C[o + 4, o + 5] = -c10
        C[o + 5, o + 4] = -c10
        C[o + 5, o + 5] = c5 + c10
        C[o + 6, o + 6] = c3
    M[14, 14] = P["m2"] * P["R2"] ** 2 / 2 + P["m2"] * P["e2"] ** 2
    M[15, 15] = P["m5"] * P["R5"] ** 2 / 2 + P["m5"] * P["e5"] ** 2
    K[14, 14] = kt1 + kt2
    K[14, 15] = -kt2
    K[15, 14] = -kt2
    K[15, 15] = kt2
    C[14, 14] = ct1 + ct2
    C[14, 15] = -ct2
    C[15, 14] = -ct2
    C[15, 15] = ct2
    return M, C, K


@pytest.mark.parametrize("overrides", [
    {},
    # distinct values, so that a support or segment on the wrong station shows
    dict(k1=1.1e6, k2=2.2e6, k3=3.3e6, k5=5.5e6, c_support=310.0,
         c6=61.0, c7=72.0, c8=83.0, c9=94.0, c10=105.0, ct1=1.5, ct2=2.5),
])
def test_linear_matrices_equal_printed_paper_matrices(overrides):
    P = h.params(**overrides)
    for got, want, name in zip(h.linear_matrices(P), paper_matrices(P), "MCK"):
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=0, err_msg=name)


def test_shaft_stiffness_values():
    d = h.derived(h.params())
    EI = 2e11 * 1.178e-7
    assert d["k6"] == pytest.approx(3 * EI / 0.33**3, rel=1e-14)
    assert d["k8"] == pytest.approx(12 * EI / 0.6**3, rel=1e-14)
    assert d["kt2"] == pytest.approx(7.7e10 * 2.356e-7 / 1.16, rel=1e-14)
    assert d["omega_high"] == pytest.approx(2700.0)


# ---------------------------------------------------------------------------
# rub
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("frac", [0.0, 0.3, 0.999, 1.0])
def test_rub_force_zero_inside_clearance(frac):
    P = h.params()
    for ang in np.linspace(0.0, 2 * np.pi, 7):
        q = np.zeros(16)
        r = frac * P["delta"]
        q[X[2]], q[Y[2]] = r * np.cos(ang), r * np.sin(ang)
        assert h.rub_force(q, P) == (0.0, 0.0, 0.0)


def test_rub_force_finite_at_centre():
    P = h.params()
    q = np.zeros(16)
    f = h.forcing(0.5, q, np.zeros(16), P)
    assert np.all(np.isfinite(f))
    assert h.rub_force(q, P) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("ang", [0.0, 0.7, 2.0, 4.0])
def test_rub_force_just_above_clearance(ang):
    P = h.params()
    kr, delta, mu, R2 = P["kr"], P["delta"], P["mu"], P["R2"]
    r = delta * (1 + 1e-3)
    x, y = r * math.cos(ang), r * math.sin(ang)
    q = np.zeros(16)
    q[X[2]], q[Y[2]] = x, y
    Fx, Fy, Mr = h.rub_force(q, P)
    a = kr * (r - delta) / r
    assert Fx == pytest.approx(-a * (x - mu * y), rel=1e-9)
    assert Fy == pytest.approx(-a * (mu * x + y), rel=1e-9)
    assert Mr == pytest.approx(-mu * kr * R2 * (r - delta), rel=1e-9)
    # friction opposes the spin: negative torque, clockwise tangential force
    assert Mr < 0.0
    assert Fx * (-y) + Fy * x < 0.0
    # normal part pushes the disk back towards the centre
    assert Fx * x + Fy * y == pytest.approx(-kr * (r - delta) * r, rel=1e-9)


# ---------------------------------------------------------------------------
# bearing
# ---------------------------------------------------------------------------

def test_bearing_force_zero_within_clearance():
    P = h.params()
    rng = np.random.default_rng(3)
    for _ in range(40):
        q, _ = random_state(rng)
        rho = rng.uniform(0.0, 0.999) * P["delta0"]
        ang = rng.uniform(0.0, 2 * np.pi)
        q[X[7]] = q[X[4]] + rho * np.cos(ang)
        q[Y[7]] = q[Y[4]] + rho * np.sin(ang)
        assert h.bearing_force(rng.uniform(0.0, 6.0), q, P) == (0.0, 0.0)


@pytest.mark.parametrize("d", [6e-6, 2e-5])
def test_bearing_force_pure_x_offset_hand_sum(d):
    P = h.params()
    Cb, d0 = P["Cb"], P["delta0"]
    q = np.zeros(16)
    q[X[7]] = d  # x7 - x4 = d, cage at t = 0: balls at 0, 45, ..., 315 deg
    Fx, Fy = h.bearing_force(0.0, q, P)
    # ball at 0 deg; balls at +-45 deg if d cos45 > delta0; others unloaded
    c45 = math.sqrt(0.5)
    expected = Cb * (d - d0) ** 1.5
    if d * c45 > d0:
        expected += 2 * Cb * (d * c45 - d0) ** 1.5 * c45
    assert Fx == pytest.approx(expected, rel=1e-13)
    assert Fx > 0.0  # pulls station 4 towards station 7
    assert abs(Fy) < 1e-13 * Fx
    # action on 4, reaction on 7, in the full forcing
    Pb = h.params(**{**CONSERVATIVE, "Cb": P["Cb"], "E": 0.0, "k3": 0.0})
    f = h.forcing(0.0, q, np.zeros(16), Pb)
    assert f[X[4]] == pytest.approx(Fx, rel=1e-13)
    assert f[X[7]] == pytest.approx(-Fx, rel=1e-13)


# ---------------------------------------------------------------------------
# manoeuvre
# ---------------------------------------------------------------------------

def test_maneuver_acceleration():
    P = h.params()
    g, W, R = P["g"], P["roll_rate"], P["roll_radius"]
    assert h.maneuver_acceleration(0.0, P) == (0.0, -g)
    assert h.maneuver_acceleration(1.999, P) == (0.0, -g)
    ax, ay = h.maneuver_acceleration(2.0, P)  # inertial term switches on
    assert (ax, ay) == pytest.approx((W**2 * R, -g), rel=1e-15)
    t = 2.37
    th = W * (t - 2.0)
    ax, ay = h.maneuver_acceleration(t, P)
    assert ax == pytest.approx(W**2 * R * math.cos(th) - g * math.sin(2 * th), rel=1e-13)
    assert ay == pytest.approx(-W**2 * R * math.sin(th) - g * math.cos(2 * th), rel=1e-13)
    for t in (4.0, 5.0):  # off again; theta frozen at 2 pi: gravity straight down
        ax, ay = h.maneuver_acceleration(t, P)
        assert ax == pytest.approx(0.0, abs=1e-12)
        assert ay == pytest.approx(-g, rel=1e-14)


def test_static_sag_under_gravity():
    """Without unbalance, rub and bearing, q = K^-1 m g is an equilibrium."""
    P = h.params(e2=0.0, e5=0.0, e7=0.0, kr=0.0, Cb=0.0)
    _, _, K = h.linear_matrices(P)
    load = np.zeros(16)
    load[7:14] = [-P[f"m{i}"] * P["g"] for i in range(1, 8)]
    q = np.linalg.solve(K, load)
    assert np.all(q[7:14] < 0.0)
    dydt = h.rhs_numpy(1.0, np.concatenate([q, np.zeros(16)]), P)
    assert np.abs(dydt[16:]).max() < 1e-9 * P["g"]


# ---------------------------------------------------------------------------
# derivation of the eccentric disk terms
# ---------------------------------------------------------------------------

def _free_disk_params():
    # no stiffness, damping or external load: each disk is a free rigid body
    return h.params(**{**CONSERVATIVE, "e2": 5e-3, "e5": 2e-3, "E": 0.0, "G": 0.0,
                       "k1": 0.0, "k2": 0.0, "k3": 0.0, "k5": 0.0})


def _check_free_disk(t, y, dydt, P):
    """Centroid acceleration and spin acceleration of a free disk vanish."""
    for ix, iy, ia, m, e, phi0 in ((X[2], Y[2], A2, "m2", "e2", "phi02"),
                                   (X[5], Y[5], A5, "m5", "e5", "phi05")):
        phi = P["omega_low"] * t + y[ia] + P[phi0]
        phid = P["omega_low"] + y[16 + ia]
        add = dydt[16 + ia]
        # d/dt of v_G = (x_dot - e phi_dot sin phi, y_dot + e phi_dot cos phi)
        aGx = dydt[16 + ix] - P[e] * (add * math.sin(phi) + phid**2 * math.cos(phi))
        aGy = dydt[16 + iy] + P[e] * (add * math.cos(phi) - phid**2 * math.sin(phi))
        scale = P[e] * phid**2
        assert abs(add) < 1e-9 * scale / P[e]
        assert abs(aGx) < 1e-12 * scale
        assert abs(aGy) < 1e-12 * scale


def test_free_eccentric_disk_centroid_moves_uniformly():
    P = _free_disk_params()
    rng = np.random.default_rng(4)
    for _ in range(20):
        q, qd = random_state(rng)
        t = rng.uniform(0.0, 6.0)
        y = np.concatenate([q, qd])
        _check_free_disk(t, y, h.rhs_numpy(t, y, P), P)


# ---------------------------------------------------------------------------
# numba kernel against the numpy reference
# ---------------------------------------------------------------------------

def test_numba_matches_numpy():
    pytest.importorskip("numba")
    rhs = h.make_rhs_numba()
    rng = np.random.default_rng(5)
    out = np.empty(32)
    cases = [(h.params(), 1e-4), (h.params(), 1e-5),
             (h.params(e2=5e-3, e5=2e-3, mu=0.3, kr=2e7), 1e-4)]
    n_rub = n_bearing = 0
    for P, disp in cases:
        p = h.pack(P)
        for k in range(300):
            q, qd = random_state(rng, disp)
            if k == 0:
                q[X[2]] = q[Y[2]] = 0.0  # rub law at r2 = 0
            t = rng.uniform(0.0, 6.0)
            y = np.concatenate([q, qd])
            ref = h.rhs_numpy(t, y, P)
            rhs(t, y, p, out)
            assert np.all(np.isfinite(out))
            np.testing.assert_array_equal(out[:16], ref[:16])
            # Normwise per block. The floor is the rounding of the ball
            # angle omega_c t + 2 pi j / Nb (|theta| up to 1.4e4 rad, ulp
            # ~2e-12): the kernel rotates cos/sin(omega_c t) instead.
            bend, tors = slice(16, 30), slice(30, 32)
            for blk in (bend, tors):
                err = np.abs(out[blk] - ref[blk]).max() / np.abs(ref[blk]).max()
                assert err < 5e-12, (P, t, y)
            n_rub += h.rub_force(q, P)[0] != 0.0
            n_bearing += h.bearing_force(t, q, P)[0] != 0.0
    assert n_rub > 50 and n_bearing > 50  # the nonlinear branches were exercised


def test_numba_free_eccentric_disk():
    pytest.importorskip("numba")
    rhs = h.make_rhs_numba()
    P = _free_disk_params()
    p = h.pack(P)
    rng = np.random.default_rng(6)
    out = np.empty(32)
    for _ in range(20):
        q, qd = random_state(rng)
        t = rng.uniform(0.0, 6.0)
        y = np.concatenate([q, qd])
        rhs(t, y, p, out)
        _check_free_disk(t, y, out, P)


# ---------------------------------------------------------------------------
# energy conservation
# ---------------------------------------------------------------------------

def _energy(t, y, P, K):
    q, qd = y[:16], y[16:]
    return 0.5 * qd @ h.mass_matrix(t, q, P) @ qd + 0.5 * q @ K @ q


def _run_energy(P, y0, t_end):
    K = h.linear_matrices(P)[2]
    sol = solve_ivp(lambda t, y: h.rhs_numpy(t, y, P), (0.0, t_end), y0,
                    method="DOP853", rtol=1e-12, atol=1e-14, dense_output=False)
    assert sol.success, sol.message
    E = np.array([_energy(t, y, P, K) for t, y in zip(sol.t, sol.y.T)])
    return E, sol


def test_energy_conserved_free_oscillation():
    P = h.params(**CONSERVATIVE)
    rng = np.random.default_rng(7)
    q0, qd0 = random_state(rng, 1e-5)
    E, sol = _run_energy(P, np.concatenate([q0, qd0]), 2e-2)
    assert sol.t.size > 20
    assert np.abs(E / E[0] - 1.0).max() < 1e-9


def test_energy_conserved_eccentric_disks_without_drive():
    """omega_low = 0 makes T = 1/2 qd^T M(q) qd exactly (no rheonomic term).

    With large eccentricities and a soft torsion spring the disks swing
    through ~1 rad, so the state-dependent couplings and the centripetal
    forces exchange energy between bending and torsion; a wrong sign or a
    missing term in either shows as energy drift.
    """
    P = h.params(**{**CONSERVATIVE, "omega_low": 0.0, "e2": 5e-3, "e5": 3e-3,
                    "G": 7.7e8})
    y0 = np.zeros(32)
    y0[16 + A2] = 200.0
    y0[16 + A5] = -120.0
    y0[16 + X[2]] = 0.05
    E, sol = _run_energy(P, y0, 2e-2)
    assert np.ptp(sol.y[A2]) > 1.0  # the disk really turned
    assert np.ptp(sol.y[X[2]]) > 1e-4  # and the shaft really bent
    assert np.abs(E / E[0] - 1.0).max() < 1e-9


# ---------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------

def test_params_rejects_unknown_name():
    with pytest.raises(TypeError, match="omega_lo"):
        h.params(omega_lo=1.0)


@pytest.mark.parametrize("nb", [0, 2.5])
def test_pack_rejects_bad_ball_count(nb):
    with pytest.raises(ValueError, match="Nb"):
        h.pack(h.params(Nb=nb))


def test_pack_layout():
    P = h.params()
    p = h.pack(P)
    assert p.dtype == np.float64 and p.shape == (len(h.PACKED_NAMES),)
    d = h.derived(P)
    assert p[h.PACKED_NAMES.index("omega_c")] == d["omega_c"]
    assert p[h.PACKED_NAMES.index("1/J5")] == 1.0 / d["J5"]
    assert p[h.PACKED_NAMES.index("g")] == P["g"]
