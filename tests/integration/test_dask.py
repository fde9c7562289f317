"""Campaigns on a real Dask cluster (scheduler and worker processes on loopback), worker deaths
and retries, for the dask and the local executor; the dask options of ``brakeca run``.

A 2 x 2 design (S x A) over a 5 x 100 cell band and 2 stops, as in test_campaign.py. Workers
are killed by a ``simulate_fn`` that SIGKILLs its own process; marker files in ``tmp_path``
count the attempts of each run across processes.
"""

from __future__ import annotations

import contextlib
import functools
import io
import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from campaign_helpers import (
    DESIGN_TEMPLATE,
    assert_same_runs,
    console_text,
    deterministic,
    drawing,
    ignores_sigint,
    must_not_run,
    quiet,
    run_dataset,
    started_as_a_job,
    tiny,
    write_design,
)
from rich.console import Console
from typer.testing import CliRunner

from brakeca.campaign import (
    CampaignResult,
    DaskExecutor,
    ExecutorError,
    load_campaign,
    make_executor,
    run_campaign,
)
from brakeca.cli import app
from brakeca.contact import ContactError
from brakeca.results import RunResult
from brakeca.simulation import simulate

distributed = pytest.importorskip("distributed")
dask = pytest.importorskip("dask")
psutil = pytest.importorskip("psutil")

TINY = tiny(2)
DESIGN = drawing(DESIGN_TEMPLATE.format(root_seed=23))


def _children() -> set[int]:
    """Process ids of this process's descendants (multiprocessing's tracker aside)."""
    pids = set()
    for proc in psutil.Process().children(recursive=True):
        try:
            if not any("resource_tracker" in part for part in proc.cmdline()):
                pids.add(proc.pid)
        except psutil.NoSuchProcess:
            pass
    return pids


def _assert_no_new_children(before: set[int]) -> None:
    """Wait up to 20 s for the processes started since ``before`` to end; fail if any lives."""
    new = []
    for pid in _children() - before:
        try:
            new.append(psutil.Process(pid))
        except psutil.NoSuchProcess:
            pass
    _, alive = psutil.wait_procs(new, timeout=20)
    assert not alive, [p.cmdline() for p in alive]


# top-level (picklable) simulate functions; bind marker_dir with functools.partial -------------


def _is_test(config, test: int) -> bool:
    """Whether ``config`` is test 1 (S -, A -), 2 (S +, A -), 3 (S -, A +) or 4 (S +, A +)."""
    s_high = config.automaton.secondary_removal_fraction == 1.0
    a_high = config.pad.fibre_area_fraction > 0.15
    return (int(s_high) + 2 * int(a_high) + 1) == test


def _count_attempt(marker_dir: Path, seed: int) -> int:
    """Append one line to the run's attempt file; return the attempts so far."""
    path = Path(marker_dir) / f"{seed}.attempts"
    with path.open("a", encoding="utf-8") as f:
        f.write(f"{os.getpid()}\n")
    return len(path.read_text(encoding="utf-8").splitlines())


def _attempts(marker_dir: Path, seed: int) -> int:
    path = Path(marker_dir) / f"{seed}.attempts"
    return len(path.read_text(encoding="utf-8").splitlines()) if path.exists() else 0


def chaos(config, *, seed, marker_dir, progress=None):
    """The real simulate, except that test 2 SIGKILLs its worker process the first time it
    runs, test 3 raises a model error every time, and test 4 SIGKILLs its worker every time."""
    if _is_test(config, 2) or _is_test(config, 3) or _is_test(config, 4):
        attempt = _count_attempt(marker_dir, seed)
        if _is_test(config, 3):
            raise ContactError("injected: no plateau can touch the disc")
        if _is_test(config, 4) or attempt == 1:
            os.kill(os.getpid(), signal.SIGKILL)
    return simulate(config, seed=seed, progress=progress)


def slow(config, *, seed, progress=None):
    """The real simulate, two seconds late (the runs are still out when the test acts)."""
    time.sleep(2.0)
    return simulate(config, seed=seed, progress=progress)


def raises_on_test_3(config, *, seed, progress=None):
    """The real simulate, except that test 3 raises a model error."""
    if _is_test(config, 3):
        raise ContactError("injected: no plateau can touch the disc")
    return simulate(config, seed=seed, progress=progress)


# fixtures ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def design_file(tmp_path_factory) -> Path:
    return write_design(tmp_path_factory.mktemp("design"), TINY, DESIGN)


@pytest.fixture(scope="module")
def local(design_file, tmp_path_factory) -> CampaignResult:
    """The reference: the default local executor, two worker processes."""
    out = tmp_path_factory.mktemp("local") / "campaign"
    result = run_campaign(
        design_file, out, executor="local", workers=2, progress=False, console=quiet()
    )
    assert result.ok and len(result.computed) == 4
    return result


@pytest.fixture(scope="module")
def cluster():
    """An existing cluster: scheduler and two one-thread worker processes on 127.0.0.1;
    the scheduler gives a task whose worker died one more try."""
    settings = {
        "distributed.scheduler.allowed-failures": 1,
        "distributed.scheduler.worker-saturation": 1.0,
    }
    with dask.config.set(settings), _loopback_cluster(2) as cluster:
        yield cluster


def _loopback_cluster(n_workers: int) -> Any:
    """A LocalCluster of ``n_workers`` one-thread worker processes on 127.0.0.1, its
    scheduler's HTTP server on a free loopback port (no dashboard)."""
    return distributed.LocalCluster(
        n_workers=n_workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
        scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
    )


# dask --------------------------------------------------------------------------------------


def test_dask_local_cluster_is_bit_identical_to_local_and_closed(local, design_file, tmp_path):
    before = _children()
    result = run_campaign(
        design_file,
        tmp_path / "dask",
        executor="dask",
        workers=2,
        progress=False,
        console=quiet(),
    )
    assert result.ok and len(result.computed) == 4 and not result.failed
    assert_same_runs(result, local)
    assert list(result.summary["MU"]) == list(local.summary["MU"])  # bit for bit
    assert list(result.summary["V"]) == list(local.summary["V"])
    loaded = load_campaign(tmp_path / "dask")
    pd.testing.assert_frame_equal(deterministic(loaded.summary), deterministic(result.summary))
    _assert_no_new_children(before)  # the cluster the campaign started is gone


def _check_chaos(result: CampaignResult, local: CampaignResult, markers: Path, text: str) -> None:
    """After a campaign with :func:`chaos` and ``max_retries=1``: tests 1 and 2 ok and equal
    to the reference, test 3 failed at once, test 4 failed after two deaths."""
    summary = result.summary
    seeds = [int(seed) for seed in summary["seed"]]
    assert list(summary["status"]) == ["ok", "ok", "failed", "failed"], text
    assert _attempts(markers, seeds[1]) >= 2  # killed once, then finished on a new worker
    assert summary.loc[2, "error"] == "ContactError: injected: no plateau can touch the disc"
    assert _attempts(markers, seeds[2]) == 1  # raised: never retried
    assert "worker process died 2 times" in summary.loc[3, "error"]
    assert _attempts(markers, seeds[3]) == 2  # 1 + max_retries
    assert np.isnan(summary.loc[2, "MU"]) and np.isnan(summary.loc[3, "MU"])
    ok = summary["status"] == "ok"
    pd.testing.assert_frame_equal(  # NaN rows make the integer columns float
        deterministic(summary[ok]),
        deterministic(local.summary[ok]),
        check_exact=True,
        check_dtype=False,
    )
    for rid in summary.loc[ok, "run_id"]:
        xr.testing.assert_identical(
            run_dataset(result.out_dir, rid), run_dataset(local.out_dir, rid)
        )
    for rid in summary.loc[~ok, "run_id"]:
        assert not (result.out_dir / "runs" / f"{rid}.nc").exists()
    assert sorted(result.failed) == sorted(summary.loc[~ok, "run_id"])
    assert not list(result.out_dir.rglob("*.tmp"))
    loaded = load_campaign(result.out_dir)
    assert list(loaded.summary["status"]) == ["ok", "ok", "failed", "failed"]
    assert list(loaded.summary["error"]) == list(summary["error"])


def test_dask_worker_deaths_cost_only_their_run(local, design_file, tmp_path, capfd):
    """A LocalCluster started by the campaign, workers SIGKILLed mid-campaign: max_retries is
    the scheduler's allowed-failures; a run that raises is failed at once; the rest finish.
    The deaths are the campaign's lines, not dask's raw log lines ("... - distributed.nanny -
    WARNING - Restarting worker", in the middle of the progress bar)."""
    import logging

    markers = tmp_path / "markers"
    markers.mkdir()
    console = quiet()
    result = run_campaign(
        design_file,
        tmp_path / "campaign",
        executor="dask",
        workers=2,
        max_retries=1,
        simulate_fn=functools.partial(chaos, marker_dir=markers),
        progress=False,
        console=console,
    )
    text = console_text(console)
    _check_chaos(result, local, markers, text)
    assert "KilledWorker" in result.summary.loc[3, "error"]
    # three kills (test 2 once, test 4 twice): each death told once, in the campaign's words
    # (the last may come after the campaign's end, when no nanny restarts a worker any more)
    told = sum(
        1 if m[1] == "a" else int(m[1])
        for m in re.finditer(r"worker died: (a|\d+) dask worker process", text)
    )
    assert 1 <= told <= 3, text
    assert "(a run at most 1 time(s), then it fails)" in text
    err = capfd.readouterr().err
    assert "Restarting worker" not in err and "caused the cluster to lose" not in err, err
    for name in ("distributed.nanny", "distributed.scheduler"):  # the filter is gone again
        assert not logging.getLogger(name).filters


class _Boom(io.StringIO):
    """A console file that breaks on the first message: an error inside the campaign loop."""

    def write(self, text: str) -> int:
        raise RuntimeError("console broke")


def test_dask_cluster_is_closed_when_the_campaign_fails(design_file, tmp_path):
    before = _children()
    with pytest.raises(RuntimeError, match="console broke"):
        run_campaign(
            design_file,
            tmp_path / "campaign",
            executor="dask",
            workers=1,
            simulate_fn=raises_on_test_3,
            progress=False,
            console=Console(file=_Boom(), width=200),
        )
    _assert_no_new_children(before)
    assert not list((tmp_path / "campaign").rglob("*.tmp"))


def test_unreachable_scheduler_is_reported(design_file, tmp_path):
    """A port where nothing listens is named at once (before, the Client waited for dask's
    30 s connect timeout and said only that it had timed out)."""
    with socket.socket() as probe:  # a free loopback port, closed again
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    with pytest.raises(
        ExecutorError,
        match=rf"scheduler at tcp://127.0.0.1:{port}: nothing listens at 127.0.0.1:{port} "
        r"\(connection refused\)",
    ):
        run_campaign(
            design_file,
            tmp_path / "campaign",
            executor="dask",
            scheduler=f"tcp://127.0.0.1:{port}",
            progress=False,
            console=quiet(),
        )


def test_a_scheduler_lost_mid_campaign_stops_it_with_a_clear_error(design_file, tmp_path):
    """A review: a campaign on an existing cluster whose scheduler died waited for good on
    runs that could not finish (dask's client had closed after 30 s of failed reconnects),
    and Ctrl-C then gave two tracebacks. It stops with an ExecutorError once the client
    closes (here after dask's connect timeout, set to 2 s), keeping what was done."""
    import threading

    before = _children()
    with (
        dask.config.set({"distributed.comm.timeouts.connect": "2s"}),
        _loopback_cluster(1) as cluster,
    ):
        address = cluster.scheduler_address
        threading.Timer(1.0, cluster.close).start()  # while the first run sleeps
        t0 = time.monotonic()
        with pytest.raises(ExecutorError) as info:
            run_campaign(
                design_file,
                tmp_path / "campaign",
                executor="dask",
                scheduler=address,
                simulate_fn=slow,
                progress=False,
                console=quiet(),
            )
    text = " ".join(str(info.value).split())
    assert f"the Dask client lost the scheduler at {address} and closed" in text
    assert "the same command resumes once a scheduler is there" in text
    assert time.monotonic() - t0 < 60
    assert not (tmp_path / "campaign" / "summary.csv").exists()  # no run counted as failed
    _assert_no_new_children(before)


def test_a_scheduler_that_crashes_mid_campaign_fails_no_run(design_file, tmp_path):
    """A diff review: when the scheduler dies outright, dask cancels the client's futures at
    once, while it tries to reconnect; those runs had been recorded as failed (and a
    campaign at its end finished with them). They go back to the queue; once the client
    gives up (dask's connect timeout, 2 s here) the campaign stops with an ExecutorError,
    no run counted as failed."""
    import threading

    info_file = tmp_path / "scheduler.json"
    # the processes unpickle slow() from this test module: they see this process's path
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    quietly = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "env": env}
    scheduler = subprocess.Popen(
        [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
         "--port", "0", "--dashboard-address", "127.0.0.1:0", "--scheduler-file",
         str(info_file)],
        **quietly,
    )  # fmt: skip
    worker = None
    try:
        deadline = time.monotonic() + 60
        while not info_file.exists():
            assert time.monotonic() < deadline and scheduler.poll() is None
            time.sleep(0.1)
        worker = subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker", "--scheduler-file",
             str(info_file), "--nthreads", "1", "--nworkers", "1", "--no-dashboard"],
            **quietly,
        )  # fmt: skip
        console = quiet()
        # SIGKILL the scheduler while the first run sleeps in slow()
        threading.Timer(6.0, scheduler.kill).start()
        with (
            dask.config.set({"distributed.comm.timeouts.connect": "2s"}),
            pytest.raises(ExecutorError, match="the Dask client lost the scheduler at"),
        ):
            run_campaign(
                design_file,
                tmp_path / "campaign",
                executor="dask",
                scheduler_file=info_file,
                simulate_fn=slow,
                progress=False,
                console=console,
            )
        assert "run failed" not in console.file.getvalue()
        assert not (tmp_path / "campaign" / "summary.csv").exists()
    finally:
        for proc in (scheduler, worker):
            if proc is not None and proc.poll() is None:
                proc.kill()
            if proc is not None:
                proc.wait(timeout=30)


def test_the_wait_for_workers_that_are_not_there_is_said_once() -> None:
    """A review: a campaign on a scheduler without workers printed nothing and looked hung;
    after a while without a worker it says once that the runs wait for them."""
    from types import SimpleNamespace

    from brakeca._executors import _DaskBackend

    client = SimpleNamespace(
        nthreads=dict, status="running", scheduler=SimpleNamespace(address="tcp://h:1")
    )
    backend = _DaskBackend(SimpleNamespace(client=client, deaths=None))
    backend.WAIT_NOTE_AFTER = 0.05
    # no worker known to import brakeca: no run is submitted (a diff review: one queued in
    # the scheduler went to a worker without brakeca the moment it registered)
    assert backend.free() == 0 and backend.waiting() is None  # the clock starts
    time.sleep(0.1)
    client.status = "connecting"  # (the link lost for a while: not said, nothing submitted)
    assert backend.waiting() is None and backend.free() == 0 and backend.lost() is None
    client.status = "running"
    assert backend.waiting() == (
        "the Dask scheduler at tcp://h:1 has no worker yet: the runs wait for workers to join "
        "(Ctrl-C stops; the same command resumes)"
    )
    assert backend.waiting() is None and backend.lost() is None  # said once
    # workers count once asked: one answers, one's link fails (asked again later, counted
    # for nothing meanwhile), one cannot import brakeca (refused, naming it)
    answers: dict = {"w": "0.1.0", "x": OSError("link")}
    client.run = lambda fn, workers, on_error: {a: answers[a] for a in workers}
    client.nthreads = lambda: {"w": 2, "x": 3}
    assert backend.free() == 2 and backend.waiting() is None
    answers["x"] = "0.1.0"
    assert backend.free() == 5 and backend.checked == {"w", "x"}
    answers["y"] = "import failed: RuntimeError: no folder for the kernels' cache"
    client.nthreads = lambda: {"w": 2, "x": 3, "y": 1}
    with pytest.raises(ExecutorError, match=r"^brakeca does not import on the Dask worker\(s\) "
                       r"at y \(RuntimeError: no folder for the kernels' cache\)"):  # fmt: skip
        backend.free()
    # a probe that cannot run there (another Python, say) refuses the worker too, where it
    # had been asked for ever (a diff review)
    answers["z"] = TypeError("code() argument 13 must be str")
    client.nthreads = lambda: {"w": 2, "x": 3, "z": 1}
    with pytest.raises(ExecutorError, match=r"at z \(TypeError: code\(\) argument 13"):
        backend.free()
    # a worker gone is forgotten: another at its address is asked again
    client.nthreads = lambda: {"w": 2}
    assert backend.free() == 2 and backend.checked == {"w"}
    answers["x"] = "import failed: ModuleNotFoundError: No module named 'brakeca'"
    client.nthreads = lambda: {"w": 2, "x": 3}
    with pytest.raises(ExecutorError, match=r"at x \(ModuleNotFoundError"):
        backend.free()
    answers["x"] = "0.1.0"
    client.nthreads = lambda: {"w": 2, "x": 3}
    # a future dask cancelled while the link was down is run again, not failed
    import concurrent.futures as cf

    cancelled: cf.Future = cf.Future()
    cancelled.cancel()
    assert not backend.interrupted(cancelled)  # connected: a cancellation of its own
    client.status = "connecting"
    assert backend.interrupted(cancelled)
    client.status = "closed"
    assert backend.lost() == (
        "the Dask client lost the scheduler at tcp://h:1 and closed: no run can finish"
    )


def test_a_listener_that_is_no_scheduler_is_refused(cluster):
    """Something else at the address (here a socket that never answers, as the dashboard's
    HTTP port does not answer dask's handshake; and a worker) is named before a Client
    exists: a Client waited on such a listener without a bound (over ten minutes seen)."""
    with (
        socket.create_server(("127.0.0.1", 0)) as silent,
        dask.config.set({"distributed.comm.timeouts.connect": "1s"}),
        pytest.raises(ExecutorError, match=r"did not answer as a Dask scheduler within 1 s"),
    ):
        make_executor("dask", scheduler=f"tcp://127.0.0.1:{silent.getsockname()[1]}")
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        worker = next(iter(client.scheduler_info()["workers"]))
    with pytest.raises(ExecutorError, match=r"is not a Dask scheduler \(it is a Worker\)"):
        make_executor("dask", scheduler=worker)


def test_an_address_dask_cannot_use_is_refused_at_once(tmp_path):
    """A robustness review: 'garbage://x', or a scheduler file without an address, gave the
    error and then a 60 s hang and a traceback at exit (the half-made Client closing); so did
    a tls:// address without dask's TLS settings (a cluster review). All are refused before
    a Client exists, in a child interpreter that must end quickly."""
    (tmp_path / "empty.json").write_text("{}")
    for args, message in (
        ({"scheduler": "garbage://x"}, "unknown address scheme 'garbage'"),
        ({"scheduler_file": str(tmp_path / "empty.json")}, "holds no scheduler address"),
        ({"scheduler": "tls://127.0.0.1:8786"}, "a tls:// scheduler needs dask's TLS"),
    ):
        code = (
            "from brakeca._executors import make_executor, ExecutorError\n"
            "try:\n"
            f"    make_executor('dask', **{args!r})\n"
            "except ExecutorError as exc:\n"
            "    print(exc)\n"
        )
        t0 = time.monotonic()
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=60
        )
        assert message in out.stdout and "Exception ignored" not in out.stderr, out
        assert time.monotonic() - t0 < 30


def test_make_executor_dask_and_scheduler_arguments(tmp_path):
    with pytest.raises(ValueError, match="scheduler needs executor='dask'"):
        make_executor("local", scheduler="tcp://127.0.0.1:8786")
    with pytest.raises(ValueError, match="scheduler_file needs executor='dask'"):
        make_executor("serial", scheduler_file=tmp_path / "s.json")
    with pytest.raises(ValueError, match="not both"):
        make_executor("dask", scheduler="tcp://h:1", scheduler_file=tmp_path / "s.json")
    with pytest.raises(ValueError, match="does not exist"):
        make_executor("dask", scheduler_file=tmp_path / "missing.json")
    with pytest.raises(ValueError, match="max_retries"):
        make_executor("dask", max_retries=-1)
    with pytest.raises(ValueError, match="max_retries"):
        run_campaign("paper", tmp_path / "never", max_retries=-1, progress=False)
    with pytest.raises(ValueError, match="scheduler needs"):
        run_campaign("paper", tmp_path / "never", scheduler="tcp://h:1", progress=False)
    assert not (tmp_path / "never").exists()


def test_make_executor_dask_by_scheduler_file(cluster, tmp_path):
    path = tmp_path / "scheduler.json"
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        client.write_scheduler_file(str(path))
    with make_executor("dask", scheduler_file=path) as ex:
        assert isinstance(ex, DaskExecutor) and ex.cluster is None
        assert ex.address == cluster.scheduler_address
        assert ex.submit(os.getenv, "OMP_NUM_THREADS").result() == "1"
    assert ex.client.status == "closed"


def test_make_executor_dask_starts_and_closes_a_loopback_cluster():
    before = _children()
    with make_executor("dask", 1, max_retries=0) as ex:
        assert isinstance(ex, DaskExecutor) and ex.cluster is not None
        assert ex.address.startswith("tcp://127.0.0.1:")
        assert ex.submit(os.getenv, "NUMBA_NUM_THREADS").result() == "1"
        assert ex.submit(os.getenv, "OMP_NUM_THREADS").result() == "1"
        assert ex.submit(pow, 3, 2).result() == 9
        info = ex.client.scheduler_info()
        assert [w["nthreads"] for w in info["workers"].values()] == [1]
        assert ex.client.run_on_scheduler(_allowed_failures) == 0
    assert ex.client.status == "closed" and ex.cluster.status.name == "closed"
    _assert_no_new_children(before)


def test_an_unguarded_script_is_not_rerun_when_a_dask_worker_is_replaced(tmp_path):
    """A LocalCluster's nanny spawns a new worker when one dies, at any time while the
    cluster runs, not only when it starts: the main module (here a script without an
    ``if __name__ == "__main__":`` guard) must not run in that worker either. The
    executor's own state is left as it found it: ``__main__.__spec__`` is restored."""
    script = tmp_path / "study.py"
    script.write_text(
        "import os, signal, sys, time\n"
        "from brakeca.campaign import make_executor\n"
        "print('top level ran', flush=True)\n"
        "spec = sys.modules['__main__'].__spec__\n"
        "with make_executor('dask', 1, max_retries=0) as ex:\n"
        "    first = ex.submit(os.getpid).result()\n"
        "    os.kill(first, signal.SIGKILL)\n"
        "    deadline = time.monotonic() + 60\n"
        "    while True:\n"
        "        try:\n"
        "            second = ex.submit(os.getpid).result(timeout=10)\n"
        "        except Exception:\n"
        "            second = first\n"
        "        if second != first or time.monotonic() > deadline:\n"
        "            break\n"
        "        time.sleep(0.5)\n"
        "    print('replaced', second != first, flush=True)\n"
        "print('spec restored', sys.modules['__main__'].__spec__ is spec, flush=True)\n"
    )
    done = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["top level ran", "replaced True", "spec restored True"], (
        done.stdout + done.stderr
    )


def _allowed_failures(dask_scheduler) -> int:
    return dask_scheduler.allowed_failures


@pytest.mark.slow
@pytest.mark.timeout(1800)
def test_client_killed_on_dask_resumes_and_leaves_no_process(local, design_file, tmp_path):
    """SIGKILL a ``python -m brakeca.campaign --executor dask`` halfway: its cluster's
    processes go with it, the finished run files are complete, and a resume reuses them."""
    out = tmp_path / "campaign"
    cmd = [sys.executable, "-m", "brakeca.campaign", str(design_file), str(out)]
    cmd += ["--executor", "dask", "--workers", "2", "--no-progress"]
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    try:
        while not list((out / "runs").glob("*.nc")):
            assert proc.poll() is None, "the campaign ended before writing a run file"
            assert time.monotonic() < deadline, "no run file appeared within 120 s"
            time.sleep(0.01)
        orphans = psutil.Process(proc.pid).children(recursive=True)
        proc.send_signal(signal.SIGKILL)
    finally:
        if proc.poll() is None:  # a failed wait above: leave no campaign (and cluster) behind
            with contextlib.suppress(psutil.NoSuchProcess):
                for child in psutil.Process(proc.pid).children(recursive=True):
                    child.kill()
            proc.kill()
        proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    _, alive = psutil.wait_procs(orphans, timeout=30)
    assert not alive, [p.cmdline() for p in alive]
    assert not (out / "summary.csv").exists()
    finished = sorted(p.stem for p in (out / "runs").glob("*.nc"))
    for rid in finished:
        RunResult.from_netcdf(out / "runs" / f"{rid}.nc")  # complete files only
    resumed = run_campaign(design_file, out, executor="serial", progress=False, console=quiet())
    assert resumed.ok and sorted(resumed.reused) == finished
    assert len(resumed.computed) == 4 - len(finished)
    assert not list(out.rglob("*.tmp"))
    assert_same_runs(resumed, local)


# local executor ----------------------------------------------------------------------------


def test_local_worker_deaths_cost_only_their_run(local, design_file, tmp_path):
    """Worker processes SIGKILLed mid-campaign: the lost run is tried again (once here), a
    run that raises is failed at once; the next pass computes only the failed runs."""
    markers = tmp_path / "markers"
    markers.mkdir()
    console = quiet()
    result = run_campaign(
        design_file,
        tmp_path / "campaign",
        executor="local",
        workers=2,
        max_retries=1,
        simulate_fn=functools.partial(chaos, marker_dir=markers),
        progress=False,
        console=console,
    )
    text = console_text(console)
    _check_chaos(result, local, markers, text)
    assert _attempts(markers, int(result.summary.loc[1, "seed"])) == 2  # exactly
    assert "BrokenProcessPool" in result.summary.loc[3, "error"]
    assert text.count("worker died") == 2 and "trying again (1 of 1)" in text
    healed = run_campaign(  # with the real simulate, inline
        design_file, result.out_dir, executor="serial", progress=False, console=quiet()
    )
    assert healed.ok and sorted(healed.computed) == sorted(result.failed)
    assert len(healed.reused) == 2
    assert_same_runs(healed, local)


# command line ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--scheduler", "tcp://127.0.0.1:8786"], "--scheduler needs --executor dask"),
        (["--executor", "local", "--scheduler-file", "{file}"], "--scheduler-file needs"),
        (
            ["--executor", "dask", "--scheduler", "tcp://h:1", "--scheduler-file", "{file}"],
            "not both",
        ),
        (["--executor", "dask", "--scheduler", "tcp://h:1", "--workers", "2"], "--workers"),
        (["--executor", "cluster"], "--executor"),
        (  # taken without a word (a fuzz review)
            ["--executor", "serial", "--workers", "4"],
            "--workers does not apply to --executor serial",
        ),
    ],
)
def test_cli_rejects_bad_executor_options(design_file, tmp_path, args, message):
    scheduler_file = tmp_path / "scheduler.json"
    scheduler_file.write_text("{}", encoding="utf-8")
    args = [a.replace("{file}", str(scheduler_file)) for a in args]
    out = tmp_path / "never"
    res = CliRunner().invoke(app, ["run", str(design_file), "-o", str(out), *args])
    assert res.exit_code == 2, res.output
    assert message in " ".join(res.output.split())
    assert not out.exists()


def test_cli_max_retries_is_refused_for_an_existing_cluster(design_file, tmp_path):
    """A cluster review: --max-retries with --scheduler-file was ignored without a word (the
    existing scheduler's allowed-failures counts the tries), while --workers was refused."""
    for where in (["--scheduler", "tcp://127.0.0.1:8786"], ["--scheduler-file", __file__]):
        args = ["run", str(design_file), "-o", str(tmp_path / "c"), "--executor", "dask"]
        res = CliRunner().invoke(app, [*args, *where, "--max-retries", "1"])
        assert res.exit_code == 2, res.output
        assert "--max-retries does not apply to an existing Dask cluster" in res.output
        assert "ALLOWED_FAILURES" in res.output
    assert not (tmp_path / "c").exists()


def test_cli_max_retries_must_not_be_negative(design_file, tmp_path):
    res = CliRunner().invoke(
        app, ["run", str(design_file), "-o", str(tmp_path / "c"), "--max-retries", "-1"]
    )
    assert res.exit_code == 2 and "--max-retries" in res.output


def test_cli_runs_on_an_existing_cluster(cluster, local, design_file, tmp_path):
    out = tmp_path / "campaign"
    res = CliRunner().invoke(
        app,
        [
            "run",
            str(design_file),
            "-o",
            str(out),
            "--executor",
            "dask",
            "--scheduler",
            cluster.scheduler_address,
            "--no-report",
            "--maps-at",
            "2",  # passed to the cluster's workers with the run
        ],
    )
    assert res.exit_code == 0, res.output
    assert "4 run(s) computed" in res.output
    assert_same_runs(load_campaign(out), local, maps_at=[2])
    # the campaign did not close a cluster it did not start
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        assert client.submit(pow, 2, 5).result() == 32


def test_a_worker_where_brakeca_does_not_import_is_refused_before_any_run(
    cluster, design_file, tmp_path
):
    """A cluster review: a run sent to a worker without brakeca killed the worker (dask could
    not unpickle the run there), and the campaign then waited for workers ("no worker yet")
    that were gone. Each worker is asked first; here one (brakeca hidden by a preload script)
    joins the module's cluster of two, and the campaign stops, naming it, before any run."""
    hide = tmp_path / "hide_brakeca.py"
    hide.write_text('import sys\nsys.modules["brakeca"] = None\n', encoding="utf-8")
    out = tmp_path / "campaign"
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        own = set(client.nthreads())
        worker = subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker", cluster.scheduler_address,
             "--nthreads", "1", "--nworkers", "1", "--no-dashboard", "--host", "127.0.0.1",
             "--preload", str(hide)],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )  # fmt: skip
        try:
            client.wait_for_workers(len(own) + 1, timeout=60)
            (joined,) = set(client.nthreads()) - own
            with pytest.raises(ExecutorError) as err:
                run_campaign(
                    design_file,
                    out,
                    executor="dask",
                    scheduler=cluster.scheduler_address,
                    simulate_fn=must_not_run,
                    progress=False,
                    console=quiet(),
                )
        finally:
            worker.terminate()
            worker.wait(timeout=30)
    text = " ".join(str(err.value).split())
    assert f"brakeca does not import on the Dask worker(s) at {joined} (" in text
    assert "ModuleNotFoundError" in text and "docs/cluster.md" in text
    assert not list((out / "runs").glob("*.nc"))


def test_a_default_client_in_the_process_loses_no_run(cluster, local, design_file, tmp_path):
    """A cluster review: with a dask.distributed Client open as the process's default (a
    notebook, or the script docs/cluster.md shows with client.get_executor), xarray asked the
    scheduler for a lock named after the in-memory run file; every run was computed, then
    recorded as failed ("Semaphore or Lock ... not known"), and campaign.nc raised. The runs
    are written with a thread lock, whatever the default Client."""
    with distributed.Client(cluster.scheduler_address) as client:  # the default
        n = sum(client.nthreads().values())
        result = run_campaign(
            design_file,
            tmp_path / "campaign",
            executor=client.get_executor(pure=False),
            workers=n,
            progress=False,
            console=quiet(),
        )
        assert result.ok and len(result.computed) == 4, result.summary[["status", "error"]]
        assert_same_runs(result, local)
        served = run_campaign(
            design_file, tmp_path / "serial", executor="serial", progress=False, console=quiet()
        )
        assert served.ok and len(served.computed) == 4
    assert (tmp_path / "campaign" / "campaign.nc").is_file()
    assert_same_runs(load_campaign(tmp_path / "campaign"), local)


def test_a_worker_death_without_retries_is_said_once_and_consistently():
    """A cluster review, with --max-retries 0: dask's "Task ... marked as failed because 1
    workers died" line came through, and after the run's failure the campaign said dask
    "gives its run to a worker again". The line is dropped (the campaign names the failed
    run), and the death is said as it is."""
    import logging

    from brakeca._executors import WorkerDeaths
    from brakeca.campaign import _say_deaths

    deaths = WorkerDeaths()
    try:

        def kept(name: str, text: str) -> bool:
            record = logging.LogRecord(name, logging.ERROR, __file__, 1, text, None, None)
            return deaths.filter(record)

        died = "Task ('x', 0) marked as failed because 1 workers died while trying to run it"
        assert not kept("distributed.scheduler", died)
        assert kept("distributed.scheduler", "Task x marked as failed because it timed out")
        assert kept("distributed.worker", died)  # another logger's: not ours to drop
    finally:
        deaths.detach()
    for retries, said in (
        (0, "dask starts another, and its run is not tried again (no retries allowed)"),
        (2, "gives its run to a worker again (a run at most 2 time(s), then it fails)"),
    ):
        console = Console(file=io.StringIO(), width=200)
        _say_deaths(console, 1, retries)
        assert said in console.file.getvalue()  # type: ignore[attr-defined]


def test_ctrl_c_stops_a_local_cluster_at_once_and_quietly(design_file, tmp_path):
    """A cluster review: Ctrl-C (SIGINT to the process group, as a terminal sends it) on a
    campaign's own LocalCluster printed 4 s of dask warnings and KeyboardInterrupt tracebacks
    of its workers before the campaign's line. The workers now ignore Ctrl-C and the
    campaign kills them itself, with dask's loggers held back while the cluster closes."""
    started = tmp_path / "started"  # a file per run a worker has begun
    started.mkdir()
    script = tmp_path / "interrupted.py"
    script.write_text(
        "import signal, sys, time\n"
        # SIGINT as at a terminal, even where this test runs with it ignored
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "from brakeca.campaign import run_campaign\n"
        "def slow(config, *, seed, progress=None, maps_at=()):\n"
        f"    open({str(started)!r} + '/' + str(seed), 'w').close()\n"
        "    time.sleep(120)\n"
        "if __name__ == '__main__':\n"
        "    print('started', flush=True)\n"
        "    try:\n"
        f"        run_campaign({str(design_file)!r}, {str(tmp_path / 'c')!r}, executor='dask',\n"
        "                     workers=2, simulate_fn=slow, progress=False)\n"
        "    except KeyboardInterrupt:\n"
        "        print('interrupted', flush=True)\n"
    )
    with started_as_a_job([str(script)], "started") as proc:
        deadline = time.monotonic() + 120.0
        workers: list[psutil.Process] = []
        while time.monotonic() < deadline and len(workers) < 2:
            workers = [
                p
                for p in psutil.Process(proc.pid).children()
                if "spawn_main" in " ".join(p.cmdline()) and ignores_sigint(p.pid)
            ]
            time.sleep(0.2)
        assert len(workers) == 2, "the cluster's two workers should run, ignoring Ctrl-C"
        while time.monotonic() < deadline and len(list(started.iterdir())) < 2:
            time.sleep(0.1)  # the runs are sent to them (a tests review: not a 3 s sleep)
        assert len(list(started.iterdir())) == 2
        os.killpg(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=60)
        assert out.strip() == "interrupted", (out, err)
        assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
        assert "distributed." not in err, err
        _, alive = psutil.wait_procs(workers, timeout=10)
        assert not alive


def test_a_missing_dask_is_refused_before_the_folder_is_written(tmp_path, monkeypatch) -> None:
    """A packaging review: without the cluster extra, --executor dask said so only after the
    campaign had written its folder and warmed up the kernels."""
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *args: None if name == "distributed" else real(name, *args),
    )
    with pytest.raises(
        ExecutorError, match=r"pip install 'brakeca\[cluster\]' \(not installed: distributed\)$"
    ):
        run_campaign("paper", tmp_path / "out", executor="dask", quick=True, max_stops=1)
    assert not (tmp_path / "out").exists()
