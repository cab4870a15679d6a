// constraints/deformable_node_position.h: a node pinned to a target,
// g = T(X + u) - p̂ (m = 3, n = 3).
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineDeformableNodePosition(py::module_&) {
  using T = DeformableNodePositionConstraint;
  using Ref = ConstraintRefOf<T>;
  ConstraintClass<T>()
      .def("get_node_index", Forward<Ref>(&T::GetNodeIndex));
}

}  // namespace superdex::python
