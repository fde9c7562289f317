"""The orchestrator: one run of the model over a drive cycle. Wiring only, no physics.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from brakeca import _kernels as K
from brakeca.config import SimulationConfig
from brakeca.contact import ContactError
from brakeca.cycle import Stop, brake_demand, expand_stops, step_distance
from brakeca.geometry import Grid, make_grid
from brakeca.results import RunResult, build_dataset
from brakeca.surface import NONE, SECONDARY, Surface, generate_surface

__all__ = ["LedgerError", "SimulationState", "advance_stop", "end_of_stop", "simulate"]

Progress = Callable[[int, int], None]


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
    order: np.ndarray = field(init=False)
    heap_keys: np.ndarray = field(init=False)
    heap_vals: np.ndarray = field(init=False)
    cand: np.ndarray = field(init=False)
    ncand: np.ndarray = field(init=False)
    rule4_list: np.ndarray = field(init=False)
    cnt: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        n = self.height.size
        self.order = np.zeros(n, dtype=np.int64)
        self.heap_keys = np.zeros(4 * n + 8)
        self.heap_vals = np.zeros(4 * n + 8, dtype=np.int64)
        self.cand = np.zeros(n, dtype=np.int8)
        self.ncand = np.zeros(self.n_radial * self.n_subdomains, dtype=np.int64)
        self.rule4_list = np.zeros(n, dtype=np.int64)
        self.cnt = np.zeros(K.N_CNT, dtype=np.int64)
        self.resync()

    @classmethod
    def from_surface(cls, surface: Surface, grid: Grid) -> SimulationState:
        """Initial state of a fresh pad surface on ``grid``."""
        n_r, n_t = surface.height.shape
        n_sub = grid.n_subdomains
        rows = np.repeat(np.arange(n_r), n_t)
        cols = np.tile(np.arange(n_t), n_r)
        height = np.ascontiguousarray(surface.height, dtype=np.float64).ravel().copy()
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
        )

    def resync(self) -> None:
        """Rebuild every derived structure from heights and statuses: the plateau order
        (stable sort, highest first), the resin heap, the creation candidates, the areas and
        held volume, and a rule-4 check of every secondary plateau at the next step."""
        plateau = np.flatnonzero(self.status != NONE)
        ranked = plateau[np.argsort(-self.height[plateau], kind="stable")]
        self.order[: ranked.size] = ranked
        self.cnt[K.CNT_PLATEAU] = ranked.size
        K.heap_rebuild(self.heap_keys, self.heap_vals, self.cnt, self.status, self.height)
        K.rebuild_candidates(self.status, self.cand, self.ncand, self.cell_bin, self.n_angular)
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
) -> tuple[float, int]:
    """Between stops: the particles in the contact leave it, and rule S removes secondaries.

    Parameters
    ----------
    state
        Run state, changed in place.
    removal_fraction
        S [-]: 0 keeps every secondary plateau, 1 removes all; in between a random fraction
        S of them (``round(S n)`` cells drawn without replacement from ``rng``).
    rng
        The run's generator (drawn from only when 0 < S < 1).

    Returns
    -------
    emitted : float
        Volume emitted by the flush and the removal [m^3].
    removed : int
        Number of secondary plateaus removed [-].
    """
    emitted = float(state.inflow.sum())
    state.inflow[:] = 0.0
    secondary = np.flatnonzero(state.status == SECONDARY)
    if removal_fraction >= 1.0:
        chosen = secondary
    elif removal_fraction <= 0.0 or secondary.size == 0:
        chosen = secondary[:0]
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


@dataclass
class _StopLog:
    records: list[np.ndarray]
    dts: list[np.ndarray]
    flush: list[float]
    s_removed: list[int]
    rule_counts: list[np.ndarray]


def simulate(
    config: SimulationConfig,
    *,
    seed: int | None = None,
    rng: np.random.Generator | None = None,
    progress: Progress | None = None,
) -> RunResult:
    """Simulate one pad over the configured drive cycle.

    Parameters
    ----------
    config
        The resolved, validated configuration.
    seed
        Seed of the run's random generator (recorded in the result). Default 0.
    rng
        A generator to use instead of ``seed`` (its seed is then recorded as -1).
    progress
        Called as ``progress(stops_done, stops_total)`` after every stop.

    Returns
    -------
    RunResult
        Per-stop responses, MU, V, thinned per-step series, surface maps, provenance.

    Raises
    ------
    ContactError
        The demanded torque cannot be reached (names the stop and the step).
    LedgerError
        The volume ledger failed to close (a bug).
    """
    t0 = time.perf_counter()
    if rng is None:
        seed = 0 if seed is None else int(seed)
        rng = np.random.default_rng(seed)
    elif seed is None:
        seed = -1
    grid = make_grid(config)
    surface = generate_surface(config.pad, grid, rng)
    state = SimulationState.from_surface(surface, grid)
    stops = expand_stops(config)
    n_r, n_t = grid.shape
    lists = scratch_lists(n_r * n_t)
    log = _StopLog([], [], [], [], [])
    for stop in stops:
        dt, rec, counts = advance_stop(state, grid, config, stop, lists)
        flush, n_removed = end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
        log.records.append(rec)
        log.dts.append(dt)
        log.flush.append(flush)
        log.s_removed.append(n_removed)
        log.rule_counts.append(counts)
        if progress is not None:
            progress(stop.index, len(stops))
    final_ledger = _final_ledger(state)
    dataset = build_dataset(
        config=config,
        seed=seed,
        grid=grid,
        stops=stops,
        records=log.records,
        dts=log.dts,
        flush=log.flush,
        s_removed=log.s_removed,
        rule_counts=log.rule_counts,
        initial_status=surface.status,
        final_status=state.status.reshape(n_r, n_t),
        final_height=state.height.reshape(n_r, n_t),
        final_ledger=final_ledger,
        wall_time=time.perf_counter() - t0,
    )
    return RunResult(config=config, seed=seed, dataset=dataset)


def scratch_lists(n_cells: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Three int64 scratch lists of ``n_cells`` entries for the kernel."""
    return tuple(np.zeros(n_cells, dtype=np.int64) for _ in range(3))  # type: ignore[return-value]


def advance_stop(
    state: SimulationState,
    grid: Grid,
    config: SimulationConfig,
    stop: Stop,
    scratch: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run every time step of one stop on ``state`` (in place) with the compiled kernel.

    Returns
    -------
    dt : ndarray
        Step durations [s].
    rec : ndarray (n_steps, N_REC)
        Per-step record (see :mod:`brakeca._kernels`).
    counts : ndarray of int64, length 8
        Firings of rules 1..7 (index = rule number).

    Raises
    ------
    ContactError, LedgerError
        As :func:`simulate`.
    """
    n_r, n_t = grid.shape
    created, destroyed, scratch = scratch or scratch_lists(n_r * n_t)
    profile = stop.profile(step_distance(config))
    dt, fraction = profile.dt, profile.fraction
    # the demanded band friction force is proportional to the deceleration
    per_unit = brake_demand(config, 1.0, grid.area).band_friction_force
    targets = per_unit * np.asarray(profile.deceleration, dtype=np.float64)
    rec = K.empty_record(dt.size)
    counts = np.zeros(8, dtype=np.int64)
    rule6 = config.automaton.rule6_max_gap
    fr = config.friction
    code, done = K.run_stop(
        state.height,
        state.base,
        state.status,
        state.fibre_floor,
        state.cand,
        state.ncand,
        state.inflow,
        state.outflow,
        state.order,
        state.heap_keys,
        state.heap_vals,
        state.rule4_list,
        state.cnt,
        state.acc,
        state.cell_area,
        state.cell_slide,
        state.cell_bin,
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
        scratch,
    )
    if code != K.OK:
        _raise_kernel_error(code, done, stop, float(targets[min(done, dt.size - 1)]), rec, config)
    return dt, rec, counts


def _final_ledger(state: SimulationState) -> float:
    """Relative ledger residual after the last stop (streams flushed) [-]."""
    removed = state.acc[K.ACC_REMOVED]
    resid = removed - state.held_volume() - state.inflow.sum() - state.acc[K.ACC_EMITTED]
    return abs(resid) / removed if removed > 0 else abs(resid)


def _raise_kernel_error(code, done, stop: Stop, target, rec, config) -> None:
    where = f"stop {stop.index} ({stop.block}), step {done + 1}"
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
            "the torque cannot be reached"
        )
    if code == K.ERR_LEDGER:
        raise LedgerError(
            f"{where}: the volume ledger residual {rec[done - 1, K.R_LEDGER]:.3e} exceeds "
            f"output.ledger_tolerance = {config.output.ledger_tolerance}"
        )
    raise RuntimeError(f"{where}: kernel error code {code}")
