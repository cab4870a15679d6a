"""Compares the final-state hashes of two perf harness runs, row by row.

A change that must not alter behaviour (a refactoring, a faster kernel that
adds the same numbers in the same order) leaves every run's final state
identical bit for bit: the `state_hash` column of results.csv is then equal
on every row. Rows are matched by their settings (study, family, size,
method, ...), not by position; a row present in one file only, or a status
that differs, counts as a mismatch too.

usage: compare_state_hashes.py BEFORE/results.csv AFTER/results.csv
Exits 0 when every row matches, 1 otherwise (the mismatches are listed).
"""
import csv
import sys

KEY = ("suite", "study", "family", "size", "stiffness_ratio", "method", "rtol", "newton_tol",
       "constraint_hessian", "near_rigid", "integrator", "dt", "end_time")


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    table = {}
    for row in rows:
        key = tuple(row.get(k, "") for k in KEY)
        # a key seen twice (a suite runs the same settings in two studies
        # under one label) keeps every occurrence, in order
        table.setdefault(key, []).append((row.get("status", ""), row.get("state_hash", "")))
    return table


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    before, after = load(sys.argv[1]), load(sys.argv[2])
    mismatches = []
    for key in sorted(set(before) | set(after)):
        a, b = before.get(key), after.get(key)
        if a != b:
            mismatches.append((key, a, b))
    for key, a, b in mismatches:
        label = " ".join(f"{k}={v}" for k, v in zip(KEY, key) if v)
        print(f"differs: {label}\n  before {a}\n  after  {b}")
    total = len(set(before) | set(after))
    rows = sum(len(v) for v in after.values())
    print(f"compare_state_hashes: {total - len(mismatches)} of {total} settings equal "
          f"({rows} rows after), {len(mismatches)} differ")
    return 1 if mismatches else 0


if __name__ == "__main__":
    sys.exit(main())
