// constraints/deformable_node_to_rigid.h: a node attached to a point of a rigid
// body, g = T_R(r) - T_D(X + u) (m = 3, n = 9).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineDeformableNodeToRigid(py::module_&) {
  using T = DeformableNodeToRigidConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_local_pos", Forward<Ref>(&T::GetLocalPos),
           "r, the pivot in the rigid body's frame [m].");
}

}  // namespace superdex::python
