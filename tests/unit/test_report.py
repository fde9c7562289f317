"""Tests of brakeca.report: a single self-contained, escaped, atomically written HTML file.

References
----------
Wahlström (2016), doi:10.1155/2016/8181260.
"""

from __future__ import annotations

import math
import re
import struct
import zlib
from datetime import UTC, datetime
from html import unescape
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import Factor, anova
from brakeca.report import format_p_value, render_report, write_report

FACTORS = (
    Factor("S", (0.0, 1.0), "-", labels=("-", "+")),
    Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", labels=("-", "0", "+")),
)


def tiny_png(path: Path, width: int = 4, height: int = 3, shade: int = 128) -> Path:
    """Write a minimal valid greyscale PNG (no matplotlib needed)."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    raw = b"".join(b"\x00" + bytes([shade]) * width for _ in range(height))
    png = (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )
    path.write_bytes(png)
    return path


def make_inputs(tmp_path: Path, n_figures: int = 3) -> dict:
    rng = np.random.default_rng(1)
    rows = []
    for seed in (1, 2):
        for test, (wp, s) in enumerate(
            [(wp, s) for wp in FACTORS[1].levels for s in FACTORS[0].levels], start=1
        ):
            v = 1.234e-10 * (1 + test)
            rows.append(
                {
                    "test": test,
                    "run_id": f"t{test:02d}-s{seed}",
                    "S": s,
                    "WP": wp,
                    "seed": seed,
                    "MU": 0.41234 + 0.01 * test + 0.001 * rng.standard_normal(),
                    "V": v,
                    "V_mm3": v * 1e9,
                    "status": "ok",
                }
            )
    summary = pd.DataFrame(rows)
    summary.loc[3, "status"] = "failed"
    design = summary.loc[summary["seed"] == 1, ["test", "S", "WP"]].reset_index(drop=True)
    anova_tables = {r: anova(summary, FACTORS, r) for r in ("MU", "V")}
    figures = [
        (
            "Main effects" if k < 2 else "Maps",
            f"Caption {k} <b>&</b>",
            tiny_png(tmp_path / f"f{k}.png", shade=40 * k),
        )
        for k in range(n_figures)
    ]
    return {
        "title": "Campaign <paper> & co",
        "design_table": design,
        "summary": summary,
        "anova_tables": anova_tables,
        "figures": figures,
        "config_text": 'name = "paper"\nnote = "<script>alert(1)</script>"',
        "version": "0.1.0",
        "notes": "First paragraph with <tags> & ampersands.\n\nSecond paragraph.",
    }


def test_report_is_complete_and_self_contained(tmp_path) -> None:
    inputs = make_inputs(tmp_path)
    out = write_report(tmp_path / "out" / "report.html", **inputs)
    assert out == tmp_path / "out" / "report.html"
    html = out.read_text(encoding="utf-8")
    assert html.startswith("<!DOCTYPE html>")

    # Every figure embedded as a base64 PNG with its caption (escaped).
    assert html.count('src="data:image/png;base64,') == 3
    assert html.count("<img ") == 3
    assert "Caption 0 &lt;b&gt;&amp;&lt;/b&gt;" in html
    assert 'width="4" height="3"' in html
    assert "<h2>Main effects</h2>" in html and "<h2>Maps</h2>" in html

    # Provenance, design and per-run tables.
    assert "Campaign &lt;paper&gt; &amp; co" in html
    assert "0.1.0" in html and "doi:10.1155/2016/8181260" in html
    # what else made the results (a provenance review: the version alone does not change)
    from importlib.metadata import version

    from brakeca._cachedir import source_key

    assert f"<tr><th>Kernel sources</th><td><code>{source_key()}</code>" in html
    assert f"numpy {version('numpy')}, numba {version('numba')}, scipy " in html
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html
    assert "<script>alert(1)" not in html
    assert "MU [-]" in html and "V [mm³]" in html
    mu = inputs["summary"]["MU"].iloc[0]
    assert f">{mu:.3f}<" in html  # MU to 3 decimals
    assert f">{1.234e-10 * 2 * 1e9:.4g}<" in html  # V of test 1 in mm^3
    assert 'class="failed"' in html
    # the run scalars under readable headers and in friendly units (the CSV keeps the names)
    assert "Run id" in html and "run_id" not in html

    # ANOVA tables with formatted p-values.
    assert 'id="anova-mu"' in html and 'id="anova-v"' in html
    assert "Type II ANOVA of MU" in html
    attrs = inputs["anova_tables"]["MU"].attrs
    assert f"R² = {100 * attrs['r_squared']:.2f} %" in html
    assert f"R²(adj) = {100 * attrs['r_squared_adj']:.2f} %" in html
    # Test 4 has one run left (the other failed): the model fits it whatever its value
    # (leverage 1), so no prediction of it without it, and no predicted R-squared.
    assert math.isnan(attrs["r_squared_pred"]) and "R²(pred) = undefined" in html
    assert f"s = {attrs['s']:.4g} m³" not in html  # MU has no unit
    # V's ANOVA in mm³, like the per-run table and the figures (the CSV tables keep m³)
    v_anova = inputs["anova_tables"]["V"]
    assert f"deviation s = {v_anova.attrs['s'] * 1e9:.4g} mm³ (Minitab&#39;s S)" in html
    assert "sums of squares and mean squares in (mm³)²" in html
    v_ss = v_anova.loc[v_anova["term"] == "Residual", "sum_sq"].iloc[0]
    assert f">{v_ss * 1e18:.4g}<" in html
    assert v_anova.attrs["s"] < 1e-6  # the caller's table is left in m³
    for term in ("S", "WP", "S:WP", "Residual"):
        assert f"<td>{term}</td>" in html
    p_cells = re.findall(r'<td class="num">(&lt; 0\.001|\d\.\d{3}|–)</td>', html)
    assert p_cells
    assert "First paragraph with &lt;tags&gt; &amp; ampersands." in html
    assert "<p>Second paragraph.</p>" in html

    # Nothing external: no remote src/href, stylesheet links, imports or fonts.
    lowered = html.lower()
    for needle in ('src="http', "src='http", 'href="http', "href='http", "<link", "@import"):
        assert needle not in lowered
    assert "url(" not in lowered
    assert "document.body.dataset.imagesLoaded" in html

    # Atomic write leaves no temporary file; writing again replaces the file.
    assert [p.name for p in out.parent.iterdir()] == ["report.html"]
    write_report(out, **{**inputs, "title": "Second"})
    assert "<h1>Second</h1>" in out.read_text(encoding="utf-8")
    assert [p.name for p in out.parent.iterdir()] == ["report.html"]


def test_figures_as_mapping_and_saturated_note(tmp_path) -> None:
    inputs = make_inputs(tmp_path)
    summary = inputs["summary"]
    single = summary[summary["seed"] == 1]
    inputs["anova_tables"] = {"MU": anova(single, FACTORS, "MU")}
    inputs["figures"] = {"only figure": tiny_png(tmp_path / "x.png")}
    when = datetime(2024, 1, 2, 3, 4, 5, tzinfo=UTC)
    html = render_report(**inputs, generated=when)
    assert html.count("data:image/png;base64,") == 1
    assert "<h2>Figures</h2>" in html
    assert "2024-01-02T03:04:05+00:00" in html
    assert "saturated" in html  # the ANOVA fallback note is shown


def test_bad_figures_raise_and_leave_nothing(tmp_path) -> None:
    inputs = make_inputs(tmp_path)
    target = tmp_path / "rep" / "report.html"
    with pytest.raises(FileNotFoundError, match="missing"):
        write_report(target, **{**inputs, "figures": {"missing": tmp_path / "nope.png"}})
    (tmp_path / "fake.png").write_text("not a png")
    with pytest.raises(ValueError, match="not a PNG"):
        write_report(target, **{**inputs, "figures": {"fake": tmp_path / "fake.png"}})
    assert not target.exists()


def test_format_p_value() -> None:
    assert format_p_value(1e-9) == "< 0.001"
    assert format_p_value(0.0123) == "0.012"
    assert format_p_value(0.5) == "0.500"
    assert format_p_value(float("nan")) == "–"
    assert format_p_value(None) == "–"


def test_model_summary_text_with_lack_of_fit() -> None:
    from brakeca.report import _model_summary_text

    attrs = {"s": 0.5e-9, "r_squared": 0.99, "r_squared_adj": 0.98, "r_squared_pred": math.nan}
    attrs |= {"pure_error_df": 48.0, "lack_of_fit_df": 9.0, "lack_of_fit_F": 25.06}
    text = _model_summary_text({**attrs, "lack_of_fit_p": 3e-15}, "m³")
    expected = "s = 5e-10 m³ (Minitab's S), R² = 99.00 %, R²(adj) = 98.00 %, R²(pred) = undefined"
    assert expected in text
    assert "pure error (48 df" in text and "lack of fit (9 df" in text
    assert "lack of fit F = 25.1, p < 0.001. The lack of fit is significant" in text
    assert text.endswith("read them as approximate.")  # a statistics review asked for it
    text = _model_summary_text({**attrs, "lack_of_fit_p": 0.011}, None)
    assert "p = 0.011. The lack of fit is significant" in text
    assert _model_summary_text({**attrs, "lack_of_fit_p": 0.2}, None).endswith("p = 0.200.")
    assert "lack of fit" not in _model_summary_text({**attrs, "lack_of_fit_p": math.nan}, None)
    assert _model_summary_text({}, None) == ""


def test_figures_are_numbered_in_the_order_the_page_shows_them(tmp_path) -> None:
    inputs = make_inputs(tmp_path)
    png = [tiny_png(tmp_path / f"g{k}.png", shade=10 * k) for k in range(3)]
    inputs["figures"] = [("First", "a0", png[0]), ("Second", "b1", png[1]), ("First", "a2", png[2])]
    html = render_report(**inputs)
    captions = re.findall(r"<figcaption>Figure (\d+)\. (\w+)</figcaption>", html)
    assert captions == [("1", "a0"), ("2", "a2"), ("3", "b1")]
    assert html.index('id="figure-2"') < html.index('id="figure-3"')


def test_run_scalars_have_readable_headers_and_units(tmp_path) -> None:
    inputs = make_inputs(tmp_path)
    summary = inputs["summary"].assign(
        total_emitted_mm3=1234.5678,
        total_generated_mm3=26401.7,
        final_primary_area_fraction=0.10386,
        max_ledger_residual=6.15284e-14,
        n_steps=491160,
        wall_time=29.6289,
    )
    summary.loc[3, "n_steps"] = np.nan  # a failed run: the column becomes floats
    html = render_report(**{**inputs, "summary": summary})
    for header in ("Emitted [mm³]", "Primary, last stop [%]", "Ledger residual [-]", "Steps"):
        assert f"<th>{header}</th>" in html
    assert "total_emitted_mm3" not in html and "wall_time" not in html
    for cell in ("1235", "26,402", "10.4", "6.2e-14", "491,160", "30"):
        assert f">{cell}<" in html


def test_a_fractional_design_shows_aliases_effects_and_its_kind(tmp_path) -> None:
    import itertools

    from brakeca.analysis import two_level_effects

    # a 2^(4-1) with D = A*B*C: main effects and interaction chains, V in m³
    factors = [Factor(n, (0.0, 1.0)) for n in "ABCD"]
    rng = np.random.default_rng(2)
    rows = []
    for c, b, a in itertools.product((-1, 1), repeat=3):
        d = a * b * c
        v = (2.0 + 1.0 * a + 0.5 * a * b + 0.05 * rng.standard_normal()) * 1e-9
        rows.append({"A": (a + 1) / 2, "B": (b + 1) / 2, "C": (c + 1) / 2, "D": (d + 1) / 2})
        rows[-1].update({"V": v, "test": len(rows), "run_id": f"t{len(rows)}", "status": "ok"})
    summary = pd.DataFrame(rows)
    inputs = make_inputs(tmp_path)
    effects = two_level_effects(summary, factors, "V")
    inputs.update(
        summary=summary,
        design_table=summary[["test", "A", "B", "C", "D"]],
        anova_tables={"V": anova(summary, factors, "V")},
        effects_tables={"V": effects},
        design_info="2^(4-1) fractional factorial, resolution IV: I = A·B·C·D",
    )
    html = render_report(**inputs)
    assert "2^(4-1) fractional factorial, resolution IV: I = A·B·C·D" in html
    assert "<th>Aliases</th>" in html and "<td>B:C:D</td>" in html
    assert "C:D (aliased with A:B)" in html  # the note of the terms left out
    # the effects table, in mm³ like the rest of the report, the active effects in bold
    assert "Effect [mm³]" in html and "Lenth" in html
    top = effects.iloc[0]
    assert top["term"] == "A" and top["significant"]
    assert f'<td class="num">{top["effect"] * 1e9:.4g}</td>' in html
    assert re.search(r'<tr class="sig">\s*<td>A</td>', html)
    # a full factorial's ANOVA has no Aliases column, and no effects table with WP at 3 levels
    full = render_report(**make_inputs(tmp_path))
    assert "Aliases</th>" not in full and "Effect [" not in full


def test_a_response_surface_section_in_the_report_units(tmp_path) -> None:
    """The section 'Response surface': V's coefficients and sums of squares in mm³, the ANOVA
    by source with its indented terms, lack of fit and the stationary point; none without
    fits."""
    import itertools

    from brakeca.rsm import Coding, fit_response_surface

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    coded = list(itertools.product((-1.0, 0.0, 1.0), repeat=2)) + [(0.0, 0.0)] * 2
    rng = np.random.default_rng(4)
    rows = []
    for x1, x2 in coded:
        v = (2.0 + 0.5 * x1 - 0.8 * x1**2 + 0.3 * x1 * x2 + 0.01 * rng.standard_normal()) * 1e-9
        rows.append({"A": a.decode(x1), "WR": b.decode(x2), "V": v, "status": "ok"})
    summary = pd.DataFrame(rows)
    fit = fit_response_surface(summary, [a, b], "V")
    html = render_report(**make_inputs(tmp_path), surface_fits={"V": fit})
    section = html[html.index('<section id="surface">') :]
    section = section[: section.index("</section>")]
    assert '<a href="#surface">Response surface</a>' in html
    assert "<th>Coef [mm³]</th>" in section and "Adj SS [(mm³)²]" in section
    coef = dict(zip(fit.coefficients["term"], fit.coefficients["coef"], strict=True))
    assert f'<td class="num">{coef["A*A"] * 1e9:.5g}</td>' in section
    assert "\u2003\u2003A*WR</td>" in section and "Lack-of-Fit</td>" in section
    assert "Coded -1 to +1: A 10 to 20 %, WR log10 1e-07 to 1e-06 m." in section
    assert f"Model: V = {fit.coef[0] * 1e9:.4g} + " in section
    assert "(coded units; V in mm³)" in section
    uncoded = fit.equation(6, scale=1e9, uncoded=True)
    assert f"In uncoded units (the factors&#39; levels, log10 of WR): {uncoded}." in section
    st = fit.stationary
    assert st is not None
    assert f"Stationary point (gradient zero): a {st['kind']} at A = " in section
    assert ("inside the region" if st["inside"] else "outside the region") in section
    assert '<section id="surface">' not in render_report(**make_inputs(tmp_path))
    # "In short" gives the quadratic's significant terms, smallest p first (a review: such
    # a report's "In short" had held other lines alone, under the factorial's heading)
    findings = unescape(
        html[html.index('<section id="findings">') : html.index('<section id="design">')]
    )
    assert "The terms of each response's quadratic model" in findings
    assert "The terms of each response's ANOVA" not in findings
    terms = fit.anova[~fit.anova["source"].isin(["Model", "Linear", "Square", "2-Way Interaction"])]
    terms = terms.iloc[: list(terms["source"]).index("Error")]
    hits = terms[terms["p_value"] < 0.05].sort_values("p_value")
    assert list(hits["source"]) == ["A*A", "A", "A*WR"]  # the sizes the data were made with
    line = re.search(r"<li>(V \(.*?)</li>", findings).group(1)
    assert line.startswith("V (quadratic surface): A*A (p < 0.0001), A (p < 0.0001), A*WR (p ")
    assert f"R² = {100 * fit.statistics['r_squared']:.1f} %" in line
    assert f"; its stationary point is a {st['kind']} " in line
    # no term with p < 0.05: said so (a diff review: every term was listed, named "nan")
    from brakeca.report import surface_in_short

    noise = summary.assign(V=1e-9 * (2.0 + np.random.default_rng(5).standard_normal(len(summary))))
    flat = fit_response_surface(noise, [a, b], "V")
    assert (flat.anova.iloc[:-4]["p_value"].dropna() > 0.05).all()
    (said,) = surface_in_short({"V": flat})
    assert said.startswith("V (quadratic surface): no term has p < 0.05; R² = ")
    assert "nan" not in said


def test_the_response_optimization_in_the_report(tmp_path) -> None:
    import itertools

    from brakeca.rsm import Coding, Goal, fit_response_surface, optimize

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    rows = [
        {"A": a.decode(x1), "WR": b.decode(x2), "V": (2.0 + x1 - 0.5 * x2**2) * 1e-9}
        for x1, x2 in itertools.product((-1.0, 0.0, 1.0), repeat=2)
    ]
    fit = fit_response_surface(pd.DataFrame(rows), [a, b], "V")
    goals = [Goal("V", "minimize", 0.5e-9, 3e-9)]
    best = optimize({"V": fit}, goals)
    html = render_report(**make_inputs(tmp_path), surface_fits={"V": fit}, optimum=(goals, best))
    section = html[html.index('<h3 id="surface-optimum">') :]
    assert f"composite desirability, here {best.composite:.3f}" in section
    findings = unescape(
        html[html.index('<section id="findings">') : html.index('<section id="design">')]
    )
    assert "Then the setting that best meets the design's goals." in findings
    assert (
        f"The design's goals are best met at A = {best.levels['A']:.4g} %, WR = "
        f"{best.levels['WR']:.4g} m: composite desirability {best.composite:.3f}" in findings
    )
    assert "<td>minimize: target 0.5, upper 3</td>" in section  # V's limits in mm³
    assert f'<td class="num">{best.predicted["V"] * 1e9:#.4g}</td>' in section
    assert "At the edge of that region: A" in section  # V falls with A: A at its low end
    no_optimum = render_report(
        **make_inputs(tmp_path), surface_fits={"V": fit}, optimum_note="The goals could not"
    )
    assert "The goals could not" in no_optimum and "surface-optimum" not in no_optimum


def test_goals_without_any_surface_still_say_why(tmp_path) -> None:
    html = render_report(**make_inputs(tmp_path), optimum_note="The goals could not be optimized")
    section = html[html.index('<section id="surface">') :]
    assert "No response could be fitted" in section
    assert "The goals could not be optimized" in section


def test_the_box_cox_check_in_the_report(tmp_path) -> None:
    """One row per response: λ̂, its interval (an end beyond the search range as "below -2" or
    "above 2"), the rounded λ and the reading;
    a response without λ says why; no section without results."""
    from brakeca.boxcox import box_cox_profile

    rng = np.random.default_rng(8)
    level = np.tile(np.arange(3.0), 10)
    exog = np.column_stack([np.ones(30), level == 1, level == 2]).astype(float)
    v = box_cox_profile(10.0**level * np.exp(rng.normal(0, 0.1, 30)), exog, response="V")
    mu = box_cox_profile([0.3, -0.1, 0.2], response="MU")
    html = render_report(**make_inputs(tmp_path), box_cox={"V": v, "MU": mu})
    section = html[html.index('<h3 id="anova-box-cox">') :]
    section = section[: section.index("</section>")]
    assert f'<td class="num">{v.lambda_hat:.2f}</td>' in section
    assert f"<td>{v.ci_low:.2f} to {v.ci_high:.2f}</td>" in section
    assert "the log fits better than the response as it is" in section
    assert "<td>not defined: needs positive values" in section
    assert "anova-box-cox" not in render_report(**make_inputs(tmp_path))
    import dataclasses

    open_ended = dataclasses.replace(v, ci_low=-math.inf, ci_high=math.inf)
    html = render_report(**make_inputs(tmp_path), box_cox={"V": open_ended})
    assert "<td>below -2 to above 2</td>" in html


def test_short_wall_times_and_pm10_columns_in_the_runs_table(tmp_path) -> None:
    """A run of 0.4 s is not shown as 0 s; the PM10 columns get headers with their unit."""
    inputs = make_inputs(tmp_path)
    summary = inputs["summary"].assign(wall_time=0.43, PM10_mg_km=13949.7)
    summary.loc[summary.index[0], "wall_time"] = 123.4
    html = render_report(**{**inputs, "summary": summary})
    assert '<td class="num">0.4</td>' in html and '<td class="num">123</td>' in html
    assert "<th>PM10 [mg/km]</th>" in html and '<td class="num">13,950</td>' in html


def test_the_runs_table_shows_what_is_held_and_leaves_out_columns_that_say_nothing() -> None:
    """A report review: "Emitted" and "Worn off" printed the same in 20 of the paper study's
    24 rows though the caption sends the reader to their difference (test 1: 0.054 of 582
    mm³); the table had five columns that said nothing (replicate all 0, order = test,
    status all ok, error empty). MU_SD keeps its trailing zeros beside its neighbours."""
    from brakeca.report import _runs_table

    summary = pd.DataFrame(
        {
            "test": [1, 2],
            "replicate": [0, 0],
            "order": [1, 2],
            "status": ["ok", "ok"],
            "error": ["", ""],
            "MU_SD": [0.011, 0.0232],
            "total_emitted_mm3": [582.0, 3452.0],
            "total_generated_mm3": [582.054, 3452.0 - 5e-12],  # round-off: 0
        }
    )
    table = _runs_table(summary)
    assert table.columns == [
        "Test", "MU_SD [-]", "Emitted [mm³]", "Worn off [mm³]", "Held [mm³]"
    ]  # fmt: skip
    cells = [row["cells"] for row in table.rows]
    assert cells[0][1:] == ["0.0110", "582.0", "582.1", "0.05400"]  # as its neighbours
    assert cells[1][4] == "0"
    # where they say something, they stay: replicates, another order, a failed run
    told = summary.assign(replicate=[0, 1], order=[2, 1], status=["ok", "failed"])
    told["error"] = ["", "ContactError: x"]
    columns = _runs_table(told).columns
    assert {"Replicate", "Order", "Status", "Error"} <= set(columns)
    assert _runs_table(told).rows[1]["cls"] == "failed"


def test_a_stationary_value_of_the_wrong_sign_is_called_out(tmp_path) -> None:
    """A positive response (V) whose fitted bowl bottoms out below zero: the report says so
    beside the stationary point's value (a second review saw '-0.776 mm³' unremarked)."""
    import itertools

    from brakeca.rsm import Coding, fit_response_surface

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    rows = [
        {"A": a.decode(x1), "WR": b.decode(x2), "V": (math.exp(2 * x1) + x2**2) * 1e-9}
        for x1, x2 in itertools.product((-1.0, 0.0, 1.0), repeat=2)
    ]
    fit = fit_response_surface(pd.DataFrame(rows), [a, b], "V")
    assert fit.stationary is not None and fit.stationary["predicted"] < 0.0
    html = render_report(**make_inputs(tmp_path), surface_fits={"V": fit})
    assert "(not positive, though every run&#39;s V is: the quadratic does not keep" in html


def test_model_summary_text_reads_a_negative_predicted_r_squared() -> None:
    from brakeca.report import _model_summary_text

    attrs = {"s": 0.04, "r_squared": 0.98, "r_squared_adj": 0.92}
    text = _model_summary_text({**attrs, "r_squared_pred": -2.9788}, None)
    assert "R²(pred) = -297.88 %" in text and "R²(pred) below 0: the model predicts" in text
    assert "coefficients for" not in text  # without n and the residual df
    # the leverage of this model, whatever the design (a new user's review: the text named
    # an unreplicated factorial for a replicated and a composite design alike)
    sized = _model_summary_text({**attrs, "r_squared_pred": -0.5, "n": 11, "df_resid": 3}, None)
    assert (
        "The model has 8 coefficients for 11 runs, so a run's fit is on average 73 % its own "
        "value (its leverage)"
    ) in sized and "unreplicated" not in sized
    assert "below 0" not in _model_summary_text({**attrs, "r_squared_pred": 0.5}, None)
    assert "below 0" not in _model_summary_text({**attrs, "r_squared_pred": math.nan}, None)


def test_the_model_summary_says_what_an_unreplicated_residual_is() -> None:
    """Without pure error the residual is the terms left out, and the report says so (a
    helper's review: the paper study's 'Residual 9 df' was explained nowhere)."""
    from brakeca.report import _model_summary_text

    base = {"r_squared": 0.9, "r_squared_adj": 0.8, "r_squared_pred": 0.7, "s": 0.01}
    text = _model_summary_text({**base, "df_resid": 9.0, "pure_error_df": 0.0, "order": 2}, None)
    assert "The residual (9 df) is the terms the model leaves out (interactions of more " in text
    assert "than 2 factors): no two runs share their levels" in text
    one = _model_summary_text({**base, "df_resid": 4.0, "pure_error_df": 0.0, "order": 1}, None)
    assert "(the interactions)" in one
    # the order fitted, where a saturated model's interactions were pooled (a DoE review:
    # "more than 2 factors" above the residual of a 2^2 design's A:B)
    pooled = {
        **base,
        "df_resid": 1.0,
        "pure_error_df": 0.0,
        "order": 2,
        "fitted_order": 1,
        "pooled": True,
    }
    said = "(the interactions, pooled because the model with them left no degrees of freedom)"
    assert said in _model_summary_text(pooled, None)
    # backward elimination that removes every term: the order of the model it started from
    # (a diff review: "more than 2 factors" after a main-effects model lost all its terms)
    import itertools

    rng = np.random.default_rng(5)
    runs = pd.DataFrame(
        [
            {"A": a, "B": b, "C": c, "y": rng.standard_normal()}
            for a, b, c in itertools.product((0.0, 1.0), repeat=3)
        ]
    )
    factors = [Factor(n, (0.0, 1.0)) for n in "ABC"]
    table = anova(runs, factors, "y", interactions=False, alpha_to_remove=0.1)
    assert table.attrs["note"].endswith("no term is left")
    assert table.attrs["fitted_order"] == 1
    text = _model_summary_text(table.attrs, None)
    assert "(the interactions and the terms backward elimination removed)" in text
    reduced = {**base, "df_resid": 5.0, "pure_error_df": 0.0, "alpha_to_remove": 0.1}
    assert "and the terms backward elimination removed" in _model_summary_text(reduced, None)
    for attrs in (
        {**base, "df_resid": 9.0, "pure_error_df": 3.0},  # replicates: lack of fit instead
        {**base, "df_resid": 0.0, "pure_error_df": 0.0},  # saturated
        base,
    ):
        assert "leaves out" not in _model_summary_text(attrs, None)


def test_the_alias_note_comes_with_aliases_only_and_before_the_tables(tmp_path) -> None:
    """The ANOVA's general note (bold, Contribution) heads the section; the explanation of
    the Aliases column only where a table names aliases (it had followed the Box-Cox table,
    explaining a column a full factorial does not have; a helper's review of the report)."""
    html = render_report(**make_inputs(tmp_path))
    assert "Terms with p &lt; 0.05 in bold" in html
    assert html.index("Terms with p &lt; 0.05 in bold") < html.index('id="anova-mu"')
    assert "Aliases (designs that do not separate" not in html
    from brakeca.design import design_from_dict

    design = design_from_dict(
        {
            "name": "frac",
            "base": "paper",
            "root_seed": 1,
            "generators": ["C = A*B"],
            "factors": [
                {"name": n, "field": f, "levels": lv}
                for n, f, lv in (
                    ("A", "automaton.secondary_removal_fraction", [0, 1]),
                    ("B", "wear.resin_wear_depth", [1e-7, 1e-6]),
                    ("C", "pad.fibre_area_fraction", [0.1, 0.2]),
                )
            ],
        }
    )
    rows = pd.DataFrame([dict(p.levels) for p in design.points() for _ in range(2)])
    rows["MU"] = np.random.default_rng(3).normal(0.3, 0.01, len(rows)) + 0.05 * rows["A"]
    rows["status"] = "ok"
    inputs = make_inputs(tmp_path)
    inputs["anova_tables"] = {"MU": anova(rows, design.factors, "MU")}
    assert "Aliases (designs that do not separate" in render_report(**inputs)


def test_an_optimized_log10_v_is_also_given_as_v(tmp_path) -> None:
    """A goal on log10_V_mm3: the fitted value and both intervals also as V in mm³ (an
    engineer reads V; a helper's review of the report)."""
    import itertools

    from brakeca.rsm import Coding, Goal, fit_response_surface, optimize

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    rng = np.random.default_rng(2)
    rows = [
        {"A": a.decode(x1), "WR": b.decode(x2), "log10_V_mm3": 1.0 - 0.2 * x1 + rng.normal(0, 0.01)}
        for x1, x2 in itertools.product((-1.0, 0.0, 1.0), repeat=2)
    ]
    fit = fit_response_surface(pd.DataFrame(rows), [a, b], "log10_V_mm3")
    goals = [Goal("log10_V_mm3", "minimize", 0.5, 1.5)]
    best = optimize({"log10_V_mm3": fit}, goals)
    html = render_report(
        **make_inputs(tmp_path), surface_fits={"log10_V_mm3": fit}, optimum=(goals, best)
    )
    section = html[html.index('<h3 id="surface-optimum">') :]
    fitted = best.predicted["log10_V_mm3"]
    assert f"{fitted:#.4g} (geometric-mean V {10**fitted:.3g} mm³)" in section
    low, high = best.prediction["log10_V_mm3"]
    assert f"(V {10**low:.3g} to {10**high:.3g} mm³)" in section
    assert "minimize: target 0.5, upper 1.5 (V 3.16, 31.6 mm³)" in section  # the goal as V


def test_a_figure_wider_than_the_page_opens_at_full_size_on_a_click(tmp_path) -> None:
    """A large panel grid is scaled down to the page, where its labels are too small to
    read (a helper's review): a click shows it at full size (a checkbox and its label, no
    script); a figure that fits the page is shown as it is."""
    inputs = make_inputs(tmp_path)
    inputs["figures"] = [
        ("Interactions", "wide", tiny_png(tmp_path / "wide.png", width=2880, height=40)),
        ("Interactions", "narrow", tiny_png(tmp_path / "narrow.png", width=800, height=40)),
    ]
    html = render_report(**inputs)
    wide = html[html.index('<figure id="figure-1">') : html.index('<figure id="figure-2">')]
    narrow = html[html.index('<figure id="figure-2">') :]
    narrow = narrow[: narrow.index("</figure>")]
    assert '<input type="checkbox" class="zoom" id="zoom-1" hidden>' in wide
    assert '<label class="zoom" for="zoom-1"' in wide and "</label>" in wide
    assert 'width="2880"' in wide
    assert "zoom" not in narrow
    assert "input.zoom:checked + label.zoom img { max-width: none; }" in html


def test_the_level_means_table(tmp_path) -> None:
    """Each factor level's mean of every response, V in mm³, with the runs averaged (a
    helper's review: the report had the level means in plots and CSV files only)."""
    from brakeca.analysis import main_effects

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"]
    means = {r: main_effects(summary, FACTORS, r) for r in ("MU", "V")}
    html = render_report(**inputs, level_means=means)
    section = html[html.index('<section id="level-means">') :]
    section = section[: section.index("</section>")]
    assert '<a href="#level-means">Level means</a>' in html
    assert "<th>MU</th><th>V [mm³]</th><th>Runs</th>" in section
    first = means["V"].iloc[0]
    assert f'<td class="num">{first["mean"] * 1e9:#.4g}</td>' in section
    assert f'<td class="num">{means["MU"].iloc[0]["mean"]:#.4g}</td>' in section
    assert 'id="level-means"' not in render_report(**inputs)


def test_a_stationary_point_at_an_impossible_level_says_so() -> None:
    """A = -45 % at log10 V's stationary point was printed as a setting (a helper's review)."""
    import itertools

    from brakeca.report import _stationary_text
    from brakeca.rsm import Coding, fit_response_surface

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    rows = [  # a minimum in A far below its low level: at coded -12
        {"A": a.decode(x1), "WR": b.decode(x2), "y": (x1 + 12.0) ** 2 + x2**2}
        for x1, x2 in itertools.product((-1.0, 0.0, 1.0), repeat=2)
    ]
    fit = fit_response_surface(pd.DataFrame(rows), [a, b], "y")
    assert fit.stationary is not None and fit.stationary["levels"]["A"] < 0
    text = _stationary_text(fit, 1.0, None)
    assert "A below 0 there, which no pad can have" in text


def test_volumes_keep_their_trailing_zeros() -> None:
    """A column of volumes reads alike: 0.3350 beside 0.3463 (it had been 0.335; a helper's
    review of the report)."""
    from brakeca.report import _fmt

    assert [_fmt(v, "volume") for v in (0.335, 0.3463, 354.0, 15.8, 0.0, 12345.6)] == [
        "0.3350",
        "0.3463",
        "354.0",
        "15.80",
        "0",
        "12,346",
    ]


def test_the_level_means_note_fits_the_design() -> None:
    """Centre points of a two-level design are in no level's mean; a composite design's
    middle level holds its centre and axial runs (the note had said the first of both; a
    helper's second review)."""
    from brakeca.report import _level_means_info

    table = pd.DataFrame({"factor": ["A"], "level": [1.0], "mean": [0.3], "n": [4]})
    centred = table.copy()
    centred.attrs["center_n"] = 4
    two_level = _level_means_info({"MU": centred}, surface=False)
    assert "the 4 centre point runs are in no level's mean" in two_level
    assert "(the main-effects plots' points)" in two_level
    composite = _level_means_info({"MU": table}, surface=True)
    assert "middle level holds its centre points and the axial runs" in composite
    assert "no level's mean" not in composite and "plots' points" not in composite


def test_a_stationary_log10_v_is_also_given_as_v() -> None:
    """log10 V's stationary point's fitted value also as V in mm³ (a helper's review)."""
    import itertools

    from brakeca.report import _stationary_text
    from brakeca.rsm import Coding, fit_response_surface

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    rows = [
        {"A": a.decode(x1), "WR": b.decode(x2), "log10_V_mm3": 1.0 + x1**2 + x2**2}
        for x1, x2 in itertools.product((-1.0, 0.0, 1.0), repeat=2)
    ]
    fit = fit_response_surface(pd.DataFrame(rows), [a, b], "log10_V_mm3")
    text = _stationary_text(fit, 1.0, None)
    value = float(fit.stationary["predicted"])
    assert f"(geometric-mean V {10**value:.3g} mm³)" in text


def test_in_short_names_the_significant_terms_by_contribution() -> None:
    """The report's first section: each response's terms with p < 0.05, the largest
    contribution first, with R²; a table without a test says so."""
    from brakeca.report import _finding

    frame = pd.DataFrame(
        {
            "term": ["S", "A", "S:A", "WR", "Residual"],
            "p_value": [0.01, 1e-6, 0.2, 0.04, math.nan],
            "percent_contribution": [5.0, 80.0, 1.0, 3.0, 11.0],
        }
    )
    frame.attrs["r_squared"] = 0.89
    assert _finding("MU", frame) == (
        "MU: A (80.0 %), S (5.0 %), WR (3.0 %); together 88.0 % of the variation; R² = 89.0 %"
    )
    none = frame.assign(p_value=[0.3, 0.2, 0.5, 0.9, math.nan])
    assert _finding("V", none) == "V: no term has p < 0.05; R² = 89.0 %"
    saturated = frame.assign(p_value=math.nan)
    assert _finding("V", saturated).startswith("V: no term can be tested (no residual")
    saturated.attrs.update(n=4, df_resid=0.0)  # how many runs, where too few (a robustness
    # review); not for a constant response, which runs enough to test
    assert _finding("V", saturated).startswith("V: no term can be tested with the 4 run(s) fitted")
    assert _finding("V", pd.DataFrame()) == ""
    many = pd.DataFrame(
        {
            "term": [f"T{k}" for k in range(8)] + ["Residual"],
            "p_value": [0.001] * 8 + [math.nan],
            "percent_contribution": [10.0] * 8 + [20.0],
        }
    )
    # every term is named (a review: "and 1 more" had hidden a main effect)
    assert "T5 (10.0 %), T6 (10.0 %), T7 (10.0 %); together 80.0 %" in _finding("y", many)
    # a main effect with its level means, in the report's unit (mm³ for V), labels that are
    # names rather than signs; an interaction without
    means = pd.DataFrame(
        {
            "factor": ["S", "S", "A", "A", "C", "C"],
            "level": [0.0, 1.0, 10.0, 20.0, 1.0, 2.0],
            "label": ["-", "+", "-", "+", "paper", "trace"],
            "mean": [2e-9, 3e-9, 1e-9, 4.5e-9, 2e-9, 2e-9],
            "n": [2] * 6,
        }
    )
    frame.loc[2, "p_value"] = 0.001
    text = _finding("V", frame, means)
    assert text.startswith(
        "V: A (80.0 %: 1.000 at A = 10, 4.500 at A = 20 [mm³]), S (5.0 %: 2.000 at S = 0, "
        "3.000 at S = 1 [mm³]), WR (3.0 %), S:A (1.0 %); together"
    )
    c = frame.assign(term=["C", "A", "S:A", "WR", "Residual"])
    assert "C (5.0 %: 2.000 at C = paper, 2.000 at C = trace [mm³])" in _finding("V", c, means)


def test_in_short_cautions_a_main_effect_in_an_interaction_and_gives_log_v_in_mm3() -> None:
    """A report review: A's mean effect was given alone while WP:A made it differ fourfold
    from level to level of WP, and log10 V's level means were in log units nobody can use.
    A main effect in a significant interaction is said to be so, and log10 V's means come
    with V's geometric means in mm³ and their ratio from the first level to the last."""
    from brakeca.report import _finding

    frame = pd.DataFrame(
        {
            "term": ["WP", "A", "WP:A", "S", "Residual"],
            "p_value": [1e-6, 1e-4, 0.01, 0.3, math.nan],
            "percent_contribution": [70.0, 20.0, 5.0, 1.0, 4.0],
        }
    )
    means = pd.DataFrame(
        {
            "factor": ["A", "A", "WP", "WP"],
            "level": [10.0, 20.0, 1e-15, 1e-13],
            "label": ["-", "+", "-", "+"],
            "mean": [1.0, 0.5, 0.0, 2.0],
            "n": [2] * 4,
        }
    )
    text = _finding("log10_V_mm3", frame, means)
    assert "A (20.0 %: 1.000 at A = 10, 0.5000 at A = 20; geometric means of V 10.00, 3.162 " in (
        text
    )
    assert "mm³, ×0.316)" in text  # 10^0.5 / 10^1
    assert "geometric means of V 1.000, 100.0 mm³, ×100)" in text
    assert text.endswith(
        "; WP and A are each in a significant interaction (WP:A): their level means average "
        "over the other factor's levels, between which the effect differs (the interaction "
        "plots)"
    )
    alone = frame.assign(p_value=[1e-6, 1e-4, 0.2, 0.3, math.nan])  # WP:A not significant
    assert "interaction" not in _finding("log10_V_mm3", alone, means)
    # an interaction of three factors, significant where no pair is, cautions as well
    three = frame.assign(term=["WP", "A", "S:WP:A", "S", "Residual"])
    assert _finding("MU", three, means).endswith(
        "; WP and A are each in a significant interaction (S:WP:A): their level means "
        "average over the other factors' levels, between which the effect differs (the "
        "interaction plots)"
    )
    assert "geometric" not in _finding("MU", frame, means)
    # in a fraction, a factor in an alias of a significant interaction is cautioned too (a
    # statistics review: WP and WR were said to be "in" S:A while S:A = WP:WR)
    fraction = frame.assign(
        term=["WP", "A", "S:A", "S", "Residual"], aliases=["", "", "WP:WR", "", ""]
    )
    assert _finding("MU", fraction, means).endswith(
        "; WP and A are each in a significant interaction or one of its aliases (S:A = WP:WR): "
        "their level means average over the other factor's levels, between which the effect "
        "differs (the interaction plots); which term of an alias chain acts, the design cannot "
        "tell"
    )
    # an alias of neither WP nor A (nor one of three factors, left out): A alone, in S:A
    neither = fraction.assign(aliases=["", "", "-S:WR:C + B:C", "", ""])
    assert "; A is in a significant interaction or one of its aliases (S:A = B:C): its " in (
        _finding("MU", neither, means)
    )


def test_in_short_says_the_log_of_v_leaves_out_the_runs_that_emitted_nothing() -> None:
    """log10 V's level means, and V's geometric means from them, leave out the runs with
    V = 0 (no log); the Notes said so, the line giving those means did not."""
    from brakeca.report import in_short

    frame = pd.DataFrame(
        {
            "term": ["A", "Residual"],
            "p_value": [1e-4, math.nan],
            "percent_contribution": [90.0, 10.0],
        }
    )

    def means(n):
        return pd.DataFrame(
            {"factor": ["A", "A"], "level": [10.0, 20.0], "label": ["-", "+"],
             "mean": [1.0, 0.5], "n": n}
        )  # fmt: skip

    tables = {"V": frame, "log10_V_mm3": frame}
    lines = in_short(tables, level_means={"V": means([4, 4]), "log10_V_mm3": means([4, 2])})
    assert lines[1].endswith(
        "; these means leave out the 2 runs that emitted nothing (V = 0 has no log; Notes)"
    )
    assert "emitted nothing" not in lines[0]  # V's own line counts every run
    one = in_short(tables, level_means={"V": means([4, 4]), "log10_V_mm3": means([3, 4])})
    assert one[1].endswith("the 1 run that emitted nothing (V = 0 has no log; Notes)")
    alike = in_short(tables, level_means={"V": means([4, 4]), "log10_V_mm3": means([4, 4])})
    assert "emitted nothing" not in alike[1]


def test_in_short_names_an_aliased_term_with_its_short_aliases() -> None:
    """A review of a screening report: "In short" named S:mu0 (19.7 % of V) alone, where the
    fold-over showed the share was its aliases' (WP:slope = A:modulus). A term is now named
    with its aliases of one or two factors; those of three or more are left out."""
    from brakeca.report import _finding

    frame = pd.DataFrame(
        {
            "term": ["A", "S:mu0", "S:WP", "Residual"],
            "p_value": [0.008, 0.009, 0.01, math.nan],
            "percent_contribution": [20.4, 19.7, 7.3, 3.5],
            "aliases": ["S:WR:slope + S:modulus:mu0", "WP:slope + A:modulus", "-WR:mu0", ""],
        }
    )
    assert _finding("V", frame).startswith(
        "V: A (20.4 %), S:mu0 = WP:slope + A:modulus (19.7 %), S:WP = -WR:mu0 (7.3 %); "
    )


def test_in_short_says_the_curvature_and_what_the_pure_error_finds_besides() -> None:
    """A new user's review: "In short" hid a significant Curvature in "and 1 more", and said
    "no term has p < 0.05" for MU above an effects table with seven terms significant
    against the pure error (the ANOVA's residual held a large lack of fit)."""
    from brakeca.report import _finding

    frame = pd.DataFrame(
        {
            "term": ["A", "c", "A:c", "Curvature", "Residual"],
            "p_value": [0.2, 0.3, 0.4, 1e-11, math.nan],
            "percent_contribution": [30.0, 20.0, 5.0, 40.0, 5.0],
            "sum_sq": [7.5, 5.0, 1.25, 10.0, 1.25],
        }
    )
    # the pure error of the centre points: curvature's F = 10 / (0.01 / 2), p 0.0005
    frame.attrs.update(r_squared=0.9, lack_of_fit_p=1e-4, pure_error_df=2, pure_error_ss=0.01)
    effects = pd.DataFrame(
        {
            "term": ["A", "c", "A:c", "Ct Pt"],
            "p_value": [0.001, 0.002, 0.3, 1e-5],
            "significant": [True, True, False, True],
        }
    )
    effects.attrs["method"] = "pure error"
    assert _finding("MU", frame, effects=effects) == (
        "MU: no factor or interaction has p < 0.05; R² = 90.0 %; curvature between the "
        "levels: p < 0.001 (significant); the ANOVA's residual lacks fit (p < 0.001), and "
        "against the pure error of the repeated runs alone (the effects table) A, c also "
        "have p < 0.05"
    )
    # curvature significant against the pure error alone: the curvature clause says both
    # tests (a new user's review: "none found at 0.05", its Ct Pt hidden in "and 2 more")
    flat = frame.assign(p_value=[0.2, 0.3, 0.4, 0.07, math.nan])
    assert _finding("MU", flat, effects=effects) == (
        "MU: no factor or interaction has p < 0.05; R² = 90.0 %; curvature between the "
        "levels: p = 0.070 against the ANOVA's residual, which lacks fit (none found at "
        "0.05), p < 0.001 against the pure error of the repeated runs alone (significant); "
        "the ANOVA's residual lacks fit (p < 0.001), and against the pure error of the "
        "repeated runs alone (the effects table) A, c also have p < 0.05"
    )
    # by Lenth's method (no pure error) the centre points' term is named first
    lenth = effects.copy()
    lenth.attrs["method"] = "Lenth"
    pooled = flat.copy()
    pooled.attrs.update(flat.attrs, pooled=True)
    assert _finding("MU", pooled, effects=lenth).endswith(
        "by Lenth's method (the effects table) curvature (Ct Pt), A, c also have p < 0.05"
    )
    fits = frame.copy()
    fits.attrs.update(frame.attrs, lack_of_fit_p=0.5)
    fits["p_value"] = [0.01, 0.3, 0.4, 0.2, math.nan]
    assert _finding("MU", fits, effects=effects) == (
        "MU: A (30.0 %); together 30.0 % of the variation; R² = 90.0 %; curvature between "
        "the levels: p = 0.200 (none found at 0.05)"
    )
    # one term found besides: "has" (a review: "S:WP:A also have")
    one = effects.assign(significant=[True, False, False, False])
    assert _finding("MU", frame, effects=one).endswith("(the effects table) A also has p < 0.05")
    # no effects table (a factor of three levels), or none found besides: the lack of fit is
    # said all the same (a review of a replicated study: a general factorial's p of 0.003
    # had gone unsaid)
    general = frame[frame["term"] != "Curvature"].copy()
    general.attrs.update(frame.attrs)
    lacks = (
        "; the ANOVA's residual lacks fit (p < 0.001): terms the model leaves out move it by "
        "more than the seed-to-seed scatter, and the F tests, made against that residual, "
        "are conservative"
    )
    assert _finding("MU", general).endswith(lacks)
    none = effects.assign(significant=False)
    assert _finding("MU", general, effects=none).endswith(lacks)
    # a pure error that identical runs shrink: the lack of fit is no sure sign, and the F
    # tests are not called conservative (a diff review: beside the note that says otherwise)
    silent = general.copy()
    silent.attrs.update(general.attrs, silent_repeat_df=6)
    assert _finding("MU", silent).endswith(
        "; the ANOVA's residual lacks fit (p < 0.001), against a pure error that identical "
        "runs make small (the ANOVA's note): not a sure sign of terms the model leaves out"
    )
    # the curvature clause has said the residual lacks fit: not said again (a diff review)
    flat_none = _finding("MU", flat, effects=none)
    assert "which lacks fit" in flat_none and flat_none.count("lacks fit") == 1


def test_the_trend_of_a_three_level_factor_is_shown_under_its_anova(tmp_path) -> None:
    """A review found the report silent on how WP (three levels) enters the model: the
    ANOVA's 2 df for it say only that its levels differ. The trends table under each ANOVA
    gives its linear and quadratic parts, V's sums of squares in the report's (mm³)²."""
    from brakeca.analysis import factor_trends

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"]
    trends = {r: factor_trends(summary, FACTORS, r) for r in ("MU", "V")}
    assert list(trends["V"]["part"]) == ["linear", "quadratic"]
    html = render_report(**inputs, trend_tables=trends)
    assert html.count("Trend of ") == 2 and "Trend of V over the levels of WP" in html
    assert "SS [(mm³)²]" in html and "log10 WP" in html
    shown = float(trends["V"]["sum_sq"].iloc[0]) * 1e18
    assert f"{shown:.4g}" in html
    assert "Trend of " not in render_report(**inputs)  # none given: none shown


def test_runs_with_a_large_standardized_residual_are_named(tmp_path) -> None:
    """A review found the MU Box–Cox reading resting on one run (standardized residual 2.7)
    that nothing in the report pointed at; the runs beyond ±2 are named under the ANOVA, as
    Minitab lists its unusual observations, V in the report's mm³."""
    from brakeca.analysis import residuals

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"].copy()
    ok = summary.index[summary["status"] == "ok"]
    summary.loc[ok[0], "V"] *= 3.0  # one run far off the additive model
    table = residuals(summary, FACTORS, "V")
    far = table.loc[table["std_residual"].abs() > 2.0]
    assert len(far) >= 1
    html = render_report(**inputs, residual_tables={"V": table})
    line = re.search(r"Unusual runs \(standardized residual beyond ±2[^<]*", html)
    assert line is not None
    first = far.iloc[0]
    assert f"test {int(first['test'])}" in line.group(0)
    assert f"V {float(first['observed']) * 1e9:.4g} mm³" in line.group(0)
    assert f"standardized residual {float(first['std_residual']):+.2f}" in line.group(0)
    calm = table.assign(std_residual=0.5)
    assert "Unusual runs" not in render_report(**inputs, residual_tables={"V": calm})


def test_curvature_against_the_pure_error_where_the_residual_lacks_fit() -> None:
    """A screening review: the ANOVA said "no evidence of curvature" (p = 0.070, against a
    residual holding a large lack of fit) while the effects table's Ct Pt row, against the
    pure error, gave p < 0.001, with no word on why. The curvature text now gives the test
    against the pure error too where the lack of fit is significant, and V's sums of squares
    are converted with the pure error's (both in (mm³)²)."""
    from brakeca.report import _anova_in_report_units, _curvature_text

    frame = pd.DataFrame(
        {
            "term": ["A", "Curvature", "Residual"],
            "df": [1.0, 1.0, 5.0],
            "sum_sq": [4e-18, 2e-18, 5e-18],
            "p_value": [0.01, 0.07, math.nan],
            "aliases": ["", "", ""],
        }
    )
    frame.attrs.update(center_points=4, lack_of_fit_p=1e-5, pure_error_df=3.0)
    frame.attrs["pure_error_ss"] = 3e-21  # mean square 1e-21 m⁶: F = 2e-18 / 1e-21 = 2000
    shown, unit = _anova_in_report_units("V", frame)
    assert unit == "mm³" and shown.attrs["pure_error_ss"] == pytest.approx(3e-3)
    text = _curvature_text(shown)
    assert "p = 0.070: no evidence of curvature between the levels at 0.05." in text
    assert "holds a significant lack of fit (p < 0.001" in text
    assert "against the pure error alone (3 df, the scatter of the repeated runs) curv" in text
    assert "curvature has F = 2e+03, p < 0.001: significant." in text
    fits = frame.copy()
    fits.attrs.update(frame.attrs, lack_of_fit_p=0.4)  # no lack of fit: the ANOVA's alone
    assert "pure error" not in _curvature_text(fits)


def test_in_short_explains_only_what_the_design_has(tmp_path) -> None:
    """A figures-and-report review read aliases (with factors of another study), centre
    points and pure error in the "In short" note of a full factorial without them: the note
    now explains each only where the design has it. make_inputs: a replicated full
    factorial without centre points."""
    html = render_report(**make_inputs(tmp_path))
    intro = html[html.index("<h2>In short</h2>") : html.index("</p>", html.index("In short"))]
    assert "error holds." in intro
    assert "aliases" not in intro and "S:mu0" not in intro
    assert "centre points" not in intro
    assert "pure error of the repeated runs alone" in intro  # two seeds a test: pure error


def test_in_short_says_which_scale_of_v_to_read() -> None:
    """A figures-and-report review: V's and log10 V's lines disagreed (WR significant on one
    scale only) and nothing said which held, while Box-Cox held the log and not V, and the
    linear model fitted negative volumes. V's line now says both."""
    import types

    from brakeca.report import _scale_clause

    def _v_scale(*args):
        return _scale_clause("V", *args)

    def profile(lam, low, high):
        return types.SimpleNamespace(
            defined=True,
            lambda_hat=lam,
            ci_low=low,
            ci_high=high,
            confidence=0.95,
            contains=lambda x: low <= x <= high,
        )

    residuals = pd.DataFrame({"test": [7, 14, 19, 3], "fitted": [-1e-10, -2e-10, -3e-10, 1e-9]})
    assert _v_scale({"V": profile(0.06, -0.02, 0.14)}, {"V": residuals}, True) == (
        "; Box-Cox puts V's λ at 0.06 (95 % interval -0.02 to 0.14), which holds the log and "
        "not V as it is: read the log10_V_mm3 line; the linear model of V fits a negative "
        "volume for tests 7, 14, 19"
    )
    assert _v_scale({"V": profile(0.06, -0.02, 0.14)}, None, False).endswith("not V as it is")
    assert _v_scale({"V": profile(0.9, 0.6, 1.2)}, {"V": residuals.iloc[3:]}, True) == ""
    assert _v_scale({"V": profile(0.5, 0.3, 0.7)}, None, True) == ""  # neither 1 nor 0
    # λ̂ on the search range's edge is said to be a bound (a figures review)
    from brakeca.boxcox import box_cox_profile

    z = np.random.default_rng(1).normal(10.0, 3.0, 40)
    edge = box_cox_profile(z[z > 0.5] ** (-1 / 3), response="MU")  # z normal: λ = -3
    assert edge.edge == -1 and not edge.contains(1.0)
    assert "Box-Cox puts MU's λ at or below -2, the search range's edge (95 % interval " in (
        _scale_clause("MU", {"MU": edge}, None, True)
    )
    # few residual degrees of freedom: Montgomery's wider interval holds 1 as well, and the
    # line says the scale is not settled instead of sending the reader to the log's (a
    # user's review of a screening design with 1 residual df)
    few = profile(0.06, -0.02, 0.14)
    few.ci_low_df, few.ci_high_df, few.df_resid = -1.13, 1.08, 1.0
    assert _v_scale({"V": few}, None, True) == (
        "; Box-Cox puts V's λ at 0.06 (95 % interval -0.02 to 0.14), which holds the log and "
        "not V as it is, but with 1 residual degree of freedom Montgomery's wider interval "
        "(-1.13 to 1.08) holds λ = 1 too: the data do not settle V's scale"
    )
    # MU_SD (a review of the new response): no log line to send the reader to, so an
    # interval that holds neither 1 nor 0 is said too, and its negative fits are spreads
    assert _scale_clause(
        "MU_SD", {"MU_SD": profile(0.39, 0.24, 0.55)}, {"MU_SD": residuals}, True
    ) == (
        "; Box-Cox puts MU_SD's λ at 0.39 (95 % interval 0.24 to 0.55), which holds neither "
        "MU_SD as it is nor its log (the report analyses MU_SD as it is); the linear model "
        "of MU_SD fits a negative spread for tests 7, 14, 19"
    )
    # a reading that rests on the unusual runs says so (a report review: MU_SD's line said
    # neither scale held, while without tests 17 and 23 λ = 1 did); MU, once left out for
    # the paper study's outlier, is read as the others are
    spread = profile(0.39, 0.24, 0.55)
    spread.without, spread.without_runs = profile(0.64, 0.37, 1.03), "tests 17, 23"
    assert _scale_clause("MU_SD", {"MU_SD": spread}, None, True) == (
        "; Box-Cox puts MU_SD's λ at 0.39 (95 % interval 0.24 to 0.55), which holds neither "
        "MU_SD as it is nor its log (the report analyses MU_SD as it is); but that rests on "
        "tests 17, 23: without them, λ̂ = 0.64 (95 % interval 0.37 to 1.03), which holds "
        "λ = 1 (Box-Cox, in the ANOVA section)"
    )
    spread.without = profile(0.5, 0.3, 0.7)  # without them, still not λ = 1: nothing added
    assert _scale_clause("MU_SD", {"MU_SD": spread}, None, True).endswith("as it is)")
    # where Montgomery's interval holds λ = 1, the scale is unsettled already: no second
    # "but" (a diff review)
    spread.without = profile(0.64, 0.37, 1.03)
    spread.ci_low_df, spread.ci_high_df, spread.df_resid = 0.1, 1.2, 9.0
    unsettled = _scale_clause("MU_SD", {"MU_SD": spread}, None, True)
    assert unsettled.endswith("the data do not settle MU_SD's scale")
    assert "rests on" not in unsettled
    friction = profile(-1.43, -math.inf, -0.87)
    friction.without, friction.without_runs = profile(0.57, -1.34, math.inf), "test 23"
    assert _scale_clause("MU", {"MU": friction}, {"MU": residuals.iloc[3:]}, True) == (
        "; Box-Cox puts MU's λ at -1.43 (95 % interval below -2 to -0.87), which holds "
        "neither MU as it is nor its log (the report analyses MU as it is); but that rests "
        "on test 23: without it, λ̂ = 0.57 (95 % interval -1.34 to above 2), which holds "
        "λ = 1 (Box-Cox, in the ANOVA section)"
    )
    assert _scale_clause("MU", {"MU": profile(0.9, 0.6, 1.2)}, {"MU": residuals}, True) == (
        "; the linear model of MU fits a negative coefficient of friction for tests 7, 14, 19"
    )
    assert _scale_clause("log10_V_mm3", {}, {"log10_V_mm3": residuals}, True) == ""


def test_a_general_factorial_s_coefficients_are_folded_under_its_anova(tmp_path) -> None:
    """Minitab gives a general factorial (the paper's WP has three levels) a coefficients
    table and a regression equation, which the report had not: they are shown folded under
    each ANOVA, V's in mm³, and only where the response has no two-level effects table."""
    from brakeca.analysis import level_coefficients

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"]
    tables = {r: level_coefficients(summary, FACTORS, r) for r in ("MU", "V")}
    html = render_report(**inputs, coefficient_tables=tables)
    assert html.count("at every level, and the regression equation</summary>") == 2
    assert "Coef [mm³]" in html and "Regression equation (V in mm³)" in html
    v = tables["V"].set_index(["term", "level"])
    shown = float(v.loc[("WP", "+"), "coefficient"]) * 1e9
    assert f"{shown:.4g}" in html  # in the table, in mm³
    assert f"{shown:.4g} WP[+]" in html  # and in the equation
    assert "+ †" in html  # the level Minitab leaves out, marked
    assert "regression equation</summary>" not in render_report(**inputs)
    # a response with a two-level effects table shows that instead
    effects = {"MU": pd.DataFrame({"term": ["S"], "effect": [0.1], "significant": [True]})}
    html = render_report(**inputs, coefficient_tables=tables, effects_tables=effects)
    assert html.count("at every level, and the regression equation</summary>") == 1


def test_a_surface_s_residual_without_pure_error_is_its_higher_terms() -> None:
    """A response surface's residual without repeated runs is the terms beyond the quadratic,
    not "interactions of more than 2 factors" (an analysis review: a two-factor design's)."""
    from brakeca.report import _model_summary_text

    attrs = {"r_squared": 0.9, "df_resid": 2.0, "pure_error_df": 0.0, "s": 0.1}
    surface = _model_summary_text({**attrs, "surface": True}, None)
    assert "(the terms beyond the quadratic: cubic and higher)" in surface
    assert "interactions of more than" not in surface
    assert "interactions of more than 2 factors" in _model_summary_text(attrs, None)


def test_tukey_s_comparisons_of_a_three_level_factor_are_shown_under_its_anova(tmp_path) -> None:
    """Which of WP's levels differ: the comparisons' table under each ANOVA, V's in mm³,
    each row the second level less the first, with its simultaneous interval."""
    from brakeca.analysis import level_comparisons

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"]
    tables = {r: level_comparisons(summary, FACTORS, r) for r in ("MU", "V")}
    assert len(tables["V"]) == 3
    html = render_report(**inputs, comparison_tables=tables)
    assert html.count("Which levels of WP differ in ") == 2
    assert "Difference of their means [mm³]" in html and "95 % interval [mm³]" in html
    first = tables["V"].iloc[0]
    assert (first["level_a"], first["level_b"]) == ("-", "0")
    assert "<td>0 − (-)</td>" in html and "<td>+ − 0</td>" in html  # Minitab's brackets
    assert f"{float(first['difference']) * 1e9:.4g}" in html
    assert f"{float(first['ci_low']) * 1e9:.4g} to {float(first['ci_high']) * 1e9:.4g}" in html
    assert "Which levels of" not in render_report(**inputs)
    # Minitab's grouping letters in the caption, largest mean first
    from brakeca.analysis import tukey_grouping

    letters = tukey_grouping(tables["V"])
    assert len(letters) == 3
    shown = ", ".join(
        f"WP{r.level} in group"  # as the legends write a level (a report review)
        + ("s " if len(r.grouping) > 1 else " ")
        + " and ".join(r.grouping)
        for r in letters.itertuples()
    )
    caption = f"share no letter are significantly different): WP: {shown}"
    assert f"{caption} (tables/grouping_V.csv)." in html
    assert "Grouping by Tukey&#39;s method at 95 % (Minitab&#39;s grouping letters" in html
    # Minitab's columns: SE of difference, T = q / sqrt(2) with the difference's sign
    assert "SE of difference [mm³]" in html and "T (q / √2)" in html
    t = float(first["q"]) / np.sqrt(2.0) * np.sign(float(first["difference"]))
    # V is the same in both seeds of a test here: an exact fit (its residual at round-off is
    # taken as the 0 it is: an analysis review), so T is infinite, as the ANOVA's F
    assert np.isinf(t) and "exact fit" in tables["V"].attrs.get("note", "") + str(
        inputs["anova_tables"]["V"].attrs["note"]
    )
    assert f'<td class="num">{"∞" if t > 0 else "−∞"}</td>' in html
    t = float(tables["MU"].iloc[0]["q"]) / np.sqrt(2.0)  # MU has a scatter: a finite T
    assert np.isfinite(t) and f'<td class="num">{abs(t):.2f}</td>' in html.replace("−", "")


def test_the_log_response_s_heading_says_what_it_is(tmp_path) -> None:
    """The section of log10_V_mm3 had been headed by the column's name alone (a figures
    review); its heading now says it is log10 of V in mm³, the anchor unchanged."""
    from brakeca.analysis import anova

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"].assign(log10_V_mm3=lambda d: np.log10(d["V"] * 1e9))
    tables = {**inputs["anova_tables"], "log10_V_mm3": anova(summary, FACTORS, "log10_V_mm3")}
    html = render_report(**{**inputs, "summary": summary, "anova_tables": tables})
    assert '<h3 id="anova-log10_v_mm3">Response log10 V (column log10_V_mm3, V in mm³)</h3>' in html
    assert '<h3 id="anova-mu">Response MU</h3>' in html


def test_the_long_captions_are_given_once_and_referred_to_after(tmp_path) -> None:
    """A review: the comparisons', coefficients' and trends' captions (130-150 words each)
    were repeated word for word under every response; the first response's explains them,
    the later ones refer to it and keep their own files, notes and letters."""
    from html import unescape

    from brakeca.analysis import factor_trends, level_coefficients, level_comparisons

    inputs = make_inputs(tmp_path)
    summary = inputs["summary"]
    responses = ("MU", "V")
    html = unescape(
        render_report(
            **inputs,
            comparison_tables={r: level_comparisons(summary, FACTORS, r) for r in responses},
            coefficient_tables={r: level_coefficients(summary, FACTORS, r) for r in responses},
            trend_tables={r: factor_trends(summary, FACTORS, r) for r in responses},
        )
    )
    text = " ".join(html.split())
    for whole in (
        "(Minitab's comparisons of a general linear model)",
        "as Minitab gives them for a general factorial",
        "so its F says only that the levels differ",
    ):
        assert text.count(whole) == 1, whole
    assert "Which levels of WP differ in V: Tukey's pairwise comparisons of the levels' " in text
    assert "as explained under MU above; p < 0.05 in bold." in text
    assert "The table is tables/comparisons_V.csv." in text
    assert "The ANOVA model of V as coefficients, coded as explained under MU above" in text
    assert "The table is tables/coefficients_V.csv." in text
    assert "Trend of V over the levels of WP: its main effect split into orthogonal" in text
    assert text.count("The levels: ") == 1  # the legend with the first caption


def test_v_s_section_names_the_runs_fitted_a_negative_volume() -> None:
    """A review: only "In short" had named them; V's section gives each with its fitted and
    observed volume in mm³."""
    from brakeca.report import _negative_fits

    frame = pd.DataFrame(
        {
            "test": [7, 14, 3],
            "fitted": [-2.21e-9, -3.38e-9, 5e-9],
            "observed": [2.08e-9, 1.12e-9, 4e-9],
        }
    )
    assert _negative_fits("V", frame) == (
        " The ANOVA model fits a negative volume to 2 runs (test 7: fitted -2.21, observed "
        "2.08; test 14: fitted -3.38, observed 1.12 mm³): an additive model cannot follow "
        "effects that multiply V; log10 V's section reads them as ratios."
    )
    assert _negative_fits("MU", frame) == "" and _negative_fits("V", frame.iloc[2:]) == ""


def test_in_short_names_what_lenth_finds_in_the_interactions_a_saturated_anova_pooled() -> None:
    """A DoE review: a 2^(5-2) fraction's "In short" said no term of MU had p < 0.05, the
    ANOVA's error holding the two-factor chains it pooled (one of them 30 % of the variation),
    while the effects table found three terms by Lenth's method. The line names them."""
    import itertools

    from brakeca.analysis import two_level_effects
    from brakeca.report import _finding

    rng = np.random.default_rng(3)
    rows = []
    for c, b, a in itertools.product((-1, 1), repeat=3):  # D = ABC, standard order
        y = 10.0 + 1.0 * a + 1.2 * a * b + 0.05 * rng.standard_normal()
        rows.append({"A": a, "B": b, "C": c, "D": a * b * c, "y": y})
    frame = pd.DataFrame(rows)
    factors = [Factor(n, (-1.0, 1.0)) for n in "ABCD"]
    table = anova(frame, factors, "y")
    assert "pooled into the residual" in table.attrs["note"] and table.attrs["pooled"]
    assert table.attrs["fitted_order"] == 1 and table.attrs["order"] == 2
    assert (table["p_value"].dropna() > 0.05).all()  # the pooled chain hides A as well
    effects = two_level_effects(frame, factors, "y")
    assert effects.attrs["method"] == "Lenth"
    line = _finding("y", table, None, effects)
    assert line.startswith("y: no term has p < 0.05; R² = ")
    assert line.endswith(
        "; the ANOVA's error is the interactions it pooled (its model with them left no "
        "degrees of freedom), and by Lenth's method (the effects table) A:B = C:D, A also have "
        "p < 0.05"
    )
    # with an error of its own (replicates) nothing was pooled: no such clause
    twice = pd.concat([frame, frame.assign(y=frame["y"] + 0.01)], ignore_index=True)
    plain = _finding("y", anova(twice, factors, "y"), None, two_level_effects(twice, factors, "y"))
    assert "pooled" not in plain


def test_a_level_is_named_as_a_coded_label_only_where_the_factor_has_them() -> None:
    """The Tukey grouping names WP's levels as the legends do (WP+, WP0, WP-), but a factor
    of values whose level is 0 is "S = 0", not "S0" beside "S = 0.5" (a review of large
    designs)."""
    from brakeca.report import _coded, _level_named

    coded = pd.DataFrame({"level": ["+", "0", "-"]})
    values = pd.DataFrame({"level": ["0.5", "0", "1"]})
    assert [_level_named("WP", v, _coded(coded)) for v in coded["level"]] == ["WP+", "WP0", "WP-"]
    assert [_level_named("S", v, _coded(values)) for v in values["level"]] == [
        "S = 0.5",
        "S = 0",
        "S = 1",
    ]
    assert not _coded(pd.DataFrame({"level": ["0"]}))  # a lone 0 is a value


def test_the_nav_lists_each_anova_and_small_contributions_keep_their_digits(tmp_path) -> None:
    """A report review: the nav had no entry for the longest section's responses, and a
    contribution of 0.0031 % read "0.00" beside the Pareto bar's 0.0031."""
    from brakeca.report import _anova_table

    html = render_report(**make_inputs(tmp_path))
    nav = html[html.index('<nav aria-label="Contents">') : html.index("</nav>")]
    assert '<a href="#anova">ANOVA</a>:' in nav
    assert '<a href="#anova-mu">MU</a>' in nav and '<a href="#anova-v">V</a>' in nav
    for anchor in ("anova-mu", "anova-v"):
        assert f'id="{anchor}"' in html  # each points at its section
    frame = pd.DataFrame(
        {"term": ["S", "WP"], "df": [1.0, 1.0], "sum_sq": [1.0, 2.0], "mean_sq": [1.0, 2.0],
         "F": [3.0, 4.0], "p_value": [0.5, 0.01], "percent_contribution": [0.0031, 12.345]}
    )  # fmt: skip
    cells = [row["cells"] for row in _anova_table(frame)[0].rows]
    shares = [c for row in cells for c in row if c in ("0.0031", "12.35", "0.00")]
    assert shares == ["0.0031", "12.35"]


def test_long_lists_of_runs_name_the_first_and_count_the_rest() -> None:
    """A review of large designs: a 256-run design's line named 76 runs with negative fits
    and joined outliers with "and" seventeen times."""
    from brakeca.report import _MOST_RUNS_LISTED, _negative_fits, _runs_listed

    assert _runs_listed(["test 1"], False) == "test 1"
    assert _runs_listed(["test 1", "test 2"], False) == "test 1 and test 2"
    assert _runs_listed(["a", "b", "c"], False) == "a, b and c"
    assert _runs_listed(["a", "b", "c"], True) == "a; b and c"  # replicated names hold commas
    names = [f"test {k}" for k in range(1, 21)]
    assert _runs_listed(names, False) == ", ".join(names[:_MOST_RUNS_LISTED]) + " and 12 more"
    frame = pd.DataFrame(
        {"test": range(1, 21), "replicate": 0, "fitted": [-1e-9] * 20, "observed": 1e-9}
    )
    text = _negative_fits("V", frame)
    assert "fits a negative volume to 20 runs" in text
    assert text.count("fitted -1") == _MOST_RUNS_LISTED
    assert "and 12 more, in tables/residuals_V.csv" in text


def test_all_findings_are_the_reports_in_short_in_its_order(tmp_path) -> None:
    """A study's terminal and its report had each put "In short" together on their own (a
    maintainability review): both now take report.all_findings, the surfaces' lines first,
    a response with a surface said by it alone, then the other responses', the further
    lines given (empty ones dropped) and PM10's last."""
    import itertools

    from brakeca.report import all_findings, in_short, surface_in_short
    from brakeca.rsm import Coding, fit_response_surface

    a, b = Coding("A", 10.0, 20.0, unit="%"), Coding("WR", 1e-7, 1e-6, log=True, unit="m")
    rng = np.random.default_rng(4)
    rows = [
        {"A": a.decode(x1), "WR": b.decode(x2), "status": "ok"}
        | {"V": (2.0 + 0.5 * x1 - 0.8 * x1**2 + 0.01 * rng.standard_normal()) * 1e-9}
        for x1, x2 in [*itertools.product((-1.0, 0.0, 1.0), repeat=2), (0.0, 0.0), (0.0, 0.0)]
    ]
    fit = fit_response_surface(pd.DataFrame(rows), [a, b], "V")
    frame = pd.DataFrame(
        {
            "term": ["A", "Residual"],
            "p_value": [1e-4, math.nan],
            "percent_contribution": [90.0, 10.0],
        }
    )
    tables = {"V": frame, "MU": frame}
    lines = all_findings(
        tables, surface_fits={"V": fit}, more=["", "held at the floor"], pm10_line="PM10 line"
    )
    (surface,) = surface_in_short({"V": fit})
    (mu,) = in_short({"MU": frame})
    assert lines == [surface, mu, "held at the floor", "PM10 line"]
    assert lines[:2] != in_short(tables)  # V's own ANOVA line is left to its surface
    html = render_report(
        **(make_inputs(tmp_path) | {"anova_tables": tables}),
        surface_fits={"V": fit},
        more_findings=["", "held at the floor"],
    )
    findings = html[html.index('<section id="findings">') : html.index('<section id="design">')]
    said = [
        unescape(re.sub(r"<[^>]+>", "", li)) for li in re.findall(r"<li>(.*?)</li>", findings, re.S)
    ]
    assert said == [unescape(x) for x in lines[:3]]
