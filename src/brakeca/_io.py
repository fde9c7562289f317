"""Atomic file writes, shared by every writer of the package (run files, campaign files,
checkpoints, the report)."""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["atomic_write"]


def atomic_write(path: str | Path, write: Callable[[Path], Any]) -> Path:
    """Call ``write(tmp)`` on a temporary name beside ``path``, then rename it to ``path``.

    The temporary name is ``.<name>.<pid>.<random>.tmp`` (created by ``write``, so it gets the
    usual permissions); :func:`os.replace` makes the final name appear complete or not at all.
    A failed write leaves no temporary file behind.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


#: Format tag of a run's checkpoint (:func:`brakeca.simulation.save_checkpoint`), here so
#: that a campaign can read a checkpoint's tag without importing the kernels, and the
#: simulation without importing the run files' modules (xarray).
CHECKPOINT_FORMAT = "brakeca-checkpoint/7"


def checkpoint_is_of(meta: dict[str, Any], config: Any, seed: int) -> bool:
    """Whether a checkpoint's ``meta`` entry names this format, ``config`` and ``seed``."""
    return bool(
        meta.get("format") == CHECKPOINT_FORMAT
        and meta.get("config") == config.to_toml()
        and meta.get("seed") == seed
    )


def checkpoint_resumes(path: Path, config: Any, seed: int) -> bool:
    """Whether the checkpoint at ``path`` is one the run of ``config`` and ``seed`` would
    resume from (:func:`checkpoint_is_of`; only its small ``meta`` entry is read). False for
    a missing, unreadable or foreign file, which the run discards."""
    import json

    import numpy as np

    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
    except Exception:
        return False
    return checkpoint_is_of(meta, config, seed)
