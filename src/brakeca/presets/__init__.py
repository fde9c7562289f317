"""Shipped data: the paper's parameter set, its drive cycle and its factorial design.

Nothing here is a constant buried in code: every number lives in a TOML or CSV file beside this
module, read by the functions below.
"""

from __future__ import annotations

import csv
import io
import tomllib
from importlib import resources
from pathlib import Path

from brakeca.config import (
    BrakeBlock,
    ConfigError,
    CycleConfig,
    SimulationConfig,
    csv_delimiter,
    decimal_point,
    excel_separator,
    read_csv_text,
)

__all__ = ["available_designs", "available_presets", "load_cycle", "load_preset", "preset_text"]

_ROOT = resources.files(__name__)


def available_presets() -> list[str]:
    """Names of the shipped parameter presets."""
    return sorted(p.name[:-5] for p in _ROOT.iterdir() if p.name.endswith(".toml"))


def available_designs() -> list[str]:
    """Names of the shipped designs."""
    return sorted(
        p.name[:-5] for p in _ROOT.joinpath("designs").iterdir() if p.name.endswith(".toml")
    )


def preset_text(name: str) -> str:
    """The TOML text of a shipped parameter preset."""
    if name not in available_presets():
        raise ConfigError(f"unknown preset {name!r}; available: {', '.join(available_presets())}")
    return _ROOT.joinpath(f"{name}.toml").read_text(encoding="utf-8")


def design_path(name: str) -> Path:
    """Path of a shipped design file."""
    if name not in available_designs():
        raise ConfigError(f"unknown design {name!r}; available: {', '.join(available_designs())}")
    return Path(str(_ROOT.joinpath("designs", f"{name}.toml")))


def _read_cycle_csv(text: str, source: str) -> tuple[BrakeBlock, ...]:
    """The blocks of a block-cycle CSV: comma, semicolon or tab separated; a semicolon or
    tab separated file may write decimal commas (``0,25``)."""
    kept = [
        (lineno, ln)
        for lineno, ln in enumerate(text.splitlines(), start=1)
        if ln.strip() and not ln.lstrip().startswith("#")
    ]
    named = excel_separator(kept[0][1]) if kept else None  # an Excel "sep=;" line's
    if named is not None:
        kept.pop(0)
    if not kept:
        raise ConfigError(f"{source}: empty cycle file")
    lines = [ln for _, ln in kept]
    delimiter = named or csv_delimiter(lines[0])
    reader = csv.DictReader(io.StringIO("\n".join(lines)), delimiter=delimiter)
    reader.fieldnames = [name.strip() for name in reader.fieldnames or ()]
    twice = sorted({n for n in reader.fieldnames if n and reader.fieldnames.count(n) > 1})
    if twice:  # the last one had won without a word (a fuzz review); a trace refuses them too
        raise ConfigError(f"{source}: the header names {', '.join(twice)} twice: each column once")
    expected = {"name", "initial_speed_kmh", "final_speed_kmh", "deceleration_g", "stops"}
    missing = expected - set(reader.fieldnames)
    if missing:
        other = [
            f
            for f in reader.fieldnames
            if f.lower().startswith(("initial_speed", "final_speed")) and f not in expected
        ]
        hint = (
            f"; a block cycle gives its speeds in km/h (it has {', '.join(other)})"
            if other and any("speed_kmh" in m for m in missing)
            else ""
        )
        raise ConfigError(f"{source}: missing column(s) {', '.join(sorted(missing))}{hint}")
    blocks = []
    for row in reader:
        lineno = kept[reader.line_num - 1][0]  # the file's line, comments and blanks counted
        extra = [v for v in row.get(None) or () if v.strip()]
        if extra:
            raise ConfigError(
                f"{source}, line {lineno}: expected {len(reader.fieldnames)} values, found "
                f"more ({', '.join(map(repr, extra))} past the header's): a decimal comma in "
                "a file separated by commas? write decimal points there, or separate the "
                "values with ';'"
            )
        values = {k: (row[k] or "").strip() for k in expected}
        if delimiter != ",":
            values = {k: v if k == "name" else decimal_point(v) for k, v in values.items()}
        empty = [k for k in reader.fieldnames if k in expected and not values[k]]
        if empty:  # a review: a missing stops read "must be a whole number (got '')"
            raise ConfigError(
                f"{source}, line {lineno}: {', '.join(empty)}: missing (the row leaves "
                f"{'it' if len(empty) == 1 else 'them'} empty)"
            )
        grouped = [k for k in sorted(expected - {"name"}) if "_" in values[k]]
        if grouped:  # float() and pydantic read "5_0" as 50; no spreadsheet writes it
            k = grouped[0]
            raise ConfigError(f"{source}, line {lineno}: {k}: {values[k]!r} is not a number")
        try:
            blocks.append(BrakeBlock.model_validate(values))
        except Exception as exc:  # pydantic ValidationError
            from pydantic import ValidationError

            from brakeca.config import format_validation_error

            if isinstance(exc, ValidationError):
                raise ConfigError(
                    format_validation_error(exc, f"{source}, line {lineno}", BrakeBlock)
                ) from None
            raise
    if not blocks:
        raise ConfigError(f"{source}: no block after the header (an empty cycle)")
    return tuple(blocks)


def load_cycle(name_or_path: str | Path) -> CycleConfig:
    """Load a block cycle: a shipped name (``"paper"``) or a CSV file.

    The CSV has columns ``name, initial_speed_kmh, final_speed_kmh, deceleration_g, stops``;
    lines starting with ``#`` are comments. Comma, semicolon or tab separated; a semicolon or
    tab separated file may write decimal commas.

    Parameters
    ----------
    name_or_path
        A shipped block cycle's name (``"paper"``, Table 3 of the paper) or a CSV file.

    Returns
    -------
    CycleConfig
        The cycle's blocks, validated: speeds [km/h], deceleration [g] and stops [-] of each.

    Raises
    ------
    ConfigError
        No such file nor shipped cycle, a folder, or a line that is not a valid block; the
        message names the file and the line.

    Examples
    --------
    >>> from brakeca.presets import load_cycle
    >>> cycle = load_cycle("paper")
    >>> [(b.name, b.stops) for b in cycle.blocks][:3]
    [('Burnish', 50), ('Town #1', 20), ('Highway #1', 10)]
    >>> sum(b.stops for b in cycle.blocks)
    170
    """
    text: str
    p = Path(name_or_path)
    shipped = _ROOT.joinpath("cycles", f"{name_or_path}.csv")
    if p.is_file() and not (p.suffix == "" and shipped.is_file()):  # a file, whatever its suffix
        text, name, source = read_csv_text(p), p.stem, str(p)
    elif shipped.is_file():
        text, name, source = (
            shipped.read_text(encoding="utf-8"),
            str(name_or_path),
            f"cycle {name_or_path}",
        )
    elif p.is_dir():
        raise ConfigError(f"cycle {str(name_or_path)!r}: a folder, not a cycle's CSV file")
    else:
        raise ConfigError(
            f"unknown cycle {str(name_or_path)!r}: no such file nor a shipped block cycle "
            "(paper; a speed trace is read by brakeca.traces.load_trace)"
        )
    return CycleConfig(name=name, blocks=_read_cycle_csv(text, source))


def load_preset(name: str = "paper") -> SimulationConfig:
    """The shipped parameter preset ``name`` with its drive cycle, validated.

    Parameters
    ----------
    name
        The preset's name (:func:`available_presets`); ``"paper"``, Wahlström (2016)'s
        parameters (Tables 1, 3, 4 and 5) with this project's decisions where the paper is
        silent (docs/model.md).

    Returns
    -------
    SimulationConfig
        The configuration, SI units inside.

    Raises
    ------
    ConfigError
        An unknown name.

    Examples
    --------
    >>> from brakeca.presets import load_preset
    >>> paper = load_preset()
    >>> paper.mesh.n_radial, paper.mesh.n_angular, paper.friction.mu_0
    (201, 1000, 0.6)
    """
    data = tomllib.loads(preset_text(name))
    cycle = data.pop("cycle", {"file": name})
    cyc = load_cycle(cycle.get("file", name)) if "blocks" not in cycle else CycleConfig(**cycle)
    data["cycle"] = cyc.model_dump()
    return SimulationConfig.from_dict(data, source=f"preset {name}")
