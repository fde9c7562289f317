"""The orchestrator: one run of the model over a drive cycle. Wiring only, no physics.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

import numpy as np

from brakeca import _kernels as K
from brakeca import _lazy
from brakeca import _records as R
from brakeca._io import (
    CHECKPOINT_FORMAT,
    atomic_write,
    checkpoint_difference,
    checkpoint_is_of,
    checkpoint_problem,
)
from brakeca.automaton import Exposure, expose_buried_fibres, pad_surface
from brakeca.config import MAX_SEED, PadConfig, SimulationConfig
from brakeca.contact import ContactError
from brakeca.cycle import (
    Stop,
    brake_demand,
    cycle_events,
    map_stops,
    step_distance,
)
from brakeca.friction import friction_stress_peak
from brakeca.geometry import Grid, make_grid
from brakeca.surface import (
    NONE,
    PRIMARY,
    SECONDARY,
    FibreField,
    FibreFieldError,
    Surface,
    deepen_fibre_field,
    generate_surface,
)

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


class CheckpointError(ValueError):
    """A checkpoint file that cannot be used: unreadable, of another format, or of another
    run (configuration or seed)."""


class CheckpointWarning(UserWarning):
    """A checkpoint could not be written (a full or read-only disk): the run goes on, and a
    resume starts from the last checkpoint that was written, or from the first stop."""


class LedgerError(RuntimeError):
    """The volume ledger stopped closing: a bug, never a physical outcome."""


@dataclass
class SimulationState:
    """The mutable state of a run between stops (flat arrays, index ``j * n_angular + i``).

    Attributes
    ----------
    height : float64 array
        Cell heights [m].
    base : float64 array
        Height under the deposit of secondary cells [m].
    status : int8 array
        NONE / PRIMARY / SECONDARY.
    fibre_floor : float64 array
        Fibre underside [m] (-inf for columns).
    inflow, outflow : float64 arrays (n_radial * n_subdomains)
        Particle streams per bin ``j * n_sub + k`` [m^3].
    acc : float64 array
        Accumulators: removed, emitted, held [m^3]; primary and secondary area [m^2].
    cell_area : float64 array
        Each cell's area, its row's ``A_j = r_j dtheta dr`` [m^2].
    cell_slide : float64 array
        Each cell's sliding distance in a full step, its row's ``r_j N_m dtheta`` [m].
    cell_bin : int64 array
        Each cell's stream bin ``j * n_sub + k`` [-].
    fibres : FibreField or None
        The fibre field (``pad.fibre_model = "field"`` only); its ``next`` changes in place,
        and it is replaced when it is laid deeper.

    The other arrays are derived bookkeeping of the kernel (sorted plateaus, resin heap,
    creation candidates, rule-4 list), rebuilt by :meth:`resync`.
    """

    height: np.ndarray
    base: np.ndarray
    status: np.ndarray
    fibre_floor: np.ndarray
    inflow: np.ndarray
    outflow: np.ndarray
    acc: np.ndarray
    cell_area: np.ndarray
    cell_slide: np.ndarray
    cell_bin: np.ndarray
    n_radial: int
    n_angular: int
    n_subdomains: int
    fibres: FibreField | None = None
    exposed: np.ndarray = field(init=False)
    pk: tuple = field(init=False)
    gone: tuple = field(init=False)
    bin_area: np.ndarray = field(init=False)
    bin_slide: np.ndarray = field(init=False)
    rule7_on: bool = field(init=False)
    heap_keys: np.ndarray = field(init=False)
    heap_vals: np.ndarray = field(init=False)
    cand: np.ndarray = field(init=False)
    ncand: np.ndarray = field(init=False)
    cmax: np.ndarray = field(init=False)
    rule4_list: np.ndarray = field(init=False)
    cnt: np.ndarray = field(init=False)
    mark: np.ndarray = field(init=False)
    prof: np.ndarray = field(init=False)
    lazy: _lazy.Lazy | None = field(init=False, default=None)
    lazy_walk: np.ndarray = field(init=False)
    packed_stale: bool = field(init=False, default=False)

    def __post_init__(self) -> None:
        n = self.height.size
        self.pk = K.packed_records(n)
        self.gone = K.packed_records(n)
        # every cell of a stream bin (one row, one subdomain) has the same area and slide
        self.bin_area = np.zeros(self.n_radial * self.n_subdomains)
        self.bin_slide = np.zeros(self.n_radial * self.n_subdomains)
        self.bin_area[self.cell_bin] = self.cell_area
        self.bin_slide[self.cell_bin] = self.cell_slide
        # the fibre field exposes fibres later, so rule 7 is checked even with none yet
        self.rule7_on = bool(np.isfinite(self.fibre_floor).any()) or self.fibres is not None
        self.exposed = np.zeros(0, dtype=np.int64)  # the fibre field's scratch, made on use
        self.mark = np.zeros(n, dtype=np.int8)
        self.prof = np.zeros(K.N_TIMED, dtype=np.int64)  # cycles per kernel phase (profiling)
        # lazy kernel counters: solves that walked, walk steps, envelope iterations, jumps,
        # cycles in the envelope iteration, cycles in the walk, exact-scan fallbacks
        self.lazy_walk = np.zeros(8)
        self.heap_keys = np.zeros(4 * n + 8)
        self.heap_vals = np.zeros(4 * n + 8, dtype=np.int64)
        self.cand = np.zeros(n, dtype=np.int8)
        self.ncand = np.zeros(self.n_radial * self.n_subdomains, dtype=np.int64)
        self.cmax = np.zeros(self.n_radial * self.n_subdomains)
        self.rule4_list = np.zeros(n, dtype=np.int64)
        self.cnt = np.zeros(K.N_CNT, dtype=np.int64)
        self.resync()

    def array(self, name: str) -> np.ndarray:
        """A state array by name; ``pk_h``, ``pk_base``, ``pk_idx``, ``pk_bin`` and ``pk_st``
        are the fields of the packed plateau records."""
        if name in _PACKED_FIELDS:
            return self.pk[_PACKED_FIELDS[name]]
        return getattr(self, name)

    @classmethod
    def from_surface(cls, surface: Surface, grid: Grid) -> SimulationState:
        """Initial state of a fresh pad surface on ``grid``."""
        n_r, n_t = surface.height.shape
        n_sub = grid.n_subdomains
        rows = np.repeat(np.arange(n_r), n_t)
        cols = np.tile(np.arange(n_t), n_r)
        height = np.ascontiguousarray(surface.height, dtype=np.float64).ravel().copy()
        fibres = surface.field
        if fibres is not None:
            fibres = dataclasses.replace(fibres, next=fibres.next.copy())
        return cls(
            height=height,
            base=height.copy(),
            status=np.ascontiguousarray(surface.status, dtype=np.int8).ravel().copy(),
            fibre_floor=np.ascontiguousarray(surface.fibre_floor, dtype=np.float64).ravel().copy(),
            inflow=np.zeros(n_r * n_sub),
            outflow=np.zeros(n_r * n_sub),
            acc=np.zeros(K.N_ACC),
            cell_area=np.asarray(grid.cell_area, dtype=np.float64)[rows],
            cell_slide=np.asarray(grid.step_sliding_distance, dtype=np.float64)[rows],
            cell_bin=(rows * n_sub + cols // grid.columns_per_subdomain).astype(np.int64),
            n_radial=n_r,
            n_angular=n_t,
            n_subdomains=n_sub,
            fibres=fibres,
        )

    def resync(self) -> None:
        """Rebuild every derived structure from heights and statuses: the plateau order
        (stable sort, highest first), the resin heap, the creation candidates, the areas and
        held volume, and a rule-4 check of every secondary plateau at the next step."""
        plateau = np.flatnonzero(self.status != NONE)
        ranked = plateau[np.argsort(-self.height[plateau], kind="stable")]
        K.pack_plateaus(
            ranked,
            ranked.size,
            self.pk,
            self.height,
            self.base,
            self.cell_bin,
            self.status,
            self.cnt,
        )
        self.packed_stale = False
        K.heap_rebuild(self.heap_keys, self.heap_vals, self.cnt, self.status, self.height)
        K.rebuild_candidates(
            self.status,
            self.height,
            self.cand,
            self.ncand,
            self.cmax,
            self.cell_bin,
            self.n_angular,
        )
        secondary = np.flatnonzero(self.status == SECONDARY)
        self.rule4_list[: secondary.size] = secondary
        self.cnt[K.CNT_RULE4] = secondary.size
        self.acc[K.ACC_HELD] = self.held_volume()
        self.acc[K.ACC_PRIMARY_AREA] = float(self.cell_area[self.status == 1].sum())
        self.acc[K.ACC_SECONDARY_AREA] = float(self.cell_area[secondary].sum())

    def held_volume(self) -> float:
        """Volume held in secondary plateaus, summed from the state [m^3]."""
        sec = self.status == SECONDARY
        return float(np.sum((self.height[sec] - self.base[sec]) * self.cell_area[sec]))


def end_of_stop(
    state: SimulationState,
    removal_fraction: float,
    rng: np.random.Generator,
    rule: Literal["count", "draw"] = "count",
    streams: Literal["emit", "carry"] = "emit",
) -> tuple[float, int]:
    """Between stops: the particles in the contact leave it (unless ``streams`` carries
    them into the next stop), and rule S removes secondaries.

    Parameters
    ----------
    state
        Run state, changed in place.
    removal_fraction
        S [-]: 0 keeps every secondary plateau, 1 removes all; in between a random fraction
        S of them, as ``rule`` picks them.
    rng
        The run's generator (drawn from only when 0 < S < 1 and there is a secondary
        plateau).
    rule
        ``"count"``: ``round(S n)`` of the ``n`` secondary plateaus (Python's rounding, half
        to even), drawn without replacement; ``"draw"``: each one with probability S, one
        uniform number per plateau in cell order (``automaton.secondary_removal_rule``).
    streams
        ``"emit"``: the particles in the streams leave the contact and count as emitted;
        ``"carry"``: they stay in the streams for the next stop
        (``automaton.end_of_stop_streams``).

    Returns
    -------
    emitted : float
        Volume emitted by the flush and the removal [m^3].
    removed : int
        Number of secondary plateaus removed [-].
    """
    emitted = 0.0
    if streams == "emit":
        emitted = float(state.inflow.sum())
        state.inflow[:] = 0.0
    secondary = np.flatnonzero(state.status == SECONDARY)
    if removal_fraction >= 1.0:
        chosen = secondary
    elif removal_fraction <= 0.0 or secondary.size == 0:
        chosen = secondary[:0]
    elif rule == "draw":
        chosen = secondary[rng.random(secondary.size) < removal_fraction]
    else:
        n_remove = round(removal_fraction * secondary.size)
        chosen = np.sort(rng.choice(secondary, size=n_remove, replace=False))
    if chosen.size:
        deposit = (state.height[chosen] - state.base[chosen]) * state.cell_area[chosen]
        emitted += float(deposit.sum())
        state.height[chosen] = state.base[chosen]
        state.status[chosen] = NONE
        state.resync()
    state.acc[K.ACC_EMITTED] += emitted
    return emitted, int(chosen.size)


def expose_fibres(state: SimulationState, pad: PadConfig, grid: Grid) -> Exposure:
    """Between stops, with the fibre field: lay the field deeper where the wear front needs it
    (:func:`brakeca.surface.deepen_fibre_field`); then cells whose pad surface is worn into a
    buried fibre become primary plateaus (:func:`brakeca.automaton.expose_buried_fibres`),
    the deposits of the secondary plateaus among them are emitted (added to the emitted volume
    in ``state.acc``), and the kernel's structures are rebuilt if any cell changed. Nothing
    happens without a field.

    Parameters
    ----------
    state
        The run's state after a stop, changed in place.
    pad
        The pad's parameters (the fibres' sizes [m] and area fraction [-]).
    grid
        The polar grid.

    Returns
    -------
    Exposure
        The cells exposed [-], the largest depth of fibre worn before exposure [m] and the
        volume worn so [m^3], the fibre intervals passed within the stop [-] and the deposit volume
        released [m^3]; all zero without a field.
    """
    if state.fibres is None:
        return Exposure(0, 0.0, 0.0, 0, 0.0)
    lowest = float(pad_surface(state.status, state.height, state.base).min())
    state.fibres = deepen_fibre_field(
        state.fibres,
        pad,
        grid,
        lowest,
        state.status,
        state.height,
        state.fibre_floor,
    )
    fibres = state.fibres
    done = expose_buried_fibres(
        state.status,
        state.height,
        state.base,
        state.fibre_floor,
        state.cell_area,
        fibres.top,
        fibres.bottom,
        fibres.offsets[1:],
        fibres.next,
    )
    if done.exposed:
        state.acc[K.ACC_EMITTED] += done.released
        state.resync()
    return done


@dataclass
class _StopLog:
    """What a run keeps of its finished stops: per stop, the reductions of the per-step
    records and the records of the steps the per-step series keeps
    (:func:`brakeca.results.summarise_stop`), the step durations [s], the volume flushed at
    the end of the stop [m^3], the secondary plateaus rule S removed, the rule counts, and
    with the fibre field what the exposure after the stop did; the maps kept after stops."""

    summaries: list[np.ndarray]
    kept: list[np.ndarray]
    dts: list[np.ndarray]
    flush: list[float]
    s_removed: list[int]
    rule_counts: list[np.ndarray]
    exposures: list[Exposure] = field(default_factory=list)
    #: stop -> (statuses [-], heights [m]) after it, for the stops :func:`simulate`'s
    #: ``maps_at`` asks for
    maps: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)


def simulate(
    config: SimulationConfig,
    *,
    seed: int | None = None,
    rng: np.random.Generator | None = None,
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
        A generator to use instead of ``seed`` (its seed is then recorded as -1); not with
        ``seed``.
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
        ``config`` is not a :class:`~brakeca.config.SimulationConfig` (a dict, a preset name).
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
    else:
        seed = -1
    if checkpoint_every < 1:
        raise ValueError(f"checkpoint_every must be >= 1, got {checkpoint_every}")
    grid = make_grid(config)
    kernel = kernel_for(config)  # an unsupported numerics.kernel is refused before any work
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
        log = _StopLog([], [], [], [], [], [])
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
    for stop in stops[len(log.dts) :]:
        dt, rec, counts = advance_stop(state, grid, config, stop, lists)
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
    )
    if checkpoint and not keep_checkpoint:
        Path(checkpoint).unlink(missing_ok=True)
    result = RunResult(config=config, seed=seed, dataset=dataset)
    if distance is not None:
        _record_pm10(result, distance)
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
    from brakeca.emissions import pm10_from_run

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
        "; distance: the trace's distance the simulated events belong to [m]; pm10_mg_km "
        "(_low, _high): the vehicle's brake PM10 over it [mg/km] with brakeca.emissions' "
        "default factors and their ranges (docs/cycles.md section 5)"
    )


# --- checkpoints -------------------------------------------------------------------------
_PACKED_FIELDS = {
    "pk_h": K.P_H,
    "pk_base": K.P_BASE,
    "pk_idx": K.P_IDX,
    "pk_bin": K.P_BIN,
    "pk_st": K.P_ST,
}
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
    log: _StopLog,
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
        The :class:`SimulationState` after the last stop done.
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
    log: _StopLog
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
        The :class:`SimulationState`, the statuses before the first stop [-], the per-stop
        log, the random generator's saved state and the run's wall time so far [s]; None
        when there is no file.

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
    log = _StopLog(
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


def scratch_lists(n_cells: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel's three int64 scratch lists of ``n_cells`` entries (created cells, destroyed
    cells, positions of the destroyed records)."""
    return (
        np.zeros(n_cells, dtype=np.int64),
        np.zeros(n_cells, dtype=np.int64),
        np.zeros(n_cells, dtype=np.int64),
    )


class StopSteps(NamedTuple):
    """The steps of one stop, as :func:`advance_stop` ran them (a named tuple: ``dt, rec,
    counts = advance_stop(...)`` unpacks it).

    Attributes
    ----------
    dt : ndarray
        Step durations [s].
    rec : ndarray (n_steps, N_REC)
        Per-step record (see :mod:`brakeca._kernels`).
    counts : ndarray of int64, length 8
        Firings of rules 1..7 (index = rule number) [-].
    """

    dt: np.ndarray
    rec: np.ndarray
    counts: np.ndarray


def advance_stop(
    state: SimulationState,
    grid: Grid,
    config: SimulationConfig,
    stop: Stop,
    scratch: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> StopSteps:
    """Run every time step of one stop on ``state`` (in place) with the compiled kernel.

    Parameters
    ----------
    state
        The run's state, advanced in place.
    grid
        The polar grid.
    config
        The run's configuration.
    stop
        The stop to run (speeds [m/s], deceleration [m/s^2]).
    scratch
        The kernel's three int64 scratch lists of one entry per cell (:func:`scratch_lists`),
        to reuse from stop to stop; made afresh when None.

    Returns
    -------
    StopSteps
        The step durations [s], the per-step record and the rule firings.

    Raises
    ------
    ContactError, LedgerError
        As :func:`simulate`.
    """
    n_r, n_t = grid.shape
    created, destroyed, dpos = scratch or scratch_lists(n_r * n_t)
    profile = stop.profile(step_distance(config))
    dt, fraction = profile.dt, profile.fraction
    # the demanded band friction force is proportional to the deceleration
    per_unit = brake_demand(config, 1.0, grid.area).band_friction_force
    targets = per_unit * np.asarray(profile.deceleration, dtype=np.float64)
    rec = K.empty_record(dt.size)
    counts = np.zeros(8, dtype=np.int64)
    rule6 = config.automaton.rule6_max_gap
    fr = config.friction
    if kernel_for(config, grid) == "lazy":
        code, done = _run_lazy(
            state, grid, config, targets, fraction, rec, counts, scratch=(created, destroyed)
        )
        if code != K.OK:
            _raise_kernel_error(code, done, stop, targets, rec, config, state)
        return StopSteps(dt, rec, counts)
    if state.packed_stale:
        state.resync()
    code, done = K.run_stop(
        state.pk,
        state.gone,
        state.height,
        state.base,
        state.status,
        state.fibre_floor,
        state.cand,
        state.ncand,
        state.cmax,
        state.mark,
        state.inflow,
        state.outflow,
        state.heap_keys,
        state.heap_vals,
        state.rule4_list,
        state.cnt,
        state.acc,
        state.cell_area,
        state.cell_bin,
        state.bin_area,
        state.bin_slide,
        n_r,
        n_t,
        grid.n_subdomains,
        config.contact.stiffness,
        fr.mu_0,
        fr.slope,
        fr.mu_min,
        config.wear.specific_wear_rate,
        config.wear.resin_wear_depth,
        math.inf if rule6 is None else rule6,
        state.rule7_on,
        config.contact.bar_length,
        config.automaton.creation_order == "east_to_west",
        targets,
        fraction,
        config.output.ledger_tolerance,
        config.output.ledger_every,
        rec,
        counts,
        created,
        destroyed,
        dpos,
        state.prof,
        *_field_args(state),
    )
    if code != K.OK:
        _raise_kernel_error(code, done, stop, targets, rec, config, state)
    return StopSteps(dt, rec, counts)


_NO_FIELD = (False, np.zeros(0), np.zeros(0), np.zeros(0, np.int64), np.zeros(0, np.int64))


def _field_args(state: SimulationState) -> tuple:
    """The exact kernel's fibre-field arguments: on/off, the intervals' tops and bottoms [m],
    each cell's end and next interval, and a scratch list for the cells exposed in a step."""
    f = state.fibres
    if f is None:
        return (*_NO_FIELD, np.zeros(0, np.int64))
    if state.exposed.size != state.status.size:
        state.exposed = np.zeros(state.status.size, dtype=np.int64)
    end = np.ascontiguousarray(f.offsets[1:])
    return True, f.top, f.bottom, end, f.next, state.exposed


def kernel_for(config: SimulationConfig, grid: Grid | None = None) -> str:
    """The step kernel that runs ``config``: ``"exact"`` or ``"lazy"``
    (:meth:`brakeca.config.SimulationConfig.resolved_kernel`), checked to support it.
    ``grid``: the config's grid, if at hand (else it is built).

    Raises
    ------
    ValueError
        ``numerics.kernel = "lazy"`` for a configuration the lazy kernel does not support
        (a validated configuration never has it: the configuration refuses it).
    """
    kernel = config.resolved_kernel()
    if kernel == "exact" or config.numerics.kernel == "auto" or _lazy.supports(config, grid):
        return kernel
    raise ValueError(
        "numerics.kernel = 'lazy' supports fibres as columns with rule 6 off "
        "(pad.fibre_model = 'columns', automaton.rule6_max_gap unset) and WP K s < 1/2; "
        "use numerics.kernel = 'exact' or 'auto'"
    )


def _run_lazy(state, grid, config, targets, fraction, rec, counts, scratch):
    """One stop with the lazy kernel (brakeca._lazy)."""
    n_r, n_t = grid.shape
    if state.lazy is None:
        state.lazy = _lazy.Lazy(n_r, n_t, grid.n_subdomains)
    lz = state.lazy
    created, destroyed = scratch
    fr = config.friction
    tot = np.zeros(_lazy.N_E)
    code, done = _lazy.run_stop_lazy(
        _lazy.structures(lz),
        state.height,
        state.base,
        state.status,
        state.cand,
        state.ncand,
        state.cmax,
        state.mark,
        state.inflow,
        state.outflow,
        lz.resin_key,
        lz.resin_col,
        lz.resin_n,
        state.rule4_list,
        state.cnt,
        state.acc,
        state.cell_area,
        state.cell_bin,
        state.bin_area,
        state.bin_slide,
        n_r,
        n_t,
        grid.n_subdomains,
        lz.p2,
        config.contact.stiffness,
        fr.mu_0,
        fr.slope,
        fr.mu_min,
        config.wear.specific_wear_rate,
        config.wear.resin_wear_depth,
        config.contact.bar_length,
        config.automaton.creation_order == "east_to_west",
        targets,
        fraction,
        config.output.ledger_tolerance,
        rec,
        counts,
        created,
        destroyed,
        lz.dh,
        lz.marked,
        tot,
        state.lazy_walk,
        state.prof,
    )
    state.packed_stale = True
    return code, done


def _final_ledger(state: SimulationState) -> float:
    """Relative ledger residual after the last stop (the streams flushed, or, carried,
    counted as in the streams) [-]."""
    removed = state.acc[K.ACC_REMOVED]
    resid = removed - state.held_volume() - state.inflow.sum() - state.acc[K.ACC_EMITTED]
    return abs(resid) / removed if removed > 0 else abs(resid)


#: Largest relative miss of the demanded friction force a stop may end with [-]: the contact
#: solve meets it to round-off (about 1e-13 over the paper's study; a root off by more than
#: 1e-8 is found again by the exact scan), so a larger miss means the configuration is
#: beyond what the solve can resolve in floating point (a foundation so stiff that the
#: plateaus' interference vanishes beside their heights, say), and the run would be noise.
FRICTION_TOLERANCE = 1e-6


def _check_friction(residual: float, stop: Stop, config: SimulationConfig) -> None:
    """Raise ContactError if a stop's friction residual [-] exceeds
    :data:`FRICTION_TOLERANCE` or is not a number (a robustness review had a run at
    ``contact.elastic_modulus = 1e30`` recorded as ok, with MU 0 and a residual of 1)."""
    if residual <= FRICTION_TOLERANCE:
        return
    contact = config.contact
    missed = (
        "is not a number"
        if math.isnan(residual)
        else f"missed the demanded one by {residual:.3g} of it (tolerance {FRICTION_TOLERANCE:g})"
    )
    raise ContactError(
        f"stop {stop.index} ({stop.block}): the friction force {missed}: the torque control cannot "
        f"be resolved for this configuration (contact.elastic_modulus = "
        f"{contact.elastic_modulus:g} Pa, contact.bar_length = {contact.bar_length:g} m, "
        f"foundation stiffness {contact.elastic_modulus / contact.bar_length:.3g} Pa/m)"
    )


def _plateau_area(state: SimulationState) -> float:
    """The area [m^2] of the cells that are plateaus (primary or secondary) in ``state``."""
    plateau = (state.status == PRIMARY) | (state.status == SECONDARY)
    return float(state.cell_area[plateau].sum())


def _friction_maximum(config: SimulationConfig, plateau_area: float) -> tuple[str, float] | None:
    """The friction law's maximum, when it has one: with ``friction.mu_min = 0`` (and
    ``slope > 0``) ``mu(p) p`` peaks at ``p = mu_0 / (2c)`` and falls to 0 beyond
    ``mu_0 / c``, so the friction force has a maximum over the disc position and a demand
    above it has no root (the solvers report no root, which the kernels call "no plateau",
    or a root past the foundation's length). Returns a sentence saying so and the bound
    [N] of that maximum, ``mu_0^2 / (4c)`` [Pa] times the plateaus' area ``plateau_area``
    [m^2]; None without a maximum or without plateaus."""
    fr = config.friction
    if fr.mu_min != 0.0 or fr.slope <= 0.0 or plateau_area <= 0.0:
        return None
    # (with mu_min > 0, mu(p) p has a peak on the linear branch too, but grows past the
    # floor: no maximum of the force)
    p_star, peak = friction_stress_peak(fr.mu_0, fr.slope, 0.0)  # [Pa]: the most mu(p) p can be
    law = (
        f"with friction.mu_min = 0 the friction law mu(p) p peaks at {peak / 1e6:.3g} MPa "
        f"(p = mu_0 / 2c = {p_star / 1e6:.3g} MPa) and falls to 0 beyond "
        f"mu_0 / c, so the friction force has a maximum over the disc position"
    )
    return law, peak * plateau_area


def _field_error(
    exc: FibreFieldError, stop: Stop, config: SimulationConfig, lowest_disc: float
) -> FibreFieldError:
    """``exc`` of :func:`brakeca.surface.deepen_fibre_field` with the stop, the disc's lowest
    position in it [m] and the fields that set how far the surface comes down."""
    c, w = config.contact, config.wear
    return FibreFieldError(
        f"stop {stop.index} ({stop.block}): {exc}. The disc came down to "
        f"{lowest_disc * 1e3:.3f} mm in this stop, and the resin above it was cut to it: the "
        f"foundation's compliance (contact.elastic_modulus = {c.elastic_modulus:g} Pa, "
        f"contact.bar_length = {c.bar_length:g} m) or the wear (wear.specific_wear_rate = "
        f"{w.specific_wear_rate:g} m^2/N, wear.resin_wear_depth = {w.resin_wear_depth:g} m) "
        "take the surface down faster than the field is laid; pad.fibre_model = 'columns' "
        "has no such limit (docs/model.md §7)"
    )


def _raise_kernel_error(code, done, stop: Stop, targets, rec, config, state) -> None:
    """Raise the error of kernel ``code`` at step ``done`` of ``stop``, whose demanded
    friction forces [N] are ``targets``."""
    where = f"stop {stop.index} ({stop.block}), step {done + 1}"
    target = float(targets[min(done, targets.size - 1)])
    note = ""  # what the friction law's maximum adds to a "beyond its length"
    if code in (K.ERR_NO_PLATEAU, K.ERR_BAR):
        area = _plateau_area(state)
        maximum = _friction_maximum(config, area)
        if maximum is not None:
            law, bound = maximum
            if target > bound or code == K.ERR_NO_PLATEAU:  # plateaus there: no root
                raise ContactError(
                    f"{where}: {law}, and the demanded friction force {target:.4g} N is above "
                    f"it: no disc position carries it (the {area * 1e6:.4g} mm^2 of "
                    f"plateaus give at most {bound:.4g} N, were they all at that pressure at "
                    "once). Set friction.mu_min above 0 (the paper's floor is 0.15), or lower "
                    "the demand"
                )
            note = f" ({law}, which this demand may exceed)"
    if code == K.ERR_NO_PLATEAU:
        raise ContactError(
            f"{where}: no plateau cell can reach the disc, so the demanded friction force "
            f"{target:.4g} N cannot be carried (pad.fibre_area_fraction = "
            f"{config.pad.fibre_area_fraction})"
        )
    if code == K.ERR_BAR:
        raise ContactError(
            f"{where}: reaching the demanded friction force {target:.4g} N would compress the "
            f"foundation beyond its length contact.bar_length = {config.contact.bar_length} m; "
            f"the torque cannot be reached{note}"
        )
    if code == K.ERR_LEDGER:
        raise LedgerError(
            f"{where}: the volume ledger residual {rec[done - 1, K.R_LEDGER]:.3e} exceeds "
            f"output.ledger_tolerance = {config.output.ledger_tolerance}"
        )
    raise RuntimeError(f"{where}: kernel error code {code}")
