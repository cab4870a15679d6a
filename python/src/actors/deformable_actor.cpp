// actors/deformable_actor.h: DeformableActorParams and DeformableActor
// (tetrahedral solids and triangle shells).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineDeformableActor(py::module_& m) {
  using P = DeformableActorParams;
  ParamsClass<P>(
      m, "DeformableActorParams",
      "A deformable actor (Scene.create_deformable_actor): tetrahedra, triangles or both. Mesh "
      "arrays read as copies: assign whole arrays (e.g. from make_tet_box).")
      .Field("nodes", &P::nodes, "reference positions X, actor frame [m], an (n, 3) array")
      .Field("tetrahedra", &P::tetrahedra,
             "volumetric elements (positive volume), an (m, 4) int array")
      .Field("triangles", &P::triangles, "shell elements, an (m, 3) int array")
      .Field("position", &P::position, "actor transform T: translation [m]")
      .Field("rotation", &P::rotation, "actor transform T: rotation [w, x, y, z]")
      .Field("density", &P::density, "ρ [kg/m³], > 0, default 1000")
      .Field("young_modulus", &P::youngModulus, "E [Pa], > 0, default 1e5")
      .Field("poisson_ratio", &P::poissonRatio, "ν in (-1, 0.5), default 0.3")
      .Field("material", &P::material, "TetMaterialModel, default StableNeoHookean")
      .Field("thickness", &P::thickness, "shell thickness h [m], > 0 with triangles, default 1e-3")
      .Field("membrane", &P::membrane, "MembraneModel of the triangles, default StVK (TensionField for cloth)")
      .Field("shell_bending", &P::shellBending,
             "bending on interior edges of the triangles, default True")
      .Field("initial_displacements", &P::initialDisplacements,
             "optional initial displacements u (actor frame), (n, 3) or empty")
      .Field("initial_velocities", &P::initialVelocities,
             "optional initial velocities (world frame), (n, 3) or empty");

  using Ref = DeformableActorRef;
  using A = DeformableActor;
  py::class_<Ref, NodalActorRef>(m, "DeformableActor",
                                 "A mesh of nodes with 3 displacement DoFs each; node i's world "
                                 "position is T(X + u). Elements: linear tetrahedra, shell "
                                 "membranes (StVK or tension field) and bending hinges.")
      .def("get_num_tetrahedra", Forward<Ref>(&A::GetNumTetrahedra))
      .def("get_num_triangles", Forward<Ref>(&A::GetNumTriangles))
      .def("get_num_hinges", Forward<Ref>(&A::GetNumHinges),
           "Bending hinges (interior shell edges).")
      .def(
          "get_tetrahedra", [](Ref const& self) { return ToArray(self.Get().GetTetrahedra()); },
          "Node indices of the tetrahedra, an (m, 4) int array.")
      .def(
          "get_triangles", [](Ref const& self) { return ToArray(self.Get().GetTriangles()); },
          "Node indices of the triangles, an (m, 3) int array.")
      .def("get_node_reference_position",
           ForwardIndexed<Ref>(&A::GetNodeReferencePosition, &A::GetNumNodes, "node index"),
           py::arg("i"), "X of node i (actor frame) [m].")
      .def(
          "get_node_reference_positions",
          [](Ref const& self) {
            A const& a = self.Get();
            DynamicArray<Real3> x(static_cast<std::size_t>(a.GetNumNodes()));
            for (int i = 0; i < a.GetNumNodes(); ++i) x[i] = a.GetNodeReferencePosition(i);
            return ToArray(x);
          },
          "X of all nodes (actor frame), an (n, 3) array.")
      .def("get_node_displacement",
           ForwardIndexed<Ref>(&A::GetNodeDisplacement, &A::GetNumNodes, "node index"),
           py::arg("i"), "u of node i (actor frame) [m].")
      .def(
          "get_node_displacements",
          [](Ref const& self) {
            A const& a = self.Get();
            DynamicArray<Real3> u(static_cast<std::size_t>(a.GetNumNodes()));
            for (int i = 0; i < a.GetNumNodes(); ++i) u[i] = a.GetNodeDisplacement(i);
            return ToArray(u);
          },
          "u of all nodes (actor frame), an (n, 3) array.")
      .def(
          "get_node_positions",
          [](Ref const& self) { return ToArray(self.Get().GetNodePositions()); },
          "World positions of all nodes, an (n, 3) array (one bulk copy).")
      .def("get_total_mass", Forward<Ref>(&A::GetTotalMass), "[kg]")
      .def("get_transform_position", Forward<Ref>(&A::GetTransformPosition),
           "Translation of T [m].")
      .def("get_kinetic_energy", Forward<Ref>(&A::GetKineticEnergy), "[J]")
      .def("get_elastic_energy", Forward<Ref>(&A::GetElasticEnergy),
           "Elastic energy of every element at the current configuration [J].")
      .def("count_inverted_tetrahedra", Forward<Ref>(&A::CountInvertedTetrahedra),
           "Tetrahedra with det F <= 0 now.");
}

}  // namespace superdex::python
