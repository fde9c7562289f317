"""The end of a step leaves the packed records in the order of the next step.

:func:`brakeca._kernels.phase_apply` receives the surviving records in contact compacted to
the front (``pk[:w]``), the records destroyed in contact (in ``gone``), the records out of
contact (``pk[n_in:n_plat]``, some destroyed out of contact) and the new secondary plateaus.
It must leave exactly the sequence [survivors in contact][new][survivors out of contact],
insertion-sorted (a stable sort by height, highest first), whichever way the records out of
contact have to move: left (more removed than added), right (more added), or not at all,
with or without removals among them. Some of these cases are rare in real runs (removals out
of contact need rule 6 or a rule-4 mark on a secondary out of contact), so each is built here.
"""

from __future__ import annotations

import numpy as np
import pytest

from brakeca import _kernels as K
from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import SimulationState
from brakeca.surface import Surface


def _state(rng):
    config = load_preset().with_updates(
        {"mesh.n_radial": 2, "mesh.n_angular": 40, "mesh.n_subdomains": 4}
    )
    grid = make_grid(config)
    status = np.zeros(grid.shape, dtype=np.int8)
    status[:, ::2] = K.PRIMARY  # every other column: 40 plateau cells, 40 resin cells
    height = np.where(status == K.PRIMARY, rng.uniform(50e-6, 60e-6, grid.shape), 10e-6)
    surface = Surface(height, status, np.full(grid.shape, -np.inf), 0)
    return SimulationState.from_surface(surface, grid)


def _records(pk, lo, hi):
    return [tuple(a[q].item() for a in pk) for q in range(lo, hi)]


@pytest.mark.parametrize("head_dead", [0, 3])
@pytest.mark.parametrize("n_new", [0, 2, 6])
@pytest.mark.parametrize("tail_dead", [0, 2])
def test_records_end_in_the_next_steps_order(head_dead, n_new, tail_dead):
    rng = np.random.default_rng(head_dead * 100 + n_new * 10 + tail_dead)
    state = _state(rng)
    pk, cnt = state.pk, state.cnt
    n_plat = int(cnt[K.CNT_PLATEAU])
    n_in = 10  # the first 10 records were in contact
    z = 0.5 * (pk[K.P_H][n_in - 1] + pk[K.P_H][n_in])
    # the wear pass compacted the survivors in contact to the front; the others are in `gone`
    head = _records(pk, 0, n_in)
    dead_at = sorted(rng.choice(n_in, size=head_dead, replace=False).tolist())
    survivors = [r for q, r in enumerate(head) if q not in dead_at]
    gone = K.packed_records(state.height.size)
    for k, q in enumerate(dead_at):
        K._put_at(gone, k, *head[q])
    for q, r in enumerate(survivors):
        K._put_at(pk, q, *r)
    w = len(survivors)
    # records destroyed out of contact (rule 6 or 4), and new secondary plateaus
    tail = _records(pk, n_in, n_plat)
    tail_at = sorted((n_in + rng.choice(n_plat - n_in, size=tail_dead, replace=False)).tolist())
    none_cells = np.flatnonzero(state.status == K.NONE)
    created = np.sort(rng.choice(none_cells, size=n_new, replace=False))
    before = state.height[created].copy()
    n = state.height.size
    destroyed, dpos, new = (np.zeros(n, dtype=np.int64) for _ in range(3))
    for k, q in enumerate(dead_at):
        destroyed[k] = head[q][K.P_IDX]
    for k, q in enumerate(tail_at):
        destroyed[head_dead + k] = pk[K.P_IDX][q]
        dpos[head_dead + k] = q
    new[:n_new] = created
    n_sec = 0
    held = K.phase_apply(
        pk, gone, head_dead, w, n_in, cnt, state.bin_area, state.height, state.base,
        state.status, state.cand, state.ncand, state.cmax, state.cell_area, state.cell_bin,
        state.outflow, state.acc, state.mark, state.heap_keys, state.heap_vals,
        state.rule4_list, z, state.n_angular, destroyed, dpos, head_dead + tail_dead, new,
        n_new, 0.0, n_sec, True,
    )  # fmt: skip
    fresh = [
        (z, float(before[c]), int(idx), int(state.cell_bin[idx]), K.SECONDARY)
        for c, idx in enumerate(created)
    ]
    kept_tail = [r for q, r in zip(range(n_in, n_plat), tail, strict=True) if q not in tail_at]
    sequence = survivors + fresh + kept_tail
    expected = sorted(sequence, key=lambda r: -r[K.P_H])  # stable, like the insertion sort
    assert cnt[K.CNT_PLATEAU] == len(expected)
    got = _records(pk, 0, int(cnt[K.CNT_PLATEAU]))
    assert [r[K.P_IDX] for r in got] == [r[K.P_IDX] for r in expected]
    assert got == [tuple(type(g)(e) for g, e in zip(gr, er, strict=True)) for gr, er in
                   zip(got, expected, strict=True)]  # fmt: skip
    # the held volume is summed in the order of the sequence (only new records hold any here)
    want = 0.0
    for r in sequence:
        if r[K.P_ST] == K.SECONDARY:
            want += (r[K.P_H] - r[K.P_BASE]) * state.bin_area[r[K.P_BIN]]
    assert held == want
    # the destroyed cells are resin now, the new ones secondary plateaus at z
    assert np.all(state.status[destroyed[: head_dead + tail_dead]] == K.NONE)
    assert np.all(state.status[created] == K.SECONDARY) and np.all(state.height[created] == z)
