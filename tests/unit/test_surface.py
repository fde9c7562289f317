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
    # fibres are laid until they cover A: only the last can go past it, by at most the part of
    # the band it can cover (a test-suite review: no upper bound had let any excess pass)
    pad = config.pad
    last = pad.fibre_length_max * min(pad.fibre_diameter_max + 2 * dr, n_radial * dr)
    assert covered <= 0.10 * grid.area + last + grid.cell_area_map().max()


def test_centres_beyond_the_edges_keep_the_fibre_share_at_the_edges() -> None:
    """Centres drawn over the band only (the spec's reading, the default) thin the fibres
    towards the band's edges: on 8 full-resolution surfaces at A = 20 % the first and last 5
    rows hold 13 % fibre against 20 % mid-band (a spec audit). ``pad.fibre_centres =
    "beyond_edges"`` draws them over the band widened by a fibre's reach, and the edge rows
    hold as much as the middle; A is met either way, and the default's draws are unchanged."""
    from brakeca.surface import centre_area

    shares = {}
    for mode in ("band", "beyond_edges"):
        config = load_preset("paper").with_updates({"A": 20, "pad.fibre_centres": mode})
        grid = make_grid(config)
        edge, middle, covered, laid = [], [], [], []
        for seed in range(8):
            surface = generate_surface(config.pad, grid, np.random.default_rng(seed))
            fibre = surface.status == PRIMARY
            edge.append(np.r_[fibre[:5], fibre[-5:]].mean())
            middle.append(fibre[90:110].mean())
            covered.append(float((fibre * grid.cell_area[:, None]).sum() / grid.area))
            laid.append(surface.n_fibres)
        shares[mode] = float(np.mean(edge)) / float(np.mean(middle))
        assert min(covered) >= 0.2 and max(covered) < 0.21  # A, whichever the centres
        expected = config.expected_fibres()["the surface"]
        assert abs(np.mean(laid) / expected - 1) < 0.25, mode  # the MAX_FIBRES estimate
    assert shares["band"] < 0.75 and 0.9 < shares["beyond_edges"] < 1.1
    grid = make_grid(load_preset("paper"))
    reach = load_preset("paper").with_updates({"pad.fibre_centres": "beyond_edges"}).pad
    assert reach.fibre_reach == pytest.approx(5e-3 + 350e-6)
    assert centre_area(grid, 0.0) == pytest.approx(grid.area, rel=1e-9)
    # the default draws as before the option existed: the same surfaces to the bit (the
    # hashes of the version before it, columns and the fibre field's first slab)
    import hashlib

    for update, digest in (
        ({}, "27cedc9c1a1fa85e"),
        ({"pad.fibre_model": "field"}, "0cb1f846fd0828dc"),
    ):
        config = load_preset("paper").with_updates(update)
        s = generate_surface(config.pad, make_grid(config), np.random.default_rng(4))
        h = hashlib.sha256(s.height.tobytes() + s.status.tobytes() + s.fibre_floor.tobytes())
        if s.field is not None:
            h.update(s.field.top.tobytes() + s.field.bottom.tobytes())
        assert (h.hexdigest()[:16], s.n_fibres) == (digest, 177)


def test_crossing_fibres_keep_the_higher_top_and_the_lower_floor(monkeypatch) -> None:
    """Two fibres laid across each other (their draws set by hand), rasterised by brute
    force: where both cover a cell its height is the higher of their tops and its fibre floor
    the lower of their floors (spec section 9; the fibres' axes lie at one level, so that is
    the axis less the larger half-chord); laying stops once they cover A. A physics
    audit found the rule held only by a digest: "the last fibre wins" failed no test that
    says why."""
    config = load_preset("paper").with_updates(
        {"mesh.n_radial": 21, "mesh.n_angular": 400, "pad.fibre_model": "layer"}
    )
    grid = make_grid(config)
    rc, tc = float(grid.radius[10]), float(grid.angle[200])
    # length [m], diameter [m], orientation [rad], centre radius [m] and angle [rad]
    fibres = [(4e-3, 1.0e-3, 0.3, rc, tc), (3e-3, 0.7e-3, 0.3 + np.pi / 2, rc, tc + 1e-3)]

    def brute(length, diameter, phi, r0, t0):  # half-chord where the fibre covers, else NaN
        x = grid.radius[:, None] * np.cos(grid.angle)[None, :] - r0 * np.cos(t0)
        y = grid.radius[:, None] * np.sin(grid.angle)[None, :] - r0 * np.sin(t0)
        along = x * np.cos(phi) + y * np.sin(phi)
        across = np.abs(y * np.cos(phi) - x * np.sin(phi))
        inside = (np.abs(along) <= length / 2) & (across < diameter / 2)
        return np.where(inside, np.sqrt(np.maximum((diameter / 2) ** 2 - across**2, 0)), np.nan)

    first, second = (brute(*f) for f in fibres)
    both = ~np.isnan(first) & ~np.isnan(second)
    assert both.sum() >= 20  # a crossing of many cells
    # where both cover a cell, each fibre has the higher top somewhere
    assert (first[both] > second[both]).any() and (second[both] > first[both]).any()
    cover_first = float(np.nansum(~np.isnan(first) * grid.cell_area[:, None]))
    pad = config.pad.model_copy(  # covered once the second fibre lies, not before
        update={"fibre_area_fraction": cover_first * (1 + 1e-9) / grid.area}
    )
    queue = list(fibres)
    monkeypatch.setattr(_Band, "draw", lambda self, pad, rng: queue.pop(0))
    surface = generate_surface(pad, grid, np.random.default_rng(1))
    assert surface.n_fibres == 2 and not queue

    axis = pad.resin_roughness
    covered = ~np.isnan(first) | ~np.isnan(second)
    np.testing.assert_array_equal(surface.status == PRIMARY, covered)
    top = np.fmax(first, second)  # the higher half-chord of the fibres covering a cell
    np.testing.assert_allclose(surface.height[covered], axis + top[covered], rtol=1e-12)
    np.testing.assert_allclose(
        surface.fibre_floor[covered], axis - top[covered], rtol=1e-12, atol=1e-18
    )


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_one_fibre_lies_where_its_draws_put_it(seed) -> None:
    """One fibre rasterised by brute force over the whole band, from its own draws (the
    order generate_surface's Notes give), against the surface: the cells whose centres lie
    in the fibre's footprint (within half its length along its axis, within half its
    diameter across it) are primary, each as high as the axis plus the half-chord there
    (spec section 9), and its floor the axis less it; every other cell keeps its resin
    height. A tests review found the geometry checked only against a digest of an earlier
    surface: a fibre standing 0.8 chord high, or turned half as far, had passed every check
    but the digest."""
    config = load_preset("paper").with_updates(
        {"mesh.n_radial": 21, "mesh.n_angular": 200, "pad.fibre_model": "layer"}
    )
    pad = config.pad.model_copy(update={"fibre_area_fraction": 1e-6})  # one fibre covers it
    grid = make_grid(config)
    surface = generate_surface(pad, grid, np.random.default_rng(seed))
    assert surface.n_fibres == 1

    rng = np.random.default_rng(seed)
    resin = rng.uniform(0.0, pad.resin_roughness, size=grid.shape)
    length = rng.uniform(pad.fibre_length_min, pad.fibre_length_max)
    diameter = rng.uniform(pad.fibre_diameter_min, pad.fibre_diameter_max)
    phi = rng.uniform(0.0, np.pi)
    dr = grid.radius[1] - grid.radius[0]
    dth = grid.angle[1] - grid.angle[0]
    r_lo, r_hi = grid.radius[0] - dr / 2, grid.radius[-1] + dr / 2
    rc = np.sqrt(rng.uniform(r_lo**2, r_hi**2))  # uniform in area over the band
    tc = rng.uniform(grid.angle[0] - dth / 2, grid.angle[-1] + dth / 2)
    expected_top = np.full(grid.shape, np.nan)
    for j, r in enumerate(grid.radius):
        for i, t in enumerate(grid.angle):
            x, y = r * np.cos(t) - rc * np.cos(tc), r * np.sin(t) - rc * np.sin(tc)
            along = x * np.cos(phi) + y * np.sin(phi)
            across = abs(y * np.cos(phi) - x * np.sin(phi))
            if abs(along) <= length / 2 and across < diameter / 2:
                expected_top[j, i] = np.sqrt((diameter / 2) ** 2 - across**2)
    fibre = ~np.isnan(expected_top)
    assert fibre.sum() >= 2  # (a fibre of several cells, so that the test says something)
    np.testing.assert_array_equal(surface.status == PRIMARY, fibre)
    axis = pad.resin_roughness  # the fibres' axes lie at the top of the resin's roughness
    np.testing.assert_allclose(surface.height[fibre], axis + expected_top[fibre], rtol=1e-12)
    np.testing.assert_allclose(
        surface.fibre_floor[fibre], axis - expected_top[fibre], rtol=1e-12, atol=1e-18
    )
    np.testing.assert_array_equal(surface.height[~fibre], resin[~fibre])
