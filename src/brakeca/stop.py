"""One stop of a run: its steps, every one in a compiled kernel call (:func:`advance_stop`),
and what happens between stops: the particles in the contact leave it and rule S removes
secondary plateaus (:func:`end_of_stop`), and with the fibre field the fibres the wear reached
are exposed (:func:`expose_fibres`). Wiring and checks; the physics is in
:mod:`brakeca.automaton`, :mod:`brakeca.contact`, :mod:`brakeca.friction`,
:mod:`brakeca.wear` and the kernels.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import math
from typing import Literal, NamedTuple

import numpy as np

from brakeca import _kernels as K
from brakeca import _lazy
from brakeca.automaton import Exposure, expose_buried_fibres, pad_surface
from brakeca.config import PadConfig, SimulationConfig
from brakeca.contact import ContactError
from brakeca.cycle import Stop, brake_demand, step_distance
from brakeca.friction import friction_stress_peak
from brakeca.geometry import Grid
from brakeca.state import SimulationState
from brakeca.surface import NONE, PRIMARY, SECONDARY, FibreFieldError, deepen_fibre_field

__all__ = [
    "LedgerError",
    "StopSteps",
    "advance_stop",
    "end_of_stop",
    "expose_fibres",
    "kernel_for",
    "scratch_lists",
]


class LedgerError(RuntimeError):
    """The volume ledger stopped closing: a bug, never a physical outcome."""


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
        As :func:`brakeca.simulation.simulate`.
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
                # (below the bound, the plateaus' heights differ, so at no disc position are
                # all of them at the law's peak: the wording had read as a contradiction, a
                # physics review)
                raise ContactError(
                    f"{where}: {law}, and the demanded friction force {target:.4g} N is above "
                    "it: no disc position carries it (the "
                    f"{area * 1e6:.4g} mm^2 of plateaus "
                    + (
                        f"give at most {bound:.4g} N, were they all at that pressure at once"
                        if target > bound
                        else f"would give {bound:.4g} N were they all at that pressure at once, "
                        "but their heights differ, so at any one disc position they give less "
                        "than the demand"
                    )
                    + "). Set friction.mu_min above 0 (the paper's floor is 0.15), or lower "
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
        trace = config.cycle.trace
        shares = (  # a trace's demand is scaled by its brake shares (a physics review)
            f", scaled by the trace's shares (cycle.trace.friction_share = "
            f"{trace.friction_share:g}, front_brake_share = {trace.front_brake_share:g}, "
            f"front_load_share = {trace.front_load_share:g})"
            if config.cycle.trace_file
            else ""
        )
        raise ContactError(
            f"{where}: reaching the demanded friction force {target:.4g} N would compress the "
            f"foundation beyond its length contact.bar_length = {config.contact.bar_length} m; "
            f"the torque cannot be reached{note}. The demand comes from "
            f"vehicle.wheel_load_mass = {config.vehicle.wheel_load_mass:g} kg braked at the "
            f"cycle's deceleration{shares}: a lighter wheel load or a gentler stop lowers it, a "
            "longer bar or a stiffer contact.elastic_modulus carries more"
        )
    if code == K.ERR_LEDGER:
        raise LedgerError(
            f"{where}: the volume ledger residual {rec[done - 1, K.R_LEDGER]:.3e} exceeds "
            f"output.ledger_tolerance = {config.output.ledger_tolerance}"
        )
    raise RuntimeError(f"{where}: kernel error code {code}")
