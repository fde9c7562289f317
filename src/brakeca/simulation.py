"""The orchestrator: one run of the model over a drive cycle. Wiring only, no physics.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from brakeca import _records as R
from brakeca._io import rng_state_json
from brakeca._warmup import announce_if_cold
from brakeca.automaton import Exposure  # noqa: F401 (importable from here, as before)
from brakeca.checkpoint import (
    Checkpoint,
    CheckpointError,
    CheckpointWarning,
    load_checkpoint,
    save_checkpoint,
)
from brakeca.config import MAX_SEED, SimulationConfig
from brakeca.cycle import Stop, cycle_events, map_stops  # noqa: F401 (Stop: as before)
from brakeca.geometry import make_grid
from brakeca.state import SimulationState, StopLog
from brakeca.stop import (  # noqa: F401 (FRICTION_TOLERANCE: importable from here, as before)
    FRICTION_TOLERANCE,
    LedgerError,
    StopSteps,
    _check_friction,
    _field_error,
    _final_ledger,
    advance_stop,
    end_of_stop,
    expose_fibres,
    kernel_for,
    scratch_lists,
)
from brakeca.surface import FibreFieldError, generate_surface

if TYPE_CHECKING:
    from brakeca.results import RunResult

__all__ = [
    "Checkpoint",
    "CheckpointError",
    "CheckpointWarning",
    "LedgerError",
    "SimulationState",
    "StopSteps",
    "advance_stop",
    "end_of_stop",
    "expose_fibres",
    "load_checkpoint",
    "save_checkpoint",
    "simulate",
]

Progress = Callable[[int, int], None]

#: (the name :class:`~brakeca.state.StopLog` had here before the fortieth session)
_StopLog = StopLog


def simulate(
    config: SimulationConfig,
    *,
    seed: int | None = None,
    rng: np.random.Generator | int | None = None,
    progress: Progress | None = None,
    checkpoint: str | Path | None = None,
    checkpoint_every: int = 10,
    keep_checkpoint: bool = False,
    maps_at: Iterable[int] = (),
) -> RunResult:
    """Simulate one pad over the configured drive cycle.

    Parameters
    ----------
    config
        The resolved, validated configuration.
    seed
        Seed of the run's random generator (recorded in the result), a whole number from 0
        to :data:`MAX_SEED` (2**64 - 1, the largest a run file holds). Default 0.
    rng
        A :class:`numpy.random.Generator` to use instead of ``seed`` (a whole number is taken
        as the seed, as SPEC 7 has it); not with ``seed``, nor with ``checkpoint``
        (a checkpoint tells runs apart by their seed). The run then records the seed -1
        and the generator's state before its first draw, as JSON in the run file's
        ``rng_state`` attribute (:meth:`brakeca.results.RunResult.generator` makes a
        generator in that state).
    progress
        Called as ``progress(stops_done, stops_total)`` after every stop.
    checkpoint
        A file to save the run's state to every ``checkpoint_every`` stops (atomically). If it
        exists and belongs to this config and seed, the run resumes from it; the result is
        bit-identical to an uninterrupted run. Removed when the run completes, unless
        ``keep_checkpoint``.
    checkpoint_every
        Stops between checkpoints [-].
    keep_checkpoint
        Leave the checkpoint when the run completes, for the caller to remove once the
        result is safe (written to its file): a process killed in between then still has it.
    maps_at
        Stops (numbered from 1) after which to keep the pad's status and height maps, at the
        stop's end after rule S (the run file's ``map_status`` and ``map_height`` along
        ``map_stop``), to show how the plateaus develop over the cycle. Keeping them changes
        nothing else of the run. Each map costs 5 bytes a cell in memory and in the file
        (1 MB at the paper's full resolution).

    Returns
    -------
    RunResult
        Per-stop responses, MU, V, thinned per-step series, surface maps, provenance; on a
        speed trace also the distance [m] and the PM10 band [mg/km] in the dataset's
        attributes (``distance``, ``pm10_mg_km``, ``pm10_mg_km_low``, ``pm10_mg_km_high``).

    Raises
    ------
    TypeError
        ``config`` is not a :class:`~brakeca.config.SimulationConfig` (a dict, a preset name);
        ``rng`` is not a :class:`numpy.random.Generator` nor a whole number; ``seed`` is a
        generator.
    ValueError
        A seed that is not a whole number in range, or both ``seed`` and ``rng``; a stop of
        ``maps_at`` that the cycle does not have.
    CheckpointError
        A ValueError: the checkpoint is of another run or cannot be read, or it ran a stop
        of ``maps_at`` without keeping its map.
    ContactError
        The demanded torque cannot be reached (names the stop and the step).
    LedgerError
        The volume ledger failed to close (a bug).

    Examples
    --------
    The first three stops of the paper's cycle on the quick band (21 rows, 2 mm), at the
    preset's levels (test 15's) with a pad of seed 2016:

    >>> from brakeca.presets import load_preset
    >>> from brakeca.simulation import simulate
    >>> config = load_preset().with_updates({"mesh.n_radial": 21, "cycle.max_stops": 3})
    >>> result = simulate(config, seed=2016)
    >>> result.dataset.sizes["stop"], result.seed
    (3, 2016)
    >>> 0.15 <= result.MU <= 0.6  # between the friction law's floor and mu_0
    True
    >>> result.scalars()["max_ledger_residual"] < 1e-12  # the volume ledger closes
    True
    >>> again = simulate(config, seed=2016)  # the same seed gives the same run, to the bit
    >>> (again.MU, again.V) == (result.MU, result.V)
    True
    """
    # imported here, not at the top: the run files' module loads xarray and pandas (about
    # 50 MB), which the warm-up child, the process that holds the compiler's memory, does not
    # need (brakeca._warmup)
    from brakeca.results import SUM_FRICTION_RESIDUAL, RunResult, build_dataset, summarise_stop

    if not isinstance(config, SimulationConfig):
        raise TypeError(
            f"config must be a SimulationConfig (e.g. brakeca.presets.load_preset('paper'), "
            f"changed with .with_updates({{'WP': 1e-13}})), not {type(config).__name__}"
        )
    t0 = time.perf_counter()
    if isinstance(rng, int | np.integer) and not isinstance(rng, bool):
        if seed is not None:  # SPEC 7: rng=<int> seeds a new generator, as seed= does
            raise ValueError("give seed or rng, not both (a run records the seed it ran with)")
        if not 0 <= rng <= MAX_SEED:
            raise ValueError(f"rng: a seed is a whole number from 0 to 2**64 - 1, got {rng!r}")
        seed, rng = int(rng), None
    if rng is not None and not isinstance(rng, np.random.Generator):
        raise TypeError(
            f"rng must be a numpy.random.Generator (numpy.random.default_rng(...)) or a "
            f"seed, not {type(rng).__name__}"
        )
    if isinstance(seed, np.random.Generator):
        raise TypeError("seed: got a numpy Generator; pass it as rng=, or a whole number as seed")
    if rng is None:
        seed = 0 if seed is None else seed
        if (
            isinstance(seed, bool)
            or not isinstance(seed, int | np.integer)
            or not 0 <= seed <= MAX_SEED
        ):
            # checked before any work: a seed the run file cannot hold (above 2**64 - 1)
            # failed only when the computed run was written
            raise ValueError(f"seed must be a whole number from 0 to 2**64 - 1, got {seed!r}")
        seed = int(seed)
        rng = np.random.default_rng(seed)
    elif seed is not None:
        raise ValueError("give seed or rng, not both (a run records the seed it ran with)")
    elif checkpoint:
        raise ValueError(
            "checkpoint: a checkpointed run needs a seed, not rng (a checkpoint tells one run "
            "from another by its configuration and seed)"
        )
    else:
        seed = -1
        rng_start = rng_state_json(rng.bit_generator.state)
    if checkpoint_every < 1:
        raise ValueError(f"checkpoint_every must be >= 1, got {checkpoint_every}")
    grid = make_grid(config)
    kernel = kernel_for(config)  # an unsupported numerics.kernel is refused before any work
    announce_if_cold(config)  # a minute's compiling in silence looked hung
    stops = list(cycle_events(config))
    # a trace's distance, for the run file's PM10: taken now, from the events run (the
    # trace file is not read again at the end, where a change to it would lose the run)
    distance = _trace_distance(config)
    kept_maps = map_stops(maps_at, len(stops))
    n_r, n_t = grid.shape
    lists = scratch_lists(n_r * n_t)
    resumed = load_checkpoint(checkpoint, config, seed, grid) if checkpoint else None
    if resumed is None:
        surface = generate_surface(config.pad, grid, rng)
        state = SimulationState.from_surface(surface, grid)
        initial_status = surface.status
        log = StopLog([], [], [], [], [], [])
        elapsed_before = 0.0
    else:
        state, initial_status, log, rng_state, elapsed_before = resumed
        rng.bit_generator.state = rng_state
        missed = [k for k in kept_maps if k <= len(log.dts) and k not in log.maps]
        if missed:
            raise CheckpointError(
                f"maps_at: stop {missed[0]} ran before the checkpoint {checkpoint} without "
                f"keeping its map; ask only for stops after {len(log.dts)}, or delete the "
                "checkpoint to run from the start"
            )
    start = sum(d.size for d in log.dts)  # steps done before the first stop to run
    checkpoint_failed = False  # warned once, not at every checkpoint stop
    before_s = None  # the last stop's statuses before rule S, where it removes plateaus
    for stop in stops[len(log.dts) :]:
        dt, rec, counts = advance_stop(state, grid, config, stop, lists)
        if stop.index == len(stops):
            before_s = state.status.reshape(n_r, n_t).astype(np.int8)
        flush, n_removed = end_of_stop(
            state,
            config.automaton.secondary_removal_fraction,
            rng,
            config.automaton.secondary_removal_rule,
            config.automaton.end_of_stop_streams,
        )
        try:
            exposure = expose_fibres(state, config.pad, grid)
        except FibreFieldError as exc:
            raise _field_error(exc, stop, config, float(rec[:, R.R_DISC].min())) from None
        flush += exposure.released
        summary, kept = summarise_stop(rec, dt, start, config.output.series_every)
        del rec  # not kept: the whole run's records would be 51 MB at full resolution
        _check_friction(summary[SUM_FRICTION_RESIDUAL], stop, config)
        start += dt.size
        log.summaries.append(summary)
        log.kept.append(kept)
        log.dts.append(dt)
        log.flush.append(flush)
        log.s_removed.append(n_removed)
        log.rule_counts.append(counts)
        log.exposures.append(exposure)
        if stop.index in kept_maps:
            log.maps[stop.index] = (
                state.status.reshape(n_r, n_t).astype(np.int8),
                state.height.reshape(n_r, n_t).astype(np.float32),
            )
        if checkpoint and stop.index % checkpoint_every == 0 and stop.index < len(stops):
            try:
                save_checkpoint(
                    checkpoint,
                    config,
                    seed,
                    state,
                    initial_status,
                    log,
                    rng,
                    elapsed_before + time.perf_counter() - t0,
                )
            except OSError as exc:  # the run itself need not fail for it
                if not checkpoint_failed:
                    import warnings

                    warnings.warn(
                        f"checkpoint {checkpoint}: cannot write it after stop {stop.index} "
                        f"({exc.strerror or exc}); the run goes on, trying again at its next "
                        "checkpoint, and an interruption before one is written resumes from "
                        "the last one written (or from the first stop)",
                        CheckpointWarning,
                        stacklevel=2,
                    )
                checkpoint_failed = True
        if progress is not None:
            progress(stop.index, len(stops))
    final_ledger = _final_ledger(state)
    dataset = build_dataset(
        config=config,
        seed=seed,
        grid=grid,
        stops=stops,
        summaries=np.stack(log.summaries),
        kept=np.concatenate(log.kept),
        dts=log.dts,
        flush=log.flush,
        s_removed=log.s_removed,
        rule_counts=log.rule_counts,
        initial_status=initial_status,
        final_status=state.status.reshape(n_r, n_t),
        final_height=state.height.reshape(n_r, n_t),
        final_ledger=final_ledger,
        wall_time=elapsed_before + time.perf_counter() - t0,
        kernel=config.numerics.kernel,
        kernel_stops={kernel: len(log.dts)},  # one kernel runs every stop
        contact_fallbacks=int(state.lazy_walk[6]),
        fibre_exposure=log.exposures if state.fibres is not None else None,
        maps={k: log.maps[k] for k in kept_maps},
        # (a figures review: the final maps of S = 1 runs showed no secondary plateau)
        final_status_before_s=before_s if log.s_removed and log.s_removed[-1] else None,
    )
    if checkpoint and not keep_checkpoint:
        Path(checkpoint).unlink(missing_ok=True)
    result = RunResult(config=config, seed=seed, dataset=dataset)
    if distance is not None:
        _record_pm10(result, distance)
    if seed == -1:
        result.dataset.attrs["rng_state"] = rng_start
        result.dataset.attrs["comment"] += (
            "; seed -1: the run drew from a generator it was given, whose state before the "
            "first draw is rng_state (JSON of numpy's bit_generator.state)"
        )
    return result


def _trace_distance(config: SimulationConfig) -> float | None:
    """The distance [m] a trace cycle's simulated events belong to; None for a block cycle."""
    if not config.cycle.trace_file:
        return None
    from brakeca.traces import configured_cycle

    return float(configured_cycle(config).distance)


def _record_pm10(result: RunResult, distance: float) -> None:
    """Record a trace run's ``distance`` [m] and PM10 in its dataset's attributes, so that
    the run file gives them without its trace (a black-box review: only the console had
    them)."""
    from brakeca.emissions import CAVEAT, pm10_from_run

    estimate = pm10_from_run(result, distance)
    result.dataset.attrs.update(
        {
            "distance": float(distance),
            "pm10_mg_km": float(estimate.central),
            "pm10_mg_km_low": float(estimate.low),
            "pm10_mg_km_high": float(estimate.high),
        }
    )
    result.dataset.attrs["comment"] += (
        "; pm10_mg_km (_low, _high): the vehicle's brake PM10 over that distance [mg/km] "
        "with brakeca.emissions' default factors and their ranges (docs/cycles.md section 5): "
        f"{CAVEAT}"
    )
