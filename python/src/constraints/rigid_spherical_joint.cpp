// constraints/rigid_spherical_joint.h: ball-and-socket between two rigid bodies,
// g = T_A(r_A) - T_B(r_B)   (m = 3, n = 12).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineRigidSphericalJoint(py::module_&) {
  using T = RigidSphericalJointConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_local_pos_a", Forward<Ref>(&T::GetLocalPosA), "r_A, body frame of A [m].")
      .def("get_local_pos_b", Forward<Ref>(&T::GetLocalPosB), "r_B, body frame of B [m].");
}

}  // namespace superdex::python
