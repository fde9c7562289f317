"""numba's cache folder follows the package's sources (a helper's change is never served stale)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import brakeca
from brakeca._cachedir import prune, source_key

PACKAGE = Path(brakeca.__file__).resolve().parent


def _cache_dir_of_a_fresh_interpreter(env: dict[str, str]) -> str:
    code = (
        "import os, brakeca, numba.core.config as c;"
        "print(os.environ.get('NUMBA_CACHE_DIR', ''), c.CACHE_DIR, sep='|')"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return out.stdout.strip()


def _env(**changes: str | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    for key, value in changes.items():
        if value is None:
            env.pop(key, None)
        else:
            env[key] = value
    return env


def test_cache_folder_is_keyed_by_the_sources(tmp_path) -> None:
    folder = tmp_path / "xdg" / "brakeca" / "numba" / source_key()
    seen = _cache_dir_of_a_fresh_interpreter(_env(XDG_CACHE_HOME=str(tmp_path / "xdg")))
    assert seen == f"{folder}|{folder}"
    assert folder.is_dir()


def test_a_set_cache_dir_is_kept(tmp_path) -> None:
    mine = str(tmp_path / "mine")
    seen = _cache_dir_of_a_fresh_interpreter(_env(NUMBA_CACHE_DIR=mine))
    assert seen == f"{mine}|{mine}"


def test_an_unwritable_cache_home_leaves_numbas_default(tmp_path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    seen = _cache_dir_of_a_fresh_interpreter(_env(XDG_CACHE_HOME=str(blocker)))
    assert seen == "|"  # NUMBA_CACHE_DIR unset, numba's CACHE_DIR empty: its default


def test_any_change_to_any_module_changes_the_key(tmp_path) -> None:
    copy = tmp_path / "brakeca"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    assert source_key(copy) == source_key(PACKAGE)
    helper = copy / "_jit.py"  # a helper file, not a kernel's own
    helper.write_text(helper.read_text() + "\n# a change\n")
    assert source_key(copy) != source_key(PACKAGE)
    helper.rename(copy / "_jit2.py")  # names count too
    assert source_key(copy) != source_key(PACKAGE)


def _folder(root: Path, name: str, age: float, now: float, files: int = 0) -> Path:
    folder = root / name
    folder.mkdir(parents=True)
    for k in range(files):
        path = folder / f"kernel{k}.nbi"
        path.write_text("x")
        os.utime(path, (now - age, now - age))
    os.utime(folder, (now - age, now - age))
    return folder


def test_prune_removes_only_other_versions_unused_long_enough(tmp_path) -> None:
    now = 2.0e9
    day = 86400.0
    current = _folder(tmp_path, "0" * 16, 90 * day, now, files=2)  # in use, however old
    empty_old = _folder(tmp_path, "1" * 16, 2 * day, now)
    empty_new = _folder(tmp_path, "2" * 16, 3600.0, now)  # a process of it may be starting
    full_old = _folder(tmp_path, "3" * 16, 31 * day, now, files=3)
    full_recent = _folder(tmp_path, "4" * 16, 29 * day, now, files=3)
    touched = _folder(tmp_path, "5" * 16, 31 * day, now, files=1)
    os.utime(touched / "kernel0.nbi", (now - day, now - day))  # one file used yesterday
    other = _folder(tmp_path, "not-a-key", 90 * day, now)  # not ours
    upper = _folder(tmp_path, "A" * 16, 90 * day, now)  # not a source key either
    removed = prune(current, now=now)
    assert sorted(removed) == sorted([empty_old, full_old])
    for kept in (current, empty_new, full_recent, touched, other, upper):
        assert kept.is_dir()
    assert not empty_old.exists() and not full_old.exists()


def test_import_touches_its_folder_and_prunes_old_ones(tmp_path) -> None:
    root = tmp_path / "xdg" / "brakeca" / "numba"
    long_ago = 1.0e9  # [s since the epoch] 2001
    stale = _folder(root, "f" * 16, 0.0, long_ago, files=1)
    mine = _folder(root, source_key(), 0.0, long_ago)
    _cache_dir_of_a_fresh_interpreter(_env(XDG_CACHE_HOME=str(tmp_path / "xdg")))
    assert not stale.exists()
    assert mine.is_dir() and mine.stat().st_mtime > long_ago + 86400.0  # touched now
