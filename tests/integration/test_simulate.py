"""Whole runs: determinism, netCDF round trip, responses, clear failures, the CLI."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from typer.testing import CliRunner

from brakeca.cli import app
from brakeca.config import SimulationConfig
from brakeca.contact import ContactError
from brakeca.presets import load_preset
from brakeca.results import RunResult
from brakeca.simulation import simulate


@pytest.fixture(scope="module")
def small():
    """3 rows x 1000 columns, high wear so that secondary plateaus form, 3 short stops."""
    from conftest import short_cycle

    return load_preset().with_updates(
        {
            "mesh.n_radial": 5,
            "WP": 1e-13,
            "pad.resin_roughness": 100e-6,
            "cycle": short_cycle(stops=3, v0=30, v1=4, g=0.25),
        }
    )


@pytest.fixture(scope="module")
def run(small):
    return simulate(small, seed=11)


def _without_wall_time(ds):
    ds = ds.copy()
    ds.attrs.pop("wall_time")
    ds.attrs.pop("date_created")  # (when the run was made)
    return ds


def test_same_seed_bit_identical(small, run):
    again = simulate(small, seed=11)
    xr.testing.assert_identical(_without_wall_time(run.dataset), _without_wall_time(again.dataset))


def test_different_seed_different_surface(small, run):
    other = simulate(small, seed=12)
    assert not np.array_equal(run.dataset.initial_status, other.dataset.initial_status)


def test_netcdf_round_trip(tmp_path, run):
    path = run.to_netcdf(tmp_path / "run.nc")
    back = RunResult.from_netcdf(path)
    assert back.config == run.config and back.seed == 11
    xr.testing.assert_identical(back.dataset, run.dataset)
    assert not list(tmp_path.glob(".*tmp"))  # no temporary left behind


def test_foreign_file_rejected(tmp_path):
    p = tmp_path / "x.nc"
    xr.Dataset({"a": ("x", [1, 2])}).to_netcdf(p, engine="h5netcdf")
    with pytest.raises(ValueError, match="not a brakeca run"):
        RunResult.from_netcdf(p)
    p.write_bytes(b"garbage")
    with pytest.raises(ValueError, match="not a readable"):
        RunResult.from_netcdf(p)


def _damaged(ds: xr.Dataset, how: str) -> xr.Dataset:
    """``ds`` damaged as a file from elsewhere could be."""
    ds = ds.copy(deep=True)
    if how == "MU NaN":
        ds["MU"] = ds["MU"] * np.nan
    elif how == "V -inf":
        ds["V"] = ds["V"] * 0 - np.inf
    elif how == "status 7":
        ds["final_status"][0, 0] = 7
    elif how == "status float":
        ds["final_status"] = ds["final_status"].astype(float)
    elif how == "per-stop on the grid":
        ds["mean_cof"] = ds["final_height"].astype(float)
    elif how == "text COF":
        ds["mean_cof"] = ds["mean_cof"].astype(str)
    elif how == "another grid":
        ds = ds.isel(radius=slice(0, 2))
    elif how == "no stop":
        ds = ds.isel(stop=slice(0, 0))
    elif how == "no final map":
        ds = ds.drop_vars("final_status")
    elif how == "no generated volume":  # (a resume read it, and ended with a KeyError)
        ds = ds.drop_vars("generated_volume")
    elif how == "no wall time":
        del ds.attrs["wall_time"]
    return ds


DAMAGES = {
    "MU NaN": "'MU' is not finite",
    "V -inf": "'V' is not finite",
    "status 7": "'final_status' holds statuses other than 0, 1 and 2",
    "status float": "'final_status' is of type float64, not whole numbers",
    "no generated volume": "it lacks 'generated_volume'",
    "no wall time": "its wall_time attribute is not a number",
    "per-stop on the grid": "'mean_cof' is on (radius, angle), not (stop)",
    "text COF": "'mean_cof' is of type",
    "another grid": "its maps are 2 x 1000 cells, its configuration's grid 5 x 1000",
    "no stop": "it has no stop",
    "no final map": "it lacks 'final_status'",
}


@pytest.mark.parametrize("how", list(DAMAGES))
def test_a_damaged_run_file_is_refused_with_what_is_wrong(tmp_path, run, how):
    """A security review: a run file of other shapes, types or statuses had ended ``plot``,
    ``analyze`` and a resume with a traceback, and one of MU = NaN was reused into a
    summary; each is refused naming the file and what is wrong, and ``plot`` says so."""
    path = tmp_path / "r.nc"
    _damaged(run.dataset, how).to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ValueError) as info:
        RunResult.from_netcdf(path)
    assert str(info.value).startswith(f"{path}: not a run file brakeca wrote (")
    assert DAMAGES[how] in str(info.value)
    res = CliRunner().invoke(app, ["plot", str(path)])
    assert res.exit_code == 2 and DAMAGES[how] in " ".join(res.output.split()), res.output
    assert not (tmp_path / "r_figures").exists()


def test_responses_are_plausible(run):
    ds = run.dataset
    assert set(ds.sizes) >= {"stop", "step", "radius", "angle"}
    assert np.all((ds.mean_cof >= 0.15 - 1e-12) & (ds.mean_cof <= 0.6))
    assert float(ds.max_ledger_residual) < 1e-11
    assert float(ds.max_friction_residual) < 1e-10
    # each stop's own maxima are kept (they had been overwritten by the run's: an API
    # review), and the run's friction residual is the largest of them
    assert ds["stop_max_ledger_residual"].dims == ds["stop_max_friction_residual"].dims == ("stop",)
    assert float(ds.stop_max_friction_residual.max()) == float(ds.max_friction_residual)
    assert float(ds.stop_max_ledger_residual.max()) <= float(ds.max_ledger_residual)
    assert np.all(ds.emitted_volume > 0) and np.all(ds.generated_volume > 0)
    assert run.MU == pytest.approx(float(ds.mean_cof.mean()))
    assert run.V == pytest.approx(float(ds.emitted_volume.mean()))
    assert np.all(ds.line_pressure > 0)
    # everything generated left or is still held: emitted <= generated over the run
    assert float(ds.emitted_volume.sum()) <= float(ds.generated_volume.sum()) * (1 + 1e-12)
    for name in ("mean_cof", "emitted_volume", "normal_force", "step_cof"):
        assert np.all(np.isfinite(ds[name]))


def test_thinned_series_are_every_nth_step_across_stops(small):
    """The per-step series kept every ``output.series_every`` steps are the whole run's steps
    0, n, 2n, ... whatever the stops' lengths (picked stop by stop)."""
    every = 7
    full = small.with_updates({"output.series_every": 1})
    ds1 = simulate(full, seed=11).dataset
    ds7 = simulate(small.with_updates({"output.series_every": every}), seed=11).dataset
    assert ds1.sizes["step"] > 3 * every
    assert ds1.n_steps.values.sum() == ds1.sizes["step"]
    assert set(np.unique(ds1.n_steps.values % every)) != {0}  # stops not multiples of 7
    series = [name for name in ds1.data_vars if name.startswith("step_")]
    assert "step_cof" in series and "step_disc_position" in series
    for name in series:
        np.testing.assert_array_equal(ds7[name].values, ds1[name].values[::every], err_msg=name)


def test_unreachable_torque_is_a_clear_error(small):
    from brakeca.config import ConfigError, UnitWarning

    # a pad without fibres, which no step could run, is refused before any work (an API
    # review: it had passed the check and failed at stop 1, step 1)
    with pytest.raises(ConfigError, match=r"must be above 0 .* \(a pad without fibres has no"):
        small.with_updates({"A": 0})
    with pytest.raises(ConfigError, match=r"pad.fibre_area_fraction: must lie in \(0, 1\)"):
        small.with_updates({"pad.fibre_area_fraction": 0.0})
    # the kernels' own check, for a surface without plateaus all the same (a copy of the
    # configuration that skips validation: pydantic's own model_copy, which brakeca's
    # models replace with one that validates)
    from pydantic import BaseModel

    pad = BaseModel.model_copy(small.pad, update={"fibre_area_fraction": 0})
    bare = BaseModel.model_copy(small, update={"pad": pad})
    with pytest.raises(ContactError, match="no plateau cell can reach"):
        simulate(bare, seed=1)

    with pytest.warns(UnitWarning, match="contact.elastic_modulus = 10000 Pa, a foundation"):
        soft = small.with_updates({"contact.bar_length": 1e-3, "contact.elastic_modulus": 1e4})
    with pytest.raises(ContactError, match="bar_length") as info:
        simulate(soft, seed=1)
    # and names what sets the demand (a review: a wheel load typed 1000 times too large was
    # blamed on the bar's length alone)
    assert "vehicle.wheel_load_mass = " in str(info.value)


def test_a_torque_the_solve_cannot_resolve_fails_the_run(small):
    """A robustness review: a foundation of 1e30 Pa (or a bar of 1e300 m) ran to the end,
    MU 0 (or NaN) and a friction residual of 1, recorded as ok. Such a run now fails at its
    first stop, naming the contact fields; the paper's stiffness meets the torque to
    round-off. Those two are refused by the fields' ranges now (a physics review: a
    stiffness that rounded to 0 ended in a ZeroDivisionError); the stiffest foundation they
    allow still fails the run, naming them."""
    from brakeca.config import ConfigError

    stiffest = {"contact.elastic_modulus": 1e13, "contact.bar_length": 1e-9}
    with pytest.raises(
        ContactError,
        match=r"stop 1 \(test\): the friction force missed the demanded one by .* "
        r"\(contact.elastic_modulus = 1e\+13 Pa, contact.bar_length = 1e-09 m",
    ):
        simulate(small.with_updates(stiffest), seed=1)
    for updates in ({"contact.elastic_modulus": 1e30}, {"contact.bar_length": 1e300}):
        with pytest.raises(ConfigError, match=r"must lie in \["):
            small.with_updates(updates)
    assert simulate(small, seed=1).dataset["max_friction_residual"] < 1e-10
    # a stop shorter than one step's travel had crashed on an empty array, naming no field

    # (a gravity of 1e300 m/s², which had reached it, is refused by its range now)
    blink = {"name": "test", "initial_speed_kmh": 50.0, "final_speed_kmh": 50.0 - 1e-12}
    blink |= {"deceleration_g": 0.25, "stops": 1}  # a stop of 1.6e-12 m
    with pytest.raises(ConfigError, match=r"under 1e-9 of one time step's travel .* no time"):
        simulate(small.with_updates({"cycle.blocks": [blink]}), seed=1)
    # (a wheel radius of 1e300 m is refused by its range now, at most 2 m)
    with pytest.raises(ConfigError, match=r"vehicle.wheel_radius: must lie in \(0, 2\]"):
        small.with_updates({"vehicle.wheel_radius": 1e300})


def test_seeds_are_checked_before_any_work_and_the_largest_round_trips(small, tmp_path):
    """A seed above 2**64 - 1 ran the whole run and then failed writing its file (h5py has no
    type for it); a float seed was truncated without a word."""
    from brakeca.simulation import MAX_SEED

    for bad in (-1, 1.5, "3", True, MAX_SEED + 1):
        with pytest.raises(ValueError, match=r"seed must be a whole number from 0 to 2\*\*64 - 1"):
            simulate(small, seed=bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="give seed or rng, not both"):
        simulate(small, seed=1, rng=np.random.default_rng(1))
    with pytest.raises(ValueError, match="give seed or rng, not both"):
        simulate(small, seed=1, rng=3)
    with pytest.raises(ValueError, match=r"^rng: a seed is a whole number from 0 to 2\*\*64"):
        simulate(small, rng=-1)
    # a generator passed as the seed, or another kind of generator, is named (an API review:
    # a ValueError about whole numbers, and an AttributeError 'bit_generator')
    with pytest.raises(TypeError, match="seed: got a numpy Generator; pass it as rng="):
        simulate(small, seed=np.random.default_rng(1))  # type: ignore[arg-type]
    for other in (np.random.RandomState(3), "3", 1.5):
        with pytest.raises(TypeError, match=r"rng must be a numpy\.random\.Generator"):
            simulate(small, rng=other)  # type: ignore[arg-type]
    one_stop = small.with_updates({"cycle.max_stops": 1})
    path = simulate(one_stop, seed=MAX_SEED).to_netcdf(tmp_path / "max.nc")
    assert RunResult.from_netcdf(path).seed == MAX_SEED
    assert simulate(one_stop, seed=np.uint64(7)).seed == 7
    # rng=<whole number> is that seed (SPEC 7), recorded as the run's seed
    by_rng = simulate(one_stop, rng=7)
    assert by_rng.seed == 7 and by_rng.MU == simulate(one_stop, seed=7).MU
    res = CliRunner().invoke(app, ["simulate", "-o", str(tmp_path / "x.nc"), "--seed", str(2**64)])
    assert res.exit_code == 2 and "--seed" in res.output


def test_a_run_given_a_generator_records_its_state_and_rebuilds_it(small, tmp_path):
    """simulate(rng=) records seed -1, and the generator's state before the first draw in the
    run file (it had recorded -1 alone: such a run could not be repeated); the generator
    rebuilt from the file repeats the run to the bit. A seeded run's generator is its seed's."""
    config = small.with_updates({"cycle.max_stops": 2, "S": 0.5})  # rule S draws
    rng = np.random.default_rng(11)
    rng.random(3)  # a generator already used: its state, not a seed, is what repeats the run
    run = simulate(config, rng=rng)
    assert run.seed == -1 and "rng_state" in run.dataset.attrs
    back = RunResult.from_netcdf(run.to_netcdf(tmp_path / "rng.nc"))
    again = simulate(config, rng=back.generator())
    timing = ["wall_time"]
    xr.testing.assert_identical(
        again.dataset.drop_vars(timing, errors="ignore").assign_attrs(
            wall_time=0.0, date_created=""
        ),
        run.dataset.drop_vars(timing, errors="ignore").assign_attrs(wall_time=0.0, date_created=""),
    )
    seeded = simulate(config.with_updates({"cycle.max_stops": 1}), seed=5)
    assert seeded.generator().random() == np.random.default_rng(5).random()
    old = RunResult(config=run.config, seed=-1, dataset=run.dataset.copy())
    del old.dataset.attrs["rng_state"]
    with pytest.raises(ValueError, match="earlier brakeca"):
        old.generator()
    # a name from a file calls nothing but a bit generator (np.random.seed had been called:
    # a security review)
    import json

    state = json.loads(run.dataset.attrs["rng_state"])
    for name in ("seed", "__dir__"):
        old.dataset.attrs["rng_state"] = json.dumps({**state, "bit_generator": name})
        with pytest.raises(ValueError, match=f"generator state of '{name}', not one of"):
            old.generator()
    with pytest.raises(ValueError, match="checkpoint: a checkpointed run needs a seed"):
        simulate(config, rng=np.random.default_rng(1), checkpoint=tmp_path / "c.npz")


def test_cli_simulate(tmp_path):
    runner = CliRunner()
    out = tmp_path / "r.nc"
    res = runner.invoke(
        app,
        [
            "simulate",
            "--set",
            "mesh.n_radial=3",
            "--set",
            "mesh.n_angular=100",
            "--stops",
            "1",
            "--seed",
            "4",
            "-o",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    assert "MU =" in res.stdout and "mm³ per stop" in res.stdout
    r = RunResult.from_netcdf(out)
    assert r.seed == 4 and r.config.cycle.max_stops == 1 and r.dataset.sizes["stop"] == 1
    # the header announces the run's time steps before any work
    assert f"1 stop ({int(r.dataset.n_steps.sum()):,} time steps), seed 4" in res.output
    # no note but the one a band of 3 x 100 cells earns: its fibres cover 32 % at A = 20 %
    notes = [ln for ln in res.output.splitlines() if ln.startswith("note:")]
    assert [n[:32] for n in notes] == ["note: the fibres cover 32 % of t"]
    short = ["simulate", "--set", "mesh.n_radial=2", "--set", "mesh.n_angular=50"]
    one_stop_cycle = tmp_path / "one.csv"
    one_stop_cycle.write_text(
        "name,initial_speed_kmh,final_speed_kmh,deceleration_g,stops\nB,20,4,0.3,1\n"
    )
    res = runner.invoke(
        app, [*short, "--cycle", str(one_stop_cycle), "--stops", "5", "-o", str(tmp_path / "f.nc")]
    )
    assert res.exit_code == 0, res.output
    assert "note: --stops 5: the cycle has 1 stop; all of them run, once" in res.output
    res = runner.invoke(app, ["simulate", "--set", "A=150", "-o", str(tmp_path / "bad.nc")])
    assert res.exit_code == 2 and "above 0 and below 100 %" in res.output
    assert not (tmp_path / "bad.nc").exists()
    # an output that cannot be written (its folder is a file) is refused before the run
    blocker = tmp_path / "blocker"
    blocker.write_text("")
    tiny = ["simulate", "--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100"]
    res = runner.invoke(app, [*tiny, "--stops", "1", "--seed", "4", "-o", str(blocker / "r.nc")])
    assert res.exit_code == 2 and "cells, cycle" not in res.output, res.output
    # one that fails when written after the run (a full disk, say): the run is kept
    real_write = RunResult.to_netcdf

    def full_disk(self, path):
        if Path(path).parent == tmp_path:
            raise OSError(28, "No space left on device")
        return real_write(self, path)

    RunResult.to_netcdf = full_disk
    try:
        res = runner.invoke(
            app, [*tiny, "--stops", "1", "--seed", "4", "-o", str(tmp_path / "f2.nc")]
        )
    finally:
        RunResult.to_netcdf = real_write
    assert res.exit_code == 1, res.output
    kept = Path(res.output.split("the run was saved to ")[1].split()[0])
    assert RunResult.from_netcdf(kept).MU == r.MU
    kept.unlink()
    kept.parent.rmdir()
    # an output that is a folder is refused before the run, not when its file is written
    res = runner.invoke(app, ["simulate", "--stops", "1", "-o", str(tmp_path)])
    assert res.exit_code == 2 and "is a folder" in res.output and "cells, cycle" not in res.output
    res = runner.invoke(app, ["simulate", "-o", str(out), "--seed", "-1"])
    assert res.exit_code == 2 and "--seed" in res.output
    # a model error (no fibre to carry the torque): exit 1, the error the last line, no file
    small = ["--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100", "--stops", "1"]
    soft = ["--set", "contact.bar_length=1e-3", "--set", "contact.elastic_modulus=1e4"]
    res = runner.invoke(app, ["simulate", *small, *soft, "-o", str(tmp_path / "b.nc")])
    assert res.exit_code == 1, res.output
    last = res.output.strip().splitlines()[-1]
    assert last.startswith("error: stop 1 (Burnish), step 1: reaching the demanded friction")
    assert not (tmp_path / "b.nc").exists()


def test_cli_simulate_trace_cycle_and_changed_trace(tmp_path):
    from brakeca.config import ConfigError
    from brakeca.traces import configured_cycle, with_cycle

    runner = CliRunner()
    out = tmp_path / "t.nc"
    traced = ["simulate", "--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100"]
    traced += ["--cycle", "example_trace"]
    res = runner.invoke(app, [*traced, "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "mg/km" in res.stdout and "Euro 7" in res.stdout and "pass" not in res.stdout.lower()
    # the battery-electric limit beside a run braked by friction alone is explained (a review)
    assert "here the friction brakes do all the braking" in " ".join(res.stdout.split())
    run = RunResult.from_netcdf(out)
    assert run.config.cycle.trace_file == "example_trace" and run.dataset.sizes["stop"] == 5
    assert f"5 stops ({int(run.dataset.n_steps.sum()):,} time steps)" in res.output
    # the user's emission factors: printed and recorded (a review: only Python took them)
    factors = tmp_path / "emissions.toml"
    factors.write_text("airborne_fraction = 0.4\n")
    mine = tmp_path / "mine.nc"
    res = runner.invoke(app, [*traced, "--emissions", str(factors), "-o", str(mine)])
    assert res.exit_code == 0, res.output
    assert "airborne share 0.4 (0.3 to 0.6)" in " ".join(res.stdout.split())
    regenerating = runner.invoke(
        app, [*traced, "--set", "cycle.trace.friction_share=0.5", "-o", str(tmp_path / "r.nc")]
    )
    assert regenerating.exit_code == 0, regenerating.output
    assert "friction brakes do all the braking" not in regenerating.stdout
    attrs = RunResult.from_netcdf(mine).dataset.attrs
    assert attrs["pm10_mg_km"] == pytest.approx(0.8 * run.dataset.attrs["pm10_mg_km"], rel=1e-12)
    assert "airborne share 0.4" in attrs["pm10_factors"]
    assert "of the factors in pm10_factors" in attrs["comment"]
    tiny = ["--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100", "--stops", "1"]
    block = runner.invoke(
        app, ["simulate", *tiny, "--emissions", str(factors), "-o", str(tmp_path / "block.nc")]
    )
    assert block.exit_code == 0, block.output
    assert "PM10 in mg/km is given on a speed trace only" in " ".join(block.output.split())
    # a trace file that changes after the configuration was made is refused
    trace = tmp_path / "trace.csv"
    trace.write_text("time_s,speed_kmh\n0,0\n10,50\n20,50\n27,0\n30,0\n")
    config = with_cycle(load_preset(), trace)
    assert len(configured_cycle(config).events) == 1
    assert configured_cycle(config) is configured_cycle(config)  # detected once, then kept
    trace.write_text("time_s,speed_kmh\n0,0\n10,50\n20,50\n25,0\n30,0\n")
    with pytest.raises(ConfigError, match="content changed"):
        configured_cycle(config)


def test_cli_surface_draws_the_levels_and_names_bad_ones(tmp_path):
    runner = CliRunner()
    png = tmp_path / "maps.png"
    res = runner.invoke(app, ["surface", "-o", str(png), "--quick", "--levels", "10, 20"])
    assert res.exit_code == 0, res.output
    assert png.read_bytes().startswith(b"\x89PNG") and f"wrote {png}" in res.output
    assert "note:" not in res.output
    # a level that reads like a fraction gets the note --set A=0.2 gets (a black-box review)
    res = runner.invoke(app, ["surface", "-o", str(png), "--quick", "--levels", "0.2,20"])
    assert res.exit_code == 0
    assert "note: --levels are in %: 0.2 is less than 1 % fibres (10 is 10 %)" in res.output
    for levels, message in [
        ("abc", "--levels 'abc': 'abc' is not a number"),
        ("", "--levels '': no level"),
        ("10,10", "--levels '10,10': 10 % is given twice"),
        ("inf", "'inf' is not a finite number"),
        ("150", "--levels 150: must be above 0 and below 100 %"),
        ("10,,20", "--levels '10,,20': an empty level between commas"),  # (a fuzz review)
    ]:
        bad = tmp_path / "bad.png"
        res = runner.invoke(app, ["surface", "-o", str(bad), "--quick", "--levels", levels])
        assert res.exit_code == 2 and message in res.output, (levels, res.output)
        assert "Traceback" not in res.output and not bad.exists()


def test_cli_plot_draws_a_run_files_figures(tmp_path, run):
    path = run.to_netcdf(tmp_path / "r.nc")
    res = CliRunner().invoke(app, ["plot", str(path)])
    assert res.exit_code == 0, res.output
    folder = tmp_path / "r_figures"
    for name in ("mu_per_stop.png", "steps.png", "maps.png"):
        assert (folder / name).read_bytes().startswith(b"\x89PNG")
        assert f"wrote {folder / name}" in res.output.replace("\n", "")
    res = CliRunner().invoke(app, ["plot", str(path), "-o", str(tmp_path / "elsewhere")])
    assert res.exit_code == 0 and (tmp_path / "elsewhere" / "maps.png").is_file()
    not_a_run = tmp_path / "x.nc"
    not_a_run.write_text("no")
    res = CliRunner().invoke(app, ["plot", str(not_a_run)])
    assert res.exit_code == 2 and "not a readable netCDF file" in res.output
    res = CliRunner().invoke(app, ["plot", str(tmp_path / "missing.nc")])
    assert res.exit_code == 2 and "does not exist" in res.output


@pytest.mark.parametrize("kernel", ["exact", "lazy"])
def test_a_ledger_beyond_its_tolerance_stops_the_run(small, kernel):
    """The ledger is checked every step (spec section 11): with a tolerance below round-off
    (1e-300), the first step whose residual is not exactly zero stops the run with a
    LedgerError naming the stop, the step, the residual and the field; at the default the
    same run closes. (No test reached this path before: a third review.)"""
    from brakeca.simulation import LedgerError

    config = small.with_updates({"numerics.kernel": kernel, "cycle.max_stops": 2})
    strict = config.with_updates({"output.ledger_tolerance": 1e-300})
    with pytest.raises(LedgerError) as info:
        simulate(strict, seed=1)
    message = str(info.value)
    assert message.startswith("stop 1 (test), step ")
    assert "the volume ledger residual" in message
    assert "exceeds output.ledger_tolerance = 1e-300" in message
    assert float(simulate(config, seed=1).dataset["max_ledger_residual"]) < 1e-12


@pytest.mark.parametrize("kernel", ["exact", "lazy"])
def test_a_demand_above_a_floorless_laws_maximum_names_the_law(small, kernel):
    """friction.mu_min = 0: the friction force has a maximum, here below the demand. Both
    kernels had said "no plateau cell can reach the disc", or that the foundation would be
    compressed beyond its length (a root far away, from round-off), though plateaus touch."""
    config = small.with_updates(
        {"friction.mu_min": 0.0, "A": 20, "numerics.kernel": kernel, "cycle.max_stops": 1}
    )
    with pytest.raises(ContactError) as err:
        simulate(config, seed=1)
    message = str(err.value)
    assert "friction.mu_min = 0" in message and "no disc position carries it" in message
    assert "no plateau cell" not in message and "bar_length" not in message
    # the bound it names is above the demand only with the words that say why that is no
    # contradiction (a physics review read "2.008 N is above it ... give at most 2.733 N")
    import re

    demand = float(re.search(r"demanded friction force ([0-9.e+-]+) N", message)[1])
    bound = float(re.search(r"give (?:at most )?([0-9.e+-]+) N", message)[1])
    assert (bound < demand) == ("give at most" in message), message
    assert (bound >= demand) == ("but their heights differ" in message), message


def test_cli_simulate_keeps_maps_after_the_stops_asked_and_plot_draws_them(tmp_path):
    """--maps-at keeps the status and height maps after chosen stops in the run file (the
    last one equal to the final map); 'brakeca plot' then draws them one under the other.
    Stops the cycle does not have, or text, are refused before any work."""
    from campaign_helpers import TINY_CLI

    tiny = TINY_CLI[: TINY_CLI.index("--executor")]  # simulate has no executor
    runner = CliRunner()
    path = tmp_path / "r.nc"
    res = runner.invoke(app, ["simulate", "-o", str(path), *tiny, "--maps-at", "2,1"])
    assert res.exit_code == 0, res.output
    ds = RunResult.from_netcdf(path).dataset
    assert list(ds["map_stop"].values) == [1, 2] and ds["map_status"].shape == (2, 5, 100)
    np.testing.assert_array_equal(ds["map_status"].sel(map_stop=2), ds["final_status"])
    res = runner.invoke(app, ["plot", str(path)])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r_figures" / "maps_by_stop.png").read_bytes().startswith(b"\x89PNG")
    for maps, message in (
        # (with --stops 2 of the cycle's 170, which it now says)
        (
            "3",
            "--maps-at: stop 3 is not a stop of this cycle (whole numbers from 1 to 2) "
            "(cycle.max_stops = 2, --stops, runs only the first 2 of the cycle's 170 stops)",
        ),
        ("1,1", "--maps-at: a stop is given twice"),
        ("1;2", "--maps-at '1;2': expected stop numbers separated by commas"),
    ):
        other = tmp_path / "other.nc"
        res = runner.invoke(app, ["simulate", "-o", str(other), *tiny, "--maps-at", maps])
        assert res.exit_code == 2 and message in " ".join(res.output.split()), (maps, res.output)
        assert not other.exists()


def test_a_run_file_given_as_config_runs_again_as_it_ran(tmp_path):
    """A provenance review: -c RUN.nc failed ("a TOML file is UTF-8 text") and no way to
    run a run file again was documented. Its configuration, seed and maps are taken (a
    --seed given wins), and the run is the same, bit for bit, but for when it was made."""
    from campaign_helpers import TINY_CLI

    tiny = TINY_CLI[: TINY_CLI.index("--executor")]
    runner = CliRunner()
    first = tmp_path / "first.nc"
    res = runner.invoke(
        app, ["simulate", "-o", str(first), *tiny, "--set", "A=10", "--seed", "7", "--maps-at", "1"]
    )
    assert res.exit_code == 0, res.output
    again = tmp_path / "again.nc"
    res = runner.invoke(app, ["simulate", "-c", str(first), "-o", str(again)])
    assert res.exit_code == 0, res.output
    assert "seed 7" in res.output
    a, b = RunResult.from_netcdf(first), RunResult.from_netcdf(again)
    xr.testing.assert_identical(_without_wall_time(a.dataset), _without_wall_time(b.dataset))
    other = tmp_path / "other.nc"
    res = runner.invoke(app, ["simulate", "-c", str(first), "-o", str(other), "--seed", "8"])
    assert res.exit_code == 0, res.output
    assert RunResult.from_netcdf(other).seed == 8
    # the configuration alone, as a TOML file, with a note of what it cannot hold
    res = runner.invoke(app, ["config", "-c", str(first)])
    assert res.exit_code == 0, res.output
    assert SimulationConfig.from_toml(res.stdout) == a.config
    assert "as does this configuration with --seed 7 --maps-at 1" in " ".join(res.stderr.split())
    # --stops shorter than the maps it kept: they are dropped with a note (a diff review: it
    # failed on a --maps-at the user never gave)
    short = tmp_path / "short.nc"
    two = tmp_path / "two.nc"
    res = runner.invoke(app, ["simulate", "-c", str(first), "-o", str(two), "--maps-at", "1,2"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["simulate", "-c", str(two), "-o", str(short), "--stops", "1"])
    assert res.exit_code == 0, res.output
    assert "kept maps after stops 1, 2; this run has 1, so it keeps those after 1" in " ".join(
        res.output.split()
    )
    assert list(RunResult.from_netcdf(short).dataset["map_stop"].values) == [1]
    # a run file of other emission factors: said, the defaults used
    from brakeca.results import write_atomic

    marked = tmp_path / "marked.nc"
    write_atomic(a.dataset.assign_attrs(pm10_factors="--emissions my.toml: ..."), marked)
    res = runner.invoke(app, ["simulate", "-c", str(marked), "-o", str(tmp_path / "m2.nc")])
    assert res.exit_code == 0 and "give --emissions again" in " ".join(res.output.split())
    # a campaign.nc is not a run file; a run made from a generator's state needs --seed
    from brakeca.results import write_atomic as write

    campaign_nc = tmp_path / "campaign.nc"
    write(xr.Dataset(attrs={"design": "x"}), campaign_nc)
    res = runner.invoke(app, ["simulate", "-c", str(campaign_nc), "-o", str(tmp_path / "c.nc")])
    assert res.exit_code == 2
    assert "a netCDF file without a run's configuration (config)" in " ".join(res.output.split())
    state = tmp_path / "state.nc"
    write(a.dataset.assign_attrs(seed=-1), state)
    res = runner.invoke(app, ["simulate", "-c", str(state), "-o", str(tmp_path / "s.nc")])
    assert res.exit_code == 2 and "give --seed" in res.output
    res = runner.invoke(
        app, ["simulate", "-c", str(state), "-o", str(tmp_path / "s.nc"), "--seed", "7"]
    )
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["config", "-c", str(state)])
    assert res.exit_code == 0 and "random generator's state" in " ".join(res.stderr.split())
    # a trace run whose trace moved: the error says what the run file recorded and how to go
    # on (it had said only "no such file")
    import shutil

    from brakeca.presets import __file__ as presets_init

    trace = tmp_path / "mine.csv"
    shutil.copy(Path(presets_init).parent / "cycles" / "example_trace.csv", trace)
    traced = tmp_path / "traced.nc"
    res = runner.invoke(app, ["simulate", "-o", str(traced), *tiny, "--cycle", str(trace)])
    assert res.exit_code == 0, res.output
    trace.rename(tmp_path / "moved.csv")
    res = runner.invoke(app, ["simulate", "-c", str(traced), "-o", str(tmp_path / "t2.nc")])
    assert res.exit_code == 2
    assert f"(the run file's trace, recorded at {trace}: --cycle PATH reads it" in " ".join(
        res.output.split()
    )
    not_a_run = tmp_path / "bad.nc"
    not_a_run.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 64)
    res = runner.invoke(app, ["simulate", "-c", str(not_a_run), "-o", str(tmp_path / "x.nc")])
    assert res.exit_code == 2 and "cannot read the run file" in " ".join(res.output.split())


def test_cli_simulate_says_how_much_pad_wore(tmp_path):
    """The pad's worn volume (fibre and resin, the run's generated volume) and the mean depth
    it makes over the band, which the run file gives only as volumes per stop."""
    import re

    from campaign_helpers import TINY_CLI

    from brakeca.geometry import make_grid

    tiny = TINY_CLI[: TINY_CLI.index("--executor")]
    path = tmp_path / "r.nc"
    res = CliRunner().invoke(app, ["simulate", "-o", str(path), *tiny])
    assert res.exit_code == 0, res.output
    match = re.search(r"band worn: (\S+) mm³, a mean depth of (\S+) mm", res.output)
    assert match is not None, res.output
    run = RunResult.from_netcdf(path)
    # V is the band's, and the line says how much of the pad that is (a docs walkthrough: a
    # new user read it as the pad's)
    band = make_grid(run.config).area
    share = band / run.config.brake.pad_area
    text = " ".join(res.output.split())
    assert (
        f"V = {run.V * 1e9:.6g} mm³ per stop, from the band of 5 rows ({band * 1e6:.4g} mm², "
        f"{100 * share:.3g} % of the pad; a whole pad: V / {share:.4g})"
    ) in text
    # MU and the spread of the stops' mean COF (the run's MU_SD) on one line
    assert (
        f"MU = {run.MU:.4f}, MU_SD = {run.MU_SD:.3g} (the spread of the 2 stops' mean COF)"
    ) in text
    worn = float(run.dataset["generated_volume"].sum())
    assert float(match[1]) == pytest.approx(worn * 1e9, rel=1e-5)
    depth = worn / make_grid(run.config).area
    assert float(match[2]) == pytest.approx(depth * 1e3, rel=1e-3) and depth > 0
    assert "note: more than a new car pad" not in res.output  # 2 stops: far from 10 mm


def test_cli_simulate_notes_a_depth_past_a_real_pads(tmp_path, monkeypatch):
    """The model has no pad thickness: a depth beyond a new pad's friction material is
    noted (the threshold lowered here so that two tiny stops pass it)."""
    from campaign_helpers import TINY_CLI

    from brakeca import cli

    monkeypatch.setattr(cli, "PAD_DEPTH_NOTE", 1e-12)
    tiny = TINY_CLI[: TINY_CLI.index("--executor")]
    res = CliRunner().invoke(app, ["simulate", "-o", str(tmp_path / "r.nc"), *tiny])
    assert res.exit_code == 0, res.output
    assert "note: more than a new car pad's friction material (typically 10-12 mm)" in (
        " ".join(res.output.split())
    )


def test_the_run_file_may_not_overwrite_an_input_or_another_kind_of_file(tmp_path):
    """A black-box review: `simulate --cycle my.csv -o my.csv` wrote the run over its own
    trace (and -o over any file). The inputs and files that are not netCDF are refused
    before any work; a name without .nc gets a note."""
    import shutil

    from campaign_helpers import TINY_CLI

    from brakeca.presets import __file__ as presets_init

    tiny = TINY_CLI[: TINY_CLI.index("--executor")]
    trace = tmp_path / "my.csv"
    shutil.copy(Path(presets_init).parent / "cycles" / "example_trace.csv", trace)
    before = trace.read_bytes()
    res = CliRunner().invoke(app, ["simulate", "--cycle", str(trace), "-o", str(trace), *tiny])
    assert res.exit_code == 2, res.output
    assert "the same file as an input of this run" in " ".join(res.output.split())
    assert trace.read_bytes() == before
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    res = CliRunner().invoke(app, ["simulate", "-o", str(notes), *tiny])
    assert res.exit_code == 2
    assert "exists and is not a netCDF file (a run file)" in " ".join(res.output.split())
    assert notes.read_text() == "my notes\n"
    run = tmp_path / "run.dat"
    res = CliRunner().invoke(app, ["simulate", "-o", str(run), *tiny])
    assert res.exit_code == 0, res.output
    assert "a run file is netCDF" in " ".join(res.output.split())
    # a run file is written over by the next run of that name, as before
    res = CliRunner().invoke(app, ["simulate", "-o", str(run), *tiny, "--seed", "2"])
    assert res.exit_code == 0, res.output
    assert RunResult.from_netcdf(run).seed == 2


def test_run_files_carry_cf_metadata_on_every_coordinate(tmp_path) -> None:
    """Every coordinate has units and a long name, and the status maps' flag_values are
    numbers of the variable's type, as CF tools decode them (they were the text "0 1 2";
    an API review)."""
    import numpy as np

    from brakeca.design import quick_config

    config = quick_config(load_preset("paper")).with_updates({"cycle.max_stops": 1})
    simulate(config, seed=1, maps_at=[1]).to_netcdf(tmp_path / "r.nc")
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        for name in ("stop", "step", "rule", "radius", "angle", "map_stop"):
            assert {"units", "long_name"} <= set(ds[name].attrs), name
    # a coordinate variable has no _FillValue: it holds no missing value (CF 2.5.1; xarray
    # gave the float ones NaN, which CF checkers flag: an API review)
    import h5py

    with h5py.File(tmp_path / "r.nc") as raw:
        for name in ("radius", "angle", "stop", "step", "map_stop"):
            assert "_FillValue" not in raw[name].attrs, name
        assert "_FillValue" in raw["step_cof"].attrs  # data variables keep theirs
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        for name in ("initial_status", "final_status", "map_status"):
            flags = ds[name].attrs["flag_values"]
            assert flags.dtype == ds[name].dtype == np.int8
            assert list(flags) == [0, 1, 2]
        # a single-run review: the band's area was not in the file, the per-step shares'
        # long names did not say of what, the heights not from where
        mesh = config.mesh  # A_sim = sum of r_j dtheta dr over the rows, times the columns
        expected = (
            float(ds["radius"].sum())
            * np.radians(mesh.angular_step_deg)
            * mesh.radial_step
            * ds["angle"].size
        )
        assert ds.attrs["band_area"] == pytest.approx(expected, rel=1e-12)
        assert ds["step_contact_area_fraction"].attrs["long_name"] == "area in contact / band area"
        assert ds["final_height"].attrs["long_name"].startswith("cell height above the pad datum")
        assert "cells" in ds["secondary_removed_between_stops"].attrs["long_name"]
        assert "band_area: the simulated band's area A_sim [m2]" in ds.attrs["comment"]


def test_a_full_disk_is_an_oserror_not_a_crash(tmp_path, run) -> None:
    """Writing a run file (and ``campaign.nc``, written the same way) to a full disk crashed
    the process in h5py with a segmentation fault, so no handler could say what happened and
    how to go on (a robustness review; a small tmpfs reproduced it). The file is made in
    memory now and written as bytes: a file-size limit, which fails the writes as a full disk
    does, gives an OSError, and no temporary file is left."""
    import subprocess
    import sys
    import textwrap

    path = tmp_path / "run.nc"
    run.to_netcdf(path)
    size = path.stat().st_size
    path.unlink()
    script = tmp_path / "full.py"
    script.write_text(
        textwrap.dedent(
            f"""
            import resource, signal
            from brakeca.results import RunResult
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # EFBIG instead of the signal
            result = RunResult.from_netcdf({str(tmp_path / "in.nc")!r})
            resource.setrlimit(resource.RLIMIT_FSIZE, ({size // 2}, {size // 2}))
            try:
                result.to_netcdf({str(path)!r})
            except OSError as exc:
                print("OSError", exc.errno)
            """
        )
    )
    run.to_netcdf(tmp_path / "in.nc")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    assert done.stdout.split() == ["OSError", "27"], done.stdout  # EFBIG: File too large
    assert sorted(p.name for p in tmp_path.iterdir()) == ["full.py", "in.nc"]


def test_a_band_too_small_for_its_fibres_gets_a_note():
    """An API review: 3 x 100 cells at A = 10 % began with a third of the band primary, and
    nothing said so; the command line now notes a start far from A (and not on the quick
    band, whose share is near A)."""
    import io

    from rich.console import Console

    from brakeca.cli import _fibre_share_note

    config = load_preset().with_updates({"mesh.n_radial": 3, "mesh.n_angular": 100, "A": 10})
    status = np.zeros((3, 100), dtype=np.int8)
    for share, noted in ((0.33, True), (0.11, False)):
        status[:] = 0
        status[:, : round(100 * share)] = 1
        out = Console(file=io.StringIO(), width=300)
        ds = xr.Dataset(
            {"initial_status": (("radius", "angle"), status)},
            coords={"radius": [0.112, 0.1121, 0.1122]},  # [m]
        )
        _fibre_share_note(out, config, ds)
        text = out.file.getvalue()
        assert ("the fibres cover 33 % of the band at the start, not A = 10 %" in text) is noted
        assert bool(text) is noted


def test_a_run_keeps_its_last_stops_plateaus_from_before_rule_s():
    """A figures review: the final maps of the S = 1 runs showed no secondary plateau (rule S
    had removed them all after the last stop), so half the study's maps said nothing of
    the plateaus that carried their runs. A run whose rule S removes plateaus after its
    last stop keeps the statuses from before it; one whose rule S removes none does not."""
    from conftest import resumable_config

    ds = simulate(resumable_config(stops=2, removal=1.0), seed=1).dataset
    before, after = ds["final_status_before_s"].to_numpy(), ds["final_status"].to_numpy()
    assert (before == 2).sum() == int(ds["secondary_removed_between_stops"][-1]) > 0
    assert not (after == 2).any()
    np.testing.assert_array_equal(np.where(before == 2, 0, before), after)
    kept = simulate(resumable_config(stops=2, removal=0.0), seed=1).dataset
    assert "final_status_before_s" not in kept and (kept["final_status"] == 2).any()


def test_a_runs_per_stop_table_and_its_equality(small) -> None:
    """RunResult.per_stop() is the run's per-stop table (the obvious dataset.to_dataframe()
    broadcasts every cell of the band), and two results are equal only where they are one
    (a dataclass's == had compared the datasets' truth values: any two runs of one config and
    seed were equal, whatever their datasets; an API review)."""
    from brakeca.study import per_stop_table

    config = small.with_updates({"cycle.max_stops": 2})
    run, other = simulate(config, seed=1), simulate(config, seed=2)
    table = run.per_stop()
    pd.testing.assert_frame_equal(table, per_stop_table(run))
    assert list(table["stop"]) == [1, 2] and set(table["seed"]) == {1}
    assert table["mean_cof"].mean() == pytest.approx(run.MU, rel=1e-15)
    assert table["emitted_mm3"].mean() == pytest.approx(run.V * 1e9, rel=1e-15)
    mixed = RunResult(config=run.config, seed=run.seed, dataset=other.dataset)
    assert mixed != run and run == run and len({run, mixed}) == 2
    # the block table takes the run as its siblings do (it had failed on "no attribute
    # 'columns'": an API review), and the run's map draws from its DataArray alone
    from brakeca.plotting import plot_surface_map
    from brakeca.study import block_table

    pd.testing.assert_frame_equal(block_table(run), block_table(per_stop_table(run)))
    assert not block_table(run).empty
    with pytest.raises(TypeError, match=r"^block_table takes per_stop_table's table, a "):
        block_table(run.dataset)
    final = run.dataset["final_status"]
    drawn = plot_surface_map(final, title="final")
    given = plot_surface_map(final.values, final["radius"].values, final["angle"].values)
    assert (drawn.axes[0].images[0].get_array() == given.axes[0].images[0].get_array()).all()
    drawn = plot_surface_map(final.transpose("angle", "radius"))  # by its dims' names
    assert (drawn.axes[0].images[0].get_array() == given.axes[0].images[0].get_array()).all()
    with pytest.raises(TypeError, match=r"^radius and angle: give the cells' radii \[m\]"):
        plot_surface_map(final.values)
    with pytest.raises(TypeError, match=r"^status: one map on radius and angle, got one over "
                       r"map_stop too; pick one \(e.g. .sel\(map_stop=...\)"):  # fmt: skip
        plot_surface_map(final.expand_dims(map_stop=[1, 2]))
    with pytest.raises(
        TypeError,
        match=r"^radius: an array of the cells' radii \[m\], got 'final' \(a title is title=\)$",
    ):
        plot_surface_map(final, "final")
