"""Backward elimination of the factorial ANOVA model (``alpha_to_remove``), checked against
the same elimination done by hand with statsmodels: the model's terms, the table of the
model kept, and the residuals and effects that follow it."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pandas as pd
import pytest
from statsmodels.formula.api import ols
from statsmodels.stats.anova import anova_lm

from brakeca import analysis
from brakeca.analysis import Factor

FACTORS = [Factor("A", (0.0, 1.0)), Factor("B", (0.0, 1.0)), Factor("C", (0.0, 1.0))]
CODED = {"A": "x1", "B": "x2", "C": "x3"}


def _runs(effects: dict[str, float], replicates: int = 2, seed: int = 11) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    rows = [
        dict(zip("ABC", code, strict=True))
        for _ in range(replicates)
        for code in itertools.product((0.0, 1.0), repeat=3)
    ]
    d = pd.DataFrame(rows)
    for name, column in CODED.items():
        d[column] = 2.0 * d[name] - 1.0
    d["y"] = 10.0 + rng.normal(0.0, 0.3, len(d))
    for term, size in effects.items():
        d["y"] += size * np.prod([d[CODED[f]] for f in term.split(":")], axis=0)
    d["status"] = "ok"
    return d


def _by_hand(runs: pd.DataFrame, alpha: float, typ: int) -> tuple[list[str], pd.DataFrame]:
    """Backward elimination with statsmodels: mains and two-factor interactions, drop the
    largest p above alpha among the terms no other term contains."""
    terms = ["A", "B", "C", "A:B", "A:C", "B:C"]

    def fit(names):
        formula = "y ~ " + " + ".join(":".join(CODED[f] for f in t.split(":")) for t in names)
        table = anova_lm(ols(formula, runs).fit(), typ=typ)
        table.index = [
            {":".join(CODED[f] for f in t.split(":")): t for t in names}.get(i, i)
            for i in table.index
        ]
        return table

    while True:
        table = fit(terms)
        top = [
            t
            for t in terms
            if not any(t != u and set(t.split(":")) < set(u.split(":")) for u in terms)
        ]
        worst = max(top, key=lambda t: table.loc[t, "PR(>F)"])
        if table.loc[worst, "PR(>F)"] <= alpha:
            return terms, table
        terms.remove(worst)


@pytest.mark.parametrize("typ", [2, 3])
@pytest.mark.parametrize(
    "effects",
    [
        {"A": 1.0, "B": 0.4, "A:B": 0.5},
        {"A:B": 1.0},  # hierarchy: A and B stay while A:B does
        {"C": 0.8, "B:C": 0.3, "A": 0.05},
    ],
)
def test_backward_elimination_equals_statsmodels_by_hand(effects, typ) -> None:
    runs = _runs(effects)
    expected, reference = _by_hand(runs, 0.1, typ)
    table = analysis.anova(runs, FACTORS, "y", typ=typ, alpha_to_remove=0.1)
    terms = [t for t in table["term"] if t != "Residual"]
    assert terms == expected
    for _, row in table.iterrows():
        ref = reference.loc[row["term"]]
        assert row["df"] == ref["df"]
        assert row["sum_sq"] == pytest.approx(ref["sum_sq"], rel=1e-9)
        if row["term"] != "Residual":
            assert row["p_value"] == pytest.approx(ref["PR(>F)"], rel=1e-7)
    removed = [t for t in ["A", "B", "C", "A:B", "A:C", "B:C"] if t not in terms]
    note = table.attrs["note"]
    assert "backward elimination (alpha to remove 0.1" in note
    assert all(t in note for t in removed)
    if effects == {"A:B": 1.0}:
        assert {"A", "B", "A:B"} <= set(terms)


def test_the_reduced_models_residuals_and_effects_follow_the_anova() -> None:
    runs = _runs({"A": 1.0, "B": 0.4, "A:B": 0.5})
    result = analysis.analyze(runs, FACTORS, ["y"], alpha_to_remove=0.1)["y"]
    anova = result["anova"]
    terms = [t for t in anova["term"] if t != "Residual"]
    assert len(terms) < 6  # something was removed
    assert result["residuals"].attrs["formula"] == anova.attrs["formula"]
    fit = ols("y ~ " + " + ".join(":".join(CODED[f] for f in t.split(":")) for t in terms), runs)
    assert np.allclose(result["residuals"]["residual"], fit.fit().resid, atol=1e-12)
    effects = result["effects"].set_index("term")
    assert sorted(effects.index) == sorted(terms)
    p = anova.set_index("term")["p_value"]
    for term in terms:  # a balanced two-level design: t^2 = F, the same p
        assert effects.loc[term, "p_value"] == pytest.approx(p[term], rel=1e-9)
    assert "model given" in result["effects"].attrs["note"]
    from brakeca.report import _effects_table

    caption = _effects_table("y", result["effects"])[1]
    named = caption.split("for the terms of the ANOVA's model: ")[1].split(";")[0].split(", ")
    assert sorted(named) == sorted(terms)  # the terms the reduced model kept, by name
    # without it: the whole model
    whole = analysis.analyze(runs, FACTORS, ["y"])["y"]["anova"]
    assert len(whole) == 7 and "backward" not in whole.attrs["note"]


def test_no_residual_degrees_of_freedom_removes_nothing() -> None:
    runs = _runs({"A": 1.0}, replicates=1).iloc[[0, 4]]  # A at its two levels, once each
    table = analysis.anova(runs, FACTORS[:1], "y", alpha_to_remove=0.1)
    assert list(table["term"]) == ["A", "Residual"]
    assert "no term removed" in table.attrs["note"]


def _drop_one_by_hand(runs: pd.DataFrame, names: list[str], alpha: float) -> list[str]:
    """Backward elimination with statsmodels' least squares, each term's p from the F test
    of dropping it alone (valid with empty cells, where the ANOVA is sequential)."""
    from scipy import stats
    from statsmodels.tools.sm_exceptions import SingularMatrixWarning

    token = {n: f"C({n}, Sum)" for n in names}
    terms = names + [f"{a}:{b}" for a, b in itertools.combinations(names, 2)]

    def fit(ts):
        rhs = " + ".join(":".join(token[p] for p in t.split(":")) for t in ts) if ts else "1"
        with warnings.catch_warnings():  # an empty cell: rank-deficient, by design
            warnings.simplefilter("ignore", SingularMatrixWarning)
            return ols("y ~ " + rhs, runs).fit()

    while terms:
        full = fit(terms)
        p = {}
        for t in terms:
            if any(t != u and set(t.split(":")) < set(u.split(":")) for u in terms):
                continue
            reduced = fit([u for u in terms if u != t])
            df = reduced.df_resid - full.df_resid
            f_value = ((reduced.ssr - full.ssr) / df) / (full.ssr / full.df_resid)
            p[t] = stats.f.sf(f_value, df, full.df_resid)
        worst = max(p, key=p.get)
        if p[worst] <= alpha:
            break
        terms.remove(worst)
    return terms


@pytest.mark.parametrize("seed", range(6))
def test_mixed_levels_with_an_empty_cell_eliminate_by_the_drop_one_test(seed) -> None:
    """A 3 x 2 x 2 design, twice, with every run at P = 1, Q = 0 missing: the ANOVA is
    sequential there, and the elimination must not judge by its order-dependent p values
    (a review found P:R removed at p 0.46 whose adjusted p was 0.27)."""
    rng = np.random.default_rng(seed)
    rows = [
        {"P": p, "Q": q, "R": r}
        for _ in range(2)
        for p, q, r in itertools.product((0.0, 1.0, 2.0), (0.0, 1.0), (0.0, 1.0))
    ]
    runs = pd.DataFrame(rows)
    runs["y"] = (
        0.8 * (runs.P == 2)
        + 0.6 * (runs.P == 1) * runs.Q
        + 0.4 * runs.R
        + 0.3 * runs.Q * runs.R
        + rng.normal(0.0, 1.0, len(runs))
    )
    runs = runs[~((runs.P == 1.0) & (runs.Q == 0.0))].reset_index(drop=True)
    runs["status"] = "ok"
    factors = [Factor("P", (0.0, 1.0, 2.0)), Factor("Q", (0.0, 1.0)), Factor("R", (0.0, 1.0))]
    for alpha in (0.1, 0.3, 0.5):
        for typ in (2, 3):
            table = analysis.anova(runs, factors, "y", typ=typ, alpha_to_remove=alpha)
            kept = [t for t in table["term"] if t != "Residual"]
            assert kept == _drop_one_by_hand(runs, ["P", "Q", "R"], alpha)


def test_centre_points_curvature_is_never_removed() -> None:
    runs = _runs({"A": 1.0}, replicates=1)
    centre = pd.DataFrame({"A": [0.5] * 3, "B": [0.5] * 3, "C": [0.5] * 3})
    centre["y"] = 10.0 + np.array([0.01, -0.02, 0.015])  # no curvature
    centre["status"] = "ok"
    runs = pd.concat([runs, centre], ignore_index=True)
    table = analysis.anova(runs, FACTORS, "y", alpha_to_remove=0.1)
    assert list(table["term"])[-2:] == ["Curvature", "Residual"]
    assert table.set_index("term").loc["Curvature", "p_value"] > 0.1
    # every factorial term removed: the curvature is left, and the note says so (it had
    # said "no term is left" above the Curvature row: an analysis review)
    flat = runs.assign(y=10.0 + np.random.default_rng(4).normal(0.0, 0.02, len(runs)))
    table = analysis.anova(flat, FACTORS, "y", alpha_to_remove=0.001)
    assert list(table["term"]) == ["Curvature", "Residual"]
    assert table.attrs["note"].endswith("no term is left but the curvature of the centre points")
    flat.loc[0, "y"] += 1.0  # an outlier: the model without it cannot be refitted, and why
    unusual = analysis.unusual_runs(flat, FACTORS, "y", alpha_to_remove=0.001)
    assert len(unusual) and unusual.attrs["without_note"].startswith(
        "its only term is the curvature of the centre points"
    )


@pytest.mark.parametrize("typ", [2, 3])
def test_every_term_removed_leaves_the_mean_and_no_effects(typ) -> None:
    runs = _runs({}, replicates=2, seed=3)
    result = analysis.analyze(runs, FACTORS, ["y"], anova_type=typ, alpha_to_remove=0.001)["y"]
    anova = result["anova"]
    assert list(anova["term"]) == ["Residual"] and anova["df"].iloc[0] == len(runs) - 1
    assert anova.attrs["formula"] == "y ~ 1" == result["residuals"].attrs["formula"]
    assert "no term is left" in anova.attrs["note"]
    assert result["effects"].empty and "removed every term" in result["effects"].attrs["note"]


def test_a_constant_response_loses_no_term() -> None:
    runs = _runs({}).assign(y=0.3)
    for typ in (2, 3):
        table = analysis.anova(runs, FACTORS, "y", typ=typ, alpha_to_remove=0.1)
        assert len(table) == 7 and "no term removed" in table.attrs["note"]


def test_an_earlier_effects_table_does_not_outlive_an_empty_one(tmp_path) -> None:
    runs = _runs({"A": 1.0})
    analysis.save_tables(analysis.analyze(runs, FACTORS, ["y"]), tmp_path)
    assert (tmp_path / "effects_y.csv").is_file()
    reduced = analysis.analyze(runs, FACTORS, ["y"], alpha_to_remove=1e-12)
    assert reduced["y"]["effects"].empty
    analysis.save_tables(reduced, tmp_path)
    assert not (tmp_path / "effects_y.csv").exists()


def test_residuals_and_box_cox_check_alpha_to_remove() -> None:
    from brakeca.boxcox import box_cox

    runs = _runs({"A": 1.0})
    for bad in (1.5, "0.1"):
        with pytest.raises(ValueError, match="alpha_to_remove"):
            analysis.residuals(runs, FACTORS, "y", alpha_to_remove=bad)
        with pytest.raises(ValueError, match="alpha_to_remove"):
            box_cox(runs.assign(y=runs.y + 20), FACTORS, "y", alpha_to_remove=bad)
    assert (
        "alpha to remove 0.1"
        in analysis.anova(runs, FACTORS, "y", alpha_to_remove=np.float32(0.1)).attrs["note"]
    )


def test_the_reviews_empty_cell_case_keeps_the_term_its_sequential_p_would_drop() -> None:
    """P:R's sequential p is 0.46 here but its drop-one p 0.27: at 0.3 it stays."""
    y = [6.2437, 9.9561, 11.0435, 9.6474, 9.7305, 10.9509, 9.7056, 9.4376, 8.6674, 13.5104]
    y += [8.7262, 9.5778, 9.2426, 11.4925, 8.7937, 12.2699, 9.7016, 10.486, 9.1773, 14.4432]
    cells = [(1, 1, 0), (1, 1, 1), (2, 0, 0), (2, 0, 1), (2, 1, 0), (2, 1, 1)]
    cells += [(3, 0, 0), (3, 0, 1), (3, 1, 0), (3, 1, 1)]
    runs = pd.DataFrame(cells * 2, columns=["P", "Q", "R"]).astype(float)
    runs["y"] = y
    runs["status"] = "ok"
    factors = [Factor("P", (1.0, 2.0, 3.0)), Factor("Q", (0.0, 1.0)), Factor("R", (0.0, 1.0))]
    whole = analysis.anova(runs, factors, "y")
    assert whole.attrs["typ"].startswith("Type I (sequential")
    assert whole.set_index("term").loc["P:R", "p_value"] > 0.3
    table = analysis.anova(runs, factors, "y", alpha_to_remove=0.3)
    assert "no term removed" in table.attrs["note"]
    assert _drop_one_by_hand(runs, ["P", "Q", "R"], 0.3) == ["P", "Q", "R", "P:Q", "P:R", "Q:R"]


# --- the model's order -------------------------------------------------------------------


@pytest.mark.parametrize("typ", [2, 3])
def test_terms_up_through_three_factors_equal_statsmodels(typ) -> None:
    runs = _runs({"A": 1.0, "A:B:C": 0.4})
    table = analysis.anova(runs, FACTORS, "y", typ=typ, interactions=3)
    assert list(table["term"]) == ["A", "B", "C", "A:B", "A:C", "B:C", "A:B:C", "Residual"]
    # the factor column C would hide patsy's C(): the coded columns stand for the factors
    fit = ols("y ~ C(x1, Sum) * C(x2, Sum) * C(x3, Sum)", runs.drop(columns="C")).fit()
    reference = anova_lm(fit, typ=typ)
    for (_, row), (_, ref) in zip(
        table.iterrows(), reference.drop(index="Intercept", errors="ignore").iterrows(), strict=True
    ):
        assert row["sum_sq"] == pytest.approx(ref["sum_sq"], rel=1e-9)
        assert row["df"] == ref["df"]
    assert table.attrs["formula"] == "y ~ A + B + C + A:B + A:C + B:C + A:B:C"
    assert (
        analysis.residuals(runs, FACTORS, "y", interactions=3).attrs["formula"]
        == (table.attrs["formula"])
    )


def test_order_one_is_main_effects_and_a_saturated_order_is_pooled_step_by_step() -> None:
    runs = _runs({"A": 1.0})
    one = analysis.anova(runs, FACTORS, "y", interactions=1)
    assert one.equals(analysis.anova(runs, FACTORS, "y", interactions=False))
    single = _runs({"A": 1.0}, replicates=1)  # 8 runs: the three-factor term leaves no df
    table = analysis.anova(single, FACTORS, "y", interactions=3)
    assert list(table["term"])[-2:] == ["B:C", "Residual"]
    assert table.set_index("term").loc["Residual", "df"] == 1
    assert "three-factor interactions pooled into the residual" in table.attrs["note"]


@pytest.mark.parametrize("bad", [0, -1, 2.5, "2"])
def test_the_order_is_checked(bad) -> None:
    with pytest.raises(ValueError, match="interactions: expected True"):
        analysis.anova(_runs({}), FACTORS, "y", interactions=bad)
    for order in (bad, True):  # max_order takes a whole number, not interactions' flags
        with pytest.raises(ValueError, match=r"^max_order: expected the most factors in a term"):
            analysis.analyze(_runs({}), FACTORS, ["y"], max_order=order)


def test_analyze_with_an_order_fits_the_effects_of_its_terms() -> None:
    runs = _runs({"A": 1.0, "A:B": 0.5})
    result = analysis.analyze(runs, FACTORS, ["y"], max_order=1)["y"]
    assert [t for t in result["anova"]["term"] if t != "Residual"] == ["A", "B", "C"]
    assert sorted(result["effects"]["term"]) == ["A", "B", "C"]
    assert result["residuals"].attrs["formula"] == "y ~ A + B + C"


def test_ranked_effects_of_a_three_factor_term_are_its_classical_effect() -> None:
    runs = _runs({"A:B:C": 0.4, "A:B": 0.7})
    ranked = analysis.ranked_effects(runs, FACTORS, "y", interactions=3).set_index("term")
    sign = runs.x1 * runs.x2 * runs.x3
    hand = runs.y[sign > 0].mean() - runs.y[sign < 0].mean()
    assert ranked.loc["A:B:C", "effect"] == pytest.approx(hand, rel=1e-12)
    sign2 = runs.x1 * runs.x2
    assert ranked.loc["A:B", "effect"] == pytest.approx(
        runs.y[sign2 > 0].mean() - runs.y[sign2 < 0].mean(), rel=1e-12
    )


def test_an_explicit_default_order_changes_nothing() -> None:
    """max_order=2 is the default model: the report is the same as without it (a review
    found the effects table switched from every estimable effect to the ANOVA's terms)."""
    runs = _runs({"A": 3.0}, replicates=1)
    plain = analysis.analyze(runs, FACTORS, ["y"])["y"]
    two = analysis.analyze(runs, FACTORS, ["y"], max_order=2)["y"]
    assert plain["effects"].equals(two["effects"]) and plain["anova"].equals(two["anova"])
    assert "A:B:C" in list(plain["effects"]["term"])  # every estimable effect, Lenth's
    main = analysis.analyze(runs, FACTORS, ["y"], main_effects_only=True, max_order=1)["y"]
    assert (
        main["effects"].attrs["note"]
        == analysis.analyze(runs, FACTORS, ["y"], main_effects_only=True)["y"]["effects"].attrs[
            "note"
        ]
    )
    with pytest.raises(ValueError, match="max_order"):
        analysis.analyze(runs, FACTORS, ["y"], max_order=True)


def test_the_order_is_checked_before_the_data() -> None:
    one_run = _runs({}).iloc[:1]
    with pytest.raises(ValueError, match="interactions: expected True"):
        analysis.anova(one_run, FACTORS, "y", interactions=0)
    with pytest.raises(ValueError, match="interactions: expected True"):
        analysis.residuals(one_run.iloc[:0], FACTORS, "y", interactions="2")


def test_a_term_that_is_a_word_of_the_defining_relation_is_aliased_with_the_mean() -> None:
    runs = _runs({"A": 1.0}, replicates=2)
    half = runs[(runs.x1 * runs.x2 * runs.x3) > 0]  # I = A*B*C
    table = analysis.anova(half, FACTORS, "y", interactions=3)
    assert (
        "A:B:C (aliased with the mean: a word of the design's defining relation)"
        in (table.attrs["note"])
    )


def test_the_report_says_the_anova_is_reduced_or_of_another_order() -> None:
    from brakeca.report import render_report

    runs = _runs({"A": 1.0, "A:B": 0.5})
    reduced = analysis.anova(runs, FACTORS, "y", alpha_to_remove=0.1)
    three = analysis.anova(runs, FACTORS, "y", interactions=3)
    assert reduced.attrs["alpha_to_remove"] == 0.1 and three.attrs["order"] == 3
    html = render_report(
        title="t",
        design_table=pd.DataFrame({"test": [1]}),
        summary=runs,
        anova_tables={"y": reduced, "z": three},
        figures={},
        config_text="",
        version="0",
    )
    assert "reduced by backward elimination (alpha to remove 0.1" in html
    assert "terms up through 3 factors" in html


def test_the_effects_caption_says_when_it_fits_more_than_the_anova() -> None:
    from brakeca.report import _effects_table

    runs = _runs({"A": 1.0}, replicates=2)  # replicated 2^3: A:B:C estimable
    default = analysis.analyze(runs, FACTORS, ["y"])["y"]["effects"]
    assert "A:B:C" in list(default["term"])
    assert "keeps interactions of three or more factors" in _effects_table("y", default)[1]
    three = analysis.analyze(runs, FACTORS, ["y"], max_order=3)["y"]["effects"]
    assert "keeps interactions of three" not in _effects_table("y", three)[1]


@pytest.mark.parametrize("bad", [0, 0.0, 1, 1.0, 1.5, -0.1, float("nan"), "0.1", True, None])
def test_alpha_to_remove_has_one_rule_everywhere(bad):
    """The design, anova, rsm's elimination and both commands' --reduce refuse the same
    values with the same words (each prefixed with its own name); None means "no
    reduction" to anova and the design, and is no level for rsm's alpha."""
    from pydantic import ValidationError

    from brakeca import rsm
    from brakeca.design import Design

    runs = _runs({"A": 1.0})
    expected = "expected a level above 0 and below 1 (0.1 in Minitab)"
    if bad is None:
        assert analysis.alpha_problem(bad) is not None
        analysis.anova(runs, FACTORS, "y", alpha_to_remove=None)
        return
    assert analysis.alpha_problem(bad) == f"{expected}, got {bad!r}"
    with pytest.raises(ValueError, match=r"alpha_to_remove: expected a level above 0"):
        analysis.anova(runs, FACTORS, "y", alpha_to_remove=bad)
    with pytest.raises(ValueError, match=r"^alpha: expected a level above 0"):
        rsm.backward_elimination(runs, FACTORS[:2], "y", alpha=bad)
    factors = [{"name": "WP", "field": "wear.k_plateau", "levels": [1e-14, 1e-13]}]
    with pytest.raises(ValidationError) as err:
        Design.model_validate(
            {"name": "d", "base_config": "paper", "factors": factors, "alpha_to_remove": bad}
        )
    assert expected in str(err.value) and "alpha_to_remove" in str(err.value)
    assert analysis.alpha_problem(0.1) is None and analysis.alpha_problem(np.float64(0.05)) is None
