"""How likely a design's analysis is to find a factor's effect, and how many replicates it needs.

A campaign's runs scatter from seed to seed (the random fibre layout and automaton): the pure
error of a replicated study. Whether the study's ANOVA calls a factor significant then
depends on the size of its effect against that scatter, on the number of runs and on the
degrees of freedom the model leaves for the error. Before spending hours of simulation, this
module gives, for each factor of a design, the power of that ANOVA's F test: the probability
that it finds (p < alpha) a difference ``effect`` between two of the factor's level means
when the runs scatter by ``sigma``, at the smallest noncentrality a difference of ``effect``
can give (two level means ``effect`` apart, the others midway), the figure Minitab's "Power
and Sample Size" for factorial designs uses for a balanced design (in an unbalanced one the
midway arrangement is close to the least favourable, not exactly it). Minitab's default model
differs (every term of a two-level design; terms up to an order, and blocks, for a general
full factorial), and so do its error degrees of freedom and its power.

The model is the one the study fits (:func:`brakeca.analysis.anova`): main effects and the
two-factor interactions the design can estimate, main effects alone for a Plackett-Burman
design, the interactions pooled into the error when they would leave none, the terms up
through the design's ``model_order``, or its ``model_terms``; the whole model,
not one that a design's ``alpha_to_remove`` reduces by the data. Its error degrees of freedom
come from the design's own tests (centre points included), repeated ``replicates`` times.

References
----------
D. C. Montgomery, Design and Analysis of Experiments, 8th ed., Wiley 2013, section 5.3.5
(choice of sample size: the noncentrality of the F test of a factor's main effect).
"""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

if TYPE_CHECKING:
    from brakeca.design import Design

__all__ = [
    "POWER_COLUMNS",
    "check_factorial",
    "factor_power",
    "pooling_note",
    "pure_error",
    "pure_error_sigma",
    "replicates_needed",
    "smallest_effect",
]

#: Columns of :func:`factor_power`, in order.
POWER_COLUMNS: tuple[str, ...] = (
    "factor",
    "levels",
    "replicates",
    "runs",
    "df",
    "df_error",
    "noncentrality",
    "power",
)

#: Most replicates :func:`replicates_needed` tries [-].
MAX_REPLICATES = 1000


def _check(
    design: Design | str | Path, sigma: float, alpha: float, effect: float | None = None
) -> Design:
    """The design (a :class:`~brakeca.design.Design`, a shipped design's name or a design
    file, as :func:`brakeca.campaign.run_campaign` takes), after refusing an ``effect`` or
    ``sigma`` not above 0, an ``alpha`` outside (0, 1) and a response-surface design, naming
    the argument."""
    from brakeca.analysis import alpha_problem
    from brakeca.design import Design, load_design

    given = [("sigma", sigma)] if effect is None else [("effect", effect), ("sigma", sigma)]
    for name, value in given:
        if (
            isinstance(value, bool | str)
            or not isinstance(value, numbers.Real)
            or not (math.isfinite(value) and value > 0)
        ):
            raise ValueError(f"{name}: expected a finite number above 0, got {value!r}")
    problem = alpha_problem(alpha, usual="0.05 is usual")
    if problem:
        raise ValueError(f"alpha: {problem}")
    if isinstance(design, str | Path):
        design = load_design(design)
    elif not isinstance(design, Design):
        raise TypeError(
            f"design: expected a Design, a shipped design's name or a design file, got "
            f"{type(design).__name__}"
        )
    check_factorial(design)
    return design


def check_factorial(design: Design) -> None:
    """Refuse a response-surface design (ValueError naming it): power is computed for the
    factorial ANOVA's factors, and such a design's report fits a quadratic instead.

    Parameters
    ----------
    design
        The design.
    """
    if design.is_response_surface:
        raise ValueError(
            f"design: {design.name} is a {design.kind}: power is computed for the factorial "
            "ANOVA's factors, not for a response-surface design's quadratic terms (its "
            "report fits the quadratic); brakeca design shows the terms its runs estimate"
        )


#: The most replicates :func:`factor_power` evaluates, as a design may have
#: (:attr:`brakeca.design.Design.replicates`); the search of :func:`replicates_needed` stops
#: at :data:`MAX_REPLICATES`.
MOST_REPLICATES = 10_000


def _replicate_counts(design: Design, replicates: Sequence[int] | None) -> list[int]:
    """The replicates to evaluate, checked: by default 1 to 5, and up to the design's own."""
    if replicates is not None and (
        isinstance(replicates, str | bytes) or not isinstance(replicates, Iterable)
    ):
        raise ValueError(
            f"replicates: expected a list of whole numbers, e.g. [2], got {replicates!r}"
        )
    counts = (
        list(replicates)
        if replicates is not None
        else list(range(1, max(5, design.replicates) + 1))
    )
    for r in counts:
        if isinstance(r, bool) or not isinstance(r, int | np.integer) or r < 1:
            raise ValueError(f"replicates: expected whole numbers of 1 or more, got {r!r}")
        if r > MOST_REPLICATES:  # a design's own limit; 10,000 take seconds and 0.5 GB
            raise ValueError(
                f"replicates: at most {MOST_REPLICATES:,} (a design's limit), got {int(r):,}"
            )
    twice = sorted({int(r) for r in counts if counts.count(r) > 1})
    if twice:
        raise ValueError(f"replicates: {twice[0]} is given twice")
    return [int(r) for r in counts]


def _runs(design: Design, replicates: int) -> pd.DataFrame:
    """The design's tests, each ``replicates`` times, as a summary of usable runs."""
    combos = design.combinations()
    frame = pd.DataFrame(
        [dict(c) for c in combos for _ in range(replicates)], columns=list(design.factor_names)
    )
    frame["status"] = "ok"
    return frame


def _factor_tests(design: Design, replicates: int) -> dict[str, tuple[float, float, float]]:
    """For each factor: its degrees of freedom in the study's ANOVA over the design's runs,
    the error degrees of freedom, and the noncentrality per (effect / sigma)^2 of its F test
    at the least favourable arrangement of its level means [-].

    The noncentrality of an F test is the sum of squares its term would have if every run
    gave its expected response, over sigma^2; so each pair of the factor's levels is put one
    unit apart (the others midway, every other effect nil), the study's ANOVA (its model and
    its ``anova_type``) is taken of those noise-free responses, and the pair whose sum of
    squares is least gives the factor's figure. In a balanced design that is
    ``n / 2`` with ``n`` the runs at a level; in an unbalanced one (a run table) it also
    holds what the adjustment for the other factors takes away. The degrees of freedom are
    those of the same table: the factor's NaN when it has one level in the runs."""
    from brakeca.analysis import anova

    frame = _runs(design, replicates)
    factors = list(design.factors)

    def table_of(y: Any) -> pd.DataFrame:
        return anova(
            frame.assign(y=y),
            factors,
            "y",
            interactions=design.anova_model,
            typ=design.anova_type,
        ).set_index("term")

    # any response that is not constant gives the table's degrees of freedom
    table = table_of(np.cos(np.arange(len(frame)) * 2.399963))
    df_error = float(table.loc["Residual", "df"]) if "Residual" in table.index else 0.0
    out = {}
    for f in factors:
        used = [level for level in f.levels if (frame[f.name] == level).any()]
        if f.name not in table.index or len(used) < 2:
            out[f.name] = (math.nan, df_error, math.nan)
            continue
        least = math.inf
        for low, high in itertools.combinations(used, 2):
            means = frame[f.name].map(
                lambda v, lo=low, hi=high: -0.5 if v == lo else 0.5 if v == hi else 0.0
            )
            term = table_of(means.astype(float))
            least = min(least, float(term.loc[f.name, "sum_sq"]) if f.name in term.index else 0.0)
        out[f.name] = (float(table.loc[f.name, "df"]), df_error, least)
    return out


def factor_power(
    design: Design | str | Path,
    effect: float,
    sigma: float,
    *,
    replicates: Sequence[int] | None = None,
    alpha: float = 0.05,
) -> pd.DataFrame:
    """Power of the study's ANOVA to find each factor's effect.

    Parameters
    ----------
    design
        A design, a shipped design's name or a design file (not a response-surface design,
        whose report fits a surface instead).
    effect
        The difference between two of a factor's level means to find [response unit].
    sigma
        The run-to-run standard deviation of the response at one setting (the seed-to-seed
        scatter; a replicated campaign's pure error, :func:`pure_error_sigma`) [response
        unit, the same as ``effect``'s].
    replicates
        Runs per test to evaluate [-]; by default 1 to 5, and the design's own
        ``replicates`` when it has more.
    alpha
        Significance level of the test [-].

    Returns
    -------
    pandas.DataFrame
        :data:`POWER_COLUMNS`, one row per factor and number of replicates: ``levels`` [-],
        ``replicates`` [-], ``runs`` (tests times replicates) [-], ``df`` (the factor's
        degrees of freedom; NaN when the runs leave it at one level, or the design's
        ``model_terms`` give it no term) [-], ``df_error`` [-],
        ``noncentrality`` of the F test at the least favourable arrangement of the level
        means (:func:`_factor_tests`; ``n * effect**2 / (2 * sigma**2)`` in a balanced design
        with ``n`` runs at each level) [-] and ``power`` [-] (NaN without error degrees of
        freedom, or for a factor the runs do not vary).

    Raises
    ------
    ValueError
        ``effect`` or ``sigma`` not above 0, ``alpha`` outside (0, 1), a replicate count
        below 1, or a response-surface design; a ``ConfigError`` (a ``ValueError``) for a
        design name or file :func:`brakeca.design.load_design` cannot load.
    TypeError
        ``design`` is none of a design, a name or a file.
    """

    design = _check(design, sigma, alpha, effect)
    return _power_table(design, effect, sigma, _replicate_counts(design, replicates), alpha, {})


def _tests_at(
    design: Design, r: int, cache: dict[int, dict[str, tuple[float, float, float]]]
) -> dict[str, tuple[float, float, float]]:
    """:func:`_factor_tests` at ``r`` replicates, from those at 1 and 2: from two replicates
    on, the model no longer pools (the repeats give the error degrees of freedom), each more
    replicate adds the design's tests to the error degrees of freedom, and the noise-free
    sums of squares grow in proportion to the replicates."""
    if r <= 2:
        if r not in cache:
            cache[r] = _factor_tests(design, r)
        return cache[r]
    two = _tests_at(design, 2, cache)
    return {
        name: (df_f, df_error + (r - 2) * design.n_tests, per_unit * r / 2)
        for name, (df_f, df_error, per_unit) in two.items()
    }


def pooling_note(design: Design, replicates: int) -> str:
    """What the study's ANOVA pools into the error over ``replicates`` repeats of the
    design's tests, where its model would leave no error degrees of freedom: e.g. ``"model
    with two-factor interactions is saturated (0 residual df): interactions pooled into the
    residual, main effects only"``; empty when it pools nothing.

    Parameters
    ----------
    design
        The design.
    replicates
        Each test's repeats [-], at least 1.

    Returns
    -------
    str
        The ANOVA's notes on pooling, joined by ``"; "``.
    """
    from brakeca.analysis import anova

    # from 2 repeats on, every test's repeats leave residual df, so the model is fitted as at
    # 2: the same pooling, without an ANOVA of every run (10,000 replicates of the paper's
    # design had taken 7 s and 470 MB to say nothing: a review)
    frame = _runs(design, min(replicates, 2))
    table = anova(
        frame.assign(y=np.cos(np.arange(len(frame)) * 2.399963)),
        list(design.factors),
        "y",
        interactions=design.anova_model,
        typ=design.anova_type,
    )
    parts = [p.strip() for p in str(table.attrs.get("note", "")).split(";")]
    return "; ".join(p for p in parts if "pooled into the residual" in p)


def _power_table(
    design: Design,
    effect: float,
    sigma: float,
    counts: Sequence[int],
    alpha: float,
    cache: dict[int, dict[str, tuple[float, float, float]]],
) -> pd.DataFrame:
    """:func:`factor_power` for checked arguments, with ``cache`` of :func:`_tests_at`."""
    from scipy import stats

    ratio = (effect / sigma) ** 2
    rows = []
    for r in counts:
        tests = _tests_at(design, r, cache)
        for f in design.factors:
            df_f, df_error, per_unit = tests[f.name]
            lam = per_unit * ratio
            if df_error >= 1 and df_f >= 1:
                critical = stats.f.isf(alpha, df_f, df_error)
                # scipy's noncentral F gives nonsense at a noncentrality of exactly 0
                power = float(stats.ncf.sf(critical, df_f, df_error, lam)) if lam > 0 else alpha
                if math.isnan(power):  # scipy's NaN past a noncentrality of about 1e19,
                    power = 1.0  # where the power has long reached its limit, 1 (a review)
            else:
                power = math.nan
            rows.append(_row(design, f.name, r, df_f, df_error, lam, power))
    return pd.DataFrame(rows, columns=list(POWER_COLUMNS))


def _row(
    design: Design,
    name: str,
    r: int,
    df_f: float,
    df_error: float,
    lam: float,
    power: float,
) -> dict[str, Any]:
    """One row of :data:`POWER_COLUMNS`."""
    return {
        "factor": name,
        "levels": len(design.factor(name).levels),
        "replicates": r,
        "runs": design.n_tests * r,
        "df": df_f,
        "df_error": df_error,
        "noncentrality": lam,
        "power": power,
    }


def replicates_needed(
    design: Design | str | Path,
    effect: float,
    sigma: float,
    *,
    target: float = 0.8,
    alpha: float = 0.05,
) -> pd.DataFrame:
    """The fewest replicates (runs per test) that give each factor's effect the power
    ``target``.

    Parameters
    ----------
    design, effect, sigma, alpha
        As for :func:`factor_power`.
    target
        The power wanted [-], between 0 and 1 (0.8 and 0.9 are usual).

    Returns
    -------
    pandas.DataFrame
        :data:`POWER_COLUMNS`, one row per factor, at the fewest replicates whose power
        reaches ``target``; where even :data:`MAX_REPLICATES` do not, that row with its power.

    Raises
    ------
    ValueError
        As :func:`factor_power`, or ``target`` not above ``alpha`` and below 1.
    TypeError
        As :func:`factor_power`.
    """
    design = _check(design, sigma, alpha, effect)
    if isinstance(target, bool | str) or not alpha < target < 1:
        # a power at or below alpha is met without any effect (a black-box review)
        raise ValueError(
            f"target: expected a power above alpha ({alpha:g}) and below 1, got {target!r}"
        )
    rows: dict[int, dict[str, pd.Series]] = {}
    cache: dict[int, dict[str, tuple[float, float, float]]] = {}

    def at(r: int) -> dict[str, pd.Series]:
        if r not in rows:
            table = _power_table(design, effect, sigma, [r], alpha, cache)
            rows[r] = {str(row["factor"]): row for _, row in table.iterrows()}
        return rows[r]

    def reached(row: pd.Series) -> bool:
        return bool(row["power"] >= target)  # NaN (no error df) is not

    chosen = []
    for f in design.factors:
        # power grows with the replicates: double them until it reaches the target, then
        # halve the interval between the last two
        high = 1
        while high < MAX_REPLICATES and not reached(at(high)[f.name]):
            high = min(2 * high, MAX_REPLICATES)
        if not reached(at(high)[f.name]):
            chosen.append(at(high)[f.name])
            continue
        low = high // 2  # not reached there (or 0)
        while high - low > 1:
            middle = (low + high) // 2
            if reached(at(middle)[f.name]):
                high = middle
            else:
                low = middle
        chosen.append(at(high)[f.name])
    return pd.DataFrame(chosen, columns=list(POWER_COLUMNS)).reset_index(drop=True)


def smallest_effect(
    design: Design | str | Path,
    sigma: float,
    *,
    target: float = 0.8,
    replicates: Sequence[int] | None = None,
    alpha: float = 0.05,
) -> pd.DataFrame:
    """The smallest difference between two of a factor's level means that the study's ANOVA
    finds with the power ``target``, for each factor and number of replicates (the other way
    round from :func:`factor_power`).

    Parameters
    ----------
    design, sigma, replicates, alpha
        As for :func:`factor_power`.
    target
        The power wanted [-], above ``alpha`` and below 1.

    Returns
    -------
    pandas.DataFrame
        :data:`POWER_COLUMNS` and ``effect``, the smallest difference [response unit, as
        ``sigma``], one row per factor and number of replicates; ``power`` is ``target``
        there. NaN where the test cannot be made (no error degrees of freedom, a factor the
        runs do not vary).

    Raises
    ------
    ValueError
        As :func:`factor_power`, or ``target`` not between ``alpha`` and 1.
    TypeError
        As :func:`factor_power`.
    """
    from scipy import optimize, stats

    design = _check(design, sigma, alpha)
    if isinstance(target, bool | str) or not alpha < target < 1:
        raise ValueError(
            f"target: expected a power above alpha ({alpha:g}) and below 1, got {target!r}"
        )
    cache: dict[int, dict[str, tuple[float, float, float]]] = {}
    rows, effects = [], []
    for r in _replicate_counts(design, replicates):
        tests = _tests_at(design, r, cache)
        for f in design.factors:
            df_f, df_error, per_unit = tests[f.name]
            if not (df_f >= 1 and df_error >= 1 and per_unit > 0):
                rows.append(_row(design, f.name, r, df_f, df_error, math.nan, math.nan))
                effects.append(math.nan)
                continue
            critical = stats.f.isf(alpha, df_f, df_error)

            def short(
                lam: float,
                df_f: float = df_f,
                df_error: float = df_error,
                critical: float = critical,
            ) -> float:
                return float(stats.ncf.sf(critical, df_f, df_error, lam)) - target

            high = 1.0
            while short(high) < 0:
                high *= 2.0
            lam = optimize.brentq(short, 1e-12, high, xtol=1e-12, rtol=1e-12)
            rows.append(_row(design, f.name, r, df_f, df_error, lam, target))
            effects.append(sigma * math.sqrt(lam / per_unit))
    return pd.DataFrame(rows, columns=list(POWER_COLUMNS)).assign(effect=effects)


def pure_error_sigma(summary: pd.DataFrame, factors: Sequence[Any], response: str) -> float:
    """The run-to-run standard deviation of ``response`` at one setting, from a replicated
    campaign: the square root of its pure-error mean square (the runs' scatter about their
    test's mean, pooled over the tests) [response unit].

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only usable runs count, as in
        :func:`brakeca.analysis.anova`).
    factors
        The design's factors.
    response
        The response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3].

    Returns
    -------
    float
        ``sqrt(pure_error_ss / pure_error_df)`` [response unit], the ``sigma`` that
        :func:`factor_power` takes.

    Raises
    ------
    ValueError
        No test with two usable runs (an unreplicated campaign has no pure error).
    """
    return pure_error(summary, factors, response)[0]


def pure_error(
    summary: pd.DataFrame, factors: Sequence[Any], response: str, confidence: float = 0.95
) -> tuple[float, float, tuple[float, float]]:
    """:func:`pure_error_sigma` with its degrees of freedom and confidence interval: how
    well the campaign knows the scatter (a few degrees of freedom know it roughly, and the
    power computed from it inherits that).

    Parameters
    ----------
    summary, factors, response
        As :func:`pure_error_sigma` takes them.
    confidence
        Of the interval [-].

    Returns
    -------
    tuple
        ``(sigma, df, (low, high))``: sigma [response unit], its degrees of freedom [-] and
        the chi-square interval of sigma, ``sigma sqrt(df / chi2(1 - a/2, df))`` to ``sigma
        sqrt(df / chi2(a/2, df))`` [response unit].

    Raises
    ------
    ValueError
        No test with two usable runs.
    """
    from scipy import stats

    from brakeca.analysis import anova

    attrs = anova(summary, factors, response).attrs
    df = float(attrs.get("pure_error_df", math.nan))
    if not df >= 1:
        raise ValueError(
            f"{response}: the campaign has no pure error (no test with two usable runs): "
            "sigma needs a replicated campaign, or give it yourself"
        )
    sigma = math.sqrt(float(attrs["pure_error_ss"]) / df)
    tail = (1.0 - confidence) / 2.0
    low = sigma * math.sqrt(df / float(stats.chi2.ppf(1.0 - tail, df)))
    high = sigma * math.sqrt(df / float(stats.chi2.ppf(tail, df)))
    return sigma, df, (low, high)
