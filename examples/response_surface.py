"""A response-surface study from Python: design, runs, quadratic fits, optimum, figures.

Runs the shipped central composite design ``response_surface`` (WP and WR log-coded, A linear; 17
runs) on the quick band (2 mm, 21 rows) and asks where the pad emits least at a COF near
0.35, as ``brakeca run response_surface --quick`` and ``brakeca optimize FOLDER --reduce 0.1
-g log10_V_mm3:min:-1.5:1 -g MU:target:0.3:0.35:0.45`` would, but step by step (the surfaces
reduced by backward elimination at alpha 0.1, as ``--reduce 0.1`` does; without it,
``brakeca optimize`` fits the full quadratics and finds another optimum)::

    .venv/bin/python examples/response_surface.py          # 1 min 29 s, 2 cores, compiled kernels
    .venv/bin/python examples/response_surface.py --tiny     # a 5 x 100 cell band, 2 stops

The ``--tiny`` variant (seconds; what the test suite runs) shows the workflow, not results.
Outputs go to ``examples_out/response_surface`` (``examples_out/response_surface_tiny`` with
``--tiny``, whose runs are of another band; ``--out`` for another folder).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from brakeca.campaign import run_campaign
from brakeca.design import load_design
from brakeca.plotting import plot_overlaid_contours, plot_response_surface
from brakeca.rsm import Goal, backward_elimination, optimize
from brakeca.study import with_log_v

#: a 5 x 100 cell band and the first two stops: the workflow in seconds, not a result
TINY = {"mesh.n_radial": 5, "mesh.n_angular": 100, "mesh.n_subdomains": 10}


def main(argv: list[str] | None = None) -> dict:
    """Run the example; returns the fits and the optimum (for the tests)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="a 5 x 100 cell band, 2 stops")
    parser.add_argument(
        "--out", type=Path, default=None, help="output folder (default examples_out/...)"
    )
    parser.add_argument(
        "--workers", type=int, default=None, help="runs at once (default: one per core)"
    )
    args = parser.parse_args(argv)
    if args.out is None:  # the two variants' runs differ: each in its own folder
        args.out = Path("examples_out/response_surface" + ("_tiny" if args.tiny else ""))

    design = load_design("response_surface")
    print(design.kind)  # central composite design (face-centred, α = 1), 3 factors: ...
    result = run_campaign(
        design,
        args.out,
        quick=not args.tiny,
        overrides=TINY if args.tiny else None,
        max_stops=2 if args.tiny else None,
        workers=1 if args.tiny else args.workers,
        executor="serial" if args.tiny else "local",
        progress=not args.tiny,
    )
    summary = with_log_v(result.summary)  # adds log10_V_mm3, where V's effects add

    # the quadratic surfaces, reduced by backward elimination at alpha 0.1 (hierarchical)
    fits = {r: backward_elimination(summary, design.factors, r) for r in ("MU", "log10_V_mm3")}
    for fit in fits.values():
        print(fit.equation())
        print(fit.anova[["source", "df", "adj_ss", "F", "p_value"]].to_string(index=False))
        print("R²(pred) =", round(fit.statistics["r_squared_pred"], 3), "|", *fit.notes)

    # the least V at MU near 0.35: on the quick band V is about a tenth of the full band's
    goals = [
        Goal("log10_V_mm3", "minimize", -1.5, 1.0),
        Goal("MU", "target", 0.30, 0.45, target=0.35),
    ]
    best = optimize(fits, goals)
    print(pd.Series(best.levels, name="setting"))
    print("fitted:", best.predicted, "composite desirability:", round(best.composite, 3))

    figures = args.out / "example_figures"
    for response, fit in fits.items():
        plot_response_surface(fit, figures / f"surface_{response}.png")
    plot_overlaid_contours(fits, goals, best, figures / "overlaid_contours.png")
    print("figures:", figures)
    return {"fits": fits, "optimum": best, "figures": figures}


if __name__ == "__main__":
    main()
