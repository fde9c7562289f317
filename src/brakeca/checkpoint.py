"""A run's checkpoint: its complete state between stops, written atomically
(:func:`save_checkpoint`) and read back (:func:`load_checkpoint`) so that a resumed run is
bit-identical to one never interrupted.
"""

from __future__ import annotations

import json
from itertools import pairwise
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from brakeca import _kernels as K
from brakeca._io import (
    CHECKPOINT_FORMAT,
    atomic_write,
    checkpoint_difference,
    checkpoint_is_of,
    checkpoint_problem,
)
from brakeca.automaton import Exposure
from brakeca.config import SimulationConfig
from brakeca.geometry import Grid
from brakeca.state import SimulationState, StopLog
from brakeca.surface import NONE, PRIMARY, SECONDARY, FibreField, Surface

__all__ = [
    "Checkpoint",
    "CheckpointError",
    "CheckpointWarning",
    "load_checkpoint",
    "save_checkpoint",
]


class CheckpointError(ValueError):
    """A checkpoint file that cannot be used: unreadable, of another format, or of another
    run (configuration or seed)."""


class CheckpointWarning(UserWarning):
    """A checkpoint could not be written (a full or read-only disk): the run goes on, and a
    resume starts from the last checkpoint that was written, or from the first stop."""


_STATE_ARRAYS = (
    "height",
    "base",
    "status",
    "fibre_floor",
    "inflow",
    "outflow",
    "acc",
    "pk_h",
    "pk_base",
    "pk_idx",
    "pk_bin",
    "pk_st",
    "heap_keys",
    "heap_vals",
    "cand",
    "ncand",
    "cmax",
    "rule4_list",
    "cnt",
    "lazy_walk",
)
_FIELD_ARRAYS = ("offsets", "top", "bottom", "next")
_LOG_ARRAYS = (
    "summaries",
    "kept",
    "kept_lengths",
    "dts",
    "lengths",
    "flush",
    "s_removed",
    "rule_counts",
    "exposures",
    "map_stops",
    "map_status",
    "map_height",
)
#: the arrays a checkpoint has (:func:`save_checkpoint`); no other is read
_KNOWN = frozenset(
    {"meta", "initial_status", "field_counts"}
    | {f"state_{name}" for name in _STATE_ARRAYS}
    | {f"field_{name}" for name in _FIELD_ARRAYS}
    | {f"log_{name}" for name in _LOG_ARRAYS}
)
#: The most bytes a checkpoint's entry may hold, per cell of the grid [B]: the state's and
#: the fibre field's arrays hold at most 40 bytes a cell (the resin heap's keys and values);
#: a fibre field's intervals, far less than 64 a cell; a per-stop log's maps, 9 bytes a cell
#: and stop; plus a fixed allowance per entry for the step records
_MAX_BYTES_PER_CELL = 4096
_MAX_BYTES_FIXED = 1 << 26


def _check_sizes(data: Any, names: list[str], grid: Grid) -> None:
    """Raise ValueError where an entry of the .npz ``data`` would decompress to more than a
    run of ``grid`` writes (:data:`_MAX_BYTES_PER_CELL`), before it is read."""
    n = grid.shape[0] * grid.shape[1]
    limit = _MAX_BYTES_FIXED + _MAX_BYTES_PER_CELL * n
    for name in names:
        size = data.zip.getinfo(f"{name}.npy").file_size
        if size > limit:
            raise ValueError(f"its {name} holds {size} bytes, more than a run of this grid writes")


def _surface_problem(arrays: dict[str, np.ndarray], grid: Grid) -> str | None:
    """What is wrong with the cells' arrays a checkpoint gives (their sizes and kinds,
    statuses, finite heights), or None."""
    n = grid.shape[0] * grid.shape[1]
    for name, kind in (
        ("state_height", "f"),
        ("state_status", "i"),
        ("state_fibre_floor", "f"),
        ("initial_status", "i"),
    ):
        a = arrays.get(name)
        if a is None or a.size != n or a.dtype.kind != kind:
            return f"{name}: {n} values of kind {kind!r} expected"
    for name in ("state_status", "initial_status"):
        if not np.isin(arrays[name], (NONE, PRIMARY, SECONDARY)).all():
            return f"{name}: a status other than 0, 1 or 2"
    if not np.isfinite(arrays["state_height"]).all():
        return "state_height: a height that is not finite"
    return None


def _state_problem(
    arrays: dict[str, np.ndarray], state: SimulationState, *, field: bool
) -> str | None:
    """What is wrong with a checkpoint's kernel bookkeeping against the fresh ``state`` of
    its grid: an array's shape or type, a count beyond its array, a cell index, stream bin or
    status out of range, a fibre field's arrays missing (``field``: the run's pad has one) or
    there without one, or out of order; or None. The kernels read
    and write through these without bounds checks (a security review: a crafted checkpoint
    crashed the run with a segmentation fault)."""
    for name in _STATE_ARRAYS:
        got, want = arrays.get(f"state_{name}"), state.array(name)
        if got is None or got.shape != want.shape or got.dtype != want.dtype:
            return f"state_{name}: shape {want.shape} of {want.dtype} expected"
    n, bins = state.status.size, state.bin_area.size
    cnt = arrays["state_cnt"]
    plateaus, heap, rule4, secondary = (int(cnt[k]) for k in range(K.N_CNT))
    for what, count, room in (
        ("plateaus", plateaus, n),
        ("resin heap", heap, arrays["state_heap_vals"].size),
        ("rule-4 list", rule4, arrays["state_rule4_list"].size),
        ("secondary plateaus", secondary, n),
    ):
        if not 0 <= count <= room:
            return f"state_cnt: {count} {what} for room for {room}"

    def within(values: np.ndarray, top: int) -> bool:
        return bool(((values >= 0) & (values < top)).all())

    if not (
        within(arrays["state_pk_idx"][:plateaus], n)
        and within(arrays["state_pk_bin"][:plateaus], bins)
        and within(arrays["state_pk_st"][:plateaus], K.DEAD + 1)
        and within(arrays["state_heap_vals"][:heap], n)
        and within(arrays["state_rule4_list"][:rule4], n)
        and within(arrays["state_cand"], 2)
    ):
        return "a cell index, stream bin or status out of range"
    per_bin = np.bincount(state.cell_bin, minlength=bins)
    ncand = arrays["state_ncand"]
    if not ((ncand >= 0) & (ncand <= per_bin)).all():
        return "state_ncand: more candidates than a stream bin has cells"
    names = ["field_counts", *(f"field_{name}" for name in _FIELD_ARRAYS)]
    if any(name in arrays for name in names) != field or not (
        all(name in arrays for name in names) or not field
    ):
        return "the fibre field's arrays " + ("missing" if field else "of a run without one")
    if field:
        if arrays["field_counts"].shape != (3,) or arrays["field_counts"].dtype.kind != "i":
            return "field_counts: three whole numbers expected"
        offsets, nxt = arrays["field_offsets"], arrays["field_next"]
        top, bottom = arrays["field_top"], arrays["field_bottom"]
        if (
            offsets.shape != (n + 1,)
            or nxt.shape != (n,)
            or offsets.dtype.kind != "i"
            or nxt.dtype.kind != "i"
            or top.shape != bottom.shape
            or top.ndim != 1
            or offsets[0] != 0
            or offsets[-1] != top.size
            or (np.diff(offsets) < 0).any()
            or ((nxt < offsets[:-1]) | (nxt > offsets[1:])).any()
        ):
            return "the fibre field's intervals out of order"
    return None


def save_checkpoint(
    path: str | Path,
    config: SimulationConfig,
    seed: int,
    state: SimulationState,
    initial_status: np.ndarray,
    log: StopLog,
    rng: np.random.Generator,
    elapsed: float,
) -> Path:
    """Write the complete state of a run between stops to ``path`` atomically (.npz).

    Everything the next stop reads is saved, the kernel's bookkeeping included (plateau order
    with its tie order, the resin heap), so a resumed run is bit-identical.

    Parameters
    ----------
    path
        The checkpoint file.
    config, seed
        The run's configuration and seed [-] (a resume checks them).
    state
        The :class:`~brakeca.state.SimulationState` after the last stop done.
    initial_status
        The cells' statuses before the first stop [-].
    log
        The per-stop log so far (records, step durations [s], end-of-stop emissions [m^3]).
    rng
        The run's random generator (its state is saved).
    elapsed
        The run's wall time so far [s].

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    lengths = np.array([d.size for d in log.dts], dtype=np.int64)
    map_keys = sorted(log.maps)
    arrays: dict[str, Any] = {f"state_{name}": state.array(name) for name in _STATE_ARRAYS}
    if state.fibres is not None:
        f = state.fibres
        arrays.update({f"field_{name}": getattr(f, name) for name in _FIELD_ARRAYS})
        arrays["field_counts"] = np.array([f.seed, f.slabs, f.n_fibres], dtype=np.int64)
    arrays.update(
        initial_status=initial_status,
        log_summaries=np.stack(log.summaries),
        log_kept=np.concatenate(log.kept),
        log_kept_lengths=np.array([k.shape[0] for k in log.kept], dtype=np.int64),
        log_dts=np.concatenate(log.dts),
        log_lengths=lengths,
        log_flush=np.asarray(log.flush, dtype=np.float64),
        log_s_removed=np.asarray(log.s_removed, dtype=np.int64),
        log_rule_counts=np.stack(log.rule_counts),
        log_exposures=np.array(log.exposures, dtype=np.float64).reshape(-1, len(Exposure._fields)),
        log_map_stops=np.array(map_keys, dtype=np.int64),
        log_map_status=np.array([log.maps[k][0] for k in map_keys], dtype=np.int8).reshape(
            -1, *initial_status.shape
        ),
        log_map_height=np.array([log.maps[k][1] for k in map_keys], dtype=np.float32).reshape(
            -1, *initial_status.shape
        ),
    )
    meta = {
        "format": CHECKPOINT_FORMAT,
        "config": config.to_toml(),
        "seed": int(seed),
        "rng": rng.bit_generator.state,
        "elapsed": float(elapsed),
    }
    arrays["meta"] = np.array(json.dumps(meta))

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:  # a handle: np.savez would append ".npz" to a name
            np.savez(fh, **arrays)

    return atomic_write(path, write)


class Checkpoint(NamedTuple):
    """A run's state between stops, as :func:`load_checkpoint` reads it back (a named
    tuple: it unpacks in this order).

    Attributes
    ----------
    state : SimulationState
        The state after the last stop done.
    initial_status : ndarray
        The cells' statuses before the first stop [-].
    log
        The per-stop log so far.
    rng_state : dict
        The random generator's saved state (``bit_generator.state``).
    elapsed : float
        The run's wall time so far [s].
    """

    state: SimulationState
    initial_status: np.ndarray
    log: StopLog
    rng_state: dict
    elapsed: float


def load_checkpoint(
    path: str | Path, config: SimulationConfig, seed: int, grid: Grid
) -> Checkpoint | None:
    """Read a checkpoint written by :func:`save_checkpoint` for this config and seed.

    Parameters
    ----------
    path
        The checkpoint file.
    config, seed
        The run's configuration and seed [-]: the checkpoint must be of them.
    grid
        The run's :class:`brakeca.geometry.Grid`.

    Returns
    -------
    Checkpoint or None
        The :class:`~brakeca.state.SimulationState`, the statuses before the first stop
        [-], the per-stop log, the random generator's saved state and the run's wall time so
        far [s]; None when there is no file.

    Raises
    ------
    CheckpointError
        (A ``ValueError``.) A checkpoint of another run, or a file that is not a readable
        checkpoint: it is never silently trusted or ignored.
    """
    path = Path(path)
    if not path.exists():
        return None
    problem = checkpoint_problem(path)
    if problem is not None:
        raise CheckpointError(f"{path}: {problem}")
    try:
        with np.load(path, allow_pickle=False) as data:
            # the meta first (checkpoint_problem has bounded its size), then only the arrays
            # a checkpoint has, each no larger than a run of this grid writes it (a security
            # review: a small file of a large entry decompressed to 800 times its size before
            # any check)
            meta = json.loads(str(data["meta"]))
            ours = checkpoint_is_of(meta, config, seed)
            if ours:
                known = [k for k in data.files if k in _KNOWN]
                _check_sizes(data, known, grid)
                arrays = {k: data[k].copy() for k in known}
    except Exception as exc:
        raise CheckpointError(
            f"{path}: unreadable checkpoint ({exc}); delete it to start over"
        ) from None
    if not ours:
        why = checkpoint_difference(meta, config, seed)
        hint = (
            " (a run's number of stops is part of its configuration: a checkpoint of a run "
            "of other stops does not go on as this one)"
            if "cycle.max_stops" in why
            else ""
        )
        raise CheckpointError(
            f"{path}: checkpoint of another run ({why}){hint}; delete it, or give another "
            "checkpoint file, to start this run"
        )
    problem = _surface_problem(arrays, grid)
    if problem is not None:  # (before the kernels rebuild the state from them)
        raise CheckpointError(f"{path}: not a checkpoint of this run's grid ({problem})")
    state = SimulationState.from_surface(
        Surface(
            height=arrays["state_height"].reshape(grid.shape),
            status=arrays["state_status"].reshape(grid.shape),
            fibre_floor=arrays["state_fibre_floor"].reshape(grid.shape),
            n_fibres=0,
        ),
        grid,
    )
    problem = _state_problem(arrays, state, field=config.pad.fibre_model == "field")
    if problem is not None:  # the kernels index with these: never trusted unchecked
        raise CheckpointError(
            f"{path}: not a consistent checkpoint ({problem}); delete it to start over"
        )
    if "field_counts" in arrays:
        seed, slabs, n_fibres = (int(v) for v in arrays["field_counts"])
        parts = {name: arrays[f"field_{name}"] for name in _FIELD_ARRAYS}
        state.fibres = FibreField(**parts, seed=seed, slabs=slabs, n_fibres=n_fibres)
        state.rule7_on = True
    for name in _STATE_ARRAYS:
        state.array(name)[...] = arrays[f"state_{name}"]
    try:  # (a log of other lengths, or without an array, is not this run's)
        bounds = np.concatenate([[0], np.cumsum(arrays["log_lengths"])])
        kept_bounds = np.concatenate([[0], np.cumsum(arrays["log_kept_lengths"])])
        log = StopLog(
            summaries=list(arrays["log_summaries"]),
            kept=[arrays["log_kept"][a:b] for a, b in pairwise(kept_bounds)],
            dts=[arrays["log_dts"][a:b] for a, b in pairwise(bounds)],
            flush=[float(v) for v in arrays["log_flush"]],
            s_removed=[int(v) for v in arrays["log_s_removed"]],
            rule_counts=list(arrays["log_rule_counts"]),
            exposures=[
                Exposure(int(e[0]), float(e[1]), float(e[2]), int(e[3]), float(e[4]))
                for e in arrays["log_exposures"]
            ],
            maps={
                int(k): (arrays["log_map_status"][i], arrays["log_map_height"][i])
                for i, k in enumerate(arrays.get("log_map_stops", ()))
            },
        )
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        raise CheckpointError(
            f"{path}: not a consistent checkpoint (its per-stop log: {exc!r}); delete it "
            "to start over"
        ) from None
    return Checkpoint(state, arrays["initial_status"], log, meta["rng"], float(meta["elapsed"]))
