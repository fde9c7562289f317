"""The paper study's reference summary and ``benchmarks/study_check.py``, which compares to it."""

from __future__ import annotations

import csv
import importlib.util
from pathlib import Path
from types import ModuleType

import pytest

from brakeca.design import load_design

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "study_check.py"


def _load_script() -> ModuleType:
    spec = importlib.util.spec_from_file_location("study_check", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


study_check = _load_script()


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


def test_reference_is_the_paper_study_at_full_resolution() -> None:
    """Each reference row is the paper design's run of that test: same levels, seed and run id.

    The run id hashes the resolved configuration (full resolution, every stop) and the seed, so
    a change to the preset, the design or the seeding makes the reference stale here first.
    """
    rows = _rows(study_check.REFERENCE)
    points = load_design("paper").points()
    assert [(int(r["test"]), int(r["replicate"])) for r in rows] == [
        (p.test, p.replicate) for p in points
    ]
    for row, point in zip(rows, points, strict=True):
        assert row["run_id"] == point.run_id
        assert int(row["seed"]) == point.seed
        assert {name: float(row[name]) for name in point.levels} == point.levels
        assert row["status"] == "ok"
        assert int(row["n_steps"]) == 491160  # the whole 170-stop cycle
    assert "wall_time" not in rows[0]


def _write(path: Path, rows: list[dict[str, str]], columns: list[str]) -> Path:
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    return path


def test_check_passes_an_equal_study_whatever_its_wall_times(tmp_path: Path) -> None:
    rows = _rows(study_check.REFERENCE)
    columns = [*rows[0], "wall_time"]
    study = [dict(r, wall_time=str(10.0 + k)) for k, r in enumerate(rows)]
    _write(tmp_path / "summary.csv", study[::-1], columns)  # row order does not matter
    assert study_check.main(["check", str(tmp_path)]) == 0


def test_check_names_every_value_row_and_column_that_differs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rows = _rows(study_check.REFERENCE)
    columns = list(rows[0])
    changed = [dict(r) for r in rows[1:]]  # test 1 missing
    mu = float(changed[4]["MU"])
    changed[4]["MU"] = repr(mu + mu * 2.0**-52)  # test 6, one unit in the last place
    _write(tmp_path / "summary.csv", changed, [c for c in columns if c != "V_mm3"])
    assert study_check.main(["check", str(tmp_path / "summary.csv")]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[:-1] == [
        "column 'V_mm3' only in the reference",
        "test 1, replicate 0: only in the reference",
        f"test 6, replicate 0, MU: reference {rows[5]['MU']}, study {changed[4]['MU']}",
    ]
    assert out[-1].startswith("3 difference(s)")


def test_save_then_check_round_trips(tmp_path: Path) -> None:
    reference = tmp_path / "reference.csv"
    rows = _rows(study_check.REFERENCE)
    study = _write(tmp_path / "summary.csv", rows, list(rows[0]))
    assert study_check.main(["save", str(study), "--reference", str(reference)]) == 0
    assert reference.read_text() == study_check.REFERENCE.read_text()
    assert study_check.main(["check", str(study), "--reference", str(reference)]) == 0


def test_a_study_without_summary_is_refused(tmp_path: Path) -> None:
    with pytest.raises(SystemExit) as err:
        study_check.main(["check", str(tmp_path)])
    assert err.value.code == 2


def test_a_file_that_is_not_a_summary_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    other = tmp_path / "other.csv"
    other.write_text("a,b\n1,2\n")
    with pytest.raises(SystemExit) as err:
        study_check.main(["check", str(other)])
    assert err.value.code == 2
    assert "not a campaign summary (no test and replicate columns)" in capsys.readouterr().err
