"""Model reduction for transients: Craig-Bampton with the nonlinear coordinates physical.

- :mod:`rotorkit.reduction.system`: :func:`reduce`, :class:`ReducedSystem`,
  :class:`ReductionError`;
- :mod:`rotorkit.reduction.basis`: the Craig-Bampton basis (numbers);
- :mod:`rotorkit.reduction.codegen`: the generated reduced right-hand side.

See docs/reduction.md.
"""

from .system import ReducedSystem, ReductionError, reduce

__all__ = ["reduce", "ReducedSystem", "ReductionError"]
