"""A model of chosen terms (Minitab's Terms dialog): ``interactions=[...]`` in the analysis,
``model_terms`` in a design, ``brakeca analyze --terms``."""

from __future__ import annotations

import numpy as np
import pytest
from test_analysis import FACTORS, _design, _levels01, _two_level

from brakeca.analysis import (
    analyze,
    anova,
    canonical_terms,
    residuals,
    split_terms,
    two_level_effects,
)

NAMES = [f.name for f in FACTORS]  # S, WP, WR, A


def test_terms_are_written_in_design_order_and_sorted_by_order() -> None:
    assert canonical_terms(["A*WP", "S", "WP", "A", "WR"], NAMES) == [
        "S",
        "WP",
        "WR",
        "A",
        "WP:A",
    ]
    assert canonical_terms("S + WP + S:WP", NAMES) == ["S", "WP", "S:WP"]
    assert canonical_terms("S, WP,  WP * S ", NAMES) == ["S", "WP", "S:WP"]
    every = "S WR A S*WR S*A WR*A A*S*WR"
    assert canonical_terms(every, NAMES)[-1] == "S:WR:A"
    assert split_terms(" S  WP*A,WR+ A : S ") == ["S", "WP*A", "WR", "A:S"]


@pytest.mark.parametrize(
    ("terms", "message"),
    [
        ([], "model_terms: no term given; name at least one factor"),
        ("", "model_terms: no term given"),
        (["S", "X*WP"], "model_terms: term 'X*WP': 'X' is not a factor of the design (its "
         "factors: S, WP, WR, A)"),
        (["S", "S*"], "term 'S*': an empty name is not a factor"),
        ("S,,WP", "model_terms: an empty term between separators in 'S,,WP'"),
        ("S + + WP", "an empty term between separators"),
        ("s wp", "'s' is not a factor of the design (its factors: S, WP, WR, A); did you mean "
         "'S'? names are case-sensitive"),
        (["S", "WP*A"], "model_terms: the model is not hierarchical (WP:A without WP, A): each "
         "interaction needs every lower-order term of its factors"),
        ("S WP A S*WP*A WP*A", "(S:WP:A without S:WP, S:A)"),
        (["WP*WP"], "term 'WP*WP' names a factor twice"),
        (["S", "WP", "WP:S", "S*WP"], "term 'S*WP' is given twice (as 'WP:S')"),
        ("S|WP|S", "model_terms: term 'S|WP|S' names a factor twice"),
        ("S|X", "term 'X': 'X' is not a factor of the design"),
        ([1, 2], "model_terms: expected a list of terms"),
        (3, "model_terms: expected a list of terms"),
    ],
)  # fmt: skip
def test_bad_terms_name_the_term_and_the_factors(terms, message) -> None:
    with pytest.raises(ValueError) as info:
        canonical_terms(terms, NAMES)
    assert message in str(info.value)


def test_an_anova_of_chosen_terms_is_statsmodels_fit_of_those_terms() -> None:
    """The paper's design with main effects and the one interaction WP:A: the sums of
    squares, degrees of freedom and residual are statsmodels' Type II of that formula, in
    whatever order or spelling the terms are given."""
    import statsmodels.formula.api as smf
    from statsmodels.stats.anova import anova_lm

    rows = _design(replicates=2)
    table = anova(rows, FACTORS, "MU", interactions=["A*WP", "S", "WP", "WR", "A"])
    fit = smf.ols("MU ~ C(S) + C(WP) + C(WR) + C(A) + C(WP):C(A)", rows).fit()
    expected = anova_lm(fit, typ=2)
    assert list(table["term"]) == ["S", "WP", "WR", "A", "WP:A", "Residual"]
    np.testing.assert_allclose(table["df"], expected["df"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(table["sum_sq"], expected["sum_sq"], rtol=1e-9, atol=1e-18)
    np.testing.assert_allclose(table["F"].iloc[:-1], expected["F"].iloc[:-1], rtol=1e-9)
    assert table.attrs["model_terms"] == ["S", "WP", "WR", "A", "WP:A"]
    assert table.attrs["order"] == 2
    assert table.attrs["formula"] == "MU ~ S + WP + WR + A + WP:A"
    assert table.attrs["df_resid"] == pytest.approx(fit.df_resid)
    assert table.attrs["note"] == ""  # hierarchical, estimable: nothing to say
    same = anova(rows, FACTORS, "MU", interactions=["S", "WP", "WR", "A", "WP:A"])
    assert same.drop(columns="note").equals(table.drop(columns="note"))


def test_a_model_of_all_terms_up_through_an_order_equals_that_order() -> None:
    rows = _design(replicates=2)
    pairs = [f"{a}*{b}" for i, a in enumerate(NAMES) for b in NAMES[i + 1 :]]
    by_order = anova(rows, FACTORS, "V", interactions=2)
    by_terms = anova(rows, FACTORS, "V", interactions=[*NAMES, *pairs])
    assert list(by_terms["term"]) == list(by_order["term"])
    np.testing.assert_array_equal(by_terms["sum_sq"], by_order["sum_sq"])
    assert by_order.attrs["model_terms"] is None


def test_minitab_s_bar_stands_for_every_term_of_its_factors() -> None:
    """``S|WP|A`` (Minitab's full-factorial bar; an API review had it refused as "'S|WP|A'
    is not a factor") is S, WP, A, their three two-factor interactions and the three-factor
    one; terms two bars share are made once, and the bar mixes with plain terms."""
    assert canonical_terms("S|WP|A", NAMES) == ["S", "WP", "A", "S:WP", "S:A", "WP:A", "S:WP:A"]
    assert canonical_terms("S | WP  WP|A WR", NAMES) == ["S", "WP", "WR", "A", "S:WP", "WP:A"]
    assert split_terms("S | WP|A, WR") == ["S|WP|A", "WR"]
    # a term a bar makes, also named on its own, is one term (a review: "given twice")
    assert canonical_terms("S + S|WP", NAMES) == ["S", "WP", "S:WP"]
    assert canonical_terms("S|WP S*WP", NAMES) == ["S", "WP", "S:WP"]
    rows = _design(replicates=2)
    by_bar = anova(rows, FACTORS, "MU", interactions="S|WP|WR|A")
    assert list(by_bar["term"]) == list(anova(rows, FACTORS, "MU", interactions=4)["term"])


def test_a_model_that_is_not_hierarchical_is_refused() -> None:
    """Its interaction would be coded one way in the fit (taking over the effects of the
    terms it lacks: WP:A with 5 df) and another in Type III, backward elimination and the
    effects table (2 df): the tables disagreed with themselves (a helper's review)."""
    with pytest.raises(ValueError, match=r"^interactions: the model is not hierarchical \(S:WP"):
        anova(_design(replicates=2), FACTORS, "MU", interactions=["S", "S*WP", "A"])


def test_terms_may_come_as_an_array_or_series() -> None:
    import pandas as pd

    rows = _design(replicates=2)
    listed = anova(rows, FACTORS, "MU", interactions=["S", "WP", "S*WP"])
    # or one string, as analyze's model_terms takes them (anova refused it: an API review)
    for given in (np.array(["S", "WP", "S*WP"]), pd.Series(["S", "WP", "S*WP"]), "S WP S*WP"):
        table = anova(rows, FACTORS, "MU", interactions=given)
        assert table.drop(columns="note").equals(listed.drop(columns="note"))
    from brakeca.analysis import residuals

    listed_residuals = residuals(rows, FACTORS, "MU", interactions=["S", "WP", "S*WP"])
    assert residuals(rows, FACTORS, "MU", interactions="S + WP + S:WP").equals(listed_residuals)


def test_a_fraction_fitted_without_some_main_effects_names_every_alias() -> None:
    """The alias chains name every factor of the design, in the model or not: leaving a
    main effect out of a fraction's model raised KeyError (a helper's review)."""
    gens = {"E": "ABC", "F": "BCD", "G": "ACD"}
    rows = _two_level("ABCDEFG", gens, {"A": 3.0, "D": -2.0}, noise=0.3)
    table = anova(rows, _levels01("ABCDEFG"), "y", interactions=["A", "B", "D", "A*B"])
    assert list(table["term"]) == ["A", "B", "D", "A:B", "Residual"]
    assert set(table.set_index("term").loc["A:B", "aliases"].split(" + ")) == {"C:E", "F:G"}
    result = analyze(rows, _levels01("ABCDEFG"), ("y",), model_terms="A B D A*B")
    assert sorted(result["y"]["effects"]["term"]) == ["A", "A:B", "B", "D"]


def test_chosen_terms_are_not_pooled_when_they_saturate_the_model() -> None:
    """Asked for by order, a saturated model's highest interactions are pooled into the
    residual; the terms chosen one by one are fitted as given, and F cannot be computed."""
    rows = _two_level("ABC", {}, {"A": 3.0}, noise=0.3)  # 8 runs
    every = ["A", "B", "C", "A*B", "A*C", "B*C", "A*B*C"]
    table = anova(rows, _levels01("ABC"), "y", interactions=every)
    assert list(table["term"])[:-1] == ["A", "B", "C", "A:B", "A:C", "B:C", "A:B:C"]
    assert table["F"].isna().all() and "saturated model (0 residual df)" in table.attrs["note"]
    pooled = anova(rows, _levels01("ABC"), "y", interactions=3)
    assert "A:B:C" not in list(pooled["term"]) and "pooled" in pooled.attrs["note"]


def test_a_term_of_a_factor_with_one_level_in_the_data_is_left_out() -> None:
    rows = _design(replicates=2)
    rows = rows[rows["A"] == 10.0]
    table = anova(rows, FACTORS, "MU", interactions=["S", "WP", "A", "WP*A", "S*WP"])
    assert list(table["term"]) == ["S", "WP", "S:WP", "Residual"]
    assert (
        "terms of a factor with a single level in the data are left out: A, WP:A"
        in (table.attrs["note"])
    )
    s_only = rows[rows["S"] == 0.0]
    empty = anova(s_only, FACTORS, "MU", interactions=["S"])
    assert list(empty["term"]) == ["Residual"]
    assert "left out: S; no term of the model is left" in empty.attrs["note"]


def test_chosen_terms_with_backward_elimination() -> None:
    rows = _design(replicates=2)
    table = anova(
        rows, FACTORS, "MU", interactions=["S", "WP", "WR", "A", "S*WP", "WR*A"],
        alpha_to_remove=0.05,
    )  # fmt: skip
    assert "S:WP" in list(table["term"])  # the real interaction stays
    assert "WR:A" not in list(table["term"])
    assert "removed WR:A" in table.attrs["note"]


def test_analyze_follows_the_chosen_terms_in_residuals_and_effects() -> None:
    rows = _two_level("ABCD", {}, {"A": 3.0, "B": 1.0, "A:B": 0.8}, noise=0.3)
    factors = _levels01("ABCD")
    result = analyze(rows, factors, ("y",), model_terms="A B C D A*B")
    table = result["y"]["anova"]
    assert list(table["term"]) == ["A", "B", "C", "D", "A:B", "Residual"]
    assert result["y"]["residuals"].attrs["df_resid"] == 16 - 6
    effects = result["y"]["effects"]
    assert sorted(effects["term"]) == ["A", "A:B", "B", "C", "D"]
    assert effects.attrs["terms_given"] and effects.attrs["method"] == "residual"
    plain = two_level_effects(rows, factors, "y")
    assert len(plain) == 15  # every effect, Lenth's, without terms given
    with pytest.raises(ValueError, match=r"^model_terms, max_order: give one of them"):
        analyze(rows, factors, ("y",), model_terms=["A"], max_order=2)
    with pytest.raises(ValueError, match=r"^model_terms: term 'E': 'E' is not a factor"):
        analyze(rows, factors, ("y",), model_terms=["A", "E"])


def test_residuals_of_chosen_terms_are_those_of_the_least_squares_fit() -> None:
    import statsmodels.formula.api as smf

    rows = _design(replicates=2)
    res = residuals(rows, FACTORS, "MU", interactions=["S", "WP", "S*WP"])
    fit = smf.ols("MU ~ C(S) * C(WP)", rows).fit()
    np.testing.assert_allclose(res["fitted"], fit.fittedvalues, rtol=1e-12)
    assert res.attrs["formula"] == "MU ~ S + WP + S:WP"


def test_a_design_carries_its_model_terms_as_the_tables_write_them() -> None:
    import tomllib

    from brakeca.config import ConfigError
    from brakeca.design import design_from_dict, load_design

    paper = load_design("paper").to_dict()
    design = design_from_dict({**paper, "model_terms": "S WP WR A A*WP"})
    assert design.model_terms == ("S", "WP", "WR", "A", "WP:A")
    assert design.anova_model == design.model_terms
    assert load_design("paper").anova_model == 2
    again = design_from_dict(tomllib.loads(design.to_toml()))
    assert again.model_terms == design.model_terms
    listed = design_from_dict({**paper, "model_terms": ["A*WP", "S", "WP", "WR", "A"]})
    assert listed == design
    for extra, message in (
        ({"model_terms": ["S", "X"]}, "d.toml: model_terms: term 'X': 'X' is not a factor"),
        ({"model_terms": []}, "d.toml: model_terms: no term given"),
        ({"model_terms": "S", "model_order": 1}, "model_terms, model_order: give one of them"),
    ):
        with pytest.raises(ConfigError) as info:
            design_from_dict({**paper, **extra}, source="d.toml")
        assert message in str(info.value)
    surface = load_design("response_surface").to_dict()
    with pytest.raises(ConfigError, match="model_terms: a central composite design's report"):
        design_from_dict({**surface, "model_terms": "mu0"})


def test_power_is_of_the_model_of_the_design_terms() -> None:
    """The main effects chosen one by one are the model of order 1: the same power, and
    more error df than the default model with the two-factor interactions."""
    from brakeca.design import design_from_dict, load_design
    from brakeca.power import factor_power

    paper = load_design("paper").to_dict()
    by_terms = factor_power(design_from_dict({**paper, "model_terms": "S WP WR A"}), 0.01, 0.01)
    by_order = factor_power(design_from_dict({**paper, "model_order": 1}), 0.01, 0.01)
    default = factor_power(load_design("paper"), 0.01, 0.01)
    assert by_terms.equals(by_order)
    assert (by_terms["df_error"] > default["df_error"]).all()


def test_brakeca_power_names_the_model_and_the_factors_left_out_of_it(tmp_path) -> None:
    from typer.testing import CliRunner

    from brakeca.cli import app
    from brakeca.design import design_from_dict, load_design

    path = tmp_path / "d.toml"
    path.write_text(
        design_from_dict({**load_design("paper").to_dict(), "model_terms": "S WP S*WP"}).to_toml()
    )
    res = CliRunner().invoke(
        app, ["power", str(path), "--effect", "0.01", "--sigma", "0.01"], env={"COLUMNS": "120"}
    )
    assert res.exit_code == 0, res.output
    rows = {line.split("│")[1].strip(): line for line in res.output.splitlines() if "│" in line}
    assert "not in the model" in rows["WR"] and "not in the model" in rows["A"]
    assert "not in the model" not in rows["WP"]
    assert "the ANOVA model: the terms S, WP, S:WP (model_terms)" in res.output
    plain = CliRunner().invoke(app, ["power", "paper", "--effect", "0.01", "--sigma", "0.01"])
    assert "the ANOVA model: main effects and two-factor interactions\n" in plain.output


def test_terms_from_any_iterable_once_and_bad_ones_before_any_work() -> None:
    """A generator was read by the type check and then refused as empty; a dict was taken
    as its keys; a bad term passed unchecked where fewer than two runs were usable (a
    helper's review of the change)."""
    from brakeca.config import ConfigError
    from brakeca.design import design_from_dict, load_design

    assert canonical_terms((t for t in ["WP", "S"]), NAMES) == ["S", "WP"]
    assert canonical_terms({"WP", "S"}, NAMES) == ["S", "WP"]
    with pytest.raises(ValueError, match="expected a list of terms"):
        canonical_terms({"S": 1}, NAMES)
    one_run = _design().iloc[:1]
    with pytest.raises(ValueError, match=r"^interactions: term 'X': 'X' is not a factor"):
        anova(one_run, FACTORS, "MU", interactions=["X"])
    rows = _design(replicates=2)
    by_set = anova(rows, FACTORS, "MU", interactions={"S", "WP", "S*WP"})
    assert list(by_set["term"]) == ["S", "WP", "S:WP", "Residual"]
    with pytest.raises(ConfigError) as info:  # the message says model_terms once
        design_from_dict({**load_design("paper").to_dict(), "model_terms": "S,,WP"}, source="d")
    assert "model_terms: an empty term between separators in 'S,,WP'" in str(info.value)
    assert "model_terms: model_terms" not in str(info.value)


def test_the_effects_caption_lists_the_terms_in_the_models_order() -> None:
    from brakeca.report import _effects_table

    gens = {"D": "ABC"}
    rows = _two_level("ABCD", gens, {"A": 3.0, "D": 1.0}, noise=0.3, replicates=2)
    effects = analyze(rows, _levels01("ABCD"), ("y",), model_terms="A B C D A*B")["y"]["effects"]
    caption = _effects_table("y", effects)[1]
    assert "for the terms of the ANOVA's model: A, B, C, D, A:B;" in caption
