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

    def to_csv(self, path: Path, index: bool, compression: str | None) -> None:
        assert index is False and compression is None
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


@pytest.mark.parametrize("kind", ["PCG64", "PCG64DXSM", "MT19937", "Philox", "SFC64"])
def test_a_generator_s_state_round_trips_through_json(kind):
    """simulate(rng=) records the state as JSON; MT19937, Philox and SFC64 keep numpy arrays
    in theirs, which json.dumps refused (a review of the change that records it)."""
    import numpy as np

    from brakeca._io import rng_state_from_json, rng_state_json

    rng = np.random.Generator(getattr(np.random, kind)(7))
    rng.random(5)
    text = rng_state_json(rng.bit_generator.state)
    bit_generator = getattr(np.random, kind)()
    bit_generator.state = rng_state_from_json(text)
    assert np.array_equal(np.random.Generator(bit_generator).random(9), rng.random(9))


def test_a_compressed_table_is_compressed_by_its_suffix(tmp_path):
    """to_csv infers gzip from ".gz"; the temporary name the atomic write uses has no such
    suffix, so write_table gives the compression itself (a review)."""
    import gzip

    path = write_table(pd.DataFrame({"a": [1]}), tmp_path / "t.csv.gz")
    assert gzip.decompress(path.read_bytes()) == b"a\n1\n"


def test_a_long_list_of_a_configuration_change_is_shown_by_its_first_item() -> None:
    """A review: the refusal of a trace campaign's folder for the block cycle printed all
    nine block tables on one line; a long list is its first item and its length."""
    import copy

    from brakeca._io import config_changes
    from brakeca.presets import load_preset

    paper = load_preset("paper").to_dict()
    trace = copy.deepcopy(paper)
    trace["cycle"]["blocks"] = []
    (change,) = config_changes(trace, paper)
    assert change.startswith("cycle.blocks: [] -> [{'name': 'Burnish', ")
    assert change.endswith(", ... (9 items)]") and change.count("'name'") == 1
    # two lists of one length: the item that differs, not two lists shortened alike
    more = copy.deepcopy(paper)
    more["cycle"]["blocks"][4]["stops"] += 1
    (change,) = config_changes(paper, more)
    assert change.startswith("cycle.blocks[4]: {'name': ") and "'stops': " in change
    assert "items" not in change
    short = copy.deepcopy(paper)
    short["mesh"]["n_radial"] = 21
    assert config_changes(paper, short) == ["mesh.n_radial: 201 -> 21"]


def test_a_replacement_windows_refuses_is_tried_again_then_named(tmp_path, monkeypatch) -> None:
    """Windows refuses to replace a file another program holds open (Excel holding
    summary.csv): tried again for a while, then refused with the likely cause; elsewhere
    the first refusal stands (a portability review)."""
    import os

    import brakeca._io as io_module

    monkeypatch.setattr(io_module, "_WINDOWS_RETRIES", (0.0, 0.0, 0.0))
    real = os.replace
    calls = []

    def held(times: int):
        def replace(src, dst):
            calls.append(dst)
            if len(calls) <= times:
                raise PermissionError(13, "Access is denied")
            real(src, dst)

        return replace

    target, tmp = tmp_path / "summary.csv", tmp_path / ".summary.csv.tmp"
    monkeypatch.setattr(io_module.os, "replace", held(2))  # released after two refusals
    tmp.write_text("a\n")
    io_module._replace(tmp, target, windows=True)
    assert target.read_text() == "a\n" and len(calls) == 3
    calls.clear()
    monkeypatch.setattr(io_module.os, "replace", held(10))  # held throughout
    tmp.write_text("b\n")
    with pytest.raises(
        PermissionError, match=r"is summary\.csv open in another program"
    ) as held_open:
        io_module._replace(tmp, target, windows=True)
    assert len(calls) == 4 and target.read_text() == "a\n"
    # the file named (the command names it), not the temporary one Windows refused
    assert held_open.value.errno == 13 and held_open.value.filename == str(target)
    calls.clear()
    with pytest.raises(PermissionError, match="Access is denied") as raised:
        io_module._replace(tmp, target, windows=False)
    assert len(calls) == 1 and "another program" not in str(raised.value)
