// constraints/joint_rotation_tracking.h: drives the relative rotation of two
// rigid bodies toward a target (m = 3, n = 6).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineJointRotationTracking(py::module_&) {
  using T = JointRotationTrackingConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_target_rotation", Forward<Ref>(&T::GetTargetRotation),
           "The current target R̂ (B relative to A, A-local) [w, x, y, z].");
}

}  // namespace superdex::python
