"""The report's note on the COF floor (brakeca.study._floor_note): the stops whose mean COF
is friction.mu_min, where MU cannot show an effect below it (a review of the report found
two runs at the floor for 38 % of their stops, and the report silent on it)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr

from brakeca.presets import load_preset
from brakeca.study import _floor_note


def _result(cof: np.ndarray, fields=("wear.specific_wear_rate",)) -> SimpleNamespace:
    n_run, n_stop = cof.shape
    data = xr.Dataset(
        {"mean_cof": (("run", "stop"), cof)},
        coords={
            "run": np.arange(1, n_run + 1),
            "stop": np.arange(1, n_stop + 1),
            "test": ("run", np.arange(1, n_run + 1)),
            "replicate": ("run", np.zeros(n_run, dtype=int)),
        },
    )
    design = SimpleNamespace(factors=[SimpleNamespace(field=f) for f in fields])
    return SimpleNamespace(dataset=data, design=design)


def test_the_runs_at_the_floor_are_counted_and_the_most_named() -> None:
    base = load_preset("paper")
    floor = base.friction.mu_min
    cof = np.full((4, 10), 0.3)
    cof[1, :4] = floor  # test 2: 40 % of its stops at the floor
    cof[3, :1] = floor  # test 4: 10 %
    cof[2, 5] = floor * 1.011  # 1.1 % above it: not at it
    cof[0, :] = np.nan  # test 1 failed (no stop): not counted
    note = _floor_note(_result(cof), base)
    assert note.startswith("The COF floor: 2 of the 3 finished runs have stops whose mean COF")
    assert "lies within 1 % of the floor friction.mu_min = 0.15" in note
    assert "the most in test 2 (40 % of its stops) and test 4 (10 %)." in note
    # within 1 % of it is at it (a report review: a run whose every stop lay within 0.3 %
    # of the floor had been counted at it in 38 % of its stops, by equality to 1e-9)
    cof[2, 5:] = floor * 1.009
    note = _floor_note(_result(cof), base)
    assert "the most in test 3 (50 % of its stops), test 2 (40 %) and test 4 (10 %)." in note


def test_the_runs_held_at_the_floor_are_an_in_short_line() -> None:
    """Runs held at the floor half their stops or more are named in "In short" (a report
    review: the note alone, at the end, left MU's effects read as if unbounded)."""
    from brakeca.study import _floor_line

    base = load_preset("paper")
    floor = base.friction.mu_min
    cof = np.full((3, 10), 0.3)
    cof[0, :] = floor * 1.003  # test 1: every stop
    cof[1, :5] = floor  # test 2: half
    cof[2, :4] = floor  # test 3: 40 %, not named
    line = _floor_line(_result(cof), base)
    assert line.startswith(
        "MU at the COF floor: test 1 (100 %) and test 2 (50 %) spend half their stops or more "
        "within 1 % of friction.mu_min = 0.15"
    )
    cof[0, :] = 0.3
    import pandas as pd

    held = _result(cof)
    held.summary = pd.DataFrame({"status": ["ok"] * 3, "MU_SD": [0.01, 0.02, 0.03]})
    one = _floor_line(held, base)
    assert one.startswith(  # one run: its stops (a review)
        "MU at the COF floor: test 2 (50 %) spends half its stops or more within 1 %"
    )
    assert ", and that run's MU_SD may be small because the floor holds them, not their pads" in one
    cof[:2, :] = 0.3
    assert _floor_line(_result(cof), base) == ""  # test 3 alone, under half
    many = np.full((8, 4), floor)  # eight runs held: five named, the rest counted
    assert _floor_line(_result(many), base).startswith(
        "MU at the COF floor: test 1 (100 %), test 2 (100 %), test 3 (100 %), test 4 (100 %), "
        "test 5 (100 %) and 3 more runs spend half their stops or more"
    )


def test_a_run_of_a_shorter_cycle_counts_over_its_own_stops() -> None:
    """A diff review: campaign.nc pads a shorter run's stops with NaN, and such a run was
    left out of the finished runs; with a status coordinate, the finished runs are those
    'ok', each counted over its own stops."""
    base = load_preset("paper")
    floor = base.friction.mu_min
    cof = np.full((3, 10), 0.3)
    cof[0, 5:] = np.nan  # a run of 5 stops
    cof[0, :2] = floor  # 40 % of its own stops at the floor
    cof[2, :] = np.nan  # a failed run
    result = _result(cof)
    result.dataset = result.dataset.assign_coords(status=("run", ["ok", "ok", "failed"]))
    note = _floor_note(result, base)
    assert note.startswith("The COF floor: 1 of the 2 finished runs")
    assert "the most in test 1 (40 % of its stops)." in note


def test_no_note_without_stops_at_the_floor_or_with_a_factor_on_the_friction_law() -> None:
    base = load_preset("paper")
    assert _floor_note(_result(np.full((3, 5), 0.3)), base) == ""
    at_floor = np.full((3, 5), base.friction.mu_min)
    assert _floor_note(_result(at_floor, ("friction.mu_min",)), base) == ""
    assert _floor_note(_result(at_floor), None) == ""
    assert "3 of the 3" in _floor_note(_result(at_floor), base)
    # the law's slope moves where the floor is reached, not the floor: the note stays (a
    # review of a replicated study: every floor statement had gone with a slope factor)
    assert "3 of the 3" in _floor_note(_result(at_floor, ("friction.slope",)), base)


def test_v_captions_of_the_quick_band_say_its_volumes_are_a_fraction_of_the_full_band_s():
    """A figures review: the quick study's V figures said "as the paper's Figure 8" with
    volumes a tenth of the paper's band's, and only one sentence at the top said why."""
    from brakeca.design import quick_config
    from brakeca.presets import load_preset
    from brakeca.study import _band_caption

    paper = load_preset("paper")
    assert _band_caption(paper) == "" and _band_caption(None) == ""
    wide = paper.with_updates({"mesh.n_radial": 101, "mesh.radial_step": 200e-6})
    assert _band_caption(wide) == ""  # the full 20 mm in fewer, wider rows
    assert _band_caption(quick_config(paper)) == (
        "; V here leaves the simulated band of 21 rows (2 mm), about 0.1 times the full "
        "band's, so compare its shape with the paper's, not its values"
    )


def test_the_per_run_table_gives_each_runs_areas_over_the_whole_cycle() -> None:
    """The last stop's secondary share does not represent a run (a report review: 67 % at
    stop 170 after 0 % in stops 166-169): the per-run table gains the secondary plateau
    area and the area in contact over the cycle, weighted by the stops' durations, beside
    the last stop's share."""
    import pandas as pd

    from brakeca.study import _with_cycle_areas

    secondary = np.array([[0.0, 0.6], [0.2, 0.2]])
    contact = np.array([[0.3, 0.9], [0.5, 0.5]])
    duration = np.array([[1.0, 3.0], [2.0, np.nan]])  # run b ran one stop
    data = xr.Dataset(
        {
            "secondary_area_fraction": (("run", "stop"), secondary),
            "contact_area_fraction": (("run", "stop"), contact),
            "duration": (("run", "stop"), duration),
        },
        coords={"run": [1, 2], "stop": [1, 2], "run_id": ("run", ["a", "b"])},
    )
    shown = pd.DataFrame(
        {"run_id": ["b", "a"], "final_secondary_area_fraction": [0.2, 0.6], "n_steps": [1, 2]}
    )
    out = _with_cycle_areas(shown, SimpleNamespace(dataset=data))
    assert list(out.columns) == [
        "run_id",
        "final_secondary_area_fraction",
        "cycle_secondary_area_fraction",
        "cycle_contact_area_fraction",
        "n_steps",
    ]
    assert list(out["cycle_secondary_area_fraction"]) == [0.2, (0.0 * 1 + 0.6 * 3) / 4]
    assert list(out["cycle_contact_area_fraction"]) == [0.5, (0.3 * 1 + 0.9 * 3) / 4]
    assert _with_cycle_areas(shown, SimpleNamespace(dataset=None)) is shown


def test_the_note_on_v_gives_the_bands_share_of_the_pad() -> None:
    """The words "not scaled to the pad" gave no factor (a report review): the paper's band is 1,744
    mm² of the pad's 5,080 mm², 34 %; the quick band's 2.1 mm, 182 mm², 3.6 %; a tiny band
    of 5 x 100 cells 4.34 mm², 0.085 % (a review: it had read "4 mm², 0 %")."""
    from brakeca.design import quick_config
    from brakeca.study import _band_share

    paper = load_preset("paper")
    assert _band_share(paper) == ": the band is 1,744 mm², 34 % of the pad's 5,080 mm²"
    assert _band_share(quick_config(paper)) == ": the band is 182 mm², 3.6 % of the pad's 5,080 mm²"
    tiny = paper.with_updates({"mesh.n_radial": 5, "mesh.n_angular": 100})
    assert _band_share(tiny) == ": the band is 4.34 mm², 0.085 % of the pad's 5,080 mm²"
    assert _band_share(None) == ""


def test_the_trade_off_figure_is_coloured_by_the_factor_that_moves_v_most() -> None:
    import pandas as pd

    from brakeca.study import _strongest_on_v

    factors = [SimpleNamespace(name=n) for n in ("S", "WP", "A")]
    summary = pd.DataFrame(
        {
            "S": [0, 1, 0, 1],
            "WP": [1, 1, 2, 2],
            "A": [10, 20, 20, 10],
            "V": [1.0, 1.5, 10.0, 12.0],  # WP: x9 between its levels, S x1.23, A x1.18
            "status": ["ok"] * 4,
        }
    )
    result = SimpleNamespace(summary=summary, design=SimpleNamespace(factors=factors))
    assert _strongest_on_v(result) == "WP"
    result.summary = summary.assign(V=0.0)  # no positive means: no colouring
    assert _strongest_on_v(result) is None


def test_the_block_table_says_where_in_the_cycle_v_comes_from() -> None:
    """MU and V block by block for each run (an engineer's read: the 15 Highway stops gave
    35-70 % of the paper study's V): a row per run and block in cycle order, the block's
    stops, mean COF, mean and total emitted volume and its share of the run's."""
    import pandas as pd

    from brakeca.study import block_table

    per_stop = pd.DataFrame(
        {
            "test": [1] * 5 + [2] * 5,
            "replicate": [0] * 10,
            "A": [10.0] * 5 + [20.0] * 5,
            "seed": [7] * 5 + [8] * 5,
            "stop": [1, 2, 3, 4, 5] * 2,
            "block": ["Town", "Town", "Highway", "Highway", "Hill"] * 2,
            "mean_cof": [0.2, 0.4, 0.3, 0.3, 0.5] * 2,
            "emitted_mm3": [1.0, 3.0, 10.0, 14.0, 0.0, 0, 0, 0, 0, 0],
        }
    )
    table = block_table(per_stop)
    assert list(table.columns) == [
        "test", "replicate", "A", "seed", "block", "stops", "mean_cof", "emitted_mm3",
        "emitted_total_mm3", "share_of_emitted_percent",
    ]  # fmt: skip
    one = table[table["test"] == 1]
    assert list(one["block"]) == ["Town", "Highway", "Hill"]  # the cycle's order
    assert list(one["stops"]) == [2, 2, 1]
    np.testing.assert_allclose(one["mean_cof"], [0.3, 0.3, 0.5])
    np.testing.assert_allclose(one["emitted_mm3"], [2.0, 12.0, 0.0])
    np.testing.assert_allclose(one["share_of_emitted_percent"], [100 * 4 / 28, 100 * 24 / 28, 0])
    assert table.loc[table["test"] == 2, "share_of_emitted_percent"].isna().all()  # nothing
    assert block_table(per_stop.drop(columns="block")).empty  # a trace's cycle


def test_an_older_summary_gets_the_friction_stability_from_the_stops() -> None:
    """A campaign written before MU_SD existed gets it from campaign.nc's per-stop mean COF
    (the run's order in the summary need not be the dataset's); a failed run gets NaN, and
    a summary that has the column keeps it."""
    import pandas as pd

    from brakeca._consolidate import _with_mu_sd

    cof = np.array([[0.2, 0.4, 0.3], [0.25, 0.25, 0.25], [np.nan] * 3])
    data = xr.Dataset(
        {"mean_cof": (("run", "stop"), cof)},
        coords={"run": [1, 2, 3], "stop": [1, 2, 3], "run_id": ("run", ["a", "b", "c"])},
    )
    summary = pd.DataFrame(
        {
            "run_id": ["b", "a", "c"],
            "status": ["ok", "ok", "failed"],
            "MU": [0.25, 0.3, np.nan],
            "V": [1.0, 2.0, np.nan],
        }
    )
    out = _with_mu_sd(summary, data)
    assert list(out.columns) == ["run_id", "status", "MU", "MU_SD", "V"]
    assert out["MU_SD"].iloc[0] == 0.0
    assert out["MU_SD"].iloc[1] == np.sqrt((0.1**2 + 0.1**2 + 0.0) / 3)
    assert np.isnan(out["MU_SD"].iloc[2])
    assert "MU_SD" not in summary.columns  # the caller's frame is left as it was
    assert _with_mu_sd(out.assign(MU_SD=7.0), data)["MU_SD"].tolist() == [7.0] * 3


def test_the_notes_say_how_much_of_mu_sd_lies_between_the_blocks() -> None:
    """A review of MU_SD: in the paper's study 95 % of it lay between the blocks' means (the
    cycle's conditions), which the notes' burnish example had undersold; the share is now
    computed for the study's own runs (a failed run and a constant one left out)."""
    from brakeca.study import _block_share

    cof = np.array(
        [
            [0.2, 0.2, 0.4, 0.4],  # all between the two blocks: 100 %
            [0.2, 0.3, 0.3, 0.4],  # means 0.25, 0.35: between 0.02 of 0.04 in all, 50 %
            [0.3, 0.3, 0.3, 0.3],  # constant: no share
            [0.3, np.nan, np.nan, np.nan],  # failed: left out
        ]
    )
    data = xr.Dataset(
        {"mean_cof": (("run", "stop"), cof)},
        coords={"run": [1, 2, 3, 4], "stop": [1, 2, 3, 4], "block": ("stop", list("aabb"))},
    )
    text = _block_share(SimpleNamespace(dataset=data))
    assert text == (
        ": in the finished runs 75 % of MU_SD² (median; 50 to 100 %) lies between the blocks' mean "
        "COF (tables/by_block.csv), so MU_SD reads mostly as the friction's sensitivity to "
        "the blocks' conditions"
    )
    # each block the same two values: all of it within the blocks
    within = data.assign(mean_cof=(("run", "stop"), np.tile([0.2, 0.4, 0.2, 0.4], (4, 1))))
    assert _block_share(SimpleNamespace(dataset=within)).startswith(": in the finished runs 0 % of")
    assert _block_share(SimpleNamespace(dataset=within)).endswith(
        "drift at each block's conditions"
    )
    one = data.assign_coords(block=("stop", list("aaaa")))
    assert _block_share(SimpleNamespace(dataset=one)) == ""
    assert _block_share(SimpleNamespace(dataset=data.drop_vars("block"))) == ""


def test_mu_sd_is_analysed_only_where_a_run_has_a_spread() -> None:
    """A review of MU_SD: a study of one stop a run made an ANOVA of zeros, a regression
    equation of '+ 0' terms and four empty figures; MU_SD is left out there (and where the
    summary lacks it), and kept as soon as one finished run has a spread."""
    import pandas as pd

    from brakeca.study import RESPONSES, analysed_responses

    flat = pd.DataFrame({"status": ["ok", "ok", "failed"], "MU_SD": [0.0, 0.0, np.nan]})
    assert analysed_responses(flat) == ("MU", "V", "log10_V_mm3")
    assert analysed_responses(flat.drop(columns="MU_SD")) == ("MU", "V", "log10_V_mm3")
    assert analysed_responses(flat.assign(MU_SD=[0.0, 1e-6, np.nan])) == RESPONSES
    # a failed run's value does not count
    assert "MU_SD" not in analysed_responses(flat.assign(MU_SD=[0.0, 0.0, 0.5]))


def test_no_cube_plot_without_a_finished_run_or_for_a_factor_of_three_levels() -> None:
    """A diff review: with no factorial run finished, the cube's factors were the first
    three in the design's order, captioned as those of the largest effects."""
    import pandas as pd

    from brakeca.analysis import Factor
    from brakeca.study import _cube_factors

    factors = [Factor("S", (0.0, 1.0)), Factor("A", (10.0, 20.0)), Factor("WR", (1.0, 2.0))]
    runs = pd.DataFrame(
        {
            "S": [0.0, 1.0] * 4,
            "A": [10.0, 10.0, 20.0, 20.0] * 2,
            "WR": [1.0] * 4 + [2.0] * 4,
            "MU": [0.2, 0.2, 0.4, 0.4, 0.2, 0.21, 0.4, 0.41],
            "status": "ok",
        }
    )
    assert _cube_factors(factors, runs, "MU") == ["S", "A", "WR"]
    assert _cube_factors(factors, runs.assign(status="failed"), "MU") == []
    assert _cube_factors(factors, runs, "log10_V_mm3") == []  # V's own cube says it
    three = [*factors[:2], Factor("WR", (1.0, 1.5, 2.0))]
    assert _cube_factors(three, runs, "MU") == []  # Minitab's: every factor of two levels


def test_the_stops_note_does_not_need_the_trace_the_runs_were_made_of(monkeypatch) -> None:
    """A review: brakeca analyze failed with a traceback on a trace campaign whose trace had
    been moved or edited since (the runs hold all the analysis needs; only the --stops note
    had read the trace again, for the cycle's number of stops)."""
    from brakeca import traces
    from brakeca.study import _cut_short

    paper = load_preset("paper")
    short = paper.with_updates({"cycle.max_stops": 2})
    assert _cut_short(short) == "the first 2 of the cycle's 170 stops"
    assert _cut_short(paper) is None

    def moved(config):
        raise traces.TraceError("/somewhere/tr.csv", None, "no such file, nor a shipped cycle")

    monkeypatch.setattr(traces, "configured_cycle", moved)
    assert _cut_short(short) == "the first 2 stops of the cycle"
    assert _cut_short(paper) is None
