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

numba compiles a callee with its caller's options, so a helper compiled this way may call
only functions that allocate nothing either (or that happen to be compiled already by another
caller: a dependence that held for the resin rebuild, which sorted with ``np.argsort``, until
``_lazy._resin_build_row`` sorted in given scratch; docs/performance.md, tenth session).
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
