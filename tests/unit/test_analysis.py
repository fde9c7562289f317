"""Tests of brakeca.analysis against hand computation on synthetic factorial tables.

References
----------
Wahlström (2016), doi:10.1155/2016/8181260, Tables 1-2 (the 2 x 3 x 2 x 2 design).
"""

from __future__ import annotations

import itertools
import math
import warnings
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from brakeca.analysis import (
    ANOVA_COLUMNS,
    MODEL_SUMMARY_COLUMNS,
    Factor,
    ResponseAnalysis,
    alias_structure,
    analyze,
    anova,
    as_factor,
    interaction_aliases,
    interaction_table,
    interaction_tables,
    interactions_long,
    main_effects,
    model_summary,
    ok_runs,
    ranked_effects,
    residuals,
    save_tables,
    two_level_effects,
)

S = Factor("S", (0.0, 1.0), "-", "Secondary plateaus removed", ("-", "+"))
WP = Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", "Specific wear rate", ("-", "0", "+"))
WR = Factor("WR", (1e-7, 1e-6), "m", "Resin wear depth", ("-", "+"))
A = Factor("A", (10.0, 20.0), "%", "Metal fibre area fraction", ("-", "+"))
FACTORS = (S, WP, WR, A)

#: The tables of one response's analysis (analyze), in order.
TABLES = (
    "main_effects",
    "interactions",
    "interactions_long",
    "anova",
    "ranked_effects",
    "residuals",
    "effects",
    "trends",
    "model_summary",
    "coefficients",
    "comparisons",
    "unusual",
)

# Known additive effects per level index and a known S x WP interaction.
EFFECT = {"S": (0.0, 0.02), "WP": (-0.01, 0.0, 0.015), "WR": (0.0, 0.003), "A": (0.0, 0.03)}
S_WP = ((0.0, 0.0, 0.0), (0.0, 0.004, 0.012))


def _design(replicates: int = 1, noise: float = 1e-3, seed: int = 7) -> pd.DataFrame:
    """The paper's 24-run design (S fastest, then WP, WR, A) with a synthetic MU and V."""
    rng = np.random.default_rng(seed)
    rows = []
    test = 0
    for a, wr, wp, s in itertools.product(range(2), range(2), range(3), range(2)):
        test += 1
        for r in range(replicates):
            mu = 0.40 + EFFECT["S"][s] + EFFECT["WP"][wp] + EFFECT["WR"][wr] + EFFECT["A"][a]
            mu += S_WP[s][wp] + noise * rng.standard_normal()
            v = 1e-10 * (1.0 + 2.0 * wp + 0.5 * a) * (1.0 + 0.05 * rng.standard_normal())
            rows.append(
                {
                    "test": test,
                    "run_id": f"t{test:02d}-r{r}",
                    "S": S.levels[s],
                    "WP": WP.levels[wp],
                    "WR": WR.levels[wr],
                    "A": A.levels[a],
                    "seed": 1000 * r + test,
                    "MU": mu,
                    "V": v,
                    "V_mm3": v * 1e9,
                    "wall_time": 1.0,
                    "status": "ok",
                }
            )
    return pd.DataFrame(rows)


def _hand_level_means(rows: pd.DataFrame, name: str, response: str) -> dict[float, float]:
    sums: dict[float, float] = {}
    counts: dict[float, int] = {}
    for _, row in rows.iterrows():
        key = float(row[name])
        sums[key] = sums.get(key, 0.0) + float(row[response])
        counts[key] = counts.get(key, 0) + 1
    return {k: sums[k] / counts[k] for k in sums}


def _hand_cell_means(rows: pd.DataFrame, a: str, b: str, response: str) -> dict:
    sums: dict[tuple[float, float], float] = {}
    counts: dict[tuple[float, float], int] = {}
    for _, row in rows.iterrows():
        key = (float(row[a]), float(row[b]))
        sums[key] = sums.get(key, 0.0) + float(row[response])
        counts[key] = counts.get(key, 0) + 1
    return {k: sums[k] / counts[k] for k in sums}


def _hand_ss_main(rows: pd.DataFrame, name: str, response: str) -> float:
    grand = sum(rows[response]) / len(rows)
    means = _hand_level_means(rows, name, response)
    total = 0.0
    for level, mean in means.items():
        n = sum(1 for v in rows[name] if float(v) == level)
        total += n * (mean - grand) ** 2
    return total


def _hand_ss_interaction(rows: pd.DataFrame, a: str, b: str, response: str) -> float:
    grand = sum(rows[response]) / len(rows)
    ma = _hand_level_means(rows, a, response)
    mb = _hand_level_means(rows, b, response)
    cells = _hand_cell_means(rows, a, b, response)
    total = 0.0
    for (la, lb), m in cells.items():
        n = sum(
            1
            for va, vb in zip(rows[a], rows[b], strict=True)
            if float(va) == la and float(vb) == lb
        )
        total += n * (m - ma[la] - mb[lb] + grand) ** 2
    return total


def _total_ss(rows: pd.DataFrame, response: str) -> float:
    y = [float(v) for v in rows[response]]
    grand = sum(y) / len(y)
    return sum((v - grand) ** 2 for v in y)


# --- Factor ----------------------------------------------------------------------------------


def test_factor_level_label_and_validation() -> None:
    assert WP.level_label(1e-14) == "0"
    assert WP.level_label(1.0000000001e-13) == "+"
    assert S.level_label(0.0) == "-"
    assert Factor("X", (1.0, 2.5)).level_label(2.5) == "2.5"
    assert WP.level_label(3e-14) == "3e-14"  # no matching level: the value itself
    assert WP.level_index(5.0) is None
    assert WP.axis_label == "WP [m³/(N·m)]"
    assert isinstance(Factor("X", [1, 2]).levels, tuple)
    with pytest.raises(ValueError, match="labels"):
        Factor("X", (1.0, 2.0), labels=("-",))
    with pytest.raises(ValueError, match="duplicate"):
        Factor("X", (1.0, 1.0))
    with pytest.raises(ValueError):
        Factor("", (1.0,))
    mapped = as_factor({"name": "A", "levels": [10, 20], "unit": "%", "labels": ["-", "+"]})
    assert mapped == Factor("A", (10.0, 20.0), "%", "", ("-", "+"))
    duck = SimpleNamespace(name="S", levels=(0, 1), unit="-", label="Secondary", labels=None)
    assert as_factor(duck) == Factor("S", (0.0, 1.0), "-", "Secondary")
    with pytest.raises(TypeError):
        as_factor(SimpleNamespace(name="X"))


# --- main effects and interactions -----------------------------------------------------------


def test_main_effects_match_hand_computation() -> None:
    rows = _design()
    table = main_effects(rows, FACTORS, "MU")
    assert list(table.columns) == ["factor", "level", "label", "mean", "n"]
    assert len(table) == 2 + 3 + 2 + 2
    for factor in FACTORS:
        hand = _hand_level_means(rows, factor.name, "MU")
        sub = table.loc[table["factor"] == factor.name]
        assert list(sub["level"]) == list(factor.levels)
        assert list(sub["label"]) == list(factor.labels)
        assert list(sub["n"]) == [24 // len(factor.levels)] * len(factor.levels)
        for level, mean in zip(sub["level"], sub["mean"], strict=True):
            assert mean == pytest.approx(hand[level], rel=1e-12)
    # Balanced design without noise: a level mean minus the grand mean is the level's effect.
    exact = main_effects(_design(noise=0.0), FACTORS, "MU")
    a = exact.loc[exact["factor"] == "A", "mean"].to_numpy()
    assert a[1] - a[0] == pytest.approx(0.03, rel=1e-9)


def test_interaction_table_matches_hand_computation() -> None:
    rows = _design()
    table = interaction_table(rows, S, WP, "MU")
    assert table.shape == (2, 3)
    assert table.index.name == "S" and table.columns.name == "WP"
    hand = _hand_cell_means(rows, "S", "WP", "MU")
    for la, lb in itertools.product(S.levels, WP.levels):
        assert table.loc[la, lb] == pytest.approx(hand[(la, lb)], rel=1e-12)
    # Known interaction: without noise the S:WP contrast recovers S_WP exactly.
    exact = interaction_table(_design(noise=0.0), S, WP, "MU").to_numpy()
    contrast = exact[1] - exact[0] - (exact[1, 0] - exact[0, 0])
    assert contrast == pytest.approx(np.array(S_WP[1]) - S_WP[1][0], abs=1e-12)

    tables = interaction_tables(rows, FACTORS, "MU")
    assert list(tables) == [
        ("S", "WP"),
        ("S", "WR"),
        ("S", "A"),
        ("WP", "WR"),
        ("WP", "A"),
        ("WR", "A"),
    ]
    by_name = interaction_table(rows, "WR", "A", "MU")
    assert np.allclose(by_name.to_numpy(), tables[("WR", "A")].to_numpy(), rtol=1e-12)

    long = interactions_long(rows, FACTORS, "MU")
    assert len(long) == sum(len(a.levels) * len(b.levels) for a, b in tables_pairs())
    assert set(long["n"]) == {4, 6}  # 24 runs / 6 or 4 cells per pair
    one = long[(long["factor_a"] == "S") & (long["factor_b"] == "WP")]
    assert np.allclose(one["mean"].to_numpy(), table.to_numpy().ravel(), rtol=1e-12)


def tables_pairs() -> list[tuple[Factor, Factor]]:
    return list(itertools.combinations(FACTORS, 2))


# --- ANOVA -----------------------------------------------------------------------------------


def test_anova_unreplicated_matches_hand_sums_of_squares() -> None:
    rows = _design(noise=1e-3)
    table = anova(rows, FACTORS, "MU")
    assert list(table.columns) == list(ANOVA_COLUMNS)
    expected_terms = ["S", "WP", "WR", "A", "S:WP", "S:WR", "S:A", "WP:WR", "WP:A", "WR:A"]
    assert list(table["term"]) == [*expected_terms, "Residual"]
    df = dict(zip(table["term"], table["df"], strict=True))
    assert df["WP"] == 2 and df["S:WP"] == 2 and df["WP:A"] == 2 and df["S"] == 1
    assert df["Residual"] == 23 - 14
    total = _total_ss(rows, "MU")
    assert table["sum_sq"].sum() == pytest.approx(total, rel=1e-10)
    assert table["percent_contribution"].sum() == pytest.approx(100.0, rel=1e-10)
    ss = dict(zip(table["term"], table["sum_sq"], strict=True))
    for factor in FACTORS:
        assert ss[factor.name] == pytest.approx(_hand_ss_main(rows, factor.name, "MU"), rel=1e-9)
    for a, b in itertools.combinations(FACTORS, 2):
        hand = _hand_ss_interaction(rows, a.name, b.name, "MU")
        assert ss[f"{a.name}:{b.name}"] == pytest.approx(hand, rel=1e-8, abs=1e-15)
    assert (table["note"] == "").all()
    assert table.attrs["typ"] == "Type II"
    p = dict(zip(table["term"], table["p_value"], strict=True))
    assert p["S:WP"] < 1e-3 and p["A"] < 1e-6  # the known effects are found
    assert math.isnan(p["Residual"])
    ms = table["sum_sq"] / table["df"]
    assert np.allclose(table["mean_sq"], ms, rtol=1e-12)


def test_anova_replicated_residual_is_pure_error() -> None:
    # Two factors with their interaction: the model holds every cell, the residual is the
    # within-cell (seed-to-seed) scatter only.
    rows = _design(replicates=2, noise=2e-3)
    rows = rows[(rows["WR"] == WR.levels[0]) & (rows["A"] == A.levels[0])]
    assert len(rows) == 12
    table = anova(rows, [S, WP], "MU")
    resid = table.loc[table["term"] == "Residual"].iloc[0]
    assert resid["df"] == 12 - 6
    cells = _hand_cell_means(rows, "S", "WP", "MU")
    pure = sum(
        (float(r["MU"]) - cells[(float(r["S"]), float(r["WP"]))]) ** 2 for _, r in rows.iterrows()
    )
    assert resid["sum_sq"] == pytest.approx(pure, rel=1e-9)
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(rows, "MU"), rel=1e-10)
    assert table.loc[table["term"] != "Residual", "F"].notna().all()

    full = _design(replicates=2, noise=2e-3)
    table = anova(full, FACTORS, "MU")
    assert table.loc[table["term"] == "Residual", "df"].item() == 48 - 1 - 14
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(full, "MU"), rel=1e-10)


def test_anova_saturated_falls_back_without_crashing() -> None:
    rows = _design()
    rows = rows[(rows["WR"] == WR.levels[0]) & (rows["A"] == A.levels[0])]  # 2 x 3, n = 6
    table = anova(rows, [S, WP], "MU")
    assert list(table["term"]) == ["S", "WP", "Residual"]
    assert "saturated" in table["note"].iloc[0]
    assert "saturated" in table.attrs["note"]
    resid = table.loc[table["term"] == "Residual"].iloc[0]
    assert resid["df"] == 2
    # The pooled residual is the S:WP interaction sum of squares.
    hand = _hand_ss_interaction(rows, "S", "WP", "MU")
    assert resid["sum_sq"] == pytest.approx(hand, rel=1e-9)
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(rows, "MU"), rel=1e-10)

    # Even the main-effects model is saturated: F and p are NaN, with a note.
    two = rows[rows["WP"] == WP.levels[0]]
    table = anova(two, [S], "MU")
    assert list(table["term"]) == ["S", "Residual"]
    assert table["F"].isna().all() and table["p_value"].isna().all()
    assert "F and p cannot be computed" in table["note"].iloc[0]
    # a full-rank design: the Type II sums of squares are defined without residual degrees
    # of freedom (statsmodels' anova_lm cannot give them then; they come from the columns)
    assert table.attrs["typ"] == "Type II"
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(two, "MU"), rel=1e-10)
    assert "sequential" not in table.attrs["note"]

    # A factor that does not vary, and a single run: still no exception.
    table = anova(two, [S, WP], "MU")
    assert "single level" in table["note"].iloc[0]
    assert anova(two.iloc[:1], [S], "MU").empty

    # Main effects only on a saturated-with-interactions design works as usual.
    table = anova(rows, [S, WP], "MU", interactions=False)
    assert table["note"].iloc[0] == ""
    assert table.loc[table["term"] == "Residual", "df"].item() == 2


def test_perfect_fit_and_constant_response_do_not_warn() -> None:
    rows = _design(noise=0.0)
    table = anova(rows, FACTORS, "MU")
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(rows, "MU"), rel=1e-9)
    rows = rows.assign(MU=0.4)
    table = anova(rows, FACTORS, "MU")
    assert table["F"].isna().all()
    assert "constant" in table["note"].iloc[0]


def test_status_and_missing_values_are_excluded() -> None:
    rows = _design()
    rows.loc[3, "status"] = "failed"
    rows.loc[3, "MU"] = 99.0
    rows.loc[5, "V"] = np.nan
    assert len(ok_runs(rows)) == 23
    assert len(ok_runs(rows.drop(columns="status"))) == 24
    table = main_effects(rows, FACTORS, "MU")
    assert table.groupby("factor")["n"].sum().eq(23).all()
    assert table["mean"].max() < 1.0
    assert main_effects(rows, FACTORS, "V").groupby("factor")["n"].sum().eq(22).all()
    unbalanced = anova(rows, FACTORS, "MU")
    assert unbalanced.loc[unbalanced["term"] == "Residual", "df"].item() == 8
    assert "unbalanced" in unbalanced["note"].iloc[0]
    with pytest.raises(KeyError, match="nope"):
        main_effects(rows, FACTORS, "nope")
    bad = rows.copy()
    bad.loc[0, "WP"] = 5e-14
    with pytest.raises(ValueError, match="match none"):
        main_effects(bad, FACTORS, "MU")


def test_ranked_effects_order_and_classical_effects() -> None:
    rows = _design(noise=1e-3)
    ranked = ranked_effects(rows, FACTORS, "MU")
    assert len(ranked) == 10
    assert "Residual" not in set(ranked["term"])
    assert (np.diff(ranked["sum_sq"].to_numpy()) <= 0).all()
    assert list(ranked["rank"]) == list(range(1, 11))
    assert ranked["cumulative_percent"].iloc[-1] == pytest.approx(
        ranked["percent_contribution"].sum()
    )
    effect = dict(zip(ranked["term"], ranked["effect"], strict=True))
    means = _hand_level_means(rows, "S", "MU")
    assert effect["S"] == pytest.approx(means[1.0] - means[0.0], rel=1e-12)
    cells = _hand_cell_means(rows, "WR", "A", "MU")
    lo, hi = WR.levels
    a0, a1 = A.levels
    hand = (cells[(hi, a1)] - cells[(hi, a0)] - cells[(lo, a1)] + cells[(lo, a0)]) / 2
    assert effect["WR:A"] == pytest.approx(hand, rel=1e-9)
    assert math.isnan(effect["WP"]) and math.isnan(effect["S:WP"])
    kinds = dict(zip(ranked["term"], ranked["kind"], strict=True))
    assert kinds["S"] == "main" and kinds["S:WP"] == "interaction"
    assert ranked["term"].iloc[0] == "A"  # the largest known effect (0.03 on half the runs)


def test_each_response_s_analysis_is_a_dataclass_and_a_mapping_of_its_tables() -> None:
    """analyze() returns a ResponseAnalysis per response (the style guide's result
    dataclass); each table is an attribute and an item by the same name (the dict it
    returned before), so code written against the dict reads it unchanged."""
    bundle = analyze(_design(replicates=2), FACTORS, ["MU"])["MU"]
    assert isinstance(bundle, ResponseAnalysis)
    assert list(bundle) == list(TABLES)
    assert len(bundle) == 12
    for name in bundle:
        assert bundle[name] is getattr(bundle, name)
    assert bundle.get("anova") is bundle.anova and bundle.get("fit") is None
    assert "anova" in bundle and "fit" not in bundle and 0 not in bundle
    with pytest.raises(KeyError, match="fit"):
        bundle["fit"]
    assert dict(bundle)["trends"] is bundle.trends
    with pytest.raises(AttributeError):  # frozen, as a result should be
        bundle.anova = bundle.effects  # type: ignore[misc]
    shown = repr(bundle)
    assert shown.startswith("ResponseAnalysis('MU ~ S + WP + ")
    assert "anova=11x9" in shown and "interactions=6 tables" in shown


def test_a_finished_run_without_a_finite_response_is_named_not_dropped_silently() -> None:
    """A run of status ok whose response is NaN (or log10 of a V of 0) is left out of the
    fit; the ANOVA's note had said only "unbalanced design" (an API review)."""
    rows = _design(replicates=2)
    rows.loc[[4, 31], "MU"] = [np.nan, np.inf]
    table = anova(rows, FACTORS, "MU")
    assert table.attrs["note"].startswith(
        "2 finished run(s) left out, MU not a finite number: test 3, test 16; unbalanced design"
    )
    assert table.attrs["n"] == len(rows) - 2
    assert anova(_design(replicates=2), FACTORS, "MU").attrs["note"] == ""
    few = _design(replicates=1).iloc[:3].assign(MU=[0.3, np.nan, np.nan])
    assert anova(few, FACTORS, "MU").attrs["note"] == (
        "only 1 usable run(s) for MU; no ANOVA possible (2 finished run(s) left out, MU not a "
        "finite number: test 2, test 3)"
    )
    rows["replicate"] = rows.groupby("test").cumcount()  # replicates are named where they differ
    assert (
        anova(rows, FACTORS, "MU")
        .attrs["note"]
        .startswith(
            "2 finished run(s) left out, MU not a finite number: test 3 replicate 0, test 16 "
            "replicate 1;"
        )
    )


def test_save_tables_names_what_it_takes(tmp_path) -> None:
    """One response's analysis had given "KeyError: 'main_effects'", which it has; a file
    where the folder goes, a bare FileExistsError (an API review)."""
    result = analyze(_design(replicates=2), FACTORS, ["MU"])
    with pytest.raises(TypeError, match=r"one response's analysis; save_tables takes analyze"):
        save_tables(result["MU"], tmp_path)
    a_file = tmp_path / "run.nc"
    a_file.write_bytes(b"")
    with pytest.raises(NotADirectoryError, match=r"directory: .*run.nc exists and is not a"):
        save_tables(result, a_file)
    assert not result["MU"].unusual.empty  # this seed's noise has one run beyond ±2
    assert len(save_tables({"MU": result["MU"]}, tmp_path / "tables")) == 11


def test_analyze_and_save_tables(tmp_path) -> None:
    rows = _design(replicates=2)
    result = analyze(rows, FACTORS)
    assert set(result) == {"MU", "V"}
    for bundle in result.values():
        assert set(bundle) == set(TABLES)
        assert bundle["effects"].empty  # WP has three levels: no two-level effects table
        assert bundle["model_summary"].equals(model_summary(bundle["anova"]))
        assert list(bundle["trends"]["factor"]) == ["WP", "WP"]  # but a trend
    written = save_tables(result, tmp_path / "tables")
    names = sorted(p.name for p in written)
    stems = ("main_effects", "interactions", "anova", "model_summary", "ranked_effects")
    stems = (*stems, "residuals", "trends", "coefficients", "comparisons", "grouping")
    unusual = [f"unusual_{r}.csv" for r in ("MU", "V") if not result[r].unusual.empty]
    expected = [f"{stem}_{r}.csv" for stem in stems for r in ("MU", "V")]
    assert names == sorted(expected + unusual)
    summary_mu = pd.read_csv(tmp_path / "tables" / "model_summary_MU.csv")
    assert list(summary_mu.columns) == list(MODEL_SUMMARY_COLUMNS)
    assert summary_mu["r_squared"].item() == pytest.approx(result["MU"]["anova"].attrs["r_squared"])
    # the model is written with its response, as the report writes it (it had read "y ~ ...")
    assert summary_mu["formula"].item().startswith("MU ~ S + WP + ")
    assert result["V"]["residuals"].attrs["formula"].startswith("V ~ S + WP + ")
    for path in written:
        assert path.stat().st_size > 0
    anova_v = pd.read_csv(tmp_path / "tables" / "anova_V.csv", keep_default_na=False)
    assert list(anova_v.columns) == list(ANOVA_COLUMNS)
    inter = pd.read_csv(tmp_path / "tables" / "interactions_MU.csv")
    assert len(inter) == sum(len(a.levels) * len(b.levels) for a, b in tables_pairs())
    # A hand-built result with only the wide interaction tables is accepted too.
    slim = {"MU": {k: v for k, v in result["MU"].items() if k != "interactions_long"}}
    save_tables(slim, tmp_path / "slim")
    assert len(pd.read_csv(tmp_path / "slim" / "interactions_MU.csv")) == len(inter)


@settings(max_examples=25, deadline=None)
@given(
    replicates=st.integers(1, 3),
    values=st.lists(
        st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False), min_size=18, max_size=18
    ),
)
def test_anova_sum_of_squares_adds_up(replicates: int, values: list[float]) -> None:
    f1 = Factor("P", (1.0, 2.0))
    f2 = Factor("Q", (1.0, 2.0, 3.0))
    rows = [
        {"P": p, "Q": q, "y": values[k]}
        for k, (r, p, q) in enumerate(itertools.product(range(replicates), f1.levels, f2.levels))
    ]
    frame = pd.DataFrame(rows)
    table = anova(frame, [f1, f2], "y")
    total = _total_ss(frame, "y")
    assert table["sum_sq"].sum() == pytest.approx(total, rel=1e-9, abs=1e-9)


@settings(max_examples=25, deadline=None)
@given(
    replicates=st.integers(2, 3),
    dropped=st.integers(0, 5),
    values=st.lists(
        st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False), min_size=18, max_size=18
    ),
)
def test_anova_matches_statsmodels_term_by_term_unbalanced(
    replicates: int, dropped: int, values: list[float]
) -> None:
    """Each term's sum of squares, F and p against statsmodels' Type II ANOVA, with one run
    of a cell dropped (unbalanced: Type I, II and III differ there; the additivity above
    holds for all of them on balanced data, so it checked no term: a tests review)."""
    import statsmodels.formula.api as smf
    from statsmodels.stats.anova import anova_lm

    f1 = Factor("P", (1.0, 2.0))
    f2 = Factor("Q", (1.0, 2.0, 3.0))
    rows = [
        {"P": p, "Q": q, "y": values[k]}
        for k, (r, p, q) in enumerate(itertools.product(range(replicates), f1.levels, f2.levels))
    ]
    frame = pd.DataFrame(rows).drop(index=dropped).reset_index(drop=True)
    assume(_total_ss(frame, "y") > 1e-6)  # (a constant response: statsmodels' sums are NaN)
    table = anova(frame, [f1, f2], "y").set_index("term")
    with warnings.catch_warnings():  # (a constant response: statsmodels' rank warnings)
        warnings.simplefilter("ignore")
        ref = anova_lm(smf.ols("y ~ C(P) + C(Q) + C(P):C(Q)", frame).fit(), typ=2)
    scale = max(1.0, _total_ss(frame, "y"))
    for name, term in (
        ("P", "C(P)"),
        ("Q", "C(Q)"),
        ("P:Q", "C(P):C(Q)"),
        ("Residual", "Residual"),
    ):
        assert table.loc[name, "df"] == ref.loc[term, "df"], name
        assert table.loc[name, "sum_sq"] == pytest.approx(
            ref.loc[term, "sum_sq"], rel=1e-9, abs=1e-9 * scale
        ), name
    residual = ref.loc["Residual", "sum_sq"]
    if residual > 1e-6 * scale:  # F and p are defined (not a response fitted exactly)
        for name, term in (("P", "C(P)"), ("Q", "C(Q)"), ("P:Q", "C(P):C(Q)")):
            assert table.loc[name, "F"] == pytest.approx(ref.loc[term, "F"], rel=1e-6, abs=1e-9)
            assert table.loc[name, "p_value"] == pytest.approx(
                ref.loc[term, "PR(>F)"], rel=1e-6, abs=1e-12
            )


def test_anova_with_an_empty_cell_uses_sequential_sums_of_squares() -> None:
    rows = _design(noise=1e-3)
    rows = rows[~((rows["S"] == 1.0) & (rows["WP"] == 1e-13))]  # the S+ WP+ cell failed
    table = anova(rows, FACTORS, "MU")
    assert (
        table.attrs["typ"] == "Type I (sequential; the design is rank-deficient, e.g. empty cells)"
    )
    assert "sequential" in table["note"].iloc[0]
    df = dict(zip(table["term"], table["df"], strict=True))
    assert df["S:WP"] == 1  # one of the two interaction contrasts is not estimable
    assert df["Residual"] == len(rows) - 1 - sum(v for k, v in df.items() if k != "Residual")
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(rows, "MU"), rel=1e-10)
    assert table.loc[table["term"] != "Residual", "p_value"].notna().all()


def _loo_press(rows: pd.DataFrame, response: str) -> float:
    """PRESS the slow, obvious way: refit without each run and predict it."""
    import statsmodels.formula.api as smf

    formula = "y ~ " + " + ".join(
        [f"C({f.name})" for f in FACTORS]
        + [f"C({a.name}):C({b.name})" for a, b in itertools.combinations(FACTORS, 2)]
    )
    frame = rows[[f.name for f in FACTORS]].copy()
    frame["y"] = rows[response].to_numpy(dtype=float)
    frame = frame.reset_index(drop=True)
    press = 0.0
    for i in range(len(frame)):
        fit = smf.ols(formula, data=frame.drop(index=i)).fit()
        press += float(frame["y"][i] - fit.predict(frame.iloc[[i]]).item()) ** 2
    return press


@pytest.mark.parametrize("replicates", [1, 2])
def test_model_summary_and_residuals_match_statsmodels_and_refits(replicates: int) -> None:
    import statsmodels.formula.api as smf

    rows = _design(replicates=replicates, noise=2e-3)
    table = anova(rows, FACTORS, "MU")
    formula = "MU ~ " + " + ".join(
        [f"C({f.name})" for f in FACTORS]
        + [f"C({a.name}):C({b.name})" for a, b in itertools.combinations(FACTORS, 2)]
    )
    fit = smf.ols(formula, data=rows).fit()
    attrs = table.attrs
    assert attrs["df_resid"] == fit.df_resid == table.loc[table["term"] == "Residual", "df"].item()
    assert attrs["s"] == pytest.approx(math.sqrt(fit.mse_resid), rel=1e-9)
    assert attrs["r_squared"] == pytest.approx(fit.rsquared, rel=1e-9)
    assert attrs["r_squared_adj"] == pytest.approx(fit.rsquared_adj, rel=1e-9)
    press = _loo_press(rows, "MU")
    assert attrs["r_squared_pred"] == pytest.approx(1.0 - press / _total_ss(rows, "MU"), rel=1e-8)
    assert attrs["r_squared_pred"] < attrs["r_squared_adj"] < attrs["r_squared"] < 1.0

    res = residuals(rows, FACTORS, "MU")
    assert len(res) == len(rows)
    assert list(res["test"]) == list(rows["test"])
    assert np.allclose(res["observed"], rows["MU"], rtol=0, atol=0)
    assert np.allclose(res["fitted"], fit.fittedvalues, rtol=0, atol=1e-12)
    assert np.allclose(res["residual"], fit.resid, rtol=0, atol=1e-12)
    influence = fit.get_influence()
    assert np.allclose(res["leverage"], influence.hat_matrix_diag, rtol=1e-9)
    assert np.allclose(res["std_residual"], influence.resid_studentized_internal, rtol=1e-7)
    # A balanced full factorial: every run has the same leverage, p / n.
    assert np.allclose(res["leverage"], (1 + 5 + 9) / len(rows), rtol=1e-9)
    assert res.attrs["s"] == pytest.approx(attrs["s"], rel=1e-12)


def test_model_summary_where_statistics_are_not_defined() -> None:
    rows = _design()
    two = rows[(rows["WR"] == WR.levels[0]) & (rows["A"] == A.levels[0])].copy()
    # 2 x 3 cells, one run each, main effects only (interactions pooled): defined.
    pooled = anova(two, [S, WP], "MU")
    assert pooled.attrs["df_resid"] == 2 and math.isfinite(pooled.attrs["r_squared_pred"])
    # One factor per cell and a single run each: saturated, nothing but R-squared is defined.
    one = two[two["S"] == S.levels[0]]
    saturated = anova(one, [WP], "MU")
    assert saturated.attrs["df_resid"] == 0
    assert saturated.attrs["r_squared"] == pytest.approx(1.0)
    for key in ("s", "r_squared_adj", "r_squared_pred"):
        assert math.isnan(saturated.attrs[key]), key
    res = residuals(one, [WP], "MU")
    assert np.allclose(res["leverage"], 1.0) and res["std_residual"].isna().all()
    # A constant response: no R-squared.
    flat = rows.assign(MU=0.4)
    constant = anova(flat, FACTORS, "MU")
    assert math.isnan(constant.attrs["r_squared"]) and constant.attrs["s"] < 1e-12
    assert residuals(flat, FACTORS, "MU")["std_residual"].isna().all()
    summary = model_summary(constant)
    assert list(summary.columns) == list(MODEL_SUMMARY_COLUMNS) and len(summary) == 1


def test_lack_of_fit_and_pure_error_match_the_nested_model_test() -> None:
    import statsmodels.formula.api as smf
    from statsmodels.stats.anova import anova_lm

    rows = _design(replicates=2, noise=2e-3)
    # A three-factor interaction the two-factor model cannot hold: lack of fit to find.
    bump = np.where((rows["S"] == 1.0) & (rows["WR"] == 1e-6) & (rows["A"] == 20.0), 0.03, 0.0)
    rows = rows.assign(MU=rows["MU"] + bump)
    attrs = anova(rows, FACTORS, "MU").attrs
    cells = _hand_cell_means_all(rows, "MU")
    pure = sum(
        (float(r["MU"]) - cells[tuple(float(r[f.name]) for f in FACTORS)]) ** 2
        for _, r in rows.iterrows()
    )
    assert attrs["pure_error_df"] == 48 - 24 and attrs["lack_of_fit_df"] == 33 - 24
    assert attrs["pure_error_ss"] == pytest.approx(pure, rel=1e-9)
    two = " + ".join(
        [f"C({f.name})" for f in FACTORS]
        + [f"C({a.name}):C({b.name})" for a, b in itertools.combinations(FACTORS, 2)]
    )
    full = "C(S) * C(WP) * C(WR) * C(A)"
    nested = anova_lm(smf.ols(f"MU ~ {two}", rows).fit(), smf.ols(f"MU ~ {full}", rows).fit())
    assert attrs["lack_of_fit_F"] == pytest.approx(nested["F"].iloc[1], rel=1e-8)
    assert attrs["lack_of_fit_p"] == pytest.approx(nested["Pr(>F)"].iloc[1], rel=1e-6)
    assert attrs["lack_of_fit_p"] < 1e-3
    assert model_summary(anova(rows, FACTORS, "MU"))["lack_of_fit_p"].item() == pytest.approx(
        attrs["lack_of_fit_p"]
    )
    # Without replicates there is no pure error; with a model that holds every cell, no
    # lack of fit.
    single = anova(_design(), FACTORS, "MU").attrs
    assert single["pure_error_df"] == 0 and math.isnan(single["lack_of_fit_p"])
    cellwise = rows[(rows["WR"] == WR.levels[0]) & (rows["A"] == A.levels[0])]
    held = anova(cellwise, [S, WP], "MU").attrs
    assert held["lack_of_fit_df"] == 0 and math.isnan(held["lack_of_fit_F"])
    assert held["pure_error_ss"] == pytest.approx(held["s"] ** 2 * held["df_resid"], rel=1e-9)


def _hand_cell_means_all(rows: pd.DataFrame, response: str) -> dict:
    sums: dict[tuple[float, ...], list[float]] = {}
    for _, row in rows.iterrows():
        key = tuple(float(row[f.name]) for f in FACTORS)
        sums.setdefault(key, []).append(float(row[response]))
    return {k: sum(v) / len(v) for k, v in sums.items()}


# --- fractional designs: aliasing and two-level effects -----------------------------------


def _two_level(
    names: str, generators: dict[str, str], effects: dict[str, float], **kw
) -> pd.DataFrame:
    """A regular two-level fraction in standard order: the base factors (those not generated)
    form a full factorial, first fastest; a generated factor's coded level (-1/+1) is the
    product of its word's. ``effects`` maps a term (``"A"``, ``"A:D"``) to its coefficient on
    the coded columns; levels are 0 and 1 in the table."""
    rng = np.random.default_rng(kw.get("seed", 3))
    base = [n for n in names if n not in generators]
    rows = []
    for replicate in range(kw.get("replicates", 1)):
        for combo in itertools.product((-1, 1), repeat=len(base)):
            x = dict(zip(base, reversed(combo), strict=True))
            for name, word in generators.items():
                x[name] = int(np.prod([x[f] for f in word]))
            y = 10.0 + sum(c * np.prod([x[f] for f in t.split(":")]) for t, c in effects.items())
            y += kw.get("noise", 0.2) * rng.standard_normal()
            rows.append({**{n: (x[n] + 1) / 2 for n in names}, "y": y, "replicate": replicate})
    return pd.DataFrame(rows)


def _levels01(names: str) -> list[Factor]:
    return [Factor(n, (0.0, 1.0)) for n in names]


def test_full_factorial_has_no_aliases() -> None:
    table = anova(_design(noise=1e-3), FACTORS, "MU")
    assert (table["aliases"] == "").all()
    assert "aliased" not in table.attrs["note"]


def test_half_fraction_leaves_aliased_interactions_out() -> None:
    # 2^(4-1), D = ABC: I = ABCD, so A = BCD, AB = CD, AC = BD, AD = BC
    rows = _two_level("ABCD", {"D": "ABC"}, {"A": 1.0, "B": 0.5})
    table = anova(rows, _levels01("ABCD"), "y")
    note = table.attrs["note"]
    for left_out, kept in (("C:D", "A:B"), ("B:D", "A:C"), ("B:C", "A:D")):
        assert f"{left_out} (aliased with {kept})" in note
    aliases = dict(zip(table["term"], table["aliases"], strict=True))
    assert aliases["A"] == "B:C:D" and aliases["D"] == "A:B:C"
    # mains + 3 interaction chains saturate the 8 runs: the chains are pooled, 3 df remain
    assert list(table["term"]) == ["A", "B", "C", "D", "Residual"]
    assert table.loc[table["term"] == "Residual", "df"].item() == 3
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(rows, "y"), rel=1e-10)
    # a main effect's sum of squares is N/4 times its effect squared (orthogonal columns)
    y, a = rows["y"].to_numpy(), rows["A"].to_numpy()
    effect = y[a == 1].mean() - y[a == 0].mean()
    assert table.loc[table["term"] == "A", "sum_sq"].item() == pytest.approx(8 / 4 * effect**2)


def test_resolution_three_fraction_aliases_mains_with_interactions() -> None:
    rows = _two_level("ABC", {"C": "AB"}, {"A": 1.0})  # 2^(3-1), I = ABC
    table = anova(rows, _levels01("ABC"), "y")
    assert list(table["term"]) == ["A", "B", "C", "Residual"]
    assert dict(zip(table["term"], table["aliases"], strict=True))["A"] == "B:C"
    assert "A:B (aliased with C)" in table.attrs["note"]
    assert "F and p cannot be computed" in table.attrs["note"]  # 4 runs, 4 parameters


def test_mixed_level_fraction_keeps_the_three_level_factor_crossed() -> None:
    # WP (3 levels) crossed with the 2^(3-1) of S, WR, A with A = S*WR, two seeds a test
    rows = []
    rng = np.random.default_rng(5)
    for _, wp, wr, s in itertools.product(range(2), range(3), (-1, 1), (-1, 1)):
        a = s * wr
        rows.append({"S": S.levels[(s + 1) // 2], "WP": WP.levels[wp]})
        rows[-1].update({"WR": WR.levels[(wr + 1) // 2], "A": A.levels[(a + 1) // 2]})
        rows[-1]["MU"] = 0.3 + 0.02 * s + 0.05 * a + 0.01 * wp + 1e-3 * rng.standard_normal()
    frame = pd.DataFrame(rows)
    table = anova(frame, FACTORS, "MU")
    note = table.attrs["note"]
    for left_out, kept in (("S:WR", "A"), ("S:A", "WR"), ("WR:A", "S")):
        assert f"{left_out} (aliased with {kept})" in note
    assert list(table["term"]) == ["S", "WP", "WR", "A", "S:WP", "WP:WR", "WP:A", "Residual"]
    aliases = dict(zip(table["term"], table["aliases"], strict=True))
    assert aliases["S"] == "WR:A" and aliases["WP"] == ""
    assert aliases["S:WP"] == "WP:WR:A"  # WP x (S = WR A)
    assert table.loc[table["term"] == "Residual", "df"].item() == 24 - 12
    assert table["sum_sq"].sum() == pytest.approx(_total_ss(frame, "MU"), rel=1e-9)
    # unreplicated, the model with the WP interactions saturates the 12 runs: mains only
    table = anova(frame.iloc[:12], FACTORS, "MU")
    assert list(table["term"]) == ["S", "WP", "WR", "A", "Residual"]


def _lenth_by_hand(effects: list[float]) -> float:
    magnitude = sorted(abs(e) for e in effects)
    s0 = 1.5 * float(np.median(magnitude))
    return 1.5 * float(np.median([m for m in magnitude if m < 2.5 * s0]))


@pytest.mark.parametrize("alpha", [5, 1.0, 0.0, -1, "0.05", True])
def test_two_level_effects_refuse_an_alpha_outside_0_1(alpha) -> None:
    """alpha=5 had marked every effect significant and alpha=-1 none (a helper's review)."""
    rows = _two_level("ABC", {}, {"A": 3.0}, noise=0.3)
    with pytest.raises(ValueError, match=r"^alpha: expected a level above 0 and below 1"):
        two_level_effects(rows, _levels01("ABC"), "y", alpha=alpha)


def test_two_level_effects_of_an_unreplicated_fraction_use_lenth() -> None:
    from scipy import stats

    # 2^(7-3), resolution IV: E = ABC, F = BCD, G = ACD, so AD = CG = EF
    gens = {"E": "ABC", "F": "BCD", "G": "ACD"}
    rows = _two_level("ABCDEFG", gens, {"A": 3.0, "D": -2.0, "A:D": 1.5}, noise=0.3)
    effects = two_level_effects(rows, _levels01("ABCDEFG"), "y")
    assert len(effects) == 15  # a saturated model: 16 runs, 15 effects
    assert list(effects["term"].iloc[:3]) == ["A", "D", "A:D"]  # the active ones, by |t|
    assert effects["significant"].iloc[:3].all() and not effects["significant"].iloc[3:].any()
    by_term = effects.set_index("term")
    y = rows["y"].to_numpy()
    for name in "ABCDEFG":
        x = rows[name].to_numpy()
        assert by_term.loc[name, "effect"] == pytest.approx(y[x == 1].mean() - y[x == 0].mean())
    assert set(by_term.loc["A:D", "aliases"].split(" + ")) >= {"C:G", "E:F"}
    pse = _lenth_by_hand(list(effects["effect"]))
    assert effects.attrs["method"] == "Lenth" and effects.attrs["pse"] == pytest.approx(pse)
    assert effects.attrs["df"] == pytest.approx(5.0)
    t = by_term.loc["A", "effect"] / pse
    assert by_term.loc["A", "t"] == pytest.approx(t)
    assert by_term.loc["A", "p_value"] == pytest.approx(2 * stats.t.sf(abs(t), 5.0))
    assert effects.attrs["margin_of_error"] == pytest.approx(stats.t.ppf(0.975, 5.0) * pse)


def test_lenth_on_a_response_without_scatter_says_t_measures_round_off() -> None:
    """A deterministic response (no seed-to-seed scatter) leaves the nil effects at round-off,
    so Lenth's PSE is 1e-16 and t reaches 1e15: a note says so; with scatter, no note."""
    rows = _two_level("ABCD", {}, {"A": 3.0, "B": 0.1}, noise=0.0)
    rows["y"] = rows["y"] * 0.1 + 0.3  # round-off in the nil effects
    effects = two_level_effects(rows, _levels01("ABCD"), "y")
    assert effects.attrs["method"] == "Lenth" and 0 < effects.attrs["pse"] < 1e-14
    assert "is at the round-off of the largest effect" in effects.attrs["note"]
    noisy_rows = _two_level("ABCD", {}, {"A": 3.0}, noise=1e-6)
    noisy = two_level_effects(noisy_rows, _levels01("ABCD"), "y")
    assert noisy.attrs["method"] == "Lenth" and "round-off" not in noisy.attrs["note"]


def test_two_level_effects_with_replicates_use_pure_error() -> None:
    rows = _two_level("ABCD", {"D": "ABC"}, {"B": 1.0}, replicates=2, noise=0.5)
    effects = two_level_effects(rows, _levels01("ABCD"), "y")
    assert len(effects) == 7 and effects.attrs["method"] == "pure error"
    cells = rows.groupby(["A", "B", "C", "D"])["y"]
    pure = float(((rows["y"] - cells.transform("mean")) ** 2).sum()) / (16 - 8)
    se = 2 * math.sqrt(pure / 16)  # orthogonal -1/+1 columns: var(coefficient) = s^2 / N
    assert np.allclose(effects["se"], se) and effects.attrs["df"] == 8
    assert effects.set_index("term").loc["B", "significant"]


def test_two_level_effects_need_two_level_factors() -> None:
    effects = two_level_effects(_design(), FACTORS, "MU")
    assert effects.empty and "WP has 3 levels" in effects.attrs["note"]


def test_two_level_effects_reproduce_montgomerys_filtration_example() -> None:
    """The unreplicated 2^4 of D. C. Montgomery, Design and Analysis of Experiments (Example
    6.2, the pilot-plant filtration rate): his effect estimates, and the active effects A, C,
    D, AC and AD that his normal probability plot picks out. Lenth's PSE of these 15 effects
    is 2.625 (s0 = 1.5 x 2.625; PSE = 1.5 x median of the ten below 2.5 s0 = 1.5 x 1.75)."""
    rate = [45, 71, 48, 65, 68, 60, 80, 65, 43, 100, 45, 104, 75, 86, 70, 96]  # A fastest
    rows = [
        {"A": a, "B": b, "C": c, "D": d, "rate": rate[k]}
        for k, (d, c, b, a) in enumerate(itertools.product((0.0, 1.0), repeat=4))
    ]
    effects = two_level_effects(pd.DataFrame(rows), _levels01("ABCD"), "rate")
    published = {"A": 21.625, "B": 3.125, "C": 9.875, "D": 14.625, "A:B": 0.125}
    published.update({"A:C": -18.125, "A:D": 16.625, "B:C": 2.375, "B:D": -0.375})
    published.update({"C:D": -1.125, "A:B:C": 1.875, "A:B:D": 4.125, "A:C:D": -1.625})
    published.update({"B:C:D": -2.625, "A:B:C:D": 1.375})
    got = dict(zip(effects["term"], effects["effect"], strict=True))
    assert got == pytest.approx(published, abs=1e-12)
    assert set(effects.loc[effects["significant"], "term"]) == {"A", "C", "D", "A:C", "A:D"}
    assert effects.attrs["pse"] == pytest.approx(2.625)
    assert effects.attrs["margin_of_error"] == pytest.approx(2.5706 * 2.625, rel=1e-4)
    # Lenth's SME: t at gamma = (1 + 0.95^(1/15)) / 2 on 5 df, 5.22 in his Table (m = 15)
    assert effects.attrs["simultaneous_margin"] == pytest.approx(5.22 * 2.625, rel=2e-3)
    # significant means p below alpha itself (a test-suite audit: p <= 2 alpha passed, every
    # effect being far from 0.05): B's p is about 0.29
    p_b = float(effects.set_index("term").loc["B", "p_value"])
    assert 0.25 < p_b < 0.3
    wide = two_level_effects(pd.DataFrame(rows), _levels01("ABCD"), "rate", alpha=0.3)
    narrow = two_level_effects(pd.DataFrame(rows), _levels01("ABCD"), "rate", alpha=0.2)
    assert bool(wide.set_index("term").loc["B", "significant"])
    assert not bool(narrow.set_index("term").loc["B", "significant"])


def test_alias_structure_of_a_regular_fraction_and_of_a_plackett_burman_design() -> None:
    # 2^(5-2) with D = AB, E = AC (resolution III): I = ABD = ACE = BCDE
    tests = _two_level("ABCDE", {"D": "AB", "E": "AC"}, {}).drop(columns=["y", "replicate"])
    structure = alias_structure(tests, _levels01("ABCDE"))
    chains = dict(zip(structure["term"], structure["aliases"], strict=True))
    assert set(chains["A"].split(" + ")) == {"B:D", "C:E"}
    assert set(chains["B:C"].split(" + ")) == {"D:E", "A:B:E", "A:C:D"}
    assert len(structure) == 7 and not structure.attrs["not_estimable"]  # 8 tests
    assert structure.attrs["max_correlation"] == 0.0  # its estimable chains are orthogonal
    # a 12-run Plackett-Burman design (its first row from Plackett and Burman 1946, the next
    # ten by cyclic shifts, then all minus): main effects only, each two-factor interaction
    # partly confounded with several of them, so no alias chains but none estimable either
    first = [1, 1, -1, 1, 1, 1, -1, -1, -1, 1, -1]
    rows = [first[-k:] + first[:-k] for k in range(11)] + [[-1] * 11]
    names = "ABCDEFGHJKL"
    pb = pd.DataFrame([[(x + 1) / 2 for x in row] for row in rows], columns=list(names))
    coded = pb.to_numpy() * 2 - 1
    assert np.allclose(coded.T @ coded, 12 * np.eye(11))  # orthogonal main effects
    structure = alias_structure(pb, _levels01(names))
    assert list(structure["term"]) == list(names) and (structure["aliases"] == "").all()
    assert len(structure.attrs["not_estimable"]) == 55
    # each main effect is 1/3 correlated with the interactions of the others, which it
    # cannot estimate (the saturated design had read 0: a design review)
    assert structure.attrs["max_correlation"] == pytest.approx(1.0 / 3.0)
    # four of its columns: the main effects and their interactions are estimable together
    # but not orthogonal (a user review found 'clear of the others' printed for PB20)
    four = alias_structure(pb[list("ABCD")], _levels01("ABCD"))
    assert not four.attrs["not_estimable"] and (four["aliases"] == "").all()
    assert four.attrs["max_correlation"] == pytest.approx(1.0 / 3.0)


def test_alias_chains_carry_their_signs() -> None:
    # 2^(5-2) with D = AB and E = -AC: A's column equals B:D's and minus C:E's, so the effect
    # reported for A is A + BD - CE; here y has only C:E (coefficient 2) and B (0.5)
    rows = _two_level("ABCDE", {"D": "AB", "E": "AC"}, {"C:E": -2.0, "B": 0.5}, noise=0.01)
    rows["E"] = 1.0 - rows["E"]  # E = -AC: the same runs with E's levels swapped
    rows["y"] = 10.0 + 0.5 * (2 * rows["B"] - 1) + 2.0 * (2 * rows["C"] - 1) * (2 * rows["E"] - 1)
    effects = two_level_effects(rows, _levels01("ABCDE"), "y").set_index("term")
    assert effects.loc["A", "aliases"] == "B:D - C:E"
    assert effects.loc["A", "effect"] == pytest.approx(-4.0)  # 2 x (0 + 0 - 2)
    table = anova(rows, _levels01("ABCDE"), "y")
    assert dict(zip(table["term"], table["aliases"], strict=True))["A"] == "B:D - C:E"


def test_plackett_burman_run_table_keeps_its_main_effects_unbiased() -> None:
    first = [1, 1, -1, 1, 1, 1, -1, -1, -1, 1, -1]
    rows = [first[-k:] + first[:-k] for k in range(11)] + [[-1] * 11]
    rng = np.random.default_rng(8)
    coded = np.array(rows)[:, :5]  # five factors in the first five columns of a PB12
    y = 1.0 + 0.3 * coded[:, 0] - 0.2 * coded[:, 3] + 0.01 * rng.standard_normal(12)
    frame = pd.DataFrame((coded + 1) / 2, columns=list("ABCDE")).assign(y=y)
    effects = two_level_effects(frame, _levels01("ABCDE"), "y")
    assert sorted(effects["term"]) == list("ABCDE")  # no interaction fills the spare df
    assert "partly confounded" in effects.attrs["note"]
    d = frame["D"].to_numpy()
    plain = y[d == 1].mean() - y[d == 0].mean()
    assert effects.set_index("term").loc["D", "effect"] == pytest.approx(plain, abs=1e-12)


def _pb_frame(runs: int, k: int, seed: int = 3) -> tuple[pd.DataFrame, list[Factor]]:
    from brakeca.design import _plackett_burman_signs

    names = [f"F{i}" for i in range(k)]
    coded = np.array(_plackett_burman_signs(runs, k), dtype=float)
    frame = pd.DataFrame((coded + 1) / 2, columns=names)
    frame["y"] = np.random.default_rng(seed).normal(0.0, 0.1, runs)
    return frame, [Factor(n, (0.0, 1.0)) for n in names]


@pytest.mark.parametrize("runs", [12, 20, 24, 44])
def test_plackett_burman_designs_fit_their_main_effects_alone(runs) -> None:
    """A statistics review found interactions in the effects table of every 24-run design (a
    four-factor term among 11 factors, correlated with the main effects it then biased) and
    in the 12- and 20-run designs of three factors. Every projection of a Plackett-Burman
    design is now fitted with its main effects alone, unless it is a full factorial (a 24- or
    44-run design over three factors), whose interactions the data can estimate; and always
    when the design asks for it."""
    for k in range(2, min(runs - 1, 11) + 1):
        frame, factors = _pb_frame(runs, k)
        asked = two_level_effects(frame, factors, "y", main_effects_only=True)
        assert sorted(asked["term"]) == sorted(f.name for f in factors), (runs, k)
        assert "main effects alone" in asked.attrs["note"]
        found = two_level_effects(frame, factors, "y")
        counts = frame.groupby([f.name for f in factors]).size()
        if len(counts) == 2**k:  # a replicated full factorial: interactions estimable
            if counts.nunique() == 1:
                assert "non-regular" not in found.attrs["note"], (runs, k)
                assert found.attrs["method"] == "pure error", (runs, k)
        else:  # non-regular
            assert sorted(found["term"]) == sorted(f.name for f in factors), (runs, k)
            if k < runs - 1:  # a saturated design has no room for an interaction
                assert "non-regular" in found.attrs["note"], (runs, k)
            assert "not orthogonal" not in found.attrs["note"], (runs, k)


def test_effects_with_spare_degrees_of_freedom_use_the_residual_as_the_anova_does() -> None:
    """A 12-run design over seven factors leaves 4 residual degrees of freedom: the effects'
    t and p come from that residual, as Minitab's coded coefficients do and as the ANOVA of
    the same main effects does (t^2 = F); the review had found Lenth's method there, with p
    = 0.49 in the effects table against 0.029 in the ANOVA."""
    from scipy import stats

    frame, factors = _pb_frame(12, 7)
    coded = 2 * frame[[f.name for f in factors]].to_numpy() - 1
    frame["y"] += 0.15 * coded[:, 0] - 0.08 * coded[:, 4]
    effects = two_level_effects(frame, factors, "y")
    assert effects.attrs["method"] == "residual" and effects.attrs["df"] == 4
    assert np.isnan(effects.attrs["pse"]) and "4 degrees of freedom" in effects.attrs["note"]
    table = anova(frame, factors, "y", interactions=False).set_index("term")
    by_term = effects.set_index("term")
    for f in factors:
        assert by_term.loc[f.name, "t"] ** 2 == pytest.approx(table.loc[f.name, "F"], rel=1e-9)
        assert by_term.loc[f.name, "p_value"] == pytest.approx(table.loc[f.name, "p_value"])
    x = np.column_stack([np.ones(12), coded])
    _, rss, *_ = np.linalg.lstsq(x, frame["y"].to_numpy(), rcond=None)
    se = 2 * math.sqrt(float(rss[0]) / 4 / 12)  # orthogonal columns: var(coef) = s^2 / N
    assert np.allclose(by_term["se"], se)
    assert effects.attrs["margin_of_error"] == pytest.approx(stats.t.ppf(0.975, 4) * se)
    tables = analyze(frame, factors, ["y"], main_effects_only=True)["y"]
    assert not any(":" in str(t) for t in tables["anova"]["term"])


def test_a_failed_run_makes_the_effects_adjusted_with_their_own_standard_errors() -> None:
    rows = _two_level("ABC", {}, {"A": 1.0, "C": 0.5}, noise=0.05).iloc[:-1]  # 7 of the 2^3
    effects = two_level_effects(rows, _levels01("ABC"), "y")
    assert "not orthogonal" in effects.attrs["note"]
    x = np.column_stack(
        [np.ones(7)]
        + [2 * rows[c].to_numpy() - 1 for c in "ABC"]
        + [
            (2 * rows[a].to_numpy() - 1) * (2 * rows[b].to_numpy() - 1)
            for a, b in ("AB", "AC", "BC")
        ]
    )
    relative = 7 * np.diag(np.linalg.inv(x.T @ x))[1:]
    by_term = effects.set_index("term")
    ratio = by_term.loc[["A", "B", "C", "A:B", "A:C", "B:C"], "se"] / effects.attrs["pse"]
    assert np.allclose(ratio.to_numpy(), np.sqrt(relative))
    assert np.allclose(by_term["t"], by_term["effect"] / by_term["se"])


def test_failed_runs_of_a_regular_design_keep_its_interactions_in_the_effects() -> None:
    """A DoE review: five failed runs of a replicated 2^3 correlated the A:B column with A's
    by 0.27 in the runs left, and the effects table called the design non-regular and fitted
    the main effects alone, its error holding an interaction the ANOVA found with p = 1e-6.
    Regularity and alias chains are read from the runs planned (the summary's failed rows);
    an interaction the runs left cannot estimate is named."""
    rows = _two_level("ABC", {}, {"A": 1.0, "A:B": 0.8}, replicates=2, noise=0.05)
    rows["status"] = "ok"
    lost = (rows["B"] == 0) & (rows["C"] == 0)  # both runs of two settings
    lost.loc[rows.index[(rows["A"] == 1) & (rows["B"] == 1) & (rows["C"] == 1)][0]] = True
    rows.loc[lost, "status"] = "failed"
    rows.loc[lost, "y"] = np.nan
    ok = rows.loc[~lost]
    a, b = (2 * ok[c].to_numpy() - 1 for c in "AB")
    assert abs(np.corrcoef(a * b, a)[0, 1]) > 0.2  # what had made it "non-regular"
    effects = two_level_effects(rows, _levels01("ABC"), "y")
    note = effects.attrs["note"]
    assert "non-regular" not in note
    assert "cannot tell these interactions from the terms before them" in note
    assert note.endswith("so they are left out: B:C, A:B:C")
    assert set(effects["term"]) == {"A", "B", "C", "A:B", "A:C"}
    table = anova(rows, _levels01("ABC"), "y").set_index("term")
    assert set(table.index) - {"Residual"} == set(effects["term"])  # the ANOVA's terms
    by_term = effects.set_index("term")
    for term in ("A:B", "A:C"):  # the highest terms: Type II's test of each is the t test
        assert by_term.loc[term, "p_value"] == pytest.approx(table.loc[term, "p_value"], rel=1e-6)
    assert by_term.loc["A:B", "effect"] == pytest.approx(1.6, abs=0.1)
    # the runs as a table of their own, without the failed rows: the design is what they are
    alone = two_level_effects(ok, _levels01("ABC"), "y")
    assert "non-regular" in alone.attrs["note"]
    # a chain of a fraction the runs left cannot estimate is named once, as the chain (a diff
    # review: A:D and B:C, one chain of D = ABC, had been named as two interactions)
    half = _two_level("ABCD", {"D": "ABC"}, {"A": 1.0, "A:B": 1.2}, noise=0.05, replicates=2)
    half["status"] = "ok"
    half.loc[[0, 8], ["status", "y"]] = ["failed", np.nan]  # both runs of one setting
    effects = two_level_effects(half, _levels01("ABCD"), "y")
    assert effects.attrs["note"].endswith("so they are left out: A:D (= B:C)")
    assert dict(zip(effects["term"], effects["aliases"], strict=True))["A:B"] == "C:D"


def test_a_constant_response_has_no_effects() -> None:
    rows = _two_level("ABC", {}, {}, noise=0.0).assign(y=0.3)
    rows["y"] += 1e-17 * np.arange(len(rows))
    effects = two_level_effects(rows, _levels01("ABC"), "y")
    assert effects.empty and "constant" in effects.attrs["note"]


def test_a_main_effect_aliased_with_another_stays_out_of_the_pooled_model() -> None:
    rows = _two_level("AC", {}, {"A": 1.0}).assign(B=lambda f: f["A"])  # B's column is A's
    table = anova(rows, _levels01("ABC"), "y")
    assert "B (aliased with A)" in table.attrs["note"]
    assert "B" not in set(table["term"]) and " B" not in table.attrs["formula"]


def test_interaction_aliases_of_a_half_fraction() -> None:
    """D = -A*B*C: A:B is aliased with -C:D, and so on for every pair; a full factorial has
    none."""
    rows = [
        {"A": a, "B": b, "C": c, "D": -a * b * c}
        for c, b, a in itertools.product((-1.0, 1.0), repeat=3)
    ]
    factors = [Factor(n, (-1.0, 1.0)) for n in "ABCD"]
    aliases = interaction_aliases(pd.DataFrame(rows), factors)
    assert aliases == {
        ("A", "B"): "-C:D", ("A", "C"): "-B:D", ("A", "D"): "-B:C",
        ("B", "C"): "-A:D", ("B", "D"): "-A:C", ("C", "D"): "-A:B",
    }  # fmt: skip
    full = [{"A": a, "B": b} for a, b in itertools.product((-1.0, 1.0), repeat=2)]
    assert interaction_aliases(pd.DataFrame(full), factors[:2]) == {}


def _unbalanced() -> pd.DataFrame:
    """The paper's design, replicated twice, with five runs failed: unbalanced, full rank."""
    rows = _design(replicates=2, noise=2e-3)
    rows.loc[[0, 7, 18, 30, 41], "status"] = "failed"
    return rows


def test_type_iii_anova_equals_statsmodels_with_sum_coding() -> None:
    import statsmodels.formula.api as smf
    from statsmodels.stats.anova import anova_lm

    rows = _unbalanced()
    table = anova(rows, FACTORS, "MU", typ=3).set_index("term")
    assert table.attrs["typ"] == "Type III (adjusted)"
    assert "adjusted (Type III) sums of squares do not add up" in table.attrs["note"]
    terms = [f"C({f.name}, Sum)" for f in FACTORS]
    formula = " + ".join(terms + [f"{a}:{b}" for a, b in itertools.combinations(terms, 2)])
    ref = anova_lm(smf.ols(f"MU ~ {formula}", ok_runs(rows)).fit(), typ=3)
    for term, name in zip(
        ref.index[1:-1], [*(f.name for f in FACTORS), *_pair_names()], strict=True
    ):
        assert table.loc[name, "df"] == ref.loc[term, "df"], name
        assert table.loc[name, "sum_sq"] == pytest.approx(ref.loc[term, "sum_sq"], rel=1e-9)
        assert table.loc[name, "F"] == pytest.approx(ref.loc[term, "F"], rel=1e-9)
        assert table.loc[name, "p_value"] == pytest.approx(ref.loc[term, "PR(>F)"], rel=1e-6)
    assert table.loc["Residual", "sum_sq"] == pytest.approx(ref.loc["Residual", "sum_sq"])
    # Unbalanced, Type II differs from it (so the option changes something here).
    two = anova(rows, FACTORS, "MU").set_index("term")
    assert two.attrs["typ"] == "Type II"
    assert not np.allclose(two.loc["S", "sum_sq"], table.loc["S", "sum_sq"], rtol=1e-6)
    assert "anova_type = 3" in two.attrs["note"]


def _pair_names() -> list[str]:
    return [f"{a.name}:{b.name}" for a, b in itertools.combinations(FACTORS, 2)]


def test_type_ii_and_iii_agree_on_a_balanced_design() -> None:
    rows = _design(replicates=2, noise=2e-3)
    two, three = anova(rows, FACTORS, "MU"), anova(rows, FACTORS, "MU", typ=3)
    assert list(two["term"]) == list(three["term"])
    np.testing.assert_allclose(three["sum_sq"], two["sum_sq"], rtol=1e-9)
    np.testing.assert_allclose(three["p_value"], two["p_value"], rtol=1e-6, equal_nan=True)
    assert "unbalanced" not in three.attrs["note"]


def test_type_iii_f_is_the_square_of_the_coefficients_t() -> None:
    """Minitab's agreement of its coefficients table with its adjusted ANOVA: for a
    two-level term, F = t^2 once a run has failed, which Type II does not give."""
    two_level = [S, A]
    rows = _design(replicates=3, noise=2e-3)
    rows = rows[(rows["WP"] == WP.levels[0]) & (rows["WR"] == WR.levels[0])].copy()
    rows.iloc[[0, 5], rows.columns.get_loc("status")] = "failed"
    assert len(ok_runs(rows)) == 10
    table = anova(rows, two_level, "MU", typ=3).set_index("term")
    effects = two_level_effects(rows, two_level, "MU").set_index("term")
    for term in ["S", "A", "S:A"]:
        assert table.loc[term, "F"] == pytest.approx(effects.loc[term, "t"] ** 2, rel=1e-9)
        assert table.loc[term, "p_value"] == pytest.approx(effects.loc[term, "p_value"])
    second = anova(rows, two_level, "MU").set_index("term")
    assert second.loc["S", "F"] != pytest.approx(effects.loc["S", "t"] ** 2, rel=1e-6)


@pytest.mark.parametrize("typ", [1, 4, True, "3", 3.0])
def test_anova_type_must_be_2_or_3(typ: object) -> None:
    with pytest.raises(ValueError, match=r"typ: .*Type 2 or 3"):
        anova(_design(), FACTORS, "MU", typ=typ)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"typ: .*Type 2 or 3"):
        analyze(_design(), FACTORS, anova_type=typ)  # type: ignore[arg-type]


def test_anova_type_takes_statsmodels_spelling() -> None:
    """typ="III", which statsmodels' anova_lm takes, had been refused (an API review)."""
    for spelt, typ in (("II", 2), ("III", 3)):
        pd.testing.assert_frame_equal(
            anova(_design(), FACTORS, "MU", typ=spelt),  # type: ignore[arg-type]
            anova(_design(), FACTORS, "MU", typ=typ),
        )


def test_type_iii_falls_back_to_sequential_when_rank_deficient() -> None:
    rows = _design(replicates=2)
    rows.loc[rows["test"] == 1, "status"] = "failed"  # the cell S-, WP- left empty
    rows = rows[(rows["WR"] == WR.levels[0]) & (rows["A"] == A.levels[0])]
    table = anova(rows, [S, WP], "MU", typ=3).set_index("term")
    why = "the design is rank-deficient, e.g. empty cells"
    assert table.attrs["typ"] == f"Type I (sequential; {why})"
    assert table.loc["S:WP", "df"] == 1  # one of its two degrees of freedom is estimable


def test_effects_vif_is_one_when_orthogonal_and_matches_the_regression_definition() -> None:
    two_level = [S, WR, A]
    rows = _design(replicates=2, noise=2e-3)
    rows = rows[rows["WP"] == WP.levels[0]].copy()
    balanced = two_level_effects(rows, two_level, "MU")
    np.testing.assert_allclose(balanced["vif"], 1.0, rtol=1e-12)
    rows.iloc[[0, 3, 6], rows.columns.get_loc("status")] = "failed"
    effects = two_level_effects(rows, two_level, "MU").set_index("term")
    assert (effects["vif"] > 1.0 + 1e-6).any()
    # 1 / (1 - R^2) of each term's -1/+1 column on the other terms', by plain least squares
    ok = ok_runs(rows)
    coded = {f.name: np.where(ok[f.name] == f.levels[1], 1.0, -1.0) for f in two_level}
    columns = {}
    for term in effects.index:
        columns[term] = np.prod([coded[name] for name in term.split(":")], axis=0)
    for term, x in columns.items():
        others = np.column_stack([np.ones(len(ok))] + [c for t, c in columns.items() if t != term])
        fitted = others @ np.linalg.lstsq(others, x, rcond=None)[0]
        r2 = 1.0 - np.sum((x - fitted) ** 2) / np.sum((x - x.mean()) ** 2)
        assert effects.loc[term, "vif"] == pytest.approx(1.0 / (1.0 - r2), rel=1e-9)


def test_type_ii_from_the_columns_equals_statsmodels_on_an_unbalanced_design() -> None:
    """The Type II table the ANOVA takes where anova_lm cannot run (no residual degrees of
    freedom) is the same as anova_lm's wherever both run: a 3 x 2 x 2 design, twice, with
    three runs missing, and every two-factor interaction."""
    from statsmodels.stats.anova import anova_lm

    from brakeca.analysis import _column_table, _ols

    rng = np.random.default_rng(1)
    rows = [
        {"f0": f"L0{a}", "f1": f"L0{b}", "f2": f"L0{c}"}
        for a, b, c in itertools.product(range(3), range(2), range(2))
        for _ in range(2)
    ]
    frame = pd.DataFrame(rows).drop(index=[0, 5, 9]).reset_index(drop=True)
    frame.insert(0, "y", rng.normal(size=len(frame)))
    terms = ["C(f0)", "C(f1)", "C(f2)", "C(f0):C(f1)", "C(f0):C(f2)", "C(f1):C(f2)"]
    fit = _ols(frame, terms)
    ours = _column_table(frame, terms, fit, typ=2)
    theirs = anova_lm(fit, typ=2).loc[ours.index]
    assert np.allclose(ours["sum_sq"], theirs["sum_sq"], rtol=1e-10, atol=1e-14)
    assert np.allclose(ours["F"].iloc[:-1], theirs["F"].iloc[:-1], rtol=1e-10)
    assert list(ours["df"]) == list(theirs["df"])


def test_a_design_stands_for_its_factors_and_names_alone_are_refused() -> None:
    """analyze(summary, design) had said "not a factor (needs 'name' and 'levels'): ('name',
    'paper')", a field of the design (a helper's API review), then asked for design.factors;
    a design (or a campaign result) now gives its factors. Names alone are refused, saying
    why: the levels come from the design (a centre point's value is no level)."""
    import types

    from brakeca.design import load_design

    design = load_design("paper")
    rows = pd.DataFrame(
        {"S": [0.0, 1.0] * 6, "WP": np.repeat([1e-15, 1e-14, 1e-13], 4), "WR": 1e-7, "A": 10.0}
    )
    rows["MU"], rows["status"] = np.linspace(0.3, 0.4, 12), "ok"
    expected = main_effects(rows, design.factors, "MU")
    pd.testing.assert_frame_equal(main_effects(rows, design, "MU"), expected)
    result = types.SimpleNamespace(design=design, summary=rows)  # as a CampaignResult
    pd.testing.assert_frame_equal(main_effects(rows, result, "MU"), expected)
    with pytest.raises(TypeError, match=r"^factors: 'S', 'WP' are names; the analysis needs each "
                       r"factor's levels: pass the design"):  # fmt: skip
        main_effects(rows, ["S", "WP"], "MU")
    with pytest.raises(TypeError, match=r"^factors: 'S' is a name;"):
        anova(rows, "S", "MU")
    with pytest.raises(KeyError, match=r"'log10_V_mm3' is not a column of the summary; "
                       r"brakeca.study.with_log_v\(summary\) adds it"):  # fmt: skip
        anova(rows.assign(V_mm3=1.0), design, "log10_V_mm3")
    with pytest.raises(KeyError, match=r"'mu' is not a column of the summary; did you mean 'MU'"):
        anova(rows, design, "mu")
    with pytest.raises(KeyError, match=r"'MU_SD' is not a column of the summary; a campaign "
                       r"written before MU_SD .*load_campaign\(folder\) computes it"):  # fmt: skip
        anova(rows, design, "MU_SD")


def test_an_exact_fit_has_its_type_ii_sums_of_squares():
    """A response the model fits exactly (residual sum of squares 0) with residual df left:
    Type II had given NaN sums of squares, F and p, a statsmodels note and a false
    'unbalanced design' (a helper's fuzzing). Both types now give the term its sum of
    squares, F infinite, p 0, and a note that says why."""
    d = pd.DataFrame({"A": [20.0, 20.0, 10.0, 10.0], "y": [0.5, 0.5, -0.5, -0.5]})
    d["status"] = "ok"
    for typ in (2, 3):
        out = anova(d, [Factor("A", (10.0, 20.0))], "y", typ=typ).set_index("term")
        assert out.loc["A", "sum_sq"] == pytest.approx(1.0, rel=1e-12)
        assert out.loc["A", "F"] == math.inf and out.loc["A", "p_value"] == 0.0
        assert out.loc["Residual", "sum_sq"] == 0.0 and out.loc["Residual", "df"] == 2.0
        assert out.attrs["note"].startswith("exact fit: the model leaves no residual scatter")
        assert "statsmodels" not in out.attrs["note"] and "unbalanced" not in out.attrs["note"]


def test_a_residual_at_round_off_is_the_exact_fit_it_is():
    """Identical replicates, or a response additive to the last digit, leave a residual of
    1e-31: its F of 1e30 and p of 1e-46 (and Tukey's T, a trend's F, lack of fit's F, a
    Box-Cox λ̂ fitted to it) had measured the floating-point error (an analysis review). It
    is taken as the exact fit it is, as a residual of exactly 0; a constant response's
    trend parts have no F at all."""
    from brakeca.analysis import factor_trends, level_comparisons
    from brakeca.boxcox import box_cox_profile

    wp = Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", "", ("-", "0", "+"))
    rows = pd.DataFrame(
        [
            {"test": i + 1, "WP": w, "MU": v, "status": "ok"}
            for i, (w, v) in enumerate(zip(wp.levels, [0.25, 0.5, 0.75], strict=True))
            for _ in range(2)
        ]
    )
    out = anova(rows, [wp], "MU")
    table = out.set_index("term")
    assert table.loc["Residual", "sum_sq"] == 0.0 and out.attrs["s"] == 0.0
    assert table.loc["WP", "F"] == math.inf and table.loc["WP", "p_value"] == 0.0
    assert "exact fit" in out.attrs["note"] and "to round-off" in out.attrs["note"]
    assert math.isnan(out.attrs["lack_of_fit_F"])
    tukey = level_comparisons(rows, [wp], "MU")
    assert np.isinf(tukey["q"]).all() and (tukey["p_adjusted"] == 0.0).all()
    trends = factor_trends(rows, [wp], "MU").set_index("part")
    assert trends.loc["linear", "F"] == math.inf  # 0.5 of the spread: a real part
    assert math.isnan(trends.loc["quadratic", "F"])  # 1e-33: round-off, no part
    exog = np.column_stack([np.ones(6), np.repeat([0.0, 1.0, 2.0], 2)])
    assert not box_cox_profile(rows["MU"].to_numpy(), exog).defined
    # a constant response: no trend part is tested (its 1e-34 had F infinite)
    s = Factor("S", (0.0, 1.0), "-", "", ("-", "+"))
    flat = pd.DataFrame(
        [
            {"test": i, "S": a, "WP": w, "MU": 0.15, "status": "ok"}
            for i, (a, w, _) in enumerate(itertools.product(s.levels, wp.levels, range(2)))
        ]
    )
    parts = factor_trends(flat, [s, wp], "MU")
    assert len(parts) and parts["F"].isna().all() and parts["p_value"].isna().all()


def test_an_exact_fit_is_one_in_every_table():
    """An additive response with identical replicates: the effects table, the residuals and
    a response surface take the fit as exact, as the ANOVA does (a diff review: t of 9.5e14,
    runs flagged unusual on round-off, a surface's F of 4e28)."""
    from brakeca.analysis import residuals, two_level_effects
    from brakeca.rsm import Coding, fit_response_surface

    s = Factor("S", (0.0, 1.0), "-", "", ("-", "+"))
    a = Factor("A", (10.0, 20.0), "%", "", ("-", "+"))
    rows = pd.DataFrame(
        [
            {"test": t + 1, "replicate": r, "S": x, "A": y, "status": "ok",
             "MU": 0.3 + 0.02 * x + 0.001 * y}
            for t, (y, x) in enumerate(itertools.product(a.levels, s.levels))
            for r in range(2)
        ]
    )  # fmt: skip
    assert "exact fit" in anova(rows, [s, a], "MU").attrs["note"]
    effects = two_level_effects(rows, [s, a], "MU").set_index("term")
    assert effects.loc["S", "t"] == math.inf and effects.loc["A", "t"] == math.inf
    assert effects.loc["S", "p_value"] == 0.0 and math.isnan(effects.loc["S:A", "t"])
    assert "exact fit" in effects.attrs["note"]
    assert residuals(rows, [s, a], "MU")["std_residual"].isna().all()
    x = np.repeat([-1.0, 0.0, 1.0], 3)
    z = np.tile([-1.0, 0.0, 1.0], 3)
    square = pd.DataFrame({"x": x, "z": z, "y": 2.0 + 0.3 * x - 0.2 * z**2 + 0.1 * x * z})
    fit = fit_response_surface(square, [Coding("x", -1.0, 1.0), Coding("z", -1.0, 1.0)], "y")
    assert fit.coefficients["t"].isna().all() and fit.anova["F"].isna().all()
    assert fit.statistics["s"] == 0.0 and any("exactly, to round-off" in n for n in fit.notes)


def test_real_scatter_tiny_beside_an_offset_is_not_an_exact_fit():
    """A third diff review: a floor of the values' own round-off had made scatter of 1e-14
    about 0.15 an exact fit, and its noise terms infinitely significant; and a pure error of
    1e-11 beside effects of 0.1 had lost its lack-of-fit test."""
    from brakeca.analysis import exact_fit

    s = Factor("S", (0.0, 1.0), "-", "", ("-", "+"))
    a = Factor("A", (10.0, 20.0), "%", "", ("-", "+"))
    b = Factor("B", (0.0, 1.0), "-", "", ("-", "+"))
    rng = np.random.default_rng(3)
    rows = pd.DataFrame(
        [
            {"test": t, "S": x, "A": y, "B": z, "status": "ok"}
            for t, (x, y, z) in enumerate(itertools.product(s.levels, a.levels, b.levels))
            for _ in range(2)
        ]
    )
    rows["MU"] = 0.15 + 1e-9 * rows["S"] + rng.normal(0.0, 1e-14, len(rows))
    table = anova(rows, [s, a, b], "MU", interactions=1).set_index("term")
    assert "exact fit" not in table.attrs["note"]
    assert np.isfinite(table["F"].drop("Residual")).all() and table.loc["A", "p_value"] > 1e-3
    # pure error of 1e-11 beside effects of 0.1: tested, not round-off
    rows["MU"] = (
        0.2 + 0.1 * rows["S"] + 3e-12 * rows["S"] * rows["B"] + rng.normal(0.0, 1e-11, len(rows))
    )
    lof = anova(rows, [s, a, b], "MU", interactions=1)
    assert lof.attrs["lack_of_fit_df"] > 0 and np.isfinite(lof.attrs["lack_of_fit_F"])
    assert exact_fit(1e-20, [0.0, 1.0]) and not exact_fit(1e-17, [0.0, 1.0])  # of 0.5


def test_an_exact_fit_s_curvature_is_infinite_in_the_effects_table_too():
    """With an exact fit and centre points off the plane, the ANOVA's Curvature has F
    infinite; the effects table's Ct Pt row had been left out (t NaN): a third review."""
    from brakeca.analysis import two_level_effects

    s = Factor("S", (0.0, 1.0), "-", "", ("-", "+"))
    a = Factor("A", (10.0, 20.0), "%", "", ("-", "+"))
    rows = [
        {"test": t + 1, "S": x, "A": y, "MU": 0.2 + 0.02 * x + 0.001 * y, "status": "ok"}
        for t, (y, x) in enumerate(itertools.product(a.levels, s.levels))
        for _ in range(2)
    ]
    rows += [{"test": 5, "S": 0.5, "A": 15.0, "MU": 0.3, "status": "ok"}] * 3
    frame = pd.DataFrame(rows)
    table = anova(frame, [s, a], "MU").set_index("term")
    assert table.loc["Curvature", "F"] == math.inf
    effects = two_level_effects(frame, [s, a], "MU").set_index("term")
    assert effects.loc["Ct Pt", "t"] == math.inf and effects.loc["Ct Pt", "p_value"] == 0.0


def test_an_exact_fit_s_nil_term_is_nil_in_the_coefficients_too():
    """An effect of 1e-11 about 0.3, in an exact fit: nil in the ANOVA (its sum of squares
    at round-off), and nil in the coefficients and Tukey's comparisons too (they had judged
    round-off by 1e-12 of the intercept and called it significant: a review)."""
    from brakeca.analysis import level_coefficients

    s = Factor("S", (0.0, 1.0), "-", "", ("-", "+"))
    a = Factor("A", (10.0, 20.0), "%", "", ("-", "+"))
    rows = pd.DataFrame(
        [
            {"test": t, "S": x, "A": y, "MU": 0.3 + 0.5 * x + 1e-11 * y, "status": "ok"}
            for t, (x, y) in enumerate(itertools.product(s.levels, a.levels))
            for _ in range(2)
        ]
    )
    table = anova(rows, [s, a], "MU", interactions=1).set_index("term")
    assert table.loc["S", "F"] == math.inf and math.isnan(table.loc["A", "F"])
    coefficients = level_coefficients(rows, [s, a], "MU", interactions=1)
    by_term = coefficients.groupby("term")["t"]
    assert np.isinf(by_term.get_group("S")).all() and by_term.get_group("A").isna().all()


def test_repeats_without_scatter_are_named_in_the_note():
    """Replicates identical in a response (runs held at the COF floor do not depend on their
    seed) add residual degrees of freedom with no error in them: the note counts them (an
    analysis review); none where every repeat scatters, or none does (an exact fit)."""
    s = Factor("S", (0.0, 1.0), "-", "", ("-", "+"))
    a = Factor("A", (10.0, 20.0), "%", "", ("-", "+"))
    cell = {(0.0, 10.0): 0.30, (1.0, 10.0): 0.34, (0.0, 20.0): 0.37, (1.0, 20.0): 0.35}

    def rows(scatter):
        return pd.DataFrame(
            [
                {"test": t + 1, "replicate": r, "S": x, "A": y, "status": "ok",
                 "MU": cell[(x, y)] + (0.001 * r if (x, y) in scatter else 0.0)}
                for t, (y, x) in enumerate(itertools.product(a.levels, s.levels))
                for r in range(3)
            ]
        )  # fmt: skip

    some = anova(rows({(0.0, 10.0)}), [s, a], "MU", interactions=1)
    note = some.attrs["note"]
    assert note.startswith("3 of the 4 repeated level combinations have identical runs")
    assert "their 6 degrees of freedom count in the residual" in note
    assert some.attrs["silent_repeat_df"] == 6
    every = anova(rows(set(cell)), [s, a], "MU", interactions=1)
    assert "identical runs" not in every.attrs["note"] and every.attrs["silent_repeat_df"] == 0
    # every repeat identical, with a lack of fit left (no interaction in the model): said,
    # and no lack-of-fit test against a pure error of round-off (a diff review)
    all_silent = anova(rows(set()), [s, a], "MU", interactions=1)
    assert all_silent.attrs["note"].startswith("all 4 repeated level combinations have")
    assert all_silent.attrs["lack_of_fit_df"] == 1 and math.isnan(all_silent.attrs["lack_of_fit_F"])
    none = anova(rows(set()), [s, a], "MU", interactions=2).attrs["note"]
    assert "identical runs" not in none and none.startswith("exact fit")


def test_the_anova_csv_gives_the_table_s_note_once(tmp_path) -> None:
    """A user's review: a screening design's 538-character note was on each of its 15 rows;
    the CSV has it on the first row, and the table in memory keeps it on every row."""
    rows = _design(replicates=1)
    result = analyze(rows, FACTORS, ["MU"], max_order=4)  # saturated: its highest pooled
    note = result["MU"].anova["note"]
    assert note.iloc[0].startswith("model with four-factor interactions is saturated")
    assert note.nunique() == 1 and len(note) > 2
    save_tables(result, tmp_path)
    written = pd.read_csv(tmp_path / "anova_MU.csv", keep_default_na=False)["note"]
    assert written.iloc[0] == note.iloc[0] and (written.iloc[1:] == "").all()


def test_lenths_pse_trims_the_effects_beyond_2_5_s0() -> None:
    """Lenth (1989): s0 = 1.5 median |c|, PSE = 1.5 median of the |c| <= 2.5 s0. An
    unreplicated 2^3 built from known effects (A 20, B 4.0, C 1.4, AB -1.2, AC 1.0, BC -0.8,
    ABC 0.5) puts B between 2 s0 and 2.5 s0: median |c| = 1.2, s0 = 1.8, 2.5 s0 = 4.5 keeps
    B and trims A, so PSE = 1.5 median(0.5, 0.8, 1.0, 1.2, 1.4, 4.0) = 1.65 (a trim at 2 s0
    gives 1.5; a mutation review found no fixture with an effect in that band)."""
    from scipy import stats

    effects = {"A": 20.0, "B": 4.0, "C": 1.4, "A:B": -1.2, "A:C": 1.0, "B:C": -0.8}
    effects["A:B:C"] = 0.5
    rows = []
    for c, b, a in itertools.product((-1, 1), repeat=3):
        x = {"A": a, "B": b, "C": c}
        y = 50.0 + sum(e / 2 * math.prod(x[f] for f in t.split(":")) for t, e in effects.items())
        rows.append({"A": (a + 1) / 2, "B": (b + 1) / 2, "C": (c + 1) / 2, "y": y})
    table = two_level_effects(pd.DataFrame(rows), _levels01("ABC"), "y").set_index("term")
    assert table.attrs["pse"] == pytest.approx(1.65, rel=1e-12)
    assert table.attrs["df"] == pytest.approx(7 / 3, rel=1e-12)
    assert table.loc["B", "effect"] == pytest.approx(4.0, rel=1e-12)
    assert table.loc["B", "t"] == pytest.approx(4.0 / 1.65, rel=1e-12)
    assert table.loc["B", "p_value"] == pytest.approx(2 * stats.t.sf(4.0 / 1.65, 7 / 3), rel=1e-9)
