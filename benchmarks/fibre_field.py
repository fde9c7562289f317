"""What the fibre field's exposure did in a run: per group of stops, the cells exposed (of them,
those exposed only after their stop), the largest lag of those, and the fibre above them against
the pad volume worn.

Usage::

    .venv/bin/brakeca simulate --set pad.fibre_model=field --set WP=1e-13 --set A=10 \\
        --seed 2016 --stops 60 -o field.nc
    .venv/bin/python benchmarks/fibre_field.py field.nc [--every 10]

Prints one line per group of ``--every`` stops, then the run's totals (docs/model.md section 7).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from brakeca.results import RunResult


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", help="a run file of pad.fibre_model = 'field' (.nc)")
    parser.add_argument("--every", type=int, default=10, help="stops per line [default: 10]")
    args = parser.parse_args(argv)
    if args.every < 1:
        parser.error(f"--every must be >= 1, got {args.every}")
    try:
        ds = RunResult.from_netcdf(args.run).dataset
    except (OSError, ValueError) as exc:
        parser.error(str(exc))
    if "fibre_cells_exposed" not in ds:
        parser.error(f"{args.run}: not a run of pad.fibre_model = 'field'")
    exposed = ds.fibre_cells_exposed.values
    late = ds.fibre_cells_exposed_late.values
    lag = ds.fibre_exposure_lag.values
    cut = ds.fibre_volume_cut_as_resin.values
    # absent from run files written before the variable was added
    skipped = int(ds["fibre_intervals_skipped"].sum()) if "fibre_intervals_skipped" in ds else "?"
    worn = ds.generated_volume.values
    primary = ds.primary_area_fraction.values
    cof = ds.mean_cof.values
    rule7 = ds.rule_firings.sel(rule=7).values
    n = exposed.size
    print(
        f"{'stops':>9} {'exposed':>9} {'late':>6} {'rule 7':>8} {'max lag um':>10} "
        f"{'late fibre / worn':>17} {'primary':>8} {'COF':>6}"
    )
    for a in range(0, n, args.every):
        b = min(n, a + args.every)
        share = cut[a:b].sum() / worn[a:b].sum() if worn[a:b].sum() > 0 else float("nan")
        print(
            f"{a + 1:>4}-{b:<4} {int(exposed[a:b].sum()):>9} {int(late[a:b].sum()):>6} "
            f"{int(rule7[a:b].sum()):>8} {1e6 * lag[a:b].max():>10.1f} {share:>17.6f} "
            f"{primary[b - 1]:>8.4f} "
            f"{np.mean(cof[a:b]):>6.3f}"
        )
    print(
        f"total: {int(exposed.sum())} cells exposed ({int(late.sum())} after their stop, "
        f"{skipped} fibres passed unexposed), "
        f"max lag {1e6 * lag.max():.1f} um, fibre above those {1e9 * cut.sum():.4f} mm3 of "
        f"{1e9 * worn.sum():.3f} mm3 worn ({cut.sum() / worn.sum():.2e}), MU {float(ds.MU):.4f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
