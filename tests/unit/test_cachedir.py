"""numba's cache folder follows the package's sources (a helper's change is never served stale)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import brakeca
from brakeca._cachedir import source_key

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
