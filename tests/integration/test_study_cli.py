"""`brakeca run` and `brakeca analyze` end to end on a 2x2 design over tiny grids."""

from __future__ import annotations

import itertools
import re
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from campaign_helpers import TINY_CLI
from typer.testing import CliRunner

from brakeca.cli import app
from brakeca.results import RunResult

DESIGN = """
name = "tiny"
base = "paper"
root_seed = 5
[[factors]]
name = "S"
field = "S"
levels = [0.0, 1.0]
labels = ["-", "+"]
[[factors]]
name = "A"
field = "A"
levels = [10.0, 20.0]
labels = ["-", "+"]
unit = "%"
"""

TINY = TINY_CLI


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    design = folder / "design_in.toml"
    design.write_text(DESIGN)
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(folder / "c"), *TINY])
    assert res.exit_code == 0, res.output
    return folder / "c", res


def test_outputs_present_and_consistent(campaign):
    out, res = campaign
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary["test"]) == [1, 2, 3, 4]
    assert list(summary["S"]) == [0, 1, 0, 1] and list(summary["A"]) == [10, 10, 20, 20]
    ds = xr.open_dataset(out / "campaign.nc", engine="h5netcdf")
    for _, row in summary.iterrows():
        run = RunResult.from_netcdf(out / "runs" / f"{row['run_id']}.nc")
        assert run.MU == pytest.approx(row["MU"], rel=1e-15)
        assert run.V == pytest.approx(row["V"], rel=1e-15)
        np.testing.assert_array_equal(
            ds["mean_cof"].sel(run=int(row["test"])).values, run.dataset["mean_cof"].values
        )
    ds.close()
    # the block-by-block figure takes the campaign as block_table does (it had failed with
    # "no attribute 'empty'"), its rows named by the design's levels
    from brakeca.campaign import load_campaign
    from brakeca.plotting import plot_by_block
    from brakeca.study import block_table

    result = load_campaign(out)
    drawn = [
        plot_by_block(result).axes[0],
        plot_by_block(block_table(result), result).axes[0],
    ]
    names = [[t.get_text() for t in ax.get_yticklabels()] for ax in drawn]
    assert names[0] == names[1] and names[0][0].startswith("T1: S-")
    assert [t.get_text() for t in drawn[0].texts] == [t.get_text() for t in drawn[1].texts]
    for name in (
        "main_effects_MU",
        "main_effects_V",
        "interactions_MU",
        "interactions_V",
        "mu_per_stop",
        "v_per_stop",
        "mu_per_stop_by_test",
        "v_per_stop_by_test",
        "secondary_area_by_level",
        "contact_area_by_level",
        "v_per_run",
        "mu_vs_v",
        "fibre_maps",
        "pareto_MU",
        "pareto_V",
        "residuals_MU",
        "residuals_V",
        "main_effects_log10_V_mm3",
        "residuals_log10_V_mm3",
        "residuals_by_level_MU",
        "residuals_by_level_log10_V_mm3",
        "main_effects_MU_SD",
        "residuals_MU_SD",
        "cube_MU",
        "cube_V",
        "cube_MU_SD",
    ):
        assert (out / "figures" / f"{name}.png").stat().st_size > 1000
    # one residual degree of freedom: no λ, so no Box-Cox plot (the table says why)
    assert not (out / "figures" / "box_cox.png").exists()
    assert len(list((out / "figures").glob("final_map_test*.png"))) == 4
    for resp in ("MU", "V", "log10_V_mm3", "MU_SD"):
        for table in (
            "main_effects",
            "anova",
            "model_summary",
            "interactions",
            "ranked_effects",
            "residuals",
        ):
            assert (out / "tables" / f"{table}_{resp}.csv").exists()
    # the per-stop table: every run's stops, in friendly units; MU and V are its means
    per_stop = pd.read_csv(out / "tables" / "per_stop.csv")
    assert list(per_stop.columns[:6]) == ["test", "replicate", "S", "A", "seed", "stop"]
    assert len(per_stop) == 4 * 2 and list(per_stop["stop"]) == [1, 2] * 4
    by_test = per_stop.groupby("test")
    np.testing.assert_allclose(by_test["mean_cof"].mean(), summary["MU"], rtol=1e-12)
    np.testing.assert_allclose(by_test["emitted_mm3"].mean(), summary["V"] * 1e9, rtol=1e-12)
    assert list(by_test["seed"].first()) == list(summary["seed"])
    run = RunResult.from_netcdf(out / "runs" / f"{summary['run_id'][2]}.nc").dataset
    third = per_stop[per_stop["test"] == 3]
    np.testing.assert_allclose(third["line_pressure_MPa"], run["line_pressure"] * 1e-6)
    assert list(third["block"]) == list(run["block"].values)
    # block by block: each run's emitted volume shared out over its blocks
    by_block = pd.read_csv(out / "tables" / "by_block.csv")
    np.testing.assert_allclose(
        by_block.groupby("test")["emitted_total_mm3"].sum(), by_test["emitted_mm3"].sum()
    )
    np.testing.assert_allclose(by_block.groupby("test")["share_of_emitted_percent"].sum(), 100.0)
    html = (out / "report.html").read_text()
    # a block cycle has no PM10 in mg/km, and the report says why (a report review: it
    # appeared nowhere, unsaid)
    assert "No brake PM10 in mg/km: the runs&#39; drive cycle is a block cycle" in html or (
        "No brake PM10 in mg/km: the runs' drive cycle is a block cycle" in html
    )
    n_img = len(re.findall(r'<img[^>]+src="data:image/png;base64,', html))
    # per response (MU, V, log10 V, MU_SD: main effects, interactions, Pareto, residuals and, both
    # factors having two levels, the effects, the residuals by level), per campaign (MU per
    # stop, by run, by test and by level, the secondary plateau and contact areas by level,
    # V per stop, by run and by test, V per run, MU against V, fibre maps; no Box-Cox plots at
    # one residual df), maps and, both factors of two levels, the cube plots (a square here)
    # of MU, V and MU_SD
    assert n_img == 6 * 4 + 3 + 10 + 4
    # the Box-Cox check of MU's, V's and MU_SD's scale, under the ANOVA model (main effects:
    # the model with the interaction would leave 4 runs no residual degree of freedom)
    scales = pd.read_csv(out / "tables" / "box_cox.csv")
    assert list(scales["response"]) == ["MU", "V", "MU_SD"]
    assert list(scales["model"]) == [f"ANOVA model: {r} ~ S + A" for r in ("MU", "V", "MU_SD")]
    assert (scales["df_resid"] == 1).all()
    assert scales["lambda_hat"].isna().all()
    assert scales["note"].str.startswith("the model leaves one residual degree of freedom").all()
    assert '<h3 id="anova-box-cox">Scale of the responses (Box–Cox)</h3>' in html
    assert (out / "tables" / "effects_MU.csv").exists()
    # the maps' captions give each level with its unit (S has none)
    assert "Test 3 (S = 0, A = 20 %): plateaus after the first 2 of the cycle" in html
    assert "Model summary: residual standard deviation s = " in html
    assert "<h2>In short</h2>" in html and "<li>MU: " in html  # the significant terms
    # the report says at its top what the campaign left out of the paper's study
    assert (
        "These runs were made on a grid of 5 × 100 cells instead of the paper&#39;s 201 × 1000 "
        "(its Table 5)" in html
    )
    assert "over the first 2 of the cycle&#39;s 170 stops only (--stops)" in html
    # and the captions say so too (they had said "over the whole cycle")
    assert "MU per stop over the first 2 of the cycle&#39;s 170 stops for every run" in html
    assert "whole cycle" not in html
    # the tables' units are written beside them (V in m³ there, mm³ in the report)
    readme = (out / "tables" / "README.md").read_text(encoding="utf-8")
    assert "**V in m³ per stop**" in readme and "`per_stop.csv`" in readme
    assert "The CSV tables in tables/ keep SI units: V in m³ there" in html
    assert "report:" in res.stdout and "summary:" in res.stdout


def test_the_report_s_in_short_is_printed_too(campaign, tmp_path):
    """The main job ends with the report's "In short" on the terminal, line for line as the
    report has it, and so does brakeca analyze (a user had to open the report for it)."""
    from html import escape

    out, res = campaign
    html = (out / "report.html").read_text(encoding="utf-8")
    for output in (
        res.output,
        CliRunner()
        .invoke(app, ["analyze", str(out), "--no-figures", "-o", str(tmp_path / "a")])
        .output,
    ):
        assert "in short (the ANOVA's terms with p < 0.05, largest share first):" in output
        after = output[output.index("largest share first):") :].splitlines()[1:]
        lines = [line.strip() for line in itertools.takewhile(lambda x: x.startswith("  "), after)]
        assert [line.split(":")[0] for line in lines] == ["MU", "V", "log10_V_mm3", "MU_SD"]
        for line in lines:
            assert escape(line, quote=False) in html.replace("&#39;", "'")
        assert output.index("in short") < output.index("report: ")


def test_main_effects_table_matches_summary(campaign):
    out, _ = campaign
    summary = pd.read_csv(out / "summary.csv")
    me = pd.read_csv(out / "tables" / "main_effects_MU.csv")
    for factor in ("S", "A"):
        for level, group in summary.groupby(factor):
            row = me[(me["factor"] == factor) & np.isclose(me["level"], level)]
            assert float(row["mean"].iloc[0]) == pytest.approx(group["MU"].mean(), rel=1e-12)


def test_rerun_reuses_and_analyze_rewrites(campaign, tmp_path):
    """(On a copy of the module's campaign: it removes the report, the maps and tables the
    other tests read, which had made them pass in file order only; a tests review.)"""
    import shutil

    out = tmp_path / "c"
    shutil.copytree(campaign[0], out)
    mtimes = {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.nc")}
    design = campaign[0].parent / "design_in.toml"
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *TINY, "--no-report"])
    assert res.exit_code == 0, res.output
    assert "0 run(s) computed, 4 reused" in res.output
    assert mtimes == {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.nc")}
    (out / "report.html").unlink()
    assert list((out / "figures").glob("final_map_test*.png"))
    # a figure of an earlier analysis of other responses or another kind of design, and a
    # file of the user's
    for name in ("surface_MU.png", "profile_MU.png", "cube_log10_V_mm3.png", "surface_notes.png"):
        (out / "figures" / name).write_bytes(b"x")
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-run-maps"])
    assert res.exit_code == 0, res.output
    assert (out / "report.html").exists()
    # the maps of the earlier analysis, which the report no longer lists, are gone, and so
    # are its other figures this one did not draw; the user's file stays
    assert not list((out / "figures").glob("final_map_test*.png"))
    for name in ("surface_MU.png", "profile_MU.png", "cube_log10_V_mm3.png"):
        assert not (out / "figures" / name).exists(), name
    assert (out / "figures" / "surface_notes.png").read_bytes() == b"x"
    # every figure it draws is one a later analysis removes when it does not draw it
    from brakeca.study import _REPORT_FIGURES

    for path in (out / "figures").iterdir():
        assert path.name in {*_REPORT_FIGURES, "surface_notes.png"}, path.name
    assert "Type II ANOVA of MU" in (out / "report.html").read_text(encoding="utf-8")
    # Type III sums of squares on request (the design's anova_type is 2)
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures", "--anova-type", "3"])
    assert res.exit_code == 0, res.output
    assert "Type III (adjusted) ANOVA of MU" in (out / "report.html").read_text(encoding="utf-8")
    res = CliRunner().invoke(app, ["analyze", str(out), "--anova-type", "1"])
    assert res.exit_code != 0 and "--anova-type: expected 2 (Type II) or 3" in res.output
    for bad in ("0", "1"):
        res = CliRunner().invoke(app, ["analyze", str(out), "--reduce", bad])
        assert res.exit_code != 0 and "--reduce" in res.output
    res = CliRunner().invoke(app, ["analyze", str(out), "--order", "0"])
    assert res.exit_code != 0 and "--order: expected the most factors in a model term, 1 to 10" in (
        res.output
    )
    # the model's order on request: main effects only (the tables alone: --no-figures)
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures", "--order", "1"])
    assert res.exit_code == 0, res.output
    table = pd.read_csv(out / "tables" / "anova_MU.csv", keep_default_na=False)
    assert [t for t in table["term"] if t != "Residual"] == ["S", "A"]
    assert "with 2 factors" not in res.output
    # an order beyond the factors: said to be every interaction (a new user's review)
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures", "--order", "4"])
    assert res.exit_code == 0, res.output
    assert (
        "terms up through order 4, which with 2 factors is every interaction, as --order 2 gives"
    ) in " ".join(res.output.split())
    # a reduced model on request: the ANOVA's note names what backward elimination removed,
    # and the residual plots (their caption, ending in ';': the Box-Cox table's cell holds
    # the ANOVA model's formula too) are of the same model; every term removed: no effects
    # table or figure of an earlier analysis is left behind (the figure as one with figures
    # would have left it). (One analysis with figures for both: at 0.5 this campaign's MU
    # had lost every term already; a review of the suite's time.)
    assert (out / "tables" / "effects_MU.csv").is_file()
    (out / "figures").mkdir(exist_ok=True)
    (out / "figures" / "effects_MU.png").write_bytes(b"x")
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-run-maps", "--reduce", "1e-300"])
    assert res.exit_code == 0, res.output
    table = pd.read_csv(out / "tables" / "anova_MU.csv", keep_default_na=False)
    assert "backward elimination (alpha to remove 1e-300" in table["note"].iloc[0]
    kept = [t for t in table["term"] if t != "Residual"]
    formula = "MU ~ " + (" + ".join(kept) or "1")
    assert f"model: {formula};" in (out / "report.html").read_text(encoding="utf-8")
    assert list(table["term"]) == ["Residual"]
    assert not (out / "tables" / "effects_MU.csv").exists()
    assert not (out / "figures" / "effects_MU.png").exists()
    # a design's own alpha_to_remove set aside on request (a growth review: nothing could)
    text = (out / "design.toml").read_text(encoding="utf-8")
    (out / "design.toml").write_text(
        text.replace("root_seed = ", "alpha_to_remove = 1e-300\nroot_seed = ", 1), encoding="utf-8"
    )
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures"])
    assert res.exit_code == 0, res.output
    table = pd.read_csv(out / "tables" / "anova_MU.csv", keep_default_na=False)
    assert "backward elimination (alpha to remove 1e-300" in table["note"].iloc[0]
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures", "--reduce", "none"])
    assert res.exit_code == 0, res.output
    table = pd.read_csv(out / "tables" / "anova_MU.csv", keep_default_na=False)
    assert "backward elimination" not in " ".join(table["note"].astype(str))
    # the whole model (S:A pooled, as it saturates these four runs), not the reduced one
    assert [t for t in table["term"] if t != "Residual"] == ["S", "A"]
    res = CliRunner().invoke(app, ["analyze", str(out), "--reduce", "some"])
    assert res.exit_code == 2 and "--reduce: expected a level above 0 and below 1 (0.1 in " in (
        " ".join(res.output.split())
    )
    (out / "design.toml").write_text(text, encoding="utf-8")


def test_without_figures_the_same_tables_and_a_report_that_says_so(campaign, tmp_path):
    """--no-figures: the tables and a report without figures, quickly (for trying one model
    after another); the figures of an earlier analysis go, as they may show another model,
    and a file of the user's in figures/ stays. `brakeca run` and `paper` take it too."""
    import shutil

    out = tmp_path / "c"
    shutil.copytree(campaign[0], out)
    drawn = {p.name for p in (out / "figures").iterdir()}
    assert "effects_MU.png" in drawn and any(n.startswith("final_map_") for n in drawn)
    (out / "figures" / "mine.txt").write_text("notes", encoding="utf-8")
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures"])
    assert res.exit_code == 0, res.output
    said = " ".join(res.output.split())
    assert "analysing 4 runs: tables and the report (about 3 s)" in said
    assert "figures:" not in said and f"report: {out / 'report.html'}" in said
    assert [p.name for p in (out / "figures").iterdir()] == ["mine.txt"]
    for table in (campaign[0] / "tables").iterdir():  # as the analysis with figures wrote them
        assert (out / "tables" / table.name).read_bytes() == table.read_bytes(), table.name
    html = " ".join((out / "report.html").read_text(encoding="utf-8").split())
    assert "<img" not in html and "<figure" not in html
    header = html[: html.index("</header>")]  # under the title
    assert (
        "Written without its figures (--no-figures, or write_study(..., figures=False))" in header
    )
    assert "Type II ANOVA of MU" in html
    # with no file of the user's there, the empty folder goes too; by `brakeca run` on the
    # finished campaign (nothing computed)
    # a folder sent without its run files: the figures that could not be drawn again stay
    sent = tmp_path / "sent"
    shutil.copytree(campaign[0], sent, ignore=shutil.ignore_patterns("runs"))
    res = CliRunner().invoke(app, ["analyze", str(sent), "--no-figures"])
    assert res.exit_code == 0, res.output
    kept = sorted(p.name for p in (sent / "figures").iterdir())
    assert kept == ["fibre_maps.png"] + [f"final_map_test0{t}_r0.png" for t in (1, 2, 3, 4)]
    (out / "figures" / "mine.txt").unlink()
    design = campaign[0].parent / "design_in.toml"
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *TINY, "--no-figures"])
    assert res.exit_code == 0, res.output
    assert "0 run(s) computed, 4 reused" in res.output
    assert not (out / "figures").exists()
    assert "Written without its figures" in (out / "report.html").read_text(encoding="utf-8")


def test_plot_draws_a_campaigns_runs(campaign, tmp_path):
    out, _ = campaign
    figures = tmp_path / "figs"
    res = CliRunner().invoke(app, ["plot", str(out), "--test", "3", "-o", str(figures)])
    assert res.exit_code == 0, res.output
    assert "[1/1] test 3: wrote" in res.output
    assert sorted(p.name for p in figures.iterdir()) == ["test03_r0"]
    names = sorted(p.name for p in (figures / "test03_r0").iterdir())
    assert names == ["maps.png", "mu_per_stop.png", "steps.png"]
    # every run, by default into the campaign's run_figures folder
    res = CliRunner().invoke(app, ["plot", str(out)])
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in (out / "run_figures").iterdir()) == [
        f"test{t:02d}_r0" for t in (1, 2, 3, 4)
    ]
    # a test the campaign lacks, --test on a run file, an unfinished campaign
    res = CliRunner().invoke(app, ["plot", str(out), "--test", "5"])
    assert res.exit_code == 2 and "--test 5: the campaign has tests 1 to 4" in res.output
    run_file = next((out / "runs").glob("*.nc"))
    res = CliRunner().invoke(app, ["plot", str(run_file), "--test", "1"])
    assert res.exit_code == 2 and "--test selects runs of a campaign folder" in res.output
    unfinished = tmp_path / "unfinished"
    unfinished.mkdir()
    (unfinished / "design.toml").write_text((out / "design.toml").read_text())
    res = CliRunner().invoke(app, ["plot", str(unfinished)])
    assert res.exit_code == 2 and "the campaign has not finished" in res.output
    res = CliRunner().invoke(app, ["plot", str(tmp_path)])
    assert res.exit_code == 2 and "not a campaign folder" in res.output
    # a summary edited by hand is refused as an analysis refuses it (a security review: one
    # without a test column, or of a 400-digit test, had ended plot with a traceback)
    edited = tmp_path / "edited"
    shutil.copytree(out, edited, ignore=shutil.ignore_patterns("runs", "figures", "run_figures"))
    summary = pd.read_csv(edited / "summary.csv", dtype=str, keep_default_na=False)
    for damage in ("a long test", "no test"):
        if damage == "a long test":
            summary.loc[0, "test"] = "9" * 400
            summary.to_csv(edited / "summary.csv", index=False)
        else:
            summary.drop(columns="test").to_csv(edited / "summary.csv", index=False)
        for command in ("plot", "analyze"):
            res = CliRunner().invoke(app, [command, str(edited)])
            said = " ".join(res.output.split())
            assert res.exit_code == 2 and "summary.csv: its" in said, (damage, command, said)
            assert "it was edited or damaged" in said, said


def test_bad_design_is_reported_before_any_run(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(DESIGN.replace("levels = [10.0, 20.0]", "levels = [10.0, 150.0]"))
    res = CliRunner().invoke(app, ["run", str(bad), "-o", str(tmp_path / "c"), *TINY])
    assert res.exit_code == 2
    assert "bad.toml" in res.output and "150" in res.output
    assert not (tmp_path / "c" / "runs").exists() or not list((tmp_path / "c" / "runs").iterdir())
    # a unit in brackets is not taken for console markup (rich dropped "[m^3/(N m)]")
    bad.write_text(DESIGN + '[[factors]]\nname = "WP"\nlevels = [1e-13, -5]\n')
    res = CliRunner().invoke(app, ["run", str(bad), "-o", str(tmp_path / "c"), *TINY[:4]])
    assert res.exit_code == 2
    assert "level -5 [m^3/(N m)] is not valid" in " ".join(res.output.split()), res.output


def test_one_factor_trace_campaign_reports_pm10(tmp_path):
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "one"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "A"\nfield = "A"\n'
        'levels = [10.0, 20.0]\nunit = "%"\n'
    )
    out = tmp_path / "c"
    res = CliRunner().invoke(
        app,
        [
            "run",
            str(design),
            "-o",
            str(out),
            "--cycle",
            "example_trace",
            "--set",
            "mesh.n_radial=3",
            "--set",
            "mesh.n_angular=100",
            "--executor",
            "serial",
        ],
    )
    assert res.exit_code == 0, res.output
    pm10 = pd.read_csv(out / "tables" / "pm10.csv")
    assert np.all(pm10["PM10_low_mg_km"] < pm10["PM10_mg_km"])
    assert np.all(pm10["PM10_mg_km"] < pm10["PM10_high_mg_km"])
    html = (out / "report.html").read_text()
    assert "7 mg/km" in html and "3 mg/km" in html and "<th>PM10 [mg/km]</th>" in html
    # each band against each limit, in the table, its own section and "In short" (a review:
    # the report gave the figures and a note, no verdict, and not the factors used)
    for column, limit in (("vs_7_mg_km", 7.0), ("vs_3_mg_km", 3.0)):
        expected = np.where(
            pm10["PM10_high_mg_km"] < limit,
            "below",
            np.where(pm10["PM10_low_mg_km"] > limit, "above", "straddles"),
        )
        assert list(pm10[column]) == list(expected)
    section = html[html.index('<section id="pm10">') :]
    section = section[: section.index("</section>")]
    assert "airborne share 0.5 (0.3 to 0.6)" in section
    assert "the limits hold for the WLTP-Brake cycle" in section
    # what the figures are not, in the report, tables/README.md and each run file (an
    # emissions review), and short headers in the table (a diff review)
    import html as html_text

    from brakeca.emissions import CAVEAT
    from brakeca.results import RunResult

    assert f"Each is {CAVEAT}." in html_text.unescape(section)
    assert (
        "<th>7 mg/km (M1)</th>" in section and "<th>3 mg/km (M1, battery-electric)</th>" in section
    )
    readme = " ".join((out / "tables" / "README.md").read_text(encoding="utf-8").split())
    assert f"each figure is {CAVEAT}." in readme
    run = RunResult.from_netcdf(out / "runs" / f"{pm10['run_id'][0]}.nc")
    assert run.dataset.attrs["comment"].endswith(CAVEAT)
    assert "The factors (brakeca&#39;s defaults, with each run&#39;s pads" in section
    # friction alone against the battery-electric limit is said (a review: simulate said it)
    assert "2 of the 2 runs brake by friction alone (cycle.trace.friction_share = 1)" in section
    assert "Brake PM10 over " in " ".join(res.output.split())
    # the same campaign with the user's factors: nothing run again, PM10 scaled
    factors = tmp_path / "emissions.toml"
    factors.write_text("[emissions]\nairborne_fraction = 0.4\n")
    again = CliRunner().invoke(
        app,
        [
            "analyze",
            str(out),
            "-o",
            str(tmp_path / "a"),
            "--emissions",
            str(factors),
            "--no-figures",
        ],
    )
    assert again.exit_code == 0, again.output
    mine = pd.read_csv(tmp_path / "a" / "tables" / "pm10.csv")
    assert np.allclose(mine["PM10_mg_km"], 0.8 * pm10["PM10_mg_km"], rtol=1e-12, atol=0)
    assert "airborne share 0.4 (0.3 to 0.6)" in (tmp_path / "a" / "report.html").read_text()
    factors.write_text("airborne_fraction = 0.9\n")
    bad = CliRunner().invoke(
        app, ["analyze", str(out), "-o", str(tmp_path / "b"), "--emissions", str(factors)]
    )
    assert bad.exit_code == 2
    assert "--emissions" in bad.output and "airborne_fraction" in bad.output
    assert not (tmp_path / "b").exists()  # refused before anything was written


CYCLE_DESIGN = """
name = "cycles"
base = "paper"
root_seed = 3
[[factors]]
name = "C"
field = "cycle"
levels = [1, 2]
choices = ["paper", "example_trace"]
labels = ["paper", "trace"]
[[factors]]
name = "A"
field = "A"
levels = [10.0, 20.0]
unit = "%"
"""


def test_design_factor_selects_the_cycle(tmp_path):
    design = tmp_path / "d.toml"
    design.write_text(CYCLE_DESIGN)
    out = tmp_path / "c"
    factors = tmp_path / "emissions.toml"
    factors.write_text("airborne_fraction = 0.4\n")
    args = ["run", str(design), "-o", str(out), "--stops", "2", "--set", "mesh.n_radial=3"]
    args += ["--set", "mesh.n_angular=100", "--executor", "serial", "--emissions", str(factors)]
    refused = CliRunner().invoke(app, [*args, "--no-report"])
    assert refused.exit_code == 2 and "with --no-report 'brakeca analyze" in refused.output
    assert not out.exists()
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    # the runs table names a categorical factor's levels by their labels
    rows = [line for line in res.output.splitlines() if re.match(r"│\s+\d+ │", line)]
    assert [r.split("│")[2].strip() for r in rows] == ["paper", "trace"] * 2
    summary = pd.read_csv(out / "summary.csv")
    for _, row in summary.iterrows():
        run = RunResult.from_netcdf(out / "runs" / f"{row['run_id']}.nc")
        is_trace = row["C"] == 2
        assert bool(run.config.cycle.trace_file) == is_trace
        assert run.dataset.block.values[0] == ("urban" if is_trace else "Burnish")
    # the report names a categorical factor's levels by their labels too
    report = (out / "report.html").read_text(encoding="utf-8")
    assert "Test 2 (C = trace, A = 10 %)" in report, report[:2000]
    # the captions say each run has its cycle, and each map after how many of its stops
    import html

    report = html.unescape(report)
    assert (
        "MU per stop over the first 2 stops of each run's cycle (the design's factor C " in report
    )
    assert "Test 2 (C = trace, A = 10 %): plateaus after the first 2 of the cycle's " in report
    runs = report[report.index('<section id="runs">') :]
    runs = runs[: runs.index("</section>")]
    assert runs.count("<td>trace</td>") == 2 and runs.count("<td>paper</td>") == 2
    assert "<th>PM10 [mg/km]</th>" in runs
    pm10 = pd.read_csv(out / "tables" / "pm10.csv")
    assert pm10.loc[pm10["C"] == 1, "PM10_mg_km"].isna().all()
    assert (pm10.loc[pm10["C"] == 2, "PM10_mg_km"] > 0).all()
    # the positions only for the trace's runs; run's --emissions reached the report
    assert pm10.loc[pm10["C"] == 1, ["vs_7_mg_km", "vs_3_mg_km"]].isna().all().all()
    assert pm10.loc[pm10["C"] == 2, "vs_7_mg_km"].isin(["below", "straddles", "above"]).all()
    for _, row in pm10[pm10["C"] == 2].iterrows():
        recorded = RunResult.from_netcdf(out / "runs" / f"{row['run_id']}.nc").dataset.attrs
        assert row["PM10_mg_km"] == pytest.approx(0.8 * recorded["pm10_mg_km"], rel=1e-12)
    section = report[report.index('<section id="pm10">') :]
    section = section[: section.index("</section>")]
    assert section.count("<tr><td") == 2 and "airborne share 0.4" in section
    assert "The factors (given with --emissions)" in section
    assert "vs_7_mg_km" not in runs  # in the PM10 section, not the per-run table


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (lambda t: t.replace('choices = ["paper", "example_trace"]\n', ""), "needs choices"),
        (lambda t: t.replace('["paper", "example_trace"]', '["paper"]'), "2 levels but 1 choices"),
        (lambda t: t.replace('"example_trace"]', '"no_such_cycle"]'), "no_such_cycle"),
        (
            lambda t: t.replace('unit = "%"', 'unit = "%"\nchoices = ["a", "b"]'),
            "expected a number",
        ),
    ],
)
def test_bad_cycle_factor_names_the_problem(tmp_path, edit, needle):
    from brakeca.config import ConfigError
    from brakeca.design import load_design

    design = tmp_path / "bad.toml"
    design.write_text(edit(CYCLE_DESIGN))
    with pytest.raises(ConfigError, match=needle) as info:
        load_design(design)
    assert "bad.toml" in str(info.value)


@pytest.mark.parametrize(
    ("args", "folder"),
    [
        ([], "results/paper"),
        (["--quick"], "results/paper_quick"),
        (["--quick", "-o", "elsewhere"], "elsewhere"),
        (["--quick", "--no-report"], "results/paper_quick"),
        (["--no-figures"], "results/paper"),
    ],
)
def test_paper_default_folder_keeps_quick_and_full_apart(monkeypatch, args, folder) -> None:
    import brakeca.cli as cli

    seen = {}

    def record(design, output, **kwargs):
        seen.update(design=design, output=output, quick=kwargs["quick"], report=kwargs["report"])
        seen.update(figures=kwargs["figures"])

    monkeypatch.setattr(cli, "_run_and_report", record)
    res = CliRunner().invoke(app, ["paper", *args])
    assert res.exit_code == 0, res.output
    assert seen["design"] == "paper" and str(seen["output"]) == folder
    assert seen["quick"] == ("--quick" in args)
    assert seen["report"] == ("--no-report" not in args)
    assert seen["figures"] == ("--no-figures" not in args)


def test_a_campaign_whose_runs_all_fail_still_gets_its_report(tmp_path):
    """Every run fails (a foundation too soft to carry the torque): the command exits 1 and
    writes the report, with each run's error and no figures, instead of a traceback."""
    design = tmp_path / "design_in.toml"
    design.write_text(DESIGN)
    out = tmp_path / "c"
    soft = [*TINY, "--set", "contact.elastic_modulus=1"]
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *soft])
    assert res.exit_code == 1, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception
    html = (out / "report.html").read_text()
    assert "0 of 4 runs finished; 4 failed" in html
    assert html.count("would compress the foundation beyond its length") == 4
    assert not list((out / "figures").glob("*.png"))


def _interrupt(*_args, **_kwargs):
    raise KeyboardInterrupt


def test_ctrl_c_says_what_is_kept_and_how_to_go_on(tmp_path, monkeypatch):
    """typer turns Ctrl-C into exit status 130 without a word; the commands say what was kept
    and how to resume."""
    import brakeca._warmup
    import brakeca.campaign
    import brakeca.simulation
    import brakeca.study

    design = tmp_path / "d.toml"
    design.write_text(DESIGN)
    out = tmp_path / "c"
    with monkeypatch.context() as patch:
        patch.setattr(brakeca.campaign, "run_campaign", _interrupt)
        res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *TINY])
    assert res.exit_code == 130
    assert f"interrupted: the finished runs and the checkpoints in {out} are kept" in res.output
    assert "the same command resumes" in res.output

    # during the report: every run is done, analyze writes it
    with monkeypatch.context() as patch:
        patch.setattr(brakeca.study, "write_study", _interrupt)
        res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *TINY])
        assert res.exit_code == 130
        assert f"'brakeca analyze {out}' writes the report" in res.output
        res = CliRunner().invoke(app, ["analyze", str(out), "--no-run-maps"])
        assert res.exit_code == 130 and "the report is not complete" in res.output
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures"])
    assert res.exit_code == 0 and (out / "report.html").is_file()

    # simulate, in the warm-up or in the run: nothing written, and how a rerun could resume
    run_file = tmp_path / "r.nc"
    args = ["simulate", "-o", str(run_file), "--set", "mesh.n_radial=3", "--stops", "1"]
    with monkeypatch.context() as patch:
        patch.setattr(brakeca._warmup, "warm_up", _interrupt)
        res = CliRunner().invoke(app, args)
    assert res.exit_code == 130 and "--checkpoint PATH would let a rerun resume" in res.output
    checkpoint = tmp_path / "k.npz"
    with monkeypatch.context() as patch:
        patch.setattr(brakeca.simulation, "simulate", _interrupt)
        res = CliRunner().invoke(app, [*args, "--checkpoint", str(checkpoint)])
    assert res.exit_code == 130  # before any stop was saved: nothing to resume from
    assert f"no stop had been saved to {checkpoint} yet" in " ".join(res.output.split())
    import json

    import numpy as np

    from brakeca._io import CHECKPOINT_FORMAT

    np.savez(checkpoint, meta=json.dumps({"format": CHECKPOINT_FORMAT}))  # one was saved
    with monkeypatch.context() as patch:
        patch.setattr(brakeca.simulation, "simulate", _interrupt)
        res = CliRunner().invoke(app, [*args, "--checkpoint", str(checkpoint)])
    assert res.exit_code == 130
    assert f"the checkpoint {checkpoint} resumes it" in res.output.replace("\n", "")
    assert not run_file.exists()


def test_other_options_into_a_finished_folder_are_refused_unless_replace(campaign, tmp_path):
    """`brakeca run` with other options (--stops 1 instead of 2) into a finished campaign's
    folder: one line naming the difference and --replace, exit 2, the study untouched."""
    import shutil

    out = tmp_path / "c"
    shutil.copytree(campaign[0], out)
    report = (out / "report.html").read_bytes()
    design = campaign[0].parent / "design_in.toml"
    options = [o if o != "2" else "1" for o in TINY]  # --stops 1
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *options, "--no-report"])
    assert res.exit_code == 2, res.output
    assert "holds a campaign of another base configuration (cycle.max_stops: 2 -> 1)" in (
        " ".join(res.output.split())  # rich wraps the line at the terminal's width
    )
    assert "Traceback" not in res.output and "--replace" in res.output
    assert (out / "report.html").read_bytes() == report
    res = CliRunner().invoke(
        app, ["run", str(design), "-o", str(out), *options, "--no-report", "--replace"]
    )
    assert res.exit_code == 0, res.output
    assert "4 run(s) computed, 0 reused" in res.output


def test_the_design_table_names_coding_centre_and_field() -> None:
    """The report's design table gives each factor's coding where any is log-coded, its
    centre point where the design has them, and the configuration field an alias sets (a
    helper's review: the geometric centre of a log-coded factor showed only per run)."""
    import types

    from brakeca.design import design_from_dict
    from brakeca.study import _design_table

    design = design_from_dict(
        {
            "name": "c",
            "base": "paper",
            "root_seed": 1,
            "center_points": 2,
            "factors": [
                {"name": "WR", "field": "WR", "levels": [1e-7, 1e-6], "coding": "log"},
                {"name": "A", "field": "A", "levels": [10, 20]},
            ],
        }
    )
    table = _design_table(types.SimpleNamespace(design=design)).set_index("factor")
    assert list(table["coding"]) == ["log", "linear"]
    assert table.loc["WR", "centre point"] == "3.162e-07" and table.loc["A", "centre point"] == "15"
    assert list(table["field"]) == ["wear.resin_wear_depth", "pad.fibre_area_fraction"]


def test_a_changed_trace_is_refused_before_any_run(tmp_path):
    """A trace edited after the campaign's configuration was made had failed every run to
    compute, one by one (a helper's review of the docs): it is refused before any run; runs
    already finished are reused as they are."""
    import shutil

    import brakeca.presets

    trace = tmp_path / "trace.csv"
    shutil.copy(Path(brakeca.presets.__file__).parent / "cycles" / "example_trace.csv", trace)
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "one"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "A"\nfield = "A"\n'
        'levels = [10.0, 20.0]\nunit = "%"\n'
    )
    out = tmp_path / "c"
    small = ["--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100", "--stops", "1"]
    args = ["run", str(design), "-o", str(out), "--cycle", str(trace), *small]
    res = CliRunner().invoke(app, [*args, "--executor", "serial", "--no-report"])
    assert res.exit_code == 0, res.output
    trace.write_text(trace.read_text() + "\n", encoding="utf-8")  # edited afterwards
    again = ["run", str(out / "design.toml"), "-o", str(out), "--executor", "serial"]
    res = CliRunner().invoke(app, [*again, "--no-report"])
    assert res.exit_code == 0 and "already done" in res.output  # finished runs: reused
    for run_file in (out / "runs").glob("*.nc"):
        run_file.unlink()
    res = CliRunner().invoke(app, [*again, "--no-report"])
    assert res.exit_code == 2, res.output
    assert "its content changed since the configuration was made" in " ".join(res.output.split())
    assert not list((out / "runs").glob("*.nc"))


def test_the_per_stop_table_of_one_run_is_its_rows_of_the_campaigns(campaign):
    """per_stop_table takes a single run as well (a helper writing the examples had built
    the table by hand): a run file's rows are the campaign table's rows of that run, less
    the design's columns."""
    from brakeca.campaign import load_campaign
    from brakeca.study import per_stop_table

    out, _ = campaign
    result = load_campaign(out)
    whole = per_stop_table(result)
    run_id = result.summary["run_id"][2]
    one = per_stop_table(RunResult.from_netcdf(out / "runs" / f"{run_id}.nc"))
    assert list(one.columns) == list(whole.columns[4:])  # from seed on
    expected = whole[whole["test"] == 3].drop(columns=["test", "replicate", "S", "A"])
    pd.testing.assert_frame_equal(one, expected.reset_index(drop=True))
    with pytest.raises(TypeError, match="takes a CampaignResult or a RunResult, got DataFrame"):
        per_stop_table(result.summary)


def test_analyze_fits_the_terms_chosen(campaign, tmp_path):
    """``--terms`` fits the ANOVA of the terms given (Minitab's Terms dialog), and the
    report says so; a bad term, or --terms with --order, is refused before any work."""
    import shutil

    out = tmp_path / "c"
    shutil.copytree(campaign[0], out)
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-run-maps", "--terms", "A S"])
    assert res.exit_code == 0, res.output
    assert "the report's ANOVA model: the terms S, A (the design's own model: " in res.output
    table = pd.read_csv(out / "tables" / "anova_MU.csv", keep_default_na=False)
    assert list(table["term"]) == ["S", "A", "Residual"]  # design order, no S:A
    assert table["df"].iloc[-1] == 1
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "ANOVA of MU, of the terms chosen: S, A." in html
    # the residual plots are of that model (their caption: the Box-Cox table's cell, which
    # has "ANOVA model: MU ~ S + A" without figures too, ends without the ';')
    assert "model: MU ~ S + A;" in html
    effects = pd.read_csv(out / "tables" / "effects_MU.csv", keep_default_na=False)
    assert sorted(effects["term"]) == ["A", "S"]
    for args, message in (
        (["--terms", "S*B"], "error: --terms: term 'S*B': 'B' is not a factor of the design"),
        (["--terms", "S", "--order", "2"], "error: --terms, --order: give one of them"),
    ):
        res = CliRunner().invoke(app, ["analyze", str(out), *args])
        assert res.exit_code == 2 and message in res.output, res.output


def test_analyze_writes_into_another_folder_and_leaves_the_campaign_as_it_was(campaign, tmp_path):
    """``analyze -o DIR`` writes its tables, figures and report there and only reads the
    campaign: the same analysis as in the campaign folder (what it reads from there too:
    the run files' maps, the configuration, the notes), a model of chosen terms beside it,
    and a DIR that cannot be a folder, is another campaign's or lies inside this one
    refused before any work."""
    import hashlib
    import os
    import shutil

    src = tmp_path / "c"
    shutil.copytree(campaign[0], src)  # (other tests analyse the fixture's folder their way)
    # src holds `brakeca run`'s analysis in place, with every run's maps (the same bytes as
    # `brakeca analyze` in place writes, dates aside)

    def files(folder: Path) -> dict[str, tuple[str, int]]:
        return {
            str(p.relative_to(folder)): (
                hashlib.sha256(p.read_bytes()).hexdigest(),
                p.stat().st_mtime_ns,
            )
            for p in sorted(folder.rglob("*"))
            if p.is_file()
        }

    def undated(report: Path) -> str:
        return re.sub(r"\d{4}-\d\d-\d\dT[\d:+]+", "", report.read_text(encoding="utf-8"))

    before = files(src)
    same = tmp_path / "elsewhere" / "same"
    res = CliRunner().invoke(app, ["analyze", str(src), "-o", str(same)])
    assert res.exit_code == 0, res.output
    assert files(src) == before  # not a file of the campaign written, nor touched
    said = " ".join(res.output.split())
    assert f"report: {same / 'report.html'}" in said and f"tables: {same / 'tables'}" in said
    for part in ("tables", "figures"):
        names = sorted(p.name for p in (src / part).iterdir())
        assert sorted(p.name for p in (same / part).iterdir()) == names
        assert any(n.startswith("final_map_") for n in names) or part == "tables"
        for name in set(names) - {"README.md"}:  # (the README: below)
            assert (same / part / name).read_bytes() == (src / part / name).read_bytes(), name
    # the same report: figures in the same order, the configuration and notes read from the
    # campaign folder; only the tables' README says where the campaign is
    assert undated(same / "report.html") == undated(src / "report.html")
    readme = (same / "tables" / "README.md").read_text(encoding="utf-8")
    assert f"`{src / 'summary.csv'}`: one row per run" in readme
    assert f"brakeca analyze {src} -o {same}" in readme
    assert "`../summary.csv`" in (src / "tables" / "README.md").read_text(encoding="utf-8")
    # -o naming the campaign's own folder (spelled otherwise) is the analysis in place
    relative = os.path.relpath(src)  # (the same folder, a path that is not equal as text)
    res = CliRunner().invoke(app, ["analyze", str(src), "--no-figures", "-o", relative])
    assert res.exit_code == 0, res.output
    assert "`../summary.csv`" in (src / "tables" / "README.md").read_text(encoding="utf-8")
    before = files(src)
    reduced = tmp_path / "reduced"
    res = CliRunner().invoke(
        app, ["analyze", str(src), "--no-figures", "--terms", "A S", "-o", str(reduced)]
    )
    assert res.exit_code == 0, res.output
    assert "without --terms, into a folder of its own)" in " ".join(res.output.split())
    assert list(pd.read_csv(reduced / "tables" / "anova_MU.csv")["term"]) == ["S", "A", "Residual"]
    assert "ANOVA of MU, of the terms chosen: S, A." in (reduced / "report.html").read_text("utf-8")
    blocker = tmp_path / "a_file"
    blocker.write_text("x", encoding="utf-8")
    for dest, message in (
        (blocker, "cannot create it (a file of that name exists"),
        (src / "mine", f"inside the campaign's folder {src}, where a campaign run there again"),
        (campaign[0], "another campaign's folder (it has design.toml, summary.csv, runs)"),
    ):
        kept = files(campaign[0])
        res = CliRunner().invoke(app, ["analyze", str(src), "-o", str(dest)])
        assert res.exit_code == 2, res.output
        assert f"error: -o {dest}: {message}" in " ".join(res.output.split()), res.output
        assert files(src) == before and files(campaign[0]) == kept
    assert not (src / "mine").exists()


def test_a_folder_sent_without_its_run_files_is_analysed(campaign, tmp_path):
    """A helper's review: `brakeca analyze` on a folder of summary.csv, campaign.nc and the
    design (sent without runs/) stopped with a traceback in the fibre-map figure, even with
    --no-run-maps. The tables and report now come from what is there, the run files' maps
    are drawn for the runs that have them, and the report says which runs have none."""
    import shutil

    out, _ = campaign
    sent = tmp_path / "sent"
    sent.mkdir()
    for name in ("summary.csv", "campaign.nc", "design.toml", "base_config.toml"):
        shutil.copy(out / name, sent / name)
    res = CliRunner().invoke(app, ["analyze", str(sent)])
    assert res.exit_code == 0, res.output
    html = (sent / "report.html").read_text(encoding="utf-8")
    assert "none of the 4 finished runs has its run file" in html
    assert not list((sent / "figures").glob("final_map_*.png"))
    assert not (sent / "figures" / "fibre_maps.png").exists()
    for name in ("anova_MU.csv", "per_stop.csv", "box_cox.csv"):
        assert (sent / "tables" / name).is_file()
    anova = pd.read_csv(sent / "tables" / "anova_MU.csv")
    assert {"S", "A", "Residual"} <= set(anova.iloc[:, 0])
    # one run file back: the other three named (the files are read without figures too;
    # that its maps are drawn, and none of the others', is checked below, with figures: one
    # analysis with figures fewer, a review of the suite's time)
    summary = pd.read_csv(out / "summary.csv")
    (sent / "runs").mkdir()
    rid = summary.loc[summary["test"] == 3, "run_id"].item()
    shutil.copy(out / "runs" / f"{rid}.nc", sent / "runs")
    res = CliRunner().invoke(app, ["analyze", str(sent), "--no-figures"])
    assert res.exit_code == 0, res.output
    html = " ".join((sent / "report.html").read_text(encoding="utf-8").split())
    assert "3 of the 4 finished runs have no run file (of tests 1, 2, 4)" in html
    # and on the terminal (a robustness review: the report alone had said so)
    assert "3 of the 4 finished runs have no run file (of tests 1, 2, 4)" in " ".join(
        res.output.split()
    )
    assert not (sent / "figures").exists()  # (no map left over for the check below)
    # damaged run files (cut short, not netCDF) are left out and named, in the report and
    # on the terminal (the analysis stopped with a traceback, half its outputs rewritten);
    # the one file that reads has its maps drawn, the missing and the damaged none
    for test, damage in ((1, "cut"), (2, "junk")):
        rid = summary.loc[summary["test"] == test, "run_id"].item()
        if damage == "cut":
            data = (out / "runs" / f"{rid}.nc").read_bytes()
            (sent / "runs" / f"{rid}.nc").write_bytes(data[: len(data) // 3])
        else:
            (sent / "runs" / f"{rid}.nc").write_text("junk", encoding="utf-8")
    res = CliRunner().invoke(app, ["analyze", str(sent)])
    assert res.exit_code == 0, res.output
    said = " ".join(res.output.split())
    assert "note: In " in said and "the run files of tests 1, 2 cannot be read (" in said
    assert "computes those runs again" in said
    html = " ".join((sent / "report.html").read_text(encoding="utf-8").split())
    assert "the run files of tests 1, 2 cannot be read (" in html
    assert "not a readable netCDF file" in html
    assert "1 of the 4 finished runs has no run file (of test 4)" in html
    assert [p.name for p in (sent / "figures").glob("final_map_*.png")] == [
        "final_map_test03_r0.png"
    ]


def test_stops_beyond_the_cycle_get_a_note(tmp_path, monkeypatch):
    """A black-box review: `brakeca run --stops 500` ran the 170 stops without a word
    (`brakeca simulate` had a note)."""
    import brakeca.campaign
    from brakeca.config import ConfigError

    def stop_here(*args, **kwargs):
        raise ConfigError("stopped before any run")

    monkeypatch.setattr(brakeca.campaign, "run_campaign", stop_here)
    for stops, noted in (("500", True), ("170", False)):
        res = CliRunner().invoke(
            app, ["run", "paper", "-o", str(tmp_path / "c"), "--quick", "--stops", stops]
        )
        assert res.exit_code == 2 and "stopped before any run" in res.output
        text = " ".join(res.output.split())
        assert (
            "note: --stops 500: the cycle has 170 stops, so every run goes its whole cycle" in text
        ) is noted
    # a design whose factor chooses the cycle: the longest of its runs' cycles
    design = tmp_path / "cycles.toml"
    design.write_text(CYCLE_DESIGN)
    for stops, noted in (("500", True), ("100", False)):
        res = CliRunner().invoke(
            app, ["run", str(design), "-o", str(tmp_path / "c"), "--quick", "--stops", stops]
        )
        assert res.exit_code == 2, res.output
        text = " ".join(res.output.split())
        assert ("the longest cycle of the runs has 170 stops" in text) is noted


def test_a_factor_on_the_stops_gives_each_run_its_own(tmp_path):
    """A factor on cycle.max_stops: each run goes its own stops, which the captions say
    (a review saw the base configuration's stops in them); --stops beside it is refused,
    and --maps-at is checked against the shortest of the runs' cycles."""
    import html

    design = tmp_path / "d.toml"
    design.write_text(
        'name = "ms"\nbase = "paper"\nroot_seed = 1\n'
        '[[factors]]\nname = "N"\nfield = "cycle.max_stops"\nlevels = [1, 2]\n'
    )
    tiny = ["--set", "mesh.n_radial=5", "--set", "mesh.n_angular=100", "--executor", "serial"]
    out = tmp_path / "c"
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *tiny, "--stops", "2"])
    assert res.exit_code == 2 and "the design's factor 'N' sets cycle.max_stops" in res.output
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *tiny, "--maps-at", "2"])
    assert res.exit_code == 2
    assert (
        "stop 2 is not a stop of this cycle (whole numbers from 1 to 1) (the shortest of the "
        in (" ".join(res.output.split()))
    )
    assert not out.exists()
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), *tiny])
    assert res.exit_code == 0, res.output
    report = html.unescape((out / "report.html").read_text(encoding="utf-8"))
    assert "MU per stop over each run's cycle (the design's factor N sets it)" in report
    assert "Test 1 (N = 1): plateaus after the first 1 of the cycle's 170 stops" in report
    assert "Test 2 (N = 2): plateaus after the first 2 of the cycle's 170 stops" in report


def test_run_warns_of_a_noisy_trace_a_cycle_factor_chooses(tmp_path, monkeypatch):
    """A review: `brakeca run` warned of speed noise only for the trace of --cycle or of the
    design's base, not for one a design's cycle factor chooses. Each trace of the runs is
    looked at now, and each warning said once."""
    import brakeca.campaign
    from brakeca.config import ConfigError

    def stop_here(*args, **kwargs):
        raise ConfigError("stopped before any run")

    monkeypatch.setattr(brakeca.campaign, "run_campaign", stop_here)
    t = np.arange(0.0, 130.0, 0.1)
    clean = np.interp(t, [0, 20, 60, 70, 100, 130], [0, 60, 60, 0, 80, 20])
    noisy = np.maximum(clean + np.random.default_rng(0).normal(0.0, 0.5, t.size), 0.0)
    trace = tmp_path / "noisy.csv"
    trace.write_text(
        "time_s,speed_kmh\n" + "".join(f"{a:.1f},{b:.3f}\n" for a, b in zip(t, noisy, strict=True))
    )
    design = tmp_path / "d.toml"
    design.write_text(CYCLE_DESIGN.replace('"example_trace"', repr(str(trace)).replace("'", '"')))
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(tmp_path / "c"), "--quick"])
    assert res.exit_code == 2 and "stopped before any run" in res.output
    text = " ".join(res.output.split())
    assert text.count("braking events decelerate on average at less than half") == 1


def test_a_run_without_emission_is_named_where_the_log_scale_leaves_it_out(campaign, tmp_path):
    """A run with V = 0 has no log10_V_mm3 and left the log scale's analysis without a word
    (an API review): the report names it."""
    import shutil

    from brakeca.campaign import load_campaign
    from brakeca.study import write_study

    out, _ = campaign
    copy = tmp_path / "c"
    shutil.copytree(out, copy)
    (copy / ".brakeca.lock").unlink(missing_ok=True)
    result = load_campaign(copy)
    result.summary.loc[result.summary["test"] == 2, "V"] = 0.0
    write_study(result, run_maps=False)  # (the only figures drawn with a V of 0)
    html = " ".join((copy / "report.html").read_text(encoding="utf-8").split())
    assert "Test 2 emitted nothing (V = 0): log10_V_mm3 has no value there, so its" in html
    assert "leaves that run out (the analysis of V keeps it)" in html


def test_levels_given_high_first_are_noted_by_run_and_in_the_report(tmp_path):
    """`brakeca design` had the note alone: `brakeca run` and the report now say it too, as
    the effects' signs and the derived coefficient follow the order given."""
    from html import unescape

    design = tmp_path / "high_first.toml"
    design.write_text(DESIGN.replace("levels = [10.0, 20.0]", "levels = [20.0, 10.0]"))
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(tmp_path / "c"), *TINY])
    assert res.exit_code == 0, res.output
    said = "factor A's levels are not given low first (20, 10)"
    assert " ".join(res.output.split()).count(said) == 1
    html = unescape((tmp_path / "c" / "report.html").read_text(encoding="utf-8"))
    assert f"{said[0].upper()}{said[1:]}: tables and plots take them in this order" in html
    assert "(Minitab and JMP take the levels in value order)" in " ".join(html.split())
    shown = CliRunner().invoke(app, ["design", str(design), "--no-tests"])
    assert " ".join(shown.output.split()).count(said) == 1


def test_the_residual_plots_say_a_standard_order_is_not_time(campaign):
    """A design not randomized runs in standard order, so the residuals' order panel sorts
    the runs by their levels (a helper's review: runs 13-24 of the paper's study are exactly
    its A = 20 % runs); the caption says so."""
    from html import unescape

    out, _ = campaign
    html = " ".join(unescape((out / "report.html").read_text(encoding="utf-8")).split())
    assert "randomize_order is off), so the order panel sorts them by their levels" in html


def test_a_design_file_of_the_user_s_in_the_folder_is_not_written_over(tmp_path):
    """A user's own design.toml kept in the campaign folder had been replaced by the
    campaign's (its comments lost: a helper's review); it is refused before anything is
    written, and a campaign's own design.toml still resumes."""
    folder = tmp_path / "mine"
    folder.mkdir()
    text = "# my notes on this design\n" + DESIGN
    (folder / "design.toml").write_text(text)
    for design in (folder / "design.toml", folder):
        res = CliRunner().invoke(app, ["run", str(design), "-o", str(folder), *TINY])
        assert res.exit_code == 2, res.output
        said = " ".join(res.output.split())
        assert "design.toml: a design file brakeca did not write" in said
        assert (folder / "design.toml").read_text() == text
        assert sorted(p.name for p in folder.iterdir()) == ["design.toml"]
    # (--no-report: the report is not this test's; the runs and the folders are)
    res = CliRunner().invoke(
        app, ["run", str(folder), "-o", str(tmp_path / "c"), *TINY, "--no-report"]
    )
    assert res.exit_code == 0, res.output  # the user's design, run into another folder
    # the campaign's own folder: its design.toml (brakeca's) is taken to resume
    again = CliRunner().invoke(
        app, ["run", str(tmp_path / "c"), "-o", str(tmp_path / "c"), *TINY, "--no-report"]
    )
    assert again.exit_code == 0, again.output


def test_a_trace_at_another_path_is_named_as_the_same_content(tmp_path):
    """The same trace copied elsewhere: the refusal says that its content is the same and
    where the runs' trace was (a determinism review: a run records its trace by path)."""
    import shutil

    from brakeca.presets import __file__ as presets_init

    shipped = Path(presets_init).parent / "cycles" / "example_trace.csv"
    first, second = tmp_path / "a" / "tr.csv", tmp_path / "b" / "tr.csv"
    for path in (first, second):
        path.parent.mkdir()
        shutil.copy(shipped, path)
    design = tmp_path / "d.toml"
    design.write_text('name = "m"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "A"\n')
    design.write_text(design.read_text() + "levels = [10, 20]\n")
    out = tmp_path / "c"
    tiny = ["--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100", "--stops", "1"]
    args = ["run", str(design), "-o", str(out), *tiny, "--no-report", "--executor", "serial"]
    assert CliRunner().invoke(app, [*args, "--cycle", str(first)]).exit_code == 0
    moved = CliRunner().invoke(app, [*args, "--cycle", str(second)])
    assert moved.exit_code == 2
    text = " ".join(moved.output.split())
    assert "Its trace has the same content (SHA-256) at another path" in text
    assert f"give the trace at its first path ({first}) to resume them" in text
    # the trace edited in place: said so, not "the first campaign's command, run again,
    # brings its study back", which is the command refused (a review)
    lines = first.read_text(encoding="utf-8").splitlines(keepends=True)
    row = lines[-1].split(",")
    row[1] = str(float(row[1]) + 0.5)
    first.write_text("".join(lines[:-1]) + ",".join(row) + ("" if row[-1].endswith("\n") else "\n"))
    edited = CliRunner().invoke(app, [*args, "--cycle", str(first)])
    assert edited.exit_code == 2
    text = " ".join(edited.output.split())
    assert (
        f"Its trace {first} has other content (SHA-256) than when the campaign ran, so these "
        "would be other runs"
    ) in text
    assert (
        "the first campaign's command, with its trace as it was, run again with --replace, "
        "brings" in text
    )


def test_an_analysis_writes_nowhere_a_link_in_the_folder_points(campaign, tmp_path):
    """A security review: a folder someone sent, whose figures/ is a link to another
    place, had its analysis write and remove files there; refused, before any work."""
    import shutil

    from brakeca.campaign import load_campaign
    from brakeca.study import write_study

    out = tmp_path / "c"
    shutil.copytree(campaign[0], out)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "pareto_MU.png").write_bytes(b"precious")
    shutil.rmtree(out / "figures")
    (out / "figures").symlink_to(elsewhere)
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures"])
    assert res.exit_code == 2
    said = " ".join(res.output.split())
    assert f"its figures is a link (to {elsewhere}), where the analysis would write" in said
    with pytest.raises(ValueError, match="its figures is a link"):
        write_study(load_campaign(out), figures=False)
    assert (elsewhere / "pareto_MU.png").read_bytes() == b"precious"
    assert [p.name for p in elsewhere.iterdir()] == ["pareto_MU.png"]


def test_a_run_id_that_is_a_path_is_refused(campaign, tmp_path):
    """A security review: a summary's and campaign.nc's run_id made into a path had the
    analysis read a run file elsewhere and draw it as the test's; a run id is 16
    hexadecimal digits, and a file of more than a brakeca file holds is not read."""
    import shutil

    import xarray as xr

    from brakeca.results import load_netcdf

    out = tmp_path / "c"
    shutil.copytree(campaign[0], out)
    elsewhere = "../../elsewhere/run"
    summary = pd.read_csv(out / "summary.csv", dtype={"run_id": str})
    summary.loc[0, "run_id"] = elsewhere
    summary.to_csv(out / "summary.csv", index=False)
    ds = load_netcdf(out / "campaign.nc")
    ids = ds["run_id"].values.astype(object)
    ids[0] = elsewhere
    ds.assign_coords(run_id=("run", ids)).to_netcdf(out / "campaign.nc", engine="h5netcdf")
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures"])
    assert res.exit_code == 2
    assert "a run_id is '../../elsewhere/run', not a run's id" in " ".join(res.output.split())
    with pytest.raises(ValueError, match=r"its variables hold 0\.0 GiB, more than"):
        load_netcdf(campaign[0] / "campaign.nc", limit=1000)
    assert isinstance(load_netcdf(campaign[0] / "campaign.nc"), xr.Dataset)
