"""Statistical analysis of a factorial campaign: main effects, interactions, ANOVA.

Pure pandas / statsmodels; no plotting here (see :mod:`brakeca.plotting`).

The input is the campaign ``summary`` table, one row per run, with one column per factor
holding the level value in the design's user unit, a ``seed`` column (replicates share the
factor levels and differ in seed) and the responses, by default ``MU`` (mean coefficient of
friction [-]) and ``V`` (mean emitted wear volume per stop [m^3]). When a ``status`` column is
present only rows with ``status == "ok"`` are analysed. Rows whose response is missing or not
finite are left out of the analysis of that response.

Factors are treated as categorical throughout, as in the paper's full factorial design
(Tables 1 and 2): ``S`` (2 levels), ``WP`` (3 levels), ``WR`` (2 levels), ``A`` (2 levels).

Designs other than a full factorial (a fractional factorial, a run table made elsewhere) may
not separate every effect: a term whose columns are completely aliased (confounded) with
terms before it is left out of the model, with a note, and every term's ``aliases`` (the
terms of up to three factors it cannot be told apart from, Minitab's "Alias Structure") are
listed beside it. When every factor has two levels, :func:`two_level_effects` gives the
effects with their significance, from the residual of the fitted effects (the pure error of
replicates or centre points, the terms left out) or, where the model is saturated, from
Lenth's pseudo standard error, as Minitab's Pareto chart of standardized effects does.
Centre points add a test of curvature (:func:`anova`), and ``alpha_to_remove`` reduces the
model by backward elimination.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260 (main effects: Figures 6 and 8; interactions: Figures 7 and 9).
"""

from __future__ import annotations

import itertools
import math
import numbers
import os
import re
import warnings
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple, TypeGuard

import numpy as np
import pandas as pd

from brakeca._io import write_table

if TYPE_CHECKING:  # pragma: no cover
    from brakeca._consolidate import CampaignResult

__all__ = [
    "ANOVA_COLUMNS",
    "ANOVA_TYPES",
    "COEFFICIENT_COLUMNS",
    "COMPARISON_COLUMNS",
    "CONSTANT_TERM",
    "EFFECTS_COLUMNS",
    "MODEL_SUMMARY_COLUMNS",
    "RESIDUAL_COLUMNS",
    "TREND_COLUMNS",
    "UNUSUAL_COLUMNS",
    "UNUSUAL_RESIDUAL",
    "Factor",
    "Model",
    "ResponseAnalysis",
    "alias_structure",
    "analyze",
    "anova",
    "as_factor",
    "canonical_terms",
    "cube_means",
    "default_label",
    "display_unit",
    "factor_trends",
    "interaction_aliases",
    "interaction_table",
    "interaction_tables",
    "interactions_long",
    "level_coefficients",
    "level_comparisons",
    "main_effects",
    "model_matrix",
    "model_summary",
    "ok_runs",
    "ranked_effects",
    "residuals",
    "save_tables",
    "split_terms",
    "tukey_grouping",
    "two_level_effects",
    "unusual_runs",
]

#: A model's terms, as :func:`anova` and the functions beside it take them (``interactions``):
#: True (main effects and two-factor interactions), False (main effects), a whole number (the
#: terms up through that many factors) or a list of terms (``["S", "WP", "S*WP"]``, as
#: Minitab's Terms dialog picks them one by one).
Model = bool | int | Sequence[str]


@dataclass(frozen=True, eq=False)
class ResponseAnalysis(Mapping[str, Any]):
    """The analysis of one response (:func:`analyze`), table by table.

    Each table is an attribute, and also an item by its name (a read-only mapping, as
    :func:`analyze` returned a dict before this class: ``result["MU"]["anova"]`` is
    ``result["MU"].anova``, and :func:`save_tables` takes either). Code that changed that
    dict in place (``bundle["x"] = ...``, ``bundle.copy()``) makes its own,
    ``dict(bundle)``. The tables' values are in the response's units (MU
    [-], V [m^3 per stop], log10_V_mm3 [-]), the factors' levels in their design units.

    Attributes
    ----------
    main_effects : DataFrame
        Mean response at each level of each factor (:func:`main_effects`).
    interactions : dict of (str, str) to DataFrame
        Cell-mean table of each pair of factors (:func:`interaction_tables`).
    interactions_long : DataFrame
        The same cell means, one row per cell (:func:`interactions_long`).
    anova : DataFrame
        ANOVA table (:func:`anova`); its ``attrs`` hold the formula and the fit statistics.
    ranked_effects : DataFrame
        The ANOVA's terms ranked by sum of squares, for a Pareto chart (:func:`ranked_effects`).
    residuals : DataFrame
        Fitted values and residuals of each run (:func:`residuals`).
    effects : DataFrame
        Effects and coefficients of a two-level design (:func:`two_level_effects`); empty
        unless every factor has two levels.
    trends : DataFrame
        Linear and quadratic trends (:func:`factor_trends`); empty unless a factor has three
        levels or more.
    model_summary : DataFrame
        One row: S, R², adjusted and predicted R² of the ANOVA's fit (:func:`model_summary`).
    coefficients : DataFrame
        The model's coefficient at every level of its terms, with the regression equation
        in its ``attrs["equation"]`` (:func:`level_coefficients`): Minitab's table for a
        general factorial (a factor of three levels, the paper's WP).
    comparisons : DataFrame
        Tukey's pairwise comparisons of the levels of each factor of three levels or more
        (:func:`level_comparisons`); empty where there is none.
    unusual : DataFrame
        The runs the model fits badly, with their deleted residuals, outlier test and
        Cook's distances, and the ANOVA without them in its ``attrs["without"]``
        (:func:`unusual_runs`); empty where there is none.
    """

    main_effects: pd.DataFrame
    interactions: dict[tuple[str, str], pd.DataFrame]
    interactions_long: pd.DataFrame
    anova: pd.DataFrame
    ranked_effects: pd.DataFrame
    residuals: pd.DataFrame
    effects: pd.DataFrame
    trends: pd.DataFrame
    model_summary: pd.DataFrame
    coefficients: pd.DataFrame
    comparisons: pd.DataFrame
    unusual: pd.DataFrame

    def __getitem__(self, name: str) -> Any:
        if not isinstance(name, str) or name not in self._names():
            raise KeyError(name)
        return getattr(self, name)

    def __iter__(self) -> Iterator[str]:
        return iter(self._names())

    def __len__(self) -> int:
        return len(self._names())

    @classmethod
    def _names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    def __repr__(self) -> str:
        formula = self.anova.attrs.get("formula", "")
        shapes = ", ".join(
            f"{name}={len(value)} table{'' if len(value) == 1 else 's'}"
            if isinstance(value, dict)
            else f"{name}={value.shape[0]}x{value.shape[1]}"
            for name, value in ((n, getattr(self, n)) for n in self._names())
        )
        return f"ResponseAnalysis({formula!r}; {shapes})"


#: Columns of the table returned by :func:`anova`, in order.
ANOVA_COLUMNS: tuple[str, ...] = (
    "term",
    "df",
    "sum_sq",
    "mean_sq",
    "F",
    "p_value",
    "percent_contribution",
    "aliases",
    "note",
)

#: Relative tolerance used to match a value in the summary to one of a factor's levels.
_LEVEL_RTOL = 1e-6  # brakeca.design.LEVEL_RTOL (a test checks they agree)


_SUPERSCRIPTS = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def display_unit(unit: str) -> str:
    """A unit as text for people: powers as superscripts and, in a unit made of symbols,
    a product's space as a middle dot. The files keep the ASCII form (``m^3/(N m)``, as
    the configuration's field descriptions write it); the report and the plots show this.

    Parameters
    ----------
    unit
        A unit in brakeca's ASCII form, e.g. ``"m^3/(N m)"``, ``"1/MPa"``, ``"%"``.

    Returns
    -------
    str
        The same unit for display. A unit with a word (``per``, or four letters or more:
        ``"per cent"``) keeps its spaces, and a power that is not a whole number its caret.

    Examples
    --------
    >>> display_unit("m^3/(N m)")
    'm³/(N·m)'
    >>> display_unit("m^-1"), display_unit("%"), display_unit("mm^3 per stop")
    ('m⁻¹', '%', 'mm³ per stop')
    >>> display_unit("g per km"), display_unit("Pa m^0.5")
    ('g per km', 'Pa·m^0.5')
    """
    text = re.sub(
        r"(?<=[A-Za-zµ)])\^(-?\d+)(?![.\d])", lambda m: m.group(1).translate(_SUPERSCRIPTS), unit
    )
    if not re.search(r"[A-Za-z]{4,}|\bper\b", text):
        text = re.sub(r"(?<=[A-Za-zµ⁰¹²³⁴⁵⁶⁷⁸⁹)]) +(?=[A-Za-zµ(])", "·", text)
    return text


#: Units the figures show a factor's levels in, by the design's unit: each prefixed unit
#: with its size in the design's unit (:func:`shown_unit`).
_SHOWN_PREFIXES: dict[str, tuple[tuple[str, float], ...]] = {
    "m": (("m", 1.0), ("mm", 1e-3), ("µm", 1e-6), ("nm", 1e-9)),
    "Pa": (("Pa", 1.0), ("kPa", 1e3), ("MPa", 1e6), ("GPa", 1e9)),
}


def shown_unit(unit: str, levels: Iterable[float]) -> tuple[str, float]:
    """The unit to show ``levels`` [``unit``] in, and its size [``unit``]: for a length in
    m or a pressure in Pa, the largest of the unit and its prefixed units (mm, µm, nm; kPa,
    MPa, GPa) that puts the largest level's magnitude in [0.1, 1000), to round-off (1e-04 m
    as 0.1 mm, 1e-10 m as 0.1 nm); the unit itself where none does or every level is 0; any
    other unit as it is.

    Examples
    --------
    >>> shown_unit("m", (1e-7, 1e-6))
    ('µm', 1e-06)
    >>> shown_unit("Pa", (2e6, 1e7)), shown_unit("m", (0.5, 2.0)), shown_unit("%", (10, 20))
    (('MPa', 1000000.0), ('m', 1.0), ('%', 1.0))
    """
    largest = max((abs(float(v)) for v in levels), default=0.0)
    for name, size in _SHOWN_PREFIXES.get(unit.strip(), ()):
        if largest > 0 and 0.1 * (1.0 - 1e-9) <= largest / size < 1000.0:
            return name, size
    return unit, 1.0


@dataclass(frozen=True)
class Factor:
    """One factor of a factorial design, with its levels in the design's user unit.

    Parameters
    ----------
    name
        Short name, also the column name in the campaign summary (e.g. ``"WP"``).
    levels
        Level values [user unit], in design order (low first for two-level factors).
    unit
        Unit of the level values, e.g. ``"m^3/(N m)"``, ``"%"`` or ``"-"``.
    label
        Long, human-readable description, e.g. ``"Specific wear rate of plateaus"``.
    labels
        Optional level labels, one per level, e.g. ``("-", "0", "+")``.
    coding
        ``"linear"`` (default) or ``"log"``: where a two-level factor's centre point lies
        (:attr:`center`), the middle of its levels or their geometric mean.

    References
    ----------
    Wahlström (2016), Tables 1 and 2, doi:10.1155/2016/8181260.
    """

    name: str
    levels: tuple[float, ...]
    unit: str = ""
    label: str = ""
    labels: tuple[str, ...] | None = None
    coding: str = "linear"

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"factor name must be a non-empty string, got {self.name!r}")
        if self.coding not in ("linear", "log"):
            raise ValueError(
                f"factor {self.name!r}: coding must be 'linear' or 'log', got {self.coding!r}"
            )
        levels = tuple(float(v) for v in self.levels)
        if not levels:
            raise ValueError(f"factor {self.name!r}: needs at least one level")
        if not all(math.isfinite(v) for v in levels):
            raise ValueError(f"factor {self.name!r}: levels must be finite, got {levels}")
        for i, j in itertools.combinations(range(len(levels)), 2):
            if math.isclose(levels[i], levels[j], rel_tol=_LEVEL_RTOL, abs_tol=0.0):
                raise ValueError(f"factor {self.name!r}: duplicate levels {levels}")
        object.__setattr__(self, "levels", levels)
        if self.labels is not None:
            labels = tuple(str(s) for s in self.labels)
            if len(labels) != len(levels):
                raise ValueError(
                    f"factor {self.name!r}: {len(labels)} labels for {len(levels)} levels"
                )
            object.__setattr__(self, "labels", labels)

    def level_index(self, value: Any) -> int | None:
        """Return the index of the level matching ``value``, or None when none matches.

        Parameters
        ----------
        value
            A level value [user unit]; matched with a relative tolerance of 1e-6.

        Returns
        -------
        int or None
            Position in :attr:`levels`.
        """
        try:
            x = float(value)
        except (TypeError, ValueError):
            return None
        for i, level in enumerate(self.levels):
            if math.isclose(x, level, rel_tol=_LEVEL_RTOL, abs_tol=0.0):
                return i
        return None

    def level_label(self, value: Any) -> str:
        """Return the label of the level ``value`` (e.g. ``"+"``), or the value formatted.

        Parameters
        ----------
        value
            A level value [user unit].

        Returns
        -------
        str
            The level's label when :attr:`labels` is set and ``value`` matches a level,
            ``"0"`` (Minitab's code of the centre) when it is the labelled factor's centre
            point (:attr:`center`), otherwise ``value`` in ``%g`` format.
        """
        i = self.level_index(value)
        if i is not None and self.labels is not None:
            return self.labels[i]
        centre = self.center
        if self.labels is not None and centre is not None:
            try:
                if math.isclose(float(value), centre, rel_tol=_LEVEL_RTOL, abs_tol=0.0):
                    return "0"
            except (TypeError, ValueError):
                pass
        try:
            return f"{float(value):g}"
        except (TypeError, ValueError):
            return str(value)

    @property
    def center(self) -> float | None:
        """The level of a centre point [user unit]: the middle of a two-level factor's
        levels, their geometric mean with ``coding = "log"`` (as
        :meth:`brakeca.design.Design.center_levels`); None for any other factor."""
        if len(self.levels) != 2:
            return None
        low, high = min(self.levels), max(self.levels)
        if self.coding == "log":
            if low <= 0:
                return None
            return float(10.0 ** ((math.log10(low) + math.log10(high)) / 2.0))
        return (low + high) / 2.0

    @property
    def shown_unit(self) -> tuple[str, float]:
        """The unit the figures show the levels in, and its size [design unit]: a length in
        m or a pressure in Pa with the SI prefix that puts the largest level between 0.1
        and 1000 (WR's levels of 1e-07 and 1e-06 m as 0.1 and 1 µm: friendly units at the
        edges), any other unit as it is, with size 1 (:func:`shown_unit`)."""
        return shown_unit(self.unit, self.levels)

    def shown(self, value: Any) -> str:
        """A level [design unit] as the figures write it, in :attr:`shown_unit`:
        ``"0.1"`` for WR = 1e-07 m (µm), ``"20"`` for A = 20 %."""
        return f"{float(value) / self.shown_unit[1]:g}"

    @property
    def axis_label(self) -> str:
        """Name with unit for plot axes, e.g. ``"WP [m³/(N·m)]"``, ``"WR [µm]"``
        (:attr:`shown_unit`, :func:`display_unit`): the unit of :meth:`shown`'s levels."""
        unit = self.shown_unit[0]
        return f"{self.name} [{display_unit(unit)}]" if unit else self.name


def default_label(field: Any) -> str:
    """The label of a design's factor that gives none, from the configuration ``field`` it
    sets (a dotted field or a factor alias, ``"WR"``): the paper's description of one of its
    factors' fields (:data:`brakeca.config.PAPER_FACTOR_LABELS`), else ``""`` (a design's
    own factors had gone by their bare names in the figures' titles: a review).

    Examples
    --------
    >>> default_label("WR"), default_label("wear.specific_wear_rate")
    ('Resin wear depth', 'Specific wear rate of plateaus')
    >>> default_label("contact.elastic_modulus"), default_label(None)
    ('', '')
    """
    from brakeca.config import FACTOR_ALIASES, PAPER_FACTOR_LABELS

    if not isinstance(field, str):
        return ""
    target = FACTOR_ALIASES[field][0] if field in FACTOR_ALIASES else field
    return PAPER_FACTOR_LABELS.get(target, "")


def as_factor(obj: Any) -> Factor:
    """Convert a factor-like object or mapping to a :class:`Factor`.

    Parameters
    ----------
    obj
        A :class:`Factor`, a mapping or any object with ``name`` and ``levels`` (and optionally
        ``unit``, ``label``, ``labels``, ``field``), e.g. a design entry loaded from TOML;
        without a label, one of a field of the paper's factors gets the paper's
        (:func:`default_label`).

    Returns
    -------
    Factor
    """
    if isinstance(obj, Factor):
        return obj
    if isinstance(obj, Mapping):
        get = obj.get
    else:

        def get(key: str, default: Any = None) -> Any:
            return getattr(obj, key, default)

    name = get("name")
    levels = get("levels")
    if name is None or levels is None:
        raise TypeError(f"not a factor (needs 'name' and 'levels'): {obj!r}")
    labels = get("labels")
    return Factor(
        name=str(name),
        levels=tuple(levels),
        unit=str(get("unit", "") or ""),
        label=str(get("label", "") or "") or default_label(get("field")),
        labels=None if labels is None else tuple(labels),
        coding=str(get("coding", "linear") or "linear"),
    )


# --- helpers ---------------------------------------------------------------------------------


def ok_runs(summary: pd.DataFrame) -> pd.DataFrame:
    """Return the rows of ``summary`` that finished, i.e. ``status == "ok"``.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.

    Returns
    -------
    pandas.DataFrame
        A copy holding the rows with status ``"ok"``, or all rows when there is no
        ``status`` column.
    """
    if "status" in summary.columns:
        mask = summary["status"].astype(str).str.strip().str.lower() == "ok"
        return summary.loc[mask].copy()
    return summary.copy()


def _design_factors(factors: Any) -> list[Any]:
    """The factors given, as a list: a :class:`brakeca.design.Design` (or a campaign result)
    stands for its design's factors (iterating a design gives its fields); shared with
    :mod:`brakeca.rsm`."""
    design = getattr(factors, "design", None)  # a CampaignResult
    if design is not None and hasattr(design, "factor_names"):
        factors = design
    if hasattr(factors, "factor_names"):  # a Design
        return list(factors.factors)
    return list(factors)


def _factors(factors: Iterable[Any]) -> list[Factor]:
    """The factors as :class:`Factor` objects: factor-likes (:func:`as_factor`), or a
    :class:`brakeca.design.Design` or campaign result for its design's factors. Names alone
    are refused: the levels come from the design, not from the runs' values (a centre
    point's value is no level)."""
    factors = [factors] if isinstance(factors, str) else _design_factors(factors)
    names = [f for f in factors if isinstance(f, str)]
    if names:
        are = "is a name" if len(names) == 1 else "are names"
        raise TypeError(
            f"factors: {', '.join(map(repr, names))} {are}; "
            "the analysis needs each factor's levels: pass the design (or a campaign result), "
            "or brakeca.analysis.Factor(name, levels) for each"
        )
    out = [as_factor(f) for f in factors]
    names = [f.name for f in out]
    if len(set(names)) != len(names):
        raise ValueError(f"duplicate factor names: {names}")
    return out


def _is_campaign(obj: Any) -> bool:
    """Whether ``obj`` is a campaign result (:func:`brakeca.load_campaign`): a summary
    and a design."""
    return (
        not isinstance(obj, pd.DataFrame)
        and hasattr(obj, "summary")
        and hasattr(getattr(obj, "design", None), "factor_names")
    )


def _campaign_parts(
    summary: Any, factors: Any = (), *, optional: bool = False
) -> tuple[pd.DataFrame, Any]:
    """(summary table, factors) of a table function's first two arguments: a campaign result
    given as the summary stands for its summary and, where ``factors`` is None, for its
    design's factors (an API review: only :func:`analyze` took a campaign, the others
    failed with "'NoneType' object is not iterable"). ``factors`` None beside a table is
    refused, naming what to give, unless they are ``optional`` (a figure that can do
    without them). A campaign's summary gets ``log10_V_mm3`` where it has none."""
    if _is_campaign(summary):
        rows = summary.summary
        if "log10_V_mm3" not in rows.columns and "V" in rows.columns:
            # the log scale of V, as analyze gives it (a table or figure of a campaign had
            # said it was no column: an API review)
            from brakeca.study import with_log_v

            rows = with_log_v(rows)
        return rows, (summary if factors is None else factors)
    if factors is None and not optional:
        raise TypeError(
            "factors: give the design's factors (or the design), or a campaign result as "
            "the first argument (brakeca.load_campaign(folder) reads one)"
        )
    return summary, factors


def _design_of(factors: Any) -> Any | None:
    """The design behind ``factors`` where it is a :class:`brakeca.design.Design` or a
    campaign result, else None."""
    if hasattr(factors, "anova_model"):
        return factors
    design = getattr(factors, "design", None)
    return design if hasattr(design, "anova_model") else None


def _model_settings(
    factors: Any, interactions: Model | None, typ: int | str | None, alpha_to_remove: float | None
) -> tuple[Model, Any, float | None]:
    """The model, the ANOVA's type (as given where it is not 'II' or 'III', for the caller's
    check: :func:`_check_anova_type`) and the level of backward elimination a table fits: each
    left unset (None) is the design's where ``factors`` is a design or a campaign result, as
    :func:`analyze` and the report take them (an API review found ``anova(summary, design,
    "MU")`` a Type II, unreduced fit beside the report's Type III, reduced one); otherwise
    all two-factor interactions, Type II and the whole model."""
    if isinstance(typ, str) and typ in ("II", "III"):  # statsmodels' anova_lm spells them so
        typ = len(typ)
    design = _design_of(factors)
    if design is not None:
        if interactions is None:
            chosen = design.anova_model
            interactions = chosen if isinstance(chosen, int) else list(chosen)
        if typ is None:
            typ = design.anova_type
        if alpha_to_remove is None and not design.is_response_surface:
            alpha_to_remove = design.alpha_to_remove
    return (
        (True if interactions is None else interactions),
        (2 if typ is None else typ),
        (alpha_to_remove),
    )


def _clean(summary: pd.DataFrame, factors: Sequence[Any], response: str) -> pd.DataFrame:
    """Rows usable for ``response``: status ok, response finite, factor columns present
    (``factors``: anything with a ``name``, e.g. :class:`Factor` or
    :class:`brakeca.rsm.Coding`). Selected by position, so a repeated index label is fine."""
    if response not in summary.columns:
        hint = ""
        if response == "log10_V_mm3" and "V_mm3" in summary.columns:
            hint = "; brakeca.study.with_log_v(summary) adds it"
        elif response == "MU_SD":  # a summary.csv written before the friction stability
            hint = (
                "; a campaign written before MU_SD has none in its summary.csv: "
                "brakeca.load_campaign(folder) computes it from campaign.nc"
            )
        else:
            near = [c for c in summary.columns if str(c).lower() == response.lower()]
            hint = f"; did you mean {near[0]!r}?" if near else ""
        raise KeyError(f"response {response!r} is not a column of the summary{hint}")
    missing = [f.name for f in factors if f.name not in summary.columns]
    if missing:
        raise KeyError(f"factor column(s) {missing} not in the summary")
    data = ok_runs(summary)
    y = pd.to_numeric(data[response], errors="coerce").to_numpy(dtype=float)
    finite = np.isfinite(y)
    data = data.loc[finite].copy()
    data[response] = y[finite]
    return data


def _not_finite(summary: pd.DataFrame, response: str) -> str:
    """A note naming the finished runs :func:`_clean` leaves out because ``response`` is not
    a finite number (a NaN, or ``log10_V_mm3`` of a run that emitted nothing), by test
    (and replicate) where the summary has them, by row otherwise; "" for none."""
    data = ok_runs(summary)
    if response not in data.columns:
        return ""
    y = pd.to_numeric(data[response], errors="coerce").to_numpy(dtype=float)
    bad = data.loc[~np.isfinite(y)]
    if bad.empty:
        return ""
    if "test" in bad.columns:
        from brakeca._console import is_replicated  # (rich, kept out of this module's import)

        replicated = is_replicated(data)
        names = [
            f"test {row.test}" + (f" replicate {row.replicate}" if replicated else "")
            for row in bad.itertuples()
        ]
    else:
        names = [f"row {i}" for i in bad.index]
    shown = ", ".join(names[:10]) + (f" and {len(names) - 10} more" if len(names) > 10 else "")
    return f"{len(names)} finished run(s) left out, {response} not a finite number: {shown}"


def _center_mask(data: pd.DataFrame, factors: Sequence[Factor]) -> np.ndarray:
    """Which rows of ``data`` are centre points: every factor at its :attr:`Factor.center`
    (none unless every factor has two levels)."""
    mask = np.full(len(data), bool(factors))
    for f in factors:
        centre = f.center
        if centre is None:
            return np.zeros(len(data), dtype=bool)
        values = pd.to_numeric(data[f.name], errors="coerce").to_numpy(dtype=float)
        mask &= np.isclose(values, centre, rtol=_LEVEL_RTOL, atol=0.0)
    return mask


def _cube(data: pd.DataFrame, factors: Sequence[Factor]) -> pd.DataFrame:
    """``data`` without its centre points (:func:`_center_mask`): the rows at the factors'
    levels, which level means, cell means and effects are taken over."""
    return data.loc[~_center_mask(data, factors)]


def _with_centre_rows(x: np.ndarray, n_c: int, *, indicator: bool = True) -> np.ndarray:
    """The model matrix ``x`` [-] of the runs at the factors' levels (its first column the
    intercept) followed by ``n_c`` centre points' rows: 1 in the intercept and 0 in every
    other column (a factor coded -1/+1 is 0 midway), and with ``indicator`` a last column
    that is 1 on the centre points alone (Minitab's "Ct Pt"), which fits their mean."""
    centre = np.zeros((n_c, x.shape[1]))
    centre[:, 0] = 1.0
    out = np.vstack([x, centre])
    if indicator:
        out = np.column_stack([out, np.r_[np.zeros(len(x)), np.ones(n_c)]])
    return out


def _codes(data: pd.DataFrame, factor: Factor) -> np.ndarray:
    """Level index of every row for ``factor``; raises on values that match no level."""
    values = data[factor.name].to_list()
    codes = np.array([factor.level_index(v) for v in values], dtype=object)
    bad = [v for v, c in zip(values, codes, strict=True) if c is None]
    if bad:
        raise ValueError(
            f"factor {factor.name!r}: value(s) {sorted(set(map(str, bad)))} match none of the "
            f"levels {factor.levels}"
        )
    return codes.astype(int)


def _factor_from_data(summary: pd.DataFrame, name: str) -> Factor:
    if name not in summary.columns:  # (a bare KeyError: 'B', an API review)
        raise KeyError(
            f"factor {name!r} is not a column of the summary; its columns: "
            + ", ".join(str(c) for c in summary.columns)
        )
    values = pd.to_numeric(ok_runs(summary)[name], errors="coerce").dropna().unique()
    return Factor(name=name, levels=tuple(sorted(float(v) for v in values)))


def _resolve(summary: pd.DataFrame, factor: Factor | str | Any) -> Factor:
    if isinstance(factor, str):
        return _factor_from_data(summary, factor)
    return as_factor(factor)


# --- level means -----------------------------------------------------------------------------


def main_effects(
    summary: pd.DataFrame | CampaignResult, factors: Iterable[Any] | None, response: str
) -> pd.DataFrame:
    """Level means of a response for every factor (main-effects table).

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors (:class:`Factor` or factor-like objects).
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].

    Returns
    -------
    pandas.DataFrame
        Columns ``factor``, ``level`` [user unit], ``label``, ``mean`` [response unit] and
        ``n`` (number of runs averaged); one row per factor level in design order. A level
        without any usable run has ``n = 0`` and ``mean = NaN``. Centre points (every
        factor at its :attr:`Factor.center`) are in no level's mean: ``attrs`` carries their
        mean ``center_mean`` [response unit] and number ``center_n`` (NaN and 0 without).

    References
    ----------
    Wahlström (2016), Figures 6 (MU) and 8 (V), doi:10.1155/2016/8181260.

    Examples
    --------
    A replicated 2² design (8 runs) whose MU has known effects: S +0.05, A +0.11 and their
    interaction +0.02 (effects as Minitab gives them: the change from the low to the high level):

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor
    >>> factors = [Factor("S", (0.0, 1.0)), Factor("A", (10.0, 20.0), unit="%")]
    >>> runs = pd.DataFrame({
    ...     "S": [0.0, 1.0] * 4,
    ...     "A": [10.0, 10.0, 20.0, 20.0] * 2,
    ...     "MU": [0.30, 0.34, 0.40, 0.46, 0.32, 0.34, 0.40, 0.48],
    ... })
    >>> from brakeca.analysis import main_effects
    >>> table = main_effects(runs, factors, "MU")
    >>> print(table[["factor", "level", "mean", "n"]].round(4).to_string(index=False))
    factor  level  mean  n
         S    0.0 0.355  4
         S    1.0 0.405  4
         A   10.0 0.325  4
         A   20.0 0.435  4
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)
    data = _clean(summary, factors, response)
    centre = _center_mask(data, factors)
    at_centre = data.loc[centre, response].to_numpy(dtype=float)
    data = data.loc[~centre]
    y = data[response].to_numpy(dtype=float)
    rows = []
    for f in factors:
        codes = _codes(data, f)
        for i, level in enumerate(f.levels):
            sel = y[codes == i]
            rows.append(
                {
                    "factor": f.name,
                    "level": level,
                    "label": f.level_label(level),
                    "mean": float(sel.mean()) if sel.size else math.nan,
                    "n": int(sel.size),
                }
            )
    out = pd.DataFrame(rows, columns=["factor", "level", "label", "mean", "n"])
    out = out.astype({"level": float, "mean": float, "n": int})
    out.attrs.update(
        center_mean=float(at_centre.mean()) if at_centre.size else math.nan,
        center_n=int(at_centre.size),
    )
    return out


def _cell_stats(
    data: pd.DataFrame, a: Factor, b: Factor, response: str
) -> tuple[np.ndarray, np.ndarray]:
    ca = _codes(data, a)
    cb = _codes(data, b)
    y = data[response].to_numpy(dtype=float)
    sums = np.zeros((len(a.levels), len(b.levels)))
    counts = np.zeros((len(a.levels), len(b.levels)), dtype=int)
    np.add.at(sums, (ca, cb), y)
    np.add.at(counts, (ca, cb), 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        means = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    return means, counts


def interaction_table(
    summary: pd.DataFrame | CampaignResult,
    factor_a: Factor | str,
    factor_b: Factor | str,
    response: str,
) -> pd.DataFrame:
    """Cell means of a response for a pair of factors (two-way interaction table).

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary.
    factor_a, factor_b
        The two factors (:class:`Factor`, factor-like object, or a column name, in which case
        the levels are the sorted distinct values found in the summary: a design's centre
        points are then a level of their own; give the design's factors to leave them out).
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].

    Returns
    -------
    pandas.DataFrame
        Means [response unit]; index = levels of ``factor_a`` (named after it), columns =
        levels of ``factor_b`` (named after it). Empty cells are NaN.

    References
    ----------
    Wahlström (2016), Figures 7 (MU) and 9 (V), doi:10.1155/2016/8181260.
    """
    summary = _campaign_parts(summary)[0]  # a campaign result: its summary
    a = _resolve(summary, factor_a)
    b = _resolve(summary, factor_b)
    if a.name == b.name:
        raise ValueError(f"interaction of {a.name!r} with itself")
    data = _cube(_clean(summary, [a, b], response), [a, b])
    means, _ = _cell_stats(data, a, b, response)
    return pd.DataFrame(
        means,
        index=pd.Index(a.levels, name=a.name),
        columns=pd.Index(b.levels, name=b.name),
    )


def _cube_level_order(factor: Any) -> tuple[int, int]:
    """A two-level factor's level indices along its cube edge, the lower value first (as
    Minitab draws a cube), whichever order the design lists them in [-]."""
    return (0, 1) if float(factor.levels[0]) <= float(factor.levels[1]) else (1, 0)


def cube_means(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    names: Sequence[str] | None = None,
) -> pd.DataFrame:
    """The mean response at each corner of two or three two-level factors, over the other
    factors' levels (Minitab's cube plot of data means; :func:`brakeca.plotting.plot_cube`
    draws it).

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite
        response are used). Or a campaign result: its summary, and its design where
        ``factors`` is None.
    factors
        The design's factors (or the design, or a campaign result); centre points (every
        factor at its centre) are in no corner.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    names
        The two or three factors of the cube, each of two levels, in the order of its axes
        (horizontal, vertical, depth). By default the (up to) three two-level factors with
        the largest main effects on ``response`` (the difference of their level means), in
        the design's order.

    Returns
    -------
    pandas.DataFrame
        One row per corner, the first factor's level changing fastest and each factor's
        low level first (the design may list it second): a column per factor of the cube
        (its level, in the design's unit), ``mean`` [response unit] (NaN at a corner
        no run reaches, as in a fraction) and ``n``, the runs averaged there. ``attrs``
        ``factors``: the cube's factor names.

    Raises
    ------
    ValueError
        Fewer than two two-level factors, ``names`` that are not two or three of them, or no
        finished run to choose the factors by.

    Examples
    --------
    >>> import pandas as pd
    >>> from brakeca.analysis import Factor, cube_means
    >>> runs = pd.DataFrame({
    ...     "S": [0, 1, 0, 1, 0, 1, 0, 1], "A": [10, 10, 20, 20, 10, 10, 20, 20],
    ...     "WR": [1, 1, 1, 1, 2, 2, 2, 2],
    ...     "MU": [0.30, 0.34, 0.40, 0.46, 0.32, 0.34, 0.40, 0.48],
    ... })
    >>> factors = [Factor("S", [0, 1]), Factor("A", [10, 20]), Factor("WR", [1, 2])]
    >>> cube_means(runs, factors, "MU", names=["S", "A"])
         S     A  mean  n
    0  0.0  10.0  0.31  2
    1  1.0  10.0  0.34  2
    2  0.0  20.0  0.40  2
    3  1.0  20.0  0.47  2
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)
    by_name = {f.name: f for f in factors}
    two_level = [f.name for f in factors if len(f.levels) == 2]
    data = _clean(summary, factors, response)
    data = data.loc[~_center_mask(data, factors)]
    if names is None:
        if not len(data):  # the default pick would read NaN spreads as a choice
            raise ValueError(
                f"no finished run with a finite {response} to take the cube's means of"
            )
        if len(two_level) < 2:
            raise ValueError(
                f"a cube needs two or three factors of two levels; this design has "
                f"{len(two_level)} ({', '.join(two_level) or 'none'})"
            )
        table = main_effects(data, factors, response)
        spread = {
            name: abs(float(np.ptp(table.loc[table["factor"] == name, "mean"])))
            for name in two_level
        }
        chosen = sorted(two_level, key=lambda n: -np.nan_to_num(spread[n], nan=-1.0))[:3]
        names = [n for n in two_level if n in chosen]  # the design's order
    names = list(names)
    unknown = [n for n in names if n not in by_name]
    if unknown:
        raise ValueError(f"names: {unknown} not factors of the design ({', '.join(by_name)})")
    if not 2 <= len(names) <= 3 or len(set(names)) != len(names):
        raise ValueError(f"names: two or three different factors, got {names}")
    wide = [n for n in names if len(by_name[n].levels) != 2]
    if wide:
        raise ValueError(f"names: {wide} not of two levels; a cube's factors have two each")
    cube = [by_name[n] for n in names]
    codes = np.column_stack([_codes(data, f) for f in cube])  # (0, k) without a run
    y = data[response].to_numpy(dtype=float)
    rows = []
    low_first = [_cube_level_order(f) for f in cube]
    for corner in itertools.product((0, 1), repeat=len(cube)):
        code = [order[c] for order, c in zip(low_first, corner[::-1], strict=True)]
        at = np.all(codes == np.array(code), axis=1)
        row: dict[str, Any] = {f.name: f.levels[c] for f, c in zip(cube, code, strict=True)}
        row.update(mean=float(y[at].mean()) if at.any() else math.nan, n=int(at.sum()))
        rows.append(row)
    out = pd.DataFrame(rows, columns=[*names, "mean", "n"]).astype({"mean": float, "n": int})
    out = out.astype({n: float for n in names})
    out.attrs["factors"] = tuple(names)
    return out


def interaction_tables(
    summary: pd.DataFrame | CampaignResult, factors: Iterable[Any] | None, response: str
) -> dict[tuple[str, str], pd.DataFrame]:
    """Interaction tables (see :func:`interaction_table`) for every pair of factors.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors; pairs are taken in design order.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].

    Returns
    -------
    dict
        ``{(name_a, name_b): table}`` for every pair ``a`` before ``b`` in ``factors``.
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)
    return {
        (a.name, b.name): interaction_table(summary, a, b, response)
        for a, b in itertools.combinations(factors, 2)
    }


def interactions_long(
    summary: pd.DataFrame | CampaignResult, factors: Iterable[Any] | None, response: str
) -> pd.DataFrame:
    """All two-way cell means in long form (one row per cell of every factor pair).

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].

    Returns
    -------
    pandas.DataFrame
        Columns ``factor_a``, ``level_a``, ``label_a``, ``factor_b``, ``level_b``,
        ``label_b``, ``mean`` [response unit], ``n``.
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)
    data = _cube(_clean(summary, factors, response), factors)
    rows = []
    for a, b in itertools.combinations(factors, 2):
        means, counts = _cell_stats(data, a, b, response)
        for i, la in enumerate(a.levels):
            for j, lb in enumerate(b.levels):
                rows.append(
                    {
                        "factor_a": a.name,
                        "level_a": la,
                        "label_a": a.level_label(la),
                        "factor_b": b.name,
                        "level_b": lb,
                        "label_b": b.level_label(lb),
                        "mean": float(means[i, j]),
                        "n": int(counts[i, j]),
                    }
                )
    columns = ["factor_a", "level_a", "label_a", "factor_b", "level_b", "label_b", "mean", "n"]
    return pd.DataFrame(rows, columns=columns)


# --- ANOVA -----------------------------------------------------------------------------------


def _empty_anova(note: str) -> pd.DataFrame:
    out = pd.DataFrame({c: pd.Series(dtype=float) for c in ANOVA_COLUMNS})
    out = out.astype({"term": object, "note": object})
    out.attrs["note"] = note
    return out


def _ols(frame: pd.DataFrame, terms: Sequence[str]) -> Any:
    """Ordinary least squares of ``y`` on ``terms`` (intercept only when empty)."""
    from statsmodels.formula.api import ols

    return ols("y ~ " + (" + ".join(terms) if terms else "1"), data=frame).fit()


def _sequential_table(frame: pd.DataFrame, terms: Sequence[str], fit: Any) -> pd.DataFrame:
    """Type I (sequential) ANOVA from nested fits; df from rank differences, so it also
    holds for rank-deficient designs (empty cells), where ``anova_lm`` can fail."""
    from scipy import stats

    rows = []
    previous = _ols(frame, [])
    for k, term in enumerate(terms):
        current = _ols(frame, terms[: k + 1])
        rows.append(
            (
                term,
                float(round(previous.df_resid - current.df_resid)),
                max(float(previous.ssr - current.ssr), 0.0),
            )
        )
        previous = current
    df_resid, ssr = float(fit.df_resid), float(fit.ssr)
    table = pd.DataFrame(rows, columns=["term", "df", "sum_sq"]).set_index("term")
    mean_resid = ssr / df_resid if df_resid > 0 else np.nan
    table["F"] = (table["sum_sq"] / table["df"].where(table["df"] > 0)) / mean_resid
    table["PR(>F)"] = stats.f.sf(table["F"], table["df"], df_resid)
    table.loc["Residual"] = [df_resid, ssr, np.nan, np.nan]
    return table


def _column_table(frame: pd.DataFrame, terms: Sequence[str], fit: Any, *, typ: int) -> pd.DataFrame:
    """Type II or Type III ANOVA from the terms' columns: each term's sum of squares is the
    rise of the residual sum of squares when its columns leave a model, with every factor in
    deviation (sum-to-zero) coding (:func:`_term_columns`); its df is its number of columns.
    Type III (adjusted, ``typ=3``): the term leaves the full model, as Minitab's "Adjusted
    SS" and JMP's effect tests. Type II (``typ=2``): the term leaves the model of every term
    that does not contain it, which is what :func:`statsmodels.stats.anova.anova_lm` gives
    (used here where that cannot run: no residual degrees of freedom). Needs a full-rank
    model matrix; F and p are taken against ``fit``'s residual (NaN without one)."""
    from scipy import stats

    y = frame["y"].to_numpy(dtype=float)
    blocks = {t: _term_columns(frame, t) for t in terms}

    def ssr(names: Sequence[str]) -> float:
        return _sse(np.hstack([np.ones((y.size, 1)), *(blocks[t] for t in names)]), y)

    full = ssr(terms)
    rows = []
    for term in terms:
        if typ == 3:
            without, within = [t for t in terms if t != term], full
        else:
            parts = set(term.split(":"))
            without = [t for t in terms if not parts <= set(t.split(":"))]
            within = ssr([*without, term])
        rows.append((term, float(blocks[term].shape[1]), max(ssr(without) - within, 0.0)))
    df_resid = float(fit.df_resid)
    table = pd.DataFrame(rows, columns=["term", "df", "sum_sq"]).set_index("term")
    table = table.astype(float)  # also when no term is left (a reduced model)
    mean_resid = float(fit.ssr) / df_resid if df_resid > 0.5 else np.nan
    table["F"] = (table["sum_sq"] / table["df"]) / mean_resid
    table["PR(>F)"] = stats.f.sf(table["F"], table["df"], df_resid)
    table.loc["Residual"] = [df_resid, float(fit.ssr), np.nan, np.nan]
    return table


#: The sums of squares :func:`anova` can give: ``typ`` [-] and its name in the table.
ANOVA_TYPES: dict[int, str] = {2: "Type II", 3: "Type III (adjusted)"}


def _fit_anova(
    frame: pd.DataFrame, terms: Sequence[str], *, check_only: bool = False, typ: int = 2
) -> tuple[Any, pd.DataFrame | None, str, list[str]]:
    """Fit OLS on ``frame`` (column ``y``); return (fit, ANOVA table, type, messages).

    Type II sums of squares from :func:`statsmodels.stats.anova.anova_lm` (``typ=2``; from
    :func:`_column_table` without residual degrees of freedom) or adjusted Type III ones
    (``typ=3``, :func:`_column_table`) for a full-rank design;
    sequential (Type I) sums of squares from nested fits when the design matrix is
    rank-deficient (empty cells) or the table cannot be computed. With ``check_only`` only
    the fit is made (table None).
    """
    from statsmodels.stats.anova import anova_lm

    with warnings.catch_warnings(record=True) as caught, np.errstate(all="ignore"):
        # A perfect fit (zero residual) or a saturated model divides by zero in F, and a
        # constant response makes the constraint covariance singular; those cases are
        # reported in the table and its note, not as warnings.
        warnings.simplefilter("always")
        fit = _ols(frame, terms)
        table = None
        kind = ANOVA_TYPES[typ]
        if not check_only:
            exog = fit.model.exog
            full_rank = np.linalg.matrix_rank(exog) == exog.shape[1]
            if full_rank:
                try:
                    if typ == 2 and fit.df_resid >= 0.5:
                        table = anova_lm(fit, typ=2)
                        if table.drop(index="Residual")["sum_sq"].isna().any():
                            # an exact fit (no residual): anova_lm's Wald tests divide by a
                            # zero scale; the nested fits give the same Type II sums
                            table = _column_table(frame, terms, fit, typ=2)
                            caught[:] = [w for w in caught if "full rank" not in str(w.message)]
                    else:  # anova_lm cannot run without residual degrees of freedom
                        table = _column_table(frame, terms, fit, typ=typ)
                except (ValueError, np.linalg.LinAlgError):
                    table = None
            if table is None:
                table = _sequential_table(frame, terms, fit)
                name = kind.split(" (")[0]
                if not full_rank:
                    why = "the design is rank-deficient, e.g. empty cells"
                else:
                    why = f"{name} could not be computed"
                kind = f"Type I (sequential; {why})"
    messages = sorted(
        {
            f"statsmodels: {w.message}"
            for w in caught
            if not issubclass(w.category, RuntimeWarning) and "rank-deficient" not in str(w.message)
        }
    )
    if kind.startswith("Type I "):
        messages.append(
            "sums of squares are sequential (Type I): they depend on the order of the terms"
        )
    return fit, table, kind, messages


def anova(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
    typ: int | str | None = None,
    alpha_to_remove: float | None = None,
) -> pd.DataFrame:
    """Analysis of variance of a response over categorical factors.

    Fits ``y ~ C(f1) + C(f2) + ... + C(f1):C(f2) + ...`` (main effects and, when
    ``interactions`` is true, all two-factor interactions; or up to the order it gives) by
    ordinary least squares with
    :func:`statsmodels.formula.api.ols` and tabulates it with **Type II** sums of squares
    (:func:`statsmodels.stats.anova.anova_lm`; ``typ=2``, the default) or **Type III**
    (adjusted) ones (``typ=3``): each term's rise in the residual sum of squares when it alone
    leaves the full model, the factors in sum-to-zero coding, as Minitab's "Adjusted SS" and
    JMP's effect tests. For a balanced (orthogonal) design such as the paper's full factorial,
    Type I, II, III and the classical hand-computed sums of squares coincide, and the sums of
    squares of all terms plus the residual add up to the total sum of squares about the mean.
    They differ once the design is unbalanced (a failed run): Type II adjusts each term for
    the others but not for the interactions that contain it, Type III for every other term.
    With Type III a two-level term's F equals the square of its coefficient's t in
    :func:`two_level_effects` only where that table fits the same terms as the ANOVA (e.g.
    two factors and their interaction): it may also keep interactions of three factors, which
    the ANOVA leaves in the residual, or leave out partly confounded ones. The column
    ``percent_contribution`` is each term's sum of squares of the table's type over the total;
    in an unbalanced design it then need not add up to 100 %, and differs from Minitab's
    "Contribution", which takes the sequential sums of squares.

    The residual is what the model does not explain: with replicates (several seeds per
    factor-level combination) it contains the pure error (run-to-run scatter from the random
    fibre layout and automaton), plus the higher-order interactions that are not in the model;
    when the model holds every cell (e.g. two factors with their interaction) it is pure error
    only. Without replicates the residual is the higher-order interactions alone.

    If the design matrix is rank-deficient (a factor-level combination without a usable run,
    e.g. a failed run in an unreplicated design), Type II is not defined by ``anova_lm``;
    sequential (Type I) sums of squares from nested fits are reported instead, with the
    degrees of freedom of each term reduced to what is estimable, and a note says so. For
    an unbalanced but full-rank design the Type II sums of squares need not add up to the
    total; a note says so.

    **Centre points** (runs with every factor at its :attr:`Factor.center`, a design's
    ``center_points``) are fitted as Minitab fits them: the model gains an indicator of them
    ("Ct Pt"), the row ``Curvature`` (1 df) tests their mean against the other runs', every
    other term's sum of squares is the one the other runs give, and the residual gains the
    centre points' pure error (:func:`_with_curvature`).

    If the requested model leaves zero residual degrees of freedom (saturated, unreplicated),
    its highest-order interactions are pooled into the residual, order by order down to the
    two-factor ones, and then a main-effects model is fitted; if that is still saturated, F
    and p are reported as NaN. Either case is
    explained in the ``note`` column (and ``attrs["note"]``); the function never raises for
    lack of degrees of freedom.

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite response
        are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors (:class:`Factor` or factor-like objects); their columns hold the
        level values and are treated as categorical. Or the design itself, or a campaign
        result (:func:`brakeca.load_campaign`): then ``interactions``, ``typ`` and
        ``alpha_to_remove`` left unset are the design's (its ``model_order`` or
        ``model_terms``, ``anova_type`` and ``alpha_to_remove``), as :func:`analyze` and the
        report take them; pass ``design.factors`` for the defaults below.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions
        Include all two-factor interactions (True, the default), main effects only (False),
        or the interactions of up to this many factors (a whole number: 1 main effects, 2
        the default, 3 with the three-factor interactions, as Minitab's "terms up through
        order"). Where the model would leave no residual degrees of freedom, the highest
        order is pooled into the residual, order by order, with a note. Or the model's
        terms one by one, as Minitab's Terms dialog picks them: a list (or array) such as
        ``["S", "WP", "A", "WP*A"]``, or one string of them, ``"S WP A WP*A"``
        (:func:`canonical_terms`; a hierarchical model, each
        interaction with the lower-order terms of its factors), fitted as given: no
        pooling; a term of a factor with one level in the data, or aliased with the terms
        before it (in a fraction), is left out with a note.
    typ
        The sums of squares: 2 (Type II, the default) or 3 (Type III, adjusted); ``"II"``
        and ``"III"`` as :func:`statsmodels.stats.anova.anova_lm` takes them.
    alpha_to_remove
        Reduce the model by backward elimination, as Minitab's stepwise "backward" for a
        factorial design: drop the term with the largest p value above this level [-] among
        those no other term contains, refit, until every such term has p at or below it
        (0.1 in Minitab). The terms removed are pooled into the residual; the note names
        them. By default the whole model.

    Returns
    -------
    pandas.DataFrame
        Columns ``term`` (``"S"``, ``"WP"``, ``"S:WP"``, ..., with centre points ``"Curvature"``,
        then ``"Residual"``), ``df``, ``sum_sq`` [response unit^2], ``mean_sq`` [response unit^2],
        ``F``, ``p_value``, ``percent_contribution`` (``sum_sq`` / total sum of squares about the
        mean * 100 [%]), ``aliases`` (the terms of up to three factors the design cannot tell apart
        from the row's, in a fraction; for ``Curvature``, the factors the centre points also differ
        in; empty otherwise) and ``note`` (empty unless a fallback applied). ``attrs`` carries
        ``typ``, ``formula``, ``note``, ``n``, ``total_sum_sq``, ``center_points`` (their number),
        ``order`` (the most factors in a term asked for), ``fitted_order`` (the most in a term of
        the model before backward elimination: fewer where interactions were pooled or aliased, 0
        with no term), ``pooled`` (whether interactions were pooled into the residual because the
        model with them was saturated), ``model_terms`` (the terms given, as the table names them,
        or None) and ``alpha_to_remove``, and the model summary that Minitab and JMP print beside
        the table: ``s`` (residual standard deviation, sqrt of the residual mean square) [response
        unit], ``r_squared``, ``r_squared_adj``, ``r_squared_pred`` (predicted R-squared, 1 - PRESS
        / total sum of squares) [-] and ``df_resid`` [-]; a statistic that is not defined (no
        residual degrees of freedom, a constant response, a run of leverage 1 for
        ``r_squared_pred``) is NaN. With replicates, also the residual's split into pure error and
        lack of fit, with the F test of the one against the other: ``pure_error_df``,
        ``pure_error_ss``, ``lack_of_fit_df``, ``lack_of_fit_ss`` [response unit^2],
        ``lack_of_fit_F`` and ``lack_of_fit_p`` [-] (NaN where not defined).

    References
    ----------
    Wahlström (2016), Section 4 (factorial design) and Figures 6 to 9,
    doi:10.1155/2016/8181260.

    Examples
    --------
    A replicated 2² design (8 runs) whose MU has known effects: S +0.05, A +0.11 and their
    interaction +0.02 (effects as Minitab gives them: the change from the low to the high level):

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor
    >>> factors = [Factor("S", (0.0, 1.0)), Factor("A", (10.0, 20.0), unit="%")]
    >>> runs = pd.DataFrame({
    ...     "S": [0.0, 1.0] * 4,
    ...     "A": [10.0, 10.0, 20.0, 20.0] * 2,
    ...     "MU": [0.30, 0.34, 0.40, 0.46, 0.32, 0.34, 0.40, 0.48],
    ... })
    >>> from brakeca.analysis import anova
    >>> table = anova(runs, factors, "MU")  # main effects and the two-factor interaction
    >>> print(table[["term", "df", "sum_sq", "F", "p_value"]].round(4).to_string(index=False))
        term  df  sum_sq     F  p_value
           S 1.0  0.0050  50.0   0.0021
           A 1.0  0.0242 242.0   0.0001
         S:A 1.0  0.0008   8.0   0.0474
    Residual 4.0  0.0004   NaN      NaN
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    interactions, typ, alpha_to_remove = _model_settings(
        factors, interactions, typ, alpha_to_remove
    )
    typ = _check_anova_type(typ)
    _check_alpha_to_remove(alpha_to_remove)
    _model_order(interactions)
    factors = _factors(factors)
    if _is_term_list(interactions):  # checked once, before any work
        interactions = canonical_terms(interactions, [f.name for f in factors], name="interactions")
    data = _clean(summary, factors, response)
    n = len(data)
    y = data[response].to_numpy(dtype=float)
    dropped = _not_finite(summary, response)
    if n < 2:
        return _empty_anova(
            f"only {n} usable run(s) for {response}; no ANOVA possible"
            + (f" ({dropped})" if dropped else "")
        )
    constant = _is_constant(y)
    total_ss = 0.0 if constant else float(np.sum((y - y.mean()) ** 2))

    centre = _center_mask(data, factors)
    y_center = y[centre]
    frame, term_names, terms, notes = _model(
        data.loc[~centre],
        factors,
        y[~centre],
        interactions,
        y_center=y_center,
        alpha_to_remove=alpha_to_remove,
    )
    if dropped:  # not silently (an API review: only "unbalanced design" said anything)
        notes.insert(0, dropped)
    if not term_names:
        out = pd.DataFrame(
            [
                [
                    "Residual",
                    n - 1.0,
                    total_ss,
                    total_ss / (n - 1),
                    np.nan,
                    np.nan,
                    100.0 if total_ss > 0 else np.nan,
                    "",
                    "",
                ]
            ],
            columns=list(ANOVA_COLUMNS),
        )
        notes.append("no factor varies in the data; nothing to test")
        out["note"] = "; ".join(notes)
        out.attrs.update(note="; ".join(notes), typ=None, formula="", n=n, total_sum_sq=total_ss)
        out.attrs.update(_fit_statistics(y, *_least_squares(np.ones((n, 1)), y), total_ss))
        return out

    fit, table, kind, messages = _fit_anova(frame, terms, typ=typ)
    assert table is not None  # only a check_only call returns no table
    exog = np.asarray(fit.model.exog, dtype=float)
    y_fit = frame["y"].to_numpy(dtype=float)
    lof_frame = frame
    if y_center.size:
        table, exog, y_fit, lof_frame = _with_curvature(table, frame, terms, exog, y_center)
    df_resid = float(table.loc["Residual", "df"])
    saturated = df_resid < 0.5
    resid_ss = float(table.loc["Residual", "sum_sq"])
    exact = not saturated and not constant and exact_fit(resid_ss, y_fit)
    if saturated:
        notes.append("saturated model (0 residual df): F and p cannot be computed")
    elif exact:
        notes.append(
            "exact fit: the model leaves no residual scatter (residual sum of squares 0"
            + (f", to round-off: {resid_ss:.2g}" if resid_ss > 0 else "")
            + "), so F is infinite and p 0 for every term with a sum of squares above "
            "round-off"
        )
        # as the exact 0 it is: the F and p of round-off said nothing (an exact 0 too: a
        # term of 1e-33 then has no F, as at round-off)
        table = table.copy()
        table.loc["Residual", "sum_sq"] = 0.0
        terms_ss = table["sum_sq"].drop(index="Residual")
        nil = np.array([_negligible(ss, total_ss) for ss in terms_ss])
        table.loc[terms_ss.index, "F"] = np.where(nil, np.nan, np.inf)
        table.loc[terms_ss.index, "PR(>F)"] = np.where(nil, np.nan, 0.0)

    out = pd.DataFrame(
        {
            "term": [term_names.get(str(t), str(t)) for t in table.index],
            "df": table["df"].to_numpy(dtype=float),
            "sum_sq": table["sum_sq"].to_numpy(dtype=float),
        }
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        out["mean_sq"] = np.where(
            out["df"] > 0, out["sum_sq"] / out["df"].where(out["df"] > 0), np.nan
        )
        out["F"] = table["F"].to_numpy(dtype=float)
        out["p_value"] = table["PR(>F)"].to_numpy(dtype=float)
        out["percent_contribution"] = out["sum_sq"] / total_ss * 100.0 if total_ss > 0 else np.nan
    names = {t[2:-1]: n for t, n in term_names.items() if ":" not in t}
    chains = _alias_chains(frame, terms)
    out["aliases"] = [_chain_text(chains.get(str(t), []), names) for t in table.index]
    left_out = _left_out(factors, names.values()) if y_center.size else []
    if left_out:  # the centre points differ from the other runs in those factors too
        out.loc[out["term"] == CURVATURE, "aliases"] = " + ".join(left_out)
        notes.append(_confounded_curvature(left_out))
    resid = out["term"] == "Residual"
    out.loc[resid, ["F", "p_value"]] = np.nan
    if saturated:
        out[["F", "p_value"]] = np.nan
        out.loc[resid, ["sum_sq", "mean_sq", "percent_contribution"]] = [0.0, np.nan, 0.0]
    if constant:
        notes.append("response is constant; F, p and contributions are undefined")
        out[["F", "p_value", "percent_contribution"]] = np.nan
        out["sum_sq"] = 0.0
        out["mean_sq"] = np.where(out["df"] > 0, 0.0, np.nan)
    else:
        if messages and not saturated:
            notes.extend(messages)
        if not math.isclose(float(out["sum_sq"].sum()), total_ss, rel_tol=1e-8, abs_tol=0.0):
            if kind == ANOVA_TYPES[2]:
                notes.append(
                    "unbalanced design: the Type II sums of squares do not add up to the "
                    "total, and differ from the adjusted (Type III) sums of squares Minitab "
                    "and JMP show (Type II adjusts each term for the others but not for the "
                    "interactions that contain it; typ=3, or anova_type = 3 in the design, "
                    "gives Type III)"
                )
            elif kind == ANOVA_TYPES[3]:
                notes.append(
                    "unbalanced design: the adjusted (Type III) sums of squares do not add up "
                    "to the total (each term is adjusted for every other term)"
                )
    silent = None if constant or saturated or exact else _silent_repeats(lof_frame)
    if silent is not None:
        notes.append(silent[0])
    note = "; ".join(notes)
    out["note"] = note
    out = out[list(ANOVA_COLUMNS)].reset_index(drop=True)
    out.attrs.update(
        typ=kind,
        formula=f"{response} ~ "
        + (
            " + ".join([term_names[t] for t in terms] + (["Ct Pt"] if y_center.size else [])) or "1"
        ),
        note=note,
        n=n,
        total_sum_sq=total_ss,
        center_points=int(y_center.size),
        order=_model_order(interactions),
        fitted_order=frame.attrs.get("fitted_order", 0),
        pooled=bool(frame.attrs.get("pooled", False)),
        model_terms=list(interactions) if _is_term_list(interactions) else None,
        alpha_to_remove=alpha_to_remove,
    )
    out.attrs.update(_fit_statistics(y_fit, *_least_squares(exog, y_fit), total_ss))
    out.attrs.update(_lack_of_fit(lof_frame, df_resid, float(table.loc["Residual", "sum_sq"])))
    if exact:
        out.attrs["s"] = 0.0  # (the round-off's 1e-15)
    # the residual's degrees of freedom of identical repeats (the note's; report's In short)
    out.attrs["silent_repeat_df"] = 0 if silent is None else silent[1]
    return out


#: The ANOVA's term for the curvature that centre points test (Minitab's "Curvature").
CURVATURE = "Curvature"
#: The effects table's row of the centre points' indicator (Minitab's "Ct Pt").
CENTER_TERM = "Ct Pt"


def _left_out(factors: Sequence[Factor], varying: Iterable[str]) -> list[str]:
    """The factors not among ``varying`` (those with a single level in the runs that are not
    centre points): the centre points' term is confounded with their main effects."""
    kept = set(varying)
    return [f.name for f in factors if f.name not in kept]


def _confounded_curvature(left_out: Sequence[str]) -> str:
    which = ", ".join(left_out)
    return (
        f"{which} {'has' if len(left_out) == 1 else 'have'} a single level in the runs that "
        "are not centre points, so the centre points' term (Curvature, Ct Pt) is confounded "
        f"with the main effect of {which}: it does not test curvature"
    )


def _with_curvature(
    table: pd.DataFrame,
    frame: pd.DataFrame,
    terms: Sequence[str],
    exog: np.ndarray,
    y_center: np.ndarray,
) -> tuple[pd.DataFrame, np.ndarray, np.ndarray, pd.DataFrame]:
    """The ANOVA ``table`` of the runs at the factors' levels (``frame``, model matrix
    ``exog``) with the centre points ``y_center`` [response unit] added, as Minitab fits a
    design with centre points: the model gains an indicator of the centre points ("Ct Pt"),
    which fits their mean, so that every other term's sum of squares is unchanged (of any
    type), the residual gains their scatter about their mean (pure error, ``n_c - 1``
    degrees of freedom), and the row :data:`CURVATURE` (1 degree of freedom) is the rise of
    the residual sum of squares when the indicator leaves the model, each factor then coded
    -1/+1 and the centre points 0: for a balanced design ``n_f n_c / (n_f + n_c)`` times the
    squared difference of the two means. F and p of every term are taken against the new
    residual.

    Returns the table (its rows in order, :data:`CURVATURE` before ``Residual``), the model
    matrix of all runs (the centre points last) [-], their responses and a frame of all runs
    for :func:`_lack_of_fit` (the centre points one more cell).
    """
    from scipy import stats

    y_cube = frame["y"].to_numpy(dtype=float)
    n_c = y_center.size
    y = np.concatenate([y_cube, y_center])
    coded = np.hstack([np.ones((y_cube.size, 1)), *(_term_columns(frame, t) for t in terms)])
    reduced = _with_centre_rows(coded, n_c, indicator=False)
    sse = _sse(_with_centre_rows(coded, n_c), y)
    rows = table.drop(index="Residual")[["df", "sum_sq"]].astype(float)
    rows.loc[CURVATURE] = [1.0, max(_sse(reduced, y) - sse, 0.0)]
    df_resid = float(table.loc["Residual", "df"]) + n_c - 1
    mean_resid = sse / df_resid if df_resid > 0.5 else np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        rows["F"] = (rows["sum_sq"] / rows["df"].where(rows["df"] > 0)) / mean_resid
    rows["PR(>F)"] = stats.f.sf(rows["F"], rows["df"], df_resid)
    rows.loc["Residual"] = [df_resid, sse, np.nan, np.nan]
    exog_all = _with_centre_rows(exog, n_c)
    cells = [c for c in frame.columns if c != "y"]
    centre_rows = pd.DataFrame({"y": y_center, **{c: "centre" for c in cells}})
    return rows, exog_all, y, pd.concat([frame, centre_rows], ignore_index=True)


def alpha_problem(alpha: Any, *, usual: str = "0.1 in Minitab") -> str | None:
    """What is wrong with ``alpha`` as a significance level [-] (a number above 0 and below 1,
    not text or a bool), or None when nothing is: the one rule of every place that takes one
    (a design's ``alpha_to_remove``, ``brakeca analyze --reduce``, :func:`anova`,
    :func:`brakeca.rsm.backward_elimination`, :func:`two_level_effects`,
    :func:`level_coefficients`, the power functions; and :func:`level_comparisons`'
    ``confidence``, of the same range), which each prefix with their own name. ``usual`` is
    the value the message gives as usual (an alpha to remove's by default)."""
    if (
        isinstance(alpha, bool | np.bool_ | str)
        or not isinstance(alpha, numbers.Real)
        or not (0.0 < float(alpha) < 1.0)
    ):
        return f"expected a level above 0 and below 1 ({usual}), got {alpha!r}"
    return None


def _check_alpha_to_remove(alpha: Any) -> None:
    problem = None if alpha is None else alpha_problem(alpha)
    if problem:
        raise ValueError(f"alpha_to_remove: {problem}")


def _check_anova_type(typ: Any) -> int:
    """``typ`` where it is 2 or 3 (a whole number); a ValueError naming it otherwise."""
    if type(typ) is not int or typ not in ANOVA_TYPES:
        raise ValueError(
            f"typ: the ANOVA's sums of squares are of Type 2 or 3 (Type III, adjusted; 'II' "
            f"and 'III' as statsmodels spells them), got {typ!r}"
        )
    return typ


def _silent_repeats(frame: pd.DataFrame) -> tuple[str, int] | None:
    """A note on the repeated level combinations of ``frame`` (``y`` and the factors'
    columns) whose runs are identical in ``y`` (within 1e-13 of its size: no scatter
    between their seeds: a response that does not depend on the seed, as MU_SD of runs of
    one stop), with their degrees of freedom; None where none is. Their degrees of freedom
    count in the residual with no error in them (an analysis review: 8 of 9 residual df
    were copies, and A's p of 0.003 would have been 0.41 against the rest; every repeat
    identical, with a lack of fit left, is said too: a diff review)."""
    cells = [c for c in frame.columns if c != "y"]
    if not cells:
        return None
    groups = frame.groupby(cells, sort=False)["y"]
    size = groups.size()
    spread = groups.max() - groups.min()
    scale = float(np.max(np.abs(frame["y"].to_numpy(dtype=float)), initial=0.0))
    repeated = size > 1
    silent = repeated & (spread <= 1e-13 * scale)
    if not silent.any():
        return None
    df = int((size[silent] - 1).sum())
    every = silent.sum() == repeated.sum()
    count = (
        f"all {int(repeated.sum())}"
        if every
        else f"{int(silent.sum())} of the {int(repeated.sum())}"
    )
    return (
        f"{count} repeated level combinations have "
        "identical runs (no scatter between their seeds: a response that does not depend on "
        f"the seed there): their {df} degree{'s' if df != 1 else ''} of freedom count in the "
        "residual with no error in them, so the F tests are stronger than the other runs' "
        "scatter warrants",
        df,
    )


def _lack_of_fit(frame: pd.DataFrame, df_resid: float, ssr: float) -> dict[str, float]:
    """The residual split, as Minitab prints it for a replicated design, into pure error
    (the scatter of the runs of one factor-level combination about their mean: here the
    seed-to-seed scatter) and lack of fit (what is left: the terms the model leaves out, such
    as three-factor interactions), with the F test of lack of fit against pure error.
    ``frame`` holds ``y`` and the factors' columns (one cell per distinct row), ``df_resid``
    [-] and ``ssr`` [response unit^2] are the model's residual.

    Returns ``pure_error_df``, ``pure_error_ss`` [response unit^2], ``lack_of_fit_df``,
    ``lack_of_fit_ss`` [response unit^2], ``lack_of_fit_F`` and ``lack_of_fit_p`` [-]; the
    last two are NaN unless both parts have degrees of freedom (replicates, and a model that
    does not hold every cell), the sums of squares NaN without replicates.
    """
    cells = [c for c in frame.columns if c != "y"]  # the factors that vary: at least one
    y = frame["y"].to_numpy(dtype=float)
    groups = frame.groupby(cells, sort=False)["y"]
    df_pe = float(len(y) - groups.ngroups)
    out = {
        "pure_error_df": df_pe,
        "pure_error_ss": math.nan,
        "lack_of_fit_df": math.nan,
        "lack_of_fit_ss": math.nan,
        "lack_of_fit_F": math.nan,
        "lack_of_fit_p": math.nan,
    }
    if df_pe < 0.5:
        return out
    means = groups.transform("mean").to_numpy(dtype=float)
    ss_pe = float(np.sum((y - means) ** 2))
    df_lof = df_resid - df_pe
    ss_lof = max(ssr - ss_pe, 0.0)
    out.update(pure_error_ss=ss_pe, lack_of_fit_df=df_lof, lack_of_fit_ss=ss_lof)
    if df_lof > 0.5 and not _pure_error_at_round_off(ss_pe, y):  # (identical repeats)
        from scipy import stats

        f_value = (ss_lof / df_lof) / (ss_pe / df_pe)
        out.update(lack_of_fit_F=f_value, lack_of_fit_p=float(stats.f.sf(f_value, df_lof, df_pe)))
    return out


def _coded_frame(
    data: pd.DataFrame, factors: Sequence[Factor], y: np.ndarray | None = None
) -> tuple[pd.DataFrame, dict[str, str], list[str]]:
    """The factors that vary in ``data`` as categorical columns ``f0``, ``f1``, ... (level
    codes ``"L00"``, ``"L01"``, ...; beside ``y`` when given), the mapping of those safe
    column names to the factor names, and the names of the factors with a single level in
    the data, which are left out."""
    frame = pd.DataFrame({"y": y}) if y is not None else pd.DataFrame(index=range(len(data)))
    names: dict[str, str] = {}
    single: list[str] = []
    for i, f in enumerate(factors):
        codes = _codes(data, f)
        if np.unique(codes).size < 2:
            single.append(f.name)
            continue
        frame[f"f{i}"] = [f"L{c:02d}" for c in codes]
        names[f"f{i}"] = f.name
    return frame, names, single


def split_terms(text: str) -> list[str]:
    """The terms of a model written on one line, as ``brakeca analyze --terms`` and a
    design's ``model_terms`` take them: separated by spaces, commas or ``+`` (``"S WP WR A
    S*WP"``, ``"S + WP + S:WP"``); a term's factors joined by ``*`` or ``:``, or by ``|``
    for every term of those factors (Minitab's bar: :func:`canonical_terms` expands it).

    Parameters
    ----------
    text
        The terms on one line.

    Returns
    -------
    list of str
        The terms as written (``"S*WP"``), spaces around ``*``, ``:`` and ``|`` removed; empty for
        a blank line. :func:`canonical_terms` checks them against the factors.

    Raises
    ------
    ValueError
        Two commas or ``+`` with no term between them (``"S,,WP"``).
    """
    import re

    joined = re.sub(r"\s*([*:|])\s*", r"\1", text.strip())  # "WP * A" is one term
    if not joined:
        return []
    terms = re.split(r"\s*[,+]\s*|\s+", joined)
    if "" in terms:  # "S,,WP", "S + + WP", ", S": a term left out by mistake?
        raise ValueError(f"an empty term between separators in {text!r}")
    return terms


def canonical_terms(terms: Any, factors: Sequence[str], *, name: str = "model_terms") -> list[str]:
    """The model ``terms`` checked against the ``factors`` (their names, in design order),
    each written as the tables write it (``"S:WP"``: the factors joined by ``:`` in design
    order), in the order the model fits them: by number of factors, then design order.

    Parameters
    ----------
    terms
        A list of terms, each a factor name or factor names joined by ``*`` or ``:``
        (``"S*WP"``, ``"S:WP:A"``), or by ``|`` for all the terms of those factors, as
        Minitab writes a full factorial model (``"S|WP|A"``: S, WP, A, their three
        two-factor interactions and the three-factor one); a string is split by
        :func:`split_terms`.
    factors
        The design's factor names.
    name
        What the caller calls the argument, which starts every message.

    Returns
    -------
    list of str
        The terms, as above.

    Raises
    ------
    ValueError
        No term, a factor not in the design, a factor twice in a term (squares belong to a
        response-surface design), a term given twice, or a model that is not hierarchical
        (an interaction without a lower-order term of its factors: its columns would also
        take those terms' effects, and the tables could not code it as one product of
        contrasts throughout); the message names the term.
    """
    if isinstance(terms, str):
        try:
            terms = split_terms(terms)
        except ValueError as exc:
            raise ValueError(f"{name}: {exc}") from None
    if isinstance(terms, Iterable) and not isinstance(terms, Mapping | bytes):
        terms = list(terms)  # once: a generator is read here
    if not isinstance(terms, list) or not all(isinstance(t, str) for t in terms):
        raise ValueError(
            f"{name}: expected a list of terms (factor names, an interaction's joined by '*'), "
            f"got {terms!r}"
        )
    if not terms:
        raise ValueError(f"{name}: no term given; name at least one factor")
    terms = _expand_bars(terms, name)
    index = {f: i for i, f in enumerate(factors)}
    seen: dict[tuple[int, ...], str] = {}
    for term in terms:
        parts = [p.strip() for p in term.replace("*", ":").split(":")]
        unknown = [p for p in parts if p not in index]
        if unknown:
            what = repr(unknown[0]) if unknown[0] else "an empty name"
            alike = [f for f in factors if f.lower() == unknown[0].lower()]
            hint = f"; did you mean {alike[0]!r}? names are case-sensitive" if alike else ""
            raise ValueError(
                f"{name}: term {term!r}: {what} is not a factor of the design (its factors: "
                f"{', '.join(factors)}){hint}"
            )
        if len(set(parts)) < len(parts):
            raise ValueError(
                f"{name}: term {term!r} names a factor twice; a factorial model's terms "
                "are main effects and interactions of different factors (squares belong "
                "to a response-surface design)"
            )
        key = tuple(sorted(index[p] for p in parts))
        if key in seen:
            raise ValueError(f"{name}: term {term!r} is given twice (as {seen[key]!r})")
        seen[key] = term
    out = [":".join(factors[i] for i in key) for key in sorted(seen, key=lambda k: (len(k), k))]
    gaps = _hierarchy_gaps(out)
    if gaps:
        raise ValueError(
            f"{name}: the model is not hierarchical ({'; '.join(gaps)}): each interaction "
            "needs every lower-order term of its factors in the model, as in 'WP A WP*A'; "
            "add them (a term without them would take over their effects)"
        )
    return out


def _expand_bars(terms: list[str], name: str) -> list[str]:
    """``terms`` with each ``"A|B|C"`` replaced by every term of its factors (``A``, ``B``,
    ``C``, ``A:B``, ``A:C``, ``B:C``, ``A:B:C``), each made once over all the bars and the
    terms named besides; the other terms as given (checked by :func:`canonical_terms`)."""

    def factors_of(term: str) -> frozenset[str]:
        return frozenset(p.strip() for p in term.replace("*", ":").split(":"))

    plain = {factors_of(t) for t in terms if "|" not in t}
    out: list[str] = []
    made: set[frozenset[str]] = set()
    for term in terms:
        if "|" not in term:
            if factors_of(term) not in made:  # a bar's term named again: once
                out.append(term)
            continue
        parts = [p.strip() for p in term.split("|")]
        if len(set(parts)) < len(parts):
            raise ValueError(f"{name}: term {term!r} names a factor twice")
        for k in range(1, len(parts) + 1):
            for combo in itertools.combinations(parts, k):
                key = frozenset(combo)
                if key not in made and key not in plain:  # (a review: "S + S|WP" had
                    made.add(key)  # said S was given twice)
                    out.append(":".join(combo))
    return out


def _hierarchy_gaps(terms: Sequence[str]) -> list[str]:
    """The terms (``"S:WP"``) of which some lower-order part is not among ``terms``, each
    with its missing parts: ``["S:WP without S"]``."""
    given = {frozenset(t.split(":")) for t in terms}
    gaps = []
    for term in terms:
        parts = term.split(":")
        missing = [
            ":".join(sub)
            for k in range(1, len(parts))
            for sub in itertools.combinations(parts, k)
            if frozenset(sub) not in given
        ]
        if missing:
            gaps.append(f"{term} without {', '.join(missing)}")
    return gaps


def _model_order(interactions: Model, *, name: str = "interactions") -> int:
    """The highest number of factors in the model's terms, from ``interactions``: True 2 (the
    two-factor interactions), False 1 (main effects), a whole number that number, a list of
    terms its longest term's (checked against the factors by :func:`canonical_terms`). ``name``
    is the argument the caller took it as: ``max_order`` takes a whole number only."""
    if isinstance(interactions, bool | np.bool_) and name == "interactions":
        return 2 if interactions else 1
    if name == "interactions" and _is_term_list(interactions):
        terms = split_terms(interactions) if isinstance(interactions, str) else interactions
        return max((len(str(t).replace("*", ":").split(":")) for t in terms), default=1)
    if (
        isinstance(interactions, bool | np.bool_)
        or not isinstance(interactions, numbers.Integral)
        or interactions < 1
    ):
        flags = (
            "True (two-factor interactions), False (main effects), "
            if name == "interactions"
            else ""
        )
        terms = ", or a list of terms" if name == "interactions" else ""
        raise ValueError(
            f"{name}: expected {flags}the most factors in a term, a whole number from 1{terms}, "
            f"got {interactions!r}"
        )
    return int(interactions)


def _is_number(text: str) -> bool:
    """Whether ``text`` reads as a number (an order given as text, not a term)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _is_term_list(interactions: Any) -> TypeGuard[Sequence[str]]:
    """Whether ``interactions`` gives the model's terms (a list of them, or one string of them
    as analyze's ``model_terms`` takes it: anova refused it, an API review), not a flag or
    an order (text that reads as a number, "2", is an order given as text, refused)."""
    if isinstance(interactions, str):
        return not _is_number(interactions)
    return isinstance(
        interactions, Sequence | np.ndarray | pd.Series | pd.Index | set | frozenset
    ) and not isinstance(interactions, str | bytes)


_ORDER_NAMES = {2: "two-factor", 3: "three-factor", 4: "four-factor", 5: "five-factor"}


def _model(
    data: pd.DataFrame,
    factors: Sequence[Factor],
    y: np.ndarray,
    interactions: Model,
    *,
    y_center: np.ndarray | None = None,
    alpha_to_remove: float | None = None,
) -> tuple[pd.DataFrame, dict[str, str], list[str], list[str]]:
    """The model :func:`anova` fits: (frame, term names, terms, notes).

    ``data`` holds the runs at the factors' levels, without centre points, whose responses
    ``y_center`` bring their pure error to the residual (so the interactions are kept where
    only the centre points leave the model any degrees of freedom). With
    ``alpha_to_remove`` the terms are then reduced by backward elimination
    (:func:`_eliminate`).

    ``frame`` holds ``y`` and one categorical column per factor that varies in the data;
    ``terms`` are the formula terms: main effects, and the interactions up through the order
    ``interactions`` gives, :func:`_model_order`, unless they would leave no residual degrees
    of freedom, in which case the highest order is pooled into the residual, order by order,
    and a note says so; or the terms ``interactions`` lists (:func:`canonical_terms`), as they
    are, less those of a factor with a single level in the data. ``term names`` maps every
    term asked for, pooled ones included, to its display name (``"S"``, ``"S:WP"``), and is
    empty when no factor varies.
    """
    order = _model_order(interactions)
    notes: list[str] = []
    frame, names, single = _coded_frame(data, factors, y)
    notes.extend(f"factor {n} has a single level in the data and is left out" for n in single)
    if not names:
        return frame, {}, [], notes
    y_center = np.zeros(0) if y_center is None else y_center
    if _is_term_list(interactions):
        terms, term_names, given_notes = _given_terms(names, interactions)
        notes.extend(given_notes)
        terms = _estimable(frame, terms, term_names, notes)
    else:
        terms, term_names = _terms_up_through(names, order)
        estimable = _estimable(frame, terms, term_names, notes)
        terms = _pooled_while_saturated(frame, estimable, y_center, notes)
        frame.attrs["pooled"] = len(terms) < len(estimable)
    # the most factors in a term of the model before any elimination: below the order asked
    # for where a saturated model's interactions were pooled or the design aliases them
    frame.attrs["fitted_order"] = max((t.count(":") + 1 for t in terms), default=0)
    if alpha_to_remove is not None:
        terms, removed = _eliminate(frame, terms, alpha_to_remove, y_center=y_center)
        notes.append(
            f"backward elimination (alpha to remove {alpha_to_remove:g}, keeping the model "
            "hierarchical): "
            + (
                "removed " + ", ".join(term_names[t] for t in removed)
                if removed
                else "no term removed"
            )
            + (
                "; no term is left"
                + (
                    " but the curvature of the centre points"
                    if y_center is not None and len(y_center)
                    else ""
                )
                if removed and not terms
                else ""
            )
        )
    return frame, term_names, terms, notes


def _terms_up_through(names: Mapping[str, str], order: int) -> tuple[list[str], dict[str, str]]:
    """The formula terms of every main effect and interaction of up to ``order`` of the
    factors ``names`` (safe column name to factor name), by order, and their display
    names."""
    combos = [
        combo
        for k in range(1, min(order, len(names)) + 1)
        for combo in itertools.combinations(names, k)
    ]
    terms = [":".join(f"C({c})" for c in combo) for combo in combos]
    term_names = {
        term: ":".join(names[c] for c in combo) for term, combo in zip(terms, combos, strict=True)
    }
    return terms, term_names


def _given_terms(
    names: Mapping[str, str], given: Sequence[str]
) -> tuple[list[str], dict[str, str], list[str]]:
    """The formula terms of the model terms ``given`` (as :func:`canonical_terms` writes
    them: :func:`anova` and :func:`_model_arrays` check them first) over the factors that
    vary (``names``, safe column name to factor name), the display names of those terms and
    of every varying factor's main effect, and a note naming the terms left out for a factor
    with a single level in the data."""
    column = {factor: safe for safe, factor in names.items()}
    terms: list[str] = []
    # every varying factor's main effect is named, in the model or not: the alias chains
    # and the curvature's confounding name them
    term_names = {f"C({safe})": factor for safe, factor in names.items()}
    dropped: list[str] = []
    for term in given:
        parts = term.split(":")
        if not all(p in column for p in parts):
            dropped.append(term)
            continue
        formula = ":".join(f"C({column[p]})" for p in parts)
        terms.append(formula)
        term_names[formula] = term
    notes = []
    if dropped:
        notes.append(
            "terms of a factor with a single level in the data are left out: "
            + ", ".join(dropped)
            + ("; no term of the model is left" if not terms else "")
        )
    return terms, term_names, notes


def _estimable(
    frame: pd.DataFrame, terms: list[str], term_names: Mapping[str, str], notes: list[str]
) -> list[str]:
    """``terms`` less those aliased (confounded) with terms before them, each named in a note
    added to ``notes`` with what it is aliased with."""
    terms, left_out = _estimable_terms(frame, terms)
    if left_out:
        described = []
        for term, aliases in left_out.items():
            with_what = " and ".join(term_names[t] for t in aliases)
            if not with_what:
                with_what = (
                    "the mean: a word of the design's defining relation"
                    if _constant_term(frame, term)
                    else "a combination of the terms before it"
                )
            described.append(f"{term_names[term]} (aliased with {with_what})")
        notes.append(
            "terms aliased (confounded) with terms before them are left out, since the design "
            "cannot tell them apart: " + "; ".join(described)
        )
    return terms


def _pooled_while_saturated(
    frame: pd.DataFrame, terms: list[str], y_center: np.ndarray, notes: list[str]
) -> list[str]:
    """``terms`` with the interactions of the highest order pooled into the residual, order
    by order, while the model leaves no residual degrees of freedom (the centre points'
    ``y_center`` counted), each step named in a note added to ``notes``."""
    spare_df = max(y_center.size - 1, 0)
    fit, _, _, _ = _fit_anova(frame, terms, check_only=True)
    top = max((t.count(":") + 1 for t in terms), default=1)
    while top > 2 and fit.df_resid + spare_df < 0.5:
        name = _ORDER_NAMES.get(top, f"{top}-factor")
        notes.append(
            f"model with {name} interactions is saturated (0 residual df): the {name} "
            "interactions pooled into the residual"
        )
        terms = [t for t in terms if t.count(":") + 1 < top]
        top -= 1
        fit, _, _, _ = _fit_anova(frame, terms, check_only=True)
    if fit.df_resid + spare_df < 0.5 and top == 2:
        notes.append(
            "model with two-factor interactions is saturated (0 residual df): interactions "
            "pooled into the residual, main effects only"
        )
        terms = [t for t in terms if ":" not in t]
    return terms


def _eliminate(
    frame: pd.DataFrame, terms: Sequence[str], alpha: float, *, y_center: np.ndarray
) -> tuple[list[str], list[str]]:
    """Backward elimination, as Minitab's stepwise "backward" for a factorial design: drop
    the term with the largest p value above ``alpha`` among those no other term contains (a
    main effect stays while an interaction of it does), refit, and go on until every such
    term has p <= ``alpha``. A term's p is the F test of dropping it alone from the current
    model (the rise of the residual sum of squares over the columns it takes away, against
    the model's residual mean square, the centre points' indicator and pure error
    included): its adjusted test, which Type II and Type III give alike for such a term, and
    which holds in a design with empty cells too. Nothing is removed without residual
    degrees of freedom or from a constant response (no p values to judge by). Returns the
    terms kept and those removed, in order."""
    from scipy import stats

    y_cube = frame["y"].to_numpy(dtype=float)
    n_c = y_center.size
    y = np.concatenate([y_cube, y_center])
    blocks = {t: _term_columns(frame, t) for t in terms}

    def fit(names: Sequence[str]) -> tuple[float, int]:
        x = np.hstack([np.ones((y_cube.size, 1)), *(blocks[t] for t in names)])
        if n_c:
            x = _with_centre_rows(x, n_c)
        return _sse(x, y), int(np.linalg.matrix_rank(x))

    kept: list[str] = list(terms)
    removed: list[str] = []
    if _is_constant(y):
        return kept, removed
    while kept:
        sse, rank = fit(kept)
        df_resid = y.size - rank
        if df_resid < 1 or exact_fit(sse, y):  # nothing to test against (round-off too)
            break
        parts = {t: set(t.split(":")) for t in kept}
        p: dict[str, float] = {}
        for t in kept:
            if any(u != t and parts[t] < parts[u] for u in kept):
                continue  # an interaction holds it
            sse_t, rank_t = fit([u for u in kept if u != t])
            df_t = rank - rank_t
            if df_t >= 1:
                f_value = ((sse_t - sse) / df_t) / (sse / df_resid)
                p[t] = float(stats.f.sf(max(f_value, 0.0), df_t, df_resid))
        worst = _next_to_remove(p, alpha)
        if worst is None:
            break
        kept.remove(worst)
        removed.append(worst)
    return kept, removed


def _next_to_remove(p: Mapping[str, float], alpha: float) -> str | None:
    """The term backward elimination removes next, of those it may remove with their p
    values: the one of largest p if that is above ``alpha`` [-], else None (also when no p
    is finite). Shared with :func:`brakeca.rsm.backward_elimination`."""
    finite = {t: float(v) for t, v in p.items() if np.isfinite(v)}
    if not finite:
        return None
    worst = max(finite, key=finite.__getitem__)
    return worst if finite[worst] > alpha else None


def _contrast_columns(labels: pd.Series) -> np.ndarray:
    """Deviation (sum-to-zero) coding of a categorical column: one column per observed level
    but the first, +1 at that level and -1 at the first level; a two-level factor's single
    column is the classical -1/+1 contrast of a two-level design."""
    values = labels.to_numpy()
    levels = sorted(set(values))
    first = (values == levels[0]).astype(float)
    return np.column_stack([(values == level).astype(float) - first for level in levels[1:]])


def _row_kron(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The row-wise Kronecker product of two column blocks [-]: an interaction's columns
    from its factors' (row i: every product of a column of ``a`` and one of ``b``, ``a``'s
    slowest)."""
    return (a[:, :, None] * b[:, None, :]).reshape(len(a), -1)


def _term_columns(frame: pd.DataFrame, term: str) -> np.ndarray:
    """The contrast columns of a model term (``"C(f0)"``, ``"C(f0):C(f1)"``, ...): the
    products of its factors' :func:`_contrast_columns`."""
    out = np.ones((len(frame), 1))
    for part in term.split(":"):
        contrasts = _contrast_columns(frame[part[2:-1]])
        out = _row_kron(out, contrasts)
    return out


def _constant_term(frame: pd.DataFrame, term: str) -> bool:
    """Whether a term's contrast columns are the same in every row: aliased with the mean."""
    columns = _term_columns(frame, term)
    return bool(np.allclose(columns, columns[:1], rtol=0.0, atol=1e-12))


def _rank(*blocks: np.ndarray) -> int:
    """Rank of the intercept column beside ``blocks`` [-]."""
    first = blocks[0] if blocks else np.ones((0, 1))
    return int(np.linalg.matrix_rank(np.hstack([np.ones((first.shape[0], 1)), *blocks])))


def _same_span(a: np.ndarray, b: np.ndarray, rank_a: int | None = None) -> bool:
    """Whether two terms' columns span the same space beside the intercept: the design cannot
    tell the two effects apart (complete aliasing, e.g. ``AB`` and ``CD`` in a 2^(4-1)
    fraction with ``D = ABC``)."""
    rank_a = _rank(a) if rank_a is None else rank_a
    return _rank(b) == rank_a == _rank(a, b)


def _estimable_terms(
    frame: pd.DataFrame, terms: Sequence[str]
) -> tuple[list[str], dict[str, list[str]]]:
    """Split ``terms`` into those the data can estimate in turn and those left out.

    A term is left out when its columns add nothing to the span of the intercept and the
    terms kept before it: it is completely aliased (confounded) with them, as two-factor
    interactions are with each other, or with main effects, in a fractional factorial. The
    mapping gives, for each term left out, the kept terms it is aliased with alone (empty when
    it is aliased only with a combination of them). A term that adds some but not all of its
    degrees of freedom (an empty cell of a multi-level interaction) is kept: the ANOVA then
    reports sequential sums of squares (:func:`_fit_anova`).
    """
    columns = {t: _term_columns(frame, t) for t in terms}
    kept: list[str] = []
    left_out: dict[str, list[str]] = {}
    rank = 1
    for term in terms:
        new_rank = _rank(*(columns[t] for t in kept), columns[term])
        if new_rank > rank:
            kept.append(term)
            rank = new_rank
        else:
            left_out[term] = [t for t in kept if _same_span(columns[term], columns[t])]
    return kept, left_out


#: Largest number of candidate terms :func:`_alias_chains` compares a model term with; beyond
#: it, three-factor interactions are not searched.
_MAX_ALIAS_CANDIDATES = 1000


def _candidate_terms(factors: Sequence[str], max_order: int) -> list[str]:
    """Every term of one to ``max_order`` of ``factors`` (safe column names), by order, then
    design order; the highest orders are dropped while there are more than
    :data:`_MAX_ALIAS_CANDIDATES` terms."""
    order = max_order
    while order > 1 and sum(math.comb(len(factors), k) for k in range(1, order + 1)) > (
        _MAX_ALIAS_CANDIDATES
    ):
        order -= 1
    return [
        ":".join(f"C({f})" for f in combo)
        for k in range(1, min(order, len(factors)) + 1)
        for combo in itertools.combinations(factors, k)
    ]


def _alias_chains(frame: pd.DataFrame, terms: Sequence[str]) -> dict[str, list[tuple[str, int]]]:
    """For each model term, the other terms of up to three factors that the data cannot tell
    apart from it (same span beside the intercept), as (formula term, sign).

    The sign is that of the alias's contrast column against the term's, +1 or -1, when both
    are single columns (two-level factors): then the term's estimate is the term's effect plus
    the signed sum of its aliases' (Minitab's "Alias Structure", e.g. ``A + B:D - C:E`` when
    ``D = A*B`` and ``E = -A*C``); 0 when a term has several columns (factors of more levels),
    where no sign applies. Empty lists for a full factorial.
    """
    candidates = _candidate_terms([c for c in frame.columns if c != "y"], 3)
    columns = {t: _term_columns(frame, t) for t in candidates}
    columns.update({t: _term_columns(frame, t) for t in terms if t not in columns})
    ranks = {t: _rank(c) for t, c in columns.items()}
    chains: dict[str, list[tuple[str, int]]] = {}
    for term in terms:
        chain = []
        for other in candidates:
            if other == term or ranks[other] != ranks[term]:
                continue
            if not _same_span(columns[term], columns[other], ranks[term]):
                continue
            sign = 0
            if columns[term].shape[1] == 1 and columns[other].shape[1] == 1:
                sign = 1 if float(columns[term][:, 0] @ columns[other][:, 0]) > 0 else -1
            chain.append((other, sign))
        chains[term] = chain
    return chains


def _chain_text(aliases: Sequence[tuple[str, int]], names: Mapping[str, str]) -> str:
    """A term's aliases as signed text: ``"B:D - C:E"`` (a leading ``-`` when the first is
    negative), joined by ``+`` where no sign applies."""
    text = ""
    for k, (term, sign) in enumerate(aliases):
        shown = _display_term(term, names)
        if k == 0:
            text = f"-{shown}" if sign < 0 else shown
        else:
            text += f" - {shown}" if sign < 0 else f" + {shown}"
    return text


def _display_term(term: str, names: Mapping[str, str]) -> str:
    """``"C(f0):C(f1)"`` as ``"S:WP"``, from the safe column names' factor names."""
    return ":".join(names[part[2:-1]] for part in term.split(":"))


#: A residual sum of squares at or below this fraction of the total [-] is round-off: the
#: model fits every run exactly (its residuals 1e-9 of the response's spread and below), as
#: where replicates are identical or the response is additive to the last digit. F and p of
#: such a residual had measured the floating-point error (F of 1e30, p of 1e-46: an
#: analysis review), so it is taken as the exact fit it is.
ROUND_OFF_SS = 1e-18


def exact_fit(resid_ss: float, y: Any) -> bool:
    """Whether a residual sum of squares ``resid_ss`` [response unit^2] of a fit of ``y`` is
    round-off: at or below :data:`ROUND_OFF_SS` of ``y``'s total sum of squares, the rule by
    which a term's sum of squares is nil too. The ANOVA, effects table, backward
    elimination, unusual runs and response surfaces all take such a fit as exact (a diff
    review found the rule in some of them only: one fit, two verdicts; a floor of the
    values' own round-off, 1e-13 of the largest, had then made real scatter tiny beside an
    offset exact, and noise terms infinitely significant: a third review)."""
    values = np.asarray(y, dtype=float)
    if values.size == 0:
        return False
    return _negligible(resid_ss, float(np.sum((values - values.mean()) ** 2)))


def _negligible(ss: float, total_ss: float) -> bool:
    """Whether a sum of squares ``ss`` is round-off beside the total ``total_ss`` [response
    unit^2]: at or below :data:`ROUND_OFF_SS` of it (a residual: an exact fit; a term's:
    nil)."""
    return float(ss) <= ROUND_OFF_SS * float(total_ss)


def _pure_error_at_round_off(ss_pe: float, y: Any) -> bool:
    """Whether a pure error sum of squares ``ss_pe`` [response unit^2] of runs ``y`` is the
    round-off of the values themselves (within 1e-13 of the largest in size a run, as
    :func:`_silent_repeats` judges identical runs): identical repeats, no test of lack of
    fit. A pure error is differences within cells, which no model's cancellation enters:
    judged by the total instead, real scatter 1e-10 of the effects had lost its test (a
    third review)."""
    values = np.asarray(y, dtype=float)
    if values.size == 0:
        return True
    return float(ss_pe) <= values.size * (1e-13 * float(np.max(np.abs(values)))) ** 2


def _is_constant(y: np.ndarray) -> bool:
    """Whether a response does not vary beyond round-off (its spread within 1e-13 of its size)."""
    return float(np.ptp(y)) <= 1e-13 * float(np.max(np.abs(y)))


def _sse(exog: np.ndarray, y: np.ndarray) -> float:
    """The residual sum of squares of the least-squares fit of ``y`` on ``exog``
    [response unit^2]."""
    coef, *_ = np.linalg.lstsq(exog, y, rcond=None)
    r = y - exog @ coef
    return float(r @ r)


def _vif(exog: np.ndarray) -> np.ndarray:
    """Variance inflation factors of the columns after the intercept [-]: 1 / (1 - R_j^2),
    R_j^2 of column j regressed on the others (with the intercept)."""
    k = exog.shape[1]
    out = np.full(k, math.nan)
    for j in range(1, k):
        col = exog[:, j]
        others = np.delete(exog, j, axis=1)
        ss_tot = float(np.sum((col - col.mean()) ** 2))
        if ss_tot <= 0:
            continue
        r2 = 1.0 - _sse(others, col) / ss_tot
        out[j] = 1.0 / (1.0 - r2) if r2 < 1.0 - 1e-12 else math.inf
    return out


def _least_squares(exog: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The least-squares fit of ``y`` on ``exog``: fitted values [response unit], leverages
    (the diagonal of the hat matrix ``X X^+``, also for a rank-deficient ``X``) [-] and the
    residual degrees of freedom [-]."""
    exog = np.asarray(exog, dtype=float)
    coef, *_ = np.linalg.lstsq(exog, y, rcond=None)
    leverage = np.einsum("ij,ji->i", exog, np.linalg.pinv(exog))
    return exog @ coef, leverage, float(y.size - np.linalg.matrix_rank(exog))


def _fit_statistics(
    y: np.ndarray, fitted: np.ndarray, leverage: np.ndarray, df_resid: float, total_ss: float
) -> dict[str, float]:
    """Model summary of a least-squares fit (:func:`_least_squares`), as Minitab and JMP print
    it: ``s`` (standard deviation of the residuals, sqrt of the residual mean square)
    [response unit], ``r_squared``, ``r_squared_adj`` and ``r_squared_pred`` (from the PRESS
    statistic, sum of (e_i / (1 - h_i))^2) [-], and the model's ``df_resid`` [-].

    A statistic that is not defined is NaN: every one but ``r_squared`` without residual
    degrees of freedom, the R-squares of a constant response, and ``r_squared_pred`` when a
    run has leverage 1 (the model fits it exactly whatever its value).
    """
    n = y.size
    resid = y - fitted
    ssr = float(resid @ resid)
    out = {"df_resid": df_resid, "s": math.nan, "r_squared": math.nan}
    out.update(r_squared_adj=math.nan, r_squared_pred=math.nan)
    if df_resid > 0.5:
        out["s"] = math.sqrt(ssr / df_resid)
    if total_ss > 0:
        out["r_squared"] = 1.0 - ssr / total_ss
        if df_resid > 0.5:
            out["r_squared_adj"] = 1.0 - (ssr / df_resid) / (total_ss / (n - 1))
            if np.all(leverage < 1.0 - 1e-9):
                press = float(np.sum((resid / (1.0 - leverage)) ** 2))
                out["r_squared_pred"] = 1.0 - press / total_ss
    return out


#: Columns of the table returned by :func:`residuals`, after the runs' own (``test``,
#: ``replicate``, ``order``: those present), in order.
RESIDUAL_COLUMNS: tuple[str, ...] = (
    "observed",
    "fitted",
    "residual",
    "leverage",
    "std_residual",
    "deleted_residual",
    "cooks_distance",
    "dfits",
)


def residuals(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
    alpha_to_remove: float | None = None,
) -> pd.DataFrame:
    """Fitted values and residuals of the model :func:`anova` fits, one row per usable run.

    These are what a residual plot shows (:func:`brakeca.plotting.plot_residuals`): the
    ANOVA's F tests assume residuals that are independent, normal and of one variance, which
    a normal probability plot and plots against the fitted value and the run order check.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions
        Include two-factor interactions, the terms up through an order (as in
        :func:`anova`, with the same pooling when they would saturate the model), or the
        terms listed.
    alpha_to_remove
        The model reduced by backward elimination, as :func:`anova` reduces it. Both unset,
        given a design (or a campaign result), the design's, as in :func:`anova`.

    Returns
    -------
    pandas.DataFrame
        The summary's ``test``, ``replicate`` and ``order`` columns (those present), then
        :data:`RESIDUAL_COLUMNS`: ``observed``, ``fitted`` and ``residual`` [response unit],
        ``leverage`` [-] (diagonal of the hat matrix), ``std_residual`` [-] (the residual
        over ``s sqrt(1 - leverage)``, Minitab's SRES), ``deleted_residual`` [-] (the
        residual against the model fitted without the run, in that fit's standard errors:
        ``std_residual * sqrt((df - 1) / (df - std_residual^2))`` with ``df`` the residual's
        degrees of freedom; Minitab's TRES, statsmodels' externally studentized residual),
        ``cooks_distance`` [-] (``std_residual^2 / p * leverage / (1 - leverage)`` with
        ``p`` the model's parameters: how far the run moves the fitted values; Minitab's
        COOK) and ``dfits`` [-] (``deleted_residual * sqrt(leverage / (1 - leverage))``;
        Minitab's DFIT). Each NaN without residual degrees of freedom (the deleted residual
        also with one), at leverage 1 or for a constant response, whose residuals are
        round-off. ``attrs`` carries ``response``, ``formula``, ``df_resid`` and ``s``.
        :func:`unusual_runs` lists the runs the model fits badly.
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    interactions, _, alpha_to_remove = _model_settings(factors, interactions, 2, alpha_to_remove)
    data, y, exog, formula = _model_arrays(
        summary, factors, response, interactions, alpha_to_remove=alpha_to_remove
    )
    return _residuals_of(data, y, exog, formula, response)


def _residuals_of(
    data: pd.DataFrame, y: np.ndarray, exog: np.ndarray, formula: str, response: str
) -> pd.DataFrame:
    """:func:`residuals` of a model already made (:func:`_model_arrays`' results)."""
    if y.size == 0:
        out = _run_columns(data)
        for c in RESIDUAL_COLUMNS:
            out[c] = pd.Series(dtype=float)
        out.attrs.update(response=response, formula="", df_resid=math.nan, s=math.nan)
        return out
    fitted, leverage, df_resid = _least_squares(exog, y)
    stats = _fit_statistics(y, fitted, leverage, df_resid, float(np.sum((y - y.mean()) ** 2)))
    out = _residual_frame(data, y, fitted, leverage, stats["s"], df_resid)
    out.attrs.update(response=response, formula=formula, df_resid=stats["df_resid"], s=stats["s"])
    return out


def _run_columns(data: pd.DataFrame) -> pd.DataFrame:
    """The ``test``, ``replicate`` and ``order`` columns of ``data`` (those present), indexed
    from 0: the first columns of a residuals table."""
    keep = [c for c in ("test", "replicate", "order") if c in data.columns]
    return data[keep].reset_index(drop=True)


def _residual_frame(
    data: pd.DataFrame,
    y: np.ndarray,
    fitted: np.ndarray,
    leverage: np.ndarray,
    s: float,
    df_resid: float,
) -> pd.DataFrame:
    """A residuals table (:func:`residuals`; also :func:`brakeca.rsm.surface_residuals`):
    the runs' columns of ``data``, then ``observed``, ``fitted``, ``residual`` [response
    unit], ``leverage`` [-], ``std_residual`` [-], the residual over ``s sqrt(1 -
    leverage)`` with ``s`` the fit's residual standard deviation [response unit] and
    ``df_resid`` its degrees of freedom, and from it ``deleted_residual`` (Minitab's TRES),
    ``cooks_distance`` and ``dfits`` [-]; NaN where they are not finite (no residual degrees
    of freedom, or one for the deleted residual), at leverage 1, for a constant response
    and for an exact fit (:func:`exact_fit`: residuals of round-off, in a standard deviation
    of round-off, had flagged runs as unusual: a diff review)."""
    out = _run_columns(data)
    out["observed"] = y
    out["fitted"] = fitted
    out["residual"] = y - fitted
    out["leverage"] = leverage
    with np.errstate(divide="ignore", invalid="ignore"):
        std = (y - fitted) / (s * np.sqrt(1.0 - leverage))
    exact = exact_fit(float(np.sum((y - fitted) ** 2)), y)
    usable = (leverage < 1.0 - 1e-9) & np.isfinite(std) & (not _is_constant(y)) & (not exact)
    r = np.where(usable, std, np.nan)
    out["std_residual"] = r
    # the deleted residual: the run's residual against the fit without it, in that fit's
    # standard errors, from r alone (r^2 <= df_resid; infinite where they are equal)
    params = float(y.size - df_resid)  # the model's parameters (its rank)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = (df_resid - 1.0) / (df_resid - r**2)
        # r^2 = df_resid (to round-off, which can make the ratio negative): the run is the
        # residual's only departure, and the fit without it is exact (a review)
        ratio = np.where(df_resid - r**2 <= 1e-9 * df_resid, np.inf, ratio)
        deleted = r * np.sqrt(ratio) if df_resid > 1.5 else r * np.nan
        odds = leverage / (1.0 - leverage)
        out["deleted_residual"] = deleted
        out["cooks_distance"] = r**2 / params * odds
        out["dfits"] = deleted * np.sqrt(odds)
    return out


#: Columns of the table returned by :func:`unusual_runs`, after the runs' own (``test``,
#: ``replicate``, ``order``: those present), in order.
UNUSUAL_COLUMNS: tuple[str, ...] = (
    "observed",
    "fitted",
    "residual",
    "std_residual",
    "deleted_residual",
    "outlier_p",
    "leverage",
    "cooks_distance",
)

#: The standardized residual beyond which a run is unusual (Minitab's "R" flag) [-].
UNUSUAL_RESIDUAL = 2.0


def unusual_runs(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
    typ: int | str | None = None,
    alpha_to_remove: float | None = None,
    alpha: float = 0.05,
) -> pd.DataFrame:
    """The runs the model fits badly, with how much each moves the fit and what the ANOVA
    says without them: Minitab's "Fits and Diagnostics for Unusual Observations" (its R
    flag), with the deleted residuals, Cook's distances and the outlier test JMP and
    statsmodels give, and the ANOVA refitted without those runs.

    A run is unusual where its standardized residual exceeds :data:`UNUSUAL_RESIDUAL` in
    size; about 1 run in 20 does by chance. The standardized residual cannot exceed the
    square root of the residual's degrees of freedom, so in a small model it understates a
    run the model does not describe; the deleted residual (the run's residual against the
    model fitted without it, in that fit's standard errors; Minitab's TRES) does not, and
    follows Student's t with ``df_resid - 1`` degrees of freedom where the run belongs to
    the model: ``outlier_p`` is that tail, two-sided, times the number of runs (Bonferroni),
    at most 1 (statsmodels' ``outlier_test``). Cook's distance measures how far the run
    moves the fitted values (Minitab's COOK): about 1 and more is much.

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite response
        are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions, typ, alpha_to_remove
        The ANOVA's model, as :func:`anova` takes them (unset, given a design, the
        design's); the refit keeps its terms (a reduced
        model is not reduced again, so that only the runs change).
    alpha
        Significance level of the refit's comparison [-].

    Returns
    -------
    pandas.DataFrame
        One row per unusual run, largest standardized residual in size first: the runs'
        columns of :func:`residuals`, then :data:`UNUSUAL_COLUMNS`: ``observed``,
        ``fitted`` and ``residual`` [response unit], ``std_residual``,
        ``deleted_residual``, ``outlier_p`` (Bonferroni-adjusted), ``leverage`` and
        ``cooks_distance`` [-]. Empty where no run is unusual or there is no residual.
        ``attrs``: ``response``, ``formula``, ``threshold``, ``alpha``, ``n`` (the runs
        fitted), ``df_resid`` (the model's), ``largest_other_cooks`` (the largest Cook's
        distance of the other runs), ``without`` (the ANOVA of the same terms without the
        unusual runs, :func:`anova`'s table, or None) and ``without_note`` (why there is
        none: too few runs left, a term no longer estimable; empty otherwise).

    Examples
    --------
    A 2 x 3 design, twice, whose test 6 lies about 0.02 above a model of main effects: its
    standardized residual looks mild, its deleted residual does not, and without it S is
    significant:

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor, anova, unusual_runs
    >>> factors = [Factor("S", (0.0, 1.0)), Factor("WP", (1.0, 2.0, 3.0))]
    >>> runs = pd.DataFrame({
    ...     "test": range(1, 13), "S": [0.0, 1.0] * 6, "WP": [1.0, 1.0, 2.0, 2.0, 3.0, 3.0] * 2,
    ...     "MU": [0.301, 0.304, 0.348, 0.357, 0.401, 0.425, 0.3, 0.306, 0.352, 0.351, 0.4, 0.406],
    ... })
    >>> table = unusual_runs(runs, factors, "MU", interactions=False)
    >>> columns = ["test", "std_residual", "deleted_residual", "outlier_p", "cooks_distance"]
    >>> print(table[columns].round(3).to_string(index=False))
     test  std_residual  deleted_residual  outlier_p  cooks_distance
        6         2.677             7.752      0.001           0.896
    >>> with_it = anova(runs, factors, "MU", interactions=False).set_index("term")
    >>> without = table.attrs["without"].set_index("term")
    >>> p, q = with_it.loc["S", "p_value"], without.loc["S", "p_value"]
    >>> print(f"S: p = {p:.3f}, {q:.3f} without")
    S: p = 0.053, 0.009 without
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    from scipy import stats

    problem = alpha_problem(alpha, usual="0.05 is usual")
    if problem:
        raise ValueError(f"alpha: {problem}")
    interactions, typ, alpha_to_remove = _model_settings(
        factors, interactions, typ, alpha_to_remove
    )
    factors = _factors(factors)
    summary = summary.reset_index(drop=True)  # labels are positions: the runs dropped below
    data, y, exog, formula = _model_arrays(
        summary, factors, response, interactions, alpha_to_remove=alpha_to_remove
    )
    frame = _residuals_of(data, y, exog, formula, response)
    # the columns of a table with rows also where none is unusual (the residuals' columns,
    # without outlier_p, had broken code written against a study with an outlier)
    out = frame.iloc[0:0].reindex(columns=[*_run_columns(data).columns, *UNUSUAL_COLUMNS])
    out.attrs.update(
        response=response,
        formula=formula,
        threshold=UNUSUAL_RESIDUAL,
        alpha=float(alpha),
        n=int(y.size),
        df_resid=float(frame.attrs.get("df_resid", math.nan)),
        largest_other_cooks=math.nan,
        without=None,
        without_note="",
    )
    z = pd.to_numeric(frame.get("std_residual"), errors="coerce").to_numpy(dtype=float)
    large = np.abs(np.nan_to_num(z)) > UNUSUAL_RESIDUAL
    if not large.any():
        return out
    df = float(frame.attrs["df_resid"])
    t = frame["deleted_residual"].to_numpy(dtype=float)
    with np.errstate(invalid="ignore"):
        p = np.minimum(1.0, y.size * 2.0 * stats.t.sf(np.abs(t), df - 1.0))
    order = np.argsort(-np.abs(z[large]), kind="stable")
    rows = frame.loc[large].assign(outlier_p=p[large]).iloc[order]
    attrs = dict(out.attrs)
    out = rows[[*_run_columns(data).columns, *UNUSUAL_COLUMNS]].reset_index(drop=True)
    out.attrs.update(attrs)
    cooks = frame["cooks_distance"].to_numpy(dtype=float)
    if (~large).any() and np.isfinite(cooks[~large]).any():
        out.attrs["largest_other_cooks"] = float(np.nanmax(cooks[~large]))
    try:
        refit = _refit_without(summary, factors, response, formula, exog, data.index[large])
        if refit is None:
            out.attrs["without_note"] = (
                "its only term is the curvature of the centre points, which the refit does "
                "not take"  # (not "no terms" beside a Curvature row: an analysis review)
                if "Ct Pt" in formula
                else "the model has no terms"
            )
            return out
        table = anova(refit.kept, factors, response, interactions=refit.terms, typ=typ)
    except ValueError as exc:  # too few runs left for the model
        out.attrs["without_note"] = str(exc)
        return out
    if not refit.same:
        out.attrs["without_note"] = "the runs left cannot estimate the same model"
        return out
    out.attrs["without"] = table
    return out


class _Refit(NamedTuple):
    """A model fitted again without some runs (:func:`_refit_without`): the summary's rows
    left, their response [response unit] and model matrix [-], the model's terms, and
    whether those runs estimate the same model."""

    kept: pd.DataFrame
    y: np.ndarray
    exog: np.ndarray
    terms: list[str]
    same: bool


def _refit_without(
    summary: pd.DataFrame,
    factors: Sequence[Any],
    response: str,
    formula: str,
    exog: np.ndarray,
    drop: Iterable[Any],
) -> _Refit | None:
    """The model of ``formula`` and ``exog`` (:func:`_model_arrays`') fitted again to
    ``summary`` without its rows ``drop`` (labels): its terms as the first fit took them (a
    reduced model is not reduced again, so that only the runs change), shared by
    :func:`unusual_runs` and :func:`brakeca.boxcox.box_cox`. ``same`` is False where a term
    lost its runs: a level gone (the term left out), a cell emptied (the same terms, fewer
    estimable). None where the model has no terms.

    Raises
    ------
    ValueError
        Too few runs are left for the model (as :func:`_model_arrays`).
    """
    terms = [t.strip() for t in formula.split("~", 1)[1].split("+")]
    terms = [t for t in terms if t not in ("1", "Ct Pt")]
    if not terms:
        return None
    kept = summary.drop(index=drop)
    _, y, exog2, formula2 = _model_arrays(kept, factors, response, terms)
    same = formula2 == formula and np.linalg.matrix_rank(exog2) >= np.linalg.matrix_rank(exog)
    return _Refit(kept, y, exog2, terms, same)


def _exog(frame: pd.DataFrame, terms: Sequence[str], n: int) -> np.ndarray:
    """The model matrix of ``terms`` on ``frame`` (the intercept alone when empty) [-]."""
    if not terms:
        return np.ones((n, 1))
    return np.asarray(_fit_anova(frame, terms, check_only=True)[0].model.exog, dtype=float)


def _fitted_model(
    summary: pd.DataFrame,
    factors: Iterable[Any],
    response: str,
    interactions: Model,
    alpha_to_remove: float | None,
) -> tuple[list[Factor], pd.DataFrame, np.ndarray, np.ndarray, Any]:
    """The model :func:`anova` fits, as it makes it: the factors, the usable rows of
    ``summary``, their response [response unit], the centre points' mask and
    :func:`_model`'s (frame, term names, terms, notes) of the other runs (None without
    usable rows); shared by :func:`_model_arrays` and :func:`factor_trends`."""
    factors = _factors(factors)
    if _is_term_list(interactions):  # checked once, before any work
        interactions = canonical_terms(interactions, [f.name for f in factors], name="interactions")
    data = _clean(summary, factors, response)
    y = data[response].to_numpy(dtype=float)
    if y.size == 0:
        return factors, data, y, np.zeros(0, dtype=bool), None
    centre = _center_mask(data, factors)
    model = _model(
        data.loc[~centre],
        factors,
        y[~centre],
        interactions,
        y_center=y[centre],
        alpha_to_remove=alpha_to_remove,
    )
    return factors, data, y, centre, model


def _model_arrays(
    summary: pd.DataFrame,
    factors: Iterable[Any],
    response: str,
    interactions: Model,
    *,
    alpha_to_remove: float | None = None,
) -> tuple[pd.DataFrame, np.ndarray, np.ndarray, str]:
    """The model :func:`anova` fits, as arrays: the usable rows of ``summary``, their
    response [response unit], the model matrix [-] (:func:`model_matrix`) and the formula
    (``"MU ~ S + WP + S:WP"``, named by the response; empty, and a one-column matrix,
    without usable rows)."""
    _check_alpha_to_remove(alpha_to_remove)
    _model_order(interactions)
    _, data, y, centre, model = _fitted_model(
        summary, factors, response, interactions, alpha_to_remove
    )
    if model is None:
        return data, y, np.ones((0, 1)), ""
    n_c = int(centre.sum())
    frame, term_names, terms, _ = model
    names = [term_names[t] for t in terms] + (["Ct Pt"] if n_c else [])
    formula = f"{response} ~ " + (" + ".join(names) if names else "1")
    cube = _exog(frame, terms, y.size - n_c)
    if not n_c:
        return data, y, cube, formula
    # the centre points' rows (the intercept and the indicator, "Ct Pt", which fits their
    # mean whatever their other columns hold), put back in the runs' order
    stacked = _with_centre_rows(cube, n_c)
    exog = np.empty_like(stacked)
    exog[~centre] = stacked[: len(cube)]
    exog[centre] = stacked[len(cube) :]
    return data, y, exog, formula


def model_matrix(
    summary: pd.DataFrame,
    factors: Iterable[Any],
    response: str,
    *,
    interactions: Model = True,
) -> np.ndarray:
    """The model matrix of the model :func:`anova` fits, one row per usable run.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
    factors
        The design's factors.
    response
        Response column; it selects the usable runs (finished, with a finite value), in the
        order of :func:`residuals`.
    interactions
        Include two-factor interactions, the terms up through an order, or the terms
        listed, as in :func:`anova`.

    Returns
    -------
    numpy.ndarray
        Shape (runs, columns) [-]: the intercept, then the terms' treatment-coded columns
        (terms aliased with earlier ones left out, as in :func:`anova`; the columns can still
        be dependent where cells of the design are empty); with centre points, a last column
        indicating them (Ct Pt), their other columns 0 but the intercept.
    """
    return _model_arrays(summary, factors, response, interactions)[2]


def ranked_effects(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
) -> pd.DataFrame:
    """Model terms ranked by sum of squares, for a Pareto chart.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions
        Include two-factor interactions, the terms up through an order, or the terms
        listed (as in :func:`anova`). Unset, given a design (or a campaign result), the
        design's model, its ANOVA type and backward elimination as :func:`anova` takes
        them; pass ``design.factors`` for the whole model of two-factor interactions.

    Returns
    -------
    pandas.DataFrame
        Columns ``rank`` (1 = largest), ``term``, ``kind`` (``"main"``, ``"interaction"`` or,
        with centre points, ``"curvature"``),
        ``df``, ``sum_sq``, ``percent_contribution`` [%], ``cumulative_percent`` [%], ``F``,
        ``p_value`` and ``effect`` [response unit]. ``effect`` is the classical effect for
        two-level factors, mean at ``levels[1]`` minus mean at ``levels[0]``, and for the
        interaction of two two-level factors ``(m11 - m10 - m01 + m00) / 2`` from the cell
        means (of q factors, the signed sum of the 2^q cell means over 2^(q-1)); NaN
        otherwise. These are plain differences of means: once a run has failed
        (an unbalanced design) they are not adjusted for the other factors, unlike the
        effects of :func:`two_level_effects` (twice the least-squares coefficient), which
        then differ from them. The residual is not ranked.

    References
    ----------
    Wahlström (2016), Section 4, doi:10.1155/2016/8181260.
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    if _design_of(factors) is None:  # (a design stays one: anova takes its settings)
        factors = _factors(factors)  # (an iterator of factors is read once)
    table = anova(summary, factors, response, interactions=interactions)
    return _rank_terms(table, summary, _factors(factors), response)


def _rank_terms(
    table: pd.DataFrame, summary: pd.DataFrame, factors: list[Factor], response: str
) -> pd.DataFrame:
    """:func:`ranked_effects` from the ANOVA table ``table`` of ``response``."""
    columns = [
        "rank",
        "term",
        "kind",
        "df",
        "sum_sq",
        "percent_contribution",
        "cumulative_percent",
        "F",
        "p_value",
        "effect",
    ]
    terms = table.loc[table["term"] != "Residual"].copy()
    if terms.empty:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in columns})
    data = _cube(_clean(summary, factors, response), factors)
    by_name = {f.name: f for f in factors}
    y = data[response].to_numpy(dtype=float)

    def effect(term: str) -> float:
        parts = term.split(":")
        if any(p not in by_name or len(by_name[p].levels) != 2 for p in parts):
            return math.nan
        if len(parts) == 1:
            codes = _codes(data, by_name[parts[0]])
            if not (np.any(codes == 0) and np.any(codes == 1)):
                return math.nan
            return float(y[codes == 1].mean() - y[codes == 0].mean())
        # the contrast of the cell means of the term's factors: for two factors
        # (m11 - m10 - m01 + m00) / 2, for q factors the signed sum over 2^q cells / 2^(q-1)
        codes = np.column_stack([_codes(data, by_name[p]) for p in parts])
        total = 0.0
        for cell in itertools.product((0, 1), repeat=len(parts)):
            at = np.all(codes == np.array(cell), axis=1)
            if not at.any():
                return math.nan  # an empty cell: no classical effect
            sign = (-1) ** (len(parts) - sum(cell))
            total += sign * float(y[at].mean())
        return total / 2.0 ** (len(parts) - 1)

    terms["kind"] = [
        "interaction" if ":" in t else "curvature" if t == CURVATURE else "main"
        for t in terms["term"]
    ]
    terms["effect"] = [effect(t) for t in terms["term"]]
    terms = terms.sort_values("sum_sq", ascending=False, kind="stable").reset_index(drop=True)
    terms["rank"] = np.arange(1, len(terms) + 1)
    terms["cumulative_percent"] = terms["percent_contribution"].cumsum()
    out = terms[columns].copy()
    out.attrs.update(table.attrs)
    return out


def alias_structure(tests: pd.DataFrame, factors: Iterable[Any]) -> pd.DataFrame:
    """The alias structure of a design's tests, as Minitab prints it for a fractional
    factorial before it runs: each main effect and two-factor interaction the tests can
    estimate, with the effects of up to three factors they cannot tell it apart from.

    Parameters
    ----------
    tests
        One row per test, a column per factor holding its level [design unit] (e.g.
        ``pandas.DataFrame(design.combinations())``); no response is needed. Centre points
        are left out (they estimate no effect).
    factors
        The design's factors.

    Returns
    -------
    pandas.DataFrame
        Columns ``term`` (``"S"``, ``"S:WP"``) and ``aliases`` (``"WR:A + ..."``, empty when
        none), one row per estimable term, main effects first, then the two-factor
        interactions in design order, each alias chain once (named by its first member).
        ``attrs["not_estimable"]`` lists the two-factor interactions that are aliased only
        with a combination of the terms before them (partial confounding of a non-regular
        design), which no row names, and ``attrs["with_mean"]`` those constant over the
        tests (aliased with the mean); ``attrs["aliased_main_effects"]`` the pairs (main
        effect, main effect) the tests cannot tell apart (a run table of resolution II,
        which a fraction's generators are refused for); ``attrs["max_correlation"]`` is
        the largest absolute correlation between the columns of two different estimable
        terms, or of a main effect and a two-factor interaction the tests cannot estimate
        beside the main effects (a saturated Plackett-Burman design's) [-]: 0 where they
        are orthogonal (a full factorial, a regular fraction's clear terms), between 0 and 1
        where terms are partly confounded (a Plackett-Burman design's main effects and
        two-factor interactions).
    """
    factors = _factors(factors)
    frame, names, _ = _coded_frame(_cube(tests, factors), factors)
    columns = list(names)
    terms = [f"C({c})" for c in columns] + [
        f"C({a}):C({b})" for a, b in itertools.combinations(columns, 2)
    ]
    kept, left_out = _estimable_terms(frame, terms) if terms else ([], {})
    chains = _alias_chains(frame, kept)
    shown = set(kept) | {a for t in kept for a, _ in chains[t]}
    out = pd.DataFrame(
        {
            "term": [_display_term(t, names) for t in kept],
            "aliases": [_chain_text(chains[t], names) for t in kept],
        },
        columns=["term", "aliases"],
    )
    hidden = [t for t in left_out if t not in shown]
    constant = [t for t in hidden if _constant_term(frame, t)]
    out.attrs["not_estimable"] = [_display_term(t, names) for t in hidden if t not in constant]
    out.attrs["with_mean"] = [_display_term(t, names) for t in constant]
    out.attrs["aliased_main_effects"] = [
        (_display_term(t, names), _display_term(a, names))
        for t in kept
        if ":" not in t
        for a, _ in chains[t]
        if ":" not in a
    ]
    # and of a main effect with a two-factor interaction the tests cannot estimate beside
    # the main effects (a saturated Plackett-Burman design: its +-1/3 had read as 0, "partly
    # confounded" without a number; a design review)
    mains = [t for t in kept if ":" not in t]
    unseen = [t for t in hidden if t not in constant and ":" in t]
    out.attrs["max_correlation"] = max(
        _largest_correlation(frame, kept), _largest_correlation(frame, mains, unseen)
    )
    return out


def _largest_correlation(
    frame: pd.DataFrame, terms: Sequence[str], others: Sequence[str] | None = None
) -> float:
    """The largest absolute correlation between a column of one term and a column of
    another [-] (0 for fewer than two terms or orthogonal ones); with ``others``, between a
    column of a term of ``terms`` and one of ``others``."""

    def block(term: str) -> np.ndarray:
        cols = _term_columns(frame, term)
        cols = cols - cols.mean(axis=0)
        norms = np.linalg.norm(cols, axis=0)
        return cols[:, norms > 0] / norms[norms > 0]

    blocks = [block(t) for t in terms]
    if others is None:
        pairs = list(itertools.combinations(blocks, 2))
    else:
        theirs = [block(t) for t in others]  # each once (a diff review: PB44 took 5 s)
        pairs = [(a, b) for a in blocks for b in theirs]
    largest = 0.0
    for a, b in pairs:
        if a.size and b.size:
            largest = max(largest, float(np.max(np.abs(a.T @ b))))
    return 0.0 if largest < 1e-12 else largest


def interaction_aliases(tests: pd.DataFrame, factors: Iterable[Any]) -> dict[tuple[str, str], str]:
    """The two-factor interactions each pair of factors' interaction cannot be told apart
    from, as signed text: what an interaction plot's panel shows for a fraction.

    Parameters
    ----------
    tests
        One row per test, a column per factor [design unit].
    factors
        The design's factors.

    Returns
    -------
    dict
        ``(a, b)`` (factor names in design order) to e.g. ``"WR:modulus + mu0:slope"``
        (the other two-factor interactions in the pair's alias chain, signed relative to it);
        only pairs that have such aliases (none for a full factorial).
    """
    factors = _factors(factors)
    frame, names, _ = _coded_frame(_cube(tests, factors), factors)
    columns = list(names)
    pairs = {f"C({a}):C({b})": (names[a], names[b]) for a, b in itertools.combinations(columns, 2)}
    if not pairs:
        return {}
    chains = _alias_chains(frame, list(pairs))
    out = {}
    for term, pair in pairs.items():
        two = [(t, sign) for t, sign in chains[term] if t.count(":") == 1]
        if two:
            out[pair] = _chain_text(two, names)
    return out


# --- two-level effects ---------------------------------------------------------------------

#: Columns of :func:`two_level_effects`, in order.
EFFECTS_COLUMNS: tuple[str, ...] = (
    "term",
    "order",
    "effect",
    "coefficient",
    "se",
    "t",
    "p_value",
    "vif",
    "significant",
    "aliases",
)

#: An interaction whose contrast column correlates this much or more with a column kept
#: before it is left out of :func:`two_level_effects` (partial confounding: 1/3 in a
#: 12-run Plackett-Burman design; a failed run of a 16-run fraction gives 1/15) [-].
_MAX_EFFECT_CORRELATION = 0.2


def _planned_frame(
    summary: pd.DataFrame, factors: Sequence[Factor], columns: Sequence[str]
) -> pd.DataFrame:
    """The coded ``columns`` (:func:`_coded_frame`'s) of every run of ``summary`` at the
    factors' levels, whatever its status or response: the design as planned, less its
    centre points and any row whose factor values match no level."""
    known = np.ones(len(summary), dtype=bool)
    for f in factors:
        known &= np.array([f.level_index(v) is not None for v in summary[f.name].to_list()])
    rows = summary.loc[known]
    rows = rows.loc[~_center_mask(rows, factors)]
    frame, _, _ = _coded_frame(rows, factors)
    return frame[list(columns)]


#: Fewest effects Lenth's method is applied to [-].
_MIN_LENTH_EFFECTS = 3


def _effect_terms(
    frame: pd.DataFrame, candidates: Sequence[str], planned: pd.DataFrame | None = None
) -> tuple[list[str], list[str], bool, list[str]]:
    """The terms :func:`two_level_effects` fits, the interactions it leaves out as partly
    confounded, whether the design is non-regular, and the interactions the runs that
    finished cannot estimate although the design could.

    ``frame`` holds the runs that finished; ``planned`` (the same columns) every run of the
    design, failed ones too (``frame`` when None): the design's structure, its alias chains
    and whether it is regular, is read from the runs planned, so that runs lost from a
    full factorial or a regular fraction do not make it "non-regular" (a DoE review: five
    failed runs of a replicated 2^3 correlated WP:A with WP by 0.27, and the effects table
    fell to the main effects, its error holding an interaction the ANOVA found with
    p = 1e-6).

    Main effects are kept when estimable (:func:`_estimable_terms`). A design in which an
    interaction's contrast column correlates with a main effect's by
    :data:`_MAX_EFFECT_CORRELATION` or more, without being aliased with the terms kept
    (partial confounding, as in every Plackett-Burman design), is non-regular: its main
    effects alone are fitted, as Minitab fits a Plackett-Burman design, since filling its
    spare degrees of freedom with the first interactions found would bias them. Otherwise an
    interaction is kept when the runs that finished estimate it and its column's correlation
    with every column kept so far is below :data:`_MAX_EFFECT_CORRELATION` in the design: a
    full factorial or a regular fraction keeps one term per alias chain, all orthogonal as
    planned.
    """
    planned = frame if planned is None else planned
    mains = [t for t in candidates if ":" not in t]
    kept, _ = _estimable_terms(frame, mains)
    columns = [_term_columns(planned, t)[:, 0] for t in kept]
    rank = _rank(*(c[:, None] for c in columns)) if columns else 1
    fitted = [_term_columns(frame, t)[:, 0] for t in kept]
    fitted_rank = _rank(*(c[:, None] for c in fitted)) if fitted else 1

    def correlation(column: np.ndarray, others: Sequence[np.ndarray]) -> float:
        return max(
            (abs(float(np.corrcoef(column, c)[0, 1])) for c in others if np.ptp(c) > 0),
            default=0.0,
        )

    interactions = [t for t in candidates if ":" in t]
    column_of = {t: _term_columns(planned, t)[:, 0] for t in interactions}
    main_columns = list(columns)
    for term in interactions:
        column = column_of[term]
        if _rank(*(c[:, None] for c in main_columns), column[:, None]) == rank:
            continue  # aliased with a main effect (or a combination of them)
        if correlation(column, main_columns) >= _MAX_EFFECT_CORRELATION:
            return kept, interactions, True, []
    partial: list[str] = []
    lost: list[str] = []
    chains = list(columns)  # the planned columns of the terms kept and lost: one per chain
    for term in interactions:
        column = column_of[term]
        new_rank = _rank(*(c[:, None] for c in chains), column[:, None])
        if new_rank == rank:
            continue  # aliased with a term kept or lost: its chain is named by that one
        if correlation(column, columns) >= _MAX_EFFECT_CORRELATION:
            partial.append(term)
            continue
        chains.append(column)
        rank = new_rank
        fitted_column = _term_columns(frame, term)[:, 0]
        new_fitted_rank = _rank(*(c[:, None] for c in fitted), fitted_column[:, None])
        if new_fitted_rank == fitted_rank:
            lost.append(term)  # the runs lost leave it aliased with the terms kept
            continue
        kept.append(term)
        columns.append(column)
        fitted.append(fitted_column)
        fitted_rank = new_fitted_rank
    return kept, partial, False, lost


#: Lenth's PSE below this fraction of the largest effect [-] is round-off: the data have no
#: scatter (a deterministic response), and the t values measure the floating-point error.
_ROUND_OFF_PSE = 1e-9


def _lenth_pse(contrasts: np.ndarray) -> float:
    """Lenth's pseudo standard error of unreplicated effects [response unit]:
    ``s0 = 1.5 median |c|``, then ``1.5 median`` of the ``|c| < 2.5 s0`` (Lenth 1989)."""
    magnitude = np.abs(contrasts)
    s0 = 1.5 * float(np.median(magnitude))
    small = magnitude[magnitude < 2.5 * s0]
    return 1.5 * float(np.median(small)) if small.size else math.nan


def two_level_effects(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    alpha: float = 0.05,
    main_effects_only: bool | None = None,
    model_terms: Sequence[str] | None = None,
) -> pd.DataFrame:
    """Effects of a design whose factors all have two levels, with their significance, as
    Minitab's "Coded Coefficients" table and Pareto chart of standardized effects show them.

    The factors are coded -1 (first level) and +1 (second level); the main effects and the
    interactions the data can estimate are fitted by least squares, and each effect is twice
    its coefficient: the mean response at +1 minus the mean at -1, for an orthogonal design.
    The terms are taken in order of their number of factors; an interaction is left out when
    it is aliased with the terms before it (its chain is then named by its lowest-order
    member) or correlated with one of them by :data:`_MAX_EFFECT_CORRELATION` or more. A
    non-regular design, whose interactions are partly confounded with the main effects (every
    Plackett-Burman design), is fitted with its main effects alone, as Minitab fits it: its
    spare degrees of freedom would otherwise take the first interactions found and bias the
    main effects. A full factorial or a regular fraction, unreplicated, is saturated: as many
    effects as distinct runs less one, all orthogonal (interactions of more factors are
    searched only while there are at most 1000 candidate terms).

    As in Minitab's coded coefficients, the standard error of an effect comes from the
    residual mean square of the fitted effects whenever it has degrees of freedom: the pure
    error of replicates (runs that repeat a factor-level combination), together with the
    degrees of freedom the fitted terms leave (a Plackett-Burman design's spare columns, the
    interactions left out); ``t`` then has the residual's degrees of freedom, and the p-values
    equal the ANOVA's of the same terms. A saturated model has no residual: its effects are
    judged against Lenth's pseudo standard error (PSE) of the effects, the method Minitab's
    Pareto chart and normal plot use for it: with ``m`` effects, ``s0 = 1.5 median|effect|``,
    ``PSE = 1.5 median{|effect| : |effect| < 2.5 s0}``, ``t = effect / PSE`` with ``m / 3``
    degrees of freedom (Lenth's approximation, conservative for few effects: JMP simulates
    the reference distribution instead, and calls more effects active in an 8-run fraction).
    It assumes that few effects are active (effect sparsity), which is what screening designs
    rely on. Where the columns are not orthogonal (a run table, a failed run) the effects'
    variances differ: each effect is scaled by the square root of its variance relative to an
    orthogonal design's before the PSE is taken, and its standard error is the PSE times that
    root.

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite response
        are fitted; every row at the factors' levels, failed ones too, is the design as
        planned, whose regularity and alias chains the effects follow).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    alpha
        Significance level of ``significant`` and the margins of error [-].
    main_effects_only
        Fit the main effects alone, whatever the data could estimate besides (a
        Plackett-Burman design's analysis, which :func:`analyze` asks for from the design).
    model_terms
        Fit these terms alone (display names, ``"S"``, ``"S:WR"``; e.g. those of an ANOVA
        reduced by backward elimination, which :func:`analyze` passes); terms of a factor
        that does not vary in the data are skipped. With both this and
        ``main_effects_only`` unset and ``factors`` a design (or a campaign result), the
        design's analysis decides them as :func:`analyze` does: a Plackett-Burman design's
        main effects alone, and where the design reduces its ANOVA (``alpha_to_remove``) or
        sets its model (``model_order``, ``model_terms``), that ANOVA's terms; otherwise
        every effect the data can estimate.

    Returns
    -------
    pandas.DataFrame
        :data:`EFFECTS_COLUMNS`, one row per estimated term, largest ``|t|`` first: ``term``
        (``"S"``, ``"S:WR"``), ``order`` (factors in the term), ``effect`` and
        ``coefficient`` [response unit], ``se`` (standard error of the effect) [response
        unit], ``t`` and ``p_value`` [-], ``vif`` (the variance inflation factor, as in
        Minitab's table: ``1 / (1 - R_j^2)`` of the term's column regressed on the others',
        1 where the design is orthogonal) [-], ``significant`` (``p_value < alpha``) and
        ``aliases`` (the terms of up to three factors the design cannot tell apart from it).
        With centre points whose term is tested, a last row :data:`CENTER_TERM` (``"Ct
        Pt"``, order 0), as Minitab's coded coefficients end: its ``coefficient`` (the
        centre points' mean less the model's value at the centre), ``se`` (twice its
        coefficient's standard error, as in the other rows, so that t = 2 coefficient / se),
        ``t``, ``p_value``, ``vif`` and ``significant``, with no ``effect`` (NaN).
        Empty (with ``attrs["note"]`` saying why) when a factor that varies has other than two
        levels, the response is constant, or too few effects can be estimated (none with
        replicates; fewer than three for Lenth's method). ``attrs`` carries ``method``
        (``"Lenth"``; ``"pure error"`` when the residual is pure error alone, of replicates or
        centre points;
        ``"residual"`` otherwise), ``df``, ``pse`` (Lenth's PSE, NaN without Lenth)
        [response unit], ``margin_of_error`` (the effect a term of an orthogonal design must
        exceed to be significant at ``alpha``) and ``simultaneous_margin`` (the same for all
        ``m`` effects at once, Lenth's SME) [response unit], ``alpha``, ``n``,
        ``center_points`` (their number; they are fitted by an indicator, Minitab's "Ct Pt",
        and take no part in the effects), ``curvature`` (the Ct Pt row: ``coefficient``, the
        centre points' mean less the model's value at the centre [response unit], ``se``,
        ``t`` and ``p_value``; NaN without centre points or with Lenth's method; and
        ``aliases``, the factors it is confounded with, when one has a single level in the
        other runs), ``terms_given`` (whether ``model_terms`` chose the terms),
        ``model_terms`` (those terms as given, in the model's order, or None) and ``note``
        (what the reader must know: a design that is not orthogonal, a non-regular design
        fitted with its main effects alone, interactions left out as partly confounded or
        as not estimable from the runs analysed though the design could estimate them, an
        error that is not pure error alone, a PSE of zero; empty otherwise).

    References
    ----------
    R. V. Lenth, "Quick and easy analysis of unreplicated factorials", Technometrics 31(4),
    469-473, 1989. doi:10.1080/00401706.1989.10488595

    Examples
    --------
    A replicated 2² design (8 runs) whose MU has known effects: S +0.05, A +0.11 and their
    interaction +0.02 (effects as Minitab gives them: the change from the low to the high level):

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor
    >>> factors = [Factor("S", (0.0, 1.0)), Factor("A", (10.0, 20.0), unit="%")]
    >>> runs = pd.DataFrame({
    ...     "S": [0.0, 1.0] * 4,
    ...     "A": [10.0, 10.0, 20.0, 20.0] * 2,
    ...     "MU": [0.30, 0.34, 0.40, 0.46, 0.32, 0.34, 0.40, 0.48],
    ... })
    >>> from brakeca.analysis import two_level_effects
    >>> table = two_level_effects(runs, factors, "MU")  # largest first
    >>> print(table[["term", "effect", "t", "p_value"]].round(4).to_string(index=False))
    term  effect       t  p_value
       A    0.11 15.5563   0.0001
       S    0.05  7.0711   0.0021
     S:A    0.02  2.8284   0.0474
    """
    from scipy import stats

    from brakeca.design import _points  # "1 centre point", "3 centre points"

    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    design = _design_of(factors)
    if design is not None and main_effects_only is None and model_terms is None:
        # the design's analysis, as analyze() takes it (a diff review: given a design or a
        # campaign this table fitted every effect beside the report's reduced one)
        main_effects_only = design.plackett_burman is not None
        _, _, alpha_to_remove = _model_settings(factors, None, None, None)
        chosen = design.anova_model
        if (
            alpha_to_remove is not None
            or not isinstance(chosen, int)
            or chosen != (1 if main_effects_only else 2)
        ):
            table = anova(summary, factors, response)  # the design's model, as anova takes it
            model_terms = [t for t in table["term"] if t not in ("Residual", CURVATURE)]
    main_effects_only = bool(main_effects_only)

    problem = alpha_problem(alpha, usual="0.05 is usual")
    if problem:
        raise ValueError(f"alpha: {problem}")
    factors = _factors(factors)
    data = _clean(summary, factors, response)
    centre = _center_mask(data, factors)
    y_center = data.loc[centre, response].to_numpy(dtype=float)
    n_c = y_center.size
    data = data.loc[~centre]
    y = data[response].to_numpy(dtype=float)
    empty = pd.DataFrame({c: pd.Series(dtype=float) for c in EFFECTS_COLUMNS})
    empty = empty.astype({"term": object, "aliases": object, "significant": bool})

    def none(why: str) -> pd.DataFrame:
        out = empty.copy()
        out.attrs.update(note=why, method=None, n=int(y.size), alpha=alpha)
        return out

    frame, names, single = _coded_frame(data, factors, y)
    for f in factors:
        if f.name in names.values() and len(f.levels) != 2:
            return none(
                f"factor {f.name} has {len(f.levels)} levels; effects need two-level factors"
            )
    if not names:
        return none("no factor varies in the data")
    if _is_constant(np.concatenate([y, y_center])):
        return none("the response is constant: no effects")
    cells = list(names)
    n_points = int(frame.groupby(cells, sort=False).ngroups) + (1 if n_c else 0)
    partial: list[str] = []
    lost: list[str] = []
    planned: pd.DataFrame | None = None
    nonregular = False
    if model_terms is not None:
        column = {name: c for c, name in names.items()}
        wanted = [
            ":".join(f"C({column[part]})" for part in term.split(":"))
            for term in model_terms
            if all(part in column for part in term.split(":"))
        ]
        terms = _estimable_terms(frame, wanted)[0]
    elif main_effects_only:
        terms = _estimable_terms(frame, _candidate_terms(cells, 1))[0]
    else:
        planned = _planned_frame(summary, factors, list(names))
        terms, partial, nonregular, lost = _effect_terms(
            frame, _candidate_terms(cells, len(cells)), planned
        )
    df_pe = float(y.size + n_c - n_points)
    # the terms kept are estimable in turn; centre points add their indicator ("Ct Pt")
    df_resid = float(y.size + n_c - 1 - len(terms) - (1 if n_c else 0))
    if df_resid >= 1:
        method = "pure error" if df_resid == df_pe else "residual"
    else:
        method = "Lenth"
    if model_terms is not None and not terms:
        return none(
            "no term of the model given varies in the data (e.g. backward elimination "
            "removed every term)"
        )
    if len(terms) < (1 if method != "Lenth" else _MIN_LENTH_EFFECTS):
        return none(
            f"{len(terms)} effect(s) can be estimated from {n_points} distinct runs; "
            + (
                "none to test"
                if method != "Lenth"
                else f"Lenth's method needs {_MIN_LENTH_EFFECTS} or more"
            )
        )
    exog = np.column_stack([np.ones(y.size)] + [_term_columns(frame, t)[:, 0] for t in terms])
    y_all = y
    curvature: dict[str, Any] = dict.fromkeys(("coefficient", "se", "t", "p_value"), math.nan)
    if n_c:  # the centre points: every factor 0, and an indicator that fits their mean
        exog = _with_centre_rows(exog, n_c)
        y_all = np.concatenate([y, y_center])
    coef, *_ = np.linalg.lstsq(exog, y_all, rcond=None)
    k = len(terms)
    coefficient = coef[1 : 1 + k]
    effect = 2.0 * coefficient
    # each effect's variance relative to an orthogonal design's, sigma^2 * 4 / N with N the
    # runs at the factors' levels (1 for a full factorial or a regular fraction; larger where
    # the columns are correlated)
    inverse = np.diag(np.linalg.pinv(exog.T @ exog))
    relative = y.size * inverse[1 : 1 + k]
    vifs = _vif(exog)  # the terms', then the indicator's with centre points
    vif = vifs[1 : 1 + k]
    exact = False
    if method != "Lenth":  # the fitted effects' residual mean square, as Minitab's
        sse = float(np.sum((y_all - exog @ coef) ** 2))
        exact = exact_fit(sse, y_all)  # the ANOVA's exact fit: no scatter, t infinite
        mse = 0.0 if exact else sse / df_resid
        se = 2.0 * np.sqrt(mse * relative / y.size)
        df, pse = df_resid, math.nan
        margin = float(stats.t.ppf(1 - alpha / 2, df)) * 2.0 * math.sqrt(mse / y.size)
        simultaneous = math.nan
        if n_c:  # Minitab's "Ct Pt" row: the centre points' mean less the fitted one there
            se_c = math.sqrt(mse * inverse[-1])
            t_c = coef[-1] / se_c if se_c > 0 else math.nan
            curvature.update(
                coefficient=float(coef[-1]),
                se=se_c,
                t=t_c,
                p_value=float(2.0 * stats.t.sf(abs(t_c), df)),
            )
    else:  # Lenth's PSE of the effects, each scaled to an orthogonal design's variance
        pse = _lenth_pse(effect / np.sqrt(relative))
        se = pse * np.sqrt(relative)
        df = len(terms) / 3.0
        margin = float(stats.t.ppf(1 - alpha / 2, df)) * pse
        gamma = (1.0 + (1.0 - alpha) ** (1.0 / len(terms))) / 2.0
        simultaneous = float(stats.t.ppf(gamma, df)) * pse
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(np.isfinite(se) & (se > 0), effect / se, np.nan)
    if exact:  # as the ANOVA's F: infinite for an effect above round-off, none for the rest
        real = np.abs(effect) > _ROUND_OFF_PSE * float(np.max(np.abs(effect), initial=0.0))
        t = np.where(real, np.copysign(np.inf, effect), np.nan)
        if n_c:  # as the ANOVA's Curvature: infinite where it is above round-off
            real_c = abs(float(coef[-1])) > _ROUND_OFF_PSE * float(
                np.max(np.abs(effect), initial=abs(float(coef[-1])))
            )
            curvature.update(
                t=math.copysign(math.inf, float(coef[-1])) if real_c else math.nan,
                p_value=0.0 if real_c else math.nan,
            )
    p = 2.0 * stats.t.sf(np.abs(t), df)
    # the design's alias chains, as planned (runs lost may part a chain in the data)
    chains = _alias_chains(frame if planned is None else planned, terms)
    out = pd.DataFrame(
        {
            "term": [_display_term(term, names) for term in terms],
            "order": [term.count(":") + 1 for term in terms],
            "effect": effect,
            "coefficient": coefficient,
            "se": se,
            "t": t,
            "p_value": p,
            "vif": vif,
            "significant": np.isfinite(p) & (p < alpha),
            "aliases": [_chain_text(chains[term], names) for term in terms],
        }
    )
    out = out.sort_values("t", key=np.abs, ascending=False, kind="stable").reset_index(drop=True)
    if n_c and math.isfinite(curvature["p_value"]):  # Minitab's last coded coefficient
        row = {
            "term": CENTER_TERM,
            "order": 0,
            "effect": math.nan,
            "coefficient": curvature["coefficient"],
            "se": 2.0 * curvature["se"],  # as the other rows': t = 2 coefficient / se
            "t": curvature["t"],
            "p_value": curvature["p_value"],
            "vif": float(vifs[-1]),
            "significant": bool(curvature["p_value"] < alpha),
            "aliases": " + ".join(single),
        }
        out = pd.concat([out, pd.DataFrame([row])], ignore_index=True)
    notes = [f"factor {name} has a single level in the data and is left out" for name in single]
    if method == "Lenth" and not (math.isfinite(pse) and pse > 0.0):
        notes.append("Lenth's PSE is zero or undefined (most effects are nil), so t is not defined")
    elif method == "Lenth" and pse < _ROUND_OFF_PSE * float(np.max(np.abs(effect))):
        notes.append(
            f"Lenth's PSE ({pse:.3g}) is at the round-off of the largest effect: the small "
            "effects are nil, the response holds no scatter, so t and p measure round-off, not "
            "evidence"
        )
    elif exact:
        notes.append(
            "exact fit: the model leaves no residual scatter beyond round-off, so t is "
            "infinite and p 0 for every effect above round-off, as the ANOVA's F"
        )
    if not np.allclose(relative, 1.0, rtol=1e-9, atol=1e-9):
        notes.append(
            "the design is not orthogonal (a run table, or failed runs): each effect is twice "
            "its coefficient adjusted for the others, not the plain difference of means, and its "
            f"standard error is up to {math.sqrt(float(np.max(relative))):.3g} times an "
            "orthogonal design's"
        )
    if model_terms is not None:
        notes.append("the terms of the model given are fitted (e.g. a reduced model)")
    elif main_effects_only:
        notes.append("the main effects alone are fitted, as for a Plackett-Burman design")
    elif nonregular:
        notes.append(
            "the design is non-regular (as a Plackett-Burman design is): its interactions are "
            "partly confounded with the main effects, so the main effects alone are fitted"
        )
    elif partial:
        notes.append(
            "interactions partly confounded with the effects before them (a correlation of "
            f"{_MAX_EFFECT_CORRELATION:g} or more) are left out: "
            + ", ".join(_display_term(t, names) for t in partial)
        )
    if lost:
        planned_chains = _alias_chains(planned, lost) if planned is not None else {}
        notes.append(
            "the runs analysed (those that finished with a value of the response) cannot tell "
            "these interactions from the terms before them, as the whole design could, so "
            "they are left out: "
            + ", ".join(
                _display_term(t, names)
                + (f" (= {_chain_text(planned_chains[t], names)})" if planned_chains.get(t) else "")
                for t in lost
            )
        )
    if method == "residual":
        notes.append(
            f"the error is the residual of the fitted effects ({df_resid:g} degrees of freedom"
            + (f", {df_pe:g} of them pure error" if df_pe else "")
            + ")"
        )
    if n_c:
        notes.append(
            f"{_points(n_c, 'centre point')} fitted by {'its' if n_c == 1 else 'their'} own "
            "term (Ct Pt), which keeps them out of the effects"
            + (
                ": with one centre point the saturated model has no error to test curvature "
                "against here (the ANOVA tests it against its residual, the interactions it "
                "leaves out)"
                if method == "Lenth"
                else ""
            )
        )
        if single:  # the centre points differ from the other runs in those factors too
            curvature["aliases"] = " + ".join(single)
            notes.append(_confounded_curvature(single))
    out.attrs.update(
        method=method,
        df=df,
        pse=pse,
        margin_of_error=margin,
        simultaneous_margin=simultaneous,
        alpha=alpha,
        n=int(y.size + n_c),
        terms_given=model_terms is not None,
        model_terms=None if model_terms is None else [str(t) for t in model_terms],
        center_points=n_c,
        curvature=curvature,
        note="; ".join(notes),
    )
    return out[list(EFFECTS_COLUMNS)]


# --- bundle and export -----------------------------------------------------------------------


#: Columns of the table returned by :func:`factor_trends`, in order.
TREND_COLUMNS: tuple[str, ...] = (
    "factor",
    "part",
    "scale",
    "df",
    "sum_sq",
    "F",
    "p_value",
    "percent_of_factor",
    "percent_contribution",
)

#: The parts of a trend by degree (then "degree 5", ...).
_TREND_PARTS = {1: "linear", 2: "quadratic", 3: "cubic", 4: "quartic"}


def _evenly_spaced(values: np.ndarray) -> bool:
    steps = np.diff(np.sort(values))
    return bool(np.allclose(steps, steps[0], rtol=_LEVEL_RTOL, atol=0.0))


def _trend_scale(factor: Factor, levels: np.ndarray) -> tuple[np.ndarray, str]:
    """The scale a factor's trend is taken on: its levels' values where they are evenly
    spaced (or not evenly spaced on the log either, and not log-coded), their log10 where
    the levels are evenly spaced on the log or the factor is log-coded; with the scale's
    name (``"WP"``, ``"log10 WP"``)."""
    positive = bool(np.all(levels > 0))
    if _evenly_spaced(levels) or not positive:
        return levels, factor.name
    logs = np.log10(levels)
    if _evenly_spaced(logs) or factor.coding == "log":
        return logs, f"log10 {factor.name}"
    return levels, factor.name


def _polynomials(scores: np.ndarray) -> np.ndarray:
    """Orthogonal polynomials over the levels (equal weights), as R's ``poly``: column
    ``d - 1`` of degree ``d`` in the scores, orthogonal to the constant and to the lower
    degrees, of unit length, and rising with the score at its highest power."""
    x = scores - scores.mean()
    q, r = np.linalg.qr(np.vander(x, scores.size, increasing=True))
    return (q * np.sign(np.diag(r)))[:, 1:]


def factor_trends(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
    typ: int | str | None = None,
    alpha_to_remove: float | None = None,
) -> pd.DataFrame:
    """The trend of each factor of three or more levels: its main effect split into a
    linear, a quadratic (and higher) part by orthogonal polynomials, each part tested
    against the residual of :func:`anova`'s model.

    The ANOVA takes every factor as categorical: a factor of ``k`` levels has ``k - 1``
    degrees of freedom whatever its levels' values, and its F test says only that the
    levels differ. The parts here say how: a significant linear part and an insignificant
    quadratic one mean the response moves evenly across the levels; a significant quadratic
    part means it curves (or turns) between them. The polynomials are in the level values
    where those are evenly spaced, in their log10 where they are evenly spaced on the log
    (the paper's WP: 1e-15, 1e-14, 1e-13) or the factor is log-coded, else in the values
    (column ``scale``). Each part's sum of squares is the rise in the residual sum of
    squares when its column alone leaves the ANOVA's model, with the other factors in
    sum-to-zero coding and the factor's interactions made of its polynomials (so it is the
    adjusted, Type III, single-degree-of-freedom test: its F is the square of the part's
    t); in a balanced design the parts add up to the factor's sum of squares in the ANOVA,
    and each part's is the classical contrast sum of squares of the level means. F and p
    are taken against the ANOVA's residual mean square and degrees of freedom (with centre
    points, their pure error included; the centre points themselves, at no level of the
    factor, are left out of the parts). Factors with ``choices`` (their levels only number
    the choices) have no trend.

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite
        response are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors, or the design (or a campaign result).
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions, typ, alpha_to_remove
        The ANOVA's model, as :func:`anova` takes them (unset, given a design, the
        design's; the parts are taken in its model and against its residual).

    Returns
    -------
    pandas.DataFrame
        One row per part of each factor of three or more levels in the data: ``factor``,
        ``part`` (``"linear"``, ``"quadratic"``, ...), ``scale`` (the polynomials' variable,
        e.g. ``"log10 WP"``), ``df`` (1), ``sum_sq`` [response unit^2], ``F``, ``p_value``
        [-], ``percent_of_factor`` (the part's share of the factor's sum of squares in the
        ANOVA; the parts add up to 100 % in a balanced design only) and
        ``percent_contribution`` (of the total sum of squares about the mean) [%]; on an
        exact fit (no residual scatter) F is infinite and p 0, as in the ANOVA. Empty where
        no factor has three levels; ``attrs["note"]`` names the factors
        left out and why (not in the model, a rank-deficient design, no residual).

    References
    ----------
    D. C. Montgomery, *Design and Analysis of Experiments*, 8th ed., Wiley, 2013, section
    3.5.4 (orthogonal contrasts) and 5.5 (fitting response curves in a factorial).
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    interactions, typ, alpha_to_remove = _model_settings(
        factors, interactions, typ, alpha_to_remove
    )
    raw = _design_factors(factors) if not isinstance(factors, str) else [factors]
    table = anova(
        summary,
        raw,  # the factors once: an iterator given is read once, by _design_factors
        response,
        interactions=interactions,
        typ=typ,
        alpha_to_remove=alpha_to_remove,
    )
    return _trends(summary, raw, response, table, interactions, alpha_to_remove)


def _trends(
    summary: pd.DataFrame,
    raw: list[Any],
    response: str,
    table: pd.DataFrame,
    interactions: Model,
    alpha_to_remove: float | None,
) -> pd.DataFrame:
    """:func:`factor_trends` of the design's factors ``raw`` (a list: their ``choices``
    kept) against ``table``, the :func:`anova` of the same model (which :func:`analyze`
    has already)."""
    nominal = {
        str(_field(f, "name"))
        for f in raw
        if not isinstance(f, str) and _field(f, "choices") is not None
    }
    out = pd.DataFrame({c: pd.Series(dtype=float) for c in TREND_COLUMNS})
    out = out.astype({"factor": object, "part": object, "scale": object})
    notes: list[str] = []
    # the ANOVA's model, as anova() makes it (the same pooling and elimination)
    factors, data, _, _, model = _fitted_model(
        summary, raw, response, interactions, alpha_to_remove
    )
    if model is None or len(data) < 2 or "Residual" not in set(table["term"]):
        out.attrs["note"] = "no ANOVA to split"
        return out
    frame, term_names, terms, _ = model
    rows = table.set_index("term")
    resid_df = float(rows.loc["Residual", "df"])
    resid_ms = float(rows.loc["Residual", "mean_sq"]) if resid_df > 0.5 else math.nan
    total_ss = float(table.attrs.get("total_sum_sq", math.nan))
    column = {name: col for col, name in term_names.items() if ":" not in col}
    rows_out = []
    for factor in factors:
        if factor.name in nominal or factor.name not in column:
            continue
        col = column[factor.name][2:-1]  # "C(f1)" -> "f1"
        codes = np.array([int(c[1:]) for c in frame[col]])
        present = np.unique(codes)
        if present.size < 3:
            continue
        main = column[factor.name]
        if main not in terms:
            notes.append(f"{factor.name} is not in the model")
            continue
        scores, scale = _trend_scale(factor, np.array([factor.levels[c] for c in present]))
        poly = _polynomials(scores)[np.searchsorted(present, codes)]
        blocks = [np.ones((len(frame), 1))]
        where = 0
        for term in terms:
            block = np.ones((len(frame), 1))
            for part in term.split(":"):
                name = part[2:-1]
                contrasts = poly if name == col else _contrast_columns(frame[name])
                block = _row_kron(block, contrasts)
            if term == main:
                where = sum(b.shape[1] for b in blocks)
            blocks.append(block)
        exog = np.hstack(blocks)
        if np.linalg.matrix_rank(exog) < exog.shape[1]:
            notes.append(f"{factor.name}: the design is rank-deficient (empty cells)")
            continue
        inverse = np.linalg.inv(exog.T @ exog)
        coef = inverse @ (exog.T @ frame["y"].to_numpy(dtype=float))
        factor_ss = float(rows.loc[factor.name, "sum_sq"]) if factor.name in rows.index else 0.0
        for degree in range(1, present.size):
            j = where + degree - 1
            ss = float(coef[j] ** 2 / inverse[j, j])
            if resid_ms > 0:
                f_value = ss / resid_ms
            elif resid_ms == 0.0 and resid_df > 0.5 and total_ss > 0:  # an exact fit, as
                # the ANOVA has it; a part at round-off has none, nor has a constant
                # response (its parts of 1e-34 had F infinite: an analysis review)
                f_value = math.nan if _negligible(ss, total_ss) else math.inf
            else:
                f_value = math.nan
            rows_out.append(
                {
                    "factor": factor.name,
                    "part": _TREND_PARTS.get(degree, f"degree {degree}"),
                    "scale": scale,
                    "df": 1.0,
                    "sum_sq": ss,
                    "F": f_value,
                    "p_value": _f_sf(f_value, resid_df),
                    "percent_of_factor": 100.0 * ss / factor_ss if factor_ss > 0 else math.nan,
                    "percent_contribution": 100.0 * ss / total_ss if total_ss > 0 else math.nan,
                }
            )
    if math.isnan(resid_ms) and rows_out:
        notes.append("no residual degrees of freedom: F and p cannot be computed")
    if rows_out:
        out = pd.DataFrame(rows_out, columns=list(TREND_COLUMNS))
    out.attrs["note"] = "; ".join(notes)
    return out


#: Columns of the table returned by :func:`level_coefficients`, in order.
COEFFICIENT_COLUMNS: tuple[str, ...] = (
    "term",
    "level",
    "coefficient",
    "se",
    "t",
    "p_value",
    "vif",
    "derived",
    "significant",
)

#: The constant's row in :func:`level_coefficients` (Minitab's name for it).
CONSTANT_TERM = "Constant"


def level_coefficients(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
    typ: int | str | None = None,
    alpha_to_remove: float | None = None,
    alpha: float = 0.05,
) -> pd.DataFrame:
    """The coefficients of the ANOVA's model at every level of its factors, as Minitab's
    "Coefficients" table and regression equation give them for a general full factorial.

    Every factor is categorical and coded by effects (sum-to-zero) coding, as Minitab codes a
    general factorial's factors: a factor of ``k`` levels has ``k - 1`` columns, column
    ``j`` being 1 at level ``j``, -1 at the last level and 0 elsewhere, and an interaction's
    columns are the products of its factors'. The coefficient of a level is then its
    least-squares mean (the unweighted mean of the model's cell means at that level) less
    the constant (the unweighted mean of all cells); in a balanced design, the level's mean
    response less the grand mean. A factor's coefficients add up to zero over its levels,
    and an interaction's over each of its factors' levels. Minitab prints every level but
    each factor's last, which the others fix (and an interaction's cells at the last level
    of any of its factors); here those are given too (``derived``, as JMP's "Expanded
    Estimates" give them), with their standard errors from the coefficients' covariance. The
    last level is the last as the design lists them, which is Minitab's (the last in value
    order) for levels given low first. This is the table a design with a factor of three
    levels or more has in place of :func:`two_level_effects` (the paper's WP); for a
    two-level factor the coefficient of its second level is half its effect (the first
    level's, the row Minitab prints, is minus that).

    The model is :func:`anova`'s (the same terms, pooling and elimination), fitted to the
    runs at the factors' levels; standard errors, t and p come from the ANOVA's residual
    mean square and degrees of freedom (with centre points, their pure error included, and a
    last row :data:`CENTER_TERM`, the centre points' mean less the constant, as Minitab's
    "Ct Pt").

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite response
        are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors, or the design (or a campaign result).
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions, typ, alpha_to_remove
        The ANOVA's model, as :func:`anova` takes them (unset, given a design or a campaign
        result, the design's).
    alpha
        Significance level of ``significant`` [-].

    Returns
    -------
    pandas.DataFrame
        :data:`COEFFICIENT_COLUMNS`, one row per level of each term, in the model's order
        after :data:`CONSTANT_TERM`: ``term`` (``"WP"``, ``"S:WP"``), ``level`` (the level's
        label, ``"+"``, or its value; an interaction's levels joined by ``", "`` in the
        term's order), ``coefficient`` and ``se`` [response unit], ``t``, ``p_value`` and
        ``vif`` (of the coefficient's column; NaN for a derived level) [-], ``derived``
        (the level Minitab leaves out: a factor's last level, or an interaction cell at the
        last level of one of its factors) and ``significant`` (``p_value < alpha``). Without
        residual degrees of freedom ``se``, ``t`` and ``p_value`` are NaN, as Minitab prints
        "*". Only the constant's row where no factor varies; empty where the model matrix is
        rank-deficient (empty cells) or no run is usable; ``attrs["note"]`` says why.
        ``attrs`` also carries ``equation``, the regression equation with every level
        (``"MU = 0.4 + 0.01 S[-] - 0.01 S[+] + ..."``, the level in brackets standing for 1
        at that level and 0 elsewhere, as Minitab writes its general factorial's equation),
        ``df_resid``, ``alpha``, ``formula`` (the ANOVA's) and ``levels`` (each factor's
        ``{label: value}`` where its labels are not its values, e.g. ``{"WP": {"-": 1e-15,
        ...}}``, the values in the design's unit, which ``units`` gives by factor; a
        categorical factor has none). A constant response (or one the model fits exactly)
        has no t or p for a coefficient that is zero to round-off (within 1e-12 of the
        largest in size). With centre points the VIFs are of the model
        matrix with their rows and the Ct Pt column, as Minitab's.

    References
    ----------
    D. C. Montgomery, *Design and Analysis of Experiments*, 8th ed., Wiley, 2013, section
    5.3 (the effects model of a factorial) and 3.9.2.

    Examples
    --------
    A 3 x 2 design, replicated, whose level means of WP are 0.30, 0.40 and 0.50 (and A adds
    0.02 at its second level):

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor, level_coefficients
    >>> factors = [Factor("WP", (1.0, 2.0, 3.0), labels=("-", "0", "+")), Factor("A", (10.0, 20.0))]
    >>> runs = pd.DataFrame({
    ...     "WP": [1.0, 2.0, 3.0] * 4,
    ...     "A": [10.0] * 6 + [20.0] * 6,
    ...     "MU": [0.30, 0.39, 0.50, 0.28, 0.39, 0.48, 0.31, 0.42, 0.51, 0.31, 0.40, 0.51],
    ... })
    >>> table = level_coefficients(runs, factors, "MU", interactions=False)
    >>> columns = ["term", "level", "coefficient", "se", "p_value", "derived"]
    >>> print(table[columns].round(4).to_string(index=False))
        term level  coefficient     se  p_value  derived
    Constant               0.40 0.0025   0.0000    False
          WP     -        -0.10 0.0035   0.0000    False
          WP     0         0.00 0.0035   1.0000    False
          WP     +         0.10 0.0035   0.0000     True
           A    10        -0.01 0.0025   0.0039    False
           A    20         0.01 0.0025   0.0039     True
    >>> print(table.attrs["equation"])
    MU = 0.4 - 0.1 WP[-] + 0 WP[0] + 0.1 WP[+] - 0.01 A[10] + 0.01 A[20]
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    problem = alpha_problem(alpha, usual="0.05 is usual")
    if problem:
        raise ValueError(f"alpha: {problem}")
    interactions, typ, alpha_to_remove = _model_settings(
        factors, interactions, typ, alpha_to_remove
    )
    raw = _design_factors(factors) if not isinstance(factors, str) else [factors]
    table = anova(
        summary, raw, response, interactions=interactions, typ=typ, alpha_to_remove=alpha_to_remove
    )
    return _coefficients(summary, raw, response, table, interactions, alpha_to_remove, alpha)


@dataclass(frozen=True)
class _Span:
    """One term of an :class:`_EffectsFit`: its display name, its first column in the model
    matrix, ``expand`` (the matrix taking its estimated coefficients to every cell's, the
    Kronecker product of its factors' codings), its cells' level labels, for each cell the
    estimated column it is (its index in the term) or -1 (a derived cell), and each cell's
    number of runs in the fit (centre points apart)."""

    name: str
    start: int
    expand: np.ndarray
    labels: list[str]
    column: list[int]
    counts: list[int]


@dataclass(frozen=True)
class _EffectsFit:
    """:func:`anova`'s model fitted with every factor in effects (sum-to-zero) coding, the
    last level as reference: the coefficients [response unit], the inverse of X'X [-], the
    residual mean square [response unit^2] and degrees of freedom of the ANOVA, the VIFs,
    the terms (:class:`_Span`), the centre points' responses, the ANOVA's note and, for
    each factor, how many of its levels the usable runs hold and how many it has."""

    coef: np.ndarray
    inverse: np.ndarray
    mse: float
    df_resid: float
    vif: np.ndarray
    spans: list[_Span]
    y_center: np.ndarray
    anova_note: str
    levels_present: dict[str, tuple[int, int]]

    @property
    def constant(self) -> bool:
        """Whether the response is constant (nothing is tested then)."""
        return "response is constant" in self.anova_note

    @property
    def round_off(self) -> float:
        """A value within this of zero is zero to round-off [response unit]: 1e-9 of the
        largest coefficient in size after the intercept, as a nil effect in the effects
        table and (squared) a nil sum of squares in the ANOVA (a review: 1e-12 of the
        intercept as well had called an effect of 1e-11 about 0.3 significant where the
        ANOVA found it nil); 1e-12 of the intercept where there is no other coefficient."""
        others = np.abs(self.coef[1:]) if self.coef.size > 1 else np.zeros(0)
        if others.size and float(np.max(others)) > 0:
            return _ROUND_OFF_PSE * float(np.max(others))
        return 1e-12 * float(np.max(np.abs(self.coef), initial=0.0))

    def standardized(self, value: float, se: float) -> float:
        """``value / se`` [-]; where the residual is 0 (an exact fit, as the ANOVA has it)
        infinite for a value not zero to round-off, unless the response is constant; NaN
        where there is no standard error."""
        if se > 0:
            return value / se
        if se == 0.0 and abs(value) > self.round_off and not self.constant:
            return math.copysign(math.inf, value)
        return math.nan


def _effects_fit(
    summary: pd.DataFrame,
    raw: list[Any],
    response: str,
    table: pd.DataFrame,
    interactions: Model,
    alpha_to_remove: float | None,
) -> _EffectsFit | str:
    """The model of ``table`` (:func:`anova`'s, as it makes it) in effects coding
    (:class:`_EffectsFit`), or why there is none; shared by :func:`level_coefficients` and
    :func:`level_comparisons`."""
    factors_, data, _, centre, model = _fitted_model(
        summary, raw, response, interactions, alpha_to_remove
    )
    if model is None or "Residual" not in set(table["term"]):
        return "no model to fit"
    frame, term_names, terms, _ = model
    by_name = {f.name: f for f in factors_}
    column_of = {col: name for col, name in term_names.items() if ":" not in col}
    y = frame["y"].to_numpy(dtype=float)
    # each factor's levels in the data (design order), its labels and its effects coding,
    # L (k x (k - 1)): the full set of level coefficients is L times the estimated ones
    levels: dict[str, list[str]] = {}
    coding: dict[str, np.ndarray] = {}
    columns: dict[str, np.ndarray] = {}
    index: dict[str, np.ndarray] = {}  # each run's level, as its index in levels[col]
    for col in column_of:
        name = col[2:-1]  # "C(f1)" -> "f1"
        factor = by_name[column_of[col]]
        codes = np.array([int(c[1:]) for c in frame[name]])
        present = np.unique(codes)
        levels[col] = [factor.level_label(factor.levels[c]) for c in present]
        k = present.size
        coding[col] = np.vstack([np.eye(k - 1), -np.ones((1, k - 1))])
        index[col] = np.searchsorted(present, codes)
        columns[col] = coding[col][index[col]]
    blocks = [np.ones((y.size, 1))]
    spans = []
    for term in terms:
        parts = [f"C({p[2:-1]})" for p in term.split(":")]
        block = np.ones((y.size, 1))
        expand = np.ones((1, 1))
        labels = [""]
        for part in parts:
            block = _row_kron(block, columns[part])
            expand = np.kron(expand, coding[part])
            labels = [f"{a}, {b}" if a else b for a in labels for b in levels[part]]
        # the cells (levels' indices) in the order of kron's rows; a cell at the last level
        # of one of its factors is derived, any other is the estimated column it names
        sizes = [len(levels[part]) for part in parts]
        cells = list(itertools.product(*(range(k) for k in sizes)))
        column = [
            -1
            if any(i == k - 1 for i, k in zip(cell, sizes, strict=True))
            else int(np.ravel_multi_index(cell, [k - 1 for k in sizes]))
            for cell in cells
        ]
        cell_of_run = np.ravel_multi_index([index[part] for part in parts], sizes)
        counts = np.bincount(cell_of_run, minlength=len(cells)).tolist()
        start = sum(b.shape[1] for b in blocks)
        spans.append(_Span(term_names[term], start, expand, labels, column, counts))
        blocks.append(block)
    exog = np.hstack(blocks)
    if np.linalg.matrix_rank(exog) < exog.shape[1]:
        return "the design is rank-deficient (empty cells)"
    inverse = np.linalg.inv(exog.T @ exog)
    coef = inverse @ (exog.T @ y)
    n_c = int(np.sum(centre))
    # Minitab's VIFs, with centre points, are of the matrix with their rows and Ct Pt
    vif = _vif(_with_centre_rows(exog, n_c) if n_c else exog)
    rows = table.set_index("term")
    df_resid = float(rows.loc["Residual", "df"])
    mse = float(rows.loc["Residual", "mean_sq"]) if df_resid > 0.5 else math.nan
    return _EffectsFit(
        coef=coef,
        inverse=inverse,
        mse=mse,
        df_resid=df_resid,
        vif=vif,
        spans=spans,
        y_center=data.loc[centre, response].to_numpy(dtype=float),
        anova_note=str(table.attrs.get("note", "")),
        levels_present={
            f.name: (len({f.level_index(v) for v in data[f.name]} - {None}), len(f.levels))
            for f in factors_
        },
    )


def tukey_grouping(comparisons: pd.DataFrame) -> pd.DataFrame:
    """Minitab's "Grouping Information Using the Tukey Method": the levels of each factor of
    a :func:`level_comparisons` table, largest mean first, each with letters; levels that
    share a letter do not differ significantly, levels with no letter in common do.

    The letters are the compact letter display of the table's ``significant`` pairs by
    Piepho's insert, absorb and sweep: starting from one group of every level, each
    significant pair splits every group that holds both into one without either of them,
    groups inside another are dropped, a level leaves a group whose pairs with it other
    groups cover, and the groups are lettered A, B, ... from the largest mean (by their
    members' ranks). A pair without a p value (two levels of equal means in an exact fit)
    counts as not significant.

    Parameters
    ----------
    comparisons
        A table of :func:`level_comparisons`.

    Returns
    -------
    pandas.DataFrame
        One row per level of each factor: ``factor``, ``level`` (its label), ``n`` (its
        number of usable runs, centre points apart; missing for a table without ``n_a`` and
        ``n_b``, such as one written before they were added), ``mean`` (its least-squares
        mean) [response unit] and ``grouping`` (its letters, e.g. ``"AB"``); none for a
        factor whose pairs have no p value (no residual). :func:`save_tables` writes it as
        ``grouping_<R>.csv``.

    References
    ----------
    H.-P. Piepho, "An algorithm for a letter-based representation of all-pairwise
    comparisons", Journal of Computational and Graphical Statistics 13(2), 456-466, 2004.

    Examples
    --------
    >>> import pandas as pd
    >>> from brakeca.analysis import tukey_grouping
    >>> table = pd.DataFrame({
    ...     "factor": ["WP"] * 3, "level_a": ["-", "-", "0"], "level_b": ["0", "+", "+"],
    ...     "n_a": [8, 8, 8], "n_b": [8, 8, 8],
    ...     "mean_a": [0.30, 0.30, 0.32], "mean_b": [0.32, 0.50, 0.50],
    ...     "p_adjusted": [0.4, 0.001, 0.002], "significant": [False, True, True],
    ... })
    >>> print(tukey_grouping(table).to_string(index=False))
    factor level  n  mean grouping
        WP     +  8  0.50        A
        WP     0  8  0.32        B
        WP     -  8  0.30        B
    """
    rows: list[dict[str, Any]] = []
    for factor, pairs in comparisons.groupby("factor", sort=False):
        if pairs["p_adjusted"].isna().all():  # no residual: nothing was tested
            continue
        means: dict[str, float] = {}
        counts: dict[str, Any] = {}
        for _, rec in pairs.iterrows():
            for side in "ab":
                level = str(rec[f"level_{side}"])
                means.setdefault(level, float(rec[f"mean_{side}"]))
                n = rec.get(f"n_{side}")
                counts.setdefault(level, pd.NA if n is None or pd.isna(n) else int(n))
        order = sorted(means, key=lambda level: -means[level])  # largest mean first
        groups: list[frozenset[str]] = [frozenset(order)]
        for _, rec in pairs[pairs["significant"].astype(bool)].iterrows():
            a, b = str(rec["level_a"]), str(rec["level_b"])
            split: list[frozenset[str]] = []
            for group in groups:
                if a in group and b in group:
                    split += [group - {a}, group - {b}]
                else:
                    split.append(group)
            groups = [g for g in dict.fromkeys(split) if not any(g < h for h in split)]
        # sweep: a level keeps a letter only where it needs it (a pair of the letter's that
        # no other letter of both covers), and a letter left on no level goes
        swept = [set(g) for g in sorted(groups, key=lambda g: sorted(map(order.index, g)))]
        for members in swept:
            for level in sorted(members, key=order.index):
                others = [h for h in swept if h is not members]
                if any(level in h for h in others) and all(
                    any(level in h and other in h for h in others)
                    for other in members
                    if other != level
                ):
                    members.discard(level)
        groups = [frozenset(g) for g in swept if g]
        # lettered A, B, ... from the largest mean: by their members' ranks, then the next
        groups.sort(key=lambda g: sorted(map(order.index, g)))
        for level in order:
            letters = "".join(chr(ord("A") + i) for i, group in enumerate(groups) if level in group)
            rows.append(
                {
                    "factor": factor,
                    "level": level,
                    "n": counts[level],
                    "mean": means[level],
                    "grouping": letters,
                }
            )
    out = pd.DataFrame(rows, columns=["factor", "level", "n", "mean", "grouping"])
    return out.astype({"n": "Int64"})


def _zero_residual_note(fit: _EffectsFit, statistic: str, of: str) -> str:
    """What a table of ``fit`` says where its residual is 0: a constant response has no
    ``statistic`` (t, q) or p; an exact fit's is infinite, p 0, for every ``of`` (coefficient,
    difference) not zero to round-off, as the ANOVA's F."""
    if fit.constant:
        return f"response is constant: no {statistic} or p"
    return (
        f"exact fit (no residual scatter): {statistic} is infinite and p 0 for every {of} "
        "that is not zero"
    )


def _coefficients(
    summary: pd.DataFrame,
    raw: list[Any],
    response: str,
    table: pd.DataFrame,
    interactions: Model,
    alpha_to_remove: float | None,
    alpha: float = 0.05,
    fit: _EffectsFit | str | None = None,
) -> pd.DataFrame:
    """:func:`level_coefficients` of the design's factors ``raw`` against ``table``, the
    :func:`anova` of the same model (which :func:`analyze` has already), and of ``fit``, its
    :func:`_effects_fit` where that is made already."""
    from scipy import stats

    out = pd.DataFrame({c: pd.Series(dtype=float) for c in COEFFICIENT_COLUMNS})
    out = out.astype({"term": object, "level": object, "derived": bool, "significant": bool})
    out.attrs.update(note="", equation="", df_resid=math.nan, alpha=alpha)
    out.attrs["formula"] = table.attrs.get("formula", "")
    # what each label stands for, where the labels are not the values (a Minitab user's
    # review: "-", "0", "+" without their values are easy to misread)
    nominal = {  # a categorical factor's levels only number its choices: left out
        str(_field(f, "name"))
        for f in raw
        if not isinstance(f, str) and _field(f, "choices") is not None
    }
    labelled = [
        f
        for f in _factors(raw)
        if f.name not in nominal and any(f.level_label(v) != f"{v:g}" for v in f.levels)
    ]
    out.attrs["levels"] = {f.name: {f.level_label(v): v for v in f.levels} for f in labelled}
    out.attrs["units"] = {f.name: f.unit for f in labelled}
    if fit is None:
        fit = _effects_fit(summary, raw, response, table, interactions, alpha_to_remove)
    if isinstance(fit, str):
        out.attrs["note"] = fit + (": no coefficients" if "rank" in fit else "")
        return out
    coef, inverse, mse, df_resid = fit.coef, fit.inverse, fit.mse, fit.df_resid
    out.attrs["df_resid"] = df_resid
    if math.isnan(mse):
        out.attrs["note"] = "no residual degrees of freedom: no standard errors, t or p"
    elif mse == 0.0:
        out.attrs["note"] = _zero_residual_note(fit, "t", "coefficient")

    def row(term: str, level: str, b: float, var: float, v: float, derived: bool) -> dict:
        se = math.sqrt(mse * var) if not math.isnan(mse) else math.nan
        t = fit.standardized(b, se)
        p = float(2.0 * stats.t.sf(abs(t), df_resid)) if not math.isnan(t) else math.nan
        significant = bool(p < alpha) if not math.isnan(p) else False
        return dict(
            term=term,
            level=level,
            coefficient=b,
            se=se,
            t=t,
            p_value=p,
            vif=v,
            derived=derived,
            significant=significant,
        )

    records = [row(CONSTANT_TERM, "", float(coef[0]), float(inverse[0, 0]), math.nan, False)]
    for span in fit.spans:
        estimated = slice(span.start, span.start + span.expand.shape[1])
        full = span.expand @ coef[estimated]
        variance = np.einsum("ij,jk,ik->i", span.expand, inverse[estimated, estimated], span.expand)
        for i, label in enumerate(span.labels):
            j = span.column[i]
            records.append(
                row(
                    span.name,
                    label,
                    float(full[i]),
                    float(variance[i]),
                    float(fit.vif[span.start + j]) if j >= 0 else math.nan,
                    j < 0,
                )
            )
    if fit.y_center.size:
        b = float(fit.y_center.mean()) - float(coef[0])
        var = 1.0 / fit.y_center.size + float(inverse[0, 0])
        records.append(row(CENTER_TERM, "", b, var, float(fit.vif[-1]), False))
    attrs = dict(out.attrs)
    out = pd.DataFrame(records, columns=list(COEFFICIENT_COLUMNS))
    out.attrs.update(attrs)
    out.attrs["equation"] = _equation(out, response)
    return out


#: Columns of the table returned by :func:`level_comparisons`, in order.
COMPARISON_COLUMNS: tuple[str, ...] = (
    "factor",
    "level_a",
    "level_b",
    "n_a",
    "n_b",
    "mean_a",
    "mean_b",
    "difference",
    "se",
    "q",
    "p_adjusted",
    "ci_low",
    "ci_high",
    "significant",
)


def level_comparisons(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    *,
    interactions: Model | None = None,
    typ: int | str | None = None,
    alpha_to_remove: float | None = None,
    confidence: float = 0.95,
) -> pd.DataFrame:
    """Tukey's pairwise comparisons of the levels of each factor of three levels or more, as
    Minitab's "Comparisons" of a general linear model give them: which of the paper's three
    WP levels differ from which.

    The ANOVA's F for such a factor says only that its levels are not all alike. Here each
    pair of its levels is compared by the difference of their least-squares means in the
    ANOVA's model (a level's mean with the other factors' levels weighted alike, as
    :func:`level_coefficients` gives it: the constant plus the level's coefficient; in a
    balanced design the level's mean response), its standard error from the model's
    residual mean square and the coefficients' covariance, and Tukey's studentized range
    ``q = |difference| / se * sqrt(2)`` over the factor's ``k`` levels with the residual's
    degrees of freedom: the p values and the simultaneous intervals hold for all the
    factor's pairs at once (Tukey-Kramer where the design is not balanced). Where the factor
    takes part in a significant interaction, its differences change with the other factor's
    level and these, averaged over it, say less: ``attrs["note"]`` names such interactions
    (their interaction plot shows the differences level by level).

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows with a finite response
        are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors, or the design (or a campaign result).
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions, typ, alpha_to_remove
        The ANOVA's model, as :func:`anova` takes them (unset, given a design or a campaign
        result, the design's).
    confidence
        Simultaneous confidence of the intervals; ``significant`` is ``p_adjusted < 1 -
        confidence`` [-].

    Returns
    -------
    pandas.DataFrame
        :data:`COMPARISON_COLUMNS`, one row per pair of levels of each factor of three levels
        or more in the model, in the design's order of the levels: ``factor``, ``level_a``
        and ``level_b`` (labels, ``level_a`` the earlier), ``n_a`` and ``n_b`` (their
        numbers of usable runs, centre points apart), ``mean_a`` and ``mean_b`` (the
        levels' least-squares means), ``difference`` (``mean_b - mean_a``, Minitab's
        "Difference of Levels") and ``se`` [response unit], ``q`` (the studentized range)
        and ``p_adjusted`` (Tukey's) [-], ``ci_low`` and ``ci_high`` (the simultaneous
        interval of the difference) [response unit] and ``significant``. Empty where no
        such factor is in the model, the model matrix is rank-deficient or no run is
        usable; without residual degrees of freedom (or scatter) only the means and
        differences. ``attrs``: ``confidence``, ``df_resid``, ``method`` (``"Tukey"``),
        ``formula`` (the ANOVA's) and ``note`` (the interactions of the factor with an ANOVA
        p below ``1 - confidence``, a factor left out of the model, levels without usable
        runs).

    References
    ----------
    J. W. Tukey, "Comparing individual means in the analysis of variance", Biometrics 5(2),
    99-114, 1949; C. Y. Kramer, "Extension of multiple range tests to group means with
    unequal numbers of replications", Biometrics 12(3), 307-310, 1956; D. C. Montgomery,
    *Design and Analysis of Experiments*, 8th ed., Wiley, 2013, section 3.5.7.

    Examples
    --------
    The 3 x 2 design of :func:`level_coefficients` (WP's level means 0.30, 0.40, 0.50):

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor, level_comparisons
    >>> factors = [Factor("WP", (1.0, 2.0, 3.0), labels=("-", "0", "+")), Factor("A", (10.0, 20.0))]
    >>> runs = pd.DataFrame({
    ...     "WP": [1.0, 2.0, 3.0] * 4,
    ...     "A": [10.0] * 6 + [20.0] * 6,
    ...     "MU": [0.30, 0.39, 0.50, 0.28, 0.39, 0.48, 0.31, 0.42, 0.51, 0.31, 0.40, 0.51],
    ... })
    >>> table = level_comparisons(runs, factors, "MU", interactions=False)
    >>> columns = ["level_a", "level_b", "difference", "ci_low", "ci_high", "significant"]
    >>> print(table[columns].round(3).to_string(index=False))
    level_a level_b  difference  ci_low  ci_high  significant
          -       0         0.1   0.083    0.117         True
          -       +         0.2   0.183    0.217         True
          0       +         0.1   0.083    0.117         True
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    problem = alpha_problem(confidence, usual="0.95 is usual")  # the same range as alpha's
    if problem:
        raise ValueError(f"confidence: {problem}")
    interactions, typ, alpha_to_remove = _model_settings(
        factors, interactions, typ, alpha_to_remove
    )
    raw = _design_factors(factors) if not isinstance(factors, str) else [factors]
    table = anova(
        summary, raw, response, interactions=interactions, typ=typ, alpha_to_remove=alpha_to_remove
    )
    return _comparisons(summary, raw, response, table, interactions, alpha_to_remove, confidence)


def _comparisons(
    summary: pd.DataFrame,
    raw: list[Any],
    response: str,
    table: pd.DataFrame,
    interactions: Model,
    alpha_to_remove: float | None,
    confidence: float = 0.95,
    fit: _EffectsFit | str | None = None,
) -> pd.DataFrame:
    """:func:`level_comparisons` of the design's factors ``raw`` against ``table``, the
    :func:`anova` of the same model (which :func:`analyze` has already), and of ``fit``, its
    :func:`_effects_fit` where that is made already."""
    from scipy import stats

    out = pd.DataFrame({c: pd.Series(dtype=float) for c in COMPARISON_COLUMNS})
    out = out.astype(
        {"factor": object, "level_a": object, "level_b": object, "n_a": int, "n_b": int}
        | {"significant": bool}
    )
    out.attrs.update(confidence=float(confidence), df_resid=math.nan, method="Tukey", note="")
    out.attrs["formula"] = table.attrs.get("formula", "")
    if fit is None:
        fit = _effects_fit(summary, raw, response, table, interactions, alpha_to_remove)
    if isinstance(fit, str):
        out.attrs["note"] = fit
        return out
    out.attrs["df_resid"] = fit.df_resid
    mse, df = fit.mse, fit.df_resid
    alpha = 1.0 - float(confidence)
    p_of = dict(zip(table["term"], table["p_value"], strict=True))
    records: list[dict[str, Any]] = []
    notes: list[str] = []
    # a factor of three levels or more in the data that the model left out (eliminated)
    in_model = {span.name for span in fit.spans}
    for name, (present, total) in fit.levels_present.items():
        if total >= 3 and 0 < present < total:
            notes.append(
                f"{name}: {present} of its {total} levels have usable runs"
                + ("" if present >= 3 else ", too few to compare")
            )
        if present >= 3 and name not in in_model:
            notes.append(f"{name} is not in the model")
    for span in fit.spans:
        k = len(span.labels)
        if ":" in span.name or k < 3:
            continue
        estimated = slice(span.start, span.start + span.expand.shape[1])
        effects = span.expand @ fit.coef[estimated]
        covariance = fit.inverse[estimated, estimated]
        means = float(fit.coef[0]) + effects
        usable = not math.isnan(mse)
        q_crit = float(stats.studentized_range.ppf(confidence, k, df)) if usable else math.nan
        for i, j in itertools.combinations(range(k), 2):
            d = span.expand[j] - span.expand[i]
            difference = float(means[j] - means[i])
            se = math.sqrt(mse * float(d @ covariance @ d)) if usable else math.nan
            # an exact fit (the residual 0): every difference not zero to round-off is
            # significant, as the ANOVA's F is infinite; a constant response has none
            q = abs(fit.standardized(difference, se)) * math.sqrt(2.0)
            if math.isnan(q):
                p = math.nan
            else:
                p = 0.0 if math.isinf(q) else float(stats.studentized_range.sf(q, k, df))
            half = q_crit / math.sqrt(2.0) * se
            records.append(
                {
                    "factor": span.name,
                    "level_a": span.labels[i],
                    "level_b": span.labels[j],
                    "n_a": span.counts[i],
                    "n_b": span.counts[j],
                    "mean_a": float(means[i]),
                    "mean_b": float(means[j]),
                    "difference": difference,
                    "se": se,
                    "q": q,
                    "p_adjusted": p,
                    "ci_low": difference - half,
                    "ci_high": difference + half,
                    "significant": bool(p < alpha) if not math.isnan(p) else False,
                }
            )
        crossing = [
            str(term)
            for term, p in p_of.items()
            if ":" in str(term)
            and span.name in str(term).split(":")
            and not pd.isna(p)
            and float(p) < alpha
        ]
        if crossing:
            which = (
                "a significant interaction" if len(crossing) == 1 else "significant interactions"
            )
            others = (
                "the other factor's level" if len(crossing) == 1 else "the other factors' levels"
            )
            partners = list(
                dict.fromkeys(
                    part for term in crossing for part in term.split(":") if part != span.name
                )
            )
            named = " and ".join(partners)
            notes.append(
                f"{span.name} is in {which} ({', '.join(crossing)}): its differences change "
                f"with {others} ({named}), and these comparisons average them over "
                + (f"{named}'s levels" if len(partners) == 1 else f"the levels of {named}")
                + " (the interaction plot shows them level by level)"
            )
    if records and math.isnan(mse):
        notes.append("no residual degrees of freedom: no standard errors, intervals or p")
    elif records and mse == 0.0:
        notes.append(_zero_residual_note(fit, "q", "difference"))
    if records:
        attrs = dict(out.attrs)
        out = pd.DataFrame(records, columns=list(COMPARISON_COLUMNS))
        out.attrs.update(attrs)
    out.attrs["note"] = "; ".join(notes)
    return out


def _equation(table: pd.DataFrame, response: str, *, scale: float = 1.0) -> str:
    """The regression equation of a :func:`level_coefficients` table, ``"MU = 0.4 - 0.1
    WP[-] + ..."``: its rows' coefficients times ``scale`` (e.g. 1e9 for V in mm^3), each to
    4 significant digits (one within 1e-12 of the largest in size is written 0, not
    -1.388e-17), named ``term[level]`` (the constant unnamed; ``Ct Pt`` as it is)."""
    values = table["coefficient"].to_numpy(dtype=float) * scale
    largest = float(np.max(np.abs(values))) if values.size else 0.0
    text = f"{response} ="
    for k, (term, level, value) in enumerate(
        zip(table["term"], table["level"], values, strict=True)
    ):
        if abs(value) <= 1e-12 * largest:
            value = 0.0
        name = "" if term == CONSTANT_TERM else (term if not level else f"{term}[{level}]")
        if k == 0:
            text += f" {value:.4g}" + (f" {name}" if name else "")
        else:
            text += f" {'-' if value < 0 else '+'} {abs(value):.4g}" + (f" {name}" if name else "")
    return text


def _f_sf(f_value: float, df_resid: float) -> float:
    """p of an F of one degree of freedom against ``df_resid`` [-] (NaN where undefined)."""
    from scipy import stats

    if df_resid < 0.5 or math.isnan(f_value):
        return math.nan
    return 0.0 if math.isinf(f_value) else float(stats.f.sf(f_value, 1.0, df_resid))


def _field(obj: Any, key: str) -> Any:
    """``obj[key]`` of a mapping, ``obj.key`` of another object; None where absent."""
    if isinstance(obj, Mapping):
        return obj.get(key)
    return getattr(obj, key, None)


def analyze(
    summary: pd.DataFrame | Any,
    factors: Iterable[Any] | None = None,
    responses: Sequence[str] = ("MU", "V"),
    *,
    main_effects_only: bool | None = None,
    anova_type: int | None = None,
    alpha_to_remove: float | None = None,
    max_order: int | None = None,
    model_terms: Sequence[str] | str | None = None,
) -> dict[str, ResponseAnalysis]:
    """Run the whole analysis for several responses.

    Given a design (a campaign result, or the design as ``factors``), each of
    ``anova_type``, ``alpha_to_remove`` and the model (``main_effects_only``, ``max_order``,
    ``model_terms``, all three unset) left unset is the design's, as the report takes it
    (:func:`brakeca.study.write_study`): ``analyze(brakeca.load_campaign("study"))`` gives
    the report's tables. Without a design they default to the full model of main effects and
    two-factor interactions, Type II, unreduced.

    Parameters
    ----------
    summary
        Campaign summary, one row per run; or a campaign result
        (:func:`brakeca.load_campaign`), its summary and, without ``factors``, its design's
        factors: ``analyze(brakeca.load_campaign("study"))``.
    factors
        The design's factors, or the design itself (or a campaign result) for them; every
        analysis function takes these alike.
    responses
        Response columns, by default ``("MU", "V")`` (mean COF [-], emitted volume per stop
        [m^3]); ``"log10_V_mm3"`` [-] is computed from V where the summary has no such
        column (:func:`brakeca.study.with_log_v`).
    main_effects_only
        The ANOVA and the effects table fit the main effects alone, as Minitab analyses a
        Plackett-Burman design (its interactions are partly confounded with the main
        effects); the interaction plots' cell means are still given. Unset: true for a
        Plackett-Burman design, else false.
    anova_type
        The ANOVA's sums of squares (:func:`anova`'s ``typ``): 2 (Type II, the default
        without a design) or 3 (Type III, adjusted, as Minitab and JMP give them); unset, the
        design's ``anova_type``.
    alpha_to_remove
        Reduce each response's model by backward elimination (:func:`anova`); the residuals
        and, for a two-level design, the effects table are then of the reduced model, as in
        Minitab after a stepwise reduction. Unset, the design's ``alpha_to_remove`` (not for
        a response-surface design, whose report reduces its surfaces instead).
    max_order
        The model's terms up through this many factors (:func:`anova`'s ``interactions``),
        instead of main effects and two-factor interactions (main effects alone with
        ``main_effects_only``); where it is not that default, the effects table then fits
        the ANOVA's terms too.
    model_terms
        The model's terms one by one instead (:func:`canonical_terms`: ``["S", "WP",
        "S*WP"]``, or one string of them), as Minitab's Terms dialog picks them; the
        residuals and the effects table are then of that model, and ``main_effects_only``
        no longer applies to either. Not with ``max_order``.

    Raises
    ------
    ValueError
        ``max_order`` not a whole number from 1, ``model_terms`` naming a factor not in
        ``factors`` (or as :func:`canonical_terms` refuses it), or both given; before any
        work.

    Returns
    -------
    dict of str to ResponseAnalysis
        ``{response: ResponseAnalysis}``: each response's tables (main effects,
        interactions, ANOVA, ranked effects, residuals, two-level effects, trends, model
        summary, level coefficients, pairwise comparisons, unusual runs) as attributes, or
        as items by name (``result["MU"]["anova"]``).

    References
    ----------
    Wahlström (2016), Figures 6 to 9, doi:10.1155/2016/8181260.

    Examples
    --------
    The replicated 2² design of :func:`anova`'s example (MU's effects: S +0.05, A +0.11, S×A
    +0.02):

    >>> import pandas as pd
    >>> from brakeca.analysis import Factor, analyze
    >>> factors = [Factor("S", (0.0, 1.0)), Factor("A", (10.0, 20.0), unit="%")]
    >>> runs = pd.DataFrame({
    ...     "S": [0.0, 1.0] * 4,
    ...     "A": [10.0, 10.0, 20.0, 20.0] * 2,
    ...     "MU": [0.30, 0.34, 0.40, 0.46, 0.32, 0.34, 0.40, 0.48],
    ... })
    >>> result = analyze(runs, factors, ["MU"])
    >>> mu = result["MU"]
    >>> print(mu.effects[["term", "effect", "coefficient"]].round(4).to_string(index=False))
    term  effect  coefficient
       A    0.11        0.055
       S    0.05        0.025
     S:A    0.02        0.010
    >>> print(mu.model_summary[["n", "s", "r_squared"]].round(4).to_string(index=False))
     n    s  r_squared
     8 0.01     0.9868
    >>> mu["anova"] is mu.anova  # a table by its name too
    True
    """
    design = None
    if not isinstance(summary, pd.DataFrame) and hasattr(summary, "summary"):
        design = getattr(summary, "design", None)
        factors = summary if factors is None else factors  # a CampaignResult: its design
        summary = summary.summary
    design = _design_of(factors) or design  # the design itself, or a campaign result's
    if design is not None and hasattr(design, "anova_model"):
        # what the report takes from the design (study.write_study; an API review found
        # analyze(load_campaign(...)) a Type II, unreduced fit beside a report's Type III,
        # reduced one)
        chosen_model = main_effects_only is not None  # the model's terms, by their flag
        if main_effects_only is None:
            main_effects_only = design.plackett_burman is not None
        if anova_type is None:
            anova_type = design.anova_type
        if alpha_to_remove is None and not design.is_response_surface:
            alpha_to_remove = design.alpha_to_remove
        if max_order is None and model_terms is None and not chosen_model:
            chosen = design.anova_model
            if isinstance(chosen, int):
                max_order = chosen
            else:
                model_terms = chosen
    main_effects_only = bool(main_effects_only)
    anova_type = 2 if anova_type is None else anova_type
    if isinstance(summary, str | os.PathLike):  # a campaign folder (a fuzz review)
        raise TypeError(
            f"summary: a campaign's summary table or result, not a path ({str(summary)!r}): "
            "brakeca.load_campaign(folder) reads a campaign folder, and analyze() takes what "
            "it returns"
        )
    if factors is None:
        raise TypeError(
            "factors: give the design's factors (or the design), or a campaign result as "
            "the first argument (brakeca.load_campaign(folder) reads one)"
        )
    # the factors once (an iterator is read once), with a categorical factor's choices kept
    # for factor_trends
    design_factors = [factors] if isinstance(factors, str) else _design_factors(factors)
    factors = _factors(design_factors)
    if isinstance(responses, str):
        responses = (responses,)
    if "log10_V_mm3" in responses and "log10_V_mm3" not in summary.columns:
        if "V" in summary.columns:
            from brakeca.study import with_log_v

            summary = with_log_v(summary)
    result: dict[str, ResponseAnalysis] = {}
    default = 1 if main_effects_only else 2
    if max_order is not None:
        _model_order(max_order, name="max_order")  # checked before any work
    model: Model = max_order if max_order is not None else not main_effects_only
    if model_terms is not None:
        if max_order is not None:
            raise ValueError("model_terms, max_order: give one of them, not both")
        model = canonical_terms(model_terms, [f.name for f in factors])
    # the effects table fits every effect the data can estimate, unless the ANOVA's model is
    # not the default one (another order, terms given, or reduced): then that model's terms
    follow = (
        alpha_to_remove is not None
        or model_terms is not None
        or (max_order is not None and max_order != default)
    )
    for response in responses:
        table = anova(
            summary,
            factors,
            response,
            interactions=model,
            typ=anova_type,
            alpha_to_remove=alpha_to_remove,
        )
        kept = [t for t in table["term"] if t not in ("Residual", CURVATURE)] if follow else None
        # the effects-coded fit the coefficients and the comparisons share
        fit = _effects_fit(summary, design_factors, response, table, model, alpha_to_remove)
        result[response] = ResponseAnalysis(
            main_effects=main_effects(summary, factors, response),
            interactions=interaction_tables(summary, factors, response),
            interactions_long=interactions_long(summary, factors, response),
            anova=table,
            ranked_effects=_rank_terms(table, summary, factors, response),
            residuals=residuals(
                summary,
                factors,
                response,
                interactions=model,
                alpha_to_remove=alpha_to_remove,
            ),
            effects=two_level_effects(
                summary,
                factors,
                response,
                main_effects_only=main_effects_only,
                model_terms=kept,
            ),
            trends=_trends(summary, design_factors, response, table, model, alpha_to_remove),
            # S, R², adjusted and predicted R² as the CLI's model_summary table (they had
            # been in the ANOVA's attrs alone, which concat and merge drop: an API review)
            model_summary=model_summary(table),
            coefficients=_coefficients(
                summary, design_factors, response, table, model, alpha_to_remove, fit=fit
            ),
            comparisons=_comparisons(
                summary, design_factors, response, table, model, alpha_to_remove, fit=fit
            ),
            unusual=unusual_runs(
                summary,
                factors,
                response,
                interactions=model,
                typ=anova_type,
                alpha_to_remove=alpha_to_remove,
            ),
        )
    return result


#: Columns of :func:`model_summary`, in order.
MODEL_SUMMARY_COLUMNS: tuple[str, ...] = (
    "n",
    "df_resid",
    "s",
    "r_squared",
    "r_squared_adj",
    "r_squared_pred",
    "pure_error_df",
    "pure_error_ss",
    "lack_of_fit_df",
    "lack_of_fit_ss",
    "lack_of_fit_F",
    "lack_of_fit_p",
    "formula",
)


def model_summary(table: pd.DataFrame) -> pd.DataFrame:
    """The model summary of an :func:`anova` table as a one-row table.

    Parameters
    ----------
    table
        A table returned by :func:`anova`.

    Returns
    -------
    pandas.DataFrame
        One row with :data:`MODEL_SUMMARY_COLUMNS`: ``n`` (runs used) [-], ``df_resid`` [-],
        ``s`` [response unit], ``r_squared``, ``r_squared_adj``, ``r_squared_pred`` [-], the
        pure-error and lack-of-fit split of the residual (see :func:`anova`) and
        ``formula``; NaN (or empty) where the table does not carry the statistic.
    """
    attrs = table.attrs
    row = {c: attrs.get(c, math.nan) for c in MODEL_SUMMARY_COLUMNS}
    row["formula"] = attrs.get("formula", "")
    return pd.DataFrame([row], columns=list(MODEL_SUMMARY_COLUMNS))


def _long_from_tables(tables: Mapping[tuple[str, str], pd.DataFrame]) -> pd.DataFrame:
    frames = []
    for (a, b), table in tables.items():
        long = table.stack(future_stack=True).rename("mean").reset_index()
        long.columns = ["level_a", "level_b", "mean"]
        long.insert(0, "factor_a", a)
        long.insert(2, "factor_b", b)
        frames.append(long[["factor_a", "level_a", "factor_b", "level_b", "mean"]])
    if not frames:
        return pd.DataFrame(columns=["factor_a", "level_a", "factor_b", "level_b", "mean"])
    return pd.concat(frames, ignore_index=True)


def save_tables(result: Mapping[str, Mapping[str, Any]], directory: str | Path) -> list[Path]:
    """Write the tables of :func:`analyze` as CSV files.

    Parameters
    ----------
    result
        Output of :func:`analyze`, ``{response: ResponseAnalysis}`` (or mappings of the same
        tables by name).
    directory
        Target directory; created if missing.

    Raises
    ------
    TypeError
        ``result`` is one response's :class:`ResponseAnalysis`, not a mapping of them.
    NotADirectoryError
        ``directory`` is a file.

    Returns
    -------
    list of pathlib.Path
        The files written: ``main_effects_<R>.csv``, ``interactions_<R>.csv`` (long form),
        ``anova_<R>.csv`` (the table's note on its first row only),
        ``model_summary_<R>.csv`` (one row: ``n``, ``df_resid``, ``s``, ``r_squared``,
        ``r_squared_adj``, ``r_squared_pred``, ``formula``; see :func:`anova`) and
        ``ranked_effects_<R>.csv`` for every response ``R``,
        ``residuals_<R>.csv`` when the bundle has them (:func:`residuals`),
        ``trends_<R>.csv`` when it has a non-empty :func:`factor_trends` table,
        ``effects_<R>.csv`` when it has a non-empty :func:`two_level_effects` table,
        ``coefficients_<R>.csv`` when it has a non-empty :func:`level_coefficients` table
        and no effects table (a design with a factor of three levels or more: a two-level
        design's coded coefficients are in its effects table), ``comparisons_<R>.csv``
        when it has a non-empty :func:`level_comparisons` table, and ``grouping_<R>.csv``,
        its levels' :func:`tukey_grouping` letters, when the comparisons have p values, and
        ``unusual_<R>.csv`` when :func:`unusual_runs` names a run.
    """
    if isinstance(result, ResponseAnalysis):  # a KeyError: 'main_effects' (an API review)
        raise TypeError(
            "result: one response's analysis; save_tables takes analyze()'s whole result, "
            "{response: ResponseAnalysis}, e.g. save_tables({'MU': result['MU']}, directory)"
        )
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise NotADirectoryError(f"directory: {directory} exists and is not a folder")
    directory.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for response, bundle in result.items():
        long = bundle.get("interactions_long")
        if long is None:
            long = _long_from_tables(bundle.get("interactions", {}))
        tables = {
            "main_effects": bundle["main_effects"],
            "interactions": long,
            "anova": bundle["anova"],
            "model_summary": (  # (analyze's; computed for a bundle made without it)
                bundle["model_summary"]
                if "model_summary" in bundle
                else model_summary(bundle["anova"])
            ),
            "ranked_effects": bundle["ranked_effects"],
        }
        if bundle.get("residuals") is not None:
            tables["residuals"] = bundle["residuals"]
        trends = bundle.get("trends")
        if trends is not None and not trends.empty:
            tables["trends"] = trends
        else:  # as the effects table's, below
            (directory / f"trends_{response}.csv").unlink(missing_ok=True)
        effects = bundle.get("effects")
        if effects is not None and not effects.empty:
            tables["effects"] = effects
        else:  # an earlier analysis's (e.g. of another reduced model) would outlive it
            (directory / f"effects_{response}.csv").unlink(missing_ok=True)
        coefficients = bundle.get("coefficients")
        if (
            (effects is None or effects.empty)
            and coefficients is not None
            and not coefficients.empty
        ):
            tables["coefficients"] = coefficients
        else:
            (directory / f"coefficients_{response}.csv").unlink(missing_ok=True)
        comparisons = bundle.get("comparisons")
        if comparisons is not None and not comparisons.empty:
            tables["comparisons"] = comparisons
            grouping = tukey_grouping(comparisons)
        else:
            (directory / f"comparisons_{response}.csv").unlink(missing_ok=True)
            grouping = None
        if grouping is not None and not grouping.empty:
            tables["grouping"] = grouping
        else:
            (directory / f"grouping_{response}.csv").unlink(missing_ok=True)
        unusual = bundle.get("unusual")
        if unusual is not None and not unusual.empty:
            tables["unusual"] = unusual
        else:
            (directory / f"unusual_{response}.csv").unlink(missing_ok=True)
        # the ANOVA's note is the table's: once, on its first row, not on every row (a
        # user's review: a screening design's 538 characters, fifteen times)
        table = tables["anova"]
        if "note" in table.columns and len(table) > 1 and table["note"].nunique() == 1:
            table = table.copy()
            table.loc[table.index[1:], "note"] = ""
            tables["anova"] = table
        for stem, table in tables.items():
            path = directory / f"{stem}_{response}.csv"
            write_table(table, path)
            written.append(path)
    return written
