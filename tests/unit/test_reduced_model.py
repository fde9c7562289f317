"""Backward elimination of the factorial ANOVA model (``alpha_to_remove``), checked against
the same elimination done by hand with statsmodels: the model's terms, the table of the
model kept, and the residuals and effects that follow it."""

from __future__ import annotations

import itertools

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

    assert "for the terms of the model given" in _effects_table("y", result["effects"])[1]
    # without it: the whole model
    whole = analysis.analyze(runs, FACTORS, ["y"])["y"]["anova"]
    assert len(whole) == 7 and "backward" not in whole.attrs["note"]


def test_no_residual_degrees_of_freedom_removes_nothing() -> None:
    runs = _runs({"A": 1.0}, replicates=1).iloc[[0, 4]]  # A at its two levels, once each
    table = analysis.anova(runs, FACTORS[:1], "y", alpha_to_remove=0.1)
    assert list(table["term"]) == ["A", "Residual"]
    assert "no term removed" in table.attrs["note"]


@pytest.mark.parametrize("bad", [0.0, 1.0, 1.5, True, "0.1"])
def test_alpha_to_remove_is_checked(bad) -> None:
    with pytest.raises(ValueError, match="alpha_to_remove: expected a significance level"):
        analysis.anova(_runs({}), FACTORS, "y", alpha_to_remove=bad)
