"""Published finite journal-bearing tables, and this film's quantities in their conventions.

The verification of :mod:`rotorkit.fluidfilm` (``tests/test_reynolds_bearing.py``,
``tests/test_raimondi_boyd.py``) and its bench (``bench/fluidfilm_reynolds.py``) read the printed
tables from here, so that there is one transcription of each (docs/fluid-film-bearings.md compares them
entry by entry):

- :data:`SOMEYA`, :data:`SOMEYA_FLOW_FRICTION`: Someya (ed.), *Journal-Bearing Databook*, Springer 1989,
  two-axial-groove bearing, L/D = 0.5 and 1 (pp. 14, 17; transcription in github.com/VictorLier/Tribology,
  Assignment2/Someya.py). Axes: x along the load, y at +90 deg in the direction of rotation
  (:data:`TO_SOMEYA` maps this package's axes to them); stiffness ``K c / W``, damping ``C c Omega / W``.
  The grooves are 10 deg wide at +-90 deg from the load (:data:`SOMEYA_GROOVES`: the width the printed
  friction column gives).
- :data:`RAIMONDI_BOYD`: Raimondi & Boyd, "A solution for the finite journal bearing and its application
  to analysis and design", ASLE Trans. 1 (1958), full journal bearing, L/D = 1, 0.5, 0.25 (as transcribed
  in github.com/Piter-T-UC/MecaPy, mecapy/mecapy/bearings/lubrication_data.py); the film fed at ambient
  pressure at the maximum film thickness (:func:`supplied_film`).
"""

from __future__ import annotations

import math

import numpy as np

from .reynolds import FilmGrid, solve_film

__all__ = ["SOMEYA", "SOMEYA_FLOW_FRICTION", "SOMEYA_GROOVES", "TO_SOMEYA", "RAIMONDI_BOYD", "RAIMONDI_BOYD_COLUMNS",
           "half_unit", "rigid_turn", "databook_friction_and_side_flow", "supplied_film", "sommerfeld_and_attitude",
           "raimondi_boyd_variables"]

#: Someya's coefficient rows per L/D: S, eps, phi (deg), kxx, kxy, kyx, kyy, bxx, bxy, byx, byy
SOMEYA = {
    0.5: [
        (4.43, 0.1, 80.4, 1.75, 10.3, -9.66, 2.7, 20.6, 2.08, 2.08, 11.4),
        (2.07, 0.2, 71.6, 1.88, 5.63, -4.41, 2.56, 11.2, 2.22, 2.22, 6.43),
        (1.24, 0.3, 64.1, 2.07, 4.27, -2.56, 2.34, 8.5, 2.32, 2.32, 4.73),
        (0.798, 0.4, 57.5, 2.39, 3.75, -1.57, 2.17, 7.32, 2.24, 2.24, 3.5),
        (0.517, 0.5, 51.1, 2.89, 3.57, -0.924, 2.03, 6.81, 2.1, 2.1, 2.6),
        (0.323, 0.6, 44.7, 3.65, 3.62, -0.427, 1.92, 6.81, 2.08, 2.08, 2.06),
        (0.187, 0.7, 38.2, 4.92, 3.88, 0.0235, 1.83, 7.32, 2.16, 2.16, 1.7),
        (0.0926, 0.8, 31.2, 7.35, 4.46, 0.527, 1.78, 8.17, 2.05, 2.05, 1.24),
        (0.0315, 0.9, 22.7, 13.8, 5.76, 1.24, 1.72, 10.6, 2.03, 2.03, 0.846),
    ],
    1.0: [
        (1.45, 0.1, 78.7, 2.04, 10.2, -9.62, 2.77, 20.8, 1.67, 1.67, 7.55),
        (0.689, 0.2, 69.9, 1.99, 5.45, -4.38, 2.56, 11.3, 1.78, 1.78, 4.39),
        (0.424, 0.3, 61.0, 2.2, 3.96, -2.52, 2.31, 8.67, 1.99, 1.99, 3.5),
        (0.284, 0.4, 54.6, 2.37, 3.34, -1.6, 2.06, 7.57, 2.1, 2.09, 2.94),
        (0.194, 0.5, 49.1, 2.67, 3.09, -1.0, 1.89, 6.99, 2.0, 2.0, 2.31),
        (0.131, 0.6, 43.8, 3.19, 3.06, -0.553, 1.77, 6.69, 1.82, 1.82, 1.74),
        (0.0828, 0.7, 38.4, 4.16, 3.29, -0.0851, 1.75, 7.07, 2.0, 2.0, 1.59),
        (0.0469, 0.8, 32.1, 6.1, 3.82, 0.42, 1.74, 8.08, 2.15, 2.15, 1.34),
        (0.0195, 0.9, 25.0, 11.9, 5.28, 1.32, 1.8, 10.1, 2.06, 2.06, 0.916),
    ],
}
#: Someya's printed side flow Q = q / (R Omega c L) (both ends) and journal friction T = f R / c per L/D:
#: S, eps, Q, T on every row of the two tables
SOMEYA_FLOW_FRICTION = {
    0.5: [
        (5.96, 0.075, 0.0663, 111.5),
        (4.43, 0.1, 0.088, 83.0),
        (2.07, 0.2, 0.17, 39.5),
        (1.24, 0.3, 0.243, 24.4),
        (0.798, 0.4, 0.309, 16.4),
        (0.517, 0.5, 0.366, 11.3),
        (0.323, 0.6, 0.416, 7.75),
        (0.187, 0.7, 0.459, 5.13),
        (0.135, 0.75, 0.478, 4.07),
        (0.0926, 0.8, 0.496, 3.13),
        (0.0582, 0.85, 0.51, 2.3),
        (0.0315, 0.9, 0.524, 1.56),
        (0.00499, 0.975, 0.543, 0.543),
    ],
    1.0: [
        (2.95, 0.05, 0.0351, 55.1),
        (1.96, 0.075, 0.0523, 36.6),
        (1.45, 0.1, 0.0692, 27.3),
        (0.689, 0.2, 0.132, 13.2),
        (0.424, 0.3, 0.181, 8.41),
        (0.284, 0.4, 0.22, 5.93),
        (0.194, 0.5, 0.251, 4.37),
        (0.131, 0.6, 0.274, 3.26),
        (0.0828, 0.7, 0.295, 2.39),
        (0.0469, 0.8, 0.302, 1.69),
        (0.0195, 0.9, 0.3, 1.04),
        (0.00866, 0.95, 0.297, 0.684),
    ],
}
#: (x_s, y_s) = (-y, x): this package's load is along -y, Someya's along +x_s
TO_SOMEYA = np.array([[0.0, -1.0], [1.0, 0.0]])
#: Someya's two axial grooves, (centre, width) in degrees: 10 deg wide at +-90 deg from the load
SOMEYA_GROOVES = ((0.0, 10.0), (180.0, 10.0))

#: Raimondi & Boyd's rows per L/D, in the order of :data:`RAIMONDI_BOYD_COLUMNS`
RAIMONDI_BOYD = {
    1.0: [
        (0.1, 1.33, 79.5, 26.4, 3.37, 0.15, 0.54),
        (0.2, 0.631, 74.02, 12.8, 3.59, 0.28, 0.529),
        (0.4, 0.264, 63.1, 5.79, 3.99, 0.497, 0.484),
        (0.6, 0.121, 50.58, 3.22, 4.33, 0.68, 0.415),
        (0.8, 0.0446, 36.24, 1.7, 4.62, 0.842, 0.313),
        (0.9, 0.0188, 26.45, 1.05, 4.74, 0.919, 0.247),
        (0.97, 0.00474, 15.47, 0.514, 4.82, 0.973, 0.152),
    ],
    0.5: [
        (0.1, 4.31, 81.62, 85.6, 3.43, 0.173, 0.523),
        (0.2, 2.03, 74.94, 40.9, 3.72, 0.318, 0.506),
        (0.4, 0.779, 61.45, 17.0, 4.29, 0.552, 0.441),
        (0.6, 0.319, 48.14, 8.1, 4.85, 0.73, 0.365),
        (0.8, 0.0923, 33.31, 3.26, 5.41, 0.874, 0.267),
        (0.9, 0.0313, 23.66, 1.6, 5.69, 0.939, 0.206),
        (0.97, 0.00609, 13.75, 0.61, 5.88, 0.98, 0.126),
    ],
    0.25: [
        (0.1, 16.2, 82.31, 322.0, 3.45, 0.18, 0.515),
        (0.2, 7.57, 75.18, 153.0, 3.76, 0.33, 0.489),
        (0.4, 2.83, 60.86, 61.1, 4.37, 0.567, 0.415),
        (0.6, 1.07, 46.72, 26.7, 4.99, 0.746, 0.334),
        (0.8, 0.261, 31.04, 8.8, 5.6, 0.884, 0.24),
        (0.9, 0.0736, 21.85, 3.5, 5.91, 0.945, 0.18),
        (0.97, 0.0101, 12.22, 0.922, 6.12, 0.984, 0.108),
    ],
}
#: eps, S, phi (deg), (R/c) f, Q / (R c N L), Qs / Q, P / p_max
RAIMONDI_BOYD_COLUMNS = ("eps", "S", "phi", "friction", "flow", "side_flow_ratio", "load_over_pmax")


def half_unit(value, digits=3):
    """Half a unit in the last of ``digits`` significant digits of a printed ``value``."""
    return 0.5 * 10.0 ** (math.floor(math.log10(abs(value))) - digits + 1)


def rigid_turn(k, eps, phi):
    """``k`` (``K c / W``, Someya's axes) with its tangential column replaced by the rigid turn of the film.

    Turning a rotationally symmetric film with the journal turns its force: ``K e_t = (0, 1 / eps)`` for the
    dimensionless load ``(1, 0)``; ``e_t`` is perpendicular to the line of centres at the attitude ``phi``
    (rad) from the load. The radial column ``K e_r`` is kept. The Databook's stiffness is in this convention.
    """
    e_r, e_t = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
    return np.outer(k @ e_r, e_r) + np.outer([0.0, 1.0 / eps], e_t)


def databook_friction_and_side_flow(bearing, solution, sommerfeld):
    """The Databook's ``T = f R / c`` of the journal and ``Q = q / (R Omega c L)`` (both ends) of a film solution.

    Friction: Couette shear ``mu U / h`` over the whole land outside ``bearing.grooves`` (the grooves carry
    none; full shear also where the film is cavitated), plus the pressure term ``(h / 2) dp / (R dtheta)``:
    ``T = pi S integral_land dtheta / H + (pi S / 4) (X f_y - Y f_x)`` (its second term is
    ``eps sin(phi) / 2``). Side flow: ``h^3 / (12 mu) dp/dz`` at the two ends,
    ``Q = (D / L)^2 / 12 integral H^3 (-dP/dZ)|_{Z=1} dtheta``.
    """
    X, Y = solution.position
    n = 7200
    theta = (np.arange(n) + 0.5) * 2 * math.pi / n
    land = np.ones(n, bool)
    for centre, width in bearing.grooves:
        land &= np.abs((theta - math.radians(centre) + math.pi) % (2 * math.pi) - math.pi) > math.radians(width) / 2
    H = 1 - X * np.cos(theta) - Y * np.sin(theta)
    T = math.pi * sommerfeld * np.sum(1 / H[land]) * 2 * math.pi / n \
        + math.pi * sommerfeld / 4 * (X * solution.force[1] - Y * solution.force[0])
    grid, P = solution.grid, solution.pressure
    H_nodes = 1 - X * np.cos(grid.theta) - Y * np.sin(grid.theta)
    dP_dZ = (P[:, -2] - 4 * P[:, -1]) / (2 * grid.dz)  # second-order one-sided, P = 0 at Z = 1
    slenderness = bearing.length / bearing.diameter
    Q = np.sum(H_nodes**3 * -dP_dZ) * grid.dtheta / (12 * slenderness**2)
    return T, Q


def supplied_film(slenderness, eps, n_theta=144, n_z=12):
    """The film at ``(eps, 0)`` fed at ambient pressure at the maximum film thickness (``theta = pi``)."""
    grid = FilmGrid(slenderness=slenderness, n_theta=n_theta, n_z=n_z)
    supply = np.zeros(n_theta, bool)
    supply[n_theta // 2] = True
    return solve_film(grid, (eps, 0.0), ambient=supply)


def sommerfeld_and_attitude(solution):
    """``S = 2 / (pi |f|)`` and the attitude (deg) from the load (``-f``) to the eccentricity (``+x``)."""
    f = solution.force
    phi = math.degrees(math.atan2(-f[1], -f[0]))
    return 2 / (math.pi * math.hypot(*f)), (-phi + 180.0) % 360.0 - 180.0


def raimondi_boyd_variables(slenderness, eps, solution):
    """Raimondi & Boyd's columns of a :func:`supplied_film` at ``eps``: dict with ``S``, ``phi`` and the four
    design variables ``friction``, ``flow``, ``side_flow_ratio``, ``load_over_pmax``.

    Friction: Couette shear over the whole circumference (also where the film is cavitated, as Raimondi & Boyd)
    plus the pressure term, ``(R/c) f = 2 pi^2 S / sqrt(1 - eps^2) + (eps / 2) sin(phi)``. Flow into the film at
    its start ``Q / (R c N L) = pi integral_{-1}^{1} (H / 2 - H^3 / 12 dP/dtheta) dZ`` just downstream of the
    supply line; side flow at both ends ``Qs / (R c N L) = (pi / 6) (D/L)^2 integral H^3 (-dP/dZ)|_{Z=1} dtheta``;
    ``P / p_max = 1 / (2 pi S max(P))`` (``P = p c^2 / (mu Omega R^2)``). Derivatives one-sided, second order.
    """
    S, phi = sommerfeld_and_attitude(solution)
    g, P = solution.grid, solution.pressure
    H = 1 - eps * np.cos(g.theta)
    i = g.n_theta // 2
    dP_dtheta = (-3 * P[i] + 4 * P[i + 1] - P[i + 2]) / (2 * g.dtheta)
    flux = H[i] / 2 - H[i] ** 3 / 12 * dP_dtheta  # on Z_j = j / n_z; at Z = 1, P = 0 and the flux is H / 2
    weights = np.full(g.n_z, 2.0 / g.n_z)
    weights[0] = 1.0 / g.n_z
    flow = math.pi * (flux @ weights + H[i] / 2 / g.n_z)
    dP_dZ = (P[:, -2] - 4 * P[:, -1]) / (2 * g.dz)  # P = 0 at Z = 1
    side_flow = math.pi / 6 / slenderness**2 * np.sum(H**3 * -dP_dZ) * g.dtheta
    friction = 2 * math.pi**2 * S / math.sqrt(1 - eps**2) + eps / 2 * math.sin(math.radians(phi))
    return {"S": S, "phi": phi, "friction": friction, "flow": flow, "side_flow_ratio": side_flow / flow,
            "load_over_pmax": 1 / (2 * math.pi * S * P.max())}
