"""A campaign's runs keep their plateau maps after chosen stops (``maps_at``, ``--maps-at``).

The maps change no result and no run id: a campaign with them gives the summary of one
without them, and reuses runs that kept none (saying so). The report shows each run's maps
over the cycle.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from campaign_helpers import (
    DESIGN_TEMPLATE,
    deterministic,
    quiet,
    rerun_reusing,
    tiny,
    write_design,
)
from typer.testing import CliRunner

from brakeca.campaign import finish_campaign, run_campaign
from brakeca.cli import app
from brakeca.config import ConfigError
from brakeca.design import load_design, run_id
from brakeca.results import RunResult
from brakeca.study import write_study


@pytest.fixture(scope="module")
def design_file(tmp_path_factory):
    return write_design(
        tmp_path_factory.mktemp("design"), tiny(3), DESIGN_TEMPLATE.format(root_seed=7)
    )


@pytest.fixture(scope="module")
def plain(design_file, tmp_path_factory):
    out = tmp_path_factory.mktemp("plain") / "campaign"
    return run_campaign(design_file, out, executor="serial", progress=False, console=quiet())


@pytest.fixture(scope="module")
def mapped(design_file, tmp_path_factory):
    out = tmp_path_factory.mktemp("mapped") / "campaign"
    return run_campaign(
        design_file, out, executor="serial", progress=False, console=quiet(), maps_at=(3, 1)
    )


@pytest.fixture(scope="module")
def plain_analysed(plain, tmp_path_factory):
    """A copy of ``plain`` analysed (with figures) over the figures an earlier analysis left:
    a run's maps over the cycle, which these runs did not keep, and the final maps of a run
    no longer in the summary and of one named at another width; (the folder, its report).
    Two tests read it: one analysis with figures instead of two (a review of the suite's
    time)."""
    out = tmp_path_factory.mktemp("analysed") / "campaign"
    shutil.copytree(plain.out_dir, out)
    figures = out / "figures"
    figures.mkdir(exist_ok=True)
    for name in (
        "maps_by_stop_test01_r0.png",  # a map over the cycle
        "final_map_test099_r0.png",  # of a run no longer in the summary
        "final_map_test001_r0.png",  # the same run at another width
    ):
        (figures / name).write_bytes(b"x")
    html = write_study(finish_campaign(out)).read_text(encoding="utf-8")
    return out, html


def test_the_runs_keep_their_maps_and_nothing_else_changes(plain, mapped):
    assert mapped.ok
    assert list(mapped.summary["run_id"]) == list(plain.summary["run_id"])
    assert deterministic(mapped.summary).equals(deterministic(plain.summary))
    for rid in mapped.summary["run_id"]:
        ds = RunResult.from_netcdf(mapped.out_dir / "runs" / f"{rid}.nc").dataset
        assert list(ds["map_stop"].to_numpy()) == [1, 3]
        # the map after the last stop is the run's final map
        np.testing.assert_array_equal(
            ds["map_status"].sel(map_stop=3).to_numpy(), ds["final_status"].to_numpy()
        )
        plain_ds = RunResult.from_netcdf(plain.out_dir / "runs" / f"{rid}.nc").dataset
        assert "map_stop" not in plain_ds.coords


def test_the_report_shows_each_runs_maps_over_the_cycle(mapped, tmp_path):
    out = tmp_path / "campaign"
    shutil.copytree(mapped.out_dir, out)
    html = write_study(finish_campaign(out)).read_text(encoding="utf-8")
    assert "Plateau maps over the cycle" in html
    assert "plateaus before the first stop and after stops 1, 3 (brakeca run --maps-at)" in html
    figures = sorted(p.name for p in (out / "figures").glob("maps_by_stop_*.png"))
    assert figures == [f"maps_by_stop_test{t:02d}_r0.png" for t in (1, 2, 3, 4)]
    # analysed without the run maps, the report drops them and their files; emission
    # factors given for runs on a block cycle are said to have nothing to apply to
    from brakeca.emissions import EmissionParameters

    notes: list[str] = []
    write_study(
        finish_campaign(out),
        run_maps=False,
        note=notes.append,
        emissions=EmissionParameters(airborne_fraction=0.4),
    )
    assert not list((out / "figures").glob("maps_by_stop_*.png"))
    assert any("no finished run is on one: there is no PM10" in n for n in notes), notes
    assert not (out / "tables" / "pm10.csv").exists()


def test_a_campaign_without_maps_draws_no_maps_over_the_cycle(plain_analysed):
    out, html = plain_analysed
    assert "Plateau maps over the cycle" not in html
    assert not (out / "figures" / "maps_by_stop_test01_r0.png").exists()  # an earlier one's


def test_maps_of_gone_runs_go_and_those_that_cannot_be_drawn_again_stay(plain_analysed, tmp_path):
    """An analysis removes the run maps an earlier one drew for runs no longer in the summary
    (or named at another width), but keeps those of runs still in it whose file has gone (a
    folder sent without runs/): they could not be drawn again (a diff review)."""
    out = tmp_path / "campaign"
    shutil.copytree(plain_analysed[0], out)  # (analysed over those maps: the fixture's)
    figures = out / "figures"
    gone = figures / "final_map_test099_r0.png"  # of a run no longer in the summary
    wide = figures / "final_map_test001_r0.png"  # the same run at another width
    assert not gone.exists() and not wide.exists()
    drawn = sorted(p.name for p in figures.glob("final_map_test*.png"))
    assert drawn == [f"final_map_test{t:02d}_r0.png" for t in (1, 2, 3, 4)]
    # without the run files: every map stays, and none is listed in the report
    shutil.rmtree(out / "runs")
    html = write_study(finish_campaign(out)).read_text(encoding="utf-8")
    assert sorted(p.name for p in figures.glob("final_map_test*.png")) == drawn
    assert "final_map_test01_r0.png" not in html


def test_run_without_run_maps_reports_without_them(plain, design_file, tmp_path):
    """`brakeca run --no-run-maps`, as `analyze` has it (a review of large designs: a
    256-run report embedded 256 maps, 10-15 MB and most of the analysis's time, and only
    `analyze` could leave them out)."""
    out = tmp_path / "campaign"
    shutil.copytree(plain.out_dir, out)  # every run reused: the report alone is made
    args = ["run", str(design_file), "-o", str(out), "--executor", "serial", "--no-run-maps"]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "analysing 4 runs: tables, figures and the report" in " ".join(res.output.split())
    assert (out / "report.html").is_file()
    assert not list((out / "figures").glob("final_map_test*.png"))


def test_finished_runs_without_the_maps_are_reused_with_a_warning(plain, tmp_path):
    out = tmp_path / "campaign"
    shutil.copytree(plain.out_dir, out)
    again, said = rerun_reusing(out, maps_at=[2])
    assert sorted(again.reused) == sorted(plain.computed) and not again.computed
    text = " ".join(said.split())
    assert "4 finished run(s) (of tests 1, 2, 3, 4) ran without keeping maps after stops 2" in (
        text
    )
    assert "Delete their run files" in text


@pytest.mark.parametrize(
    ("maps_at", "message"),
    [
        ([4], r"maps_at: stop 4 is not a stop of this cycle \(whole numbers from 1 to 3\)"),
        ([0], r"maps_at: stop 0 is not a stop of this cycle"),
        ([1, 1], r"maps_at: a stop is given twice"),
        ([1.5], r"maps_at: stop 1.5 is not a stop"),
        ([np.int64(9)], r"maps_at: stop 9 is not a stop of this cycle"),  # not np.int64(9)
        ("1,2", r"maps_at: expected stop numbers, e.g. \[1, 50, 170\], got .1,2."),
    ],
)
def test_maps_at_is_checked_before_anything_is_written(design_file, tmp_path, maps_at, message):
    out = tmp_path / "campaign"
    with pytest.raises(ConfigError, match=message):
        run_campaign(design_file, out, executor="serial", console=quiet(), maps_at=maps_at)
    assert not out.exists()
    # also against a cycle cut short with max_stops
    with pytest.raises(
        ConfigError, match=r"stop 3 is not a stop of this cycle \(whole numbers from 1 to 2\)"
    ):
        run_campaign(design_file, out, executor="serial", console=quiet(), max_stops=2, maps_at=[3])
    assert not out.exists()


def test_the_command_line_takes_maps_at(design_file, mapped, tmp_path):
    out = tmp_path / "campaign"
    args = ["run", str(design_file), "-o", str(out), "--executor", "serial", "--no-report"]
    res = CliRunner().invoke(app, [*args, "--maps-at", "1,x"])
    assert res.exit_code == 2 and "--maps-at '1,x': expected stop numbers" in res.output
    res = CliRunner().invoke(app, [*args, "--maps-at", "9"])
    assert res.exit_code == 2
    assert "--maps-at: stop 9 is not a stop of this cycle" in " ".join(res.output.split())
    assert not out.exists()
    res = CliRunner().invoke(app, [*args, "--maps-at", "3,1"])
    assert res.exit_code == 0, res.output
    for rid in mapped.summary["run_id"]:
        ds = RunResult.from_netcdf(out / "runs" / f"{rid}.nc").dataset
        assert list(ds["map_stop"].to_numpy()) == [1, 3]


def test_a_checkpoint_without_an_asked_map_starts_the_run_over(design_file, mapped, tmp_path):
    """A campaign killed in a run, resumed with --maps-at for a stop its checkpoint ran
    without a map: the worker discards the checkpoint and runs from the start, so the run
    keeps every asked map and its result is the uninterrupted run's."""
    from brakeca._executors import _execute
    from brakeca.simulation import simulate

    point = next(p for p in load_design(design_file).points() if p.test == 2)
    ckpt = tmp_path / f".{run_id(point)}.checkpoint.npz"
    simulate(
        point.config, seed=point.seed, checkpoint=ckpt, checkpoint_every=1, keep_checkpoint=True
    )
    assert ckpt.exists()  # saved after stop 2 (of 3), without maps
    # the campaign's count of runs it resumes leaves it out: the run starts over
    from brakeca._io import checkpoint_resumes

    assert checkpoint_resumes(ckpt, point.config, point.seed)
    assert checkpoint_resumes(ckpt, point.config, point.seed, (3,))  # stop 3 is still to run
    assert not checkpoint_resumes(ckpt, point.config, point.seed, (1, 3))
    result = _execute(None, point.config, point.seed, ckpt, 1, maps_at=(1, 3))
    assert list(result.dataset["map_stop"].to_numpy()) == [1, 3]
    kept = RunResult.from_netcdf(mapped.out_dir / "runs" / f"{run_id(point)}.nc").dataset
    np.testing.assert_array_equal(
        result.dataset["map_status"].to_numpy(), kept["map_status"].to_numpy()
    )
    assert result.MU == mapped.summary.set_index("test").loc[2, "MU"]


def test_the_minimal_command_line_takes_maps_at(design_file, mapped, tmp_path):
    """`python -m brakeca.campaign ... --maps-at` as `brakeca run --maps-at` (a review found
    the minimal command line without it)."""
    from brakeca.campaign import main

    out = tmp_path / "campaign"
    common = [str(design_file), str(out), "--executor", "serial", "--no-progress"]
    assert main([*common, "--maps-at", "9"]) == 2 and not out.exists()
    assert main([*common, "--maps-at", "1,3"]) == 0
    for rid in mapped.summary["run_id"]:
        ds = RunResult.from_netcdf(out / "runs" / f"{rid}.nc").dataset
        assert list(ds["map_stop"].to_numpy()) == [1, 3]
    assert main([*common, "--maps-at", "x"]) == 2  # brakeca run's check and message


def test_the_minimal_command_line_is_brakeca_run(design_file, tmp_path, capsys):
    """`python -m brakeca.campaign` forwards to `brakeca run --no-report`: its checks and
    exit statuses (2, nothing run), `--max-stops` read as `--stops`, `--no-progress` taken."""
    from brakeca.campaign import main

    out = tmp_path / "campaign"
    common = [str(design_file), str(out), "--executor", "serial", "--no-progress"]
    for stops in ("--max-stops", "--stops"):  # each option of brakeca run's takes its value
        assert main([*common, stops, "0"]) == 2 and not out.exists()
        assert "Invalid value for '--stops'" in capsys.readouterr().err
    assert main([*common, "--workers=0"]) == 2 and not out.exists()
    assert "--workers" in capsys.readouterr().err
    assert main([*common, "--no-such-option"]) == 2 and not out.exists()
    assert "No such option: --no-such-option" in capsys.readouterr().err
    assert main([*common, "--bogus", "3"]) == 2 and not out.exists()  # not "3 arguments"
    assert "No such option: --bogus" in capsys.readouterr().err
    assert main([str(design_file)]) == 2 and not out.exists()
    assert "expected a design and a folder, got 1 argument(s)" in capsys.readouterr().err
    assert main(["--help"]) == 0 and "brakeca run" in capsys.readouterr().out
