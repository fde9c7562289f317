"""A campaign killed in the middle of a long run resumes that run from its checkpoint.

Each run in progress saves its state every ``checkpoint_every`` stops to
``runs/.<run_id>.checkpoint.npz``; the next campaign on the folder resumes from it, with a
bit-identical result, and removes it when the run completes. A checkpoint that cannot be used
(another version's format, a damaged file) is discarded, never fatal.
"""

from __future__ import annotations

import io

import pytest
from campaign_helpers import DESIGN_TEMPLATE, deterministic, quiet, tiny, write_design
from rich.console import Console

from brakeca import simulation
from brakeca.campaign import run_campaign
from brakeca.design import load_design, run_id


class Interrupted(Exception):
    pass


def _stop_after(n):
    def progress(done, total):
        if done == n:
            raise Interrupted

    return progress


@pytest.fixture(scope="module")
def design_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("design")
    return write_design(folder, tiny(4), DESIGN_TEMPLATE.format(root_seed=5))


@pytest.fixture(scope="module")
def uninterrupted(design_file, tmp_path_factory):
    out = tmp_path_factory.mktemp("plain") / "campaign"
    result = run_campaign(
        design_file, out, executor="serial", checkpoint_every=1, progress=False, console=quiet()
    )
    assert not list((out / "runs").glob(".*"))  # every checkpoint removed with its run
    return result


def _killed_after_two_stops(design_file, out):
    """The checkpoint in ``out`` of test 1's run, killed after its second stop."""
    point = next(p for p in load_design(design_file).points() if p.test == 1)
    ckpt = out / "runs" / f".{run_id(point)}.checkpoint.npz"
    ckpt.parent.mkdir(parents=True)
    with pytest.raises(Interrupted):
        simulation.simulate(
            point.config,
            seed=point.seed,
            checkpoint=ckpt,
            checkpoint_every=1,
            progress=_stop_after(2),
        )
    assert ckpt.exists()
    return ckpt


def _spy_on_resumes(monkeypatch) -> list[int]:
    """The stops already done of each run resumed from a checkpoint, as they resume."""
    resumed: list[int] = []
    load = simulation.load_checkpoint

    def spy(*args, **kwargs):
        found = load(*args, **kwargs)
        if found is not None:
            resumed.append(len(found[2].dts))  # stops already done
        return found

    monkeypatch.setattr(simulation, "load_checkpoint", spy)
    return resumed


def test_a_run_resumes_from_its_checkpoint(design_file, uninterrupted, tmp_path, monkeypatch):
    out = tmp_path / "campaign"
    ckpt = _killed_after_two_stops(design_file, out)
    resumed = _spy_on_resumes(monkeypatch)
    # a terminal too: its bar shows no resumption (a robustness review)
    log = Console(file=io.StringIO(), width=200, force_terminal=True)
    result = run_campaign(design_file, out, executor="serial", progress=True, console=log)
    assert resumed == [2]
    said = log.file.getvalue()  # type: ignore[attr-defined]
    assert "4 of 4 run(s) to compute (0 already done; 1 resumed from a checkpoint)" in said
    # a line per run above the bar, which had counted whole runs alone (a robustness review)
    assert said.count(" done: test ") == 4 and "resumed from a checkpoint: MU" in said
    assert not ckpt.exists()
    assert deterministic(result.summary).equals(deterministic(uninterrupted.summary))


def test_an_unusable_checkpoint_is_discarded(design_file, uninterrupted, tmp_path):
    out = tmp_path / "campaign"
    point = next(p for p in load_design(design_file).points() if p.test == 2)
    ckpt = out / "runs" / f".{run_id(point)}.checkpoint.npz"
    ckpt.parent.mkdir(parents=True)
    ckpt.write_bytes(b"not a checkpoint")
    log = Console(file=io.StringIO(), width=200)  # a log file: a line says what resumes
    result = run_campaign(design_file, out, executor="serial", progress=True, console=log)
    assert result.ok and not ckpt.exists()
    # not counted as resumed (a robustness review: the line had said "1 resumed"), and said
    # (a later review: it had been dropped without a word)
    assert (
        "4 of 4 run(s) to compute (0 already done; 1 with a checkpoint that cannot be used "
        "(damaged, of another run, or without a map asked for), started over)\n"
    ) in log.file.getvalue()  # type: ignore[attr-defined]
    assert deterministic(result.summary).equals(deterministic(uninterrupted.summary))


def test_checkpoint_every_is_validated(design_file, tmp_path):
    for bad in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match="checkpoint_every"):
            run_campaign(design_file, tmp_path / "c", checkpoint_every=bad, console=quiet())
    assert not (tmp_path / "c").exists()  # refused before anything is written


def test_command_line_option(design_file, uninterrupted, tmp_path):
    from typer.testing import CliRunner

    from brakeca.campaign import load_campaign
    from brakeca.cli import app

    out = tmp_path / "campaign"
    args = ["run", str(design_file), "-o", str(out), "--executor", "serial", "--no-report"]
    res = CliRunner().invoke(app, [*args, "--checkpoint-every", "-1"])
    assert res.exit_code == 2 and not out.exists()
    res = CliRunner().invoke(app, [*args, "--checkpoint-every", "0"])
    assert res.exit_code == 0, res.output
    summary = load_campaign(out).summary
    assert deterministic(summary).equals(deterministic(uninterrupted.summary))


def test_a_worker_leaves_its_checkpoint_for_the_campaign_to_remove(
    design_file, uninterrupted, tmp_path
):
    """A robustness review: the worker deleted its checkpoint when its run finished, before
    the campaign had written the run file, so a campaign killed in between (or a dask
    client killed while its workers went on) lost the run whole. The worker now leaves it;
    the campaign removes it after writing the run file, and a resumed campaign removes the
    checkpoint of a run whose file it reuses."""
    from brakeca._executors import _execute

    point = next(p for p in load_design(design_file).points() if p.test == 3)
    ckpt = tmp_path / f".{run_id(point)}.checkpoint.npz"
    result = _execute(None, point.config, point.seed, ckpt, 1)
    assert result.MU > 0 and ckpt.exists()  # left for the campaign
    # a campaign killed after writing run 3's file, before removing its checkpoint
    out = tmp_path / "campaign"
    (out / "runs").mkdir(parents=True)
    result.to_netcdf(out / "runs" / f"{run_id(point)}.nc")
    stale = out / "runs" / ckpt.name
    ckpt.rename(stale)
    resumed = run_campaign(design_file, out, executor="serial", progress=False, console=quiet())
    assert resumed.reused == (run_id(point),)
    assert not list((out / "runs").glob(".*"))
    assert deterministic(resumed.summary).equals(deterministic(uninterrupted.summary))


def test_checkpoints_off_still_resume_from_one_written_before(
    design_file, uninterrupted, tmp_path, monkeypatch
):
    """A campaign resumed with checkpoints off (``--checkpoint-every 0``) started its
    interrupted runs over and left their checkpoints on disk (a robustness review). It
    resumes from them now, writes no more, and removes them once the run file is written."""
    out = tmp_path / "campaign"
    ckpt = _killed_after_two_stops(design_file, out)
    resumed = _spy_on_resumes(monkeypatch)
    saved = []
    save = simulation.save_checkpoint

    def spy_save(*args, **kwargs):
        saved.append(args[0])
        return save(*args, **kwargs)

    monkeypatch.setattr(simulation, "save_checkpoint", spy_save)
    log = Console(file=io.StringIO(), width=200)
    result = run_campaign(
        design_file, out, executor="serial", checkpoint_every=None, progress=True, console=log
    )
    assert resumed == [2] and saved == []
    text = log.file.getvalue()  # type: ignore[attr-defined]
    assert "1 resumed from a checkpoint" in text
    # its time counts the stops before the interruption: said so (a noted inaccuracy)
    done = next(line for line in text.splitlines() if "test 1, replicate 0" in line)
    assert " s in all, resumed from a checkpoint: MU " in done
    assert text.count("resumed from a checkpoint:") == 1
    assert not ckpt.exists()
    assert deterministic(result.summary).equals(deterministic(uninterrupted.summary))
