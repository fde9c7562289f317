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
Folders of other versions are not removed (a few MB each). numba has one cache folder per
process, so other cached numba functions of a process that imports brakeca are cached there
too; set ``NUMBA_CACHE_DIR`` to choose another.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

__all__ = ["configure", "source_key"]

_PACKAGE = Path(__file__).resolve().parent


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
    except OSError:
        return None
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    config = sys.modules.get("numba.core.config")
    if config is not None:  # numba read the environment already: tell it too
        config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]
    return str(folder)
