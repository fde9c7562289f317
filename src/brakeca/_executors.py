"""Executors and backends of a campaign: where and how the runs are computed.

This module holds the executors of :func:`brakeca.campaign.make_executor` (``serial``,
``local``, ``dask``), the worker task and its process initializer, and the backends that
keep a bounded number of runs in flight and replace a worker process that died. Workers only
compute and return :class:`~brakeca.results.RunResult` objects; no file is written here.
Its public names are re-exported by :mod:`brakeca.campaign`.
"""

from __future__ import annotations

import concurrent.futures as cf
import importlib.machinery
import logging
import multiprocessing
import numbers
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import AbstractContextManager, ExitStack, contextmanager, nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from brakeca._console import brief_warnings
from brakeca._runstore import _error_text
from brakeca.config import SimulationConfig
from brakeca.design import RunPoint

if TYPE_CHECKING:
    from brakeca.results import RunResult

ExecutorKind = Literal["serial", "local", "dask"]
SimulateFn = Callable[..., "RunResult"]

#: The executor kinds of :func:`make_executor` and :func:`run_campaign`.
EXECUTOR_KINDS: tuple[str, ...] = ("serial", "local", "dask")

#: Default number of times a run whose worker process died is tried again [-].
DEFAULT_MAX_RETRIES = 2
#: Stops between the checkpoints of a campaign's runs in progress.
DEFAULT_CHECKPOINT_EVERY = 10

#: Environment set in every worker: one thread each, the pool or cluster gives the parallelism.
WORKER_ENV: Mapping[str, str] = {
    "NUMBA_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
}


# --- executors -----------------------------------------------------------------------------


class ExecutorError(RuntimeError):
    """An executor cannot be started: dask is missing, or its scheduler cannot be reached;
    or a campaign's dask client lost its scheduler while the runs went on."""


class SerialExecutor(cf.Executor):
    """A :class:`concurrent.futures.Executor` that runs each call inline, in ``submit``.

    Exceptions of the call are stored in the returned future; ``KeyboardInterrupt`` and
    other ``BaseException`` subclasses propagate.
    """

    def __init__(self) -> None:
        self._shutdown = False

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> cf.Future:
        """Run ``fn(*args, **kwargs)`` now; return a finished future."""
        if self._shutdown:
            raise RuntimeError("cannot submit after shutdown")
        future: cf.Future = cf.Future()
        try:
            result = fn(*args, **kwargs)
        except Exception as exc:
            future.set_exception(exc)
        else:
            future.set_result(result)
        return future

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Refuse further submissions (nothing runs in the background)."""
        self._shutdown = True


class DaskExecutor(cf.Executor):
    """A :class:`concurrent.futures.Executor` that sends each call to a Dask cluster.

    Calls are submitted with ``pure=False`` (every submission runs); their results come back
    to this process, which is the only one that writes files. :meth:`shutdown` closes the
    client and, when this executor started it, the :class:`distributed.LocalCluster`.

    Parameters
    ----------
    client : distributed.Client
        A connected client.
    cluster : distributed.LocalCluster, optional
        A cluster started for this executor, closed with it.
    own_client
        Close ``client`` on shutdown (True for a client made by :func:`make_executor`).
    held
        A context entered for the cluster's lifetime, exited on shutdown after the cluster
        closes (:func:`main_module_not_rerun` for a LocalCluster, whose nannies also spawn a
        worker that replaces a dead one).
    deaths
        For a LocalCluster started here: the filter that counts its worker processes' deaths
        in place of dask's log lines (:class:`WorkerDeaths`); removed on shutdown.
    """

    def __init__(
        self,
        client: Any,
        cluster: Any = None,
        *,
        own_client: bool = True,
        held: AbstractContextManager[Any] | None = None,
        deaths: WorkerDeaths | None = None,
    ) -> None:
        self.client = client
        self.cluster = cluster
        self._own_client = own_client
        self._held = held
        self.deaths = deaths
        self._executor = client.get_executor(pure=False)
        self._closed = False

    @property
    def address(self) -> str:
        """The scheduler's address."""
        return str(self.client.scheduler.address)

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> cf.Future:
        """Send ``fn(*args, **kwargs)`` to the cluster; return a concurrent.futures future."""
        return self._executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Wait for (or cancel) the submitted calls, then close the client and own cluster.

        With ``cancel_futures`` (Ctrl-C), the own cluster's worker processes are killed first
        and dask's log lines are held back while it closes: a worker in a compiled stop does
        not answer its nanny, which waited 4 s, and dask logged a page of warnings and
        tracebacks meanwhile (a cluster review). A run in progress keeps its checkpoint, as
        with the local executor."""
        if self._closed:
            return
        self._closed = True
        quiet = ExitStack()
        try:
            if cancel_futures and self.cluster is not None:
                quiet.enter_context(_dask_logs_held())
                self._kill_workers()
            self._executor.shutdown(wait=wait and not cancel_futures)
        finally:
            try:
                if self._own_client:
                    self.client.close()
            finally:
                try:
                    if self.cluster is not None:
                        self.cluster.close()
                finally:
                    if self.deaths is not None:
                        self.deaths.detach()
                    if self._held is not None:
                        self._held.__exit__(None, None, None)
                    quiet.close()

    def _kill_workers(self) -> None:
        """Kill the own cluster's worker processes now, each nanny told first not to start
        another (its close then finds the process gone)."""
        for nanny in list((getattr(self.cluster, "workers", None) or {}).values()):
            try:
                nanny.close_gracefully(reason="brakeca: the campaign was interrupted")
                pid = nanny.pid
                if pid:  # (Windows has no SIGKILL: any other signal there terminates)
                    os.kill(pid, getattr(signal, "SIGKILL", signal.SIGTERM))
            except Exception:  # a nanny without a process, or one that is gone: closed below
                pass


@contextmanager
def _dask_logs_held() -> Iterator[None]:
    """While in this block, dask's loggers in this process say nothing (a cluster being shut
    down on Ctrl-C: its workers' deaths, the cancelled tasks and comms are expected)."""
    names = ("distributed", "distributed.client", "distributed.nanny", "distributed.scheduler")
    saved = {name: logging.getLogger(name).level for name in names}
    for name in names:
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for name, level in saved.items():
            logging.getLogger(name).setLevel(level)


class WorkerDeaths(logging.Filter):
    """Counts the deaths of a LocalCluster's worker processes in place of dask's log lines.

    When a worker process dies, dask's nanny logs "Restarting worker" and the scheduler
    "Removing worker 'tcp://...' caused the cluster to lose already computed task(s), which
    will be recomputed elsewhere: {...}", with a time stamp and a logger name, on the
    campaign's terminal and in the middle of its progress bar. Both loggers live in the
    campaign's process for a cluster it started; this filter drops those two lines and counts
    the deaths, which the campaign reports in its own words (:meth:`_DaskBackend.news`).
    It also drops the scheduler's "Task ... marked as failed because N workers died while
    trying to run it": the campaign names that run as failed, with dask's reason. Every
    other line of dask's passes."""

    #: The loggers it filters.
    LOGGERS = ("distributed.nanny", "distributed.scheduler")

    def __init__(self) -> None:
        super().__init__()
        self.count = 0  # (written by the cluster's event-loop thread, read by the campaign's)
        for name in self.LOGGERS:
            logging.getLogger(name).addFilter(self)

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        if record.name == "distributed.nanny" and text.startswith("Restarting worker"):
            self.count += 1
            return False
        if record.name != "distributed.scheduler":
            return True
        lost = text.startswith("Removing worker") and "caused the cluster to lose" in text
        failed = text.startswith("Task ") and "marked as failed because" in text
        return not (lost or (failed and "workers died" in text))

    def detach(self) -> None:
        """Stop filtering."""
        for name in self.LOGGERS:
            logging.getLogger(name).removeFilter(self)


#: How often a local worker checks that the campaign's process still lives [s].
PARENT_CHECK_EVERY = 1.0


def _exit_with_parent(
    parent: int, every: float = PARENT_CHECK_EVERY, cleanup: Callable[[], object] | None = None
) -> None:
    """Watch, in a daemon thread, for the process ``parent`` to end, and end this process then.

    A local worker whose campaign was killed (SIGKILL, a closed terminal) would otherwise run
    on as an orphan, its result going nowhere. The run's checkpoint is kept, so the next
    campaign resumes it from there. The thread runs only between the run's compiled calls
    (a compiled stop holds the interpreter's lock), so an orphan ends when its stop does.
    ``cleanup``, if given, is called first (the warm-up child removes its parent's temporary
    folder).

    ``parent`` is the pid the parent gave (not this process's ``os.getppid()`` at start):
    a worker that finished starting after its campaign was killed had taken init's pid for
    its parent's and watched it for ever, blocked writing its result into a pipe no one
    read (a robustness review); it now sees a parent other than the one given and ends."""

    def watch() -> None:
        if sys.platform == "win32":  # getppid() there gives a parent's pid after it ended
            _wait_for_process_windows(parent)
        else:
            while os.getppid() == parent:
                time.sleep(every)
        try:
            if cleanup is not None:
                cleanup()
        finally:
            os._exit(1)

    threading.Thread(target=watch, name="brakeca-parent-watch", daemon=True).start()


def _wait_for_process_windows(pid: int, winapi: Any = None) -> None:
    """Return when the process ``pid`` has ended, at once if it has already (or cannot be
    opened). On Windows ``os.getppid()`` still gives a parent's pid after the parent ended
    (Python's docs), so :func:`_exit_with_parent`'s loop never ended there and a killed
    campaign's workers computed on (a portability review); this waits on the process's
    handle instead: multiprocessing's own, opened as the child started, for a pool's
    worker (a pid opened later may be another process's by then), else one opened by pid
    (the warm-up's child). ``winapi``: the ``_winapi`` module (a stand-in in the tests)."""
    parent = multiprocessing.parent_process()
    if winapi is None and parent is not None and parent.pid == pid:
        from multiprocessing.connection import wait

        wait([parent.sentinel])
        return
    if winapi is None:
        import _winapi as winapi  # (Windows only)
    try:
        handle = winapi.OpenProcess(winapi.SYNCHRONIZE, False, pid)
    except OSError:  # gone already (or not this user's): nothing to wait for
        return
    try:
        winapi.WaitForSingleObject(handle, winapi.INFINITE)
    finally:
        winapi.CloseHandle(handle)


def _init_worker(parent: int) -> None:
    """Process-pool initializer: one numba / OpenMP / BLAS thread per worker, Ctrl-C left to
    the campaign's process, and an end with it (``parent``, its pid:
    :func:`_exit_with_parent`).

    Ctrl-C in a terminal reaches every process of its group: a worker waiting for its next
    run printed a KeyboardInterrupt traceback, though the campaign's process stops its
    workers itself (:func:`_stop_pool`, which terminates them; a run in progress keeps its
    checkpoint) and says what is kept."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    brief_warnings()  # a checkpoint that cannot be written: one line, as the command's own
    os.environ.update(WORKER_ENV)
    numba = sys.modules.get("numba")
    if numba is not None:  # imported before the initializer ran (e.g. by the main module)
        try:
            numba.set_num_threads(1)
        except Exception:  # a numba without a threading layer: nothing to limit
            pass
    _exit_with_parent(parent)


@contextmanager
def terminate_as_interrupt() -> Iterator[None]:
    """While in this block, SIGTERM and SIGHUP raise KeyboardInterrupt in the main thread, as
    Ctrl-C does: a campaign or a run then stops its workers and keeps what it has (its run
    files and checkpoints) instead of ending at once with its workers left running. A
    handler the program set itself is left alone; outside the main thread this does nothing.

    A KeyboardInterrupt Python drops, raised by one of those signals or Ctrl-C while it
    runs a finalizer or a weak reference's callback ("Exception ignored in ..."), is
    remembered until the block ends (a campaign had run every run to the end and an
    analysis finished, exit status 0, as if no Ctrl-C had come; a command-line review):
    :func:`raise_if_interrupted`, called between runs, between figures and as the block
    ends, raises it again.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame: Any) -> None:
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise KeyboardInterrupt(signal.Signals(signum).name)

    saved = {}
    for name in ("SIGTERM", "SIGHUP"):
        number = getattr(signal, name, None)
        if number is not None and signal.getsignal(number) == signal.SIG_DFL:
            saved[number] = signal.signal(number, interrupt)
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        saved[signal.SIGINT] = signal.signal(signal.SIGINT, interrupt)
    hook = None
    if saved:  # the outermost block: no interrupt of an earlier one is carried into it
        _INTERRUPTS.clear()
        hook = sys.unraisablehook

        def remember(unraisable: Any) -> None:
            """Python drops a KeyboardInterrupt raised where it cannot propagate (a
            finalizer, a weak reference's callback) and hands it here: remember it (only
            the lost ones: one that propagated, even if code in the block caught it, is not
            raised again; a diff review)."""
            exc = unraisable.exc_value
            if isinstance(exc, KeyboardInterrupt):
                name = exc.args[0] if len(exc.args) == 1 else "SIGINT"
                _INTERRUPTS.append(getattr(signal, str(name), signal.SIGINT))
            hook(unraisable)

        sys.unraisablehook = remember
    try:
        yield
        if saved:  # one lost after the last check (a diff review: the last run's
            raise_if_interrupted()  # finalizers; the command had ended with status 0)
    finally:
        for number, handler in saved.items():
            signal.signal(number, handler)
        if hook is not None:
            sys.unraisablehook = hook
            _INTERRUPTS.clear()


#: The signals whose KeyboardInterrupt Python dropped in a :func:`terminate_as_interrupt`
#: block (its ``sys.unraisablehook``), by number [-].
_INTERRUPTS: list[int] = []


def raise_if_interrupted() -> None:
    """Raise KeyboardInterrupt where a signal came in a :func:`terminate_as_interrupt` block
    and its KeyboardInterrupt was lost (raised in a finalizer or a weak reference's callback,
    which Python only prints); nothing otherwise, and outside such a block."""
    if _INTERRUPTS:
        signum = _INTERRUPTS[-1]
        _INTERRUPTS.clear()
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise KeyboardInterrupt(signal.Signals(signum).name)


def _tracker_outlives_a_hangup(posix: bool | None = None) -> None:
    """Start multiprocessing's resource tracker, if it does not run yet, with SIGHUP ignored.

    A closed terminal sends SIGHUP to the whole process group: the tracker (which ignores
    only SIGINT and SIGTERM) died with it, and the campaign, stopping its workers as for
    Ctrl-C, printed "resource_tracker: process died unexpectedly" and a KeyError traceback
    for every semaphore of its pools (a cluster review). It ends as usual when this process
    does. Outside the main thread, where signals cannot be set, it starts as it would
    anyway, taking SIGHUP as usual. Only on POSIX systems, where the tracker runs (on Windows,
    where it does not, starting it failed: ``No module named '_posixsubprocess'``, every
    campaign of the default executor with it: a portability review); ``posix``: by default
    whether it runs on one."""
    if not (os.name == "posix" if posix is None else posix):
        return
    from multiprocessing import resource_tracker

    with _ignoring("SIGHUP"):
        resource_tracker.ensure_running()


@contextmanager
def _ignoring(name: str) -> Iterator[None]:
    """While in this block, the signal ``name`` (``"SIGINT"``, ``"SIGHUP"``) is ignored in
    this process, and so in the processes started in it, which inherit an ignored signal
    (Python leaves an ignored SIGINT ignored too); only in the main thread, where signals
    can be set, and where the platform has the signal."""
    number = getattr(signal, name, None)
    if number is None or threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = signal.signal(number, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(number, saved)


def _stop_pool(pool: cf.ProcessPoolExecutor) -> None:
    """Shut ``pool`` down now: its worker processes are terminated (a run in progress keeps
    its checkpoint) and its queued runs cancelled. A plain ``shutdown(wait=False)`` would not
    do: the interpreter waits at exit for the runs in progress, whose results are lost."""
    terminate = getattr(pool, "terminate_workers", None)  # Python 3.14
    if terminate is not None:
        terminate()
    else:
        for process in list((getattr(pool, "_processes", None) or {}).values()):
            if process.is_alive():
                process.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


@contextmanager
def main_module_not_rerun() -> Iterator[None]:
    """While in this block, processes started by "spawn" do not run this process's main module.

    A spawned process runs the parent's main script first, as ``__mp_main__``, so that
    functions defined there can be unpickled in it; a script that calls ``run_campaign``
    without an ``if __name__ == "__main__":`` guard then starts a campaign in every worker
    (and every one fails on the campaign's lock). brakeca's worker task needs nothing from the
    main module, so its workers are started while the main module's spec names
    ``"__main__"``, which ``multiprocessing.spawn.prepare`` leaves alone, as it does for
    ``python -m package``. It also keeps the command line's modules out of the workers.
    """
    main = sys.modules.get("__main__")
    if main is None:
        yield
        return
    missing = object()
    saved = main.__dict__.get("__spec__", missing)
    main.__spec__ = importlib.machinery.ModuleSpec("__main__", None)
    try:
        yield
    finally:
        if saved is missing:
            del main.__spec__
        else:
            main.__spec__ = saved


def _local_pool(workers: int) -> cf.ProcessPoolExecutor:
    """A process pool on the ``"spawn"`` start method, one numba/OpenMP thread per worker."""
    return cf.ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_init_worker,
        initargs=(os.getpid(),),
    )


def check_dask_installed() -> None:
    """Refuse the dask executor where dask.distributed is not installed, from the package
    index alone (importing it takes seconds): a campaign checks it before it writes
    anything or compiles (it had written its folder and warmed up first: a packaging
    review).

    Raises
    ------
    ExecutorError
        dask or dask.distributed is not installed.
    """
    import importlib.util

    missing = [name for name in ("dask", "distributed") if importlib.util.find_spec(name) is None]
    if missing:
        raise ExecutorError(
            "the dask executor needs dask.distributed: pip install 'brakeca[cluster]' "
            f"(not installed: {', '.join(missing)})"
        )


def _dask_executor(
    workers: int | None,
    scheduler: str | None,
    scheduler_file: str | Path | None,
    max_retries: int | None,
) -> DaskExecutor:
    """Connect to a Dask scheduler, or start a LocalCluster on loopback (see make_executor)."""
    check_dask_installed()
    try:
        import dask
        import distributed
    except ImportError as exc:
        raise ExecutorError(
            "the dask executor needs dask.distributed: pip install 'brakeca[cluster]' "
            f"({type(exc).__name__}: {exc})"
        ) from None
    if scheduler is not None or scheduler_file is not None:
        where = scheduler if scheduler is not None else f"scheduler file {scheduler_file}"
        # an address dask cannot use is refused before a Client exists: a Client that fails
        # in its constructor spends 60 s closing itself when the interpreter exits
        problem = _scheduler_address_problem(scheduler, scheduler_file)
        if problem:
            raise ExecutorError(f"cannot connect to the Dask scheduler at {where}: {problem}")
        try:
            if scheduler is not None:
                client = distributed.Client(scheduler, set_as_default=False)
            else:
                client = distributed.Client(
                    scheduler_file=str(scheduler_file), set_as_default=False
                )
        except Exception as exc:
            raise ExecutorError(
                f"cannot connect to the Dask scheduler at {where}: {_error_text(exc)}"
            ) from None
        return DaskExecutor(client)
    n = (os.cpu_count() or 1) if workers is None else int(workers)
    # the scheduler's HTTP server (health, metrics; no dashboard) on any free loopback port,
    # not on dask's default 8787, which another cluster may hold
    scheduler_kwargs: dict[str, Any] = {"dashboard_address": "127.0.0.1:0"}
    if max_retries is not None:
        scheduler_kwargs["allowed_failures"] = int(max_retries)
    # a one-thread worker holds only the run it executes, so a dying worker takes no queued
    # run down with it (dask counts every run on a dead worker as suspicious)
    # main_module_not_rerun, held until the executor shuts down: the nannies spawn their
    # workers while the cluster starts, and a new one whenever a worker dies (a caller's
    # function reaches a dask worker by value, cloudpickled, not from the module)
    held = main_module_not_rerun()
    held.__enter__()
    deaths = WorkerDeaths()
    try:
        # Ctrl-C ignored while the workers start, so that they ignore it: they printed
        # KeyboardInterrupt tracebacks on Ctrl-C, though the campaign's process stops them
        # itself (DaskExecutor.shutdown; a cluster review). A worker a nanny starts later,
        # in place of a dead one, takes Ctrl-C as usual
        with (
            dask.config.set({"distributed.scheduler.worker-saturation": 1.0}),
            _ignoring("SIGINT"),
        ):
            cluster = distributed.LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
                scheduler_kwargs=scheduler_kwargs,
                env=dict(WORKER_ENV),
            )
        try:
            client = distributed.Client(cluster, set_as_default=False)
        except BaseException:
            cluster.close()
            raise
    except BaseException:
        deaths.detach()
        held.__exit__(None, None, None)
        raise
    return DaskExecutor(client, cluster, held=held, deaths=deaths)


def _scheduler_address_problem(scheduler: str | None, scheduler_file: str | Path | None) -> str:
    """Why dask could not use the scheduler address given, or named in the scheduler file
    (its JSON ``address``); empty when it could."""
    import json

    from distributed.comm.addressing import parse_address
    from distributed.comm.registry import get_backend

    address = scheduler
    if address is None and scheduler_file is not None:
        try:
            address = json.loads(Path(scheduler_file).read_text(encoding="utf-8"))["address"]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            return (
                f"the file holds no scheduler address (a JSON object with 'address', as 'dask "
                f"scheduler --scheduler-file' writes it; {type(exc).__name__}: {exc})"
            )
    try:
        scheme, location = parse_address(str(address))
        get_backend(scheme)
    except (ValueError, TypeError) as exc:
        return f"{type(exc).__name__}: {exc}"
    if scheme == "tls" and not _tls_configured():
        # a Client without TLS settings failed, then hung 60 s at exit (a cluster review)
        return (
            "a tls:// scheduler needs dask's TLS settings in this process: "
            "distributed.comm.tls.ca-file and distributed.comm.tls.client.cert (and .key) in "
            "dask's configuration (a YAML file in ~/.config/dask, or the environment "
            "variables DASK_DISTRIBUTED__COMM__TLS__CA_FILE and so on), which are not both set"
        )
    if scheme in ("tcp", "tls"):
        problem = _nothing_listens(location)
        if problem or scheme == "tls":  # a TLS handshake needs the cluster's security
            return problem
        return _not_a_scheduler(f"{scheme}://{location}")
    return ""


def _tls_configured() -> bool:
    """Whether dask's configuration gives a client a TLS context (a CA file and a
    certificate), as a tls:// address needs."""
    from distributed.security import Security

    try:
        return Security().get_connection_args("client").get("ssl_context") is not None
    except Exception:  # settings that do not load: let the Client say what is wrong
        return True


def _connect_timeout() -> float:
    """Dask's connect timeout, ``distributed.comm.timeouts.connect`` [s]."""
    import dask
    from dask.utils import parse_timedelta

    return float(parse_timedelta(dask.config.get("distributed.comm.timeouts.connect"), "s"))


def _not_a_scheduler(address: str) -> str:
    """Why what answers at ``address`` is not a Dask scheduler: no answer to dask's handshake,
    or to the identity request every scheduler answers, within dask's connect timeout (a
    Client waits on a silent or foreign listener, e.g. the dashboard's HTTP port, without a
    bound); empty when a scheduler answers. Run in a thread of its own, so that it also works
    where an event loop is running (a notebook)."""
    import asyncio
    import concurrent.futures

    from distributed.comm import connect

    timeout = _connect_timeout()

    async def identify() -> Any:
        comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
        try:
            await asyncio.wait_for(comm.write({"op": "identity", "reply": True}), timeout)
            return await asyncio.wait_for(comm.read(), timeout)
        finally:
            comm.abort()

    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        try:
            reply = pool.submit(asyncio.run, identify()).result()
        except TimeoutError:
            return (
                f"what listens at {address} did not answer as a Dask scheduler within "
                f"{timeout:g} s (the dashboard's port, or another program?)"
            )
        except Exception as exc:
            return f"what listens at {address} is not a Dask scheduler ({_error_text(exc)})"
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        kind = reply.get("type") if isinstance(reply, dict) else type(reply).__name__
        return f"what listens at {address} is not a Dask scheduler (it is a {kind})"
    return ""


def _nothing_listens(location: str) -> str:
    """Why no scheduler can be at ``host:port``: the host refuses the connection or does not
    answer within dask's connect timeout (a Client would wait that long, then fail, and
    spend a minute closing itself at exit); empty when something accepts it."""
    import socket

    from distributed.comm.addressing import parse_host_port

    try:
        host, port = parse_host_port(location)
    except ValueError as exc:
        return f"ValueError: {exc}"
    timeout = _connect_timeout()
    try:
        with socket.create_connection((host, port), timeout=timeout):
            return ""
    except ConnectionRefusedError:
        return f"nothing listens at {host}:{port} (connection refused): is the scheduler running?"
    except TimeoutError:
        return f"{host}:{port} did not answer within {timeout:g} s"
    except OSError as exc:
        return f"{type(exc).__name__}: {exc}"


def make_executor(
    kind: ExecutorKind = "local",
    workers: int | None = None,
    *,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    max_retries: int | None = None,
) -> cf.Executor:
    """Create an executor for :func:`run_campaign`.

    Parameters
    ----------
    kind
        ``"serial"``: every run inline in this process (:class:`SerialExecutor`).
        ``"local"``: a :class:`~concurrent.futures.ProcessPoolExecutor` on the ``"spawn"``
        start method, each worker limited to one numba/OpenMP thread.
        ``"dask"``: a :class:`DaskExecutor`: a client of the scheduler at ``scheduler`` (or
        named in ``scheduler_file``), or, with neither, of a new
        :class:`distributed.LocalCluster` of ``workers`` one-thread worker processes bound to
        127.0.0.1, without dashboard, whose workers get :data:`WORKER_ENV`.
    workers
        Worker processes for ``"local"`` and a new LocalCluster [-]; None: ``os.cpu_count()``.
    scheduler
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"`` (``"dask"`` only).
    scheduler_file
        JSON file written by ``dask scheduler --scheduler-file`` (``"dask"`` only).
    max_retries
        For a new LocalCluster: how many times the scheduler re-runs a task whose worker died
        (``distributed.scheduler.allowed-failures``) [-]; None: dask's setting. An existing
        cluster keeps its scheduler's setting.

    Returns
    -------
    concurrent.futures.Executor
        The caller shuts it down (use it as a context manager); a :class:`DaskExecutor`
        then closes its client and the cluster it started.

    Raises
    ------
    ValueError
        Unknown kind, a worker count below 1, or a scheduler given to another kind.
    ExecutorError
        ``"dask"``: dask.distributed is not installed, or the scheduler cannot be reached.
    """
    if kind not in EXECUTOR_KINDS:
        raise ValueError(f"unknown executor {kind!r}; choose 'serial', 'local' or 'dask'")
    _check_scheduler(kind, scheduler, scheduler_file)
    _check_count("workers", workers, 1)
    _check_count("max_retries", max_retries, 0)
    if kind == "serial":
        return SerialExecutor()
    if kind == "local":
        return _local_pool((os.cpu_count() or 1) if workers is None else int(workers))
    return _dask_executor(workers, scheduler, scheduler_file, max_retries)


def _check_scheduler(
    kind: ExecutorKind | cf.Executor, scheduler: str | None, scheduler_file: str | Path | None
) -> None:
    """Raise ValueError unless a scheduler (address or file) goes with the dask kind."""
    if scheduler is None and scheduler_file is None:
        return
    if kind != "dask":
        name = "scheduler" if scheduler is not None else "scheduler_file"
        raise ValueError(f"{name} needs executor='dask', not {kind!r}")
    if scheduler is not None and scheduler_file is not None:
        raise ValueError("give scheduler or scheduler_file, not both")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise ValueError(f"scheduler must be an address such as tcp://HOST:PORT, got {scheduler!r}")
    if scheduler_file is not None and not Path(scheduler_file).is_file():
        raise ValueError(
            f"scheduler_file {str(scheduler_file)!r} does not exist; start the scheduler with "
            "'dask scheduler --scheduler-file FILE' first"
        )


def _check_count(name: str, value: object, least: int) -> None:
    """Raise ValueError, naming ``name``, unless ``value`` is None or a whole number of at
    least ``least`` (workers=2.5 was taken as 2, and "a" got int()'s message: a fuzz
    review)."""
    if value is not None and (
        isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least
    ):
        raise ValueError(f"{name}: expected a whole number at least {least}, got {value!r}")


def _execute(
    simulate_fn: SimulateFn | None,
    config: SimulationConfig,
    seed: int,
    checkpoint: Path | None = None,
    checkpoint_every: int = 10,
    maps_at: tuple[int, ...] = (),
) -> RunResult:
    """Worker task: run one simulation and return its result.

    With the default simulate and a ``checkpoint`` path, the run saves its state there every
    ``checkpoint_every`` stops and resumes from it if it exists (the only file a worker
    writes). The worker leaves it when the run completes: the campaign removes it once the
    run file is written, so a campaign killed before that resumes the run from it. A
    checkpoint that cannot be used (another version's format, unreadable, or one that ran a
    stop of ``maps_at`` without keeping its map) is deleted and the run starts over. A worker
    that does not see the campaign folder (a cluster without a shared file system) runs
    without one. ``maps_at``: the stops after which the run keeps its maps
    (:func:`brakeca.simulation.simulate`); passed to a ``simulate_fn`` only when not empty."""
    if simulate_fn is None:
        from brakeca._warmup import announcing
        from brakeca.simulation import CheckpointError, simulate

        def run() -> RunResult:
            return simulate(
                config,
                seed=seed,
                checkpoint=checkpoint,
                checkpoint_every=checkpoint_every,
                keep_checkpoint=True,
                maps_at=maps_at,
            )

        # a worker says nothing of compiling: the campaign's process has (its own line had
        # broken into the campaign's progress display: a diff review)
        with announcing(lambda text: None):
            if checkpoint is None or not Path(checkpoint).parent.is_dir():
                return simulate(config, seed=seed, maps_at=maps_at)
            try:
                return run()
            except CheckpointError:
                Path(checkpoint).unlink(missing_ok=True)
                return run()
    if maps_at:
        return simulate_fn(config, seed=seed, maps_at=maps_at)
    return simulate_fn(config, seed=seed)


# --- backends ------------------------------------------------------------------------------


class _Backend:
    """Where the runs go: submissions, capacity, and what a finished future means.

    The base class wraps any :class:`concurrent.futures.Executor` with a fixed number of
    calls in flight; it cannot replace a broken executor, so a run whose worker died is
    recorded as failed (dask retries such runs itself and then reports ``KilledWorker``).
    """

    #: Longest wait for a finished run before :meth:`free` is asked again [s]; None: no limit.
    poll: float | None = None

    def __init__(self, executor: cf.Executor, window: int, *, own: bool) -> None:
        self.executor = executor
        self.window = max(1, window)
        self.own = own
        self.in_flight = 0

    def free(self) -> int:
        """How many more runs may be submitted now."""
        return self.window - self.in_flight

    def submit(
        self, simulate_fn: SimulateFn | None, point: RunPoint, options: Mapping[str, Any]
    ) -> cf.Future:
        """Submit one run; a refused submission comes back as a failed future.
        ``options``: :func:`_execute`'s keywords (``checkpoint``, ``checkpoint_every``,
        ``maps_at``)."""
        self.in_flight += 1
        try:
            return self.executor.submit(_execute, simulate_fn, point.config, point.seed, **options)
        except Exception as exc:  # e.g. a broken executor owned by the caller
            future: cf.Future = cf.Future()
            future.set_exception(exc)
            return future

    def release(self, future: cf.Future) -> str | None:
        """Account for a finished future: the error text when its worker process died (the
        run may be tried again), None when the future holds the run's outcome."""
        self.in_flight -= 1
        return None

    def news(self) -> int:
        """Worker processes that died since the last call and whose runs the executor
        itself gives to a worker again (a LocalCluster of dask's); 0 for the others, whose
        deaths :meth:`release` reports run by run [-]."""
        return 0

    def lost(self) -> str | None:
        """Why no run can finish any more (a dask client that lost its scheduler and
        closed), or None while runs can."""
        return None

    def interrupted(self, future: cf.Future) -> bool:
        """Whether ``future`` ended without its run's outcome, to be run again (a dask
        client cancels its futures when it loses the scheduler)."""
        return False

    def waiting(self) -> str | None:
        """A note, once, where the runs wait for workers that are not there yet (an existing
        dask cluster without workers), else None."""
        return None

    def close(self, *, cancel: bool) -> None:
        """Shut the executor down when this campaign made it."""
        if self.own:
            self.executor.shutdown(wait=not cancel, cancel_futures=cancel)


def _brakeca_imports() -> Callable[[], str]:
    """A function for :meth:`distributed.Client.run` that imports on a worker what a run
    needs and returns brakeca's version there. Made here, not defined at module level: a
    module-level function travels by reference and would itself need brakeca to unpickle,
    a nested one travels by value (cloudpickle)."""

    def imports() -> str:
        try:
            import brakeca
            import brakeca.simulation  # the kernels' modules, numba
        except Exception as exc:  # as text: told apart from the link's own errors
            return f"{_IMPORT_FAILED}{type(exc).__name__}: {exc}"
        return str(brakeca.__version__)

    return imports


#: How :func:`_brakeca_imports`' answer begins where the import failed on the worker.
_IMPORT_FAILED = "import failed: "


class _DaskBackend(_Backend):
    """A :class:`DaskExecutor` with as many runs in flight as its workers have threads.

    Dask charges a worker's death to every task the worker holds, executing or waiting. With
    no more runs submitted than there are worker threads, a worker normally holds only the run
    it executes. The thread count is asked again every :attr:`poll` seconds, so workers that
    join late (a batch queue) get runs, once each is known to import brakeca
    (:meth:`_check_workers`); with no such worker yet, no run is submitted.
    """

    poll = 1.0

    def __init__(self, executor: DaskExecutor) -> None:
        super().__init__(executor, 1, own=True)
        self.client = executor.client
        self.deaths = executor.deaths
        self.told = 0
        self.address = self._address()  # while connected (a closed client's is gone)
        self.threads = 1  # the workers' threads at the last look [-]
        self.since_workers: float | None = None  # since when none (monotonic) [s]
        self.said_waiting = False
        self.checked: set[str] = set()  # the workers on which brakeca imports (addresses)

    def news(self) -> int:
        if self.deaths is None:
            return 0
        count = self.deaths.count
        new, self.told = count - self.told, count
        return new

    #: Seconds without a worker before :meth:`waiting` says so [s].
    WAIT_NOTE_AFTER = 10.0

    def _threads(self) -> int:
        """The threads of the workers known to import brakeca, now (0 where the scheduler
        does not answer) [-]; a worker seen for the first time is asked first
        (:meth:`_check_workers`), and one not asked yet, or that did not answer, counts
        for nothing: no run is submitted for it (a diff review: a run queued for a worker
        that had not joined yet went to a broken one the moment it registered)."""
        try:
            threads = dict(self.client.nthreads())
        except Exception:  # the scheduler is busy or gone: the runs in flight will tell
            return 0
        # a worker gone is forgotten: another at its address is asked again (a diff review)
        self.checked &= set(threads)
        self._check_workers(threads)
        return int(sum(n for address, n in threads.items() if address in self.checked))

    def _check_workers(self, addresses: Iterable[str]) -> None:
        """Refuse workers on which brakeca does not import (:class:`ExecutorError`).

        A run sent to such a worker kills it (dask cannot unpickle the run's configuration
        there, and the worker closes), and the campaign then waited for workers that were
        gone ("no worker yet"; a cluster review). Each worker is asked once, when it is first
        seen, before its threads count among those runs are submitted for; one whose import
        fails in any way (an ImportError, or an error of brakeca's own import, such as no
        folder for the kernels' cache) is refused; one that does not answer (gone since, or
        the scheduler busy) is asked again when it is seen again. A worker that joins while
        runs are being handed out may still take one before it is asked (the scheduler
        chooses): dask then gives that run to another worker, as after any worker's death.
        """
        new = [address for address in addresses if address not in self.checked]
        if not new:
            return
        try:
            answers = self.client.run(_brakeca_imports(), workers=new, on_error="return")
        except Exception:  # the scheduler is busy or gone, or a worker went: ask again later
            return
        broken: dict[str, str] = {}
        for address, answer in answers.items():
            if isinstance(answer, str) and answer.startswith(_IMPORT_FAILED):
                broken[address] = answer.removeprefix(_IMPORT_FAILED)  # (any error of it)
            elif isinstance(answer, OSError):  # the link's (closed, timed out): ask again
                continue
            elif isinstance(answer, BaseException):  # the probe itself could not run there
                # (another Python, say; a diff review: asked for ever, "no worker yet")
                broken[address] = f"{type(answer).__name__}: {answer}"
            else:
                self.checked.add(address)
        if broken:
            first = next(iter(broken.values()))
            raise ExecutorError(
                f"brakeca does not import on the Dask worker(s) at {', '.join(sorted(broken))} "
                f"({first}): a run sent there would kill the worker or fail. "
                'Install this brakeca on every worker (docs/cluster.md, "On a Dask '
                'cluster"), or stop those workers; the finished runs are kept, and the same '
                "command resumes"
            )

    def _connected(self) -> bool:
        return getattr(self.client, "status", "running") == "running"

    def free(self) -> int:
        if not self._connected():  # reconnecting, or closed: nothing to submit to
            return 0
        self.threads = self._threads()
        return self.threads - self.in_flight

    def interrupted(self, future: cf.Future) -> bool:
        # the moment the link to the scheduler drops, dask cancels every future of the
        # client, while it tries to reconnect (a diff review: those runs were recorded as
        # failed, and a campaign at its end finished with them)
        return future.cancelled() and not self._connected()

    def lost(self) -> str | None:
        # a client that cannot reach its scheduler again closes itself (after dask's
        # connect timeout): its futures never finish (a review found the campaign waiting
        # on them for good)
        if getattr(self.client, "status", "running") in ("closing", "closed"):
            return (
                f"the Dask client lost the scheduler at {self.address} and closed: no run "
                "can finish"
            )
        return None

    def waiting(self) -> str | None:
        if self.said_waiting or not self._connected():
            return None
        self.threads = self._threads()  # asked here too: free() only while runs wait
        if self.threads > 0:
            self.since_workers = None
            return None
        now = time.monotonic()
        if self.since_workers is None:
            self.since_workers = now
        if now - self.since_workers < self.WAIT_NOTE_AFTER:
            return None
        self.said_waiting = True
        return (
            f"the Dask scheduler at {self.address} has no worker yet: the runs wait for "
            "workers to join (Ctrl-C stops; the same command resumes)"
        )

    def _address(self) -> str:
        try:
            return str(self.client.scheduler.address)
        except Exception:
            return "its address"

    def close(self, *, cancel: bool) -> None:
        try:
            super().close(cancel=cancel)
        except Exception:  # a client already closed (its scheduler lost): nothing to stop
            if self.lost() is None:
                raise


class _LocalSlots(_Backend):
    """``workers`` one-process pools, each with at most one run in flight.

    A worker process that dies (killed, out of memory) breaks only its own pool, so the lost
    run is known exactly: the pool is replaced and the run may be tried again, while the
    runs of the other slots go on undisturbed.
    """

    def __init__(self, workers: int) -> None:
        self.pools: list[cf.ProcessPoolExecutor | None] = [None] * max(1, workers)
        self.busy: dict[cf.Future, int] = {}

    def free(self) -> int:
        return len(self.pools) - len(self.busy)

    def submit(
        self, simulate_fn: SimulateFn | None, point: RunPoint, options: Mapping[str, Any]
    ) -> cf.Future:
        taken = set(self.busy.values())
        slot = next(i for i in range(len(self.pools)) if i not in taken)
        pool = self.pools[slot]
        if pool is None:
            pool = self.pools[slot] = _local_pool(1)
        # the pool starts its process here; brakeca's own task needs no main module (a
        # simulate_fn of the caller's may come from it)
        with main_module_not_rerun() if simulate_fn is None else nullcontext():
            future = pool.submit(_execute, simulate_fn, point.config, point.seed, **options)
        self.busy[future] = slot
        return future

    def release(self, future: cf.Future) -> str | None:
        slot = self.busy.pop(future)
        exc = None if future.cancelled() else future.exception()
        if not isinstance(exc, cf.BrokenExecutor):
            return None
        pool = self.pools[slot]
        self.pools[slot] = None  # a fresh process for the next run of this slot
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
        return _error_text(exc)

    def close(self, *, cancel: bool) -> None:
        pools = [p for p in self.pools if p is not None]
        self.pools = [None] * len(self.pools)
        for pool in pools:
            if cancel:
                _stop_pool(pool)
            else:
                pool.shutdown(wait=True)


def _backend(
    executor: ExecutorKind | cf.Executor,
    workers: int | None,
    n_todo: int,
    *,
    scheduler: str | None,
    scheduler_file: str | Path | None,
    max_retries: int,
) -> _Backend:
    """The backend that runs ``n_todo`` runs on ``executor`` (see run_campaign)."""
    n_workers = (os.cpu_count() or 1) if workers is None else workers
    if isinstance(executor, cf.Executor):
        if isinstance(executor, SerialExecutor):
            window = 1
        elif type(executor).__module__.split(".")[0] == "distributed":
            # a dask client's executor: a worker's death is charged to every run it holds,
            # waiting ones too, so no more runs in flight than workers (docs/cluster.md)
            window = max(1, n_workers)
        else:  # one waiting per worker, so that none idles between runs
            window = 2 * max(1, n_workers)
        return _Backend(executor, window, own=False)
    if executor == "serial":
        return _Backend(SerialExecutor(), 1, own=True)
    if executor == "local":
        _tracker_outlives_a_hangup()
        return _LocalSlots(max(1, min(n_workers, n_todo)))
    if scheduler is None and scheduler_file is None:
        _tracker_outlives_a_hangup()  # the LocalCluster's nannies use it too
    dask_executor = make_executor(
        "dask",
        max(1, min(n_workers, n_todo)),
        scheduler=scheduler,
        scheduler_file=scheduler_file,
        max_retries=max_retries,
    )
    return _DaskBackend(dask_executor)  # type: ignore[arg-type]


@dataclass(frozen=True)
class _Execution:
    """How a campaign's runs are executed (the options of :func:`run_campaign`)."""

    executor: ExecutorKind | cf.Executor
    workers: int | None
    scheduler: str | None
    scheduler_file: str | Path | None
    max_retries: int
    checkpoint_every: int | None
    simulate_fn: SimulateFn | None
    progress: bool
    maps_at: tuple[int, ...] = ()
    on_run: Callable[[int, int], object] | None = None  # called with (done, total) per run
