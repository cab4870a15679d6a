// actors/tet_element.h: the hyperelastic models of tetrahedra.
#include "defines.h"

namespace superdex::python {

void DefineTetElement(py::module_& m) {
  py::enum_<TetMaterialModel>(m, "TetMaterialModel", "Hyperelastic model of volumetric elements.")
      .value(
          "StableNeoHookean", TetMaterialModel::StableNeoHookean,
          "Smith, de Goes, Kim 2018; matches linear elasticity at rest, defined through inversion")
      .value("LinearElastic", TetMaterialModel::LinearElastic,
             "small strain; cheapest, constant Hessian, not rotation invariant");
}

}  // namespace superdex::python
