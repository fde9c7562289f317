"""Tests of brakeca.power against statsmodels' power of the t and F tests and a simulation of
the study's own ANOVA."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from statsmodels.stats.power import FTestAnovaPower, TTestIndPower
from typer.testing import CliRunner

from brakeca.analysis import Factor, anova
from brakeca.cli import app
from brakeca.design import design_from_dict, load_design
from brakeca.power import factor_power, pure_error_sigma, replicates_needed, smallest_effect


def _one_factor(levels: list[float]) -> object:
    return design_from_dict(
        {
            "name": "one",
            "base": "paper",
            "root_seed": 1,
            "factors": [{"name": "mu0", "field": "friction.mu_0", "levels": levels}],
        }
    )


@pytest.mark.parametrize("replicates", [2, 3, 7])
def test_a_two_level_factor_alone_is_the_two_sample_t_test(replicates):
    design = _one_factor([0.5, 0.7])
    table = factor_power(design, 0.02, 0.015, replicates=[replicates])
    expected = TTestIndPower().power(
        effect_size=0.02 / 0.015, nobs1=replicates, ratio=1.0, alpha=0.05
    )
    assert table["df_error"].item() == 2 * replicates - 2
    assert table["power"].item() == pytest.approx(expected, rel=1e-9)


def test_a_three_level_factor_alone_is_the_one_way_anova():
    design = _one_factor([0.5, 0.6, 0.7])
    table = factor_power(design, 0.03, 0.02, replicates=[4], alpha=0.1)
    # the least favourable means: two of them the effect apart, the third midway
    f = math.sqrt(0.03**2 / (2 * 3 * 0.02**2))
    expected = FTestAnovaPower().power(effect_size=f, nobs=12, alpha=0.1, k_groups=3)
    assert table["power"].item() == pytest.approx(expected, rel=1e-9)


def test_the_paper_design_matches_a_simulation_of_its_anova():
    """The study's own ANOVA (main effects and two-factor interactions, 9 error df) on the
    paper's 24 tests: the share of simulated campaigns in which it finds S's effect. (Its
    p-value, a fixed function of the responses, is computed for all the campaigns at once
    by least squares, as the ANOVA's Type II F test, and checked against brakeca's ANOVA on
    the first 20 and the 5 closest to the level: 300 calls had been 10 s; a review of the
    suite's time.)"""
    import itertools

    from scipy import stats

    design = load_design("paper")
    table = factor_power(design, 0.01, 0.01, replicates=[1]).set_index("factor")
    assert table.loc["S", "df_error"] == 9
    rng = np.random.default_rng(2016)
    base = pd.DataFrame(design.combinations())
    base["status"] = "ok"
    trials = 300
    # the draws of 300 campaigns one by one, in one array
    y = 0.4 + 0.01 * base["S"].to_numpy() + 0.01 * rng.standard_normal((trials, len(base)))
    names = [f.name for f in design.factors]
    dummies = {  # each factor's levels but its first, as indicator columns
        n: [(base[n] == v).to_numpy(float) for v in sorted(base[n].unique())[1:]] for n in names
    }
    terms = [(n,) for n in names] + list(itertools.combinations(names, 2))

    def rss(model):
        """Each campaign's residual sum of squares under ``model``'s terms, and its df."""
        x = np.column_stack(
            [np.ones(len(base))]
            + [
                np.prod(c, axis=0)
                for t in model
                for c in itertools.product(*(dummies[f] for f in t))
            ]
        )
        resid = y - y @ (x @ np.linalg.pinv(x)).T
        return (resid**2).sum(axis=1), len(base) - np.linalg.matrix_rank(x)

    error, df = rss(terms)
    assert df == 9
    others = [t for t in terms if "S" not in t]  # Type II: S after the terms without it
    p = stats.f.sf((rss(others)[0] - rss([*others, ("S",)])[0]) / (error / df), 1, df)
    for k in [*range(20), *np.argsort(np.abs(p - 0.05))[:5]]:
        result = anova(base.assign(MU=y[k]), list(design.factors), "MU").set_index("term")
        assert result.loc["S", "p_value"] == pytest.approx(p[k], rel=1e-9)
    found = int((p < 0.05).sum())
    # binomial scatter of the share: about 0.028 at 300 trials
    assert found / trials == pytest.approx(table.loc["S", "power"], abs=0.09)


def test_replicates_needed_is_the_fewest_that_reach_the_target():
    design = load_design("paper")
    needed = replicates_needed(design, 0.004, 0.01, target=0.8).set_index("factor")
    for name, row in needed.iterrows():
        r = int(row["replicates"])
        assert row["power"] >= 0.8
        if r > 1:
            before = factor_power(design, 0.004, 0.01, replicates=[r - 1]).set_index("factor")
            assert before.loc[name, "power"] < 0.8
    # WP has three levels: it needs more runs than the two-level factors
    assert needed.loc["WP", "replicates"] > needed.loc["S", "replicates"]


def test_bad_input_names_the_parameter():
    design = load_design("paper")
    for kwargs, message in [
        ({"effect": 0.0, "sigma": 1.0}, "effect: expected a finite number above 0"),
        ({"effect": 1.0, "sigma": math.nan}, "sigma: expected a finite number above 0"),
        ({"effect": 1.0, "sigma": 1.0, "alpha": 1.5}, "alpha: expected a level above 0 and below"),
        ({"effect": 1.0, "sigma": 1.0, "alpha": "0.05"}, "alpha: expected a level above 0"),
        ({"effect": 1.0, "sigma": "0.0059"}, "sigma: expected a finite number above 0"),
        ({"effect": "1", "sigma": 1.0}, "effect: expected a finite number above 0"),
        ({"effect": 1.0, "sigma": 1.0, "replicates": [0]}, "replicates: expected whole numbers"),
        # no limit ran out of memory (a fuzz review: 10**8 replicates, killed)
        ({"effect": 1.0, "sigma": 1.0, "replicates": [10_001]}, "replicates: at most 10,000"),
    ]:
        with pytest.raises(ValueError, match=message):
            factor_power(design, **kwargs)
    with pytest.raises(ValueError, match=r"target: expected a power above alpha \(0.05\)"):
        replicates_needed(design, 1.0, 1.0, target=1.0)
    # at or below alpha it is met with no effect at all (a black-box review)
    with pytest.raises(ValueError, match=r"target: expected a power above alpha \(0.05\)"):
        replicates_needed(design, 1.0, 1.0, target=0.02)
    with pytest.raises(ValueError, match="replicates: 2 is given twice"):
        factor_power(design, 1.0, 1.0, replicates=[2, 1, 2])
    with pytest.raises(ValueError, match="response-surface design"):
        factor_power(load_design("response_surface"), 1.0, 1.0)
    with pytest.raises(ValueError, match="target: expected a power above alpha"):
        replicates_needed(design, 1.0, 1.0, target="0.8")
    with pytest.raises(TypeError, match="design: expected a Design, a shipped design's name"):
        factor_power({"name": "paper"}, 1.0, 1.0)


def test_a_design_is_taken_by_name_or_file_as_run_campaign_takes_it(tmp_path):
    """factor_power("paper", ...) had failed with an AttributeError (a helper's API review)."""
    from brakeca.presets import design_path

    by_object = factor_power(load_design("paper"), 0.01, 0.0059)
    pd.testing.assert_frame_equal(factor_power("paper", 0.01, 0.0059), by_object)
    pd.testing.assert_frame_equal(factor_power(design_path("paper"), 0.01, 0.0059), by_object)
    assert not replicates_needed("paper", 0.01, 0.0059).empty
    assert not smallest_effect("paper", 0.0059, replicates=[2]).empty


def test_unreplicated_saturated_design_has_no_error_df():
    design = design_from_dict(
        {
            "name": "two",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "S", "levels": [0.0, 1.0]},
                {"name": "A", "levels": [10.0, 20.0]},
            ],
        }
    )
    table = factor_power(design, 1.0, 1.0, replicates=[1, 2]).set_index("replicates")
    # one run per test: the interaction is pooled, 1 error df; two: 4 error df
    assert list(table["df_error"].unique()) == [1.0, 4.0]
    assert table["power"].notna().all()


def test_pure_error_sigma_is_the_pooled_scatter_within_tests():
    factor = Factor("S", (0.0, 1.0))
    summary = pd.DataFrame(
        {"test": [1, 1, 1, 2, 2], "S": [0.0, 0.0, 0.0, 1.0, 1.0], "status": "ok"}
    ).assign(MU=[0.40, 0.42, 0.47, 0.50, 0.53])
    ss = (0.40 - 0.43) ** 2 + (0.42 - 0.43) ** 2 + (0.47 - 0.43) ** 2 + 2 * 0.015**2
    assert pure_error_sigma(summary, [factor], "MU") == pytest.approx(math.sqrt(ss / 3))
    with pytest.raises(ValueError, match="no pure error"):
        pure_error_sigma(summary.iloc[[0, 3]], [factor], "MU")


def test_pure_error_interval_is_the_two_sided_chi_square_one():
    """sigma's interval from the pure error's SS on nu degrees of freedom: sigma sqrt(nu /
    chi2(0.975, nu)) to sigma sqrt(nu / chi2(0.025, nu)), two-sided (a mutation review: only
    an integration test's printed text checked it)."""
    from scipy import stats

    from brakeca.power import pure_error

    factor = Factor("S", (0.0, 1.0))
    summary = pd.DataFrame(
        {"test": [1, 1, 1, 2, 2], "S": [0.0, 0.0, 0.0, 1.0, 1.0], "status": "ok"}
    ).assign(MU=[0.40, 0.42, 0.47, 0.50, 0.53])
    ss = (0.40 - 0.43) ** 2 + (0.42 - 0.43) ** 2 + (0.47 - 0.43) ** 2 + 2 * 0.015**2
    sigma = math.sqrt(ss / 3)
    low = sigma * math.sqrt(3 / stats.chi2.ppf(0.975, 3))
    high = sigma * math.sqrt(3 / stats.chi2.ppf(0.025, 3))
    got_sigma, df, (got_low, got_high) = pure_error(summary, [factor], "MU")
    assert (got_sigma, df) == (pytest.approx(sigma, rel=1e-12), 3.0)
    assert (got_low, got_high) == (pytest.approx(low, rel=1e-9), pytest.approx(high, rel=1e-9))
    assert (low, high) == (pytest.approx(0.0180626386), pytest.approx(0.1188855158))


def test_the_power_command():
    runner = CliRunner()
    res = runner.invoke(app, ["power", "paper", "--effect", "0.01", "--sigma", "0.01"])
    assert res.exit_code == 0, res.output
    # S, WR and A with one replicate: 12 runs at each level, half the difference from the
    # mean at each, so the noncentrality is 24 (0.005 / 0.01)^2 = 6 on 1 and 9 df (the
    # residual of the paper's 2-factor model)
    from scipy import stats

    power = stats.ncf.sf(stats.f.ppf(0.95, 1, 9), 1, 9, 6.0)
    assert "power by replicates" in res.output and f"{power:.3f}" in res.output  # 0.589
    res = runner.invoke(
        app, ["power", "paper", "--effect", "0.01", "--sigma", "0.01", "--target", "0.9"]
    )
    assert res.exit_code == 0 and "fewest replicates for power 0.9" in res.output
    res = runner.invoke(app, ["power", "response_surface", "--effect", "1", "--sigma", "1"])
    assert res.exit_code != 0 and "response-surface design" in res.output
    # refused before --sigma-from is read and its sigma printed (a black-box review)
    res = runner.invoke(app, ["power", "response_surface", "--effect", "1", "--sigma-from", "."])
    assert res.exit_code == 2 and "sigma:" not in res.output
    assert "not for a response-surface design's quadratic terms" in " ".join(res.output.split())
    for args, message in [
        (["--effect", "0.01"], "give the response's scatter: --sigma S or --sigma-from"),
        (["--effect", "-1", "--sigma", "1"], "--effect: expected a finite number above 0"),
        (["--effect", "1", "--sigma", "1", "--replicates", "1,x"], "--replicates: expected"),
        (["--effect", "1", "--sigma", "1", "--response", "Q"], "--response: expected one of"),
        (["--effect", "1", "--sigma", "1", "--alpha", "1"], "--alpha: expected a level above 0"),
        (["--effect", "1", "--sigma", "1", "--target", "2"], "--target: expected a power"),
        (["--effect", "1", "--sigma", "1", "--sigma-from", "."], "give one of them, not both"),
    ]:
        res = runner.invoke(app, ["power", "paper", *args])
        assert res.exit_code != 0 and message in res.output, res.output


def _run_table(runs: list[dict], a_levels: list[float]) -> object:
    return design_from_dict(
        {
            "name": "table",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "S", "levels": [0.0, 1.0]},
                {"name": "A", "levels": a_levels},
            ],
            "runs": runs,
        }
    )


def test_an_unbalanced_run_table_loses_what_the_adjustment_takes():
    """S and A correlated (6 of 8 runs at S-, A- or S+, A+): the Type II test of S adjusts
    for A, so its noncentrality at E = 2 sigma is 12 with two replicates, not the 16 that
    the fewest runs at a level would give; power 0.888 (a review's simulation: 0.885)."""
    runs = [{"S": 0.0, "A": 10.0}] * 3 + [{"S": 1.0, "A": 20.0}] * 3
    runs += [{"S": 0.0, "A": 20.0}, {"S": 1.0, "A": 10.0}]
    table = factor_power(_run_table(runs, [10.0, 20.0]), 2.0, 1.0, replicates=[2, 3])
    table = table.set_index(["replicates", "factor"])
    assert table.loc[(2, "S"), "noncentrality"] == pytest.approx(12.0, rel=1e-9)
    assert table.loc[(2, "S"), "power"] == pytest.approx(0.888, abs=5e-4)
    # from two replicates on, each more adds the tests to the error and its share to the sum
    assert table.loc[(3, "S"), "noncentrality"] == pytest.approx(18.0, rel=1e-9)
    assert table.loc[(3, "S"), "df_error"] == table.loc[(2, "S"), "df_error"] + 8


def test_levels_the_runs_leave_out_and_a_nil_effect():
    both = [{"S": s, "A": a} for s in (0.0, 1.0) for a in (10.0, 20.0)]
    # A's middle level has no run: its two used levels are tested, with 1 df
    table = factor_power(_run_table(both * 2, [10.0, 15.0, 20.0]), 2.0, 1.0, replicates=[1])
    row = table.set_index("factor").loc["A"]
    assert row["df"] == 1 and row["noncentrality"] == pytest.approx(8.0)
    assert 0.5 < row["power"] < 0.6
    # a factor the runs leave at one level is not tested
    one = factor_power(_run_table([{"S": s, "A": 10.0} for s in (0.0, 1.0)] * 3, [10.0, 20.0]),
                       1.0, 1.0, replicates=[1])  # fmt: skip
    assert math.isnan(one.set_index("factor").loc["A", "power"])
    # an effect too small to move the test: its power is alpha (scipy's noncentral F gives
    # -0.95 at a noncentrality of exactly 0)
    nil = factor_power(load_design("paper"), 1e-170, 1.0, replicates=[1], alpha=0.05)
    assert (nil["power"] == 0.05).all()


def test_the_design_replicates_are_shown_and_the_search_stops_at_its_cap():
    table = factor_power(load_design("paper_replicated"), 0.01, 0.01)
    assert sorted(table["replicates"].unique()) == [1, 2, 3, 4, 5]
    seven = load_design("paper").model_copy(update={"replicates": 7})
    assert factor_power(seven, 0.01, 0.01)["replicates"].max() == 7
    never = replicates_needed(load_design("paper"), 1e-6, 0.01, target=0.9)
    assert (never["replicates"] == 1000).all() and (never["power"] < 0.9).all()


def test_the_smallest_effect_is_found_with_the_target_power():
    """The other way round: the difference each factor's test finds with power 0.8, as
    statsmodels solves the two-sample t test for its effect size, and the power there."""
    one = _one_factor([0.5, 0.7])
    table = smallest_effect(one, 0.015, target=0.8, replicates=[1, 4])
    assert math.isnan(table.loc[0, "effect"])  # one run per level: no error df
    expected = TTestIndPower().solve_power(effect_size=None, nobs1=4, power=0.8, alpha=0.05)
    assert table.loc[1, "effect"] == pytest.approx(0.015 * expected, rel=1e-6)
    paper = load_design("paper")
    found = smallest_effect(paper, 0.0059, target=0.9, replicates=[1, 3])
    for _, row in found.iterrows():
        power = factor_power(paper, row["effect"], 0.0059, replicates=[int(row["replicates"])])
        assert power.set_index("factor").loc[row["factor"], "power"] == pytest.approx(0.9)
    with pytest.raises(ValueError, match=r"target: expected a power above alpha \(0.05\)"):
        smallest_effect(paper, 1.0, target=0.05)
    with pytest.raises(ValueError, match=r"^sigma: expected a finite number above 0"):
        smallest_effect(paper, 0.0)  # it had said "effect:", checking sigma as the effect
    res = CliRunner().invoke(app, ["power", "paper", "--sigma", "0.0059", "--target", "0.8"])
    assert res.exit_code == 0 and "smallest difference in MU found with power 0.8" in res.output
    # S, WR and A with one replicate: the difference d whose noncentrality 24 (d / 2)^2 /
    # 0.0059^2 on 1 and 9 df gives power 0.8, solved here with scipy (0.007586)
    from scipy import optimize, stats

    critical = stats.f.ppf(0.95, 1, 9)
    d = optimize.brentq(
        lambda d: stats.ncf.sf(critical, 1, 9, 24 * (d / 2) ** 2 / 0.0059**2) - 0.8, 1e-4, 0.1
    )
    assert f"{d:.4g}" in res.output
    # V's figures carry their unit (a helper's review: the table had none)
    args = ["power", "paper", "--sigma", "0.01", "--target", "0.8", "--response", "V"]
    res = CliRunner().invoke(app, args, env={"COLUMNS": "200"})
    out = " ".join(res.output.split())
    assert res.exit_code == 0 and "sigma 0.01 mm³" in out and "smallest difference [mm³]" in out
    res = CliRunner().invoke(app, ["power", "paper", "--sigma", "0.0059"])
    assert res.exit_code != 0 and "give --effect E" in res.output


def test_a_run_table_has_the_power_of_the_same_full_factorial():
    """Power comes from an ANOVA of noise-free responses, an exact fit: its Type II sums of
    squares had been NaN where the fit left exactly no residual (statsmodels' Wald tests
    divide by a zero scale), which a run table's order of runs could bring about: 'no error
    df' beside 2 error df, a smallest difference of 0 (a helper's fuzzing). The run table
    and the full factorial it writes out now give the same power."""
    base = {"name": "t", "base": "paper", "root_seed": 1, "replicates": 2}
    factor = {"name": "A", "levels": [10.0, 20.0]}
    table = design_from_dict({**base, "factors": [factor], "runs": [{"A": 20.0}, {"A": 10.0}]})
    full = design_from_dict({**base, "factors": [factor]})
    a = factor_power(table, effect=0.01, sigma=0.01, replicates=[2, 3])
    b = factor_power(full, effect=0.01, sigma=0.01, replicates=[2, 3])
    np.testing.assert_allclose(a["power"], b["power"], rtol=1e-12)
    assert a["power"].between(0.05, 1).all()
    assert smallest_effect(table, sigma=0.01, target=0.8, replicates=[2])["effect"].gt(0).all()
    with pytest.raises(ValueError, match=r"replicates: expected a list of whole numbers, e.g\."):
        smallest_effect(table, sigma=0.01, replicates=2)  # type: ignore[arg-type]


def test_power_says_where_the_model_pools_its_interactions(tmp_path, monkeypatch) -> None:
    """A black-box review: an unreplicated 2 x 2 leaves its interaction no error, so the
    model pools it (error df 1), yet power's footer read 'main effects and two-factor
    interactions'. It now says at which replicates the model pools what."""
    from typer.testing import CliRunner

    from brakeca.cli import app
    from brakeca.power import pooling_note

    path = tmp_path / "ff.toml"
    path.write_text(
        'name = "ff"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "WP"\n'
        'levels = [1e-15, 1e-13]\n[[factors]]\nname = "A"\nlevels = [10, 20]\n'
    )
    design = load_design(path)
    assert "interactions pooled into the residual, main effects only" in pooling_note(design, 1)
    assert pooling_note(design, 2) == ""
    assert pooling_note(load_design("paper"), 1) == ""
    # many replicates are fitted as two (a review: 10,000 fitted 240,000 runs for nothing)
    from brakeca import power

    asked: list[int] = []
    runs = power._runs

    def counted(d, r):
        asked.append(r)
        return runs(d, r)

    monkeypatch.setattr(power, "_runs", counted)
    assert pooling_note(design, 10_000) == "" and asked == [2]
    args = ["power", str(path), "--effect", "0.01", "--sigma", "0.0059", "--replicates", "1,2"]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    text = " ".join(res.output.split())
    assert "with 1 replicate: model with two-factor interactions is saturated" in text
    assert "with 2 replicates:" not in text


def test_a_huge_noncentrality_has_power_1_not_no_error_df():
    """scipy's noncentral F is NaN past a noncentrality of about 1e19, which the command
    showed as "no error df" with 9 error df beside it (a fuzz review: sigma in m^3 for V's
    mm^3, say). The power there is 1, its limit, as at a noncentrality a little below."""
    design = load_design("paper")
    huge = factor_power(design, 1.0, 1e-10, replicates=[1])
    large = factor_power(design, 1.0, 1e-3, replicates=[1])
    assert (huge["power"] == 1.0).all() and np.allclose(large["power"], 1.0, atol=1e-12)
    assert (huge["df_error"] == 9).all()
    res = CliRunner().invoke(app, ["power", "paper", "--effect", "1", "--sigma", "1e-10"])
    assert res.exit_code == 0 and "no error df" not in res.output, res.output
