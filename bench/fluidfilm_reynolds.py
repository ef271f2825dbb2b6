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
from rotorkit.fluidfilm.published import (RAIMONDI_BOYD, SOMEYA, SOMEYA_FLOW_FRICTION, SOMEYA_GROOVES, TO_SOMEYA,
                                          databook_friction_and_side_flow, half_unit, raimondi_boyd_variables,
                                          rigid_turn, sommerfeld_and_attitude, supplied_film)

D, C, MU, W = 0.1, 1e-4, 0.03, 5000.0


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
        b = PlainJournalBearing(diameter=D, length=ld * D, clearance=C, viscosity=MU, load=W, grooves=SOMEYA_GROOVES,
                                n_theta=144, n_z=12)
        flow_friction = {eps: (q, t) for _, eps, q, t in SOMEYA_FLOW_FRICTION[ld]}  # Q, T on the rows of SOMEYA
        for (s, eps, phi, *coefficients), (q, t) in list(zip(rows, (flow_friction[r[1]] for r in rows)))[::3 if quick else 1]:
            omega = s * W * 2 * math.pi / (MU * ld * D * D * (D / 2 / C) ** 2)
            start = time.perf_counter()
            table = b.coefficients([omega])
            elapsed = time.perf_counter() - start
            T, Q = databook_friction_and_side_flow(b, b.equilibrium(omega), s)
            k = TO_SOMEYA @ table.stiffness[0] @ TO_SOMEYA.T * C / W
            c = TO_SOMEYA @ table.damping[0] @ TO_SOMEYA.T * C * omega / W
            k = rigid_turn(k, table.eccentricity_ratio[0], table.attitude_angle[0])
            computed, printed = np.concatenate([k.ravel(), c.ravel()]), np.array(coefficients)
            d = 100 * (computed - printed) / np.abs(printed)
            d_eps, d_phi = table.eccentricity_ratio[0] - eps, math.degrees(table.attitude_angle[0]) - phi
            print(f"   {ld:<4} {eps:<4} {d_eps:+.4f} {d_phi:+5.2f} {100 * (T / t - 1):+5.2f} {100 * (Q / q - 1):+5.1f} | "
                  + " ".join(f"{x:+5.1f}" for x in d)
                  + f" | {100 * (computed[2] - printed[2]) / np.abs(printed[:4]).max():+5.1f}   {elapsed:.2f} s")


def raimondi_boyd(quick):
    from scipy.optimize import brentq

    print("3. Raimondi & Boyd full journal bearing, film fed at ambient pressure at the maximum film thickness")
    print("   printed (R/c) f against 2 pi^2 S / sqrt(1 - eps^2) + (eps / 2) sin(phi) of the printed S, phi "
          "(units of the third digit of f)")
    for ld, rows in RAIMONDI_BOYD.items():
        misses = [(2 * math.pi**2 * s / math.sqrt(1 - eps**2) + eps / 2 * math.sin(math.radians(phi)) - f)
                  / (2 * half_unit(f)) for eps, s, phi, f, *_ in rows]
        print(f"   L/D = {ld}: " + " ".join(f"{m:+.1f}" for m in misses))
    grids = ((144, 12), (288, 24)) + (() if quick else ((576, 48),))
    print("   grid convergence, S (%) and phi (deg) at the tabulated eps against the printed ones, grids "
          + ", ".join(f"{a} x {b}" for a, b in grids))
    for ld, rows in RAIMONDI_BOYD.items():
        for eps, s, phi, *_ in rows:
            cells = []
            for n_theta, n_z in grids:
                s_c, phi_c = sommerfeld_and_attitude(supplied_film(ld, eps, n_theta, n_z))
                cells.append(f"{100 * (s_c / s - 1):+6.2f} % {phi_c - phi:+6.2f}")
            print(f"   {ld:<4} {eps:<4} " + " | ".join(cells))
    names = ("(R/c)f", "Q/RcNL", "Qs/Q", "P/pmax")
    for n_theta, n_z in grids[:2]:
        print(f"   grid {n_theta} x {n_z}: at the printed S, d eps and d phi (deg); at the tabulated eps, each "
              "design variable's difference in % of the printed one [units of its third digit]")
        for ld, rows in RAIMONDI_BOYD.items():
            for eps, s, phi, *printed in rows:
                eps_c = brentq(lambda e: math.log(sommerfeld_and_attitude(supplied_film(ld, e, n_theta, n_z))[0] / s),
                               max(eps - 0.03, 0.01), min(eps + 0.015, 0.985), xtol=1e-7)
                phi_c = sommerfeld_and_attitude(supplied_film(ld, eps_c, n_theta, n_z))[1]
                variables = raimondi_boyd_variables(ld, eps, supplied_film(ld, eps, n_theta, n_z))
                computed = [variables[k] for k in ("friction", "flow", "side_flow_ratio", "load_over_pmax")]
                cells = " ".join(f"{n} {100 * (c / p - 1):+5.2f} [{(c - p) / (2 * half_unit(p)):+5.1f}]"
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
    b = PlainJournalBearing(diameter=D, length=0.5 * D, clearance=C, viscosity=MU, load=W, grooves=SOMEYA_GROOVES,
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
