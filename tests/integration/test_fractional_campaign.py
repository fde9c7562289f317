"""A fractional factorial and a run table run end to end through `brakeca run`: the runs
are the design's, the folder's design.toml alone resumes them, and the report shows the
design's kind, its aliases and the two-level effects."""

from __future__ import annotations

import tomllib

import numpy as np
import pandas as pd
from campaign_helpers import TINY_CLI, cli_ok

from brakeca.design import load_design

FACTORS = """
[[factors]]
name = "S"
levels = [0.0, 1.0]
[[factors]]
name = "A"
levels = [10.0, 20.0]
[[factors]]
name = "WR"
levels = [1e-7, 1e-6]
"""

FRACTION = 'name = "half"\nbase = "paper"\nroot_seed = 5\ngenerators = ["WR = -S*A"]\n' + FACTORS

TINY = TINY_CLI


def test_a_half_fraction_runs_resumes_and_reports_its_aliases(tmp_path) -> None:
    design = tmp_path / "half.toml"
    design.write_text(FRACTION)
    out = tmp_path / "c"
    cli_ok("run", str(design), "-o", str(out), *TINY, "--no-report")
    summary = pd.read_csv(out / "summary.csv")
    # the 2^(3-1) with WR = -S*A: coded WR is minus the product of S's and A's
    assert list(summary["test"]) == [1, 2, 3, 4]
    coded = {c: summary[c].rank(method="dense").to_numpy() * 2 - 3 for c in ("S", "A", "WR")}
    assert (coded["WR"] == -coded["S"] * coded["A"]).all()
    assert (summary["status"] == "ok").all()
    # the folder's design.toml keeps the generators and alone resumes every run
    saved = tomllib.loads((out / "design.toml").read_text(encoding="utf-8"))
    assert saved["generators"] == ["WR = -S*A"]
    assert load_design(out / "design.toml").n_tests == 4
    output = cli_ok("run", str(out / "design.toml"), "-o", str(out), "--executor", "serial")
    assert "0 run(s) computed, 4 reused" in output
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "2^(3-1) fractional factorial, resolution III: 4 tests." in html
    assert "defining relation I = -S·A·WR" in html
    assert "<td>= -S·A</td>" in html  # the design table's generated column
    assert "A:WR (aliased with S)" in html  # left out of the ANOVA, with its alias
    effects = pd.read_csv(out / "tables" / "effects_MU.csv", keep_default_na=False)
    assert sorted(effects["term"]) == ["A", "S", "WR"]
    # WR = -S*A: S's column is minus A:WR's, so S's estimate is S - A:WR
    assert dict(zip(effects["term"], effects["aliases"], strict=True))["S"] == "-A:WR"
    assert (out / "figures" / "effects_MU.png").is_file()
    # its fold-over on S into the same folder: the first half's runs are reused
    folded = tmp_path / "folded.toml"
    folded.write_text(FRACTION.replace("root_seed = 5\n", 'root_seed = 5\nfoldover = ["S"]\n'))
    output = cli_ok("run", str(folded), "-o", str(out), *TINY, "--no-figures")
    assert "4 run(s) computed, 4 reused" in output
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary["test"]) == list(range(1, 9))
    assert "folded over on S, a full factorial of its two-level factors" in (
        out / "report.html"
    ).read_text(encoding="utf-8")
    # optimize without centre points: nothing estimates a curvature, and the note says so
    # (it had spoken of the centre points' pooled curvature: a user's review)
    planar = " ".join(cli_ok("optimize", str(out), "-g", "MU:max:0.1:0.5").split())
    assert "without centre points nothing estimates a curvature), so the surface is" in planar
    assert "pooled curvature" not in planar
    # three centre points added to the finished campaign: only they are computed
    centred = tmp_path / "centred.toml"
    centred.write_text(
        folded.read_text().replace("root_seed = 5\n", "root_seed = 5\ncenter_points = 3\n")
    )
    output = cli_ok("run", str(centred), "-o", str(out), *TINY)
    assert "3 run(s) computed, 8 reused" in output
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary["test"]) == list(range(1, 12))
    centre = summary.iloc[8:]
    assert (centre["S"] == 0.5).all() and (centre["A"] == 15.0).all()
    assert np.allclose(centre["WR"], 5.5e-7, rtol=1e-12, atol=0)
    assert centre["seed"].nunique() == 3
    anova = pd.read_csv(out / "tables" / "anova_MU.csv")
    assert "Curvature" in list(anova["term"])
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "plus 3 centre points: 11 tests." in html
    assert "Curvature: the 3 centre points&#39; mean" in html
    # optimize on it: it says the design is no response-surface design (the centre points'
    # curvature rests on one square term), and its fit's notes, the aliased terms on one
    # line (a black-box review: the optimum moved with the factors' order, without a word)
    text = " ".join(cli_ok("optimize", str(out), "-g", "MU:max:0.1:0.5").split())
    assert "not a response-surface design: its runs do not give every factor a square" in text
    assert "design estimates each factor's square term on its own." in text  # (was cut short)
    assert "rests on that pooled curvature" in text
    assert text.count("note: left out of the quadratic, since the runs cannot estimate") == 1
    assert "A*A" in text and "WR*WR" in text


def test_a_run_table_from_csv_runs_in_its_order(tmp_path) -> None:
    (tmp_path / "runs.csv").write_text("# three points\nWR;A;S\n1e-6;20;1\n1e-7;10;0\n1e-6;20;1\n")
    design = tmp_path / "table.toml"
    design.write_text(
        'name = "table"\nbase = "paper"\nroot_seed = 5\nruns_file = "runs.csv"\n' + FACTORS
    )
    out = tmp_path / "c"
    cli_ok("run", str(design), "-o", str(out), *TINY, "--no-report")
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary["S"]) == [1.0, 0.0, 1.0] and list(summary["A"]) == [20.0, 10.0, 20.0]
    assert summary["seed"].nunique() == 3  # a repeated point is a test of its own
    saved = tomllib.loads((out / "design.toml").read_text(encoding="utf-8"))
    assert "runs_file" not in saved and len(saved["runs"]) == 3  # inlined: no CSV needed
    (tmp_path / "runs.csv").unlink()
    output = cli_ok("run", str(out / "design.toml"), "-o", str(out), "--executor", "serial")
    assert "0 run(s) computed, 3 reused" in output
    assert "Run table: 3 tests." in (out / "report.html").read_text(encoding="utf-8")


def test_a_plackett_burman_design_runs_and_fits_its_main_effects_alone(
    tmp_path,
) -> None:
    design = tmp_path / "pb.toml"
    design.write_text(
        'name = "pb"\nbase = "paper"\nroot_seed = 9\nplackett_burman = 12\n' + FACTORS
    )
    out = tmp_path / "c"
    cli_ok("run", str(design), "-o", str(out), *TINY)  # (the only figures of main effects alone)
    summary = pd.read_csv(out / "summary.csv")
    assert list(summary["test"]) == list(range(1, 13)) and (summary["status"] == "ok").all()
    # balanced: every factor at each of its levels in 6 tests
    assert all(summary[f].value_counts().tolist() == [6, 6] for f in ("S", "A", "WR"))
    effects = pd.read_csv(out / "tables" / "effects_MU.csv", keep_default_na=False)
    terms = set(effects["term"])
    assert {"A", "S", "WR"} <= terms  # the two-factor interactions, partly confounded: out
    assert not {"S:A", "S:WR", "A:WR"} & terms
    anova_terms = set(pd.read_csv(out / "tables" / "anova_MU.csv")["term"])
    assert not any(":" in str(t) for t in anova_terms)  # main effects alone, as Minitab
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Plackett-Burman design, 12 tests, 3 factors" in html
