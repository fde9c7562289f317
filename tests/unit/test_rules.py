"""Each of the seven plateau rules, firing and not firing, on hand-built grids."""

from __future__ import annotations

import numpy as np
import pytest

from brakeca.automaton import (
    creation_rule,
    gap_fill_cost,
    rule1_east_support,
    rule2_east_and_one_diagonal,
    rule3_east_and_both_diagonals,
    rule4_lost_support,
    rule5_deposit_worn,
    rule6_primary_out_of_reach,
    rule7_fibre_worn,
)

# status grids, 3 rows x 3 columns, the cell under test at the centre (row 1, col 1)
#   row 2 = north, row 0 = south, column 2 = east
N, P, S = 0, 1, 2


def grid(rows):
    """rows given north first, as drawn"""
    return np.array(rows[::-1], dtype=np.int8).ravel()


CENTRE = 1 * 3 + 1


@pytest.mark.parametrize(
    ("rows", "expected"),
    [
        ([[N, N, N], [N, N, P], [N, N, N]], 1),  # east only
        ([[N, N, P], [N, N, S], [N, N, N]], 2),  # east + north-east
        ([[N, N, N], [N, N, P], [N, N, P]], 2),  # east + south-east
        ([[N, N, P], [N, N, P], [N, N, S]], 3),  # east + both diagonals
        ([[N, N, P], [N, N, N], [N, N, P]], 0),  # diagonals without east: no rule
        ([[P, P, P], [P, N, N], [P, P, P]], 0),  # support west/north/south only
        ([[N, N, N], [N, P, P], [N, N, N]], 0),  # already a plateau: not a candidate
    ],
)
def test_creation_rules(rows, expected):
    st = grid(rows)
    assert creation_rule(st, CENTRE, 3, 3) == expected
    assert rule1_east_support(st, CENTRE, 3, 3) == (expected == 1)
    assert rule2_east_and_one_diagonal(st, CENTRE, 3, 3) == (expected == 2)
    assert rule3_east_and_both_diagonals(st, CENTRE, 3, 3) == (expected == 3)


def test_no_support_beyond_the_trailing_edge_or_radial_edges():
    st = np.array([N, P, N, N], dtype=np.int8)  # one row of 4
    assert creation_rule(st, 3, 1, 4) == 0  # east of the trailing edge is not a plateau
    assert creation_rule(st, 0, 1, 4) == 1  # one row: no diagonals exist
    two_rows = np.array([[N, P], [N, P]], dtype=np.int8).ravel()
    assert creation_rule(two_rows, 0, 2, 2) == 2  # south row: only a north-east neighbour


def test_gap_fill_cost():
    assert gap_fill_cost(10e-6, 4e-6, 2e-8) == pytest.approx(6e-6 * 2e-8)


def test_rule4_lost_support():
    assert rule4_lost_support(grid([[N, N, N], [N, S, N], [N, N, N]]), CENTRE, 3)
    assert not rule4_lost_support(grid([[N, N, N], [N, S, P], [N, N, N]]), CENTRE, 3)
    assert not rule4_lost_support(grid([[N, N, N], [N, S, S], [N, N, N]]), CENTRE, 3)
    # support only diagonal is not enough: rule 4 reads the cell directly east
    assert rule4_lost_support(grid([[N, N, P], [N, S, N], [N, N, P]]), CENTRE, 3)
    # at the trailing edge there is no eastern neighbour
    assert rule4_lost_support(np.array([N, S], dtype=np.int8), 1, 2)
    # not a secondary: rule 4 does not apply
    assert not rule4_lost_support(grid([[N, N, N], [N, P, N], [N, N, N]]), CENTRE, 3)


def test_rule5_deposit_worn():
    assert rule5_deposit_worn(2, 5e-6, 5e-6)
    assert not rule5_deposit_worn(2, 5.1e-6, 5e-6)
    assert not rule5_deposit_worn(1, 5e-6, 5e-6)


def test_rule6_primary_out_of_reach():
    assert rule6_primary_out_of_reach(1, 10e-6, 40e-6, 20e-6)
    assert not rule6_primary_out_of_reach(1, 30e-6, 40e-6, 20e-6)
    assert not rule6_primary_out_of_reach(1, 10e-6, 40e-6, np.inf)  # off by default
    assert not rule6_primary_out_of_reach(2, 10e-6, 40e-6, 20e-6)
    # at the bound: a gap of exactly max_gap survives ("exceeds"; binary fractions, so that
    # the gap is exact; a tests review found the bound unpinned)
    assert not rule6_primary_out_of_reach(1, 0.25, 0.75, 0.5)
    assert rule6_primary_out_of_reach(1, 0.25, 0.75, np.nextafter(0.5, 0.0))


def test_rule7_fibre_worn():
    assert rule7_fibre_worn(1, 99e-6, 100e-6)
    assert not rule7_fibre_worn(1, 101e-6, 100e-6)
    assert not rule7_fibre_worn(1, -1.0, -np.inf)  # columns never wear through
    assert not rule7_fibre_worn(2, 99e-6, 100e-6)
    # at the bound: worn down to the fibre's underside exactly is worn through ("at or
    # below")
    assert rule7_fibre_worn(1, 100e-6, 100e-6)
    assert not rule7_fibre_worn(1, np.nextafter(100e-6, 1.0), 100e-6)
