#!/usr/bin/python3
"""Plots the output of superdex_cantilever.

usage: plot.py DIR [--dpi N] [--png PATH]

Reads DIR/cantilever.csv, DIR/cantilever_reference.csv, the frames listed in
DIR/cantilever.pvd and DIR/cantilever_static.vtu, and writes
DIR/cantilever.png (or PATH) with two panels: a side view (x-y) of the beam
at the last frame, its front face coloured by the displacement magnitude,
with the centre line at earlier frames and the static equilibrium; and the
tip deflection over time against the static and Euler-Bernoulli values.

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
from matplotlib.collections import PolyCollection  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vtu import VTK_TETRA, front_faces, read_pvd, read_vtu  # noqa: E402


def centre_line(points, reference):
    """Mean position of each cross-section (nodes sharing a reference x)."""
    xs, section = np.unique(np.round(reference[:, 0], 9), return_inverse=True)
    counts = np.bincount(section)
    return np.column_stack(
        [np.bincount(section, weights=points[:, k]) / counts for k in range(3)]
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir", help="folder holding cantilever.csv and the .vtu frames")
    parser.add_argument("--dpi", type=int, default=120, help="resolution (default 120)")
    parser.add_argument("--png", help="output image (default DIR/cantilever.png)")
    args = parser.parse_args()

    csv_path = os.path.join(args.dir, "cantilever.csv")
    try:
        data = np.genfromtxt(csv_path, delimiter=",", names=True)
        ref = np.genfromtxt(
            os.path.join(args.dir, "cantilever_reference.csv"), delimiter=",", names=True
        )
        frames = read_pvd(os.path.join(args.dir, "cantilever.pvd"))
        static_points, _, static_data = read_vtu(os.path.join(args.dir, "cantilever_static.vtu"), VTK_TETRA)
        last_points, tets, last_data = read_vtu(frames[-1][1], VTK_TETRA)
    except (OSError, ET.ParseError, KeyError, IndexError) as e:
        sys.exit(f"plot.py: cannot read the output in {args.dir}: {e}")
    if data.size < 2:
        sys.exit(f"plot.py: {csv_path} has fewer than two rows")

    t = data["t"]
    length, side = float(ref["length"]), float(ref["side"])
    reference = last_points - last_data["displacement"]
    faces = front_faces(tets, reference)

    fig, (ax_view, ax_tip) = plt.subplots(
        1, 2, figsize=(13, 5.4), gridspec_kw={"width_ratios": [1.25, 1]}
    )

    # ---- side view ----
    # the straight beam, the static equilibrium and the wall
    ax_view.add_patch(
        plt.Rectangle((0, -side / 2), length, side, fill=False, ls="--", lw=0.8, color="0.6")
    )
    static_reference = static_points - static_data["displacement"]
    static_line = centre_line(static_points, static_reference)
    # centre line at earlier frames, coloured by time
    cmap = plt.get_cmap("Greys")
    step = max(1, len(frames) // 12)
    shown = frames[::step][:-1]
    for i, (time, path) in enumerate(shown):
        points, _, fdata = read_vtu(path, VTK_TETRA)
        line = centre_line(points, points - fdata["displacement"])
        ax_view.plot(
            line[:, 0], line[:, 1], lw=0.8, color=cmap(0.25 + 0.5 * i / max(1, len(shown) - 1))
        )
    ax_view.plot([], [], lw=0.8, color="0.5", label=f"centre line, t = 0 … {shown[-1][0]:.2f} s")
    ax_view.plot(
        static_line[:, 0], static_line[:, 1], "--", lw=1.6, color="tab:red",
        label="static equilibrium (centre line)",
    )
    # the last frame's front face, coloured by |u|
    polys = PolyCollection(
        last_points[faces][:, :, :2], cmap="viridis", edgecolors="face", linewidths=0.2
    )
    polys.set_array(last_data["displacement_magnitude"][faces].mean(axis=1))
    ax_view.add_collection(polys)
    fig.colorbar(polys, ax=ax_view, label="|u| [m]", fraction=0.04, pad=0.02)
    ax_view.axvspan(-0.06, 0, color="0.75", zorder=0)
    ax_view.text(-0.03, 0.1, "clamp", rotation=90, ha="center", va="bottom", fontsize=8)
    ax_view.set_xlim(-0.08, length + 0.08)
    ax_view.set_ylim(-1.02 * length, 0.2)
    ax_view.set_aspect("equal")
    ax_view.set_xlabel("x [m]")
    ax_view.set_ylabel("y [m]")
    ax_view.set_title(f"Side view at t = {frames[-1][0]:.2f} s (front face z = +{side / 2:g} m)")
    ax_view.legend(loc="lower left", fontsize=8)
    ax_view.grid(alpha=0.3)

    # ---- tip deflection ----
    ax_tip.plot(t, data["tip_deflection"], lw=1.4, color="tab:blue", label="tip deflection −u_y")
    ax_tip.plot(t, -data["tip_dx"], lw=0.9, color="tab:green", label="tip pulled back −u_x")
    ax_tip.plot(t, data["tip_dz"], lw=0.9, color="tab:purple", label="tip sideways u_z")
    static = float(ref["static_tip_deflection"])
    ax_tip.axhline(static, ls="--", color="tab:red", lw=1.2,
                   label=f"static equilibrium: {static:.3f} m")
    eb = float(ref["euler_bernoulli"])
    ax_tip.axhline(eb, ls=":", color="k", lw=1.2,
                   label=f"Euler–Bernoulli qL⁴/8EI: {eb:.3f} m (linear)")
    ax_tip.set_xlim(t[0], t[-1])
    ax_tip.set_xlabel("t [s]")
    ax_tip.set_ylabel("[m]")
    ax_tip.set_title("Tip of the beam (mean of the end face's nodes)")
    ax_tip.grid(alpha=0.3)
    ax_tip.set_ylim(min(-0.05, 1.1 * min(data["tip_dz"].min(), (-data["tip_dx"]).min())),
                    1.3 * max(eb, data["tip_deflection"].max()))
    ax_tip.legend(loc="upper center", bbox_to_anchor=(0.5, 0.94), fontsize=8, ncol=2)

    dt = t[1] - t[0]
    fig.suptitle(
        f"SuperDex cantilever — {len(t) - 1} steps of {dt:.4g} s, "
        f"E = {float(ref['young']):g} Pa, "
        f"mean {np.mean(data['newton_iterations'][1:]):.2f} Newton iterations/step, "
        f"final tip deflection {data['tip_deflection'][-1]:.3f} m"
    )
    fig.tight_layout()
    png = args.png or os.path.join(args.dir, "cantilever.png")
    fig.savefig(png, dpi=args.dpi)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
