"""Validated, frozen parameter objects for one simulation, with TOML load and dump.

Every field carries its unit (SI unless the name says otherwise, e.g. ``angular_step_deg``)
and its source: "Table N" refers to Wahlström (2016), "decision" to ``docs/model.md``.

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, ClassVar, Literal, NamedTuple, Self

import numpy as np
import tomli_w
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

__all__ = [
    "FACTOR_ALIASES",
    "PAPER_FACTOR_LABELS",
    "AutomatonConfig",
    "BrakeBlock",
    "BrakeConfig",
    "ConfigError",
    "ContactConfig",
    "CycleConfig",
    "FrictionConfig",
    "MeshConfig",
    "NumericsConfig",
    "OutputConfig",
    "PadConfig",
    "SimulationConfig",
    "TraceCycleConfig",
    "UnitWarning",
    "VehicleConfig",
    "WearConfig",
    "apply_overrides",
    "load_config",
    "parse_override",
    "parse_overrides",
    "unit_notes",
    "unit_notes_by_field",
]


class ConfigError(ValueError):
    """A configuration value is missing, unknown or outside its allowed range."""


class UnitWarning(UserWarning):
    """A value that is allowed but reads like a slip of unit: a fibre fraction ``A`` below
    1 % (``A`` is in %, so 0.1 is 0.1 %, not 10 %). The command line prints these as notes;
    from Python they are warnings (``warnings.simplefilter("error", UnitWarning)`` makes
    them errors)."""


def warn_unit(note: str | None) -> None:
    """Warn (:class:`UnitWarning`) with ``note``, unless it is None, at the line of the code
    that called into brakeca (the first frame outside the package and pydantic), whichever
    way it came in (``with_updates``, ``apply_overrides``, a design's levels)."""
    if note is None:
        return
    import os
    import sys
    import warnings

    import pydantic

    inside = tuple(  # with the separator: not brakeca_tools nor pydantic_settings
        os.path.join(os.path.dirname(path), "") for path in (__file__, str(pydantic.__file__))
    )
    frame = sys._getframe(1)
    level = 2  # stacklevel 2: the caller of this function
    while frame.f_back is not None and frame.f_code.co_filename.startswith(inside):
        frame = frame.f_back
        level += 1
    warnings.warn(note, UnitWarning, stacklevel=level)


def _numeric(annotation: Any) -> bool:
    """Whether a field's annotation is a number (``int``, ``float``, or one of them or None)."""
    if annotation in (int, float):
        return True
    args = getattr(annotation, "__args__", ())
    return bool(args) and all(a in (int, float, type(None)) for a in args)


class _Checked(BaseModel):
    """A model whose number fields refuse ``true``/``false``: pydantic takes ``True`` for 1
    in an ``int`` or ``float`` field, so ``mesh.n_radial = true`` had made a one-row band."""

    @field_validator("*", mode="before")
    @classmethod
    def _no_bool_for_a_number(cls, value: Any, info: ValidationInfo) -> Any:
        if isinstance(value, bool) and info.field_name is not None:
            field = cls.model_fields.get(info.field_name)
            if field is not None and _numeric(field.annotation):
                raise ValueError(f"must be a number, not {str(value).lower()}")
        return value

    def model_copy(self, *, update: Mapping[str, Any] | None = None, deep: bool = False) -> Self:
        """A copy, with the fields of ``update`` changed and **validated** (pydantic's own
        ``model_copy`` checks nothing, so ``mesh.model_copy(update={"n_radial": -5})`` had
        failed deep in a run with numpy's words: an API review); a bad value raises
        :class:`ConfigError` naming the field and its allowed range.
        :meth:`SimulationConfig.with_updates` takes dotted keys and friendly aliases.

        As pydantic's, the copy counts as given (``model_fields_set``) the fields this model
        had given and those of ``update``, and keeps the sections it does not change as they
        are (:func:`brakeca.emissions.pm10_from_run` takes what was not given from the run:
        a copy that counted every field as given had changed its PM10, a diff review)."""
        if not update:
            return super().model_copy(deep=deep)
        fields = {name: getattr(self, name) for name in type(self).model_fields}
        try:
            copy = type(self).model_validate({**fields, **dict(update)})
        except ValidationError as exc:
            raise ConfigError(
                format_validation_error(exc, f"{type(self).__name__}.model_copy", type(self))
            ) from None
        object.__setattr__(copy, "__pydantic_fields_set__", self.model_fields_set | set(update))
        return copy


class _Frozen(_Checked):
    # protected_namespaces=(): fields named model_* (a design's model_order and model_terms)
    # are ours; pydantic before 2.10 warned of them
    model_config = ConfigDict(
        frozen=True,
        extra="forbid",
        validate_default=True,
        allow_inf_nan=False,
        protected_namespaces=(),
    )

    def __setattr__(self, name: str, value: Any) -> None:
        # pydantic's ValidationError "Instance is frozen" did not say what to do instead (an
        # API review)
        cls = type(self).__name__
        if name not in type(self).model_fields:
            raise AttributeError(f"{cls} has no field {name!r} (and is frozen)")
        found = _section_path(type(self))
        if found is None:  # a frozen model of its own (EmissionParameters: a diff review)
            raise AttributeError(
                f"{cls} is frozen: make a changed one, {cls}(**{{**old.model_dump(), "
                f"{name!r}: {value!r}}})"
            )
        where, listed = found
        key = f"{where}.{name}" if where and not listed else (where or name)
        shown = "[...]" if listed else repr(value)
        raise AttributeError(
            f"a configuration cannot be changed in place ({cls} is frozen): "
            f"config.with_updates({{{key!r}: {shown}}}) gives a validated copy with the "
            "change (--set on the command line)"
        )


def _section_path(cls: type, model: Any = None, prefix: str = "") -> tuple[str, bool] | None:
    """Where :class:`SimulationConfig` holds a section of type ``cls``: its dotted path
    (``"wear"``, ``"cycle.trace"``; empty for SimulationConfig itself) and whether it is an
    item of a list there (``"cycle.blocks"``); None where it holds none."""
    import typing

    model = model or SimulationConfig
    if cls is model:
        return prefix.rstrip("."), False
    for name, info in model.model_fields.items():
        ann = info.annotation
        if ann is cls:
            return f"{prefix}{name}", False
        if cls in typing.get_args(ann):
            return f"{prefix}{name}", typing.get_origin(ann) in (tuple, list)
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            found = _section_path(cls, ann, f"{prefix}{name}.")
            if found is not None:
                return found
    return None


class VehicleConfig(_Frozen):
    """The vehicle as seen by one front brake (Table 4 of the paper)."""

    wheel_load_mass: float = Field(
        690.0,
        ge=1e-3,
        le=1e6,
        description="[kg] front wheel load, the mass this brake decelerates (1 g to 1000 t)",
    )
    wheel_radius: float = Field(
        0.314,
        gt=0,
        le=2.0,
        description="[m] rolling radius of the wheel (at most 2 m: a mining truck's is about 1.8)",
    )
    gravity: float = Field(
        9.81,
        ge=9.0,
        le=10.5,
        description="[m/s^2] standard gravity, converts g to m/s^2 (Earth's: 9.78 to 9.83; 9 "
        "to 10.5, 10 rounded)",
    )

    def unit_note(self) -> str | None:
        """A note for a wheel load that reads like a slip of unit (under 20 kg: ``0.69``
        meant as 0.69 t; an API review ran it without a word), else None."""
        m = self.wheel_load_mass
        if m < 20.0:
            return (
                f"vehicle.wheel_load_mass = {m:g} kg, under 20 kg: a car's wheel carries a "
                f"few hundred kg (the paper's 690 kg); the load is in kg, not tonnes ({m:g} t "
                f"is {1000 * m:g} kg)"
            )
        return None


class BrakeConfig(_Frozen):
    """Disc, pad and calliper geometry (Table 4 of the paper)."""

    disc_outer_radius: float = Field(
        0.139, gt=0, le=1.0, description="[m] disc outer radius (at most 1 m)"
    )
    disc_inner_radius: float = Field(0.080, gt=0, description="[m] disc inner radius")
    effective_radius: float = Field(0.113, gt=0, description="[m] disc effective radius")
    pad_area: float = Field(
        5.080e-3, gt=0, description="[m^2] pad area (less than the disc face it rubs on)"
    )
    piston_diameter: float = Field(
        0.057, ge=1e-3, le=0.3, description="[m] calliper cylinder diameter (1 mm to 0.3 m)"
    )
    pads_per_brake: int = Field(
        2, ge=1, le=8, description="[-] sliding interfaces sharing the torque (decision: 2)"
    )

    @model_validator(mode="after")
    def _radii(self) -> BrakeConfig:
        if not self.disc_inner_radius < self.effective_radius < self.disc_outer_radius:
            raise ValueError(
                "need disc_inner_radius < effective_radius < disc_outer_radius, got "
                f"{self.disc_inner_radius} / {self.effective_radius} / {self.disc_outer_radius} m"
            )
        face = math.pi * (self.disc_outer_radius**2 - self.disc_inner_radius**2)
        if self.pad_area >= face:
            raise ValueError(
                f"pad_area ({self.pad_area:g} m²) must be less than the disc face it rubs on, "
                f"pi (disc_outer_radius² - disc_inner_radius²) = {face:.4g} m² (a pad of 50 cm² "
                "is 5e-3 m²)"
            )
        return self


class MeshConfig(_Frozen):
    """Polar pad mesh and subdomains (Table 5 of the paper)."""

    angular_step_deg: float = Field(0.044, gt=0, le=1.0, description="[deg] angular step")
    # at least 0.1 µm (a fuzz review: 1e-30 m overflowed in the surface, 1e-15 m ran a
    # band 4e-15 m wide)
    radial_step: float = Field(100e-6, ge=1e-7, le=1e-2, description="[m] radial step")
    n_angular: int = Field(1000, ge=2, le=100_000, description="[-] angular points")
    n_radial: int = Field(201, ge=1, le=100_000, description="[-] radial points")
    n_subdomains: int = Field(10, ge=1, description="[-] subdomains along the sliding direction")
    inner_radius: float | None = Field(
        None,
        gt=0,
        description="[m] radius of row 0; unset, centred on the effective radius (decision)",
    )

    #: The most cells a band may have [-]: 250 times the paper's 201 x 1000 (a fuzz review:
    #: 10^10 cells passed every check, then failed allocating 75 GiB in a run).
    MAX_CELLS: ClassVar[int] = 50_000_000

    @model_validator(mode="after")
    def _divisible(self) -> MeshConfig:
        if self.n_radial * self.n_angular > self.MAX_CELLS:
            raise ValueError(
                f"n_radial x n_angular = {self.n_radial} x {self.n_angular} = "
                f"{self.n_radial * self.n_angular:.3g} cells: at most {self.MAX_CELLS:.0e} "
                "(the paper's band is 201 x 1000 = 201,000 cells, about 0.3 GB a run)"
            )
        if self.n_subdomains > self.n_angular or self.n_angular % self.n_subdomains:
            raise ValueError(
                f"n_angular ({self.n_angular}) must be a multiple of n_subdomains "
                f"({self.n_subdomains}): each subdomain holds n_angular / n_subdomains columns"
            )
        span = self.n_angular * self.angular_step_deg
        if span > 360.0 * (1.0 + 1e-12):  # (a fuzz review: 440 and 100,000 deg were taken;
            # the tolerance lets 1430 x 360/1430 deg, 360.00000000000006, be 360)
            raise ValueError(
                f"n_angular x angular_step_deg = {self.n_angular} x {self.angular_step_deg:g} "
                f"= {span:g} deg: the band is a sector of the pad, at most 360 deg (the "
                "paper's 1000 x 0.044 deg = 44 deg)"
            )
        return self

    @property
    def angular_step(self) -> float:
        """Angular step [rad]."""
        return math.radians(self.angular_step_deg)

    @property
    def columns_per_subdomain(self) -> int:
        """Columns per subdomain N_m [-]."""
        return self.n_angular // self.n_subdomains

    @property
    def band_width(self) -> float:
        """Radial width of the simulated band [m]."""
        return (self.n_radial - 1) * self.radial_step


class PadConfig(_Frozen):
    """Pad surface: metal fibres in a resin matrix (Section 2.3 and Figure 5 of the paper)."""

    fibre_area_fraction: float = Field(
        0.20,
        gt=0.0,  # no fibre, no plateau to carry the load: every step would fail (a review)
        lt=1.0,
        description="[-] area fraction covered by metal fibres (factor A), above 0, below 1",
    )
    fibre_length_min: float = Field(
        1e-3, gt=0, le=0.1, description="[m] shortest fibre (at most 0.1 m)"
    )
    fibre_length_max: float = Field(
        10e-3, gt=0, le=0.1, description="[m] longest fibre (at most 0.1 m)"
    )
    fibre_diameter_min: float = Field(
        200e-6, gt=0, le=0.01, description="[m] thinnest fibre (at most 0.01 m)"
    )
    fibre_diameter_max: float = Field(
        700e-6, gt=0, le=0.01, description="[m] thickest fibre (at most 0.01 m)"
    )
    resin_roughness: float = Field(
        100e-6,
        ge=0,
        le=1e-2,
        description="[m] resin heights are uniform in [0, resin_roughness] (at most 0.01 m)",
    )
    fibre_model: Literal["columns", "layer", "field"] = Field(
        "columns",
        description=(
            "'columns': fibres run through the pad, the fibre map persists (rule 7 never fires; "
            "decision). 'layer': a fibre is the lying cylinder only; worn below its underside "
            "it becomes resin (rule 7 fires). 'field': fibres also lie at random depths "
            "through the pad, laid ahead of the wear; a fibre worn through becomes resin "
            "(rule 7), and the resin cut stops at the fibre below, which becomes a primary "
            "plateau."
        ),
    )
    fibre_centres: Literal["band", "beyond_edges"] = Field(
        "band",
        description=(
            "where fibre centres are drawn: band (uniform over the band, fibres clipped at "
            "its edges, so the fibre share thins towards them) or beyond_edges (over the band "
            "widened by half the longest fibre and the thickest fibre's radius, so a cell near "
            "an edge is covered as one inside it) (decision: band)"
        ),
    )

    @property
    def fibre_reach(self) -> float:
        """How far beyond the band ``fibre_centres = "beyond_edges"`` draws centres: half
        the longest fibre plus the thickest fibre's radius [m]; 0 for ``"band"``."""
        if self.fibre_centres == "band":
            return 0.0
        return self.fibre_length_max / 2.0 + self.fibre_diameter_max / 2.0

    @model_validator(mode="after")
    def _ranges(self) -> PadConfig:
        for name in ("fibre_length", "fibre_diameter"):
            low, high = getattr(self, f"{name}_min"), getattr(self, f"{name}_max")
            if low > high:
                raise ValueError(f"{name}_min ({low:g} m) must not exceed {name}_max ({high:g} m)")
        radius = self.fibre_diameter_min / 2.0
        # (to round-off: a factor in µm makes the default 200 µm 9.999999999999999e-05 m's
        # double, a diff review)
        if self.fibre_model == "field" and not 0.0 < self.resin_roughness <= radius * (1 + 1e-9):
            # (a physics review: the field's fibres lie below 0, the surface fibres' axes at
            # the resin band's top; a deeper band left a layer without fibres between them,
            # which runs fell through, and at 0 the field's first fibres, cut at 0, met the
            # resin there and were exposed after the first stop without any wear)
            raise ValueError(
                f"resin_roughness = {self.resin_roughness:.12g} m with fibre_model = 'field': "
                f"it must lie in (0, {radius:.12g}] m, above 0 and at most the thinnest fibre's "
                "radius (fibre_diameter_min / 2), so that the field's fibres, which lie below "
                "0, meet the surface fibres, whose axes lie at the resin band's top"
            )
        return self


class ContactConfig(_Frozen):
    """Elastic (Winkler) foundation: each cell is a bar of stiffness K = E / L."""

    elastic_modulus: float = Field(
        1e9,
        ge=1e-3,
        le=1e13,
        description="[Pa] foundation modulus E (decision; 1 mPa to 1e13 Pa)",
    )
    bar_length: float = Field(
        10e-3, ge=1e-9, le=1.0, description="[m] foundation bar length L (decision; 1 nm to 1 m)"
    )

    @property
    def stiffness(self) -> float:
        """Foundation stiffness K = E / L [Pa/m]."""
        return self.elastic_modulus / self.bar_length

    def unit_note(self) -> str | None:
        """A note for a modulus that reads like a slip of unit (under 1 MPa: ``1`` meant as
        1 GPa), else None."""
        if self.elastic_modulus < 1e6:
            return (
                f"contact.elastic_modulus = {self.elastic_modulus:g} Pa, a foundation under "
                "1 MPa: the modulus is in Pa (the default 1 GPa is 1e9)"
            )
        return None


#: The smallest friction.slope above 0 [1/Pa]: times the softest foundation's stiffness
#: (1 mPa over 1 m) still a normal number
MIN_SLOPE = 1e-20


class FrictionConfig(_Frozen):
    """Pressure-dependent local COF on plateaus, mu(p) = max(mu_min, mu_0 - c p) (Figure 4)."""

    mu_0: float = Field(0.6, gt=0, le=2.0, description="[-] COF at zero pressure (decision)")
    slope: float = Field(
        3e-8,
        ge=0,
        le=1.0,
        description="[1/Pa] decrease of COF per pascal, c (0.03 per MPa; decision; at most 1)",
    )
    mu_min: float = Field(0.15, ge=0, description="[-] COF floor (Figure 4 of the paper)")

    @model_validator(mode="after")
    def _floor(self) -> FrictionConfig:
        if self.mu_min > self.mu_0:
            raise ValueError(f"mu_min ({self.mu_min}) must not exceed mu_0 ({self.mu_0})")
        if 0.0 < self.slope < MIN_SLOPE:  # (times the softest foundation's stiffness, it
            # rounded to 0, and the solve divided by it: a physics review)
            raise ValueError(
                f"slope = {self.slope:g} 1/Pa: a slope this small is 0 to the contact solve; "
                f"give 0 (a constant COF) or at least {MIN_SLOPE:g}"
            )
        return self

    def unit_note(self) -> str | None:
        """A note for a slope that reads like a slip of unit (the COF at its floor from
        under 1 kPa: 0.03 meant per MPa given per Pa), else None."""
        if self.slope > 0 and self.mu_0 > self.mu_min:
            floor_at = (self.mu_0 - self.mu_min) / self.slope
            if floor_at < 1e3:
                return (
                    f"friction.slope = {self.slope:g} 1/Pa: the COF falls to its floor "
                    f"{self.mu_min:g} at {floor_at:.3g} Pa, so every plateau in contact is at "
                    "the floor; the slope is per Pa (the paper's 0.03 per MPa is 3e-8)"
                )
        return None


class WearConfig(_Frozen):
    """Archard wear of plateaus and the fixed-depth resin wear."""

    specific_wear_rate: float = Field(
        1e-14, gt=0, le=1e-9, description="[m^3/(N m)] Archard specific wear rate WP (factor WP)"
    )
    resin_wear_depth: float = Field(
        1e-7, gt=0, le=1e-3, description="[m] depth WR resin is worn to below the disc (factor WR)"
    )


class AutomatonConfig(_Frozen):
    """Plateau rules and the between-stop rule."""

    secondary_removal_fraction: float = Field(
        0.0,
        ge=0.0,
        le=1.0,
        description="[-] fraction S of secondary plateaus removed between stops",
    )
    rule6_max_gap: float | None = Field(
        None,
        gt=0,
        description=(
            "[m] rule 6: a primary plateau whose gap to the disc exceeds this is destroyed; "
            "unset, rule 6 is off (decision)"
        ),
    )
    creation_order: Literal["west_to_east", "east_to_west"] = Field(
        "west_to_east",
        description="order in which a row's candidates draw on the inflow (decision: west_to_east)",
    )
    end_of_stop_streams: Literal["emit", "carry"] = Field(
        "emit",
        description=(
            "the particles still in the streams when a stop ends: emit (they leave the "
            "contact, counted in that stop's emissions) or carry (they stay for the next "
            "stop) (decision: emit)"
        ),
    )
    secondary_removal_rule: Literal["count", "draw"] = Field(
        "count",
        description=(
            "how rule S picks the secondary plateaus it removes when 0 < S < 1: count "
            "(round(S n) of the n, at random) or draw (each one with probability S) (decision: "
            "count)"
        ),
    )


#: Above this deceleration [g] a block of a drive cycle brakes harder than a car's tyres
#: grip (about 1 g on a dry road): the value reads like one in m/s² (:meth:`CycleConfig.unit_note`).
GRIP_DECELERATION_G = 1.2


def plain_text_problem(value: str, *, formula: bool = True, lines: bool = False) -> str | None:
    """Why ``value``, a name or label from a file, may not go into the tables and the
    terminal, or None: a control character (a terminal's escape sequences; a newline or a
    tab, but with ``lines``), or,
    with ``formula``, a start a spreadsheet reads as a formula (``=``, ``@``, or ``+`` or
    ``-`` before anything but a number: the tables' cells are opened in Excel; a security
    review). ``-`` and ``+`` alone or before ``α`` (a composite design's axial levels), and
    numbers, are plain."""
    allowed = "\n\t" if lines else ""
    if any((ord(c) < 32 or 127 <= ord(c) < 160) and c not in allowed for c in value):
        return f"{value!r} holds a control character"
    if formula and (
        value[:1] in ("=", "@") or (value[:1] in ("+", "-") and value[1:] not in ("", "α"))
    ):
        try:
            float(value)
        except ValueError:
            return (
                f"{value!r} starts with {value[0]!r}, which a spreadsheet opening the tables "
                "reads as a formula"
            )
    return None


class BrakeBlock(_Frozen):
    """One block of stops of a block drive cycle (one row of Table 3)."""

    name: str = Field(min_length=1, description="block name")
    initial_speed_kmh: float = Field(gt=0, le=500, description="[km/h] speed at brake-on")
    final_speed_kmh: float = Field(ge=0, le=500, description="[km/h] speed at brake-off")
    deceleration_g: float = Field(
        ge=0.01,
        le=2.0,
        description="[g] constant deceleration (from 0.01 g: a stop of 200 km/h then lasts "
        "under 10 minutes; 1e-9 g had asked for terabytes of time steps)",
    )
    stops: int = Field(ge=1, le=100_000, description="[-] number of stops in the block")

    @field_validator("name")
    @classmethod
    def _plain_name(cls, value: str) -> str:
        if (problem := plain_text_problem(value)) is not None:
            raise ValueError(f"block name {problem}")
        return value

    @model_validator(mode="after")
    def _speeds(self) -> BrakeBlock:
        if self.final_speed_kmh >= self.initial_speed_kmh:
            raise ValueError(
                f"block {self.name!r}: final_speed_kmh ({self.final_speed_kmh}) must be lower "
                f"than initial_speed_kmh ({self.initial_speed_kmh})"
            )
        return self


class TraceCycleConfig(_Frozen):
    """How braking events are found in a trace and what the modelled brake must deliver.

    Defaults, literature ranges and sources are in the field descriptions and in
    ``docs/cycles.md``. :meth:`no_corrections` gives the settings under which a trace built
    from block stops reproduces the block cycle (brake share 1, no road load).

    The modelled brake is one front brake that decelerates its wheel-load mass ``m_w``
    (``vehicle.wheel_load_mass``) at ``a_brake`` (docs/model.md, section 1). From the vehicle's
    deceleration ``a`` of a step, its mean speed ``v``::

        a_road(v) = g C_rr + rho C_dA v^2 / (2 m)            road load per unit vehicle mass
        a_brake   = c phi_f / psi_f * (a - a_road(v))        floored at min_brake_deceleration

    ``c`` is the friction share of braking (regeneration removed), ``phi_f`` the front axle's
    share of the friction braking force and ``psi_f`` the front axle's share of the static
    vehicle weight (so that ``m_w = psi_f m / 2`` and the front brake's force is
    ``c phi_f m (a - a_road) / 2``). With ``phi_f = psi_f`` and ``c = 1`` the brake takes its
    static load share, the reading of the paper's block cycle.
    """

    # detection
    threshold: float = Field(
        0.3,
        gt=0,
        le=20.0,
        description=(
            "[m/s^2] a sample interval is braking when the vehicle decelerates faster than "
            "this; above coasting (road load alone gives ~0.1-0.3 m/s^2), range 0.1-0.5"
        ),
    )
    min_duration: float = Field(
        2.0, ge=0, description="[s] shortest braking event kept (shorter ones are dropped)"
    )
    smoothing: float = Field(
        0.0,
        ge=0,
        description=(
            "[s] width of a centred moving average applied to the speed before detection and "
            "for the event profiles; 0 = off (clean, prescribed traces); ~1 s for measured ones"
        ),
    )
    merge_gap: float = Field(
        1.0,
        ge=0,
        description="[s] braking stretches separated by at most this are one event",
    )
    # road load
    vehicle_mass: float = Field(
        2300.0,
        ge=100.0,
        le=1_000_000.0,
        description=(
            "[kg] vehicle test mass m: aerodynamic term and vehicle-level energies; default "
            "2 x 690 kg / 0.6, the paper's wheel load at psi_f = 0.6"
        ),
    )
    rolling_resistance: float = Field(
        0.010,
        ge=0,
        le=0.05,
        description="[-] rolling resistance coefficient C_rr, range 0.006-0.015 (Wong 2008)",
    )
    drag_area: float = Field(
        0.7,
        ge=0,
        le=10.0,
        description="[m^2] drag coefficient times frontal area C_d A, range 0.5-1.0 for cars",
    )
    air_density: float = Field(
        1.2, gt=0, le=2.0, description="[kg/m^3] air density rho, 1.225 at 15 C sea level (ISA)"
    )
    gravity: float = Field(
        9.81,
        ge=9.0,
        le=10.5,
        description="[m/s^2] gravity in the rolling resistance (Earth's: 9.78 to 9.83; 9 to "
        "10.5, 10 rounded)",
    )
    # brake share
    friction_share: float = Field(
        1.0,
        gt=0,
        le=1.0,
        description=(
            "[-] share c of the braking done by the friction brakes; 1 without regenerative "
            "braking, lower for hybrids and electric vehicles (GTR No. 24 gives values)"
        ),
    )
    front_brake_share: float = Field(
        0.7,
        gt=0,
        le=1.0,
        description="[-] front axle's share phi_f of the friction braking force, range 0.6-0.8",
    )
    front_load_share: float = Field(
        0.6,
        gt=0,
        le=1.0,
        description="[-] front axle's share psi_f of the static vehicle weight, range 0.5-0.65",
    )
    min_brake_deceleration: float = Field(
        0.01,
        gt=0,
        le=1.0,
        description=(
            "[m/s^2] floor of a_brake: the simulation solves a torque balance and needs a "
            "positive demand (a step where road load alone decelerates the car drags the "
            "pads); at most 1 m/s^2"
        ),
    )

    @classmethod
    def no_corrections(cls, **updates: Any) -> TraceCycleConfig:
        """Brake share 1, no road load: a trace of block stops reproduces the block cycle."""
        base = {
            "rolling_resistance": 0.0,
            "drag_area": 0.0,
            "friction_share": 1.0,
            "front_brake_share": 0.6,
            "front_load_share": 0.6,
        }
        return cls.from_dict({**base, **updates})

    @classmethod
    def from_dict(
        cls,
        data: dict[str, Any],
        *,
        source: str = "trace cycle",
        heads: Mapping[str, str] | None = None,
    ) -> TraceCycleConfig:
        """Validate a mapping; errors name the field (``ConfigError``; a field in ``heads`` by
        the name given there, :func:`format_validation_error`)."""
        try:
            return cls.model_validate(dict(data))
        except ValidationError as exc:
            raise ConfigError(format_validation_error(exc, source, cls, heads)) from None

    @property
    def brake_share(self) -> float:
        """Multiplier c phi_f / psi_f from friction-brake deceleration to a_brake [-]."""
        return self.friction_share * self.front_brake_share / self.front_load_share

    def road_load_deceleration(self, speed: np.ndarray | float) -> np.ndarray:
        """Deceleration road load alone gives the vehicle at ``speed`` [m/s] [m/s^2]."""
        v = np.asarray(speed, dtype=np.float64)
        return self.gravity * self.rolling_resistance + (
            self.air_density * self.drag_area * v * v / (2.0 * self.vehicle_mass)
        )

    def brake_deceleration(self, deceleration: np.ndarray, mean_speed: np.ndarray) -> np.ndarray:
        """Deceleration the modelled brake delivers for its wheel-load mass [m/s^2].

        Parameters
        ----------
        deceleration
            Vehicle deceleration of each step [m/s^2].
        mean_speed
            Mean speed of each step [m/s] (road load is evaluated there).
        """
        a = np.asarray(deceleration, dtype=np.float64)
        if self.rolling_resistance or self.drag_area:
            a = a - self.road_load_deceleration(mean_speed)
        share = self.brake_share
        if share != 1.0:
            a = share * a
        return np.maximum(a, self.min_brake_deceleration)


# --- the trace ------------------------------------------------------------------------------


class CycleConfig(_Frozen):
    """The drive cycle: a block cycle (Table 3 of the paper: stops at constant deceleration),
    or a speed trace whose braking events are detected (docs/cycles.md)."""

    name: str = Field("custom", description="cycle name")
    blocks: tuple[BrakeBlock, ...] = Field((), description="blocks in driving order")
    trace_file: str | None = Field(
        None, description="a speed-trace CSV (time, speed) or a shipped trace name"
    )
    trace_sha256: str | None = Field(
        None,
        pattern=r"^[0-9a-f]{64}$",  # as hashlib writes it, which the check compares with
        description="SHA-256 of the trace file's content (64 lowercase hexadecimal digits), "
        "checked before a run",
    )
    trace_speed_unit: str | None = Field(
        None, description="speed unit of a trace whose header states none (km/h, m/s, mph)"
    )
    trace: TraceCycleConfig = Field(
        TraceCycleConfig(), description="event detection, road load and brake share of a trace"
    )
    max_stops: int | None = Field(
        None,
        ge=1,
        le=1_000_000,
        description="[-] run only the first N stops (unset: the whole cycle), at most 10^6",
    )

    @field_validator("trace_speed_unit")
    @classmethod
    def _known_speed_unit(cls, value: str | None) -> str | None:
        """A speed unit a trace's header may give (a fuzz review: any text was taken)."""
        if value is None:
            return value
        from brakeca.traces import SPEED_UNITS, _norm_unit  # (traces imports this module)

        if _norm_unit(value) not in SPEED_UNITS:
            raise ValueError(f"unknown speed unit {value!r}; use one of km/h, m/s, mph")
        return value

    @model_validator(mode="after")
    def _one_source(self) -> CycleConfig:
        if bool(self.blocks) == bool(self.trace_file):
            raise ValueError(
                "give either blocks (a block cycle) or trace_file (a speed trace), not both "
                "and not neither"
            )
        return self

    def unit_note(self) -> str | None:
        """A note where blocks decelerate beyond a car's grip (above
        :data:`GRIP_DECELERATION_G`), as decelerations in m/s² given as g read (1.96 for
        0.2 g: an API review found it run as given), every such block named; None
        otherwise."""
        fast = [b for b in self.blocks if b.deceleration_g > GRIP_DECELERATION_G]
        if not fast:
            return None
        a = fast[0].deceleration_g
        if len(fast) == 1:
            head = f"block {fast[0].name!r} decelerates at deceleration_g = {a:g} g"
        else:
            named = [f"{b.name!r} ({b.deceleration_g:g} g)" for b in fast]
            head = f"blocks {', '.join(named[:-1])} and {named[-1]} decelerate"
        return (
            f"cycle.blocks: {head}, beyond a car's grip (about 1 g on a dry road): "
            f"deceleration_g is in g, not m/s² ({a:g} m/s² is {a / 9.81:.3g} g)"
        )

    @property
    def n_stops(self) -> int | None:
        """Number of stops that will be simulated [-] (None for a trace before detection)."""
        if self.trace_file:
            return self.max_stops
        total = sum(b.stops for b in self.blocks)
        return total if self.max_stops is None else min(total, self.max_stops)


class OutputConfig(_Frozen):
    """What a run keeps besides the per-stop responses."""

    series_every: int = Field(
        50,
        ge=1,
        le=1_000_000_000,
        description="[-] keep every Nth step in the thinned per-step series",
    )
    ledger_tolerance: float = Field(
        1e-9, gt=0, le=1e-2, description="[-] relative volume-ledger residual that stops a run"
    )
    ledger_every: int = Field(
        1,
        ge=1,
        le=1_000_000_000,
        description=(
            "[-] sum the held volume from the state every N steps for the ledger (1: every step; "
            "in between the incrementally tracked value is used); exact kernel only: the lazy "
            "kernel sums it at the last step of every stop"
        ),
    )


class NumericsConfig(_Frozen):
    """How the model is computed (not what it is)."""

    kernel: Literal["auto", "lazy", "exact"] = Field(
        "auto",
        description=(
            "step kernel: 'lazy' (per-row affine wear, work per step ~ rows + changes; equal to "
            "'exact' to round-off per step, the same study over whole runs), 'exact' (every "
            "cell in contact visited, bit-identical to earlier brakeca versions), 'auto' "
            "(lazy where it applies, exact where it does not: docs/model.md section 13)"
        ),
    )


#: Radial rows of the band ``--quick`` narrows to (2 mm at the paper's 0.1 mm step).
QUICK_N_RADIAL = 21

#: The most fibres the surface, or one slab of the fibre field, may need to reach the fibre
#: fraction A: laying a million takes 20 to 80 s. Fibres far smaller than a cell would need
#: billions, and the surface generation would never end.
MAX_FIBRES = 1_000_000


class SimulationConfig(_Frozen):
    """Everything that defines one simulated run, except the seed."""

    vehicle: VehicleConfig = VehicleConfig()
    brake: BrakeConfig = BrakeConfig()
    mesh: MeshConfig = MeshConfig()
    pad: PadConfig = PadConfig()
    contact: ContactConfig = ContactConfig()
    friction: FrictionConfig = FrictionConfig()
    wear: WearConfig = WearConfig()
    automaton: AutomatonConfig = AutomatonConfig()
    cycle: CycleConfig
    output: OutputConfig = OutputConfig()
    numerics: NumericsConfig = NumericsConfig()
    quick: bool = Field(False, description="true where --quick narrowed the band (2 mm, 21 rows)")

    @model_validator(mode="after")
    def _quick_is_the_quick_band(self) -> SimulationConfig:
        # `quick` labels a run (its header, run file and report) as the narrowed band; set
        # by hand on another band it would label a full-width run "quick"
        if self.quick and (
            self.mesh.n_radial != QUICK_N_RADIAL or self.mesh.inner_radius is not None
        ):
            inner = (
                f", mesh.inner_radius = {self.mesh.inner_radius:g} m"
                if self.mesh.inner_radius is not None
                else ""
            )
            raise ValueError(
                f"quick = true marks the band --quick narrows to {QUICK_N_RADIAL} rows centred "
                f"on the effective radius (mesh.n_radial = {QUICK_N_RADIAL}, mesh.inner_radius "
                f"unset), but this configuration has mesh.n_radial = {self.mesh.n_radial}"
                f"{inner}: use --quick (brakeca.design.quick_config from Python) instead of "
                "setting quick; to change the band of a quick configuration, set quick = "
                "false with it (with_updates({'quick': False, ...}))"
            )
        return self

    @model_validator(mode="after")
    def _band_on_disc(self) -> SimulationConfig:
        r0 = self.inner_radius
        r1 = r0 + self.mesh.band_width
        if r0 < self.brake.disc_inner_radius or r1 > self.brake.disc_outer_radius:
            raise ValueError(
                f"the simulated band [{r0 * 1e3:.3f}, {r1 * 1e3:.3f}] mm must lie on the disc "
                f"[{self.brake.disc_inner_radius * 1e3:.3f}, "
                f"{self.brake.disc_outer_radius * 1e3:.3f}] mm (mesh.inner_radius, mesh.n_radial, "
                "mesh.radial_step)"
            )
        return self

    @model_validator(mode="after")
    def _band_within_pad(self) -> SimulationConfig:
        # the band carries the pad's force times A_sim / A_pad (cycle.brake_demand): a band
        # larger than the pad would carry more than the pad does (a fuzz review)
        from brakeca.geometry import make_grid  # (geometry imports this module)

        area = make_grid(self).area
        if area > self.brake.pad_area:
            raise ValueError(
                f"the simulated band's area, {area * 1e6:.5g} mm² (mesh.n_radial, "
                "mesh.radial_step, mesh.n_angular, mesh.angular_step_deg), is larger than "
                f"the pad's, brake.pad_area = {self.brake.pad_area * 1e6:.5g} mm²: the band is "
                "a part of the pad, and carries the pad's force times their ratio"
            )
        return self

    @model_validator(mode="after")
    def _lazy_kernel_applies(self) -> SimulationConfig:
        problem = self.lazy_kernel_problem()
        if self.numerics.kernel == "lazy" and problem is not None:
            raise ValueError(
                f"numerics.kernel = 'lazy' cannot run this configuration: {problem}; use "
                "numerics.kernel = 'exact' or 'auto' (docs/model.md section 13)"
            )
        return self

    def resolved_kernel(self) -> str:
        """The step kernel that runs this configuration, ``"exact"`` or ``"lazy"``:
        ``numerics.kernel`` itself, or for ``"auto"`` (the default) the lazy kernel where it
        can run the configuration (:meth:`lazy_kernel_problem`) and the exact one elsewhere
        (docs/model.md section 13)."""
        choice = self.numerics.kernel
        if choice != "auto":
            return choice
        return "lazy" if self.lazy_kernel_problem() is None else "exact"

    def lazy_kernel_problem(self) -> str | None:
        """Why the lazy kernel cannot run this configuration, naming the fields; None where it
        can: fibres as columns (no rule 7), rule 6 off, and Archard wear of less than the
        interference in one step, ``WP K s < 1/2`` with ``s`` the outer row's sliding distance
        in a step (docs/model.md section 13)."""
        if self.pad.fibre_model != "columns":
            return f"pad.fibre_model = {self.pad.fibre_model!r} (rule 7; only 'columns')"
        if self.automaton.rule6_max_gap is not None:
            return "automaton.rule6_max_gap is set (rule 6; only unset)"
        from brakeca.geometry import make_grid  # (geometry imports this module)

        slide = float(np.max(make_grid(self).step_sliding_distance))
        wear = self.wear.specific_wear_rate * self.contact.stiffness * slide
        if not wear < 0.5:
            return (
                f"wear.specific_wear_rate x contact stiffness x step sliding distance = "
                f"{wear:.3g}, not below 1/2"
            )
        return None

    @model_validator(mode="after")
    def _fibres_cover_in_reason(self) -> SimulationConfig:
        counts = self.expected_fibres()
        for what, n in counts.items():
            if n > MAX_FIBRES:
                pad = self.pad
                raise ValueError(
                    f"pad.fibre_length_min/max = {pad.fibre_length_min:g}/"
                    f"{pad.fibre_length_max:g} m and pad.fibre_diameter_min/max = "
                    f"{pad.fibre_diameter_min:g}/{pad.fibre_diameter_max:g} m: fibres this small "
                    f"would need about {n:.2g} of them to make the fibre fraction "
                    f"A = {pad.fibre_area_fraction:g} of {what}, more than {MAX_FIBRES:,} "
                    "(the paper's fibres are 1-10 mm long and 200-700 um thick)"
                )
        return self

    def expected_fibres(self) -> dict[str, float]:
        """About how many fibres the surface (and, with the fibre field, each slab of it)
        takes to reach the fibre fraction A [-]: ``-ln(1 - A)`` times the band's area (or a
        slab's volume) over a fibre's mean projected area (or volume), overlaps counted."""
        pad = self.pad
        if pad.fibre_area_fraction <= 0.0:
            return {}
        from brakeca.geometry import make_grid  # (geometry imports this module)

        grid = make_grid(self)
        cover = -math.log1p(-pad.fibre_area_fraction) * grid.area
        if pad.fibre_reach > 0.0:  # centres drawn over a wider area: more fibres
            from brakeca.surface import centre_area

            cover *= float(centre_area(grid, pad.fibre_reach) / centre_area(grid, 0.0))
        length = (pad.fibre_length_min + pad.fibre_length_max) / 2.0
        d0, d1 = pad.fibre_diameter_min, pad.fibre_diameter_max
        counts = {"the surface": cover / (length * (d0 + d1) / 2.0)}
        if pad.fibre_model == "field":
            from brakeca.surface import FIELD_SLAB

            volume = length * math.pi / 4.0 * (d0 * d0 + d0 * d1 + d1 * d1) / 3.0
            counts["each slab of the fibre field"] = cover * FIELD_SLAB / volume
        return counts

    @property
    def inner_radius(self) -> float:
        """Radius of row 0 [m]; centred on the effective radius unless the mesh sets it."""
        if self.mesh.inner_radius is not None:
            return self.mesh.inner_radius
        return self.brake.effective_radius - self.mesh.band_width / 2.0

    # --- serialisation -------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """Plain nested dict (None fields dropped, TOML has no null)."""
        return _drop_none(self.model_dump(mode="python"))

    def __repr__(self) -> str:
        """One line: grid, cycle, the paper's four factors, fibre model and kernel
        (:meth:`to_toml` gives every field)."""
        cycle = self.cycle
        source = f"trace {Path(cycle.trace_file).name!r}" if cycle.trace_file else "blocks"
        stops = "" if cycle.max_stops is None else f", first {cycle.max_stops} stops"
        if cycle.blocks and cycle.n_stops != cycle.max_stops and cycle.max_stops is not None:
            # more than the cycle has: every stop runs (it had said "first 1000 stops")
            stops = f", max_stops {cycle.max_stops}: all {cycle.n_stops} stops"
        return (
            f"SimulationConfig({self.mesh.n_radial} x {self.mesh.n_angular} cells"
            f"{' (quick)' if self.quick else ''}, cycle {cycle.name!r} ({source}{stops}), "
            f"S={self.automaton.secondary_removal_fraction:g}, "
            f"WP={self.wear.specific_wear_rate:g} m^3/(N m), "
            f"WR={self.wear.resin_wear_depth:g} m, A={100 * self.pad.fibre_area_fraction:g} %, "
            f"fibres {self.pad.fibre_model}, kernel {self.numerics.kernel}"
            + "".join(f", {key} {value}" for key, value in self._variants().items())
            + "; to_toml() for every field)"
        )

    def _variants(self) -> dict[str, Any]:
        """The fields of :data:`ID_NEUTRAL` (the model's later variants) that are not at
        their default, for :meth:`__repr__`."""
        out = {}
        for key, neutral in ID_NEUTRAL.items():
            if "[]" in key:
                continue
            value: Any = self
            for part in key.split("."):
                value = getattr(value, part)
            if value != neutral:
                out[key.split(".")[-1]] = value
        return out

    def __str__(self) -> str:
        return repr(self)

    def to_toml(self) -> str:
        """The resolved configuration as TOML text."""
        return tomli_w.dumps(self.to_dict())

    def identity_toml(self) -> str:
        """:meth:`to_toml` without the fields of :data:`ID_NEUTRAL` that hold their neutral
        value: the text a run's id (:func:`brakeca.design.run_id_for`) and a checkpoint's
        match hash and compare, so that a field added to the model with a default that does
        what brakeca did before changes no run id of a finished campaign."""
        data = self.to_dict()
        for key, neutral in ID_NEUTRAL.items():
            _drop_neutral(data, key.split("."), neutral)
        return tomli_w.dumps(data)

    def to_commented_toml(self) -> str:
        """:meth:`to_toml` with each field's description (its unit first, ``[m]``) as a
        comment at the end of its line, as ``brakeca config`` prints it; the comments change
        nothing when the text is read back (:meth:`from_toml`)."""
        import re

        lines: list[str] = []
        table: list[str] = []
        array = False

        def unset() -> None:  # a table's unset fields, which TOML cannot hold, as comments
            if array:
                return
            section: Any = self
            for part in table:
                section = getattr(section, part, None)
            if not isinstance(section, BaseModel):
                return
            at = len(lines)
            while at and not lines[at - 1].strip():  # before the blank line that ends it
                at -= 1
            for name in type(section).model_fields:
                if getattr(section, name) is None:
                    text = _field_description(type(self), [*table, name])
                    comment = f"# {name} = ...  # unset by default"
                    if text and len(comment) + len(text) + 2 <= 120:
                        added = [f"{comment}; {text}"]
                    else:  # a long description on a line of its own
                        added = [comment, *([f"#   {text}"] if text else [])]
                    lines[at:at] = added
                    at += len(added)

        for line in self.to_toml().splitlines():
            header = re.fullmatch(r"\[(\[?)([A-Za-z0-9_.]+)\]\]?", line.strip())
            if header:
                unset()
                table, array = header.group(2).split("."), bool(header.group(1))
            match = re.match(r"([A-Za-z0-9_]+) = ", line)
            text = _field_description(type(self), [*table, match.group(1)]) if match else None
            if text and not line.rstrip().endswith(("[", "{")):  # not a value's first line
                line = f"{line}  # {text}"
            lines.append(line)
        unset()
        head = (
            "# brakeca configuration (brakeca config): SI units inside, each field's unit in "
            "brackets;\n# docs/nomenclature.md names the symbols, docs/model.md the model; "
            "a field\n# commented out is unset by default: give it a value to set it.\n"
        )
        return head + "\n".join(lines) + "\n"

    @classmethod
    def from_dict(
        cls,
        data: Mapping[str, Any],
        *,
        source: str = "config",
        heads: Mapping[str, str] | None = None,
    ) -> SimulationConfig:
        """Validate a nested mapping; errors name the field and the allowed values (a field
        in ``heads`` by the name given there, :func:`format_validation_error`)."""
        try:
            return cls.model_validate(dict(data))
        except ValidationError as exc:
            raise ConfigError(format_validation_error(exc, source, cls, heads)) from None

    @classmethod
    def from_toml(cls, text: str, *, source: str = "config") -> SimulationConfig:
        """Parse and validate TOML text."""
        if not isinstance(text, str):  # (3 gave an AttributeError; bytes a TypeError)
            raise TypeError(
                f"{source}: expected TOML text (str), got {type(text).__name__}; "
                "brakeca.load_config reads a file"
            )
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ConfigError(f"{source}: not valid TOML: {exc}") from None
        return cls.from_dict(data, source=source)

    def with_updates(self, updates: Mapping[str, Any]) -> SimulationConfig:
        """A copy with dotted-key updates, validated: variants are copies, never mutations.

        Parameters
        ----------
        updates
            Dotted field names (``"wear.specific_wear_rate"``) or the paper's factor names
            (``"WP"``, ``"A"``: :data:`FACTOR_ALIASES`, in their design units) to values.

        Returns
        -------
        SimulationConfig
            The new configuration; this one is unchanged.

        Raises
        ------
        ConfigError
            An unknown field, a value out of its range, or two keys for one field (a factor
            name and its dotted key); the message names the field and the range.
        TypeError
            ``updates`` is not a mapping, or a key is not text.

        Examples
        --------
        >>> from brakeca.config import ConfigError
        >>> from brakeca.presets import load_preset
        >>> paper = load_preset()
        >>> wears_faster = paper.with_updates({"WP": 1e-13, "mesh.n_radial": 21})
        >>> wears_faster.wear.specific_wear_rate, paper.wear.specific_wear_rate  # [m³/(N·m)]
        (1e-13, 1e-14)
        >>> try:  # a bad value is refused, with the field and its range
        ...     paper.with_updates({"A": 150})
        ... except ConfigError as exc:
        ...     print(exc)
        A (= pad.fibre_area_fraction): must be above 0 and below 100 %, got 150
        """
        return apply_overrides(self, updates)


#: Fields added to :class:`SimulationConfig` after its run ids were first issued, each with
#: the value that does what brakeca did before the field existed. At that value a field is
#: left out of :meth:`SimulationConfig.identity_toml`, so that adding it changed no run id:
#: a campaign finished by an earlier version is reused, not run again. A new field goes here
#: (a test lists the fields of the first run ids and fails on one that is in neither).
ID_NEUTRAL: dict[str, Any] = {
    "automaton.secondary_removal_rule": "count",
    "automaton.end_of_stop_streams": "emit",
    "pad.fibre_centres": "band",
}


def unit_notes(config: SimulationConfig) -> list[str]:
    """The notes on values of ``config`` that read like slips of unit (the foundation's
    modulus, the COF's slope, the wheel load, a block's deceleration); the command line
    prints them, Python warns
    (:class:`UnitWarning`) as the configuration is made."""
    return list(unit_notes_by_field(config).values())


def unit_notes_by_field(config: SimulationConfig) -> dict[tuple[str, Any], str]:
    """:func:`unit_notes` keyed by the field each is about and its value (the slope's note
    also gives where the COF meets its floor, which ``mu_0`` and ``mu_min`` move; one slip
    is one key however the note is worded)."""
    hardest = max((b.deceleration_g for b in config.cycle.blocks), default=0.0)
    notes = {
        ("contact.elastic_modulus", config.contact.elastic_modulus): config.contact.unit_note(),
        ("friction.slope", config.friction.slope): config.friction.unit_note(),
        ("vehicle.wheel_load_mass", config.vehicle.wheel_load_mass): config.vehicle.unit_note(),
        # the blocks' note names every block beyond grip; its value, a number for the
        # command line's "(and so at ...)", the hardest braking
        ("cycle.blocks", hardest): config.cycle.unit_note(),
    }
    return {key: text for key, text in notes.items() if text is not None}


def _drop_neutral(table: Any, parts: Sequence[str], neutral: Any) -> None:
    """Delete the field at the dotted path ``parts`` from the nested dict ``table`` where it
    holds ``neutral``; a part ending in ``[]`` (``blocks[]``) is a list of tables, each of
    which is visited (:data:`ID_NEUTRAL`'s keys)."""
    head, rest = parts[0], parts[1:]
    if not isinstance(table, dict):
        return
    if not rest:
        value = table.get(head)
        if head in table and type(value) is type(neutral) and value == neutral:
            del table[head]
        return
    if head.endswith("[]"):
        for item in table.get(head[:-2]) or ():
            _drop_neutral(item, rest, neutral)
    else:
        _drop_neutral(table.get(head), rest, neutral)
        if table.get(head) == {}:  # a section of neutral fields only: as if it never was
            del table[head]


def _drop_none(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _drop_none(v) for k, v in value.items() if v is not None}
    if isinstance(value, list | tuple):
        return [_drop_none(v) for v in value]
    return value


#: pydantic's error types of a numeric bound
_BOUND_ERRORS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")


#: Units a value above a field's range may have been given in, by the field's unit: the
#: friendly unit's name, its size in the field's unit, and how far from the field's default
#: the value so read may lie (a specific wear rate quoted in mm³/(N·m) within the paper's
#: hundredfold span, a resin depth in µm; a length in mm only near the default, so that a
#: radius in cm is not called one in mm: an API review and a diff review).
_SMALLER_UNITS: dict[str, tuple[tuple[str, float, float], ...]] = {
    "m": (("µm", 1e-6, 100.0), ("mm", 1e-3, 3.0)),
    "m^3/(N m)": (("mm³/(N·m)", 1e-9, 100.0),),
    # a slope per MPa (the paper's 0.03), a wheel load in g (a diff review: neither had a
    # hint once their ranges were bounded)
    "1/Pa": (("1/MPa", 1e-6, 1000.0),),
    "kg": (("g", 1e-3, 100.0),),
}


def _smaller_unit(
    unit: str, value: float, ctx: Mapping[str, Any], upper: float, default: Any
) -> str:
    """Where ``value``, above its field's range, reads as given in a smaller unit
    (:data:`_SMALLER_UNITS`) that puts it within the range and near the field's ``default``
    (where it has a number for one), the sentence that says so: ``"in m, not µm (0.1 µm is
    1e-07 m)"``; empty otherwise."""
    lower = ctx.get("ge", ctx.get("gt", -math.inf))
    unit = unit.removeprefix("[").removesuffix("]")  # ("[1/Pa]" after a range)
    shown = unit.replace("^3", "³").replace("(N m)", "(N·m)")
    near = default if isinstance(default, float) and default > 0 else None
    fits = [
        (abs(math.log(value * size / near)) if near else 0.0, name, value * size)
        for name, size, span in _SMALLER_UNITS.get(unit, ())
        if lower <= value * size <= upper
        and (near is None or abs(math.log(value * size / near)) <= math.log(span))
    ]
    if not fits:
        return ""
    _, name, converted = min(fits)
    return f"in {shown}, not {name} ({value:g} {name} is {converted:.3g} {shown})"


def _field_info(model: Any, loc: Sequence[Any]) -> Any | None:
    """The pydantic FieldInfo of the field of ``model`` at ``loc``; None where ``loc`` is not
    a field of nested models."""
    import typing

    from pydantic import BaseModel

    info = None
    cls = model
    for part in loc:
        if isinstance(part, int) and info is not None:  # an item of a list field: its model
            continue
        if not (isinstance(cls, type) and issubclass(cls, BaseModel)):
            # a list of models (tuple[BrakeBlock, ...]) or an optional one: the model
            args = [a for a in typing.get_args(cls) if isinstance(a, type)]
            cls = args[0] if args else None
            if not (isinstance(cls, type) and issubclass(cls, BaseModel)):
                return None
        if not isinstance(part, str) or part not in cls.model_fields:
            return None
        info = cls.model_fields[part]
        cls = info.annotation
    return info


def _field_unit(model: Any, loc: Sequence[Any]) -> str:
    """The unit of the field of ``model`` at ``loc``, as its description begins (``"[m] ..."``
    gives ``"m"``), empty for a dimensionless field ``[-]`` or one without a unit."""
    info = _field_info(model, loc)
    found = re.match(r"\[([^\]]+)\]", (info.description or "") if info is not None else "")
    return "" if found is None or found.group(1) == "-" else found.group(1)


def _as_number(value: Any) -> float | None:
    """``value`` as a finite float where it is a number or a number's text, else None."""
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def _allowed_range(model: Any, loc: Sequence[Any]) -> str | None:
    """The interval a numeric field of ``model`` at ``loc`` allows, e.g. ``"[0, 2]"`` or
    ``"(0, 1)"``, when it has a bound on both sides; None otherwise (one bound, or ``loc``
    not a field of nested models)."""
    import annotated_types as at

    info = _field_info(model, loc)
    if info is None:
        return None
    low: Any = None
    high: Any = None
    left, right = "[", "]"
    for bound in info.metadata:
        if isinstance(bound, at.Ge):
            low = bound.ge
        elif isinstance(bound, at.Gt):
            low, left = bound.gt, "("
        elif isinstance(bound, at.Le):
            high = bound.le
        elif isinstance(bound, at.Lt):
            high, right = bound.lt, ")"
    if low is None or high is None:
        return None
    return f"{left}{low:g}, {high:g}{right}"


def _known_keys(model: Any, loc: Sequence[Any]) -> list[str] | None:
    """The keys the table at ``loc`` (field names, no list indexes) in ``model`` takes,
    following nested models, the items of lists of them and optional ones; None where
    ``loc`` leads elsewhere."""
    import typing

    from pydantic import BaseModel

    def is_model(cls: Any) -> bool:
        return isinstance(cls, type) and issubclass(cls, BaseModel)

    def model_in(annotation: Any) -> Any:
        if is_model(annotation):
            return annotation
        args = [a for a in typing.get_args(annotation) if a is not type(None)]
        return args[0] if args else None

    cls = model
    for part in loc:
        if not is_model(cls) or part not in cls.model_fields:
            return None
        cls = model_in(cls.model_fields[part].annotation)
    return list(cls.model_fields) if is_model(cls) else None


def _first_sentence(text: str, most: int = 110) -> str:
    """``text`` up to the end of its first sentence, without its first parenthesis where it
    is longer than ``most`` characters, and then at most that (cut at a word, with "...")."""
    head = text.split(". ", 1)[0]
    for aside in (" (", "; "):  # the unit and name, without the aside
        if len(head) > most and aside in head[10:]:
            head = head[: head.index(aside, 10)]
    if len(head) <= most:
        return head
    return head[: most - 3].rsplit(" ", 1)[0] + "..."


def _field_description(model: Any, loc: Sequence[str]) -> str | None:
    """The comment of the field at ``loc`` (field names) in ``model``, following nested
    models, lists of them and optional ones: the first sentence of its description (its
    unit first), or the choices of a field of fixed choices; None where there is none."""
    import typing

    from pydantic import BaseModel

    def model_in(annotation: Any) -> Any:
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            return annotation
        for arg in typing.get_args(annotation):
            found = model_in(arg)
            if found is not None:
                return found
        return None

    cls = model
    for part in loc[:-1]:
        if cls is None or part not in cls.model_fields:
            return None
        cls = model_in(cls.model_fields[part].annotation)
    if cls is None or loc[-1] not in cls.model_fields:
        return None
    field = cls.model_fields[loc[-1]]
    choices = [
        a
        for arg in [field.annotation, *typing.get_args(field.annotation)]
        if typing.get_origin(arg) is typing.Literal
        for a in typing.get_args(arg)
    ]
    if choices:  # a description cut short would name one choice, not the one set
        return "one of " + ", ".join(repr(c) for c in choices)
    return _first_sentence(field.description) if field.description else None


def item_path(loc: Sequence[str | int]) -> str:
    """A field's path as a user reads it: keys joined by dots, a list's items counted from 1,
    as a TOML file's tables are (``("factors", 2, "levels")`` is ``factors #3.levels``)."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f" #{part + 1}"
        else:
            out += f".{part}" if out else str(part)
    return out


def format_validation_error(
    exc: ValidationError,
    source: str,
    model: Any = None,
    heads: Mapping[str, str] | None = None,
) -> str:
    """Turn a pydantic error into lines ``source: field.path: problem (got value)``.

    ``model`` (the model class validated) lets a bound's error give the whole allowed range
    of the field, e.g. ``must lie in [0, 2]`` where pydantic names only the bound crossed.
    ``heads`` maps a field's path to what its lines begin with instead of ``source:
    field.path``: the name the user gave it (``override S (= automaton.secondary_...)``,
    ``--threshold``).
    """
    heads = heads or {}
    lines = []
    errors = exc.errors()
    failed_items = {err["loc"][:-1] for err in errors} | {
        err["loc"][:i] for err in errors for i in range(1, len(err["loc"]))
    }
    for err in errors:
        if err["type"] == "too_short" and err["loc"] in failed_items:
            # pydantic also calls a list "too short" when its items failed; the items' errors
            # say what is wrong
            continue
        path = ".".join(str(p) for p in err["loc"])
        shown = item_path(err["loc"])
        loc = f"{shown}: " if shown else ""  # a model's validator: its message names the fields
        msg = err["msg"]
        if err["type"] == "extra_forbidden":
            msg = "unknown key"
            keys = _known_keys(model, [p for p in err["loc"][:-1] if not isinstance(p, int)])
            close = difflib.get_close_matches(str(err["loc"][-1]), keys or [], n=1, cutoff=0.6)
            if close:
                msg += f" (did you mean {close[0]!r}?)"
            elif str(err["loc"][-1]) in ("kind", "type", "design") and "box_behnken" in (
                keys or []
            ):  # a new user's kind = "composite"
                msg += (
                    "; a design's kind comes from its keys: generators or fraction_runs, runs "
                    "or runs_file, plackett_burman, [composite], [box_behnken], or none of "
                    "them for a full factorial"
                )
        elif err["type"] == "missing":
            msg = "required field is missing"
        elif err["type"] == "value_error":
            msg = msg.removeprefix("Value error, ")
        elif err["type"] in ("too_short", "too_long") and "ctx" in err:
            ctx = err["ctx"]
            most = "at least" if err["type"] == "too_short" else "at most"
            bound = ctx.get("min_length" if err["type"] == "too_short" else "max_length")
            msg = f"needs {most} {bound} item{'' if bound == 1 else 's'}"
        elif err["type"] in ("list_type", "tuple_type"):
            msg = "should be a list, in brackets: [...]"
        elif err["type"] in ("model_type", "model_attributes_type", "dict_type"):
            # pydantic's "Input should be a valid dictionary or instance of NumericsConfig"
            # (a fuzz review)
            msg = "should be a table of fields: a [section], or {key = value, ...}"
        elif err["type"] == "string_too_short":
            least = (err.get("ctx") or {}).get("min_length", 1)
            msg = "must not be empty" if least == 1 else f"needs at least {least} characters"
        elif err["type"] == "string_pattern_mismatch" and path.endswith("sha256"):
            msg = "must be a SHA-256 digest, 64 lowercase hexadecimal digits"
        elif err["type"] == "string_type":
            msg = 'should be text, in quotes: "..."'
        elif err["type"] in ("bool_type", "bool_parsing"):
            msg = "must be true or false"
        got = err.get("input")
        not_finite = isinstance(got, float) and not math.isfinite(got)
        if err["type"] in _BOUND_ERRORS or err["type"] == "finite_number" or not_finite:
            interval = _allowed_range(model, err["loc"]) if model is not None else None
            # the field's unit after its range (an API review: "(0, 0.3] (got 57)" did not
            # say the piston's diameter is in metres, not millimetres)
            unit = _field_unit(model, err["loc"]) if model is not None else ""
            if unit[:1].isdigit():  # "at least 0 [1/Pa]", not "at least 0 1/Pa"
                unit = f"[{unit}]"
            if interval is not None and unit:
                interval += f" {unit}"
            if not_finite:
                which = "NaN" if math.isnan(got) else "infinite"
                msg = "must be a finite number" + (f" in {interval}" if interval else "")
                msg += f", not {which}"
            elif interval is not None:
                msg = f"must lie in {interval}"
            elif err["type"] in _BOUND_ERRORS:  # one bound: pydantic's "Input should be..."
                words = {
                    "greater_than": ("above", "gt"),
                    "greater_than_equal": ("at least", "ge"),
                    "less_than": ("below", "lt"),
                    "less_than_equal": ("at most", "le"),
                }
                word, key = words[err["type"]]
                bound = (err.get("ctx") or {}).get(key)
                msg = (
                    f"must be {word} {bound:g}"
                    if isinstance(bound, float)
                    else (f"must be {word} {bound}")
                )
                if unit:
                    msg += f" {unit}"
            value = _as_number(got)  # a CSV's text too
            upper = (err.get("ctx") or {}).get("le", (err.get("ctx") or {}).get("lt"))
            if path == "pad.fibre_area_fraction" and value == 0:
                msg += f" (got {got!r}): a pad without fibres has no plateau to carry the load"
            elif path == "pad.fibre_area_fraction" and value is not None and value >= 1:
                example = f", {value / 100:g} for {value:g} %" if value < 100 else " below 1"
                msg += f" (got {got!r}): a fraction{example}; or set A, in per cent"
            elif value is not None and not unit and upper == 1 and 1 < value <= 100:
                # a share [-] given in per cent (not a field of a unit capped at 1: a radius)
                msg += f" (got {got!r}): a fraction, {value / 100:g} for {value:g} %"
            elif value is not None and unit == "g" and 2 < value <= 25:  # m/s² given as g
                msg += f" (got {got!r}): in g, not m/s² ({value:g} m/s² is {value / 9.81:.3g} g)"
            elif value is not None and upper is not None and value > upper and model is not None:
                info = _field_info(model, err["loc"])
                default = getattr(info, "default", None)
                slip = _smaller_unit(unit, value, err.get("ctx") or {}, upper, default)
                if slip:
                    msg += f" (got {got!r}): {slip}"
        elif err["type"] in ("float_type", "float_parsing", "int_type", "int_parsing"):
            msg = "must be a " + ("whole number" if err["type"].startswith("int") else "number")
        elif err["type"] == "int_from_float":
            msg = "must be a whole number"
        elif err["type"] == "int_parsing_size":  # 1e300: pydantic's "exceeded maximum size"
            interval = _allowed_range(model, err["loc"]) if model is not None else None
            msg = "must be a whole number" + (f" in {interval}" if interval else "")
        got_text = (
            ""
            if err["type"] in ("missing",) or isinstance(got, dict) or "got " in msg or not_finite
            else f" (got {got!r})"
        )
        head = heads.get(path)
        lines.append(f"{head}: " if head else f"{source}: {loc}")
        lines[-1] += f"{msg}{got_text}"
    return "\n".join(lines)


# --- overrides and the paper's factor names ------------------------------------------------

#: The paper's factor names, mapped to (config field, multiplier from the factor's unit to
#: the field's, the factor's unit): A is given in % and set as a fraction [-]; S, WP and WR
#: in their field's own unit.
FACTOR_ALIASES: dict[str, tuple[str, float, str]] = {
    "S": ("automaton.secondary_removal_fraction", 1.0, "-"),
    "WP": ("wear.specific_wear_rate", 1.0, "m^3/(N m)"),
    "WR": ("wear.resin_wear_depth", 1.0, "m"),
    "A": ("pad.fibre_area_fraction", 0.01, "%"),
}
#: The paper's descriptions of the fields its factors set (Table 1), by configuration field:
#: the label of a design's factor on such a field where the design gives none (figures'
#: titles and the report's design table).
PAPER_FACTOR_LABELS: dict[str, str] = {
    "automaton.secondary_removal_fraction": "Secondary plateaus removed between stops",
    "wear.specific_wear_rate": "Specific wear rate of plateaus",
    "wear.resin_wear_depth": "Resin wear depth",
    "pad.fibre_area_fraction": "Metal fibre area fraction",
}

#: Allowed values of a factor name in its unit: [low, high) (A = 100 %: no resin, and the
#: fibres laid at random would never cover the whole band).
_ALIAS_RANGES = {"A": (0.0, 100.0)}


#: The largest run seed [-]: run files store it as an unsigned 64-bit integer (checked by
#: ``simulation.simulate`` and the command line's ``--seed``).
MAX_SEED = 2**64 - 1

_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?|[+-]?\d+,")


def decimal_point(text: str) -> str:
    """``text`` with its decimal comma made a point (``"0,25"`` -> ``"0.25"``) when it is a
    number written that way, as spreadsheets write CSV in such locales; else ``text``."""
    return text.replace(",", ".") if _DECIMAL_COMMA.fullmatch(text) else text


#: The most bytes a drive cycle (a speed trace, a block cycle) or a design's run table may
#: hold [B]
MAX_CSV_BYTES = 256 << 20


def read_csv_text(path: str | Path) -> str:
    """The text of a CSV file: UTF-16 where it begins with its byte-order mark (Windows
    PowerShell writes it), else UTF-8 (a byte-order mark dropped), else Windows-1252, which
    spreadsheets in western European locales write (a German Excel export's ``Straße``);
    the numbers and the ASCII headers read the same either way.

    Parameters
    ----------
    path
        The file.

    Returns
    -------
    str
        Its text.

    Raises
    ------
    OSError
        The file cannot be read, or holds more than :data:`MAX_CSV_BYTES`.
    UnicodeDecodeError
        Not UTF-16 with its mark, UTF-8 or Windows-1252 (a byte that Windows-1252 leaves
        undefined).
    """
    # at most MAX_CSV_BYTES are read (a security review: a configuration a run file carries
    # may name any file as its trace, which was read whole)
    with Path(path).open("rb") as f:
        data = f.read(MAX_CSV_BYTES + 1)
    if len(data) > MAX_CSV_BYTES:
        raise OSError(
            f"{path}: more than {MAX_CSV_BYTES / 2**20:g} MiB, larger than a drive cycle or "
            "run table brakeca reads (a day of 10 Hz samples is under 20 MiB)"
        )
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):  # UTF-16, as Windows PowerShell writes
        return data.decode("utf-16")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1252")


def csv_float(text: str) -> float:
    """``float(text)`` for a number in a CSV cell, without the Python-only spelling that
    ``float`` takes and no spreadsheet writes: digits grouped by underscores (``"1_0"``,
    which ``float`` reads as 10).

    Raises
    ------
    ValueError
        ``text`` is not a number, or groups its digits with underscores.
    """
    if "_" in text:
        raise ValueError(f"could not convert string to float: {text!r}")
    return float(text)


def csv_delimiter(header: str) -> str:
    """The separator of a CSV file from its header line: comma, semicolon or tab."""
    return next((d for d in (",", ";", "\t") if d in header), ",")


def excel_separator(line: str) -> str | None:
    """The separator an Excel ``sep=;`` line above a CSV header names (``sep=`` alone: a
    comma), or None for any other line."""
    s = line.strip("\r\n ")
    if not s.lower().startswith("sep="):
        return None
    return s[4:5] or ","


def parse_override(text: str) -> tuple[str, Any]:
    """Split ``KEY=VALUE`` and parse the value as a TOML value (bare words become strings).

    Parameters
    ----------
    text
        One ``--set`` option's text, ``KEY=VALUE``.

    Returns
    -------
    tuple
        The key (stripped) and the value (a TOML number, boolean, array or string).

    Raises
    ------
    ConfigError
        No ``=``, or an empty key.

    Examples
    --------
    >>> from brakeca.config import parse_override
    >>> parse_override("WP=1e-13"), parse_override("numerics.kernel = exact")
    (('WP', 1e-13), ('numerics.kernel', 'exact'))
    """
    if "=" not in text:
        raise ConfigError(f"--set {text!r}: expected KEY=VALUE, e.g. --set WP=1e-13")
    key, raw = text.split("=", 1)
    key = key.strip()
    raw = raw.strip()
    if not key:
        raise ConfigError(f"--set {text!r}: empty key")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    return key, value


def parse_overrides(texts: Sequence[str] | None) -> dict[str, Any]:
    """``--set KEY=VALUE`` options as a mapping (:func:`parse_override` each); a key given
    twice is refused, where the last would silently have won.

    Parameters
    ----------
    texts
        The ``--set`` options' texts, ``KEY=VALUE`` each; None for none.

    Returns
    -------
    dict
        Each key to its value, in the order given.

    Raises
    ------
    ConfigError
        As :func:`parse_override`, or a key given twice.
    """
    updates: dict[str, Any] = {}
    for text in texts or ():
        key, value = parse_override(text)
        if key in updates:
            raise ConfigError(
                f"--set {key} is given twice ({updates[key]!r} and {value!r}); give it once"
            )
        updates[key] = value
    return updates


def plain_number(value: Any) -> int | float | None:
    """``value`` as a Python int or float when it is a real number (a numpy integer or float
    too, as a notebook's ``np.arange`` gives), else None (text, booleans, arrays)."""
    if isinstance(value, bool | np.bool_):
        return None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    return value if isinstance(value, int | float) else None


def _resolve_alias(key: str, value: Any) -> tuple[str, Any]:
    if key not in FACTOR_ALIASES:
        return key, value
    field, scale, unit = FACTOR_ALIASES[key]
    number = plain_number(value)
    if number is None and isinstance(value, str):  # "1e-13", as the fields take it (their
        try:  # pydantic reads a number's text; the aliases had refused it: a review)
            number = csv_float(value.strip())
        except ValueError:
            number = None
        if number is not None and not math.isfinite(number):
            number = None
    if number is None:
        what = "a number" + ("" if unit == "-" else f" in {unit}")
        raise ConfigError(f"{key} (= {field}): expected {what}, got {value!r}")
    value = number
    lo_hi = _ALIAS_RANGES.get(key)
    if lo_hi is not None and not lo_hi[0] < value < lo_hi[1]:
        raise ConfigError(
            f"{key} (= {field}): must be above {lo_hi[0]:g} and below {lo_hi[1]:g} {unit}, "
            f"got {value}"
            + (" (a pad without fibres has no plateau to carry the load)" if value == 0 else "")
        )
    if key == "A" and 0.0 < value < 1.0:
        warn_unit(
            f"A is in %: A = {value:g} is {value:g} % fibres; for {100 * value:g} % give "
            f"A = {100 * value:g}"
        )
    return field, value * scale


def _check_cycle_name(config: SimulationConfig, given: Mapping[str, str], data: Any) -> None:
    """Refuse ``cycle.name`` set alone to a shipped cycle's name other than the cycle's: the
    name labels the cycle the configuration holds, it does not load one (an API review:
    ``{"cycle.name": "example_trace"}`` ran the paper's 170 stops under the trace's name)."""
    name = data.get("cycle", {}).get("name") if "cycle.name" in given else None
    loads = {"cycle.blocks", "cycle.trace_file"} & set(given)
    if not isinstance(name, str) or name == config.cycle.name or loads:
        return
    from brakeca.traces import available_cycles

    if name in available_cycles():
        raise ConfigError(
            f"override {given['cycle.name']}: {name!r} is a shipped cycle, but cycle.name only "
            f"labels the cycle this configuration holds ({config.cycle.name!r}); to run "
            f"{name!r}, use --cycle {name} (brakeca.traces.with_cycle(config, {name!r}) from "
            "Python)"
        )


def _rename_cycle(config: SimulationConfig, given: Mapping[str, str], data: Any) -> None:
    """A cycle given anew without a name of its own does not keep the old cycle's: other
    blocks are the cycle ``"custom"``, a trace in place of blocks is named by its file's
    stem (an API review: one block of one's own ran, and was recorded, as cycle 'paper').
    A trace file set over a trace keeps the name: it may be the same file, read elsewhere."""
    cycle = data.get("cycle")
    if "cycle.name" in given or not isinstance(cycle, dict):
        return
    old = config.cycle
    trace = cycle.get("trace_file")
    if "cycle.trace_file" in given and not old.trace_file and isinstance(trace, str) and trace:
        cycle["name"] = Path(trace).stem
    elif "cycle.blocks" in given and _as_blocks(cycle.get("blocks")) != old.blocks:
        cycle["name"] = "custom"


def _as_blocks(blocks: Any) -> tuple[BrakeBlock, ...] | None:
    """``blocks`` as validated :class:`BrakeBlock` s (the blocks themselves, a tuple of them,
    their dicts), or None where they are not valid (the configuration's check says why)."""
    try:
        return tuple(
            b if isinstance(b, BrakeBlock) else BrakeBlock.model_validate(b) for b in blocks
        )
    except (TypeError, ValueError):  # (pydantic's ValidationError is a ValueError)
        return None


def apply_overrides(config: SimulationConfig, updates: Mapping[str, Any]) -> SimulationConfig:
    """Return a validated copy of ``config`` with dotted-key (or factor-name) updates applied.

    Parameters
    ----------
    config
        The base configuration.
    updates
        Mapping of dotted keys (``"wear.specific_wear_rate"``) or factor names (``S``, ``WP``,
        ``WR``, ``A`` in the paper's units, A in percent) to values.

    Raises
    ------
    ConfigError
        Unknown key, a value outside its allowed range, or two keys for one field (a factor
        name and its dotted key); the message names the field.
    TypeError
        ``updates`` is not a mapping, or a key is not text.

    Returns
    -------
    SimulationConfig
        The validated copy; ``config`` is unchanged.
    """
    if not isinstance(updates, Mapping):
        raise TypeError(
            "updates: expected a mapping of field (or factor name) to value, e.g. "
            f"{{'WP': 1e-13, 'friction.mu_0': 0.5}}, got {type(updates).__name__}"
        )
    data = config.to_dict()
    given: dict[str, str] = {}  # field -> the key that set it
    for key, value in updates.items():
        if not isinstance(key, str):  # ({1: 2} gave an AttributeError: a fuzz review)
            raise TypeError(
                "updates: expected field names (dotted, e.g. 'wear.specific_wear_rate') or "
                f"factor names as keys, got {key!r}"
            )
        path, value = _resolve_alias(key, value)
        if path in given:
            raise ConfigError(
                f"override {key}: {given[path]} sets the same field ({path}); give one of them"
            )
        given[path] = key
        parts = path.split(".")
        node = data
        known: dict[str, Any] | None = SimulationConfig.model_fields
        for depth, part in enumerate(parts):
            last = depth == len(parts) - 1
            if known is not None and part not in known:
                allowed = ", ".join(sorted(known)) if known else "(none)"
                close = _close_field(key)
                raise ConfigError(
                    f"override {key}: unknown field {'.'.join(parts[: depth + 1])!r}; "
                    + (f"did you mean {close!r}? " if close else "")
                    + f"allowed here: {allowed} (or a factor name: {', '.join(FACTOR_ALIASES)})"
                )
            if last:
                node[part] = value
            else:
                node = node.setdefault(part, {})
                if not isinstance(node, dict):
                    raise ConfigError(f"override {key}: {part!r} is not a section")
                ann = known[part].annotation if known is not None else None
                known = getattr(ann, "model_fields", None)
    _check_cycle_name(config, given, data)
    _rename_cycle(config, given, data)
    if "cycle.trace_file" in given and "cycle.trace_sha256" not in given:
        # the digest was the old file's: a new trace would be refused as 'changed' (a
        # review: --set cycle.trace_file on a configuration file that records its trace)
        data.get("cycle", {}).pop("trace_sha256", None)
    # a factor's field named by the name it was given as
    heads = {path: f"override {key} (= {path})" for path, key in given.items() if key != path}
    updated = SimulationConfig.from_dict(data, source="override", heads=heads)
    for (field, _), note in unit_notes_by_field(updated).items():
        # a value this update set that reads like a slip of unit, also by its section
        # (with_cycle sets the whole cycle: a diff review)
        if any(field == g or field.startswith(f"{g}.") for g in given):
            warn_unit(note)
    return updated


def _field_paths(model: Any = None, prefix: str = "") -> list[str]:
    """The dotted names of every field of :class:`SimulationConfig` that holds a value
    (``"friction.mu_0"``), not a section."""
    paths = []
    for name, info in (model or SimulationConfig).model_fields.items():
        inner = getattr(info.annotation, "model_fields", None)
        if inner is not None:
            paths += _field_paths(info.annotation, f"{prefix}{name}.")
        else:
            paths.append(f"{prefix}{name}")
    return paths


def _close_field(key: str) -> str | None:
    """The field or factor name a misspelt ``key`` of :meth:`SimulationConfig.with_updates`
    most likely means: one that differs only in case (``"wp"``), the field of that name
    in its section (``"mu_0"``: ``"friction.mu_0"``), or a close spelling
    (``"friction.mu0"``); None where none is close (an API review: the loaders said "did
    you mean", with_updates did not)."""
    names = [*FACTOR_ALIASES, *_field_paths()]
    alike = [n for n in names if n.lower() == key.lower()]
    if alike:
        return alike[0]
    leaf = [n for n in names if n.rsplit(".", 1)[-1].lower() == key.rsplit(".", 1)[-1].lower()]
    if len(leaf) == 1:
        return leaf[0]
    close = difflib.get_close_matches(key, names, n=1, cutoff=0.75)
    return close[0] if close else None


def is_run_file(path: Path) -> bool:
    """Whether ``path`` is a netCDF (HDF5) file, as a run file is, by its first bytes."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError:
        return False
    return head.startswith((b"\x89HDF\r\n\x1a\n", b"CDF"))


class RunFileSettings(NamedTuple):
    """What a run file holds besides its results that running it again takes
    (:func:`run_file_settings`)."""

    config: str  # its configuration, TOML
    seed: int  # its seed; -1 for a run made from a random generator's state
    maps: list[int]  # the stops it kept maps after
    emissions: str | None  # the --emissions it was made with (pm10_factors), None: defaults


def run_file_settings(path: Path) -> RunFileSettings:
    """The configuration, seed, kept maps and emission factors of the run file ``path``, read
    at once without its results; ConfigError where it cannot be read or is a netCDF file
    that is no run's (a campaign.nc, say)."""
    import xarray as xr

    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            attrs = dict(ds.attrs)
            maps = [int(s) for s in ds["map_stop"].values] if "map_stop" in ds.coords else []
    except Exception as exc:  # (h5py's and xarray's errors alike)
        raise ConfigError(f"{path}: cannot read the run file: {exc}") from None
    config, factors = attrs.get("config"), attrs.get("pm10_factors")
    if not isinstance(config, str):
        raise ConfigError(f"{path}: a netCDF file without a run's configuration (config)")
    try:
        seed = int(attrs.get("seed", -1))
    except (TypeError, ValueError):  # (a traceback had followed: a security review)
        raise ConfigError(
            f"{path}: the run file's seed {str(attrs.get('seed'))[:40]!r} is not a whole number"
        ) from None
    return RunFileSettings(
        config,
        seed,
        maps,
        factors if isinstance(factors, str) and factors else None,
    )


def load_config(path: str | Path) -> SimulationConfig:
    """Load and validate a configuration TOML file, or a run file's configuration.

    Parameters
    ----------
    path
        A whole configuration in TOML (``brakeca config > FILE`` writes the paper's), UTF-8,
        or a run file (``.nc``), whose run's configuration is read (to run it again).

    Returns
    -------
    SimulationConfig
        The validated configuration (SI units inside; see each field's description).

    Raises
    ------
    ConfigError
        The file cannot be read, is not TOML, or a field is unknown, missing or out of its
        range; the message names the file and the field.
    """
    path = Path(path)
    if is_run_file(path):  # a run file's own configuration (a provenance review)
        text = run_file_settings(path).config
        config = SimulationConfig.from_toml(text, source=f"{path} (its config attribute)")
        for note in unit_notes(config):
            warn_unit(f"{path}: {note}")
        return config
    try:
        text = path.read_text(encoding="utf-8-sig")  # a BOM (Windows editors) is not TOML
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read: {exc.strerror}") from None
    except UnicodeDecodeError as exc:  # as a design file's message
        raise ConfigError(f"{path}: cannot read: {exc} (a TOML file is UTF-8 text)") from None
    try:
        config = SimulationConfig.from_toml(text, source=str(path))
    except ConfigError as exc:
        if _is_design(text):  # in one line (a command-line review: nine lines of errors)
            raise ConfigError(
                f"{path}: a design (it has [[factors]]), not a simulation configuration: run "
                f"it with 'brakeca run {path} -o FOLDER' ('brakeca design {path}' shows its "
                "tests)"
            ) from None
        if f"{path}: cycle: required field is missing" not in str(exc).splitlines():
            raise
        # most likely a file of changes only: every section but the cycle has defaults
        raise ConfigError(
            f"{exc}\n{path}: a configuration file is a whole configuration, not changes to a "
            "preset: 'brakeca config > FILE' writes the paper's to edit ('--set KEY=VALUE' "
            "changes one field of a preset)"
        ) from None
    for note in unit_notes(config):
        warn_unit(f"{path}: {note}")
    return _anchored_trace(config, path)


def _is_design(text: str) -> bool:
    """Whether TOML ``text`` reads as a design file: ``factors`` (or a run table) at its top
    level."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return False
    return "factors" in data or "runs" in data


def _anchored_trace(config: SimulationConfig, path: Path) -> SimulationConfig:
    """``config`` (loaded from the file ``path``) with a speed trace given by a relative
    ``cycle.trace_file`` read next to the file where it is there (as a design's
    ``base_config`` is; else from the current folder, as before), and, where the file gives
    no ``cycle.trace_sha256``, recorded as ``--cycle`` records it: its absolute path and the
    SHA-256 of its content, and its name unless the file names the cycle itself (other than
    the preset's ``paper`` or the default ``custom``). A black-box review: a trace set in a
    configuration file ran under the name 'paper', without its digest, and from the folder
    the command ran in."""
    cyc = config.cycle
    trace = cyc.trace_file
    if not trace:
        return config
    here = path.parent / trace
    chosen = here if not Path(trace).is_absolute() and here.is_file() else Path(trace)
    if not chosen.is_file():  # a shipped trace's name, or a missing file (configured_cycle)
        return config
    if cyc.trace_sha256 is not None:  # recorded: only where to read it
        if chosen == Path(trace):
            return config
        return config.with_updates(
            {"cycle.trace_file": str(chosen.resolve()), "cycle.trace_sha256": cyc.trace_sha256}
        )
    from brakeca.traces import with_cycle

    try:
        recorded = with_cycle(config, chosen, speed_unit=cyc.trace_speed_unit)
    except ConfigError as exc:
        raise ConfigError(f"{path}: cycle.trace_file {trace}: {exc}") from None
    if cyc.name not in ("paper", "custom"):  # the file's own name for its trace (not an
        # override: a name that is a shipped cycle's is the file's to give)
        named = recorded.cycle.model_copy(update={"name": cyc.name})
        recorded = recorded.model_copy(update={"cycle": named})
    return recorded
