"""Unit tests of brakeca.design: factorial expansion, test order, seeds, run ids, validation."""

from __future__ import annotations

import copy
import itertools
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from brakeca.analysis import as_factor
from brakeca.config import ConfigError
from brakeca.design import (
    Design,
    Factor,
    design_from_dict,
    execution_order,
    load_design,
    point_seed,
    quick_config,
    run_id,
    run_id_for,
)
from brakeca.presets import design_path, load_preset

# Table 2 of Wahlström (2016): S varies fastest, then WP, WR, A.
PAPER_LEVELS = {
    "S": (0.0, 1.0),
    "WP": (1e-15, 1e-14, 1e-13),
    "WR": (1e-7, 1e-6),
    "A": (10.0, 20.0),
}


def _paper_dict() -> dict[str, Any]:
    return tomllib.loads(design_path("paper").read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def paper() -> Design:
    return load_design("paper")


@pytest.fixture(scope="module")
def paper_points(paper: Design):
    return paper.points()


# --- the paper's design --------------------------------------------------------------------


def test_paper_has_24_points_in_table2_order(paper, paper_points):
    assert paper.factor_names == ("S", "WP", "WR", "A")
    assert paper.n_tests == 24
    assert len(paper_points) == 24
    assert [p.test for p in paper_points] == list(range(1, 25))
    assert all(p.replicate == 0 for p in paper_points)
    expected = [
        {"S": s, "WP": wp, "WR": wr, "A": a}
        for a in PAPER_LEVELS["A"]
        for wr in PAPER_LEVELS["WR"]
        for wp in PAPER_LEVELS["WP"]
        for s in PAPER_LEVELS["S"]
    ]
    assert [p.levels for p in paper_points] == expected


def test_paper_test_1_all_minus_test_24_all_plus(paper, paper_points):
    labels = [{f.name: f.label_of(p.levels[f.name]) for f in paper.factors} for p in paper_points]
    assert labels[0] == {"S": "-", "WP": "-", "WR": "-", "A": "-"}
    assert labels[23] == {"S": "+", "WP": "+", "WR": "+", "A": "+"}
    # a few rows of Table 2 spelled out
    assert labels[1] == {"S": "+", "WP": "-", "WR": "-", "A": "-"}
    assert labels[2] == {"S": "-", "WP": "0", "WR": "-", "A": "-"}
    assert labels[5] == {"S": "+", "WP": "+", "WR": "-", "A": "-"}
    assert labels[6] == {"S": "-", "WP": "-", "WR": "+", "A": "-"}
    assert labels[12] == {"S": "-", "WP": "-", "WR": "-", "A": "+"}


def test_paper_points_resolve_the_config_fields(paper_points):
    first, last = paper_points[0].config, paper_points[-1].config
    assert first.automaton.secondary_removal_fraction == 0.0
    assert first.wear.specific_wear_rate == 1e-15
    assert first.wear.resin_wear_depth == 1e-7
    assert first.pad.fibre_area_fraction == pytest.approx(0.10, rel=1e-15)
    assert last.automaton.secondary_removal_fraction == 1.0
    assert last.wear.specific_wear_rate == 1e-13
    assert last.wear.resin_wear_depth == 1e-6
    assert last.pad.fibre_area_fraction == pytest.approx(0.20, rel=1e-15)
    base = load_preset("paper")
    # everything else is the base preset
    assert first.mesh == base.mesh
    assert first.cycle == base.cycle
    assert first.friction == base.friction


def test_seeds_follow_the_documented_formula_and_are_distinct(paper, paper_points):
    for p in paper_points:
        ss = np.random.SeedSequence([paper.root_seed, p.test, p.replicate])
        assert p.seed == int(ss.generate_state(1, dtype=np.uint32)[0])
        assert p.seed == point_seed(paper.root_seed, p.test, p.replicate)
    assert len({p.seed for p in paper_points}) == 24
    # regression: a change of the derivation would silently change every run
    assert paper_points[0].seed == point_seed(2016, 1, 0) == 2484888077


def test_seeds_are_stable_across_loads_replicates_and_ordering(paper, paper_points):
    again = load_design("paper").points()
    assert [p.seed for p in again] == [p.seed for p in paper_points]
    replicated = paper.model_copy(update={"replicates": 3}).points()
    firsts = {p.test: p.seed for p in replicated if p.replicate == 0}
    assert firsts == {p.test: p.seed for p in paper_points}
    shuffled = paper.model_copy(update={"randomize_order": True}).points()
    assert {(p.test, p.replicate): p.seed for p in shuffled} == {
        (p.test, p.replicate): p.seed for p in paper_points
    }


def test_replicates(paper):
    points = paper.model_copy(update={"replicates": 3}).points()
    assert len(points) == 72
    assert [(p.test, p.replicate) for p in points] == [
        (t, r) for t in range(1, 25) for r in range(3)
    ]
    assert len({p.seed for p in points}) == 72
    assert len({run_id(p) for p in points}) == 72
    by_test: dict[int, list] = {}
    for p in points:
        by_test.setdefault(p.test, []).append(p)
    for reps in by_test.values():
        assert all(r.config == reps[0].config for r in reps)
        assert all(r.levels == reps[0].levels for r in reps)


def test_shipped_replicated_paper_design_extends_the_paper_design(paper, paper_points):
    replicated = load_design("paper_replicated")
    points = replicated.points()
    assert replicated.replicates == 3 and len(points) == 72
    assert replicated.factors == paper.factors and replicated.root_seed == paper.root_seed
    # Replicate 0 is the unreplicated design's run: same configuration, seed and run id.
    firsts = {p.test: p for p in points if p.replicate == 0}
    for p in paper_points:
        assert firsts[p.test].config == p.config and firsts[p.test].seed == p.seed
        assert run_id(firsts[p.test]) == run_id(p)


def test_randomized_order_keeps_test_numbers(paper, paper_points):
    design = paper.model_copy(update={"randomize_order": True})
    points = design.points()
    assert [(p.test, p.levels) for p in points] == [(p.test, p.levels) for p in paper_points]
    orders = [p.order for p in points]
    assert sorted(orders) == list(range(1, 25))
    assert orders != list(range(1, 25))
    assert orders == [p.order for p in design.points()]  # seeded, reproducible
    executed = execution_order(points)
    assert [p.order for p in executed] == list(range(1, 25))
    assert [p.order for p in paper_points] == list(range(1, 25))


def test_mixed_levels_3x2_first_factor_fastest():
    design = design_from_dict(
        {
            "name": "mixed",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "mu0", "field": "friction.mu_0", "levels": [0.5, 0.6, 0.7]},
                {"name": "A", "field": "A", "levels": [15, 25], "unit": "%"},
            ],
        }
    )
    points = design.points()
    assert [(p.levels["mu0"], p.levels["A"]) for p in points] == [
        (0.5, 15),
        (0.6, 15),
        (0.7, 15),
        (0.5, 25),
        (0.6, 25),
        (0.7, 25),
    ]
    assert [p.config.friction.mu_0 for p in points] == [0.5, 0.6, 0.7] * 2
    # the alias A takes percent, like --set A=15
    assert [p.config.pad.fibre_area_fraction for p in points] == pytest.approx(
        [0.15] * 3 + [0.25] * 3
    )


def test_an_alias_factor_takes_the_alias_unit_unless_given():
    def factor(**extra: Any) -> Any:
        levels = [1e-14, 1e-13] if extra["field"] == "WP" else [0.4, 0.5]
        spec = {"name": "F", "levels": levels, **extra}
        return design_from_dict(
            {"name": "u", "base": "paper", "root_seed": 1, "factors": [spec]}
        ).factors[0]

    assert factor(field="A").unit == "%"
    assert factor(field="WP").unit == "m^3/(N m)"
    assert factor(field="A", unit="percent").unit == "percent"
    assert factor(field="friction.mu_0").unit == "-"  # the field's own unit, [-]
    assert factor(field="friction.slope").unit == "1/Pa"
    # a scaled factor's levels are in the user's unit, which the design does not know
    assert factor(field="friction.slope", scale=1e-6).unit == "-"


def test_a_factor_named_after_an_alias_needs_no_field():
    design = design_from_dict(
        {
            "name": "n",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "WP", "levels": [1e-15, 1e-13]},
                {"name": "A", "levels": [10, 20]},
            ],
        }
    )
    assert [(f.field, f.unit) for f in design.factors] == [("WP", "m^3/(N m)"), ("A", "%")]
    assert [p.config.pad.fibre_area_fraction for p in design.points()][-1] == pytest.approx(0.2)


def test_a_factor_without_a_field_is_one_error_not_two():
    """pydantic also calls the factor list too short when its only item fails; the message
    keeps only the item's error."""
    spec = {"name": "F", "levels": [0.5, 0.6]}
    with pytest.raises(ConfigError) as info:
        design_from_dict({"name": "n", "base": "paper", "root_seed": 1, "factors": [spec]})
    assert str(info.value) == "design: factors.0.field: required field is missing"


def test_many_factors_full_factorial_is_complete():
    factors = [
        {"name": "f1", "field": "friction.mu_0", "levels": [0.5, 0.6]},
        {"name": "f2", "field": "friction.slope", "levels": [1e-8, 2e-8, 3e-8]},
        {"name": "f3", "field": "contact.elastic_modulus", "levels": [1e9, 2e9]},
        {"name": "f4", "field": "mesh.n_angular", "levels": [100, 200, 300, 400]},
    ]
    design = design_from_dict({"name": "d", "base": "paper", "root_seed": 3, "factors": factors})
    points = design.points()
    assert len(points) == 2 * 3 * 2 * 4
    combos = [tuple(p.levels.values()) for p in points]
    expected = [c[::-1] for c in itertools.product(*[f["levels"] for f in reversed(factors)])]
    assert combos == expected
    assert isinstance(points[0].config.mesh.n_angular, int)


def test_run_id_is_short_stable_and_sensitive(paper_points):
    ids = [run_id(p) for p in paper_points]
    assert all(len(i) == 16 and int(i, 16) >= 0 for i in ids)
    assert len(set(ids)) == 24
    assert ids == [p.run_id for p in load_design("paper").points()]
    p = paper_points[0]
    assert run_id_for(p.config, p.seed + 1) != ids[0]
    assert run_id_for(p.config.with_updates({"friction.mu_0": 0.61}), p.seed) != ids[0]


def test_quick_config_narrows_band_centred_on_effective_radius():
    base = load_preset("paper")
    quick = quick_config(base)
    assert quick.quick is True
    assert quick.mesh.n_radial == 21
    assert quick.mesh.inner_radius is None
    assert quick.mesh.band_width == pytest.approx(2e-3)
    centre = quick.inner_radius + quick.mesh.band_width / 2
    assert centre == pytest.approx(base.brake.effective_radius)
    assert quick.mesh.radial_step == base.mesh.radial_step
    assert quick.mesh.angular_step_deg == base.mesh.angular_step_deg
    assert quick.mesh.n_angular == base.mesh.n_angular
    assert quick.cycle == base.cycle
    # an explicit inner radius is dropped: the quick band is always centred
    shifted = base.with_updates({"mesh.inner_radius": 0.09, "mesh.n_radial": 11})
    assert quick_config(shifted).inner_radius == pytest.approx(quick.inner_radius)


def test_campaign_wide_settings_and_factor_precedence(paper):
    points = paper.points(quick=True, max_stops=2, overrides={"friction.mu_0": 0.7})
    for p in points:
        assert p.config.quick and p.config.mesh.n_radial == 21
        assert p.config.cycle.max_stops == 2
        assert p.config.friction.mu_0 == 0.7
        assert p.config.wear.specific_wear_rate == p.levels["WP"]
    # an override of a factor's field is refused (it would be ignored), see below
    with pytest.raises(ConfigError, match="override WP"):
        paper.points(overrides={"WP": 5e-14})
    assert [p.seed for p in points] == [p.seed for p in paper.points()]
    with pytest.raises(ConfigError, match="friction"):
        paper.points(overrides={"friction.nope": 1})


def test_to_toml_round_trip(paper, tmp_path):
    text = paper.to_toml()
    again = design_from_dict(tomllib.loads(text), source="round trip")
    assert again == paper
    base_file = tmp_path / "base.toml"
    base_file.write_text(load_preset("paper").to_toml(), encoding="utf-8")
    (tmp_path / "d.toml").write_text(paper.to_toml(base_config="base.toml"), encoding="utf-8")
    from_file = load_design(tmp_path / "d.toml")
    assert from_file.base is None
    assert from_file.base_config == base_file.resolve()
    assert [p.run_id for p in from_file.points()] == [p.run_id for p in paper.points()]


def test_factor_model_is_frozen_and_scales(paper):
    a = paper.factor("A")
    assert a.override(10.0) == ("pad.fibre_area_fraction", 10.0 * 0.01)
    assert paper.factor("S").override(1.0) == ("automaton.secondary_removal_fraction", 1.0)
    with pytest.raises(Exception, match="frozen"):
        a.scale = 2.0  # type: ignore[misc]
    assert Factor(name="n", field="mesh.n_radial", levels=(5, 7)).override(5) == (
        "mesh.n_radial",
        5,
    )


# --- bad design files ----------------------------------------------------------------------


def _write(tmp_path: Path, data: dict[str, Any], name: str = "bad.toml") -> Path:
    path = tmp_path / name
    path.write_text(tomli_w.dumps(data), encoding="utf-8")
    return path


def _mutated(mutate) -> dict[str, Any]:
    data = _paper_dict()
    mutate(data)
    return data


def _set(data: dict, path: tuple, value: Any) -> None:
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value


BAD_CASES = {
    "unknown top-level key": (lambda d: _set(d, ("colour",), "red"), ["colour", "unknown key"]),
    "unknown factor key": (
        lambda d: _set(d, ("factors", 1, "step"), 2),
        ["factors.1.step", "unknown key"],
    ),
    "duplicate factor names": (
        lambda d: _set(d, ("factors", 2, "name"), "WP"),
        ["factors.2.name", "duplicate", "'WP'"],
    ),
    "unknown field": (
        lambda d: _set(d, ("factors", 0, "field"), "automaton.secondary_removal"),
        ["factors.0.field", "automaton.secondary_removal", "unknown configuration field"],
    ),
    "unknown section": (
        lambda d: _set(d, ("factors", 0, "field"), "brakes.pad_area"),
        ["factors.0.field", "brakes"],
    ),
    "field is a section": (
        lambda d: _set(d, ("factors", 0, "field"), "wear"),
        ["factors.0.field", "section"],
    ),
    "A = 150 %": (
        lambda d: _set(d, ("factors", 3, "levels"), [10.0, 150.0]),
        ["factors.3.levels", "'A'", "150", "pad.fibre_area_fraction"],
    ),
    "A alias = 150 %": (
        lambda d: (
            (_set(d, ("factors", 3, "field"), "A"), _set(d, ("factors", 3, "scale"), 1.0))
            and _set(d, ("factors", 3, "levels"), [10.0, 150.0])
        ),
        ["factors.3.levels", "'A'", "150"],
    ),
    "negative wear rate": (
        lambda d: _set(d, ("factors", 1, "levels"), [-1e-15, 1e-14, 1e-13]),
        ["factors.1.levels", "'WP'", "wear.specific_wear_rate"],
    ),
    "labels mismatch": (
        lambda d: _set(d, ("factors", 1, "labels"), ["-", "+"]),
        ["factors.1", "labels", "3 levels", "2 labels"],
    ),
    "one level": (
        lambda d: _set(d, ("factors", 0, "levels"), [0.0]),
        ["factors.0.levels", "at least 2"],
    ),
    "repeated level": (
        lambda d: _set(d, ("factors", 0, "levels"), [1.0, 1.0]),
        ["factors.0.levels", "differ"],
    ),
    "string level": (
        lambda d: _set(d, ("factors", 0, "levels"), [0.0, "high"]),
        ["factors.0.levels", "number"],
    ),
    "no factors": (lambda d: _set(d, ("factors",), []), ["factors"]),
    "missing root_seed": (lambda d: d.pop("root_seed"), ["root_seed", "required"]),
    "zero replicates": (lambda d: _set(d, ("replicates",), 0), ["replicates"]),
    "unknown preset": (lambda d: _set(d, ("base",), "nope"), ["base", "nope"]),
    "base and base_config": (lambda d: _set(d, ("base_config",), "x.toml"), ["base"]),
    "missing base config file": (
        lambda d: (d.pop("base"), _set(d, ("base_config",), "missing.toml")),
        ["base_config", "missing.toml"],
    ),
    "reserved factor name": (
        lambda d: _set(d, ("factors", 0, "name"), "seed"),
        ["factors.0.name", "reserved"],
    ),
    "non-identifier factor name": (
        lambda d: _set(d, ("factors", 0, "name"), "S plus"),
        ["factors.0.name", "identifier"],
    ),
    "two factors, one field": (
        lambda d: _set(d, ("factors", 0, "field"), "wear.specific_wear_rate"),
        ["factors.1.field", "both set", "wear.specific_wear_rate"],
    ),
}


@pytest.mark.parametrize("case", sorted(BAD_CASES))
def test_bad_design_file_names_file_and_field(tmp_path, case):
    mutate, fragments = BAD_CASES[case]
    path = _write(tmp_path, _mutated(mutate))
    with pytest.raises(ConfigError) as info:
        load_design(path)
    message = str(info.value)
    assert str(path) in message
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def test_bad_toml_and_missing_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("name = 'x'\nfactors = [", encoding="utf-8")
    with pytest.raises(ConfigError, match=r"broken\.toml: not valid TOML"):
        load_design(path)
    with pytest.raises(ConfigError, match="no such file nor a shipped design"):
        load_design(tmp_path / "absent.toml")
    with pytest.raises(ConfigError, match="shipped design"):
        load_design("not-a-design")


def test_base_config_relative_to_design_file(tmp_path):
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "base.toml").write_text(
        load_preset("paper").with_updates({"friction.mu_0": 0.55}).to_toml(), encoding="utf-8"
    )
    data = _paper_dict()
    del data["base"]
    data["base_config"] = "base.toml"
    design = load_design(_write(sub, data, "d.toml"))
    assert design.points()[0].config.friction.mu_0 == 0.55
    # an invalid base config file: the error names both files
    (sub / "base.toml").write_text("[friction]\nmu_0 = -1\n", encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        load_design(sub / "d.toml")
    assert "d.toml: base_config" in str(info.value)
    assert "base.toml" in str(info.value)


# --- property test: malformed designs always raise ConfigError -----------------------------

_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
    st.sampled_from(["paper", "S", "WP", "A", "mesh.n_radial", "wear", "x.y", "", "\x00"]),
)
_values = st.recursive(
    _scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=10,
)
_top_keys = st.sampled_from(
    [
        "name",
        "description",
        "base",
        "base_config",
        "factors",
        "root_seed",
        "replicates",
        "randomize_order",
        "extra",
    ]
)
_factor_keys = st.sampled_from(
    ["name", "field", "levels", "scale", "labels", "unit", "label", "bogus"]
)


@st.composite
def _malformed(draw) -> Any:
    if draw(st.integers(0, 9)) == 0:
        return draw(_values)  # not even a table
    data = copy.deepcopy(_paper_dict())
    for _ in range(draw(st.integers(1, 4))):
        where = draw(st.sampled_from(["top", "factor", "drop", "drop_factor_key"]))
        if where == "top":
            data[draw(_top_keys)] = draw(_values)
        elif where == "drop":
            data.pop(draw(_top_keys), None)
        elif isinstance(data.get("factors"), list) and data["factors"]:
            i = draw(st.integers(0, len(data["factors"]) - 1))
            factor = data["factors"][i]
            if not isinstance(factor, dict):
                continue
            if where == "factor":
                factor[draw(_factor_keys)] = draw(_values)
            else:
                factor.pop(draw(_factor_keys), None)
    return data


@settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(_malformed())
def test_malformed_designs_raise_config_error_only(data):
    try:
        design = design_from_dict(data, source="fuzz.toml")
    except ConfigError as exc:
        assert str(exc).startswith("fuzz.toml")
        return
    # a mutation may leave a valid design: it must then expand without surprises
    points = design.points()
    assert len(points) == design.n_tests * design.replicates
    assert all(math.isfinite(v) for p in points for v in p.levels.values())


def test_the_readme_design_loads_as_described():
    readme = (Path(__file__).parents[2] / "README.md").read_text(encoding="utf-8")
    blocks = [b.split("```", 1)[0] for b in readme.split("```toml\n")[1:]]
    design = design_from_dict(tomllib.loads(blocks[0]), source="README.md")
    assert design.n_tests == 6 and design.replicates == 2
    assert [(f.name, f.field, f.unit) for f in design.factors] == [
        ("WP", "WP", "m^3/(N m)"),
        ("mu0", "friction.mu_0", "-"),
    ]


@pytest.mark.parametrize(
    ("key", "shown"),
    [
        ("WP", "WP (wear.specific_wear_rate)"),
        ("pad.fibre_area_fraction", "pad.fibre_area_fraction"),
    ],
)
def test_an_override_of_a_field_the_design_varies_is_refused(key, shown):
    """`brakeca run paper --set WP=1e-13` ran the paper's WP levels without a word: the
    factor sets the field in every run after the campaign-wide overrides."""
    design = load_design("paper")
    value = 1e-13 if key == "WP" else 0.3
    factor = "WP" if key == "WP" else "A"
    with pytest.raises(ConfigError) as info:
        design.points(overrides={key: value})
    assert str(info.value) == (
        f"override {shown}: the design's factor {factor!r} sets this field in every run, so "
        "the override would be ignored; remove one of them"
    )
    # a field no factor sets is fine
    assert design.points(overrides={"friction.mu_0": 0.5})[0].config.friction.mu_0 == 0.5


def test_the_designs_guide_example_loads_as_described():
    guide = (Path(__file__).parents[2] / "docs" / "designs.md").read_text(encoding="utf-8")
    example = guide.split("```toml\n")[1].split("```", 1)[0]
    design = design_from_dict(tomllib.loads(example), source="docs/designs.md")
    assert design.n_tests == 9 and design.replicates == 2  # "its 3 × 3 × 2 = 18 runs"
    assert [(f.field, f.unit) for f in design.factors] == [
        ("WP", "m^3/(N m)"),
        ("friction.mu_0", "-"),
    ]


def test_a_categorical_factor_sets_a_text_field_by_its_choices():
    spec = {
        "name": "fibres",
        "field": "pad.fibre_model",
        "levels": [0, 1],
        "choices": ["columns", "field"],
    }
    order = {"name": "creation", "field": "automaton.creation_order", "levels": [1, 2]}
    order["choices"] = ["west_to_east", "east_to_west"]
    order["labels"] = ["W-E", "E-W"]
    design = design_from_dict(
        {"name": "c", "base": "paper", "root_seed": 1, "factors": [spec, order]}
    )
    got = [(p.config.pad.fibre_model, p.config.automaton.creation_order) for p in design.points()]
    assert got == [
        ("columns", "west_to_east"),
        ("field", "west_to_east"),
        ("columns", "east_to_west"),
        ("field", "east_to_west"),
    ]
    # labels default to the choices; given labels are kept
    assert design.factors[0].labels == ("columns", "field")
    assert design.factors[1].labels == ("W-E", "E-W")
    # its levels only number the choices: no unit, so a plot's axis reads "fibres", not
    # "fibres [-]"
    assert [f.unit for f in design.factors] == ["", ""]
    assert as_factor(design.factors[0]).axis_label == "fibres"
    # a choice the field does not take names the factor, the level and the allowed values
    bad = {**spec, "choices": ["columns", "feld"]}
    with pytest.raises(ConfigError, match=r"factor 'fibres' .*'columns', 'layer' or 'field'"):
        design_from_dict({"name": "c", "base": "paper", "root_seed": 1, "factors": [bad]})
    with pytest.raises(ConfigError, match="a scale does not apply"):
        design_from_dict(
            {"name": "c", "base": "paper", "root_seed": 1, "factors": [{**spec, "scale": 2.0}]}
        )
