"""Contact from Python (docs/contact.md): the names of the API, a box coming
to rest on a static ground with its weight carried by the contacts, and bad
colliders refused naming the field."""
import math

import numpy as np
import pytest

import mochi
from helpers import raises


def make_box_on_ground(mu=0.5):
    scene = mochi.Scene.create(contact=mochi.ContactParams(activation_distance=1e-3))
    ground = scene.create_collider(actor=None, shape=mochi.ShapeType.Plane, friction=mu)
    box = scene.create_rigid_actor(mass=2.0, inertia=[0.0133] * 3, position=[0, 0.12, 0])
    shape = scene.create_collider(actor=box, shape=mochi.ShapeType.Box, half_extents=[0.1, 0.1, 0.1],
                                  friction=mu)
    return scene, ground, box, shape


def test_contact_params_and_collider_api():
    params = mochi.SceneParams()
    assert params.contact.activation_distance == pytest.approx(1e-3)
    params.contact.stiffness = 2e6  # nested params read by reference
    assert params.contact.stiffness == 2e6
    scene, ground, box, shape = make_box_on_ground()
    assert scene.get_num_colliders() == 2
    assert ground.get_shape() == mochi.ShapeType.Plane
    assert shape.get_shape() == mochi.ShapeType.Box
    assert shape.get_actor() == box.get_handle()
    assert ground.get_id() != shape.get_id()


def test_a_box_falls_and_rests_on_the_ground():
    scene, ground, box, shape = make_box_on_ground()
    for _ in range(120):
        scene.step(1.0 / 60)
        assert box.get_position()[1] > 0.1  # its bottom face never below the ground
    stats = scene.get_stats()
    assert stats.active_contacts >= 4
    assert 0 < stats.min_contact_distance < 1e-3
    assert stats.contact_pattern_builds == 0  # obstacle contacts fit the analysed pattern
    assert stats.contact_recenterings == 0  # a box at rest stays well within its bounds
    assert stats.pattern_builds == 1
    # the contact phases of the last step: each ran, they are parts of the
    # step, and the contact assembly is part of the assembly
    phases = (stats.contact_broad_phase_seconds, stats.contact_narrow_phase_seconds,
              stats.contact_ccd_seconds, stats.contact_assembly_seconds)
    assert all(t > 0 for t in phases) and sum(phases) <= stats.step_seconds
    assert stats.contact_assembly_seconds <= stats.assembly_seconds
    contacts = scene.get_contacts()
    assert len(contacts) == stats.active_contacts
    # at rest the contacts carry the weight, m g = 19.62 N, along +y
    total = sum(c.normal_force * np.asarray(c.normal)[1] for c in contacts)
    assert total == pytest.approx(2.0 * 9.81, rel=1e-3)
    assert all(c.collider_a == shape.get_id() and c.collider_b == ground.get_id() for c in contacts)
    assert abs(box.get_linear_velocity()[1]) < 1e-6


def test_bad_colliders_are_refused_naming_the_field():
    scene = mochi.Scene.create()
    with raises(mochi.ErrorCode.InvalidArgument, "radius"):
        scene.create_collider(shape=mochi.ShapeType.Sphere, radius=0)
    with raises(mochi.ErrorCode.InvalidArgument, "position"):
        scene.create_collider(shape=mochi.ShapeType.Sphere, radius=0.1, position=[0, math.nan, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "triangles[0]"):
        scene.create_collider(shape=mochi.ShapeType.TriangleMesh, vertices=[[0, 0, 0], [1, 0, 0], [2, 0, 0]],
                              triangles=[[0, 1, 2]])
    with raises(mochi.ErrorCode.InvalidArgument, "contact.activationDistance"):
        mochi.Scene.create(contact=mochi.ContactParams(activation_distance=-1))
    assert mochi.ContactParams().ccd_max_iterations == 10000
    with raises(mochi.ErrorCode.InvalidArgument, "contact.ccdMaxIterations must be in [1, 100000000], got 0"):
        mochi.Scene.create(contact=mochi.ContactParams(ccd_max_iterations=0))
    with raises(mochi.ErrorCode.InvalidArgument, "halfLength must be finite and within ±1000000000"):
        scene.create_collider(shape=mochi.ShapeType.Capsule, radius=0.1, half_length=1e300)
    assert scene.get_num_colliders() == 0
    # a collider that starts through another is refused, naming both
    scene.create_collider(shape=mochi.ShapeType.Plane)
    box = scene.create_rigid_actor(position=[0, 0.05, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "intersects collider 0 (Plane)"):
        scene.create_collider(actor=box, shape=mochi.ShapeType.Box, half_extents=[0.1, 0.1, 0.1])
    assert scene.get_num_colliders() == 1
    # a destroyed actor takes its colliders along
    scene.destroy_actor(box)
    assert scene.get_num_colliders() == 1


def test_a_kinematic_ground_lifts_the_box_and_the_geometry_reads_back():
    scene, ground, box, shape = make_box_on_ground()
    for _ in range(60):
        scene.step(1.0 / 60)
    # the box's corners in the world, its 12 edges' 18 (two triangles a face)
    corners = np.asarray(shape.get_world_vertices())
    assert corners.shape == (8, 3)
    assert corners[:, 1].min() > 0
    assert len(shape.get_triangles()) == 12
    assert len(shape.get_edges()) == 18
    assert shape.get_thickness() == 0
    # the ground rises 0.1 m over 0.5 s, by a target per step, carrying the box
    for _ in range(30):
        ground.set_target_transform(np.asarray(ground.get_position()) + [0, 0.2 / 60, 0], [1, 0, 0, 0])
        scene.step(1.0 / 60)
        assert box.get_position()[1] - 0.1 > ground.get_position()[1]
    assert ground.get_position()[1] == pytest.approx(0.1, rel=1e-12)
    assert box.get_linear_velocity()[1] == pytest.approx(0.2, rel=0.01)
    assert scene.get_stats().contact_pattern_builds == 0
    # a body's collider is moved by its actor; a teleport into the box is refused
    with raises(mochi.ErrorCode.InvalidArgument, "carried by an actor"):
        shape.set_target_transform([0, 0, 0], [1, 0, 0, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "intersects collider"):
        ground.set_transform([0, 0.5, 0], [1, 0, 0, 0])
    assert ground.get_position()[1] == pytest.approx(0.1, rel=1e-12)


def test_a_link_collider_stops_a_swinging_pendulum_on_the_ground():
    # a revolute pendulum 0.35 m up, released horizontal; the sphere (r = 5 cm)
    # 0.4 m out on its link would swing to 5 cm below the ground: it comes to
    # rest on it instead (0.35 - 0.4 sin(theta) = r, sin(theta) = 0.75)
    scene = mochi.Scene.create()
    ground = scene.create_collider(shape=mochi.ShapeType.Plane, friction=0.5)
    arm = scene.create_articulated_actor(links=[
        mochi.ArticulatedLinkParams(parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1],
                                    parent_to_joint_position=[0, 0.35, 0], center_of_mass=[0.2, 0, 0],
                                    mass=1.0, inertia=[1e-3, 0.0133, 0.0133])])
    tip = scene.create_collider(actor=arm, link=0, shape=mochi.ShapeType.Sphere, radius=0.05,
                                position=[0.4, 0, 0])
    assert tip.get_link() == 0 and tip.get_actor() == arm.get_handle()
    for _ in range(90):
        scene.step(1.0 / 60)
        angle = arm.get_joint_positions()[0]
        centre = 0.35 + 0.4 * math.sin(angle)  # the sphere's centre height
        assert centre > 0.05  # above the ground by its radius: never through it
    # at rest on the ground: the sphere's gap in (0, d-hat = 1 mm), the angle
    # near -asin(0.75)
    gap = 0.35 + 0.4 * math.sin(arm.get_joint_positions()[0]) - 0.05
    assert 0 < gap < 1e-3
    contacts = scene.get_contacts()
    assert len(contacts) == 1
    assert contacts[0].collider_a == tip.get_id() and contacts[0].collider_b == ground.get_id()
    assert abs(arm.get_joint_velocities()[0]) < 1e-3
    with raises(mochi.ErrorCode.InvalidArgument, "link must name a link"):
        scene.create_collider(actor=arm, link=1, shape=mochi.ShapeType.Sphere, radius=0.05)


def test_the_links_of_a_mechanism_touch_each_other_but_not_their_parent_or_child():
    # a 3-link chain along +x, capsules on each link: links 0 and 2 may
    # touch, links 0 and 1 (parent and child) and 1 and 2 may not; then the
    # last link is driven round into the first and comes to rest on it
    params = mochi.SceneParams()
    params.gravity = [0, 0, 0]
    scene = mochi.Scene.create(params)
    lengths, start = [0.4, 0.1, 0.36], [0.0, math.pi / 2, math.pi / 2]
    arm = scene.create_articulated_actor(links=[
        mochi.ArticulatedLinkParams(parent=i - 1, joint=mochi.JointType.Revolute, axis=[0, 0, 1],
                                    parent_to_joint_position=[0, 0.5, 0] if i == 0 else [lengths[i - 1], 0, 0],
                                    center_of_mass=[lengths[i] / 2, 0, 0], mass=0.2,
                                    inertia=[1e-5, 0.2 * lengths[i] ** 2 / 12, 0.2 * lengths[i] ** 2 / 12],
                                    initial_position=[start[i]])
        for i in range(3)])
    along_x = [math.cos(math.pi / 4), 0, math.sin(math.pi / 4), 0]  # local z along x
    ends = [(0.02, 0.38), (0.02, 0.08), (0.05, 0.35)]
    capsules = [scene.create_collider(actor=arm, link=i, shape=mochi.ShapeType.Capsule, radius=0.015,
                                      half_length=(b - a) / 2, position=[(a + b) / 2, 0, 0], rotation=along_x)
                for i, (a, b) in enumerate(ends)]
    assert capsules[0].may_touch(capsules[2]) and capsules[2].may_touch(capsules[0])
    assert not capsules[0].may_touch(capsules[1]) and not capsules[1].may_touch(capsules[2])
    held = [scene.create_articulated_single_dof_target_constraint(
        actor=arm, joint_index=i, target=start[i], stiffness=2.0 if i == 2 else 100.0,
        damping=0.05 if i == 2 else 1.0) for i in range(3)]
    for s in range(60):
        held[2].set_target_dof(math.pi / 2 + min((s + 1) / 30, 1) * (2.6 - math.pi / 2))
        scene.step(1.0 / 60)
    # joint 2 stopped where link 2's capsule meets link 0's (~1.772 rad with
    # the arm straight), far short of its target 2.6
    angle = arm.get_joint_positions()[2]
    assert 1.76 < angle < 1.82
    contacts = scene.get_contacts()
    assert contacts and all({c.collider_a, c.collider_b} == {capsules[0].get_id(), capsules[2].get_id()}
                            for c in contacts)
