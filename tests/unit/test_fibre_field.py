"""The fibre field (``pad.fibre_model = "field"``): fibres through the pad, merged per cell into
the intervals wear meets, and their exposure between stops."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from brakeca.automaton import expose_buried_fibres
from brakeca.config import ConfigError
from brakeca.contact import ContactError
from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import simulate
from brakeca.surface import (
    FIELD_SLAB,
    NONE,
    PRIMARY,
    SECONDARY,
    FibreFieldError,
    _merge_intervals,
    deepen_fibre_field,
    generate_surface,
)


def _naive_merge(n_cells, cell, top, bottom):
    """Union of intervals per cell, the obvious way: sort each cell's intervals by top and
    sweep."""
    out = []
    for c in range(n_cells):
        mine = sorted(
            ((t, b) for cc, t, b in zip(cell, top, bottom, strict=True) if cc == c), reverse=True
        )
        merged: list[list[float]] = []
        for t, b in mine:
            if merged and t >= merged[-1][1]:
                merged[-1][1] = min(merged[-1][1], b)
            else:
                merged.append([t, b])
        out.append(merged)
    return out


def test_merge_matches_the_obvious_sweep():
    rng = np.random.default_rng(7)
    n_cells = 13
    cell = rng.integers(0, n_cells, 400)
    top = rng.uniform(-1.0, 0.0, 400).round(2)  # rounded: ties and touching ends occur
    bottom = top - rng.uniform(0.0, 0.2, 400).round(2)
    offsets, mt, mb = _merge_intervals(n_cells, cell, top, bottom)
    expected = _naive_merge(n_cells, cell, top, bottom)
    assert offsets[-1] == sum(len(e) for e in expected)
    for c in range(n_cells):
        mine = slice(offsets[c], offsets[c + 1])
        got = list(zip(mt[mine], mb[mine], strict=True))
        assert got == [tuple(e) for e in expected[c]], c
    assert np.all(mb <= mt)


def _pad(model, A=20):
    return load_preset().with_updates({"pad.fibre_model": model, "A": A})


@pytest.mark.parametrize("A", [10, 20])
def test_field_keeps_the_surface_and_fills_the_pad_to_A(A):
    """Same seed: the field's surface is the other models' to the bit. Laid slab by slab
    ahead of the wear, the field's fibre fraction is A at every depth, across the slabs'
    boundaries (the Boolean model's count; without the -ln(1 - A) correction it would be
    0.181 at A = 20 %)."""
    config = _pad("field", A)
    grid = make_grid(config)
    layer = generate_surface(_pad("layer", A).pad, grid, np.random.default_rng(5))
    surface = generate_surface(config.pad, grid, np.random.default_rng(5))
    np.testing.assert_array_equal(surface.height, layer.height)
    np.testing.assert_array_equal(surface.status, layer.status)
    fibre = layer.status == PRIMARY
    # a surface fibre's floor is its own underside or, where a buried fibre meets it, lower
    assert np.all(surface.fibre_floor[fibre] <= layer.fibre_floor[fibre])
    assert np.mean(surface.fibre_floor[fibre] < layer.fibre_floor[fibre]) < 0.5
    assert np.all(np.isneginf(surface.fibre_floor[~fibre]))
    f = surface.field
    assert f is not None and f.slabs == 1
    first = f.offsets[:-1]
    # every interval not holding a surface fibre lies in the first slab, cut at 0
    buried = np.ones(f.top.size, dtype=bool)
    buried[first[fibre.ravel()]] = False
    r_max = config.pad.fibre_diameter_max / 2
    assert np.all(f.top[buried] <= 0.0) and np.all(f.bottom[buried] >= -FIELD_SLAB - r_max)
    _check_layout(f)
    # the next interval: the second for a fibre cell, the first for a resin cell
    np.testing.assert_array_equal(f.next, first + fibre.ravel())
    status = surface.status.ravel().copy()
    height = surface.height.ravel().copy()
    floor = surface.fibre_floor.ravel().copy()
    for lowest in (-0.5, -1.5, -2.5):  # the wear front comes down, a slab at a time
        f = deepen_fibre_field(f, config.pad, grid, lowest * FIELD_SLAB, status, height, floor)
    assert f.slabs == 4
    _check_layout(f)
    area = np.repeat(grid.cell_area, grid.shape[1])
    for k in range(1, 7):  # 1 mm layers from 1 mm to 7 mm down; slab boundaries at 2, 4, 6
        assert f.volume_fraction(area, -k * 1e-3, -(k + 1) * 1e-3) == pytest.approx(
            A / 100, abs=0.01
        )
    # and on average over the layers below the first (the surface's own layer aside), close
    # enough to tell the Boolean model's -ln(1 - A) from A itself, which fills 1 - e^(-A):
    # 0.095 at A = 10 % (a tests review: the per-layer bound let that through by 0.001); the
    # layers scatter by about 0.003, so their mean by about 0.0013
    deep = [f.volume_fraction(area, -k * 1e-3, -(k + 1) * 1e-3) for k in range(2, 7)]
    assert np.mean(deep) == pytest.approx(A / 100, abs=0.003)
    assert f.volume_fraction(area, -8.5e-3, -9.5e-3) == 0.0  # not laid yet
    assert np.all(floor[fibre.ravel()] <= surface.fibre_floor.ravel()[fibre.ravel()])


def _check_layout(f):
    """Intervals non-empty, disjoint and descending within each cell; ``next`` within them."""
    assert np.all(f.bottom < f.top)
    same_cell = np.repeat(np.arange(f.next.size), np.diff(f.offsets))
    follows = same_cell[1:] == same_cell[:-1]
    assert np.all(f.top[1:][follows] < f.bottom[:-1][follows])
    assert np.all((f.offsets[:-1] <= f.next) & (f.next <= f.offsets[1:]))


def test_a_field_without_surface_fibres_is_its_slab_alone():
    """``start_fibre_field`` with no surface fibres (a review: its defaults were passed by no
    call or test): the first slab's intervals alone, each cell's next its first; the same,
    to the bit, as with a surface that has no fibres, for the same draw."""
    from brakeca.surface import start_fibre_field

    config = load_preset().with_updates({"pad.fibre_model": "field", "A": 20, "mesh.n_radial": 21})
    grid = make_grid(config)
    alone = start_fibre_field(config.pad, grid, np.random.default_rng(3))
    none = np.zeros(grid.shape, dtype=bool)
    zeros = np.zeros(grid.shape)
    with_none = start_fibre_field(
        config.pad, grid, np.random.default_rng(3), None, none, zeros, zeros
    )
    for name in ("offsets", "top", "bottom", "next"):
        np.testing.assert_array_equal(getattr(alone, name), getattr(with_none, name))
    assert alone.slabs == 1 and alone.top.size > 0
    np.testing.assert_array_equal(alone.next, alone.offsets[:-1])
    assert np.all(alone.top <= 0.0)  # buried: the slab lies under the resin band's datum
    _check_layout(alone)


def test_deepening_drops_worn_intervals_and_extends_floors():
    """Deepening keeps only the intervals ahead of each cell's surface, lowers a primary's
    floor where a new fibre touches its fibre, and refuses a surface that came down past the
    field's laid slabs in one stop."""
    config = _pad("field", 20).with_updates({"mesh.n_radial": 41})
    grid = make_grid(config)
    surface = generate_surface(config.pad, grid, np.random.default_rng(2))
    f = surface.field
    status = surface.status.ravel().copy()
    height = surface.height.ravel().copy()
    floor = surface.fibre_floor.ravel().copy()
    f.next[:] = f.offsets[1:]  # every interval worn: only the primaries' own fibres remain
    before = floor.copy()
    deeper = deepen_fibre_field(f, config.pad, grid, -0.1e-3, status, height, floor)
    assert deeper.slabs == 2
    primary = status == PRIMARY
    np.testing.assert_array_equal(deeper.next[primary], deeper.offsets[:-1][primary] + 1)
    assert np.all(deeper.top[deeper.offsets[:-1][primary]] == height[primary])
    assert np.all(floor[primary] <= before[primary])
    # the new slab's fibres all lie below the first slab's axes
    r_max = config.pad.fibre_diameter_max / 2
    assert np.all(deeper.top[deeper.next[deeper.next < deeper.offsets[1:]]] <= -FIELD_SLAB + r_max)
    with pytest.raises(FibreFieldError, match="came down more than a slab"):
        deepen_fibre_field(deeper, config.pad, grid, -2.9 * FIELD_SLAB, status, height, floor)


def test_field_needs_some_resin():
    with pytest.raises(ConfigError, match=r"fibre_area_fraction: must lie in \(0, 1\)"):
        _pad("field").with_updates({"pad.fibre_area_fraction": 1.0})


def _cells():
    """Six cells with one or two buried intervals each, and their states [m, m^2]."""
    top = np.array([-1.0, -1.0, -3.0, -1.0, -1.0, -2.0, -1.0]) * 1e-4
    bottom = np.array([-2.0, -2.0, -4.0, -2.0, -2.0, -3.0, -2.0]) * 1e-4
    offsets = np.array([0, 1, 3, 4, 5, 6, 7])  # cell 1 has two intervals, the others one
    end = offsets[1:].copy()
    nxt = offsets[:-1].copy()
    status = np.array([NONE, NONE, NONE, SECONDARY, PRIMARY, NONE], dtype=np.int8)
    height = np.array([-0.5, -3.5, -0.99, -1.2, -2.5, -2.0]) * 1e-4
    base = height.copy()
    base[3] = -1.5e-4  # a deposit 0.3e-4 m thick on resin worn into the fibre
    floor = np.full(6, -np.inf)
    floor[4] = -3e-4
    area = np.full(6, 2.0)
    return status, height, base, floor, area, top, bottom, end, nxt


def test_exposure_rule_cell_by_cell():
    status, height, base, floor, area, top, bottom, end, nxt = _cells()
    h0 = height.copy()
    exposed, lag, lag_volume, skipped, released = expose_buried_fibres(
        status, height, base, floor, area, top, bottom, end, nxt
    )
    # cell 0: resin above its fibre's top: unchanged
    assert status[0] == NONE and nxt[0] == 0 and height[0] == h0[0]
    # cell 1: resin worn through its first fibre (-1e-4..-2e-4) into its second (-3..-4e-4)
    assert status[1] == PRIMARY and floor[1] == -4e-4 and nxt[1] == 3 and height[1] == h0[1]
    # cell 2: resin just above its fibre's top: unchanged
    assert status[2] == NONE and nxt[2] == 3
    # cell 3: a secondary plateau whose base is in its fibre: primary at its base, deposit out
    assert status[3] == PRIMARY and height[3] == -1.5e-4 and floor[3] == -2e-4 and nxt[3] == 5
    assert released == pytest.approx((-1.2e-4 + 1.5e-4) * 2.0)
    # cell 4: a primary plateau is not touched
    assert status[4] == PRIMARY and floor[4] == -3e-4 and nxt[4] == 5
    # cell 5: resin exactly at its fibre's underside: the fibre is passed, nothing left below
    assert status[5] == NONE and nxt[5] == end[5]
    assert exposed == 2 and skipped == 2
    assert lag == pytest.approx(max(-3e-4 + 3.5e-4, -1e-4 + 1.5e-4))
    assert lag_volume == pytest.approx((-3e-4 + 3.5e-4) * 2.0 + (-1e-4 + 1.5e-4) * 2.0)
    # applied again: nothing more to do
    again = expose_buried_fibres(status, height, base, floor, area, top, bottom, end, nxt)
    assert again == (0, 0.0, 0.0, 0, 0.0)


def _script():
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "fibre_field.py"
    spec = importlib.util.spec_from_file_location("fibre_field", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_layer_fibres_run_out_where_the_field_goes_on(tmp_path, capsys):
    """High wear, A = 10 %: the one-layer fibres wear through and the pad runs out of
    plateaus (a clear ContactError); with the field, wear exposes the fibre below in the
    steps, rule 7 fires, and the run completes with its volume ledger closed."""
    from conftest import short_cycle

    base = load_preset().with_updates(
        {
            "mesh.n_radial": 11,
            "WP": 1e-13,
            "A": 10,
            "cycle": short_cycle(stops=30, v0=50, v1=10, g=0.3),
        }
    )
    with pytest.raises(ContactError, match="bar_length"):
        simulate(base.with_updates({"pad.fibre_model": "layer"}), seed=3)
    run = simulate(base.with_updates({"pad.fibre_model": "field"}), seed=3)
    ds = run.dataset
    assert int(ds.rule_firings.sel(rule=7).sum()) > 0
    assert np.all(ds.fibre_cells_exposed.values[-10:] > 0)
    # the resin cut stops at the fibres: none is left to expose after a stop, with a lag
    assert ds.fibre_cells_exposed_late.sum() == 0 and ds.fibre_exposure_lag.max() == 0
    assert float(ds.primary_area_fraction[-1]) > 0.05
    assert float(ds.max_ledger_residual) < 1e-11
    assert np.all(ds.fibre_exposure_lag >= 0) and np.all(ds.fibre_volume_cut_as_resin >= 0)
    assert ds.fibre_intervals_skipped.dtype == np.int64 and ds.fibre_intervals_skipped.min() >= 0
    # benchmarks/fibre_field.py summarises the same run from its file
    script = _script()
    assert script.main([str(run.to_netcdf(tmp_path / "field.nc")), "--every", "10"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 5 and lines[1].split()[0] == "1-10"
    assert f"{int(ds.fibre_cells_exposed.sum())} cells exposed" in lines[-1]
    columns = simulate(base.with_updates({"cycle.max_stops": 1}), seed=3)
    with pytest.raises(SystemExit):
        script.main([str(columns.to_netcdf(tmp_path / "columns.nc"))])
    assert "not a run of pad.fibre_model = 'field'" in capsys.readouterr().err


def test_rule6_with_the_field_over_a_whole_run():
    """Rule 6 and the field together over 30 stops (the kernel-against-twin case covers a
    hand-made grid only): rule 6 fires, fibres are still exposed, and the ledger closes."""
    from conftest import short_cycle

    config = load_preset().with_updates(
        {
            "mesh.n_radial": 11,
            "WP": 1e-13,
            "A": 10,
            "cycle": short_cycle(stops=30, v0=50, v1=10, g=0.3),
            "pad.fibre_model": "field",
            "automaton.rule6_max_gap": 20e-6,
        }
    )
    ds = simulate(config, seed=3).dataset
    assert int(ds.rule_firings.sel(rule=6).sum()) > 0
    assert int(ds.rule_firings.sel(rule=7).sum()) > 0
    assert np.all(ds.fibre_cells_exposed.values[-10:] > 0)
    assert int(ds.fibre_cells_exposed_late.sum()) == 0
    assert float(ds.max_ledger_residual) < 1e-11
    assert float(ds.max_friction_residual) < 1e-8


def test_expected_fibre_counts_match_what_is_laid():
    """The estimate behind the configuration's check against endless fibre laying
    (``SimulationConfig.expected_fibres``) is close to the counts the generator lays."""
    from brakeca.surface import _Band, _lay_slab

    for A in (10, 20):
        config = _pad("field").with_updates({"A": A})
        grid = make_grid(config)
        expected = config.expected_fibres()
        laid = generate_surface(config.pad, grid, np.random.default_rng(4)).n_fibres
        slab = _lay_slab(config.pad, grid, _Band.of(grid), 4, 3)[3]
        assert laid == pytest.approx(expected["the surface"], rel=0.25)
        assert slab == pytest.approx(expected["each slab of the fibre field"], rel=0.25)


def test_a_surface_that_comes_down_past_the_field_in_one_stop_is_a_clear_error(tmp_path):
    """A soft foundation lets the disc sink 3.7 mm in the first stop and the resin cut
    follows it, past the 2 mm the field is laid ahead: the run stops with a FibreFieldError
    naming the stop, the disc's depth and the fields that set it (a helper's fuzzing: it had
    been a bare RuntimeError that blamed wear, a traceback on the command line)."""
    from typer.testing import CliRunner

    from brakeca.cli import app
    from brakeca.simulation import simulate

    soft = {
        "mesh.n_radial": 3,
        "mesh.n_angular": 100,
        "contact.elastic_modulus": 1e7,
        "pad.fibre_model": "field",
        "cycle.max_stops": 1,
    }
    config = load_preset("paper").with_updates(soft)
    with pytest.raises(FibreFieldError) as info:
        simulate(config, seed=0)
    message = str(info.value)
    assert message.startswith("stop 1 (Burnish): the pad surface came down to -3.725 mm")
    assert "The disc came down to -3.725 mm in this stop" in message
    assert "contact.elastic_modulus = 1e+07 Pa" in message and "pad.fibre_model" in message
    settings = [a for k, v in soft.items() if k != "cycle.max_stops" for a in ("--set", f"{k}={v}")]
    out = tmp_path / "x.nc"
    res = CliRunner().invoke(app, ["simulate", "-o", str(out), *settings, "--stops", "1"])
    assert res.exit_code == 1 and "Traceback" not in res.output and not out.exists()
    assert "error: stop 1 (Burnish): the pad surface came down" in res.output
