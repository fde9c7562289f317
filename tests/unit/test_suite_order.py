"""The suite's own bookkeeping: the files it runs first are files it has."""

from __future__ import annotations

from pathlib import Path

from conftest import LONGEST_FIRST


def test_the_files_run_first_exist() -> None:
    """A file renamed or removed would drop out of the order silently (tests/conftest.py)."""
    tests = Path(__file__).parents[1]
    assert [name for name in LONGEST_FIRST if not (tests / name).is_file()] == []
    assert len(set(LONGEST_FIRST)) == len(LONGEST_FIRST)
