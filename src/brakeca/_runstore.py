"""Run files of a campaign: the record kept of each run, and writing and checking run files.

This module holds :class:`_Record`, the atomic file helpers, the checks that decide whether a
run file (or a worker's result) belongs to its run, and the conversion of a finished future
into a record (writing its run file). Only the campaign process calls it.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import socket
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from brakeca import __version__
from brakeca._io import config_changes, write_text
from brakeca.design import Design, RunPoint, run_id

if TYPE_CHECKING:
    from brakeca.config import SimulationConfig
    from brakeca.results import RunResult

try:  # POSIX advisory locks; without them (Windows) campaigns are not locked
    import fcntl
except ImportError:  # pragma: no cover - not on the supported platforms
    fcntl = None  # type: ignore[assignment]

#: Name of the lock file of a campaign directory.
LOCK_NAME = ".brakeca.lock"

#: Dimensions of a run file that are not per-stop (left out of campaign.nc).
_NON_STOP_DIMS = frozenset({"step", "radius", "angle"})


# --- one campaign at a time in a directory ---------------------------------------------------


class CampaignLockedError(RuntimeError):
    """Another campaign is writing the same campaign directory."""


@contextmanager
def campaign_lock(out: Path) -> Iterator[None]:
    """Hold an exclusive lock on the campaign directory ``out`` while a campaign writes it.

    The lock is an advisory ``fcntl.flock`` on ``out/.brakeca.lock``, which also names the
    holder, and when the campaign ends, that it is not held. The operating system releases
    it when the process ends, however it ends, so a killed campaign never leaves a stale lock
    (its file still names it); the file itself stays (removing it would race with a campaign
    starting at that moment).

    On a file system that does not support ``flock`` (some network mounts) the campaign runs
    unlocked, as it did before locks existed.

    Raises
    ------
    CampaignLockedError
        Another process holds the lock (on this machine, or on another machine that shares the
        folder, where the file system supports ``flock``).
    """
    if fcntl is None:  # pragma: no cover
        yield
        return
    out.mkdir(parents=True, exist_ok=True)
    with open(out / LOCK_NAME, "a+", encoding="utf-8") as fh:
        locked = False
        for attempt in range(6):  # lock_holder (brakeca analyze) holds it for an instant
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
                locked = True
                break
            except BlockingIOError:
                if attempt < 5:
                    time.sleep(0.05)
                    continue
                fh.seek(0)
                holder = fh.read().strip() or "another process"
                raise CampaignLockedError(
                    f"{out}: another campaign is writing this folder ({holder}); wait for it "
                    "to finish, or write to another output folder"
                ) from None
            except OSError:  # a file system without flock (some network mounts): unlocked
                break
        if not locked:
            yield
            return
        fh.seek(0)
        fh.truncate()
        stamp = time.strftime("%Y-%m-%d %H:%M:%S")
        holder = f"pid {os.getpid()} on {socket.gethostname()}"
        fh.write(f"{holder}, since {stamp}\n")
        fh.flush()
        try:
            yield
        finally:
            # the file stays: it says, while still held, that it is free now (it had kept
            # naming the finished campaign as if it were running: a user's review)
            try:
                fh.seek(0)
                fh.truncate()
                ended = time.strftime("%Y-%m-%d %H:%M:%S")
                fh.write(f"not held; last held by {holder}, from {stamp} to {ended}\n")
                fh.flush()
            except OSError:  # a full disk: the lock is released all the same
                pass
            fcntl.flock(fh, fcntl.LOCK_UN)


def lock_holder(out: Path) -> str | None:
    """Who holds the campaign lock of ``out`` (``"pid 123 on host, since ..."``), or None
    when no campaign is writing the folder (or it has no lock file, or the file system has
    no ``flock``). Takes the lock shared for an instant, so it never blocks."""
    path = out / LOCK_NAME
    if fcntl is None or not path.is_file():  # pragma: no cover
        return None
    try:
        with open(path, encoding="utf-8") as fh:
            try:
                fcntl.flock(fh, fcntl.LOCK_SH | fcntl.LOCK_NB)
            except BlockingIOError:
                return fh.read().strip() or "another process"
            except OSError:
                return None
            fcntl.flock(fh, fcntl.LOCK_UN)
    except OSError:
        return None
    return None


# --- records and results -------------------------------------------------------------------


@dataclass(frozen=True)
class _Record:
    """What the campaign keeps of one run: status, scalars and the per-stop variables."""

    point: RunPoint
    run_id: str
    status: str  # "ok" or "failed"
    error: str = ""
    scalars: dict[str, float] = field(default_factory=dict)
    per_stop: xr.Dataset | None = None
    source_key: str | None = None  # the kernels' sources that made it (its run file's)


# --- file helpers --------------------------------------------------------------------------


def _remove_stale_temporaries(folder: Path) -> list[Path]:
    """Delete ``.<name>.<random>.tmp`` files left by a killed campaign in ``folder``."""
    removed = []
    for tmp in folder.glob(".*.tmp"):
        if tmp.is_file():
            tmp.unlink(missing_ok=True)
            removed.append(tmp)
    return removed


def _per_stop(dataset: xr.Dataset) -> xr.Dataset:
    """The variables of a run dataset that are indexed by stop (and no map or step dim)."""
    names = [
        name
        for name, var in dataset.data_vars.items()
        if "stop" in var.dims and not _NON_STOP_DIMS.intersection(var.dims)
    ]
    out = dataset[names]
    return out.drop_vars([c for c in out.coords if _NON_STOP_DIMS.intersection(out[c].dims)])


def _record_from_result(point: RunPoint, rid: str, result: RunResult) -> _Record:
    scalars = {k: _number(v) for k, v in result.scalars().items()}
    key = result.dataset.attrs.get("source_key")
    return _Record(
        point,
        rid,
        "ok",
        "",
        scalars,
        _per_stop(result.dataset).load(),
        str(key) if key is not None else None,
    )


def _number(value: Any) -> float | int:
    if isinstance(value, bool | np.bool_):
        return int(value)
    if isinstance(value, int | np.integer):
        return int(value)
    return float(value)


def _check_result(result: Any, point: RunPoint) -> str | None:
    """Why ``result`` is not the result of ``point`` (None when it is)."""
    from brakeca.results import RunResult

    if not isinstance(result, RunResult):
        return f"the simulation returned {type(result).__name__}, not a RunResult"
    if int(result.seed) != point.seed:
        return f"the result has seed {result.seed}, the run {point.seed}"
    if result.config != point.config:
        return "the result's configuration differs from the run's"
    return None


def _load_existing(path: Path, point: RunPoint) -> tuple[RunResult | None, str]:
    """Load a run file for reuse: (result, "") or (None, why it cannot be trusted)."""
    from brakeca.results import RunResult

    try:
        result = RunResult.from_netcdf(path)
    except Exception as exc:
        return None, f"cannot be read ({type(exc).__name__}: {exc})"
    problem = _check_result(result, point)
    if problem is not None:
        return None, f"belongs to another run ({problem})"
    return result, ""


# --- finished runs -------------------------------------------------------------------------


#: The error of a run cancelled outside the campaign (the campaign cancels only runs it stops
#: waiting for, and a run dask cancels when its link to the scheduler drops goes back to the
#: queue): on a shared cluster, another client, the dashboard or the scheduler's own restart.
CANCELLED = (
    "the run was cancelled on the executor, not by this campaign (on a dask cluster: another "
    "client, the dashboard or a restart of the scheduler); running the campaign again runs it"
)


def _finish(future: cf.Future, point: RunPoint, runs: Path) -> _Record:
    """Turn a finished future into a record, writing the run file when it succeeded."""
    rid = run_id(point)
    if future.cancelled():
        return _Record(point, rid, "failed", CANCELLED)
    try:
        result = future.result()
    except Exception as exc:
        return _Record(point, rid, "failed", _error_text(exc))
    problem = _check_result(result, point)
    if problem is not None:
        return _Record(point, rid, "failed", problem)
    try:
        result.to_netcdf(runs / f"{rid}.nc")  # atomic
    except Exception as exc:
        return _Record(point, rid, "failed", f"cannot write the run file: {_error_text(exc)}")
    return _record_from_result(point, rid, result)


def _error_text(exc: BaseException) -> str:
    """One line (for the CSV) naming the exception; a dask KilledWorker said plainly."""
    if type(exc).__name__ == "KilledWorker":
        tries = getattr(exc, "allowed_failures", None)
        worker = getattr(getattr(exc, "last_worker", None), "address", "?")
        if tries is not None and int(tries) == 0:  # as the campaign says of such a death
            text = (
                "KilledWorker: the worker process died while running it (last worker "
                f"{worker}); not tried again (no retries allowed)"
            )
        else:
            times = "repeatedly" if tries is None else f"{int(tries) + 1} times"
            text = (
                f"KilledWorker: the worker process died {times} while running it (dask "
                f"retried it on other workers; last worker {worker}); not retried again"
            )
    else:
        text = f"{type(exc).__name__}: {exc}".strip()
    return " ".join(text.split())  # one line, for the CSV


def existing_base(out: Path) -> SimulationConfig | None:
    """The base configuration of the campaign already in ``out`` (its base_config.toml);
    None when the folder holds no campaign or a base this version cannot read."""
    from brakeca.config import ConfigError, load_config

    path = out / "base_config.toml"
    if not path.is_file():
        return None
    try:
        return load_config(path)
    except (ConfigError, OSError):
        return None


def base_differences(old: SimulationConfig | None, base: SimulationConfig) -> list[str]:
    """How a campaign's base configuration ``old`` (:func:`existing_base`) differs from
    ``base``: one ``"key: old -> new"`` per differing field, in the order of the
    configuration; empty when there is none or it is the same."""
    if old is None or old == base:
        return []
    return config_changes(old.to_dict(), base.to_dict())


def moved_trace(old: SimulationConfig | None, base: SimulationConfig) -> str | None:
    """The trace path of a campaign's base ``old`` (:func:`existing_base`) when ``base``
    names the same trace content (the same ``cycle.trace_sha256``) at another path, else
    None: a run's id and a campaign's base keep the trace's path, so a moved trace makes
    other runs."""
    if old is None:
        return None
    was, new = old.cycle, base.cycle
    if (
        was.trace_file
        and new.trace_file
        and was.trace_file != new.trace_file
        and was.trace_sha256 is not None
        and was.trace_sha256 == new.trace_sha256
    ):
        return str(was.trace_file)
    return None


def edited_trace(old: SimulationConfig | None, base: SimulationConfig) -> str | None:
    """The trace path where a campaign's base ``old`` and ``base`` name the same trace file
    whose content (``cycle.trace_sha256``) has changed since, else None."""
    if old is None:
        return None
    was, new = old.cycle, base.cycle
    if (
        was.trace_file
        and was.trace_file == new.trace_file
        and was.trace_sha256 is not None
        and was.trace_sha256 != new.trace_sha256
    ):
        return str(was.trace_file)
    return None


#: How a campaign's own design.toml and base_config.toml begin (:func:`_write_design`), by
#: which a campaign tells them from a user's files (``campaign._foreign_design``).
DESIGN_HEADER = "# Design of campaign"
BASE_HEADER = "# Resolved base configuration of campaign"


def design_text(design: Design) -> str:
    """The text of a campaign's design.toml for ``design`` (its base is base_config.toml)."""
    return (
        f"{DESIGN_HEADER} {design.name!r} (base: base_config.toml beside this file).\n"
        + design.to_toml(base_config="base_config.toml")
    )


def design_changes(out: Path, design: Design) -> str:
    """How ``design`` differs from the design.toml a campaign left in ``out``, e.g.
    ``"A's levels [10, 20] -> [10, 25]"`` or ``"replicates 2 -> 3"`` (a cluster review: a
    level changed between a campaign's kill and its resume replaced design.toml without a
    word); empty where there is none, or nothing it can read."""
    import tomllib

    path = out / "design.toml"
    try:
        old_text = path.read_text(encoding="utf-8")
        new_text = design_text(design)
        if old_text == new_text:
            return ""
        return _table_changes(tomllib.loads(old_text), tomllib.loads(new_text))
    except (OSError, ValueError, TypeError, AttributeError):  # nothing it can read
        return ""


def _table_changes(old: dict[str, Any], new: dict[str, Any]) -> str:
    """:func:`design_changes` of two designs' tables (``factors`` compared factor by factor,
    by name); empty where they hold the same values."""

    def shown(table: dict[str, Any], key: str) -> str:
        value = table.get(key, "(unset)")
        if key == "runs" and isinstance(value, list):  # a run table by its size (a diff
            # review: two composite designs' tables had made a refusal of 1,700 characters)
            return f"{len(value)} test{'' if len(value) == 1 else 's'}"
        return repr(value) if isinstance(value, str) and key in table else str(value)

    said = []
    for key in sorted((set(old) | set(new)) - {"factors"}):
        if old.get(key) != new.get(key):
            change = f"{shown(old, key)} -> {shown(new, key)}"
            said.append(f"{key} {change}" if key != "runs" else f"the run table's {change}")
    old_factors = {f.get("name"): f for f in old.get("factors", [])}
    new_factors = {f.get("name"): f for f in new.get("factors", [])}
    for name, factor in new_factors.items():
        was = old_factors.get(name)
        if was is None:
            said.append(f"factor {name} added")
            continue
        for key in sorted((set(was) | set(factor)) - {"name"}):
            if was.get(key) != factor.get(key):
                said.append(f"{name}'s {key} {shown(was, key)} -> {shown(factor, key)}")
    said += [f"factor {name} removed" for name in old_factors if name not in new_factors]
    kept_old = [name for name in old_factors if name in new_factors]
    kept_new = [name for name in new_factors if name in old_factors]
    if kept_old != kept_new:  # (a growth review: factors reordered were not said)
        said.append(f"the factors' order {', '.join(kept_old)} -> {', '.join(kept_new)}")
    return "; ".join(said)


def _kept_base_header(path: Path, base: SimulationConfig) -> str | None:
    """The header of the folder's ``base_config.toml`` where the file holds ``base`` already
    (a campaign run again from the folder, with or without the first one's options): it says
    where the base came from (a provenance review: it had become "From '<this file>';
    overrides {}", the first campaign's --set and --stops lost); None otherwise."""
    if existing_base(path.parent) != base:
        return None
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    if not text.startswith(BASE_HEADER):
        return None
    lines = text.splitlines(keepends=True)
    return "".join(lines[: next(i for i, line in enumerate(lines) if not line.startswith("#"))])


def _write_design(
    out: Path,
    design: Design,
    base: SimulationConfig,
    *,
    overrides: Mapping[str, Any] | None,
    quick: bool,
    max_stops: int | None,
) -> Design:
    """Write base_config.toml and design.toml; return the design they describe. A campaign
    writes them at its start into a new folder, and with its summary, after its runs, into
    one that holds a study (a campaign stopped or failed before its summary leaves that
    study's files)."""
    origin = f"preset {design.base!r}" if design.base is not None else repr(str(design.base_config))
    header = (
        f"{BASE_HEADER} {design.name!r}, written by brakeca "
        f"{__version__}.\n# From {origin}; overrides {dict(overrides or {})!r}, "
        f"max_stops {max_stops!r}, quick {quick!r}.\n"
    )
    path = out / "base_config.toml"
    kept = _kept_base_header(path, base)
    write_text(path, (kept or header) + base.to_toml())
    write_text(out / "design.toml", design_text(design))
    return design.model_copy(
        update={"base": None, "base_config": (out / "base_config.toml").resolve()}
    )
