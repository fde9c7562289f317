"""Brake PM10 in mg/km from a run's emitted wear volume, with the Euro 7 limits beside it.

The simulation gives the wear volume that left the simulated band of one pad over the cycle.
The chain to a vehicle's airborne PM10 per kilometre, every factor a parameter of
:class:`EmissionParameters` with its default, literature range and source::

    V_pad     = V_band A_pad / A_band                 the band is a sample of the pad
    V_front   = V_pad n_pads n_brakes                 both pads of both front brakes
    V_vehicle = V_front / f_front                     f_front: front axle's share of emissions
    m         = V_vehicle rho (1 + r_disc)            rho: debris density, r_disc: disc/pad mass
    m_PM10    = m f_air f_PM10                        airborne share, PM10 share of airborne
    E         = m_PM10 / distance                     [mg/km]

The low/high band takes every factor at the end of its range that lowers/raises E at once: an
envelope of what the parameter ranges allow, not a statistical interval. These factors are
approximate and material dependent; the band is the honest way to show a result against the
limits, never as a bare pass or fail.

The figure is a **model estimate of the order of magnitude**, not a measurement: the band
spans these factors only, not the wear model's own parameters (the specific wear rate WP
moves the emitted volume a hundredfold across the paper's levels, and no pad's WP is
calibrated here), nor disc wear (counted only through ``r_disc``, 0 by default: pad material
alone), temperature, or the bedding UN GTR No. 24 prescribes before its measurement. It is
no evidence of meeting or missing a Euro 7 limit, which applies to the GTR 24 WLTP-Brake
result of a type-approval test (:data:`CAVEAT`).

References
----------
Regulation (EU) 2024/1257 (Euro 7), Annex I: brake PM10 limits. UN GTR No. 24: the
WLTP-Brake cycle and the measurement. T. Grigoratos and G. Martini, "Brake wear particle
emissions: a review", Environ. Sci. Pollut. Res. 22 (2015) 2491-2504. A. Garg et al., "Brake
wear particulate matter emissions", Environ. Sci. Technol. 34 (2000) 4463-4469. P. G. Sanders
et al., "Airborne brake wear debris: size distributions, composition, and a comparison of
dynamometer and vehicle tests", Environ. Sci. Technol. 37 (2003) 4060-4069.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, ValidationError, model_validator

from brakeca.config import ConfigError, _Frozen, format_validation_error

if TYPE_CHECKING:  # pragma: no cover
    from brakeca.results import RunResult

__all__ = [
    "CAVEAT",
    "EURO7_LIMITS",
    "EURO7_PM10_LIMIT",
    "EURO7_PM10_LIMIT_PEV",
    "EURO7_REFERENCE",
    "PM10_COLUMNS",
    "EmissionParameters",
    "PM10Estimate",
    "load_emissions",
    "pm10_band",
    "pm10_from_run",
    "pm10_mg_per_km",
]

#: Where the limits come from.
EURO7_REFERENCE = (
    "Regulation (EU) 2024/1257 (Euro 7), Annex I; measured on the WLTP-Brake cycle of UN GTR No. 24"
)
#: What every PM10 figure brakeca prints comes with (the report, ``brakeca simulate``, the
#: run file's comment, ``tables/pm10.csv``'s README): an emissions review found nothing that
#: said it was not compliance evidence.
CAVEAT = (
    "a model estimate of the order of magnitude, not a UN GTR No. 24 measurement nor evidence "
    "of meeting or missing a Euro 7 limit: its band spans the emission factors only (the "
    "central figure pad material alone, the high end up to twice its mass from the disc), "
    "not the wear model's parameters (WP moves the emitted volume a hundredfold across the "
    "paper's levels), temperature or bedding"
)
#: Euro 7 brake PM10 limit for M1 cars other than pure battery-electric ones [mg/km per
#: vehicle] (the regulation lowers it later, and gives vans, N1, values of their own: its
#: Annex I).
EURO7_PM10_LIMIT = 7.0
#: Euro 7 brake PM10 limit for pure battery-electric M1 cars [mg/km per vehicle].
EURO7_PM10_LIMIT_PEV = 3.0
#: The columns of a campaign's PM10 table on a speed trace (``tables/pm10.csv``, written by
#: ``brakeca.study``; not columns of ``summary.csv``): PM10 low, central and high [mg/km].
PM10_COLUMNS: tuple[str, str, str] = ("PM10_low_mg_km", "PM10_mg_km", "PM10_high_mg_km")
#: The limits by vehicle, [mg/km].
EURO7_LIMITS: dict[str, float] = {
    "M1 car other than pure battery-electric": EURO7_PM10_LIMIT,
    "M1 car, pure battery-electric": EURO7_PM10_LIMIT_PEV,
}

#: Whether E rises (+1) or falls (-1) with each ranged factor.
_DIRECTION: dict[str, int] = {
    "debris_density": 1,
    "airborne_fraction": 1,
    "pm10_share": 1,
    "disc_to_pad_mass_ratio": 1,
    "front_emission_share": -1,
}


def _end_problem(field: Any, end: float) -> str | None:
    """The interval the field ``field`` (a pydantic ``FieldInfo``) allows, with its unit, when
    ``end`` is not finite or lies outside it (a range's end must be a value its factor may
    take: the factor's own ``Field`` bounds, so that the two cannot drift apart); None when
    ``end`` lies within it."""
    import annotated_types as at

    low: Any = -math.inf
    high: Any = math.inf
    low_in = high_in = False
    for bound in field.metadata:
        if isinstance(bound, at.Ge):
            low, low_in = bound.ge, True
        elif isinstance(bound, at.Gt):
            low, low_in = bound.gt, False
        elif isinstance(bound, at.Le):
            high, high_in = bound.le, True
        elif isinstance(bound, at.Lt):
            high, high_in = bound.lt, False
    above = end > low or (low_in and end == low)
    below = end < high or (high_in and end == high)
    if math.isfinite(end) and above and below:
        return None
    unit = (field.description or "").split("]", 1)[0].lstrip("[")
    return f"{'[' if low_in else '('}{low:g}, {high:g}{']' if high_in else ')'}" + (
        "" if unit in ("", "-") else f" {unit}"
    )


class EmissionParameters(_Frozen):
    """The factors from emitted band volume to vehicle PM10, each with a (low, high) range.

    Ranges are approximate literature spans, not confidence intervals; see ``docs/cycles.md``.
    Validated as the configuration is (frozen, no unknown field, no ``true`` for a number,
    no infinity).
    """

    debris_density: float = Field(
        2600.0,
        gt=0,
        description=(
            "[kg/m^3] density of the worn pad material rho: the friction material's bulk "
            "density, not the particles' (iron oxides, 5000-7000 kg/m^3, would overstate "
            "it): roughly 2000 kg/m^3 for organic to 4000 kg/m^3 for semi-metallic pads; "
            "approximate, from data-sheet values"
        ),
    )
    debris_density_range: tuple[float, float] = Field(
        (2000.0, 4000.0), description="[kg/m^3] low and high debris density of the envelope"
    )
    airborne_fraction: float = Field(
        0.5,
        gt=0,
        le=1,
        description=(
            "[-] share f_air of the wear mass that becomes airborne (the rest stays on the "
            "brake, wheel or road); reported ~0.3-0.6 (Garg et al. 2000; Sanders et al. 2003; "
            "Grigoratos & Martini 2015), far less for some organic (NAO) pads (2-21 % in "
            "Hagino et al. 2016), whose airborne_fraction_range an --emissions file sets"
        ),
    )
    airborne_fraction_range: tuple[float, float] = Field(
        (0.3, 0.6), description="[-] low and high airborne share of the envelope"
    )
    pm10_share: float = Field(
        0.8,
        gt=0,
        le=1,
        description=(
            "[-] share f_PM10 of the airborne mass in particles below 10 um; reported ~0.6-0.9 "
            "(same sources)"
        ),
    )
    pm10_share_range: tuple[float, float] = Field(
        (0.6, 0.9), description="[-] low and high PM10 share of the envelope"
    )
    disc_to_pad_mass_ratio: float = Field(
        0.0,
        ge=0,
        description=(
            "[-] disc wear mass per pad wear mass r_disc. The model tracks pad wear only, so "
            "the default 0 counts pad material only; cast-iron discs often lose a comparable "
            "mass (rough, pairing dependent), hence the range"
        ),
    )
    disc_to_pad_mass_ratio_range: tuple[float, float] = Field(
        (0.0, 2.0), description="[-] low and high disc-to-pad wear mass ratio of the envelope"
    )
    front_emission_share: float = Field(
        0.7,
        gt=0,
        le=1,
        description=(
            "[-] front axle's share f_front of the vehicle's brake emissions; if emissions "
            "follow friction work, the front brake force share (0.6-0.8 for cars, Limpert 2011)"
        ),
    )
    front_emission_share_range: tuple[float, float] = Field(
        (0.6, 0.8), description="[-] low and high front-axle share of the envelope"
    )
    pads_per_brake: int = Field(
        2, ge=1, le=8, description="[-] pads of one brake; like brake.pads_per_brake"
    )
    brakes_per_axle: int = Field(2, ge=1, le=4, description="[-] brakes on the front axle")

    @model_validator(mode="after")
    def _in_ranges(self) -> EmissionParameters:
        for name in _DIRECTION:
            value = getattr(self, name)
            lo, hi = getattr(self, f"{name}_range")
            for end in (lo, hi):
                if (text := _end_problem(type(self).model_fields[name], end)) is not None:
                    raise ValueError(f"{name}_range: its ends must lie in {text}, got [{lo}, {hi}]")
            if not lo <= hi:
                raise ValueError(f"{name}_range: low {lo} must not exceed high {hi}")
            if not lo <= value <= hi:
                default = name not in self.model_fields_set
                default_range = f"{name}_range" not in self.model_fields_set
                raise ValueError(
                    f"{name} = {value}{' (its default)' if default else ''} lies outside its "
                    f"range{' (the default)' if default_range else ''} [{lo}, {hi}]"
                    + (
                        f": give {name} within the range too"
                        if default
                        else f": give {name}_range too, as [low, high] about it"
                        if default_range
                        else ""
                    )
                    + (  # g/cm³ (mg/mm³) for kg/m³ (a review: 2.6 for 2600)
                        f" (debris_density is in kg/m³: {value:g} g/cm³ is {value * 1e3:g} kg/m³)"
                        if name == "debris_density" and 0.5 <= value <= 20.0
                        else " (debris_density_range is in kg/m³, like debris_density)"
                        if name == "debris_density" and 0.5 <= lo <= hi <= 20.0
                        else ""
                    )
                )
        return self

    @classmethod
    def from_dict(cls, data: dict[str, Any], *, source: str = "emissions") -> EmissionParameters:
        """Validate a mapping; errors name the field (``ConfigError``).

        Parameters
        ----------
        data
            Field names to values, in the fields' units (densities [kg/m^3], shares and
            ratios [-], counts [-]); missing fields take their defaults.
        source
            What the error messages' lines begin with (the file or option the mapping came
            from).

        Returns
        -------
        EmissionParameters
            The validated parameters.

        Raises
        ------
        ConfigError
            (A ``ValueError``.) An unknown field, a value outside its allowed bounds, a range
            whose low end exceeds its high end, or a factor outside its own range; the
            message names the field.
        """
        try:
            return cls.model_validate(dict(data))
        except ValidationError as exc:
            # the class: a bound's error gives the whole range, an unknown key the near
            # names (a fuzz review)
            raise ConfigError(format_validation_error(exc, source, cls)) from None

    def factors_text(self) -> str:
        """The chain's factors as a sentence for a report, each with its range, e.g.
        ``"debris density 2600 kg/m³ (2000 to 4000), ..."``."""
        ranged = [
            ("debris density", "debris_density", " kg/m³"),
            ("airborne share", "airborne_fraction", ""),
            ("PM10 share of the airborne", "pm10_share", ""),
            ("disc-to-pad wear mass ratio", "disc_to_pad_mass_ratio", ""),
            ("front axle's share of the emissions", "front_emission_share", ""),
        ]
        parts = [
            f"{label} {getattr(self, name):.4g}{unit} "
            f"({getattr(self, name + '_range')[0]:.4g} to {getattr(self, name + '_range')[1]:.4g})"
            for label, name, unit in ranged
        ]
        pads, brakes = self.pads_per_brake, self.brakes_per_axle
        parts.append(
            f"{pads} pad{'s' if pads != 1 else ''} a brake, {brakes} front "
            f"brake{'s' if brakes != 1 else ''}"
        )
        return ", ".join(parts)

    @property
    def pm10_fraction(self) -> float:
        """Share of the wear mass emitted as airborne PM10, f_air f_PM10 [-]."""
        return self.airborne_fraction * self.pm10_share

    def at(self, end: Literal["low", "high"]) -> EmissionParameters:
        """These parameters with every ranged factor at the end that gives the low/high E.

        Parameters
        ----------
        end
            ``"low"``: each ranged factor at the end of its range that lowers the PM10
            emission E; ``"high"``: at the end that raises it.

        Returns
        -------
        EmissionParameters
            A copy with ``debris_density``, ``airborne_fraction``, ``pm10_share``,
            ``disc_to_pad_mass_ratio`` and ``front_emission_share`` moved to those ends (the
            ranges and the pad and brake counts unchanged).
        """
        updates: dict[str, float] = {}
        for name, sign in _DIRECTION.items():
            lo, hi = getattr(self, f"{name}_range")
            rising = (end == "high") == (sign > 0)
            updates[name] = hi if rising else lo
        return self.model_copy(update=updates)


def pm10_mg_per_km(
    emitted_volume_band: float,
    *,
    band_area: float,
    pad_area: float,
    distance: float,
    params: EmissionParameters | None = None,
) -> float:
    """Vehicle brake PM10 per distance [mg/km] from the volume a simulated band emitted.

    Parameters
    ----------
    emitted_volume_band
        Wear volume that left the simulated band over the cycle [m^3].
    band_area
        Area of the simulated band A_band [m^2].
    pad_area
        Area of the whole pad A_pad [m^2].
    distance
        Distance of the cycle the volume belongs to [m].
    params
        The factors of the chain (default :class:`EmissionParameters`).

    Returns
    -------
    float
        Airborne PM10 of the vehicle's brakes [mg/km].

    Raises
    ------
    ValueError
        If ``band_area``, ``pad_area`` or ``distance`` is not positive, or the emitted volume
        is negative.

    Examples
    --------
    1 mm³ emitted by the paper's band (1744 mm² of a 5080 mm² pad) over 100 km: 2.91 mm³
    from the pad, 7.57 mg at 2600 kg/m³, 3.03 mg of it airborne PM10 (0.5 × 0.8), four pads
    on the front axle, which emits 70 % of the vehicle's:

    >>> from brakeca.emissions import pm10_mg_per_km
    >>> pm10 = pm10_mg_per_km(1e-9, band_area=1.7442e-3, pad_area=5.08e-3, distance=100e3)
    >>> round(pm10, 4)  # [mg/km]
    0.1731
    """
    p = params or EmissionParameters()
    if not (band_area > 0 and pad_area > 0 and distance > 0):
        raise ValueError(
            f"band_area, pad_area and distance must be positive, got {band_area}, {pad_area}, "
            f"{distance}"
        )
    if emitted_volume_band < 0:
        raise ValueError(f"emitted volume must not be negative, got {emitted_volume_band}")
    pad_volume = emitted_volume_band * pad_area / band_area
    vehicle_volume = pad_volume * p.pads_per_brake * p.brakes_per_axle / p.front_emission_share
    mass = vehicle_volume * p.debris_density * (1.0 + p.disc_to_pad_mass_ratio)  # [kg]
    pm10 = mass * p.pm10_fraction
    return pm10 * 1e6 / (distance / 1000.0)  # kg -> mg, m -> km


@dataclass(frozen=True)
class PM10Estimate:
    """Vehicle brake PM10 with the band the parameter ranges allow.

    Attributes
    ----------
    low, central, high : float
        PM10 with every factor at the lowering end, at its default, at the raising end
        [mg/km].
    distance : float
        Distance the emission is spread over [m].
    params : EmissionParameters
        The parameters used.
    """

    low: float
    central: float
    high: float
    distance: float
    params: EmissionParameters

    def position(self, limit: float) -> Literal["below", "straddles", "above"]:
        """Where the band lies against a limit [mg/km]: wholly below, across it, wholly above.

        Parameters
        ----------
        limit
            The PM10 limit [mg/km], e.g. :data:`EURO7_PM10_LIMIT`.

        Returns
        -------
        str
            ``"below"`` if ``high < limit``, ``"above"`` if ``low > limit``, else
            ``"straddles"`` (a band end equal to the limit straddles it).
        """
        if self.high < limit:
            return "below"
        if self.low > limit:
            return "above"
        return "straddles"

    def describe(self, source: str | None = None) -> list[str]:
        """Lines for a report: the estimate for the whole vehicle, its band, the factors,
        and where the band lies against each Euro 7 limit (no bare pass/fail).

        Parameters
        ----------
        source
            Where the factors came from (a file's path), named in the factors' line; None:
            the defaults (with the run's pads and front share), and the line says how to
            give others.

        Returns
        -------
        list of str
            The lines.
        """
        p = self.params
        pads = p.pads_per_brake * p.brakes_per_axle
        lines = [
            f"vehicle brake PM10 ~ {self.central:.3g} mg/km (band {self.low:.3g} to "
            f"{self.high:.3g} mg/km from the parameter ranges) over "
            f"{self.distance / 1000.0:.4g} km: the simulated band's emission scaled to its "
            f"pad, to the front axle's {pads} pads and by the front axle's share "
            f"{p.front_emission_share:.3g} to the vehicle",
            f"factors: {p.factors_text()} "
            + (
                f"(from {source})"
                if source is not None
                else "(brakeca.emissions.EmissionParameters; change them with --emissions FILE, "
                "docs/cycles.md)"
            ),
        ]
        words = {
            "below": "the model's whole band lies below",
            "straddles": "the model's band straddles",
            "above": "the model's whole band lies above",
        }
        for who, limit in EURO7_LIMITS.items():
            lines.append(f"Euro 7 limit {limit:g} mg/km ({who}): {words[self.position(limit)]} it")
        lines.append(f"limits: {EURO7_REFERENCE}")
        lines.append(f"note: {CAVEAT}")
        if self.distance < SHORT_DISTANCE:
            lines.append(
                f"note: over {self.distance / 1000.0:.3g} km only; the limits hold for the "
                "WLTP-Brake cycle's 192 km, whose mix of stops a short trace does not have"
            )
        return lines


#: Below this distance [m] a trace's mg/km is compared with the Euro 7 limits with a note:
#: they hold for the WLTP-Brake cycle, 192 km of mixed driving (UN GTR No. 24).
SHORT_DISTANCE = 10_000.0


def pm10_band(
    emitted_volume_band: float,
    *,
    band_area: float,
    pad_area: float,
    distance: float,
    params: EmissionParameters | None = None,
) -> PM10Estimate:
    """(low, central, high) brake PM10 [mg/km]; arguments as :func:`pm10_mg_per_km`.

    Parameters
    ----------
    emitted_volume_band
        Wear volume that left the simulated band over the cycle [m^3].
    band_area
        Area of the simulated band A_band [m^2].
    pad_area
        Area of the whole pad A_pad [m^2].
    distance
        Distance of the cycle the volume belongs to [m].
    params
        The factors of the chain and their ranges (default :class:`EmissionParameters`).

    Returns
    -------
    PM10Estimate
        PM10 with the factors at the lowering ends, at their values and at the raising ends
        [mg/km] (:meth:`EmissionParameters.at`), with ``distance`` [m] and ``params``.

    Raises
    ------
    ValueError
        As :func:`pm10_mg_per_km`: an area or the distance not positive, or the volume
        negative.

    Examples
    --------
    >>> from brakeca.emissions import pm10_band
    >>> estimate = pm10_band(1e-9, band_area=1.7442e-3, pad_area=5.08e-3, distance=100e3)
    >>> [round(v, 3) for v in (estimate.low, estimate.central, estimate.high)]  # [mg/km]
    [0.052, 0.173, 1.258]
    """
    p = params or EmissionParameters()
    areas = {"band_area": band_area, "pad_area": pad_area, "distance": distance}
    return PM10Estimate(
        low=pm10_mg_per_km(emitted_volume_band, **areas, params=p.at("low")),
        central=pm10_mg_per_km(emitted_volume_band, **areas, params=p),
        high=pm10_mg_per_km(emitted_volume_band, **areas, params=p.at("high")),
        distance=float(distance),
        params=p,
    )


def pm10_from_run(
    result: RunResult,
    distance: float,
    params: EmissionParameters | None = None,
) -> PM10Estimate:
    """PM10 band of a run: its total emitted band volume over ``distance`` [m].

    Parameters
    ----------
    result
        A run (``emitted_volume`` per stop, summed over the stops it simulated).
    distance
        Distance the simulated stops belong to [m], e.g.
        :attr:`brakeca.traces.CycleSource.distance`.
    params
        Emission factors (default :class:`EmissionParameters`). The fields they do not set
        (``model_fields_set``: those given to the constructor or to
        :meth:`EmissionParameters.from_dict`) take the run's values where the run has them:
        ``pads_per_brake`` the run's ``brake.pads_per_brake`` and, on a speed trace, the
        front axle's share of the emissions ``front_emission_share`` the run's front brake
        force share ``cycle.trace.front_brake_share`` (emissions following friction work;
        its range the default's spread about it, 0.1 either side, within (0, 1]; unless the
        share or its range is given): the run's front brake was loaded with that share, so a
        fixed 0.7 would scale a front brake given 0.9 of the braking up to a vehicle that
        brakes more than it does. Parameters whose every field is set (another estimate's
        ``params``, say) keep theirs, so pass the factors you mean, not another run's.

    Returns
    -------
    PM10Estimate
        Low, central and high PM10 [mg/km] of the run's band volume [m^3] scaled from the
        band's area (:func:`brakeca.geometry.make_grid`) to ``brake.pad_area`` [m^2].

    Raises
    ------
    ValueError
        If ``distance`` is not positive (as :func:`pm10_mg_per_km`).
    """
    from brakeca.geometry import make_grid

    config = result.config
    given = params or EmissionParameters()
    mine = given.model_fields_set  # (none for the default)
    runs: dict[str, Any] = {}  # the run's values of the fields the caller left unset
    if "pads_per_brake" not in mine:
        runs["pads_per_brake"] = config.brake.pads_per_brake
    if config.cycle.trace_file and not mine & {
        "front_emission_share",
        "front_emission_share_range",
    }:
        phi = config.cycle.trace.front_brake_share
        lo, hi = EmissionParameters.model_fields["front_emission_share_range"].default
        default = EmissionParameters.model_fields["front_emission_share"].default
        # the default's spread (0.6 to 0.8 about 0.7) moved to the run's share, within (0, 1]
        runs["front_emission_share"] = phi
        runs["front_emission_share_range"] = (
            max(lo + (phi - default), 0.5 * phi),  # lo itself at the default share
            min(hi + (phi - default), 1.0),
        )
    params = EmissionParameters.model_validate({**given.model_dump(), **runs})
    volume = float(result.dataset["emitted_volume"].sum())
    return pm10_band(
        volume,
        band_area=make_grid(config).area,
        pad_area=config.brake.pad_area,
        distance=distance,
        params=params,
    )


def load_emissions(path: str | Path) -> EmissionParameters:
    """Read emission factors from a TOML file: :class:`EmissionParameters`' fields, at the
    top level or in an ``[emissions]`` table; a field left out keeps its default (or, for
    ``pads_per_brake`` and the front axle's share, the run's: :func:`pm10_from_run`).

    Parameters
    ----------
    path
        The file, UTF-8 TOML, e.g. ``airborne_fraction = 0.4`` and
        ``airborne_fraction_range = [0.3, 0.5]`` (densities [kg/m^3], shares and ratios [-]).

    Returns
    -------
    EmissionParameters
        The validated factors.

    Raises
    ------
    ConfigError
        The file cannot be read or is not TOML, or a field is unknown or out of its range
        (a factor outside its own range included); the message names the file and the field.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from brakeca.emissions import load_emissions
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp) / "emissions.toml"
    ...     _ = path.write_text("[emissions]\\nairborne_fraction = 0.4\\n")
    ...     load_emissions(path).airborne_fraction
    0.4
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: cannot read: {exc} (a TOML file is UTF-8 text)") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None
    if isinstance(data.get("emissions"), dict):
        others = sorted(set(data) - {"emissions"})
        if others:
            raise ConfigError(
                f"{path}: the factors go in one [emissions] table or at the top level, not "
                f"both (also: {', '.join(others)})"
            )
        data = data["emissions"]
    return EmissionParameters.from_dict(data, source=str(path))
