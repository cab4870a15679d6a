// actors/nodal_actor.h: the common face of deformable actors and rods.
#include "defines.h"
#include "support/arrays.h"
#include "support/objects.h"

namespace superdex::python {

namespace {

/// fn(actor, i) for every node, as an (n, 3) array.
template <class F>
py::array_t<real> PerNode(NodalActor const& actor, F fn) {
  DynamicArray<Real3> values(static_cast<std::size_t>(actor.GetNumNodes()));
  for (int i = 0; i < actor.GetNumNodes(); ++i) values[i] = fn(actor, i);
  return ToArray(values);
}

}  // namespace

void DefineNodalActor(py::module_& m) {
  using Ref = NodalActorRef;
  using A = NodalActor;
  py::class_<Ref, ActorRef>(
      m, "NodalActor",
      "Actors made of nodes with a world position: DeformableActor (3 DoFs per node) and "
      "RodActor (4: displacement, then twist). Node i's position T(X + u) is linear in its 3 "
      "displacement DoFs. Every node index is checked: out of range raises "
      "mochi.Error(InvalidArgument).")
      .def("get_num_nodes", Forward<Ref>(&A::GetNumNodes))
      .def("get_node_position",
           ForwardIndexed<Ref>(&A::GetNodePosition, &A::GetNumNodes, "node index"), py::arg("i"),
           "World position T(X + u) of node i [m].")
      .def("get_node_velocity",
           ForwardIndexed<Ref>(&A::GetNodeVelocity, &A::GetNumNodes, "node index"), py::arg("i"),
           "World-frame velocity of node i [m/s].")
      .def("get_node_mass", ForwardIndexed<Ref>(&A::GetNodeMass, &A::GetNumNodes, "node index"),
           py::arg("i"), "Lumped mass of node i [kg].")
      .def(
          "get_node_positions",
          [](Ref const& self) {
            return PerNode(self.Get(), [](A const& a, int i) { return a.GetNodePosition(i); });
          },
          "World positions of all nodes, an (n, 3) array (one bulk copy).")
      .def(
          "get_node_velocities",
          [](Ref const& self) {
            return PerNode(self.Get(), [](A const& a, int i) { return a.GetNodeVelocity(i); });
          },
          "World-frame velocities of all nodes, an (n, 3) array.")
      .def(
          "get_node_masses",
          [](Ref const& self) {
            A const& a = self.Get();
            DynamicArray<real> masses(static_cast<std::size_t>(a.GetNumNodes()));
            for (int i = 0; i < a.GetNumNodes(); ++i) masses[i] = a.GetNodeMass(i);
            return ToArray(Span<real const>(masses));
          },
          "Lumped masses of all nodes [kg], an (n,) array.")
      .def("get_transform_rotation", Forward<Ref>(&A::GetTransformRotation),
           "Rotation [w, x, y, z] of the actor transform T (identity for rods).")
      .def("get_node_dof_stride", Forward<Ref>(&A::GetNodeDofStride),
           "DoFs per node (3 for solids and shells, 4 for rods).")
      .def(
          "get_node_position_dofs",
          [](Ref const& self, int i) {
            A const& a = self.Get();
            CheckIndex(i, a.GetNumNodes(), "node index");
            DynamicArray<int> const dofs = a.GetNodePositionDofs(i);
            return ToArray(Span<int const>(dofs));
          },
          py::arg("i"), "Local DoFs of node i's displacement: stride·i + [0, 1, 2].");
}

}  // namespace superdex::python
