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
from brakeca.surface import FibreField, Surface

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
            meta = json.loads(str(data["meta"]))
            arrays = {k: data[k].copy() for k in data.files if k != "meta"}
    except Exception as exc:
        raise CheckpointError(
            f"{path}: unreadable checkpoint ({exc}); delete it to start over"
        ) from None
    if not checkpoint_is_of(meta, config, seed):
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
    state = SimulationState.from_surface(
        Surface(
            height=arrays["state_height"].reshape(grid.shape),
            status=arrays["state_status"].reshape(grid.shape),
            fibre_floor=arrays["state_fibre_floor"].reshape(grid.shape),
            n_fibres=0,
        ),
        grid,
    )
    if "field_counts" in arrays:
        seed, slabs, n_fibres = (int(v) for v in arrays["field_counts"])
        parts = {name: arrays[f"field_{name}"] for name in _FIELD_ARRAYS}
        state.fibres = FibreField(**parts, seed=seed, slabs=slabs, n_fibres=n_fibres)
        state.rule7_on = True
    for name in _STATE_ARRAYS:
        state.array(name)[...] = arrays[f"state_{name}"]
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
    return Checkpoint(state, arrays["initial_status"], log, meta["rng"], float(meta["elapsed"]))
