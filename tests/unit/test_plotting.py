"""Smoke tests of brakeca.plotting: every figure renders to a non-empty PNG.

References
----------
Wahlström (2016), doi:10.1155/2016/8181260, Figures 5 to 11.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from brakeca.analysis import Factor, ok_runs, ranked_effects, residuals
from brakeca.plotting import (
    plot_box_cox,
    plot_cof_series,
    plot_fibre_maps,
    plot_interactions,
    plot_main_effects,
    plot_mu_per_stop,
    plot_pareto,
    plot_residuals,
    plot_surface_map,
    plot_v_per_run,
)

PNG = b"\x89PNG\r\n\x1a\n"

FACTORS = (
    Factor("S", (0.0, 1.0), "-", "Secondary plateaus removed", ("-", "+")),
    Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", "Specific wear rate", ("-", "0", "+")),
    Factor("WR", (1e-7, 1e-6), "m", "Resin wear depth", ("-", "+")),
    Factor("A", (10.0, 20.0), "%", "Metal fibre area fraction", ("-", "+")),
)
BLOCKS = (("Burnish", 6), ("Town #1", 4), ("Highway #1", 3), ("Hill descent", 2))


@pytest.fixture(scope="module")
def summary() -> pd.DataFrame:
    rng = np.random.default_rng(3)
    rows = []
    levels = [f.levels for f in FACTORS]
    for test, (a, wr, wp, s) in enumerate(
        itertools.product(levels[3], levels[2], levels[1], levels[0]), start=1
    ):
        v = 1e-10 * (1 + np.log10(wp / 1e-15)) * (1 + 0.1 * rng.random())
        rows.append(
            {
                "test": test,
                "run_id": f"t{test:02d}",
                "S": s,
                "WP": wp,
                "WR": wr,
                "A": a,
                "seed": test,
                "MU": 0.4 + 0.02 * s + 0.001 * a + 0.005 * rng.standard_normal(),
                "V": v,
                "V_mm3": v * 1e9,
                "status": "ok",
            }
        )
    frame = pd.DataFrame(rows)
    frame.loc[5, "status"] = "failed"
    return frame


@pytest.fixture(scope="module")
def campaign(summary: pd.DataFrame) -> xr.Dataset:
    names = [name for name, n in BLOCKS for _ in range(n)]
    n_run, n_stop = len(summary), len(names)
    rng = np.random.default_rng(4)
    cof = 0.4 + 0.01 * np.cumsum(rng.standard_normal((n_run, n_stop)), axis=1) / n_stop
    coords = {
        "run": summary["test"].to_numpy(),
        "stop": np.arange(1, n_stop + 1),
        "block": ("stop", names),
    }
    coords.update({f.name: ("run", summary[f.name].to_numpy()) for f in FACTORS})
    return xr.Dataset(
        {
            "mean_cof": (("run", "stop"), cof),
            "emitted_volume": (("run", "stop"), np.full((n_run, n_stop), 1e-10)),
        },
        coords=coords,
    )


def _status_map(n_r: int = 201, n_a: int = 1000, fraction: float = 0.1, seed: int = 0):
    rng = np.random.default_rng(seed)
    status = (rng.random((n_r, n_a)) < fraction).astype(np.int8)
    status[rng.random((n_r, n_a)) < 0.05] = 2
    radius = np.linspace(0.103, 0.123, n_r)
    angle = np.radians(np.linspace(-22.0, 22.0, n_a))
    return status, radius, angle


def _check_png(path, fig, n_axes: int) -> None:
    data = path.read_bytes()
    assert data.startswith(PNG) and len(data) > 1000
    assert len(fig.axes) == n_axes
    for ax in fig.axes:  # a panel is labelled; a cell without axes holds a legend
        assert (
            ax.get_xlabel()
            or ax.get_ylabel()
            or ax.get_title()
            or (not ax.axison and ax.get_legend() is not None)
        )


def test_main_effects_and_interactions(tmp_path, summary) -> None:
    for response in ("MU", "V"):
        path = tmp_path / f"main_{response}.png"
        fig = plot_main_effects(summary, FACTORS, response, path=path)
        _check_png(path, fig, n_axes=4)
        # The V panel shows mm^3: the plotted means are the m^3 means times 1e9.
        if response == "V":
            assert "mm³" in fig.axes[0].get_ylabel()
            ok = summary[summary["status"] == "ok"]
            y = fig.axes[0].lines[0].get_ydata()
            expected = ok.groupby("S")["V"].mean().to_numpy() * 1e9
            assert np.allclose(y, expected, rtol=1e-12)
            grand = fig.axes[0].lines[1].get_ydata()[0]
            assert grand == pytest.approx(ok["V"].mean() * 1e9)
    path = tmp_path / "interactions.png"
    fig = plot_interactions(summary, FACTORS, "MU", path=path)
    _check_png(path, fig, n_axes=8)  # one panel per pair of 4 factors, 2 legend cells
    # each row's legend names its line factor; below the first row it stands in the empty
    # cell left of the row, off the lines (a review: one legend over a panel's lines, the
    # colours of the row's other panels unnamed)
    titles = [ax.get_legend().get_title().get_text() for ax in fig.axes if ax.get_legend()]
    assert titles == ["lines: S", "lines: WP", "lines: WR"]
    assert [ax.axison for ax in fig.axes if ax.get_legend()] == [True, False, False]
    fig = plot_interactions(summary, FACTORS[:2], "V")
    assert len(fig.axes) == 1
    with pytest.raises(ValueError):
        plot_interactions(summary, FACTORS[:1], "MU")


def test_mu_per_stop_v_per_run_and_pareto(tmp_path, summary, campaign) -> None:
    path = tmp_path / "mu_per_stop.png"
    fig = plot_mu_per_stop(campaign, path=path, factors=FACTORS)
    _check_png(path, fig, n_axes=1)
    ax = fig.axes[0]
    assert len(ax.lines) == len(summary) + len(BLOCKS) - 1  # runs + block boundaries
    texts = {t.get_text() for t in ax.texts}
    assert {name for name, _ in BLOCKS} <= texts
    labels = [line.get_label() for line in ax.lines if not line.get_label().startswith("_")]
    assert labels[0] == "T1: S-, WP-, WR-, A-"
    assert labels[-1] == "T24: S+, WP+, WR+, A+"
    two_stops = campaign.isel(stop=slice(0, 2))
    ticks = plot_mu_per_stop(two_stops, factors=FACTORS).axes[0].get_xticks()
    assert np.all(ticks == np.round(ticks))  # stop numbers are whole: no tick at stop 1.25
    # A replicated campaign: runs numbered 1..2n, tests from the coordinate; one colour and
    # one legend entry per test.
    twice = xr.concat([campaign, campaign], dim="run")
    twice = twice.assign_coords(
        run=np.arange(1, 2 * len(summary) + 1), test=("run", np.tile(summary["test"], 2))
    )
    fig = plot_mu_per_stop(twice, factors=FACTORS)
    ax = fig.axes[0]
    runs = [line for line in ax.lines if np.size(line.get_xdata()) == len(campaign["stop"])]
    assert len(runs) == 2 * len(summary)
    labels = [line.get_label() for line in runs if not line.get_label().startswith("_")]
    assert labels[0] == "T1: S-, WP-, WR-, A-" and labels[-1] == "T24: S+, WP+, WR+, A+"
    assert len(labels) == len(summary)
    assert runs[0].get_color() == runs[len(summary)].get_color()
    assert runs[0].get_color() != runs[1].get_color()
    assert "replicates" in ax.get_title()
    # Without factors the runs are named by value, and no block coordinate is fine.
    fig = plot_mu_per_stop(campaign.drop_vars("block"))
    assert fig.axes[0].lines[0].get_label().startswith("T1: S=0, WP=1e-15")
    # More tests than a legend holds (a review of large designs: 150 tests, 82 named, every
    # 40th alike): each run grey, their mean, the highest and lowest named
    from brakeca.plotting import MOST_TESTS_NAMED

    many = xr.concat([campaign] * 2, dim="run")
    many = many.assign_coords(run=np.arange(1, 49), test=("run", np.arange(1, 49)))
    assert 48 > MOST_TESTS_NAMED
    ax = plot_mu_per_stop(many, factors=FACTORS).axes[0]
    named = [line.get_label() for line in ax.get_legend().get_lines()]
    values = many["mean_cof"].transpose("run", "stop").to_numpy()
    top = int(np.argmax(values.mean(axis=1))) + 1  # the test (run numbers from 1)
    assert named[0] == "mean of the 48 runs" and len(named) == 3
    assert named[1].startswith(f"highest over the cycle: T{top}: ")
    assert named[2].startswith("lowest over the cycle: T")
    from matplotlib.collections import LineCollection

    (grey,) = [c for c in ax.collections if isinstance(c, LineCollection)]  # (one: the
    # legend's best place then avoids the named lines only; a diff review)
    assert len(grey.get_segments()) == 48 and "(48 tests: each run grey)" in ax.get_title()
    (mean,) = [line for line in ax.lines if line.get_label() == "mean of the 48 runs"]
    np.testing.assert_allclose(mean.get_ydata(), values.mean(axis=0), rtol=1e-12)
    # the finished runs alone make the mean and the extremes (a diff review: a run that
    # failed early was "highest" on its first stops, and was counted in the mean); a run
    # of a shorter cycle is finished, and counts over the stops it made
    stopped = many.copy(deep=True)
    early = np.r_[[1.0] * 3, [np.nan] * (stopped.sizes["stop"] - 3)]
    stopped["mean_cof"][dict(run=top - 1)] = early
    status = np.array(["ok"] * 48, dtype=object)
    status[top - 1] = "failed"
    stopped = stopped.assign_coords(status=("run", status))
    ax = plot_mu_per_stop(stopped, factors=FACTORS).axes[0]
    named = [line.get_label() for line in ax.get_legend().get_lines()]
    assert named[0] == "mean of the 47 finished runs"
    assert not named[1].startswith(f"highest over the cycle: T{top}: ")
    shorter = stopped.assign_coords(status=("run", np.array(["ok"] * 48, dtype=object)))
    ax = plot_mu_per_stop(shorter, factors=FACTORS).axes[0]
    named = [line.get_label() for line in ax.get_legend().get_lines()]
    assert named[0] == "mean of the 48 runs"
    assert named[1].startswith(f"highest over the cycle: T{top}: ")  # its mean COF of 1

    path = tmp_path / "v_per_run.png"
    fig = plot_v_per_run(summary, path=path)
    _check_png(path, fig, n_axes=1)
    heights = [p.get_height() for p in fig.axes[0].patches]
    assert len(heights) == 24
    assert heights[0] == pytest.approx(summary["V"].iloc[0] * 1e9)
    assert heights[5] == 0.0  # failed run
    assert any(t.get_text() == "failed" for t in fig.axes[0].texts)
    replicated = pd.concat([summary, summary.assign(seed=summary["seed"] + 100)])
    fig = plot_v_per_run(replicated)
    assert len(fig.axes[0].patches) == 24
    assert "replicates" in fig.axes[0].get_title()
    assert "replicates" not in plot_v_per_run(summary).axes[0].get_title()
    # a log axis where the tests' V span more than two decades (the smallest bars had looked
    # empty; a helper's review), else linear; either can be asked for
    spread = ok_runs(summary)["V"]
    expected = "log" if spread.max() > 100 * spread.min() else "linear"
    assert plot_v_per_run(summary).axes[0].get_yscale() == expected
    wide = summary.assign(V=summary["V"] * np.where(summary["test"] % 2 == 0, 1e3, 1.0))
    assert plot_v_per_run(wide).axes[0].get_yscale() == "log"
    points = plot_v_per_run(wide).axes[0]
    assert not points.patches and len(points.lines[0].get_ydata()) == 24  # points, no bars
    assert "log scale" in plot_v_per_run(wide).axes[0].get_ylabel()
    assert plot_v_per_run(wide, log=False).axes[0].get_yscale() == "linear"
    assert plot_v_per_run(summary, log=True).axes[0].get_yscale() == "log"

    path = tmp_path / "pareto.png"
    ranked = ranked_effects(summary, FACTORS, "MU")
    fig = plot_pareto(ranked, "MU", path=path)
    _check_png(path, fig, n_axes=2)  # bars + cumulative twin axis
    assert len(fig.axes[0].patches) == len(ranked)
    # each bar's share over it, starred where p < 0.05 (a figures review: a significant
    # bar of 0.3 % showed no colour)
    order = ranked.sort_values("percent_contribution", ascending=False, kind="stable")
    shown = [t.get_text() for t in fig.axes[0].texts]
    assert shown == [
        f"{v:.2g}" + ("*" if p < 0.05 else "")
        for v, p in zip(order["percent_contribution"], order["p_value"], strict=True)
    ]


def test_residual_plots(tmp_path, summary) -> None:
    res = residuals(summary, FACTORS, "V")
    path = tmp_path / "residuals_V.png"
    fig = plot_residuals(res, "V", path=path)
    _check_png(path, fig, n_axes=4)
    norm, fits, hist, order = fig.axes
    points = norm.lines[0]
    assert np.allclose(np.sort(points.get_xdata()), np.sort(res["std_residual"]))
    quantiles = np.asarray(points.get_ydata())
    assert np.all(np.diff(quantiles) > 0) and quantiles[0] == pytest.approx(-quantiles[-1])
    assert len(norm.lines) == 2  # the points and the reference line
    assert np.allclose(fits.lines[0].get_xdata(), res["fitted"] * 1e9)  # V in mm^3
    assert sum(p.get_height() for p in hist.patches) == len(res)
    assert "order" in order.get_xlabel().lower() or "test" in order.get_xlabel().lower()
    # the runs beyond +-2 are named in the panels against the fits and the order, as
    # Minitab marks them (a figures review: the paper study's outlier was an unnamed point)
    named = {t.get_text() for t in fits.texts}
    assert named == {t.get_text() for t in order.texts}
    assert "replicate" not in res.columns  # one run a test: named by its test
    unusual = res.loc[res["std_residual"].abs() > 2, "test"]
    assert named == {f"test {int(t)}" for t in unusual}
    big = res.assign(std_residual=np.where(np.arange(len(res)) == 3, 3.5, 0.1))
    assert [t.get_text() for t in plot_residuals(big, "V").axes[1].texts] == [
        f"test {int(big['test'].iloc[3])}"
    ]
    twice = big.assign(replicate=np.arange(len(big)) % 2)
    assert [t.get_text() for t in plot_residuals(twice, "V").axes[1].texts] == [
        f"test {int(big['test'].iloc[3])}/1"
    ]
    # A saturated model has no standardized residuals: raw ones, and a note.
    one = summary[(summary["S"] == 0.0) & (summary["status"] == "ok")].drop_duplicates("WP")
    saturated = residuals(one, [f for f in FACTORS if f.name == "WP"], "MU")
    fig = plot_residuals(saturated, "MU")
    assert "Residual (" in fig.axes[0].get_xlabel()
    assert any("raw residuals" in t.get_text() for t in fig.axes[0].texts)


def test_box_cox_plots(tmp_path) -> None:
    """A panel per response: the profile, the interval shaded, λ̂ and the lines at 0 and 1;
    a response without λ gets a panel saying why."""
    from brakeca.boxcox import box_cox_profile

    rng = np.random.default_rng(2)
    good = box_cox_profile(rng.lognormal(0.0, 0.5, 30), response="V")
    bad = box_cox_profile([1.0, -2.0, 3.0], response="MU")
    path = tmp_path / "box_cox.png"
    fig = plot_box_cox({"V": good, "MU": bad}, path=path)
    _check_png(path, fig, n_axes=2)
    v_ax, mu_ax = fig.axes
    curve = v_ax.lines[0]
    assert np.allclose(curve.get_ydata(), good.profile["log_likelihood"])
    assert any(np.allclose(line.get_xdata(), good.lambda_hat) for line in v_ax.lines[1:])
    assert len(v_ax.patches) == 1  # the interval
    assert any("needs positive values" in t.get_text() for t in mu_ax.texts)
    # a long reason is wrapped inside its panel (one residual df's ran across all three)
    one_df = box_cox_profile([1.0, 2.0, 5.0], np.column_stack([np.ones(3), np.arange(3.0)]))
    fig = plot_box_cox({"V": good, "MU": one_df})
    (text,) = fig.axes[1].texts
    assert "one residual degree" in text.get_text()
    assert max(len(line) for line in text.get_text().split("\n")) <= 38
    # λ̂ on the search range's edge is said to be a bound (a figures review read "λ̂ =
    # -2.00" beside an interval open to -inf), its line inside the panel; the panel zooms
    # to the top of a profile falling far below it
    y = np.exp(np.exp(np.log(np.random.default_rng(5).lognormal(3.0, 0.02, 30)) / 4.0))
    edge = box_cox_profile(y, response="V")
    assert edge.edge != 0
    ax = plot_box_cox({"V": edge}).axes[0]
    labels = ax.get_legend_handles_labels()[1]
    bound = "≤ -2" if edge.edge < 0 else "≥ 2"
    assert f"λ̂ {bound} (the search range's edge)" in labels
    low, high = ax.get_xlim()
    assert low < edge.lambda_hat < high
    steep = box_cox_profile(np.random.default_rng(2).lognormal(0.0, 2.0, 30), response="V")
    ll = steep.profile["log_likelihood"].to_numpy()
    bottom, top = plot_box_cox({"V": steep}).axes[0].get_ylim()
    assert ll.max() - ll.min() > 100.0  # the profile falls far
    assert ll.min() < bottom < ll.max() < top and ll.max() - bottom < 30.0


def test_names_of_points_do_not_overprint() -> None:
    """Two unusual runs at one place are named a line apart, with a leader to the moved one;
    a point near the axes' right edge is named on its left (its name had crossed the edge)."""
    import matplotlib.pyplot as plt

    from brakeca.plotting import _name_points

    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0.0, 0.5, 1.0, 1.0], [0.0, 1.0, 2.0, 2.02], "o")
    _name_points(ax, [0.5, 1.0, 1.0], [1.0, 2.0, 2.02], ["test 1", "test 7", "test 8"])
    offsets = {t.get_text(): t for t in ax.texts}
    assert offsets["test 1"].get_horizontalalignment() == "left"
    assert offsets["test 8"].get_horizontalalignment() == "right"  # in the right fifth
    assert offsets["test 8"].xyann[1] == 0.0 and offsets["test 7"].xyann[1] != 0.0
    assert offsets["test 7"].arrow_patch is not None and offsets["test 8"].arrow_patch is None
    fig.canvas.draw()
    from matplotlib.text import Text

    boxes = [Text.get_window_extent(t) for t in ax.texts]  # the names, not their leaders
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    plt.close(fig)
    # more names at one place than lines above and below it: joined, none printed over
    # another, none beyond the axes (a diff review: eight unusual runs had overprinted)
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0.0, 1.0], [0.0, 1.0], "o")
    names = [f"test {k}" for k in range(1, 13)]
    _name_points(ax, [0.5] * 12, [0.98] * 12, names)
    fig.canvas.draw()
    shown = ", ".join(t.get_text() for t in ax.texts)
    assert sorted(shown.split(", ")) == sorted(names)  # every name once
    assert any(", " in t.get_text() for t in ax.texts)  # some joined
    boxes = [Text.get_window_extent(t) for t in ax.texts]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    frame = ax.get_window_extent()
    assert all(frame.y0 <= b.y0 and b.y1 <= frame.y1 + 1 for b in boxes)
    plt.close(fig)
    # a point elsewhere whose name finds no room is not joined to another point's name
    # (a review: "test 10/1, test 11/0" stood at WP0, test 11 being at WP+)
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0.0, 1.0], [0.0, 1.0], "o")
    _name_points(ax, [0.5] * 12 + [0.42], [0.98] * 13, [*names, "test 99 elsewhere"])
    assert "test 99 elsewhere" in [t.get_text() for t in ax.texts]
    plt.close(fig)


def test_surface_maps(tmp_path) -> None:
    status, radius, angle = _status_map()
    path = tmp_path / "map.png"
    fig = plot_surface_map(status, radius, angle, title="Final plateau map, test 1", path=path)
    _check_png(path, fig, n_axes=1)
    ax = fig.axes[0]
    assert len(ax.images) == 1
    assert ax.images[0].get_extent()[0] == pytest.approx(-22.0, abs=0.1)
    assert "Radius [mm]" in ax.get_ylabel() and "sliding direction" in ax.get_xlabel()
    legend_text = " ".join(t.get_text() for t in fig.legends[0].get_texts())
    assert "primary plateau" in legend_text and "secondary plateau" in legend_text

    # Non-uniform, descending coordinates take the pcolormesh path.
    r = np.geomspace(0.123, 0.103, 20)
    a = np.radians(np.linspace(44.0, 0.0, 50))
    fig = plot_surface_map(np.zeros((20, 50), dtype=int), r, a)
    assert len(fig.axes[0].collections) == 1
    with pytest.raises(ValueError, match="shape"):
        plot_surface_map(status, radius[:-1], angle)
    with pytest.raises(ValueError, match="status codes"):
        plot_surface_map(np.full((2, 3), 3), radius[:2], angle[:3])
    # radii in mm drew an axis of 113200 mm (an API review); degrees likewise
    with pytest.raises(ValueError, match=r"^radius: the cells' radii in m .* in mm, give radius"):
        plot_surface_map(status, radius * 1000, angle)
    with pytest.raises(ValueError, match=r"^angle: .* give numpy.radians\(angle\)"):
        plot_surface_map(status, radius, np.degrees(angle))

    path = tmp_path / "fibre_maps.png"
    maps = {
        "A- (10 %)": _status_map(fraction=0.1, seed=1),
        "A+ (20 %)": _status_map(fraction=0.2, seed=2),
    }
    fig = plot_fibre_maps(maps, path=path)
    _check_png(path, fig, n_axes=2)
    # the area fractions are in the panels' titles, not over the maps
    assert fig.axes[0].get_title().startswith("A- (10 %) (primary ")
    assert all(not ax.texts for ax in fig.axes)
    fig = plot_fibre_maps({**maps, "third": _status_map(40, 80)}, ncols=2)
    assert len(fig.axes) == 3
    # five levels: three per row by default, not one row five maps wide
    five = {
        f"A = {a} %": _status_map(40, 80, fraction=a / 100, seed=a) for a in (5, 10, 15, 20, 30)
    }
    fig = plot_fibre_maps(five)
    rows = {round(ax.get_position().y0, 3) for ax in fig.axes}
    assert len(fig.axes) == 5 and len(rows) == 2
    # four: two by two, not three and one; the title is the caller's
    fig = plot_fibre_maps(dict(list(five.items())[:4]), title="Test 5: S = 0")
    rows = {round(ax.get_position().y0, 3) for ax in fig.axes}
    assert len(fig.axes) == 4 and len(rows) == 2
    assert len({round(ax.get_position().x0, 3) for ax in fig.axes}) == 2
    assert fig.get_suptitle() == "Test 5: S = 0"
    # to scale (the study's figure): a millimetre of radius as long on the page as one of arc
    # at the mean radius; filling the axes had stretched the paper's band's radius about 2.2
    # times (a figures review)
    fig = plot_fibre_maps(maps, true_scale=True)
    fig.canvas.draw()
    status, radius, angle = maps["A- (10 %)"]
    for ax in fig.axes:
        box = ax.get_window_extent()
        span_r = (radius[-1] - radius[0]) * len(radius) / (len(radius) - 1)
        span_arc = (angle[-1] - angle[0]) * len(angle) / (len(angle) - 1) * radius.mean()
        assert box.height / box.width == pytest.approx(span_r / span_arc, rel=0.02)
    assert len({round(ax.get_position().x0, 3) for ax in fig.axes}) == 1  # one per row
    # a single map too (the study's final maps), where the band stands tall enough to read
    from brakeca.plotting import fits_to_scale

    fig = plot_surface_map(status, radius, angle, "map", true_scale=True)
    fig.canvas.draw()
    box = fig.axes[0].get_window_extent()
    assert box.height / box.width == pytest.approx(span_r / span_arc, rel=0.02)
    assert fits_to_scale(radius, angle)  # 20 by 87 mm, as the paper's band
    quick = np.linspace(0.112, 0.114, 21)  # the quick band's 2 mm: a strip, not to scale
    assert not fits_to_scale(quick, angle)


def test_cof_series(tmp_path) -> None:
    n = 50_000
    t = np.linspace(0.0, 120.0, n)
    steps = xr.Dataset(
        {"cof": ("step", 0.4 + 0.01 * np.sin(t)), "normal_force": ("step", 3000 + 10 * t)},
        coords={"time": ("step", t)},
    )
    path = tmp_path / "series.png"
    fig = plot_cof_series(steps, path=path, max_points=5000)
    _check_png(path, fig, n_axes=2)
    assert len(fig.axes[0].lines[0].get_xdata()) <= 5000
    assert fig.axes[1].get_xlabel() == "Time [s]"
    fig = plot_cof_series(pd.DataFrame({"mu": [0.4, 0.41, 0.42]}))
    assert len(fig.axes) == 1 and fig.axes[0].get_xlabel() == "Step index [-]"
    with pytest.raises(KeyError):
        plot_cof_series({"x": [1, 2]})


def test_no_pyplot_state_is_left_behind(summary) -> None:
    import matplotlib.pyplot as plt

    before = plt.get_fignums()
    plot_main_effects(summary, FACTORS, "MU")
    assert plt.get_fignums() == before


@pytest.mark.parametrize("n_factors", [1, 2, 4])
def test_titles_fit_in_their_figures(summary, n_factors) -> None:
    """A one-panel interaction plot (two factors) is 4.2 inches wide: its one-line title was
    cut at both edges."""
    factors = FACTORS[:n_factors]
    figures = [plot_main_effects(summary, factors, "MU"), plot_main_effects(summary, factors, "V")]
    if n_factors > 1:
        figures += [plot_interactions(summary, factors, r) for r in ("MU", "V")]
    for fig in figures:
        fig.canvas.draw()
        title = fig._suptitle.get_window_extent()
        assert 0 <= title.x0 and title.x1 <= fig.bbox.width, fig._suptitle.get_text()
        assert title.y1 <= fig.bbox.height


def test_effects_plot(tmp_path) -> None:
    from brakeca.analysis import two_level_effects
    from brakeca.plotting import plot_effects

    rng = np.random.default_rng(4)
    rows = []
    for c, b, a in itertools.product((0.0, 1.0), repeat=3):
        rows.append({"A": a, "B": b, "C": c, "MU": 0.3 + 0.1 * a + 0.01 * rng.standard_normal()})
    factors = [Factor(n, (0.0, 1.0)) for n in "ABC"]
    effects = two_level_effects(pd.DataFrame(rows), factors, "MU")
    fig = plot_effects(effects, "MU", tmp_path / "effects.png")
    assert (tmp_path / "effects.png").read_bytes().startswith(PNG)
    pareto, half = fig.axes
    top = max(pareto.get_yticklabels(), key=lambda t: t.get_position()[1])
    assert top.get_text() == "A"  # the largest effect at the top
    assert half.get_xlabel().startswith("Absolute effect")
    empty = plot_effects(effects.iloc[:0], "MU", tmp_path / "none.png")
    assert "no effects" in empty.axes[0].texts[0].get_text()


def test_response_surface_contours(tmp_path) -> None:
    """One panel per pair of factors on the factors' own (log) scales, V in mm³, the runs
    and the stationary point drawn; a single factor gets the fitted curve."""
    from brakeca.plotting import plot_response_surface
    from brakeca.rsm import Coding, fit_response_surface

    codings = [
        Coding("WP", 1e-15, 1e-13, log=True, unit="m^3/(N m)"),
        Coding("A", 10.0, 20.0, unit="%"),
        Coding("WR", 1e-7, 1e-6, log=True, unit="m"),
    ]
    points = [p for p in itertools.product((-1.0, 0.0, 1.0), repeat=3)]
    rows = []
    for x in points:
        v = (3.0 - (x[0] - 0.2) ** 2 - 0.5 * (x[1] + 0.1) ** 2 - 0.3 * x[2] ** 2) * 1e-9
        rows.append({c.name: c.decode(xi) for c, xi in zip(codings, x, strict=True)} | {"V": v})
    fit = fit_response_surface(pd.DataFrame(rows), codings, "V")
    assert fit.stationary is not None and fit.stationary["kind"] == "maximum"
    fig = plot_response_surface(fit, tmp_path / "surface.png")
    assert (tmp_path / "surface.png").read_bytes().startswith(PNG)
    panels = [ax for ax in fig.axes if ax.get_xlabel() and ax.get_visible()]
    assert [(ax.get_xlabel(), ax.get_ylabel()) for ax in panels] == [
        ("WP [m³/(N·m)]", "A [%]"),
        ("WP [m³/(N·m)]", "WR [µm]"),
        ("A [%]", "WR [µm]"),
    ]
    # the runs drawn in the axis's unit: WR's 1e-07 to 1e-06 m as 0.1 to 1 µm
    runs = [line for line in panels[2].lines if line.get_label() == "runs (projected)"]
    assert sorted(set(np.round(runs[0].get_ydata(), 12))) == [0.1, 0.316227766017, 1.0]
    fig.canvas.draw()  # its log axis labelled in plain numbers ("2×10⁻¹" had read oddly)
    low, high = panels[2].get_ylim()
    labels = {
        t.get_text()
        for minor in (False, True)
        for t in panels[2].get_yticklabels(minor=minor)
        if low * (1 - 1e-9) <= t.get_position()[1] <= high * (1 + 1e-9) and t.get_text()
    }
    assert {"0.1", "0.2", "1"} <= labels and not any("10" in x for x in labels), labels
    assert panels[0].get_xticklabels()[1].get_text().startswith("$\\mathdefault{10^{")  # WP
    assert panels[0].get_xscale() == "log" and panels[2].get_yscale() == "log"
    assert panels[2].get_xscale() == "linear"
    labels = panels[0].get_legend_handles_labels()[1]
    assert labels == ["runs (projected)", "stationary point (maximum, projected)"]
    one = fit_response_surface(pd.DataFrame(rows), codings[:1], "V")
    curve = plot_response_surface(one, tmp_path / "one.png").axes[0]
    fitted = curve.lines[0].get_ydata()
    assert curve.get_xscale() == "log" and max(fitted) == pytest.approx(
        max(one.predict_coded({"WP": np.linspace(-1, 1, 81)})) * 1e9
    )


def test_overlaid_contours_shade_where_a_goal_is_missed(tmp_path) -> None:
    from brakeca.plotting import plot_overlaid_contours
    from brakeca.rsm import Coding, Goal, fit_response_surface, optimize

    codings = [Coding("p", -1.0, 1.0), Coding("q", 1.0, 100.0, log=True, unit="m")]
    rows = []
    for x, y in itertools.product((-1.0, 0.0, 1.0), repeat=2):
        rows.append({"p": x, "q": codings[1].decode(y), "V": (2 + x + 0.5 * y) * 1e-9,
                     "MU": 0.3 + 0.05 * y - 0.02 * x * x})  # fmt: skip
    data = pd.DataFrame(rows)
    fits = {r: fit_response_surface(data, codings, r) for r in ("V", "MU")}
    goals = [Goal("V", "minimize", 1e-9, 2e-9), Goal("MU", "maximize", 0.3, 0.35)]
    best = optimize(fits, goals)
    fig = plot_overlaid_contours(fits, goals, best, tmp_path / "ov.png")
    assert (tmp_path / "ov.png").read_bytes().startswith(PNG)
    ax = fig.axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_yscale()) == ("p", "q [m]", "log")
    assert "V ≤ 2 mm³, MU ≥ 0.3" in fig._suptitle.get_text()
    star = next(line for line in ax.lines if line.get_label() == "optimum")
    assert tuple(star.get_xydata()[0]) == pytest.approx((best.levels["p"], best.levels["q"]))
    one = plot_overlaid_contours(
        {"V": fits["V"]}, goals[:1], optimize({"V": fits["V"]}, goals[:1]), None
    )
    assert len([ax for ax in one.axes if ax.get_visible()]) == 1


def test_interaction_panels_of_a_fraction_name_their_aliases(summary) -> None:
    from brakeca.plotting import plot_interactions

    fig = plot_interactions(summary, FACTORS, "MU", aliases={("WR", "A"): "-S:WP"})
    titled = [ax for ax in fig.axes if ax.get_title()]
    assert [(ax.get_title(), ax.get_xlabel()) for ax in titled] == [("= -S:WP", "A [%]")]
    assert not any(ax.get_title() for ax in plot_interactions(summary, FACTORS, "MU").axes)


def test_cof_series_of_a_run_draws_its_steps_not_its_stops() -> None:
    """A run's dataset holds per-stop means (mean_cof, normal_force over ``stop``) beside its
    per-step series (step_*): the steps are drawn, against time. A series over stops alone is
    refused (it had been drawn and labelled as steps; a helper's API review)."""
    import types

    n, stops = 300, 4
    run = xr.Dataset(
        {
            "step_cof": ("step", np.full(n, 0.4)),
            "step_normal_force": ("step", np.full(n, 2500.0)),
            "step_time": ("step", np.linspace(0.0, 30.0, n)),
            "mean_cof": ("stop", np.full(stops, 0.3)),
            "normal_force": ("stop", np.full(stops, 9.0)),
        }
    )
    for source in (run, types.SimpleNamespace(dataset=run)):  # a RunResult has .dataset
        fig = plot_cof_series(source)
        assert len(fig.axes[0].lines[0].get_ydata()) == n
        assert set(fig.axes[1].lines[0].get_ydata()) == {2500.0}
        assert fig.axes[-1].get_xlabel() == "Braking time [s] (the stops end to end)"
        assert fig.axes[0].get_title() == "Per-step series (300 steps)"
    # a run keeps one step in output.series_every: the title says so, of the run's steps
    # (it had read "9824 steps" for a run of 491,160)
    sampled = run.assign_coords(step=np.arange(n) * 50 + 1)
    sampled.attrs["n_steps_total"] = 15_000
    title = plot_cof_series(sampled, max_points=100).axes[0].get_title()
    assert title == "Per-step series (one step in 150 of the run's 15,000 steps)"
    with pytest.raises(ValueError, match="'mean_cof' is a series over stop, not over steps"):
        plot_cof_series(run[["mean_cof", "normal_force"]])


def test_mu_per_stop_takes_a_campaign_result_or_one_run(campaign) -> None:
    """A CampaignResult (its dataset and its design's factors) and a single run's dataset (no
    ``run`` dimension) are drawn; the first had raised AttributeError (a helper's review)."""
    import types

    result = types.SimpleNamespace(dataset=campaign, design=types.SimpleNamespace(factors=FACTORS))
    fig = plot_mu_per_stop(result)
    expected = plot_mu_per_stop(campaign, factors=FACTORS)
    assert [line.get_label() for line in fig.axes[0].lines] == [
        line.get_label() for line in expected.axes[0].lines
    ]
    one = campaign.isel(run=0, drop=True)[["mean_cof"]]
    assert "run" not in one.dims
    fig = plot_mu_per_stop(types.SimpleNamespace(dataset=one))  # a RunResult has .dataset
    runs = [line for line in fig.axes[0].lines if np.size(line.get_xdata()) == one.sizes["stop"]]
    assert len(runs) == 1
    np.testing.assert_array_equal(runs[0].get_ydata(), one["mean_cof"].to_numpy())
    with pytest.raises(TypeError, match="campaign: expected a CampaignResult"):
        plot_mu_per_stop(0.4)
    with pytest.raises(TypeError, match="campaign: item 1 is a float, not a RunResult"):
        plot_mu_per_stop([0.4, 0.5])


def test_mu_per_stop_compares_runs_given_as_a_mapping_or_a_list(campaign) -> None:
    """Two runs to compare need no campaign (a helper writing the examples had concatenated
    their datasets by hand): a mapping labels them, a list by their seeds; a shorter run
    ends where it ends."""
    import types

    def run(k: int, stops: int) -> types.SimpleNamespace:  # what plotting reads of a RunResult
        ds = campaign.isel(run=k, drop=True).isel(stop=slice(0, stops))[["mean_cof"]]
        return types.SimpleNamespace(dataset=ds, seed=10 + k)

    a, b = run(0, campaign.sizes["stop"]), run(1, 5)
    fig = plot_mu_per_stop({"A = 10 %": a, "A = 20 %": b})
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["A = 10 %", "A = 20 %"]
    lines = [line for line in fig.axes[0].lines if line.get_label().startswith("A = ")]
    np.testing.assert_array_equal(lines[0].get_ydata(), a.dataset["mean_cof"].to_numpy())
    np.testing.assert_array_equal(lines[1].get_ydata()[:5], b.dataset["mean_cof"].to_numpy())
    assert np.isnan(lines[1].get_ydata()[5:]).all()
    fig = plot_mu_per_stop([a, b])
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["seed 10", "seed 11"]
    with pytest.raises(ValueError, match="two runs share a label"):
        plot_mu_per_stop([a, a])
    # one seed, two pads (an API review: refused as sharing a label): named by what differs
    from brakeca.presets import load_preset

    paper = load_preset()
    one = types.SimpleNamespace(dataset=a.dataset, seed=3, config=paper)
    other = types.SimpleNamespace(
        dataset=b.dataset, seed=3, config=paper.with_updates({"WP": 1e-13, "A": 10})
    )
    fig = plot_mu_per_stop([one, other])
    assert [t.get_text() for t in fig.legends[0].get_texts()] == [
        "WP = 1e-14 m³/(N·m), A = 20 %",
        "WP = 1e-13 m³/(N·m), A = 10 %",
    ]
    with pytest.raises(ValueError, match="two runs share a label"):  # nothing differs
        plot_mu_per_stop([one, types.SimpleNamespace(dataset=b.dataset, seed=3, config=paper)])
    with pytest.raises(ValueError, match="no runs to plot"):
        plot_mu_per_stop({})


def test_profiler_draws_the_fitted_surface_along_each_factor() -> None:
    """Each panel: the quadratic along one factor, the others at their centre, with the
    confidence band of the fitted mean around it (checked against the fit itself)."""
    from brakeca.analysis import Factor
    from brakeca.plotting import plot_profiler
    from brakeca.rsm import fit_response_surface

    rng = np.random.default_rng(5)
    a, b = np.meshgrid([-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0])
    a, b = np.r_[a.ravel(), 0.0, 0.0], np.r_[b.ravel(), 0.0, 0.0]
    y = 2.0 + 0.5 * a - 0.3 * b + 0.4 * a * a + 0.1 * a * b + rng.normal(0, 0.02, a.size)
    rows = pd.DataFrame({"P": 10 + 5 * a, "Q": 1 + 0.5 * b, "y": y, "status": "ok"})
    factors = [Factor("P", (5.0, 10.0, 15.0)), Factor("Q", (0.5, 1.0, 1.5))]
    fit = fit_response_surface(rows, factors, "y")
    fig = plot_profiler(fit)
    assert len(fig.axes) == 2
    line = fig.axes[0].lines[0]
    x, fitted = line.get_xdata(), line.get_ydata()
    np.testing.assert_allclose(x[[0, -1]], [5.0, 15.0])
    np.testing.assert_allclose(fitted, fit.predict({"P": x, "Q": np.ones_like(x)}), rtol=1e-12)
    band = fig.axes[0].collections[0].get_paths()[0].vertices[:, 1]
    low, high = fit.confidence_interval({"P": (x - 10) / 5, "Q": np.zeros_like(x)})
    assert band.min() == pytest.approx(low.min()) and band.max() == pytest.approx(high.max())


def test_mu_per_stop_tells_neighbouring_tests_apart(campaign) -> None:
    """A qualitative palette with the line style changing every ten tests (neighbouring
    tests had shared a rainbow hue), and the block names above the axes, off the lines (a
    helper's review of the report)."""
    fig = plot_mu_per_stop(campaign, factors=FACTORS)
    ax = fig.axes[0]
    runs = [line for line in ax.lines if np.size(line.get_xdata()) == len(campaign["stop"])]
    styles = [(line.get_color(), line.get_linestyle()) for line in runs]
    assert len(set(styles)) == len(runs) == 24  # every test its own colour and style
    assert all(a[0] != b[0] for a, b in itertools.pairwise(styles))  # neighbours' hues
    assert styles[0][0] == styles[10][0] and styles[0][1] != styles[10][1]
    assert ax.texts and all(t.get_position()[1] > 1.0 for t in ax.texts)


def test_mu_per_stop_title_clears_the_block_names(campaign) -> None:
    """The rotated block names above the axes had reached into the title (a helper's review)."""
    fig = plot_mu_per_stop(campaign, factors=FACTORS)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    title = ax.title.get_window_extent(renderer)
    assert ax.texts
    assert all(t.get_window_extent(renderer).y1 < title.y0 for t in ax.texts)


def test_run_labels_code_centre_points_as_0() -> None:
    """A centre point's legend entry had read 'S0.5, WP1e-14, mu00.6' (a helper's review):
    each labelled factor at its centre reads 0, and a name ending in a digit is spaced."""
    from brakeca.plotting import _run_label

    factors = {
        "S": Factor("S", (0.0, 1.0), labels=("-", "+")),
        "mu0": Factor("mu0", (0.5, 0.7), labels=("-", "+")),
        "WP": Factor("WP", (1e-15, 1e-13), labels=("-", "+"), coding="log"),
    }
    assert _run_label(17, {"S": 0.5, "mu0": 0.6, "WP": 1e-14}, factors) == "T17: S0, mu0 0, WP0"
    assert _run_label(1, {"S": 1.0, "mu0": 0.5, "WP": 1e-15}, factors) == "T1: S+, mu0 -, WP-"
    assert _run_label(2, {"S": 0.3, "mu0": 0.5, "WP": 1e-15}, factors) == "T2: S=0.3, mu0 -, WP-"


def test_mu_per_stop_by_level_draws_each_levels_mean_of_the_finished_runs() -> None:
    """The main effects over the cycle: each line the stop-by-stop mean of the runs at one
    level; a centre point (at no level) and a failed run (NaN) are left out."""
    from brakeca.plotting import plot_mu_per_stop_by_level

    stops = 5
    a = np.array([10.0, 20.0, 10.0, 20.0, 15.0, 10.0])
    s = np.array([0.0, 0.0, 1.0, 1.0, 0.5, 1.0])
    cof = np.outer(a / 100.0 + s, np.ones(stops)) + np.arange(stops) * 1e-3
    cof[5] = np.nan  # a failed run
    ds = xr.Dataset(
        {"mean_cof": (("run", "stop"), cof)},
        coords={
            "run": np.arange(1, 7),
            "stop": np.arange(1, stops + 1),
            "A": ("run", a),
            "S": ("run", s),
            "block": ("stop", ["B1"] * 2 + ["B2"] * 3),
        },
    )
    factors = [Factor("S", (0.0, 1.0), "-", "S", ("-", "+")), Factor("A", (10.0, 20.0), "%")]
    fig = plot_mu_per_stop_by_level(ds, factors)
    s_ax, a_ax = fig.axes[:2]
    low, high = (line.get_ydata() for line in s_ax.lines)
    np.testing.assert_allclose(low, cof[[0, 1]].mean(axis=0))
    np.testing.assert_allclose(high, cof[[2, 3]].mean(axis=0))  # not the failed run 6
    labels = [t.get_text() for t in s_ax.get_legend().get_texts()]
    assert labels == ["S- (0), 2 runs", "S+ (1), 2 runs"]
    np.testing.assert_allclose(a_ax.lines[0].get_ydata(), cof[[0, 2]].mean(axis=0))
    assert [t.get_text() for t in a_ax.get_legend().get_texts()][1] == "A = 20 %, 2 runs"
    # the levels told apart by line style as well as by colour (a figures review)
    assert [line.get_linestyle() for line in a_ax.lines] == ["-", "--"]
    with pytest.raises(ValueError, match="no factor of the campaign"):
        plot_mu_per_stop_by_level(ds, [Factor("X", (0.0, 1.0))])


def test_a_file_name_where_a_title_or_the_factors_go_is_named(campaign, tmp_path) -> None:
    """``plot_surface_map(status, radius, angle, "map.png")`` drew a figure titled "map.png"
    and wrote nothing; ``plot_mu_per_stop_by_level(campaign, "x.png")`` took the name's
    letters for factors (an API review)."""
    from brakeca.plotting import plot_mu_per_stop_by_level

    status, radius, angle = _status_map(n_r=5, n_a=20)
    with pytest.raises(TypeError, match=r"^title: 'map.png' reads like a file name; the file"):
        plot_surface_map(status, radius, angle, "map.png")
    with pytest.raises(TypeError, match=r"^title: .* reads like a file name"):
        plot_surface_map(status, radius, angle, tmp_path / "map.png")
    plot_surface_map(status, radius, angle, "Pad after stop 170", tmp_path / "map.png")
    assert (tmp_path / "map.png").is_file()
    with pytest.raises(TypeError, match=r"^factors: got 'x.png', not factors; the file to"):
        plot_mu_per_stop_by_level(campaign, "x.png")
    assert not (tmp_path / "x.png").exists()


def test_single_axes_figures_draw_into_a_users_grid(campaign, summary, tmp_path) -> None:
    """No figure took ``ax=``, so none could go into a notebook's subplot grid (an API
    review). The four single-axes figures do now: they draw on the axes given, keep their
    legend and title there, and ``path`` writes the user's whole figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    status, radius, angle = _status_map(n_r=5, n_a=40)
    ranked = pd.DataFrame(
        {
            "term": ["WP", "A", "S"],
            "percent_contribution": [60.0, 30.0, 10.0],
            "p_value": [0.001, 0.01, 0.4],
        }
    )
    got = [
        plot_mu_per_stop(campaign, factors=FACTORS, ax=axes[0, 0]),
        plot_v_per_run(summary, ax=axes[0, 1]),
        plot_pareto(ranked, "MU", ax=axes[1, 0]),
        plot_surface_map(status, radius, angle, "Pad", tmp_path / "grid.png", ax=axes[1, 1]),
    ]
    assert all(g is fig for g in got)
    assert len(fig.axes) >= 4 and (tmp_path / "grid.png").read_bytes().startswith(PNG)
    assert axes[0, 0].get_legend() is not None and axes[1, 1].get_title() == "Pad"
    assert axes[0, 1].patches or axes[0, 1].lines  # V's bars (or points) are on its axes
    with pytest.raises(TypeError, match=r"^ax: expected a matplotlib Axes, got str$"):
        plot_pareto(ranked, "MU", ax="left")  # type: ignore[arg-type]
    plt.close(fig)


def test_ax_in_a_figure_without_a_canvas_or_in_a_subfigure(campaign, tmp_path) -> None:
    """``plot_mu_per_stop(ax=...)`` asked the figure's canvas for its renderer, which a
    Figure made without pyplot has not (AttributeError), and an axes of a SubFigure gave
    back the SubFigure, which cannot be saved (a review of ax=)."""
    from matplotlib.figure import Figure

    plain = Figure()
    assert plot_mu_per_stop(campaign, factors=FACTORS, ax=plain.subplots()) is plain
    whole = Figure(figsize=(12, 4))
    left = whole.subfigures(1, 2)[0]
    path = tmp_path / "sub.png"
    assert plot_mu_per_stop(campaign, path, factors=FACTORS, ax=left.subplots()) is whole
    assert path.read_bytes().startswith(PNG)


def test_figures_of_several_panels_draw_into_a_figure_or_subfigure(
    campaign, summary, tmp_path
) -> None:
    """The figures of several panels took no figure of one's own, so two could not be set
    side by side (noted, not done, in the thirty-fifth session). Each takes ``fig=`` now: a
    Figure or a SubFigure, whose panels and title it draws there, and returns (and writes)
    the figure that holds it all."""
    import inspect

    from matplotlib.figure import Figure

    import brakeca.plotting as plotting

    several = {
        name
        for name, function in vars(plotting).items()
        if name.startswith("plot_") and callable(function)
        if "fig" in inspect.signature(function).parameters
    }
    one_panel = {
        "plot_mu_per_stop",
        "plot_mu_vs_v",
        "plot_v_per_run",
        "plot_pareto",
        "plot_surface_map",
        "plot_trace",
    }
    public = {name for name in plotting.__all__ if name.startswith("plot_")}
    assert several == public - one_panel  # every figure takes fig= or (one panel) ax=

    whole = Figure(figsize=(16, 6))  # no pyplot, no canvas of its own
    left, right = whole.subfigures(1, 2)
    path = tmp_path / "side_by_side.png"
    assert plotting.plot_main_effects(summary, FACTORS, "MU", fig=left) is whole
    got = plotting.plot_mu_per_stop_by_level(campaign, FACTORS, path, fig=right)
    assert got is whole and path.read_bytes().startswith(PNG)
    assert len(left.axes) == len(FACTORS) and len(right.axes) == len(FACTORS)
    assert left._suptitle.get_text() == "Main effects plot for MU"
    assert whole._suptitle is None  # each title on its own half

    plain = Figure()
    maps = {"a": _status_map(20, 40), "b": _status_map(20, 40, seed=1)}
    assert plotting.plot_fibre_maps(maps, fig=plain) is plain and len(plain.axes) == 2
    with pytest.raises(TypeError, match=r"^fig: expected a matplotlib Figure or SubFigure, got "):
        plotting.plot_interactions(summary, FACTORS, "MU", fig=plain.axes[0])


def test_a_runs_per_step_series_breaks_at_each_stop() -> None:
    """A single-run review: steps.png joined its lines across the stops' ends (a short stop
    merged into the next) and called the pad's force the normal force."""
    steps = xr.Dataset(
        {
            "step_cof": ("step", [0.3, 0.31, 0.32, 0.4, 0.41, 0.5]),
            "step_normal_force": ("step", [1e4, 1e4, 1e4, 2e4, 2e4, 3e4]),
            "step_time": ("step", [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]),
            "step_stop": ("step", [1, 1, 1, 2, 2, 3]),
        },
        coords={"step": np.arange(1, 7)},
    )
    fig = plot_cof_series(steps)
    cof, force = fig.axes
    line = cof.lines[0].get_ydata()
    assert np.isnan(line).sum() == 2 and list(np.flatnonzero(np.isnan(line))) == [3, 6]
    assert force.get_ylabel() == "Pad normal force [N]"
    starts = [ln.get_xdata()[0] for ln in cof.lines[1:]]
    assert starts == [0.4, 0.6]  # a faint line at each new stop's first kept step
    plain = plot_cof_series(pd.DataFrame({"mu": [0.4, 0.41], "normal_force": [1.0, 2.0]}))
    assert plain.axes[1].get_ylabel() == "Normal force [N]"


def test_per_stop_plots_label_the_variable_they_draw(campaign, summary) -> None:
    """plot_mu_per_stop(variable="emitted_volume") drew the volumes [m^3] under the mean COF's
    label and title, and the interaction plot's V axis had no unit (an API review). Another
    variable is named by its long_name and units, a volume in mm^3 as V is drawn elsewhere."""
    from brakeca.plotting import plot_interactions, plot_mu_per_stop, plot_mu_per_stop_by_level

    data = campaign.copy()
    data["emitted_volume"].attrs.update(long_name="wear volume emitted", units="m3")
    fig = plot_mu_per_stop(data, variable="emitted_volume")
    ax = fig.axes[0]
    # the axis short (a figures review: the long name ran the figure's height), the title long
    assert ax.get_ylabel() == "Emitted volume per stop [mm³]"
    assert ax.get_title().startswith("Wear volume emitted: each stop over the cycle")
    assert np.allclose(ax.lines[-1].get_ydata(), 0.1)  # 1e-10 m^3 = 0.1 mm^3 (a run's line)
    fig = plot_mu_per_stop(data)
    assert fig.axes[0].get_ylabel() == "Mean coefficient of friction μ per stop [-]"
    # the COF floor drawn and named where given (a figures review), for the COF alone
    floored = plot_mu_per_stop(data, floor=0.15).axes[0]
    assert any(np.allclose(line.get_ydata(), 0.15) for line in floored.lines)
    assert "COF floor μ_min = 0.15" in [t.get_text() for t in floored.texts]
    volume = plot_mu_per_stop(data, variable="emitted_volume", floor=0.15).axes[0]
    assert "COF floor μ_min = 0.15" not in [t.get_text() for t in volume.texts]
    # a log axis where asked, or (log=None) where the values span more than two decades,
    # as the study's figure of the emitted volume per stop draws them
    assert plot_mu_per_stop(data, variable="emitted_volume", log=None).axes[0].get_yscale() == (
        "linear"
    )
    assert ax.get_yscale() == "linear"  # (log=False by default)
    spread = data.copy(deep=True)
    spread["emitted_volume"][0, 0] = 1e-6  # 1000 mm^3 beside 0.1 mm^3
    ax = plot_mu_per_stop(spread, variable="emitted_volume", log=None).axes[0]
    assert ax.get_yscale() == "log" and ax.get_ylabel().endswith("(log scale)")
    fig = plot_mu_per_stop_by_level(data, FACTORS, variable="emitted_volume")
    assert fig.axes[0].get_ylabel() == "Emitted volume per stop [mm³]"
    labels = {a.get_ylabel() for a in plot_interactions(summary, FACTORS, "V").axes}
    assert "V (mean) [mm³]" in labels


def test_area_fractions_per_stop_are_drawn_in_per_cent_of_the_band(campaign) -> None:
    """The study's figures of the secondary plateaus' area and the area in contact by level
    draw the run file's fractions [-] in per cent under a short label (their long_name is a
    formula), wrapped to the panels' height, where the long label had run into the panel
    below."""
    from brakeca.plotting import plot_mu_per_stop, plot_mu_per_stop_by_level

    data = campaign.copy()
    data["contact_area_fraction"] = xr.full_like(data["mean_cof"], 0.25)
    data["contact_area_fraction"].attrs.update(
        long_name="time-weighted area in contact / band area", units="1"
    )
    data["contact_area_fraction"][0, :] = 0.5  # one run of the first factor's low level
    fig = plot_mu_per_stop_by_level(data, FACTORS, variable="contact_area_fraction")
    label = fig.axes[0].get_ylabel()
    assert label.replace("\n", " ") == "Area in contact per stop [% of band]"
    assert "\n" in label
    assert fig.texts[0].get_text().startswith("Area in contact (time-weighted, % of the band)")
    low = FACTORS[0].levels[0]
    assert data[FACTORS[0].name][0] == low
    n_low = int((data[FACTORS[0].name] == low).sum())  # the low level's line: their mean
    np.testing.assert_allclose(
        fig.axes[0].lines[0].get_ydata(), 100 * (0.5 + 0.25 * (n_low - 1)) / n_low
    )
    # each run too, thin, under the means (runs=True)
    both = plot_mu_per_stop_by_level(data, FACTORS, variable="contact_area_fraction", runs=True)
    # (a collection per level, not a line per run: the legend's "best" place avoids the
    # means only, not every run's line; a report review saw it cover a mean line)
    from matplotlib.collections import LineCollection

    ax = both.axes[0]
    thin = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert sum(len(c.get_segments()) for c in thin) == len(data["run"])
    assert len(thin) == 2 and len(ax.lines) == 2  # the two levels' means
    low_runs = np.stack([seg[:, 1] for seg in thin[0].get_segments()])
    np.testing.assert_allclose(low_runs.mean(axis=0), ax.lines[0].get_ydata())
    ax = plot_mu_per_stop(data, variable="contact_area_fraction").axes[0]
    assert ax.get_ylabel() == "Area in contact per stop [% of band]"
    np.testing.assert_allclose(ax.lines[-1].get_ydata(), 25.0)


def test_an_anova_table_given_for_another_table_is_named_or_used_rightly(summary) -> None:
    """A bare KeyError 'fitted' for an ANOVA table given to plot_residuals, a bare KeyError
    for a factor the summary lacks, and the Residual drawn as a ranked term of plot_pareto
    (an API review)."""
    from brakeca.analysis import anova, interaction_table
    from brakeca.plotting import plot_pareto, plot_residuals

    table = anova(summary, FACTORS, "MU")
    with pytest.raises(ValueError, match=r"expected the table brakeca\.analysis\.residuals"):
        plot_residuals(table, "MU")
    with pytest.raises(KeyError, match="factor 'B' is not a column of the summary"):
        interaction_table(summary, FACTORS[0].name, "B", "MU")
    ticks = [t.get_text() for t in plot_pareto(table, "MU").axes[0].get_xticklabels()]
    assert "Residual" not in ticks and len(ticks) == len(table) - 1


def test_a_panel_of_a_grid_keeps_its_legend_and_title_to_itself(campaign) -> None:
    """In a 2 x 2 grid of one's own, the 24 runs' legend had lain over the panel's lines and
    its neighbour's, and the long title and axis label over the next panel (noticed in the
    thirty-seventh session): a panel's legend stands beside it, its title and label are
    wrapped, and nothing of one panel reaches into another's axes or out of the figure."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(14, 9), layout="constrained")
    for ax in axes.flat:
        plot_mu_per_stop(campaign, factors=FACTORS, ax=ax)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    for ax in axes.flat:
        legend = ax.get_legend().get_window_extent(renderer)
        title = ax.title.get_window_extent(renderer)
        assert legend.x0 >= ax.bbox.x1  # beside the panel, not over its lines
        assert "\n" in ax.title.get_text()
        for box in (legend, title):
            assert page.x0 <= box.x0 <= box.x1 <= page.x1
            assert page.y0 <= box.y0 <= box.y1 <= page.y1
            for other in axes.flat:
                if other is not ax:
                    assert not box.overlaps(other.bbox), (box, other.bbox)
    plt.close(fig)


def test_a_grid_of_surface_maps_and_one_run_keeps_each_panel_to_itself(campaign) -> None:
    """An API review: in a row of three panels (two maps and one run's MU per stop), each
    map's legend of three columns ran into the next panel and off the figure, and the one
    run's title said "all runs" and ran off the figure. A map's legend stands below its
    panel in the columns its width holds, and titles are wrapped to the panel's width."""
    import matplotlib.pyplot as plt

    status, radius, angle = _status_map()
    one = campaign.isel(run=[0])
    fig, axes = plt.subplots(1, 3, figsize=(15, 4), layout="constrained")
    plot_surface_map(status, radius, angle, "Pad before the first stop", ax=axes[0])
    plot_surface_map(status, radius, angle, "Pad after the last stop", ax=axes[1])
    plot_mu_per_stop(one, factors=FACTORS, ax=axes[2])
    assert "all runs" not in axes[2].get_title()
    assert "all runs" in plot_mu_per_stop(campaign, factors=FACTORS).axes[0].get_title()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    for ax in axes.flat:
        boxes = [ax.title.get_window_extent(renderer)]
        if ax.get_legend() is not None:
            legend = ax.get_legend().get_window_extent(renderer)
            assert legend.y1 <= ax.bbox.y0  # below the map, not over it
            boxes.append(legend)
        for box in boxes:
            assert page.x0 <= box.x0 <= box.x1 <= page.x1
            assert page.y0 <= box.y0 <= box.y1 <= page.y1
            for other in axes.flat:
                if other is not ax:
                    assert not box.overlaps(other.bbox), (box, other.bbox)
    assert axes[0].get_legend() is not None and axes[2].get_legend() is None
    plt.close(fig)
    # panels in SubFigures are measured as they are placed (a diff review: measured against
    # the whole figure, their legends took three columns and ran together off the figure)
    fig = plt.figure(figsize=(15, 4), layout="constrained")
    panels = [sub.subplots() for sub in fig.subfigures(1, 3)]
    for ax in panels[:2]:
        plot_surface_map(status, radius, angle, "Pad after the last stop of the cycle", ax=ax)
    plot_mu_per_stop(one, factors=FACTORS, ax=panels[2])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legends = [ax.get_legend().get_window_extent(renderer) for ax in panels[:2]]
    for box in legends + [ax.title.get_window_extent(renderer) for ax in panels]:
        assert fig.bbox.x0 <= box.x0 <= box.x1 <= fig.bbox.x1
    assert not legends[0].overlaps(legends[1])
    plt.close(fig)
    # without a layout engine nothing makes room below: the legend stays inside the map
    fig, ax = plt.subplots()
    plot_surface_map(status, radius, angle, "Pad", ax=ax)
    fig.canvas.draw()
    legend = ax.get_legend().get_window_extent(fig.canvas.get_renderer())
    assert ax.bbox.y0 - 1 <= legend.y0 and legend.y1 <= ax.bbox.y1 + 1
    plt.close(fig)


def test_a_panel_without_a_layout_keeps_its_legend_inside(campaign, tmp_path) -> None:
    """Without a layout engine nothing makes room beside a panel: a legend put there had
    lain over the next panel or off the figure (a review: 22 % of it on the canvas of
    ``plt.subplots()``), so it stays inside the axes there."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    plot_mu_per_stop(campaign, tmp_path / "one.png", factors=FACTORS, ax=ax)
    fig.canvas.draw()
    legend = ax.get_legend().get_window_extent(fig.canvas.get_renderer())
    assert legend.x1 <= ax.bbox.x1 + 1 and legend.x0 >= ax.bbox.x0 - 1
    plt.close(fig)


def test_the_figures_take_a_design_or_an_analysis_as_the_analysis_functions_do(
    summary, tmp_path
) -> None:
    """An API review: plot_main_effects(summary, design, ...) failed with "not a factor ...
    ('name', 'paper')" (iterating a design gives its fields) though every analysis function
    takes a design; and plot_pareto, plot_residuals and plot_effects refused the
    ResponseAnalysis analyze() returns. Each now takes them and draws the same figure."""
    import types

    from brakeca.analysis import analyze
    from brakeca.design import design_from_dict
    from brakeca.plotting import plot_effects

    design = design_from_dict(
        {
            "name": "plots",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": f.name, "field": field, "levels": list(f.levels)}
                | ({"scale": 0.01, "unit": "%"} if f.name == "A" else {})
                for f, field in zip(
                    FACTORS,
                    (
                        "automaton.secondary_removal_fraction",
                        "wear.specific_wear_rate",
                        "wear.resin_wear_depth",
                        "pad.fibre_area_fraction",
                    ),
                    strict=True,
                )
            ],
        }
    )
    by_factors = plot_main_effects(summary, FACTORS, "MU")
    campaign = types.SimpleNamespace(design=design, summary=summary)  # as a CampaignResult
    for given in (design, campaign):
        fig = plot_main_effects(summary, given, "MU")
        for ours, theirs in zip(fig.axes, by_factors.axes, strict=True):
            np.testing.assert_array_equal(ours.lines[0].get_ydata(), theirs.lines[0].get_ydata())
        assert len(plot_interactions(summary, given, "MU").axes) == 8
    two = [f for f in FACTORS if len(f.levels) == 2]
    result = analyze(summary, two, ["MU"])
    for plot, table in ((plot_pareto, "ranked_effects"), (plot_residuals, "residuals")):
        expected = plot(result["MU"][table], "MU")
        for given in (result["MU"], result):
            fig = plot(given, "MU")
            assert len(fig.axes) == len(expected.axes)
            assert [t.get_text() for t in fig.axes[0].get_xticklabels()] == [
                t.get_text() for t in expected.axes[0].get_xticklabels()
            ]
    assert len(plot_effects(result["MU"], "MU").axes) == 2
    with pytest.raises(KeyError, match=r"response: 'V' is not one of the analysis' responses"):
        plot_pareto(result, "V")


def test_titles_name_log10_v_as_a_quantity_not_a_column(summary) -> None:
    """A figures review read the column name log10_V_mm3 in titles and axes; they say
    log10 V (its axis label says mm³)."""
    data = summary.assign(log10_V_mm3=np.log10(summary["V_mm3"]))
    fig = plot_interactions(data, FACTORS[:2], "log10_V_mm3")
    title = " ".join(fig.texts[0].get_text().split())  # (wrapped to fit)
    assert title.startswith("Interaction plot for log10 V: log10 of V in mm³")
    assert fig.axes[0].get_ylabel() == "log10 V (mean) [-]"
    assert "log10_V_mm3" not in plot_main_effects(data, FACTORS, "log10_V_mm3").texts[0].get_text()


def test_residuals_by_level_draw_each_runs_residual_at_its_level(summary) -> None:
    """Residuals against each factor's levels (Minitab's residuals versus the variables, new
    with a figures review's list of what the report lacked): a panel per factor, each
    usable run's standardized residual at its level, the runs of a level side by side, a
    run beyond ±2 named."""
    from brakeca.analysis import residuals
    from brakeca.plotting import plot_residuals_by_level

    table = residuals(summary, FACTORS, "MU")
    fig = plot_residuals_by_level(table, summary, FACTORS, "MU")
    assert len(fig.axes) == len(FACTORS)
    ok = summary[summary["status"] == "ok"].set_index("test")
    # a length in µm, friendly at the edges (the design's 1e-07 m)
    assert [t.get_text() for t in fig.axes[2].get_xticklabels()] == ["-\n0.1", "+\n1"]
    assert fig.axes[2].get_xlabel() == "WR [µm]"
    for ax, factor in zip(fig.axes, FACTORS, strict=True):
        points = ax.lines[0]
        x, y = points.get_xdata(), points.get_ydata()
        np.testing.assert_array_equal(y, table["std_residual"])
        at = [factor.levels.index(ok.loc[t, factor.name]) for t in table["test"]]
        np.testing.assert_array_equal(np.round(x), at)  # at its level, within ±0.18
        assert np.abs(x - at).max() <= 0.18 + 1e-12
        assert [t.get_text() for t in ax.get_xticklabels()] == [
            f"{factor.level_label(v)}\n{factor.shown(v)}" for v in factor.levels
        ]
        # the unit on the axis, the long name above, as the main-effects plots (a report
        # review: the axes had no unit)
        assert (ax.get_xlabel(), ax.get_title()) == (factor.axis_label, factor.label)
    assert fig.axes[0].get_ylabel() == "Standardized residual [-]"
    far = summary.copy()
    far.loc[0, "MU"] += 0.2  # test 1 far off the model
    table = residuals(far, FACTORS, "MU")
    assert table["std_residual"].abs().max() > 2
    fig = plot_residuals_by_level(table, far, FACTORS, "MU")
    assert all("test 1" in [t.get_text() for t in ax.texts] for ax in fig.axes)
    with pytest.raises(ValueError, match="summary: no column WP"):
        plot_residuals_by_level(table, summary.drop(columns="WP"), FACTORS, "MU")
    # without standardized residuals (leverage 1), raw ones, and the figure says so
    raw = plot_residuals_by_level(table.assign(std_residual=np.nan), far, FACTORS, "MU")
    assert raw.axes[0].get_ylabel().startswith("Residual (")
    assert "raw residuals" in raw.axes[0].texts[-1].get_text()


def test_level_comparisons_draw_each_pairs_interval(summary) -> None:
    """Tukey's simultaneous intervals as Minitab draws them (a figures review's list of what
    the report lacked): a row per pair of a factor's levels, the difference at its point and
    the interval about it, red where it does not hold zero."""
    from brakeca.analysis import level_comparisons
    from brakeca.plotting import plot_level_comparisons

    table = level_comparisons(summary, FACTORS, "V")
    assert list(table["factor"]) == ["WP"] * 3
    fig = plot_level_comparisons(table, "V")
    (ax,) = fig.axes
    assert [t.get_text() for t in ax.get_yticklabels()] == ["WP0 − WP-", "WP+ − WP-", "WP+ − WP0"]
    points = [line for line in ax.lines if line.get_marker() == "o"]
    spans = [line for line in ax.lines if line.get_linestyle() == "-" and line.get_marker() != "o"]
    np.testing.assert_allclose([p.get_xdata()[0] for p in points], table["difference"] * 1e9)
    np.testing.assert_allclose(
        [s.get_xdata() for s in spans], table[["ci_low", "ci_high"]].to_numpy() * 1e9
    )
    red = [p.get_color() == "#b2182b" for p in points]
    assert red == list((table["ci_low"] > 0) | (table["ci_high"] < 0))
    assert ax.get_xlabel() == "Difference of means (Emitted wear volume per stop V [mm³])"
    with pytest.raises(ValueError, match="no pair of levels"):
        plot_level_comparisons(table.iloc[0:0], "V")
    # a factor without level labels: its values, named (a diff review: "mu00.6 − mu00.5")
    plain = [Factor(f.name, f.levels) for f in FACTORS]
    table = level_comparisons(summary, plain, "V")
    ax = plot_level_comparisons(table, "V").axes[0]
    assert ax.get_yticklabels()[0].get_text() == "WP = 1e-14 − WP = 1e-15"


def test_v_per_run_writes_each_tests_levels_under_it(summary) -> None:
    """The axis had named the tests alone (a figures review): given the factors, or a
    campaign, each test's levels stand under its number, one line a factor, and the axis
    label names their order."""
    from brakeca.plotting import plot_v_per_run

    ax = plot_v_per_run(summary, factors=FACTORS).axes[0]
    ticks = [t.get_text() for t in ax.get_xticklabels()]
    first = summary.set_index("test")
    for tick, test in zip(ticks, sorted(summary["test"]), strict=True):
        expected = [str(test)] + [f.level_label(first.loc[test, f.name]) for f in FACTORS]
        assert tick.split("\n") == expected
    assert ax.get_xlabel() == "Test number [-], its levels below it: S, WP, WR, A from the top"
    assert [t.get_text() for t in ax.texts] == ["failed", "test\nS\nWP\nWR\nA"]  # rows named
    design = type("Design", (), {"factor_names": [f.name for f in FACTORS], "factors": FACTORS})
    campaign = type("Campaign", (), {"summary": summary, "design": design()})()
    assert [t.get_text() for t in plot_v_per_run(campaign).axes[0].get_xticklabels()] == ticks
    plain = plot_v_per_run(summary).axes[0]  # the test numbers alone
    numbers = [str(t) for t in sorted(summary["test"])]
    assert [t.get_text() for t in plain.get_xticklabels()] == numbers
    # beyond MOST_TESTS_NAMED tests, rows as even as they can be, every test once, the axes
    # as wide as the longest row (a figures review: 125 tests in a row 7,400 pixels wide)
    from brakeca.plotting import MOST_TESTS_NAMED

    n = 3 * MOST_TESTS_NAMED + 5
    many = pd.DataFrame({"test": np.arange(1, n + 1), "V": np.linspace(1e-9, 2e-9, n)})
    axes = plot_v_per_run(many.assign(status="ok")).axes
    per_row = -(-n // len(axes))
    assert len(axes) == 4 and per_row <= MOST_TESTS_NAMED
    shown = [int(t.get_text()) for ax in axes for t in ax.get_xticklabels()]
    assert shown == list(range(1, n + 1))
    widths = {round(ax.get_xlim()[1] - ax.get_xlim()[0], 9) for ax in axes}
    assert widths == {per_row + 0.2}


def test_mu_vs_v_puts_each_test_at_its_mu_and_v(summary) -> None:
    """The trade-off figure (an engineer's read: no figure set MU against V): a point per
    finished test at its MU and V [mm³], labelled with its test number, coloured by a
    factor's levels."""
    from brakeca.plotting import plot_mu_vs_v

    ax = plot_mu_vs_v(summary, factors=FACTORS, by="WP").axes[0]
    ok = summary[summary["status"] == "ok"]
    points = [line for line in ax.lines if line.get_linestyle() == "None"]
    assert len(points) == 3  # one series per level of WP
    # told apart by marker as well as by colour (a figures review: red and green alone)
    assert [p.get_marker() for p in points] == ["o", "s", "^"]
    xs = np.concatenate([p.get_xdata() for p in points])
    ys = np.concatenate([p.get_ydata() for p in points])
    assert sorted(xs) == sorted(ok["MU"]) and np.allclose(sorted(ys), sorted(ok["V"] * 1e9))
    labelled = [int(t) for text in ax.texts for t in text.get_text().split(", ")]
    assert sorted(labelled) == sorted(ok["test"])  # tests at one point share a label
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "WP- (1e-15 m³/(N·m))",
        "WP0 (1e-14 m³/(N·m))",
        "WP+ (1e-13 m³/(N·m))",
    ]
    with pytest.raises(KeyError, match="by: 'X' is not a factor"):
        plot_mu_vs_v(summary, factors=FACTORS, by="X")
    # a test near two labelled points is named once (a review of large designs: tests named
    # in two labels): three tests in a row, 0.025 apart on the scaled axes, and a far one
    chain = pd.DataFrame(
        {"test": [1, 2, 3, 4], "MU": [0.200, 0.2025, 0.205, 0.3], "V": [1e-9] * 3 + [2e-9]}
    ).assign(status="ok")
    texts = [t.get_text() for t in plot_mu_vs_v(chain).axes[0].texts]
    named = [int(t) for text in texts for t in text.split(", ")]
    assert sorted(named) == [1, 2, 3, 4], texts
    # MU across, V up: a pad material wants the lower right, as the caption says (a diff
    # review caught "upper left")
    assert ax.get_xlabel().startswith("MU") and ax.get_ylabel().startswith("V")
    # beyond MOST_TESTS_NAMED tests only the trade-off front is named (a figures review: the
    # labels of 125 tests ran into one another): high MU and low V, no test beating it in both
    from brakeca.plotting import MOST_TESTS_NAMED

    n = MOST_TESTS_NAMED + 10
    rng = np.random.default_rng(2)
    many = pd.DataFrame(
        {"test": np.arange(1, n + 1), "MU": rng.uniform(0.15, 0.4, n), "V": rng.uniform(1, 9, n)}
    ).assign(status="ok", V=lambda f: f["V"] * 1e-9)
    axes = plot_mu_vs_v(many).axes[0]
    named = sorted(int(t) for text in axes.texts for t in text.get_text().split(", "))
    mu, v = many["MU"].to_numpy(), many["V"].to_numpy()
    front = [
        int(t)
        for t, m, w in zip(many["test"], mu, v, strict=True)
        if not ((mu >= m) & (v <= w) & ((mu > m) | (v < w))).any()
    ]
    assert named == sorted(front) and 0 < len(front) < n
    assert f"the {len(front)} tests no other has both" in axes.get_title()
    from brakeca.plotting import mu_v_names_front_only

    assert mu_v_names_front_only(many)
    # the tests drawn are counted, as the caption counts them: failed ones are not drawn (a
    # diff review: a caption had counted them)
    failed = many.copy()
    failed.loc[failed["test"] > MOST_TESTS_NAMED - 2, "status"] = "failed"
    assert not mu_v_names_front_only(failed)
    assert not any(
        "no other has both" in line for line in [plot_mu_vs_v(failed).axes[0].get_title()]
    )


def test_cube_means_are_the_corners_runs_means_and_pick_the_largest_effects(summary) -> None:
    """cube_means (Minitab's cube plot of data means): each corner's mean is the mean of the
    finished runs there, over the other factors; by default the three two-level factors
    whose level means differ most; a corner no run reaches is NaN with n = 0."""
    from brakeca.analysis import cube_means, main_effects

    table = cube_means(summary, FACTORS, "MU", names=["A", "S", "WR"])
    ok = ok_runs(summary)
    by_hand = ok.groupby(["A", "S", "WR"])["MU"].agg(["mean", "size"])
    assert list(table.columns) == ["A", "S", "WR", "mean", "n"] and len(table) == 8
    assert list(table["A"][:2]) == [10.0, 20.0]  # the first factor changes fastest
    for _, row in table.iterrows():
        mean, size = by_hand.loc[(row["A"], row["S"], row["WR"])]
        assert row["mean"] == pytest.approx(mean, rel=1e-14, abs=0) and row["n"] == size
    assert table["n"].sum() == len(ok)  # the failed run is in no corner
    # the default: of the two-level factors, the three whose level means differ most, in
    # the design's order; B, a fourth with a real effect on V, displaces the weakest
    two = [f for f in FACTORS if f.name != "WP"]
    with_b = summary.assign(B=(np.arange(len(summary)) // 3 % 2).astype(float))
    with_b["V"] = with_b["V"] + 5e-11 * with_b["B"]
    four = [*two, Factor("B", (0.0, 1.0))]
    effects = main_effects(with_b, four, "V")
    spread = {f.name: np.ptp(effects.loc[effects["factor"] == f.name, "mean"]) for f in four}
    strongest = sorted(spread, key=lambda n: -spread[n])[:3]
    expected = tuple(f.name for f in four if f.name in strongest)
    assert "B" in expected and len(expected) == 3
    assert cube_means(with_b, four, "V").attrs["factors"] == expected
    assert cube_means(summary, FACTORS, "V").attrs["factors"] == ("S", "WR", "A")  # WP: 3
    with pytest.raises(ValueError, match="no finished run with a finite MU"):
        cube_means(summary.assign(status="failed"), FACTORS, "MU")
    # a half fraction: half the corners of a cube of three have no run
    half = summary[summary["S"] == (summary["A"] == 20.0).astype(float)]
    corners = cube_means(half, FACTORS, "MU", names=["S", "WR", "A"])
    assert (corners["n"] == 0).sum() == 4 and corners.loc[corners["n"] == 0, "mean"].isna().all()
    with pytest.raises(ValueError, match=r"names: \['WP'\] not of two levels"):
        cube_means(summary, FACTORS, "MU", names=["S", "WP"])
    with pytest.raises(ValueError, match="two or three different factors"):
        cube_means(summary, FACTORS, "MU", names=["S"])
    with pytest.raises(ValueError, match=r"names: \['X'\] not factors of the design"):
        cube_means(summary, FACTORS, "MU", names=["S", "X"])
    with pytest.raises(ValueError, match="needs two or three factors of two levels; this"):
        cube_means(summary, [FACTORS[1]], "MU")


def test_cube_plot_writes_each_corners_mean(tmp_path, summary) -> None:
    from brakeca.analysis import cube_means
    from brakeca.plotting import plot_cube

    path = tmp_path / "cube.png"
    fig = plot_cube(summary, FACTORS, "V", path, names=["S", "A", "WR"])
    assert path.read_bytes().startswith(PNG)
    texts = [t.get_text() for t in fig.axes[0].texts]
    corners = cube_means(summary, FACTORS, "V", names=["S", "A", "WR"])
    assert {f"{m * 1e9:.4g}" for m in corners["mean"]} <= {t.split("\n")[0] for t in texts}
    # the failed run leaves one corner two runs where the others have three: each says so
    assert sum(t.endswith("\n(n = 2)") for t in texts) == 1
    assert sum(t.endswith("\n(n = 3)") for t in texts) == 7
    assert "Cube plot (data means) for V [mm³]" in fig.texts[0].get_text()
    # each mean at its corner: S along, A up, WR into the page (drawn up and to the right)
    at = {
        t.get_text().split("\n")[0]: t.xy for t in fig.axes[0].texts if t.get_text()[:1].isdigit()
    }
    for _, row in corners.iterrows():
        i, j, k = (
            float(row[n] == f.levels[1])
            for n, f in (("S", FACTORS[0]), ("A", FACTORS[3]), ("WR", FACTORS[2]))
        )
        assert at[f"{row['mean'] * 1e9:.4g}"] == pytest.approx((i + 0.55 * k, j + 0.4 * k))
    square = plot_cube(summary, FACTORS, "MU", names=["S", "A"])
    assert len([t for t in square.axes[0].texts if t.get_text()[:1].isdigit()]) == 4
    half = summary[summary["S"] == (summary["A"] == 20.0).astype(float)]
    sparse = plot_cube(half, FACTORS, "MU", names=["S", "WR", "A"])
    assert [t.get_text() for t in sparse.axes[0].texts].count("no run") == 4


def test_cube_puts_each_factors_low_level_first_whichever_order_the_design_lists(
    summary,
) -> None:
    """Minitab draws a cube's low level at the near end of each edge: a design that lists
    A's levels high first (20 %, then 10 %) gives the same corners, rows and positions as
    one that lists them low first."""
    from brakeca.analysis import cube_means
    from brakeca.plotting import plot_cube

    a_low, a_high = FACTORS[3], Factor("A", (20.0, 10.0), "%", "Metal fibre area fraction")
    listed = [FACTORS[0], FACTORS[2], a_high]
    usual = cube_means(summary, [FACTORS[0], FACTORS[2], a_low], "MU", names=["S", "A"])
    table = cube_means(summary, listed, "MU", names=["S", "A"])
    pd.testing.assert_frame_equal(table, usual)
    assert list(table["A"]) == [10.0, 10.0, 20.0, 20.0]
    fig = plot_cube(summary, listed, "MU", names=["S", "A"])
    texts = fig.axes[0].texts
    at = {t.get_text().split("\n")[0]: t.xy for t in texts if t.get_text()[:2] == "0."}
    for _, row in table.iterrows():  # A = 10 % along the bottom edge, 20 % along the top
        assert at[f"{row['mean']:.4g}"] == pytest.approx((row["S"], float(row["A"] == 20.0)))
    ends = {t.get_text(): t.xy for t in texts if t.get_text() in ("10", "20")}
    assert ends == {"10": pytest.approx((0.0, 0.0)), "20": pytest.approx((0.0, 1.0))}


def test_by_block_writes_each_runs_block_means_and_shares() -> None:
    """The block-by-block table as a figure (tables/by_block.csv was a CSV alone): a row per
    run in test order, a column per block in the cycle's order, each cell its value."""
    from brakeca.plotting import plot_by_block

    rows = []
    for test, s in ((1, 0.0), (2, 1.0)):
        for block, stops, cof, share in (
            ("Burnish", 3, 0.2 + 0.1 * s, 60.0),
            ("Town", 2, 0.3, 40.0),
        ):
            rows.append(
                {
                    "test": test,
                    "replicate": 0,
                    "S": s,
                    "block": block,
                    "stops": stops,
                    "mean_cof": cof,
                    "share_of_emitted_percent": share - 10 * s,
                }
            )
    table = pd.DataFrame(rows)
    factors = [Factor("S", (0.0, 1.0), "-", "S", ("-", "+"))]
    fig = plot_by_block(table, factors)
    left, right = fig.axes[:2]  # then their colour bars
    assert [t.get_text() for t in left.get_yticklabels()] == ["T1: S-", "T2: S+"]
    assert [t.get_text() for t in left.get_xticklabels()] == ["Burnish (3)", "Town (2)"]
    cells = {
        (round(t.get_position()[1]), round(t.get_position()[0])): t.get_text() for t in left.texts
    }
    # 3 decimals: at 2, a run at the COF floor and one 0.004 above it read alike (a report
    # review)
    assert cells == {(0, 0): "0.200", (0, 1): "0.300", (1, 0): "0.300", (1, 1): "0.300"}
    assert sorted(t.get_text() for t in right.texts) == ["30", "40", "50", "60"]
    assert [bar.get_ylabel() for bar in fig.axes[2:]] == ["[-]", "[%]"]  # the colour bars
    assert [t.get_text() for t in plot_by_block(table).axes[0].get_yticklabels()] == ["T1", "T2"]
    with pytest.raises(ValueError, match="block_table's table"):
        plot_by_block(table.drop(columns="block"))
    # two replicates of a test: a row each, named by replicate
    twice = table.assign(test=1, replicate=[0, 0, 1, 1])
    rows = plot_by_block(twice, factors).axes[0].get_yticklabels()
    assert [t.get_text() for t in rows] == ["T1 r0: S-", "T1 r1: S+"]


def test_main_effects_of_a_response_no_run_has(summary) -> None:
    """Every run's response missing (V = 0 everywhere, so no log10 V): the panels are drawn
    empty without matplotlib's warning of a legend with nothing to name (warnings are
    errors here; an analysis review saw it in a report's log)."""
    fig = plot_main_effects(summary.assign(MU=np.nan), FACTORS, "MU")
    assert fig.axes[0].get_legend() is None


def test_main_effects_wrap_beyond_six_factors() -> None:
    """Eleven factors had made one row 4440 px wide, read at 3 px a letter in the report (a
    review of large designs): the panels wrap at six a row, as Minitab's, each row's first
    panel with the response's label, the cells left over hidden."""
    import itertools

    from brakeca.analysis import Factor
    from brakeca.plotting import MAIN_EFFECTS_PER_ROW, plot_main_effects

    names = [f"F{k}" for k in range(8)]
    factors = [Factor(n, (0.0, 1.0), "-", n) for n in names]
    rng = np.random.default_rng(3)
    rows = [
        dict(zip(names, levels, strict=True)) for levels in itertools.product((0.0, 1.0), repeat=8)
    ]
    summary = pd.DataFrame(rows).assign(MU=rng.uniform(0.2, 0.4, 256), status="ok")
    fig = plot_main_effects(summary, factors, "MU")
    shown = [ax for ax in fig.axes if ax.get_visible()]
    assert MAIN_EFFECTS_PER_ROW == 6 and len(shown) == 8 and len(fig.axes) == 12
    assert [ax.get_title() for ax in shown] == names
    labelled = [ax for ax in shown if ax.get_ylabel()]
    assert labelled == [shown[0], shown[6]]  # each row's first
    for ax, name in zip(shown, names, strict=True):
        means = summary.groupby(name)["MU"].mean().to_numpy()
        np.testing.assert_allclose(ax.lines[0].get_ydata(), means, rtol=1e-12)


def test_per_stop_by_test_draws_each_test_over_the_others(tmp_path, campaign, summary) -> None:
    """A figures review could not tell 24 runs' lines apart in one panel (ten colours, three
    line styles): the same runs as small multiples, a panel per test, its runs black over
    every other run in grey."""
    from matplotlib.collections import LineCollection

    from brakeca.plotting import MOST_TESTS_NAMED, plot_mu_per_stop_by_test

    path = tmp_path / "by_test.png"
    fig = plot_mu_per_stop_by_test(campaign, path, factors=FACTORS, floor=0.15)
    assert path.read_bytes().startswith(PNG)
    axes = fig.axes
    assert len(axes) == len(summary)  # 24 panels, 4 a row
    values = campaign["mean_cof"].transpose("run", "stop").to_numpy()
    for k, ax in enumerate(axes):
        (own,) = [line for line in ax.lines if line.get_color() == "black"]
        np.testing.assert_array_equal(own.get_ydata(), values[k])  # its own run, unscaled
        (grey,) = [c for c in ax.collections if isinstance(c, LineCollection)]
        others = np.array([segment[:, 1] for segment in grey.get_segments()])
        np.testing.assert_array_equal(others, np.delete(values, k, axis=0))  # every other
        assert any(np.allclose(line.get_ydata(), 0.15) for line in ax.lines)  # the floor
    assert axes[0].get_title() == "T1: S-, WP-, WR-, A-"
    assert axes[4].get_title() == "T5: S-, WP+, WR-, A-"
    assert axes[0].get_shared_y_axes().joined(axes[0], axes[-1])  # one scale to compare
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend[:2] == ["the panel's test", "every other run"]
    assert "COF floor μ_min = 0.15" in legend
    # chosen tests, in the order given; a test the campaign lacks is named with the range
    fig = plot_mu_per_stop_by_test(campaign, factors=FACTORS, tests=[5, 2], columns=3)
    titles = [ax.get_title() for ax in fig.axes]  # (no empty third panel)
    assert titles == ["T5: S-, WP+, WR-, A-", "T2: S+, WP-, WR-, A-"]
    with pytest.raises(
        ValueError, match=r"^tests: \[25\] not among the campaign's tests \(1 to 24\)"
    ):
        plot_mu_per_stop_by_test(campaign, tests=[25])
    with pytest.raises(ValueError, match=r"^tests: none given; the campaign's are 1 to 24$"):
        plot_mu_per_stop_by_test(campaign, tests=[])
    with pytest.raises(TypeError, match=r"^tests: expected the tests as a list"):
        plot_mu_per_stop_by_test(campaign, tests="12")
    gaps = campaign.isel(run=[0, 4, 8]).assign_coords(test=("run", [1, 5, 9]))
    with pytest.raises(ValueError, match=r"\(1, 5, 9\)$"):  # not "1 to 9"
        plot_mu_per_stop_by_test(gaps, tests=[2])
    with pytest.raises(ValueError, match=r"^columns: expected a whole number"):
        plot_mu_per_stop_by_test(campaign, columns=0)
    # one stop: a point each, which a line alone does not draw (a diff review: empty panels),
    # and one tick, at the stop (the integer locator had fallen back to 0.5, 0.6, ...)
    from brakeca.plotting import plot_mu_per_stop_by_level

    first = campaign.isel(stop=[0])
    for drawn in (
        plot_mu_per_stop(first, factors=FACTORS),
        plot_mu_per_stop_by_level(first, FACTORS),
        plot_mu_per_stop_by_test(first, factors=FACTORS),
    ):
        assert list(drawn.axes[0].get_xticks()) == [1.0]
    fig = plot_mu_per_stop_by_test(campaign.isel(stop=[0]), factors=FACTORS)
    (own,) = [line for line in fig.axes[0].lines if line.get_color() == "black"]
    assert own.get_marker() == "o" and list(own.get_xdata()) == [1]
    grey = [line for line in fig.axes[0].lines if line.get_color() == "0.72"]
    assert len(grey) == 1 and grey[0].get_ydata().size == len(summary) - 1
    # a run alone: one panel, named as the run, not as a test 0 it does not have
    one = campaign.isel(run=0).drop_vars("run")
    assert [ax.get_title() for ax in plot_mu_per_stop_by_test(one).axes] == ["the run"]
    with pytest.raises(KeyError, match="no variable 'wear'"):
        plot_mu_per_stop_by_test(campaign, variable="wear")
    # beyond MOST_TESTS_NAMED tests the caller names the panels
    many = xr.concat([campaign] * 2, dim="run")
    many = many.assign_coords(run=np.arange(1, 49), test=("run", np.arange(1, 49)))
    assert 48 > MOST_TESTS_NAMED
    with pytest.raises(ValueError, match=r"^tests: the campaign has 48 tests, more panels"):
        plot_mu_per_stop_by_test(many)
    axes = plot_mu_per_stop_by_test(many, tests=range(40, 49)).axes
    assert len(axes) == 9 and axes[0].get_title() == "T40: S=1, WP=1e-14, WR=1e-07, A=20"
    # replicates share their test's panel, both black; a run not finished is said so
    twice = xr.concat([campaign, campaign], dim="run")
    status = np.array(["ok"] * (2 * len(summary)), dtype=object)
    status[len(summary)] = "failed"  # test 1's second replicate
    twice = twice.assign_coords(
        run=np.arange(1, 2 * len(summary) + 1),
        test=("run", np.tile(summary["test"], 2)),
        status=("run", status),
    )
    fig = plot_mu_per_stop_by_test(twice, factors=FACTORS)
    axes = fig.axes
    assert len(axes) == len(summary)
    assert len([line for line in axes[0].lines if line.get_color() == "black"]) == 2
    title = axes[0].get_title().replace("\n", " ")  # (wrapped to the panel)
    assert title == "T1: S-, WP-, WR-, A- (1 of 2 runs not finished)"
    assert axes[1].get_title() == "T2: S+, WP-, WR-, A-"
    # a volume in mm³, on a log axis where it spans more than two decades
    spread = campaign.copy(deep=True)
    spread["emitted_volume"][0, 0] = 1e-6
    spread["emitted_volume"].attrs["units"] = "m3"
    fig = plot_mu_per_stop_by_test(spread, variable="emitted_volume", log=None)
    assert fig.axes[0].get_yscale() == "log"
    assert fig.axes[0].get_ylabel().replace("\n", " ") == "Emitted volume per stop [mm³] (log)"
    assert np.allclose(fig.axes[1].lines[-1].get_ydata(), 0.1)  # 1e-10 m³
