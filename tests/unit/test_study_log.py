"""The study analyses V on a log scale too, where multiplicative effects add."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import Factor, anova
from brakeca.study import with_log_v

WP = Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", "Specific wear rate", ("-", "0", "+"))
A = Factor("A", (10.0, 20.0), "%", "Metal fibre area fraction", ("-", "+"))


def _multiplicative(replicates: int = 2) -> pd.DataFrame:
    """V = 1 mm^3 x 10**k (WP level k) x 0.4 (A+) x a small seed scatter."""
    rng = np.random.default_rng(3)
    rows = []
    for (k, wp), (a, level_a), _ in itertools.product(
        enumerate(WP.levels), enumerate(A.levels), range(replicates)
    ):
        v_mm3 = 10.0**k * (0.4 if a else 1.0) * math.exp(0.02 * rng.standard_normal())
        rows.append({"WP": wp, "A": level_a, "V": v_mm3 * 1e-9, "status": "ok"})
    return pd.DataFrame(rows)


def test_log_v_column() -> None:
    summary = pd.DataFrame({"V": [2e-9, 0.0, -1e-12, np.nan], "status": ["ok"] * 4})
    out = with_log_v(summary)
    assert out["log10_V_mm3"].iloc[0] == pytest.approx(math.log10(2.0), rel=1e-12)
    assert out["log10_V_mm3"].iloc[1:].isna().all()
    assert "log10_V_mm3" not in summary.columns  # the input is not changed


def test_multiplicative_effects_are_an_interaction_on_v_and_add_on_log_v() -> None:
    data = with_log_v(_multiplicative())
    raw = anova(data, [WP, A], "V").set_index("term")
    log = anova(data, [WP, A], "log10_V_mm3").set_index("term")
    # On V the product WP x A shows as an interaction; on log V it is (nearly) gone.
    assert raw.loc["WP:A", "percent_contribution"] > 5.0 and raw.loc["WP:A", "p_value"] < 1e-3
    assert log.loc["WP:A", "percent_contribution"] < 0.1
    assert log.attrs["r_squared_pred"] > raw.attrs["r_squared_pred"]


def test_design_table_lists_levels_with_their_labels_or_alone() -> None:
    from types import SimpleNamespace

    from brakeca.design import design_from_dict
    from brakeca.study import _design_table

    design = design_from_dict(
        {
            "name": "t",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "A", "field": "A", "levels": [5.0, 10.0]},
                {"name": "WP", "field": "WP", "levels": [1e-14, 1e-13], "labels": ["-", "+"]},
            ],
        }
    )
    table = _design_table(SimpleNamespace(design=design))  # type: ignore[arg-type]
    assert list(table["levels"]) == ["5, 10", "- = 1e-14, + = 1e-13"]
    assert list(table["unit"]) == ["%", "m³/(N·m)"]


def test_a_fold_over_report_gives_the_generators_the_fold_over_broke_as_before_it() -> None:
    """After a fold-over on S, modulus = S*WP*WR and slope = S*WR*A no longer hold (the
    folded half reverses S): the report had listed them as the design's generators."""
    from types import SimpleNamespace

    from brakeca.design import load_design
    from brakeca.study import _design_info, _design_table

    design = load_design("screen_fold")
    table = _design_table(SimpleNamespace(design=design)).set_index("factor")  # type: ignore[arg-type]
    assert table.loc["modulus", "generated"] == "(= S·WP·WR before the fold-over)"
    assert table.loc["slope", "generated"] == "(= S·WR·A before the fold-over)"
    assert table.loc["mu0", "generated"] == "= WP·WR·A"  # no S: it still holds
    info = _design_info(design)
    assert "Generators of the fraction before its fold-over on S: modulus = S*WP*WR" in info
    assert "defining relation I = WP·WR·A·mu0 = " in info
    plain = _design_table(SimpleNamespace(design=load_design("screen"))).set_index("factor")  # type: ignore[arg-type]
    assert plain.loc["modulus", "generated"] == "= S·WP·WR"
