"""Code generation: generated Python source (unrolled or structured), its C translation, and the on-disk cache.

This package's own namespace holds only what is needed before any code is generated (:func:`codegen_mode`), so
a warm start that finds its model in the cache never imports sympy.
"""

STRUCTURED_FROM = 40
"""Models with at least this many coordinates get the structured path (``auto``); see :func:`codegen_mode`."""

CODEGEN_MODES = ("auto", "unrolled", "structured")


def codegen_mode(n_coordinates, mode="auto"):
    """``'unrolled'`` or ``'structured'`` for a model of ``n_coordinates``.

    ``auto`` (``$ROTORKIT_CODEGEN`` overrides it) picks the structured path
    from :data:`STRUCTURED_FROM` coordinates: below it, unrolled code is as
    fast as hand-written code and compiles in seconds; above it, unrolled
    code grows with the square of the model and numba's compile time with it
    (``bench/bench_fe.py --sections codegen`` measures both).
    """
    import os

    from ..errors import ParameterError

    if mode == "auto":
        mode = os.environ.get("ROTORKIT_CODEGEN", "auto") or "auto"
    if mode not in CODEGEN_MODES:
        raise ParameterError(f"codegen={mode!r} is unknown; expected 'auto', 'unrolled' or 'structured'")
    if mode == "auto":
        return "structured" if n_coordinates >= STRUCTURED_FROM else "unrolled"
    return mode
