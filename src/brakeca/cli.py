"""The command line: parsing and printing, nothing else.

``brakeca simulate`` runs one pad over the drive cycle and ``brakeca plot`` draws its
figures; ``brakeca surface`` draws the fibre maps; ``brakeca run`` / ``analyze`` / ``paper``
run and read factorial campaigns. Speed is measured by the scripts in ``benchmarks/``
(``bench.py`` prints the JSON line of ``docs/performance.md``), which need the NumPy reference
kept with the tests.
"""

from __future__ import annotations

import math
import signal
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any, Literal, NoReturn

import typer
from rich.markup import escape

from brakeca import __version__
from brakeca._console import LogConsole, is_replicated, run_tags
from brakeca.cli_cycle import _file_path
from brakeca.config import (
    MAX_SEED,
    ConfigError,
    RunFileSettings,
    SimulationConfig,
    load_config,
    parse_overrides,
)
from brakeca.presets import available_designs

app = typer.Typer(
    add_completion=False,
    rich_markup_mode=None,
    no_args_is_help=True,
    # -h as well as --help (a command-line review: "No such option: -h")
    context_settings={"help_option_names": ["-h", "--help"]},
    help=(
        "Cellular-automaton simulation of brake pad friction, wear and wear emissions "
        "(Wahlström 2016, doi:10.1155/2016/8181260) and factorial studies over pad properties."
    ),
)
console = LogConsole(stderr=True)
out = LogConsole()


def _fail(message: str, code: int = 2) -> NoReturn:
    console.print(f"[bold red]error:[/] {escape(message)}", highlight=False)
    raise typer.Exit(code)


def output_problem(path: Path, *, folder: bool = False) -> str | None:
    """Why the output ``path`` cannot be written, or None if it can; nothing is created.

    The command lines of every command that writes (``-o``) ask this before any work, so
    that a run or a figure is not computed for a place it cannot go. The nearest folder that
    exists on the way to ``path`` must be a folder and take a new file (a probe file, removed
    at once: as root, or on a read-only or virtual file system such as ``/proc``, the
    permission bits do not tell); the folders after it are created when the output is
    written.

    Parameters
    ----------
    path
        The output: a file, or a folder when ``folder``.
    folder
        Whether ``path`` is a folder (a campaign's, the figures'); else a file, written into
        its parent folder.

    Returns
    -------
    str or None
        The problem, worded to follow ``-o PATH: `` (e.g. ``"cannot create it (afile is a
        file, not a folder)"``), or None.
    """
    import os
    import tempfile

    verb = "create" if folder else "write"
    if folder and os.path.lexists(path) and not path.is_dir():
        return "cannot create it (a file of that name exists; give a folder)"
    if folder:
        from brakeca._io import linked_output_problem

        if (problem := linked_output_problem(path)) is not None:
            return problem
    if not folder and path.is_dir():
        return "cannot write it (it is a folder; give a file name)"
    existing = path if folder else path.parent
    while not os.path.lexists(existing) and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        return f"cannot {verb} it ({existing} is a file, not a folder)"
    if not folder and os.path.lexists(path) and not os.access(path, os.W_OK):
        return "cannot write it (permission denied: the file is read-only)"
    try:
        with tempfile.TemporaryFile(dir=existing):
            pass
    except OSError as exc:
        if folder and existing == path:  # the folder itself is there
            return f"cannot write in it ({exc.strerror or exc})"
        return f"cannot {verb} it (cannot write in {existing}: {exc.strerror or exc})"
    return None


def _folder_path(text: str) -> Path:
    """``-o``'s folder: an empty text is refused, where it would be the working folder
    (``Path("")`` is ``.``: ``-o "$OUT"`` with OUT unset filled it with a campaign; a fuzz
    review); what else cannot be written is refused before any work (:func:`_check_output`)."""
    if not text.strip():
        raise typer.BadParameter("an empty path; give the folder to write, e.g. -o results/mine")
    return Path(text)


def _check_output(path: Path, option: str | None = "-o", *, folder: bool = False) -> None:
    """Refuse (exit status 2) an output that cannot be written, before any work
    (:func:`output_problem`); ``option``: the option that gave it, None for a default."""
    problem = output_problem(path, folder=folder)
    if problem is not None:
        _fail(f"{'' if option is None else option + ' '}{path}: {problem}")


#: How a netCDF file starts: netCDF-4 (HDF5) and classic netCDF.
_NETCDF_MAGIC = (b"\x89HDF\r\n\x1a\n", b"CDF\x01", b"CDF\x02", b"CDF\x05")


def _check_run_output(path: Path, inputs: Sequence[Path | str | None]) -> None:
    """Refuse (exit status 2) a run file's ``-o`` that is one of the command's input files,
    or an existing file that is not a netCDF file: writing would destroy it (a black-box
    review wrote a run over its own trace). A name that does not end in ``.nc`` gets a
    note."""
    for source in inputs:
        if source and path.exists() and Path(source).exists() and path.samefile(source):
            _fail(f"-o {path}: the same file as an input of this run ({source}); name the run file")
    if path.is_file():
        with path.open("rb") as fh:
            head = fh.read(8)
        if head and not head.startswith(_NETCDF_MAGIC):
            _fail(
                f"-o {path}: exists and is not a netCDF file (a run file), so writing would "
                "destroy it; give another name or delete it first"
            )
    if path.suffix.lower() != ".nc":
        console.print(
            f"[yellow]note:[/] -o {escape(str(path))}: a run file is netCDF; brakeca plot and "
            "xarray read it whatever its name, but .nc tells others what it is",
            highlight=False,
        )


def _check_figure_output(path: Path) -> None:
    """:func:`_check_output` for a figure's ``-o``, whose suffix must be a figure format
    (:func:`brakeca.plotting.figure_format`)."""
    from brakeca.plotting import figure_format

    _check_output(path)
    try:
        figure_format(path)
    except ValueError as exc:
        _fail(f"-o {exc}")


def _write_or_keep(path: Path, write: Callable[[Path], Any], what: str) -> None:
    """Write a computed result with ``write(path)`` (its folder created); if that fails, write
    it into a new temporary folder instead and fail with exit status 1, naming both, so that
    the work is not lost.

    Parameters
    ----------
    path
        The output file (``-o``).
    write
        Writes the result to the file it is given.
    what
        The result, for the message (``"run"``, ``"figure"``).
    """
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write(path)
    except OSError as exc:  # computed: keep it where a file can be written
        import tempfile

        kept = Path(tempfile.mkdtemp(prefix=f"brakeca-{what}-")) / path.name
        write(kept)
        _fail(f"-o {path}: cannot write it ({exc}); the {what} was saved to {kept}", code=1)
    except Exception as exc:  # not the place but the content: a traceback had said it
        _fail(
            f"-o {path}: the {what} cannot be written ({type(exc).__name__}: {exc}); please "
            "report this, with the command",
            code=1,
        )


def _announce_compiling(message: str) -> None:
    """Say, before the wait, that the kernels are being compiled (brakeca._warmup)."""
    console.print(message, style="dim", markup=False, highlight=False)


@contextmanager
def _on_interrupt(message: str | Callable[[], str]) -> Iterator[None]:
    """Turn Ctrl-C inside the block into ``message`` (or what ``message()`` says then) and
    exit status 130 (typer would exit 130 without a word); SIGTERM and SIGHUP too, so that a
    killed run keeps its checkpoint and stops its children instead of leaving them running.
    Those exit with the shell's status for the signal, 128 + its number (143 for SIGTERM,
    129 for SIGHUP), as a batch scheduler or a shell script expects of a terminated job."""
    from brakeca._executors import terminate_as_interrupt

    try:
        with terminate_as_interrupt():
            yield
    except KeyboardInterrupt as exc:
        text = message() if callable(message) else message
        console.print(f"[bold yellow]interrupted:[/] {escape(text)}", highlight=False)
        raise typer.Exit(_interrupt_status(exc)) from None


def _interrupt_status(exc: KeyboardInterrupt) -> int:
    """The exit status for an interrupt: 128 + the signal's number where
    :func:`brakeca._executors.terminate_as_interrupt` raised it for a signal (its name is the
    exception's argument), 130 (128 + SIGINT) for Ctrl-C."""
    name = exc.args[0] if len(exc.args) == 1 and isinstance(exc.args[0], str) else ""
    number = getattr(signal, name, None) if name.startswith("SIG") else None
    return 128 + int(number) if number is not None else 130


def _percent_note(updates: dict[str, Any]) -> None:
    """A note for ``A`` given below 1: A is in %, and 0.2 reads like the fraction 20 %."""
    value = updates.get("A")
    if isinstance(value, int | float) and not isinstance(value, bool) and 0.0 < value < 1.0:
        console.print(
            f"[yellow]note:[/] A is in %: A={value:g} is {value:g} % fibres; for "
            f"{100 * value:g} % give A={100 * value:g}",
            highlight=False,
        )


def _unused_levels_note(design: Any) -> None:
    """A note for a run table that leaves a factor's level without a test (its main-effects
    row would have no run)."""
    for name, levels in design.levels_without_runs().items():
        shown = ", ".join(design.factor(name).label_of(v) for v in levels)
        console.print(
            f"[yellow]note:[/] factor {name!r}: level{'s' if len(levels) > 1 else ''} {shown} "
            f"{'have' if len(levels) > 1 else 'has'} no test in the run table; the analysis "
            "shows no mean there (drop it from levels, or add a run at it)",
            highlight=False,
        )


def _config_notes(configs: Iterable[SimulationConfig]) -> None:
    """The notes on values that read like slips of unit (:func:`brakeca.config.unit_notes`)
    of ``configs`` (a run's, or a campaign's tests'), each text once."""
    from brakeca.config import unit_notes_by_field

    first: dict[str, str] = {}  # a field's note, once: a design's levels all slip alike
    values: dict[str, list[Any]] = {}
    for config in configs:
        for (field, value), text in unit_notes_by_field(config).items():
            if field not in first:
                first[field], values[field] = text, [value]
            elif value not in values[field]:
                values[field].append(value)
    for field, text in first.items():
        more = values[field][1:]
        if more:  # a new user saw the same note three times, once per level
            shown = ", ".join(f"{v:g}" for v in more)
            text += f" (and so at {field} = {shown})"
        _note(text)


def _trace_notes(configs: Iterable[SimulationConfig]) -> None:
    """The notes on the speed traces of ``configs`` (a run's, or a campaign's runs'), each
    text once: events that look like speed noise (:func:`brakeca.traces.slow_events_warning`)
    and a car whose front wheel load is not the brake's
    (:func:`brakeca.traces.wheel_load_note`)."""
    from brakeca.traces import configured_cycle, slow_events_warning, wheel_load_note

    said: set[str] = set()
    for config in configs:
        if not config.cycle.trace_file:
            continue
        texts = [
            (
                "warning",
                slow_events_warning(configured_cycle(config).events, config.cycle.trace.threshold),
            ),
            ("note", wheel_load_note(config)),
        ]
        for kind, text in texts:
            if text is not None and text not in said:
                said.add(text)
                console.print(f"[yellow]{kind}:[/] {escape(text)}", highlight=False)


def _design_notes(design: Any) -> None:
    """A note for a design factor on A (the fibre fraction, in %) with levels below 1 %:
    levels of 0.1 and 0.2 read like the fractions 10 % and 20 %; one for a factor whose
    unit is not its field's while its scale is 1 (:meth:`brakeca.design.Factor.unit_note`);
    and one for a factor whose levels are not given low first
    (:meth:`brakeca.design.Factor.order_note`)."""
    for factor in design.factors:
        for note in (factor.unit_note(), factor.order_note()):
            if note is not None:
                _note(note)
    from brakeca.config import FACTOR_ALIASES
    from brakeca.design import _target

    for factor in design.factors:  # a new user's S on friction.slope (a fraction's A is usual)
        own = FACTOR_ALIASES.get(factor.name)
        if own is not None and _target(factor.field) != own[0]:
            console.print(
                f"[yellow]note:[/] factor {factor.name!r} sets {factor.field}; {factor.name} is "
                f"also the paper's name for {own[0]}, which --set {factor.name}=... sets",
                highlight=False,
            )
    for factor in design.factors:
        if factor.choices is not None or factor.field != "A":  # the alias, in %
            continue
        low = [f"{level:g}" for level in factor.levels if 0.0 < factor.override(level)[1] < 1.0]
        if low:
            console.print(
                f"[yellow]note:[/] factor {factor.name!r} sets A, the fibre fraction in %: "
                f"level{'s' if len(low) > 1 else ''} {', '.join(low)} "
                f"{'are' if len(low) > 1 else 'is'} less than 1 % fibres (a level of 10 is 10 %)",
                highlight=False,
            )


def _run_file(config_file: Path | None) -> RunFileSettings | None:
    """The settings of a run file given as ``-c``, to run it again as it ran (a provenance
    review found no way documented); None for a TOML file. A run file that cannot be read,
    or a netCDF file that is no run's, fails the command."""
    from brakeca.config import is_run_file, run_file_settings

    if config_file is None or not is_run_file(config_file):
        return None
    try:
        return run_file_settings(config_file)
    except ConfigError as exc:
        _fail(str(exc))


def _run_seed(run: RunFileSettings, config_file: Path) -> int:
    """The seed of the run file ``config_file`` to run it again; a run made from a
    generator's state fails the command (``--seed`` gives one)."""
    if run.seed < 0:
        _fail(
            f"-c {config_file}: the run was made from a random generator's state, not a seed; "
            "give --seed, or repeat it from Python: RunResult.from_netcdf(...).generator()"
        )
    return run.seed


def resolve_config(
    preset: str | None,
    config_file: Path | None,
    overrides: list[str] | None,
    stops: int | None,
    quick: bool,
) -> SimulationConfig:
    """Build the run configuration from a preset or file, ``--set`` overrides, --stops, --quick."""
    from brakeca.design import check_quick_overrides, quick_config
    from brakeca.presets import load_preset

    if config_file is not None and preset is not None:
        raise ConfigError(
            f"--preset {preset} and -c {config_file}: give one of them (a config file is a "
            "whole configuration, not changes to a preset)"
        )
    if config_file is not None:
        config = load_config(config_file)
    else:
        config = load_preset("paper" if preset is None else preset)
    updates = parse_overrides(overrides)
    _percent_note(updates)
    if quick:
        check_quick_overrides(updates)
    if stops is not None:
        if "cycle.max_stops" in updates:
            raise ConfigError("--stops and --set cycle.max_stops both set it; give one of them")
        updates["cycle.max_stops"] = stops
    if updates:
        config = config.with_updates(updates)
    if quick:
        config = quick_config(config)
    return config


PresetOpt = Annotated[
    str | None,
    typer.Option("--preset", metavar="NAME", help="shipped parameter set  [default: paper]"),
]
ConfigOpt = Annotated[
    Path | None,
    typer.Option(
        "--config",
        "-c",
        metavar="PATH",
        help="a config TOML file instead of a preset, or a run file (.nc): its run's config",
    ),
]
SetOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        metavar="KEY=VALUE",
        help="KEY=VALUE override of any config field (dotted), or a factor: S, WP, WR, A (in %)",
    ),
]
#: --seed of a command that takes a run file as -c: by default the run's, else 0
SeedFromRunOpt = Annotated[
    int | None,
    typer.Option(
        "--seed",
        min=0,
        max=MAX_SEED,
        metavar="N",
        help="seed of the run's random generator  [default: 0; with -c RUN.nc, its run's]",
    ),
]
StopsOpt = Annotated[
    int | None,
    typer.Option(
        "--stops",
        min=1,
        max=1_000_000,  # cycle.max_stops's bound (a fuzz review: 10^20 ran, then lost the run)
        metavar="N",
        help="run only the first N stops of the cycle",
    ),
]
#: ``--run-maps/--no-run-maps`` of ``run``, ``paper`` and ``analyze``
RunMapsOpt = Annotated[
    bool,
    typer.Option(
        help="draw the plateau maps of every run (final; over the cycle where it kept maps) "
        "into the report; without, a report of many runs is far smaller and quicker"
    ),
]

FiguresOpt = Annotated[
    bool,
    typer.Option(
        help="draw the report's figures; without, the tables and a report without figures "
        "in a fraction of the time (for trying one model after another), and the figures "
        "of an earlier analysis removed"
    ),
]

QuickOpt = Annotated[
    bool,
    typer.Option("--quick", help="narrow the band to 2 mm (21 rows); same cells and cycle"),
]
ReplaceOpt = Annotated[
    bool,
    typer.Option(
        "--replace",
        help="write over a folder's campaign of other options (another --quick or --stops, "
        "or, for run, --set or --cycle) or of a design whose runs this one leaves out; "
        "without it that is refused, and the run files of both are kept either way",
    ),
]
EmissionsOpt = Annotated[
    Path | None,
    typer.Option(
        "--emissions",
        metavar="FILE",
        dir_okay=False,
        help="TOML of the factors from emitted volume to PM10 in mg/km on a speed trace "
        "(brakeca.emissions.EmissionParameters' fields, e.g. airborne_fraction = 0.4 and "
        "airborne_fraction_range = [0.3, 0.5]); those left out keep their defaults and the "
        "run's pads per brake and front brake share; not kept with a campaign: give it to "
        "analyze again (docs/cycles.md)",
    ),
]


def _emissions(path: Path | None) -> Any:
    """The :class:`brakeca.emissions.EmissionParameters` of ``--emissions`` (None without
    it); a file that cannot be read or a bad field stops the command first (exit 2)."""
    if path is None:
        return None
    from brakeca.emissions import load_emissions

    try:
        return load_emissions(path)
    except ConfigError as exc:
        _fail(f"--emissions {exc}")


SpeedUnitOpt = Annotated[
    str | None,
    typer.Option(
        "--speed-unit",
        metavar="UNIT",
        help="km/h, m/s or mph: speed unit of a --cycle trace whose header states none",
    ),
]


@app.command(short_help="simulate one pad over the drive cycle (netCDF run file)")
def simulate(
    output: Annotated[
        Path,
        typer.Option(
            "-o", "--output", metavar="PATH", parser=_file_path, help="run file to write (.nc)"
        ),
    ],
    preset: PresetOpt = None,
    config_file: ConfigOpt = None,
    overrides: SetOpt = None,
    seed: SeedFromRunOpt = None,
    stops: StopsOpt = None,
    quick: QuickOpt = False,
    checkpoint: Annotated[
        Path | None,
        typer.Option(
            "--checkpoint",
            metavar="PATH",
            dir_okay=False,
            help="save the run's state here every --checkpoint-every stops; rerun to resume",
        ),
    ] = None,
    checkpoint_every: Annotated[
        int | None,
        typer.Option(
            "--checkpoint-every",
            min=1,
            metavar="N",
            help="stops between checkpoints (with --checkpoint)  [default: 10]",
        ),
    ] = None,
    cycle: Annotated[
        str | None,
        typer.Option(
            "--cycle",
            metavar="CYCLE",
            help="drive cycle: a block-cycle CSV, a speed-trace CSV or a shipped name "
            "(paper, example_trace); see docs/cycles.md",
        ),
    ] = None,
    speed_unit: SpeedUnitOpt = None,
    maps_at: Annotated[
        str | None,
        typer.Option(
            "--maps-at",
            metavar="STOPS",
            help="keep the pad's status and height maps after these stops, e.g. 1,50,170 "
            "('brakeca plot' draws them); with -c RUN.nc, by default the run file's",
        ),
    ] = None,
    emissions: EmissionsOpt = None,
) -> None:
    """Simulate one pad over the drive cycle and write a netCDF run file (-c RUN.nc runs a run
    file's configuration again, with its seed and maps unless given)."""
    from rich.progress import (
        BarColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    from brakeca.contact import ContactError
    from brakeca.cycle import step_distance
    from brakeca.simulation import LedgerError, map_stops
    from brakeca.simulation import simulate as run_simulation
    from brakeca.surface import FibreFieldError
    from brakeca.traces import configured_cycle, with_cycle

    if speed_unit is not None and cycle is None:
        _fail("--speed-unit gives the speed unit of a --cycle trace; give --cycle too")
    factors = _emissions(emissions)
    again = _run_file(config_file)
    inherited: list[int] = []  # the run file's maps, where --maps-at is not given
    if again is not None and config_file is not None:
        if seed is None:
            seed = _run_seed(again, config_file)
            console.print(f"seed {seed}: the run file's (--seed gives another)", highlight=False)
        if maps_at is None:
            inherited = again.maps
        if again.emissions is not None and emissions is None:
            console.print(
                f"[yellow]note:[/] the run file's PM10 came from other emission factors "
                f"({escape(again.emissions)}); give --emissions again for the same, the "
                "defaults are used",
                highlight=False,
            )
    if seed is None:
        seed = 0
    recorded: str | None = None  # a run file's trace, where it recorded one
    try:
        config = resolve_config(preset, config_file, overrides, stops, quick)
        if again is not None and cycle is None:
            recorded = config.cycle.trace_file
        if cycle is not None:
            config = with_cycle(config, cycle, speed_unit=speed_unit)
        source = configured_cycle(config)
        distance = step_distance(config)
        steps = sum(e.profile(distance).dt.size for e in source.events)  # ms for the paper's
    except ConfigError as exc:
        _fail(
            str(exc)
            + (
                f" (the run file's trace, recorded at {recorded}: --cycle PATH reads it from "
                "where it is now, and checks nothing of it against the run file)"
                if recorded and not Path(recorded).is_file()
                else ""
            )
        )
    kept_maps = [k for k in inherited if k <= len(source.events)]
    if len(kept_maps) < len(inherited):  # (--stops or --cycle runs fewer: a diff review)
        console.print(
            f"[yellow]note:[/] the run file kept maps after stops "
            f"{', '.join(map(str, inherited))}; this run has {len(source.events)}, so it keeps "
            + (f"those after {', '.join(map(str, kept_maps))}" if kept_maps else "none")
            + " (--maps-at chooses)",
            highlight=False,
        )
    if maps_at is not None:
        try:
            kept_maps = map_stops(_maps_at_stops(maps_at), len(source.events), name="--maps-at")
        except ValueError as exc:
            n_run = len(source.events)
            _fail(
                str(exc)
                + (
                    f" (cycle.max_stops = {n_run}, --stops, runs only the first {n_run} of the "
                    f"cycle's {source.n_total} stops)"
                    if n_run < source.n_total
                    else ""
                )
            )
    _check_output(output)
    _check_run_output(
        output, [config_file, config.cycle.trace_file and Path(config.cycle.trace_file)]
    )
    if checkpoint is None and checkpoint_every is not None:
        _fail("--checkpoint-every sets how often --checkpoint saves; give --checkpoint too")
    if checkpoint is not None:
        from brakeca._io import checkpoint_problem

        _check_output(checkpoint, "--checkpoint")
        if checkpoint.resolve() == output.resolve():
            _fail(
                f"--checkpoint {checkpoint}: the same file as -o, which the run file would "
                "replace and the end of the run remove; give the checkpoint another name"
            )
        problem = checkpoint_problem(checkpoint)
        if problem is not None:
            _fail(f"--checkpoint {checkpoint}: {problem}")
    n_r, n_t = config.mesh.n_radial, config.mesh.n_angular
    n_stops = len(source.events)
    console.print(
        f"brakeca {__version__}: {n_r} x {n_t} cells, cycle {escape(source.name)} ({source.kind}), "
        f"{n_stops} stop{'' if n_stops == 1 else 's'} ({steps:,} time steps), seed {seed}"
        + (" (quick)" if config.quick else "")
    )
    _config_notes([config])
    _trace_notes([config])
    asked = config.cycle.max_stops
    if asked is not None and asked > source.n_total:
        console.print(
            f"[yellow]note:[/] --stops {asked}: the cycle has {source.n_total} "
            f"stop{'' if source.n_total == 1 else 's'}; all of them run, once",
            highlight=False,
        )
    columns = (
        TextColumn("stops"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total}"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
    )
    from brakeca._warmup import warm_up

    def resume() -> str:  # read when the interrupt comes: has a checkpoint been saved?
        if checkpoint is None:
            return "--checkpoint PATH would let a rerun resume"
        if not checkpoint.exists():
            return f"no stop had been saved to {checkpoint} yet; the same command starts over"
        return f"the checkpoint {checkpoint} resumes it from its last saved stop (the same command)"

    with _on_interrupt(lambda: f"nothing written; {resume()}"):
        warmed = warm_up([config], announce=_announce_compiling)
    if warmed is not None:
        console.print(f"[dim]kernels compiled or loaded in a child process ({warmed:.1f} s)[/]")
    if checkpoint is not None and checkpoint.exists():
        from brakeca._io import checkpoint_resumes

        if checkpoint_resumes(checkpoint, config, seed, kept_maps):
            console.print(
                f"resuming from the checkpoint {escape(str(checkpoint))} (the stops it holds "
                "are not run again)",
                highlight=False,
            )
    failure: tuple[str, int] | None = None
    from brakeca._warmup import announcing

    # a run that compiles in this process after all (the warm-up failed) says so as the
    # warm-up does, and once (it had said it again, unstyled: a diff review)
    say = _announce_compiling if warmed is None else (lambda text: None)
    with (
        _on_interrupt(lambda: f"nothing written; {resume()}"),
        announcing(say),
        Progress(*columns, console=console, transient=False) as bar,
    ):
        task = bar.add_task("simulate", total=n_stops)
        try:
            result = run_simulation(
                config,
                seed=seed,
                progress=lambda done, total: bar.update(task, completed=done),
                checkpoint=checkpoint,
                checkpoint_every=10 if checkpoint_every is None else checkpoint_every,
                keep_checkpoint=True,  # removed below, once the run file is written
                maps_at=kept_maps,
            )
        except (ContactError, LedgerError, FibreFieldError) as exc:
            failure = (str(exc), 1)
        except ValueError as exc:  # a checkpoint of another run, or without a map asked for
            failure = (str(exc).replace("maps_at: ", "--maps-at: ", 1), 2)
        except OSError as exc:  # the checkpoint passed the check: a full disk, say
            failure = (f"--checkpoint {checkpoint}: cannot write it ({exc}); nothing written", 1)
    if failure is not None:  # after the bar's last line, so that the error is the last word
        _fail(*failure)
    estimate = None
    if source.kind == "trace":
        from brakeca.emissions import pm10_from_run

        estimate = pm10_from_run(result, source.distance, factors)
        if factors is not None:  # the run file records the figures printed
            result.dataset.attrs.update(
                {
                    "pm10_mg_km": float(estimate.central),
                    "pm10_mg_km_low": float(estimate.low),
                    "pm10_mg_km_high": float(estimate.high),
                    "pm10_factors": (
                        f"--emissions {Path(str(emissions)).resolve()}: "
                        f"{estimate.params.factors_text()}"
                    ),
                }
            )
            result.dataset.attrs["comment"] += (
                "; here pm10_mg_km (_low, _high) are of the factors in pm10_factors "
                "(brakeca simulate --emissions), not the defaults"
            )
    elif factors is not None:
        console.print(
            f"[yellow]note:[/] --emissions {escape(str(emissions))}: PM10 in mg/km is given "
            "on a speed trace only (--cycle TRACE.csv): a block cycle has no distance",
            highlight=False,
        )
    _write_or_keep(output, result.to_netcdf, "run")
    if checkpoint is not None:
        checkpoint.unlink(missing_ok=True)
    from brakeca.geometry import make_grid

    band = make_grid(config).area  # [m^2]
    share = band / config.brake.pad_area
    n_run = result.dataset.sizes.get("stop", 0)
    out.print(
        f"MU = {result.MU:.4f}"
        + (
            f", MU_SD = {result.MU_SD:.3g} (the spread of the {n_run} stops' mean COF)"
            if n_run > 1
            else ""
        )
    )
    out.print(
        f"V  = {result.V * 1e9:.6g} mm³ per stop, from the band of {config.mesh.n_radial} rows "
        f"({band * 1e6:.4g} mm², {100 * share:.3g} % of the pad; a whole pad: V / {share:.4g})",
        highlight=False,
    )
    ds = result.dataset
    worn = float(ds["generated_volume"].sum())  # [m^3] of pad material: fibre and resin
    depth = worn / band  # [m]
    out.print(f"band worn: {worn * 1e9:.6g} mm³, a mean depth of {depth * 1e3:.4g} mm")
    if depth > PAD_DEPTH_NOTE:
        out.print(
            "[yellow]note:[/] more than a new car pad's friction material (typically 10-12 "
            "mm): the model sets no pad thickness and wears on (docs/model.md section 6)",
            highlight=False,
        )
    _fibre_share_note(out, config, ds)
    out.print(
        f"ledger residual (max, relative) = {float(ds['max_ledger_residual']):.2e}; "
        f"friction residual (max) = {float(ds['max_friction_residual']):.2e}"
    )
    if estimate is not None:
        for line in estimate.describe(None if emissions is None else str(emissions)):
            out.print(line, highlight=False)
        if config.cycle.trace.friction_share == 1.0:
            out.print(
                "[yellow]note:[/] the 3 mg/km limit is for pure battery-electric cars, which "
                "brake partly by regeneration; here the friction brakes do all the braking "
                "(cycle.trace.friction_share = 1; GTR No. 24 gives an electric car's share)",
                highlight=False,
            )
    out.print(f"wrote {output}", markup=False)


def _fibre_share_note(out: Any, config: Any, ds: Any) -> None:
    """A note where the pad's fibres cover a share of the band at the start far from A (more
    than a quarter of A, or 2 points, off): a band too small against the fibres' size
    (pad.fibre_length_max, pad.fibre_diameter_max) draws too few of them to reach A (an API
    review: 3 x 100 cells at A = 10 % began with 33 % primary, without a word). Columns
    only: a fibre field buries fibres on purpose."""
    from brakeca.geometry import status_area_fractions

    wanted = float(config.pad.fibre_area_fraction)
    if config.pad.fibre_model != "columns" or wanted <= 0:
        return
    status = ds["initial_status"].to_numpy()
    share = float(status_area_fractions(status, ds["radius"].to_numpy())[1])
    if abs(share - wanted) > max(0.25 * wanted, 0.02):
        out.print(
            f"[yellow]note:[/] the fibres cover {100 * share:.3g} % of the band at the start, "
            f"not A = {100 * wanted:g} %: the band ({config.mesh.n_radial} x "
            f"{config.mesh.n_angular} cells) is too small against the fibres' size to hold "
            "A's share of them, and its results do not stand for A",
            highlight=False,
        )


def _percent_levels(text: str) -> list[float]:
    """The fibre area fractions [%] of ``--levels``: comma separated, finite, each once."""
    import math

    example = "give fibre area fractions in %, comma separated, e.g. --levels 10,20"
    values: list[float] = []
    if not text.strip():
        raise ConfigError(f"--levels {text!r}: no level; {example}")
    for item in (part.strip() for part in text.split(",")):
        if not item:  # (10,,20 was taken, where --maps-at 1,,2 is refused: a fuzz review)
            raise ConfigError(f"--levels {text!r}: an empty level between commas; {example}")
        try:
            value = float(item)
        except ValueError:
            raise ConfigError(f"--levels {text!r}: {item!r} is not a number; {example}") from None
        if not math.isfinite(value):
            raise ConfigError(f"--levels {text!r}: {item!r} is not a finite number; {example}")
        if value in values:
            raise ConfigError(f"--levels {text!r}: {value:g} % is given twice")
        values.append(value)
    return values


@app.command("plot", short_help="figures of a run file, or of a campaign's runs")
def plot(
    path: Annotated[
        Path,
        typer.Argument(
            metavar="RUN|FOLDER",
            exists=True,
            help="a run file (.nc, from brakeca simulate or a campaign's runs/), or a campaign "
            "folder (brakeca run -o) to draw each of its runs",
        ),
    ],
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="DIR",
            parser=_folder_path,
            help="folder for the PNG files (default: beside the run file, RUN_figures; for a "
            "campaign, FOLDER/run_figures, one subfolder per run)",
        ),
    ] = None,
    tests: Annotated[
        list[int] | None,
        typer.Option(
            "--test",
            metavar="N",
            min=1,
            help="a campaign's test to draw (repeat for more; default: every test)",
        ),
    ] = None,
) -> None:
    """Figures of one run: MU per stop over the cycle, the per-step COF and normal force
    against the braking time, and the initial and final plateau maps. Given a campaign
    folder, the same figures for each of its runs (or the tests named by --test)."""
    from brakeca.plotting import FIGURE_FORMATS
    from brakeca.results import RunResult
    from brakeca.study import campaign_runs_to_plot, plot_run

    suffix = output.suffix.lower().lstrip(".") if output is not None else ""
    if output is not None and suffix in FIGURE_FORMATS and not output.is_dir():
        # a folder named like a figure (a command-line review: 'figs.png/' made silently)
        console.print(
            f"[yellow]note:[/] -o {escape(str(output))} is the folder the figures go into "
            "(several PNG files), not one figure's file",
            highlight=False,
        )
    if not path.is_dir():
        if tests:
            _fail("--test selects runs of a campaign folder; RUN is a single run file")
        try:
            result = RunResult.from_netcdf(path)
        except (OSError, ValueError) as exc:
            _fail(str(exc))
        folder = output if output is not None else path.with_name(f"{path.stem}_figures")
        _check_output(folder, "-o" if output is not None else None, folder=True)
        try:
            written = plot_run(result, folder)
        except OSError as exc:  # after the check: a full disk, say; the run file is unchanged
            _fail(f"{folder}: cannot write the figures ({exc})", code=1)
        for figure in written:
            out.print(f"wrote {figure}", markup=False)
        return
    try:
        rows = campaign_runs_to_plot(path, tests or ())
    except (OSError, ValueError) as exc:
        from brakeca._runstore import lock_holder

        holder = lock_holder(path) if isinstance(exc, FileNotFoundError) else None
        if holder is not None:  # 'brakeca run' would be refused by its lock (a review)
            _fail(
                f"a campaign is writing {path} ({holder}) and has not written its summary.csv "
                f"yet: plot a run file of {path / 'runs'} instead, or the campaign when it ends"
            )
        _fail(str(exc))
    base = output if output is not None else path / "run_figures"
    _check_output(base, "-o" if output is not None else None, folder=True)
    replicated = is_replicated(rows)
    from brakeca._consolidate import campaign_folder, read_summary

    # named as the whole campaign's runs are (the width of its largest test number)
    tag = run_tags(read_summary(campaign_folder(path) / "summary.csv"))
    drawn = 0
    with _on_interrupt(f"the figures written so far are in {base}"):
        for k, row in enumerate(rows.itertuples(index=False), start=1):
            name = tag(row._asdict())
            head = f"[{k}/{len(rows)}] test {int(row.test)}"
            run_file = path / "runs" / f"{row.run_id}.nc"
            if row.status != "ok" or not run_file.is_file():
                why = "failed" if row.status != "ok" else f"{run_file} is missing"
                console.print(f"{head}: skipped ({why})", highlight=False, markup=False)
                continue
            try:
                result = RunResult.from_netcdf(run_file)
            except (OSError, ValueError) as exc:
                console.print(f"{head}: skipped ({exc})", highlight=False, markup=False)
                continue
            replicate = f", replicate {int(row.replicate)}" if replicated else ""
            try:
                plot_run(result, base / name, name=f"test {int(row.test)}{replicate}")
            except OSError as exc:  # after the check: a full disk, say
                _fail(
                    f"{base / name}: cannot write the figures ({exc}); those of the runs "
                    f"before it are in {base}",
                    code=1,
                )
            drawn += 1
            out.print(f"{head}: wrote {base / name}", highlight=False, markup=False)
    if drawn == 0:
        _fail(f"no run of {path} could be drawn", code=1)


@app.command(short_help="the initial fibre maps of the A levels (paper Figure 5)")
def surface(
    output: Annotated[
        Path,
        typer.Option(
            "-o",
            "--output",
            metavar="PATH",
            parser=_file_path,
            help="figure to write (.png; .pdf, .svg and others by the suffix)",
        ),
    ],
    preset: PresetOpt = None,
    config_file: ConfigOpt = None,
    overrides: SetOpt = None,
    seed: SeedFromRunOpt = None,
    levels: Annotated[
        str,
        typer.Option(
            "--levels", metavar="A,...", help="fibre area fractions to draw, in %, comma separated"
        ),
    ] = "10,20",
    quick: QuickOpt = False,
) -> None:
    """Draw the initial fibre maps of the A levels (the paper's Figure 5) to PNG."""
    import numpy as np

    from brakeca.geometry import make_grid
    from brakeca.plotting import plot_fibre_maps, save_figure
    from brakeca.surface import generate_surface

    if seed is None:  # a run file's own surface (a diff review: it drew seed 0's)
        again = _run_file(config_file)
        seed = 0 if again is None or config_file is None else _run_seed(again, config_file)
    try:
        given = parse_overrides(overrides)
        fixed = [k for k in given if k in ("A", "pad.fibre_area_fraction")]
        if fixed:
            raise ConfigError(
                f"--set {fixed[0]}: the maps' fibre fractions are --levels (in %), which "
                "would replace it; give --levels instead"
            )
        config = resolve_config(preset, config_file, overrides, None, quick)
        values = _percent_levels(levels)
        configs = {}
        for v in values:
            try:
                configs[f"A = {v:g} %"] = config.with_updates({"A": v})
            except ConfigError as exc:  # named as the option the user gave
                _fail(f"--levels {v:g}: " + str(exc).split(": ", 1)[-1])
    except (ConfigError, ValueError) as exc:
        _fail(str(exc))
    low = [f"{v:g}" for v in values if 0.0 < v < 1.0]
    if low:  # (--set A's note would name A=...)
        console.print(
            f"[yellow]note:[/] --levels are in %: {', '.join(low)} "
            f"{'are' if len(low) > 1 else 'is'} less than 1 % fibres (10 is 10 %)",
            highlight=False,
        )
    _check_figure_output(output)
    maps = {}
    for label, cfg in configs.items():
        grid = make_grid(cfg)
        surf = generate_surface(cfg.pad, grid, np.random.default_rng(seed))
        maps[label] = (surf.status, np.asarray(grid.radius), np.asarray(grid.angle))
    figure = plot_fibre_maps(maps)
    _write_or_keep(output, lambda path: save_figure(figure, path), "figure")
    out.print(f"wrote {output}", markup=False)


ExecutorOpt = Annotated[
    str,
    typer.Option(
        "--executor",
        metavar="NAME",
        help="serial (debugging), local (worker processes) or dask (a Dask cluster; without "
        "--scheduler or --scheduler-file, a local one on 127.0.0.1)",
    ),
]
WorkersOpt = Annotated[
    int | None,
    typer.Option(
        "--workers",
        min=1,
        metavar="N",
        help="worker processes of local, or of the cluster --executor dask starts "
        "(default: one per core)",
    ),
]
SchedulerOpt = Annotated[
    str | None,
    typer.Option(
        "--scheduler",
        metavar="ADDRESS",
        help="address of a running Dask scheduler, tcp://HOST:PORT (with --executor dask)",
    ),
]
SchedulerFileOpt = Annotated[
    Path | None,
    typer.Option(
        "--scheduler-file",
        metavar="PATH",
        help="scheduler file written by 'dask scheduler --scheduler-file' (with --executor dask)",
    ),
]
MaxRetriesOpt = Annotated[
    int | None,
    typer.Option(
        "--max-retries",
        min=0,
        metavar="N",
        show_default=False,
        help="times a run whose worker process died (killed, out of memory) is tried again "
        "before it is recorded as failed; a run that raises is not retried [default: 2; an "
        "existing Dask cluster: its scheduler's allowed-failures, docs/cluster.md]",
    ),
]


CheckpointOpt = Annotated[
    int,
    typer.Option(
        "--checkpoint-every",
        min=0,
        metavar="N",
        help="save each run in progress every N stops, so an interrupted campaign resumes it "
        "from there (0: no new checkpoints; a run still resumes from one written before)",
    ),
]


MapsAtOpt = Annotated[
    str | None,
    typer.Option(
        "--maps-at",
        metavar="STOPS",
        help="every run keeps the pad's status and height maps after these stops, e.g. "
        "1,85,170; the report shows each run's plateaus over the cycle (a finished run is "
        "reused as it is)",
    ),
]


def _maps_at_stops(text: str) -> list[int]:
    """``--maps-at``'s stop numbers, e.g. ``"1,50,170"`` (exits 2 on anything else)."""
    try:
        return [int(part) for part in text.split(",")]
    except ValueError:
        _fail(f"--maps-at {text!r}: expected stop numbers separated by commas, e.g. 1,50,170")


def _run_and_report(
    design: str,
    output: Path,
    *,
    workers: int | None,
    executor: str,
    quick: bool,
    stops: int | None,
    overrides: list[str] | None,
    report: bool,
    scheduler: str | None = None,
    scheduler_file: Path | None = None,
    max_retries: int | None = None,
    checkpoint_every: int = 10,
    cycle: str | None = None,
    speed_unit: str | None = None,
    replace: bool = False,
    maps_at: str | None = None,
    output_option: str | None = "-o",
    emissions: Path | None = None,
    run_maps: bool = True,
    figures: bool = True,
) -> None:
    import time

    from brakeca.campaign import (
        DEFAULT_MAX_RETRIES,
        EXECUTOR_KINDS,
        CampaignLockedError,
        ExecutorError,
        finish_campaign,
        run_campaign,
    )
    from brakeca.study import write_study

    # option combinations that do not go together: refused before anything runs (exit 2)
    factors = _emissions(emissions)
    if factors is not None and not report:
        _fail(
            f"--emissions {emissions} sets the report's PM10; with --no-report 'brakeca analyze "
            f"{output} --emissions {emissions}' takes it once the runs are done"
        )
    if executor not in EXECUTOR_KINDS:
        _fail(f"--executor {executor!r}: choose one of {', '.join(EXECUTOR_KINDS)}")
    if executor != "dask":
        for name, value in (("--scheduler", scheduler), ("--scheduler-file", scheduler_file)):
            if value is not None:
                _fail(f"{name} needs --executor dask (got --executor {executor})")
    if scheduler is not None and scheduler_file is not None:
        _fail("give --scheduler or --scheduler-file, not both")
    if scheduler is not None and not scheduler.strip():
        _fail("--scheduler: empty address; give tcp://HOST:PORT")
    if scheduler_file is not None and not scheduler_file.is_file():
        _fail(
            f"--scheduler-file {scheduler_file}: no such file; start the scheduler with "
            "'dask scheduler --scheduler-file FILE' first"
        )
    if workers is not None and executor == "serial":
        _fail(
            "--workers does not apply to --executor serial, which runs one run at a time in "
            "this process; use --executor local for worker processes"
        )
    if workers is not None and (scheduler is not None or scheduler_file is not None):
        _fail(
            "--workers does not apply to an existing Dask cluster (--scheduler, "
            "--scheduler-file): its workers are started with it"
        )
    if max_retries is not None and (scheduler is not None or scheduler_file is not None):
        # (a cluster review: it was ignored without a word)
        _fail(
            "--max-retries does not apply to an existing Dask cluster (--scheduler, "
            "--scheduler-file): its scheduler's distributed.scheduler.allowed-failures counts "
            "the tries; set it when starting the scheduler, e.g. "
            "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES=2 dask scheduler ..."
        )
    if speed_unit is not None and cycle is None:
        _fail("--speed-unit gives the speed unit of a --cycle trace; give --cycle too")
    try:
        updates = parse_overrides(overrides)
        _percent_note(updates)
        if cycle is not None:
            from brakeca.presets import load_preset
            from brakeca.traces import configured_cycle, with_cycle

            with_trace = with_cycle(load_preset(), cycle, speed_unit=speed_unit)
            configured_cycle(with_trace)  # refuses a trace without braking events, up front
            updates["cycle"] = with_trace.cycle.model_dump(mode="json")
    except ConfigError as exc:
        _fail(str(exc))
    asked_maps = _maps_at_stops(maps_at) if maps_at is not None else []
    _check_output(output, output_option, folder=True)  # None: the default folder
    from brakeca.design import load_design

    try:
        loaded = load_design(design)
        _design_notes(loaded)
        _unused_levels_note(loaded)
        # each test's configuration once (replicates share it), and each cycle once
        configs = list(
            dict.fromkeys(
                p.config for p in loaded.points(overrides=updates, quick=quick, max_stops=stops)
            )
        )
        _config_notes(configs)
        _trace_notes(configs)
        if stops is not None:
            from brakeca.traces import configured_cycle

            # every run's cycle: a design factor on the cycle may give runs another one
            cycles = {c.cycle: c for c in configs}
            n_total = max(configured_cycle(c).n_total for c in cycles.values())
            if stops > n_total:
                console.print(
                    f"[yellow]note:[/] --stops {stops}: the "
                    + ("cycle has" if len(cycles) == 1 else "longest cycle of the runs has")
                    + f" {n_total} stops, so every run goes its whole cycle",
                    highlight=False,
                )
    except ConfigError:  # run_campaign says what is wrong with it, before any run
        pass
    from brakeca._warmup import announcing

    kept = "the finished runs" + (" and the checkpoints" if checkpoint_every else "")
    # an existing cluster's workers go on with the runs they began (a cluster review: the
    # message had not said so, and they ran for minutes)
    held = (
        "; the cluster's workers finish the runs they had begun (writing their checkpoints), "
        "with no one to take the results: stop them if you will not resume soon"
        if scheduler is not None or scheduler_file is not None
        else ""
    )
    try:
        t0 = time.perf_counter()
        with (
            _on_interrupt(f"{kept} in {output} are kept; the same command resumes{held}"),
            announcing(_announce_compiling),
        ):
            result = run_campaign(
                design,
                output,
                workers=workers,
                executor=executor,  # type: ignore[arg-type]
                scheduler=scheduler,
                scheduler_file=scheduler_file,
                max_retries=DEFAULT_MAX_RETRIES if max_retries is None else max_retries,
                checkpoint_every=checkpoint_every or None,
                quick=quick,
                max_stops=stops,
                overrides=updates or None,
                console=console,
                replace=replace,
                maps_at=asked_maps,
            )
    except (ConfigError, ExecutorError, CampaignLockedError) as exc:
        text = str(exc).replace("maps_at: ", "--maps-at: ", 1)
        if isinstance(exc, ConfigError) and overrides and " is not valid: " in text:
            # a level refused on a base the --set options changed (a review: the message
            # named the design and another factor's level, never the --set)
            text += " (the runs' base configuration has --set " + ", --set ".join(overrides) + ")"
        _fail(text)
    except OSError as exc:  # the folder passed the check: a full disk, say
        # a folder where brakeca writes a file (its lock, say): which one, to move (a
        # robustness review got only "cannot write in it")
        # (a file written by renaming a temporary one onto it names the target second)
        target = getattr(exc, "filename2", None) or exc.filename
        blocked = (
            f"{target} is a folder where brakeca writes a file: move it away; "
            if isinstance(exc, IsADirectoryError) and target
            else ""
        )
        _fail(
            f"-o {output}: cannot write in it ({exc}); {blocked}{kept} are kept there, and the "
            "same command resumes once it can be written",
            code=1,
        )
    elapsed = time.perf_counter() - t0
    console.print(
        f"{len(result.computed)} run(s) computed, {len(result.reused)} reused, "
        f"{len(result.failed)} failed in {elapsed:.0f} s"
    )
    _print_summary(result.summary, result.design)
    if report:
        later = f"every run is in {output}; 'brakeca analyze {output}' writes the report"
        _say_analysing(run_maps, len(result.summary), figures=figures)
        lines: list[str] = []
        with _on_interrupt(later):
            try:
                path = write_study(
                    finish_campaign(output),
                    run_maps=run_maps,
                    note=_note,
                    in_short=lines.append,
                    emissions=factors,
                    figures=figures,
                )
            except OSError as exc:  # a full disk, say: the runs are done
                _fail(f"-o {output}: cannot write the report ({exc}); {later}", code=1)
        _print_in_short(lines)
        out.print(f"report: {path}", markup=False)
    out.print(f"summary: {Path(output) / 'summary.csv'}", markup=False)
    if result.failed:
        raise typer.Exit(1)


def _say_analysing(run_maps: bool, runs: int, *, figures: bool = True) -> None:
    """Say what the silence before the report is (a command-line review: 20 to 45 s without
    a word after the runs' table), and how long it may last: on the development machine
    about 20 s and 0.15 s a run, and 0.4 s more a run for its maps (a review of large
    designs: 256 runs took 2 min 20 s, 55 s without the maps); without figures, about 2.3 s
    and 0.08 s a run (4 runs 2.6 s, the paper's 24 runs 4.1 s, its run files read by
    brakeca._netcdf)."""
    if not figures:
        seconds = 2.3 + runs * 0.08
        what = "tables"
    else:
        seconds = 20.0 + runs * (0.55 if run_maps else 0.15)
        what = "tables, figures" + (
            ", each run's plateau maps (--no-run-maps leaves them out)" if run_maps else ""
        )
    if seconds < 45:
        took = f"about {seconds:.0f} s" if not figures else "half a minute or so"
    else:
        took = f"about {seconds / 60.0:.0f} min"

    console.print(
        f"analysing {runs} run{'s' if runs != 1 else ''}: {what} and the report ({took})",
        style="dim",
        highlight=False,
    )


def _print_summary(summary, design=None) -> None:
    """The runs as a table: test, factor levels (a categorical factor's by its choice's
    label), status, MU, V and MU_SD (where the summary has it). When the levels' values make
    the table wider than the terminal (seven factors in 80 columns), every factor with labels
    shows its labels (-, +) instead, and the caption says so; where it is still too wide,
    MU_SD is left out (summary.csv has it); the test number, MU and V are never cut."""
    import pandas as pd
    from rich.table import Table

    factor_cols = [
        c
        for c in summary.columns
        if c not in {"test", "replicate", "order", "run_id", "seed", "status", "error"}
        and summary.columns.get_loc(c) < summary.columns.get_loc("seed")
    ]

    centre = design.center_levels() if design is not None and design.center_points else {}

    def level(name: str, value: float, *, labelled: bool) -> str:
        if design is not None and name in design.factor_names:
            factor = design.factor(name)
            if factor.labels is not None and (labelled or factor.choices is not None):
                if name in centre and value == centre[name] and value not in factor.levels:
                    return "0"  # a centre point's level, coded 0 as brakeca design codes it
                return factor.label_of(value)
        return f"{value:g}"

    def shown(row: Any) -> bool:  # a finished run, or a test with a finished replicate
        return bool(row.get("status", "ok") == "ok" or (averaged and pd.notna(row["MU"])))

    def rows(labelled: bool) -> list[list[str]]:
        return [
            [
                str(int(row["test"])),
                *([str(int(row["replicate"]))] if with_replicate else []),
                *(escape(level(c, row[c], labelled=labelled)) for c in factor_cols),
                *([str(row.get("status", "ok"))] if with_status else []),
                f"{row['MU']:.4f}" if shown(row) else "-",
                f"{row['V_mm3']:.5g}" if shown(row) else "-",
                *([spread(row)] if with_spread else []),
            ]
            for _, row in summary.iterrows()
        ]

    def spread(row: Any) -> str:  # MU_SD, NaN for a run without one
        value = row.get("MU_SD")
        return f"{value:.3g}" if shown(row) and value is not None and pd.notna(value) else "-"

    averaged = ""
    if (
        is_replicated(summary) and len(summary) > _MOST_RUN_ROWS
    ):  # a new user's 220 rows: a row per test, its replicates averaged
        summary, averaged = _per_test(summary, factor_cols)
    # a row per run of a replicated design: its replicate beside its test, which the rows of
    # a test share (a docs walkthrough: two rows 'test 1' and nothing to tell them apart)
    with_replicate = not averaged and is_replicated(summary)
    statuses = summary["status"] if "status" in summary.columns else pd.Series(["ok"])
    with_status = bool((statuses.astype(str) != "ok").any())  # all ok: the column says nothing
    headers = [
        "test",
        *(["rep"] if with_replicate else []),
        *factor_cols,
        *(["status"] if with_status else []),
        "MU",
        "V [mm³/stop]",
    ]
    with_spread = "MU_SD" in summary.columns  # friction stability (a campaign since 2026-11)
    if with_spread:
        headers.append("MU_SD")

    def widths(cells: list[list[str]]) -> list[int]:
        return [max([len(h), *(len(r[k]) for r in cells)]) for k, h in enumerate(headers)]

    def too_wide(cells: list[list[str]]) -> bool:
        return sum(widths(cells)) + 3 * len(headers) + 1 > out.width

    cells = rows(labelled=False)
    caption = averaged or None
    if too_wide(cells):
        cells = rows(labelled=True)
        caption = (
            "levels by their labels"
            + (", centre points 0" if centre else "")
            + "; summary.csv has the values"
            + (f"; {averaged}" if averaged else "")
        )
    if with_spread and too_wide(cells):  # the responses stay whole: MU_SD gives way
        with_spread = False
        headers.pop()
        cells = [row[:-1] for row in cells]
        caption = (caption + "; " if caption else "") + "MU_SD in summary.csv"
    table = Table(title="runs", caption=caption, show_lines=False)
    for k, (col, width) in enumerate(zip(headers, widths(cells), strict=True)):
        # the test number (and replicate) and the responses
        whole = k <= int(with_replicate) or k >= len(headers) - 2 - int(with_spread)
        table.add_column(
            escape(col), justify="right", no_wrap=whole, min_width=width if whole else None
        )
    if len(cells) > _MOST_RUN_ROWS:  # the first and last rows (a review of large designs:
        # a 256-test design's 262 lines pushed what followed off the screen)
        left_out = len(cells) - _HEAD_ROWS - _TAIL_ROWS
        cells = [
            *cells[:_HEAD_ROWS],
            ["⋮"] * len(headers),
            *cells[-_TAIL_ROWS:],
        ]
        table.caption = (table.caption + "; " if table.caption else "") + (
            f"{left_out} rows not shown: summary.csv has every run"
        )
    for row in cells:
        table.add_row(*row)
    out.print(table)


#: The most runs :func:`_print_summary` shows a row each; a replicated design beyond it gets a
#: row per test, its replicates averaged, and a table still longer its first
#: :data:`_HEAD_ROWS` and last :data:`_TAIL_ROWS` rows.
_MOST_RUN_ROWS = 48
_HEAD_ROWS = 24
_TAIL_ROWS = 12


def _per_test(summary: Any, factor_cols: Sequence[str]) -> tuple[Any, str]:
    """``summary`` with a row per test: its levels, MU, V_mm3 (and MU_SD) averaged over the
    finished replicates, status ``ok`` when all finished, else ``k/n ok``; and the table's
    caption."""
    import pandas as pd

    rows = []
    for test, group in summary.groupby("test", sort=False):
        ok = group[group.get("status", pd.Series("ok", index=group.index)).astype(str) == "ok"]
        row = {"test": test, **{c: group[c].iloc[0] for c in factor_cols}}
        row["status"] = (
            "ok"
            if len(ok) == len(group)
            else (f"{len(ok)}/{len(group)} ok" if len(ok) else "failed")
        )
        row["MU"] = float(ok["MU"].mean())  # NaN without a finished replicate
        row["V_mm3"] = float(ok["V_mm3"].mean())
        if "MU_SD" in group:  # the mean of the replicates' spreads
            row["MU_SD"] = float(ok["MU_SD"].mean())
        rows.append(row)
    per_test = pd.DataFrame(rows)
    n = summary["replicate"].nunique()
    return per_test, f"a row per test: the mean of its {n} replicates; summary.csv has every run"


DesignArg = Annotated[
    str,
    typer.Argument(
        metavar="DESIGN",
        help="a design file (TOML), a campaign folder (its design.toml) or a shipped design: "
        f"{', '.join(available_designs())}",
    ),
]


@app.command(short_help="run every point of a design (resumes finished runs)")
def run(
    design: DesignArg,
    output: Annotated[
        Path,
        typer.Option("-o", "--output", metavar="PATH", parser=_folder_path, help="campaign folder"),
    ],
    workers: WorkersOpt = None,
    executor: ExecutorOpt = "local",
    scheduler: SchedulerOpt = None,
    scheduler_file: SchedulerFileOpt = None,
    max_retries: MaxRetriesOpt = None,
    checkpoint_every: CheckpointOpt = 10,
    quick: QuickOpt = False,
    stops: StopsOpt = None,
    overrides: SetOpt = None,
    report: Annotated[bool, typer.Option(help="analyse and write the report at the end")] = True,
    cycle: Annotated[
        str | None,
        typer.Option(
            "--cycle",
            metavar="CYCLE",
            help="drive cycle of every run: a block-cycle or speed-trace CSV or a shipped name; "
            "with a trace the report gives PM10 in mg/km next to the Euro 7 limits",
        ),
    ] = None,
    speed_unit: SpeedUnitOpt = None,
    replace: ReplaceOpt = False,
    maps_at: MapsAtOpt = None,
    emissions: EmissionsOpt = None,
    run_maps: RunMapsOpt = True,
    figures: FiguresOpt = True,
) -> None:
    """Run every point of a design into a campaign folder (resumes finished runs)."""
    _run_and_report(
        design,
        output,
        workers=workers,
        executor=executor,
        scheduler=scheduler,
        scheduler_file=scheduler_file,
        max_retries=max_retries,
        checkpoint_every=checkpoint_every,
        quick=quick,
        stops=stops,
        overrides=overrides,
        report=report,
        cycle=cycle,
        speed_unit=speed_unit,
        replace=replace,
        maps_at=maps_at,
        emissions=emissions,
        run_maps=run_maps,
        figures=figures,
    )


#: ``--reduce``'s help: what it does and the values it takes
_BACKWARD = (
    "backward elimination of the terms with p above ALPHA (above 0 and below 1; 0.1 in Minitab)"
)


def _reduce_option(text: str | None) -> float | Literal["none"] | None:
    """``--reduce``'s value: a level, ``"none"`` (the whole model, whatever the design's
    alpha_to_remove: a growth review found no way to set it aside from the command line), or
    None when not given; exit status 2 naming the option otherwise."""
    from brakeca.analysis import alpha_problem

    if text is None:
        return None
    if text.strip().lower() == "none":
        return "none"
    try:
        value = float(text)
    except ValueError:
        _fail(
            "--reduce: expected a level above 0 and below 1 (0.1 in Minitab), or none, got "
            f"{text!r}"
        )
    if (problem := alpha_problem(value)) is not None:
        _fail(f"--reduce: {problem}")
    return value


def _without_reduction(result: Any) -> Any:
    """The campaign ``result`` with its design's alpha_to_remove set aside (``--reduce
    none``)."""
    import dataclasses

    design = result.design.model_copy(update={"alpha_to_remove": None})
    return dataclasses.replace(result, design=design)


@app.command(short_help="main effects, interactions, ANOVA, figures, report")
def analyze(
    folder: Annotated[
        Path, typer.Argument(metavar="FOLDER", help="campaign folder written by brakeca run")
    ],
    run_maps: RunMapsOpt = True,
    anova_type: Annotated[
        int | None,
        typer.Option(
            metavar="2|3",
            help="the ANOVA's sums of squares: 2 (Type II) or 3 (Type III, adjusted, as "
            "Minitab and JMP); by default the design's anova_type (2 unless set)",
        ),
    ] = None,
    order: Annotated[
        int | None,
        typer.Option(
            "--order",
            metavar="K",
            help="the ANOVA model's terms up through K factors (1 to 10): 1 main effects, 2 "
            "with the two-factor interactions, 3 with the three-factor ones (Minitab's 'terms "
            "up through order'); by default the design's model_order (2, or main effects for a "
            "Plackett-Burman design, unless set)",
        ),
    ] = None,
    terms: Annotated[
        str | None,
        typer.Option(
            "--terms",
            metavar="TERMS",
            help="the ANOVA model's terms one by one instead, as Minitab's Terms dialog "
            "picks them: factor names, an interaction's joined by '*', separated by spaces, "
            'commas or \'+\' (e.g. "S WP WR A WP*A"; "S|WP|A" for every term of S, WP and A); '
            "its residuals, Box-Cox check and effects "
            "table follow it; by default the design's model_terms (if set)",
        ),
    ] = None,
    reduce: Annotated[
        str | None,
        typer.Option(
            "--reduce",
            metavar="ALPHA|none",
            help=f"reduce the models by {_BACKWARD}, keeping them hierarchical: the ANOVA "
            "model (and its residuals, Box-Cox check and effects table), or a "
            "response-surface design's surfaces; by default the design's alpha_to_remove "
            "(none unless set); 'none': the whole model, whatever the design sets",
        ),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="DIR",
            parser=_folder_path,
            help="folder for the tables, figures and report.html (default: the campaign "
            "folder itself); the campaign's files are only read, so a campaign that cannot "
            "be written to, or a second analysis of it, goes there",
        ),
    ] = None,
    emissions: EmissionsOpt = None,
    figures: FiguresOpt = True,
) -> None:
    """Analyse a campaign: main effects, interactions, ANOVA, figures and report.html."""
    from brakeca.campaign import finish_campaign
    from brakeca.study import check_max_order, destination_problem, write_study

    factors = _emissions(emissions)
    alpha = _reduce_option(reduce)
    if anova_type is not None and anova_type not in (2, 3):
        _fail(f"--anova-type: expected 2 (Type II) or 3 (Type III, adjusted), got {anova_type}")
    if order is not None and not 1 <= order <= 10:
        _fail(f"--order: expected the most factors in a model term, 1 to 10, got {order}")
    from brakeca._runstore import lock_holder

    holder = lock_holder(folder)
    try:
        result = finish_campaign(folder)
    except (ConfigError, FileNotFoundError, ValueError) as exc:
        if holder is not None and isinstance(exc, FileNotFoundError):
            # its first campaign has not written the summary yet ('brakeca run' would be
            # refused by the lock, which the message of load_campaign says to use)
            _fail(
                f"a campaign is writing {folder} ({holder}) and has not written its "
                "summary.csv and campaign.nc yet; analyse it when the campaign ends"
            )
        _fail(str(exc))
    if alpha == "none":
        result, alpha = _without_reduction(result), None
    try:
        chosen = check_max_order(result.design, order, terms)  # before the summary is printed
    except ValueError as exc:
        text = str(exc)
        for name, option in (
            ("model_terms, max_order: ", "--terms, --order: "),
            ("model_terms: ", "--terms: "),
            ("max_order: ", "--order: "),
        ):
            if text.startswith(name):
                text = option + text.removeprefix(name)
                break
        _fail(text)
    if holder is not None:
        console.print(
            f"[yellow]note:[/] a campaign is writing {escape(str(folder))} ({escape(holder)}): "
            "this report is of the study as it stands; analyse again when the campaign ends",
            highlight=False,
        )
    # before the summary is printed
    if output is None:
        dest = folder
        problem = output_problem(dest, folder=True)
        if problem is not None:
            _fail(
                f"{folder}: {problem}; the analysis writes its tables, figures and report.html "
                "there: give another folder for them with -o"
            )
    else:
        dest = output
        _check_output(dest, folder=True)
        if (problem := destination_problem(folder, dest)) is not None:
            _fail(f"-o {dest}: {problem}")
    _print_summary(result.summary, result.design)
    _say_analysing(run_maps, len(result.summary), figures=figures)
    lines: list[str] = []
    with _on_interrupt("the report is not complete; run the same command again"):
        try:
            path = write_study(
                result,
                run_maps=run_maps,
                anova_type=anova_type,
                alpha_to_remove=alpha,
                max_order=order,
                model_terms=terms,
                note=_note,
                output=output,
                in_short=lines.append,
                emissions=factors,
                figures=figures,
            )
        except OSError as exc:  # a full disk, a file the folder's owner made read-only
            where = exc.filename or dest
            _fail(f"{where}: cannot write it ({exc.strerror or exc}); the report is not complete")
    if chosen is not None or order is not None:
        model = f"the terms {', '.join(chosen)}" if chosen else f"terms up through order {order}"
        k = len(result.design.factors)
        if not chosen and order is not None and order > k:  # (a new user's review)
            model += (
                f", which with {k} factors is every interaction, as --order {k} gives"
                if k > 1
                else ", which with 1 factor is its main effect alone"
            )
        out.print(
            f"the report's ANOVA model: {model} (the design's own model: brakeca analyze "
            f"{folder} without {'--terms' if chosen else '--order'}"
            + ("" if output is None else ", into a folder of its own")
            + ")",
            markup=False,
            highlight=False,
        )
    _print_in_short(lines)
    out.print(
        f"tables: {dest / 'tables'}\n"
        + (f"figures: {dest / 'figures'}\n" if figures else "")
        + f"report: {path}",
        markup=False,
    )


def _print_in_short(lines: Sequence[str]) -> None:
    """Print the report's "In short" (:func:`brakeca.report.in_short`, for a response
    surface :func:`brakeca.report.surface_in_short`): each response's terms with p < 0.05
    and R², under a heading; nothing without lines."""
    if lines:
        from brakeca.report import SURFACE_LINE
        from brakeca.study import PM10_LINE_START, RESPONSES

        pm10 = lines[-1].startswith(PM10_LINE_START)
        surface = any(SURFACE_LINE in line for line in lines)
        # a response's ANOVA line (in a surface design, one too few runs fit a quadratic for)
        anova = any(line.startswith(tuple(f"{r}: " for r in RESPONSES)) for line in lines)
        kinds = [
            "the terms with p < 0.05 of each response's quadratic surface, smallest p first"
            if surface
            else "",
            "the ANOVA's terms with p < 0.05, largest share first" if anova or not surface else "",
        ]
        out.print(
            "in short ("
            + "; otherwise ".join(k for k in kinds if k)
            + ("; last, PM10 against the Euro 7 limits" if pm10 else "")
            + "):",
            markup=False,
        )
        for line in lines:
            out.print(f"  {line}", markup=False, highlight=False, emoji=False)


def _note(text: str) -> None:
    """Print a note of plain text (escaped), as the commands print theirs: the config's unit
    notes, a trace's, the report's on the run files (:func:`brakeca.study.write_study`)."""
    console.print(f"[yellow]note:[/] {escape(text)}", highlight=False)


_GOAL_FORM = (
    "RESPONSE:min:TARGET:UPPER, RESPONSE:max:LOWER:TARGET or "
    "RESPONSE:target:LOWER:TARGET:UPPER (desirability 1 at TARGET, 0 at LOWER and UPPER, as "
    "Minitab names them; min or minimize, max or maximize), with RESPONSE one of MU, V (in "
    "mm³), log10_V_mm3, MU_SD; e.g. "
    "V:min:0.1:5 or MU:target:0.35:0.4:0.45"
)


def _parse_goal(text: str) -> Any:
    """A :class:`brakeca.rsm.Goal` from ``--goal`` text, checked as a design's goal
    (:class:`brakeca.design.GoalSpec`: its messages in the text's units, V in mm³)."""
    from pydantic import ValidationError

    from brakeca.config import format_validation_error
    from brakeca.design import GOAL_RESPONSES, GoalSpec

    parts = [p.strip() for p in text.split(":")]
    # the words a design file's goal takes too (a DoE review: -g MU:maximize:... was refused)
    kinds = {
        "min": "minimize",
        "max": "maximize",
        "minimize": "minimize",
        "maximize": "maximize",
        "target": "target",
    }
    if len(parts) >= 2 and parts[0] not in GOAL_RESPONSES:
        same = [r for r in GOAL_RESPONSES if r.lower() == parts[0].lower()]
        hint = f" (did you mean {same[0]}?)" if same else ""
        raise ValueError(
            f"--goal {text!r}: unknown response {parts[0]!r}{hint}; the responses are "
            f"{', '.join(GOAL_RESPONSES)}; expected {_GOAL_FORM}"
        )
    if len(parts) >= 2 and parts[1] not in kinds:
        raise ValueError(
            f"--goal {text!r}: unknown goal {parts[1]!r}; the goals are min (minimize), max "
            "(maximize) and target; "
            f"expected {_GOAL_FORM}"
        )
    if len(parts) < 2:
        raise ValueError(f"--goal {text!r}: expected {_GOAL_FORM}")
    response, kind = parts[0], kinds[parts[1]]
    need = 3 if kind == "target" else 2
    if len(parts) - 2 != need:
        raise ValueError(f"--goal {text!r}: {parts[1]} takes {need} numbers; expected {_GOAL_FORM}")
    numbers = []
    for part in parts[2:]:
        try:
            numbers.append(float(part))
        except ValueError:
            raise ValueError(
                f"--goal {text!r}: {part!r} is not a number; expected {_GOAL_FORM}"
            ) from None
    if kind == "target":
        limits = {"lower": numbers[0], "target": numbers[1], "upper": numbers[2]}
        low, mid, high = numbers
        if not low < mid < high:  # in the command's order, not rsm.Goal's arguments
            ordered = sorted(numbers)
            hint = (
                f"; for a target of {ordered[1]:g} between {ordered[0]:g} and {ordered[2]:g}, "
                f"give {response}:target:{ordered[0]:g}:{ordered[1]:g}:{ordered[2]:g}"
                if len(set(numbers)) == 3
                else ""
            )
            raise ValueError(
                f"--goal {text!r}: a target goal is LOWER:TARGET:UPPER, the target strictly "
                f"between the limits; got lower {low:g}, target {mid:g}, upper {high:g}{hint}"
            )
    else:
        limits = {"lower": numbers[0], "upper": numbers[1]}
    try:
        spec = GoalSpec(response=response, goal=kind, **limits)
    except ValidationError as exc:
        raise ValueError(format_validation_error(exc, f"--goal {text!r}")) from None
    return spec.to_goal()


#: The most tests whose levels ``brakeca design`` and ``power`` check together (a fraction of
#: a millisecond each; ``brakeca run`` checks every one before it starts).
_MOST_TESTS_CHECKED = 20_000


def _check_combinations(design: Any) -> list[SimulationConfig]:
    """Check every test's levels together (:meth:`Design.apply_levels`), up to
    :data:`_MOST_TESTS_CHECKED` tests; beyond, say that ``brakeca run`` will. Returns the
    tests' configurations (the base's alone beyond)."""
    base = design.resolved_base()
    if design.n_tests > _MOST_TESTS_CHECKED:
        console.print(
            f"[yellow]note:[/] the levels of the {design.n_tests:,} tests are checked together "
            "by brakeca run, before it starts, not here",
            highlight=False,
        )
        return [base]
    return [design.apply_levels(base, combo) for combo in design.combinations()]


def _anova_model_text(design: Any) -> str:
    """The report's ANOVA model of ``design`` in words: its terms, or up through which
    order, and where that comes from."""
    if design.model_terms is not None:
        return f"the terms {', '.join(design.model_terms)} (model_terms)"
    order = design.anova_order
    where = (
        " (model_order)"
        if design.model_order is not None
        else " (a Plackett-Burman design)"
        if design.plackett_burman is not None
        else ""
    )
    if order == 1:
        return "main effects" + where
    if order == 2:
        return "main effects and two-factor interactions" + where
    return f"every term up through {order} factors" + where


#: A mean wear depth [m] above which ``brakeca simulate`` notes that a real pad would be worn
#: through: a new car pad's friction material is typically 10-12 mm thick (docs/model.md
#: section 6; the model itself has no thickness).
PAD_DEPTH_NOTE = 10e-3


def _interval_text(low: float, high: float) -> str:
    """An interval's ends as the optimizer's table shows them: ``"none"`` where it is not
    defined (a surface with no residual degrees of freedom), not ``"nan to nan"``."""
    if not (math.isfinite(low) and math.isfinite(high)):
        return "none"
    return f"{low:.4g} to {high:.4g}"


@app.command(short_help="the factor setting that best meets goals for MU, V and MU_SD")
def optimize(
    folder: Annotated[
        Path, typer.Argument(metavar="FOLDER", help="campaign folder written by brakeca run")
    ],
    goals: Annotated[
        list[str] | None,
        typer.Option(
            "--goal",
            "-g",
            metavar="GOAL",
            help=f"a response's goal: {_GOAL_FORM}; by default the design's goals",
        ),
    ] = None,
    reduce: Annotated[
        str | None,
        typer.Option(
            "--reduce",
            metavar="ALPHA|none",
            help=f"reduce each surface first: {_BACKWARD}, keeping the model hierarchical; "
            "by default the design's alpha_to_remove, else the full quadratic; 'none': the "
            "full quadratic, whatever the design sets",
        ),
    ] = None,
) -> None:
    """Find the factor setting that best meets every goal, on the response surfaces fitted to
    a campaign's runs (a quadratic in the coded factors, brakeca.rsm; best from a central
    composite design): the largest composite desirability (Derringer and Suich), as Minitab's
    Response Optimizer. Searches the region the runs span; numeric factors only. Without
    --goal, the goals of the campaign's design ([[goals]] in its file)."""
    from rich.table import Table

    from brakeca.campaign import load_campaign
    from brakeca.design import GOAL_RESPONSES
    from brakeca.rsm import LEFT_OUT_NOTE, response_surfaces
    from brakeca.rsm import optimize as find_optimum
    from brakeca.study import with_log_v

    try:
        parsed = [_parse_goal(g) for g in goals or ()]
        result = load_campaign(folder)
        if not parsed:
            parsed = [g.to_goal() for g in result.design.goals]
        if not parsed:
            raise ValueError(
                f"{folder}: its design has no goals; give one or more: --goal {_GOAL_FORM}"
            )
        given = _reduce_option(reduce)
        alpha = (
            None
            if given == "none"
            else given
            if given is not None
            else result.design.alpha_to_remove
        )
        fits = response_surfaces(
            with_log_v(result.summary),
            result.design.factors,
            [g.response for g in parsed],
            alpha_to_remove=alpha,
        )
        best = find_optimum(fits, parsed)
    except (ConfigError, FileNotFoundError, ValueError) as exc:
        _fail(str(exc))
    table = Table(title="factor setting")
    for column in ("factor", "level", "coded"):
        table.add_column(column, justify="left" if column == "factor" else "right")
    for f in result.design.factors:
        if f.name in best.levels:
            unit = "" if f.unit in ("", "-") else f" {f.unit}"
            table.add_row(
                escape(f.name), f"{best.levels[f.name]:.4g}{unit}", f"{best.coded[f.name]:+.3f}"
            )
    out.print(table)
    table = Table(title="responses there")
    for column in ("response", "fitted", "95 % CI of the mean", "95 % PI of one run"):
        table.add_column(column, justify="left" if column == "response" else "right")
    goals_table = Table(title="goals")
    for column in ("response", "goal", "desirability"):
        goals_table.add_column(column, justify="right" if column == "desirability" else "left")
    for goal in parsed:
        unit, scale = GOAL_RESPONSES[goal.response]
        name = escape(goal.response + ("" if unit == "-" else f" [{unit}]"))
        low, high = best.interval[goal.response]
        pi_low, pi_high = best.prediction[goal.response]
        table.add_row(
            name,
            f"{best.predicted[goal.response] * scale:.4g}",
            _interval_text(low * scale, high * scale),
            _interval_text(pi_low * scale, pi_high * scale),
        )
        goals_table.add_row(
            name,
            goal.describe(scale, "g"),
            f"{best.desirability[goal.response]:.3f}",
        )
    out.print(table)
    out.print(goals_table)
    out.print(f"composite desirability: {best.composite:.3f}", markup=False)
    said: list[str] = []
    aliased: list[str] = []  # terms left out: aliased with terms before them, one line
    for goal in parsed:  # each fit's notes, once when the fits share them
        for note in fits[goal.response].notes:
            if note.startswith("removed by backward elimination"):
                out.print(f"{goal.response}: {note}", markup=False, highlight=False, emoji=False)
            elif note.endswith(LEFT_OUT_NOTE):
                term = note[: -len(LEFT_OUT_NOTE)]
                if term not in aliased:
                    aliased.append(term)
            elif note not in said:
                said.append(note)
    if aliased:
        said.append(
            f"left out of the quadratic, since the runs cannot estimate them apart from the "
            f"terms before them: {', '.join(aliased)}"
        )
    for note in said:
        out.print(f"note: {note}", markup=False, highlight=False, emoji=False)
    for goal in parsed:  # a surface that predicts no better than the runs' mean (a DoE
        # review: a composite desirability of 1.000 on R²(pred) -85 %, said by the report only)
        pred = fits[goal.response].statistics.get("r_squared_pred", math.nan)
        if pred < 0.0:
            out.print(
                f"note: {goal.response}'s surface predicts a run it left out worse than the "
                f"mean of the runs does (R²(pred) = {100 * pred:.1f} %): its fitted value, "
                "and a desirability resting on it, say little; try fewer terms (--reduce) "
                "or more runs",
                markup=False,
                highlight=False,
            )
    two_level = [f.name for f in result.design.factors if len(f.levels) < 3]
    if not result.design.is_response_surface and two_level:  # (each factor else has a square)
        several = [f.name for f in result.design.factors if len(f.levels) >= 3]
        if result.design.center_points:
            curvature = (
                "centre points give the curvature as one term, the first factor's square "
                "standing for all), so a setting inside the region rests on that pooled "
                "curvature"
            )
        elif several:
            curvature = (
                f"without centre points only {' and '.join(several)}, of three levels or "
                f"more, {'has' if len(several) == 1 else 'have'} one), so the surface is "
                f"planar in {', '.join(two_level)}"
            )
        else:
            curvature = (
                "without centre points nothing estimates a curvature), so the surface is "
                "planar in every factor (with its interactions) and a setting inside the "
                "region is known no better than its corners"
            )
        out.print(
            f"note: {folder} holds a {result.design.kind}, not a response-surface design: its "
            f"runs do not give every factor a square term (a factor at two levels has none; "
            f"{curvature}. A central composite or Box-Behnken design estimates each factor's "
            "square term on its own.",
            markup=False,
            highlight=False,
        )
    if best.note:
        out.print(f"note: {best.note}", markup=False, highlight=False)
    if best.edge_matters:  # (not at 1: something beyond could be better)
        out.print(
            "at the edge of the region the runs span: "
            + ", ".join(best.on_boundary)
            + " (the best setting may lie beyond it; the surface is not known there)",
            markup=False,
            highlight=False,
        )


@app.command(short_help="how many replicates a design needs to find an effect")
def power(
    design: Annotated[
        str,
        typer.Argument(
            metavar="DESIGN",
            help=f"a design file (TOML) or a shipped design: {', '.join(available_designs())}; "
            "not a response-surface design (its report fits a quadratic, not this ANOVA)",
        ),
    ],
    effect: Annotated[
        float | None,
        typer.Option(
            metavar="E",
            help="the difference between two of a factor's level means to find, in the "
            "response's unit (V in mm³ per stop, MU, log10_V_mm3 and MU_SD without unit); "
            "without it, --target gives the smallest difference found with that power",
        ),
    ] = None,
    sigma: Annotated[
        float | None,
        typer.Option(
            metavar="S",
            help="the run-to-run (seed-to-seed) standard deviation of the response at one "
            "setting, in the same unit",
        ),
    ] = None,
    sigma_from: Annotated[
        Path | None,
        typer.Option(
            metavar="FOLDER",
            help="take S from a replicated campaign: its pure error of --response",
        ),
    ] = None,
    response: Annotated[
        str,
        typer.Option(
            metavar="R",
            help="the response: MU, V (in mm³), log10_V_mm3 or MU_SD, whose unit E and S are in, "
            "and whose pure error --sigma-from takes",
        ),
    ] = "MU",
    replicates: Annotated[
        str | None,
        typer.Option(
            metavar="N,N,...",
            help="the replicates (runs per test) to evaluate; by default 1 to 5, and up to "
            "the design's own replicates when it has more",
        ),
    ] = None,
    target: Annotated[
        float | None,
        typer.Option(
            metavar="P",
            help="the fewest replicates that give each factor this power (e.g. 0.8); "
            "without --effect, the smallest difference found with it",
        ),
    ] = None,
    alpha: Annotated[float, typer.Option(metavar="A", help="significance level")] = 0.05,
) -> None:
    """The power of the study's ANOVA to find each factor's effect: the probability that it
    calls a difference of E between two of the factor's level means significant (p < A) when
    runs at one setting scatter by S (another seed, another result). For the model the study
    fits (main effects and two-factor interactions; main effects alone for a Plackett-Burman
    design; the design's model_order or model_terms where set; the whole model, not one
    alpha_to_remove reduces by the data; centre points' pure error counted), as Minitab's
    Power and Sample Size for factorial designs. With
    --target, the fewest replicates that reach that power, or, without --effect, the
    smallest difference found with that power."""
    from rich.table import Table

    from brakeca.design import GOAL_RESPONSES, load_design
    from brakeca.power import (
        check_factorial,
        factor_power,
        pure_error,
        replicates_needed,
        smallest_effect,
    )

    try:
        loaded = load_design(design)
        check_factorial(loaded)  # refused before anything is printed
        _check_combinations(loaded)  # every run's levels together, as brakeca run does
        if sigma is None and sigma_from is None:
            raise ValueError("give the response's scatter: --sigma S or --sigma-from FOLDER")
        if sigma is not None and sigma_from is not None:
            raise ValueError("--sigma, --sigma-from: give one of them, not both")
        if response not in GOAL_RESPONSES:
            raise ValueError(
                f"--response: expected one of {', '.join(GOAL_RESPONSES)}, got {response!r}"
            )
        unit, scale = GOAL_RESPONSES[response]
        if sigma_from is not None:
            from brakeca.campaign import load_campaign
            from brakeca.study import with_log_v

            result = load_campaign(sigma_from)
            found, df, (low, high) = pure_error(
                with_log_v(result.summary), result.design.factors, response
            )
            sigma = scale * found
            shown = "" if unit == "-" else f" {unit}"
            out.print(
                f"sigma: {sigma:.4g}{shown}, the pure error of {response} in {sigma_from}, "
                f"with {df:g} degree{'' if df == 1 else 's'} of freedom (95 % interval "
                f"{scale * low:.3g} to {scale * high:.3g}{shown})"
                + (": a rough figure, and the power below inherits it" if df < 10 else "")
                + "; it holds for the runs of that campaign, at its band and cycle",
                markup=False,
                highlight=False,
            )
        assert sigma is not None
        if effect is None and target is None:
            raise ValueError(
                "give --effect E (each factor's power to find it), or --target P without "
                "--effect (the smallest difference found with that power)"
            )
        try:
            # an empty --replicates is refused as --maps-at's and --levels' are (it had
            # meant the default without a word; a fuzz review)
            counts = (
                [int(part) for part in replicates.split(",")] if replicates is not None else None
            )
        except ValueError:
            raise ValueError(
                f"--replicates: expected whole numbers separated by commas, got {replicates!r}"
            ) from None
        if effect is None:
            assert target is not None
            table_data = smallest_effect(
                loaded, sigma, target=target, replicates=counts, alpha=alpha
            )
        elif target is not None:
            if counts is not None:  # (they were ignored: a black-box review)
                raise ValueError(
                    "--replicates with --target and --effect: the search finds the replicates "
                    "itself; give --replicates without --target for the power at those"
                )
            table_data = replicates_needed(loaded, effect, sigma, target=target, alpha=alpha)
        else:
            table_data = factor_power(loaded, effect, sigma, replicates=counts, alpha=alpha)
    except (ConfigError, FileNotFoundError, ValueError) as exc:
        text = str(exc)
        for name in ("effect", "sigma", "alpha", "target", "replicates"):
            if text.startswith(f"{name}: "):
                text = f"--{text}"  # the option that gave it
        _fail(text)
    unit_text = "" if unit == "-" else f" {unit}"
    if effect is None:
        title = f"smallest difference in {response} found with power {target:g}"
        given = f"sigma {sigma:.4g}{unit_text}"
    else:
        title = (
            f"fewest replicates for power {target:g}"
            if target is not None
            else "power by replicates"
        )
        given = f"effect in {response} {effect:g}{unit_text}, sigma {sigma:.4g}{unit_text}"
    table = Table(title=f"{loaded.name}: {title} ({given}, alpha {alpha:g})")
    last = (
        ("smallest difference" + ("" if unit == "-" else f" [{unit}]"))
        if effect is None
        else "power"
    )
    for column in ("factor", "levels", "replicates", "runs", "error df", last):
        table.add_column(escape(column), justify="left" if column == "factor" else "right")

    def in_model(factor: str) -> bool:
        return loaded.model_terms is None or factor in loaded.model_terms

    import pandas as pd

    from brakeca.analysis import alias_structure

    # a main effect the ANOVA leaves out for one it cannot be told from (a run table of
    # resolution II; a review had read "not varied" for it)
    pairs = alias_structure(pd.DataFrame(loaded.combinations()), loaded.factors).attrs.get(
        "aliased_main_effects", []
    )
    from brakeca.report import _listed

    # both ways, every partner (a DoE review: a dict of pairs kept only the last partner of
    # a factor aliased with two)
    partners: dict[str, list[str]] = {}
    for pair in pairs:
        for a, b in (pair, pair[::-1]):
            partners.setdefault(a, []).append(b)
    partners = {a: list(dict.fromkeys(bs)) for a, bs in partners.items()}
    aliased = {a: _listed(bs) for a, bs in partners.items()}
    together: dict[str, list[str]] = {}  # a factor whose figure is its partners', once each
    for _, row in table_data.iterrows():
        value = row["effect"] if effect is None else row["power"]
        if str(row["factor"]) in aliased and not math.isnan(row["df"]):
            together[str(row["factor"])] = partners[str(row["factor"])]
        if math.isnan(row["df"]) and not in_model(str(row["factor"])):
            shown = "not in the model"
        elif math.isnan(row["df"]) and str(row["factor"]) in aliased:
            shown = f"aliased with {aliased[str(row['factor'])]}"
        elif math.isnan(row["df"]):
            shown = "not varied"
        elif math.isnan(value):
            shown = "no error df"
        else:
            shown = f"{value:.4g}" if effect is None else f"{value:.3f}"
        table.add_row(
            escape(str(row["factor"])),
            str(int(row["levels"])),
            str(int(row["replicates"])),
            str(int(row["runs"])),
            f"{row['df_error']:g}",
            shown,
        )
    out.print(table)
    out.print(f"the ANOVA model: {_anova_model_text(loaded)}", markup=False, highlight=False)
    for name, other in together.items():
        out.print(
            f"{name}'s figure is that of {_listed([name, *other])} together: the tests cannot "
            "tell them apart (brakeca design names the aliases)",
            markup=False,
            highlight=False,
        )
    from brakeca.power import pooling_note

    for r in sorted({int(r) for r in table_data["replicates"]}):
        if pooled := pooling_note(loaded, r):  # the model as fitted at that many replicates
            out.print(
                f"with {r} replicate{'s' if r != 1 else ''}: {pooled} (as the report's ANOVA "
                "does; the error df above count them)",
                markup=False,
                highlight=False,
            )
    if loaded.center_points:
        out.print(
            f"runs: the design's tests, its {loaded.center_points} centre point"
            f"{'s' if loaded.center_points != 1 else ''} among them, each run as often as the "
            "replicates say (centre points too); their pure error is in the error df",
            markup=False,
            highlight=False,
        )
    if effect is not None and target is not None and (table_data["power"] < target).any():
        out.print(
            "some factors do not reach the power with the most replicates tried "
            f"({int(table_data['replicates'].max())})",
            markup=False,
        )


def default_paper_folder(*, quick: bool, stops: int | None) -> Path:
    """The campaign folder of ``brakeca paper`` without ``-o``: ``results/paper``,
    ``results/paper_quick`` with ``--quick`` (another band: other runs), and ``_stopsN``
    added with ``--stops N`` (the first N stops only: a study of its own, which must not
    replace the whole cycle's summary and report)."""
    name = "paper_quick" if quick else "paper"
    if stops is not None:
        name += f"_stops{stops}"
    return Path("results") / name


@app.command(short_help="the paper's 24-run study, its analysis and report")
def paper(
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="PATH",
            parser=_folder_path,
            help="campaign folder (default: results/paper; results/paper_quick with --quick; "
            "_stopsN added with --stops N)",
        ),
    ] = None,
    workers: WorkersOpt = None,
    executor: ExecutorOpt = "local",
    scheduler: SchedulerOpt = None,
    scheduler_file: SchedulerFileOpt = None,
    max_retries: MaxRetriesOpt = None,
    checkpoint_every: CheckpointOpt = 10,
    quick: QuickOpt = False,
    stops: StopsOpt = None,
    replace: ReplaceOpt = False,
    maps_at: MapsAtOpt = None,
    report: Annotated[bool, typer.Option(help="analyse and write the report at the end")] = True,
    run_maps: RunMapsOpt = True,
    figures: FiguresOpt = True,
) -> None:
    """The paper's whole study: the 24-run factorial design, then the analysis and report.
    With --stops N and no -o, a folder of its own (results/paper_stopsN), so that a
    truncated study never replaces the whole cycle's."""
    given = output is not None
    if output is None:  # the quick band's runs are not the full band's: a folder each
        output = default_paper_folder(quick=quick, stops=stops)
        console.print(f"campaign folder: {output}", markup=False, highlight=False)
    _run_and_report(
        "paper",
        output,
        workers=workers,
        executor=executor,
        scheduler=scheduler,
        scheduler_file=scheduler_file,
        max_retries=max_retries,
        checkpoint_every=checkpoint_every,
        quick=quick,
        stops=stops,
        overrides=None,
        report=report,
        replace=replace,
        maps_at=maps_at,
        # a default folder that cannot be written is named as the default, not as a -o the
        # user did not give (a command-line review)
        output_option="-o" if given else None,
        run_maps=run_maps,
        figures=figures,
    )


@app.command("design", short_help="a design's tests, resolution and alias structure")
def show_design(
    design: DesignArg,
    tests: Annotated[bool, typer.Option(help="list the tests and their levels")] = True,
) -> None:
    """Check a design before running it: its kind and runs, a fraction's generators,
    defining relation and resolution, the alias structure of its main effects and two-factor
    interactions (what it cannot tell apart), its factors (the field each sets, its unit and
    the value of each level) and its tests (with their run order when it is randomized)."""
    import pandas as pd
    from rich.table import Table

    from brakeca.analysis import alias_structure
    from brakeca.design import GOAL_RESPONSES, load_design

    try:
        loaded = load_design(design)
        configs = _check_combinations(loaded)  # a level valid alone may not be with the others
    except ConfigError as exc:
        _fail(str(exc))
    _design_notes(loaded)
    _unused_levels_note(loaded)
    _config_notes(configs)  # the base's and the levels' values, as run notes them
    combos = loaded.combinations()
    runs = loaded.n_tests * loaded.replicates
    out.print(f"{loaded.name}: {loaded.kind}", markup=False, highlight=False)
    if loaded.description:
        out.print(loaded.description, markup=False, highlight=False)
    out.print(
        f"{loaded.n_tests} tests × {loaded.replicates} replicate(s) = {runs} runs; root seed "
        f"{loaded.root_seed}",
        markup=False,
        highlight=False,
    )
    orders: dict[int, list[int]] = {}
    if loaded.randomize_order:
        try:
            for point in loaded.points():
                orders.setdefault(point.test, []).append(point.order)
        except ConfigError as exc:
            _fail(str(exc))
        listed = tests and loaded.replicates <= _MOST_ORDERS_LISTED
        out.print(
            "run order: randomized (randomize_order = true, seeded by the root seed); each "
            "run's place in it is in "
            + ("the order column of the tests below and in " if listed else "")
            + "summary.csv's order column",
            markup=False,
            highlight=False,
        )
    if loaded.is_fractional:
        out.print(f"generators: {', '.join(loaded.generators)}", markup=False, highlight=False)
        out.print(
            f"defining relation: {loaded.relation_text()}",
            markup=False,
            highlight=False,
            emoji=False,
        )
    if loaded.is_response_surface:
        _print_surface_model(loaded)
    for goal in loaded.goals:
        unit = GOAL_RESPONSES[goal.response][0]
        out.print(
            f"goal: {goal.response} "
            + goal.to_goal(scale=1.0).describe(spec="g")
            + ("" if unit == "-" else f" [{unit}]"),
            markup=False,
            highlight=False,
            emoji=False,
        )
    if not loaded.is_response_surface:  # a response surface's model is the quadratic,
        # printed above, not the categorical one whose alias structure this is
        _print_aliases(alias_structure(pd.DataFrame(combos), loaded.factors))
    if loaded.anova_type == 3:
        out.print(
            "ANOVA: Type III (adjusted) sums of squares (anova_type = 3)",
            markup=False,
            highlight=False,
        )
    if loaded.center_points and loaded.center_points * loaded.replicates == 1:
        out.print(
            "note: one centre point run tests curvature but gives no pure error (two or more "
            "do: the error of an unreplicated design without its interactions)",
            markup=False,
            highlight=False,
        )
    if loaded.model_order is not None:
        out.print(
            f"the report's ANOVA model: terms up through {loaded.model_order} factor"
            f"{'s' if loaded.model_order != 1 else ''} (model_order)"
            + (
                f"; the design has {len(loaded.factors)}, so every interaction the data can "
                "estimate"
                if loaded.model_order > len(loaded.factors)
                else ""
            ),
            markup=False,
            highlight=False,
        )
    if loaded.model_terms is not None:
        out.print(
            f"the report's ANOVA model: {_anova_model_text(loaded)}", markup=False, highlight=False
        )
    if loaded.alpha_to_remove is not None:
        what = "surfaces" if loaded.is_response_surface else "ANOVA model"
        out.print(
            f"the report reduces its {what} by backward elimination of the terms with p above "
            f"{loaded.alpha_to_remove:g} (alpha_to_remove)",
            markup=False,
            highlight=False,
        )
    _print_factors(loaded)
    if tests:
        table = Table(title="tests")
        table.add_column("test", justify="right", no_wrap=True)
        for f in loaded.factors:
            table.add_column(escape(f.name), justify="right")
        with_order = bool(orders) and loaded.replicates <= _MOST_ORDERS_LISTED
        if with_order:
            table.add_column("order", justify="right")
        centre = loaded.center_levels() if loaded.center_points else None
        for k, combo in enumerate(combos, start=1):
            at_centre = centre is not None and all(combo[n] == centre[n] for n in centre)
            table.add_row(
                str(k),
                *(
                    "0"
                    if at_centre and loaded.factor(n).labels
                    else escape(loaded.factor(n).label_of(v))
                    for n, v in combo.items()
                ),
                *([", ".join(map(str, orders[k]))] if with_order else []),
            )
        out.print(table)


def _print_aliases(structure: Any) -> None:
    """The alias structure of ``brakeca design`` (:func:`brakeca.analysis.alias_structure`):
    the alias chains, or that there are none, and the partly confounded terms."""
    chains = [
        f"{term} - {aliases[1:]}" if aliases.startswith("-") else f"{term} + {aliases}"
        for term, aliases in zip(structure["term"], structure["aliases"], strict=True)
        if aliases
    ]
    if chains:
        out.print(
            "alias structure (effects of up to three factors the tests cannot tell apart):",
            markup=False,
        )
        for chain in chains:
            out.print(f"  {chain}", markup=False, highlight=False, emoji=False)  # WR:A:x: no emoji
    hidden = structure.attrs.get("not_estimable", [])
    constant_terms = structure.attrs.get("with_mean", [])
    partly = structure.attrs.get("max_correlation", 0.0)
    for term, other in structure.attrs.get("aliased_main_effects", []):
        out.print(
            f"[yellow]warning:[/] the tests cannot tell main effect {escape(other)} from "
            f"{escape(term)} (resolution II): in these tests the level of one fixes the "
            "other's, so an effect estimated for either is that of both together",
            highlight=False,
        )
    if not chains and (hidden or constant_terms or partly > 0.0):
        out.print(
            "alias structure: no main effect or two-factor interaction is completely aliased "
            "with another (up to three-factor interactions), but some are partly confounded"
            + (f" (correlations up to {partly:.2g})" if partly > 0.0 else ""),
            markup=False,
        )
    elif not chains:
        out.print(
            "alias structure: every main effect and two-factor interaction is clear of the "
            "others (up to three-factor interactions)",
            markup=False,
        )
    if hidden:
        out.print(
            "not estimable (each aliased with a combination of the terms before it, though "
            "with no single one): " + ", ".join(hidden),
            markup=False,
            highlight=False,
            emoji=False,
        )
    if constant_terms:
        out.print(
            "not estimable (the same in every test: aliased with the mean): "
            + ", ".join(constant_terms),
            markup=False,
            highlight=False,
            emoji=False,
        )


#: ``brakeca design`` lists a randomized design's run order in its tests table up to this many
#: replicates (a number per replicate) [-]
_MOST_ORDERS_LISTED = 4


def _factor_cells(design: Any, factor: Any) -> tuple[str, str, str, list[str], str]:
    """A factor's row of the factors table: name, the configuration field it sets (times its
    scale), unit, one ``label = value`` per level, and its coding where the design shows
    codings (:func:`_shows_coding`; empty for others)."""
    from brakeca.config import FACTOR_ALIASES

    field, scale = factor.field, factor.scale
    if field in FACTOR_ALIASES:  # S, WP, WR, A: the alias's field, in the alias's unit
        field, alias_scale, _ = FACTOR_ALIASES[field]
        scale *= alias_scale
    sets = field if scale == 1.0 else f"{field} × {scale:g}"
    levels = []
    for k, value in enumerate(factor.levels):
        text = factor.choices[k] if factor.choices is not None else f"{value:g}"
        label = factor.label_of(value)
        levels.append(text if label == text else f"{label} = {text}")
    if design.center_points:  # where the centre points put it
        centre = design.center_levels()[factor.name]
        geometric = " (geometric)" if factor.coding == "log" else ""
        # coded 0 in the tests table, as Minitab codes a centre point, where levels have labels
        levels.append(f"{'0' if factor.labels else 'centre'} = {centre:g}{geometric}")
    coding = ""
    if _shows_coding(design) and not factor.categorical:
        coding = "log10" if factor.coding == "log" else "linear"
    return factor.name, sets, factor.unit, levels, coding


def _shows_coding(design: Any) -> bool:
    """Whether ``brakeca design`` gives the factors' coding: for a response-surface design
    (its model's), and wherever a factor is log-coded (its centre point, an optimized
    setting's coded value: a run table's too)."""
    return bool(design.is_response_surface or any(f.coding == "log" for f in design.factors))


def _print_factors(design: Any) -> None:
    """The factors table of ``brakeca design``: what each factor sets and the value of each
    of its levels (the tests table gives only their labels), as Minitab's factor information.
    Each factor on one line when that fits the terminal, else its levels one a line."""
    from rich.table import Table

    rows = [_factor_cells(design, f) for f in design.factors]
    headers = ["factor", "sets", "unit", "levels"]
    if _shows_coding(design):
        headers.append("coding")

    def cells(stacked: int) -> list[list[str]]:
        """The rows: stacked (1), a level a line and the scale under the field; and (2) the
        field broken after its first dot."""
        if not stacked:
            return [[n, s, u, ", ".join(levels), c] for n, s, u, levels, c in rows]
        if stacked > 1:
            rows_ = [(n, s.replace(".", ".\n", 1), u, lv, c) for n, s, u, lv, c in rows]
        else:
            rows_ = rows
        return [
            [n, s.replace(" × ", "\n× "), u, "\n".join(levels), c] for n, s, u, levels, c in rows_
        ]

    def width(table: list[list[str]]) -> int:
        """Columns [-] the table takes: its widest lines, borders and padding."""
        widest = [
            max([len(h), *(len(line) for row in table for line in row[k].splitlines())])
            for k, h in enumerate(headers)
        ]
        return sum(widest) + 3 * len(headers) + 1

    stacked = next((k for k in (0, 1) if width(cells(k)) <= out.width), 2)
    table = Table(title="factors (each level: label = value, in the unit)", show_lines=stacked > 0)
    for h in headers:
        table.add_column(h, justify="left", overflow="fold")  # cut, never dropped for "…"
    for row in cells(stacked):
        table.add_row(*(escape(c) for c in row[: len(headers)]))
    out.print(table)


def _print_surface_model(design: Any) -> None:
    """The coding and the quadratic model a composite design's runs can estimate."""
    import pandas as pd

    from brakeca.rsm import coding_of, surface_terms

    codings = [coding_of(f) for f in design.factors]
    out.print(
        "coded -1 to +1: "
        + "; ".join(
            f"{c.name} {'log10 ' if c.log else ''}{c.low:g} to {c.high:g}"
            + (f" {c.unit}" if c.unit and c.unit != "-" else "")
            for c in codings
        ),
        markup=False,
        highlight=False,
        emoji=False,
    )
    runs = pd.DataFrame(design.combinations() * design.replicates)
    model = surface_terms(runs, codings)
    terms = model["terms"]
    counts = {
        "linear": sum("*" not in t for t in terms),
        "square": sum(t.partition("*")[0] == t.partition("*")[2] for t in terms),
    }
    counts["interaction"] = len(terms) - counts["linear"] - counts["square"]
    out.print(
        f"response-surface model: {len(terms) + 1} coefficients ("
        + ", ".join(f"{n} {kind}" for kind, n in counts.items())
        + f" terms and the constant) from {len(runs)} runs: {model['df_resid']:.0f} residual "
        f"df, {model['pure_error_df']:.0f} of them pure error (repeated points)",
        markup=False,
        highlight=False,
    )
    for note in model["notes"]:
        out.print(f"  {note}", markup=False, highlight=False, emoji=False)
    import numpy as np

    vif = model["vif"]
    if vif.size and np.all(np.isfinite(vif)):
        worst = int(np.argmax(vif))
        out.print(
            f"largest variance inflation factor of its terms: {vif[worst]:.3g} ({terms[worst]}; "
            "1 where a term's column is orthogonal to the others)",
            markup=False,
            highlight=False,
        )


@app.command("config", short_help="print the resolved configuration as TOML")
def show_config(
    preset: PresetOpt = None,
    config_file: ConfigOpt = None,
    overrides: SetOpt = None,
    stops: StopsOpt = None,
    quick: QuickOpt = False,
) -> None:
    """Print the resolved configuration as TOML (validate a config without running it)."""
    from brakeca.traces import configured_cycle

    try:
        config = resolve_config(preset, config_file, overrides, stops, quick)
        # a trace is read and checked as a run reads it (its file, unit and digest; a fuzz
        # review found a missing trace_file and a unit of furlongs taken here)
        configured_cycle(config)
    except ConfigError as exc:
        _fail(str(exc))
    _config_notes([config])  # on standard error, as the A note
    again = _run_file(config_file)
    if again is not None and config_file is not None:  # what the TOML cannot hold
        maps = f" --maps-at {','.join(map(str, again.maps))}" if again.maps else ""
        console.print(
            "[yellow]note:[/] the run's seed and maps are not part of its configuration: "
            + (
                f"'brakeca simulate -c {escape(str(config_file))}' runs it as it ran, as does "
                f"this configuration with --seed {again.seed}{maps}"
                if again.seed >= 0
                else "it was made from a random generator's state, not a seed, which "
                "RunResult.from_netcdf(...).generator() repeats from Python"
            ),
            highlight=False,
        )
    out.print(config.to_commented_toml(), highlight=False, markup=False, end="")


#: The documents ``brakeca docs`` names, with what each holds.
DOCS: dict[str, str] = {
    "model": "the model and every decision the code takes, with reasons",
    "designs": "writing a design, running a campaign, reading its analysis",
    "study": "what the paper's study shows with this implementation",
    "cycles": "block cycles, speed traces, PM10 in mg/km next to the Euro 7 limits",
    "cluster": "a study on a Dask cluster or SLURM, retries, resume",
    "nomenclature": "one name per quantity",
    "performance": "measured speed and how to reproduce it",
    "performance-history": "every session's measurements, with the ideas that did not pay",
}


def docs_folder() -> Path | None:
    """Where the documents are: ``brakeca/docs`` in an installed wheel, the repository's
    ``docs/`` in a checkout (an editable install); None where neither is."""
    import brakeca

    package = Path(brakeca.__file__).resolve().parent
    for folder in (package / "docs", package.parent.parent / "docs"):
        if (folder / "model.md").is_file():
            return folder
    return None


@app.command("docs", short_help="the documentation: where it is, or one document's text")
def show_docs(
    name: Annotated[
        str | None,
        typer.Argument(help=f"a document to print: {', '.join(DOCS)}", show_default=False),
    ] = None,
) -> None:
    """Where the documents the help texts and reports cite (docs/model.md, ...) are, in a
    checkout or an installed package, or one document's text (Markdown), e.g.
    'brakeca docs model | less'."""
    folder = docs_folder()
    if folder is None:
        _fail("the documents are not installed here (they are the repository's docs/ folder)")
    if name is None:
        typer.echo(f"documents in {folder}:")
        for key, what in DOCS.items():
            typer.echo(f"  {key:<13} {what}")
        typer.echo("'brakeca docs NAME' prints one (Markdown)")
        return
    key = name.removesuffix(".md").removeprefix("docs/")
    if key not in DOCS:
        _fail(f"docs: no document {name!r}; choose one of {', '.join(DOCS)}")
    typer.echo((folder / f"{key}.md").read_text(encoding="utf-8"), nl=False)


@app.callback(invoke_without_command=True)
def _root(
    ctx: typer.Context,
    version: Annotated[bool, typer.Option("--version", help="print the version")] = False,
) -> None:
    if version:
        out.print(__version__)
        raise typer.Exit(0)
    # the commands print their own notes for values that read like unit slips (A below 1 %),
    # where the library warns (config.UnitWarning); for this command only: the filters are
    # restored when it ends (a command run in-process leaves the library's warnings on)
    import warnings

    from brakeca.config import UnitWarning

    ctx.with_resource(warnings.catch_warnings())
    warnings.simplefilter("ignore", UnitWarning)
    # the library's other warnings (a checkpoint that cannot be written) as one line
    from brakeca._console import brief_warnings

    ctx.call_on_close(brief_warnings())


def _register_subcommands() -> None:
    from brakeca.cli_cycle import cycle_app

    app.add_typer(cycle_app, name="cycle", help="inspect drive cycles (block cycles and traces)")


_register_subcommands()


def _lenient(stream: Any) -> None:
    """Have ``stream`` write ``?`` for a character its encoding lacks instead of stopping
    the command: on Windows, output sent to a file or a pipe is written in the ANSI code
    page (cp1252), which has no λ, α, − or ⋮, and the commands that print them ended with a
    UnicodeEncodeError, the lines after it (the report's path) unprinted (a portability
    review). Nothing changes for a stream that writes UTF-8."""
    import codecs

    try:
        if codecs.lookup(stream.encoding).name == "utf-8" or stream.errors != "strict":
            return  # (stderr's backslashreplace, say, which keeps the code point)
        stream.reconfigure(errors="replace")
    except (AttributeError, LookupError, TypeError, ValueError):  # not a text file's stream
        pass


def main() -> None:
    """Entry point of the ``brakeca`` command."""
    from brakeca._cachedir import KernelCacheError

    for stream in (sys.stdout, sys.stderr):
        _lenient(stream)
    try:
        app()
    except KernelCacheError as exc:  # the environment, not a bug: no traceback
        console.print(f"[bold red]error:[/] {escape(str(exc))}", highlight=False)
        sys.exit(1)
    except KeyboardInterrupt as exc:  # pragma: no cover - interactive
        console.print("interrupted")
        sys.exit(_interrupt_status(exc))


if __name__ == "__main__":  # pragma: no cover
    main()
