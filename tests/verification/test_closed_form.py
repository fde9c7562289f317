"""Closed-form checks: flat punch on the Winkler foundation, Archard wear at constant pressure,
the torque balance, and the first-root rule of the contact solver."""

from __future__ import annotations

import numpy as np
import pytest

from brakeca import _kernels as K
from brakeca.contact import ContactError, friction_force, solve_disc_position
from brakeca.cycle import brake_demand, expand_stops, step_distance, stop_steps
from brakeca.geometry import make_grid
from brakeca.reference import archard_wear_depth_constant_pressure, flat_punch_pressure
from brakeca.simulation import SimulationState, advance_stop
from brakeca.surface import Surface

LAW = {"mu_0": 0.6, "slope": 3e-8, "mu_min": 0.15}


def flat_plateau_state(grid, h0=50e-6):
    """Every cell a primary plateau at the same height: a flat punch."""
    shape = grid.shape
    surface = Surface(
        height=np.full(shape, h0),
        status=np.ones(shape, dtype=np.int8),
        fibre_floor=np.full(shape, -np.inf),
        n_fibres=0,
    )
    return SimulationState.from_surface(surface, grid)


@pytest.mark.parametrize("tau", [0.5e6, 2.9e6, 3.2e6, 10e6])  # linear branch, near peak, floor
def test_flat_punch_uniform_pressure(tau):
    K_ = 1e11
    area = np.full(50, 1e-8)
    h = np.full(50, 1e-4)
    z = solve_disc_position(h, area, stiffness=K_, target=tau * area.sum(), **LAW)
    p = K_ * (1e-4 - z)
    assert p == pytest.approx(flat_punch_pressure(tau * area.sum(), area.sum(), **LAW), rel=1e-12)
    # above the peak friction stress mu_0^2/(4c) = 3 MPa the root is on the floor branch
    if tau > 3e6:
        assert p == pytest.approx(tau / 0.15, rel=1e-12)


def test_first_root_is_the_smallest_load():
    """Two groups of cells: the friction force peaks, dips, then rises again; the solver must
    return the first crossing met from the top, checked against a dense scan."""
    rng = np.random.default_rng(1)
    h = np.concatenate([rng.uniform(2.0e-4, 2.1e-4, 40), rng.uniform(0.5e-4, 0.6e-4, 400)])
    area = np.full(h.size, 1e-8)
    zs = np.linspace(h.max(), h.min() - 3e-4, 40001)
    F = np.array(
        [
            friction_force(h, area, z, 1e11, **{"mu_0": 0.6, "slope": 3e-8, "mu_min": 0.15})
            for z in zs
        ]
    )
    for target in [0.5 * F.max(), 0.9 * F[zs > 1.0e-4].max(), 1.2 * F[zs > 1.0e-4].max()]:
        z = solve_disc_position(h, area, stiffness=1e11, target=target, **LAW)
        first = zs[np.argmax(F >= target)]
        assert abs(z - first) <= (zs[0] - zs[1])  # within one scan spacing
        assert friction_force(h, area, z, 1e11, **LAW) == pytest.approx(target, rel=1e-12)


def test_no_plateau_is_a_clear_error():
    with pytest.raises(ContactError, match="no plateau"):
        solve_disc_position(np.array([]), np.array([]), stiffness=1e11, target=1.0, **LAW)


def test_archard_wear_of_a_flat_punch_over_a_stop(tiny_config):
    """Uniform flat plateaus under torque control keep a constant uniform pressure; after a stop
    every cell has worn exactly WP p * (sliding distance over the stop). One row, so that every
    cell slides the same distance and the punch stays flat (with several rows the outer rows
    wear more and the pressure redistributes, by ~1e-6 relative here)."""
    config = tiny_config.with_updates(
        {"cycle.max_stops": 1, "wear.specific_wear_rate": 1e-13, "mesh.n_radial": 1}
    )
    grid = make_grid(config)
    state = flat_plateau_state(grid)
    stop = expand_stops(config)[0]
    _, rec, counts = advance_stop(state, grid, config, stop)
    target = brake_demand(config, stop.deceleration, grid.area).band_friction_force
    p = flat_punch_pressure(target, grid.area, **LAW)
    _, fraction = stop_steps(stop, step_distance(config))
    slid = np.asarray(grid.step_sliding_distance) * fraction.sum()
    expected = archard_wear_depth_constant_pressure(1e-13, p, slid)  # per row
    worn = 50e-6 - state.height.reshape(grid.shape)
    np.testing.assert_allclose(worn, np.broadcast_to(expected[:, None], grid.shape), rtol=1e-9)
    # the load balance: friction force equals the demand every step; pressure uniform
    np.testing.assert_allclose(rec[:, K.R_FRICTION], target, rtol=1e-12)
    np.testing.assert_allclose(rec[:, K.R_NORMAL], p * grid.area, rtol=1e-12)
    assert counts.sum() == 0  # no resin, no secondary: no rule fires
