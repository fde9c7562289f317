"""A whole run timed stop by stop, one JSON line per stop, and a table per block of the cycle.

Usage:
    python benchmarks/stop_times.py run -o stops.jsonl [--kernel auto] [--rows 201] [--wp 1e-13]
        [--set A=10 ...] [--save-at 80 --save-dir states/] [--resume states/state_201_80.pkl]
    python benchmarks/stop_times.py table stops.jsonl [other.jsonl ...]

``run`` drives the paper cycle stop by stop (``advance_stop`` and ``end_of_stop``, as
``simulate`` does) from the surface of ``--seed`` and writes, for every stop, its wall time [s],
its steps, the lazy kernel's solver counters per step (solves that walked, breakpoints walked,
envelope iterations, jumps), the share of each kernel phase (the kernel's cycle counters), the
mean contact area fraction and the rule firings per step. Compiling or loading the kernels
is timed first, on a throwaway state (the header line's ``compile_and_first_stop_s``), so the
first stop's own time excludes it. ``table`` sums the stops of each block of the cycle, for one
file or several side by side (each column headed by its kernel and file).

``--set KEY=VALUE`` sets any other configuration field, as ``brakeca simulate --set`` does
(the study's most expensive run, test 5, is ``--wp 1e-13 --set A=10``). ``--save-at N``
pickles ``(state, rng, N)`` after stop N into ``--save-dir``, as ``state_<rows>_<N>.pkl``;
``--resume FILE`` starts from such a file at stop N + 1, to time late stops again without
running the cycle up to them (the same ``--rows``, ``--wp`` and ``--set`` as the run that saved
it; the state is the grid and the streams, so a version whose kernel differs can resume the
state another version saved: ``side_by_side.py --resume``).
"""

from __future__ import annotations

import argparse
import json
import pickle
import sys
import time
from pathlib import Path

import numpy as np


def run(args: argparse.Namespace) -> None:
    from brakeca import _kernels as K
    from brakeca.config import parse_override
    from brakeca.cycle import expand_stops
    from brakeca.geometry import make_grid
    from brakeca.presets import load_preset
    from brakeca.simulation import SimulationState, advance_stop, end_of_stop, kernel_for
    from brakeca.surface import generate_surface

    updates: dict[str, object] = {
        "mesh.n_radial": args.rows,
        "WP": args.wp,
        "numerics.kernel": args.kernel,
    }
    updates.update(parse_override(item) for item in args.set)
    config = load_preset().with_updates(updates)
    save_at = set(args.save_at)
    if save_at:  # (it had failed writing the first state, after the stops before it)
        Path(args.save_dir).mkdir(parents=True, exist_ok=True)
    grid = make_grid(config)
    stops = expand_stops(config)
    # compile (or load from the cache) on a throwaway state first
    t = time.perf_counter()
    scratch = SimulationState.from_surface(
        generate_surface(config.pad, grid, np.random.default_rng(0)), grid
    )
    advance_stop(scratch, grid, config, stops[0])
    compile_s = time.perf_counter() - t
    del scratch
    first = 0
    if args.resume:
        with open(args.resume, "rb") as fh:
            saved = pickle.load(fh)
        if not (isinstance(saved, tuple) and len(saved) == 3):
            sys.exit(f"{args.resume}: not a state saved by --save-at (state, rng, stop)")
        state, rng, first = saved
        if state.height.size != grid.shape[0] * grid.shape[1]:
            sys.exit(
                f"{args.resume}: {state.height.size} cells, not this run's {grid.shape} "
                "(give the --rows of the run that saved it)"
            )
        # the lazy kernel's structures are rebuilt from the grid at every stop: drop a saved
        # copy, whose layout may be another version's (a state saved by one version then
        # resumes in any, as side_by_side.py --resume needs)
        state.lazy = None
    else:
        rng = np.random.default_rng(args.seed)
        state = SimulationState.from_surface(generate_surface(config.pad, grid, rng), grid)
    with open(args.output, "w") as out:
        out.write(
            json.dumps(
                {
                    "kernel": kernel_for(config),
                    "grid": f"{grid.shape[0]}x{grid.shape[1]}",
                    "wp": args.wp,
                    "seed": args.seed,
                    "set": args.set,
                    "compile_and_first_stop_s": round(compile_s, 3),
                    "resumed_after_stop": first,
                }
            )
            + "\n"
        )
        for stop in stops:
            if stop.index <= first:
                continue
            w0 = state.lazy_walk.copy()
            p0 = state.prof.copy()
            t = time.perf_counter()
            dt, rec, counts = advance_stop(state, grid, config, stop)
            elapsed = time.perf_counter() - t
            end_of_stop(state, config.automaton.secondary_removal_fraction, rng)
            walk = (state.lazy_walk - w0) / dt.size
            prof = state.prof - p0
            line = {
                "stop": stop.index,
                "block": stop.block,
                "s": round(elapsed, 3),
                "steps": int(dt.size),
                "walk": walk[:4].round(2).tolist(),
                "prof": (prof / max(prof.sum(), 1)).round(3).tolist(),
                "contact": float(rec[:, K.R_CONTACT_AREA].mean() / grid.area),
                "rules_per_step": (counts / dt.size).round(1).tolist(),
            }
            out.write(json.dumps(line) + "\n")
            out.flush()
            if stop.index in save_at:
                path = f"{args.save_dir}/state_{args.rows}_{stop.index}.pkl"
                with open(path, "wb") as fh:
                    lazy, state.lazy = state.lazy, None  # rebuilt at every stop: not saved
                    pickle.dump((state, rng, stop.index), fh)
                    state.lazy = lazy


def table(paths: list[str]) -> None:
    names = [Path(path).name for path in paths]
    runs = []
    for path in paths:
        with open(path) as fh:
            lines = [json.loads(line) for line in fh]
        runs.append((lines[0], [line for line in lines if "stop" in line]))
    blocks: list[tuple[str, int, int]] = []
    for line in runs[0][1]:
        if not blocks or blocks[-1][0] != line["block"]:
            blocks.append((line["block"], line["stop"], line["stop"]))
        else:
            blocks[-1] = (blocks[-1][0], blocks[-1][1], line["stop"])
    head = " | ".join(
        f"{h['kernel']}, {name} [s]" for (h, _), name in zip(runs, names, strict=True)
    )
    print(f"| block | stops | steps | {head} |")
    print("|---|---|---|" + "---|" * len(runs))
    totals = [0.0] * len(runs)
    for name, first, last in blocks:
        cells = []
        steps = 0  # the most of any file's (a resumed run's file holds fewer stops)
        for k, (_, stops) in enumerate(runs):
            group = [s for s in stops if first <= s["stop"] <= last]
            seconds = sum(s["s"] for s in group)
            totals[k] += seconds
            steps = max(steps, sum(s["steps"] for s in group))
            cells.append(f"{seconds:.1f}")
        print(f"| {name} | {first}–{last} | {steps:,} | " + " | ".join(cells) + " |")
    print("| whole cycle | | | " + " | ".join(f"**{t:.0f}**" for t in totals) + " |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run")
    r.add_argument("-o", "--output", required=True)
    r.add_argument("--kernel", default="auto", choices=["auto", "lazy", "exact"])
    r.add_argument("--rows", type=int, default=201)
    r.add_argument("--wp", type=float, default=1e-13)
    r.add_argument("--seed", type=int, default=2016)
    r.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    r.add_argument("--save-at", type=int, action="append", default=[], metavar="STOP")
    r.add_argument("--save-dir", default=".")
    r.add_argument("--resume", default=None, metavar="FILE", help="a state saved by --save-at")
    t = sub.add_parser("table")
    t.add_argument("paths", nargs="+")
    args = ap.parse_args()
    if args.command == "run":
        run(args)
    else:
        table(args.paths)


if __name__ == "__main__":
    sys.exit(main())
