"""Where numba caches brakeca's compiled kernels: a folder per version of the sources.

numba decides whether a cached kernel is still valid from the kernel's own source file only,
not from the files of the helpers compiled into it (numba issue/PR 8396, not merged). After an
update that changes only a helper, a shared cache would serve a kernel with the old helper
inside, and results would silently be those of the old code. So, unless ``NUMBA_CACHE_DIR`` is
already set (``scripts/paper`` and ``scripts/test`` set their own, keyed the same way), brakeca
points numba's cache at ``$XDG_CACHE_HOME/brakeca/numba/<key>`` (``~/.cache`` when
``XDG_CACHE_HOME`` is unset), where ``<key>`` is a hash of every ``.py`` file of the package.
The variable is exported, so worker and warm-up processes use the same folder. If that folder
cannot be created, numba's default (``__pycache__`` beside the sources) is left in place.
Each import touches its version's folder; the folders of other versions are removed once
unused: an empty one after a day, any other after 30 days (:func:`prune`; a version used
again later just compiles once more). numba has one cache folder per process, so other cached
numba functions of a process that imports brakeca are cached there too; set
``NUMBA_CACHE_DIR`` to choose another.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

__all__ = ["configure", "prune", "source_key"]

_PACKAGE = Path(__file__).resolve().parent

#: [s] another version's cache folder is removed after this long untouched
KEEP_UNUSED = 30 * 86400.0
#: [s] another version's empty cache folder (a version imported, nothing compiled) is removed
#: after this long: not at once, since a process of that version may be just starting
KEEP_EMPTY = 86400.0


def source_key(package: Path = _PACKAGE) -> str:
    """16 hex digits of the sha256 of the package's ``.py`` files (names and contents)."""
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        digest.update(path.relative_to(package).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()[:16]


def configure() -> str | None:
    """Set ``NUMBA_CACHE_DIR`` (and numba's config, if numba is loaded) to this version's
    folder unless it is set already; returns the folder in use, or None for numba's default."""
    given = os.environ.get("NUMBA_CACHE_DIR")
    if given:
        return given
    root = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    folder = Path(root) / "brakeca" / "numba" / source_key()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if not os.access(folder, os.W_OK):
            return None
        os.utime(folder)  # in use: loading cached kernels writes nothing numba would date
    except OSError:
        return None
    prune(folder)
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    config = sys.modules.get("numba.core.config")
    if config is not None:  # numba read the environment already: tell it too
        config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]
    return str(folder)


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
