"""Box-Cox check of a response's scale: which power of the response a linear model fits best.

The ANOVA and the response surface assume residuals of one variance. When a factor multiplies
the response (as WP does V, over two decades), the residuals grow with it, and a power or the
log of the response is the scale on which the effects add. Box and Cox (1964) choose that
scale from the data: among the power transformations

    y(λ) = (y^λ - 1) / (λ g^(λ-1))     (λ ≠ 0),     y(0) = g ln y,

with ``g`` the geometric mean of ``y`` (so that every ``y(λ)`` is in the unit of ``y`` and the
residual sums of squares of different ``λ`` compare), the maximum-likelihood ``λ`` is the one
whose fit of the model leaves the smallest residual sum of squares ``SSE(λ)``. The profile
log-likelihood is

    L(λ) = -(n / 2) ln(SSE(λ) / n),

and the values of ``λ`` with ``L(λ) >= L(λ̂) - χ²(1, 0.95) / 2`` form its 95 % confidence
interval (the likelihood-ratio interval, as R's ``MASS::boxcox`` draws it; Minitab's help
does not give the formula of its plot's interval). The likelihood counts all ``n`` runs, not
the residual degrees of freedom, so where the model leaves few of them the interval is narrow:
Montgomery's approximate interval (section 15.1.1: the ``λ`` whose ``SSE(λ)`` lies below
``SSE(λ̂) (1 + t²(α/2, ν) / ν)``, ``ν`` the residual degrees of freedom) is wider, e.g. for V
of the paper's full-resolution study (9 residual degrees of freedom of 24 runs) -0.14 to 0.21
against -0.08 to 0.11, and for MU up to -0.50 against -0.87. Both are computed
(``ci_low``, ``ci_high`` and ``ci_low_df``, ``ci_high_df``). The reading follows the
likelihood-ratio interval, and says so where Montgomery's also holds λ = 1 or λ = 0 that the
other leaves out: then the data do not settle the scale (a helper's review found a response
surface with 7 residual degrees of freedom whose MU read "the log fits better" though
Montgomery's interval held λ = 1). As Minitab
does, ``λ`` is searched in [-2, 2] and a rounded value (the nearest multiple of 0.5) is
reported beside the optimum.

This module only reads the data: it says whether the untransformed response (``λ = 1``) or
its log (``λ = 0``) is supported, so a reader can tell whether the study's ``log10_V_mm3``
is the better scale for V. It changes no analysis.

References
----------
G. E. P. Box and D. R. Cox, "An analysis of transformations", Journal of the Royal
Statistical Society B 26 (1964) 211-252, doi:10.1111/j.2517-6161.1964.tb00553.x.
D. C. Montgomery, Design and Analysis of Experiments, 8th ed., Wiley 2013, section 15.1.1.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from brakeca._io import write_table
from brakeca.analysis import UNUSUAL_RESIDUAL as _UNUSUAL_RESIDUAL
from brakeca.analysis import exact_fit

if TYPE_CHECKING:
    from brakeca.analysis import Model

__all__ = [
    "BOX_COX_COLUMNS",
    "BoxCox",
    "box_cox",
    "box_cox_profile",
    "box_cox_table",
    "surface_box_cox",
]

#: The search range of λ [-], Minitab's.
LAMBDA_RANGE: tuple[float, float] = (-2.0, 2.0)
#: How near an end of the search range λ̂ is on its edge [-]: the bounded search stops about
#: 1e-3 short of an edge where the likelihood still rises there.
EDGE_TOLERANCE = 1e-3

#: Points of the profile on :data:`LAMBDA_RANGE` (a step of 0.025) [-].
_GRID_POINTS = 161

#: The standardized residual beyond which a run is unusual (Minitab's "R") [-]: the one of
#: :func:`brakeca.analysis.unusual_runs` and the report's list of unusual runs.
UNUSUAL_RESIDUAL = _UNUSUAL_RESIDUAL

#: Columns of :func:`box_cox_table`, in order.
BOX_COX_COLUMNS: tuple[str, ...] = (
    "response",
    "n",
    "df_resid",
    "model",
    "lambda_hat",
    "ci_low",
    "ci_high",
    "ci_low_df",
    "ci_high_df",
    "rounded_lambda",
    "confidence",
    "reading",
    "note",
    "without_unusual",
)


def interval_text(low: float, high: float) -> str:
    """An interval of λ in words, ``"-0.08 to 0.11"``; an end beyond the search range
    (infinite) as ``"below -2"`` or ``"above 2"``."""
    lo, hi = LAMBDA_RANGE
    a = f"below {lo:g}" if math.isinf(low) else f"{low:.2f}"
    b = f"above {hi:g}" if math.isinf(high) else f"{high:.2f}"
    return f"{a} to {b}"


@dataclass(frozen=True)
class BoxCox:
    """The Box-Cox profile of one response under one model (:func:`box_cox_profile`).

    Attributes
    ----------
    response
        The response column, e.g. ``"V"``.
    n
        Runs used [-].
    df_resid
        Residual degrees of freedom of the model [-].
    model
        The model the transformed response was fitted with, as text.
    lambda_hat
        The maximum-likelihood λ in :data:`LAMBDA_RANGE` [-]; NaN when it is not defined
        (``note`` says why).
    ci_low, ci_high
        The confidence interval of λ [-]; ``-inf`` or ``inf`` where it reaches past the
        search range on that side; NaN when λ is not defined.
    rounded
        ``lambda_hat`` rounded to the nearest multiple of 0.5 [-] (Minitab's rounded λ).
    confidence
        The interval's confidence level [-].
    profile
        ``lam`` [-] and ``log_likelihood`` [-] over :data:`LAMBDA_RANGE` (empty when λ is
        not defined).
    note
        Why λ is not defined, or that the optimum lies on the search range's edge.
    ci_low_df, ci_high_df
        Montgomery's approximate interval of λ [-], which counts the residual degrees of
        freedom: the λ whose ``SSE(λ)`` lies below ``SSE(λ̂) (1 + t²(α/2, ν) / ν)``; wider than
        ``ci_low``, ``ci_high`` where ``ν`` is small. ``-inf``, ``inf`` and NaN as those.
    without_unusual
        What λ̂, its interval and the reading become without the unusual runs (standardized
        residual beyond ``unusual`` in :func:`box_cox`), under the same model terms, one
        sentence, or why there is no second profile (the runs left cannot estimate the same
        model); empty where no run is unusual, and always under a response surface's
        quadratic (:func:`surface_box_cox` makes no second profile). One run can carry the
        whole reading: in the quick paper study MU's λ̂ is
        -1.17 (interval up to -0.49), and without its one unusual run -0.09 (-1.81 to 1.37),
        which holds both λ = 1 and λ = 0 (a DoE review).
    without
        The second profile itself, without the unusual runs (None where there is none), and
        ``without_runs`` those runs by name (``"test 23"``), as :func:`brakeca.plotting.
        plot_box_cox` draws it beside the first.
    """

    response: str
    n: int
    df_resid: float
    model: str
    lambda_hat: float
    ci_low: float
    ci_high: float
    rounded: float
    confidence: float
    profile: pd.DataFrame
    note: str = ""
    ci_low_df: float = math.nan
    ci_high_df: float = math.nan
    without_unusual: str = ""
    without: BoxCox | None = None
    without_runs: str = ""

    @property
    def defined(self) -> bool:
        """Whether λ could be estimated."""
        return math.isfinite(self.lambda_hat)

    @property
    def edge(self) -> int:
        """-1 or +1 where λ̂ lies on the low or high edge of the search range (within
        :data:`EDGE_TOLERANCE`; the best λ may lie beyond it, so λ̂ is a bound, not an
        estimate), 0 inside it or where λ is not defined [-]."""
        if not self.defined or self.profile.empty:
            return 0
        lam = self.profile["lam"].to_numpy(dtype=float)
        if self.lambda_hat <= lam[0] + EDGE_TOLERANCE:
            return -1
        return 1 if self.lambda_hat >= lam[-1] - EDGE_TOLERANCE else 0

    def hat_text(self) -> str:
        """λ̂ as a report writes it: ``"-1.43"``, or on the search range's edge the bound it
        is, ``"≤ -2"`` or ``"≥ 2"`` (a figures review read "λ̂ = -2.00" beside an interval
        open to -inf)."""
        if self.edge:
            lam = self.profile["lam"].to_numpy(dtype=float)
            return f"≤ {lam[0]:g}" if self.edge < 0 else f"≥ {lam[-1]:g}"
        return f"{self.lambda_hat:.2f}"

    def contains(self, lam: float) -> bool:
        """Whether ``lam`` [-] lies within the confidence interval.

        Parameters
        ----------
        lam
            A power λ [-].

        Returns
        -------
        bool
            True if λ is defined and ``ci_low <= lam <= ci_high`` (ends included).
        """
        return self.defined and self.ci_low <= lam <= self.ci_high

    @property
    def reading(self) -> str:
        """What the interval says about the scale, in one sentence; where Montgomery's wider
        interval (``ci_low_df``, ``ci_high_df``) also holds λ = 1 or λ = 0 that the
        likelihood-ratio interval leaves out, a clause says so."""
        if not self.defined:
            return ""
        sentence = self._likelihood_reading()
        also = [
            f"λ = {lam:g}"
            for lam in (1.0, 0.0)
            if not self.contains(lam) and self.ci_low_df <= lam <= self.ci_high_df
        ]
        if also:
            wider = interval_text(self.ci_low_df, self.ci_high_df)
            sentence += (
                f"; but with {self.df_resid:g} residual degrees of freedom, Montgomery's wider "
                f"interval ({wider}) also holds {' and '.join(also)}, so the data do not "
                "settle the scale"
            )
        return sentence

    def _halves_inside(self) -> list[float]:
        """The multiples of 0.5 in :data:`LAMBDA_RANGE` that the interval holds [-]."""
        lo, hi = LAMBDA_RANGE
        return [k / 2 for k in range(int(2 * lo), int(2 * hi) + 1) if self.contains(k / 2)]

    def _pointed(self) -> float:
        """Where neither λ = 1 nor λ = 0 lies within the interval, the power the reading
        points to: the multiple of 0.5 within it nearest λ̂, else λ̂ itself [-]."""
        inside = self._halves_inside()
        if inside:
            return min(inside, key=lambda lam: abs(lam - self.lambda_hat))
        return self.lambda_hat

    def _points_to(self) -> tuple[bool, bool, float | None]:
        """What the likelihood-ratio reading says: whether λ = 1 and λ = 0 lie within the
        interval, and where neither does, the power it points to (rounded as the reading
        shows it)."""
        one, zero = self.contains(1.0), self.contains(0.0)
        pointed = None if one or zero else float(f"{self._pointed():.2g}")
        return one, zero, pointed

    def _likelihood_reading(self) -> str:
        """:attr:`reading` from the likelihood-ratio interval alone."""
        pct = f"{100 * self.confidence:g} %"
        if self.contains(1.0) and self.contains(0.0):
            return (
                f"both λ = 1 (the response as it is) and λ = 0 (its log) lie within the {pct} "
                "interval: the data do not choose between them"
            )
        if self.contains(1.0):
            return f"λ = 1 lies within the {pct} interval: no transformation is called for"
        if self.contains(0.0):
            rounded = (
                f"; so does λ = {self.rounded:g}, the rounded λ̂"
                if self.rounded not in (0.0, 1.0) and self.contains(self.rounded)
                else ""
            )
            return (
                f"λ = 0 lies within the {pct} interval and λ = 1 does not: the log fits "
                "better than the response as it is" + rounded
            )
        if self._halves_inside():  # the simple power nearest the optimum that the interval holds
            return (
                f"neither λ = 1 nor λ = 0 lies within the {pct} interval: the data point to "
                f"λ ≈ {self._pointed():g}"
            )
        return (
            f"neither λ = 1 nor λ = 0, nor any multiple of 0.5, lies within the {pct} "
            f"interval: the data point to λ ≈ {self.lambda_hat:.2g}"
        )

    def row(self) -> dict[str, Any]:
        """One row of :func:`box_cox_table`."""
        return {
            "response": self.response,
            "n": self.n,
            "df_resid": self.df_resid,
            "model": self.model,
            "lambda_hat": self.lambda_hat,
            "ci_low": self.ci_low,
            "ci_high": self.ci_high,
            "ci_low_df": self.ci_low_df,
            "ci_high_df": self.ci_high_df,
            "rounded_lambda": self.rounded,
            "confidence": self.confidence,
            "reading": self.reading,
            "note": self.note,
            "without_unusual": self.without_unusual,
        }


def _undefined(
    response: str, n: int, df_resid: float, model: str, confidence: float, note: str
) -> BoxCox:
    nan = math.nan
    empty = pd.DataFrame({"lam": pd.Series(dtype=float), "log_likelihood": pd.Series(dtype=float)})
    return BoxCox(response, n, df_resid, model, nan, nan, nan, nan, confidence, empty, note)


def box_cox_profile(
    y: Sequence[float] | np.ndarray,
    exog: np.ndarray | None = None,
    *,
    response: str = "y",
    model: str = "",
    confidence: float = 0.95,
) -> BoxCox:
    """The Box-Cox profile likelihood of ``y`` under the linear model ``exog``.

    Parameters
    ----------
    y
        The response, every value positive and finite [response unit].
    exog
        The model matrix, one row per value of ``y``, its intercept included [-]; None for
        the intercept alone. Its rank, not its number of columns, counts.
    response
        The response's name, for the result.
    model
        The model as text, for the result.
    confidence
        Level of the interval of λ [-], in (0, 1).

    Returns
    -------
    BoxCox
        λ̂, its likelihood-ratio interval and Montgomery's (``ci_low_df``, ``ci_high_df``),
        the rounded λ and the profile. λ is not defined (NaN, with a note)
        when a value is not positive, the response is constant, or the model leaves fewer
        than two residual degrees of freedom (with one, the profile has a pole wherever the
        one residual changes sign).

    Raises
    ------
    ValueError
        ``y`` holds a value that is not finite, ``exog`` has another number of rows, or
        ``confidence`` lies outside (0, 1).

    Notes
    -----
    With ``u = y / g``, ``y(λ) = g (u^λ - 1) / λ`` plus a constant, which the intercept
    absorbs (``expm1(λ ln u) / λ``, exact at λ = 0 as ``ln u``); so the residuals are computed
    on a scale near 1 whatever the unit of ``y`` (V in m³ is about 1e-9), and λ̂ does not
    depend on that unit.
    """
    from scipy import optimize, stats

    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    y = np.asarray(y, dtype=float).ravel()
    if not np.all(np.isfinite(y)):
        raise ValueError(f"{response}: every value must be finite")
    n = y.size
    x = np.ones((n, 1)) if exog is None else np.asarray(exog, dtype=float)
    if x.ndim != 2 or x.shape[0] != n:
        raise ValueError(f"{response}: exog has shape {x.shape}, {n} rows expected")
    rank = int(np.linalg.matrix_rank(x)) if n else 0
    df_resid = float(n - rank)

    def undefined(note: str) -> BoxCox:
        return _undefined(response, n, df_resid, model, confidence, note)

    if n < 2:
        return undefined(f"{n} usable run(s)")
    if np.any(y <= 0.0):
        return undefined("needs positive values (a power of a value ≤ 0 is not defined)")
    log_y = np.log(y)
    log_u = log_y - float(np.mean(log_y))
    if float(np.ptp(log_u)) <= 1e-13:
        return undefined("the response is constant")
    if df_resid < 0.5:
        return undefined("the model leaves no residual degrees of freedom")
    if df_resid < 1.5:  # the residual space is one line: SSE(λ) is one residual squared
        return undefined(
            "the model leaves one residual degree of freedom: the likelihood's SSE is then "
            "one residual squared, which falls to zero wherever that residual changes sign, "
            "and λ̂ would sit on that pole"
        )
    # An orthonormal basis of the model's columns: the residual of w is w - Q (Q' w).
    u_svd, sing, _ = np.linalg.svd(x, full_matrices=False)
    q = u_svd[:, : int(np.sum(sing > sing[0] * max(x.shape) * np.finfo(float).eps))]
    g = math.exp(float(np.mean(log_y)))

    def log_likelihood(lam: float) -> float:
        w = log_u if lam == 0.0 else np.expm1(lam * log_u) / lam
        r = w - q @ (q.T @ w)
        if exact_fit(float(r @ r), w):  # an exact fit, to round-off: the likelihood is
            # unbounded there (a λ̂ fitted to round-off had been given: an analysis review)
            return math.inf
        sse = g * g * float(r @ r)
        return -0.5 * n * math.log(sse / n)

    lo, hi = LAMBDA_RANGE
    grid = np.linspace(lo, hi, _GRID_POINTS)
    ll = np.array([log_likelihood(float(lam)) for lam in grid])
    if not np.all(np.isfinite(ll)):
        return undefined("the model fits the transformed response exactly at some λ")
    k = int(np.argmax(ll))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    best = optimize.minimize_scalar(
        lambda lam: -log_likelihood(float(lam)),
        bounds=(a, b),
        method="bounded",
        options={"xatol": 1e-8},
    )
    lam_hat, ll_hat = float(best.x), -float(best.fun)
    if ll[k] > ll_hat:  # the grid point is better (an edge of the range)
        lam_hat, ll_hat = float(grid[k]), float(ll[k])
    cut = ll_hat - 0.5 * float(stats.chi2.ppf(confidence, 1))
    # Montgomery's: SSE(λ) <= SSE(λ̂) (1 + t²/ν), i.e. L(λ) >= L(λ̂) - (n/2) ln(1 + t²/ν)
    t = float(stats.t.ppf(0.5 + confidence / 2, df_resid))
    cut_df = ll_hat - 0.5 * n * math.log1p(t * t / df_resid)

    def crossing(side: int, cut: float) -> float:
        """Where L falls to ``cut`` on one side of λ̂; ±inf beyond the search range."""
        # the grid points outwards from λ̂, with the profile already computed there
        inner = np.flatnonzero(grid < lam_hat)[::-1] if side < 0 else np.flatnonzero(grid > lam_hat)
        points = np.concatenate(([lam_hat], grid[inner]))
        values = np.concatenate(([ll_hat], ll[inner]))
        below = np.nonzero(values < cut)[0]
        if below.size == 0:
            return -math.inf if side < 0 else math.inf
        j = int(below[0])
        return float(
            optimize.brentq(
                lambda lam: log_likelihood(float(lam)) - cut,
                points[j - 1],
                points[j],
                xtol=1e-10,
            )
        )

    ci_low, ci_high = crossing(-1, cut), crossing(+1, cut)
    ci_low_df, ci_high_df = crossing(-1, cut_df), crossing(+1, cut_df)
    note = ""
    # the bounded search stops within about 1e-3 of an edge where the likelihood still
    # rises there (-1.9997 was seen for a rising profile; a helper's review)
    if lam_hat <= lo + EDGE_TOLERANCE or lam_hat >= hi - EDGE_TOLERANCE:
        note = (
            f"λ̂ lies on the edge of the search range [{lo:g}, {hi:g}]: the best λ may lie beyond it"
        )
    rounded = float(min(max(0.5 * round(2.0 * lam_hat), lo), hi))
    profile = pd.DataFrame({"lam": grid, "log_likelihood": ll})
    return BoxCox(
        response,
        n,
        df_resid,
        model,
        lam_hat,
        ci_low,
        ci_high,
        rounded,
        confidence,
        profile,
        note,
        ci_low_df,
        ci_high_df,
    )


def box_cox(
    summary: pd.DataFrame,
    factors: Iterable[Any],
    response: str,
    *,
    interactions: Model = True,
    alpha_to_remove: float | None = None,
    confidence: float = 0.95,
    unusual: float | None = UNUSUAL_RESIDUAL,
) -> BoxCox:
    """The Box-Cox profile of a campaign's response under the ANOVA model.

    The model is the one :func:`brakeca.analysis.anova` fits (categorical factors, with the
    two-factor interactions unless they would saturate it), over the usable runs. Where runs
    have a standardized residual beyond ``unusual`` under that model (the report's unusual
    runs), the profile is computed again without them under the same terms (a reduced model
    is not reduced again), and :attr:`BoxCox.without_unusual` says what it reads then, or
    that the runs left cannot estimate that model.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
    factors
        The design's factors.
    response
        A positive response, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    interactions
        Include two-factor interactions, or up to an order, as in
        :func:`brakeca.analysis.anova`.
    alpha_to_remove
        The model reduced by backward elimination, as :func:`brakeca.analysis.anova`
        reduces it (on the response as it is).
    confidence
        Level of the interval of λ [-].
    unusual
        The size of standardized residual [-] beyond which a run is left out of the second
        profile (2, Minitab's "R"); None for no second profile.

    Returns
    -------
    BoxCox
        See :func:`box_cox_profile`.

    Raises
    ------
    ValueError
        An ``interactions`` order or ``alpha_to_remove`` that :func:`brakeca.analysis.anova`
        refuses, or as :func:`box_cox_profile` (``confidence`` outside (0, 1)).
    """
    from brakeca.analysis import _model_arrays

    factors = list(factors)
    summary = summary.reset_index(drop=True)  # runs by position: its labels may repeat
    data, y, exog, formula = _model_arrays(
        summary, factors, response, interactions, alpha_to_remove=alpha_to_remove
    )
    result = box_cox_profile(
        y, exog, response=response, model=f"ANOVA model: {formula}", confidence=confidence
    )
    if unusual is None or not result.defined:
        return result
    from dataclasses import replace

    from brakeca.analysis import _refit_without, _residuals_of

    frame = _residuals_of(data, y, exog, formula, response)  # (the model fitted once)
    # the residuals' rows are the model's runs (``data``), in its order
    z = pd.to_numeric(frame["std_residual"], errors="coerce").to_numpy(dtype=float)
    large = np.abs(np.nan_to_num(z)) > unusual
    if not large.any():
        return result
    rows, z = data.loc[large], z[large]
    from brakeca._console import is_replicated

    replicated = is_replicated(data)
    who = _runs_named(rows, z, replicated)
    # the same model without those runs (its terms as the first fit took them)
    try:
        refit = _refit_without(summary, factors, response, formula, exog, rows.index)
        if refit is None:  # no terms
            return result
        other = box_cox_profile(refit.y, refit.exog, response=response, confidence=confidence)
    except ValueError as exc:  # too few runs left for the model
        return replace(result, without_unusual=f"without {who}: {exc}")
    if not refit.same:
        return replace(
            result,
            without_unusual=(
                f"without {who}, the runs left cannot estimate the same model "
                f"({formula.split('~', 1)[1].strip()}): no second profile"
            ),
        )
    from brakeca._console import run_named, tests_named

    return replace(
        result,
        without_unusual=_without_text(result, other, who, len(rows)),
        without=other,
        # "; " between runs: a replicated campaign's names hold commas (a diff review);
        # "tests 17, 23" otherwise, not "test 17; test 23" (a review)
        without_runs=(
            "; ".join(run_named(rec, replicated) for _, rec in rows.iterrows())
            if replicated or "test" not in rows
            else tests_named(int(t) for t in rows["test"])
        ),
    )


def _runs_named(rows: pd.DataFrame, z: np.ndarray, replicated: bool) -> str:
    """The unusual runs ``rows`` by test (and replicate, in a ``replicated`` campaign, as the
    report's list of unusual runs names them), with their standardized residuals ``z``."""
    from brakeca._console import run_named

    names = [
        f"{run_named(rec, replicated)} (standardized residual {zi:+.2f})"
        for (_, rec), zi in zip(rows.iterrows(), z, strict=True)
    ]
    return " and ".join(names) if len(names) < 3 else ", ".join(names)


def _without_text(result: BoxCox, other: BoxCox, who: str, n: int) -> str:
    """:attr:`BoxCox.without_unusual`: the second profile's λ̂, interval and reading, and
    whether the first (likelihood-ratio) reading holds without the ``n`` runs ``who``: the
    same of λ = 1 and λ = 0 inside the interval and, where neither is, the same power
    pointed to."""
    if not other.defined:
        return f"without {who}, λ is not defined ({other.note})"
    them = "that run" if n == 1 else "those runs"
    first = result._points_to()
    holds = other._points_to() == first
    if not holds and not (first[0] or first[1]):
        # both point to a power no simple one stands for: the same reading where the second
        # λ̂ lies within the first interval (-0.21 against -0.22, to two figures, had been
        # "rests on those runs": a review of a replicated study)
        holds = (
            not other.contains(1.0)
            and not other.contains(0.0)
            and not result._halves_inside()
            and not other._halves_inside()
            and result.contains(other.lambda_hat)
        )
    verdict = "the reading holds" if holds else f"so the reading of all the runs rests on {them}"
    note = f" ({other.note})" if other.note else ""
    return (
        f"without {who}: λ̂ = {other.lambda_hat:.2f}{note}, "
        f"{100 * other.confidence:g} % interval {interval_text(other.ci_low, other.ci_high)}; "
        f"{other._likelihood_reading()}; {verdict}"
    )


def surface_box_cox(fit: Any, *, confidence: float = 0.95) -> BoxCox:
    """The Box-Cox profile of a response under its fitted response-surface model.

    Parameters
    ----------
    fit
        A :class:`brakeca.rsm.SurfaceFit`: its runs and its model's terms (as fitted, after
        any elimination) in coded units.
    confidence
        Level of the interval of λ [-].

    Returns
    -------
    BoxCox
        See :func:`box_cox_profile`.

    Raises
    ------
    ValueError
        ``confidence`` outside (0, 1) (as :func:`box_cox_profile`).
    """
    from brakeca import rsm

    points = fit.points
    x = {c.name: points[c.name].to_numpy(dtype=float) for c in fit.codings}
    columns = [np.ones(len(points))] + [rsm._term_values(t, x) for t in fit.terms]
    model = "quadratic model: " + (" + ".join(fit.terms) if fit.terms else "constant")
    return box_cox_profile(
        points["y"].to_numpy(dtype=float),
        np.column_stack(columns),
        response=fit.response,
        model=model,
        confidence=confidence,
    )


def box_cox_table(results: Mapping[str, BoxCox] | Iterable[BoxCox]) -> pd.DataFrame:
    """The results as one table, one row per response (:data:`BOX_COX_COLUMNS`).

    Parameters
    ----------
    results
        :class:`BoxCox` results, or a mapping whose values are (its keys are not used).

    Returns
    -------
    pandas.DataFrame
        One row per result (:meth:`BoxCox.row`), the columns :data:`BOX_COX_COLUMNS`; λ and
        its interval [-].
    """
    items = results.values() if isinstance(results, Mapping) else results
    return pd.DataFrame([r.row() for r in items], columns=list(BOX_COX_COLUMNS))


def save_box_cox_table(results: Mapping[str, BoxCox], path: str | Path) -> Path:
    """Write :func:`box_cox_table` as CSV to ``path``; returns the path.

    Parameters
    ----------
    results
        Response to :class:`BoxCox` result.
    path
        The CSV file to write; its folder is created if missing.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_table(box_cox_table(results), path)
    return path
