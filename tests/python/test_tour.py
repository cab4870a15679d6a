"""The runtime interface of constraints.md through mochi, on the scene of
examples/python/tour.py (and of the C++ examples/constraint_tour), with the
results asserted: lifecycle, introspection, parameters, kinematic targets,
diagnostics and queries, limits."""
import math

import numpy as np
import pytest

import mochi
from helpers import about_z

INF = math.inf
# Exact kinematics (g of a configuration set at creation): only round-off in
# a few products of unit quaternions and rotation matrices, ~1e-16.
KINEMATIC_TOL = 1e-12


class Tour:
    """The tour's scene: base held by a pin and a rotation target, an arm on a
    spherical joint with a swing range, a carriage on a prismatic joint with a
    rotation lock, a tool following a rigid target, a one-link wrist driven by
    an articulated target within a range."""

    def __init__(self):
        self.scene = mochi.Scene.create()
        s = self.scene
        self.base = s.create_rigid_actor(position=[0, 0, 0])
        self.arm = s.create_rigid_actor(position=[1, 0, 0])
        self.carriage = s.create_rigid_actor(position=[0, -1, 0])
        self.tool = s.create_rigid_actor(position=[2, 0, 0])
        self.wrist = s.create_articulated_actor(links=[mochi.ArticulatedLinkParams(
            parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1], parent_to_joint_position=[0, 2, 0],
            mass=0.5, inertia=[1e-3, 1e-2, 1e-2], center_of_mass=[0.25, 0, 0])])
        self.pin = s.create_rigid_pivot_position_constraint(actor=self.base, stiffness=1e5, damping=10)
        self.hold = s.create_rigid_pivot_rotation_constraint(actor=self.base, stiffness=1e4, damping=1)
        self.shoulder = s.create_rigid_spherical_joint_constraint(
            actor_a=self.base, actor_b=self.arm, local_pos_a=[0.5, 0, 0], local_pos_b=[-0.5, 0, 0],
            stiffness=1e5)
        self.swing = s.create_joint_rotation_range_constraint(
            actor_a=self.base, actor_b=self.arm, lower_limits=[-INF, -INF, -0.5], upper_limits=[INF, INF, 0.5],
            stiffness=1e3)
        self.slide = s.create_rigid_prismatic_joint_constraint(
            actor_a=self.base, actor_b=self.carriage, joint_frame=mochi.exp([-math.pi / 2, 0, 0]),
            lower_limit=-0.2, upper_limit=0.2, stiffness=1e4)
        self.lock = s.create_joint_rotation_tracking_constraint(
            actor_a=self.base, actor_b=self.carriage, stiffness=1e3, damping=1)
        self.grip = s.create_rigid_pivot_to_rigid_target_constraint(
            actor=self.tool, local_pos=[0.1, 0, 0], position=[2, 0, 0], stiffness=1e4)
        self.drive = s.create_articulated_single_dof_target_constraint(
            actor=self.wrist, joint_index=0, stiffness=50, damping=1)
        self.stop = s.create_articulated_single_dof_range_constraint(
            actor=self.wrist, joint_index=0, lower_limit=-0.4, upper_limit=0.4, stiffness=1e4)


@pytest.fixture
def tour():
    return Tour()


def test_lifecycle_factories_return_typed_objects(tour):
    assert tour.scene.get_num_actors() == 5
    assert tour.scene.get_num_constraints() == 9
    assert tour.scene.get_num_dofs() == 4 * 6 + 1
    assert isinstance(tour.base, mochi.RigidActor)
    assert isinstance(tour.wrist, mochi.ArticulatedActor)
    assert isinstance(tour.shoulder, mochi.RigidSphericalJointConstraint)
    assert isinstance(tour.shoulder, mochi.Constraint)
    assert isinstance(tour.drive, mochi.ArticulatedSingleDofConstraint)
    assert tour.drive.get_type() == mochi.ConstraintType.ArticulatedSingleDofTarget
    assert tour.stop.get_type() == mochi.ConstraintType.ArticulatedSingleDofRange
    # get_constraint / get_actor resolve handles to equal objects of the same class
    again = tour.scene.get_constraint(tour.shoulder.get_handle())
    assert again == tour.shoulder and type(again) is mochi.RigidSphericalJointConstraint
    assert hash(again) == hash(tour.shoulder)
    assert tour.scene.get_actor(tour.arm.get_handle()) == tour.arm
    assert tour.shoulder != tour.swing
    # for_each_constraint visits every constraint once, in creation order
    seen = []
    tour.scene.for_each_constraint(lambda c: seen.append(c.get_type()))
    assert seen == [mochi.ConstraintType.RigidPivotPosition, mochi.ConstraintType.RigidPivotRotation,
                    mochi.ConstraintType.RigidSphericalJoint, mochi.ConstraintType.JointRotationRange,
                    mochi.ConstraintType.RigidPrismaticJoint, mochi.ConstraintType.JointRotationTracking,
                    mochi.ConstraintType.RigidPivotToRigidTarget,
                    mochi.ConstraintType.ArticulatedSingleDofTarget,
                    mochi.ConstraintType.ArticulatedSingleDofRange]
    assert tour.scene.get_constraints() == [tour.pin, tour.hold, tour.shoulder, tour.swing, tour.slide,
                                            tour.lock, tour.grip, tour.drive, tour.stop]
    visited = []
    tour.scene.for_each_actor(visited.append)
    assert visited == [tour.base, tour.arm, tour.carriage, tour.tool, tour.wrist]


def test_introspection(tour):
    # (m, n, DoFs per actor) of each type, as the reference page's table
    expected = {
        "pin": (3, 6, [[0, 1, 2, 3, 4, 5]]),
        "hold": (3, 3, [[3, 4, 5]]),
        "shoulder": (3, 12, [[0, 1, 2, 3, 4, 5], [6, 7, 8, 9, 10, 11]]),
        "swing": (3, 6, [[3, 4, 5], [9, 10, 11]]),
        "slide": (3, 9, [[0, 1, 2, 3, 4, 5], [12, 13, 14]]),
        "lock": (3, 6, [[3, 4, 5], [15, 16, 17]]),
        "grip": (3, 6, [[18, 19, 20, 21, 22, 23]]),
        "drive": (1, 1, [[24]]),
        "stop": (1, 1, [[24]]),
    }
    for name, (m, n, dofs) in expected.items():
        c = getattr(tour, name)
        assert c.get_dimension() == m, name
        assert c.get_num_dofs() == n, name
        assert c.get_num_actors() == len(dofs), name
        for i, d in enumerate(dofs):
            indices = c.get_dof_indices_for_actor(i)
            assert isinstance(indices, np.ndarray)
            assert indices.tolist() == d, name
    assert tour.slide.get_actor(0) == tour.base
    assert tour.slide.get_actor(1) == tour.carriage
    assert tour.slide.get_actor(2) is None  # out of range, as the C++ nullptr
    assert tour.slide.get_dof_indices_for_actor(2).size == 0
    assert tour.swing.is_range() and tour.stop.is_range() and not tour.slide.is_range()


def test_parameters(tour):
    pin = tour.pin
    assert (pin.get_stiffness(), pin.get_damping(), pin.get_saturation()) == (1e5, 10, -1)
    pin.set_stiffness(2e5)
    pin.set_damping(20)
    pin.set_saturation(0.01)
    assert pin.get_saturation() == 0.01
    pin.set_saturation(-1)
    with pytest.raises(mochi.Error) as e:
        pin.set_stiffness(-1)
    assert e.value.code == mochi.ErrorCode.InvalidArgument
    # the failed call changed nothing
    assert (pin.get_stiffness(), pin.get_damping(), pin.get_saturation()) == (2e5, 20, -1)


def test_kinematic_targets(tour):
    tour.pin.set_target_position([0, 0.05, 0])
    tour.pin.update_old_target()
    np.testing.assert_allclose(tour.pin.get_deviation(), [0, -0.05, 0], atol=KINEMATIC_TOL)
    assert tour.pin.get_target_position().tolist() == [0, 0.05, 0]
    tour.hold.set_target_rotation(about_z(0.1))
    np.testing.assert_allclose(tour.hold.get_deviation(), [0, 0, -0.1], atol=KINEMATIC_TOL)
    tour.lock.set_target_rotation([1, 0, 0, 0])
    np.testing.assert_allclose(tour.lock.get_deviation(), [0, 0, 0], atol=KINEMATIC_TOL)
    np.testing.assert_allclose(tour.lock.get_target_rotation(), [1, 0, 0, 0], atol=KINEMATIC_TOL)
    tour.grip.set_target_transform([2, 0, 0], about_z(0.2))
    np.testing.assert_allclose(tour.grip.get_deviation(),
                               [0.1 * (1 - math.cos(0.2)), -0.1 * math.sin(0.2), 0], atol=KINEMATIC_TOL)
    tour.drive.set_target_dof(0.3)
    np.testing.assert_allclose(tour.drive.get_deviation(), [-0.3], atol=KINEMATIC_TOL)
    assert tour.drive.get_coordinate() == 0


def test_kinematic_target_animates_the_body(tour):
    # a target moved every step drags its body along (the reference page's "moving base")
    tour.pin.set_stiffness(1e6)
    tour.pin.set_damping(1e3)
    for step in range(1, 51):
        tour.pin.set_target_position([0.002 * step, 0, 0])
        tour.scene.step(0.01)
    # 0.1 m moved at 0.2 m/s; the compliant pin lags by about v·d/k + m·a/k,
    # a few 1e-4 m: 5e-3 m bounds the lag with a wide margin
    assert abs(tour.base.get_position()[0] - 0.1) < 5e-3


def test_methods_that_do_not_apply(tour):
    cases = [
        (lambda: tour.pin.set_target_dof(0.3), "SetTargetDof"),
        (lambda: tour.hold.set_target_position([0, 0, 0]), "SetTargetPosition"),
        (lambda: tour.shoulder.update_old_target(), "UpdateOldTarget"),
        (lambda: tour.slide.get_limit_min_values(), "GetLimitMinValues"),
        (lambda: tour.slide.get_limit_max_values(), "GetLimitMaxValues"),
        (lambda: tour.drive.set_target_rotation([1, 0, 0, 0]), "SetTargetRotation"),
        (lambda: tour.pin.set_target_transform([0, 0, 0], [1, 0, 0, 0]), "SetTargetTransform"),
    ]
    for call, method in cases:
        with pytest.raises(mochi.Error) as e:
            call()
        assert e.value.code == mochi.ErrorCode.NotSupported
        assert method in e.value.message


def test_limits(tour):
    lower, upper = tour.swing.get_limit_min_values(), tour.swing.get_limit_max_values()
    assert isinstance(lower, np.ndarray)
    assert lower.tolist() == [-INF, -INF, -0.5]
    assert upper.tolist() == [INF, INF, 0.5]
    np.testing.assert_array_equal(tour.swing.get_deviation(), [0, 0, 0])
    assert tour.stop.get_limit_min_values().tolist() == [-0.4]
    assert tour.stop.get_limit_max_values().tolist() == [0.4]
    # the prismatic joint's travel limits are not reported (reference page), but readable
    assert (tour.slide.get_lower_limit(), tour.slide.get_upper_limit()) == (-0.2, 0.2)


def test_force_queries(tour):
    force = mochi.QueryType.ConstraintForce
    assert tour.pin.is_query_supported(force)
    with pytest.raises(mochi.Error) as e:
        tour.pin.get_force()
    assert e.value.code == mochi.ErrorCode.InvalidState
    tour.pin.register_query(force)
    tour.shoulder.register_query(force)
    with pytest.raises(mochi.Error) as e:
        tour.pin.get_force()  # registered, but no step yet
    assert e.value.code == mochi.ErrorCode.InvalidState
    tour.scene.step(0.01)
    pin_force = tour.pin.get_force()
    joint_force = tour.shoulder.get_force()
    assert pin_force.shape == (6,) and joint_force.shape == (12,)
    # the joint acts on the two bodies with opposite forces (to round-off in f = -Jᵀ(κ g))
    np.testing.assert_allclose(joint_force[0:3], -joint_force[6:9], atol=1e-9)
    # the pin carries the weight of what hangs from the base, upward: not zero
    assert pin_force[1] > 0
    # get_force is a copy: later steps do not change the array already returned
    before = pin_force.copy()
    tour.scene.step(0.01)
    np.testing.assert_array_equal(pin_force, before)
    # the scene-level convenience registers the query on every constraint
    assert tour.scene.register_query(force) == tour.scene.get_num_constraints()
    tour.scene.step(0.01)
    assert tour.grip.get_force().shape == (6,)


def test_stats_and_time(tour):
    for _ in range(3):
        tour.scene.step(0.01)
    stats = tour.scene.get_stats()
    assert stats.steps == 3
    assert stats.pattern_builds == 1 and stats.symbolic_analyses == 1  # topology unchanged: reused
    assert stats.num_dofs == 25
    assert stats.newton_iterations >= 1
    assert stats.step_seconds > 0
    assert "Cholesky" in stats.linear_solver  # 25 DoFs: Auto picks dense
    assert tour.scene.get_time() == pytest.approx(0.03, abs=1e-15)


def test_destruction(tour):
    s = tour.scene
    s.destroy_constraint(tour.grip)  # by object
    hold_handle = tour.hold.get_handle()
    s.destroy_constraint(hold_handle)  # by handle
    assert s.get_constraint(hold_handle) is None
    with pytest.raises(mochi.Error) as e:
        s.destroy_constraint(hold_handle)
    assert e.value.code == mochi.ErrorCode.InvalidHandle
    hold2 = s.create_rigid_pivot_rotation_constraint(actor=tour.base, stiffness=1e4)
    assert s.get_constraint(hold_handle) is None  # the old handle stays stale
    assert s.get_constraint(hold2.get_handle()) == hold2
    before = s.get_num_constraints()
    s.destroy_actor(tour.arm)
    assert s.get_num_constraints() == before - 2  # the shoulder and the swing went with the arm
    assert not tour.shoulder.is_alive() and not tour.swing.is_alive()
    # the carriage's DoFs were renumbered
    assert tour.slide.get_dof_indices_for_actor(1).tolist() == [6, 7, 8]
    s.step(0.01)
