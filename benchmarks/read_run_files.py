"""Reading run files: xarray against brakeca's own reader of h5py alone, checked and timed.

    python benchmarks/read_run_files.py FOLDER_OR_FILE [...] [--rounds 5]

An analysis reads every run file of its campaign (``results.load_netcdf``), and that took most
of an analysis without figures: 0.13-0.25 s a full-resolution run file through xarray's
``open_dataset(engine="h5netcdf")`` and ``.load()``, almost all of it h5netcdf's and xarray's
handling of the file's metadata (about 1,300 h5py lookups of dimension scales a file), against
about 0.01 s for the file's arrays through h5py alone. ``brakeca._netcdf.fast_load`` (a
helper's prototype, fifty-fourth session) reads a netCDF4 file that brakeca wrote with h5py
directly into the Dataset xarray gives, and ``load_netcdf`` takes it where it mirrors the
installed xarray and h5netcdf (``_netcdf.usable()``).

For each file this prints whether the two readers' datasets are identical
(``xarray.testing.assert_identical``, and the same variable order and attribute types), or
that fast_load refuses it (the package then reads it through xarray), and then the median
time of each reader per file [ms] over ``--rounds`` rounds, of the files both read alike.
On the forty-seventh session's full-resolution study folder (24 run files and
``campaign.nc``): identical for every file, xarray 132 ms a file, ``fast_load`` 28 ms
(fifty-fourth session, two shared cores).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import xarray as xr

from brakeca._netcdf import Unsupported, fast_load


def _xarray_load(path: Path) -> xr.Dataset:
    """The dataset as xarray reads it (as results.load_netcdf does where fast_load does not
    apply, without its size check)."""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def _same(path: Path) -> str:
    """ "identical", or what differs between the two readers' datasets of ``path``."""
    try:
        fast = fast_load(path)
    except Unsupported as exc:
        return f"refused ({exc})"
    slow = _xarray_load(path)
    try:
        xr.testing.assert_identical(fast, slow)
    except AssertionError as exc:
        return "DIFFERENT: " + " ".join(str(exc).split())[:300]
    if list(fast.variables) != list(slow.variables):
        return "DIFFERENT: the variables' order"
    for name in slow.variables:
        for key, value in slow[name].attrs.items():
            if type(fast[name].attrs[key]) is not type(value):
                return f"DIFFERENT: the type of {name}'s attribute {key}"
    for key, value in slow.attrs.items():
        if type(fast.attrs[key]) is not type(value):
            return f"DIFFERENT: the type of the attribute {key}"
    return "identical"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="+", type=Path, help="netCDF files, or folders of them")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args(argv)
    files: list[Path] = []
    for path in args.paths:
        files += sorted(path.rglob("*.nc")) if path.is_dir() else [path]
    if not files:
        print("no netCDF file given", file=sys.stderr)
        return 2
    different = 0
    timed = []  # the files both read alike
    for path in files:
        try:
            said = _same(path)
        except Exception as exc:  # (xarray too cannot read it)
            said = f"unreadable ({type(exc).__name__}: {exc})"
        different += said.startswith("DIFFERENT")
        if said == "identical":
            timed.append(path)
        print(f"{path}: {said}")
    if not timed:
        return 1 if different else 0
    readers = {"xarray": _xarray_load, "fast_load": fast_load}
    times: dict[str, list[float]] = {name: [] for name in readers}
    for _ in range(args.rounds):
        for name, read in readers.items():
            start = time.perf_counter()
            for path in timed:
                read(path)
            times[name].append((time.perf_counter() - start) / len(timed) * 1e3)
    for name, values in times.items():
        print(f"{name}: {statistics.median(values):.1f} ms a file (median of {args.rounds} rounds)")
    return 1 if different else 0


if __name__ == "__main__":
    sys.exit(main())
