"""End-to-end tests of brakeca.campaign with the real simulator on tiny grids.

A 2 x 2 design (S x A) over a 5 x 100 cell band and 3 stops: each run takes well under a
second once numba's cache is warm.
"""

from __future__ import annotations

import concurrent.futures as cf
import io
import math
import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from campaign_helpers import (
    DESIGN_TEMPLATE,
    assert_same_runs,
    console_text,
    deterministic,
    drawing,
    must_not_run,
    quiet,
    rerun_reusing,
    started_as_a_job,
    tiny,
    write_design,
)
from rich.console import Console
from typer.testing import CliRunner

from brakeca._runstore import CANCELLED
from brakeca.campaign import (
    CampaignResult,
    SerialExecutor,
    finish_campaign,
    load_campaign,
    make_executor,
    run_campaign,
)
from brakeca.cli import app
from brakeca.config import ConfigError
from brakeca.design import load_design
from brakeca.results import RunResult
from brakeca.simulation import simulate

TINY = tiny(3)
DESIGN = drawing(DESIGN_TEMPLATE.format(root_seed=11))


def _mtimes(folder: Path) -> dict[str, int]:
    return {p.name: p.stat().st_mtime_ns for p in sorted(folder.glob("*.nc"))}


# top-level (picklable) simulate functions -----------------------------------------------------


def fails_on_test_3(config, *, seed, progress=None):
    """The real simulate, except that the run with S = 0.5 and A = 20 % raises."""
    if config.automaton.secondary_removal_fraction == 0.5 and config.pad.fibre_area_fraction > 0.15:
        raise RuntimeError("boom: injected failure")
    return simulate(config, seed=seed, progress=progress)


# fixtures ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def design_file(tmp_path_factory) -> Path:
    return write_design(tmp_path_factory.mktemp("design"), TINY, DESIGN)


@pytest.fixture(scope="module")
def serial(design_file, tmp_path_factory) -> CampaignResult:
    out = tmp_path_factory.mktemp("serial") / "campaign"
    return run_campaign(design_file, out, executor="serial", progress=False, console=quiet())


# tests -------------------------------------------------------------------------------------


def test_serial_campaign_runs_end_to_end(serial):
    assert serial.ok
    assert len(serial.computed) == 4 and not serial.reused and not serial.failed
    out = serial.out_dir
    for name in ("design.toml", "base_config.toml", "summary.csv", "campaign.nc"):
        assert (out / name).is_file()
    assert sorted(p.stem for p in (out / "runs").glob("*.nc")) == sorted(serial.computed)
    assert not list(out.rglob("*.tmp"))
    summary = serial.summary
    assert list(summary["test"]) == [1, 2, 3, 4]
    assert list(summary["S"]) == [0.5, 1.0, 0.5, 1.0]
    assert list(summary["A"]) == [10.0, 10.0, 20.0, 20.0]
    assert list(summary.columns[:9]) == [
        "test",
        "replicate",
        "order",
        "run_id",
        "S",
        "A",
        "seed",
        "status",
        "error",
    ]
    assert {"MU", "V", "V_mm3", "max_ledger_residual", "n_steps"} <= set(summary.columns)
    assert (summary["status"] == "ok").all()
    assert np.isfinite(summary["MU"]).all() and (summary["V"] > 0).all()
    assert summary["seed"].nunique() == 4
    # one line each, not the whole configuration and dataset
    assert (
        repr(serial) == f"CampaignResult('tiny' in {str(out)!r}: 4 runs, 4 ok, 0 failed, "
        "4 computed now, 0 reused)"
    )
    assert repr(load_campaign(out)).endswith(": 4 runs, 4 ok, 0 failed)")
    run = RunResult.from_netcdf(out / "runs" / f"{summary['run_id'][0]}.nc")
    assert repr(run) == (
        f"RunResult(seed={summary['seed'][0]}, 3 stops, 5 x 100 cells, "
        f"MU={summary['MU'][0]:.4f}, MU_SD={summary['MU_SD'][0]:.3g}, "
        f"V={summary['V_mm3'][0]:.4g} mm³ per stop)"
    )


def test_summary_and_campaign_nc_match_the_run_files(serial):
    out = serial.out_dir
    loaded = load_campaign(out)
    summary, ds = loaded.summary, loaded.dataset
    pd.testing.assert_frame_equal(summary, serial.summary, check_dtype=False, check_exact=True)
    assert ds.sizes == {"run": 4, "stop": 3, "rule": 7}
    assert list(ds["run"].values) == [1, 2, 3, 4]  # one replicate: run == test
    assert list(ds["test"].values) == [1, 2, 3, 4]
    assert list(ds["S"].values) == [0.5, 1.0, 0.5, 1.0]
    assert ds["A"].attrs["units"] == "%"
    assert list(ds["block"].values) == ["Burnish"] * 3
    # every run scalar carries its unit, as the run files' MU and V do (a helper's review)
    from brakeca.results import RUN_SCALARS

    for name in RUN_SCALARS:
        if name in ds.data_vars and ds[name].dims == ("run",):
            assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    assert (ds["V"].attrs["units"], ds["V_mm3"].attrs["units"]) == ("m3", "mm3")
    assert ds["wall_time"].attrs["units"] == "s"
    for i, row in summary.iterrows():
        run = RunResult.from_netcdf(out / "runs" / f"{row['run_id']}.nc")
        if i == 0:  # the run file explains its coordinates and attributes (a helper's walk)
            assert (
                "5: a secondary plateau whose deposit is worn through"
                in (run.dataset["rule"].attrs["rule_meanings"])
            )
            assert run.dataset["stop"].attrs["long_name"] == "stop of the drive cycle, from 1"
            assert "max_stops: the cycle's first N stops only" in run.dataset.attrs["comment"]
            assert run.dataset.attrs["paper_factors"] == (
                f"S = {row['S']:g}, WP = {run.config.wear.specific_wear_rate:g} m^3/(N m), "
                f"WR = {run.config.wear.resin_wear_depth:g} m, A = {row['A']:g} %"
            )
        assert run.seed == row["seed"] == int(ds["seed"][i])
        scalars = run.scalars()
        assert row["MU"] == scalars["MU"] == float(ds["MU"][i])
        assert row["V"] == scalars["V"] == float(ds["V"][i])
        assert row["V_mm3"] == scalars["V_mm3"]
        for name in ("mean_cof", "emitted_volume", "normal_force", "line_pressure"):
            np.testing.assert_array_equal(ds[name][i].values, run.dataset[name].values)
    # the campaign's design.toml reproduces the same runs without the original files
    again = load_design(out / "design.toml").points()
    assert [p.run_id for p in again] == list(summary["run_id"])
    assert loaded.design.factor_names == ("S", "A")


def test_friction_stability_is_the_spread_of_the_stops_mean_cof(serial, tmp_path):
    """MU_SD, the friction stability a study analyses beside MU and V, is the standard
    deviation of the run's per-stop mean COF about MU over its stops; a campaign folder
    written before the scalar existed (no MU_SD column) gets the same values when loaded."""
    summary = serial.summary
    assert list(summary.columns).index("MU_SD") == list(summary.columns).index("MU") + 1
    for _, row in summary.iterrows():
        run = RunResult.from_netcdf(serial.out_dir / "runs" / f"{row['run_id']}.nc")
        cof = run.dataset["mean_cof"].to_numpy()
        assert cof.size == 3 and np.ptp(cof) > 0  # the spread is not trivially 0 here
        by_hand = math.sqrt(sum((c - cof.mean()) ** 2 for c in cof) / cof.size)
        assert row["MU_SD"] == run.MU_SD == pytest.approx(by_hand, rel=1e-12, abs=0)
        assert row["MU"] == pytest.approx(cof.mean(), rel=1e-12, abs=0)
    old = tmp_path / "old"
    shutil.copytree(serial.out_dir, old)
    summary.drop(columns="MU_SD").to_csv(old / "summary.csv", index=False)
    serial.dataset.drop_vars("MU_SD").to_netcdf(old / "campaign.nc", engine="h5netcdf")
    loaded = load_campaign(old).summary
    np.testing.assert_array_equal(loaded["MU_SD"], summary["MU_SD"])
    assert list(loaded.columns) == list(summary.columns)


def test_local_executor_gives_identical_values(serial, design_file, tmp_path):
    local = run_campaign(
        design_file,
        tmp_path / "local",
        executor="local",
        workers=2,
        progress=False,
        console=quiet(),
    )
    assert local.ok and len(local.computed) == 4
    # the S = 0.5 runs drew on the generator between stops: a worker that re-seeded or
    # shared it would differ here
    assert local.dataset["secondary_removed_between_stops"][[0, 2]].sum() > 0
    assert_same_runs(local, serial)


def test_progress_in_a_log_file_is_one_line_per_run(serial, design_file, tmp_path):
    """Without a terminal (a log file) there is no live bar: a line when the campaign starts
    and one per finished run, with its time and responses."""
    # not a terminal; 80 columns, rich's width for a file, narrower than a run's line
    console = Console(file=io.StringIO(), width=80)
    out = tmp_path / "logged"
    shutil.copytree(serial.out_dir, out)
    (out / "runs" / f"{serial.summary.run_id[0]}.nc").unlink()  # one run left to do
    run_campaign(design_file, out, executor="serial", progress=True, console=console)
    lines = console_text(console).splitlines()
    assert "1 of 4 run(s) to compute (3 already done)" in lines
    mu = serial.summary.MU[0]
    done = [line for line in lines if line.startswith("run 4/4 done: test 1, replicate 0")]
    assert len(done) == 1 and f"MU {mu:.4f}" in done[0] and done[0].endswith("mm³/stop")
    assert not [line for line in lines if "━" in line or "ETA" in line]  # no bar at the end


def test_rerun_skips_every_run(serial, tmp_path):
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    before = _mtimes(out / "runs")

    def rerun() -> tuple[CampaignResult, str]:
        return rerun_reusing(out, progress=True)

    again, text = rerun()
    assert sorted(again.reused) == sorted(serial.computed)
    assert not again.computed and not again.failed
    assert _mtimes(out / "runs") == before
    assert "nothing to compute" in text
    assert "belong to no run of this design" not in text
    assert "design.toml:" not in text  # its own design: nothing replaced
    pd.testing.assert_frame_equal(again.summary, serial.summary, check_exact=True)
    # A run file of an earlier design in the folder is left alone, not analysed, and said.
    old = out / "runs" / "00000000deadbeef.nc"
    shutil.copyfile(out / "runs" / f"{serial.summary.run_id[0]}.nc", old)
    third, text = rerun()
    assert "1 run file(s) in" in text and "belong to no run of this design" in text
    assert old.exists()
    pd.testing.assert_frame_equal(third.summary, serial.summary, check_exact=True)


def test_a_design_that_replaces_the_folders_design_says_how(serial, tmp_path):
    """A cluster review: a level changed, between a campaign's kill and its resume, for runs
    not yet begun was taken and design.toml replaced without a word. A design that keeps
    every run of the folder's is still taken, and the campaign says what changed."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    more = out / "more.toml"  # beside base_config.toml, which it names
    text = (out / "design.toml").read_text(encoding="utf-8")
    assert "\nreplicates = 1\n" in text
    more.write_text(text.replace("\nreplicates = 1\n", "\nreplicates = 2\n"))
    console = quiet()
    result = run_campaign(more, out, executor="serial", progress=False, console=console)
    assert result.ok and len(result.reused) == 4 and len(result.computed) == 4
    said = " ".join(console_text(console).split())
    assert "design.toml: this design replaces the folder's (replicates 1 -> 2)" in said
    assert "replicates = 2" in (out / "design.toml").read_text(encoding="utf-8")
    # a level changed (as for runs not yet begun), and a factor's key added
    from brakeca._runstore import design_changes
    from brakeca.design import load_design

    a_factor = (
        '    20.0,\n]\nscale = 0.01\nlabels = [\n    "-",\n    "+",\n]\nunit = "%"\nlabel = ""'
    )
    assert a_factor in text
    other = out / "other.toml"
    other.write_text(text.replace(a_factor, a_factor.replace("20.0", "25.0") + '\ncoding = "log"'))
    assert design_changes(out, load_design(other)) == (
        "replicates 2 -> 1; A's coding (unset) -> 'log'; A's levels [10.0, 20.0] -> [10.0, 25.0]"
    )
    # a design.toml it cannot read, or one that differs in layout alone: nothing to say
    odd = tmp_path / "odd"
    odd.mkdir()
    for content in (b"factors = 1\n", b"factors = ['A']\n", b"\xff\xfe", b"name = \n"):
        (odd / "design.toml").write_bytes(content)
        assert design_changes(odd, load_design(other)) == ""
    (odd / "design.toml").write_text("# another comment\n" + other.read_text())
    assert design_changes(odd, load_design(other)) == ""
    # a run table said by its size, not written out (a diff review: two composite designs'
    # tables made a refusal of 1,700 characters)
    from brakeca._runstore import _table_changes

    runs = [{"A": 10.0}, {"A": 20.0}]
    assert _table_changes({"runs": runs}, {"runs": [*runs, {"A": 15.0}]}) == (
        "the run table's 2 tests -> 3 tests"
    )
    assert _table_changes({}, {"runs": runs[:1]}) == "the run table's (unset) -> 1 test"


def test_a_folder_of_other_options_is_not_replaced_unless_asked(serial, tmp_path):
    """A campaign rerun with other options (here fewer stops: a --stops) into a finished
    campaign's folder would replace its summary and report: refused before anything is
    written, naming what differs; with replace=True it runs, and the first campaign's run
    files stay, so its own command brings its study back without computing anything."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    design = load_design(out / "design.toml")
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and p.suffix != ".lock"}
    with pytest.raises(ConfigError) as info:
        run_campaign(design, out, executor="serial", max_stops=2, progress=False, console=quiet())
    message = str(info.value)
    assert "holds a campaign of another base configuration (cycle.max_stops: 3 -> 2)" in message
    assert "--replace; replace=True from Python" in message
    assert {
        p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and p.suffix != ".lock"
    } == before
    two = run_campaign(
        design, out, executor="serial", max_stops=2, progress=False, console=quiet(), replace=True
    )
    assert two.ok and len(two.computed) == 4 and len(list((out / "runs").glob("*.nc"))) == 8
    back = run_campaign(
        design,
        out,
        executor="serial",
        max_stops=3,
        simulate_fn=must_not_run,
        progress=False,
        console=quiet(),
        replace=True,
    )
    pd.testing.assert_frame_equal(back.summary, serial.summary, check_exact=True)


def test_a_design_that_leaves_out_the_folders_runs_is_not_run_there_unless_asked(serial, tmp_path):
    """A robustness review: an unrelated design run into a finished campaign's folder (same
    base configuration) replaced its summary, campaign.nc, design and report with one dim
    line. It is refused now, naming the study there; a design that keeps every run of it and
    adds others (more replicates here; a fold-over) takes the folder over, computing only
    the new runs."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    for name in ("other", "more"):
        (tmp_path / name).mkdir()
    other = write_design(tmp_path / "other", TINY, DESIGN_TEMPLATE.format(root_seed=12))
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and p.suffix != ".lock"}
    with pytest.raises(ConfigError) as info:
        run_campaign(other, out, executor="serial", progress=False, console=quiet())
    assert "holds the study of another design (design 'tiny', 4 runs, 4 of them not in this" in (
        str(info.value)
    )
    assert {
        p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and p.suffix != ".lock"
    } == before
    more = write_design(
        tmp_path / "more",
        TINY,
        DESIGN.replace("root_seed = 11\n", "root_seed = 11\nreplicates = 2\n"),
    )
    bigger = run_campaign(more, out, executor="serial", progress=False, console=quiet())
    assert len(bigger.reused) == 4 and len(bigger.computed) == 4 and bigger.ok
    # its two seeds per test give brakeca power the seed-to-seed scatter
    by_test = bigger.summary.groupby("test")["MU"]
    pooled = math.sqrt(float(((bigger.summary["MU"] - by_test.transform("mean")) ** 2).sum()) / 4)
    res = CliRunner().invoke(
        app, ["power", str(more), "--effect", "0.01", "--sigma-from", str(out)]
    )
    assert res.exit_code == 0, res.output
    said = " ".join(res.output.split())
    assert f"sigma: {pooled:.4g}, the pure error of MU in {out}, with 4 degrees of" in said
    # how well 4 df know it: the chi-square interval, and that it is rough (a user's review)
    from scipy import stats

    low = pooled * math.sqrt(4 / stats.chi2.ppf(0.975, 4))
    high = pooled * math.sqrt(4 / stats.chi2.ppf(0.025, 4))
    assert f"(95 % interval {low:.3g} to {high:.3g}): a rough figure, and the power" in said
    replaced = run_campaign(
        other, out, executor="serial", progress=False, console=quiet(), replace=True
    )
    assert replaced.ok and len(replaced.computed) == 4


def _levels_of_a(levels: str) -> str:
    """The design with A's levels ``levels`` (and no labels)."""
    return DESIGN.replace("levels = [10.0, 20.0]", f"levels = {levels}").replace(
        'scale = 0.01\nlabels = ["-", "+"]', "scale = 0.01"
    )


def test_a_level_added_says_why_the_finished_runs_are_not_this_designs(serial, tmp_path):
    """A black-box review: a level added in the middle of a factor was refused as 'another
    design', with no word of why every old level's runs were 'not in this one' (the tests
    are numbered anew, and a run's seed follows its test number). The refusal says so now;
    a level after the last level of the last factor keeps every run."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    for name in ("middle", "after"):
        (tmp_path / name).mkdir()
    middle = write_design(tmp_path / "middle", TINY, _levels_of_a("[10.0, 15.0, 20.0]"))
    with pytest.raises(ConfigError) as info:
        run_campaign(middle, out, executor="serial", progress=False, console=quiet())
    text = " ".join(str(info.value).split())
    # what differs, as a design that extends the study is told (a growth review: counts
    # alone were said)
    assert (
        "(design 'tiny', 4 runs, 2 of them not in this one; this design differs from it in "
        "A's labels ['-', '+'] -> (unset); A's levels [10.0, 20.0] -> [10.0, 15.0, 20.0])" in text
    )
    assert "2 of the runs left out are configurations this design also runs, under other" in text
    assert "a level after the last level of the last factor) needs neither" in text

    def refusal(name: str, design_text: str) -> str:
        """The refusal of a campaign of ``design_text`` into ``out``, whitespace folded."""
        (tmp_path / name).mkdir()
        with pytest.raises(ConfigError) as info:
            run_campaign(
                write_design(tmp_path / name, TINY, design_text),
                out,
                executor="serial",
                progress=False,
                console=quiet(),
            )
        return " ".join(str(info.value).split())

    # another root seed keeps the test numbers: its runs are not 'under other test numbers'
    text = refusal("seed", DESIGN.replace("root_seed = 11", "root_seed = 12"))
    # (a new user's review: the count alone did not say why)
    assert "4 of them not in this one; its root_seed is 11, this design's 12: every run's" in text
    assert "under other test numbers" not in text
    # a design of A alone (S at the base's 0): the runs there ran S at 0.5 and 1, so none
    # of them is a configuration it runs, whatever their levels of A (a new user's review:
    # the count had compared A alone, and said 3 were 'under other test numbers')
    a_only = (
        DESIGN[: DESIGN.index("[[factors]]")] + DESIGN[DESIGN.index('[[factors]]\nname = "A"') :]
    )
    text = refusal("a_only", a_only)
    assert "(design 'tiny', 4 runs, 4 of them not in this one; this design differs from it " in text
    assert "in factor S removed)" in text and "under other test numbers" not in text
    # the factors in another order: said, and why that numbers the tests anew
    swapped = (
        DESIGN[: DESIGN.index("[[factors]]")]
        + DESIGN[DESIGN.index('[[factors]]\nname = "A"') :]
        + "\n"
        + DESIGN[DESIGN.index("[[factors]]") : DESIGN.index('[[factors]]\nname = "A"')]
    )
    text = refusal("swapped", swapped)
    assert "this design differs from it in the factors' order S, A -> A, S)" in text
    assert "the factors put in another order" in text
    after = write_design(tmp_path / "after", TINY, _levels_of_a("[10.0, 20.0, 30.0]"))
    bigger = run_campaign(after, out, executor="serial", progress=False, console=quiet())
    assert bigger.ok and len(bigger.reused) == 4 and len(bigger.computed) == 2


def test_corrupt_and_foreign_run_files_are_recomputed(serial, tmp_path):
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    ids = list(serial.summary["run_id"])
    runs = out / "runs"
    truncated, garbage, foreign = (runs / f"{i}.nc" for i in ids[:3])
    data = truncated.read_bytes()
    truncated.write_bytes(data[: len(data) // 2])
    garbage.write_bytes(b"this is not a netCDF file\n" * 10)
    shutil.copyfile(runs / f"{ids[3]}.nc", foreign)  # a valid run file under the wrong name
    untouched = (runs / f"{ids[3]}.nc").stat().st_mtime_ns
    console = quiet()
    result = run_campaign(
        load_design(out / "design.toml"), out, executor="serial", progress=False, console=console
    )
    text = console_text(console)
    for rid in ids[:3]:
        assert rid in text
    assert text.count("recomputing") == 3
    assert "cannot be read" in text and "belongs to another run" in text
    assert sorted(result.recomputed) == sorted(ids[:3])
    assert sorted(result.computed) == sorted(ids[:3])
    assert result.reused == (ids[3],)
    assert (runs / f"{ids[3]}.nc").stat().st_mtime_ns == untouched
    pd.testing.assert_frame_equal(
        deterministic(result.summary), deterministic(serial.summary), check_exact=True
    )
    for rid in ids[:3]:
        assert RunResult.from_netcdf(runs / f"{rid}.nc").seed in set(serial.summary["seed"])


def test_run_files_of_other_shapes_or_non_finite_results_are_recomputed(serial, tmp_path):
    """A security review: a resume reused a run file on its seed and configuration alone,
    so one of MU = NaN went into summary.csv, and one of other statuses ended the resume with
    a traceback; both are now recomputed, with the reason named."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    ids = list(serial.summary["run_id"])
    runs = out / "runs"
    nan_mu, bad_status = (runs / f"{i}.nc" for i in ids[:2])
    for path, damage in ((nan_mu, "MU"), (bad_status, "final_status")):
        ds = xr.load_dataset(path, engine="h5netcdf")
        if damage == "MU":
            ds["MU"] = ds["MU"] * np.nan
        else:
            ds["final_status"][:] = 9
        ds.to_netcdf(path, engine="h5netcdf")
    console = quiet()
    result = run_campaign(
        load_design(out / "design.toml"), out, executor="serial", progress=False, console=console
    )
    text = " ".join(console_text(console).split())
    assert "'MU' is not finite" in text
    assert "'final_status' holds statuses other than 0, 1 and 2" in text
    assert sorted(result.recomputed) == sorted(ids[:2]) and len(result.reused) == 2
    pd.testing.assert_frame_equal(
        deterministic(result.summary), deterministic(serial.summary), check_exact=True
    )


def test_failed_run_is_recorded_and_others_continue(serial, design_file, tmp_path):
    out = tmp_path / "campaign"
    console = quiet()
    result = run_campaign(
        design_file,
        out,
        executor="serial",
        simulate_fn=fails_on_test_3,
        progress=False,
        console=console,
    )
    summary = result.summary
    assert list(summary["status"]) == ["ok", "ok", "failed", "ok"]
    assert "RuntimeError: boom: injected failure" in summary.loc[2, "error"]
    assert np.isnan(summary.loc[2, "MU"])
    assert not result.ok and len(result.failed) == 1 and len(result.computed) == 3
    assert "run failed" in console_text(console) and "1 of 4 run(s) failed" in console_text(console)
    assert not (out / "runs" / f"{summary.loc[2, 'run_id']}.nc").exists()
    assert np.isnan(result.dataset["mean_cof"][2]).all()
    assert str(result.dataset["status"][2].values) == "failed"
    loaded = load_campaign(out)
    assert list(loaded.summary["status"]) == ["ok", "ok", "failed", "ok"]
    assert loaded.summary.loc[2, "error"] == summary.loc[2, "error"]
    # a loaded campaign's failed runs are in failed (empty, `if loaded.failed` had said none
    # failed: an API review); what the campaign computed is not kept
    assert loaded.failed == result.failed and not loaded.computed and not loaded.ok
    # a test's run file by its number (an API review built the path from the summary)
    assert loaded.run(2).MU == summary.loc[1, "MU"]
    with pytest.raises(ValueError, match="test 3, replicate 0 failed: RuntimeError: boom"):
        loaded.run(3)
    with pytest.raises(KeyError, match="test 9, replicate 0: not a run of this campaign"):
        loaded.run(9)
    with pytest.raises(TypeError, match=r"^test: expected a whole number .* got '2'$"):
        loaded.run("2")  # it had said test 2 was not a run of the campaign (an API review)
    assert loaded.run(np.int64(2)).MU == loaded.run(2).MU == loaded.run(np.float64(2.0)).MU
    with pytest.raises(TypeError, match=r"^test: expected a whole number .* got 2.5$"):
        loaded.run(2.5)
    with pytest.raises(KeyError, match=r"test 2, replicate 5: .* \(test 2's replicates: 0\)"):
        loaded.run(2, replicate=5)
    # a second pass computes only the failed run
    healed = run_campaign(design_file, out, executor="serial", progress=False, console=quiet())
    assert healed.ok and healed.computed == (summary.loc[2, "run_id"],) and len(healed.reused) == 3
    pd.testing.assert_frame_equal(
        deterministic(healed.summary), deterministic(serial.summary), check_exact=True
    )


def test_runs_made_by_other_kernel_sources_are_reused_with_a_note(serial, tmp_path):
    """A provenance review: the version (0.1.0) never changed, so a folder of runs made by
    code that computed other last bits was reused without a word. A run file records its
    kernels' sources, libraries and date; a run made by other sources is named on reuse."""
    import platform

    from brakeca._cachedir import source_key
    from brakeca.results import write_atomic

    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    rid = serial.summary["run_id"][1]
    run = RunResult.from_netcdf(out / "runs" / f"{rid}.nc").dataset
    assert run.attrs["source_key"] == source_key()
    assert run.attrs["software"].startswith(f"Python {platform.python_version()}, numpy ")
    assert run.attrs["date_created"].endswith("+00:00")
    write_atomic(run.load().assign_attrs(source_key="0123456789abcdef"), out / "runs" / f"{rid}.nc")
    header = (out / "base_config.toml").read_text(encoding="utf-8").split("\nquick")[0]
    assert "tiny_base.toml'" in header  # the base configuration the design named
    console = quiet()
    again = run_campaign(
        out / "design.toml", out, executor="serial", simulate_fn=must_not_run, console=console
    )
    assert again.ok and len(again.reused) == 4
    # the folder's own base configuration keeps its header, which says where it came from
    # (it had become "From '<this file>'; overrides {}": the same review)
    assert (out / "base_config.toml").read_text(encoding="utf-8").startswith(header + "\nquick")
    run_campaign(  # and with the first campaign's options again (a diff review)
        out / "design.toml", out, executor="serial", max_stops=3, simulate_fn=must_not_run,
        console=quiet(),
    )  # fmt: skip
    assert (out / "base_config.toml").read_text(encoding="utf-8").startswith(header + "\nquick")
    text = " ".join(console_text(console).split())
    assert f"note: 1 finished run(s) (of test {serial.summary['test'][1]}) were made by other " in (
        text
    )
    assert f"(source_key {source_key()}; the run files record theirs, or, made before" in text


class _CancelsTheThirdRun(SerialExecutor):
    """The caller's executor, on which someone else cancels the third run submitted (as
    another client or the dashboard can on a shared dask cluster)."""

    submitted = 0

    def submit(self, fn, /, *args, **kwargs):
        self.submitted += 1
        if self.submitted == 3:
            future: cf.Future = cf.Future()
            future.cancel()
            future.set_running_or_notify_cancel()  # as an executor does: wait() sees it then
            return future
        return super().submit(fn, *args, **kwargs)


def test_a_run_cancelled_outside_the_campaign_says_so_and_is_run_again(
    serial, design_file, tmp_path
):
    out = tmp_path / "campaign"
    console = quiet()
    result = run_campaign(design_file, out, executor=_CancelsTheThirdRun(), console=console)
    summary = result.summary
    assert sorted(summary["status"]) == ["failed", "ok", "ok", "ok"]
    failed = summary[summary["status"] == "failed"].iloc[0]
    # it had read "the run was cancelled", which did not say by whom nor what to do
    assert failed["error"] == CANCELLED
    assert "not by this campaign" in CANCELLED and "running the campaign again runs it" in CANCELLED
    assert "not by this campaign" in console_text(console)
    healed = run_campaign(design_file, out, executor="serial", progress=False, console=quiet())
    assert healed.ok and healed.computed == (failed["run_id"],)
    pd.testing.assert_frame_equal(
        deterministic(healed.summary), deterministic(serial.summary), check_exact=True
    )


KILLED_WHILE_WRITING_THE_SECOND_RUN = """\
import os, pathlib, signal, sys
from brakeca.campaign import run_campaign

write_bytes = pathlib.Path.write_bytes
run_files = 0

def dies_in_the_second_run_file(self, data):
    global run_files
    if self.parent.name == "runs" and self.name.endswith(".tmp"):
        run_files += 1
        if run_files == 2:  # half the file on disk, then the process is gone
            write_bytes(self, data[: len(data) // 2])
            os.kill(os.getpid(), signal.SIGKILL)
    return write_bytes(self, data)

pathlib.Path.write_bytes = dies_in_the_second_run_file
run_campaign(sys.argv[1], sys.argv[2], executor="serial", progress=False)
"""


def test_sigkill_halfway_then_resume(serial, design_file, tmp_path):
    """A campaign SIGKILLed while it writes its second run file keeps the first run's
    complete file, and no part of the second under a run file's name; the next campaign
    removes the half-written temporary file, reuses the first run and computes the rest,
    bit-identical to a campaign that ran through. (The child kills itself inside the write:
    the test had raced a campaign of tiny runs with a kill from outside, which could come
    after the campaign had finished, and did not reach the write.)"""
    out = tmp_path / "campaign"
    script = tmp_path / "killed_while_writing.py"
    script.write_text(KILLED_WHILE_WRITING_THE_SECOND_RUN, encoding="utf-8")
    cmd = [sys.executable, str(script), str(design_file), str(out)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == -signal.SIGKILL, done.stderr
    assert not (out / "summary.csv").exists()
    finished = _mtimes(out / "runs")
    assert len(finished) == 1
    for name in finished:
        RunResult.from_netcdf(out / "runs" / name)  # complete files only, never a partial one
    (half,) = (out / "runs").glob(".*.tmp")  # the second run's, cut off
    with pytest.raises(ValueError, match="not a readable netCDF file"):
        RunResult.from_netcdf(half)

    resumed = run_campaign(design_file, out, executor="serial", progress=False, console=quiet())
    assert resumed.ok
    assert sorted(f"{r}.nc" for r in resumed.reused) == sorted(finished)
    assert len(resumed.computed) == 4 - len(finished)
    after = _mtimes(out / "runs")
    assert {k: after[k] for k in finished} == finished
    assert not list(out.rglob("*.tmp"))
    assert_same_runs(resumed, serial)


def test_replicates_layout_and_randomized_order(design_file, tmp_path):
    design = load_design(design_file).model_copy(update={"replicates": 2, "randomize_order": True})
    result = run_campaign(
        design,
        tmp_path / "campaign",
        executor="serial",
        max_stops=2,
        progress=False,
        console=quiet(),
    )
    assert result.ok
    summary, ds = result.summary, result.dataset
    assert list(summary["test"]) == [1, 1, 2, 2, 3, 3, 4, 4]
    assert list(summary["replicate"]) == [0, 1] * 4
    assert sorted(summary["order"]) == list(range(1, 9))
    assert ds.sizes["run"] == 8 and ds.sizes["stop"] == 2
    assert list(ds["run"].values) == list(range(1, 9))
    assert list(ds["test"].values) == [1, 1, 2, 2, 3, 3, 4, 4]
    assert list(ds["replicate"].values) == [0, 1] * 4
    assert summary["seed"].nunique() == 8
    # replicates of a test share factor levels, not results
    assert summary.loc[0, "MU"] != summary.loc[1, "MU"]


def test_finish_campaign_calls_each_step(serial):
    seen: list[CampaignResult] = []
    result = finish_campaign(serial.out_dir, steps=[seen.append, seen.append])
    assert len(seen) == 2 and seen[0] is result
    assert list(result.summary["run_id"]) == list(serial.summary["run_id"])


def test_load_campaign_of_an_unfinished_directory(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such folder"):
        load_campaign(tmp_path / "nowhere")
    (tmp_path / "afile").write_text("")
    with pytest.raises(FileNotFoundError, match=r"afile: not a folder \(a file\)"):
        load_campaign(tmp_path / "afile")
    with pytest.raises(FileNotFoundError, match=r"not a campaign folder \(no design.toml"):
        load_campaign(tmp_path)
    (tmp_path / "design.toml").write_text("")
    hint = f"has not finished: 'brakeca run {tmp_path / 'design.toml'} -o {tmp_path}' finishes"
    with pytest.raises(FileNotFoundError, match=re.escape(hint)):
        load_campaign(tmp_path)


def test_a_damaged_summary_is_not_analysed(serial, tmp_path):
    """A robustness review: a summary.csv cut short, or with a row deleted, was analysed as
    it was (a run with no level, three runs of four) with no word. Read against campaign.nc
    and the design, it is refused, with the command that writes it again."""
    text = (serial.out_dir / "summary.csv").read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    for damaged, problem in (
        ("".join(lines[:3] + lines[4:]), "its 3 runs are not the 4 of campaign.nc"),
        ("".join(lines[:1] + lines[2:] + lines[1:2]), "its runs are not those of campaign.nc"),
        (text[: len(text) - len(lines[-1]) + 30], "not 'ok' or 'failed'"),
    ):
        out = tmp_path / "campaign"
        shutil.rmtree(out, ignore_errors=True)
        shutil.copytree(serial.out_dir, out)
        (out / "summary.csv").write_text(damaged, encoding="utf-8")
        with pytest.raises(ValueError, match=re.escape(problem)) as info:
            load_campaign(out)
        assert f"'brakeca run {out / 'design.toml'} -o {out}' writes it again" in str(info.value)
    rebuilt = run_campaign(
        out / "design.toml", out, executor="serial", progress=False, console=quiet()
    )
    assert len(rebuilt.reused) == 4
    pd.testing.assert_frame_equal(load_campaign(out).summary, serial.summary, check_exact=True)


def test_make_executor():
    with make_executor("serial") as ex:
        assert isinstance(ex, SerialExecutor)
        assert ex.submit(pow, 2, 10).result() == 1024
        assert isinstance(ex.submit(int, "x").exception(), ValueError)
    with pytest.raises(ValueError, match="unknown executor"):
        make_executor("cluster")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="at least 1"):
        make_executor("local", 0)
    with make_executor("local", 1) as ex:
        assert ex.submit(os.getenv, "NUMBA_NUM_THREADS").result() == "1"


def test_a_dask_client_executor_plugs_in(serial, design_file, tmp_path):
    """The executor seam: any concurrent.futures executor, e.g. dask's, runs a campaign."""
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        result = run_campaign(
            design_file,
            tmp_path / "dask",
            executor=client.get_executor(),
            workers=2,
            progress=False,
            console=quiet(),
        )
    assert result.ok and len(result.computed) == 4
    assert_same_runs(result, serial)  # runs as threads of this process: bit-identical too


def test_bad_arguments_fail_before_anything_is_written(design_file, tmp_path):
    out = tmp_path / "never"
    with pytest.raises(ValueError, match="unknown executor"):
        run_campaign(design_file, out, executor="cluster", progress=False)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="at least 1"):
        run_campaign(design_file, out, workers=0, progress=False)
    # 2.5 was taken as 2, "a" got int()'s message (a fuzz review)
    for workers in (2.5, "a", True):
        expected = f"workers: expected a whole number at least 1, got {workers!r}"
        with pytest.raises(ValueError, match=re.escape(expected)):
            run_campaign(design_file, out, workers=workers, progress=False)  # type: ignore[arg-type]
        with pytest.raises(ValueError, match="workers: expected a whole number"):
            make_executor("local", workers=workers)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="max_retries: expected a whole number at least 0"):
        run_campaign(design_file, out, max_retries="2", progress=False)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"mesh\.n_radial"):
        run_campaign(design_file, out, overrides={"mesh.n_radial": 0}, progress=False)
    with pytest.raises(ConfigError, match="max_stops"):
        run_campaign(design_file, out, max_stops=0, progress=False)
    assert not out.exists()
    a_file = tmp_path / "a_file"
    a_file.write_text("keep me")
    with pytest.raises(ConfigError, match="exists and is not a folder"):
        run_campaign(design_file, a_file, progress=False)
    assert a_file.read_text() == "keep me"


def test_a_script_without_a_main_guard_runs_its_campaign_once(tmp_path):
    """multiprocessing's "spawn" runs the parent's main script again in every worker; a
    script that called run_campaign at its top level then started a campaign in each worker,
    which failed on the campaign's lock, and every run failed. brakeca's workers no longer run
    the caller's main module."""
    # a 2 x 2 design: four runs on two workers show it as the paper's 24 did (a review of
    # the suite's time)
    (tmp_path / "tiny.toml").write_text(
        'name = "tiny"\nbase = "paper"\nroot_seed = 5\n'
        '[[factors]]\nname = "S"\nlevels = [0.0, 1.0]\n'
        '[[factors]]\nname = "A"\nlevels = [10.0, 20.0]\n'
    )
    script = tmp_path / "study.py"
    script.write_text(
        "from brakeca.campaign import run_campaign\n"
        "print('top level ran', flush=True)\n"
        "result = run_campaign(\n"
        "    'tiny.toml', 'c', workers=2, max_stops=1, progress=False,\n"
        "    overrides={'mesh.n_radial': 3, 'mesh.n_angular': 100},\n"
        ")\n"
        "print('ok runs', int((result.summary.status == 'ok').sum()), flush=True)\n"
    )
    done = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["top level ran", "ok runs 4"], done.stdout
    assert "Traceback" not in done.stderr and "another campaign" not in done.stderr


def test_a_dask_clients_executor_gets_no_more_runs_than_workers() -> None:
    """A dask worker's death is charged to every run it holds, waiting ones too: a client's
    executor gets ``workers`` runs in flight, another executor twice that (docs/cluster.md;
    a helper's review found the doc's 'workers' untrue for the client's executor)."""
    import concurrent.futures as cf

    from brakeca._executors import _backend

    class ClientExecutor(cf.Executor):  # stands for distributed.cfexecutor.ClientExecutor
        pass

    ClientExecutor.__module__ = "distributed.cfexecutor"
    kw = {"scheduler": None, "scheduler_file": None, "max_retries": 2}
    assert _backend(ClientExecutor(), 3, 10, **kw).window == 3
    distributed = pytest.importorskip("distributed")
    real = distributed.cfexecutor.ClientExecutor  # where dask's own lives
    assert real.__module__.split(".")[0] == "distributed"
    with cf.ThreadPoolExecutor(2) as pool:
        assert _backend(pool, 3, 10, **kw).window == 6


def test_an_edited_value_of_the_summary_is_named(serial, tmp_path):
    """A level, a response or a test number edited by hand (a spreadsheet's decimal comma,
    text, a level the design lacks) had reached the analysis as it was, or as a traceback
    (a helper's fuzzing): every value campaign.nc holds per run is checked, and the first
    that differs is named."""
    import csv

    text = (serial.out_dir / "summary.csv").read_text(encoding="utf-8")
    rows = list(csv.reader(io.StringIO(text)))
    header = rows[0]
    first = dict(zip(header, rows[1], strict=True))
    for column, value, problem in (
        ("S", "0.25", f"its S in row 1 is 0.25, where campaign.nc has {float(first['S'])!r}"),
        ("A", "10,0", "its A in row 1 is '10,0', where campaign.nc has 10.0"),
        ("MU", "high", "its MU in row 1 is 'high', where campaign.nc has"),
        ("test", "one", "its test in row 1 is 'one', where campaign.nc has 1"),
        ("MU", None, "its column MU is missing"),
    ):
        edited = [list(r) for r in rows]
        k = header.index(column)
        if value is None:
            edited = [r[:k] + r[k + 1 :] for r in edited]
        else:
            edited[1][k] = value
        buffer = io.StringIO()
        csv.writer(buffer, lineterminator="\n").writerows(edited)
        out = tmp_path / "campaign"
        shutil.rmtree(out, ignore_errors=True)
        shutil.copytree(serial.out_dir, out)
        (out / "summary.csv").write_text(buffer.getvalue(), encoding="utf-8")
        with pytest.raises(ValueError, match=re.escape(problem)):
            load_campaign(out)
    pd.testing.assert_frame_equal(
        load_campaign(serial.out_dir).summary, serial.summary, check_exact=True
    )


def test_plots_of_a_campaign_dataset_read_its_factors(serial):
    """``campaign.nc`` opened with xarray is drawn as the CampaignResult is, its factors read
    from the factor coordinates' attributes; ``ds.design`` (the design's text) had raised
    AttributeError in plot_mu_per_stop (an API review)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.text import Text

    from brakeca.plotting import plot_mu_per_stop, plot_mu_per_stop_by_level

    with xr.open_dataset(serial.out_dir / "campaign.nc") as ds:
        assert isinstance(ds.attrs["design"], str)
        for plot in (plot_mu_per_stop, plot_mu_per_stop_by_level):
            texts = [
                [t.get_text() for t in fig.findobj(Text) if t.get_text()]
                for fig in (plot(ds.load()), plot(serial))
            ]
            assert texts[0] == texts[1]
            assert any("S+" in t or t == "+" for t in texts[0])  # the factors' labels


def test_analyze_in_a_folder_it_cannot_write_fails_cleanly(serial, tmp_path, monkeypatch):
    """``brakeca analyze`` on a read-only folder ended in a traceback from the first table
    it wrote (a robustness review; as root, permission bits do not refuse, so the read-only
    file system is stood in for here). It is refused before the summary is printed, and a
    write that fails later (a full disk) is one clean error."""
    import errno
    import tempfile

    folder = tmp_path / "copy"
    shutil.copytree(serial.out_dir, folder)
    real = tempfile.TemporaryFile

    def read_only(*args, dir=None, **kwargs):
        if dir is not None and Path(dir) == folder:
            raise OSError(errno.EROFS, "Read-only file system")
        return real(*args, dir=dir, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(tempfile, "TemporaryFile", read_only)
        res = CliRunner().invoke(app, ["analyze", str(folder)])
    assert res.exit_code == 2, res.output
    text = " ".join(res.output.split())
    assert f"error: {folder}: cannot write in it (Read-only file system); the analysis" in text
    assert "Traceback" not in res.output and not (folder / "tables" / "x").exists()

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(folder / "tables" / "a.csv"))

    monkeypatch.setattr("brakeca.study.write_study", full)
    res = CliRunner().invoke(app, ["analyze", str(folder)])
    assert res.exit_code == 2, res.output
    text = " ".join(res.output.split())
    assert f"{folder / 'tables' / 'a.csv'}: cannot write it (No space left on device); the " in text


def test_a_replace_stopped_before_its_summary_leaves_the_folders_study_whole(
    serial, tmp_path, monkeypatch
):
    """A --replace campaign wrote its design.toml and base_config.toml before any run, so one
    that failed or was stopped (an unreachable scheduler, Ctrl-C) left the folder's summary
    under another design, which analyze reported as the new one and the first design could
    not take back (a robustness review). They are written with the summary now; a study
    that replaces the folder's removes the analysis of the old one, and analyze notes a
    campaign writing the folder."""
    from brakeca import _runstore

    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    (out / "report.html").write_text("the old study's report", encoding="utf-8")
    (out / "tables").mkdir(exist_ok=True)
    (tmp_path / "other").mkdir()
    other = write_design(tmp_path / "other", TINY, DESIGN_TEMPLATE.format(root_seed=12))
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and p.suffix != ".lock"}

    def stopped(config, *, seed, progress=None, maps_at=()):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_campaign(
            other, out, executor="serial", simulate_fn=stopped, progress=False,
            console=quiet(), replace=True,
        )  # fmt: skip
    after = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and p.suffix != ".lock"}
    assert after == before  # design.toml, base_config.toml, summary.csv, report.html
    # a first campaign in a new folder writes them at once: stopped, it resumes from them
    fresh = tmp_path / "fresh"
    with pytest.raises(KeyboardInterrupt):
        run_campaign(
            other, fresh, executor="serial", simulate_fn=stopped, progress=False, console=quiet()
        )
    assert "root_seed = 12" in (fresh / "design.toml").read_text(encoding="utf-8")
    assert (fresh / "base_config.toml").is_file() and not (fresh / "summary.csv").exists()
    replaced = run_campaign(
        other, out, executor="serial", progress=False, console=(console := quiet()), replace=True
    )
    assert replaced.ok and len(replaced.computed) == 4
    assert "root_seed = 12" in (out / "design.toml").read_text(encoding="utf-8")
    assert not (out / "report.html").exists() and not (out / "tables").exists()
    said = " ".join(console_text(console).split())
    assert "removed the earlier study's analysis (report.html, tables/" in said
    # the same runs again: nothing of the analysis is removed
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    rerun_reusing(out, progress=False)
    assert (out / "report.html").read_text(encoding="utf-8") == "this study's report"
    # a run computed again (its file deleted, or damaged) differs in its wall time alone: the
    # analysis (whose maps and notes of that file may be out of date) goes, said as it is (it
    # was "of other runs": a robustness review); another result is another study
    from brakeca.campaign import _stale_analysis

    (out / "tables").mkdir()
    text = (out / "summary.csv").read_text(encoding="utf-8")
    header, first, *rest = text.splitlines(keepends=True)
    column = header.rstrip("\n").split(",").index("wall_time")
    cells = first.rstrip("\n").split(",")
    cells[column] = str(float(cells[column]) + 1.5)
    removed, why = _stale_analysis(out, "".join([header, ",".join(cells) + "\n", *rest]))
    assert removed == ["report.html", "tables/"] and not (out / "report.html").exists()
    assert why.startswith("runs of it were computed again, with the same results; 'brakeca")
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    cells[header.split(",").index("MU")] = "0.5"
    changed = "".join([header, ",".join(cells) + "\n", *rest])
    n = len(text.splitlines()) - 1
    assert _stale_analysis(out, changed) == (
        ["report.html"],
        f"it was of {n} runs, {n - 1} of them among these {n} with the same results",
    )
    assert _stale_analysis(out, text) == ([], "")  # the same text: nothing to remove
    # a folder of an earlier version, without a scalar this one adds (MU_SD): said so, not
    # "of other runs"
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    frame = pd.read_csv(io.StringIO(text), dtype=str, keep_default_na=False)
    (out / "summary.csv").write_text(
        frame.drop(columns="MU_SD").to_csv(index=False), encoding="utf-8"
    )
    removed, why = _stale_analysis(out, frame.to_csv(index=False))
    assert removed == ["report.html"]
    assert why.startswith("this version of brakeca adds MU_SD to summary.csv, the runs' results")
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    other = frame.assign(MU=frame["MU"].where(frame.index > 0, "0.5"))
    assert _stale_analysis(out, other.to_csv(index=False))[1] == (
        f"it was of {n} runs, {n - 1} of them among these {n} with the same results"
    )
    # the same runs and results, written otherwise: a level 10 as 10.0 (a growth review: a
    # design grown to a composite one said its runs were "other runs")
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    floats = frame.assign(test=frame["test"] + ".0")
    removed, why = _stale_analysis(out, floats.to_csv(index=False))
    assert removed == ["report.html"] and why.startswith("it was of these runs, with the same")
    wholly = frame.assign(MU="0.5", run_id="0123456789abcdef")
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    assert _stale_analysis(out, wholly.to_csv(index=False))[1] == "it was of other runs"
    # replicates added: the runs there are some of these, their results the same (a new
    # user's review: "it was of other runs")
    (out / "summary.csv").write_text(text, encoding="utf-8")
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    more = pd.concat([frame, frame.iloc[:1].assign(run_id="0123456789abcdef", replicate="1")])
    removed, why = _stale_analysis(out, more.to_csv(index=False))
    assert removed == ["report.html"] and why == (
        f"it was of {len(frame)} of these {len(frame) + 1} runs (this design adds the others)"
    )
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    changed_too = more.assign(MU=more["MU"].where(more.index > 0, "0.5"))
    assert _stale_analysis(out, changed_too.to_csv(index=False))[1] == (
        f"it was of {n} runs, {n - 1} of them among these {n + 1} with the same results"
    )
    (out / "summary.csv").write_text(text, encoding="utf-8")
    (out / "report.html").write_text("this study's report", encoding="utf-8")
    # analyze while a campaign holds the folder says so
    monkeypatch.setattr(_runstore, "lock_holder", lambda folder: "pid 1 on host, since then")
    res = CliRunner().invoke(app, ["analyze", str(out), "--no-figures"])  # (the note alone)
    assert res.exit_code == 0, res.output
    assert "note: a campaign is writing" in res.output
    assert "(pid 1 on host, since then): this report is of the study as it stands" in " ".join(
        res.output.split()
    )
    # the first campaign of a folder, still running, has no summary yet: analyze said to
    # finish it with 'brakeca run', which the lock refuses (a robustness review)
    res = CliRunner().invoke(app, ["analyze", str(fresh)])
    said = " ".join(res.output.split())
    assert res.exit_code == 2 and "(pid 1 on host, since then) and has not written" in said
    assert "analyse it when the campaign ends" in said and "finishes it" not in said


def test_a_run_file_of_an_earlier_version_is_reused_beside_new_ones(serial, tmp_path):
    """Run files made before held_volume and stream_volume existed are reused (their run
    ids are the same): campaign.nc takes every run's variables, NaN where a run lacks one,
    whichever run comes first (it had taken the first longest run's variables alone)."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    first = out / "runs" / f"{serial.summary['run_id'].iloc[0]}.nc"
    with xr.open_dataset(first) as ds:
        old = ds.drop_vars(["held_volume", "stream_volume"]).load()
    old.to_netcdf(first, engine="h5netcdf")
    (out / "campaign.nc").unlink()
    again = run_campaign(
        out / "design.toml", out, executor="serial", progress=False, console=quiet()
    )
    assert len(again.reused) == 4 and not again.computed
    with xr.open_dataset(out / "campaign.nc") as ds:
        held = ds["held_volume"].to_numpy()
        assert np.isnan(held[0]).all() and np.isfinite(held[1:]).all()
        assert ds["held_volume"].attrs["units"] == "m3"


def test_a_run_file_of_another_seed_or_configuration_alone_is_recomputed(serial, tmp_path):
    """A test-suite audit: the check of a reused run file's seed, or of its configuration,
    could each be removed without a test failing (the foreign file differed in both). Here
    one file differs in its seed alone and one in its configuration alone."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    ids = list(serial.summary["run_id"])
    runs = out / "runs"
    for rid, change in ((ids[0], "seed"), (ids[1], "config")):
        path = runs / f"{rid}.nc"
        with xr.open_dataset(path) as ds:
            edited = ds.load()
        if change == "seed":
            edited.attrs["seed"] = int(edited.attrs["seed"]) + 1
        else:
            before = edited.attrs["config"]
            edited.attrs["config"] = before.replace("mu_0 = 0.6", "mu_0 = 0.61")
            assert edited.attrs["config"] != before
        edited.to_netcdf(path, engine="h5netcdf")
    console = quiet()
    result = run_campaign(
        out / "design.toml", out, executor="serial", progress=False, console=console
    )
    text = " ".join(console_text(console).split())
    assert sorted(result.recomputed) == sorted(ids[:2])
    assert "belongs to another run (the result has seed" in text
    assert "belongs to another run (the result's configuration differs from the run's)" in text


def test_an_unfinished_first_campaign_is_not_taken_over_by_another_design(tmp_path):
    """A first campaign stopped before its summary, resumed with another design (other
    levels), took it without a word: its design.toml was overwritten and the checkpoint of
    a run the new design leaves out stayed for good (a robustness review). It is refused now
    as another study is, naming the runs it would leave out; --replace takes it on purpose,
    and the same design resumes as before."""
    design = write_design(tmp_path, TINY, DESIGN)
    calls = []

    def one_then_stop(config, *, seed, progress=None, maps_at=()):
        if calls:
            raise KeyboardInterrupt
        calls.append(seed)
        return simulate(config, seed=seed)

    out = tmp_path / "c"
    with pytest.raises(KeyboardInterrupt):
        run_campaign(
            design, out, executor="serial", simulate_fn=one_then_stop, progress=False,
            console=quiet(),
        )  # fmt: skip
    assert len(list((out / "runs").glob("*.nc"))) == 1 and not (out / "summary.csv").exists()
    other = tmp_path / "other.toml"
    other.write_text(DESIGN.replace("levels = [10.0, 20.0]", "levels = [15.0, 20.0]"))
    before = (out / "design.toml").read_text(encoding="utf-8")
    with pytest.raises(ConfigError) as refused:
        run_campaign(other, out, executor="serial", simulate_fn=must_not_run, console=quiet())
    text = " ".join(str(refused.value).split())
    assert "holds another design's runs (the unfinished campaign of design 'tiny': 1 of" in text
    assert "would replace its design.toml and leave those runs out" in text and "--replace" in text
    assert (out / "design.toml").read_text(encoding="utf-8") == before
    shutil.copytree(out, tmp_path / "taken")
    # the same design resumes it: the finished run is reused
    done = run_campaign(design, out, executor="serial", progress=False, console=quiet())
    assert done.ok and len(done.computed) == 3 and len(done.reused) == 1
    # and the other design takes it on purpose
    (tmp_path / "taken" / ".brakeca.lock").unlink(missing_ok=True)
    taken = run_campaign(
        other, tmp_path / "taken", executor="serial", progress=False, console=quiet(), replace=True
    )
    assert taken.ok and len(taken.computed) == 4  # the run of A = 10 % is not among them
    assert len(list((tmp_path / "taken" / "runs").glob("*.nc"))) == 5  # and is kept
    # a --replace stopped in its turn resumes from the folder's design.toml without
    # --replace: the first design's run files are not its runs (a diff review found it
    # refused, naming the design it resumed)
    (tmp_path / "taken" / "summary.csv").unlink()
    (tmp_path / "taken" / "campaign.nc").unlink()
    again = run_campaign(
        tmp_path / "taken" / "design.toml", tmp_path / "taken", executor="serial",
        simulate_fn=must_not_run, progress=False, console=quiet(),
    )  # fmt: skip
    assert again.ok and len(again.reused) == 4
    text = " ".join(str(refused.value).split())
    assert "run again with --replace, resumes its campaign" in text


def test_campaign_nc_names_every_coordinate(serial) -> None:
    """campaign.nc's stop, block, seed, replicate, run_id, status and error had no attributes,
    though a run file gives stop and block theirs, and a dimensionless factor had the unit
    '-' where the file's other variables have UDUNITS' '1' (an API review)."""
    with xr.open_dataset(serial.out_dir / "campaign.nc", engine="h5netcdf") as ds:
        for name in ds.coords:
            assert "long_name" in ds[name].attrs, name
        assert ds["stop"].attrs["units"] == "1"
        assert ds["S"].attrs["units"] == "1" and ds["A"].attrs["units"] == "%"
    from brakeca.plotting import _campaign_factors

    factors = _campaign_factors(serial.dataset)  # as the axes write it
    assert factors is not None and factors[0].axis_label == "S [-]"


def test_a_progress_function_is_called_as_each_run_finishes(design_file, tmp_path) -> None:
    """run_campaign took a progress bar or nothing; a notebook's own progress had no hook
    (simulate takes a function per stop; an API review). A function gets (done, total) per
    run, the reused runs counted, and the console no bar or run lines."""
    out = tmp_path / "c"
    calls: list[tuple[int, int]] = []
    console = quiet()
    run_campaign(
        design_file, out, executor="serial", progress=lambda *a: calls.append(a),
        console=console, max_stops=1,
    )  # fmt: skip
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert " done: test " not in console_text(console)
    (out / "runs" / f"{load_campaign(out).summary['run_id'][2]}.nc").unlink()
    calls.clear()
    run_campaign(design_file, out, executor="serial", progress=lambda *a: calls.append(a),
                 console=quiet(), max_stops=1)  # fmt: skip
    assert calls == [(4, 4)]  # three reused, the fourth computed
    calls.clear()
    run_campaign(design_file, out, executor="serial", progress=lambda *a: calls.append(a),
                 console=quiet(), max_stops=1)  # fmt: skip
    assert calls == [(4, 4)]  # every run reused: once, done (it had never been called)


def test_a_closed_terminal_stops_a_local_campaign_without_tracebacks(design_file, tmp_path):
    """A cluster review: SIGHUP to the process group (a closed terminal) killed
    multiprocessing's resource tracker too, and the campaign, stopping its workers, printed
    "resource_tracker: process died unexpectedly" and a KeyError traceback per semaphore.
    The tracker is started with SIGHUP ignored; the campaign stops as for Ctrl-C."""
    import time

    started = tmp_path / "started"  # a file per run a worker has begun
    started.mkdir()
    (tmp_path / "slowsim.py").write_text(
        "import time\ndef slow(config, *, seed, progress=None, maps_at=()):\n"
        f"    open({str(started)!r} + '/' + str(seed), 'w').close()\n"
        "    time.sleep(120)\n"
    )
    script = tmp_path / "hung_up.py"
    script.write_text(
        "from brakeca.campaign import run_campaign\n"
        "from slowsim import slow\n"
        "if __name__ == '__main__':\n"
        "    print('started', flush=True)\n"
        "    try:\n"
        f"        run_campaign({str(design_file)!r}, {str(tmp_path / 'c')!r}, executor='local',\n"
        "                     workers=2, simulate_fn=slow, progress=False)\n"
        "    except KeyboardInterrupt as exc:\n"
        "        print('interrupted', exc, flush=True)\n"
    )
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), *sys.path]))
    with started_as_a_job([str(script)], "started", env=env) as proc:

        def children() -> list[str]:
            path = Path(f"/proc/{proc.pid}/task/{proc.pid}/children")
            return path.read_text().split() if path.exists() else []

        deadline = time.monotonic() + 120.0
        while time.monotonic() < deadline and len(children()) < 3:
            time.sleep(0.2)  # the tracker and the two workers
        assert len(children()) >= 3, children()
        while time.monotonic() < deadline and len(list(started.iterdir())) < 2:
            time.sleep(0.1)  # the workers take their runs (a tests review: not a 3 s sleep)
        assert len(list(started.iterdir())) == 2
        os.killpg(proc.pid, signal.SIGHUP)
        out, err = proc.communicate(timeout=60)
        assert out.strip() == "interrupted SIGHUP", (out, err)
        assert "Traceback" not in err and "resource_tracker" not in err, err


def test_a_folders_edited_design_or_base_is_named_as_such(serial, tmp_path):
    """A robustness review: a level edited in a folder's design.toml reached the analysis as
    a traceback, a factor added to it was blamed on summary.csv, and an edited
    base_config.toml was refused as "another design", naming no field."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    design_text = (out / "design.toml").read_text(encoding="utf-8")
    assert "    20.0,\n" in design_text
    (out / "design.toml").write_text(design_text.replace("    20.0,\n", "    25.0,\n"))
    edited = r"design.toml: factor A's levels are 10.0, 25.0, and none is the runs' 20.0: it "
    with pytest.raises(ValueError, match=edited + "was edited after the runs; put it back"):
        load_campaign(out)
    added = '\n[[factors]]\nname = "WR"\nlevels = [1e-7, 2e-7]\n'
    (out / "design.toml").write_text(design_text + added)
    with pytest.raises(ValueError, match=r"design.toml: it has factor WR, which the runs "):
        load_campaign(out)
    # replicates or a root seed edited (a growth review: the report then said "4 tests x 2
    # replicates = 8 runs" and "4 of 4 runs finished")
    assert "replicates = 1\n" in design_text and "root_seed = 11\n" in design_text
    for edit, said in (
        ("replicates = 2\n", "it has 4 tests × 2 replicates = 8 runs, where the folder has 4 "),
        ("root_seed = 12\n", r"its root_seed 12 does not give the runs' seeds \(test 1, "),
    ):
        key = edit.split(" = ")[0]
        was = next(line for line in design_text.splitlines(keepends=True) if line.startswith(key))
        (out / "design.toml").write_text(design_text.replace(was, edit))
        with pytest.raises(ValueError, match="design.toml: " + said):
            load_campaign(out)
    (out / "design.toml").write_text(design_text)
    assert load_campaign(out).ok  # as it was
    base = (out / "base_config.toml").read_text(encoding="utf-8")
    assert "wheel_load_mass = 690.0\n" in base
    (out / "base_config.toml").write_text(
        base.replace("wheel_load_mass = 690.0", "wheel_load_mass = 700.0")
    )
    with pytest.raises(ConfigError, match=r"holds this design's study with other values than "
                       r"those given now \(test 1: vehicle.wheel_load_mass: 690.0 -> 700.0\): "
                       r"its base_config.toml was edited"):  # fmt: skip
        run_campaign(load_design(out / "design.toml"), out, executor="serial", console=quiet())
    # a damaged campaign.nc gets the fix a missing one gets
    (out / "base_config.toml").write_text(base)
    data = (out / "campaign.nc").read_bytes()
    (out / "campaign.nc").write_bytes(data[:2000])
    with pytest.raises(ValueError, match=r"not a readable netCDF file .*; 'brakeca run .*design"
                       r".toml -o .*' writes it again from the run files$"):  # fmt: skip
        load_campaign(out)


def test_checkpoints_of_no_run_of_the_design_are_named(serial, tmp_path):
    """A robustness review: a design.toml edited in a stopped campaign's folder left the run
    the first design had begun behind, its checkpoint kept for good without a word."""
    out = tmp_path / "campaign"
    shutil.copytree(serial.out_dir, out)
    (out / "runs" / ".0123456789abcdef.checkpoint.npz").write_bytes(b"not read")
    result, text = rerun_reusing(out, progress=False)
    assert result.ok and len(result.reused) == 4
    said = " ".join(text.split())
    assert "note: 1 checkpoint(s) in " in said
    assert (
        "are of runs begun by another design or configuration run in this folder (an earlier "
        "one, or one stopped before its summary), none of this one" in said
    )
    assert (out / "runs" / ".0123456789abcdef.checkpoint.npz").read_bytes() == b"not read"


def test_the_checkpoints_workers_get_are_absolute(design_file, tmp_path, monkeypatch):
    """A cluster review: a dask worker started in another folder read a relative -o from its
    own and ran without checkpoints, without a word; the paths the runs are given are
    absolute."""
    import brakeca._executors as executors

    given = []
    real = executors._execute

    def recording(simulate_fn, config, seed, **options):
        given.append(options.get("checkpoint"))
        return real(simulate_fn, config, seed, **options)

    monkeypatch.setattr(executors, "_execute", recording)
    monkeypatch.chdir(tmp_path)
    result = run_campaign(
        design_file, "relative", executor="serial", progress=False, console=quiet()
    )
    assert result.ok and len(given) == 4
    assert all(p is not None and p.is_absolute() for p in given)
    assert all(p.parent == (tmp_path / "relative" / "runs") for p in given)


def test_runs_made_by_workers_of_other_kernel_sources_are_named(design_file, tmp_path, monkeypatch):
    """A cluster review: runs computed by a cluster's workers of another brakeca were mixed
    in without a word (only the next campaign said so); the campaign that computes them
    names them."""
    import brakeca.simulation

    real = brakeca.simulation.simulate

    def elsewhere(config, **kwargs):
        result = real(config, **kwargs)
        result.dataset.attrs["source_key"] = "0123456789abcdef"  # as another version's
        return result

    monkeypatch.setattr(brakeca.simulation, "simulate", elsewhere)
    console = quiet()
    result = run_campaign(design_file, tmp_path / "c", executor="serial", console=console)
    assert result.ok
    said = " ".join(console_text(console).split())
    assert (
        "note: 4 run(s) computed now (of tests 1, 2, 3, 4) were made by workers with other" in said
    )
    assert "(source_key 0123456789abcdef) than this install's" in said


def test_campaign_nc_reads_as_xarray_reads_it(serial):
    """brakeca's own reader (``_netcdf.fast_load``, test_netcdf_reader.py) gives xarray's
    Dataset of a campaign's campaign.nc too: string coordinates, list attributes."""
    from brakeca import _netcdf

    if not _netcdf.usable():
        pytest.skip("fast_load mirrors xarray 2026.9 and h5netcdf 1.8 only")
    path = serial.out_dir / "campaign.nc"
    fast, slow = _netcdf.fast_load(path), xr.load_dataset(path, engine="h5netcdf")
    xr.testing.assert_identical(fast, slow)
    assert list(fast.variables) == list(slow.variables)
    assert list(fast.coords) == list(slow.coords)
    assert {k: type(v) for k, v in fast.attrs.items()} == {
        k: type(v) for k, v in slow.attrs.items()
    }
    for name in slow.variables:
        assert fast[name].dtype == slow[name].dtype, name
