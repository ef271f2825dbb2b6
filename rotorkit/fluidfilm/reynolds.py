"""Finite-difference Reynolds equation of a plain journal bearing, Reynolds (Swift-Stieber) cavitation condition.

The film of a plain cylindrical bearing (radius ``R``, length ``L``, radial
clearance ``c``, isoviscous oil ``mu``, journal spinning at ``Omega > 0``
about ``+z``) is unwrapped onto ``0 <= theta < 2 pi`` (``theta`` about ``+z``
from ``+x``, the same angle as in :mod:`rotorkit.elements.squeeze_film`) and
``-L/2 <= z <= L/2``. Incompressible, laminar, no fluid inertia:

    1/R^2 d/dtheta (h^3 dp/dtheta) + d/dz (h^3 dp/dz) = 6 mu Omega dh/dtheta + 12 mu dh/dt,
    h = c - x cos(theta) - y sin(theta).

Dimensionless (``P = p c^2 / (mu Omega R^2)``, ``H = h / c``, ``Z = 2 z / L``,
``tau = Omega t``, ``X = x / c``, ``X' = dx/dt / (c Omega)``):

    d/dtheta (H^3 dP/dtheta) + (D/L)^2 d/dZ (H^3 dP/dZ) = 6 dH/dtheta + 12 dH/dtau,
    H = 1 - X cos(theta) - Y sin(theta),   dH/dtau = -(X' cos(theta) + Y' sin(theta)).

``P = 0`` at the open ends ``Z = +-1``; the aligned journal makes ``P`` even
in ``Z``, so only ``0 <= Z < 1`` is solved (``dP/dZ = 0`` at ``Z = 0``).

**Cavitation: Reynolds (Swift-Stieber) condition**, as the linear
complementarity problem of Christopherson: with the discrete operator
written ``A P = f`` (``A`` the negative of the left-hand side, an M-matrix),

    P >= 0,   A P - f >= 0,   P_i (A P - f)_i = 0,

i.e. the film is full where ``P > 0`` and cavitated (``P = 0``, the film
cannot hold tension) where the full-film equation would ask for a negative
pressure; at the film-rupture boundary both ``P`` and its normal gradient
vanish (the Reynolds condition), and the film re-forms where the pressure
rises again. It is solved exactly (to rounding) by a primal-dual active-set
method (Hintermueller, Ito & Kunisch 2002), each step one sparse direct
solve on the full-film nodes; for an M-matrix it ends in a few steps.
Not mass-conserving in the re-formation zone (that needs an Elrod/JFO
scheme); the published tables used for verification (Someya 1989, Lund)
make the same choice.

Film force on the journal ``F = -R integral integral p (cos(theta), sin(theta)) dtheta dz``,
``F = mu Omega R^3 L / (2 c^2) f`` with the dimensionless ``f = -integral_{-1}^{1} integral P n dtheta dZ``.

Discretisation: conservative second-order central differences on a
uniform ``n_theta x n_z`` node grid (``theta_i = 2 pi i / n_theta``,
``Z_j = j / n_z``, ``j = 0 .. n_z - 1``; ``Z = 1`` carries ``P = 0``), ``H^3``
at the half nodes from the exact film thickness there, the wedge term as the
difference of the exact ``H`` at the half nodes (so the scheme conserves
flow), forces by the trapezoidal rule (spectrally accurate in the periodic
``theta``).
"""

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["FilmGrid", "FilmSolution", "solve_film", "film_derivatives"]

#: the coarsest grid accepted: fewer nodes do not resolve the converging wedge
MIN_THETA, MIN_Z = 24, 4


@dataclass(frozen=True)
class FilmGrid:
    """The finite-difference grid of one bearing (geometry in ``slenderness`` only).

    Parameters
    ----------
    slenderness : float
        ``L / D`` (> 0).
    n_theta : int
        Nodes around the circumference (>= 24).
    n_z : int
        Nodes on the half length ``0 <= Z < 1`` (>= 4).
    """

    slenderness: float
    n_theta: int = 72
    n_z: int = 12

    def __post_init__(self):
        s = self.slenderness
        if not (isinstance(s, (int, float)) and math.isfinite(s) and s > 0):
            raise ParameterError(f"FilmGrid: slenderness = {s!r}: expected L/D > 0")
        for name, low in (("n_theta", MIN_THETA), ("n_z", MIN_Z)):
            n = getattr(self, name)
            if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < low:
                raise ParameterError(f"FilmGrid: {name} = {n!r}: grid too coarse, expected an integer >= {low}")
        dtheta = 2 * math.pi / self.n_theta
        theta = dtheta * np.arange(self.n_theta)
        object.__setattr__(self, "theta", theta)
        object.__setattr__(self, "dtheta", dtheta)
        object.__setattr__(self, "dz", 1.0 / self.n_z)
        # trapezoidal weights over the full length -1 <= Z <= 1 (the half grid counted twice; Z = 1 has P = 0)
        wz = np.full(self.n_z, 2.0 / self.n_z)
        wz[0] = 1.0 / self.n_z
        object.__setattr__(self, "weights", np.outer(np.full(self.n_theta, dtheta), wz).ravel())
        n = self.n_theta * self.n_z
        i, j = np.divmod(np.arange(n), self.n_z)
        object.__setattr__(self, "_i", i)
        object.__setattr__(self, "_j", j)
        cos, sin = np.cos(theta), np.sin(theta)
        object.__setattr__(self, "_n", (np.repeat(cos, self.n_z), np.repeat(sin, self.n_z)))


def _film(grid, X, Y):
    """``H`` at the nodes and at the half nodes ``theta_{i+1/2}``, shape (n_theta,) each."""
    th = grid.theta
    half = th + grid.dtheta / 2
    return 1 - X * np.cos(th) - Y * np.sin(th), 1 - X * np.cos(half) - Y * np.sin(half)


def _assemble(grid, X, Y, Xd=0.0, Yd=0.0):
    """Sparse ``A`` (CSR, n x n) and ``f`` (n,) of ``A P = f`` at journal position ``(X, Y)``, velocity ``(Xd, Yd)``."""
    import scipy.sparse as sp

    nt, nz = grid.n_theta, grid.n_z
    H, Hh = _film(grid, X, Y)
    if H.min() <= 0:
        raise ParameterError(f"journal at ({X!r}, {Y!r}) touches the bore (eccentricity ratio >= 1)")
    i, j = grid._i, grid._j
    ae = (Hh**3)[i] / grid.dtheta**2  # between theta_i and theta_{i+1}
    aw = (Hh**3)[(i - 1) % nt] / grid.dtheta**2
    bz = (H**3)[i] * (1.0 / grid.slenderness) ** 2 / grid.dz**2  # (D/L)^2 H^3 / dZ^2
    k = np.arange(nt * nz)
    east, west = ((i + 1) % nt) * nz + j, ((i - 1) % nt) * nz + j
    up_coeff = np.where(j == 0, 2 * bz, bz)  # ghost node P_{-1} = P_1 on the symmetry plane
    rows = [k, k, k, k[j < nz - 1], k[j > 0]]
    cols = [k, east, west, (k + 1)[j < nz - 1], (k - 1)[j > 0]]
    vals = [ae + aw + 2 * bz, -ae, -aw, -up_coeff[j < nz - 1], -bz[j > 0]]
    A = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(k.size, k.size))
    wedge = 6 * (Hh - np.roll(Hh, 1)) / grid.dtheta  # 6 dH/dtheta, the flux-difference form
    cos, sin = grid._n
    f = -wedge[i] + 12 * (Xd * cos + Yd * sin)  # f = -(6 dH/dtheta + 12 dH/dtau)
    return A, f


def _solve_free(A, f, free):
    from scipy.sparse.linalg import spsolve

    P = np.zeros(f.size)
    idx = np.flatnonzero(free)
    if idx.size:
        P[idx] = spsolve(A[idx][:, idx].tocsc(), f[idx], permc_spec="NATURAL")  # banded: no reordering
    return P


def _complementarity(A, f, free=None, fixed=None, max_steps=100):
    """Primal-dual active-set solution of ``P >= 0, A P - f >= 0, P (A P - f) = 0``; returns (P, full-film mask).

    ``fixed`` marks nodes held at ``P = 0`` (supply grooves), never free.
    """
    free = f > 0 if free is None else free.copy()  # first guess: full film where the film converges
    keep = np.ones(f.size, bool) if fixed is None else ~fixed
    free &= keep
    for _ in range(max_steps):
        P = _solve_free(A, f, free)
        multiplier = A @ P - f  # zero on the full film
        scale = max(np.abs(f).max(), 1e-300)
        new = (P - multiplier / scale > 0) & keep
        if np.array_equal(new, free):
            return P, free
        free = new
    raise ParameterError(f"Reynolds cavitation: the active-set iteration did not settle in {max_steps} steps")


@dataclass(frozen=True)
class FilmSolution:
    """The film of a plain journal bearing at one journal position and velocity (dimensionless).

    Attributes
    ----------
    grid : FilmGrid
    position, velocity : tuple of float
        ``(X, Y) = (x, y) / c`` and ``(X', Y') = (x', y') / (c Omega)``.
    pressure : numpy.ndarray, shape (n_theta, n_z)
        ``P = p c^2 / (mu Omega R^2)`` on ``theta_i``, ``Z_j`` (half length, ``Z_j = j / n_z``).
    force : numpy.ndarray, shape (2,)
        ``f = F 2 c^2 / (mu Omega R^3 L)``, the film force on the journal.
    full_film : numpy.ndarray of bool, shape (n_theta, n_z)
        The nodes where the film is full (the rest cavitated).
    """

    grid: FilmGrid
    position: tuple
    velocity: tuple
    pressure: np.ndarray
    force: np.ndarray
    full_film: np.ndarray


def _force(grid, P):
    cos, sin = grid._n
    w = grid.weights * P
    return -np.array([w @ cos, w @ sin])


def solve_film(grid, position, velocity=(0.0, 0.0), full_film=None, ambient=None):
    """The cavitated film and its force at a journal position and velocity (dimensionless).

    Parameters
    ----------
    grid : FilmGrid
    position : (float, float)
        ``(X, Y)``, journal centre over the clearance; ``X^2 + Y^2 < 1``.
    velocity : (float, float)
        ``(X', Y')``, journal centre velocity over ``c Omega``.
    full_film : numpy.ndarray of bool, optional
        A first guess of the full-film nodes (e.g. a nearby solution's), fewer active-set steps.
    ambient : numpy.ndarray of bool, shape (n_theta,), optional
        Angles held at ``P = 0`` over the whole length (axial supply grooves at ambient pressure).

    Returns
    -------
    FilmSolution
    """
    X, Y = map(float, position)
    Xd, Yd = map(float, velocity)
    if not math.hypot(X, Y) < 1:
        raise ParameterError(f"position = {position!r}: expected an eccentricity ratio sqrt(X^2 + Y^2) < 1")
    A, f = _assemble(grid, X, Y, Xd, Yd)
    if full_film is None:
        full_film = _coarse_guess(grid, (X, Y), (Xd, Yd), ambient)
    guess = None if full_film is None else np.asarray(full_film, bool).ravel()
    fixed = None if ambient is None else np.repeat(np.asarray(ambient, bool), grid.n_z)
    P, free = _complementarity(A, f, guess, fixed=fixed)
    shape = (grid.n_theta, grid.n_z)
    return FilmSolution(grid=grid, position=(X, Y), velocity=(Xd, Yd), pressure=P.reshape(shape),
                        force=_force(grid, P), full_film=free.reshape(shape))


def _coarse_guess(grid, position, velocity, ambient):
    """The full-film nodes of the same film on a grid half as fine, on this grid's nodes (None if too coarse).

    The active-set iteration moves the film boundary by about a node per step; starting from the coarse
    grid's boundary (itself found from a coarser one) leaves it a step or two. The answer does not depend on
    the guess (the complementarity problem has one solution), only the number of steps.
    """
    nt, nz = grid.n_theta // 2, grid.n_z // 2
    if nt < MIN_THETA or nz < MIN_Z:
        return None
    coarse = FilmGrid(slenderness=grid.slenderness, n_theta=nt, n_z=nz)
    i = np.rint(grid.theta / coarse.dtheta).astype(int) % nt
    j = np.minimum(np.rint(np.arange(grid.n_z) * grid.dz / coarse.dz).astype(int), nz - 1)
    ambient_coarse = None if ambient is None else np.asarray(ambient, bool)[np.rint(
        coarse.theta / grid.dtheta).astype(int) % grid.n_theta]
    full = solve_film(coarse, position, velocity, ambient=ambient_coarse).full_film
    return full[np.ix_(i, j)]


def film_derivatives(solution, step=1e-6):
    """``d f / d(X, Y, X', Y')`` at a solution, shape (2, 4), with its cavitation boundary held.

    The velocity derivatives are exact (``f`` is linear in ``X', Y'`` on a fixed full-film region); the position
    derivatives are central differences of the full-film solve with the step ``step``. Holding the boundary is
    the first-order perturbation of the Reynolds-condition film: the boundary moves, but ``P`` and its normal
    gradient vanish there, so its motion changes the force only to second order.
    """
    from scipy.sparse.linalg import splu

    grid = solution.grid
    X, Y = solution.position
    Xd, Yd = solution.velocity
    free = solution.full_film.ravel()
    idx = np.flatnonzero(free)
    out = np.empty((2, 4))
    for col, (dx, dy) in enumerate(((step, 0.0), (0.0, step))):
        forces = []
        for sign in (1, -1):
            A, f = _assemble(grid, X + sign * dx, Y + sign * dy, Xd, Yd)
            forces.append(_force(grid, _solve_free(A, f, free)))
        out[:, col] = (forces[0] - forces[1]) / (2 * step)
    A, _ = _assemble(grid, X, Y, Xd, Yd)
    lu = splu(A[idx][:, idx].tocsc(), permc_spec="NATURAL")
    cos, sin = grid._n
    for col, n in ((2, cos), (3, sin)):
        dP = np.zeros(free.size)
        dP[idx] = lu.solve(12 * n[idx])  # d f / d X' = 12 cos(theta), d f / d Y' = 12 sin(theta)
        out[:, col] = _force(grid, dP)
    return out
