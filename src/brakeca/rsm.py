"""Response-surface models of a campaign: a quadratic in the coded factors, as Minitab's
"Analyze Response Surface Design" and JMP's "Response Surface" fit it.

The factorial analysis (:mod:`brakeca.analysis`) treats every factor as categorical: one mean
per level. A design whose factors take several numeric levels, such as a central composite
design (``composite`` in a design file, :mod:`brakeca.design`), is read instead as a smooth
function of the factors: each factor is coded to ``x = -1`` at its low and ``x = +1`` at its
high level (on log10 of the level for a factor with ``coding = "log"``, such as WP, whose
levels span decades), and the response is fitted by least squares to

.. math::

    \\hat y = b_0 + \\sum_i b_i x_i + \\sum_i b_{ii} x_i^2 + \\sum_{i<j} b_{ij} x_i x_j

(a square term only for a factor with three or more distinct levels in the data). The fit
gives Minitab's tables: the coded coefficients with their standard errors, t and p values and
variance inflation factors; the analysis of variance with adjusted (type III) sums of squares,
by source (linear, square, two-way interaction, each term) with the error split into lack of
fit and pure error when the design repeats a point (centre points: here the seed-to-seed
scatter); the model summary (S, R², adjusted and predicted R²); and the stationary point of
the surface (where its gradient is zero: a maximum, a minimum or a saddle point), in coded
and in the factors' own units. :func:`optimize` then finds the factor setting that best meets
goals for several responses at once (Derringer and Suich's desirability, Minitab's Response
Optimizer). The designs made for this are the central composite and the Box-Behnken design
(``composite``, ``box_behnken``).

Pure numpy, pandas and scipy; the figures are :func:`brakeca.plotting.plot_response_surface`
and :func:`brakeca.plotting.plot_overlaid_contours`.

References
----------
D. C. Montgomery, *Design and Analysis of Experiments*, 8th ed., Wiley, 2013, chapter 11
(response surface methods; the stationary point, section 11.3.1; the central composite design,
section 11.4.2).
G. Derringer and R. Suich, "Simultaneous optimization of several response variables",
Journal of Quality Technology 12(4), 214-219, 1980.
G. E. P. Box, J. S. Hunter and W. G. Hunter, *Statistics for Experimenters*, 2nd ed., Wiley,
2005, chapter 11.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from brakeca._io import write_table
from brakeca.analysis import _clean as _usable_rows
from brakeca.analysis import (
    _design_factors,
    _fit_statistics,
    _is_constant,
    _next_to_remove,
    _pure_error_at_round_off,
    _sse,
    _vif,
    alpha_problem,
    display_unit,
    exact_fit,
    shown_unit,
)

__all__ = [
    "ANOVA_COLUMNS",
    "COEFFICIENT_COLUMNS",
    "LEFT_OUT_NOTE",
    "Coding",
    "Goal",
    "Optimum",
    "SurfaceFit",
    "backward_elimination",
    "coding_of",
    "fit_response_surface",
    "optimize",
    "optimum_table",
    "response_surfaces",
    "save_surface_tables",
    "stationary_table",
    "surface_residuals",
    "surface_terms",
]

#: Columns of :attr:`SurfaceFit.coefficients`, in order.
COEFFICIENT_COLUMNS: tuple[str, ...] = ("term", "coef", "se", "t", "p_value", "vif")

#: Columns of :attr:`SurfaceFit.anova`, in order.
ANOVA_COLUMNS: tuple[str, ...] = ("source", "depth", "df", "adj_ss", "adj_ms", "F", "p_value")

#: The end of a fit's note on a term it leaves out, aliased with the terms before it (a term
#: name comes first: ``"A*B" + LEFT_OUT_NOTE``).
LEFT_OUT_NOTE = " cannot be estimated apart from the terms before it: left out"

#: Coded points closer than this [-] are the same point (for pure error and lack of fit).
_SAME_POINT = 1e-9


@dataclass(frozen=True)
class Coding:
    """How one factor is coded in a response-surface model.

    Parameters
    ----------
    name
        The factor's name, its column in the campaign summary.
    low, high
        The levels coded -1 and +1 [design unit], ``low < high``.
    log
        Code log10 of the level (the levels must be positive) rather than the level.
    unit
        Unit of the levels, for labels.
    label
        Human-readable description.
    """

    name: str
    low: float
    high: float
    log: bool = False
    unit: str = ""
    label: str = ""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(
                f"factor {self.name!r}: the levels coded -1 and +1 must be finite with low < "
                f"high, got {self.low!r} and {self.high!r}"
            )
        if self.log and self.low <= 0:
            raise ValueError(
                f"factor {self.name!r}: log coding needs positive levels, got {self.low!r}"
            )

    def _ends(self) -> tuple[float, float]:
        if self.log:
            return math.log10(self.low), math.log10(self.high)
        return self.low, self.high

    def code(self, values: Any) -> np.ndarray:
        """Coded values [-] of levels ``values`` [design unit] (NaN for a non-positive value
        of a log-coded factor).

        Parameters
        ----------
        values
            A level or an array of levels [design unit].

        Returns
        -------
        numpy.ndarray
            Float array of the shape of ``values``: -1 at ``low``, +1 at ``high`` [-].
        """
        v = np.asarray(values, dtype=float)
        lo, hi = self._ends()
        if self.log:
            with np.errstate(divide="ignore", invalid="ignore"):
                v = np.where(v > 0, np.log10(np.where(v > 0, v, 1.0)), np.nan)
        return (v - 0.5 * (lo + hi)) / (0.5 * (hi - lo))

    def decode(self, coded: Any) -> np.ndarray:
        """Levels [design unit] at coded values ``coded`` [-]; a log-coded level beyond the
        floats' range (a stationary point far outside the runs) is inf or 0, without a
        warning.

        Parameters
        ----------
        coded
            A coded value or an array of them [-].

        Returns
        -------
        numpy.ndarray
            Float array of the shape of ``coded``: the levels [design unit] (the inverse of
            :meth:`code`).
        """
        x = np.asarray(coded, dtype=float)
        lo, hi = self._ends()
        v = 0.5 * (lo + hi) + x * 0.5 * (hi - lo)
        if not self.log:
            return v
        with np.errstate(over="ignore", under="ignore"):
            return np.power(10.0, v)

    @property
    def shown_unit(self) -> tuple[str, float]:
        """The unit the figures show the levels in, and its size [design unit]: a length in
        m or a pressure in Pa with the SI prefix that suits the levels coded -1 and +1, as
        the figures of levels show them (:func:`brakeca.analysis.shown_unit`)."""
        return shown_unit(self.unit, (self.low, self.high))

    def shown(self, coded: Any) -> np.ndarray:
        """The levels at the coded values ``coded`` [-] in :attr:`shown_unit`: :meth:`decode`
        over the unit's size (WR's 1e-07 m as 0.1 µm)."""
        return self.decode(coded) / self.shown_unit[1]

    @property
    def axis_label(self) -> str:
        """Name with unit, e.g. ``"WP [m³/(N·m)]"``, ``"WR [µm]"``: the unit of
        :meth:`shown`'s levels (:func:`brakeca.analysis.display_unit`)."""
        unit = self.shown_unit[0]
        return f"{self.name} [{display_unit(unit)}]" if unit and unit != "-" else self.name


def coding_of(factor: Any) -> Coding:
    """The :class:`Coding` of a design factor (:class:`brakeca.design.Factor`), an analysis
    factor (:class:`brakeca.analysis.Factor`) or a mapping with ``name`` and ``levels``.

    Low and high are the factor's ``coded_range`` when it has one (a composite design's cube
    points), else its lowest and highest level; ``coding = "log"`` codes log10.

    Parameters
    ----------
    factor
        The factor: its ``name``, ``levels`` [design unit], and when present ``choices``,
        ``coded_range`` [design unit], ``coding``, ``unit`` and ``label``.

    Returns
    -------
    Coding
        The factor's name, the levels coded -1 and +1 [design unit], log or linear coding,
        unit and label.

    Raises
    ------
    ValueError
        A categorical factor (one with ``choices``): it has no numeric scale to fit a surface
        over; fewer than two distinct levels; log coding with a level that is not positive.
    """
    get = factor.get if isinstance(factor, Mapping) else lambda k, d=None: getattr(factor, k, d)
    name = str(get("name"))
    if get("choices") is not None:
        raise ValueError(
            f"factor {name!r} is categorical (choices): a response surface needs numeric factors"
        )
    levels = [float(v) for v in get("levels") or ()]
    if len(set(levels)) < 2:
        raise ValueError(f"factor {name!r}: needs two different levels, got {levels}")
    coded_range = get("coded_range")
    low, high = (min(levels), max(levels)) if coded_range is None else map(float, coded_range)
    log = str(get("coding", "linear") or "linear") == "log"
    if log and min(levels) <= 0:
        raise ValueError(f"factor {name!r}: log coding needs positive levels, got {min(levels)!r}")
    return Coding(
        name=name,
        low=low,
        high=high,
        log=log,
        unit=str(get("unit", "") or ""),
        label=str(get("label", "") or ""),
    )


@dataclass(frozen=True)
class SurfaceFit:
    """A fitted response surface (:func:`fit_response_surface`).

    Attributes
    ----------
    response
        The response column, e.g. ``"MU"`` [-].
    codings
        The factors' codings, in design order.
    terms
        The model's terms after the intercept: ``"WP"`` (linear), ``"WP*WP"`` (square),
        ``"WP*A"`` (two-way interaction).
    coef
        Intercept then one coefficient per term, in coded units [response unit].
    coefficients
        :data:`COEFFICIENT_COLUMNS`, the intercept (``"Constant"``) first: ``coef`` and ``se``
        [response unit], ``t``, ``p_value`` and ``vif`` (variance inflation factor, 1 for
        orthogonal columns) [-]; ``se``, ``t`` and ``p_value`` NaN without residual degrees of
        freedom.
    anova
        :data:`ANOVA_COLUMNS`: ``source`` (``"Model"``, ``"Linear"``, a term, ``"Square"``,
        ``"2-Way Interaction"``, ``"Error"``, ``"Lack-of-Fit"``, ``"Pure Error"``,
        ``"Total"``), ``depth`` (indentation: 0, 1, 2), ``df`` [-], ``adj_ss`` and ``adj_ms``
        [response unit^2], ``F`` and ``p_value`` [-]. A term's or group's adjusted sum of
        squares is the rise of the error sum of squares when it is dropped from the model.
    statistics
        ``n`` (runs used), ``df_resid``, ``s`` [response unit], ``r_squared``,
        ``r_squared_adj``, ``r_squared_pred`` [-], ``pure_error_df``, ``lack_of_fit_df``,
        ``lack_of_fit_F``, ``lack_of_fit_p`` [-] (F and p NaN unless the runs repeat a point
        and the model leaves degrees of freedom beyond those repeats).
    stationary
        The stationary point: ``kind`` (``"maximum"``, ``"minimum"``, ``"saddle point"``),
        ``coded`` and ``levels`` (per factor [-] and [design unit]), ``predicted`` [response
        unit], ``eigenvalues`` [response unit], ``inside`` (within the coded box the runs
        span); None when not every factor has a square term or the quadratic part is singular.
    points
        The runs used: the coded factors (one column per factor) and ``y``.
    notes
        What was left out of the model and why.
    xtx_inv
        ``(X'X)^-1`` of the model matrix in coded units [-]: times ``s^2``, the coefficients'
        covariance.
    """

    response: str
    codings: tuple[Coding, ...]
    terms: tuple[str, ...]
    coef: np.ndarray
    coefficients: pd.DataFrame
    anova: pd.DataFrame
    statistics: dict[str, float]
    stationary: dict[str, Any] | None
    points: pd.DataFrame
    notes: tuple[str, ...] = field(default_factory=tuple)
    xtx_inv: np.ndarray | None = None

    def predict(self, levels: Mapping[str, Any]) -> np.ndarray:
        """The fitted response [response unit] at factor levels [design unit].

        Parameters
        ----------
        levels
            Every factor's name to a level or an array of levels (broadcast together).

        Returns
        -------
        numpy.ndarray
            The fitted response [response unit], of the broadcast shape.

        Raises
        ------
        KeyError
            A factor of the fit has no level in ``levels``.
        """
        missing = [c.name for c in self.codings if c.name not in levels]
        if missing:
            raise KeyError(f"levels missing for factor(s) {missing}")
        coded = {c.name: c.code(levels[c.name]) for c in self.codings}
        self._warn_far(levels, coded)
        return self.predict_coded(coded)

    def _warn_far(self, levels: Mapping[str, Any], coded: Mapping[str, Any]) -> None:
        """Warn (:class:`brakeca.config.UnitWarning`) for a level farther outside the runs'
        range than half that range: the surface is extrapolated there, and such a level often
        is one in another unit (A = 0.15 for 15 %: an API review saw 0.108 come back without
        a word)."""
        import warnings

        from brakeca.config import UnitWarning

        extent = self.extent()
        for c in self.codings:
            lo, hi = extent[c.name]
            margin = 0.5 * (hi - lo)
            values = np.ravel(np.asarray(coded[c.name], dtype=float))
            far = np.isnan(values) | (values < lo - margin) | (values > hi + margin)
            if far.any():
                given = float(np.ravel(np.asarray(levels[c.name], dtype=float))[np.argmax(far)])
                span = c.decode(np.array([lo, hi]))
                unit = f" {c.unit}" if c.unit and c.unit != "-" else ""
                warnings.warn(
                    f"{c.name} = {given:g}{unit} lies far outside the runs' levels "
                    f"({span[0]:g} to {span[1]:g}{unit}): the surface is extrapolated there "
                    "(is the level in the factor's unit?)",
                    UnitWarning,
                    stacklevel=3,
                )

    def predict_coded(self, coded: Mapping[str, Any]) -> np.ndarray:
        """The fitted response [response unit] at coded factor values [-].

        Parameters
        ----------
        coded
            Every factor's name to a coded value or an array of them (broadcast together)
            [-].

        Returns
        -------
        numpy.ndarray
            The fitted response [response unit], of the broadcast shape.
        """
        arrays = np.broadcast_arrays(*(np.asarray(coded[c.name], float) for c in self.codings))
        x = dict(zip((c.name for c in self.codings), arrays, strict=True))
        out = np.full(arrays[0].shape, float(self.coef[0]))
        for b, term in zip(self.coef[1:], self.terms, strict=True):
            out = out + b * _term_values(term, x)
        return out

    def confidence_interval(
        self, coded: Mapping[str, Any], level: float = 0.95, *, new_run: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """Confidence interval of the fitted mean response [response unit] at coded factor
        values [-]: ``y_hat -/+ t s sqrt(x' (X'X)^-1 x)``; with ``new_run``, the prediction
        interval of one new run there, ``y_hat -/+ t s sqrt(1 + x' (X'X)^-1 x)`` (here: one
        more seed). NaN without residual degrees of freedom.

        Parameters
        ----------
        coded
            Every factor's name to coded values (broadcast together).
        level
            Confidence level [-].
        new_run
            The prediction interval of a single new run instead of the mean's interval.

        Returns
        -------
        low, high : numpy.ndarray
            The interval's ends [response unit], of the broadcast shape.
        """
        from scipy import stats

        arrays = np.broadcast_arrays(*(np.asarray(coded[c.name], float) for c in self.codings))
        x = dict(zip((c.name for c in self.codings), arrays, strict=True))
        rows = np.stack([np.ones(arrays[0].shape)] + [_term_values(t, x) for t in self.terms])
        centre = self.predict_coded(coded)
        df = self.statistics.get("df_resid", math.nan)
        s = self.statistics.get("s", math.nan)
        if self.xtx_inv is None or not df > 0.5 or not math.isfinite(s):
            nan = np.full(centre.shape, math.nan)
            return nan, nan.copy()
        var = np.einsum("i...,ij,j...->...", rows, self.xtx_inv, rows) + (1.0 if new_run else 0.0)
        half = float(stats.t.ppf(0.5 + level / 2.0, df)) * s * np.sqrt(var)
        return centre - half, centre + half

    def loses_sign(self, value: float) -> bool:
        """Whether a fitted ``value`` [response unit] is not positive though every run's
        response is (a quadratic in V can dip below zero, where a log scale would not).

        Parameters
        ----------
        value
            A fitted response value [response unit].

        Returns
        -------
        bool
            True if every run's response is positive (and there are runs) and ``value <= 0``.
        """
        y = self.points["y"].to_numpy(dtype=float)
        return bool(y.size and np.all(y > 0.0) and value <= 0.0)

    def extent(self) -> dict[str, tuple[float, float]]:
        """The coded range the runs span, per factor [-]."""
        return {
            c.name: (float(self.points[c.name].min()), float(self.points[c.name].max()))
            for c in self.codings
        }

    def uncoded_coefficients(self) -> pd.Series:
        """The fitted model in uncoded units, as Minitab's "regression equation in uncoded
        units": the coded model expanded in the factors' levels [design unit] (in log10 of
        the level for a log-coded factor).

        Returns
        -------
        pandas.Series
            Coefficients [response unit per unit of the term] indexed by ``"Constant"``,
            then linear terms (``"A"``, ``"log10(WP)"``), squares (``"A*A"``) and two-way
            interactions (``"log10(WP)*A"``) in the coded model's order. A coded square or
            interaction gives linear terms in uncoded units too, so a linear term the coded
            model left out (backward elimination) can appear here.

        Notes
        -----
        With a factor's coded value :math:`x = (u - m)/h`, where :math:`u` is the level (or
        its log10), :math:`m` the centre and :math:`h` the half-range of the levels coded
        -1 and +1, each coded term is expanded: :math:`b x = b(u - m)/h`,
        :math:`b x^2 = b(u^2 - 2mu + m^2)/h^2`, :math:`b x_i x_j = b(u_i - m_i)(u_j -
        m_j)/(h_i h_j)`. The uncoded model predicts what the coded one does, to round-off
        (the cancellation grows with :math:`m/h`: use :meth:`predict` for predictions).
        """
        coding = {c.name: c for c in self.codings}

        def centre_half(name: str) -> tuple[float, float]:
            lo, hi = coding[name]._ends()
            return 0.5 * (lo + hi), 0.5 * (hi - lo)

        def named(name: str) -> str:
            return f"log10({name})" if coding[name].log else name

        linear: dict[str, float] = {}
        higher: dict[str, float] = {}
        constant = float(self.coef[0])
        for b, term in zip(self.coef[1:], self.terms, strict=True):
            b = float(b)
            first, _, second = term.partition("*")
            m1, h1 = centre_half(first)
            if not second:
                linear[named(first)] = linear.get(named(first), 0.0) + b / h1
                constant -= b * m1 / h1
                continue
            m2, h2 = centre_half(second)
            c = b / (h1 * h2)
            key = f"{named(first)}*{named(second)}"
            higher[key] = higher.get(key, 0.0) + c
            linear[named(first)] = linear.get(named(first), 0.0) - c * m2
            linear[named(second)] = linear.get(named(second), 0.0) - c * m1
            constant += c * m1 * m2
        # a linear term the expansion gave exactly 0 (a factor centred at 0) is left out
        # unless the coded model has it (a diff review: "+ 0 C")
        coded_linear = {named(t) for t in self.terms if "*" not in t}
        order = [
            named(c.name)
            for c in self.codings
            if named(c.name) in linear
            and (linear[named(c.name)] != 0.0 or named(c.name) in coded_linear)
        ]
        values = [constant] + [linear[k] for k in order] + list(higher.values())
        return pd.Series(values, index=["Constant", *order, *higher], name=self.response)

    def equation(self, digits: int = 4, *, scale: float = 1.0, uncoded: bool = False) -> str:
        """The fitted model, e.g. ``"MU = 0.41 - 0.012 WP + ..."``.

        Parameters
        ----------
        digits
            Significant digits of each coefficient [-].
        scale
            Multiplier of the coefficients, from the response's unit to the one wanted
            (1e9 for V in m^3 written in mm^3) [-].
        uncoded
            In coded units (the default), or in the factors' levels [design unit]
            (:meth:`uncoded_coefficients`; a log-coded factor as ``log10(WP)``).

        Returns
        -------
        str
            ``"<response> = b0 +/- b WP ..."``, interactions and squares written with ``·``
            (``WP·A``, ``WP·WP``).
        """
        if uncoded:
            series = self.uncoded_coefficients()
            coef, terms = series.to_numpy() * scale, [str(t) for t in series.index[1:]]
        else:
            coef, terms = self.coef * scale, list(self.terms)
        parts = [f"{self.response} = {coef[0]:.{digits}g}"]
        for b, term in zip(coef[1:], terms, strict=True):
            sign = "-" if b < 0 else "+"
            parts.append(f"{sign} {abs(b):.{digits}g} {term.replace('*', '·')}")
        return " ".join(parts)


def _term_values(term: str, x: Mapping[str, np.ndarray]) -> np.ndarray:
    a, _, b = term.partition("*")
    return x[a] * x[b] if b else x[a]


def _candidate_terms(names: Sequence[str], squares: Sequence[str]) -> list[tuple[str, str]]:
    """(term, group) in Minitab's order: linear, square, two-way interaction."""
    out = [(n, "Linear") for n in names]
    out += [(f"{n}*{n}", "Square") for n in names if n in squares]
    out += [(f"{a}*{b}", "2-Way Interaction") for a, b in itertools.combinations(names, 2)]
    return out


def _f_test(ss: float, df: float, mse: float, df_resid: float) -> tuple[float, float, float]:
    """Mean square, F and p of a source against the error mean square."""
    from scipy import stats

    ms = ss / df if df > 0 else math.nan
    if df_resid > 0.5 and mse > 0 and df > 0:
        f_value = ms / mse
        return ms, f_value, float(stats.f.sf(f_value, df, df_resid))
    return ms, math.nan, math.nan


def _usable(
    summary: pd.DataFrame, codings: Sequence[Coding], response: str
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The rows :func:`brakeca.analysis._clean` keeps (status ok, finite response) whose
    coded factors are finite too, and those rows' coded factors and ``y``."""
    data = _usable_rows(summary, codings, response)
    frame = pd.DataFrame(index=range(len(data)))
    for c in codings:
        frame[c.name] = c.code(pd.to_numeric(data[c.name], errors="coerce").to_numpy(float))
    frame["y"] = data[response].to_numpy(float)
    finite = np.isfinite(frame.to_numpy(dtype=float)).all(axis=1)
    return data.iloc[np.flatnonzero(finite)], frame[finite].reset_index(drop=True)


def _clean(summary: pd.DataFrame, codings: Sequence[Coding], response: str) -> pd.DataFrame:
    """The coded factors and ``y`` of the usable rows (:func:`_usable`)."""
    return _usable(summary, codings, response)[1]


def _pure_error(points: pd.DataFrame, names: Sequence[str]) -> tuple[float, float]:
    """Pure-error sum of squares [response unit^2] and degrees of freedom [-]: the scatter
    of the runs at one point about their mean."""
    if not names:
        y = points["y"].to_numpy(float)
        return float(np.sum((y - y.mean()) ** 2)), float(y.size - 1)
    keys = np.round(points[list(names)].to_numpy(float) / _SAME_POINT).astype(np.int64)
    _, group = np.unique(keys, axis=0, return_inverse=True)
    group = group.ravel()
    y = points["y"].to_numpy(float)
    means = np.bincount(group, weights=y) / np.bincount(group)
    resid = y - means[group]
    return float(resid @ resid), float(y.size - means.size)


def _model_matrix(
    points: pd.DataFrame,
    names: Sequence[str],
    quadratic: bool,
    interactions: bool,
    exclude: frozenset[str] = frozenset(),
) -> tuple[list[str], list[tuple[str, str]], np.ndarray, list[str]]:
    """The factors that vary, the (term, group) kept, the model matrix (intercept first) and
    the notes on what was left out, for coded ``points``; terms in ``exclude`` are not
    candidates."""
    notes: list[str] = []
    varying = []
    for name in names:
        if np.ptp(points[name].to_numpy(float)) > _SAME_POINT:
            varying.append(name)
        else:
            notes.append(f"{name} does not vary in the runs used and is left out")
    squares = [
        n for n in varying if np.unique(np.round(points[n].to_numpy(float) / _SAME_POINT)).size >= 3
    ]
    if quadratic:
        for n in varying:
            if n not in squares:
                notes.append(f"{n} has two levels: no square term")
    candidates = [
        (t, g)
        for t, g in _candidate_terms(varying, squares if quadratic else [])
        if (interactions or g != "2-Way Interaction") and t not in exclude
    ]
    x = {n: points[n].to_numpy(float) for n in varying}
    columns = [np.ones(len(points))]
    kept: list[tuple[str, str]] = []
    rank = 1
    for term, group in candidates:
        trial = np.column_stack([*columns, _term_values(term, x)])
        trial_rank = int(np.linalg.matrix_rank(trial))
        if trial_rank > rank:
            columns.append(trial[:, -1])
            kept.append((term, group))
            rank = trial_rank
        else:
            notes.append(f"{term}{LEFT_OUT_NOTE}")
    return varying, kept, np.column_stack(columns), notes


def surface_terms(tests: pd.DataFrame, factors: Iterable[Any]) -> dict[str, Any]:
    """What a quadratic response surface over a design's tests can estimate, before any run.

    Parameters
    ----------
    tests
        One row per run (or per test), a column per factor [design unit].
    factors
        The numeric factors, coded by :func:`coding_of`.

    Returns
    -------
    dict
        ``terms`` (the model's terms after the intercept), ``df_resid`` (runs less
        coefficients) [-], ``pure_error_df`` (runs less distinct points) [-], ``vif`` (each
        term's variance inflation factor, 1 for a column orthogonal to the others) [-] and
        ``notes`` (what is left out and why), as :func:`fit_response_surface` would fit them.

    Raises
    ------
    ValueError
        A factor :func:`coding_of` refuses (categorical, fewer than two levels, log coding
        of a level that is not positive).
    """
    codings = [f if isinstance(f, Coding) else coding_of(f) for f in _design_factors(factors)]
    points = pd.DataFrame({c.name: c.code(tests[c.name].to_numpy(float)) for c in codings})
    names = [c.name for c in codings]
    varying, kept, exog, notes = _model_matrix(points, names, True, True)
    _, df_pe = _pure_error(points.assign(y=0.0), varying)
    return {
        "terms": [t for t, _ in kept],
        "df_resid": float(exog.shape[0] - exog.shape[1]),
        "pure_error_df": df_pe,
        "vif": _vif(exog)[1:],
        "notes": notes,
    }


def fit_response_surface(
    summary: pd.DataFrame,
    factors: Iterable[Any],
    response: str,
    *,
    quadratic: bool = True,
    interactions: bool = True,
    exclude: Iterable[str] = (),
) -> SurfaceFit:
    """Fit a full quadratic response surface in the coded factors.

    Parameters
    ----------
    summary
        Campaign summary, one row per run; only ``status == "ok"`` rows with a finite response
        are used.
    factors
        The numeric factors (design or analysis factors, or :class:`Coding` objects), coded
        by :func:`coding_of`. Factors that do not vary in the data are left out, with a note.
    response
        Response column, e.g. ``"MU"`` [-] or ``"log10_V_mm3"`` [-].
    quadratic
        Fit square terms (for the factors with three or more distinct levels in the data).
    interactions
        Fit the two-way interactions.
    exclude
        Terms to leave out (``"WR*WR"``, ``"A*WR"``; a reduced model, see
        :func:`backward_elimination`).

    Returns
    -------
    SurfaceFit
        The coefficients, ANOVA, model summary and stationary point. Terms are taken in
        order (linear, square, interaction); a term the runs cannot tell apart from the terms
        before it (its column in their span) is left out, with a note.

    Raises
    ------
    ValueError
        A categorical factor, factor names that repeat, or fewer than two usable runs.

    Notes
    -----
    With ``X`` the model matrix in coded units and ``y`` the response, ``b = (X'X)^-1 X'y``,
    ``se(b_j) = sqrt(MSE [(X'X)^-1]_jj)``. The stationary point of ``b_0 + x'b + x'Bx``
    (``B`` symmetric, ``B_ii = b_ii``, ``B_ij = b_ij / 2``) is ``x_s = -B^-1 b / 2``; the
    signs of ``B``'s eigenvalues tell a maximum (all negative) from a minimum (all positive)
    and a saddle point (Montgomery 2013, section 11.3.1).
    """
    codings = [f if isinstance(f, Coding) else coding_of(f) for f in _design_factors(factors)]
    names = [c.name for c in codings]
    if len(set(names)) != len(names):
        raise ValueError(f"factor names repeat: {names}")
    points = _clean(summary, codings, response)
    if len(points) < 2:
        raise ValueError(
            f"response {response!r}: {len(points)} usable run(s); a surface needs at least 2"
        )
    y = points["y"].to_numpy(float)
    varying, kept, exog, notes = _model_matrix(
        points, names, quadratic, interactions, frozenset(exclude)
    )
    n, p = exog.shape
    xtx_inv = np.linalg.inv(exog.T @ exog)
    coef = xtx_inv @ exog.T @ y
    fitted = exog @ coef
    resid = y - fitted
    sse = float(resid @ resid)
    df_resid = float(n - p)
    sst = float(np.sum((y - y.mean()) ** 2))
    constant = _is_constant(y)
    if constant:
        notes.append(f"{response} is constant over the runs: no test is possible")
    exact = not constant and df_resid > 0.5 and exact_fit(sse, y)
    if exact:  # (F of 4e28 and t of 2e15: a diff review)
        sse = 0.0
        notes.append(
            f"the quadratic fits {response} exactly, to round-off: no scatter is left to "
            "test the terms against (no F, t or p)"
        )
    mse = sse / df_resid if df_resid > 0.5 else math.nan

    from scipy import stats

    se = np.sqrt(mse * np.diag(xtx_inv)) if df_resid > 0.5 else np.full(p, math.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = coef / se
    p_values = (
        2.0 * stats.t.sf(np.abs(t), df_resid)
        if df_resid > 0.5 and not constant and not exact
        else t * math.nan
    )
    vif = _vif(exog)
    coefficients = pd.DataFrame(
        {
            "term": ["Constant"] + [term for term, _ in kept],
            "coef": coef,
            "se": se,
            "t": t if not (constant or exact) else np.full(p, math.nan),
            "p_value": p_values,
            "vif": vif,
        },
        columns=list(COEFFICIENT_COLUMNS),
    )

    # analysis of variance, adjusted sums of squares
    rows: list[dict[str, Any]] = []
    no_test = constant or not df_resid > 0.5

    def add(source: str, depth: int, df: float, ss: float) -> None:
        ms, f_value, p_value = _f_test(ss, df, mse, df_resid)
        if no_test:
            f_value = p_value = math.nan
        rows.append(dict(source=source, depth=depth, df=df, adj_ss=ss, adj_ms=ms, F=f_value,
                         p_value=p_value))  # fmt: skip

    def dropped_ss(indices: Sequence[int]) -> float:
        keep = [j for j in range(p) if j - 1 not in indices]
        return max(_sse(exog[:, keep], y) - sse, 0.0)

    add("Model", 0, float(p - 1), max(sst - sse, 0.0))
    for group in ("Linear", "Square", "2-Way Interaction"):
        members = [k for k, (_, g) in enumerate(kept) if g == group]
        if not members:
            continue
        add(group, 1, float(len(members)), dropped_ss(members))
        for k in members:
            add(kept[k][0], 2, 1.0, dropped_ss([k]))
    ss_pe, df_pe = _pure_error(points, varying)
    df_lof = df_resid - df_pe
    lack = {"pure_error_df": df_pe, "lack_of_fit_df": df_lof}
    lack.update(lack_of_fit_F=math.nan, lack_of_fit_p=math.nan)
    rows.append(dict(source="Error", depth=0, df=df_resid, adj_ss=sse, adj_ms=mse, F=math.nan,
                     p_value=math.nan))  # fmt: skip
    if df_pe > 0.5 and df_lof > 0.5:
        ss_lof = max(sse - ss_pe, 0.0)
        ms_lof, ms_pe = ss_lof / df_lof, ss_pe / df_pe
        # (a pure error of round-off, identical repeats, tests nothing)
        tested = not (constant or _pure_error_at_round_off(ss_pe, y))
        f_lof = ms_lof / ms_pe if tested else math.nan
        p_lof = float(stats.f.sf(f_lof, df_lof, df_pe)) if math.isfinite(f_lof) else math.nan
        lack.update(lack_of_fit_F=f_lof, lack_of_fit_p=p_lof)
        rows.append(dict(source="Lack-of-Fit", depth=1, df=df_lof, adj_ss=ss_lof, adj_ms=ms_lof,
                         F=f_lof, p_value=p_lof))  # fmt: skip
        rows.append(dict(source="Pure Error", depth=1, df=df_pe, adj_ss=ss_pe, adj_ms=ms_pe,
                         F=math.nan, p_value=math.nan))  # fmt: skip
    rows.append(dict(source="Total", depth=0, df=float(n - 1), adj_ss=sst, adj_ms=math.nan,
                     F=math.nan, p_value=math.nan))  # fmt: skip
    anova = pd.DataFrame(rows, columns=list(ANOVA_COLUMNS))

    leverage = np.einsum("ij,jk,ik->i", exog, xtx_inv, exog)
    statistics: dict[str, float] = {"n": float(n)}
    statistics.update(_fit_statistics(y, fitted, leverage, df_resid, sst))
    if exact:
        statistics["s"] = 0.0  # (the round-off's)
    if constant:  # R² of round-off means nothing
        statistics.update(r_squared=math.nan, r_squared_adj=math.nan, r_squared_pred=math.nan)
    statistics.update(lack)

    used = tuple(c for c in codings if c.name in varying)
    fit = SurfaceFit(
        response=response,
        codings=used,
        terms=tuple(term for term, _ in kept),
        coef=coef,
        coefficients=coefficients,
        anova=anova,
        statistics=statistics,
        stationary=None,
        points=points[[*varying, "y"]],
        notes=tuple(notes),
        xtx_inv=xtx_inv,
    )
    object.__setattr__(fit, "stationary", _stationary(fit))
    return fit


def _stationary(fit: SurfaceFit) -> dict[str, Any] | None:
    """The stationary point of a surface with a square term for every factor."""
    names = [c.name for c in fit.codings]
    k = len(names)
    coef = dict(zip(fit.terms, fit.coef[1:], strict=True))
    if k == 0 or any(f"{n}*{n}" not in coef for n in names):
        return None
    b = np.array([coef.get(n, 0.0) for n in names])
    quad = np.zeros((k, k))
    for i, a in enumerate(names):
        quad[i, i] = coef[f"{a}*{a}"]
        for j in range(i + 1, k):
            quad[i, j] = quad[j, i] = 0.5 * coef.get(f"{a}*{names[j]}", 0.0)
    eigenvalues = np.linalg.eigvalsh(quad)
    scale = float(np.max(np.abs(eigenvalues)))
    if scale == 0.0 or float(np.min(np.abs(eigenvalues))) <= 1e-12 * scale:
        return None
    coded = -0.5 * np.linalg.solve(quad, b)
    if np.all(eigenvalues < 0):
        kind = "maximum"
    elif np.all(eigenvalues > 0):
        kind = "minimum"
    else:
        kind = "saddle point"
    extent = fit.extent()
    inside = all(
        extent[n][0] - 1e-9 <= x <= extent[n][1] + 1e-9 for n, x in zip(names, coded, strict=True)
    )
    point = dict(zip(names, coded, strict=True))
    return {
        "kind": kind,
        "coded": {n: float(x) for n, x in point.items()},
        "levels": {c.name: float(c.decode(point[c.name])) for c in fit.codings},
        "predicted": float(fit.predict_coded(point)),
        "eigenvalues": [float(v) for v in eigenvalues],
        "inside": inside,
    }


def _removable(terms: Sequence[str]) -> list[str]:
    """The terms that can leave a hierarchical model: every square and interaction, and a
    linear term only when no square or interaction holding its factor remains."""
    higher = [t for t in terms if "*" in t]
    held = {f for t in higher for f in t.split("*")}
    return [t for t in terms if "*" in t or t not in held]


def backward_elimination(
    summary: pd.DataFrame, factors: Iterable[Any], response: str, *, alpha: float = 0.1
) -> SurfaceFit:
    """A reduced response surface: from the full quadratic, drop the term with the largest p
    value above ``alpha``, refit, and go on until every term left has p <= ``alpha``, keeping
    the model hierarchical (a factor's linear term stays while a square or interaction of it
    does), as Minitab's backward elimination ("alpha to remove", 0.1 by default). A term
    the full quadratic leaves out, since the runs cannot estimate it apart from the terms
    before it, stays out: removing its alias partner does not bring it in.

    Parameters
    ----------
    summary, factors, response
        As :func:`fit_response_surface`.
    alpha
        Alpha to remove [-], between 0 and 1.

    Returns
    -------
    SurfaceFit
        The reduced fit; its ``notes`` name the terms removed, in order. The full fit when
        it has no residual degrees of freedom (no p values to judge by).

    Raises
    ------
    ValueError
        ``alpha`` not between 0 and 1, or as :func:`fit_response_surface`.
    """
    problem = alpha_problem(alpha)
    if problem:
        raise ValueError(f"alpha: {problem}")
    factors = _design_factors(factors)
    removed: list[str] = []
    fit = fit_response_surface(summary, factors, response)
    # the terms the full model cannot estimate stay out, as in Minitab, which removes them
    # once before the elimination: dropping an alias partner would otherwise let one in
    aliased = [n for n in fit.notes if n.endswith(LEFT_OUT_NOTE)]
    never = [n[: -len(LEFT_OUT_NOTE)] for n in aliased]
    while True:
        p = dict(zip(fit.coefficients["term"], fit.coefficients["p_value"], strict=True))
        worst = _next_to_remove({t: p[t] for t in _removable(fit.terms)}, alpha)
        if worst is None:
            break
        removed.append(worst)
        fit = fit_response_surface(summary, factors, response, exclude=[*never, *removed])
    if removed:
        note = f"removed by backward elimination (alpha to remove {alpha:g}): {', '.join(removed)}"
        object.__setattr__(fit, "notes", (*fit.notes, *aliased, note))
    return fit


def surface_residuals(fit: SurfaceFit, summary: pd.DataFrame) -> pd.DataFrame:
    """Fitted values and residuals of a response surface, one row per run it was fitted to.

    Parameters
    ----------
    fit
        A fit of :func:`fit_response_surface` (or :func:`backward_elimination`).
    summary
        The campaign summary it was fitted to.

    Returns
    -------
    pandas.DataFrame
        The columns of :func:`brakeca.analysis.residuals`: the summary's ``test``,
        ``replicate`` and ``order`` (those present), ``observed``, ``fitted`` and ``residual``
        [response unit], ``leverage``, ``std_residual``, ``deleted_residual``,
        ``cooks_distance`` and ``dfits`` [-] (NaN without residual degrees of freedom, at
        leverage 1 or for a constant response); ``attrs`` carries ``response``, ``formula``,
        ``df_resid`` and ``s``.

    Raises
    ------
    ValueError
        ``summary`` is not the one ``fit`` was fitted to (other usable runs or values).
    """
    from brakeca.analysis import _residual_frame

    data, points = _usable(summary, fit.codings, fit.response)
    y = points["y"].to_numpy(float)
    if y.size != len(fit.points) or not np.array_equal(y, fit.points["y"].to_numpy(float)):
        raise ValueError(f"{fit.response}: the summary is not the one the surface was fitted to")
    x = {c.name: points[c.name].to_numpy(float) for c in fit.codings}
    exog = np.column_stack([np.ones(y.size)] + [_term_values(t, x) for t in fit.terms])
    xtx_inv = fit.xtx_inv if fit.xtx_inv is not None else np.linalg.pinv(exog.T @ exog)
    leverage = np.einsum("ij,jk,ik->i", exog, xtx_inv, exog)
    s = fit.statistics.get("s", math.nan)
    out = _residual_frame(
        data, y, exog @ fit.coef, leverage, s, fit.statistics.get("df_resid", math.nan)
    )
    terms = " + ".join(fit.terms) if fit.terms else "1"
    out.attrs.update(
        response=fit.response,
        formula=f"{fit.response} ~ {terms} (coded)",
        df_resid=fit.statistics.get("df_resid", math.nan),
        s=s,
    )
    return out


def response_surfaces(
    summary: pd.DataFrame,
    factors: Iterable[Any],
    responses: Sequence[str],
    *,
    alpha_to_remove: float | None = None,
) -> dict[str, SurfaceFit]:
    """:func:`fit_response_surface` for each response that has at least two usable runs.

    Parameters
    ----------
    summary
        Campaign summary, one row per run.
    factors
        The design's factors (numeric).
    responses
        Response columns.
    alpha_to_remove
        Reduce each surface by :func:`backward_elimination` at this level [-]; None: the
        full quadratic.

    Returns
    -------
    dict of str to SurfaceFit
        One fit per response; a response with fewer than two usable runs is left out.

    Raises
    ------
    ValueError
        As :func:`fit_response_surface` and :func:`backward_elimination`, but for too few
        usable runs (that response is left out).
    """
    factors = _design_factors(factors)
    out = {}
    for response in responses:
        try:
            if alpha_to_remove is None:
                out[response] = fit_response_surface(summary, factors, response)
            else:
                out[response] = backward_elimination(
                    summary, factors, response, alpha=alpha_to_remove
                )
        except ValueError as exc:
            if "usable run" not in str(exc):
                raise
    return out


def stationary_table(fit: SurfaceFit) -> pd.DataFrame:
    """The stationary point as a table, one row per factor: ``factor``, ``coded`` [-],
    ``level`` [design unit]; empty without one. ``attrs`` carries ``kind``, ``predicted``
    [response unit] and ``inside``.

    Parameters
    ----------
    fit
        A fitted response surface.

    Returns
    -------
    pandas.DataFrame
        Columns ``factor``, ``coded`` [-] and ``level`` [design unit], a row per factor of
        the fit; no row when it has no stationary point (and no ``attrs``).
    """
    st = fit.stationary
    if st is None:
        return pd.DataFrame(columns=["factor", "coded", "level"])
    out = pd.DataFrame(
        {
            "factor": list(st["coded"]),
            "coded": list(st["coded"].values()),
            "level": [st["levels"][n] for n in st["coded"]],
        }
    )
    out.attrs.update(kind=st["kind"], predicted=st["predicted"], inside=st["inside"])
    return out


def save_surface_tables(fits: Mapping[str, SurfaceFit], directory: str | Path) -> list[Path]:
    """Write each fit's tables as CSV files.

    Parameters
    ----------
    fits
        Output of :func:`response_surfaces`.
    directory
        Target directory; created if missing.

    Returns
    -------
    list of pathlib.Path
        ``surface_coefficients_<R>.csv``, ``surface_anova_<R>.csv`` and
        ``surface_summary_<R>.csv`` (one row: the model summary, the model's equation in
        coded units and, to 17 digits, in uncoded units, the stationary point's kind,
        predicted response and whether it lies inside the runs' box, and each factor's coded
        value and level there) for every response ``R``.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for response, fit in fits.items():
        row: dict[str, Any] = dict(fit.statistics)
        row["equation"] = fit.equation()
        row["equation_uncoded"] = fit.equation(17, uncoded=True)
        st = fit.stationary
        row["stationary_kind"] = "" if st is None else st["kind"]
        row["stationary_predicted"] = math.nan if st is None else st["predicted"]
        row["stationary_inside"] = "" if st is None else bool(st["inside"])
        for c in fit.codings:
            row[f"stationary_{c.name}_coded"] = math.nan if st is None else st["coded"][c.name]
            row[f"stationary_{c.name}"] = math.nan if st is None else st["levels"][c.name]
        tables = {
            "surface_coefficients": fit.coefficients,
            "surface_anova": fit.anova,
            "surface_summary": pd.DataFrame([row]),
        }
        for stem, table in tables.items():
            path = directory / f"{stem}_{response}.csv"
            write_table(table, path)
            written.append(path)
    return written


# --- response optimizer ----------------------------------------------------------------------

#: Grid points per factor of the optimizer's first search, by number of factors (at most
#: about 10^5 points in all) [-].
_GRID = {1: 201, 2: 101, 3: 41, 4: 17, 5: 11, 6: 7}


@dataclass(frozen=True)
class Goal:
    """What is wanted of one response, as a desirability function (Derringer and Suich 1980;
    Minitab's Response Optimizer).

    Parameters
    ----------
    response
        The response column, e.g. ``"MU"`` or ``"log10_V_mm3"``.
    kind
        ``"minimize"`` (or ``"min"``): desirability 1 at or below ``lower``, 0 at or above
        ``upper``; ``"maximize"`` (or ``"max"``): 0 at or below ``lower``, 1 at or above
        ``upper``; ``"target"``: 1 at ``target``, 0 at or beyond ``lower`` and ``upper``.
        Given as ``min`` or ``max``, it is kept as ``minimize`` or ``maximize``.
    lower, upper
        The limits [response unit: the unit of the summary column the surface was fitted
        to, so **V in m³** (``Goal("V", "minimize", 0.1e-9, 5e-9)`` for 0.1 to 5 mm³); the
        command line's ``--goal`` and a design file's ``[[goals]]`` take V in mm³ and
        convert it (:meth:`brakeca.design.GoalSpec.to_goal`)], ``lower < upper``.
    target
        The target [response unit, as the limits], strictly between the limits
        (``"target"`` only).
    weight
        Shape of the desirability between its limits [-]: 1 linear, above 1 stricter, below 1
        more lenient.
    importance
        Weight of this response in the composite desirability [-].
    """

    response: str
    kind: Literal["minimize", "maximize", "target", "min", "max"]
    lower: float
    upper: float
    target: float | None = None
    weight: float = 1.0
    importance: float = 1.0

    def __post_init__(self) -> None:
        where = f"goal of {self.response}"
        # "min" and "max", as --goal and a design file's [[goals]] take them
        kind = {"min": "minimize", "max": "maximize"}.get(self.kind, self.kind)
        object.__setattr__(self, "kind", kind)
        if self.kind not in ("minimize", "maximize", "target"):
            raise ValueError(
                f"{where}: kind must be 'minimize' ('min'), 'maximize' ('max') or 'target', "
                f"got {self.kind!r}"
            )
        if not (math.isfinite(self.lower) and math.isfinite(self.upper)):
            raise ValueError(f"{where}: the limits must be finite numbers")
        if not self.lower < self.upper:
            # named as describe() names them: a minimum's lower number is its target, a
            # maximum's upper one (a black-box review saw 'lower limit' for a minimum's target)
            first, second = {
                "minimize": ("target", "upper limit"),
                "maximize": ("lower limit", "target"),
            }.get(self.kind, ("lower limit", "upper limit"))
            raise ValueError(
                f"{where}: {self.kind}: the {first} {self.lower:g} (lower) must be below the "
                f"{second} {self.upper:g} (upper)"
            )
        if self.kind == "target":
            if self.target is None or not self.lower < self.target < self.upper:
                hint = ""
                if self.target is not None and self.lower < self.upper < self.target:
                    # Goal("MU", "target", 0.15, 0.2, 0.3) written as --goal's LOWER:TARGET:UPPER
                    hint = (
                        f" (the arguments are lower, upper, target: Goal({self.response!r}, "
                        f"'target', {self.lower:g}, {self.target:g}, target={self.upper:g}) "
                        f"for {self.upper:g} between {self.lower:g} and {self.target:g})"
                    )
                raise ValueError(
                    f"{where}: a target goal needs a target strictly between {self.lower:g} and "
                    f"{self.upper:g}, got {self.target!r}{hint}"
                )
        elif self.target is not None:
            raise ValueError(f"{where}: only a 'target' goal takes a target")
        for key in ("weight", "importance"):
            value = getattr(self, key)
            if not (math.isfinite(value) and 0.1 <= value <= 10):
                raise ValueError(f"{where}: {key} must be between 0.1 and 10, got {value!r}")

    @property
    def bounds(self) -> tuple[float, ...]:
        """The numbers the goal is given by, in order [response unit]: (lower, upper), or
        (lower, target, upper) for a target."""
        if self.target is not None:  # a target goal (only it has one)
            return (self.lower, self.target, self.upper)
        return (self.lower, self.upper)

    def describe(self, scale: float = 1.0, spec: str = ".4g") -> str:
        """The goal with its numbers named, as Minitab's optimizer names them:
        ``"minimize: target 0.5, upper 3"``, ``"maximize: lower 0.3, target 0.45"``,
        ``"target: lower 0.3, target 0.35, upper 0.45"`` (the numbers times ``scale`` [the
        unit shown per response unit], formatted with ``spec``).

        Parameters
        ----------
        scale
            Multiplier of the numbers, from the response unit to the unit shown (1e9 for V
            in m^3 shown in mm^3) [-].
        spec
            Format specification of each number (:func:`format`).

        Returns
        -------
        str
            The kind, then each of :attr:`bounds` with its name, then ``weight`` and
            ``importance`` where they are not 1.
        """
        names = {
            "minimize": ("target", "upper"),
            "maximize": ("lower", "target"),
            "target": ("lower", "target", "upper"),
        }[self.kind]
        values = ", ".join(
            f"{n} {format(v * scale, spec)}" for n, v in zip(names, self.bounds, strict=True)
        )
        extra = "".join(
            f", {key} {getattr(self, key):g}"
            for key in ("weight", "importance")
            if getattr(self, key) != 1.0
        )
        return f"{self.kind}: {values}{extra}"

    @property
    def acceptance_limits(self) -> tuple[float, ...]:
        """The limits a response must stay within to be acceptable at all (desirability
        above 0) [response unit]: a minimize goal's upper, a maximize goal's lower, or both
        of a target's."""
        if self.kind == "minimize":
            return (self.upper,)
        if self.kind == "maximize":
            return (self.lower,)
        return (self.lower, self.upper)

    def acceptable(self, y: Any) -> np.ndarray:
        """Whether response values ``y`` [response unit] are within
        :attr:`acceptance_limits` (limits included).

        Parameters
        ----------
        y
            A response value or an array of them [response unit].

        Returns
        -------
        numpy.ndarray
            Bool array of the shape of ``y``.
        """
        y = np.asarray(y, dtype=float)
        if self.kind == "minimize":
            return y <= self.upper
        if self.kind == "maximize":
            return y >= self.lower
        return (y >= self.lower) & (y <= self.upper)

    def desirability(self, y: Any) -> np.ndarray:
        """Desirability [-] (0 to 1) of response values ``y`` [response unit].

        Parameters
        ----------
        y
            A response value or an array of them [response unit].

        Returns
        -------
        numpy.ndarray
            Float array of the shape of ``y``, 0 to 1 [-]: linear between the limits (and the
            target) raised to the power ``weight``, clipped to 0 and 1 beyond them.
        """
        y = np.asarray(y, dtype=float)
        span = self.upper - self.lower
        if self.kind == "minimize":
            d = (self.upper - y) / span
        elif self.kind == "maximize":
            d = (y - self.lower) / span
        else:
            target = float(self.target)  # type: ignore[arg-type]
            d = np.where(
                y <= target,
                (y - self.lower) / (target - self.lower),
                (self.upper - y) / (self.upper - target),
            )
        return np.power(np.clip(d, 0.0, 1.0), self.weight)


@dataclass(frozen=True)
class Optimum:
    """The best factor setting the optimizer found (:func:`optimize`).

    Attributes
    ----------
    coded
        Each factor's coded value [-].
    levels
        Each factor's level [design unit].
    predicted
        Each response's fitted value there [response unit].
    interval
        Each response's 95 % confidence interval of the fitted mean there [response unit]
        (NaN without residual degrees of freedom).
    prediction
        Each response's 95 % prediction interval of one new run there (another seed)
        [response unit].
    desirability
        Each response's desirability there [-].
    composite
        The composite desirability, the importance-weighted geometric mean of the
        individual ones [-]; 0 when some response is outside its limits everywhere searched.
    on_boundary
        The factors at an end of the searched region.
    note
        Why the setting is a compromise, if it is (empty otherwise).
    units
        Each factor's unit, for labels.
    tied_share
        The share of the searched grid whose score equals the best [-]: above
        :data:`_TIED_SHARE` the goals leave a plateau of equally good settings (the note says
        so).
    """

    coded: dict[str, float]
    levels: dict[str, float]
    predicted: dict[str, float]
    interval: dict[str, tuple[float, float]]
    prediction: dict[str, tuple[float, float]]
    desirability: dict[str, float]
    composite: float
    on_boundary: tuple[str, ...]
    note: str = ""
    units: dict[str, str] = field(default_factory=dict)
    tied_share: float = 0.0

    @property
    def edge_matters(self) -> bool:
        """Whether a factor at an edge of the region may hide a better setting beyond it: at
        the edge and below full desirability (at 1 nothing beyond can be better; on a plateau
        of a goal missed everywhere, the setting nearest its limits is at the edge because
        a better one may lie beyond)."""
        return bool(self.on_boundary) and self.composite < 1.0


#: The share of the optimizer's grid tied at the best score above which the goals are said
#: not to single out one setting [-].
_TIED_SHARE = 0.01


def _composite(goals: Sequence[Goal], values: Mapping[str, np.ndarray]) -> np.ndarray:
    total = sum(g.importance for g in goals)
    log_d = 0.0
    for g in goals:
        with np.errstate(divide="ignore"):
            log_d = log_d + g.importance * np.log(g.desirability(values[g.response]))
    return np.exp(log_d / total)


def _mean_desirability(goals: Sequence[Goal], values: Mapping[str, np.ndarray]) -> np.ndarray:
    total = sum(g.importance for g in goals)
    weighted = [g.importance * g.desirability(values[g.response]) for g in goals]
    return np.asarray(np.sum(weighted, axis=0) / total, dtype=float)


def _nearest_limits(goals: Sequence[Goal], values: Mapping[str, np.ndarray]) -> np.ndarray:
    """Minus the goals' shortfalls: how far each goal's response lies beyond the limit it
    must reach to have any desirability (above ``upper`` for a minimum, below ``lower`` for
    a maximum, outside ``lower`` to ``upper`` for a target), in spans of its limits, weighted
    by importance and summed [-]; 0 where every goal has some desirability."""
    total: Any = 0.0
    for g in goals:
        y = np.asarray(values[g.response], dtype=float)
        low = -math.inf if g.kind == "minimize" else g.lower  # a minimum has no lower limit
        high = math.inf if g.kind == "maximize" else g.upper  # nor a maximum an upper one
        miss = np.maximum(low - y, 0.0) + np.maximum(y - high, 0.0)
        total = total - g.importance * miss / (g.upper - g.lower)
    return np.asarray(total, dtype=float)


def _beyond_the_runs(fit: SurfaceFit, coded: np.ndarray) -> str:
    """A note when the coded point lies farther from the design's centre than every run (a
    rotatable composite or a Box-Behnken design spans a sphere, not the box the optimizer
    searches, so its corners are extrapolation); empty otherwise."""
    runs = fit.points[[c.name for c in fit.codings]].to_numpy(dtype=float)
    if runs.size == 0:
        return ""
    farthest = float(np.max(np.linalg.norm(runs, axis=1)))
    distance = float(np.linalg.norm(coded))
    if distance <= farthest * (1.0 + 1e-6):
        return ""
    return (
        f"the setting lies {distance:.3g} coded units from the design's centre, farther than "
        f"any run ({farthest:.3g}): the fitted surfaces are extrapolated there; confirm it "
        "with runs, or restrict the goals"
    )


def optimize(fits: Mapping[str, SurfaceFit], goals: Sequence[Goal]) -> Optimum:
    """The factor setting that best meets every goal: the largest composite desirability of
    the fitted surfaces over the region the runs span (Derringer and Suich 1980, as Minitab's
    Response Optimizer).

    The region is the box of the coded factors' ranges in the runs (for a face-centred
    composite design, the cube of the factors' levels). A grid over it (:data:`_GRID` points
    per factor) is searched first; the ten best grid points are then refined by bounded
    quasi-Newton steps (L-BFGS-B), and the best point of all is returned. When some goal is
    missed everywhere (the composite desirability is 0 over the whole grid), the setting of
    the largest importance-weighted mean desirability is returned instead, with a note. A
    setting farther from the centre than every run (a corner of the box of a rotatable
    composite or a Box-Behnken design, which span a sphere) gets a note that the surfaces are
    extrapolated there.

    Parameters
    ----------
    fits
        Response to fitted surface (:func:`response_surfaces`), all over the same factors.
    goals
        One goal per response optimized (at least one; each response once, with a fit).

    Returns
    -------
    Optimum
        The setting in coded [-] and design units [design unit], each response's fitted
        value, 95 % confidence and prediction intervals [response unit] and desirability
        [-], the composite desirability [-], the factors on the boundary, and notes.

    Raises
    ------
    ValueError
        No goal, a response without a fit or named twice, or fits over different factors.

    References
    ----------
    G. Derringer and R. Suich, "Simultaneous optimization of several response variables",
    Journal of Quality Technology 12(4), 214-219, 1980.
    """
    from scipy import optimize as sciopt

    goals = list(goals)
    if not goals:
        raise ValueError("optimize: give at least one goal")
    names = [g.response for g in goals]
    for name in names:
        if names.count(name) > 1:
            raise ValueError(f"optimize: response {name!r} has two goals")
        if name not in fits:
            fitted = ", ".join(fits) or "none"
            raise ValueError(
                f"optimize: no fitted surface of {name!r} (fewer than two finished runs with a "
                f"finite {name}?); surfaces fitted: {fitted}"
            )
    chosen = {g.response: fits[g.response] for g in goals}
    first = next(iter(chosen.values()))
    factors = [c.name for c in first.codings]
    for name, fit in chosen.items():
        if [c.name for c in fit.codings] != factors:
            raise ValueError(
                f"optimize: the surfaces are over different factors ({name!r}: "
                f"{[c.name for c in fit.codings]}, not {factors})"
            )
    extent = first.extent()
    # a factor in no fitted model (removed by backward elimination) changes nothing: it is
    # held at the centre of its range, not left to wander to an edge
    active = {n for fit in chosen.values() for term in fit.terms for n in term.split("*")}
    idle = [n for n in factors if n not in active]
    for n in idle:
        mid = 0.5 * (extent[n][0] + extent[n][1])
        extent[n] = (mid, mid)
    bounds = [extent[n] for n in factors]
    k = len(factors)

    def values_at(coded: Mapping[str, Any]) -> dict[str, np.ndarray]:
        return {r: fit.predict_coded(coded) for r, fit in chosen.items()}

    axes = [np.linspace(lo, hi, _GRID.get(k, 5) if hi > lo else 1) for lo, hi in bounds]
    mesh = np.meshgrid(*axes, indexing="ij")
    grid = {n: m.ravel() for n, m in zip(factors, mesh, strict=True)}
    on_grid = values_at(grid)  # the surfaces' predictions over the grid, once
    score = _composite
    note = ""
    if not np.any(_composite(goals, on_grid) > 0):
        if np.any(_mean_desirability(goals, on_grid) > 0):
            score = _mean_desirability  # some goal is missed everywhere: a compromise
            note = (
                "no setting in the region meets every goal's limits (composite desirability 0 "
                "everywhere); this is the setting of the largest mean desirability instead"
            )
        else:  # every goal missed everywhere (a review: the first grid point came back)
            score = _nearest_limits
            note = (
                "no setting in the region gives any goal a desirability above 0; this is the "
                "setting nearest the goals' limits (each goal's distance beyond its limit, in "
                "spans of its limits): the fitted responses do not reach the limits asked for"
            )
    scores = score(goals, on_grid)
    # a score flat over part of the region (a goal met everywhere there, or one met nowhere
    # with the mean desirability) ties many grid points: among them the setting nearest the
    # limits of the goals it misses, not the first in index order (a review: the first was
    # the lowest MU of the tied region, the goal missed by most)
    top = float(np.max(scores))
    tied = scores >= top - 1e-9 * max(abs(top), 1.0)
    tied_share = float(np.mean(tied))
    # by score, then (where the score is not itself that) nearest the missed goals' limits,
    # then nearest the design's centre (a region tied throughout had given a corner beyond
    # the runs: a new user's review)
    centre = np.round(np.sqrt(sum(np.square(grid[n]) for n in factors)), 12)
    if score is not _nearest_limits and tied.sum() > 1:
        order = np.lexsort((centre, -_nearest_limits(goals, on_grid), -scores))
    else:
        order = np.lexsort((centre, -scores))
    starts = order[:10]
    best_x = np.array([grid[n][starts[0]] for n in factors])
    best_score = float(scores[starts[0]])

    def loss(x: np.ndarray) -> float:
        point = dict(zip(factors, x, strict=True))
        return -float(score(goals, values_at(point)))

    if best_score > 0 or score is _nearest_limits:  # a score of 0 has no slope to follow
        for i in starts:
            x0 = np.array([grid[n][i] for n in factors])
            res = sciopt.minimize(loss, x0, method="L-BFGS-B", bounds=bounds)
            if -res.fun > best_score + 1e-12:
                best_x, best_score = np.clip(res.x, *np.array(bounds).T), -float(res.fun)
    coded = {n: float(x) for n, x in zip(factors, best_x, strict=True)}
    predicted = {r: float(v) for r, v in values_at(coded).items()}
    interval, prediction = {}, {}
    for r, fit in chosen.items():
        lo, hi = fit.confidence_interval(coded)
        interval[r] = (float(lo), float(hi))
        lo, hi = fit.confidence_interval(coded, new_run=True)
        prediction[r] = (float(lo), float(hi))
    span = {n: hi - lo for n, (lo, hi) in extent.items()}
    notes = [note] if note else []
    for g in goals:  # limits a thousand times the response: a unit slip (an API review)
        largest = float(np.nanmax(np.abs(on_grid[g.response])))
        if largest > 0 and min(abs(g.lower), abs(g.upper)) > 1e3 * largest:
            scale, unit = (1e9, " mm³") if g.response == "V" else (1.0, "")  # V as users give it
            notes.append(
                f"the limits of {g.response}'s goal ({g.lower * scale:g} to "
                f"{g.upper * scale:g}{unit}) are over a thousand times the fitted "
                f"{g.response} anywhere in the region (at most {largest * scale:.3g}{unit})"
                + (
                    ": from Python, brakeca.rsm.Goal takes V in m³ (a design file and --goal "
                    "in mm³)"
                    if g.response == "V"
                    else ""
                )
            )
    if tied_share > _TIED_SHARE:
        notes.append(
            f"{100 * tied_share:.0f} % of the region searched reaches the same score, so the "
            "goals do not single out one setting: this is one of them"
            + (
                ", the nearest to the limits of the goals missed"
                if score is _mean_desirability
                else ", the nearest to the design's centre"
            )
        )
    if idle:
        notes.append(
            f"{', '.join(idle)} {'is' if len(idle) == 1 else 'are'} in none of the fitted "
            "models, so any level gives the same fit: held at the centre of the range"
        )
    reach = _beyond_the_runs(first, best_x)
    if reach:
        notes.append(reach)
    for r, fit in chosen.items():
        if fit.statistics.get("df_resid", 0.0) < 0.5:
            notes.append(
                f"the surface of {r} leaves no residual degrees of freedom (as many terms as "
                "distinct runs): no confidence or prediction interval"
            )
        elif float(fit.statistics.get("s", math.nan)) == 0.0:  # an exact fit (a review:
            # intervals of zero width went without a word)
            notes.append(
                f"the surface of {r} fits its runs exactly (s = 0): its intervals have no "
                "width, and say nothing of how far a new run may fall"
            )
        p_lof = float(fit.statistics.get("lack_of_fit_p", math.nan))
        if p_lof < 0.05:  # NaN (no repeated points) compares False
            notes.append(
                f"the surface of {r} lacks fit (lack-of-fit p = {p_lof:.2g}): the runs depart "
                "from the quadratic by more than the seed-to-seed scatter, so its fitted value "
                "here is approximate and its intervals are mostly that misfit"
            )
        if fit.loses_sign(predicted[r]):
            notes.append(
                f"the fitted {r} is "
                + (f"{predicted[r] * 1e9:.3g} mm³" if r == "V" else f"{predicted[r]:.3g}")
                + f" there, though every run's {r} is "
                "positive: the quadratic does not keep the response's sign (a log scale "
                "may fit it better)"
            )
        elif math.isfinite(interval[r][0]) and fit.loses_sign(interval[r][0]):
            # a review: V's interval of -4.2 to 4.3 mm³ went without a word
            notes.append(
                f"the confidence interval of {r} there reaches below 0, where no run's {r} "
                "is: the quadratic's uncertainty is as large as the response (a log scale "
                "may fit it better)"
            )
    note = "; ".join(notes)
    return Optimum(
        coded=coded,
        levels={c.name: float(c.decode(coded[c.name])) for c in first.codings},
        predicted=predicted,
        interval=interval,
        prediction=prediction,
        desirability={g.response: float(g.desirability(predicted[g.response])) for g in goals},
        composite=float(_composite(goals, {r: np.asarray(v) for r, v in predicted.items()})),
        on_boundary=tuple(
            n
            for n in factors
            if n not in idle
            and min(abs(coded[n] - extent[n][0]), abs(coded[n] - extent[n][1])) <= 1e-6 * span[n]
        ),
        note=note,
        units={c.name: c.unit for c in first.codings},
        tied_share=tied_share,
    )


def optimum_table(optimum: Optimum, goals: Sequence[Goal]) -> pd.DataFrame:
    """An :class:`Optimum` as one long table: a row per factor (``kind`` "factor": ``name``,
    ``value`` its level [design unit], ``coded`` [-]) and a row per response (``kind``
    "response": ``value`` the fitted value, ``low`` and ``high`` the 95 % confidence interval
    of the mean and ``pi_low`` and ``pi_high`` the 95 % prediction interval of one new run
    [response unit], the goal's ``goal``, ``lower``, ``target`` and ``upper``
    [response unit] as Minitab's table gives them (a minimize goal's target, where its
    desirability reaches 1, and upper limit; a maximize goal's lower limit and target; a
    target goal's three) and ``desirability`` [-]), then one row "composite" with the
    composite desirability [-] and the note.

    Parameters
    ----------
    optimum
        A result of :func:`optimize`.
    goals
        The goals it was found for (a row per goal, in their order).

    Returns
    -------
    pandas.DataFrame
        Columns ``kind``, ``name``, ``value``, ``coded``, ``low``, ``high``, ``pi_low``,
        ``pi_high``, ``goal``, ``lower``, ``target``, ``upper``, ``desirability`` and
        ``note``; NaN (or None) where a column does not apply to a row.
    """
    rows: list[dict[str, Any]] = [
        {"kind": "factor", "name": n, "value": v, "coded": optimum.coded[n]}
        for n, v in optimum.levels.items()
    ]

    def minimizing(goal: Goal) -> bool:
        return goal.kind in ("minimize", "min")

    def maximizing(goal: Goal) -> bool:
        return goal.kind in ("maximize", "max")

    for g in goals:
        low, high = optimum.interval[g.response]
        pi_low, pi_high = optimum.prediction[g.response]
        rows.append(
            {
                "kind": "response",
                "name": g.response,
                "value": optimum.predicted[g.response],
                "low": low,
                "high": high,
                "pi_low": pi_low,
                "pi_high": pi_high,
                "goal": g.kind,
                # as Minitab's table has them (and the command line prints them): a
                # minimize goal's target and upper limit, a maximize goal's lower limit and
                # target; the limit where its desirability reaches 1 is its target
                "lower": math.nan if minimizing(g) else g.lower,
                "target": g.lower if minimizing(g) else g.upper if maximizing(g) else g.target,
                "upper": math.nan if maximizing(g) else g.upper,
                "desirability": optimum.desirability[g.response],
            }
        )
    rows.append(
        {"kind": "composite", "name": "D", "value": optimum.composite, "note": optimum.note}
    )
    columns = ["kind", "name", "value", "coded", "low", "high", "pi_low", "pi_high", "goal"]
    columns += ["lower", "target"]
    return pd.DataFrame(rows, columns=[*columns, "upper", "desirability", "note"])
