// constraints/rod_element_rotation_to_rigid.h: a rod element's material frame
// driven relative to a rigid body, g = Log((R_R R̂ R₀)⁻¹ R_e R₀) (m = 3, n = 11).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRodElementRotationToRigid(py::module_& m) {
  using P = RodElementRotationToRigidConstraintParams;
  ParamsClass<P>(
      m, "RodElementRotationToRigidConstraintParams",
      "g = Log((R_R R̂ R₀)⁻¹ R_e R₀) (m = 3, n = 11: the body's 3 rotation DoFs, the element's "
      "8). The target starts as the creation-time relative rotation.")
      .Field("rigid_actor", &P::rigidActor, "a rigid actor, or an articulated actor with rigid_link")
      .Field("rigid_link", &P::rigidLink, "the articulated actor\'s link acting as the rigid body (-1: a rigid actor)")
      .Field("rod_actor", &P::rodActor, "a rod actor")
      .Field("element_index", &P::elementIndex, "element e = (e, e+1) of the rod")
      .Field("joint_frame", &P::jointFrame, "R₀, world, at creation [w, x, y, z]")
      .CompliantFields("[N·m/rad]", "[N·m·s/rad]", "[rad]");

  using T = RodElementRotationToRigidConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "RodElementRotationToRigidConstraint",
                                 "Rod element orientation relative to a body.")
      .def("get_element_index", Forward<Ref>(&T::GetElementIndex))
      .def("get_target_rotation", Forward<Ref>(&T::GetTargetRotation),
           "The current target R̂ (rod element relative to the body, body-local) [w, x, y, z].");
}

}  // namespace superdex::python
