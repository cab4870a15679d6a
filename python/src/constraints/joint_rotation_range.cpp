// constraints/joint_rotation_range.h: componentwise bounds on the relative
// rotation of two rigid bodies (range type, m = 3, n = 6).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineJointRotationRange(py::module_&) {
  using T = JointRotationRangeConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_relative_rotation", Forward<Ref>(&T::GetRelativeRotation),
           "r_AB, the measured relative rotation vector [rad].");
}

}  // namespace superdex::python
