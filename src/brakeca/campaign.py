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
        .brakeca.lock      the lock that keeps a second campaign out while one writes here

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
import csv
import math
import sys
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from brakeca._cachedir import source_key
from brakeca._consolidate import (
    CAMPAIGN_FORMAT,
    CampaignResult,
    _campaign_dataset,
    _summary_frame,
    load_campaign,
    read_summary,
)
from brakeca._executors import (
    DEFAULT_CHECKPOINT_EVERY,
    DEFAULT_MAX_RETRIES,
    EXECUTOR_KINDS,
    WORKER_ENV,
    DaskExecutor,
    ExecutorError,
    ExecutorKind,
    SerialExecutor,
    SimulateFn,
    _backend,
    _check_count,
    _check_scheduler,
    _Execution,
    check_dask_installed,
    make_executor,
    raise_if_interrupted,
    terminate_as_interrupt,
)
from brakeca._io import checkpoint_resumes, write_text
from brakeca._runstore import (
    BASE_HEADER,
    DESIGN_HEADER,
    CampaignLockedError,
    _finish,
    _load_existing,
    _Record,
    _record_from_result,
    _remove_stale_temporaries,
    _write_design,
    base_differences,
    campaign_lock,
    design_changes,
    edited_trace,
    existing_base,
    moved_trace,
)
from brakeca.config import ConfigError, SimulationConfig
from brakeca.cycle import cycle_events, map_stops
from brakeca.design import Design, RunPoint, execution_order, load_design, run_id

if TYPE_CHECKING:
    from rich.console import Console

    from brakeca.results import RunResult


__all__ = [
    "CAMPAIGN_FORMAT",
    "DEFAULT_CHECKPOINT_EVERY",
    "DEFAULT_MAX_RETRIES",
    "EXECUTOR_KINDS",
    "WORKER_ENV",
    "CampaignLockedError",
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


# --- the campaign --------------------------------------------------------------------------


def _seconds(t: float) -> str:
    """A run's wall time [s] for a progress line: a tenth of a second below 10 s."""
    return f"{t:.1f}" if t < 10.0 else f"{t:.0f}"


def _maps_for(maps_at: Iterable[int], points: Sequence[RunPoint]) -> list[int]:
    """``maps_at`` checked against the cycle of every run, before any work: the stops, in
    order (ConfigError names ``maps_at`` and the stops of the shortest cycle)."""
    if isinstance(maps_at, Iterable) and not isinstance(maps_at, str | bytes):
        maps_at = list(maps_at)  # (a generator is read once)
        if not maps_at:
            return []
    stops: dict[Any, int] = {}  # each cycle's stops, counted once
    for point in points:
        if point.config.cycle not in stops:
            stops[point.config.cycle] = len(cycle_events(point.config))
    try:
        return map_stops(maps_at, min(stops.values(), default=0))
    except ValueError as exc:  # a ConfigError, as the design's and the overrides' are
        shortest = " (the shortest of the design's cycles)" if len(set(stops.values())) > 1 else ""
        raise ConfigError(f"{exc}{shortest}") from None


def _kept_maps(result: RunResult) -> set[int]:
    """The stops after which a run kept its maps (``map_stop``; empty for none)."""
    ds = result.dataset
    return {int(k) for k in ds["map_stop"].to_numpy()} if "map_stop" in ds.coords else set()


def _checkpoint_path(runs: Path, point: RunPoint) -> Path:
    """Where the run of ``point`` in progress keeps its checkpoint: ``runs/.<run_id>...``."""
    return runs / f".{run_id(point)}.checkpoint.npz"


def run_campaign(
    design: Design | str | Path,
    out_dir: str | Path,
    *,
    workers: int | None = None,
    executor: ExecutorKind | cf.Executor = "local",
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    max_retries: int = DEFAULT_MAX_RETRIES,
    checkpoint_every: int | None = DEFAULT_CHECKPOINT_EVERY,
    quick: bool = False,
    max_stops: int | None = None,
    overrides: Mapping[str, Any] | None = None,
    simulate_fn: SimulateFn | None = None,
    progress: bool | Callable[[int, int], object] = True,
    console: Console | None = None,
    replace: bool = False,
    maps_at: Iterable[int] = (),
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
    checkpoint_every
        Each run in progress saves its state every this many stops to
        ``runs/.<run_id>.checkpoint.npz``, so a campaign killed in the middle of a long run
        resumes that run from its last checkpoint, bit-identically; the file goes once the
        run's file is written. None: no checkpoints. The worker writes it, so on a cluster
        the campaign folder must be on a file system the workers share (else the checkpoints
        are lost, and only the finished runs are reused).
    quick
        Narrow every run's band with :func:`brakeca.design.quick_config`.
    max_stops
        Run only the first ``max_stops`` stops of the cycle [-].
    overrides
        Dotted-key (or factor-alias) configuration updates applied to every run before the
        factor levels.
    simulate_fn
        Module-level (picklable) function with the signature of
        :func:`brakeca.simulation.simulate`; None uses that function. The local executor's
        workers run the caller's main module only for a ``simulate_fn`` of the caller's (to
        find it): a script that passes one must call this under
        ``if __name__ == "__main__":``; with None no guard is needed.
    progress
        Show a progress bar over the runs, with an ETA, and a line per finished run; or a
        function ``progress(done, total)``, called as each run finishes (or fails) with the
        runs done so far and all the design's runs, reused ones counted [-], with no bar and
        no lines (as :func:`brakeca.simulation.simulate` takes one per stop); once, with
        ``done == total``, where every run is reused.
    console
        Where messages and the progress bar go; None: a console on standard error.
    replace
        Write into a folder that holds a campaign of another base configuration (other
        overrides, ``quick`` or ``max_stops``), replacing its ``summary.csv``,
        ``campaign.nc`` and report; the run files of both stay. Without it that is refused,
        since a rerun with other options would quietly replace a finished study. A campaign
        of the same base (a resume, a fold-over) needs no flag.
    maps_at
        Stops (numbered from 1) after which every run keeps the pad's status and height maps
        (:func:`brakeca.simulation.simulate`'s ``maps_at``); the report then shows each run's
        plateaus over the cycle. Keeping them changes no result and no run id, so a finished
        run is reused as it is: one that ran without these maps is kept without them (a
        warning names it; delete its file to run it again with them). A run resumed from a
        checkpoint that ran a stop of ``maps_at`` without its map starts over.

    Returns
    -------
    CampaignResult
        The summary and consolidated dataset, also written to ``summary.csv`` and
        ``campaign.nc``. A run that raised has status ``"failed"`` and its error message;
        the others are unaffected.

    Raises
    ------
    ConfigError
        The design, an override or a level does not validate, a stop of ``maps_at`` is not
        one of the cycle's (also with ``max_stops``), or ``out_dir`` holds a campaign
        of another base configuration, or of a design whose runs this one leaves out, and
        ``replace`` is false (before anything is written).
    ValueError
        An unknown executor, ``workers`` below 1, ``max_retries`` below 0, or a scheduler
        that does not go with the executor (before anything is written); a
        :class:`~brakeca.config.ConfigError` (a ValueError) if ``out_dir`` is a file.
    ExecutorError
        ``"dask"``: dask.distributed is missing or the scheduler cannot be reached (after the
        design files are written, before any run starts).
    CampaignLockedError
        Another campaign is writing ``out_dir`` (before anything is written).
    KeyboardInterrupt
        Ctrl-C, or SIGTERM or SIGHUP while the runs are computed (in the main thread, where
        the program has not set its own handler): the local workers are stopped at once, and
        the finished runs' files and the runs in progress's checkpoints are kept, so the same
        call resumes.
    """
    from rich.console import Console

    if isinstance(executor, str) and executor not in EXECUTOR_KINDS:
        raise ValueError(f"unknown executor {executor!r}; choose 'serial', 'local' or 'dask'")
    _check_scheduler(executor, scheduler, scheduler_file)
    if executor == "dask":
        check_dask_installed()  # before the folder is written or the kernels compiled
    _check_count("workers", workers, 1)
    _check_count("max_retries", max_retries, 0)
    if checkpoint_every is not None and (
        isinstance(checkpoint_every, bool)
        or int(checkpoint_every) != checkpoint_every
        or checkpoint_every < 1
    ):
        raise ValueError(
            f"checkpoint_every must be a whole number at least 1 (or None: off), got "
            f"{checkpoint_every!r}"
        )
    console = console if console is not None else Console(stderr=True)
    if not isinstance(design, Design):
        design = load_design(design)
    points = design.points(overrides=overrides, quick=quick, max_stops=max_stops)
    base = design.resolved_base(overrides=overrides, quick=quick, max_stops=max_stops)
    kept_maps = _maps_for(maps_at, points)

    how = _Execution(
        executor=executor,
        workers=workers,
        scheduler=scheduler,
        scheduler_file=scheduler_file,
        max_retries=int(max_retries),
        checkpoint_every=checkpoint_every,
        simulate_fn=simulate_fn,
        progress=bool(progress) and not callable(progress),
        maps_at=tuple(kept_maps),
        on_run=progress if callable(progress) else None,
    )
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out}: exists and is not a folder; name a campaign folder")
    theirs = _foreign_design(out)
    if theirs is not None:
        raise ConfigError(theirs)
    with campaign_lock(out):
        return _run_locked(
            design,
            points,
            base,
            out,
            how,
            quick=quick,
            max_stops=max_stops,
            overrides=overrides,
            console=console,
            replace=replace,
        )


def _foreign_design(out: Path) -> str | None:
    """Why a campaign must not start in ``out``: its ``design.toml`` is a file brakeca did
    not write (a user's design kept there), which the campaign would write over with its
    own; None otherwise. A campaign's own design.toml starts with brakeca's header, and a
    folder with brakeca's base_config.toml holds a campaign whatever its design.toml says
    (one edited by hand)."""
    design, base = out / "design.toml", out / "base_config.toml"
    if not design.is_file():
        return None

    def first_line(path: Path) -> str:
        try:
            with path.open(encoding="utf-8") as handle:
                return handle.readline()
        except (OSError, UnicodeDecodeError):
            return ""

    if first_line(design).startswith(DESIGN_HEADER) or first_line(base).startswith(BASE_HEADER):
        return None
    return (
        f"{design}: a design file brakeca did not write; a campaign writes its own "
        f"design.toml into its folder {out} and would replace this one. Keep your design "
        f"outside the folder (e.g. {out.parent / (out.name + '_design.toml')}) or name "
        "another folder with -o"
    )


def _run_locked(
    design: Design,
    points: list[RunPoint],
    base: SimulationConfig,
    out: Path,
    how: _Execution,
    *,
    quick: bool,
    max_stops: int | None,
    overrides: Mapping[str, Any] | None,
    console: Console,
    replace: bool = False,
) -> CampaignResult:
    """The body of :func:`run_campaign`, run while the campaign directory is locked."""
    from rich.markup import escape

    from brakeca._console import say, tests_named

    runs = out / "runs"
    runs.mkdir(parents=True, exist_ok=True)
    stale = _remove_stale_temporaries(runs) + _remove_stale_temporaries(out)
    if stale:
        say(console, f"[dim]removed {len(stale)} temporary file(s) left by an interrupted run[/]")
    if not replace:
        changes = design_changes(out, design)
        _refuse_to_replace(out, base, points, design.root_seed, changes)
        if changes:
            say(
                console,
                f"[dim]design.toml: this design replaces the folder's ({escape(changes)}); "
                "the runs of the folder's design done so far are all among its runs[/]",
            )
    # a folder that holds a study gets the design and base with the summary, after the runs:
    # a campaign stopped or failed before then (a --replace whose cluster is unreachable,
    # Ctrl-C) leaves that study whole. A new folder gets them now, so that a first campaign
    # stopped halfway resumes from FOLDER/design.toml, and its options are checked on resume
    written = (
        None
        if (out / "summary.csv").is_file()
        else _write_design(out, design, base, overrides=overrides, quick=quick, max_stops=max_stops)
    )

    records: dict[str, _Record] = {}
    todo: list[RunPoint] = []
    recomputed: list[str] = []
    reused: list[str] = []
    without_maps: list[RunPoint] = []  # reused runs that lack a map maps_at asks for
    other_kernels: list[RunPoint] = []  # reused runs made by other kernel sources
    here = source_key()
    wanted: set[str] = set()
    for point in execution_order(points):
        rid = run_id(point)
        wanted.add(rid)
        path = runs / f"{rid}.nc"
        if path.exists():
            result, why = _load_existing(path, point)
            if result is not None:
                records[rid] = _record_from_result(point, rid, result)
                reused.append(rid)
                if not set(how.maps_at) <= _kept_maps(result):
                    without_maps.append(point)
                if result.dataset.attrs.get("source_key") != here:  # (None: made before
                    other_kernels.append(point)  # run files recorded it: a diff review)
                # a campaign killed between writing the run file and removing the checkpoint
                _checkpoint_path(runs, point).unlink(missing_ok=True)
                continue
            say(
                console,
                f"[yellow]warning:[/] {escape(str(path))} (test {point.test}, "
                f"replicate {point.replicate}) {escape(why)}; recomputing it",
            )
            recomputed.append(rid)
        todo.append(point)

    if without_maps:
        say(
            console,
            f"[yellow]warning:[/] {len(without_maps)} finished run(s) (of "
            f"{tests_named(p.test for p in without_maps)}) "
            f"ran without keeping maps after stops {', '.join(map(str, how.maps_at))}; they "
            "are reused as they are, without those maps. Delete their run files in "
            f"{escape(str(runs))} to run them again with the maps",
            highlight=False,
        )

    if other_kernels:
        # a provenance review: the version alone did not tell another code's runs apart
        say(
            console,
            f"[yellow]note:[/] {len(other_kernels)} finished run(s) (of "
            f"{tests_named(p.test for p in other_kernels)}) were made by other kernel "
            f"sources than this install's (source_key {here}; the run files record theirs, "
            "or, made before run files recorded it, none); "
            "they are reused as they are, and a run made now may differ from them (in the "
            "last bits where the change kept the model). Delete their run files in "
            f"{escape(str(runs))} to run them again",
            highlight=False,
        )

    foreign = sorted(f.name for f in runs.glob("*.nc") if f.stem not in wanted)
    if foreign:
        say(
            console,
            f"[dim]{len(foreign)} run file(s) in {escape(str(runs))} belong to no run of this "
            "design (another design or configuration run in the same folder: an earlier "
            "one, or one stopped before its summary); they are left as they are and not "
            "analysed[/]",
        )
    begun = sorted(
        f.name
        for f in runs.glob(".*.checkpoint.npz")
        if f.name.removeprefix(".").removesuffix(".checkpoint.npz") not in wanted
    )
    if begun:  # (a robustness review: a design.toml edited in a stopped campaign's folder
        # left the run it had begun behind without a word)
        say(
            console,
            f"[yellow]note:[/] {len(begun)} checkpoint(s) in {escape(str(runs))} are of runs "
            "begun by another design or configuration run in this folder (an earlier one, or "
            "one stopped before its summary), none of this one; they are left as they are "
            "(that design, run again here, resumes them; delete them to free the space)",
            highlight=False,
        )

    computed: list[str] = []
    failed: list[str] = []
    if todo:
        from brakeca.traces import check_trace_unchanged

        checked: set[tuple[str | None, str | None]] = set()
        for point in todo:  # a changed trace fails every run: refuse it before any is run
            key = (point.config.cycle.trace_file, point.config.cycle.trace_sha256)
            if key not in checked:
                checked.add(key)
                check_trace_unchanged(point.config)
        with terminate_as_interrupt():  # SIGTERM, SIGHUP: stop the workers, keep what is done
            _execute_points(
                todo, runs, records, computed, failed, how, n_total=len(points), console=console
            )
    else:
        if how.progress:
            say(
                console,
                f"all {len(points)} runs of {escape(str(out))} already done; nothing to compute",
            )
        if how.on_run is not None:  # a notebook's bar completes (an API review: never called)
            how.on_run(len(points), len(points))

    ordered = [records[run_id(p)] for p in points]
    summary = _summary_frame(design, ordered)
    campaign_design = written or _write_design(
        out, design, base, overrides=overrides, quick=quick, max_stops=max_stops
    )
    dataset = _campaign_dataset(campaign_design, ordered, summary, base)
    summary_text = summary.to_csv(index=False)
    replaced, why = _stale_analysis(out, summary_text)
    write_text(out / "summary.csv", summary_text)
    if replaced:
        say(console, f"[dim]removed the earlier study's analysis ({', '.join(replaced)}): {why}[/]")
    from brakeca.results import write_atomic  # made in memory: a full disk is an OSError

    write_atomic(dataset, out / "campaign.nc")
    if failed:
        say(
            console,
            f"[red]{len(failed)} of {len(points)} run(s) failed[/]; "
            f"see {escape(str(out / 'summary.csv'))}",
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


def _without_wall_time(summary_text: str) -> str:
    """A summary.csv's text without its ``wall_time`` column, to tell a run computed again
    with the same results (in another time) from another study."""
    import io

    rows = list(csv.reader(io.StringIO(summary_text)))
    if not rows or "wall_time" not in rows[0]:
        return summary_text
    drop = rows[0].index("wall_time")
    return "\n".join(",".join(row[:drop] + row[drop + 1 :]) for row in rows)


def _columns_added(before: str, after: str) -> list[str]:
    """The columns ``after`` (a summary.csv's text) adds to ``before`` where it is otherwise
    the same, its runs' values equal but their wall time: the same study written by a version
    of brakeca with more run scalars (MU_SD); empty otherwise."""
    import io

    old = list(csv.reader(io.StringIO(before)))
    new = list(csv.reader(io.StringIO(after)))
    if not old or not new or len(old) != len(new):
        return []
    added = [c for c in new[0] if c not in old[0]]
    if not added or any(c not in new[0] for c in old[0]):
        return []
    if any(len(r) != len(old[0]) for r in old) or any(len(r) != len(new[0]) for r in new):
        return []
    mine = [k for k, c in enumerate(old[0]) if c != "wall_time"]
    theirs = [new[0].index(old[0][k]) for k in mine]
    same = all(
        [row[k] for k in mine] == [other[k] for k in theirs]
        for row, other in zip(old[1:], new[1:], strict=True)
    )
    return added if same else []


def _runs_kept(before: str, after: str) -> tuple[int, int, int] | None:
    """``(n_before, n_after, n_kept)``: the runs of ``before`` and ``after`` (two
    summary.csv's texts) and how many of ``before``'s are runs of ``after`` with the same
    results (numbers compared as numbers: a design grown to a composite one writes a level
    10 as ``10.0``; a growth review); None where they share none, or cannot be read."""
    import io

    import pandas as pd

    try:
        old = pd.read_csv(io.StringIO(before), dtype=str, keep_default_na=False)
        new = pd.read_csv(io.StringIO(after), dtype=str, keep_default_na=False)
    except (ValueError, pd.errors.ParserError):
        return None
    if "run_id" not in old.columns or "run_id" not in new.columns or old.empty:
        return None  # (a summary of no run: nothing kept to speak of)
    shared = [c for c in old.columns if c in new.columns and c not in ("wall_time", "order")]
    theirs = new[shared].drop_duplicates("run_id").set_index("run_id")
    kept = 0
    for _, row in old[shared].iterrows():
        rid = row["run_id"]
        if rid in theirs.index and all(
            _same_cell(row[c], theirs.at[rid, c]) for c in shared if c != "run_id"
        ):
            kept += 1
    return (len(old), len(new), kept) if kept else None


def _same_cell(a: str, b: str) -> bool:
    """Whether two summary.csv cells say the same: equal text, or equal numbers (NaN equal
    to NaN)."""
    if a == b:
        return True
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return x == y or (x != x and y != y)


def _stale_analysis(out: Path, summary_text: str) -> tuple[list[str], str]:
    """Remove the analysis (report.html, tables/, figures/) of the study in ``out`` when the
    summary about to be written (``summary_text``, summary.csv's text) differs from the one
    there (another study, more replicates, failed runs computed again): it would describe
    runs that are no longer the folder's study, and a campaign run without its report
    (``--no-report``) would leave it there. Returns what was removed, and why."""
    import shutil

    path = out / "summary.csv"
    if not path.is_file():
        return [], ""
    try:  # the text summary.csv gets: equal text is an equal study, failed runs and all
        before = path.read_text(encoding="utf-8")
        why = (
            # a run computed again (its file deleted to keep maps, or damaged) with the same
            # results: the analysis's maps and notes of that run's file may be out of date,
            # so it goes too, said as it is (it was "of other runs": a robustness review)
            "runs of it were computed again, with the same results; 'brakeca analyze "
            f"{out}' writes it anew"
            if _without_wall_time(before) == _without_wall_time(summary_text)
            else "it was of other runs"
        )
        kept = _runs_kept(before, summary_text)
        if kept is not None and kept[2] == kept[0] and kept[1] > kept[0]:
            # replicates or tests added (a new user's review: "other runs")
            why = f"it was of {kept[0]} of these {kept[1]} runs (this design adds the others)"
        elif kept is not None and kept[0] == kept[1] == kept[2] and why.endswith("other runs"):
            why = (  # the same runs and results, written otherwise (10 as 10.0)
                f"it was of these runs, with the same results; 'brakeca analyze {out}' writes "
                "it anew"
            )
        elif kept is not None and kept[2] < kept[0]:  # (--replace by a design of some of
            # them: "other runs" hid those kept, a growth review)
            why = (
                f"it was of {kept[0]} runs, {kept[2]} of them among these {kept[1]} with the "
                "same results"
            )
        added = _columns_added(before, summary_text)
        if added:  # a folder of an earlier version (a session's own rerun said "other runs")
            why = (
                f"this version of brakeca adds {', '.join(added)} to summary.csv, the runs' "
                f"results the same; 'brakeca analyze {out}' writes it anew"
            )
    except (OSError, UnicodeDecodeError, csv.Error):
        before, why = "", "it was of other runs"
    if before == summary_text:
        return [], ""
    removed = []
    for name in ("report.html", "tables", "figures"):
        target = out / name
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        elif target.exists() or target.is_symlink():
            target.unlink()
        else:
            continue
        removed.append(name + ("/" if name != "report.html" else ""))
    return removed, why


def _refuse_to_replace(
    out: Path,
    base: SimulationConfig,
    points: Sequence[RunPoint],
    root_seed: int | None = None,
    changes: str = "",
) -> None:
    """Raise ConfigError if ``out`` holds a study that a campaign of ``base`` and the runs
    ``points`` would replace: one of another base configuration, or of a design whose runs
    it leaves out (another ``root_seed``, the new design's, is named, and ``changes``, how
    the design differs from the folder's, :func:`design_changes`)."""
    old = existing_base(out)
    changed = base_differences(old, base)
    if changed:
        shown = "; ".join(changed[:4]) + (
            f"; and {len(changed) - 4} more" if len(changed) > 4 else ""
        )
        what, first, after = "a campaign of another base configuration", "campaign's command", ""
        moved = moved_trace(old, base)
        if moved is not None:  # (a determinism review: the same trace, copied elsewhere)
            after = (
                ". Its trace has the same content (SHA-256) at another path, but a run "
                "records its trace by its path, so these would be other runs: give the trace "
                f"at its first path ({moved}) to resume them"
            )
        elif (edited := edited_trace(old, base)) is not None:
            # the first campaign's command is this one: a review found that advice circular
            first = "campaign's command, with its trace as it was"
            after = (
                f". Its trace {edited} has other content (SHA-256) than when the campaign "
                "ran, so these would be other runs"
            )
    else:
        shown, renumbered = _runs_left_out(out, points, root_seed)
        if not shown:
            return
        remade = "" if renumbered else _remade_note(out, points)
        if remade:  # the design's own runs, of other values: not "another design" (a diff
            # review: --replace, the advice for one, would have set the study aside)
            raise ConfigError(
                f"{out} holds this design's study with other values than those given now "
                f"({remade}): its base_config.toml was edited, or the options differ (--set, "
                "--stops, --quick). Put them back as the runs have them to resume or extend "
                "that study, or run these values into a folder of their own (--replace here "
                "would replace its summary.csv and report.html; its run files are kept)"
            )
        what, first = "the study of another design", "design"
        if not (out / "summary.csv").is_file():
            what = "another design's runs"
        said = [
            c
            for c in changes.split("; ")
            if c and not (c.startswith("root_seed ") and "root_seed" in shown)
        ]
        if said:  # what differs (a growth review: only counts were said, and a hint that
            # named another cause); a root seed said above, with what it does, not again
            more = f"; and {len(said) - 4} more" if len(said) > 4 else ""
            shown += f"; this design differs from it in {'; '.join(said[:4])}{more}"
        after = (
            ". A design that keeps every run of the study there and adds others (more "
            "replicates, centre points, a fold-over of a design without centre points, a "
            "level after the last level of the last factor) needs neither"
        )
        if renumbered:
            after += (
                f". {renumbered} of the runs left out are configurations this design also "
                "runs, under other test numbers: a run's seed follows its test number (and "
                "replicate), so those are other runs. A level added anywhere but after the "
                "last level of the last factor, the factors put in another order, a factor "
                "added (but last, with its first level the base configuration's value), or "
                "tests put before the centre points (a fold-over, a composite design's axial "
                "points) numbers the tests anew"
            )
    replaced = "summary.csv and report.html" if (out / "report.html").is_file() else "summary.csv"
    back = "brings its study back"
    if not (out / "summary.csv").is_file():
        replaced, back = "design.toml and leave those runs out", "resumes its campaign"
    raise ConfigError(
        f"{out} holds {what} ({shown}): this one would replace its {replaced}. Give another "
        "folder, or replace it on purpose (--replace; replace=True "
        f"from Python): the run files of both are kept, and the first {first}, run again "
        f"with --replace, {back}{after}"
    )


def _runs_left_out(
    out: Path, points: Sequence[RunPoint], root_seed: int | None = None
) -> tuple[str, int]:
    """What the study already in ``out`` has that a campaign of ``points`` would leave out of
    its summary: e.g. ``"design 'screen', 16 runs, 16 of them not in this one"`` (empty when
    there is no study there or every run of it is in ``points``), and how many of the runs
    left out have a combination of levels that ``points`` also has (under another test
    number, so another seed)."""
    path = out / "summary.csv"
    if not path.is_file():
        return _unfinished_left_out(out, points), 0
    try:
        old = read_summary(path)
        ids = set(old["run_id"].astype(str))
    except Exception:  # a damaged summary is rebuilt from the run files: nothing to keep
        return "", 0
    missing = ids - {run_id(p) for p in points}
    if not missing:
        return "", 0
    name, seed_there = "?", None
    try:
        import tomllib

        there = tomllib.loads((out / "design.toml").read_text(encoding="utf-8"))
        name, seed_there = str(there["name"]), there.get("root_seed")
    except Exception:
        pass
    # left out, of a configuration this design runs under another test number (so another
    # seed): compared whole, since the study there may set fields this design leaves at the
    # base (a review: runs of another elastic modulus had been counted by the shared
    # factors' levels alone)
    renumbered = 0
    try:
        earlier = load_design(out / "design.toml").points()
    except Exception:  # a design.toml this version cannot read: nothing to compare
        earlier = []
    tests_of: dict[str, set[int]] = {}
    for p in points:
        tests_of.setdefault(p.config.model_dump_json(), set()).add(p.test)
    for p in earlier:
        if run_id(p) in missing:
            ours = tests_of.get(p.config.model_dump_json(), set())
            renumbered += bool(ours) and p.test not in ours
    seeds = (
        f"; its root_seed is {seed_there}, this design's {root_seed}: every run's seed differs"
        if root_seed is not None and isinstance(seed_there, int) and seed_there != root_seed
        else ""
    )
    shown = f"design {name!r}, {len(ids)} runs, {len(missing)} of them not in this one{seeds}"
    return shown, renumbered


def _same_level(a: Any, b: Any) -> bool:
    """Whether two levels are the same: as text, or as numbers to a relative 1e-9 (a CSV's
    round trip)."""
    if str(a) == str(b):
        return True
    try:
        return math.isclose(float(a), float(b), rel_tol=1e-9, abs_tol=0.0)
    except (TypeError, ValueError):
        return False


def _remade_note(out: Path, points: Sequence[RunPoint]) -> str:
    """Where a test and replicate of the study in ``out`` left out by ``points`` is one of
    them, of the same factors, levels and seed, with another configuration (an edited
    base_config.toml, another --set): the fields that differ, from the run file's own
    configuration, e.g. ``"test 1: vehicle.wheel_load_mass: 690.0 -> 700.0"``; empty
    otherwise (a robustness review: an edited base_config.toml had been called another
    design, naming no field)."""
    from brakeca._io import config_changes
    from brakeca.config import run_file_settings

    try:
        old = read_summary(out / "summary.csv")
    except Exception:  # no summary (or a damaged one): nothing to compare
        return ""
    missing = set(old["run_id"].astype(str)) - {run_id(p) for p in points}
    ours = {(p.test, p.replicate): p for p in points}
    try:  # the factors of the study there: another design's test is not "the run there"
        names = set(load_design(out / "design.toml").factor_names)
    except Exception:
        return ""
    for row in old.to_dict("records"):
        run, status = str(row.get("run_id", "")), row.get("status", "")
        key = (int(row.get("test", 0)), int(row.get("replicate", 0)))
        if run not in missing or status != "ok" or key not in ours:
            continue
        point = ours[key]
        same = (
            set(point.levels) == names
            and int(row.get("seed", -1)) == point.seed
            and all(_same_level(row.get(n), v) for n, v in point.levels.items())
        )
        if not same:
            continue
        try:
            made = SimulationConfig.from_toml(run_file_settings(out / "runs" / f"{run}.nc").config)
        except Exception:  # no run file, or one this version cannot read: nothing to name
            continue
        changed = config_changes(made.to_dict(), point.config.to_dict())
        if not changed:
            continue
        shown = "; ".join(changed[:3]) + (
            f"; and {len(changed) - 3} more" if len(changed) > 3 else ""
        )
        return f"test {key[0]}: {shown}"
    return ""


def _unfinished_left_out(out: Path, points: Sequence[RunPoint]) -> str:
    """What a first campaign in ``out``, stopped before it wrote its summary, has done or
    begun (run files, checkpoints in ``runs/``) that a campaign of ``points`` would leave
    out, e.g. ``"the unfinished campaign of design 'tiny': 2 of its runs, done or begun,
    not in this one"``; empty when there is none (a robustness review: such a folder took
    another design without a word, its checkpoints left behind for good)."""
    runs = out / "runs"
    if not (out / "design.toml").is_file() or not runs.is_dir():
        return ""
    try:  # the runs of the folder's own design (design.toml and base_config.toml): the files
        # of a design an earlier --replace left behind are not its (a diff review found the
        # folder's own design refused for them)
        there = load_design(out / "design.toml")
        theirs = {run_id(p) for p in there.points()}
        name = there.name
    except Exception:  # a design.toml this version cannot read: nothing to hold to
        return ""
    started = {f.stem for f in runs.glob("*.nc")} | {
        f.name.removeprefix(".").removesuffix(".checkpoint.npz")
        for f in runs.glob(".*.checkpoint.npz")
    }
    missing = (started & theirs) - {run_id(p) for p in points}
    if not missing:
        return ""
    return (
        f"the unfinished campaign of design {name!r}: {len(missing)} of its runs, done or "
        "begun, not in this one"
    )


def _execute_points(
    todo: Sequence[RunPoint],
    runs: Path,
    records: dict[str, _Record],
    computed: list[str],
    failed: list[str],
    how: _Execution,
    *,
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

    from brakeca._console import say, tests_named

    max_retries = how.max_retries
    on_this_machine = how.executor in ("local", "serial") or (
        how.executor == "dask" and how.scheduler is None and how.scheduler_file is None
    )
    if on_this_machine and how.simulate_fn is None:
        # compile the kernels once, in a child process, before the runs start: the workers
        # (or this process) load them from the cache instead of each compiling them (time,
        # and the compiler's ~180 MB per process)
        from brakeca._warmup import warm_up

        warmed = warm_up(p.config for p in todo)
        if warmed is not None and how.progress:
            say(console, f"[dim]kernels compiled or loaded in a child process ({warmed:.1f} s)[/]")
    backend = _backend(
        how.executor,
        how.workers,
        len(todo),
        scheduler=how.scheduler,
        scheduler_file=how.scheduler_file,
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
        # in a log file (not a terminal, nor a notebook) the runs' lines alone: the bar's
        # last state had come out as one more line at the end
        disable=not how.progress or not (console.is_terminal or console.is_jupyter),
        transient=False,
    )
    resuming: set[str] = set()  # the runs that go on from a checkpoint
    if how.progress:
        unusable = 0
        for p in todo:  # with checkpoints off too: a run resumes from one written before
            path = _checkpoint_path(runs, p)
            if checkpoint_resumes(path, p.config, p.seed, how.maps_at):
                resuming.add(run_id(p))
            elif path.exists():  # damaged, another run's, or without a map asked for
                unusable += 1
        resumed = len(resuming)
        if not console.is_terminal or resumed or unusable:  # the bar shows no resumption
            say(
                console,
                f"{len(todo)} of {n_total} run(s) to compute ({n_total - len(todo)} already done"
                + (f"; {resumed} resumed from a checkpoint" if resumed else "")
                + (
                    f"; {unusable} with a checkpoint that cannot be used (damaged, of another "
                    "run, or without a map asked for), started over"
                    if unusable
                    else ""
                )
                + ")",
                highlight=False,
            )
    queue = collections.deque(todo)
    pending: dict[cf.Future, RunPoint] = {}
    deaths: dict[str, int] = {}
    elsewhere: list[tuple[RunPoint, str | None]] = []  # runs made by other kernel sources
    here = source_key()  # (it reads the kernels' sources: once, not at every run)
    finished = False
    try:
        with bar:
            task = bar.add_task("runs", total=n_total, completed=n_total - len(todo))
            while queue or pending:
                raise_if_interrupted()  # a Ctrl-C Python dropped in a callback (a review)
                while queue and backend.free() > 0:
                    point = queue.popleft()
                    options: dict[str, Any] = {}
                    checkpoint = _checkpoint_path(runs, point)
                    # absolute: a worker started in another folder (a cluster's) read a
                    # relative -o from its own and ran without checkpoints (a cluster
                    # review)
                    if how.checkpoint_every is not None:
                        options["checkpoint"] = checkpoint.absolute()
                        options["checkpoint_every"] = int(how.checkpoint_every)
                    elif checkpoint.is_file():
                        # checkpoints off: a run resumes from one written before, and
                        # writes no more (no stop index reaches this)
                        options["checkpoint"] = checkpoint.absolute()
                        options["checkpoint_every"] = 2**62
                    if how.maps_at:
                        options["maps_at"] = how.maps_at
                    pending[backend.submit(how.simulate_fn, point, options)] = point
                bar.update(task, description=f"runs ({len(pending)} running)")
                if pending:
                    done, _ = cf.wait(
                        list(pending), timeout=backend.poll, return_when=cf.FIRST_COMPLETED
                    )
                else:  # none could be submitted (a dask client reconnecting): wait a while
                    done = set()
                    time.sleep(backend.poll or 0.1)
                if (why := backend.lost()) is not None:  # before its cancelled runs count
                    raise ExecutorError(
                        f"{why}; the finished runs (and checkpoints) in {runs.parent} are "
                        "kept, and the same command resumes once a scheduler is there"
                    )
                if (note := backend.waiting()) is not None:
                    say(console, f"[yellow]note:[/] {note}", highlight=False)
                _say_deaths(console, backend.news(), max_retries)
                for future in sorted(done, key=lambda f: pending[f].order):
                    point = pending.pop(future)
                    rid = run_id(point)
                    if backend.interrupted(future):  # run again once the link is back
                        backend.release(future)
                        queue.appendleft(point)
                        continue
                    death = backend.release(future)
                    if death is not None:
                        deaths[rid] = deaths.get(rid, 0) + 1
                        if deaths[rid] <= max_retries:
                            say(
                                console,
                                f"[yellow]worker died:[/] test {point.test}, replicate "
                                f"{point.replicate} ({rid}): {escape(death)}; trying again "
                                f"({deaths[rid]} of {max_retries})",
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
                        if record.status == "ok":
                            # the run file is written: its checkpoint can go (the worker
                            # leaves it, so that a campaign killed before this resumes it)
                            _checkpoint_path(runs, point).unlink(missing_ok=True)
                            if how.simulate_fn is None and record.source_key != here:
                                elsewhere.append((point, record.source_key))
                    records[rid] = record
                    (computed if record.status == "ok" else failed).append(rid)
                    if record.status != "ok":
                        say(
                            console,
                            f"[red]run failed:[/] test {point.test}, replicate {point.replicate} "
                            f"({rid}): {escape(record.error)}",
                        )
                    elif how.progress:
                        # a line per run, in a log file (no live bar there) and above the
                        # terminal's bar (which counted whole runs alone, for minutes on end
                        # at full resolution: a robustness review)
                        sc = record.scalars
                        say(
                            console,
                            f"run {n_total - len(todo) + len(computed) + len(failed)}/{n_total} "
                            f"done: test {point.test}, replicate "
                            f"{point.replicate} ({rid}) in {_seconds(sc['wall_time'])} s"
                            + (" in all, resumed from a checkpoint" if rid in resuming else "")
                            + ": "
                            f"MU {sc['MU']:.4f}, V {sc['V_mm3']:.4g} mm³/stop",
                            highlight=False,
                        )
                    bar.advance(task)
                    if how.on_run is not None:  # (a notebook's own progress: an API review)
                        how.on_run(n_total - len(todo) + len(computed) + len(failed), n_total)
            _say_deaths(console, backend.news(), max_retries)  # (a death logged last)
            bar.update(task, description="runs")
        if elsewhere:  # a cluster's workers of another version (a cluster review: the
            # runs had been mixed in without a word, and only the next campaign said so)
            theirs = sorted({str(k) for _, k in elsewhere})
            say(
                console,
                f"[yellow]note:[/] {len(elsewhere)} run(s) computed now (of "
                f"{tests_named(p.test for p, _ in elsewhere)}) were made by workers with other "
                f"kernel sources (source_key {', '.join(theirs)}) than this install's "
                f"({here}): the cluster runs another version of brakeca, whose results "
                "may differ from this one's; install the same version on the workers "
                "(docs/cluster.md) and delete those run files to run them again",
                highlight=False,
            )
        finished = True
    finally:
        if not finished:
            for future in pending:
                try:
                    future.cancel()
                except Exception:  # a closed dask client cannot cancel: nothing runs on
                    if backend.lost() is None:
                        raise
        backend.close(cancel=not finished)


def _say_deaths(console: Console, died: int, max_retries: int) -> None:
    """Say that ``died`` worker processes of a dask LocalCluster died, which dask replaces
    and whose runs it retries itself (which run a worker held, dask does not say; its own
    log lines are dropped, :class:`brakeca._executors.WorkerDeaths`)."""
    if not died:
        return
    from brakeca._console import say

    one = died == 1
    text = (
        "a dask worker process died; dask starts another"
        if one
        else f"{died} dask worker processes died; dask starts others"
    )
    runs = "its run" if one else "their runs"
    if max_retries == 0:  # its run failed with it (a cluster review: "gives its run to a
        # worker again" had followed the run's failure)
        text += f", and {runs} {'is' if one else 'are'} not tried again (no retries allowed)"
    else:
        text += (
            f" and gives {runs} to a worker again (a run at most {max_retries} time(s), then "
            "it fails)"
        )
    say(console, "[yellow]worker died:[/] " + text)


# --- reading back --------------------------------------------------------------------------


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


#: the minimal command line's options that ``brakeca run`` names otherwise, and those it
#: drops (``brakeca run`` shows its progress bar, or its lines where output is not a terminal)
_RENAMED = {"--max-stops": "--stops"}
_DROPPED = {"--no-progress"}


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m brakeca.campaign DESIGN OUT_DIR [options]``: ``brakeca run DESIGN -o
    OUT_DIR --no-report [options]``, kept for scripts written against it.

    The options are ``brakeca run``'s (``brakeca run --help``), with ``--max-stops N`` for
    ``--stops N``; ``--no-progress`` is accepted and ignored. The checks, messages and exit
    statuses are ``brakeca run``'s: 0 when every run finished, 1 when some failed, 2 for a
    bad option, design or executor (nothing run then).
    """
    import typer

    from brakeca.cli import app

    args = list(sys.argv[1:] if argv is None else argv)
    if "-h" in args or "--help" in args:
        print(
            "usage: python -m brakeca.campaign DESIGN OUT_DIR [options]\n\n"
            "Runs 'brakeca run DESIGN -o OUT_DIR --no-report [options]' (its options: brakeca "
            "run --help), with --max-stops N for --stops N; --no-progress is ignored."
        )
        return 0
    command = typer.main.get_command(app)
    run = command.commands["run"]  # type: ignore[attr-defined]
    # the options that take a value, brakeca run's own and --max-stops, and those known
    options_of = [p for p in run.params if p.param_type_name == "option"]
    takes_value = {"--max-stops"} | {
        opt for p in options_of if not getattr(p, "is_flag", False) for opt in p.opts
    }
    known = (
        takes_value
        | _DROPPED
        | {opt for p in options_of for opt in (*p.opts, *getattr(p, "secondary_opts", ()))}
    )
    positional: list[str] = []
    options: list[str] = []
    items = iter(args)
    for item in items:
        name = item.split("=", 1)[0]
        if name in _DROPPED:
            continue
        if item.startswith("-") and item != "-":
            options.append(_RENAMED.get(name, name) + item[len(name) :])
            if "=" not in item and name in takes_value:
                value = next(items, None)
                if value is not None:  # (none: brakeca run says the option needs one)
                    options.append(value)
        else:
            positional.append(item)
    unknown = [o for o in options if o.startswith("-") and o.split("=", 1)[0] not in known]
    if len(positional) > 2 and unknown:  # (an unknown option's value read as an argument)
        positional, options = positional[:2], [*options, *positional[2:]]
    if len(positional) != 2:
        print(
            "usage: python -m brakeca.campaign DESIGN OUT_DIR [options of brakeca run]; "
            f"expected a design and a folder, got {len(positional)} argument(s)",
            file=sys.stderr,
        )
        return 2
    design, out_dir = positional
    try:  # click's standalone mode prints a bad option's message and exits with a status
        command.main(["run", design, "-o", out_dir, "--no-report", *options], prog_name="brakeca")
    except SystemExit as exc:
        code = exc.code
        return code if isinstance(code, int) else (0 if code is None else 1)
    return 0


if __name__ == "__main__":
    from brakeca.campaign import main as _main  # the importable module, so workers can pickle

    sys.exit(_main())
