"""Where the compiled kernels spend their time, source line by source line, with ``perf``.

    python benchmarks/perf_lines.py [--set A=10 ...] [--wp 1e-13] [--stops 8] [--skip 0]
        [--seconds 10]

Linux only; needs ``perf`` (the operating system's clock is enough: no hardware counters),
``gdb``, ``objdump`` and ``addr2line``, and the right to attach to a child process (root, or
``perf_event_paranoid`` <= 1 and ptrace allowed). What it does (docs/performance-history.md, ninth
session):

1. A child process compiles the kernels with line tables (``NUMBA_DEBUGINFO=1``, in a cache
   folder of its own), runs one stop to warm up, then runs the next stops of the paper cycle
   at full resolution (test 5's levels by default: ``--wp 1e-13 --set A=10``).
2. ``perf record -e cpu-clock`` samples it for ``--seconds``.
3. gdb names the compiled function and offset of each sampled address (numba registers its
   code with gdb's JIT interface); ``addr2line`` on that function's object code, cut out of
   numba's cache file, gives the source line.

Prints one JSON line: the samples, the share in numba's reference counting
(``NRT_incref``/``NRT_decref``; 22 % before the ninth session, 0.1 % after), and the source
lines with the largest shares.
"""

from __future__ import annotations

import argparse
import collections
import glob
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHILD = r"""
import os, sys, time
import numpy as np
from numba.core.runtime import nrt
from brakeca.config import parse_override
from brakeca.cycle import expand_stops
from brakeca.geometry import make_grid
from brakeca.presets import load_preset
from brakeca.simulation import SimulationState, advance_stop, end_of_stop
from brakeca.surface import generate_surface

work, wp, stops, skip = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
sets = sys.argv[5:]
updates = {"WP": wp, "cycle.max_stops": skip + stops + 1}
updates.update(parse_override(item) for item in sets)
config = load_preset().with_updates(updates)
grid = make_grid(config)
cycle = expand_stops(config)
rng = np.random.default_rng(2016)
state = SimulationState.from_surface(generate_surface(config.pad, grid, rng), grid)
advance_stop(state, grid, config, cycle[0])  # compiles
end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
for stop in cycle[1 : 1 + skip]:  # not sampled
    advance_stop(state, grid, config, stop)
    end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
lib = nrt.rtsys.library
with open(os.path.join(work, "ready"), "w") as f:
    f.write(f"{lib.get_pointer_to_function('NRT_incref')}")
for stop in cycle[1 + skip :]:
    advance_stop(state, grid, config, stop)
    end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
while not os.path.exists(os.path.join(work, "done")):  # gdb reads the symbols first
    time.sleep(0.2)
"""


def _objects(cache: Path, work: Path) -> dict[str, tuple[str, int]]:
    """Function name (as gdb prints it) -> (object file, offset), from numba's cache files."""
    names: dict[str, tuple[str, int]] = {}
    for k, path in enumerate(glob.glob(str(cache / "**" / "*.nbc"), recursive=True)):
        data = Path(path).read_bytes()
        start = data.find(b"\x7fELF")
        if start < 0:
            continue
        elf = data[start:]
        (shoff,) = struct.unpack_from("<Q", elf, 0x28)
        shentsize, shnum = struct.unpack_from("<HH", elf, 0x3A)
        obj = work / f"lib{k}.o"
        obj.write_bytes(elf[: shoff + shentsize * shnum])
        table = subprocess.run(["objdump", "-tC", str(obj)], capture_output=True, text=True)
        for line in table.stdout.splitlines():
            if " F " in line:
                name = line.split("\t")[-1].split(None, 1)[-1].strip()
                names.setdefault(name, (str(obj), int(line.split()[0], 16)))
    return names


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wp", type=float, default=1e-13)
    ap.add_argument("--set", action="append", default=["A=10"], help="KEY=VALUE override")
    ap.add_argument("--stops", type=int, default=8, help="stops run after the warm-up stop")
    ap.add_argument(
        "--skip",
        type=int,
        default=0,
        help="stops run before sampling starts (after the warm-up stop), to profile a later "
        "block of the cycle: --skip 99 samples from stop 101 on",
    )
    ap.add_argument("--seconds", type=float, default=10.0, help="how long perf samples")
    ap.add_argument("--top", type=int, default=25, help="source lines listed")
    args = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="brakeca-perf-"))
    cache = work / "numba_cache"
    env = dict(os.environ, NUMBA_DEBUGINFO="1", NUMBA_CACHE_DIR=str(cache), NUMBA_NUM_THREADS="1")
    argv = [str(work), str(args.wp), str(args.stops), str(args.skip), *args.set]
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, *argv],
        env=env,
    )
    try:
        while not (work / "ready").exists():
            if child.poll() is not None:
                sys.exit("perf_lines: the child run ended before it was warm")
            time.sleep(0.5)
        incref = int((work / "ready").read_text())
        data = work / "perf.data"
        subprocess.run(
            [
                *("perf", "record", "-q", "-e", "cpu-clock", "-F", "2000"),
                *("-p", str(child.pid), "-o", str(data), "--", "sleep", str(args.seconds)),
            ],
            check=True,
            capture_output=True,
        )
        script = subprocess.run(
            ["perf", "script", "-i", str(data), "-F", "ip"], capture_output=True, text=True
        )
        ips = collections.Counter(int(x, 16) for x in script.stdout.split())
        commands = work / "gdb.txt"
        top_ips = [ip for ip, _ in ips.most_common(3000)]
        commands.write_text("".join(f"info symbol {ip:#x}\n" for ip in top_ips))
        gdb = subprocess.run(
            ["gdb", "-p", str(child.pid), "-batch", "-x", str(commands)],
            capture_output=True,
            text=True,
        )
    finally:
        (work / "done").write_text("1")
        child.wait(timeout=120)
    symbols = [
        line for line in gdb.stdout.splitlines() if " in section" in line or "No symbol" in line
    ]
    names = _objects(cache, work)
    total = sum(ips.values())
    nrt = sum(n for ip, n in ips.items() if incref <= ip < incref + 0x30)
    per_object: dict[str, list[tuple[int, int]]] = collections.defaultdict(list)
    lines: collections.Counter[str] = collections.Counter()
    for ip, sym in zip(top_ips, symbols, strict=False):
        m = re.match(r"(.*?)(?: \+ (\d+))? in section", sym)
        if m and m.group(1).strip() in names:
            obj, base = names[m.group(1).strip()]
            per_object[obj].append((base + int(m.group(2) or 0), ips[ip]))
        else:
            lines["(outside the kernels' code)"] += ips[ip]
    for obj, queries in per_object.items():
        out = subprocess.run(
            ["addr2line", "-e", obj, *(hex(a) for a, _ in queries)], capture_output=True, text=True
        ).stdout.splitlines()
        for (_, n), where in zip(queries, out, strict=False):
            lines[where.rsplit("/", 1)[-1]] += n
    print(
        json.dumps(
            {
                "samples": total,
                "reference_counting_share": round(nrt / total, 4) if total else None,
                "lines": [
                    {"line": k, "share": round(v / total, 4)}
                    for k, v in lines.most_common(args.top)
                ],
            }
        )
    )
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
