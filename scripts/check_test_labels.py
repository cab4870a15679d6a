#!/usr/bin/env python3
"""Every ctest test carries at least one label of the documented set
(docs/testing.md), so that `ctest -L <label>` and `ctest -LE slow` select
what they say. Reads the test list of a build directory through
`ctest --show-only=json-v1`; prints the count per label.

usage: check_test_labels.py CTEST BUILD_DIR
"""
import collections
import json
import subprocess
import sys

LABELS = {"unit", "slow", "mpi", "python", "fuzz", "install", "perf", "examples", "docs"}


def main(ctest, build_dir):
    listing = subprocess.run([ctest, "--test-dir", build_dir, "--show-only=json-v1"],
                             check=True, capture_output=True, text=True).stdout
    counts = collections.Counter()
    unlabelled = []
    for test in json.loads(listing)["tests"]:
        labels = set()
        for prop in test.get("properties", []):
            if prop["name"] == "LABELS":
                labels.update(prop["value"])
        if not labels & LABELS:
            unlabelled.append(f"{test['name']} (labels: {sorted(labels) or 'none'})")
        counts.update(labels)
    for label, count in sorted(counts.items()):
        print(f"{label:>10}: {count} tests")
    if unlabelled:
        print(f"{len(unlabelled)} tests carry none of {sorted(LABELS)}:")
        for line in unlabelled:
            print("  " + line)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
