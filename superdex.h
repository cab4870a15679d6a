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

#include <superdex/constraints/constraint.h>
#include <superdex/constraints/constraint_type_headers.h>  // every type (constraint_types.h)

#include <superdex/contact/collider.h>
#include <superdex/contact/contact_params.h>

#include <superdex/linsolve/linear_solver.h>

#include <superdex/stage/integrator.h>
#include <superdex/scene/scene.h>
#include <superdex/scene/scene_params.h>
