#!/usr/bin/env python3
"""The thrown chain of tests/scene/stiff_chain_test.cpp ("out of plane"), for
any number of links and time step: N box links (0.1 x 0.02 x 0.02 m, 1 kg)
joined by RigidSphericalJoint constraints (k = 1e6 N/m) and pinned at one end,
the free end thrown at 3 m/s along z and every link spinning at (0.9, 0.3, 0)
rad/s; 3 s with CHOLMOD and backward Euler.

Usage:  PYTHONPATH=build/python /usr/bin/python3 perf/harness/thrown_chain.py \
            N STEPS_PER_SECOND [GaussNewton|GeometricStiffness|GeometricStiffnessDiagonal]

Prints the mean Newton iterations per step, or the step in which Newton failed.
"""
import sys

import mochi

LENGTH, SIDE, MASS, STIFFNESS = 0.1, 0.02, 1.0, 1e6


def main(argv):
    if len(argv) not in (3, 4):
        sys.exit(__doc__)
    links, steps_per_second = int(argv[1]), float(argv[2])
    mode = argv[3] if len(argv) == 4 else "GeometricStiffness"
    params = mochi.SceneParams()
    params.linear_solver = mochi.LinearSolverType.Cholmod
    params.newton.constraint_hessian = getattr(mochi.ConstraintHessian, mode)
    scene = mochi.Scene.create(params)
    across, along = MASS / 12 * 2 * SIDE**2, MASS / 12 * (LENGTH**2 + SIDE**2)
    bodies = [scene.create_rigid_actor(mass=MASS, inertia=[across, along, along],
                                       position=[(i + 0.5) * LENGTH, 0, 0]) for i in range(links)]
    scene.create_rigid_pivot_position_constraint(actor=bodies[0], local_pos=[-LENGTH / 2, 0, 0],
                                                 position=[0, 0, 0], stiffness=STIFFNESS)
    for a, b in zip(bodies, bodies[1:]):
        scene.create_rigid_spherical_joint_constraint(actor_a=a, actor_b=b, local_pos_a=[LENGTH / 2, 0, 0],
                                                      local_pos_b=[-LENGTH / 2, 0, 0], stiffness=STIFFNESS)
    for i, body in enumerate(bodies):
        body.set_velocity([0, 0, 3 * (i + 0.5) / links], [0.9, 0.3, 0])
    steps, newton = int(round(3 * steps_per_second)), 0
    label = f"N = {links}, dt = 1/{steps_per_second:g}, {mode}"
    for step in range(steps):
        try:
            scene.step(1 / steps_per_second)
        except mochi.Error:
            print(f"{label}: Newton fails in step {step + 1}")
            return
        newton += scene.get_stats().newton_iterations
    print(f"{label}: 3 s, {newton / steps:.2f} Newton iterations per step")


if __name__ == "__main__":
    main(sys.argv)
