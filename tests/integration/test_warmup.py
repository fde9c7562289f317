"""Compiling the kernels ahead in a child process (brakeca._warmup)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from campaign_helpers import ignores_sigint, started_as_a_job

from brakeca._warmup import _child, tiny_config, warm_up
from brakeca.config import UnitWarning
from brakeca.contact import ContactError
from brakeca.presets import load_preset
from brakeca.simulation import kernel_for, simulate


def test_tiny_config_keeps_the_kernel_and_the_cell_size_on_two_rows():
    config = load_preset()
    tiny = tiny_config(config)
    assert tiny.mesh.n_radial == 2 and tiny.cycle.max_stops == 1
    assert tiny.mesh.n_angular == config.mesh.n_angular
    assert tiny.numerics.kernel == kernel_for(config) == "lazy"
    rule6 = config.with_updates({"automaton.rule6_max_gap": 1e-5})
    assert tiny_config(rule6).numerics.kernel == "exact"


def test_warm_up_is_skipped_for_kernels_this_process_holds():
    config = load_preset().with_updates({"mesh.n_radial": 3, "cycle.max_stops": 1})
    simulate(tiny_config(config), seed=0)  # compiled or loaded here
    assert warm_up([config, load_preset()]) is None


def test_a_config_that_cannot_run_is_skipped_without_a_traceback():
    """A foundation too soft for the braking torque raises ContactError at the first step:
    the warm-up child skips it silently (the run reports the error itself) and still warms
    the configurations after it."""
    good = load_preset().with_updates({"mesh.n_radial": 3, "cycle.max_stops": 1})
    soft = {"contact.bar_length": 1e-3, "contact.elastic_modulus": 1e4}
    with pytest.warns(UnitWarning):
        bad = good.with_updates(soft)
    assert _child([bad, good]) == 1
    assert _child([good]) == 0
    with pytest.raises(ContactError, match="would compress the"):
        simulate(bad, seed=0)
    # the child process: no traceback on the terminal, and the warm-up reports a failure
    probe = (
        "import warnings; warnings.simplefilter('ignore'); "
        "from brakeca._warmup import warm_up; from brakeca.presets import load_preset; "
        f"print(warm_up([load_preset().with_updates({{**{soft!r}, 'cycle.max_stops': 1}})]))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "None"
    assert "Traceback" not in out.stderr and "ContactError" not in out.stderr


def test_the_coordinating_process_does_not_load_numba():
    """A campaign's main process warms the kernels up in a child and reads run files: it
    never needs numba or the kernels' modules (65 MB of its memory; the study's largest
    process is this one, which also writes the report)."""
    probe = (
        "import sys; from brakeca._warmup import warm_up; from brakeca.presets import "
        "load_preset; from brakeca import results, campaign, analysis, report; "
        "c = load_preset().with_updates({'mesh.n_radial': 3, 'cycle.max_stops': 1}); "
        "took = warm_up([c, c.with_updates({'automaton.rule6_max_gap': 1e-5})]); "
        "print(took is not None, sorted(m for m in ('numba', 'brakeca._kernels', "
        "'brakeca._lazy', 'brakeca.simulation') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "True []"


_CAMPAIGN_PROBE = """
import sys
from pathlib import Path
sys.path.insert(0, sys.argv[1])  # the tests' folder: campaign_helpers
from campaign_helpers import DESIGN_TEMPLATE, quiet, tiny, write_design
from brakeca.campaign import run_campaign
from brakeca.study import write_study
if __name__ == "__main__":
    folder = Path(sys.argv[2])
    design = write_design(folder, tiny(2), DESIGN_TEMPLATE.format(root_seed=3))
    result = run_campaign(
        design, folder / "campaign", executor="local", workers=2, maps_at=(1, 2),
        progress=False, console=quiet(),
    )
    write_study(result)
    print(result.ok, sorted(m for m in ("numba", "brakeca._kernels", "brakeca._lazy",
        "brakeca.simulation") if m in sys.modules))
"""


def test_a_whole_campaign_with_maps_leaves_numba_out_of_the_main_process(tmp_path):
    """The same for a campaign that runs on worker processes, keeps maps (whose stops are
    checked against the cycle before any work) and is analysed: the main process never
    imports the kernels (the thirty-ninth session found ``maps_at``'s check importing
    ``brakeca.simulation``, 60 MB, in every study)."""
    script = tmp_path / "probe.py"
    script.write_text(_CAMPAIGN_PROBE, encoding="utf-8")
    tests = Path(__file__).resolve().parents[1]
    out = subprocess.run(
        [sys.executable, str(script), str(tests), str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    )
    assert out.stdout.strip().splitlines()[-1] == "True []"


_PROBE = """
import json, sys
from brakeca import _kernels, _lazy, automaton, contact, friction, wear
from brakeca._warmup import tiny_config
from brakeca.presets import load_preset
from brakeca.simulation import simulate
simulate(tiny_config(load_preset()), seed=0)
hits = _lazy.run_stop_lazy.stats.cache_hits
# every compiled function a run calls from Python, not only the stop kernel: none compiles
misses = [
    name
    for module in (_kernels, _lazy, automaton, contact, friction, wear)
    for name, obj in vars(module).items()
    if hasattr(obj, "stats") and sum(obj.stats.cache_misses.values())
]
print(json.dumps({"hits": sum(hits.values()), "compiled": misses}))
"""


@pytest.mark.slow
@pytest.mark.timeout(1800)
def test_warm_up_fills_an_empty_cache_for_the_next_process(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    warm = (
        "from brakeca._warmup import warm_up; from brakeca.presets import load_preset; "
        "print(warm_up([load_preset()]))"
    )
    out = subprocess.run(
        [sys.executable, "-c", warm], env=env, capture_output=True, text=True, check=True
    )
    assert float(out.stdout.strip().splitlines()[-1]) > 0.0
    assert list((tmp_path / "cache").rglob("*.nbi"))
    probe = subprocess.run(
        [sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, check=True
    )
    stats = json.loads(probe.stdout.strip().splitlines()[-1])
    assert stats == {"hits": 1, "compiled": []}


def test_a_campaign_on_this_machine_warms_up_with_the_configs_it_runs(tmp_path, monkeypatch):
    from campaign_helpers import DESIGN_TEMPLATE, quiet, tiny, write_design

    from brakeca import _warmup
    from brakeca.campaign import run_campaign

    seen: list[list] = []
    monkeypatch.setattr(_warmup, "warm_up", lambda configs: seen.append(list(configs)))
    design = write_design(tmp_path, tiny(1), DESIGN_TEMPLATE.format(root_seed=5))
    run_campaign(design, tmp_path / "a", executor="serial", progress=False, console=quiet())
    assert len(seen) == 1 and len(seen[0]) == 4
    assert {c.pad.fibre_area_fraction for c in seen[0]} == {0.1, 0.2}
    # a campaign with its own simulate function (nothing of ours to compile) does not
    seen.clear()

    def fake(config, *, seed, progress=None):
        return simulate(config, seed=seed, progress=progress)

    run_campaign(
        design,
        tmp_path / "b",
        executor="serial",
        simulate_fn=fake,
        progress=False,
        console=quiet(),
    )
    assert seen == []


def test_the_simulation_module_does_not_load_xarray():
    """The warm-up child imports the stop's modules while it holds the compiler's memory; the
    run-file module (xarray, pandas: about 50 MB) is imported only when simulate builds one."""
    probe = (
        "import sys, brakeca.simulation, brakeca.stop, brakeca.state, brakeca.checkpoint; "
        "print('xarray' in sys.modules, 'pandas' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "False False"


def test_ctrl_c_during_the_warm_up_gives_no_child_traceback(tmp_path):
    """Ctrl-C at a terminal reaches the whole process group. The child ignores it and the
    parent, interrupted in subprocess.run, kills it: no compiler traceback on the terminal,
    no child left behind. An empty cache makes the child compile (about 45 s), so the signal
    arrives while it works."""
    import time

    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    script = (  # SIGINT as at a terminal, even where this test runs with it ignored (a
        # job started with & by a non-interactive shell): Python then leaves it ignored
        "import signal\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "import sys\n"
        "from brakeca._warmup import warm_up\n"
        "from brakeca.presets import load_preset\n"
        "print('warming', flush=True)\n"
        "try:\n"
        "    warm_up([load_preset()])\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
    )
    with started_as_a_job(["-c", script], "warming", env=env) as proc:
        # wait until the child runs and ignores SIGINT (on a loaded machine its start takes
        # seconds; a signal before that would hit it, or the parent still inside Popen)
        deadline = time.monotonic() + 120.0
        children: list[int] = []
        while time.monotonic() < deadline:
            children = _children(proc.pid)
            if children and all(ignores_sigint(pid) for pid in children):
                break
            time.sleep(0.2)
        assert children, "the warm-up child should be running"
        assert all(ignores_sigint(pid) for pid in children), "the child should ignore SIGINT"
        time.sleep(1.0)  # the child is compiling
        os.killpg(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=60)
        assert out.strip() == "interrupted"
        assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
        for pid in children:
            assert not _alive(pid)


def _children(pid: int) -> list[int]:
    """Process ids whose parent is ``pid`` (from /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:  # gone meanwhile
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def test_the_warm_up_imports_nothing_from_the_folder_it_was_started_in(tmp_path):
    """A security review: the warm-up's child ran ``python -m``, which puts the working
    directory first on sys.path, so a ``brakeca/`` folder in a campaign folder someone sent
    ran its code when a run was started there; ``-P`` leaves it out."""
    marker = tmp_path / "ran"
    fake = tmp_path / "sent" / "brakeca"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text(
        f"from pathlib import Path\nPath({str(marker)!r}).touch()\nraise SystemExit(3)\n",
        encoding="utf-8",
    )
    code = (
        "from brakeca._warmup import warm_up\n"
        "from brakeca.presets import load_preset\n"
        "took = warm_up([load_preset().with_updates({'mesh.n_radial': 3})], announce=print)\n"
        "assert took is not None, 'the warm-up failed'\n"
    )
    done = subprocess.run(
        [sys.executable, "-P", "-c", code],  # (this process, as a console script starts)
        cwd=fake.parent,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert not marker.exists()
