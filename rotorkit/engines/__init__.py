"""Time-integration engines (optional compiled back ends).

Submodules may depend on optional packages (for example ``rk_numba`` needs
numba); import them explicitly and guard the import when the dependency is
optional.
"""
