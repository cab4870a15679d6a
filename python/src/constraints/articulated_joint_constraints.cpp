// constraints/articulated_joint_constraints.h: the four types on an articulated
// actor's reduced pose (one joint each; no world frames).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineArticulatedJointConstraints(py::module_&) {
  using Single = ArticulatedSingleDofConstraint;
  ConstraintClass<Single>()
      .def("get_coordinate", Forward<ConstraintRefOf<Single>>(&Single::GetCoordinate),
           "θ now [rad or m].");
  using Rotation = Articulated3dRotationConstraint;
  ConstraintClass<Rotation>()
      .def("get_joint_rotation_vector",
           Forward<ConstraintRefOf<Rotation>>(&Rotation::GetJointRotationVector),
           "φ = Log(R_j) now [rad].");
}

}  // namespace superdex::python
