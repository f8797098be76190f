"""Four-lane vectors of doubles inside numba loops, for the product with K.

numba has no vector type, and LLVM's vectorizers do not find the one shape
that suits a product in 3x3 node blocks: a running sum per block row, four
lanes wide, fed by one multiply-add a row and block. Without reordering of
sums its SLP vectorizer pairs two lanes at most; with reordering its loop
vectorizer gathers (linalg._bsr_apply). This module gives the loops that
shape directly: a numba type whose LLVM form is <4 x double> (AVX's ymm
register; two SSE registers on a machine without AVX) and the few
operations the product needs, each a single LLVM instruction or intrinsic.

    zeros()              (0, 0, 0, 0)
    load(a, i)           a[i:i + 4]; a must hold a[i + 3]
    load3(a, i)          (a[i], a[i + 1], a[i + 2], 0): a masked load, never
                         past a[i + 2]
    fma(a, b, c)         a * b + c, lane by lane, each rounded once
    add(a, b)            a + b, lane by lane
    sum3(v)              (v[0] + v[1]) + v[2]

Every lane is computed as the scalar code would compute it: the vectors
change which sums run side by side, not how each one rounds.
"""

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic, models, register_model

_DOUBLE4 = ir.VectorType(ir.DoubleType(), 4)
_MASK4 = ir.VectorType(ir.IntType(1), 4)
_I32 = ir.IntType(32)


class Double4(types.Type):
    """Four doubles in one vector register."""

    def __init__(self):
        super().__init__(name="double4")


double4 = Double4()


@register_model(Double4)
class _Double4Model(models.PrimitiveModel):
    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, _DOUBLE4)


def _doubles_at(array, index) -> bool:
    """Whether (array, index) type as a C-contiguous float64 array and an integer."""
    return (isinstance(array, types.Array) and array.dtype == types.float64
            and array.layout == "C" and isinstance(index, types.Integer))


def _address(context, builder, array_type, array, index):
    """The address of array[index] (a C-contiguous array), as a pointer to four doubles."""
    data = context.make_array(array_type)(context, builder, array).data
    return builder.bitcast(builder.gep(data, [index]), _DOUBLE4.as_pointer())


@intrinsic
def zeros(typingctx):
    def codegen(context, builder, signature, args):
        return ir.Constant(_DOUBLE4, [0.0] * 4)
    return double4(), codegen


@intrinsic
def load(typingctx, array, index):
    if not _doubles_at(array, index):
        return None

    def codegen(context, builder, signature, args):
        pointer = _address(context, builder, signature.args[0], *args)
        return builder.load(pointer, align=8)
    return double4(array, index), codegen


@intrinsic
def load3(typingctx, array, index):
    if not _doubles_at(array, index):
        return None

    def codegen(context, builder, signature, args):
        pointer = _address(context, builder, signature.args[0], *args)
        masked_load = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(_DOUBLE4, [_DOUBLE4.as_pointer(), _I32, _MASK4,
                                                       _DOUBLE4]),
            "llvm.masked.load.v4f64.p0v4f64")
        return builder.call(masked_load, [pointer, ir.Constant(_I32, 8),
                                          ir.Constant(_MASK4, [1, 1, 1, 0]),
                                          ir.Constant(_DOUBLE4, [0.0] * 4)])
    return double4(array, index), codegen


@intrinsic
def fma(typingctx, a, b, c):
    def codegen(context, builder, signature, args):
        fused = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(_DOUBLE4, [_DOUBLE4] * 3), "llvm.fma.v4f64")
        return builder.call(fused, args)
    return double4(double4, double4, double4), codegen


@intrinsic
def add(typingctx, a, b):
    def codegen(context, builder, signature, args):
        return builder.fadd(*args)
    return double4(double4, double4), codegen


@intrinsic
def sum3(typingctx, v):
    def codegen(context, builder, signature, args):
        lanes = [builder.extract_element(args[0], ir.Constant(_I32, k)) for k in range(3)]
        return builder.fadd(builder.fadd(lanes[0], lanes[1]), lanes[2])
    return types.float64(double4), codegen
