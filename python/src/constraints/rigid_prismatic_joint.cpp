// constraints/rigid_prismatic_joint.h: relative translation of two rigid bodies
// restricted to a sliding axis, optional travel limits (m = 3, n = 9).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRigidPrismaticJoint(py::module_& m) {
  using P = RigidPrismaticJointConstraintParams;
  ParamsClass<P>(
      m, "RigidPrismaticJointConstraintParams",
      "Slider: s = R₀⁻¹ R_A⁻¹ (t_B - t_A) - s_ref; g₁ = s₁, g₂ = s₂, g₃ the signed violation of "
      "s₃ against the travel limits (m = 3, n = 9). Does not restrict relative rotation (add a "
      "JointRotationTracking); its limits are not reported by get_limit_min/max_values.")
      .Field("actor_a", &P::actorA, "a rigid actor")
      .Field("actor_b", &P::actorB, "a different rigid actor")
      .Field("link_a", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)")
      .Field("link_b", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)")
      .Field("joint_frame", &P::jointFrame,
             "joint frame, world, at creation [w, x, y, z]; z = sliding axis")
      .Field("offset_around_rest", &P::offsetAroundRest,
             "s_ref = the creation-time offset (default True)")
      .Field("reference_offset", &P::referenceOffset,
             "s_ref when not offset_around_rest [m], joint frame")
      .Field("lower_limit", &P::lowerLimit, "l on s₃ [m], default -inf")
      .Field("upper_limit", &P::upperLimit, "u on s₃ [m], >= l, default +inf")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = RigidPrismaticJointConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "RigidPrismaticJointConstraint",
                                 "Slider joint with optional travel limits.")
      .def("get_offset", Forward<Ref>(&T::GetOffset),
           "s (before the limit rule), the offset of B from A in the joint frame [m].")
      .def("get_lower_limit", Forward<Ref>(&T::GetLowerLimit), "l [m]")
      .def("get_upper_limit", Forward<Ref>(&T::GetUpperLimit), "u [m]");
}

}  // namespace superdex::python
