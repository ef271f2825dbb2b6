"""The library's own error types.

Every error a user can trigger with bad input is one of these, so callers can
catch ``RotorkitError`` (or the built-in ``ValueError``/``TypeError`` it
derives from) and never see a bare ``KeyError`` or ``ZeroDivisionError``.
"""

__all__ = [
    "RotorkitError",
    "ParameterError",
    "UnitError",
    "ArgumentTypeError",
    "TopologyError",
    "SimulationError",
    "DiskFullError",
]


class RotorkitError(Exception):
    """Base class of every error rotorkit raises on purpose."""


class ParameterError(RotorkitError, ValueError):
    """A parameter has a bad value (sign, range, unknown name)."""


class UnitError(ParameterError, TypeError):
    """A quantity has the wrong physical dimension or type."""


class ArgumentTypeError(ParameterError, TypeError):
    """An argument is an object of the wrong kind (a Model where a compiled system is expected, a number where a
    signal name is); the message says what is expected."""


class TopologyError(RotorkitError, ValueError):
    """Elements do not fit together (unknown station, rotor without support, ...)."""


class SimulationError(RotorkitError, RuntimeError):
    """An integration failed; ``partial`` holds the result up to the failure.

    Attributes
    ----------
    partial : rotorkit.result.Result or None
        The samples computed before the failure.
    time : float or None
        The time (s) the integration reached.
    """

    def __init__(self, message, *, partial=None, time=None):
        super().__init__(message)
        self.partial = partial
        self.time = time


class DiskFullError(RotorkitError, OSError):
    """No space left (or the quota reached) on the disk a file is written to; the message names the folder, its
    file system and the free space, and what to do. Its ``errno`` is ``ENOSPC`` or ``EDQUOT``."""

    def __str__(self):
        return self.strerror or super().__str__()
