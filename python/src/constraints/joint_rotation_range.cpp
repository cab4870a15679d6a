// constraints/joint_rotation_range.h: componentwise bounds on the relative
// rotation of two rigid bodies (range type, m = 3, n = 6).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineJointRotationRange(py::module_& m) {
  using P = JointRotationRangeConstraintParams;
  ParamsClass<P>(m, "JointRotationRangeConstraintParams",
                 "Bounds per component of r_AB = Log(R₀⁻¹ R_A⁻¹ R_B R₀ R_ref⁻¹); g_j the one-sided "
                 "violation (range type, m = 3, n = 6).")
      .Field("actor_a", &P::actorA, "a rigid actor")
      .Field("actor_b", &P::actorB, "a different rigid actor")
      .Field("link_a", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)")
      .Field("link_b", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)")
      .Field("joint_frame", &P::jointFrame, "joint frame R₀, world, at creation [w, x, y, z]")
      .Field("lower_limits", &P::lowerLimits,
             "l_j [rad], -inf for no bound; each <= the upper limit")
      .Field("upper_limits", &P::upperLimits, "u_j [rad], +inf for no bound")
      .Field("range_around_rest", &P::rangeAroundRest,
             "R_ref = the creation-time relative rotation (default True)")
      .Field("reference_rotation", &P::referenceRotation, "R_ref when not range_around_rest")
      .CompliantFields("[N·m/rad]", "[N·m·s/rad]", "[rad]");

  using T = JointRotationRangeConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "JointRotationRangeConstraint", "Range of relative rotation.")
      .def("get_relative_rotation", Forward<Ref>(&T::GetRelativeRotation),
           "r_AB, the measured relative rotation vector [rad].");
}

}  // namespace superdex::python
