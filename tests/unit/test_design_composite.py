"""Unit tests of brakeca.design's central composite designs (``composite``) and of a factor's
regression coding (``coding``, ``coded_range``)."""

from __future__ import annotations

import itertools
import math
import re
import tomllib
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from brakeca.config import ConfigError
from brakeca.design import Composite, Design, Factor, design_from_dict, load_design
from brakeca.presets import available_designs, load_preset

#: Two-level numeric factors on real configuration fields, whose face-centred composite
#: designs stay inside every field's range.
FACTORS: dict[str, dict[str, Any]] = {
    "mu0": {"field": "friction.mu_0", "levels": [0.5, 0.6]},
    "slope": {"field": "friction.slope", "levels": [1e-8, 2e-8]},
    "modulus": {"field": "contact.elastic_modulus", "levels": [1e9, 2e9]},
    "bar": {"field": "contact.bar_length", "levels": [5e-3, 1e-2]},
    "WP": {"levels": [1e-15, 1e-13], "coding": "log"},
    "WR": {"levels": [1e-7, 1e-6], "coding": "log"},
    "A": {"levels": [10.0, 20.0]},
}


def _factors(*names: str, **changes: dict[str, Any]) -> list[dict[str, Any]]:
    return [{"name": n, **FACTORS[n], **changes.get(n, {})} for n in names]


def _data(names: str | list[dict[str, Any]], **extra: Any) -> dict[str, Any]:
    factors = _factors(*names.split()) if isinstance(names, str) else names
    return {
        "name": "ccd",
        "base": "paper",
        "root_seed": 7,
        "composite": {},
        "factors": factors,
        **extra,
    }


def _ccd(names: str | list[dict[str, Any]], **extra: Any) -> Design:
    return design_from_dict(_data(names, **extra), source="ccd.toml")


def _coded(design: Design, combo: dict[str, Any]) -> tuple[float, ...]:
    return tuple(design.factor(n).coded(v) for n, v in combo.items())


# --- tests and their order ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("names", "center"),
    [
        ("mu0 slope", 1),
        ("mu0 slope", 4),
        ("mu0 slope modulus", 3),
        ("mu0 slope modulus bar", 6),
        ("mu0 slope modulus bar A", 2),
        ("mu0 slope modulus bar A WP", 1),
    ],
)
def test_a_composite_design_has_cube_axial_and_centre_points(names, center):
    design = _ccd(names, composite={"center": center})
    k = len(names.split())
    n = 2**k + 2 * k + center
    assert design.n_tests == n == len(design.combinations())
    assert design.is_composite and design.is_run_table and not design.is_fractional
    coded = [_coded(design, c) for c in design.combinations()]
    # Minitab's standard order: the cube (first factor fastest, - first), the axial points
    # (each factor at -alpha then +alpha), the centre points
    cube = [combo[::-1] for combo in itertools.product((-1.0, 1.0), repeat=k)]
    axial = [tuple(s if j == i else 0.0 for j in range(k)) for i in range(k) for s in (-1.0, 1.0)]
    expected = cube + axial + [(0.0,) * k] * center
    assert [tuple(round(x, 12) + 0.0 for x in point) for point in coded] == expected


def test_the_cube_points_are_the_given_levels_not_recomputed():
    # 0.6 - 0.3 is 0.29999999999999993 and 10.4 - 0.3 10.099999999999998: the cube's levels
    # must be 0.3, 0.9, 10.1 and 10.7 themselves
    factors = [
        {"name": "mu0", "field": "friction.mu_0", "levels": [0.3, 0.9]},
        {"name": "A", "levels": [10.1, 10.7]},
        {"name": "S", "levels": [0, 1]},
    ]
    for alpha in ("face", "rotatable"):
        design = _ccd(factors[:2], composite={"alpha": alpha})
        combos = design.combinations()
        assert {c["mu0"] for c in combos[:4]} == {0.3, 0.9}
        assert {c["A"] for c in combos[:4]} == {10.1, 10.7}
        assert design.factor("mu0").coded_range == (0.3, 0.9)
    # face-centred: the axial points are the given levels too
    face = _ccd(factors)
    assert [c["mu0"] for c in face.combinations()[8:10]] == [0.3, 0.9]
    assert [c["A"] for c in face.combinations()[10:12]] == [10.1, 10.7]
    assert face.factor("mu0").levels == (0.3, 0.6, 0.9)
    s = face.factor("S")
    assert s.levels == (0, 0.5, 1) and all(type(v) is int for v in (s.levels[0], s.levels[2]))


@pytest.mark.parametrize("k", [2, 3, 4])
def test_rotatable_axial_points_lie_at_2_to_the_k_over_4(k):
    names = "mu0 slope modulus bar".split()[:k]
    # wide ranges so the axial points stay valid
    changes = {
        "mu0": {"levels": [0.4, 0.6]},
        "slope": {"levels": [2e-8, 4e-8]},
        "modulus": {"levels": [2e9, 4e9]},
        "bar": {"levels": [0.02, 0.03]},
    }
    design = _ccd(_factors(*names, **changes), composite={"alpha": "rotatable", "center": 2})
    alpha = 2 ** (k / 4)
    assert design.composite is not None
    assert design.composite.alpha_value(k) == pytest.approx(alpha, rel=1e-15)
    axial = design.combinations()[2**k : 2**k + 2 * k]
    for i, name in enumerate(names):
        low, high = changes[name]["levels"]
        mid, half = (low + high) / 2, (high - low) / 2
        assert axial[2 * i][name] == pytest.approx(mid - alpha * half, rel=1e-12)
        assert axial[2 * i + 1][name] == pytest.approx(mid + alpha * half, rel=1e-12)
        others = [n for n in names if n != name]
        for row in axial[2 * i : 2 * i + 2]:
            for n in others:
                lo, hi = changes[n]["levels"]
                assert row[n] == pytest.approx((lo + hi) / 2, rel=1e-12)
        f = design.factor(name)
        assert f.levels == tuple(sorted(f.levels)) and len(f.levels) == 5
        assert f.labels == ("-α", "-", "0", "+", "+α")
        assert (f.levels[1], f.levels[3]) == (low, high)


def test_orthogonal_alpha_makes_the_quadratic_columns_orthogonal():
    # Montgomery (2013), §11.4.2: k = 2 with 4 centre points gives alpha = 1.210
    assert Composite(alpha="orthogonal", center=4).alpha_value(2) == pytest.approx(1.2100, abs=5e-5)
    assert Composite(alpha="orthogonal", center=1).alpha_value(2) == 1.0  # face-centred
    for k, center in itertools.product((2, 3, 4, 5), (1, 3, 6)):
        alpha = Composite(alpha="orthogonal", center=center).alpha_value(k)
        points = [list(c) for c in itertools.product((-1.0, 1.0), repeat=k)]
        points += [
            [s * alpha if j == i else 0.0 for j in range(k)] for i in range(k) for s in (-1, 1)
        ]
        points += [[0.0] * k] * center
        squares = [[x * x for x in p] for p in points]
        means = [sum(col) / len(points) for col in zip(*squares, strict=True)]
        cross = sum((sq[0] - means[0]) * (sq[1] - means[1]) for sq in squares)
        assert cross == pytest.approx(0.0, abs=1e-9), (k, center)
    design = _ccd("mu0 slope", composite={"alpha": "orthogonal", "center": 4})
    assert "(orthogonal, α = 1.21)" in design.kind
    assert design.factor("mu0").levels[0] == pytest.approx(0.55 - 1.21 * 0.05, rel=1e-4)


def test_log_coding_centres_on_the_geometric_mean():
    design = _ccd("WP A WR", composite={"alpha": "rotatable", "center": 2})
    wp, wr = design.factor("WP"), design.factor("WR")
    assert wp.coding == "log" and design.factor("A").coding == "linear"
    assert wp.levels[2] == pytest.approx(1e-14, rel=1e-12)
    assert wr.levels[2] == pytest.approx(math.sqrt(1e-7 * 1e-6), rel=1e-12)
    alpha = 2**0.75
    assert wp.levels[0] == pytest.approx(10 ** (-14 - alpha), rel=1e-12)
    assert wp.levels[4] == pytest.approx(10 ** (-14 + alpha), rel=1e-12)
    assert (wp.levels[1], wp.levels[3]) == (1e-15, 1e-13)
    assert wp.coded(1e-14) == pytest.approx(0.0, abs=1e-12)
    assert wp.coded(wp.levels[4]) == pytest.approx(alpha, rel=1e-12)
    assert wp.uncoded(-1) == 1e-15 and wp.uncoded(1) == 1e-13
    assert design.combinations()[-1] == {
        "WP": wp.levels[2],
        "A": 15.0,
        "WR": wr.levels[2],
    }


def test_labels_and_levels_of_a_face_centred_design():
    design = _ccd("mu0 A")
    for f in design.factors:
        assert f.labels == ("-", "0", "+") and len(f.levels) == 3
        assert f.coded_range == (f.levels[0], f.levels[2])
    labels = [
        tuple(design.factor(n).label_of(v) for n, v in c.items()) for c in design.combinations()
    ]
    assert labels == [
        ("-", "-"),
        ("+", "-"),
        ("-", "+"),
        ("+", "+"),
        ("-", "0"),
        ("+", "0"),
        ("0", "-"),
        ("0", "+"),
        *[("0", "0")] * 4,
    ]


@pytest.mark.parametrize(
    ("composite", "kind"),
    [
        (
            {"center": 3},
            "central composite design (face-centred, α = 1), 3 factors: 8 cube, 6 axial and 3 "
            "centre points",
        ),
        (
            {"alpha": "rotatable", "center": 1},
            "central composite design (rotatable, α = 1.682), 3 factors: 8 cube, 6 axial and 1 "
            "centre point",
        ),
        ({"alpha": "orthogonal", "center": 6}, "central composite design (orthogonal, α = 1.525)"),
        ({"alpha": 1.5}, "central composite design (α = 1.5), 3 factors"),
        ({"alpha": 1}, "central composite design (face-centred, α = 1)"),
    ],
)
def test_kind_describes_the_composite_design(composite, kind):
    factors = _factors("mu0", "A", "WP", mu0={"levels": [0.4, 0.6]})
    assert _ccd(factors, composite=composite).kind.startswith(kind)


def test_replicates_multiply_every_test_and_centre_points_have_their_own_seeds():
    design = _ccd("WP A WR", composite={"center": 3}, replicates=2)
    points = design.points()
    assert design.n_tests == 17 and len(points) == 34
    assert [p.test for p in points] == [t for t in range(1, 18) for _ in range(2)]
    centre = [p for p in points if p.test >= 15]
    assert len({p.levels["A"] for p in centre}) == 1  # the same levels ...
    assert len({p.seed for p in centre}) == 6  # ... each run its own seed
    assert len({p.run_id for p in centre}) == 6
    assert len({p.run_id for p in points}) == 34


# --- round trip ---------------------------------------------------------------------------


@pytest.mark.parametrize("alpha", ["face", "rotatable", "orthogonal", 1.3])
def test_a_composite_design_round_trips_through_toml(alpha):
    design = _ccd("WP A WR", composite={"alpha": alpha, "center": 2})
    text = design.to_toml()
    assert "[composite]" in text and "runs = [" in text
    data = tomllib.loads(text)
    assert data["composite"]["alpha"] == alpha
    again = design_from_dict(data)
    assert again == design
    assert again.combinations() == design.combinations()
    assert again.kind == design.kind
    assert [f.levels for f in again.factors] == [f.levels for f in design.factors]
    assert again.to_toml() == text


def test_coding_is_written_only_when_not_linear():
    design = _ccd("WP A")
    factors = design.to_dict()["factors"]
    assert factors[0]["coding"] == "log" and "coding" not in factors[1]
    assert factors[1]["coded_range"] == [10.0, 20.0]
    paper = load_design("paper").to_dict()
    assert all("coding" not in f and "coded_range" not in f for f in paper["factors"])


def test_a_written_design_with_edited_tests_is_refused():
    data = tomllib.loads(_ccd("mu0 A", composite={"center": 2}).to_toml())
    edited = [dict(r) for r in data["runs"]]
    edited[3]["A"] = 15.0
    with pytest.raises(ConfigError, match=r"ccd.toml: runs #4.A: test 4 of the central composite"):
        design_from_dict({**data, "runs": edited}, source="ccd.toml")
    with pytest.raises(ConfigError, match=r"runs: the central composite design .* has 10 tests"):
        design_from_dict({**data, "runs": data["runs"][:-1]}, source="ccd.toml")
    factors = [dict(f) for f in data["factors"]]
    factors[1]["coded_range"] = [10.0, 30.0]
    with pytest.raises(ConfigError, match=r"factors #2.levels: factor 'A': the central composite"):
        design_from_dict({**data, "factors": factors}, source="ccd.toml")
    factors = [dict(f) for f in data["factors"]]
    del factors[0]["coded_range"]
    with pytest.raises(ConfigError, match=r"factors #1.coded_range: factor 'mu0'"):
        design_from_dict({**data, "factors": factors}, source="ccd.toml")


# --- errors -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (_data("mu0"), r"composite: a central composite design takes 2 to 6 factors, got 1"),
        (
            _data("mu0 slope modulus bar A WP WR"),
            r"composite: a central composite design takes 2 to 6 factors, got 7",
        ),
        (
            _data(_factors("mu0", "A", A={"levels": [10.0, 15.0, 20.0]})),
            r"factors #2.levels: factor 'A': a central composite design takes exactly two levels",
        ),
        (
            _data(_factors("mu0", "A", A={"levels": [20.0, 10.0]})),
            r"factors #2.levels: .*low < high",
        ),
        (
            _data(
                [
                    *_factors("mu0"),
                    {
                        "name": "fibres",
                        "field": "pad.fibre_model",
                        "levels": [0, 1],
                        "choices": ["columns", "field"],
                    },
                ]
            ),
            r"factors #2.choices: factor 'fibres' is categorical",
        ),
        (
            _data(_factors("mu0", "A", A={"labels": ["lo", "hi"]})),
            r"factors #2.labels: factor 'A': a central composite design labels its levels itself",
        ),
        (
            _data(_factors("mu0", "A", A={"coded_range": [10.0, 25.0]})),
            r"factors #2.coded_range: factor 'A'",
        ),
        (_data("mu0 A", generators=["A = mu0"]), r"composite, generators: "),
        (_data("mu0 A", fraction_runs=4), r"composite, fraction_runs: "),
        (_data("mu0 A", runs_file="runs.csv"), r"composite, runs_file: "),
        (_data("mu0 A", foldover="all"), r"composite, foldover: .*no other level"),
        (_data("mu0 A", composite={"alpha": 0.5}), r"composite.alpha: expected 'face'"),
        (_data("mu0 A", composite={"alpha": 11}), r"composite.alpha: expected 'face'"),
        (_data("mu0 A", composite={"alpha": "diagonal"}), r"composite.alpha: expected 'face'"),
        (_data("mu0 A", composite={"alpha": True}), r"composite.alpha: expected 'face'"),
        (_data("mu0 A", composite={"center": 0}), r"composite.center: "),
        (_data("mu0 A", composite={"centre": 3}), r"composite.centre: unknown key"),
    ],
)
def test_a_bad_composite_design_names_the_field(data, message):
    with pytest.raises(ConfigError, match=message):
        design_from_dict(data, source="ccd.toml")


def test_axial_points_outside_a_field_range_name_the_factor():
    # A = 1..5 %, rotatable over 3 factors: 3 - 1.682 * 2 < 0 %
    factors = _factors("mu0", "A", "WP", mu0={"levels": [0.4, 0.6]}, A={"levels": [1.0, 5.0]})
    with pytest.raises(
        ConfigError,
        match=r"ccd.toml: factors #2.levels: factor 'A' .*level -0.36.* an axial level of the "
        r"central composite design \(alpha = 1.682\): choose a smaller alpha",
    ):
        _ccd(factors, composite={"alpha": "rotatable"})
    assert _ccd(factors).factor("A").levels == (1.0, 3.0, 5.0)  # face-centred: inside


@pytest.mark.parametrize(
    ("factor", "message"),
    [
        (
            {"name": "mu0", "field": "friction.mu_0", "levels": [0.0, 0.5], "coding": "log"},
            r"factors #1: coding: factor 'mu0' .* level 0.0 is not",
        ),
        (
            {
                "name": "fibres",
                "field": "pad.fibre_model",
                "levels": [0, 1],
                "choices": ["columns", "field"],
                "coding": "log",
            },
            r"factors #1: coding: factor 'fibres' is categorical",
        ),
        (
            {
                "name": "fibres",
                "field": "pad.fibre_model",
                "levels": [0, 1],
                "choices": ["columns", "field"],
                "coded_range": [0, 1],
            },
            r"factors #1: coded_range: factor 'fibres' is categorical",
        ),
        ({"name": "A", "levels": [10, 20], "coding": "square"}, r"factors #1.coding: "),
        (
            {"name": "A", "levels": [10, 20], "coded_range": [20, 10]},
            r"factors #1.coded_range: .*low < high",
        ),
        (
            {"name": "A", "levels": [10, 20], "coded_range": [10, 10]},
            r"factors #1.coded_range: .*low < high",
        ),
        (
            {"name": "A", "levels": [10, 20], "coded_range": [10]},
            r"factors #1.coded_range: expected two",
        ),
        (
            {"name": "A", "levels": [10, 20], "coded_range": [10, math.inf]},
            r"factors #1.coded_range: expected two finite numbers",
        ),
        (
            {"name": "A", "levels": [10, 20], "coded_range": [0, 20], "coding": "log"},
            r"factors #1: coded_range: factor 'A' is coded 'log' .* 0.0 is not",
        ),
    ],
)
def test_a_bad_coding_names_the_field(factor, message):
    with pytest.raises(ConfigError, match=message):
        design_from_dict({"name": "d", "base": "paper", "root_seed": 1, "factors": [factor]})


def test_a_factorial_factor_may_be_log_coded_with_a_coded_range():
    design = design_from_dict(
        {
            "name": "d",
            "base": "paper",
            "root_seed": 1,
            "factors": [
                {"name": "WP", "levels": [1e-15, 1e-14, 1e-13], "coding": "log"},
                {"name": "A", "levels": [10, 15, 20], "coded_range": [12, 18]},
            ],
        }
    )
    assert design.kind == "full factorial" and design.n_tests == 9
    wp, a = design.factors
    assert wp.coding_range == (1e-15, 1e-13) and wp.coded(1e-14) == pytest.approx(0.0, abs=1e-12)
    assert a.coded(12) == -1.0 and a.coded(18) == 1.0 and a.coded(20) == pytest.approx(5 / 3)
    assert a.uncoded(0) == 15.0
    assert Factor(name="A", levels=(10, 20)).coding_range == (10.0, 20.0)
    assert tomllib.loads(design.to_toml())["factors"][1]["coded_range"] == [12.0, 18.0]


# --- the shipped design -------------------------------------------------------------------


def test_the_shipped_surface_design_is_a_face_centred_ccd_in_17_runs():
    assert "response_surface" in available_designs()
    design = load_design("response_surface")
    assert design.n_tests == 17 and design.replicates == 1 and design.root_seed == 2016
    assert design.factor_names == ("WP", "A", "WR")
    assert design.kind == (
        "central composite design (face-centred, α = 1), 3 factors: 8 cube, 6 axial and 3 "
        "centre points"
    )
    wp, a, wr = design.factors
    assert (wp.coding, a.coding, wr.coding) == ("log", "linear", "log")
    assert wp.levels[0] == 1e-15 and wp.levels[2] == 1e-13
    assert wp.levels[1] == pytest.approx(1e-14, rel=1e-12)
    assert wr.levels[1] == pytest.approx(3.1622776601683795e-7, rel=1e-12)
    assert a.levels == (10.0, 15.0, 20.0)
    points = design.points()
    # every run inside the paper's ranges; S is the paper preset's
    s = load_preset("paper").automaton.secondary_removal_fraction
    assert all(p.config.automaton.secondary_removal_fraction == s for p in points)
    assert all(1e-15 <= p.config.wear.specific_wear_rate <= 1e-13 for p in points)
    assert all(1e-7 <= p.config.wear.resin_wear_depth <= 1e-6 for p in points)
    assert len({p.run_id for p in points}) == 17


# --- Box-Behnken designs ------------------------------------------------------------------


def _bbd(names: str, **extra: Any) -> Design:
    data = _data(names, **extra)
    del data["composite"]
    data.setdefault("box_behnken", {})
    return design_from_dict(data, source="bbd.toml")


@pytest.mark.parametrize(("names", "edges"), [("mu0 slope modulus", 12),
                                              ("mu0 slope modulus bar", 24),
                                              ("mu0 slope modulus bar A", 40)])  # fmt: skip
def test_a_box_behnken_design_pairs_every_two_factors(names, edges):
    design = _bbd(names, box_behnken={"center": 2})
    k = len(names.split())
    assert design.n_tests == edges + 2 and design.is_response_surface
    assert not design.is_composite and design.surface_design is design.box_behnken
    coded = [_coded(design, c) for c in design.combinations()]
    for point in coded[:edges]:  # two factors at an extreme, the others at the centre
        assert sorted(abs(round(x, 12)) for x in point) == [0.0] * (k - 2) + [1.0, 1.0]
    assert {tuple(round(x, 12) + 0.0 for x in p) for p in coded[edges:]} == {(0.0,) * k}
    pairs = {tuple(i for i, x in enumerate(p) if abs(x) > 0.5) for p in coded[:edges]}
    assert pairs == set(itertools.combinations(range(k), 2))  # every pair, each 4 times
    assert all(design.factor(n).labels == ("-", "0", "+") for n in design.factor_names)


def test_box_behnken_standard_order_and_kind():
    """Minitab's standard order for three factors: (A, B), (A, C), (B, C), each pair's 2^2
    with its first factor fastest, then the centre points."""
    design = _bbd("mu0 slope modulus")
    expected = [
        (-1, -1, 0), (1, -1, 0), (-1, 1, 0), (1, 1, 0),
        (-1, 0, -1), (1, 0, -1), (-1, 0, 1), (1, 0, 1),
        (0, -1, -1), (0, 1, -1), (0, -1, 1), (0, 1, 1),
        (0, 0, 0), (0, 0, 0), (0, 0, 0),
    ]  # fmt: skip
    got = [tuple(round(x, 12) + 0.0 for x in _coded(design, c)) for c in design.combinations()]
    assert got == [tuple(float(x) for x in p) for p in expected]
    assert design.kind == (
        "Box-Behnken design, 3 factors: 12 edge points (each pair of factors at - and +, the "
        "others at 0) and 3 centre points"
    )
    back = design_from_dict(tomllib.loads(design.to_toml()), source="written")
    assert back.combinations() == design.combinations() and back.box_behnken == design.box_behnken


@pytest.mark.parametrize(
    ("extra", "names", "message"),
    [
        ({"box_behnken": {}, "composite": {}}, "mu0 slope modulus", "not both"),
        ({"box_behnken": {}}, "mu0 slope", "box_behnken: a Box-Behnken design takes 3 to 5"),
        ({"box_behnken": {"center": 0}}, "mu0 slope modulus", "box_behnken.center"),
        ({"box_behnken": {}, "generators": ["modulus = mu0*slope"]}, "mu0 slope modulus",
         "box_behnken, generators"),
    ],
)  # fmt: skip
def test_a_bad_box_behnken_design_names_the_field(extra, names, message):
    data = _data(names, **extra)
    if "composite" not in extra:
        del data["composite"]
    with pytest.raises(ConfigError, match=re.escape(message)):
        design_from_dict(data, source="bbd.toml")


def test_a_written_box_behnken_design_with_edited_tests_is_refused():
    written = tomllib.loads(_bbd("mu0 slope modulus").to_toml())
    written["runs"][0]["mu0"] = 0.6
    with pytest.raises(ConfigError, match=r"runs #1\.mu0: test 1 of the Box-Behnken design"):
        design_from_dict(written, source="written")


# --- goals ----------------------------------------------------------------------------------

_GOALS = [
    {"response": "V", "goal": "minimize", "lower": 0.1, "upper": 5.0},
    {"response": "MU", "goal": "target", "lower": 0.3, "target": 0.35, "upper": 0.45},
]


def test_goals_of_a_response_surface_design_round_trip_and_convert_v_to_si():
    design = _ccd("mu0 slope", goals=_GOALS)
    v, mu = design.goals
    goal = v.to_goal()
    assert goal.kind == "minimize"  # the limits from mm³ to m³
    assert (goal.lower, goal.upper) == pytest.approx((0.1e-9, 5e-9), rel=1e-15)
    assert mu.to_goal().target == 0.35
    back = design_from_dict(tomllib.loads(design.to_toml()), source="written")
    assert back.goals == design.goals
    assert "goals" not in _ccd("mu0 slope").to_dict()


@pytest.mark.parametrize(
    ("goals", "extra", "message"),
    [
        (_GOALS[:1], {"composite": None}, "goals: the report optimizes goals on the response"),
        ([_GOALS[0], _GOALS[0]], {}, "goals #2.response: 'V' has a goal already"),
        ([{**_GOALS[0], "lower": 5.0, "upper": 0.1}], {},
         "minimize: the target 5 (lower) must be below the upper limit 0.1 (upper)"),
        ([{**_GOALS[1], "target": 0.5}], {}, "a target goal needs a target strictly between 0.3"),
        ([{**_GOALS[0], "response": "W"}], {}, "goals #1.response"),
        ([{**_GOALS[0], "goal": "least"}], {}, "goals #1.goal"),
    ],
)  # fmt: skip
def test_bad_goals_name_the_field(goals, extra, message):
    data = {**_data("mu0 slope", goals=goals), **extra}
    if data.get("composite") is None:
        data.pop("composite")
    with pytest.raises(ConfigError, match=re.escape(message)):
        design_from_dict(data, source="ccd.toml")


def test_the_shipped_surface_design_has_its_example_goals():
    goals = load_design("response_surface").goals
    assert [(g.response, g.goal) for g in goals] == [
        ("log10_V_mm3", "minimize"),
        ("MU", "target"),
    ]


# --- Plackett-Burman designs ----------------------------------------------------------------


def _pb(runs: int, factors: list[dict[str, Any]], **extra: Any) -> Design:
    data = {"name": "pb", "base": "paper", "root_seed": 3, "plackett_burman": runs}
    return design_from_dict({**data, "factors": factors, **extra}, source="pb.toml")


@pytest.mark.parametrize("fold", [("mu0",), ("mu0", "slope"), ("mu0", "slope", "WP")])
def test_a_plackett_burman_design_folded_on_some_factors_says_what_is_clear(fold):
    """A growth review: folded on S, a Plackett-Burman design was said to have its main
    effects clear of each other only, and nothing of the two-factor interactions, though
    WP's correlation with WR*A stays 1/3. What the kind says is checked on the tests: a
    folded factor is clear of the interactions of two folded or two unfolded factors, an
    unfolded one of those of a folded and an unfolded one; the others stay partly
    confounded."""
    import itertools

    names = ("mu0", "slope", "modulus", "WP", "WR", "A")
    design = _pb(12, _factors(*names), foldover=list(fold))
    if len(fold) == 1:
        assert design.kind.endswith(
            "(main effects clear of each other; mu0 clear of the two-factor interactions, "
            "each other partly confounded with those of the unfolded factors)"
        )
    else:
        assert design.kind.endswith(
            "each partly confounded with some two-factor interactions: a folded factor with "
            "those of a folded and an unfolded factor, an unfolded one with those of two "
            "folded or two unfolded factors)"
        )
    combos = design.combinations()
    x = {
        n: np.array([1.0 if c[n] == FACTORS[n]["levels"][1] else -1.0 for c in combos])
        for n in names
    }
    for m in names:
        for a, b in itertools.combinations([n for n in names if n != m], 2):
            clear = (m in fold) == ((a in fold) == (b in fold))
            corr = abs(float(np.mean(x[m] * x[a] * x[b])))
            assert (corr < 1e-12) == clear, (m, a, b, corr)
    whole = _pb(12, _factors(*names), foldover="all")
    assert whole.kind.endswith(
        "(main effects clear of each other and of the two-factor interactions)"
    )


def test_the_published_generators_are_the_quadratic_residue_rows():
    """Plackett and Burman's 12-, 20-, 24-, 44- and 48-run generators (as Minitab's "Summary
    of Plackett-Burman designs" prints them) are Paley's quadratic-residue rows of 11, 19,
    23, 43 and 47, from which the 44- and 48-run ones are made here."""
    from brakeca.design import (
        PLACKETT_BURMAN,
        PLACKETT_BURMAN_GENERATORS,
        _quadratic_residue_row,
    )

    printed = {
        44: "++--+-+--+++-+++++---+-+++-----+---++-+-++-",
        48: "+++++-++++--+-+-+++--+--++-++---+-+-++----+----",
    }
    for runs in (12, 20, 24, 44, 48):
        assert _quadratic_residue_row(runs - 1) == PLACKETT_BURMAN_GENERATORS[runs]
        assert PLACKETT_BURMAN_GENERATORS[runs] == printed.get(
            runs, PLACKETT_BURMAN_GENERATORS[runs]
        )
    assert PLACKETT_BURMAN == (12, 20, 24, 28, 32, 36, 44, 48)


def test_plackett_burman_tests_are_minitabs():
    """Minitab's own example (its help, "Example of a Plackett-Burman design with center
    points": 9 factors in 12 runs, randomized, centre points left out here) holds the tests
    brakeca makes for 9 factors, and not those of the generator read as a row."""
    from brakeca.design import _plackett_burman_signs, _plackett_burman_signs_by_rows

    minitab = """
        ---+++-++ +++-++-+- +-+---+++ +-++-+--- -++-+---+ ++-+---++
        --------- +---+++-+ -+---+++- --+++-++- -+++-++-+ ++-++-+--
    """
    rows = {tuple(1 if c == "+" else -1 for c in word) for word in minitab.split()}
    assert len(rows) == 12
    assert {tuple(t) for t in _plackett_burman_signs(12, 9)} == rows
    assert {tuple(t) for t in _plackett_burman_signs_by_rows(12, 9)} != rows
    # Minitab's standard order: the generator is the first factor's column
    first = [t[0] for t in _plackett_burman_signs(12, 11)]
    assert "".join("+" if x > 0 else "-" for x in first) == "++-+++---+--"


@pytest.mark.parametrize("runs", [12, 20, 24, 28, 32, 36, 44, 48])
def test_plackett_burman_columns_are_balanced_and_orthogonal(runs):
    from brakeca.design import _plackett_burman_signs

    signs = _plackett_burman_signs(runs, runs - 1)
    assert len(signs) == runs and signs[-1] == [-1] * (runs - 1)
    assert len({tuple(t) for t in signs}) == runs
    for i, j in itertools.combinations_with_replacement(range(runs - 1), 2):
        dot = sum(row[i] * row[j] for row in signs)
        assert dot == (runs if i == j else 0)
    assert all(sum(row[i] for row in signs) == 0 for i in range(runs - 1))


def test_the_28_run_design_shifts_its_three_blocks():
    from brakeca.design import PLACKETT_BURMAN_28, _plackett_burman_signs

    signs = _plackett_burman_signs(28, 27)
    text = ["".join("+" if x > 0 else "-" for x in t) for t in signs]
    assert text[:9] == list(PLACKETT_BURMAN_28)
    for i, row in enumerate(PLACKETT_BURMAN_28):
        a, b, c = row[:9], row[9:18], row[18:]
        assert text[9 + i] == c + a + b and text[18 + i] == b + c + a


def test_a_plackett_burman_design_writes_its_tests_and_reads_back():
    factors = [
        {"name": "mu0", "field": "friction.mu_0", "levels": [0.5, 0.7]},
        *({"name": n, **FACTORS[n]} for n in ("slope", "modulus", "bar", "WP", "WR", "A")),
    ]
    design = _pb(12, factors)
    assert design.n_tests == 12 and design.kind.startswith(
        "Plackett-Burman design, 12 tests, 7 factors (main effects clear"
    )
    combos = design.combinations()
    # the generator ++-+++---+- down the first factor's column: test 1 is + - + - - - + ...
    assert (
        combos[0]["mu0"] == 0.7
        and combos[0]["slope"] == 1e-8
        and combos[0]["modulus"] == (FACTORS["modulus"]["levels"][1])
    )
    assert combos[-1] == {f["name"]: f["levels"][0] for f in factors}  # the all-minus test
    back = design_from_dict(tomllib.loads(design.to_toml()), source="written")
    assert back.combinations() == combos and back.plackett_burman == 12
    written = tomllib.loads(design.to_toml())
    written["runs"][3]["A"] = 20.0 if written["runs"][3]["A"] == 10.0 else 10.0
    with pytest.raises(ConfigError, match=r"runs #4\.A: test 4 of the Plackett-Burman"):
        design_from_dict(written, source="written")
    # a design written before brakeca took Minitab's order (the generator as the first test)
    # still reads back, so that its campaign stays readable; another order does not
    from brakeca.design import _plackett_burman_signs_by_rows

    earlier = tomllib.loads(design.to_toml())
    earlier["runs"] = [
        {f["name"]: f["levels"][(x + 1) // 2] for f, x in zip(factors, signs, strict=True)}
        for signs in _plackett_burman_signs_by_rows(12, 7)
    ]
    assert design_from_dict(earlier, source="earlier").runs == tuple(earlier["runs"])
    earlier["runs"] = earlier["runs"][1:] + earlier["runs"][:1]
    with pytest.raises(ConfigError, match=r"runs #1\.\w+: test 1 of the Plackett-Burman"):
        design_from_dict(earlier, source="earlier")
    folded = _pb(12, factors, foldover="all")
    assert folded.n_tests == 24 and "folded over on mu0, slope" in folded.kind


@pytest.mark.parametrize(
    ("runs", "factors", "extra", "message"),
    [
        (16, 3, {}, "plackett_burman: expected the number of tests, one of 12, 20, 24"),
        (12, 1, {}, "a design of 12 tests takes 2 to 11 factors, got 1"),
        (12, 3, {"generators": ["x = a*b"]}, "plackett_burman, generators"),
    ],
)
def test_a_bad_plackett_burman_design_names_the_field(runs, factors, extra, message):
    names = ("mu0", "slope", "modulus")[:factors]
    with pytest.raises(ConfigError, match=re.escape(message)):
        _pb(runs, _factors(*names), **extra)
    three = _factors("mu0", "slope", mu0={"levels": [0.5, 0.6, 0.7]})
    with pytest.raises(ConfigError, match=re.escape("factors #1.levels: factor 'mu0'")):
        _pb(12, three)


# --- any input: a design or a ConfigError, nothing else --------------------------------------

_ANY = st.one_of(
    st.none(), st.booleans(), st.integers(-3, 30), st.floats(allow_nan=True),
    st.sampled_from(["face", "rotatable", "orthogonal", "x"]), st.just([]), st.just({}),
    st.lists(st.floats(-1, 30), max_size=3),
)  # fmt: skip
_FACTOR = st.fixed_dictionaries(
    {"name": st.sampled_from(["S", "WP", "WR", "A", "x y", "mu0"]), "levels": _ANY},
    optional={
        "field": st.sampled_from(["friction.mu_0", "friction.slope", "cycle", "no.such"]),
        "coding": st.sampled_from(["log", "linear", "exp"]),
        "coded_range": _ANY,
        "labels": st.just(["-", "+"]),
    },
)


@settings(max_examples=150, deadline=None)
@given(
    factors=st.lists(_FACTOR, max_size=5),
    key=st.sampled_from(["composite", "box_behnken", "plackett_burman"]),
    value=st.one_of(_ANY, st.fixed_dictionaries({}, optional={"alpha": _ANY, "center": _ANY})),
    goals=st.one_of(st.none(), st.lists(st.fixed_dictionaries({"response": _ANY}), max_size=2)),
)
def test_any_response_surface_or_screening_input_gives_a_design_or_a_config_error(
    factors, key, value, goals
):
    data: dict[str, Any] = {"name": "f", "base": "paper", "root_seed": 1, "factors": factors}
    data[key] = value
    if goals is not None:
        data["goals"] = goals
    import warnings

    from brakeca.config import UnitWarning

    try:
        with warnings.catch_warnings():  # levels that read like slips of unit are allowed
            warnings.simplefilter("ignore", UnitWarning)
            design_from_dict(data, source="fuzz.toml")
    except ConfigError as exc:
        assert str(exc).startswith("fuzz.toml")


@pytest.mark.parametrize("value", [{}, [], "12", 12.0, True])
def test_a_plackett_burman_size_that_is_no_whole_number_names_the_field(value):
    with pytest.raises(ConfigError, match="plackett_burman: expected the number of tests"):
        _pb(value, _factors("mu0", "slope"))  # type: ignore[arg-type]


def test_alpha_to_remove_of_a_response_surface_and_of_a_factorial_design():
    design = _ccd("mu0 slope", alpha_to_remove=0.1)
    assert design.alpha_to_remove == 0.1
    assert design_from_dict(tomllib.loads(design.to_toml())).alpha_to_remove == 0.1
    for value, message in [(1.5, "alpha_to_remove"), (0.0, "alpha_to_remove")]:
        with pytest.raises(ConfigError, match=message):
            _ccd("mu0 slope", alpha_to_remove=value)
    # a factorial design's report reduces its ANOVA model instead (it was refused before)
    data = {**_data("mu0 slope", alpha_to_remove=0.1)}
    del data["composite"]
    factorial = design_from_dict(data, source="x.toml")
    assert factorial.alpha_to_remove == 0.1 and not factorial.is_response_surface


def test_model_order_is_refused_for_a_response_surface_design():
    with pytest.raises(ConfigError, match="model_order: a central composite design's report"):
        _ccd("mu0 slope", model_order=2)
