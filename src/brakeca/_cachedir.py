"""Where numba caches brakeca's compiled kernels: a folder per version of the sources.

numba decides whether a cached kernel is still valid from the kernel's own source file only,
not from the files of the helpers compiled into it (numba issue/PR 8396, not merged). After an
update that changes only a helper, a shared cache would serve a kernel with the old helper
inside, and results would silently be those of the old code. So brakeca caches its own
compiled functions in ``$XDG_CACHE_HOME/brakeca/numba/<key>`` (``~/.cache`` when
``XDG_CACHE_HOME`` is unset), where ``<key>`` is a hash of the package's files that
compiled code comes from (:data:`KERNEL_SOURCES`), so that a change elsewhere (the analysis,
the report, the command line) loads the kernels already compiled.

It does so with a cache locator of its own (:func:`install`, called by every module that
compiles), which numba asks first and which answers only for functions defined in brakeca's
own files: ``import brakeca`` sets no environment variable and changes no numba setting, and
the numba functions of other packages and of the user's code are cached where numba puts them.
Worker and warm-up processes compute the same folder from the same sources. If
``NUMBA_CACHE_DIR`` is set (``scripts/paper`` and ``scripts/test`` set their own, keyed the
same way), numba's own locator puts everything there instead. If the folder cannot be created
(a read-only home), a private folder of the user's in the system's temporary folder is used
(``brakeca-<uid>/numba/<key>``, mode 0700, refused unless the user owns it); if neither can,
numba's default (``__pycache__`` beside the sources) is left in place where the sources are
writable, and otherwise :func:`install` stops with a message that names ``NUMBA_CACHE_DIR``
(numba's own error named a locator and the source file). If numba's caching
internals are not the ones this module knows, it falls back to setting ``NUMBA_CACHE_DIR``
for the process. The first compiling module of a process touches its version's folder; the
folders of other versions are removed once unused: an empty one after a day, any other after
30 days (:func:`prune`; a version used again later just compiles once more).
"""

from __future__ import annotations

import functools
import hashlib
import os
from pathlib import Path
from typing import Any

__all__ = [
    "KernelCacheError",
    "cache_folder",
    "install",
    "kernel_cache_dir",
    "prune",
    "source_key",
]

_PACKAGE = Path(__file__).resolve().parent

#: [s] another version's cache folder is removed after this long untouched
KEEP_UNUSED = 30 * 86400.0
#: [s] another version's empty cache folder (a version imported, nothing compiled) is removed
#: after this long: not at once, since a process of that version may be just starting
KEEP_EMPTY = 86400.0


class KernelCacheError(RuntimeError):
    """No folder brakeca's compiled kernels could be cached in (see :func:`install`)."""


#: The package's files that numba's compiled code comes from: every module that defines a
#: jitted function, and the brakeca modules they import (a kernel may call their functions or
#: read their constants, which numba freezes into the machine code). A test checks it against
#: those modules' imports.
KERNEL_SOURCES: tuple[str, ...] = (
    "_cachedir.py",
    "_jit.py",
    "_kernels.py",
    "_lazy.py",
    "_records.py",
    "automaton.py",
    "contact.py",
    "friction.py",
    "wear.py",
)


def source_key(package: Path = _PACKAGE) -> str:
    """16 hex digits of the sha256 of the package's :data:`KERNEL_SOURCES` (names and
    contents; a file that is missing counts as empty)."""
    digest = hashlib.sha256()
    for name in sorted(KERNEL_SOURCES):
        path = package / name
        digest.update(name.encode())
        digest.update(b"\0")
        digest.update(path.read_bytes() if path.is_file() else b"")
        digest.update(b"\0")
    return digest.hexdigest()[:16]


def _private_temp_root() -> tuple[Path, str | None]:
    """The user's own folder in the system's temporary folder, ``brakeca-<uid>``, made with
    mode 0700, and why it cannot be used (None when it can): it cannot be made, or it is a
    link, is not the user's or lets others write or read it (numba's cache files are
    pickles: loading another user's would run their code)."""
    import stat
    import tempfile

    uid = os.getuid() if hasattr(os, "getuid") else None
    root = Path(tempfile.gettempdir()) / f"brakeca-{uid if uid is not None else 'user'}"
    try:
        root.mkdir(mode=0o700, exist_ok=True)
        info = root.lstat()
    except OSError as exc:
        return root, f"cannot be made ({exc.strerror or exc})"
    if not stat.S_ISDIR(info.st_mode):
        return root, "is not a folder (a link or a file)"
    if uid is not None and info.st_uid != uid:
        return root, f"belongs to user {info.st_uid}, not to you"
    if uid is not None and info.st_mode & 0o077:
        return root, f"is open to others (mode {stat.S_IMODE(info.st_mode):o}, not 700)"
    return root, None


def _usable(folder: Path) -> bool:
    """Whether ``folder`` could be created (with its parents) and written; touches it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if not os.access(folder, os.W_OK):
            return False
        os.utime(folder)  # in use: loading cached kernels writes nothing numba would date
    except OSError:
        return False
    return True


@functools.cache
def cache_folder() -> Path | None:
    """This version's cache folder, created and touched (and the other versions' pruned) on
    the first call of the process: ``$XDG_CACHE_HOME/brakeca/numba/<key>`` (``~/.cache``
    when the variable is unset), else, when that cannot be created or written, the same key
    in the user's private temporary folder (``<tmp>/brakeca-<uid>/numba/<key>``); None when
    neither can."""
    home = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    folder = Path(home) / "brakeca" / "numba" / source_key()
    if not _usable(folder):
        temp, problem = _private_temp_root()
        if problem is not None:
            return None
        folder = temp / "numba" / source_key()
        if not _usable(folder):
            return None
    prune(folder)
    return folder


def kernel_cache_dir() -> str | None:
    """The folder numba caches brakeca's kernels in: ``NUMBA_CACHE_DIR`` when set, else
    :func:`cache_folder`; None for numba's default place beside the sources."""
    given = os.environ.get("NUMBA_CACHE_DIR")
    if given:
        return given
    folder = cache_folder()
    return None if folder is None else str(folder)


def _inside_package(py_file: str) -> bool:
    try:
        return Path(py_file).resolve().is_relative_to(_PACKAGE)
    except (OSError, ValueError):
        return False


@functools.cache  # once per process
def install() -> None:
    """Make numba cache the functions defined in brakeca's files in :func:`cache_folder`
    (unless ``NUMBA_CACHE_DIR`` is set), before they are compiled; every other function's
    cache stays where numba puts it. Safe to call again; call it before decorating."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return  # numba's own locator honours it, for every function
    folder = cache_folder()
    if folder is None:
        if os.access(_PACKAGE, os.W_OK):
            return  # numba's default: __pycache__ beside the sources
        home = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        temp, problem = _private_temp_root()
        raise KernelCacheError(
            "brakeca cannot cache its compiled kernels: its cache folder under "
            f"{home} cannot be written, the private folder {temp} "
            f"{problem or 'cannot be written'}, and its sources ({_PACKAGE}) are read-only. "
            "Set NUMBA_CACHE_DIR to a folder you can write (or XDG_CACHE_HOME) and run again"
        )
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    base = getattr(caching, "UserProvidedCacheLocator", None) or getattr(
        caching, "_UserProvidedCacheLocator", None
    )
    classes = getattr(impl, "_locator_classes", None)
    if base is None or not isinstance(classes, list):  # internals unknown: the whole process
        os.environ["NUMBA_CACHE_DIR"] = str(folder)
        from numba.core import config

        config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]
        return

    class BrakecaCacheLocator(base):  # type: ignore[misc, valid-type]
        """numba's user-provided-folder locator, for brakeca's own files and folder only."""

        def __init__(self, py_func: object, py_file: str) -> None:
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno  # type: ignore[attr-defined]
            subpath = self.get_suitable_cache_subpath(py_file)
            self._cache_path = os.path.join(str(folder), subpath)

        @classmethod
        def from_function(cls, py_func: object, py_file: str) -> BrakecaCacheLocator | None:
            if not _inside_package(py_file):
                return None
            parent: Any = super(base, cls)  # the source-file mixin: its checks
            return parent.from_function(py_func, py_file)

    classes.insert(0, BrakecaCacheLocator)


def _last_used(folder: Path) -> tuple[float, bool]:
    """Newest modification time [s since the epoch] of the folder and the files in it, and
    whether it holds any file."""
    newest = folder.stat().st_mtime
    empty = True
    for path in folder.rglob("*"):
        empty = False
        newest = max(newest, path.stat().st_mtime)
    return newest, empty


def prune(current: Path, now: float | None = None) -> list[Path]:
    """Remove the cache folders of other brakeca versions beside ``current``: empty ones
    untouched for :data:`KEEP_EMPTY`, others untouched for :data:`KEEP_UNUSED` (``now`` [s
    since the epoch], default the clock). Only folders named like a :func:`source_key` are
    considered; anything that cannot be read or removed is left. Returns the removed folders."""
    import shutil
    import time

    now = time.time() if now is None else now
    removed: list[Path] = []
    try:
        siblings = list(current.parent.iterdir())
    except OSError:
        return removed
    for folder in siblings:
        name = folder.name
        if folder == current or len(name) != 16 or any(c not in "0123456789abcdef" for c in name):
            continue
        try:
            if not folder.is_dir() or folder.is_symlink():
                continue
            newest, empty = _last_used(folder)
            if now - newest > (KEEP_EMPTY if empty else KEEP_UNUSED):
                shutil.rmtree(folder)
                removed.append(folder)
        except OSError:
            continue
    return removed
