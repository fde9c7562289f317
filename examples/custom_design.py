"""A design of your own from Python: campaign, resume, main effects, ANOVA, interactions.

Writes a design that ships with no preset, a 2 x 2 x 2 full factorial over the plateaus'
specific wear rate WP, the COF law's intercept ``friction.mu_0`` (a configuration field the
paper does not vary) and the fibre area fraction A, two seeds per test (16 runs), as a design
file (docs/designs.md has every key); runs it on the quick band (2 mm, 21 rows, the whole
cycle); runs it again into the same folder, which reuses every run; reads the campaign back
and analyses it (level means, the ANOVA with its model summary, a two-way interaction table)
and draws the main-effects plots, as ``brakeca run DESIGN.toml -o FOLDER --quick`` and
``brakeca analyze FOLDER`` would, step by step::

    .venv/bin/python examples/custom_design.py           # 16 runs, 2 workers: 4 min 15 s
    .venv/bin/python examples/custom_design.py --tiny    # a 5 x 100 cell band, 2 stops

(4 min 15 s measured on 2 cores that another job shared; the runs with WP = 1e-13 take the
longest.) The ``--tiny`` variant (seconds; what the test suite runs) shows the workflow, not
results. Outputs go to ``examples_out/custom_design`` (``examples_out/custom_design_tiny`` with
``--tiny``, whose runs are of another band; ``--out`` for another folder): the design file,
the campaign folder ``campaign/`` and the figures ``figures/``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from brakeca.analysis import anova, interaction_table, main_effects, model_summary
from brakeca.campaign import load_campaign, run_campaign
from brakeca.design import load_design
from brakeca.plotting import plot_interactions, plot_main_effects
from brakeca.study import with_log_v

#: The design: the keys of a design file (docs/designs.md, "The design file").
DESIGN = """\
name = "wear_vs_friction"
description = "Plateau wear rate, COF-law intercept and fibre fraction, two seeds per test"
base = "paper"            # the parameter preset every run starts from
root_seed = 2026          # every run's seed derives from it (test, replicate)
replicates = 2            # two seeds per test: pure error for the ANOVA

[[factors]]
name = "WP"               # a paper factor needs no field; WP in m³/(N·m)
levels = [1e-15, 1e-13]
labels = ["-", "+"]

[[factors]]
name = "mu0"
field = "friction.mu_0"   # any configuration field by its dotted name (brakeca config)
levels = [0.5, 0.7]
labels = ["-", "+"]
label = "COF at zero pressure"

[[factors]]
name = "A"                # a paper factor in %
levels = [10.0, 20.0]
labels = ["-", "+"]
"""

#: a 5 x 100 cell band and the first two stops: the workflow in seconds, not a result
TINY = {"mesh.n_radial": 5, "mesh.n_angular": 100, "mesh.n_subdomains": 10}


def _cells(table: pd.DataFrame, scale: float = 1.0) -> str:
    """An interaction table as text, its levels written as ``name=level``."""
    shown = table * scale
    shown.index = [f"{table.index.name}={v:g}" for v in table.index]
    shown.columns = [f"{table.columns.name}={v:g}" for v in table.columns]
    return shown.to_string(float_format=lambda v: f"{v:.4g}")


def main(argv: list[str] | None = None) -> dict:
    """Run the example; returns the design, both campaign calls, the loaded campaign, the
    tables and the figures (for the tests)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="a 5 x 100 cell band, 2 stops")
    parser.add_argument(
        "--out", type=Path, default=None, help="output folder (default examples_out/...)"
    )
    parser.add_argument("--workers", type=int, default=2, help="runs at once (default 2)")
    args = parser.parse_args(argv)
    if args.out is None:  # the two variants' runs differ: each in its own folder
        args.out = Path("examples_out/custom_design" + ("_tiny" if args.tiny else ""))

    # the design file, read as `brakeca run` reads it: its levels are checked against the
    # fields they set before anything runs (brakeca.design.design_from_dict(tomllib.loads(
    # DESIGN)) reads the same text without a file)
    args.out.mkdir(parents=True, exist_ok=True)
    design_file = args.out / "wear_vs_friction.toml"
    design_file.write_text(DESIGN, encoding="utf-8")
    design = load_design(design_file)
    n_runs = design.n_tests * design.replicates
    print(
        f"{design.name}: {design.kind}, {design.n_tests} tests x {design.replicates} seeds "
        f"= {n_runs} runs"
    )
    for f in design.factors:
        print(f"  {f.name:4} {f.field:22} levels {', '.join(f'{v:g}' for v in f.levels)} {f.unit}")

    folder = args.out / "campaign"
    options = {  # the same options both times: a campaign of other options is refused
        "quick": not args.tiny,
        "overrides": TINY if args.tiny else None,
        "max_stops": 2 if args.tiny else None,
        "workers": 1 if args.tiny else args.workers,
        "executor": "serial" if args.tiny else "local",
        "progress": not args.tiny,
    }
    result = run_campaign(design, folder, **options)
    print(
        f"campaign {folder}: {len(result.computed)} runs computed, {len(result.reused)} reused, "
        f"{len(result.failed)} failed"
    )
    # the same call again: every run's file is there, so nothing is computed (after an
    # interruption it would compute only the runs missing)
    again = run_campaign(design, folder, **options)
    print(
        f"run again into the same folder: {len(again.computed)} computed, "
        f"{len(again.reused)} of {len(again.summary)} reused"
    )

    # read back from the folder (summary.csv, campaign.nc, design.toml), as a later script would
    loaded = load_campaign(folder)
    summary = with_log_v(loaded.summary)  # adds log10_V_mm3, where V's effects add
    factors = loaded.design.factors
    names = [f.name for f in factors]
    per_test = summary.groupby(["test", *names], sort=True)[["MU", "V_mm3"]].mean()
    print("mean of the two seeds per test (V in mm³ per stop):")
    print(per_test.reset_index().to_string(index=False, float_format=lambda v: f"{v:.4g}"))

    # level means of MU [-] and V [mm³ per stop]
    effects = main_effects(summary, factors, "MU")
    effects["V_mm3"] = main_effects(summary, factors, "V_mm3")["mean"]
    effects = effects.rename(columns={"mean": "MU"})[["factor", "label", "level", "MU", "V_mm3"]]
    print("level means (main effects):")
    print(effects.to_string(index=False, float_format=lambda v: f"{v:.4g}"))

    # the ANOVA: main effects and two-factor interactions, Type II; V on the log scale
    tables = {}
    for response in ("MU", "log10_V_mm3"):
        table = anova(summary, factors, response)
        tables[response] = table
        fit = model_summary(table).iloc[0]
        print(f"ANOVA of {response} ({table.attrs['typ']}, {fit['formula']}):")
        shown = table[["term", "df", "F", "p_value", "percent_contribution"]]
        print(shown.to_string(index=False, float_format=lambda v: f"{v:.3g}", na_rep=""))
        print(
            f"  S = {fit['s']:.3g}, R² = {100 * fit['r_squared']:.1f} %, "
            f"R²(adj) = {100 * fit['r_squared_adj']:.1f} %, "
            f"R²(pred) = {100 * fit['r_squared_pred']:.1f} %"
        )
    cells = interaction_table(summary, "WP", "mu0", "MU")
    print("MU at each WP and mu0 (interaction table):")
    print(_cells(cells))

    figures = args.out / "figures"
    paths = [
        figures / "main_effects_MU.png",
        figures / "main_effects_V.png",
        figures / "interactions_MU.png",
    ]
    plot_main_effects(summary, factors, "MU", paths[0])
    plot_main_effects(summary, factors, "V", paths[1])  # V is plotted in mm³
    plot_interactions(summary, factors, "MU", paths[2])
    print("figures:", figures)
    return {
        "design": design,
        "result": result,
        "again": again,
        "loaded": loaded,
        "main_effects": effects,
        "anova": tables,
        "interaction": cells,
        "figures": paths,
    }


if __name__ == "__main__":
    main()
