"""Figures of a factorial campaign: main effects, interactions, per-stop COF, wear, maps.

Every function builds its own :class:`matplotlib.figure.Figure` on an Agg canvas (no pyplot,
no global backend switch, no figure registry to leak), returns it and, when ``path`` is
given, saves it as PNG at 150 dpi. The single-axes figures (:func:`plot_mu_per_stop`,
:func:`plot_v_per_run`, :func:`plot_pareto`, :func:`plot_surface_map`) draw instead on an
axes given as ``ax=``, in a figure of one's own (a notebook's subplot grid). matplotlib is
imported only inside the functions, so importing :mod:`brakeca.plotting` is cheap and works
without a display.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260 (Figures 5 to 11).
"""

from __future__ import annotations

import itertools
import math
import os
import textwrap
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from brakeca._io import atomic_write
from brakeca.analysis import (
    CENTER_TERM,
    UNUSUAL_RESIDUAL,
    Factor,
    ResponseAnalysis,
    _campaign_parts,
    _cube_level_order,
    _factors,
    interaction_table,
    main_effects,
    ok_runs,
)
from brakeca.geometry import status_area_fractions

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

    from brakeca._consolidate import CampaignResult
    from brakeca.traces import BrakingEvent, SpeedTrace

__all__ = [
    "DPI",
    "STATUS_COLOURS",
    "STATUS_NAMES",
    "fits_to_scale",
    "plot_box_cox",
    "plot_by_block",
    "plot_cof_series",
    "plot_cube",
    "plot_effects",
    "plot_fibre_maps",
    "plot_interactions",
    "plot_level_comparisons",
    "plot_main_effects",
    "plot_mu_per_stop",
    "plot_mu_per_stop_by_level",
    "plot_mu_per_stop_by_test",
    "plot_mu_vs_v",
    "plot_overlaid_contours",
    "plot_pareto",
    "plot_profiler",
    "plot_residuals",
    "plot_residuals_by_level",
    "plot_response_surface",
    "plot_surface_map",
    "plot_trace",
    "plot_v_per_run",
    "save_figure",
]

#: Resolution of saved PNG files [dots per inch].
DPI = 150

#: Colours of the surface status codes 0 (resin), 1 (primary plateau), 2 (secondary plateau).
STATUS_COLOURS: tuple[str, str, str] = ("#d9d9d9", "#27496d", "#f28e2b")

#: Legend names of the surface status codes.
STATUS_NAMES: tuple[str, str, str] = (
    "resin (no plateau)",
    "primary plateau (metal fibre)",
    "secondary plateau",
)

#: Axis label and factor from data unit to plotted unit, per known response.
_RESPONSES: dict[str, tuple[str, float]] = {
    "MU": ("Mean coefficient of friction μ [-]", 1.0),
    "V": ("Emitted wear volume per stop V [mm³]", 1e9),
    "V_mm3": ("Emitted wear volume per stop V [mm³]", 1.0),
    "log10_V_mm3": ("log10 of V in mm³ per stop [-]", 1.0),
    "MU_SD": ("SD of the per-stop mean COF [-]", 1.0),
}


def _response_axis(response: str) -> tuple[str, float]:
    return _RESPONSES.get(response, (response, 1.0))


def _shown(response: str) -> str:
    """A response as titles name it: ``log10 V`` for the column ``log10_V_mm3`` (a figures
    review read the column's name as a label), others as they are."""
    return {"log10_V_mm3": "log10 V"}.get(response, response)


def _axis_unit(attrs: Any) -> str:
    """A unit as the axes write it: a dimensionless one ``-``, where a file has UDUNITS'
    ``1``."""
    unit = str(attrs.get("units", ""))
    return "-" if unit == "1" else unit


#: Axis label, title words and scale of the per-stop area fractions [-] of a run file,
#: drawn in per cent of the band (their ``long_name``, e.g. "time-weighted area in contact /
#: band area", is a formula, too long for an axis).
_AREA_AXES: dict[str, tuple[str, str]] = {
    "primary_area_fraction": ("Primary plateau area", "primary plateau area"),
    "secondary_area_fraction": ("Secondary plateau area", "secondary plateau area"),
    "contact_area_fraction": ("Area in contact", "area in contact"),
}


def _variable_axis(data: Any, variable: str) -> tuple[str, str, float]:
    """(axis label, what it is for a title, scale) of a per-stop variable of a run file or
    campaign dataset: the mean COF as the paper names it, an area fraction [-] in per cent
    of the band (time-weighted over the stop), another variable by its ``long_name`` and
    ``units``, a volume [m^3] in mm^3 as the other figures draw V (the plots had named every
    variable the mean COF: an API review)."""
    if variable == "mean_cof":
        return "Mean coefficient of friction μ per stop [-]", "mean coefficient of friction", 1.0
    if variable in _AREA_AXES:
        label, what = _AREA_AXES[variable]
        return f"{label} per stop [% of band]", f"{what} (time-weighted, % of the band)", 100.0
    attrs = getattr(data[variable], "attrs", {})
    name = str(attrs.get("long_name") or variable)
    units = _axis_unit(attrs).strip() or "-"
    scale = 1.0
    if units in ("m3", "m^3", "m³"):
        units, scale = "mm³", 1e9
    label = _SHORT_AXES.get(variable, f"{name[:1].upper()}{name[1:]}")
    return f"{label} [{units}]", name, scale


#: Axis labels of per-stop variables whose long name (the title's) is longer than an axis
#: (a figures review: the emitted volume's ran the whole height of the figure).
_SHORT_AXES = {"emitted_volume": "Emitted volume per stop"}


def _figure(figsize: tuple[float, float]) -> Figure:
    """A new figure on an Agg canvas, with constrained (tight) layout."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _axes(ax: Axes | None, figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    """A new figure of ``figsize`` [in] with one axes, or the figure of ``ax`` and ``ax``
    itself, to draw into a figure of one's own (a subplot of a grid)."""
    if ax is None:
        fig = _figure(figsize)
        return fig, fig.subplots()
    if not hasattr(ax, "figure") or not hasattr(ax, "plot"):
        raise TypeError(f"ax: expected a matplotlib Axes, got {type(ax).__name__}")
    return _root_figure(ax.figure), ax


def _panel_inches(ax: Axes) -> tuple[float, float]:
    """The width and height [in] of a panel ``ax`` as its figure places it (before a layout
    engine's adjustments)."""
    box = ax.get_window_extent()  # (a SubFigure's axes are placed within it: a diff review)
    dpi = _root_figure(ax.figure).dpi
    return box.width / dpi, box.height / dpi


def _panel_chars(ax: Axes, fontsize: float, most: int) -> int:
    """How many characters of ``fontsize`` [pt] a line across the panel ``ax`` holds, at
    most ``most`` (about half an em a character; at least 20)."""
    return max(20, min(most, int(_panel_inches(ax)[0] * 72.0 / (0.55 * fontsize))))


def _root_figure(fig: Any) -> Figure:
    """The figure that holds ``fig`` (itself, or a SubFigure's parents up to the Figure):
    the one a figure function returns and saves."""
    while fig.figure is not fig:
        fig = fig.figure
    return fig


def _panels(
    fig: Figure | SubFigure | None, figsize: tuple[float, float]
) -> tuple[Figure, Figure | SubFigure]:
    """A new figure of ``figsize`` [in] for a figure of several panels, or ``fig``, a Figure
    or SubFigure of one's own to draw them into; with the figure that holds it all, which
    is the one returned and saved."""
    if fig is None:
        new = _figure(figsize)
        return new, new
    if not hasattr(fig, "subplots") or not hasattr(fig, "subfigures"):
        raise TypeError(
            f"fig: expected a matplotlib Figure or SubFigure, got {type(fig).__name__} "
            "(for an Axes, the figures of one panel take ax=)"
        )
    return _root_figure(fig), fig


def _name_points(ax: Axes, xs: Any, ys: Any, names: Sequence[str], **text: Any) -> None:
    """Name points beside them, as :meth:`~matplotlib.axes.Axes.annotate` would, without two
    names printed on one another ("test 105" over "test 75": a figures review): each to the
    right of its point (to its left in the axes' right fifth, where it had crossed the axes'
    edge), moved up to three lines up or down, inside the axes, where it would overlap a name
    placed before; where no such place is free, joined to the name it overlaps if that one
    names a point at nearly the same place (``"test 1, test 8"``; a name joined to another
    point's had put a test at the wrong level: a review), else printed at its point.
    ``text``: the names' :class:`~matplotlib.text.Text` properties (``fontsize`` [pt],
    ``color``). Call it once the axes' limits are set."""
    import matplotlib as mpl

    size = float(text.get("fontsize", mpl.rcParams["font.size"]))
    tall = 1.25 * size  # a line [pt]
    ax.get_xlim(), ax.get_ylim()  # the view's limits as they will be drawn
    points = ax.transData.transform(np.column_stack([xs, ys]))
    per_point = 72.0 / ax.figure.dpi
    fraction = ax.transAxes.inverted().transform(points)[:, 0]
    frame = ax.get_window_extent()
    bottom, top = frame.y0 * per_point, frame.y1 * per_point
    # boxes [pt] (left, bottom, right, top) of the names placed, with their annotations and
    # the points [pt] they name
    placed: list[tuple[tuple[float, float, float, float], Any, tuple[float, float]]] = []

    def overlapping(
        box: tuple[float, float, float, float], near: tuple[float, float] | None = None
    ) -> int | None:
        """The first placed name ``box`` overlaps (of a point within a line of ``near``
        [pt], where given)."""
        for i, (b, _, (ax_, ay_)) in enumerate(placed):
            if box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]:
                if near is None or max(abs(ax_ - near[0]), abs(ay_ - near[1])) < tall:
                    return i
        return None

    for k in np.argsort(-np.asarray(ys, dtype=float), kind="stable"):
        x, y = points[k] * per_point
        wide = 0.6 * size * len(names[k])
        left_side = fraction[k] > 0.8
        dx = -4.0 if left_side else 4.0
        x0 = x + dx - wide if left_side else x + dx
        free = None
        for dy in (0.0, tall, -tall, 2 * tall, -2 * tall, 3 * tall, -3 * tall):
            box = (x0, y + dy - tall / 2, x0 + wide, y + dy + tall / 2)
            if bottom <= box[1] and box[3] <= top and overlapping(box) is None:
                free = dy, box
                break
        if free is None:  # no room: joined to the name it would print over, of a point
            # at nearly the same place
            i = overlapping((x0, y - tall / 2, x0 + wide, y + tall / 2), near=(x, y))
            if i is not None:
                (left, low, right, high), other, anchor = placed[i]
                other.set_text(f"{other.get_text()}, {names[k]}")
                more = 0.6 * size * (len(names[k]) + 2)  # its box grows by the name
                grown = (
                    (left - more, low, right, high)
                    if other.get_ha() == "right"
                    else (left, low, right + more, high)
                )
                placed[i] = grown, other, anchor
                continue
            free = 0.0, (x0, y - tall / 2, x0 + wide, y + tall / 2)
        dy, box = free
        annotation = ax.annotate(
            names[k],
            (xs[k], ys[k]),
            xytext=(dx, dy),
            textcoords="offset points",
            ha="right" if left_side else "left",
            va="center",
            # a name moved off its point's line keeps a thin line to it
            arrowprops=(
                None
                if dy == 0.0
                else {"arrowstyle": "-", "lw": 0.5, "color": text.get("color", "0.3")}
            ),
            **text,
        )
        placed.append((box, annotation, (x, y)))


def _suptitle(fig: Figure | SubFigure, text: str) -> None:
    """``fig.suptitle(text)``, broken after its first ": " when one line is wider than the
    figure (a one-panel interaction plot), and smaller if it is still too wide."""
    title = fig.suptitle(text)
    width = fig.bbox.width

    def too_wide() -> bool:  # the extent from the figure's own renderer, any canvas
        return bool(title.get_window_extent().width > 0.98 * width)

    if too_wide() and ": " in text:
        title.set_text(text.replace(": ", ":\n", 1))
    size = float(title.get_fontsize())
    while too_wide() and size > 7:
        size -= 1
        title.set_fontsize(size)


#: The file formats a figure is written in, by the file's suffix (none: PNG).
FIGURE_FORMATS: tuple[str, ...] = ("png", "pdf", "svg", "jpg", "jpeg", "tif", "tiff", "eps", "webp")


def figure_format(path: str | Path) -> str:
    """The format a figure written to ``path`` takes: its suffix's (``.svg`` -> ``"svg"``),
    PNG without one; raises ValueError naming the formats for another suffix (a ``.xyz``
    had been written as PNG)."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if not suffix:
        return "png"
    if suffix not in FIGURE_FORMATS:
        shown = ", ".join("." + f for f in FIGURE_FORMATS)
        raise ValueError(f"{path}: a figure is written as {shown} (by its suffix), not .{suffix}")
    return suffix


def save_figure(fig: Figure, path: str | Path | None) -> Figure:
    """Save ``fig`` when ``path`` is given (parents are created), in the format of its suffix
    (:func:`figure_format`: PNG, PDF, SVG...; raster formats at :data:`DPI`).

    Parameters
    ----------
    fig
        The figure.
    path
        Target file, or None to skip saving.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``, for chaining.
    """
    if path is not None:
        if not isinstance(path, str | os.PathLike):  # plot_mu_per_stop(campaign, design)
            raise TypeError(
                f"path: a file to write (str or Path), not {type(path).__name__}; a figure's "
                "factors, where it takes them, are given as factors="
            )
        path = Path(path)
        kind = figure_format(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=DPI, format=kind))
    return fig


def _tick_label(factor: Factor, level: float) -> str:
    """``"-\n0.1"``: a level's label over its value in the axis's unit (:meth:`Factor.shown`)."""
    if factor.labels is not None:
        return f"{factor.level_label(level)}\n{factor.shown(level)}"
    return factor.shown(level)


def _level_colours(n: int) -> list[Any]:
    """Colours of a factor's ``n`` levels, the same in every figure: low blue and high red
    (grey between for three; a green middle level had been told from the red one by its hue
    alone, which a red-green colour-blind reader cannot: a figures review), viridis for
    more. The figures give the levels their own line style or marker too
    (:data:`LEVEL_STYLES`, :data:`LEVEL_MARKERS`)."""
    import matplotlib as mpl

    if n == 2:
        return ["#2166ac", "#b2182b"]
    if n == 3:
        return ["#2166ac", "#7f7f7f", "#b2182b"]
    return list(mpl.colormaps["viridis"](np.linspace(0.0, 0.9, n)))


#: Line styles of a factor's levels, in level order (repeating beyond four) [-].
LEVEL_STYLES = ("-", "--", "-.", ":")
#: Markers of a factor's levels, in level order (repeating beyond six) [-].
LEVEL_MARKERS = ("o", "s", "^", "D", "v", "P")


def _with_unit(value: str, unit: str, space: str = " ") -> str:
    """``"0.1 µm"``: a value's text with its unit for people (:func:`display_unit`), none
    for a dimensionless one (``""`` or ``"-"``); ``space`` between them."""
    from brakeca.analysis import display_unit

    return value + (f"{space}{display_unit(unit)}" if unit and unit != "-" else "")


def _legend_label(factor: Factor, level: float) -> str:
    """``"WP+ (1e-13 m³/(N·m))"``, ``"A = 20 %"``, ``"WR- (0.1 µm)"``: a level in a legend,
    with its unit (a figures review: "A = 20" left the reader to guess it), in the unit the
    figures show it in (:meth:`Factor.shown`)."""
    shown = _with_unit(factor.shown(level), factor.shown_unit[0])
    if factor.labels is not None:
        return f"{factor.name}{factor.level_label(level)} ({shown})"
    return f"{factor.name} = {shown}"


def _finite_response(summary: pd.DataFrame, response: str) -> np.ndarray:
    if response not in summary.columns:
        raise KeyError(f"response {response!r} is not a column of the summary")
    y = pd.to_numeric(ok_runs(summary)[response], errors="coerce").to_numpy(dtype=float)
    return y[np.isfinite(y)]


# --- main effects and interactions (Figures 6 to 9) ------------------------------------------


def _mark_centre(ax: Any, value: float) -> None:
    """The centre points' mean ``value`` [plotted unit] as a black diamond midway between a
    two-level factor's levels (at x = 0.5), labelled for the legend."""
    ax.plot([0.5], [value], "D", color="#222222", ms=6, label="centre points")


def plot_main_effects(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Main-effects plot: level means of a response, one panel per factor.

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors (:class:`brakeca.analysis.Factor` or factor-like), or the
        design (or a campaign result) for its factors.
    response
        Response column: ``"MU"`` [-] or ``"V"`` [m^3], the latter plotted in mm^3.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per factor, sharing the y axis; the grand mean is a dashed line, and the
        centre points' mean (a design with centre points) a black diamond midway between the levels.

    References
    ----------
    Wahlström (2016), Figures 6 (MU) and 8 (V), doi:10.1155/2016/8181260.
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)  # factor-likes, or a design or campaign result for its own
    if not factors:
        raise ValueError("no factors to plot")
    table = main_effects(summary, factors, response)
    ylabel, scale = _response_axis(response)
    y = _finite_response(summary, response)
    grand = float(y.mean()) * scale if y.size else math.nan
    centre = table.attrs.get("center_mean", math.nan)
    centre = float(centre) if table.attrs.get("center_n") else None

    # at most MAIN_EFFECTS_PER_ROW panels a row, as Minitab wraps them (a review of large
    # designs: eleven factors in one row, 4440 px wide, read at 3 px a letter)
    cols = min(len(factors), MAIN_EFFECTS_PER_ROW)
    n_rows = math.ceil(len(factors) / cols)
    root, fig = _panels(fig, (2.6 * cols + 1.0, 3.6 * n_rows))
    grid = fig.subplots(n_rows, cols, sharey=True, squeeze=False)
    axes = grid.ravel()
    for ax in axes[len(factors) :]:
        ax.set_visible(False)
    for ax, factor in zip(axes, factors, strict=False):
        rows = table.loc[table["factor"] == factor.name]
        x = np.arange(len(rows))
        ax.plot(x, rows["mean"].to_numpy() * scale, "o-", color="#27496d", lw=1.8, ms=6)
        if math.isfinite(grand):
            what = "grand mean" + (" (all runs, centre points too)" if centre is not None else "")
            ax.axhline(grand, ls="--", lw=1.0, color="0.45", label=what)
        if centre is not None and len(rows) == 2:
            _mark_centre(ax, centre * scale)
        ax.set_xticks(x, [_tick_label(factor, lv) for lv in rows["level"]])
        ax.set_xlim(-0.4, len(rows) - 0.6)
        ax.set_xlabel(factor.axis_label)
        ax.set_title(factor.label or factor.name, fontsize=9)
        ax.grid(True, axis="y", alpha=0.3)
    for ax in grid[:, 0]:
        ax.set_ylabel(ylabel)
    if axes[0].get_legend_handles_labels()[0]:  # (no usable run: nothing to name)
        axes[0].legend(loc="best", fontsize=8)
    _suptitle(fig, f"Main effects plot for {_shown(response)}")
    return save_figure(root, path)


#: The most panels of :func:`plot_main_effects` side by side; more factors wrap [-].
MAIN_EFFECTS_PER_ROW = 6


def plot_interactions(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    path: str | Path | None = None,
    *,
    aliases: Mapping[tuple[str, str], str] | None = None,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Interaction-plot matrix: cell means of a response for every pair of factors.

    The panel in row ``i`` and column ``j`` (``i < j``) shows the mean response against the
    levels of factor ``j``, one line per level of factor ``i``; panels below the diagonal are
    not drawn, so the figure has one axes per pair. In a fraction a panel shows its pair's
    interaction together with the interactions aliased with it (``aliases``): each such
    panel is titled with them, e.g. ``"= WR:modulus + mu0:slope"``. In a design with centre
    points their mean is a black diamond midway in each panel of two-level factors, as in the
    main-effects plot.

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows are used).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary, and its
        design where ``factors`` is None.
    factors
        The design's factors, at least two, or the design (or a campaign result) for its
        factors.
    response
        Response column: ``"MU"`` [-] or ``"V"`` [m^3], the latter plotted in mm^3.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    aliases
        ``(a, b)`` to the two-factor interactions aliased with ``a:b``
        (:func:`brakeca.analysis.interaction_aliases`); none for a full factorial.
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Wahlström (2016), Figures 7 (MU) and 9 (V), doi:10.1155/2016/8181260.
    """
    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)  # factor-likes, or a design or campaign result for its own
    aliases = aliases or {}
    nf = len(factors)
    if nf < 2:
        raise ValueError("an interaction plot needs at least two factors")
    ylabel, scale = _response_axis(response)
    means = main_effects(summary, factors, response).attrs
    centre = float(means["center_mean"]) if means.get("center_n") else None
    size = nf - 1
    root, fig = _panels(fig, (3.0 * size + 1.2, 2.6 * size + 0.6))
    grid = fig.subplots(size, size, sharey=True, squeeze=False)
    markers = LEVEL_MARKERS
    for i, j in itertools.product(range(size), range(1, nf)):
        ax = grid[i, j - 1]
        if j < i:
            fig.delaxes(ax)
            continue
        if j == i:  # the empty cell left of the row: its legend, as Minitab sets it
            ax.axis("off")
            continue
        a, b = factors[i], factors[j]
        table = interaction_table(summary, a, b, response)
        x = np.arange(len(b.levels))
        colours = _level_colours(len(a.levels))  # as in the by-level figures (a review)
        for k, level in enumerate(a.levels):
            ax.plot(
                x,
                table.loc[level].to_numpy(dtype=float) * scale,
                marker=markers[k % len(markers)],
                color=colours[k % len(colours)],
                lw=1.5,
                ms=5,
                label=_legend_label(a, level),
            )
        if centre is not None and len(b.levels) == 2:  # as in the main-effects plot
            _mark_centre(ax, centre * scale)
        ax.set_xticks(x, [_tick_label(b, lv) for lv in b.levels], fontsize=8)
        ax.set_xlim(-0.3, len(b.levels) - 0.7)
        ax.set_xlabel(b.axis_label, fontsize=8)
        if (a.name, b.name) in aliases:
            ax.set_title(f"= {aliases[(a.name, b.name)]}", fontsize=7, color="#7f7f7f")
        ax.grid(True, axis="y", alpha=0.3)
        ax.tick_params(axis="y", labelleft=True, labelsize=8)
        if j == i + 1:
            unit = ylabel[ylabel.rfind("[") :] if ylabel.endswith("]") else ""
            ax.set_ylabel(f"{_shown(response)} (mean) {unit}".strip(), fontsize=8)
            # the row's lines are a's levels in every panel of the row: its legend beside
            # the row where there is room (a review: a legend in the first panel alone, over
            # its lines, left the colours of the others' unnamed)
            holder = grid[i, i - 1] if i else ax
            holder.legend(
                *ax.get_legend_handles_labels(),
                title=f"lines: {a.name}",
                fontsize=7 if not i else 8,
                title_fontsize=8 if not i else 9,
                loc="best" if not i else "center right",
            )
    _suptitle(fig, f"Interaction plot for {_shown(response)}: {ylabel}")
    return save_figure(root, path)


def _cube_rank(factor: Any, k: int) -> int:
    """Where a two-level factor's level ``k`` goes along its cube edge: 0 (the near end) for
    the lower value (:func:`brakeca.analysis._cube_level_order`)."""
    return _cube_level_order(factor).index(k)


def plot_cube(
    summary: pd.DataFrame | CampaignResult,
    factors: Iterable[Any] | None,
    response: str,
    path: str | Path | None = None,
    *,
    names: Sequence[str] | None = None,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Cube plot of data means, as Minitab draws it for a two-level design: the mean
    response at each corner of two factors (a square) or three (a cube), over the other
    factors' levels (:func:`brakeca.analysis.cube_means`).

    Parameters
    ----------
    summary
        Campaign summary, one row per run (only ``status == "ok"`` rows are used). Or a
        campaign result: its summary, and its design where ``factors`` is None.
    factors
        The design's factors, or the design (or a campaign result) for its factors.
    response
        Response column, e.g. ``"MU"`` [-] or ``"V"`` [m^3] (written in mm^3).
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    names
        The cube's two or three two-level factors, along its horizontal, vertical and depth
        edges; by default the three with the largest main effects on ``response``.
    fig
        A Figure or SubFigure to draw into; a new figure by default.

    Returns
    -------
    matplotlib.figure.Figure
        One axes: each corner labelled with its mean (and its number of runs where the
        corners hold different numbers; "no run" where none, as at half the corners of a
        fraction's cube of three factors that its generator ties together).
    """
    from brakeca.analysis import cube_means

    summary, factors = _campaign_parts(summary, factors)  # a campaign result
    factors = _factors(factors)
    table = cube_means(summary, factors, response, names)
    chosen = list(table.attrs["factors"])
    by_name = {f.name: f for f in factors}
    cube = [by_name[n] for n in chosen]
    _, scale = _response_axis(response)
    depth = np.array([0.55, 0.4])  # the depth edge's offset on the page
    root, fig = _panels(fig, (6.4, 5.2) if len(cube) == 3 else (5.2, 4.4))
    ax = fig.subplots()
    corners = []
    for _, row in table.iterrows():  # each corner where its levels' ranks put it
        index = tuple(_cube_rank(f, int(f.level_index(row[f.name]) or 0)) for f in cube)
        xy = np.array([float(index[0]), float(index[1])])
        if len(cube) == 3:
            xy = xy + index[2] * depth
        corners.append((index, xy, float(row["mean"]), int(row["n"])))
    at = {code: xy for code, xy, _, _ in corners}
    for code, xy, _, _ in corners:  # each edge once, from the corner with the lower code
        for k in range(len(cube)):
            if code[k] == 0:
                other = list(code)
                other[k] = 1
                end = at[tuple(other)]
                # the back corner low and left, which the front faces hide, and its
                # three edges drawn dashed
                hidden = len(cube) == 3 and (0, 0, 1) in (code, tuple(other))
                ax.plot(
                    [xy[0], end[0]],
                    [xy[1], end[1]],
                    color="0.55" if hidden else "0.2",
                    lw=1.0 if hidden else 1.4,
                    ls="--" if hidden else "-",
                    zorder=1,
                )
    uneven = len({n for *_, n in corners if n}) > 1
    finite = [m for _, _, m, _ in corners if math.isfinite(m)]
    for _code, xy, mean, n in corners:
        text = f"{mean * scale:.4g}" if n else "no run"  # a mean of finite values
        if n and uneven:
            text += f"\n(n = {n})"
        ax.plot(*xy, "o", color="#27496d" if n else "0.7", ms=7, zorder=2)
        extreme = n and len(finite) > 1 and mean in (max(finite), min(finite))
        ax.annotate(
            text,
            (float(xy[0]), float(xy[1])),
            xytext=(0, 9),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=10,
            fontweight="bold" if extreme else "normal",
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.85},
            zorder=3,
        )
    # the factors along their edges, each level at its end: (factor, where its name goes,
    # the name's offset [points], alignment and rotation, where level k's end is, the level
    # labels' offset and alignment)
    right = np.array([1.0, 0.0])
    edges: list[tuple[Any, ...]] = [
        (cube[0], (0.5, 0.0), (0, -30), "center", "top", 0,
         lambda k: (float(k), 0.0), (0, -8), "center", "top"),
        (cube[1], (0.0, 0.5), (-36, 0), "right", "center", 90,
         lambda k: (0.0, float(k)), (-8, 0), "right", "center"),
    ]  # fmt: skip
    if len(cube) == 3:  # the depth edge, low right
        edges.append(
            (cube[2], tuple(right + 0.5 * depth), (14, -6), "left", "top", 0,
             lambda k: tuple(right + k * depth), (10, 0), "left", "center")
        )  # fmt: skip
    for factor, at, offset, ha, va, rotation, end, end_offset, end_ha, end_va in edges:
        ax.annotate(factor.axis_label, at, xytext=offset, textcoords="offset points", ha=ha,
                    va=va, fontsize=9, rotation=rotation)  # fmt: skip
        for k, level in enumerate(factor.levels):
            ax.annotate(_cube_level(factor, level), end(_cube_rank(factor, k)), xytext=end_offset,
                        textcoords="offset points", ha=end_ha, va=end_va, fontsize=8)  # fmt: skip
    ax.set_xlim(-0.45, 1.45 + (depth[0] if len(cube) == 3 else 0.0))
    ax.set_ylim(-0.3, 1.3 + (depth[1] if len(cube) == 3 else 0.0))
    ax.set_aspect("equal")
    ax.axis("off")
    label, _ = _response_axis(response)
    unit = label[label.rfind("[") :] if label.endswith("]") else ""
    _suptitle(fig, f"Cube plot (data means) for {_shown(response)} {unit}".rstrip())
    return save_figure(root, path)


def _cube_level(factor: Factor, level: float) -> str:
    """A level at its edge's end: ``"- (10)"``, or the value alone, in the unit of the
    edge's name (:meth:`Factor.shown`)."""
    if factor.labels is not None:
        return f"{factor.level_label(level)} ({factor.shown(level)})"
    return factor.shown(level)


# --- per-stop and per-run responses (Figures 10 and 11) --------------------------------------


def _block_spans(blocks: Sequence[Any], stops: np.ndarray) -> list[tuple[str, float, float]]:
    """Contiguous (name, first stop - 0.5, last stop + 0.5) stretches of equal block names."""
    spans: list[tuple[str, float, float]] = []
    start = 0
    for k in range(1, len(blocks) + 1):
        if k == len(blocks) or blocks[k] != blocks[start]:
            spans.append((str(blocks[start]), stops[start] - 0.5, stops[k - 1] + 0.5))
            start = k
    return spans


def _shade_blocks(ax: Any, spans: Sequence[tuple[str, float, float]]) -> None:
    """Shade every second block of :func:`_block_spans` light grey, behind the lines."""
    for k, (_, lo, hi) in enumerate(spans):
        if k % 2:
            ax.axvspan(lo, hi, color="0.93", lw=0, zorder=0)


def _run_label(run: Any, levels: Mapping[str, Any], factors: Mapping[str, Factor]) -> str:
    parts = []
    for name, value in levels.items():
        factor = factors.get(name)
        label = factor.level_label(value) if factor is not None else None
        if factor is not None and factor.labels is not None and label in (*factor.labels, "0"):
            # "S+", a centre point's "S0"; "mu0 +" where the name ends in a digit
            parts.append(f"{name} {label}" if name[-1:].isdigit() else f"{name}{label}")
        else:
            try:
                parts.append(f"{name}={float(value):g}")
            except (TypeError, ValueError):
                parts.append(f"{name}={value}")
    head = f"T{int(run)}" if isinstance(run, int | np.integer) else f"{run}"
    return f"{head}: {', '.join(parts)}" if parts else head


def plot_by_block(
    table: Any,
    factors: Iterable[Any] | None = None,
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Block by block, for every run: the mean COF of each block of the cycle and the
    block's share of the run's emitted volume, as two tables of coloured cells (a row per
    run, a column per block in the cycle's order), each cell written.

    Parameters
    ----------
    table
        :func:`brakeca.study.block_table`'s table (``tables/by_block.csv``): ``test`` (and
        ``replicate``), the factors' columns, ``block``, ``mean_cof`` [-] and
        ``share_of_emitted_percent`` [%]; or a campaign to make it of.
    factors
        The design's factors (or the design, or a campaign result), for each row's levels
        (``T5: S-, WP+, WR-, A-``); by default a campaign's own, given as ``table``;
        without them, the rows are named by test alone.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw into; a new figure by default.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes: the blocks' mean COF, and their shares of the emitted volume (each row sums
        to 100 %; empty for a run that emitted nothing); each block named with its number of
        stops (the first run's), as a block's share grows with it.
    """
    if not isinstance(table, pd.DataFrame) and hasattr(table, "design"):
        # a campaign, as block_table takes it (plot_by_block(campaign) had failed with "no
        # attribute 'empty'")
        from brakeca.study import block_table

        if factors is None:
            factors = _campaign_factors(table)
        table = block_table(table)
    needed = {"test", "block", "mean_cof", "share_of_emitted_percent"}
    if not isinstance(table, pd.DataFrame) or table.empty or not needed <= set(table.columns):
        raise ValueError(
            "table: brakeca.study.block_table's table (test, block, mean_cof, "
            "share_of_emitted_percent), of a cycle of named blocks"
        )
    by_name = {f.name: f for f in _factors(factors)} if factors is not None else {}
    import matplotlib as mpl

    from brakeca._console import is_replicated

    keys = ["test", "replicate"] if "replicate" in table.columns else ["test"]
    replicated = is_replicated(table)
    blocks = list(dict.fromkeys(table["block"].astype(str)))
    heads = table.drop_duplicates(keys)  # each run's first row, in the table's order
    runs = list(map(tuple, heads[keys].to_numpy().tolist()))
    labels = [
        _run_label(
            f"T{int(row['test'])} r{int(row['replicate'])}" if replicated else int(row["test"]),
            {name: row[name] for name in by_name if name in table.columns},
            by_name,
        )
        for _, row in heads.iterrows()
    ]
    index = pd.MultiIndex.from_tuples(runs, names=keys)
    wide = {
        column: table.assign(block=table["block"].astype(str))
        .pivot_table(index=keys, columns="block", values=column, aggfunc="first", dropna=False)
        .reindex(index=index, columns=blocks)
        .to_numpy(dtype=float)
        for column in ("mean_cof", "share_of_emitted_percent")
    }
    n_runs, n_blocks = len(runs), len(blocks)
    names = blocks
    if "stops" in table.columns:  # a block's share of V grows with its number of stops
        once = table.drop_duplicates("block")
        stops = dict(zip(once["block"].astype(str), once["stops"], strict=True))
        names = [f"{b} ({int(stops[b])})" for b in blocks]
    root, fig = _panels(fig, (2.6 + 1.35 * n_blocks + 2.2, 1.2 + 0.3 * n_runs))
    axes = fig.subplots(1, 2, sharey=True)
    # 3 decimals: at 2, runs at the COF floor (0.15) and runs 0.004 above it read alike (a
    # report review); both maps light where the value is high (magma_r had been the reverse)
    panels = (
        ("mean_cof", "Mean COF of the block's stops [-]", "viridis", "{:.3f}", "[-]"),
        (
            "share_of_emitted_percent",
            "Share of the run's emitted volume [%]",
            "magma",
            "{:.0f}",
            "[%]",
        ),
    )
    for ax, (column, title, cmap, form, unit) in zip(axes, panels, strict=True):
        values = wide[column]
        finite = values[np.isfinite(values)]
        low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        if high <= low:
            high = low + 1e-12
        image = ax.imshow(
            np.ma.masked_invalid(values), aspect="auto", cmap=cmap, vmin=low, vmax=high
        )
        colours = mpl.colormaps[cmap]
        for i, j in itertools.product(range(n_runs), range(n_blocks)):
            value = values[i, j]
            if not math.isfinite(value):
                continue
            shade = colours((value - low) / (high - low))
            light = 0.299 * shade[0] + 0.587 * shade[1] + 0.114 * shade[2] > 0.55
            ax.text(
                j,
                i,
                form.format(value),
                ha="center",
                va="center",
                fontsize=7,
                color="black" if light else "white",
            )
        ax.set_xticks(range(n_blocks), names, rotation=35, ha="right", fontsize=8)
        ax.set_title(title, fontsize=9)
        fig.colorbar(image, ax=ax, fraction=0.04, pad=0.02).set_label(unit, fontsize=8)
    axes[0].set_yticks(range(n_runs), labels, fontsize=7)
    _suptitle(fig, "Block by block: each run's mean COF, and where its emissions come from")
    return save_figure(root, path)


def _runs_side_by_side(runs: Any, variable: str) -> Any:
    """Runs given as ``{label: RunResult}`` or a list of RunResults (labelled by seed, or
    where they share one by the factors that differ, :func:`_differing_factors`) as one
    Dataset of ``variable`` along a ``run`` dimension of their labels, for
    :func:`plot_mu_per_stop`."""
    import xarray as xr

    items = list(runs.items()) if isinstance(runs, Mapping) else [(None, r) for r in runs]
    if not items:
        raise ValueError("campaign: no runs to plot")
    labels, frames = [], []
    for k, (label, run) in enumerate(items):
        dataset = getattr(run, "dataset", None)
        if dataset is None or variable not in getattr(dataset, "data_vars", ()):
            raise TypeError(
                f"campaign: item {k + 1} is a {type(run).__name__}, not a RunResult with "
                f"{variable!r}"
            )
        labels.append(str(label) if label is not None else f"seed {run.seed}")
        frames.append(dataset[[variable]])
    if not isinstance(runs, Mapping) and len(set(labels)) < len(labels):
        # runs of one seed and other pads (the comparison examples/single_run.py makes): each
        # named by the factors that differ (an API review: two materials of seed 3 were
        # refused as sharing a label)
        labels = _differing_factors([r for _, r in items], labels)
    if len(set(labels)) < len(labels):
        raise ValueError(f"campaign: two runs share a label ({labels}); give them as a mapping")
    return xr.concat(
        frames,
        dim=pd.Index(labels, name="run"),
        join="outer",
        coords="minimal",
        compat="override",
    )


def _differing_factors(runs: Sequence[Any], labels: Sequence[str]) -> list[str]:
    """Labels for runs that share a seed: the paper's factors (S, WP, WR, A, in their units)
    in which their configurations differ, after the seed where the seeds differ too;
    ``labels`` where no factor differs or a run has no configuration."""
    from brakeca.analysis import shown_unit
    from brakeca.config import FACTOR_ALIASES
    from brakeca.results import paper_factor_levels

    try:
        levels = [paper_factor_levels(run.config) for run in runs]
    except AttributeError:
        return list(labels)
    differ = [name for name in FACTOR_ALIASES if len({lv[name] for lv in levels}) > 1]
    if not differ:
        return list(labels)
    seeds = len({str(run.seed) for run in runs}) > 1
    # each factor in the unit the figures show its levels in ("WR = 0.1 µm")
    units = {n: shown_unit(FACTOR_ALIASES[n][2], [lv[n] for lv in levels]) for n in differ}
    return [
        ", ".join(
            ([label] if seeds else [])
            + [f"{n} = {_with_unit(f'{lv[n] / units[n][1]:g}', units[n][0])}" for n in differ]
        )
        for label, lv in zip(labels, levels, strict=True)
    ]


def _campaign_factors(campaign: Any) -> list[Factor] | None:
    """The design factors of a campaign: a :class:`~brakeca.campaign.CampaignResult`'s
    design's, or those a campaign dataset (``campaign.nc``) names in its ``factors``
    attribute, read from their coordinates' attributes (levels, labels, unit, long name);
    None for anything else (a run, a mapping of runs)."""
    if hasattr(campaign, "data_vars"):  # a Dataset: its attrs["design"] is the design's text
        names = campaign.attrs.get("factors")
        if isinstance(names, str):  # one factor: netCDF reads a one-item list back as text
            names = [names]
        if not names or any(n not in campaign.coords for n in names):
            return None
        return [
            Factor(
                name=str(n),
                levels=tuple(np.atleast_1d(campaign[n].attrs["levels"]).tolist()),
                unit=_axis_unit(campaign[n].attrs),
                label=str(campaign[n].attrs.get("long_name", "")),
                labels=_labels_attr(campaign[n].attrs.get("labels")),
            )
            for n in names
            if "levels" in campaign[n].attrs
        ] or None
    design = getattr(campaign, "design", None)
    return list(design.factors) if design is not None and hasattr(design, "factors") else None


def _labels_attr(labels: Any) -> tuple[str, ...] | None:
    """A factor's level labels as netCDF stores them (a list, or one text for one label)."""
    if labels is None:
        return None
    return (str(labels),) if isinstance(labels, str) else tuple(str(x) for x in labels)


def _stop_ticks(ax: Axes, stops: np.ndarray) -> None:
    """Ticks at whole stop numbers only: matplotlib's integer locator, or the stop itself
    where there is one (the locator then fell back to 0.5, 0.6, ...: a diff review)."""
    from matplotlib.ticker import FixedLocator, MaxNLocator

    if np.unique(stops).size == 1:
        ax.xaxis.set_major_locator(FixedLocator([float(stops[0])]))
    else:
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))


@dataclass(frozen=True)
class _PerStopRuns:
    """The runs of a per-stop figure: ``data`` the dataset (a ``run`` dimension, one run's
    added), ``values`` the variable [plotted unit] as (run, stop), ``keys`` each run's test
    (its replicates share it), ``ok`` whether each run finished, and how the runs are
    named (:meth:`label`)."""

    data: Any
    values: np.ndarray
    stops: np.ndarray
    keys: list[Any]
    ok: np.ndarray
    by_name: dict[str, Factor]
    factor_coords: list[str]
    ylabel: str
    what: str

    def label(self, k: int) -> str:
        """``"T5: S-, WP+, WR-, A-"``: run ``k``'s test and levels (:func:`_run_label`)."""
        levels = {c: self.data[c].to_numpy()[k] for c in self.factor_coords}
        return _run_label(self.keys[k], levels, self.by_name)


#: A campaign dataset's coordinates along ``run`` that are not levels (a run named by them
#: had read "T40: S=1, ..., test=40").
_RUN_BOOKKEEPING = frozenset(
    {"run", "test", "replicate", "order", "seed", "run_id", "status", "error"}
)


def _per_stop_runs(campaign: Any, factors: Iterable[Any] | None, variable: str) -> _PerStopRuns:
    """The runs of ``campaign`` (a campaign, a run, runs side by side or a dataset, as
    :func:`plot_mu_per_stop` takes them) and their ``variable`` per stop."""
    if not hasattr(campaign, "data_vars") and (  # a Dataset is a Mapping too
        isinstance(campaign, Mapping)
        or (isinstance(campaign, Sequence) and not isinstance(campaign, str))
    ):
        campaign = _runs_side_by_side(campaign, variable)
    if factors is None:
        factors = _campaign_factors(campaign)
    campaign = getattr(campaign, "dataset", campaign)  # a CampaignResult or a RunResult
    if not hasattr(campaign, "data_vars"):
        raise TypeError(
            "campaign: expected a CampaignResult, a RunResult or an xarray Dataset, got "
            f"{type(campaign).__name__}"
        )
    if variable not in campaign.data_vars:
        raise KeyError(f"campaign has no variable {variable!r}")
    one = "run" not in campaign[variable].dims
    if one:  # one run
        campaign = campaign[[variable]].expand_dims(run=[0])
    by_name = {f.name: f for f in _factors(factors if factors is not None else ())}
    ylabel, what, scale = _variable_axis(campaign, variable)
    runs = campaign["run"].to_numpy()
    if by_name:  # the factors name the runs; the other run coordinates are bookkeeping
        factor_coords = [name for name in by_name if name in campaign.coords]
    else:
        factor_coords = [
            name
            for name, coord in campaign.coords.items()
            if name not in _RUN_BOOKKEEPING and tuple(coord.dims) == ("run",)
        ]
    tests = campaign["test"].to_numpy() if "test" in campaign.coords else runs
    if one:  # (not "T0", a number it does not have: a diff review)
        tests = np.array(["the run"], dtype=object)
    if "status" in campaign.coords:
        ok = np.asarray(campaign["status"].to_numpy()).astype(str) == "ok"
    else:
        ok = np.ones(len(runs), dtype=bool)
    return _PerStopRuns(
        data=campaign,
        values=campaign[variable].transpose("run", "stop").to_numpy() * scale,
        stops=campaign["stop"].to_numpy(),
        keys=[t.item() if hasattr(t, "item") else t for t in tests],
        ok=ok,
        by_name=by_name,
        factor_coords=factor_coords,
        ylabel=ylabel,
        what=what,
    )


def _log_axis(values: np.ndarray, log: bool | None) -> bool:
    """Whether a per-stop figure draws ``values`` on a log axis: as ``log`` says, or (None)
    where their positive values span more than two decades; never without a positive one."""
    positive = values[np.isfinite(values) & (values > 0)]
    if log is None:
        log = positive.size > 0 and float(positive.max()) > 100.0 * float(positive.min())
    return bool(log) and positive.size > 0


def _floor_line(ax: Axes, floor: float) -> Any:
    """The COF law's floor [-] as a broad pale line under the runs: a style no run's line
    has (a diff review: a dotted floor among the dotted runs of tests 21 to 24)."""
    return ax.axhline(floor, color="0.5", lw=4.0, alpha=0.3, zorder=0.5)


def plot_mu_per_stop(
    campaign: Any,
    path: str | Path | None = None,
    *,
    factors: Iterable[Any] | None = None,
    variable: str = "mean_cof",
    title: str | None = None,
    ax: Axes | None = None,
    log: bool | None = False,
    floor: float | None = None,
) -> Figure:
    """Mean coefficient of friction per stop over the whole cycle, one line per run.

    Parameters
    ----------
    campaign
        A :class:`~brakeca.campaign.CampaignResult` (its dataset, and its design's factors
        unless ``factors`` is given), a :class:`~brakeca.results.RunResult`, several runs
        to compare (a mapping ``{label: RunResult}``, or a list of them, named by their
        seeds, or runs of one seed by the paper's factors in which they differ; runs of
        different lengths end where they end), or an xarray
        Dataset with dims ``run`` and ``stop`` (or ``stop`` alone, one run), the variable
        ``variable`` [-], the factor coordinates along ``run``, optionally ``test(run)`` (a
        campaign's test numbers: the replicates of a test share its colour and legend entry;
        without it each run is its own test) and ``block(stop)`` (block names), which are
        shaded and labelled.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    factors
        Optional factors; their level labels (``"-"``, ``"0"``, ``"+"``) name the runs.
    variable
        Data variable to plot, ``"mean_cof"`` by default.
    title
        The axes' title; by default one for all the runs of a campaign. A single run gets
        no legend.

    ax
        An axes to draw on, in a figure of one's own (a subplot of a grid); by default a
        new figure. ``path`` then writes that whole figure. In a panel the default title and
        the axis label are wrapped, and in a figure with a layout engine
        (``layout="constrained"`` or ``"tight"``, which make room for it) the legend of more
        than six tests stands beside the panel; without one it stays inside, as a figure
        without a layout cannot make room.
    log
        Draw the values on a log axis; None: where their positive values span more than two
        decades (a stop whose value is 0 then has no point), e.g. the emitted volume per
        stop, ``variable="emitted_volume"`` [mm³].
    floor
        The COF law's floor ``friction.mu_min`` [-], drawn as a broad pale line under the
        runs and named, where runs hold at it (the study's figure); none by default, and for
        another variable.

    Returns
    -------
    matplotlib.figure.Figure
        One axes.

    References
    ----------
    Wahlström (2016), Figure 10, doi:10.1155/2016/8181260.
    """
    import matplotlib as mpl
    from matplotlib.transforms import blended_transform_factory

    runs_ = _per_stop_runs(campaign, factors, variable)
    campaign, stops, keys = runs_.data, runs_.stops, runs_.keys
    ylabel, what = runs_.ylabel, runs_.what
    n = len(keys)
    given = ax is not None
    fig, ax = _axes(ax, (13.0, 6.0))

    if "block" in campaign.coords:
        blocks = [str(b) for b in campaign["block"].to_numpy()]
        trans = blended_transform_factory(ax.transData, ax.transAxes)
        spans = _block_spans(blocks, stops)
        _shade_blocks(ax, spans)
        for k, (name, lo, hi) in enumerate(spans):
            if k:
                ax.axvline(lo, color="0.6", lw=0.6, zorder=1)
            ax.text(  # above the axes, clear of the runs' lines
                0.5 * (lo + hi),
                1.01,
                name,
                transform=trans,
                rotation=90,
                ha="center",
                va="bottom",
                fontsize=7,
                color="0.25",
            )

    # neighbouring tests in different hues (a qualitative palette), the line style changing
    # every ten: up to 40 tests told apart (a rainbow had made neighbours alike)
    palette = mpl.colormaps["tab10"]
    styles = ("-", "--", ":", "-.")
    values = runs_.values
    # A run is named by its test; the replicates of a test (several seeds) share its colour,
    # line style and legend entry.
    position = {key: i for i, key in enumerate(dict.fromkeys(keys))}
    n_tests = len(position)
    labelled: set[Any] = set()
    many = n_tests > MOST_TESTS_NAMED
    for k, key in enumerate(keys):
        i = position[key]
        first = key not in labelled
        labelled.add(key)
        if many:  # each run grey, unnamed (below): no legend holds them
            continue
        ax.plot(
            stops,
            values[k],
            lw=1.0,
            ls=styles[(i // 10) % len(styles)],
            marker="o" if stops.size <= 20 else None,  # a few stops: a point each
            ms=3,
            color=palette(i % 10),
            label=runs_.label(k) if first else "_replicate",
        )
    if many:
        # beyond MOST_TESTS_NAMED tests a legend left most of them out, and colours and
        # styles repeated (a review of large designs): the runs grey, their mean over the
        # runs and the runs highest and lowest over the cycle named
        _run_lines(ax, stops, values, lw=0.6, colour="0.6", alpha=0.6)
        # the finished runs' mean over those reaching each stop, and the highest and lowest
        # of them by their own stops' mean (a run that failed early had been the highest on
        # its first stops; one that emitted nothing the lowest on a log axis, where it has
        # no line; runs of a shorter cycle are finished, not failed: a diff review)
        done = runs_.ok & np.isfinite(values).any(axis=1)
        finished = np.flatnonzero(done)
        if finished.size:
            rows = values[finished]
            with np.errstate(all="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # a stop no run reached
                overall = np.nanmean(rows, axis=1)
                mean = np.nanmean(rows, axis=0)
            ax.plot(
                stops,
                mean,
                lw=1.8,
                color="black",
                label=f"mean of the {finished.size} "
                + ("runs" if finished.size == n else "finished runs"),
            )
            emitting = overall > 0
            among = finished[emitting] if emitting.any() else finished
            scores = overall[emitting] if emitting.any() else overall
            for k, colour, word in (
                (int(among[np.argmax(scores)]), "#b2182b", "highest"),
                (int(among[np.argmin(scores)]), "#2166ac", "lowest"),
            ):
                ax.plot(
                    stops,
                    values[k],
                    lw=1.2,
                    color=colour,
                    label=f"{word} over the cycle: {runs_.label(k)}",
                )
    if floor is not None and variable == "mean_cof":  # (a figures review: the runs held at
        # the floor, which the report names, were a bundle of lines at 0.15 unexplained)
        _floor_line(ax, floor)
        ax.text(
            0.005,
            floor,
            f"COF floor μ_min = {floor:g}",
            transform=blended_transform_factory(ax.transAxes, ax.transData),
            va="top",  # under the line: the runs held at it run along its top
            fontsize=7,
            color="0.25",
            bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.7, "pad": 0.5},
            zorder=4,
        )
    ax.set_xlim(stops.min() - 0.5, stops.max() + 0.5)
    ax.set_xlabel("Stop number [-]")

    _stop_ticks(ax, stops)  # no stop 0.75 with a few stops
    if _log_axis(values, log):
        ax.set_yscale("log")
        ylabel += " (log scale)"
    ax.set_ylabel(ylabel)
    if title is None:
        title = (
            "Mean coefficient of friction per stop over the cycle"
            if variable == "mean_cof"
            else f"{what[:1].upper()}{what[1:]}: each stop over the cycle"
        ) + (", all runs" if n > 1 else "")  # (one run's had said "all runs": an API review)
        if many:
            title += f" ({n_tests} tests: each run grey)"
        elif n_tests < n:
            title += " (the replicates of a test share its colour)"
        if given:  # a panel of a grid: the title and the axis label wrapped to its width
            title = textwrap.fill(title, _panel_chars(ax, 12.0, 55))
            ax.set_ylabel(textwrap.fill(ylabel, 40))
    # above the block names, which stand above the axes: pad by the tallest name [points]
    pad = 6.0
    if ax.texts:  # (the figure's own renderer: a figure of one's own may have no Agg canvas)
        tallest = max(t.get_window_extent().height for t in ax.texts)
        pad += tallest * 72.0 / fig.dpi + 0.01 * ax.bbox.height * 72.0 / fig.dpi
    ax.set_title(title, pad=pad)
    ax.grid(True, alpha=0.3)
    if many:
        if ax.get_legend_handles_labels()[0]:  # (no finished run: nothing to name)
            ax.legend(fontsize=7, loc="best")
    elif n > 1 and given and (n_tests <= 6 or fig.get_layout_engine() is None):
        ax.legend(fontsize=7, ncols=1 if n_tests <= 30 else 2)  # (no room made beside it)
    elif n > 1 and given:  # beside the panel, where the figure's layout makes room for it
        ax.legend(
            fontsize=6,
            loc="upper left",
            bbox_to_anchor=(1.01, 1.0),
            borderaxespad=0.0,
            ncols=1 if n_tests <= 16 else 2,  # (a panel is shorter than 24 entries)
        )
    elif n > 1:
        fig.legend(loc="outside right upper", fontsize=7, ncols=1 if n_tests <= 30 else 2)
    return save_figure(fig, path)


def plot_mu_per_stop_by_test(
    campaign: Any,
    path: str | Path | None = None,
    *,
    factors: Iterable[Any] | None = None,
    variable: str = "mean_cof",
    tests: Iterable[Any] | None = None,
    log: bool | None = False,
    floor: float | None = None,
    columns: int = 4,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """:func:`plot_mu_per_stop` as small multiples: one panel per test, its runs drawn
    black over every other run's line in pale grey, all panels on the same axes.

    Where 24 runs' lines cross in one figure, ten colours and three line styles cannot
    tell them apart; here each test is read on its own, against the others.

    Parameters
    ----------
    campaign
        What :func:`plot_mu_per_stop` takes: a campaign, a run, runs side by side or an
        xarray Dataset with dims ``run`` and ``stop``, the variable ``variable``, the
        factors' levels along ``run``, optionally ``test(run)`` (the replicates of a test
        share its panel), ``status(run)`` (a run not ``"ok"`` is said so in its panel's
        title) and ``block(stop)`` (every second block shaded).
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    factors
        Optional factors; their level labels (``"-"``, ``"0"``, ``"+"``) name the tests.
    variable
        Data variable to plot, ``"mean_cof"`` [-] by default; a volume [m^3] is drawn in
        mm^3, an area fraction in per cent of the band.
    tests
        The tests to draw, a panel each, in the order given (the other runs stay grey
        behind them); every test by default, at most :data:`MOST_TESTS_NAMED` of them.
    log
        Draw the values on a log axis; None: where their positive values span more than two
        decades, as :func:`plot_mu_per_stop`.
    floor
        The COF law's floor ``friction.mu_min`` [-], drawn in every panel as a broad pale
        line under the runs (the mean COF only).
    columns
        Panels a row, at least 1 [-].
    fig
        A Figure or SubFigure to draw the panels into; a new figure by default. The figure
        returned, and written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per test, sharing both axes.

    Raises
    ------
    ValueError
        ``tests`` names a test the campaign does not have, or none; more than
        :data:`MOST_TESTS_NAMED` tests without ``tests``; ``columns`` below 1.
    KeyError
        The campaign has no ``variable``.

    References
    ----------
    Wahlström (2016), Figure 10, doi:10.1155/2016/8181260 (all runs in one panel).
    """
    from matplotlib.lines import Line2D

    if isinstance(columns, bool) or not isinstance(columns, int | np.integer) or columns < 1:
        raise ValueError(f"columns: expected a whole number of panels a row >= 1, got {columns!r}")
    runs = _per_stop_runs(campaign, factors, variable)
    values, stops, keys = runs.values, runs.stops, runs.keys
    order = list(dict.fromkeys(keys))
    if tests is None:
        if len(order) > MOST_TESTS_NAMED:
            raise ValueError(
                f"tests: the campaign has {len(order)} tests, more panels than one figure "
                f"reads well (at most {MOST_TESTS_NAMED}); name the tests to draw, e.g. "
                f"tests={order[:4]!r}, or draw every run in one panel (plot_mu_per_stop)"
            )
    else:
        if isinstance(tests, str | bytes):  # ("12" would be the tests "1" and "2")
            raise TypeError(f"tests: expected the tests as a list, e.g. [5, 17], got {tests!r}")
        chosen = [t.item() if hasattr(t, "item") else t for t in tests]
        if not chosen:
            raise ValueError(f"tests: none given; the campaign's are {_test_range(order)}")
        unknown = [t for t in chosen if t not in order]
        if unknown:
            raise ValueError(
                f"tests: {unknown} not among the campaign's tests ({_test_range(order)})"
            )
        order = list(dict.fromkeys(chosen))
    cols = min(int(columns), len(order))
    rows = math.ceil(len(order) / cols)
    root, fig = _panels(fig, (3.0 * cols + 0.6, 1.9 * rows + 1.3))
    axes = fig.subplots(rows, cols, sharex=True, sharey=True, squeeze=False).ravel()
    blocks = [str(b) for b in runs.data["block"].to_numpy()] if "block" in runs.data.coords else []
    spans = _block_spans(blocks, stops) if blocks else []
    at_floor = floor is not None and variable == "mean_cof"
    width = _panel_chars(axes[0], 8.0, 60)
    few = stops.size <= 20  # a point at each stop too: a run of one stop has no line (a
    # diff review: a one-stop campaign's panels were empty)
    for ax, key in zip(axes, order, strict=False):
        mine = np.array([k == key for k in keys])
        _shade_blocks(ax, spans)
        if at_floor:
            _floor_line(ax, float(floor))  # type: ignore[arg-type]
        _run_lines(ax, stops, values[~mine], lw=0.5, colour="0.72", alpha=0.7)
        if few and (~mine).any():
            ax.plot(np.tile(stops, int((~mine).sum())), values[~mine].ravel(), "o", ms=2,
                    color="0.72", alpha=0.7)  # fmt: skip
        for row in values[mine]:
            ax.plot(stops, row, lw=1.1, color="black", marker="o" if few else None, ms=3, zorder=3)
        title = runs.label(int(np.flatnonzero(mine)[0]))
        unfinished, own = int(np.count_nonzero(~runs.ok[mine])), int(mine.sum())
        if unfinished:
            title += (
                " (not finished)"
                if unfinished == own
                else f" ({unfinished} of {own} runs not finished)"
            )
        ax.set_title(textwrap.fill(title, width), fontsize=8)
        ax.grid(True, alpha=0.3)
    for ax in axes[len(order) :]:
        ax.remove()
    axes = axes[: len(order)]
    for k in range(len(order)):  # the lowest panel of each column shows the stops
        if k + cols >= len(order):
            axes[k].xaxis.set_tick_params(labelbottom=True)
            axes[k].set_xlabel("Stop number [-]", fontsize=8)
    log = _log_axis(values, log)
    if log:
        axes[0].set_yscale("log")  # (shared)
    ylabel = "Mean μ per stop [-]" if variable == "mean_cof" else runs.ylabel
    for ax in axes[::cols]:
        ax.set_ylabel(textwrap.fill(ylabel + (" (log)" if log else ""), 26), fontsize=8)

    _stop_ticks(axes[0], stops)  # shared: no stop 1.2
    axes[0].set_xlim(stops.min() - 0.5, stops.max() + 0.5)
    handles: list[Any] = [
        Line2D([], [], color="black", lw=1.1, label="the panel's test"),
        Line2D([], [], color="0.72", lw=0.8, label="every other run"),
    ]
    if at_floor:
        handles.append(
            Line2D([], [], color="0.5", lw=4.0, alpha=0.3, label=f"COF floor μ_min = {floor:g}")
        )
    if spans and len(spans) > 1:
        from matplotlib.patches import Patch

        handles.append(Patch(color="0.93", label="every second block of the cycle"))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=8)
    _suptitle(
        fig,
        (
            "Mean coefficient of friction per stop over the cycle"
            if variable == "mean_cof"
            else f"{runs.what[:1].upper()}{runs.what[1:]}: each stop over the cycle"
        )
        + ", test by test",
    )
    return save_figure(root, path)


def _test_range(tests: Sequence[Any]) -> str:
    """The tests a campaign has, for a message: ``"1 to 24"`` where they are every whole
    number between, else the first few."""
    whole = [int(t) for t in tests if isinstance(t, int | np.integer)]
    if (
        whole
        and len(whole) == len(tests)
        and sorted(whole) == list(range(min(whole), max(whole) + 1))
    ):
        return f"{min(whole)} to {max(whole)}"
    return ", ".join(map(repr, tests[:6])) + (", ..." if len(tests) > 6 else "")


def _run_lines(
    ax: Axes, stops: np.ndarray, rows: np.ndarray, *, lw: float, colour: Any, alpha: float
) -> None:
    """Each row of ``rows`` against ``stops`` as one collection of thin lines, unnamed: the
    legend's "best" place then avoids the named lines only, not every run's (a line each
    had put the legend over a mean line; a report review and a diff review)."""
    from matplotlib.collections import LineCollection

    segments = [np.column_stack([stops, row]) for row in rows]
    ax.add_collection(LineCollection(segments, linewidths=lw, colors=[colour], alpha=alpha))


#: The most tests a figure of every run's line names one by one; beyond, the runs are grey,
#: their mean and the highest and lowest named [-].
MOST_TESTS_NAMED = 40


def plot_mu_per_stop_by_level(
    campaign: Any,
    factors: Iterable[Any] | None = None,
    path: str | Path | None = None,
    *,
    variable: str = "mean_cof",
    fig: Figure | SubFigure | None = None,
    runs: bool = False,
) -> Figure:
    """The main effects over the cycle: the mean COF per stop of the runs at each level of
    each factor, one panel per factor.

    Each line is the mean, stop by stop, over the finished runs at that level (in an
    orthogonal design the other factors are balanced in it, as in a main-effects plot);
    runs at none of the levels (centre points) are left out. Where all runs' lines cross,
    as in :func:`plot_mu_per_stop` with 24 of them, these show which factor moves MU in
    which block of the cycle.

    Parameters
    ----------
    campaign
        A :class:`~brakeca.campaign.CampaignResult` (its dataset, and its design's factors
        unless ``factors`` is given) or an xarray Dataset with dims ``run`` and ``stop``,
        ``variable`` [-], the factors' levels as coordinates along ``run`` and optionally
        ``block(stop)``, whose blocks are shaded.
    factors
        The factors (:class:`brakeca.analysis.Factor` or factor-like); by default the
        campaign's design's.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    variable
        Data variable to average, ``"mean_cof"`` [-] by default.
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.
    runs
        Also draw each run's own line, thin and faint in its level's colour, under the
        means: where the runs of a level are in different states (a plateau area near 0 in
        some, 60 % in others), the mean alone is an area no run has.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per factor (two columns), sharing both axes.

    Raises
    ------
    ValueError
        No factor has its levels as a coordinate of the campaign.
    KeyError
        The campaign has no ``variable``.
    """

    if isinstance(factors, str | Path):  # plot_mu_per_stop_by_level(campaign, "x.png")
        raise TypeError(
            f"factors: got {str(factors)!r}, not factors; the file to write is path= "
            "(plot_mu_per_stop_by_level(campaign, factors=None, path=...))"
        )
    if factors is None:
        factors = _campaign_factors(campaign)
    data = getattr(campaign, "dataset", campaign)
    factors = _factors(factors if factors is not None else ())
    factors = [f for f in factors if f.name in getattr(data, "coords", {})]
    if not factors:
        raise ValueError("no factor of the campaign to plot by (its levels along 'run')")
    if variable not in data.data_vars:
        raise KeyError(f"campaign has no variable {variable!r}")
    if "run" not in data[variable].dims:  # one run: its own levels
        data = data.expand_dims(run=[0])
        data = data.assign_coords({f.name: ("run", [data[f.name].item()]) for f in factors})
    ylabel, what, scale = _variable_axis(data, variable)
    values = data[variable].transpose("run", "stop").to_numpy().astype(float) * scale
    stops = data["stop"].to_numpy()
    cols = 2 if len(factors) > 1 else 1
    rows = math.ceil(len(factors) / cols)
    root, fig = _panels(fig, (12.0, 2.3 * rows + 1.0))
    axes = fig.subplots(rows, cols, sharex=True, sharey=True, squeeze=False).ravel()
    blocks = [str(b) for b in data["block"].to_numpy()] if "block" in data.coords else []
    for ax, factor in zip(axes, factors, strict=False):
        _shade_blocks(ax, _block_spans(blocks, stops) if blocks else [])
        at = np.array([factor.level_index(v) for v in data[factor.name].to_numpy()])
        colours = _level_colours(len(factor.levels))
        for index, (level, colour) in enumerate(zip(factor.levels, colours, strict=True)):
            mine = values[at == index]  # the runs at this level (Factor.level_index)
            mine = mine[np.isfinite(mine).all(axis=1)]  # the finished runs
            if not len(mine):
                continue
            if runs:
                _run_lines(ax, stops, mine, lw=0.5, colour=colour, alpha=0.25)
            ax.plot(
                stops,
                mine.mean(axis=0),
                lw=1.3,
                ls=LEVEL_STYLES[index % len(LEVEL_STYLES)],
                color=colour,
                label=f"{_legend_label(factor, level)}, {len(mine)} run"
                + ("s" if len(mine) != 1 else ""),
            )
        ax.set_title(factor.label or factor.name, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=7)
    for ax in axes[len(factors) :]:
        ax.set_visible(False)
    for k in range(len(factors)):  # the lowest panel of each column shows the stops
        if k + cols >= len(factors):
            axes[k].xaxis.set_tick_params(labelbottom=True)
            axes[k].set_xlabel("Stop number [-]")
    for ax in axes[::cols]:  # wrapped to the panel's height (2.3 in), or they overlap
        ax.set_ylabel(
            "Mean μ per stop [-]" if variable == "mean_cof" else textwrap.fill(ylabel, 30)
        )

    _stop_ticks(axes[0], stops)  # shared: no stop 1.2
    _suptitle(
        fig,
        "Mean coefficient of friction per stop at each factor level (main effects)"
        if variable == "mean_cof"
        else f"{what[:1].upper()}{what[1:]}: each stop, at each factor level (main effects)",
    )
    return save_figure(root, path)


def plot_v_per_run(
    summary: pd.DataFrame | CampaignResult,
    path: str | Path | None = None,
    *,
    log: bool | None = None,
    ax: Axes | None = None,
    factors: Iterable[Any] | None = None,
) -> Figure:
    """Mean emitted wear volume per stop for every run (test), as bars in mm^3.

    Replicates (rows sharing a test number) are averaged and drawn with a one-standard-
    deviation error bar; tests without any successful run are marked "failed".

    Parameters
    ----------
    summary
        Campaign summary with ``test`` and ``V`` [m^3] (or ``V_mm3`` [mm^3]).
        Or a campaign result (:func:`brakeca.load_campaign`): its summary.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    log
        A logarithmic V axis, with a point per test instead of a bar; by default where the
        tests' V span more than two decades (where a linear axis shows the smallest as
        empty bars).

    ax
        An axes to draw on, in a figure of one's own (a subplot of a grid); by default a
        new figure. ``path`` then writes that whole figure.
    factors
        The design's factors (or the design): each test's levels are written under its
        number, one line per factor (its level label, ``+``, ``-``, or its value), as the
        paper's Table 4 gives them; by default a campaign result's design, else the test
        numbers alone.

    Returns
    -------
    matplotlib.figure.Figure
        One axes.

    References
    ----------
    Wahlström (2016), Figure 11, doi:10.1155/2016/8181260.
    """
    summary, factors = _campaign_parts(summary, factors, optional=True)  # a campaign result
    shown_factors = [f for f in _factors(factors) if f.name in summary.columns] if factors else []
    if "V" in summary.columns:
        column, scale = "V", 1e9
    elif "V_mm3" in summary.columns:
        column, scale = "V_mm3", 1.0
    else:
        raise KeyError("summary has neither 'V' [m^3] nor 'V_mm3' [mm^3]")
    if "test" not in summary.columns:
        raise KeyError("summary has no 'test' column")
    tests = sorted(pd.unique(summary["test"]))
    data = ok_runs(summary)
    values = pd.to_numeric(data[column], errors="coerce") * scale
    grouped = values.groupby(data["test"]).agg(["mean", "std", "count"]).reindex(tests)

    height = 4.0 + 0.16 * len(shown_factors)  # the levels' lines under the axis
    # beyond MOST_TESTS_NAMED tests, rows of at most that many (a figures review: 125 tests
    # in one row made a figure 7,400 pixels wide, its levels unreadable in the report)
    rows = 1 if ax is not None else max(1, math.ceil(len(tests) / MOST_TESTS_NAMED))
    per_row = max(1, math.ceil(len(tests) / rows))  # rows as even as they can be
    chunks = [tests[k : k + per_row] for k in range(0, len(tests), per_row)] or [[]]
    if ax is None:
        fig = _figure((max(6.0, 0.38 * len(chunks[0]) + 2.0), height * len(chunks)))
        axes = list(np.atleast_1d(fig.subplots(len(chunks), 1, sharey=True, squeeze=False)[:, 0]))
    else:
        fig, ax = _axes(ax, (6.0, height))
        axes = [ax]
    heights_all = grouped["mean"].to_numpy(dtype=float)
    err_all = grouped["std"].where(grouped["count"] > 1).to_numpy(dtype=float)
    shown = heights_all[np.isfinite(heights_all)]
    if log is None:
        log = bool(shown.size and np.all(shown > 0) and shown.max() > 100.0 * shown.min())
    first = summary.drop_duplicates("test").set_index("test") if shown_factors else None
    for ax, chunk in zip(axes, chunks, strict=True):
        _v_bars(ax, chunk, grouped, first, shown_factors, bool(log), span=per_row)
    for ax in axes[:-1]:  # the axis named once, under the last row
        ax.set_xlabel("")
    axes[len(axes) // 2].set_ylabel(
        "Emitted wear volume per stop V [mm³]" + (", log scale" if log else "")
    )
    title = "Mean emitted wear volume per stop, per test"
    if np.isfinite(err_all).any():
        title += " (mean ± 1 standard deviation of its replicates)"
    # wrapped to the figure's width (an 11-test figure had cut it at both ends: a review)
    axes[0].set_title(textwrap.fill(title, _panel_chars(axes[0], 12.0, 200)))
    return save_figure(fig, path)


def _v_bars(
    ax: Axes,
    tests: Sequence[Any],
    grouped: pd.DataFrame,
    first: pd.DataFrame | None,
    shown_factors: Sequence[Factor],
    log: bool,
    *,
    span: int,
) -> None:
    """:func:`plot_v_per_run`'s one row: ``tests``' mean V [mm³] (``grouped``'s ``mean``,
    ``std`` and ``count`` by test) as bars, or points on a ``log`` axis, each test's levels
    (``first``: a row of each test's levels) under its number; the axis ``span`` tests
    wide, so that a shorter last row has the others' bars."""
    grouped = grouped.reindex(tests)
    x = np.asarray(tests, dtype=float)
    heights = grouped["mean"].to_numpy(dtype=float)
    err = grouped["std"].where(grouped["count"] > 1).to_numpy(dtype=float)
    if log:  # points: a bar's length on a log axis would depend on where the axis starts
        ax.set_yscale("log")
        ax.plot(x, heights, "o", color="#27496d", ms=6, zorder=2)
    else:
        ax.bar(x, np.nan_to_num(heights), width=0.75, color="#27496d", zorder=2)
    if np.isfinite(err).any():
        ax.errorbar(x, heights, yerr=err, fmt="none", ecolor="0.2", capsize=2, lw=0.8, zorder=3)
    for xi, h in zip(x, heights, strict=True):
        if not np.isfinite(h):
            ax.text(
                xi,
                0.0,
                "failed",
                rotation=90,
                ha="center",
                va="bottom",
                fontsize=7,
                color="r",
                transform=ax.get_xaxis_transform(),  # at the axes' bottom, on either scale
            )
    labels = [str(t) for t in tests]
    if shown_factors and first is not None:  # each test's levels under its number (a
        # figures review: the axis named the tests alone, so reading the figure took the
        # design's table beside it)
        for k, t in enumerate(tests):
            for f in shown_factors:  # "+", "-", "0" (a centre point) or the value
                labels[k] += "\n" + f.level_label(float(first.loc[t, f.name]))
    ax.set_xticks(x, labels, fontsize=8)
    if x.size:  # no empty margins
        ax.set_xlim(float(x.min()) - 0.6, max(float(x.max()), float(x.min()) + span - 1) + 0.6)
    if shown_factors and x.size:  # the rows named at their left, aligned as the tick labels
        import matplotlib as mpl

        pad = float(mpl.rcParams["xtick.major.size"]) + float(mpl.rcParams["xtick.major.pad"])
        trans, va, _ = ax.get_xaxis_text1_transform(pad)
        ax.text(
            float(x.min()) - 0.6,
            0.0,
            "test\n" + "\n".join(f.name for f in shown_factors),
            transform=trans,
            va=va,
            ha="right",
            fontsize=8,
            color="0.3",
        )
    ax.set_xlabel(
        "Test number [-]"
        + (
            f", its levels below it: {', '.join(f.name for f in shown_factors)} from the top"
            if shown_factors
            else ""
        )
    )
    ax.grid(True, axis="both" if log else "y", alpha=0.3, zorder=0)


def plot_mu_vs_v(
    summary: pd.DataFrame | CampaignResult,
    path: str | Path | None = None,
    *,
    factors: Iterable[Any] | None = None,
    by: str | None = None,
    log: bool | None = None,
    ax: Axes | None = None,
) -> Figure:
    """The trade-off between friction and emissions: each test's MU against its V, one
    labelled point a test, coloured by the levels of one factor (beyond
    :data:`MOST_TESTS_NAMED` tests, only the tests of the trade-off front are labelled: those
    no other test has both a higher MU and a lower V).

    The paper's conclusion is such a trade-off (what raises the friction level raises the
    emissions too); the main effects give it factor by factor, this figure run by run: a
    pad material wants the lower right (high MU, low V).

    Parameters
    ----------
    summary
        Campaign summary with ``test``, ``MU`` [-] and ``V`` [m^3] (or ``V_mm3``
        [mm^3]); replicates are averaged. Or a campaign result: its summary and, where
        ``factors`` is None, its design.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    factors
        The design's factors (or the design), for ``by``'s levels and their labels.
    by
        The factor whose levels colour the points; by default none (one colour).
    log
        V on a log axis; by default where the tests' V span more than two decades.
    ax
        An axes to draw on; by default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        One axes.

    Raises
    ------
    KeyError
        The summary lacks ``test``, ``MU`` or V, or ``by`` names no factor of it.
    """
    summary, factors = _campaign_parts(summary, factors, optional=True)  # a campaign result
    if "V" in summary.columns:
        column, scale = "V", 1e9
    elif "V_mm3" in summary.columns:
        column, scale = "V_mm3", 1.0
    else:
        raise KeyError("summary has neither 'V' [m^3] nor 'V_mm3' [mm^3]")
    for needed in ("test", "MU"):
        if needed not in summary.columns:
            raise KeyError(f"summary has no {needed!r} column")
    known = {f.name: f for f in _factors(factors)} if factors else {}
    if by is not None and (by not in summary.columns or (known and by not in known)):
        raise KeyError(f"by: {by!r} is not a factor of the summary")
    data = ok_runs(summary)
    data = data.assign(_v=pd.to_numeric(data[column], errors="coerce") * scale)
    keep = ["test", *([by] if by else [])]
    means = data.groupby(keep, sort=True)[["MU", "_v"]].mean().reset_index()
    means = means[np.isfinite(means["MU"]) & np.isfinite(means["_v"])]
    fig, ax = _axes(ax, (7.5, 5.0))
    v = means["_v"].to_numpy(dtype=float)
    if log is None:
        log = bool(v.size and np.all(v > 0) and v.max() > 100.0 * v.min())
    if by:
        levels = sorted(pd.unique(means[by]))
        colours = _level_colours(len(levels))
        factor = known.get(by)
        for k, (level, colour) in enumerate(zip(levels, colours, strict=True)):
            at = means[means[by] == level]
            name = _legend_label(factor, float(level)) if factor else f"{by} = {level:g}"
            marker = LEVEL_MARKERS[k % len(LEVEL_MARKERS)]
            ax.plot(at["MU"], at["_v"], marker, color=colour, ms=7, label=name)
        ax.legend(fontsize=8, loc="best")
    else:
        ax.plot(means["MU"], means["_v"], "o", color="#27496d", ms=7)
    # tests at nearly one point share a label ("4, 10"), which had been drawn over each other
    # into "410" (a diff review)
    mu = means["MU"].to_numpy(dtype=float)
    y = np.log10(np.maximum(v, 1e-300)) if log else v

    def unit(a: np.ndarray) -> np.ndarray:
        span = float(np.ptp(a)) if a.size else 0.0
        return (a - a.min()) / span if span > 0 else np.zeros_like(a)

    near = np.c_[unit(mu), unit(y)]
    tests = [int(t) for t in means["test"]]
    labelled: list[int] = []
    named: set[int] = set()  # each test in one label only (a review of large designs: a test
    # near two labelled points had been named in both)
    # Beyond MOST_TESTS_NAMED tests the labels of 125 had run into one another (a figures
    # review): only the trade-off front is labelled then, the tests no other test beats in
    # both (a higher MU and a lower V).
    front = _trade_off_front(mu, v) if len(tests) > MOST_TESTS_NAMED else None
    for k in np.lexsort((near[:, 1], near[:, 0])):
        if front is not None and not front[k]:
            continue
        if k in named or any(np.hypot(*(near[k] - near[j])) < 0.03 for j in labelled):
            continue
        labelled.append(int(k))
        close = [
            i
            for i in range(len(tests))
            if i not in named
            and (front is None or front[i])  # (the title says which tests are named)
            and np.hypot(*(near[i] - near[k])) < 0.03
        ]
        named.update(close)
        ax.annotate(
            ", ".join(str(tests[i]) for i in sorted(close, key=lambda i: tests[i])),
            (mu[k], v[k]),
            xytext=(4, 3),
            textcoords="offset points",
            fontsize=7,
            color="0.25",
        )
    if log:
        ax.set_yscale("log")
    ax.set_xlabel("MU, mean coefficient of friction [-]")
    ax.set_ylabel("V, emitted wear volume per stop [mm³]" + (", log scale" if log else ""))
    ax.set_title(
        "Friction against emissions, test by test"
        + (
            ""
            if front is None
            else f"\n(labelled: the {int(front.sum())} tests no other has both a higher MU "
            "and a lower V)"
        )
    )
    ax.grid(True, which="major", alpha=0.3)
    return save_figure(fig, path)


def mu_v_names_front_only(summary: pd.DataFrame) -> bool:
    """Whether :func:`plot_mu_vs_v` names only the trade-off front for ``summary``: more than
    :data:`MOST_TESTS_NAMED` tests with a finished run of finite MU and V (the points it
    draws; a caption that counted failed tests too had disagreed with it: a diff review)."""
    column = "V" if "V" in summary.columns else "V_mm3"
    data = ok_runs(summary)
    if not {"test", "MU", column} <= set(data.columns):
        return False
    means = (
        data.assign(_v=pd.to_numeric(data[column], errors="coerce"))
        .groupby("test")[["MU", "_v"]]
        .mean()
    )
    drawn = np.isfinite(means["MU"].to_numpy(dtype=float)) & np.isfinite(means["_v"].to_numpy())
    return int(drawn.sum()) > MOST_TESTS_NAMED


def _trade_off_front(mu: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Whether each point lies on the trade-off front of high ``mu`` [-] and low ``v``
    [any unit]: no other point has a higher or equal MU and a lower or equal V, one of them
    strictly."""
    mu, v = np.asarray(mu, dtype=float), np.asarray(v, dtype=float)
    better_or_equal = (mu[None, :] >= mu[:, None]) & (v[None, :] <= v[:, None])
    strictly = (mu[None, :] > mu[:, None]) | (v[None, :] < v[:, None])
    return np.asarray(~(better_or_equal & strictly).any(axis=1), dtype=bool)


def _table_of(given: Any, table: str, response: str) -> Any:
    """``given`` itself, or the ``table`` of an analysis it holds: of a
    :class:`~brakeca.analysis.ResponseAnalysis`, or of ``response``'s in :func:`analyze`'s
    whole result (a mapping of them), so that ``plot_pareto(result["MU"], "MU")`` and
    ``plot_pareto(result, "MU")`` draw ``result["MU"].ranked_effects``."""
    if isinstance(given, Mapping) and not isinstance(given, ResponseAnalysis):
        if given and all(isinstance(v, ResponseAnalysis) for v in given.values()):
            if response not in given:
                raise KeyError(
                    f"response: {response!r} is not one of the analysis' responses "
                    f"({', '.join(map(repr, given))})"
                )
            given = given[response]
    return given[table] if isinstance(given, ResponseAnalysis) else given


def plot_pareto(
    ranked: pd.DataFrame | ResponseAnalysis | Mapping[str, ResponseAnalysis],
    response: str,
    path: str | Path | None = None,
    *,
    ax: Axes | None = None,
) -> Figure:
    """Pareto chart of the percent contribution of every model term.

    Parameters
    ----------
    ranked
        Output of :func:`brakeca.analysis.ranked_effects` (``term``,
        ``percent_contribution`` [%], optionally ``p_value``), largest first; or a
        :class:`~brakeca.analysis.ResponseAnalysis` (or :func:`~brakeca.analysis.analyze`'s
        whole result) for its ``ranked_effects``.
    response
        Response name, for the title.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).

    ax
        An axes to draw on, in a figure of one's own (a subplot of a grid); by default a
        new figure. ``path`` then writes that whole figure.
    Returns
    -------
    matplotlib.figure.Figure
        Two axes: the bars and the twin axis of the cumulative percentage.

    References
    ----------
    Wahlström (2016), Section 4, doi:10.1155/2016/8181260.
    """
    ranked = _table_of(ranked, "ranked_effects", response)
    # the terms alone: given an ANOVA table, its residual is no term to rank (an API review)
    table = ranked.loc[~ranked["term"].isin(["Residual", "Lack of fit", "Pure error"])]
    table = table.sort_values("percent_contribution", ascending=False, kind="stable")
    terms = [str(t) for t in table["term"]]
    pct = table["percent_contribution"].to_numpy(dtype=float)
    if "p_value" in table.columns:
        p = table["p_value"].to_numpy(dtype=float)
    else:
        p = np.full(len(table), np.nan)
    significant = np.isfinite(p) & (p < 0.05)

    fig, ax = _axes(ax, (max(6.0, 0.55 * len(terms) + 2.5), 4.2))
    x = np.arange(len(terms))
    colours = np.where(significant, "#27496d", "#9fb3c8")
    ax.bar(x, pct, color=colours, zorder=2)
    # each bar's share, starred where p < 0.05: a significant term of a fraction of a per
    # cent is a bar too low to show its colour (a figures review)
    for xi, value, sig in zip(x, pct, significant, strict=True):
        if np.isfinite(value):
            ax.annotate(
                f"{value:.2g}" + ("*" if sig else ""),
                (xi, value),
                xytext=(0, 2),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=7,
            )
    ax.set_xticks(x, terms, rotation=45, ha="right")
    ax.set_xlabel("Model term")
    ax.set_ylabel("Contribution to total sum of squares [%]")
    ax.set_title(f"Contribution of the ANOVA terms to {_shown(response)} (dark and *: p < 0.05)")
    ax.grid(True, axis="y", alpha=0.3, zorder=0)
    twin = ax.twinx()
    twin.plot(x, np.nancumsum(pct), "o-", color="#f28e2b", ms=4, lw=1.2)
    twin.set_ylim(0, 105)
    twin.set_ylabel("Cumulative contribution [%] (the rest: residual)")
    if not terms:
        ax.text(0.5, 0.5, "no model terms", transform=ax.transAxes, ha="center")
    return save_figure(fig, path)


def plot_effects(
    effects: pd.DataFrame | ResponseAnalysis | Mapping[str, ResponseAnalysis],
    response: str,
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """The effects of a two-level design, as Minitab draws them: a Pareto chart of the
    standardized effects ``|t|`` with the reference line of significance, and a half-normal
    plot of the absolute effects (Daniel's plot), where inactive effects lie on a line through
    the origin and active ones stand off it to the right.

    Parameters
    ----------
    effects
        Output of :func:`brakeca.analysis.two_level_effects` (``term``, ``effect``, ``t``,
        ``significant``; its ``attrs`` ``method``, ``df``, ``alpha``, ``pse``); a row ``Ct
        Pt`` (centre points), which has no effect, is left out, as Minitab leaves it out. Or
        a :class:`~brakeca.analysis.ResponseAnalysis` (or :func:`~brakeca.analysis.analyze`'s
        whole result) for its ``effects``.
    response
        Response column the effects are of, e.g. ``"MU"`` [-] or ``"V"`` [m^3] (drawn in the
        unit of the other figures, mm^3 for ``V``).
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes.

    References
    ----------
    R. V. Lenth, Technometrics 31(4), 469-473, 1989 (doi:10.1080/00401706.1989.10488595);
    C. Daniel, Technometrics 1(4), 311-341, 1959 (half-normal plots).
    """
    from scipy import stats

    effects = _table_of(effects, "effects", response)
    label, scale = _response_axis(response)
    attrs = effects.attrs
    alpha = float(attrs.get("alpha", 0.05))
    df = float(attrs.get("df", math.nan))
    method = attrs.get("method") or "?"
    effects = effects.loc[effects["term"] != CENTER_TERM]  # no effect: not in the charts
    n = len(effects)
    root, fig = _panels(fig, (11.0, max(4.6, 0.2 * n + 1.4)))  # a bar per effect, each readable
    ax_pareto, ax_half = fig.subplots(1, 2, width_ratios=(1.3, 1.0))
    _suptitle(fig, f"Effects on {_shown(response)} ({method}, α = {alpha:g})")
    if n == 0:
        for ax in (ax_pareto, ax_half):
            ax.text(0.5, 0.5, "no effects", transform=ax.transAxes, ha="center")
        return save_figure(root, path)
    order = np.argsort(-np.abs(effects["t"].to_numpy(dtype=float)), kind="stable")
    table = effects.iloc[order]
    t = np.abs(table["t"].to_numpy(dtype=float))
    significant = table["significant"].to_numpy(dtype=bool)
    y = np.arange(n)[::-1]
    colours = np.where(significant, "#27496d", "#9fb3c8")
    ax_pareto.barh(y, np.nan_to_num(t), color=colours, zorder=2)
    ax_pareto.set_yticks(y, [str(term) for term in table["term"]])
    if math.isfinite(df) and df > 0:
        critical = float(stats.t.ppf(1 - alpha / 2, df))
        ax_pareto.axvline(critical, color="#e15759", lw=1.2, ls="--", zorder=3)
        ax_pareto.text(
            critical, -0.45, f" {critical:.3g}", color="#e15759", va="bottom", fontsize=8
        )
    ax_pareto.set_xlabel("Standardized effect |t| [-]")
    ax_pareto.set_title("Pareto chart (dark: significant)")
    ax_pareto.grid(True, axis="x", alpha=0.3, zorder=0)
    magnitude = np.sort(np.abs(effects["effect"].to_numpy(dtype=float)) * scale)
    quantile = stats.halfnorm.ppf((np.arange(1, n + 1) - 0.5) / n)
    by_size = effects.iloc[np.argsort(np.abs(effects["effect"].to_numpy(dtype=float)))]
    ax_half.plot(magnitude, quantile, "o", color="#9fb3c8", ms=5, zorder=2)
    active = by_size["significant"].to_numpy(dtype=bool)
    ax_half.plot(magnitude[active], quantile[active], "o", color="#27496d", ms=5, zorder=3)
    for x_value, q_value, term, is_active in zip(
        magnitude, quantile, by_size["term"], active, strict=True
    ):
        if is_active:
            ax_half.annotate(
                str(term), (x_value, q_value), xytext=(4, -3), textcoords="offset points"
            )
    pse = float(attrs.get("pse", math.nan))
    if math.isfinite(pse) and pse > 0:  # the line the inactive effects follow: |e| = PSE q
        top = float(quantile[-1])
        ax_half.plot([0.0, pse * scale * top], [0.0, top], "-", color="#f28e2b", lw=1)
    ax_half.set_xlabel(f"Absolute effect ({label})")
    ax_half.set_ylabel("Half-normal quantile [-]")
    ax_half.set_title("Half-normal plot")
    ax_half.grid(True, alpha=0.3)
    return save_figure(root, path)


def _pair_panels(
    n_panels: int, fig: Figure | SubFigure | None
) -> tuple[Figure, Figure | SubFigure, np.ndarray]:
    """``n_panels`` axes, three to a row (those left over hidden), for the panels of pairs of
    factors of a response surface, in a new figure or in ``fig`` (:func:`_panels`)."""
    ncols = min(n_panels, 3)
    nrows = math.ceil(n_panels / ncols)
    root, fig = _panels(fig, (4.3 * ncols + 0.6, 3.8 * nrows + 0.6))
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False).ravel())
    for ax in axes[n_panels:]:
        ax.set_visible(False)
    return root, fig, axes


def plot_response_surface(
    fit: Any,
    path: str | Path | None = None,
    *,
    resolution: int = 81,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Contour plots of a fitted response surface, as Minitab's contour plots: one panel per
    pair of factors, the other factors held at their centre (coded 0), over the coded box the
    runs span, with the runs (projected onto the pair) and the stationary point when it lies
    in the region the runs span (projected onto the pair, as the runs are). A single factor
    gets the fitted curve through its runs.

    Parameters
    ----------
    fit
        A :class:`brakeca.rsm.SurfaceFit`.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    resolution
        Grid points per axis [-].
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per pair of factors (one for a single factor), each factor on its own scale
        (logarithmic for a log-coded factor), the response in the unit of the other figures
        (mm^3 for ``V``).
    """
    label, scale = _response_axis(fit.response)
    codings = list(fit.codings)
    extent = fit.extent()
    pairs = list(itertools.combinations(range(len(codings)), 2))
    root, fig, axes = _pair_panels(max(len(pairs), 1), fig)
    _suptitle(fig, f"Fitted response surface of {fit.response} ({label})")
    st = fit.stationary
    if len(codings) == 1:
        c = codings[0]
        lo, hi = extent[c.name]
        x = np.linspace(lo, hi, resolution)
        ax = axes[0]
        ax.plot(c.shown(x), fit.predict_coded({c.name: x}) * scale, color="#27496d")
        ax.plot(c.shown(fit.points[c.name]), fit.points["y"] * scale, "o", color="#f28e2b")
        ax.set_xlabel(c.axis_label)
        ax.set_ylabel(label)
        if c.log:
            _log_scale(ax.xaxis)
        ax.grid(True, alpha=0.3)
        return save_figure(root, path)
    for ax, (i, j) in zip(axes, pairs, strict=False):
        a, b = codings[i], codings[j]
        xa = np.linspace(extent[a.name][0], extent[a.name][1], resolution)
        xb = np.linspace(extent[b.name][0], extent[b.name][1], resolution)
        grid_a, grid_b = np.meshgrid(xa, xb)
        coded = {c.name: np.zeros_like(grid_a) for c in codings}
        coded[a.name], coded[b.name] = grid_a, grid_b
        z = fit.predict_coded(coded) * scale
        filled = ax.contourf(a.shown(grid_a), b.shown(grid_b), z, levels=12, cmap="viridis")
        lines = ax.contour(
            a.shown(grid_a), b.shown(grid_b), z, levels=filled.levels, colors="white",
            linewidths=0.5,
        )  # fmt: skip
        ax.clabel(lines, lines.levels[::2], fontsize=7, fmt="%.3g")
        fig.colorbar(filled, ax=ax, label=label)  # each panel has its own colour scale
        ax.plot(
            a.shown(fit.points[a.name]), b.shown(fit.points[b.name]), "o", ms=4,
            mfc="white", mec="black", label="runs (projected)", clip_on=False, zorder=4,
        )  # fmt: skip
        if st is not None and st["inside"]:  # outside, it is on no panel's slice
            sa, sb = st["coded"][a.name], st["coded"][b.name]
            ax.plot(a.shown(sa), b.shown(sb), "*", ms=12, color="#e15759", zorder=5,
                    label=f"stationary point ({st['kind']}, projected)")  # fmt: skip
        if a.log:
            _log_scale(ax.xaxis)
        if b.log:
            _log_scale(ax.yaxis)
        ax.set_xlabel(a.axis_label)
        ax.set_ylabel(b.axis_label)
        held = [c for c in codings if c.name not in (a.name, b.name)]
        if held:  # wrapped to the panel (a review of large designs: four held factors ran
            # past the panel into its neighbour's)
            ax.set_title(
                textwrap.fill(  # (a pair is not broken: non-breaking spaces in it)
                    "others at their centre: "
                    + ", ".join(f"{c.name}\u00a0=\u00a0{_centre_text(c)}" for c in held),
                    _panel_chars(ax, 8.0, 70),
                ),
                fontsize=8,
            )
    axes[0].legend(fontsize=7, loc="best")
    return save_figure(root, path)


def _log_scale(axis: Any) -> None:
    """A log scale on ``axis`` whose labels read as plain numbers between 0.001 and 10⁴
    (``0.2``, ``0.4``, ``1`` where a factor in µm spans a decade; matplotlib writes
    ``2×10⁻¹``), as powers of ten beyond; the ticks labelled are matplotlib's choice."""
    from matplotlib.ticker import LogFormatterSciNotation

    class Plain(LogFormatterSciNotation):
        def __call__(self, x: float, pos: int | None = None) -> str:
            shown = super().__call__(x, pos)
            return f"{x:g}" if shown and 1e-3 <= abs(x) < 1e4 else shown

    ax = axis.axes
    (ax.set_xscale if axis is ax.xaxis else ax.set_yscale)("log")
    axis.set_major_formatter(Plain())
    axis.set_minor_formatter(Plain(labelOnlyBase=False))  # (as matplotlib's log scale)


def _centre_text(coding: Any) -> str:
    """``"0.316\u00a0µm"``: a factor's centre (coded 0) in the unit its axis shows."""
    return _with_unit(f"{float(coding.shown(0.0)):.3g}", coding.shown_unit[0], "\u00a0")


def plot_profiler(
    fit: Any,
    path: str | Path | None = None,
    *,
    resolution: int = 81,
    level: float = 0.95,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """The fitted response surface along each factor with the others at their centre (coded
    0), with the confidence band of the fitted mean, as JMP's prediction profiler: the main
    effects of a response-surface design as its quadratic gives them. (The level means of a
    composite design's runs are no such thing: its levels are not balanced against the other
    factors, so a factor's raw means mix in the others' effects.)

    Parameters
    ----------
    fit
        A :class:`brakeca.rsm.SurfaceFit`.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    resolution
        Points per factor [-].
    level
        Confidence level of the band [-] (none drawn without residual degrees of freedom).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per factor, sharing the response axis (in the unit of the other figures:
        mm^3 for ``V``), each factor over the coded range its runs span, on its own scale
        (logarithmic for a log-coded factor), with its centre marked.
    """
    label, scale = _response_axis(fit.response)
    codings = list(fit.codings)
    extent = fit.extent()
    n = max(len(codings), 1)
    root, fig = _panels(fig, (3.0 * n + 0.8, 3.4))
    axes = np.atleast_1d(fig.subplots(1, n, sharey=True, squeeze=False).ravel())
    _suptitle(
        fig,
        f"Prediction profile of {fit.response} ({label}): the fitted surface along each factor, "
        f"the others at their centre, {100 * level:g} % confidence band",
    )
    for ax, c in zip(axes, codings, strict=False):
        lo, hi = extent[c.name]
        x = np.linspace(lo, hi, resolution)
        coded = {d.name: np.zeros_like(x) for d in codings}
        coded[c.name] = x
        fitted = fit.predict_coded(coded) * scale
        low, high = fit.confidence_interval(coded, level)
        levels = c.shown(x)
        if np.all(np.isfinite(low)):
            ax.fill_between(levels, low * scale, high * scale, color="#27496d", alpha=0.18)
        ax.plot(levels, fitted, color="#27496d")
        ax.axvline(float(c.shown(0.0)), color="0.5", lw=0.8, ls=":")
        if fit.loses_sign(float(np.min(fitted)) / scale):  # a positive response below 0
            ax.axhline(0.0, color="#a61b1b", lw=0.8)
            ax.text(
                0.02,
                0.02,
                "below 0: the quadratic's,\nnot any run's",
                transform=ax.transAxes,
                fontsize=7,
                color="#a61b1b",
                va="bottom",
            )
        if c.log:
            _log_scale(ax.xaxis)
        ax.set_xlabel(c.axis_label)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel(label)
    return save_figure(root, path)


def plot_overlaid_contours(
    fits: Mapping[str, Any],
    goals: Sequence[Any],
    optimum: Any,
    path: str | Path | None = None,
    *,
    resolution: int = 121,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Minitab's overlaid contour plot: where every response meets its goal's limits, over
    each pair of factors with the others at the optimum's levels. White: every response
    within its limits (at or below a minimize goal's upper limit, at or above a maximize
    goal's lower limit, between a target goal's limits); grey: some response outside. Each
    response's limits drawn as its own contour lines; the optimum marked.

    Parameters
    ----------
    fits
        Response to :class:`brakeca.rsm.SurfaceFit`, all over the same factors.
    goals
        The :class:`brakeca.rsm.Goal` of each response drawn.
    optimum
        The :class:`brakeca.rsm.Optimum` of those goals.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    resolution
        Grid points per axis [-].
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per pair of factors (one for a single factor: the responses against it).
    """
    goals = list(goals)
    first = fits[goals[0].response]
    codings = list(first.codings)
    extent = first.extent()
    pairs = list(itertools.combinations(range(len(codings)), 2)) or [(0, 0)]
    root, fig, axes = _pair_panels(len(pairs), fig)
    _suptitle(
        fig,
        "Where every response meets its limits (white), the others at the optimum: "
        + ", ".join(_limits_text(g) for g in goals),
    )
    colours = ["#e15759", "#4e79a7", "#59a14f", "#f28e2b", "#b07aa1"]
    for ax, (i, j) in zip(axes, pairs, strict=False):
        a, b = codings[i], codings[j]
        xa = np.linspace(extent[a.name][0], extent[a.name][1], resolution)
        if i == j:  # one factor: each response against it, its limits as lines
            coded = {a.name: xa}
            for colour, goal in zip(itertools.cycle(colours), goals):
                _, scale = _response_axis(goal.response)
                y = fits[goal.response].predict_coded(coded) * scale
                ax.plot(a.shown(xa), y, color=colour, label=goal.response)
                for limit in goal.acceptance_limits:
                    ax.axhline(limit * scale, color=colour, ls="--", lw=0.8)
            ax.axvline(float(a.shown(optimum.coded[a.name])), color="black", lw=0.8)
            ax.set_xlabel(a.axis_label)
            if a.log:
                _log_scale(ax.xaxis)
            ax.legend(fontsize=7)
            continue
        xb = np.linspace(extent[b.name][0], extent[b.name][1], resolution)
        grid_a, grid_b = np.meshgrid(xa, xb)
        coded = {c.name: np.full_like(grid_a, optimum.coded[c.name]) for c in codings}
        coded[a.name], coded[b.name] = grid_a, grid_b
        va, vb = a.shown(grid_a), b.shown(grid_b)
        values = {g.response: fits[g.response].predict_coded(coded) for g in goals}
        feasible = np.logical_and.reduce([g.acceptable(values[g.response]) for g in goals])
        ax.contourf(va, vb, (~feasible).astype(float), levels=[0.5, 1.5], colors=["#bdbdbd"])
        for colour, goal in zip(itertools.cycle(colours), goals):
            _, scale = _response_axis(goal.response)
            y = values[goal.response] * scale
            levels = sorted({v * scale for v in goal.acceptance_limits})
            if np.nanmin(y) < levels[-1] and np.nanmax(y) > levels[0]:
                lines = ax.contour(va, vb, y, levels=levels, colors=colour, linewidths=1.2)
                ax.clabel(lines, fontsize=7, fmt=f"{goal.response} %.3g")
        ax.plot(a.shown(optimum.coded[a.name]), b.shown(optimum.coded[b.name]), "*", ms=13,
                color="black", label="optimum", zorder=5, clip_on=False)  # fmt: skip
        if a.log:
            _log_scale(ax.xaxis)
        if b.log:
            _log_scale(ax.yaxis)
        ax.set_xlabel(a.axis_label)
        ax.set_ylabel(b.axis_label)
    axes[0].legend(fontsize=7, loc="lower left")
    return save_figure(root, path)


def _limits_text(goal: Any) -> str:
    _, scale = _response_axis(goal.response)
    unit = " mm³" if goal.response == "V" else ""
    if goal.kind == "minimize":
        return f"{goal.response} ≤ {goal.upper * scale:.3g}{unit}"
    if goal.kind == "maximize":
        return f"{goal.response} ≥ {goal.lower * scale:.3g}{unit}"
    return f"{goal.lower * scale:.3g} ≤ {goal.response} ≤ {goal.upper * scale:.3g}{unit}"


def plot_residuals(
    residuals: pd.DataFrame | ResponseAnalysis | Mapping[str, ResponseAnalysis],
    response: str,
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Residual plots of the ANOVA model, four in one: normal probability plot, residuals
    against the fitted values, histogram, residuals against the run order.

    The F tests of the ANOVA assume independent, normally distributed residuals of one
    variance: the normal plot shows departures from normality (points off the line), the plot
    against the fitted values a variance that grows with the response (a funnel), and the plot
    against the order a drift. Standardized residuals are drawn where they are defined (the
    residual over ``s sqrt(1 - leverage)`` [-], so about 95 % fall within ±2), raw residuals
    otherwise.

    Parameters
    ----------
    residuals
        Output of :func:`brakeca.analysis.residuals` (``fitted``, ``residual``,
        ``std_residual``, optionally ``order`` or ``test``); or a
        :class:`~brakeca.analysis.ResponseAnalysis` (or :func:`~brakeca.analysis.analyze`'s
        whole result) for its ``residuals``.
    response
        Response column the residuals are of, e.g. ``"MU"`` [-] or ``"V"`` [m^3] (drawn in
        the unit of the other figures, mm^3 for ``V``).
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        Four axes.
    """
    from scipy import stats

    residuals = _table_of(residuals, "residuals", response)
    missing = [c for c in ("fitted", "residual", "std_residual") if c not in residuals.columns]
    if missing:  # an ANOVA table, say (a bare KeyError: 'fitted', an API review)
        raise ValueError(
            f"residuals: expected the table brakeca.analysis.residuals returns, with the "
            f"columns fitted, residual and std_residual; this one lacks {', '.join(missing)}"
        )
    label, scale = _response_axis(response)
    fitted = residuals["fitted"].to_numpy(dtype=float) * scale
    std = residuals["std_residual"].to_numpy(dtype=float)
    standardized = std.size > 0 and bool(np.all(np.isfinite(std)))
    r = std if standardized else residuals["residual"].to_numpy(dtype=float) * scale
    r_label = "Standardized residual [-]" if standardized else f"Residual ({label})"
    if "order" in residuals.columns:
        order, order_label = residuals["order"].to_numpy(dtype=float), "Run order [-]"
    elif "test" in residuals.columns:
        order, order_label = residuals["test"].to_numpy(dtype=float), "Test number [-]"
    else:
        order, order_label = np.arange(1.0, r.size + 1.0), "Observation [-]"

    root, fig = _panels(fig, (9.0, 6.5))
    (ax_norm, ax_fit), (ax_hist, ax_order) = fig.subplots(2, 2)
    _suptitle(fig, f"Residual plots for {_shown(response)}")
    if r.size == 0:
        for ax in (ax_norm, ax_fit, ax_hist, ax_order):
            ax.text(0.5, 0.5, "no usable runs", transform=ax.transAxes, ha="center")
        return save_figure(root, path)
    n = r.size
    ranks = np.arange(1, n + 1)
    quantiles = stats.norm.ppf((ranks - 0.375) / (n + 0.25))  # Blom's plotting positions
    ordered = np.sort(r)
    ax_norm.plot(ordered, quantiles, "o", color="#27496d", ms=4)
    if standardized:
        ref = np.array([min(ordered[0], quantiles[0]), max(ordered[-1], quantiles[-1])])
        ax_norm.plot(ref, ref, "-", color="#f28e2b", lw=1)
    ax_norm.set_xlabel(r_label)
    ax_norm.set_ylabel("Normal quantile [-]")
    ax_norm.set_title("Normal probability plot")
    ax_fit.plot(fitted, r, "o", color="#27496d", ms=4)
    ax_fit.set_xlabel(f"Fitted value ({label})")
    ax_fit.set_ylabel(r_label)
    ax_fit.set_title("Versus fits")
    ax_hist.hist(r, bins=max(5, int(math.sqrt(n)) + 1), color="#9fb3c8", edgecolor="#27496d")
    ax_hist.set_xlabel(r_label)
    from matplotlib.ticker import MaxNLocator

    ax_hist.xaxis.set_major_locator(MaxNLocator(nbins=5))  # raw residuals' long tick labels
    ax_hist.set_ylabel("Runs [-]")
    ax_hist.set_title("Histogram")
    sort = np.argsort(order, kind="stable")
    ax_order.plot(order[sort], r[sort], "o-", color="#27496d", ms=4, lw=0.8)
    ax_order.set_xlabel(order_label)
    ax_order.set_ylabel(r_label)
    ax_order.set_title("Versus order")
    for ax in (ax_norm, ax_fit, ax_hist, ax_order):
        ax.grid(True, alpha=0.3)
    for ax in (ax_fit, ax_order):
        ax.axhline(0.0, color="0.3", lw=0.8)
    if standardized:  # the unusual runs named, as Minitab marks them (a figures review:
        # an outlier of the paper study's MU model was an unnamed point among the others)
        names = _run_labels(residuals)
        far = np.flatnonzero(np.abs(r) > UNUSUAL_RESIDUAL)
        for ax, x in ((ax_fit, fitted), (ax_order, order)):
            _name_points(ax, x[far], r[far], [names[k] for k in far], fontsize=8, color="#c0392b")
    if not standardized:
        _say_raw(ax_norm)
    return save_figure(root, path)


def _say_raw(ax: Any) -> None:
    """Say in ``ax`` that it draws raw residuals, standardized ones being undefined."""
    ax.text(
        0.02,
        0.98,
        "standardized residuals undefined\n(no residual df or leverage 1):\nraw residuals",
        transform=ax.transAxes,
        va="top",
        fontsize=8,
    )


def plot_residuals_by_level(
    residuals: pd.DataFrame | ResponseAnalysis | Mapping[str, ResponseAnalysis],
    summary: Any,
    factors: Iterable[Any] | None,
    response: str,
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Residuals against each factor's levels, one panel per factor: Minitab's "residuals
    versus the variables".

    The F tests assume one variance at every level; a level whose runs scatter more than
    the others' (a spread that grows with the level, as a volume's often does) shows here,
    where the four-in-one plot (:func:`plot_residuals`) mixes the levels. The runs beyond
    ±2 standardized residuals are named, as there.

    Parameters
    ----------
    residuals
        Output of :func:`brakeca.analysis.residuals` (``test``, optionally ``replicate``,
        ``residual``, ``std_residual``); or a :class:`~brakeca.analysis.ResponseAnalysis`
        (or :func:`~brakeca.analysis.analyze`'s whole result) for its ``residuals``.
    summary
        The campaign summary the residuals are of (its runs' levels, by ``test`` and
        ``replicate``); or a campaign result, its summary and, where ``factors`` is None,
        its design.
    factors
        The design's factors, or the design (or a campaign result) for them.
    response
        Response column the residuals are of, e.g. ``"MU"`` [-] or ``"V"`` [m^3].
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw the panels into; a new figure by default. The figure
        returned, and written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per factor (up to four a row), sharing the residual axis.

    Raises
    ------
    ValueError
        The residuals lack ``test`` or the residual columns, or the summary a factor.
    """
    summary, factors = _campaign_parts(summary, factors)
    factors = _factors(factors)
    residuals = _table_of(residuals, "residuals", response)
    missing = [c for c in ("test", "residual", "std_residual") if c not in residuals.columns]
    if missing:
        raise ValueError(
            f"residuals: expected the table brakeca.analysis.residuals returns; this one "
            f"lacks {', '.join(missing)}"
        )
    absent = [f.name for f in factors if f.name not in summary.columns]
    if absent or "test" not in summary.columns:
        raise ValueError(
            f"summary: no column {', '.join(absent or ['test'])}: the levels of the runs come "
            "from the campaign's summary"
        )
    keys = ["test", "replicate"] if "replicate" in residuals.columns else ["test"]
    keys = [k for k in keys if k in summary.columns]
    levels = summary[[*keys, *[f.name for f in factors]]].drop_duplicates(keys)
    runs = residuals.merge(levels, on=keys, how="left", validate="many_to_one")
    std = runs["std_residual"].to_numpy(dtype=float)
    standardized = std.size > 0 and bool(np.all(np.isfinite(std)))
    label, scale = _response_axis(response)
    r = std if standardized else runs["residual"].to_numpy(dtype=float) * scale
    r_label = "Standardized residual [-]" if standardized else f"Residual ({label})"
    names = _run_labels(runs)
    cols = min(len(factors), 4) or 1
    rows = math.ceil(max(len(factors), 1) / cols)
    root, fig = _panels(fig, (3.0 * cols + 1.0, 2.8 * rows + 0.8))
    axes = fig.subplots(rows, cols, sharey=True, squeeze=False).ravel()
    _suptitle(fig, f"Residuals of {_shown(response)} against the factors' levels")
    named: list[tuple[Axes, np.ndarray, np.ndarray, list[str]]] = []  # the unusual runs
    for ax, factor in zip(axes, factors, strict=False):
        values = runs[factor.name].to_numpy(dtype=float)
        shown = np.unique(values[np.isfinite(values)])  # the levels the runs have (centre too)
        x = np.searchsorted(shown, values).astype(float)
        # the runs of a level side by side, in test order, not on one another
        offset = np.zeros_like(x)
        for k in range(shown.size):
            at = np.flatnonzero(x == k)
            if at.size > 1:
                offset[at] = np.linspace(-0.18, 0.18, at.size)
        ax.plot(x + offset, r, "o", color="#27496d", ms=4)
        ax.axhline(0.0, color="0.3", lw=0.8)
        if standardized:
            for bound in (-UNUSUAL_RESIDUAL, UNUSUAL_RESIDUAL):
                ax.axhline(bound, color="0.5", lw=0.8, ls=":")
            far = np.flatnonzero(np.abs(r) > UNUSUAL_RESIDUAL)
            named.append((ax, (x + offset)[far], r[far], [names[k] for k in far]))
        ax.set_xticks(
            range(shown.size),
            [
                _tick_label(factor, float(v)) if float(v) in factor.levels else factor.shown(v)
                for v in shown
            ],
        )
        ax.set_xlim(-0.5, shown.size - 0.5)
        # with its unit and the long name above, as the main-effects plots (a report review)
        ax.set_xlabel(factor.axis_label)
        ax.set_title(factor.label or factor.name, fontsize=9)
        ax.grid(True, axis="y", alpha=0.3)
    for ax, xs, ys, labels in named:  # once every panel's limits are set (shared y)
        _name_points(ax, xs, ys, labels, fontsize=8, color="#c0392b")
    for ax in axes[len(factors) :]:
        ax.set_visible(False)
    for ax in axes[::cols]:
        ax.set_ylabel(r_label)
    if not standardized and len(factors):  # as plot_residuals says it (a diff review)
        _say_raw(axes[0])
    return save_figure(root, path)


def plot_level_comparisons(
    comparisons: pd.DataFrame | ResponseAnalysis | Mapping[str, ResponseAnalysis],
    response: str,
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Tukey's simultaneous intervals of the differences of a factor's level means, one panel
    per factor of three levels or more, as Minitab draws them.

    Each pair of levels is a row: its difference of means (``mean_b - mean_a``) and its
    interval; an interval that does not hold zero (the pair differs, drawn red) is
    significant at the table's confidence for all the factor's pairs at once.

    Parameters
    ----------
    comparisons
        Output of :func:`brakeca.analysis.level_comparisons`; or a
        :class:`~brakeca.analysis.ResponseAnalysis` (or :func:`~brakeca.analysis.analyze`'s
        whole result) for its ``comparisons``.
    response
        Response column they are of, e.g. ``"MU"`` [-] or ``"V"`` [m^3] (drawn in the unit
        of the other figures, mm^3 for ``V``).
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw the panels into; a new figure by default. The figure
        returned, and written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per factor compared.

    Raises
    ------
    ValueError
        The table has no comparison (no factor of three levels or more), or lacks the
        columns of :func:`brakeca.analysis.level_comparisons`.
    """
    table = _table_of(comparisons, "comparisons", response)
    needed = ("factor", "level_a", "level_b", "difference", "ci_low", "ci_high")
    missing = [c for c in needed if c not in table.columns]
    if missing:
        raise ValueError(
            "comparisons: expected the table brakeca.analysis.level_comparisons returns; this "
            f"one lacks {', '.join(missing)}"
        )
    if table.empty:
        raise ValueError("comparisons: no pair of levels to draw (no factor of 3 levels or more)")
    label, scale = _response_axis(response)
    confidence = float(table.attrs.get("confidence", 0.95))
    names = list(dict.fromkeys(table["factor"]))
    most = int(table["factor"].value_counts().max())
    root, fig = _panels(fig, (5.5 * len(names), 1.8 + 0.45 * most))
    axes = np.atleast_1d(fig.subplots(1, len(names), squeeze=False).ravel())
    _suptitle(
        fig,
        f"Tukey simultaneous {100 * confidence:g} % intervals: differences of the level means "
        f"of {_shown(response)}",
    )
    for ax, name in zip(axes, names, strict=True):
        rows = table[table["factor"] == name].reset_index(drop=True)
        y = np.arange(len(rows))[::-1]
        diff = rows["difference"].to_numpy(dtype=float) * scale
        low = rows["ci_low"].to_numpy(dtype=float) * scale
        high = rows["ci_high"].to_numpy(dtype=float) * scale
        differs = (low > 0) | (high < 0)
        for k in range(len(rows)):
            colour = "#b2182b" if differs[k] else "#27496d"
            if np.isfinite(low[k]) and np.isfinite(high[k]):
                ax.plot([low[k], high[k]], [y[k], y[k]], "-", color=colour, lw=1.6)
            ax.plot([diff[k]], [y[k]], "o", color=colour, ms=5)
        ax.axvline(0.0, color="0.3", lw=0.8, ls="--")
        pairs = zip(rows["level_a"], rows["level_b"], strict=True)

        def level(label: Any, name: str = name) -> str:  # "WP+", or "mu0 = 0.6" for a value
            return f"{name}{label}" if str(label) in ("-", "0", "+") else f"{name} = {label}"

        ax.set_yticks(y, [f"{level(b)} − {level(a)}" for a, b in pairs])
        ax.set_ylim(-0.6, len(rows) - 0.4)
        ax.set_title(f"{name}", fontsize=10)
        ax.set_xlabel(f"Difference of means ({label})")
        ax.grid(True, axis="x", alpha=0.3)
    return save_figure(root, path)


def _run_labels(residuals: pd.DataFrame) -> list[str]:
    """Each row's run as a short label: ``"test 23"``, ``"test 5/1"`` (test/replicate) where
    the table holds replicates, the row number where it has no test column."""
    if "test" not in residuals.columns:
        return [f"run {k + 1}" for k in range(len(residuals))]
    from brakeca._console import is_replicated

    tests = residuals["test"].to_numpy()
    if is_replicated(residuals):
        reps = residuals["replicate"].to_numpy()
        return [f"test {int(a)}/{int(b)}" for a, b in zip(tests, reps, strict=True)]
    return [f"test {int(a)}" for a in tests]


def plot_box_cox(
    results: Mapping[str, Any],
    path: str | Path | None = None,
    *,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Box-Cox plots: the profile log-likelihood of λ for each response, as R's
    ``MASS::boxcox`` draws it.

    Each panel shows ``L(λ)`` over [-2, 2], the line ``L(λ̂) - χ²(1, 0.95) / 2`` whose
    crossings bound the 95 % interval of λ (shaded), λ̂ and the two usual scales, λ = 1 (the
    response as it is) and λ = 0 (its log). Where the analysis had unusual runs
    (:attr:`brakeca.boxcox.BoxCox.without`), the profile without them is drawn dashed,
    shifted to the same maximum, so that the dotted line bounds its interval too. A
    response for which λ is not defined (a value not positive, no residual degrees of
    freedom) gets a panel saying why.

    Parameters
    ----------
    results
        ``{response: BoxCox}`` from :mod:`brakeca.boxcox`.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per response.
    """
    from scipy import stats

    items = list(results.items())
    n = max(len(items), 1)
    root, fig = _panels(fig, (4.2 * n, 3.6))
    axes = np.atleast_1d(fig.subplots(1, n))
    _suptitle(fig, "Box-Cox plots: which power of the response the model fits best")
    if not items:
        axes[0].text(0.5, 0.5, "no response", transform=axes[0].transAxes, ha="center")
        return save_figure(root, path)
    for ax, (response, result) in zip(axes, items, strict=True):
        ax.set_title(str(response))
        ax.set_xlabel("λ [-]")
        ax.set_ylabel("Profile log-likelihood [-]")
        if not result.defined:
            ax.text(
                0.5,
                0.5,
                "λ not defined:\n" + textwrap.fill(result.note, 38),
                transform=ax.transAxes,
                ha="center",
                va="center",
                fontsize=8,
            )
            continue
        lam = result.profile["lam"].to_numpy(dtype=float)
        ll = result.profile["log_likelihood"].to_numpy(dtype=float)
        cut = float(np.max(ll)) - 0.5 * float(stats.chi2.ppf(result.confidence, 1))
        cut = max(cut, float(ll.min()))
        ax.plot(lam, ll, "-", color="#27496d", lw=1.5)
        other = getattr(result, "without", None)
        if other is not None and other.defined and len(other.profile):
            # the profile without the unusual runs, shifted to the same maximum, so that the
            # dotted line bounds its interval too (a figures review: MU's reading rests on
            # one run, which the figure did not show)
            ll_other = other.profile["log_likelihood"].to_numpy(dtype=float)
            ax.plot(
                other.profile["lam"].to_numpy(dtype=float),
                ll_other + (float(np.max(ll)) - float(np.max(ll_other))),
                "--",
                color="#b2182b",
                lw=1.2,
                label=f"without {result.without_runs} (shifted; λ̂ "
                + ("" if other.edge else "= ")
                + f"{other.hat_text()})",
            )
            # its interval, on the dotted line its shifted profile crosses there
            ends = (max(other.ci_low, lam[0]), min(other.ci_high, lam[-1]))
            ax.plot(
                ends, (cut, cut), "-", color="#b2182b", lw=3.0, alpha=0.6, solid_capstyle="butt"
            )
        low = max(result.ci_low, lam[0])
        high = min(result.ci_high, lam[-1])
        ax.axvspan(
            low,
            high,
            color="#9fb3c8",
            alpha=0.35,
            lw=0,
            label=f"{100 * result.confidence:g} % interval",
        )
        ax.axhline(cut, color="0.4", lw=0.8, ls=":")
        # on the search range's edge, λ̂ is a bound, not an estimate (BoxCox.hat_text)
        hat = (
            f"λ̂ {result.hat_text()} (the search range's edge)"
            if result.edge
            else (f"λ̂ = {result.hat_text()}")
        )
        ax.axvline(result.lambda_hat, color="#f28e2b", lw=1.2, label=hat)
        for ref, name in ((1.0, "λ = 1"), (0.0, "λ = 0 (log)")):
            ax.axvline(ref, color="0.2", lw=0.8, ls="--")
            ax.text(  # beside its line, on white (the line struck it through; a review)
                ref,
                0.02,
                f"{name} ",
                transform=ax.get_xaxis_transform(),
                fontsize=7,
                rotation=90,
                ha="right",
                va="bottom",
                # translucent, under the profiles: the curve stays seen (a diff review)
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.6, "pad": 0.5},
                zorder=1.5,
            )
        margin = 0.02 * (lam[-1] - lam[0])  # a λ̂ on the range's edge stays seen
        ax.set_xlim(lam[0] - margin, lam[-1] + margin)
        # the top of the profile, where the interval is read: a profile falling 200 units
        # had squeezed it into the top 5 % of the panel (a figures review)
        top = float(np.max(ll))
        floor = top - 12.0 * (top - cut)
        if float(ll.min()) < floor:
            ax.set_ylim(floor, top + 0.08 * (top - floor))
        ax.grid(True, alpha=0.3)
        # below the axes: inside, it had covered the λ = 0 label (a report review)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.24), frameon=False)
    return save_figure(root, path)


# --- surface maps (Figure 5 and final plateau maps) ------------------------------------------


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges from cell centres (midpoints, extrapolated half a step at the ends)."""
    c = np.asarray(centres, dtype=float)
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _band_ratio(radius: Any, angle: Any) -> float:
    """The band's radial span over its arc at the mean radius [-] (cell edge to cell edge):
    about 0.23 for the paper's band, 0.024 for the quick band."""
    r = np.asarray(radius, dtype=float)
    a = np.asarray(angle, dtype=float)
    span_r = float(np.ptp(r)) * (r.size / (r.size - 1)) if r.size > 1 else 0.0
    arc = float(np.ptp(a)) * (a.size / (a.size - 1)) * float(np.mean(r)) if a.size > 1 else 0.0
    return span_r / arc if arc > 0 else 0.0


def fits_to_scale(radius: Any, angle: Any) -> bool:
    """Whether a band drawn to scale (``true_scale``) across a page stands about 1 inch tall
    or more: the paper's band does (20 by 87 mm); the quick band (2 by 87 mm) would be a
    strip a quarter of an inch high, so its maps fill their axes instead.

    Parameters
    ----------
    radius, angle
        The cells' centres [m] and [rad].

    Returns
    -------
    bool
        Whether ``true_scale`` maps of the band are readable.
    """
    return _band_ratio(radius, angle) * 11.2 >= 1.0


def _check_map(status: Any, radius: Any, angle: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    s = np.asarray(status)
    r = np.asarray(radius, dtype=float)
    a = np.asarray(angle, dtype=float)
    if s.ndim != 2 or s.shape != (r.size, a.size):
        raise ValueError(
            f"status shape {s.shape} does not match (n_radial, n_angular) = ({r.size}, {a.size})"
        )
    if s.size and (s.min() < 0 or s.max() > 2):
        raise ValueError("status codes must be 0 (resin), 1 (primary) or 2 (secondary)")
    if r.size and float(np.nanmax(np.abs(r))) > 1.0:
        # radii in mm had drawn an axis of 113200 mm (an API review); a disc is under 1 m
        raise ValueError(
            f"radius: the cells' radii in m (a disc's are under 1 m), got up to "
            f"{float(np.nanmax(np.abs(r))):g}: in mm, give radius / 1000 (in cm, radius / 100)"
        )
    if a.size and float(np.nanmax(np.abs(a))) > 2.0 * np.pi:
        raise ValueError(
            f"angle: the cells' angles in rad, got up to {float(np.nanmax(np.abs(a))):g}: in "
            "degrees, give numpy.radians(angle)"
        )
    if r.size > 1 and r[0] > r[-1]:
        r, s = r[::-1], s[::-1, :]
    if a.size > 1 and a[0] > a[-1]:
        a, s = a[::-1], s[:, ::-1]
    return s.astype(np.int8), r, a


def _draw_map(
    ax: Axes, status: Any, radius: Any, angle: Any, title: str, *, true_scale: bool = False
) -> tuple[list[Any], np.ndarray]:
    """Draw one status map on ``ax``; return legend handles and area fractions.
    ``true_scale``: a millimetre of radius as long as a millimetre of arc at the band's mean
    radius (the axes' aspect; otherwise the map fills the axes)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    s, r, a = _check_map(status, radius, angle)
    cmap = ListedColormap(list(STATUS_COLOURS))
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    x_edges = np.degrees(_edges(a))
    y_edges = _edges(r) * 1e3
    uniform = all(
        v.size < 3 or np.allclose(np.diff(v), np.diff(v)[0], rtol=1e-6, atol=0) for v in (r, a)
    )
    if uniform:
        ax.imshow(
            s,
            cmap=cmap,
            norm=norm,
            origin="lower",
            extent=(x_edges[0], x_edges[-1], y_edges[0], y_edges[-1]),
            aspect="auto",
            interpolation="nearest",
        )
    else:
        ax.pcolormesh(x_edges, y_edges, s, cmap=cmap, norm=norm, rasterized=True)
    if true_scale:  # a degree of angle is r pi / 180 mm of arc at the mean radius r [mm]
        ax.set_aspect(180.0 / (np.pi * float(np.mean(r)) * 1e3))
    ax.set_xlabel("Angle [°] (sliding direction →)")
    ax.set_ylabel("Radius [mm]")
    if title:
        ax.set_title(title, fontsize=10)
    handles = [
        Patch(facecolor=STATUS_COLOURS[k], edgecolor="0.4", label=STATUS_NAMES[k]) for k in range(3)
    ]
    return handles, status_area_fractions(s, r)


def plot_surface_map(
    status: Any,
    radius: Any = None,
    angle: Any = None,
    title: str = "",
    path: str | Path | None = None,
    *,
    ax: Axes | None = None,
    true_scale: bool = False,
) -> Figure:
    """Map of the pad surface status on the polar band (angle on x, radius on y).

    Parameters
    ----------
    status
        Integer array of shape (n_radial, n_angular): 0 = resin (no plateau), 1 = primary
        plateau (metal fibre), 2 = secondary plateau; or a run's map as an xarray DataArray
        on ``radius`` and ``angle`` (``result.dataset["final_status"]``), whose coordinates
        give ``radius`` and ``angle`` where they are not given.
    radius
        Cell-centre radii [m], length n_radial.
    angle
        Cell-centre angles [rad], length n_angular (plotted in degrees; sliding direction is
        increasing angle).
    title
        Figure title.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).

    ax
        An axes to draw on, in a figure of one's own (a subplot of a grid); by default a
        new figure. ``path`` then writes that whole figure. In a panel the title is wrapped
        to its width and the legend stands below it in a figure with a layout engine
        (``layout="constrained"`` or ``"tight"``, which make room for it); without one it
        stays inside, over the map, as a figure without a layout cannot make room.
    true_scale
        Draw the map to scale: a millimetre of radius as long as a millimetre of arc at the
        band's mean radius; a new figure's height then follows the band (1.5 to 6 in;
        :func:`fits_to_scale` says whether a band is tall enough to read so). Without it
        the map fills a figure of its own of 10 by 3.6 in, which stretches the paper's
        band's radius about 1.2 times.

    Returns
    -------
    matplotlib.figure.Figure
        One axes; the legend gives the area fraction of each status.

    References
    ----------
    Wahlström (2016), Figure 5 (fibre maps) and Section 2 (plateau model),
    doi:10.1155/2016/8181260.
    """
    if isinstance(title, Path) or (
        path is None and str(title).lower().endswith((".png", ".pdf", ".svg", ".jpg", ".jpeg"))
    ):
        # plot_surface_map(status, radius, angle, "map.png") drew a figure titled "map.png"
        # and wrote no file
        raise TypeError(
            f"title: {str(title)!r} reads like a file name; the file to write is path= "
            "(plot_surface_map(status, radius, angle, title, path))"
        )
    status, radius, angle = _map_parts(status, radius, angle)
    given = ax is not None
    height = 3.6
    if true_scale:
        height = min(6.0, max(1.5, 9.0 * _band_ratio(radius, angle) + 1.35))
    fig, ax = _axes(ax, (10.0, height))
    handles, fractions = _draw_map(ax, status, radius, angle, "", true_scale=true_scale)
    for h, f in zip(handles, fractions, strict=True):
        h.set_label(f"{h.get_label()}: {100 * f:.1f} %")
    if given:  # within a figure of one's own: the legend and title on these axes
        # in as many columns as the panel's width holds (three in a row had run into the
        # next panel: an API review); below it, clear of the map, where the figure's layout
        # engine makes room for it, and inside it otherwise, as a figure without a layout
        # cannot make room
        width, height = _panel_inches(ax)
        ncols = 3 if width >= 7.0 else 1
        if fig.get_layout_engine() is None:
            ax.legend(handles=handles, loc="upper right", ncols=ncols, fontsize=7)
        else:
            ax.legend(
                handles=handles,
                loc="upper center",
                bbox_to_anchor=(0.5, -0.5 / max(height, 0.5)),
                ncols=ncols,
                fontsize=7,
                frameon=False,
            )
        if title:
            ax.set_title(textwrap.fill(title, _panel_chars(ax, 12.0, 80)))
    else:
        fig.legend(handles=handles, loc="outside lower center", ncols=3, fontsize=8)
        if title:
            _suptitle(fig, title)
    return save_figure(fig, path)


def _map_parts(status: Any, radius: Any, angle: Any) -> tuple[Any, Any, Any]:
    """A map's (status, radius [m], angle [rad]): a DataArray on ``radius`` and ``angle`` (a
    run file's ``final_status``) gives the coordinates not given (an xarray user had to pass
    them again: an API review)."""
    for name, value in (("radius", radius), ("angle", angle)):
        if isinstance(value, str):
            unit = "radii [m]" if name == "radius" else "angles [rad]"
            raise TypeError(
                f"{name}: an array of the cells' {unit}, got {value!r} (a title is title=)"
            )
    coords = getattr(status, "coords", None)
    dims = set(getattr(status, "dims", ()))
    if coords is not None and {"radius", "angle"} <= dims:
        others = sorted(str(d) for d in dims - {"radius", "angle"})
        if others:
            raise TypeError(
                f"status: one map on radius and angle, got one over {', '.join(others)} too; "
                f"pick one (e.g. .sel({others[0]}=...) or .isel(...))"
            )
        status = status.transpose("radius", "angle")
        radius = coords["radius"].values if radius is None else radius
        angle = coords["angle"].values if angle is None else angle
    if radius is None or angle is None:
        raise TypeError(
            "radius and angle: give the cells' radii [m] and angles [rad], or the status as "
            "a DataArray on radius and angle (a run's dataset['final_status'])"
        )
    return np.asarray(status), radius, angle


def plot_fibre_maps(
    maps: Mapping[str, tuple[Any, Any, Any]],
    path: str | Path | None = None,
    *,
    ncols: int | None = None,
    title: str = "Pad surface maps",
    fig: Figure | SubFigure | None = None,
    true_scale: bool = False,
) -> Figure:
    """Several surface maps side by side, e.g. the fibre layouts of the A levels.

    Parameters
    ----------
    maps
        ``{panel title: (status, radius [m], angle [rad])}``, see :func:`plot_surface_map`.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    ncols
        Panels per row; by default all in one row up to three maps, two by two for four, three
        per row beyond (five A levels side by side made a figure 4,200 pixels wide); one per
        row with ``true_scale``.
    title
        The figure's title.
    true_scale
        Draw each map to scale: a millimetre of radius as long as a millimetre of arc at the
        band's mean radius, so that a fibre lies at its angle (the paper's band, 20 mm by
        87 mm of arc, fills two panels side by side only with the radius stretched about 2.2
        times, which makes fibres look more radial than they lie).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per map, with a shared legend.

    References
    ----------
    Wahlström (2016), Figure 5, doi:10.1155/2016/8181260.
    """
    if not maps:
        raise ValueError("no maps to plot")
    n = len(maps)
    default = 1 if true_scale else (2 if n == 4 else min(n, 3))
    ncols = default if ncols is None else max(1, min(int(ncols), n))
    nrows = math.ceil(n / ncols)
    height = 3.0
    if true_scale:  # the panels' height as the first map's shape gives it, within 1.5-6 in
        _, r0, a0 = _check_map(*next(iter(maps.values())))
        height = min(6.0, max(1.5, 0.75 * (11.2 / ncols) * _band_ratio(r0, a0) + 0.9))
    root, fig = _panels(fig, (5.6 * ncols if not true_scale else 12.0, height * nrows + 0.8))
    grid = fig.subplots(nrows, ncols, squeeze=False)
    handles: list[Any] = []
    for k, (ax, (name, (status, radius, angle))) in enumerate(
        zip(grid.ravel(), maps.items(), strict=False)
    ):
        handles, fractions = _draw_map(ax, status, radius, angle, "", true_scale=true_scale)
        # the area fractions in the title, not in a box over the map's corner
        ax.set_title(
            f"{name} (primary {100 * fractions[1]:.1f} %, secondary {100 * fractions[2]:.1f} %)",
            fontsize=10,
        )
        if k // ncols != nrows - 1 and k + ncols < n:
            ax.set_xlabel("")
    for ax in grid.ravel()[n:]:
        fig.delaxes(ax)
    fig.legend(handles=handles, loc="outside lower center", ncols=3, fontsize=8)
    _suptitle(fig, title)
    return save_figure(root, path)


# --- per-step series -------------------------------------------------------------------------

# a run's dataset (brakeca.results.RunResult.dataset) names its per-step series step_*; they
# come first, since it also holds per-stop variables (mean_cof, normal_force) of other names
_COF_NAMES = ("step_cof", "cof", "mu", "mean_cof", "friction_coefficient", "COF", "MU")
_FORCE_NAMES = ("step_normal_force", "normal_force", "force", "FN", "F_N")
_TIME_NAMES = ("step_time", "time", "t")


def _column(source: Any, names: Sequence[str]) -> tuple[str, np.ndarray] | None:
    keys = list(source.keys()) if hasattr(source, "keys") else []
    if hasattr(source, "coords"):
        keys += list(source.coords)
    for name in names:
        if name in keys:
            return name, np.asarray(source[name]).ravel()
    return None


def plot_cof_series(
    steps_ds: Any,
    path: str | Path | None = None,
    *,
    max_points: int = 20000,
    fig: Figure | SubFigure | None = None,
) -> Figure:
    """Per-step series of the coefficient of friction and normal force, thinned for plotting.

    Parameters
    ----------
    steps_ds
        A run (:class:`~brakeca.results.RunResult` or its dataset, whose per-step series
        ``step_cof`` [-], ``step_normal_force`` [N] and ``step_time`` [s] are drawn), or an
        xarray Dataset, pandas DataFrame or mapping with a COF series (``cof``, ``mu`` or
        ``mean_cof``) [-], optionally ``normal_force`` [N] and ``time`` [s] (else the step
        index is used on x). A variable over stops or runs is refused.
    path
        Optional file to write: PNG at 150 dpi, or the format of its suffix (:func:`save_figure`).
    max_points
        At most this many points per series are drawn (regular stride).
    fig
        A Figure or SubFigure to draw the panels into (e.g. one of ``fig.subfigures(1, 2)``,
        to set this figure beside another); a new figure by default. The figure returned, and
        written to ``path``, is the one that holds it all.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes (COF, normal force) sharing x, or one when there is no normal force.

    References
    ----------
    Wahlström (2016), Section 3 (brake cycle), doi:10.1155/2016/8181260.
    """
    steps_ds = getattr(steps_ds, "dataset", steps_ds)  # a RunResult: its dataset
    cof = _column(steps_ds, _COF_NAMES)
    if cof is None:
        raise KeyError(f"no COF series found (looked for {', '.join(_COF_NAMES)})")
    dims = getattr(steps_ds[cof[0]], "dims", ())
    if "stop" in dims or "run" in dims:
        raise ValueError(
            f"{cof[0]!r} is a series over {', '.join(map(str, dims))}, not over steps: pass a "
            "run's dataset (its per-step series are step_cof, step_normal_force and step_time), "
            "or plot the per-stop means with plot_mu_per_stop"
        )
    force = _column(steps_ds, _FORCE_NAMES)
    time = _column(steps_ds, _TIME_NAMES)
    n = cof[1].size
    stride = max(1, math.ceil(n / max(int(max_points), 1)))
    if time is not None and time[1].size == n:
        x, xlabel = time[1].astype(float), "Time [s]"
        if time[0] == "step_time":  # a run's: the stops' braking times end to end
            xlabel = "Braking time [s] (the stops end to end)"
    else:
        x, xlabel = np.arange(n, dtype=float), "Step index [-]"
    # a run keeps every output.series_every-th step of its n_steps_total (results.py)
    total = getattr(steps_ds, "attrs", {}).get("n_steps_total")
    kept = 1
    if "step" in getattr(steps_ds, "coords", ()) and np.asarray(steps_ds["step"]).size >= 2:
        index = np.asarray(steps_ds["step"])
        kept = max(int(index[1] - index[0]), 1)
    every = stride * kept
    of = f"{int(total):,} steps" if total else f"{n * kept:,} steps"
    title = (
        f"Per-step series (one step in {every:,} of the run's {of})"
        if every > 1
        else (f"Per-step series ({of})")
    )

    root, fig = _panels(fig, (10.0, 5.5 if force is not None else 3.4))
    axes = fig.subplots(2 if force is not None else 1, 1, sharex=True, squeeze=False)[:, 0]
    xs = x[::stride]
    ys = [cof[1][::stride].astype(float)] + (
        [force[1][::stride].astype(float)] if force is not None else []
    )
    stop = _column(steps_ds, ("step_stop",))
    starts: np.ndarray = np.zeros(0)
    if stop is not None and stop[1].size == n:  # a run's: no line across a stop's end
        cut = np.flatnonzero(np.diff(stop[1][::stride]) != 0) + 1
        starts = xs[cut]
        xs = np.insert(xs.astype(float), cut, np.nan)
        ys = [np.insert(y, cut, np.nan) for y in ys]
    axes[0].plot(xs, ys[0], lw=0.7, color="#27496d")
    axes[0].set_ylabel("Coefficient of friction μ [-]")
    axes[0].set_title(title)
    axes[0].grid(True, alpha=0.3)
    if force is not None:
        axes[1].plot(xs, ys[1], lw=0.7, color="#f28e2b")
        pad = force[0] == "step_normal_force"  # a run's: the pad's force (results.py)
        axes[1].set_ylabel("Pad normal force [N]" if pad else "Normal force [N]")
        axes[1].grid(True, alpha=0.3)
    if 0 < starts.size <= 40:  # each stop's start, where they can still be told apart
        for ax in axes:
            for at in starts:
                ax.axvline(at, color="0.8", lw=0.5, zorder=0)
    axes[-1].set_xlabel(xlabel)
    return save_figure(root, path)


def plot_trace(
    trace: SpeedTrace,
    events: Sequence[BrakingEvent],
    *,
    path: str | Path | None = None,
    title: str | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Speed over time with the braking events shaded and numbered (``brakeca cycle inspect``).

    Parameters
    ----------
    trace
        The speed trace.
    events
        Its braking events (:func:`brakeca.traces.detect_events`).
    path
        File to write (:func:`save_figure`: PNG at :data:`DPI`, or the format of its
        suffix), or None.
    title
        Figure title (default: the trace name and the number of events).
    ax
        Axes to draw on, in a figure of one's own (a subplot of a grid); by default a new
        figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (``ax``'s, when given): time [s], or [min] for a trace over an hour,
        against speed [km/h].
    """
    from matplotlib.collections import PolyCollection

    from brakeca.cycle import KMH

    minutes = trace.duration > 3600.0
    scale = 60.0 if minutes else 1.0
    fig, ax = _axes(ax, (10.0, 3.8))
    ax.plot(trace.time / scale, trace.speed / KMH, color="#27496d", lw=1.0, label="speed")
    top = float(trace.speed.max() / KMH) if trace.speed.size else 0.0
    if events:  # one collection of spans, the axes' height each: a long cycle's 200,000
        # events as separate patches took minutes and gigabytes to draw
        spans = [
            [(x0, 0.0), (x0, 1.0), (x1, 1.0), (x1, 0.0)]
            for x0, x1 in ((e.start_time / scale, e.end_time / scale) for e in events)
        ]
        ax.add_collection(
            PolyCollection(
                spans,
                transform=ax.get_xaxis_transform(),
                facecolors="#f28e2b",
                alpha=0.35,
                linewidths=0,
                label="braking event",
            ),
            autolim=False,
        )
    for e in events if len(events) <= 40 else ():  # numbered while they can be read
        ax.annotate(
            str(e.index),
            ((e.start_time + e.end_time) / 2.0 / scale, e.initial_speed / KMH),
            xytext=(0, 4),
            textcoords="offset points",
            ha="center",
            fontsize=7,
        )
    ax.set_xlabel("time [min]" if minutes else "time [s]")
    ax.set_ylabel("speed [km/h]")
    ax.set_ylim(0.0, max(top * 1.12, 1.0))
    ax.set_xlim(trace.time[0] / scale, trace.time[-1] / scale)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title or f"{trace.name}: {len(events)} braking events", fontsize=10)
    return save_figure(fig, path)
