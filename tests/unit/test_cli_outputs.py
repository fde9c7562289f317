"""Outputs the command line cannot write are refused before any work, in one line (no
traceback); a result computed before a write fails is kept; `run --speed-unit`; the default
folder of a truncated `brakeca paper`."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pandas as pd
import pytest
from typer.testing import CliRunner

import brakeca.campaign
import brakeca.cli as cli
from brakeca.cli import app, output_problem

TINY_DESIGN = """
name = "tiny"
base = "paper"
root_seed = 5
[[factors]]
name = "A"
field = "A"
levels = [10.0, 20.0]
unit = "%"
"""


def _invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def _one_error_line(res, code: int = 2) -> str:
    """The output of a refused command: exit status ``code``, no traceback, and the last
    line an ``error:`` line, which is returned (joined, if the terminal wrapped it)."""
    assert res.exit_code == code, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception
    assert "Traceback" not in res.output
    text = " ".join(res.output.split())
    assert "error: " in text, res.output
    return text[text.index("error: ") :]


def _no_work(*_args, **_kwargs):
    raise AssertionError("no work should start")


@pytest.fixture
def afile(tmp_path, monkeypatch) -> Path:
    """A file in the working directory, named as a folder by the outputs below."""
    monkeypatch.chdir(tmp_path)
    path = Path("afile")
    path.write_text("")
    return path


def test_output_problem_names_what_is_wrong_and_creates_nothing(tmp_path) -> None:
    afile = tmp_path / "afile"
    afile.write_text("")
    assert output_problem(afile / "c", folder=True) == (
        f"cannot create it ({afile} is a file, not a folder)"
    )
    assert output_problem(afile / "x" / "f.png") == (
        f"cannot write it ({afile} is a file, not a folder)"
    )
    assert output_problem(afile, folder=True) == (
        "cannot create it (a file of that name exists; give a folder)"
    )
    assert output_problem(tmp_path) == "cannot write it (it is a folder; give a file name)"
    # new folders on the way are fine: they are created when the output is written
    assert output_problem(tmp_path / "new" / "deeper", folder=True) is None
    assert output_problem(tmp_path / "new" / "f.png") is None
    assert output_problem(tmp_path, folder=True) is None
    assert output_problem(afile) is None  # an existing file is replaced
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_output_problem_tries_the_folder_instead_of_trusting_permissions() -> None:
    """As root every permission bit says yes; /proc takes no new file all the same."""
    problem = output_problem(Path("/proc/x"), folder=True)
    assert problem is not None and problem.startswith("cannot create it (cannot write in /proc")
    problem = output_problem(Path("/proc/f.png"))
    assert problem is not None and problem.startswith("cannot write it (cannot write in /proc")


def test_campaign_outputs_are_checked_before_any_run(afile, monkeypatch) -> None:
    monkeypatch.setattr(brakeca.campaign, "run_campaign", _no_work)
    design = Path("d.toml")
    design.write_text(TINY_DESIGN)
    for args in (
        ["run", str(design), "-o", "afile/c", "--quick", "--stops", "1"],
        ["paper", "-o", "afile/c", "--quick", "--stops", "1"],
    ):
        line = _one_error_line(_invoke(*args))
        assert line == "error: -o afile/c: cannot create it (afile is a file, not a folder)"
    line = _one_error_line(_invoke("run", str(design), "-o", "afile", "--quick"))
    assert "-o afile: cannot create it (a file of that name exists; give a folder)" in line
    # an empty -o (OUT unset in -o "$OUT") was the working folder, which took the campaign
    # (a fuzz review); plot's figures likewise
    Path("r.nc").write_text("")
    for args in (["run", str(design)], ["paper", "--quick"], ["plot", "r.nc"]):
        res = _invoke(*args, "-o", "")
        assert res.exit_code == 2, res.output
        assert "'-o' / '--output': an empty path; give the folder" in " ".join(res.output.split())
    assert sorted(p.name for p in Path().iterdir()) == ["afile", "d.toml", "r.nc"]


def test_a_checkpoint_that_cannot_be_written_is_refused_before_the_run(afile, monkeypatch):
    import brakeca._warmup

    monkeypatch.setattr(brakeca._warmup, "warm_up", _no_work)
    args = ["simulate", "-o", "r.nc", "--stops", "1", "--checkpoint", "afile/k.npz"]
    line = _one_error_line(_invoke(*args))
    assert (
        line == "error: --checkpoint afile/k.npz: cannot write it (afile is a file, not a folder)"
    )


def test_a_write_that_fails_during_a_campaign_is_one_line_and_keeps_the_runs(
    tmp_path, monkeypatch
) -> None:
    def disk_full(*_args, **_kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(brakeca.campaign, "run_campaign", disk_full)
    design = tmp_path / "d.toml"
    design.write_text(TINY_DESIGN)
    out = tmp_path / "c"
    line = _one_error_line(_invoke("run", str(design), "-o", str(out)), code=1)
    assert f"-o {out}: cannot write in it ([Errno 28] No space left on device)" in line
    assert "the finished runs and the checkpoints are kept there" in line
    # a folder in the way of a file (the lock, say) is named, to move (a robustness review)
    lock = str(out / ".brakeca.lock")

    def in_the_way(*_args, **_kwargs):
        raise IsADirectoryError(21, "Is a directory", lock)

    monkeypatch.setattr(brakeca.campaign, "run_campaign", in_the_way)
    line = _one_error_line(_invoke("run", str(design), "-o", str(out)), code=1)
    assert f"{lock} is a folder where brakeca writes a file: move it away; the finished" in line
    # for real: a file written through a temporary one renamed onto it names the file (a
    # diff review: it had named the temporary one)
    monkeypatch.undo()
    real = tmp_path / "real"
    (real / "design.toml").mkdir(parents=True)
    line = _one_error_line(_invoke("run", str(design), "-o", str(real)), code=1)
    assert f"{real / 'design.toml'} is a folder where brakeca writes a file: move it away" in line


def test_figure_outputs_are_checked_before_any_work(afile, monkeypatch) -> None:
    import brakeca.study
    from brakeca.results import RunResult

    line = _one_error_line(_invoke("surface", "-o", "afile/f.png", "--quick"))
    assert line == "error: -o afile/f.png: cannot write it (afile is a file, not a folder)"
    # cycle inspect: refused before its table is printed
    res = _invoke("cycle", "inspect", "example_trace", "-o", "afile/c.png")
    line = _one_error_line(res)
    assert line == "error: -o afile/c.png: cannot write it (afile is a file, not a folder)"
    assert "braking events" not in res.output
    # plot: a run file's figures, and a campaign's
    monkeypatch.setattr(RunResult, "from_netcdf", classmethod(lambda cls, path: object()))
    monkeypatch.setattr(brakeca.study, "plot_run", _no_work)
    Path("r.nc").write_text("")
    line = _one_error_line(_invoke("plot", "r.nc", "-o", "afile/figs"))
    assert line == "error: -o afile/figs: cannot create it (afile is a file, not a folder)"
    Path("r_figures").write_text("")  # the default folder
    line = _one_error_line(_invoke("plot", "r.nc"))
    assert line == "error: r_figures: cannot create it (a file of that name exists; give a folder)"


def test_a_campaign_folder_that_is_a_file_is_named_so(afile) -> None:
    for command in ("analyze", "optimize"):
        line = _one_error_line(_invoke(command, "afile"))
        assert line.startswith("error: afile: not a folder (a file)"), line
    assert "no such folder" in _one_error_line(_invoke("analyze", "missing"))


def test_a_figure_that_cannot_be_written_after_all_is_kept(afile, monkeypatch) -> None:
    """The check passed (a folder that became a file meanwhile, a full disk): the figure is
    written into a temporary folder, and the command exits 1 naming it."""
    monkeypatch.setattr(cli, "output_problem", lambda path, folder=False: None)
    for args, what in (
        (["surface", "-o", "afile/f.png", "--quick"], "figure"),
        (["cycle", "inspect", "example_trace", "-o", "afile/c.png"], "plot"),
    ):
        line = _one_error_line(_invoke(*args), code=1)
        assert line.startswith(f"error: -o {args[args.index('-o') + 1]}: cannot write it ("), line
        kept = Path(line.split(f"the {what} was saved to ")[1])
        assert kept.read_bytes().startswith(b"\x89PNG")
        kept.unlink()
        kept.parent.rmdir()


def test_run_takes_the_speed_unit_of_a_trace_without_one(tmp_path, monkeypatch) -> None:
    seen: dict = {}

    def record(design, output, **kwargs):
        seen.update(kwargs)
        raise KeyboardInterrupt  # stop there: nothing to run

    monkeypatch.setattr(brakeca.campaign, "run_campaign", record)
    trace = tmp_path / "t1.csv"
    trace.write_text("time_s,speed\n0,0\n10,50\n20,50\n27,0\n30,0\n")
    design = tmp_path / "d.toml"
    design.write_text(TINY_DESIGN)
    base = ["run", str(design), "-o", str(tmp_path / "c"), "--cycle", str(trace)]
    line = _one_error_line(_invoke(*base))
    assert "states no unit" in line and "--speed-unit" in line
    res = _invoke(*base, "--speed-unit", "km/h")
    assert res.exit_code == 130, res.output
    assert seen["overrides"]["cycle"]["trace_speed_unit"] == "km/h"
    line = _one_error_line(_invoke(*base, "--speed-unit", "furlongs"))
    assert "unknown speed unit 'furlongs'" in line
    # without a trace to apply to, the option is refused, not ignored
    for args in (
        ["run", str(design), "-o", str(tmp_path / "c"), "--speed-unit", "km/h"],
        ["simulate", "-o", str(tmp_path / "r.nc"), "--speed-unit", "km/h"],
    ):
        line = _one_error_line(_invoke(*args))
        assert line == (
            "error: --speed-unit gives the speed unit of a --cycle trace; give --cycle too"
        )


@pytest.mark.parametrize(
    ("args", "folder"),
    [
        (["--stops", "10"], "results/paper_stops10"),
        (["--quick", "--stops", "10"], "results/paper_quick_stops10"),
        (["--stops", "10", "-o", "elsewhere"], "elsewhere"),
        ([], "results/paper"),
    ],
)
def test_a_truncated_paper_study_gets_a_folder_of_its_own(monkeypatch, args, folder) -> None:
    seen: dict = {}

    def record(design, output, **kwargs):
        seen.update(output=output, stops=kwargs["stops"])

    monkeypatch.setattr(cli, "_run_and_report", record)
    res = _invoke("paper", *args)
    assert res.exit_code == 0, res.output
    assert str(seen["output"]) == folder
    assert seen["stops"] == (10 if "--stops" in args else None)
    said = f"campaign folder: {folder}" in res.output
    assert said == ("-o" not in args)


def test_output_problem_leaves_an_unwritable_folder_alone(tmp_path) -> None:
    """Where permissions do apply (not as root), a read-only folder is refused too."""
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        problem = output_problem(folder / "f.png")
        if os.access(folder, os.W_OK):  # root: the probe file was written and removed
            assert problem is None
        else:
            assert problem == f"cannot write it (cannot write in {folder}: Permission denied)"
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o700)


def test_a_fraction_given_for_a_percent_gets_a_note() -> None:
    """A is in %: A=0.2 is taken as 0.2 %, and said so on standard error (the TOML on standard
    output stays clean); A=20 gets no note (a user review)."""
    from typer.testing import CliRunner

    from brakeca.cli import app

    runner = CliRunner()
    res = runner.invoke(app, ["config", "--set", "A=0.2"])
    assert res.exit_code == 0
    assert "note: A is in %: A=0.2 is 0.2 % fibres; for 20 % give A=20" in res.stderr
    assert "note" not in res.stdout and "fibre_area_fraction = 0.002" in res.stdout
    assert "note" not in runner.invoke(app, ["config", "--set", "A=20"]).stderr


def test_a_figure_is_written_in_the_format_of_its_suffix(tmp_path) -> None:
    """brakeca surface -o s.svg had written PNG data under any suffix (a helper's review):
    the suffix's format is written, and an unknown suffix is refused before any work."""
    from brakeca.plotting import figure_format

    assert figure_format("a.SVG") == "svg" and figure_format("noext") == "png"
    with pytest.raises(ValueError, match=r"not \.xyz"):
        figure_format("a.xyz")
    runner = CliRunner()
    base = ["surface", "--set", "mesh.n_radial=5", "--set", "mesh.n_angular=100"]
    res = runner.invoke(app, [*base, "-o", str(tmp_path / "s.svg")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "s.svg").read_text(encoding="utf-8").lstrip().startswith("<?xml")
    res = runner.invoke(app, [*base, "-o", str(tmp_path / "s.xyz")])
    assert res.exit_code == 2 and "a figure is written as .png" in res.output
    assert not (tmp_path / "s.xyz").exists()
    res = runner.invoke(app, [*base, "--set", "A=50", "-o", str(tmp_path / "a.png")])
    assert res.exit_code == 2 and "give --levels instead" in res.output


def test_a_preset_and_a_config_file_are_not_given_together(tmp_path) -> None:
    """-c won silently over --preset (and --preset nope passed; a helper's review)."""
    path = tmp_path / "c.toml"
    res = CliRunner().invoke(app, ["config"])
    path.write_text(res.stdout, encoding="utf-8")
    for preset in ("nope", "paper"):
        res = CliRunner().invoke(app, ["config", "-c", str(path), "--preset", preset])
        assert res.exit_code == 2 and "give one of them" in res.output
    assert CliRunner().invoke(app, ["config", "-c", str(path)]).exit_code == 0
    assert CliRunner().invoke(app, ["config", "--preset", "paper"]).exit_code == 0


def test_config_checks_a_trace_as_a_run_would() -> None:
    """`brakeca config` validates a configuration without running it, but took a trace_file
    that does not exist, a speed unit of furlongs and a digest of 'zz', which `simulate`
    refused afterwards (the digest as 'its content changed'; a fuzz review)."""
    trace = ["--set", "cycle.blocks=[]", "--set", "cycle.trace_file=example_trace"]
    line = _one_error_line(_invoke("config", *trace[:2], "--set", "cycle.trace_file=nope.csv"))
    assert "nope.csv: no such file, nor a shipped cycle" in line, line
    for extra, message in (
        (["--set", "cycle.trace_speed_unit=furlongs"], "unknown speed unit 'furlongs'"),
        (
            ["--set", "cycle.trace_sha256=zz"],
            "cycle.trace_sha256: must be a SHA-256 digest, 64 lowercase hexadecimal digits "
            "(got 'zz')",
        ),
    ):
        line = _one_error_line(_invoke("config", *trace, *extra))
        assert message in line, line
    assert _invoke("config", *trace).exit_code == 0


def test_messages_name_what_the_user_gave() -> None:
    """A helper's review of the command line: --set S=2 named only the field S sets, a bad
    --threshold was 'options: threshold', and a goal with words for numbers was told it
    had the wrong count of them."""
    runner = CliRunner()
    res = runner.invoke(app, ["config", "--set", "S=2"])
    assert res.exit_code == 2
    assert "override S (= automaton.secondary_removal_fraction): must lie in [0, 1]" in res.output
    res = runner.invoke(app, ["cycle", "inspect", "example_trace", "--threshold", "-1"])
    assert res.exit_code == 2 and "error: --threshold: must lie in" in res.output
    with pytest.raises(ValueError, match="'a' is not a number"):
        cli._parse_goal("MU:min:a:b")
    with pytest.raises(ValueError, match="min takes 2 numbers"):
        cli._parse_goal("MU:min:1")
    # a new user's review: the command's order explained by rsm.Goal's Python arguments, and
    # an unknown response told only the general form
    with pytest.raises(ValueError) as info:
        cli._parse_goal("MU:target:0.3:0.6:0.5")
    assert str(info.value) == (
        "--goal 'MU:target:0.3:0.6:0.5': a target goal is LOWER:TARGET:UPPER, the target "
        "strictly between the limits; got lower 0.3, target 0.6, upper 0.5; for a target of "
        "0.5 between 0.3 and 0.6, give MU:target:0.3:0.5:0.6"
    )
    with pytest.raises(ValueError, match=r"^--goal 'mu:max:0.3:0.4': unknown response 'mu' "):
        cli._parse_goal("mu:max:0.3:0.4")
    with pytest.raises(ValueError, match=r"\(did you mean MU\?\); the responses are MU, V, "):
        cli._parse_goal("mu:max:0.3:0.4")
    with pytest.raises(
        ValueError,
        match=r"unknown goal .maximum.; the goals are min \(minimize\), max \(maximize\) and",
    ):
        cli._parse_goal("MU:maximum:0.3:0.4")
    # the friction stability is a response a goal may name too
    steady = cli._parse_goal("MU_SD:min:0.01:0.05")
    assert (steady.response, steady.kind, steady.upper) == ("MU_SD", "minimize", 0.05)
    with pytest.raises(ValueError, match=r"\(did you mean MU_SD\?\)"):
        cli._parse_goal("mu_sd:min:0.01:0.05")


def test_a_replicated_campaigns_table_has_a_row_per_test() -> None:
    """A new user's 220-run campaign printed 220 rows at every run and analysis: beyond 48
    runs, a replicated design's table has a row per test, the replicates averaged, with a
    test whose replicate failed marked k/n ok and its mean over the others."""
    rows = []
    for rep in range(5):
        for test in range(1, 13):
            failed = (test, rep) == (3, 2)
            rows.append(
                {
                    "test": test,
                    "replicate": rep,
                    "order": 1,
                    "A": 10.0 * (1 + test % 2),
                    "seed": 1,
                    "run_id": "x",
                    "MU": math.nan if failed else 0.2 + 0.01 * test + 0.001 * rep,
                    "V_mm3": math.nan if failed else float(test),
                    "status": "failed" if failed else "ok",
                }
            )
    with cli.out.capture() as captured:
        cli._print_summary(pd.DataFrame(rows))
    text = captured.get()
    lines = [line for line in text.splitlines() if line.startswith("│")]
    assert len(lines) == 12
    assert "│    3 │ 20 │ 4/5 ok │ 0.2320 │" in text  # (0.230 + 0.231 + 0.233 + 0.234) / 4
    assert "the mean of its 5 replicates" in " ".join(text.split())


def test_the_runs_table_shows_mu_sd_where_it_fits() -> None:
    """The terminal's table of runs gives each run's friction stability beside MU and V
    (summary.csv has it since the forty-sixth session); where the table would not fit the
    terminal even with the levels' labels, MU_SD gives way and the caption says where it is;
    a summary without it (an earlier campaign) has no such column."""
    import io

    from rich.console import Console

    rows = [
        {"test": t, "order": t, "A": 10.0 * t, "seed": t, "run_id": "x", "MU": 0.2,
         "MU_SD": 0.0123 * t, "V_mm3": 1.5, "status": "ok"}
        for t in (1, 2)
    ]  # fmt: skip
    saved = cli.out
    try:
        for width, shown in ((100, True), (40, False)):
            cli.out = Console(file=io.StringIO(), width=width, record=True)
            cli._print_summary(pd.DataFrame(rows))
            text = cli.out.export_text()
            assert ("MU_SD" in text.splitlines()[2]) is shown, text
            assert ("0.0246" in text) is shown
            assert ("MU_SD in summary.csv" in " ".join(text.split())) is not shown
        cli.out = Console(file=io.StringIO(), width=100, record=True)
        cli._print_summary(pd.DataFrame(rows).drop(columns="MU_SD"))
        assert "MU_SD" not in cli.out.export_text()
    finally:
        cli.out = saved


def test_a_replicated_campaigns_runs_name_their_replicate() -> None:
    """Up to 48 runs a replicated design's table has a row per run: each names its replicate
    beside its test (a docs walkthrough: two rows 'test 1' with different MU and nothing to
    tell them apart); an unreplicated design's table has no such column."""
    rows = [
        {"test": t, "replicate": r, "order": 1, "A": 10.0 * t, "seed": 1, "run_id": "x",
         "MU": 0.2 + 0.01 * t + 0.001 * r, "V_mm3": float(t), "status": "ok"}
        for t in (1, 2)
        for r in (0, 1, 2)
    ]  # fmt: skip
    with cli.out.capture() as captured:
        cli._print_summary(pd.DataFrame(rows))
    text = captured.get()
    assert [c.strip() for c in text.splitlines()[2].split("┃")[1:3]] == ["test", "rep"]
    assert "│    1 │   2 │ 10 │ 0.2120 │" in text
    with cli.out.capture() as captured:
        cli._print_summary(pd.DataFrame([r for r in rows if r["replicate"] == 0]))
    assert "rep" not in captured.get()


@pytest.mark.parametrize(
    ("lines", "heading"),
    [
        (["MU: A (50.0 %)"], "in short (the ANOVA's terms with p < 0.05, largest share first):"),
        (
            ["MU (quadratic surface): A (p 0.01)", "MU at the COF floor: test 7 (50 %) ..."],
            "in short (the terms with p < 0.05 of each response's quadratic surface, smallest "
            "p first):",
        ),
        (  # a response too few runs fit a quadratic for keeps its ANOVA's line (a diff review)
            ["MU (quadratic surface): A (p 0.01)", "V: WP (90.0 %)"],
            "in short (the terms with p < 0.05 of each response's quadratic surface, smallest "
            "p first; otherwise the ANOVA's terms with p < 0.05, largest share first):",
        ),
    ],
)
def test_the_in_short_heading_says_which_model_its_lines_are_of(lines, heading) -> None:
    import io

    from rich.console import Console

    buffer = io.StringIO()
    saved, cli.out = cli.out, Console(file=buffer, width=300)
    try:
        cli._print_in_short(lines)
    finally:
        cli.out = saved
    assert buffer.getvalue().splitlines()[0] == heading


def test_an_interrupted_campaign_on_an_existing_cluster_says_its_workers_go_on(
    tmp_path, monkeypatch
) -> None:
    """A cluster review: stopped, a campaign on an existing cluster said only that the same
    command resumes, while the cluster's workers went on with their runs for minutes."""

    def interrupted(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(brakeca.campaign, "run_campaign", interrupted)
    design = tmp_path / "d.toml"
    design.write_text(TINY_DESIGN)
    args = ["run", str(design), "-o", str(tmp_path / "c"), "--executor", "dask"]
    res = _invoke(*args, "--scheduler", "tcp://127.0.0.1:1")
    said = " ".join(res.output.split())
    assert res.exit_code == 130, res.output
    assert "the same command resumes; the cluster's workers finish the runs they had begun" in said
    res = _invoke(*args[:-2])  # the local executor stops its own workers: nothing to add
    assert res.exit_code == 130 and "cluster's workers" not in res.output


def test_a_long_runs_table_shows_its_first_and_last_rows() -> None:
    """A review of large designs: a 256-test design printed 262 lines, the report's "in
    short" pushed off the screen; beyond 48 rows the first 24 and the last 12 are shown."""
    import io

    from rich.console import Console

    rows = [
        {"test": t, "order": t, "A": 10.0, "seed": t, "run_id": "x", "MU": 0.2, "V_mm3": 1.5,
         "status": "ok"}
        for t in range(1, 61)
    ]  # fmt: skip
    saved = cli.out
    try:
        cli.out = Console(file=io.StringIO(), width=100, record=True)
        cli._print_summary(pd.DataFrame(rows))
        text = cli.out.export_text()
    finally:
        cli.out = saved
    shown = [int(line.split("│")[1]) for line in text.splitlines() if line.startswith("│ ")
             and line.split("│")[1].strip().isdigit()]  # fmt: skip
    assert shown == [*range(1, 25), *range(49, 61)]
    assert "⋮" in text and "24 rows not shown: summary.csv has every run" in " ".join(text.split())
