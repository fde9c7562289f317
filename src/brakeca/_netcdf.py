"""Reading a netCDF file brakeca wrote with h5py alone, into the Dataset xarray gives.

:func:`results.load_netcdf` reads every run file of an analysis; through xarray and h5netcdf a
full-resolution run file takes 0.13-0.25 s, almost all of it their handling of its metadata
(about 1,300 h5py lookups of dimension scales), against 0.03 s here
(``benchmarks/read_run_files.py`` measures both and checks them identical). :func:`fast_load`
mirrors how xarray 2026.9 and h5netcdf 1.8 decode such a file (the order of data variables and
coordinates, string coordinates as fixed-width unicode, ``_FillValue`` masking), so it is used
only with those versions (:func:`usable`; a test checks it identical to xarray's reading of
every kind of run file and of ``campaign.nc``), and it raises :class:`Unsupported` for
anything it does not mirror (groups, named types, unlimited dimensions, compressed variables,
CF attributes it does not decode...), where the caller reads the file with xarray. A helper's
prototype (fifty-fourth session), checked on the full-resolution study's files, small runs of
every kind and hand-made edge cases.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path
from typing import Any, cast

import h5py
import numpy as np
import xarray as xr

__all__ = ["Unsupported", "fast_load", "usable"]

#: The versions :func:`fast_load` mirrors: xarray's and h5netcdf's releases (major.minor)
_MIRRORED = {"xarray": ("2026.9",), "h5netcdf": ("1.8",)}


@functools.cache
def usable() -> bool:
    """Whether :func:`fast_load` mirrors the installed xarray and h5netcdf: releases of the
    versions it was checked on (not a development build after them); else a file is read
    through them."""
    import re
    from importlib.metadata import PackageNotFoundError, version

    try:
        found = {dist: version(dist) for dist in _MIRRORED}
    except PackageNotFoundError:
        return False
    return all(
        re.fullmatch(r"\d+\.\d+\.\d+", v) is not None
        and ".".join(v.split(".")[:2]) in _MIRRORED[dist]
        for dist, v in found.items()
    )


class Unsupported(ValueError):
    """The file has something fast_load does not mirror: read it with xarray instead."""


# the attributes h5netcdf hides (h5netcdf.attrs._HIDDEN_ATTRS)
_HIDDEN = frozenset(
    (
        "REFERENCE_LIST",
        "CLASS",
        "DIMENSION_LIST",
        "NAME",
        "_Netcdf4Dimid",
        "_Netcdf4Coordinates",
        "_nc3_strict",
        "_NCProperties",
    )
)
# attributes that make xarray's CF decoding do more than fast_load mirrors
_DECODED = frozenset(
    (
        "scale_factor",
        "add_offset",
        "missing_value",
        "_Unsigned",
        "dtype",
        "calendar",
        "_Encoding",
        "bounds",
    )
)
_TIME_UNITS = frozenset(
    ("days", "hours", "minutes", "seconds", "milliseconds", "microseconds", "nanoseconds")
)
_NOT_A_VARIABLE = b"This is a netCDF dimension but not a netCDF variable."
_NUMERIC = frozenset("iuf")
_FILTERS = {
    "zlib": False,
    "szip": False,
    "bzip2": False,
    "blosc": False,
    "zstd": False,
    "shuffle": False,
    "fletcher32": False,
}  # h5netcdf's filters() without any


def _attrs(obj: Any, names: list[str]) -> dict[str, Any]:
    """``obj``'s attributes ``names`` as h5netcdf's Attributes and then xarray's
    _read_attributes give them."""
    out = {}
    for key in names:
        value: Any = obj.attrs[key]
        if isinstance(value, h5py.Empty):
            raise Unsupported(f"empty attribute {key!r}")
        dtype: Any = getattr(value, "dtype", None)
        if not isinstance(value, str) and (
            dtype is None or dtype.kind not in "iufSO" or h5py.check_enum_dtype(dtype)
        ):
            raise Unsupported(f"attribute {key!r} of type {dtype}")
        if isinstance(value, str) or (dtype is not None and dtype.kind == "O"):
            # a variable-length string (h5py decodes those; other objects are refused)
            if not isinstance(value, str):
                if not all(isinstance(v, str) for v in value.flat):
                    raise Unsupported(f"attribute {key!r} of objects")
                value = value.tolist()
        elif dtype.kind == "S":  # fixed-length: h5netcdf decodes those longer than 1
            info = h5py.check_string_dtype(obj.attrs.get_id(key).dtype)
            if info is None:
                raise Unsupported(f"attribute {key!r}: bytes, not a string type")
            if info.length is not None and info.length > 1:
                if np.isscalar(value):
                    value = cast(Any, value).decode(info.encoding, "surrogateescape")
                else:
                    value = [b.decode(info.encoding, "surrogateescape") for b in value.flat]
            elif not np.isscalar(value):
                value = value.tolist()
        if not np.isscalar(value) and len(value) == 1:
            value = value[0]
        if isinstance(value, bytes) and key not in ("_FillValue", "missing_value"):
            try:
                value = value.decode("utf-8")
            except UnicodeDecodeError:
                raise Unsupported(f"attribute {key!r}: bytes, not UTF-8") from None
        out[key] = value
    return out


def _marked(name: Any) -> bool:
    """Whether a dataset's NAME attribute (bytes or text) marks it a dimension but not a
    variable, as h5netcdf reads it."""
    if isinstance(name, bytes | np.bytes_):
        return _NOT_A_VARIABLE in bytes(name)
    return isinstance(name, str) and _NOT_A_VARIABLE.decode() in name


def fast_load(path: str | Path, limit: int | None = None) -> xr.Dataset:
    """The dataset ``xr.load_dataset(path, engine="h5netcdf")`` reads from the netCDF4 file
    ``path``; raises Unsupported (or h5py's error) where the file has what this does not
    mirror, and where its numbers would hold more than ``limit`` bytes."""
    source = os.path.abspath(os.fspath(path))
    with h5py.File(source, "r") as f:
        if "_nc3_strict" in f.attrs:
            raise Unsupported("NETCDF4_CLASSIC file")
        objects, dim_ids, sizes = {}, {}, {}
        for name, obj in f.items():
            if not isinstance(obj, h5py.Dataset):
                raise Unsupported(f"{name!r} is a {type(obj).__name__}, not a variable")
            if "_nc4_non_coord_" in name or obj.shape is None:
                raise Unsupported(f"variable {name!r}")
            names = list(obj.attrs)
            is_scale = "CLASS" in names and obj.attrs["CLASS"] == b"DIMENSION_SCALE"
            marked = "NAME" in names and _marked(obj.attrs["NAME"])
            if is_scale:
                if "_Netcdf4Dimid" not in names or obj.ndim != 1 or obj.maxshape != obj.shape:
                    raise Unsupported(f"dimension {name!r} (unlimited or without an id)")
                dim_id = int(obj.attrs["_Netcdf4Dimid"])
                if dim_id in dim_ids:
                    raise Unsupported(f"dimension id {dim_id} twice")
                dim_ids[dim_id], sizes[name] = name, obj.shape[0]
                if marked:
                    continue
            elif marked:  # (h5netcdf skips any such dataset: a review found it returned here)
                raise Unsupported(f"{name!r}: marked not a variable, but no dimension")
            objects[name] = (obj, names, is_scale)
        raw = {}
        for name, (obj, names, is_scale) in objects.items():
            dtype = obj.dtype
            if dtype.kind in _NUMERIC and dtype.isnative and not h5py.check_enum_dtype(dtype):
                is_string = False
            elif h5py.check_vlen_dtype(dtype) is str:
                is_string = True
            else:
                raise Unsupported(f"variable {name!r} of type {dtype}")
            # its dimensions as h5netcdf's BaseVariable._lookup_dimensions finds them
            if "_Netcdf4Coordinates" in names and is_scale:
                try:
                    dims = tuple(dim_ids[int(i)] for i in obj.attrs["_Netcdf4Coordinates"])
                except KeyError:
                    raise Unsupported(f"{name!r}: an unknown dimension id") from None
            elif "DIMENSION_LIST" in names:
                refs = obj.attrs["DIMENSION_LIST"]
                if len(refs) != obj.ndim or obj.ndim == 0 or any(len(r) == 0 for r in refs):
                    raise Unsupported(f"{name!r}: a dimension without a scale")
                dims = tuple(f[r[-1]].name for r in refs)
                if any(d[:1] != "/" or d[1:] not in sizes for d in dims):
                    raise Unsupported(f"{name!r}: a dimension scale that is not a dimension")
                dims = tuple(d[1:] for d in dims)
            elif name in sizes:
                dims = (name,)
            elif obj.ndim == 0:
                dims = ()
            else:
                raise Unsupported(f"{name!r}: a dimension without a scale")
            if obj.shape != tuple(sizes[d] for d in dims):
                raise Unsupported(f"{name!r}: shape {obj.shape}, dimensions {dims}")
            attrs = _attrs(obj, [k for k in names if k not in _HIDDEN])
            # every refusal before any data is read (a review: a late one wasted the reads)
            if obj.id.get_create_plist().get_nfilters():
                raise Unsupported(f"{name!r}: compressed or filtered")
            if _DECODED & attrs.keys():
                raise Unsupported(f"{name!r}: attributes {sorted(_DECODED & attrs.keys())}")
            units = attrs.get("units")
            if isinstance(units, str) and "since" in units:
                raise Unsupported(f"{name!r}: a time variable")
            if "_FillValue" in attrs:
                values = np.ravel(attrs["_FillValue"])
                if is_string or values.size != 1 or values.dtype.kind not in _NUMERIC:
                    raise Unsupported(f"{name!r}: _FillValue {attrs['_FillValue']!r}")
                if np.isnan(values[0]) and dtype.kind != "f":
                    raise Unsupported(f"{name!r}: NaN _FillValue of an integer")
                if not np.isnan(values[0]) and units in _TIME_UNITS:
                    raise Unsupported(f"{name!r}: _FillValue of a time-like variable")
            if not isinstance(attrs.get("coordinates", ""), str):
                raise Unsupported(f"{name!r}: coordinates {attrs['coordinates']!r}")
            raw[name] = (obj, dims, attrs, is_string)
        texts: dict[str, np.ndarray] = {}  # the text variables' values, once read
        if limit is not None:
            # at most 8 bytes a number as returned (an integer with a _FillValue comes back as
            # floats: counted as stored, a review found 4 times the limit let through); text,
            # from its longest value, before it is widened (xarray's fixed-width unicode)
            size = 0
            for name, (obj, _, _, is_string) in raw.items():
                if is_string:  # (read once: kept for the Dataset)
                    texts[name] = np.asarray(obj.asstr()[()], dtype=object)
                    longest = max((len(t) for t in texts[name].flat), default=1)
                    size += obj.size * 4 * max(longest, 1)
                else:
                    size += obj.size * 8
                if size > limit:
                    raise Unsupported(f"its variables hold over {limit} bytes")
        global_attrs = _attrs(f, [k for k in f.attrs if k not in _HIDDEN])

        variables: dict[str, xr.Variable] = {}
        coord_names: set[str] = set()
        for name, (obj, dims, attrs, is_string) in raw.items():
            encoding = {
                "dtype": obj.dtype,
                "contiguous": obj.chunks is None,
                "chunksizes": obj.chunks,
            }
            if obj.chunks is not None:
                encoding["preferred_chunks"] = dict(zip(dims, obj.chunks, strict=True))
            encoding.update(_FILTERS, source=source, original_shape=obj.shape)
            if is_string:  # xarray's ObjectVLenStringCoder: fixed-width str, dtype too
                if name not in texts:
                    texts[name] = np.asarray(obj.asstr()[()], dtype=object)
                data = texts[name].astype(str)
                encoding = {"dtype": data.dtype}  # (astype dropped the rest)
            else:
                data = np.asarray(obj[()])
            if "_FillValue" in attrs:  # xarray's CFMaskCoder
                fill = attrs.pop("_FillValue")  # (checked above)
                values = np.ravel(fill)
                encoding["_FillValue"] = fill
                if not np.isnan(values[0]):
                    to = (
                        data.dtype
                        if data.dtype.kind == "f"
                        else (np.float32 if data.dtype.itemsize <= 2 else np.float64)
                    )
                    data = np.array(data, dtype=to, copy=True)
                    data[data == values[0]] = np.nan
            if "coordinates" in attrs:  # (a string: checked above)
                text = attrs.pop("coordinates")
                encoding["coordinates"] = text
                coord_names.update(c for c in text.split() if c in raw)
            variables[name] = xr.Variable(dims, data, attrs, encoding)
    if isinstance(global_attrs.get("coordinates"), str):
        coord_names.update(global_attrs.pop("coordinates").split())
    # as xarray's StoreBackendEntrypoint: the data variables, then the coordinates, each in
    # the file's order (its default indexes made alike)
    coords = {k: v for k, v in variables.items() if k in coord_names or v.dims == (k,)}
    data_vars = {k: v for k, v in variables.items() if k not in coords}
    ds = xr.Dataset(data_vars, coords=coords, attrs=global_attrs)
    ds.encoding = {"unlimited_dims": set(), "source": source}
    return ds
