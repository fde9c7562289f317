"""Campaigns: run every point of a factorial design, resumably, in parallel, and consolidate.

A campaign directory holds::

    out_dir/
        design.toml        the design, its base replaced by base_config.toml
        base_config.toml   the resolved base configuration (campaign-wide overrides, max_stops
                           and quick applied), so design.toml alone reproduces every run
        runs/<run_id>.nc   one netCDF file per run (brakeca.results format), named by
                           brakeca.design.run_id (hash of the resolved config and the seed)
        summary.csv        one row per run in test order: test, replicate, order, run_id,
                           one column per factor [design unit], seed, status, error, scalars
        campaign.nc        every per-stop variable along (run, stop), scalars along run

Runs whose file already exists and loads back with the same seed and configuration are reused,
so an interrupted campaign is resumed by running it again; a corrupt or foreign run file is
reported and recomputed. Workers only compute and return :class:`~brakeca.results.RunResult`
objects; this process writes every file, each one atomically (a temporary file in the same
folder, then :func:`os.replace`), so a killed campaign never leaves a half-written run file
under its final name.

Executors (:func:`make_executor`): ``serial`` (inline, for debugging), ``local`` (worker
processes on this machine, the default) and ``dask`` (a Dask cluster: an existing scheduler or
a LocalCluster on loopback). Results do not depend on the executor. A run whose worker process
dies is tried again, a bounded number of times, then recorded as failed with its error; a run
that raises is recorded as failed at once. The other runs finish either way.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import math
import multiprocessing
import os
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pandas as pd
import xarray as xr

from brakeca import __version__
from brakeca._io import atomic_write
from brakeca.config import ConfigError, SimulationConfig
from brakeca.design import Design, RunPoint, execution_order, load_design, run_id

if TYPE_CHECKING:
    from rich.console import Console

    from brakeca.results import RunResult

__all__ = [
    "CAMPAIGN_FORMAT",
    "DEFAULT_MAX_RETRIES",
    "EXECUTOR_KINDS",
    "WORKER_ENV",
    "CampaignResult",
    "DaskExecutor",
    "ExecutorError",
    "SerialExecutor",
    "finish_campaign",
    "load_campaign",
    "main",
    "make_executor",
    "read_summary",
    "run_campaign",
]

CAMPAIGN_FORMAT = "brakeca-campaign/1"  #: format marker of campaign.nc

ExecutorKind = Literal["serial", "local", "dask"]
SimulateFn = Callable[..., "RunResult"]

#: The executor kinds of :func:`make_executor` and :func:`run_campaign`.
EXECUTOR_KINDS: tuple[str, ...] = ("serial", "local", "dask")

#: Default number of times a run whose worker process died is tried again [-].
DEFAULT_MAX_RETRIES = 2

#: Environment set in every worker: one thread each, the pool or cluster gives the parallelism.
WORKER_ENV: Mapping[str, str] = {
    "NUMBA_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
}

#: Dimensions of a run file that are not per-stop (left out of campaign.nc).
_NON_STOP_DIMS = frozenset({"step", "radius", "angle"})


# --- executors -----------------------------------------------------------------------------


class ExecutorError(RuntimeError):
    """An executor cannot be started: dask is missing, or its scheduler cannot be reached."""


class SerialExecutor(cf.Executor):
    """A :class:`concurrent.futures.Executor` that runs each call inline, in ``submit``.

    Exceptions of the call are stored in the returned future; ``KeyboardInterrupt`` and
    other ``BaseException`` subclasses propagate.
    """

    def __init__(self) -> None:
        self._shutdown = False

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> cf.Future:
        """Run ``fn(*args, **kwargs)`` now; return a finished future."""
        if self._shutdown:
            raise RuntimeError("cannot submit after shutdown")
        future: cf.Future = cf.Future()
        try:
            result = fn(*args, **kwargs)
        except Exception as exc:
            future.set_exception(exc)
        else:
            future.set_result(result)
        return future

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Refuse further submissions (nothing runs in the background)."""
        self._shutdown = True


class DaskExecutor(cf.Executor):
    """A :class:`concurrent.futures.Executor` that sends each call to a Dask cluster.

    Calls are submitted with ``pure=False`` (every submission runs); their results come back
    to this process, which is the only one that writes files. :meth:`shutdown` closes the
    client and, when this executor started it, the :class:`distributed.LocalCluster`.

    Parameters
    ----------
    client : distributed.Client
        A connected client.
    cluster : distributed.LocalCluster, optional
        A cluster started for this executor, closed with it.
    own_client
        Close ``client`` on shutdown (True for a client made by :func:`make_executor`).
    """

    def __init__(self, client: Any, cluster: Any = None, *, own_client: bool = True) -> None:
        self.client = client
        self.cluster = cluster
        self._own_client = own_client
        self._executor = client.get_executor(pure=False)
        self._closed = False

    @property
    def address(self) -> str:
        """The scheduler's address."""
        return str(self.client.scheduler.address)

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> cf.Future:
        """Send ``fn(*args, **kwargs)`` to the cluster; return a concurrent.futures future."""
        return self._executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Wait for (or cancel) the submitted calls, then close the client and own cluster."""
        if self._closed:
            return
        self._closed = True
        try:
            self._executor.shutdown(wait=wait and not cancel_futures)
        finally:
            try:
                if self._own_client:
                    self.client.close()
            finally:
                if self.cluster is not None:
                    self.cluster.close()


def _init_worker() -> None:
    """Process-pool initializer: one numba / OpenMP / BLAS thread per worker."""
    os.environ.update(WORKER_ENV)
    numba = sys.modules.get("numba")
    if numba is not None:  # imported before the initializer ran (e.g. by the main module)
        try:
            numba.set_num_threads(1)
        except Exception:  # a numba without a threading layer: nothing to limit
            pass


def _local_pool(workers: int) -> cf.ProcessPoolExecutor:
    """A process pool on the ``"spawn"`` start method, one numba/OpenMP thread per worker."""
    return cf.ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_init_worker,
    )


def _dask_executor(
    workers: int | None,
    scheduler: str | None,
    scheduler_file: str | Path | None,
    max_retries: int | None,
) -> DaskExecutor:
    """Connect to a Dask scheduler, or start a LocalCluster on loopback (see make_executor)."""
    try:
        import dask
        import distributed
    except ImportError as exc:
        raise ExecutorError(
            "the dask executor needs dask.distributed: pip install 'brakeca[cluster]' "
            f"({type(exc).__name__}: {exc})"
        ) from None
    if scheduler is not None or scheduler_file is not None:
        where = scheduler if scheduler is not None else f"scheduler file {scheduler_file}"
        try:
            if scheduler is not None:
                client = distributed.Client(scheduler, set_as_default=False)
            else:
                client = distributed.Client(
                    scheduler_file=str(scheduler_file), set_as_default=False
                )
        except Exception as exc:
            raise ExecutorError(
                f"cannot connect to the Dask scheduler at {where}: {_error_text(exc)}"
            ) from None
        return DaskExecutor(client)
    n = (os.cpu_count() or 1) if workers is None else int(workers)
    # the scheduler's HTTP server (health, metrics; no dashboard) on any free loopback port,
    # not on dask's default 8787, which another cluster may hold
    scheduler_kwargs: dict[str, Any] = {"dashboard_address": "127.0.0.1:0"}
    if max_retries is not None:
        scheduler_kwargs["allowed_failures"] = int(max_retries)
    # a one-thread worker holds only the run it executes, so a dying worker takes no queued
    # run down with it (dask counts every run on a dead worker as suspicious)
    with dask.config.set({"distributed.scheduler.worker-saturation": 1.0}):
        cluster = distributed.LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            scheduler_kwargs=scheduler_kwargs,
            env=dict(WORKER_ENV),
        )
        try:
            client = distributed.Client(cluster, set_as_default=False)
        except BaseException:
            cluster.close()
            raise
    return DaskExecutor(client, cluster)


def make_executor(
    kind: ExecutorKind = "local",
    workers: int | None = None,
    *,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    max_retries: int | None = None,
) -> cf.Executor:
    """Create an executor for :func:`run_campaign`.

    Parameters
    ----------
    kind
        ``"serial"``: every run inline in this process (:class:`SerialExecutor`).
        ``"local"``: a :class:`~concurrent.futures.ProcessPoolExecutor` on the ``"spawn"``
        start method, each worker limited to one numba/OpenMP thread.
        ``"dask"``: a :class:`DaskExecutor`: a client of the scheduler at ``scheduler`` (or
        named in ``scheduler_file``), or, with neither, of a new
        :class:`distributed.LocalCluster` of ``workers`` one-thread worker processes bound to
        127.0.0.1, without dashboard, whose workers get :data:`WORKER_ENV`.
    workers
        Worker processes for ``"local"`` and a new LocalCluster [-]; None: ``os.cpu_count()``.
    scheduler
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"`` (``"dask"`` only).
    scheduler_file
        JSON file written by ``dask scheduler --scheduler-file`` (``"dask"`` only).
    max_retries
        For a new LocalCluster: how many times the scheduler re-runs a task whose worker died
        (``distributed.scheduler.allowed-failures``) [-]; None: dask's setting. An existing
        cluster keeps its scheduler's setting.

    Returns
    -------
    concurrent.futures.Executor
        The caller shuts it down (use it as a context manager); a :class:`DaskExecutor`
        then closes its client and the cluster it started.

    Raises
    ------
    ValueError
        Unknown kind, a worker count below 1, or a scheduler given to another kind.
    ExecutorError
        ``"dask"``: dask.distributed is not installed, or the scheduler cannot be reached.
    """
    if kind not in EXECUTOR_KINDS:
        raise ValueError(f"unknown executor {kind!r}; choose 'serial', 'local' or 'dask'")
    _check_scheduler(kind, scheduler, scheduler_file)
    if workers is not None and int(workers) < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if max_retries is not None and int(max_retries) < 0:
        raise ValueError(f"max_retries must be at least 0, got {max_retries}")
    if kind == "serial":
        return SerialExecutor()
    if kind == "local":
        return _local_pool((os.cpu_count() or 1) if workers is None else int(workers))
    return _dask_executor(workers, scheduler, scheduler_file, max_retries)


def _check_scheduler(
    kind: ExecutorKind | cf.Executor, scheduler: str | None, scheduler_file: str | Path | None
) -> None:
    """Raise ValueError unless a scheduler (address or file) goes with the dask kind."""
    if scheduler is None and scheduler_file is None:
        return
    if kind != "dask":
        name = "scheduler" if scheduler is not None else "scheduler_file"
        raise ValueError(f"{name} needs executor='dask', not {kind!r}")
    if scheduler is not None and scheduler_file is not None:
        raise ValueError("give scheduler or scheduler_file, not both")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise ValueError(f"scheduler must be an address such as tcp://HOST:PORT, got {scheduler!r}")
    if scheduler_file is not None and not Path(scheduler_file).is_file():
        raise ValueError(
            f"scheduler_file {str(scheduler_file)!r} does not exist; start the scheduler with "
            "'dask scheduler --scheduler-file FILE' first"
        )


def _execute(simulate_fn: SimulateFn | None, config: SimulationConfig, seed: int) -> RunResult:
    """Worker task: run one simulation and return its result (no file I/O)."""
    if simulate_fn is None:
        from brakeca.simulation import simulate as simulate_fn
    return simulate_fn(config, seed=seed)


# --- records and results -------------------------------------------------------------------


@dataclass(frozen=True)
class _Record:
    """What the campaign keeps of one run: status, scalars and the per-stop variables."""

    point: RunPoint
    run_id: str
    status: str  # "ok" or "failed"
    error: str = ""
    scalars: dict[str, float] = field(default_factory=dict)
    per_stop: xr.Dataset | None = None


@dataclass(frozen=True)
class CampaignResult:
    """A finished (or loaded) campaign.

    Attributes
    ----------
    out_dir : Path
        The campaign directory.
    design : Design
        The design as written to ``design.toml`` (its base is ``base_config.toml``).
    summary : pandas.DataFrame
        ``summary.csv``: one row per run in test order.
    dataset : xarray.Dataset
        ``campaign.nc``: per-stop variables on (run, stop), scalars on run.
    computed, reused, failed, recomputed : tuple of str
        Run ids computed now, reused from existing files, failed, and recomputed because
        their file was corrupt or foreign (also in ``computed`` or ``failed``). Empty for a
        campaign read by :func:`load_campaign`.
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


# --- file helpers --------------------------------------------------------------------------


def _write_text(path: Path, text: str) -> Path:
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def _remove_stale_temporaries(folder: Path) -> list[Path]:
    """Delete ``.<name>.<random>.tmp`` files left by a killed campaign in ``folder``."""
    removed = []
    for tmp in folder.glob(".*.tmp"):
        if tmp.is_file():
            tmp.unlink(missing_ok=True)
            removed.append(tmp)
    return removed


def _per_stop(dataset: xr.Dataset) -> xr.Dataset:
    """The variables of a run dataset that are indexed by stop (and no map or step dim)."""
    names = [
        name
        for name, var in dataset.data_vars.items()
        if "stop" in var.dims and not _NON_STOP_DIMS.intersection(var.dims)
    ]
    out = dataset[names]
    return out.drop_vars([c for c in out.coords if _NON_STOP_DIMS.intersection(out[c].dims)])


def _record_from_result(point: RunPoint, rid: str, result: RunResult) -> _Record:
    scalars = {k: _number(v) for k, v in result.scalars().items()}
    return _Record(point, rid, "ok", "", scalars, _per_stop(result.dataset).load())


def _number(value: Any) -> float | int:
    if isinstance(value, bool | np.bool_):
        return int(value)
    if isinstance(value, int | np.integer):
        return int(value)
    return float(value)


def _check_result(result: Any, point: RunPoint) -> str | None:
    """Why ``result`` is not the result of ``point`` (None when it is)."""
    from brakeca.results import RunResult

    if not isinstance(result, RunResult):
        return f"the simulation returned {type(result).__name__}, not a RunResult"
    if int(result.seed) != point.seed:
        return f"the result has seed {result.seed}, the run {point.seed}"
    if result.config != point.config:
        return "the result's configuration differs from the run's"
    return None


def _load_existing(path: Path, point: RunPoint) -> tuple[RunResult | None, str]:
    """Load a run file for reuse: (result, "") or (None, why it cannot be trusted)."""
    from brakeca.results import RunResult

    try:
        result = RunResult.from_netcdf(path)
    except Exception as exc:
        return None, f"cannot be read ({type(exc).__name__}: {exc})"
    problem = _check_result(result, point)
    if problem is not None:
        return None, f"belongs to another run ({problem})"
    return result, ""


# --- the campaign --------------------------------------------------------------------------


def run_campaign(
    design: Design | str | Path,
    out_dir: str | Path,
    *,
    workers: int | None = None,
    executor: ExecutorKind | cf.Executor = "local",
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    max_retries: int = DEFAULT_MAX_RETRIES,
    quick: bool = False,
    max_stops: int | None = None,
    overrides: Mapping[str, Any] | None = None,
    simulate_fn: SimulateFn | None = None,
    progress: bool = True,
    console: Console | None = None,
) -> CampaignResult:
    """Run every point of ``design`` into ``out_dir``, reusing the runs already there.

    Parameters
    ----------
    design
        A :class:`~brakeca.design.Design`, a shipped design name or a design file.
    out_dir
        Campaign directory (created); see the module docstring for its layout.
    workers
        Worker processes of the ``"local"`` executor and of a LocalCluster started by
        ``"dask"`` [-]; None: ``os.cpu_count()`` (never more than the runs left to do).
    executor
        ``"serial"``, ``"local"``, ``"dask"`` (see :func:`make_executor`; the campaign closes
        what it starts, also on error), or any :class:`concurrent.futures.Executor` (e.g.
        ``distributed.Client.get_executor()``), which the caller keeps and shuts down.
    scheduler
        ``"dask"``: address of a running scheduler (``tcp://HOST:PORT``); None: a
        LocalCluster on 127.0.0.1 for this campaign (unless ``scheduler_file`` is given).
    scheduler_file
        ``"dask"``: the scheduler's JSON file (``dask scheduler --scheduler-file FILE``).
    max_retries
        How many times a run whose worker process died (killed, out of memory) is tried
        again before it is recorded as failed [-]. ``"local"``: each run is counted on its
        own; ``"dask"``: the LocalCluster's ``allowed-failures`` (an existing cluster keeps
        its scheduler's). A run that raises is never retried.
    quick
        Narrow every run's band with :func:`brakeca.design.quick_config`.
    max_stops
        Run only the first ``max_stops`` stops of the cycle [-].
    overrides
        Dotted-key (or factor-alias) configuration updates applied to every run before the
        factor levels.
    simulate_fn
        Module-level (picklable) function with the signature of
        :func:`brakeca.simulation.simulate`; None uses that function.
    progress
        Show a progress bar over the runs, with an ETA.
    console
        Where messages and the progress bar go; None: a console on standard error.

    Returns
    -------
    CampaignResult
        The summary and consolidated dataset, also written to ``summary.csv`` and
        ``campaign.nc``. A run that raised has status ``"failed"`` and its error message;
        the others are unaffected.

    Raises
    ------
    ConfigError
        The design, an override or a level does not validate (before anything is written).
    ValueError
        An unknown executor, ``workers`` below 1, ``max_retries`` below 0, or a scheduler
        that does not go with the executor (before anything is written).
    ExecutorError
        ``"dask"``: dask.distributed is missing or the scheduler cannot be reached (after the
        design files are written, before any run starts).
    """
    from rich.console import Console
    from rich.markup import escape

    if isinstance(executor, str) and executor not in EXECUTOR_KINDS:
        raise ValueError(f"unknown executor {executor!r}; choose 'serial', 'local' or 'dask'")
    _check_scheduler(executor, scheduler, scheduler_file)
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if isinstance(max_retries, bool) or int(max_retries) != max_retries or max_retries < 0:
        raise ValueError(f"max_retries must be a whole number at least 0, got {max_retries!r}")
    console = console if console is not None else Console(stderr=True)
    if not isinstance(design, Design):
        design = load_design(design)
    points = design.points(overrides=overrides, quick=quick, max_stops=max_stops)
    base = design.resolved_base(overrides=overrides, quick=quick, max_stops=max_stops)

    out = Path(out_dir)
    runs = out / "runs"
    runs.mkdir(parents=True, exist_ok=True)
    stale = _remove_stale_temporaries(runs) + _remove_stale_temporaries(out)
    if stale:
        console.print(f"[dim]removed {len(stale)} temporary file(s) left by an interrupted run[/]")
    campaign_design = _write_design(
        out, design, base, overrides=overrides, quick=quick, max_stops=max_stops
    )

    records: dict[str, _Record] = {}
    todo: list[RunPoint] = []
    recomputed: list[str] = []
    reused: list[str] = []
    for point in execution_order(points):
        rid = run_id(point)
        path = runs / f"{rid}.nc"
        if path.exists():
            result, why = _load_existing(path, point)
            if result is not None:
                records[rid] = _record_from_result(point, rid, result)
                reused.append(rid)
                continue
            console.print(
                f"[yellow]warning:[/] {escape(str(path))} (test {point.test}, "
                f"replicate {point.replicate}) {escape(why)}; recomputing it"
            )
            recomputed.append(rid)
        todo.append(point)

    computed: list[str] = []
    failed: list[str] = []
    if todo:
        _execute_points(
            todo,
            runs,
            records,
            computed,
            failed,
            executor=executor,
            workers=workers,
            scheduler=scheduler,
            scheduler_file=scheduler_file,
            max_retries=int(max_retries),
            simulate_fn=simulate_fn,
            progress=progress,
            n_total=len(points),
            console=console,
        )
    elif progress:
        console.print(
            f"all {len(points)} runs of {escape(str(out))} already done; nothing to compute"
        )

    ordered = [records[run_id(p)] for p in points]
    summary = _summary_frame(design, ordered)
    dataset = _campaign_dataset(campaign_design, ordered, summary, base)
    atomic_write(out / "summary.csv", lambda tmp: summary.to_csv(tmp, index=False))
    atomic_write(out / "campaign.nc", lambda tmp: dataset.to_netcdf(tmp, engine="h5netcdf"))
    if failed:
        console.print(
            f"[red]{len(failed)} of {len(points)} run(s) failed[/]; "
            f"see {escape(str(out / 'summary.csv'))}"
        )
    return CampaignResult(
        out_dir=out,
        design=campaign_design,
        summary=summary,
        dataset=dataset,
        computed=tuple(computed),
        reused=tuple(reused),
        failed=tuple(failed),
        recomputed=tuple(recomputed),
    )


def _write_design(
    out: Path,
    design: Design,
    base: SimulationConfig,
    *,
    overrides: Mapping[str, Any] | None,
    quick: bool,
    max_stops: int | None,
) -> Design:
    """Write base_config.toml and design.toml; return the design they describe."""
    origin = f"preset {design.base!r}" if design.base is not None else repr(str(design.base_config))
    header = (
        f"# Resolved base configuration of campaign {design.name!r}, written by brakeca "
        f"{__version__}.\n# From {origin}; overrides {dict(overrides or {})!r}, "
        f"max_stops {max_stops!r}, quick {quick!r}.\n"
    )
    _write_text(out / "base_config.toml", header + base.to_toml())
    _write_text(
        out / "design.toml",
        f"# Design of campaign {design.name!r} (base: base_config.toml beside this file).\n"
        + design.to_toml(base_config="base_config.toml"),
    )
    return design.model_copy(
        update={"base": None, "base_config": (out / "base_config.toml").resolve()}
    )


class _Backend:
    """Where the runs go: submissions, capacity, and what a finished future means.

    The base class wraps any :class:`concurrent.futures.Executor` with a fixed number of
    calls in flight; it cannot replace a broken executor, so a run whose worker died is
    recorded as failed (dask retries such runs itself and then reports ``KilledWorker``).
    """

    #: Longest wait for a finished run before :meth:`free` is asked again [s]; None: no limit.
    poll: float | None = None

    def __init__(self, executor: cf.Executor, window: int, *, own: bool) -> None:
        self.executor = executor
        self.window = max(1, window)
        self.own = own
        self.in_flight = 0

    def free(self) -> int:
        """How many more runs may be submitted now."""
        return self.window - self.in_flight

    def submit(self, simulate_fn: SimulateFn | None, point: RunPoint) -> cf.Future:
        """Submit one run; a refused submission comes back as a failed future."""
        self.in_flight += 1
        try:
            return self.executor.submit(_execute, simulate_fn, point.config, point.seed)
        except Exception as exc:  # e.g. a broken executor owned by the caller
            future: cf.Future = cf.Future()
            future.set_exception(exc)
            return future

    def release(self, future: cf.Future) -> str | None:
        """Account for a finished future: the error text when its worker process died (the
        run may be tried again), None when the future holds the run's outcome."""
        self.in_flight -= 1
        return None

    def close(self, *, cancel: bool) -> None:
        """Shut the executor down when this campaign made it."""
        if self.own:
            self.executor.shutdown(wait=not cancel, cancel_futures=cancel)


class _DaskBackend(_Backend):
    """A :class:`DaskExecutor` with as many runs in flight as its workers have threads.

    Dask charges a worker's death to every task the worker holds, executing or waiting. With
    no more runs submitted than there are worker threads, a worker normally holds only the run
    it executes. The thread count is asked again every :attr:`poll` seconds, so workers that
    join late (a batch queue) get runs; with no worker yet, one run waits in the scheduler.
    """

    poll = 1.0

    def __init__(self, executor: DaskExecutor) -> None:
        super().__init__(executor, 1, own=True)
        self.client = executor.client

    def free(self) -> int:
        try:
            threads = sum(self.client.nthreads().values())
        except Exception:  # the scheduler is busy or gone: the runs in flight will tell
            threads = 0
        return max(threads, 1) - self.in_flight


class _LocalSlots(_Backend):
    """``workers`` one-process pools, each with at most one run in flight.

    A worker process that dies (killed, out of memory) breaks only its own pool, so the lost
    run is known exactly: the pool is replaced and the run may be tried again, while the
    runs of the other slots go on undisturbed.
    """

    def __init__(self, workers: int) -> None:
        self.pools: list[cf.ProcessPoolExecutor | None] = [None] * max(1, workers)
        self.busy: dict[cf.Future, int] = {}

    def free(self) -> int:
        return len(self.pools) - len(self.busy)

    def submit(self, simulate_fn: SimulateFn | None, point: RunPoint) -> cf.Future:
        taken = set(self.busy.values())
        slot = next(i for i in range(len(self.pools)) if i not in taken)
        pool = self.pools[slot]
        if pool is None:
            pool = self.pools[slot] = _local_pool(1)
        future = pool.submit(_execute, simulate_fn, point.config, point.seed)
        self.busy[future] = slot
        return future

    def release(self, future: cf.Future) -> str | None:
        slot = self.busy.pop(future)
        exc = None if future.cancelled() else future.exception()
        if not isinstance(exc, cf.BrokenExecutor):
            return None
        pool = self.pools[slot]
        self.pools[slot] = None  # a fresh process for the next run of this slot
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
        return _error_text(exc)

    def close(self, *, cancel: bool) -> None:
        pools = [p for p in self.pools if p is not None]
        self.pools = [None] * len(self.pools)
        for pool in pools:
            pool.shutdown(wait=not cancel, cancel_futures=cancel)


def _backend(
    executor: ExecutorKind | cf.Executor,
    workers: int | None,
    n_todo: int,
    *,
    scheduler: str | None,
    scheduler_file: str | Path | None,
    max_retries: int,
) -> _Backend:
    """The backend that runs ``n_todo`` runs on ``executor`` (see run_campaign)."""
    n_workers = (os.cpu_count() or 1) if workers is None else workers
    if isinstance(executor, cf.Executor):
        window = 1 if isinstance(executor, SerialExecutor) else 2 * max(1, n_workers)
        return _Backend(executor, window, own=False)
    if executor == "serial":
        return _Backend(SerialExecutor(), 1, own=True)
    if executor == "local":
        return _LocalSlots(max(1, min(n_workers, n_todo)))
    dask_executor = make_executor(
        "dask",
        max(1, min(n_workers, n_todo)),
        scheduler=scheduler,
        scheduler_file=scheduler_file,
        max_retries=max_retries,
    )
    return _DaskBackend(dask_executor)  # type: ignore[arg-type]


def _execute_points(
    todo: Sequence[RunPoint],
    runs: Path,
    records: dict[str, _Record],
    computed: list[str],
    failed: list[str],
    *,
    executor: ExecutorKind | cf.Executor,
    workers: int | None,
    scheduler: str | None,
    scheduler_file: str | Path | None,
    max_retries: int,
    simulate_fn: SimulateFn | None,
    progress: bool,
    n_total: int,
    console: Console,
) -> None:
    """Submit ``todo`` (a bounded number in flight), write each result as it comes back.

    A run whose worker process died goes back to the front of the queue until it has died
    ``max_retries + 1`` times, then it is recorded as failed; a run that raised is recorded
    as failed at once (the model is deterministic: it would raise again).
    """
    from rich.markup import escape
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    backend = _backend(
        executor,
        workers,
        len(todo),
        scheduler=scheduler,
        scheduler_file=scheduler_file,
        max_retries=max_retries,
    )
    bar = Progress(
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
        console=console,
        disable=not progress,
        transient=False,
    )
    queue = collections.deque(todo)
    pending: dict[cf.Future, RunPoint] = {}
    deaths: dict[str, int] = {}
    finished = False
    try:
        with bar:
            task = bar.add_task("runs", total=n_total, completed=n_total - len(todo))
            while queue or pending:
                while queue and backend.free() > 0:
                    point = queue.popleft()
                    pending[backend.submit(simulate_fn, point)] = point
                done, _ = cf.wait(
                    list(pending), timeout=backend.poll, return_when=cf.FIRST_COMPLETED
                )
                for future in sorted(done, key=lambda f: pending[f].order):
                    point = pending.pop(future)
                    rid = run_id(point)
                    death = backend.release(future)
                    if death is not None:
                        deaths[rid] = deaths.get(rid, 0) + 1
                        if deaths[rid] <= max_retries:
                            console.print(
                                f"[yellow]worker died:[/] test {point.test}, replicate "
                                f"{point.replicate} ({rid}): {escape(death)}; trying again "
                                f"({deaths[rid]} of {max_retries})"
                            )
                            queue.appendleft(point)
                            continue
                        times = "once" if deaths[rid] == 1 else f"{deaths[rid]} times"
                        error = (
                            f"the worker process died {times} while running it, not retried "
                            f"again (max_retries {max_retries}; last: {death})"
                        )
                        record = _Record(point, rid, "failed", error)
                    else:
                        record = _finish(future, point, runs)
                    records[rid] = record
                    (computed if record.status == "ok" else failed).append(rid)
                    if record.status != "ok":
                        console.print(
                            f"[red]run failed:[/] test {point.test}, replicate {point.replicate} "
                            f"({rid}): {escape(record.error)}"
                        )
                    bar.advance(task)
        finished = True
    finally:
        if not finished:
            for future in pending:
                future.cancel()
        backend.close(cancel=not finished)


def _finish(future: cf.Future, point: RunPoint, runs: Path) -> _Record:
    """Turn a finished future into a record, writing the run file when it succeeded."""
    rid = run_id(point)
    if future.cancelled():
        return _Record(point, rid, "failed", "the run was cancelled")
    try:
        result = future.result()
    except Exception as exc:
        return _Record(point, rid, "failed", _error_text(exc))
    problem = _check_result(result, point)
    if problem is not None:
        return _Record(point, rid, "failed", problem)
    try:
        result.to_netcdf(runs / f"{rid}.nc")  # atomic
    except Exception as exc:
        return _Record(point, rid, "failed", f"cannot write the run file: {_error_text(exc)}")
    return _record_from_result(point, rid, result)


def _error_text(exc: BaseException) -> str:
    """One line (for the CSV) naming the exception; a dask KilledWorker said plainly."""
    if type(exc).__name__ == "KilledWorker":
        tries = getattr(exc, "allowed_failures", None)
        worker = getattr(getattr(exc, "last_worker", None), "address", "?")
        times = "repeatedly" if tries is None else f"{int(tries) + 1} times"
        text = (
            f"KilledWorker: the worker process died {times} while running it (dask retried "
            f"it on other workers; last worker {worker}); not retried again"
        )
    else:
        text = f"{type(exc).__name__}: {exc}".strip()
    return " ".join(text.split())  # one line, for the CSV


# --- consolidation -------------------------------------------------------------------------

_FIRST_SCALARS = ("MU", "V", "V_mm3")


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
        "replicate": ("run", summary["replicate"].to_numpy(np.int64)),
        "order": ("run", summary["order"].to_numpy(np.int64), {"long_name": "execution order"}),
        "seed": ("run", summary["seed"].to_numpy(np.int64)),
        "run_id": ("run", np.array([r.run_id for r in records], dtype=object)),
        "status": ("run", np.array([r.status for r in records], dtype=object)),
        "error": ("run", np.array([r.error for r in records], dtype=object)),
        "stop": ("stop", np.arange(1, n_stop + 1)),
    }
    if longest is not None:
        if "block" in longest.coords:
            coords["block"] = ("stop", np.asarray(longest["block"].values, dtype=object))
        for name, coord in longest.coords.items():
            if name not in coords and "stop" not in coord.dims:
                coords[name] = coord.variable
    for factor in design.factors:
        values = np.asarray([r.point.levels[factor.name] for r in records])
        attrs = {
            "units": factor.unit,
            "long_name": factor.label or factor.name,
            "field": factor.field,
            "scale": factor.scale,
            "levels": np.asarray(factor.levels, dtype=float),
        }
        if factor.labels is not None:
            attrs["labels"] = list(factor.labels)
        coords[factor.name] = ("run", values, attrs)

    data_vars: dict[str, Any] = {}
    if longest is not None:
        for name in longest.data_vars:
            var = longest[name]
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
            data_vars[name] = (("run", "stop", *extra_dims), array, dict(var.attrs))
    for name in _scalar_names(records):
        if name in data_vars or name in coords:
            continue
        data_vars[name] = ("run", pd.to_numeric(summary[name], errors="coerce").to_numpy())
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
    except ValueError:
        pass
    try:
        floats = [math.nan if t == "" else float(t) for t in texts]
    except ValueError:
        return values.astype(object)
    return pd.Series(floats, index=values.index, dtype=np.float64)


def read_summary(path: str | Path) -> pd.DataFrame:
    """Read a ``summary.csv``, numbers bit-exact (Python's float parser, whatever pandas).

    Text columns (``run_id``, ``status``, ``error``) stay text, empty errors are ``""``.
    """
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    for name in frame.columns:
        if name in _TEXT_COLUMNS:
            frame[name] = frame[name].astype(object)
        else:
            frame[name] = _parse_column(frame[name])
    return frame


def load_campaign(out_dir: str | Path) -> CampaignResult:
    """Read a finished campaign directory.

    Returns
    -------
    CampaignResult
        Design (from ``design.toml``), summary (``summary.csv``) and dataset
        (``campaign.nc``, loaded into memory); the run-id tuples are empty.

    Raises
    ------
    FileNotFoundError
        A file is missing (the campaign has not finished).
    ConfigError
        ``design.toml`` is invalid.
    ValueError
        ``campaign.nc`` is not a brakeca campaign file.
    """
    out = Path(out_dir)
    for name in ("design.toml", "summary.csv", "campaign.nc"):
        if not (out / name).is_file():
            raise FileNotFoundError(
                f"{out / name}: missing; is {out} a finished campaign? (run it again to finish it)"
            )
    design = load_design(out / "design.toml")
    summary = read_summary(out / "summary.csv")
    try:
        dataset = xr.load_dataset(out / "campaign.nc", engine="h5netcdf")
    except Exception as exc:
        raise ValueError(f"{out / 'campaign.nc'}: not a readable netCDF file ({exc})") from None
    if dataset.attrs.get("format") != CAMPAIGN_FORMAT:
        raise ValueError(f"{out / 'campaign.nc'}: not a brakeca campaign file")
    return CampaignResult(out_dir=out, design=design, summary=summary, dataset=dataset)


def finish_campaign(
    out_dir: str | Path, *, steps: Iterable[Callable[[CampaignResult], Any]] = ()
) -> CampaignResult:
    """Post-process a finished campaign: load it and hand it to each step in turn.

    This is the hook the command line wires to the analysis, plots and report
    (:mod:`brakeca.analysis`, :mod:`brakeca.plotting`, :mod:`brakeca.report`); the campaign
    itself never calls them, so a campaign runs without any of them installed.

    Parameters
    ----------
    out_dir
        The campaign directory.
    steps
        Callables ``step(result)`` run in order; their return values are ignored.

    Returns
    -------
    CampaignResult
        As :func:`load_campaign`.
    """
    result = load_campaign(out_dir)
    for step in steps:
        step(result)
    return result


# --- python -m brakeca.campaign -----------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> int:
    """Minimal command line: ``python -m brakeca.campaign DESIGN OUT_DIR [options]``.

    Returns the exit status: 0 when every run finished, 1 when some failed, 2 on a
    configuration or executor error.
    """
    import argparse

    from brakeca.config import parse_override

    parser = argparse.ArgumentParser(prog="python -m brakeca.campaign", description=main.__doc__)
    parser.add_argument("design", help="shipped design name or design TOML file")
    parser.add_argument("out_dir", help="campaign directory")
    parser.add_argument("--executor", choices=list(EXECUTOR_KINDS), default="local")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS")
    parser.add_argument("--scheduler-file", default=None, metavar="PATH")
    parser.add_argument("--max-retries", type=int, default=DEFAULT_MAX_RETRIES)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--max-stops", type=int, default=None)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    try:
        overrides = dict(parse_override(text) for text in args.set)
        result = run_campaign(
            args.design,
            args.out_dir,
            workers=args.workers,
            executor=args.executor,
            scheduler=args.scheduler,
            scheduler_file=args.scheduler_file,
            max_retries=args.max_retries,
            quick=args.quick,
            max_stops=args.max_stops,
            overrides=overrides,
            progress=not args.no_progress,
        )
    except (ConfigError, ExecutorError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0 if result.ok else 1


if __name__ == "__main__":
    from brakeca.campaign import main as _main  # the importable module, so workers can pickle

    sys.exit(_main())
