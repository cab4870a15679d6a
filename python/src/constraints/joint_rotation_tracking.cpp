// constraints/joint_rotation_tracking.h: drives the relative rotation of two
// rigid bodies toward a target (m = 3, n = 6).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineJointRotationTracking(py::module_& m) {
  using P = JointRotationTrackingConstraintParams;
  ParamsClass<P>(
      m, "JointRotationTrackingConstraintParams",
      "g = Log((R_A R̂ R₀)⁻¹ R_B R₀) (m = 3, n = 6); the target R̂ starts as the creation-time "
      "relative rotation and is changed with set_target_rotation.")
      .Field("actor_a", &P::actorA, "a rigid actor")
      .Field("actor_b", &P::actorB, "a different rigid actor")
      .Field("link_a", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)")
      .Field("link_b", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)")
      .Field("joint_frame", &P::jointFrame, "joint frame R₀, world, at creation [w, x, y, z]")
      .CompliantFields("[N·m/rad]", "[N·m·s/rad]", "[rad]");

  using T = JointRotationTrackingConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "JointRotationTrackingConstraint", "Relative-rotation target.")
      .def("get_target_rotation", Forward<Ref>(&T::GetTargetRotation),
           "The current target R̂ (B relative to A, A-local) [w, x, y, z].");
}

}  // namespace superdex::python
