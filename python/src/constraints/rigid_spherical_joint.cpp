// constraints/rigid_spherical_joint.h: ball-and-socket between two rigid bodies,
// g = T_A(r_A) - T_B(r_B)   (m = 3, n = 12).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRigidSphericalJoint(py::module_& m) {
  using P = RigidSphericalJointConstraintParams;
  ParamsClass<P>(
      m, "RigidSphericalJointConstraintParams",
      "Ball-and-socket between two rigid bodies: g = T_A(r_A) - T_B(r_B) (m = 3, n = 12).")
      .Field("actor_a", &P::actorA, "a rigid actor (RigidActor or ActorHandle)")
      .Field("actor_b", &P::actorB, "a different rigid actor")
      .Field("link_a", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)")
      .Field("link_b", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)")
      .Field("local_pos_a", &P::localPosA, "pivot r_A in A's body frame [m]")
      .Field("local_pos_b", &P::localPosB, "pivot r_B in B's body frame [m]")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = RigidSphericalJointConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "RigidSphericalJointConstraint",
                                 "Ball-and-socket joint: g = T_A(r_A) - T_B(r_B).")
      .def("get_local_pos_a", Forward<Ref>(&T::GetLocalPosA), "r_A, body frame of A [m].")
      .def("get_local_pos_b", Forward<Ref>(&T::GetLocalPosB), "r_B, body frame of B [m].");
}

}  // namespace superdex::python
