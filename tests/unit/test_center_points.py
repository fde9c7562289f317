"""Centre points in two-level designs: the design's tests (brakeca.design) and the curvature
test, pure error and effects of their analysis (brakeca.analysis), checked against
statsmodels' least squares of the same model (every factor coded -1/+1, the centre points 0,
and an indicator of the centre points, Minitab's "Ct Pt")."""

from __future__ import annotations

import itertools
import math
import tomllib

import numpy as np
import pandas as pd
import pytest
from statsmodels.formula.api import ols
from statsmodels.stats.anova import anova_lm

from brakeca import analysis, power
from brakeca.analysis import Factor
from brakeca.config import ConfigError
from brakeca.design import design_from_dict, point_seed
from brakeca.report import _curvature_text


def _design(**extra):
    data = {
        "name": "c",
        "base": "paper",
        "root_seed": 5,
        "factors": [
            {"name": "A", "levels": [10, 20]},
            {"name": "WR", "levels": [1e-10, 1e-8], "coding": "log"},
            {"name": "S", "levels": [0.0, 1.0]},
        ],
    }
    data.update(extra)
    return design_from_dict(data)


# --- the design --------------------------------------------------------------------------


def test_centre_points_follow_the_factorial_tests_at_the_middle_of_the_levels() -> None:
    plain = _design()
    design = _design(center_points=3)
    combos = design.combinations()
    assert design.n_tests == len(combos) == 8 + 3
    assert combos[:8] == plain.combinations()
    centre = {"A": 15, "WR": pytest.approx(1e-9, rel=1e-12), "S": 0.5}
    for combo in combos[8:]:
        assert combo == centre
    assert type(combos[8]["A"]) is int  # both levels ints and the middle whole: an int
    assert design.kind == "full factorial, plus 3 centre points"
    # the factorial's tests keep their seeds, so its runs are reused when centre points are
    # added to a finished campaign; each centre point has a seed of its own
    assert [p.seed for p in design.points()[:8]] == [p.seed for p in plain.points()]
    seeds = [p.seed for p in design.points()[8:]]
    assert seeds == [point_seed(5, t, 0) for t in (9, 10, 11)] and len(set(seeds)) == 3


def test_centre_points_in_a_fraction_after_its_fold_over_and_in_toml() -> None:
    design = _design(generators=["S = A*WR"], foldover=["A"], center_points=2)
    combos = design.combinations()
    assert design.n_tests == len(combos) == 4 + 4 + 2
    assert combos[8] == combos[9] == design.center_levels()
    assert design.kind.endswith(
        "folded over on A, a full factorial of its two-level factors, plus 2 centre points"
    )
    saved = tomllib.loads(design.to_toml())
    assert saved["center_points"] == 2
    assert design_from_dict(saved).combinations() == combos
    assert "center_points" not in tomllib.loads(_design().to_toml())  # 0, the default


def test_centre_points_of_a_plackett_burman_design() -> None:
    design = _design(plackett_burman=12, center_points=1)
    assert design.n_tests == 13
    assert design.kind.startswith("Plackett-Burman design, 12 tests")
    assert design.kind.endswith("plus 1 centre point")


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ({"center_points": 101}, "center_points"),
        ({"center_points": -1}, "center_points"),
        ({"center_points": 2.0}, "whole number of centre points"),
        ({"center_points": "2"}, "whole number of centre points"),
        ({"center_points": True}, "center_points"),
        ({"center_points": 2, "composite": {"alpha": "face", "center": 2}}, "composite.center"),
    ],
)
def test_centre_point_counts_and_designs_refused(extra, message) -> None:
    with pytest.raises(ConfigError, match=message):
        _design(**extra)


def test_centre_points_need_two_level_numeric_factors() -> None:
    base = {"name": "c", "base": "paper", "root_seed": 1, "center_points": 2}
    three = [{"name": "A", "levels": [10, 15, 20]}, {"name": "S", "levels": [0.0, 1.0]}]
    with pytest.raises(ConfigError, match=r"factors #1\.levels: factor 'A' has 3 levels"):
        design_from_dict({**base, "factors": three})
    choice = [
        {"name": "cyc", "field": "cycle", "levels": [1, 2], "choices": ["paper", "paper"]},
        {"name": "S", "levels": [0.0, 1.0]},
    ]
    with pytest.raises(ConfigError, match=r"factor 'cyc' is categorical"):
        design_from_dict({**base, "factors": choice})
    # an integer field whose middle is not whole: named, with the level
    rows = [{"name": "rows", "field": "mesh.n_radial", "levels": [21, 40]}]
    with pytest.raises(
        ConfigError, match=r"center_points: factor 'rows' .*its centre point, 30\.5"
    ):
        design_from_dict({**base, "factors": rows})
    whole = design_from_dict(
        {**base, "factors": [{"name": "rows", "field": "mesh.n_radial", "levels": [21, 41]}]}
    )
    assert whole.points()[-1].config.mesh.n_radial == 31


# --- the analysis ------------------------------------------------------------------------

FACTORS = [
    Factor("A", (10.0, 20.0)),
    Factor("B", (1e-10, 1e-9), coding="log"),
    Factor("C", (0.5, 1.5)),
]


def _runs(replicates: int = 1, centre: int = 3, drop: tuple[int, ...] = (), seed: int = 3):
    """A 2^3 factorial with centre points and a curved response; columns x1..x3 and ct
    code the model for statsmodels."""
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(replicates):
        for code in itertools.product((0, 1), repeat=3):
            row = {f.name: f.levels[k] for f, k in zip(FACTORS, code, strict=True)}
            rows.append(row | {"x1": 2 * code[0] - 1, "x2": 2 * code[1] - 1, "x3": 2 * code[2] - 1})
    for _ in range(centre):
        rows.append({f.name: f.center for f in FACTORS} | {"x1": 0, "x2": 0, "x3": 0})
    d = pd.DataFrame(rows)
    d["ct"] = ((d.x1 == 0) & (d.x2 == 0) & (d.x3 == 0)).astype(float)
    d["y"] = 1 + 2 * d.x1 - 0.5 * d.x2 + 0.3 * d.x1 * d.x2 + 0.8 * d.ct
    d["y"] += rng.normal(0.0, 0.2, len(d))
    d["status"] = "ok"
    return d.drop(index=list(drop)).reset_index(drop=True)


_NAMES = {
    "A": "x1",
    "B": "x2",
    "C": "x3",
    "A:B": "x1:x2",
    "A:C": "x1:x3",
    "B:C": "x2:x3",
    "Curvature": "ct",
    "Residual": "Residual",
}


def test_factor_centre_is_the_middle_or_the_geometric_mean() -> None:
    assert FACTORS[0].center == 15.0
    assert FACTORS[1].center == pytest.approx(math.sqrt(1e-10 * 1e-9), rel=1e-12)
    assert Factor("W", (1.0, 2.0, 3.0)).center is None
    with pytest.raises(ValueError, match="coding"):
        Factor("A", (1.0, 2.0), coding="square")


@pytest.mark.parametrize(
    ("replicates", "centre", "drop", "typ"),
    [(1, 3, (), 2), (1, 3, (), 3), (2, 4, (1, 5), 2), (2, 4, (1, 5), 3), (1, 1, (), 2)],
)
def test_anova_with_centre_points_is_the_model_with_a_centre_point_term(
    replicates, centre, drop, typ
) -> None:
    runs = _runs(replicates, centre, drop)
    table = analysis.anova(runs, FACTORS, "y", typ=typ)
    fit = ols("y ~ x1 + x2 + x3 + x1:x2 + x1:x3 + x2:x3 + ct", runs).fit()
    reference = anova_lm(fit, typ=typ)
    assert list(table["term"]) == [*_NAMES]
    for _, row in table.iterrows():
        ref = reference.loc[_NAMES[row["term"]]]
        assert row["df"] == ref["df"]
        assert row["sum_sq"] == pytest.approx(ref["sum_sq"], rel=1e-9)
        if row["term"] != "Residual":
            assert row["F"] == pytest.approx(ref["F"], rel=1e-9)
            assert row["p_value"] == pytest.approx(ref["PR(>F)"], rel=1e-7)
    assert table.attrs["typ"].startswith("Type II" if typ == 2 else "Type III")
    assert table.attrs["formula"] == "y ~ A + B + C + A:B + A:C + B:C + Ct Pt"
    assert table.attrs["center_points"] == centre and table.attrs["n"] == len(runs)
    assert table.attrs["r_squared"] == pytest.approx(fit.rsquared, rel=1e-12)
    assert table.attrs["r_squared_adj"] == pytest.approx(fit.rsquared_adj, rel=1e-12)
    assert table.attrs["s"] == pytest.approx(math.sqrt(fit.mse_resid), rel=1e-12)
    # the centre points are one more cell of the pure error
    cells = runs.groupby(["x1", "x2", "x3"])["y"]
    pure = float(((runs["y"] - cells.transform("mean")) ** 2).sum())
    assert table.attrs["pure_error_df"] == len(runs) - cells.ngroups
    if table.attrs["pure_error_df"]:
        assert table.attrs["pure_error_ss"] == pytest.approx(pure, rel=1e-9)
    residuals = analysis.residuals(runs, FACTORS, "y")
    assert np.allclose(residuals["residual"], fit.resid, rtol=0, atol=1e-12)
    assert np.allclose(residuals["leverage"], fit.get_influence().hat_matrix_diag, atol=1e-12)


def test_curvature_of_a_balanced_design_is_the_difference_of_the_two_means() -> None:
    runs = _runs(1, 4)
    table = analysis.anova(runs, FACTORS, "y").set_index("term")
    y_f = runs.loc[runs.ct == 0, "y"]
    y_c = runs.loc[runs.ct == 1, "y"]
    hand = len(y_f) * len(y_c) / len(runs) * (y_f.mean() - y_c.mean()) ** 2
    assert table.loc["Curvature", "sum_sq"] == pytest.approx(hand, rel=1e-10)
    # the terms, the curvature and the residual add up to the total
    total = float(((runs["y"] - runs["y"].mean()) ** 2).sum())
    assert table["sum_sq"].sum() == pytest.approx(total, rel=1e-10)
    # without the centre points: the same factorial terms, the residual smaller by their
    # pure error (3 df)
    cube = analysis.anova(runs[runs.ct == 0], FACTORS, "y").set_index("term")
    for term in ("A", "B", "A:B", "B:C"):
        assert table.loc[term, "sum_sq"] == pytest.approx(cube.loc[term, "sum_sq"], rel=1e-10)
    assert table.loc["Residual", "df"] == cube.loc["Residual", "df"] + 3
    assert table.loc["Residual", "sum_sq"] == pytest.approx(
        cube.loc["Residual", "sum_sq"] + float(((y_c - y_c.mean()) ** 2).sum()), rel=1e-10
    )


def test_centre_points_keep_the_interactions_of_an_unreplicated_two_factor_design() -> None:
    """2^2 with its interaction is saturated: the centre points' pure error tests it."""
    runs = _runs(1, 3)
    runs = runs[runs["C"].isin([0.5, 1.0])].copy()  # C at its low level, and the centre
    runs["C"] = np.where(runs["ct"] == 1, 1.0, 0.5)
    factors = FACTORS[:2]
    table = analysis.anova(runs.drop(columns="C"), factors, "y")
    assert list(table["term"]) == ["A", "B", "A:B", "Curvature", "Residual"]
    assert table.loc[table["term"] == "Residual", "df"].item() == 2
    assert table["p_value"].iloc[:4].notna().all()
    assert "saturated" not in table.attrs["note"]


def test_level_means_interactions_and_effects_leave_the_centre_points_out() -> None:
    runs = _runs(1, 3)
    means = analysis.main_effects(runs, FACTORS, "y")
    cube = runs[runs.ct == 0]
    a = means[means["factor"] == "A"]
    assert list(a["n"]) == [4, 4]
    assert a["mean"].tolist() == pytest.approx(
        [cube.loc[cube.A == 10, "y"].mean(), cube.loc[cube.A == 20, "y"].mean()], rel=1e-12
    )
    assert means.attrs["center_n"] == 3
    assert means.attrs["center_mean"] == pytest.approx(runs.loc[runs.ct == 1, "y"].mean())
    cells = analysis.interaction_table(runs, FACTORS[0], FACTORS[1], "y")
    assert cells.shape == (2, 2) and cells.notna().all().all()
    assert analysis.alias_structure(runs[["A", "B", "C"]], FACTORS)["aliases"].eq("").all()
    ranked = analysis.ranked_effects(runs, FACTORS, "y")
    assert ranked.set_index("term").loc["Curvature", "kind"] == "curvature"
    assert math.isnan(ranked.set_index("term").loc["Curvature", "effect"])
    assert ranked.set_index("term").loc["A", "effect"] == pytest.approx(
        cube.loc[cube.A == 20, "y"].mean() - cube.loc[cube.A == 10, "y"].mean(), rel=1e-12
    )


@pytest.mark.parametrize(("replicates", "centre", "drop"), [(1, 3, ()), (2, 4, (1, 5))])
def test_effects_with_centre_points_are_the_saturated_model_with_a_centre_point_term(
    replicates, centre, drop
) -> None:
    runs = _runs(replicates, centre, drop)
    fit = ols("y ~ x1 * x2 * x3 + ct", runs).fit()
    effects = analysis.two_level_effects(runs, FACTORS, "y")
    assert effects.attrs["method"] == "pure error"
    assert effects.attrs["df"] == fit.df_resid
    terms = dict(_NAMES, **{"A:B:C": "x1:x2:x3", "Ct Pt": "ct"})
    assert effects["term"].iloc[-1] == "Ct Pt"  # last, as Minitab's coded coefficients end
    ct = effects.iloc[-1]
    assert math.isnan(ct["effect"]) and ct["order"] == 0
    assert ct["se"] == pytest.approx(2.0 * fit.bse["ct"], rel=1e-9)  # as the other rows
    assert ct["t"] == pytest.approx(fit.tvalues["ct"], rel=1e-9)
    assert ct["significant"] == (fit.pvalues["ct"] < 0.05)
    for _, row in effects.iloc[:-1].iterrows():
        name = terms[row["term"]]
        assert row["coefficient"] == pytest.approx(fit.params[name], rel=1e-9)
        assert row["se"] == pytest.approx(2.0 * fit.bse[name], rel=1e-9)
        assert row["p_value"] == pytest.approx(fit.pvalues[name], rel=1e-7)
    curvature = effects.attrs["curvature"]
    assert curvature["coefficient"] == pytest.approx(fit.params["ct"], rel=1e-9)
    assert curvature["se"] == pytest.approx(fit.bse["ct"], rel=1e-9)
    assert curvature["p_value"] == pytest.approx(fit.pvalues["ct"], rel=1e-7)
    assert effects.attrs["center_points"] == centre
    assert "Ct Pt" in effects.attrs["note"]


def test_one_centre_point_of_a_saturated_design_leaves_lenth() -> None:
    runs = _runs(1, 1)
    effects = analysis.two_level_effects(runs, FACTORS, "y")
    assert effects.attrs["method"] == "Lenth"
    assert math.isnan(effects.attrs["curvature"]["p_value"])
    assert "no error to test curvature against here" in effects.attrs["note"]
    assert "Ct Pt" not in list(effects["term"])  # not tested: no row
    # Lenth's effects are the factorial's alone
    cube = analysis.two_level_effects(runs[runs.ct == 0], FACTORS, "y")
    assert effects["effect"].tolist() == pytest.approx(cube["effect"].tolist(), rel=1e-12)


def test_report_sentence_on_curvature() -> None:
    curved = analysis.anova(_runs(1, 4), FACTORS, "y")
    text = _curvature_text(curved)
    assert "the 4 centre points' mean" in text and "significant" in text
    flat = _runs(1, 4)
    flat.loc[flat.ct == 1, "y"] -= 0.8  # no curvature left but the noise
    text = _curvature_text(analysis.anova(flat, FACTORS, "y"))
    assert "no evidence of curvature" in text
    assert _curvature_text(analysis.anova(flat[flat.ct == 0], FACTORS, "y")) == ""


def test_power_counts_the_centre_points_pure_error() -> None:
    plain = _design()
    design = _design(center_points=4)
    with_centre = power.factor_power(design, effect=1.0, sigma=1.0, replicates=[1])
    without = power.factor_power(plain, effect=1.0, sigma=1.0, replicates=[1])
    a = with_centre.set_index("factor").loc["A"]
    b = without.set_index("factor").loc["A"]
    # the 2^3 with its two-factor interactions leaves 1 df; the centre points add 3
    assert b["df_error"] == 1 and a["df_error"] == 4
    assert a["runs"] == 12 and a["power"] > b["power"]
    # 4 runs at a level, 1 apart: n / 2 = 2, with the centre points or not
    assert a["noncentrality"] == pytest.approx(2.0) and b["noncentrality"] == pytest.approx(2.0)


def test_curvature_confounded_with_a_factor_left_out_is_named_not_reported() -> None:
    """Both runs at B's second level failed: the centre points differ from the rest in B
    too, so their term is B's main effect as much as curvature (found by a review)."""
    factors = [Factor("A", (10.0, 20.0)), Factor("B", (0.0, 1.0))]
    runs = pd.DataFrame(
        [(10, 0), (20, 0), (10, 1), (20, 1), (15, 0.5), (15, 0.5), (15, 0.5)], columns=["A", "B"]
    )
    runs["y"] = 5 + 2 * (2 * runs.B - 1) + np.array([0.01, -0.02, 0.03, 0, 0.01, -0.01, 0.02])
    runs["status"] = ["ok", "ok", "failed", "failed", "ok", "ok", "ok"]
    table = analysis.anova(runs, factors, "y")
    assert table.set_index("term").loc["Curvature", "aliases"] == "B"
    assert "confounded with the main effect of B" in table.attrs["note"]
    text = _curvature_text(table)
    assert "not a test of curvature" in text and "significant" not in text
    effects = analysis.two_level_effects(runs, factors, "y")
    assert effects.attrs["curvature"]["aliases"] == "B"
    # with every run finished, nothing is confounded
    runs["status"] = "ok"
    assert analysis.anova(runs, factors, "y").set_index("term").loc["Curvature", "aliases"] == ""
    assert "aliases" not in analysis.two_level_effects(runs, factors, "y").attrs["curvature"]


def test_plackett_burman_residuals_are_of_the_anovas_main_effects_model() -> None:
    """analyze(main_effects_only=True) gives residuals of the model its ANOVA fits; the
    centre points' pure error had let the residuals keep interactions (a review)."""
    design = design_from_dict(
        {
            "name": "pb",
            "base": "paper",
            "root_seed": 1,
            "plackett_burman": 12,
            "center_points": 3,
            "factors": [
                {"name": "S", "levels": [0.0, 1.0]},
                {"name": "WP", "levels": [1e-15, 1e-13]},
                {"name": "WR", "levels": [1e-7, 1e-6]},
                {"name": "A", "levels": [10.0, 20.0]},
                {"name": "mu0", "field": "friction.mu_0", "levels": [0.5, 0.7]},
            ],
        }
    )
    runs = pd.DataFrame(design.combinations())
    runs["y"] = np.random.default_rng(2).normal(size=len(runs)) + runs["S"]
    runs["status"] = "ok"
    out = analysis.analyze(runs, design.factors, ["y"], main_effects_only=True)["y"]
    assert out["anova"].attrs["formula"] == "y ~ S + WP + WR + A + mu0 + Ct Pt"
    assert out["residuals"].attrs["formula"] == out["anova"].attrs["formula"]


def test_report_wording_for_one_centre_point_and_for_pure_error_of_centre_points() -> None:
    one = analysis.anova(_runs(1, 1), FACTORS, "y")
    assert "Curvature: the centre point's value against" in _curvature_text(one)
    from brakeca.report import _effects_table

    _, caption = _effects_table("y", analysis.two_level_effects(_runs(1, 3), FACTORS, "y"))
    assert "pure error of the centre points (2 degrees of freedom)" in caption
    # a screening review: every effect bold against the seeds' scatter at the centre
    assert "the seeds' scatter at the centre alone, which may be smaller than at the" in caption
    assert "Ct Pt, is the centre points' term: its coefficient is the 3 centre points' mean" in (
        caption
    )
    _, caption = _effects_table("y", analysis.two_level_effects(_runs(2, 3), FACTORS, "y"))
    assert "pure error of the replicates and centre points (10 degrees of freedom)" in caption
    lenth = analysis.two_level_effects(_runs(1, 1), FACTORS, "y")
    assert "1 centre point fitted by its own term" in lenth.attrs["note"]


@pytest.mark.parametrize(
    "name", ["Curvature", "Residual", "Model", "Linear", "Square", "Error", "Total", "Constant"]
)
def test_a_factor_cannot_be_named_after_an_anova_row(name) -> None:
    with pytest.raises(ConfigError, match=f"factor name '{name}' is a row of the analysis"):
        design_from_dict(
            {
                "name": "c",
                "base": "paper",
                "root_seed": 1,
                "factors": [{"name": name, "field": "S", "levels": [0.0, 1.0]}],
            }
        )


def test_the_effects_plot_leaves_the_centre_points_row_out(tmp_path) -> None:
    from brakeca.plotting import plot_effects

    effects = analysis.two_level_effects(_runs(1, 3), FACTORS, "y")
    fig = plot_effects(effects, "MU", path=tmp_path / "e.png")
    pareto = fig.axes[0]
    labels = [t.get_text() for t in pareto.get_yticklabels()]
    assert len(labels) == 7 and "Ct Pt" not in labels


def test_the_interaction_plot_marks_the_centre_points_mean(tmp_path) -> None:
    from brakeca.plotting import plot_interactions

    runs = _runs(1, 3)
    fig = plot_interactions(runs, FACTORS, "y", path=tmp_path / "i.png")
    marks = [
        line for ax in fig.axes for line in ax.get_lines() if line.get_label() == "centre points"
    ]
    assert len(marks) == 3  # one in each of the three panels of three factors
    centre = runs.loc[runs.ct == 1, "y"].mean()
    assert all(float(m.get_ydata()[0]) == pytest.approx(centre) for m in marks)
    assert all(float(m.get_xdata()[0]) == 0.5 for m in marks)
    no_centre = plot_interactions(runs[runs.ct == 0], FACTORS, "y")
    assert not [
        line
        for ax in no_centre.axes
        for line in ax.get_lines()
        if line.get_label() == "centre points"
    ]


def test_brakeca_design_shows_the_centre_and_notes_a_single_centre_point(tmp_path) -> None:
    from typer.testing import CliRunner

    from brakeca.cli import app

    res = CliRunner().invoke(
        app, ["design", "screen_center"], env={"COLUMNS": "200"}, terminal_width=200
    )
    assert res.exit_code == 0, res.output
    # the centre coded 0, as in the tests table (and the report's), where the levels are - / +
    assert "- = 0, + = 1, 0 = 0.5 " in res.output and "0 = 1e-14 (geometric)" in res.output
    rows = [line.split("│")[1:-1] for line in res.output.splitlines() if line.startswith("│  ")]
    tests = {int(r[0]): [c.strip() for c in r[1:]] for r in rows if r[0].strip().isdigit()}
    assert len(tests) == 20 and tests[17] == tests[20] == ["0"] * 7
    assert set(tests[1]) == {"-"} and set(tests[16]) == {"+"}
    assert "one centre point run" not in res.output
    one = tmp_path / "one.toml"
    one.write_text(_design(center_points=1).to_toml(), encoding="utf-8")
    res = CliRunner().invoke(app, ["design", str(one), "--no-tests"])
    assert res.exit_code == 0 and "one centre point run tests curvature but gives no" in (
        res.output
    )


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("center_points", 101, "a whole number of centre points, 0 to 100, got 101"),
        ("model_order", 0, "the most factors in a model term, a whole number from 1 to 10, got 0"),
        ("alpha_to_remove", 1, "a level above 0 and below 1 .0.1 in Minitab., got 1"),
        ("alpha_to_remove", "0.1", "a level above 0 and below 1"),
    ],
)
def test_out_of_range_keys_give_the_whole_range(key, value, message) -> None:
    with pytest.raises(ConfigError, match=f"{key}: expected {message}"):
        _design(**{key: value})


def test_brakeca_power_says_its_runs_include_the_centre_points() -> None:
    from typer.testing import CliRunner

    from brakeca.cli import app

    res = CliRunner().invoke(
        app, ["power", "screen_center", "--effect", "0.02", "--sigma", "0.013", "--replicates", "1"]
    )
    assert res.exit_code == 0, res.output
    assert "its 4 centre points among them" in res.output


def test_the_reports_effects_table_gives_t_as_coefficient_over_its_se_on_every_row() -> None:
    """The report shows Minitab's SE Coef, so t = coefficient / SE on every row, the Ct Pt
    row's too, which has no effect (it had shown twice its coefficient's SE in a column
    named "SE of effect", beside a t and a caption from the coefficient's; a helper's
    review of the report)."""
    from brakeca.report import _effects_table

    effects = analysis.two_level_effects(_runs(1, 3), FACTORS, "y")
    assert effects["term"].iloc[-1] == "Ct Pt"
    table, caption = _effects_table("y", effects)
    col = {name: i for i, name in enumerate(table.columns)}
    assert "SE of coefficient" in col
    for row in table.rows:
        cells = row["cells"]
        coef, se, t = (float(cells[col[c]]) for c in ("Coefficient", "SE of coefficient", "t"))
        assert t == pytest.approx(coef / se, rel=1e-2)  # t is shown to 3 digits
    se_ct = float(table.rows[-1]["cells"][col["SE of coefficient"]])
    assert f"(SE {se_ct:.4g}" in caption
