"""Finite-difference plain journal bearing: verification figures and solve times, all from one run.

    python bench/fluidfilm_reynolds.py [--quick]

Prints
1. the short-bearing limit: eccentricity, attitude and the coefficients against the closed form
   (``JournalBearing.operating_point``) at L/D = 0.05, 0.1, 0.2 (default grid 72 x 12), and how the stiffness
   difference scatters with the grid at L/D = 0.1;
2. Someya's Journal-Bearing Databook, two-axial-groove bearing (pp. 14 and 17; transcription in
   github.com/VictorLier/Tribology, Assignment2/Someya.py), grooves 10 degrees wide at +-90 degrees from the load
   (the width the printed friction column gives), grid 144 x 12 (the groove edges on nodes): for each printed
   Sommerfeld number, the differences in eccentricity ratio and attitude angle, the journal friction T and side
   flow Q against the printed ones, and each of the eight coefficients' difference in % of the printed entry
   (stiffness in the Databook's rigid-turn convention; k_yx also in % of the largest stiffness, it changes sign
   near eps = 0.7); and how closely the printed stiffness obeys the rigid turn;
3. Raimondi & Boyd (1958), full journal bearing, L/D = 1, 0.5, 0.25 (the printed table as transcribed in
   github.com/Piter-T-UC/MecaPy, mecapy/mecapy/bearings/lubrication_data.py), the film fed at ambient pressure at
   the maximum film thickness: at each tabulated eps, the eccentricity ratio and attitude at the printed S, and
   the friction variable, inlet flow, side-flow ratio and P/p_max at the tabulated eps against the printed ones
   (% and units of the last printed digit), on 144 x 12 and 288 x 24 nodes; S and phi at the tabulated eps on
   144 x 12, 288 x 24 and 576 x 48 (grid convergence); the printed friction against the formula of the printed
   S and phi;
4. medians of one cavitated film solve on a 60 x 20 grid and of ``coefficients`` per speed (72 x 12, and 144 x 12
   with the Databook's grooves), with the load average.
"""

import math
import os
import statistics
import sys
import time

import numpy as np

from rotorkit.elements.journal_bearing import JournalBearing
from rotorkit.fluidfilm import FilmGrid, PlainJournalBearing, solve_film

D, C, MU, W = 0.1, 1e-4, 0.03, 5000.0
SOMEYA = {  # S, eps, phi, kxx, kxy, kyx, kyy, bxx, bxy, byx, byy (x along the load)
    0.5: [(4.43, 0.1, 80.4, 1.75, 10.3, -9.66, 2.70, 20.6, 2.08, 2.08, 11.4),
          (2.07, 0.2, 71.6, 1.88, 5.63, -4.41, 2.56, 11.2, 2.22, 2.22, 6.43),
          (1.24, 0.3, 64.1, 2.07, 4.27, -2.56, 2.34, 8.50, 2.32, 2.32, 4.73),
          (0.798, 0.4, 57.5, 2.39, 3.75, -1.57, 2.17, 7.32, 2.24, 2.24, 3.50),
          (0.517, 0.5, 51.1, 2.89, 3.57, -0.924, 2.03, 6.81, 2.10, 2.10, 2.60),
          (0.323, 0.6, 44.7, 3.65, 3.62, -0.427, 1.92, 6.81, 2.08, 2.08, 2.06),
          (0.187, 0.7, 38.2, 4.92, 3.88, 0.0235, 1.83, 7.32, 2.16, 2.16, 1.70),
          (0.0926, 0.8, 31.2, 7.35, 4.46, 0.527, 1.78, 8.17, 2.05, 2.05, 1.24),
          (0.0315, 0.9, 22.7, 13.8, 5.76, 1.24, 1.72, 10.6, 2.03, 2.03, 0.846)],
    1.0: [(1.45, 0.1, 78.7, 2.04, 10.2, -9.62, 2.77, 20.8, 1.67, 1.67, 7.55),
          (0.689, 0.2, 69.9, 1.99, 5.45, -4.38, 2.56, 11.3, 1.78, 1.78, 4.39),
          (0.424, 0.3, 61.0, 2.20, 3.96, -2.52, 2.31, 8.67, 1.99, 1.99, 3.50),
          (0.284, 0.4, 54.6, 2.37, 3.34, -1.60, 2.06, 7.57, 2.10, 2.09, 2.94),
          (0.194, 0.5, 49.1, 2.67, 3.09, -1.00, 1.89, 6.99, 2.00, 2.00, 2.31),
          (0.131, 0.6, 43.8, 3.19, 3.06, -0.553, 1.77, 6.69, 1.82, 1.82, 1.74),
          (0.0828, 0.7, 38.4, 4.16, 3.29, -0.0851, 1.75, 7.07, 2.00, 2.00, 1.59),
          (0.0469, 0.8, 32.1, 6.10, 3.82, 0.420, 1.74, 8.08, 2.15, 2.15, 1.34),
          (0.0195, 0.9, 25.0, 11.9, 5.28, 1.32, 1.80, 10.1, 2.06, 2.06, 0.916)],
}
TO_SOMEYA = np.array([[0.0, -1.0], [1.0, 0.0]])


def short_limit():
    print("1. short-bearing limit (default grid 72 x 12)")
    print("   L/D   S_s   eps_fd  eps_closed  dphi[deg]  max|dK|/max|K|  max|dC|/max|C|")
    for ld in (0.05, 0.1, 0.2):
        L = ld * D
        b = PlainJournalBearing(diameter=D, length=L, clearance=C, viscosity=MU, load=W)
        jb = JournalBearing(station=1, radius=D / 2, length=L, clearance=C, viscosity=MU)
        for ss in (0.3, 0.1):
            omega = ss * 8 * W * C**2 / (MU * D * L**3)
            t = b.coefficients([omega])
            op = jb.operating_point(load=W, speed=omega)
            dk = np.abs(t.stiffness[0] - op.stiffness).max() / np.abs(op.stiffness).max()
            dc = np.abs(t.damping[0] - op.damping).max() / np.abs(op.damping).max()
            print(f"   {ld:<5} {ss:<5} {t.eccentricity_ratio[0]:.4f}  {op.eccentricity_ratio:.4f}      "
                  f"{math.degrees(t.attitude_angle[0] - op.attitude_angle):+.2f}      {dk:.3f}           {dc:.3f}")


def grid_scatter():
    print("1b. short-bearing limit, L/D = 0.1, S_s = 0.3: stiffness difference against the grid (n_z = 12)")
    L = 0.1 * D
    omega = 0.3 * 8 * W * C**2 / (MU * D * L**3)
    op = JournalBearing(station=1, radius=D / 2, length=L, clearance=C, viscosity=MU).operating_point(load=W,
                                                                                                    speed=omega)
    for n_theta in (72, 96, 144):
        t = PlainJournalBearing(diameter=D, length=L, clearance=C, viscosity=MU, load=W,
                                n_theta=n_theta).coefficients([omega])
        dk = np.abs(t.stiffness[0] - op.stiffness).max() / np.abs(op.stiffness).max()
        print(f"   n_theta = {n_theta:<4} max|dK|/max|K| = {dk:.3f}")


def rigid_turn(k, eps, phi):
    """``k`` (Someya's frame) with the tangential column of a rigidly turned film, ``K e_t = (0, 1 / eps)``."""
    e_r, e_t = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
    return np.outer(k @ e_r, e_r) + np.outer([0.0, 1.0 / eps], e_t)


GROOVES = ((0.0, 10.0), (180.0, 10.0))
FLOW_FRICTION = {  # (Q, T) printed on the rows of SOMEYA
    0.5: [(0.0880, 83.0), (0.170, 39.5), (0.243, 24.4), (0.309, 16.4), (0.366, 11.3), (0.416, 7.75), (0.459, 5.13),
          (0.496, 3.13), (0.524, 1.56)],
    1.0: [(0.0692, 27.3), (0.132, 13.2), (0.181, 8.41), (0.220, 5.93), (0.251, 4.37), (0.274, 3.26), (0.295, 2.39),
          (0.302, 1.69), (0.300, 1.04)],
}


def friction_and_flow(b, solution, s):
    """Journal friction ``T = f R / c`` (Couette shear over the whole land, none in the grooves, plus the pressure
    term) and side flow ``Q = q / (R Omega c L)`` (both ends), the Databook's columns."""
    X, Y = solution.position
    n = 7200
    theta = (np.arange(n) + 0.5) * 2 * math.pi / n
    distance = np.min([np.abs((theta - math.radians(c) + math.pi) % (2 * math.pi) - math.pi) for c, _ in GROOVES],
                      axis=0)
    H = 1 - X * np.cos(theta) - Y * np.sin(theta)
    T = math.pi * s * np.sum(1 / H[distance > math.radians(GROOVES[0][1]) / 2]) * 2 * math.pi / n \
        + math.pi * s / 4 * (X * solution.force[1] - Y * solution.force[0])
    grid, P = solution.grid, solution.pressure
    H_nodes = 1 - X * np.cos(grid.theta) - Y * np.sin(grid.theta)
    Q = np.sum(H_nodes**3 * (4 * P[:, -1] - P[:, -2]) / (2 * grid.dz)) * grid.dtheta / (12 * (b.length / b.diameter) ** 2)
    return T, Q


def someya(quick):
    print("2. Someya two-axial-groove bearing (grooves 10 deg at +-90 deg from the load, grid 144 x 12)")
    print("   the printed table: max|K e_t - (0, 1/eps)| / max|K| (0 for a film that turns rigidly with the journal)")
    for ld, rows in SOMEYA.items():
        residual = [np.abs(np.reshape(r[3:7], (2, 2)) @ [-math.sin(math.radians(r[2])), math.cos(math.radians(r[2]))]
                           - [0.0, 1.0 / r[1]]).max() / np.abs(r[3:7]).max() for r in rows]
        print(f"   L/D = {ld}: " + " ".join(f"{x:.4f}" for x in residual))
    print("   differences in % of the printed entry (k_yx/max: in % of the largest printed stiffness)")
    print("   L/D  eps  d_eps    dphi   dT    dQ  |  kxx   kxy   kyx   kyy   bxx   bxy   byx   byy | kyx/max  time")
    for ld, rows in SOMEYA.items():
        b = PlainJournalBearing(diameter=D, length=ld * D, clearance=C, viscosity=MU, load=W, grooves=GROOVES,
                                n_theta=144, n_z=12)
        for (s, eps, phi, *coefficients), (q, t) in list(zip(rows, FLOW_FRICTION[ld]))[::3 if quick else 1]:
            omega = s * W * 2 * math.pi / (MU * ld * D * D * (D / 2 / C) ** 2)
            start = time.perf_counter()
            table = b.coefficients([omega])
            elapsed = time.perf_counter() - start
            T, Q = friction_and_flow(b, b.equilibrium(omega), s)
            k = TO_SOMEYA @ table.stiffness[0] @ TO_SOMEYA.T * C / W
            c = TO_SOMEYA @ table.damping[0] @ TO_SOMEYA.T * C * omega / W
            k = rigid_turn(k, table.eccentricity_ratio[0], table.attitude_angle[0])
            computed, printed = np.concatenate([k.ravel(), c.ravel()]), np.array(coefficients)
            d = 100 * (computed - printed) / np.abs(printed)
            d_eps, d_phi = table.eccentricity_ratio[0] - eps, math.degrees(table.attitude_angle[0]) - phi
            print(f"   {ld:<4} {eps:<4} {d_eps:+.4f} {d_phi:+5.2f} {100 * (T / t - 1):+5.2f} {100 * (Q / q - 1):+5.1f} | "
                  + " ".join(f"{x:+5.1f}" for x in d)
                  + f" | {100 * (computed[2] - printed[2]) / np.abs(printed[:4]).max():+5.1f}   {elapsed:.2f} s")


RAIMONDI_BOYD = {  # eps, S, phi (deg), (R/c) f, Q / (R c N L), Qs / Q, P / p_max
    1.0: [(0.1, 1.33, 79.5, 26.4, 3.37, 0.150, 0.540), (0.2, 0.631, 74.02, 12.8, 3.59, 0.280, 0.529),
          (0.4, 0.264, 63.10, 5.79, 3.99, 0.497, 0.484), (0.6, 0.121, 50.58, 3.22, 4.33, 0.680, 0.415),
          (0.8, 0.0446, 36.24, 1.70, 4.62, 0.842, 0.313), (0.9, 0.0188, 26.45, 1.05, 4.74, 0.919, 0.247),
          (0.97, 0.00474, 15.47, 0.514, 4.82, 0.973, 0.152)],
    0.5: [(0.1, 4.31, 81.62, 85.6, 3.43, 0.173, 0.523), (0.2, 2.03, 74.94, 40.9, 3.72, 0.318, 0.506),
          (0.4, 0.779, 61.45, 17.0, 4.29, 0.552, 0.441), (0.6, 0.319, 48.14, 8.10, 4.85, 0.730, 0.365),
          (0.8, 0.0923, 33.31, 3.26, 5.41, 0.874, 0.267), (0.9, 0.0313, 23.66, 1.60, 5.69, 0.939, 0.206),
          (0.97, 0.00609, 13.75, 0.610, 5.88, 0.980, 0.126)],
    0.25: [(0.1, 16.2, 82.31, 322.0, 3.45, 0.180, 0.515), (0.2, 7.57, 75.18, 153.0, 3.76, 0.330, 0.489),
           (0.4, 2.83, 60.86, 61.1, 4.37, 0.567, 0.415), (0.6, 1.07, 46.72, 26.7, 4.99, 0.746, 0.334),
           (0.8, 0.261, 31.04, 8.80, 5.60, 0.884, 0.240), (0.9, 0.0736, 21.85, 3.50, 5.91, 0.945, 0.180),
           (0.97, 0.0101, 12.22, 0.922, 6.12, 0.984, 0.108)],
}


def _half_unit(value):
    """Half a unit in the third significant digit of a printed value."""
    return 0.5 * 10.0 ** (math.floor(math.log10(abs(value))) - 2)


def _supplied(ld, eps, n_theta, n_z):
    """The film at (eps, 0) fed at ambient pressure at the maximum film thickness (theta = pi)."""
    supply = np.zeros(n_theta, bool)
    supply[n_theta // 2] = True
    return solve_film(FilmGrid(slenderness=ld, n_theta=n_theta, n_z=n_z), (eps, 0.0), ambient=supply)


def _s_phi(solution):
    f = solution.force
    return 2 / (math.pi * math.hypot(*f)), (-math.degrees(math.atan2(-f[1], -f[0])) + 180.0) % 360.0 - 180.0


def _design_variables(ld, eps, solution):
    """(R/c) f, Q / (R c N L), Qs / Q, P / p_max of a supplied film (as tests/test_raimondi_boyd.py)."""
    s, phi = _s_phi(solution)
    g, P = solution.grid, solution.pressure
    H = 1 - eps * np.cos(g.theta)
    i = g.n_theta // 2
    flux = H[i] / 2 - H[i] ** 3 / 12 * (-3 * P[i] + 4 * P[i + 1] - P[i + 2]) / (2 * g.dtheta)
    weights = np.full(g.n_z, 2.0 / g.n_z)
    weights[0] = 1.0 / g.n_z
    flow = math.pi * (flux @ weights + H[i] / 2 / g.n_z)
    side = math.pi / 6 / ld**2 * np.sum(H**3 * (4 * P[:, -1] - P[:, -2]) / (2 * g.dz)) * g.dtheta
    friction = 2 * math.pi**2 * s / math.sqrt(1 - eps**2) + eps / 2 * math.sin(math.radians(phi))
    return friction, flow, side / flow, 1 / (2 * math.pi * s * P.max())


def raimondi_boyd(quick):
    from scipy.optimize import brentq

    print("3. Raimondi & Boyd full journal bearing, film fed at ambient pressure at the maximum film thickness")
    print("   printed (R/c) f against 2 pi^2 S / sqrt(1 - eps^2) + (eps / 2) sin(phi) of the printed S, phi "
          "(units of the third digit of f)")
    for ld, rows in RAIMONDI_BOYD.items():
        misses = [(2 * math.pi**2 * s / math.sqrt(1 - eps**2) + eps / 2 * math.sin(math.radians(phi)) - f)
                  / (2 * _half_unit(f)) for eps, s, phi, f, *_ in rows]
        print(f"   L/D = {ld}: " + " ".join(f"{m:+.1f}" for m in misses))
    grids = ((144, 12), (288, 24)) + (() if quick else ((576, 48),))
    print("   grid convergence, S (%) and phi (deg) at the tabulated eps against the printed ones, grids "
          + ", ".join(f"{a} x {b}" for a, b in grids))
    for ld, rows in RAIMONDI_BOYD.items():
        for eps, s, phi, *_ in rows:
            cells = []
            for n_theta, n_z in grids:
                s_c, phi_c = _s_phi(_supplied(ld, eps, n_theta, n_z))
                cells.append(f"{100 * (s_c / s - 1):+6.2f} % {phi_c - phi:+6.2f}")
            print(f"   {ld:<4} {eps:<4} " + " | ".join(cells))
    names = ("(R/c)f", "Q/RcNL", "Qs/Q", "P/pmax")
    for n_theta, n_z in grids[:2]:
        print(f"   grid {n_theta} x {n_z}: at the printed S, d eps and d phi (deg); at the tabulated eps, each "
              "design variable's difference in % of the printed one [units of its third digit]")
        for ld, rows in RAIMONDI_BOYD.items():
            for eps, s, phi, *printed in rows:
                eps_c = brentq(lambda e: math.log(_s_phi(_supplied(ld, e, n_theta, n_z))[0] / s),
                               max(eps - 0.03, 0.01), min(eps + 0.015, 0.985), xtol=1e-7)
                phi_c = _s_phi(_supplied(ld, eps_c, n_theta, n_z))[1]
                computed = _design_variables(ld, eps, _supplied(ld, eps, n_theta, n_z))
                cells = " ".join(f"{n} {100 * (c / p - 1):+5.2f} [{(c - p) / (2 * _half_unit(p)):+5.1f}]"
                                 for n, c, p in zip(names, computed, printed))
                print(f"   {ld:<4} {eps:<4} {eps_c - eps:+.4f} {phi_c - phi:+5.2f} | {cells}")


def _median_times(fn, repeats):
    """(wall, cpu) medians in seconds: the cpu time of this process is less sensitive to a shared machine's load."""
    wall, cpu = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def timings(repeats):
    print(f"4. times (load average {os.getloadavg()[0]:.1f}, medians of {repeats} runs, wall / cpu)")
    grid = FilmGrid(slenderness=0.5, n_theta=60, n_z=20)
    solve_film(grid, (0.6, 0.0))
    wall, cpu = _median_times(lambda: solve_film(grid, (0.6, 0.0)), repeats)
    print(f"   one cavitated film, 60 x 20 grid: {wall * 1e3:.1f} / {cpu * 1e3:.1f} ms")
    b = PlainJournalBearing(diameter=D, length=0.5 * D, clearance=C, viscosity=MU, load=W)
    wall, cpu = _median_times(lambda: b.coefficients([500.0]), max(3, repeats // 5))
    print(f"   equilibrium + eight coefficients, 72 x 12 grid: {wall * 1e3:.0f} / {cpu * 1e3:.0f} ms per speed")
    b = PlainJournalBearing(diameter=D, length=0.5 * D, clearance=C, viscosity=MU, load=W, grooves=GROOVES,
                            n_theta=144, n_z=12)
    omega = 0.517 * W * 2 * math.pi / (MU * 0.5 * D * D * (D / 2 / C) ** 2)  # the Databook's eps = 0.5 row
    wall, cpu = _median_times(lambda: b.coefficients([omega]), max(3, repeats // 5))
    print(f"   the same, two 10 deg grooves, 144 x 12 grid (the Databook comparison): {wall * 1e3:.0f} / {cpu * 1e3:.0f} ms "
          "per speed")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    short_limit()
    grid_scatter()
    someya(quick)
    raimondi_boyd(quick)
    timings(5 if quick else 20)
