// The constraint types, one line each: the one list a new type is added to
// (docs/extending.md). Everything a type needs beyond its own two files
// comes from here:
//   ConstraintType::Name and its name (ToString)       constraint_kernel.h
//   Scene::CreateNameConstraint(NameConstraintParams)  scene/scene.h, the factory
//     calling the class's Create (its validation)
//   the sources and headers of the build              constraints/CMakeLists.txt
//   mochi's params class, create_name_constraint and  python/src/constraints/types.cpp
//     the downcast of a Constraint to its class
//   the API fuzzer's coverage                         tests/fuzz/fuzz_scene_api.cpp
//   the table of types in docs/constraints.md         tests/constraints/constraint_registry_test
//
//   X(Name, Class, file)
//     Name   the type: ConstraintType::Name, the params struct NameConstraintParams
//     Class  the class its factory creates (one class may serve a target and a
//            range type: one line each)
//     file   constraints/file.h and constraints/file.cc declare and define
//            the params, the class and Class::Create
//
// The order is ConstraintType's (its values are stable: append new types
// before the blank line that ends the list; every entry ends in a backslash).
#pragma once

// clang-format off
#define SUPERDEX_CONSTRAINT_TYPES(X)                                                                  \
  X(RigidSphericalJoint, RigidSphericalJointConstraint, rigid_spherical_joint)                         \
  X(RigidPrismaticJoint, RigidPrismaticJointConstraint, rigid_prismatic_joint)                         \
  X(JointRotationRange, JointRotationRangeConstraint, joint_rotation_range)                            \
  X(JointRotationTracking, JointRotationTrackingConstraint, joint_rotation_tracking)                   \
  X(RigidPivotPosition, RigidPivotPositionConstraint, rigid_pivot_position)                            \
  X(RigidPivotToRigidTarget, RigidPivotToRigidTargetConstraint, rigid_pivot_to_rigid_target)           \
  X(RigidPivotRotation, RigidPivotRotationConstraint, rigid_pivot_rotation)                            \
  X(DeformableNodePosition, DeformableNodePositionConstraint, deformable_node_position)                \
  X(DeformableNodeToDeformableNode, DeformableNodeToDeformableNodeConstraint, deformable_node_to_deformable_node) \
  X(DeformableNodeToRigid, DeformableNodeToRigidConstraint, deformable_node_to_rigid)                  \
  X(ArticulatedSingleDofTarget, ArticulatedSingleDofConstraint, articulated_joint_constraints)         \
  X(ArticulatedSingleDofRange, ArticulatedSingleDofConstraint, articulated_joint_constraints)          \
  X(Articulated3dRotationTarget, Articulated3dRotationConstraint, articulated_joint_constraints)       \
  X(Articulated3dRotationRange, Articulated3dRotationConstraint, articulated_joint_constraints)        \
  X(RodElementRotationToRigid, RodElementRotationToRigidConstraint, rod_element_rotation_to_rigid)       \

// clang-format on
