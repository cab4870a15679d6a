// actors/tet_element.h and actors/shell_element.h: the hyperelastic models of
// tetrahedra and the membrane models of shell triangles.
#include "defines.h"

namespace superdex::python {

void DefineTetElement(py::module_& m) {
  py::enum_<TetMaterialModel>(m, "TetMaterialModel", "Hyperelastic model of volumetric elements.")
      .value(
          "StableNeoHookean", TetMaterialModel::StableNeoHookean,
          "Smith, de Goes, Kim 2018; matches linear elasticity at rest, defined through inversion")
      .value("LinearElastic", TetMaterialModel::LinearElastic,
             "small strain; cheapest, constant Hessian, not rotation invariant");
  py::enum_<MembraneModel>(m, "MembraneModel", "Membrane model of shell triangles (docs/deformables.md).")
      .value("StVK", MembraneModel::StVK,
             "Saint Venant-Kirchhoff, plane stress: resists compression; non-convex where compressed")
      .value("TensionField", MembraneModel::TensionField,
             "StVK relaxed by tension-field theory: no compressive stress (cloth wrinkles); convex");
}

}  // namespace superdex::python
