"""Compiled step kernels (numba) and nothing else.

One call of :func:`run_stop` runs every time step of one stop, so Python overhead is paid per
stop, not per step. The physics lives in named functions of :mod:`brakeca.contact`,
:mod:`brakeca.friction`, :mod:`brakeca.wear` and :mod:`brakeca.automaton`; this module wires
them in the order of a step (decision, docs/model.md), one compiled function per phase:

1. :func:`phase_contact` -- contact solve on the current heights (first root of the torque
   balance) -> z;
2. + 3a. :func:`phase_friction_wear` -- friction and Archard wear of the plateaus in contact;
3b. :func:`phase_resin` -- the resin cut;
4a. :func:`phase_destruction` -- rules 4-7, statuses as at the start of the step;
4b. :func:`phase_creation` -- rules 1-3 drawing on the inflow, gaps measured to this z;
    :func:`phase_apply` -- the status changes take effect;
5. :func:`phase_advance` -- the particle streams advance one subdomain; the last emits.

State arrays are flat (index ``j * n_angular + i``); per-cell constants (area, sliding distance,
stream bin ``j * n_sub + k``) are precomputed so hot loops do no integer division. Work per step
is proportional to the cells in contact plus the cells whose status changes, not to the grid:

* plateau cells are kept sorted by height (``order``), repaired by insertion sort each step;
* resin (status none) cells are kept in a max-heap by height, so the resin cut visits only the
  cells above the disc (stale heap entries are skipped: key != height or status != none);
* creation candidates (a none cell with a plateau directly east) are flagged and counted per
  stream bin, updated where statuses change;
* rule 4 is checked only on cells whose eastern neighbour lost its plateau status.

``fastmath`` stays off: results are bit-reproducible.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from brakeca.automaton import (
    creation_rule,
    gap_fill_cost,
    rule4_lost_support,
    rule5_deposit_worn,
    rule6_primary_out_of_reach,
    rule7_fibre_worn,
)
from brakeca.contact import SOLVE_OK, first_root
from brakeca.friction import local_cof
from brakeca.wear import archard_wear_depth, resin_cut_depth

NONE = 0
PRIMARY = 1
SECONDARY = 2

# indices into the float accumulator array `acc`
ACC_REMOVED = 0  # pad material removed since the start of the run [m^3]
ACC_EMITTED = 1  # volume emitted since the start of the run [m^3]
ACC_HELD = 2  # volume held in secondary plateaus, tracked incrementally [m^3]
ACC_PRIMARY_AREA = 3  # area of primary plateaus [m^2]
ACC_SECONDARY_AREA = 4  # area of secondary plateaus [m^2]
N_ACC = 5

# indices into the int counter array `cnt`
CNT_PLATEAU = 0  # valid entries of `order`
CNT_HEAP = 1  # entries of the resin heap
CNT_RULE4 = 2  # entries of the rule-4 check list
N_CNT = 3

# indices into the per-step record array `rec[step, :]`
R_COF = 0
R_NORMAL = 1
R_FRICTION = 2
R_CONTACT_AREA = 3
R_PRIMARY_AREA = 4
R_SECONDARY_AREA = 5
R_EMITTED = 6
R_GENERATED = 7
R_LEDGER = 8
R_DISC = 9
R_HELD = 10
R_STREAM = 11
R_TARGET = 12
N_REC = 13

# per-step scratch sums `sums`
S_FRICTION = 0
S_NORMAL = 1
S_CONTACT = 2
S_REMOVED = 3
N_SUMS = 4

# error codes
OK = 0
ERR_NO_PLATEAU = 1
ERR_BAR = 2
ERR_LEDGER = 3


# --- small data structures -------------------------------------------------------------------
@njit(cache=True)
def sort_packed(n, pk_h, pk_base, pk_area, pk_slide, pk_floor, pk_idx, pk_bin, pk_st):
    """Insertion sort of the packed plateau records by height, highest first (stable).

    Linear in n plus the number of inversions: the order is nearly sorted from the last step.
    """
    for a in range(1, n):
        hk = pk_h[a]
        if pk_h[a - 1] >= hk:
            continue
        rb, ra, rs, rf = pk_base[a], pk_area[a], pk_slide[a], pk_floor[a]
        ri, rn, rt = pk_idx[a], pk_bin[a], pk_st[a]
        b = a - 1
        while b >= 0 and pk_h[b] < hk:
            pk_h[b + 1] = pk_h[b]
            pk_base[b + 1] = pk_base[b]
            pk_area[b + 1] = pk_area[b]
            pk_slide[b + 1] = pk_slide[b]
            pk_floor[b + 1] = pk_floor[b]
            pk_idx[b + 1] = pk_idx[b]
            pk_bin[b + 1] = pk_bin[b]
            pk_st[b + 1] = pk_st[b]
            b -= 1
        pk_h[b + 1] = hk
        pk_base[b + 1] = rb
        pk_area[b + 1] = ra
        pk_slide[b + 1] = rs
        pk_floor[b + 1] = rf
        pk_idx[b + 1] = ri
        pk_bin[b + 1] = rn
        pk_st[b + 1] = rt


@njit(cache=True)
def heap_push(keys, vals, cnt, key, val):
    """Push (key, val) on the max-heap held in ``keys[:cnt[CNT_HEAP]]``."""
    n = cnt[CNT_HEAP]
    keys[n] = key
    vals[n] = val
    cnt[CNT_HEAP] = n + 1
    while n > 0:
        parent = (n - 1) >> 1
        if keys[parent] >= keys[n]:
            break
        keys[parent], keys[n] = keys[n], keys[parent]
        vals[parent], vals[n] = vals[n], vals[parent]
        n = parent


@njit(cache=True)
def heap_pop(keys, vals, cnt):
    """Remove the top of the max-heap; returns (key, val)."""
    key = keys[0]
    val = vals[0]
    n = cnt[CNT_HEAP] - 1
    cnt[CNT_HEAP] = n
    keys[0] = keys[n]
    vals[0] = vals[n]
    i = 0
    while True:
        left = 2 * i + 1
        if left >= n:
            break
        big = left
        if left + 1 < n and keys[left + 1] > keys[left]:
            big = left + 1
        if keys[i] >= keys[big]:
            break
        keys[i], keys[big] = keys[big], keys[i]
        vals[i], vals[big] = vals[big], vals[i]
        i = big
    return key, val


@njit(cache=True)
def heap_rebuild(keys, vals, cnt, status, height):
    """Rebuild the resin heap from every status-none cell (drops stale entries)."""
    cnt[CNT_HEAP] = 0
    for idx in range(status.size):
        if status[idx] == NONE:
            heap_push(keys, vals, cnt, height[idx], idx)


@njit(cache=True)
def refresh_candidate(status, cand, ncand, cell_bin, idx, n_angular):
    """Recompute the creation-candidate flag of cell idx (none, with a plateau directly east)."""
    i = idx % n_angular
    new = status[idx] == NONE and i + 1 < n_angular and status[idx + 1] != NONE
    if new != (cand[idx] != 0):
        cand[idx] = 1 if new else 0
        ncand[cell_bin[idx]] += 1 if new else -1


@njit(cache=True)
def rebuild_candidates(status, cand, ncand, cell_bin, n_angular):
    """Flag every creation candidate from scratch."""
    ncand[:] = 0
    for idx in range(status.size):
        cand[idx] = 0
        refresh_candidate(status, cand, ncand, cell_bin, idx, n_angular)


# --- the phases of a step --------------------------------------------------------------------
# `pk` is the tuple of packed plateau records, sorted by height (highest first), valid for the
# first cnt[CNT_PLATEAU] entries: (height [m], deposit base [m], area [m^2], full-step sliding
# distance [m], fibre floor [m], cell index, stream bin, status). During a stop the packed
# height and base of a plateau cell are authoritative; the grid arrays are written back by
# `sync_grid` at the end of every stop.
@njit(cache=True)
def phase_contact(pk, cnt, stiffness, mu_0, slope, mu_min, target, bar_length):
    """Step phase 1: sort the plateaus and solve the torque balance for z.

    Returns (z [m], n_in: plateaus in contact = leading packed records, error code)."""
    pk_h, pk_base, pk_area, pk_slide, pk_floor, pk_idx, pk_bin, pk_st = pk
    n_plat = cnt[CNT_PLATEAU]
    sort_packed(n_plat, pk_h, pk_base, pk_area, pk_slide, pk_floor, pk_idx, pk_bin, pk_st)
    z, n_in, code = first_root(pk_h, pk_area, n_plat, stiffness, mu_0, slope, mu_min, target)
    if code != SOLVE_OK:
        return z, n_in, ERR_NO_PLATEAU
    if pk_h[0] - z > bar_length:
        return z, n_in, ERR_BAR
    return z, n_in, OK


@njit(cache=True)
def phase_friction_wear(
    pk,
    n_in,
    outflow,
    acc,
    mark,
    z,
    stiffness,
    mu_0,
    slope,
    mu_min,
    wear_rate,
    frac,
    sums,
    destroyed,
    rule_counts,
):
    """Step phases 2, 3a and rules 5 and 7: friction of the plateaus in contact, their Archard
    wear, and the destruction of those worn down (marked in ``mark``, listed in ``destroyed``).

    Primary wear is new pad material (removed); wear of a secondary plateau moves volume from
    its deposit to the stream and is clipped at the deposit (rule 5 then fires).
    Returns the number of cells listed in ``destroyed``."""
    pk_h, pk_base, pk_area, pk_slide, pk_floor, pk_idx, pk_bin, pk_st = pk
    f_fric = 0.0
    f_norm = 0.0
    a_contact = 0.0
    removed = 0.0
    held_out = 0.0
    n_dest = 0
    for q in range(n_in):
        u = pk_h[q] - z
        if u <= 0.0:
            continue
        area = pk_area[q]
        p = stiffness * u
        mu = local_cof(p, mu_0, slope, mu_min)
        f_fric += mu * p * area
        f_norm += p * area
        a_contact += area
        dh = archard_wear_depth(wear_rate, p, pk_slide[q] * frac, u)
        s = pk_st[q]
        if s == SECONDARY:
            dep = pk_h[q] - pk_base[q]
            if dh >= dep:
                dh = dep
                pk_h[q] = pk_base[q]  # deposit used up
            else:
                pk_h[q] -= dh
            vol = dh * area
            outflow[pk_bin[q]] += vol
            held_out += vol
            fire = 5 if rule5_deposit_worn(s, pk_h[q], pk_base[q]) else 0
        else:
            pk_h[q] -= dh
            vol = dh * area
            outflow[pk_bin[q]] += vol
            removed += vol
            fire = 7 if rule7_fibre_worn(s, pk_h[q], pk_floor[q]) else 0
        if fire:
            idx = pk_idx[q]
            mark[idx] = fire
            destroyed[n_dest] = idx
            n_dest += 1
            rule_counts[fire] += 1
    acc[ACC_HELD] -= held_out
    sums[S_FRICTION] = f_fric
    sums[S_NORMAL] = f_norm
    sums[S_CONTACT] = a_contact
    sums[S_REMOVED] = removed
    return n_dest


@njit(cache=True)
def phase_resin(
    height, status, cell_area, cell_bin, outflow, heap_keys, heap_vals, cnt, z, resin_depth, sums
):
    """Step phase 3b: every status-none cell above the disc drops to ``z - WR``; the removed
    volume joins the stream of its row and subdomain."""
    removed = 0.0
    while cnt[CNT_HEAP] > 0 and heap_keys[0] > z:
        key, idx = heap_pop(heap_keys, heap_vals, cnt)
        if status[idx] != NONE or height[idx] != key:
            continue  # stale entry
        cut = resin_cut_depth(height[idx], z, resin_depth)
        vol = cut * cell_area[idx]
        height[idx] -= cut
        outflow[cell_bin[idx]] += vol
        removed += vol
        heap_push(heap_keys, heap_vals, cnt, height[idx], idx)
    sums[S_REMOVED] += removed


@njit(cache=True)
def phase_destruction(
    pk,
    n_in,
    cnt,
    status,
    mark,
    rule4_list,
    z,
    rule6_gap,
    n_angular,
    destroyed,
    n_dest,
    rule_counts,
):
    """Step phase 4a: rules 4 and 6 on the statuses at the start of the step (rules 5 and 7
    fired in :func:`phase_friction_wear`). Returns the number of cells now in ``destroyed``.

    Rule 4 is checked only on cells whose eastern neighbour lost its plateau status
    (``rule4_list``); rule 6, when switched on, on the primary plateaus out of contact."""
    for q in range(cnt[CNT_RULE4]):
        idx = rule4_list[q]
        if mark[idx] or not rule4_lost_support(status, idx, n_angular):
            continue
        mark[idx] = 4
        destroyed[n_dest] = idx
        n_dest += 1
        rule_counts[4] += 1
    cnt[CNT_RULE4] = 0
    if rule6_gap < math.inf:
        pk_h, pk_st, pk_idx = pk[0], pk[7], pk[5]
        for q in range(n_in, cnt[CNT_PLATEAU]):
            if rule6_primary_out_of_reach(pk_st[q], pk_h[q], z, rule6_gap):
                idx = pk_idx[q]
                mark[idx] = 6
                destroyed[n_dest] = idx
                n_dest += 1
                rule_counts[6] += 1
    return n_dest


@njit(cache=True)
def phase_creation(
    height,
    status,
    cand,
    ncand,
    cell_area,
    inflow,
    outflow,
    z,
    n_radial,
    n_angular,
    n_sub,
    east_to_west,
    created,
    rule_counts,
):
    """Step phase 4b: rules 1-3. Candidates of each row draw on the inflow of their row and
    subdomain in the order the particles meet them; what is not used passes on east.
    Returns the number of cells listed in ``created``."""
    n_m = n_angular // n_sub
    n_new = 0
    for j in range(n_radial):
        for k in range(1, n_sub):
            b = j * n_sub + k
            rest = inflow[b]
            if rest > 0.0 and ncand[b] > 0:
                i0 = j * n_angular + k * n_m
                for c in range(n_m):
                    idx = i0 + (n_m - 1 - c if east_to_west else c)
                    if cand[idx] == 0:
                        continue
                    cost = gap_fill_cost(z, height[idx], cell_area[idx])
                    if cost <= rest:
                        rest -= cost
                        created[n_new] = idx
                        n_new += 1
                        rule_counts[creation_rule(status, idx, n_radial, n_angular)] += 1
            outflow[b] += rest
    return n_new


@njit(cache=True)
def _copy_record(src, a, dst, b):
    dst[0][b] = src[0][a]
    dst[1][b] = src[1][a]
    dst[2][b] = src[2][a]
    dst[3][b] = src[3][a]
    dst[4][b] = src[4][a]
    dst[5][b] = src[5][a]
    dst[6][b] = src[6][a]
    dst[7][b] = src[7][a]


@njit(cache=True)
def phase_apply(
    pk,
    tail,
    n_in,
    cnt,
    height,
    base,
    status,
    fibre_floor,
    cand,
    ncand,
    cell_area,
    cell_slide,
    cell_bin,
    outflow,
    acc,
    mark,
    heap_keys,
    heap_vals,
    rule4_list,
    z,
    n_angular,
    destroyed,
    n_dest,
    created,
    n_new,
):
    """Apply the status changes of the step: destroyed cells become none (a secondary returns
    its deposit to the stream), created cells are filled to z and inserted in the packed
    records after the cells in contact; keep the resin heap, the candidate flags and the
    rule-4 list up to date. ``tail`` is scratch of the packed layout."""
    if n_dest == 0 and n_new == 0:
        return
    n_plat = cnt[CNT_PLATEAU]
    # move the records out of contact aside, compact the ones in contact in place
    n_tail = 0
    for q in range(n_in, n_plat):
        _copy_record(pk, q, tail, n_tail)
        n_tail += 1
    w = 0
    for q in range(n_in):
        if mark[pk[5][q]]:
            _destroy(pk, q, height, base, status, outflow, acc, heap_keys, heap_vals, cnt)
        else:
            if w != q:
                _copy_record(pk, q, pk, w)
            w += 1
    for c in range(n_new):
        idx = created[c]
        area = cell_area[idx]
        acc[ACC_HELD] += (z - height[idx]) * area
        acc[ACC_SECONDARY_AREA] += area
        base[idx] = height[idx]
        height[idx] = z
        status[idx] = SECONDARY
        pk[0][w] = z
        pk[1][w] = base[idx]
        pk[2][w] = area
        pk[3][w] = cell_slide[idx]
        pk[4][w] = fibre_floor[idx]
        pk[5][w] = idx
        pk[6][w] = cell_bin[idx]
        pk[7][w] = SECONDARY
        w += 1
    for q in range(n_tail):
        if mark[tail[5][q]]:
            _destroy(tail, q, height, base, status, outflow, acc, heap_keys, heap_vals, cnt)
        else:
            _copy_record(tail, q, pk, w)
            w += 1
    cnt[CNT_PLATEAU] = w
    for q in range(n_dest):
        idx = destroyed[q]
        mark[idx] = 0
        refresh_candidate(status, cand, ncand, cell_bin, idx, n_angular)
        if idx % n_angular > 0:
            refresh_candidate(status, cand, ncand, cell_bin, idx - 1, n_angular)
            rule4_list[cnt[CNT_RULE4]] = idx - 1
            cnt[CNT_RULE4] += 1
    for q in range(n_new):
        idx = created[q]
        refresh_candidate(status, cand, ncand, cell_bin, idx, n_angular)
        if idx % n_angular > 0:
            refresh_candidate(status, cand, ncand, cell_bin, idx - 1, n_angular)


@njit(cache=True)
def _destroy(rec, q, height, base, status, outflow, acc, heap_keys, heap_vals, cnt):
    """Destroy the plateau of packed record q: it becomes resin at its current height (a
    secondary returns its remaining deposit to the stream of its row and subdomain)."""
    idx = rec[5][q]
    area = rec[2][q]
    if rec[7][q] == SECONDARY:
        dep = (rec[0][q] - rec[1][q]) * area
        outflow[rec[6][q]] += dep
        acc[ACC_HELD] -= dep
        height[idx] = rec[1][q]
        acc[ACC_SECONDARY_AREA] -= area
    else:
        height[idx] = rec[0][q]
        acc[ACC_PRIMARY_AREA] -= area
    status[idx] = NONE
    heap_push(heap_keys, heap_vals, cnt, height[idx], idx)


@njit(cache=True)
def phase_advance(inflow, outflow, n_radial, n_sub):
    """Step phase 5: streams advance one subdomain; returns (emitted, volume in the streams)."""
    emitted = 0.0
    stream = 0.0
    for j in range(n_radial):
        b0 = j * n_sub
        emitted += outflow[b0 + n_sub - 1]
        for k in range(n_sub - 1, 0, -1):
            inflow[b0 + k] = outflow[b0 + k - 1]
            stream += inflow[b0 + k]
        inflow[b0] = 0.0
        for k in range(n_sub):
            outflow[b0 + k] = 0.0
    return emitted, stream


@njit(cache=True)
def held_volume(pk, cnt):
    """Volume held in secondary plateaus, summed from the packed records [m^3]."""
    pk_h, pk_base, pk_area, pk_st = pk[0], pk[1], pk[2], pk[7]
    held = 0.0
    for q in range(cnt[CNT_PLATEAU]):
        if pk_st[q] == SECONDARY:
            held += (pk_h[q] - pk_base[q]) * pk_area[q]
    return held


@njit(cache=True)
def sync_grid(pk, cnt, height, base):
    """Write the packed heights and deposit bases back to the grid arrays."""
    for q in range(cnt[CNT_PLATEAU]):
        idx = pk[5][q]
        height[idx] = pk[0][q]
        base[idx] = pk[1][q]


@njit(cache=True)
def pack_plateaus(
    order, n, pk, height, base, cell_area, cell_slide, fibre_floor, cell_bin, status, cnt
):
    """Fill the packed records from the grid for the plateau cells listed in ``order[:n]``."""
    for q in range(n):
        idx = order[q]
        pk[0][q] = height[idx]
        pk[1][q] = base[idx]
        pk[2][q] = cell_area[idx]
        pk[3][q] = cell_slide[idx]
        pk[4][q] = fibre_floor[idx]
        pk[5][q] = idx
        pk[6][q] = cell_bin[idx]
        pk[7][q] = status[idx]
    cnt[CNT_PLATEAU] = n


# --- one stop --------------------------------------------------------------------------------
@njit(cache=True)
def run_stop(
    pk,
    tail,
    height,
    base,
    status,
    fibre_floor,
    cand,
    ncand,
    mark,
    inflow,
    outflow,
    heap_keys,
    heap_vals,
    rule4_list,
    cnt,
    acc,
    cell_area,
    cell_slide,
    cell_bin,
    n_radial,
    n_angular,
    n_sub,
    stiffness,
    mu_0,
    slope,
    mu_min,
    wear_rate,
    resin_depth,
    rule6_gap,
    bar_length,
    east_to_west,
    targets,
    fraction,
    ledger_tol,
    ledger_every,
    rec,
    rule_counts,
    created,
    destroyed,
):
    """Run every step of one stop in place.

    Parameters
    ----------
    pk, tail : tuple of 8 arrays of n_cells
        Packed plateau records (height [m], deposit base [m], area [m^2], full-step sliding
        distance [m], fibre floor [m], cell index, stream bin, status), sorted by height in the
        first ``cnt[CNT_PLATEAU]`` entries; ``tail`` is scratch of the same layout.
    height, base, fibre_floor : float64[n_cells]
        Grid heights [m] (authoritative for status-none cells during the stop; plateau cells
        are written back at the end), deposit bases [m], fibre undersides [m].
    status, cand, mark : int8[n_cells]
        NONE / PRIMARY / SECONDARY; creation-candidate flag; destruction marks (scratch, 0).
    ncand : int64[n_radial * n_sub]
        Creation candidates per stream bin.
    inflow, outflow : float64[n_radial * n_sub]
        Particle volume that entered bin (j, k) this step, and the volume leaving it [m^3].
    heap_keys, heap_vals : float64[cap], int64[cap]
        Max-heap of (height, cell) of the status-none cells (stale entries allowed).
    rule4_list : int64[n_cells]
        Cells to check for rule 4 in the next step.
    cnt : int64[N_CNT]
        Counters (plateaus, heap entries, rule-4 entries).
    acc : float64[N_ACC]
        Run accumulators (removed, emitted, held, primary and secondary area).
    cell_area, cell_slide : float64[n_cells]
        Cell area [m^2] and full-step sliding distance [m].
    cell_bin : int64[n_cells]
        Stream bin ``j * n_sub + k`` of the cell.
    n_radial, n_angular, n_sub : int
        Grid shape and number of subdomains.
    stiffness, mu_0, slope, mu_min, wear_rate, resin_depth, rule6_gap, bar_length : float
        K [Pa/m], friction law [-, 1/Pa, -], WP [m^3/(N m)], WR [m], rule-6 gap [m] (inf: off),
        foundation bar length [m].
    east_to_west : bool
        Candidates draw on the inflow east to west instead of west to east.
    targets : float64[n_steps]
        Demanded friction force of the band in each step [N].
    fraction : float64[n_steps]
        Fraction of a full step slid in each step [-].
    ledger_tol : float
        Relative ledger residual that stops the run [-].
    ledger_every : int
        Sum the held volume from the state every this many steps (and on the last step); in
        between the incrementally tracked held volume is used.
    rec : float64[n_steps, N_REC]
        Per-step record (output).
    rule_counts : int64[8]
        Firings of rules 1..7 (index = rule number), accumulated.
    created, destroyed : int64[n_cells]
        Scratch lists.

    Returns
    -------
    code : int
        OK, or an error code.
    step : int
        Number of steps completed.
    """
    sums = np.zeros(N_SUMS)
    n_steps = fraction.size
    code = OK
    done = n_steps
    for step in range(n_steps):
        frac = fraction[step]
        z, n_in, code = phase_contact(
            pk, cnt, stiffness, mu_0, slope, mu_min, targets[step], bar_length
        )
        if code != OK:
            done = step
            break
        n_dest = phase_friction_wear(
            pk,
            n_in,
            outflow,
            acc,
            mark,
            z,
            stiffness,
            mu_0,
            slope,
            mu_min,
            wear_rate,
            frac,
            sums,
            destroyed,
            rule_counts,
        )
        phase_resin(
            height,
            status,
            cell_area,
            cell_bin,
            outflow,
            heap_keys,
            heap_vals,
            cnt,
            z,
            resin_depth,
            sums,
        )
        acc[ACC_REMOVED] += sums[S_REMOVED]
        n_dest = phase_destruction(
            pk,
            n_in,
            cnt,
            status,
            mark,
            rule4_list,
            z,
            rule6_gap,
            n_angular,
            destroyed,
            n_dest,
            rule_counts,
        )
        n_new = phase_creation(
            height,
            status,
            cand,
            ncand,
            cell_area,
            inflow,
            outflow,
            z,
            n_radial,
            n_angular,
            n_sub,
            east_to_west,
            created,
            rule_counts,
        )
        phase_apply(
            pk,
            tail,
            n_in,
            cnt,
            height,
            base,
            status,
            fibre_floor,
            cand,
            ncand,
            cell_area,
            cell_slide,
            cell_bin,
            outflow,
            acc,
            mark,
            heap_keys,
            heap_vals,
            rule4_list,
            z,
            n_angular,
            destroyed,
            n_dest,
            created,
            n_new,
        )
        if cnt[CNT_HEAP] > heap_keys.size - 2 * destroyed.size:
            heap_rebuild(heap_keys, heap_vals, cnt, status, height)
        emitted, stream = phase_advance(inflow, outflow, n_radial, n_sub)
        acc[ACC_EMITTED] += emitted
        if step % ledger_every == 0 or step == n_steps - 1:
            held = held_volume(pk, cnt)
        else:
            held = acc[ACC_HELD]
        total = acc[ACC_REMOVED]
        resid = total - (held + stream + acc[ACC_EMITTED])
        rel = abs(resid) / total if total > 0.0 else abs(resid)
        rec[step, R_COF] = sums[S_FRICTION] / sums[S_NORMAL] if sums[S_NORMAL] > 0.0 else 0.0
        rec[step, R_NORMAL] = sums[S_NORMAL]
        rec[step, R_FRICTION] = sums[S_FRICTION]
        rec[step, R_CONTACT_AREA] = sums[S_CONTACT]
        rec[step, R_PRIMARY_AREA] = acc[ACC_PRIMARY_AREA]
        rec[step, R_SECONDARY_AREA] = acc[ACC_SECONDARY_AREA]
        rec[step, R_EMITTED] = emitted
        rec[step, R_GENERATED] = sums[S_REMOVED]
        rec[step, R_LEDGER] = rel
        rec[step, R_DISC] = z
        rec[step, R_HELD] = held
        rec[step, R_STREAM] = stream
        rec[step, R_TARGET] = targets[step]
        if rel > ledger_tol:
            code = ERR_LEDGER
            done = step + 1
            break
    sync_grid(pk, cnt, height, base)
    return code, done


def empty_record(n_steps: int) -> np.ndarray:
    """A per-step record array for ``n_steps`` steps."""
    return np.zeros((n_steps, N_REC), dtype=np.float64)
