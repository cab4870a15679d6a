#!/usr/bin/python3
"""Steps the tour's limits and targets for 2 s and plots them: the arm swings
down from horizontal until the JointRotationRange stops it at -0.5 rad, and the
one-link wrist is driven by an ArticulatedSingleDofTarget toward 0.6 rad but
stopped by an ArticulatedSingleDofRange at 0.4 rad.

    PYTHONPATH=<build>/python /usr/bin/python3 examples/python/plot_tour.py OUT_DIR

Writes OUT_DIR/plot_tour.png (matplotlib, Agg backend) and prints the final
values.
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mochi  # noqa: E402

DT = 0.005
DURATION = 2.0


def simulate():
    scene = mochi.Scene.create(integrator=mochi.IntegratorType.Bdf2)
    base = scene.create_rigid_actor(position=[0, 0, 0])
    arm = scene.create_rigid_actor(position=[1, 0, 0])
    scene.create_rigid_pivot_position_constraint(actor=base, stiffness=1e5, damping=10)
    scene.create_rigid_pivot_rotation_constraint(actor=base, stiffness=1e4, damping=1)
    scene.create_rigid_spherical_joint_constraint(actor_a=base, actor_b=arm, local_pos_a=[0.5, 0, 0],
                                                  local_pos_b=[-0.5, 0, 0], stiffness=1e5)
    inf = math.inf
    swing = scene.create_joint_rotation_range_constraint(
        actor_a=base, actor_b=arm, lower_limits=[-inf, -inf, -0.5], upper_limits=[inf, inf, 0.5], stiffness=1e3,
        damping=70)  # about critical for the arm's 1.25 kg·m² about the joint: 2 sqrt(k I) = 71
    wrist = scene.create_articulated_actor(links=[mochi.ArticulatedLinkParams(
        parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1], parent_to_joint_position=[0, 2, 0], mass=0.5,
        inertia=[1e-3, 1e-2, 1e-2], center_of_mass=[0.25, 0, 0])])
    drive = scene.create_articulated_single_dof_target_constraint(actor=wrist, joint_index=0, target=0.6,
                                                                  stiffness=50, damping=1)
    scene.create_articulated_single_dof_range_constraint(actor=wrist, joint_index=0, lower_limit=-0.4,
                                                         upper_limit=0.4, stiffness=1e3, damping=2)
    rows = []
    for _ in range(int(round(DURATION / DT))):
        scene.step(DT)
        rows.append((scene.get_time(), swing.get_relative_rotation()[2], swing.get_deviation()[2],
                     wrist.get_joint_positions()[0], drive.get_deviation()[0]))
    return np.array(rows)


def plot(rows, path):
    t, swing_angle, swing_violation, wrist_angle, _ = rows.T
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    top.plot(t, swing_angle, label="arm swing r_AB,z")
    top.plot(t, swing_violation, label="range violation g_z", linestyle="--")
    top.axhline(-0.5, color="gray", linewidth=0.8, label="limits ±0.5 rad")
    top.axhline(0.5, color="gray", linewidth=0.8)
    top.set_ylabel("rad")
    top.set_title("JointRotationRange stops a falling arm")
    top.legend(loc="lower left", fontsize=8)
    bottom.plot(t, wrist_angle, label="wrist joint angle θ")
    bottom.axhline(0.6, color="tab:green", linestyle=":", label="target 0.6 rad")
    bottom.axhline(0.4, color="gray", linewidth=0.8, label="range limit 0.4 rad")
    bottom.set_ylabel("rad")
    bottom.set_xlabel("time [s]")
    bottom.set_title("ArticulatedSingleDofTarget against ArticulatedSingleDofRange")
    bottom.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", help="folder for plot_tour.png (created if missing)")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    rows = simulate()
    path = os.path.join(args.out_dir, "plot_tour.png")
    plot(rows, path)
    t, swing_angle, swing_violation, wrist_angle, _ = rows[-1]
    print(f"t = {t:.3f} s: arm swing {swing_angle:.6f} rad (range violation {swing_violation:.6e} rad), "
          f"wrist {wrist_angle:.6f} rad")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
