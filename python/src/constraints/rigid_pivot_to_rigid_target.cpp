// constraints/rigid_pivot_to_rigid_target.h: a rigid body's point pinned to
// the same point carried by a prescribed rigid motion, g = T(r) - T̂(r).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineRigidPivotToRigidTarget(py::module_&) {
  using T = RigidPivotToRigidTargetConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_local_pos", Forward<Ref>(&T::GetLocalPos), "r, body frame [m].");
}

}  // namespace superdex::python
