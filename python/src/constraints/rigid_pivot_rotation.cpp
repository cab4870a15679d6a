// constraints/rigid_pivot_rotation.h: a rigid body's pivot frame driven toward
// a world rotation, g = Log(R R_ℓ R̂⁻¹) (m = 3, n = 3).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineRigidPivotRotation(py::module_&) {
  using T = RigidPivotRotationConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_local_rotation", Forward<Ref>(&T::GetLocalRotation),
           "R_ℓ, body frame [w, x, y, z].");
}

}  // namespace superdex::python
