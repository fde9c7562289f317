"""Single-file, offline HTML report of a factorial campaign.

The report holds the provenance (package version, date, configuration), the design table,
the per-run results (MU, V), the ANOVA table of every response and every figure, embedded as
a base64 PNG ``data:`` URI. It loads no external resource (no CSS, JavaScript, fonts or
images from the network) and can be opened offline or mailed as one file. Everything that
comes from data is HTML-escaped (Jinja2 autoescaping). A tiny inline script sets
``document.body.dataset.imagesLoaded`` to the number of images that decoded
(``naturalWidth > 0``) once all have settled, which the browser test checks.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import base64
import math
import numbers
import platform
import re
import struct
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from brakeca._cachedir import source_key
from brakeca._console import is_replicated, run_named
from brakeca._io import write_text
from brakeca.analysis import UNUSUAL_RESIDUAL as _UNUSUAL_RESIDUAL
from brakeca.analysis import display_unit
from brakeca.results import library_versions

__all__ = [
    "REPORT_TEMPLATE",
    "all_findings",
    "format_p_value",
    "in_short",
    "render_report",
    "surface_in_short",
    "write_report",
]

PAPER_REFERENCE = (
    'J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad '
    'Properties on Friction and Wear Emissions", Advances in Tribology, 2016, '
    "Article ID 8181260, doi:10.1155/2016/8181260"
)

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

#: Jinja2 template of the report (autoescaped; no external resources).
REPORT_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="brakeca {{ version }}">
<title>{{ title }}</title>
<style>
:root { --fg: #1d2733; --muted: #5b6673; --line: #d5dbe1; --head: #eef2f6; --accent: #27496d; }
* { box-sizing: border-box; }
body { margin: 0 auto; max-width: 1200px; padding: 1.5rem 2rem 4rem; color: var(--fg);
  font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial,
  sans-serif; background: #fff; }
h1 { font-size: 1.7rem; margin: 0 0 .3rem; color: var(--accent); }
h2 { font-size: 1.3rem; margin: 2.2rem 0 .6rem; padding-bottom: .2rem;
  border-bottom: 2px solid var(--line); }
h3 { font-size: 1.05rem; margin: 1.4rem 0 .4rem; }
.meta, .note, figcaption, .caption { color: var(--muted); font-size: .9rem; }
nav ul { display: flex; flex-wrap: wrap; gap: .3rem 1.2rem; padding: 0; list-style: none; }
nav a, a { color: var(--accent); }
.table-wrap { overflow-x: auto; margin: .4rem 0 1rem; }
table { border-collapse: collapse; font-size: .85rem; }
th, td { border: 1px solid var(--line); padding: .25rem .55rem; text-align: left;
  white-space: nowrap; }
th { background: var(--head); font-weight: 600; }
table.kv td { white-space: normal; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.sig td { font-weight: 600; }
tr.failed td { color: #a61b1b; }
tr:nth-child(even) td { background: #fafbfc; }
p.equation { font-family: ui-monospace, monospace; font-size: .85rem; }
pre { background: #f6f8fa; border: 1px solid var(--line); padding: .8rem; overflow-x: auto;
  font: 12px/1.4 ui-monospace, SFMono-Regular, Menlo, Consolas, monospace; }
figure { margin: 1.2rem 0 2rem; overflow-x: auto; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid var(--line); }
figure label.zoom { cursor: zoom-in; }
input.zoom:checked + label.zoom { cursor: zoom-out; }
input.zoom:checked + label.zoom img { max-width: none; }
@media print { nav { display: none; } figure, table { page-break-inside: avoid; } }
</style>
</head>
<body>
<header>
<h1>{{ title }}</h1>
<p class="meta">brakeca {{ version }} &middot; generated {{ generated }}</p>
{%- if notice %}
<p class="note">{{ notice }}</p>
{%- endif %}
</header>
<nav aria-label="Contents"><ul>
{%- if findings %}
<li><a href="#findings">In short</a></li>
{%- endif %}
<li><a href="#design">Design</a></li>
<li><a href="#runs">Per-run results</a></li>
{%- if pm10 %}
<li><a href="#pm10">Brake PM10</a></li>
{%- endif %}
{%- if level_means %}
<li><a href="#level-means">Level means</a></li>
{%- endif %}
<li><a href="#anova">ANOVA</a>
{%- if anova | length > 1 or box_cox %}:
{%- for item in anova %} <a href="#anova-{{ item.anchor }}">{{ item.heading }}</a>
{%- if not loop.last or box_cox %},{% endif %}
{%- endfor %}
{%- if box_cox %} <a href="#anova-box-cox">Box–Cox</a>{% endif %}
{%- endif %}</li>
{%- if surfaces or optimum_note %}
<li><a href="#surface">Response surface</a></li>
{%- endif %}
{%- for section in figure_sections %}
<li><a href="#{{ section.anchor }}">{{ section.name }}</a></li>
{%- endfor %}
{%- if notes %}
<li><a href="#notes">Notes</a></li>
{%- endif %}
<li><a href="#provenance">Provenance</a></li>
</ul></nav>


{% macro render_table(table, caption_text="") -%}
<div class="table-wrap"><table>
{%- if caption_text %}<caption class="caption">{{ caption_text }}</caption>{% endif %}
<thead><tr>{% for col in table.columns %}<th>{{ col }}</th>{% endfor %}</tr></thead>
<tbody>
{%- for row in table.rows %}
<tr{% if row.cls %} class="{{ row.cls }}"{% endif %}>
{%- for cell in row.cells %}<td{% if table.numeric[loop.index0] %} class="num"{% endif %}>
{{- cell }}</td>{% endfor %}</tr>
{%- endfor %}
</tbody></table></div>
{%- endmacro %}

{%- if findings %}
<section id="findings">
<h2>In short</h2>
{%- if findings_surface %}
<p class="note">The terms of each response's quadratic model (section "Response surface")
with p &lt; 0.05, smallest p first, and its R²; the lack of fit where the runs repeat a point
and it is significant; and where the fitted surface's stationary point lies (a maximum, a
minimum or a saddle point, inside or outside the region the runs span).
{%- if optimum %} Then the setting that best meets the design's goals.{% endif %}
{%- else %}
<p class="note">The terms of each response's ANOVA (below) with p &lt; 0.05, largest share of
the variation first (contribution: the term's sum of squares over the total). A main effect
among the first six comes with the mean response at each of its levels (plain means of the
runs, as in the table "Level means"; a design that is not balanced mixes the other factors'
effects into them). The ANOVA's notes say what its error holds.
{%- if anova_aliases %} A term is named with its aliases of one or two factors (as
<code>A:B = C:D</code>): the share is the whole chain's, which the design cannot split among
them.{% endif %}
{%- if findings_centre %} The centre points' curvature is always said.{% endif %}
{%- if findings_pure_error %} Where the ANOVA's residual lacks fit, the terms that the effects
table, tested against the pure error of the repeated runs alone, finds besides are named
too.{% endif %}
{%- endif %}
{%- if pm10 %} The last line gives the runs' brake PM10 against the Euro 7 limits (section
"Brake PM10").{% endif %}</p>
<ul>
{%- for line in findings %}
<li>{{ line }}</li>
{%- endfor %}
</ul>
</section>
{%- endif %}

<section id="design">
<h2>Design</h2>
{%- if design_info %}<p class="note">{{ design_info }}</p>{% endif %}
{{ render_table(design) }}
</section>

<section id="runs">
<h2>Per-run results</h2>
<p class="note">MU: mean coefficient of friction over the stops run [-], 3 decimals; V: mean
emitted wear volume per stop [mm&sup3;]; MU_SD: friction stability, the standard deviation of
the per-stop mean COF over the stops run [-], divided by their number, not one less (not one of
the paper's responses; 0 where every stop had the same mean COF). Emitted and worn off: the
volumes that left the band and that wear removed from it over the whole run; held: their
difference, what the secondary plateaus still hold (the particles in the contact leave it at
the end of every stop; where they are carried over the stops, automaton.end_of_stop_streams =
"carry", held counts them too). Primary and secondary, last stop: the plateaus' shares of the
band in the last stop, time-weighted over it (before the S rule acts at its end). Secondary and
in contact, all stops: the secondary plateaus' share of the band (in contact or not) and the
share in contact, time-weighted over every stop the run made. Ledger residual: the largest
relative misclosure of the volume ledger in any step; friction residual: the largest relative
miss of the demanded friction force. Wall time: the run's own computing time.</p>
{{ render_table(runs) }}
</section>

{%- if pm10 %}
<section id="pm10">
<h2>Brake PM10 against the Euro 7 limits</h2>
<p class="note">{{ pm10_info }}</p>
{{ render_table(pm10) }}
</section>
{%- endif %}

{%- if level_means %}
<section id="level-means">
<h2>Level means</h2>
<p class="note">{{ level_means_info }}</p>
{{ render_table(level_means) }}
</section>
{%- endif %}

<section id="anova">
<h2>ANOVA</h2>
{%- if anova_info %}<p class="note">{{ anova_info }}</p>{% endif %}
{%- if anova %}
<p class="note">Terms with p &lt; 0.05 in bold. Contribution: the term's sum of squares in
this table over the total sum of squares about the mean (in a balanced design the same as
sequential sums of squares would give; in an unbalanced one Minitab's "Contribution", from
sequential sums of squares, differs).
{%- if anova_aliases %} Aliases (designs that do not separate every effect, such as a
fractional factorial): the terms of up to three factors the design cannot tell apart from the
term; what the table gives for the term is its effect plus theirs, each with the sign shown
(B:D - C:E: plus the effect of B:D, minus that of C:E; two-level terms only).
{%- endif %}</p>
{%- endif %}
{%- for item in anova %}
<h3 id="anova-{{ item.anchor }}">Response {{ item.heading }}</h3>
{%- if item.info %}<p class="note">{{ item.info }}</p>{% endif %}
{{ render_table(item.table) }}
{%- if item.note %}<p class="note">Note: {{ item.note }}</p>{% endif %}
{%- if item.unusual %}<p class="note">{{ item.unusual }}</p>{% endif %}
{%- if item.trends %}
<p class="note">{{ item.trends_info }}</p>
{{ render_table(item.trends) }}
{%- endif %}
{%- if item.effects %}
<p class="note">{{ item.effects_info }}</p>
{{ render_table(item.effects) }}
{%- endif %}
{%- if item.comparisons %}
<p class="note">{{ item.comparisons_info }}</p>
{{ render_table(item.comparisons) }}
{%- endif %}
{%- if item.coefficients %}
<details>
<summary>Coefficients of {{ item.response }} at every level, and the regression equation</summary>
<p class="note">{{ item.coefficients_info }}</p>
{{ render_table(item.coefficients) }}
<p class="note">Regression equation{{ item.equation_unit }}, X[l] being 1 in a run at level l
of X and 0 elsewhere (X:Y[l, m]: at level l of X and m of Y):</p>
<p class="equation">{{ item.equation }}</p>
</details>
{%- endif %}
{%- else %}
{%- if not anova_info %}<p class="note">No ANOVA tables.</p>{% endif %}
{%- endfor %}
{%- if box_cox %}
<h3 id="anova-box-cox">Scale of the responses (Box–Cox)</h3>
<p class="note">{{ box_cox_info }}</p>
{{ render_table(box_cox) }}
{%- endif %}
</section>
{%- if surfaces or optimum_note %}

<section id="surface">
<h2>Response surface</h2>
<p class="note">{{ surface_intro if surfaces else surface_none }}</p>
{%- for item in surfaces %}
<h3 id="surface-{{ item.anchor }}">Response {{ item.heading }}</h3>
<p class="note">{{ item.info }}</p>
{{ render_table(item.coefficients) }}
{{ render_table(item.anova) }}
{%- if item.stationary %}<p class="note">{{ item.stationary }}</p>{% endif %}
{%- endfor %}
{%- if optimum %}
<h3 id="surface-optimum">Response optimization</h3>
<p class="note">{{ optimum.info }}</p>
{{ render_table(optimum.factors) }}
{{ render_table(optimum.responses) }}
{%- endif %}
{%- if optimum_note %}<p class="note">{{ optimum_note }}</p>{% endif %}
</section>
{%- endif %}

{% for section in figure_sections %}
<section id="{{ section.anchor }}">
<h2>{{ section.name }}</h2>
{%- for fig in section.figures %}
<figure id="figure-{{ fig.number }}">
{%- if fig.wide %}
<input type="checkbox" class="zoom" id="zoom-{{ fig.number }}" hidden>
<label class="zoom" for="zoom-{{ fig.number }}"
 title="click: full size (scroll sideways), click again: fit">
{%- endif %}
<img src="data:image/png;base64,{{ fig.data }}" alt="{{ fig.caption }}"
{%- if fig.width %} width="{{ fig.width }}" height="{{ fig.height }}"{% endif %}>
{%- if fig.wide %}</label>{% endif %}
<figcaption>Figure {{ fig.number }}. {{ fig.caption }}</figcaption>
</figure>
{%- endfor %}
</section>
{% endfor %}

{%- if notes %}
<section id="notes">
<h2>Notes</h2>
{%- for para in notes %}
<p>{{ para }}</p>
{%- endfor %}
</section>
{%- endif %}

<section id="provenance">
<h2>Provenance</h2>
<div class="table-wrap"><table class="kv">
<tr><th>brakeca version</th><td>{{ version }}</td></tr>
<tr><th>Report generated</th><td>{{ generated }} (each run file records when it was made,
<code>date_created</code>)</td></tr>
<tr><th>Kernel sources</th><td><code>{{ source_key }}</code> (this install's; each run file
records its own, <code>source_key</code>, and a campaign names the runs it reuses that other
sources made)</td></tr>
<tr><th>Python</th><td>{{ python }}</td></tr>
<tr><th>Libraries</th><td>{{ libraries }}</td></tr>
<tr><th>Model reference</th><td>{{ reference }}</td></tr>
</table></div>
<details>
<summary>Configuration (design and resolved base configuration)</summary>
<pre>{{ config_text }}</pre>
</details>
</section>


<script>
(function () {
  var images = Array.prototype.slice.call(document.images);
  var pending = images.length;
  function finish() {
    var loaded = images.filter(function (im) { return im.complete && im.naturalWidth > 0; });
    document.body.dataset.imagesTotal = String(images.length);
    document.body.dataset.imagesLoaded = String(loaded.length);
  }
  function settle() { pending -= 1; if (pending === 0) { finish(); } }
  if (pending === 0) { finish(); return; }
  images.forEach(function (im) {
    if (im.complete) { settle(); return; }
    im.addEventListener("load", settle, { once: true });
    im.addEventListener("error", settle, { once: true });
  });
})();
</script>
</body>
</html>
"""


# --- formatting ------------------------------------------------------------------------------


def _is_missing(value: Any) -> bool:
    if value is None:
        return True
    try:
        return bool(pd.isna(value))
    except (TypeError, ValueError):
        return False


def _fmt(value: Any, spec: str = ".6g") -> str:
    """Format a table cell: floats with ``spec`` (``"sig4"``: 4 significant digits, trailing
    zeros kept; ``"volume"``: the same, and whole numbers with thousands separators from
    10,000 on; ``"seconds"``: one decimal below 10), integers plainly, missing as a dash."""
    if _is_missing(value):
        return "–"
    if isinstance(value, bool | np.bool_):
        return str(bool(value))
    whole = spec.endswith("d")  # an integer format: a float column of whole numbers too
    if isinstance(value, int | np.integer):
        return format(int(value), spec) if whole else str(int(value))
    if isinstance(value, float | np.floating):
        v = float(value)
        if math.isinf(v):
            return "∞" if v > 0 else "−∞"
        if whole:
            return format(int(v), spec) if v.is_integer() else format(v, ".6g")
        if spec == "volume" and 1e4 <= abs(v) < 1e15:  # no exponent up to 1e15
            return f"{v:,.0f}"
        if spec in ("volume", "sig4"):
            # 4 significant digits, trailing zeros kept, so that a column reads alike
            # (0.3350 beside 0.3463)
            return format(v, "#.4g").rstrip(".") if v != 0.0 else "0"
        if spec == "seconds":  # a tenth of a second below 10 s (a short run is not 0 s)
            return format(v, ".1f") if abs(v) < 10.0 else format(v, ",.0f")
        return format(v, spec)
    return str(value)


def format_p_value(p: Any) -> str:
    """Format a p-value for a table.

    Parameters
    ----------
    p
        The p-value [-] or NaN.

    Returns
    -------
    str
        ``"< 0.001"`` below 0.001, three decimals otherwise, a dash when missing.
    """
    if _is_missing(p):
        return "–"
    p = float(p)
    if p < 1e-3:
        return "< 0.001"
    return f"{p:.3f}"


@dataclass(frozen=True)
class _Table:
    columns: list[str]
    numeric: list[bool]
    rows: list[dict[str, Any]]


def _generic_table(frame: pd.DataFrame) -> _Table:
    columns = [str(c) for c in frame.columns]
    numeric = [pd.api.types.is_numeric_dtype(frame[c]) for c in frame.columns]
    rows = [
        {"cells": [_fmt(v) for v in record], "cls": ""}
        for record in frame.itertuples(index=False, name=None)
    ]
    return _Table(columns, numeric, rows)


#: the per-run table's headers and formats of the run scalars (RunResult.scalars) and the
#: campaign's columns: column -> (header, format, multiplier); the CSV keeps the names
_RUN_COLUMNS: dict[str, tuple[str, str, float]] = {
    "test": ("Test", "", 1.0),
    "replicate": ("Replicate", "", 1.0),
    "order": ("Order", "", 1.0),
    "run_id": ("Run id", "", 1.0),
    "seed": ("Seed", "", 1.0),
    "status": ("Status", "", 1.0),
    "error": ("Error", "", 1.0),
    # 5e-06, not 0.0000 (a review); 0.0110, not 0.011, beside 0.0232 (a report review)
    "MU_SD": ("MU_SD [-]", "#.3g", 1.0),
    "total_emitted_mm3": ("Emitted [mm³]", "volume", 1.0),
    "total_generated_mm3": ("Worn off [mm³]", "volume", 1.0),
    "held_mm3": ("Held [mm³]", "volume", 1.0),  # as its neighbours (a diff review)
    "final_primary_area_fraction": ("Primary, last stop [%]", ".1f", 100.0),
    "final_secondary_area_fraction": ("Secondary, last stop [%]", ".1f", 100.0),
    "cycle_secondary_area_fraction": ("Secondary, all stops [%]", ".1f", 100.0),
    "cycle_contact_area_fraction": ("In contact, all stops [%]", ".1f", 100.0),
    "max_ledger_residual": ("Ledger residual [-]", ".1e", 1.0),
    "max_friction_residual": ("Friction residual [-]", ".1e", 1.0),
    "n_steps": ("Steps", ",d", 1.0),
    "wall_time": ("Wall time [s]", "seconds", 1.0),
    "PM10_low_mg_km": ("PM10 low [mg/km]", "volume", 1.0),
    "PM10_mg_km": ("PM10 [mg/km]", "volume", 1.0),
    "PM10_high_mg_km": ("PM10 high [mg/km]", "volume", 1.0),
}


def _runs_table(summary: pd.DataFrame) -> _Table:
    """Per-run table: MU to 3 decimals, V in mm^3 (V_mm3 dropped when V is present), the
    other run scalars with readable headers and units (:data:`_RUN_COLUMNS`).

    What the secondary plateaus still hold at the end, worn off less emitted, is a column
    of its own after those two (at 4 significant figures they printed the same in 20 of the
    paper study's 24 rows, though the caption sends the reader to their difference; a report
    review); a difference within the sums' round-off (1e-9 of the volume worn off) is 0.
    Columns that say nothing are left out: the replicate of an unreplicated
    campaign, the run order where it is the test number, the status where every run is ok
    and the error where none has one (the CSV keeps them all).
    """
    frame = summary.copy()
    if {"total_emitted_mm3", "total_generated_mm3"} <= set(frame.columns):
        worn = pd.to_numeric(frame["total_generated_mm3"], errors="coerce")
        held = worn - pd.to_numeric(frame["total_emitted_mm3"], errors="coerce")
        # 0 within the sums' round-off (a run whose S removed every deposit read -1.67e-10)
        held = held.mask(held.abs() <= 1e-9 * worn.abs(), 0.0)
        at = list(frame.columns).index("total_generated_mm3") + 1
        frame.insert(at, "held_mm3", held)
    quiet = []
    if "replicate" in frame.columns and not is_replicated(frame):
        quiet.append("replicate")
    if {"order", "test"} <= set(frame.columns) and frame["order"].equals(frame["test"]):
        quiet.append("order")
    if "status" in frame.columns and frame["status"].astype(str).str.strip().eq("ok").all():
        quiet.append("status")
    if "error" in frame.columns and frame["error"].fillna("").astype(str).str.strip().eq("").all():
        quiet.append("error")
    frame = frame.drop(columns=quiet)
    headers: dict[str, str] = {}
    formats: dict[str, str] = {}
    for name, (header, spec, factor) in _RUN_COLUMNS.items():
        if name in frame.columns:
            headers[name] = header
            if spec:
                formats[name] = spec
            if factor != 1.0:
                frame[name] = pd.to_numeric(frame[name], errors="coerce") * factor
    if "V" in frame.columns:
        frame["V"] = pd.to_numeric(frame["V"], errors="coerce") * 1e9
        frame = frame.drop(columns=["V_mm3"], errors="ignore")
        headers["V"] = "V [mm³]"
        formats["V"] = "volume"
    elif "V_mm3" in frame.columns:
        headers["V_mm3"] = "V [mm³]"
        formats["V_mm3"] = "volume"
    if "MU" in frame.columns:
        headers["MU"] = "MU [-]"
        formats["MU"] = ".3f"
    columns = [headers.get(str(c), str(c)) for c in frame.columns]
    numeric = [pd.api.types.is_numeric_dtype(frame[c]) for c in frame.columns]
    specs = [formats.get(str(c), ".6g") for c in frame.columns]
    status = list(frame["status"]) if "status" in frame.columns else [None] * len(frame)
    rows = []
    for record, st in zip(frame.itertuples(index=False, name=None), status, strict=True):
        cells = [_fmt(v, spec) for v, spec in zip(record, specs, strict=True)]
        failed = st is not None and str(st).strip().lower() not in ("ok", "")
        rows.append({"cells": cells, "cls": "failed" if failed else ""})
    return _Table(columns, numeric, rows)


_ANOVA_HEADERS = {
    "term": "Term",
    "df": "df",
    "sum_sq": "Sum of squares",
    "mean_sq": "Mean square",
    "F": "F",
    "p_value": "p",
    "percent_contribution": "Contribution [%]",
    "aliases": "Aliases",
}

#: the two-level effects table's headers (:func:`brakeca.analysis.two_level_effects`)
_EFFECT_HEADERS = {
    "term": "Term",
    "effect": "Effect",
    "coefficient": "Coefficient",
    "se": "SE of coefficient",
    "t": "t",
    "p_value": "p",
    "vif": "VIF",
    "aliases": "Aliases",
}


#: responses whose ANOVA the report shows in another unit than the analysis's SI one:
#: response -> (factor from the SI value to the shown one, shown unit); V is shown in mm³ per
#: stop like the per-run table and the figures (the CSV tables keep m³)
_REPORT_UNITS = {"V": (1e9, "mm³"), "V_mm3": (1.0, "mm³")}


def _anova_in_report_units(response: str, frame: pd.DataFrame) -> tuple[pd.DataFrame, str | None]:
    """``frame`` with its sums of squares, mean squares and residual standard deviation s
    converted to the unit the report shows ``response`` in, and that unit (None: unitless)."""
    if response not in _REPORT_UNITS:
        return frame, None
    factor, unit = _REPORT_UNITS[response]
    if factor == 1.0:
        return frame, unit
    shown = frame.copy()
    for col in ("sum_sq", "mean_sq"):
        if col in shown.columns:
            shown[col] = pd.to_numeric(shown[col], errors="coerce") * factor**2
    shown.attrs = dict(frame.attrs)
    if "s" in shown.attrs and not _is_missing(shown.attrs["s"]):
        shown.attrs["s"] = float(shown.attrs["s"]) * factor
    for key in ("pure_error_ss", "lack_of_fit_ss"):  # sums of squares, as the table's
        if key in shown.attrs and not _is_missing(shown.attrs[key]):
            shown.attrs[key] = float(shown.attrs[key]) * factor**2
    return shown, unit


def _names_aliases(table: _Table) -> bool:
    """Whether ``table`` has an Aliases column with a term in it (a full factorial's has none,
    and then the report need not explain the column)."""
    if "Aliases" not in table.columns:
        return False
    at = table.columns.index("Aliases")
    return any(str(row["cells"][at]).strip() not in ("", "–", "-") for row in table.rows)


def _anova_table(frame: pd.DataFrame) -> tuple[_Table, str]:
    cols = [c for c in _ANOVA_HEADERS if c in frame.columns]
    if "aliases" in cols and not frame["aliases"].fillna("").astype(str).str.strip().any():
        cols.remove("aliases")  # a full factorial: no term has aliases
    extra = [c for c in frame.columns if c not in _ANOVA_HEADERS and c != "note"]
    rows = []
    for _, rec in frame.iterrows():
        cells = []
        for c in cols + extra:
            v = rec[c]
            if c == "p_value":
                cells.append(format_p_value(v))
            elif c == "df":
                cells.append(_fmt(v, ".0f"))
            elif c == "percent_contribution":  # 0.0031, not 0.00 beside the Pareto's bar
                small = not _is_missing(v) and 0.0 < abs(float(v)) < 0.005  # (a report review)
                cells.append(_fmt(v, ".2g" if small else ".2f"))
            elif c in ("term", "aliases"):
                cells.append(_fmt(v))
            else:
                cells.append(_fmt(v, ".4g"))
        p = rec["p_value"] if "p_value" in frame.columns else math.nan
        sig = not _is_missing(p) and float(p) < 0.05
        rows.append({"cells": cells, "cls": "sig" if sig else ""})
    columns = [_ANOVA_HEADERS[c] for c in cols] + [str(c) for c in extra]
    numeric = [c not in ("term", "aliases") for c in cols] + [
        pd.api.types.is_numeric_dtype(frame[c]) for c in extra
    ]
    notes: list[str] = []
    if "note" in frame.columns:
        for n in frame["note"]:
            if not _is_missing(n) and str(n) and str(n) not in notes:
                notes.append(str(n))
    if not notes and frame.attrs.get("note"):
        notes.append(str(frame.attrs["note"]))
    return _Table(columns, numeric, rows), "; ".join(notes)


#: The standardized residual beyond which a run is named as unusual (Minitab's "R") [-]; the
#: Box-Cox check leaves the same runs out of its second profile (brakeca.boxcox).
UNUSUAL_RESIDUAL = _UNUSUAL_RESIDUAL


def _p_text(p: float) -> str:
    """A p value in running text: two significant digits, ``< 0.0001`` below that."""
    return "< 0.0001" if p < 1e-4 else f"{p:.2g}"


def _verdicts_without(
    anova: pd.DataFrame | None,
    unusual: pd.DataFrame | None,
    alpha: float = 0.05,
    who: str | None = None,
) -> str:
    """What the ANOVA says without the unusual runs (:func:`brakeca.analysis.unusual_runs`'
    ``attrs["without"]``) against ``anova``: the terms that become significant at ``alpha``
    and those that stop being so, each with both p values, or that every term keeps its
    verdict; empty without such a refit. ``who`` names the runs left out (``"it"`` or
    ``"them"`` by default)."""
    if anova is None or unusual is None or unusual.empty:
        return ""
    them = who or ("it" if len(unusual) == 1 else "them")
    without = unusual.attrs.get("without")
    if without is None:
        why = unusual.attrs.get("without_note", "")
        return f"without {them} the model cannot be refitted ({why})" if why else ""
    before = anova.set_index("term")["p_value"]
    after = without.set_index("term")["p_value"]
    gained: list[str] = []
    lost: list[str] = []
    for term, p in before.items():
        if term == "Residual" or term not in after.index or _is_missing(p):
            continue
        q = after[term]
        if _is_missing(q) or (float(p) < alpha) == (float(q) < alpha):
            continue
        (gained if float(q) < alpha else lost).append(
            f"{term} (p {_p_text(float(p))} → {_p_text(float(q))})"
        )
    if not gained and not lost:
        return f"every term keeps its verdict at p < {alpha:g} without {them}"
    parts = []
    if gained:
        parts.append(f"{_listed(gained)} {'becomes' if len(gained) == 1 else 'become'} significant")
    if lost:
        parts.append(f"{_listed(lost)} {'stops' if len(lost) == 1 else 'stop'} being significant")
    return (
        f"without {them}, at p < {alpha:g}, "
        + " and ".join(parts)
        + "; the other terms keep their verdicts"
    )


def _residual_ss(table: pd.DataFrame) -> float:
    """The residual sum of squares of an :func:`brakeca.analysis.anova` table [response
    unit^2]; NaN without its row."""
    rows = table.loc[table["term"] == "Residual", "sum_sq"]
    return float(rows.iloc[0]) if len(rows) else math.nan


def _listed(items: Sequence[str], sep: str = ", ") -> str:
    """``"a"``, ``"a and b"``, ``"a, b and c"`` (``sep`` between all but the last two: ``"; "``
    where the items hold commas)."""
    return items[0] if len(items) == 1 else sep.join(items[:-1]) + " and " + items[-1]


def _outlier_clause(
    anova: pd.DataFrame,
    unusual: pd.DataFrame | None,
    residual_tables: Mapping[str, pd.DataFrame] | None,
    response: Any,
) -> str:
    """The "In short" clause on the runs the Bonferroni outlier test calls outliers of the
    model (:func:`brakeca.analysis.unusual_runs`), with the ANOVA's verdicts that change
    without the unusual runs; empty where there is none."""
    outliers = _outliers(unusual)
    if unusual is None or outliers.empty:
        return ""
    alpha = float(unusual.attrs.get("alpha", 0.05))
    residuals = (residual_tables or {}).get(response)
    replicated = residuals is not None and is_replicated(residuals)
    named = _runs_listed([run_named(rec, replicated) for _, rec in outliers.iterrows()], replicated)
    verb = "is an outlier" if len(outliers) == 1 else "are outliers"
    setting = _within_settings(outliers, residuals, anova)
    straddle = _straddling(outliers, residuals) if not setting else ""
    if setting:
        reading = (
            f": the runs of {setting}, which scatter more than the other settings' runs (the "
            "model fits each setting's mean)"
        )
    elif straddle:
        reading = (
            f": the runs of {straddle}, on either side of the model's value there, which "
            "scatter more than the other settings' runs"
        )
    elif setting is not None:
        reading = ": far from the other runs at their setting (the model fits each setting's mean)"
    else:
        reading = ""
    clause = (
        f"; {named} {verb} of the model (Bonferroni p "
        + ", ".join(_p_text(float(v)) for v in outliers["outlier_p"])
        + ")"
        + reading
    )
    who = None  # the refit leaves out every unusual run: named where they are more
    if len(unusual) > len(outliers):
        every = _runs_listed(
            [run_named(rec, replicated) for _, rec in unusual.iterrows()], replicated
        )
        who = f"the unusual runs ({every})"
    verdicts = _verdicts_without(anova, unusual, alpha, who)
    return clause + (f", and {verdicts}" if verdicts else "")


def _within_settings(
    outliers: pd.DataFrame, residuals: pd.DataFrame | None, anova: pd.DataFrame | None
) -> str | None:
    """Where the ANOVA's model leaves no lack of fit (its residual is pure error: it fits
    every setting's mean), what the outlier test finds is runs far from the other runs at
    their setting, not a misfit of the model (a DoE review: both replicates of a test had
    been called outliers the model "does not describe"): ``"test 4"`` where the
    ``outliers`` are every run of that one test, ``""`` otherwise; None where the model
    leaves a lack of fit (or there is no pure error)."""
    if anova is None or outliers.empty:
        return None
    pure, df = anova.attrs.get("pure_error_df", math.nan), anova.attrs.get("df_resid", math.nan)
    if _is_missing(pure) or _is_missing(df) or float(pure) < 0.5:
        return None
    if abs(float(pure) - float(df)) > 0.5:
        return None
    test = _every_run_of_one_test(outliers, residuals)
    return "" if test is None else f"test {test}"


def _every_run_of_one_test(outliers: pd.DataFrame, residuals: pd.DataFrame | None) -> int | None:
    """The test whose every run (two or more) the ``outliers`` are, of the runs in
    ``residuals``; None where they are not that."""
    if residuals is None or "test" not in outliers.columns or "test" not in residuals.columns:
        return None
    tests = set(pd.to_numeric(outliers["test"], errors="coerce"))
    if len(tests) != 1 or len(outliers) < 2:
        return None
    (test,) = tests
    runs = int((pd.to_numeric(residuals["test"], errors="coerce") == test).sum())
    return int(test) if runs == len(outliers) else None


def _straddling(outliers: pd.DataFrame, residuals: pd.DataFrame | None) -> str:
    """``"test 4"`` where the ``outliers`` are every run (two or more) of that one test and
    lie on either side of the model's value there, their mean residual within half their
    largest: they depart from each other, not from the model (a review of a replicated
    study: both replicates of a test, 8.3 and 6.2 mm³ about a fit of 7.1, had been called
    outliers the model "does not describe"), whatever lack of fit the model leaves; ``""``
    otherwise."""
    test = _every_run_of_one_test(outliers, residuals)
    if test is None or "residual" not in outliers.columns:
        return ""
    r = pd.to_numeric(outliers["residual"], errors="coerce").to_numpy(dtype=float)
    if not (np.isfinite(r).all() and (r > 0).any() and (r < 0).any()):
        return ""
    return f"test {test}" if abs(float(r.mean())) <= 0.5 * float(np.abs(r).max()) else ""


def _outliers(unusual: pd.DataFrame | None) -> pd.DataFrame:
    """The rows of an :func:`brakeca.analysis.unusual_runs` table that its Bonferroni outlier
    test calls outliers (``outlier_p`` below its ``alpha``); empty where there is none."""
    if unusual is None or unusual.empty or "outlier_p" not in unusual.columns:
        return pd.DataFrame()
    alpha = float(unusual.attrs.get("alpha", 0.05))
    return unusual.loc[pd.to_numeric(unusual["outlier_p"], errors="coerce") < alpha]


#: The most runs a sentence of the report names one by one; the rest are counted [-].
_MOST_RUNS_LISTED = 8


def _runs_listed(names: list[str], replicated: bool) -> str:
    """Runs' names in a sentence, ``"test 14, test 75 and test 29"``, the first
    :data:`_MOST_RUNS_LISTED` and a count of the rest (a review of large designs: "test 14
    and test 75 and test 29 and ..." seventeen times); "; " between a replicated campaign's
    names, which hold commas."""
    shown, rest = names[:_MOST_RUNS_LISTED], len(names) - _MOST_RUNS_LISTED
    sep = "; " if replicated else ", "
    return sep.join(shown) + f" and {rest} more" if rest > 0 else _listed(shown, sep)


def _negative_fits(response: str, frame: pd.DataFrame | None, log_section: bool = True) -> str:
    """For V, the runs its ANOVA model fits a negative volume, with the fitted and observed
    values in mm³ (a review: "In short" had named them, V's section not), and, with
    ``log_section``, that log10 V's section reads the effects as ratios; empty otherwise."""
    if response != "V" or frame is None or not {"fitted", "observed"} <= set(frame.columns):
        return ""
    negative = frame.loc[pd.to_numeric(frame["fitted"], errors="coerce") < 0]
    if negative.empty:
        return ""
    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    replicated = is_replicated(frame)
    shown = negative.head(_MOST_RUNS_LISTED)
    runs = "; ".join(
        f"{run_named(rec, replicated)}: fitted {_fmt(float(rec['fitted']) * factor, '.3g')}, "
        f"observed {_fmt(float(rec['observed']) * factor, '.3g')}"
        for _, rec in shown.iterrows()
    ) + (  # the first ones; the table has them all (a review of large designs)
        f"; and {len(negative) - len(shown)} more, in tables/residuals_{response}.csv"
        if len(negative) > len(shown)
        else ""
    )
    return (
        f" The ANOVA model fits a negative volume to {len(negative)} "
        f"run{'' if len(negative) == 1 else 's'} ({runs}{' ' + unit if unit else ''}): an "
        "additive model cannot follow effects that multiply V"
        + ("; log10 V's section reads them as ratios." if log_section else ".")
    )


def _unusual_text(
    response: str,
    frame: pd.DataFrame,
    unusual: pd.DataFrame | None = None,
    anova: pd.DataFrame | None = None,
) -> str:
    """The runs whose standardized residual exceeds :data:`UNUSUAL_RESIDUAL` in size
    (:func:`brakeca.analysis.residuals`), as Minitab lists its "unusual observations", with
    their observed and fitted values in the report's unit, their deleted residuals and
    Cook's distances; from :func:`brakeca.analysis.unusual_runs`' table ``unusual`` (when
    given) the outliers of the model by the Bonferroni test and what the ANOVA ``anova``
    says without those runs. Where no run is unusual, that none is, with the largest; empty
    without standardized residuals."""
    if "std_residual" not in frame.columns or frame.empty:
        return ""
    z = pd.to_numeric(frame["std_residual"], errors="coerce")
    large = frame.loc[z.abs() > UNUSUAL_RESIDUAL]
    replicated = is_replicated(frame)
    if large.empty:
        if z.isna().all():
            return ""
        top = frame.loc[z.abs().idxmax()]  # (a review: the section had been silent)
        return (
            f"No run's standardized residual is beyond ±{UNUSUAL_RESIDUAL:g} (the largest: "
            f"{float(top['std_residual']):+.2f}, {run_named(top, replicated)})."
        )
    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    items = []
    for _, rec in large.iterrows():
        who = run_named(rec, replicated)
        extra = ""
        if not _is_missing(rec.get("deleted_residual", math.nan)):
            deleted = float(rec["deleted_residual"])
            extra += ", deleted residual " + (
                f"{deleted:+.1f}" if abs(deleted) < 1e3 else f"{deleted:+.3g}"
            )
        if not _is_missing(rec.get("cooks_distance", math.nan)):
            extra += f", Cook's distance {float(rec['cooks_distance']):.2g}"
        items.append(
            f"{who} ({response} {_fmt(float(rec['observed']) * factor, '.4g')}"
            f"{' ' + unit if unit else ''}, fitted {_fmt(float(rec['fitted']) * factor, '.4g')}, "
            f"standardized residual {float(rec['std_residual']):+.2f}{extra})"
        )
    n = len(frame)
    text = (
        f"Unusual runs (standardized residual beyond ±{UNUSUAL_RESIDUAL:g}, Minitab's R): "
        + "; ".join(items)
        + f". By chance about 1 run in 20 lies beyond ±{UNUSUAL_RESIDUAL:g} ({n} runs "
        "here); such a run matters where it fails the outlier test or has a large Cook's "
        "distance (about 1 or more)"
        # (the Box-Cox check is of MU, V and MU_SD, not of a response already on a log scale)
        + (
            "."
            if response == "log10_V_mm3"
            else ", and the Box–Cox check is read again without it."
        )
    )
    if unusual is not None and not unusual.empty and "outlier_p" in unusual.columns:
        p = pd.to_numeric(unusual["outlier_p"], errors="coerce")
        outliers = _outliers(unusual)
        if not outliers.empty:
            names = [run_named(rec, replicated) for _, rec in outliers.iterrows()]
            named = " and ".join(names)
            df = frame.attrs.get("df_resid", unusual.attrs.get("df_resid", math.nan))
            largest = float(pd.to_numeric(outliers["std_residual"], errors="coerce").abs().max())
            ceiling = (  # where the standardized residual looks mild, near its ceiling
                f" (with {_fmt(float(df), '.0f')} residual degrees of freedom a standardized "
                f"residual cannot exceed √{_fmt(float(df), '.0f')} = {math.sqrt(float(df)):.2f},"
                " which is why it can look mild)"
                if not _is_missing(df)
                and float(df) > 0
                and 0.75 * math.sqrt(float(df)) < largest < 3.0
                else ""
            )
            verb = "is an outlier" if len(names) == 1 else "are outliers"
            share = ""  # how much of the F tests' error is theirs: the refit's residual
            without = unusual.attrs.get("without")
            if anova is not None and without is not None:
                ssr = _residual_ss(anova)
                fall = 1.0 - _residual_ss(without) / ssr if ssr > 0 else math.nan
                who = (
                    ("it" if len(names) == 1 else "them")
                    if len(unusual) == len(outliers)
                    else "the unusual runs"
                )
                if math.isfinite(fall):
                    share = (
                        f": without {who} the residual sum of squares, the error every F "
                        f"test is against, falls by {100 * fall:.0f} %"
                    )
            setting = _within_settings(outliers, frame, anova)
            straddle = _straddling(outliers, frame) if not setting else ""
            them = "it" if len(names) == 1 else "them"
            if straddle:
                reading = (
                    f"; they are every run of {straddle}, on either side of the model's value "
                    "there, so it is not the model they depart from but each other: the runs "
                    "at this setting scatter more than those at the others, which the one "
                    "error of the F tests does not allow for"
                )
            elif setting:
                reading = (
                    f"; they are every run of {setting}, and the model fits each setting's "
                    "mean (it leaves no lack of fit), so it is not the model they depart from "
                    "but each other: the runs at this setting scatter more than those at the "
                    "others, which the one error of the F tests does not allow for"
                )
            elif setting is not None:
                reading = (
                    "; the model fits each setting's mean (it leaves no lack of fit), so what "
                    f"sets {them} apart is {'its' if len(names) == 1 else 'their'} distance "
                    "from the other runs at the same setting, not a misfit of the model"
                )
            else:
                reading = f", so the model does not describe {them}"
            # no setting run twice (no pure error: no replicate, no centre points run
            # more than once): a seed's pad cannot be told from the model's misfit (an
            # engineer's read: the paper study's test 23 was flagged, never explained)
            pure = float((anova.attrs if anova is not None else {}).get("pure_error_df") or 0)
            settings = "its setting" if len(names) == 1 else "their settings"
            once = (
                ""
                if setting or straddle or pure > 0 or replicated
                else " With no setting run twice, a seed's unusual pad cannot be told from a "
                f"behaviour the model misses: {settings} run again with other seeds (the "
                "design's replicates) would tell."
            )
            text += (
                f" {named[:1].upper()}{named[1:]} {verb} of this model: the deleted "
                "residual, the run's residual against the model fitted without it in that "
                "fit's standard errors, has p "
                + ", ".join(_p_text(float(v)) for v in outliers["outlier_p"])
                + f" after Bonferroni's correction over the {n} runs{ceiling}"
                + reading
                + share
                + "."
                + once
            )
        elif p.notna().any():
            text += (
                (" It is not" if len(unusual) == 1 else " None is")
                + f" an outlier of this model: Bonferroni's outlier test over the {n} runs "
                + f"gives p {_p_text(float(p.min()))}"
                + ("." if len(unusual) == 1 else " at the smallest.")
            )
        other = unusual.attrs.get("largest_other_cooks", math.nan)
        if not _is_missing(other):
            text += f" The largest Cook's distance of the other runs: {float(other):.2g}."
        verdicts = _verdicts_without(anova, unusual)
        if verdicts:
            text += f" {verdicts[:1].upper()}{verdicts[1:]}."
    files = f"tables/residuals_{response}.csv" + (
        f" and tables/unusual_{response}.csv" if unusual is not None and not unusual.empty else ""
    )
    return text + f" The runs' diagnostics: {files}."


def _trends_table(
    response: str, frame: pd.DataFrame, explained_under: str | None = None
) -> tuple[_Table, str]:
    """The trends of the factors of three or more levels
    (:func:`brakeca.analysis.factor_trends`, sums of squares in the report's unit of
    ``response``) and their caption; shorter where ``explained_under`` names the response
    whose caption explained the table."""
    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    rows = []
    for _, rec in frame.iterrows():
        cells = [
            _fmt(rec["factor"]),
            _fmt(rec["part"]),
            _fmt(rec["scale"]),
            _fmt(float(rec["sum_sq"]) * factor**2, ".4g"),
            _fmt(rec["F"], ".4g"),
            format_p_value(rec["p_value"]),
            _fmt(rec["percent_of_factor"], ".1f"),
        ]
        p = rec["p_value"]
        sig = not _is_missing(p) and float(p) < 0.05
        rows.append({"cells": cells, "cls": "sig" if sig else ""})
    square = f" [({unit})²]" if unit else ""
    columns = [
        "Factor",
        "Part",
        "Polynomial in",
        f"SS{square}",
        "F",
        "p",
        "Share of the factor's SS [%]",
    ]
    names = " and ".join(dict.fromkeys(str(f) for f in frame["factor"]))
    several = frame["factor"].nunique() > 1
    if explained_under:
        caption = (
            f"Trend of {response} over the levels of {names}: "
            + ("each such" if several else "its")
            + " main effect split into orthogonal polynomials in the levels' values, each part "
            f"tested against the ANOVA's residual, as explained under {explained_under} above."
            + (f" Sums of squares in ({unit})²." if unit else "")
        )
    else:
        caption = (
            f"Trend of {response} over the levels of {names}. The ANOVA takes each factor as "
            "categorical (a factor of k levels has k − 1 degrees of freedom, whatever the "
            "levels' values), so its F says only that the levels differ. Here "
            + ("each such" if several else "that")
            + " main effect is split into orthogonal polynomials in the levels' values (or their "
            "log10, where the levels are evenly spaced on the log or the factor is coded 'log'), "
            "each part of 1 degree of freedom tested against the ANOVA's residual; in a "
            "balanced design the parts' shares add up to 100 %. A significant quadratic part means "
            "the response does not move evenly across the levels: its steps from one level to "
            "the next differ (with three levels that is all it can say; the share of the "
            "factor's sum of squares says how much)."
            + (f" Sums of squares in ({unit})²." if unit else "")
        )
    note = frame.attrs.get("note")
    if note:
        caption += f" Note: {note}."
    numeric = [False, False, False, True, True, True, True]
    return _Table(columns, numeric, rows), caption


def _heading(response: str) -> str:
    """A response as a section heading names it: ``log10 V (column log10_V_mm3, V in mm³)``
    for the column ``log10_V_mm3`` (a review read the column's name as a heading), others
    as they are."""
    if response == "log10_V_mm3":
        return "log10 V (column log10_V_mm3, V in mm³)"
    return response


def _t_text(t: float) -> str:
    """A T value in a table: two decimals, as Minitab prints it, and three significant digits
    from 10,000 in size (a residual at round-off makes T huge)."""
    if math.isinf(t):  # an exact fit: the difference is certain
        return "∞" if t > 0 else "−∞"
    return f"{t:.2f}" if abs(t) < 1e4 else f"{t:.3g}"


def _coded(rows: pd.DataFrame) -> bool:
    """Whether a factor's levels in a grouping table (its ``level`` column) are coded
    labels, each ``-``, ``0`` or ``+``, with a ``-`` or ``+`` among them."""
    levels = {str(v) for v in rows["level"]}
    return levels <= {"-", "0", "+"} and bool(levels & {"-", "+"})


def _level_named(factor: str, label: Any, coded: bool = True) -> str:
    """A factor's level in a sentence: ``WP+``, ``WP0``, ``WP-`` for the coded labels of a
    factor whose levels are all ``-``, ``0`` or ``+`` (``coded``), as the figures' legends
    write them (the grouping had read "WP + ..., WP (-)"; a report review), ``A = 10`` for
    another (a level 0 of a factor of values is not a coded label: "S0 in group A, S = 0.5";
    a review of large designs)."""
    text = str(label)
    return f"{factor}{text}" if coded and text in ("-", "0", "+") else f"{factor} = {text}"


def _comparisons_table(
    response: str, frame: pd.DataFrame, explained_under: str | None = None
) -> tuple[_Table, str]:
    """Tukey's pairwise comparisons (:func:`brakeca.analysis.level_comparisons`, in the
    report's unit of ``response``) and their caption; shorter where ``explained_under``
    names the response whose caption explained the table."""
    from brakeca.analysis import tukey_grouping

    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    confidence = float(frame.attrs.get("confidence", 0.95))

    def level(label: Any) -> str:  # a negative one bracketed, as Minitab writes it
        text = str(label)
        return f"({text})" if text.startswith("-") else text

    rows = []
    for _, rec in frame.iterrows():
        low, high = float(rec["ci_low"]) * factor, float(rec["ci_high"]) * factor
        t_value = math.nan  # Minitab's T: the difference over its SE, q / sqrt(2) signed
        if not _is_missing(rec["q"]):
            t_value = math.copysign(float(rec["q"]) / math.sqrt(2.0), float(rec["difference"]))
        cells = [
            _fmt(rec["factor"]),
            f"{level(rec['level_b'])} − {level(rec['level_a'])}",
            _fmt(float(rec["difference"]) * factor, ".4g"),
            _fmt(float(rec["se"]) * factor, ".4g"),
            "–" if _is_missing(low) else f"{_fmt(low, '.4g')} to {_fmt(high, '.4g')}",
            "–" if _is_missing(t_value) else _t_text(t_value),
            format_p_value(rec["p_adjusted"]),
        ]
        rows.append({"cells": cells, "cls": "sig" if bool(rec["significant"]) else ""})
    in_unit = f" [{unit}]" if unit else ""
    columns = [
        "Factor",
        "Levels (later − earlier)",
        f"Difference of their means{in_unit}",
        f"SE of difference{in_unit}",
        f"Simultaneous {100 * confidence:g} % interval{in_unit}",
        "T (q / √2)",
        "Adjusted p",
    ]
    names = " and ".join(dict.fromkeys(str(f) for f in frame["factor"]))
    if explained_under:
        caption = (
            f"Which levels of {names} differ in {response}: Tukey's pairwise comparisons of "
            f"the levels' least-squares means, as explained under {explained_under} above; "
            f"p < {1 - confidence:.2g} in bold. The table is tables/comparisons_{response}.csv."
        )
    else:
        caption = (
            f"Which levels of {names} differ in {response}: Tukey's pairwise comparisons of the "
            "levels' least-squares means in the ANOVA's model (in a balanced design, the levels' "
            "mean responses), each difference the later "
            "level's mean less the earlier's, with "
            f"simultaneous {100 * confidence:g} % intervals and p values adjusted for all the "
            "pairs of the factor (Minitab's comparisons of a general linear model); "
            f"p < {1 - confidence:.2g} in bold. The table is tables/comparisons_{response}.csv."
        )
    grouping = tukey_grouping(frame)
    if not grouping.empty:
        caption += (
            f" Grouping by Tukey's method at {100 * confidence:g} % (Minitab's grouping "
            "letters, the levels from the largest mean; the means of levels that share no "
            "letter are significantly different): "
            + "; ".join(
                f"{name}: "
                + ", ".join(
                    f"{_level_named(name, r.level, _coded(rows_))} in group"
                    f"{'s' if len(r.grouping) > 1 else ''} " + " and ".join(r.grouping)
                    for r in rows_.itertuples()
                )
                for name, rows_ in grouping.groupby("factor", sort=False)
            )
            + f" (tables/grouping_{response}.csv)."
        )
    note = frame.attrs.get("note")
    if note:
        caption += f" Note: {note}."
    numeric = [False, False, True, True, False, True, True]
    return _Table(columns, numeric, rows), caption


def _coefficients_table(
    response: str, frame: pd.DataFrame, explained_under: str | None = None
) -> tuple[_Table, str, str, str]:
    """The coefficients at every level (:func:`brakeca.analysis.level_coefficients`, in the
    report's unit of ``response``), their caption (shorter where ``explained_under`` names
    the response whose caption explained the table), the regression equation in that unit
    and the unit's words for its heading (``" (V in mm³)"``; empty without a unit)."""
    from brakeca.analysis import _equation

    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    rows = []
    for _, rec in frame.iterrows():
        level = str(rec["level"]) + (" †" if bool(rec["derived"]) else "")
        cells = [
            _fmt(rec["term"]),
            level if str(rec["level"]) else "",
            _fmt(float(rec["coefficient"]) * factor, ".4g"),
            _fmt(float(rec["se"]) * factor, ".4g"),
            _fmt(rec["t"], ".3g"),
            format_p_value(rec["p_value"]),
            _fmt(rec["vif"], ".3g"),
        ]
        rows.append({"cells": cells, "cls": "sig" if bool(rec["significant"]) else ""})
    in_unit = f" [{unit}]" if unit else ""
    columns = ["Term", "Level", f"Coef{in_unit}", f"SE Coef{in_unit}", "T", "p", "VIF"]
    alpha = float(frame.attrs.get("alpha", 0.05))
    legend = frame.attrs.get("levels") or {}
    units = frame.attrs.get("units") or {}
    if explained_under:
        caption = (
            f"The ANOVA model of {response} as coefficients, coded as explained under "
            f"{explained_under} above (a level's coefficient is its least-squares mean less "
            "the constant, and its p tests it against 0, not against the other levels). "
            "Standard errors, T and p against the ANOVA's residual "
            f"({_fmt(frame.attrs.get('df_resid'), '.0f')} degrees of freedom); p < {alpha:g} "
            f"in bold; † rows Minitab omits. The table is tables/coefficients_{response}.csv."
        )
        legend = {}  # (given there)
    else:
        caption = (
            f"The ANOVA model of {response} as coefficients, as Minitab gives them for a general "
            "factorial: each factor coded by effects (sum-to-zero) coding, so a level's "
            "coefficient is its least-squares mean less the constant (in a balanced design, the "
            "level's mean less the grand mean) and a term's coefficients add up to zero over "
            "each of its factors' levels; for a two-level factor, minus and plus half its effect. "
            "Standard errors, T and p against the ANOVA's "
            f"residual ({_fmt(frame.attrs.get('df_resid'), '.0f')} degrees of freedom); "
            f"p < {alpha:g} in bold. A level's p tests its coefficient against 0 (its "
            "least-squares mean against the constant), not against the other levels: Tukey's "
            "comparisons compare the levels. † Rows Minitab omits (a factor's last level, "
            "and an interaction's cells at the last level of any of its factors: the other rows "
            "fix them) are shown with their standard errors, as in JMP's expanded estimates; they "
            f"have no VIF. The table is tables/coefficients_{response}.csv."
        )
    if legend:
        caption += (
            " The levels: "
            + "; ".join(
                f"{name}: "
                + ", ".join(f"{label} = {float(value):g}" for label, value in labels.items())
                + (
                    f" [{display_unit(units[name])}]"
                    if units.get(name) and units[name] not in ("-", "")
                    else ""
                )
                for name, labels in legend.items()
            )
            + "."
        )
    note = frame.attrs.get("note")
    if note:
        caption += f" Note: {note}."
    numeric = [False, False, True, True, True, True, True]
    words = f" ({response} in {unit})" if unit else ""
    return _Table(columns, numeric, rows), caption, _equation(frame, response, scale=factor), words


def _model_terms_of(effects: pd.DataFrame) -> list[str]:
    """The terms an effects table fits, in the model's order (its attrs' ``model_terms``,
    those kept there); else its rows' (not the centre points'), fewest factors first."""
    from brakeca.analysis import CENTER_TERM

    shown = {str(t) for t in effects["term"]}
    given = effects.attrs.get("model_terms")
    if given:
        return [str(t) for t in given if str(t) in shown]
    rows = effects[effects["term"] != CENTER_TERM].sort_values("order", kind="stable")
    return [str(t) for t in rows["term"]]


def _effects_table(response: str, frame: pd.DataFrame) -> tuple[_Table, str]:
    """The two-level effects table (in the report's unit of ``response``) and its caption."""
    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    cols = [c for c in _EFFECT_HEADERS if c in frame.columns]
    rows = []
    for _, rec in frame.iterrows():
        cells = []
        for c in cols:
            v = rec[c]
            if c == "p_value":
                cells.append(format_p_value(v))
            elif c in ("term", "aliases"):
                cells.append(_fmt(v))
            elif c in ("effect", "coefficient"):
                cells.append(_fmt(float(v) * factor, ".4g"))
            elif c == "se":
                # the table's se is the effect's (the Ct Pt row's: twice its coefficient's);
                # shown as the coefficient's, as Minitab's SE Coef, so t = coefficient / SE on
                # every row, the Ct Pt row's too (which has no effect)
                cells.append(_fmt(0.5 * float(v) * factor, ".4g"))
            else:
                cells.append(_fmt(v, ".3g"))
        rows.append({"cells": cells, "cls": "sig" if bool(rec.get("significant")) else ""})
    headers = [
        _EFFECT_HEADERS[c] + (f" [{unit}]" if unit and c in ("effect", "coefficient", "se") else "")
        for c in cols
    ]
    attrs = frame.attrs
    alpha = float(attrs.get("alpha", 0.05))
    if attrs.get("method") == "Lenth":
        how = (
            f"unreplicated, so each effect's standard error is Lenth's pseudo standard error "
            f"(PSE = {_fmt(float(attrs.get('pse', math.nan)) * factor, '.4g')}"
            f"{' ' + unit if unit else ''}, {_fmt(attrs.get('df'), '.3g')} degrees of freedom), "
            "which assumes that few effects are active"
        )
    elif attrs.get("method") == "pure error":
        n_c = int(attrs.get("center_points", 0) or 0)
        if not n_c:
            of = "replicates"
        elif float(attrs.get("df", 0.0)) > n_c - 1 + 0.5:
            of = "replicates and centre points"
        else:
            of = "centre points"
        how = (
            f"standard errors from the pure error of the {of} "
            f"({_fmt(attrs.get('df'), '.0f')} degrees of freedom)"
        )
        if of == "centre points":  # the seeds' scatter at one setting (a screening review)
            how += (
                ", the seeds' scatter at the centre alone, which may be smaller than at the "
                "corners: where it is much smaller than the effects, every effect tests "
                "significant, and the sizes of the effects say more than their p-values"
            )
    else:
        how = (
            f"standard errors from the residual mean square of the fitted effects "
            f"({_fmt(attrs.get('df'), '.0f')} degrees of freedom), as the ANOVA's"
        )
    caption = (
        f"Effects of {response} (every factor has two levels): twice the coefficient of each "
        "term coded -1/+1 (for an orthogonal design, the mean at the second level less the "
        "mean at the first), "
        + (
            "for the terms of the ANOVA's model: " + ", ".join(_model_terms_of(frame))
            if attrs.get("terms_given")
            else "for every effect the design can estimate (one term per alias chain)"
        )
        + f"; {how}. Significant effects (p < {alpha:g}) in bold."
    )
    if not attrs.get("terms_given") and "order" in frame.columns and (frame["order"] >= 3).any():
        caption += (
            " It keeps interactions of three or more factors, which the ANOVA above leaves in "
            "its residual, so the two tables' errors, and their p values, differ; the design's "
            "model_order (brakeca analyze --order) fits the same terms in both."
        )
    curvature = attrs.get("curvature") or {}
    if attrs.get("center_points") and not _is_missing(curvature.get("p_value", math.nan)):
        caption += (
            f" The last row, Ct Pt, is the centre points' term: its coefficient is "
            f"{_centre_points_text(int(attrs['center_points']))} less the model's value at "
            f"the centre (SE {_fmt(float(curvature['se']) * factor, '.4g')}"
            f"{' ' + unit if unit else ''}); its Effect cell is blank (an effect belongs to a "
            "two-level term)"
            + (
                f", and is confounded with the main effect of {curvature['aliases']}: not a "
                "test of curvature."
                if curvature.get("aliases")
                else "."
            )
        )
    if attrs.get("note"):
        caption += f" Note: {attrs['note']}."
    return _Table(headers, [c not in ("term", "aliases") for c in cols], rows), caption


_SURFACE_INTRO = (
    "The response as a smooth function of the factors: a quadratic in the coded factors (-1 "
    "at a factor's low and +1 at its high cube level; on log10 of the level for a factor "
    "coded 'log'), fitted by least squares, as Minitab's Analyze Response Surface Design "
    "fits it. Coefficients in coded units, with their standard errors, t, p and variance "
    "inflation factors (VIF 1: a column orthogonal to the others). The ANOVA uses adjusted "
    "(type III) sums of squares: what the error sum of squares rises by when the term, or "
    "the whole group, is dropped from the model. Terms with p < 0.05 in bold."
)

#: headers of the response-surface coefficient table
_SURFACE_COEF_HEADERS = {
    "term": "Term",
    "coef": "Coef",
    "se": "SE coef",
    "t": "t",
    "p_value": "p",
    "vif": "VIF",
}


_BOX_COX_INFO = (
    "Which power y^λ of each response the model fits best (Box and Cox 1964): the λ of "
    "greatest likelihood in [−2, 2], searched as Minitab does, its 95 % likelihood-ratio "
    "interval and the nearest multiple of 0.5. λ = 1 is the response as it is, λ = 0 its log "
    "(the report's log10_V_mm3 for V). Only a reading of the data: it transforms nothing, "
    "and each response is analysed on the scale it has in this report (V both as it is and "
    "as log10_V_mm3, the λ = 0 reading)."
)
#: said where the figure is drawn (a λ is defined for some response)
_BOX_COX_FIGURE = " The figure 'Box-Cox plots' shows each profile."


def _level_means_info(means: Mapping[str, pd.DataFrame], surface: bool) -> str:
    """The note above the level-means table: what a mean is over, for this design."""
    text = "The mean of each response over the runs at each level of each factor"
    if not surface:
        text += " (the main-effects plots' points)"
    text += ", with the number of runs averaged"
    n_c = max((int(t.attrs.get("center_n", 0) or 0) for t in means.values()), default=0)
    if n_c:
        text += f"; the {n_c} centre point runs are in no level's mean"
    if surface:
        text += (
            "; a composite design's middle level holds its centre points and the axial "
            "runs at it, and its levels are not balanced against the other factors, so a "
            "level's mean also carries their effects (the profiles in 'Main effects' give "
            "each factor's effect from the fitted surface)"
        )
    else:
        text += (
            ". In an unbalanced design (failed runs) a level's mean also carries the other "
            "factors' effects"
        )
    return text + ". V in mm³ per stop."


def _level_means_table(means: Mapping[str, pd.DataFrame]) -> _Table:
    """One row per factor level: its label and value, each response's mean at it (in the
    report's unit: mm³ for V) and the runs averaged, from :func:`brakeca.analysis.main_effects`
    tables by response (which share their factors, levels and counts)."""
    responses = list(means)
    first = means[responses[0]]
    columns = ["Factor", "Level"]
    for response in responses:
        _, unit = _REPORT_UNITS.get(response, (1.0, None))
        columns.append(f"{response}" + (f" [{unit}]" if unit else ""))
    columns.append("Runs")
    rows = []
    for i in range(len(first)):
        rec = first.iloc[i]
        label = str(rec["label"]) if not _is_missing(rec.get("label")) else ""
        value = _fmt(rec["level"], ".4g")
        level = value if not label or label == value else f"{label} = {value}"
        cells = [str(rec["factor"]), level]
        for response in responses:
            factor, _ = _REPORT_UNITS.get(response, (1.0, None))
            mean = means[response].iloc[i]["mean"]
            cells.append(_fmt(float(mean) * factor, "sig4") if not _is_missing(mean) else "–")
        cells.append(_fmt(rec["n"]))
        rows.append({"cells": cells, "cls": ""})
    return _Table(columns, [False, False] + [True] * (len(responses) + 1), rows)


def _edge(bc: Any) -> int:
    """:attr:`brakeca.boxcox.BoxCox.edge` of ``bc`` (0 for an object without it)."""
    return int(getattr(bc, "edge", 0))


def _hat(bc: Any) -> str:
    """:meth:`brakeca.boxcox.BoxCox.hat_text` of ``bc`` (λ̂ to 2 decimals without it)."""
    return bc.hat_text() if hasattr(bc, "hat_text") else f"{bc.lambda_hat:.2f}"


def _box_cox_table(results: Mapping[str, Any]) -> _Table:
    """The Box-Cox results (:class:`brakeca.boxcox.BoxCox`), one row per response."""
    from brakeca.boxcox import interval_text

    rows = []
    for response, r in results.items():
        if r.defined:
            reading = r.reading + (f" ({r.note})" if r.note else "")
            if r.without_unusual:
                reading += ". " + r.without_unusual[0].upper() + r.without_unusual[1:]
            cells = [
                _hat(r),  # on the search range's edge, the bound it is
                interval_text(r.ci_low, r.ci_high),
                interval_text(r.ci_low_df, r.ci_high_df),
                _fmt(r.rounded, "g"),
                reading,
            ]
        else:
            cells = ["–", "–", "–", "–", f"not defined: {r.note}"]
        rows.append({"cells": [str(response), r.model, *cells], "cls": ""})
    pct = next((f"{100 * r.confidence:g} %" for r in results.values()), "95 %")
    columns = [
        "Response",
        "Model",
        "λ̂",
        f"{pct} interval",
        f"{pct} interval by the residual df (Montgomery)",
        "Rounded λ",
        "Reading",
    ]
    return _Table(columns, [False, False, True, False, False, True, False], rows)


def _surface_item(response: str, fit: Any) -> dict[str, Any]:
    """The report's tables and sentences of one :class:`brakeca.rsm.SurfaceFit`, in the
    report's unit of ``response`` (mm³ for V)."""
    factor, unit = _REPORT_UNITS.get(response, (1.0, None))
    u = f" [{unit}]" if unit else ""
    coef_rows = []
    for _, rec in fit.coefficients.iterrows():
        p = rec["p_value"]
        coef_rows.append(
            {
                "cells": [
                    str(rec["term"]),
                    _fmt(float(rec["coef"]) * factor, ".5g"),
                    _fmt(float(rec["se"]) * factor, ".3g"),
                    _fmt(rec["t"], ".3g"),
                    format_p_value(p),
                    _fmt(rec["vif"], ".3g"),
                ],
                "cls": "sig" if not _is_missing(p) and float(p) < 0.05 else "",
            }
        )
    headers = [
        _SURFACE_COEF_HEADERS[c] + (u if c in ("coef", "se") else "") for c in _SURFACE_COEF_HEADERS
    ]
    coefficients = _Table(headers, [False, True, True, True, True, True], coef_rows)
    anova_rows = []
    for _, rec in fit.anova.iterrows():
        p = rec["p_value"]
        anova_rows.append(
            {
                "cells": [
                    "\u2003" * int(rec["depth"]) + str(rec["source"]),
                    _fmt(rec["df"], ".0f"),
                    _fmt(float(rec["adj_ss"]) * factor**2, ".4g"),
                    _fmt(float(rec["adj_ms"]) * factor**2, ".4g"),
                    _fmt(rec["F"], ".3g"),
                    format_p_value(p),
                ],
                "cls": "sig" if not _is_missing(p) and float(p) < 0.05 else "",
            }
        )
    sq = f" [({unit})²]" if unit else ""
    anova = _Table(
        ["Source", "DF", f"Adj SS{sq}", f"Adj MS{sq}", "F", "p"],
        [False, True, True, True, True, True],
        anova_rows,
    )
    stats = dict(fit.statistics)
    stats["s"] = float(stats.get("s", math.nan)) * factor
    codings = ", ".join(
        f"{c.name} {'log10 ' if c.log else ''}{_fmt(c.low, '.4g')} to {_fmt(c.high, '.4g')}"
        + (f" {display_unit(c.unit)}" if c.unit and c.unit != "-" else "")
        for c in fit.codings
    )
    uncoded = fit.uncoded_coefficients().index  # the log-coded factors it has terms of
    logged = [
        c.name for c in fit.codings if c.log and any(f"log10({c.name})" in t for t in uncoded)
    ]
    info = (
        f"Model: {fit.equation(scale=factor).replace(fit.response, response, 1)} (coded units"
        + (f"; {response} in {unit}" if unit else "")
        + f"). Coded -1 to +1: {codings}. In uncoded units (the factors' levels"
        + "".join(f", log10 of {name}" for name in logged)
        + f"): {fit.equation(6, scale=factor, uncoded=True).replace(fit.response, response, 1)}."
        + _model_summary_text({**stats, "surface": True}, unit)
    )
    if fit.notes:
        info += " Note: " + "; ".join(fit.notes) + "."
    return {
        "response": response,
        "anchor": _anchor(response),
        "heading": _heading(str(response)),
        "info": info,
        "coefficients": coefficients,
        "anova": anova,
        "stationary": _stationary_text(fit, factor, unit),
    }


def _v_of(log10_v_mm3: float) -> str:
    """V [mm³] of a value of ``log10_V_mm3``, to 3 significant digits."""
    return _fmt(10.0**log10_v_mm3, ".3g")


def _interval_cell(shown: Any, low: float, high: float) -> str:
    """An interval's cell: its ends, or a dash where it is not defined (no residual df)."""
    if not (math.isfinite(low) and math.isfinite(high)):
        return "–"
    return f"{shown(low)} to {shown(high)}"


def _optimum_item(goals: Sequence[Any], optimum: Any) -> dict[str, Any]:
    """The report's tables of the response optimizer's result."""
    factor_rows = []
    for name, level in optimum.levels.items():
        unit = optimum.units.get(name, "")
        setting = _fmt(level, ".4g") + ("" if unit in ("", "-") else f" {display_unit(unit)}")
        factor_rows.append({"cells": [name, setting, f"{optimum.coded[name]:+.3f}"], "cls": ""})
    factors = _Table(["Factor", "Setting", "Coded"], [False, True, True], factor_rows)
    rows = []
    for g in goals:
        scale, unit = _REPORT_UNITS.get(g.response, (1.0, None))
        low, high = optimum.interval[g.response]
        pi_low, pi_high = optimum.prediction[g.response]
        fitted = optimum.predicted[g.response]

        def shown(v: float, scale: float = scale) -> str:
            return _fmt(v * scale, "sig4")

        cells = [
            g.response + (f" [{unit}]" if unit else ""),
            shown(fitted),
            _interval_cell(shown, low, high),
            _interval_cell(shown, pi_low, pi_high),
            g.describe(scale),
            _fmt(optimum.desirability[g.response], ".3f"),
        ]
        if g.response == "log10_V_mm3":  # V itself, in the unit an engineer reads
            # 10^(the mean of log10 V) is V's geometric mean (its median, for a log-normal
            # scatter), not its mean; a run's interval transforms as it is
            cells[1] += f" (geometric-mean V {_v_of(fitted)} mm³)"
            cells[2] += f" (geometric-mean V {_v_of(low)} to {_v_of(high)} mm³)"
            cells[3] += f" (V {_v_of(pi_low)} to {_v_of(pi_high)} mm³)"
            cells[4] += " (V " + ", ".join(_v_of(v) for v in g.bounds) + " mm³)"
        rows.append({"cells": cells, "cls": ""})
    responses = _Table(
        [
            "Response",
            "Fitted",
            "95 % CI of the mean",
            "95 % PI of one run",
            "Goal (limits)",
            "Desirability",
        ],
        [False, True, True, True, False, True],
        rows,
    )
    info = (
        "The factor setting that best meets the design's goals (Derringer and Suich's "
        "desirability, as Minitab's Response Optimizer): each response's desirability runs "
        "from 0 at its worse limit to 1 at its better one (a target's from 0 at either limit "
        "to 1 at the target); the setting maximizes their importance-weighted geometric "
        f"mean, the composite desirability, here {optimum.composite:.3f}, over the region "
        "the runs span. CI: where the fitted mean lies; PI: where one more run (another "
        "seed) would fall if the model held (both from the model's residual, which holds "
        "its lack of fit as well as the seed-to-seed scatter)."
    )
    if optimum.note:
        info += f" Note: {optimum.note}."
    if getattr(optimum, "edge_matters", bool(optimum.on_boundary)):
        info += (
            f" At the edge of that region: {', '.join(optimum.on_boundary)}; the best setting "
            "may lie beyond it, where the surface is not known."
        )
    return {"info": info, "factors": factors, "responses": responses}


def _stationary_text(fit: Any, factor: float, unit: str | None) -> str:
    """A sentence on the stationary point of ``fit``, or why there is none."""
    st = fit.stationary
    if st is None:
        return (
            "No stationary point: not every factor has a square term (two-level factors), or "
            "the quadratic part is singular."
        )
    levels = ", ".join(
        f"{c.name} = {_fmt(st['levels'][c.name], '.4g')}"
        + (f" {display_unit(c.unit)}" if c.unit and c.unit != "-" else "")
        + f" (coded {st['coded'][c.name]:+.2f})"
        for c in fit.codings
    )
    where = (
        "inside the region the runs span"
        if st["inside"]
        else "outside the region the runs span, so an extrapolation: read the contour plots "
        "for the best point inside it"
    )
    # a level below 0 where every run's is above (A = -45 %): no pad has it
    impossible = [
        c.name for c in fit.codings if float(st["levels"][c.name]) < 0.0 < min(c.low, c.high)
    ]
    if impossible:
        where += (
            f" ({', '.join(impossible)} below 0 there, which no pad can have: the point is "
            "a property of the fitted quadratic, not a setting)"
        )
    predicted = _fmt(float(st["predicted"]) * factor, ".5g") + (f" {unit}" if unit else "")
    if fit.response == "log10_V_mm3" and abs(float(st["predicted"])) < 300:
        predicted += f" (geometric-mean V {_v_of(float(st['predicted']))} mm³)"
    if fit.loses_sign(float(st["predicted"])):
        predicted += (
            f" (not positive, though every run's {fit.response} is: the quadratic does not "
            "keep the response's sign there, and a log scale may fit it better)"
        )
    return (
        f"Stationary point (gradient zero): a {st['kind']} at {levels}, {where}; fitted "
        f"response there {predicted}. Eigenvalues of the quadratic part: "
        + ", ".join(_fmt(v * factor, ".3g") for v in st["eigenvalues"])
        + " (all negative: a maximum; all positive: a minimum; mixed: a saddle)."
    )


#: The rows of a surface fit's ANOVA that are groups or the error, not terms.
_SURFACE_GROUPS = frozenset(
    {
        "Model",
        "Linear",
        "Square",
        "2-Way Interaction",
        "Error",
        "Lack-of-Fit",
        "Pure Error",
        "Total",
    }
)


#: What follows the response's name in a line of :func:`surface_in_short` (a command's
#: heading of "In short" tells the two kinds of line by it).
SURFACE_LINE = " (quadratic surface): "


def surface_in_short(surface_fits: Mapping[str, Any] | None, optimum: Any = None) -> list[str]:
    """The lines of a response-surface report's "In short", before :func:`in_short`'s: for
    each response, its quadratic's terms with p < 0.05, the smallest p first, R², a
    significant lack of fit and the stationary point's kind and place; then, with an
    optimum, the setting that best meets the design's goals.

    Parameters
    ----------
    surface_fits
        Response to :class:`brakeca.rsm.SurfaceFit`, as :func:`write_report` takes them.
    optimum
        The response optimizer's :class:`brakeca.rsm.Optimum`, or None.

    Returns
    -------
    list of str
        One line per response, then the optimum's; empty without fits.
    """
    lines = [line for r, fit in (surface_fits or {}).items() if (line := _surface_finding(r, fit))]
    if optimum is not None:
        lines.append(_optimum_finding(optimum))
    return lines


def _surface_finding(response: str, fit: Any) -> str:
    """One line of a response-surface report's "In short": the terms of ``fit``'s quadratic
    (a :class:`brakeca.rsm.SurfaceFit`) with p < 0.05, smallest p first, R², a significant
    lack of fit, and the stationary point's kind and place (a review: such a report's "In
    short" had held the COF-floor line alone, under the factorial's heading)."""
    terms = fit.anova[~fit.anova["source"].isin(_SURFACE_GROUPS)]
    stats = fit.statistics
    r2 = stats.get("r_squared", math.nan)
    r2_text = "" if _is_missing(r2) else f"; R² = {100.0 * float(r2):.1f} %"
    p = terms["p_value"].astype(float)
    if terms.empty:
        return f"{response}{SURFACE_LINE}no term in the model"
    if p.isna().all():
        return (
            f"{response}{SURFACE_LINE}no term can be tested (no residual degrees of "
            "freedom, or a constant response; the section 'Response surface' says which)"
        )
    tested = terms.assign(p=p)  # (assigned before the filter: an empty frame took p's rows)
    hits = tested[tested["p"] < 0.05].sort_values("p", kind="stable")
    text = (
        f"{response}{SURFACE_LINE}"
        + ", ".join(
            f"{t} (p {_p_text(float(q))})" for t, q in zip(hits["source"], hits["p"], strict=True)
        )
        if len(hits)
        else f"{response}{SURFACE_LINE}no term has p < 0.05"
    ) + r2_text
    lof = stats.get("lack_of_fit_p", math.nan)
    if not _is_missing(lof) and float(lof) < 0.05:
        text += (
            f"; the quadratic lacks fit (p {_p_text(float(lof))}): it departs from the runs "
            "by more than their scatter at repeated levels"
        )
    st = fit.stationary
    if st is not None:
        where = "inside" if st["inside"] else "outside"
        text += f"; its stationary point is a {st['kind']} {where} the runs' region"
    return text


def _optimum_finding(optimum: Any) -> str:
    """The line of "In short" on the response optimizer's setting (:func:`_optimum_item`)."""
    setting = ", ".join(
        f"{name} = {_fmt(level, '.4g')}"
        + (
            ""
            if optimum.units.get(name, "") in ("", "-")
            else f" {display_unit(optimum.units[name])}"
        )
        for name, level in optimum.levels.items()
    )
    return (
        f"The design's goals are best met at {setting}: composite desirability "
        f"{optimum.composite:.3f} (0 misses a goal's limit, 1 meets every goal; section "
        "'Response surface')"
    )


def _model_summary_text(attrs: Mapping[str, Any], unit: str | None) -> str:
    """ " Model summary: residual standard deviation s = ..., R² = ... %, ..." from
    :func:`brakeca.analysis.anova`'s attrs (or a response surface's statistics, with
    ``surface`` True), or "" when the table carries none."""
    if "r_squared" not in attrs:
        return ""

    def pct(key: str) -> str:
        value = attrs.get(key, math.nan)
        return "undefined" if _is_missing(value) else f"{100.0 * float(value):.2f} %"

    s = attrs.get("s", math.nan)
    s_text = "undefined" if _is_missing(s) else f"{float(s):.4g}" + (f" {unit}" if unit else "")
    text = (
        f" Model summary: residual standard deviation s = {s_text} (Minitab's S), R² = "
        f"{pct('r_squared')}, R²(adj) = {pct('r_squared_adj')}, R²(pred) = "
        f"{pct('r_squared_pred')} (R²(pred) from the PRESS statistic, each run predicted by "
        "the model fitted without it)."
    )
    pred = attrs.get("r_squared_pred", math.nan)
    if not _is_missing(pred) and float(pred) < 0.0:
        text += (
            " R²(pred) below 0: the model predicts a run left out worse than the mean of the "
            "others does."
        )
        n_runs, df_left = attrs.get("n", math.nan), attrs.get("df_resid", math.nan)
        if not _is_missing(n_runs) and not _is_missing(df_left) and float(n_runs) > 0:
            n_coef = float(n_runs) - float(df_left)  # the fit's coefficients, intercept too
            # (a new user's review: the text named an unreplicated factorial in every design)
            text += (
                f" The model has {n_coef:.0f} coefficients for {float(n_runs):.0f} runs, so "
                f"a run's fit is on average {100 * n_coef / float(n_runs):.0f} % its own "
                "value (its leverage): the more it is, the better the model describes these "
                "runs and the worse it may predict new ones."
            )
    p_lof = attrs.get("lack_of_fit_p", math.nan)
    pure_df = attrs.get("pure_error_df", math.nan)
    resid_df = attrs.get("df_resid", math.nan)
    if not _is_missing(pure_df) and float(pure_df) < 0.5 and not _is_missing(resid_df):
        if float(resid_df) > 0.5:
            # the order fitted, not the one asked for: a saturated model's interactions are
            # pooled (a DoE review: "more than 2 factors" above the residual of a 2^2's A:B)
            fitted = attrs.get("fitted_order")
            order = int(fitted if fitted else attrs.get("order") or 2)
            if attrs.get("model_terms"):
                left = "every term not among those chosen"
            elif attrs.get("surface"):  # a response surface: no order of interactions (an
                # analysis review read "more than 2 factors" of a two-factor design)
                left = "the terms beyond the quadratic: cubic and higher"
            elif order == 1:
                left = "the interactions"
            else:
                left = f"interactions of more than {order} factors"
            pooled = bool(attrs.get("pooled"))
            if pooled:
                left += ", pooled because the model with them left no degrees of freedom"
            if attrs.get("alpha_to_remove") is not None:
                left += f"{',' if pooled else ''} and the terms backward elimination removed"
            text += (
                f" The residual ({float(resid_df):.0f} df) is the terms the model leaves out "
                f"({left}): no two runs share their levels, so there is no pure error to "
                "test them against. Its mean square estimates the run-to-run scatter only "
                "where those terms are negligible; where they are not it is larger, and the F "
                "tests are conservative."
            )
    if not _is_missing(p_lof):
        p_text = _p_relation(p_lof)
        text += (
            f" The residual splits into pure error ({float(attrs['pure_error_df']):.0f} df: the "
            f"scatter between runs of the same levels) and lack of fit "
            f"({float(attrs['lack_of_fit_df']):.0f} df: the terms left out of the model); lack "
            f"of fit F = {float(attrs['lack_of_fit_F']):.3g}, p {p_text}."
        )
        if float(p_lof) < 0.05:
            text += (
                " The lack of fit is significant: the model departs from the runs by more "
                "than their scatter at repeated levels, so s, the intervals and any optimum "
                "or stationary point of the model carry that misfit; read them as approximate."
            )
    return text


def _p_relation(p: Any) -> str:
    """A p-value for a sentence, ``"p " + this``: ``"< 0.001"`` or ``"= 0.011"``."""
    text = format_p_value(p)
    return text if text.startswith("<") else f"= {text}"


def _centre_points_text(n: int) -> str:
    """``"the 3 centre points' mean"``, ``"the centre point's value"``."""
    return "the centre point's value" if n == 1 else f"the {n} centre points' mean"


def _curvature_text(frame: pd.DataFrame) -> str:
    """ " Curvature: ..." for an ANOVA with centre points (its row ``Curvature``), or ""."""
    n_c = int(frame.attrs.get("center_points", 0) or 0)
    rows = _curvature_rows(frame)
    if not n_c or rows.empty:
        return ""
    what = (
        f" Curvature: {_centre_points_text(n_c)} against the other runs' (Minitab's Ct Pt, "
        "fitted by its own term so that the other terms are the factorial's)"
    )
    aliases = _confounded_with(rows)
    if aliases:
        return (
            what + f"; not a test of curvature: {aliases} did not vary among the other runs, "
            f"so the centre points also differ from them in {aliases}, and the term cannot "
            f"tell curvature from the main effect of {aliases}."
        )
    p = rows["p_value"].iloc[0]
    if _is_missing(p):
        resid = frame.loc[frame["term"] == "Residual", "df"]
        why = (
            "no residual degrees of freedom"
            if resid.empty or _is_missing(resid.iloc[0]) or float(resid.iloc[0]) < 0.5
            else "F and p are not defined; see the note"
        )
        return what + f"; not tested ({why})."
    p_text = _p_relation(p)
    pure = _pure_error_curvature(frame, rows)
    if float(p) < 0.05:
        return (
            what + f", p {p_text}: significant, so the response is not linear in the factors "
            "between their levels (on their coded scale: the log10 of a factor coded 'log', "
            "so a response that is linear in log10 WP shows none), and the factorial model "
            "does not describe the middle of "
            "the region; a response-surface design (a central composite design adds axial "
            "points to these tests) would fit the curvature and tell which factor makes it." + pure
        )
    return what + f", p {p_text}: no evidence of curvature between the levels at 0.05." + pure


def _curvature_rows(frame: pd.DataFrame) -> pd.DataFrame:
    """The ANOVA's row ``Curvature`` (a design with centre points), or no row."""
    return frame.loc[frame["term"] == "Curvature"] if "term" in frame.columns else frame.iloc[:0]


def _confounded_with(rows: pd.DataFrame) -> str:
    """The factors the Curvature row (:func:`_curvature_rows`) is confounded with (those
    that did not vary among the other runs), or "" where it tests curvature."""
    aliases = rows["aliases"].iloc[0] if "aliases" in rows.columns else ""
    return "" if _is_missing(aliases) else str(aliases).strip()


def _lack_of_fit_p(frame: pd.DataFrame) -> float | None:
    """The ANOVA's lack-of-fit p where it is significant (below 0.05), else None."""
    p = frame.attrs.get("lack_of_fit_p", math.nan)
    return None if _is_missing(p) or float(p) >= 0.05 else float(p)


def _curvature_against_pure_error(
    frame: pd.DataFrame, rows: pd.DataFrame
) -> tuple[float, float, float] | None:
    """Where the ANOVA's residual holds a significant lack of fit, the curvature test
    against the pure error alone: F, p and the pure error's df; None otherwise."""
    from scipy import stats

    pe_df = frame.attrs.get("pure_error_df", math.nan)
    pe_ss = frame.attrs.get("pure_error_ss", math.nan)
    if _lack_of_fit_p(frame) is None or _is_missing(pe_df) or _is_missing(pe_ss):
        return None
    if float(pe_df) < 0.5 or float(pe_ss) <= 0.0:
        return None
    ss = float(rows["sum_sq"].iloc[0])
    f_value = ss / (float(pe_ss) / float(pe_df))
    return f_value, float(stats.f.sf(f_value, 1.0, float(pe_df))), float(pe_df)


def _pure_error_curvature(frame: pd.DataFrame, rows: pd.DataFrame) -> str:
    """Where the ANOVA's residual holds a significant lack of fit, the curvature test
    against the pure error alone (a review found the ANOVA's verdict and the effects
    table's contradicting each other without a word); empty otherwise."""
    test = _curvature_against_pure_error(frame, rows)
    if test is None:
        return ""
    f_value, p_pe, pe_df = test
    lof_p = _lack_of_fit_p(frame)
    verdict = "significant" if p_pe < 0.05 else "not significant"
    return (
        f" The residual this F is taken against holds a significant lack of fit (p "
        f"{_p_relation(lof_p)}: terms the model leaves out), which weakens its tests; against "
        f"the pure error alone ({pe_df:.0f} df, the scatter of the repeated runs) "
        f"curvature has F = {f_value:.3g}, p "
        f"{_p_relation(p_pe)}: {verdict}. The pure error of centre points is the seeds' "
        "scatter at the centre, which may be smaller than at the corners."
    )


def _anchor(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_-]+", "-", str(text)).strip("-").lower() or "x"


# --- figures ---------------------------------------------------------------------------------


def _png_size(data: bytes) -> tuple[int, int] | None:
    if len(data) >= 24 and data[12:16] == b"IHDR":
        width, height = struct.unpack(">II", data[16:24])
        return int(width), int(height)
    return None


def _figure_entries(
    figures: Mapping[str, str | Path] | Iterable[tuple[Any, ...]],
) -> list[tuple[str, str, Path]]:
    entries: list[tuple[str, str, Path]] = []
    if isinstance(figures, Mapping):
        return [("Figures", str(caption), Path(p)) for caption, p in figures.items()]
    for item in figures:
        item = tuple(item)
        if len(item) == 3:
            entries.append((str(item[0]), str(item[1]), Path(item[2])))
        elif len(item) == 2:
            entries.append(("Figures", str(item[0]), Path(item[1])))
        else:
            raise ValueError(f"figure entry must be (section, caption, png_path), got {item!r}")
    return entries


#: Width [px] of the page's text column (body max-width 1200 px less 2 x 2rem padding):
#: a wider figure is shown scaled down, and a click on it shows it at full size.
_PAGE_WIDTH_PX = 1136


def _figure_sections(
    figures: Mapping[str, str | Path] | Iterable[tuple[Any, ...]] | None,
) -> list[dict[str, Any]]:
    sections: dict[str, dict[str, Any]] = {}
    for section, caption, png in _figure_entries(figures or {}):
        try:
            data = png.read_bytes()
        except OSError as exc:
            raise FileNotFoundError(f"figure {caption!r}: cannot read {png}: {exc}") from None
        if not data.startswith(_PNG_SIGNATURE):
            raise ValueError(f"figure {caption!r}: {png} is not a PNG file")
        size = _png_size(data)
        entry = sections.setdefault(
            section, {"name": section, "anchor": f"fig-{_anchor(section)}", "figures": []}
        )
        entry["figures"].append(
            {
                "number": 0,  # numbered below, in the order the page shows them
                "caption": caption,
                "data": base64.b64encode(data).decode("ascii"),
                "width": size[0] if size else None,
                "height": size[1] if size else None,
                # wider than the page shows it (1200 px less padding): a click shows it
                # at full size, where a large panel grid's labels are legible
                "wide": bool(size and size[0] > _PAGE_WIDTH_PX),
            }
        )
    number = 0
    for entry in sections.values():
        for fig in entry["figures"]:
            number += 1
            fig["number"] = number
    return list(sections.values())


# --- rendering -------------------------------------------------------------------------------


def in_short(
    anova_tables: Mapping[str, pd.DataFrame],
    *,
    level_means: Mapping[str, pd.DataFrame] | None = None,
    effects_tables: Mapping[str, pd.DataFrame] | None = None,
    box_cox: Mapping[str, Any] | None = None,
    residual_tables: Mapping[str, pd.DataFrame] | None = None,
    unusual_tables: Mapping[str, pd.DataFrame] | None = None,
) -> list[str]:
    """The lines of the report's "In short": for each response, its ANOVA's terms with
    p < 0.05, the largest share of the variation first, a main effect with the mean response
    at each level, and R² (V's with what its Box–Cox check says of its scale), and the runs
    the Bonferroni outlier test calls outliers of the model, with the verdicts that change
    without them.

    Parameters
    ----------
    anova_tables, level_means, effects_tables, box_cox, residual_tables, unusual_tables
        As :func:`write_report` takes them.

    Returns
    -------
    list of str
        One line per response that has one (none for a response without an ANOVA), V in
        mm³, as the report shows them.
    """
    return [
        line
        + (
            _scale_clause(str(r), box_cox, residual_tables, "log10_V_mm3" in anova_tables)
            if line
            else ""
        )
        + _outlier_clause(frame, (unusual_tables or {}).get(r), residual_tables, r)
        + (_log_left_out(level_means) if str(r) == "log10_V_mm3" and line else "")
        for r, frame in anova_tables.items()
        if (
            line := _finding(
                str(r), frame, (level_means or {}).get(r), (effects_tables or {}).get(r)
            )
        )
    ]


def _log_left_out(level_means: Mapping[str, pd.DataFrame] | None) -> str:
    """The clause of log10 V's "In short" line on the runs its level means (and so the
    geometric means of V it gives) leave out: those that emitted nothing, which have no log
    (the Notes said so, the line did not); empty where V's and the log's means count the same
    runs."""
    v, log = (level_means or {}).get("V"), (level_means or {}).get("log10_V_mm3")
    if v is None or log is None or v.empty or log.empty or "n" not in v or "n" not in log:
        return ""
    first = str(v["factor"].iloc[0])  # every run is at one level of each factor
    n_v = int(v.loc[v["factor"] == first, "n"].sum())
    n_log = int(log.loc[log["factor"] == first, "n"].sum())
    if n_v <= n_log:
        return ""
    k = n_v - n_log
    return (
        f"; these means leave out the {k} run{'s' if k > 1 else ''} that emitted nothing "
        "(V = 0 has no log; Notes)"
    )


def all_findings(
    anova_tables: Mapping[str, pd.DataFrame],
    *,
    surface_fits: Mapping[str, Any] | None = None,
    optimum: Any = None,
    level_means: Mapping[str, pd.DataFrame] | None = None,
    effects_tables: Mapping[str, pd.DataFrame] | None = None,
    box_cox: Mapping[str, Any] | None = None,
    residual_tables: Mapping[str, pd.DataFrame] | None = None,
    unusual_tables: Mapping[str, pd.DataFrame] | None = None,
    more: Sequence[str] = (),
    pm10_line: str | None = None,
) -> list[str]:
    """Every line of the report's "In short", in its order: the response surfaces' and the
    optimum's (:func:`surface_in_short`), each other response's (:func:`in_short`; a
    response with a surface is said by it), the non-empty lines of ``more`` (e.g. the runs
    held at the COF floor) and ``pm10_line``. The report and a study's terminal print these
    same lines (a review: each had assembled them on its own).

    Parameters
    ----------
    anova_tables, surface_fits, level_means, effects_tables, box_cox
        As :func:`write_report` takes them.
    residual_tables, unusual_tables
        As :func:`write_report` takes them.
    optimum
        The optimizer's result (:func:`brakeca.rsm.optimize`), or None.
    more
        Further lines, after the responses'.
    pm10_line
        The line of the runs' brake PM10, last; None without one.

    Returns
    -------
    list of str
    """
    lines = surface_in_short(surface_fits, optimum)
    lines += in_short(
        {r: t for r, t in anova_tables.items() if r not in (surface_fits or {})},
        level_means=level_means,
        effects_tables=effects_tables,
        box_cox=box_cox,
        residual_tables=residual_tables,
        unusual_tables=unusual_tables,
    )
    lines.extend(line for line in more if line)
    if pm10_line is not None:
        lines.append(pm10_line)
    return lines


def render_report(
    *,
    title: str,
    design_table: pd.DataFrame,
    summary: pd.DataFrame,
    anova_tables: Mapping[str, pd.DataFrame],
    figures: Mapping[str, str | Path] | Iterable[tuple[Any, ...]],
    config_text: str,
    version: str,
    notes: str = "",
    generated: datetime | None = None,
    effects_tables: Mapping[str, pd.DataFrame] | None = None,
    design_info: str = "",
    surface_fits: Mapping[str, Any] | None = None,
    optimum: tuple[Any, Any] | None = None,
    optimum_note: str = "",
    level_means: Mapping[str, pd.DataFrame] | None = None,
    box_cox: Mapping[str, Any] | None = None,
    anova_info: str = "",
    trend_tables: Mapping[str, pd.DataFrame] | None = None,
    residual_tables: Mapping[str, pd.DataFrame] | None = None,
    coefficient_tables: Mapping[str, pd.DataFrame] | None = None,
    comparison_tables: Mapping[str, pd.DataFrame] | None = None,
    unusual_tables: Mapping[str, pd.DataFrame] | None = None,
    pm10: tuple[pd.DataFrame, str, str] | None = None,
    more_findings: Sequence[str] = (),
    notice: str = "",
) -> str:
    """Render the report to an HTML string (see :func:`write_report` for the parameters).

    Returns
    -------
    str
        The complete, self-contained HTML document.
    """
    import jinja2

    from brakeca.analysis import CENTER_TERM, CURVATURE

    env = jinja2.Environment(
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=False,
        lstrip_blocks=False,
        keep_trailing_newline=True,
    )
    template = env.from_string(REPORT_TEMPLATE)
    when = generated or datetime.now(UTC)
    anova_items = []
    # each long caption once, under the first response that has its table; the later ones
    # refer to it (a review: three captions of 130-150 words, word for word, three times)
    explained: dict[str, str] = {}
    for response, frame in anova_tables.items():
        frame, unit = _anova_in_report_units(str(response), frame)
        table, note = _anova_table(frame)
        typ = frame.attrs.get("typ")
        info = f"{typ} ANOVA of {response}" if typ else f"ANOVA of {response}"
        if frame.attrs.get("model_terms"):
            info += ", of the terms chosen: " + ", ".join(frame.attrs["model_terms"])
        elif frame.attrs.get("order") not in (None, 2):
            info += f", terms up through {frame.attrs['order']} factor" + (
                "s" if frame.attrs["order"] != 1 else ""
            )
        if frame.attrs.get("alpha_to_remove") is not None:
            info += (
                ", reduced by backward elimination (alpha to remove "
                f"{float(frame.attrs['alpha_to_remove']):g}; the note names the terms removed)"
            )
        if unit:
            info += f"; sums of squares and mean squares in ({unit})²"
        info += "." + _model_summary_text(frame.attrs, unit) + _curvature_text(frame)
        effects = (effects_tables or {}).get(response)
        effects_table, effects_info = (
            _effects_table(str(response), effects)
            if effects is not None and not effects.empty
            else (None, "")
        )
        trends = (trend_tables or {}).get(response)
        trends_table, trends_info = (
            _trends_table(str(response), trends, explained.get("trends"))
            if trends is not None and not trends.empty
            else (None, "")
        )
        coefficients = (coefficient_tables or {}).get(response)
        coefficients_table, coefficients_info, equation, equation_unit = (
            _coefficients_table(str(response), coefficients, explained.get("coefficients"))
            if effects_table is None and coefficients is not None and not coefficients.empty
            else (None, "", "", "")
        )
        comparisons = (comparison_tables or {}).get(response)
        comparisons_table, comparisons_info = (
            _comparisons_table(str(response), comparisons, explained.get("comparisons"))
            if comparisons is not None and not comparisons.empty
            else (None, "")
        )
        for kind, shown in (
            ("trends", trends_table),
            ("coefficients", coefficients_table),
            ("comparisons", comparisons_table),
        ):
            if shown is not None:
                explained.setdefault(kind, str(response))
        anova_items.append(
            {
                "response": str(response),
                "comparisons": comparisons_table,
                "comparisons_info": comparisons_info,
                "coefficients": coefficients_table,
                "coefficients_info": coefficients_info,
                "equation": equation,
                "equation_unit": equation_unit,
                "anchor": _anchor(response),
                "heading": _heading(str(response)),
                "table": table,
                "note": note,
                "info": info,
                "effects": effects_table,
                "effects_info": effects_info,
                "trends": trends_table,
                "trends_info": trends_info,
                "unusual": _unusual_text(
                    str(response),
                    (residual_tables or {}).get(response, pd.DataFrame()),
                    (unusual_tables or {}).get(response),
                    anova_tables[response],
                )
                + _negative_fits(
                    str(response),
                    (residual_tables or {}).get(response),
                    "log10_V_mm3" in anova_tables,
                ),
            }
        )
    paragraphs = [p.strip() for p in re.split(r"\n\s*\n", notes or "") if p.strip()]
    findings = all_findings(
        anova_tables,
        surface_fits=surface_fits,
        optimum=None if optimum is None else optimum[1],
        level_means=level_means,
        effects_tables=effects_tables,
        box_cox=box_cox,
        residual_tables=residual_tables,
        unusual_tables=unusual_tables,
        more=more_findings,
        pm10_line=None if pm10 is None else pm10[2],
    )
    return template.render(
        title=title,
        version=version,
        generated=when.isoformat(timespec="seconds"),
        python=f"{platform.python_implementation()} {platform.python_version()}",
        source_key=source_key(),
        libraries=library_versions(
            "numpy", "numba", "scipy", "pandas", "statsmodels", "xarray", "matplotlib"
        ),
        reference=PAPER_REFERENCE,
        config_text=config_text,
        design=_generic_table(design_table),
        design_info=design_info,
        runs=_runs_table(summary),
        level_means=_level_means_table(level_means) if level_means else None,
        level_means_info=_level_means_info(level_means or {}, bool(surface_fits)),
        anova=anova_items,
        anova_aliases=any(
            _names_aliases(table)
            for item in anova_items
            for table in (item["table"], item["effects"])
            if isinstance(table, _Table)
        ),
        figure_sections=_figure_sections(figures),
        notice=notice,
        notes=paragraphs,
        surfaces=[_surface_item(str(r), fit) for r, fit in (surface_fits or {}).items()],
        surface_intro=_SURFACE_INTRO,
        surface_none="No response could be fitted (fewer than two finished runs with a finite "
        "value).",
        optimum=None if optimum is None else _optimum_item(*optimum),
        optimum_note=optimum_note,
        box_cox=_box_cox_table(box_cox) if box_cox else None,
        box_cox_info=_BOX_COX_INFO
        + (_BOX_COX_FIGURE if box_cox and any(b.defined for b in box_cox.values()) else ""),
        anova_info=anova_info,
        findings=findings,
        findings_surface=bool(surface_fits),
        pm10=None if pm10 is None else _generic_table(pm10[0]),
        pm10_info="" if pm10 is None else pm10[1],
        # what the findings' note explains only where the design has it (a review read
        # aliases, centre points and pure error in a report of a full factorial without them)
        findings_centre=any(
            CENTER_TERM in set(t["term"]) or CURVATURE in set(t["term"])
            for t in anova_tables.values()
            if "term" in t.columns
        ),
        findings_pure_error=any(
            float(t.attrs.get("pure_error_df", 0) or 0) > 0 for t in anova_tables.values()
        ),
    )


#: The most significant terms :func:`_finding` names for a response.
_MOST_FINDINGS = 6


def _level_run(response: str, factor: str, means: pd.DataFrame | None) -> str:
    """A main effect in words from the level means: ``"0.225 at S = 0, 0.203 at S = 1"``
    (in the report's unit: mm³ for V); empty where the table lacks the factor or a mean."""
    if means is None or means.empty or "factor" not in means.columns:
        return ""
    rows = means[means["factor"] == factor]
    if rows.empty or rows["mean"].isna().any():
        return ""
    scale, unit = _REPORT_UNITS.get(response, (1.0, None))
    parts = []
    for _, rec in rows.iterrows():
        label = str(rec["label"]) if not _is_missing(rec.get("label")) else ""
        value = _fmt(rec["level"], ".4g")
        shown = label if label and label not in ("-", "+", "0") and label != value else value
        parts.append(f"{_fmt(float(rec['mean']) * scale, 'sig4')} at {factor} = {shown}")
    text = ", ".join(parts) + (f" [{unit}]" if unit else "")
    if response == "log10_V_mm3":  # the means of log10 V back in mm³: V's geometric means,
        # and their ratio from the first level to the last (a report review: "0.2214 at WP =
        # 1e-15" is in log units nobody can use)
        geometric = [10.0 ** float(m) for m in rows["mean"]]
        text += (
            "; geometric means of V "
            + ", ".join(_fmt(g, "sig4") for g in geometric)
            + f" mm³, ×{geometric[-1] / geometric[0]:.3g}"
        )
    return text


def _short_alias_terms(chain: Any) -> list[tuple[str, str]]:
    """The terms of an alias chain (the ANOVA's ``aliases``, ``"WP:slope + A:modulus"``) of
    one or two factors, each with its sign (``("+", "WP:slope")``): the aliases a screening
    design's reader weighs (those of three factors and more are taken as negligible)."""
    if _is_missing(chain) or not str(chain).strip():
        return []
    kept: list[tuple[str, str]] = []
    sign = "+"
    for token in str(chain).split():
        if token in ("+", "-"):
            sign = token
            continue
        if token.startswith("-") and len(token) > 1:
            sign, token = "-", token[1:]
        if token.count(":") <= 1:
            kept.append((sign, token))
        sign = "+"
    return kept


def _short_aliases(chain: Any) -> str:
    """:func:`_short_alias_terms` as text, ``"WP:slope + A:modulus"``; empty where there are
    none."""
    kept = _short_alias_terms(chain)
    if not kept:
        return ""
    text = ("-" if kept[0][0] == "-" else "") + kept[0][1]
    return text + "".join(f" {sign} {term}" for sign, term in kept[1:])


def _finding(
    response: str,
    frame: pd.DataFrame,
    means: pd.DataFrame | None = None,
    effects: pd.DataFrame | None = None,
) -> str:
    """One line of the report's "In short": the terms of ``response``'s ANOVA with p < 0.05,
    largest contribution first, with their contributions [%] and R², and for a main effect
    the mean response at each of its levels (``means``, :func:`brakeca.analysis.main_effects`);
    what stands in the way where there is no test (no residual degrees of freedom, a constant
    response); empty for an empty table. The curvature of centre points is always said (it
    is the question centre points ask), and where the ANOVA's residual lacks fit, the terms
    the effects table (``effects``, tested against the pure error) finds besides."""
    text = _finding_terms(response, frame, means)
    if not text:
        return text
    curvature = _curvature_finding(frame)
    pure_error = _pure_error_finding(frame, effects)
    if "which lacks fit" in curvature and pure_error.endswith(_CONSERVATIVE):
        pure_error = ""  # said by the curvature clause (a diff review: said twice)
    return text + curvature + pure_error + _pooled_finding(frame, effects)


#: The responses whose "In short" line says what their scale check finds, with the word for
#: a negative fitted value: the positive responses MU, V and MU_SD.
_SCALE_CLAUSES = {"MU": "coefficient of friction", "V": "volume", "MU_SD": "spread"}


def _scale_clause(
    response: str,
    box_cox: Mapping[str, Any] | None,
    residual_tables: Mapping[str, pd.DataFrame] | None,
    log_line: bool,
) -> str:
    """The clause of V's or MU_SD's "In short" line on its scale: where the Box-Cox interval
    leaves out λ = 1 and holds λ = 0, that the log fits better (for V, that the
    log10_V_mm3 line is the scale to read); for MU_SD, which has no log line, also where the
    interval holds neither; unless Montgomery's interval, which counts the residual degrees
    of freedom, holds λ = 1: then that the data do not settle the scale; and where the
    profile without the unusual runs holds λ = 1, that the reading rests on them (a report
    review: MU_SD's line said neither scale held while the Box-Cox section said that without
    tests 17 and 23 no transformation was called for; MU's had been left out for its
    outlier). And the runs whose fitted value the linear model makes negative (a
    figures-and-report review: V's two lines disagreed on WR, and nothing said which held; a
    review of MU_SD). Empty where neither applies, and for another response."""
    from brakeca.boxcox import interval_text

    what = _SCALE_CLAUSES.get(response)
    if what is None:
        return ""
    clauses = []
    bc = (box_cox or {}).get(response)
    if bc is not None and getattr(bc, "defined", False) and not bc.contains(1.0):
        holds_log = bc.contains(0.0)
        if holds_log or response != "V":
            text = (
                f"Box-Cox puts {response}'s λ "
                + (  # "≤ -2": a bound at the search range's edge
                    f"at or {'below' if _edge(bc) < 0 else 'above'} {_hat(bc)[2:]}, the "
                    "search range's edge"
                    if _edge(bc)
                    else f"at {_hat(bc)}"
                )
                + f" ({100 * bc.confidence:g} "
                f"% interval {interval_text(bc.ci_low, bc.ci_high)}), which holds "
                + (
                    f"the log and not {response} as it is"
                    if holds_log
                    else f"neither {response} as it is nor its log"
                )
            )
            low, high = getattr(bc, "ci_low_df", math.nan), getattr(bc, "ci_high_df", math.nan)
            if low <= 1.0 <= high:  # as the Box-Cox section's reading says (a user's review)
                text += (
                    f", but with {bc.df_resid:g} residual degree"
                    f"{'' if bc.df_resid == 1 else 's'} of freedom Montgomery's "
                    f"wider interval ({low:.2f} to {high:.2f}) holds λ = 1 too: the data do "
                    f"not settle {response}'s scale"
                )
            elif response == "V" and log_line:
                text += ": read the log10_V_mm3 line"
            elif response != "V":
                text += f" (the report analyses {response} as it is)"
            other = getattr(bc, "without", None)
            unsettled = low <= 1.0 <= high  # said already: no second "but" (a diff review)
            if other is not None and other.defined and other.contains(1.0) and not unsettled:
                runs = getattr(bc, "without_runs", "") or "the unusual runs"
                them = "it" if runs.startswith("test ") and ";" not in runs else "them"
                text += (
                    f"; but that rests on {runs}: without {them}, λ̂ "
                    f"{'' if _edge(other) else '= '}{_hat(other)} "
                    f"({100 * other.confidence:g} % interval "
                    f"{interval_text(other.ci_low, other.ci_high)}), which holds λ = 1 (Box-Cox, "
                    "in the ANOVA section)"
                )
            clauses.append(text)
    residuals = (residual_tables or {}).get(response)
    if residuals is not None and {"fitted", "test"} <= set(residuals.columns):
        negative = residuals.loc[residuals["fitted"] < 0, "test"]
        if len(negative):
            named = sorted({int(t) for t in negative})
            tests = ", ".join(str(t) for t in named[:_MOST_RUNS_LISTED]) + (
                f" and {len(named) - _MOST_RUNS_LISTED} more (tables/residuals_{response}.csv)"
                if len(named) > _MOST_RUNS_LISTED
                else ""
            )  # (a 256-run design's line had named 76: a review of large designs)
            clauses.append(
                f"the linear model of {response} fits a negative {what} for test"
                f"{'s' if negative.nunique() > 1 else ''} {tests}"
            )
    return "".join(f"; {c}" for c in clauses)


def _curvature_finding(frame: pd.DataFrame) -> str:
    """``"; curvature: p = 0.035 (significant)"`` where the ANOVA has centre points' row;
    where its residual lacks fit and the test against the pure error alone (the ANOVA's
    note's, :func:`_curvature_against_pure_error`) judges curvature otherwise, both (a new
    user's review: "none found" beside a Ct Pt of p < 0.001 hidden in "and 2 more")."""
    rows = _curvature_rows(frame)
    if rows.empty:
        return ""
    aliases = _confounded_with(rows)
    if aliases:  # as _curvature_text says
        return f"; the centre points' term is no test of curvature (confounded with {aliases})"
    p = rows["p_value"].iloc[0]
    if _is_missing(p):
        return "; curvature not tested"
    verdict = "significant" if float(p) < 0.05 else "none found at 0.05"
    test = _curvature_against_pure_error(frame, rows)
    pure_p = None if test is None else test[1]
    if pure_p is not None and (pure_p < 0.05) != (float(p) < 0.05):
        other = "significant" if float(pure_p) < 0.05 else "none found at 0.05"
        return (
            f"; curvature between the levels: p {_p_relation(p)} against the ANOVA's "
            f"residual, which lacks fit ({verdict}), p {_p_relation(pure_p)} against the "
            f"pure error of the repeated runs alone ({other})"
        )
    return f"; curvature between the levels: p {_p_relation(p)} ({verdict})"


def _pure_error_finding(frame: pd.DataFrame, effects: pd.DataFrame | None) -> str:
    """Where the ANOVA's residual holds a significant lack of fit, that, with the terms the
    effects table finds with p < 0.05 against the pure error that the ANOVA does not (a new
    user's review: "no term has p < 0.05" above an effects table with seven), or, where
    there is no such table (a factor of three levels) or it finds none besides, what the
    lack of fit means for the F tests (a review of a replicated study: a general factorial's
    lack of fit, p 0.003, had gone unsaid); empty otherwise."""
    lof_p = _lack_of_fit_p(frame)
    if lof_p is None:
        return ""
    lacks = f"; the ANOVA's residual lacks fit (p {_p_relation(lof_p)})"
    if frame.attrs.get("silent_repeat_df"):  # against a pure error identical runs shrink
        # (a diff review: "conservative" beside the note that says the F tests are not)
        return (
            f"{lacks}, against a pure error that identical runs make small (the ANOVA's "
            "note): not a sure sign of terms the model leaves out"
        )
    by_pure_error = (
        effects is not None
        and not effects.empty
        and effects.attrs.get("method") == "pure error"
        and "significant" in effects.columns
    )
    shown = _effects_beyond(frame, effects) if by_pure_error and effects is not None else ""
    if shown:
        return (
            f"{lacks}, and against the pure error of the repeated runs alone (the effects "
            f"table) {shown} also {_have(shown)} p < 0.05"
        )
    return f"{lacks}: terms the model leaves out move it by more than the seed-to-seed" + (
        _CONSERVATIVE
    )


#: The end of In short's plain lack-of-fit clause (:func:`_pure_error_finding`).
_CONSERVATIVE = " scatter, and the F tests, made against that residual, are conservative"


def _pooled_finding(frame: pd.DataFrame, effects: pd.DataFrame | None) -> str:
    """The terms the effects table finds with p < 0.05 by Lenth's method that the ANOVA,
    whose residual is the interactions it pooled because its model was saturated, does not
    (a DoE review: a 2^(5-2) fraction's "In short" said no term of MU had p < 0.05, its
    error holding an alias chain of 30 % of the variation that the effects table found with
    p = 0.004); empty otherwise."""
    if effects is None or effects.empty or effects.attrs.get("method") != "Lenth":
        return ""
    if not frame.attrs.get("pooled"):
        return ""
    shown = _effects_beyond(frame, effects)
    if not shown:
        return ""
    return (
        "; the ANOVA's error is the interactions it pooled (its model with them left no "
        f"degrees of freedom), and by Lenth's method (the effects table) {shown} also "
        f"{_have(shown)} p < 0.05"
    )


def _have(shown: str) -> str:
    """``"has"`` after one term of :func:`_effects_beyond`, ``"have"`` after several."""
    return "have" if ("," in shown or " and " in shown) else "has"


def _effects_beyond(frame: pd.DataFrame, effects: pd.DataFrame) -> str:
    """The terms significant in the effects table (``"WP:WR = A:mu0"`` for an alias chain)
    that the ANOVA ``frame`` does not find with p < 0.05, at most :data:`_MOST_FINDINGS`
    named; empty for none. The centre points' term (``"curvature (Ct Pt)"``) first, and
    not where it is tested against the pure error: the curvature clause says what each
    table finds of it there (:func:`_curvature_finding`)."""
    if "significant" not in effects.columns:
        return ""
    from brakeca.analysis import CENTER_TERM

    named = set(frame.loc[frame["p_value"].astype(float) < 0.05, "term"].astype(str))
    found = effects.loc[effects["significant"].astype(bool)]
    chains = found["aliases"] if "aliases" in found.columns else pd.Series("", index=found.index)
    extra: list[str] = []
    for term, chain in zip(found["term"], chains, strict=True):
        if str(term) in named or (str(term) == CENTER_TERM and "Curvature" in named):
            continue
        if str(term) == CENTER_TERM:
            # against the pure error the curvature clause gives it (_curvature_finding);
            # Lenth's, first, never among those cut short
            if effects.attrs.get("method") != "pure error":
                extra.insert(0, "curvature (Ct Pt)")
            continue
        short = _short_aliases(chain)
        extra.append(f"{term} = {short}" if short else str(term))
    if not extra:
        return ""
    return ", ".join(extra[:_MOST_FINDINGS]) + (
        f" and {len(extra) - _MOST_FINDINGS} more" if len(extra) > _MOST_FINDINGS else ""
    )


def _finding_terms(response: str, frame: pd.DataFrame, means: pd.DataFrame | None) -> str:
    """:func:`_finding` without its curvature and pure-error clauses."""
    if frame.empty or "p_value" not in frame.columns:
        return ""
    terms = frame[~frame["term"].isin(["Residual", "Curvature"])]
    if terms.empty:
        return f"{response}: no term in the model"
    r2 = frame.attrs.get("r_squared", math.nan)
    r2_text = "" if _is_missing(r2) else f"; R² = {100.0 * float(r2):.1f} %"
    p = terms["p_value"].astype(float)
    if p.isna().all():
        # with how many runs (a robustness review: a campaign whose failed runs left too
        # few for the model did not say so here)
        n, df = frame.attrs.get("n"), frame.attrs.get("df_resid")
        too_few = isinstance(n, numbers.Integral) and df is not None and float(df) == 0.0
        fitted = f" with the {int(n)} run(s) fitted" if too_few else ""
        return (
            f"{response}: no term can be tested{fitted} (no residual degrees of freedom, or "
            "a constant response; the ANOVA's note says which)"
        )
    hits = terms[p < 0.05].sort_values("percent_contribution", ascending=False, kind="stable")
    if hits.empty:
        which = "factor or interaction" if "Curvature" in set(frame["term"]) else "term"
        return f"{response}: no {which} has p < 0.05" + r2_text
    named = []
    chains = hits["aliases"] if "aliases" in hits.columns else pd.Series("", index=hits.index)
    for i, (t, c, chain) in enumerate(
        zip(hits["term"], hits["percent_contribution"], chains, strict=True)
    ):
        # the first few with their level means; the rest named, with their shares (a
        # review: "and 1 more" had hidden WR, a main effect, to save a few words)
        run = "" if ":" in str(t) or i >= _MOST_FINDINGS else _level_run(response, str(t), means)
        short = _short_aliases(chain)
        name = f"{t} = {short}" if short else str(t)  # its alias chain's share, not its own
        named.append(f"{name} ({float(c):.1f} %" + (f": {run}" if run else "") + ")")
    text = ", ".join(named)
    share = float(hits["percent_contribution"].sum())
    return (
        f"{response}: {text}; together {share:.1f} % of the variation"
        + r2_text
        + _averaged_over(hits, means)
    )


def _averaged_over(hits: pd.DataFrame, means: pd.DataFrame | None) -> str:
    """A caution where a main effect given with its level means is in a significant
    interaction: its means average over the other factor's levels, between which its effect
    differs (a report review: A's mean effect on MU was given alone while it was 0.033 at
    WP- and 0.158 at WP+); empty otherwise."""
    if means is None:
        return ""
    terms = [str(t) for t in hits["term"]]
    chains = hits["aliases"] if "aliases" in hits.columns else [""] * len(terms)
    # interactions of two factors and more (a model of order 3 can find S:WP:A significant
    # where no pair is: the main effects in it average over it all the same), each with its
    # aliases of two factors: in a fraction, S:WR = WP:A holds WP as much as S (a review:
    # WP was said to be in S:WR)
    joint = {
        t: (
            _short_aliases(chain),
            {
                f
                for term in [t, *(a for _, a in _short_alias_terms(chain))]
                for f in term.split(":")
            },
        )
        for t, chain in zip(terms, chains, strict=True)
        if ":" in t
    }
    shown = [t for t in terms[:_MOST_FINDINGS] if ":" not in t]
    caught = [f for f in shown if any(f in factors for _, factors in joint.values())]
    if not caught:
        return ""
    within = [t for t, (_, factors) in joint.items() if factors & set(caught)]
    names = _listed(caught)
    each = "is" if len(caught) == 1 else "are each"
    others = (
        "the other factor's levels"
        if all(t.count(":") == 1 for t in within)
        else "the other factors' levels"
    )
    aliased = any(joint[t][0] for t in within)
    named = ", ".join(f"{t} = {joint[t][0]}" if joint[t][0] else t for t in within)
    return (
        f"; {names} {each} in a significant interaction"
        + (" or one of its aliases" if aliased else "")
        + f" ({named}): "
        f"{'its' if len(caught) == 1 else 'their'} level means average over {others}, "
        "between which the effect differs (the interaction plots)"
        + ("; which term of an alias chain acts, the design cannot tell" if aliased else "")
    )


def write_report(
    path: str | Path,
    *,
    title: str,
    design_table: pd.DataFrame,
    summary: pd.DataFrame,
    anova_tables: Mapping[str, pd.DataFrame],
    figures: Mapping[str, str | Path] | Iterable[tuple[Any, ...]],
    config_text: str,
    version: str,
    notes: str = "",
    generated: datetime | None = None,
    effects_tables: Mapping[str, pd.DataFrame] | None = None,
    design_info: str = "",
    surface_fits: Mapping[str, Any] | None = None,
    optimum: tuple[Any, Any] | None = None,
    optimum_note: str = "",
    box_cox: Mapping[str, Any] | None = None,
    anova_info: str = "",
    level_means: Mapping[str, pd.DataFrame] | None = None,
    trend_tables: Mapping[str, pd.DataFrame] | None = None,
    residual_tables: Mapping[str, pd.DataFrame] | None = None,
    coefficient_tables: Mapping[str, pd.DataFrame] | None = None,
    comparison_tables: Mapping[str, pd.DataFrame] | None = None,
    unusual_tables: Mapping[str, pd.DataFrame] | None = None,
    pm10: tuple[pd.DataFrame, str, str] | None = None,
    more_findings: Sequence[str] = (),
    notice: str = "",
) -> Path:
    """Write the campaign report as one self-contained HTML file.

    Parameters
    ----------
    path
        Target ``.html`` file; written atomically (temporary file in the same directory,
        then :func:`os.replace`), parent directories are created.
    title
        Report title.
    design_table
        The design (one row per test, factor levels), shown as is.
    summary
        Campaign summary, one row per run; ``MU`` [-] is shown with 3 decimals and ``V``
        [m^3] converted to mm^3 (``V_mm3`` is then omitted as a duplicate).
    anova_tables
        ``{response: table}`` from :func:`brakeca.analysis.anova`; p-values are formatted,
        rows with p < 0.05 are bold and any ``note`` is printed below the table.
    figures
        Either ``{caption: png_path}`` (one section "Figures") or an iterable of
        ``(section, caption, png_path)``; every PNG is embedded as a base64 ``data:`` URI.
    config_text
        The configuration (e.g. TOML) shown verbatim in a ``<pre>`` block.
    version
        Package version for the provenance.
    notes
        Free text shown at the end; blank lines separate paragraphs.
    generated
        Timestamp for the provenance; now (UTC) by default.
    effects_tables
        ``{response: table}`` from :func:`brakeca.analysis.two_level_effects`, shown below
        the response's ANOVA where not empty (designs whose factors all have two levels).
    design_info
        A sentence on the design shown above the design table (its kind, resolution and
        defining relation for a fractional factorial).
    surface_fits
        ``{response: fit}`` from :func:`brakeca.rsm.response_surfaces`, shown in a section
        "Response surface" (coded coefficients, ANOVA, model summary, stationary point) when
        given and not empty.
    optimum
        ``(goals, optimum)``: the design's goals (:class:`brakeca.rsm.Goal`) and
        :func:`brakeca.rsm.optimize`'s result, shown at the end of that section.
    optimum_note
        Shown at the end of that section: why there is no optimum though the design has
        goals, or a caveat beside it (the goals' V limits set for another band or cycle).
    box_cox
        ``{response: BoxCox}`` from :mod:`brakeca.boxcox`, shown at the end of the ANOVA
        section as "Scale of the responses (Box–Cox)" when given and not empty.
    anova_info
        A note shown at the top of the ANOVA section (e.g. why a response-surface design has
        no categorical ANOVA there).
    level_means
        ``{response: table}`` from :func:`brakeca.analysis.main_effects` (the same factors
        and runs for every response), shown as one table "Level means" before the ANOVA.
    trend_tables
        ``{response: table}`` from :func:`brakeca.analysis.factor_trends`, shown under the
        response's ANOVA table when not empty: the linear and quadratic parts of each
        factor of three or more levels.
    residual_tables
        ``{response: table}`` from :func:`brakeca.analysis.residuals`: the runs whose
        standardized residual exceeds :data:`UNUSUAL_RESIDUAL` in size are named under the
        response's ANOVA table, as Minitab lists its unusual observations.
    coefficient_tables
        ``{response: table}`` from :func:`brakeca.analysis.level_coefficients`, shown (folded,
        with the regression equation) under the response's ANOVA table where the response
        has no two-level effects table: a design with a factor of three levels or more.
    comparison_tables
        ``{response: table}`` from :func:`brakeca.analysis.level_comparisons`, shown under
        the response's ANOVA table when not empty: Tukey's pairwise comparisons of the levels
        of each factor of three levels or more.
    unusual_tables
        ``{response: table}`` from :func:`brakeca.analysis.unusual_runs`: with the unusual
        runs, the report names those the Bonferroni outlier test calls outliers of the
        model and says which of the ANOVA's verdicts change without them (the same runs
        its "In short" names).
    pm10
        The runs' brake PM10 on a speed trace: a table (one row per run: its levels, PM10
        and band [mg/km], where the band lies against each Euro 7 limit), the paragraph
        above it, and the line "In short" ends with.
    more_findings
        Further lines of "In short", after the responses' (and before PM10's): e.g. the
        runs held at the COF floor (:func:`brakeca.study.write_study`).
    notice
        A paragraph under the title, before everything: e.g. that the report was written
        without its figures (:func:`brakeca.study.write_study`).

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    FileNotFoundError
        A figure file cannot be read.
    ValueError
        A figure file is not a PNG.

    References
    ----------
    Wahlström (2016), doi:10.1155/2016/8181260.
    """
    html = render_report(
        title=title,
        design_table=design_table,
        summary=summary,
        anova_tables=anova_tables,
        figures=figures,
        config_text=config_text,
        version=version,
        notes=notes,
        generated=generated,
        effects_tables=effects_tables,
        design_info=design_info,
        surface_fits=surface_fits,
        optimum=optimum,
        optimum_note=optimum_note,
        box_cox=box_cox,
        anova_info=anova_info,
        level_means=level_means,
        trend_tables=trend_tables,
        residual_tables=residual_tables,
        coefficient_tables=coefficient_tables,
        comparison_tables=comparison_tables,
        unusual_tables=unusual_tables,
        pm10=pm10,
        more_findings=more_findings,
        notice=notice,
    )
    return write_text(path, html)
