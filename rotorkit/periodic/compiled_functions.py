"""The model's jitted functions inside the continuation kernel from their addresses (numba first-class functions).

A first-class function argument of a compiled kernel costs numba two Python calls at every kernel call to find
its addresses (about 3.5 us each), and a call through its C wrapper address costs about 10 ns more than a call by
numba's own calling convention, which numba uses only where the argument is a dispatcher (whose addresses take
it some 40 us per call to find). The continuation kernel takes the addresses instead, as integers found once per
model (:func:`function_addresses`), and :func:`core_function` / :func:`jac_function` make the first-class function
values of them inside: the C wrapper's address and, where numba gives it, the jitted function's, which calls
then use.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["CORE", "JAC", "core_function", "jac_function", "function_addresses"]

_VEC, _MAT = types.float64[::1], types.float64[:, ::1]
#: the types of the model's ``rhs`` and ``switches`` (``f(t, y, p, out)``) and of its ``jac`` (``jac(t, y, p, J)``)
CORE = types.FunctionType(types.void(types.float64, _VEC, _VEC, _VEC))
JAC = types.FunctionType(types.void(types.float64, _VEC, _VEC, _MAT))


def _maker(function_type):
    def make(typingctx, c_address, jit_address):
        def codegen(context, builder, signature, args):
            value = cgutils.create_struct_proxy(function_type)(context, builder)  # zero-filled: no Python object
            pointer = context.get_value_type(types.voidptr)
            value.c_addr = builder.inttoptr(args[0], pointer)
            if "jit_addr" in context.data_model_manager[function_type]._fields:
                value.jit_addr = builder.inttoptr(args[1], pointer)  # zero: calls take the C wrapper
            return value._getvalue()

        return function_type(types.int64, types.int64), codegen

    return make


core_function = intrinsic(_maker(CORE))
core_function.__doc__ = """``f(t, y, p, out)`` at ``(c_address, jit_address)`` (:func:`function_addresses`)."""
jac_function = intrinsic(_maker(JAC))
jac_function.__doc__ = """``jac(t, y, p, J)`` at ``(c_address, jit_address)`` (:func:`function_addresses`)."""


def function_addresses(functions):
    """``int64`` addresses ``(c, jit)`` per function of the dispatchers ``(rhs, jac, switches)``, flat (6), or
    None if numba does not give a C wrapper's address; a jit address numba does not give is 0."""
    import numpy as np
    from numba.experimental.function_type import _get_jit_address, _get_wrapper_address

    addresses = []
    for function, kind in zip(functions, (CORE, JAC, CORE)):
        try:
            c_address = _get_wrapper_address(function, kind.signature)
        except Exception:  # noqa: BLE001 - another numba's internals: the Python path
            return None
        try:
            jit_address = _get_jit_address(function, kind.signature)
        except Exception:  # noqa: BLE001 - calls take the C wrapper
            jit_address = 0
        if not (isinstance(c_address, int) and c_address > 0 and isinstance(jit_address, int)):
            return None
        addresses += [c_address, jit_address]
    return np.array(addresses, dtype=np.int64)
