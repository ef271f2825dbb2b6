"""Hand-written AL-31F dual-rotor equations of motion (independent reference).

This module implements the 16-DOF rub-impact dual-rotor model of
``shared/paper/rub-impact-dual-rotor.txt`` (eqs. 1-20, Table 1) as settled
by ``shared/MODEL_NOTES.md``, written by hand from the model description.
It shares no code with rotorkit and must never import it: it exists to test
and benchmark rotorkit's symbolic derivation and generated code.

Two implementations of the same right-hand side are provided:

* :func:`rhs_numpy` -- a clear reference: assemble the full 16x16 mass
  matrix and the forcing vector, then ``np.linalg.solve``.
* :func:`make_rhs_numba` -- returns ``rhs_numba(t, y, p, dydt)``, a
  hand-optimised ``numba.njit`` kernel (closed-form 3x3 disk solves, no
  allocation, ball angles by angle addition), the "hand-written compiled"
  baseline for benchmarks. numba is imported lazily and stays optional.

States (fixed convention)
-------------------------
``q = [x1..x7, y1..y7, alpha2, alpha5]`` (16), ``y = [q, q_dot]`` (32) and
``dy/dt = [q_dot, q_ddot]``. Units: m, rad, s, SI throughout.

Equations of motion
-------------------
``M(t, q) q_ddot = f(t, q, q_dot)`` with

``f = -C q_dot - K q + F_u + F_b + F_r + F_g``

* ``C``, ``K``: the printed eqs. 8 and 11 (supports k1, k2, k3, k5 on x1,
  x3, x7, x6; shaft segments k6..k10 between stations 1-2 ... 5-6; torsion
  kt1 from alpha2 to the constant-speed drive, kt2 between alpha2 and
  alpha5); same matrices in x and y.
* ``F_b``: intermediate ball bearing, +F on station 4, -F on station 7.
* ``F_r``: rub at disk 2 (forces on x2, y2 and friction torque on alpha2).
* ``F_g``: gravity and barrel-roll load ``m_i (a_x, a_y)`` on every mass
  m1..m7, x and y only.
* ``F_u``: HP unbalance ``m7 e7 omega_high^2 (cos, sin)(omega_high t)``
  (kinematic) and the centripetal terms of the LP disks derived below.

Derivation of the LP disk terms (i = 2, 5)
------------------------------------------
Phase ``phi = omega_low t + alpha + phi0``, so ``phi_dot = omega_low +
alpha_dot`` and ``phi_ddot = alpha_ddot``. Centroid ``(x + e cos phi,
y + e sin phi)``, centroid velocity

    v_G = (x_dot - e phi_dot sin phi,  y_dot + e phi_dot cos phi).

Kinetic energy ``T = 1/2 m |v_G|^2 + 1/2 J phi_dot^2`` expands to

    T = 1/2 m (x_dot^2 + y_dot^2)
        + m e phi_dot (-x_dot sin phi + y_dot cos phi)
        + 1/2 (J + m e^2) phi_dot^2.

Lagrange, coordinate x:
    dT/dx_dot = m x_dot - m e phi_dot sin phi
    d/dt      = m x_ddot - m e sin phi alpha_ddot - m e phi_dot^2 cos phi
    dT/dx     = 0
    =>  m x_ddot - m e sin phi alpha_ddot = m e phi_dot^2 cos phi + Q_x
Coordinate y:
    dT/dy_dot = m y_dot + m e phi_dot cos phi
    d/dt      = m y_ddot + m e cos phi alpha_ddot - m e phi_dot^2 sin phi
    =>  m y_ddot + m e cos phi alpha_ddot = m e phi_dot^2 sin phi + Q_y
Coordinate alpha:
    dT/dalpha_dot = m e (-x_dot sin phi + y_dot cos phi) + (J + m e^2) phi_dot
    d/dt = m e (-x_ddot sin phi + y_ddot cos phi)
           - m e phi_dot (x_dot cos phi + y_dot sin phi)
           + (J + m e^2) alpha_ddot
    dT/dalpha = -m e phi_dot (x_dot cos phi + y_dot sin phi)
    (the two velocity-product terms cancel)
    =>  -m e sin phi x_ddot + m e cos phi y_ddot + (J + m e^2) alpha_ddot = Q_alpha

So the (x, y, alpha) block of a disk is

    [[ m,           0,          -m e sin phi ],
     [ 0,           m,           m e cos phi ],
     [ -m e sin phi, m e cos phi, J + m e^2  ]]

and the only velocity-dependent inertial forcing is the centripetal pair
``m e phi_dot^2 (cos phi, sin phi)`` on (x, y), with ``phi_dot = omega_low +
alpha_dot``; the alpha row gets none. (This is the paper's F_u / F_ua with
the acceleration terms moved to the left-hand side.) Gravity and manoeuvre
loads act on the shaft centre only, with no torsional term (MODEL_NOTES).

Closed-form block solve (used by the numba kernel): with ``s = sin phi``,
``c = cos phi`` and right-hand sides ``(f_x, f_y, f_a)``, eliminating x_ddot
and y_ddot from the alpha row leaves the Schur complement ``J``:

    alpha_ddot = (f_a + e (s f_x - c f_y)) / J
    x_ddot     = f_x / m + e s alpha_ddot
    y_ddot     = f_y / m - e c alpha_ddot

(``det = m^2 J > 0``: the block is positive definite whenever m, J > 0.)
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "DEFAULTS",
    "PACKED_NAMES",
    "params",
    "derived",
    "linear_matrices",
    "mass_matrix",
    "bearing_force",
    "rub_force",
    "maneuver_acceleration",
    "unbalance_force",
    "forcing",
    "rhs_numpy",
    "pack",
    "make_rhs_numba",
]

#: Physical parameters in SI (Table 1 and MODEL_NOTES).
DEFAULTS: dict[str, float] = {
    # lumped masses (kg): LP stations 1..6, HP rotor 7
    "m1": 2.0, "m2": 10.0, "m3": 2.0, "m4": 2.0, "m5": 6.0, "m6": 2.0,
    "m7": 8.0,
    # LP disk radii (m); J_i = m_i R_i^2 / 2
    "R2": 0.075, "R5": 0.03,
    # eccentricities (m) and initial phases (rad)
    "e2": 46.35e-6, "e5": 46.35e-6, "e7": 47.5e-6,
    "phi02": 0.0, "phi05": 0.0,
    # supports (N/m) on x1 (k1), x3 (k2), x7 (k3), x6 (k5); damping (N s/m)
    "k1": 1e6, "k2": 1e6, "k3": 1e6, "k5": 1e6,
    "c_support": 300.0,
    # shaft: E (Pa), I (m^4), segment lengths (m)
    "E": 2e11, "I": 1.178e-7,
    "l1": 0.33, "l2": 0.33, "l3": 0.6, "l4": 0.23, "l5": 0.23,
    # torsion: G (Pa), Ip (m^4)
    "G": 7.7e10, "Ip": 2.356e-7,
    # shaft bending damping (N s/m) and torsional damping (N m s/rad)
    "c6": 150.0, "c7": 150.0, "c8": 150.0, "c9": 150.0, "c10": 150.0,
    "ct1": 1.0, "ct2": 1.0,
    # intermediate ball bearing
    "Cb": 1.334e10, "delta0": 5e-6, "R_inner": 40.1e-3, "R_outer": 63.9e-3,
    "Nb": 8,
    # rub-impact at disk 2
    "kr": 8e6, "delta": 1.34e-4, "mu": 0.1,
    # speeds (rad/s)
    "omega_low": 1500.0, "speed_ratio": 1.8,
    # barrel roll
    "roll_rate": math.pi, "roll_radius": 3.0, "roll_start": 2.0,
    "roll_end": 4.0, "g": 9.81,
}

_LP_MASSES = ("m1", "m2", "m3", "m4", "m5", "m6", "m7")


def params(**overrides: float) -> dict[str, float]:
    """Return a copy of :data:`DEFAULTS` with ``overrides`` applied.

    Raises
    ------
    TypeError
        If an override names a parameter that does not exist.
    """
    unknown = sorted(set(overrides) - set(DEFAULTS))
    if unknown:
        raise TypeError(
            f"unknown AL-31F parameter(s) {unknown}; expected names from DEFAULTS"
        )
    P = dict(DEFAULTS)
    P.update(overrides)
    return P


def derived(P: dict) -> dict[str, float]:
    """Derived constants: shaft stiffnesses, inertias, speeds.

    Returns k6..k10 (N/m), kt1, kt2 (N m/rad), J2, J5 (kg m^2),
    omega_high and the cage speed omega_c (rad/s).
    """
    EI = P["E"] * P["I"]
    GIp = P["G"] * P["Ip"]
    wl = P["omega_low"]
    wh = P["speed_ratio"] * wl
    return {
        "k6": 3.0 * EI / P["l1"] ** 3,
        "k7": 12.0 * EI / P["l2"] ** 3,
        "k8": 12.0 * EI / P["l3"] ** 3,
        "k9": 12.0 * EI / P["l4"] ** 3,
        "k10": 3.0 * EI / P["l5"] ** 3,
        "kt1": GIp / P["l1"],
        "kt2": GIp / (P["l2"] + P["l3"] + P["l4"]),
        "J2": 0.5 * P["m2"] * P["R2"] ** 2,
        "J5": 0.5 * P["m5"] * P["R5"] ** 2,
        "omega_high": wh,
        "omega_c": (wl * P["R_inner"] + wh * P["R_outer"])
        / (P["R_inner"] + P["R_outer"]),
    }


# ---------------------------------------------------------------------------
# Linear part (paper eqs. 8, 11, 20)
# ---------------------------------------------------------------------------

def _chain_matrix(a1, a2, a3, a5, a6, a7, a8, a9, a10):
    """The 7x7 pattern of eqs. 8 / 11 (supports a1, a2, a3, a5; shaft a6..a10)."""
    return np.array([
        [a1 + a6, -a6, 0, 0, 0, 0, 0],
        [-a6, a6 + a7, -a7, 0, 0, 0, 0],
        [0, -a7, a2 + a7 + a8, -a8, 0, 0, 0],
        [0, 0, -a8, a8 + a9, -a9, 0, 0],
        [0, 0, 0, -a9, a9 + a10, -a10, 0],
        [0, 0, 0, 0, -a10, a5 + a10, 0],
        [0, 0, 0, 0, 0, 0, a3],
    ], dtype=float)


def _block_diag(A, B, T):
    out = np.zeros((16, 16))
    out[:7, :7] = A
    out[7:14, 7:14] = B
    out[14:, 14:] = T
    return out


def linear_matrices(P: dict):
    """Constant matrices of the paper, eqs. 8, 11 and 20.

    Returns
    -------
    M0 : (16, 16) ndarray
        ``blockdiag(M_c, M_c, J'_c)`` with ``J'_c = diag(J2 + m2 e2^2,
        J5 + m5 e5^2)`` (kg, kg m^2). This is the mass matrix without the
        state-dependent eccentric coupling; see :func:`mass_matrix`.
    C : (16, 16) ndarray
        ``blockdiag(C_x, C_y, C_t)`` (N s/m, N m s/rad).
    K : (16, 16) ndarray
        ``blockdiag(K_x, K_y, K_t)`` (N/m, N m/rad).
    """
    d = derived(P)
    Mc = np.diag([float(P[name]) for name in _LP_MASSES])
    Jc = np.diag([d["J2"] + P["m2"] * P["e2"] ** 2,
                  d["J5"] + P["m5"] * P["e5"] ** 2])
    cs = P["c_support"]
    Cx = _chain_matrix(cs, cs, cs, cs, P["c6"], P["c7"], P["c8"], P["c9"], P["c10"])
    Kx = _chain_matrix(P["k1"], P["k2"], P["k3"], P["k5"],
                       d["k6"], d["k7"], d["k8"], d["k9"], d["k10"])
    ct1, ct2 = P["ct1"], P["ct2"]
    kt1, kt2 = d["kt1"], d["kt2"]
    Ct = np.array([[ct1 + ct2, -ct2], [-ct2, ct2]])
    Kt = np.array([[kt1 + kt2, -kt2], [-kt2, kt2]])
    return _block_diag(Mc, Mc, Jc), _block_diag(Cx, Cx, Ct), _block_diag(Kx, Kx, Kt)


# ---------------------------------------------------------------------------
# State-dependent mass matrix
# ---------------------------------------------------------------------------

# (index of x_i, index of y_i, index of alpha_i, mass, e, phi0) for the LP disks
_DISKS = ((1, 8, 14, "m2", "e2", "phi02"), (4, 11, 15, "m5", "e5", "phi05"))


def mass_matrix(t: float, q, P: dict) -> np.ndarray:
    """Full mass matrix ``M(t, q)`` (16, 16).

    ``M0`` of :func:`linear_matrices` plus, for each LP disk i = 2, 5 with
    ``phi_i = omega_low t + alpha_i + phi0_i``, the symmetric couplings
    ``M[x_i, alpha_i] = -m_i e_i sin(phi_i)`` and
    ``M[y_i, alpha_i] = m_i e_i cos(phi_i)``.
    """
    M = linear_matrices(P)[0]
    wl = P["omega_low"]
    for ix, iy, ia, m, e, phi0 in _DISKS:
        phi = wl * t + q[ia] + P[phi0]
        me = P[m] * P[e]
        M[ix, ia] = M[ia, ix] = -me * np.sin(phi)
        M[iy, ia] = M[ia, iy] = me * np.cos(phi)
    return M


# ---------------------------------------------------------------------------
# Generalised forces
# ---------------------------------------------------------------------------

def bearing_force(t: float, q, P: dict):
    """Intermediate ball bearing force ``(F_x, F_y)`` (N) on station 4.

    Station 7 receives ``(-F_x, -F_y)``. Ball j at
    ``theta_j = omega_c t + 2 pi (j - 1) / Nb``; deformation
    ``delta_j = (x7 - x4) cos theta_j + (y7 - y4) sin theta_j - delta0``;
    ``F = Cb sum max(delta_j, 0)^1.5 (cos theta_j, sin theta_j)``.
    """
    Nb = int(P["Nb"])
    wc = derived(P)["omega_c"]
    theta = wc * t + 2.0 * np.pi * np.arange(Nb) / Nb
    c, s = np.cos(theta), np.sin(theta)
    dj = (q[6] - q[3]) * c + (q[13] - q[10]) * s - P["delta0"]
    w = P["Cb"] * np.maximum(dj, 0.0) ** 1.5
    return float(np.sum(w * c)), float(np.sum(w * s))


def rub_force(q, P: dict):
    """Rub-impact at disk 2: ``(F_x, F_y, M_r)`` (N, N, N m).

    For ``r2 = hypot(x2, y2) > delta``:
    ``(F_x, F_y) = -kr (r2 - delta) / r2 [[1, -mu], [mu, 1]] (x2, y2)`` and
    friction torque on alpha2 ``M_r = -mu kr R2 (r2 - delta)`` (opposes the
    positive spin; MODEL_NOTES overrides the paper's + sign). All zero for
    ``r2 <= delta`` (so finite at ``r2 = 0``).
    """
    x2, y2 = q[1], q[8]
    r2 = math.hypot(x2, y2)
    if not r2 > P["delta"]:
        return 0.0, 0.0, 0.0
    pen = r2 - P["delta"]
    a = P["kr"] * pen / r2
    mu = P["mu"]
    return (-a * (x2 - mu * y2), -a * (mu * x2 + y2), -mu * P["kr"] * P["R2"] * pen)


def maneuver_acceleration(t: float, P: dict):
    """Gravity + barrel-roll load per unit mass ``(a_x, a_y)`` (m/s^2).

    ``theta = roll_rate * clip(t - roll_start, 0, roll_end - roll_start)``;
    the inertial term ``roll_rate^2 roll_radius (cos theta, -sin theta)`` is
    on for ``roll_start <= t < roll_end``; gravity
    ``-g (sin 2 theta, cos 2 theta)`` acts always. The load on mass i is
    ``m_i (a_x, a_y)``.
    """
    t0, t1 = P["roll_start"], P["roll_end"]
    theta = P["roll_rate"] * min(max(t - t0, 0.0), t1 - t0)
    ax = -P["g"] * math.sin(2.0 * theta)
    ay = -P["g"] * math.cos(2.0 * theta)
    if t0 <= t < t1:
        A = P["roll_rate"] ** 2 * P["roll_radius"]
        ax += A * math.cos(theta)
        ay -= A * math.sin(theta)
    return ax, ay


def unbalance_force(t: float, q, qd, P: dict) -> np.ndarray:
    """Velocity-dependent unbalance forcing (16,) (N, N m).

    LP disks: centripetal ``m e (omega_low + alpha_dot)^2 (cos phi, sin phi)``
    on (x_i, y_i) (the acceleration coupling is in :func:`mass_matrix`);
    HP rotor: ``m7 e7 omega_high^2 (cos, sin)(omega_high t)`` on (x7, y7).
    """
    f = np.zeros(16)
    wl = P["omega_low"]
    for ix, iy, ia, m, e, phi0 in _DISKS:
        phi = wl * t + q[ia] + P[phi0]
        cent = P[m] * P[e] * (wl + qd[ia]) ** 2
        f[ix] += cent * np.cos(phi)
        f[iy] += cent * np.sin(phi)
    wh = P["speed_ratio"] * wl
    hp = P["m7"] * P["e7"] * wh ** 2
    f[6] += hp * np.cos(wh * t)
    f[13] += hp * np.sin(wh * t)
    return f


def forcing(t: float, q, qd, P: dict) -> np.ndarray:
    """Right-hand side ``f(t, q, q_dot)`` (16,) with ``M q_ddot = f``."""
    q = np.asarray(q, dtype=float)
    qd = np.asarray(qd, dtype=float)
    _, C, K = linear_matrices(P)
    f = -C @ qd - K @ q + unbalance_force(t, q, qd, P)
    Fbx, Fby = bearing_force(t, q, P)
    f[3] += Fbx
    f[10] += Fby
    f[6] -= Fbx
    f[13] -= Fby
    Frx, Fry, Mr = rub_force(q, P)
    f[1] += Frx
    f[8] += Fry
    f[14] += Mr
    ax, ay = maneuver_acceleration(t, P)
    m = np.array([P[name] for name in _LP_MASSES], dtype=float)
    f[0:7] += m * ax
    f[7:14] += m * ay
    return f


def rhs_numpy(t: float, y, P: dict) -> np.ndarray:
    """Reference ``dy/dt = [q_dot, M^-1 f]`` (32,) via ``np.linalg.solve``."""
    y = np.asarray(y, dtype=float)
    q, qd = y[:16], y[16:]
    qdd = np.linalg.solve(mass_matrix(t, q, P), forcing(t, q, qd, P))
    return np.concatenate((qd, qdd))


# ---------------------------------------------------------------------------
# Hand-optimised compiled kernel
# ---------------------------------------------------------------------------

#: Layout of the vector returned by :func:`pack` (derived constants included).
PACKED_NAMES = (
    "m1", "m2", "m3", "m4", "m5", "m6", "m7",                       # 0-6
    "1/m1", "1/m2", "1/m3", "1/m4", "1/m5", "1/m6", "1/m7",         # 7-13
    "e2", "e5", "m2*e2", "m5*e5", "1/J2", "1/J5", "phi02", "phi05",  # 14-21
    "k1", "k2", "k3", "k5", "c_support",                            # 22-26
    "k6", "k7", "k8", "k9", "k10",                                  # 27-31
    "c6", "c7", "c8", "c9", "c10",                                  # 32-36
    "kt1", "kt2", "ct1", "ct2",                                     # 37-40
    "Cb", "delta0", "omega_c", "Nb", "cos(2pi/Nb)", "sin(2pi/Nb)",   # 41-46
    "kr", "delta", "mu", "mu*kr*R2",                                # 47-50
    "omega_low", "omega_high", "m7*e7*omega_high^2",                # 51-53
    "roll_rate", "roll_rate^2*roll_radius", "roll_start", "roll_end",
    "g",                                                            # 54-58
)


def pack(P: dict) -> np.ndarray:
    """Flatten ``P`` into the float64 vector read by ``rhs_numba``.

    The layout is :data:`PACKED_NAMES`; it holds derived constants
    (reciprocal masses and inertias, shaft stiffnesses, cage speed, ...)
    so the kernel does no divisions by parameters.
    """
    d = derived(P)
    Nb = int(P["Nb"])
    if Nb < 1 or Nb != P["Nb"]:
        raise ValueError(f"Nb must be a positive integer number of balls, got {P['Nb']!r}")
    wh = d["omega_high"]
    m = [float(P[name]) for name in _LP_MASSES]
    vals = (
        *m,
        *(1.0 / mi for mi in m),
        P["e2"], P["e5"], P["m2"] * P["e2"], P["m5"] * P["e5"],
        1.0 / d["J2"], 1.0 / d["J5"], P["phi02"], P["phi05"],
        P["k1"], P["k2"], P["k3"], P["k5"], P["c_support"],
        d["k6"], d["k7"], d["k8"], d["k9"], d["k10"],
        P["c6"], P["c7"], P["c8"], P["c9"], P["c10"],
        d["kt1"], d["kt2"], P["ct1"], P["ct2"],
        P["Cb"], P["delta0"], d["omega_c"], float(Nb),
        math.cos(2.0 * math.pi / Nb), math.sin(2.0 * math.pi / Nb),
        P["kr"], P["delta"], P["mu"], P["mu"] * P["kr"] * P["R2"],
        P["omega_low"], wh, P["m7"] * P["e7"] * wh * wh,
        P["roll_rate"], P["roll_rate"] ** 2 * P["roll_radius"],
        P["roll_start"], P["roll_end"], P["g"],
    )
    p = np.array(vals, dtype=np.float64)
    assert p.shape == (len(PACKED_NAMES),)
    return p


def _rhs_kernel(t, y, p, dydt):
    """Hand-optimised RHS; writes ``dy/dt`` into ``dydt`` (32,). Pure loops.

    Plain Python here; :func:`make_rhs_numba` compiles it. ``dydt[16:]`` is
    used first for the generalised forces, then turned into accelerations.
    """
    # --- parameters (layout: PACKED_NAMES) ---
    m1 = p[0]; m2 = p[1]; m3 = p[2]; m4 = p[3]; m5 = p[4]; m6 = p[5]; m7 = p[6]
    e2 = p[14]; e5 = p[15]; m2e2 = p[16]; m5e5 = p[17]
    iJ2 = p[18]; iJ5 = p[19]; phi02 = p[20]; phi05 = p[21]
    k1 = p[22]; k2 = p[23]; k3 = p[24]; k5 = p[25]; cs = p[26]
    k6 = p[27]; k7 = p[28]; k8 = p[29]; k9 = p[30]; k10 = p[31]
    c6 = p[32]; c7 = p[33]; c8 = p[34]; c9 = p[35]; c10 = p[36]
    kt1 = p[37]; kt2 = p[38]; ct1 = p[39]; ct2 = p[40]
    Cb = p[41]; delta0 = p[42]; wc = p[43]; nb = int(p[44])
    cd = p[45]; sd = p[46]
    kr = p[47]; delta = p[48]; mu = p[49]; mukrR2 = p[50]
    wl = p[51]; wh = p[52]; hp = p[53]
    roll_rate = p[54]; roll_acc = p[55]; t0 = p[56]; t1 = p[57]; g = p[58]

    for i in range(16):
        dydt[i] = y[16 + i]

    # --- gravity + barrel roll (per unit mass) ---
    tau = t - t0
    if tau < 0.0:
        tau = 0.0
    elif tau > t1 - t0:
        tau = t1 - t0
    theta = roll_rate * tau
    if theta == 0.0:                     # steady flight before the roll
        sth = 0.0
        cth = 1.0
    else:
        sth = math.sin(theta)
        cth = math.cos(theta)
    ax = -g * (2.0 * sth * cth)          # -g sin 2 theta
    ay = -g * (cth * cth - sth * sth)    # -g cos 2 theta
    if t >= t0 and t < t1:
        ax += roll_acc * cth
        ay -= roll_acc * sth

    # --- bending: shaft segments + supports, same in x (off=0) and y (off=7) ---
    for off in range(0, 14, 7):
        u1 = y[off]; u2 = y[off + 1]; u3 = y[off + 2]; u4 = y[off + 3]
        u5 = y[off + 4]; u6 = y[off + 5]; u7 = y[off + 6]
        v1 = y[16 + off]; v2 = y[17 + off]; v3 = y[18 + off]; v4 = y[19 + off]
        v5 = y[20 + off]; v6 = y[21 + off]; v7 = y[22 + off]
        s12 = k6 * (u1 - u2) + c6 * (v1 - v2)
        s23 = k7 * (u2 - u3) + c7 * (v2 - v3)
        s34 = k8 * (u3 - u4) + c8 * (v3 - v4)
        s45 = k9 * (u4 - u5) + c9 * (v4 - v5)
        s56 = k10 * (u5 - u6) + c10 * (v5 - v6)
        a = ax if off == 0 else ay
        dydt[16 + off] = -k1 * u1 - cs * v1 - s12 + m1 * a
        dydt[17 + off] = s12 - s23 + m2 * a
        dydt[18 + off] = s23 - s34 - k2 * u3 - cs * v3 + m3 * a
        dydt[19 + off] = s34 - s45 + m4 * a
        dydt[20 + off] = s45 - s56 + m5 * a
        dydt[21 + off] = s56 - k5 * u6 - cs * v6 + m6 * a
        dydt[22 + off] = -k3 * u7 - cs * v7 + m7 * a

    # --- torsion ---
    a2 = y[14]; a5 = y[15]; ad2 = y[30]; ad5 = y[31]
    st = kt2 * (a2 - a5) + ct2 * (ad2 - ad5)
    fa2 = -kt1 * a2 - ct1 * ad2 - st
    fa5 = st

    # --- HP unbalance (kinematic) ---
    wht = wh * t
    dydt[22] += hp * math.cos(wht)
    dydt[29] += hp * math.sin(wht)

    # --- intermediate bearing: balls by angle addition from one sin/cos ---
    dx = y[6] - y[3]
    dy = y[13] - y[10]
    if dx * dx + dy * dy > delta0 * delta0:   # else no ball can be loaded
        wct = wc * t
        c = math.cos(wct)
        s = math.sin(wct)
        fbx = 0.0
        fby = 0.0
        for _ in range(nb):
            dj = dx * c + dy * s - delta0
            if dj > 0.0:
                w = Cb * dj * math.sqrt(dj)
                fbx += w * c
                fby += w * s
            c, s = c * cd - s * sd, s * cd + c * sd
        dydt[19] += fbx
        dydt[26] += fby
        dydt[22] -= fbx
        dydt[29] -= fby

    # --- rub at disk 2 ---
    x2 = y[1]; y2 = y[8]
    rsq = x2 * x2 + y2 * y2
    if rsq > delta * delta:
        r2 = math.sqrt(rsq)
        pen = r2 - delta
        k = kr * pen / r2
        dydt[17] -= k * (x2 - mu * y2)
        dydt[24] -= k * (mu * x2 + y2)
        fa2 -= mukrR2 * pen

    # --- LP disk 2: centripetal term + closed-form 3x3 solve ---
    phi = wl * t + a2 + phi02
    s = math.sin(phi)
    c = math.cos(phi)
    pd = wl + ad2
    cen = m2e2 * pd * pd
    fx = dydt[17] + cen * c
    fy = dydt[24] + cen * s
    add = (fa2 + e2 * (s * fx - c * fy)) * iJ2
    dydt[17] = fx * p[8] + e2 * s * add
    dydt[24] = fy * p[8] - e2 * c * add
    dydt[30] = add

    # --- LP disk 5 ---
    phi = wl * t + a5 + phi05
    s = math.sin(phi)
    c = math.cos(phi)
    pd = wl + ad5
    cen = m5e5 * pd * pd
    fx = dydt[20] + cen * c
    fy = dydt[27] + cen * s
    add = (fa5 + e5 * (s * fx - c * fy)) * iJ5
    dydt[20] = fx * p[11] + e5 * s * add
    dydt[27] = fy * p[11] - e5 * c * add
    dydt[31] = add

    # --- diagonal masses ---
    for off in range(0, 14, 7):
        dydt[16 + off] *= p[7]
        dydt[18 + off] *= p[9]
        dydt[19 + off] *= p[10]
        dydt[21 + off] *= p[12]
        dydt[22 + off] *= p[13]


_RHS_NUMBA = None


def make_rhs_numba():
    """Compile (once) and return ``rhs_numba(t, y, p, dydt)``.

    ``y`` (32,) C-contiguous float64, ``p = pack(P)``, ``dydt`` (32,)
    C-contiguous float64 output, filled in place; returns None. Compiled
    eagerly for that signature (about 1 s), without on-disk cache. Imports
    numba lazily (ImportError if it is missing).

    For ``solve_ivp`` wrap it, e.g. ``lambda t, y: (rhs(t, y, p, out), out.copy())[1]``.
    """
    global _RHS_NUMBA
    if _RHS_NUMBA is None:
        import numba

        _RHS_NUMBA = numba.njit(
            "void(float64, float64[::1], float64[::1], float64[::1])",
            cache=False, error_model="numpy",
        )(_rhs_kernel)
    return _RHS_NUMBA
