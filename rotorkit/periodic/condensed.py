"""Harmonic balance condensed onto the coordinates where local nonlinear forces act.

With the full equations ``D z = F + N(z_c)`` per harmonic (``D`` the exact
linear dynamic stiffness ``K - (k w)^2 M + i k w C`` of
:class:`~rotorkit.periodic.hb.HarmonicBalance`, ``F`` the input forces at
rest, ``N`` the nonlinear forces, acting and depending only on the contact
coordinates ``c``), the other coordinates ``i`` follow from the contact ones,
``z_i = D_ii^-1 (F_i - D_ic z_c)``. The unknowns are the contact
coordinates' coefficients and the residual is the force balance there,

    R_c = S z_c - f - N(z_c),   S = D_cc - D_ci D_ii^-1 D_ic,   f = F_c - D_ci D_ii^-1 F_i

(N, exact: no modal truncation; ``S`` is the inverse of the receptance
``G_cc``, formed directly). ``S`` comes from one complex LU of ``D_ii``
per harmonic and parameter
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
    from .derived import periodic_module

    return tuple(periodic_module(model).NONLINEAR_COORDINATES)


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
        self._others = np.setdiff1d(np.arange(self.n), self.kept)
        self.full = HarmonicBalance(system, speed_parameter=self.speed_parameter, harmonics=self.harmonics,
                                    subharmonic=self.subharmonic, samples=self.samples)

    @property
    def size(self):
        return len(self.kept) * (2 * self.harmonics + 1)

    def _condensation(self, frame):
        """``(S, f, T, z_i0)`` of a frame, computed once per frame (real coefficient form, module notes).

        ``S`` (H2 nc, H2 nc) is the condensed dynamic stiffness ``D_cc - D_ci D_ii^-1 D_ic`` and ``f``
        (H2 nc,) the condensed input ``F_c - D_ci D_ii^-1 F_i`` (N), so that ``R_c = S z_c - f - N``;
        the other coordinates are ``z_i = z_i0 - T z_c``. Forming ``S`` directly (rather than inverting
        the receptance ``G_cc``) keeps the residual's round-off at that of the forces: the inverse of an
        inverse carried ``cond(D) eps`` relative errors into the stiffness, a floor near the Newton
        tolerance on stiff beam models where the corrector then stalled.
        """
        found = getattr(frame, "_condensed", None)
        if found is not None:
            return found
        H, c = self.harmonics, self.kept
        i = self._others
        nc, ni = len(c), len(i)
        H2 = 2 * H + 1
        w = frame.omega
        F = frame.forcing  # (2H+1, n)
        S = np.zeros((H2, nc, H2, nc))
        f = np.zeros((H2, nc))
        T = np.zeros((H2, ni, H2, nc))
        zi = np.zeros((H2, ni))
        for k in range(H + 1):
            D = frame.stiffness - (k * w) ** 2 * frame.mass + 1j * (k * w) * frame.damping
            Fk = F[0].astype(complex) if k == 0 else F[2 * k - 1] - 1j * F[2 * k]
            if k == 0:
                D = D.real
                Fk = Fk.real
            X = np.linalg.solve(D[np.ix_(i, i)], np.hstack([D[np.ix_(i, c)], Fk[i, None]])) if ni else \
                np.zeros((0, nc + 1), dtype=D.dtype)
            Sk = D[np.ix_(c, c)] - D[np.ix_(c, i)] @ X[:, :nc]
            fk = Fk[c] - D[np.ix_(c, i)] @ X[:, nc]
            if k == 0:
                S[0, :, 0, :], f[0], T[0, :, 0, :], zi[0] = Sk, fk, X[:, :nc], X[:, nc]
                continue
            ia, ib = 2 * k - 1, 2 * k
            # F = S Q with Q = a - i b, F = Fa - i Fb: Fa = Sr a + Si b, Fb = -Si a + Sr b (same for T)
            for out, M in ((S, Sk), (T, X[:, :nc])):
                out[ia, :, ia, :], out[ia, :, ib, :] = M.real, M.imag
                out[ib, :, ia, :], out[ib, :, ib, :] = -M.imag, M.real
            f[ia], f[ib] = fk.real, -fk.imag
            zi[ia], zi[ib] = X[:, nc].real, -X[:, nc].imag
        frame._condensed = (S.reshape(H2 * nc, H2 * nc), f.ravel(), T.reshape(H2 * ni, H2 * nc), zi.ravel())
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
        S, f, _, _ = self._condensation(frame)
        N, dN = self.nonlinear_forces(z, frame, jacobian)
        R = S @ np.asarray(z) - f - N
        if not np.all(np.isfinite(R)):
            from .errors import ConvergenceError

            raise ConvergenceError("the condensed residual is not finite: the iteration diverged")
        return R, (None if dN is None else S - dN)

    def expand(self, z, frame):
        """All coordinates' coefficients: ``z_c`` and ``z_i = z_i0 - T z_c``, shape (n (2H + 1),)."""
        _, _, T, zi = self._condensation(frame)
        H2 = 2 * self.harmonics + 1
        Z = np.empty((H2, self.n))
        Z[:, self.kept] = np.reshape(z, (H2, -1))
        Z[:, self._others] = np.reshape(zi - T @ np.asarray(z), (H2, -1))
        return Z.ravel()

    def time_residual(self, z, frame, samples):
        return self.full.time_residual(self.expand(z, frame), frame, samples)
