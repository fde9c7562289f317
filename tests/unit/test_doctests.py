"""The Examples sections of brakeca's docstrings run, and show what they say they show.

Each module listed here has examples (a module whose examples were all removed fails too);
they run as doctests with the module's namespace, as ``python -m doctest`` would.
"""

from __future__ import annotations

import doctest
import importlib

import pytest

#: The modules with examples, and the fewest examples each holds.
MODULES = {
    "brakeca.friction": 3,
    "brakeca.wear": 2,
    "brakeca.reference": 2,
    "brakeca.contact": 3,
    "brakeca.geometry": 1,
    "brakeca.cycle": 4,
    "brakeca.surface": 1,
    "brakeca.emissions": 2,
    "brakeca.config": 2,
    "brakeca.design": 3,
    "brakeca.analysis": 3,
    "brakeca.simulation": 1,
}


@pytest.mark.parametrize("name", list(MODULES))
def test_docstring_examples_run(name: str) -> None:
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False
    )
    report: list[str] = []
    tests = [t for t in finder.find(module, name) if t.examples]
    for test in tests:
        runner.run(test, out=report.append)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, "".join(report)
    with_examples = sorted(t.name for t in tests)
    assert len(with_examples) >= MODULES[name], with_examples
