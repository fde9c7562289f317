"""The seven plateau rules of the cellular automaton (Section 2.2 of the paper).

Each rule is a named, compiled function of the statuses at the start of the step (synchronous
update, decision). Cells are addressed by their flat index ``idx = j * n_angular + i``; east is
``+1`` (the sliding direction), north is ``+n_angular`` (outwards). A neighbour outside the grid is
"not a plateau".

Creation of secondary plateaus (a cell of status none, upstream of a plateau):
rule 1: a plateau to the east only; rule 2: east and one of north-east / south-east;
rule 3: east, north-east and south-east. The cell is filled if the inflowing particle volume
covers the gap to the disc, ``(z - h) A``.

Destruction: rule 4, a secondary plateau with no plateau directly east (lost its support);
rule 5, a secondary plateau whose deposit is worn away; rule 6, a primary plateau too far below
the disc (off by default); rule 7, a primary plateau worn below its fibre.

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.2.
"""

from __future__ import annotations

from brakeca._jit import njit_noalloc

__all__ = [
    "creation_rule",
    "gap_fill_cost",
    "rule1_east_support",
    "rule2_east_and_one_diagonal",
    "rule3_east_and_both_diagonals",
    "rule4_lost_support",
    "rule5_deposit_worn",
    "rule6_primary_out_of_reach",
    "rule7_fibre_worn",
]

_NONE = 0


@njit_noalloc
def _plateau(status, idx: int) -> bool:
    return status[idx] != _NONE


@njit_noalloc
def _supports(status, idx: int, n_radial: int, n_angular: int):
    """(east, north-east, south-east) plateau flags of cell idx; off-grid counts as none."""
    j = idx // n_angular
    i = idx - j * n_angular
    if i + 1 >= n_angular:
        return False, False, False
    east = _plateau(status, idx + 1)
    ne = j + 1 < n_radial and _plateau(status, idx + n_angular + 1)
    se = j >= 1 and _plateau(status, idx - n_angular + 1)
    return east, ne, se


@njit_noalloc
def rule1_east_support(status, idx: int, n_radial: int, n_angular: int) -> bool:
    """Rule 1: a none cell with a plateau east and none north-east or south-east."""
    if status[idx] != _NONE:
        return False
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    return e and not ne and not se


@njit_noalloc
def rule2_east_and_one_diagonal(status, idx: int, n_radial: int, n_angular: int) -> bool:
    """Rule 2: a none cell with a plateau east and exactly one of north-east / south-east."""
    if status[idx] != _NONE:
        return False
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    return e and (ne != se)


@njit_noalloc
def rule3_east_and_both_diagonals(status, idx: int, n_radial: int, n_angular: int) -> bool:
    """Rule 3: a none cell with plateaus east, north-east and south-east."""
    if status[idx] != _NONE:
        return False
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    return e and ne and se


@njit_noalloc
def creation_rule(status, idx: int, n_radial: int, n_angular: int) -> int:
    """Which creation rule (1, 2 or 3) makes cell idx a candidate; 0 if none does."""
    if status[idx] != _NONE:
        return 0
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    if not e:
        return 0
    return 1 + int(ne) + int(se)


@njit_noalloc
def gap_fill_cost(disc_position: float, height: float, cell_area: float) -> float:
    """Particle volume needed to fill a cell's gap to the disc, ``(z - h) A`` [m^3]."""
    return (disc_position - height) * cell_area


@njit_noalloc
def rule4_lost_support(status, idx: int, n_angular: int) -> bool:
    """Rule 4: a secondary plateau with no plateau directly east (fewer than one eastern
    plateau neighbour) loses its support and is destroyed."""
    if status[idx] != 2:
        return False
    i = idx % n_angular
    return i + 1 >= n_angular or status[idx + 1] == _NONE


@njit_noalloc
def rule5_deposit_worn(status, height: float, deposit_base: float) -> bool:
    """Rule 5: a secondary plateau whose deposit has been worn away is destroyed."""
    return status == 2 and height <= deposit_base


@njit_noalloc
def rule6_primary_out_of_reach(status, height: float, disc_position: float, max_gap: float) -> bool:
    """Rule 6: a primary plateau whose gap to the disc exceeds ``max_gap`` [m] is destroyed
    (reading of "its height is less than the minimum gap"; ``max_gap = inf`` switches it off)."""
    return status == 1 and disc_position - height > max_gap


@njit_noalloc
def rule7_fibre_worn(status, height: float, fibre_floor: float) -> bool:
    """Rule 7: a primary plateau worn down to the underside of its fibre is destroyed
    (never with fibres as columns, whose floor is -inf)."""
    return status == 1 and height <= fibre_floor
