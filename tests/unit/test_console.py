"""The command line's console keeps messages on one line in a log file."""

from __future__ import annotations

import io

from rich.console import Console
from rich.table import Table

from brakeca._console import LogConsole, say

LONG = "error: " + " ".join(["/a/long/path/to/a/design/file/named/in/the/message"] * 4)


def _printed(console_type: type[Console], *objects: object, terminal: bool = False) -> str:
    buffer = io.StringIO()
    console = console_type(file=buffer, width=80, force_terminal=terminal)
    console.print(*objects)
    return buffer.getvalue()


def test_long_message_is_one_line_in_a_log() -> None:
    assert _printed(Console, LONG).count("\n") > 1  # what rich alone does at 80 columns
    text = _printed(LogConsole, LONG)
    assert text.count("\n") == 1
    assert text == LONG + "\n"


def test_terminal_and_tables_are_laid_out_as_by_rich() -> None:
    assert _printed(LogConsole, LONG, terminal=True) == _printed(Console, LONG, terminal=True)
    table = Table("test", "MU")
    table.add_row("1", "0.2718")
    assert _printed(LogConsole, table) == _printed(Console, table)


def test_say_applies_the_rule_on_any_console() -> None:
    buffer = io.StringIO()
    say(Console(file=buffer, width=80), LONG)
    assert buffer.getvalue() == LONG + "\n"


def test_the_width_follows_columns_set_after_the_console_is_made(monkeypatch) -> None:
    """rich fixes the width COLUMNS gives when a console is made; the command line's are made
    at import, so ``CliRunner(env={"COLUMNS": ...})`` had no effect where COLUMNS was set
    then (as it is in a pytest-xdist worker)."""
    monkeypatch.setenv("COLUMNS", "80")
    console = LogConsole(file=io.StringIO())
    assert Console(file=io.StringIO()).width == 80 and console.width == 80
    monkeypatch.setenv("COLUMNS", "132")
    assert Console(file=io.StringIO(), width=None).width == 132  # made now: rich reads it
    assert console.width == 132
    assert LogConsole(file=io.StringIO(), width=100).width == 100  # a width given is kept
    assert LogConsole(file=io.StringIO(), width=100, height=10).size == (100, 10)


def test_run_tags_sort_in_test_order_at_any_size() -> None:
    import pandas as pd

    from brakeca._console import run_tags

    small = pd.DataFrame({"test": [1, 2, 24], "replicate": [0, 0, 0]})
    assert [run_tags(small)(row) for _, row in small.iterrows()] == [
        "test01_r0",
        "test02_r0",
        "test24_r0",
    ]
    big = pd.DataFrame({"test": [5, 11, 100, 100], "replicate": [0, 0, 9, 10]})
    tags = [run_tags(big)(row) for _, row in big.iterrows()]
    assert tags == ["test005_r00", "test011_r00", "test100_r09", "test100_r10"]
    assert sorted(tags) == tags
    no_replicate = pd.DataFrame({"test": [3]})
    assert run_tags(no_replicate)({"test": 3}) == "test03_r0"


def test_tests_named_counts_those_it_leaves_out() -> None:
    from brakeca._console import tests_named

    assert tests_named([3]) == "test 3"
    assert tests_named([4, 1, 2, 2]) == "tests 1, 2, 4"
    assert tests_named(range(1, 126)) == "tests 1, 2, 3, 4, 5, 6, 7, 8 and 117 more"
