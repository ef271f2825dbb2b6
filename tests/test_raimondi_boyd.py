"""The finite-difference Reynolds film against Raimondi & Boyd's full (360 degree) journal bearing tables.

A. A. Raimondi, J. Boyd, "A solution for the finite journal bearing and its application to analysis and design",
*ASLE Transactions* 1 (1958), Parts I-III: the full journal bearing at L/D = 1, 0.5 and 0.25, isoviscous, the film
starting at ambient pressure at the maximum film thickness (the oil supply) and ending with the Reynolds
(Swift-Stieber) condition. Columns: eccentricity ratio ``eps`` (their input), Sommerfeld number
``S = mu N L D (R/c)^2 / W`` (``N`` rev/s), attitude angle ``phi`` (deg), friction variable ``(R/c) f``, flow
variable ``Q / (R c N L)`` (``Q`` the flow into the film at its start), side-flow ratio ``Qs / Q`` (both ends) and
``P / p_max`` (``P = W / (L D)``). The printed values as transcribed in github.com/Piter-T-UC/MecaPy,
``mecapy/mecapy/bearings/lubrication_data.py`` (from the table reproduced with Shigley's charts); the L/D = 1
``S``, ``phi`` and ``(R/c) f`` columns agree with two independent transcriptions (mathworks.com/matlabcentral/answers/
707318: ``S`` and ``(R/c) f`` at six rows, one ``f`` rounded to 3.2; the ROTORDIN app's validation script: ``S`` and
``phi`` at eps = 0.2 - 0.8), all three with ``S = 0.264`` at eps = 0.4 (whose printed friction says 0.2606, below).

The film here: :func:`rotorkit.fluidfilm.solve_film` with the journal at ``(eps, 0)`` and the line
``theta = pi`` (the maximum film thickness) held at ambient pressure over the whole length (``ambient=``), the
same finite-difference film as :class:`~rotorkit.fluidfilm.PlainJournalBearing`. Without that supply line (the
plain 360 degree film of ``PlainJournalBearing``, whose film re-forms where the complementarity condition lets it)
the attitude at small eccentricity is several degrees larger than the printed one (tested below): Raimondi & Boyd's
film is fed at the maximum film thickness.

The rule for "within printed precision": ``eps`` is Raimondi & Boyd's input (exact), every other column is printed
to three significant digits (the attitude to 0.01 or 0.1 degree). At the printed ``S``, the computed eccentricity
ratio is within the interval the rounding of ``S`` leaves, ``0.5 ulp(S) / |dS/deps|``, and the attitude within half
a unit of its last digit plus ``|dphi/deps|`` times that interval; ``(R/c) f``, ``Q / (R c N L)``, ``Qs / Q`` and
``P / p_max`` at the tabulated ``eps`` within half a unit of their third digit. Beyond it, what the tests allow
(``EPS_MISS``, ``PHI_MISS``, ``allowed``) is the measured miss rounded up, with the reasons below and per entry in
docs/fluid-film-bearings.md ("Raimondi & Boyd").
"""

from __future__ import annotations

import math

import pytest

from rotorkit.fluidfilm.published import (RAIMONDI_BOYD, RAIMONDI_BOYD_COLUMNS, half_unit, raimondi_boyd_variables,
                                          sommerfeld_and_attitude, supplied_film)

COLUMNS = RAIMONDI_BOYD_COLUMNS

GRID = dict(n_theta=144, n_z=12)


def half_unit_angle(phi):
    """Half a unit of the printed attitude (``79.5`` has one decimal, ``74.02`` two; the floats keep the digits)."""
    return 0.05 if round(phi, 1) == phi else 0.005


def performance(slenderness, eps, **grid):
    """Raimondi & Boyd's columns of this film at ``eps`` (:func:`~rotorkit.fluidfilm.published.raimondi_boyd_variables`)."""
    return raimondi_boyd_variables(slenderness, eps, supplied_film(slenderness, eps, **grid))


def eccentricity_at(slenderness, s, eps_guess, **grid):
    """The eccentricity ratio (and its attitude, deg) whose film carries the load of Sommerfeld number ``s``."""
    from scipy.optimize import brentq

    def log_ratio(eps):
        return math.log(sommerfeld_and_attitude(supplied_film(slenderness, eps, **grid))[0] / s)

    low, high = max(eps_guess - 0.03, 0.01), min(eps_guess + 0.015, 0.985)
    eps = brentq(log_ratio, low, high, xtol=1e-7)
    return eps, sommerfeld_and_attitude(supplied_film(slenderness, eps, **grid))[1]


# Beyond printed precision, what the test allows (measured on 144 x 12 nodes, and on 288 x 24 for the docs; the
# tolerance is the largest measured miss rounded up). The grid is converged (144 x 12 to 576 x 48 moves S by
# <= 0.3 % and phi by <= 0.02 deg at eps <= 0.9, 0.6 % at 0.97), so the misses are of the printed values
# (docs/fluid-film-bearings.md, "Raimondi & Boyd"):
#   - eps at the printed S within 0.001 (S within 0.2 - 0.6 % where the printed rounding is 0.04 - 0.4 %), except
#     rows out of the smooth trend of their neighbours: L/D = 1, eps = 0.4 (printed S 1.3 % above this film's:
#     its own printed friction says S = 0.2606, this film's, not the printed 0.264; tested below), L/D = 0.5,
#     eps = 0.4 (printed S 0.9 - 1 % below), and L/D = 0.25 at eps = 0.4 - 0.8 (printed S 0.4 - 1.1 % below:
#     eps within 0.0015 - 0.002);
#   - phi within 0.25 deg (0.4 deg at L/D = 1, eps = 0.4 and L/D = 0.5, eps = 0.8; 0.3 deg at L/D = 0.25,
#     eps = 0.4);
#   - (R/c) f follows S (the formula above): within 1 %, 3.5 % at eps = 0.97 where the printed S is 1.2 - 3 % below
#     this film's converged one (a film 0.03 c thin: Raimondi & Boyd's mesh);
#   - Qs / Q within 0.6 % (printed rounding 0.05 - 0.3 %);
#   - P / p_max (the peak pressure): 1 % at eps <= 0.6, 2.5 % at 0.8 and 0.9, 6.5 % at 0.97;
#   - Q / (R c N L): printed precision on every row.
EPS_MISS = {(1.0, 0.4): 0.004, (0.5, 0.4): 0.003, (0.25, 0.4): 0.0015, (0.25, 0.6): 0.002, (0.25, 0.8): 0.0015}
PHI_MISS = {(1.0, 0.4): 0.4, (0.5, 0.8): 0.4, (0.25, 0.4): 0.3}


def allowed(column, slenderness, eps, printed):
    """The tolerance of one design variable (relative), printed precision at least."""
    precision = half_unit(printed) / abs(printed)
    miss = {"flow": 0.0, "side_flow_ratio": 6e-3,
            "friction": 3.5e-2 if eps > 0.95 else 1e-2,
            "load_over_pmax": 1e-2 if eps <= 0.6 else (2.5e-2 if eps <= 0.9 else 6.5e-2)}[column]
    return max(precision, miss)


@pytest.mark.parametrize("slenderness", [1.0, 0.5, 0.25])
def test_eccentricity_and_attitude_at_the_printed_sommerfeld_number(slenderness):
    for eps, s, phi, *_ in RAIMONDI_BOYD[slenderness]:
        eps_c, phi_c = eccentricity_at(slenderness, s, eps, **GRID)
        # the interval of eps that the rounding of S leaves, from this film's slope dS/deps
        d = 2e-3
        s_up, phi_up = sommerfeld_and_attitude(supplied_film(slenderness, min(eps + d, 0.985)))
        s_down, phi_down = sommerfeld_and_attitude(supplied_film(slenderness, eps - d))
        d_eps = half_unit(s) / abs((s_up - s_down) / (2 * d))
        d_phi = half_unit_angle(phi) + abs((phi_up - phi_down) / (2 * d)) * d_eps
        assert abs(eps_c - eps) <= max(d_eps, EPS_MISS.get((slenderness, eps), 1e-3)), (eps, eps_c, d_eps)
        assert abs(phi_c - phi) <= max(d_phi, PHI_MISS.get((slenderness, eps), 0.25)), (eps, phi_c, phi, d_phi)


@pytest.mark.parametrize("slenderness", [1.0, 0.5, 0.25])
def test_friction_flow_side_flow_and_peak_pressure_at_the_tabulated_eccentricity(slenderness):
    # the flow into the film within printed precision on every row (allowed("flow", ...) is the precision)
    for eps, s, phi, *printed in RAIMONDI_BOYD[slenderness]:
        computed = performance(slenderness, eps, **GRID)
        for column, value in zip(COLUMNS[3:], printed):
            assert abs(computed[column] / value - 1) <= allowed(column, slenderness, eps, value) + 1e-12, \
                (slenderness, eps, column, computed[column], value)


def test_misses_are_not_the_grid():
    """Where the printed S misses most (L/D = 1, eps = 0.4; L/D = 0.5, eps = 0.4), this film's S does not move
    with the grid (144 x 12 to 288 x 24: < 0.3 %), while it stays 0.9 - 1.4 % from the printed one."""
    for slenderness, eps, s in ((1.0, 0.4, 0.264), (0.5, 0.4, 0.779)):
        coarse = sommerfeld_and_attitude(supplied_film(slenderness, eps, **GRID))[0]
        fine = sommerfeld_and_attitude(supplied_film(slenderness, eps, n_theta=288, n_z=24))[0]
        assert abs(fine / coarse - 1) < 3e-3
        assert 8e-3 < abs(fine / s - 1) < 1.5e-2


def test_without_the_supply_line_the_attitude_at_small_eccentricity_misses():
    """The plain 360 degree film (PlainJournalBearing without grooves: no line held at ambient pressure) at the
    printed S of L/D = 1, eps = 0.1: its film re-forms downstream of the maximum film thickness, the attitude is
    more than 3 deg above Raimondi & Boyd's 79.5 (measured 4.4; the supplied film: within 0.15 deg, measured 0.11)."""
    from rotorkit.fluidfilm import PlainJournalBearing

    D, C, MU, W = 0.1, 1e-4, 0.03, 5000.0
    b = PlainJournalBearing(diameter=D, length=D, clearance=C, viscosity=MU, load=W, n_theta=144)
    omega = 1.33 * W * 2 * math.pi / (MU * D * D * (D / 2 / C) ** 2)
    table = b.coefficients([omega])
    assert abs(table.sommerfeld[0] - 1.33) < 1e-12
    assert math.degrees(table.attitude_angle[0]) - 79.5 > 3.0
    assert abs(eccentricity_at(1.0, 1.33, 0.1, **GRID)[1] - 79.5) < 0.15


def test_printed_friction_is_the_full_circumference_shear_of_the_printed_statics():
    """Raimondi & Boyd's friction variable is ``2 pi^2 S / sqrt(1 - eps^2) + (eps / 2) sin(phi)`` of their printed
    ``S`` and ``phi`` (Couette shear over the whole circumference, none removed where the film cavitates), to the
    rounding of ``S`` and ``f`` (measured: within 0.9 units of the third digit of ``f``) on every row but one: L/D = 1,
    eps = 0.4, whose printed friction 5.79 is that of ``S = 0.2606`` (this film's 0.2605 - 0.2608), not of the
    printed 0.264."""
    for slenderness, rows in RAIMONDI_BOYD.items():
        for eps, s, phi, friction, *_ in rows:
            formula = 2 * math.pi**2 * s / math.sqrt(1 - eps**2) + eps / 2 * math.sin(math.radians(phi))
            rounding = half_unit(friction) + 2 * math.pi**2 * half_unit(s) / math.sqrt(1 - eps**2)
            if (slenderness, eps) == (1.0, 0.4):
                assert abs(formula - friction) > 10 * half_unit(friction)
                s_from_friction = (friction - eps / 2 * math.sin(math.radians(phi))) * math.sqrt(1 - eps**2) / (
                    2 * math.pi**2)
                assert abs(s_from_friction - 0.2606) < 5e-4
            else:
                assert abs(formula - friction) <= rounding + 1e-12, (slenderness, eps, formula, friction)
