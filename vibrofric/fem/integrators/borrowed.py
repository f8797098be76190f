"""Arrays without reference counts, for the compiled time loops.

numba counts the references to every array a compiled function holds: each
array argument, each name bound to one, each argument of an inlined call
gets an atomic increment and a decrement (NRT_incref / NRT_decref), and a
tuple of arrays passed to a compiled function one pair per array. numba's
pruning of these pairs stops at branches, and the friction law is full of
them: in the implicit contact iteration (contact_solve.py) the node loop
kept 6 pairs a node and one a friction sub-step, ~1,100 pairs a step of the
reduced Fig 7 run (30 nodes, 11 sub-steps, 2.2 evaluations), a sixth of the
loop's time (docs/performance.md, "Design choices measured").

``borrowed(x)`` is ``x`` (an array, or a tuple or named tuple of arrays and
scalars) with each array's reference-count pointer set to null: the counts
on it become a test for null. A borrowed array owns nothing, so it must not
outlive the array it was taken from nor leave the compiled code: take it in
a compiled function from its arguments (which the caller holds through the
call), and return only scalars.
"""

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


def _borrowable(ty) -> bool:
    if isinstance(ty, types.Array):
        return True
    if isinstance(ty, types.BaseTuple):
        return all(_borrowable(item) for item in ty)
    return isinstance(ty, (types.Number, types.Boolean))


def _without_counts(context, builder, ty, value):
    if isinstance(ty, types.Array):
        array = context.make_array(ty)(context, builder, value=value)
        array.meminfo = cgutils.get_null_value(array.meminfo.type)
        array.parent = cgutils.get_null_value(array.parent.type)
        return array._getvalue()
    if isinstance(ty, types.BaseTuple):
        items = [_without_counts(context, builder, item, builder.extract_value(value, i))
                 for i, item in enumerate(ty)]
        return context.make_tuple(builder, ty, items)
    return value


@intrinsic
def borrowed(typingctx, x):
    """``x`` with its arrays' reference counts dropped (see the module's docstring)."""
    if not _borrowable(x):
        return None

    def codegen(context, builder, signature, args):
        return _without_counts(context, builder, signature.args[0], args[0])

    return x(x), codegen
