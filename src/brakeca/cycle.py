"""Drive cycles: blocks of stops at constant deceleration, and the exact stop kinematics.

The time step is the time a point of the disc takes to pass one subdomain; in each step the
disc turns by ``N_m * dtheta`` and the vehicle travels ``s = R_wheel * N_m * dtheta``. At
constant deceleration ``a`` the speeds obey ``v_{n+1}^2 = v_n^2 - 2 a s`` exactly, and the last
step of a stop is a partial one (decision, docs/model.md).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.4, Table 3.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from brakeca.config import SimulationConfig

__all__ = [
    "MAX_STOP_STEPS",
    "BrakeDemand",
    "Stop",
    "StopProfile",
    "brake_demand",
    "check_step_count",
    "cycle_events",
    "expand_stops",
    "map_stops",
    "step_distance",
    "stop_steps",
]

KMH = 1.0 / 3.6  #: one km/h in m/s


@dataclass(frozen=True)
class Stop:
    """One braking event of a block cycle (SI units).

    Attributes
    ----------
    index : int
        1-based stop number in the cycle [-].
    block : str
        Name of the block the stop belongs to.
    initial_speed, final_speed : float
        Vehicle speed at brake-on and brake-off [m/s].
    deceleration : float
        Constant deceleration [m/s^2].
    """

    index: int
    block: str
    initial_speed: float
    final_speed: float
    deceleration: float

    def profile(self, distance: float) -> StopProfile:
        """The time steps of this stop for a full-step travel ``distance`` [m].

        Parameters
        ----------
        distance
            Vehicle travel of one full step, s [m] (:func:`step_distance`).

        Returns
        -------
        StopProfile
            Step durations [s], fractions of a full step [-] (:func:`stop_steps`), and the
            stop's constant deceleration in every step [m/s^2].

        Raises
        ------
        ConfigError
            As :func:`stop_steps`: the stop would have no time step, or more than
            :data:`MAX_STOP_STEPS`.
        """
        dt, fraction = stop_steps(self, distance)
        return StopProfile(dt, fraction, np.full(dt.size, self.deceleration))


@dataclass(frozen=True)
class StopProfile:
    """The time steps of one braking event.

    Attributes
    ----------
    dt : ndarray
        Duration of each step [s].
    fraction : ndarray
        Fraction of a full step travelled in each step [-].
    deceleration : ndarray
        Vehicle deceleration the brake must deliver in each step [m/s^2].
    """

    dt: np.ndarray
    fraction: np.ndarray
    deceleration: np.ndarray


def expand_stops(config: SimulationConfig) -> list[Stop]:
    """The stops of the configured block cycle in driving order, cut to ``cycle.max_stops``.

    Parameters
    ----------
    config
        The configuration; its ``cycle.blocks`` give speeds [km/h] and decelerations [g].

    Returns
    -------
    list of Stop
        One per stop, numbered from 1, in SI units: initial and final speed [m/s],
        deceleration [m/s^2].

    Examples
    --------
    The paper's cycle: 170 stops in nine blocks, from burnish to hill descent:

    >>> from brakeca.cycle import expand_stops
    >>> from brakeca.presets import load_preset
    >>> stops = expand_stops(load_preset())
    >>> len(stops), stops[0].block, stops[-1].block
    (170, 'Burnish', 'Hill descent')
    >>> round(stops[0].initial_speed * 3.6, 6), round(stops[0].deceleration / 9.81, 6)  # km/h, g
    (50.0, 0.25)
    """
    stops: list[Stop] = []
    g = config.vehicle.gravity
    for block in config.cycle.blocks:
        for _ in range(block.stops):
            stops.append(
                Stop(
                    index=len(stops) + 1,
                    block=block.name,
                    initial_speed=block.initial_speed_kmh * KMH,
                    final_speed=block.final_speed_kmh * KMH,
                    deceleration=block.deceleration_g * g,
                )
            )
    return stops[: config.cycle.n_stops]


#: The most time steps one stop may take [-]: the paper's longest stop takes 8,481 at Table 5's
#: mesh, and 1e7 allocates 160 MB for its time steps alone (a review: an angular step of
#: 1e-9 degree asked for 531 GiB before a word was said).
MAX_STOP_STEPS = 10_000_000


def check_step_count(total: float, distance: float, where: str) -> None:
    """Refuse a stop of more than :data:`MAX_STOP_STEPS` time steps before its arrays are
    made.

    Parameters
    ----------
    total
        The stop's braking distance in full steps [-] (fractional; may be infinite).
    distance
        Vehicle travel of one full step, s [m].
    where
        The stop, for the message (``"stop 3 (Burnish)"``).

    Raises
    ------
    ConfigError
        ``total`` exceeds :data:`MAX_STOP_STEPS` (or is not finite); the message names the
        fields that set the step.
    """
    if total <= MAX_STOP_STEPS:
        return
    from brakeca.config import ConfigError

    raise ConfigError(
        f"{where} brakes over {total * distance:.4g} m in time steps of s = R_wheel N_m "
        f"dtheta = {distance:.3g} m: {total:.3g} steps, more than the {MAX_STOP_STEPS:,} a "
        "stop may take (the paper's longest takes 8,481). Check vehicle.wheel_radius [m], "
        "mesh.angular_step_deg [deg] and mesh.n_angular / mesh.n_subdomains (N_m), and the "
        "stop's speeds and deceleration"
    )


def step_distance(config: SimulationConfig) -> float:
    """Vehicle travel per full time step, s = R_wheel N_m dtheta [m]: the wheel turns, as the
    disc, by one subdomain (N_m columns of dtheta [rad]) a step; 24.11 mm at Table 5's mesh
    and the paper's 314 mm wheel.

    Parameters
    ----------
    config
        The configuration (``vehicle.wheel_radius`` [m], the mesh's columns per subdomain
        [-] and angular step [rad]).

    Returns
    -------
    float
        s [m].

    Notes
    -----
    ``s = R_wheel N_m dtheta``: the time step is the time a point of the disc takes to pass
    one subdomain (the paper's definition), in which the disc and the wheel turn by
    ``N_m dtheta``; row ``j`` of the pad slides ``r_j N_m dtheta`` in that step
    (:func:`brakeca.geometry.make_grid`). Speeds then follow ``v_{n+1}^2 = v_n^2 - 2 a s``
    (:func:`stop_steps`; docs/model.md section 2).

    References
    ----------
    Wahlström (2016), Section 2.4 (the time step) and Table 4, doi:10.1155/2016/8181260.

    Examples
    --------
    >>> from brakeca.cycle import step_distance
    >>> from brakeca.presets import load_preset
    >>> round(step_distance(load_preset()) * 1e3, 2)  # [mm]
    24.11
    """
    return (
        config.vehicle.wheel_radius * config.mesh.columns_per_subdomain * config.mesh.angular_step
    )


def stop_steps(stop: Stop, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Durations and sliding fractions of the time steps of one stop.

    Parameters
    ----------
    stop
        The stop.
    distance
        Vehicle travel of one full step, s [m].

    Returns
    -------
    dt : ndarray
        Duration of each step, (v_n - v_{n+1}) / a [s].
    fraction : ndarray
        Fraction of a full step travelled (1 except for the last, partial step) [-].

    Raises
    ------
    ConfigError
        If the stop would have no time step: it brakes over less than 1e-9 of a step's
        travel ``s`` (a stop shorter than one step but longer than that takes one partial
        step), or more than :data:`MAX_STOP_STEPS` (:func:`check_step_count`); the message
        names the stop and the fields to check.

    Notes
    -----
    ``v_{n+1}^2 = v_n^2 - 2 a s``; the stop ends when the speed reaches its final speed.

    Examples
    --------
    The first stop of the paper's cycle, 50 to 4 km/h at 0.25 g:

    >>> from brakeca.cycle import expand_stops, step_distance, stop_steps
    >>> from brakeca.presets import load_preset
    >>> config = load_preset()
    >>> dt, fraction = stop_steps(expand_stops(config)[0], step_distance(config))
    >>> dt.size, round(float(dt.sum()), 3)  # steps, braking time [s]
    (1621, 5.21)
    >>> float(fraction[0]), round(float(fraction[-1]), 3)  # the last step is a partial one
    (1.0, 0.496)
    """
    a = stop.deceleration
    v0, v1 = stop.initial_speed, stop.final_speed
    total = (v0 * v0 - v1 * v1) / (2.0 * a * distance)  # full steps, fractional
    check_step_count(total, distance, f"stop {stop.index} ({stop.block})")
    n_full = math.floor(total)
    rest = total - n_full
    if rest < 1e-9:  # the stop ends on a full step (to round-off)
        rest = 0.0
    n = n_full + (1 if rest > 0.0 else 0)
    if n == 0:
        from brakeca.config import ConfigError

        raise ConfigError(
            f"stop {stop.index} ({stop.block}) brakes over {total * distance:.3g} m, under "
            f"1e-9 of one time step's travel s = R_wheel N_m dtheta = {distance:.3g} m: it "
            "would have no time step (check vehicle.wheel_radius, mesh.angular_step_deg, "
            "vehicle.gravity and the stop's speeds and deceleration)"
        )
    k = np.arange(n + 1, dtype=np.float64)
    travelled = np.minimum(k, total) * distance
    v = np.sqrt(np.maximum(v0 * v0 - 2.0 * a * travelled, v1 * v1))
    v[-1] = v1
    dt = (v[:-1] - v[1:]) / a
    fraction = np.ones(n)
    if rest > 0.0:
        fraction[-1] = rest
    return dt, fraction


@dataclass(frozen=True)
class BrakeDemand:
    """What one stop asks of the simulated band (decisions in docs/model.md).

    Attributes
    ----------
    brake_torque : float
        Torque of this wheel's brake, T = m_w a R_wheel [N m].
    pad_friction_force : float
        Friction force of one pad at the effective radius, T / (n_pads r_eff) [N].
    band_friction_force : float
        Share of the simulated band, F_f,pad A_sim / A_pad [N].
    """

    brake_torque: float
    pad_friction_force: float
    band_friction_force: float


def brake_demand(config: SimulationConfig, deceleration: float, band_area: float) -> BrakeDemand:
    """Demanded friction for a deceleration on a simulated band.

    Parameters
    ----------
    config
        The configuration (wheel load [kg], wheel radius [m], pads, effective radius [m], pad
        area [m^2]).
    deceleration
        The vehicle's deceleration [m/s^2].
    band_area
        The simulated band's area A_sim [m^2].

    Returns
    -------
    BrakeDemand
        The brake torque [N m], each pad's friction force [N] and the band's share of it
        [N] (uniform nominal pressure: the pad's times A_sim / A_pad).

    Notes
    -----
    ``T = m_w a R_wheel``, ``F_f,pad = T / (n_pads r_eff)`` and
    ``F_f,sim = F_f,pad A_sim / A_pad``. The paper gives the car's and brake's data (Table 4)
    and a constant deceleration per stop (Table 3), nothing else; reading the front wheel load
    ``m_w`` (``vehicle.wheel_load_mass``, 690 kg) as the mass this brake decelerates, sharing
    the torque between ``n_pads`` = 2 pads (``brake.pads_per_brake``), each pad's friction
    acting at the effective radius ``r_eff``, and a uniform nominal pressure over the pad are
    decisions (docs/model.md section 1). Under torque control ``F_f,sim`` is the target of the
    contact solve, and the normal load is whatever it takes at the current COF. A speed-trace
    cycle passes, step by step, the deceleration left to this brake after the road load and
    the split between the axles (docs/model.md section 1, "Speed traces").

    References
    ----------
    Wahlström (2016), Section 2.4 and Tables 3 and 4, doi:10.1155/2016/8181260.

    Examples
    --------
    >>> from brakeca.cycle import brake_demand
    >>> from brakeca.geometry import make_grid
    >>> from brakeca.presets import load_preset
    >>> config = load_preset()
    >>> demand = brake_demand(config, 0.3 * 9.81, make_grid(config).area)  # 0.3 g
    >>> round(demand.brake_torque, 1), round(demand.pad_friction_force, 1)  # [N m], [N]
    (637.6, 2821.4)
    >>> round(demand.band_friction_force, 1)  # the band's share [N]
    968.7
    """
    torque = config.vehicle.wheel_load_mass * deceleration * config.vehicle.wheel_radius
    pad = torque / (config.brake.pads_per_brake * config.brake.effective_radius)
    return BrakeDemand(torque, pad, pad * band_area / config.brake.pad_area)


def cycle_events(config: SimulationConfig) -> list:
    """The stops of a block cycle, or the braking events of a trace cycle, to simulate."""
    if not config.cycle.trace_file:
        return expand_stops(config)
    from brakeca.traces import configured_cycle

    return list(configured_cycle(config).events)


def map_stops(maps_at: Iterable[int], n_stops: int, *, name: str = "maps_at") -> list[int]:
    """``maps_at`` (:func:`brakeca.simulation.simulate`) checked against a cycle of
    ``n_stops`` stops.

    Parameters
    ----------
    maps_at
        Stop numbers [-], from 1.
    n_stops
        The cycle's stops [-].
    name
        What the errors call ``maps_at`` (``--maps-at`` on the command line).

    Returns
    -------
    list of int
        The stops, in order.

    Raises
    ------
    ValueError
        Not whole numbers from 1 to ``n_stops``, or a stop given twice.
    """
    if isinstance(maps_at, str | bytes) or not isinstance(maps_at, Iterable):
        raise ValueError(f"{name}: expected stop numbers, e.g. [1, 50, 170], got {maps_at!r}")
    stops = list(maps_at)
    for k in stops:
        if isinstance(k, bool) or not isinstance(k, int | np.integer) or not 1 <= k <= n_stops:
            shown = int(k) if isinstance(k, np.integer) else repr(k)  # not np.int64(9)
            raise ValueError(
                f"{name}: stop {shown} is not a stop of this cycle (whole numbers from 1 to "
                f"{n_stops})"
            )
    if len(set(stops)) < len(stops):
        raise ValueError(f"{name}: a stop is given twice ({stops})")
    return sorted(int(k) for k in stops)
