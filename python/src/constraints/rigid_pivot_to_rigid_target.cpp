// constraints/rigid_pivot_to_rigid_target.h: a rigid body's point pinned to
// the same point carried by a prescribed rigid motion, g = T(r) - T̂(r).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRigidPivotToRigidTarget(py::module_& m) {
  using P = RigidPivotToRigidTargetConstraintParams;
  ParamsClass<P>(
      m, "RigidPivotToRigidTargetConstraintParams",
      "g = T(r) - T̂(r) = t + R r - (t̂ + R̂ r) (m = 3, n = 6); T̂ set with set_target_transform.")
      .Field("actor", &P::actor, "a rigid actor, or an articulated actor with link")
      .Field("link", &P::link, "the articulated actor\'s link acting as the body (-1: a rigid actor)")
      .Field("local_pos", &P::localPos, "pivot r in the body frame [m]")
      .Field("position", &P::position, "target translation t̂, world [m]")
      .Field("rotation", &P::rotation, "target rotation R̂, world [w, x, y, z]")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = RigidPivotToRigidTargetConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "RigidPivotToRigidTargetConstraint",
                                 "Point-to-rigid-target pin.")
      .def("get_local_pos", Forward<Ref>(&T::GetLocalPos), "r, body frame [m].");
}

}  // namespace superdex::python
