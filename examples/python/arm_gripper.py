#!/usr/bin/python3
"""An articulated arm with a rigid gripper holding a soft block and a rod.

A four-joint arm (an articulated actor: base yaw, shoulder, elbow, wrist)
carries a rigid gripper welded to its last link (RigidSphericalJoint plus
JointRotationTracking between link 3 and the gripper, both on an articulated
link). The gripper holds a soft tetrahedral block by the nodes of its top face
(DeformableNodeToRigid on the gripper), and a rod hangs clamped to the elbow
link (DeformableNodeToRigid and RodElementRotationToRigid with rigid_link=2).
ArticulatedSingleDofTarget constraints drive the joints: the base turns by
1 rad over the first second and the shoulder lifts by 0.3 rad, then both
hold.

    PYTHONPATH=<build>/python /usr/bin/python3 examples/python/arm_gripper.py OUT_DIR

Writes OUT_DIR/arm_gripper.pvd with one .vtu per actor and frame (the arm as
a polyline through its joints, the gripper as a box, the block, the rod),
OUT_DIR/arm_gripper.png (matplotlib, Agg backend), and prints the final state.
"""
import argparse
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mochi  # noqa: E402

DT = 0.01
DURATION = 2.0
FRAME_EVERY = 5
LINK = 0.3  # link length [m]
YAW_END, LIFT_END = 1.0, 0.3  # targets reached at t = 1 s [rad]


def rotation_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def build():
    scene = mochi.Scene.create(integrator=mochi.IntegratorType.Bdf2, gravity=[0, 0, -9.81])  # z up
    # the arm: yaw about z at the origin, then three pitch joints about y;
    # links along +x, horizontal at rest
    axes = [[0, 0, 1], [0, 1, 0], [0, 1, 0], [0, 1, 0]]
    links = []
    for i, axis in enumerate(axes):
        links.append(mochi.ArticulatedLinkParams(
            parent=i - 1, joint=mochi.JointType.Revolute, axis=axis,
            parent_to_joint_position=[0, 0, 0.2] if i == 0 else [LINK if i > 1 else 0, 0, 0],
            mass=1.0 if i > 0 else 2.0, inertia=[0.002, 0.01, 0.01], center_of_mass=[LINK / 2 if i > 0 else 0, 0, 0],
            damping=0.5))
    arm = scene.create_articulated_actor(links=links)
    tip = 3 * LINK
    # targets hold every joint where it starts; yaw and shoulder are moved below
    targets = [scene.create_articulated_single_dof_target_constraint(
        actor=arm, joint_index=j, target=0.0, stiffness=2e3, damping=50) for j in range(4)]
    # the gripper: a 0.1 m x 0.1 m x 0.04 m rigid palm at the arm's tip, welded to link 3
    gripper = scene.create_rigid_actor(mass=0.3, inertia=[3e-4, 3e-4, 5e-4], position=[tip + 0.05, 0, 0.2])
    weld_position = scene.create_rigid_spherical_joint_constraint(
        actor_a=arm, link_a=3, local_pos_a=[LINK, 0, 0], actor_b=gripper, local_pos_b=[-0.05, 0, 0],
        stiffness=1e6, damping=100)
    weld_rotation = scene.create_joint_rotation_tracking_constraint(
        actor_a=arm, link_a=3, actor_b=gripper, stiffness=1e4, damping=10)
    # the soft block under the palm, held by the nodes of its top face
    size = 0.08
    mesh = mochi.make_tet_box(origin=[tip + 0.05 - size / 2, -size / 2, 0.2 - 0.02 - size],
                              size=[size, size, size], cells=[2, 2, 2])
    block = scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=mesh.tetrahedra, density=500,
                                          young_modulus=5e4)
    top = 0.2 - 0.02
    holds = [scene.create_deformable_node_to_rigid_constraint(
        deformable_actor=block, rigid_actor=gripper, deformable_node_index=i, stiffness=1e5, damping=10)
        for i, x in enumerate(mesh.nodes) if abs(x[2] - top) < 1e-9]
    # the rod: 0.4 m hanging from the elbow link (link 2) at 0.15 m from its joint
    rod = scene.create_rod_actor(nodes=[[LINK + 0.15, 0, 0.2 - 0.04 * i] for i in range(11)], radius=0.004,
                                 young_modulus=1e8, density=1000)
    rod_position = scene.create_deformable_node_to_rigid_constraint(
        deformable_actor=rod, rigid_actor=arm, rigid_link=2, deformable_node_index=0, stiffness=1e5)
    rod_rotation = scene.create_rod_element_rotation_to_rigid_constraint(
        rigid_actor=arm, rigid_link=2, rod_actor=rod, element_index=0, stiffness=50)
    for c in [weld_position, weld_rotation, rod_position] + holds:
        c.register_query(mochi.QueryType.ConstraintForce)
    return dict(scene=scene, arm=arm, targets=targets, gripper=gripper, weld=(weld_position, weld_rotation),
                block=block, mesh=mesh, holds=holds, rod=rod, rod_clamp=(rod_position, rod_rotation))


def write_frame(s, out_dir, series, frame, time):
    arm, gripper = s["arm"], s["gripper"]
    # the arm: a polyline through its joints and the tip
    points = [arm.get_link_position(i) for i in range(4)]
    points.append(points[-1] + rotation_matrix(arm.get_link_rotation(3)) @ [LINK, 0, 0])
    names = {}
    names["arm"] = f"arm_{frame:04d}.vtu"
    mochi.write_vtu_polylines(os.path.join(out_dir, names["arm"]), points, [list(range(len(points)))])
    # the gripper: a box of 12 triangles
    r, c = rotation_matrix(gripper.get_rotation()), gripper.get_position()
    half = np.array([0.05, 0.05, 0.02])
    corners = [c + r @ (half * [sx, sy, sz]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    faces = [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
             [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
    names["gripper"] = f"gripper_{frame:04d}.vtu"
    mochi.write_vtu(os.path.join(out_dir, names["gripper"]), corners, triangles=faces)
    names["block"] = f"block_{frame:04d}.vtu"
    block = s["block"]
    mochi.write_vtu(os.path.join(out_dir, names["block"]), block.get_node_positions(),
                    tetrahedra=s["mesh"].tetrahedra)
    names["rod"] = f"rod_{frame:04d}.vtu"
    mochi.write_rods_vtu(os.path.join(out_dir, names["rod"]), [s["rod"]])
    for name in ("arm", "gripper", "block", "rod"):
        series[name].add_frame(time, names[name])


def simulate(out_dir):
    s = build()
    scene, arm, targets = s["scene"], s["arm"], s["targets"]
    series = {name: mochi.VtkSeries(os.path.join(out_dir, f"arm_gripper_{name}.pvd"))
              for name in ("arm", "gripper", "block", "rod")}
    history = {k: [] for k in ("t", "yaw", "lift", "yaw_target", "lift_target", "weld", "rod_tip_z",
                               "hold_force")}
    steps = int(round(DURATION / DT))
    write_frame(s, out_dir, series, 0, 0.0)
    for n in range(1, steps + 1):
        t = n * DT
        ramp = min(t, 1.0)
        ramp = ramp * ramp * (3 - 2 * ramp)  # smooth step 0 -> 1 over the first second
        targets[0].set_target_dof(YAW_END * ramp)
        targets[1].set_target_dof(-LIFT_END * ramp)  # about +y: negative lifts the arm
        scene.step(DT)
        q = arm.get_joint_positions()
        history["t"].append(t)
        history["yaw"].append(q[0])
        history["lift"].append(-q[1])
        history["yaw_target"].append(YAW_END * ramp)
        history["lift_target"].append(LIFT_END * ramp)
        history["weld"].append(np.linalg.norm(s["weld"][0].get_deviation()))
        history["rod_tip_z"].append(s["rod"].get_node_position(s["rod"].get_num_nodes() - 1)[2])
        # the holds' force on the block (the block's node DoFs come first in each)
        history["hold_force"].append(sum(c.get_force()[2] for c in s["holds"]))
        if n % FRAME_EVERY == 0:
            write_frame(s, out_dir, series, n // FRAME_EVERY, t)
    history = {k: np.array(v) for k, v in history.items()}
    history["block_weight"] = s["block"].get_total_mass() * 9.81
    return s, history


def plot(history, path):
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    t = history["t"]
    ax = axes[0]
    ax.plot(t, history["yaw"], label="base yaw")
    ax.plot(t, history["yaw_target"], "--", label="yaw target")
    ax.plot(t, history["lift"], label="shoulder lift")
    ax.plot(t, history["lift_target"], "--", label="lift target")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("joint angle [rad]")
    ax.legend(fontsize=8)
    ax.set_title("arm joints (articulated actor)")
    ax = axes[1]
    ax.semilogy(t, np.maximum(history["weld"], 1e-16))
    ax.set_xlabel("t [s]")
    ax.set_ylabel("|g| [m]")
    ax.set_title("gripper weld on link 3: deviation")
    ax = axes[2]
    ax.plot(t, history["hold_force"], label="holds' lift on the block [N]")
    ax.axhline(history["block_weight"], color="gray", linestyle=":", label="block weight m g [N]")
    ax.set_xlabel("t [s]")
    ax.legend(fontsize=8)
    ax.set_title("soft block in the gripper")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    s, history = simulate(args.out_dir)
    plot(history, os.path.join(args.out_dir, "arm_gripper.png"))
    block_mass = s["block"].get_total_mass()
    print(f"arm_gripper: t = {DURATION:.1f} s, yaw {history['yaw'][-1]:.6f} rad (target {YAW_END}), "
          f"lift {history['lift'][-1]:.6f} rad (target {LIFT_END}), weld deviation {history['weld'][-1]:.3e} m, "
          f"block weight {block_mass * 9.81:.6f} N, hold lift {history['hold_force'][-1]:.6f} N, "
          f"rod tip z {history['rod_tip_z'][-1]:.6f} m, tree solve {s['arm'].is_solved_on_tree()}")


if __name__ == "__main__":
    main()
