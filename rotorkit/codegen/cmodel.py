"""A generated model's functions compiled as C (the ``c`` back end): callable from Python and by address.

:func:`c_functions` translates a generated module's ``rhs`` and ``switches``
(``jac`` in a Jacobian module) into C (:mod:`rotorkit.codegen.csource`),
builds them into ``<cache>/models/<key>/model_c.so`` (:mod:`rotorkit.codegen.cbuild`)
and returns them as :class:`CFunction` objects: ``f(t, y, p, out)`` like the
numba functions, and ``f.address`` for the compiled integration loop
(:mod:`rotorkit.engines.rk_c`).
"""

import ctypes

import numpy as np

from . import cbuild, csource

__all__ = ["CFunction", "c_functions", "translatable"]

_ARGTYPES = (ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)
_LOADED = {}  # module name -> {function name: CFunction}


class CFunction:
    """A compiled ``void f(double t, const double *y, const double *p, double *out)``.

    Call it as ``f(t, y, p, out)`` with float64 C-contiguous arrays (``out``
    written); ``address`` is the function pointer the C integration loop takes.
    """

    def __init__(self, library, name):
        function = getattr(library, name)
        function.argtypes, function.restype = _ARGTYPES, None
        self._function, self._library, self.name = function, library, name  # the library stays loaded
        self.address = ctypes.cast(function, ctypes.c_void_p).value

    def __call__(self, t, y, p, out):
        for array, what in ((y, "y"), (p, "p"), (out, "out")):
            if not (isinstance(array, np.ndarray) and array.dtype == np.float64 and array.flags.c_contiguous):
                raise TypeError(f"{self.name}: {what} must be a C-contiguous float64 numpy array")
        if not out.flags.writeable:
            raise TypeError(f"{self.name}: out must be writeable")
        self._function(float(t), y.ctypes.data, p.ctypes.data, out.ctypes.data)

    def __repr__(self):
        return f"<CFunction {self.name} at {self.address:#x}>"


def translatable(module):
    """Whether the module's code generation is one the C translation covers (unrolled)."""
    return getattr(module, "CODEGEN", None) == "unrolled" and hasattr(module, "__rotorkit_source__")


def c_functions(module):
    """``{name: CFunction}`` for the generated functions of ``module`` (``rhs``, ``switches``, ``jac``: those it has).

    Built once per cache entry (signed, reused by later processes) and loaded
    once per process.

    Raises
    ------
    rotorkit.codegen.csource.Untranslatable
        Structured code generation (matrices), or a construct outside the
        straight-line subset.
    rotorkit.codegen.cbuild.CompilerError
        No C compiler, or it failed.
    """
    found = _LOADED.get(module.__name__)
    if found is None:
        if not translatable(module):
            raise csource.Untranslatable(f"{module.__name__}: code generation {getattr(module, 'CODEGEN', '?')!r} "
                                         "(or no generated source); the c back end covers unrolled code")
        names = [n for n in csource.FUNCTIONS if callable(getattr(module, n, None))]
        text = csource.translate(module.__rotorkit_source__, names, row_length=2 * module.N_COORDINATES)
        library = cbuild.library(getattr(module, "__rotorkit_entry__", None), "model_c", text)
        found = _LOADED[module.__name__] = {n: CFunction(library, n) for n in names}
    return found
