"""The command-line help reads on an 80-column terminal: every option's whole name is shown,
and the units written in brackets in the help texts are not taken for markup."""

from __future__ import annotations

import re

import pytest
import typer.main
from typer.testing import CliRunner

from brakeca.cli import app

COMMANDS = [
    ["simulate"],
    ["surface"],
    ["plot"],
    ["run"],
    ["analyze"],
    ["optimize"],
    ["power"],
    ["paper"],
    ["config"],
    ["design"],
    ["docs"],
    ["cycle", "inspect"],
]


def _command(args: list[str]):
    """The click command (or group) that ``brakeca ARGS`` names."""
    command = typer.main.get_command(app)
    for name in args:
        command = command.commands[name]
    return command


def _help(args: list[str]) -> str:
    res = CliRunner().invoke(app, [*args, "--help"], env={"COLUMNS": "80"}, terminal_width=80)
    assert res.exit_code == 0, res.output
    return res.output


@pytest.mark.parametrize("args", COMMANDS, ids=" ".join)
def test_help_fits_80_columns_with_whole_option_names(args):
    text = _help(args)
    for param in _command(args).params:
        for opt in param.opts:
            if opt.startswith("--"):
                assert re.search(rf"(^|[\s,/]){re.escape(opt)}\b", text, re.M), (opt, text)
    assert "…" not in text
    assert max(len(line) for line in text.splitlines()) <= 80


def test_units_in_brackets_are_shown():
    text = _help(["cycle", "inspect"])
    assert "[s] a trace's shortest braking event kept" in text
    assert "[m/s²] a trace's braking" in text


@pytest.mark.parametrize("args", [[], ["cycle"]], ids=["brakeca", "brakeca cycle"])
def test_command_lists_are_not_cut(args):
    text = _help(args)
    commands = text.split("Commands:")[1]
    assert "..." not in commands and "…" not in commands
    names = [line.split()[0] for line in commands.strip().splitlines()]
    assert sorted(names) == sorted(_command(args).commands)


def test_every_command_is_registered():
    """A helper put between a command's decorator and its function had taken the command's
    place: ``brakeca optimize`` was gone, and only an integration test noticed."""
    top = typer.main.get_command(app).commands
    assert sorted(top) == sorted(
        ["simulate", "plot", "surface", "run", "analyze", "optimize", "power", "paper",
         "design", "config", "docs", "cycle"]
    )  # fmt: skip
    assert top["optimize"].callback.__name__ == "optimize"


def test_docs_says_where_the_documents_are_and_prints_one() -> None:
    """A packaging review: the help texts and reports cite docs/model.md and the others,
    which an installed package had no way to reach; the wheel carries them and 'brakeca
    docs' finds them (here, the checkout's)."""
    from pathlib import Path

    from brakeca.cli import DOCS

    res = CliRunner().invoke(app, ["docs"])
    assert res.exit_code == 0, res.output
    folder = Path(res.output.splitlines()[0].removeprefix("documents in ").rstrip(":"))
    assert set(DOCS) <= {p.stem for p in folder.glob("*.md")}
    for key in DOCS:
        assert f"  {key} " in res.output
    res = CliRunner().invoke(app, ["docs", "docs/model.md"])
    assert res.exit_code == 0 and res.output == (folder / "model.md").read_text(encoding="utf-8")
    res = CliRunner().invoke(app, ["docs", "modle"])
    assert res.exit_code == 2
    assert "no document 'modle'; choose one of model, designs," in res.output


def test_h_is_help_too() -> None:
    """A command-line review: 'brakeca simulate -h' read "No such option: -h"."""
    from typer.testing import CliRunner

    from brakeca.cli import app

    for args in (["-h"], ["simulate", "-h"], ["cycle", "inspect", "-h"]):
        res = CliRunner().invoke(app, args)
        assert res.exit_code == 0 and "Usage: " in res.output, (args, res.output)


def test_a_files_output_that_is_empty_or_a_folder_says_so(tmp_path) -> None:
    """A command-line review: "-o ''" of simulate, surface and cycle inspect read "File ''
    is a directory"; a folder given is named as one."""
    from typer.testing import CliRunner

    from brakeca.cli import app

    for command in (["simulate"], ["surface"], ["cycle", "inspect", "paper"]):
        empty = CliRunner().invoke(app, [*command, "-o", ""])
        assert empty.exit_code == 2 and "an empty path; give the file to write" in empty.output
        folder = CliRunner().invoke(app, [*command, "-o", str(tmp_path)])
        text = " ".join(folder.output.split())
        assert folder.exit_code == 2 and "is a folder; give the file to write in it" in text
