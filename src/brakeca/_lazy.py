"""The lazy compiled stop kernel (numba): the same step as :mod:`brakeca._kernels`, with work
per step proportional to the rows and to the cells that change, not to the cells in contact.

Why it is fast
--------------
Archard wear of a plateau cell in contact is affine in its height, ``h' = z + beta_j (h - z)``
with ``beta_j = 1 - WP K s_j f`` the same for every cell of row ``j``. So the kernel keeps, per
row, the cells in contact in *raw* coordinates ``r`` with ``h = a_j r + c_j`` and wears the
whole row by updating ``(a_j, c_j)`` (two multiplications), never touching the cells. Sums of
``r`` and ``r^2`` over the cells of a row (split where the contact law changes branch) and over
the cells of each stream bin give the friction force, its derivatives and the wear volume per
bin in O(rows) per step. Per row:

* the cells in contact form an array sorted by height (highest first), the cells out of contact
  a second array sorted the other way; a cell crosses the contact edge by moving from the end
  of one to the end of the other, so neither array is ever re-sorted (the in-contact cells keep
  their order under the common affine map, and all of them stay above the disc);
* during a contact solve the edge is an index ``ke`` into the in-contact array: a cell the edge
  passes on the way up stays in the array, out of the segment sums, and comes back by moving
  the index; only the cells still past the edge at the root are moved out
  (:func:`_commit_row`). The solve climbs to the envelope's root and walks back down to F's
  first root, so the cells between the two cross twice per step; moving them costs a few sums
  this way instead of two array moves each;
* four partition indices split the cells in contact where ``u = h - z`` crosses ``u_c``,
  ``u_f``, ``u*`` (:mod:`brakeca.contact`); segment sums are kept as the indices move;
* rule 5 (a secondary plateau worn through its deposit: ``a r + c <= b``) is detected with a
  kinetic tournament tree over the row's secondary plateaus in contact: each is the line
  ``r a - b`` in the row's decreasing scale ``a``, and the tree keeps the lowest line and the
  value of ``a`` at which that changes;
* a destroyed plateau leaves a tombstone in its array (dropped when it reaches the end).

The torque-controlled contact root is the first root of ``F(z) = T`` as the approach grows
(docs/model.md), found without a global sort: the running-maximum envelope ``F_hat`` of the
friction law (``mu p`` held at its peak from ``p*`` until the floor branch climbs past it) is
monotone and ``F <= F_hat``, so its first root ``z_hat`` (a bracketed quadratic iteration on the
segment sums) has no root of ``F`` before it. Where no cell sits in the window ``(u*, u_c)``,
``F = F_hat`` at ``z_hat`` and that is the root; otherwise the breakpoints of ``F`` are walked
from ``z_hat`` until the quadratic between two of them reaches the target. The root is the same
as the exact scan's, to round-off.

Results therefore equal the exact kernel's to round-off per operation, not bit for bit; the
rules compare heights and volumes with thresholds, so individual cells diverge over a run, and
the agreement is statistical (docs/model.md, "The lazy kernel"). Layer fibres (rule 7) and rule
6 are not supported here: :func:`supports` tells, and the simulation then uses the exact kernel.

The resin cut works row by row: each row keeps its resin cells as entries sorted by height (a
few hundred entries, so a cut touches a few cache lines instead of climbing a heap of the whole
grid). Cells are cut highest first, and every cell of a row has the same area, so cells of a
row at one height cut the same volume and each stream bin's sum is bit-identical to what one
heap of the whole grid gives; only the step's total generated volume is summed in another
order (it enters the ledger and the per-step record, not the state). The cells cut in a step
share their new height and go back as one block (:func:`_resin_cut`).

State between stops is the grid alone (heights, bases, statuses, streams, and the candidate
flags and rule-4 list the kernels share); the row structures and resin entries are rebuilt from
the grid at the start of every stop, so a checkpoint taken between stops resumes
bit-identically.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from brakeca import _cachedir
from brakeca._jit import njit_noalloc, njit_noalloc_inline, prefetch
from brakeca._kernels import (
    ACC_EMITTED,
    ACC_HELD,
    ACC_REMOVED,
    ACC_SECONDARY_AREA,
    CNT_RULE4,
    CNT_SECONDARY,
    ERR_BAR,
    ERR_LEDGER,
    ERR_NO_PLATEAU,
    N_SUMS,
    NONE,
    OK,
    S_CONTACT,
    S_FRICTION,
    S_NORMAL,
    S_REMOVED,
    SECONDARY,
    T_APPLY,
    T_CONTACT,
    T_CREATION,
    T_RESIN,
    T_REST,
    T_WEAR,
    _clock,
    phase_advance,
    phase_creation,
    record_step,
    refresh_candidate,
)
from brakeca.automaton import rule4_lost_support
from brakeca.contact import SOLVE_OK, first_root_binned
from brakeca.wear import resin_cut_depth

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

# where a cell is held during a stop
W_NONE = 0
W_IN = 1  # in the row's in-contact array
W_OUT = 2  # in the row's out-of-contact array

# segments of a row's in-contact array, by u = h - z: [0,kc) u >= u_c; [kc,kf) u_f <= u < u_c;
# [kf,ks) u* <= u < u_f; [ks,nin) u < u*
SEG_A = 0
SEG_B = 1
SEG_C = 2
SEG_D = 3

#: renormalise a row's affine map (raw coordinates recomputed, sums rebuilt) every this many
#: steps or when its scale falls below RENORM_SCALE; bounds round-off drift of the sums
RENORM_EVERY = 512
RENORM_SCALE = 0.5

#: largest step [m] of the contact search while it has no bracket (an approach of 1 mm is
#: already 100 MPa on the foundation)
MAX_EXPANSION = 1e-3

#: relative friction residual above which a contact root is recomputed by the exact sorted
#: scan (:func:`brakeca.contact.first_root_binned`); counted in ``walk[6]``
ROOT_CHECK = 1e-8


def supports(config, grid=None) -> bool:
    """Whether the lazy kernel can run ``config``: fibres as columns (no rule 7), rule 6 off,
    and Archard wear of less than the interference in one step (``WP K s < 1/2``); the
    reasons are :meth:`brakeca.config.SimulationConfig.lazy_kernel_problem`'s. ``grid`` is
    not needed (kept for callers that pass it)."""
    return config.lazy_kernel_problem() is None


class Lazy:
    """The lazy kernel's scratch arrays for one grid (allocated once per run)."""

    def __init__(self, n_radial: int, n_angular: int, n_sub: int) -> None:
        n = n_radial * n_angular
        p2 = 1
        while p2 < n_angular:
            p2 *= 2
        self.in_r = np.zeros(n)
        self.in_idx = np.zeros(n, dtype=np.int32)
        self.out_h = np.zeros(n)
        self.out_idx = np.zeros(n, dtype=np.int32)
        self.in_s = np.zeros(n, dtype=np.int8)  # status of the entries (read in order)
        self.out_s = np.zeros(n, dtype=np.int8)
        # secondary plateaus that crossed the contact edge since the rule-5 trees were last
        # brought up to date ([0] is the count) and their flags
        self.tdirty = np.zeros(n + 1, dtype=np.int64)
        self.tmark = np.zeros(n, dtype=np.int8)
        self.where = np.zeros(n, dtype=np.int8)
        self.pos = np.zeros(n, dtype=np.int32)
        self.cell_r = np.zeros(n)
        self.rows = np.zeros((n_radial, 8), dtype=np.int64)  # nin, nout, kc, kf, ks, ke
        self.amap = np.ones((n_radial, 4))  # a, c, a before this step's wear, c before
        self.seg = np.zeros((n_radial, 4, 3))  # per segment: count, sum r, sum r^2
        self.bins = np.zeros((n_radial * n_sub, 4))  # primary count, sum r; secondary ...
        # rule-5 trees, one per row, node k of row j at record j * 2 * p2 + k: (winner's
        # column, -1 if none; largest certificate in the subtree; winner's r; winner's base)
        self.tree = np.zeros((n_radial * 2 * p2, 4))
        self.tree[:, TR_W] = -1.0
        self.tree[:, TR_SUB] = -np.inf
        self.tree_a = np.ones(n_radial)
        self.stack = np.zeros(2 * p2 + 8, dtype=np.int64)
        self.dh = np.zeros(n)
        self.marked = np.zeros(n, dtype=np.int64)
        self.walk = np.zeros(8)
        self.p2 = p2
        # per-row resin entries sorted by height (key, column; stale entries allowed, until a
        # row fills its room and is rebuilt from the grid), row j's at
        # [resin_n[j, RN_S], resin_n[j, RN_S] + resin_n[j, RN_N])
        room = RESIN_ROOM * n_angular + 8
        self.resin_key = np.zeros((n_radial, room))
        self.resin_col = np.zeros((n_radial, room), dtype=np.int32)
        self.resin_n = np.zeros((n_radial, 2), dtype=np.int64)  # count, start (RN_N, RN_S)


# rows[j, *]
RW_NIN = 0
RW_NOUT = 1
RW_KC = 2
RW_KF = 3
RW_KS = 4
RW_KE = 5  # the contact edge during a solve: cells at [ke, nin) are out of contact


# --- kinetic tournament tree (rule 5) -----------------------------------------------------
# the fields of a tree record (a node and its sibling share a cache line)
TR_W = 0
TR_SUB = 1
TR_R = 2
TR_B = 3
# how many iterations ahead the loops over scattered cells prefetch a cell's data
AHEAD = 8

# bits of ``tmark``, one byte per cell: flags for the next flush, and whether the cell's leaf
# in its row's tree holds a line (``tree[leaf, TR_W] >= 0``, kept beside the flags so that the
# flush and the status changes read one byte instead of the tree's record)
TM_CROSSED = 1
TM_STALE = 2
TM_FLAGS = 3
TM_LEAF = 4


@njit(cache=True, inline="always")
def _tree_leaf(p2, j, col):
    """Record of the leaf of column ``col`` in row ``j``'s tree."""
    return j * 2 * p2 + p2 + col


@njit_noalloc
def _tree_dirty(tdirty, tmark, idx, flag):
    """List cell idx for the next :func:`_tree_flush` (once), with ``flag`` TM_CROSSED (it
    crossed the contact edge) or TM_STALE (its leaf is stale: a plateau re-created where a
    destroyed one left it); a cell flagged TM_STALE stays so. The TM_LEAF bit is kept."""
    m = tmark[idx]
    if (m & TM_FLAGS) == 0:
        tdirty[0] += 1
        tdirty[tdirty[0]] = idx
    if flag > (m & TM_FLAGS):
        tmark[idx] = (m & TM_LEAF) | flag


@njit_noalloc
def _tree_recompute(tree, off, node, a):
    """Node ``node`` of the tree at record ``off`` from its two children: the lower line at
    scale ``a`` wins; its certificate is the scale at which the other overtakes it."""
    left = off + 2 * node
    right = left + 1
    wl = tree[left, TR_W]
    wr = tree[right, TR_W]
    ev = -math.inf
    if wl < 0.0:
        w, rw, bw = wr, tree[right, TR_R], tree[right, TR_B]
    elif wr < 0.0:
        w, rw, bw = wl, tree[left, TR_R], tree[left, TR_B]
    else:
        rl, bl = tree[left, TR_R], tree[left, TR_B]
        rr, br = tree[right, TR_R], tree[right, TR_B]
        if rl * a - bl <= rr * a - br:
            w, rw, bw, ro, bo = wl, rl, bl, rr, br
        else:
            w, rw, bw, ro, bo = wr, rr, br, rl, bl
        if rw < ro:
            ev = (bw - bo) / (rw - ro)
            if ev > a:
                ev = a
    s = ev
    if tree[left, TR_SUB] > s:
        s = tree[left, TR_SUB]
    if tree[right, TR_SUB] > s:
        s = tree[right, TR_SUB]
    k = off + node
    tree[k, TR_W] = w
    tree[k, TR_SUB] = s
    tree[k, TR_R] = rw
    tree[k, TR_B] = bw


@njit_noalloc
def _tree_set(tree, p2, j, col, active, a, r, b):
    """Insert (``active``, the line ``r a - b``) or remove the line of the cell in column
    ``col`` of row ``j``."""
    off = j * 2 * p2
    leaf = _tree_leaf(p2, j, col)
    if active:
        tree[leaf, TR_W] = col
        tree[leaf, TR_R] = r
        tree[leaf, TR_B] = b
    else:
        tree[leaf, TR_W] = -1.0
    node = (p2 + col) >> 1
    while node >= 1:
        k = off + node
        w0 = tree[k, TR_W]
        s0 = tree[k, TR_SUB]
        r0 = tree[k, TR_R]
        b0 = tree[k, TR_B]
        _tree_recompute(tree, off, node, a)
        if (
            tree[k, TR_W] == w0
            and tree[k, TR_SUB] == s0
            and tree[k, TR_R] == r0
            and tree[k, TR_B] == b0
        ):
            break  # the parents read nothing else of this node: nothing above can change
        node >>= 1


@njit_noalloc
def _tree_advance(tree, p2, j, a, stack):
    """Bring row ``j``'s tree to scale ``a`` (lower than before): recompute every node whose
    certificate failed, children before parents."""
    off = j * 2 * p2
    if tree[off + 1, TR_SUB] < a:
        return
    n = 0
    stack[0] = 1
    top = 1
    # collect in pre-order at the end of the stack array, then recompute in reverse
    m = stack.size
    while top > 0:
        top -= 1
        node = stack[top]
        if node >= p2 or tree[off + node, TR_SUB] < a:
            continue
        n += 1
        stack[m - n] = node
        stack[top] = 2 * node
        stack[top + 1] = 2 * node + 1
        top += 2
    for q in range(n):
        _tree_recompute(tree, off, stack[m - n + q], a)


@njit_noalloc
def _tree_flush(tree, p2, ta, cell_r, base, where, tdirty, tmark, n_angular):
    """Bring the rule-5 trees up to date with the secondary plateaus that crossed the contact
    edge (each crossing only listed the cell: during a contact solve cells cross back and
    forth, and only the net change reaches the tree)."""
    for k in range(1, tdirty[0] + 1):
        if k + AHEAD <= tdirty[0]:
            ahead = tdirty[k + AHEAD]
            prefetch(tmark, ahead)
            prefetch(where, ahead)
            prefetch(cell_r, ahead)
            prefetch(base, ahead)
            # the first records its climb reads and writes (its leaf, the nodes one and two
            # levels up), which miss the cache: test 5's first 12 stops 0.898 ± 0.033 of the
            # time (sixteenth session); prefetching two levels more gained nothing
            ja = ahead // n_angular
            leaf = _tree_leaf(p2, ja, ahead - ja * n_angular)
            off = ja * 2 * p2
            prefetch(tree, leaf)
            prefetch(tree, off + ((leaf - off) >> 1))
            prefetch(tree, off + ((leaf - off) >> 2))
        idx = tdirty[k]
        m = tmark[idx]
        has = (m & TM_LEAF) != 0
        want = where[idx] == W_IN
        # a leaf in place is this plateau's own, unless it is marked stale (a plateau created
        # where a destroyed one left its leaf: the line changed, so its path is recomputed);
        # a cell that left and re-entered keeps its line to an ulp
        if want != has or (want and (m & TM_FLAGS) == TM_STALE):
            j = idx // n_angular
            _tree_set(tree, p2, j, idx - j * n_angular, want, ta[j], cell_r[idx], base[idx])
            has = want
        tmark[idx] = TM_LEAF if has else 0
    tdirty[0] = 0


@njit_noalloc
def _tree_build(tree, p2, j, a):
    off = j * 2 * p2
    for node in range(p2 - 1, 0, -1):
        _tree_recompute(tree, off, node, a)


# --- segment bookkeeping ------------------------------------------------------------------
@njit_noalloc
def _seg_of(rows, j, q):
    if q >= rows[j, RW_KS]:
        return SEG_D
    if q >= rows[j, RW_KF]:
        return SEG_C
    if q >= rows[j, RW_KC]:
        return SEG_B
    return SEG_A


@njit_noalloc
def _seg_add(seg, j, s, r, sign):
    seg[j, s, 0] += sign
    seg[j, s, 1] += sign * r
    seg[j, s, 2] += sign * r * r


@njit_noalloc
def _bin_add(bins, b, status, r, sign):
    if status == SECONDARY:
        bins[b, 2] += sign
        bins[b, 3] += sign * r
    else:
        bins[b, 0] += sign
        bins[b, 1] += sign * r


@njit(cache=True, inline="always")
def _on(a, c, r, z, t):
    """Whether a cell of raw coordinate r has interference ``u = a r + c - z >= t`` (the one
    test every partition and breakpoint of the kernel uses, so they agree to the bit)."""
    return a * r + c - z >= t


@njit_noalloc
def _partitions_stale(rows, in_r, j, row0, a, c, z, uc, uf, us):
    """Whether any partition index of row j is not where _fix_partitions would put it."""
    nin = rows[j, RW_KE]
    ks = rows[j, RW_KS]
    kf = rows[j, RW_KF]
    kc = rows[j, RW_KC]
    if ks < nin and _on(a, c, in_r[row0 + ks], z, us):
        return True
    if kf < ks and _on(a, c, in_r[row0 + kf], z, uf):
        return True
    if kc < kf and _on(a, c, in_r[row0 + kc], z, uc):
        return True
    if kc > 0 and not _on(a, c, in_r[row0 + kc - 1], z, uc):
        return True
    if kf > kc and not _on(a, c, in_r[row0 + kf - 1], z, uf):
        return True
    return ks > kf and not _on(a, c, in_r[row0 + ks - 1], z, us)


@njit_noalloc
def _edge_stale(rows, in_r, in_idx, out_h, out_idx, j, row0, a, c, z, incl):
    """Whether row j's contact edge must move to reach z."""
    ke = rows[j, RW_KE]
    q = row0 + ke - 1
    while q >= row0 and in_idx[q] < 0:
        q -= 1
    if q >= row0:
        h = a * in_r[q] + c
        if h < z or (not incl and h == z):
            return True
    nin = rows[j, RW_NIN]
    q = row0 + ke
    while q < row0 + nin and in_idx[q] < 0:
        q += 1
    if q < row0 + nin:
        h = a * in_r[q] + c
        return h > z or (incl and h == z)
    nout = rows[j, RW_NOUT]
    if nout > 0:
        q = row0 + nout - 1
        if out_idx[q] < 0:
            return True
        h = out_h[q]
        if h > z or (incl and h == z):
            return True
    return False


@njit(cache=True, inline="always")
def _sums_in(n, s, q, r):
    """A segment's sums (count, sum r, sum r^2), held in locals, after a cell of raw
    coordinate r joins it: the additions of ``_seg_add(..., r, 1.0)``."""
    return n + 1.0, s + r, q + r * r


@njit(cache=True, inline="always")
def _sums_out(n, s, q, r):
    """A segment's sums, held in locals, after a cell of raw coordinate r leaves it: the
    additions of ``_seg_add(..., r, -1.0)`` (``x + (-1.0) r`` is ``x - r``, and
    ``((-1.0) r) r`` is ``-(r r)``, exactly)."""
    return n - 1.0, s - r, q - r * r


@njit(cache=True, inline="always")
def _shift(n_from, s_from, q_from, n_to, s_to, q_to, r):
    """The sums of two segments after a cell of raw coordinate r moves from the first to the
    second (:func:`_sums_out`, then :func:`_sums_in`)."""
    n_from, s_from, q_from = _sums_out(n_from, s_from, q_from, r)
    n_to, s_to, q_to = _sums_in(n_to, s_to, q_to, r)
    return n_from, s_from, q_from, n_to, s_to, q_to


@njit_noalloc_inline
def _fix_partitions(rows, seg, in_r, in_idx, amap, j, row0, z, uc, uf, us):
    """Move the partition indices of row j to disc position z (segment sums follow).

    The sums of the four segments are held in locals while the indices move and stored once
    at the end: each sum gets the same additions in the same order as with two
    :func:`_seg_add` calls per cell (:func:`_shift`), without a store and reload per move."""
    a = amap[j, 0]
    c = amap[j, 1]
    nin = rows[j, RW_KE]
    ks = rows[j, RW_KS]
    kf = rows[j, RW_KF]
    kc = rows[j, RW_KC]
    n_a, s_a, q_a = seg[j, SEG_A, 0], seg[j, SEG_A, 1], seg[j, SEG_A, 2]
    n_b, s_b, q_b = seg[j, SEG_B, 0], seg[j, SEG_B, 1], seg[j, SEG_B, 2]
    n_c, s_c, q_c = seg[j, SEG_C, 0], seg[j, SEG_C, 1], seg[j, SEG_C, 2]
    n_d, s_d, q_d = seg[j, SEG_D, 0], seg[j, SEG_D, 1], seg[j, SEG_D, 2]
    moves = 0
    while ks < nin and _on(a, c, in_r[row0 + ks], z, us):
        if in_idx[row0 + ks] >= 0:  # D -> C
            n_d, s_d, q_d, n_c, s_c, q_c = _shift(n_d, s_d, q_d, n_c, s_c, q_c, in_r[row0 + ks])
        ks += 1
        moves += 1
    while kf < ks and _on(a, c, in_r[row0 + kf], z, uf):
        if in_idx[row0 + kf] >= 0:  # C -> B
            n_c, s_c, q_c, n_b, s_b, q_b = _shift(n_c, s_c, q_c, n_b, s_b, q_b, in_r[row0 + kf])
        kf += 1
        moves += 1
    while kc < kf and _on(a, c, in_r[row0 + kc], z, uc):
        if in_idx[row0 + kc] >= 0:  # B -> A
            n_b, s_b, q_b, n_a, s_a, q_a = _shift(n_b, s_b, q_b, n_a, s_a, q_a, in_r[row0 + kc])
        kc += 1
        moves += 1
    while kc > 0 and not _on(a, c, in_r[row0 + kc - 1], z, uc):
        kc -= 1
        if in_idx[row0 + kc] >= 0:  # A -> B
            n_a, s_a, q_a, n_b, s_b, q_b = _shift(n_a, s_a, q_a, n_b, s_b, q_b, in_r[row0 + kc])
        moves += 1
    while kf > kc and not _on(a, c, in_r[row0 + kf - 1], z, uf):
        kf -= 1
        if in_idx[row0 + kf] >= 0:  # B -> C
            n_b, s_b, q_b, n_c, s_c, q_c = _shift(n_b, s_b, q_b, n_c, s_c, q_c, in_r[row0 + kf])
        moves += 1
    while ks > kf and not _on(a, c, in_r[row0 + ks - 1], z, us):
        ks -= 1
        if in_idx[row0 + ks] >= 0:  # C -> D
            n_c, s_c, q_c, n_d, s_d, q_d = _shift(n_c, s_c, q_c, n_d, s_d, q_d, in_r[row0 + ks])
        moves += 1
    seg[j, SEG_A, 0], seg[j, SEG_A, 1], seg[j, SEG_A, 2] = n_a, s_a, q_a
    seg[j, SEG_B, 0], seg[j, SEG_B, 1], seg[j, SEG_B, 2] = n_b, s_b, q_b
    seg[j, SEG_C, 0], seg[j, SEG_C, 1], seg[j, SEG_C, 2] = n_c, s_c, q_c
    seg[j, SEG_D, 0], seg[j, SEG_D, 1], seg[j, SEG_D, 2] = n_d, s_d, q_d
    rows[j, RW_KS] = ks
    rows[j, RW_KF] = kf
    rows[j, RW_KC] = kc
    return moves


# L = (rows, seg, in_r, in_idx, amap, out_h, out_idx, where, pos, cell_r, bins,
#      tree, tree_a, stack): the lazy structures (see :class:`Lazy`)
def structures(lz: Lazy) -> tuple:
    """The tuple of lazy structures passed to the compiled functions."""
    return (
        lz.rows,
        lz.seg,
        lz.in_r,
        lz.in_idx,
        lz.amap,
        lz.out_h,
        lz.out_idx,
        lz.where,
        lz.pos,
        lz.cell_r,
        lz.bins,
        lz.tree,
        lz.tree_a,
        lz.stack,
        lz.in_s,
        lz.out_s,
        lz.tdirty,
        lz.tmark,
    )


@njit_noalloc
def _compact_in(rows, in_r, in_idx, in_s, pos, j, n_angular):
    """Drop the tombstones of row j's in-contact array (order kept; partitions follow)."""
    row0 = j * n_angular
    kc = rows[j, RW_KC]
    kf = rows[j, RW_KF]
    ks = rows[j, RW_KS]
    ke = rows[j, RW_KE]
    w = 0
    nkc = nkf = nks = nke = 0
    for q in range(rows[j, RW_NIN]):
        if q == kc:
            nkc = w
        if q == kf:
            nkf = w
        if q == ks:
            nks = w
        if q == ke:
            nke = w
        idx = in_idx[row0 + q]
        if idx >= 0:
            in_r[row0 + w] = in_r[row0 + q]
            in_idx[row0 + w] = idx
            in_s[row0 + w] = in_s[row0 + q]
            pos[idx] = w
            w += 1
    n = rows[j, RW_NIN]
    rows[j, RW_KC] = w if kc >= n else nkc
    rows[j, RW_KF] = w if kf >= n else nkf
    rows[j, RW_KS] = w if ks >= n else nks
    rows[j, RW_KE] = w if ke >= n else nke
    rows[j, RW_NIN] = w


@njit_noalloc
def _compact_out(rows, out_h, out_idx, out_s, pos, j, n_angular):
    """Drop the tombstones of row j's out-of-contact array (order kept)."""
    row0 = j * n_angular
    w = 0
    for q in range(rows[j, RW_NOUT]):
        idx = out_idx[row0 + q]
        if idx >= 0:
            out_h[row0 + w] = out_h[row0 + q]
            out_idx[row0 + w] = idx
            out_s[row0 + w] = out_s[row0 + q]
            pos[idx] = w
            w += 1
    rows[j, RW_NOUT] = w


@njit_noalloc_inline
def _contact_row(
    rows,
    seg,
    in_r,
    in_idx,
    amap,
    out_h,
    out_idx,
    where,
    pos,
    cell_r,
    bins,
    in_s,
    out_s,
    tdirty,
    tmark,
    j,
    z,
    incl,
    n_sub,
    n_angular,
):
    """Move row j's contact edge to z: cells with ``h <= z`` leave (``h < z`` when ``incl``),
    cells with ``h > z`` (``h >= z``) enter. Returns the number of cells that crossed.

    During a solve the edge moves inside the in-contact array first: a cell that leaves stays
    there, past the edge index ``ke``, and only its segment sums change; it comes back by
    moving the index. Only when the edge passes the end of the array do cells enter from the
    out-of-contact array (written: ``where``/``pos``, the bin sums, and ``cell_r`` and the
    rule-5 marks for secondary plateaus; the entries carry their status, the stream bin follows
    from the column). :func:`_commit_row` moves the cells left past the edge out at the root."""
    row0 = j * n_angular
    n_m = n_angular // n_sub
    b0 = j * n_sub
    a = amap[j, 0]
    c = amap[j, 1]
    nin = rows[j, RW_NIN]
    ke = rows[j, RW_KE]
    moves = 0
    # segment D's sums in locals (stored at the end; the same additions in the same order as
    # with _seg_add: _sums_in, _sums_out): the cells at the edge are nearly always in D
    n_d, s_d, q_d = seg[j, SEG_D, 0], seg[j, SEG_D, 1], seg[j, SEG_D, 2]
    # leaving: the edge moves up the in-contact array
    while ke > 0:
        q = row0 + ke - 1
        if in_idx[q] >= 0:
            r = in_r[q]
            h = a * r + c
            if h > z or (incl and h == z):
                break
            s_of = _seg_of(rows, j, ke - 1)
            if s_of == SEG_D:
                n_d, s_d, q_d = _sums_out(n_d, s_d, q_d, r)
            else:
                _seg_add(seg, j, s_of, r, -1.0)
            moves += 1
        ke -= 1
        if rows[j, RW_KS] > ke:
            rows[j, RW_KS] = ke
        if rows[j, RW_KF] > ke:
            rows[j, RW_KF] = ke
        if rows[j, RW_KC] > ke:
            rows[j, RW_KC] = ke
    # entering: first the cells left past the edge (tombstones are passed only on the way to
    # a cell that enters, or to the end of the array)
    while ke < nin:
        q = ke
        while q < nin and in_idx[row0 + q] < 0:
            q += 1
        if q == nin:
            ke = nin
            break
        r = in_r[row0 + q]
        h = a * r + c
        if not (h > z or (incl and h == z)):
            break
        n_d, s_d, q_d = _sums_in(n_d, s_d, q_d, r)
        moves += 1
        ke = q + 1
    rows[j, RW_KE] = ke
    if ke < nin:
        seg[j, SEG_D, 0], seg[j, SEG_D, 1], seg[j, SEG_D, 2] = n_d, s_d, q_d
        return moves
    # then from the out-of-contact array
    nout = rows[j, RW_NOUT]
    while nout > 0:
        q = row0 + nout - 1
        idx = out_idx[q]
        if idx >= 0:
            h = out_h[q]
            if not (h > z or (incl and h == z)):
                break
            st = out_s[q]
            r = (h - c) / a
            if nin == n_angular:
                rows[j, RW_NIN] = nin
                _compact_in(rows, in_r, in_idx, in_s, pos, j, n_angular)
                nin = rows[j, RW_NIN]
            in_r[row0 + nin] = r
            in_idx[row0 + nin] = idx
            in_s[row0 + nin] = st
            where[idx] = W_IN
            pos[idx] = nin
            n_d, s_d, q_d = _sums_in(n_d, s_d, q_d, r)
            _bin_add(bins, b0 + (idx - row0) // n_m, st, r, 1.0)
            if st == SECONDARY:
                cell_r[idx] = r
                _tree_dirty(tdirty, tmark, idx, TM_CROSSED)
            nin += 1
            moves += 1
        nout -= 1
    seg[j, SEG_D, 0], seg[j, SEG_D, 1], seg[j, SEG_D, 2] = n_d, s_d, q_d
    rows[j, RW_NIN] = nin
    rows[j, RW_KE] = nin
    rows[j, RW_NOUT] = nout
    return moves


@njit_noalloc
def _commit_row(
    rows,
    in_r,
    in_idx,
    amap,
    out_h,
    out_idx,
    where,
    pos,
    bins,
    in_s,
    out_s,
    tdirty,
    tmark,
    j,
    n_sub,
    n_angular,
):
    """Move the cells of row j left past the contact edge (``[ke, nin)`` of the in-contact
    array) to the out-of-contact array, lowest first, each to its top, and drop the tombstones
    at the array's end; the segment sums of the cells moved were taken off as the edge passed
    them, their bin sums and the rule-5 marks follow here."""
    row0 = j * n_angular
    n_m = n_angular // n_sub
    b0 = j * n_sub
    a = amap[j, 0]
    c = amap[j, 1]
    ke = rows[j, RW_KE]
    nin = rows[j, RW_NIN]
    nout = rows[j, RW_NOUT]
    while nin > ke:
        q = row0 + nin - 1
        idx = in_idx[q]
        if idx >= 0:
            r = in_r[q]
            h = a * r + c
            st = in_s[q]
            _bin_add(bins, b0 + (idx - row0) // n_m, st, r, -1.0)
            if st == SECONDARY:
                _tree_dirty(tdirty, tmark, idx, TM_CROSSED)
            # to the top of the out-of-contact array (it is the highest of them)
            if nout == n_angular:
                rows[j, RW_NOUT] = nout
                _compact_out(rows, out_h, out_idx, out_s, pos, j, n_angular)
                nout = rows[j, RW_NOUT]
            w = nout
            while w > 0 and out_idx[row0 + w - 1] >= 0 and out_h[row0 + w - 1] > h:
                out_h[row0 + w] = out_h[row0 + w - 1]
                out_idx[row0 + w] = out_idx[row0 + w - 1]
                out_s[row0 + w] = out_s[row0 + w - 1]
                pos[out_idx[row0 + w]] = w
                w -= 1
            out_h[row0 + w] = h
            out_idx[row0 + w] = idx
            out_s[row0 + w] = st
            where[idx] = W_OUT
            pos[idx] = w
            nout += 1
        nin -= 1
    while nin > 0 and in_idx[row0 + nin - 1] < 0:
        nin -= 1  # tombstones at the end go too
    rows[j, RW_NIN] = nin
    rows[j, RW_KE] = nin
    for k in (RW_KC, RW_KF, RW_KS):
        if rows[j, k] > nin:
            rows[j, k] = nin
    rows[j, RW_NOUT] = nout


@njit_noalloc_inline
def _move_row(L, j, z, incl, uc, uf, us, n_sub, n_angular):
    """Move row j's contact edge (if it is stale) and partitions (if stale) to z; returns the
    number of cells moved. Inlined into each pass over the rows (a call would hand over every
    array of ``L`` word by word: brakeca._jit.njit_noalloc_inline)."""
    rows, seg, in_r, in_idx, amap, out_h, out_idx = L[0], L[1], L[2], L[3], L[4], L[5], L[6]
    where, pos, cell_r, bins = L[7], L[8], L[9], L[10]
    in_s, out_s, tdirty, tmark = L[14], L[15], L[16], L[17]
    moves = 0
    row0 = j * n_angular
    if _edge_stale(rows, in_r, in_idx, out_h, out_idx, j, row0, amap[j, 0], amap[j, 1], z, incl):
        moves += _contact_row(
            rows,
            seg,
            in_r,
            in_idx,
            amap,
            out_h,
            out_idx,
            where,
            pos,
            cell_r,
            bins,
            in_s,
            out_s,
            tdirty,
            tmark,
            j,
            z,
            incl,
            n_sub,
            n_angular,
        )
    if _partitions_stale(rows, in_r, j, row0, amap[j, 0], amap[j, 1], z, uc, uf, us):
        moves += _fix_partitions(rows, seg, in_r, in_idx, amap, j, row0, z, uc, uf, us)
    return moves


# indices into the evaluation totals `tot`
E_F = 0  # friction force F [N]
E_D = 1  # dF/dw [N/m] (w: approach, -z)
E_Q = 2  # -1/2 d2F/dw2 [N/m^2]
E_FH = 3  # envelope F_hat [N]
E_DH = 4
E_QH = 5
E_NWIN = 6  # cells with u in [u*, u_c) (where F < F_hat)
E_AU = 7  # sum of A u over the cells in contact [m^3]
E_AREA = 8  # contact area [m^2]
E_MOVES = 9
E_ACC = 10  # tot[E_ACC : E_ACC + 5]: the walk's totals (F, D, Q, S, QD), scratch for _walk
N_E = 15


@njit_noalloc
def _evaluate(
    L,
    z,
    incl,
    tot,
    status,
    cell_bin,
    base,
    n_radial,
    n_angular,
    n_sub,
    p2,
    bin_area,
    stiffness,
    mu_0,
    slope,
    mu_min,
    uc,
    uf,
    us,
):
    """Move every row's contact edge and partitions to z and sum F, F_hat and their
    derivatives into ``tot``."""
    seg, amap = L[1], L[4]
    k0 = mu_0 * stiffness
    k1 = mu_min * stiffness
    k2 = slope * stiffness * stiffness
    peak = mu_0 * mu_0 / (4.0 * slope) if slope > 0.0 else 0.0
    t_e_f = t_e_d = t_e_q = t_e_fh = t_e_dh = t_e_qh = t_e_nwin = t_e_au = t_e_area = 0.0
    moves = 0
    for j in range(n_radial):
        moves += _move_row(L, j, z, incl, uc, uf, us, n_sub, n_angular)
        a = amap[j, 0]
        d = amap[j, 1] - z
        area = bin_area[j * n_sub]
        nA, sA = seg[j, SEG_A, 0], seg[j, SEG_A, 1]
        nB, sB = seg[j, SEG_B, 0], seg[j, SEG_B, 1]
        nC, sC, qC = seg[j, SEG_C, 0], seg[j, SEG_C, 1], seg[j, SEG_C, 2]
        nD, sD, qD = seg[j, SEG_D, 0], seg[j, SEG_D, 1], seg[j, SEG_D, 2]
        uA = a * sA + d * nA
        uB = a * sB + d * nB
        uC = a * sC + d * nC
        uD = a * sD + d * nD
        u2C = a * a * qC + 2.0 * a * d * sC + d * d * nC
        u2D = a * a * qD + 2.0 * a * d * sD + d * d * nD
        t_e_f += area * (k1 * (uA + uB) + k0 * (uC + uD) - k2 * (u2C + u2D))
        t_e_d += area * (k1 * (nA + nB) + k0 * (nC + nD) - 2.0 * k2 * (uC + uD))
        t_e_q += area * k2 * (nC + nD)
        t_e_fh += area * (k1 * uA + peak * (nB + nC) + k0 * uD - k2 * u2D)
        t_e_dh += area * (k1 * nA + k0 * nD - 2.0 * k2 * uD)
        t_e_qh += area * k2 * nD
        t_e_nwin += nB + nC
        t_e_au += area * (uA + uB + uC + uD)
        t_e_area += area * (nA + nB + nC + nD)
    tot[E_F] = t_e_f
    tot[E_D] = t_e_d
    tot[E_Q] = t_e_q
    tot[E_FH] = t_e_fh
    tot[E_DH] = t_e_dh
    tot[E_QH] = t_e_qh
    tot[E_NWIN] = t_e_nwin
    tot[E_AU] = t_e_au
    tot[E_AREA] = t_e_area
    tot[E_MOVES] = moves
    return moves


@njit(cache=True, inline="always")
def _local_step(f, dfd, q, target):
    """Approach change delta with f + dfd delta - q delta^2 = target, nearest zero (nan if the
    local quadratic has none)."""
    rest = target - f
    if q > 0.0:
        disc = dfd * dfd - 4.0 * q * rest
        if disc < 0.0:
            return math.nan
        den = dfd + math.sqrt(disc)
        if den <= 0.0:
            return math.nan
        return 2.0 * rest / den
    if dfd > 0.0:
        return rest / dfd
    return math.nan


@njit_noalloc
def _row_terms(seg, amap, j, z, area, k0, k1, k2):
    """Row j's share of (F, D, Q) at disc position z."""
    a = amap[j, 0]
    d = amap[j, 1] - z
    nF = seg[j, SEG_A, 0] + seg[j, SEG_B, 0]
    sF = seg[j, SEG_A, 1] + seg[j, SEG_B, 1]
    nR = seg[j, SEG_C, 0] + seg[j, SEG_D, 0]
    sR = seg[j, SEG_C, 1] + seg[j, SEG_D, 1]
    qR = seg[j, SEG_C, 2] + seg[j, SEG_D, 2]
    uF = a * sF + d * nF
    uR = a * sR + d * nR
    u2R = a * a * qR + 2.0 * a * d * sR + d * d * nR
    f = area * (k1 * uF + k0 * uR - k2 * u2R)
    df = area * (k1 * nF + k0 * nR - 2.0 * k2 * uR)
    q = area * k2 * nR
    return f, df, q


@njit_noalloc
def _row_event(rows, in_r, in_idx, amap, out_h, out_idx, j, z, n_angular, uf):
    """Row j's highest breakpoint of F strictly below z (-inf if none)."""
    row0 = j * n_angular
    best = -math.inf
    nin = rows[j, RW_NIN]
    ke = rows[j, RW_KE]
    q = ke
    while q < nin and in_idx[row0 + q] < 0:
        q += 1
    if q < nin:
        best = amap[j, 0] * in_r[row0 + q] + amap[j, 1]
    else:
        nout = rows[j, RW_NOUT]
        while nout > 0 and out_idx[row0 + nout - 1] < 0:
            nout -= 1
        rows[j, RW_NOUT] = nout
        if nout > 0:
            best = out_h[row0 + nout - 1]
    kf = rows[j, RW_KF]
    if kf < ke:
        a = amap[j, 0]
        c = amap[j, 1]
        r = in_r[row0 + kf]
        zf = a * r + c - uf
        # the highest z at which _on (the partition test) puts it on the floor: the two are
        # rounded differently, so step down to where they agree
        while not _on(a, c, r, zf, uf):
            zf = np.nextafter(zf, -math.inf)
        if zf > best and zf < z:
            best = zf
    return best


@njit_noalloc_inline
def _evt_top(evt, node):
    """The larger of node's two children in the rows' max-tree, ``left if left >= right else
    right`` (so the left one where they compare equal, as 0.0 and -0.0 do), for both
    :func:`_evt_set` and :func:`_evt_build`."""
    left = evt[2 * node]
    right = evt[2 * node + 1]
    return left if left >= right else right


@njit_noalloc
def _evt_set(evt, m, j, value):
    """Max-tree over rows (leaves at m + j): set row j's next event. The climb stops at the
    first node whose maximum is unchanged: the nodes above it are unchanged too."""
    node = m + j
    evt[node] = value
    node >>= 1
    while node >= 1:
        top = _evt_top(evt, node)
        if evt[node] == top:
            break
        evt[node] = top
        node >>= 1


@njit_noalloc
def _evt_build(evt, m):
    """Max-tree over rows: every inner node from the leaves, bottom up (the values
    :func:`_evt_set` would leave, in one pass)."""
    for node in range(m - 1, 0, -1):
        evt[node] = _evt_top(evt, node)


@njit_noalloc
def _row_slope(seg, amap, j, z, area, k0, k1, k2):
    """Row j's (S, QD): the slope of the walk's linear bound (floor and falling cells at
    mu_min K, rising cells at their tangent) and how fast the tangents fall (S' = -2 QD)."""
    a = amap[j, 0]
    d = amap[j, 1] - z
    n_abc = seg[j, SEG_A, 0] + seg[j, SEG_B, 0] + seg[j, SEG_C, 0]
    nD = seg[j, SEG_D, 0]
    uD = a * seg[j, SEG_D, 1] + d * nD
    return area * (k1 * n_abc + k0 * nD - 2.0 * k2 * uD), area * k2 * nD


@njit_noalloc
def _entering_weight(L, level, n_radial, n_angular, n_sub, bin_area):
    """Sum of the areas of the cells out of contact above ``level`` [m^2] (tombstones
    included: an upper bound)."""
    rows, in_r, amap, out_h = L[0], L[2], L[4], L[5]
    we = 0.0
    for j in range(n_radial):
        row0 = j * n_angular
        ke = rows[j, RW_KE]
        nin = rows[j, RW_NIN]
        if ke < nin:
            # above every cell out of contact; descending: first index with h <= level
            a = amap[j, 0]
            c = amap[j, 1]
            lo = ke
            hi = nin
            while lo < hi:
                mid = (lo + hi) >> 1
                if a * in_r[row0 + mid] + c > level:
                    lo = mid + 1
                else:
                    hi = mid
            we += bin_area[j * n_sub] * (lo - ke)
            if lo < nin:
                continue
        n = rows[j, RW_NOUT]
        if n == 0 or out_h[row0 + n - 1] <= level:
            continue
        lo = 0
        hi = n  # first index with out_h > level (ascending array)
        while lo < hi:
            mid = (lo + hi) >> 1
            if out_h[row0 + mid] > level:
                hi = mid
            else:
                lo = mid + 1
        we += bin_area[j * n_sub] * (n - lo)
    return we


@njit_noalloc
def _walk_start(
    L,
    z,
    evt,
    status,
    cell_bin,
    base,
    n_radial,
    n_angular,
    n_sub,
    p2,
    bin_area,
    k0,
    k1,
    k2,
    uc,
    uf,
    us,
    acc5,
):
    """Every row's edge and partitions at z (inclusive), the event tree, and the walk's
    totals ``acc5 = (F, D, Q, S, QD)``."""
    rows, seg, in_r, in_idx, amap, out_h, out_idx = L[0], L[1], L[2], L[3], L[4], L[5], L[6]
    m = evt.size // 2
    evt[:] = -math.inf
    acc5[:] = 0.0
    for j in range(n_radial):
        _move_row(L, j, z, True, uc, uf, us, n_sub, n_angular)
        area = bin_area[j * n_sub]
        fj, dj, qj = _row_terms(seg, amap, j, z, area, k0, k1, k2)
        sj, qdj = _row_slope(seg, amap, j, z, area, k0, k1, k2)
        acc5[0] += fj
        acc5[1] += dj
        acc5[2] += qj
        acc5[3] += sj
        acc5[4] += qdj
        evt[m + j] = _row_event(rows, in_r, in_idx, amap, out_h, out_idx, j, z, n_angular, uf)
    _evt_build(evt, m)


@njit_noalloc
def _walk(
    L,
    z,
    target,
    tot,
    evt,
    status,
    cell_bin,
    base,
    n_radial,
    n_angular,
    n_sub,
    p2,
    bin_area,
    stiffness,
    mu_0,
    slope,
    mu_min,
    uc,
    uf,
    us,
    walk,
):
    """Walk F's breakpoints down from z (where F < target) to the first root; returns it with
    every row's edge and partitions there (or -inf if F never reaches the target).

    Between breakpoints F is the quadratic of the segment sums. Where many breakpoints lie
    ahead, the walk jumps: for an advance ``w <= u_c - u*`` from here,
    ``F <= F_here + S w + mu_0 K A_enter(w) w`` (cells on the floor grow at mu_min K, cells past
    the peak by at most mu_min K w, rising cells stay below their tangent, cells entering
    contact below mu_0 K u), so no root lies before the advance at which that bound reaches
    the target."""
    rows, seg, in_r, in_idx, amap, out_h, out_idx = L[0], L[1], L[2], L[3], L[4], L[5], L[6]
    k0 = mu_0 * stiffness
    k1 = mu_min * stiffness
    k2 = slope * stiffness * stiffness
    m = evt.size // 2
    w_cap = uc - us if uc - us < math.inf else 1e-4
    # in the caller's array: allocating here made numba compile this function with reference
    # counting (test 14's levels take 0.981 of the time without; seventeenth session)
    acc5 = tot[E_ACC : E_ACC + 5]
    _walk_start(
        L,
        z,
        evt,
        status,
        cell_bin,
        base,
        n_radial,
        n_angular,
        n_sub,
        p2,
        bin_area,
        k0,
        k1,
        k2,
        uc,
        uf,
        us,
        acc5,
    )
    f, df, q, sl, qd = acc5[0], acc5[1], acc5[2], acc5[3], acc5[4]
    zc = z
    since = 0
    while True:
        walk[1] += 1.0
        if f >= target:
            return zc
        z_next = evt[1]
        if z_next == -math.inf and mu_min == 0.0 and slope > 0.0:
            # every cell is past its floor, where mu(p) p = 0: F stays below the target (the
            # round-off left in df would put a root far away); the exact scan says no root.
            # (With slope = 0 no cell has a floor, mu = mu_0: F rises without bound.)
            return -math.inf
        delta = _local_step(f, df, q, target)
        if delta == delta and delta >= 0.0 and zc - delta >= z_next:
            return zc - delta
        if z_next == -math.inf:
            return -math.inf
        gap = zc - z_next
        rest = target - f
        since += 1
        if since >= 8 and sl > 0.0 and rest > 16.0 * sl * gap:
            since = 0
            w0 = min(rest / sl, w_cap)
            we = _entering_weight(L, zc - w0, n_radial, n_angular, n_sub, bin_area)
            w1 = min(rest / (sl + k0 * we), w0)
            if w1 > gap:
                walk[3] += 1.0
                zc = zc - w1
                _walk_start(
                    L,
                    zc,
                    evt,
                    status,
                    cell_bin,
                    base,
                    n_radial,
                    n_angular,
                    n_sub,
                    p2,
                    bin_area,
                    k0,
                    k1,
                    k2,
                    uc,
                    uf,
                    us,
                    acc5,
                )
                f, df, q, sl, qd = acc5[0], acc5[1], acc5[2], acc5[3], acc5[4]
                continue
        # advance to the breakpoint, then let its row change
        f += df * gap - q * gap * gap
        df -= 2.0 * q * gap
        sl -= 2.0 * qd * gap
        zc = z_next
        node = 1
        while node < m:
            node = 2 * node if evt[2 * node] >= evt[2 * node + 1] else 2 * node + 1
        j = node - m
        area = bin_area[j * n_sub]
        f0, d0, q0 = _row_terms(seg, amap, j, zc, area, k0, k1, k2)
        s0, qd0 = _row_slope(seg, amap, j, zc, area, k0, k1, k2)
        _move_row(L, j, zc, True, uc, uf, us, n_sub, n_angular)
        f1, d1, q1 = _row_terms(seg, amap, j, zc, area, k0, k1, k2)
        s1, qd1 = _row_slope(seg, amap, j, zc, area, k0, k1, k2)
        f += f1 - f0
        df += d1 - d0
        q += q1 - q0
        sl += s1 - s0
        qd += qd1 - qd0
        _evt_set(
            evt, m, j, _row_event(rows, in_r, in_idx, amap, out_h, out_idx, j, zc, n_angular, uf)
        )


@njit(cache=True)
def _exact_root(
    L,
    target,
    tot,
    walk,
    status,
    cell_bin,
    base,
    n_radial,
    n_angular,
    n_sub,
    p2,
    bin_area,
    stiffness,
    mu_0,
    slope,
    mu_min,
    uc,
    uf,
    us,
):
    """The safety net: every plateau height materialised, sorted, and the exact scan of
    :func:`brakeca.contact.first_root_binned`; rows moved to its root. Returns (z, code)."""
    rows, in_r, in_idx, amap, out_h, out_idx = L[0], L[2], L[3], L[4], L[5], L[6]
    walk[6] += 1.0
    n = 0
    for j in range(n_radial):
        n += rows[j, RW_NIN] + rows[j, RW_NOUT]
    hs = np.empty(n)
    bs = np.empty(n, dtype=np.int64)
    m = 0
    for j in range(n_radial):
        row0 = j * n_angular
        a = amap[j, 0]
        c = amap[j, 1]
        for q in range(rows[j, RW_NIN]):
            idx = in_idx[row0 + q]
            if idx >= 0:
                hs[m] = a * in_r[row0 + q] + c
                bs[m] = cell_bin[idx]
                m += 1
        for q in range(rows[j, RW_NOUT]):
            idx = out_idx[row0 + q]
            if idx >= 0:
                hs[m] = out_h[row0 + q]
                bs[m] = cell_bin[idx]
                m += 1
    order = np.argsort(-hs[:m], kind="mergesort")
    z, _, code = first_root_binned(
        hs[:m][order], bs[:m][order], bin_area, m, stiffness, mu_0, slope, mu_min, target
    )
    if code != SOLVE_OK:
        return z, 2
    _evaluate(
        L,
        z,
        False,
        tot,
        status,
        cell_bin,
        base,
        n_radial,
        n_angular,
        n_sub,
        p2,
        bin_area,
        stiffness,
        mu_0,
        slope,
        mu_min,
        uc,
        uf,
        us,
    )
    return z, 0


@njit(cache=True)
def solve_contact(
    L,
    z_start,
    target,
    tot,
    evt,
    status,
    cell_bin,
    base,
    n_radial,
    n_angular,
    n_sub,
    p2,
    bin_area,
    stiffness,
    mu_0,
    slope,
    mu_min,
    uc,
    uf,
    us,
    walk,
):
    """The first root of F(z) = target as the approach grows (see the module docstring);
    leaves every row's edge and partitions at the root. Returns (z, code)."""
    args = (
        status,
        cell_bin,
        base,
        n_radial,
        n_angular,
        n_sub,
        p2,
        bin_area,
        stiffness,
        mu_0,
        slope,
        mu_min,
        uc,
        uf,
        us,
    )
    z = z_start
    t_start = _clock()
    zhi = math.inf  # F_hat < target above here
    zlo = -math.inf  # F_hat >= target at and below here
    last = 0.0
    model = False
    found = False
    for _ in range(400):
        walk[2] += 1.0
        moves = _evaluate(L, z, False, tot, *args)
        fh = tot[E_FH]
        if model and moves == 0 and abs(fh - target) <= 1e-10 * target:
            # the same partition as the model's: the root of its quadratic (the residual test
            # guards against a model step taken from far away, whose z is inexact)
            found = True
            break
        if fh < target:
            zhi = z
        else:
            zlo = z
            if zhi - zlo <= 1e-15 * (abs(z) + 1e-6):
                found = True
                break
        delta = _local_step(fh, tot[E_DH], tot[E_QH], target)
        z_new = z - delta
        model = True
        if not (z_new > zlo and z_new < zhi):  # nan or outside the bracket
            model = False
            if zlo > -math.inf and zhi < math.inf:
                z_new = 0.5 * (zlo + zhi)
            elif fh < target:
                last = min(max(2.0 * last, 1e-9), MAX_EXPANSION)
                z_new = z - last
            else:
                last = min(max(2.0 * last, 1e-9), MAX_EXPANSION)
                z_new = z + last
        if z_new == z:
            found = True
            break
        z = z_new
    if not found:
        return _exact_root(L, target, tot, walk, *args)
    walk[4] += _clock() - t_start
    if tot[E_NWIN] == 0.0 or tot[E_F] >= target:
        if abs(tot[E_F] - target) > ROOT_CHECK * target:
            return _exact_root(L, target, tot, walk, *args)
        return z, 0
    # F < F_hat here: walk F's breakpoints from z until the quadratic between two of them
    # reaches the target (no root of F lies above z, where F <= F_hat < target). One row
    # changes at a breakpoint: F, D, Q follow incrementally; a max-tree over the rows finds
    # the next breakpoint.
    walk[0] += 1.0
    t0 = _clock()
    z = _walk(L, z, target, tot, evt, *args, walk)
    if z == -math.inf:
        return _exact_root(L, target, tot, walk, *args)
    _evaluate(L, z, False, tot, *args)
    walk[5] += _clock() - t0
    if abs(tot[E_F] - target) > ROOT_CHECK * target:
        return _exact_root(L, target, tot, walk, *args)
    return z, 0


# --- the resin cut, row by row ----------------------------------------------------------------
PEND = 32  # room per row for new resin cells not yet merged into the row's sorted entries
# room for a row's resin entries, per cell of the row: the stale entries left below the disc
# fill it, and a full row is rebuilt from the grid (which entries are there, and the order of
# equal keys, change no value: every entry of one key cuts the same volume into the same
# sums, so this only sets how often rows are rebuilt; 4: half as often as with 2)
RESIN_ROOM = 4


# Each row keeps its resin (status none) cells as entries (height, column) sorted by height,
# lowest first, so the cells above the disc are the end of the array. The cut of a step takes
# them highest first; each drops to z - WR. Every cell of a row has the same area, so two cells
# of a row at the same height cut the same volume: each stream bin's sum is the same in
# whatever order equal heights are cut, and only the step's total (summed row by row) depends
# on the layout. The cells cut in one step land on one height (z - WR, exactly wherever
# z - WR and the heights are within a factor two of each other: most of a run, not where the
# disc crosses height zero, the pad's heights starting above it and wearing below), so they
# go back in as one block, merged from the top: a cut costs the cells it cuts, with no sift;
# a block that round-off left apart is sorted first (nearly sorted: cheap).
# While the disc wears into the pad, the block is the lowest of the row: every entry left is
# above the new z - WR (test 5: all of a row's ~160 entries, with ~47 of them cut a step), so
# a row's entries sit at an offset in its room, with the free room mostly below them, and such
# a block is put below them (no entry moves) instead of merged from the top (every entry
# moves). The entries move only when the room on one side runs out (:func:`_resin_fit`).
# Cells that become resin between cuts wait in a short per-row list (PEND entries) and join
# the cut from there, or the sorted entries when the list is full.
RN_N = 0  # resin_n[j, RN_N]: how many entries row j has
RN_S = 1  # resin_n[j, RN_S]: where they start in the row's room


@njit_noalloc
def _resin_place(rk, rc, rn, j, s):
    """Move row j's entries to start at s (in its room)."""
    s0 = rn[j, RN_S]
    n = rn[j, RN_N]
    if s > s0:  # upwards: from the top down
        for e in range(n - 1, -1, -1):
            rk[j, s + e] = rk[j, s0 + e]
            rc[j, s + e] = rc[j, s0 + e]
    elif s < s0:
        for e in range(n):
            rk[j, s + e] = rk[j, s0 + e]
            rc[j, s + e] = rc[j, s0 + e]
    rn[j, RN_S] = s


@njit(cache=True, inline="always")
def _resin_start(below, free):
    """Where :func:`_resin_fit` and :func:`_resin_build_row` put a row's entries, with
    ``below`` entries' room needed under them and ``free`` more to spare: the spare room below
    them, but 2 PEND entries' above (at most half of it)."""
    return below + free - min(free // 2, 2 * PEND)


@njit_noalloc
def _resin_fit(rk, rc, rn, j, below, above):
    """Make room for ``below`` entries under row j's entries and ``above`` over them, moving
    them if needed (to :func:`_resin_start`): the blocks of cut cells go below, the waiting
    cells merge in near the top. False if the room is too small (the caller rebuilds the row
    from the grid)."""
    s = rn[j, RN_S]
    n = rn[j, RN_N]
    cap = rk.shape[1]
    if s >= below and s + n + above <= cap:
        return True
    free = cap - n - below - above
    if free < 0:
        return False
    _resin_place(rk, rc, rn, j, _resin_start(below, free))
    return True


@njit_noalloc
def _resin_build_row(rk, rc, rn, j, status, height, n_angular, sk, sc):
    """Row j's resin entries from the grid (its status-none cells), sorted lowest first, equal
    heights in column order, placed as :func:`_resin_fit` places them; ``sk``/``sc``: scratch
    for ``n_angular`` entries."""
    row0 = j * n_angular
    n = 0
    for i in range(n_angular):
        if status[row0 + i] == NONE:
            rk[j, n] = height[row0 + i]
            rc[j, n] = i
            n += 1
    rn[j, RN_N] = n
    rn[j, RN_S] = 0
    _merge_sort_entries(rk[j], rc[j], n, sk, sc)
    _resin_place(rk, rc, rn, j, _resin_start(0, rk.shape[1] - n))


@njit_noalloc
def _resin_live(status, height, idx, key):
    """Whether an entry (cell idx at height ``key``) is still a resin cell at that height."""
    return status[idx] == NONE and height[idx] == key


@njit_noalloc
def _sort_entries(keys, cols, n):
    """Sort the first n entries by key, lowest first (insertion sort: n is small)."""
    for i in range(1, n):
        k = keys[i]
        c = cols[i]
        m = i - 1
        while m >= 0 and keys[m] > k:
            keys[m + 1] = keys[m]
            cols[m + 1] = cols[m]
            m -= 1
        keys[m + 1] = k
        cols[m + 1] = c


#: length of the runs, sorted by insertion, that :func:`_merge_sort_entries` then merges
SORT_RUN = 16


@njit_noalloc
def _merge_sort_entries(keys, cols, n, sk, sc):
    """Sort the first n entries by key, lowest first, keeping the order of equal keys (a
    stable merge sort: the order of ``np.argsort(kind="mergesort")``), with ``sk``/``sc``
    (room for n) as the scratch: nothing is allocated."""
    for lo in range(0, n, SORT_RUN):
        m = min(SORT_RUN, n - lo)
        _sort_entries(keys[lo : lo + m], cols[lo : lo + m], m)
    src_k, src_c, dst_k, dst_c = keys, cols, sk, sc
    in_place = True  # the sorted runs are in keys/cols
    width = SORT_RUN
    while width < n:
        for lo in range(0, n, 2 * width):
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i = lo
            k = mid
            for w in range(lo, hi):
                if k >= hi or (i < mid and src_k[i] <= src_k[k]):
                    dst_k[w] = src_k[i]
                    dst_c[w] = src_c[i]
                    i += 1
                else:
                    dst_k[w] = src_k[k]
                    dst_c[w] = src_c[k]
                    k += 1
        src_k, src_c, dst_k, dst_c = dst_k, dst_c, src_k, src_c
        in_place = not in_place
        width *= 2
    if not in_place:
        for w in range(n):
            keys[w] = sk[w]
            cols[w] = sc[w]


@njit_noalloc
def _merge_entries(keys, cols, n, bk, bc, b):
    """Merge b sorted entries ``bk``/``bc`` into the sorted first n of ``keys``/``cols`` (room
    for n + b), from the top down: entries below the block's lowest key do not move."""
    i = n - 1
    k = b - 1
    w = n + b - 1
    while k >= 0:
        if i >= 0 and keys[i] > bk[k]:
            keys[w] = keys[i]
            cols[w] = cols[i]
            i -= 1
        else:
            keys[w] = bk[k]
            cols[w] = bc[k]
            k -= 1
        w -= 1


@njit_noalloc
def _resin_merge_pending(rk, rc, rn, pk, pc, pn, j, status, height, n_angular, sk, sc):
    """Row j's waiting entries (the live ones) into its sorted entries; a row without room is
    rebuilt from the grid instead (``sk``/``sc``: scratch for ``n_angular`` entries)."""
    row0 = j * n_angular
    p = 0
    for e in range(pn[j]):
        if _resin_live(status, height, row0 + pc[j, e], pk[j, e]):
            pk[j, p] = pk[j, e]
            pc[j, p] = pc[j, e]
            p += 1
    pn[j] = 0
    if not _resin_fit(rk, rc, rn, j, 0, p):
        _resin_build_row(rk, rc, rn, j, status, height, n_angular, sk, sc)
        return
    _sort_entries(pk[j], pc[j], p)
    s = rn[j, RN_S]
    _merge_entries(rk[j, s:], rc[j, s:], rn[j, RN_N], pk[j], pc[j], p)
    rn[j, RN_N] += p


@njit_noalloc
def _resin_cut_cell(idx, height, area, b, outflow, z, wr):
    """Cut resin cell idx (above the disc, area ``area`` [m^2]) to ``z - WR``: its volume
    joins stream bin ``b``. Returns the volume [m^3]."""
    cut = resin_cut_depth(height[idx], z, wr)
    vol = cut * area
    height[idx] -= cut
    outflow[b] += vol
    return vol


@njit_noalloc
def _resin_push(rk, rc, rn, pk, pc, pn, j, col, status, height, n_angular, sk, sc):
    """Cell ``col`` of row j has become resin at its height: it waits in the row's short list
    (merged into the sorted entries first if the list is full; ``sk``/``sc``: scratch for
    ``n_angular`` entries)."""
    if pn[j] == pk.shape[1]:
        _resin_merge_pending(rk, rc, rn, pk, pc, pn, j, status, height, n_angular, sk, sc)
    p = pn[j]
    pk[j, p] = height[j * n_angular + col]
    pc[j, p] = col
    pn[j] = p + 1


@njit_noalloc
def _resin_cut(
    rk,
    rc,
    rn,
    pk,
    pc,
    pn,
    bk,
    bc,
    height,
    status,
    cell_area,
    cell_bin,
    outflow,
    n_radial,
    n_angular,
    n_sub,
    z,
    wr,
):
    """Step phase 3b: every status-none cell above the disc drops to ``z - WR``; the removed
    volume joins the stream of its row and subdomain. Returns the volume removed [m^3].

    Per row, the entries above the disc (the end of the sorted entries, and the waiting ones
    above it, sorted) are cut highest first, stale ones dropped: the order of heights of one
    heap of the grid, so the same sums. The cut cells go back in as one block at their new
    height, below the entries left if it is the lowest (the usual case), else merged from the
    top. ``bk``/``bc`` are scratch for ``n_angular + PEND`` entries (the block from the start,
    a row's waiting entries from the end: a cell is cut once)."""
    removed = 0.0
    top = bk.shape[0]
    width = n_angular // n_sub  # columns per subdomain
    for j in range(n_radial):
        row0 = j * n_angular
        area = cell_area[row0]  # one area per row, one bin per row and subdomain
        b0 = cell_bin[row0]
        n = rn[j, RN_N]
        s = rn[j, RN_S]
        keys, cols = rk[j, s:], rc[j, s:]
        # the waiting entries: those above the disc are cut now, the others wait on
        a = 0
        kept = 0
        for e in range(pn[j]):
            k = pk[j, e]
            col = pc[j, e]
            if not _resin_live(status, height, row0 + col, k):
                continue
            if k > z:
                bk[top - 1 - a] = k  # from the end of the scratch, clear of the block
                bc[top - 1 - a] = col
                a += 1
            else:
                pk[j, kept] = k
                pc[j, kept] = col
                kept += 1
        pn[j] = kept
        lo = n
        while lo > 0 and keys[lo - 1] > z:
            lo -= 1
        if lo == n and a == 0:
            continue
        if a > 1:
            _sort_entries(bk[top - a :], bc[top - a :], a)
        # cut both runs highest first; the cut cells make the block bk[:b] (cut order)
        i = n - 1
        e = top - 1
        b = 0
        while i >= lo or e >= top - a:
            if i - AHEAD >= lo:
                prefetch(status, row0 + cols[i - AHEAD])
                prefetch(height, row0 + cols[i - AHEAD])
            if e < top - a or (i >= lo and keys[i] >= bk[e]):
                k = keys[i]
                col = cols[i]
                i -= 1
            else:
                k = bk[e]
                col = bc[e]
                e -= 1
            idx = row0 + col
            if not _resin_live(status, height, idx, k):
                continue  # stale, or a second entry of a cell cut just now
            removed += _resin_cut_cell(idx, height, area, b0 + col // width, outflow, z, wr)
            bk[b] = height[idx]
            bc[b] = col
            b += 1
        rn[j, RN_N] = lo
        # lowest first: the reverse of the cut order, sorted again if round-off broke a tie
        for q in range(b // 2):
            k = bk[q]
            bk[q] = bk[b - 1 - q]
            bk[b - 1 - q] = k
            col = bc[q]
            bc[q] = bc[b - 1 - q]
            bc[b - 1 - q] = col
        for q in range(1, b):
            if bk[q] < bk[q - 1]:
                _sort_entries(bk, bc, b)
                break
        # the block below the entries left if none is lower (equal keys may go either way:
        # they cut the same volume), else merged in from the top
        low = lo == 0 or (b > 0 and bk[b - 1] <= keys[0])
        if not _resin_fit(rk, rc, rn, j, b if low else 0, 0 if low else b):
            # no room: the row from the grid, its waiting cells included
            _resin_build_row(rk, rc, rn, j, status, height, n_angular, bk, bc)  # bk: free now
            pn[j] = 0
            continue
        s = rn[j, RN_S]
        if low:  # no entry moves
            s -= b
            for q in range(b):
                rk[j, s + q] = bk[q]
                rc[j, s + q] = bc[q]
            rn[j, RN_S] = s
        else:
            _merge_entries(rk[j, s:], rc[j, s:], lo, bk, bc, b)
        rn[j, RN_N] = lo + b
    return removed


# --- building, renormalising and writing back ----------------------------------------------
@njit_noalloc
def _rebuild_row(L, j, z, status, height, cell_bin, base, n_angular, n_sub, p2, sk, sc):
    """Row j from the grid: every plateau cell out of contact (sorted by height, equal heights
    in column order), the map reset to ``h = r + z``; the next evaluation moves the cells in
    contact in. ``sk``/``sc``: scratch for ``n_angular`` entries."""
    (
        rows,
        seg,
        _in_r,
        _in_idx,
        amap,
        out_h,
        out_idx,
        where,
        pos,
        _cell_r,
        bins,
        tree,
        ta,
        _stack,
        _in_s,
        out_s,
        _tdirty,
        tmark,
    ) = L
    row0 = j * n_angular
    tmark[row0 : row0 + n_angular] = 0  # the tree is cleared below; no flags are pending
    n = 0
    for i in range(n_angular):
        idx = row0 + i
        if status[idx] != NONE:
            out_h[row0 + n] = height[idx]
            out_idx[row0 + n] = idx
            n += 1
        else:
            where[idx] = W_NONE
    _merge_sort_entries(out_h[row0 : row0 + n], out_idx[row0 : row0 + n], n, sk, sc)
    for q in range(n):
        idx = out_idx[row0 + q]
        out_s[row0 + q] = status[idx]
        where[idx] = W_OUT
        pos[idx] = q
    rows[j, RW_NIN] = 0
    rows[j, RW_NOUT] = n
    rows[j, RW_KC] = 0
    rows[j, RW_KF] = 0
    rows[j, RW_KS] = 0
    rows[j, RW_KE] = 0
    seg[j, :, :] = 0.0
    bins[j * n_sub : (j + 1) * n_sub, :] = 0.0
    amap[j, 0] = 1.0
    amap[j, 1] = z
    ta[j] = 1.0
    off = j * 2 * p2
    tree[off : off + 2 * p2, TR_W] = -1.0
    tree[off : off + 2 * p2, TR_SUB] = -math.inf


@njit_noalloc
def _renormalise_row(L, j, z, status, cell_bin, base, n_angular, n_sub, p2):
    """Reset row j's map to ``h = r + z`` (a = 1): raw coordinates of the cells in contact
    recomputed (tombstones too, so the order stays), segment, bin sums and the rule-5 tree
    rebuilt from them."""
    (
        rows,
        seg,
        in_r,
        in_idx,
        amap,
        _out_h,
        _out_idx,
        _where,
        _pos,
        cell_r,
        bins,
        tree,
        ta,
        _stack,
        _in_s,
        _out_s,
        _tdirty,
        tmark,
    ) = L
    row0 = j * n_angular
    a = amap[j, 0]
    c = amap[j, 1]
    seg[j, :, :] = 0.0
    bins[j * n_sub : (j + 1) * n_sub, :] = 0.0
    off = j * 2 * p2
    tree[off + p2 : off + 2 * p2, TR_W] = -1.0
    for i in range(n_angular):
        tmark[row0 + i] &= TM_FLAGS
    for q in range(rows[j, RW_NIN]):
        r = (a * in_r[row0 + q] + c) - z
        in_r[row0 + q] = r
        idx = in_idx[row0 + q]
        if idx >= 0:
            cell_r[idx] = r
            _seg_add(seg, j, _seg_of(rows, j, q), r, 1.0)
            _bin_add(bins, cell_bin[idx], status[idx], r, 1.0)
            if status[idx] == SECONDARY:
                leaf = _tree_leaf(p2, j, idx - row0)
                tree[leaf, TR_W] = idx - row0
                tree[leaf, TR_R] = r
                tree[leaf, TR_B] = base[idx]
                tmark[idx] |= TM_LEAF
    amap[j, 0] = 1.0
    amap[j, 1] = z
    ta[j] = 1.0
    _tree_build(tree, p2, j, 1.0)


@njit_noalloc
def _sync_row(L, j, height, n_angular):
    """Write row j's plateau heights back to the grid."""
    rows, in_r, in_idx, amap, out_h, out_idx = L[0], L[2], L[3], L[4], L[5], L[6]
    row0 = j * n_angular
    a = amap[j, 0]
    c = amap[j, 1]
    for q in range(rows[j, RW_NIN]):
        idx = in_idx[row0 + q]
        if idx >= 0:
            height[idx] = a * in_r[row0 + q] + c
    for q in range(rows[j, RW_NOUT]):
        idx = out_idx[row0 + q]
        if idx >= 0:
            height[idx] = out_h[row0 + q]


@njit_noalloc
def _current_height(where, pos, amap, in_r, out_h, idx, n_angular):
    """Height of plateau cell idx now [m]."""
    j = idx // n_angular
    q = j * n_angular + pos[idx]
    if where[idx] == W_IN:
        return amap[j, 0] * in_r[q] + amap[j, 1]
    return out_h[q]


@njit_noalloc
def _remove(rows, seg, in_r, in_idx, out_idx, where, pos, bins, idx, status, cell_bin, n_angular):
    """Take plateau cell idx out of the row structures (a tombstone stays in its array)."""
    j = idx // n_angular
    row0 = j * n_angular
    q = pos[idx]
    if where[idx] == W_IN:
        r = in_r[row0 + q]
        _seg_add(seg, j, _seg_of(rows, j, q), r, -1.0)
        _bin_add(bins, cell_bin[idx], status[idx], r, -1.0)
        in_idx[row0 + q] = -1  # its rule-5 leaf, if any, goes when it surfaces (lazy deletion)
    elif where[idx] == W_OUT:
        out_idx[row0 + q] = -1
    where[idx] = W_NONE


@njit_noalloc
def _push_out(rows, out_h, out_idx, out_s, where, pos, idx, h, n_angular):
    """A new secondary plateau at height h (not above the disc) joins its row out of
    contact."""
    j = idx // n_angular
    row0 = j * n_angular
    if rows[j, RW_NOUT] == n_angular:
        _compact_out(rows, out_h, out_idx, out_s, pos, j, n_angular)
    w = rows[j, RW_NOUT]
    while w > 0 and out_idx[row0 + w - 1] < 0:
        w -= 1  # drop tombstones at the top
    rows[j, RW_NOUT] = w + 1
    while w > 0 and out_h[row0 + w - 1] > h:
        out_h[row0 + w] = out_h[row0 + w - 1]
        out_idx[row0 + w] = out_idx[row0 + w - 1]
        out_s[row0 + w] = out_s[row0 + w - 1]
        if out_idx[row0 + w] >= 0:
            pos[out_idx[row0 + w]] = w
        w -= 1
    out_h[row0 + w] = h
    out_idx[row0 + w] = idx
    out_s[row0 + w] = SECONDARY
    where[idx] = W_OUT
    pos[idx] = w


@njit(cache=True)
def check_invariants(L, status, height, n_radial, n_angular):
    """Every entry of the row arrays agrees with ``where``/``pos``, is a plateau cell, and the
    arrays are sorted (in contact: raw coordinate descending; out of contact: height
    ascending); every plateau cell is held exactly once; each cell's TM_LEAF bit says whether
    its leaf in its row's rule-5 tree holds a line. Returns the number of violations (for the
    tests)."""
    rows, in_r, in_idx, out_h, out_idx, where, pos = L[0], L[2], L[3], L[5], L[6], L[7], L[8]
    tree, tmark = L[11], L[17]
    p2 = tree.shape[0] // (2 * n_radial)
    bad = 0
    for idx in range(status.size):
        j = idx // n_angular
        if ((tmark[idx] & TM_LEAF) != 0) != (
            tree[_tree_leaf(p2, j, idx - j * n_angular), TR_W] >= 0.0
        ):
            bad += 1
    seen = np.zeros(status.size, dtype=np.int64)
    for j in range(n_radial):
        row0 = j * n_angular
        if rows[j, RW_KE] != rows[j, RW_NIN]:
            bad += 1
        last = math.inf
        for q in range(rows[j, RW_NIN]):
            idx = in_idx[row0 + q]
            if idx >= 0:
                seen[idx] += 1
                if where[idx] != W_IN or pos[idx] != q or status[idx] == NONE:
                    bad += 1
                if in_r[row0 + q] > last:
                    bad += 1
                last = in_r[row0 + q]
        last = -math.inf
        for q in range(rows[j, RW_NOUT]):
            idx = out_idx[row0 + q]
            if idx >= 0:
                seen[idx] += 1
                if where[idx] != W_OUT or pos[idx] != q or status[idx] == NONE:
                    bad += 1
                if out_h[row0 + q] < last:
                    bad += 1
                last = out_h[row0 + q]
    for idx in range(status.size):
        if (status[idx] != NONE) != (seen[idx] == 1):
            bad += 1
    return bad


@njit_noalloc
def _prefetch_listed(cells, q, n, a1, a2, a3, a4, a5, a6):
    """Start loading the entries of six per-cell arrays for the cell listed ``AHEAD`` places
    after place q of ``cells[:n]`` (a loop over listed cells, at place q)."""
    if q + AHEAD < n:
        idx = cells[q + AHEAD]
        prefetch(a1, idx)
        prefetch(a2, idx)
        prefetch(a3, idx)
        prefetch(a4, idx)
        prefetch(a5, idx)
        prefetch(a6, idx)


@njit_noalloc
def _held_from_state(L, status, base, cell_area, n_radial, n_angular):
    """Volume held in secondary plateaus, summed cell by cell from the structures [m^3]."""
    rows, in_r, in_idx, amap, out_h, out_idx = L[0], L[2], L[3], L[4], L[5], L[6]
    held = 0.0
    for j in range(n_radial):
        row0 = j * n_angular
        a = amap[j, 0]
        c = amap[j, 1]
        for q in range(rows[j, RW_NIN]):
            idx = in_idx[row0 + q]
            if idx >= 0 and status[idx] == SECONDARY:
                held += (a * in_r[row0 + q] + c - base[idx]) * cell_area[idx]
        for q in range(rows[j, RW_NOUT]):
            idx = out_idx[row0 + q]
            if idx >= 0 and status[idx] == SECONDARY:
                held += (out_h[row0 + q] - base[idx]) * cell_area[idx]
    return held


@njit_noalloc
def _thresholds(stiffness, mu_0, slope, mu_min):
    """(u_c, u_f, u*) [m]: where mu p climbs back to its peak on the floor branch, where the
    floor starts, and where mu p peaks (all equal when mu p is monotone)."""
    if slope <= 0.0:
        return math.inf, math.inf, math.inf
    uf = (mu_0 - mu_min) / (slope * stiffness)
    if 2.0 * mu_min >= mu_0:
        return uf, uf, uf
    us = mu_0 / (2.0 * slope * stiffness)
    uc = mu_0 * mu_0 / (4.0 * slope * mu_min * stiffness) if mu_min > 0.0 else math.inf
    return uc, uf, us


@njit(cache=True)
def run_stop_lazy(
    L,
    height,
    base,
    status,
    cand,
    ncand,
    cmax,
    mark,
    inflow,
    outflow,
    resin_key,
    resin_col,
    resin_n,
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
    p2,
    stiffness,
    mu_0,
    slope,
    mu_min,
    wear_rate,
    resin_depth,
    bar_length,
    east_to_west,
    targets,
    fraction,
    ledger_tol,
    rec,
    rule_counts,
    created,
    destroyed,
    dheight,
    marked,
    tot,
    walk,
    prof,
):
    """Run every step of one stop in place (the lazy kernel; arguments as
    :func:`brakeca._kernels.run_stop`, plus the lazy structures ``L`` and scratch; the resin
    cells are in per-row sorted entries ``resin_key``, ``resin_col``, ``resin_n``, built from
    the grid here). Returns (code, steps done)."""
    (
        rows,
        seg,
        in_r,
        in_idx,
        amap,
        out_h,
        out_idx,
        where,
        pos,
        cell_r,
        bins,
        tree,
        ta,
        stack,
        in_s,
        out_s,
        tdirty,
        tmark,
    ) = L
    uc, uf, us = _thresholds(stiffness, mu_0, slope, mu_min)
    ztop = -math.inf
    for idx in range(status.size):
        if status[idx] != NONE and height[idx] > ztop:
            ztop = height[idx]
    if ztop == -math.inf:
        return ERR_NO_PLATEAU, 0
    # the rule-5 list left by the last step of the stop before: the trees are rebuilt here,
    # and _rebuild_row clears every cell's marks
    tdirty[0] = 0
    # the resin cut's scratch (and the sorts' of the rows' entries)
    blk_key = np.empty(n_angular + PEND)
    blk_col = np.empty(n_angular + PEND, dtype=np.int32)
    for j in range(n_radial):
        _rebuild_row(
            L, j, ztop, status, height, cell_bin, base, n_angular, n_sub, p2, blk_key, blk_col
        )
        _resin_build_row(
            resin_key, resin_col, resin_n, j, status, height, n_angular, blk_key, blk_col
        )
    # the rows' waiting resin entries (none at the start: the rows were built above)
    pend_key = np.empty((n_radial, PEND))
    pend_col = np.empty((n_radial, PEND), dtype=np.int32)
    pend_n = np.zeros(n_radial, dtype=np.int64)
    sums = np.zeros(N_SUMS)
    m = 1
    while m < n_radial:
        m *= 2
    evt = np.full(2 * m, -math.inf)
    n_steps = fraction.size
    z = ztop
    for step in range(n_steps):
        frac = fraction[step]
        t0 = _clock()
        for j in range(n_radial):
            if amap[j, 0] < RENORM_SCALE or (step > 0 and step % RENORM_EVERY == 0):
                _renormalise_row(L, j, z, status, cell_bin, base, n_angular, n_sub, p2)
        z, code = solve_contact(
            L,
            z,
            targets[step],
            tot,
            evt,
            status,
            cell_bin,
            base,
            n_radial,
            n_angular,
            n_sub,
            p2,
            bin_area,
            stiffness,
            mu_0,
            slope,
            mu_min,
            uc,
            uf,
            us,
            walk,
        )
        for j in range(n_radial):
            nin = rows[j, RW_NIN]
            if rows[j, RW_KE] < nin or (nin > 0 and in_idx[j * n_angular + nin - 1] < 0):
                _commit_row(
                    rows,
                    in_r,
                    in_idx,
                    amap,
                    out_h,
                    out_idx,
                    where,
                    pos,
                    bins,
                    in_s,
                    out_s,
                    tdirty,
                    tmark,
                    j,
                    n_sub,
                    n_angular,
                )
        if code != 0 or tot[E_AREA] == 0.0:
            sync(L, height, n_radial, n_angular)
            return ERR_NO_PLATEAU, step
        _tree_flush(tree, p2, ta, cell_r, base, where, tdirty, tmark, n_angular)
        umax = -math.inf
        for j in range(n_radial):
            row0 = j * n_angular
            for q in range(rows[j, RW_NIN]):
                if in_idx[row0 + q] >= 0:
                    u = amap[j, 0] * in_r[row0 + q] + amap[j, 1] - z
                    if u > umax:
                        umax = u
                    break
        if umax > bar_length:
            sync(L, height, n_radial, n_angular)
            return ERR_BAR, step
        sums[S_FRICTION] = tot[E_F]
        sums[S_NORMAL] = stiffness * tot[E_AU]
        sums[S_CONTACT] = tot[E_AREA]
        t1 = _clock()
        prof[T_CONTACT] += t1 - t0
        # rule 4 on the start-of-step statuses (marks only)
        n4 = 0
        for q in range(cnt[CNT_RULE4]):
            if q + AHEAD < cnt[CNT_RULE4]:
                ahead = rule4_list[q + AHEAD]
                prefetch(mark, ahead)
                prefetch(status, ahead)
            idx = rule4_list[q]
            if mark[idx] or not rule4_lost_support(status, idx, n_angular):
                continue
            mark[idx] = 4
            rule_counts[4] += 1
            marked[n4] = idx
            n4 += 1
        cnt[CNT_RULE4] = 0
        # Archard wear of every cell in contact: volumes per stream bin, then the row maps
        removed = 0.0
        held_out = 0.0
        for j in range(n_radial):
            b0 = j * n_sub
            alpha = wear_rate * stiffness * bin_slide[b0] * frac
            a = amap[j, 0]
            c = amap[j, 1]
            d = c - z
            area = bin_area[b0]
            for k in range(n_sub):
                b = b0 + k
                vp = alpha * area * (a * bins[b, 1] + d * bins[b, 0])
                vs = alpha * area * (a * bins[b, 3] + d * bins[b, 2])
                outflow[b] += vp + vs
                removed += vp
                held_out += vs
            beta = 1.0 - alpha
            amap[j, 0] = beta * a
            amap[j, 1] = beta * c + alpha * z
        acc[ACC_HELD] -= held_out
        # rule 5: secondary plateaus worn through their deposit (wear clipped at it)
        n_dest = 0
        for j in range(n_radial):
            off = j * 2 * p2
            a = amap[j, 0]
            c = amap[j, 1]
            if tree[off + 1, TR_W] < 0.0:
                ta[j] = a
                continue
            _tree_advance(tree, p2, j, a, stack)
            ta[j] = a
            row0 = j * n_angular
            while tree[off + 1, TR_W] >= 0.0:
                col = int(tree[off + 1, TR_W])
                idx = row0 + col
                if where[idx] != W_IN:  # the leaf of a plateau destroyed since: drop it
                    _tree_set(tree, p2, j, col, False, a, 0.0, 0.0)
                    tmark[idx] &= TM_FLAGS
                    continue
                h_new = a * cell_r[idx] + c
                if h_new > base[idx]:
                    break
                corr = (base[idx] - h_new) * cell_area[idx]
                outflow[cell_bin[idx]] -= corr
                acc[ACC_HELD] += corr
                _remove(
                    rows,
                    seg,
                    in_r,
                    in_idx,
                    out_idx,
                    where,
                    pos,
                    bins,
                    idx,
                    status,
                    cell_bin,
                    n_angular,
                )
                _tree_set(tree, p2, j, col, False, a, 0.0, 0.0)
                tmark[idx] &= TM_FLAGS
                if mark[idx] == 4:
                    rule_counts[4] -= 1  # worn through: counted as rule 5
                mark[idx] = 5
                rule_counts[5] += 1
                destroyed[n_dest] = idx
                dheight[n_dest] = base[idx]
                n_dest += 1
        # rule 4: destroyed at their height after this step's wear
        for q in range(n4):
            if q + AHEAD < n4:
                ahead = marked[q + AHEAD]
                prefetch(mark, ahead)
                prefetch(where, ahead)
                prefetch(pos, ahead)
                # half as far ahead, its position is known by now: its entry
                ahead = marked[q + AHEAD // 2]
                prefetch(in_r, ahead - ahead % n_angular + pos[ahead])
            idx = marked[q]
            if mark[idx] != 4:
                continue
            dheight[n_dest] = _current_height(where, pos, amap, in_r, out_h, idx, n_angular)
            _remove(
                rows, seg, in_r, in_idx, out_idx, where, pos, bins, idx, status, cell_bin, n_angular
            )
            destroyed[n_dest] = idx
            n_dest += 1
        t2 = _clock()
        prof[T_WEAR] += t2 - t1
        sums[S_REMOVED] = removed + _resin_cut(
            resin_key,
            resin_col,
            resin_n,
            pend_key,
            pend_col,
            pend_n,
            blk_key,
            blk_col,
            height,
            status,
            cell_area,
            cell_bin,
            outflow,
            n_radial,
            n_angular,
            n_sub,
            z,
            resin_depth,
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
        # the status changes take effect together
        for q in range(n_dest):
            _prefetch_listed(destroyed, q, n_dest, cell_area, base, height, cell_bin, status, mark)
            idx = destroyed[q]
            area = cell_area[idx]
            dep = (dheight[q] - base[idx]) * area
            outflow[cell_bin[idx]] += dep
            acc[ACC_HELD] -= dep
            height[idx] = base[idx]
            acc[ACC_SECONDARY_AREA] -= area
            cnt[CNT_SECONDARY] -= 1
            status[idx] = NONE
            j = idx // n_angular
            _resin_push(
                resin_key,
                resin_col,
                resin_n,
                pend_key,
                pend_col,
                pend_n,
                j,
                idx - j * n_angular,
                status,
                height,
                n_angular,
                blk_key,
                blk_col,
            )
        for q in range(n_new):
            _prefetch_listed(created, q, n_new, cell_area, height, tmark, base, where, pos)
            idx = created[q]
            area = cell_area[idx]
            acc[ACC_HELD] += (z - height[idx]) * area
            acc[ACC_SECONDARY_AREA] += area
            j = idx // n_angular
            if tmark[idx] & TM_LEAF:
                # the stale leaf of a plateau destroyed here before: its line changes now, and
                # the next flush updates its path once (removed, or the new line if the new
                # plateau is in contact by then); nothing reads the tree until that flush
                _tree_dirty(tdirty, tmark, idx, TM_STALE)
            base[idx] = height[idx]
            height[idx] = z
            status[idx] = SECONDARY
            _push_out(rows, out_h, out_idx, out_s, where, pos, idx, z, n_angular)
        cnt[CNT_SECONDARY] += n_new
        for q in range(n_dest):
            if q + AHEAD < n_dest:
                prefetch(cand, destroyed[q + AHEAD])
            idx = destroyed[q]
            mark[idx] = 0
            refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular)
            if idx % n_angular > 0:
                refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx - 1, n_angular)
                rule4_list[cnt[CNT_RULE4]] = idx - 1
                cnt[CNT_RULE4] += 1
        for q in range(n_new):
            if q + AHEAD < n_new:
                prefetch(cand, created[q + AHEAD])
            idx = created[q]
            refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx, n_angular)
            if idx % n_angular > 0:
                refresh_candidate(status, height, cand, ncand, cmax, cell_bin, idx - 1, n_angular)
        t5 = _clock()
        prof[T_APPLY] += t5 - t4
        emitted, stream = phase_advance(inflow, outflow, n_radial, n_sub)
        acc[ACC_EMITTED] += emitted
        if step == n_steps - 1:
            held = _held_from_state(L, status, base, cell_area, n_radial, n_angular)
        else:
            held = acc[ACC_HELD]
        rel = record_step(rec, step, sums, acc, emitted, held, stream, z, targets[step])
        prof[T_REST] += _clock() - t5
        if rel > ledger_tol:
            sync(L, height, n_radial, n_angular)
            return ERR_LEDGER, step + 1
    sync(L, height, n_radial, n_angular)
    return OK, n_steps


@njit_noalloc
def sync(L, height, n_radial, n_angular):
    """Write every plateau height back to the grid."""
    for j in range(n_radial):
        _sync_row(L, j, height, n_angular)
