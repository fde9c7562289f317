"""Speed benchmark: prints one JSON line.

    python benchmarks/bench.py [--stops 3] [--rows 201] [--ref-rows 21] [--ref-steps 30]

Measures, in one process on one core:

* ``compile_s``: numba compile (or cache load) time, from a one-stop run on a tiny grid with
  each kernel timed below (so no timed run includes compiling);
* a full-resolution run (Table 5 grid unless ``--rows``) of the first ``--stops`` stops:
  ``measured_s``, ``steps``, ``steps_per_s``, ``ns_per_cell_step``, and ``cycle_extrapolated_s``
  = measured time per step x the 491,160 steps of the whole cycle (the cost per step changes
  over the cycle as plateaus form; the extrapolation from the first stops says so);
* ``speedup_vs_numpy``: the compiled kernel against the slow NumPy reference of the tests
  (``tests/naive.py``), side by side on the same grid (``--ref-rows`` x 1000) and the same
  ``--ref-steps`` steps from the same state;
* ``scaling`` (with ``--scaling 21,61,201``): the same stops on several band widths, to show the
  cost grows linearly with cells x steps (constant ns per cell-step);
* ``peak_rss_mb``: peak resident memory of the process (the full-resolution run dominates).

``--set KEY=VALUE`` (repeated) times other levels than the preset's, e.g. test 5's
(``--set WP=1e-13 --set A=10``), the study's most expensive; the JSON line then names them
(``levels``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from brakeca import __version__
from brakeca.config import parse_overrides
from brakeca.cycle import brake_demand, expand_stops, step_distance, stop_steps
from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import SimulationState, advance_stop, kernel_for, simulate
from brakeca.surface import generate_surface

CYCLE_STEPS = 491_160


def time_compile(kernels: list[str]) -> float:
    tiny = load_preset().with_updates(
        {"mesh.n_radial": 2, "mesh.n_angular": 20, "mesh.n_subdomains": 2, "cycle.max_stops": 1}
    )
    t = time.perf_counter()
    for kernel in kernels:
        simulate(tiny.with_updates({"numerics.kernel": kernel}), seed=0)
    return time.perf_counter() - t


def time_run(
    rows: int, stops: int, seed: int, kernel: str = "auto", updates: dict | None = None
) -> dict:
    config = load_preset().with_updates(
        {
            **(updates or {}),
            "mesh.n_radial": rows,
            "cycle.max_stops": stops,
            "numerics.kernel": kernel,
        }
    )
    t = time.perf_counter()
    result = simulate(config, seed=seed)
    elapsed = time.perf_counter() - t
    steps = int(result.dataset["n_steps"].sum())
    cells = rows * config.mesh.n_angular
    return {
        "grid": f"{rows}x{config.mesh.n_angular}",
        "stops": stops,
        "steps": steps,
        "measured_s": round(elapsed, 3),
        "steps_per_s": round(steps / elapsed, 1),
        "ns_per_cell_step": round(elapsed / steps / cells * 1e9, 3),
        "cycle_extrapolated_s": round(elapsed / steps * CYCLE_STEPS, 1),
        # the first stops are the cycle's cheapest (burnish, little of the band in contact):
        # a whole run costs more per step, by its levels (docs/performance.md, whole runs)
        "extrapolated_from": f"the first {stops} stop{'' if stops == 1 else 's'} only",
        "MU": round(result.MU, 5),
        "kernel": kernel_for(config),
        "stops_lazy": int(result.dataset.attrs["stops_lazy"]),
        "stops_exact": int(result.dataset.attrs["stops_exact"]),
    }


def speedup_vs_numpy(rows: int, n_steps: int, seed: int, kernel: str = "auto") -> dict:
    """Kernel vs tests/naive.py on the same grid, same state, same steps."""
    import naive

    config = load_preset().with_updates(
        {"mesh.n_radial": rows, "WP": 1e-13, "numerics.kernel": kernel}
    )
    grid = make_grid(config)
    rng = np.random.default_rng(seed)
    surface = generate_surface(config.pad, grid, rng)
    stop = expand_stops(config)[0]
    _, fraction = stop_steps(stop, step_distance(config))
    target = brake_demand(config, stop.deceleration, grid.area).band_friction_force
    fr = config.friction
    params = {
        "area_row": np.asarray(grid.cell_area),
        "slide_row": np.asarray(grid.step_sliding_distance),
        "K": config.contact.stiffness,
        "mu0": fr.mu_0,
        "c": fr.slope,
        "mumin": fr.mu_min,
        "WP": config.wear.specific_wear_rate,
        "WR": config.wear.resin_wear_depth,
        "nsub": grid.n_subdomains,
        "rule6_gap": np.inf,
        "east_to_west": False,
    }
    ref = {
        "H": surface.height.copy(),
        "B": surface.height.copy(),
        "S": surface.status.copy(),
        "FF": surface.fibre_floor.copy(),
        "inflow": np.zeros((rows, grid.n_subdomains)),
        "removed": 0.0,
        "emitted": 0.0,
    }
    t = time.perf_counter()
    for n in range(n_steps):
        naive.step(ref, params, target, fraction[n])
    t_ref = time.perf_counter() - t
    # the kernel on the same steps: a one-block cycle cut to n_steps by its speeds
    state = SimulationState.from_surface(surface, grid)
    short = config.with_updates({"cycle.max_stops": 1})
    stop_short = _stop_with_steps(short, n_steps)
    t = time.perf_counter()
    dt, _, _ = advance_stop(state, grid, short, stop_short)
    t_fast = time.perf_counter() - t
    assert dt.size == n_steps, (dt.size, n_steps)
    return {
        "grid": f"{rows}x{config.mesh.n_angular}",
        "steps": n_steps,
        "numpy_s": round(t_ref, 3),
        "kernel_s": round(t_fast, 5),
        "speedup": round(t_ref / t_fast, 1),
        "kernel": kernel_for(config),
    }


def _stop_with_steps(config, n_steps):
    """The first stop of the cycle, shortened to exactly ``n_steps`` full steps."""
    from brakeca.cycle import Stop

    stop = expand_stops(config)[0]
    s = step_distance(config)
    v1_sq = stop.initial_speed**2 - 2 * stop.deceleration * s * n_steps
    return Stop(
        stop.index, stop.block, stop.initial_speed, float(np.sqrt(v1_sq)), stop.deceleration
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stops", type=int, default=3, help="full-resolution stops to time")
    ap.add_argument("--rows", type=int, default=201, help="radial rows of the timed run")
    ap.add_argument("--ref-rows", type=int, default=21, help="rows of the NumPy comparison")
    ap.add_argument("--ref-steps", type=int, default=30, help="steps of the NumPy comparison")
    ap.add_argument("--seed", type=int, default=2016)
    ap.add_argument(
        "--scaling",
        default="",
        help="comma-separated radial row counts: time --stops stops on each (linearity check)",
    )
    ap.add_argument(
        "--kernel", default="auto", choices=["auto", "lazy", "exact"], help="numerics.kernel"
    )
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a config override of the timed runs, e.g. --set WP=1e-13 --set A=10 (test 5's "
        "levels, the study's most expensive)",
    )
    ap.add_argument(
        "--also-exact",
        action="store_true",
        help="time the same run with the exact kernel too, in this process (ratio in one run)",
    )
    args = ap.parse_args()
    updates = parse_overrides(args.set)
    out = {
        "brakeca": __version__,
        "machine": f"{platform.machine()} {os.cpu_count()} cpu, {platform.python_version()}",
        "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
        "compile_s": round(time_compile([args.kernel] + (["exact"] if args.also_exact else [])), 3),
    }
    if updates:
        out["levels"] = updates
    out["run"] = time_run(args.rows, args.stops, args.seed, args.kernel, updates)
    if args.also_exact:
        out["exact_run"] = time_run(args.rows, args.stops, args.seed, "exact", updates)
        out["exact_over_this"] = round(out["exact_run"]["measured_s"] / out["run"]["measured_s"], 2)
    if args.scaling:
        out["scaling"] = [
            time_run(int(r), args.stops, args.seed, args.kernel, updates)
            for r in args.scaling.split(",")
            if r.strip()
        ]
    out["reference"] = speedup_vs_numpy(args.ref_rows, args.ref_steps, args.seed, args.kernel)
    out["speedup_vs_numpy"] = out["reference"]["speedup"]
    out["peak_rss_mb"] = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
