"""Read a finished campaign the way the paper does: tables, figures and the HTML report.

Wiring only: the numbers come from :mod:`brakeca.analysis`, the figures from
:mod:`brakeca.plotting`, the page from :mod:`brakeca.report`. Outputs, in the campaign folder::

    tables/      main effects, interactions (long form), ANOVA, model summary (S, R-squared,
                 adjusted and predicted R-squared), ranked effects and residuals, per response;
                 for a central composite design the response surface's coefficients, ANOVA
                 and summary with the stationary point (surface_*_<R>.csv, brakeca.rsm);
                 the Box-Cox check of MU's, V's and MU_SD's scale (box_cox.csv, brakeca.boxcox)
    figures/     PNG figures (paper Figures 5-11, Pareto charts, residual and Box-Cox plots,
                 final plateau map of each run; cube plots of a two-level design; contour
                 plots of a response surface)
    report.html  everything above in one self-contained page

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from brakeca import __version__
from brakeca._console import is_replicated, run_named, run_tags, tests_named
from brakeca._io import linked_output_problem, write_table, write_text
from brakeca.analysis import default_label, display_unit
from brakeca.campaign import CampaignResult
from brakeca.design import Design, _target
from brakeca.emissions import CAVEAT, EURO7_LIMITS
from brakeca.results import RunResult

if TYPE_CHECKING:
    import xarray as xr

    from brakeca.analysis import Model
    from brakeca.emissions import EmissionParameters, PM10Estimate

__all__ = [
    "RESPONSES",
    "analysed_responses",
    "block_table",
    "destination_problem",
    "per_stop_table",
    "plot_run",
    "with_log_v",
    "write_study",
]

#: The responses a study analyses: ``MU`` [-], ``V`` [m^3 per stop] (shown in mm^3),
#: ``log10_V_mm3`` [-] (log10 of V in mm^3 per stop) and ``MU_SD`` [-] (friction
#: stability: the standard deviation of the per-stop mean COF over the stops; not the
#: paper's).
RESPONSES = ("MU", "V", "log10_V_mm3", "MU_SD")
_LABELS = {
    "MU": "mean COF MU",
    "V": "mean emitted wear volume per stop V",
    "log10_V_mm3": "log10 of V (V in mm³ per stop)",
    "MU_SD": "friction stability MU_SD (standard deviation of the per-stop mean COF)",
}
#: a response's name in a caption that says more of it in parentheses
_SHORT = {"MU_SD": "friction stability MU_SD"}
#: the paper's figure of each response's main effects and interactions (analysis.py)
_PAPER_MAIN = {
    "MU": " (as the paper's Figure 6)",
    "V": " (as the paper's Figure 8)",
    "log10_V_mm3": "",
    "MU_SD": "",
}
_PAPER_INTERACTIONS = {
    "MU": " (as the paper's Figure 7)",
    "V": " (as the paper's Figure 9)",
    "log10_V_mm3": "",
    "MU_SD": "",
}


def analysed_responses(summary: pd.DataFrame) -> tuple[str, ...]:
    """The responses of :data:`RESPONSES` a study analyses for ``summary`` (with
    log10_V_mm3): all of them but MU_SD where no finished run has a spread to show (every
    run made one stop, or the summary has no such column): its ANOVA would be one of zeros
    (a review of MU_SD)."""
    from brakeca.analysis import ok_runs

    ok = ok_runs(summary)
    if "MU_SD" in ok:
        spread = pd.to_numeric(ok["MU_SD"], errors="coerce").to_numpy(dtype=float)
        if np.any(np.isfinite(spread) & (spread > 0.0)):
            return RESPONSES
    return tuple(r for r in RESPONSES if r != "MU_SD")


def with_log_v(summary: pd.DataFrame) -> pd.DataFrame:
    """The summary with the response ``log10_V_mm3``: log10 of V in mm^3 per stop [-].

    The factors act on V multiplicatively (WP alone spans two decades), so an additive model
    of V itself fits effects that are products as interactions and can predict negative
    volumes; on the log scale they add. The study analyses both scales. Runs with V <= 0 (no
    emission) get NaN and are left out of the log analysis.

    Parameters
    ----------
    summary
        A campaign's summary, one row per run, with its column ``V`` [m^3 per stop].

    Returns
    -------
    pandas.DataFrame
        A copy with the column ``log10_V_mm3`` [-] added.
    """
    v_mm3 = pd.to_numeric(summary["V"], errors="coerce").to_numpy(dtype=float) * 1e9
    with np.errstate(divide="ignore", invalid="ignore"):
        log_v = np.where(v_mm3 > 0, np.log10(v_mm3), np.nan)
    return summary.assign(log10_V_mm3=log_v)


#: Per-stop variables of ``campaign.nc`` in ``tables/per_stop.csv``: column, variable and
#: the factor from its SI unit to the column's unit.
_PER_STOP_COLUMNS = (
    ("mean_cof", "mean_cof", 1.0),
    ("emitted_mm3", "emitted_volume", 1e9),
    ("generated_mm3", "generated_volume", 1e9),
    ("primary_area_fraction", "primary_area_fraction", 1.0),
    ("secondary_area_fraction", "secondary_area_fraction", 1.0),
    ("contact_area_fraction", "contact_area_fraction", 1.0),
    ("normal_force_N", "normal_force", 1.0),
    ("line_pressure_MPa", "line_pressure", 1e-6),
    ("duration_s", "duration", 1.0),
    ("n_steps", "n_steps", 1.0),
)


def per_stop_table(result: CampaignResult | RunResult) -> pd.DataFrame:
    """Per-stop results as one long table, for a spreadsheet or a DoE tool: every finished
    run's of a campaign, or a single run's.

    Parameters
    ----------
    result
        A loaded campaign, or one run (:func:`brakeca.simulation.simulate`'s result or
        :meth:`RunResult.from_netcdf`).

    Returns
    -------
    pandas.DataFrame
        One row per run and stop it ran, runs with status ``"ok"`` only, in test and
        replicate order: ``test``, ``replicate``, the factors' levels (these three for a
        campaign only), ``seed``, ``stop``, ``block`` (when the cycle names its blocks), then
        ``mean_cof`` [-] (MU is its mean over a run's stops), ``emitted_mm3`` and
        ``generated_mm3`` [mm³] (``V_mm3`` is the mean of ``emitted_mm3``; V [m^3] that of
        ``emitted_volume``), the time-weighted plateau and contact area fractions of the band
        [-], ``normal_force_N`` [N] and ``line_pressure_MPa`` [MPa], ``duration_s`` [s] and
        ``n_steps`` [-].
    """
    if isinstance(result, RunResult):
        return _stops_frame(result.dataset, {"seed": int(result.seed)})
    if not isinstance(result, CampaignResult):
        raise TypeError(
            f"per_stop_table takes a CampaignResult or a RunResult, got {type(result).__name__}"
        )
    ds = result.dataset
    names = [f.name for f in result.design.factors]
    status = np.asarray(ds["status"].values, dtype=str)
    frames = []
    for i in np.flatnonzero(status == "ok"):
        run = ds.isel(run=int(i))
        ids: dict[str, object] = {
            "test": int(run["test"]),
            "replicate": int(run["replicate"]) if "replicate" in run.coords else 0,
        }
        ids.update({name: run[name].item() for name in names})
        ids["seed"] = int(run["seed"])
        frames.append(_stops_frame(run, ids))
    if not frames:
        return pd.DataFrame(columns=["test", "replicate", *names, "seed", "stop"])
    table = pd.concat(frames, ignore_index=True)
    return table.sort_values(["test", "replicate", "stop"], kind="stable").reset_index(drop=True)


def block_table(per_stop: pd.DataFrame | CampaignResult | RunResult) -> pd.DataFrame:
    """MU and V block by block for each run, from :func:`per_stop_table`: where in the cycle
    a run's emissions come from (an engineer's read of the study: the 15 Highway stops gave
    35-70 % of V, so a ranking of pads depends on the cycle).

    Parameters
    ----------
    per_stop
        :func:`per_stop_table`'s table, with its ``block`` column, or the campaign or run
        to make it of.

    Returns
    -------
    pandas.DataFrame
        One row per run and block, in test, replicate and cycle order: the run's ids and
        levels (the columns before ``stop``), ``block``, ``stops`` [-], ``mean_cof`` (the
        block's stops' mean) [-], ``emitted_mm3`` (their mean) and ``emitted_total_mm3``
        [mm³], and ``share_of_emitted_percent`` (of the run's total) [%]. Empty where the
        table has no ``block`` column (a trace's cycle).
    """
    if isinstance(per_stop, CampaignResult | RunResult):  # as its siblings take them (it
        # had failed with "no attribute 'columns'": an API review)
        per_stop = per_stop_table(per_stop)
    if not isinstance(per_stop, pd.DataFrame):
        raise TypeError(
            f"block_table takes per_stop_table's table, a CampaignResult or a RunResult, got "
            f"{type(per_stop).__name__}"
        )
    if "block" not in per_stop.columns or per_stop.empty:
        return pd.DataFrame()
    ids = list(per_stop.columns[: list(per_stop.columns).index("stop")])
    keys = ["test", "replicate"] if "test" in ids else ["seed"]
    frame = per_stop.assign(_order=per_stop.groupby(keys, sort=False).cumcount())
    first = frame.groupby([*keys, "block"], sort=False)["_order"].transform("min")
    frame = frame.assign(_first=first)
    grouped = frame.groupby([*ids, "block", "_first"], sort=False, dropna=False)
    out = grouped.agg(
        stops=("stop", "size"),
        mean_cof=("mean_cof", "mean"),
        emitted_mm3=("emitted_mm3", "mean"),
        emitted_total_mm3=("emitted_mm3", "sum"),
    ).reset_index()
    total = out.groupby(keys, sort=False)["emitted_total_mm3"].transform("sum")
    out["share_of_emitted_percent"] = np.where(
        total > 0, 100.0 * out["emitted_total_mm3"] / total.where(total > 0, 1.0), np.nan
    )
    out = out.sort_values([*keys, "_first"], kind="stable").drop(columns="_first")
    return out.reset_index(drop=True)


def _stops_frame(run: Any, ids: dict[str, object]) -> pd.DataFrame:
    """One run's rows of :func:`per_stop_table`: ``ids`` (its test, levels, seed), then the
    stops it ran (a campaign's runs share a stop axis; a shorter run's tail is NaN)."""
    ran = np.isfinite(run["mean_cof"].to_numpy())
    frame: dict[str, object] = dict(ids)
    frame["stop"] = run["stop"].to_numpy()[ran]
    if "block" in run.coords:
        frame["block"] = np.asarray(run["block"].values, dtype=str)[ran]
    for column, variable, factor in _PER_STOP_COLUMNS:
        values = run[variable].to_numpy()[ran]
        frame[column] = values.astype(np.int64) if column == "n_steps" else values * factor
    return pd.DataFrame(frame)


def _design_table(result: CampaignResult) -> pd.DataFrame:
    design = result.design
    generated = {}  # a fraction's generated factor -> its word, "= S·WP·WR"
    broken = design.generators_folded_away
    for text in design.generators:
        target, word = (part.strip() for part in text.split("=", 1))
        shown = word.replace(" ", "").replace("*", "·")
        generated[target] = (
            f"(= {shown} before the fold-over)" if target in broken else ("= " + shown)
        )
    rows = []
    logs = any(f.coding == "log" for f in design.factors)
    centre = design.center_levels() if design.center_points else {}
    for f in design.factors:
        row = {
            "factor": f.name,
            "meaning": f.label or default_label(f.field),
            "field": _target(f.field),  # a factor alias ("WP") as the field it sets
            "unit": display_unit(f.unit),
            "levels": ", ".join(
                f"{lev:g}" if f.labels is None else f"{lab} = {lev:g}"
                for lab, lev in zip(f.labels or f.levels, f.levels, strict=True)
            ),
        }
        if logs:  # which factors are coded on log10 of the level (geometric centre)
            row["coding"] = f.coding
        if centre:
            row["centre point"] = f"{centre[f.name]:.4g}"
        if generated:
            row["generated"] = generated.get(f.name, "")
        rows.append(row)
    return pd.DataFrame(rows)


def _design_info(design: Design) -> str:
    """A sentence on the design for the report: its kind, runs and, for a fractional
    factorial, the defining relation and what the resolution means for the analysis."""
    runs = design.n_tests * design.replicates
    text = (
        f"{design.kind[:1].upper()}{design.kind[1:]}: {design.n_tests} tests"
        + (f" × {design.replicates} replicates = {runs} runs" if design.replicates > 1 else "")
        + "."
    )
    if design.is_response_surface:
        text += (
            " Its factors are numeric with three or more levels: the section 'Response "
            "surface' fits the response as a quadratic in the coded factors (curvature and "
            "two-factor interactions), with the stationary point; the main effects are shown "
            "along the fitted surface (a profile) and the pairs in contour plots, since a "
            "response-surface design's level means, in the tables, are not balanced against "
            "the other factors."
        )
    if design.center_points:
        n_c = design.center_points * design.replicates  # runs at the centre
        text += (
            (
                f" Its {n_c} centre point runs (every factor midway between its levels; at "
                "the geometric mean for a factor coded 'log') give pure error and test "
                "curvature"
                if n_c > 1
                else " Its centre point (every factor midway between its levels; at the "
                "geometric mean for a factor coded 'log') tests curvature, without pure error"
            )
            + " (the ANOVA's row Curvature); the level means, the interaction plots and the "
            "effects are of the other tests."
        )
    if design.is_fractional:
        relation = design.relation_text(times="·")
        if design.foldover:
            folded = ", ".join(design.foldover)
            text += (
                f" Generators of the fraction before its fold-over on {folded}: "
                f"{', '.join(design.generators)}; the fold-over (the tests again with the signs "
                f"of {folded} reversed) keeps the words with an even number of them: defining "
                f"relation {relation}."
            )
        else:
            text += f" Generators: {', '.join(design.generators)}; defining relation {relation}."
        resolution = design.resolution
        if resolution == 3:
            text += (
                " Resolution III: main effects are aliased with two-factor interactions; read "
                "a main effect as its alias chain's signed sum (the ANOVA's Aliases column)."
            )
        elif resolution == 4:
            text += (
                " Resolution IV: main effects are clear of two-factor interactions, which are "
                "aliased with each other."
            )
        elif resolution is not None and resolution >= 5:
            text += (
                " Resolution V or higher: main effects and two-factor interactions are clear of "
                "each other."
            )
    return text


_TABLES_README = (
    """\
# The campaign's tables

Written by brakeca {version} ({again}). Comma-separated, one header row,
numbers in full precision.

**Units.** The tables keep the SI units of the analysis: **V in m³ per stop** (1e-9 of the
mm³ the report, the terminal and the figures show), so V's sums of squares and mean squares
are in m⁶ and its effects, coefficients, residuals and standard deviation S in m³. A column
whose name ends in `_mm3` is in mm³, `_MPa` in MPa, `_N` in N, `_s` in s, `_mg_km` in mg/km;
`wall_time` (a run's computing time) is in s.
MU, `MU_SD` (friction stability: the standard deviation of the stops' mean COF over the
stops, divided by their number, not one less) and `log10_V_mm3` (log10 of V in mm³) are
dimensionless. Factor columns hold the levels in
the design's units (WP in m³/(N·m), WR in m, A in %, S in -).

Files (R is the response: MU, V, log10_V_mm3 or MU_SD):

- `{summary}`: one row per run: levels, seed, MU, MU_SD, V (m³) and V_mm3, the run's
  scalars (a campaign written before MU_SD has no such column: the analysis computes it
  from campaign.nc's per-stop mean COF).
- `per_stop.csv`: one row per run and stop: mean COF, emitted and generated volume (mm³),
  plateau and contact area fractions, normal force (N), line pressure (MPa), duration (s).
- `by_block.csv` (a cycle of named blocks): one row per run and block of the cycle: its
  stops, the mean of their mean COF, their mean and total emitted volume (mm³) and the
  block's share of the run's emitted volume (%): where in the cycle V comes from.
- `main_effects_R.csv`, `interactions_R.csv`: the mean response per level, per pair of levels.
- `anova_R.csv`, `model_summary_R.csv`, `ranked_effects_R.csv`: the ANOVA of the categorical
  model, its summary (S, R², adjusted and predicted R², the model's formula), its terms by
  contribution. A term's contribution is its sum of squares in the ANOVA table (Type II, or
  Type III with the design's `anova_type = 3`: the report's ANOVA section names which; Type I
  where the design is rank-deficient, which the table's `note` column, on its first row,
  then says) over the
  total about the mean; in a balanced design these
  are Minitab's sequential sums of squares too, in an unbalanced one they differ from them.
  `ranked_effects_R.csv`'s `effect`, for a term of two-level factors only: mean at the high
  level minus mean at the low (twice the coefficient in ±1 coding, as Minitab's "Effect");
  for an interaction of q such factors, the signed sum of the 2^q cell means over 2^(q-1);
  empty for a term with a factor of three or more levels, whose per-level means are in
  `main_effects_R.csv` and `interactions_R.csv`.
- `residuals_R.csv`: observed, fitted, residual, leverage, standardized residual per run
  (the residual over S·sqrt(1 − leverage), Minitab's "standardized residual"; the normal
  probability plot puts them at Blom's positions, (i − 3/8)/(n + 1/4)), deleted residual
  (the residual against the model fitted without the run, in that fit's standard errors;
  Minitab's TRES), Cook's distance (how far the run moves the fitted values) and DFITS.
- `unusual_R.csv` (where a run's standardized residual is beyond ±2): those runs, with
  `outlier_p`, the deleted residual's two-sided p times the number of runs (Bonferroni's
  outlier test); the report says which of the ANOVA's verdicts change without them.
- `trends_R.csv` (a factor of three or more levels): its main effect split into linear and
  quadratic (and higher) parts, orthogonal polynomials in its levels (`scale`: their values,
  or their log10 where evenly spaced on the log), each with its sum of squares, F and p.
- `effects_R.csv` (two-level designs): effects, coefficients, `se` (the standard error of the
  effect, twice the coefficient's; on the Ct Pt row, which has no effect, twice its
  coefficient's, so t = coefficient / (se / 2) on every row; the report shows the
  coefficient's), t, p.
- `coefficients_R.csv` (a design with a factor of three or more levels, such as the paper's
  WP, in place of `effects_R.csv`): the ANOVA model's coefficient at every level of each
  term, in effects (sum-to-zero) coding as Minitab codes a general factorial, with `se`, t,
  p and VIF; `derived` marks the rows Minitab leaves out (a factor's last level, and an
  interaction's cells at the last level of any of its factors: the other rows fix them).
  A level's coefficient is its least-squares mean less the constant. The regression
  equation is the constant plus, for each term, the coefficient of the run's level(s): the
  report writes it out.
- `comparisons_R.csv` (a factor of three or more levels): Tukey's pairwise comparisons of
  its levels' least-squares means (`mean_a`, `mean_b`; in a balanced design the level means)
  in the ANOVA model: `difference` (`mean_b - mean_a`, the later level less the earlier), its
  `se`, the studentized range `q` (Minitab prints T = q / √2), `p_adjusted` (Tukey's), the
  simultaneous 95 % interval (`ci_low`, `ci_high`) and `significant` (p below 0.05), with
  each level's number of usable runs (`n_a`, `n_b`).
- `grouping_R.csv` (with `comparisons_R.csv`, where it has p values): Minitab's "Grouping
  Information Using the Tukey Method", each level of the factor with its `n`, least-squares
  `mean` and `grouping` letters, the largest mean first; levels that share no letter differ
  significantly (`brakeca.analysis.tukey_grouping`). The report's caption lists the letters.
- `box_cox.csv`: the Box–Cox check of the scale of MU, V and MU_SD (where analysed);
  `without_unusual` (under the ANOVA model, not a response surface's quadratic): λ̂, its
  interval and the reading without the runs whose standardized residual is beyond ±2 (the
  report's unusual runs), under the same terms, and whether the reading holds without them.
- `surface_*_R.csv` (response-surface designs): coded coefficients, ANOVA by source, summary
  (its equation in the response's SI unit), residuals of the quadratic.
- `optimum.csv`: the optimum of the design's goals (V and its limits in m³); each goal's
  `lower`, `target` and `upper` as Minitab gives them: a minimize goal's target (where it
  is fully met) and upper limit, a maximize goal's lower limit and target.
"""
    + textwrap.fill(
        "- `pm10.csv` (runs on a speed trace): the summary with PM10 in mg/km (low, central, "
        "high) and where each band lies against the Euro 7 limits (`vs_7_mg_km`, "
        f"`vs_3_mg_km`): each figure is {CAVEAT}.",
        width=92,
        subsequent_indent="  ",
        break_on_hyphens=False,
    )
    + "\n"
)


def _base_config(out: Path) -> Any:
    """The campaign's ``base_config.toml`` as a configuration; None when it is missing or no
    longer loads (the report then says nothing about the scope)."""
    from brakeca.config import ConfigError, load_config

    path = out / "base_config.toml"
    if not path.exists():
        return None
    try:
        return load_config(path)
    except ConfigError:
        return None


def _band_caption(base: Any) -> str:
    """What a V figure's caption adds for a band narrower than the paper's (the quick band):
    that its volumes are that band's, a fraction of the full band's, so the paper's figures
    compare by their shape; empty for the paper's band or an unknown base configuration."""
    if base is None:
        return ""
    from brakeca.presets import load_preset

    full = load_preset("paper").mesh.band_width  # [m]
    width = base.mesh.band_width
    if width >= full * (1 - 1e-9):  # by the width, not the rows (a review: 101 rows of 0.2 mm)
        return ""
    return (
        f"; V here leaves the simulated band of {base.mesh.n_radial} rows "
        f"({width * 1e3:g} mm), about {width / full:.2g} times the full band's, so compare "
        "its shape with the paper's, not its values"
    )


def _scope(base: Any) -> str:
    """What a campaign left out of the paper's study, for the top of the report: the quick
    band and a cycle cut short (``--stops``); empty for the whole band and cycle."""
    if base is None:
        return ""
    from brakeca.presets import load_preset

    paper = load_preset("paper").mesh
    mesh = base.mesh
    parts = []
    if base.quick:
        parts.append(
            f"on the quick band, {mesh.n_radial} radial rows ({mesh.band_width * 1e3:g} mm) "
            f"instead of the paper's {paper.n_radial}: V is the volume leaving the simulated "
            f"band, so it is about {mesh.n_radial / paper.n_radial:.2g} times the full band's"
        )
    elif (mesh.n_radial, mesh.n_angular) != (paper.n_radial, paper.n_angular):
        parts.append(
            f"on a grid of {mesh.n_radial} × {mesh.n_angular} cells instead of the paper's "
            f"{paper.n_radial} × {paper.n_angular} (its Table 5): V is the volume leaving the "
            "simulated band, so it grows with the band's width"
        )
    cut = _cut_short(base)
    if cut is not None:
        parts.append(
            f"over {cut} only (--stops), so MU and V are means over those stops, and MU_SD "
            "their spread, not over the cycle"
        )
    if not parts:
        return ""
    return "These runs were made " + "; and ".join(parts) + "."


def _cut_short(base: Any) -> str | None:
    """The stops of a campaign run with --stops, in words: "the first N of the cycle's M
    stops"; None for the whole cycle or an unknown base configuration (``base``: None)."""
    from brakeca.config import ConfigError
    from brakeca.traces import configured_cycle

    if base is not None:
        asked = base.cycle.max_stops
        try:
            n_total = configured_cycle(base).n_total
        except (ConfigError, OSError):  # a trace moved, edited or deleted since the runs:
            # the runs hold what the analysis needs (a review: analyze had failed on it)
            return None if asked is None else f"the first {asked} stops of the cycle"
        if asked is not None and asked < n_total:
            return f"the first {asked} of the cycle's {n_total} stops"
    return None


#: A stop is "at the COF floor" where its mean COF lies within this share of
#: ``friction.mu_min`` above it [-] (a report review: equality to 1e-9 had counted 38 % of the
#: stops of a run whose every stop lay within 0.3 % of the floor).
FLOOR_TOLERANCE = 0.01


@dataclass(frozen=True)
class _Floor:
    """The finished runs' shares of stops at the COF floor (:func:`_floor_shares`)."""

    floor: float
    share: np.ndarray
    names: list[str]


def _floor_shares(result: CampaignResult, base: Any) -> _Floor | None:
    """Each finished run's share of stops whose mean COF lies within
    :data:`FLOOR_TOLERANCE` of the floor ``friction.mu_min`` (every contact at or above the
    pressure where the law reaches it), with the runs' names; None where no stop is, the
    campaign's dataset has no ``mean_cof``, the base configuration is unknown or a factor
    sets the floor itself (``friction.mu_min``; one of the law's other parameters moves
    where the floor is reached, not the floor: a review of a replicated study found every
    floor statement left out where ``friction.slope`` was a factor)."""
    data = getattr(result, "dataset", None)
    if base is None or data is None or "mean_cof" not in getattr(data, "data_vars", {}):
        return None
    if any(str(f.field) == "friction.mu_min" for f in result.design.factors):
        return None
    floor = float(base.friction.mu_min)
    cof = data["mean_cof"].transpose("run", "stop").to_numpy().astype(float)
    if "status" in data.coords:  # the finished runs (a shorter cycle's are padded with NaN)
        done = np.asarray([str(v) == "ok" for v in data["status"].to_numpy()])
    else:
        done = np.isfinite(cof).any(axis=1)
    if floor <= 0 or not done.any():
        return None
    stops = np.isfinite(cof[done])
    at = (cof[done] - floor <= FLOOR_TOLERANCE * floor) & stops
    share = at.sum(axis=1) / np.maximum(stops.sum(axis=1), 1)
    if not share.any():
        return None
    tests = data["test" if "test" in data.coords else "run"].to_numpy()[done]
    replicates = data["replicate"].to_numpy()[done] if "replicate" in data.coords else None
    replicated = replicates is not None and len(set(replicates.tolist())) > 1
    names = [
        run_named(
            {"test": t, "replicate": None if replicates is None else replicates[k]}, replicated
        )
        for k, t in enumerate(tests)
    ]
    return _Floor(floor, share, names)


def _floor_note(result: CampaignResult, base: Any) -> str:
    """A note on the stops whose mean COF is at the floor ``friction.mu_min``
    (:func:`_floor_shares`): there MU is held at the floor and cannot show an effect below
    it. Empty where no stop is."""
    found = _floor_shares(result, base)
    if found is None:
        return ""
    share = found.share
    most = np.argsort(-share, kind="stable")[: min(3, int((share > 0).sum()))]
    parts = [
        f"{found.names[int(k)]} ({100 * share[k]:.0f} %" + (" of its stops)" if i == 0 else ")")
        for i, k in enumerate(most)
    ]
    sep = "; " if any("," in n for n in found.names) else ", "  # "test 3, replicate 1"
    from brakeca.report import _listed

    named = _listed(parts, sep)
    return (
        f"The COF floor: {int((share > 0).sum())} of the {share.size} finished runs have "
        f"stops whose mean COF lies within {100 * FLOOR_TOLERANCE:g} % of the floor "
        f"friction.mu_min = {found.floor:g} (every plateau in contact at a pressure where "
        f"the friction law reaches it, or nearly), the most in {named}. In those stops MU is "
        "held at the floor and cannot show an effect that would take it lower, which "
        "compresses the effects on MU of the factors that press the contact harder "
        "(tables/per_stop.csv, column mean_cof)."
    )


#: The per-run table's cycle means of the per-stop area fractions [-]: column -> variable.
CYCLE_AREAS = {
    "cycle_secondary_area_fraction": "secondary_area_fraction",
    "cycle_contact_area_fraction": "contact_area_fraction",
}


def _with_cycle_areas(shown: pd.DataFrame, result: CampaignResult) -> pd.DataFrame:
    """``shown`` (the per-run table) with each run's secondary plateau area and area in
    contact over all the stops it ran, time-weighted by the stops' durations [-], beside the
    last stop's (a report review: the last stop's share does not represent a run, e.g. 67 %
    at stop 170 after 0 % in stops 166-169); unchanged where the campaign's dataset lacks
    them."""
    data = getattr(result, "dataset", None)
    needed = ["duration", "run_id", *CYCLE_AREAS.values()]
    if data is None or "run_id" not in shown.columns:
        return shown
    if any(v not in data.variables for v in needed):
        return shown
    ids = [str(v) for v in data["run_id"].to_numpy()]
    duration = data["duration"].transpose("run", "stop").to_numpy().astype(float)
    weight = np.where(np.isfinite(duration), duration, 0.0)
    total = weight.sum(axis=1)
    out = shown.copy()
    for column, variable in CYCLE_AREAS.items():
        values = data[variable].transpose("run", "stop").to_numpy().astype(float)
        mean = np.where(
            total > 0,
            (np.nan_to_num(values) * weight).sum(axis=1) / np.maximum(total, 1e-300),
            np.nan,
        )
        by_id = dict(zip(ids, mean, strict=True))
        out[column] = [by_id.get(str(r), np.nan) for r in out["run_id"]]
    if "final_secondary_area_fraction" in out.columns:  # beside the last stop's share
        rest = [c for c in out.columns if c not in CYCLE_AREAS]
        at = rest.index("final_secondary_area_fraction") + 1
        out = out[[*rest[:at], *CYCLE_AREAS, *rest[at:]]]
    return out


def _strongest_on_v(result: CampaignResult) -> str | None:
    """The factor whose level means of V span the widest ratio (the largest over the
    smallest), to colour the trade-off figure by; None where V has no positive means."""
    summary = result.summary
    if "V" not in summary.columns:
        return None
    from brakeca.analysis import ok_runs

    ok = ok_runs(summary)
    best, spread = None, 1.0
    for f in result.design.factors:
        if f.name not in ok.columns:
            continue
        means = ok.groupby(f.name)["V"].mean()
        means = means[means > 0]
        if len(means) > 1 and float(means.max() / means.min()) > spread:
            best, spread = f.name, float(means.max() / means.min())
    return best


def _band_share(base: Any) -> str:
    """The simulated band's area against the pad's, for the note on V (a report review: "not
    scaled to the pad" gave no factor): ``": the band is 1,744 mm², 34 % of the pad's
    5,080 mm²"``; empty where the base configuration is unknown."""
    if base is None:
        return ""
    from brakeca.geometry import make_grid

    band = make_grid(base).area * 1e6
    pad = float(base.brake.pad_area) * 1e6
    share = 100 * band / pad  # [%]; two digits at least (a small band had read "0 %")
    area = f"{band:,.0f}" if band >= 100 else f"{band:.3g}"
    percent = f"{share:.0f}" if share >= 10 else f"{share:.2g}"
    return f": the band is {area} mm², {percent} % of the pad's {pad:,.0f} mm²"


def _block_share(result: CampaignResult) -> str:
    """What share of MU_SD's square lies between the means of the cycle's blocks, over the
    finished runs (a review of MU_SD: 95 % in the paper's study, so it reads mostly as the
    friction's sensitivity to the blocks' conditions), as a clause of the notes: ``": in
    the finished runs 95 % of MU_SD² (median; 23 to 100 %) lies between the blocks' mean COF
    (tables/by_block.csv), ..."``; empty for a cycle without named blocks, or one block, and
    for a design with a factor on the cycle (its runs have blocks of their own)."""
    data = result.dataset
    if "mean_cof" not in data or "block" not in data.coords:
        return ""
    if _cycle_factors(getattr(result, "design", None)):  # the runs' blocks differ
        return ""
    blocks = np.asarray(data["block"].values).astype(str)
    names = list(dict.fromkeys(blocks))
    if len(names) < 2:
        return ""
    cof = np.asarray(data["mean_cof"].transpose("run", "stop"), dtype=float)
    shares = []
    for row in cof:
        if not np.isfinite(row).all():  # a failed run (or one cut short)
            continue
        total = float(np.sum((row - row.mean()) ** 2))
        if total <= 0.0:
            continue
        within = sum(
            float(np.sum((row[blocks == b] - row[blocks == b].mean()) ** 2)) for b in names
        )
        shares.append(100.0 * (1.0 - within / total))
    if not shares:
        return ""
    median = float(np.median(shares))
    spread = f" (median; {min(shares):.0f} to {max(shares):.0f} %)" if len(shares) > 1 else ""
    reading = (
        "the friction's sensitivity to the blocks' conditions"
        if median >= 50.0
        else "the friction's drift at each block's conditions"
    )
    return (
        f": in the finished runs {median:.0f} % of MU_SD²{spread} lies between the blocks' mean "
        f"COF (tables/by_block.csv), so MU_SD reads mostly as {reading}"
    )


def _cycle_factors(design: Any) -> list[str]:
    """The design's factors that set the cycle (``cycle``, ``cycle.max_stops``...): its runs
    then have blocks of their own, which campaign.nc's one block axis does not give."""
    factors = getattr(design, "factors", ())
    return [f.name for f in factors if _target(f.field).split(".")[0] == "cycle"]


def _floor_line(result: CampaignResult, base: Any) -> str:
    """The "In short" line on the runs held at the COF floor for most of their stops (half
    or more), where MU cannot fall further (a report review: the note alone, at the end,
    left MU's effects read as if unbounded); empty where no run is."""
    found = _floor_shares(result, base)
    if found is None:
        return ""
    held = [k for k in np.argsort(-found.share, kind="stable") if found.share[k] >= 0.5]
    if not held:
        return ""
    named = [f"{found.names[int(k)]} ({100 * found.share[k]:.0f} %)" for k in held]
    if len(named) > 6:  # the first five, the most held first, and a count
        named = [*named[:5], f"{len(named) - 5} more runs"]
    sep = "; " if any("," in n for n in found.names) else ", "  # "test 3, replicate 1"
    from brakeca.report import _listed

    runs = _listed(named, sep)
    return (
        f"MU at the COF floor: {runs} spend"
        + ("s half its stops " if len(named) == 1 else " half their stops ")
        + f"or more within {100 * FLOOR_TOLERANCE:g} % of friction.mu_min = {found.floor:g}, "
        "where MU cannot fall further: the effects on MU of what lowers it are compressed "
        "there"
        + (
            (", and that run's" if len(named) == 1 else ", and those runs'")
            # "may be": the floor steadies the stops it holds, not the run's other stops (a
            # review of a replicated study: runs held at it had a spread like the others')
            + " MU_SD may be small because the floor holds them, not their pads"
            if "MU_SD" in analysed_responses(getattr(result, "summary", pd.DataFrame()))
            else ""
        )
        + " (Notes)"
    )


def _optimize(design: Design, surfaces: dict, tables_dir: Path) -> tuple[Any, list, str]:
    """The optimum of a response-surface design's goals (:func:`brakeca.rsm.optimize`),
    written to ``tables/optimum.csv``: (optimum, goals, note), or (None, [], why not) when
    the design has no goals or a goal's response has no surface."""
    if not design.goals:
        return None, [], ""
    from brakeca import rsm

    goals = [g.to_goal() for g in design.goals]
    try:
        optimum = rsm.optimize(surfaces, goals)
    except ValueError as exc:
        return None, goals, f"The goals could not be optimized: {exc}."
    write_table(rsm.optimum_table(optimum, goals), tables_dir / "optimum.csv")
    return optimum, goals, ""


_SURFACE_ANOVA_NOTE = (
    "A response-surface design: each response's analysis of variance is that of its quadratic "
    "model, in the section 'Response surface', and its residual plots are that model's. The "
    "ANOVA that treats every factor level as a category of its own (main effects and "
    "two-factor interactions, as for a factorial design) is still written to "
    "tables/anova_R.csv, but not shown: a composite or Box-Behnken design leaves most "
    "combinations of those levels without a run, so that ANOVA is rank-deficient."
)

#: The responses whose scale the report checks (Box-Cox); log10_V_mm3 is one of V's scales.
_BOX_COX_RESPONSES = ("MU", "V", "MU_SD")


#: how the effects chart judges the effects (two_level_effects' attrs "method"), in captions
_EFFECTS_METHOD = {
    "Lenth": "Lenth's pseudo standard error",
    "pure error": "against the pure error",
    "residual": "against the residual of the fitted effects",
}


#: The responses a two-level design's report draws a cube plot of (log10 V's corners would be
#: V's geometric means in log units: V's own cube says it plainer).
_CUBE_RESPONSES = ("MU", "V", "MU_SD")


def _cube_factors(factors: Sequence[Any], data: pd.DataFrame, response: str) -> list[str]:
    """The factors of ``response``'s cube plot (:func:`brakeca.analysis.cube_means`' choice:
    the three two-level factors with the largest main effects) where every factor has two
    levels, as Minitab offers the plot; none for another design or response, or where it
    cannot be drawn."""
    from brakeca.analysis import cube_means

    if (
        response not in _CUBE_RESPONSES
        or len(factors) < 2
        or any(len(f.levels) != 2 for f in factors)
    ):
        return []
    try:
        return list(cube_means(data, factors, response).attrs["factors"])
    except (KeyError, ValueError):  # no such column, or no usable run
        return []


def _has_centre(data: pd.DataFrame, factors: Sequence[Any]) -> bool:
    """Whether ``data`` holds centre points of ``factors`` (every factor at its centre)."""
    from brakeca.analysis import _center_mask, _factors

    try:
        return bool(_center_mask(data, _factors(factors)).any())
    except (KeyError, ValueError, TypeError):
        return False


def _box_cox(
    data: pd.DataFrame,
    factors: list[Any],
    surfaces: dict[str, Any],
    responses: Sequence[str],
    *,
    interactions: Model,
    alpha_to_remove: float | None,
) -> dict[str, Any]:
    """The Box-Cox profile of each of ``responses`` (of MU, V and MU_SD): under the fitted
    quadratic for a response-surface design, under the ANOVA model otherwise (its order,
    ``interactions``, and reduced as the ANOVA is)."""
    from brakeca import boxcox

    return {
        resp: boxcox.surface_box_cox(surfaces[resp])
        if resp in surfaces
        else boxcox.box_cox(
            data,
            factors,
            resp,
            interactions=interactions,
            alpha_to_remove=alpha_to_remove,
        )
        for resp in responses
    }


@dataclass(frozen=True)
class _RunPm10:
    """A run's PM10 [mg/km] and whether its friction brakes did all its braking
    (``cycle.trace.friction_share = 1``: no regeneration)."""

    estimate: PM10Estimate
    friction_only: bool


def _pm10_of(run: RunResult, emissions: EmissionParameters | None = None) -> _RunPm10 | None:
    """PM10 [mg/km] of a run on a speed-trace cycle with ``emissions`` (the defaults and
    the run's own pads and front share for what it does not set); None for a run on a block
    cycle, whose distance between stops is unknown. The distance is the one the run
    recorded (its trace need not be here), else its trace's (an earlier version's run)."""
    from brakeca.emissions import pm10_from_run
    from brakeca.traces import configured_cycle

    if not run.config.cycle.trace_file:
        return None
    attrs = run.dataset.attrs
    distance = (
        float(attrs["distance"]) if "distance" in attrs else configured_cycle(run.config).distance
    )
    return _RunPm10(
        pm10_from_run(run, distance, emissions), run.config.cycle.trace.friction_share == 1.0
    )


#: The vehicles of :data:`brakeca.emissions.EURO7_LIMITS` in a few words, for a table's
#: header (the prose names them whole).
_SHORT_VEHICLES: dict[str, str] = {
    "M1 car other than pure battery-electric": "M1",
    "M1 car, pure battery-electric": "M1, battery-electric",
}


def _sig3(x: float) -> str:
    """``x`` to three significant digits, without an exponent from 1e-4 to below a million:
    1270, 0.0524."""
    return f"{float(f'{x:.3g}'):g}" if abs(x) < 1e6 else f"{x:.3g}"


#: The columns of ``tables/pm10.csv`` after the PM10 band: where the band lies against each
#: Euro 7 limit (``below``, ``straddles``, ``above``; :meth:`PM10Estimate.position`), by
#: limit [mg/km]: ``vs_7_mg_km``, ``vs_3_mg_km``.
PM10_POSITION_COLUMNS: dict[str, float] = {
    f"vs_{limit:g}_mg_km": limit for limit in EURO7_LIMITS.values()
}


#: How the "In short" line on the runs' PM10 begins (the last line write_study's
#: ``in_short`` is given on a speed trace), by which a command tells it from the ANOVA's.
PM10_LINE_START = "Brake PM10 over "


@dataclass(frozen=True)
class _Pm10:
    """A campaign's PM10 for the report: the summary with the PM10 columns (``pm10.csv``),
    the report's table and its paragraph, and the "In short" line."""

    summary: pd.DataFrame
    table: pd.DataFrame
    info: str
    line: str


def _pm10_report(
    summary: pd.DataFrame,
    pm10_of: Mapping[str, _RunPm10 | None],
    design: Design,
    *,
    given: bool = False,
) -> _Pm10 | None:
    """PM10 [mg/km] low/central/high of every run on a speed-trace cycle and where its band
    lies against each Euro 7 limit (NaN and empty for runs on a block cycle, failed runs and
    runs whose file is missing or unreadable: those not in ``pm10_of``); None when no run is
    on a trace. ``given``: the factors are the user's (``--emissions``), not the defaults."""
    from brakeca.emissions import (
        EURO7_PM10_LIMIT_PEV,
        EURO7_REFERENCE,
        PM10_COLUMNS,
        SHORT_DISTANCE,
    )

    ok = {rid: run for rid, run in pm10_of.items() if run is not None}
    estimates = {rid: run.estimate for rid, run in ok.items()}
    if not estimates:
        return None
    values: dict[str, list[Any]] = {name: [] for name in (*PM10_COLUMNS, *PM10_POSITION_COLUMNS)}
    shown: list[dict[str, Any]] = []
    replicated = is_replicated(summary)
    for _, row in summary.iterrows():
        est = estimates.get(str(row.get("run_id", ""))) if row.get("status", "ok") == "ok" else None
        triple = (math.nan,) * 3 if est is None else (est.low, est.central, est.high)
        for key, value in zip(PM10_COLUMNS, triple, strict=True):
            values[key].append(value)
        for key, limit in PM10_POSITION_COLUMNS.items():
            values[key].append("" if est is None else est.position(limit))
        if est is None:
            continue
        levels = {
            f.name: f.label_of(row[f.name]) if f.choices is not None else f"{row[f.name]:g}"
            for f in design.factors
        }
        shown.append(
            {
                "Test": int(row["test"]),
                **({"Replicate": int(row["replicate"])} if replicated else {}),
                **levels,
                "PM10 [mg/km]": _sig3(est.central),
                "Band [mg/km]": f"{_sig3(est.low)} to {_sig3(est.high)}",
                **{  # short headers: the table's do not wrap (a diff review)
                    f"{limit:g} mg/km ({_SHORT_VEHICLES.get(who, who)})": est.position(limit)
                    for who, limit in EURO7_LIMITS.items()
                },
            }
        )
    runs = list(estimates.values())
    distances = sorted({est.distance for est in runs})
    km = (
        f"{distances[0] / 1000.0:.4g} km"
        if len(distances) == 1
        else f"{distances[0] / 1000.0:.4g} to {distances[-1] / 1000.0:.4g} km"
    )
    factors = sorted({est.params.factors_text() for est in runs})
    whose = (
        "given with --emissions"
        if given
        else "brakeca's defaults, with each run's pads per brake and front brake share"
    )
    factor_text = (
        f"The factors ({whose}): {factors[0]}."
        if len(factors) == 1
        else f"The factors ({whose}) differ between runs: " + "; ".join(factors) + "."
    )
    friction_only = sum(run.friction_only for run in ok.values())
    regen = (
        f" {friction_only} of the {len(ok)} runs brake by friction alone "
        "(cycle.trace.friction_share = 1): the "
        f"{EURO7_PM10_LIMIT_PEV:g} mg/km limit is for pure battery-electric "
        "cars, which brake partly by regeneration (GTR No. 24 gives their share)."
        if friction_only
        else ""
    )
    short = (
        (
            f" Over {km} only"
            if len(distances) == 1
            else f" Runs over less than {SHORT_DISTANCE / 1000.0:g} km"
        )
        + ": the limits hold for the WLTP-Brake cycle's 192 km of mixed driving (UN GTR "
        "No. 24), whose mix of stops a short trace does not have."
        if distances[0] < SHORT_DISTANCE
        else ""
    )
    info = (
        f"The vehicle's brake PM10 over the {km} of trace the runs simulate, from each run's "
        "emitted "
        "volume: the simulated band's emission scaled to its pad, to the front axle's pads "
        "and by the front axle's share of the emissions to the vehicle, then to mass (debris "
        "density, plus the disc's wear at the disc-to-pad mass ratio) and to airborne PM10 "
        "(airborne share, PM10 share); the band takes every factor at the end of its "
        "literature range that lowers or raises the figure at once (docs/cycles.md): an "
        f"envelope, not a statistical interval. {factor_text} 'brakeca analyze FOLDER "
        "--emissions FILE' takes others. Where each run's band lies against the Euro 7 "
        f"limits ({EURO7_REFERENCE}): below, straddles or above it; a band across a limit is "
        f"not a pass or a fail.{short}{regen} tables/pm10.csv has every run's figures. Each "
        f"is {CAVEAT}."
    )
    centrals = [est.central for est in runs]
    counts = "; ".join(
        f"against {limit:g} mg/km, "
        + ", ".join(
            f"{n} {word}"
            for word, n in (
                (w, sum(est.position(limit) == w for est in runs))
                for w in ("below", "straddles", "above")
            )
            if n
        )
        for limit in EURO7_LIMITS.values()
    )
    line = (
        f"{PM10_LINE_START}{km}: central figures {_sig3(min(centrals))} to "
        f"{_sig3(max(centrals))} mg/km over the {len(runs)} runs on a speed trace; the "
        f"model's bands (estimates, not compliance evidence) {counts}"
        + (" (a short trace: the limits hold for WLTP-Brake's 192 km)" if short else "")
        + (
            f"; {friction_only} run(s) brake by friction alone, while the "
            f"{EURO7_PM10_LIMIT_PEV:g} mg/km limit is for battery-electric cars"
            if friction_only
            else ""
        )
        + "."
    )
    return _Pm10(summary.assign(**values), pd.DataFrame(shown), info, line)


def check_max_order(
    design: Any, max_order: int | None, model_terms: Sequence[str] | str | None = None
) -> list[str] | None:
    """Check :func:`write_study`'s model against the design: a model order or terms are
    refused for a response-surface design, whose report fits a quadratic surface instead;
    the terms must name the design's factors, and are not given with an order.

    Returns
    -------
    list of str or None
        The terms as the tables write them (:func:`brakeca.analysis.canonical_terms`), or
        None without ``model_terms``.

    Raises
    ------
    ValueError
        As above; the message starts with the argument's name.
    """
    from brakeca.analysis import canonical_terms

    if max_order is not None and design.is_response_surface:
        raise ValueError(
            "max_order: a response-surface design's report fits a quadratic surface, not a "
            "factorial model of some order"
        )
    if model_terms is None:
        return None
    if design.is_response_surface:
        raise ValueError(
            "model_terms: a response-surface design's report fits a quadratic surface, not a "
            "factorial model of chosen terms"
        )
    if max_order is not None:
        raise ValueError("model_terms, max_order: give one of them, not both")
    return canonical_terms(model_terms, list(design.factor_names))


def write_study(
    result: CampaignResult,
    *,
    run_maps: bool = True,
    anova_type: int | None = None,
    alpha_to_remove: float | None = None,
    max_order: int | None = None,
    model_terms: Sequence[str] | str | None = None,
    note: Callable[[str], object] | None = None,
    output: str | Path | None = None,
    in_short: Callable[[str], object] | None = None,
    emissions: EmissionParameters | None = None,
    figures: bool = True,
) -> Path:
    """Write tables, figures and ``report.html`` for a loaded campaign.

    Parameters
    ----------
    result
        A campaign loaded by :func:`brakeca.campaign.load_campaign`.
    run_maps
        Also draw the final plateau map of every run (one PNG per run), and for a run that
        kept maps after chosen stops (``run_campaign(maps_at=)``) its maps over the cycle.
    anova_type
        The ANOVA's sums of squares, 2 (Type II) or 3 (Type III, adjusted); by default the
        design's ``anova_type``.
    alpha_to_remove
        Reduce the models by backward elimination at this level [-]: the response surfaces
        of a response-surface design, the ANOVA model (with its residuals, Box-Cox check and
        effects table) of any other design; by default the design's ``alpha_to_remove``
        (none unless set).
    max_order
        The ANOVA model's terms up through this many factors (1 main effects, 2 the
        default, 3...); by default the design's ``model_order`` (2, or main effects alone
        for a Plackett-Burman design, unless set).
    model_terms
        The ANOVA model's terms one by one instead (``["S", "WP", "WR", "A", "WP*A"]``, or
        one string of them; :func:`brakeca.analysis.canonical_terms`), as Minitab's Terms
        dialog picks them; by default the design's ``model_terms`` where it has them and
        no ``max_order`` is given. Not with ``max_order``.
    note
        Called with the text of each note the report gives on the run files (one that cannot
        be read, left out of the figures), for a command to print it as well.
    output
        The folder the tables, figures and report go to (created); by default the
        campaign's own folder. The campaign's files are only read, so another folder
        analyses a campaign that cannot be written to, or keeps two analyses of one
        campaign (e.g. of two models) side by side. Not another campaign's folder, nor a
        folder inside this campaign's (:func:`destination_problem`).
    in_short
        Called, once the report is written, with each line of its "In short" (each
        response's significant terms with their shares and R²;
        :func:`brakeca.report.surface_in_short` and :func:`brakeca.report.in_short`), for
        a command to print them as well; on a speed trace, last, a line on the runs' PM10
        against the Euro 7 limits.
    emissions
        The factors from a run's emitted volume to the vehicle's PM10 [mg/km] of the runs
        on a speed trace (:func:`brakeca.emissions.load_emissions`); the fields it does not
        set keep their defaults and the run's pads per brake and front brake share
        (:func:`brakeca.emissions.pm10_from_run`). By default the defaults, with each
        run's own pads per brake and front brake share: the figures its run file records.
    figures
        Draw the figures (the default). Without, the tables and a report without figures,
        which says so under its title, in a fraction of the time: for trying one model
        after another (``model_terms``, ``alpha_to_remove``...). The figures an earlier
        analysis drew into the folder are removed, since they may show another model, but
        for those that could not be drawn again (with ``run_maps``, as with figures, the
        maps of runs whose files are gone; the fibre maps where no run file can be read)
        and files of other names.

    Returns
    -------
    Path
        The report file.

    Raises
    ------
    TypeError
        ``result`` is not a campaign result (a folder's path, say).
    ValueError
        ``output`` is a folder the analysis must not write (:func:`destination_problem`).
    """
    from brakeca import report

    if not hasattr(result, "out_dir"):  # a folder, say: 'str' object has no attribute ...
        raise _not_a(
            "a campaign result", result, "brakeca.load_campaign(folder) reads a campaign folder"
        )
    source = Path(result.out_dir)
    out = source if output is None else Path(output)
    problem = destination_problem(source, out) or linked_output_problem(out)
    if problem is not None:
        raise ValueError(f"output {out}: {problem}")
    in_place = out.resolve() == source.resolve()  # (-o given as the campaign's folder too)
    tables_dir = out / "tables"
    drawn = _Figures(out / "figures", draw=figures)
    base = _base_config(source)
    scope = _scope(base)
    found = _analyse(
        result,
        tables_dir,
        readme=_TABLES_README.format(
            version=__version__,
            summary="../summary.csv" if in_place else str(source / "summary.csv"),
            again="`brakeca analyze` writes them again"
            if in_place
            else f"of the campaign in {source}; `brakeca analyze {source} -o {out}` writes "
            "them again",
        ),
        scope=scope,
        anova_type=anova_type,
        alpha_to_remove=alpha_to_remove,
        max_order=max_order,
        model_terms=model_terms,
    )
    surfaces = found.surfaces
    if len(found.ok):  # with no finished run there is nothing to plot; the report says why
        band = _band_caption(base)
        _response_figures(drawn, result, found, band)
        held = _floor_shares(result, base)  # runs held at the COF floor: the floor drawn
        _cycle_figures(
            drawn,
            result,
            found.by_block,
            _stops_run(result, base),
            band,
            floor=None if held is None else held.floor,
        )
    files = _run_file_figures(
        drawn,
        found.ok,
        result.design,
        source / "runs",
        run_maps=run_maps,
        emissions=emissions,
        run_tag=run_tags(result.summary),
    )
    # the figures an earlier analysis drew that this one did not (a model or a design
    # changed since; all of them without figures) would outlive the report's list; but the
    # fibre maps, where no run file could be read to draw them again
    drawn.sweep(keep=() if files.pm10_of else ("fibre_maps.png",))
    notes = _study_notes(result, found, files, base, source, note=note)
    floor_line = _floor_line(result, base)
    pm10 = _pm10_report(result.summary, files.pm10_of, result.design, given=emissions is not None)
    summary = result.summary if pm10 is None else pm10.summary
    if pm10 is not None:
        write_table(summary, tables_dir / "pm10.csv")
    else:
        (tables_dir / "pm10.csv").unlink(missing_ok=True)  # an earlier analysis's
        if emissions is not None and note is not None:
            note(
                "the emission factors given apply to runs on a speed trace, and no finished "
                "run is on one: there is no PM10 in mg/km to give"
            )
    shown = summary.drop(columns=list(PM10_POSITION_COLUMNS), errors="ignore")  # in its section
    shown = _with_cycle_areas(shown, result)
    for f in result.design.factors:
        if f.choices is not None and f.name in shown.columns:  # 'paper', not its level 1
            shown[f.name] = [f.label_of(v) if pd.notna(v) else v for v in shown[f.name]]
    config_text = (
        (source / "base_config.toml").read_text(encoding="utf-8")
        if (source / "base_config.toml").exists()
        else ""
    )
    design_text = (
        (source / "design.toml").read_text(encoding="utf-8")
        if (source / "design.toml").exists()
        else ""
    )
    tables = found.tables  # the responses analysed (analysed_responses), in their order
    anova_tables = {resp: tables[resp]["anova"] for resp in tables if resp not in surfaces}
    effects_tables = {resp: tables[resp]["effects"] for resp in tables}
    level_means = {resp: tables[resp]["main_effects"] for resp in tables}
    residual_tables = {
        resp: tables[resp]["residuals"]
        for resp in tables
        if tables[resp].get("residuals") is not None
    }
    unusual_tables = {
        resp: tables[resp]["unusual"] for resp in tables if tables[resp].get("unusual") is not None
    }
    path = report.write_report(
        out / "report.html",
        title=f"brakeca study: {result.design.name}",
        design_table=_design_table(result),
        summary=shown,
        anova_tables=anova_tables,
        figures=drawn.listed,
        config_text=design_text + "\n# --- base configuration ---\n" + config_text,
        version=__version__,
        notes=notes,
        effects_tables=effects_tables,
        design_info=" ".join(t for t in (scope, _design_info(result.design)) if t),
        surface_fits=surfaces,
        optimum=None if found.optimum is None else (found.goals, found.optimum),
        optimum_note=found.optimum_note,
        box_cox=found.scales,
        anova_info=_SURFACE_ANOVA_NOTE if surfaces else "",
        level_means=level_means,
        trend_tables={resp: tables[resp]["trends"] for resp in tables},
        coefficient_tables={resp: tables[resp]["coefficients"] for resp in tables},
        comparison_tables={resp: tables[resp]["comparisons"] for resp in tables},
        residual_tables=residual_tables,
        unusual_tables=unusual_tables,
        pm10=None if pm10 is None else (pm10.table, pm10.info, pm10.line),
        more_findings=[floor_line],
        notice=""
        if figures
        else "Written without its figures (--no-figures, or write_study(..., figures=False)): "
        "where the text speaks of a plot, brakeca analyze without --no-figures draws it.",
    )
    if in_short is not None:  # the report's lines (report.all_findings), one by one
        for line in report.all_findings(
            anova_tables,
            surface_fits=surfaces,
            optimum=found.optimum,
            level_means=level_means,
            effects_tables=effects_tables,
            box_cox=found.scales,
            residual_tables=residual_tables,
            unusual_tables=unusual_tables,
            more=[floor_line],
            pm10_line=None if pm10 is None else pm10.line,
        ):
            in_short(line)
    return path


def _not_a(what: str, given: Any, reader: str) -> TypeError:
    """The error for ``result`` that is not ``what``; for a path, with the call that reads
    the file (``reader``)."""
    path = f" ({str(given)!r}): {reader}" if isinstance(given, str | Path) else ""
    return TypeError(f"result: {what}, not {type(given).__name__}{path}")


def destination_problem(campaign_dir: str | Path, output: str | Path) -> str | None:
    """Why the analysis of the campaign in ``campaign_dir`` must not go to the folder
    ``output``, or None where it may (the campaign's own folder, or a folder elsewhere).

    Parameters
    ----------
    campaign_dir
        The campaign's folder.
    output
        Where the tables, figures and report would go.

    Returns
    -------
    str or None
        The reason, worded to follow ``output PATH: ``: ``output`` is another campaign's
        folder (its report and tables would be replaced by this campaign's), or lies inside
        this campaign's folder (a campaign run there again would remove the campaign's own
        analysis, as out of date, and leave that one describing the old runs).
    """
    source, out = Path(campaign_dir).resolve(), Path(output).resolve()
    if out == source:
        return None
    if source in out.parents:
        return (
            f"inside the campaign's folder {campaign_dir}, where a campaign run there again "
            "would leave it describing the old runs; give a folder outside it (or none, for "
            "the campaign's own analysis)"
        )
    marks = [name for name in ("design.toml", "summary.csv", "runs") if (out / name).exists()]
    if marks:
        return (
            f"another campaign's folder (it has {', '.join(marks)}): its report and tables "
            "would be replaced by this campaign's; give a folder of its own"
        )
    return None


@dataclass
class _Figures:
    """The report's figures as they are drawn: each PNG in ``folder``, listed as (section,
    caption, path). With ``draw`` False none is drawn or listed. :meth:`sweep` removes the
    report figures an earlier analysis drew that this one did not list."""

    folder: Path
    listed: list[tuple[str, str, Path]] = field(default_factory=list)
    draw: bool = True

    def __post_init__(self) -> None:
        if self.draw:
            self.folder.mkdir(parents=True, exist_ok=True)

    def add(self, section: str, caption: str, name: str, fig_fn, *args, **kwargs) -> bool:
        """Draw ``fig_fn(*args, path=..., **kwargs)`` into ``name`` and list it; True if it
        was drawn."""
        from brakeca._executors import raise_if_interrupted

        raise_if_interrupted()  # a Ctrl-C Python dropped in a callback (a review)
        path = self.folder / name
        if not self.draw:  # (an earlier analysis's figure of that name: sweep removes it)
            return False
        fig_fn(*args, path=path, **kwargs)
        self.listed.append((section, caption, path))
        return True

    def sweep(self, keep: Iterable[str] = ()) -> None:
        """Remove the report's figures an earlier analysis drew that this one did not list
        (:data:`_REPORT_FIGURES`), but those named in ``keep``; then, where none is drawn,
        the folder if nothing is left in it. The runs' own maps are
        :func:`_run_file_figures`' to remove."""
        if not self.folder.is_dir():
            return
        kept = {path.name for _, _, path in self.listed} | set(keep)
        for name in _REPORT_FIGURES:
            if name not in kept:
                (self.folder / name).unlink(missing_ok=True)
        if not self.draw and not any(self.folder.iterdir()):
            self.folder.rmdir()


#: The names of the report's figures but the runs' maps (``final_map_*``, ``maps_by_stop_*``):
#: each response's and the campaign's (exact names: a file of the user's named otherwise,
#: ``surface_notes.png``, stays)
_REPORT_FIGURES = (
    *(
        f"{kind}_{response}.png"
        for kind in (
            "main_effects",
            "interactions",
            "pareto",
            "profile",
            "cube",
            "effects",
            "surface",
            "residuals",
            "residuals_by_level",
            "comparisons",
        )
        for response in _LABELS
    ),
    "box_cox.png",
    "overlaid_contours.png",
    "mu_per_stop.png",
    "mu_per_stop_by_test.png",
    "mu_per_stop_by_level.png",
    "secondary_area_by_level.png",
    "contact_area_by_level.png",
    "v_per_stop.png",
    "v_per_stop_by_test.png",
    "by_block.png",
    "v_per_run.png",
    "mu_vs_v.png",
    "fibre_maps.png",
)


@dataclass(frozen=True)
class _Found:
    """What :func:`_analyse` computed: the finished runs (``ok``), the analysed summary
    (``data``, with log10_V_mm3), each response's tables, a
    response-surface design's surfaces and their residuals, the optimum of its goals (with
    the goals and a note), the Box-Cox profiles and the block-by-block table (empty for a
    cycle without named blocks)."""

    ok: pd.DataFrame
    data: pd.DataFrame
    by_block: pd.DataFrame
    tables: dict[str, Any]
    surfaces: dict[str, Any]
    surface_residuals: dict[str, pd.DataFrame]
    optimum: Any
    goals: list
    optimum_note: str
    scales: dict[str, Any]


def _analyse(
    result: CampaignResult,
    tables_dir: Path,
    *,
    readme: str,
    scope: str,
    anova_type: int | None,
    alpha_to_remove: float | None,
    max_order: int | None,
    model_terms: Sequence[str] | str | None,
) -> _Found:
    """The numbers of :func:`write_study` (its parameters of the same names), written to
    ``tables_dir``: every table of ``tables/`` but ``pm10.csv`` (:func:`write_study`, from
    the run files), and ``readme`` as its README.md."""
    from brakeca import analysis, boxcox

    summary = result.summary
    factors = list(result.design.factors)
    data = with_log_v(summary)
    responses = analysed_responses(data)
    typ = result.design.anova_type if anova_type is None else anova_type
    alpha = result.design.alpha_to_remove if alpha_to_remove is None else alpha_to_remove
    surface_design = result.design.is_response_surface
    terms = check_max_order(result.design, max_order, model_terms)
    model: int | Sequence[str]
    if terms is not None:
        model = terms
    elif max_order is not None:
        model = max_order
    else:
        model = result.design.anova_model
    tables = analysis.analyze(
        data,
        factors,
        responses,
        main_effects_only=result.design.plackett_burman is not None,
        anova_type=typ,
        alpha_to_remove=None if surface_design else alpha,
        max_order=model if isinstance(model, int) else None,
        model_terms=None if isinstance(model, int) else model,
    )
    analysis.save_tables(tables, tables_dir)
    surfaces: dict[str, Any] = {}
    surface_residuals: dict[str, pd.DataFrame] = {}
    if surface_design:
        from brakeca import rsm

        surfaces = rsm.response_surfaces(data, factors, responses, alpha_to_remove=alpha)
        rsm.save_surface_tables(surfaces, tables_dir)
        for resp, fit in surfaces.items():
            surface_residuals[resp] = rsm.surface_residuals(fit, data)
            write_table(surface_residuals[resp], tables_dir / f"surface_residuals_{resp}.csv")
    optimum, goals, optimum_note = _optimize(result.design, surfaces, tables_dir)
    if scope and any(g.response != "MU" for g in goals):
        optimum_note = " ".join(
            t
            for t in (
                optimum_note,
                f"{scope} The goals' limits on V are in absolute volume per stop: check that "
                "they were set for this band and cycle.",
            )
            if t
        )
    scales = _box_cox(
        data,
        factors,
        surfaces,
        [r for r in _BOX_COX_RESPONSES if r in responses],
        interactions=model,
        alpha_to_remove=None if surface_design else alpha,
    )
    boxcox.save_box_cox_table(scales, tables_dir / "box_cox.csv")
    per_stop = per_stop_table(result)
    write_table(per_stop, tables_dir / "per_stop.csv")
    by_block = block_table(per_stop)
    if by_block.empty:  # a cycle without named blocks (a trace): an earlier analysis's goes
        (tables_dir / "by_block.csv").unlink(missing_ok=True)
    else:
        write_table(by_block, tables_dir / "by_block.csv")
    write_text(tables_dir / "README.md", readme)
    return _Found(
        ok=analysis.ok_runs(summary),
        data=data,
        by_block=by_block,
        tables=tables,
        surfaces=surfaces,
        surface_residuals=surface_residuals,
        optimum=optimum,
        goals=goals,
        optimum_note=optimum_note,
        scales=scales,
    )


def _stops_run(result: CampaignResult, base: Any) -> str:
    """What stops the per-stop figures' captions say each run ran: the whole cycle, its
    first stops (--stops), or each run's own cycle where a factor sets it."""
    factors = result.design.factors
    # a factor on the cycle (its file, its stops) gives each run its own
    on_cycle = _cycle_factors(result.design)
    cut = (  # --stops, unless a factor sets the stops (each run's own then)
        base.cycle.max_stops
        if base is not None
        and on_cycle
        and not any(_target(f.field) == "cycle.max_stops" for f in factors)
        else None
    )
    if not on_cycle:
        return _cut_short(base) or "the whole cycle"
    return (
        (f"the first {cut} stops of " if cut is not None else "")
        + f"each run's cycle (the design's factor{'s' if len(on_cycle) > 1 else ''} "
        + f"{', '.join(on_cycle)} set{'' if len(on_cycle) > 1 else 's'} it)"
    )


def _response_figures(
    figures: _Figures, result: CampaignResult, found: _Found, band: str = ""
) -> None:
    """Each response's figures (main effects or a surface's profile, interactions, ranked
    effects, contour plots, residuals), the Box-Cox plots and a response-surface design's
    overlaid contours; ``band`` (:func:`_band_caption`) ends the captions of V's main
    effects and interactions."""
    from brakeca import analysis, plotting
    from brakeca.report import _listed

    factors = list(result.design.factors)
    data, tables, surfaces = found.data, found.tables, found.surfaces
    optimum, goals, scales = found.optimum, found.goals, found.scales
    surface_residuals = found.surface_residuals
    aliases = analysis.interaction_aliases(pd.DataFrame(result.design.combinations()), factors)
    for resp in tables:  # the responses analysed
        label = _LABELS[resp]
        if resp in surfaces:
            # a composite design's level means are not balanced against the other
            # factors, so its raw main-effects and interaction plots mix in their effects
            # (and can contradict the fit): the fitted surface's profile instead, and the
            # contour plots for the pairs (no Pareto chart: the categorical ANOVA's, which
            # is not shown)
            figures.add(
                "Main effects",
                f"Main effects on {label}, from the fitted quadratic surface: the response "
                "along each factor with the others at their centre, with the 95 % "
                "confidence band of the fitted mean (JMP's prediction profiler). The "
                "runs' level means (the table 'Level means') are not balanced against "
                "the other factors in a response-surface design, so they mix in the others' "
                "effects",
                f"profile_{resp}.png",
                plotting.plot_profiler,
                surfaces[resp],
            )
        else:
            figures.add(
                "Main effects",
                f"Main effects on {label}" + _PAPER_MAIN[resp] + (band if resp == "V" else ""),
                f"main_effects_{resp}.png",
                plotting.plot_main_effects,
                data,
                factors,
                resp,
            )
        cube = _cube_factors(factors, data, resp) if resp not in surfaces else []
        if cube:
            others = len(factors) - len(cube)
            figures.add(
                "Main effects",
                f"Cube plot of {_SHORT.get(resp, resp)}, as Minitab's cube plot of data means: "
                f"the mean of the runs at each corner of {_listed(cube)}"
                + (
                    f", the {len(cube)} factors with the largest main effects on it, over "
                    + (
                        f"the other {others} factors' levels"
                        if others > 1
                        else "the other factor's levels"
                    )
                    if others
                    else ""
                )
                + "; the largest and smallest in bold"
                + ("; centre points in no corner" if _has_centre(data, factors) else ""),
                f"cube_{resp}.png",
                plotting.plot_cube,
                data,
                factors,
                resp,
                names=cube,
            )
        if len(factors) >= 2 and resp not in surfaces:  # interactions need two factors
            figures.add(
                "Interactions",
                f"Two-factor interactions on {label}"
                + _PAPER_INTERACTIONS[resp]
                + (band if resp == "V" else "")
                + (
                    "; a panel titled '= ...' shows its pair's interaction together with "
                    "the interactions aliased with it"
                    if aliases
                    else ""
                ),
                f"interactions_{resp}.png",
                plotting.plot_interactions,
                data,
                factors,
                resp,
                aliases=aliases,
            )
        if resp not in surfaces:  # a response surface's terms are in its own section
            figures.add(
                "Ranked effects",
                f"Pareto of the ANOVA terms of {label}: each term's share of the total sum "
                "of squares (a term of several degrees of freedom, such as a factor of "
                "three levels, tends to gather more than a term of one; dark and starred: "
                "p < 0.05; the number over each bar is its share in %)",
                f"pareto_{resp}.png",
                plotting.plot_pareto,
                tables[resp]["ranked_effects"],
                resp,
            )
        effects = tables[resp]["effects"]
        if not effects.empty:  # every factor has two levels
            figures.add(
                "Ranked effects",
                f"Effects on {label}: Pareto chart of the standardized effects, with the "
                "line a significant effect crosses, and half-normal plot of the effects "
                f"({_EFFECTS_METHOD.get(str(effects.attrs.get('method')), '')})",
                f"effects_{resp}.png",
                plotting.plot_effects,
                effects,
                resp,
            )
        if resp in surfaces:
            fit = surfaces[resp]
            figures.add(
                "Contour plots",
                f"Contour plots of the fitted quadratic surface of {label} (coded model "
                "in the section 'Response surface'), each pair of factors with the others "
                "at their centre; the runs projected onto the pair; the star: the "
                "stationary point, projected, when it lies inside the region the runs span",
                f"surface_{resp}.png",
                plotting.plot_response_surface,
                fit,
            )
        # a response surface's residuals are its quadratic's, the others the ANOVA's
        residuals = surface_residuals.get(resp, tables[resp]["residuals"])
        model = "quadratic surface" if resp in surfaces else "ANOVA model"
        formula = str(residuals.attrs.get("formula", ""))
        order_note = (
            ""
            if result.design.randomize_order
            else "; the runs are in the design's standard order (randomize_order is off), so "
            "the order panel sorts them by their levels, not by time: a pattern there shows "
            "what the model leaves out (higher-order interactions) or a spread that changes "
            "with the levels, not a drift (the runs are independent simulations)"
        )
        figures.add(
            "Residuals",
            f"Residual plots of the {model} of {label}; model: {formula}{order_note}",
            f"residuals_{resp}.png",
            plotting.plot_residuals,
            residuals,
            resp,
        )
        # (Tukey's intervals are a table under each ANOVA: drawn, plotting.
        # plot_level_comparisons, they repeated it, averaged over the interactions; an
        # engineer's read of the report: an earlier analysis's figure goes, _Figures.sweep)
        if len(residuals) and "test" in residuals.columns:
            # one variance at every level, as the F tests assume (Minitab's residuals
            # versus the variables; the four-in-one plot mixes the levels)
            names = [f.name for f in factors if f.name in found.ok.columns]
            repeated = bool(names) and bool(found.ok.duplicated(names).any())
            figures.add(
                "Residuals",
                f"Residuals of the {model} of {label} against each factor's levels (the runs "
                "of a level side by side in test order): a level whose runs scatter more "
                "than the others' breaks the one variance the F tests assume"
                + (
                    ""
                    if repeated
                    else "; with no setting run twice, the residuals mix the interactions the "
                    "model leaves out with the run-to-run scatter, which cannot be told apart, "
                    "so this shows how they fall across the levels and cannot test the "
                    "variance itself"
                ),
                f"residuals_by_level_{resp}.png",
                plotting.plot_residuals_by_level,
                residuals,
                data,
                factors,
                resp,
            )
    if any(b.defined for b in scales.values()):  # else the table says why: nothing to draw
        # the model the profiles were taken under, as it was (the caption had named both
        # kinds for a factorial study; a report review)
        kinds = {str(b.model).split(":", 1)[0].strip() for b in scales.values() if b.defined}
        under = {
            frozenset({"ANOVA model"}): "its ANOVA model",
            frozenset({"quadratic model"}): "its response surface's quadratic model",
        }.get(frozenset(kinds), "its model (the ANOVA model, or a response surface's quadratic)")
        figures.add(
            "Residuals",
            f"Box-Cox plots of {_listed(list(scales))}: the likelihood of each power λ of the "
            f"response under {under}, the 95 % interval "
            "of λ shaded; λ = 0 is the log (section 'Scale of the responses')"
            + (
                "; dashed, the profile without the unusual runs, shifted to the same maximum, "
                "its 95 % interval the red bar on the dotted line: where its λ̂ lies far from the "
                "solid one's, the reading rests on those runs"
                if any(
                    getattr(getattr(b, "without", None), "defined", False) for b in scales.values()
                )
                else ""
            ),
            "box_cox.png",
            plotting.plot_box_cox,
            scales,
        )
    if optimum is not None:
        figures.add(
            "Contour plots",
            "Overlaid contour plot: where every response meets its goal's limits (white), "
            "each pair of factors with the others at the optimum's levels; the star: the "
            "optimum",
            "overlaid_contours.png",
            plotting.plot_overlaid_contours,
            surfaces,
            goals,
            optimum,
        )


def _by_test(
    figures: _Figures,
    result: CampaignResult,
    variable: str,
    name: str,
    what: str,
    more: str,
    **options: Any,
) -> None:
    """The figure of every run per stop above it, test by test (small multiples, a panel
    per test: a figures review could not tell 24 lines apart in one panel), where the
    campaign has ``variable`` and two to :data:`brakeca.plotting.MOST_TESTS_NAMED` tests;
    else none (an earlier analysis's goes: :meth:`_Figures.sweep`). ``what`` names the
    variable in the caption, and ``more`` ends it."""
    from brakeca import plotting

    dataset = result.dataset
    if variable not in getattr(dataset, "data_vars", {}) or "run" not in dataset.dims:
        return
    runs = dataset.sizes["run"]
    tests = len(np.unique(dataset["test"].to_numpy())) if "test" in dataset.coords else runs
    if not 2 <= tests <= plotting.MOST_TESTS_NAMED:
        return
    figures.add(
        "Runs",
        f"{what} per stop, test by test: each panel's test in black over every other run in "
        "grey, on the same axes (the figure above, one test at a time"
        + ("; a test's replicates each a black line" if tests < runs else "")
        + ")"
        + more,
        name,
        plotting.plot_mu_per_stop_by_test,
        dataset,
        factors=list(result.design.factors),
        variable=variable,
        **options,
    )


def _cycle_figures(
    figures: _Figures,
    result: CampaignResult,
    by_block: pd.DataFrame,
    stops_run: str,
    band: str = "",
    floor: float | None = None,
) -> None:
    """The figures over the cycle and over the runs: MU per stop (every run's, with the COF
    ``floor`` [-] where runs hold at it, and by level), block by block (``by_block``,
    :func:`block_table`'s, as tables/by_block.csv), and V per run; ``stops_run`` says in the
    captions what stops the runs ran, and ``band`` (:func:`_band_caption`) ends V's."""
    from brakeca import plotting

    factors = list(result.design.factors)
    summary = result.summary
    coords = getattr(result.dataset, "coords", {})
    n_blocks = len({str(b) for b in coords["block"].to_numpy()}) if "block" in coords else 0
    figures.add(
        "Runs",
        f"MU per stop over {stops_run} for every run (as the paper's Figure 10)"
        + (
            f"; the broad pale line, named 'COF floor', is the COF law's floor "
            f"friction.mu_min = {floor:g}, where runs hold"
            if floor is not None
            else ""
        ),
        "mu_per_stop.png",
        plotting.plot_mu_per_stop,
        result.dataset,
        factors=factors,
        floor=floor,
    )
    _by_test(figures, result, "mean_cof", "mu_per_stop_by_test.png", "MU", "", floor=floor)
    figures.add(
        "Runs",
        f"MU per stop over {stops_run} at each level of each factor: the mean of the "
        "finished runs at that level, stop by stop (the main effects over the cycle"
        + ("; centre points left out" if result.design.center_points else "")
        + ")"
        + (
            ", the cycle's blocks shaded (named in the figure of MU per stop above)"
            if n_blocks > 1
            else ""
        ),
        "mu_per_stop_by_level.png",
        plotting.plot_mu_per_stop_by_level,
        result.dataset,
        factors,
    )
    for variable, what, name in (
        ("secondary_area_fraction", "Secondary plateau area", "secondary_area_by_level.png"),
        ("contact_area_fraction", "Area in contact", "contact_area_by_level.png"),
    ):
        # what carries MU and V over the cycle (the paper's reading of its effects; a
        # figures review found no figure of the plateaus' or the contact's area over it)
        if variable in getattr(result.dataset, "data_vars", {}):
            figures.add(
                "Runs",
                f"{what} per stop over {stops_run} at each level of each factor, in per cent "
                "of the band and time-weighted over each stop: the mean of the finished runs "
                "at that level, stop by stop (thick), and each run (thin); where a level's "
                "runs are in different states, some near none and some near all of it, the "
                "mean is an area no run has"
                + (
                    "; the secondary plateaus in contact or not (the deposits the disc does "
                    "not touch count too)"
                    if variable == "secondary_area_fraction"
                    else ""
                )
                + ("; centre points left out" if result.design.center_points else "")
                + (
                    " (the cycle's blocks shaded, named in the figure of MU per stop above)"
                    if n_blocks > 1
                    else ""
                ),
                name,
                plotting.plot_mu_per_stop_by_level,
                result.dataset,
                factors,
                variable=variable,
                runs=True,
            )
    if "emitted_volume" in getattr(result.dataset, "data_vars", {}):
        # where in the cycle each run's V comes from (a figures review: V is the mean of
        # 170 stops whose volumes span decades, most of it from a few blocks)
        figures.add(
            "Runs",
            f"Emitted wear volume per stop over {stops_run} for every run (V is their mean; "
            "on a log axis where the stops' volumes span more than two decades, a stop that "
            "emitted nothing without a point)",
            "v_per_stop.png",
            plotting.plot_mu_per_stop,
            result.dataset,
            factors=factors,
            variable="emitted_volume",
            log=None,
        )
    _by_test(
        figures,
        result,
        "emitted_volume",
        "v_per_stop_by_test.png",
        "The emitted wear volume",
        "; on a log axis as above, a stop that emitted nothing without a point",
        log=None,
    )
    if n_blocks > 1 and not _cycle_factors(result.design) and not by_block.empty:
        # the block-by-block table as a figure (an engineer's read: a CSV alone; a review
        # of MU_SD: its spread lies mostly between the blocks' mean COF)
        figures.add(
            "Runs",
            "Block by block, for every finished run: the mean COF of each block's stops (left; "
            "MU_SD is mostly the differences along a row) and the block's share of the "
            "run's emitted volume (right; each block named with its number of stops, as its "
            "share grows with them); the numbers are tables/by_block.csv's",
            "by_block.png",
            plotting.plot_by_block,
            by_block,
            factors,
        )
    figures.add(
        "Runs",
        (
            "V of every test, the mean of its finished replicates, with ± 1 standard "
            "deviation where two or more finished"
            if is_replicated(summary)
            else "V for every run"
        )
        + " (as the paper's Figure 11; on a log axis, a point per test, where the "
        "tests' V span more than two decades)" + band,
        "v_per_run.png",
        plotting.plot_v_per_run,
        summary,
        factors=factors,
    )
    if {"MU", "V"} <= set(summary.columns):
        # the paper's trade-off run by run (an engineer's read: no figure set MU against V)
        by = _strongest_on_v(result)
        figures.add(
            "Runs",
            "The trade-off between friction and emissions: each test's MU against its V"
            + (" (the means of its replicates), " if is_replicated(summary) else ", ")
            + (
                "labelled with its test number"
                if not plotting.mu_v_names_front_only(summary)
                else f"labelled with its test number only where no other test has both a "
                f"higher MU and a lower V (beyond {plotting.MOST_TESTS_NAMED} tests)"
            )
            + (f", coloured by the levels of {by}, the factor that moves V most" if by else "")
            + "; a pad material wants the lower right (high MU, low V)"
            + band,
            "mu_vs_v.png",
            plotting.plot_mu_vs_v,
            summary,
            factors=factors,
            by=by,
        )


@dataclass(frozen=True)
class _RunFiles:
    """What :func:`_run_file_figures` read from the run files: the message of each file
    that cannot be read (by run id), each readable run's PM10 (by run id; None: not on a
    trace) and the finished runs whose file was read."""

    unreadable: dict[str, str]
    pm10_of: dict[str, _RunPm10 | None]
    filed: pd.DataFrame


#: The kinds of a run's own maps, the start of their figures' names.
_RUN_MAPS = ("final_map", "maps_by_stop")


def _run_file_figures(
    figures: _Figures,
    ok: pd.DataFrame,
    design: Design,
    runs_dir: Path,
    *,
    run_maps: bool,
    emissions: EmissionParameters | None = None,
    run_tag: Callable[[Any], str],
) -> _RunFiles:
    """The figures drawn from the runs' own files in ``runs_dir``: the initial fibre map of
    each A level and, with ``run_maps``, every run's final plateau map and its maps over the
    cycle, named by ``run_tag(row)`` (:func:`brakeca._console.run_tags` of the whole
    summary)."""
    from brakeca import plotting

    factors = list(design.factors)
    fig_dir = figures.folder
    # The figures of the runs' own files draw the runs whose file is there: a folder sent
    # without runs/ (summary.csv and campaign.nc) still gives every table and the report, and
    # a damaged file is left out as a missing one is, and named (it raised half-way through
    # the figures, leaving new tables beside the old report: a fuzz review). Each file is
    # read once (three reads had been a third of the analysis's time: a speed review): its
    # final maps drawn, its PM10 and, for the first run at each A level, its initial fibre
    # map kept; the fibre maps are listed before the runs' maps, as before.
    unreadable: dict[str, str] = {}
    pm10_of: dict[str, _RunPm10 | None] = {}  # None: not on a trace
    first_pad: dict[float, tuple[int, tuple[np.ndarray, np.ndarray, np.ndarray]]] = {}
    names = {f.name for f in factors}
    replicated = is_replicated(ok)
    pads_at = len(figures.listed)  # where the fibre maps go, before the runs' maps

    # The maps an earlier analysis drew would outlive the report's list: without run_maps,
    # or of runs that have left the summary, or named at another width (a design grown past
    # 99 tests); they are removed once this analysis has drawn its own, but for the maps of
    # runs still in the summary whose file cannot be read now (a folder sent without runs/:
    # they could not be drawn again; a diff review).
    earlier = [*fig_dir.glob("final_map_test*.png"), *fig_dir.glob("maps_by_stop_*.png")]
    undrawable: set[str] = set()  # the names of the maps of such runs
    for _, row in ok.iterrows() if "run_id" in ok.columns else ():  # (none: no run finished)
        rid = str(row["run_id"])
        path = runs_dir / f"{rid}.nc"
        run = None
        try:
            run = RunResult.from_netcdf(path) if path.is_file() else None
        except (OSError, ValueError) as exc:
            unreadable[rid] = str(exc)
        if run is None:  # missing or unreadable: its earlier maps cannot be drawn again
            undrawable.update(f"{kind}_{run_tag(row)}.png" for kind in _RUN_MAPS)
            continue
        ds = run.dataset
        pm10_of[rid] = _pm10_of(run, emissions)
        if "A" in names and float(row["A"]) not in first_pad:
            first_pad[float(row["A"])] = (
                int(row["test"]),
                (ds["initial_status"].to_numpy(), ds["radius"].to_numpy(), ds["angle"].to_numpy()),
            )
        if not run_maps:
            continue
        levels = ", ".join(
            f"{f.name} = {f.label_of(row[f.name])}"
            if f.choices is not None
            else f"{f.name} = {row[f.name]:g}"
            + ("" if f.unit in ("", "-") else f" {display_unit(f.unit)}")
            for f in factors
        )
        which = (
            f", replicate {int(row['replicate'])} (seed {int(row['seed'])})" if replicated else ""
        )
        tag = run_tag(row)
        span = _cut_short(run.config) or "the whole cycle"
        removal = run.config.automaton.secondary_removal_fraction
        status, after, title = "final_status", span, f"after {span}"
        if "final_status_before_s" in ds:  # the last stop's plateaus, before rule S
            # (a figures review: the maps of S = 1 runs, after rule S, showed none of the
            # secondary plateaus that had carried their last stop)
            status = "final_status_before_s"
            after += (
                f", at the end of the last stop, before the S rule (S = {removal:g}) removed "
                "secondary plateaus"
            )
            title += ", before rule S"
        elif (
            removal > 0
            and "secondary_removed_between_stops" in ds
            and not int(ds["secondary_removed_between_stops"][-1])
        ):
            after += (
                f"; the S rule (S = {removal:g}) found no secondary plateau to remove after "
                "the last stop"
            )
        elif removal > 0:  # a run file of an earlier version: the state after rule S
            after += (
                f", after the S rule (S = {removal:g}) removed secondary plateaus at the "
                "end of the last stop (the per-run table's secondary share is the last "
                "stop's own, before it)"
            )
            title += " and rule S"
        n_sub = run.config.mesh.n_subdomains
        if n_sub > 1 and (ds[status].to_numpy() == 2).any():
            # (a figures review took the empty first subdomain for an artefact)
            after += (
                f". The first of the band's {n_sub} subdomains (the left 1/{n_sub} of the "
                "map, where the disc enters the pad) holds no secondary plateau: no particle "
                "stream reaches it (docs/model.md §7)"
            )
        to_scale = plotting.fits_to_scale(ds["radius"].to_numpy(), ds["angle"].to_numpy())
        figures.add(
            "Final plateau maps",
            f"Test {int(row['test'])} ({levels}){which}: plateaus after {after}. The "
            "legend's shares are the map's own; the per-run table's 'last stop' ones are "
            "that stop's time averages" + ("; drawn to scale" if to_scale else ""),
            f"final_map_{tag}.png",
            plotting.plot_surface_map,
            *(ds[name].to_numpy() for name in (status, "radius", "angle")),
            # what the map is after, in the figure too (a review compared its secondary
            # share of 0 with the summary's last-stop share, which is before rule S)
            title=f"Test {int(row['test'])}: {levels}; {title}",
            true_scale=to_scale,
        )
        if "map_status" not in ds:
            continue
        kept = ", ".join(str(int(k)) for k in ds["map_stop"].to_numpy())
        figures.add(
            "Plateau maps over the cycle",
            f"Test {int(row['test'])} ({levels}){which}: plateaus before the first stop "
            f"and after stop{'s' if ds.sizes['map_stop'] > 1 else ''} {kept} (brakeca run "
            "--maps-at)",
            f"maps_by_stop_{tag}.png",
            plotting.plot_fibre_maps,
            _maps_over_cycle(ds),
            title=f"Test {int(row['test'])}: {levels}{which}",
        )
    drawn = {path.name for _, _, path in figures.listed}
    for stale in earlier:
        if stale.name not in drawn and not (run_maps and stale.name in undrawable):
            stale.unlink(missing_ok=True)
    filed = ok[[str(rid) in pm10_of for rid in ok["run_id"]]] if len(pm10_of) else ok.iloc[:0]
    if first_pad:
        from brakeca.report import _listed

        shown_tests = [str(first_pad[level][0]) for level in sorted(first_pad)]
        _, radius, angle = next(iter(first_pad.values()))[1]
        to_scale = plotting.fits_to_scale(radius, angle)  # (a quick band: a thin strip)
        if figures.add(
            "Pad surfaces",
            "Initial fibre maps of the A levels (as the paper's Figure 5): the pads of tests "
            f"{_listed(shown_tests)}, the first run at each level (every run draws a pad of its "
            "own from its seed)"
            + (
                ", drawn to scale: a millimetre of radius as long as one of arc at the band's "
                "mean radius"
                if to_scale
                else ", the radius stretched to fill the panels (to scale, the band would be "
                "a thin strip)"
            ),
            "fibre_maps.png",
            plotting.plot_fibre_maps,
            {f"A = {level:g} %": first_pad[level][1] for level in sorted(first_pad)},
            title=f"Initial pad surfaces: test{'s' if len(shown_tests) > 1 else ''} "
            + _listed(shown_tests),  # (not "1 and 6 and 11 and 16": a figures review)
            true_scale=to_scale,
        ):
            figures.listed.insert(pads_at, figures.listed.pop())
    return _RunFiles(unreadable, pm10_of, filed)


def _study_notes(
    result: CampaignResult,
    found: _Found,
    files: _RunFiles,
    base: Any,
    source: Path,
    *,
    note: Callable[[str], object] | None,
) -> str:
    """The report's notes: the runs finished, what MU and V are, the factors whose levels are
    not given low first, the run files that cannot be read or are missing, the runs that
    emitted nothing, the stops at the COF's floor (:func:`_floor_note`) and why a block
    cycle's runs have no PM10; the note on unreadable files also goes to ``note``."""
    summary, ok, surfaces = result.summary, found.ok, found.surfaces
    unreadable, filed = files.unreadable, files.filed
    runs_dir = source / "runs"
    n_failed = int((summary.get("status", pd.Series(dtype=str)) != "ok").sum())
    notes = (
        f"{len(ok)} of {len(summary)} runs finished"
        + (f"; {n_failed} failed (see the per-run table)" if n_failed else "")
        + ". MU is the mean over the stops of the time-weighted mean COF of each stop; V is the "
        "mean wear volume per stop that leaves the simulated band (not scaled to the pad"
        + _band_share(base)
        + "); "
        "log10_V_mm3 is V on a log scale (log10 of V in mm³), where the factors' "
        "multiplicative effects on V add, so that the interactions carry less of its variation "
        + (
            "(compare the residual plots and R²(pred) of the two surfaces). "
            if surfaces
            else "(compare the interactions' shares in the two ANOVA tables, the residual "
            "plots and R²(pred) of V and log10_V_mm3). "
        )
        + "MU_SD, the friction stability, is the standard deviation of the stops' mean COF "
        "about MU, a population one (divided by the number of stops, not one less): the "
        "lower, the steadier the friction over the cycle. It is not one of the paper's "
        "responses. It takes in the changes of the cycle's conditions from stop to stop (their "
        "speeds and pressures) as well as the friction's drift over time"
        + _block_share(result)
        + ", and a run held at the COF floor (friction.mu_min) is steady because the floor "
        "holds it, not its pad"
        + (
            ". "
            if "MU_SD" in found.tables
            else "; no run finished, so MU_SD is not analysed. "
            if found.ok.empty  # (not "one stop each": an analysis review)
            else "; no finished run has a spread over its stops (one stop each), so MU_SD is "
            "not analysed. "
        )
        + "The CSV tables in tables/ keep SI units: V in m³ there, not mm³ "
        "(tables/README.md lists them). "
        "Modelling decisions: docs/model.md."
    )
    for factor in result.design.factors:  # levels given high first: the effects' signs
        order = factor.order_note()
        if order is not None:
            notes += "\n\n" + order[:1].upper() + order[1:] + "."
    if unreadable:
        bad = ok.loc[ok["run_id"].isin(unreadable), "test"]
        text = (
            f"In {runs_dir}, the run file{'s' if len(bad) > 1 else ''} of "
            f"{tests_named(int(t) for t in bad)} cannot be read ("
            + "; ".join(unreadable.values())
            + "): the report leaves "
            + ("them" if len(bad) > 1 else "it")
            + f" out; 'brakeca run {source / 'design.toml'} -o {source}' computes "
            + ("those runs" if len(bad) > 1 else "the run")
            + " again."
        )
        notes += "\n\n" + text
        if note is not None:
            note(text)
    if len(filed) + len(unreadable) < len(ok):
        lost = ok.loc[~ok["run_id"].isin([*filed["run_id"], *unreadable]), "test"]
        which = (
            f"none of the {len(ok)} finished runs has its run file"
            if not len(filed)
            else f"{len(lost)} of the {len(ok)} finished runs "
            f"{'has' if len(lost) == 1 else 'have'} no run file (of "
            f"{tests_named(int(t) for t in lost)})"
        )
        text = (
            f"In {runs_dir}, {which}: the tables and the per-stop figures come from "
            "summary.csv and campaign.nc, but those runs' plateau maps (and PM10 on a speed "
            "trace) are not shown."
        )
        notes += "\n\n" + text
        if note is not None:  # on the terminal too, as an unreadable one (a robustness
            # review: only the report had said so)
            note(text)
    silent = ok.loc[pd.to_numeric(ok["V"], errors="coerce") <= 0, "test"] if "V" in ok else []
    if len(silent):  # (left out of the log scale's analysis without a word: an API review)
        notes += (
            f"\n\n{tests_named(int(t) for t in silent).capitalize()} emitted nothing (V = 0): "
            "log10_V_mm3 has no value there, so its analysis leaves "
            + (
                "that run out (the analysis of V keeps it)."
                if len(silent) == 1
                else "those runs out (the analysis of V keeps them)."
            )
        )
    floor_note = _floor_note(result, base)
    if floor_note:
        notes += "\n\n" + floor_note
    cycle = getattr(base, "cycle", None)
    if len(files.filed) and cycle is not None and not getattr(cycle, "trace_file", None):
        if not any(v is not None for v in files.pm10_of.values()):
            # said, not only left out (a report review: PM10 appeared nowhere, and nothing
            # said why)
            notes += (
                "\n\nNo brake PM10 in mg/km: the runs' drive cycle is a block cycle (as the "
                "paper's), which gives the stops but not the distance driven between them, so "
                "there is no emission per kilometre to give; a run on a speed trace gives one "
                "(docs/cycles.md)."
            )
    return notes


def plot_run(result: RunResult, folder: str | Path, name: str | None = None) -> list[Path]:
    """The figures of one run, as ``brakeca plot`` draws them.

    Parameters
    ----------
    result
        A run (``RunResult.from_netcdf`` reads a run file).
    folder
        Where the PNG files go (created).
    name
        What the run is, put first in the titles, e.g. ``"test 5"`` for a campaign's run.

    Returns
    -------
    list of Path
        ``mu_per_stop.png`` (the mean COF of each stop run, paper Figure 10 for
        one run), ``steps.png`` (the thinned per-step COF and pad normal force against the
        braking time [s]) and ``maps.png`` (the initial and final plateau maps); for a run
        that kept maps after chosen stops (``simulate(maps_at=)``, ``brakeca simulate
        --maps-at``) also ``maps_by_stop.png``, the map before the first stop and after each
        of those, one under the other.
    """
    from brakeca.plotting import plot_cof_series, plot_fibre_maps, plot_mu_per_stop

    if not isinstance(result, RunResult):  # a run file's path, say (an API review)
        raise _not_a("a RunResult", result, "brakeca.RunResult.from_netcdf(path) reads a run file")
    ds = result.dataset
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    about = f"seed {result.seed}, MU = {result.MU:.4f}, V = {result.V * 1e9:.4g} mm³ per stop"
    if name:
        about = f"{name}, {about}"
    paths = [out / "mu_per_stop.png", out / "steps.png", out / "maps.png"]
    plot_mu_per_stop(
        ds,
        paths[0],
        title=f"Mean coefficient of friction per stop, {ds.sizes['stop']} stops ({about})",
    )
    # the dataset's step series with its attributes: the title then says which of the
    # run's steps it shows (a plain dict gave "4,652 steps" for a run of 232,582)
    plot_cof_series(ds[["step_cof", "step_normal_force", "step_time"]], paths[1])
    radius, angle = ds["radius"].to_numpy(), ds["angle"].to_numpy()
    plot_fibre_maps(
        {
            "before the first stop": (ds["initial_status"].to_numpy(), radius, angle),
            "after the last stop": (ds["final_status"].to_numpy(), radius, angle),
        },
        paths[2],
        ncols=1,
    )
    if "map_status" in ds:
        paths.append(out / "maps_by_stop.png")
        plot_fibre_maps(_maps_over_cycle(ds), paths[-1], ncols=1)
    return paths


def _maps_over_cycle(ds: xr.Dataset) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """A run's plateau maps before the first stop and after each stop it kept a map of
    (``map_stop``), titled with the stop and its block: :func:`plotting.plot_fibre_maps`'s
    input (status [-], radius [m], angle [rad])."""
    radius, angle = ds["radius"].to_numpy(), ds["angle"].to_numpy()
    blocks = ds["block"].to_series() if "block" in ds.coords else None
    maps = {"before the first stop": (ds["initial_status"].to_numpy(), radius, angle)}
    for k in ds["map_stop"].to_numpy():
        where = f" ({blocks.loc[int(k)]})" if blocks is not None else ""
        status = ds["map_status"].sel(map_stop=k).to_numpy()
        maps[f"after stop {int(k)}{where}"] = (status, radius, angle)
    return maps


def campaign_runs_to_plot(campaign_dir: str | Path, tests: Sequence[int] = ()) -> pd.DataFrame:
    """The runs of a finished campaign whose figures ``brakeca plot FOLDER`` draws.

    Parameters
    ----------
    campaign_dir
        A campaign folder (``brakeca run -o``) with its ``summary.csv``.
    tests
        Test numbers [-] to draw; empty: every test.

    Returns
    -------
    pandas.DataFrame
        Rows of ``summary.csv`` for the selected tests, in test and replicate order,
        failed runs included (they have no run file to draw).

    Raises
    ------
    FileNotFoundError
        No such folder, not a campaign, or no ``summary.csv`` or ``campaign.nc`` yet.
    ValueError
        A test number the campaign does not have, or a folder :func:`load_campaign` refuses
        (a summary edited or damaged, a design edited after the runs).
    """
    from brakeca._consolidate import campaign_folder

    out = campaign_folder(campaign_dir)
    if not (out / "summary.csv").is_file():
        raise FileNotFoundError(
            f"{out / 'summary.csv'}: missing; the campaign has not finished: plot a run file "
            f"of {out / 'runs'} instead, or finish it with "
            f"'brakeca run {out / 'design.toml'} -o {out}'"
        )
    # the summary as an analysis reads it, checked against campaign.nc and the design (a
    # security review: a summary without a test or status column had ended plot with a
    # traceback, and one of a 400-digit test with an OverflowError)
    from brakeca.campaign import load_campaign

    summary = load_campaign(out).summary
    have = sorted({int(t) for t in summary["test"]})
    unknown = sorted({int(t) for t in tests} - set(have))
    if unknown:
        raise ValueError(
            f"--test {', '.join(map(str, unknown))}: the campaign has tests {have[0]} to {have[-1]}"
            if have == list(range(have[0], have[-1] + 1))
            else f"--test {', '.join(map(str, unknown))}: the campaign's tests are "
            f"{', '.join(map(str, have))}"
        )
    rows = summary if not tests else summary[summary["test"].isin([int(t) for t in tests])]
    keys = ["test", "replicate"] if "replicate" in rows.columns else ["test"]
    return rows.sort_values(keys).reset_index(drop=True)
