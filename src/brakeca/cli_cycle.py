"""``brakeca cycle``: look at a drive cycle before simulating it.

``brakeca cycle inspect FILE`` reads a speed trace (or a block cycle), prints the braking events
found, the distance and the braking energy, and draws the trace with the events shaded. Cycle
formats and the detection parameters are described in ``docs/cycles.md``.
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from brakeca._console import LogConsole
from brakeca.config import ConfigError
from brakeca.cycle import KMH, Stop
from brakeca.traces import (
    BrakingEvent,
    TraceCycleConfig,
    _read_text,
    block_trace,
    brake_work,
    braking_energy,
    cycle_file_kind,
    detect_events,
    event_distance,
    load_cycle_source,
    slow_events_warning,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["cycle_app", "inspect_cycle"]


def _file_path(text: str) -> Path:
    """``-o``'s file (of ``cycle inspect``, and of :mod:`brakeca.cli`'s ``simulate`` and
    ``surface``, which import it from here: this module does not import that one at its
    top): an empty text and a folder are refused, each with what to give (a command-line
    review: "-o ''" had read "File '' is a directory")."""
    if not text.strip():
        raise typer.BadParameter("an empty path; give the file to write")
    path = Path(text)
    if path.is_dir():
        raise typer.BadParameter(f"{text} is a folder; give the file to write in it")
    return path


cycle_app = typer.Typer(
    add_completion=False,
    rich_markup_mode=None,
    no_args_is_help=True,
    # -h as well as --help (a command-line review: "No such option: -h")
    context_settings={"help_option_names": ["-h", "--help"]},
    help="Drive cycles: block cycles (Table 3 form) and speed traces (time, speed).",
)
console = LogConsole(stderr=True)
out = LogConsole()


@cycle_app.callback()
def _cycle() -> None:
    """Drive cycles: block cycles (Table 3 form) and speed traces (time, speed)."""


def _fail(message: str, code: int = 2) -> None:
    from rich.markup import escape

    console.print(f"[bold red]error:[/] {escape(message)}", highlight=False)
    raise typer.Exit(code)


def _energy(joules: float) -> str:
    return f"{joules / 1e6:.4g} MJ" if abs(joules) >= 1e6 else f"{joules / 1e3:.4g} kJ"


def _write_plot(figure: Figure, path: Path) -> None:
    """Write the plot as PNG at 150 dpi and say so; where ``path`` cannot be written after
    all (checked before the work), into a temporary folder, and exit with status 1."""
    from brakeca.cli import _write_or_keep
    from brakeca.plotting import save_figure

    _write_or_keep(path, lambda p: save_figure(figure, p), "plot")
    out.print(f"wrote {path}", markup=False, highlight=False)


def inspect_cycle(
    file: str,
    trace_config: TraceCycleConfig,
    *,
    speed_unit: str | None = None,
    plot: Path | None = None,
    preset: str = "paper",
) -> None:
    """Print the events, distance and braking energy of a cycle; optionally plot it."""
    from rich.markup import escape
    from rich.table import Table

    from brakeca.presets import load_preset

    config = load_preset(preset)
    m_w = config.vehicle.wheel_load_mass
    source = load_cycle_source(file, config, trace_config, speed_unit=speed_unit)
    events = list(source.events)
    if source.kind == "trace":
        trace = source.trace
        assert trace is not None
        out.print(
            f"{source.name}: speed trace, {trace.time.size} samples over {trace.duration:g} s "
            f"({trace.source})",
            highlight=False,
        )
        table = Table(title="braking events (a: mean deceleration, s: distance)", show_lines=False)
        # the units on a line of their own: at 80 columns (a pipe, a log) the headers are
        # then narrow enough that no value is cut ('101-1…')
        for col in (
            "#",
            "trip",
            "t_on\n[s]",
            "dur\n[s]",
            "v_on\n[km/h]",
            "v_off\n[km/h]",
            "a\n[m/s²]",
            "s\n[m]",
            "lines",
        ):
            table.add_column(
                escape(col), justify="left" if col == "trip" else "right", no_wrap=True
            )
        for e in events:
            assert isinstance(e, BrakingEvent)
            table.add_row(
                str(e.index),
                e.block,
                f"{e.start_time:g}",
                f"{e.duration:.3g}",
                f"{e.initial_speed / KMH:.1f}",
                f"{e.final_speed / KMH:.1f}",
                f"{e.deceleration:.2f}",
                f"{e.distance:.1f}",
                f"{e.first_line}-{e.last_line}" if e.first_line is not None else "-",
            )
        out.print(table)
        tc = trace_config
        braking = sum(event_distance(e) for e in events)
        out.print(
            f"events found: {len(events)} (deceleration above {tc.threshold:g} m/s² for at "
            f"least {tc.min_duration:g} s; smoothing {tc.smoothing:g} s, merge gap "
            f"{tc.merge_gap:g} s)",
            highlight=False,
        )
        warning = slow_events_warning(events, tc.threshold)
        if warning is not None:
            out.print(f"[yellow]warning:[/] {escape(warning)}", highlight=False)
        out.print(
            f"distance: {source.distance / 1000.0:.3f} km, of which braking "
            f"{braking / 1000.0:.3f} km",
            highlight=False,
        )
        out.print(
            f"kinetic energy removed in the events (vehicle {tc.vehicle_mass:g} kg): "
            f"{_energy(braking_energy(events, tc.vehicle_mass))}",
            highlight=False,
        )
        out.print(
            f"work of the modelled front brake (wheel load {m_w:g} kg, brake share "
            f"{tc.brake_share:.3g}, road load C_rr {tc.rolling_resistance:g}, C_dA "
            f"{tc.drag_area:g} m²): {_energy(brake_work(events, m_w))}; the brake share "
            "c φ_f / ψ_f is the front brake's share of the braking over its share of the "
            "load, above 1 for front-biased brakes (docs/cycles.md)",
            highlight=False,
        )
        if plot is not None:
            from brakeca.plotting import plot_trace

            _write_plot(plot_trace(trace, events), plot)  # type: ignore[arg-type]
        return
    out.print(f"{source.name}: block cycle, {source.n_total} stops", highlight=False)
    table = Table(title="blocks", show_lines=False)
    for col in ("block", "stops", "v_on [km/h]", "v_off [km/h]", "a [m/s²]", "s per stop [m]"):
        table.add_column(escape(col), justify="left" if col == "block" else "right")
    # a row per run of like stops: two blocks of one name apart in the cycle are two rows
    # (one dict by name had counted both under the first's speeds and deceleration)
    block_stops = [e for e in events if isinstance(e, Stop)]
    runs = itertools.groupby(
        block_stops, key=lambda e: (e.block, e.initial_speed, e.final_speed, e.deceleration)
    )
    for (block, *_), group in runs:
        like = list(group)
        s = like[0]
        table.add_row(
            block,
            str(len(like)),
            f"{s.initial_speed / KMH:.0f}",
            f"{s.final_speed / KMH:.0f}",
            f"{s.deceleration:.2f}",
            f"{event_distance(s):.1f}",
        )
    out.print(table)
    out.print(
        f"braking distance: {source.distance / 1000.0:.3f} km (a block cycle has no distance "
        "between stops)",
        highlight=False,
    )
    out.print(
        f"work of the modelled brake (wheel load {m_w:g} kg): {_energy(brake_work(events, m_w))}",
        highlight=False,
    )
    if plot is not None:
        stops = [s for s in events if isinstance(s, Stop)]
        slowest = min(s.deceleration for s in stops)
        trace = block_trace(stops, coast=min(0.1, 0.25 * slowest), name=source.name)
        shown = detect_events(
            trace,
            config=TraceCycleConfig.no_corrections(
                threshold=0.5 * slowest, min_duration=0.0, merge_gap=0.0
            ),
        )
        from brakeca.plotting import plot_trace

        figure = plot_trace(
            trace,
            shown,
            title=f"{source.name}: {len(shown)} stops, drawn with invented drives between them",
        )
        _write_plot(figure, plot)


@cycle_app.command("inspect", short_help="events, distance, braking energy and a plot of a cycle")
def inspect(
    file: Annotated[
        str,
        typer.Argument(
            metavar="CYCLE",
            help="a speed trace or block cycle CSV, or a shipped cycle: paper, example_trace",
        ),
    ],
    threshold: Annotated[
        float | None,
        typer.Option(
            "--threshold",
            metavar="X",
            help="[m/s²] a trace's braking: decelerating faster than this  [default: 0.3]",
        ),
    ] = None,
    min_duration: Annotated[
        float | None,
        typer.Option(
            "--min-duration",
            metavar="X",
            help="[s] a trace's shortest braking event kept  [default: 2]",
        ),
    ] = None,
    smoothing: Annotated[
        float | None,
        typer.Option(
            "--smoothing",
            metavar="X",
            help="[s] a trace's moving-average window on the speed  [default: 0]",
        ),
    ] = None,
    merge_gap: Annotated[
        float | None,
        typer.Option(
            "--merge-gap",
            metavar="X",
            help="[s] a trace's braking stretches this close are joined  [default: 1]",
        ),
    ] = None,
    speed_unit: Annotated[
        str | None,
        typer.Option(
            "--speed-unit",
            metavar="UNIT",
            help="a trace's speed unit, km/h, m/s or mph, if its header states none",
        ),
    ] = None,
    no_corrections: Annotated[
        bool,
        typer.Option("--no-corrections", help="brake share 1 and no road load (as a block cycle)"),
    ] = False,
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="PATH",
            parser=_file_path,
            help="figure of the trace, events shaded (.png; .pdf, .svg... by the suffix)",
        ),
    ] = None,
) -> None:
    """Events found, distance, braking energy, and a plot of a drive cycle."""
    updates = {
        k: v
        for k, v in {
            "threshold": threshold,
            "min_duration": min_duration,
            "smoothing": smoothing,
            "merge_gap": merge_gap,
        }.items()
        if v is not None
    }
    if output is not None:  # before the table: a plot that cannot be written, up front
        from brakeca.cli import _check_figure_output

        _check_figure_output(output)
    try:
        given = [f"--{k.replace('_', '-')}" for k in updates]
        if given and cycle_file_kind(_read_text(file)[0]) == "blocks":
            # refused, as --speed-unit is (a command-line review: ignored without a word);
            # --no-corrections is what a block cycle is anyway
            raise ConfigError(
                f"{file} is a block cycle, whose stops are given: {', '.join(given)} "
                f"{'applies' if len(given) == 1 else 'apply'} to a speed trace's event "
                "detection; remove " + ("it" if len(given) == 1 else "them")
            )
        if no_corrections:
            tc = TraceCycleConfig.no_corrections(**updates)
        else:
            # a field of the options is named by the option that gave it
            heads = {name: f"--{name.replace('_', '-')}" for name in updates}
            tc = TraceCycleConfig.from_dict(updates, source="options", heads=heads)
        inspect_cycle(file, tc, speed_unit=speed_unit, plot=output)
    except ConfigError as exc:
        _fail(str(exc))
