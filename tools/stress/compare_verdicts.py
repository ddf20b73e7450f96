#!/usr/bin/python3
"""Compares the verdict columns of two gimbalsim_stress CSVs (e.g. the grid
run before and after a change): every run is matched by (group, scene, sets);
prints the runs present in only one and the runs whose verdict differs.
Exit 0 when both CSVs have the same runs with the same verdicts, 1 otherwise.

    /usr/bin/python3 tools/stress/compare_verdicts.py BEFORE.csv AFTER.csv
"""
import collections
import csv
import sys
import os
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pages"))
import output_file  # noqa: E402,F401  (its import keeps the console: a reader gone stops nothing)


def verdicts(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    out = collections.Counter()
    for r in rows:
        out[(r["group"], r["scene"], r["sets"], r["verdict"])] += 1
    return rows, out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    (ra, a), (rb, b) = verdicts(sys.argv[1]), verdicts(sys.argv[2])
    only_a, only_b = a - b, b - a
    for (g, s, sets, v), n in sorted(only_a.items()):
        print(f"before only: {v:15s} {g} / {s} / {sets}" + (f" (x{n})" if n > 1 else ""))
    for (g, s, sets, v), n in sorted(only_b.items()):
        print(f"after only:  {v:15s} {g} / {s} / {sets}" + (f" (x{n})" if n > 1 else ""))
    count = lambda rows: collections.Counter(r["verdict"] for r in rows)  # noqa: E731
    print(f"before: {len(ra)} runs {dict(sorted(count(ra).items()))}")
    print(f"after:  {len(rb)} runs {dict(sorted(count(rb).items()))}")
    same = not only_a and not only_b
    print("verdicts identical run for run" if same else "VERDICTS DIFFER")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
