"""How brakeca compiles its kernel helpers with numba.

numba counts references to every array a compiled function holds: a helper that takes arrays
increments each one's count on entry and decrements it on exit, with an atomic instruction and
an opaque call each. numba's pruning pass removes such pairs in straight-line code, but not in
many helpers with branches (``refresh_candidate``'s two ``if`` were enough), and the step
kernels call such helpers for every cell event: in the lazy kernel the counts took about a
quarter of the run time, and the opaque calls kept LLVM from optimising across them
(docs/performance-history.md, ninth session). A helper that allocates no array
needs no counts, because its caller holds every array it is given; :func:`njit_noalloc`
compiles such helpers without them (numba's ``_nrt=False``). Functions that allocate (``np.empty``,
``np.argsort``...) keep ``njit(cache=True)``; a helper compiled this way that tried to allocate
fails to compile, so the rule cannot be broken silently.

numba compiles a callee with its caller's options, so a helper compiled this way may call
only functions that allocate nothing either (or that happen to be compiled already by another
caller: a dependence that held for the resin rebuild, which sorted with ``np.argsort``, until
``_lazy._resin_build_row`` sorted in given scratch; docs/performance-history.md, tenth session).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic, overload

from brakeca import _cachedir

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

F = TypeVar("F", bound=Callable[..., Any])


def njit_noalloc(fn: F) -> F:
    """Compile ``fn``, a helper that takes arrays but allocates none, without reference
    counting (cached on disk like every kernel)."""
    return njit(cache=True, _nrt=False)(fn)  # type: ignore[call-overload]


def njit_noalloc_inline(fn: F) -> F:
    """:func:`njit_noalloc`, and inlined into its callers by numba (``inline="always"``).

    numba passes every array to a compiled function it calls as its whole structure, seven
    machine words for a one-dimensional array and two more per further dimension, and LLVM
    does not inline a helper of more than a few lines. A helper that takes many arrays and is
    called thousands of times a step pays for the call: inlining ``_lazy._contact_row`` and
    ``_lazy._fix_partitions`` (15 and 5 arrays, about 1,700 calls a step in the low-wear
    runs' contact solve) made those runs take 0.78 of the time in the burnish stops and
    0.885-0.907 in later blocks (docs/performance-history.md, seventeenth session). Each call
    site gets its own copy of the code (compiling the lazy kernel took 6.6 s longer), so this
    is for hot helpers with few call sites."""
    return njit(cache=True, _nrt=False, inline="always")(fn)  # type: ignore[call-overload]


def prefetch(arr: Any, i: int) -> None:
    """``prefetch(arr, i)`` in compiled code: ask the processor to start loading the cache
    line of ``arr[i]`` (of ``arr[i, 0]`` for a two-dimensional array; LLVM's
    ``llvm.prefetch``, for reading, to be kept in every cache level). It has no effect on any
    value, so no result can change; it only lets loads of scattered cells that a loop will
    need a few iterations later overlap (docs/performance-history.md, eleventh session). An index
    outside the array is harmless (a prefetch never faults), so callers need not check it.
    Called from Python (numba's JIT disabled) it does nothing."""


@overload(prefetch, inline="always")
def _prefetch_overload(arr: Any, i: Any) -> Any:
    if not isinstance(arr, types.Array) or arr.ndim > 2 or not isinstance(i, types.Integer):
        return None

    def impl(arr: Any, i: Any) -> None:  # pragma: no cover - compiled
        _llvm_prefetch(arr, i)  # type: ignore[call-arg]

    return impl


@intrinsic
def _llvm_prefetch(typingctx: Any, arr: Any, idx: Any) -> Any:
    """``llvm.prefetch`` of the address of ``arr[idx]`` (``arr[idx, 0]``), for reading."""
    if not isinstance(arr, types.Array) or arr.ndim > 2 or not isinstance(idx, types.Integer):
        return None
    sig = types.void(arr, idx)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        aryty, idxty = signature.args
        ary = context.make_array(aryty)(context, builder, args[0])
        i = context.cast(builder, args[1], idxty, types.intp)
        zero = context.get_constant(types.intp, 0)
        item = cgutils.get_item_pointer2(
            context,
            builder,
            data=ary.data,
            shape=cgutils.unpack_tuple(builder, ary.shape, aryty.ndim),
            strides=cgutils.unpack_tuple(builder, ary.strides, aryty.ndim),
            layout=aryty.layout,
            inds=[i] + [zero] * (aryty.ndim - 1),
            wraparound=False,
        )
        ptr = builder.bitcast(item, ir.IntType(8).as_pointer())
        i32 = ir.IntType(32)
        fnty = ir.FunctionType(ir.VoidType(), [ptr.type, i32, i32, i32])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.prefetch.p0")
        builder.call(fn, [ptr, i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen
