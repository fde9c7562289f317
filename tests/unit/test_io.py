"""Tables, text and figures are written atomically: a writer stopped halfway (an error, Ctrl-C)
leaves the file as it was, whole, and no temporary file behind."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import pandas as pd
import pytest

from brakeca._io import write_table, write_text
from brakeca.plotting import save_figure


class _Cut(Exception):
    """The writer's failure halfway."""


class _HalfTable:
    """A table whose CSV writer writes a first line and then fails."""

    def to_csv(self, path: Path, index: bool) -> None:
        assert index is False
        Path(path).write_text("MU,V\n", encoding="utf-8")
        raise _Cut


def test_a_table_is_written_whole_and_without_its_index(tmp_path):
    path = write_table(pd.DataFrame({"MU": [0.2, 0.3]}, index=[7, 8]), tmp_path / "t.csv")
    assert path.read_text(encoding="utf-8") == "MU\n0.2\n0.3\n"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]


def test_a_table_cut_off_halfway_leaves_the_old_one(tmp_path):
    path = tmp_path / "effects_MU.csv"
    path.write_text("old\n", encoding="utf-8")
    with pytest.raises(_Cut):
        write_table(_HalfTable(), path)
    assert path.read_text(encoding="utf-8") == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["effects_MU.csv"]


def test_text_is_written_with_newline_line_ends(tmp_path):
    path = write_text(tmp_path / "sub" / "README.md", "a\nb\n")
    assert path.read_bytes() == b"a\nb\n"


def test_a_figure_cut_off_halfway_leaves_the_old_one(tmp_path, monkeypatch):
    path = tmp_path / "main_effects_MU.png"
    path.write_bytes(b"old")
    fig, _ = plt.subplots()
    try:

        def half(target, **kwargs):
            Path(target).write_bytes(b"\x89PNG")
            raise KeyboardInterrupt

        monkeypatch.setattr(fig, "savefig", half)
        with pytest.raises(KeyboardInterrupt):
            save_figure(fig, path)
        assert path.read_bytes() == b"old"
        assert [p.name for p in tmp_path.iterdir()] == ["main_effects_MU.png"]
        monkeypatch.undo()
        save_figure(fig, path)
        assert path.read_bytes()[:4] == b"\x89PNG"
        assert [p.name for p in tmp_path.iterdir()] == ["main_effects_MU.png"]
    finally:
        plt.close(fig)
