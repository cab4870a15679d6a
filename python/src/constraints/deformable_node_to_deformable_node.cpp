// constraints/deformable_node_to_deformable_node.h: a spring between nodes of
// two deformable actors, g = T_A(X_A + u_A) - T_B(X_B + u_B) (m = 3, n = 6).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineDeformableNodeToDeformableNode(py::module_& m) {
  using P = DeformableNodeToDeformableNodeConstraintParams;
  ParamsClass<P>(m, "DeformableNodeToDeformableNodeConstraintParams",
                 "g = T_A(X_A + u_A) - T_B(X_B + u_B) (m = 3, n = 6).")
      .Field("actor_a", &P::actorA, "a deformable or rod actor")
      .Field("actor_b", &P::actorB, "another deformable or rod actor")
      .Field("node_index_a", &P::nodeIndexA, "node of A")
      .Field("node_index_b", &P::nodeIndexB, "node of B")
      .CompliantFields("[N/m]", "[N·s/m]", "[m]");

  using T = DeformableNodeToDeformableNodeConstraint;
  py::class_<ConstraintRefOf<T>, ConstraintRef>(m, "DeformableNodeToDeformableNodeConstraint",
                                                "Node-to-node spring between two nodal actors.");
}

}  // namespace superdex::python
