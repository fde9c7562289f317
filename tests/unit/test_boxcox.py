"""Box-Cox check of a response's scale (brakeca.boxcox)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from brakeca import analysis
from brakeca.boxcox import (
    BOX_COX_COLUMNS,
    box_cox,
    box_cox_profile,
    box_cox_table,
    save_box_cox_table,
    surface_box_cox,
)


@pytest.fixture
def lognormal() -> np.ndarray:
    return np.random.default_rng(1).lognormal(0.0, 0.5, 40)


def test_intercept_only_profile_is_scipys_log_likelihood(lognormal: np.ndarray) -> None:
    """With the intercept alone, L(λ) is scipy's boxcox_llf, and λ̂ and its interval are
    scipy's maximum-likelihood estimate and likelihood-ratio interval."""
    result = box_cox_profile(lognormal)
    profile = result.profile
    expected = [stats.boxcox_llf(lam, lognormal) for lam in profile["lam"]]
    np.testing.assert_allclose(profile["log_likelihood"], expected, rtol=1e-10)
    _, lam, (low, high) = stats.boxcox(lognormal, alpha=0.05)
    assert result.lambda_hat == pytest.approx(lam, abs=1e-6)
    assert result.ci_low == pytest.approx(low, abs=1e-6)
    assert result.ci_high == pytest.approx(high, abs=1e-6)
    assert result.rounded == 0.0 and result.contains(0.0) and not result.contains(1.0)
    assert "the log fits better" in result.reading


def test_model_profile_is_the_residual_sum_of_squares_of_the_scaled_transform() -> None:
    """With a model, L(λ) = -n/2 ln(SSE/n) of the OLS fit of (y^λ - 1) / (λ g^(λ-1))."""
    import statsmodels.api as sm

    rng = np.random.default_rng(7)
    x = np.repeat(np.arange(4.0), 6)
    exog = np.column_stack([np.ones(x.size), x, x**2])
    y = np.exp(0.4 * x + rng.normal(0.0, 0.2, x.size))
    result = box_cox_profile(y, exog)
    g = math.exp(np.mean(np.log(y)))
    for lam in (-1.0, 0.5, 1.25):
        w = (y**lam - 1.0) / (lam * g ** (lam - 1.0))
        sse = sm.OLS(w, exog).fit().ssr
        expected = -0.5 * y.size * math.log(sse / y.size)
        got = np.interp(lam, result.profile["lam"], result.profile["log_likelihood"])
        assert got == pytest.approx(expected, rel=1e-9)
    assert result.df_resid == y.size - 3


def test_lambda_does_not_depend_on_the_unit(lognormal: np.ndarray) -> None:
    """V in m³ (about 1e-9) gives the λ it gives in mm³."""
    a = box_cox_profile(lognormal)
    b = box_cox_profile(lognormal * 1e-9)
    assert b.lambda_hat == pytest.approx(a.lambda_hat, abs=1e-6)
    assert b.ci_low == pytest.approx(a.ci_low, abs=1e-6)
    assert b.ci_high == pytest.approx(a.ci_high, abs=1e-6)


def test_a_multiplicative_response_points_to_the_log_and_an_additive_one_to_no_transform() -> None:
    """Data made on a known scale: a factor that multiplies y over two decades gives λ near 0
    (1 excluded); a factor that adds a small shift to y gives λ = 1 inside the interval (a flat
    profile), and the square of an additive model gives λ near 0.5."""
    rng = np.random.default_rng(3)
    level = np.tile(np.arange(3.0), 20)
    exog = np.column_stack([np.ones(level.size), level == 1, level == 2]).astype(float)
    noise = rng.normal(0.0, 0.15, level.size)
    multiplicative = box_cox_profile(10.0**level * np.exp(noise), exog)
    # λ̂'s spread over seeds is about 0.06 here (0.1 with 8 runs a level, where the 95 %
    # interval held 0 for 37 of 40 seeds), so the test does not hang on the seed.
    assert abs(multiplicative.lambda_hat) < 0.25 and not multiplicative.contains(1.0)
    additive = box_cox_profile(100.0 + 3.0 * level + noise, exog)
    assert additive.contains(1.0)
    squared = box_cox_profile((1.0 + 12.0 * level + noise) ** 2, exog)
    # over 100 seeds: |λ̂ - 0.5| < 0.2 and neither 0 nor 1 in the interval every time
    assert abs(squared.lambda_hat - 0.5) < 0.2 and squared.rounded == 0.5
    assert not squared.contains(1.0) and not squared.contains(0.0)


@pytest.mark.parametrize(
    ("y", "exog", "why"),
    [
        ([1.0, 2.0, -1.0, 3.0], None, "positive"),
        ([1.0, 2.0, 0.0, 3.0], None, "positive"),
        ([2.0, 2.0, 2.0], None, "constant"),
        ([1.0, 2.0, 3.0], np.eye(3), "no residual degrees of freedom"),
        # one residual df: 1 - 2 * 2**λ + 5**λ changes sign between λ = -1 and 1, so the
        # profile has a pole there (a review: λ̂ 0.48, interval 0.48 to 0.48)
        ([1.0, 2.0, 5.0], np.column_stack([np.ones(3), np.arange(3.0)]), "one residual degree"),
        ([1.0], None, "1 usable run"),
    ],
)
def test_undefined_cases_say_why(y: list[float], exog: np.ndarray | None, why: str) -> None:
    result = box_cox_profile(y, exog, response="R")
    assert not result.defined and math.isnan(result.ci_low)
    assert why in result.note and result.reading == "" and result.profile.empty


def test_an_optimum_beyond_the_range_is_flagged() -> None:
    """Data that want λ well above 2 (the exp of a normal sample's log) end at the edge with
    a note and an open interval on that side."""
    y = np.log(np.random.default_rng(5).lognormal(3.0, 0.02, 30))  # near-constant, skewed left
    y = np.exp(np.exp(y / 4.0))
    result = box_cox_profile(y)
    assert result.lambda_hat in (-2.0, 2.0)
    assert "edge of the search range" in result.note
    assert math.isinf(result.ci_low if result.lambda_hat < 0 else result.ci_high)
    # written as the bound it is, in the report's table, sentence and figure
    assert result.edge == (-1 if result.lambda_hat < 0 else 1)
    assert result.hat_text() == ("≤ -2" if result.edge < 0 else "≥ 2")
    inside = box_cox_profile(np.random.default_rng(2).lognormal(0.0, 0.5, 30))
    assert inside.edge == 0 and inside.hat_text() == f"{inside.lambda_hat:.2f}"


def test_bad_input_is_refused() -> None:
    with pytest.raises(ValueError, match="finite"):
        box_cox_profile([1.0, math.nan, 2.0])
    with pytest.raises(ValueError, match="rows expected"):
        box_cox_profile([1.0, 2.0, 3.0], np.ones((2, 1)))
    with pytest.raises(ValueError, match="confidence"):
        box_cox_profile([1.0, 2.0, 3.0], confidence=1.0)


def _factorial_summary() -> tuple[pd.DataFrame, list[analysis.Factor]]:
    rng = np.random.default_rng(11)
    rows = []
    for wp in (1e-15, 1e-14, 1e-13):
        for a in (10.0, 20.0):
            for rep in range(3):
                v = 3e-9 * (wp / 1e-15) ** 0.9 * (0.5 if a == 20.0 else 1.0)
                rows.append(
                    {
                        "WP": wp,
                        "A": a,
                        "replicate": rep,
                        "status": "ok",
                        "V": v * math.exp(rng.normal(0.0, 0.1)),
                        "MU": 0.3 + 0.01 * rng.normal(),
                    }
                )
    factors = [
        analysis.Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)"),
        analysis.Factor("A", (10.0, 20.0), "%"),
    ]
    return pd.DataFrame(rows), factors


def test_campaign_box_cox_uses_the_anova_model() -> None:
    """On a campaign summary the profile is that of the ANOVA model's matrix; V made
    multiplicative in WP and A points to its log."""
    summary, factors = _factorial_summary()
    result = box_cox(summary, factors, "V")
    exog = analysis.model_matrix(summary, factors, "V")
    direct = box_cox_profile(summary["V"].to_numpy(), exog)
    assert result.lambda_hat == pytest.approx(direct.lambda_hat, abs=1e-12)
    assert result.df_resid == 18 - 6 and result.model.startswith("ANOVA model: V ~")
    assert result.contains(0.0) and not result.contains(1.0)
    failed = summary.assign(status=["failed"] + ["ok"] * (len(summary) - 1))
    assert box_cox(failed, factors, "V").n == len(summary) - 1


def test_surface_box_cox_uses_the_fitted_quadratic() -> None:
    from brakeca import rsm

    rng = np.random.default_rng(2)
    pts = [(a, b) for a in (-1.0, 0.0, 1.0) for b in (-1.0, 0.0, 1.0)] * 2
    summary = pd.DataFrame(pts, columns=["x1", "x2"])
    summary["status"] = "ok"
    summary["R"] = np.exp(1.0 + 0.8 * summary.x1 - 0.5 * summary.x2 + rng.normal(0, 0.05, 18))
    factors = [analysis.Factor("x1", (-1.0, 0.0, 1.0)), analysis.Factor("x2", (-1.0, 0.0, 1.0))]
    fit = rsm.fit_response_surface(summary, factors, "R")
    result = surface_box_cox(fit)
    assert result.df_resid == 18 - 6 and result.model.startswith("quadratic model: x1 + x2")
    assert result.contains(0.0)


def test_table_and_file(tmp_path) -> None:
    results = {"a": box_cox_profile([1.0, 2.0, 4.0, 8.0, 3.0]), "b": box_cox_profile([1.0, -1.0])}
    table = box_cox_table(results)
    assert tuple(table.columns) == BOX_COX_COLUMNS and len(table) == 2
    path = save_box_cox_table(results, tmp_path / "t" / "box_cox.csv")
    back = pd.read_csv(path)
    assert back.loc[1, "note"].startswith("needs positive values")


def test_the_reading_never_points_outside_the_interval() -> None:
    """λ̂ = -0.18 with an interval of -0.27 to -0.09 rounds to 0, which the interval excludes:
    the reading then gives λ̂ itself (a second review saw 'the data point to λ ≈ 0')."""
    import dataclasses

    base = box_cox_profile(np.random.default_rng(1).lognormal(0.0, 0.5, 40))
    base = dataclasses.replace(base, ci_low_df=math.nan, ci_high_df=math.nan)  # LR alone
    narrow = dataclasses.replace(base, lambda_hat=-0.18, ci_low=-0.27, ci_high=-0.09, rounded=0.0)
    assert narrow.reading.endswith(
        "nor any multiple of 0.5, lies within the 95 % interval: the data point to λ ≈ -0.18"
    )
    wide = dataclasses.replace(base, lambda_hat=-1.2, ci_low=-2.0, ci_high=-0.4, rounded=-1.0)
    assert wide.reading.endswith("the data point to λ ≈ -1")
    half = dataclasses.replace(base, lambda_hat=0.3, ci_low=0.1, ci_high=0.6, rounded=0.5)
    assert half.reading.endswith("the data point to λ ≈ 0.5")


def test_the_log_reading_names_the_rounded_lambda_it_also_holds() -> None:
    """A review of a response-surface report: "Rounded λ 0.5" stood beside the reading "the
    log fits better" (λ̂ = 0.30, both 0 and 0.5 in the interval) without a word."""
    import dataclasses

    base = box_cox_profile(np.random.default_rng(1).lognormal(0.0, 0.5, 40))
    base = dataclasses.replace(base, ci_low_df=math.nan, ci_high_df=math.nan)  # LR alone
    both = dataclasses.replace(base, lambda_hat=0.3, ci_low=-0.1, ci_high=0.7, rounded=0.5)
    assert both.reading == (
        "λ = 0 lies within the 95 % interval and λ = 1 does not: the log fits better than "
        "the response as it is; so does λ = 0.5, the rounded λ̂"
    )
    log = dataclasses.replace(base, lambda_hat=0.1, ci_low=-0.3, ci_high=0.4, rounded=0.0)
    assert log.reading.endswith("the log fits better than the response as it is")


def test_the_rounded_lambda_is_the_nearest_multiple_of_a_half() -> None:
    """A test-suite audit: rounding lambda-hat down (floor) passed, every tested lambda-hat
    sitting just above a multiple of 0.5. The 2.5th power of a normal sample is normal at
    lambda = 0.4: its lambda-hat is below 0.5 and rounds up to it."""
    z = np.random.default_rng(1).normal(10.0, 1.0, 400)
    result = box_cox_profile(z**2.5)
    assert 0.25 < result.lambda_hat < 0.5
    assert result.rounded == 0.5


def test_an_optimum_a_hair_inside_the_edge_is_flagged_too() -> None:
    """A campaign's MU whose profile still rises at -2: the bounded search stopped at
    -1.9997, and the note of the edge was missing (a helper's review of the command line).
    Its 2 x 2 design with 2 replicates, the model of the report (with the interaction)."""
    mu = [
        0.17007593402541168,
        0.16954222411085793,
        0.16989818931682316,
        0.1668956053683922,
        0.346048650748015,
        0.3626827316588751,
        0.403376895456233,
        0.3736608351407872,
    ]
    a = np.array([-1, -1, 1, 1, -1, -1, 1, 1], dtype=float)
    b = np.array([-1, -1, -1, -1, 1, 1, 1, 1], dtype=float)
    exog = np.column_stack([np.ones(8), a, b, a * b])
    result = box_cox_profile(mu, exog)
    assert result.lambda_hat < -1.99
    assert "edge of the search range" in result.note and math.isinf(result.ci_low)


def test_montgomerys_interval_counts_the_residual_degrees_of_freedom() -> None:
    """A helper's review: the likelihood-ratio interval counts all n runs, so with few
    residual degrees of freedom it is narrow (a response surface's MU, 7 of them, read 'the
    log fits better' though Montgomery's interval held λ = 1). Montgomery's interval (section
    15.1.1) is computed too: at its ends SSE(λ) = SSE(λ̂) (1 + t²(α/2, ν)/ν), by statsmodels'
    OLS of the scaled transform; it holds the likelihood-ratio interval; and the reading says
    where it holds λ = 1 or 0 that the other leaves out."""
    import dataclasses

    import statsmodels.api as sm

    rng = np.random.default_rng(3)
    x = np.repeat(np.arange(4.0), 3)
    exog = np.column_stack([np.ones(x.size), x, x**2, x**3])  # 12 runs, 8 residual df
    y = np.exp(0.5 * x + rng.normal(0.0, 0.15, x.size))
    result = box_cox_profile(y, exog)
    g = math.exp(np.mean(np.log(y)))

    def sse(lam: float) -> float:
        w = np.log(y) * g if lam == 0.0 else (y**lam - 1.0) / (lam * g ** (lam - 1.0))
        return float(sm.OLS(w, exog).fit().ssr)

    nu = result.df_resid
    assert nu == 8.0
    t = stats.t.ppf(0.975, nu)
    for end in (result.ci_low_df, result.ci_high_df):
        assert math.isfinite(end)
        assert sse(end) == pytest.approx(sse(result.lambda_hat) * (1.0 + t * t / nu), rel=1e-6)
    assert result.ci_low_df < result.ci_low < result.ci_high < result.ci_high_df
    row = result.row()
    assert (row["ci_low_df"], row["ci_high_df"]) == (result.ci_low_df, result.ci_high_df)
    # λ = 0 inside the wider interval only: the reading says the scale is not settled
    only_df = dataclasses.replace(
        result, lambda_hat=0.6, ci_low=0.2, ci_high=1.0, ci_low_df=-0.1, ci_high_df=1.2
    )
    assert only_df.reading.startswith("λ = 1 lies within the 95 % interval")
    assert only_df.reading.endswith(
        "; but with 8 residual degrees of freedom, Montgomery's wider interval (-0.10 to "
        "1.20) also holds λ = 0, so the data do not settle the scale"
    )
    same = dataclasses.replace(only_df, ci_low_df=0.1, ci_high_df=0.9)
    assert "Montgomery" not in same.reading


def test_the_profile_without_the_unusual_runs_says_whether_the_reading_holds() -> None:
    """One run can carry the reading (the quick paper study's MU: λ̂ -1.17, and -0.09 with
    both 1 and 0 in the interval without its one unusual run; a DoE review): the runs whose
    standardized residual is beyond 2 under the model are left out of a second profile,
    named with their residuals, and the result says whether the reading holds without
    them."""
    summary, factors = _factorial_summary()
    summary["test"] = np.arange(1, len(summary) + 1)
    # V with the same spread in every cell (-d, 0, +d over its replicates): every
    # standardized residual is 1.22, none beyond 2, so there is no second profile
    v = 3e-9 * (summary["WP"] / 1e-15) ** 0.9 * np.where(summary["A"] == 20.0, 0.5, 1.0)
    even = summary.assign(V=v + 1e-10 * (summary["replicate"] - 1))
    z = analysis.residuals(even, factors, "V")["std_residual"].abs()
    assert (z < 2).all() and box_cox(even, factors, "V").without_unusual == ""
    planted = even.copy()
    planted.loc[4, "V"] += 1e-9  # one run far off its cell
    planted.loc[0, "status"] = "failed"  # and one failed: the residuals' rows are the others
    usable = planted[planted["status"] == "ok"]
    z = analysis.residuals(planted, factors, "V")["std_residual"].to_numpy()
    large = np.abs(z) > 2
    tests = list(usable.loc[large, "test"])
    assert 5 in tests and 1 not in tests
    result = box_cox(planted, factors, "V")
    alone = box_cox(planted[~planted["test"].isin(tests)], factors, "V", unusual=None)
    assert alone.n == len(planted) - 1 - len(tests)
    assert box_cox(planted, factors, "V", unusual=None).without_unusual == ""
    text = result.without_unusual
    reps = list(usable.loc[large, "replicate"])  # named too: the summary has replicates
    named = [
        f"test {t}, replicate {r} (standardized residual {zi:+.2f})"
        for t, r, zi in zip(tests, reps, z[large], strict=True)
    ]
    assert text.startswith("without " + " and ".join(named) + ": ")
    assert f"λ̂ = {alone.lambda_hat:.2f}" in text and alone.reading.split(";")[0] in text
    # the planted run moved λ off 1 (the data point to 1.5); without it λ = 1 is back inside
    assert not result.contains(1.0) and alone.contains(1.0)
    them = "that run" if len(tests) == 1 else "those runs"
    assert text.endswith(f"so the reading of all the runs rests on {them}")
    assert box_cox_table({"V": result})["without_unusual"].item() == text
    # the second profile itself, which the Box-Cox figure draws dashed beside the first,
    # shifted to its maximum (a figures review: the figure had not shown that the reading
    # rests on a run)
    assert result.without is not None
    pd.testing.assert_frame_equal(result.without.profile, alone.profile)
    assert result.without_runs == "; ".join(
        f"test {t}, replicate {r}" for t, r in zip(tests, reps, strict=True)
    )
    # one replicate a test: "tests 5, 9" (not "test 5; test 9"); a summary without test
    # numbers: "a run" (a diff review found a KeyError there)
    from brakeca._console import tests_named

    single = planted.assign(replicate=0)  # every run its own test
    assert box_cox(single, factors, "V").without_runs == tests_named(tests)
    bare = single.drop(columns="test")
    assert box_cox(bare, factors, "V").without_runs == "; ".join(["a run"] * len(tests))
    from brakeca.plotting import plot_box_cox

    ax = plot_box_cox({"V": result}).axes[0]
    dashed = [
        line for line in ax.lines if line.get_linestyle() == "--" and line.get_label()[0] != "_"
    ]
    assert len(dashed) == 1 and dashed[0].get_label().startswith(f"without {result.without_runs}")
    solid = ax.lines[0].get_ydata()
    assert np.max(dashed[0].get_ydata()) == pytest.approx(np.max(solid), rel=1e-12)
    np.testing.assert_allclose(
        np.diff(dashed[0].get_ydata()), np.diff(alone.profile["log_likelihood"]), rtol=1e-9
    )


def test_the_second_profile_keeps_the_model_and_the_rows_by_position() -> None:
    """A review of the check: the second profile is the same model's (a reduced model is not
    reduced again, and a model the runs left cannot estimate gets no second profile, where a
    factor had been dropped without a word); runs are left out by position (a summary's
    index labels may repeat: all runs of a label had been dropped); and the reading holds
    only where it points to the same power."""
    from brakeca.boxcox import BoxCox, _without_text

    summary, factors = _factorial_summary()
    summary["test"] = np.arange(1, len(summary) + 1)
    v = 3e-9 * (summary["WP"] / 1e-15) ** 0.9 * np.where(summary["A"] == 20.0, 0.5, 1.0)
    planted = summary.assign(V=v + 1e-10 * (summary["replicate"] - 1))
    planted.loc[4, "V"] += 1e-9  # unusual runs in test 5's cell
    first = box_cox(planted, factors, "V")
    assert "test 5, replicate 1" in first.without_unusual
    assert "λ̂ = " in first.without_unusual  # a second profile
    repeated = planted.set_axis([0, 1] * (len(planted) // 2))  # labels that repeat
    assert box_cox(repeated, factors, "V").without_unusual == first.without_unusual
    # two replicates a cell: a cell's two runs are flagged together, and without them the
    # cell is empty: the same model cannot be fitted
    pairs = planted[planted["replicate"] < 2].reset_index(drop=True)
    z = analysis.residuals(pairs, factors, "V")["std_residual"].abs()
    assert z.nlargest(2).iloc[1] == pytest.approx(z.max())  # the pair of test 5's cell
    text = box_cox(pairs, factors, "V", unusual=float(z.max()) * 0.999).without_unusual
    assert "the runs left cannot estimate the same model" in text, text
    # the verdict: the same inside-or-not of 1 and 0, and the same power pointed to

    def made(lam: float, low: float, high: float) -> BoxCox:
        return BoxCox("V", 24, 9.0, "m", lam, low, high, round(2 * lam) / 2, 0.95, pd.DataFrame())

    minus_one = made(-1.1, -1.6, -0.6)
    assert _without_text(minus_one, made(-0.9, -1.3, -0.6), "t", 1).endswith("the reading holds")
    assert _without_text(minus_one, made(1.6, 1.3, 1.9), "t", 1).endswith(
        "so the reading of all the runs rests on that run"
    )
    # a power no multiple of 0.5 stands for, pointed to by both: the reading holds where the
    # second λ̂ lies within the first interval (-0.21 against -0.22 had been "rests on":
    # a review of a replicated study), and not where it lies outside it
    near = made(-0.21, -0.32, -0.08)
    assert _without_text(near, made(-0.22, -0.35, -0.08), "t", 1).endswith("the reading holds")
    assert _without_text(near, made(-0.4, -0.45, -0.35), "t", 1).endswith(
        "so the reading of all the runs rests on that run"
    )
