"""hb.newton's lazy Jacobian (the continuation corrector's): the same iterates and root, fewer Jacobians.

Closed form: ``R(z) = (z_0^3 - 8, z_1 - z_0^2)`` has the root ``(2, 4)`` and the Jacobian
``[[3 z_0^2, 0], [-2 z_0, 1]]``.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit.periodic.errors import ConvergenceError
from rotorkit.periodic.hb import newton


def problem(log):
    def fun(z, jacobian):
        log.append((z.copy(), jacobian))
        R = np.array([z[0] ** 3 - 8.0, z[1] - z[0] ** 2])
        return R, (np.array([[3.0 * z[0] ** 2, 0.0], [-2.0 * z[0], 1.0]]) if jacobian else None)
    return fun


@pytest.mark.parametrize("start", [(3.0, 1.0), (1.0, 0.0), (2.5, 7.0)])
def test_lazy_jacobian_same_iterates_fewer_jacobians(start):
    eager, lazy = [], []
    z1, n1, r1, J1 = newton(problem(eager), np.array(start), tol=1e-12, scale=1.0)
    z2, n2, r2, J2 = newton(problem(lazy), np.array(start), tol=1e-12, scale=1.0, lazy_jacobian=True)
    assert np.allclose(z2, [2.0, 4.0], rtol=0, atol=1e-12)
    assert np.array_equal(z1, z2) and n1 == n2 and r1 == r2
    # the same points are evaluated, in the same order; the lazy run asks for fewer Jacobians
    assert len({tuple(z) for z, _ in lazy}) == len({tuple(z) for z, _ in eager})
    jacobians = [z for z, wanted in lazy if wanted]
    assert sum(wanted for _, wanted in lazy) < sum(wanted for _, wanted in eager)
    # the returned Jacobian is the one at the last point where one was evaluated (the iterate before the root)
    last = jacobians[-1]
    assert np.array_equal(J2, [[3.0 * last[0] ** 2, 0.0], [-2.0 * last[0], 1.0]])
    assert not np.array_equal(last, z2)
    assert np.array_equal(J1, [[3.0 * z1[0] ** 2, 0.0], [-2.0 * z1[0], 1.0]])


def test_lazy_jacobian_raises_as_the_eager_one():
    def fun(z, jacobian):  # no root: z^2 + 1
        return np.array([z[0] ** 2 + 1.0]), (np.array([[2.0 * z[0]]]) if jacobian else None)
    for lazy in (False, True):
        with pytest.raises(ConvergenceError, match="no convergence in 5 Newton iterations"):
            newton(fun, np.array([0.5]), tol=1e-12, scale=1.0, max_iterations=5, lazy_jacobian=lazy)
