#!/usr/bin/python3
"""Plots the output of superdex_double_pendulum.

usage: plot.py DIR [--dpi N] [--png PATH]

Reads DIR/double_pendulum.csv and writes DIR/double_pendulum.png (or PATH)
with two panels: the path of the second rod's tip coloured by time, and the
kinetic, potential and total energy over time.

Run it with Debian's /usr/bin/python3 (numpy and matplotlib).
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir", help="folder holding double_pendulum.csv")
    parser.add_argument("--dpi", type=int, default=120, help="resolution (default 120)")
    parser.add_argument("--png", help="output image (default DIR/double_pendulum.png)")
    args = parser.parse_args()

    csv_path = os.path.join(args.dir, "double_pendulum.csv")
    try:
        data = np.genfromtxt(csv_path, delimiter=",", names=True)
    except OSError as e:
        sys.exit(f"plot.py: cannot read {csv_path}: {e}")
    if data.size < 2:
        sys.exit(f"plot.py: {csv_path} has fewer than two rows")

    t = data["t"]
    x2, y2 = data["x2"], data["y2"]

    fig, (ax_path, ax_energy) = plt.subplots(
        1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1, 1.35]}
    )

    # ---- tip path of the second rod, coloured by time ----
    points = np.column_stack([x2, y2]).reshape(-1, 1, 2)
    segments = np.concatenate([points[:-1], points[1:]], axis=1)
    lines = LineCollection(segments, cmap="viridis", linewidth=0.8)
    lines.set_array(0.5 * (t[:-1] + t[1:]))
    ax_path.add_collection(lines)
    reach = 2.05
    ax_path.set_xlim(-reach, reach)
    ax_path.set_ylim(-reach, reach)
    ax_path.set_aspect("equal")
    ax_path.plot([0], [0], "ko", ms=5, label="pivot")
    # initial configuration
    ax_path.plot(
        [0, data["x1"][0], x2[0]], [0, data["y1"][0], y2[0]], "-o", color="0.4",
        lw=2, ms=4, label="t = 0",
    )
    ax_path.add_patch(plt.Circle((0, 0), 2.0, fill=False, ls=":", color="0.7"))
    ax_path.set_xlabel("x [m]")
    ax_path.set_ylabel("y [m]")
    ax_path.set_title("Tip path of the second rod")
    ax_path.legend(loc="lower left", fontsize=8)
    fig.colorbar(lines, ax=ax_path, label="t [s]", fraction=0.046, pad=0.04)

    # ---- energy ----
    ax_energy.plot(t, data["kinetic"], lw=0.8, label="kinetic")
    ax_energy.plot(t, data["potential"], lw=0.8, label="potential")
    ax_energy.plot(t, data["total"], lw=1.6, color="k", label="total")
    e0, e1 = data["total"][0], data["total"][-1]
    ax_energy.set_xlabel("t [s]")
    ax_energy.set_ylabel("energy [J]")
    ax_energy.set_xlim(t[0], t[-1])
    ax_energy.set_title(f"Energy (total: {e0:.3f} J → {e1:.3f} J)")
    ax_energy.grid(alpha=0.3)
    ax_energy.legend(loc="lower left", fontsize=8, ncol=3)

    dt = t[1] - t[0]
    fig.suptitle(
        f"SuperDex double pendulum — {len(t) - 1} steps of {dt:g} s, "
        f"mean {np.mean(data['newton_iterations'][1:]):.2f} Newton iterations/step, "
        f"max joint deviation "
        f"{max(data['pivot_deviation'].max(), data['joint_deviation'].max()):.2e} m"
    )
    fig.tight_layout()
    png = args.png or os.path.join(args.dir, "double_pendulum.png")
    fig.savefig(png, dpi=args.dpi)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
