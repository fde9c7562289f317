"""The first-use compile (about 40 s in a child process) is announced before the wait, when
the cache lacks a kernel: `brakeca simulate`, `run` and `paper` say so first, not only after."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

import brakeca._warmup as warmup
import brakeca.campaign
from brakeca.cli import app
from brakeca.presets import load_preset

VERSION = f"py{sys.version_info.major}{sys.version_info.minor}{getattr(sys, 'abiflags', '')}"


def _index(cache: Path, module: str, name: str) -> Path:
    """A kernel's cache index file, as numba names it under NUMBA_CACHE_DIR."""
    folder = cache / "brakeca_0123abcd"
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{module}.{name}-100.{VERSION}.nbi"
    path.write_bytes(b"")
    return path


def test_cold_kernels_reads_the_cache_folder(tmp_path, monkeypatch) -> None:
    cache = tmp_path / "cache"
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(cache))
    lazy = load_preset()
    exact = lazy.with_updates({"automaton.rule6_max_gap": 1e-5})
    assert warmup.cold_kernels([lazy]) == ["lazy"]  # no folder yet: nothing cached
    assert warmup.cold_kernels([lazy, exact]) == ["lazy", "exact"]
    _index(cache, "_lazy", "run_stop_lazy")
    assert warmup.cold_kernels([lazy]) == []
    assert warmup.cold_kernels([lazy, exact]) == ["exact"]
    # an index older than the kernel's source is stale: numba compiles again
    stale = _index(cache, "_kernels", "run_stop")
    source = Path(warmup.__file__).with_name("_kernels.py").stat().st_mtime
    os.utime(stale, (source - 10.0, source - 10.0))
    assert warmup.cold_kernels([exact]) == ["exact"]
    # without the variable, brakeca's own folder (brakeca._cachedir.cache_folder)
    from brakeca import _cachedir

    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(_cachedir, "cache_folder", lambda: cache)
    assert warmup.cold_kernels([lazy]) == []
    monkeypatch.setattr(_cachedir, "cache_folder", lambda: None)
    assert warmup.cold_kernels([lazy]) is None  # numba's default place: not known


def test_the_kernel_is_chosen_as_the_simulation_chooses_it() -> None:
    from brakeca.simulation import kernel_for

    config = load_preset()
    for updates, expected in (
        ({}, "lazy"),
        ({"automaton.rule6_max_gap": 1e-5}, "exact"),
        ({"pad.fibre_model": "field"}, "exact"),
        ({"numerics.kernel": "exact"}, "exact"),
        ({"WP": 1e-13, "A": 10}, "lazy"),
    ):
        changed = config.with_updates(updates)
        # the warm-up reads the configuration's choice (no numba), the simulation checks it
        assert changed.resolved_kernel() == kernel_for(changed) == expected, updates


def _fake_child(calls: list[str]):
    def run(args, check=False):
        calls.append("child")
        return subprocess.CompletedProcess(args, 0)

    return run


def test_warm_up_announces_before_the_child_only_when_cold(tmp_path, monkeypatch) -> None:
    cache = tmp_path / "cache"
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(cache))
    calls: list[str] = []
    monkeypatch.setattr(warmup.subprocess, "run", _fake_child(calls))
    monkeypatch.setattr(warmup, "_compiled_here", lambda kernel: False)
    config = load_preset()
    assert warmup.warm_up([config], announce=calls.append) is not None
    assert calls == [warmup.COMPILING, "child"]
    calls.clear()
    with warmup.announcing(calls.append):  # a campaign's call, which names no callback
        warmup.warm_up([config])
    assert calls == [warmup.COMPILING, "child"]
    calls.clear()
    monkeypatch.setattr(warmup, "to_stderr", lambda text: calls.append(f"stderr: {text}"))
    warmup.warm_up([config])  # no one to tell: stderr (the Python API had compiled in silence)
    assert calls == [f"stderr: {warmup.COMPILING}", "child"]
    calls.clear()
    _index(cache, "_lazy", "run_stop_lazy")
    with warmup.announcing(calls.append):
        warmup.warm_up([config], announce=calls.append)
    assert calls == ["child"]  # cached: loading takes a second, nothing to announce


def _announce_then_interrupt(configs, *, announce=None):
    say = announce if announce is not None else warmup._ANNOUNCE.get()
    assert say is not None, "the command line should give the warm-up a callback"
    say(warmup.COMPILING)
    raise KeyboardInterrupt


def test_simulate_and_run_print_the_announcement(tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(warmup, "warm_up", _announce_then_interrupt)
    res = CliRunner().invoke(app, ["simulate", "-o", str(tmp_path / "r.nc"), "--stops", "1"])
    assert res.exit_code == 130, res.output
    lines = res.output.splitlines()
    assert warmup.COMPILING in lines
    assert lines.index(warmup.COMPILING) < next(
        k for k, line in enumerate(lines) if line.startswith("interrupted:")
    )

    def campaign(design, output, **kwargs):  # what run_campaign's warm-up does
        warmup.warm_up([load_preset()])

    monkeypatch.setattr(brakeca.campaign, "run_campaign", campaign)
    res = CliRunner().invoke(app, ["run", "paper", "-o", str(tmp_path / "c"), "--stops", "1"])
    assert res.exit_code == 130, res.output
    assert warmup.COMPILING in res.output.splitlines()
    assert warmup._ANNOUNCE.get() is None  # set for the campaign only


@pytest.mark.parametrize("kernel", ["lazy", "exact"])
def test_the_index_looked_for_is_the_one_numba_writes(kernel) -> None:
    """Checked on numba's own cache object of the kernel's entry point (nothing compiled)."""
    import importlib

    module, name = warmup._ENTRIES[kernel]
    dispatcher = getattr(importlib.import_module(module), name)
    index = Path(dispatcher._cache._cache_file._index_path).resolve()
    from brakeca._cachedir import kernel_cache_dir

    cache = Path(str(kernel_cache_dir())).resolve()
    assert index.relative_to(cache).match(warmup._index_pattern(kernel))


def test_the_warm_up_configuration_of_a_quick_run_is_valid() -> None:
    """The warm-up compiles on a two-row band: for a --quick configuration that band must not
    stay labelled quick (a 21-row label; refused since quick = true needs 21 rows), or every
    quick run's warm-up failed with a traceback and each worker compiled on its own."""
    from brakeca._warmup import tiny_config
    from brakeca.design import quick_config
    from brakeca.presets import load_preset

    tiny = tiny_config(quick_config(load_preset("paper")))
    assert tiny.mesh.n_radial == 2 and not tiny.quick and tiny.cycle.max_stops == 1


def test_simulate_from_python_says_it_compiles_when_cold(monkeypatch) -> None:
    """A packaging review: simulate() in a notebook compiled for a minute in silence; where
    its kernel is neither compiled in the process nor cached it says so (to stderr, or to a
    campaign's callback), and not where it is."""
    from conftest import short_cycle

    from brakeca.simulation import simulate

    config = load_preset().with_updates(
        {"mesh.n_radial": 3, "mesh.n_angular": 60, "mesh.n_subdomains": 2, "cycle": short_cycle(1)}
    )
    said: list[str] = []
    monkeypatch.setattr(warmup, "to_stderr", said.append)
    with monkeypatch.context() as m:  # a warm cache (this test alone may meet a cold one)
        m.setattr(warmup, "cold_kernels", lambda configs: [])
        simulate(config, seed=1)  # compiled in this process or loaded: nothing to say
    assert said == []
    simulate(config, seed=1)  # compiled in this process now, whatever the cache held
    assert said == []
    monkeypatch.setattr(warmup, "_compiled_here", lambda kernel: False)
    monkeypatch.setattr(warmup, "cold_kernels", lambda configs: ["lazy"])
    simulate(config, seed=1)
    assert said == [warmup.COMPILING]
    with warmup.announcing(lambda text: said.append(f"callback: {text}")):
        simulate(config, seed=1)
    assert said[-1] == f"callback: {warmup.COMPILING}"
