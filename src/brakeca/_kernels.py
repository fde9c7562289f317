"""Compiled step kernels (numba) and nothing else.

One call runs every time step of one stop, so Python overhead is paid per stop, not per step.
The physics lives in named functions of :mod:`brakeca.contact`, :mod:`brakeca.friction`,
:mod:`brakeca.wear` and :mod:`brakeca.automaton`; this module wires them in the order of a step
(decision, docs/model.md):

1. contact solve on the current heights (first root of the torque balance) -> z, p;
2. friction;
3. wear: Archard on plateau cells in contact, then the resin cut;
4. rules, reading the statuses at the start of the step: destruction (4-7), then creation
   (1-3) drawing on the inflow, gaps measured to this step's z;
5. the particle streams advance one subdomain; what leaves the last subdomain is emitted.

State arrays are flat (index ``j * n_angular + i``). ``fastmath`` stays off: results are
bit-reproducible.
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
ACC_NONE_MAX = 2  # an upper bound of the heights of status-none cells [m]
N_ACC = 3

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
N_REC = 12

# error codes
OK = 0
ERR_NO_PLATEAU = 1
ERR_BAR = 2
ERR_LEDGER = 3


@njit(cache=True)
def sort_order(order, n, height):
    """Insertion sort of ``order[:n]`` by height, highest first (stable).

    Linear in n plus the number of inversions: the order is nearly sorted from the last step.
    """
    for a in range(1, n):
        key = order[a]
        hk = height[key]
        b = a - 1
        while b >= 0 and height[order[b]] < hk:
            order[b + 1] = order[b]
            b -= 1
        order[b + 1] = key


@njit(cache=True)
def run_stop(
    height, base, status, fibre_floor, inflow, outflow, order, n_plat_arr, acc,
    cell_area_row, slide_row, n_radial, n_angular, n_sub,
    stiffness, mu_0, slope, mu_min, wear_rate, resin_depth, rule6_gap, bar_length,
    east_to_west, target, fraction, ledger_tol, rec, rule_counts, created, destroyed,
):
    """Run every step of one stop in place.

    Parameters
    ----------
    height, base, fibre_floor : float64[n_cells]
        Cell height [m]; height under the deposit of secondary cells [m]; fibre underside [m].
    status : int8[n_cells]
        NONE / PRIMARY / SECONDARY.
    inflow, outflow : float64[n_radial, n_sub]
        Particle volume that entered subdomain k this step, and the volume leaving it [m^3].
    order : int64[n_cells]
        Plateau cells sorted by height (highest first) in ``order[:n_plat_arr[0]]``.
    n_plat_arr : int64[1]
        Number of plateau cells.
    acc : float64[N_ACC]
        Run accumulators (removed, emitted, bound on resin heights).
    cell_area_row, slide_row : float64[n_radial]
        Cell area [m^2] and full-step sliding distance [m] of each row.
    n_radial, n_angular, n_sub : int
        Grid shape and number of subdomains.
    stiffness, mu_0, slope, mu_min, wear_rate, resin_depth, rule6_gap, bar_length : float
        K [Pa/m], friction law [-, 1/Pa, -], WP [m^3/(N m)], WR [m], rule-6 gap [m] (inf: off),
        foundation bar length [m].
    east_to_west : bool
        Candidates draw on the inflow east to west instead of west to east.
    target : float
        Demanded friction force of the band [N].
    fraction : float64[n_steps]
        Fraction of a full step slid in each step [-].
    ledger_tol : float
        Relative ledger residual that stops the run [-].
    rec : float64[n_steps, N_REC]
        Per-step record (output).
    rule_counts : int64[8]
        Firings of rules 1..7 (index = rule number), accumulated.
    created, destroyed : int64[n_cells]
        Scratch lists.

    Returns
    -------
    code : int
        OK, or an error code; on error ``rec[step]`` of the failing step is not written.
    step : int
        Number of steps completed.
    """
    n_cells = n_radial * n_angular
    n_m = n_angular // n_sub
    for step in range(fraction.size):
        frac = fraction[step]
        n_plat = n_plat_arr[0]
        # ---- 1. contact solve ----------------------------------------------------------
        sort_order(order, n_plat, height)
        z, n_in, code = first_root(order, n_plat, height, cell_area_row, n_angular, stiffness,
                                   mu_0, slope, mu_min, target)
        if code != SOLVE_OK:
            return ERR_NO_PLATEAU, step
        if height[order[0]] - z > bar_length:
            return ERR_BAR, step
        # ---- 2. friction and 3a. Archard wear of plateaus in contact --------------------
        f_fric = 0.0
        f_norm = 0.0
        a_contact = 0.0
        generated = 0.0
        removed = 0.0
        for q in range(n_in):
            idx = order[q]
            u = height[idx] - z
            if u <= 0.0:
                continue
            j = idx // n_angular
            k = (idx - j * n_angular) // n_m
            area = cell_area_row[j]
            p = stiffness * u
            mu = local_cof(p, mu_0, slope, mu_min)
            f_fric += mu * p * area
            f_norm += p * area
            a_contact += area
            dh = archard_wear_depth(wear_rate, p, slide_row[j] * frac, u)
            if status[idx] == SECONDARY:
                dep = height[idx] - base[idx]
                if dh >= dep:
                    dh = dep
                    height[idx] = base[idx]  # deposit used up (rule 5 fires below)
                else:
                    height[idx] -= dh
                outflow[j, k] += dh * area  # held -> stream: not new wear
            else:
                height[idx] -= dh
                vol = dh * area
                outflow[j, k] += vol
                removed += vol
                generated += vol
        # ---- 3b. resin cut: status-none cells above the disc drop to z - WR --------------
        if acc[ACC_NONE_MAX] > z:
            new_max = -math.inf
            for idx in range(n_cells):
                if status[idx] != NONE:
                    continue
                cut = resin_cut_depth(height[idx], z, resin_depth)
                if cut > 0.0:
                    j = idx // n_angular
                    k = (idx - j * n_angular) // n_m
                    vol = cut * cell_area_row[j]
                    height[idx] -= cut
                    outflow[j, k] += vol
                    removed += vol
                    generated += vol
                if height[idx] > new_max:
                    new_max = height[idx]
            acc[ACC_NONE_MAX] = new_max
        acc[ACC_REMOVED] += removed
        # ---- 4a. destruction (rules 4-7), statuses as at the start of the step -----------
        n_dest = 0
        for q in range(n_plat):
            idx = order[q]
            s = status[idx]
            fire = 0
            if s == SECONDARY:
                if rule5_deposit_worn(s, height[idx], base[idx]):
                    fire = 5
                elif rule4_lost_support(status, idx, n_angular):
                    fire = 4
            else:
                if rule7_fibre_worn(s, height[idx], fibre_floor[idx]):
                    fire = 7
                elif rule6_primary_out_of_reach(s, height[idx], z, rule6_gap):
                    fire = 6
            if fire:
                destroyed[n_dest] = idx
                n_dest += 1
                rule_counts[fire] += 1
        # ---- 4b. creation (rules 1-3) drawing on this step's inflow, row by row ----------
        n_new = 0
        for j in range(n_radial):
            area = cell_area_row[j]
            for k in range(1, n_sub):
                rest = inflow[j, k]
                if rest > 0.0:
                    i0 = j * n_angular + k * n_m
                    for c in range(n_m):
                        idx = i0 + (n_m - 1 - c if east_to_west else c)
                        rule = creation_rule(status, idx, n_radial, n_angular)
                        if rule == 0:
                            continue
                        cost = gap_fill_cost(z, height[idx], area)
                        if cost <= rest:
                            rest -= cost
                            created[n_new] = idx
                            n_new += 1
                            rule_counts[rule] += 1
                outflow[j, k] += rest
        # ---- apply the status changes --------------------------------------------------
        for q in range(n_dest):
            idx = destroyed[q]
            if status[idx] == SECONDARY:
                j = idx // n_angular
                k = (idx - j * n_angular) // n_m
                outflow[j, k] += (height[idx] - base[idx]) * cell_area_row[j]
                height[idx] = base[idx]
            status[idx] = NONE
            if height[idx] > acc[ACC_NONE_MAX]:
                acc[ACC_NONE_MAX] = height[idx]
        for q in range(n_new):
            idx = created[q]
            base[idx] = height[idx]
            height[idx] = z
            status[idx] = SECONDARY
        if n_dest or n_new:
            # compact the order, inserting the new cells (h = z) after the cells in contact
            w = 0
            for q in range(n_plat):
                if q == n_in:
                    for c in range(n_new):
                        destroyed[w] = created[c]  # reuse as scratch
                        w += 1
                idx = order[q]
                if status[idx] != NONE:
                    destroyed[w] = idx
                    w += 1
            if n_in >= n_plat:
                for c in range(n_new):
                    destroyed[w] = created[c]
                    w += 1
            for q in range(w):
                order[q] = destroyed[q]
            n_plat_arr[0] = w
            n_plat = w
        # ---- 5. streams advance; ledger ------------------------------------------------
        emitted = 0.0
        stream = 0.0
        for j in range(n_radial):
            emitted += outflow[j, n_sub - 1]
            for k in range(n_sub - 1, 0, -1):
                inflow[j, k] = outflow[j, k - 1]
                stream += inflow[j, k]
            inflow[j, 0] = 0.0
            for k in range(n_sub):
                outflow[j, k] = 0.0
        acc[ACC_EMITTED] += emitted
        held = 0.0
        a_prim = 0.0
        a_sec = 0.0
        for q in range(n_plat):
            idx = order[q]
            area = cell_area_row[idx // n_angular]
            if status[idx] == SECONDARY:
                held += (height[idx] - base[idx]) * area
                a_sec += area
            else:
                a_prim += area
        total = acc[ACC_REMOVED]
        resid = total - (held + stream + acc[ACC_EMITTED])
        scale = total if total > 0.0 else 1.0
        rel = abs(resid) / scale if total > 0.0 else abs(resid)
        rec[step, R_COF] = f_fric / f_norm if f_norm > 0.0 else 0.0
        rec[step, R_NORMAL] = f_norm
        rec[step, R_FRICTION] = f_fric
        rec[step, R_CONTACT_AREA] = a_contact
        rec[step, R_PRIMARY_AREA] = a_prim
        rec[step, R_SECONDARY_AREA] = a_sec
        rec[step, R_EMITTED] = emitted
        rec[step, R_GENERATED] = generated
        rec[step, R_LEDGER] = rel
        rec[step, R_DISC] = z
        rec[step, R_HELD] = held
        rec[step, R_STREAM] = stream
        if rel > ledger_tol:
            return ERR_LEDGER, step + 1
    return OK, fraction.size


def empty_record(n_steps: int) -> np.ndarray:
    """A per-step record array for ``n_steps`` steps."""
    return np.zeros((n_steps, N_REC), dtype=np.float64)
