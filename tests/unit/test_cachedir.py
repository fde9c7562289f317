"""numba's cache folder of brakeca's kernels follows the package's sources (a helper's change is
never served stale), and no other numba function's."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import brakeca
from brakeca._cachedir import KERNEL_SOURCES, prune, source_key

PACKAGE = Path(brakeca.__file__).resolve().parent


_PROBE = """
import json, os, sys
import brakeca
imported = {"env": os.environ.get("NUMBA_CACHE_DIR"), "numba": "numba" in sys.modules}
import brakeca.wear
import numba.core.config as config
sys.path.insert(0, sys.argv[1])
import users_module
print(json.dumps({
    **imported,
    "env_after": os.environ.get("NUMBA_CACHE_DIR"),
    "config_after": config.CACHE_DIR,
    "brakeca": brakeca.wear.archard_wear_depth._cache._cache_path,
    "users": users_module.twice._cache._cache_path,
}))
"""


def _probe(tmp_path: Path, env: dict[str, str]) -> dict[str, object]:
    """What a fresh interpreter sees: the environment and numba's setting after ``import
    brakeca`` and after a compiling module, and where numba caches one of brakeca's kernels
    and one of a user's own cached functions."""
    users = tmp_path / "users"
    users.mkdir(exist_ok=True)
    (users / "users_module.py").write_text(
        "from numba import njit\n\n@njit(cache=True)\ndef twice(x):\n    return 2 * x\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", _PROBE, str(users)],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    return dict(json.loads(out.stdout.strip().splitlines()[-1]))


def _env(**changes: str | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    for key, value in changes.items():
        if value is None:
            env.pop(key, None)
        else:
            env[key] = value
    return env


def test_cache_folder_is_keyed_by_the_sources_and_only_for_brakeca(tmp_path) -> None:
    """brakeca's kernels are cached in the folder of this version of the sources; importing
    brakeca sets no variable and no numba setting, and a user's own cached numba function
    stays where numba puts it (a review had found NUMBA_CACHE_DIR set by ``import
    brakeca``, which redirected every numba cache of the process)."""
    folder = tmp_path / "xdg" / "brakeca" / "numba" / source_key()
    seen = _probe(tmp_path, _env(XDG_CACHE_HOME=str(tmp_path / "xdg")))
    assert seen["env"] is None and not seen["numba"]  # import brakeca: nothing yet
    assert seen["env_after"] is None and seen["config_after"] == ""
    assert Path(str(seen["brakeca"])).parent == folder
    assert folder.is_dir()
    assert Path(str(seen["users"])) == tmp_path / "users" / "__pycache__"  # numba's default


def test_a_set_cache_dir_is_kept(tmp_path) -> None:
    mine = tmp_path / "mine"
    seen = _probe(tmp_path, _env(NUMBA_CACHE_DIR=str(mine)))
    assert seen["env_after"] == str(mine) and seen["config_after"] == str(mine)
    assert Path(str(seen["brakeca"])).parent == mine
    assert Path(str(seen["users"])).parent == mine  # numba's own rule, for everyone


def test_an_unwritable_cache_home_falls_back_to_a_private_temporary_folder(tmp_path) -> None:
    """A read-only home (a container, a locked-down account): the kernels are cached in the
    user's own folder in the temporary folder, made private (a review: with the package
    installed read-only too, numba stopped every run with 'no locator available')."""
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    temp = tmp_path / "tmp"
    temp.mkdir()
    seen = _probe(tmp_path, _env(XDG_CACHE_HOME=str(blocker), TMPDIR=str(temp)))
    assert seen["env_after"] is None and seen["config_after"] == ""
    private = temp / f"brakeca-{os.getuid()}"
    assert Path(str(seen["brakeca"])).parent == private / "numba" / source_key()
    assert private.stat().st_mode & 0o777 == 0o700


def test_a_temporary_folder_others_can_write_is_refused(tmp_path) -> None:
    """Another user's (or a world-writable) ``brakeca-<uid>`` in the temporary folder is not
    used, since numba's cache files are pickles; numba's default beside the sources (here
    writable) is left in place."""
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    temp = tmp_path / "tmp"
    (temp / f"brakeca-{os.getuid()}").mkdir(parents=True)
    (temp / f"brakeca-{os.getuid()}").chmod(0o777)
    seen = _probe(tmp_path, _env(XDG_CACHE_HOME=str(blocker), TMPDIR=str(temp)))
    assert Path(str(seen["brakeca"])) == PACKAGE / "__pycache__"  # beside the sources
    assert not (temp / f"brakeca-{os.getuid()}" / "numba").exists()


def test_no_writable_cache_anywhere_is_a_clear_error(monkeypatch, tmp_path) -> None:
    """No cache folder and read-only sources: install() says what to set, before numba
    would fail on the first kernel with 'cannot cache function ...: no locator available'."""
    import tempfile

    from brakeca import _cachedir

    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(_cachedir, "cache_folder", lambda: None)
    monkeypatch.setattr(_cachedir, "_PACKAGE", tmp_path / "read-only sources (missing)")
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    private = tmp_path / f"brakeca-{os.getuid()}"
    private.mkdir()
    private.chmod(0o755)
    message = r"cannot cache its compiled kernels.*NUMBA_CACHE_DIR"
    with pytest.raises(_cachedir.KernelCacheError, match=message) as info:
        _cachedir.install.__wrapped__()
    # it names the private folder and why it was refused (a review: "cannot be written")
    assert f"the private folder {private} is open to others (mode 755, not 700)" in str(info.value)


def test_a_linked_temporary_folder_is_refused(tmp_path) -> None:
    """``brakeca-<uid>`` as a link (to the user's own folder, even) is not followed."""
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    temp = tmp_path / "tmp"
    temp.mkdir()
    target = tmp_path / "elsewhere"
    target.mkdir(mode=0o700)
    (temp / f"brakeca-{os.getuid()}").symlink_to(target)
    seen = _probe(tmp_path, _env(XDG_CACHE_HOME=str(blocker), TMPDIR=str(temp)))
    assert Path(str(seen["brakeca"])) == PACKAGE / "__pycache__"  # beside the sources
    assert not (target / "numba").exists()


def test_a_change_to_compiled_code_changes_the_key_and_no_other_does(tmp_path) -> None:
    copy = tmp_path / "brakeca"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    assert source_key(copy) == source_key(PACKAGE)
    helper = copy / "_jit.py"  # a helper file, not a kernel's own
    helper.write_text(helper.read_text() + "\n# a change\n")
    changed = source_key(copy)
    assert changed != source_key(PACKAGE)
    helper.rename(copy / "_jit2.py")  # a missing file counts too
    assert source_key(copy) not in (changed, source_key(PACKAGE))
    helper = copy / "_jit2.py"
    helper.rename(copy / "_jit.py")
    for name in ("analysis.py", "cli.py", "config.py", "report.py"):  # no compiled code
        module = copy / name
        module.write_text(module.read_text() + "\n# a change\n")
    assert source_key(copy) == changed


_COMPILING = re.compile(r"^\s*@(njit|njit_noalloc|njit_noalloc_inline)\b|\bnjit\(", re.M)


def test_the_key_covers_every_module_compiled_code_comes_from() -> None:
    """KERNEL_SOURCES is every module that defines a jitted function and every brakeca module
    they import (in a fresh process), so no helper or constant a kernel uses is left out."""
    compiling = sorted(
        f"brakeca.{p.stem}" for p in PACKAGE.glob("*.py") if _COMPILING.search(p.read_text())
    )
    assert "brakeca._lazy" in compiling and "brakeca.wear" in compiling
    code = (
        "import importlib, json, sys\n"
        f"for name in {compiling!r}: importlib.import_module(name)\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.startswith('brakeca.'))))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    imported = {m.removeprefix("brakeca.") + ".py" for m in json.loads(out)}
    assert imported == set(KERNEL_SOURCES)


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


def test_the_kernels_touch_their_folder_and_prune_old_ones(tmp_path) -> None:
    root = tmp_path / "xdg" / "brakeca" / "numba"
    long_ago = 1.0e9  # [s since the epoch] 2001
    stale = _folder(root, "f" * 16, 0.0, long_ago, files=1)
    mine = _folder(root, source_key(), 0.0, long_ago)
    _probe(tmp_path, _env(XDG_CACHE_HOME=str(tmp_path / "xdg")))
    assert not stale.exists()
    assert mine.is_dir() and mine.stat().st_mtime > long_ago + 86400.0  # touched now


def test_every_cached_function_of_brakeca_uses_its_folder(tmp_path) -> None:
    """Each module that compiles calls ``_cachedir.install()`` before it decorates: a module
    that forgot would cache its functions beside the sources, where a helper's change would
    not reach them."""
    code = """
import importlib, pkgutil, sys, brakeca
from numba.core.registry import CPUDispatcher
for info in pkgutil.iter_modules(brakeca.__path__):
    if info.name not in ("__main__", "cli", "cli_cycle"):
        importlib.import_module("brakeca." + info.name)
seen = 0
for name, module in list(sys.modules.items()):
    if name.startswith("brakeca"):
        for value in vars(module).values():
            cache = getattr(value, "_cache", None)
            if isinstance(value, CPUDispatcher) and getattr(cache, "_impl", None) is not None:
                seen += 1
                kind = type(cache._impl.locator).__name__
                assert kind == "BrakecaCacheLocator", (name, value.__name__, kind)
print(seen)
"""
    out = subprocess.run(
        [sys.executable, "-c", code],
        env=_env(XDG_CACHE_HOME=str(tmp_path / "xdg")),
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    assert int(out.stdout.strip()) > 50  # the kernels and their helpers


def test_the_command_line_reports_no_cache_folder_in_a_line(monkeypatch, capsys) -> None:
    """``brakeca`` prints the message and exits with status 1, without a traceback."""
    from brakeca import _cachedir, cli

    def no_cache() -> None:
        raise _cachedir.KernelCacheError("brakeca cannot cache its compiled kernels: (test)")

    monkeypatch.setattr(cli, "app", no_cache)
    with pytest.raises(SystemExit) as stop:
        cli.main()
    assert stop.value.code == 1
    err = capsys.readouterr().err
    assert "error: brakeca cannot cache its compiled kernels: (test)" in err
    assert "Traceback" not in err
