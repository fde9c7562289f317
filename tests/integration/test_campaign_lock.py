"""One campaign at a time in a campaign directory: a second one is refused, clearly, before it
writes anything, and a killed campaign does not leave the folder locked."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from campaign_helpers import DESIGN_TEMPLATE, quiet, tiny, write_design
from typer.testing import CliRunner

from brakeca.campaign import CampaignLockedError, run_campaign
from brakeca.cli import app

HOLD = textwrap.dedent(
    """
    import sys, time
    from pathlib import Path
    from brakeca._runstore import campaign_lock
    with campaign_lock(Path(sys.argv[1])):
        print("locked", flush=True)
        time.sleep(600)
    """
)


@pytest.fixture
def design(tmp_path):
    """A 2 x 2 design on a tiny band, one stop."""
    return write_design(tmp_path, tiny(1), DESIGN_TEMPLATE.format(root_seed=3))


@pytest.fixture
def holder(tmp_path):
    """A process that holds the lock of ``tmp_path / "campaign"`` until it is killed."""
    out = tmp_path / "campaign"
    proc = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(out)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout.readline().strip() == "locked"
        yield out, proc
    finally:
        proc.kill()
        proc.wait()
        proc.stdout.close()


def test_a_second_campaign_is_refused_and_writes_nothing(holder, design):
    out, proc = holder
    with pytest.raises(CampaignLockedError, match=f"pid {proc.pid}") as err:
        run_campaign(design, out, executor="serial", progress=False, console=quiet())
    assert str(out) in str(err.value)
    assert sorted(p.name for p in out.iterdir()) == [".brakeca.lock"]


def test_the_command_line_says_why(holder, design):
    out, _ = holder
    res = CliRunner().invoke(app, ["run", str(design), "-o", str(out), "--executor", "serial"])
    assert res.exit_code == 2
    assert "another campaign is writing this folder" in " ".join(res.output.split())


def test_a_killed_holder_releases_the_lock(holder, design):
    out, proc = holder
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    result = run_campaign(design, out, executor="serial", progress=False, console=quiet())
    assert len(result.computed) == 4
    said = Path(out / ".brakeca.lock").read_text()  # ended: it says so, naming the holder
    assert said.startswith(f"not held; last held by pid {os.getpid()} on ")


def test_a_file_system_without_flock_runs_unlocked(tmp_path, monkeypatch):
    import fcntl

    from brakeca._runstore import campaign_lock

    calls = []

    def no_flock(fd, op):
        calls.append(op)
        raise OSError(95, "Operation not supported")

    monkeypatch.setattr(fcntl, "flock", no_flock)
    with campaign_lock(tmp_path / "campaign"):
        pass  # no error: the campaign goes on without a lock
    assert calls == [fcntl.LOCK_EX | fcntl.LOCK_NB]  # it did ask (a tests review: no assert)


def test_lock_holder_names_a_campaign_and_does_not_keep_one_out(tmp_path, monkeypatch):
    """``brakeca analyze`` asks who holds the lock by taking it shared for an instant: a
    campaign starting in that instant waits for it instead of failing (a diff review)."""
    import fcntl
    import time
    import types

    from brakeca import _runstore
    from brakeca._runstore import LOCK_NAME, campaign_lock, lock_holder

    out = tmp_path / "campaign"
    assert lock_holder(out) is None  # no folder, no lock file
    with campaign_lock(out):
        assert lock_holder(out).startswith(f"pid {os.getpid()} on ")
        assert (out / LOCK_NAME).read_text().startswith(f"pid {os.getpid()} on ")
    assert lock_holder(out) is None  # the file stays, unheld, and says so
    assert (out / LOCK_NAME).read_text().startswith("not held; last held by pid ")
    with open(out / LOCK_NAME, encoding="utf-8") as fh:
        fcntl.flock(fh, fcntl.LOCK_SH)  # as lock_holder holds it for an instant
        waits: list[float] = []

        def wait(seconds: float) -> None:  # its first wait ends that instant (not a timer:
            waits.append(seconds)  # a tests review found 150 ms of margin on a busy machine)
            if len(waits) == 1:
                fcntl.flock(fh, fcntl.LOCK_UN)

        clock = {n: getattr(time, n) for n in dir(time) if not n.startswith("_")}
        monkeypatch.setattr(_runstore, "time", types.SimpleNamespace(**{**clock, "sleep": wait}))
        with campaign_lock(out):
            pass
        assert waits == [0.05]  # it waited once, then took the lock
