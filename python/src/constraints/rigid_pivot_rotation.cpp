// constraints/rigid_pivot_rotation.h: a rigid body's pivot frame driven toward
// a world rotation, g = Log(R R_ℓ R̂⁻¹) (m = 3, n = 3).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRigidPivotRotation(py::module_& m) {
  using P = RigidPivotRotationConstraintParams;
  ParamsClass<P>(m, "RigidPivotRotationConstraintParams",
                 "g = Log(R R_ℓ R̂⁻¹) (m = 3, n = 3: the body's rotation DoFs).")
      .Field("actor", &P::actor, "a rigid actor, or an articulated actor with link")
      .Field("link", &P::link, "the articulated actor\'s link acting as the body (-1: a rigid actor)")
      .Field("local_rotation", &P::localRotation, "pivot frame R_ℓ in the body frame [w, x, y, z]")
      .Field("rotation", &P::rotation, "target R̂, world [w, x, y, z]")
      .CompliantFields("[N·m/rad]", "[N·m·s/rad]", "[rad]");

  using T = RigidPivotRotationConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "RigidPivotRotationConstraint",
                                 "Rotation target of a rigid body.")
      .def("get_local_rotation", Forward<Ref>(&T::GetLocalRotation),
           "R_ℓ, body frame [w, x, y, z].");
}

}  // namespace superdex::python
