"""The kernels' compiled helpers are compiled without reference counting (brakeca._jit)."""

from __future__ import annotations

import numba
import numpy as np
import pytest
from numba.core.errors import TypingError
from numba.core.registry import CPUDispatcher

from brakeca import _jit, _kernels, _lazy, automaton, contact

# the compiled functions that keep numba's reference counting: those that allocate arrays,
# or call one that does (solve_contact)
ALLOCATING = {
    "brakeca._lazy": {
        "_exact_root",
        "check_invariants",
        "run_stop_lazy",
        "solve_contact",
    },
    "brakeca._kernels": {"run_stop"},
    "brakeca.contact": {"first_root"},
    "brakeca.automaton": set(),
}
# helpers compiled by njit_noalloc_inline (hot, with many array arguments and few call sites;
# _evt_top is a three-line rule shared by two helpers, inlined where they use it)
INLINED = {"_contact_row", "_fix_partitions", "_move_row", "_evt_top"}
# scalar helpers (no array arguments, so nothing to count) that numba inlines
SCALAR_INLINED = {
    "_tree_leaf",
    "_on",
    "_local_step",
    "_shift",
    "_sums_in",
    "_sums_out",
    "_resin_start",
}


def _compiled(module) -> dict[str, CPUDispatcher]:
    return {
        name: obj
        for name, obj in vars(module).items()
        if isinstance(obj, CPUDispatcher) and obj.py_func.__module__ == module.__name__
    }


@pytest.mark.parametrize("module", [_lazy, _kernels, contact, automaton], ids=lambda m: m.__name__)
def test_helpers_that_allocate_nothing_skip_reference_counting(module) -> None:
    """Every compiled function of the step kernels is either listed as allocating (and keeps
    reference counting) or compiled by ``njit_noalloc``: a new helper that takes arrays must
    not bring back the per-call counts (docs/performance-history.md, ninth session)."""
    allocating = ALLOCATING[module.__name__]
    compiled = _compiled(module)
    assert allocating <= compiled.keys(), allocating - compiled.keys()
    for name, dispatcher in compiled.items():
        nrt = dispatcher.targetoptions.get("_nrt", True)
        if name in allocating:
            assert nrt, f"{module.__name__}.{name} allocates: it needs reference counting"
        elif name in SCALAR_INLINED:
            assert dispatcher.targetoptions.get("inline") == "always", name
        else:
            assert nrt is False, f"{module.__name__}.{name}: use brakeca._jit.njit_noalloc"
    inlined = {
        name
        for name, dispatcher in compiled.items()
        if name not in SCALAR_INLINED and dispatcher.targetoptions.get("inline") == "always"
    }
    assert inlined == (INLINED if module is _lazy else set())


def test_noalloc_helper_refuses_to_allocate() -> None:
    """A helper compiled without reference counting cannot allocate: it fails to compile
    instead of leaking or freeing memory it does not own."""

    def bad(n):
        return np.zeros(n).sum()

    compiled = _jit.njit_noalloc(bad)
    with pytest.raises(TypingError, match="zeros"):
        compiled(3)


def test_noalloc_helper_writes_through_to_the_callers_array() -> None:
    """Arrays pass to a helper compiled by ``njit_noalloc`` by reference, from Python and
    from another compiled function alike."""

    def bump(a, i):
        a[i] += 1.0

    helper = _jit.njit_noalloc(bump)
    a = np.zeros(4)
    helper(a, 2)

    @_jit.njit_noalloc
    def twice(b):
        helper(b, 0)
        helper(b, 0)

    twice(a)
    assert a.tolist() == [2.0, 0.0, 1.0, 0.0]


def test_prefetch_compiles_to_llvm_prefetch_and_changes_nothing() -> None:
    """``_jit.prefetch`` on one- and two-dimensional arrays of the kernels' dtypes, in one
    compiled function (so one declaration of ``llvm.prefetch`` serves every pointer type),
    emits the intrinsic and leaves every value alone, also for an index past the end."""

    def gather(f8, i1, i4, tree, idx):
        s = 0.0
        for q in range(idx.size):
            ahead = idx[q + 1] if q + 1 < idx.size else 10**6
            _jit.prefetch(f8, ahead)
            _jit.prefetch(i1, ahead)
            _jit.prefetch(i4, ahead)
            _jit.prefetch(tree, ahead)
            i = idx[q]
            s += f8[i] + i1[i] + i4[i] + tree[i, 1]
        return s

    # njit_noalloc's options but no disk cache: numba cannot show the machine code of a
    # function loaded from its cache, which a second run of the suite on the same sources does
    compiled = numba.njit(_nrt=False)(gather)
    rng = np.random.default_rng(3)
    f8 = rng.random(50)
    i1 = rng.integers(-5, 5, 50).astype(np.int8)
    i4 = rng.integers(0, 9, 50).astype(np.int32)
    tree = rng.random((50, 4))
    idx = rng.integers(0, 50, 200)
    assert compiled(f8, i1, i4, tree, idx) == gather(f8, i1, i4, tree, idx)
    ir = next(iter(compiled.inspect_llvm().values()))
    assert "@llvm.prefetch" in ir


def test_prefetch_refuses_other_arguments() -> None:
    def bad(a):
        _jit.prefetch(a, 0)

    with pytest.raises(TypingError):
        _jit.njit_noalloc(bad)(np.zeros((2, 2, 2)))


def test_inlined_helper_writes_through_to_the_callers_array() -> None:
    """A helper compiled by ``njit_noalloc_inline`` is inlined into a compiled caller and
    writes to the caller's array as a called helper would."""

    def bump(a, i):
        a[i] += 1.0

    helper = _jit.njit_noalloc_inline(bump)
    assert helper.targetoptions.get("inline") == "always"

    @_jit.njit_noalloc
    def caller(a):
        for i in range(a.size):
            helper(a, i)
            helper(a, i)

    a = np.arange(4.0)
    caller(a)
    np.testing.assert_array_equal(a, np.arange(4.0) + 2.0)
