"""The metal-fibre surface (spec section 9): where fibres are laid, and that the fibre
fraction A is reached on any band the mesh accepts."""

from __future__ import annotations

import numpy as np
import pytest

from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.surface import PRIMARY, _Band, generate_surface


@pytest.mark.parametrize("n_radial", [1, 2, 5])
def test_fibres_are_laid_on_the_band_whatever_its_rows(n_radial) -> None:
    """The band spans half a radial step beyond its first and last rows, one row included
    (its bounds had been +-0.5 m around the row, so no fibre could touch it and the surface
    generation never ended)."""
    config = load_preset("paper").with_updates({"mesh.n_radial": n_radial, "A": 10})
    grid = make_grid(config)
    band = _Band.of(grid)
    dr = config.mesh.radial_step
    assert band.r_lo == pytest.approx(grid.radius[0] - dr / 2, rel=1e-12)
    assert band.r_hi == pytest.approx(grid.radius[-1] + dr / 2, rel=1e-12)
    surface = generate_surface(config.pad, grid, np.random.default_rng(1))
    assert surface.n_fibres > 0
    covered = float(((surface.status == PRIMARY) * grid.cell_area_map()).sum())
    assert covered >= 0.10 * grid.area
