"""Where the time goes: the share of each kernel phase, stop by stop.

Usage: python benchmarks/phase_profile.py [--stops 60] [--rows 21] [--wp 1e-13] [--every 10]
       [--set KEY=VALUE ...]

Runs the first ``--stops`` stops of the paper cycle on a band of ``--rows`` rows (quick band
by default) and, for every group of ``--every`` stops, prints the ns per cell-step, the cells
in contact, the secondary area, the status changes a step (plateaus created by rules 1-3
and destroyed by rules 4-7) and the share of each phase of the step. With the lazy kernel it
then prints the contact solve's counters a step: the trial positions evaluated (each a pass
over the rows), the breakpoints walked and the walk's jumps (each a pass as well), and the
shares of the step spent in the bracketed search and in the walk (both inside "contact",
which also holds the moves across the contact edge after the root and the rule-5 tree
flush). ``--set`` takes the overrides of ``brakeca simulate`` (``--set S=1 --set A=20``:
another test's levels). The phases are timed inside the compiled kernel with the CPU's cycle
counter (``SimulationState.prof``), so there is no Python overhead in the shares.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from brakeca import _kernels as K
from brakeca.config import parse_override
from brakeca.cycle import expand_stops
from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import SimulationState, advance_stop, end_of_stop
from brakeca.surface import generate_surface

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--stops", type=int, default=60)
ap.add_argument("--rows", type=int, default=21)
ap.add_argument("--wp", type=float, default=1e-13)
ap.add_argument("--every", type=int, default=10)
ap.add_argument("--seed", type=int, default=2016)
ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
args = ap.parse_args()

updates = {"mesh.n_radial": args.rows, "WP": args.wp}
updates.update(parse_override(item) for item in args.set)
config = load_preset().with_updates(updates)
grid = make_grid(config)
rng = np.random.default_rng(args.seed)
state = SimulationState.from_surface(generate_surface(config.pad, grid, rng), grid)
stops = expand_stops(config)[: args.stops]
cells = grid.shape[0] * grid.shape[1]
# warm up (compile or load the cache) on a copy of the state
advance_stop(
    SimulationState.from_surface(
        generate_surface(config.pad, grid, np.random.default_rng(0)), grid
    ),
    grid,
    config,
    stops[0],
)
print(
    f"{'stops':>7} {'ns/cell-step':>12} {'contact':>7} {'second.':>7} {'made':>6} {'lost':>6}  "
    + " ".join(f"{p:>14}" for p in K.TIMED_PHASES)
)
for g in range(0, len(stops), args.every):
    group = stops[g : g + args.every]
    state.prof[:] = 0
    state.lazy_walk[:] = 0
    steps = 0
    contact = secondary = 0.0
    elapsed = 0.0
    made = lost = 0
    for stop in group:
        t = time.perf_counter()
        dt, rec, counts = advance_stop(state, grid, config, stop)
        made += int(counts[1:4].sum())
        lost += int(counts[4:8].sum())
        elapsed += time.perf_counter() - t
        end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
        steps += dt.size
        contact += rec[:, K.R_CONTACT_AREA].sum() / grid.area
        secondary += rec[:, K.R_SECONDARY_AREA].sum() / grid.area
    total = state.prof.sum()
    share = state.prof / total if total > 0 else np.full(state.prof.size, np.nan)  # no counter
    print(
        f"{group[0].index:>3}-{group[-1].index:<3} {elapsed / steps / cells * 1e9:12.2f} "
        f"{contact / steps:7.3f} {secondary / steps:7.3f} {made / steps:6.0f} {lost / steps:6.0f}  "
        + " ".join(f"{100 * s:13.1f}%" if s == s else f"{'n/a':>14}" for s in share)
    )
    walk = state.lazy_walk  # see SimulationState.lazy_walk
    if walk[2] > 0 and total > 0:  # the lazy kernel ran
        print(
            f"{'':>7} solve: {walk[2] / steps:.2f} positions, {walk[1] / steps:.1f} walk steps, "
            f"{walk[3] / steps:.2f} jumps a step; bracket {100 * walk[4] / total:.1f}%, "
            f"walk {100 * walk[5] / total:.1f}% of the step"
        )
