// actors/rod_actor.h: RodActorParams and RodActor (discrete elastic rods).
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRodActor(py::module_& m) {
  using P = RodActorParams;
  ParamsClass<P>(m, "RodActorParams",
                 "A discrete elastic rod on a polyline (Scene.create_rod_actor). Section: "
                 "circular of `radius` unless section_area > 0 (then all four explicit section "
                 "fields > 0).")
      .Field("nodes", &P::nodes,
             "rest positions, world [m], an (n, 3) array, n >= 2, no zero-length element")
      .Field("radius", &P::radius, "circular section radius [m], default 0.01")
      .Field("section_area", &P::sectionArea,
             "explicit section: area A [m²] (> 0 enables the explicit section)")
      .Field("second_moment_of_area_1", &P::secondMomentOfArea1, "I₁ about d₁ [m⁴]")
      .Field("second_moment_of_area_2", &P::secondMomentOfArea2, "I₂ about d₂ [m⁴]")
      .Field("torsion_constant", &P::torsionConstant, "J [m⁴]")
      .Field("young_modulus", &P::youngModulus, "E [Pa], > 0, default 1e9")
      .Field("shear_modulus", &P::shearModulus, "G [Pa]; <= 0 (default) means E / (2(1 + ν))")
      .Field("poisson_ratio", &P::poissonRatio, "ν in (-1, 0.5], used when shear_modulus <= 0")
      .Field("density", &P::density, "ρ [kg/m³], > 0, default 1000")
      .Field("material_director", &P::materialDirector,
             "rest director d₁ of element 0 (world; zero chooses one); the others follow by "
             "parallel transport")
      .Field("material_directors", &P::materialDirectors,
             "optional rest director per element, (n - 1, 3); overrides material_director "
             "(natural twist)")
      .Field("initial_velocities", &P::initialVelocities,
             "optional node velocities (world), (n, 3) or empty");

  using Ref = RodActorRef;
  using A = RodActor;
  py::class_<Ref, NodalActorRef>(m, "RodActor",
                                 "A discrete elastic rod: nodes 0..n-1, elements e = (e, e+1); "
                                 "4 DoFs per node (displacement, then the twist of the element "
                                 "starting at it; the last node's twist is inert). Indices are "
                                 "checked.")
      .def("get_num_elements", Forward<Ref>(&A::GetNumElements))
      .def("get_node_reference_position",
           ForwardIndexed<Ref>(&A::GetNodeReferencePosition, &A::GetNumNodes, "node index"),
           py::arg("i"), "Rest position of node i, world [m].")
      .def(
          "get_node_positions",
          [](Ref const& self) { return ToArray(self.Get().GetNodePositions()); },
          "World positions of all nodes, an (n, 3) array.")
      .def("get_twist", ForwardIndexed<Ref>(&A::GetTwist, &A::GetNumNodes, "node index"),
           py::arg("i"),
           "θ of element i (node i's 4th DoF) [rad], relative to its reference frame.")
      .def(
          "get_twists",
          [](Ref const& self) {
            A const& a = self.Get();
            DynamicArray<real> twist(static_cast<std::size_t>(a.GetNumNodes()));
            for (int i = 0; i < a.GetNumNodes(); ++i) twist[i] = a.GetTwist(i);
            return ToArray(Span<real const>(twist));
          },
          "θ of every node (the last one inert), an (n,) array [rad].")
      .def("get_twist_velocity",
           ForwardIndexed<Ref>(&A::GetTwistVelocity, &A::GetNumNodes, "node index"), py::arg("i"),
           "[rad/s]")
      .def("get_twist_inertia",
           ForwardIndexed<Ref>(&A::GetTwistInertia, &A::GetNumNodes, "node index"), py::arg("i"),
           "[kg·m²]")
      .def("get_total_mass", Forward<Ref>(&A::GetTotalMass), "[kg]")
      .def("get_rest_length",
           ForwardIndexed<Ref>(&A::GetRestLength, &A::GetNumElements, "element index"),
           py::arg("e"), "Rest length of element e [m].")
      .def("get_material_frame",
           ForwardIndexed<Ref>(&A::GetMaterialFrame, &A::GetNumElements, "element index"),
           py::arg("e"), "Material frame [d₁ d₂ t] of element e, a 3x3 array (columns).")
      .def("get_material_frame_jacobian",
           ForwardIndexed<Ref>(&A::GetMaterialFrameJacobian, &A::GetNumElements, "element index"),
           py::arg("e"),
           "World angular increment of element e's material frame per increment of its nodes' 8 "
           "DoFs (3x8).")
      .def(
          "get_strain",
          [](Ref const& self, int i) {
            A const& a = self.Get();
            CheckIndexRange(i, 1, a.GetNumNodes() - 1, "interior node index");
            return Real3(a.GetStrain(i));
          },
          py::arg("i"), "(κ₁, κ₂, m) at interior node i, 1 <= i <= n - 2.")
      .def(
          "get_rest_strain",
          [](Ref const& self, int i) {
            A const& a = self.Get();
            CheckIndexRange(i, 1, a.GetNumNodes() - 1, "interior node index");
            return Real3(a.GetRestStrain(i));
          },
          py::arg("i"), "Rest (κ̄₁, κ̄₂, m̄) at interior node i, 1 <= i <= n - 2.")
      .def("get_stiffness", Forward<Ref>(&A::GetStiffness), "Section stiffnesses (RodStiffness).")
      .def("get_kinetic_energy", Forward<Ref>(&A::GetKineticEnergy), "[J]")
      .def("get_elastic_energy", Forward<Ref>(&A::GetElasticEnergy),
           "Stretching + bending + twisting energy [J].");
}

}  // namespace superdex::python
