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

Between stops, with the fibre field (``pad.fibre_model = "field"``): a cell whose pad surface is
worn down into a buried fibre becomes a primary plateau again (:func:`expose_buried_fibres`;
NumPy, not compiled: it runs once a stop).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.2.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from brakeca import _cachedir
from brakeca._jit import njit_noalloc

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

__all__ = [
    "Exposure",
    "creation_rule",
    "expose_buried_fibres",
    "gap_fill_cost",
    "pad_surface",
    "rule1_east_support",
    "rule2_east_and_one_diagonal",
    "rule3_east_and_both_diagonals",
    "rule4_lost_support",
    "rule5_deposit_worn",
    "rule6_primary_out_of_reach",
    "rule7_fibre_worn",
]

_NONE = 0
_PRIMARY = 1
_SECONDARY = 2


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
    """Rule 1: a none cell with a plateau east and none north-east or south-east.

    Parameters
    ----------
    status : int8 array (n_cells,)
        Cell statuses at the start of the step, flat (``idx = j * n_angular + i``): 0 none,
        1 primary, 2 secondary [-].
    idx : int
        Flat index of the cell [-].
    n_radial, n_angular : int
        Rows and columns of the grid [-].

    Returns
    -------
    bool
        Whether rule 1 makes the cell a creation candidate (off-grid neighbours count as
        none).

    Notes
    -----
    ``rule1 = (status[j, i] = none) and E and not NE and not SE`` for the cell ``(j, i)``,
    with ``E = status[j, i+1] != none``, ``NE = status[j+1, i+1] != none`` and
    ``SE = status[j-1, i+1] != none``; a neighbour off the grid (past the trailing edge or the
    radial edges) is not a plateau. The paper's rule 1 asks for one plateau neighbour to the
    east; rules 2 and 3 take the cells that also have diagonal support, so the three rules
    are disjoint. Primary and secondary plateaus both count as neighbours (a decision,
    docs/model.md section 7, rules 1-3, and the table of decisions fixed in code).

    A candidate becomes a secondary plateau, rising to ``z``, if the inflow still available to
    its row and subdomain covers its gap ``(z - h) A_j`` (:func:`gap_fill_cost`); that test is
    the creation step's, not this function's. The kernels flag candidates (a plateau directly
    east) in ``_kernels.refresh_candidate`` without calling this function; it states the rule
    and is tested cell by cell (docs/model.md, introduction).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    if status[idx] != _NONE:
        return False
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    return e and not ne and not se


@njit_noalloc
def rule2_east_and_one_diagonal(status, idx: int, n_radial: int, n_angular: int) -> bool:
    """Rule 2: a none cell with a plateau east and exactly one of north-east / south-east.

    Parameters
    ----------
    status : int8 array (n_cells,)
        Cell statuses at the start of the step, flat (``idx = j * n_angular + i``): 0 none,
        1 primary, 2 secondary [-].
    idx : int
        Flat index of the cell [-].
    n_radial, n_angular : int
        Rows and columns of the grid [-].

    Returns
    -------
    bool
        Whether rule 2 makes the cell a creation candidate (off-grid neighbours count as
        none).

    Notes
    -----
    ``rule2 = (status[j, i] = none) and E and (NE xor SE)`` for the cell ``(j, i)``, with
    ``E``, ``NE`` and ``SE`` as in :func:`rule1_east_support` (``status != none`` of the cell
    east, north-east and south-east; off the grid, not a plateau). The paper's rule 2: a
    plateau to the east and one to the north-east or south-east. Primary and secondary
    plateaus both count as neighbours, and more support does not make filling cheaper
    (decisions, docs/model.md section 7, rules 1-3).

    Whether a candidate becomes a secondary plateau, and where the kernels flag it, is as
    :func:`rule1_east_support` says.

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    if status[idx] != _NONE:
        return False
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    return e and (ne != se)


@njit_noalloc
def rule3_east_and_both_diagonals(status, idx: int, n_radial: int, n_angular: int) -> bool:
    """Rule 3: a none cell with plateaus east, north-east and south-east.

    Parameters
    ----------
    status : int8 array (n_cells,)
        Cell statuses at the start of the step, flat (``idx = j * n_angular + i``): 0 none,
        1 primary, 2 secondary [-].
    idx : int
        Flat index of the cell [-].
    n_radial, n_angular : int
        Rows and columns of the grid [-].

    Returns
    -------
    bool
        Whether rule 3 makes the cell a creation candidate.

    Notes
    -----
    ``rule3 = (status[j, i] = none) and E and NE and SE`` for the cell ``(j, i)``, with ``E``,
    ``NE`` and ``SE`` as in :func:`rule1_east_support` (``status != none`` of the cell east,
    north-east and south-east; off the grid, not a plateau). The paper's rule 3: plateaus to
    the east, the north-east and the south-east. Primary and secondary plateaus both count as
    neighbours, and more support does not make filling cheaper (decisions, docs/model.md
    section 7, rules 1-3).

    Whether a candidate becomes a secondary plateau, and where the kernels flag it, is as
    :func:`rule1_east_support` says.

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    if status[idx] != _NONE:
        return False
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    return e and ne and se


@njit_noalloc
def creation_rule(status, idx: int, n_radial: int, n_angular: int) -> int:
    """Which creation rule (1, 2 or 3) makes cell idx a candidate; 0 if none does.

    Parameters
    ----------
    status : int8 array (n_cells,)
        Cell statuses at the start of the step, flat (``idx = j * n_angular + i``): 0 none,
        1 primary, 2 secondary [-].
    idx : int
        Flat index of the cell [-].
    n_radial, n_angular : int
        Rows and columns of the grid [-].

    Returns
    -------
    int
        1, 2 or 3: the rule (1 + the number of diagonal plateau neighbours, given a plateau
        east); 0 when the cell is not a none cell or has no plateau east [-].

    Notes
    -----
    ``rule = 1 + NE + SE`` if ``status[j, i] = none`` and ``E``, else 0, for the cell
    ``(j, i)``, with ``E``, ``NE`` and ``SE`` (1 or 0) as in :func:`rule1_east_support`
    (``status != none`` of the cell east, north-east and south-east; off the grid, not a
    plateau). It returns ``k`` exactly when rule ``k`` holds (:func:`rule1_east_support`,
    :func:`rule2_east_and_one_diagonal`, :func:`rule3_east_and_both_diagonals`). The exact
    kernel calls it only to count which rule created each secondary plateau
    (``rule_firings``); candidacy itself is the flag of ``_kernels.refresh_candidate``
    (docs/model.md, introduction and section 7, rules 1-3).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    if status[idx] != _NONE:
        return 0
    e, ne, se = _supports(status, idx, n_radial, n_angular)
    if not e:
        return 0
    return 1 + int(ne) + int(se)


@njit_noalloc
def gap_fill_cost(disc_position: float, height: float, cell_area: float) -> float:
    """Particle volume needed to fill a cell's gap to the disc, ``(z - h) A`` [m^3], for the
    disc at ``disc_position`` z [m], the cell's height ``height`` h [m] and area ``cell_area``
    A [m^2].

    Parameters
    ----------
    disc_position : float
        Disc surface position z of the step [m].
    height : float
        Height h of the cell [m].
    cell_area : float
        Area A of the cell [m^2].

    Returns
    -------
    float
        Gap volume ``(z - h) A`` [m^3] (negative for a cell above the disc; not clipped).
    """
    return (disc_position - height) * cell_area


@njit_noalloc
def rule4_lost_support(status, idx: int, n_angular: int) -> bool:
    """Rule 4: a secondary plateau with no plateau directly east (fewer than one eastern
    plateau neighbour) loses its support and is destroyed.

    Parameters
    ----------
    status : int8 array (n_cells,)
        Cell statuses at the start of the step, flat (``idx = j * n_angular + i``): 0 none,
        1 primary, 2 secondary [-].
    idx : int
        Flat index of the cell [-].
    n_angular : int
        Columns of the grid [-].

    Returns
    -------
    bool
        Whether the cell is a secondary plateau whose east neighbour is none or off the grid
        (a cell in the last column).

    Notes
    -----
    ``rule4 = (status[j, i] = secondary) and (i = n_angular - 1 or status[j, i+1] = none)``.
    The paper destroys a secondary plateau with "fewer than one eastern plateau neighbour";
    reading that neighbour as the cell directly east (the sliding direction), not the three
    eastern cells, is a decision (docs/model.md section 7, rule 4, and the table of
    decisions fixed in code). It reads the statuses at the start of the step (synchronous
    update); the destroyed plateau's remaining deposit returns to the stream of its row and
    subdomain. Both kernels call this function.

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    if status[idx] != 2:
        return False
    i = idx % n_angular
    return i + 1 >= n_angular or status[idx + 1] == _NONE


@njit_noalloc
def rule5_deposit_worn(status, height: float, deposit_base: float) -> bool:
    """Rule 5: a secondary plateau (status 2) whose deposit has been worn away is destroyed:
    its height ``height`` [m] at or below its deposit's base ``deposit_base`` [m].

    Parameters
    ----------
    status : int
        Status of the cell: 0 none, 1 primary, 2 secondary [-].
    height : float
        Height of the cell after this step's wear [m].
    deposit_base : float
        Height under the cell's deposit [m].

    Returns
    -------
    bool
        Whether the cell is a secondary plateau with ``height <= deposit_base``.

    Notes
    -----
    ``rule5 = (status = secondary) and h <= b``, with ``h`` the height after this step's
    wear and ``b`` the height under the deposit. The paper's "wears down" is read as: the
    deposit is used up, the Archard wear of a secondary plateau being clipped at its deposit
    (a decision, docs/model.md section 7, rule 5). The lazy kernel takes rule 5 without this
    function, by a certificate ``a r + c <= b`` in its trees (docs/model.md, introduction and
    section 13).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    return status == 2 and height <= deposit_base


@njit_noalloc
def rule6_primary_out_of_reach(status, height: float, disc_position: float, max_gap: float) -> bool:
    """Rule 6: a primary plateau whose gap to the disc, ``disc_position - height`` [m] (both
    [m]), exceeds ``max_gap`` [m] is destroyed (reading of "its height is less than the
    minimum gap"; ``max_gap = inf`` switches it off).

    Parameters
    ----------
    status : int
        Status of the cell: 0 none, 1 primary, 2 secondary [-].
    height : float
        Height of the cell [m].
    disc_position : float
        Disc surface position z of the step [m].
    max_gap : float
        Largest gap below the disc a primary plateau survives [m]
        (``automaton.rule6_max_gap``; ``inf`` when unset).

    Returns
    -------
    bool
        Whether the cell is a primary plateau with ``disc_position - height > max_gap``.

    Notes
    -----
    ``rule6 = (status = primary) and z - h > max_gap``. The paper destroys a primary plateau
    whose "height is less than the minimum gap between pad and disc"; reading that as a
    primary standing more than ``max_gap`` below the disc, and switching it off by default
    (``max_gap = inf``, since with fibres as columns it would delete fibres that are merely
    recessed), are decisions (docs/model.md section 7, rule 6; ``automaton.rule6_max_gap``).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    return status == 1 and disc_position - height > max_gap


@njit_noalloc
def rule7_fibre_worn(status, height: float, fibre_floor: float) -> bool:
    """Rule 7: a primary plateau worn down to the underside of its fibre is destroyed: its
    height ``height`` [m] at or below ``fibre_floor`` [m] (never with fibres as columns,
    whose floor is -inf).

    Parameters
    ----------
    status : int
        Status of the cell: 0 none, 1 primary, 2 secondary [-].
    height : float
        Height of the cell after this step's wear [m].
    fibre_floor : float
        Underside of the cell's fibre [m] (``-inf`` with fibres as columns).

    Returns
    -------
    bool
        Whether the cell is a primary plateau with ``height <= fibre_floor``.

    Notes
    -----
    ``rule7 = (status = primary) and h <= floor``, with ``h`` the height after this step's
    wear and ``floor`` the underside of the cell's fibre. The paper's "wears down" for a
    fibre is the spec's open point, settled by ``pad.fibre_model``: with fibres as columns
    (the default) the floor is ``-inf`` and the rule never fires; with ``layer`` the floor is
    the lying cylinder's underside, with ``field`` the bottom of the merged fibre interval it
    lies in (docs/model.md section 7, "The fibre 'wears down' question", and the table of the
    3-D fibre field).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.
    """
    return status == 1 and height <= fibre_floor


class Exposure(NamedTuple):
    """What :func:`expose_buried_fibres` did."""

    exposed: int
    """Cells that became primary plateaus [-]."""
    max_lag: float
    """Largest depth by which an exposed cell's surface lay below its fibre's top [m]: how far
    wear went into the fibre before the end of the stop exposed it."""
    lag_volume: float
    """The fibre those depths hold, summed over the exposed cells: fibre removed as resin
    because its exposure waited for the end of the stop [m^3]."""
    skipped: int
    """Buried fibre intervals passed wholly within one stop [-]."""
    released: float
    """Volume of the deposits of the secondary plateaus exposed [m^3]."""


def pad_surface(status: np.ndarray, height: np.ndarray, base: np.ndarray) -> np.ndarray:
    """The pad material's surface of each cell [m]: its height ``height`` [m], or for a
    secondary plateau (``status`` 2) the height under its deposit, ``base`` [m].

    Parameters
    ----------
    status : int array
        Cell statuses: 0 none, 1 primary, 2 secondary [-].
    height : float64 array
        Cell heights [m] (same shape as ``status``).
    base : float64 array
        Heights under the secondary plateaus' deposits [m] (same shape).

    Returns
    -------
    float64 array
        Pad surface of each cell [m], of the shape of the arguments (a new array).
    """
    return np.where(status == _SECONDARY, base, height)


def expose_buried_fibres(
    status: np.ndarray,
    height: np.ndarray,
    base: np.ndarray,
    fibre_floor: np.ndarray,
    cell_area: np.ndarray,
    top: np.ndarray,
    bottom: np.ndarray,
    end: np.ndarray,
    next_interval: np.ndarray,
) -> Exposure:
    """Fibre exposure (the fibre field, between stops): a cell whose pad surface has come down
    to or below the top of the next buried fibre under it becomes a primary plateau.

    The pad surface of a resin cell is its height; of a secondary plateau, the height under its
    deposit (the resin below a deposit is cut whenever the deposit is lost and the cell is
    briefly resin, so it goes down with the disc). The cell keeps that height (the fibre is
    cut flush with the resin around it) and takes the fibre's underside as its floor, below
    which rule 7 turns it back to resin. A secondary plateau's deposit is released: it leaves
    the contact with the other particles at the end of the stop. A fibre the surface has
    passed wholly (its underside above the cell) is skipped. Runs once a stop, on the state
    the stop left; changes ``status``, ``height``, ``base``, ``fibre_floor`` and
    ``next_interval`` in place.

    Parameters
    ----------
    status : int8 array (n_cells,)
        Cell statuses; resin and secondary cells can change [-].
    height, base : float64 arrays (n_cells,)
        Cell heights, and the heights under the secondary plateaus' deposits [m].
    fibre_floor : float64 array (n_cells,)
        Fibre underside of primary cells [m].
    cell_area : float64 array (n_cells,)
        Cell areas [m^2].
    top, bottom : float64 arrays
        The field's intervals, per cell disjoint and highest first [m]
        (:class:`brakeca.surface.FibreField`).
    end : int64 array (n_cells,)
        One past each cell's last interval [-].
    next_interval : int64 array (n_cells,)
        Each cell's next interval below its surface [-].

    Returns
    -------
    Exposure
        Cells exposed, the largest lag [m] and the fibre volume it holds [m^3], intervals
        skipped, deposit volume released [m^3].
    """
    exposed = 0
    skipped = 0
    max_lag = 0.0
    lag_volume = 0.0
    released = 0.0
    surface = pad_surface(status, height, base)
    cells = np.flatnonzero((status != _PRIMARY) & (next_interval < end))
    while cells.size:
        k = next_interval[cells]
        reached = surface[cells] <= top[k]
        cells, k = cells[reached], k[reached]
        within = surface[cells] > bottom[k]
        hit, kh = cells[within], k[within]
        if hit.size:
            sec = hit[status[hit] == _SECONDARY]
            released += float(np.sum((height[sec] - base[sec]) * cell_area[sec]))
            height[hit] = surface[hit]
            base[hit] = surface[hit]
            status[hit] = _PRIMARY
            fibre_floor[hit] = bottom[kh]
            next_interval[hit] = kh + 1
            exposed += int(hit.size)
            lag = top[kh] - surface[hit]
            max_lag = max(max_lag, float(np.max(lag)))
            lag_volume += float(np.sum(lag * cell_area[hit]))
        passed = cells[~within]
        next_interval[passed] += 1
        skipped += int(passed.size)
        cells = passed[next_interval[passed] < end[passed]]
    return Exposure(exposed, max_lag, lag_volume, skipped, released)
