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
from dataclasses import dataclass

import numpy as np

from brakeca import _kernels as K
from brakeca.config import SimulationConfig
from brakeca.contact import ContactError
from brakeca.cycle import Stop, brake_demand, expand_stops, step_distance, stop_steps
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
    inflow, outflow : float64 arrays (n_radial, n_subdomains)
        Particle streams [m^3].
    order : int64 array
        Plateau cells by height, highest first, in ``order[:n_plateau[0]]``.
    n_plateau : int64 array of length 1
    acc : float64 array
        Accumulators: removed [m^3], emitted [m^3], bound on resin heights [m].
    """

    height: np.ndarray
    base: np.ndarray
    status: np.ndarray
    fibre_floor: np.ndarray
    inflow: np.ndarray
    outflow: np.ndarray
    order: np.ndarray
    n_plateau: np.ndarray
    acc: np.ndarray

    @classmethod
    def from_surface(cls, surface: Surface, n_subdomains: int) -> SimulationState:
        """Initial state of a fresh pad surface."""
        n_r, n_t = surface.height.shape
        height = np.ascontiguousarray(surface.height, dtype=np.float64).ravel().copy()
        status = np.ascontiguousarray(surface.status, dtype=np.int8).ravel().copy()
        none = status == NONE
        acc = np.zeros(K.N_ACC)
        acc[K.ACC_NONE_MAX] = height[none].max() if none.any() else -math.inf
        state = cls(
            height=height,
            base=height.copy(),
            status=status,
            fibre_floor=np.ascontiguousarray(surface.fibre_floor, dtype=np.float64).ravel().copy(),
            inflow=np.zeros((n_r, n_subdomains)),
            outflow=np.zeros((n_r, n_subdomains)),
            order=np.zeros(height.size, dtype=np.int64),
            n_plateau=np.zeros(1, dtype=np.int64),
            acc=acc,
        )
        state.rebuild_order()
        return state

    def rebuild_order(self) -> None:
        """Sort the plateau cells by height from scratch (stable, highest first)."""
        plateau = np.flatnonzero(self.status != NONE)
        ranked = plateau[np.argsort(-self.height[plateau], kind="stable")]
        self.order[: ranked.size] = ranked
        self.n_plateau[0] = ranked.size

    def held_volume(self, cell_area_row: np.ndarray, n_angular: int) -> float:
        """Volume held in secondary plateaus [m^3]."""
        sec = np.flatnonzero(self.status == SECONDARY)
        return float(np.sum((self.height[sec] - self.base[sec]) * cell_area_row[sec // n_angular]))


def end_of_stop(
    state: SimulationState,
    grid: Grid,
    removal_fraction: float,
    rng: np.random.Generator,
) -> tuple[float, int]:
    """Between stops: the particles in the contact leave it, and rule S removes secondaries.

    Parameters
    ----------
    state
        Run state, changed in place.
    grid
        The grid.
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
    n_t = grid.angle.size
    emitted = float(state.inflow.sum())
    state.inflow[:] = 0.0
    secondary = np.flatnonzero(state.status == SECONDARY)
    if removal_fraction >= 1.0:
        chosen = secondary
    elif removal_fraction <= 0.0 or secondary.size == 0:
        chosen = secondary[:0]
    else:
        n_remove = int(round(removal_fraction * secondary.size))
        chosen = np.sort(rng.choice(secondary, size=n_remove, replace=False))
    if chosen.size:
        deposit = (state.height[chosen] - state.base[chosen]) * grid.cell_area[chosen // n_t]
        emitted += float(deposit.sum())
        state.height[chosen] = state.base[chosen]
        state.status[chosen] = NONE
        state.acc[K.ACC_NONE_MAX] = max(state.acc[K.ACC_NONE_MAX], float(state.height[chosen].max()))
        state.rebuild_order()
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
    state = SimulationState.from_surface(surface, grid.n_subdomains)
    stops = expand_stops(config)
    n_r, n_t = grid.shape
    created = np.zeros(n_r * n_t, dtype=np.int64)
    destroyed = np.zeros(n_r * n_t, dtype=np.int64)
    log = _StopLog([], [], [], [], [])
    for stop in stops:
        dt, rec, counts = advance_stop(state, grid, config, stop, created, destroyed)
        flush, n_removed = end_of_stop(state, grid, config.automaton.secondary_removal_fraction, rng)
        log.records.append(rec)
        log.dts.append(dt)
        log.flush.append(flush)
        log.s_removed.append(n_removed)
        log.rule_counts.append(counts)
        if progress is not None:
            progress(stop.index, len(stops))
    final_ledger = _final_ledger(state, grid)
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


def advance_stop(
    state: SimulationState,
    grid: Grid,
    config: SimulationConfig,
    stop: Stop,
    created: np.ndarray | None = None,
    destroyed: np.ndarray | None = None,
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
    if created is None or destroyed is None:
        created = np.zeros(n_r * n_t, dtype=np.int64)
        destroyed = np.zeros(n_r * n_t, dtype=np.int64)
    dt, fraction = stop_steps(stop, step_distance(config))
    demand = brake_demand(config, stop.deceleration, grid.area)
    rec = K.empty_record(dt.size)
    counts = np.zeros(8, dtype=np.int64)
    rule6 = config.automaton.rule6_max_gap
    fr = config.friction
    code, done = K.run_stop(
        state.height, state.base, state.status, state.fibre_floor, state.inflow,
        state.outflow, state.order, state.n_plateau, state.acc,
        grid.cell_area, grid.step_sliding_distance, n_r, n_t, grid.n_subdomains,
        config.contact.stiffness, fr.mu_0, fr.slope, fr.mu_min,
        config.wear.specific_wear_rate, config.wear.resin_wear_depth,
        math.inf if rule6 is None else rule6, config.contact.bar_length,
        config.automaton.creation_order == "east_to_west",
        demand.band_friction_force, fraction, config.output.ledger_tolerance,
        rec, counts, created, destroyed,
    )
    if code != K.OK:
        _raise_kernel_error(code, done, stop, demand.band_friction_force, rec, config)
    return dt, rec, counts


def _final_ledger(state: SimulationState, grid: Grid) -> float:
    """Relative ledger residual after the last stop (streams flushed) [-]."""
    removed = state.acc[K.ACC_REMOVED]
    held = state.held_volume(grid.cell_area, grid.angle.size)
    resid = removed - held - state.inflow.sum() - state.acc[K.ACC_EMITTED]
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

