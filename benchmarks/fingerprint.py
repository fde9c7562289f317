"""Bit-for-bit fingerprints of a few short runs, to compare two kernel versions.

    PYTHONPATH=/path/to/checkout/src python benchmarks/fingerprint.py [--stops 60]

Each case drives :func:`brakeca.stop.advance_stop` and :func:`end_of_stop` directly and
hashes (SHA-256) every per-step record, the rule counts and, after every stop, the grid state
(heights, deposit bases, statuses, streams, accumulators). Two versions of the kernel give
bit-identical results when every line printed is the same. The cases fire every rule: high
wear (secondary plateaus form and are destroyed), S = 0.5 (random removal), the layer fibre
model with rule 6 on (rules 6 and 7), creation east to west, and a deep resin cut.

The fifth case, ``study_test1``, is the paper study's test 1 (S = 0, WP = 1e-15, WR = 1e-7,
A = 10 %) at full resolution with the study's seed, over its first 70 stops (the burnish and
Town #1). It is there because the four short cases missed a change that was not bit-identical:
the sixteenth session's rule-5 certificate bounds (12bf2a6) left their hashes unchanged but
changed seven of the study's runs at round-off. On this case that change first differs at
stop 61. It takes about half a minute with the lazy kernel.
"""

from __future__ import annotations

import argparse
import hashlib
import json
from typing import Any

import numpy as np

from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import SimulationState, advance_stop, cycle_events, end_of_stop
from brakeca.surface import generate_surface

CASES: dict[str, dict[str, Any]] = {
    "wp+_s0": {"mesh.n_radial": 21, "WP": 1e-13, "S": 0.0},
    "wp+_s05_wr+": {"mesh.n_radial": 11, "WP": 1e-13, "S": 0.5, "WR": 1e-6},
    "layer_rule6": {  # the layer fibres wear through at about stop 50
        "_stops": 40,
        "mesh.n_radial": 11,
        "WP": 1e-13,
        "S": 1.0,
        "pad.fibre_model": "layer",
        "automaton.rule6_max_gap": 80e-6,
    },
    "east_to_west": {
        "mesh.n_radial": 11,
        "WP": 1e-13,
        "automaton.creation_order": "east_to_west",
    },
    "study_test1": {  # full resolution, the paper study's seed for test 1
        "_stops": 70,
        "_seed": 2484888077,
        "S": 0.0,
        "WP": 1e-15,
        "WR": 1e-7,
        "A": 10.0,
    },
}

#: cases with rule 6 or layer fibres, which only the exact kernel runs
LAZY_UNSUPPORTED = ("layer_rule6",)


def fingerprint(updates: dict, stops: int | None, kernel: str = "exact") -> dict:
    """Run the first stops of the paper cycle with ``updates`` and step kernel ``kernel``;
    return hashes and MU. ``updates`` may hold the case's stop count ``_stops`` (60 if not)
    and seed ``_seed`` (7 if not); ``stops``, if given, caps the stop count."""
    updates = {**updates, "numerics.kernel": kernel}
    case_stops = updates.pop("_stops", 60)
    seed = updates.pop("_seed", 7)
    stops = case_stops if stops is None else min(stops, case_stops)
    config = load_preset().with_updates(updates)
    grid = make_grid(config)
    rng = np.random.default_rng(seed)
    state = SimulationState.from_surface(generate_surface(config.pad, grid, rng), grid)
    digest = hashlib.sha256()
    cofs = []
    fired = np.zeros(8, dtype=np.int64)
    for stop in cycle_events(config)[:stops]:
        dt, rec, counts = advance_stop(state, grid, config, stop)
        end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
        for arr in (
            dt,
            rec,
            counts,
            state.height,
            state.base,
            state.status,
            state.inflow,
            state.acc,
        ):
            digest.update(np.ascontiguousarray(arr).tobytes())
        fired += counts
        cofs.append(float(np.average(rec[:, 0], weights=dt)))
    return {
        "stops": stops,
        "sha256": digest.hexdigest()[:16],
        "MU": float(np.mean(cofs)),
        "rule_firings": fired[1:].tolist(),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--stops",
        type=int,
        default=None,
        help="cap every case at this many stops (default: each case's own, 60 or 70)",
    )
    ap.add_argument("--case", action="append", choices=sorted(CASES))
    ap.add_argument(
        "--kernel",
        choices=("exact", "lazy"),
        default="exact",
        help="step kernel (the lazy kernel skips the cases it does not support)",
    )
    args = ap.parse_args()
    for name in args.case or CASES:
        if args.kernel == "lazy" and name in LAZY_UNSUPPORTED:
            continue
        print(
            json.dumps({"case": name, **fingerprint(CASES[name], args.stops, kernel=args.kernel)}),
            flush=True,
        )


if __name__ == "__main__":
    main()
