"""Consolidation of a campaign: ``summary.csv``, ``campaign.nc`` and reading them back.

This module holds :data:`CAMPAIGN_FORMAT`, :class:`CampaignResult`, the builders of the
summary table and the consolidated dataset from the run records, and :func:`read_summary`
and :func:`load_campaign`. Its public names are re-exported by :mod:`brakeca.campaign`.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from brakeca import __version__
from brakeca._runstore import _Record
from brakeca.analysis import default_label
from brakeca.config import ConfigError, SimulationConfig
from brakeca.design import Design, is_run_id, load_design
from brakeca.results import RunResult, scalar_attrs

CAMPAIGN_FORMAT = "brakeca-campaign/1"  #: format marker of campaign.nc


# --- results -------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class CampaignResult:
    """A finished (or loaded) campaign.

    Two results are equal only where they are the same object (``==`` is ``is``), as
    :class:`~brakeca.results.RunResult`'s: a dataclass's ``==`` compared the summaries'
    truth values and raised (an API review).

    A run is found three ways, each with its own key: :meth:`run` takes the **test number**
    (and replicate), the ``summary``'s rows are numbered from 0 in test order (its ``test``
    and ``replicate`` columns name them), and the ``dataset``'s ``run`` coordinate counts
    from 1 in the same order (with one replicate, the test number).

    Attributes
    ----------
    out_dir : Path
        The campaign directory.
    design : Design
        The design as written to ``design.toml`` (its base is ``base_config.toml``).
    summary : pandas.DataFrame
        ``summary.csv``: one row per run in test order: ids, the factors' levels [design
        unit], seed, status, error, and the run scalars of
        :data:`brakeca.results.RUN_SCALAR_UNITS` (``MU`` [-], ``V`` [m^3 per stop],
        ``V_mm3`` [mm^3 per stop], the totals [mm^3], fractions and residuals [-],
        ``wall_time`` [s]).
    dataset : xarray.Dataset
        ``campaign.nc``: per-stop variables on (run, stop), scalars on run, each with its
        ``units`` and ``long_name`` attributes (as a run file's, :mod:`brakeca.results`).
    computed, reused, failed, recomputed : tuple of str
        Run ids computed now, reused from existing files, failed, and recomputed because
        their file was corrupt or foreign (also in ``computed`` or ``failed``). For a
        campaign read by :func:`load_campaign`, ``failed`` holds the summary's failed runs
        and the others are empty (what a campaign computed is not kept).
    """

    out_dir: Path
    design: Design
    summary: pd.DataFrame
    dataset: xr.Dataset
    computed: tuple[str, ...] = ()
    reused: tuple[str, ...] = ()
    failed: tuple[str, ...] = ()
    recomputed: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """True when every run finished."""
        return bool((self.summary["status"] == "ok").all())

    def run(self, test: int, replicate: int = 0) -> RunResult:
        """The run file of a test (and replicate) of this campaign, read
        (``runs/<run_id>.nc``; an API review had to build the path from the summary).

        Raises
        ------
        TypeError
            ``test`` or ``replicate`` is not a whole number.
        KeyError
            The campaign has no such test and replicate.
        ValueError
            The run failed (no run file), or its file cannot be read.
        FileNotFoundError
            Its run file is not in the folder (a folder sent without ``runs/``).
        """
        for name, value in (("test", test), ("replicate", replicate)):
            # run("2") had said test 2 was not a run of the campaign (an API review); a
            # whole number as a float (a row of a numeric frame) is taken (a diff review)
            whole = isinstance(value, numbers.Integral) or (
                isinstance(value, numbers.Real) and float(value).is_integer()
            )
            if isinstance(value, bool) or not whole:
                raise TypeError(
                    f"{name}: expected a whole number (the summary's {name} column), got {value!r}"
                )
        test, replicate = int(test), int(replicate)  # ("test 9.0" in a message otherwise)
        rows = self.summary
        chosen = rows[(rows["test"] == test) & (rows.get("replicate", 0) == replicate)]
        if chosen.empty:
            of_test = rows[rows["test"] == test]
            if not len(rows):
                why = f"test {test}: this campaign has no runs"
            elif len(of_test):  # the test is there, not that replicate (an API review)
                reps = sorted(int(r) for r in of_test.get("replicate", pd.Series([0])))
                why = (
                    f"test {test}, replicate {replicate}: not a run of this campaign (test "
                    f"{test}'s replicates: {', '.join(map(str, reps))})"
                )
            else:
                why = (
                    f"test {test}, replicate {replicate}: not a run of this campaign (tests "
                    f"{int(rows['test'].min())} to {int(rows['test'].max())})"
                )
            raise KeyError(why)
        row = chosen.iloc[0]
        if row["status"] != "ok":
            raise ValueError(f"test {test}, replicate {replicate} failed: {row['error']}")
        return RunResult.from_netcdf(Path(self.out_dir) / "runs" / f"{row['run_id']}.nc")

    def __repr__(self) -> str:
        """One line: design, folder and run counts (the attributes hold the rest)."""
        n = len(self.summary)
        n_ok = int((self.summary["status"] == "ok").sum()) if n else 0
        now = (
            f", {len(self.computed)} computed now, {len(self.reused)} reused"
            if self.computed or self.reused
            else ""
        )
        return (
            f"CampaignResult({self.design.name!r} in {str(self.out_dir)!r}: {n} runs, "
            f"{n_ok} ok, {n - n_ok} failed{now})"
        )


# --- consolidation -------------------------------------------------------------------------

_FIRST_SCALARS = ("MU", "MU_SD", "V", "V_mm3")


def _scalar_names(records: Iterable[_Record]) -> list[str]:
    names: list[str] = list(_FIRST_SCALARS)
    for record in records:
        for name in record.scalars:
            if name not in names:
                names.append(name)
    return names


def _summary_frame(design: Design, records: Sequence[_Record]) -> pd.DataFrame:
    """One row per record (test order): ids, factor levels, seed, status, error, scalars."""
    scalar_names = _scalar_names(records)
    rows = []
    for rec in records:
        row: dict[str, Any] = {
            "test": rec.point.test,
            "replicate": rec.point.replicate,
            "order": rec.point.order,
            "run_id": rec.run_id,
        }
        for name in design.factor_names:
            row[name] = rec.point.levels[name]
        row.update(seed=rec.point.seed, status=rec.status, error=rec.error)
        for name in scalar_names:
            row[name] = rec.scalars.get(name, math.nan)
        rows.append(row)
    frame = pd.DataFrame(rows)
    for name in ("run_id", "status", "error"):
        frame[name] = frame[name].astype(object)
    return frame


def _campaign_dataset(
    design: Design, records: Sequence[_Record], summary: pd.DataFrame, base: SimulationConfig
) -> xr.Dataset:
    """Consolidated dataset: per-stop variables on (run, stop), scalars and ids on run."""
    n_run = len(records)
    ok = [r.per_stop for r in records if r.per_stop is not None]
    longest = max(ok, key=lambda ds: ds.sizes["stop"]) if ok else None
    n_stop = longest.sizes["stop"] if longest is not None else 0
    run = np.arange(1, n_run + 1)
    coords: dict[str, Any] = {
        "run": ("run", run, {"long_name": "run index in test order (the test when 1 replicate)"}),
        "test": ("run", summary["test"].to_numpy(np.int64), {"long_name": "test number"}),
        # each with a long_name, as a run file's coordinates (an API review found them bare)
        "replicate": (
            "run",
            summary["replicate"].to_numpy(np.int64),
            {"long_name": "replicate of the test, from 0"},
        ),
        "order": ("run", summary["order"].to_numpy(np.int64), {"long_name": "execution order"}),
        "seed": (
            "run",
            summary["seed"].to_numpy(np.int64),
            {"long_name": "seed of the run's random generator"},
        ),
        "run_id": (
            "run",
            np.array([r.run_id for r in records], dtype=object),
            {"long_name": "run id: the run file is runs/<run_id>.nc"},
        ),
        "status": (
            "run",
            np.array([r.status for r in records], dtype=object),
            {"long_name": "ok, or failed (see error)"},
        ),
        "error": (
            "run",
            np.array([r.error for r in records], dtype=object),
            {"long_name": "why the run failed (empty when it finished)"},
        ),
        "stop": (
            "stop",
            np.arange(1, n_stop + 1),
            {"units": "1", "long_name": "stop of the drive cycle, from 1"},
        ),
    }
    if longest is not None:
        if "block" in longest.coords:
            coords["block"] = (
                "stop",
                np.asarray(longest["block"].values, dtype=object),
                dict(longest["block"].attrs),
            )
        if "stop" in longest.coords:
            coords["stop"] = (*coords["stop"][:2], dict(longest["stop"].attrs))
        for name, coord in longest.coords.items():
            if str(name) not in coords and "stop" not in coord.dims:
                coords[str(name)] = coord.variable
    for factor in design.factors:
        values = np.asarray([r.point.levels[factor.name] for r in records])
        attrs = {
            "units": "1" if factor.unit == "-" else factor.unit,  # UDUNITS' 1 (none: none)
            # (a factor on a paper's field without a label: the paper's, as the figures
            # of the campaign show it; analysis.default_label)
            "long_name": factor.label or default_label(factor.field) or factor.name,
            "field": factor.field,
            "scale": factor.scale,
            "levels": np.asarray(factor.levels, dtype=float),
        }
        if factor.labels is not None:
            attrs["labels"] = list(factor.labels)
        coords[factor.name] = ("run", values, attrs)

    data_vars: dict[str, Any] = {}
    if longest is not None:
        # every run's variables: runs of an earlier version (reused) may lack one a newer run
        # has (held_volume, stream_volume), which is then NaN for them
        names = list(dict.fromkeys(str(n) for ds in [longest, *ok] for n in ds.data_vars))
        for name in names:
            var = next(ds[name] for ds in [longest, *ok] if name in ds)
            extra_dims = tuple(d for d in var.dims if d != "stop")
            extra_shape = tuple(var.sizes[d] for d in extra_dims)
            full = all(
                ds is not None and name in ds and ds.sizes["stop"] == n_stop
                for ds in (r.per_stop for r in records)
            )
            dtype = var.dtype if full else np.result_type(var.dtype, np.float64)
            fill = 0 if full else np.nan
            array = np.full((n_run, n_stop, *extra_shape), fill, dtype=dtype)
            for i, rec in enumerate(records):
                ds = rec.per_stop
                if ds is not None and name in ds:
                    values = ds[name].transpose("stop", *extra_dims).values
                    array[i, : values.shape[0]] = values
            data_vars[str(name)] = (("run", "stop", *extra_dims), array, dict(var.attrs))
    for name in _scalar_names(records):
        if name in data_vars or name in coords:
            continue
        data_vars[name] = (
            "run",
            pd.to_numeric(summary[name], errors="coerce").to_numpy(),
            scalar_attrs(name),
        )
    attrs = {
        "format": CAMPAIGN_FORMAT,
        "title": f"brakeca campaign {design.name}",
        "design_name": design.name,
        "description": design.description,
        "factors": list(design.factor_names),
        "root_seed": str(design.root_seed),
        "replicates": design.replicates,
        "randomize_order": int(design.randomize_order),
        "design": design.to_toml(base_config="base_config.toml"),
        "base_config": base.to_toml(),
        "quick": int(base.quick),
        "brakeca_version": __version__,
        "references": "J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260",
    }
    return xr.Dataset(data_vars=data_vars, coords=coords, attrs=attrs)


# --- reading back --------------------------------------------------------------------------


_TEXT_COLUMNS = ("run_id", "status", "error")


def _parse_column(values: pd.Series) -> pd.Series:
    """Exact numbers from CSV text: int64 when every value is an integer, else float64."""
    texts = [v.strip() for v in values]
    try:
        return pd.Series([int(t) for t in texts], index=values.index, dtype=np.int64)
    except (ValueError, OverflowError):  # (an integer past int64: read as a float, as
        pass  # pandas would; it had ended analyze with a traceback: a security review)
    try:
        floats = [math.nan if t == "" else float(t) for t in texts]
    except ValueError:
        return values.astype(object)
    return pd.Series(floats, index=values.index, dtype=np.float64)


def read_summary(path: str | Path) -> pd.DataFrame:
    """Read a ``summary.csv``, numbers bit-exact (Python's float parser, whatever pandas).

    Text columns (``run_id``, ``status``, ``error``) stay text, empty errors are ``""``.

    Parameters
    ----------
    path
        The ``summary.csv`` file.

    Returns
    -------
    pandas.DataFrame
        One row per run, every value as the campaign wrote it (the file holds each float's
        shortest round-trip text, so the values are the campaign's to the bit).
    """
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    for name in frame.columns:
        if name in _TEXT_COLUMNS:
            frame[name] = frame[name].astype(object)
        else:
            frame[name] = _parse_column(frame[name])
    return frame


def campaign_folder(out_dir: str | Path) -> Path:
    """``out_dir`` as a path, checked to be a campaign's folder (it holds ``design.toml``).

    Raises
    ------
    FileNotFoundError
        No such folder, a file, or a folder without ``design.toml``; the message says which.
    """
    out = Path(out_dir)
    if not out.is_dir():
        if out.exists():
            raise FileNotFoundError(
                f"{out}: not a folder (a file); give the campaign folder 'brakeca run -o' wrote"
            )
        raise FileNotFoundError(f"{out}: no such folder")
    if not (out / "design.toml").is_file():
        raise FileNotFoundError(
            f"{out}: not a campaign folder (no design.toml; 'brakeca run' writes one)"
        )
    return out


def load_campaign(out_dir: str | Path) -> CampaignResult:
    """Read a finished campaign directory.

    Parameters
    ----------
    out_dir
        The campaign's folder (``brakeca run -o``, ``run_campaign``'s ``out_dir``).

    Returns
    -------
    CampaignResult
        Design (from ``design.toml``), summary (``summary.csv``) and dataset
        (``campaign.nc``, loaded into memory); ``failed`` holds the failed runs' ids, the
        other run-id tuples are empty.

    Raises
    ------
    FileNotFoundError
        A file is missing (the campaign has not finished).
    ConfigError
        ``design.toml`` is invalid.
    ValueError
        ``campaign.nc`` is not a readable brakeca campaign file, or ``summary.csv`` does not
        match it (edited or damaged; ``brakeca run`` writes it again).
    """
    out = campaign_folder(out_dir)
    for name in ("summary.csv", "campaign.nc"):
        if not (out / name).is_file():
            raise FileNotFoundError(
                f"{out / name}: missing; the campaign has not finished: "
                f"'brakeca run {out / 'design.toml'} -o {out}' finishes it"
            )
    import warnings

    from brakeca.config import UnitWarning

    with warnings.catch_warnings():  # said when the campaign was made, not at every read
        warnings.simplefilter("ignore", UnitWarning)
        design = load_design(out / "design.toml")
    summary = read_summary(out / "summary.csv")
    from brakeca.results import load_netcdf

    try:
        dataset = load_netcdf(out / "campaign.nc")
    except ValueError as exc:  # with the fix, as a missing one gets (a robustness review)
        raise ValueError(
            f"{exc}; 'brakeca run {out / 'design.toml'} -o {out}' writes it again from the "
            "run files"
        ) from None
    if dataset.attrs.get("format") != CAMPAIGN_FORMAT:
        raise ValueError(f"{out / 'campaign.nc'}: not a brakeca campaign file")
    problem = _design_problem(summary, dataset, design)
    if problem:  # before the summary's check, which would blame summary.csv
        raise ValueError(
            f"{out / 'design.toml'}: {problem}: it was edited after the runs; put it back as "
            f"the runs have it, or run the edited design into a folder of its own "
            f"('brakeca run FILE -o NEW')"
        )
    problem = _summary_problem(summary, dataset, design)
    if problem:
        raise ValueError(
            f"{out / 'summary.csv'}: {problem}: it was edited or damaged; 'brakeca run "
            f"{out / 'design.toml'} -o {out}' writes it again from the run files"
        )
    # the failed runs are the summary's: ``if result.failed`` had read a loaded campaign with
    # failed runs as none (an API review)
    failed = tuple(str(r) for r in summary.loc[summary["status"] != "ok", "run_id"])
    return CampaignResult(
        out_dir=out,
        design=design,
        summary=_with_mu_sd(summary, dataset),
        dataset=dataset,
        failed=failed,
    )


def _with_mu_sd(summary: pd.DataFrame, dataset: xr.Dataset) -> pd.DataFrame:
    """``summary`` with the friction stability ``MU_SD`` [-] after ``MU``, from campaign.nc's
    per-stop mean COF, where a campaign written before that scalar has no such column (as
    :attr:`brakeca.results.RunResult.MU_SD` computes it: the standard deviation over the
    stops run, ``ddof=0``); NaN for a failed run. A summary that has it is returned as is."""
    if "MU_SD" in summary.columns or "mean_cof" not in dataset or "MU" not in summary:
        return summary
    by_id = {str(r): i for i, r in enumerate(dataset["run_id"].values)}
    cof = np.asarray(dataset["mean_cof"].transpose("run", "stop"), dtype=float)
    values = []
    for run_id, status in zip(summary["run_id"], summary["status"], strict=True):
        row = cof[by_id[str(run_id)]] if str(run_id) in by_id else np.array([])
        row = row[np.isfinite(row)]
        values.append(float(np.std(row)) if status == "ok" and row.size else math.nan)
    out = summary.copy()
    out.insert(list(out.columns).index("MU") + 1, "MU_SD", values)
    return out


def _design_problem(summary: pd.DataFrame, dataset: xr.Dataset, design: Design) -> str:
    """Why the folder's ``design.toml`` is not the design its runs were made of (a factor
    that neither summary.csv nor campaign.nc has, a level of the runs that is none of a
    factor's levels nor its centre); empty when it is. An edited level had reached the
    analysis as a traceback, an added factor been blamed on summary.csv (a robustness
    review)."""
    from brakeca.design import _match_level

    centre = design.center_levels() if design.center_points else {}
    for factor in design.factors:
        name = factor.name
        if name in dataset.coords:  # the runs' levels as campaign.nc has them (a summary
            # edited alone is the summary's own problem)
            values = pd.Series(np.asarray(dataset.coords[name].values))
        elif name in summary.columns:
            values = summary[name]
        else:
            return f"it has factor {name}, which the runs (summary.csv, campaign.nc) have not"
        for value in pd.unique(values.dropna()):
            value = value.item() if isinstance(value, np.generic) else value
            if isinstance(value, str) and factor.choices is None:
                try:
                    value = float(value)
                except ValueError:
                    continue  # not a number: the summary's own problem
            if _match_level(factor, value) is not None:
                continue
            middle = centre.get(name)
            if middle is not None and not isinstance(value, str):
                if math.isclose(float(value), float(middle), rel_tol=1e-9, abs_tol=0.0):
                    continue
            levels = ", ".join(f"{v!r}" for v in factor.levels)
            return f"factor {name}'s levels are {levels}, and none is the runs' {value!r}"
    return _runs_problem(dataset, design)


def _runs_problem(dataset: xr.Dataset, design: Design) -> str:
    """Why the runs of ``dataset`` (campaign.nc's: a summary edited alone is the summary's
    own problem) are not ``design``'s tests and replicates, or their seeds not its root
    seed's; empty when they are, or where campaign.nc cannot say (a growth review:
    replicates or root_seed edited in a campaign's design.toml had given a report of "4
    tests x 2 replicates = 8 runs" and "4 of 4 runs finished")."""
    from brakeca.design import point_seed

    if "test" not in dataset.coords or "seed" not in dataset.coords:
        return ""
    try:
        n_tests = design.n_tests
        tests = [int(t) for t in dataset.coords["test"].values]
        replicates = (
            [int(r) for r in dataset.coords["replicate"].values]
            if "replicate" in dataset.coords
            else [0] * len(tests)
        )
        seeds = [int(s) for s in dataset.coords["seed"].values]
    except (ConfigError, TypeError, ValueError, OverflowError):
        return ""
    expected = n_tests * design.replicates
    if len(tests) != expected or max(replicates, default=0) >= design.replicates:
        return (
            f"it has {n_tests} tests × {design.replicates} replicate"
            f"{'' if design.replicates == 1 else 's'} = {expected} runs, where the folder has "
            f"{len(tests)} runs of {len(set(replicates))} replicate"
            f"{'' if len(set(replicates)) == 1 else 's'}"
        )
    for test, replicate, seed in zip(tests, replicates, seeds, strict=True):
        if point_seed(design.root_seed, test, replicate) != seed:
            return (
                f"its root_seed {design.root_seed} does not give the runs' seeds (test "
                f"{test}, replicate {replicate} ran with seed {seed})"
            )
    return ""


def _summary_problem(summary: pd.DataFrame, dataset: xr.Dataset, design: Design) -> str:
    """Why a summary read back does not hold the campaign's runs (rows, run ids, status,
    levels, and every other value ``campaign.nc`` holds per run, as it and the design have
    them); empty when it does."""
    if "run_id" not in summary.columns or "status" not in summary.columns:
        return "it has no run_id or status column"
    ids = [str(r) for r in summary["run_id"]]
    odd = next((r for r in ids if not is_run_id(r)), None)
    if odd is not None:  # (a path: the analysis had read and drawn a file elsewhere)
        return f"a run_id is {odd[:40]!r}, not a run's id (16 hexadecimal digits)"
    expected = [str(r) for r in dataset["run_id"].values] if "run_id" in dataset else ids
    if ids != expected:
        return (
            f"its {len(ids)} runs are not the {len(expected)} of campaign.nc"
            if len(ids) != len(expected)
            else "its runs are not those of campaign.nc, in its order"
        )
    bad = sorted(set(summary["status"].astype(str)) - {"ok", "failed"})
    if bad:
        return f"a run's status is {bad[0]!r}, not 'ok' or 'failed'"
    for name in design.factor_names:
        if name not in summary.columns:
            return f"the column of factor {name} is missing"
        if summary[name].isna().any():
            return f"factor {name} has no level in some row"
    # every column campaign.nc holds per run, value for value (a level, a response or a
    # test number edited by hand had reached the analysis as it was, or as a traceback)
    for key, values in dataset.variables.items():
        name = str(key)
        if name == "run" or tuple(values.dims) != ("run",):
            continue
        if name not in summary.columns:
            return f"its column {name} is missing"
        row = _first_difference(summary[name].to_numpy(), np.asarray(values.values))
        if row is not None:
            mine, theirs = summary[name].iloc[row], np.asarray(values.values)[row]
            mine = mine.item() if isinstance(mine, np.generic) else mine
            return (
                f"its {name} in row {row + 1} is {mine!r}, where campaign.nc has {theirs.item()!r}"
            )
    return ""


def _first_difference(mine: np.ndarray, theirs: np.ndarray) -> int | None:
    """The first row where a summary column ``mine`` differs from campaign.nc's ``theirs``
    (numbers compared exactly, NaN equal to NaN; text as text), or None."""
    if theirs.dtype.kind in "iuf":
        ours = pd.to_numeric(pd.Series(mine), errors="coerce").to_numpy(dtype=float)
        other = theirs.astype(float)
        # text that is no number (a decimal comma) is NaN here, unlike campaign.nc's
        same = (ours == other) | (np.isnan(ours) & np.isnan(other))
    else:
        same = np.array([str(a) == str(b) for a, b in zip(mine, theirs, strict=True)])
    bad = np.flatnonzero(~same)
    return int(bad[0]) if bad.size else None
