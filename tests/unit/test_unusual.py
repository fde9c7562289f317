"""The runs a model fits badly (brakeca.analysis.unusual_runs) and the residual table's
influence measures: deleted residuals, Cook's distances and DFITS as statsmodels gives them,
Bonferroni's outlier test, and the ANOVA refitted without the unusual runs. A helper's
review of the paper's study found test 23 an outlier of MU's model (deleted residual 11.0,
Bonferroni p 1e-4) that the report had called a mild flag (standardized residual 2.91, which
cannot exceed sqrt(9) with 9 residual degrees of freedom)."""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import (
    RESIDUAL_COLUMNS,
    UNUSUAL_COLUMNS,
    Factor,
    analyze,
    anova,
    residuals,
    save_tables,
    unusual_runs,
)
from brakeca.report import _unusual_text, in_short

S = Factor("S", (0.0, 1.0), labels=("-", "+"))
WP = Factor("WP", (1e-15, 1e-14, 1e-13), labels=("-", "0", "+"))
A = Factor("A", (10.0, 20.0), labels=("-", "+"))
FACTORS = (S, WP, A)


def _runs(replicates: int = 2, bump: float = 0.0, seed: int = 9) -> pd.DataFrame:
    """A 2 x 3 x 2 design with additive effects, noise, and ``bump`` added to test 5's
    first replicate (with seed 9 and no bump, no run's standardized residual under the
    main effects is beyond +-2)."""
    rng = np.random.default_rng(seed)
    rows = []
    for test, (a, wp, s) in enumerate(itertools.product(range(2), range(3), range(2)), start=1):
        for r in range(replicates):
            mu = 0.3 + 0.02 * s + (0.0, 0.01, 0.03)[wp] + 0.015 * a
            mu += 0.002 * rng.standard_normal() + (bump if (test, r) == (5, 0) else 0.0)
            rows.append(
                {
                    "test": test,
                    "replicate": r,
                    "S": S.levels[s],
                    "WP": WP.levels[wp],
                    "A": A.levels[a],
                    "MU": mu,
                    "status": "ok",
                }
            )
    return pd.DataFrame(rows)


def _influence(runs: pd.DataFrame, formula: str):
    from statsmodels.formula.api import ols

    return ols(formula, data=runs).fit()


def test_the_influence_measures_are_statsmodels_s() -> None:
    """Deleted (externally studentized) residuals, Cook's distances and DFITS equal
    statsmodels' OLSInfluence of the same model, unbalanced too."""
    runs = _runs().drop(index=[3, 16]).reset_index(drop=True)
    table = residuals(runs, FACTORS, "MU")
    assert list(table.columns) == ["test", "replicate", *RESIDUAL_COLUMNS]
    fit = _influence(runs, "MU ~ (C(S) + C(WP) + C(A))**2")
    influence = fit.get_influence()
    np.testing.assert_allclose(table["std_residual"], influence.resid_studentized_internal)
    np.testing.assert_allclose(
        table["deleted_residual"], influence.resid_studentized_external, rtol=1e-9
    )
    np.testing.assert_allclose(table["cooks_distance"], influence.cooks_distance[0], rtol=1e-9)
    np.testing.assert_allclose(table["dfits"], influence.dffits[0], rtol=1e-9)


def test_without_residual_degrees_of_freedom_there_are_no_influence_measures() -> None:
    """A saturated model (one run per cell, every interaction) leaves no residual: the
    measures are NaN, not round-off; one degree of freedom leaves no deleted residual."""
    runs = _runs(replicates=1)
    every = ["S", "WP", "A", "S|WP|A"]
    saturated = residuals(runs, FACTORS, "MU", interactions=every)
    assert saturated.attrs["df_resid"] == 0
    assert saturated[["std_residual", "deleted_residual", "cooks_distance"]].isna().all().all()
    assert unusual_runs(runs, FACTORS, "MU", interactions=every).empty
    one = residuals(runs.iloc[:6], [S, WP], "MU", interactions=False)  # 6 runs, 4 parameters
    assert one.attrs["df_resid"] == 2
    two = residuals(runs.iloc[:5], [S, WP], "MU", interactions=False)
    assert two.attrs["df_resid"] == 1
    assert two["deleted_residual"].isna().all()
    assert two["std_residual"].notna().sum() > 0


def test_an_outlier_is_named_with_bonferroni_s_test_and_the_anova_without_it() -> None:
    """Test 5's first replicate 0.03 off: the only unusual run, its outlier_p statsmodels'
    Bonferroni p, the largest other Cook's distance given, and the refit the ANOVA of the
    runs without it; a design without such a run gives an empty table with the same
    attrs."""
    runs = _runs(bump=0.03)
    table = unusual_runs(runs, FACTORS, "MU", interactions=False)
    assert list(table.columns) == ["test", "replicate", *UNUSUAL_COLUMNS]
    assert list(table["test"]) == [5] and list(table["replicate"]) == [0]
    fit = _influence(runs, "MU ~ C(S) + C(WP) + C(A)")
    outliers = fit.outlier_test()  # student_resid, unadj_p, bonf(p), in the runs' order
    row = outliers.iloc[8]  # test 5, replicate 0
    assert table["deleted_residual"].item() == pytest.approx(row["student_resid"], rel=1e-9)
    assert table["outlier_p"].item() == pytest.approx(row["bonf(p)"], rel=1e-6)
    assert table["outlier_p"].item() < 0.05
    cooks = fit.get_influence().cooks_distance[0]
    assert table.attrs["largest_other_cooks"] == pytest.approx(np.delete(cooks, 8).max())
    assert table.attrs["df_resid"] == len(runs) - 5 and table.attrs["n"] == len(runs)
    without = table.attrs["without"]
    expected = anova(runs.drop(index=8), FACTORS, "MU", interactions=["S", "WP", "A"])
    pd.testing.assert_frame_equal(without, expected, check_exact=False, rtol=1e-12)
    assert table.attrs["without_note"] == ""
    calm = unusual_runs(_runs(), FACTORS, "MU", interactions=False)
    assert calm.empty and calm.attrs["without"] is None
    # with the columns of a table with rows (it had the residuals', without outlier_p, so
    # code written against a study with an outlier failed on one without: a docs review)
    assert list(calm.columns) == list(table.columns)
    with pytest.raises(ValueError, match=r"alpha: "):
        unusual_runs(runs, FACTORS, "MU", alpha=5)


def test_the_refit_keeps_a_reduced_model_s_terms() -> None:
    """A reduced model is refitted with its terms, not reduced again, so only the runs
    change."""
    runs = _runs(bump=0.03)
    reduced = anova(runs, FACTORS, "MU", alpha_to_remove=0.1)
    table = unusual_runs(runs, FACTORS, "MU", alpha_to_remove=0.1)
    assert not table.empty
    kept = [t for t in reduced["term"] if t != "Residual"]
    assert kept != list(anova(runs, FACTORS, "MU")["term"][:-1])  # reduced indeed
    assert [t for t in table.attrs["without"]["term"] if t != "Residual"] == kept


def test_analyze_and_save_tables_give_the_unusual_runs(tmp_path) -> None:
    runs = _runs(bump=0.03)
    result = analyze(runs, FACTORS, ["MU"], max_order=1)
    expected = unusual_runs(runs, FACTORS, "MU", interactions=1)
    pd.testing.assert_frame_equal(result["MU"].unusual, expected)
    save_tables(result, tmp_path)
    written = pd.read_csv(tmp_path / "unusual_MU.csv")
    assert list(written["test"]) == [5]
    save_tables(analyze(_runs(), FACTORS, ["MU"], max_order=1), tmp_path)
    assert not (tmp_path / "unusual_MU.csv").exists()  # the earlier analysis's, removed


def test_the_report_names_the_outlier_and_the_verdicts_that_change() -> None:
    """The report's text under the ANOVA and its "In short": the outlier with its
    Bonferroni p and the residual's ceiling, the largest other Cook's distance, and each
    term whose verdict at 5 % changes without it, with both p values."""
    runs = _runs(bump=0.03)
    frame = residuals(runs, FACTORS, "MU", interactions=False)
    table = unusual_runs(runs, FACTORS, "MU", interactions=False)
    full = anova(runs, FACTORS, "MU", interactions=False)
    text = _unusual_text("MU", frame, table, full)
    assert "test 5, replicate 0 (MU " in text  # (the summary's replicate number)
    assert "is an outlier of this model" in text
    assert "cannot exceed" not in text  # +4.06 does not look mild (the paper's 2.91 of √9 does)
    assert "with no setting run twice" not in text  # (replicated: its setting ran twice)
    # each setting run once: say how to tell a seed's pad from what the model misses (an
    # engineer's read: test 23 was flagged and never explained)
    once = _runs(replicates=1, bump=0.03)
    once_table = unusual_runs(once, FACTORS, "MU", interactions=False)
    assert list(once_table.loc[once_table["outlier_p"] < 0.05, "test"]) == [5]
    once_frame = residuals(once, FACTORS, "MU", interactions=False)
    once_anova = anova(once, FACTORS, "MU", interactions=False)
    once_text = _unusual_text("MU", once_frame, once_table, once_anova)
    advice = (
        "%. With no setting run twice, a seed's unusual pad cannot be told from a behaviour "
        "the model misses: its setting run again with other seeds (the design's replicates) "
        "would tell. "
    )
    assert "so the model does not describe it: without it the residual sum" in once_text
    assert advice in once_text  # a sentence of its own, after the error's fall
    # a setting run twice elsewhere (centre points: pure error) knows the seeds' scatter (a
    # diff review: the sentence was said of a design with centre points run four times)
    centre = once_anova.copy()
    centre.attrs = {**once_anova.attrs, "pure_error_df": 3.0}
    assert "With no setting run twice" not in _unusual_text("MU", once_frame, once_table, centre)
    assert "The largest Cook's distance of the other runs: " in text
    # removing one run lowers the residual sum of squares by e^2 / (1 - h)
    e, h = frame["residual"].to_numpy(), frame["leverage"].to_numpy()
    fall = 100 * e[8] ** 2 / (1 - h[8]) / np.sum(e**2)  # test 5, replicate 0
    said = "without it the residual sum of squares, the error every F test is against, falls by"
    assert f"{said} {fall:.0f} %" in text
    # here every term keeps its verdict (the model's terms are all clear with it)
    assert "Every term keeps its verdict at p < 0.05 without it." in text
    assert text.endswith("tables/residuals_MU.csv and tables/unusual_MU.csv.")
    (line,) = in_short({"MU": full}, residual_tables={"MU": frame}, unusual_tables={"MU": table})
    assert "is an outlier of the model (Bonferroni p < 0.0001), and every term keeps" in line
    # without an outlier (a run beyond +-2 by chance): named, and said not to be one
    mild = table.assign(outlier_p=0.5)
    said = _unusual_text("MU", frame, mild, full)
    assert "It is not an outlier of this model: Bonferroni's outlier test over the 24 runs" in said
    assert "is an outlier" not in said
    (plain,) = in_short({"MU": full}, unusual_tables={"MU": mild})
    assert "outlier" not in plain


def test_the_report_says_which_terms_become_significant_without_the_outlier() -> None:
    """unusual_runs' example: S's p is 0.053 with test 6 and 0.009 without it; the report's
    text and "In short" say S becomes significant, with both p values."""
    factors = [Factor("S", (0.0, 1.0)), Factor("WP", (1.0, 2.0, 3.0))]
    runs = pd.DataFrame(
        {
            "test": range(1, 13),
            "S": [0.0, 1.0] * 6,
            "WP": [1.0, 1.0, 2.0, 2.0, 3.0, 3.0] * 2,
            "MU": [0.301, 0.304, 0.348, 0.357, 0.401, 0.425, 0.3, 0.306, 0.352, 0.351, 0.4, 0.406],
        }
    )
    frame = residuals(runs, factors, "MU", interactions=False)
    table = unusual_runs(runs, factors, "MU", interactions=False)
    full = anova(runs, factors, "MU", interactions=False)
    text = _unusual_text("MU", frame, table, full)
    said = "Without it, at p < 0.05, S (p 0.053 → 0.0087) becomes significant; the other terms"
    assert said in text
    # its standardized residual, 2.68, looks mild: the text says why it cannot be larger
    assert "with 8 residual degrees of freedom a standardized residual cannot exceed √8" in text
    (line,) = in_short({"MU": full}, residual_tables={"MU": frame}, unusual_tables={"MU": table})
    assert "and without it, at p < 0.05, S (p 0.053 → 0.0087) becomes significant" in line


def test_a_run_that_is_the_only_departure_from_an_exact_fit_is_an_outlier() -> None:
    """A review: one run 0.01 off a response the model fits exactly otherwise has r^2 =
    df_resid to round-off, which had made its deleted residual NaN (never an outlier); it
    is infinite now, its Bonferroni p 0."""
    rows = [
        {"S": s, "WP": wp, "A": a, "MU": 0.3 + 0.02 * s + 0.01 * i + 0.015 * a}
        for s, (i, wp), a in itertools.product((0.0, 1.0), enumerate(WP.levels), (10.0, 20.0))
    ]
    runs = pd.DataFrame(rows).assign(test=range(1, 13))
    runs.loc[4, "MU"] += 0.01
    table = unusual_runs(runs, FACTORS, "MU", interactions=False)
    assert list(table["test"]) == [5]
    assert np.isinf(table["deleted_residual"].item()) and table["outlier_p"].item() == 0.0


def test_in_short_names_every_run_the_refit_leaves_out() -> None:
    """A review: the refit leaves out every run beyond +-2, and "In short" had named only
    the outlier among them, crediting it with what the others changed."""
    runs = _runs(bump=0.03)
    frame = residuals(runs, FACTORS, "MU", interactions=False)
    table = unusual_runs(runs, FACTORS, "MU", interactions=False)
    first = pd.DataFrame(table)  # (without attrs: concat compares them, the refit a table)
    first.attrs = {}
    second = first.assign(test=9, replicate=1, outlier_p=0.7, std_residual=-2.1)
    both = pd.concat([first, second], ignore_index=True)
    both.attrs = dict(table.attrs)
    full = anova(runs, FACTORS, "MU", interactions=False)
    (line,) = in_short({"MU": full}, residual_tables={"MU": frame}, unusual_tables={"MU": both})
    assert "test 5, replicate 0 is an outlier of the model (Bonferroni p " in line
    assert "without the unusual runs (test 5, replicate 0 and test 9, replicate 1)" in line


def test_the_report_says_when_no_run_is_unusual() -> None:
    """A review: a response without unusual runs had no word on them; it now says none is
    beyond +-2 and names the largest."""
    frame = residuals(_runs(), FACTORS, "MU", interactions=False)
    top = frame.loc[frame["std_residual"].abs().idxmax()]
    text = _unusual_text("MU", frame)
    assert text == (
        f"No run's standardized residual is beyond ±2 (the largest: "
        f"{top['std_residual']:+.2f}, test {int(top['test'])}, replicate {int(top['replicate'])})."
    )


def test_the_verdicts_without_name_terms_that_gain_and_lose_significance() -> None:
    from brakeca.report import _verdicts_without

    before = pd.DataFrame(
        {"term": ["A", "B", "C", "Residual"], "p_value": [0.2, 0.01, 0.03, np.nan]}
    )
    after = before.assign(p_value=[0.004, 0.3, 0.02, np.nan])
    unusual = pd.DataFrame({"test": [3, 7]})
    unusual.attrs["without"] = after
    assert _verdicts_without(before, unusual) == (
        "without them, at p < 0.05, A (p 0.2 → 0.004) becomes significant and B (p 0.01 → 0.3) "
        "stops being significant; the other terms keep their verdicts"
    )
    unusual.attrs["without"], unusual.attrs["without_note"] = None, "too few runs"
    assert _verdicts_without(before, unusual) == (
        "without them the model cannot be refitted (too few runs)"
    )


def _reads_as_scatter(diagnosed, detail: str, short: str) -> None:
    """The unusual runs' text holds ``detail`` and not "does not describe", and the "In
    short" line ``short``, for ``diagnosed`` (:func:`_diagnosed`'s)."""
    model, frame, table = diagnosed
    text = _unusual_text("MU", frame, table, model)
    assert detail in text and "does not describe" not in text
    (line,) = in_short({"MU": model}, residual_tables={"MU": frame}, unusual_tables={"MU": table})
    assert short in line


def _diagnosed(runs: pd.DataFrame, interactions):
    """MU's ANOVA, residuals and unusual runs under one model of ``runs``."""
    return (
        anova(runs, FACTORS, "MU", interactions=interactions),
        residuals(runs, FACTORS, "MU", interactions=interactions),
        unusual_runs(runs, FACTORS, "MU", interactions=interactions),
    )


def test_outliers_of_a_model_that_fits_every_setting_are_said_to_scatter_at_it() -> None:
    """A DoE review: both replicates of one test were called outliers the model "does not
    describe", where the model fits every setting's mean (no lack of fit is left) and the two
    runs are simply far apart. The report says so; with a lack of fit it keeps the old
    reading."""
    runs = _runs(replicates=2)
    runs.loc[runs["test"] == 5, "MU"] += np.array([0.02, -0.02])
    full, frame, table = _diagnosed(runs, 3)  # every setting's mean: no lack of fit
    assert full.attrs["pure_error_df"] == full.attrs["df_resid"] == 12
    outliers = table.loc[table["outlier_p"] < 0.05]
    assert sorted(outliers["test"]) == [5, 5]
    _reads_as_scatter(
        (full, frame, table),
        "they are every run of test 5, and the model fits each setting's mean",
        ": the runs of test 5, which scatter more than the other settings' runs",
    )
    # one run of three far from the others at its setting: not "every run", still no misfit
    three = _runs(replicates=3)
    three.loc[(three["test"] == 5) & (three["replicate"] == 0), "MU"] += 0.03
    full, frame, table = _diagnosed(three, 3)
    assert list(table.loc[table["outlier_p"] < 0.05, "test"]) == [5]
    text = _unusual_text("MU", frame, table, full)
    assert "distance from the other runs at the same setting, not a misfit" in text
    # a model that leaves a lack of fit, test 5's two runs on either side of its value
    # there: they depart from each other, not from the model (a review of a replicated
    # study: such a pair had been outliers the model "does not describe")
    main, frame, table = _diagnosed(runs, False)
    assert main.attrs["lack_of_fit_df"] > 0
    assert (table["outlier_p"] < 0.05).all() and sorted(table["test"]) == [5, 5]
    _reads_as_scatter(
        (main, frame, table),
        "they are every run of test 5, on either side of the model's value there",
        ": the runs of test 5, on either side of the model's value there",
    )
    # both on one side of it: the model misses them
    apart = _runs(replicates=2)
    apart.loc[apart["test"] == 5, "MU"] += np.array([0.04, 0.03])
    main, frame, table = _diagnosed(apart, False)
    flagged = table.loc[table["outlier_p"] < 0.05]
    assert len(flagged) and (flagged["residual"] > 0).all()
    text = _unusual_text("MU", frame, table, main)
    assert "so the model does not describe" in text and "either side" not in text
