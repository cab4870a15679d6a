#!/usr/bin/python3
"""Plots the output of superdex_rods.

usage: plot.py DIR [--dpi N] [--png PATH]

Reads DIR/rods.csv and the frames listed in DIR/rods.pvd and writes
DIR/rods.png (or PATH) with three panels: a side view (x-y) of the three rods
at six times, each drawn in the colour of its twist angle; an end view (y-z,
looking down the spin axis) of the rod tips' paths; and the axial torque the
rods' clamps put on the hub with the axis rod's twist at its middle and tip
over time.

Run it with Debian's /usr/bin/python3 (numpy and matplotlib).
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vtu import read_polylines, read_pvd  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir")
    parser.add_argument("--dpi", type=int, default=110)
    parser.add_argument("--png")
    args = parser.parse_args()
    series = read_csv(os.path.join(args.dir, "rods.csv"))
    frames = read_pvd(os.path.join(args.dir, "rods.pvd"))
    if not frames:
        sys.exit("no frames in rods.pvd")

    fig, (side, end, history) = plt.subplots(1, 3, figsize=(15, 4.6))
    # side view at six times spread over the run, coloured by twist
    end_time = frames[-1][0]
    wanted = np.linspace(0, end_time, 6)
    chosen = sorted({min(range(len(frames)), key=lambda i: abs(frames[i][0] - t)) for t in wanted})
    twists = []
    shapes = []
    for index in chosen:
        time, path = frames[index]
        points, lines, data = read_polylines(path)
        twists.append(np.atleast_1d(data["twist"]))
        shapes.append((time, points, lines))
    limit = max(np.abs(np.concatenate(twists)).max(), 1e-6)
    for (time, points, lines), twist in zip(shapes, twists):
        for line in lines:
            xy = points[line][:, :2]
            segments = np.stack([xy[:-1], xy[1:]], axis=1)
            collection = LineCollection(segments, cmap="coolwarm", norm=plt.Normalize(-limit, limit), linewidth=2)
            collection.set_array(twist[line][:-1])
            side.add_collection(collection)
        tip = points[lines[0][-1]]
        side.annotate(f"{time:.2f} s", tip[:2], textcoords="offset points", xytext=(4, -2), fontsize=7)
    side.autoscale()
    side.set_aspect("equal")
    side.set_xlabel("x [m]")
    side.set_ylabel("y [m]")
    side.set_title("side view, colour = twist θ")
    fig.colorbar(collection, ax=side, label="twist θ [rad]", shrink=0.8)

    # tip paths, looking down the spin axis
    for r, colour in zip(range(3), ("k", "tab:blue", "tab:orange")):
        end.plot(series[f"tip{r}_z"], series[f"tip{r}_y"], color=colour, linewidth=1, label=f"rod {r} tip")
        end.plot(series[f"tip{r}_z"][-1], series[f"tip{r}_y"][-1], "o", color=colour, markersize=4)
    end.set_aspect("equal")
    end.set_xlabel("z [m]")
    end.set_ylabel("y [m]")
    end.set_title("tip paths, end view (down the spin axis)")
    end.legend(fontsize=8)

    history.plot(series["t"], series["hub_torque_x"], color="k", label="clamp torque on hub [N m]")
    history.set_xlabel("t [s]")
    history.set_ylabel("torque about x [N m]")
    twin = history.twinx()
    twin.plot(series["t"], series["axis_twist_mid"], color="tab:red", linewidth=1, label="axis rod θ, middle")
    twin.plot(series["t"], series["axis_twist_tip"], color="tab:purple", linewidth=1, label="axis rod θ, tip")
    twin.plot(series["t"], series["hub_angle"], color="tab:gray", linestyle="--", linewidth=1, label="hub angle")
    twin.set_ylabel("angle [rad]")
    lines = history.get_legend_handles_labels()
    more = twin.get_legend_handles_labels()
    history.legend(lines[0] + more[0], lines[1] + more[1], fontsize=7, loc="lower right")
    history.set_title("hub torque and twist")

    fig.tight_layout()
    out = args.png or os.path.join(args.dir, "rods.png")
    fig.savefig(out, dpi=args.dpi)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
