"""Borrowed arrays for the kernels' hot calls: the same data without a reference count.

numba counts references to every array a jitted function takes: a call that passes the work arrays
increments and decrements one counter per array, an atomic operation each (the AFT residual takes 32 arrays,
19 of them the continuation's workspace; Hill's workspace holds 37). :func:`borrowed` gives arrays (or tuples
of them, nested) whose reference count numba skips: the same data, shape and strides with no memory owner.
A function may borrow the arrays it takes as arguments, for as long as it runs (the caller holds them until it
returns); it must not borrow arrays it allocates itself (numba frees an array after its last use, and a
borrowed view does not count as one) nor return a borrowed array to Python.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["borrowed"]


def _borrow(context, builder, ty, value):
    if isinstance(ty, types.Array):
        source = context.make_array(ty)(context, builder, value)
        view = context.make_array(ty)(context, builder)
        view.meminfo = cgutils.get_null_value(source.meminfo.type)  # numba's incref/decref skip a null owner
        view.parent = cgutils.get_null_value(source.parent.type)
        view.nitems = source.nitems
        view.itemsize = source.itemsize
        view.data = source.data
        view.shape = source.shape
        view.strides = source.strides
        return view._getvalue()
    if isinstance(ty, types.BaseTuple):
        out = cgutils.get_null_value(context.get_value_type(ty))
        for i, member in enumerate(ty.types):
            out = builder.insert_value(out, _borrow(context, builder, member, builder.extract_value(value, i)), i)
        return out
    return value  # not an array: as it is


@intrinsic
def borrowed(typingctx, value):
    """``value`` (an array or a tuple of arrays and other values, nested) with every array borrowed: the same
    type, data, shape and strides, no reference count (module notes)."""
    def codegen(context, builder, signature, args):
        return _borrow(context, builder, signature.args[0], args[0])

    return value(value), codegen
