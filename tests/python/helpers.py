"""Scene builders shared by the mochi test files (the Python twin of
tests/test_scenes.h), and `raises`."""
import contextlib
import math

import numpy as np
import pytest

import mochi


@contextlib.contextmanager
def raises(code, *fragments):
    """The block raises mochi.Error with `code` and a message containing every fragment."""
    with pytest.raises(mochi.Error) as info:
        yield info
    e = info.value
    assert e.code == code, str(e)
    for fragment in fragments:
        assert fragment in e.message, (fragment, e.message)


def make_zoo(scene):
    """One actor of every kind, for the factories of every constraint type:
    two rigid bodies, a tet box, a rod, an articulated actor with a revolute
    joint (link 0) and a spherical joint (link 1)."""
    zoo = {}
    zoo["a"] = scene.create_rigid_actor(position=[0, 0, 0])
    zoo["b"] = scene.create_rigid_actor(position=[1, 0, 0])
    mesh = mochi.make_tet_box(origin=[0, 2, 0], size=[0.1, 0.1, 0.1], cells=[1, 1, 1])
    zoo["soft"] = scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=mesh.tetrahedra)
    zoo["soft2"] = scene.create_deformable_actor(nodes=mesh.nodes + [0.5, 0, 0], tetrahedra=mesh.tetrahedra)
    zoo["rod"] = scene.create_rod_actor(nodes=[[0, 3, 0], [0.1, 3, 0], [0.2, 3, 0]], radius=0.005)
    zoo["arm"] = scene.create_articulated_actor(links=[
        mochi.ArticulatedLinkParams(parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1],
                                    parent_to_joint_position=[0, 4, 0], center_of_mass=[0.25, 0, 0]),
        mochi.ArticulatedLinkParams(parent=0, joint=mochi.JointType.Spherical,
                                    parent_to_joint_position=[0.5, 0, 0], center_of_mass=[0.25, 0, 0]),
    ])
    return zoo


def valid_params(zoo):
    """(factory name, params class, valid keyword arguments) for every constraint type."""
    a, b, soft, soft2, rod, arm = (zoo[k] for k in ("a", "b", "soft", "soft2", "rod", "arm"))
    return [
        ("create_rigid_spherical_joint_constraint", mochi.RigidSphericalJointConstraintParams,
         dict(actor_a=a, actor_b=b, local_pos_a=[0.5, 0, 0], local_pos_b=[-0.5, 0, 0], stiffness=1e4)),
        ("create_rigid_prismatic_joint_constraint", mochi.RigidPrismaticJointConstraintParams,
         dict(actor_a=a, actor_b=b, lower_limit=-0.1, upper_limit=0.1, stiffness=1e4)),
        ("create_joint_rotation_range_constraint", mochi.JointRotationRangeConstraintParams,
         dict(actor_a=a, actor_b=b, lower_limits=[-1, -1, -1], upper_limits=[1, 1, 1], stiffness=1e3)),
        ("create_joint_rotation_tracking_constraint", mochi.JointRotationTrackingConstraintParams,
         dict(actor_a=a, actor_b=b, stiffness=1e3)),
        ("create_rigid_pivot_position_constraint", mochi.RigidPivotPositionConstraintParams,
         dict(actor=a, stiffness=1e4)),
        ("create_rigid_pivot_to_rigid_target_constraint", mochi.RigidPivotToRigidTargetConstraintParams,
         dict(actor=a, stiffness=1e4)),
        ("create_rigid_pivot_rotation_constraint", mochi.RigidPivotRotationConstraintParams,
         dict(actor=a, stiffness=1e3)),
        ("create_deformable_node_position_constraint", mochi.DeformableNodePositionConstraintParams,
         dict(actor=soft, node_index=0, position=soft.get_node_position(0), stiffness=1e4)),
        ("create_deformable_node_to_deformable_node_constraint",
         mochi.DeformableNodeToDeformableNodeConstraintParams,
         dict(actor_a=soft, actor_b=soft2, node_index_a=1, node_index_b=0, stiffness=1e3)),
        ("create_deformable_node_to_rigid_constraint", mochi.DeformableNodeToRigidConstraintParams,
         dict(deformable_actor=soft, rigid_actor=a, deformable_node_index=0, stiffness=1e3)),
        ("create_rod_element_rotation_to_rigid_constraint", mochi.RodElementRotationToRigidConstraintParams,
         dict(rigid_actor=a, rod_actor=rod, element_index=0, stiffness=10)),
        ("create_articulated_single_dof_target_constraint", mochi.ArticulatedSingleDofTargetConstraintParams,
         dict(actor=arm, joint_index=0, target=0.1, stiffness=10)),
        ("create_articulated_single_dof_range_constraint", mochi.ArticulatedSingleDofRangeConstraintParams,
         dict(actor=arm, joint_index=0, lower_limit=-0.5, upper_limit=0.5, stiffness=10)),
        ("create_articulated_3d_rotation_target_constraint", mochi.Articulated3dRotationTargetConstraintParams,
         dict(actor=arm, joint_index=1, stiffness=10)),
        ("create_articulated_3d_rotation_range_constraint", mochi.Articulated3dRotationRangeConstraintParams,
         dict(actor=arm, joint_index=1, lower_limits=[-1, -1, -1], upper_limits=[1, 1, 1], stiffness=10)),
    ]


def about_z(angle):
    """Unit quaternion [w, x, y, z] of a rotation by `angle` about z."""
    return np.array([math.cos(angle / 2), 0, 0, math.sin(angle / 2)])


def sagging_beam(**params):
    """A 0.6 m beam of 12x3x3 tet cells (624 DoFs), clamped at x = 0 by stiff node
    constraints, in a scene created with `params`; returns (scene, beam)."""
    mesh = mochi.make_tet_box(origin=[0, 0, 0], size=[0.6, 0.15, 0.15], cells=[12, 3, 3])
    scene = mochi.Scene.create(**params)
    beam = scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=mesh.tetrahedra, density=1000,
                                         young_modulus=1e6, poisson_ratio=0.3)
    for i, x in enumerate(beam.get_node_reference_positions()):
        if x[0] == 0:
            scene.create_deformable_node_position_constraint(actor=beam, node_index=i, position=x,
                                                             stiffness=1e8)
    return scene, beam
