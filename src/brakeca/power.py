"""How likely a design's analysis is to find a factor's effect, and how many replicates it needs.

A campaign's runs scatter from seed to seed (the random fibre layout and automaton): the pure
error of a replicated study. Whether the study's ANOVA calls a factor significant then
depends on the size of its effect against that scatter, on the number of runs and on the
degrees of freedom the model leaves for the error. Before spending hours of simulation, this
module gives, for each factor of a design, the power of that ANOVA's F test: the probability
that it finds (p < alpha) a difference ``effect`` between two of the factor's level means
when the runs scatter by ``sigma``, as Minitab's "Power and Sample Size" for factorial designs
computes it (the smallest noncentrality a difference of ``effect`` can give: two level means
``effect`` apart, the others midway).

The model is the one the study fits (:func:`brakeca.analysis.anova`): main effects and the
two-factor interactions the design can estimate, main effects alone for a Plackett-Burman
design, the interactions pooled into the error when they would leave none. Its error degrees
of freedom come from the design's own tests, repeated ``replicates`` times.

References
----------
D. C. Montgomery, Design and Analysis of Experiments, 8th ed., Wiley 2013, section 5.3.5
(choice of sample size: the noncentrality of the F test of a factor's main effect).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

if TYPE_CHECKING:
    from brakeca.design import Design

__all__ = ["POWER_COLUMNS", "factor_power", "pure_error_sigma", "replicates_needed"]

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


def _check(effect: float, sigma: float, alpha: float) -> None:
    for name, value in (("effect", effect), ("sigma", sigma)):
        if isinstance(value, bool) or not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name}: expected a finite number above 0, got {value!r}")
    if isinstance(alpha, bool) or not 0 < alpha < 1:
        raise ValueError(f"alpha: expected a significance level between 0 and 1, got {alpha!r}")


def _model_df(design: Design, replicates: int) -> tuple[dict[str, float], float, dict[str, int]]:
    """The main-effect df of each factor in the study's ANOVA model over the design's tests,
    each ``replicates`` times, its error df, and each factor's smallest number of runs at one
    of its levels [-]."""
    from brakeca.analysis import anova

    combos = design.combinations()
    rows = [dict(c) for c in combos for _ in range(replicates)]
    frame = pd.DataFrame(rows, columns=list(design.factor_names))
    # any response that is not constant: the degrees of freedom do not depend on it
    frame["y"] = np.cos(np.arange(len(frame)) * 2.399963)
    frame["status"] = "ok"
    table = anova(
        frame,
        list(design.factors),
        "y",
        interactions=design.plackett_burman is None,
    )
    df = {str(t): float(d) for t, d in zip(table["term"], table["df"], strict=True)}
    df_error = df.pop("Residual", 0.0)
    counts = {
        f.name: int(frame[f.name].value_counts().reindex(list(f.levels), fill_value=0).min())
        for f in design.factors
    }
    return df, df_error, counts


def factor_power(
    design: Design,
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
        A design (not a response-surface design, whose report fits a surface instead).
    effect
        The difference between two of a factor's level means to find [response unit].
    sigma
        The run-to-run standard deviation of the response at one setting (the seed-to-seed
        scatter; a replicated campaign's pure error, :func:`pure_error_sigma`) [response
        unit, the same as ``effect``'s].
    replicates
        Runs per test to evaluate [-]; by default 1 to 5.
    alpha
        Significance level of the test [-].

    Returns
    -------
    pandas.DataFrame
        :data:`POWER_COLUMNS`, one row per factor and number of replicates: ``levels`` [-],
        ``replicates`` [-], ``runs`` (tests times replicates) [-], ``df`` (the factor's
        degrees of freedom) [-], ``df_error`` [-], ``noncentrality`` (of the F test,
        ``n * effect**2 / (2 * sigma**2)`` with ``n`` the runs at each level; the fewest, when
        a run table gives the levels unevenly, which makes the power a lower bound) [-] and
        ``power`` [-] (NaN without error degrees of freedom: add replicates).

    Raises
    ------
    ValueError
        ``effect`` or ``sigma`` not above 0, ``alpha`` outside (0, 1), a replicate count
        below 1, or a response-surface design.
    """
    from scipy import stats

    _check(effect, sigma, alpha)
    if design.is_response_surface:
        raise ValueError(
            "design: the power of a response-surface design's terms is not computed here (its "
            "report fits a quadratic surface, not the factorial ANOVA)"
        )
    counts = list(replicates) if replicates is not None else [1, 2, 3, 4, 5]
    for r in counts:
        if isinstance(r, bool) or not isinstance(r, int | np.integer) or r < 1:
            raise ValueError(f"replicates: expected whole numbers of 1 or more, got {r!r}")
    rows = []
    for r in counts:
        df, df_error, at_level = _model_df(design, int(r))
        for f in design.factors:
            df_f = df.get(f.name, math.nan)
            lam = at_level[f.name] * effect**2 / (2.0 * sigma**2)
            if df_error >= 1 and df_f >= 1:
                critical = stats.f.isf(alpha, df_f, df_error)
                power = float(stats.ncf.sf(critical, df_f, df_error, lam))
            else:
                power = math.nan
            rows.append(
                {
                    "factor": f.name,
                    "levels": len(f.levels),
                    "replicates": int(r),
                    "runs": design.n_tests * int(r),
                    "df": df_f,
                    "df_error": df_error,
                    "noncentrality": lam,
                    "power": power,
                }
            )
    return pd.DataFrame(rows, columns=list(POWER_COLUMNS))


def replicates_needed(
    design: Design, effect: float, sigma: float, *, target: float = 0.8, alpha: float = 0.05
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
        As :func:`factor_power`, or ``target`` outside (0, 1).
    """
    if isinstance(target, bool) or not 0 < target < 1:
        raise ValueError(f"target: expected a power between 0 and 1, got {target!r}")
    _check(effect, sigma, alpha)
    rows: dict[int, dict[str, pd.Series]] = {}

    def at(r: int) -> dict[str, pd.Series]:
        if r not in rows:
            table = factor_power(design, effect, sigma, replicates=[r], alpha=alpha)
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


def pure_error_sigma(summary: pd.DataFrame, factors: Sequence[Any], response: str) -> float:
    """The run-to-run standard deviation of ``response`` at one setting, from a replicated
    campaign: the square root of its pure-error mean square (the runs' scatter about their
    test's mean, pooled over the tests) [response unit].

    Raises
    ------
    ValueError
        No test with two usable runs (an unreplicated campaign has no pure error).
    """
    from brakeca.analysis import anova

    attrs = anova(summary, factors, response).attrs
    df = float(attrs.get("pure_error_df", math.nan))
    if not df >= 1:
        raise ValueError(
            f"{response}: the campaign has no pure error (no test with two usable runs): "
            "sigma needs a replicated campaign, or give it yourself"
        )
    return math.sqrt(float(attrs["pure_error_ss"]) / df)
