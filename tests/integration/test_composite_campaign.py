"""A central composite design run end to end through `brakeca run`: its tests are the cube,
axial and centre points, each centre point with its own seed; the folder's design.toml alone
resumes it; the report and tables carry the fitted response surface."""

from __future__ import annotations

import tomllib

import numpy as np
import pandas as pd
import pytest
from campaign_helpers import TINY_CLI, cli_ok
from typer.testing import CliRunner

from brakeca.cli import app
from brakeca.design import load_design
from brakeca.rsm import fit_response_surface

CCD = """
name = "ccd"
base = "paper"
root_seed = 11

[composite]
alpha = "face"
center = 2

[[factors]]
name = "A"
levels = [10.0, 20.0]

[[factors]]
name = "WR"
levels = [1e-7, 1e-6]
coding = "log"

[[goals]]
response = "V"
goal = "minimize"
lower = 0.0
upper = 50.0
"""


def test_a_face_centred_composite_runs_resumes_and_reports_its_surface(tmp_path) -> None:
    design = tmp_path / "ccd.toml"
    design.write_text(CCD)
    out = tmp_path / "c"
    # (without figures: the report the resume below writes draws them, and is the one read;
    # a review of the suite's time)
    first = cli_ok("run", str(design), "-o", str(out), *TINY_CLI, "--no-figures")
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary["test"]) == list(range(1, 11))
    # "In short" on the terminal is the quadratic's (a review: a composite's report had
    # given the COF-floor line alone, under the factorial ANOVA's heading)
    assert "in short (the terms with p < 0.05 of each response's quadratic surface" in first
    assert "\n  MU (quadratic surface): " in first and "the ANOVA's terms" not in first
    assert "nan (p" not in first  # (every term named "nan" where none had p < 0.05)
    assert "\n  The design's goals are best met at A = " in first
    assert (summary["status"] == "ok").all()
    # cube (A fastest), axial (A -, A +, WR -, WR +), then the centre twice
    wr0 = 10**-6.5
    expected = [(10, 1e-7), (20, 1e-7), (10, 1e-6), (20, 1e-6)]
    expected += [(10, wr0), (20, wr0), (15, 1e-7), (15, 1e-6), (15, wr0), (15, wr0)]
    np.testing.assert_allclose(summary[["A", "WR"]].to_numpy(), expected, rtol=1e-12)
    assert summary["seed"].nunique() == 10 and summary["run_id"].nunique() == 10
    # the folder's design.toml keeps the composite and its tests, and alone resumes them
    saved = tomllib.loads((out / "design.toml").read_text(encoding="utf-8"))
    assert saved["composite"] == {"alpha": "face", "center": 2}
    assert load_design(out / "design.toml").n_tests == 10
    output = cli_ok("run", str(out / "design.toml"), "-o", str(out), "--executor", "serial")
    assert "0 run(s) computed, 10 reused" in output
    # the response surface: tables, figure and report section, from the summary's runs
    coefficients = pd.read_csv(out / "tables" / "surface_coefficients_MU.csv")
    assert list(coefficients["term"]) == ["Constant", "A", "WR", "A*A", "WR*WR", "A*WR"]
    fit = fit_response_surface(summary, load_design(out / "design.toml").factors, "MU")
    np.testing.assert_allclose(coefficients["coef"], fit.coefficients["coef"], rtol=1e-9)
    anova = pd.read_csv(out / "tables" / "surface_anova_MU.csv")
    assert {"Lack-of-Fit", "Pure Error"} <= set(anova["source"])  # the two centre points
    assert (out / "figures" / "surface_MU.png").is_file()
    assert (out / "tables" / "surface_summary_log10_V_mm3.csv").is_file()
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Central composite design (face-centred, α = 1), 2 factors" in html
    assert '<section id="surface">' in html and "Coded -1 to +1: A 10 to 20 %, WR log10" in html
    assert html.count("<h2>Response surface</h2>") == 1  # the figures: "Contour plots"
    assert "<h2>Contour plots</h2>" in html
    # the Box-Cox check of a response surface's responses uses the fitted quadratic
    scales = pd.read_csv(out / "tables" / "box_cox.csv").set_index("response")
    assert scales.loc["MU", "model"] == "quadratic model: A + WR + A*A + WR*WR + A*WR"
    assert (out / "figures" / "box_cox.png").is_file() and "Scale of the responses" in html
    # a response surface's ANOVA and residuals are its quadratic's, not the categorical ones
    anova_section = html[html.index('<section id="anova">') :]
    anova_section = anova_section[: anova_section.index("</section>")]
    assert "A response-surface design: each response&#39;s analysis of variance" in anova_section
    assert '<h3 id="anova-MU">' not in anova_section
    assert "Residual plots of the quadratic surface of mean COF MU; model: MU ~ A + WR" in html
    assert not (out / "figures" / "pareto_MU.png").exists()
    # main effects from the fitted surface (a profile), not the unbalanced level means, and
    # no categorical interaction plot (the contour plots cover the pairs)
    for resp in ("MU", "V", "log10_V_mm3"):
        assert (out / "figures" / f"profile_{resp}.png").is_file()
        assert not (out / "figures" / f"main_effects_{resp}.png").exists()
        assert not (out / "figures" / f"interactions_{resp}.png").exists()
    assert "from the fitted quadratic surface" in html
    residuals = pd.read_csv(out / "tables" / "surface_residuals_MU.csv")
    np.testing.assert_allclose(residuals["observed"], summary["MU"], rtol=1e-12)
    np.testing.assert_allclose(
        residuals["fitted"], fit.predict({"A": summary["A"], "WR": summary["WR"]}), rtol=1e-9
    )
    # the design's goal: the optimum in the report and tables/optimum.csv, V in mm³
    optimum = pd.read_csv(out / "tables" / "optimum.csv")
    v_row = optimum[optimum["name"] == "V"].iloc[0]
    assert v_row["goal"] == "minimize" and v_row["upper"] == pytest.approx(50e-9, rel=1e-15)
    # Minitab's columns: a minimize goal has a target (where it is fully met) and an upper
    # limit, no lower (its target had been in lower: a user's review)
    assert v_row["target"] == 0.0 and np.isnan(v_row["lower"])
    assert (out / "figures" / "overlaid_contours.png").is_file()
    assert '<h3 id="surface-optimum">Response optimization</h3>' in html
    assert "minimize: target 0, upper 50" in html
    assert "The goals&#39; limits on V are in absolute volume per stop" in html  # 2 stops
    # without --goal, brakeca optimize takes the design's goals
    assert "minimize: target 0, upper 50" in cli_ok("optimize", str(out))
    # the response optimizer on the same folder: V given in mm³, the setting inside the box
    res = CliRunner().invoke(
        app,
        ["optimize", str(out), "-g", "V:min:0:50", "-g", "MU:target:0.1:0.3:0.6"],
        env={"COLUMNS": "160"},
    )
    assert res.exit_code == 0, res.output
    assert "composite desirability: " in res.output and "V [mm³]" in res.output
    assert (
        "target: lower 0.1, target 0.3, upper 0.6" in res.output
        and "minimize: target 0, upper 50" in res.output
    )
    # a goal met everywhere: no 'the best setting may lie beyond' (nothing can beat 1)
    met = " ".join(cli_ok("optimize", str(out), "-g", "MU:min:5:6").split())
    assert "composite desirability: 1.000" in met and "at the edge of the region" not in met
    reduced = cli_ok("optimize", str(out), "--reduce", "0.5")
    assert "composite desirability: " in reduced
    # 'none': the full quadratic, as the design (without alpha_to_remove) gives by default
    assert cli_ok("optimize", str(out), "--reduce", "none") == cli_ok("optimize", str(out))
    bad = CliRunner().invoke(app, ["optimize", str(out), "--reduce", "1"])
    assert bad.exit_code == 2 and "--reduce: expected a level above 0 and below 1" in bad.output
    # a surface that predicts left-out runs worse than their mean is said to (a DoE review:
    # a desirability of 1.000 on R²(pred) -85 %, said by the report only)
    mu_text = " ".join(cli_ok("optimize", str(out), "-g", "MU:max:0.1:0.5").split())
    worse = fit.statistics["r_squared_pred"] < 0
    assert ("MU's surface predicts a run it left out worse than the mean" in mu_text) is worse
    bad = CliRunner().invoke(app, ["optimize", str(out), "-g", "MU:target:0.3:0.2"])
    assert bad.exit_code == 2 and "target takes 3 numbers" in bad.output
    # a response surface's report fits a quadratic: no factorial model order for it
    bad = CliRunner().invoke(app, ["analyze", str(out), "--order", "1"])
    assert bad.exit_code != 0 and "--order: a response-surface design's report" in bad.output
