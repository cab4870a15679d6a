#!/usr/bin/python3
"""The constraint runtime interface from Python: every method of the reference
page (constraints.md, "Runtime interface") on a small scene, each call checked.
The Python twin of examples/constraint_tour/main.cpp (same scene, same values);
docs/python.md quotes it.

    PYTHONPATH=<build>/python /usr/bin/python3 examples/python/tour.py

The scene (y is up, gravity (0, -9.81, 0)):
  base      held at the origin by a RigidPivotPosition (its centre) and a
            RigidPivotRotation (its orientation);
  arm       hangs from the base's right end by a RigidSphericalJoint, its swing
            limited by a JointRotationRange;
  carriage  slides along the vertical axis through the base
            (RigidPrismaticJoint + JointRotationTracking);
  tool      one of its points follows a prescribed rigid motion
            (RigidPivotToRigidTarget);
  wrist     an articulated actor (one revolute joint) driven by an
            ArticulatedSingleDofTarget and limited by an ArticulatedSingleDofRange.
Prints what each call returns; exits 1 when any call or value is not what the
documentation says.
"""
import math
import sys

import numpy as np

import mochi

failures = 0


def ok(what, fn):
    """A call that must succeed; returns its result."""
    global failures
    try:
        result = fn()
    except mochi.Error as e:
        print(f"  FAILED  {what}: {e}")
        failures += 1
        return None
    print(f"  ok      {what}")
    return result


def fails(what, fn, code):
    """A call that must raise mochi.Error with `code`; prints the library's message."""
    global failures
    try:
        fn()
    except mochi.Error as e:
        if e.code == code:
            print(f"  error   {what} -> {e}")
            return
        print(f"  FAILED  {what}: expected {code.name}, got {e}")
    else:
        print(f"  FAILED  {what}: expected {code.name}, got success")
    failures += 1


def check(what, condition):
    global failures
    print(f"  {'check  ' if condition else 'FAILED '} {what}")
    if not condition:
        failures += 1


def near(a, b, tolerance=1e-9):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= tolerance))


def about_z(angle):
    """Unit quaternion [w, x, y, z] of a rotation by `angle` about z."""
    return mochi.exp([0.0, 0.0, angle])


def main():
    np.set_printoptions(precision=4, suppress=True, linewidth=120)
    inf = math.inf

    # ---- 1. scene and bodies ----
    print("1. scene and bodies")
    scene = ok("Scene.create()", lambda: mochi.Scene.create())
    if scene is None:
        return 1
    bodies = {}
    for name, position in [("base", [0, 0, 0]), ("arm", [1, 0, 0]), ("carriage", [0, -1, 0]),
                           ("tool", [2, 0, 0])]:
        # 1 kg, inertia (1, 1, 1) kg·m², at rest
        bodies[name] = ok(f"create_rigid_actor({name})",
                          lambda position=position: scene.create_rigid_actor(position=position))
    base, arm, carriage, tool = (bodies[n] for n in ("base", "arm", "carriage", "tool"))
    # a one-link arm on a revolute joint about z at (0, 2, 0), link centre 0.25 m along x
    wrist = ok("create_articulated_actor(wrist)", lambda: scene.create_articulated_actor(
        links=[mochi.ArticulatedLinkParams(parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1],
                                           parent_to_joint_position=[0, 2, 0], mass=0.5,
                                           inertia=[1e-3, 1e-2, 1e-2], center_of_mass=[0.25, 0, 0])]))
    if failures:
        return 1

    # ---- 2. constraints, one factory each ----
    print("2. constraints")
    # hold the base: its centre at the origin, its orientation at identity
    pin = ok("create_rigid_pivot_position_constraint", lambda: scene.create_rigid_pivot_position_constraint(
        actor=base, local_pos=[0, 0, 0], position=[0, 0, 0], stiffness=1e5, damping=10))
    hold = ok("create_rigid_pivot_rotation_constraint", lambda: scene.create_rigid_pivot_rotation_constraint(
        actor=base, rotation=[1, 0, 0, 0], stiffness=1e4, damping=1))
    # the arm hangs from the base's right end (0.5, 0, 0) by its left end
    shoulder_params = mochi.RigidSphericalJointConstraintParams(
        actor_a=base, actor_b=arm, local_pos_a=[0.5, 0, 0], local_pos_b=[-0.5, 0, 0], stiffness=1e5)
    shoulder = ok("create_rigid_spherical_joint_constraint",
                  lambda: scene.create_rigid_spherical_joint_constraint(shoulder_params))
    # its swing in the x-y plane (z component of the relative rotation vector)
    # stays within ±0.5 rad of the rest pose; the other two components are free
    swing = ok("create_joint_rotation_range_constraint", lambda: scene.create_joint_rotation_range_constraint(
        actor_a=base, actor_b=arm, lower_limits=[-inf, -inf, -0.5], upper_limits=[inf, inf, 0.5],
        stiffness=1e3))
    # the carriage slides along world y (the joint frame's z axis), ±0.2 m
    # around where it starts; the prismatic joint leaves rotation free, so a
    # JointRotationTracking keeps the carriage's orientation relative to the base
    z_to_y = mochi.exp([-math.pi / 2, 0, 0])  # turns z onto y
    slide = ok("create_rigid_prismatic_joint_constraint", lambda: scene.create_rigid_prismatic_joint_constraint(
        actor_a=base, actor_b=carriage, joint_frame=z_to_y, lower_limit=-0.2, upper_limit=0.2, stiffness=1e4))
    lock = ok("create_joint_rotation_tracking_constraint",
              lambda: scene.create_joint_rotation_tracking_constraint(
                  actor_a=base, actor_b=carriage, stiffness=1e3, damping=1))
    # the tool's point (0.1, 0, 0) follows the prescribed transform T̂
    grip = ok("create_rigid_pivot_to_rigid_target_constraint",
              lambda: scene.create_rigid_pivot_to_rigid_target_constraint(
                  actor=tool, local_pos=[0.1, 0, 0], position=[2, 0, 0], rotation=[1, 0, 0, 0], stiffness=1e4))
    # the wrist's joint is driven toward a target angle, within ±0.4 rad
    drive = ok("create_articulated_single_dof_target_constraint",
               lambda: scene.create_articulated_single_dof_target_constraint(
                   actor=wrist, joint_index=0, target=0.0, stiffness=50, damping=1))
    stop = ok("create_articulated_single_dof_range_constraint",
              lambda: scene.create_articulated_single_dof_range_constraint(
                  actor=wrist, joint_index=0, lower_limit=-0.4, upper_limit=0.4, stiffness=1e4))
    if failures:
        return 1

    # bad parameters are reported and create nothing
    bad = shoulder_params.__copy__()
    bad.actor_b = base  # the same body twice
    fails("create_rigid_spherical_joint_constraint(actor_a == actor_b)",
          lambda: scene.create_rigid_spherical_joint_constraint(bad), mochi.ErrorCode.InvalidArgument)
    check("9 constraints", scene.get_num_constraints() == 9)

    # ---- 3. handles and introspection ----
    print("3. handles and introspection")
    shoulder_handle = shoulder.get_handle()
    check("get_constraint(shoulder.get_handle()) == shoulder", scene.get_constraint(shoulder_handle) == shoulder)

    def describe(c):
        dofs = " ".join(str(c.get_dof_indices_for_actor(i).tolist()) for i in range(c.get_num_actors()))
        print(f"          {c.get_type().name:28s} actors {c.get_num_actors()}  m {c.get_dimension()}"
              f"  n {c.get_num_dofs():2d}  dofs {dofs}")

    scene.for_each_constraint(describe)
    check("slide.get_actor(1) == carriage", slide.get_actor(1) == carriage)
    check("slide.get_actor(2) is None (out of range)", slide.get_actor(2) is None)
    check("slide.get_type() == RigidPrismaticJoint", slide.get_type() == mochi.ConstraintType.RigidPrismaticJoint)
    check("swing touches the arm's rotation DoFs [9, 10, 11]",
          swing.get_dof_indices_for_actor(1).tolist() == [9, 10, 11])
    check("drive touches the wrist's DoF [24]", drive.get_dof_indices_for_actor(0).tolist() == [24])

    # ---- 4. stiffness, damping, saturation ----
    print("4. parameters")
    ok("pin.set_stiffness(2e5)", lambda: pin.set_stiffness(2e5))
    ok("pin.set_damping(20)", lambda: pin.set_damping(20))
    ok("pin.set_saturation(0.01)   force cap 2e5 * 0.01 = 2000 N", lambda: pin.set_saturation(0.01))
    ok("pin.set_saturation(-1)     disabled again", lambda: pin.set_saturation(-1))
    fails("pin.set_stiffness(-1)", lambda: pin.set_stiffness(-1), mochi.ErrorCode.InvalidArgument)
    check("the failed call changed nothing: stiffness 2e5", pin.get_stiffness() == 2e5)
    check("get_damping() == 20, get_saturation() == -1", pin.get_damping() == 20 and pin.get_saturation() == -1)

    # ---- 5. targets ----
    print("5. targets")
    # teleport the pin's target 5 cm up: update_old_target, so the jump is not
    # read as a velocity by the damping term
    ok("pin.set_target_position([0, 0.05, 0])", lambda: pin.set_target_position([0, 0.05, 0]))
    ok("pin.update_old_target()", lambda: pin.update_old_target())
    g = pin.get_deviation()
    print(f"          pin g = {g} m")
    check("pin g = T(r) - p = (0, -0.05, 0)", near(g, [0, -0.05, 0]))
    # turn the base's target 0.1 rad about z without update_old_target: the
    # damping term reads the change as the target moving during the next step
    ok("hold.set_target_rotation(0.1 rad about z)", lambda: hold.set_target_rotation(about_z(0.1)))
    g = hold.get_deviation()
    print(f"          hold g = {g} rad")
    check("hold g = Log(R R̂⁻¹) = (0, 0, -0.1)", near(g, [0, 0, -0.1]))
    ok("lock.set_target_rotation(identity)", lambda: lock.set_target_rotation([1, 0, 0, 0]))
    check("lock g = 0 (the bodies are aligned)", near(lock.get_deviation(), [0, 0, 0]))
    ok("grip.set_target_transform([2, 0, 0], 0.2 rad about z)",
       lambda: grip.set_target_transform([2, 0, 0], about_z(0.2)))
    g = grip.get_deviation()
    print(f"          grip g = {g} m")
    check("grip g = T(r) - T̂(r)", near(g, [0.1 * (1 - math.cos(0.2)), -0.1 * math.sin(0.2), 0]))
    ok("drive.set_target_dof(0.3)", lambda: drive.set_target_dof(0.3))
    check("drive g = θ - θ̂ = -0.3", near(drive.get_deviation(), [-0.3]))

    # ---- 6. methods that do not apply ----
    print("6. methods that do not apply")
    fails("pin.set_target_dof(0.3)", lambda: pin.set_target_dof(0.3), mochi.ErrorCode.NotSupported)
    fails("hold.set_target_position(...)", lambda: hold.set_target_position([0, 0, 0]),
          mochi.ErrorCode.NotSupported)
    fails("shoulder.update_old_target()", lambda: shoulder.update_old_target(), mochi.ErrorCode.NotSupported)
    fails("slide.get_limit_min_values()", lambda: slide.get_limit_min_values(), mochi.ErrorCode.NotSupported)

    # ---- 7. limits of the range types ----
    print("7. limits")
    lower = ok("swing.get_limit_min_values()", lambda: swing.get_limit_min_values())
    upper = ok("swing.get_limit_max_values()", lambda: swing.get_limit_max_values())
    print(f"          lower {lower}, upper {upper}")
    check("unbounded components report -inf / +inf",
          lower is not None and upper is not None and lower.tolist() == [-inf, -inf, -0.5]
          and upper.tolist() == [inf, inf, 0.5])
    check("swing g = 0 inside its bounds", near(swing.get_deviation(), [0, 0, 0]))
    check("stop limits [-0.4] .. [0.4]",
          stop.get_limit_min_values().tolist() == [-0.4] and stop.get_limit_max_values().tolist() == [0.4])
    check("swing.is_range(), not slide.is_range()", swing.is_range() and not slide.is_range())

    # ---- 8. force queries ----
    print("8. force queries")
    check("pin.is_query_supported(ConstraintForce)", pin.is_query_supported(mochi.QueryType.ConstraintForce))
    fails("pin.get_force() before register_query", lambda: pin.get_force(), mochi.ErrorCode.InvalidState)
    ok("pin.register_query(ConstraintForce)", lambda: pin.register_query(mochi.QueryType.ConstraintForce))
    ok("shoulder.register_query(ConstraintForce)", lambda: shoulder.register_query(mochi.QueryType.ConstraintForce))
    fails("pin.get_force() before a step", lambda: pin.get_force(), mochi.ErrorCode.InvalidState)
    ok("scene.step(0.01)", lambda: scene.step(0.01))
    pin_force = ok("pin.get_force()", lambda: pin.get_force())
    print(f"          pin force = {pin_force}  (N on the base, then N·m)")
    joint_force = ok("shoulder.get_force()", lambda: shoulder.get_force())
    print(f"          shoulder force = {joint_force}")
    check("the joint pulls the two bodies with opposite forces",
          joint_force is not None and near(joint_force[0:3], -joint_force[6:9]))
    stats = scene.get_stats()
    print(f"          {stats}")
    check("one step, one pattern build", stats.steps == 1 and stats.pattern_builds == 1)

    # ---- 9. destruction ----
    print("9. destruction")
    ok("destroy_constraint(grip)        by object", lambda: scene.destroy_constraint(grip))
    hold_handle = hold.get_handle()
    ok("destroy_constraint(hold_handle) by handle", lambda: scene.destroy_constraint(hold_handle))
    check("get_constraint(hold_handle) is None (stale)", scene.get_constraint(hold_handle) is None)
    fails("destroy_constraint(hold_handle) again", lambda: scene.destroy_constraint(hold_handle),
          mochi.ErrorCode.InvalidHandle)
    fails("hold.get_deviation() on the destroyed constraint", lambda: hold.get_deviation(),
          mochi.ErrorCode.InvalidHandle)
    # a new constraint may reuse the freed slot; the old handle stays stale
    hold2 = ok("create_rigid_pivot_rotation_constraint (again)",
               lambda: scene.create_rigid_pivot_rotation_constraint(actor=base, stiffness=1e4, damping=1))
    print(f"          old handle {hold_handle}, new handle {hold2.get_handle()}")
    check("the old handle still names nothing",
          scene.get_constraint(hold_handle) is None and scene.get_constraint(hold2.get_handle()) == hold2)
    before = scene.get_num_constraints()
    ok("destroy_actor(arm)", lambda: scene.destroy_actor(arm))
    print(f"          constraints: {before} -> {scene.get_num_constraints()}")
    check("the shoulder and the swing range went with the arm",
          scene.get_num_constraints() == before - 2 and scene.get_constraint(shoulder_handle) is None
          and not shoulder.is_alive() and not swing.is_alive())
    check("the carriage's DoFs were renumbered: slide touches [6, 7, 8]",
          slide.get_dof_indices_for_actor(1).tolist() == [6, 7, 8])
    ok("scene.step(0.01)", lambda: scene.step(0.01))

    if failures:
        print(f"tour.py: {failures} unexpected result(s)")
        return 1
    print("tour.py: every call returned what was expected")
    return 0


if __name__ == "__main__":
    sys.exit(main())
