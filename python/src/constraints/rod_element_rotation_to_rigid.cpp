// constraints/rod_element_rotation_to_rigid.h: a rod element's material frame
// driven relative to a rigid body, g = Log((R_R R̂ R₀)⁻¹ R_e R₀) (m = 3, n = 11).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineRodElementRotationToRigid(py::module_&) {
  using T = RodElementRotationToRigidConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_element_index", Forward<Ref>(&T::GetElementIndex))
      .def("get_target_rotation", Forward<Ref>(&T::GetTargetRotation),
           "The current target R̂ (rod element relative to the body, body-local) [w, x, y, z].");
}

}  // namespace superdex::python
