"""Compile the step kernels ahead, in a child process.

numba compiles a kernel on its first call and caches the machine code on disk
(``cache=True``, in :func:`brakeca._cachedir.kernel_cache_dir`). Compiling holds about 180 MB
of LLVM memory that the process never gives back, so a full-resolution run that compiles its
kernels first peaks near 580 MB, against about 410 MB when it loads them from the cache
(docs/performance-history.md).
:func:`warm_up` therefore compiles (or only loads) the kernels a set of configurations needs in
a short-lived child process (a plain interpreter: ``python -m brakeca._warmup``), by running
each on a two-row band for one stop: the run that follows, or a campaign's worker processes,
then load the machine code from the cache. It also saves time in a campaign with a cold cache:
the kernels are compiled once, not once per worker.

Compiling takes 35–55 s (measured); loading, a second or two. So that the wait does not look like a
hang, :func:`warm_up` says ``compiling the kernels ...`` before it when it can tell cheaply that
the cache lacks a kernel it needs (:func:`cold_kernels`), through the callback it is given or
the one a caller set with :func:`announcing` (the command line's, around a campaign).

The warm-up is an optimisation only: if it fails (a cache directory that cannot be written, a
configuration that cannot run on two rows), the runs compile for themselves as before. A
configuration whose stop raises (a pad no plateau of which reaches the disc, say) is skipped
without a word: the run that follows meets the same error and reports it, once, as the run's.
"""

from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

from brakeca.config import SimulationConfig

# the compiled entry point of each kernel (its dispatcher holds a signature once this process
# has compiled it or loaded it from the cache, which it wrote or found there)
_ENTRIES = {"lazy": ("brakeca._lazy", "run_stop_lazy"), "exact": ("brakeca._kernels", "run_stop")}


#: What :func:`warm_up` says before it compiles (see :func:`cold_kernels`).
COMPILING = (
    "compiling the kernels (about a minute, once for each version of brakeca in each "
    "environment) ..."
)

_ANNOUNCE: ContextVar[Callable[[str], None] | None] = ContextVar("_ANNOUNCE", default=None)


def to_stderr(text: str) -> None:
    """Where no caller tells the user (the Python API: ``simulate``, ``run_campaign`` in a
    notebook or a script), the notice goes to stderr: a first run that compiled for a minute
    in silence looked hung (a packaging review)."""
    print(f"brakeca: {text}", file=sys.stderr, flush=True)


def announce_if_cold(config: SimulationConfig) -> None:
    """Say :data:`COMPILING` (by the caller's callback of :func:`announcing`, else to stderr)
    where running ``config`` in this process compiles its kernel: not compiled here yet and
    not in the cache (:func:`cold_kernels`). For :func:`brakeca.simulation.simulate`, which
    compiles in its own process where nothing warmed it up."""
    kernel = config.resolved_kernel()
    if _compiled_here(kernel) or not cold_kernels([config]):
        return
    say = _ANNOUNCE.get() or to_stderr
    say(COMPILING)


@contextmanager
def announcing(say: Callable[[str], None]) -> Iterator[None]:
    """Within the block, :func:`warm_up` calls without their own ``announce`` (a campaign's)
    tell ``say`` before they compile, as if given ``announce=say``."""
    token = _ANNOUNCE.set(say)
    try:
        yield
    finally:
        _ANNOUNCE.reset(token)


def _index_pattern(kernel: str) -> str:
    """The glob pattern, relative to the kernels' cache folder, of the index file numba writes
    for ``kernel``'s entry point: ``<folder of the sources>_<hash>/<module>.<function>-<first
    line>.py<version><abiflags>.nbi``."""
    module, name = _ENTRIES[kernel]
    version = f"py{sys.version_info.major}{sys.version_info.minor}{getattr(sys, 'abiflags', '')}"
    return f"*/{module.rpartition('.')[2]}.{name}-*.{version}.nbi"


def cold_kernels(configs: Iterable[SimulationConfig]) -> list[str] | None:
    """The step kernels (``"lazy"``, ``"exact"``) that ``configs`` need and numba's cache
    does not hold, so that running them compiles them (35–55 s); from the cache folder's
    file names alone, without importing numba.

    A kernel counts as cached when its entry point's index file (``*.nbi``) is in the
    kernels' cache folder (:func:`brakeca._cachedir.kernel_cache_dir`) and is not older than
    the kernel's source file. A cached kernel may still compile for a model
    option not run before (the warm-up then takes longer than a load, unannounced).

    Returns
    -------
    list of str or None
        The kernels, in the order of :data:`_ENTRIES` (empty if all are cached); None if
        the cache folder is not known (numba's default place beside the sources).
    """
    from brakeca._cachedir import kernel_cache_dir

    cache = kernel_cache_dir()
    if not cache:
        return None
    needed = {c.resolved_kernel() for c in configs}  # without importing numba
    cold = []
    for kernel in _ENTRIES:
        if kernel not in needed:
            continue
        source = Path(__file__).with_name(f"{_ENTRIES[kernel][0].rpartition('.')[2]}.py")
        try:
            changed = source.stat().st_mtime
            stamps = [p.stat().st_mtime for p in Path(cache).glob(_index_pattern(kernel))]
        except OSError:
            return None
        if not any(stamp >= changed for stamp in stamps):
            cold.append(kernel)
    return cold


def tiny_config(config: SimulationConfig) -> SimulationConfig:
    """``config`` on a two-row band for one stop, with its kernel pinned: the same compiled
    code paths (argument types and model options) at a cost of well under a second."""
    return config.with_updates(
        {
            "mesh.n_radial": 2,
            "quick": False,  # a quick configuration's band is 21 rows: this one is not
            "cycle.max_stops": 1,
            "numerics.kernel": config.resolved_kernel(),
        }
    )


def _key(config: SimulationConfig) -> tuple:
    """What selects the compiled code a run calls: the kernel and the model options it
    branches on in Python."""
    return (
        config.resolved_kernel(),
        config.pad.fibre_model,
        config.automaton.rule6_max_gap is None,
        config.automaton.creation_order,
    )


def _compiled_here(kernel: str) -> bool:
    """Whether this process already holds ``kernel``'s machine code (and so the cache has it);
    False where the kernel's module is not even imported."""
    module_name, name = _ENTRIES[kernel]
    module = sys.modules.get(module_name)
    return module is not None and bool(getattr(module, name).signatures)


def _child(configs: list[SimulationConfig]) -> int:
    """Run one stop of each distinct configuration on two rows, the way ``simulate`` runs a
    stop (the same compiled entry points: the state's structures, the stop kernel, the end of
    the stop), without building a run file: ``simulate``'s run file would import xarray and
    pandas into the process that holds the compiler's memory (about 50 MB more).

    Returns
    -------
    int
        How many distinct configurations raised (and were skipped) [-].
    """
    import numpy as np

    from brakeca.cycle import cycle_events
    from brakeca.geometry import make_grid
    from brakeca.state import SimulationState
    from brakeca.stop import advance_stop, end_of_stop, scratch_lists
    from brakeca.surface import generate_surface

    seen: set[tuple] = set()
    failed = 0
    for config in configs:
        key = _key(config)
        if key not in seen:
            seen.add(key)
            tiny = tiny_config(config)
            grid = make_grid(tiny)
            rng = np.random.default_rng(0)
            try:
                state = SimulationState.from_surface(generate_surface(tiny.pad, grid, rng), grid)
                lists = scratch_lists(grid.shape[0] * grid.shape[1])
                advance_stop(state, grid, tiny, cycle_events(tiny)[0], lists)
                end_of_stop(state, tiny.automaton.secondary_removal_fraction, rng)
            except Exception:  # the run reports it (module docstring); the next config goes on
                failed += 1
    return failed


def warm_up(
    configs: Iterable[SimulationConfig], *, announce: Callable[[str], None] | None = None
) -> float | None:
    """Compile (or load) the kernels ``configs`` need in a child process; see the module
    docstring.

    Parameters
    ----------
    configs
        The configurations to be run.
    announce
        Called with :data:`COMPILING` before the child starts when a kernel it needs is not
        in the cache (:func:`cold_kernels`); by default the callback of :func:`announcing`,
        and without one :func:`to_stderr`.

    Returns
    -------
    float or None
        Wall time of the warm-up [s]; None if nothing needed it (this process has those kernels
        already) or it failed.
    """
    todo = list(configs)
    if all(name in sys.modules for name, _ in _ENTRIES.values()):
        # this process holds the kernels' modules (it ran a simulation): skip what it compiled
        todo = [c for c in todo if not _compiled_here(_key(c)[0])]
    # else the child sorts the configurations out: which kernel runs a configuration is
    # decided by brakeca.simulation, and importing it here would load numba and the kernels'
    # modules into a process that may only coordinate workers and write the report (65 MB)
    if not todo:
        return None
    say = announce if announce is not None else (_ANNOUNCE.get() or to_stderr)
    if cold_kernels(todo):
        say(COMPILING)
    t0 = time.perf_counter()
    # a plain interpreter running this module, not a multiprocessing child: "spawn" would
    # import this process's main module there first (the command line's: about 40 MB more
    # in the process that holds the compiler's memory, the largest of a study)
    with tempfile.TemporaryDirectory(prefix="brakeca-warm-up-") as tmp:
        path = Path(tmp) / "configs.pickle"
        path.write_bytes(pickle.dumps(todo))
        # -P: no module of the folder the command was given in is imported ahead of the
        # installed ones (-m puts the working directory first on sys.path, so a brakeca/ or
        # numpy/ folder in a campaign folder someone sent ran its code: a security review)
        done = subprocess.run(
            [sys.executable, "-P", "-m", "brakeca._warmup", str(path), str(os.getpid())],
            check=False,
        )
    if done.returncode != 0:
        return None
    return time.perf_counter() - t0


def _main(argv: list[str]) -> int:
    """The child's entry point. It ignores SIGINT: Ctrl-C at a terminal reaches the whole
    process group, and the parent, interrupted in ``subprocess.run``, kills the child itself,
    so the user sees the parent's message instead of a compiler's traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # a parent killed outright (SIGKILL) cannot stop this child or remove its folder
    import shutil

    from brakeca._executors import _exit_with_parent

    folder = Path(argv[1]).parent

    def remove_folder() -> None:
        if folder.name.startswith("brakeca-warm-up-"):  # warm_up's TemporaryDirectory
            shutil.rmtree(folder, ignore_errors=True)

    # the parent's pid as it gave it: one killed before this child started is not init
    parent = int(argv[2]) if len(argv) > 2 else os.getppid()
    _exit_with_parent(parent, cleanup=remove_folder)
    return 1 if _child(pickle.loads(Path(argv[1]).read_bytes())) else 0


if __name__ == "__main__":
    sys.exit(_main(sys.argv))
