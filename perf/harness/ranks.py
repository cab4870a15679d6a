#!/usr/bin/env python3
"""Strong and weak scaling of a scene over MPI ranks (docs/distributed.md).

Usage:  /usr/bin/python3 perf/harness/ranks.py [--harness PATH] [--ranks 1,2]
            [--methods pcg-gamg,mumps] [--family cantilever]
            [--strong-size 100x20x20] [--weak-cells 50x10x10] [--steps 5]
            [--out results/ranks]

Runs `mpiexec -n R superdex_perf run ... --format json` for every rank count
R and method:
  strong  the same scene (--strong-size) on every R;
  weak    a scene R times as large along x: --weak-cells NXxNYxNZ becomes
          (R·NX)xNYxNZ, about R times the DoFs, the same per rank.
mpiexec gets --oversubscribe, and --allow-run-as-root when run as root.

Output (into --out):
  ranks.csv           one row per run: study, method, ranks, dofs, dofs per
                      rank, wall and steady time per step, parallel
                      efficiency (strong: t1 / (R tR); weak: t1 / tR, both on
                      the steady time), peak memory per rank (the largest
                      rank's), Newton and linear iterations, status, reason.
  strong_scaling.png  steady time per step against ranks (log-log), one line
                      per method, with each method's ideal t1 / R dashed.
  weak_scaling.png    steady time per step against ranks, with the ideal
                      (flat) line, and the efficiency per point.
Exit status: 0 when every run succeeded, 1 otherwise.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys


def run(harness, ranks, family, size, method, steps):
    launcher = shutil.which("mpiexec") or shutil.which("mpirun")
    command = [launcher, "--oversubscribe"]
    if os.geteuid() == 0:
        command.append("--allow-run-as-root")
    command += ["-n", str(ranks), harness, "run", "--family", family, "--size", size,
                "--method", method, "--steps", str(steps), "--format", "json"]
    done = subprocess.run(command, capture_output=True, text=True)
    for line in done.stdout.splitlines():
        if line.startswith("{"):
            return json.loads(line)
    return {"status": "failed", "reason": (done.stderr or done.stdout).strip()[-300:]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--harness", default="build/perf/harness/superdex_perf")
    parser.add_argument("--ranks", default="1,2")
    parser.add_argument("--methods", default="pcg-gamg,mumps")
    parser.add_argument("--family", default="cantilever")
    parser.add_argument("--strong-size", default="100x20x20")
    parser.add_argument("--weak-cells", default="50x10x10")
    parser.add_argument("--steps", type=int, default=5)
    parser.add_argument("--out", default="results/ranks")
    args = parser.parse_args()
    ranks = [int(r) for r in args.ranks.split(",")]
    methods = args.methods.split(",")
    nx, ny, nz = (int(c) for c in args.weak_cells.split("x"))
    os.makedirs(args.out, exist_ok=True)

    rows = []
    for study in ("strong", "weak"):
        for method in methods:
            base = None
            for r in ranks:
                size = args.strong_size if study == "strong" else f"{r * nx}x{ny}x{nz}"
                result = run(args.harness, r, args.family, size, method, args.steps)
                ok = result.get("status") == "ok"
                steady = result.get("steady_per_step_s") if ok else None
                if r == ranks[0] and ok:
                    base = (r, steady)
                efficiency = None
                if ok and base:
                    r0, t0 = base
                    efficiency = (t0 * r0) / (steady * r) if study == "strong" else t0 / steady
                dofs = result.get("dofs")
                row = {"study": study, "method": method, "ranks": r, "size": size, "dofs": dofs,
                       "dofs_per_rank": dofs / r if dofs else None,
                       "wall_per_step_s": result.get("wall_per_step_s"), "steady_per_step_s": steady,
                       "efficiency": efficiency, "peak_rss_mb_per_rank": result.get("peak_rss_mb"),
                       "newton_iterations": result.get("newton_iterations"),
                       "linear_iterations": result.get("linear_iterations"),
                       "status": result.get("status"), "reason": result.get("reason", "")}
                rows.append(row)
                print(", ".join(f"{k}={v}" for k, v in row.items() if k != "reason" or v), flush=True)

    with open(os.path.join(args.out, "ranks.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for study in ("strong", "weak"):
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for method in methods:
            points = [(r["ranks"], r["steady_per_step_s"], r["efficiency"]) for r in rows
                      if r["study"] == study and r["method"] == method and r["steady_per_step_s"]]
            if not points:
                continue
            x = [p[0] for p in points]
            y = [p[1] for p in points]
            line, = ax.plot(x, y, "o-", label=method)
            ideal = [y[0] * x[0] / r for r in x] if study == "strong" else [y[0]] * len(x)
            ax.plot(x, ideal, "--", color=line.get_color(), alpha=0.6, label=f"{method} ideal")
            for r, t, e in points:
                if e is not None and r != x[0]:
                    ax.annotate(f"{100 * e:.0f} %", (r, t), textcoords="offset points", xytext=(5, 5))
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xticks(ranks)
        ax.set_xticklabels([str(r) for r in ranks])
        ax.set_xlabel("MPI ranks")
        ax.set_ylabel("time per step, without the one-time analysis [s]")
        what = (f"{args.family} {args.strong_size}" if study == "strong"
                else f"{args.family} (R·{nx})x{ny}x{nz}")
        ax.set_title(f"{study} scaling: {what}, {args.steps} steps")
        ax.legend(fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        path = os.path.join(args.out, f"{study}_scaling.png")
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        print("wrote", path)
    return 0 if all(r["status"] == "ok" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
