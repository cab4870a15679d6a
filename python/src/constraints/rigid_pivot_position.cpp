// constraints/rigid_pivot_position.h: a rigid body's point pinned to a target,
// g = T(r) - p̂ (m = 3, n = 6).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineRigidPivotPosition(py::module_&) {
  using T = RigidPivotPositionConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_local_pos", Forward<Ref>(&T::GetLocalPos), "r, body frame [m].")
      .def("get_target_position", Forward<Ref>(&T::GetTargetPosition), "p̂, world [m].");
}

}  // namespace superdex::python
