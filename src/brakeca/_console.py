"""The rich console of the command line: messages stay on one line in a log file.

rich wraps text at the console's width, and a console that does not write to a terminal has
a width of 80 columns. So ``brakeca study ... > log`` would split a long message (an error that
names a path, a run's line) over two lines of the log, and ``grep`` would miss it.
:class:`LogConsole` prints plain-text messages unwrapped when its output is not a terminal;
tables and other renderables are laid out as rich lays them out, and a terminal sees no change.
"""

from __future__ import annotations

from typing import Any

from rich.console import Console


class LogConsole(Console):
    """A :class:`rich.console.Console` whose text messages are not wrapped outside a terminal."""

    def print(self, *objects: Any, soft_wrap: bool | None = None, **kwargs: Any) -> None:
        if soft_wrap is None and not self.is_terminal and all(isinstance(o, str) for o in objects):
            soft_wrap = True
        super().print(*objects, soft_wrap=soft_wrap, **kwargs)
