"""The Examples sections of brakeca's docstrings run, and show what they say they show.

Every module of the package is searched, so an example added anywhere runs; the modules
listed in :data:`WITH_EXAMPLES` must keep at least that many docstrings with examples (a test
fails where they go missing). They run as doctests with the module's namespace, as
``python -m doctest`` would.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import brakeca

#: The modules whose docstrings hold examples, and the fewest such docstrings each has.
WITH_EXAMPLES = {
    "brakeca.friction": 3,
    "brakeca.wear": 2,
    "brakeca.reference": 2,
    "brakeca.contact": 3,
    "brakeca.geometry": 1,
    "brakeca.cycle": 4,
    "brakeca.surface": 1,
    "brakeca.emissions": 3,
    "brakeca.config": 2,
    "brakeca.design": 3,
    "brakeca.analysis": 5,
    "brakeca.simulation": 1,
    "brakeca.results": 1,
    "brakeca.presets": 2,
}

#: Every module of the package but the command line's entry point (``python -m brakeca``).
MODULES = sorted(
    info.name
    for info in pkgutil.walk_packages(brakeca.__path__, "brakeca.")
    if info.name != "brakeca.__main__"
)


def test_the_listed_modules_are_the_packages() -> None:
    assert set(WITH_EXAMPLES) <= set(MODULES)
    assert len(MODULES) > 30  # the package's modules were found


@pytest.mark.parametrize("name", MODULES)
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
    assert len(with_examples) >= WITH_EXAMPLES.get(name, 0), with_examples
