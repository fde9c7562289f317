"""Atomic file writes, shared by every writer of the package (run files, campaign files,
checkpoints, the tables, figures and report)."""

from __future__ import annotations

import os
import secrets
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

__all__ = [
    "atomic_write",
    "linked_output_problem",
    "rng_state_from_json",
    "rng_state_json",
    "write_table",
    "write_text",
]


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
        _replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


#: How often, and how long apart [s], a replacement refused on Windows is tried again
_WINDOWS_RETRIES = (0.05, 0.1, 0.2, 0.4, 0.8)


def _replace(tmp: Path, path: Path, *, windows: bool | None = None) -> None:
    """``os.replace(tmp, path)``; on Windows (``windows``: by default where it runs), which
    refuses to replace a file another program holds open (Excel holding ``summary.csv``, a
    notebook's ``campaign.nc``; briefly an antivirus or the search indexer), tried again over
    about 1.5 s, then refused with the likely cause named (a portability review)."""
    if windows is None:
        windows = sys.platform == "win32"
    for pause in _WINDOWS_RETRIES if windows else ():
        try:
            os.replace(tmp, path)
            return
        except PermissionError:
            time.sleep(pause)
    try:
        os.replace(tmp, path)
    except PermissionError as exc:
        if not windows:
            raise
        raise PermissionError(
            exc.errno,
            f"{exc.strerror}: is {path.name} open in another program (a spreadsheet, a "
            "notebook)? If so, close it and run the command again",
            str(path),
        ) from exc


def linked_output_problem(folder: str | Path) -> str | None:
    """Why an analysis must not write into ``folder``: its ``tables`` or ``figures`` is a
    link (a folder someone sent, with a link to another place, where the analysis would
    write its tables and figures and remove the earlier ones of the same names: a security
    review); None where neither is one. Worded to follow ``PATH: ``."""
    for name in ("tables", "figures"):
        part = Path(folder) / name
        if part.is_symlink():
            return (
                f"its {name} is a link (to {part.readlink()}), where the analysis would write "
                f"and remove files; replace the link with a folder of its own"
            )
    return None


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` as UTF-8 with ``\\n`` line ends, atomically
    (:func:`atomic_write`)."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8", newline="\n"))


#: Compression pandas infers from a file's suffix, which the temporary name of
#: :func:`write_table` does not carry.
_COMPRESSION = {".gz": "gzip", ".bz2": "bz2", ".zip": "zip", ".xz": "xz", ".zst": "zstd"}


def write_table(table: Any, path: str | Path) -> Path:
    """Write a pandas DataFrame ``table`` to ``path`` as CSV without its index, atomically
    (:func:`atomic_write`): an analysis stopped halfway leaves each table whole, the old one
    or the new one, never a truncated file. Compressed by the suffix as pandas does it
    (``.csv.gz``: gzip)."""
    compression = _COMPRESSION.get(Path(path).suffix.lower())
    return atomic_write(path, lambda tmp: table.to_csv(tmp, index=False, compression=compression))


def rng_state_json(state: Mapping[str, Any]) -> str:
    """A numpy bit generator's ``state`` as JSON text; the arrays some generators keep
    (MT19937's key, Philox's counter, SFC64's state) as ``{"ndarray": [...], "dtype": ...}``
    (:func:`rng_state_from_json` reads it back)."""
    import json

    import numpy as np

    def encode(value: Any) -> Any:
        if isinstance(value, np.ndarray):
            return {"ndarray": value.tolist(), "dtype": str(value.dtype)}
        if isinstance(value, np.integer):
            return int(value)
        raise TypeError(f"not JSON: {type(value).__name__}")

    return json.dumps(state, default=encode)


def rng_state_from_json(text: str) -> dict[str, Any]:
    """The bit generator state :func:`rng_state_json` wrote, its arrays numpy arrays again."""
    import json

    import numpy as np

    def decode(obj: dict[str, Any]) -> Any:
        if set(obj) == {"ndarray", "dtype"}:
            return np.array(obj["ndarray"], dtype=obj["dtype"])
        return obj

    return dict(json.loads(text, object_hook=decode))


#: Format tag of a run's checkpoint (:func:`brakeca.checkpoint.save_checkpoint`), here so
#: that a campaign can read a checkpoint's tag without importing the kernels, and the
#: simulation without importing the run files' modules (xarray).
CHECKPOINT_FORMAT = "brakeca-checkpoint/8"


def checkpoint_is_of(meta: dict[str, Any], config: Any, seed: int) -> bool:
    """Whether a checkpoint's ``meta`` entry names this format, ``config`` and ``seed``. A
    checkpoint written by a version whose configuration lacked a field added since (at the
    value :data:`brakeca.config.ID_NEUTRAL` gives it) is of the same run, as its run id is."""
    if meta.get("format") != CHECKPOINT_FORMAT or meta.get("seed") != seed:
        return False
    text = meta.get("config")
    if text == config.to_toml():
        return True
    try:
        return bool(type(config).from_toml(str(text)).identity_toml() == config.identity_toml())
    except ValueError:  # not a configuration this version reads (ConfigError)
        return False


def flat_keys(data: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """A nested mapping as ``{"dotted.key": value}`` (a configuration's fields by name)."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        if isinstance(value, Mapping):
            out.update(flat_keys(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def config_changes(before: Mapping[str, Any], after: Mapping[str, Any]) -> list[str]:
    """How the configuration ``after`` differs from ``before`` (both as ``to_dict`` gives
    them): one ``"key: old -> new"`` per differing field, in ``before``'s order and then
    ``after``'s new fields, a field one of them lacks shown as ``unset``; of two lists of
    one length the first item that differs (``cycle.blocks[4]: {...} -> {...}``), else a long
    list by its first item and its length."""
    old, new = flat_keys(before), flat_keys(after)

    def shown(table: dict[str, Any], key: str) -> str:
        if key not in table:
            return "unset"
        value = table[key]
        if isinstance(value, list | tuple) and len(value) > 2 and len(repr(value)) > 80:
            # a block cycle's nine blocks on one line (a review): their number and the first
            return f"[{value[0]!r}, ... ({len(value)} items)]"
        return repr(value)

    def change(key: str) -> str:
        a, b = old.get(key), new.get(key)
        if isinstance(a, list | tuple) and isinstance(b, list | tuple) and len(a) == len(b):
            # the same length: the items that differ, not two shortened lists that may read
            # alike (a diff review)
            at = [i for i, (x, y) in enumerate(zip(a, b, strict=True)) if x != y]
            more = f" (and {len(at) - 1} more item(s))" if len(at) > 1 else ""
            return f"{key}[{at[0]}]: {a[at[0]]!r} -> {b[at[0]]!r}{more}"
        return f"{key}: {shown(old, key)} -> {shown(new, key)}"

    keys = list(old) + [k for k in new if k not in old]
    return [change(k) for k in keys if old.get(k) != new.get(k)]


def checkpoint_difference(meta: dict[str, Any], config: Any, seed: int) -> str:
    """What differs between a checkpoint's ``meta`` and this run (for a checkpoint that is
    not :func:`checkpoint_is_of` it): its format, its seed, or the first configuration fields
    that differ (``"cycle.max_stops: 2 -> 3"``); a single-run review was told only "config,
    seed or format differ"."""
    if meta.get("format") != CHECKPOINT_FORMAT:
        return f"its format is {meta.get('format')!r}, this version's {CHECKPOINT_FORMAT!r}"
    if meta.get("seed") != seed:
        return f"its seed is {meta.get('seed')}, this run's {seed}"
    try:
        theirs = type(config).from_toml(str(meta.get("config"))).to_dict()
    except ValueError:  # not a configuration this version reads
        return "its configuration is not one this version reads"

    changed = config_changes(theirs, config.to_dict())
    if not changed:
        return "its configuration differs"
    more = f"; and {len(changed) - 3} more" if len(changed) > 3 else ""
    return "its configuration differs: " + "; ".join(changed[:3]) + more


def _checkpoint_meta(path: Path) -> Any:
    """A checkpoint's small ``meta`` entry (JSON), read without its arrays; raises on a file
    that has none."""
    import json

    import numpy as np

    with np.load(path, allow_pickle=False) as data:
        if data.zip.getinfo("meta.npy").file_size > _MAX_META_BYTES:  # (never decompressed)
            raise ValueError("a meta entry larger than a checkpoint's")
        return json.loads(str(data["meta"]))


#: The most bytes a checkpoint's ``meta`` (its configuration and generator state, a few kB)
#: may decompress to [B]
_MAX_META_BYTES = 1 << 24


def checkpoint_problem(path: str | Path) -> str | None:
    """Why the existing file ``path`` is not a brakeca checkpoint, with what to do, or None
    when it is one (an ``.npz`` archive with brakeca's ``meta`` entry; of which run, not
    asked) or there is no file. Only the archive's directory and its ``meta`` are read; the
    command line and :func:`brakeca.checkpoint.load_checkpoint` both ask it."""
    import zipfile

    path = Path(path)
    if not path.exists():
        return None
    try:
        with path.open("rb") as f:
            head = f.read(8)
    except OSError as exc:
        return f"cannot read it ({exc.strerror or exc})"
    if head.startswith(b"\x89HDF"):
        problem = "a netCDF/HDF5 file (a run file?), not a brakeca checkpoint"
    elif not zipfile.is_zipfile(path):
        problem = "not a brakeca checkpoint (not an .npz archive; a damaged one, or another file)"
    else:
        try:
            meta = _checkpoint_meta(path)
        except Exception:
            problem = "an .npz archive without a readable brakeca checkpoint entry (meta)"
        else:
            if isinstance(meta, dict) and str(meta.get("format", "")).startswith(
                "brakeca-checkpoint/"
            ):
                return None
            problem = "an .npz archive that is not a brakeca checkpoint"
    return (
        f"{problem}; give the checkpoint another path (if it is a damaged checkpoint of this "
        "run, delete it to start over)"
    )


def checkpoint_resumes(path: Path, config: Any, seed: int, maps_at: Sequence[int] = ()) -> bool:
    """Whether the checkpoint at ``path`` is one the run of ``config`` and ``seed`` would
    resume from (:func:`checkpoint_is_of`; only its small ``meta`` entry is read, and with
    ``maps_at`` the stops it ran and kept maps of). False for a missing, unreadable or
    foreign file, and for one that ran a stop of ``maps_at`` without keeping its map (a
    campaign's worker discards those and starts the run over; :func:`brakeca.simulation.simulate`
    refuses the last with a :class:`~brakeca.checkpoint.CheckpointError`)."""
    try:
        meta = _checkpoint_meta(path)
        if not checkpoint_is_of(meta, config, seed):
            return False
        if not maps_at:
            return True
        import numpy as np

        with np.load(path, allow_pickle=False) as data:
            done = int(data["log_lengths"].size)
            kept = {int(k) for k in data["log_map_stops"]}
        return all(k in kept or k > done for k in maps_at)
    except Exception:
        return False
