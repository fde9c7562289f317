"""brakeca's own reader of its netCDF files (``brakeca._netcdf.fast_load``) gives the Dataset
xarray gives, for every kind of run file and for a campaign's ``campaign.nc``; what it does not
mirror falls back to xarray."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from brakeca import _netcdf
from brakeca.presets import load_preset
from brakeca.results import load_netcdf, write_atomic
from brakeca.simulation import simulate

mirrored = pytest.mark.skipif(
    not _netcdf.usable(),
    reason="fast_load mirrors xarray 2026.9 and h5netcdf 1.8 only (others read through them)",
)


def assert_same_as_xarray(path: Path) -> None:
    """``fast_load(path)`` is xarray's Dataset of ``path``: identical, in the same order of
    variables, with attributes of the same types."""
    fast = _netcdf.fast_load(path)
    slow = xr.load_dataset(path, engine="h5netcdf")
    xr.testing.assert_identical(fast, slow)
    assert list(fast.variables) == list(slow.variables)
    assert list(fast.coords) == list(slow.coords)
    for name in slow.variables:
        assert list(fast[name].attrs) == list(slow[name].attrs), name
        for key, value in slow[name].attrs.items():
            assert type(fast[name].attrs[key]) is type(value), (name, key)
            assert np.asarray(fast[name].attrs[key]).dtype == np.asarray(value).dtype
        assert fast[name].dtype == slow[name].dtype, name
    assert list(fast.attrs) == list(slow.attrs)
    for key, value in slow.attrs.items():
        assert type(fast.attrs[key]) is type(value), key


@pytest.fixture(scope="module")
def small():
    return load_preset().with_updates(
        {"mesh.n_radial": 5, "mesh.n_angular": 100, "cycle.max_stops": 2}
    )


KINDS = {
    "plain": ({}, {}),
    "one stop": ({"cycle.max_stops": 1}, {}),
    "maps kept": ({}, {"maps_at": [1, 2]}),
    "fibre field, S = 1": ({"pad.fibre_model": "field", "S": 1}, {}),
}


@mirrored
@pytest.mark.parametrize("kind", list(KINDS))
def test_a_run_file_reads_as_xarray_reads_it(small, tmp_path, kind):
    updates, options = KINDS[kind]
    run = simulate(small.with_updates(updates), seed=3, **options)
    path = run.to_netcdf(tmp_path / "run.nc")
    assert_same_as_xarray(path)
    xr.testing.assert_identical(load_netcdf(path), run.dataset)


@mirrored
def test_a_trace_run_file_reads_as_xarray_reads_it(small, tmp_path):
    from brakeca.traces import with_cycle

    run = simulate(with_cycle(small, "example_trace"), seed=3)
    assert_same_as_xarray(run.to_netcdf(tmp_path / "trace.nc"))


def test_what_it_does_not_mirror_is_read_by_xarray(small, tmp_path, monkeypatch):
    """A variable xarray scales on reading (``scale_factor``) is refused, and load_netcdf
    reads the file through xarray instead; so is any file fast_load fails on."""
    ds = xr.Dataset({"a": ("x", np.arange(3.0))}, attrs={"title": "t"})
    scaled = tmp_path / "scaled.nc"
    ds.to_netcdf(scaled, engine="h5netcdf", encoding={"a": {"scale_factor": 0.5}})
    with pytest.raises(_netcdf.Unsupported, match="scale_factor"):
        _netcdf.fast_load(scaled)
    xr.testing.assert_identical(load_netcdf(scaled), xr.load_dataset(scaled, engine="h5netcdf"))
    run = simulate(small, seed=3)
    path = write_atomic(run.dataset, tmp_path / "run.nc")

    def broken(*args, **kwargs):
        raise RuntimeError("a reader that fails")

    monkeypatch.setattr(_netcdf, "fast_load", broken)
    xr.testing.assert_identical(load_netcdf(path), run.dataset)
    # too large a file: refused by the size check, with its message (xarray's path)
    monkeypatch.undo()
    with pytest.raises(ValueError, match=r"its variables hold .* GiB, more than a brakeca file"):
        load_netcdf(path, limit=1000)


@mirrored
def test_crafted_files_are_refused_not_read_otherwise(tmp_path):
    """A review of the reader: a dataset h5netcdf skips (marked not a variable) had been
    returned; an integer variable with a _FillValue, returned as floats, had been counted at
    its stored size (a 6 kB file declaring 200 MB of int8 came back as 800 MB of float32);
    text had been counted at 8 bytes a value, though xarray widens it to its longest."""
    import h5netcdf
    import h5py

    marked = tmp_path / "marked.nc"
    ds = xr.Dataset({"v": ("x", np.arange(3.0)), "w": ("x", np.ones(3))}, coords={"x": [1, 2, 3]})
    ds.to_netcdf(marked, engine="h5netcdf")
    with h5py.File(marked, "a") as f:
        f["w"].attrs["NAME"] = b"This is a netCDF dimension but not a netCDF variable."
    with pytest.raises(_netcdf.Unsupported, match="marked not a variable"):
        _netcdf.fast_load(marked)
    xr.testing.assert_identical(load_netcdf(marked), xr.load_dataset(marked, engine="h5netcdf"))
    declared = tmp_path / "declared.nc"
    with h5netcdf.File(declared, "w") as f:  # no chunk written: a few kB
        f.dimensions = {"x": 20_000_000}
        f.create_variable("v", ("x",), np.int8, chunks=(1_000_000,), fillvalue=np.int8(-1))
    assert declared.stat().st_size < 100_000
    with pytest.raises(_netcdf.Unsupported, match="its variables hold over 30000000 bytes"):
        _netcdf.fast_load(declared, limit=30_000_000)  # 20 MB stored, 80 MB as float32
    with pytest.raises(ValueError, match=r"declared.nc: its variables hold 0.1 GiB"):
        load_netcdf(declared, limit=30_000_000)
    text = np.array(["a"] * 2000, dtype=object)
    text[0] = "x" * 2000  # 2000 values of 2000 characters once widened: 16 MB
    wide = tmp_path / "wide.nc"
    xr.Dataset({"s": ("n", text)}).to_netcdf(wide, engine="h5netcdf")
    with pytest.raises(_netcdf.Unsupported, match="its variables hold over 1000000 bytes"):
        _netcdf.fast_load(wide, limit=1_000_000)
    with pytest.raises(ValueError, match=r"wide.nc: its variables hold"):
        load_netcdf(wide, limit=1_000_000)
