#!/usr/bin/python3
"""Plots the output of superdex_soft_block.

usage: plot.py DIR [--dpi N] [--png PATH] [--times T1,T2,...] [--magnify M]

Reads DIR/soft_block.csv and the frames listed in DIR/soft_block.pvd, and
writes DIR/soft_block.png (or PATH): an overview of the motion (the target,
handle and centre-of-mass paths with the block's outline at the chosen
times), the positions and the force balance over time (the sum of the
attachment forces on the block against its weight and against the rate of
change of its momentum), and one side view per chosen time, with the
deformation (the motion less the handle's rigid carry) magnified.

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


def outline(faces):
    """Boundary edges of a set of triangles, as index pairs."""
    count = {}
    for face in faces:
        for k in range(3):
            edge = tuple(sorted((face[k], face[(k + 1) % 3])))
            count[edge] = count.get(edge, 0) + 1
    return np.array([e for e, c in count.items() if c == 1], dtype=int)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir", help="folder holding soft_block.csv and the .vtu frames")
    parser.add_argument("--dpi", type=int, default=120, help="resolution (default 120)")
    parser.add_argument("--png", help="output image (default DIR/soft_block.png)")
    parser.add_argument("--times", default="0,0.5,1,1.5,2,end",
                        help="times of the side views [s] (default 0,0.5,1,1.5,2,end)")
    parser.add_argument("--magnify", type=float, default=10,
                        help="deformation magnification in the side views (default 10)")
    args = parser.parse_args()

    csv_path = os.path.join(args.dir, "soft_block.csv")
    try:
        data = np.genfromtxt(csv_path, delimiter=",", names=True)
        frames = read_pvd(os.path.join(args.dir, "soft_block.pvd"))
    except (OSError, ET.ParseError) as e:
        sys.exit(f"plot.py: cannot read the output in {args.dir}: {e}")
    if data.size < 2 or not frames:
        sys.exit(f"plot.py: {csv_path} has fewer than two rows, or no frames")
    t = data["t"]
    frame_times = np.array([f[0] for f in frames])

    # the frames closest to the requested times
    wanted = []
    for text in args.times.split(","):
        time = frame_times[-1] if text.strip() == "end" else float(text)
        i = int(np.argmin(np.abs(frame_times - time)))
        if i not in wanted:
            wanted.append(i)
    views = []
    for i in wanted:
        points, tets, fdata = read_vtu(frames[i][1], VTK_TETRA)
        views.append((frame_times[i], points, tets, fdata))
    reference = views[0][1] - views[0][3]["displacement"]
    faces = front_faces(views[0][2], reference)
    edges = outline(faces)
    side = np.ptp(reference[:, 0])

    fig = plt.figure(figsize=(14, 9.2))
    outer = fig.add_gridspec(2, 1, height_ratios=[1.5, 1], hspace=0.22)
    top = outer[0].subgridspec(3, 2, width_ratios=[1, 1.15], hspace=0.1, wspace=0.18)
    cmap = plt.get_cmap("plasma")
    colours = [cmap(0.85 * k / max(1, len(views) - 1)) for k in range(len(views))]

    # ---- overview, true scale ----
    ax = fig.add_subplot(top[:, 0])
    ax.plot(data["target_x"], data["target_y"], "--", color="0.3", lw=1.2,
            label="handle target (animated)")
    ax.plot(data["com_x"], data["com_y"], color="tab:blue", lw=1.0,
            label="block centre of mass")
    for (time, points, _, _), colour in zip(views, colours):
        xy = points[:, :2]
        for a, b in edges:
            ax.plot(xy[[a, b], 0], xy[[a, b], 1], color=colour, lw=1.1)
        row = int(np.argmin(np.abs(t - time)))
        ax.plot(data["handle_x"][row], data["handle_y"][row], "s", color=colour, ms=6,
                mec="k", label=f"t = {time:.2f} s")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Motion (front face outline, handle ■), true scale")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    ax.set_ylim(-0.25, 0.45)

    # ---- positions, vertical and horizontal force balance ----
    ax_p = fig.add_subplot(top[0, 1])
    ax_p.plot(t, data["target_x"], "--", color="0.3", lw=1.0, label="target x, y")
    ax_p.plot(t, data["target_y"], "--", color="0.3", lw=1.0)
    ax_p.plot(t, data["com_x"], color="tab:blue", lw=1.2, label="centre of mass x")
    ax_p.plot(t, data["com_y"], color="tab:orange", lw=1.2, label="centre of mass y")
    ax_p.set_ylabel("[m]")
    ax_p.grid(alpha=0.3)
    ax_p.legend(loc="center right", fontsize=8)
    ax_p.tick_params(labelbottom=False)
    ax_p.set_title(
        f"Force balance: max |M a − (F + M g)| = {data['balance_residual'][1:].max():.1e} "
        f"of the weight"
    )
    ax_fy = fig.add_subplot(top[1, 1], sharex=ax_p)
    weight = data["weight"][0]
    ax_fy.plot(t[1:], data["force_y"][1:], color="k", lw=1.3,
               label="attachments on the block, F_y")
    ax_fy.axhline(weight, color="tab:red", ls="--", lw=1.0, label=f"weight M g = {weight:.2f} N")
    stride = max(1, len(t) // 60)
    ax_fy.plot(t[1::stride], (data["momentum_rate_y"] + weight)[1::stride], "o", ms=3,
               mfc="none", color="tab:green", label="M a_y + M g")
    ax_fy.set_ylabel("vertical [N]")
    ax_fy.grid(alpha=0.3)
    ax_fy.legend(loc="upper right", fontsize=8, ncol=3)
    ax_fy.set_ylim(min(data["force_y"][1:].min(), weight) - 3,
                   max(data["force_y"][1:].max(), weight) + 6)
    ax_fy.tick_params(labelbottom=False)
    ax_fx = fig.add_subplot(top[2, 1], sharex=ax_p)
    ax_fx.plot(t[1:], data["force_x"][1:], color="k", lw=1.3, label="F_x")
    ax_fx.plot(t[1::stride], data["momentum_rate_x"][1::stride], "o", ms=3, mfc="none",
               color="tab:green", label="M a_x")
    ax_fx.set_ylabel("horizontal [N]")
    ax_fx.set_xlabel("t [s]")
    ax_fx.set_xlim(t[0], t[-1])
    ax_fx.grid(alpha=0.3)
    ax_fx.legend(loc="upper right", fontsize=8, ncol=2)

    # ---- side views: rigid carry (dashed) + magnified deformation, |d| in mm ----
    bottom = outer[1].subgridspec(1, len(views) + 1, width_ratios=[1] * len(views) + [0.08],
                                  wspace=0.08)
    dmax = max(1e-12, max(v[3]["deformation_magnitude"].max() for v in views)) * 1e3
    polys = None
    for k, ((time, points, _, fdata), colour) in enumerate(zip(views, colours)):
        axv = fig.add_subplot(bottom[k])
        deformation = fdata["deformation"]
        carried = points - deformation
        drawn = (carried + args.magnify * deformation)[:, :2]
        polys = PolyCollection(drawn[faces], cmap="viridis", edgecolors="face", linewidths=0.5)
        polys.set_array(1e3 * fdata["deformation_magnitude"][faces].mean(axis=1))
        polys.set_clim(0, dmax)
        axv.add_collection(polys)
        for a, b in edges:
            axv.plot(carried[[a, b], 0], carried[[a, b], 1], "--", color="0.4", lw=0.7)
        row = int(np.argmin(np.abs(t - time)))
        hx, hy = data["handle_x"][row], data["handle_y"][row]
        axv.plot(hx, hy, "s", color=colour, ms=7, mec="k")
        half = 0.75 * side
        centre_y = hy - 0.55 * side
        axv.set_xlim(hx - half, hx + half)
        axv.set_ylim(centre_y - half, centre_y + half)
        axv.set_aspect("equal")
        axv.set_title(f"t = {time:.2f} s, {np.degrees(data['handle_angle'][row]):+.1f}°",
                      fontsize=9)
        axv.tick_params(labelsize=7)
        if k:
            axv.tick_params(labelleft=False)
        axv.set_xlabel("x [m]", fontsize=8)
    fig.colorbar(polys, cax=fig.add_subplot(bottom[-1]), label="|deformation| [mm]")
    fig.text(0.5, 0.375,
             f"Side views (front face), deformation × {args.magnify:g} about the handle's rigid "
             f"carry (dashed); angle = handle's swing",
             ha="center", fontsize=10)

    iters = data["newton_iterations"][1:]
    fig.suptitle(
        f"SuperDex soft block — {len(t) - 1} steps of {t[1] - t[0]:.4g} s, "
        f"mean {np.mean(iters):.2f} Newton iterations/step; "
        f"max deformation {1e3 * data['max_deformation'].max():.2f} mm, "
        f"max swing {np.degrees(np.abs(data['handle_angle']).max()):.1f}°"
    )
    fig.subplots_adjust(left=0.06, right=0.95, top=0.93, bottom=0.06)
    png = args.png or os.path.join(args.dir, "soft_block.png")
    fig.savefig(png, dpi=args.dpi)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
