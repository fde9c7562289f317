"""The top-level names of ``import brakeca``: imported on first use, the same objects as the
submodules'."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

import brakeca


def test_import_brakeca_stays_cheap():
    code = "import sys, brakeca; print(sorted({'numba', 'xarray', 'pandas'} & set(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


@pytest.mark.parametrize("name", sorted(brakeca._EXPORTS))
def test_each_top_level_name_is_the_submodules_object(name):
    module = importlib.import_module(brakeca._EXPORTS[name])
    assert getattr(brakeca, name) is getattr(module, name)
    assert name in brakeca.__all__ and name in dir(brakeca)


def test_all_names_the_exports():
    assert sorted(brakeca.__all__) == sorted(["__version__", *brakeca._EXPORTS])


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'simulation_config'"):
        brakeca.simulation_config  # noqa: B018


@pytest.mark.parametrize("config", [{"WP": 1e-13}, "paper", None])
def test_simulate_says_what_a_config_is(config):
    """simulate({'WP': 1e-13}) or simulate('paper') raised AttributeError: 'dict' object has
    no attribute 'mesh' (a second review)."""
    from brakeca.simulation import simulate

    with pytest.raises(TypeError, match=r"config must be a SimulationConfig \(e.g. brakeca"):
        simulate(config, seed=1)


def test_a_path_or_a_name_where_an_object_goes_is_named(tmp_path):
    """write_study, plot_run and quick_config had said "'str' object has no attribute
    'out_dir'" (or 'dataset', 'with_updates') for a folder, a run file or a preset's name
    (an API review); each now names the argument and the call that reads it."""
    with pytest.raises(TypeError, match=r"result: a campaign result, not str \('camp'\): "
                       r"brakeca.load_campaign\(folder\)"):  # fmt: skip
        brakeca.write_study("camp")
    with pytest.raises(TypeError, match=r"result: a RunResult, not PosixPath .*from_netcdf"):
        brakeca.plot_run(tmp_path / "run.nc", tmp_path)
    with pytest.raises(TypeError, match=r"config: a SimulationConfig \(brakeca.load_preset"):
        brakeca.quick_config("paper")


def test_analyze_takes_a_finished_campaign() -> None:
    """``brakeca.analyze(campaign)`` had needed the summary and the design's factors apart,
    and ``log10_V_mm3``, which the docs call the analysis's, was a KeyError (an API
    review)."""
    import numpy as np
    import pandas as pd

    from brakeca.design import load_design
    from brakeca.study import with_log_v

    design = load_design("paper")
    rng = np.random.default_rng(1)
    rows = pd.DataFrame(design.combinations())
    rows = rows.assign(MU=0.3 + 0.01 * rng.standard_normal(24), V=1e-9 * (1 + rng.random(24)))
    rows["status"] = "ok"
    campaign = type("Campaign", (), {"summary": rows, "design": design})()
    out = brakeca.analyze(campaign, responses=["MU", "log10_V_mm3"])
    expected = brakeca.analyze(with_log_v(rows), design.factors, ["MU", "log10_V_mm3"])
    for response in ("MU", "log10_V_mm3"):
        pd.testing.assert_frame_equal(out[response]["anova"], expected[response]["anova"])
    with pytest.raises(TypeError, match=r"^factors: give the design's factors"):
        brakeca.analyze(rows)
    # a campaign folder's path: say how to read it (a fuzz review)
    with pytest.raises(TypeError, match=r"not a path \('camp'\): brakeca.load_campaign"):
        brakeca.analyze("camp")
    # the design's analysis settings, as the report takes them: a Type III ANOVA reduced at
    # 0.1 (analyze(campaign) had fitted Type II, unreduced: an API review); an argument given
    # still wins
    chosen = design.model_copy(update={"anova_type": 3, "alpha_to_remove": 0.1})
    reduced = type("Campaign", (), {"summary": rows, "design": chosen})()
    out = brakeca.analyze(reduced, responses=["MU"])["MU"]["anova"]
    given = brakeca.analyze(rows, design.factors, ["MU"], anova_type=3, alpha_to_remove=0.1)
    expected = given["MU"]["anova"]
    pd.testing.assert_frame_equal(out, expected)
    assert out.attrs["typ"] == "Type III (adjusted)" and len(out) < 11  # terms removed
    assert brakeca.analyze(rows, chosen, ["MU"])["MU"]["anova"].equals(expected)
    other = brakeca.analyze(reduced, responses=["MU"], anova_type=2)
    assert other["MU"]["anova"].attrs["typ"] == "Type II"
    # main_effects_only given chooses the model, as without a design (a diff review: the
    # design's order had won over it)
    alone = brakeca.analyze(campaign, responses=["MU"], main_effects_only=True)["MU"]["anova"]
    assert list(alone["term"]) == ["S", "WP", "WR", "A", "Residual"]


def test_each_table_takes_the_designs_settings_as_analyze_does() -> None:
    """Given the design or a campaign, anova, residuals, unusual_runs, the level tables and
    the ranked effects fit the design's model, ANOVA type and elimination, as analyze and the
    report do (an API review: anova(summary, design, "MU") was a Type II, unreduced fit
    beside the report's Type III, reduced one; unusual_runs took neither a design nor a
    campaign, whose fields it iterated)."""
    import numpy as np
    import pandas as pd

    from brakeca import analysis
    from brakeca.design import load_design

    design = load_design("paper").model_copy(
        update={"anova_type": 3, "alpha_to_remove": 0.1, "model_order": 1}
    )
    rng = np.random.default_rng(1)
    rows = pd.DataFrame(design.combinations())
    rows = rows.assign(MU=0.3 + 0.01 * rng.standard_normal(24) + 0.02 * (rows["A"] == 20))
    rows["status"] = "ok"
    campaign = type("Campaign", (), {"summary": rows, "design": design})()
    report = brakeca.analyze(campaign, responses=["MU"])["MU"]
    for given in (design, campaign):
        table = analysis.anova(rows, given, "MU")
        pd.testing.assert_frame_equal(table, report.anova)
        assert table.attrs["typ"] == "Type III (adjusted)"
        assert ":" not in "".join(table["term"]) and len(table) < 6  # order 1, reduced
        pd.testing.assert_frame_equal(analysis.residuals(rows, given, "MU"), report.residuals)
        unusual = analysis.unusual_runs(rows, given, "MU")
        pd.testing.assert_frame_equal(unusual, report.unusual)
        coefficients = analysis.level_coefficients(rows, given, "MU")
        pd.testing.assert_frame_equal(coefficients, report.coefficients)
        ranked = analysis.ranked_effects(rows, given, "MU")
        assert list(ranked["term"]) == list(report.ranked_effects["term"])
    # the factors alone: the defaults (two-factor interactions, Type II, the whole model)
    plain = analysis.anova(rows, design.factors, "MU")
    assert plain.attrs["typ"] == "Type II" and "WP:A" in set(plain["term"])
    # an argument given wins over the design's
    two = analysis.anova(rows, design, "MU", typ=2)
    assert two.attrs["typ"] == "Type II" and len(two) == len(report.anova)


def test_a_campaign_result_stands_for_its_summary_and_design_in_every_table() -> None:
    """Only analyze took a campaign result; the table and plot functions failed with
    "'NoneType' object is not iterable" or "no attribute 'columns'" (an API review). A
    campaign given as the summary is its summary, and, with factors None, its design."""
    import matplotlib

    matplotlib.use("Agg")
    import numpy as np
    import pandas as pd

    from brakeca import analysis, plotting
    from brakeca.design import load_design

    design = load_design("paper")
    rng = np.random.default_rng(2)
    rows = pd.DataFrame(design.combinations())
    rows = rows.assign(MU=0.3 + 0.01 * rng.standard_normal(24), V=1e-9 * (1 + rng.random(24)))
    rows["status"] = "ok"
    rows["test"] = range(1, 25)
    campaign = type("Campaign", (), {"summary": rows, "design": design})()
    # the log scale of V, as analyze gives it (a table of a campaign had said it was no
    # column: an API review)
    logged = analysis.main_effects(campaign, None, "log10_V_mm3")
    from brakeca.study import with_log_v

    pd.testing.assert_frame_equal(
        logged, analysis.main_effects(with_log_v(rows), design, "log10_V_mm3")
    )
    with pytest.raises(KeyError, match=r"with_log_v\(summary\) adds it"):
        analysis.main_effects(rows.assign(V_mm3=1.0), design, "log10_V_mm3")
    for table in (
        analysis.main_effects,
        analysis.interactions_long,
        analysis.anova,
        analysis.residuals,
        analysis.unusual_runs,
        analysis.ranked_effects,
        analysis.factor_trends,
        analysis.level_coefficients,
        analysis.level_comparisons,
    ):
        pd.testing.assert_frame_equal(table(campaign, None, "MU"), table(rows, design, "MU"))
    effects = analysis.two_level_effects(campaign, None, "MU")  # (not every factor has 2 levels)
    pd.testing.assert_frame_equal(effects, analysis.two_level_effects(rows, design, "MU"))
    pairs = analysis.interaction_tables(campaign, None, "MU")
    assert pairs.keys() == analysis.interaction_tables(rows, design, "MU").keys()
    pd.testing.assert_frame_equal(
        analysis.interaction_table(campaign, "WP", "A", "MU"),
        analysis.interaction_table(rows, "WP", "A", "MU"),
    )
    assert len(plotting.plot_main_effects(campaign, None, "MU").axes) == 4
    assert len(plotting.plot_interactions(campaign, None, "MU").axes) >= 6
    assert len(plotting.plot_v_per_run(campaign).axes) == 1
    # factors None beside a table, or a design where a figure takes its file, are named
    with pytest.raises(TypeError, match=r"^factors: give the design's factors"):
        analysis.anova(rows, None, "MU")
    with pytest.raises(TypeError, match=r"^path: a file to write \(str or Path\), not Design"):
        plotting.plot_v_per_run(rows, design)  # type: ignore[arg-type]


def test_the_effects_table_takes_the_designs_analysis_as_analyze_does() -> None:
    """Given a design or a campaign, two_level_effects fits the model the design's analysis
    fits, as analyze's effects table (a diff review: it fitted every estimable effect beside
    the report's reduced model); main_effects_only or model_terms given still win."""
    import numpy as np
    import pandas as pd

    from brakeca import analysis
    from brakeca.design import load_design

    design = load_design("screen").model_copy(update={"alpha_to_remove": 0.1})
    rng = np.random.default_rng(3)
    rows = pd.DataFrame(design.combinations())
    rows["MU"] = (
        0.3 + 0.02 * (rows["S"] == rows["S"].max()) + 0.004 * rng.standard_normal(len(rows))
    )
    rows["status"] = "ok"
    campaign = type("Campaign", (), {"summary": rows, "design": design})()
    report = brakeca.analyze(campaign, responses=["MU"])["MU"].effects
    for given in (design, campaign):
        pd.testing.assert_frame_equal(analysis.two_level_effects(rows, given, "MU"), report)
    every = analysis.two_level_effects(rows, design.factors, "MU")
    assert len(report) < len(every)  # the reduced model's terms, not every effect
    alone = analysis.two_level_effects(rows, design, "MU", main_effects_only=True)
    assert set(alone["term"]) == set(design.factor_names)


def test_the_package_ships_its_type_hints_and_a_campaign_compares_by_identity(tmp_path) -> None:
    """An API review: no py.typed marker, so a user's mypy saw every brakeca name as Any (PEP
    561); a campaign result's == (a dataclass's) compared its summary's truth value and
    raised, so ``campaign in [other]`` failed."""
    from importlib.resources import files

    import pandas as pd
    import xarray as xr

    from brakeca.campaign import CampaignResult
    from brakeca.design import load_design

    assert files("brakeca").joinpath("py.typed").is_file()
    parts = (tmp_path, load_design("paper"), pd.DataFrame({"MU": [0.3]}), xr.Dataset())
    one, other = CampaignResult(*parts), CampaignResult(*parts)
    assert one == one and one != other and one in [one] and other not in [one]
    assert len({id(one): one}) == 1
