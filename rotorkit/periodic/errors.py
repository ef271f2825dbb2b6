"""The errors of the periodic-response analyses (subclasses of the library's own)."""

from ..errors import ParameterError, RotorkitError

__all__ = ["NoOscillatingInput", "ConvergenceError"]


class NoOscillatingInput(ParameterError):
    """The model has no periodic input (no unbalance, no periodic force): its only steady state is static."""


class ConvergenceError(RotorkitError, RuntimeError):
    """Newton's method did not bring the harmonic-balance residual below its tolerance.

    Attributes
    ----------
    residual : float
        The smallest residual reached, relative to the residual scale.
    parameter : float or None
        The value of the continuation parameter where it failed.
    """

    def __init__(self, message, *, residual=None, parameter=None):
        super().__init__(message)
        self.residual = residual
        self.parameter = parameter
