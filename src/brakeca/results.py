"""Run results: an xarray Dataset with provenance, saved to and loaded from netCDF.

Per stop (dim ``stop``): ``mean_cof`` (time-weighted mean global COF) [-], ``emitted_volume``
[m^3], ``generated_volume`` [m^3], ``primary_area_fraction`` and ``secondary_area_fraction``
(time-weighted) [-], ``contact_area_fraction`` [-], ``normal_force`` (pad) [N],
``band_normal_force`` [N], ``line_pressure`` [Pa], ``duration`` [s], ``n_steps``,
``secondary_removed_between_stops`` [-] (cells, rule S), ``end_of_stop_emitted_volume`` [m^3]
(the flush and the deposits S removes), ``min_disc_position`` [m], ``held_volume`` and
``stream_volume`` [m^3] (in the secondary plateaus and in the streams at the stop's last step:
the sum of ``generated_volume`` up to a stop is its ``held_volume`` + ``stream_volume`` + the
sum of ``emitted_volume`` less its own ``end_of_stop_emitted_volume``, the volume ledger),
``stop_max_ledger_residual`` and ``stop_max_friction_residual`` [-] (the stop's largest, over
its steps),
``rule_firings(stop, rule)`` [-]; with the fibre field (``pad.fibre_model = "field"``) also
``fibre_cells_exposed`` [-], of those ``fibre_cells_exposed_late`` [-] (only after the stop),
``fibre_exposure_lag`` [m] and ``fibre_volume_cut_as_resin`` [m^3], ``fibre_intervals_skipped``
[-]. Every variable carries its ``units`` and ``long_name`` attributes.

Scalars: ``MU`` [-], ``V`` [m^3 per stop], ``max_ledger_residual`` [-],
``max_friction_residual`` [-] (:data:`RUN_SCALAR_UNITS`). A thinned per-step series on dim
``step`` (every ``output.series_every``-th step): ``step_time`` [s] (the run's braking time at
the step's end, summed over its stops), ``step_stop`` [-], ``step_cof`` [-],
``step_normal_force`` (pad) [N], ``step_contact_area_fraction``, ``step_primary_area_fraction``,
``step_secondary_area_fraction`` [-], ``step_disc_position`` [m]. Maps on (``radius`` [m],
``angle`` [rad]): ``initial_status``, ``final_status`` (0 resin, 1 primary, 2 secondary
plateau), ``final_height`` [m], and where rule S removed secondary plateaus after the last
stop ``final_status_before_s`` (the statuses at the end of the last stop, before it);
where the run was asked to keep them (``simulate(maps_at=)``,
``brakeca simulate --maps-at``), ``map_status`` [-] and ``map_height`` [m] after those stops,
along ``map_stop`` [-]. Attributes: the resolved config (TOML), seed, package version, the
kernels' sources (``source_key``, :func:`brakeca._cachedir.source_key`: the version alone does
not change with every commit), the Python, numpy and numba versions and platform
(``software``), when the run was made (``date_created``, UTC), wall time [s], the simulated
band's area ``band_area`` [m^2], the step kernel setting (``exact``, ``lazy``, or ``auto``:
lazy where it applies, docs/model.md section 13), how many stops each kernel ran
(``stops_lazy``, ``stops_exact``) and how many of the lazy kernel's contact solves fell back to
the exact scan, ``paper_factors`` (the paper's S, WP, WR and A as the run has them, in their
units) and a ``comment`` that explains ``quick``, ``max_stops`` and ``n_steps_total``; a run on
a speed trace also ``distance`` [m] (the trace's distance its events belong to) and
``pm10_mg_km``, ``pm10_mg_km_low``, ``pm10_mg_km_high`` [mg/km]
(:func:`brakeca.emissions.pm10_from_run`, the default factors; ``brakeca simulate --emissions
FILE`` records its own, named in ``pm10_factors``); the ``rule`` coordinate's
``rule_meanings`` names the seven plateau rules (:data:`RULE_ATTRS`).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 3.
"""

from __future__ import annotations

import contextlib
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from brakeca import __version__
from brakeca import _records as R  # the record columns (without numba)
from brakeca._cachedir import source_key
from brakeca._io import atomic_write, rng_state_from_json
from brakeca.config import SimulationConfig

__all__ = [
    "FORMAT",
    "RUN_SCALARS",
    "RUN_SCALAR_UNITS",
    "RunResult",
    "build_dataset",
    "summarise_stop",
]

FORMAT = "brakeca-run/1"  #: format marker written to and checked in every run file
M3_TO_MM3 = 1e9


#: The per-stop variables of a run file: name -> (unit, description).
STOP_VARIABLES: dict[str, tuple[str, str]] = {
    "mean_cof": ("1", "time-weighted mean global COF of the stop"),
    "emitted_volume": ("m3", "wear volume that left the band during the stop and after it"),
    "generated_volume": ("m3", "pad material removed (primary plateau + resin wear)"),
    "primary_area_fraction": ("1", "time-weighted primary plateau area / band area"),
    "secondary_area_fraction": ("1", "time-weighted secondary plateau area / band area"),
    "contact_area_fraction": ("1", "time-weighted area in contact / band area"),
    "band_normal_force": ("N", "time-weighted normal force on the simulated band"),
    "normal_force": ("N", "time-weighted pad normal force, band force * A_pad / A_sim"),
    "line_pressure": ("Pa", "hydraulic pressure, pad normal force / piston area"),
    "duration": ("s", "duration of the stop"),
    "n_steps": ("1", "time steps in the stop"),
    # the stop's own maxima; the run's (max_*_residual) are scalars of the same names
    # without stop_ (these had been written under those names and then overwritten by the
    # scalars, so no file held them: an API review)
    "stop_max_friction_residual": (
        "1",
        "max |F_friction / F_demanded - 1| over the stop's steps",
    ),
    "stop_max_ledger_residual": ("1", "max relative volume-ledger residual over the stop's steps"),
    "secondary_removed_between_stops": (
        "1",
        "secondary plateau cells removed by rule S after the stop",
    ),
    "end_of_stop_emitted_volume": (
        "m3",
        "particles flushed (none with the streams carried) and deposits removed by S",
    ),
    "min_disc_position": ("m", "lowest disc surface position z in the stop"),
    "held_volume": (
        "m3",
        "volume held in secondary plateaus at the stop's last step, before rule S",
    ),
    "stream_volume": (
        "m3",
        "particle volume in the streams at the stop's last step, before the stop's end",
    ),
}

#: The per-stop counters of a run with the fibre field: name -> (unit, description).
FIBRE_VARIABLES: dict[str, tuple[str, str]] = {
    "fibre_cells_exposed": (
        "1",
        "cells whose wear reached a buried fibre, which became primary plateaus",
    ),
    "fibre_cells_exposed_late": (
        "1",
        "of those, the cells exposed only after the stop (inside a fibre at its end)",
    ),
    "fibre_exposure_lag": (
        "m",
        "largest depth a cell exposed after the stop was below its fibre's top",
    ),
    "fibre_volume_cut_as_resin": (
        "m3",
        "fibre above the cells exposed after the stop, worn as resin or by Archard",
    ),
    "fibre_intervals_skipped": (
        "1",
        "buried fibres the pad surface passed wholly within the stop, never exposed",
    ),
}

#: The per-run scalars of :meth:`RunResult.scalars`: columns of a campaign's summary.
RUN_SCALARS: tuple[str, ...] = (
    "MU",
    "MU_SD",
    "V",
    "V_mm3",
    "total_emitted_mm3",
    "total_generated_mm3",
    "final_primary_area_fraction",
    "final_secondary_area_fraction",
    "max_ledger_residual",
    "max_friction_residual",
    "n_steps",
    "wall_time",
)

#: The per-run scalars: name -> (unit, description); a run file's MU, V and residuals and a
#: campaign's dataset carry them as ``units`` and ``long_name``.
RUN_SCALAR_UNITS: dict[str, tuple[str, str]] = {
    "MU": ("1", "mean over the stops of the per-stop mean COF"),
    "MU_SD": ("1", "standard deviation over the stops of the per-stop mean COF"),
    "V": ("m3", "mean emitted wear volume per stop"),
    "V_mm3": ("mm3", "mean emitted wear volume per stop"),
    "total_emitted_mm3": ("mm3", "wear volume emitted over the run"),
    "total_generated_mm3": ("mm3", "wear volume generated over the run"),
    "final_primary_area_fraction": ("1", "primary plateau area fraction in the last stop"),
    "final_secondary_area_fraction": ("1", "secondary plateau area fraction in the last stop"),
    "max_ledger_residual": ("1", "max relative volume-ledger residual of the run"),
    "max_friction_residual": ("1", "max |F_friction / F_demanded - 1| over the run's steps"),
    "n_steps": ("1", "time steps of the run"),
    "wall_time": ("s", "wall time of the run"),
}


def software_versions() -> str:
    """The Python, numpy and numba versions and the platform a run is made with, as a run
    file records them (``software``): ``"Python 3.11.7, numpy 2.4.6, numba 0.68.1, Linux
    x86_64"``."""
    import platform

    return (
        f"Python {platform.python_version()}, {library_versions('numpy', 'numba')}, "
        f"{platform.system()} {platform.machine()}"
    )


def library_versions(*dists: str) -> str:
    """The installed versions of the distributions ``dists``: ``"numpy 2.4.6, numba
    0.68.1"`` (``unknown`` for one without its metadata)."""
    from importlib.metadata import PackageNotFoundError, version

    parts = []
    for dist in dists:
        try:
            parts.append(f"{dist} {version(dist)}")
        except PackageNotFoundError:  # (a build without its metadata)
            parts.append(f"{dist} unknown")
    return ", ".join(parts)


def scalar_attrs(name: str) -> dict[str, str]:
    """``units`` and ``long_name`` of the run scalar ``name`` (:data:`RUN_SCALAR_UNITS`);
    empty for another name."""
    if name not in RUN_SCALAR_UNITS:
        return {}
    unit, description = RUN_SCALAR_UNITS[name]
    return {"units": unit, "long_name": description}


def paper_factor_levels(config: SimulationConfig) -> dict[str, float]:
    """The paper's factors S, WP, WR and A as ``config`` sets them, by name, in their units
    (:data:`brakeca.config.FACTOR_ALIASES`: A in %)."""
    import operator

    from brakeca.config import FACTOR_ALIASES

    return {
        name: float(operator.attrgetter(field)(config)) / scale
        for name, (field, scale, _) in FACTOR_ALIASES.items()
    }


def _paper_factors(config: SimulationConfig) -> str:
    """The paper's factors S, WP, WR and A as ``config`` sets them, in their units (A in %):
    ``"S = 0, WP = 1e-13 m^3/(N m), WR = 1e-06 m, A = 20 %"``, a run file's attribute."""
    from brakeca.config import FACTOR_ALIASES

    return ", ".join(
        f"{name} = {level:g}"
        + ("" if FACTOR_ALIASES[name][2] == "-" else f" {FACTOR_ALIASES[name][2]}")
        for name, level in paper_factor_levels(config).items()
    )


#: The status maps' ``flag_values`` (CF: of the variable's type, int8).
_FLAG_VALUES = np.array([0, 1, 2], dtype=np.int8)

#: Attributes of a run file's ``rule`` coordinate: the seven plateau rules of the paper's
#: Section 2 (docs/model.md section 7 gives how each is read).
RULE_ATTRS: dict[str, str] = {
    "units": "1",
    "long_name": "plateau rule of the cellular automaton",
    "rule_meanings": (
        "1-3: a cell with a plateau directly east (1), and one (2) or both (3) eastern "
        "diagonals, becomes a secondary plateau; 4: a secondary plateau without a plateau "
        "directly east is removed; 5: a secondary plateau whose deposit is worn through is "
        "removed; 6: a primary plateau out of the disc's reach (off by default); 7: a fibre "
        "worn through (never with fibres as columns)"
    ),
}

#: Names a campaign's summary and dataset use besides the run scalars and the per-stop
#: variables: the log scale of V and the per-stop rule counts.
OTHER_RESULT_NAMES: tuple[str, ...] = ("log10_V_mm3", "rule_firings")


def result_names() -> frozenset[str]:
    """Every name a run's results take in a campaign's summary or dataset (a factor may not
    take one: its column would be overwritten), the PM10 columns of a trace cycle's
    report included."""
    from brakeca.emissions import PM10_COLUMNS

    return (
        frozenset(STOP_VARIABLES)
        | frozenset(FIBRE_VARIABLES)
        | frozenset(RUN_SCALARS)
        | frozenset(OTHER_RESULT_NAMES)
        | frozenset(PM10_COLUMNS)
    )


#: numpy's bit generators, which a run file's ``rng_state`` may name
_BIT_GENERATORS = ("PCG64", "PCG64DXSM", "MT19937", "Philox", "SFC64")


@dataclass(frozen=True, eq=False)
class RunResult:
    """The result of one simulated run.

    Two results are equal only where they are the same object (``==`` is ``is``): a
    dataclass's ``==`` would compare the datasets' truth values, true for any with a
    variable (an API review); compare runs with ``a.dataset.identical(b.dataset)``.

    Attributes
    ----------
    config : SimulationConfig
        The resolved configuration.
    seed : int
        Seed of the run's generator (-1 if a generator was passed in; its starting state is
        then the dataset's ``rng_state`` attribute, and :meth:`generator` rebuilds it).
    dataset : xarray.Dataset
        Everything the run produced (see the module docstring).
    """

    config: SimulationConfig
    seed: int
    dataset: xr.Dataset

    def __repr__(self) -> str:
        """One line: seed, stops, grid, MU, MU_SD (over two stops or more) and V (``config``
        and ``dataset`` hold the rest)."""
        ds = self.dataset
        grid = f"{ds.sizes.get('radius', 0)} x {ds.sizes.get('angle', 0)} cells"
        quick = " (quick)" if self.config.quick else ""
        stops = ds.sizes.get("stop", 0)
        return (
            f"RunResult(seed={self.seed}, {stops} stop{'' if stops == 1 else 's'}, {grid}{quick}, "
            f"MU={self.MU:.4f}, "
            + (f"MU_SD={self.MU_SD:.3g}, " if stops > 1 else "")
            + f"V={self.V * M3_TO_MM3:.4g} mm³ per stop)"
        )

    def generator(self) -> np.random.Generator:
        """A new generator in the state this run drew its first number from: of its seed,
        or for a run given a generator (seed -1), of the state it recorded (``rng_state``).

        Raises
        ------
        ValueError
            A run of seed -1 without ``rng_state`` (a run file of an earlier version).

        Examples
        --------
        >>> import numpy as np
        >>> from brakeca.presets import load_preset
        >>> from brakeca.simulation import simulate
        >>> config = load_preset().with_updates({"mesh.n_radial": 3, "cycle.max_stops": 1})
        >>> run = simulate(config, rng=np.random.default_rng(7))
        >>> run.seed, simulate(config, rng=run.generator()).MU == run.MU
        (-1, True)
        """
        if self.seed >= 0:
            return np.random.default_rng(self.seed)
        state = self.dataset.attrs.get("rng_state")
        if state is None:
            raise ValueError(
                "this run was given a generator (seed -1) and its file does not record the "
                "generator's state (rng_state): it was written by an earlier brakeca"
            )
        state = rng_state_from_json(state)
        name = state.get("bit_generator")
        if name not in _BIT_GENERATORS:  # a name from a file: only a bit generator's is called
            raise ValueError(
                f"this run's file records a generator state of {name!r}, not one of numpy's "
                f"bit generators ({', '.join(_BIT_GENERATORS)})"
            )
        bit_generator = getattr(np.random, name)()
        bit_generator.state = state
        return np.random.Generator(bit_generator)

    @property
    def MU(self) -> float:
        """Mean over the stops of the per-stop mean COF [-]."""
        return float(self.dataset["MU"])

    @property
    def MU_SD(self) -> float:
        """Friction stability: the standard deviation over the stops of the per-stop mean
        COF [-] (over the stops as a whole population, ``ddof=0``; 0 for a single stop). It
        is not the paper's: the paper reports MU and V only."""
        return float(np.std(np.asarray(self.dataset["mean_cof"], dtype=float)))

    @property
    def V(self) -> float:
        """Mean wear volume leaving the contact of the band, per stop [m^3]."""
        return float(self.dataset["V"])

    def scalars(self) -> dict[str, float]:
        """Per-run scalars for a summary table.

        Returns
        -------
        dict
            :data:`RUN_SCALARS` by name, in the units of :data:`RUN_SCALAR_UNITS`: ``MU`` and
            ``MU_SD`` [-], ``V`` [m^3 per stop], ``V_mm3`` [mm^3 per stop],
            ``total_emitted_mm3`` and ``total_generated_mm3`` [mm^3], the final area
            fractions [-], the residuals [-], ``n_steps`` [-] and ``wall_time`` [s].
        """
        ds = self.dataset
        return {
            "MU": self.MU,
            "MU_SD": self.MU_SD,
            "V": self.V,
            "V_mm3": self.V * M3_TO_MM3,
            "total_emitted_mm3": float(ds["emitted_volume"].sum()) * M3_TO_MM3,
            "total_generated_mm3": float(ds["generated_volume"].sum()) * M3_TO_MM3,
            "final_primary_area_fraction": float(ds["primary_area_fraction"][-1]),
            "final_secondary_area_fraction": float(ds["secondary_area_fraction"][-1]),
            "max_ledger_residual": float(ds["max_ledger_residual"]),
            "max_friction_residual": float(ds["max_friction_residual"]),
            "n_steps": int(ds["n_steps"].sum()),
            "wall_time": float(ds.attrs["wall_time"]),
        }

    def per_stop(self) -> pd.DataFrame:
        """The run's per-stop results as a table, one row per stop, in friendly units:
        :func:`brakeca.study.per_stop_table` of this run (``dataset.to_dataframe()`` would
        broadcast the per-stop variables over every cell of the band).

        Returns
        -------
        pandas.DataFrame
            ``seed``, ``stop``, ``block`` (when the cycle names its blocks), ``mean_cof``
            [-], ``emitted_mm3`` and ``generated_mm3`` [mm³], the time-weighted area
            fractions [-], ``normal_force_N`` [N], ``line_pressure_MPa`` [MPa],
            ``duration_s`` [s] and ``n_steps`` [-].
        """
        from brakeca.study import per_stop_table

        return per_stop_table(self)

    def to_netcdf(self, path: str | Path) -> Path:
        """Write the result to ``path`` atomically (temporary file, then rename)."""
        return write_atomic(self.dataset, path)

    @classmethod
    def from_netcdf(cls, path: str | Path) -> RunResult:
        """Load a run file; raises ``FileNotFoundError`` for a missing file and
        ``ValueError`` for a file that is not a brakeca run."""
        path = Path(path)
        if not path.exists():
            raise FileNotFoundError(f"{path}: no such file")
        ds = load_netcdf(path)
        if ds.attrs.get("format") != FORMAT:
            found = ds.attrs.get("format")
            raise ValueError(
                f"{path}: not a brakeca run file ("
                + (
                    f"format {found!r}, not {FORMAT!r}"
                    if found is not None
                    else f"a netCDF file without brakeca's format attribute {FORMAT!r}"
                )
                + ")"
            )
        try:
            config = SimulationConfig.from_toml(ds.attrs["config"], source=f"{path} [config]")
            seed = int(ds.attrs["seed"])
        except Exception as exc:
            raise ValueError(f"{path}: run file with a broken config attribute ({exc})") from None
        problem = run_problem(ds, config)
        if problem is not None:
            raise ValueError(f"{path}: not a run file brakeca wrote ({problem})")
        return cls(config=config, seed=seed, dataset=ds)


#: The variables of a run file that its readers use (:meth:`RunResult.scalars`, a
#: campaign's summary and its analysis's maps): a file without one is not a run's
_READ = (
    "MU",
    "V",
    "mean_cof",
    "emitted_volume",
    "generated_volume",
    "primary_area_fraction",
    "secondary_area_fraction",
    "n_steps",
    "max_ledger_residual",
    "max_friction_residual",
    "initial_status",
    "final_status",
)

#: The status maps of a run file, each on (``radius``, ``angle``); ``map_status`` on
#: (``map_stop``, ``radius``, ``angle``)
_STATUS_MAPS = ("initial_status", "final_status", "final_status_before_s")


def run_problem(ds: xr.Dataset, config: SimulationConfig) -> str | None:
    """Why ``ds`` is not a run's dataset of ``config`` as brakeca writes one (None when it
    is): the variables every reader uses present, each on its dimensions and of a number
    type, the maps of the configuration's grid, statuses 0, 1 or 2, MU, V and the per-stop
    COF and volumes finite (a security review: a run file of other shapes or statuses had
    ended ``plot``, ``analyze`` and a resume with a traceback, and one of MU = NaN was reused
    by a resume into summary.csv)."""
    for name in _READ:
        if name not in ds:
            return f"it lacks {name!r}"
    try:
        float(ds.attrs["wall_time"])
    except (KeyError, TypeError, ValueError):
        return "its wall_time attribute is not a number"
    n_stops = ds.sizes.get("stop", 0)
    if n_stops < 1:
        return "it has no stop"
    grid = (config.mesh.n_radial, config.mesh.n_angular)
    found = (ds.sizes.get("radius", 0), ds.sizes.get("angle", 0))
    if found != grid:
        return (
            f"its maps are {found[0]} x {found[1]} cells, its configuration's grid "
            f"{grid[0]} x {grid[1]}"
        )
    expected: dict[str, tuple[str, ...]] = {"MU": (), "V": ()}
    expected.update({name: ("stop",) for name in (*STOP_VARIABLES, *FIBRE_VARIABLES)})
    expected.update({name: ("radius", "angle") for name in (*_STATUS_MAPS, "final_height")})
    expected.update(
        {
            "rule_firings": ("stop", "rule"),
            "map_status": ("map_stop", "radius", "angle"),
            "map_height": ("map_stop", "radius", "angle"),
            "max_ledger_residual": (),
            "max_friction_residual": (),
        }
    )
    for name, dims in expected.items():
        if name not in ds:
            continue
        var = ds[name]
        if var.dims != dims:
            return f"{name!r} is on ({', '.join(map(str, var.dims))}), not ({', '.join(dims)})"
        if var.dtype.kind not in "iuf" or var.dtype.itemsize > 8:
            return f"{name!r} is of type {var.dtype}, not a number"
    for name in (*_STATUS_MAPS, "map_status"):
        if name in ds:
            values = np.asarray(ds[name])
            if values.dtype.kind == "f":
                return f"{name!r} is of type {values.dtype}, not whole numbers"
            if not np.isin(values, (0, 1, 2)).all():
                return f"{name!r} holds statuses other than 0, 1 and 2"
    for name in ("MU", "V", "mean_cof", "emitted_volume"):
        if not np.isfinite(np.asarray(ds[name], dtype=float)).all():
            return f"{name!r} is not finite"
    if "rule" in ds.dims and ds.sizes["rule"] != 7:
        return f"it has {ds.sizes['rule']} plateau rules, not 7"
    return None


#: The most bytes a run file or ``campaign.nc`` may hold once read [B]: a full-resolution
#: run with its maps after all 170 stops holds about 0.3 GB
MAX_NETCDF_BYTES = 4 << 30


def load_netcdf(path: str | Path, limit: int = MAX_NETCDF_BYTES) -> xr.Dataset:
    """Read the netCDF file ``path`` whole, once its variables' sizes are known to hold
    ``limit`` bytes or fewer [B] (a security review: a file of 100 kB declaring a variable
    of gigabytes took a process to 6.8 GB before anything was checked); raises ValueError
    naming the file otherwise, or where it is not a readable netCDF file."""
    from brakeca import _netcdf

    if _netcdf.usable():  # the same Dataset, about five times faster (its module docstring)
        try:
            return _netcdf.fast_load(path, limit)
        except MemoryError:
            raise
        except Exception:  # what it does not mirror, a file too large or not HDF5: xarray's
            pass  # reading, and its error
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            size = sum(int(v.nbytes) for v in ds.variables.values())
            if size <= limit:
                return ds.load()
    except Exception as exc:
        raise ValueError(f"{path}: not a readable netCDF file ({exc})") from None
    raise ValueError(
        f"{path}: its variables hold {size / 2**30:.1f} GiB, more than a brakeca file does "
        f"({limit / 2**30:.0f} GiB at most)"
    )


def write_atomic(dataset: xr.Dataset, path: str | Path) -> Path:
    """Write a Dataset to netCDF atomically: a temporary file in the same folder, then rename.

    The file is made in memory and then written as bytes, so that a full disk is an
    ``OSError`` the caller can report (writing through HDF5 to a full disk crashed the process
    with a segmentation fault inside h5py, a robustness review found). A run file is a few MB
    at full resolution.
    """
    # a coordinate variable holds no missing values (CF 2.5.1), so it gets no _FillValue,
    # which xarray gives every float variable (NaN) and CF checkers flag: an API review
    encoding = {
        name: {"_FillValue": None}
        for name in dataset.dims
        if name in dataset.coords and dataset[name].dtype.kind == "f"
    }
    with _without_a_dask_client():
        data = dataset.to_netcdf(engine="h5netcdf", encoding=encoding)
    return atomic_write(path, lambda tmp: tmp.write_bytes(data))


@contextlib.contextmanager
def _without_a_dask_client() -> Iterator[None]:
    """A context in which xarray writes with a thread lock even where a
    ``dask.distributed.Client`` is the process's default (a notebook or a SLURM script that
    opened one): xarray then asked the scheduler for a lock named after the in-memory file,
    which failed, so every run of a campaign was computed and then recorded as failed (a
    cluster review). Nothing to do where dask was never imported.

    dask's configuration is the process's, so for the write's duration (milliseconds to a
    second) another thread's dask work runs in that thread; the writes of several threads
    take turns (:data:`_DASK_CONFIG_LOCK`), so that none restores another's setting."""
    dask = sys.modules.get("dask")
    if dask is None or not hasattr(dask, "config"):
        yield
        return
    with _DASK_CONFIG_LOCK, dask.config.set(scheduler="synchronous"):
        yield


#: Held while a write sets dask's scheduler (:func:`_without_a_dask_client`).
_DASK_CONFIG_LOCK = threading.Lock()


# the per-stop reductions of a stop's per-step records that a run file needs (the columns of
# :func:`summarise_stop`'s first result): time-weighted means, sums, extremes
SUM_COF = 0  # time-weighted mean COF [-]
SUM_NORMAL = 1  # time-weighted band normal force [N]
SUM_PRIMARY_AREA = 2  # time-weighted areas [m^2]
SUM_SECONDARY_AREA = 3
SUM_CONTACT_AREA = 4
SUM_EMITTED = 5  # volume emitted during the stop's steps [m^3]
SUM_GENERATED = 6  # volume generated [m^3]
SUM_LEDGER = 7  # largest relative ledger residual [-]
SUM_DISC = 8  # lowest disc position [m]
SUM_FRICTION_RESIDUAL = 9  # largest |F / F_demanded - 1| [-]
SUM_HELD = 10  # volume held in secondary plateaus at the stop's last step [m^3]
SUM_STREAM = 11  # volume in the particle streams at the stop's last step [m^3]
N_SUM = 12


def summarise_stop(
    rec: np.ndarray, dt: np.ndarray, start: int, every: int
) -> tuple[np.ndarray, np.ndarray]:
    """What a run file keeps of one stop's per-step records ``rec`` (steps x ``R.N_REC``),
    so that a run need not hold every step's record to its end (51 MB at full resolution).

    Parameters
    ----------
    rec, dt
        The stop's per-step records and step durations [s].
    start
        Steps of the run before this stop [-].
    every
        ``output.series_every``: the per-step series keeps the run's steps 0, every, 2 every...

    Returns
    -------
    summary, kept
        The reductions (``N_SUM`` values, indexed by the ``SUM_*`` constants) and the records
        of the stop's kept steps (copies).
    """
    total = np.sum(dt)

    def tw(col: int) -> float:  # time-weighted mean of a record column over the stop
        return float(np.sum(rec[:, col] * dt) / total)

    summary = np.empty(N_SUM)
    summary[SUM_COF] = tw(R.R_COF)
    summary[SUM_NORMAL] = tw(R.R_NORMAL)
    summary[SUM_PRIMARY_AREA] = tw(R.R_PRIMARY_AREA)
    summary[SUM_SECONDARY_AREA] = tw(R.R_SECONDARY_AREA)
    summary[SUM_CONTACT_AREA] = tw(R.R_CONTACT_AREA)
    summary[SUM_EMITTED] = rec[:, R.R_EMITTED].sum()
    summary[SUM_GENERATED] = rec[:, R.R_GENERATED].sum()
    summary[SUM_LEDGER] = rec[:, R.R_LEDGER].max()
    summary[SUM_DISC] = rec[:, R.R_DISC].min()
    summary[SUM_FRICTION_RESIDUAL] = np.max(np.abs(rec[:, R.R_FRICTION] / rec[:, R.R_TARGET] - 1.0))
    summary[SUM_HELD] = rec[-1, R.R_HELD]
    summary[SUM_STREAM] = rec[-1, R.R_STREAM]
    first = -(-start // every) * every  # the first kept step at or after this stop's start
    kept = rec[np.arange(first - start, rec.shape[0], every)]
    return summary, kept


def build_dataset(
    *,
    config: SimulationConfig,
    seed: int,
    grid,
    stops,
    summaries: np.ndarray,
    kept: np.ndarray,
    dts: list[np.ndarray],
    flush: list[float],
    s_removed: list[int],
    rule_counts: list[np.ndarray],
    initial_status: np.ndarray,
    final_status: np.ndarray,
    final_height: np.ndarray,
    final_ledger: float,
    wall_time: float,
    kernel: str = "exact",
    kernel_stops: dict[str, int] | None = None,
    contact_fallbacks: int = 0,
    fibre_exposure: list | None = None,
    maps: dict[int, tuple[np.ndarray, np.ndarray]] | None = None,
    final_status_before_s: np.ndarray | None = None,
) -> xr.Dataset:
    """Assemble the run Dataset (see the module docstring for its variables and units).

    Parameters
    ----------
    config, seed
        The run's configuration and seed [-].
    grid
        Its :class:`brakeca.geometry.Grid` (radii [m], angles [rad], cell areas [m^2]).
    stops
        The stops run (:class:`brakeca.cycle.Stop`).
    summaries
        Stops x ``N_SUM``: the per-stop reductions of the kernel's per-step records, rows of
        :func:`summarise_stop` (forces [N], areas [m^2], volumes [m^3], COF [-]).
    kept
        The records of the kept steps, the stops' in order (the per-step series).
    dts
        Each stop's step durations [s].
    flush
        Each stop's end-of-stop emission (the streams' flush and the deposits S removes)
        [m^3].
    s_removed
        Each stop's secondary plateaus removed by S [-].
    rule_counts
        Each stop's rule firings [-].
    initial_status, final_status
        The cells' statuses before the first and after the last stop [-].
    final_status_before_s
        The cells' statuses at the end of the last stop, before rule S removed secondary
        plateaus [-]; None where it removed none (the map is then ``final_status``).
    final_height
        The cells' heights after the last stop [m].
    final_ledger
        The volume ledger's relative residual after the last stop [-].
    wall_time
        The run's wall time [s].
    kernel, kernel_stops, contact_fallbacks
        The kernel setting, the stops each kernel ran and the lazy kernel's fallbacks [-].
    fibre_exposure
        With the fibre field, per stop what the exposure after it did
        (:class:`brakeca.automaton.Exposure`).
    maps
        ``{stop: (statuses [-], heights [m])}``, maps after the stops the run was asked to
        keep them for (``simulate(maps_at=)``); none by default.

    Returns
    -------
    xarray.Dataset
        The run's dataset, every variable with its ``units`` and ``long_name``.
    """
    area = grid.area
    pad_scale = config.brake.pad_area / area
    piston = np.pi * config.brake.piston_diameter**2 / 4.0
    n = len(stops)
    if summaries.shape != (n, N_SUM) or len(dts) != n:
        raise ValueError(f"{summaries.shape[0]} stop summaries and {len(dts)} for {n} stops")

    def col(c: int) -> list[float]:
        return [float(v) for v in summaries[:, c]]

    per_stop: dict[str, Any] = {
        "mean_cof": col(SUM_COF),
        "emitted_volume": [e + f for e, f in zip(col(SUM_EMITTED), flush, strict=True)],
        "generated_volume": col(SUM_GENERATED),
        "primary_area_fraction": [v / area for v in col(SUM_PRIMARY_AREA)],
        "secondary_area_fraction": [v / area for v in col(SUM_SECONDARY_AREA)],
        "contact_area_fraction": [v / area for v in col(SUM_CONTACT_AREA)],
        "band_normal_force": col(SUM_NORMAL),
        "duration": [float(d.sum()) for d in dts],
        "n_steps": [d.size for d in dts],
        "stop_max_ledger_residual": col(SUM_LEDGER),
        "secondary_removed_between_stops": s_removed,
        "end_of_stop_emitted_volume": flush,
        "min_disc_position": col(SUM_DISC),
        "held_volume": col(SUM_HELD),
        "stream_volume": col(SUM_STREAM),
    }
    per_stop["normal_force"] = [f * pad_scale for f in per_stop["band_normal_force"]]
    per_stop["line_pressure"] = [f / piston for f in per_stop["normal_force"]]
    stop_idx = np.arange(1, n + 1)
    # friction residual against the demanded force of each step
    fr_res = col(SUM_FRICTION_RESIDUAL)
    per_stop["stop_max_friction_residual"] = fr_res

    data_vars: dict[str, Any] = {}
    for name, values in per_stop.items():
        unit, desc = STOP_VARIABLES[name]
        data_vars[name] = ("stop", np.asarray(values), {"units": unit, "long_name": desc})
    all_counts = np.stack(rule_counts)  # index 0: fibres exposed in the steps (the field)
    counts = all_counts[:, 1:8]
    data_vars["rule_firings"] = (
        ("stop", "rule"),
        counts,
        {"units": "1", "long_name": "cell firings of each plateau rule during the stop"},
    )
    if fibre_exposure is not None:
        late = np.asarray([e.exposed for e in fibre_exposure], dtype=np.int64)
        values = {
            "fibre_cells_exposed": all_counts[:, 0] + late,
            "fibre_cells_exposed_late": late,
            "fibre_exposure_lag": np.asarray([e.max_lag for e in fibre_exposure]),
            "fibre_volume_cut_as_resin": np.asarray([e.lag_volume for e in fibre_exposure]),
            "fibre_intervals_skipped": np.asarray(
                [e.skipped for e in fibre_exposure], dtype=np.int64
            ),
        }
        for name, (unit, desc) in FIBRE_VARIABLES.items():
            data_vars[name] = ("stop", values[name], {"units": unit, "long_name": desc})
    # thinned per-step series
    every = config.output.series_every
    all_dt = np.concatenate(dts)
    time_end = np.cumsum(all_dt)
    stop_of_step = np.concatenate(
        [np.full(d.size, s.index) for s, d in zip(stops, dts, strict=True)]
    )
    keep = np.arange(0, all_dt.size, every)
    if kept.shape != (keep.size, R.N_REC):
        raise ValueError(f"{kept.shape[0]} kept step records for {keep.size} kept steps")
    series = {
        "step_time": (  # (it read as the time within the stop: an API review)
            time_end[keep],
            "s",
            "braking time of the run at the end of the step, summed over its stops",
        ),
        "step_stop": (stop_of_step[keep], "1", "stop of the step"),
        "step_cof": (kept[:, R.R_COF], "1", "global COF of the step"),
        "step_normal_force": (
            kept[:, R.R_NORMAL] * pad_scale,
            "N",
            "pad normal force, band force * A_pad / A_sim",
        ),
        "step_contact_area_fraction": (
            kept[:, R.R_CONTACT_AREA] / area,
            "1",
            "area in contact / band area",
        ),
        "step_primary_area_fraction": (
            kept[:, R.R_PRIMARY_AREA] / area,
            "1",
            "primary plateau area / band area",
        ),
        "step_secondary_area_fraction": (
            kept[:, R.R_SECONDARY_AREA] / area,
            "1",
            "secondary plateau area / band area",
        ),
        "step_disc_position": (kept[:, R.R_DISC], "m", "disc surface position z"),
    }
    for name, (values, unit, desc) in series.items():
        data_vars[name] = ("step", values, {"units": unit, "long_name": desc})
    data_vars["initial_status"] = (
        ("radius", "angle"),
        initial_status.astype(np.int8),
        {
            "long_name": "cell status before the first stop: 0 none (resin), 1 primary "
            "plateau (fibre), 2 secondary plateau",
            "flag_values": _FLAG_VALUES,
            "flag_meanings": "none primary secondary",
        },
    )
    data_vars["final_status"] = (
        ("radius", "angle"),
        final_status.astype(np.int8),
        {
            "long_name": "cell status after the last stop: 0 none (resin), 1 primary plateau "
            "(fibre), 2 secondary plateau",
            "flag_values": _FLAG_VALUES,
            "flag_meanings": "none primary secondary",
        },
    )
    if final_status_before_s is not None:
        data_vars["final_status_before_s"] = (
            ("radius", "angle"),
            final_status_before_s.astype(np.int8),
            {
                "long_name": "cell status at the end of the last stop, before rule S removed "
                "secondary plateaus: 0 none (resin), 1 primary plateau (fibre), 2 secondary "
                "plateau",
                "flag_values": _FLAG_VALUES,
                "flag_meanings": "none primary secondary",
            },
        )
    data_vars["final_height"] = (
        ("radius", "angle"),
        final_height.astype(np.float32),
        {"units": "m", "long_name": "cell height above the pad datum after the cycle"},
    )
    if maps:
        kept_stops = sorted(maps)
        data_vars["map_status"] = (
            ("map_stop", "radius", "angle"),
            np.stack([maps[k][0] for k in kept_stops]).astype(np.int8),
            {
                "long_name": "cell status after the stop (after rule S): 0 none (resin), 1 "
                "primary plateau (fibre), 2 secondary plateau",
                "flag_values": _FLAG_VALUES,
                "flag_meanings": "none primary secondary",
            },
        )
        data_vars["map_height"] = (
            ("map_stop", "radius", "angle"),
            np.stack([maps[k][1] for k in kept_stops]).astype(np.float32),
            {"units": "m", "long_name": "cell height above the pad datum after the stop"},
        )
    mu = float(np.mean(per_stop["mean_cof"]))
    v = float(np.mean(per_stop["emitted_volume"]))
    data_vars["MU"] = ((), mu, scalar_attrs("MU"))
    data_vars["V"] = ((), v, scalar_attrs("V"))
    data_vars["max_ledger_residual"] = (
        (),
        max(float(np.max(per_stop["stop_max_ledger_residual"])), final_ledger),
        scalar_attrs("max_ledger_residual"),
    )
    data_vars["max_friction_residual"] = (
        (),
        float(np.max(fr_res)),
        scalar_attrs("max_friction_residual"),
    )
    coords = {
        "stop": ("stop", stop_idx, {"units": "1", "long_name": "stop of the drive cycle, from 1"}),
        "block": (
            "stop",
            np.array([s.block for s in stops], dtype=object),
            {"long_name": "the drive cycle's block the stop belongs to"},
        ),
        "rule": ("rule", np.arange(1, 8), RULE_ATTRS),
        "step": (
            "step",
            keep + 1,
            {"units": "1", "long_name": "time step of the run, from 1 (the kept steps)"},
        ),
        "radius": ("radius", np.asarray(grid.radius), {"units": "m", "long_name": "row radius"}),
        "angle": (
            "angle",
            np.asarray(grid.angle),
            {
                "units": "rad",
                "long_name": "column angle from the first column, in the sliding direction",
            },
        ),
    }
    if maps:
        coords["map_stop"] = (
            "map_stop",
            np.array(sorted(maps), dtype=np.int64),
            {"units": "1", "long_name": "stop after which the map was kept"},
        )
    attrs = {
        "format": FORMAT,
        "paper_factors": _paper_factors(config),
        "comment": (
            "quick: 1 when the band was narrowed by --quick; max_stops: the cycle's first N "
            "stops only, -1 for the whole cycle; n_steps_total: the run's steps, of which the "
            "step_* series keep every output.series_every-th; config: the run's whole "
            "configuration (TOML); paper_factors: the paper's four factors as the run has "
            "them (a design's other factors are in config); a campaign's summary.csv names "
            "each run's test and levels by its run id (the file name); band_area: the "
            "simulated band's area A_sim [m2]; wall_time: the run's computing time [s]"
            + (
                "; distance: the trace's distance its events belong to [m]"
                if config.cycle.trace_file
                else ""
            )
        ),
        "title": "brakeca run",
        "references": "J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260",
        "brakeca_version": __version__,
        # what made the run beyond the version, which does not change with every commit (a
        # provenance review): the kernels' sources, the libraries, the date
        "source_key": source_key(),
        "software": software_versions(),
        "date_created": datetime.now(UTC).isoformat(timespec="seconds"),
        "seed": int(seed),
        "config": config.to_toml(),
        "quick": int(config.quick),
        "max_stops": -1 if config.cycle.max_stops is None else int(config.cycle.max_stops),
        "n_steps_total": int(all_dt.size),
        "band_area": float(area),
        "wall_time": float(wall_time),
        "kernel": kernel,
        "stops_lazy": int((kernel_stops or {}).get("lazy", 0)),
        "stops_exact": int((kernel_stops or {}).get("exact", 0)),
        "contact_fallbacks": int(contact_fallbacks),
    }
    return xr.Dataset(data_vars=data_vars, coords=coords, attrs=attrs)
