"""`brakeca design`: a design's kind, runs, defining relation, alias structure and tests,
before anything runs."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from brakeca.cli import app


def _design(*args: str) -> str:
    res = CliRunner().invoke(app, ["design", *args], env={"COLUMNS": "120"})
    assert res.exit_code == 0, res.output
    return res.output


def test_a_fraction_shows_its_generators_relation_and_alias_chains() -> None:
    text = _design("screen")
    assert text.startswith("screen: 2^(7-3) fractional factorial, resolution IV\n")
    assert "16 tests × 1 replicate(s) = 16 runs; root seed 2016" in text
    assert "generators: modulus = S*WP*WR, mu0 = WP*WR*A, slope = S*WR*A" in text
    assert "defining relation: I = S*WP*WR*modulus = " in text
    # the chains, with three-factor terms printed as they are (rich would make ':a:' an emoji)
    assert "  S:WP + WR:modulus + mu0:slope\n" in text
    assert "WR:A:slope" in text
    assert "│   16 │ + │  + │  + │ + │       + │   + │     + │" in text  # the last test, all +


def test_a_full_factorial_is_clear_and_a_bad_design_names_its_problem(tmp_path) -> None:
    text = _design("paper", "--no-tests")
    assert "paper: full factorial" in text and "24 tests" in text
    assert "every main effect and two-factor interaction is clear" in text
    assert "tests" not in text.split("\n", 3)[-1]  # --no-tests: no table
    bad = tmp_path / "bad.toml"
    bad.write_text(
        'name = "bad"\nbase = "paper"\nroot_seed = 1\ngenerators = ["A = S"]\n'
        '[[factors]]\nname = "S"\nlevels = [0, 1]\n[[factors]]\nname = "A"\nlevels = [10, 20]\n'
    )
    res = CliRunner().invoke(app, ["design", str(bad)])
    assert res.exit_code == 2
    assert "generators #1: the fraction has resolution II" in res.output


def test_a_composite_design_shows_its_coding_and_quadratic_model(tmp_path) -> None:
    text = _design("response_surface")
    assert text.startswith(
        "response_surface: central composite design (face-centred, α = 1), 3 factors"
    )
    assert "coded -1 to +1: WP log10 1e-15 to 1e-13 m^3/(N m); A 10 to 20 %; WR log10" in text
    assert (
        "response-surface model: 10 coefficients (3 linear, 3 square, 3 interaction terms and "
        "the constant) from 17 runs: 7 residual df, 2 of them pure error" in text
    )
    assert "│   17 │  0 │ 0 │  0 │" in text  # the last centre point
    # its terms' correlation is the quadratic's (VIF), not the categorical alias structure's
    # (a second review saw 'partly confounded (correlations up to 0.67)' for this design)
    assert "alias structure" not in text and "partly confounded" not in text
    assert "largest variance inflation factor of its terms: 1.54 (WP*WP;" in text
    # one centre point: no pure error; a rotatable alpha gives five levels, -α to +α
    two = tmp_path / "two.toml"
    two.write_text(
        'name = "two"\nbase = "paper"\nroot_seed = 1\n[composite]\nalpha = "rotatable"\n'
        "center = 1\n"
        '[[factors]]\nname = "A"\nlevels = [12, 18]\n[[factors]]\nname = "S"\nlevels = [0.2, 0.8]\n'
    )
    text = _design(str(two))
    assert "6 coefficients (2 linear, 2 square, 1 interaction terms and the constant)" in text
    assert "from 9 runs" in text
    assert "3 residual df, 0 of them pure error" in text
    assert "│    5 │ -α │  0 │" in text


def test_a_box_behnken_design_shows_its_quadratic_model(tmp_path) -> None:
    bbd = tmp_path / "bbd.toml"
    bbd.write_text(
        'name = "bbd"\nbase = "paper"\nroot_seed = 1\n[box_behnken]\ncenter = 3\n'
        '[[factors]]\nname = "WP"\nlevels = [1e-15, 1e-13]\ncoding = "log"\n'
        '[[factors]]\nname = "A"\nlevels = [10, 20]\n'
        '[[factors]]\nname = "WR"\nlevels = [1e-7, 1e-6]\ncoding = "log"\n'
    )
    text = _design(str(bbd))
    assert text.startswith("bbd: Box-Behnken design, 3 factors: 12 edge points")
    assert "10 coefficients (3 linear, 3 square, 3 interaction terms and the constant)" in text
    assert "from 15 runs: 5 residual df, 2 of them pure error" in text
    assert "│    1 │  - │ - │  0 │" in text


def test_a_plackett_burman_design_is_partly_confounded(tmp_path) -> None:
    pb = tmp_path / "pb.toml"
    pb.write_text(
        'name = "pb"\nbase = "paper"\nroot_seed = 1\nplackett_burman = 12\n'
        + "".join(
            f'[[factors]]\nname = "{n}"\nlevels = {levels}\n'
            for n, levels in [("S", "[0, 1]"), ("WP", "[1e-15, 1e-13]"), ("WR", "[1e-7, 1e-6]"),
                              ("A", "[10, 20]"), ("mu0", "[0.5, 0.7]")]
        ).replace('name = "mu0"', 'name = "mu0"\nfield = "friction.mu_0"')
    )  # fmt: skip
    text = _design(str(pb), "--no-tests")
    assert text.startswith("pb: Plackett-Burman design, 12 tests, 5 factors")
    assert "no main effect or two-factor interaction is completely aliased" in text
    # (they were listed as 'partly confounded', which a partly confounded term is not: a
    # black-box review)
    assert "not estimable (each aliased with a combination of the terms before it, though " in text
    # twenty runs estimate all five main effects and ten interactions, but not orthogonally
    pb.write_text(pb.read_text().replace("plackett_burman = 12", "plackett_burman = 20"))
    text = _design(str(pb), "--no-tests")
    assert "clear of the others" not in text
    assert "but some are partly confounded (correlations up to 0.2" in " ".join(text.split())


def test_a_bad_optimize_goal_is_named_in_its_own_units(tmp_path) -> None:
    res = CliRunner().invoke(app, ["optimize", str(tmp_path), "-g", "V:min:5:0.1"])
    assert res.exit_code == 2
    assert (
        "goal of V: minimize: the target 5 (lower) must be below the upper limit 0.1" in res.output
    )
    # the words a design file takes, as --goal's (a DoE review: 'maximize' was refused)
    from brakeca.cli import _parse_goal

    assert _parse_goal("MU:maximize:0.2:0.3") == _parse_goal("MU:max:0.2:0.3")
    assert _parse_goal("V:minimize:0:5") == _parse_goal("V:min:0:5")


def _table_lines(text: str, title: str) -> list[str]:
    """The lines of the table titled ``title`` (title line to bottom border)."""
    lines = text.splitlines()
    start = next(k for k, line in enumerate(lines) if line.strip() == title)
    end = next(k for k in range(start, len(lines)) if lines[k].startswith("└"))
    return lines[start : end + 1]


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.replace("┃", "│").strip("│").split("│")]


FACTORS = "factors (each level: label = value, in the unit)"


def _factor_rows(text: str) -> dict[str, list[str]]:
    """The factors table's rows (a factor a line: a wide terminal), by factor name."""
    table = _table_lines(text, FACTORS)
    assert _cells(table[2])[:4] == ["factor", "sets", "unit", "levels"]
    return {cells[0]: cells for cells in map(_cells, table[4:-1])}


@pytest.mark.parametrize(
    "name", ["paper", "screen", "screen_fold", "screen_center", "response_surface"]
)
def test_the_factors_table_gives_each_levels_value_and_fits_80_columns(name) -> None:
    """The tests table gives the levels by their labels (-, 0, +): the factors table gives
    what each label stands for, the field each factor sets and its unit, before the tests."""
    from brakeca.design import load_design

    res = CliRunner().invoke(app, ["design", name], env={"COLUMNS": "80"}, terminal_width=80)
    assert res.exit_code == 0, res.output
    table = _table_lines(res.output, FACTORS)
    assert all(len(line) <= 80 for line in table), "\n".join(table)
    lines = res.output.splitlines()
    assert lines.index(table[0]) < [line.strip() for line in lines].index("tests")
    text = "\n".join(table)
    for factor in load_design(name).factors:
        assert f"│ {factor.name} " in text
        for value, label in zip(factor.levels, factor.labels or (), strict=True):
            assert f"{label} = {value:g}" in text, (factor.name, label, text)


def test_the_factors_table_names_field_scale_unit_and_coding() -> None:
    rows = _factor_rows(_design("paper"))  # 120 columns: a factor a line
    assert rows["S"] == ["S", "automaton.secondary_removal_fraction", "-", "- = 0, + = 1"]
    assert rows["WP"] == [
        "WP",
        "wear.specific_wear_rate",
        "m^3/(N m)",
        "- = 1e-15, 0 = 1e-14, + = 1e-13",
    ]
    assert rows["A"] == ["A", "pad.fibre_area_fraction × 0.01", "%", "- = 10, + = 20"]
    # an alias (screen's A, WP) names the field it stands for, with the alias's scale
    rows = _factor_rows(_design("screen"))
    assert rows["A"] == ["A", "pad.fibre_area_fraction × 0.01", "%", "- = 10, + = 20"]
    assert rows["modulus"] == ["modulus", "contact.elastic_modulus", "Pa", "- = 5e+08, + = 2e+09"]
    # a response-surface design: each factor's coding; WR's centre is the geometric mean
    rows = _factor_rows(_design("response_surface"))
    assert rows["WR"][3:] == ["- = 1e-07, 0 = 3.16228e-07, + = 1e-06", "log10"]
    assert rows["A"][3:] == ["- = 10, 0 = 15, + = 20", "linear"]
    # any design with a log-coded factor shows the coding (its centre point's, an optimized
    # setting's coded value); screen_center's WP and WR are (a helper's review: a run table
    # had shown none)
    rows = _factor_rows(_design("screen_center"))
    assert rows["WR"][-1] == "log10" and rows["S"][-1] == "linear"


def test_categorical_levels_show_their_choices(tmp_path) -> None:
    design = tmp_path / "cat.toml"
    design.write_text(
        'name = "cat"\nbase = "paper"\nroot_seed = 1\n'
        '[[factors]]\nname = "model"\nfield = "pad.fibre_model"\nlevels = [0, 1]\n'
        'choices = ["columns", "field"]\n'
        '[[factors]]\nname = "C"\nfield = "cycle"\nlevels = [1, 2]\n'
        'choices = ["paper", "example_trace"]\n'
    )
    rows = _factor_rows(_design(str(design)))
    assert rows["model"] == ["model", "pad.fibre_model", "", "columns, field"]
    assert rows["C"] == ["C", "cycle", "", "1 = paper, 2 = example_trace"]


def test_a_randomized_design_says_so_and_lists_the_run_order(tmp_path) -> None:
    from brakeca.design import load_design

    design = tmp_path / "r.toml"
    design.write_text(
        'name = "r"\nbase = "paper"\nroot_seed = 7\nrandomize_order = true\nreplicates = 2\n'
        '[[factors]]\nname = "S"\nlevels = [0, 1]\n[[factors]]\nname = "A"\nlevels = [10, 20]\n'
    )
    text = _design(str(design))
    assert (
        "run order: randomized (randomize_order = true, seeded by the root seed); each run's "
        "place in it is in the order column of the tests below and in summary.csv's order "
        "column" in text
    )
    tests = _table_lines(text, "tests")
    assert _cells(tests[2]) == ["test", "S", "A", "order"]
    orders = {int(c[0]): c[3] for c in map(_cells, tests[4:-1])}
    points = load_design(design).points()
    assert orders == {
        t: ", ".join(str(p.order) for p in points if p.test == t) for t in range(1, 5)
    }
    assert sorted(p.order for p in points) == list(range(1, 9))
    assert [p.order for p in points] != list(range(1, 9))
    # not randomized: no word of it, no order column
    text = _design("paper")
    assert "randomized" not in text and "order" not in text


def test_levels_not_given_low_first_get_a_note(tmp_path) -> None:
    descending = tmp_path / "d.toml"
    descending.write_text(
        'name = "d"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "A"\n'
        'levels = [20, 10]\n[[factors]]\nname = "S"\nlevels = [0, 1]\n'
    )
    text = " ".join(_design(str(descending), "--no-tests").split())
    assert "note: factor A's levels are not given low first (20, 10)" in text
    assert "note:" not in " ".join(_design("paper", "--no-tests").split())


def test_design_and_power_refuse_levels_that_cannot_run_together(tmp_path) -> None:
    """A level valid alone but not with a run's other levels (the lazy kernel and the fibre
    field) is refused by ``brakeca design`` and ``brakeca power`` as ``brakeca run`` refuses
    it, before anything is shown: both had printed the design as if it could run."""
    path = tmp_path / "combo.toml"
    path.write_text(
        'name = "combo"\nbase = "paper"\nroot_seed = 1\n'
        '[[factors]]\nname = "kernel"\nfield = "numerics.kernel"\nlevels = [0, 1]\n'
        'choices = ["exact", "lazy"]\n'
        '[[factors]]\nname = "fibres"\nfield = "pad.fibre_model"\nlevels = [0, 1]\n'
        'choices = ["columns", "field"]\n'
    )
    expected = "factor 'fibres' (field pad.fibre_model): level 'field' with kernel = 'lazy'"
    for args in (["design", str(path)], ["power", str(path), "--sigma", "1", "--effect", "1"]):
        res = CliRunner().invoke(app, args, env={"COLUMNS": "200"})
        assert res.exit_code == 2, res.output
        assert expected in res.output
        assert "tests" not in res.output  # nothing of the design was printed


def test_the_runs_table_codes_centre_points_0_among_labels(tmp_path) -> None:
    """Seven factors in 80 columns: the runs table gives the levels by their labels, and a
    centre point's levels (not labels of the design) had shown as cut values ('3.16…')."""
    import io

    import pandas as pd
    from rich.console import Console

    from brakeca import cli
    from brakeca.design import load_design

    design = load_design("screen_center")
    rows = []
    for test, combo in enumerate(design.combinations(), start=1):
        rows.append({"test": test, **combo, "seed": test, "MU": 0.3, "V_mm3": 1.0})
    summary = pd.DataFrame(rows)
    buffer = io.StringIO()
    console = Console(file=buffer, width=80)
    saved = cli.out
    cli.out = console
    try:
        cli._print_summary(summary, design)
    finally:
        cli.out = saved
    text = buffer.getvalue()
    assert "levels by their labels, centre points 0; summary.csv has the values" in text
    last = next(line for line in text.splitlines() if line.startswith("│   20 │"))
    assert [c.strip() for c in last.strip("│").split("│")][1:8] == ["0"] * 7
    assert "…" not in text


def test_a_levels_that_read_like_fractions_get_a_note(tmp_path) -> None:
    """A black-box review: A with levels [0.1, 0.2], meant as 10 % and 20 %, ran as 0.1 %
    and 0.2 % fibres without a word. A is in %, and `--set A=0.2` already had a note."""
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "d"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "A"\nlevels = [0.1, 20]\n'
    )
    text = " ".join(_design(str(design)).split())
    assert "note: factor 'A' sets A, the fibre fraction in %: level 0.1 is less than 1 %" in text
    assert "fibres (a level of 10 is 10 %)" in text
    assert "note:" not in " ".join(_design("paper").split())


def test_a_run_table_that_leaves_a_level_without_a_test_gets_a_note(tmp_path) -> None:
    """A black-box review: a run table with no run at WP = 1e-14, one of WP's levels, gave
    a main-effects row of n = 0 and a broken line, and brakeca design said nothing."""
    design = tmp_path / "rt.toml"
    design.write_text(
        'name = "rt"\nbase = "paper"\nroot_seed = 1\n'
        "runs = [{S = 0, WP = 1e-15}, {S = 1, WP = 1e-13}, {S = 1, WP = 1e-15}]\n"
        '[[factors]]\nname = "S"\nlevels = [0, 1]\n'
        '[[factors]]\nname = "WP"\nlevels = [1e-15, 1e-14, 1e-13]\n'
    )
    text = " ".join(_design(str(design)).split())
    assert "note: factor 'WP': level 1e-14 has no test in the run table" in text
    from brakeca.design import load_design

    assert load_design(design).levels_without_runs() == {"WP": [1e-14]}
    assert load_design("paper").levels_without_runs() == {}


def test_brakeca_design_notes_the_levels_that_read_like_slips_of_unit(tmp_path) -> None:
    """``brakeca design``, the command that checks a design before it runs, printed the
    factor's unit note only; the levels' and the base's notes were the run's (a review).
    One slip is one note, though the slope's wording follows the other factor's level."""
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "d"\nbase = "paper"\nroot_seed = 1\n'
        '[[factors]]\nname = "slope"\nfield = "friction.slope"\nlevels = [0.03, 3e-8]\n'
        '[[factors]]\nname = "mu0"\nfield = "friction.mu_0"\nlevels = [0.5, 0.6]\n'
    )
    text = " ".join(_design(str(design)).split())
    assert text.count("note: friction.slope = 0.03 1/Pa: the COF falls to its floor") == 1
    assert "friction.slope = 3e-08" not in text


def test_a_fields_slips_at_several_levels_are_one_note_and_a_paper_name_is_noted(
    tmp_path,
) -> None:
    """A new user's review: the modulus typed in MPa gave one note per level (three, with
    the centre point), and a factor named S on friction.slope went without a word, though
    --set S=... sets the paper's S."""
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "e"\nbase = "paper"\nroot_seed = 1\ncenter_points = 2\n'
        '[[factors]]\nname = "E"\nfield = "contact.elastic_modulus"\nlevels = [500, 2000]\n'
        '[[factors]]\nname = "S"\nfield = "friction.slope"\nlevels = [2e-8, 4e-8]\n'
    )
    text = " ".join(_design(str(design)).split())
    assert text.count("note: contact.elastic_modulus = ") == 1
    assert "(and so at contact.elastic_modulus = 2000, 1250)" in text
    assert (
        "note: factor 'S' sets friction.slope; S is also the paper's name for "
        "automaton.secondary_removal_fraction, which --set S=... sets"
    ) in text


def test_a_level_refused_on_a_base_changed_by_set_names_the_set(tmp_path) -> None:
    """A level valid on the preset but not with a --set: the message names the --set (a
    review: it named the design, and another factor's level, never the option)."""
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "t"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "mu0"\n'
        'field = "friction.mu_0"\nlevels = [0.5, 0.6]\n'
    )
    out = tmp_path / "c"
    args = ["run", str(design), "-o", str(out), "--quick", "--set", "friction.mu_min=0.55"]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 2
    text = " ".join(res.output.split())
    assert "mu_min (0.55) must not exceed mu_0 (0.5)" in text
    assert "(the runs' base configuration has --set friction.mu_min=0.55)" in text
    assert not out.exists()


def test_a_run_table_of_aliased_main_effects_is_warned_of_and_power_says_so(tmp_path) -> None:
    """A new user's review: a run table in which mu0 follows A (resolution II) was listed as
    'A + mu0' without a word, its constant A:mu0 column called 'aliased with a combination
    of the terms before it', and `brakeca power` called mu0 'not varied'."""
    design = tmp_path / "alias.toml"
    design.write_text(
        'name = "alias"\nbase = "paper"\nroot_seed = 1\n'
        "runs = [{A = 10, mu0 = 0.5}, {A = 20, mu0 = 0.7}, {A = 10, mu0 = 0.5}, "
        "{A = 20, mu0 = 0.7}]\n"
        '[[factors]]\nname = "A"\nlevels = [10, 20]\n'
        '[[factors]]\nname = "mu0"\nfield = "friction.mu_0"\nlevels = [0.5, 0.7]\n'
    )
    text = " ".join(_design(str(design)).split())
    assert (
        "warning: the tests cannot tell main effect mu0 from A (resolution II): in these tests "
        "the level of one fixes the other's, so an effect estimated for either is that of "
        "both together"
    ) in text
    assert "not estimable (the same in every test: aliased with the mean): A:mu0" in text
    assert "combination of the terms before it" not in text

    def power_text(replicates: str = "1") -> str:
        res = CliRunner().invoke(
            app,
            ["power", str(design), "--effect", "0.1", "--sigma", "0.05", "--replicates",
             replicates],
            env={"COLUMNS": "120"},
        )  # fmt: skip
        assert res.exit_code == 0, res.output
        return " ".join(res.output.split())

    power = power_text()
    assert "aliased with A" in power and "not varied" not in power
    assert "A's figure is that of A and mu0 together" in power
    # said once, whatever the replicate counts asked (a reread: once per row before)
    assert power_text("1,2").count("A's figure is that of A and mu0 together") == 1
    # with mu0 alone in the model, its figure is the pair's (a diff review: A, not in the
    # model, was said to carry it)
    design.write_text(design.read_text().replace("runs = ", 'model_terms = ["mu0"]\nruns = '))
    power = power_text()
    assert "not in the model" in power and "aliased with" not in power
    assert "mu0's figure is that of mu0 and A together" in power
    assert "A's figure" not in power
    design.write_text(design.read_text().replace('model_terms = ["mu0"]\n', ""))
    # a factor aliased with two: both named (a DoE review: the last pair alone was)
    three = tmp_path / "three.toml"
    three.write_text(
        'name = "three"\nbase = "paper"\nroot_seed = 1\n'
        "runs = [{A = 10, mu0 = 0.5, S = 0}, {A = 20, mu0 = 0.7, S = 1}, "
        "{A = 10, mu0 = 0.5, S = 0}, {A = 20, mu0 = 0.7, S = 1}]\n"
        '[[factors]]\nname = "A"\nlevels = [10, 20]\n'
        '[[factors]]\nname = "mu0"\nfield = "friction.mu_0"\nlevels = [0.5, 0.7]\n'
        '[[factors]]\nname = "S"\nlevels = [0, 1]\n'
    )
    res = CliRunner().invoke(
        app,
        ["power", str(three), "--effect", "0.1", "--sigma", "0.05"],
        env={"COLUMNS": "120"},
    )
    assert res.exit_code == 0, res.output
    assert "A's figure is that of A, mu0 and S together" in " ".join(res.output.split())
    # a full factorial of the same factors: no warning, no aliased row
    design.write_text(
        design.read_text().replace(
            "{A = 10, mu0 = 0.5}, {A = 20, mu0 = 0.7}]", "{A = 10, mu0 = 0.7}, {A = 20, mu0 = 0.5}]"
        )
    )
    text = " ".join(_design(str(design)).split())
    assert "warning" not in text and "aliased with the mean" not in text


def test_a_file_of_another_kind_is_named_as_such_in_one_line(tmp_path) -> None:
    """A command-line review: a configuration given as a design read fifteen "unknown key"
    lines, a design given as a configuration nine, and a netCDF file "'utf-8' codec can't
    decode byte 0x89"; each is now one line that says what the file is and where it goes."""
    config = tmp_path / "my.toml"
    config.write_text(CliRunner().invoke(app, ["config"]).output, encoding="utf-8")
    design = tmp_path / "d.toml"
    design.write_text(
        'name = "d"\nbase = "paper"\nroot_seed = 1\n[[factors]]\nname = "S"\n'
        'field = "automaton.secondary_removal_fraction"\nlevels = [0.0, 1.0]\n',
        encoding="utf-8",
    )
    netcdf = tmp_path / "run.nc"
    netcdf.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(64))
    for args, says in (
        (["run", str(config), "-o", str(tmp_path / "c")], "a simulation configuration, not a"),
        (["design", str(config)], f"run it with 'brakeca simulate -c {config} -o RUN.nc'"),
        (["simulate", "-c", str(design), "-o", str(tmp_path / "r.nc")], "a design (it has"),
        (["config", "-c", str(design)], f"'brakeca run {design} -o FOLDER'"),
        (["design", str(netcdf)], "a netCDF file (a run file or a campaign.nc), not a design"),
    ):
        res = CliRunner().invoke(app, args)
        text = " ".join(res.output.split())
        assert res.exit_code == 2 and says in text, text
        assert text.count("error:") == 1 and "unknown key" not in text, text
    assert not (tmp_path / "c").exists() and not (tmp_path / "r.nc").exists()


def test_output_read_by_a_reader_that_goes_is_not_a_failure() -> None:
    """A command-line review: 'brakeca design paper | head -1' exited 1 (rich's broken pipe),
    which a shell with pipefail reads as the command failing; it ends as it would have."""
    import subprocess
    import sys

    proc = subprocess.Popen(
        [sys.executable, "-m", "brakeca.cli", "design", "paper"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()  # gone before the first line is written (the table fits a pipe's
    # buffer, so a reader that took one line first might not be gone yet)
    status = proc.wait(timeout=120)
    with proc.stderr:
        said = proc.stderr.read()
    assert status == 0 and said == b"", said


def test_an_empty_replicates_list_is_refused() -> None:
    """A fuzz review: 'power --replicates ""' meant the default without a word, while an
    empty --maps-at or --levels is refused."""
    res = CliRunner().invoke(
        app, ["power", "paper", "--effect", "0.01", "--sigma", "0.005", "--replicates", ""]
    )
    assert res.exit_code == 2 and "--replicates: expected whole numbers" in res.output


def test_output_to_a_file_in_a_legacy_encoding_replaces_what_it_cannot_write() -> None:
    """On Windows, output sent to a file or a pipe is written in the ANSI code page (cp1252),
    which has no α: the command ended with a UnicodeEncodeError (a portability review); it
    now writes ``?`` for it and goes on."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "PYTHONIOENCODING": "cp1252"}
    done = subprocess.run(
        [sys.executable, "-m", "brakeca", "design", "response_surface", "--no-tests"],
        capture_output=True,
        env=env,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr.decode("cp1252", "replace")
    text = done.stdout.decode("cp1252")
    assert "central composite design (face-centred, ? = 1), 3 factors" in text
