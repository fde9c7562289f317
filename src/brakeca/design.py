"""Designs: factors, levels, run points, seeds and stable run identifiers.

A design file (TOML, see ``presets/designs/paper.toml``) names a base parameter set and a list
of factors, each a configuration field with its levels. :meth:`Design.combinations` lists the
design's *tests* (one factor-level combination each) and :meth:`Design.points` resolves one
validated :class:`~brakeca.config.SimulationConfig` and one seed per run (test and
replicate). A design is one of six kinds (:attr:`Design.kind`):

Full factorial (the default)
    Every combination of the factors' levels, in the paper's test order: the first factor
    varies fastest (for the paper S, then WP, WR and A, test 1 all minus, test 24 all plus;
    Table 2 of Wahlström 2016).
Regular two-level fractional factorial (key ``generators``)
    Each generator ``"D = A*B*C"`` (optionally ``"D = -A*B*C"``) makes ``D`` a *generated*
    factor whose coded level (``levels[0]`` is -1, ``levels[1]`` is +1) in every test is the
    sign times the product of the *base* factors' coded levels. The tests are the full
    factorial of the factors no generator generates, in design order with the first of them
    varying fastest; the generated levels follow. Every factor in a generator has two levels;
    the others are crossed, whatever their number of levels. The defining relation (the
    generators' words ``I = D*A*B*C`` and all their products) gives the resolution, the
    length of its shortest word; below III (two main effects aliased) the design is refused.
    ``fraction_runs = 16`` instead of ``generators`` takes the standard fraction of that many
    tests (:data:`STANDARD_FRACTIONS`) and writes its generators out.
Run table (key ``runs``, or ``runs_file``: a CSV file)
    Any design made elsewhere (Plackett-Burman, D-optimal, a JMP custom design): one row per
    test, giving each factor one of its levels; the tests are the rows, in order. A CSV file
    is read once, when the design is loaded, and its rows are kept inline, so that
    :meth:`Design.to_toml` is self-contained.
Central composite design (key ``composite``: a table with ``alpha`` and ``center``)
    A response-surface design (Minitab's "Create Response Surface Design") over 2 to 6
    numeric factors of two levels each: the 2^k cube points (the full factorial of the levels,
    coded -1 and +1, the first factor fastest), 2k axial points (each factor in turn at
    -alpha, then +alpha, the others at their centre, 0) and ``center`` centre points, in this
    order. ``alpha`` is ``"face"`` (1: every level within the given two), ``"rotatable"``,
    ``"orthogonal"`` or a number. A factor with ``coding = "log"`` is coded on log10 of its
    level (its centre is the geometric mean). The tests are written out as a run table when
    the design is validated, with each factor's levels, labels and ``coded_range``.
Plackett-Burman design (key ``plackett_burman``: 12, 20, 24, 28, 32, 36, 44 or 48 tests)
    A two-level screening design for up to one factor fewer than its tests, in Minitab's
    standard order: the published generator as the first factor's column, each further
    factor's column it shifted down one test (the 28-run design: three blocks, shifted), and
    a test with every factor at its first level; written out as a run table. Main effects
    are orthogonal, each partly confounded with the other factors' two-factor interactions
    (the 32-run design: a regular fraction, wholly aliased).
Box-Behnken design (key ``box_behnken``: a table with ``center``)
    The other response-surface design: over 3 to 5 such factors, for every pair of factors
    the 2^2 factorial of their levels with the others at their centre, then the centre
    points; three levels per factor and no run with every factor at an extreme.

A fraction or a run table may be folded over (key ``foldover``): its tests are followed by
the same tests with the named two-level factors (or all, ``"all"``) at their other level. The
first half keeps its test numbers, so its seeds and run ids are the unfolded design's.

A design of two-level numeric factors (not a response-surface design, which has its own) may
have centre points (key ``center_points``): as many tests with every factor at the middle of
its two levels, after the others, each with its own seed. They give pure error without
replicating the whole design, and a test of curvature (:func:`brakeca.analysis.anova`).

Seeds
-----
The seed of test ``t`` (1-based) and replicate ``r`` (0-based) is::

    numpy.random.SeedSequence([root_seed, t, r]).generate_state(1, dtype=numpy.uint32)[0]

It depends on nothing else: not on the number of replicates, the number of factors or the
execution order, so adding replicates or randomising the order never changes an existing run.

Nothing here writes files; the only I/O is reading a design file, its run table and its base
configuration.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260

D. C. Montgomery, "Design and Analysis of Experiments", 8th ed., Wiley, 2013, chapter 8
(two-level fractional factorial designs: generators, defining relation, resolution) and
§11.4.2 (central composite designs).
"""

from __future__ import annotations

import csv
import functools
import hashlib
import itertools
import math
import numbers
import re
import tomllib
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Literal, NamedTuple

import numpy as np
import tomli_w
from pydantic import (
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from brakeca.config import (
    FACTOR_ALIASES,
    QUICK_N_RADIAL,
    ConfigError,
    SimulationConfig,
    UnitWarning,
    _Checked,
    csv_delimiter,
    csv_float,
    decimal_point,
    excel_separator,
    format_validation_error,
    item_path,
    load_config,
    plain_number,
    plain_text_problem,
    read_csv_text,
    warn_unit,
)

__all__ = [
    "GOAL_RESPONSES",
    "MAX_GENERATORS",
    "PLACKETT_BURMAN",
    "PLACKETT_BURMAN_28",
    "PLACKETT_BURMAN_GENERATORS",
    "RESERVED_NAMES",
    "STANDARD_FRACTIONS",
    "BoxBehnken",
    "Composite",
    "Design",
    "Factor",
    "GoalSpec",
    "RunPoint",
    "check_quick_overrides",
    "design_from_dict",
    "execution_order",
    "load_design",
    "point_seed",
    "quick_config",
    "run_id",
    "run_id_for",
    "standard_generators",
]


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

#: Two levels of a factor closer than this, relative [-], are one level to the analysis
#: (``brakeca.analysis``, which matches a run's value to a level within it).
LEVEL_RTOL = 1e-6

#: Rows of the analysis's tables that are not factors' terms: the factorial ANOVA's
#: (brakeca.analysis) and the response surface's ANOVA and coefficients (brakeca.rsm).
_ANOVA_TERMS = frozenset(
    {"Residual", "Curvature", "Model", "Linear", "Square", "Error", "Total", "Constant"}
)

_ORDER_TAG = 0x6F72646572  # "order": keeps the order permutation's stream apart from run seeds

#: The most generators a fractional factorial may have [-]: its defining relation has
#: 2^p - 1 words, all of which the resolution check visits.
MAX_GENERATORS = 20

#: At most this many tests x replicates in one design [-].
_MAX_RUNS = 1_000_000

#: Standard generators of two-level fractional factorials, by (two-level factors, runs), with
#: the factors lettered A, B, C, ... in design order (I skipped): the designs of Box, Hunter
#: and Hunter (Statistics for Experimenters, 2nd ed., Table 6.14) and Montgomery (Design and
#: Analysis of Experiments, Table 8.14), minimum aberration up to 8 factors; their resolution
#: is checked by the tests. ``fraction_runs`` picks one of them.
STANDARD_FRACTIONS: dict[tuple[int, int], tuple[str, ...]] = {
    (3, 4): ("C=AB",),
    (4, 8): ("D=ABC",),
    (5, 8): ("D=AB", "E=AC"),
    (5, 16): ("E=ABCD",),
    (6, 8): ("D=AB", "E=AC", "F=BC"),
    (6, 16): ("E=ABC", "F=BCD"),
    (6, 32): ("F=ABCDE",),
    (7, 8): ("D=AB", "E=AC", "F=BC", "G=ABC"),
    (7, 16): ("E=ABC", "F=BCD", "G=ACD"),
    (7, 32): ("F=ABCD", "G=ABDE"),
    (7, 64): ("G=ABCDEF",),
    (8, 16): ("E=BCD", "F=ACD", "G=ABC", "H=ABD"),
    (8, 32): ("F=ABC", "G=ABD", "H=BCDE"),
    (8, 64): ("G=ABCD", "H=ABEF"),
    (9, 16): ("E=ABC", "F=BCD", "G=ACD", "H=ABD", "J=ABCD"),
    (9, 32): ("F=BCDE", "G=ACDE", "H=ABDE", "J=ABCE"),
    (9, 64): ("G=ABCD", "H=ACEF", "J=CDEF"),
    (10, 16): ("E=ABC", "F=BCD", "G=ACD", "H=ABD", "J=ABCD", "K=AB"),
    (10, 32): ("F=ABCD", "G=ABCE", "H=ABDE", "J=ACDE", "K=BCDE"),
}

_LETTERS = "ABCDEFGHJKL"


def standard_generators(names: Sequence[str], runs: int) -> tuple[str, ...]:
    """The generators of the standard fraction of ``runs`` tests over the two-level factors
    ``names`` (in design order: the first are the base factors, the last the generated ones),
    written with the factors' names: ``("E = A*B*C", ...)``; none for the full factorial.

    Parameters
    ----------
    names
        The two-level factors' names, in design order.
    runs
        The fraction's tests [-]: 2**(k - p) for k factors.

    Returns
    -------
    tuple of str
        The generators, one for each generated factor.

    Raises
    ------
    ValueError
        ``runs`` is not a standard fraction of that many factors; the message lists those
        that are.
    """
    k = len(names)
    if runs == 2**k:
        return ()
    if (k, runs) not in STANDARD_FRACTIONS:
        fractions = sorted(n for kk, n in STANDARD_FRACTIONS if kk == k)
        # the full factorial is a choice only within the runs a design may have (20 factors'
        # 1,048,576 were offered: a fuzz review)
        full = 2**k <= _MAX_RUNS
        choices = [*fractions, 2**k] if full else fractions
        head = f"fraction_runs: {runs} is not a standard fraction of {k} two-level factors"
        if not choices:
            raise ValueError(
                f"{head}, none is listed for them, and their full factorial's {2**k:,} runs are "
                f"more than a design may have ({_MAX_RUNS:,}); write the generators"
            )
        if len(choices) == 1:
            listed = f"{choices[0]} (the full factorial)" if full else str(choices[0])
        else:
            listed = "one of " + ", ".join(str(n) for n in choices)
            listed += " (the last: the full factorial)" if full else ""
        raise ValueError(f"{head}; choose {listed}, or write the generators")
    letter = {c: names[i] for i, c in enumerate(_LETTERS[:k])}
    return tuple(
        f"{letter[g[0]]} = {'*'.join(letter[c] for c in g[2:])}"
        for g in STANDARD_FRACTIONS[(k, runs)]
    )


class _Frozen(_Checked):  # a number field refuses true and false
    # protected_namespaces=(): model_order and model_terms are ours (pydantic before 2.10
    # warned of fields named model_*)
    model_config = ConfigDict(
        frozen=True, extra="forbid", validate_default=True, protected_namespaces=()
    )


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


#: SI prefixes a factor's unit label may put before its field's unit.
_SI_PREFIXES = {
    "p": 1e-12,
    "n": 1e-9,
    "µ": 1e-6,
    "u": 1e-6,
    "m": 1e-3,
    "k": 1e3,
    "M": 1e6,
    "G": 1e9,
}


def _short_number(x: float) -> str:
    """``x`` as a short TOML number: ``0.01``, ``1e9``, ``1e-6``."""
    if 1e-3 <= abs(x) < 1e4:
        return f"{x:g}"
    mantissa, exponent = f"{x:e}".split("e")
    return f"{float(mantissa):g}e{int(exponent)}"


def _prefixed_scale(unit: str, own: str) -> float | None:
    """The scale that turns levels in ``unit`` into the field's ``own`` unit, when ``unit``
    is ``own`` with an SI prefix (``GPa`` for ``Pa``: 1e9; ``1/MPa`` for ``1/Pa``: 1e-6) or
    ``%`` for a dimensionless field (0.01); None for any other label."""
    if unit.strip() == "%" and own in ("-", "", "1"):
        return 0.01
    if own == "kg":  # a prefix of its own already
        return None
    for prefix, size in _SI_PREFIXES.items():
        for head, sign in (("", 1), ("1/", -1)):
            if not own.startswith(head) or unit != head + prefix + own[len(head) :]:
                continue
            # the prefix goes with the first symbol's power: mm^2 is 1e-6 m^2
            power = re.match(r"[A-Za-z]+\^(\d+)", own[len(head) :])
            return float(size ** (sign * (int(power.group(1)) if power else 1)))
    return None


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
        Level values in the design's unit [unit], at least two, all different, in the
        design order; give them low first (the analysis takes them in the order given, and
        :meth:`order_note` says so where they are not).
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
    coding
        How a regression model codes the factor (and where a central composite design puts
        its centre and axial points): ``"linear"`` codes the level itself, ``"log"`` its
        decimal logarithm (for a factor spanning decades, such as WP = 1e-15..1e-13
        m^3/(N m): its centre is then the geometric mean). ``"log"`` needs every level and
        both ends of ``coded_range`` above 0 and a numeric (not categorical) factor.
    coded_range
        The two levels [design unit] a regression model codes -1 and +1 (the cube points'
        low and high of a central composite design), low < high; by default (None) the
        lowest and the highest level.
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
    coding: Literal["linear", "log"] = "linear"
    coded_range: tuple[float, float] | None = None

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
        elif "field" not in data and isinstance(data.get("name"), str):
            name = data["name"]
            near = [a for a in FACTOR_ALIASES if a.lower() == name.lower()]
            raise ValueError(
                f"factor {name!r} gives no `field` (the configuration field it sets, e.g. "
                'field = "wear.specific_wear_rate"), and only the paper\'s factors '
                f"{', '.join(FACTOR_ALIASES)} may leave it out"
                + (f" (names are case-sensitive: did you mean {near[0]!r}?)" if near else "")
            )
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
        if value in _ANOVA_TERMS:
            raise ValueError(
                f"factor name {value!r} is a row of the analysis's tables (its terms "
                f"{', '.join(sorted(_ANOVA_TERMS))}), which the factor's row would be "
                "mistaken for; name the factor otherwise"
            )
        from brakeca.results import result_names

        if value in result_names():
            raise ValueError(
                f"factor name {value!r} is the name of a result (a column of the campaign's "
                "summary or a variable of its dataset), which would overwrite the factor's "
                "levels; name the factor otherwise (e.g. after its field: mu0, not MU)"
            )
        return value

    @field_validator("labels", "choices")
    @classmethod
    def _plain_labels(
        cls, value: tuple[str, ...] | None, info: ValidationInfo
    ) -> tuple[str, ...] | None:
        for text in value or ():
            problem = plain_text_problem(text, formula=info.field_name == "labels")
            if problem is not None:
                raise ValueError(problem)
        return value

    @field_validator("unit", "label")
    @classmethod
    def _plain_text(cls, value: str) -> str:
        if (problem := plain_text_problem(value)) is not None:
            raise ValueError(problem)
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
        if isinstance(value, np.ndarray) and value.ndim == 1:
            value = list(value)  # np.logspace(-15, -13, 3)
        if isinstance(value, str | bytes) or not isinstance(value, Sequence):
            raise ValueError(f"levels must be a list of numbers, got {value!r}")
        numbers = []
        for item in value:
            number = plain_number(item)
            if number is None:
                raise ValueError(f"levels must be numbers, got {item!r}")
            try:
                finite = math.isfinite(number)
            except OverflowError:
                finite = False
            if not finite:
                raise ValueError(f"levels must be finite numbers, got {item!r}")
            numbers.append(number)
        return tuple(numbers)

    @field_validator("levels")
    @classmethod
    def _unique(cls, value: tuple[int | float, ...]) -> tuple[int | float, ...]:
        if len(set(value)) != len(value):
            raise ValueError(f"levels must all differ, got {list(value)}")
        for a, b in itertools.combinations(value, 2):
            if math.isclose(a, b, rel_tol=LEVEL_RTOL, abs_tol=0.0):
                raise ValueError(
                    f"levels {a!r} and {b!r} differ by less than {LEVEL_RTOL:g} of their "
                    f"size, which the analysis reads as one level; got {list(value)}"
                )
        return value

    @field_validator("coded_range", mode="before")
    @classmethod
    def _range(cls, value: Any) -> Any:
        if value is None:
            return value
        if isinstance(value, str | bytes) or not isinstance(value, Sequence) or len(value) != 2:
            raise ValueError("expected two levels [low, high], the levels coded -1 and +1")
        for item in value:
            if isinstance(item, bool) or not isinstance(item, int | float):
                raise ValueError(f"expected two numbers [low, high]; {item!r} is not a number")
            if not _finite_number(item):
                raise ValueError(f"expected two finite numbers [low, high]; {item!r} is not")
        low, high = value
        if not low < high:
            raise ValueError("expected [low, high] with low < high (the levels coded -1 and +1)")
        return tuple(value)

    @model_validator(mode="after")
    def _labels_match(self) -> Factor:
        if self.labels is not None and len(self.labels) != len(self.levels):
            raise ValueError(
                f"labels: factor {self.name!r} has {len(self.levels)} levels but "
                f"{len(self.labels)} labels"
            )
        if self.labels is not None and len(set(self.labels)) != len(self.labels):
            twice = next(x for x in self.labels if self.labels.count(x) > 1)
            raise ValueError(
                f"labels: factor {self.name!r} labels two levels {twice!r}; each level needs "
                "its own label, or the tables and plots could not tell them apart"
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
        if self.field in FACTOR_ALIASES and self.scale != 1.0:
            target, _, unit = FACTOR_ALIASES[self.field]
            raise ValueError(
                f"scale: factor {self.name!r} sets the paper factor {self.field}, whose levels "
                f"are in its own unit ({unit}) and converted by it, so a scale would apply "
                f"twice; remove scale, or give field = {target!r} with your scale"
            )
        if self.choices is not None and len(self.choices) != len(self.levels):
            raise ValueError(
                f"choices: factor {self.name!r} has {len(self.levels)} levels but "
                f"{len(self.choices)} choices"
            )
        if self.categorical and self.coding == "log":
            raise ValueError(
                f"coding: factor {self.name!r} is categorical (its levels only number its "
                "choices), so it cannot be coded on a log scale; remove coding = 'log'"
            )
        if self.categorical and self.coded_range is not None:
            raise ValueError(
                f"coded_range: factor {self.name!r} is categorical (its levels only number its "
                "choices), so it has no coded range; remove coded_range"
            )
        if self.coding == "log":
            for value in self.levels:
                if value <= 0:
                    raise ValueError(
                        f"coding: factor {self.name!r} is coded 'log' (log10 of its level), so "
                        f"every level must be above 0; level {value!r} is not"
                    )
            for value in self.coded_range or ():
                if value <= 0:
                    raise ValueError(
                        f"coded_range: factor {self.name!r} is coded 'log' (log10 of its "
                        f"level), so both ends must be above 0; {value!r} is not"
                    )
        return self

    @property
    def categorical(self) -> bool:
        """Whether the factor is categorical (``choices``, or the field ``cycle``): its levels
        only number its choices."""
        return self.choices is not None or self.field == "cycle"

    @property
    def coding_range(self) -> tuple[float, float]:
        """The levels coded -1 and +1 [design unit]: :attr:`coded_range`, by default the
        lowest and the highest level."""
        if self.coded_range is not None:
            return self.coded_range
        return float(min(self.levels)), float(max(self.levels))

    def coded(self, value: float) -> float:
        """The coded value [-] of level ``value`` [design unit]: -1 and +1 at the ends of
        :attr:`coding_range`, linear in the level (``coding = "linear"``) or in its log10
        (``"log"``).

        Raises
        ------
        ValueError
            A categorical factor, or a level at or below 0 with log coding.
        """
        if self.categorical:
            raise ValueError(f"factor {self.name!r} is categorical: its levels have no coding")
        low, high = self.coding_range
        if self.coding == "log":
            if value <= 0:
                raise ValueError(
                    f"factor {self.name!r} is coded 'log': level {value!r} is not above 0"
                )
            low, high, value = math.log10(low), math.log10(high), math.log10(value)
        return (2.0 * value - (low + high)) / (high - low)

    def uncoded(self, x: float) -> float:
        """The level [design unit] at coded value ``x`` [-] (the inverse of :meth:`coded`;
        exactly the ends of :attr:`coding_range` at -1 and +1)."""
        if self.categorical:
            raise ValueError(f"factor {self.name!r} is categorical: its levels have no coding")
        low, high = self.coding_range
        return _decode(low, high, self.coding, x)

    def order_note(self) -> str | None:
        """A note when a numeric factor's levels are not given low first (``levels = [20,
        10]``): the analysis takes them in the order given, where Minitab and JMP take the
        value order. None for levels in increasing order and for a categorical factor."""
        if self.categorical or all(a < b for a, b in itertools.pairwise(self.levels)):
            return None
        return (
            f"factor {self.name}'s levels are not given low first "
            f"({', '.join(f'{v:g}' for v in self.levels)}): tables and plots take them in "
            "this order, so a two-level effect is the second level's mean less the first's "
            "and a general factorial's derived coefficient is the last level's (Minitab and "
            "JMP take the levels in value order); give them low first for the usual signs"
        )

    def unit_note(self) -> str | None:
        """A note when :attr:`unit` is the field's unit with an SI prefix (``GPa`` on
        ``contact.elastic_modulus``, ``1/MPa`` on ``friction.slope``), or ``%`` on a
        dimensionless field, while :attr:`scale` is 1: the unit is a label, so the levels
        are taken in the field's own unit. None otherwise (another label, an alias, a
        categorical factor, a scale given)."""
        if self.choices is not None or self.field == "cycle" or self.field in FACTOR_ALIASES:
            return None
        own = _field_unit(self.field)
        if self.scale != 1.0 or own is None or self.unit == own:
            return None
        scale = _prefixed_scale(self.unit, own)
        if scale is None:
            return None
        return (
            f"factor {self.name!r}: its unit {self.unit!r} is a label; with scale 1 its "
            f"levels are taken in the unit of {self.field}, {own}. For levels in "
            f"{self.unit}, give scale = {_short_number(scale)}"
        )

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
        Test number in the design's test order (:meth:`Design.combinations`), 1-based [-].
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

    Parameters
    ----------
    root_seed
        The design's root seed [-].
    test
        The test number, from 1 [-].
    replicate
        The replicate, from 0 [-].

    Returns
    -------
    int
        The run's seed, 0 to 2**32 - 1 [-].

    Examples
    --------
    >>> from brakeca.design import point_seed
    >>> point_seed(2016, 5, 0)  # the paper design's root seed, test 5
    1456000950
    """
    state = np.random.SeedSequence([root_seed, test, replicate]).generate_state(1, dtype=np.uint32)
    return int(state[0])


def is_run_id(text: str) -> bool:
    """Whether ``text`` is a run's id as :func:`run_id_for` makes it (16 hexadecimal
    digits): a summary's run_id names a file in ``runs/``, never another path."""
    return len(text) == 16 and all(c in "0123456789abcdef" for c in text)


def run_id_for(config: SimulationConfig, seed: int) -> str:
    """Stable 16-hex-digit identifier of (config, seed): sha256 of the config's TOML (its
    :meth:`~brakeca.config.SimulationConfig.identity_toml`) and the seed.

    Parameters
    ----------
    config
        The run's resolved configuration.
    seed
        The run's seed [-].

    Returns
    -------
    str
        16 lowercase hex digits.
    """
    text = config.identity_toml() + f"\n# seed\n{int(seed)}\n"
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def run_id(point: RunPoint) -> str:
    """Stable identifier of a run point, used as its file name (``runs/<run_id>.nc``).

    The first 16 hex digits of the sha256 of the resolved configuration's TOML followed by the
    seed; it does not depend on the test number, the design or the package version.

    Parameters
    ----------
    point
        A run point of a design.

    Returns
    -------
    str
        16 lowercase hex digits (:func:`run_id_for` of its configuration and seed).
    """
    return run_id_for(point.config, point.seed)


def execution_order(points: Sequence[RunPoint]) -> list[RunPoint]:
    """``points`` sorted into execution order (by :attr:`RunPoint.order`).

    Parameters
    ----------
    points
        Run points, as :meth:`Design.points` gives them (in test order).

    Returns
    -------
    list of RunPoint
        The same points, in the order a campaign runs them.
    """
    return sorted(points, key=lambda p: p.order)


#: The fields :func:`quick_config` sets, which an override beside ``--quick`` cannot set.
QUICK_FIELDS = ("mesh.n_radial", "mesh.inner_radius", "quick")


def check_quick_overrides(overrides: Mapping[str, Any]) -> None:
    """Refuse overrides of the fields ``--quick`` sets (:data:`QUICK_FIELDS`): quick would
    silently overwrite them.

    Raises
    ------
    ConfigError
        Naming the override and what ``--quick`` sets instead.
    """
    for key in overrides:
        if _target(key) in QUICK_FIELDS:
            raise ConfigError(
                f"override {key}: --quick sets the band itself (mesh.n_radial = "
                f"{QUICK_N_RADIAL}, mesh.inner_radius unset), so the override would be "
                "ignored; drop --quick or the override"
            )


def quick_config(config: SimulationConfig) -> SimulationConfig:
    """Narrow the band to 21 radial rows centred on the effective radius (``--quick``).

    Keeps the cell size, the angular extent and the drive cycle; sets ``mesh.n_radial = 21``
    (2 mm at the paper's 0.1 mm radial step), unsets ``mesh.inner_radius`` and sets
    ``quick = True``.

    Parameters
    ----------
    config
        The configuration to narrow.

    Returns
    -------
    SimulationConfig
        The narrowed copy; ``config`` is unchanged.

    Raises
    ------
    TypeError
        ``config`` is not a :class:`~brakeca.config.SimulationConfig` (a preset's name, say).
    ConfigError
        The narrowed band does not fit the disc (only with an unusual radial step).

    Examples
    --------
    >>> from brakeca.design import quick_config
    >>> from brakeca.presets import load_preset
    >>> quick = quick_config(load_preset())
    >>> quick.mesh.n_radial, quick.mesh.n_angular, quick.quick  # 2 mm of the 20 mm band
    (21, 1000, True)
    """
    if not isinstance(config, SimulationConfig):  # a preset's name, say (an API review)
        raise TypeError(
            f"config: a SimulationConfig (brakeca.load_preset(name) gives one), not "
            f"{type(config).__name__}" + (f" ({config!r})" if isinstance(config, str) else "")
        )
    return config.with_updates(
        {"mesh.n_radial": QUICK_N_RADIAL, "mesh.inner_radius": None, "quick": True}
    )


# --- fractional factorials ------------------------------------------------------------------

#: Most generators whose defining relation :meth:`Design.relation_text` lists (2^12 - 1 =
#: 4095 words to sort); beyond, it gives only the count.
_MAX_LISTED_GENERATORS = 12

#: ``X = [sign] word``: the generated factor, '=', an optional sign and the product.
_GENERATOR = re.compile(r"\s*([^=\s]+)\s*=\s*([+-]?)\s*(.*?)\s*", re.DOTALL)

_GENERATOR_FORM = (
    "a generator is 'X = F1*F2*...*Fk': the generated factor, '=', then the product of base "
    "factors joined by '*', optionally after a '-' (e.g. 'D = A*B*C' or 'E = -A*B')"
)


class _Generator(NamedTuple):
    """One parsed generator ``target = sign * word``."""

    position: int
    target: str
    sign: int
    word: tuple[str, ...]


class _Word(NamedTuple):
    """A word of the defining relation: ``I = sign * factors`` (a bit per factor, in design
    order) and the generators whose product it is (a bit per generator)."""

    sign: int
    mask: int
    generators: int


def _roman(number: int) -> str:
    """``number`` (1 or more) in roman numerals: 3 -> ``"III"``, 4 -> ``"IV"``."""
    numerals = (
        (1000, "M"),
        (900, "CM"),
        (500, "D"),
        (400, "CD"),
        (100, "C"),
        (90, "XC"),
        (50, "L"),
        (40, "XL"),
        (10, "X"),
        (9, "IX"),
        (5, "V"),
        (4, "IV"),
        (1, "I"),
    )
    out = []
    for value, numeral in numerals:
        count, number = divmod(number, value)
        out.append(numeral * count)
    return "".join(out)


def _unknown_factor(key: str, name: str, names: Sequence[str]) -> ValueError:
    hint = ""
    if len(name) > 1 and all(c in names for c in name):
        hint = f"; write a product with '*': {'*'.join(name)}"
    return ValueError(f"{key}: unknown factor {name!r} (factors: {', '.join(names)}){hint}")


def _parse_generators(
    generators: Sequence[str], factors: Sequence[Factor]
) -> tuple[_Generator, ...]:
    """Parse and check the generators of a fractional factorial.

    Parameters
    ----------
    generators
        The ``"X = F1*F2*..."`` texts.
    factors
        The design's factors (unique names).

    Returns
    -------
    tuple of _Generator
        One per generator, in the given order.

    Raises
    ------
    ValueError
        Bad syntax, an unknown or repeated factor, a factor generated twice or used in a word
        while generated, a factor in a generator without exactly two levels; the message
        starts with ``generators #<n>`` (counted from 1).
    """
    names = [f.name for f in factors]
    n_levels = {f.name: len(f.levels) for f in factors}
    if len(generators) > MAX_GENERATORS:
        raise ValueError(
            f"generators: {len(generators)} generators, more than {MAX_GENERATORS}; give a "
            "design that large as a run table (runs or runs_file)"
        )
    parsed: list[_Generator] = []
    for i, text in enumerate(generators):
        key = item_path(("generators", i))
        match = _GENERATOR.fullmatch(text)
        if match is None or not match.group(1).isidentifier():
            raise ValueError(f"{key}: cannot read {text!r}: {_GENERATOR_FORM}")
        target, sign, body = match.groups()
        if not body:
            raise ValueError(
                f"{key}: {text!r} has an empty word: after '=' give the product of at least "
                "two base factors, e.g. 'D = A*B*C'"
            )
        word = tuple(part.strip() for part in body.split("*"))
        if not all(part.isidentifier() for part in word):
            hint = "" if "*" in body else " (a product is written with '*')"
            raise ValueError(f"{key}: cannot read {text!r}{hint}: {_GENERATOR_FORM}")
        for name in (target, *word):
            if name not in n_levels:
                raise _unknown_factor(key, name, names)
        repeated = next((name for name in word if word.count(name) > 1), None)
        if repeated is not None:
            raise ValueError(
                f"{key}: factor {repeated!r} appears {word.count(repeated)} times in the word "
                f"{'*'.join(word)} of {text!r}; each base factor at most once"
            )
        if target in word:
            raise ValueError(
                f"{key}: the generated factor {target!r} appears in its own word ({text!r}); "
                "a word is a product of base factors only"
            )
        parsed.append(_Generator(i, target, -1 if sign == "-" else 1, word))
    generated: dict[str, int] = {}
    for g in parsed:
        if g.target in generated:
            raise ValueError(
                f"{item_path(('generators', g.position))}: "
                f"factor {g.target!r} is generated twice (also by "
                f"{item_path(('generators', generated[g.target]))})"
            )
        generated[g.target] = g.position
    for g in parsed:
        key = item_path(("generators", g.position))
        for name in g.word:
            if name in generated:
                raise ValueError(
                    f"{key}: factor {name!r} in the word of {generators[g.position]!r} is itself "
                    f"generated (by {item_path(('generators', generated[name]))}); a word uses "
                    "base factors only"
                )
        for name in (g.target, *g.word):
            if n_levels[name] != 2:
                role = "the generated factor" if name == g.target else "the base factor"
                raise ValueError(
                    f"{key}: {role} {name!r} has {n_levels[name]} levels; a factor in a "
                    "generator needs exactly 2 (levels[0] is coded -1, levels[1] +1)"
                )
    return tuple(parsed)


def _generator_masks(parsed: Sequence[_Generator], names: Sequence[str]) -> list[tuple[int, int]]:
    """Each generator's defining word ``I = sign * target * word`` as (sign, factor bits)."""
    bit = {name: 1 << k for k, name in enumerate(names)}
    return [(g.sign, bit[g.target] | sum(bit[n] for n in g.word)) for g in parsed]


def _defining_words(parsed: Sequence[_Generator], names: Sequence[str]) -> Iterator[_Word]:
    """All 2^p - 1 words of the defining relation (products of the generators' words),
    visited in Gray-code order: each next word is one generator's product away."""
    masks = _generator_masks(parsed, names)
    sign, mask = 1, 0
    for step in range(1, 2 ** len(masks)):
        j = (step & -step).bit_length() - 1  # the generator whose inclusion flips
        sign *= masks[j][0]
        mask ^= masks[j][1]
        yield _Word(sign, mask, step ^ (step >> 1))


@functools.lru_cache(maxsize=32)
def _shortest_word(parsed: tuple[_Generator, ...], names: tuple[str, ...]) -> _Word:
    """The first shortest word of the defining relation, in its stable order (by length,
    then by its factors' design order); cached, as a relation has up to 2^20 - 1 words."""
    best: _Word | None = None
    best_key: tuple[int, tuple[int, ...]] = (len(names) + 1, ())
    for word in _defining_words(parsed, names):
        length = word.mask.bit_count()
        if length <= best_key[0]:
            key = (length, _word_key(word.mask, len(names)))
            if key < best_key:
                best, best_key = word, key
    assert best is not None, "a fraction has at least one generator"
    return best


def _word_key(mask: int, n: int) -> tuple[int, ...]:
    """The design-order indices of the factors in ``mask``."""
    return tuple(k for k in range(n) if mask >> k & 1)


def _word_text(sign: int, mask: int, names: Sequence[str]) -> str:
    """``"I = -A*B*C*D"``."""
    factors = "*".join(names[k] for k in _word_key(mask, len(names)))
    return f"I = {'-' if sign < 0 else ''}{factors}"


def _check_resolution(parsed: tuple[_Generator, ...], names: tuple[str, ...]) -> None:
    """Refuse a fraction of resolution below III (two main effects aliased)."""
    if not parsed:
        return
    word = _shortest_word(parsed, names)
    if word.mask.bit_count() >= 3:
        return
    first, second = (names[k] for k in _word_key(word.mask, len(names)))
    used = [g for k, g in enumerate(parsed) if word.generators >> k & 1]
    keys = ", ".join(item_path(("generators", g.position)) for g in used)
    # a product of m generators holds their m generated factors: a pair is one generator
    # with a single base factor, or two generators with the same word
    why = (
        "a generator's word needs at least two base factors"
        if len(used) == 1
        else "two generators have the same word (up to its sign)"
    )
    raise ValueError(
        f"{keys}: the fraction has resolution II: the main effects of {first!r} and "
        f"{second!r} are aliased (defining word {_word_text(word.sign, word.mask, names)}): "
        f"{why}; a design needs resolution III or more"
    )


# --- run tables -----------------------------------------------------------------------------


def _match_level(factor: Factor, value: int | float | str) -> int | float | None:
    """The level of ``factor`` that ``value`` stands for (None when none does).

    A number matches a level numerically (10 is the level 10.0; a relative difference of
    1e-9, as from a spreadsheet's rounding, is forgiven); a text matches a categorical
    factor's choice or label.
    """
    if isinstance(value, str):
        if factor.choices is None:
            return None
        for texts in (factor.choices, factor.labels or ()):
            if value in texts:
                return factor.levels[texts.index(value)]
        return None
    for level in factor.levels:
        if value == level:
            return level
    for level in factor.levels:
        if math.isclose(value, level, rel_tol=1e-9, abs_tol=0.0):
            return level
    return None


def _levels_text(factor: Factor) -> str:
    text = ", ".join(f"{v!r}" for v in factor.levels)
    if factor.choices is not None:
        text += f"; or a choice: {', '.join(factor.choices)}"
    return text


def _not_a_level(key: str, factor: Factor, value: Any) -> ValueError:
    return ValueError(
        f"{key}: {value!r} is not a level of factor {factor.name!r} (levels: "
        f"{_levels_text(factor)})"
    )


def _raw_choices(factors: Any) -> dict[str, dict[str, Any]]:
    """From unvalidated factor tables: each categorical factor's choice and label texts,
    mapped to their level numbers."""
    out: dict[str, dict[str, Any]] = {}
    if isinstance(factors, str | bytes) or not isinstance(factors, Sequence):
        return out
    for f in factors:
        if not isinstance(f, Mapping) or not isinstance(f.get("name"), str):
            continue
        levels, texts = f.get("levels"), {}
        if not isinstance(levels, Sequence) or isinstance(levels, str | bytes):
            continue
        for key in ("labels", "choices"):  # a choice wins over a label
            seq = f.get(key)
            if isinstance(seq, Sequence) and not isinstance(seq, str | bytes):
                if len(seq) == len(levels):
                    texts.update({str(t): lv for t, lv in zip(seq, levels, strict=True)})
        choices = f.get("choices")
        if isinstance(choices, Sequence) and not isinstance(choices, str | bytes):
            out[f["name"]] = texts
    return out


def _raw_factor_names(factors: Any) -> list[str] | None:
    """From unvalidated factor tables: the factors' names (None when there is no list)."""
    if isinstance(factors, str | bytes) or not isinstance(factors, Sequence):
        return None
    names = [f.get("name") if isinstance(f, Mapping) else None for f in factors]
    return (
        [n for n in names if isinstance(n, str)] if all(isinstance(n, str) for n in names) else None
    )


def _read_runs_csv(path: Path, factors: Sequence[Factor], where: str) -> list[dict[str, Any]]:
    """The rows of a run-table CSV file, each a factor-name to level mapping.

    The header row names the factors (every one, in any order); each further row gives one
    test. UTF-8 (a BOM is accepted), comma, semicolon or tab separated (the separator is the
    header's, as for drive traces); a semicolon- or tab-separated file may write decimal
    commas (``1,5``). Blank lines and lines starting with ``#`` are skipped; a first line
    ``sep=;`` (as Excel writes it) names the separator; trailing empty cells (a spreadsheet's
    trailing separators) are ignored.

    Parameters
    ----------
    path
        The CSV file.
    factors
        The design's factors.
    where
        Prefix of error messages (the design file and its key).

    Returns
    -------
    list of dict
        One per row, in file order: factor name to the level value from ``levels``, in
        design order.

    Raises
    ------
    ConfigError
        Unreadable file, a missing, unknown or repeated column, a wrong number of values, a
        value that is no level of its factor, fewer than two rows; the message names the
        file and the line.
    """
    names = [f.name for f in factors]
    by_name = {f.name: f for f in factors}
    try:
        text = read_csv_text(path)
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{where}: cannot read {path}: {exc}") from None
    header: list[str] | None = None
    delimiter = ","
    named: str | None = None  # the separator an Excel "sep=;" line names
    rows: list[dict[str, Any]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        if not raw.strip() or raw.lstrip().startswith("#"):
            continue
        line = raw.rstrip("\r\n")  # a leading empty cell (a tab) stays a cell
        at = f"{where}: {path}, line {lineno}"
        if header is None and named is None and (named := excel_separator(line)) is not None:
            continue
        if header is None:
            delimiter = named or csv_delimiter(line.strip())
            header = [
                c.strip().strip("\"'").strip()
                for c in next(csv.reader([line], delimiter=delimiter))
            ]
            while len(header) > 1 and not header[-1]:
                header.pop()  # a spreadsheet's trailing separators
            for k, name in enumerate(header):
                if not name:
                    raise ConfigError(f"{at}: column {k + 1} of the header has no name")
                if header.index(name) != k:
                    raise ConfigError(f"{at}: column {name!r} appears twice in the header")
                if name not in by_name:
                    raise ConfigError(
                        f"{at}: column {name!r}: unknown factor (factors: {', '.join(names)}); "
                        "the header row names the factors"
                    )
            missing = [n for n in names if n not in header]
            if missing:
                raise ConfigError(
                    f"{at}: no column for factor(s) {', '.join(missing)}; each run gives "
                    "every factor one of its levels"
                )
            continue
        cells = [
            c.strip().strip("\"'").strip() for c in next(csv.reader([line], delimiter=delimiter))
        ]
        while len(cells) > len(header) and not cells[-1]:
            cells.pop()  # a spreadsheet's trailing separators
        if len(cells) != len(header):
            raise ConfigError(
                f"{at}: expected {len(header)} values ({', '.join(header)}), found "
                f"{len(cells)}: {line!r}"
            )
        row: dict[str, Any] = {}
        for name, cell in zip(header, cells, strict=True):
            factor = by_name[name]
            key = f"{at}, column {name!r} ({item_path(('runs', len(rows), name))})"
            if not cell:
                raise ConfigError(f"{key}: no value; each run gives every factor a level")
            number = decimal_point(cell) if delimiter != "," else cell
            try:
                value: float | str = csv_float(number)
            except ValueError:
                value = cell
            level = _match_level(factor, value)
            if level is None:
                raise ConfigError(str(_not_a_level(key, factor, cell)))
            row[name] = level
        rows.append({n: row[n] for n in names})
    if header is None:
        raise ConfigError(f"{where}: {path}: empty file: no header row naming the factors")
    if len(rows) < 2:
        raise ConfigError(f"{where}: {path}: a run table needs at least 2 runs, found {len(rows)}")
    return rows


# --- central composite designs --------------------------------------------------------------

#: The factors a central composite design takes [-]: from 2 (its 2^k cube points are a full
#: factorial, so 6 factors already give 64 of them).
_COMPOSITE_FACTORS = (2, 6)

_ALPHA_NAMES = ("face", "rotatable", "orthogonal")


def _finite_number(value: Any) -> bool:
    """Whether ``value`` is a finite int or float (not a bool)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:  # an int too large for a float
        return False


def _decode(low: float, high: float, coding: str, x: float) -> float:
    """The level [design unit] at coded value ``x`` [-] of a factor coded -1 at ``low`` and +1
    at ``high``, linearly in the level (``coding = "linear"``) or in its log10 (``"log"``).
    At -1 and +1 it is ``low`` and ``high`` themselves (not recomputed)."""
    if x == -1:
        return low
    if x == 1:
        return high
    if coding == "log":
        a, b = math.log10(low), math.log10(high)
        return float(10.0 ** ((a + b) / 2.0 + x * (b - a) / 2.0))
    return (low + high) / 2.0 + x * (high - low) / 2.0


class Composite(_Frozen):
    """A central composite design (a response-surface design, as Minitab's "Create Response
    Surface Design"): the 2^k cube points of a full factorial of the factors' two levels
    (coded -1 and +1), 2k axial points (one factor at -alpha or +alpha, the others at their
    centre, 0) and ``center`` centre points (every factor at 0).

    Parameters
    ----------
    alpha
        Distance of the axial points from the centre [coded unit]: ``"face"`` 1 (face-centred,
        CCF: every point within the factors' levels), ``"rotatable"`` (2^k)^(1/4) (the
        prediction variance depends only on the distance from the centre), ``"orthogonal"``
        the distance making the pure quadratic terms orthogonal for the given centre points
        (:meth:`alpha_value`), or a number from 1 to 10.
    center
        Centre points [-]: repeated tests at the centre, each with its own seed, so their
        scatter estimates the seed-to-seed scatter (the pure error).

    References
    ----------
    D. C. Montgomery, "Design and Analysis of Experiments", 8th ed., Wiley, 2013, §11.4.2
    (central composite designs: rotatability, the face-centred and the orthogonal design).
    """

    alpha: float | Literal["face", "rotatable", "orthogonal"] = "face"
    center: int = Field(4, ge=1, le=100)

    @field_validator("alpha", mode="before")
    @classmethod
    def _alpha(cls, value: Any) -> Any:
        if isinstance(value, str) and value in _ALPHA_NAMES:
            return value
        if _finite_number(value) and 1.0 <= value <= 10.0:
            return float(value)
        raise ValueError(
            "expected 'face', 'rotatable', 'orthogonal' or a number from 1 to 10 (the axial "
            "points' distance from the centre in coded units)"
        )

    def alpha_value(self, k: int) -> float:
        """The axial distance [coded unit] for ``k`` factors.

        ``"face"``: 1; ``"rotatable"``: (2^k)^(1/4); ``"orthogonal"``:
        ((sqrt(F N) - F)^2 / 4)^(1/4) with F = 2^k cube points and N = F + 2k + ``center``
        points in all, which makes the centred columns of the squared coded levels
        orthogonal (e.g. 1.210 for k = 2 and 4 centre points; 1 for k = 2 and 1).
        """
        if self.alpha == "face":
            return 1.0
        cube = 2.0**k
        if self.alpha == "rotatable":
            return float(cube**0.25)
        if self.alpha == "orthogonal":
            total = cube + 2 * k + self.center
            return float(((math.sqrt(cube * total) - cube) ** 2 / 4.0) ** 0.25)
        return float(self.alpha)

    def describe(self, k: int) -> str:
        """The kind of axial distance for ``k`` factors: ``"face-centred, α = 1"``,
        ``"rotatable, α = 1.682"``, ``"orthogonal, α = 1.21"`` or ``"α = 1.5"``."""
        alpha = self.alpha_value(k)
        if alpha == 1.0:
            return "face-centred, α = 1"
        if isinstance(self.alpha, str):
            return f"{self.alpha}, α = {alpha:.4g}"
        return f"α = {alpha:.4g}"

    #: the design file's key, the design's name, and the factors it takes [-]
    key: ClassVar[str] = "composite"
    title: ClassVar[str] = "central composite design"
    factor_range: ClassVar[tuple[int, int]] = _COMPOSITE_FACTORS

    def kind(self, k: int) -> str:
        """:attr:`Design.kind` of this design over ``k`` factors."""
        return (
            f"{self.title} ({self.describe(k)}), {k} factors: {2**k} cube, {2 * k} axial and "
            f"{_points(self.center, 'centre point')}"
        )

    def table(
        self, factors: Sequence[tuple[str, float, float, str]]
    ) -> tuple[list[list[float]], list[list[str]], list[dict[str, float]]]:
        """The levels, labels and tests (:func:`_composite_table`)."""
        return _composite_table(factors, self)


def _points(n: int, what: str) -> str:
    return f"{n} {what}{'s' if n != 1 else ''}"


#: The factors a Box-Behnken design takes [-]: 3 to 5, whose designs pair every two factors.
_BOX_BEHNKEN_FACTORS = (3, 5)


class BoxBehnken(_Frozen):
    """A Box-Behnken design (a response-surface design, as Minitab's "Create Response
    Surface Design"): for every pair of factors the 2^2 factorial of their two levels (coded
    -1 and +1) with the other factors at their centre (0), then ``center`` centre points.
    Three levels per factor and no run at a corner of the cube (every factor at an extreme
    at once): 12 + centre runs for 3 factors, 24 + centre for 4, 40 + centre for 5.

    Parameters
    ----------
    center
        Centre points [-], as for :class:`Composite`.

    References
    ----------
    G. E. P. Box and D. W. Behnken, "Some new three level designs for the study of
    quantitative variables", Technometrics 2(4), 455-475, 1960; Montgomery (2013), §11.4.2.
    """

    center: int = Field(3, ge=1, le=100)

    key: ClassVar[str] = "box_behnken"
    title: ClassVar[str] = "Box-Behnken design"
    factor_range: ClassVar[tuple[int, int]] = _BOX_BEHNKEN_FACTORS

    def describe(self, k: int) -> str:
        """``"Box-Behnken"`` (the same for every ``k``)."""
        return "Box-Behnken"

    def kind(self, k: int) -> str:
        """:attr:`Design.kind` of this design over ``k`` factors."""
        edges = 4 * k * (k - 1) // 2
        return (
            f"{self.title}, {k} factors: {edges} edge points (each pair of factors at - and +, "
            f"the others at 0) and {_points(self.center, 'centre point')}"
        )

    def table(
        self, factors: Sequence[tuple[str, float, float, str]]
    ) -> tuple[list[list[float]], list[list[str]], list[dict[str, float]]]:
        """The levels (low, centre, high), labels (``-``, ``0``, ``+``) and tests: for each
        pair of factors in design order, the 2^2 factorial (the first of the pair fastest, -1
        first) with the others at 0; then the centre points."""
        coded = [-1.0, 0.0, 1.0]
        levels = [
            [_decode(low, high, coding, x) for x in coded] for _, low, high, coding in factors
        ]
        k = len(factors)
        points = []
        for i, j in itertools.combinations(range(k), 2):
            for xj, xi in itertools.product((-1.0, 1.0), repeat=2):
                point = [0.0] * k
                point[i], point[j] = xi, xj
                points.append(point)
        points += [[0.0] * k] * self.center
        tests = [
            {
                name: levels[m][coded.index(x)]
                for m, ((name, *_), x) in enumerate(zip(factors, p, strict=True))
            }
            for p in points
        ]
        return levels, [["-", "0", "+"] for _ in factors], tests


def _composite_table(
    factors: Sequence[tuple[str, float, float, str]], composite: Composite
) -> tuple[list[list[float]], list[list[str]], list[dict[str, float]]]:
    """The levels, labels and tests of a central composite design.

    Parameters
    ----------
    factors
        (name, low, high, coding) of each factor in design order: the levels [design unit]
        coded -1 and +1 and ``"linear"`` or ``"log"``.
    composite
        The axial distance and the centre points.

    Returns
    -------
    levels : list of list of float
        Each factor's distinct levels, ascending: low, centre, high (alpha 1), or -alpha,
        low, centre, high, +alpha.
    labels : list of list of str
        Their labels: ``-``, ``0``, ``+`` (alpha 1), or ``-α``, ``-``, ``0``, ``+``, ``+α``.
    tests : list of dict
        Factor name to level, in Minitab's standard order: the 2^k cube points (the first
        factor varying fastest, -1 first), the 2k axial points (each factor in design order
        at -alpha, then +alpha, the others at 0), then the centre points.

    Raises
    ------
    ValueError
        An axial level that falls on a cube level (alpha too close to 1).
    """
    k = len(factors)
    alpha = composite.alpha_value(k)
    coded: list[float] = [-1.0, 0.0, 1.0] if alpha == 1.0 else [-alpha, -1.0, 0.0, 1.0, alpha]
    labels = ["-", "0", "+"] if alpha == 1.0 else ["-α", "-", "0", "+", "+α"]
    levels: list[list[float]] = []
    for name, low, high, coding in factors:
        values = [_decode(low, high, coding, x) for x in coded]
        if any(
            b <= a or math.isclose(a, b, rel_tol=LEVEL_RTOL, abs_tol=0.0)
            for a, b in itertools.pairwise(values)
        ):
            raise ValueError(
                f"composite.alpha: alpha = {alpha!r} puts factor {name!r}'s axial levels on "
                f"its cube levels (or within {LEVEL_RTOL:g} of them, which the analysis reads "
                "as one level); give alpha = 1 (face) or a larger one"
            )
        levels.append(values)
    cube = [combo[::-1] for combo in itertools.product((-1.0, 1.0), repeat=k)]
    axial = [
        tuple(sign * alpha if j == i else 0.0 for j in range(k))
        for i in range(k)
        for sign in (-1.0, 1.0)
    ]
    centre = [(0.0,) * k] * composite.center
    tests = [
        {
            name: levels[j][coded.index(x)]
            for j, ((name, *_), x) in enumerate(zip(factors, point, strict=True))
        }
        for point in (*cube, *axial, *centre)
    ]
    return levels, [list(labels) for _ in factors], tests


def _quadratic_residue_row(q: int) -> str:
    """Paley's generator row for a prime ``q = 3 (mod 4)``: ``+`` at 0 and at the quadratic
    residues mod ``q``, ``-`` elsewhere; its cyclic shifts and a row of ``-`` make a Hadamard
    design of ``q + 1`` runs."""
    residues = {(i * i) % q for i in range(1, q)}
    return "".join("+" if i == 0 or i in residues else "-" for i in range(q))


#: The Plackett-Burman designs made from one generator (Plackett and Burman 1946, as Minitab
#: lists them in its "Summary of Plackett-Burman designs"): the first factor's column, in
#: test order; factor j's column is it shifted down j places (cyclically), and a last test
#: has every factor at -; one column per factor, the first k of the N - 1 [-]. The 12-, 20-,
#: 24-, 44- and 48-run generators are Paley's quadratic-residue rows of 11, 19, 23, 43 and 47
#: (a test checks them against the printed ones); the 32- and 36-run ones are printed only.
PLACKETT_BURMAN_GENERATORS: dict[int, str] = {
    12: "++-+++---+-",
    20: "++--++++-+-+----++-",
    24: "+++++-+-++--++--+-+----",
    32: "----+-+-+++-++---+++++--++-+--+",
    36: "-+-+++---+++++-+++--+----+-+-++--+-",
    44: _quadratic_residue_row(43),
    48: _quadratic_residue_row(47),
}

#: The first 9 tests of the 28-run Plackett-Burman design (Plackett and Burman 1946, as
#: Minitab lists them), three blocks of 9 factors each (A, B, C); tests 10 to 18 take the
#: blocks in the order C, A, B and tests 19 to 27 in the order B, C, A (each time shifted one
#: block to the right), and test 28 has every factor at - [-].
PLACKETT_BURMAN_28: tuple[str, ...] = (
    "+-++++----+---+--+++-+-++-+",
    "++-+++-----++--+---++++-++-",
    "-+++++---+---+--+-+-+-++-++",
    "---+-++++--+-+---++-+++-+-+",
    "---++-++++----++--++--++++-",
    "----+++++-+-+---+--+++-+-++",
    "+++---+-+--+--+-+-+-++-+++-",
    "+++---++-+--+----+++-++--++",
    "+++----++-+--+-+---++-+++-+",
)

#: The numbers of tests a Plackett-Burman design may have [-].
PLACKETT_BURMAN: tuple[int, ...] = tuple(sorted([*PLACKETT_BURMAN_GENERATORS, 28]))


def _plackett_burman_signs(runs: int, k: int) -> list[list[int]]:
    """The coded levels (-1, +1) of the Plackett-Burman design of ``runs`` tests over ``k``
    factors, in its standard order, Minitab's (see :data:`PLACKETT_BURMAN_GENERATORS` and
    :data:`PLACKETT_BURMAN_28`)."""
    if runs == 28:
        table = [[1 if c == "+" else -1 for c in row] for row in PLACKETT_BURMAN_28]
        tests = [
            [table[i][9 * ((j // 9 - shift) % 3) + j % 9] for j in range(k)]
            for shift in range(3)
            for i in range(9)
        ]
    else:
        column = [1 if c == "+" else -1 for c in PLACKETT_BURMAN_GENERATORS[runs]]
        n = len(column)
        tests = [[column[(i - j) % n] for j in range(k)] for i in range(n)]
    return [*tests, [-1] * k]


def _plackett_burman_signs_by_rows(runs: int, k: int) -> list[list[int]]:
    """The tests brakeca wrote for a Plackett-Burman design before it took Minitab's order
    (until 2026-11-26): the generator as the first test and each test after it shifted one
    place to the right (the design transposed: equally orthogonal, the same design once its
    factors are renumbered, but not Minitab's tests for each factor); still accepted when
    read back, so that a campaign made then stays readable [-]."""
    row = [1 if c == "+" else -1 for c in PLACKETT_BURMAN_GENERATORS[runs]]
    n = len(row)
    tests = [[row[(j - shift) % n] for j in range(k)] for shift in range(n)]
    return [*tests, [-1] * k]


def _signs_of(runs: Sequence[Mapping[str, Any]], factors: Sequence[Factor]) -> list[list[int]]:
    """A two-level run table's coded levels: -1 at a factor's first level, +1 at its second,
    0 at neither [-]."""
    return [
        [
            -1 if row[f.name] == f.levels[0] else 1 if row[f.name] == f.levels[-1] else 0
            for f in factors
        ]
        for row in runs
    ]


#: The responses a goal may name (a design's or ``brakeca optimize --goal``'s), with the
#: unit its limits are given in and the factor from the campaign's column to that unit: MU
#: [-], V in mm^3 per stop (the campaign's V is in m^3), log10 of V in mm^3 [-], MU_SD (the
#: friction stability, the standard deviation of the stops' mean COF) [-].
GOAL_RESPONSES: dict[str, tuple[str, float]] = {
    "MU": ("-", 1.0),
    "V": ("mm³", 1e9),
    "log10_V_mm3": ("-", 1.0),
    "MU_SD": ("-", 1.0),
}


class GoalSpec(_Frozen):
    """What a response-surface design's report optimizes for one response
    (:func:`brakeca.rsm.optimize`, Minitab's Response Optimizer); the limits in the unit of
    :data:`GOAL_RESPONSES` (V in mm^3).

    Parameters
    ----------
    response
        ``"MU"``, ``"V"``, ``"log10_V_mm3"`` or ``"MU_SD"``.
    goal
        ``"minimize"``, ``"maximize"`` or ``"target"``.
    lower, upper
        The desirability's limits [response unit; V in mm^3]: for ``minimize`` 1 at or below
        ``lower`` and 0 at or above ``upper``; for ``maximize`` the reverse; for ``target``
        0 at and beyond both.
    target
        The target [response unit], strictly between the limits (``target`` only). A
        ``minimize`` goal may give its ``lower`` as ``target``, and a ``maximize`` goal its
        ``upper``, as Minitab names them.
    weight, importance
        The desirability's shape and the response's weight in the composite [-], 0.1 to 10.
    """

    response: Literal["MU", "V", "log10_V_mm3", "MU_SD"]
    goal: Literal["minimize", "maximize", "target"]
    lower: float = Field(allow_inf_nan=False)
    upper: float = Field(allow_inf_nan=False)
    target: float | None = Field(None, allow_inf_nan=False)
    weight: float = 1.0
    importance: float = 1.0

    @model_validator(mode="before")
    @classmethod
    def _minitab_target(cls, data: Any) -> Any:
        """A minimize goal given as Minitab writes it, ``target`` and ``upper``, and a
        maximize goal as ``lower`` and ``target``: the target is the limit where the goal is
        fully met, ``lower`` of a minimum and ``upper`` of a maximum, as the report and
        ``optimum.csv`` name it (a DoE review: ``target = -4`` with ``minimize`` read
        "goals #2.lower: required field is missing")."""
        if not isinstance(data, dict) or "target" not in data:
            return data
        met = {"min": "lower", "minimize": "lower", "max": "upper", "maximize": "upper"}.get(
            str(data.get("goal"))
        )
        if met is not None and met not in data:
            data = dict(data)
            data[met] = data.pop("target")
        return data

    @field_validator("goal", mode="before")
    @classmethod
    def _short_kind(cls, value: Any) -> Any:
        """``min`` and ``max``, as ``brakeca optimize --goal`` writes them (a black-box review
        saw them refused in a design file)."""
        return {"min": "minimize", "max": "maximize"}.get(value, value)

    @model_validator(mode="after")
    def _as_goal(self) -> GoalSpec:
        try:
            self.to_goal(scale=1.0)  # rsm.Goal's checks and messages, in the design's units
        except ValueError as exc:
            text = str(exc)
            if " (the arguments are lower, upper, target: Goal(" in text:
                # rsm.Goal's hint is in Python's argument order; a design file names its keys
                # (a fuzz review)
                text = text.split(" (the arguments are", 1)[0] + (
                    f" (lower, upper and target are the keys: lower = {self.lower:g}, upper = "
                    f"{self.target:g}, target = {self.upper:g} for {self.upper:g} between "
                    f"{self.lower:g} and {self.target:g})"
                )
            raise ValueError(text) from None
        return self

    def to_goal(self, scale: float | None = None) -> Any:
        """The :class:`brakeca.rsm.Goal` in the campaign's units (V in m^3): the limits
        divided by ``scale``, by default the response's factor in :data:`GOAL_RESPONSES`."""
        from brakeca.rsm import Goal

        if scale is None:
            scale = GOAL_RESPONSES[self.response][1]
        return Goal(
            self.response,
            self.goal,
            self.lower / scale,
            self.upper / scale,
            target=None if self.target is None else self.target / scale,
            weight=self.weight,
            importance=self.importance,
        )


class Design(_Frozen):
    """A design over one base configuration: a full factorial, a regular two-level
    fractional factorial (``generators``), a run table (``runs``) or a central composite
    design (``composite``).

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
        The factors, in design order; in a full factorial the first varies fastest.
    root_seed
        Root of every run's seed [-], see :func:`point_seed`.
    replicates
        Runs per test [-], each with its own seed.
    randomize_order
        Execute the runs in a permutation seeded by ``root_seed`` (test numbers unchanged).
    generators
        A regular two-level fractional factorial: ``"X = F1*F2*...*Fk"`` or
        ``"X = -F1*F2*...*Fk"`` each, making the factor ``X`` the (signed) product of the base
        factors ``Fi`` in coded units (``levels[0]`` is -1, ``levels[1]`` +1). At most
        :data:`MAX_GENERATORS`; the fraction's resolution must be III or more.
    runs
        A run table: one mapping per test from every factor's name to one of its levels
        [design unit] (a categorical factor's level number, or its choice's text); at least
        two rows, repeats allowed. Kept as the level values of ``levels``.
    runs_file
        The run table as a CSV file (header row: the factor names), relative to the design
        file; :func:`design_from_dict` reads it into ``runs`` and unsets it.
    foldover
        Names of two-level factors (or ``"all"``) whose other level a second half of the
        tests takes (a fraction or a run table only).
    composite
        A central composite design (:class:`Composite`) over 2 to 6 numeric factors of two
        levels each, low < high (its cube points; no labels, generators, run table or
        fold-over). Its tests are written out when the design is validated: each factor's
        ``levels`` become the levels used (low, centre and high, and with alpha above 1 the
        axial levels), its ``labels`` ``-α``, ``-``, ``0``, ``+``, ``+α``, its
        ``coded_range`` [low, high], and ``runs`` the tests (in Minitab's standard order);
        a design read back with its ``runs`` is checked against them.
    box_behnken
        A Box-Behnken design (:class:`BoxBehnken`) over 3 to 5 numeric factors of two levels
        each: written out as for ``composite``, with the levels low, centre and high.
    plackett_burman
        A Plackett-Burman screening design of this many tests (12, 20, 24, 28, 32, 36, 44
        or 48;
        :data:`PLACKETT_BURMAN`) over up to one factor fewer, each of two levels (the first
        coded -, the second +); written out as ``runs`` when the design is validated.
    goals
        What the report of a response-surface design optimizes (:class:`GoalSpec`, each
        response once): it then finds the factor setting that best meets them all.
    alpha_to_remove
        The report fits reduced models: backward elimination of the terms with p above this
        level [-], keeping the model hierarchical; for a response-surface design its surfaces
        (:func:`brakeca.rsm.backward_elimination`), for any other design the ANOVA model
        (:func:`brakeca.analysis.anova`), whose residuals, Box-Cox check and effects table
        follow it; by default the whole model.
    anova_type
        The report's ANOVA sums of squares: 2 (Type II, the default) or 3 (Type III,
        adjusted, as Minitab and JMP give them); they differ only in an unbalanced design,
        e.g. once a run has failed (:func:`brakeca.analysis.anova`).
    model_order
        The report's ANOVA model: its terms up through this many factors [-] (1 main
        effects, 2 main effects and two-factor interactions, 3 with the three-factor ones, as
        Minitab's "terms up through order"); by default 2, and main effects alone for a
        Plackett-Burman design. Not for a response-surface design, whose report fits a
        quadratic.
    model_terms
        The report's ANOVA model term by term instead of :attr:`model_order`, as Minitab's
        Terms dialog picks them: factor names, an interaction's joined by ``*`` or ``:``
        (``["S", "WP", "WR", "A", "WP*A"]``, or one string ``"S WP WR A WP*A"``); kept as
        the tables write them (``"WP:A"``, factors in design order), by number of factors
        (:func:`brakeca.analysis.canonical_terms`). Its residuals, Box-Cox check and effects
        table follow it. Not with ``model_order``, nor for a response-surface design.
    center_points
        Centre points [-] (0 to 100) added to a two-level design of numeric factors (a full
        factorial, a fraction, a Plackett-Burman design or a run table): tests with every
        factor at the middle of its levels (:meth:`center_levels`), after the other tests,
        each with its own seed. Their spread is pure error, and the analysis tests
        curvature: the centre points' mean against the other tests' (Minitab's "Ct Pt").
    """

    name: str = Field(min_length=1)
    description: str = ""
    base: str | None = None
    base_config: Path | None = None
    factors: tuple[Factor, ...] = Field(min_length=1)
    root_seed: int = Field(ge=0, lt=2**128)
    replicates: int = Field(1, ge=1, le=10_000)
    randomize_order: bool = False
    generators: tuple[str, ...] = ()
    runs: tuple[dict[str, int | float], ...] | None = None
    runs_file: Path | None = None
    foldover: tuple[str, ...] = ()
    composite: Composite | None = None
    box_behnken: BoxBehnken | None = None
    plackett_burman: int | None = None
    goals: tuple[GoalSpec, ...] = ()
    alpha_to_remove: float | None = Field(None, gt=0.0, lt=1.0)
    anova_type: Literal[2, 3] = 2
    center_points: int = Field(0, ge=0, le=100)
    model_order: int | None = Field(None, ge=1, le=10)
    model_terms: tuple[str, ...] | None = None

    #: the whole-number keys and what each takes, for the refusal of text and floats, which
    #: pydantic would take for whole numbers ("1" and 1.0 as 1)
    _WHOLE_NUMBERS: ClassVar[dict[str, tuple[str, int, int]]] = {
        "root_seed": ("a whole number, 0 <= root_seed < 2**128", 0, 2**128 - 1),
        "center_points": ("a whole number of centre points, 0 to 100", 0, 100),
        "model_order": ("the most factors in a model term, a whole number from 1 to 10", 1, 10),
        "anova_type": ("2 or 3 (a whole number)", 2, 3),
        # (text had been taken, "3" as 3, where root_seed's was refused: a fuzz review)
        "replicates": ("a whole number of replicates, 1 to 10000", 1, 10_000),
    }

    @field_validator("name", "description")
    @classmethod
    def _plain_text(cls, value: str, info: ValidationInfo) -> str:
        """No control character (a terminal's escape sequences printed as they are: a
        security review), but a description's line breaks and tabs."""
        problem = plain_text_problem(value, formula=False, lines=info.field_name == "description")
        if problem is not None:
            raise ValueError(problem)
        return value

    @field_validator(*_WHOLE_NUMBERS, mode="before")
    @classmethod
    def _whole_number(cls, value: Any, info: ValidationInfo) -> Any:
        """Text and floats are refused, and a number out of range gets the whole range."""
        expected, low, high = cls._WHOLE_NUMBERS[str(info.field_name)]
        if value is None and info.field_name == "model_order":
            return value
        out_of_range = (
            isinstance(value, int) and not isinstance(value, bool) and not low <= value <= high
        )
        if isinstance(value, str | float) or out_of_range:
            raise ValueError(f"expected {expected}, got {value!r}")
        return value

    @field_validator("model_terms", mode="before")
    @classmethod
    def _terms_line(cls, value: Any) -> Any:
        """One string of terms is split as ``brakeca analyze --terms`` splits it."""
        if isinstance(value, str):
            from brakeca.analysis import split_terms

            return tuple(split_terms(value))
        return value

    @field_validator("alpha_to_remove", mode="before")
    @classmethod
    def _a_level(cls, value: Any) -> Any:
        """alpha_to_remove is a number above 0 and below 1 (not text, which pydantic takes)."""
        from brakeca.analysis import alpha_problem

        problem = None if value is None else alpha_problem(value)
        if problem:
            raise ValueError(problem)
        return value

    @field_validator("foldover", mode="before")
    @classmethod
    def _fold_names(cls, value: Any, info: Any) -> Any:
        """``"all"`` stands for every two-level factor (expanded here, so the written design
        names them)."""
        if value == "all":
            factors = info.data.get("factors") or ()
            return tuple(f.name for f in factors if len(f.levels) == 2)
        if isinstance(value, str):
            raise ValueError(
                f"expected a list of factor names or 'all', got {value!r}; e.g. "
                f"foldover = [{value!r}]"
            )
        return value

    @model_validator(mode="before")
    @classmethod
    def _standard_fraction(cls, data: Any) -> Any:
        """``fraction_runs = 16``: the standard fraction of that many tests over the two-level
        factors (:data:`STANDARD_FRACTIONS`), written out as its ``generators``."""
        if not isinstance(data, Mapping) or "fraction_runs" not in data:
            return data
        data = dict(data)
        runs = data.pop("fraction_runs")
        if data.get("generators") or data.get("runs") is not None or data.get("runs_file"):
            raise ValueError(
                "fraction_runs: give the number of runs of a standard fraction, or generators, "
                "or a run table, not two of them"
            )
        if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
            raise ValueError(f"fraction_runs: expected a whole number of runs, got {runs!r}")
        factors = data.get("factors")
        if isinstance(factors, str | bytes) or not isinstance(factors, Sequence):
            return data  # the factors' own error follows
        names = [
            f["name"]
            for f in factors
            if isinstance(f, Mapping)
            and isinstance(f.get("levels"), Sequence)
            and len(f["levels"]) == 2
        ]
        data["generators"] = list(standard_generators(names, runs))
        return data

    @model_validator(mode="before")
    @classmethod
    def _run_values(cls, data: Any) -> Any:
        """Check the run table's shape and turn a categorical factor's choice (or label)
        into its level number; the levels themselves are checked by :meth:`_consistent`."""
        if not isinstance(data, Mapping) or data.get("runs") is None:
            return data
        runs = data["runs"]
        if isinstance(runs, str | bytes | Mapping) or not isinstance(runs, Sequence):
            raise ValueError(
                "runs: expected a list of tables, one per run, each {factor = level, ...}, "
                f"got {runs!r}"
            )
        texts = _raw_choices(data.get("factors"))
        known = _raw_factor_names(data.get("factors"))
        rows = []
        for r, row in enumerate(runs):
            if not isinstance(row, Mapping):
                raise ValueError(
                    f"{item_path(('runs', r))}: "
                    f"expected a table {{factor = level, ...}}, got {row!r}"
                )
            values: dict[str, Any] = {}
            for name, value in row.items():
                key = item_path(("runs", r, name))
                if known is not None and name not in known:
                    raise ValueError(
                        f"{key}: unknown factor {name!r} (factors: {', '.join(known)})"
                    )
                if isinstance(value, str) and name in texts and value.strip() in texts[name]:
                    value = texts[name][value.strip()]
                elif isinstance(value, bool) or not isinstance(value, int | float):
                    kind = "a level number or a choice" if name in texts else "a number"
                    raise ValueError(f"{key}: expected {kind} (a level), got {value!r}")
                elif not math.isfinite(value):
                    raise ValueError(f"{key}: expected a finite number (a level), got {value!r}")
                values[name] = value
            rows.append(values)
        return {**data, "runs": rows}

    @model_validator(mode="before")
    @classmethod
    def _plackett_burman_runs(cls, data: Any) -> Any:
        """``plackett_burman = 12``: write the screening design's tests out as ``runs``
        (unless they are there already; :meth:`_check_plackett_burman` checks them then)."""
        if not isinstance(data, Mapping) or data.get("plackett_burman") is None:
            return data
        runs = data["plackett_burman"]
        if isinstance(runs, bool) or not isinstance(runs, int) or runs not in PLACKETT_BURMAN:
            raise ValueError(
                f"plackett_burman: expected the number of tests, one of "
                f"{', '.join(map(str, PLACKETT_BURMAN))}, got {runs!r} (for 8 or 16 tests "
                "take a fractional factorial: fraction_runs)"
            )
        for key in ("fraction_runs", "generators", "runs_file", "composite", "box_behnken"):
            if data.get(key) not in (None, "", (), []):
                raise ValueError(
                    f"plackett_burman, {key}: a Plackett-Burman design makes its own tests; "
                    "remove one of them"
                )
        factors = data.get("factors")
        if data.get("runs") is not None or not isinstance(factors, list | tuple):
            return data
        if not 2 <= len(factors) <= runs - 1:
            raise ValueError(
                f"plackett_burman: a design of {runs} tests takes 2 to {runs - 1} factors, got "
                f"{len(factors)}"
            )
        levels = []
        for i, f in enumerate(factors):
            if isinstance(f, Factor):
                f = f.model_dump(exclude_none=True)
            if not isinstance(f, Mapping) or not isinstance(f.get("levels"), list | tuple):
                return data  # the factor's own error follows
            if len(f["levels"]) != 2:
                raise ValueError(
                    f"{item_path(('factors', i, 'levels'))}: "
                    f"factor {f.get('name')!r}: a Plackett-Burman design "
                    f"takes two levels per factor, got {list(f['levels'])}"
                )
            levels.append((f.get("name"), f["levels"]))
        tests = [
            {name: pair[(sign + 1) // 2] for (name, pair), sign in zip(levels, signs, strict=True)}
            for signs in _plackett_burman_signs(runs, len(levels))
        ]
        return {**data, "runs": tests}

    @model_validator(mode="before")
    @classmethod
    def _composite_runs(cls, data: Any) -> Any:
        """``composite`` or ``box_behnken``: write the response-surface design's tests out as
        ``runs`` and each factor's levels, labels and coded range (unless ``runs`` is there
        already, as in a design written by :meth:`to_toml`; :meth:`_check_composite` checks
        it then)."""
        if not isinstance(data, Mapping):
            return data
        given = [m for m in (Composite, BoxBehnken) if data.get(m.key) is not None]
        if not given:
            return data
        if len(given) > 1:
            raise ValueError(
                "composite, box_behnken: a design is a central composite design or a "
                "Box-Behnken design, not both; remove one of them"
            )
        model = given[0]
        title = model.title
        others = {
            "fraction_runs": "a fractional factorial (fraction_runs)",
            "generators": "a fractional factorial (generators)",
            "runs_file": "a run table read from a file (runs_file)",
            "foldover": "folded over (its centre points have no other level)",
        }
        for key, what in others.items():
            if key in data and data[key] not in (None, "", (), []):
                raise ValueError(
                    f"{model.key}, {key}: a {title} ({model.key}) makes its own tests, so it "
                    f"cannot also be {what}; remove one of them"
                )
        raw = data[model.key]
        try:
            surface = raw if isinstance(raw, model) else model.model_validate(raw)
        except ValidationError:
            return data  # the field's own error follows
        factors = data.get("factors")
        if data.get("runs") is not None or not isinstance(factors, list | tuple):
            return data
        low_k, high_k = model.factor_range
        if not low_k <= len(factors) <= high_k:
            raise ValueError(
                f"{model.key}: a {title} takes {low_k} to {high_k} factors, got {len(factors)}"
            )
        specs: list[tuple[str, float, float, str]] = []
        tables: list[dict[str, Any]] = []
        for i, f in enumerate(factors):
            if isinstance(f, Factor):
                f = f.model_dump(exclude_none=True)
            if not isinstance(f, Mapping) or not isinstance(f.get("name"), str):
                return data  # the factor's own error follows
            key, name = item_path(("factors", i)), f["name"]
            if f.get("choices") is not None or f.get("field") == "cycle":
                raise ValueError(
                    f"{key}.choices: factor {name!r} is categorical; a {title} takes numeric "
                    "factors only (its centre points lie between the levels)"
                )
            levels = f.get("levels")
            if not isinstance(levels, list | tuple) or not all(map(_finite_number, levels)):
                return data  # the levels' own error follows
            if len(levels) != 2 or not levels[0] < levels[1]:
                raise ValueError(
                    f"{key}.levels: factor {name!r}: a {title} takes exactly two levels per "
                    "factor, [low, high] with low < high (coded -1 and +1; it adds the "
                    f"others), got {list(levels)}"
                )
            low, high = levels
            if f.get("labels") is not None:
                raise ValueError(
                    f"{key}.labels: factor {name!r}: a {title} labels its levels itself (-, "
                    "0, + and -α, +α); remove labels"
                )
            coded_range = f.get("coded_range")
            if coded_range is not None and (
                not isinstance(coded_range, list | tuple) or list(coded_range) != [low, high]
            ):
                raise ValueError(
                    f"{key}.coded_range: factor {name!r}: a {title} codes its levels [low, "
                    f"high] = {[low, high]} as -1 and +1; remove coded_range"
                )
            coding = f.get("coding", "linear")
            if coding not in ("linear", "log") or (coding == "log" and low <= 0):
                return data  # the factor's own error follows
            specs.append((name, low, high, coding))
            tables.append(dict(f))
        levels_of, labels_of, tests = surface.table(specs)
        rewritten = [
            {**f, "levels": levels, "labels": labels, "coded_range": [low, high]}
            for f, levels, labels, (_, low, high, _) in zip(
                tables, levels_of, labels_of, specs, strict=True
            )
        ]
        return {**data, "factors": rewritten, "runs": tests}

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
                    f"{item_path(('factors', i, 'name'))}: duplicate factor name {factor.name!r} "
                    f"(also {item_path(('factors', seen[factor.name]))})"
                )
            seen[factor.name] = i
            target = _target(factor.field)
            if target in fields:
                raise ValueError(
                    f"{item_path(('factors', i, 'field'))}: "
                    f"factors {fields[target]!r} and {factor.name!r} "
                    f"both set {target!r}"
                )
            fields[target] = factor.name
        table = self.runs is not None or self.runs_file is not None
        if self.runs is not None and self.runs_file is not None:
            raise ValueError(
                "runs, runs_file: give the run table inline (runs) or as a CSV file "
                "(runs_file), not both"
            )
        if self.generators and table:
            key = "runs" if self.runs is not None else "runs_file"
            raise ValueError(
                f"generators, {key}: a design is a fractional factorial (generators) or a run "
                f"table ({key}), not both"
            )
        if self.generators:
            parsed = _parse_generators(self.generators, self.factors)
            _check_resolution(parsed, self.factor_names)
        if self.foldover:
            self._check_foldover(table)
        if self.runs is not None:
            object.__setattr__(self, "runs", self._checked_runs(self.runs))
        if self.composite is not None and self.box_behnken is not None:
            raise ValueError(
                "composite, box_behnken: a design is a central composite design or a "
                "Box-Behnken design, not both; remove one of them"
            )
        if self.surface_design is not None:
            self._check_composite()
        if self.plackett_burman is not None:
            self._check_plackett_burman()
        if self.center_points:
            self._check_center_points()
        if self.model_order is not None and self.surface_design is not None:
            raise ValueError(
                f"model_order: a {self.surface_design.title}'s report fits a quadratic "
                "surface, not a factorial model of some order; remove model_order"
            )
        if self.model_terms is not None:
            self._check_model_terms()
        if self.goals:
            if self.surface_design is None:
                raise ValueError(
                    "goals: the report optimizes goals on the response surface of a "
                    "central composite or Box-Behnken design; for another design, use "
                    "'brakeca optimize FOLDER --goal ...' on its campaign"
                )
            named = [g.response for g in self.goals]
            for i, name in enumerate(named):
                if name in named[:i]:
                    raise ValueError(
                        f"{item_path(('goals', i, 'response'))}: {name!r} has a goal already"
                    )
        if self.runs is not None or self.runs_file is None:
            n_runs = self.n_tests * self.replicates
            if n_runs > _MAX_RUNS:
                key = "runs" if self.runs is not None else "factors"
                raise ValueError(f"{key}: the design has {n_runs} runs, more than 1,000,000")
        return self

    def _check_plackett_burman(self) -> None:
        """Check a Plackett-Burman design's run table against the tests it makes (a design
        read back with its ``runs``, perhaps edited by hand)."""
        assert self.plackett_burman is not None
        k = len(self.factors)
        expected = _plackett_burman_signs(self.plackett_burman, k)
        runs = self.runs or ()
        if self.plackett_burman in (12, 20, 24, 44, 48) and _signs_of(
            runs, self.factors
        ) == _plackett_burman_signs_by_rows(self.plackett_burman, k):
            return  # a design written by an earlier brakeca, in its order
        if len(runs) != len(expected):
            raise ValueError(
                f"runs: the Plackett-Burman design has {len(expected)} tests, the run table "
                f"{len(runs)}; remove runs to make them again"
            )
        for r, (row, signs) in enumerate(zip(runs, expected, strict=True)):
            for f, sign in zip(self.factors, signs, strict=True):
                if len(f.levels) != 2 or row[f.name] != f.levels[(sign + 1) // 2]:
                    raise ValueError(
                        f"{item_path(('runs', r, f.name))}: "
                        f"test {r + 1} of the Plackett-Burman design has "
                        f"{f.name} at its {'+' if sign > 0 else '-'} level; remove runs to "
                        "make the tests again"
                    )

    def _check_center_points(self) -> None:
        """Centre points need a two-level design of numeric factors (each has a centre)."""
        if self.surface_design is not None:
            key = self.surface_design.key
            raise ValueError(
                f"center_points: a {self.surface_design.title} has its own centre points; "
                f"give their number as {key}.center and remove center_points"
            )
        for i, f in enumerate(self.factors):
            if f.categorical:
                raise ValueError(
                    f"{item_path(('factors', i))}: "
                    f"factor {f.name!r} is categorical; centre points need "
                    "numeric factors only (every factor at the middle of its two levels)"
                )
            if len(f.levels) != 2:
                raise ValueError(
                    f"{item_path(('factors', i, 'levels'))}: "
                    f"factor {f.name!r} has {len(f.levels)} levels; "
                    "centre points need two-level factors (a centre between low and high), "
                    f"got {list(f.levels)}"
                )

    def center_levels(self) -> dict[str, int | float]:
        """The centre point's level of every factor [design unit]: the middle of its two
        levels (their geometric mean with ``coding = "log"``, whatever its ``coded_range``;
        an int where both levels are
        ints and the middle is whole, so that integer fields stay integers).

        Raises
        ------
        ValueError
            The design has no centre points (:attr:`center_points` is 0).
        """
        if not self.center_points:
            raise ValueError(f"design {self.name}: no centre points (center_points = 0)")
        out: dict[str, int | float] = {}
        for f in self.factors:
            value = _decode(float(min(f.levels)), float(max(f.levels)), f.coding, 0.0)
            whole = all(isinstance(v, int) for v in f.levels) and float(value).is_integer()
            out[f.name] = int(value) if whole else value
        return out

    def _check_composite(self) -> None:
        """Check a central composite design's factors and tests against those its
        ``composite`` and the factors' ``coded_range`` give (a design read back with its
        ``runs``, perhaps edited by hand).

        Raises
        ------
        ValueError
            A categorical factor, one without ``coded_range``, levels or tests other than
            the design's; the message names the field.
        """
        surface = self.surface_design
        assert surface is not None
        low_k, high_k = surface.factor_range
        k = len(self.factors)
        if not low_k <= k <= high_k:
            raise ValueError(
                f"{surface.key}: a {surface.title} takes {low_k} to {high_k} factors, got {k}"
            )
        specs: list[tuple[str, float, float, str]] = []
        for i, f in enumerate(self.factors):
            if f.categorical:
                raise ValueError(
                    f"{item_path(('factors', i, 'choices'))}: factor {f.name!r} is categorical; a "
                    f"{surface.title} takes numeric factors only"
                )
            if f.coded_range is None:
                raise ValueError(
                    f"{item_path(('factors', i, 'coded_range'))}: "
                    f"factor {f.name!r}: a {surface.title} given "
                    "with its runs needs each factor's coded_range [low, high] (the levels coded "
                    "-1 and +1); or remove runs to make the tests from the two levels"
                )
            specs.append((f.name, *f.coded_range, f.coding))
        levels_of, _, tests = surface.table(specs)
        what = f"the {surface.title} ({surface.describe(k)})"
        for i, (f, levels) in enumerate(zip(self.factors, levels_of, strict=True)):
            if len(f.levels) != len(levels) or not all(
                math.isclose(a, b, rel_tol=1e-9) for a, b in zip(f.levels, levels, strict=False)
            ):
                raise ValueError(
                    f"{item_path(('factors', i, 'levels'))}: "
                    f"factor {f.name!r}: {what} has the levels {levels} "
                    f"(from its coded_range), got {list(f.levels)}"
                )
        runs = self.runs or ()
        if len(runs) != len(tests):
            raise ValueError(
                f"runs: {what} has {len(tests)} tests, the run table {len(runs)}; remove runs "
                "to make them again"
            )
        for r, (row, test) in enumerate(zip(runs, tests, strict=True)):
            for name, value in test.items():
                if not math.isclose(row[name], value, rel_tol=1e-9):
                    raise ValueError(
                        f"{item_path(('runs', r, name))}: "
                        f"test {r + 1} of {what} has {name} = {value!r}, the "
                        f"run table {row[name]!r}; remove runs to make the tests again"
                    )

    def _check_foldover(self, table: bool) -> None:
        """Refuse a fold-over of a full factorial, of an unknown, repeated or not two-level
        factor, or one that gives the fraction's own tests back."""
        if not self.generators and not table:
            raise ValueError(
                "foldover: a full factorial folded over repeats its own tests; fold a fraction "
                "(generators) or a run table, or give the design replicates"
            )
        names = self.factor_names
        for k, name in enumerate(self.foldover):
            if name not in names:
                raise ValueError(
                    f"foldover.{k}: unknown factor {name!r} (factors: {', '.join(names)})"
                )
            if self.foldover.index(name) != k:
                raise ValueError(f"foldover.{k}: factor {name!r} is named twice")
            levels = len(self.factor(name).levels)
            if levels != 2:
                raise ValueError(
                    f"foldover.{k}: factor {name!r} has {levels} levels; a fold-over switches "
                    "a two-level factor to its other level"
                )
        if self.generators and len(self._folded_words()) == 2 ** len(self.generators) - 1:
            folded = ", ".join(self.foldover)
            raise ValueError(
                f"foldover: folding on {folded} gives the fraction's own tests back: every word "
                "of its defining relation holds an even number of these factors (a fraction "
                "whose words all have an even length, folded on all its factors, is itself); "
                "fold on fewer factors"
            )

    def _folded_words(self) -> list[_Word]:
        """The words of the defining relation that survive the fold-over: those holding an
        even number of the folded factors (the others change sign in the folded half)."""
        words = list(_defining_words(self._parsed_generators(), self.factor_names))
        if not self.foldover:
            return words
        fold = self._fold_mask()
        return [w for w in words if (w.mask & fold).bit_count() % 2 == 0]

    def _fold_mask(self) -> int:
        """The folded factors as bits, one per factor in design order (0 without a
        fold-over)."""
        return sum(1 << self.factor_names.index(n) for n in self.foldover)

    @property
    def generators_folded_away(self) -> tuple[str, ...]:
        """The generated factors whose generator no longer holds after the fold-over (its
        word holds an odd number of the folded factors, whose signs the folded half
        reverses), in the generators' order; none without a fold-over."""
        parsed = self._parsed_generators()
        masks = _generator_masks(parsed, self.factor_names)
        fold = self._fold_mask()
        return tuple(
            g.target for g, (_, m) in zip(parsed, masks, strict=True) if (m & fold).bit_count() % 2
        )

    def _checked_runs(
        self, runs: Sequence[Mapping[str, int | float]]
    ) -> tuple[dict[str, int | float], ...]:
        """The run table with each value replaced by its level in ``levels``, in design order.

        Raises
        ------
        ValueError
            Fewer than two runs, an unknown or missing factor, a value that is no level;
            the message starts with ``runs.<row>.<factor>``.
        """
        if len(runs) < 2:
            raise ValueError(f"runs: a run table needs at least 2 runs, got {len(runs)}")
        names = self.factor_names
        checked = []
        for r, row in enumerate(runs):
            for name in row:
                if name not in names:
                    raise ValueError(
                        f"{item_path(('runs', r, name))}: unknown factor {name!r} "
                        f"(factors: {', '.join(names)})"
                    )
            levels: dict[str, int | float] = {}
            for factor in self.factors:
                key = item_path(("runs", r, factor.name))
                if factor.name not in row:
                    raise ValueError(
                        f"{key}: missing: each run gives every factor one of its levels "
                        f"({_levels_text(factor)})"
                    )
                level = _match_level(factor, row[factor.name])
                if level is None:
                    raise _not_a_level(key, factor, row[factor.name])
                levels[factor.name] = level
            checked.append(levels)
        return tuple(checked)

    # --- derived ---------------------------------------------------------------------------
    @property
    def factor_names(self) -> tuple[str, ...]:
        """Factor names in design order."""
        return tuple(f.name for f in self.factors)

    @property
    def is_fractional(self) -> bool:
        """Whether the design is a two-level fractional factorial (it has generators)."""
        return bool(self.generators)

    @property
    def is_run_table(self) -> bool:
        """Whether the design is a run table (``runs`` or ``runs_file``; a central composite
        design is one too, its tests written out as ``runs``)."""
        return self.runs is not None or self.runs_file is not None

    @property
    def is_composite(self) -> bool:
        """Whether the design is a central composite design (``composite``)."""
        return self.composite is not None

    @property
    def surface_design(self) -> Composite | BoxBehnken | None:
        """The response-surface design (``composite`` or ``box_behnken``), or None."""
        return self.composite if self.composite is not None else self.box_behnken

    @property
    def is_response_surface(self) -> bool:
        """Whether the design is a response-surface design: a central composite or a
        Box-Behnken design, whose analysis fits a quadratic surface (:mod:`brakeca.rsm`)."""
        return self.surface_design is not None

    def _check_model_terms(self) -> None:
        """``model_terms`` name the design's factors, alone (not with ``model_order``), for a
        design whose report fits a factorial model; kept as the tables write them."""
        from brakeca.analysis import canonical_terms

        if self.surface_design is not None:
            raise ValueError(
                f"model_terms: a {self.surface_design.title}'s report fits a quadratic "
                "surface, not a factorial model of chosen terms; remove model_terms"
            )
        if self.model_order is not None:
            raise ValueError(
                "model_terms, model_order: give one of them (the terms one by one, or every "
                "term up through an order), not both"
            )
        assert self.model_terms is not None
        terms = canonical_terms(self.model_terms, self.factor_names)
        object.__setattr__(self, "model_terms", tuple(terms))

    @property
    def anova_model(self) -> int | tuple[str, ...]:
        """The report's ANOVA model, as :func:`brakeca.analysis.anova` takes it
        (``interactions``): :attr:`model_terms` where given, else :attr:`anova_order`."""
        return self.model_terms if self.model_terms is not None else self.anova_order

    @property
    def anova_order(self) -> int:
        """The most factors in a term of the report's ANOVA model [-]: :attr:`model_order`,
        else 1 for a Plackett-Burman design (its main effects alone), else 2."""
        if self.model_order is not None:
            return self.model_order
        return 1 if self.plackett_burman is not None else 2

    def _parsed_generators(self) -> tuple[_Generator, ...]:
        return _parse_generators(self.generators, self.factors) if self.generators else ()

    @property
    def generated_factors(self) -> tuple[str, ...]:
        """Names of the factors the generators generate, in design order (none unless the
        design is a fraction)."""
        generated = {g.target for g in self._parsed_generators()}
        return tuple(n for n in self.factor_names if n in generated)

    def defining_relation(self) -> list[tuple[int, tuple[str, ...]]]:
        """The defining relation of a fractional factorial: every word ``I = sign * F1*...``.

        Returns
        -------
        list of (int, tuple of str)
            The ``2^p - 1`` words of ``p`` generators (each generator's word ``X*F1*...*Fk``
            and all their products, factors that appear twice cancelling), as (sign, +1 or
            -1; factor names in design order), ordered by length, then by the factors'
            design order. Empty unless the design is a fraction. With a fold-over, the words
            holding an even number of the folded factors: the others are what the fold-over
            resolves (and none left: the two-level factors form a full factorial).
        """
        names = self.factor_names
        words = self._folded_words()
        words.sort(key=lambda w: (w.mask.bit_count(), _word_key(w.mask, len(names))))
        return [(w.sign, tuple(names[k] for k in _word_key(w.mask, len(names)))) for w in words]

    def relation_text(self, *, times: str = "*", most: int = 15) -> str:
        """The defining relation as text, ``"I = A*B*C*D = ..."``: its shortest ``most`` words,
        then how many more (the whole relation of ``p`` generators has ``2^p - 1`` words; of
        more than :data:`_MAX_LISTED_GENERATORS` generators only the count is given). Empty
        unless the design is a fraction.

        Parameters
        ----------
        times
            The product sign between factors (``"·"`` in the report).
        most
            The most words written [-].
        """
        p = len(self.generators)
        if p == 0:
            return ""
        if p > _MAX_LISTED_GENERATORS:
            return f"I = ... ({2**p - 1:,} words before any fold-over)"
        n_words = len(self._folded_words())
        if n_words == 0:
            return "I (no words: a full factorial of the two-level factors)"
        words = [
            ("-" if sign < 0 else "") + times.join(word)
            for sign, word in self.defining_relation()[:most]
        ]
        more = f" = ... ({n_words:,} words in all)" if n_words > most else ""
        return "I = " + " = ".join(words) + more

    @property
    def resolution(self) -> int | None:
        """The resolution of a fractional factorial: the length of the shortest word of its
        defining relation [-] (III: main effects aliased with two-factor interactions; IV:
        with three-factor ones, two-factor interactions with each other; V: two-factor
        interactions clear of each other). None unless the design is a fraction."""
        parsed = self._parsed_generators()
        if not parsed:
            return None
        if self.foldover:
            lengths = [w.mask.bit_count() for w in self._folded_words()]
            return min(lengths) if lengths else None  # none: a full factorial
        return _shortest_word(parsed, self.factor_names).mask.bit_count()

    def __repr__(self) -> str:
        """One line: name, kind, factors, tests and replicates, root seed (``to_toml()``
        gives the whole design)."""
        try:
            tests = f"{self.n_tests} tests"
        except ConfigError:  # a runs_file not yet read
            tests = "tests from its runs_file"
        return (
            f"Design({self.name!r}: {self.kind}; factors {', '.join(self.factor_names)}; "
            f"{tests} x {self.replicates} replicate{'' if self.replicates == 1 else 's'}; "
            f"root_seed {self.root_seed})"
        )

    def __str__(self) -> str:
        return repr(self)

    @property
    def kind(self) -> str:
        """The kind of design, for reports (:meth:`_cube_kind`), with its centre points:
        e.g. ``"full factorial, plus 4 centre points"``."""
        if self.center_points:
            return f"{self._cube_kind}, plus {_points(self.center_points, 'centre point')}"
        return self._cube_kind

    @property
    def _cube_kind(self) -> str:
        """The kind of design, for reports: ``"full factorial"``, ``"run table"`` or e.g.
        ``"2^(7-4) fractional factorial, resolution III"`` (with factors of other than two
        levels crossed: ``"fractional factorial (2^(4-1) in the two-level factors × 3
        levels of WP), resolution IV"``; a central composite design:
        ``"central composite design (face-centred, α = 1), 3 factors: 8 cube, 6 axial and 3
        centre points"``)."""
        if self.surface_design is not None:
            return self.surface_design.kind(len(self.factors))
        folded = f" folded over on {', '.join(self.foldover)}" if self.foldover else ""
        if self.plackett_burman is not None:
            # folded on one factor, its main effect is clear of every two-factor
            # interaction and the others' still partly confounded with those of the unfolded
            # factors; on several, each stays confounded with some (a growth review: a
            # fold-over on S was said to leave main effects clear of each other only)
            unfolded = [f.name for f in self.factors if f.name not in self.foldover]
            head = (
                f"Plackett-Burman design, {self.plackett_burman} tests, {len(self.factors)} "
                f"factors{folded} (main effects clear of each other"
            )
            if self.foldover and not unfolded:
                return head + " and of the two-factor interactions)"
            if self.plackett_burman == 32:
                return head + "; a regular fraction, see the alias structure)"
            if len(self.foldover) == 1:
                return (
                    f"{head}; {self.foldover[0]} clear of the two-factor interactions, each "
                    "other partly confounded with those of the unfolded factors)"
                )
            if self.foldover:  # (a reversed column's products with a reversed one's stay)
                return (
                    f"{head}, each partly confounded with some two-factor interactions: a "
                    "folded factor with those of a folded and an unfolded factor, an unfolded "
                    "one with those of two folded or two unfolded factors)"
                )
            return head + ", each partly confounded with the two-factor interactions of the others)"
        if self.is_run_table:
            return f"run table{folded}"
        if not self.generators:
            return "full factorial"
        two = sum(1 for f in self.factors if len(f.levels) == 2)
        fraction = f"2^({two}-{len(self.generators)})"
        if self.resolution is None:  # a fold-over that resolved every word
            resolution = "a full factorial of its two-level factors"
        else:
            resolution = f"resolution {_roman(self.resolution)}"
        others = [f for f in self.factors if len(f.levels) != 2]
        if not others:
            return f"{fraction} fractional factorial{folded}, {resolution}"
        crossed = " × ".join(f"{len(f.levels)} levels of {f.name}" for f in others)
        return (
            f"fractional factorial ({fraction} in the two-level factors × {crossed}){folded}, "
            f"{resolution}"
        )

    @property
    def n_tests(self) -> int:
        """Number of tests [-]: factor-level combinations of a full factorial, of the base
        factors of a fraction, or rows of a run table (twice as many folded over), and the
        centre points.

        Raises
        ------
        ConfigError
            A run table given as ``runs_file`` and not yet read (see :func:`design_from_dict`).
        """
        fold = 2 if self.foldover else 1
        if self.runs is not None:
            return fold * len(self.runs) + self.center_points
        self._require_runs()
        generated = set(self.generated_factors)
        cube = math.prod(len(f.levels) for f in self.factors if f.name not in generated)
        return fold * cube + self.center_points

    def _require_runs(self) -> None:
        if self.runs_file is not None and self.runs is None:
            raise ConfigError(
                f"design {self.name}: runs_file {str(self.runs_file)!r} is not read yet; load "
                "the design with load_design or design_from_dict"
            )

    def factor(self, name: str) -> Factor:
        """The factor called ``name``."""
        for f in self.factors:
            if f.name == name:
                return f
        raise KeyError(name)

    def levels_without_runs(self) -> dict[str, list[int | float]]:
        """Each factor's levels that no test of a run table sets (a run table may leave a
        level of ``levels`` out): ``{factor name: [level, ...]}``, only the factors with such
        levels; empty for the other designs, whose tests hold every level."""
        if self.runs is None:
            return {}
        used: dict[str, set[int | float]] = {f.name: set() for f in self.factors}
        for combo in self.combinations():
            for name, value in combo.items():
                used[name].add(value)
        out = {f.name: [v for v in f.levels if v not in used[f.name]] for f in self.factors}
        return {name: levels for name, levels in out.items() if levels}

    def combinations(self) -> list[dict[str, int | float]]:
        """The tests' factor levels, in test order.

        Returns
        -------
        list of dict of str to int or float
            One per test, factor name to level [design unit], every factor in design order.
            A full factorial: every combination, the first factor varying fastest. A
            fraction: the full factorial of the factors no generator generates (in design
            order, the first of them fastest), each generated factor at the level its
            generator gives. A run table: its rows. Folded over: then the same tests with
            the folded factors at their other level. Then the centre points, each factor at
            :meth:`center_levels`.

        Raises
        ------
        ConfigError
            A run table given as ``runs_file`` and not yet read.
        """
        if self.runs is not None:
            return self._folded([{f.name: row[f.name] for f in self.factors} for row in self.runs])
        self._require_runs()
        return self._folded(self._factorial())

    def _factorial(self) -> list[dict[str, int | float]]:
        """The tests of a full factorial or a regular fraction (:meth:`combinations`)."""
        parsed = self._parsed_generators()
        generated = {g.target for g in parsed}
        base = [f for f in self.factors if f.name not in generated]
        index = {f.name: k for k, f in enumerate(base)}
        target_levels = {g.target: self.factor(g.target).levels for g in parsed}
        names = self.factor_names
        combos: list[dict[str, int | float]] = []
        for reversed_combo in itertools.product(*[range(len(f.levels)) for f in reversed(base)]):
            chosen = reversed_combo[::-1]  # level index of each base factor
            levels = {f.name: f.levels[k] for f, k in zip(base, chosen, strict=True)}
            for g in parsed:
                coded = g.sign * math.prod(2 * chosen[index[n]] - 1 for n in g.word)
                levels[g.target] = target_levels[g.target][(coded + 1) // 2]
            combos.append({n: levels[n] for n in names})
        return combos

    def _folded(self, combos: list[dict[str, int | float]]) -> list[dict[str, int | float]]:
        """``combos`` followed, with a fold-over, by the same tests with each folded factor
        at its other level, then the centre points (:attr:`center_points`)."""
        if self.center_points:
            centre = self.center_levels()
            combos = self._folded_only(combos)
            return combos + [dict(centre) for _ in range(self.center_points)]
        return self._folded_only(combos)

    def _folded_only(self, combos: list[dict[str, int | float]]) -> list[dict[str, int | float]]:
        if not self.foldover:
            return combos
        other: dict[str, dict[int | float, int | float]] = {}  # a level -> the other level
        for name in self.foldover:
            low, high = self.factor(name).levels
            other[name] = {low: high, high: low}
        mirrored = [
            {n: other[n][v] if n in other else v for n, v in combo.items()} for combo in combos
        ]
        return combos + mirrored

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
        if quick:
            check_quick_overrides(updates)
            for target, name in varied.items():
                if target in QUICK_FIELDS:
                    raise ConfigError(
                        f"quick (--quick): the design's factor {name!r} sets {target}, which "
                        f"--quick sets itself (mesh.n_radial = {QUICK_N_RADIAL}, "
                        "mesh.inner_radius unset) to narrow the band; run the design without "
                        "--quick, or leave the factor out"
                    )
        if max_stops is not None and "cycle.max_stops" in varied:
            raise ConfigError(
                f"max_stops (--stops): the design's factor {varied['cycle.max_stops']!r} sets "
                "cycle.max_stops in every run, so --stops would be ignored; remove one of them"
            )
        if max_stops is not None:
            if (
                isinstance(max_stops, bool | np.bool_)
                or not isinstance(max_stops, numbers.Integral)
                or max_stops < 1
            ):
                raise ConfigError(
                    f"max_stops: expected a whole number of stops from 1, got {max_stops!r}"
                )
            if "cycle.max_stops" in updates:
                raise ConfigError(
                    "max_stops and the override cycle.max_stops both set it; give one of them"
                )
            updates["cycle.max_stops"] = int(max_stops)
        if updates:
            config = config.with_updates(updates)
        if quick:
            config = quick_config(config)
        return config

    def _level_error(
        self,
        factor: Factor,
        value: int | float,
        exc: ConfigError,
        source: str | None,
        applied: Mapping[str, int | float] | None = None,
    ) -> ConfigError:
        """The error of ``factor``'s level ``value``, which ``exc`` refused; ``applied`` are
        the levels of the run's factors set before it (a level valid alone may not be with
        them)."""
        where = source or f"design {self.name}"
        index = self.factor_names.index(factor.name)
        detail = str(exc).replace("\n", "; ")
        if self.composite is not None and factor.coded_range is not None:
            low, high = factor.coded_range
            if not low <= value <= high:
                alpha = self.composite.alpha_value(len(self.factors))
                detail += (
                    f"; it is an axial level of the central composite design (alpha = "
                    f"{alpha:.4g}): choose a smaller alpha ('face' keeps every level within "
                    "[low, high]) or narrower levels"
                )
        if self.center_points and value not in factor.levels:
            return ConfigError(
                f"{where}: center_points: factor {factor.name!r} (field {factor.field}): its "
                f"centre point, {value!r} [{factor.unit}] midway between its levels "
                f"{list(factor.levels)}, is not valid: {detail}; give levels whose middle the "
                "field takes, or remove center_points"
            )
        shown = self._level_text(factor, value)
        if applied:
            shown += " with " + ", ".join(
                f"{name} = {self._level_text(self.factor(name), v)}" for name, v in applied.items()
            )
        # a categorical factor's level refused alone is its choice: the mistake is in choices
        # (a user's review: the message had pointed at levels); a combination stays levels
        key = (
            "choices"
            if factor.choices is not None and value in factor.levels and not applied
            else "levels"
        )
        return ConfigError(
            f"{where}: {item_path(('factors', index, key))}: factor {factor.name!r} "
            f"(field {factor.field}): {'choice' if key == 'choices' else 'level'} {shown} is "
            f"not valid: {detail}"
        )

    @staticmethod
    def _level_text(factor: Factor, value: int | float) -> str:
        """A level as a message shows it: a categorical factor's choice (``'lazy'``), or the
        value with its unit (``150 [%]``; no brackets without a unit)."""
        if factor.choices is not None and value in factor.levels:
            return repr(factor.choices[factor.levels.index(value)])
        return f"{value!r} [{factor.unit}]" if factor.unit else repr(value)

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
        applied: dict[str, int | float] = {}
        for factor in self.factors:
            value = levels[factor.name]
            try:
                config = factor.apply(config, value)
            except ConfigError as exc:
                raise self._level_error(factor, value, exc, source, applied) from None
            applied[factor.name] = value
        return config

    def check_levels(
        self, base: SimulationConfig | None = None, *, source: str | None = None
    ) -> None:
        """Apply every level of every factor, one at a time, to ``base``.

        Raises
        ------
        ConfigError
            Where levels do not validate: one line for each such level (a DoE review: a
            design with two bad factors had shown the second only once the first was
            mended), naming ``source`` (the design file), the factor, its field and the
            level.
        """
        base = self.load_base() if base is None else base
        centre = self.center_levels() if self.center_points else {}
        problems: list[str] = []
        for factor in self.factors:
            values = [*factor.levels, *([centre[factor.name]] if centre else [])]
            for value in values:
                try:
                    applied = factor.apply(base, value)
                    if factor.field == "cycle" and applied.cycle.trace_file:
                        # a trace with no braking event to simulate, refused before any run
                        # (a fuzz review: the campaign computed the other choices' runs
                        # first); its events are detected once and kept (traces' cache)
                        from brakeca.traces import configured_cycle

                        configured_cycle(applied)
                except ConfigError as exc:
                    problems.append(str(self._level_error(factor, value, exc, source)))
        if problems:
            raise ConfigError("\n".join(problems))

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
        # the overrides are the caller's: warned here; the levels were as the design loaded
        base = self.resolved_base(overrides=overrides, quick=quick, max_stops=max_stops)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnitWarning)
            return self._points(base)

    def _points(self, base: SimulationConfig) -> list[RunPoint]:
        """:meth:`points` from the resolved ``base``, its warnings on levels that read like
        slips of unit aside."""
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
        """Plain dict in the design-file layout (None fields, empty generators and a factor's
        linear coding dropped; a run table's rows as ``runs``, a central composite design's
        ``composite`` as a table).

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
            {
                k: (list(v) if isinstance(v, tuple) else v)
                for k, v in f.items()
                if v is not None and not (k == "coding" and v == "linear")  # the default
            }
            for f in data["factors"]
        ]
        data["generators"] = list(data["generators"]) or None  # a full factorial: no key
        data["foldover"] = list(data["foldover"]) or None
        data["goals"] = [
            {k: v for k, v in g.items() if v is not None} for g in data["goals"]
        ] or None
        if data.get("runs") is not None:
            data["runs"] = [dict(row) for row in data["runs"]]
        if data.get("runs_file") is not None:
            data["runs_file"] = str(data["runs_file"])
        if data["anova_type"] == 2:  # the default
            data["anova_type"] = None
        if not data["center_points"]:
            data["center_points"] = None
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
        Directory a relative ``base_config``, ``runs_file`` or cycle file is read from (the
        design file's directory; by default the working directory).

    Returns
    -------
    Design
        With ``base_config`` made absolute, a ``runs_file`` read into ``runs`` (and unset),
        and every level checked against the base.

    Raises
    ------
    ConfigError
        Anything wrong; each message names ``source`` and the field (for a run-table file,
        also the CSV file and its line).
    """
    if not isinstance(data, Mapping):
        raise ConfigError(f"{source}: a design must be a table of keys, got {type(data).__name__}")
    data = dict(data)
    try:
        design = Design.model_validate(data)
    except ValidationError as exc:
        raise ConfigError(format_validation_error(exc, source, Design)) from None
    base_dir = Path(root) if root is not None else Path.cwd()
    if design.runs_file is not None:  # kept inline: the design stands alone without the CSV
        rows = _read_runs_csv(base_dir / design.runs_file, design.factors, f"{source}: runs_file")
        try:
            design = Design.model_validate({**data, "runs": rows, "runs_file": None})
        except ValidationError as exc:
            raise ConfigError(format_validation_error(exc, source, Design)) from None
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
    given = design.base_config
    try:
        if design.base_config is not None and not design.base_config.is_absolute():
            absolute = (base_dir / design.base_config).resolve()
            design = design.model_copy(update={"base_config": absolute})
        base = design.load_base()
    except (ValueError, OSError) as exc:  # ConfigError is a ValueError
        from brakeca.presets import available_presets

        field = "base" if design.base is not None else "base_config"
        detail = str(exc).replace("\n", "; ")
        if given is not None and str(given) in available_presets():
            detail += f' (a shipped preset is given as base = "{given}"; base_config is a file)'
        raise ConfigError(
            f"{source}: {field}: cannot load the base configuration: {detail}"
        ) from None
    with warnings.catch_warnings(record=True) as seen:  # the levels' notes, named below
        warnings.simplefilter("always", UnitWarning)
        design.check_levels(base, source=source)
    for text in dict.fromkeys(str(w.message) for w in seen if w.category is UnitWarning):
        warn_unit(f"{source}: a level of the design: {text}")
    for w in seen:
        if w.category is not UnitWarning:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    for factor in design.factors:
        note = factor.unit_note()
        if note is not None:
            warn_unit(f"{source}: {note}")
    return design


def load_design(path_or_name: str | Path | Mapping[str, Any]) -> Design:
    """Load and validate a design: a shipped name (``"paper"``), a TOML file or a mapping.

    Parameters
    ----------
    path_or_name
        A shipped design's name (``brakeca.presets.available_designs()``), a design file
        (docs/designs.md: factors, levels in their units, seeds, options) or a campaign
        folder (its ``design.toml``). A shipped design's name means the shipped design even
        where a folder of that name exists (``brakeca run paper -o paper`` twice runs the
        paper's design both times); give ``paper/design.toml`` for the folder's. Or the
        design file's contents as a mapping (:func:`design_from_dict`; a relative
        ``base_config`` or cycle file is then read from the current folder).

    Returns
    -------
    Design
        The validated design, its base configuration resolved and its levels checked
        against the fields they set.

    Raises
    ------
    ConfigError
        Unknown name, unreadable or invalid file; the message names the file and the field.

    Examples
    --------
    The paper's design: 2 × 3 × 2 × 2 levels, 24 tests, each with its own seed:

    >>> from brakeca.design import load_design
    >>> design = load_design("paper")
    >>> design.kind, design.n_tests, [f.name for f in design.factors]
    ('full factorial', 24, ['S', 'WP', 'WR', 'A'])
    >>> test5 = design.points()[4]
    >>> test5.test, test5.levels, test5.seed
    (5, {'S': 0.0, 'WP': 1e-13, 'WR': 1e-07, 'A': 10.0}, 1456000950)
    """
    from brakeca.presets import available_designs, design_path

    if isinstance(path_or_name, Mapping):  # a design written in Python (an API review)
        return design_from_dict(path_or_name)
    path = Path(path_or_name)
    shipped = isinstance(path_or_name, str) and path_or_name in available_designs()
    if shipped and not path.is_file():  # a folder of that name (a campaign's) is no design
        path = design_path(str(path_or_name))
    elif path.is_dir() and (path / "design.toml").is_file():  # a campaign folder: its design
        path = path / "design.toml"
    elif path.is_dir():
        raise ConfigError(
            f"design {str(path_or_name)!r}: a folder without a design.toml (a campaign "
            "folder holds one); give a design file or a shipped design "
            f"({', '.join(available_designs())})"
        )
    elif not path.is_file():
        raise ConfigError(
            f"design {str(path_or_name)!r}: no such file nor a shipped design "
            f"({', '.join(available_designs())})"
        )
    source = str(path)
    from brakeca.config import SimulationConfig, is_run_file

    # a file of another kind, named as such in one line (a command-line review: a run file
    # read "'utf-8' codec can't decode byte 0x89", a configuration fifteen "unknown key"s)
    if is_run_file(path):
        raise ConfigError(
            f"{source}: a netCDF file (a run file or a campaign.nc), not a design: give a "
            "design TOML file or a shipped design's name (brakeca design --help)"
        )
    try:
        text = path.read_text(encoding="utf-8-sig")  # a BOM (Windows editors) is not TOML
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{source}: cannot read: {exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{source}: not valid TOML: {exc}") from None
    if "factors" not in data and set(data) & (set(SimulationConfig.model_fields) - {"name"}):
        raise ConfigError(
            f"{source}: a simulation configuration, not a design (it has no [[factors]]): "
            f"run it with 'brakeca simulate -c {source} -o RUN.nc', or name it as a design's "
            "base_config (docs/designs.md)"
        )
    return design_from_dict(data, source=source, root=path.parent)
