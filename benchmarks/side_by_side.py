"""Two versions of brakeca timed side by side, in pairs, on the same stops.

    python benchmarks/side_by_side.py OLD_SRC NEW_SRC [--pairs 4] [--stops 12] [--rows 201]
        [--wp 1e-13] [--set A=10 ...] [--resume STATE.pkl] [--out DIR]

``OLD_SRC`` and ``NEW_SRC`` are ``src`` folders of two checkouts (``git worktree add`` or
``git archive REV src | tar -x -C DIR``). Each pair runs ``benchmarks/stop_times.py run`` with
each version at the same time, one per core (``taskset``), the old one on core 0 in odd pairs
and on core 1 in even pairs, so that a core slower than the other (this machine is a virtual
machine on a shared host: docs/performance.md) weighs on both versions alike. Each version
compiles into its own numba cache folder under ``--out`` (once: the first pair's first stop is
timed apart by ``stop_times.py`` and not counted). Defaults: test 5's levels (the study's most
expensive run), the first 12 stops, full resolution.

``--resume STATE.pkl`` starts both versions from a state ``stop_times.py run --save-at N``
saved (with the same ``--rows``, ``--wp`` and ``--set``), so ``--stops`` counts on from stop
N + 1: the cheap way to compare late stops (the country-road blocks) without running the
cycle up to them in every pair.

Prints one JSON line per pair (both versions' summed stop times [s] and new/old) and a last
line with the mean and standard deviation of the ratios. Needs 2 cores and Linux's
``taskset``.

With ``--alike``, each pair is two rounds instead: the old version on both cores at once,
then the new one on both cores at once (the new one first in even pairs), as a study's two
workers run one kernel. A pair's ratio is the new round's mean over the old round's. The two
processes of a round share the L3 cache and the memory bus, so a change that makes one
process take more of them can look faster beside a process of the other version than it is
beside itself; ``--alike`` measures what a study sees.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _stop_seconds(path: Path) -> float:
    total = 0.0
    for line in path.read_text().splitlines():
        row = json.loads(line)
        if "stop" in row:
            total += row["s"]
    return total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old", type=Path, help="src folder of the old version")
    ap.add_argument("new", type=Path, help="src folder of the new version")
    ap.add_argument("--pairs", type=int, default=4)
    ap.add_argument("--stops", type=int, default=12)
    ap.add_argument("--rows", type=int, default=201)
    ap.add_argument("--wp", default="1e-13")
    ap.add_argument("--set", action="append", default=None, metavar="KEY=VALUE")
    ap.add_argument("--resume", type=Path, default=None, metavar="STATE.pkl")
    ap.add_argument("--out", type=Path, default=Path("side_by_side"))
    ap.add_argument(
        "--alike",
        action="store_true",
        help="each version on both cores at once, in alternate rounds (what a study sees)",
    )
    args = ap.parse_args()
    sets = args.set if args.set is not None else ["A=10"]
    for src in (args.old, args.new):
        if not (src / "brakeca" / "__init__.py").exists():
            ap.error(f"{src}: not a src folder holding brakeca")
    if args.pairs < 1 or args.stops < 1 or args.rows < 2:
        ap.error("--pairs and --stops must be >= 1, --rows >= 2")
    if args.resume is not None and not args.resume.is_file():
        ap.error(f"--resume {args.resume}: no such file")
    args.out.mkdir(parents=True, exist_ok=True)
    srcs = {"old": args.old, "new": args.new}
    first = 0
    if args.resume is not None:
        import pickle

        with open(args.resume, "rb") as fh:
            first = int(pickle.load(fh)[2])

    def start(name: str, core: int, out: Path) -> subprocess.Popen:
        env = dict(
            os.environ,
            PYTHONPATH=str(srcs[name].resolve()),
            NUMBA_CACHE_DIR=str((args.out / f"numba_{name}").resolve()),
        )
        cmd = ["taskset", "-c", str(core), sys.executable, str(HERE / "stop_times.py")]
        cmd += ["run", "-o", str(out), "--rows", str(args.rows)]
        cmd += ["--wp", args.wp, "--set", f"cycle.max_stops={first + args.stops}"]
        if args.resume is not None:
            cmd += ["--resume", str(args.resume.resolve())]
        for item in sets:
            cmd += ["--set", item]
        return subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL)

    def wait(procs: dict) -> None:
        for name, proc in procs.items():
            if proc.wait() != 0:
                for other in procs.values():
                    other.kill()  # no run left behind on the other core
                sys.exit(f"the {name} version failed (exit {proc.returncode})")

    ratios = []
    for k in range(1, args.pairs + 1):
        if args.alike:
            times = {}
            for name in ("old", "new") if k % 2 else ("new", "old"):
                outs = [args.out / f"{name}_{k}_core{core}.jsonl" for core in (0, 1)]
                procs = {f"{name} (core {core})": start(name, core, outs[core]) for core in (0, 1)}
                wait(procs)
                times[name] = [round(_stop_seconds(out), 3) for out in outs]
            old = statistics.mean(times["old"])
            new = statistics.mean(times["new"])
            row = {"pair": k, "old_s": times["old"], "new_s": times["new"]}
        else:
            cores = {"old": 0 if k % 2 else 1, "new": 1 if k % 2 else 0}
            procs = {
                name: start(name, cores[name], args.out / f"{name}_{k}.jsonl") for name in srcs
            }
            wait(procs)
            old = _stop_seconds(args.out / f"old_{k}.jsonl")
            new = _stop_seconds(args.out / f"new_{k}.jsonl")
            row = {
                "pair": k,
                "old_core": cores["old"],
                "old_s": round(old, 3),
                "new_s": round(new, 3),
            }
        ratios.append(new / old)
        row["new_over_old"] = round(new / old, 3)
        print(json.dumps(row), flush=True)
    sd = statistics.stdev(ratios) if len(ratios) > 1 else 0.0
    print(
        json.dumps(
            {
                "pairs": len(ratios),
                "mean_new_over_old": round(statistics.mean(ratios), 3),
                "sd": round(sd, 3),
            }
        )
    )


if __name__ == "__main__":
    main()
