#!/usr/bin/python3
"""Compares the verdict columns of two gimbalsim_stress CSVs (e.g. the grid
run before and after a change): every run is matched by (group, scene, sets);
prints the runs present in only one and the runs whose verdict differs.
Exit 0 when both CSVs have the same runs with the same verdicts, 1 otherwise
(as cmp), 2 when a file is not a stress CSV: no run, a run twice, a verdict
the tool does not give.

    /usr/bin/python3 tools/stress/compare_verdicts.py BEFORE.csv AFTER.csv
"""
import argparse
import collections
import csv
import os
import stat
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pages"))
import output_file  # noqa: E402,F401  (its import keeps the console: a reader gone stops nothing)


COLUMNS = ("group", "scene", "sets", "verdict")
VERDICTS = ("TRUSTWORTHY", "STOPPED", "SILENTLY_WRONG", "STOPPED_UNCLEAR", "REFUSED")  # stress_check.cpp verdictName


def verdicts(path):
    """(rows, set of (group, scene, sets, verdict)); Refused naming the file when it holds no stress runs, a run
    twice, or a verdict the tool does not give."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):  # a pipe would block, a device never end
            raise output_file.Refused(f"{path}: not a regular file (a pipe, a device or a folder)")
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            header = reader.fieldnames or []
            missing = [c for c in COLUMNS if c not in header]
            if missing:
                raise output_file.Refused(f"{path}: not a gimbalsim_stress CSV (no column {', '.join(missing)})")
            twice = sorted({c for c in header if header.count(c) > 1})
            if twice:
                raise output_file.Refused(f"{path}:1: column {twice[0]} appears twice: which one is the run's?")
            rows, line_of = [], {}
            for r in reader:  # every row whole, with its verdict: a cut or edited row is no run
                if None in r or None in r.values():
                    raise output_file.Refused(f"{path}:{reader.line_num}: not the header's {len(header)} fields")
                if not r["verdict"]:
                    raise output_file.Refused(f"{path}:{reader.line_num}: no verdict")
                if r["verdict"] not in VERDICTS:  # (pass 45: 'BOGUS' was compared as a verdict)
                    raise output_file.Refused(f"{path}:{reader.line_num}: verdict {r['verdict']!r} is none the "
                                              f"stress tool gives ({', '.join(VERDICTS)})")
                run = tuple(r[c] for c in COLUMNS[:3])  # the grid makes each run once: a second is no run of it
                if run in line_of:
                    raise output_file.Refused(f"{path}:{reader.line_num}: the run of line {line_of[run]} again "
                                              f"({' / '.join(run)})")
                line_of[run] = reader.line_num
                rows.append(r)
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise output_file.Refused(f"{path}: cannot read it ({e})") from None
    if not rows:
        raise output_file.Refused(f"{path}: no runs: nothing to compare")
    return rows, {tuple(r[c] for c in COLUMNS) for r in rows}


def main():
    p = argparse.ArgumentParser(allow_abbrev=False, description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("before")
    p.add_argument("after")
    a = p.parse_args()
    (ra, a_), (rb, b) = verdicts(a.before), verdicts(a.after)
    only_a, only_b = a_ - b, b - a_
    for (g, s, sets, v) in sorted(only_a):
        print(f"before only: {v:15s} {g} / {s} / {sets}")
    for (g, s, sets, v) in sorted(only_b):
        print(f"after only:  {v:15s} {g} / {s} / {sets}")
    count = lambda rows: collections.Counter(r["verdict"] for r in rows)  # noqa: E731
    print(f"before: {len(ra)} runs {dict(sorted(count(ra).items()))}")
    print(f"after:  {len(rb)} runs {dict(sorted(count(rb).items()))}")
    same = not only_a and not only_b
    print("verdicts identical run for run" if same else "VERDICTS DIFFER")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(output_file.run_script("compare_verdicts", main))
