"""Factorial designs: factors, levels, run points, seeds and stable run identifiers.

A design file (TOML, see ``presets/designs/paper.toml``) names a base parameter set and a list
of factors, each a configuration field with its levels. :meth:`Design.points` expands the full
factorial in the paper's test order (the first factor varies fastest: for the paper S, then WP,
WR and A, test 1 all minus, test 24 all plus; Table 2 of Wahlström 2016) and resolves one
validated :class:`~brakeca.config.SimulationConfig` and one seed per run.

Seeds
-----
The seed of test ``t`` (1-based) and replicate ``r`` (0-based) is::

    numpy.random.SeedSequence([root_seed, t, r]).generate_state(1, dtype=numpy.uint32)[0]

It depends on nothing else: not on the number of replicates, the number of factors or the
execution order, so adding replicates or randomising the order never changes an existing run.

Nothing here writes files; the only I/O is reading a design file and its base configuration.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import hashlib
import itertools
import math
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from brakeca.config import (
    FACTOR_ALIASES,
    ConfigError,
    SimulationConfig,
    format_validation_error,
    load_config,
)

__all__ = [
    "RESERVED_NAMES",
    "Design",
    "Factor",
    "RunPoint",
    "design_from_dict",
    "execution_order",
    "load_design",
    "point_seed",
    "quick_config",
    "run_id",
    "run_id_for",
]

#: Radial rows kept by :func:`quick_config` [-] (2 mm at the paper's 0.1 mm radial step).
QUICK_N_RADIAL = 21

#: Names a factor may not take: they are columns of the campaign summary or coordinates of the
#: consolidated campaign dataset.
RESERVED_NAMES: frozenset[str] = frozenset(
    {
        "run",
        "stop",
        "step",
        "test",
        "replicate",
        "order",
        "run_id",
        "seed",
        "status",
        "error",
        "block",
        "radius",
        "angle",
    }
)

_ORDER_TAG = 0x6F72646572  # "order": keeps the order permutation's stream apart from run seeds


class _Frozen(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid", validate_default=True)


def _target(field: str) -> str:
    """The configuration field a factor field or override key sets (an alias resolved)."""
    return FACTOR_ALIASES[field][0] if field in FACTOR_ALIASES else field


def _leaf_field(field: str) -> tuple[Any, str | None]:
    """The :class:`SimulationConfig` field info of the dotted ``field``, and why it is not a
    settable leaf (None when it is; the info is None then only for an alias)."""
    if field in FACTOR_ALIASES:
        return None, None
    parts = field.split(".")
    known: Mapping[str, Any] | None = SimulationConfig.model_fields
    info = None
    for depth, part in enumerate(parts):
        here = ".".join(parts[: depth + 1])
        if known is None:
            return None, f"{here!r} is below a value, not a section"
        if part not in known:
            allowed = ", ".join(sorted(known))
            aliases = ", ".join(FACTOR_ALIASES)
            return None, (
                f"unknown configuration field {here!r}; allowed here: {allowed} "
                f"(or a factor alias: {aliases})"
            )
        info = known[part]
        known = getattr(info.annotation, "model_fields", None)
    if known is not None:
        return None, f"{field!r} is a section, not a value; name one of its fields"
    return info, None


def _leaf_field_problem(field: str) -> str | None:
    """Why ``field`` is not a settable leaf of :class:`SimulationConfig` (None when it is)."""
    return _leaf_field(field)[1]


def _field_unit(field: str) -> str | None:
    """The SI unit a configuration field's description states (``[Pa] ...``), or None."""
    info = _leaf_field(field)[0]
    match = re.match(r"\s*\[([^\]]+)\]", (info.description or "") if info else "")
    return match.group(1) if match else None


class Factor(_Frozen):
    """One factor of a factorial design.

    Parameters
    ----------
    name
        Identifier, unique in the design; the factor's column in the campaign summary.
    field
        Dotted configuration key (``"wear.specific_wear_rate"``) or a factor alias of
        :data:`brakeca.config.FACTOR_ALIASES` (``S``, ``WP``, ``WR``, ``A``; an alias takes the
        alias's unit, e.g. A in percent). By default the factor's name, when that is an alias.
    levels
        Level values in the design's unit [unit], at least two, all different; their order
        is the design order (low first).
    scale
        Multiplier from the design's unit to the field's unit [field unit / unit], e.g. 0.01
        for A given in percent and set on ``pad.fibre_area_fraction``.
    labels
        Optional level labels (``"-"``, ``"0"``, ``"+"``), one per level; by default a
        categorical factor's ``choices`` (except a cycle factor's).
    choices
        A categorical factor: the value each level sets, one per level, for a field that
        takes text (``pad.fibre_model``: ``["columns", "field"]``) or for ``cycle`` (a cycle
        file, relative to the design file, or a shipped name; required there). The levels
        then only number the choices.
    unit
        Unit of the levels as the design gives them; by default an alias's unit (``%`` for
        ``A``), else, when ``scale`` is 1, the field's own unit (``Pa`` for
        ``contact.elastic_modulus``), else ``-``; none for a categorical factor, whose plots
        then label its axis by its name alone.
    label
        Human-readable description.
    """

    name: str = Field(min_length=1, max_length=64)
    field: str = Field(min_length=1)
    levels: tuple[int | float, ...] = Field(min_length=2)
    scale: float = Field(1.0, gt=0, allow_inf_nan=False)
    labels: tuple[str, ...] | None = None
    choices: tuple[str, ...] | None = Field(
        None,
        description=(
            "the value each level sets, for a field that takes text, or for field 'cycle' the "
            "drive cycle of each level (a cycle file relative to the design file, or a "
            "shipped name)"
        ),
    )
    unit: str = "-"
    label: str = ""

    @model_validator(mode="before")
    @classmethod
    def _alias_defaults(cls, data: Any) -> Any:
        """A factor named after an alias and given no field sets that alias; a factor given
        no unit takes its alias's unit, or, unscaled, its field's unit; a categorical one
        (``choices``) has none."""
        if not isinstance(data, Mapping):
            return data
        if "field" not in data and str(data.get("name")) in FACTOR_ALIASES:
            data = {**data, "field": data["name"]}
        choices = data.get("choices")
        if "labels" not in data and data.get("field") != "cycle" and isinstance(choices, list):
            data = {**data, "labels": choices}  # a categorical factor's levels are its choices
        if "unit" not in data:
            field = str(data.get("field"))
            alias = FACTOR_ALIASES.get(field)
            if isinstance(choices, list) or field == "cycle":
                data = {**data, "unit": ""}  # levels only number the choices
            elif alias is not None:
                data = {**data, "unit": alias[2]}
            elif data.get("scale", 1.0) == 1.0 and (unit := _field_unit(field)) is not None:
                data = {**data, "unit": unit}  # levels in the field's own unit
        return data

    @field_validator("name")
    @classmethod
    def _identifier(cls, value: str) -> str:
        if not value.isidentifier():
            raise ValueError(
                f"factor name must be an identifier (letters, digits, _), got {value!r}"
            )
        if value in RESERVED_NAMES:
            raise ValueError(
                f"factor name {value!r} is reserved (campaign columns: "
                f"{', '.join(sorted(RESERVED_NAMES))})"
            )
        return value

    @field_validator("field")
    @classmethod
    def _known_field(cls, value: str) -> str:
        if value == "cycle":  # a categorical factor: its levels pick one of `choices`
            return value
        problem = _leaf_field_problem(value)
        if problem is not None:
            raise ValueError(problem)
        return value

    @field_validator("levels", mode="before")
    @classmethod
    def _numbers(cls, value: Any) -> Any:
        if isinstance(value, str | bytes) or not isinstance(value, Sequence):
            raise ValueError(f"levels must be a list of numbers, got {value!r}")
        for item in value:
            if isinstance(item, bool) or not isinstance(item, int | float):
                raise ValueError(f"levels must be numbers, got {item!r}")
            try:
                finite = math.isfinite(item)
            except OverflowError:
                finite = False
            if not finite:
                raise ValueError(f"levels must be finite numbers, got {item!r}")
        return tuple(value)

    @field_validator("levels")
    @classmethod
    def _unique(cls, value: tuple[int | float, ...]) -> tuple[int | float, ...]:
        if len(set(value)) != len(value):
            raise ValueError(f"levels must all differ, got {list(value)}")
        return value

    @model_validator(mode="after")
    def _labels_match(self) -> Factor:
        if self.labels is not None and len(self.labels) != len(self.levels):
            raise ValueError(
                f"labels: factor {self.name!r} has {len(self.levels)} levels but "
                f"{len(self.labels)} labels"
            )
        if self.field == "cycle" and self.choices is None:
            raise ValueError(
                f"choices: factor {self.name!r}: a factor on field 'cycle' needs choices (one "
                "cycle file or shipped name per level)"
            )
        if self.choices is not None and self.scale != 1.0:
            raise ValueError(
                f"scale: factor {self.name!r} has choices: its levels only number them, so a "
                "scale does not apply"
            )
        if self.choices is not None and len(self.choices) != len(self.levels):
            raise ValueError(
                f"choices: factor {self.name!r} has {len(self.levels)} levels but "
                f"{len(self.choices)} choices"
            )
        return self

    def apply(self, config: SimulationConfig, value: int | float) -> SimulationConfig:
        """``config`` with this factor set to level ``value`` [unit]."""
        if self.field == "cycle":
            from brakeca.traces import with_cycle

            return with_cycle(config, self.override(value)[1])
        return config.with_updates(dict([self.override(value)]))

    def override(self, value: int | float) -> tuple[str, Any]:
        """The ``(key, value)`` update that sets this factor to ``value`` [unit].

        The key is :attr:`field`; the value is the level's choice for a categorical factor,
        else ``value * scale`` (``value`` itself when the scale is 1, so integer fields stay
        integers).
        """
        if self.choices is not None:
            if value not in self.levels:
                raise ConfigError(f"level {value!r} is not one of {list(self.levels)}")
            return self.field, self.choices[self.levels.index(value)]
        return self.field, value if self.scale == 1.0 else value * self.scale

    def label_of(self, value: int | float) -> str:
        """The label of level ``value`` (its ``%g`` text when the factor has no labels)."""
        if self.labels is not None and value in self.levels:
            return self.labels[self.levels.index(value)]
        return f"{value:g}"


@dataclass(frozen=True)
class RunPoint:
    """One run of a design: a test (a factor-level combination) and a replicate.

    Attributes
    ----------
    test : int
        Test number in the paper's order, 1-based [-].
    replicate : int
        Replicate index, 0-based [-].
    order : int
        Position in the execution order, 1-based [-] (the test order unless the design
        randomises it).
    levels : dict of str to float
        Factor name to level value in the design's unit.
    seed : int
        Seed of the run, see :func:`point_seed` [-].
    config : SimulationConfig
        The resolved, validated configuration of the run.
    """

    test: int
    replicate: int
    order: int
    levels: dict[str, int | float]
    seed: int
    config: SimulationConfig

    @property
    def run_id(self) -> str:
        """The run's stable identifier, see :func:`run_id`."""
        return run_id(self)


def point_seed(root_seed: int, test: int, replicate: int) -> int:
    """The seed of test ``test`` (1-based), replicate ``replicate`` (0-based).

    ``SeedSequence([root_seed, test, replicate]).generate_state(1, dtype=uint32)[0]``: a
    32-bit integer that depends only on these three numbers.
    """
    state = np.random.SeedSequence([root_seed, test, replicate]).generate_state(1, dtype=np.uint32)
    return int(state[0])


def run_id_for(config: SimulationConfig, seed: int) -> str:
    """Stable 16-hex-digit identifier of (config, seed): sha256 of the config TOML and seed."""
    text = config.to_toml() + f"\n# seed\n{int(seed)}\n"
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def run_id(point: RunPoint) -> str:
    """Stable identifier of a run point, used as its file name (``runs/<run_id>.nc``).

    The first 16 hex digits of the sha256 of the resolved configuration's TOML followed by the
    seed; it does not depend on the test number, the design or the package version.
    """
    return run_id_for(point.config, point.seed)


def execution_order(points: Sequence[RunPoint]) -> list[RunPoint]:
    """``points`` sorted into execution order (by :attr:`RunPoint.order`)."""
    return sorted(points, key=lambda p: p.order)


def quick_config(config: SimulationConfig) -> SimulationConfig:
    """Narrow the band to 21 radial rows centred on the effective radius (``--quick``).

    Keeps the cell size, the angular extent and the drive cycle; sets ``mesh.n_radial = 21``
    (2 mm at the paper's 0.1 mm radial step), unsets ``mesh.inner_radius`` and sets
    ``quick = True``.

    Raises
    ------
    ConfigError
        The narrowed band does not fit the disc (only with an unusual radial step).
    """
    return config.with_updates(
        {"mesh.n_radial": QUICK_N_RADIAL, "mesh.inner_radius": None, "quick": True}
    )


class Design(_Frozen):
    """A full factorial design over one base configuration.

    Parameters
    ----------
    name
        Design name.
    description
        Free text.
    base
        Name of a shipped parameter preset (``"paper"``); exactly one of ``base`` and
        ``base_config`` is given.
    base_config
        Path of a configuration TOML; a relative path is read relative to the design file.
    factors
        The factors; the first varies fastest in the test order.
    root_seed
        Root of every run's seed [-], see :func:`point_seed`.
    replicates
        Runs per test [-], each with its own seed.
    randomize_order
        Execute the runs in a permutation seeded by ``root_seed`` (test numbers unchanged).
    """

    name: str = Field(min_length=1)
    description: str = ""
    base: str | None = None
    base_config: Path | None = None
    factors: tuple[Factor, ...] = Field(min_length=1)
    root_seed: int = Field(ge=0, lt=2**128)
    replicates: int = Field(1, ge=1, le=10_000)
    randomize_order: bool = False

    @model_validator(mode="after")
    def _consistent(self) -> Design:
        if (self.base is None) == (self.base_config is None):
            raise ValueError(
                "base: give exactly one of 'base' (a preset) and 'base_config' (a file)"
            )
        seen: dict[str, int] = {}
        fields: dict[str, str] = {}
        for i, factor in enumerate(self.factors):
            if factor.name in seen:
                raise ValueError(
                    f"factors.{i}.name: duplicate factor name {factor.name!r} "
                    f"(also factors.{seen[factor.name]})"
                )
            seen[factor.name] = i
            target = _target(factor.field)
            if target in fields:
                raise ValueError(
                    f"factors.{i}.field: factors {fields[target]!r} and {factor.name!r} both set "
                    f"{target!r}"
                )
            fields[target] = factor.name
        n_runs = math.prod(len(f.levels) for f in self.factors) * self.replicates
        if n_runs > 1_000_000:
            raise ValueError(f"factors: the design has {n_runs} runs, more than 1,000,000")
        return self

    # --- derived ---------------------------------------------------------------------------
    @property
    def factor_names(self) -> tuple[str, ...]:
        """Factor names in design order."""
        return tuple(f.name for f in self.factors)

    @property
    def n_tests(self) -> int:
        """Number of factor-level combinations [-]."""
        return math.prod(len(f.levels) for f in self.factors)

    def factor(self, name: str) -> Factor:
        """The factor called ``name``."""
        for f in self.factors:
            if f.name == name:
                return f
        raise KeyError(name)

    def combinations(self) -> list[dict[str, int | float]]:
        """Level combinations in test order: the first factor varies fastest."""
        reversed_levels = [f.levels for f in reversed(self.factors)]
        names = self.factor_names
        return [
            dict(zip(names, reversed(combo), strict=True))
            for combo in itertools.product(*reversed_levels)
        ]

    def load_base(self) -> SimulationConfig:
        """The base configuration (the preset ``base`` or the file ``base_config``).

        Raises
        ------
        ConfigError
            Unknown preset, unreadable or invalid configuration file.
        """
        if self.base is not None:
            from brakeca.presets import load_preset

            return load_preset(self.base)
        assert self.base_config is not None
        return load_config(self.base_config)

    def resolved_base(
        self,
        *,
        overrides: Mapping[str, Any] | None = None,
        quick: bool = False,
        max_stops: int | None = None,
    ) -> SimulationConfig:
        """The base configuration with the campaign-wide settings applied.

        Parameters
        ----------
        overrides
            Dotted-key (or factor-alias) updates applied to the base.
        quick
            Apply :func:`quick_config` after the overrides.
        max_stops
            Run only the first ``max_stops`` stops of the cycle [-].

        Raises
        ------
        ConfigError
            An override is unknown or out of range; the message names the field.
        """
        config = self.load_base()
        updates = dict(overrides or {})
        varied = {_target(f.field): f.name for f in self.factors}
        for key in updates:
            target = _target(key)
            if target in varied:
                shown = key if key == target else f"{key} ({target})"
                raise ConfigError(
                    f"override {shown}: the design's factor {varied[target]!r} sets this "
                    "field in every run, so the override would be ignored; remove one of them"
                )
        if max_stops is not None:
            updates["cycle.max_stops"] = max_stops
        if updates:
            config = config.with_updates(updates)
        if quick:
            config = quick_config(config)
        return config

    def _level_error(
        self, factor: Factor, value: int | float, exc: ConfigError, source: str | None
    ) -> ConfigError:
        where = source or f"design {self.name}"
        index = self.factor_names.index(factor.name)
        detail = str(exc).replace("\n", "; ")
        return ConfigError(
            f"{where}: factors.{index}.levels: factor {factor.name!r} (field {factor.field}): "
            f"level {value!r} [{factor.unit}] is not valid: {detail}"
        )

    def apply_levels(
        self,
        base: SimulationConfig,
        levels: Mapping[str, int | float],
        *,
        source: str | None = None,
    ) -> SimulationConfig:
        """``base`` with each factor set to its level in ``levels`` [design unit].

        Raises
        ------
        ConfigError
            A level is out of range for its field; the message names the design, the factor,
            the field and the level.
        """
        config = base
        for factor in self.factors:
            value = levels[factor.name]
            try:
                config = factor.apply(config, value)
            except ConfigError as exc:
                raise self._level_error(factor, value, exc, source) from None
        return config

    def check_levels(
        self, base: SimulationConfig | None = None, *, source: str | None = None
    ) -> None:
        """Apply every level of every factor, one at a time, to ``base``.

        Raises
        ------
        ConfigError
            For the first level that does not validate; the message names ``source`` (the
            design file), the factor, its field and the level.
        """
        base = self.load_base() if base is None else base
        for factor in self.factors:
            for value in factor.levels:
                try:
                    factor.apply(base, value)
                except ConfigError as exc:
                    raise self._level_error(factor, value, exc, source) from None

    def points(
        self,
        *,
        overrides: Mapping[str, Any] | None = None,
        quick: bool = False,
        max_stops: int | None = None,
    ) -> list[RunPoint]:
        """Every run of the design, in test order (test, then replicate).

        The configuration of a run is the base configuration, then the campaign-wide
        ``overrides`` and ``max_stops``, then :func:`quick_config` when ``quick``, then each
        factor's field set to ``level * scale``. An override of a field a factor sets is
        refused (the factor would overwrite it in every run).

        Parameters
        ----------
        overrides
            Dotted-key (or factor-alias) updates applied to every run.
        quick
            Narrow every run's band with :func:`quick_config`.
        max_stops
            Run only the first ``max_stops`` stops of the cycle [-].

        Returns
        -------
        list of RunPoint
            ``n_tests * replicates`` points; test ``t`` holds the ``t``-th combination of
            :meth:`combinations`. With :attr:`randomize_order` their :attr:`RunPoint.order`
            is a permutation seeded by :attr:`root_seed`; see :func:`execution_order`.

        Raises
        ------
        ConfigError
            A campaign-wide setting or a factor level does not validate.
        """
        base = self.resolved_base(overrides=overrides, quick=quick, max_stops=max_stops)
        combos = self.combinations()
        n = len(combos) * self.replicates
        if self.randomize_order:
            rng = np.random.default_rng(np.random.SeedSequence([self.root_seed, _ORDER_TAG]))
            order = [int(k) + 1 for k in rng.permutation(n)]
        else:
            order = list(range(1, n + 1))
        points: list[RunPoint] = []
        configs: dict[int, SimulationConfig] = {}
        for test, levels in enumerate(combos, start=1):
            for replicate in range(self.replicates):
                if test not in configs:
                    configs[test] = self.apply_levels(base, levels)
                points.append(
                    RunPoint(
                        test=test,
                        replicate=replicate,
                        order=order[len(points)],
                        levels=dict(levels),
                        seed=point_seed(self.root_seed, test, replicate),
                        config=configs[test],
                    )
                )
        return points

    # --- serialisation -----------------------------------------------------------------------
    def to_dict(self, *, base_config: str | Path | None = None) -> dict[str, Any]:
        """Plain dict in the design-file layout (None fields dropped).

        Parameters
        ----------
        base_config
            Replace the base by this configuration file (``base`` is then dropped).
        """
        data = self.model_dump(mode="python")
        if base_config is not None:
            data["base"] = None
            data["base_config"] = base_config
        if data.get("base_config") is not None:
            data["base_config"] = str(data["base_config"])
        data["factors"] = [
            {k: (list(v) if isinstance(v, tuple) else v) for k, v in f.items() if v is not None}
            for f in data["factors"]
        ]
        return {k: v for k, v in data.items() if v is not None}

    def to_toml(self, *, base_config: str | Path | None = None) -> str:
        """The design as design-file TOML text (see :meth:`to_dict`)."""
        return tomli_w.dumps(self.to_dict(base_config=base_config))


def design_from_dict(
    data: Mapping[str, Any], *, source: str = "design", root: str | Path | None = None
) -> Design:
    """Validate a design given as a mapping (the parsed design file).

    Parameters
    ----------
    data
        The design-file contents.
    source
        Name used in error messages (the file path).
    root
        Directory a relative ``base_config`` is read from (the design file's directory).

    Returns
    -------
    Design
        With ``base_config`` made absolute, and every level checked against the base.

    Raises
    ------
    ConfigError
        Anything wrong; each message names ``source`` and the field.
    """
    if not isinstance(data, Mapping):
        raise ConfigError(f"{source}: a design must be a table of keys, got {type(data).__name__}")
    data = dict(data)
    try:
        design = Design.model_validate(data)
    except ValidationError as exc:
        raise ConfigError(format_validation_error(exc, source)) from None
    base_dir = Path(root) if root is not None else Path.cwd()
    factors = []
    for f in design.factors:  # cycle files relative to the design file
        if f.field == "cycle" and f.choices is not None:
            f = f.model_copy(
                update={
                    "choices": tuple(
                        str((base_dir / c).resolve()) if (base_dir / c).is_file() else c
                        for c in f.choices
                    )
                }
            )
        factors.append(f)
    design = design.model_copy(update={"factors": tuple(factors)})
    try:
        if design.base_config is not None and not design.base_config.is_absolute():
            base_dir = Path(root) if root is not None else Path.cwd()
            absolute = (base_dir / design.base_config).resolve()
            design = design.model_copy(update={"base_config": absolute})
        base = design.load_base()
    except (ValueError, OSError) as exc:  # ConfigError is a ValueError
        field = "base" if design.base is not None else "base_config"
        detail = str(exc).replace("\n", "; ")
        raise ConfigError(
            f"{source}: {field}: cannot load the base configuration: {detail}"
        ) from None
    design.check_levels(base, source=source)
    return design


def load_design(path_or_name: str | Path) -> Design:
    """Load and validate a design: a shipped name (``"paper"``) or a TOML file.

    Raises
    ------
    ConfigError
        Unknown name, unreadable or invalid file; the message names the file and the field.
    """
    from brakeca.presets import available_designs, design_path

    path = Path(path_or_name)
    if isinstance(path_or_name, str) and path_or_name in available_designs() and not path.exists():
        path = design_path(path_or_name)
    elif not path.is_file():
        raise ConfigError(
            f"design {str(path_or_name)!r}: no such file nor a shipped design "
            f"({', '.join(available_designs())})"
        )
    source = str(path)
    try:
        text = path.read_text(encoding="utf-8-sig")  # a BOM (Windows editors) is not TOML
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{source}: cannot read: {exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{source}: not valid TOML: {exc}") from None
    return design_from_dict(data, source=source, root=path.parent)
