"""Compile the kernels the test suite runs into the numba cache (NUMBA_CACHE_DIR), ahead.

``scripts/test`` runs two of these, ``lazy`` and ``exact``, while the static checks run, so
that each test process loads the kernels instead of compiling them on its own (a review of
the suite's time: 52-90 s of compiling in each of its two processes). A kernel left out
here is compiled by the first test that needs it, as before; a failure here fails nothing.
"""

from __future__ import annotations

import sys

from brakeca._warmup import warm_up
from brakeca.presets import load_preset

#: The configurations each group compiles for: the default (lazy) kernel; the exact kernel
#: and the variants of the automaton the tests run with it (fibre layers or a field, rule 6:
#: the exact kernel's alone; east to west with either kernel).
GROUPS = {
    "lazy": ({}, {"automaton.creation_order": "east_to_west"}),
    "exact": (
        {"numerics.kernel": "exact"},
        {"numerics.kernel": "exact", "automaton.creation_order": "east_to_west"},
        {"pad.fibre_model": "field"},
        {"pad.fibre_model": "layer"},
        {"automaton.rule6_max_gap": 2e-5},
    ),
}


def main(group: str) -> int:
    paper = load_preset()
    warm_up([paper.with_updates(update) for update in GROUPS[group]], announce=lambda _: None)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
