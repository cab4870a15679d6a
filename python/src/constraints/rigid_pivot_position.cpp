// constraints/rigid_pivot_position.h: a rigid body's point pinned to a target,
// g = T(r) - p̂ (m = 3, n = 6).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRigidPivotPosition(py::module_& m) {
  using P = RigidPivotPositionConstraintParams;
  ParamsClass<P>(m, "RigidPivotPositionConstraintParams",
                 "Pins a point of a rigid body to a kinematic target: g = T(r) - p̂ (m = 3, n = 6).")
      .Field("actor", &P::actor, "a rigid actor, or an articulated actor with link")
      .Field("link", &P::link, "the articulated actor\'s link acting as the body (-1: a rigid actor)")
      .Field("local_pos", &P::localPos, "pivot r in the body frame [m]")
      .Field("position", &P::position, "target p̂, world [m]")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = RigidPivotPositionConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "RigidPivotPositionConstraint", "Point-to-target pin.")
      .def("get_local_pos", Forward<Ref>(&T::GetLocalPos), "r, body frame [m].")
      .def("get_target_position", Forward<Ref>(&T::GetTargetPosition), "p̂, world [m].");
}

}  // namespace superdex::python
