// constraints/deformable_node_position.h: a node pinned to a target,
// g = T(X + u) - p̂ (m = 3, n = 3).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineDeformableNodePosition(py::module_& m) {
  using P = DeformableNodePositionConstraintParams;
  ParamsClass<P>(m, "DeformableNodePositionConstraintParams",
                 "Pins a node of a deformable or rod actor: g = T(X + u) - p̂ (m = 3, n = 3).")
      .Field("actor", &P::actor, "a deformable or rod actor")
      .Field("node_index", &P::nodeIndex, "in [0, number of nodes)")
      .Field("position", &P::position, "target p̂, world [m]")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = DeformableNodePositionConstraint;
  using Ref = ConstraintRefOf<T>;
  py::class_<Ref, ConstraintRef>(m, "DeformableNodePositionConstraint", "Node-to-target pin.")
      .def("get_node_index", Forward<Ref>(&T::GetNodeIndex));
}

}  // namespace superdex::python
