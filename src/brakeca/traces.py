"""Real drive cycles as speed traces: loading, braking-event detection, per-event kinematics.

A speed trace is a CSV of time [s] and vehicle speed (km/h, m/s or mph, stated in the header or
given as an option). Braking events are the stretches where the vehicle decelerates faster than
a threshold for at least a minimum duration. Each event is simulated with its own speed
profile: as in the block cycle, a time step is the time the disc takes to pass one subdomain,
so every step covers the same vehicle travel ``s``; the step durations follow the measured
speed, and the deceleration the modelled brake must deliver follows the measured deceleration,
less the share of road load (rolling resistance and aerodynamic drag) and of the other brakes.

Between two samples the speed is taken as linear in time (constant acceleration), which is
exact for a trace built from constant-deceleration stops: such a trace reproduces the block
cycle's step durations and decelerations to round-off (``tests/unit/test_traces.py``).

Every number that shapes an event lives in :class:`TraceCycleConfig`, with its default, its
literature range and its source (also in ``docs/cycles.md``).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.4 (time
step, drive cycle). UN GTR No. 24 (laboratory measurement of brake emissions, WLTP-Brake cycle).
J. Y. Wong, Theory of Ground Vehicles, 4th ed., Wiley 2008, ch. 1 and 3 (road load).
R. Limpert, Brake Design and Safety, 3rd ed., SAE 2011 (brake force distribution).
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Literal

import numpy as np

from brakeca._io import write_text
from brakeca.config import (
    ConfigError,
    SimulationConfig,
    TraceCycleConfig,
    csv_delimiter,
    csv_float,
    decimal_point,
    excel_separator,
    read_csv_text,
)
from brakeca.cycle import KMH, Stop, StopProfile, check_step_count, expand_stops

__all__ = [
    "MPH",
    "BrakingEvent",
    "CycleSource",
    "EventKinematics",
    "SpeedTrace",
    "TraceCycleConfig",
    "TraceError",
    "available_cycles",
    "block_trace",
    "brake_work",
    "braking_energy",
    "cycle_file_kind",
    "detect_events",
    "distance_until",
    "event_distance",
    "expand_trace_events",
    "load_cycle_events",
    "load_cycle_source",
    "load_trace",
    "trace_distance",
    "write_trace",
]

MPH = 0.44704  #: one mile per hour in m/s

#: Speed units accepted in a header or as ``speed_unit`` (normalised spelling -> m/s).
SPEED_UNITS: dict[str, float] = {
    "km/h": KMH,
    "kmh": KMH,
    "km_h": KMH,
    "kph": KMH,
    "kmph": KMH,
    "m/s": 1.0,
    "m_s": 1.0,
    "ms": 1.0,
    "mps": 1.0,
    "ms-1": 1.0,
    "mph": MPH,
}
#: Time units accepted in a header (normalised spelling -> s).
TIME_UNITS: dict[str, float] = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}

#: Above this speed [m/s] (250 km/h) a drive-cycle trace is taken to be in the wrong unit.
IMPLAUSIBLE_SPEED = 250.0 * KMH
#: Above this acceleration magnitude [m/s^2] (about 1.5 g) a trace is taken to be broken.
IMPLAUSIBLE_ACCELERATION = 15.0
#: A trace read as km/h whose top speed stays below this [km/h] ...
SUSPECT_TOP_SPEED_KMH = 50.0
#: ... and whose accelerations all stay below this [m/s^2] looks like m/s labelled km/h.
SUSPECT_MAX_ACCELERATION = 1.0

_UNIT_LABEL = {KMH: "km/h", 1.0: "m/s", MPH: "mph"}

_SHIPPED = resources.files("brakeca.presets").joinpath("cycles")


class TraceError(ConfigError):
    """A speed trace cannot be read or fails a check; the message names file, line and problem.

    Attributes
    ----------
    source : str
        The file (or trace name).
    line : int or None
        1-based line of the file the problem is on (None: the file as a whole).
    problem : str
        What is wrong.

    A trace built in code (no file lines) names the 1-based ``sample`` instead.
    """

    def __init__(
        self, source: str, line: int | None, problem: str, *, sample: int | None = None
    ) -> None:
        self.source = source
        self.line = line
        self.problem = problem
        where = source
        if line is not None:
            where = f"{source}, line {line}"
        elif sample is not None:
            where = f"{source}, sample {sample}"
        super().__init__(f"{where}: {problem}")


# --- parameters ----------------------------------------------------------------------------


def _readonly(values: Any, dtype: Any = np.float64) -> np.ndarray:
    arr = np.array(values, dtype=dtype)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class SpeedTrace:
    """A vehicle speed trace (SI units), checked on construction.

    Attributes
    ----------
    time : ndarray
        Sample times, strictly increasing [s].
    speed : ndarray
        Vehicle speed at each sample, finite and >= 0 [m/s].
    source : str
        Where the trace came from (file path or a description), used in messages.
    name : str
        Short name (file stem), the default block label of its events.
    trip : tuple of str or None
        Trip label of each sample (from a ``trip`` column), or None.
    line : ndarray of int or None
        File line of each sample (messages name it), or None.
    """

    time: np.ndarray
    speed: np.ndarray
    source: str = "trace"
    name: str = "trace"
    trip: tuple[str, ...] | None = None
    line: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = _readonly(self.time)
        v = _readonly(self.speed)
        object.__setattr__(self, "time", t)
        object.__setattr__(self, "speed", v)
        if self.line is not None:
            object.__setattr__(self, "line", _readonly(self.line, np.int64))
        if self.trip is not None:
            object.__setattr__(self, "trip", tuple(str(x) for x in self.trip))
        if t.ndim != 1 or v.shape != t.shape:
            raise TraceError(self.source, None, "time and speed must be 1-D and of equal length")
        if self.line is not None and self.line.shape != t.shape:
            raise TraceError(self.source, None, "one line number per sample is needed")
        if self.trip is not None and len(self.trip) != t.size:
            raise TraceError(self.source, None, "one trip label per sample is needed")
        if t.size == 0:
            raise TraceError(self.source, None, "empty trace: no samples")
        if t.size < 2:
            raise TraceError(
                self.source, self._line(0), "only one sample; a trace needs at least two", sample=1
            )
        with np.errstate(invalid="ignore"):
            bad = ~np.isfinite(t) | ~np.isfinite(v) | (v < 0.0)
            bad[1:] |= ~(np.diff(t) > 0.0)
        if bad.any():  # the first offender, in file order
            k = int(np.flatnonzero(bad)[0])
            if not math.isfinite(t[k]):
                problem = f"time is {t[k]}"
            elif not math.isfinite(v[k]):
                problem = f"speed is {v[k]}"
            elif v[k] < 0.0:
                problem = f"negative speed {v[k]:g} m/s (speeds are 0 or more)"
            else:
                problem = (
                    f"time {t[k]:g} s is not after the previous sample's {t[k - 1]:g} s "
                    "(time must increase)"
                )
            raise TraceError(self.source, self._line(k), problem, sample=k + 1)

    def _line(self, k: int) -> int | None:
        return None if self.line is None else int(self.line[k])

    def where(self, k: int) -> str:
        """``"line L"`` of sample ``k`` (0-based), or ``"sample k+1"`` without line numbers.

        Parameters
        ----------
        k
            0-based sample index [-].

        Returns
        -------
        str
            Where the sample is, for messages.
        """
        return f"line {self.line[k]}" if self.line is not None else f"sample {k + 1}"

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return float(self.time[-1] - self.time[0])

    @property
    def distance(self) -> float:
        """Distance travelled over the whole trace [m]."""
        return trace_distance(self)

    def cumulative_distance(self) -> np.ndarray:
        """Distance travelled from the first sample to each sample [m] (speed linear in time).

        Returns
        -------
        ndarray
            Float64 array of the trace's length, 0 at the first sample [m].
        """
        t, v = self.time, self.speed
        seg = 0.5 * (v[:-1] + v[1:]) * np.diff(t)
        return np.concatenate(([0.0], np.cumsum(seg)))

    def acceleration(self) -> np.ndarray:
        """Acceleration of each sample interval, dv/dt [m/s^2] (length n - 1).

        Returns
        -------
        ndarray
            Float64 array of length n - 1, negative while decelerating [m/s^2].
        """
        return np.diff(self.speed) / np.diff(self.time)


def trace_distance(trace: SpeedTrace) -> float:
    """Distance travelled over ``trace`` [m], speed linear in time between samples.

    Parameters
    ----------
    trace
        The speed trace.

    Returns
    -------
    float
        Distance from the first to the last sample [m].
    """
    return float(trace.cumulative_distance()[-1])


def distance_until(trace: SpeedTrace, time: float) -> float:
    """Distance travelled from the start of ``trace`` until ``time`` [s] (clipped) [m].

    Parameters
    ----------
    trace
        The speed trace.
    time
        A time on the trace's clock (as ``trace.time``, not since its first sample) [s];
        clipped to the trace's first and last sample.

    Returns
    -------
    float
        Distance from the first sample to ``time`` [m], exact for speed linear in time
        between samples.
    """
    t, v = trace.time, trace.speed
    x = trace.cumulative_distance()
    if time <= t[0]:
        return 0.0
    if time >= t[-1]:
        return float(x[-1])
    j = int(np.searchsorted(t, time, side="right")) - 1
    tau = time - t[j]
    acc = (v[j + 1] - v[j]) / (t[j + 1] - t[j])
    return float(x[j] + v[j] * tau + 0.5 * acc * tau * tau)


# --- loading ----------------------------------------------------------------------------------


def _norm_unit(text: str) -> str:
    return re.sub(r"\s+", "", text.strip().lower()).replace("^-1", "-1")


def _split_header(text: str) -> tuple[str, str | None]:
    """Column title -> (lower-case name, unit or None): ``time [s]``, ``speed_kmh``."""
    raw = text.strip().strip("\"'").strip()
    m = re.fullmatch(r"(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]", raw)
    if m:
        return m.group(1).strip().lower(), _norm_unit(m.group(2))
    low = raw.lower()
    for unit in sorted({*SPEED_UNITS, *TIME_UNITS}, key=lambda u: (-len(u), u)):
        if low.endswith("_" + unit) and len(low) > len(unit) + 1:
            return low[: -len(unit) - 1], unit
    return low, None


#: Column names that are a role alone (beside the role's own name), chosen among several.
_PLAIN_NAMES = {"time": ("t",), "speed": ("v", "velocity", "vehicle_speed")}


def _role(name: str) -> str | None:
    if name == "t" or "time" in name:
        return "time"
    if name == "v" or "speed" in name or "velocity" in name:
        return "speed"
    if name in ("trip", "phase", "label"):
        return "trip"
    return None


def _parse_number(
    text: str, what: str, source: str, line: int, *, decimal_comma: bool = False
) -> float:
    if not text:
        raise TraceError(source, line, f"{what} is missing")
    if decimal_comma:
        text = decimal_point(text)  # "12,5" from a spreadsheet in a decimal-comma locale
    try:
        value = csv_float(text)
    except ValueError:
        raise TraceError(source, line, f"{what} {text!r} is not a number") from None
    if math.isnan(value):
        raise TraceError(source, line, f"{what} is NaN (every sample needs a finite number)")
    if math.isinf(value):
        raise TraceError(
            source, line, f"{what} is infinite ({text}; every sample needs a finite number)"
        )
    return value


def _speed_factor(unit: str, source: str, line: int | None, origin: str) -> float:
    key = _norm_unit(unit)
    if key not in SPEED_UNITS:
        raise TraceError(
            source,
            line,
            f"unknown speed unit {unit!r} ({origin}); use one of km/h, m/s, mph",
        )
    return SPEED_UNITS[key]


def _read_text(path_or_name: str | Path) -> tuple[str, str, str]:
    """(text, source, name) of a trace file or a shipped cycle."""
    p = Path(path_or_name)
    if p.is_file():
        try:
            return read_csv_text(p), str(p), p.stem
        except (OSError, UnicodeDecodeError) as exc:
            raise TraceError(str(p), None, f"cannot read: {exc}") from None
    shipped = _SHIPPED.joinpath(f"{path_or_name}.csv")
    if shipped.is_file():
        return shipped.read_text(encoding="utf-8-sig"), f"cycle {path_or_name}", str(path_or_name)
    if p.is_dir():  # (it was "no such file": a fuzz review)
        raise TraceError(str(p), None, "a folder, not a cycle's CSV file")
    raise TraceError(
        str(path_or_name),
        None,
        f"no such file, nor a shipped cycle ({', '.join(available_cycles())})",
    )


def load_trace(path: str | Path, *, speed_unit: str | None = None) -> SpeedTrace:
    """Load and check a speed trace CSV (or a shipped trace by name).

    Parameters
    ----------
    path
        CSV file: ``#`` comment lines, then a header naming a time column (``time_s``,
        ``time [s]``; a bare ``time`` is read as seconds) and a speed column (``speed_kmh``,
        ``speed [km/h]``, ``speed [m/s]``, ``speed_mph``), optionally a ``trip`` column
        (labels the events); other columns are ignored. Comma, semicolon or tab separated;
        a semicolon or tab separated file may write decimal commas (``12,5``), as spreadsheets
        do in such locales.
    speed_unit
        ``"km/h"``, ``"m/s"`` or ``"mph"``: the unit of the speed column when the header does
        not state one; it must agree with the header when both do. Giving it also confirms
        a slow, gentle km/h trace that would otherwise be refused as m/s labelled km/h.

    Returns
    -------
    SpeedTrace
        Time [s] and speed [m/s], with the file line of every sample.

    Raises
    ------
    TraceError
        Naming the file, the line and the problem: no such file nor shipped trace, or one
        that cannot be read; no header or no data (empty file), a missing or non-numeric
        value, NaN or infinite values, negative speed, time not increasing, an unknown or
        conflicting unit, speeds that look like m/s given as km/h (or km/h given as m/s).
    """
    text, source, name = _read_text(path)
    header: list[str] | None = None
    header_line = 0
    delim = ","
    comma = False
    cols: dict[str, int] = {}
    t_factor = v_factor = 1.0
    unit_label = ""
    confirmed = speed_unit is not None
    labelled: str | None = None  # the speed column's title where it states the unit
    times: list[float] = []
    speeds: list[float] = []
    trips: list[str] = []
    lines: list[int] = []
    named: str | None = None  # the separator an Excel "sep=;" line names
    for lineno, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        if header is None and named is None and (named := excel_separator(raw)) is not None:
            continue
        if header is None:
            delim = named or csv_delimiter(s)
            comma = delim != ","  # a semicolon or tab separated file may use decimal commas
            header = [c.strip() for c in s.split(delim)]
            header_line = lineno
            cols, t_factor, v_factor, unit_label, labelled = _read_header(
                header, source, lineno, speed_unit
            )
            continue
        fields = [f.strip().strip("\"'") for f in s.split(delim)]
        if not any(fields):  # a spreadsheet's row of separators alone: a blank line
            continue
        need = max(cols.values()) + 1
        if len(fields) < need:
            raise TraceError(
                source, lineno, f"expected {len(header)} values, found {len(fields)}: {s!r}"
            )
        if any(fields[len(header) :]):  # an empty value past the header's is a trailing delimiter
            raise TraceError(
                source,
                lineno,
                f"expected {len(header)} values, found more: {s!r} (a decimal comma in a "
                f"file separated by {'commas' if delim == ',' else repr(delim)}? write decimal "
                "points there, or separate the values with ';')",
            )
        t = _parse_number(fields[cols["time"]], "time", source, lineno, decimal_comma=comma)
        v = _parse_number(fields[cols["speed"]], "speed", source, lineno, decimal_comma=comma)
        if v < 0.0:
            raise TraceError(
                source,
                lineno,
                f"negative speed {fields[cols['speed']]} {unit_label} (speeds are 0 or more: "
                "clip a logger's noise about 0 before reading the trace)",
            )
        if times and t * t_factor <= times[-1]:
            raise TraceError(
                source,
                lineno,
                f"time {fields[cols['time']]} is not after {times[-1] / t_factor:g}, the time "
                f"on line {lines[-1]}: time must increase",
            )
        times.append(t * t_factor)
        speeds.append(v * v_factor)
        lines.append(lineno)
        if "trip" in cols:
            trips.append(fields[cols["trip"]])
    if header is None:
        raise TraceError(source, None, "empty file: no header line and no data")
    if not times:
        raise TraceError(source, header_line, "no data after the header (empty trace)")
    trace = SpeedTrace(
        time=np.asarray(times),
        speed=np.asarray(speeds),
        source=source,
        name=name,
        trip=tuple(trips) if trips else None,
        line=np.asarray(lines),
    )
    _check_plausible(trace, v_factor, unit_label, confirmed, labelled)
    return trace


def _read_header(
    header: list[str], source: str, line: int, speed_unit: str | None
) -> tuple[dict[str, int], float, float, str, str | None]:
    """The columns by role, the time and speed factors to SI, the speed unit's label, and
    the speed column's title where it states the unit (None where the option gives it)."""
    cols: dict[str, int] = {}
    units: dict[str, str | None] = {}
    found: dict[str, list[tuple[int, str, str | None]]] = {}
    for k, title in enumerate(header):
        name, unit = _split_header(title)
        role = _role(name)
        if role is not None:
            found.setdefault(role, []).append((k, name, unit))
    for role, candidates in found.items():
        # several columns of a role (wind_speed beside speed): the one named the role alone,
        # else none is guessed (the first had been taken, a wind speed for the vehicle's)
        plain = [c for c in candidates if c[1] == role or c[1] in _PLAIN_NAMES.get(role, ())]
        if len(candidates) > 1 and len(plain) != 1:
            titles = ", ".join(repr(header[c[0]]) for c in candidates)
            raise TraceError(
                source,
                line,
                f"several {role} columns ({titles}): name the vehicle's {role} column "
                f"{role} alone (e.g. '{'speed_kmh' if role == 'speed' else 'time_s'}'), or "
                "remove the others",
            )
        k, _, unit = plain[0] if len(candidates) > 1 else candidates[0]
        cols[role] = k
        units[role] = unit
    if "time" not in cols or "speed" not in cols:
        raise TraceError(
            source,
            line,
            f"expected a header naming a time and a speed column, e.g. 'time_s,speed_kmh' or "
            f"'time [s],speed [km/h]'; got the columns {', '.join(map(repr, header))}. (A "
            "block cycle's header is 'name,initial_speed_kmh,final_speed_kmh,deceleration_g,"
            "stops': a column whose name begins 'initial_speed' makes the file one; "
            "docs/cycles.md)",
        )
    t_unit = units["time"] or "s"
    if _norm_unit(t_unit) not in TIME_UNITS:
        raise TraceError(source, line, f"unknown time unit {t_unit!r}; use s, ms, min or h")
    t_factor = TIME_UNITS[_norm_unit(t_unit)]
    head_unit = units["speed"]
    if head_unit is None and speed_unit is None:
        raise TraceError(
            source,
            line,
            f"the speed column {header[cols['speed']]!r} states no unit: name it speed_kmh, "
            "'speed [km/h]' or 'speed [m/s]', or give the unit (speed_unit / --speed-unit)",
        )
    if head_unit is not None:
        factor = _speed_factor(head_unit, source, line, "header")
        if speed_unit is not None:
            given = _speed_factor(speed_unit, source, None, "speed_unit / --speed-unit")
            if given != factor:
                raise TraceError(
                    source,
                    line,
                    f"the header gives the speed in {_UNIT_LABEL[factor]} "
                    f"({header[cols['speed']]!r}) but the speed unit option says {speed_unit}",
                )
        return cols, t_factor, factor, _UNIT_LABEL[factor], header[cols["speed"]]
    assert speed_unit is not None
    factor = _speed_factor(speed_unit, source, None, "speed_unit / --speed-unit")
    return cols, t_factor, factor, _UNIT_LABEL[factor], None


def _check_plausible(
    trace: SpeedTrace, v_factor: float, unit: str, confirmed: bool, labelled: str | None = None
) -> None:
    """Refuse traces whose numbers look like the wrong unit (see the module constants).
    ``labelled``: the speed column's title where it states the unit. Without the unit
    option (``confirmed`` false) the unit is the header's, which the option may not
    contradict, so a message asks to rename that column (a review: it had advised the
    option, which was then refused)."""
    v = trace.speed
    acc = np.abs(trace.acceleration())
    top = int(np.argmax(v))
    column = repr(labelled) if labelled is not None else "of speed"
    # the unit given explicitly confirms a fast trace only in km/h: a trace in km/h given
    # as m/s (or mph) by the option is the very slip this check is for (a review's 120 km/h
    # samples ran at 432 km/h with --speed-unit m/s)
    if v[top] > IMPLAUSIBLE_SPEED and not (confirmed and v_factor == KMH):
        raise TraceError(
            trace.source,
            trace._line(top),
            f"speed {v[top] / v_factor:g} {unit}"
            + (f" ({v[top] / KMH:.0f} km/h)" if unit != "km/h" else "")
            + " is beyond any drive cycle"
            + (
                (
                    ": is the file in km/h? Give its unit as km/h, or check the data"
                    if confirmed and labelled is None
                    else f": is the file in km/h but labelled {unit}? If so, rename the "
                    f"column {column} to speed_kmh or 'speed [km/h]'"
                    + (" (and give km/h as the unit option, or none)" if confirmed else "")
                )
                if unit != "km/h"
                else ": a glitch in the data, or a unit mix-up (give --speed-unit to confirm "
                "the file's unit)"
            ),
        )
    k = int(np.argmax(acc))
    if acc[k] > IMPLAUSIBLE_ACCELERATION:
        raise TraceError(
            trace.source,
            trace._line(k + 1),
            f"the speed changes by {acc[k]:.3g} m/s^2 from {trace.where(k)}, beyond a car's "
            "grip: a unit mix-up (km/h read as m/s) or a glitch in the data",
        )
    if (
        not confirmed
        and v_factor == KMH
        and v[top] > 0.0
        and v[top] < SUSPECT_TOP_SPEED_KMH * KMH
        and acc[k] < SUSPECT_MAX_ACCELERATION
    ):
        raise TraceError(
            trace.source,
            trace._line(top),
            f"the speeds look like m/s given as km/h: the top speed is {v[top] / KMH:.3g} km/h "
            f"and no acceleration exceeds {acc[k]:.2g} m/s^2, a car trace read in km/h would "
            f"show more. If the file is in m/s, rename the column {column} "
            "to speed_ms or 'speed [m/s]'; if km/h is right, confirm it (--speed-unit km/h, "
            "speed_unit='km/h')",
        )


def write_trace(trace: SpeedTrace, path: str | Path, *, comment: str = "") -> Path:
    """Write ``trace`` as CSV ``time_s,speed_kmh[,trip]`` at full float precision.

    Parameters
    ----------
    trace
        The speed trace (time [s], speed [m/s]; written as s and km/h).
    path
        The file to write (replaced if it exists).
    comment
        Text written first, each of its lines as a ``#`` comment line.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    out = [f"# {ln}" for ln in comment.splitlines()]
    out.append("time_s,speed_kmh" + (",trip" if trace.trip is not None else ""))
    for k in range(trace.time.size):
        row = f"{float(trace.time[k])!r},{float(trace.speed[k] * 3.6)!r}"
        if trace.trip is not None:
            row += f",{trace.trip[k]}"
        out.append(row)
    return write_text(path, "\n".join(out) + "\n")


# --- events -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class EventKinematics:
    """The equal-distance steps of one braking event, with the quantities behind them.

    Attributes
    ----------
    dt : ndarray
        Duration of each step [s].
    fraction : ndarray
        Fraction of a full step travelled [-] (1 except for the last, partial step).
    speed : ndarray
        Speed at the step boundaries, length n + 1 [m/s].
    deceleration : ndarray
        Mean vehicle deceleration of each step, (v_k - v_k+1) / dt_k [m/s^2].
    brake_deceleration : ndarray
        What the modelled brake must deliver for its wheel-load mass [m/s^2]
        (:meth:`TraceCycleConfig.brake_deceleration`).
    """

    dt: np.ndarray
    fraction: np.ndarray
    speed: np.ndarray
    deceleration: np.ndarray
    brake_deceleration: np.ndarray


@dataclass(frozen=True, eq=False)
class BrakingEvent:
    """One braking event of a speed trace, usable wherever a :class:`~brakeca.cycle.Stop` is.

    Attributes
    ----------
    index : int
        1-based event number in the cycle [-].
    block : str
        Label: the trip of the brake-on sample, else the trace name.
    time : ndarray
        Sample times from brake-on to brake-off [s].
    speed : ndarray
        Speed at those samples [m/s] (smoothed when detection smoothed).
    corrections : TraceCycleConfig
        Road load and brake share applied by :meth:`profile`.
    first_line, last_line : int or None
        File lines of the brake-on and brake-off samples.
    """

    index: int
    block: str
    time: np.ndarray
    speed: np.ndarray
    corrections: TraceCycleConfig = field(default_factory=TraceCycleConfig)
    first_line: int | None = None
    last_line: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "time", _readonly(self.time))
        object.__setattr__(self, "speed", _readonly(self.speed))
        if self.time.size < 2 or self.speed.shape != self.time.shape:
            raise ValueError(f"event {self.index}: needs two or more (time, speed) samples")
        if not np.all(np.diff(self.time) > 0) or np.any(self.speed < 0):
            raise ValueError(f"event {self.index}: time must increase and speed be >= 0")
        if self.distance <= 0.0:
            raise ValueError(f"event {self.index}: the vehicle does not move")

    @property
    def initial_speed(self) -> float:
        """Speed at brake-on [m/s]."""
        return float(self.speed[0])

    @property
    def final_speed(self) -> float:
        """Speed at brake-off [m/s]."""
        return float(self.speed[-1])

    @property
    def start_time(self) -> float:
        """Brake-on time in the trace [s]."""
        return float(self.time[0])

    @property
    def end_time(self) -> float:
        """Brake-off time in the trace [s]."""
        return float(self.time[-1])

    @property
    def duration(self) -> float:
        """Event duration [s]."""
        return self.end_time - self.start_time

    @property
    def deceleration(self) -> float:
        """Mean vehicle deceleration, (v_on - v_off) / duration [m/s^2] (for display)."""
        return (self.initial_speed - self.final_speed) / self.duration

    @property
    def distance(self) -> float:
        """Distance travelled during the event [m]."""
        dt = np.diff(self.time)
        return float(np.sum(0.5 * (self.speed[:-1] + self.speed[1:]) * dt))

    def kinematics(self, distance: float) -> EventKinematics:
        """The event cut into steps of equal vehicle travel ``distance`` [m].

        Between samples the speed is linear in time, so ``v^2 = v_j^2 + 2 a_j x`` holds exactly
        within sample interval ``j``; a step boundary at travel ``x`` is placed there and its time
        solved in closed form. As in the block cycle, the last step is partial.

        Parameters
        ----------
        distance
            Vehicle travel of one full step, s [m] (:func:`brakeca.cycle.step_distance`).

        Returns
        -------
        EventKinematics
            Per step (n steps): durations [s], fractions of a full step [-], mean vehicle
            decelerations [m/s^2] and the brake's decelerations after road load and brake
            share [m/s^2]; the speeds at the n + 1 step boundaries [m/s].

        Raises
        ------
        ValueError
            If ``distance`` is not positive, or a step comes out with no duration (a bad
            trace); a :class:`~brakeca.config.ConfigError` (a ``ValueError``) if the event
            would take more than :data:`brakeca.cycle.MAX_STOP_STEPS` steps.
        """
        if not distance > 0.0:
            raise ValueError(f"step distance must be positive, got {distance}")
        t, v = self.time, self.speed
        dts = np.diff(t)
        acc = np.diff(v) / dts  # acceleration of each sample interval
        xs = np.concatenate(([0.0], np.cumsum(0.5 * (v[:-1] + v[1:]) * dts)))
        total_x = float(xs[-1])
        total = total_x / distance  # full steps, fractional
        check_step_count(total, distance, f"event {self.index} ({self.block})")
        n_full = math.floor(total)
        rest = total - n_full
        if rest < 1e-9 and n_full > 0:  # ends on a full step (to round-off), as stop_steps
            rest = 0.0
        n = n_full + (1 if rest > 0.0 else 0)
        x = np.minimum(np.arange(n + 1, dtype=np.float64), total) * distance
        x[-1] = total_x
        m = dts.size

        def at(jj: np.ndarray, xq: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            """Time since the start of interval jj, and speed, at travel xq."""
            d = xq - xs[jj]
            vj = v[jj]
            vq = np.sqrt(np.maximum(vj * vj + 2.0 * acc[jj] * d, 0.0))
            den = vj + vq
            return np.divide(2.0 * d, den, out=np.zeros_like(d), where=den > 0.0), vq

        # interval j holds x in (xs[j], xs[j+1]] (x = 0 in interval 0): where a step ends;
        # j_start holds x in [xs[j], xs[j+1]): where a step starts
        j = np.clip(np.searchsorted(xs, x, side="left") - 1, 0, m - 1)
        tau_end, vx = at(j, x)
        vx[0], vx[-1] = v[0], v[-1]
        tau_end[-1] = dts[-1]
        j_start = np.clip(np.searchsorted(xs, x[:-1], side="right") - 1, 0, m - 1)
        tau_start, _ = at(j_start, x[:-1])
        j_end = j[1:]
        same = j_start == j_end
        # times as sums of in-interval pieces, not differences of absolute times (round-off)
        whole = np.concatenate(([0.0], np.cumsum(dts)))
        dt = np.where(
            same,
            tau_end[1:] - tau_start,
            (dts[j_start] - tau_start) + (whole[j_end] - whole[j_start + 1]) + tau_end[1:],
        )
        # within one interval of constant a: dt = dv / a, exactly as cycle.stop_steps, where
        # dv stands above the speeds' round-off; at a speed constant but for round-off (a
        # smoothed or merged hold: |a| ~ 1e-15 m/s^2) dv / a is round-off over round-off, 0 or
        # of either sign, and the times of the ends are kept
        a_step = acc[j_end]
        dv = vx[1:] - vx[:-1]
        exact = same & (a_step != 0.0) & (np.abs(dv) > 1e-9 * np.maximum(vx[1:], vx[:-1]))
        np.divide(dv, a_step, out=dt, where=exact)
        if np.any(dt <= 0.0):
            k = int(np.flatnonzero(dt <= 0.0)[0])
            raise ValueError(f"event {self.index}: step {k + 1} has no duration (bad trace)")
        decel = np.where(exact, -a_step, -dv / dt)
        fraction = np.ones(n)
        if rest > 0.0:
            fraction[-1] = rest
        mean_speed = fraction * distance / dt
        brake = self.corrections.brake_deceleration(decel, mean_speed)
        return EventKinematics(dt, fraction, vx, decel, brake)

    def profile(self, distance: float) -> StopProfile:
        """The time steps of this event for a full-step travel ``distance`` [m].

        ``deceleration`` is what the modelled brake must deliver for its wheel-load mass
        (road load and brake share applied); see :meth:`kinematics`.

        Parameters
        ----------
        distance
            Vehicle travel of one full step, s [m].

        Returns
        -------
        StopProfile
            Step durations [s], fractions of a full step [-] and the brake's deceleration of
            each step [m/s^2].

        Raises
        ------
        ValueError
            As :meth:`kinematics`.
        """
        k = self.kinematics(distance)
        return StopProfile(k.dt, k.fraction, k.brake_deceleration)


def _smooth(time: np.ndarray, speed: np.ndarray, window: float) -> np.ndarray:
    """Centred moving average over ``window`` seconds (sample mean)."""
    if window <= 0.0:
        return speed
    lo = np.searchsorted(time, time - window / 2.0, side="left")
    hi = np.searchsorted(time, time + window / 2.0, side="right")
    c = np.concatenate(([0.0], np.cumsum(speed)))
    return np.maximum((c[hi] - c[lo]) / (hi - lo), 0.0)


def detect_events(
    trace: SpeedTrace,
    *,
    threshold: float | None = None,
    min_duration: float | None = None,
    config: TraceCycleConfig | None = None,
) -> list[BrakingEvent]:
    """Find the braking events of ``trace``.

    A sample interval brakes when the vehicle decelerates faster than ``threshold``
    (``-dv/dt > threshold``, on the speed smoothed over ``config.smoothing`` seconds when
    set). Braking intervals separated by at most ``config.merge_gap`` seconds join into one
    stretch; stretches shorter than ``min_duration`` or without a net speed drop are dropped.
    An event runs from the first sample of its stretch (brake-on) to the last (brake-off).

    Parameters
    ----------
    trace
        The speed trace.
    threshold
        Detection threshold [m/s^2]; default ``config.threshold``.
    min_duration
        Shortest event kept [s]; default ``config.min_duration``.
    config
        Detection, road-load and brake-share parameters (default :class:`TraceCycleConfig`).

    Returns
    -------
    list of BrakingEvent
        In time order, numbered from 1.

    Raises
    ------
    ConfigError
        If ``threshold`` or ``min_duration`` lies outside the range its
        :class:`TraceCycleConfig` field allows.
    """
    cfg = config or TraceCycleConfig()
    updates: dict[str, float] = {}
    if threshold is not None:
        updates["threshold"] = threshold
    if min_duration is not None:
        updates["min_duration"] = min_duration
    if updates:
        cfg = TraceCycleConfig.from_dict({**cfg.model_dump(), **updates})
    t = trace.time
    v = _smooth(t, trace.speed, cfg.smoothing)
    braking = -(np.diff(v) / np.diff(t)) > cfg.threshold
    edges = np.diff(np.concatenate(([0], braking.astype(np.int8), [0])))
    starts = np.flatnonzero(edges == 1)  # first braking interval = brake-on sample
    ends = np.flatnonzero(edges == -1)  # one past the last braking interval = brake-off sample
    spans: list[list[int]] = []
    for a, b in zip(starts.tolist(), ends.tolist(), strict=True):
        if spans and t[a] - t[spans[-1][1]] <= cfg.merge_gap:
            spans[-1][1] = b
        else:
            spans.append([a, b])
    events: list[BrakingEvent] = []
    for a, b in spans:
        # to the time stamps' round-off: 2.3 - 0.3 s is 1.9999999999999998 s, and a 2 s
        # event had been kept or dropped by where it started
        if t[b] - t[a] < cfg.min_duration - 1e-9 * max(1.0, abs(t[b])) or not v[b] < v[a]:
            continue
        block = trace.trip[a] if trace.trip is not None else trace.name
        events.append(
            BrakingEvent(
                index=len(events) + 1,
                block=block,
                time=t[a : b + 1],
                speed=v[a : b + 1],
                corrections=cfg,
                first_line=None if trace.line is None else int(trace.line[a]),
                last_line=None if trace.line is None else int(trace.line[b]),
            )
        )
    return events


def slow_events_warning(events: Sequence[Stop | BrakingEvent], threshold: float) -> str | None:
    """Why a trace's events look like noise, or None: the events whose mean deceleration is
    below half the detection ``threshold`` [m/s^2].

    Every braking interval of an event decelerates faster than the threshold, so an event
    far slower on average is mostly the gaps that ``merge_gap`` joined (half: a clean,
    gentle stop with short pauses, merged, stays just under the threshold): on a measured
    trace, speed noise makes short dips that join into long "events" over most of the drive,
    and the simulation then brakes the whole way (a black-box review saw a noisy 10 Hz trace
    give 80 times the PM10 of the same trace smoothed).

    Parameters
    ----------
    events
        The cycle's events (block stops are never flagged).
    threshold
        The detection threshold, ``cycle.trace.threshold`` [m/s^2].

    Returns
    -------
    str or None
        How many events and the slowest, then what to do (two sentences).
    """
    slow = [e for e in events if isinstance(e, BrakingEvent) and e.deceleration < threshold / 2]
    if not slow:
        return None
    worst = min(slow, key=lambda e: e.deceleration)
    return (
        f"{len(slow)} of the {len(events)} braking events decelerate on average at less than "
        f"half the detection threshold ({threshold:g} m/s²), e.g. event {worst.index}: "
        f"{worst.deceleration:.2g} m/s² over {worst.duration:.3g} s. Speed noise makes short "
        "dips that join into long events, which brake most of the drive and inflate V and "
        "PM10: smooth the trace over about a second (cycle.trace.smoothing: --set "
        "cycle.trace.smoothing=1; cycle inspect --smoothing 1) and check its events with "
        "brakeca cycle inspect"
    )


def wheel_load_note(config: SimulationConfig) -> str | None:
    """Why a trace run's brake load does not fit its vehicle, or None: where the front
    wheel's share of the vehicle, ``cycle.trace.vehicle_mass * front_load_share / 2``,
    differs from ``vehicle.wheel_load_mass`` (the mass the simulated brake decelerates) by
    more than 10 %. The vehicle mass enters only the road load (a black-box review set a
    1200 kg car and got the 2300 kg car's brake load).

    Parameters
    ----------
    config
        A configuration (a block cycle gives None).

    Returns
    -------
    str or None
        One sentence with the two masses and the setting that makes them agree.
    """
    if not config.cycle.trace_file:
        return None
    tc = config.cycle.trace
    share = tc.vehicle_mass * tc.front_load_share / 2.0
    m_w = config.vehicle.wheel_load_mass
    if abs(share - m_w) <= 0.1 * m_w:
        return None
    return (
        f"the brake decelerates vehicle.wheel_load_mass = {m_w:g} kg, but this trace's car "
        f"puts {share:.4g} kg on a front wheel (cycle.trace.vehicle_mass {tc.vehicle_mass:g} "
        f"kg × front_load_share {tc.front_load_share:g} / 2), which enters only the road "
        f"load; for this car set vehicle.wheel_load_mass={share:.4g}"
    )


def expand_trace_events(
    trace: SpeedTrace,
    config: TraceCycleConfig | None = None,
    *,
    max_stops: int | None = None,
) -> list[BrakingEvent]:
    """The braking events of ``trace`` in driving order, cut to the first ``max_stops``.

    Parameters
    ----------
    trace
        The speed trace.
    config
        Detection, road-load and brake-share parameters (default :class:`TraceCycleConfig`).
    max_stops
        Most events to keep [-]; None keeps all.

    Returns
    -------
    list of BrakingEvent
        The first ``max_stops`` events of :func:`detect_events`.
    """
    events = detect_events(trace, config=config)
    return events if max_stops is None else events[:max_stops]


def event_distance(event: Stop | BrakingEvent) -> float:
    """Distance travelled while braking in one stop or event [m].

    Parameters
    ----------
    event
        A block stop (constant deceleration) or a trace event.

    Returns
    -------
    float
        Braking distance, ``(v_on^2 - v_off^2) / 2a`` for a stop, the integral of the
        (linear in time) speed for an event [m].
    """
    if isinstance(event, BrakingEvent):
        return event.distance
    v0, v1 = event.initial_speed, event.final_speed
    return (v0 * v0 - v1 * v1) / (2.0 * event.deceleration)


def braking_energy(events: Sequence[Stop | BrakingEvent], mass: float) -> float:
    """Kinetic energy a body of ``mass`` [kg] loses in the events, sum of m (v_on^2 - v_off^2)/2
    [J]. With the vehicle mass: what all brakes and road load absorb together.

    Parameters
    ----------
    events
        Block stops or trace events (their brake-on and brake-off speeds [m/s]).
    mass
        The decelerated mass m [kg].

    Returns
    -------
    float
        Kinetic energy lost [J].
    """
    return float(sum(0.5 * mass * (e.initial_speed**2 - e.final_speed**2) for e in events))


def brake_work(
    events: Sequence[Stop | BrakingEvent], wheel_mass: float, *, step: float = 0.05
) -> float:
    """Work of the modelled brake over the events, sum of m_w a_brake s f [J].

    Parameters
    ----------
    events
        Block stops or trace events (their :meth:`profile` gives a_brake).
    wheel_mass
        Mass the modelled brake decelerates, ``vehicle.wheel_load_mass`` [kg].
    step
        Travel per integration step [m] (trace events only; a block stop is exact).

    Returns
    -------
    float
        Work of the modelled brake [J].
    """
    total = 0.0
    for e in events:
        if isinstance(e, Stop):  # constant deceleration: exact
            total += wheel_mass * e.deceleration * event_distance(e)
            continue
        p = e.profile(step)
        total += float(np.sum(p.deceleration * p.fraction)) * step * wheel_mass
    return total


# --- a trace from block stops -----------------------------------------------------------------


def block_trace(
    stops: Sequence[Stop],
    *,
    acceleration: float = 1.5,
    coast: float = 0.1,
    cruise: float = 2.0,
    dwell: float = 1.0,
    sample_interval: float = 1.0,
    name: str = "blocks",
) -> SpeedTrace:
    """A speed trace that drives the block stops: reach v_on, cruise, brake at a, dwell.

    Between stops the car accelerates at ``acceleration`` [m/s^2] or, when the next stop
    starts slower, coasts down at ``coast`` [m/s^2] (below any detection threshold); it
    cruises ``cruise`` [s] at the brake-on speed, brakes at the stop's constant deceleration
    to its final speed, and holds that speed for ``dwell`` [s]. Samples fall at brake-on and
    brake-off exactly, and in between at equal intervals of at most ``sample_interval`` [s].
    Each sample is labelled with the block of the stop it leads to, so detected events carry
    the block names.

    Parameters
    ----------
    stops
        The block stops, in driving order; the trace starts at the first one's brake-on
        speed [m/s].
    acceleration
        Acceleration up to a faster brake-on speed [m/s^2].
    coast
        Deceleration down to a slower brake-on speed [m/s^2].
    cruise
        Time at the brake-on speed before each stop [s].
    dwell
        Time at the final speed after each stop [s].
    sample_interval
        Longest interval between samples [s].
    name
        The trace's name.

    Returns
    -------
    SpeedTrace
        Time [s] and speed [m/s], each sample labelled (``trip``) with its stop's block.

    Raises
    ------
    TraceError
        If ``stops`` is empty (a trace needs two samples).
    """
    times: list[float] = [0.0]
    speeds: list[float] = [stops[0].initial_speed if stops else 0.0]
    trips: list[str] = [stops[0].block if stops else name]

    def segment(duration: float, v_end: float, label: str, rate: float) -> None:
        t0, v0 = times[-1], speeds[-1]
        if duration <= 0.0:
            return
        n = max(math.ceil(duration / sample_interval - 1e-9), 1)  # equal intervals
        for k in range(1, n):
            times.append(t0 + duration * k / n)
            speeds.append(v0 + rate * duration * k / n)
            trips.append(label)
        times.append(t0 + duration)
        speeds.append(v_end)
        trips.append(label)

    for stop in stops:
        v_now, v_on = speeds[-1], stop.initial_speed
        if v_on > v_now:
            segment((v_on - v_now) / acceleration, v_on, stop.block, acceleration)
        elif v_on < v_now:
            segment((v_now - v_on) / coast, v_on, stop.block, -coast)
        segment(cruise, v_on, stop.block, 0.0)
        a = stop.deceleration
        segment((v_on - stop.final_speed) / a, stop.final_speed, stop.block, -a)
        segment(dwell, stop.final_speed, stop.block, 0.0)
    return SpeedTrace(
        time=np.asarray(times),
        speed=np.asarray(speeds),
        source=f"{name} (built from block stops)",
        name=name,
        trip=tuple(trips),
    )


# --- selecting a cycle --------------------------------------------------------------------------


def available_cycles() -> list[str]:
    """Names of the shipped cycles (block cycles and traces).

    Returns
    -------
    list of str
        The names, sorted (``"paper"``, the paper's block cycle, and ``"example_trace"``),
        each usable in place of a cycle file (``brakeca simulate --cycle NAME``,
        :func:`load_cycle_source`).
    """
    return sorted(p.name[:-4] for p in _SHIPPED.iterdir() if p.name.endswith(".csv"))


def cycle_file_kind(text: str) -> Literal["blocks", "trace"]:
    """``"blocks"`` when the CSV header has the block columns, else ``"trace"``.

    Parameters
    ----------
    text
        A cycle file's content.

    Returns
    -------
    str
        ``"blocks"`` when its first line that is neither blank, a ``#`` comment nor an Excel
        ``sep=`` line has a column whose name begins ``initial_speed`` (``initial_speed_kmh``;
        also in another unit, which the block reader then names as missing its km/h column,
        rather than reading a block file as a trace); ``"trace"`` otherwise (also for a file
        without such a line, and for a trace with other extra columns).
    """
    for raw in text.splitlines():
        s = raw.strip()
        if s and not s.startswith("#") and excel_separator(s) is None:
            names = [c.strip().strip('"').lower() for c in s.split(csv_delimiter(s))]
            return "blocks" if any(n.startswith("initial_speed") for n in names) else "trace"
    return "trace"


@dataclass(frozen=True, eq=False)
class CycleSource:
    """A drive cycle ready to simulate: its events and the distance they belong to.

    Attributes
    ----------
    name : str
        Cycle name (shipped name or file stem).
    kind : {"blocks", "trace"}
        Block cycle (constant-deceleration stops) or speed trace.
    events : tuple of Stop or BrakingEvent
        The stops to simulate, cut to ``cycle.max_stops``.
    n_total : int
        Stops or events in the whole cycle [-].
    distance : float
        Distance the simulated events belong to [m]: for a trace, the whole trace (or up to
        the last simulated event when cut); for a block cycle, the braking distance only (a
        block cycle does not say how far the car drives between stops).
    trace : SpeedTrace or None
        The trace, for a trace cycle.
    """

    name: str
    kind: Literal["blocks", "trace"]
    events: tuple[Stop | BrakingEvent, ...]
    n_total: int
    distance: float
    trace: SpeedTrace | None = None


def load_cycle_source(
    path_or_name: str | Path,
    config: SimulationConfig,
    trace_config: TraceCycleConfig | None = None,
    *,
    speed_unit: str | None = None,
) -> CycleSource:
    """Load a block cycle or a speed trace (a file or a shipped name) as events to simulate.

    Parameters
    ----------
    path_or_name
        A CSV file or a shipped cycle (:func:`available_cycles`). A header with
        ``initial_speed_kmh`` makes it a block cycle, anything else a speed trace.
    config
        Supplies gravity (block decelerations in g) and ``cycle.max_stops``.
    trace_config
        Detection, road load and brake share for a trace (default :class:`TraceCycleConfig`).
    speed_unit
        Speed unit of a trace without one in its header (:func:`load_trace`).

    Returns
    -------
    CycleSource
        The events, the count in the whole cycle and the distance they belong to [m].

    Raises
    ------
    ConfigError
        A path that is neither a file nor a shipped cycle's name, a file that cannot be
        read, a bad block cycle, or a bad trace (a :class:`TraceError`, as
        :func:`load_trace`).
    """
    from brakeca.presets import load_cycle

    text, _, name = _read_text(path_or_name)
    max_stops = config.cycle.max_stops
    if cycle_file_kind(text) == "blocks":
        _no_speed_unit(speed_unit, str(path_or_name))
        cyc = load_cycle(path_or_name)
        full = expand_stops(config.with_updates({"cycle": {**cyc.model_dump(), "max_stops": None}}))
        stops = full if max_stops is None else full[:max_stops]
        dist = float(sum(event_distance(s) for s in stops))
        return CycleSource(cyc.name, "blocks", tuple(stops), len(full), dist)
    trace = load_trace(path_or_name, speed_unit=speed_unit)
    events = detect_events(trace, config=trace_config)
    kept = events if max_stops is None else events[:max_stops]
    if len(kept) < len(events):
        dist = distance_until(trace, kept[-1].end_time)
    else:
        dist = trace_distance(trace)
    return CycleSource(name, "trace", tuple(kept), len(events), dist, trace)


def load_cycle_events(
    path_or_name: str | Path,
    config: SimulationConfig,
    trace_config: TraceCycleConfig | None = None,
    *,
    speed_unit: str | None = None,
) -> list[Stop | BrakingEvent]:
    """The stops (block cycle) or braking events (trace) to simulate, cut to max_stops.

    See :func:`load_cycle_source`, which also gives the cycle's distance for mg/km.

    Parameters
    ----------
    path_or_name, config, trace_config, speed_unit
        As :func:`load_cycle_source`.

    Returns
    -------
    list of Stop or BrakingEvent
        The events of :func:`load_cycle_source` (speeds [m/s], decelerations [m/s^2]).

    Raises
    ------
    ConfigError
        As :func:`load_cycle_source`.
    """
    return list(load_cycle_source(path_or_name, config, trace_config, speed_unit=speed_unit).events)


# --- the configured cycle -------------------------------------------------------------------


def _file_digest(path_or_name: str | Path) -> str:
    import hashlib

    text, _, _ = _read_text(path_or_name)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _no_speed_unit(speed_unit: str | None, name: str) -> None:
    """A speed unit given for a block cycle, whose columns state theirs, is refused (it had
    been ignored without a word)."""
    if speed_unit is not None:
        raise ConfigError(
            f"{name} is a block cycle, whose speeds are in km/h by its columns "
            "(initial_speed_kmh, final_speed_kmh): a speed unit (speed_unit, --speed-unit) "
            "is for a speed trace; remove it"
        )


def with_cycle(
    config: SimulationConfig, path_or_name: str | Path, *, speed_unit: str | None = None
) -> SimulationConfig:
    """``config`` with its drive cycle taken from a file or a shipped cycle name.

    A block cycle is copied into the configuration (``cycle.blocks``); a speed trace is
    referenced (``cycle.trace_file``, absolute path unless shipped) with the SHA-256 of its
    content, so a run file records exactly which trace it came from and a changed file is
    refused. The trace is loaded once here, so a bad trace fails before any work.

    Parameters
    ----------
    config
        The configuration; its ``cycle.max_stops`` and ``cycle.trace`` are kept.
    path_or_name
        A CSV file or a shipped cycle (:func:`available_cycles`).
    speed_unit
        Speed unit of a trace without one in its header (:func:`load_trace`); recorded as
        ``cycle.trace_speed_unit``.

    Returns
    -------
    SimulationConfig
        A new configuration with the cycle replaced.

    Raises
    ------
    ConfigError
        A path that is neither a file nor a shipped cycle's name, a file that cannot be
        read, a bad block cycle, or a bad trace (a :class:`TraceError`, as
        :func:`load_trace`).
    """
    text, _, name = _read_text(path_or_name)
    keep = {"max_stops": config.cycle.max_stops, "trace": config.cycle.trace.model_dump()}
    if cycle_file_kind(text) == "blocks":
        from brakeca.presets import load_cycle

        _no_speed_unit(speed_unit, str(path_or_name))
        cycle = {**load_cycle(path_or_name).model_dump(), **keep}
    else:
        load_trace(path_or_name, speed_unit=speed_unit)  # validate now
        p = Path(path_or_name)
        ref = str(p.resolve()) if p.exists() else str(path_or_name)
        cycle = {
            "name": name,
            "trace_file": ref,
            "trace_sha256": _file_digest(path_or_name),
            "trace_speed_unit": speed_unit,
            **keep,
        }
    return config.with_updates({"cycle": cycle})


def check_trace_unchanged(config: SimulationConfig) -> None:
    """Raise ConfigError if ``config``'s speed trace (``cycle.trace_file``) is missing or its
    content changed since the configuration was made (its ``cycle.trace_sha256``); nothing
    for a block cycle. Only the file's digest is computed, no event detected.

    Parameters
    ----------
    config
        The configuration.

    Raises
    ------
    ConfigError
        The trace file is missing or cannot be read (a :class:`TraceError`), or its
        content's SHA-256 differs from ``cycle.trace_sha256``.
    """
    cyc = config.cycle
    if not cyc.trace_file or cyc.trace_sha256 is None:
        return
    digest = _file_digest(cyc.trace_file)
    if digest != cyc.trace_sha256:
        raise ConfigError(
            f"cycle.trace_file {cyc.trace_file}: its content changed since the "
            f"configuration was made (sha256 {digest[:12]} != {cyc.trace_sha256[:12]})"
        )


def configured_cycle(config: SimulationConfig) -> CycleSource:
    """The events to simulate for ``config`` and the distance they belong to.

    Parameters
    ----------
    config
        The configuration: a block cycle (``cycle.blocks``) or a speed trace
        (``cycle.trace_file``), cut to ``cycle.max_stops``.

    Returns
    -------
    CycleSource
        The events, the count in the whole cycle and the distance they belong to [m]. A
        trace's events are detected once for the same configuration and file content.

    Raises
    ------
    ConfigError
        The trace file is missing, its content changed since the configuration was made, or
        it holds no braking event to simulate.
    """
    cyc = config.cycle
    if not cyc.trace_file:
        stops = expand_stops(config)
        full = sum(b.stops for b in cyc.blocks)
        return CycleSource(
            cyc.name, "blocks", tuple(stops), full, float(sum(event_distance(s) for s in stops))
        )
    check_trace_unchanged(config)
    source = _trace_source(config, _file_digest(cyc.trace_file))
    if not source.events:
        tc = cyc.trace
        raise ConfigError(
            f"cycle.trace_file {cyc.trace_file}: no braking event to simulate (none decelerates "
            f"above cycle.trace.threshold = {tc.threshold:g} m/s² for cycle.trace.min_duration "
            f"= {tc.min_duration:g} s or longer); see brakeca cycle inspect"
        )
    return source


@functools.lru_cache(maxsize=4)
def _trace_source(config: SimulationConfig, digest: str) -> CycleSource:
    """:func:`load_cycle_source` for a trace cycle, kept for the same configuration and file
    content (``digest``: its SHA-256), so that the command line's summary and the
    simulation do not each detect the events of a long trace."""
    cyc = config.cycle
    assert cyc.trace_file is not None
    return load_cycle_source(cyc.trace_file, config, cyc.trace, speed_unit=cyc.trace_speed_unit)
