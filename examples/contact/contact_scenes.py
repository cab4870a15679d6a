#!/usr/bin/python3
"""Four contact scenes (docs/contact.md), drawn from their output:

1. a static box paddle moved kinematically at 0.5 m/s (a target per step)
   pushes a resting box across the ground (mu = 0.3);
2. a soft Neo-Hookean tet ball dropped from 1 m bounces on the ground (BDF2);
3. five rigid boxes stacked on the ground come to rest;
4. a cloth (tension-field membrane) dropped on a static sphere drapes over it.

    PYTHONPATH=<build>/python /usr/bin/python3 examples/contact/contact_scenes.py OUT_DIR

Writes OUT_DIR/contact_scenes.png (matplotlib, Agg backend) and prints one
line per scene with its figures.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mochi  # noqa: E402

DHAT = mochi.ContactParams().activation_distance


def box_outline(collider):
    """The x-y outline of a Box collider (its corners' convex hull, side view)."""
    corners = np.asarray(collider.get_world_vertices())[:, :2]
    centre = corners.mean(axis=0)
    order = np.argsort(np.arctan2(corners[:, 1] - centre[1], corners[:, 0] - centre[0]))
    hull = corners[order]
    return np.vstack([hull, hull[:1]])


def paddle_pushes_box():
    scene = mochi.Scene.create()
    scene.create_collider(shape=mochi.ShapeType.Plane, friction=0.3)
    box = scene.create_rigid_actor(mass=1.0, inertia=[1 / 150] * 3, position=[0, 0.1 + 0.5 * DHAT, 0])
    box_shape = scene.create_collider(actor=box, shape=mochi.ShapeType.Box, half_extents=[0.1, 0.1, 0.1],
                                      friction=0.3)
    paddle = scene.create_collider(shape=mochi.ShapeType.Box, half_extents=[0.02, 0.2, 0.3],
                                   position=[-0.17, 0.25, 0])
    dt, speed = 1 / 60, 0.5
    frames, newton = [], []
    for step in range(60):
        paddle.set_target_transform(np.asarray(paddle.get_position()) + [speed * dt, 0, 0], [1, 0, 0, 0])
        scene.step(dt)
        newton.append(scene.get_stats().newton_iterations)
        if step % 15 == 14:
            frames.append((box_outline(box_shape), box_outline(paddle)))
    return frames, box.get_linear_velocity()[0], np.mean(newton[10:])


def ball_bounces():
    scene = mochi.Scene.create(integrator=mochi.IntegratorType.Bdf2)
    scene.create_collider(shape=mochi.ShapeType.Plane)
    radius, drop, cells = 0.5, 1.0, 6  # scene 3's ball: 1 m of rubber
    nodes, tets = tet_ball([0, drop + radius, 0], radius, cells)
    ball = scene.create_deformable_actor(nodes=nodes, tetrahedra=tets, material=mochi.TetMaterialModel.StableNeoHookean,
                                         young_modulus=1e6, density=1000)
    scene.create_collider(actor=ball, group=2, mask=~2 & 0xFFFFFFFF)  # no self contact: a solid ball
    dt = 1 / 240
    times, lowest = [], []
    for step in range(int(1.2 / dt)):
        scene.step(dt)
        times.append((step + 1) * dt)
        lowest.append(np.asarray(ball.get_node_positions())[:, 1].min())
    return np.asarray(times), np.asarray(lowest)


def tet_ball(center, radius, cells):
    """A grid box of cells³ cubes, 6 tets each, its nodes moved along their rays from
    the centre onto spheres (d -> d |d|_inf / |d|_2): a round ball, as scenes::TetBall."""
    grid = np.linspace(-radius, radius, cells + 1)
    n = cells + 1
    nodes = []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                d = np.array([grid[i], grid[j], grid[k]])
                length = np.linalg.norm(d)
                if length > 0:
                    d = d * (np.abs(d).max() / length)
                nodes.append(list(np.asarray(center) + d))
    # the 6 tetrahedra of a cube around its main diagonal (corner 0 to 6)
    split = [(0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6)]
    offsets = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    tets = []
    for i in range(cells):
        for j in range(cells):
            for k in range(cells):
                ids = [(i + a) * n * n + (j + b) * n + (k + c) for a, b, c in offsets]
                for tet in split:
                    t = [ids[c] for c in tet]
                    p = np.asarray([nodes[m] for m in t])
                    if np.linalg.det(np.array([p[1] - p[0], p[2] - p[0], p[3] - p[0]])) < 0:
                        t[1], t[2] = t[2], t[1]  # positive volume
                    tets.append(t)
    return nodes, tets


def box_stack():
    scene = mochi.Scene.create()
    scene.create_collider(shape=mochi.ShapeType.Plane)
    shapes = []
    for i in range(5):
        body = scene.create_rigid_actor(mass=1.0, inertia=[1 / 150] * 3,
                                        position=[0.01 * i, 0.9 * DHAT + 0.1 + i * (0.2 + 0.9 * DHAT), 0])
        shapes.append((body, scene.create_collider(actor=body, shape=mochi.ShapeType.Box,
                                                   half_extents=[0.1, 0.1, 0.1])))
    for _ in range(60):
        scene.step(1 / 60)
    top = np.asarray(shapes[-1][0].get_position())
    for _ in range(60):
        scene.step(1 / 60)
    drift = np.linalg.norm(np.asarray(shapes[-1][0].get_position()) - top)
    return [box_outline(shape) for _, shape in shapes], drift


def cloth_drapes_on_sphere():
    scene = mochi.Scene.create()
    scene.create_collider(shape=mochi.ShapeType.Plane)
    radius = 0.2
    scene.create_collider(shape=mochi.ShapeType.Sphere, radius=radius, position=[0, radius, 0])
    cells, size = 15, 0.6
    mesh = mochi.make_triangle_grid(origin=[-size / 2, 0.45, -size / 2], size_x=size, size_z=size,
                                    cells_x=cells, cells_z=cells)
    # a cloth: 1 mm, E = 1 MPa, 0.3 kg/m²; the tension field carries no
    # compressive stress (it wrinkles), which Newton needs where it folds
    cloth = scene.create_deformable_actor(nodes=mesh.nodes, triangles=mesh.triangles, thickness=1e-3,
                                          young_modulus=1e6, density=300,
                                          membrane=mochi.MembraneModel.TensionField)
    scene.create_collider(actor=cloth)  # its surface, self contact included
    middle = [(cells + 1) * (cells // 2) + i for i in range(cells + 1)]  # the grid row at z = 0
    dt = 1 / 60
    profiles, newton, clearance = [], [], np.inf
    for step in range(60):
        scene.step(dt)
        newton.append(scene.get_stats().newton_iterations)
        nodes = np.asarray(cloth.get_node_positions())
        clearance = min(clearance, (np.linalg.norm(nodes - [0, radius, 0], axis=1) - radius).min(), nodes[:, 1].min())
        if step in (0, 9, 19, 59):
            profiles.append(((step + 1) * dt, nodes[middle][:, [0, 1]]))
    return profiles, radius, clearance, np.mean(newton), max(newton)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    out_dir = parser.parse_args().out_dir
    os.makedirs(out_dir, exist_ok=True)

    frames, box_speed, newton = paddle_pushes_box()
    times, lowest = ball_bounces()
    stack, drift = box_stack()
    profiles, radius, clearance, cloth_newton, cloth_most = cloth_drapes_on_sphere()

    fig, axes = plt.subplots(1, 4, figsize=(17, 4))
    ax = axes[0]
    for n, (box, paddle) in enumerate(frames):
        shade = 0.3 + 0.7 * (n + 1) / len(frames)
        ax.plot(*box.T, color=(0.1, 0.3, 0.8, shade))
        ax.plot(*paddle.T, color=(0.8, 0.3, 0.1, shade))
    ax.axhline(0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.set_title(f"kinematic paddle pushes a box\n(every 0.25 s; box at {box_speed:.3f} m/s)")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax = axes[1]
    ax.plot(times, lowest)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_title("soft ball dropped from 1 m (BDF2, dt 1/240)\nlowest node height")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("y [m]")
    ax = axes[2]
    for outline in stack:
        ax.plot(*outline.T, color="tab:green")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.set_title(f"5 rigid boxes at rest after 2 s\n(top box drift over 1 s {drift:.1e} m)")
    ax.set_xlabel("x [m]")
    ax = axes[3]
    ax.add_patch(plt.Circle((0, radius), radius, color="0.8"))
    for n, (t, profile) in enumerate(profiles):
        ax.plot(*profile.T, ".-", color=plt.cm.viridis(n / len(profiles)), label=f"t = {t:.2f} s")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title(f"cloth dropped on a sphere (dt 1/60)\nits middle row; {cloth_newton:.1f} Newton iterations/step")
    ax.set_xlabel("x [m]")
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "contact_scenes.png"), dpi=80)

    landed = np.argmax(lowest < 2 * DHAT)
    print(f"paddle: box speed {box_speed:.4f} m/s (paddle 0.5), {newton:.2f} Newton iterations per step once pushing")
    print(f"ball: lowest node {lowest.min():.3e} m above the ground, bounce peak {lowest[landed:].max():.3f} m of 1")
    print(f"stack: top box drift {drift:.3e} m over the last second")
    print(f"cloth: clearance {clearance:.3e} m from the sphere and the ground, "
          f"{cloth_newton:.2f} Newton iterations per step ({cloth_most} at most)")


if __name__ == "__main__":
    main()
