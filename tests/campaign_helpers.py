"""Shared pieces of the campaign tests: a 2 x 2 design (S x A) on a tiny band, quiet consoles,
and a process started as a terminal's job, for the tests that send it signals."""

from __future__ import annotations

import contextlib
import io
import os
import select
import signal
import subprocess
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import pandas as pd
import xarray as xr
from rich.console import Console

DESIGN_TEMPLATE = """\
name = "tiny"
description = "2 x 2 on a tiny band"
base_config = "tiny_base.toml"
root_seed = {root_seed}

[[factors]]
name = "S"
field = "automaton.secondary_removal_fraction"
levels = [0.0, 1.0]
labels = ["-", "+"]

[[factors]]
name = "A"
field = "pad.fibre_area_fraction"
levels = [10.0, 20.0]
scale = 0.01
labels = ["-", "+"]
unit = "%"
"""

#: `brakeca run` options for a 5 x 100 cell band, WP+ and the first 2 stops, serially.
TINY_CLI = [
    "--set",
    "mesh.n_radial=5",
    "--set",
    "mesh.n_angular=100",
    "--set",
    "WP=1e-13",
    "--stops",
    "2",
    "--executor",
    "serial",
]

#: Summary columns that depend on the machine's speed, not on the run.
TIMING = ["wall_time"]
#: ... and the run files' attributes that say when and how fast a run was made
TIMING_ATTRS = ["wall_time", "date_created"]


def tiny(max_stops: int) -> dict:
    """Overrides for a 5 x 100 cell band and the first ``max_stops`` stops."""
    return {
        "mesh.n_radial": 5,
        "mesh.n_angular": 100,
        "mesh.n_subdomains": 10,
        "cycle.max_stops": max_stops,
    }


def cli_ok(*args: str) -> str:
    """Run the command line in-process, check that it exits 0 and return its output."""
    from typer.testing import CliRunner

    from brakeca.cli import app

    res = CliRunner().invoke(app, list(args))
    assert res.exit_code == 0, res.output
    return res.output


def quiet() -> Console:
    """A console that writes to memory."""
    return Console(file=io.StringIO(), width=200)


def console_text(console: Console) -> str:
    """What a :func:`quiet` console received."""
    return console.file.getvalue()  # type: ignore[attr-defined]


def deterministic(summary: pd.DataFrame) -> pd.DataFrame:
    """The summary without its timing columns."""
    return summary.drop(columns=[c for c in TIMING if c in summary.columns])


def drawing(design_text: str) -> str:
    """``design_text`` (:data:`DESIGN_TEMPLATE`'s) with S at 0.5 and 1: at S = 0 or 1 rule S
    draws nothing, so runs at S = 0.5 are the ones that use the generator after the surface
    is made (a test-suite review: executors compared on S = 0 and 1 alone would not see a
    worker that re-seeds or shares a generator)."""
    text = design_text.replace("levels = [0.0, 1.0]", "levels = [0.5, 1.0]", 1)
    assert text != design_text
    return text


def run_dataset(out: Path, rid: str) -> xr.Dataset:
    """A run file's dataset without its timing variables and attributes."""
    from brakeca.results import RunResult

    ds = RunResult.from_netcdf(out / "runs" / f"{rid}.nc").dataset
    ds = ds.drop_vars([v for v in TIMING if v in ds.variables])
    ds.attrs = {k: v for k, v in ds.attrs.items() if k not in TIMING_ATTRS}
    return ds


def assert_same_runs(result: Any, reference: Any, *, maps_at: Sequence[int] = ()) -> None:
    """Bit-identical summaries, campaign datasets and run files (timing aside) of two
    :class:`~brakeca.campaign.CampaignResult`; with ``maps_at``, the result's runs kept maps
    after those stops, which the reference's did not (and which are all their files have
    more)."""
    pd.testing.assert_frame_equal(
        deterministic(result.summary),
        deterministic(reference.summary),
        check_exact=True,
        check_dtype=False,
    )
    xr.testing.assert_identical(
        result.dataset.drop_vars(TIMING),
        reference.dataset.drop_vars(TIMING).assign_attrs(result.dataset.attrs),
    )
    for rid in reference.summary["run_id"]:
        run = run_dataset(result.out_dir, rid)
        if maps_at:
            assert list(run["map_stop"].to_numpy()) == list(maps_at)
            run = run.drop_vars(["map_status", "map_height", "map_stop"])
        xr.testing.assert_identical(run, run_dataset(reference.out_dir, rid))


def write_design(folder, overrides: dict, design_text: str):
    """Write ``tiny_base.toml`` (the paper preset with ``overrides``) and the design file
    ``tiny.toml`` into ``folder``; returns the design file's path."""
    from brakeca.presets import load_preset

    base = load_preset("paper").with_updates(overrides)
    (folder / "tiny_base.toml").write_text(base.to_toml(), encoding="utf-8")
    path = folder / "tiny.toml"
    path.write_text(design_text, encoding="utf-8")
    return path


def must_not_run(config, *, seed, progress=None, maps_at=()):
    """A simulate that fails the test if a reused run is computed again."""
    raise AssertionError("simulate was called for a run that should have been reused")


def rerun_reusing(out, **kwargs):
    """Run the campaign in ``out`` again from its own design.toml, serially, with a simulate
    that fails the test if any run is computed: (result, what its console said)."""
    from brakeca.campaign import run_campaign
    from brakeca.design import load_design

    console = quiet()
    result = run_campaign(
        load_design(out / "design.toml"),
        out,
        executor="serial",
        simulate_fn=must_not_run,
        console=console,
        **kwargs,
    )
    return result, console_text(console)


def _default_hangup() -> None:
    """In a child before it runs: SIGHUP's default handler."""
    signal.signal(signal.SIGHUP, signal.SIG_DFL)


@contextlib.contextmanager
def started_as_a_job(
    args: Sequence[str], first_line: str, env: dict[str, str] | None = None
) -> Iterator[subprocess.Popen[str]]:
    """``python ARGS`` in a session of its own (its own process group, to which a test sends
    the signals a terminal sends), its output and errors piped, once it has printed
    ``first_line`` (within 120 s). On leaving, whatever is left of its group (the job, its
    workers) is killed, so that a failed test leaves no process behind (a tests review)."""
    proc = subprocess.Popen(
        [sys.executable, *args],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        # SIGHUP as a terminal's job has it, also where the tests run under nohup (which
        # ignores it, and a program leaves an ignored SIGHUP alone)
        preexec_fn=_default_hangup,
    )
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 120.0)
        assert ready, f"the job did not print {first_line!r} within 120 s"
        assert proc.stdout.readline().strip() == first_line
        yield proc
    finally:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(proc.pid, signal.SIGKILL)  # its group: the job and its workers
        proc.wait(timeout=30)
        for pipe in (proc.stdout, proc.stderr):
            if pipe is not None:
                pipe.close()


def ignores_sigint(pid: int) -> bool:
    """Whether process ``pid`` ignores SIGINT (its SigIgn mask in /proc holds signal 2)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    for line in status.splitlines():
        if line.startswith("SigIgn:"):
            return bool(int(line.split()[1], 16) >> (signal.SIGINT - 1) & 1)
    return False
