"""Long cases, run with `scripts/test -m slow`: full resolution, and the whole cycle."""

from __future__ import annotations

import numpy as np
import pytest

from brakeca.design import quick_config
from brakeca.presets import load_preset
from brakeca.simulation import simulate

pytestmark = [pytest.mark.slow, pytest.mark.timeout(7200)]  # full-resolution runs


def _plausible(result, n_stops):
    ds = result.dataset
    assert ds.sizes["stop"] == n_stops
    assert np.all(ds.mean_cof >= 0.15 - 1e-12) and np.all(ds.mean_cof <= 0.6)
    assert float(ds.max_ledger_residual) < 1e-11
    assert float(ds.max_friction_residual) < 1e-10
    for name in ("mean_cof", "emitted_volume", "normal_force", "line_pressure"):
        assert np.all(np.isfinite(ds[name]))
    assert np.all(ds.emitted_volume > 0)
    assert float(ds.emitted_volume.sum()) <= float(ds.generated_volume.sum()) * (1 + 1e-9)


def test_full_resolution_first_stops():
    config = load_preset().with_updates({"cycle.max_stops": 3})
    result = simulate(config, seed=2016)
    _plausible(result, 3)
    ds = result.dataset
    assert ds.sizes["radius"] == 201 and ds.sizes["angle"] == 1000
    # early in the burnish only fibres touch the disc, so the pad wear is Archard's:
    # WP x (band normal force) x (sliding distance at the effective radius), to ~10 %
    travel = (50 / 3.6) ** 2 / 2 / (0.25 * 9.81) - (4 / 3.6) ** 2 / 2 / (0.25 * 9.81)
    slid = travel * config.brake.effective_radius / config.vehicle.wheel_radius
    expected = config.wear.specific_wear_rate * ds.band_normal_force.values * slid
    np.testing.assert_allclose(ds.generated_volume.values, expected, rtol=0.1)


def test_quick_whole_cycle_high_wear():
    config = quick_config(load_preset().with_updates({"WP": 1e-13}))
    result = simulate(config, seed=2016)
    _plausible(result, 170)
    ds = result.dataset
    # plateau areas change over the burnish and secondary plateaus form at this wear rate
    assert float(ds.secondary_area_fraction.max()) > 0.05
    assert float(ds.mean_cof.max()) - float(ds.mean_cof.min()) > 0.05
