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


def _one_row_one_stop(tiny_config, kernel: str, g: float = 0.3):
    """``tiny_config`` on one row (every cell slides the same distance), one short stop at
    ``g``, WP = 1e-13, with ``kernel``."""
    import warnings

    from conftest import short_cycle

    from brakeca.config import UnitWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)  # 2 g, beyond grip, on purpose
        return tiny_config.with_updates(
            {
                "cycle": short_cycle(stops=1, g=g),
                "cycle.max_stops": 1,
                "wear.specific_wear_rate": 1e-13,
                "mesh.n_radial": 1,
                "numerics.kernel": kernel,
            }
        )


def _flat_punch_stop(config):
    """Flat plateaus over ``config``'s band run through its first stop: the grid, the state
    after it, the step records, the rule counts, the demanded friction force [N], the flat
    punch's pressure for it [Pa] and the steps' fractions of the stop's sliding [-]."""
    grid = make_grid(config)
    state = flat_plateau_state(grid)
    stop = expand_stops(config)[0]
    _, rec, counts = advance_stop(state, grid, config, stop)
    target = brake_demand(config, stop.deceleration, grid.area).band_friction_force
    p = flat_punch_pressure(target, grid.area, **LAW)
    _, fraction = stop_steps(stop, step_distance(config))
    return grid, state, rec, counts, target, p, fraction


@pytest.mark.parametrize("kernel", ["exact", "lazy"])
@pytest.mark.parametrize("g", [0.3, 2.0])  # friction stress 0.56 MPa (rising), 3.7 MPa (floor)
def test_archard_wear_of_a_flat_punch_over_a_stop(tiny_config, kernel, g):
    """Uniform flat plateaus under torque control keep a constant uniform pressure; after a stop
    every cell has worn exactly WP p * (sliding distance over the stop). One row, so that every
    cell slides the same distance and the punch stays flat (with several rows the outer rows
    wear more and the pressure redistributes, by ~1e-6 relative here). Both kernels, on the
    rising branch of mu(p) p and on the floor (2 g: above the 3 MPa peak friction stress)."""
    grid, state, rec, counts, target, p, fraction = _flat_punch_stop(
        _one_row_one_stop(tiny_config, kernel, g=g)
    )
    slid = np.asarray(grid.step_sliding_distance) * fraction.sum()
    expected = archard_wear_depth_constant_pressure(1e-13, p, slid)  # per row
    worn = 50e-6 - state.height.reshape(grid.shape)
    np.testing.assert_allclose(worn, np.broadcast_to(expected[:, None], grid.shape), rtol=1e-9)
    # the load balance: friction force equals the demand every step; pressure uniform
    np.testing.assert_allclose(rec[:, K.R_FRICTION], target, rtol=1e-12)
    np.testing.assert_allclose(rec[:, K.R_NORMAL], p * grid.area, rtol=1e-12)
    assert counts.sum() == 0  # no resin, no secondary: no rule fires


@pytest.mark.parametrize("kernel", ["exact", "lazy"])
def test_the_disc_sits_p_over_e_over_l_below_a_flat_punch(tiny_config, kernel):
    """The one place the foundation's stiffness K = E / L shows under torque control (the
    pressure does not depend on it): the disc sits p / K below the plateaus' top every step,
    the top lowered by the wear of the steps before. E and L typed here, not taken from the
    code's K (a physics audit: K = 2 E / L had passed every check but a count)."""
    config = _one_row_one_stop(tiny_config, kernel).with_updates(
        {"contact.elastic_modulus": 3e9, "contact.bar_length": 2e-2}
    )
    from brakeca.presets import load_preset

    assert load_preset("paper").contact.stiffness == 1e11  # the paper's: 1 GPa over 10 mm
    stiffness = 3e9 / 2e-2  # [Pa/m]
    grid, _, rec, _, _, p, fraction = _flat_punch_stop(config)
    slid = float(np.asarray(grid.step_sliding_distance)[0]) * fraction  # per step [m]
    worn_before = 1e-13 * p * np.concatenate([[0.0], np.cumsum(slid)[:-1]])
    np.testing.assert_allclose(
        rec[:, K.R_DISC], 50e-6 - worn_before - p / stiffness, rtol=1e-10, atol=0.0
    )


def test_the_brake_demand_by_hand_from_the_spec_tables():
    """Spec section 2 with Table 4's numbers, by hand: T = m_w a R_wheel, each of two pads
    takes T / (2 r_eff), the band its area's share A_sim / A_pad; the band's area is
    sum_j r_j dtheta dr over the cells (section 3). At 0.25 g: T = 690 x 2.4525 x 0.314."""
    from brakeca.presets import load_preset

    config = load_preset("paper")
    a = 0.25 * 9.81
    torque = 690.0 * a * 0.314
    assert torque == pytest.approx(531.35865, rel=1e-12)
    pad = torque / (2 * 0.113)
    mesh = config.mesh
    dtheta = np.radians(mesh.angular_step_deg)
    r = config.inner_radius + mesh.radial_step * np.arange(mesh.n_radial)
    area = float(np.sum(r * dtheta * mesh.radial_step)) * mesh.n_angular
    grid = make_grid(config)
    assert grid.area == pytest.approx(area, rel=1e-12)
    demand = brake_demand(config, a, grid.area)
    assert demand.brake_torque == pytest.approx(torque, rel=1e-12)
    assert demand.pad_friction_force == pytest.approx(pad, rel=1e-12)
    assert demand.band_friction_force == pytest.approx(pad * area / 5.080e-3, rel=1e-12)
    assert pad == pytest.approx(2351.14, abs=0.01)  # N; the band (201 rows): 34.3 % of it
    assert area / 5.080e-3 == pytest.approx(0.3434, abs=5e-5)


def test_the_pad_normal_force_and_line_pressure_of_a_run(tiny_config):
    """A run's per-stop outputs (spec section 2): the pad's normal force is the band's times
    A_pad / A_sim, the line pressure that over the piston's area pi d^2 / 4; per step, COF times
    normal force is the demanded friction (the torque balance)."""
    from brakeca.simulation import simulate

    config = tiny_config.with_updates({"cycle.max_stops": 2, "output.series_every": 1})
    ds = simulate(config, seed=4).dataset
    grid = make_grid(config)
    scale = 5.080e-3 / grid.area
    np.testing.assert_allclose(ds["normal_force"], ds["band_normal_force"] * scale, rtol=1e-12)
    piston = np.pi * 0.057**2 / 4
    np.testing.assert_allclose(ds["line_pressure"], ds["normal_force"] / piston, rtol=1e-12)
    stop = expand_stops(config)[0]
    demand = brake_demand(config, stop.deceleration, grid.area)
    full = ds["step_stop"].values >= 1  # every step of the two stops
    friction = ds["step_cof"].values[full] * ds["step_normal_force"].values[full] / scale
    np.testing.assert_allclose(friction, demand.band_friction_force, rtol=1e-9)


def test_the_cycle_kinematics_by_hand():
    """Spec section 4: constant deceleration, exact kinematics, a partial last step. Over every
    stop of the paper's cycle the steps' durations add up to (v0 - v1) / a and their sliding
    fractions times s to (v0^2 - v1^2) / (2 a); s = R_wheel N_m dtheta = 24.113 mm; the
    cycle has 491,160 steps, the burnish 81,050."""
    from brakeca.presets import load_preset

    config = load_preset("paper")
    s = step_distance(config)
    m = config.mesh
    assert s == pytest.approx(
        0.314 * (m.n_angular / m.n_subdomains) * np.radians(m.angular_step_deg)
    )
    assert s == pytest.approx(24.113e-3, abs=1e-6)
    total = burnish = 0
    for stop in expand_stops(config):
        dt, fraction = stop_steps(stop, s)
        v0, v1, a = stop.initial_speed, stop.final_speed, stop.deceleration
        assert dt.sum() == pytest.approx((v0 - v1) / a, rel=1e-9)
        assert (fraction * s).sum() == pytest.approx((v0**2 - v1**2) / (2 * a), rel=1e-9)
        assert np.all(fraction[:-1] == 1.0) and 0.0 < fraction[-1] <= 1.0
        total += dt.size
        burnish += dt.size if stop.block == "Burnish" else 0
    assert (total, burnish) == (491_160, 81_050)


def test_a_demand_above_the_maximum_of_a_floorless_law_has_no_root():
    """With mu_min = 0, mu(p) p peaks at mu_0^2 / 4c = 3 MPa and falls to 0 beyond mu_0 / c:
    the friction force has a maximum. A demand above it has no root, and the solver says so;
    round-off had left the slope past every floor a little above 0 and returned a root some
    1e11 m away with code 0 (a helper's fidelity audit). Below the peak the root is found."""
    from brakeca.contact import SOLVE_NO_ROOT, SOLVE_OK, first_root

    law = {"mu_0": 0.6, "slope": 3e-8, "mu_min": 0.0}
    h = np.sort(np.random.default_rng(0).uniform(100e-6, 350e-6, 2000))[::-1].copy()
    area = np.full(h.size, 1e-8)
    peak = 0.6**2 / (4 * 3e-8) * area.sum()  # no position gives more
    _, _, code = first_root(h, area, h.size, 1e11, *law.values(), 1.2 * peak)
    assert code == SOLVE_NO_ROOT
    with pytest.raises(ContactError, match="mu_min = 0 the friction force has a maximum"):
        solve_disc_position(h, area, stiffness=1e11, target=1.2 * peak, **law)
    z, _, code = first_root(h, area, h.size, 1e11, *law.values(), 0.3 * peak)
    assert code == SOLVE_OK
    assert friction_force(h, area, z, 1e11, **law) == pytest.approx(0.3 * peak, rel=1e-12)
    # a flat punch just above its peak friction stress
    flat = np.full(50, 1e-4)
    with pytest.raises(ContactError, match="has a maximum"):
        solve_disc_position(flat, area[:50], stiffness=1e11, target=3.01e6 * 50e-8, **law)


def test_a_stop_shorter_than_one_step_takes_one_partial_step():
    """Only a stop over (to round-off) no travel at all has no time step: half a step's
    travel is one step of fraction 0.5, whose duration is the stop's (v0 - v1) / a."""
    from brakeca.config import ConfigError
    from brakeca.cycle import Stop

    a, s = 2.0, 0.024
    v1 = 10.0
    v0 = np.sqrt(v1**2 + a * s)  # (v0² - v1²) / 2a = s / 2
    half = Stop(index=1, block="b", initial_speed=v0, final_speed=v1, deceleration=a)
    dt, fraction = stop_steps(half, s)
    assert fraction.tolist() == [pytest.approx(0.5, rel=1e-12)]
    assert dt.tolist() == [pytest.approx((half.initial_speed - v1) / a, rel=1e-12)]
    none = Stop(index=2, block="b", initial_speed=v1 + 1e-14, final_speed=v1, deceleration=a)
    with pytest.raises(ConfigError, match=r"stop 2 \(b\) brakes over .* under 1e-9 of one"):
        stop_steps(none, s)


def test_the_flat_punch_reference_refuses_a_force_no_pressure_gives():
    """With mu_min = 0 a force above mu_0² A / 4c has no pressure (it had divided by
    mu_min = 0); below the peak the root is the smaller of the quadratic's."""
    law = {"mu_0": 0.6, "slope": 3e-8, "mu_min": 0.0}
    peak = 0.6**2 * 1e-3 / (4 * 3e-8)
    # 0.75 of the peak: mu_0 p - c p² = 0.75 mu_0² / 4c, p = (0.6 - 0.3) / 2c = 5 MPa
    assert flat_punch_pressure(0.75 * peak, 1e-3, **law) == pytest.approx(5e6, rel=1e-12)
    with pytest.raises(ValueError, match=r"peaks at mu_0\^2 A / \(4 c\) = 3000 N"):
        flat_punch_pressure(1.01 * peak, 1e-3, **law)
    with pytest.raises(ValueError, match="area must be above 0 m"):
        flat_punch_pressure(1.0, 0.0, **LAW)


@pytest.mark.parametrize("mu_min", [0.0, 0.15])
def test_a_constant_cof_law_has_a_root_at_any_load(mu_min):
    """slope = 0 is a constant COF, mu = mu_0, whatever mu_min: the friction force rises
    without bound, so a root exists at any load. With mu_min = 0 both solvers had taken the
    last interval for 'every cell past its floor' and reported no root (a helper's fuzzing;
    with slope = 0 no cell has a floor). The flat punch carries p = F / (mu_0 A)."""
    law = {"mu_0": 0.6, "slope": 0.0, "mu_min": mu_min}
    area = np.full(50, 1e-8)
    h = np.full(50, 1e-4)
    for tau in (0.5e6, 50e6):
        z = solve_disc_position(h, area, stiffness=1e11, target=tau * area.sum(), **law)
        p = 1e11 * (1e-4 - z)
        assert p == pytest.approx(tau / 0.6, rel=1e-12)
        assert p == pytest.approx(flat_punch_pressure(tau * area.sum(), area.sum(), **law))


def test_a_constant_cof_law_runs_on_both_kernels():
    """The same law in a run: with mu_min = 0 the exact kernel had failed at the first step
    ('no plateau cell can reach the disc'); both kernels now give MU = mu_0 and the same
    run as with the floor at 0.15, which a constant 0.6 never reaches."""
    from brakeca.presets import load_preset
    from brakeca.simulation import simulate

    base = load_preset("paper").with_updates(
        {
            "mesh.n_radial": 3,
            "mesh.n_angular": 100,
            "contact.elastic_modulus": 1e7,
            "friction.slope": 0.0,
            "cycle.max_stops": 1,
        }
    )
    runs = {
        (kernel, mu_min): simulate(
            base.with_updates({"numerics.kernel": kernel, "friction.mu_min": mu_min}), seed=1
        )
        for kernel in ("exact", "lazy")
        for mu_min in (0.0, 0.15)
    }
    for run in runs.values():
        assert run.MU == pytest.approx(0.6, rel=1e-12)
        assert float(run.dataset["max_friction_residual"]) < 1e-10
    for kernel in ("exact", "lazy"):
        assert runs[kernel, 0.0].V == runs[kernel, 0.15].V
    assert runs["lazy", 0.0].V == pytest.approx(runs["exact", 0.0].V, rel=1e-9)


@pytest.mark.parametrize("kernel", ["exact", "lazy"])
def test_a_secondary_worn_through_without_support_counts_as_rule_5_alone(tiny_config, kernel):
    """By hand, on a flat punch of one row: a secondary plateau with resin east of it and a
    deposit thinner than one step's wear is destroyed by rule 5 alone, though rule 4 holds
    for it too (model.md §7: a cell worn through its deposit counts as rule 5); one with a
    thick deposit and resin east of it by rule 4. A mutation review found that counting such
    a cell under both rules went unseen: the twin's cases never reach it."""
    config = _one_row_one_stop(tiny_config, kernel)
    grid = make_grid(config)
    state = flat_plateau_state(grid)
    h0 = state.height[0]
    thin, thick = 10, 30  # secondary plateaus, each with a resin cell east of it, far down
    for cell, deposit in ((thin, 1e-15), (thick, 10e-6)):
        state.status[cell] = 2
        state.base[cell] = h0 - deposit
        state.status[cell + 1] = 0
        state.height[cell + 1] = state.base[cell + 1] = 0.0
    state.resync()
    state.acc[K.ACC_REMOVED] = state.acc[K.ACC_HELD]  # the deposits were pad worn before
    stop = expand_stops(config)[0]
    _, rec, counts = advance_stop(state, grid, config, stop)
    assert rec[0, K.R_DISC] < h0 - 1e-15  # the first step wears the thin deposit through
    np.testing.assert_array_equal(counts, [0, 0, 0, 0, 1, 1, 0, 0])
    assert state.status[thin] == state.status[thick] == 0
