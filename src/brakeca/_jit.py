"""How brakeca compiles its kernel helpers with numba.

numba counts references to every array a compiled function holds: a helper that takes arrays
increments each one's count on entry and decrements it on exit, with an atomic instruction and
an opaque call each. numba's pruning pass removes such pairs in straight-line code, but not in
many helpers with branches (``refresh_candidate``'s two ``if`` were enough), and the step
kernels call such helpers for every cell event: in the lazy kernel the counts took about a
quarter of the run time, and the opaque calls kept LLVM from optimising across them
(docs/performance.md, ninth session). A helper that allocates no array
needs no counts, because its caller holds every array it is given; :func:`njit_noalloc`
compiles such helpers without them (numba's ``_nrt=False``). Functions that allocate (``np.empty``,
``np.argsort``...) keep ``njit(cache=True)``; a helper compiled this way that tried to allocate
fails to compile, so the rule cannot be broken silently.

numba compiles a callee with its caller's options, so a helper compiled this way may call a
function that allocates only if that function has already been compiled elsewhere. Two do:
``_lazy._resin_cut`` and ``_lazy._resin_push`` (through ``_resin_merge_pending``) rebuild a
row without room with ``_resin_build_row``, which ``run_stop_lazy`` compiles first, at the
start of a stop. Called first on their own, they would fail to compile (loudly). Moving the
rebuild to the callers was tried and measured slower (docs/performance.md, ninth session);
the lasting fix is a ``_resin_build_row`` that sorts in given scratch instead of allocating.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from numba import njit

F = TypeVar("F", bound=Callable[..., Any])


def njit_noalloc(fn: F) -> F:
    """Compile ``fn``, a helper that takes arrays but allocates none, without reference
    counting (cached on disk like every kernel)."""
    return njit(cache=True, _nrt=False)(fn)  # type: ignore[call-overload]
