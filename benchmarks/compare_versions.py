"""Time one fixed run with the brakeca found on PYTHONPATH (used to compare kernel versions).

    PYTHONPATH=/path/to/checkout/src python benchmarks/compare_versions.py [--stops 40]

The run: quick band (21 x 1000 cells), WP = 1e-13 (secondary plateaus form), first --stops stops
of the paper cycle, seed 2016. Prints one JSON line: the version's source path, steps, seconds
(compile excluded by a warm-up run), ns per cell-step, and MU (to check the versions agree).
"""

import argparse
import json
import time

import brakeca
from brakeca.presets import load_preset
from brakeca.simulation import simulate

ap = argparse.ArgumentParser()
ap.add_argument("--stops", type=int, default=40)
args = ap.parse_args()
warm = load_preset().with_updates({"mesh.n_radial": 3, "mesh.n_angular": 100, "cycle.max_stops": 1})
simulate(warm, seed=0)
config = load_preset().with_updates(
    {"mesh.n_radial": 21, "WP": 1e-13, "cycle.max_stops": args.stops}
)
t = time.perf_counter()
result = simulate(config, seed=2016)
elapsed = time.perf_counter() - t
steps = int(result.dataset["n_steps"].sum())
print(
    json.dumps(
        {
            "source": brakeca.__file__,
            "steps": steps,
            "seconds": round(elapsed, 2),
            "ns_per_cell_step": round(elapsed / steps / 21000 * 1e9, 2),
            "MU": result.MU,
            "V_mm3": result.V * 1e9,
        }
    )
)
