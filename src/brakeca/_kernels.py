"""Compiled step kernels (numba) and nothing else.

One call of :func:`run_stop` runs every time step of one stop, so Python overhead is paid per
stop, not per step. The physics lives in named functions of :mod:`brakeca.contact`,
:mod:`brakeca.friction`, :mod:`brakeca.wear` and :mod:`brakeca.automaton`; this module wires
them in the order of a step (decision, docs/model.md), one compiled function per phase:

1. :func:`phase_contact` -- contact solve on the sorted plateau records (first root of the
   torque balance) -> z;
   :func:`phase_rule4` -- rule 4 on the statuses at the start of the step (marks only);
2. + 3a. :func:`phase_friction_wear` -- friction and Archard wear of the plateaus in contact,
   rules 5 and 7; the surviving records in contact compacted and re-sorted;
   :func:`phase_tail` -- rules 4 and 6 on the records out of contact;
3b. :func:`phase_resin` -- the resin cut;
4b. :func:`phase_creation` -- rules 1-3 drawing on the inflow, gaps measured to this z;
    :func:`phase_apply` -- the status changes take effect;
5. :func:`phase_advance` -- the particle streams advance one subdomain; the last emits.

Rules 4-7 read the statuses as they were at the start of the step whichever phase evaluates
them, so evaluating rule 4 before the wear pass changes nothing (a cell that both loses its
support and wears through its deposit counts as rule 5, as before).

State arrays are flat (index ``j * n_angular + i``); per-cell constants (area, sliding distance,
stream bin ``j * n_sub + k``) are precomputed so hot loops do no integer division. Work per step
is proportional to the cells in contact plus the cells whose status changes, not to the grid:

* plateau cells are packed records ``pk`` sorted by height (highest first): height, deposit
  base, cell index, stream bin and status; area and sliding distance are read from per-bin
  tables (every cell of a row has the same). The wear pass drops the destroyed records in
  contact and insertion-sorts the survivors as it writes them back; :func:`phase_apply` then
  places the new records and the records out of contact after them (linear in the records
  plus the inversions), so the next step starts from sorted records;
* resin (status none) cells are kept in a max-heap by height, so the resin cut visits only the
  cells above the disc (stale heap entries are skipped: key != height or status != none);
* creation candidates (a none cell with a plateau directly east) are flagged and counted per
  stream bin, updated where statuses change;
* rule 4 is checked only on cells whose eastern neighbour lost its plateau status.

``fastmath`` stays off: results are bit-reproducible, and every floating-point operation is
done in the same order as in the first kernel, so the results are bit-identical to it
(``benchmarks/fingerprint.py``).
"""

from __future__ import annotations

import math
import platform

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from brakeca import _cachedir
from brakeca._jit import njit_noalloc
from brakeca._records import (  # the columns of the per-step record array `rec[step, :]`
    N_REC,
    R_COF,
    R_CONTACT_AREA,
    R_DISC,
    R_EMITTED,
    R_FRICTION,
    R_GENERATED,
    R_HELD,
    R_LEDGER,
    R_NORMAL,
    R_PRIMARY_AREA,
    R_SECONDARY_AREA,
    R_STREAM,
    R_TARGET,
)
from brakeca.automaton import (
    creation_rule,
    gap_fill_cost,
    rule4_lost_support,
    rule5_deposit_worn,
    rule6_primary_out_of_reach,
    rule7_fibre_worn,
)
from brakeca.contact import SOLVE_OK, first_root_binned
from brakeca.friction import local_cof
from brakeca.wear import archard_wear_depth, resin_cut_depth

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

NONE = 0
PRIMARY = 1
SECONDARY = 2
DEAD = 3  # status of a packed record out of contact destroyed in this step (scratch)

# fields of a packed plateau record (the tuple `pk`)
P_H = 0  # height [m]
P_BASE = 1  # deposit base [m]
P_IDX = 2  # cell index
P_BIN = 3  # stream bin
P_ST = 4  # status

# indices into the float accumulator array `acc`
ACC_REMOVED = 0  # pad material removed since the start of the run [m^3]
ACC_EMITTED = 1  # volume emitted since the start of the run [m^3]
ACC_HELD = 2  # volume held in secondary plateaus, tracked incrementally [m^3]
ACC_PRIMARY_AREA = 3  # area of primary plateaus [m^2]
ACC_SECONDARY_AREA = 4  # area of secondary plateaus [m^2]
N_ACC = 5

# indices into the int counter array `cnt`
CNT_PLATEAU = 0  # packed plateau records
CNT_HEAP = 1  # entries of the resin heap
CNT_RULE4 = 2  # entries of the rule-4 check list
CNT_SECONDARY = 3  # packed records of secondary plateaus
N_CNT = 4

# per-step scratch sums `sums`
S_FRICTION = 0
S_NORMAL = 1
S_CONTACT = 2
S_REMOVED = 3
N_SUMS = 4

# phases timed by run_stop (`prof[phase]`, in cycles of the CPU's time-stamp counter)
T_CONTACT = 0  # root scan
T_WEAR = 1  # rule-4 marks, friction, wear, rules 5 and 7, records in contact re-sorted; tail
T_RESIN = 2  # resin cut
T_CREATION = 3  # rules 1-3
T_APPLY = 4  # status changes, records out of contact, held-volume sum
T_REST = 5  # streams, ledger, per-step record
N_TIMED = 6
TIMED_PHASES = ("contact", "friction+wear", "resin", "creation", "apply", "streams+ledger")

# error codes
OK = 0
ERR_NO_PLATEAU = 1
ERR_BAR = 2
ERR_LEDGER = 3


#: x86 reads its time-stamp counter from user code; elsewhere (e.g. ARM, where LLVM's cycle
#: counter is a privileged register) the phase timers read 0.
_HAS_TSC = platform.machine().lower() in ("x86_64", "amd64", "i386", "i686")


@intrinsic
def _clock(typingctx):
    """The CPU's cycle counter (``llvm.readcyclecounter``): a few ns to read, for profiling;
    0 on CPUs without a counter that user code may read."""
    sig = types.int64()

    def codegen(context, builder, signature, args):
        if not _HAS_TSC:
            return ir.Constant(ir.IntType(64), 0)
        fnty = ir.FunctionType(ir.IntType(64), [])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.readcyclecounter")
        return builder.call(fn, [])

    return sig, codegen


# --- small data structures -------------------------------------------------------------------
def packed_records(n: int) -> tuple:
    """Empty packed plateau records for ``n`` cells (height, base, index, bin, status)."""
    return (
        np.zeros(n),
        np.zeros(n),
        np.zeros(n, dtype=np.int32),
        np.zeros(n, dtype=np.int32),
        np.zeros(n, dtype=np.int8),
    )


@njit_noalloc
def _put(dst, w, h, base, idx, bn, st):
    """Insertion-sort step: place a record at the end of ``dst[:w]`` (sorted, highest first)
    and move it up past every lower record (stable)."""
    dh, db, di, dn, ds = dst
    b = w - 1
    while b >= 0 and dh[b] < h:
        dh[b + 1] = dh[b]
        db[b + 1] = db[b]
        di[b + 1] = di[b]
        dn[b + 1] = dn[b]
        ds[b + 1] = ds[b]
        b -= 1
    dh[b + 1] = h
    db[b + 1] = base
    di[b + 1] = idx
    dn[b + 1] = bn
    ds[b + 1] = st


@njit_noalloc
def _put_at(dst, w, h, base, idx, bn, st):
    """Write a record at position ``w`` of ``dst``."""
    dst[P_H][w] = h
    dst[P_BASE][w] = base
    dst[P_IDX][w] = idx
    dst[P_BIN][w] = bn
    dst[P_ST][w] = st


@njit_noalloc
def _put_sorted(dst, w, h, base, idx, bn, st):
    """Append a record at position ``w`` of ``dst`` and insertion-sort it into ``dst[:w]``."""
    if w > 0 and dst[P_H][w - 1] < h:
        _put(dst, w, h, base, idx, bn, st)
    else:
        _put_at(dst, w, h, base, idx, bn, st)


@njit_noalloc
def heap_sift_up(keys, vals, i):
    """Move entry i of a max-heap (``keys``, ``vals``) up to its place."""
    key = keys[i]
    val = vals[i]
    while i > 0:
        parent = (i - 1) >> 1
        if keys[parent] >= key:
            break
        keys[i] = keys[parent]
        vals[i] = vals[parent]
        i = parent
    keys[i] = key
    vals[i] = val


@njit_noalloc
def heap_sift_down(keys, vals, i, n):
    """Move entry i of a max-heap of n entries (``keys``, ``vals``) down to its place."""
    key = keys[i]
    val = vals[i]
    while True:
        left = 2 * i + 1
        if left >= n:
            break
        big = left
        if left + 1 < n and keys[left + 1] > keys[left]:
            big = left + 1
        if key >= keys[big]:
            break
        keys[i] = keys[big]
        vals[i] = vals[big]
        i = big
    keys[i] = key
    vals[i] = val


@njit_noalloc
def heap_push(keys, vals, cnt, key, val):
    """Push (key, val) on the max-heap held in ``keys[:cnt[CNT_HEAP]]``."""
    n = cnt[CNT_HEAP]
    keys[n] = key
    vals[n] = val
    cnt[CNT_HEAP] = n + 1
    heap_sift_up(keys, vals, n)


@njit_noalloc
def heap_pop(keys, vals, cnt):
    """Remove the top of the max-heap; returns (key, val)."""
    key = keys[0]
    val = vals[0]
    n = cnt[CNT_HEAP] - 1
    cnt[CNT_HEAP] = n
    keys[0] = keys[n]
    vals[0] = vals[n]
    heap_sift_down(keys, vals, 0, n)
    return key, val


@njit_noalloc
def heap_rebuild(keys, vals, cnt, status, height):
    """Rebuild the resin heap from every status-none cell (drops stale entries)."""
    cnt[CNT_HEAP] = 0
    for idx in range(status.size):
        if status[idx] == NONE:
            heap_push(keys, vals, cnt, height[idx], idx)


@njit_noalloc
def refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular):
    """Recompute the creation-candidate flag of cell idx (none, with a plateau directly east);
    keep ``cmax`` of its stream bin at or above the height of every candidate of the bin."""
    i = idx % n_angular
    new = status[idx] == NONE and i + 1 < n_angular and status[idx + 1] != NONE
    b = cell_bin[idx]
    if new != (cand[idx] != 0):
        cand[idx] = 1 if new else 0
        ncand[b] += 1 if new else -1
    if new and height[idx] > cmax[b]:
        cmax[b] = height[idx]


@njit_noalloc
def rebuild_candidates(status, height, cand, ncand, cmax, cell_bin, n_angular):
    """Flag every creation candidate from scratch."""
    ncand[:] = 0
    cmax[:] = -math.inf
    for idx in range(status.size):
        cand[idx] = 0
        refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular)


# --- the phases of a step --------------------------------------------------------------------
# `pk` is the tuple of packed plateau records (height [m], deposit base [m], cell index, stream
# bin, status), valid for the first cnt[CNT_PLATEAU] entries, sorted by height (highest first)
# at the start of every step. During a stop the packed height of a plateau cell is
# authoritative; the grid heights are written back by `sync_grid` at the end of every stop.
@njit_noalloc
def phase_contact(pk, cnt, bin_area, stiffness, mu_0, slope, mu_min, target, bar_length):
    """Step phase 1b: solve the torque balance for z on the sorted records.

    Returns (z [m], n_in: plateaus in contact = leading packed records, error code)."""
    pk_h = pk[P_H]
    z, n_in, code = first_root_binned(
        pk_h, pk[P_BIN], bin_area, cnt[CNT_PLATEAU], stiffness, mu_0, slope, mu_min, target
    )
    if code != SOLVE_OK:
        return z, n_in, ERR_NO_PLATEAU
    if pk_h[0] - z > bar_length:
        return z, n_in, ERR_BAR
    return z, n_in, OK


@njit_noalloc
def phase_rule4(cnt, status, mark, rule4_list, n_angular, rule_counts):
    """Rule 4 on the statuses at the start of the step, checked only on cells whose eastern
    neighbour lost its plateau status (``rule4_list``): marks them (``mark = 4``). Returns the
    number marked; :func:`phase_friction_wear` and :func:`phase_tail` find their records."""
    n4 = 0
    for q in range(cnt[CNT_RULE4]):
        idx = rule4_list[q]
        if mark[idx] or not rule4_lost_support(status, idx, n_angular):
            continue
        mark[idx] = 4
        rule_counts[4] += 1
        n4 += 1
    cnt[CNT_RULE4] = 0
    return n4


@njit_noalloc
def phase_friction_wear(
    pk,
    n_in,
    bin_area,
    bin_slide,
    fibre_floor,
    rule7_on,
    outflow,
    acc,
    mark,
    n4,
    z,
    stiffness,
    mu_0,
    slope,
    mu_min,
    wear_rate,
    frac,
    sums,
    destroyed,
    gone,
    rule_counts,
):
    """Step phases 2, 3a and rules 5 and 7: friction of the plateaus in contact, their Archard
    wear, and the destruction of those worn down; also finds the records in contact that rule
    4 marked.

    The same pass keeps the packed records of the cells in contact ready for the next step:
    the survivors are compacted to the front and insertion-sorted by their new heights (the
    destroyed ones are listed in ``destroyed`` and their records copied to ``gone``), and the
    volume held by the surviving secondary plateaus is summed in record order.

    Primary wear is new pad material (removed); wear of a secondary plateau moves volume from
    its deposit to the stream and is clipped at the deposit (rule 5 then fires; rule 5 takes
    precedence over rule 4).

    Returns
    -------
    n_gone : int
        Records destroyed (listed in ``destroyed`` and ``gone``).
    w : int
        Surviving records, now in ``pk[:w]``.
    held : float
        Volume held by the surviving secondary plateaus [m^3].
    n_sec : int
        Surviving secondary plateaus.
    left4 : int
        Rule-4 marks not found among the cells in contact.
    """
    pk_h, pk_base, pk_idx, pk_bin, pk_st = pk
    f_fric = 0.0
    f_norm = 0.0
    a_contact = 0.0
    removed = 0.0
    held_out = 0.0
    held = 0.0
    n_gone = 0
    n_sec = 0
    w = 0
    left4 = n4
    for q in range(n_in):
        fire = 0
        h = pk_h[q]
        hb = pk_base[q]
        bn = pk_bin[q]
        s = pk_st[q]
        idx = pk_idx[q]
        u = h - z
        if u > 0.0:
            area = bin_area[bn]
            p = stiffness * u
            mu = local_cof(p, mu_0, slope, mu_min)
            f_fric += mu * p * area
            f_norm += p * area
            a_contact += area
            dh = archard_wear_depth(wear_rate, p, bin_slide[bn] * frac, u)
            if s == SECONDARY:
                dep = h - hb
                if dh >= dep:
                    dh = dep
                    h = hb  # deposit used up
                else:
                    h -= dh
                vol = dh * area
                outflow[bn] += vol
                held_out += vol
                if rule5_deposit_worn(s, h, hb):
                    fire = 5
            else:
                h -= dh
                vol = dh * area
                outflow[bn] += vol
                removed += vol
                if rule7_on and rule7_fibre_worn(s, h, fibre_floor[idx]):
                    fire = 7
        if fire or (left4 and s == SECONDARY):
            m = mark[idx]
            if m == 4:
                left4 -= 1
                if fire:
                    rule_counts[4] -= 1  # worn through: counted as rule 5
            if fire:
                mark[idx] = fire
                rule_counts[fire] += 1
            if fire or m == 4:
                destroyed[n_gone] = idx
                _put_at(gone, n_gone, h, hb, idx, bn, s)
                n_gone += 1
                continue
        if s == SECONDARY:
            held += (h - hb) * bin_area[bn]
            n_sec += 1
        if w == q and (w == 0 or pk_h[w - 1] >= h):
            pk_h[q] = h  # in place and in order: only the height changed
        else:
            _put_sorted(pk, w, h, hb, idx, bn, s)
        w += 1
    acc[ACC_HELD] -= held_out
    sums[S_FRICTION] = f_fric
    sums[S_NORMAL] = f_norm
    sums[S_CONTACT] = a_contact
    sums[S_REMOVED] = removed
    return n_gone, w, held, n_sec, left4


@njit_noalloc
def phase_tail(pk, n_in, cnt, mark, left4, z, rule6_gap, destroyed, dpos, n_dest, rule_counts):
    """Rules 4 and 6 on the records out of contact: find the records of the rule-4 marks not
    found in contact, and apply rule 6 (when switched on) to the primary plateaus. Returns the
    number of cells now listed in ``destroyed``."""
    if left4 == 0 and not rule6_gap < math.inf:
        return n_dest
    pk_h, pk_idx, pk_st = pk[P_H], pk[P_IDX], pk[P_ST]
    for q in range(n_in, cnt[CNT_PLATEAU]):
        s = pk_st[q]
        if s == SECONDARY and left4:
            idx = pk_idx[q]
            if mark[idx] == 4:
                left4 -= 1
                destroyed[n_dest] = idx
                dpos[n_dest] = q
                n_dest += 1
        elif rule6_primary_out_of_reach(s, pk_h[q], z, rule6_gap):
            idx = pk_idx[q]
            mark[idx] = 6
            destroyed[n_dest] = idx
            dpos[n_dest] = q
            n_dest += 1
            rule_counts[6] += 1
        if left4 == 0 and not rule6_gap < math.inf:
            break
    return n_dest


@njit_noalloc
def phase_resin(
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
    field_on,
    field_top,
    field_bottom,
    field_end,
    field_next,
    cand,
    ncand,
    exposed,
):
    """Step phase 3b: every status-none cell above the disc drops to ``z - WR``; the removed
    volume joins the stream of its row and subdomain.

    With the fibre field (``field_on``), a cut that would go below the top of the next buried
    fibre under the cell stops at that top, and the cell is listed in ``exposed`` to become a
    primary plateau at the end of the step (:func:`phase_expose`); it is no creation
    candidate in this step. Returns the number of cells listed."""
    removed = 0.0
    n_exp = 0
    while cnt[CNT_HEAP] > 0 and heap_keys[0] > z:
        key, idx = heap_pop(heap_keys, heap_vals, cnt)
        if status[idx] != NONE or height[idx] != key:
            continue  # stale entry
        cut = resin_cut_depth(height[idx], z, resin_depth)
        if field_on:
            k = field_next[idx]
            h = height[idx]
            if k < field_end[idx] and field_top[k] >= z - resin_depth and field_bottom[k] < h:
                top = min(h, field_top[k])
                vol = (h - top) * cell_area[idx]
                height[idx] = top
                outflow[cell_bin[idx]] += vol
                removed += vol
                exposed[n_exp] = idx
                n_exp += 1
                if cand[idx] != 0:
                    cand[idx] = 0
                    ncand[cell_bin[idx]] -= 1
                continue
        vol = cut * cell_area[idx]
        height[idx] -= cut
        outflow[cell_bin[idx]] += vol
        removed += vol
        heap_push(heap_keys, heap_vals, cnt, height[idx], idx)
    sums[S_REMOVED] += removed
    return n_exp


@njit_noalloc
def phase_expose(
    pk,
    cnt,
    height,
    base,
    status,
    fibre_floor,
    cand,
    ncand,
    cmax,
    cell_area,
    cell_bin,
    acc,
    field_bottom,
    field_next,
    exposed,
    n_exp,
    n_angular,
    rule_counts,
):
    """End of step, with the fibre field: the cells the resin cut exposed (``exposed[:n_exp]``,
    each at the top of its next buried fibre) become primary plateaus with that fibre's
    underside as their floor; each record is insertion-sorted into the packed records, and
    the creation candidates around the cell are refreshed. Counted in ``rule_counts[0]``."""
    for q in range(n_exp):
        idx = exposed[q]
        k = field_next[idx]
        h = height[idx]
        status[idx] = PRIMARY
        base[idx] = h
        fibre_floor[idx] = field_bottom[k]
        field_next[idx] = k + 1
        acc[ACC_PRIMARY_AREA] += cell_area[idx]
        _put(pk, cnt[CNT_PLATEAU], h, h, idx, cell_bin[idx], PRIMARY)
        cnt[CNT_PLATEAU] += 1
        refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular)
        if idx % n_angular > 0:
            refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx - 1, n_angular)
    rule_counts[0] += n_exp


@njit_noalloc
def phase_creation(
    height,
    status,
    cand,
    ncand,
    cmax,
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

    A bin is not scanned when even its highest candidate (``cmax``, an upper bound) costs more
    than the inflow: no candidate could be filled, exactly as if it were scanned. A scan
    leaves ``cmax`` at the highest candidate that was not filled.
    Returns the number of cells listed in ``created``."""
    n_m = n_angular // n_sub
    n_new = 0
    for j in range(n_radial):
        for k in range(1, n_sub):
            b = j * n_sub + k
            rest = inflow[b]
            i0 = j * n_angular + k * n_m
            area = cell_area[i0]  # one area per row (the grid's cell areas are per radius)
            if rest > 0.0 and ncand[b] > 0 and gap_fill_cost(z, cmax[b], area) <= rest:
                top = -math.inf
                left = ncand[b]  # the bin's candidates not met yet: none after the last
                for c in range(n_m):
                    idx = i0 + (n_m - 1 - c if east_to_west else c)
                    if cand[idx] == 0:
                        continue
                    left -= 1
                    cost = gap_fill_cost(z, height[idx], area)
                    if cost <= rest:
                        rest -= cost
                        created[n_new] = idx
                        n_new += 1
                        rule_counts[creation_rule(status, idx, n_radial, n_angular)] += 1
                    elif height[idx] > top:
                        top = height[idx]
                    if left == 0:
                        break
                cmax[b] = top
            outflow[b] += rest
    return n_new


@njit_noalloc
def _destroy(rec, q, bin_area, height, status, outflow, acc, heap_keys, heap_vals, cnt):
    """Destroy the plateau of packed record q of ``rec``: it becomes resin at its current
    height (a secondary returns its remaining deposit to the stream of its row and
    subdomain); the record is marked dead."""
    idx = rec[P_IDX][q]
    bn = rec[P_BIN][q]
    area = bin_area[bn]
    if rec[P_ST][q] == SECONDARY:
        dep = (rec[P_H][q] - rec[P_BASE][q]) * area
        outflow[bn] += dep
        acc[ACC_HELD] -= dep
        height[idx] = rec[P_BASE][q]
        acc[ACC_SECONDARY_AREA] -= area
        cnt[CNT_SECONDARY] -= 1
    else:
        height[idx] = rec[P_H][q]
        acc[ACC_PRIMARY_AREA] -= area
    status[idx] = NONE
    rec[P_ST][q] = DEAD
    heap_push(heap_keys, heap_vals, cnt, height[idx], idx)


@njit_noalloc
def _tail_in_order(pk, lo, hi):
    """Insertion steps for the records ``pk[lo:hi]``, which are sorted among themselves: stop
    at the first that stays where it is (none after it would move)."""
    pk_h = pk[P_H]
    for r in range(lo, hi):
        if r == 0 or pk_h[r - 1] >= pk_h[r]:
            return
        _put(pk, r, pk_h[r], pk[P_BASE][r], pk[P_IDX][r], pk[P_BIN][r], pk[P_ST][r])


@njit_noalloc
def phase_apply(
    pk,
    gone,
    n_gone,
    w,
    n_in,
    cnt,
    bin_area,
    height,
    base,
    status,
    cand,
    ncand,
    cmax,
    cell_area,
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
    dpos,
    n_dest,
    created,
    n_new,
    held,
    n_sec,
    need_held,
):
    """Apply the status changes of the step, in record order: destroyed cells become none (a
    secondary returns its deposit to the stream); created cells are filled to z. Keeps the
    resin heap, the candidate flags and the rule-4 list up to date.

    The packed records end in the order of the next step: the survivors in contact
    (``pk[:w]``, already sorted by :func:`phase_friction_wear`), the new records, then the
    surviving records out of contact, each insertion-sorted in. With ``need_held`` the volume
    held in secondary plateaus is summed on from ``held`` in that order; returns it [m^3].

    ``gone[:n_gone]`` are the destroyed records in contact, ``dpos[n_gone:n_dest]`` the
    positions of those out of contact (increasing)."""
    for k in range(n_gone):
        _destroy(gone, k, bin_area, height, status, outflow, acc, heap_keys, heap_vals, cnt)
    for c in range(n_new):
        idx = created[c]
        area = cell_area[idx]
        acc[ACC_HELD] += (z - height[idx]) * area
        acc[ACC_SECONDARY_AREA] += area
        base[idx] = height[idx]
        height[idx] = z
        status[idx] = SECONDARY
    cnt[CNT_SECONDARY] += n_new
    for k in range(n_gone, n_dest):
        _destroy(pk, dpos[k], bin_area, height, status, outflow, acc, heap_keys, heap_vals, cnt)
    # the records out of contact: drop the dead ones, make room for the new ones
    pk_h, pk_base, pk_idx, pk_bin, pk_st = pk
    n_plat = cnt[CNT_PLATEAU]
    t0 = w + n_new  # where the records out of contact start
    tail_dead = n_dest > n_gone
    if t0 > n_in:
        if tail_dead:
            t = n_in
            for r in range(n_in, n_plat):
                if pk_st[r] != DEAD:
                    _put_at(pk, t, pk_h[r], pk_base[r], pk_idx[r], pk_bin[r], pk_st[r])
                    t += 1
            n_plat = t
        shift = t0 - n_in
        for r in range(n_plat - 1, n_in - 1, -1):
            _put_at(pk, r + shift, pk_h[r], pk_base[r], pk_idx[r], pk_bin[r], pk_st[r])
        n_plat += shift
        tail_dead = False
    for c in range(n_new):
        idx = created[c]
        _put_sorted(pk, w + c, z, base[idx], idx, cell_bin[idx], SECONDARY)
        if need_held:
            held += (z - base[idx]) * cell_area[idx]
    if t0 < n_in or tail_dead:
        t = t0
        for r in range(n_in, n_plat):
            s = pk_st[r]
            if s != DEAD:
                if need_held and s == SECONDARY:
                    held += (pk_h[r] - pk_base[r]) * bin_area[pk_bin[r]]
                _put_sorted(pk, t, pk_h[r], pk_base[r], pk_idx[r], pk_bin[r], s)
                t += 1
        cnt[CNT_PLATEAU] = t
    else:
        # the records out of contact are in place, at [t0, n_plat)
        if need_held and cnt[CNT_SECONDARY] > n_sec + n_new:
            for r in range(t0, n_plat):
                if pk_st[r] == SECONDARY:
                    held += (pk_h[r] - pk_base[r]) * bin_area[pk_bin[r]]
        _tail_in_order(pk, t0, n_plat)
        cnt[CNT_PLATEAU] = n_plat
    for q in range(n_dest):
        idx = destroyed[q]
        mark[idx] = 0
        refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular)
        if idx % n_angular > 0:
            refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx - 1, n_angular)
            rule4_list[cnt[CNT_RULE4]] = idx - 1
            cnt[CNT_RULE4] += 1
    for q in range(n_new):
        idx = created[q]
        refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular)
        if idx % n_angular > 0:
            refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx - 1, n_angular)
    return held


@njit_noalloc
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


@njit_noalloc
def sync_grid(pk, cnt, height, base):
    """Write the packed heights and deposit bases back to the grid arrays."""
    for q in range(cnt[CNT_PLATEAU]):
        idx = pk[P_IDX][q]
        height[idx] = pk[P_H][q]
        base[idx] = pk[P_BASE][q]


@njit_noalloc
def pack_plateaus(order, n, pk, height, base, cell_bin, status, cnt):
    """Fill the packed records from the grid for the plateau cells listed in ``order[:n]``."""
    n_sec = 0
    for q in range(n):
        idx = order[q]
        _put_at(pk, q, height[idx], base[idx], idx, cell_bin[idx], status[idx])
        if status[idx] == SECONDARY:
            n_sec += 1
    cnt[CNT_PLATEAU] = n
    cnt[CNT_SECONDARY] = n_sec


@njit_noalloc
def record_step(rec, step, sums, acc, emitted, held, stream, z, target):
    """Write step ``step`` of the per-step record and return the relative ledger residual
    ``|removed - (held + streams + emitted)| / removed`` (shared by both step kernels)."""
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
    rec[step, R_TARGET] = target
    return rel


# --- one stop --------------------------------------------------------------------------------
@njit(cache=True)
def run_stop(
    pk,
    gone,
    height,
    base,
    status,
    fibre_floor,
    cand,
    ncand,
    cmax,
    mark,
    inflow,
    outflow,
    heap_keys,
    heap_vals,
    rule4_list,
    cnt,
    acc,
    cell_area,
    cell_bin,
    bin_area,
    bin_slide,
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
    rule7_on,
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
    dpos,
    prof,
    field_on,
    field_top,
    field_bottom,
    field_end,
    field_next,
    exposed,
):
    """Run every step of one stop in place.

    Parameters
    ----------
    pk, gone : tuple of 5 arrays of n_cells
        Packed plateau records (height [m], deposit base [m], cell index, stream bin, status),
        sorted by height in the first ``cnt[CNT_PLATEAU]`` entries of ``pk``; ``gone`` is
        scratch of the same layout (the records destroyed in a step).
    height, base, fibre_floor : float64[n_cells]
        Grid heights [m] (authoritative for status-none cells during the stop; plateau cells
        are written back at the end), deposit bases [m], fibre undersides [m].
    status, cand, mark : int8[n_cells]
        NONE / PRIMARY / SECONDARY; creation-candidate flag; destruction marks (scratch, 0).
    ncand : int64[n_radial * n_sub]
        Creation candidates per stream bin.
    cmax : float64[n_radial * n_sub]
        Upper bound of the candidates' heights per stream bin [m].
    inflow, outflow : float64[n_radial * n_sub]
        Particle volume that entered bin (j, k) this step, and the volume leaving it [m^3].
    heap_keys, heap_vals : float64[cap], int64[cap]
        Max-heap of (height, cell) of the status-none cells (stale entries allowed).
    rule4_list : int64[n_cells]
        Cells to check for rule 4 in the next step.
    cnt : int64[N_CNT]
        Counters (plateaus, heap entries, rule-4 entries, secondary plateaus).
    acc : float64[N_ACC]
        Run accumulators (removed, emitted, held, primary and secondary area).
    cell_area : float64[n_cells]
        Cell area [m^2].
    cell_bin : int64[n_cells]
        Stream bin ``j * n_sub + k`` of the cell.
    bin_area, bin_slide : float64[n_radial * n_sub]
        Cell area [m^2] and full-step sliding distance [m] of the cells of a stream bin.
    n_radial, n_angular, n_sub : int
        Grid shape and number of subdomains.
    stiffness, mu_0, slope, mu_min, wear_rate, resin_depth, rule6_gap, bar_length : float
        K [Pa/m], friction law [-, 1/Pa, -], WP [m^3/(N m)], WR [m], rule-6 gap [m] (inf: off),
        foundation bar length [m].
    rule7_on : bool
        Some fibre has a finite underside (the layer fibre model), so rule 7 can fire.
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
    created, destroyed, dpos : int64[n_cells]
        Scratch lists (created cells, destroyed cells, positions of their records).
    prof : int64[N_TIMED]
        Cycles spent in each phase (``TIMED_PHASES``), accumulated; reading the counter costs
        a few ns per phase and step. Stays 0 on CPUs without a user-readable cycle counter.
    field_on : bool
        The fibre field is on (``pad.fibre_model = "field"``): the resin cut stops at buried
        fibres and exposes them (:func:`phase_resin`, :func:`phase_expose`).
    field_top, field_bottom : float64[n_intervals]
        The field's intervals [m] (:class:`brakeca.surface.FibreField`; empty without it).
    field_end, field_next : int64[n_cells]
        One past each cell's last interval, and its next interval below the surface (the
        latter advanced in place).
    exposed : int64[n_cells]
        Scratch list of the cells exposed in a step.

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
        t0 = _clock()
        z, n_in, code = phase_contact(
            pk, cnt, bin_area, stiffness, mu_0, slope, mu_min, targets[step], bar_length
        )
        if code != OK:
            done = step
            break
        t1 = _clock()
        prof[T_CONTACT] += t1 - t0
        n4 = phase_rule4(cnt, status, mark, rule4_list, n_angular, rule_counts)
        n_gone, w, held, n_sec, left4 = phase_friction_wear(
            pk,
            n_in,
            bin_area,
            bin_slide,
            fibre_floor,
            rule7_on,
            outflow,
            acc,
            mark,
            n4,
            z,
            stiffness,
            mu_0,
            slope,
            mu_min,
            wear_rate,
            frac,
            sums,
            destroyed,
            gone,
            rule_counts,
        )
        n_dest = phase_tail(
            pk, n_in, cnt, mark, left4, z, rule6_gap, destroyed, dpos, n_gone, rule_counts
        )
        t2 = _clock()
        prof[T_WEAR] += t2 - t1
        n_exp = phase_resin(
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
            field_on,
            field_top,
            field_bottom,
            field_end,
            field_next,
            cand,
            ncand,
            exposed,
        )
        acc[ACC_REMOVED] += sums[S_REMOVED]
        t3 = _clock()
        prof[T_RESIN] += t3 - t2
        n_new = phase_creation(
            height,
            status,
            cand,
            ncand,
            cmax,
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
        t4 = _clock()
        prof[T_CREATION] += t4 - t3
        need_held = step % ledger_every == 0 or step == n_steps - 1
        held = phase_apply(
            pk,
            gone,
            n_gone,
            w,
            n_in,
            cnt,
            bin_area,
            height,
            base,
            status,
            cand,
            ncand,
            cmax,
            cell_area,
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
            dpos,
            n_dest,
            created,
            n_new,
            held,
            n_sec,
            need_held,
        )
        if n_exp > 0:
            phase_expose(
                pk,
                cnt,
                height,
                base,
                status,
                fibre_floor,
                cand,
                ncand,
                cmax,
                cell_area,
                cell_bin,
                acc,
                field_bottom,
                field_next,
                exposed,
                n_exp,
                n_angular,
                rule_counts,
            )
        t5 = _clock()
        prof[T_APPLY] += t5 - t4
        if cnt[CNT_HEAP] > heap_keys.size - 2 * destroyed.size:
            heap_rebuild(heap_keys, heap_vals, cnt, status, height)
        emitted, stream = phase_advance(inflow, outflow, n_radial, n_sub)
        acc[ACC_EMITTED] += emitted
        if not need_held:
            held = acc[ACC_HELD]
        rel = record_step(rec, step, sums, acc, emitted, held, stream, z, targets[step])
        prof[T_REST] += _clock() - t5
        if rel > ledger_tol:
            code = ERR_LEDGER
            done = step + 1
            break
    sync_grid(pk, cnt, height, base)
    return code, done


def empty_record(n_steps: int) -> np.ndarray:
    """A per-step record array for ``n_steps`` steps."""
    return np.zeros((n_steps, N_REC), dtype=np.float64)
