"""SIGTERM and SIGHUP stop a campaign or a run as Ctrl-C does; local workers end with it."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from brakeca._executors import terminate_as_interrupt


@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP"])
def test_terminate_and_hangup_raise_keyboard_interrupt_inside_the_block(name) -> None:
    number = getattr(signal, name)
    # the default handler, as a terminal gives it (under nohup SIGHUP is ignored, which
    # terminate_as_interrupt leaves alone on purpose: test_an_ignored_hangup_stays_ignored)
    inherited = signal.signal(number, signal.SIG_DFL)
    try:
        with pytest.raises(KeyboardInterrupt, match=name), terminate_as_interrupt():
            os.kill(os.getpid(), number)
            time.sleep(1.0)  # the handler runs at the next bytecode
        assert signal.getsignal(number) == signal.SIG_DFL  # restored
    finally:
        signal.signal(number, inherited)


def test_an_ignored_hangup_stays_ignored() -> None:
    """A campaign started under nohup (SIGHUP ignored) goes on when the terminal closes."""
    inherited = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        with terminate_as_interrupt():
            assert signal.getsignal(signal.SIGHUP) == signal.SIG_IGN
            os.kill(os.getpid(), signal.SIGHUP)
            time.sleep(0.2)  # nothing raised
    finally:
        signal.signal(signal.SIGHUP, inherited)


def test_a_ctrl_c_python_drops_in_a_finalizer_is_raised_again(monkeypatch) -> None:
    """A command-line review: a Ctrl-C that came while Python ran a finalizer or a weak
    reference's callback was printed ("Exception ignored in ...") and dropped, and the
    campaign ran every run to the end, exit status 0. The block remembers it, and
    raise_if_interrupted (between runs, between figures) raises it again; once."""
    from brakeca._executors import raise_if_interrupted

    dropped = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: dropped.append(u.exc_type))

    class Interrupted:
        def __del__(self) -> None:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1.0)  # the handler runs here, inside the finalizer

    inherited = signal.signal(signal.SIGINT, signal.default_int_handler)  # as a terminal's
    try:
        with terminate_as_interrupt():
            Interrupted()  # made and finalized at once
            assert dropped == [KeyboardInterrupt]  # Python dropped it...
            with pytest.raises(KeyboardInterrupt) as info:
                raise_if_interrupted()  # ...and here it is again, as Ctrl-C's (status 130)
            assert info.value.args == ()
            raise_if_interrupted()  # once
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
        with terminate_as_interrupt():  # a later block starts without it
            raise_if_interrupted()
        # lost after the last check, it is raised as the block ends (a diff review: the
        # last run's finalizers, and the command ended with status 0)
        with pytest.raises(KeyboardInterrupt), terminate_as_interrupt():
            Interrupted()
            assert dropped == [KeyboardInterrupt] * 2
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
        # one that propagated, and that code in the block caught, is not raised again (a
        # diff review: the block had raised it a second time at its end)
        with terminate_as_interrupt():
            with contextlib.suppress(KeyboardInterrupt):
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(1.0)
            raise_if_interrupted()  # nothing
    finally:
        signal.signal(signal.SIGINT, inherited)
    raise_if_interrupted()  # outside a block: nothing


def test_a_handler_of_the_program_is_left_alone() -> None:
    seen = []
    saved = signal.signal(signal.SIGTERM, lambda *_: seen.append(1))
    try:
        with terminate_as_interrupt():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.2)
        assert seen == [1]
    finally:
        signal.signal(signal.SIGTERM, saved)


def test_a_local_worker_ends_with_its_campaign_process(tmp_path) -> None:
    """A robustness review found a killed campaign's workers running on as orphans. The
    campaign process here starts a worker of the local pool, writes the worker's pid and is
    killed by SIGKILL (which it cannot handle); the worker must end within a few seconds."""
    pid_file = tmp_path / "worker.pid"
    code = textwrap.dedent(
        f"""
        import os, time
        from brakeca._executors import _local_pool
        if __name__ == "__main__":
            pool = _local_pool(1)
            pid = pool.submit(os.getpid).result()
            open({str(pid_file)!r}, "w").write(str(pid))
            time.sleep(60)
        """
    )
    script = tmp_path / "campaign.py"
    script.write_text(code)
    _kill_parent_then_wait([sys.executable, str(script)], pid_file, lambda: True)


def _kill_parent_then_wait(command: list[str], pid_file, done) -> None:
    """Start ``command`` (the parent), wait for the pid its child writes to ``pid_file``,
    kill the parent outright and wait up to 10 s for the child to end and ``done()``."""
    parent = subprocess.Popen(command)
    child = 0
    try:
        deadline = time.monotonic() + 60
        while not pid_file.exists() or not pid_file.read_text():
            assert time.monotonic() < deadline and parent.poll() is None
            time.sleep(0.1)
        child = int(pid_file.read_text())
        assert _alive(child)
        parent.kill()
        parent.wait()
        deadline = time.monotonic() + 10
        while _alive(child) or not done():
            assert time.monotonic() < deadline, "the child outlived its parent"
            time.sleep(0.1)
        child = 0  # ended
    finally:
        if parent.poll() is None:
            parent.kill()
        if child:  # a child that outlived its parent: not left behind (a tests review)
            with contextlib.suppress(ProcessLookupError):
                os.kill(child, signal.SIGKILL)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie (ended, not yet reaped by init) counts as ended
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().split(") ")[1][0] != "Z"
    except OSError:
        return False


def test_a_child_watching_its_parent_cleans_up_and_ends(tmp_path) -> None:
    """The warm-up child's guard: when its parent is killed outright, the child calls its
    cleanup (the warm-up removes its temporary folder) and ends."""
    marker = tmp_path / "cleaned"
    pid_file = tmp_path / "child.pid"
    child = textwrap.dedent(
        f"""
        import os, time
        from pathlib import Path
        from brakeca._executors import _exit_with_parent
        _exit_with_parent(os.getppid(), 0.1, cleanup=lambda: Path({str(marker)!r}).touch())
        Path({str(pid_file)!r}).write_text(str(os.getpid()))
        time.sleep(60)
        """
    )
    parent_code = (
        "import subprocess, sys, time\n"
        f"subprocess.Popen([sys.executable, '-c', {child!r}])\n"
        "time.sleep(60)\n"
    )
    _kill_parent_then_wait([sys.executable, "-c", parent_code], pid_file, marker.exists)


def test_a_worker_whose_campaign_died_before_it_started_ends() -> None:
    """A robustness review: a worker that finished starting after its campaign was killed
    (kill -9) took init's pid for its parent's and ran on for ever; the pool gives it the
    campaign's pid, and a worker that finds another parent ends at once."""
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    code = (
        "import time\n"
        "from brakeca._executors import _init_worker\n"
        f"_init_worker({gone.pid})\n"
        "time.sleep(60)\n"
    )
    started = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-c", code], timeout=50, check=False, capture_output=True, text=True
    )
    # ended by its watcher (exit 1, nothing said), not by an error (a diff review: the old
    # _init_worker, which takes no pid, had exited 1 too, with a TypeError)
    assert done.returncode == 1 and done.stderr == "", done.stderr
    assert time.monotonic() - started < 30


def test_the_interrupt_message_is_worked_out_when_the_interrupt_comes(tmp_path) -> None:
    """brakeca simulate's message names its checkpoint as resuming only once one was saved
    (it had named one that did not exist yet; a helper's review of the command line)."""
    import typer

    from brakeca import cli

    saved = tmp_path / "k.npz"

    def message() -> str:
        return f"resumes from {saved}" if saved.exists() else "nothing saved yet"

    for exists, expected in ((False, "nothing saved yet"), (True, f"resumes from {saved}")):
        if exists:
            saved.write_bytes(b"x")
        with cli.console.capture() as captured, pytest.raises(typer.Exit) as stop:
            with cli._on_interrupt(message):
                raise KeyboardInterrupt
        assert stop.value.exit_code == 130
        assert expected in " ".join(captured.get().split())


@pytest.mark.parametrize(("raised", "status"), [((), 130), (("SIGTERM",), 143), (("SIGHUP",), 129)])
def test_a_terminated_command_exits_with_the_shells_status_for_its_signal(raised, status) -> None:
    """Ctrl-C exits 130; SIGTERM and SIGHUP, which terminate_as_interrupt raises as
    KeyboardInterrupt("SIGTERM") and so on, exit 128 + the signal's number (they exited 130)."""
    import typer

    from brakeca import cli

    with cli.console.capture(), pytest.raises(typer.Exit) as stop:
        with cli._on_interrupt("kept"):
            raise KeyboardInterrupt(*raised)
    assert stop.value.exit_code == status


def test_sigterm_reaches_the_exit_status_through_the_block() -> None:
    import typer

    from brakeca import cli

    with cli.console.capture(), pytest.raises(typer.Exit) as stop:
        with cli._on_interrupt("kept"):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(1.0)
    assert stop.value.exit_code == 128 + signal.SIGTERM


def test_a_local_worker_leaves_ctrl_c_to_the_campaign(tmp_path) -> None:
    """Ctrl-C reaches the whole process group: an idle worker printed a KeyboardInterrupt
    traceback (a helper's review). Workers ignore SIGINT; the campaign's process stops them.
    Here the whole group of a small campaign process gets SIGINT while its worker waits:
    nothing is printed by the worker, and the campaign process alone handles it."""
    ready = tmp_path / "ready"
    code = textwrap.dedent(
        f"""
        import os, signal, sys, time
        from brakeca._executors import _local_pool
        if __name__ == "__main__":
            # as at a terminal: a shell's background job (the suite run with '&') starts
            # with SIGINT ignored, and Python then installs no KeyboardInterrupt handler
            signal.signal(signal.SIGINT, signal.default_int_handler)
            pool = _local_pool(1)
            ignored = pool.submit(signal.getsignal, signal.SIGINT).result()
            assert ignored == signal.SIG_IGN, ignored
            try:  # the marker inside the try, so the signal cannot land before it
                with open({str(ready)!r}, "w") as marker:
                    marker.write("1")
                time.sleep(60)
            except KeyboardInterrupt:
                pool.shutdown(cancel_futures=True)
                print("parent interrupted")
                sys.exit(0)
        """
    )
    script = tmp_path / "campaign.py"
    script.write_text(code)
    proc = subprocess.Popen(
        [sys.executable, str(script)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, which the signal goes to
    )
    try:
        deadline = time.monotonic() + 60
        while not ready.exists():
            assert time.monotonic() < deadline and proc.poll() is None, proc.stderr.read()
            time.sleep(0.1)
        time.sleep(0.5)  # the worker back to waiting for its next call
        os.killpg(proc.pid, signal.SIGINT)
        try:
            out, err = proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
            pytest.fail(f"the campaign process did not end within 60 s of Ctrl-C: {out!r} {err!r}")
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()  # reaped, its pipes closed
    assert proc.returncode == 0 and "parent interrupted" in out, (out, err)
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err


def test_brakecas_warnings_are_one_line_in_a_worker_and_on_the_command_line(tmp_path) -> None:
    """A checkpoint that cannot be written (a full disk) warned in Python's format, naming
    ``_executors.py:548`` and quoting ``return simulate(`` (a robustness review). A local
    worker and the command line show brakeca's warnings as ``warning: MESSAGE``; other
    warnings keep Python's format, and the command's format is put back when it ends."""
    script = tmp_path / "warn.py"
    script.write_text(
        textwrap.dedent(
            """
            import warnings
            from brakeca._executors import _local_pool
            from brakeca.simulation import CheckpointWarning

            def warn():
                warnings.warn("cannot write the checkpoint", CheckpointWarning, stacklevel=2)
                warnings.warn("somebody else's", DeprecationWarning, stacklevel=2)

            if __name__ == "__main__":
                warnings.simplefilter("always")
                with _local_pool(1) as pool:
                    pool.submit(warn).result()
            """
        )
    )
    done = subprocess.run(
        [sys.executable, "-W", "always", str(script)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert "warning: cannot write the checkpoint" in lines, done.stderr
    assert not any("CheckpointWarning" in line for line in lines), done.stderr
    assert any("DeprecationWarning: somebody else's" in line for line in lines), done.stderr

    import warnings

    from brakeca._console import brief_warnings

    before = warnings.formatwarning
    restore = brief_warnings()
    try:
        from brakeca.simulation import CheckpointWarning

        text = warnings.formatwarning("full disk", CheckpointWarning, "x.py", 1, "line")
        assert text == "warning: full disk\n"
        other = warnings.formatwarning("old", DeprecationWarning, "x.py", 1, "line")
        assert other == before("old", DeprecationWarning, "x.py", 1, "line")
    finally:
        restore()
    assert warnings.formatwarning is before
    # the command line sets it for its command and puts Python's back when it ends
    from typer.testing import CliRunner

    from brakeca.cli import app

    seen = []
    import brakeca.cli

    real = brakeca.cli.resolve_config

    def spy(*args, **kwargs):  # runs inside the command
        seen.append(warnings.formatwarning("x", CheckpointWarning, "f.py", 1))
        return real(*args, **kwargs)

    brakeca.cli.resolve_config = spy
    try:
        assert CliRunner().invoke(app, ["config"]).exit_code == 0
    finally:
        brakeca.cli.resolve_config = real
    assert seen == ["warning: x\n"] and warnings.formatwarning is before


class _FakeWinapi:
    """The calls of ``_winapi`` that :func:`_wait_for_process_windows` makes, recorded."""

    SYNCHRONIZE = 0x00100000
    INFINITE = 0xFFFFFFFF

    def __init__(self, gone: bool = False) -> None:
        self.gone, self.calls = gone, []

    def OpenProcess(self, access, inherit, pid):  # (_winapi's names)
        self.calls.append(("open", access, inherit, pid))
        if self.gone:
            raise OSError(87, "The parameter is incorrect")
        return 42

    def WaitForSingleObject(self, handle, ms):
        self.calls.append(("wait", handle, ms))

    def CloseHandle(self, handle):
        self.calls.append(("close", handle))


def test_on_windows_a_worker_waits_on_its_parents_handle() -> None:
    """A portability review: on Windows ``os.getppid()`` still gives a parent's pid after the
    parent ended, so a killed campaign's workers ran on; they wait on its process handle
    there (a stand-in for ``_winapi`` here), and one that cannot be opened is gone."""
    from brakeca._executors import _wait_for_process_windows

    api = _FakeWinapi()
    _wait_for_process_windows(1234, winapi=api)
    assert api.calls == [
        ("open", api.SYNCHRONIZE, False, 1234),
        ("wait", 42, api.INFINITE),
        ("close", 42),
    ]
    gone = _FakeWinapi(gone=True)
    _wait_for_process_windows(1234, winapi=gone)  # returns at once
    assert gone.calls == [("open", gone.SYNCHRONIZE, False, 1234)]


def test_on_windows_the_watch_ends_the_worker_when_the_wait_returns(tmp_path) -> None:
    """The watching thread takes the Windows way there (sys.platform set to win32 in a
    child, the wait a stand-in that returns once a file appears): cleanup, then exit 1."""
    parent_gone, marker = tmp_path / "parent_gone", tmp_path / "cleaned"
    waiting = tmp_path / "waiting"
    code = textwrap.dedent(
        f"""
        import sys, time
        from pathlib import Path
        import brakeca._executors as ex
        def wait(pid):
            assert pid == 12345, pid
            Path({str(waiting)!r}).touch()
            while not Path({str(parent_gone)!r}).exists():
                time.sleep(0.05)
        ex._wait_for_process_windows = wait
        sys.platform = "win32"
        ex._exit_with_parent(12345, cleanup=lambda: Path({str(marker)!r}).touch())
        time.sleep(60)
        """
    )
    child = subprocess.Popen([sys.executable, "-c", code])
    try:
        deadline = time.monotonic() + 60
        while not waiting.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert waiting.exists()  # (the POSIX loop would have ended at once: no such parent)
        time.sleep(0.3)
        assert child.poll() is None and not marker.exists()  # waiting on the parent
        parent_gone.touch()
        assert child.wait(timeout=30) == 1
    finally:
        child.kill()
    assert marker.exists()


def test_on_windows_no_resource_tracker_is_started(monkeypatch) -> None:
    """Windows has no resource tracker (starting it failed: No module named
    '_posixsubprocess', every local campaign with it: a portability review)."""
    from multiprocessing import resource_tracker

    import brakeca._executors as ex

    def refuse() -> None:
        raise AssertionError("the tracker was started")

    monkeypatch.setattr(resource_tracker, "ensure_running", refuse)
    ex._tracker_outlives_a_hangup(posix=False)  # nothing started
    with pytest.raises(AssertionError, match="the tracker was started"):
        ex._tracker_outlives_a_hangup(posix=True)
