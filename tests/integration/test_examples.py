"""The examples run (on a tiny band, as their --tiny option) and give what they print."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

EXAMPLES = Path(__file__).parents[2] / "examples"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def test_the_response_surface_example_runs(tmp_path, capsys, monkeypatch) -> None:
    # its own default folder, apart from the quick variant's (whose runs are of another
    # band: one folder for both refused the second as another study)
    monkeypatch.chdir(tmp_path)
    out = _load("response_surface").main(["--tiny"])
    assert out["figures"] == Path("examples_out/response_surface_tiny/example_figures")
    assert set(out["fits"]) == {"MU", "log10_V_mm3"}
    assert 0.0 <= out["optimum"].composite <= 1.0
    for name in ("surface_MU.png", "surface_log10_V_mm3.png", "overlaid_contours.png"):
        assert (out["figures"] / name).is_file()
    printed = capsys.readouterr().out
    assert printed.startswith("central composite design (face-centred, α = 1), 3 factors")
    assert "composite desirability:" in printed


def test_the_single_run_example_runs(tmp_path, capsys, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    out = _load("single_run").main(["--tiny"])
    run, other, back = out["run"], out["other"], out["read_back"]
    folder = Path("examples_out/single_run_tiny")
    # the levels set, one seed for both materials, and the run file read back as it was run
    assert run.config.wear.specific_wear_rate == 1e-13
    assert run.config.pad.fibre_area_fraction == pytest.approx(0.10)
    assert other.config.pad.fibre_area_fraction == pytest.approx(0.20)
    assert run.seed == other.seed == back.seed == 3
    assert out["run_file"] == folder / "run_WP1e-13_A10.nc"
    assert back.config == run.config and (back.MU, back.V) == (run.MU, run.V)
    np.testing.assert_array_equal(back.dataset["mean_cof"], run.dataset["mean_cof"])
    for r in (run, other):  # each step's COF is a mean of mu(p) in [mu_min, mu_0] = [0.15, 0.6]
        assert 0.15 <= r.MU <= 0.6
        assert math.isfinite(r.V) and 0.0 < r.V < 1e-6  # m³ per stop
    assert other.MU != run.MU  # A changes the material
    assert out["difference"]["MU"] == pytest.approx(other.MU - run.MU)
    assert out["difference"]["V_ratio"] == pytest.approx(other.V / run.V)
    # the per-stop table: three stops, whose means are MU and V (in mm³)
    table = out["per_stop"]
    assert list(table["stop"]) == [1, 2, 3]
    assert table["mean_cof"].mean() == pytest.approx(run.MU)
    assert table["emitted_mm3"].mean() == pytest.approx(run.V * 1e9)
    assert ((table["duration_s"] > 0) & (table["normal_force_N"] > 0)).all()
    assert len(pd.read_csv(folder / "per_stop.csv")) == 3
    assert [p.name for p in out["figures"]] == [
        "mu_per_stop.png",
        "steps.png",
        "final_map.png",
        "compare_mu_per_stop.png",
        "compare_final_maps.png",
    ]
    for path in out["figures"]:
        assert path.parent == folder / "figures" and path.stat().st_size > 10_000
    printed = capsys.readouterr().out
    assert printed.startswith(
        "one pad material: paper preset, WP = 1e-13 m³/(N·m), A = 10 %, seed 3, 5 x 100 cells\n"
    )
    assert f"MU = {run.MU:.4f} (mean COF over 3 stops)" in printed
    assert f"V  = {run.V * 1e9:.4g} mm³ per stop" in printed
    assert "(read back: seed, config and MU the same: True)" in printed
    assert f"A 10 % -> 20 % (seed 3 both): MU {other.MU - run.MU:+.4f}" in printed


def test_the_custom_design_example_runs(tmp_path, capsys, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    out = _load("custom_design").main(["--tiny"])
    folder = Path("examples_out/custom_design_tiny")
    design = out["design"]
    assert [(f.name, f.field) for f in design.factors] == [
        ("WP", "WP"),
        ("mu0", "friction.mu_0"),
        ("A", "A"),
    ]
    assert (design.kind, design.n_tests, design.replicates) == ("full factorial", 8, 2)
    # a fresh folder: every run computed; the second call reuses them all
    result, again = out["result"], out["again"]
    assert len(result.computed) == 16 and not result.reused and not result.failed
    assert len(again.reused) == 16 and not again.computed and not again.failed
    assert sorted(again.reused) == sorted(result.computed)
    # read back from the folder: the runs of the first call, every one finished
    summary = out["loaded"].summary
    assert (folder / "campaign" / "summary.csv").is_file()
    assert (folder / "campaign" / "campaign.nc").is_file()
    assert list(summary["run_id"]) == list(result.summary["run_id"])
    np.testing.assert_array_equal(summary["MU"], result.summary["MU"])
    assert (summary["status"] == "ok").all() and summary["seed"].nunique() == 16
    assert sorted(set(summary["mu0"])) == [0.5, 0.7]
    # each run's COF lies between the floor mu_min = 0.15 and its own mu_0
    assert ((summary["MU"] >= 0.15) & (summary["MU"] <= summary["mu0"])).all()
    assert np.isfinite(summary["V"]).all() and (summary["V"] > 0).all()
    # the analysis: level means of 8 runs each, the ANOVA with 9 residual df, 2 x 2 cells
    effects = out["main_effects"]
    assert len(effects) == 6
    mu0 = effects[effects["factor"] == "mu0"]
    by_level = summary.groupby("mu0")["MU"].mean()  # the level means, not only their mean
    np.testing.assert_allclose(mu0["MU"], by_level.loc[mu0["level"]].to_numpy(), rtol=1e-12)
    for response, table in out["anova"].items():
        assert list(table["term"]) == ["WP", "mu0", "A", "WP:mu0", "WP:A", "mu0:A", "Residual"]
        assert table["df"].tolist() == [1, 1, 1, 1, 1, 1, 9], response
        p = table["p_value"].dropna()
        assert len(p) == 6 and ((p >= 0) & (p <= 1)).all(), response
        assert table["percent_contribution"].sum() == pytest.approx(100.0, rel=1e-9)
    assert out["interaction"].shape == (2, 2)
    assert np.isfinite(out["interaction"].to_numpy()).all()
    for path in out["figures"]:
        assert path.parent == folder / "figures" and path.stat().st_size > 10_000
    printed = capsys.readouterr().out
    assert printed.startswith("wear_vs_friction: full factorial, 8 tests x 2 seeds = 16 runs\n")
    assert "16 runs computed, 0 reused, 0 failed" in printed
    assert "run again into the same folder: 0 computed, 16 of 16 reused" in printed
    assert "ANOVA of MU (Type II" in printed and "ANOVA of log10_V_mm3 (Type II" in printed
