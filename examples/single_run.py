"""One pad material simulated from Python: MU, V, the per-stop table, the run file, figures.

Loads the paper's parameter preset, sets the pad's levels (WP = 1e-13 m³/(N·m), A = 10 %),
simulates it over the drive cycle on the quick band (2 mm, 21 rows) with one seed, prints MU,
V and the per-stop results, saves the run file and reads it back, draws the run's figures
(MU per stop, the per-step COF and normal force, the plateau map at the end), then runs the
same pad with A = 20 % and the same seed and prints the difference, as
``brakeca simulate --quick --set WP=1e-13 --set A=10 --seed 3`` and ``brakeca plot`` would::

    .venv/bin/python examples/single_run.py             # 170 stops, two pads: 47-55 s, 2 cores
    .venv/bin/python examples/single_run.py --stops 20  # the first 20 stops only
    .venv/bin/python examples/single_run.py --tiny      # a 5 x 100 cell band, 3 stops

The ``--tiny`` variant (seconds; what the test suite runs) shows the workflow, not results.
Outputs go to ``examples_out/single_run`` (``examples_out/single_run_tiny`` with ``--tiny``;
``--out`` for another folder).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from brakeca import study
from brakeca.design import quick_config
from brakeca.plotting import (
    plot_cof_series,
    plot_fibre_maps,
    plot_mu_per_stop,
    plot_surface_map,
)
from brakeca.presets import load_preset
from brakeca.results import RunResult
from brakeca.simulation import simulate

#: a 5 x 100 cell band: the workflow in seconds, not a result
TINY = {"mesh.n_radial": 5, "mesh.n_angular": 100, "mesh.n_subdomains": 10}
M3_TO_MM3 = 1e9


def per_stop_table(run: RunResult) -> pd.DataFrame:
    """The run's per-stop results in engineering units (brakeca.study.per_stop_table: MU and
    V are the means of its ``mean_cof`` and ``emitted_mm3`` columns), area fractions in %."""
    table = study.per_stop_table(run)
    for name in ("primary", "secondary", "contact"):
        table[f"{name}_%"] = 100 * table.pop(f"{name}_area_fraction")
    return table


def _shown(table: pd.DataFrame, rows: int = 8) -> str:
    """Some columns of the table as text; a long one as its first and last ``rows // 2``
    stops (the CSV file has them all)."""
    columns = ["stop", "block", "mean_cof", "emitted_mm3", "primary_%", "secondary_%"]
    columns += ["normal_force_N", "line_pressure_MPa", "duration_s"]
    cut = len(table) > rows
    if cut:
        table = pd.concat([table.head(rows // 2), table.tail(rows // 2)])
    lines = table[columns].to_string(index=False, float_format=lambda v: f"{v:.4g}").splitlines()
    if cut:  # mark where the stops left out were
        lines.insert(1 + rows // 2, "  ...")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> dict:
    """Run the example; returns the runs, the table, the files and the difference (for the
    tests)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="a 5 x 100 cell band, 3 stops")
    parser.add_argument("--stops", type=int, default=None, help="the first N stops only")
    parser.add_argument("--seed", type=int, default=3, help="the runs' seed (default 3)")
    parser.add_argument(
        "--out", type=Path, default=None, help="output folder (default examples_out/...)"
    )
    args = parser.parse_args(argv)
    if args.out is None:
        args.out = Path("examples_out/single_run" + ("_tiny" if args.tiny else ""))
    stops = 3 if args.tiny and args.stops is None else args.stops

    # the paper's parameters with this pad's levels (paper factors in the paper's units: WP in
    # m³/(N·m), A in %); every other field by its dotted name, e.g. "friction.mu_0"
    levels = {"WP": 1e-13, "A": 10}
    config = load_preset("paper").with_updates(
        {**levels, **(TINY if args.tiny else {}), "cycle.max_stops": stops}
    )
    if not args.tiny:
        config = quick_config(config)  # the band of --quick: 2 mm, 21 rows, the same cells
    band = f"{config.mesh.n_radial} x {config.mesh.n_angular} cells"
    print(
        f"one pad material: paper preset, WP = 1e-13 m³/(N·m), A = 10 %, seed {args.seed}, {band}"
    )

    # one seed per run, passed in: no global random state; the same seed gives the same run
    run = simulate(config, seed=args.seed)
    print(run)
    print(f"MU = {run.MU:.4f} (mean COF over {run.dataset.sizes['stop']} stops)")
    print(f"V  = {run.V * M3_TO_MM3:.4g} mm³ per stop (mean emitted wear volume)")
    table = per_stop_table(run)
    print(_shown(table))
    blocks = table.groupby("block", sort=False).agg(
        stops=("stop", "size"), mean_cof=("mean_cof", "mean"), emitted_mm3=("emitted_mm3", "mean")
    )
    print("per block of the cycle (means over its stops; V in mm³ per stop):")
    print(blocks.to_string(float_format=lambda v: f"{v:.4g}"))
    args.out.mkdir(parents=True, exist_ok=True)
    table.to_csv(args.out / "per_stop.csv", index=False)

    # the run file holds everything (config, seed, per-stop and per-step series, maps)
    run_file = run.to_netcdf(args.out / "run_WP1e-13_A10.nc")
    back = RunResult.from_netcdf(run_file)
    same = back.seed == run.seed and back.config == run.config and back.MU == run.MU
    print(f"run file: {run_file} (read back: seed, config and MU the same: {same})")

    # the figures of one run (brakeca.plot_run(back, folder) draws these three in one call)
    figures = args.out / "figures"
    ds = back.dataset
    radius, angle = ds["radius"].to_numpy(), ds["angle"].to_numpy()
    paths = [figures / "mu_per_stop.png", figures / "steps.png", figures / "final_map.png"]
    plot_mu_per_stop(back, paths[0], title=f"WP = 1e-13, A = 10 %, seed {back.seed}")
    plot_cof_series(back, paths[1])  # the per-step COF and pad normal force vs braking time
    plot_surface_map(
        ds["final_status"].to_numpy(), radius, angle, "Pad surface after the last stop", paths[2]
    )

    # another material, the same seed: the comparison is of the materials, not of the draws
    other = simulate(config.with_updates({"A": 20}), seed=args.seed)
    print(other)
    both = pd.DataFrame(
        {
            "A_%": [10, 20],
            "MU": [run.MU, other.MU],
            "V_mm3_per_stop": [run.V * M3_TO_MM3, other.V * M3_TO_MM3],
            # time-weighted over the last stop (the maps' fractions are those at its end)
            "last_stop_primary_%": [
                100 * r.scalars()["final_primary_area_fraction"] for r in (run, other)
            ],
            "last_stop_secondary_%": [
                100 * r.scalars()["final_secondary_area_fraction"] for r in (run, other)
            ],
        }
    )
    print(both.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    difference = {"MU": other.MU - run.MU, "V_ratio": other.V / run.V}
    print(
        f"A 10 % -> 20 % (seed {args.seed} both): MU {difference['MU']:+.4f}, "
        f"V x {difference['V_ratio']:.3g} ({run.V * M3_TO_MM3:.4g} -> "
        f"{other.V * M3_TO_MM3:.4g} mm³ per stop)"
    )
    # both runs' MU per stop in one figure, each labelled
    paths.append(figures / "compare_mu_per_stop.png")
    plot_mu_per_stop(
        {"A = 10 %": run, "A = 20 %": other},
        paths[-1],
        title=f"WP = 1e-13, seed {args.seed}: A = 10 % and 20 %",
    )
    paths.append(figures / "compare_final_maps.png")
    plot_fibre_maps(
        {
            f"A = {a} % after the last stop": (r.dataset["final_status"].to_numpy(), radius, angle)
            for a, r in ((10, run), (20, other))
        },
        paths[-1],
        ncols=1,
    )
    print("figures:", figures)
    return {
        "run": run,
        "other": other,
        "read_back": back,
        "per_stop": table,
        "run_file": run_file,
        "figures": paths,
        "difference": difference,
    }


if __name__ == "__main__":
    main()
