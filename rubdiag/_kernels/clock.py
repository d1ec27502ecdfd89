"""A CPU cycle counter callable from Numba kernels, to see where a kernel's time goes.

:func:`cycles` reads the processor's time-stamp counter (LLVM's ``readcyclecounter``: one
instruction, some tens of cycles; on x86 a constant rate, independent of the core's clock
changes). Callers turn counts into seconds by timing a whole kernel call with
``time.perf_counter`` as well.
"""

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.core.extending import intrinsic

__all__ = ["cycles"]


@intrinsic
def cycles(typingctx):
    """The time-stamp counter (int64): differences are elapsed cycles."""

    def codegen(context, builder, signature, args):
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.IntType(64), []), "llvm.readcyclecounter")
        return builder.call(fn, [])

    return types.int64(), codegen
