// SuperDex Physics — umbrella header. Include <superdex/superdex.h>.
#pragma once

#include <superdex/core/blas_info.h>
#include <superdex/core/communicator.h>
#include <superdex/core/config.h>
#include <superdex/core/error.h>
#include <superdex/core/handle.h>
#include <superdex/core/so3.h>
#include <superdex/core/types.h>

#include <superdex/actors/actor.h>
#include <superdex/actors/articulated_actor.h>
#include <superdex/actors/deformable_actor.h>
#include <superdex/actors/mesh.h>
#include <superdex/actors/vtk_writer.h>
#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/actors/rod_actor.h>
#include <superdex/actors/rod_element.h>

#include <superdex/constraints/articulated_joint_constraints.h>
#include <superdex/constraints/constraint.h>
#include <superdex/constraints/deformable_node_position.h>
#include <superdex/constraints/deformable_node_to_deformable_node.h>
#include <superdex/constraints/deformable_node_to_rigid.h>
#include <superdex/constraints/joint_rotation_range.h>
#include <superdex/constraints/joint_rotation_tracking.h>
#include <superdex/constraints/rigid_pivot_position.h>
#include <superdex/constraints/rigid_pivot_rotation.h>
#include <superdex/constraints/rigid_pivot_to_rigid_target.h>
#include <superdex/constraints/rigid_prismatic_joint.h>
#include <superdex/constraints/rigid_spherical_joint.h>
#include <superdex/constraints/rod_element_rotation_to_rigid.h>

#include <superdex/linsolve/linear_solver.h>

#include <superdex/stage/integrator.h>
#include <superdex/scene/scene.h>
#include <superdex/scene/scene_params.h>
