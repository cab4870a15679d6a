// constraints/articulated_joint_constraints.h: the four types on an articulated
// actor's reduced pose (one joint each; no world frames).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineArticulatedJointConstraints(py::module_& m) {
  using TP = ArticulatedSingleDofTargetConstraintParams;
  ParamsClass<TP>(
      m, "ArticulatedSingleDofTargetConstraintParams",
      "g = θ - θ̂ (m = 1, n = 1): θ a revolute angle, a prismatic offset or a free joint's "
      "translation component. Spherical joints and free-joint rotations: use the 3D types.")
      .Field("actor", &TP::actor, "an articulated actor")
      .Field("joint_index", &TP::jointIndex, "the joint of link joint_index")
      .Field("dof_index", &TP::dofIndex, "0, or 0..2 for a free joint's translation")
      .Field("target", &TP::target, "θ̂ [rad or m]")
      .CompliantFields("[N·m/rad or N/m]", "[N·m·s/rad or N·s/m]", "[rad or m]");

  using RP = ArticulatedSingleDofRangeConstraintParams;
  ParamsClass<RP>(m, "ArticulatedSingleDofRangeConstraintParams",
                  "g = max(θ - u, l - θ, 0) (m = 1, n = 1): mechanical joint limits.")
      .Field("actor", &RP::actor, "an articulated actor")
      .Field("joint_index", &RP::jointIndex, "the joint of link joint_index")
      .Field("dof_index", &RP::dofIndex, "0, or 0..2 for a free joint's translation")
      .Field("lower_limit", &RP::lowerLimit, "l, <= upper_limit, default -inf")
      .Field("upper_limit", &RP::upperLimit, "u, default +inf")
      .CompliantFields("[N·m/rad or N/m]", "[N·m·s/rad or N·s/m]", "[rad or m]");

  using T3 = Articulated3dRotationTargetConstraintParams;
  ParamsClass<T3>(
      m, "Articulated3dRotationTargetConstraintParams",
      "g = Log(R_j R̂⁻¹) (m = 3, n = 3) on a spherical or free joint; the target is in the "
      "joint's frame relative to its rest orientation (identity = rest).")
      .Field("actor", &T3::actor, "an articulated actor")
      .Field("joint_index", &T3::jointIndex, "a spherical or free joint")
      .Field("target_from_current", &T3::targetFromCurrent,
             "R̂ = the creation-time R_j (default True)")
      .Field("rotation", &T3::rotation, "R̂ when not target_from_current [w, x, y, z]")
      .CompliantFields("[N·m/rad]", "[N·m·s/rad]", "[rad]");

  using R3 = Articulated3dRotationRangeConstraintParams;
  ParamsClass<R3>(
      m, "Articulated3dRotationRangeConstraintParams",
      "Independent bounds on each component of Log(R_j) (m = 3, n = 3), one-sided violation.")
      .Field("actor", &R3::actor, "an articulated actor")
      .Field("joint_index", &R3::jointIndex, "a spherical or free joint")
      .Field("lower_limits", &R3::lowerLimits, "on Log(R_j) [rad], -inf for no bound")
      .Field("upper_limits", &R3::upperLimits, "[rad], +inf for no bound")
      .CompliantFields("[N·m/rad]", "[N·m·s/rad]", "[rad]");

  using Single = ArticulatedSingleDofConstraint;
  py::class_<ConstraintRefOf<Single>, ConstraintRef>(
      m, "ArticulatedSingleDofConstraint",
      "ArticulatedSingleDofTarget and ArticulatedSingleDofRange.")
      .def("get_coordinate", Forward<ConstraintRefOf<Single>>(&Single::GetCoordinate),
           "θ now [rad or m].");
  using Rotation = Articulated3dRotationConstraint;
  py::class_<ConstraintRefOf<Rotation>, ConstraintRef>(
      m, "Articulated3dRotationConstraint",
      "Articulated3dRotationTarget and Articulated3dRotationRange.")
      .def("get_joint_rotation_vector",
           Forward<ConstraintRefOf<Rotation>>(&Rotation::GetJointRotationVector),
           "φ = Log(R_j) now [rad].");
}

}  // namespace superdex::python
