"""Tests of brakeca.analysis.level_coefficients: the coefficients of a general factorial at
every level (Minitab's "Coefficients" table and regression equation), against statsmodels'
sum-to-zero coding, hand-computed level means and the ANOVA's fitted values.

References
----------
Wahlström (2016), doi:10.1155/2016/8181260, Tables 1-2 (the 2 x 3 x 2 x 2 design).
D. C. Montgomery, Design and Analysis of Experiments, 8th ed., section 5.3.
"""

from __future__ import annotations

import itertools
import re

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import (
    CENTER_TERM,
    COEFFICIENT_COLUMNS,
    CONSTANT_TERM,
    Factor,
    analyze,
    anova,
    level_coefficients,
    residuals,
    save_tables,
    tukey_grouping,
)

S = Factor("S", (0.0, 1.0), "-", "Secondary plateaus removed", ("-", "+"))
WP = Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", "Specific wear rate", ("-", "0", "+"))
A = Factor("A", (10.0, 20.0), "%", "Metal fibre area fraction", ("-", "+"))
FACTORS = (S, WP, A)


def _runs(replicates: int = 2, seed: int = 3) -> pd.DataFrame:
    """A 2 x 3 x 2 design with a response of main effects, an S x WP interaction and noise."""
    rng = np.random.default_rng(seed)
    rows = []
    for test, (a, wp, s) in enumerate(itertools.product(range(2), range(3), range(2)), start=1):
        for r in range(replicates):
            mu = 0.4 + 0.02 * s + (-0.01, 0.0, 0.03)[wp] + 0.015 * a + 0.01 * s * (wp == 2)
            rows.append(
                {
                    "test": test,
                    "replicate": r,
                    "S": S.levels[s],
                    "WP": WP.levels[wp],
                    "A": A.levels[a],
                    "MU": mu + 0.004 * rng.standard_normal(),
                    "status": "ok",
                }
            )
    return pd.DataFrame(rows)


def _statsmodels_fit(runs: pd.DataFrame, formula: str):
    from statsmodels.formula.api import ols

    return ols(formula, data=runs).fit()


def test_the_estimated_levels_are_statsmodels_sum_coded_coefficients() -> None:
    """Every level but each factor's last is a column of sum-to-zero coding (statsmodels'
    ``Sum`` contrast, Minitab's coding of a general factorial): the coefficients, their
    standard errors, t and p agree with statsmodels' fit of the same model."""
    runs = _runs()
    table = level_coefficients(runs, FACTORS, "MU")
    assert list(table.columns) == list(COEFFICIENT_COLUMNS)
    terms = "C(S, Sum) + C(WP, Sum) + C(A, Sum)"
    pairs = "C(S, Sum):C(WP, Sum) + C(S, Sum):C(A, Sum) + C(WP, Sum):C(A, Sum)"
    fit = _statsmodels_fit(runs, f"MU ~ {terms} + {pairs}")
    estimated = table[~table["derived"]]
    assert len(estimated) == len(fit.params)  # 1 + 1 + 2 + 1 + 2 + 1 + 2 columns
    # statsmodels orders its columns as the model's terms; in this design's interactions
    # (each with a two-level factor) its order of the cells is the table's (a 3 x 3
    # interaction's cells are matched by name in the next test)
    np.testing.assert_allclose(estimated["coefficient"], fit.params.to_numpy(), rtol=1e-10)
    np.testing.assert_allclose(estimated["se"], fit.bse.to_numpy(), rtol=1e-10)
    np.testing.assert_allclose(estimated["t"], fit.tvalues.to_numpy(), rtol=1e-10)
    np.testing.assert_allclose(estimated["p_value"], fit.pvalues.to_numpy(), rtol=1e-8)
    assert table.attrs["df_resid"] == fit.df_resid
    assert table.attrs["formula"] == "MU ~ S + WP + A + S:WP + S:A + WP:A"


def test_a_derived_level_is_minus_the_sum_of_the_others_with_its_own_error() -> None:
    """The level Minitab leaves out is fixed by the others (the coefficients of a term add
    up to zero over each of its factors' levels); its standard error is that of the linear
    combination, as statsmodels' t test of it gives."""
    runs = _runs()
    table = level_coefficients(runs, FACTORS, "MU")
    wp = table[table["term"] == "WP"]
    assert list(wp["level"]) == ["-", "0", "+"] and list(wp["derived"]) == [False, False, True]
    assert wp["coefficient"].sum() == pytest.approx(0.0, abs=1e-14)
    fit = _statsmodels_fit(
        runs, "MU ~ C(S, Sum) * C(WP, Sum) + C(S, Sum):C(A, Sum) + C(WP, Sum):C(A, Sum) + C(A, Sum)"
    )
    names = list(fit.params.index)
    contrast = np.zeros(len(names))
    for name in names:
        if name.startswith("C(WP, Sum)[S.") and ":" not in name:
            contrast[names.index(name)] = -1.0
    test = fit.t_test(contrast)
    last = wp.iloc[2]
    assert last["coefficient"] == pytest.approx(float(test.effect[0]), rel=1e-10)
    assert last["se"] == pytest.approx(float(test.sd[0, 0]), rel=1e-10)
    assert np.isnan(last["vif"]) and not np.isnan(wp.iloc[0]["vif"])
    # an interaction's cells add up to zero along each factor
    cells = table[table["term"] == "S:WP"]
    grid = cells["coefficient"].to_numpy().reshape(2, 3)
    np.testing.assert_allclose(grid.sum(axis=0), 0.0, atol=1e-14)
    np.testing.assert_allclose(grid.sum(axis=1), 0.0, atol=1e-14)
    assert list(cells["level"]) == ["-, -", "-, 0", "-, +", "+, -", "+, 0", "+, +"]
    assert list(cells["derived"]) == [False, False, True, True, True, True]


def test_in_a_balanced_design_a_level_s_coefficient_is_its_mean_less_the_grand_mean() -> None:
    runs = _runs()
    table = level_coefficients(runs, FACTORS, "MU").set_index(["term", "level"])
    grand = runs["MU"].mean()
    assert table.loc[(CONSTANT_TERM, ""), "coefficient"] == pytest.approx(grand, rel=1e-12)
    for factor in FACTORS:
        for value, label in zip(factor.levels, factor.labels or (), strict=True):
            mean = runs.loc[np.isclose(runs[factor.name], value, rtol=1e-9, atol=0.0), "MU"].mean()
            got = table.loc[(factor.name, label), "coefficient"]
            assert got == pytest.approx(mean - grand, abs=1e-13)


def test_the_regression_equation_gives_the_anova_s_fitted_values() -> None:
    """The constant plus each term's coefficient at a run's levels is the model's fitted
    value of the run (residuals()' of the same model); the equation's text lists every
    level, each to 4 significant digits."""
    runs = _runs()
    table = level_coefficients(runs, FACTORS, "MU")
    rows = zip(table["term"], table["level"], table["coefficient"], strict=True)
    coef = {(t, lv): c for t, lv, c in rows}
    labels = {f.name: dict(zip(f.levels, f.labels or (), strict=True)) for f in FACTORS}
    fitted = []
    for _, run in runs.iterrows():
        value = coef[(CONSTANT_TERM, "")]
        for term in ("S", "WP", "A", "S:WP", "S:A", "WP:A"):
            level = ", ".join(labels[name][run[name]] for name in term.split(":"))
            value += coef[(term, level)]
        fitted.append(value)
    expected = residuals(runs, FACTORS, "MU")["fitted"].to_numpy()
    np.testing.assert_allclose(fitted, expected, rtol=1e-12)
    equation = table.attrs["equation"]
    assert equation.startswith(f"MU = {coef[(CONSTANT_TERM, '')]:.4g} ")
    assert equation.count("[") == len(table) - 1  # every level of every term, named once
    first = re.search(r" ([+-]) (\S+) S\[-\]", equation)
    assert first is not None
    assert float(first.group(1) + first.group(2)) == pytest.approx(coef[("S", "-")], rel=1e-3)


def test_p_values_match_the_anova_for_one_degree_of_freedom_terms() -> None:
    """A two-level factor's coefficient has one column: its t squared is the ANOVA's F of
    the factor, and its p the same (a balanced design, where Type II is Type III)."""
    runs = _runs()
    table = level_coefficients(runs, FACTORS, "MU").set_index(["term", "level"])
    rows = anova(runs, FACTORS, "MU").set_index("term")
    for term, level in (("S", "-"), ("A", "-"), ("S:A", "-, -")):
        assert table.loc[(term, level), "t"] ** 2 == pytest.approx(rows.loc[term, "F"], rel=1e-9)
        assert table.loc[(term, level), "p_value"] == pytest.approx(
            rows.loc[term, "p_value"], rel=1e-7
        )
    assert table["significant"].equals(table["p_value"] < 0.05)


def test_the_model_is_the_anova_s_also_reduced_or_chosen() -> None:
    runs = _runs()
    reduced = level_coefficients(runs, FACTORS, "MU", alpha_to_remove=0.1)
    kept = [t for t in anova(runs, FACTORS, "MU", alpha_to_remove=0.1)["term"] if t != "Residual"]
    assert list(dict.fromkeys(reduced["term"]))[1:] == kept
    mains = level_coefficients(runs, FACTORS, "MU", interactions=False)
    assert list(dict.fromkeys(mains["term"])) == [CONSTANT_TERM, "S", "WP", "A"]
    chosen = level_coefficients(runs, FACTORS, "MU", interactions=["S", "WP", "S*WP"])
    assert list(dict.fromkeys(chosen["term"])) == [CONSTANT_TERM, "S", "WP", "S:WP"]


def test_a_saturated_model_has_coefficients_without_errors() -> None:
    """One run per cell and every interaction: no residual, as Minitab's '*'."""
    runs = _runs(replicates=1)
    every = ["S", "WP", "A", "S*WP", "S*A", "WP*A", "S*WP*A"]
    table = level_coefficients(runs, FACTORS, "MU", interactions=every)
    assert len(table) == 1 + 2 + 3 + 2 + 6 + 4 + 6 + 12
    assert table["coefficient"].notna().all()
    assert table["se"].isna().all() and table["p_value"].isna().all()
    assert not table["significant"].any()
    assert "no residual degrees of freedom" in table.attrs["note"]


def test_an_empty_cell_gives_an_empty_table_that_says_why() -> None:
    runs = _runs()
    runs = runs[~(np.isclose(runs["S"], 1.0) & np.isclose(runs["WP"], 1e-13, rtol=1e-9, atol=0.0))]
    table = level_coefficients(runs, FACTORS, "MU")
    assert table.empty and list(table.columns) == list(COEFFICIENT_COLUMNS)
    assert "rank-deficient" in table.attrs["note"]


def test_centre_points_add_minitab_s_ct_pt_row() -> None:
    """Centre points of a two-level design: their mean less the constant, with the pure
    error of the centre points in the residual."""
    s2 = Factor("S", (0.0, 1.0))
    a2 = Factor("A", (10.0, 20.0))
    rows = [
        {"S": s, "A": a, "MU": 0.4 + 0.02 * (s > 0) + 0.03 * (a > 10) + e, "status": "ok"}
        for (s, a), e in zip(
            itertools.product((0.0, 1.0), (10.0, 20.0)),
            (0.001, -0.002, 0.0015, -0.0005),
            strict=True,
        )
    ]
    rows += [{"S": 0.5, "A": 15.0, "MU": m, "status": "ok"} for m in (0.43, 0.431, 0.428)]
    runs = pd.DataFrame(rows)
    table = level_coefficients(runs, [s2, a2], "MU").set_index("term")
    constant = table.loc[CONSTANT_TERM, "coefficient"]
    assert table.loc[CENTER_TERM, "coefficient"] == pytest.approx(
        np.mean([0.43, 0.431, 0.428]) - constant, rel=1e-12
    )
    assert (
        table.attrs["df_resid"]
        == anova(runs, [s2, a2], "MU").set_index("term").loc["Residual", "df"]
    )
    # Minitab's VIFs with centre points: of the model matrix with their rows and Ct Pt,
    # here of an unbalanced cube (its first run twice), where they differ from the cube's
    from statsmodels.stats.outliers_influence import variance_inflation_factor

    runs = pd.concat([runs.iloc[[0]].assign(MU=0.402), runs], ignore_index=True)
    table = level_coefficients(runs, [s2, a2], "MU").set_index("term")
    assert list(table.index) == [CONSTANT_TERM, *"SSAA", *["S:A"] * 4, CENTER_TERM]
    s_code = np.where(runs["S"] == 0.0, 1.0, np.where(runs["S"] == 1.0, -1.0, 0.0))
    a_code = np.where(runs["A"] == 10.0, 1.0, np.where(runs["A"] == 20.0, -1.0, 0.0))
    centre = (runs["S"] == 0.5).to_numpy(dtype=float)
    exog = np.column_stack([np.ones(len(runs)), s_code, a_code, s_code * a_code, centre])
    expected = [variance_inflation_factor(exog, j) for j in range(1, 5)]
    got = [table["vif"].iloc[k] for k in (1, 3, 5)] + [table.loc[CENTER_TERM, "vif"]]
    np.testing.assert_allclose(got, expected, rtol=1e-10)
    assert not np.allclose(expected, 1.0)


def test_bad_alpha_is_named() -> None:
    with pytest.raises(ValueError, match="alpha"):
        level_coefficients(_runs(), FACTORS, "MU", alpha=1.5)


def test_analyze_gives_them_and_save_tables_writes_them_for_a_general_factorial(tmp_path) -> None:
    """The paper's kind of design (a factor of three levels) has no two-level effects
    table: its coefficients are written instead; a two-level design's coefficients are in
    its effects table, so no coefficients file is written (an earlier one is removed)."""
    runs = _runs()
    result = analyze(runs, FACTORS, ["MU"])
    pd.testing.assert_frame_equal(
        result["MU"].coefficients, level_coefficients(runs, FACTORS, "MU")
    )
    written = {p.name for p in save_tables(result, tmp_path)}
    assert "coefficients_MU.csv" in written and "effects_MU.csv" not in written
    back = pd.read_csv(tmp_path / "coefficients_MU.csv", keep_default_na=False)
    assert list(back.columns) == list(COEFFICIENT_COLUMNS)
    two_level = runs[~np.isclose(runs["WP"], 1e-14, rtol=1e-9, atol=0.0)]
    factors = (S, Factor("WP", (1e-15, 1e-13)), A)
    result = analyze(two_level, factors, ["MU"])
    assert not result["MU"].effects.empty
    written = {p.name for p in save_tables(result, tmp_path)}
    assert "coefficients_MU.csv" not in written and "effects_MU.csv" in written
    assert not (tmp_path / "coefficients_MU.csv").exists()


def test_a_three_by_three_interaction_matches_statsmodels_cell_by_cell() -> None:
    """patsy varies an interaction's first factor fastest, the table its last: the cells
    are matched by their levels' names, estimated and derived alike (the derived ones by
    statsmodels' t test of minus the sum of the others)."""
    b = Factor("P", (1.0, 2.0, 3.0), labels=("b1", "b2", "b3"))
    c = Factor("Q", (1.0, 2.0, 3.0), labels=("c1", "c2", "c3"))
    rng = np.random.default_rng(11)
    runs = pd.DataFrame(
        [
            {"P": float(i), "Q": float(j), "y": 0.1 * i * j + rng.normal(0, 0.01), "status": "ok"}
            for i, j in itertools.product((1, 2, 3), (1, 2, 3))
            for _ in range(2)
        ]
    )
    runs = runs.drop(index=[0, 7]).reset_index(drop=True)  # unbalanced too
    table = level_coefficients(runs, [b, c], "y")
    fit = _statsmodels_fit(runs, "y ~ C(P, Sum) * C(Q, Sum)")
    names = list(fit.params.index)

    def contrast(i: int, j: int) -> np.ndarray:
        """The cell (P level i, Q level j) as a combination of patsy's columns."""
        out = np.zeros(len(names))
        for ii in range(2):
            for jj in range(2):
                weight = (1.0 if i == ii else -1.0 if i == 2 else 0.0) * (
                    1.0 if j == jj else -1.0 if j == 2 else 0.0
                )
                name = f"C(P, Sum)[S.{ii + 1}.0]:C(Q, Sum)[S.{jj + 1}.0]"
                out[names.index(name)] += weight
        return out

    cells = table[table["term"] == "P:Q"].set_index("level")
    assert len(cells) == 9
    for i, j in itertools.product(range(3), range(3)):
        test = fit.t_test(contrast(i, j))
        row = cells.loc[f"b{i + 1}, c{j + 1}"]
        assert row["derived"] == (i == 2 or j == 2)
        assert row["coefficient"] == pytest.approx(float(test.effect[0]), rel=1e-9, abs=1e-14)
        assert row["se"] == pytest.approx(float(test.sd[0, 0]), rel=1e-9)


def test_a_constant_response_has_no_t_or_p() -> None:
    """Its coefficients but the constant are zero to round-off (4.6e-18 had been called
    significant, t infinite: a review); a varying response the model fits to round-off keeps
    its large t, as the ANOVA its large F."""
    runs = _runs().assign(MU=0.3)
    table = level_coefficients(runs, FACTORS, "MU")
    assert table["t"].isna().all() and not table["significant"].any()  # the constant's too
    assert table.attrs["note"] == "response is constant: no t or p"
    exact = _runs().assign(MU=lambda d: 0.3 + 0.1 * d["A"] / 20.0)  # fitted to round-off
    table = level_coefficients(exact, FACTORS, "MU", interactions=False).set_index("term")
    assert (table.loc["A", "t"].abs() > 1e10).all() and table.loc["A", "significant"].all()


# --- Tukey's pairwise comparisons ------------------------------------------------------------


def test_one_factor_s_comparisons_are_statsmodels_tukey_hsd() -> None:
    """With WP alone in the model the least-squares means are the level means and the
    residual the one-way ANOVA's: the comparisons equal statsmodels' pairwise_tukeyhsd
    (differences, standard errors, adjusted p and simultaneous intervals), unbalanced too."""
    from statsmodels.stats.multicomp import pairwise_tukeyhsd

    from brakeca.analysis import COMPARISON_COLUMNS, level_comparisons

    runs = _runs().drop(index=[0, 5, 13]).reset_index(drop=True)
    table = level_comparisons(runs, [WP], "MU", interactions=False)
    assert list(table.columns) == list(COMPARISON_COLUMNS)
    groups = runs["WP"].map(dict(zip(WP.levels, "abc", strict=True)))
    hsd = pairwise_tukeyhsd(runs["MU"], groups, alpha=0.05)
    assert [(a, b) for a, b in zip(table["level_a"], table["level_b"], strict=True)] == [
        ("-", "0"),
        ("-", "+"),
        ("0", "+"),
    ]
    np.testing.assert_allclose(table["difference"], hsd.meandiffs, rtol=1e-10)
    np.testing.assert_allclose(table["se"] * np.sqrt(2.0), hsd.std_pairs * 2.0, rtol=1e-10)
    np.testing.assert_allclose(table["p_adjusted"], hsd.pvalues, rtol=1e-4, atol=1e-12)
    np.testing.assert_allclose(table[["ci_low", "ci_high"]], hsd.confint, rtol=1e-6)
    assert list(table["significant"]) == list(hsd.reject)
    assert table.attrs["method"] == "Tukey" and table.attrs["df_resid"] == len(runs) - 3
    # each level's usable runs: 8 at every level less the three rows dropped (WP 0, -, -)
    labels = dict(zip(WP.levels, WP.labels, strict=True))  # type: ignore[arg-type]
    assert dict(runs["WP"].map(labels).value_counts()) == {"-": 6, "0": 7, "+": 8}
    assert list(table["n_a"]) == [6, 6, 7] and list(table["n_b"]) == [7, 8, 8]


def test_in_a_factorial_model_the_comparisons_are_of_least_squares_means() -> None:
    """In the whole model the means are the constant plus the level's coefficient (the
    level means in a balanced design), the standard error of a difference from the model's
    residual, sqrt(2 MSE / n per level) when balanced; q is the studentized range and p its
    tail over the factor's three levels; a significant interaction is named."""
    from scipy import stats

    from brakeca.analysis import level_comparisons

    runs = _runs()
    # a clear S x WP interaction: 0.03 more at S+ and WP+
    both = np.isclose(runs["S"], 1.0) & np.isclose(runs["WP"], 1e-13, rtol=1e-9, atol=0.0)
    runs.loc[both, "MU"] += 0.03
    table = level_comparisons(runs, FACTORS, "MU")
    coefficients = level_coefficients(runs, FACTORS, "MU").set_index(["term", "level"])
    constant = coefficients.loc[(CONSTANT_TERM, ""), "coefficient"]
    for _, row in table.iterrows():
        for side in ("a", "b"):
            level = row[f"level_{side}"]
            assert row[f"mean_{side}"] == pytest.approx(
                constant + coefficients.loc[("WP", level), "coefficient"], rel=1e-12
            )
            value = WP.levels[WP.labels.index(level)]  # type: ignore[union-attr]
            at = np.isclose(runs["WP"], value, rtol=1e-9, atol=0.0)
            assert row[f"mean_{side}"] == pytest.approx(runs.loc[at, "MU"].mean(), rel=1e-12)
    residual = anova(runs, FACTORS, "MU").set_index("term").loc["Residual"]
    se = np.sqrt(2.0 * residual["mean_sq"] / (len(runs) / 3))
    np.testing.assert_allclose(table["se"], se, rtol=1e-10)
    q = np.abs(table["difference"]) / table["se"] * np.sqrt(2.0)
    np.testing.assert_allclose(table["q"], q, rtol=1e-12)
    p = stats.studentized_range.sf(q, 3, residual["df"])
    np.testing.assert_allclose(table["p_adjusted"], p, rtol=1e-12)
    half = stats.studentized_range.ppf(0.95, 3, residual["df"]) / np.sqrt(2.0) * se
    np.testing.assert_allclose(table["ci_high"] - table["difference"], half, rtol=1e-10)
    assert "WP is in a significant interaction (S:WP)" in table.attrs["note"]
    assert level_comparisons(runs, FACTORS, "MU", interactions=False).attrs["note"] == ""


def test_comparisons_are_given_for_factors_of_three_levels_or_more_only() -> None:
    from brakeca.analysis import level_comparisons

    runs = _runs()
    two_level = runs[~np.isclose(runs["WP"], 1e-14, rtol=1e-9, atol=0.0)]
    table = level_comparisons(two_level, (S, Factor("WP", (1e-15, 1e-13)), A), "MU")
    assert table.empty and table.attrs["note"] == ""
    with pytest.raises(
        ValueError, match=r"confidence: expected a level above 0 and below 1 \(0.95"
    ):
        level_comparisons(runs, FACTORS, "MU", confidence=95)
    saturated = level_comparisons(
        _runs(replicates=1), FACTORS, "MU", interactions=["S", "WP", "A", "S|WP|A"]
    )
    assert saturated["difference"].notna().all() and saturated["p_adjusted"].isna().all()
    assert "no residual degrees of freedom" in saturated.attrs["note"]


def test_analyze_and_save_tables_give_the_comparisons(tmp_path) -> None:
    from brakeca.analysis import level_comparisons

    runs = _runs()
    result = analyze(runs, FACTORS, ["MU"])
    pd.testing.assert_frame_equal(result["MU"].comparisons, level_comparisons(runs, FACTORS, "MU"))
    written = {p.name for p in save_tables(result, tmp_path)}
    assert {"comparisons_MU.csv", "grouping_MU.csv"} <= written
    # the grouping table: each level's usable runs, least-squares mean and letters
    grouping = pd.read_csv(tmp_path / "grouping_MU.csv", keep_default_na=False)
    assert list(grouping.columns) == ["factor", "level", "n", "mean", "grouping"]
    assert list(grouping["n"]) == [8, 8, 8]
    expected = tukey_grouping(result["MU"].comparisons)
    assert list(grouping["level"]) == list(expected["level"]) == ["+", "0", "-"]
    assert list(grouping["grouping"]) == list(expected["grouping"])
    np.testing.assert_allclose(grouping["mean"], expected["mean"], rtol=1e-15)
    two_level = runs[~np.isclose(runs["WP"], 1e-14, rtol=1e-9, atol=0.0)]
    result = analyze(two_level, (S, Factor("WP", (1e-15, 1e-13)), A), ["MU"])
    assert result["MU"].comparisons.empty
    save_tables(result, tmp_path)
    for stem in ("comparisons", "grouping"):  # the earlier analysis's, removed
        assert not (tmp_path / f"{stem}_MU.csv").exists()


def test_comparisons_say_what_the_model_leaves_out_and_agree_with_the_anova_on_exact_fits() -> None:
    """A factor eliminated from the model is named, not silently dropped; a fit exact to
    round-off calls its differences significant, as its F (a constant response has no q or
    p); two interactions are both named (a review)."""
    from brakeca.analysis import level_comparisons

    runs = _runs()
    flat = runs.assign(MU=lambda d: 0.4 + 0.02 * d["S"] + 0.01 * d["A"] / 10.0)
    flat["MU"] += 1e-3 * np.random.default_rng(5).standard_normal(len(flat))
    reduced = level_comparisons(flat, FACTORS, "MU", alpha_to_remove=0.05)
    assert reduced.empty and reduced.attrs["note"] == "WP is not in the model"
    exact = runs.copy()
    exact["MU"] = 0.1 * np.searchsorted(WP.levels, exact["WP"].to_numpy()) + 0.05 * exact["S"]
    table = level_comparisons(exact, FACTORS, "MU", interactions=False)  # to round-off
    assert (table["q"] > 1e10).all() and table["significant"].all()
    constant = level_comparisons(runs.assign(MU=0.3), FACTORS, "MU")
    assert constant["p_adjusted"].isna().all() and not constant["significant"].any()
    assert constant.attrs["note"] == "response is constant: no q or p"
    both = runs.copy()
    at = np.isclose(both["WP"], 1e-13, rtol=1e-9, atol=0.0)
    both.loc[at & np.isclose(both["S"], 1.0), "MU"] += 0.03
    both.loc[at & np.isclose(both["A"], 20.0), "MU"] += 0.03
    note = level_comparisons(both, FACTORS, "MU").attrs["note"]
    assert note == (
        "WP is in significant interactions (S:WP, WP:A): its differences change with the "
        "other factors' levels (S and A), and these comparisons average them over the levels "
        "of S and A (the interaction plot shows them level by level)"
    )


def test_unbalanced_comparisons_are_statsmodels_contrasts_of_least_squares_means() -> None:
    """Tukey-Kramer: in an unbalanced factorial model each difference and its standard error
    are those of the contrast of the two levels' least-squares means in statsmodels' fit of
    the same model (Sum coding), q and p Tukey's of them."""
    from scipy import stats

    from brakeca.analysis import level_comparisons

    runs = _runs().drop(index=[0, 3, 4, 9, 17]).reset_index(drop=True)
    table = level_comparisons(runs, FACTORS, "MU")
    fit = _statsmodels_fit(
        runs,
        "MU ~ C(S, Sum) + C(WP, Sum) + C(A, Sum) + C(S, Sum):C(WP, Sum) + C(S, Sum):C(A, Sum)"
        " + C(WP, Sum):C(A, Sum)",
    )
    names = list(fit.params.index)

    def level_effect(i: int) -> np.ndarray:
        """WP's level i as a combination of the columns: its own, or minus both (the last)."""
        out = np.zeros(len(names))
        for j in range(2):
            column = names.index(f"C(WP, Sum)[S.{WP.levels[j]!r}]")
            out[column] = 1.0 if i == j else -1.0 if i == 2 else 0.0
        return out

    assert len(table) == 3
    for _, row in table.iterrows():
        i = WP.labels.index(row["level_a"])  # type: ignore[union-attr]
        j = WP.labels.index(row["level_b"])  # type: ignore[union-attr]
        test = fit.t_test(level_effect(j) - level_effect(i))
        assert row["difference"] == pytest.approx(float(test.effect[0]), rel=1e-9)
        assert row["se"] == pytest.approx(float(test.sd[0, 0]), rel=1e-9)
        q = abs(float(test.tvalue[0, 0])) * np.sqrt(2.0)
        assert row["q"] == pytest.approx(q, rel=1e-9)
        assert row["p_adjusted"] == pytest.approx(
            stats.studentized_range.sf(q, 3, fit.df_resid), rel=1e-9
        )
    # a level without usable runs is said
    failed = runs.copy()
    failed.loc[np.isclose(failed["WP"], 1e-14, rtol=1e-9, atol=0.0), "status"] = "failed"
    table = level_comparisons(failed, FACTORS, "MU")
    assert table.empty
    assert table.attrs["note"] == "WP: 2 of its 3 levels have usable runs, too few to compare"


def _pairs(means: dict[str, float], significant: set[tuple[str, str]]) -> pd.DataFrame:
    """A comparisons table of one factor "F" with these level means and significant pairs."""
    levels = list(means)
    rows = [
        {
            "factor": "F",
            "level_a": a,
            "level_b": b,
            "mean_a": means[a],
            "mean_b": means[b],
            "p_adjusted": 0.01 if (a, b) in significant or (b, a) in significant else 0.5,
            "significant": (a, b) in significant or (b, a) in significant,
        }
        for a, b in itertools.combinations(levels, 2)
    ]
    return pd.DataFrame(rows)


def test_tukey_grouping_gives_each_level_s_runs_where_the_table_has_them() -> None:
    """``n`` comes from ``n_a`` and ``n_b``; a table without them (one written before they
    were added) gives the letters with ``n`` missing."""
    from brakeca.analysis import tukey_grouping

    pairs = _pairs({"a": 3.0, "b": 2.0, "c": 1.0}, {("a", "c")})
    old = tukey_grouping(pairs)
    assert list(old["grouping"]) == ["A", "AB", "B"] and old["n"].isna().all()
    pairs["n_a"] = [4, 4, 5]  # a-b, a-c, b-c
    pairs["n_b"] = [5, 6, 6]
    table = tukey_grouping(pairs)
    assert list(table["n"]) == [4, 5, 6]
    assert list(table["grouping"]) == list(old["grouping"])


def test_tukey_grouping_letters_are_piepho_s_compact_letter_display() -> None:
    """Levels that share a letter do not differ; an overlapping chain of four levels (a
    differs from c and d, b from d) gives A, AB, BC, C, largest mean first; no difference
    gives one letter; none without p values."""
    from brakeca.analysis import tukey_grouping

    means = {"d": 1.0, "c": 2.0, "b": 3.0, "a": 4.0}  # in design order d, c, b, a
    table = tukey_grouping(_pairs(means, {("a", "c"), ("a", "d"), ("b", "d")}))
    assert list(table["level"]) == ["a", "b", "c", "d"]
    assert list(table["grouping"]) == ["A", "AB", "BC", "C"]
    assert list(table["mean"]) == [4.0, 3.0, 2.0, 1.0]
    assert list(tukey_grouping(_pairs(means, set()))["grouping"]) == ["A"] * 4
    every = set(itertools.combinations("abcd", 2))
    assert list(tukey_grouping(_pairs(means, every))["grouping"]) == ["A", "B", "C", "D"]
    # the letters hold what they say: two levels share one exactly when they do not differ
    for pairs in ({("a", "b"), ("c", "d")}, {("a", "d")}, {("a", "c"), ("b", "c")}):
        grouped = tukey_grouping(_pairs(means, pairs))
        letters = dict(zip(grouped["level"], grouped["grouping"], strict=True))
        for x, y in itertools.combinations("abcd", 2):
            share = bool(set(letters[x]) & set(letters[y]))
            assert share == ((x, y) not in pairs and (y, x) not in pairs), (pairs, x, y)
    nan = _pairs(means, set()).assign(p_adjusted=np.nan)
    assert tukey_grouping(nan).empty


def test_tukey_grouping_sweeps_letters_a_level_does_not_need_and_orders_ties() -> None:
    """A review's cases: five levels where insert-and-absorb alone gave L1 the letters ABC
    though AB say all (Piepho's sweep); groups whose largest means tie are lettered by
    their next members (b A, c B, not the order they were made in); a pair without a p
    value (equal means in an exact fit) is not significant, not a reason for no letters."""
    from brakeca.analysis import tukey_grouping

    means = {"L0": 1.0, "L1": 2.0, "L3": 3.0, "L2": 4.0, "L4": 5.0}
    table = tukey_grouping(_pairs(means, {("L0", "L3"), ("L2", "L4"), ("L3", "L4")}))
    letters = dict(zip(table["level"], table["grouping"], strict=True))
    assert letters == {"L4": "A", "L2": "BC", "L3": "B", "L1": "AB", "L0": "AC"}
    means = {"a": 4.0, "b": 3.0, "c": 2.0, "d": 1.0}
    table = tukey_grouping(_pairs(means, {("b", "c"), ("c", "d")}))
    assert list(table["grouping"]) == ["AB", "A", "B", "A"]
    pairs = _pairs(means, {("a", "d")})
    pairs.loc[(pairs["level_a"] == "b") & (pairs["level_b"] == "c"), "p_adjusted"] = np.nan
    assert list(tukey_grouping(pairs)["grouping"]) == ["A", "AB", "AB", "B"]


def test_the_levels_labels_stand_for_are_given_and_the_report_lists_them(tmp_path) -> None:
    """The rows are labelled "-", "0", "+" as Minitab's are by level; what each stands for
    (a Minitab user's review: S's "-" is 0, no removal) is in ``attrs["levels"]`` with the
    units, and the report's caption lists it; a factor without labels is left out."""
    from brakeca.report import _coefficients_table

    bare = Factor("A", (10.0, 20.0), "%")
    table = level_coefficients(_runs(), (S, WP, bare), "MU")
    assert table.attrs["levels"] == {
        "S": {"-": 0.0, "+": 1.0},
        "WP": {"-": 1e-15, "0": 1e-14, "+": 1e-13},
    }
    assert table.attrs["units"] == {"S": "-", "WP": "m^3/(N m)"}
    _, caption, _, _ = _coefficients_table("MU", table)
    assert "The levels: S: - = 0, + = 1; WP: - = 1e-15, 0 = 1e-14, + = 1e-13 [m³/(N·m)]." in (
        caption
    )
    assert "A level's p tests its coefficient against 0 (its least-squares mean" in caption


def test_a_categorical_factor_has_no_level_legend() -> None:
    """A review: a factor with choices had its choices' codes listed as its values."""
    from brakeca.design import Factor as DesignFactor

    fibres = DesignFactor(
        name="A", field="pad.fibre_model", levels=(0, 1), choices=("columns", "field")
    )
    runs = _runs().assign(A=lambda d: (d["A"] > 15).astype(int))
    table = level_coefficients(runs, (S, WP, fibres), "MU")
    assert set(table.attrs["levels"]) == {"S", "WP"}


def test_four_level_comparisons_are_statsmodels_tukey_hsd() -> None:
    """Tukey's critical value takes the factor's k level means: with four levels (six pairs)
    the intervals equal statsmodels' pairwise_tukeyhsd, unbalanced too (every other test
    had three levels, where k and the number of pairs are both 3: a mutation review)."""
    from statsmodels.stats.multicomp import pairwise_tukeyhsd

    from brakeca.analysis import level_comparisons

    rng = np.random.default_rng(7)
    levels = (1.0, 2.0, 3.0, 4.0)
    x = np.repeat(levels, [5, 6, 6, 7])
    runs = pd.DataFrame({"X": x, "MU": 0.30 + 0.02 * x + 0.01 * rng.standard_normal(x.size)})
    runs["status"] = "ok"
    table = level_comparisons(runs, [Factor("X", levels)], "MU", interactions=False)
    hsd = pairwise_tukeyhsd(runs["MU"], runs["X"].astype(str), alpha=0.05)
    assert len(table) == 6
    np.testing.assert_allclose(table["difference"], hsd.meandiffs, rtol=1e-10)
    np.testing.assert_allclose(table[["ci_low", "ci_high"]], hsd.confint, rtol=1e-6)
    np.testing.assert_allclose(table["p_adjusted"], hsd.pvalues, rtol=1e-4, atol=1e-12)
