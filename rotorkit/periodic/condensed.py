"""Harmonic balance condensed onto the coordinates where local nonlinear forces act.

With the full equations ``L z = F + S N(z_c)`` per harmonic (``L`` the exact
linear dynamic stiffness of :class:`~rotorkit.periodic.hb.HarmonicBalance`,
``F`` the input forces at rest, ``N`` the nonlinear forces, acting and
depending only on the contact coordinates ``c`` through ``S``), every
coordinate is ``z = z_lin + G N`` with ``z_lin = L^-1 F`` and the receptance
``G = L^-1 S``. The unknowns are the contact coordinates' coefficients and
the residual is the force balance there,

    R_c = G_cc^-1 (z_c - z_lin,c) - N(z_c)

(N, exact: no modal truncation). ``G`` comes from one complex LU of the
dynamic stiffness ``K - (k w)^2 M + i k w C`` per harmonic and parameter
value. ``N`` is sampled by AFT as before, with the other coordinates at
zero: ``M g = M a - M A y`` cancels the linear forces whatever they are, so
it holds the nonlinear forces and the inputs only. :meth:`expand` gives all
coordinates back.
"""

from __future__ import annotations

import numpy as np

from ..errors import ParameterError
from .hb import HarmonicBalance

__all__ = ["CondensedHarmonicBalance", "nonlinear_coordinates"]


_FOUND = {}


def nonlinear_coordinates(model):
    """Names of the coordinates on which a force that is not linear in the states acts or depends."""
    key = model.structure_key
    if key not in _FOUND:
        if len(_FOUND) > 16:
            _FOUND.clear()
        _FOUND[key] = _nonlinear_coordinates(model)
    return _FOUND[key]


def _nonlinear_coordinates(model):
    import sympy as sp

    eqs = model.equations()
    qs, us = list(eqs.coordinates), list(eqs.speeds)
    index = {s: i for i, s in enumerate(qs)}
    index.update({s: i for i, s in enumerate(us)})
    states = set(index)
    found = set()
    for (i, _), f in eqs.nonlinear_forcing().todok().items():
        f = sp.sympify(f)
        used = f.free_symbols & states
        if any(sp.diff(f, s).free_symbols & states for s in used):
            found.add(i)
            found.update(index[s] for s in used)
    names = tuple(str(q) for q in qs)
    return tuple(names[i] for i in sorted(found))


class CondensedHarmonicBalance(HarmonicBalance):
    """:class:`~rotorkit.periodic.hb.HarmonicBalance` with the contact coordinates' coefficients as unknowns.

    Parameters
    ----------
    system : rotorkit.System
    coordinates : sequence of str
        The coordinates kept (default :func:`nonlinear_coordinates`).
    **options
        As for :class:`~rotorkit.periodic.hb.HarmonicBalance`.
    """

    def __init__(self, system, *, coordinates=None, **options):
        super().__init__(system, **options)
        names = nonlinear_coordinates(system.model) if coordinates is None else tuple(coordinates)
        unknown = [c for c in names if c not in self.coordinate_names]
        if unknown or not names:
            raise ParameterError(f"condense={coordinates!r}: expected coordinates among {self.coordinate_names}"
                                 if unknown else "condense: the model has no nonlinear force to condense onto")
        self.kept = np.array([self.coordinate_names.index(c) for c in names])
        self.kept_names = names
        self.full = HarmonicBalance(system, speed_parameter=self.speed_parameter, harmonics=self.harmonics,
                                    subharmonic=self.subharmonic, samples=self.samples)

    @property
    def size(self):
        return len(self.kept) * (2 * self.harmonics + 1)

    def _condensation(self, frame):
        """``(G (full, kept), inverse of G_cc, z_lin)`` of a frame, computed once per frame."""
        found = getattr(frame, "_condensed", None)
        if found is not None:
            return found
        n, H, c = self.n, self.harmonics, self.kept
        nc = len(c)
        H2 = 2 * H + 1
        w = frame.omega
        F = frame.forcing  # (2H+1, n)
        G = np.zeros((H2, n, H2, nc))
        z_lin = np.zeros((H2, n))
        for k in range(H + 1):
            D = frame.stiffness - (k * w) ** 2 * frame.mass + 1j * (k * w) * frame.damping
            if k == 0:
                D = D.real
                rhs = np.hstack([np.eye(n)[:, c], F[0][:, None]])
                X = np.linalg.solve(D, rhs)
                G[0, :, 0, :] = X[:, :nc]
                z_lin[0] = X[:, nc]
                continue
            Fk = F[2 * k - 1] - 1j * F[2 * k]
            X = np.linalg.solve(D, np.hstack([np.eye(n)[:, c], Fk[:, None]]).astype(complex))
            Hr, Hi = X[:, :nc].real, X[:, :nc].imag
            ia, ib = 2 * k - 1, 2 * k
            # Q = a - i b = H (Fa - i Fb): a = Hr Fa + Hi Fb, b = -Hi Fa + Hr Fb
            G[ia, :, ia, :], G[ia, :, ib, :] = Hr, Hi
            G[ib, :, ia, :], G[ib, :, ib, :] = -Hi, Hr
            z_lin[ia], z_lin[ib] = X[:, nc].real, -X[:, nc].imag
        G = G.reshape(H2 * n, H2 * nc)
        rows = (np.arange(H2)[:, None] * n + c[None, :]).ravel()
        Gcc_inv = np.linalg.inv(G[rows])
        frame._condensed = (G, Gcc_inv, z_lin.ravel(), rows)
        return frame._condensed

    def _full_states(self, z, frame):
        Zc = np.reshape(z, (-1, len(self.kept)))
        Z = np.zeros((Zc.shape[0], self.n))
        Z[:, self.kept] = Zc
        return Z

    def states(self, z, frame):
        """Coordinates and velocities at the AFT instants, the others than the kept ones at zero, (N, 2n)."""
        return super().states(self._full_states(z, frame).ravel(), frame)

    def nonlinear_forces(self, z, frame, jacobian=True):
        """``(N, dN/dz)``: harmonics of the nonlinear forces on the kept coordinates and their Jacobian."""
        n, c = self.n, self.kept
        Y = self.states(z, frame)
        Mc = frame.mass[c]
        rows = np.flatnonzero(np.any(Mc != 0.0, axis=0))  # (M g)[c] needs g only where M couples to c
        Mr = Mc[:, rows]
        g = frame.accelerations(Y)[:, n + rows] - Y @ frame.A[rows].T
        force = self.P @ (g @ Mr.T) - frame.forcing[:, c]
        if not jacobian:
            return force.ravel(), None
        cs = np.concatenate([c, n + c])
        Fk = Mr @ (frame.jacobian_block(Y, n + rows, cs) - frame.A[np.ix_(rows, cs)])  # (N, nc, 2 nc)
        nc = len(c)
        dN = self._project(np.ascontiguousarray(Fk[:, :, :nc]), np.ascontiguousarray(Fk[:, :, nc:]), frame.omega)
        return force.ravel(), dN

    def residual(self, z, frame, jacobian=True):
        """``(R_c, dR_c/dz_c)`` (N): the force balance at the kept coordinates (module notes)."""
        G, Gcc_inv, z_lin, rows = self._condensation(frame)
        N, dN = self.nonlinear_forces(z, frame, jacobian)
        R = Gcc_inv @ (np.asarray(z) - z_lin[rows]) - N
        if not np.all(np.isfinite(R)):
            from .errors import ConvergenceError

            raise ConvergenceError("the condensed residual is not finite: the iteration diverged")
        return R, (None if dN is None else Gcc_inv - dN)

    def expand(self, z, frame):
        """All coordinates' coefficients ``z_lin + G N(z_c)``, shape (n (2H + 1),)."""
        G, _, z_lin, _ = self._condensation(frame)
        N, _ = self.nonlinear_forces(z, frame, jacobian=False)
        return z_lin + G @ N

    def time_residual(self, z, frame, samples):
        return self.full.time_residual(self.expand(z, frame), frame, samples)
