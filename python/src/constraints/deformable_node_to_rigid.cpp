// constraints/deformable_node_to_rigid.h: a node attached to a point of a rigid
// body, g = T_R(r) - T_D(X + u) (m = 3, n = 9).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineDeformableNodeToRigid(py::module_& m) {
  using P = DeformableNodeToRigidConstraintParams;
  ParamsClass<P>(
      m, "DeformableNodeToRigidConstraintParams",
      "g = T_R(r) - T_D(X + u) (m = 3, n = 9). By default (fix_to_deformable_pos) r is computed "
      "at creation so the constraint starts at zero deviation.")
      .Field("deformable_actor", &P::deformableActor, "a deformable or rod actor")
      .Field("rigid_actor", &P::rigidActor, "a rigid actor, or an articulated actor with rigid_link")
      .Field("rigid_link", &P::rigidLink, "the articulated actor\'s link acting as the rigid body (-1: a rigid actor)")
      .Field("deformable_node_index", &P::deformableNodeIndex, "node of the deformable actor")
      .Field("fix_to_deformable_pos", &P::fixToDeformablePos,
             "r from the node's position at creation (default True)")
      .Field("local_pos", &P::localPos,
             "r in the rigid body frame when not fix_to_deformable_pos [m]")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = DeformableNodeToRigidConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "DeformableNodeToRigidConstraint", "Node-to-rigid attachment.")
      .def("get_local_pos", Forward<Ref>(&T::GetLocalPos),
           "r, the pivot in the rigid body's frame [m].");
}

}  // namespace superdex::python
