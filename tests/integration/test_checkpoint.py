"""A long single run checkpoints its state and resumes with an identical result."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from brakeca.presets import load_preset
from brakeca.simulation import simulate


class Killed(Exception):
    pass


def _killed_after(stops, config, ckpt, **options):
    """Run ``config`` (seed 3, a checkpoint every stop into ``ckpt``) and kill it once
    ``stops`` stops are done; ``options`` go to simulate."""

    def die(done, total):
        if done == stops:
            raise Killed

    with pytest.raises(Killed):
        simulate(config, seed=3, checkpoint=ckpt, checkpoint_every=1, progress=die, **options)
    return ckpt


def _no_wall(ds):
    ds = ds.copy()
    ds.attrs.pop("wall_time")
    ds.attrs.pop("date_created")
    return ds


@pytest.mark.parametrize("removal", [0.0, 0.5])
def test_resume_from_checkpoint_is_identical(tmp_path, removal):
    from conftest import resumable_config

    config = resumable_config(stops=5, removal=removal)
    whole = simulate(config, seed=3)
    if removal:  # rule S draws after the stops resumed: the generator's state must be kept
        assert whole.dataset["secondary_removed_between_stops"][3:].sum() > 0
    ckpt = _killed_after(3, config, tmp_path / "run.ckpt.npz")
    assert ckpt.exists()
    resumed = simulate(config, seed=3, checkpoint=ckpt, checkpoint_every=1)
    xr.testing.assert_identical(_no_wall(resumed.dataset), _no_wall(whole.dataset))
    assert not ckpt.exists()  # removed once the run completes


def test_resume_with_the_fibre_field_is_identical(tmp_path):
    """The fibre field's state (its intervals and each cell's next one) is checkpointed: a run
    killed between exposures resumes bit-identically."""
    from conftest import short_cycle

    config = load_preset().with_updates(
        {
            "mesh.n_radial": 11,
            "WP": 1e-13,
            "A": 10,
            "S": 0.5,
            "pad.fibre_model": "field",
            "cycle": short_cycle(stops=5, v0=50, v1=10, g=0.3),
        }
    )
    whole = simulate(config, seed=3)
    exposed = whole.dataset.fibre_cells_exposed.values
    assert exposed[:2].sum() > 0 and exposed[2:].sum() > 0  # exposures before and after

    ckpt = _killed_after(2, config, tmp_path / "run.ckpt.npz")
    resumed = simulate(config, seed=3, checkpoint=ckpt, checkpoint_every=1)
    xr.testing.assert_identical(_no_wall(resumed.dataset), _no_wall(whole.dataset))


def test_foreign_checkpoint_is_refused(tmp_path):
    config = load_preset().with_updates(
        {"mesh.n_radial": 3, "mesh.n_angular": 100, "cycle.max_stops": 3}
    )
    ckpt = tmp_path / "c.npz"

    def die(done, total):
        raise Killed

    with pytest.raises(Killed):
        simulate(config, seed=1, checkpoint=ckpt, checkpoint_every=1, progress=die)
    # what differs is named (a single-run review was told "config, seed or format differ")
    with pytest.raises(
        ValueError, match=r"checkpoint of another run \(its seed is 1, this run's 2\)"
    ):
        simulate(config, seed=2, checkpoint=ckpt)
    longer = config.with_updates({"cycle.max_stops": 4})
    with pytest.raises(ValueError) as info:
        simulate(longer, seed=1, checkpoint=ckpt)
    assert "(its configuration differs: cycle.max_stops: 3 -> 4) (a run's number of stops" in str(
        info.value
    )
    whole = config.with_updates({"cycle.max_stops": None})  # unset: not the text 'unset'
    with pytest.raises(ValueError, match=r"cycle\.max_stops: 3 -> unset\) \(a run's number"):
        simulate(whole, seed=1, checkpoint=ckpt)
    ckpt.write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match=r"not a brakeca checkpoint \(not an \.npz archive"):
        simulate(config, seed=1, checkpoint=ckpt)


def test_the_command_line_says_it_resumes(tmp_path):
    """brakeca simulate --checkpoint names the checkpoint it resumes from (a review: it had
    resumed without a word)."""
    from typer.testing import CliRunner

    from brakeca.cli import app
    from brakeca.config import load_config

    path = tmp_path / "small.toml"
    path.write_text(
        load_preset()
        .with_updates({"mesh.n_radial": 4, "mesh.n_angular": 200, "cycle.max_stops": 3})
        .to_toml(),
        encoding="utf-8",
    )
    ckpt = tmp_path / "k.npz"

    def die_after_one(done, total):
        if done == 1:
            raise Killed

    with pytest.raises(Killed):
        simulate(load_config(path), seed=3, checkpoint=ckpt, checkpoint_every=1,
                 progress=die_after_one)  # fmt: skip
    args = ["simulate", "-c", str(path), "--seed", "3", "-o", str(tmp_path / "r.nc")]
    res = CliRunner().invoke(app, [*args, "--checkpoint", str(ckpt)])
    assert res.exit_code == 0, res.output
    assert f"resuming from the checkpoint {ckpt}" in " ".join(res.output.split())
    assert not ckpt.exists()
    res = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "again.nc"),
                                   "--checkpoint", str(ckpt)])  # fmt: skip
    assert res.exit_code == 0 and "resuming" not in res.output


def test_the_command_line_refuses_a_checkpoint_it_would_lose_or_misread(tmp_path):
    """Checked before any work (a helper's review of the command line): -o as the checkpoint
    (the end of the run had removed the run file it had just written), a run file as the
    checkpoint (its message had pointed to unpickling it and told to delete it), and
    --checkpoint-every without --checkpoint (ignored without a word)."""
    from typer.testing import CliRunner

    from brakeca.cli import app

    run = tmp_path / "r.nc"
    args = ["simulate", "--set", "mesh.n_radial=3", "--set", "mesh.n_angular=100", "--stops", "1"]
    res = CliRunner().invoke(app, [*args, "-o", str(run), "--checkpoint", str(run)])
    assert res.exit_code == 2 and "the same file as -o" in " ".join(res.output.split())
    assert CliRunner().invoke(app, [*args, "-o", str(run)]).exit_code == 0
    res = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "s.nc"), "--checkpoint", str(run)])
    out = " ".join(res.output.split())
    assert (
        res.exit_code == 2 and "a netCDF/HDF5 file (a run file?), not a brakeca checkpoint" in out
    )
    assert "0/1" not in out  # refused before the run began (no progress bar)
    assert run.exists()
    res = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "t.nc"), "--checkpoint-every", "2"])
    assert res.exit_code == 2 and "give --checkpoint too" in res.output


def test_maps_after_chosen_stops_survive_a_resume_and_change_nothing_else(tmp_path):
    """simulate(maps_at=) keeps the status and height maps after the stops asked for; the
    maps of stops before a checkpoint are in it, so a killed run resumes with them (its file
    identical to the uninterrupted run's); without maps_at the run is the same but for them.
    A resume that would lack a map (asked for only now) is refused, naming the stop."""
    from conftest import resumable_config

    config = resumable_config(stops=5)
    plain = simulate(config, seed=3)
    whole = simulate(config, seed=3, maps_at=[5, 2, 1])
    maps = whole.dataset[["map_status", "map_height"]]
    assert list(maps["map_stop"].values) == [1, 2, 5]
    assert maps["map_status"].dtype == "int8" and maps["map_height"].attrs["units"] == "m"
    xr.testing.assert_identical(
        maps["map_status"].sel(map_stop=5, drop=True).rename("final_status").drop_attrs(),
        whole.dataset["final_status"].drop_attrs(),
    )
    assert (maps["map_height"].sel(map_stop=1) > maps["map_height"].sel(map_stop=5)).any()  # wear
    # each map is the state after its stop (and the between-stop rules): a run of the first 2
    # stops ends where the map after stop 2 is (a test-suite review: an off-by-one, the map
    # before the stop or after the next, had passed)
    short = simulate(config.with_updates({"cycle.max_stops": 2}), seed=3).dataset
    np.testing.assert_array_equal(maps["map_status"].sel(map_stop=2), short["final_status"])
    np.testing.assert_array_equal(
        maps["map_height"].sel(map_stop=2), short["final_height"].astype(np.float32)
    )
    assert (maps["map_status"].sel(map_stop=2) != maps["map_status"].sel(map_stop=1)).any()
    xr.testing.assert_identical(
        _no_wall(whole.dataset.drop_vars(["map_status", "map_height", "map_stop"])),
        _no_wall(plain.dataset),
    )
    ckpt = tmp_path / "run.ckpt.npz"

    def die_after_three(done, total):
        if done == 3:
            raise Killed

    with pytest.raises(Killed):
        simulate(
            config,
            seed=3,
            checkpoint=ckpt,
            checkpoint_every=1,
            progress=die_after_three,
            maps_at=[1, 2, 5],
        )
    with pytest.raises(ValueError, match=r"maps_at: stop 3 ran before the checkpoint"):
        simulate(config, seed=3, checkpoint=ckpt, maps_at=[1, 3])
    resumed = simulate(config, seed=3, checkpoint=ckpt, checkpoint_every=1, maps_at=[1, 2, 5])
    xr.testing.assert_identical(_no_wall(resumed.dataset), _no_wall(whole.dataset))
    back = type(whole).from_netcdf(whole.to_netcdf(tmp_path / "run.nc"))
    xr.testing.assert_identical(
        _no_wall(back.dataset[["map_status", "map_height"]]), _no_wall(maps)
    )
    with pytest.raises(ValueError, match=r"maps_at: stop 6 is not a stop of this cycle"):
        simulate(config, seed=3, maps_at=[6])


def test_a_checkpoint_that_cannot_be_written_does_not_fail_the_run(tmp_path, monkeypatch):
    """A full disk failed the whole run over its optional checkpoint ("OSError: [Errno 28]
    No space left on device", naming no file; a robustness review). The run now goes on with
    one warning naming the file, and gives the same result; the checkpoint written before the
    disk filled is still there to resume from."""
    import errno

    from conftest import resumable_config

    import brakeca.simulation
    from brakeca.simulation import CheckpointWarning

    config = resumable_config(stops=5, removal=0.5)
    whole = simulate(config, seed=3)
    ckpt = tmp_path / "run.ckpt.npz"
    real = brakeca.simulation.save_checkpoint
    stops_saved = []

    def full_after_two(path, config, seed, state, initial_status, log, *rest):
        if len(log.dts) > 2:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        stops_saved.append(len(log.dts))
        return real(path, config, seed, state, initial_status, log, *rest)

    monkeypatch.setattr(brakeca.simulation, "save_checkpoint", full_after_two)

    def stop_at_four(done, total):
        if done == 4:
            raise Killed

    with pytest.warns(CheckpointWarning) as seen:
        with pytest.raises(Killed):
            simulate(config, seed=3, checkpoint=ckpt, checkpoint_every=1, progress=stop_at_four)
    assert len(seen) == 1  # once, not at every checkpoint stop
    assert str(seen[0].message).startswith(
        f"checkpoint {ckpt}: cannot write it after stop 3 (No space left on device); the run "
        "goes on"
    )
    assert stops_saved == [1, 2] and ckpt.exists()
    monkeypatch.setattr(brakeca.simulation, "save_checkpoint", real)
    resumed = simulate(config, seed=3, checkpoint=ckpt, checkpoint_every=1)  # from stop 2
    xr.testing.assert_identical(_no_wall(resumed.dataset), _no_wall(whole.dataset))


def _tampered(source, target, **changes):
    """A copy of the checkpoint ``source`` with ``changes`` (name: function of the array, or
    an array; None: left out) made, as someone might craft one."""
    with np.load(source, allow_pickle=False) as data:
        arrays = {k: data[k].copy() for k in data.files}
    for name, change in changes.items():
        if change is None:
            del arrays[name]
        else:
            arrays[name] = change(arrays[name]) if callable(change) else change
    with open(target, "wb") as fh:
        np.savez_compressed(fh, **arrays)
    return target


@pytest.mark.parametrize("field", [False, True])
def test_a_crafted_checkpoint_is_refused_before_the_kernels_read_it(tmp_path, field):
    """A security review: a checkpoint's counts and cell indices went into the kernels
    unchecked (a count beyond its array: a segmentation fault), and every entry of the file,
    however large, was decompressed before any check. Each is refused with a clear error;
    an entry a checkpoint does not have is not read at all."""
    from conftest import resumable_config

    from brakeca.checkpoint import CheckpointError, load_checkpoint
    from brakeca.geometry import make_grid

    config = resumable_config(stops=3)
    if field:
        config = config.with_updates({"pad.fibre_model": "field"})
    ckpt = _killed_after(2, config, tmp_path / "run.npz")
    grid = make_grid(config)
    n = grid.shape[0] * grid.shape[1]
    assert load_checkpoint(ckpt, config, 3, grid) is not None  # the real one loads

    def cnt(k, value):
        def change(a):
            a = a.copy()
            a[k] = value
            return a

        return change

    cases = [
        ({"state_cnt": cnt(0, n + 1)}, "plateaus for room for"),
        ({"state_cnt": cnt(1, -1)}, "resin heap for room for"),
        ({"state_pk_idx": lambda a: a + n}, "a cell index, stream bin or status out of range"),
        ({"state_heap_vals": lambda a: a - n}, "out of range"),
        ({"state_ncand": lambda a: a + n}, "more candidates than a stream bin has cells"),
        ({"state_status": lambda a: a + 3}, "a status other than 0, 1 or 2"),
        ({"state_height": lambda a: a[:-1]}, "values of kind 'f' expected"),
        ({"state_rule4_list": lambda a: a.astype(np.int32)}, "state_rule4_list: shape"),
        ({"state_cnt": None}, "state_cnt: shape"),
        ({"log_dts": None}, "its per-stop log"),
    ]
    if field:
        cases.append(({"field_next": lambda a: a + 10**6}, "the fibre field's intervals"))
        cases.append(({"field_top": None}, "the fibre field's arrays missing"))
    else:
        counts = np.array([1, 2, 3], dtype=np.int64)
        cases.append(({"field_counts": counts}, "the fibre field's arrays of a run without one"))
    for changes, message in cases:
        bad = _tampered(ckpt, tmp_path / "bad.npz", **changes)
        with pytest.raises(CheckpointError, match=message):
            load_checkpoint(bad, config, 3, grid)
    # an entry of its own is never decompressed; a known one beyond a run's size is refused
    big = np.zeros(5_000_000)  # 40 MB, a few kB compressed
    extra = _tampered(ckpt, tmp_path / "extra.npz", junk=big)
    assert load_checkpoint(extra, config, 3, grid) is not None
    import brakeca.checkpoint as module

    limit = module._MAX_BYTES_FIXED + module._MAX_BYTES_PER_CELL * n
    huge = np.zeros(limit // 8 + 1)
    bomb = _tampered(ckpt, tmp_path / "bomb.npz", log_dts=huge)
    assert bomb.stat().st_size < limit / 100
    with pytest.raises(CheckpointError, match=r"its log_dts holds \d+ bytes, more than a run"):
        load_checkpoint(bomb, config, 3, grid)
