"""Is a paper study bit-identical to the reference study? Compare its summary.csv, value by value.

    python benchmarks/study_check.py check results/paper
    python benchmarks/study_check.py save results/paper      # replace the reference (see below)

A kernel change is called bit-identical only once the whole paper study gives the same
``summary.csv`` in every column but the wall times (docs/performance.md, "Results stay
bit-identical"): the four short fingerprint cases missed a change that altered seven of the
study's 24 runs at round-off. The reference is ``benchmarks/paper_study_reference.csv``, the
``summary.csv`` of a full-resolution ``scripts/paper`` study without its ``wall_time`` column,
kept in the repository so the check does not depend on an earlier study's folder.

``check`` compares the two files as text, cell by cell (``summary.csv`` writes every float with
Python's shortest round-trip repr, so equal text is equal bits), rows matched by (test,
replicate). It prints one line per differing value and a last line with the count, and exits
with status 1 if any value, row or column differs, 0 if none does. ``save`` writes the
reference from a study's ``summary.csv``; do that only for a change that is meant to change
results, and say so in the commit.
"""

from __future__ import annotations

import argparse
import csv
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path

#: the reference study's summary, without the columns that vary from one run to the next
REFERENCE = Path(__file__).with_name("paper_study_reference.csv")

#: columns that are not results (they vary with the host)
IGNORED = ("wall_time",)

Table = dict[tuple[str, str], dict[str, str]]


def read_table(path: Path) -> tuple[list[str], Table]:
    """The columns and the rows (keyed by test and replicate, values as text) of a summary CSV."""
    with path.open(newline="") as handle:
        reader = csv.DictReader(handle)
        if reader.fieldnames is None or not {"test", "replicate"} <= set(reader.fieldnames):
            raise ValueError(f"{path}: not a campaign summary (no test and replicate columns)")
        columns = [c for c in reader.fieldnames if c not in IGNORED]
        rows: Table = {}
        for row in reader:
            key = (row["test"], row["replicate"])
            if key in rows:
                raise ValueError(f"{path}: test {key[0]}, replicate {key[1]} appears twice")
            rows[key] = {c: row[c] for c in columns}
    return columns, rows


def _in_order(keys: Iterable[tuple[str, str]]) -> list[tuple[str, str]]:
    """(test, replicate) keys sorted as numbers."""
    return sorted(keys, key=lambda k: (int(k[0]), int(k[1])))


def differences(reference: Path, study: Path) -> list[str]:
    """Every way ``study``'s summary differs from ``reference``'s, one line each (none: equal)."""
    ref_columns, ref_rows = read_table(reference)
    new_columns, new_rows = read_table(study)
    found = [f"column {c!r} only in the reference" for c in ref_columns if c not in new_columns]
    found += [f"column {c!r} only in the study" for c in new_columns if c not in ref_columns]
    for t, r in _in_order(ref_rows.keys() - new_rows.keys()):
        found.append(f"test {t}, replicate {r}: only in the reference")
    for t, r in _in_order(new_rows.keys() - ref_rows.keys()):
        found.append(f"test {t}, replicate {r}: only in the study")
    shared = [c for c in ref_columns if c in new_columns]
    for key in _in_order(ref_rows.keys() & new_rows.keys()):
        old, new = ref_rows[key], new_rows[key]
        found += [
            f"test {key[0]}, replicate {key[1]}, {c}: reference {old[c]}, study {new[c]}"
            for c in shared
            if old[c] != new[c]
        ]
    return found


def save(study: Path, reference: Path) -> int:
    """Write ``reference`` from ``study``'s summary without the ignored columns; the row count."""
    columns, rows = read_table(study)
    with reference.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns, lineterminator="\n")
        writer.writeheader()
        for key in _in_order(rows):
            writer.writerow(rows[key])
    return len(rows)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("action", choices=("check", "save"))
    ap.add_argument("study", type=Path, help="a study's folder (or its summary.csv)")
    ap.add_argument("--reference", type=Path, default=REFERENCE, help="default: %(default)s")
    args = ap.parse_args(argv)
    summary = args.study / "summary.csv" if args.study.is_dir() else args.study
    if not summary.is_file():
        ap.error(f"no summary.csv at {summary}: has the study finished?")
    try:
        if args.action == "save":
            n = save(summary, args.reference)
            print(f"wrote {args.reference} ({n} runs)")
            return 0
        found = differences(args.reference, summary)
    except ValueError as err:  # not a campaign summary, or a run twice in it
        ap.error(str(err))
    for line in found:
        print(line)
    print(f"{len(found)} difference(s) between {summary} and {args.reference}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
