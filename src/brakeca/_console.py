"""The rich console of the command line: messages stay on one line in a log file.

rich wraps text at the console's width, and a console that does not write to a terminal has
a width of 80 columns. So ``brakeca study ... > log`` would split a long message (an error that
names a path, a run's line) over two lines of the log, and ``grep`` would miss it.
:class:`LogConsole` prints plain-text messages unwrapped when its output is not a terminal;
tables and other renderables are laid out as rich lays them out, and a terminal sees no change.
:func:`say` applies the same rule on any console (the campaign's messages, whose console a
library caller may give).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from typing import Any

from rich.console import Console


def _unwrapped(console: Console, objects: tuple[Any, ...]) -> bool:
    """Whether ``objects`` go out unwrapped: text, to a console that is not a terminal."""
    return not console.is_terminal and all(isinstance(o, str) for o in objects)


def say(console: Console, *objects: Any, **kwargs: Any) -> None:
    """Print a message on ``console``, any rich console (a library caller's too), by the rule
    of :class:`LogConsole`: text unwrapped when the console is not a terminal."""
    console.print(*objects, soft_wrap=_unwrapped(console, objects), **kwargs)


class LogConsole(Console):
    """A :class:`rich.console.Console` whose text messages are not wrapped outside a terminal.

    Without an explicit ``width`` it reads ``COLUMNS`` (or the terminal's size) each time it
    lays something out, where rich fixes the width it finds in ``COLUMNS`` when the console is
    made: the command line's consoles are made when :mod:`brakeca.cli` is imported, so a
    caller that sets ``COLUMNS`` later (``CliRunner(env=...)``, a test run in a pytest-xdist
    worker) had been held to the width of the import. In Jupyter rich's own width stands."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not self.is_jupyter:  # (a notebook's console keeps rich's own width)
            if kwargs.get("width") is None:
                self._width = None
            if kwargs.get("height") is None:
                self._height = None

    def print(self, *objects: Any, soft_wrap: bool | None = None, **kwargs: Any) -> None:
        if soft_wrap is None and _unwrapped(self, objects):
            soft_wrap = True
        super().print(*objects, soft_wrap=soft_wrap, **kwargs)

    def on_broken_pipe(self) -> None:
        """Where the reader of its output has gone (``brakeca run ... | head``), write no
        more and go on: rich's own ended the command there with exit status 1 and no word
        (a campaign's report lines lost, a finished study read as a failure under
        ``pipefail``; a command-line review); the work goes on to its end and its status."""
        self.quiet = True
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self.file.fileno())
            os.close(devnull)
        except (OSError, ValueError, AttributeError):  # no file descriptor: just quiet
            pass


def brief_warnings() -> Callable[[], None]:
    """Show brakeca's own warnings (:class:`brakeca.checkpoint.CheckpointWarning`,
    :class:`brakeca.config.UnitWarning`) as one line, ``warning: MESSAGE``, where Python's
    format names the library's file and line and quotes its source (``.../_executors.py:548:
    CheckpointWarning: ...`` and ``return simulate(``), which says nothing to the command's
    user; other warnings keep Python's format. For the command line (here, where importing
    it loads only rich: every command sets it) and its worker processes; returns the
    function that puts Python's format back."""
    import warnings

    default = warnings.formatwarning

    def formatwarning(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        line: str | None = None,
    ) -> str:
        if category.__module__.split(".")[0] == "brakeca":
            return f"warning: {message}\n"
        return default(message, category, filename, lineno, line)

    warnings.formatwarning = formatwarning

    def restore() -> None:
        warnings.formatwarning = default

    return restore


def is_replicated(frame: Any) -> bool:
    """Whether a summary or residuals table holds more than one replicate of a test, so that
    :func:`run_named` names the replicate too."""
    return "replicate" in frame.columns and frame["replicate"].nunique() > 1


def run_tags(frame: Any) -> Callable[[Any], str]:
    """The names of a summary's runs in file names: ``tag(row)`` gives ``"test06_r0"``, the
    test number zero-padded to the width of the largest in ``frame`` (at least two digits)
    and the replicate to that of the largest replicate, so that a listing sorted by name
    lists the runs in test order (``test100`` had sorted before ``test11``: a review)."""

    def width(column: str, least: int) -> int:
        if column not in frame.columns or len(frame) == 0:
            return least
        return max(least, len(str(int(frame[column].max()))))

    tests, replicates = width("test", 2), width("replicate", 1)

    def tag(row: Any) -> str:
        replicate = int(row["replicate"]) if "replicate" in row.keys() else 0
        return f"test{int(row['test']):0{tests}d}_r{replicate:0{replicates}d}"

    return tag


def run_named(row: Any, replicated: bool) -> str:
    """A run in a message: ``"test 3"``, with ``", replicate 1"`` in a ``replicated``
    campaign (and a replicate given), ``"a run"`` without a test number; ``row`` is a
    summary or residuals row (a mapping or a pandas Series)."""

    def given(value: Any) -> bool:  # not None, NaN or pandas' NA
        if value is None:
            return False
        try:
            return not bool(value != value)
        except TypeError:  # pandas.NA
            return False

    test, replicate = row.get("test"), row.get("replicate")
    who = f"test {int(test)}" if given(test) else "a run"
    if replicated and given(replicate):
        who += f", replicate {int(replicate)}"
    return who


def tests_named(numbers: Iterable[int], most: int = 8) -> str:
    """Test numbers in a message, each once and in order, at most ``most`` of them:
    ``"test 3"``, ``"tests 1, 2, 4"``, ``"tests 1, 2, ..., 8 and 117 more"`` (the rest
    counted, as the docs promise: "and others" had not said how many; an analysis review)."""
    shown = sorted(set(numbers))
    return f"test{'s' if len(shown) > 1 else ''} {', '.join(map(str, shown[:most]))}" + (
        f" and {len(shown) - most} more" if len(shown) > most else ""
    )
