#!/usr/bin/python3
"""Plots the output of superdex_cloth.

usage: plot.py DIR [--dpi N] [--png PATH]

Reads DIR/cloth.csv and the last frame listed in DIR/cloth.pvd, and writes
DIR/cloth.png (or PATH): a 3-D view of the sheet at the last frame, coloured
by height, next to the kinetic and elastic energy, the pin forces against
the weight, and the Newton iterations of every step.

Run it with Debian's /usr/bin/python3 (numpy and matplotlib).
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vtu import VTK_TRIANGLE, read_pvd, read_vtu  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir", help="folder holding cloth.csv and the .vtu frames")
    parser.add_argument("--dpi", type=int, default=120, help="resolution (default 120)")
    parser.add_argument("--png", help="output image (default DIR/cloth.png)")
    args = parser.parse_args()

    csv_path = os.path.join(args.dir, "cloth.csv")
    try:
        data = np.genfromtxt(csv_path, delimiter=",", names=True)
        frames = read_pvd(os.path.join(args.dir, "cloth.pvd"))
        points, tris, _ = read_vtu(frames[-1][1], VTK_TRIANGLE)
    except (OSError, ET.ParseError, KeyError, IndexError) as e:
        sys.exit(f"plot.py: cannot read the output in {args.dir}: {e}")
    if data.size < 2:
        sys.exit(f"plot.py: {csv_path} has fewer than two rows")
    t = data["t"]

    fig = plt.figure(figsize=(13, 6.2))
    grid = fig.add_gridspec(3, 2, width_ratios=[1.1, 1], hspace=0.12, wspace=0.08)

    # ---- 3-D view: world y (up) is the plot's vertical axis ----
    ax3 = fig.add_subplot(grid[:, 0], projection="3d")
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    n_side = int(round(np.sqrt(len(points)))) - 1  # grid points (i, 0) are nodes 0 … n
    ax3.plot_trisurf(
        x, z, y, triangles=tris, cmap="viridis", edgecolor=(0, 0, 0, 0.25), linewidth=0.2,
        antialiased=True, alpha=0.85,
    )
    # the flat sheet it started from, and the pinned corners
    ax3.plot([0, 1, 1, 0, 0], [0, 0, 1, 1, 0], [0, 0, 0, 0, 0], "--", color="0.55", lw=0.8,
             label="start (flat, y = 0)")
    ax3.scatter([0, 1], [1, 1], [0, 0], color="k", s=30, depthshade=False,
                label="pinned corners")
    # paths of the two free corners over all frames: the sheet swings about
    # the line through the pins (a hinge) to the far side z > 1 and back
    corners = np.array([read_vtu(path, VTK_TRIANGLE)[0][[0, n_side]] for _, path in frames])
    for k, name in enumerate(("(0, 0, 0)", "(1, 0, 0)")):
        ax3.plot(corners[:, k, 0], corners[:, k, 2], corners[:, k, 1], lw=0.9,
                 color=("tab:orange", "tab:red")[k], label=f"path of free corner {name}")
    ax3.set_xlim(0, 1)
    ax3.set_ylim(0, 2)
    ax3.set_zlim(-1.05, 0.05)
    ax3.set_box_aspect((1, 2, 1.05))
    ax3.view_init(elev=22, azim=-62)
    ax3.set_xlabel("x [m]")
    ax3.set_ylabel("z [m]")
    ax3.set_zlabel("y [m] (up)", labelpad=10)
    ax3.legend(loc="upper center", fontsize=8, ncol=2, bbox_to_anchor=(0.5, 1.0),
               title=f"Sheet at t = {frames[-1][0]:.2f} s (colour: height)")

    # ---- energies ----
    ax_e = fig.add_subplot(grid[0, 1])
    ax_e.semilogy(t[1:], data["kinetic"][1:], lw=1.2, label="kinetic")
    ax_e.semilogy(t[1:], data["elastic"][1:], lw=1.0, label="elastic (membrane + bending)")
    ax_e.set_ylabel("energy [J]")
    ax_e.set_xlim(t[0], t[-1])
    ax_e.grid(alpha=0.3, which="both")
    ax_e.legend(loc="lower right", fontsize=8, ncol=2)
    ax_e.tick_params(labelbottom=False)
    ax_e.set_title("Energies, pin forces and Newton iterations")

    # ---- pin forces ----
    ax_f = fig.add_subplot(grid[1, 1], sharex=ax_e)
    fy = data["pin0_fy"] + data["pin1_fy"]
    ax_f.plot(t[1:], fy[1:], lw=1.2, color="k", label="sum of pin forces, y")
    ax_f.plot(t[1:], data["pin0_fx"][1:], lw=0.8, label="pin (0, 0, 1), x")
    ax_f.plot(t[1:], data["pin1_fx"][1:], lw=0.8, label="pin (1, 0, 1), x")
    ax_f.axhline(data["weight"][0], ls="--", color="tab:red", lw=1.0,
                 label=f"weight {data['weight'][0]:.3f} N")
    ax_f.set_ylabel("force [N]")
    ax_f.grid(alpha=0.3)
    ax_f.legend(loc="upper right", fontsize=8, ncol=2)
    ax_f.tick_params(labelbottom=False)

    # ---- Newton iterations ----
    ax_n = fig.add_subplot(grid[2, 1], sharex=ax_e)
    iters = data["newton_iterations"][1:]
    ax_n.bar(t[1:], iters, width=t[1] - t[0], color="tab:purple", lw=0)
    ax_n.set_yscale("log")
    ax_n.set_ylabel("Newton its")
    ax_n.set_xlabel("t [s]")
    ax_n.grid(alpha=0.3, which="both")

    dt = t[1] - t[0]
    fig.suptitle(
        f"SuperDex cloth — {len(t) - 1} steps of {dt:.4g} s, "
        f"Newton iterations/step mean {np.mean(iters):.1f}, max {int(iters.max())}; "
        f"lowest point {data['lowest_y'][-1]:.2f} m, largest edge stretch "
        f"{data['max_stretch'].max():.3f}"
    )
    fig.subplots_adjust(left=0.0, right=0.97, top=0.9, bottom=0.09)
    png = args.png or os.path.join(args.dir, "cloth.png")
    fig.savefig(png, dpi=args.dpi)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
