"""The trend of a factor of three or more levels (brakeca.analysis.factor_trends): its main
effect split into orthogonal-polynomial parts, each tested in the ANOVA's model, checked
against statsmodels' OLS with patsy's polynomial coding, an independent computation."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import Factor, anova, factor_trends

WP = Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)")
S = Factor("S", (0.0, 1.0))
A = Factor("A", (10.0, 20.0), "%")


def _runs(replicates: int = 2, seed: int = 7) -> pd.DataFrame:
    """A 3 x 2 x 2 design with replicates, the response quadratic in log10 WP."""
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(replicates):
        for wp, s, a in itertools.product(WP.levels, S.levels, A.levels):
            x = math.log10(wp) + 14.0  # -1, 0, 1
            y = 1.0 + 0.5 * x + 0.3 * x**2 + 0.2 * s + 0.1 * x * s + 0.05 * rng.standard_normal()
            rows.append({"WP": wp, "S": s, "A": a, "y": y, "status": "ok"})
    return pd.DataFrame(rows)


def _statsmodels_t(summary: pd.DataFrame, scores) -> dict[str, tuple[float, float]]:
    """(t, p) of WP's polynomial columns in OLS of y on WP (patsy's Poly, the given scores),
    S and A (sum-to-zero) and their two-factor interactions."""
    from statsmodels.formula.api import ols

    formula = f"y ~ (C(WP, Poly(scores={list(scores)})) + C(S, Sum) + C(A, Sum))**2"
    fit = ols(formula, data=summary).fit()
    out = {}
    for name, t in fit.tvalues.items():
        if name.startswith("C(WP") and ":" not in name:
            part = "linear" if name.endswith(".Linear]") else "quadratic"
            out[part] = (float(t), float(fit.pvalues[name]))
    return out


@pytest.mark.parametrize("drop", [(), (3, 10, 17)])
def test_the_parts_are_the_single_column_tests_of_the_polynomials(drop) -> None:
    """Balanced, and unbalanced (three runs dropped): each part's F is the square of the t of
    its polynomial column in the same model, and its p the t test's, as statsmodels gives."""
    summary = _runs().drop(index=list(drop)).reset_index(drop=True)
    trends = factor_trends(summary, [WP, S, A], "y")
    assert list(trends["factor"]) == ["WP", "WP"]
    assert list(trends["part"]) == ["linear", "quadratic"]
    assert set(trends["scale"]) == {"log10 WP"}  # evenly spaced on the log
    wanted = _statsmodels_t(summary, [-15.0, -14.0, -13.0])
    for part, (t, p) in wanted.items():
        row = trends.loc[trends["part"] == part].iloc[0]
        assert row["F"] == pytest.approx(t * t, rel=1e-9)
        assert row["p_value"] == pytest.approx(p, rel=1e-7)
    table = anova(summary, [WP, S, A], "y").set_index("term")
    resid_ms = table.loc["Residual", "mean_sq"]
    assert np.allclose(trends["sum_sq"] / resid_ms, trends["F"], rtol=1e-12)
    if not drop:  # balanced: the parts add up to WP's sum of squares, as contrasts do
        assert trends["sum_sq"].sum() == pytest.approx(table.loc["WP", "sum_sq"], rel=1e-10)
        assert trends["percent_of_factor"].sum() == pytest.approx(100.0, rel=1e-10)
        means = summary.groupby("WP")["y"].mean().to_numpy()
        n = len(summary) / 3
        linear = (means[2] - means[0]) ** 2 * n / 2.0  # contrast (-1, 0, 1)
        assert trends["sum_sq"].iloc[0] == pytest.approx(linear, rel=1e-10)


def test_the_trend_is_in_the_values_when_they_are_evenly_spaced_in_any_order() -> None:
    """Levels evenly spaced in the value (given out of order) take the values as the scale;
    the result is the design order's, and statsmodels' with those scores."""
    summary = _runs()
    summary["WP"] = summary["WP"].map({1e-15: 20.0, 1e-14: 10.0, 1e-13: 30.0})
    shuffled = Factor("WP", (20.0, 10.0, 30.0), "%")
    trends = factor_trends(summary, [shuffled, S, A], "y")
    assert set(trends["scale"]) == {"WP"}
    ordered = factor_trends(summary, [Factor("WP", (10.0, 20.0, 30.0)), S, A], "y")
    assert np.allclose(trends["F"], ordered["F"], rtol=1e-12, atol=0.0)
    for part, (t, _) in _statsmodels_t(summary, [10.0, 20.0, 30.0]).items():
        assert trends.loc[trends["part"] == part, "F"].iloc[0] == pytest.approx(t * t, rel=1e-9)


def test_no_trend_for_two_levels_or_a_factor_of_choices() -> None:
    summary = _runs()
    assert factor_trends(summary, [S, A], "y").empty
    by_choice = [
        {"name": "WP", "levels": list(WP.levels), "choices": ["x", "y", "z"]},
        S,
        A,
    ]
    assert factor_trends(summary, by_choice, "y").empty  # the levels only number choices


def test_a_factor_the_model_leaves_out_is_named() -> None:
    """A reduced model without WP: no parts, and the note says why."""
    summary = _runs()
    summary["y"] = 0.2 * summary["S"] + 0.01 * np.random.default_rng(1).standard_normal(24)
    trends = factor_trends(summary, [WP, S, A], "y", alpha_to_remove=0.1)
    assert trends.empty and "WP is not in the model" in trends.attrs["note"]


def test_each_parts_share_is_of_the_total_and_a_saturated_model_has_no_test() -> None:
    """A test-suite audit: percent_contribution over the factor's sum of squares, and the
    note of a model without residual degrees of freedom, passed unchecked."""
    summary = _runs()
    trends = factor_trends(summary, [WP, S, A], "y")
    total = anova(summary, [WP, S, A], "y").attrs["total_sum_sq"]
    y = summary["y"].to_numpy()
    assert total == pytest.approx(float(np.sum((y - y.mean()) ** 2)), rel=1e-12)
    np.testing.assert_allclose(trends["percent_contribution"], 100 * trends["sum_sq"] / total)
    one = _runs(replicates=1)  # 12 runs, and every term of the three factors: no residual
    every = ["WP", "S", "A", "WP*S", "WP*A", "S*A", "WP*S*A"]
    saturated = factor_trends(one, [WP, S, A], "y", interactions=every)
    assert list(saturated["part"]) == ["linear", "quadratic"]
    assert saturated["F"].isna().all() and saturated["p_value"].isna().all()
    assert "no residual degrees of freedom" in saturated.attrs["note"]
    assert (saturated["sum_sq"] > 0).all()


def test_analyze_gives_the_trends_for_factors_given_as_an_iterator() -> None:
    """A diff review: analyze() read a generator of factors twice, once empty, and gave an
    ANOVA with no trends."""
    from brakeca.analysis import analyze

    summary = _runs()
    listed = analyze(summary, [WP, S, A], responses=("y",))["y"]["trends"]
    lazily = analyze(summary, (f for f in (WP, S, A)), responses=("y",))["y"]["trends"]
    assert len(listed) == 2
    pd.testing.assert_frame_equal(lazily, listed)
    direct = factor_trends(summary, (f for f in (WP, S, A)), "y")  # read once there too
    pd.testing.assert_frame_equal(direct, listed)


def test_an_infinite_f_has_p_0_as_in_the_anova() -> None:
    """An exact fit (residual sum of squares 0) gives each part an infinite F, whose p is 0,
    as the ANOVA reports it; without residual degrees of freedom there is no p."""
    from brakeca.analysis import _f_sf

    assert _f_sf(math.inf, 9.0) == 0.0
    assert math.isnan(_f_sf(math.nan, 9.0)) and math.isnan(_f_sf(4.0, 0.0))
    from scipy import stats

    assert _f_sf(4.0, 9.0) == pytest.approx(stats.f.sf(4.0, 1, 9), rel=1e-12)  # 0.0765
