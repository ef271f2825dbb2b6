"""Piecewise functions that stay finite in generated code.

Contact laws need ``max(x, 0)``, a step, and a ratio that is 0/0 at the
origin. sympy's ``Heaviside``, ``Piecewise`` and plain division print to code
that can divide by zero or raise a negative number to a fractional power
once common-subexpression elimination hoists the pieces out of their
branches. These functions are opaque to ``cse`` and print to guarded
expressions (see :mod:`rotorkit.codegen.printer`).
"""

import sympy as sp

__all__ = ["ramp", "step", "safe_div", "window", "hypot", "contact_ratio"]


def _power(text, exp):
    """``text`` raised to ``exp`` (sympy's LaTeX printer passes ``exp`` for powers of functions)."""
    return text if exp is None else r"\left(%s\right)^{%s}" % (text, exp)


class ramp(sp.Function):
    """``max(x, 0)``: contact penetration. ``ramp(x)**1.5`` is never complex."""

    nargs = 1

    @classmethod
    def eval(cls, x):
        if x.is_number:
            return sp.Max(x, 0)
        if x.is_nonnegative:
            return x
        if x.is_nonpositive:
            return sp.S.Zero
        return None

    def fdiff(self, argindex=1):
        return step(self.args[0])

    def _latex(self, printer, exp=None):
        return _power(r"\left\langle %s \right\rangle_{+}" % printer._print(self.args[0]), exp)


class step(sp.Function):
    """Unit step, 1 for ``x > 0`` and 0 otherwise (so ``step(0) = 0``)."""

    nargs = 1

    @classmethod
    def eval(cls, x):
        if x.is_number:
            return sp.S.One if x > 0 else sp.S.Zero
        return None

    def fdiff(self, argindex=1):
        return sp.S.Zero  # the Dirac part is dropped: used for Jacobians of ramps

    def _latex(self, printer, exp=None):
        return _power(r"H\left(%s\right)" % printer._print(self.args[0]), exp)


class safe_div(sp.Function):
    """``a / b`` for ``b != 0``, and 0 for ``b == 0``.

    Used where the numerator vanishes with the denominator (a contact force
    ``k ramp(r - delta) x / r`` at ``r = 0``), so 0 is the right limit.
    """

    nargs = 2

    @classmethod
    def eval(cls, a, b):
        if a.is_zero:
            return sp.S.Zero
        if b.is_number and not b.is_zero:
            return a / b
        return None

    def fdiff(self, argindex=1):
        a, b = self.args
        if argindex == 1:
            return safe_div(sp.S.One, b)
        return -safe_div(a, b**2)

    def _latex(self, printer, exp=None):
        a, b = self.args
        return _power(r"\frac{%s}{%s}" % (printer._print(a), printer._print(b)), exp)


class window(sp.Function):
    """1 for ``start <= t < end``, else 0: an effect switched on in a time window.

    Its jumps are time discontinuities; the simulation restarts there.
    """

    nargs = 3

    @classmethod
    def eval(cls, t, start, end):
        if t.is_number and start.is_number and end.is_number:
            return sp.S.One if (start <= t) and (t < end) else sp.S.Zero
        return None

    def fdiff(self, argindex=1):
        return sp.S.Zero

    def _latex(self, printer, exp=None):
        t, start, end = (printer._print(a) for a in self.args)
        return _power(r"\mathbb{1}_{[%s,\,%s)}\left(%s\right)" % (start, end, t), exp)


class hypot(sp.Function):
    """``sqrt(x^2 + y^2)``, whose derivatives ``x / r`` stay finite (0) at the origin."""

    nargs = 2

    @classmethod
    def eval(cls, x, y):
        if x.is_zero:
            return sp.Abs(y)
        if y.is_zero:
            return sp.Abs(x)
        return None

    def fdiff(self, argindex=1):
        return safe_div(self.args[argindex - 1], self)

    def _latex(self, printer, exp=None):
        x, y = (printer._print(a) for a in self.args)
        return _power(r"\sqrt{%s^{2} + %s^{2}}" % (x, y), exp)


class contact_ratio(sp.Function):
    """``max(r - delta, 0) / r``: the share of a radial distance that is penetration.

    Its limit at ``r = 0`` is 1 for ``delta = 0`` (permanent contact: the force
    ``-k r (x, y) / r`` is linear) and 0 otherwise, so the force and its
    Jacobian are right at the origin.
    """

    nargs = 2

    def fdiff(self, argindex=1):
        r, delta = self.args
        if argindex == 1:  # d/dr (1 - delta/r) in contact
            return step(r - delta) * safe_div(delta, r**2)
        return -step(r - delta) * safe_div(sp.S.One, r)

    def _latex(self, printer, exp=None):
        r, delta = (printer._print(a) for a in self.args)
        return _power(r"\frac{\left\langle %s - %s \right\rangle_{+}}{%s}" % (r, delta, r), exp)
