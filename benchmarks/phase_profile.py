"""Where the time goes: run a quick-band simulation to a mid-cycle state, then time stops.

Usage: python benchmarks/phase_profile.py [--stops N] [--wp WP]
Prints ns per cell-step for each timed stop.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from brakeca.cycle import expand_stops
from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import SimulationState, advance_stop, end_of_stop
from brakeca.surface import generate_surface

ap = argparse.ArgumentParser()
ap.add_argument("--stops", type=int, default=6)
ap.add_argument("--wp", type=float, default=1e-13)
ap.add_argument("--rows", type=int, default=21)
args = ap.parse_args()
config = load_preset().with_updates({"mesh.n_radial": args.rows, "WP": args.wp})
grid = make_grid(config)
rng = np.random.default_rng(1)
state = SimulationState.from_surface(generate_surface(config.pad, grid, rng), grid)
stops = expand_stops(config)
cells = grid.shape[0] * grid.shape[1]
for stop in stops[: args.stops]:
    t = time.perf_counter()
    dt, rec, counts = advance_stop(state, grid, config, stop)
    el = time.perf_counter() - t
    end_of_stop(state, 0.0, rng)
    print(
        f"stop {stop.index:3d}: {dt.size} steps, {el:.3f} s, "
        f"{el / dt.size / cells * 1e9:.2f} ns/cell-step, "
        f"contact {rec[:, 3].mean() / grid.area:.3f}, secondary {rec[:, 5].mean() / grid.area:.3f}"
    )


def profile_phases(state, grid, config, stop, n_steps=400):
    """Time each compiled phase of the step separately (Python drives the steps)."""
    import math

    from brakeca import _kernels as K
    from brakeca.cycle import brake_demand, step_distance

    profile = stop.profile(step_distance(config))
    fraction = profile.fraction
    target = brake_demand(config, stop.deceleration, grid.area).band_friction_force
    fr = config.friction
    n = state.height.size
    created, destroyed, dpos = (np.zeros(n, dtype=np.int64) for _ in range(3))
    counts = np.zeros(8, dtype=np.int64)
    sums = np.zeros(K.N_SUMS)
    names = [
        "sort (+ removals, insertions)",
        "contact (root scan)",
        "rule 4 marks",
        "friction+wear+rules 5,7",
        "tail (rules 4, 6)",
        "resin",
        "creation",
        "apply",
        "advance",
        "held (ledger)",
    ]
    t = dict.fromkeys(names, 0.0)
    pc = time.perf_counter
    k_ = config.contact.stiffness
    steps = min(n_steps, fraction.size)
    cur, oth = state.pk, state.alt
    for step in range(steps):
        t0 = pc()
        if K.phase_sort(cur, oth, state.nb, state.cnt):
            cur, oth = oth, cur
        t1 = pc()
        z, n_in, _ = K.phase_contact(
            cur,
            state.cnt,
            state.bin_area,
            k_,
            fr.mu_0,
            fr.slope,
            fr.mu_min,
            target,
            config.contact.bar_length,
        )
        t2 = pc()
        n4 = K.phase_rule4(
            state.cnt, state.status, state.mark, state.rule4_list, state.n_angular, counts
        )
        t3 = pc()
        n_dest, left4 = K.phase_friction_wear(
            cur,
            n_in,
            state.bin_area,
            state.bin_slide,
            state.fibre_floor,
            state.rule7_on,
            state.outflow,
            state.acc,
            state.mark,
            n4,
            z,
            k_,
            fr.mu_0,
            fr.slope,
            fr.mu_min,
            config.wear.specific_wear_rate,
            fraction[step],
            sums,
            destroyed,
            dpos,
            counts,
        )
        t4 = pc()
        n_dest = K.phase_tail(
            cur,
            n_in,
            state.cnt,
            state.mark,
            left4,
            z,
            math.inf,
            destroyed,
            dpos,
            n_dest,
            counts,
        )
        t5 = pc()
        K.phase_resin(
            state.height,
            state.status,
            state.cell_area,
            state.cell_bin,
            state.outflow,
            state.heap_keys,
            state.heap_vals,
            state.cnt,
            z,
            config.wear.resin_wear_depth,
            sums,
        )
        state.acc[K.ACC_REMOVED] += sums[K.S_REMOVED]
        t6 = pc()
        n_new = K.phase_creation(
            state.height,
            state.status,
            state.cand,
            state.ncand,
            state.cell_area,
            state.inflow,
            state.outflow,
            z,
            state.n_radial,
            state.n_angular,
            state.n_subdomains,
            False,
            created,
            counts,
        )
        t7 = pc()
        K.phase_apply(
            cur,
            state.nb,
            n_in,
            state.cnt,
            state.bin_area,
            state.height,
            state.base,
            state.status,
            state.cand,
            state.ncand,
            state.cell_area,
            state.cell_bin,
            state.outflow,
            state.acc,
            state.mark,
            state.heap_keys,
            state.heap_vals,
            state.rule4_list,
            z,
            state.n_angular,
            destroyed,
            dpos,
            n_dest,
            created,
            n_new,
        )
        t8 = pc()
        emitted, _ = K.phase_advance(
            state.inflow, state.outflow, state.n_radial, state.n_subdomains
        )
        state.acc[K.ACC_EMITTED] += emitted
        t9 = pc()
        K.held_volume(cur, state.nb, state.cnt, state.bin_area)
        t10 = pc()
        marks = (t0, t1, t2, t3, t4, t5, t6, t7, t8, t9, t10)
        for key, a, b in zip(names, marks[:-1], marks[1:], strict=True):
            t[key] += b - a
    total = sum(t.values())
    print(
        f"per-phase time, {steps} steps of stop {stop.index}, {state.cnt[0]} plateau cells "
        "(Python-driven; each call adds ~0.3 us of dispatch):"
    )
    for key, v in t.items():
        print(f"  {key:30s} {v / steps * 1e6:9.1f} us/step  {100 * v / total:5.1f} %")


if args.stops:
    profile_phases(state, grid, config, stops[args.stops])
