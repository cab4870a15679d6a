// core/so3.h: the SO(3) maps (conventions of Sola et al. 2018; world-frame
// increments R <- Exp(δθ) R). Quaternions are numpy arrays [w, x, y, z].
#include "defines.h"

namespace superdex::python {

void DefineSo3(py::module_& m) {
  m.def("hat", &Hat, py::arg("a"), "The skew-symmetric cross-product matrix: hat(a) @ b = a × b.")
      .def("exp", &Exp, py::arg("phi"),
           "Unit quaternion [w, x, y, z] of the rotation vector phi (rotation by |phi| about "
           "phi/|phi|). E.g. exp([0, 0, 0.5]) turns 0.5 rad about z.")
      .def("exp_matrix", &ExpMatrix, py::arg("phi"), "Rotation matrix of the rotation vector phi.")
      .def("log", py::overload_cast<Quat const&>(&Log), py::arg("q"),
           "Rotation vector of a unit quaternion [w, x, y, z] (either sign), |result| in [0, pi].")
      .def("log", py::overload_cast<Real33 const&>(&Log), py::arg("rotation"),
           "Rotation vector of a 3x3 rotation matrix, |result| in [0, pi].")
      .def("left_jacobian", &LeftJacobian, py::arg("phi"),
           "J_l(phi): Exp(phi + δ) ≈ Exp(J_l(phi) δ) Exp(phi).")
      .def("left_jacobian_inverse", &LeftJacobianInverse, py::arg("phi"), "J_l(phi)^-1.")
      .def("right_jacobian", &RightJacobian, py::arg("phi"),
           "J_r(phi): Exp(phi + δ) ≈ Exp(phi) Exp(J_r(phi) δ).")
      .def("right_jacobian_inverse", &RightJacobianInverse, py::arg("phi"), "J_r(phi)^-1.");
}

}  // namespace superdex::python
