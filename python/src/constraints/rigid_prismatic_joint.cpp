// constraints/rigid_prismatic_joint.h: relative translation of two rigid bodies
// restricted to a sliding axis, optional travel limits (m = 3, n = 9).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineRigidPrismaticJoint(py::module_&) {
  using T = RigidPrismaticJointConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_offset", Forward<Ref>(&T::GetOffset),
           "s (before the limit rule), the offset of B from A in the joint frame [m].")
      .def("get_lower_limit", Forward<Ref>(&T::GetLowerLimit), "l [m]")
      .def("get_upper_limit", Forward<Ref>(&T::GetUpperLimit), "u [m]");
}

}  // namespace superdex::python
