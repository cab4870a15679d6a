"""Interleaved A/B timing of two builds of the perf harness on the same runs.

A change that must not make stepping slower is measured by running the
harness binary before and after it alternately (A, B, A, B, ...), so that a
drift of the machine's load falls on both, and comparing the medians of the
steady cost per step (steady_per_step_s: the step without the one-time
analysis). The final-state hashes of the two builds are compared too.

usage: ab_timing.py BEFORE_BIN AFTER_BIN [--rounds N] [--threads T] [--steps S]
                    [--case FAMILY:SIZE[:EXTRA ARGS]]...
With no --case: cantilever 40x8x8, rods 25x100 and chain-articulated N=1000.
BEFORE_BIN and AFTER_BIN are superdex_perf executables; a library directory
can be given as BIN=LIBDIR to run with LD_LIBRARY_PATH=LIBDIR.
"""
import argparse
import csv
import io
import os
import statistics
import subprocess
import sys

DEFAULT_CASES = ["cantilever:40x8x8", "rods:25x100", "chain-articulated:N=1000"]


def run(binary, case, threads, steps):
    path, _, libdir = binary.partition("=")
    family, size, *extra = case.split(":")
    env = dict(os.environ)
    if libdir:
        env["LD_LIBRARY_PATH"] = libdir
    args = [path, "run", "--family", family, "--size", size, "--threads", str(threads), "--steps", str(steps)]
    for item in extra:
        args += item.split()
    out = subprocess.run(args, env=env, capture_output=True, text=True, check=True).stdout
    row = list(csv.DictReader(io.StringIO(out[out.index("suite,"):])))[0]
    if row["status"] != "ok":
        sys.exit(f"ab_timing: {case} failed with {path}: {row['reason']}")
    return float(row["steady_per_step_s"]), row["state_hash"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--case", action="append")
    args = parser.parse_args()
    cases = args.case or DEFAULT_CASES
    print(f"{'case':32s} {'before ms':>10s} {'after ms':>10s} {'after/before':>13s}  hashes")
    for case in cases:
        before, after, hashes = [], [], set()
        for _ in range(args.rounds):
            t, h = run(args.before, case, args.threads, args.steps)
            before.append(t)
            hashes.add(("before", h))
            t, h = run(args.after, case, args.threads, args.steps)
            after.append(t)
            hashes.add(("after", h))
        a, b = statistics.median(before), statistics.median(after)
        same = len({h for _, h in hashes}) == 1
        print(f"{case:32s} {1e3 * a:10.3f} {1e3 * b:10.3f} {b / a:13.3f}  {'equal' if same else 'DIFFER'}",
              flush=True)


if __name__ == "__main__":
    main()
