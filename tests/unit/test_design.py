"""Unit tests of brakeca.design: factorial expansion, test order, seeds, run ids, validation."""

from __future__ import annotations

import copy
import itertools
import math
import tomllib
import types
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from brakeca.analysis import as_factor
from brakeca.cli import app
from brakeca.config import ConfigError
from brakeca.design import (
    STANDARD_FRACTIONS,
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
    # the drawn order is pinned: the same design gives the same order on every machine and
    # version (a test-suite audit: the order's own seed tag could be dropped unseen)
    assert [p.order for p in shuffled][:12] == [22, 6, 1, 15, 13, 10, 24, 5, 9, 14, 18, 4]


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
        levels = {"WP": [1e-14, 1e-13], "A": [40, 50], "friction.slope": [1e-8, 2e-8]}.get(
            extra["field"], [0.4, 0.5]
        )
        if extra.get("scale"):
            levels = [0.01, 0.02]
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


def test_a_factor_on_a_paper_field_without_a_label_gets_the_papers_in_figures_and_tables():
    """A design's own factors on the paper's fields went by their bare names ("S") in the
    figures' titles and the report's design table: they take the paper's description, while
    a label given, and a factor on another field, keep theirs; the design keeps none."""
    from brakeca.plotting import plot_main_effects
    from brakeca.study import _design_table

    design = design_from_dict(
        {
            "name": "own",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "removal", "field": "S", "levels": [0.0, 1.0]},
                {"name": "WR", "levels": [1e-7, 1e-6], "label": "Resin cut"},
                {"name": "mu0", "field": "friction.mu_0", "levels": [0.4, 0.5]},
            ],
        }
    )
    assert design.factors[0].label == ""  # (what the design file says)
    labels = [as_factor(f).label for f in design.factors]
    assert labels == ["Secondary plateaus removed between stops", "Resin cut", ""]
    summary = pd.DataFrame(
        [
            {"removal": s, "WR": wr, "mu0": m, "MU": 0.3 + 0.01 * s + m / 10, "status": "ok"}
            for s in (0.0, 1.0)
            for wr in (1e-7, 1e-6)
            for m in (0.4, 0.5)
        ]
    )
    titles = [ax.get_title() for ax in plot_main_effects(summary, design, "MU").axes]
    assert titles == ["Secondary plateaus removed between stops", "Resin cut", "mu0"]
    result = types.SimpleNamespace(design=design)
    meaning = list(_design_table(result)["meaning"])
    assert meaning == ["Secondary plateaus removed between stops", "Resin cut", ""]


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
    assert str(info.value) == (
        "design: factors #1: factor 'F' gives no `field` (the configuration field it sets, e.g. "
        'field = "wear.specific_wear_rate"), and only the paper\'s factors S, WP, WR, A may '
        "leave it out"
    )
    spec = {"name": "Wp", "levels": [1e-15, 1e-13]}  # a paper factor's name, miswritten
    with pytest.raises(ConfigError, match=r"case-sensitive: did you mean 'WP'\?\)$"):
        design_from_dict({"name": "n", "base": "paper", "root_seed": 1, "factors": [spec]})


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
        ["factors #2.step", "unknown key"],
    ),
    "duplicate factor names": (
        lambda d: _set(d, ("factors", 2, "name"), "WP"),
        ["factors #3.name", "duplicate", "'WP'"],
    ),
    "unknown field": (
        lambda d: _set(d, ("factors", 0, "field"), "automaton.secondary_removal"),
        ["factors #1.field", "automaton.secondary_removal", "unknown configuration field"],
    ),
    "unknown section": (
        lambda d: _set(d, ("factors", 0, "field"), "brakes.pad_area"),
        ["factors #1.field", "brakes"],
    ),
    "field is a section": (
        lambda d: _set(d, ("factors", 0, "field"), "wear"),
        ["factors #1.field", "section"],
    ),
    "A = 150 %": (
        lambda d: _set(d, ("factors", 3, "levels"), [10.0, 150.0]),
        ["factors #4.levels", "'A'", "150", "pad.fibre_area_fraction"],
    ),
    "A alias = 150 %": (
        lambda d: (
            (_set(d, ("factors", 3, "field"), "A"), _set(d, ("factors", 3, "scale"), 1.0))
            and _set(d, ("factors", 3, "levels"), [10.0, 150.0])
        ),
        ["factors #4.levels", "'A'", "150"],
    ),
    "negative wear rate": (
        lambda d: _set(d, ("factors", 1, "levels"), [-1e-15, 1e-14, 1e-13]),
        ["factors #2.levels", "'WP'", "wear.specific_wear_rate"],
    ),
    "labels mismatch": (
        lambda d: _set(d, ("factors", 1, "labels"), ["-", "+"]),
        ["factors #2", "labels", "3 levels", "2 labels"],
    ),
    "one level": (
        lambda d: _set(d, ("factors", 0, "levels"), [0.0]),
        ["factors #1.levels", "at least 2"],
    ),
    "repeated level": (
        lambda d: _set(d, ("factors", 0, "levels"), [1.0, 1.0]),
        ["factors #1.levels", "differ"],
    ),
    "string level": (
        lambda d: _set(d, ("factors", 0, "levels"), [0.0, "high"]),
        ["factors #1.levels", "number"],
    ),
    "repeated label": (  # a robustness review: tables and plots could not tell them apart
        lambda d: _set(d, ("factors", 0, "labels"), ["lo", "lo"]),
        ["factors #1", "labels two levels 'lo'"],
    ),
    "no factors": (lambda d: _set(d, ("factors",), []), ["factors"]),
    "missing root_seed": (lambda d: d.pop("root_seed"), ["root_seed", "required"]),
    "text root_seed": (  # pydantic took "1" for 1
        lambda d: _set(d, ("root_seed",), "1"),
        ["root_seed: expected a whole number, 0 <= root_seed < 2**128, got '1'"],
    ),
    "float root_seed": (
        lambda d: _set(d, ("root_seed",), 7.0),
        ["root_seed: expected a whole number", "got 7.0"],
    ),
    "zero replicates": (lambda d: _set(d, ("replicates",), 0), ["replicates"]),
    "text replicates": (  # taken as 3, where a text root_seed was refused (a fuzz review)
        lambda d: _set(d, ("replicates",), "3"),
        ["replicates: expected a whole number of replicates, 1 to 10000, got '3'"],
    ),
    "true replicates": (  # pydantic takes True for 1
        lambda d: _set(d, ("replicates",), True),
        ["replicates: must be a number, not true"],
    ),
    "unknown preset": (lambda d: _set(d, ("base",), "nope"), ["base", "nope"]),
    "base and base_config": (lambda d: _set(d, ("base_config",), "x.toml"), ["base"]),
    "missing base config file": (
        lambda d: (d.pop("base"), _set(d, ("base_config",), "missing.toml")),
        ["base_config", "missing.toml"],
    ),
    "reserved factor name": (
        lambda d: _set(d, ("factors", 0, "name"), "seed"),
        ["factors #1.name", "reserved"],
    ),
    "non-identifier factor name": (
        lambda d: _set(d, ("factors", 0, "name"), "S plus"),
        ["factors #1.name", "identifier"],
    ),
    "two factors, one field": (
        lambda d: _set(d, ("factors", 0, "field"), "wear.specific_wear_rate"),
        ["factors #2.field", "both set", "wear.specific_wear_rate"],
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


def test_every_bad_level_is_named_at_once(tmp_path):
    """A DoE review: with A = [10, 150] and S = [0, 2], S's error showed only once A's was
    mended. Each bad level now has its own line, in the design's order."""
    path = tmp_path / "bad.toml"
    path.write_text(
        'name = "bad"\nbase = "paper"\nroot_seed = 1\n'
        '[[factors]]\nname = "A"\nlevels = [10, 150]\n'
        '[[factors]]\nname = "S"\nlevels = [-1, 2]\n'
    )
    with pytest.raises(ConfigError) as info:
        load_design(path)
    lines = str(info.value).splitlines()
    assert len(lines) == 3, lines
    assert all(line.startswith(f"{path}: factors #") for line in lines)
    assert "factor 'A' (field A): level 150 [%] is not valid" in lines[0]
    assert "factor 'S' (field S): level -1 [-] is not valid" in lines[1]
    assert "factor 'S' (field S): level 2 [-] is not valid" in lines[2]


def test_bad_toml_and_missing_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("name = 'x'\nfactors = [", encoding="utf-8")
    with pytest.raises(ConfigError, match=r"broken\.toml: not valid TOML"):
        load_design(path)
    with pytest.raises(ConfigError, match="no such file nor a shipped design"):
        load_design(tmp_path / "absent.toml")
    with pytest.raises(ConfigError, match="shipped design"):
        load_design("not-a-design")


def test_a_campaign_folder_stands_for_its_design(tmp_path):
    """A new user's `brakeca power fact` (a campaign folder) was 'no such file'."""
    folder = tmp_path / "fact"
    folder.mkdir()
    with pytest.raises(ConfigError, match=r"'.*fact': a folder without a design.toml"):
        load_design(folder)
    (folder / "design.toml").write_text(
        'name = "f"\nbase = "paper"\nroot_seed = 3\n[[factors]]\nname = "A"\nlevels = [10, 20]\n'
    )
    assert load_design(folder).name == "f" and load_design(str(folder)).root_seed == 3


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
    import warnings

    from brakeca.config import UnitWarning

    with warnings.catch_warnings():  # levels that read like slips of unit are allowed
        warnings.simplefilter("ignore", UnitWarning)
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


def test_a_kind_key_is_told_where_a_designs_kind_comes_from():
    """A new user wrote kind = "composite": 'unknown key' alone did not say what does."""
    with pytest.raises(ConfigError, match=r"^design: kind: unknown key; a design's kind comes "):
        design_from_dict(
            {
                "name": "x",
                "base": "paper",
                "root_seed": 1,
                "kind": "composite",
                "factors": [{"name": "A", "levels": [10, 20]}],
            }
        )


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


# --- fractional factorials (generators) ----------------------------------------------------

#: Two-level factors on real configuration fields, by the letters the textbooks use.
TWO_LEVEL = {
    "A": ("friction.mu_0", [0.5, 0.6]),
    "B": ("friction.slope", [1e-8, 2e-8]),
    "C": ("contact.elastic_modulus", [1e9, 2e9]),
    "D": ("contact.bar_length", [5e-3, 1e-2]),
    "E": ("WP", [1e-15, 1e-13]),
    "F": ("WR", [1e-7, 1e-6]),
    "G": ("A", [10.0, 20.0]),
    "H": ("S", [0.0, 1.0]),
}


def _factors(names: str) -> list[dict[str, Any]]:
    return [{"name": n, "field": TWO_LEVEL[n][0], "levels": list(TWO_LEVEL[n][1])} for n in names]


def _fraction(names: str, generators: list[str], **extra: Any) -> Design:
    data = {
        "name": "screen",
        "base": "paper",
        "root_seed": 1,
        "generators": generators,
        "factors": _factors(names),
        **extra,
    }
    return design_from_dict(data, source="screen.toml")


def _coded(design: Design, combo: dict[str, Any]) -> dict[str, int]:
    """Each two-level factor's coded level: levels[0] is -1, levels[1] is +1."""
    return {
        f.name: (-1 if combo[f.name] == f.levels[0] else 1)
        for f in design.factors
        if len(f.levels) == 2
    }


@pytest.mark.parametrize("sign", [1, -1])
def test_half_fraction_2_4_1_generates_d_from_abc(sign):
    design = _fraction("ABCD", ["D = -A*B*C" if sign < 0 else "D = A*B*C"])
    combos = design.combinations()
    assert design.n_tests == len(combos) == 8
    assert design.is_fractional and design.generated_factors == ("D",)
    coded = [_coded(design, c) for c in combos]
    # the base factors form the full 2^3 in standard order (A fastest)
    assert [(c["A"], c["B"], c["C"]) for c in coded] == [
        (a, b, c) for c in (-1, 1) for b in (-1, 1) for a in (-1, 1)
    ]
    assert all(c["D"] == sign * c["A"] * c["B"] * c["C"] for c in coded)
    assert all(list(c) == ["A", "B", "C", "D"] for c in combos)  # design order
    assert design.resolution == 4
    assert design.defining_relation() == [(sign, ("A", "B", "C", "D"))]
    assert design.kind == "2^(4-1) fractional factorial, resolution IV"
    # the levels are the factors' own values, set on their fields
    points = design.points()
    assert [p.config.contact.bar_length for p in points] == [c["D"] for c in combos]
    assert {p.levels["D"] for p in points} == {5e-3, 1e-2}


def test_fraction_keeps_design_order_whatever_the_generators_order():
    # the generated factors come first in the design and the generators out of order
    factors = _factors("EDABC")
    design = design_from_dict(
        {
            "name": "s",
            "base": "paper",
            "root_seed": 1,
            "generators": [" E=-A * C ", "D = A*B"],
            "factors": factors,
        }
    )
    combos = design.combinations()
    assert len(combos) == 8
    assert all(list(c) == ["E", "D", "A", "B", "C"] for c in combos)
    coded = [_coded(design, c) for c in combos]
    assert [(c["A"], c["B"], c["C"]) for c in coded] == [
        (a, b, c) for c in (-1, 1) for b in (-1, 1) for a in (-1, 1)
    ]
    assert all(c["D"] == c["A"] * c["B"] and c["E"] == -c["A"] * c["C"] for c in coded)
    assert design.generated_factors == ("E", "D")
    assert design.generators == (" E=-A * C ", "D = A*B")  # kept as given
    # words in design order of their factors, shortest first; products of words included
    assert design.defining_relation() == [
        (-1, ("E", "A", "C")),
        (1, ("D", "A", "B")),
        (-1, ("E", "D", "B", "C")),
    ]
    assert design.resolution == 3


def test_2_7_4_resolution_iii_and_its_defining_relation():
    design = _fraction("ABCDEFG", ["D = A*B", "E = A*C", "F = B*C", "G = A*B*C"])
    assert design.n_tests == 8 and len(design.combinations()) == 8
    assert design.resolution == 3
    relation = design.defining_relation()
    assert len(relation) == 15 == len({word for _, word in relation})
    assert (1, ("A", "B", "D")) in relation and (1, ("A", "B", "C", "G")) in relation
    assert [len(w) for _, w in relation] == sorted(len(w) for _, w in relation)
    assert min(len(w) for _, w in relation) == 3
    # every word of the defining relation is constant (its sign) over the fraction's tests
    coded = [_coded(design, c) for c in design.combinations()]
    for sign, word in relation:
        assert all(math.prod(c[n] for n in word) == sign for c in coded), word
    # and the 8 tests are 8 different points
    assert len({tuple(c.values()) for c in coded}) == 8
    assert design.kind == "2^(7-4) fractional factorial, resolution III"


def test_2_5_1_with_e_abcd_has_resolution_v():
    design = _fraction("ABCDE", ["E = A*B*C*D"])
    assert design.n_tests == 16
    assert design.resolution == 5
    assert design.kind == "2^(5-1) fractional factorial, resolution V"
    assert design.defining_relation() == [(1, ("A", "B", "C", "D", "E"))]


def test_a_fraction_crosses_factors_of_other_level_counts():
    factors = _factors("AB")
    factors.append({"name": "N", "field": "mesh.n_angular", "levels": [100, 200, 300]})
    factors += _factors("CD")
    design = design_from_dict(
        {
            "name": "m",
            "base": "paper",
            "root_seed": 1,
            "generators": ["D = A*B*C"],
            "factors": factors,
        }
    )
    combos = design.combinations()
    assert design.n_tests == len(combos) == 3 * 2 ** (4 - 1)
    assert all(list(c) == ["A", "B", "N", "C", "D"] for c in combos)
    coded = [_coded(design, c) for c in combos]
    assert all(c["D"] == c["A"] * c["B"] * c["C"] for c in coded)
    # the base factors (A, B, N, C) form their full factorial, A fastest
    assert [(c["A"], c["B"], c["N"], c["C"]) for c in combos] == [
        (a, b, n, c)
        for c in TWO_LEVEL["C"][1]
        for n in (100, 200, 300)
        for b in TWO_LEVEL["B"][1]
        for a in TWO_LEVEL["A"][1]
    ]
    assert design.resolution == 4
    assert design.kind == (
        "fractional factorial (2^(4-1) in the two-level factors × 3 levels of N), resolution IV"
    )


def test_a_fraction_counts_its_own_runs_against_the_limit():
    factors = [
        *_factors("ABCD"),
        {"name": "N", "field": "mesh.n_angular", "levels": [100, 200, 300]},
        {"name": "M", "field": "friction.mu_min", "levels": [0.1, 0.12, 0.14]},
    ]
    data = {"name": "big", "base": "paper", "root_seed": 1, "replicates": 10_000}
    design = design_from_dict({**data, "factors": factors, "generators": ["D = A*B*C"]})
    assert design.n_tests == 72  # 720,000 runs: allowed
    with pytest.raises(ConfigError, match="1440000 runs, more than 1,000,000"):
        design_from_dict({**data, "factors": factors})


def test_a_categorical_factor_may_be_generated():
    factors = [
        *_factors("AB"),
        {
            "name": "creation",
            "field": "automaton.creation_order",
            "levels": [0, 1],
            "choices": ["west_to_east", "east_to_west"],
        },
    ]
    design = design_from_dict(
        {
            "name": "c",
            "base": "paper",
            "root_seed": 1,
            "generators": ["creation = A*B"],
            "factors": factors,
        }
    )
    got = [(p.levels["creation"], p.config.automaton.creation_order) for p in design.points()]
    assert got == [
        (1, "east_to_west"),
        (0, "west_to_east"),
        (0, "west_to_east"),
        (1, "east_to_west"),
    ]


def test_points_of_a_replicated_fraction_carry_the_usual_seeds():
    design = _fraction("ABCD", ["D = A*B*C"], replicates=2, root_seed=7)
    points = design.points()
    assert len(points) == 2 * design.n_tests == 16
    assert [(p.test, p.replicate) for p in points] == [(t, r) for t in range(1, 9) for r in (0, 1)]
    assert all(p.seed == point_seed(7, p.test, p.replicate) for p in points)
    assert len({p.run_id for p in points}) == 16
    combos = design.combinations()
    assert all(p.levels == combos[p.test - 1] for p in points)
    shuffled = design.model_copy(update={"randomize_order": True}).points()
    assert sorted(p.order for p in shuffled) == list(range(1, 17))
    assert [p.seed for p in shuffled] == [p.seed for p in points]


def test_a_fraction_round_trips_through_toml():
    design = _fraction("ABCDEFG", ["D = A*B", "E = A*C", "F = -B*C", "G = A*B*C"])
    text = design.to_toml()
    data = tomllib.loads(text)
    assert data["generators"] == ["D = A*B", "E = A*C", "F = -B*C", "G = A*B*C"]
    again = design_from_dict(data, source="round trip")
    assert again == design
    assert [p.run_id for p in again.points()] == [p.run_id for p in design.points()]


def test_a_full_factorial_is_unchanged(paper):
    assert paper.kind == "full factorial"
    assert not paper.is_fractional and paper.resolution is None
    assert paper.defining_relation() == [] and paper.generated_factors == ()
    assert paper.generators == () and paper.runs is None and paper.runs_file is None
    data = tomllib.loads(paper.to_toml())
    assert "generators" not in data and "runs" not in data and "runs_file" not in data


def _gen_case(generators: list[str], names: str = "ABCDE", **levels: list) -> Any:
    def build() -> dict[str, Any]:
        factors = _factors(names)
        for f in factors:
            if f["name"] in levels:
                f["levels"] = levels[f["name"]]
                f["field"] = "mesh.n_angular"
        return {
            "name": "g",
            "base": "paper",
            "root_seed": 1,
            "generators": generators,
            "factors": factors,
        }

    return build


BAD_GENERATORS = {
    "no '='": (_gen_case(["D A*B*C"]), ["generators #1", "cannot read 'D A*B*C'", "X = F1*F2"]),
    "two '='": (_gen_case(["D = A = B"]), ["generators #1", "cannot read"]),
    "juxtaposed letters": (
        _gen_case(["D = A*B*C", "E = AB"]),
        ["generators #2", "unknown factor 'AB'", "A*B"],
    ),
    "spaces, no '*'": (_gen_case(["D = A B C"]), ["generators #1", "cannot read", "'*'"]),
    "dangling '*'": (_gen_case(["D = A*B*"]), ["generators #1", "cannot read"]),
    "non-identifier target": (_gen_case(["1D = A*B"]), ["generators #1", "cannot read"]),
    "unknown generated factor": (
        _gen_case(["Z = A*B*C"]),
        ["generators #1", "unknown factor 'Z'", "factors: A, B, C, D, E"],
    ),
    "unknown base factor": (_gen_case(["D = A*B*Q"]), ["generators #1", "unknown factor 'Q'"]),
    "empty word": (_gen_case(["D = "]), ["generators #1", "empty word"]),
    "sign only": (_gen_case(["D = -"]), ["generators #1", "empty word"]),
    "generated factor with 3 levels": (
        _gen_case(["D = A*B*C"], D=[100, 200, 300]),
        ["generators #1", "generated factor 'D' has 3 levels", "exactly 2"],
    ),
    "base factor with 3 levels": (
        _gen_case(["D = A*B*C"], B=[100, 200, 300]),
        ["generators #1", "base factor 'B' has 3 levels", "exactly 2"],
    ),
    "repeated factor in a word": (
        _gen_case(["D = A*B*A"]),
        ["generators #1", "'A' appears 2 times", "A*B*A"],
    ),
    "generated factor in its own word": (
        _gen_case(["D = A*B*D"]),
        ["generators #1", "generated factor 'D' appears in its own word"],
    ),
    "generated factor in another word": (
        _gen_case(["D = A*B", "E = A*D"]),
        ["generators #2", "'D'", "itself generated", "generators #1", "base factors only"],
    ),
    "generated factor in an earlier word": (
        _gen_case(["E = A*D", "D = A*B*C"]),
        ["generators #1", "'D'", "itself generated", "generators #2"],
    ),
    "generated twice": (
        _gen_case(["D = A*B", "D = A*C"]),
        ["generators #2", "'D' is generated twice", "generators #1"],
    ),
    "D = A: resolution II": (
        _gen_case(["D = A"]),
        ["generators #1", "resolution II", "'A' and 'D' are aliased", "I = A*D"],
    ),
    "same word twice: resolution II": (
        _gen_case(["D = A*B", "E = -A*B"]),
        ["generators #1, generators #2", "resolution II", "'D' and 'E'", "I = -D*E"],
    ),
    "a single base factor, negated": (
        _gen_case(["D = A*B*C", "E = -C"]),
        ["generators #2:", "resolution II", "'C' and 'E' are aliased", "I = -C*E"],
    ),
    "not a list": (_gen_case("D = A*B*C"), ["generators"]),  # type: ignore[arg-type]
}


@pytest.mark.parametrize("case", sorted(BAD_GENERATORS))
def test_bad_generators_name_the_generator_and_the_problem(case):
    build, fragments = BAD_GENERATORS[case]
    with pytest.raises(ConfigError) as info:
        design_from_dict(build(), source="bad.toml")
    message = str(info.value)
    assert message.startswith("bad.toml: "), message
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def test_too_many_generators_are_refused():
    generators = [f"D = A*B*C{i}" for i in range(21)]
    with pytest.raises(ConfigError, match="generators: 21 generators, more than 20"):
        design_from_dict(_gen_case(generators)(), source="bad.toml")


# --- run tables (runs, runs_file) ----------------------------------------------------------

PAPER_FACTORS = [{"name": n, "levels": list(v)} for n, v in PAPER_LEVELS.items()]
TABLE = [
    {"S": 0, "WP": 1e-15, "WR": 1e-7, "A": 10},
    {"S": 1, "WP": 1e-13, "WR": 1e-6, "A": 20},
    {"S": 1.0, "WP": 1e-14, "WR": 1e-7, "A": 20.0},
    {"S": 0, "WP": 1e-15, "WR": 1e-7, "A": 10},  # a repeated point: its own test and seed
]


def _table_design(**extra: Any) -> dict[str, Any]:
    return {"name": "t", "base": "paper", "root_seed": 5, "factors": PAPER_FACTORS, **extra}


def test_an_inline_run_table_runs_its_rows_in_order():
    design = design_from_dict(_table_design(runs=TABLE))
    assert design.kind == "run table" and design.is_run_table and not design.is_fractional
    assert design.resolution is None and design.defining_relation() == []
    assert design.n_tests == 4
    combos = design.combinations()
    assert combos == [{k: float(v) for k, v in row.items()} for row in TABLE]
    # the stored levels are the factors' own values (10 is the level 10.0)
    assert all(isinstance(v, float) for c in combos for v in c.values())
    points = design.points()
    assert [p.test for p in points] == [1, 2, 3, 4]
    assert [p.seed for p in points] == [point_seed(5, t, 0) for t in range(1, 5)]
    assert points[0].config == points[3].config  # the repeated point ...
    assert points[0].run_id != points[3].run_id  # ... is a separate run with its own seed
    assert points[1].config.pad.fibre_area_fraction == pytest.approx(0.2)
    assert points[2].config.wear.specific_wear_rate == 1e-14
    replicated = design.model_copy(update={"replicates": 2, "randomize_order": True}).points()
    assert len(replicated) == 8 and sorted(p.order for p in replicated) == list(range(1, 9))


def test_a_run_table_sets_a_categorical_factor_by_its_level_number_or_choice():
    factors = [
        {"name": "fibres", "field": "pad.fibre_model", "levels": [0, 1]},
        {"name": "mu0", "field": "friction.mu_0", "levels": [0.5, 0.6, 0.7]},
    ]
    factors[0]["choices"] = ["columns", "field"]
    # a choice's text stands for its level; 0.1 * 7 = 0.7000000000000001 (a spreadsheet's
    # arithmetic) is the level 0.7
    runs = [
        {"fibres": 0, "mu0": 0.1 * 7},
        {"fibres": "field", "mu0": 0.5},
        {"fibres": 1.0, "mu0": 0.6},
    ]
    design = design_from_dict(
        {"name": "c", "base": "paper", "root_seed": 1, "factors": factors, "runs": runs}
    )
    assert design.runs == (
        {"fibres": 0, "mu0": 0.7},
        {"fibres": 1, "mu0": 0.5},
        {"fibres": 1, "mu0": 0.6},
    )
    assert [p.config.pad.fibre_model for p in design.points()] == ["columns", "field", "field"]


CSV_ROWS = [
    "S,WP,WR,A",
    "0,1e-15,1e-07,10",
    "1,1e-13,1e-06,20",
    "1,1e-14,1e-07,20",
    "0,1e-15,1e-07,10",
]


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("comma.csv", "\n".join(CSV_ROWS) + "\n"),
        (
            "semicolon.csv",
            "S;WP;WR;A\r\n0;1,0E-15;0,0000001;10\r\n1;1e-13;0,000001;20,0\r\n"
            "1;1e-14;1e-7;20\r\n0;1e-15;1e-07;10\r\n",
        ),
        ("tab.tsv", "\n".join(r.replace(",", "\t") for r in CSV_ROWS) + "\n"),
        (
            "bom.csv",
            "\ufeff# exported from JMP\n\nA,WR,S,WP\n10,1e-07,0,1e-15\n# a comment\n"
            "20,1e-06,1,1e-13\n20,1e-07,1,1e-14\n\n10,1e-07,0,1e-15,,\n",
        ),
        (  # Excel's separator line, and trailing separators on the header too
            "excel.csv",
            "sep=;\r\nS;WP;WR;A;\r\n0;1e-15;1e-07;10;\r\n1;1e-13;1e-06;20;\r\n"
            "1;1e-14;1e-07;20\r\n0;1e-15;1e-07;10;;\r\n",
        ),
    ],
)
def test_a_run_table_from_a_csv_file_is_inlined(tmp_path, name, text):
    (tmp_path / "tables").mkdir()
    (tmp_path / "tables" / name).write_text(text, encoding="utf-8")
    data = _table_design(runs_file=f"tables/{name}")
    design = load_design(_write(tmp_path, data, "d.toml"))
    assert design.runs_file is None
    assert design.runs == design_from_dict(_table_design(runs=TABLE)).runs
    assert design.n_tests == 4 and design.kind == "run table"
    # the written design holds the rows: it reloads without the CSV, to the same runs
    written = design.to_toml()
    assert "runs_file" not in tomllib.loads(written)
    (tmp_path / "tables" / name).unlink()
    elsewhere = tmp_path / "campaign"
    elsewhere.mkdir()
    (elsewhere / "design.toml").write_text(written, encoding="utf-8")
    again = load_design(elsewhere / "design.toml")
    assert again == design
    assert [p.run_id for p in again.points()] == [p.run_id for p in design.points()]


def test_a_run_table_round_trips_through_toml():
    design = design_from_dict(_table_design(runs=TABLE, replicates=3))
    again = design_from_dict(tomllib.loads(design.to_toml()), source="round trip")
    assert again == design
    assert again.runs == design.runs and again.replicates == 3


BAD_RUNS = {
    "one row": ([TABLE[0]], ["runs:", "at least 2 runs, got 1"]),
    "no level": (
        [TABLE[0], {**TABLE[1], "WP": 2e-15}],
        ["runs #2.WP", "2e-15 is not a level of factor 'WP'", "1e-15, 1e-14, 1e-13"],
    ),
    "missing factor": (
        [TABLE[0], {k: v for k, v in TABLE[1].items() if k != "WR"}],
        ["runs #2.WR", "missing"],
    ),
    "unknown factor": ([TABLE[0], {**TABLE[1], "X": 1}], ["runs #2.X", "unknown factor 'X'"]),
    "text level": (
        [{**TABLE[0], "A": "high"}, TABLE[1]],
        ["runs #1.A", "expected a number", "'high'"],
    ),
    "boolean level": ([TABLE[0], {**TABLE[1], "S": True}], ["runs #2.S", "True"]),
    "not a table": ([TABLE[0], 3], ["runs #2", "expected a table"]),
    "not a list": ("S=0", ["runs", "expected a list of tables"]),
}


@pytest.mark.parametrize("case", sorted(BAD_RUNS))
def test_bad_run_tables_name_the_row_and_the_factor(case):
    runs, fragments = BAD_RUNS[case]
    with pytest.raises(ConfigError) as info:
        design_from_dict(_table_design(runs=runs), source="bad.toml")
    message = str(info.value)
    assert message.startswith("bad.toml: "), message
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


BAD_CSV = {
    "no level": (
        "S,WP,WR,A\n0,1e-15,1e-07,10\n\n1,2e-13,1e-06,20\n",
        ["line 4", "column 'WP'", "runs #2.WP", "2e-13", "not a level of factor 'WP'"],
    ),
    "decimal comma in a comma file": (
        'S,WP,WR,A\n0,1e-15,1e-07,10\n1,1e-13,1e-06,"20,0"\n',
        ["line 3", "runs #2.A", "'20,0'"],
    ),
    "digits grouped by an underscore": (  # float() reads 1_0 as 10, a level of A
        "S,WP,WR,A\n0,1e-15,1e-07,1_0\n",
        ["line 2", "runs #1.A", "'1_0'", "not a level of factor 'A'"],
    ),
    "unknown column": ("S,WP,WR,A,X\n0,1e-15,1e-07,10,1\n", ["line 1", "'X'", "unknown factor"]),
    "missing column": ("S,WP,A\n0,1e-15,10\n", ["line 1", "no column for factor(s) WR"]),
    "repeated column": ("S,WP,WR,A,S\n", ["line 1", "'S' appears twice"]),
    "too few values": (
        "S,WP,WR,A\n0,1e-15,1e-07,10\n1,1e-13,1e-06\n",
        ["line 3", "expected 4 values (S, WP, WR, A), found 3"],
    ),
    "empty value": (
        "S;WP;WR;A\n0;1e-15;1e-07;10\n1;;1e-06;20\n",
        ["line 3", "runs #2.WP", "no value"],
    ),
    "one row": ("# one\nS,WP,WR,A\n0,1e-15,1e-07,10\n", ["at least 2 runs, found 1"]),
    "leading empty cell": (  # a tab-separated row whose first cell is empty keeps that cell
        "S\tWP\tWR\tA\n\t1e-15\t1e-07\t10\n",
        ["line 2", "runs #1.S", "no value"],
    ),
    "header cell without a name": ("\tWP\tWR\tA\n", ["line 1", "column 1 of the header"]),
    "empty file": ("# nothing\n\n", ["empty file"]),
}


@pytest.mark.parametrize("case", sorted(BAD_CSV))
def test_bad_run_table_files_name_the_file_and_line(tmp_path, case):
    text, fragments = BAD_CSV[case]
    (tmp_path / "runs.csv").write_text(text, encoding="utf-8")
    path = _write(tmp_path, _table_design(runs_file="runs.csv"))
    with pytest.raises(ConfigError) as info:
        load_design(path)
    message = str(info.value)
    assert message.startswith(f"{path}: runs_file: {tmp_path / 'runs.csv'}"), message
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def test_a_missing_run_table_file_is_named(tmp_path):
    path = _write(tmp_path, _table_design(runs_file="absent.csv"))
    with pytest.raises(ConfigError, match=r"bad\.toml: runs_file: cannot read .*absent\.csv"):
        load_design(path)


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        ({"runs": TABLE, "generators": ["S = WR*A"]}, "generators, runs: "),
        ({"runs_file": "runs.csv", "generators": ["S = WR*A"]}, "generators, runs_file: "),
        ({"runs": TABLE, "runs_file": "runs.csv"}, "runs, runs_file: "),
    ],
)
def test_a_design_has_one_kind(tmp_path, extra, fragment):
    (tmp_path / "runs.csv").write_text("\n".join(CSV_ROWS), encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        design_from_dict(_table_design(**extra), source="bad.toml", root=tmp_path)
    assert str(info.value).startswith(f"bad.toml: {fragment}"), str(info.value)
    assert "not both" in str(info.value)


def test_an_unread_runs_file_is_no_design_to_run():
    design = Design.model_validate(_table_design(runs_file="runs.csv"))
    assert design.kind == "run table"
    with pytest.raises(ConfigError, match=r"runs_file 'runs\.csv' is not read yet"):
        design.combinations()


def test_the_shipped_screening_design_is_the_standard_16_run_fraction():
    design = load_design("screen")
    assert design.n_tests == 16 and design.resolution == 4
    assert design.kind == "2^(7-3) fractional factorial, resolution IV"
    words = design.defining_relation()
    assert len(words) == 7 and all(sign == 1 and len(w) == 4 for sign, w in words)
    # every pair of its factors is a full 2 x 2 in the 16 tests (resolution >= 3)
    combos = design.combinations()
    for a, b in itertools.combinations(design.factor_names, 2):
        assert len({(c[a], c[b]) for c in combos}) == 4


def test_the_designs_guide_run_table_example_loads():
    guide = (Path(__file__).parents[2] / "docs" / "designs.md").read_text(encoding="utf-8")
    example = next(
        b for b in guide.split("```toml\n")[1:] if b.lstrip().startswith('name = "points"')
    )
    data = tomllib.loads(example.split("```", 1)[0])
    paper = tomllib.loads(design_path("paper").read_text(encoding="utf-8"))
    design = design_from_dict({**data, "factors": paper["factors"]}, source="docs/designs.md")
    assert design.kind == "run table" and design.n_tests == 3
    assert design.combinations()[1] == {"S": 1.0, "WP": 1e-13, "WR": 1e-6, "A": 20.0}


def test_a_folder_named_like_a_shipped_design_does_not_hide_it(tmp_path, monkeypatch):
    (tmp_path / "screen").mkdir()  # a campaign folder, as 'brakeca run screen -o screen' makes
    monkeypatch.chdir(tmp_path)
    assert load_design("screen").name == "screen"


def test_the_defining_relation_text_is_bounded():
    design = load_design("screen")
    assert design.relation_text(most=2) == (
        "I = S*WP*WR*modulus = S*WP*mu0*slope = ... (7 words in all)"
    )
    # 2^(15-11): fifteen two-level factors in 16 runs, 2047 words
    names = [f"F{k}" for k in range(15)]
    words = ["F0*F1", "F0*F2", "F0*F3", "F1*F2", "F1*F3", "F2*F3", "F0*F1*F2", "F0*F1*F3"]
    words += ["F0*F2*F3", "F1*F2*F3", "F0*F1*F2*F3"]
    data = {
        "name": "saturated",
        "base": "paper",
        "root_seed": 1,
        "factors": [{"name": n, "field": f, "levels": v} for n, f, v in _fifteen(names)],
        "generators": [f"{n} = {w}" for n, w in zip(names[4:], words, strict=True)],
    }
    design = design_from_dict(data)
    assert design.n_tests == 16 and design.resolution == 3
    assert design.relation_text().endswith("= ... (2,047 words in all)")
    assert design.relation_text().count(" = ") == 16  # I = 15 words = ...


def _fifteen(names):
    """Fifteen two-level factors on real fields (their levels within range)."""
    fields = [
        ("friction.mu_0", [0.5, 0.7]),
        ("friction.slope", [2e-8, 4e-8]),
        ("friction.mu_min", [0.1, 0.15]),
        ("contact.elastic_modulus", [5e8, 2e9]),
        ("contact.bar_length", [0.005, 0.01]),
        ("wear.specific_wear_rate", [1e-15, 1e-13]),
        ("wear.resin_wear_depth", [1e-7, 1e-6]),
        ("automaton.secondary_removal_fraction", [0.0, 1.0]),
        ("pad.fibre_area_fraction", [0.1, 0.2]),
        ("pad.resin_roughness", [5e-5, 1e-4]),
        ("pad.fibre_length_min", [0.001, 0.002]),
        ("pad.fibre_length_max", [0.008, 0.01]),
        ("pad.fibre_diameter_min", [0.0002, 0.0003]),
        ("pad.fibre_diameter_max", [0.0006, 0.0007]),
        ("vehicle.wheel_load_mass", [600.0, 690.0]),
    ]
    return [(n, f, v) for n, (f, v) in zip(names, fields, strict=True)]


# --- fold-over ------------------------------------------------------------------------------


def _screen(**extra: Any) -> dict[str, Any]:
    return {**tomllib.loads(design_path("screen").read_text(encoding="utf-8")), **extra}


def test_a_fold_over_appends_the_mirrored_tests_and_keeps_the_first_half():
    screen = load_design("screen")
    folded = design_from_dict(_screen(foldover=["S"]))
    assert folded.n_tests == 32
    assert folded.kind == "2^(7-3) fractional factorial folded over on S, resolution IV"
    first, second = folded.combinations()[:16], folded.combinations()[16:]
    assert first == screen.combinations()
    assert second == [{**c, "S": 1.0 - c["S"]} for c in first]
    # the same test numbers, so the same seeds and run ids: a campaign folder reuses them
    assert [p.run_id for p in folded.points()][:16] == [p.run_id for p in screen.points()]
    # the words holding S are resolved; the others stay
    assert folded.defining_relation() == [
        (1, ("WP", "WR", "A", "mu0")),
        (1, ("WP", "A", "modulus", "slope")),
        (1, ("WR", "modulus", "mu0", "slope")),
    ]
    assert folded.resolution == 4
    again = design_from_dict(tomllib.loads(folded.to_toml()))
    assert again == folded and again.combinations() == folded.combinations()


def test_folding_a_resolution_three_fraction_on_all_factors_clears_the_main_effects():
    data = {
        "name": "r3",
        "base": "paper",
        "root_seed": 1,
        "factors": [
            {"name": "S", "levels": [0, 1]},
            {"name": "A", "levels": [10, 20]},
            {"name": "WR", "levels": [1e-7, 1e-6]},
        ],
        "generators": ["WR = S*A"],
    }
    folded = design_from_dict({**data, "foldover": "all"})
    assert folded.foldover == ("S", "A", "WR")  # "all" is written out
    assert folded.n_tests == 8 and folded.resolution is None
    assert folded.kind.endswith("a full factorial of its two-level factors")
    assert sorted(map(tuple, (c.values() for c in folded.combinations()))) == sorted(
        map(
            tuple, (c.values() for c in design_from_dict({**data, "generators": []}).combinations())
        )
    )
    assert folded.relation_text().startswith("I (no words")


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        ({"foldover": ["X"]}, "foldover.0: unknown factor 'X'"),
        ({"foldover": ["S", "S"]}, "foldover.1: factor 'S' is named twice"),
        ({"foldover": "S"}, "expected a list of factor names or 'all'"),
        ({"foldover": "all"}, "gives the fraction's own tests back"),
        ({"generators": [], "foldover": ["S"]}, "a full factorial folded over repeats"),
    ],
)
def test_bad_fold_overs_are_refused_naming_the_key(extra, fragment):
    with pytest.raises(ConfigError) as info:
        design_from_dict(_screen(**extra), source="f.toml")
    assert fragment in str(info.value)


def test_a_run_table_folds_over_too():
    design = design_from_dict(_table_design(runs=TABLE[:2], foldover=["S", "A"]))
    assert design.kind == "run table folded over on S, A" and design.n_tests == 4
    assert design.combinations()[2] == {"S": 1.0, "WP": 1e-15, "WR": 1e-7, "A": 20.0}
    with pytest.raises(ConfigError, match=r"foldover\.0: factor 'WP' has 3 levels"):
        design_from_dict(_table_design(runs=TABLE, foldover=["WP"]))


# --- standard fractions (fraction_runs) -----------------------------------------------------

#: The resolution each standard fraction has (Box, Hunter and Hunter; Montgomery)
STANDARD_RESOLUTION = {
    (3, 4): 3,
    (4, 8): 4,
    (5, 8): 3,
    (5, 16): 5,
    (6, 8): 3,
    (6, 16): 4,
    (6, 32): 6,
    (7, 8): 3,
    (7, 16): 4,
    (7, 32): 4,
    (7, 64): 7,
    (8, 16): 4,
    (8, 32): 4,
    (8, 64): 5,
    (9, 16): 3,
    (9, 32): 4,
    (9, 64): 4,
    (10, 16): 3,
    (10, 32): 4,
}


@pytest.mark.parametrize(("k", "runs"), sorted(STANDARD_RESOLUTION))
def test_every_standard_fraction_has_its_resolution(k, runs):
    factors = _fifteen([f"F{i}" for i in range(15)])[:k]
    data = {
        "name": "std",
        "base": "paper",
        "root_seed": 1,
        "factors": [{"name": n, "field": f, "levels": v} for n, f, v in factors],
        "fraction_runs": runs,
    }
    design = design_from_dict(data)
    assert design.n_tests == runs and len(design.generators) == k - int(math.log2(runs))
    assert design.resolution == STANDARD_RESOLUTION[(k, runs)]
    assert sorted(STANDARD_FRACTIONS) == sorted(STANDARD_RESOLUTION)


def test_fraction_runs_writes_the_standard_generators_out():
    data = _screen()
    data.pop("generators")
    design = design_from_dict({**data, "fraction_runs": 16})
    assert design.generators == ("modulus = S*WP*WR", "mu0 = WP*WR*A", "slope = S*WR*A")
    assert design == load_design("screen")  # the shipped screen is the standard 2^(7-3)
    assert "fraction_runs" not in design.to_toml() and "generators" in design.to_toml()
    assert design_from_dict({**data, "fraction_runs": 128}).kind == "full factorial"
    # a three-level factor is crossed with the fraction of the two-level ones
    mixed = design_from_dict(_table_design(fraction_runs=4, factors=PAPER_FACTORS))
    assert mixed.n_tests == 12 and mixed.generators == ("A = S*WR",)


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        ({"fraction_runs": 12}, "choose one of 8, 16, 32, 64, 128"),
        ({"fraction_runs": 16.0}, "expected a whole number of runs"),
        ({"fraction_runs": 16, "generators": ["mu0 = S*WP"]}, "not two of them"),
    ],
)
def test_bad_fraction_runs_are_refused(extra, fragment):
    data = _screen(**extra)
    if "generators" not in extra:
        data.pop("generators")
    with pytest.raises(ConfigError) as info:
        design_from_dict(data, source="f.toml")
    assert "f.toml: fraction_runs: " in str(info.value) and fragment in str(info.value)


def test_a_full_factorial_beyond_the_runs_a_design_may_have_is_not_offered():
    """20 two-level factors were offered their full factorial's 1,048,576 runs, which a design
    may not have (a fuzz review)."""
    from brakeca.design import standard_generators

    names = [f"F{i}" for i in range(20)]
    with pytest.raises(ValueError) as info:
        standard_generators(names, 16)
    text = str(info.value)
    assert "full factorial's 1,048,576 runs are more than a design may have" in text
    assert "choose" not in text
    with pytest.raises(ValueError, match=r"choose 2048 \(the full factorial\), or write"):
        standard_generators(names[:11], 5)


@pytest.mark.parametrize(
    ("extra", "factor", "message"),
    [
        (
            {},
            {"name": "A", "levels": [10]},
            "factors #1.levels: needs at least 2 items (got (10,))",
        ),
        ({}, {"name": "A", "levels": [10, 10]}, "levels must all differ, got [10, 10]"),
        (
            {"generators": "A = S*WP"},
            {"name": "A", "levels": [10, 20]},
            "generators: should be a list, in brackets: [...] (got 'A = S*WP')",
        ),
    ],
)
def test_shape_errors_read_as_sentences(extra, factor, message) -> None:
    """pydantic's wording ("Tuple should have at least 2 items after validation") and a value
    given twice ("got [10, 10] (got [10, 10])") are rewritten (a user review)."""
    with pytest.raises(ConfigError) as info:
        design_from_dict(
            {"name": "n", "base": "paper", "root_seed": 1, "factors": [factor], **extra}
        )
    assert str(info.value).endswith(message)


def test_quick_with_an_override_of_the_band_is_refused() -> None:
    """--quick sets mesh.n_radial and mesh.inner_radius itself: an override of either beside
    it would be silently ignored (a user review ran --quick --set mesh.n_radial=201)."""
    paper = load_design("paper")
    for key in ("mesh.n_radial", "mesh.inner_radius", "quick"):
        with pytest.raises(ConfigError, match=rf"override {key}: --quick sets the band itself"):
            paper.resolved_base(overrides={key: 41}, quick=True)
    assert paper.resolved_base(overrides={"mesh.n_radial": 41}).mesh.n_radial == 41


def test_a_factor_on_what_quick_or_stops_sets_is_refused_with_them() -> None:
    """A black-box review: a factor on cycle.max_stops silently overrode --stops (and the
    report spoke of the stops --stops asked for), and a factor on mesh.n_radial with --quick
    was refused with a message about setting ``quick``, which the user had not set."""

    def design(field: str, levels: list[int]):
        spec = {"name": "f", "field": field, "levels": levels}
        return design_from_dict({"name": "n", "base": "paper", "root_seed": 1, "factors": [spec]})

    stops = design("cycle.max_stops", [2, 4])
    with pytest.raises(
        ConfigError,
        match=r"max_stops \(--stops\): the design's factor 'f' sets cycle.max_stops in every run",
    ):
        stops.points(max_stops=3)
    assert [p.config.cycle.max_stops for p in stops.points()] == [2, 4]
    rows = design("mesh.n_radial", [21, 31])
    with pytest.raises(
        ConfigError,
        match=r"quick \(--quick\): the design's factor 'f' sets mesh.n_radial, which --quick sets",
    ):
        rows.points(quick=True)
    assert [p.config.mesh.n_radial for p in rows.points()] == [21, 31]


@pytest.mark.parametrize("name", ["MU", "V", "V_mm3", "wall_time", "mean_cof", "log10_V_mm3"])
def test_a_factor_may_not_take_a_results_name(name) -> None:
    """A factor named MU was accepted, then its summary column held the response and the
    analysis failed with a traceback (a second review)."""
    spec = {"name": name, "field": "friction.mu_0", "levels": [0.5, 0.7]}
    with pytest.raises(ConfigError, match=rf"factor name '{name}' is the name of a result"):
        design_from_dict({"name": "n", "base": "paper", "root_seed": 1, "factors": [spec]})


def test_the_result_names_are_the_run_files() -> None:
    """The reserved result names cover what a run file and its summary row hold."""
    from brakeca.presets import load_preset
    from brakeca.results import RUN_SCALARS, result_names
    from brakeca.simulation import simulate

    config = load_preset("paper").with_updates(
        {"mesh.n_radial": 3, "mesh.n_angular": 100, "cycle.max_stops": 1}
    )
    run = simulate(config, seed=1)
    assert tuple(run.scalars()) == RUN_SCALARS
    per_stop = {str(n) for n, v in run.dataset.data_vars.items() if v.dims[:1] == ("stop",)}
    assert per_stop <= result_names()


def test_a_scale_on_a_paper_factor_is_refused() -> None:
    """field 'A' converts % itself: scale = 0.01 on it made A = 10 set 0.1 % (a second
    review); the field's own name takes the scale."""
    spec = {"name": "A", "levels": [10.0, 20.0], "scale": 0.01}
    with pytest.raises(ConfigError, match=r"scale: factor 'A' sets the paper factor A, whose"):
        design_from_dict({"name": "n", "base": "paper", "root_seed": 1, "factors": [spec]})
    spec["field"] = "pad.fibre_area_fraction"
    design = design_from_dict({"name": "n", "base": "paper", "root_seed": 1, "factors": [spec]})
    assert [p.config.pad.fibre_area_fraction for p in design.points()] == pytest.approx([0.1, 0.2])


def test_load_design_takes_a_mapping():
    """load_design({...}) had been a TypeError about paths (an API review): a design written
    in Python is validated as a file's is."""
    data = _paper_dict()
    assert load_design(data) == design_from_dict(data)
    with pytest.raises(ConfigError, match=r"anova_type: .*2 or 3"):
        load_design({**data, "anova_type": 4})


def test_anova_type_is_2_or_3_and_written_only_when_3(tmp_path):
    data = _paper_dict()
    assert load_design("paper").anova_type == 2
    assert "anova_type" not in design_from_dict(data).to_toml()
    three = design_from_dict({**data, "anova_type": 3})
    assert three.anova_type == 3
    written = tmp_path / "three.toml"
    written.write_text(three.to_toml(), encoding="utf-8")
    res = CliRunner().invoke(app, ["design", str(written), "--no-tests"])
    assert res.exit_code == 0 and "ANOVA: Type III (adjusted) sums of squares" in res.output
    assert design_from_dict(tomllib.loads(three.to_toml())).anova_type == 3
    for bad in (1, 4, "3", True, 2.5, 3.0):
        with pytest.raises(ConfigError, match=r"anova_type: .*2 or 3"):
            design_from_dict({**data, "anova_type": bad})


def test_a_factorial_designs_alpha_to_remove_is_written_and_announced(tmp_path):
    reduced = design_from_dict({**_paper_dict(), "alpha_to_remove": 0.1})
    written = tmp_path / "reduced.toml"
    written.write_text(reduced.to_toml(), encoding="utf-8")
    assert load_design(written).alpha_to_remove == 0.1
    res = CliRunner().invoke(app, ["design", str(written), "--no-tests"])
    assert res.exit_code == 0, res.output
    assert "the report reduces its ANOVA model by backward elimination" in res.output
    assert "above 0.1 (alpha_to_remove)" in res.output


def test_model_order_is_a_whole_number_written_and_announced(tmp_path):
    data = _paper_dict()
    three = design_from_dict({**data, "model_order": 3})
    assert three.model_order == 3 and "model_order" not in design_from_dict(data).to_toml()
    written = tmp_path / "three.toml"
    written.write_text(three.to_toml(), encoding="utf-8")
    assert load_design(written).model_order == 3
    res = CliRunner().invoke(app, ["design", str(written), "--no-tests"])
    assert res.exit_code == 0 and "terms up through 3 factors (model_order)" in res.output
    for bad in (0, 11, 2.0, "2"):
        with pytest.raises(ConfigError, match="model_order"):
            design_from_dict({**data, "model_order": bad})


def test_a_model_order_above_the_factors_is_noted(tmp_path):
    data = {**_paper_dict(), "model_order": 7}
    written = tmp_path / "seven.toml"
    written.write_text(design_from_dict(data).to_toml(), encoding="utf-8")
    res = CliRunner().invoke(app, ["design", str(written), "--no-tests"])
    assert res.exit_code == 0 and "the design has 4, so every interaction" in res.output


@pytest.mark.parametrize(
    ("key", "path", "suggestion"),
    [
        ({"center_point": 4}, "center_point", "center_points"),
        ({"replicate": 2}, "replicate", "replicates"),
        ({"anova_typ": 3}, "anova_typ", "anova_type"),
    ],
)
def test_a_mistyped_design_key_gets_a_suggestion(key, path, suggestion):
    with pytest.raises(ConfigError, match=f"{path}: unknown key \\(did you mean '{suggestion}'"):
        design_from_dict({**_paper_dict(), **key})


def test_a_mistyped_factor_or_configuration_key_gets_a_suggestion():
    from brakeca.config import SimulationConfig

    data = _paper_dict()
    data["factors"] = [dict(data["factors"][0], lable="fibres"), *data["factors"][1:]]
    with pytest.raises(ConfigError, match=r"factors #1\.lable: unknown key \(did you mean 'label'"):
        design_from_dict(data)
    with pytest.raises(ConfigError, match=r"mesh\.n_radail: unknown key \(did you mean 'n_radial'"):
        SimulationConfig.from_toml("[mesh]\nn_radail = 21\n", source="cfg")
    with pytest.raises(ConfigError) as far:  # nothing close: no guess
        design_from_dict({**_paper_dict(), "colour": "red"})
    assert "colour: unknown key (got 'red')" in str(far.value)


@pytest.mark.parametrize("bad", [0, -2, 2.5, "3", True])
def test_max_stops_is_checked_under_its_own_name(bad) -> None:
    """run_campaign(max_stops=0) had said "override: cycle.max_stops", naming an override
    nobody gave (a helper's API review)."""
    design = load_design("paper")
    with pytest.raises(ConfigError, match=r"^max_stops: expected a whole number of stops from 1"):
        design.resolved_base(max_stops=bad)
    assert design.resolved_base(max_stops=np.int64(3)).cycle.max_stops == 3


def test_a_preset_name_given_as_base_config_is_told_the_key_for_it(tmp_path) -> None:
    """base_config is a file; a preset's name there gets the key that takes it (base)."""
    path = tmp_path / "d.toml"
    path.write_text(
        'name = "d"\nbase_config = "paper"\nroot_seed = 1\n[[factors]]\nname = "S"\n'
        'field = "automaton.secondary_removal_fraction"\nlevels = [0, 1]\n',
        encoding="utf-8",
    )
    with pytest.raises(ConfigError, match='a shipped preset is given as base = "paper"'):
        load_design(path)


def test_levels_the_analysis_would_read_as_one_are_refused_before_any_run() -> None:
    """Levels within 1e-6 of each other, relative, are one level to the analysis, which had
    refused them with a traceback after every run was made (a helper's fuzzing): the design
    is refused, naming the two levels; so is a composite alpha that puts its axial levels
    that close to the cube's. The two tolerances are one."""
    from brakeca import analysis
    from brakeca.design import LEVEL_RTOL

    assert analysis._LEVEL_RTOL == LEVEL_RTOL
    base = {"name": "n", "base": "paper", "root_seed": 1}
    mu0 = {"name": "mu0", "field": "friction.mu_0", "levels": [0.5, 0.7]}
    close = {"name": "A", "levels": [10.0, 10.0000001]}
    wide = {"name": "A", "levels": [10.0, 20.0]}
    with pytest.raises(ConfigError, match=r"factors #1\.levels: levels 10\.0 and 10\.0000001 "):
        design_from_dict({**base, "factors": [close, mu0]})
    assert design_from_dict({**base, "factors": [{"name": "A", "levels": [10.0, 10.0001]}, mu0]})
    with pytest.raises(ConfigError, match=r"composite\.alpha: alpha = 1\.0000001 puts factor"):
        design_from_dict({**base, "factors": [mu0, wide], "composite": {"alpha": 1.0000001}})
    assert design_from_dict({**base, "factors": [mu0, wide], "composite": {"alpha": 1.01}})


def test_a_combination_that_cannot_run_names_its_choices() -> None:
    """Two categorical levels each valid alone but not together (the lazy kernel and the
    fibre field) are refused when the run is made, before any runs: the message had read
    "level 1 [] is not valid"; it names the choice and the levels it was set with."""
    design = design_from_dict(
        {
            "name": "k",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "kernel", "field": "numerics.kernel", "levels": [0, 1],
                 "choices": ["exact", "lazy"]},
                {"name": "fibres", "field": "pad.fibre_model", "levels": [0, 1],
                 "choices": ["columns", "field"]},
            ],
        }
    )  # fmt: skip
    with pytest.raises(ConfigError) as info:
        design.points()
    assert "factor 'fibres' (field pad.fibre_model): level 'field' with kernel = 'lazy' is not" in (
        str(info.value)
    )


def test_a_choice_the_field_refuses_is_named_as_a_choice() -> None:
    """A misspelt choice had been reported as "factors #1.levels: ... level 'feild'"; the
    mistake is in choices, and the message says so."""
    with pytest.raises(ConfigError) as info:
        design_from_dict(
            {
                "name": "c",
                "base": "paper",
                "root_seed": 1,
                "factors": [
                    {"name": "fibres", "field": "pad.fibre_model", "levels": [0, 1],
                     "choices": ["columns", "feild"]},
                ],
            }
        )  # fmt: skip
    said = str(info.value)
    assert "factors #1.choices: factor 'fibres' (field pad.fibre_model): choice 'feild' is" in said
    assert "'columns', 'layer' or 'field'" in said


def test_the_guide_s_table_of_standard_fractions_is_the_code_s() -> None:
    """docs/designs.md lists every standard fraction ``fraction_runs`` picks, with its
    generators (a docs review found the 7-factor, 64-run one missing)."""
    import re

    guide = (Path(__file__).parents[2] / "docs" / "designs.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+) \| (\d+) \| [IVX]+ \| ([A-Z =,]+) \|$", guide, re.M)
    listed = {
        (int(k), int(n)): tuple(g.replace(" ", "") for g in gens.split(", ")) for k, n, gens in rows
    }
    assert listed == {key: tuple(STANDARD_FRACTIONS[key]) for key in STANDARD_FRACTIONS}


def test_text_a_spreadsheet_or_a_terminal_would_run_is_refused() -> None:
    """A security review: a label starting with = went into the tables' CSV cells, which a
    spreadsheet runs as a formula, and a design's name printed its escape sequences on the
    terminal as they were. Both are refused where the design is read, naming the field;
    the labels brakeca writes itself (-, 0, +, -α, +α) and numbers stay plain."""
    from brakeca.config import BrakeBlock

    def design(**changes: Any) -> dict:
        factor = {"name": "A", "field": "A", "levels": [10.0, 20.0], "labels": ["-", "+"]}
        factor.update(changes.pop("factor", {}))
        return {"name": "d", "base": "paper", "root_seed": 1, "factors": [factor], **changes}

    for changes, message in (
        ({"factor": {"labels": ["=cmd|' /C calc'!A0", "+"]}}, 'labels: "=cmd'),
        ({"factor": {"labels": ["-", "@SUM(1)"]}}, "reads as a formula"),
        ({"factor": {"labels": ["-", "+HYPERLINK(1)"]}}, r"starts with '\+'"),
        ({"factor": {"label": "-low"}}, "label: '-low' starts with '-'"),
        ({"factor": {"unit": "%\x1b[2J"}}, "unit: .* holds a control character"),
        ({"name": "d\x1b]8;;http://x\x1b\\"}, "name: .* holds a control character"),
        ({"description": "two\x07"}, "description: .* holds a control character"),
    ):
        with pytest.raises(ConfigError, match=message):
            design_from_dict(design(**changes))
    plain = design(description="line one\n\tline two", factor={"labels": ["-1", "+2.5"]})
    assert design_from_dict(plain).factors[0].labels == ("-1", "+2.5")
    assert load_design("response_surface").n_tests > 0  # its -α and +α
    with pytest.raises(ValueError, match="block name '=1\\+1' starts with '='"):
        BrakeBlock(
            name="=1+1", initial_speed_kmh=50, final_speed_kmh=0, deceleration_g=0.3, stops=1
        )
