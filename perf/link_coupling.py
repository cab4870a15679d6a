#!/usr/bin/python3
"""Cost of a coupling constraint on an articulated arm: the harness's
chain-articulated (N spherical joints, 0.1 m, 1 kg links, released along +x,
backward Euler, dt = 1/60, cholmod), stepped STEPS times, alone (tree and
Dense) and with one coupling on its tip link (link N-1). Prints ms per step
(after the first), µs per link per step and Newton iterations per step.

    PYTHONPATH=build/python /usr/bin/python3 perf/link_coupling.py [N=200] [STEPS=60]

docs/articulated.md, "Links in constraints", has the figures."""
import sys
import time

import mochi

N = int(sys.argv[1]) if len(sys.argv) > 1 else 200
STEPS = int(sys.argv[2]) if len(sys.argv) > 2 else 60
L, side, m = 0.1, 0.02, 1.0

def arm(scene, solve):
    links = [mochi.ArticulatedLinkParams(parent=i - 1, joint=mochi.JointType.Spherical,
             parent_to_joint_position=[0 if i == 0 else L, 0, 0], mass=m,
             inertia=[m / 12 * 2 * side**2, m / 12 * (L**2 + side**2), m / 12 * (L**2 + side**2)],
             center_of_mass=[L / 2, 0, 0]) for i in range(N)]
    return scene.create_articulated_actor(mochi.ArticulatedActorParams(links=links, block_solve=solve))

def run(label, couple, solve=mochi.ArticulatedBlockSolve.Tree):
    scene = mochi.Scene.create(gravity=[0, -9.81, 0], integrator=mochi.IntegratorType.BackwardEuler)
    a = arm(scene, solve)
    tip = N * L
    couple(scene, a, tip)
    scene.step(1 / 60)  # the pattern and the first factorization: not timed
    t0 = time.perf_counter()
    iterations = 0
    for _ in range(STEPS - 1):
        scene.step(1 / 60)
        iterations += scene.get_stats().newton_iterations
    dt = (time.perf_counter() - t0) / (STEPS - 1)
    print(f"{label:55s} tree={a.is_solved_on_tree()!s:5s} {dt*1e3:9.2f} ms/step {dt*1e6/N:8.1f} us/link/step "
          f"{iterations/(STEPS-1):5.2f} Newton/step", flush=True)

def none(scene, a, tip): pass
def pivot(scene, a, tip):
    scene.create_rigid_pivot_position_constraint(actor=a, link=N - 1, local_pos=[L, 0, 0], position=[tip, 0, 0], stiffness=1e6)
def ball(scene, a, tip):
    b = scene.create_rigid_actor(mass=1, position=[tip, 0, 0])
    scene.create_rigid_spherical_joint_constraint(actor_a=a, link_a=N - 1, local_pos_a=[L, 0, 0], actor_b=b, stiffness=1e6)
def soft(scene, a, tip):
    mesh = mochi.make_tet_box(origin=[tip, -0.05, -0.05], size=[0.1, 0.1, 0.1], cells=[2, 2, 2])
    s = scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=mesh.tetrahedra, young_modulus=1e5)
    for i, x in enumerate(mesh.nodes):
        if abs(x[0] - tip) < 1e-9:
            scene.create_deformable_node_to_rigid_constraint(deformable_actor=s, rigid_actor=a, rigid_link=N - 1,
                                                             deformable_node_index=i, stiffness=1e5)
def rod(scene, a, tip):
    r = scene.create_rod_actor(nodes=[[tip + 0.05 * i, 0, 0] for i in range(6)], radius=0.005)
    scene.create_deformable_node_to_rigid_constraint(deformable_actor=r, rigid_actor=a, rigid_link=N - 1,
                                                     deformable_node_index=0, stiffness=1e5)
    scene.create_rod_element_rotation_to_rigid_constraint(rigid_actor=a, rigid_link=N - 1, rod_actor=r,
                                                          element_index=0, stiffness=100)

run("no coupling (tree)", none)
run("no coupling (Dense block)", none, mochi.ArticulatedBlockSolve.Dense)
run("RigidPivotPosition on the tip link", pivot)
run("RigidSphericalJoint tip link - rigid ball", ball)
run("DeformableNodeToRigid x9 tip link - tet block 2x2x2", soft)
run("rod clamp (NodeToRigid + RodElementRotationToRigid)", rod)
