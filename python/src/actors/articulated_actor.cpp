// actors/articulated_actor.h: a tree of rigid links in reduced coordinates.
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineArticulatedActor(py::module_& m) {
  py::enum_<JointType>(m, "JointType", "Joint between a link and its parent.")
      .value("Fixed", JointType::Fixed, "0 DoFs")
      .value("Revolute", JointType::Revolute, "1 DoF: rotation about `axis`")
      .value("Prismatic", JointType::Prismatic, "1 DoF: translation along `axis`")
      .value("Spherical", JointType::Spherical, "3 DoFs: R_j <- R_j Exp(δ) (local increments)")
      .value("Free", JointType::Free,
             "6 DoFs: translation p, then rotation (a free root is a floating base)");
  m.def("joint_dofs", &JointDofs, py::arg("type"), "DoFs of a joint type: 0, 1, 1, 3, 6.");
  py::enum_<ArticulatedBlockSolve>(m, "ArticulatedBlockSolve", "How an articulated actor's Newton block is solved.")
      .value("Tree", ArticulatedBlockSolve::Tree,
             "O(N) recursion over the tree (dense in the scene's matrix across MPI ranks or where a "
             "constraint couples two joints)")
      .value("Dense", ArticulatedBlockSolve::Dense, "the dense block in the scene's matrix: O(N^2) assembly, O(N^3) factorization (default)");

  using L = ArticulatedLinkParams;
  ParamsClass<L>(m, "ArticulatedLinkParams",
                 "One link and the joint to its parent: T_i = T_parent · X_pj · J(q_i) · X_jc.")
      .Field("parent", &L::parent, "an earlier link, or -1 for the world (root only)")
      .Field("joint", &L::joint, "JointType, default Revolute")
      .Field("axis", &L::axis, "revolute/prismatic axis in the joint frame (normalized), default z")
      .Field("parent_to_joint_position", &L::parentToJointPosition,
             "X_pj translation, in the parent link frame (world for the root) [m]")
      .Field("parent_to_joint_rotation", &L::parentToJointRotation, "X_pj rotation [w, x, y, z]")
      .Field("joint_to_child_position", &L::jointToChildPosition,
             "X_jc translation, in the joint's child-side frame [m]")
      .Field("joint_to_child_rotation", &L::jointToChildRotation, "X_jc rotation [w, x, y, z]")
      .Field("mass", &L::mass, "[kg], > 0")
      .Field("inertia", &L::inertia,
             "principal moments about the centre of mass, link axes [kg·m²], > 0")
      .Field("center_of_mass", &L::centerOfMass, "in the link frame [m]")
      .Field("armature", &L::armature, "added joint-space inertia per DoF, >= 0")
      .Field("damping", &L::damping, "joint damping per DoF, >= 0")
      .Field("initial_position", &L::initialPosition,
             "joint_dofs(joint) entries or empty (rest): revolute angle / prismatic offset; "
             "spherical rotation vector; free: p then rotation vector")
      .Field("initial_velocity", &L::initialVelocity,
             "joint_dofs(joint) entries (increment coordinates) or empty");

  using P = ArticulatedActorParams;
  ParamsClass<P>(
      m, "ArticulatedActorParams",
      "A tree of links (Scene.create_articulated_actor); link 0 is the root. `links` reads as a "
      "list of copies: assign a whole list.")
      .Field("links", &P::links, "list of ArticulatedLinkParams, at least one")
      .Field("block_solve", &P::blockSolve, "ArticulatedBlockSolve, default Tree")
      .Field("extrapolate_first_iterate", &P::extrapolateFirstIterate,
             "Newton's first iterate at the last step's acceleration (default True) or the "
             "constant-velocity prediction (False); the same converged state");

  using Ref = ArticulatedActorRef;
  using A = ArticulatedActor;
  auto const links = &A::GetNumLinks;
  py::class_<Ref, ActorRef>(m, "ArticulatedActor",
                            "Rigid links in reduced coordinates; the DoFs are the joints' in "
                            "link order. Link indices are checked: out of range raises "
                            "mochi.Error(InvalidArgument).")
      .def("get_num_links", Forward<Ref>(&A::GetNumLinks))
      .def("get_block_solve", Forward<Ref>(&A::GetBlockSolve))
      .def("is_solved_on_tree", Forward<Ref>(&A::IsSolvedOnTree),
           "True while the stage solver solves the actor by the tree recursion (after a step).")
      .def("get_num_coupled_constraints", Forward<Ref>(&A::GetNumCoupledConstraints),
           "Constraints between a link and another body coupled to the scene's matrix by the tree's Schur "
           "complement (as of the last pattern build).")
      .def("get_num_coupled_dofs", Forward<Ref>(&A::GetNumCoupledDofs),
           "The other bodies' DoFs those couplings reach (their dense block in the scene's matrix).")
      .def("get_num_modified_tree_factorizations", Forward<Ref>(&A::GetNumModifiedTreeFactorizations),
           "Tree factorizations made positive definite (indefinite exact Hessian) since creation.")
      .def("get_num_gauss_newton_tree_factorizations", Forward<Ref>(&A::GetNumGaussNewtonTreeFactorizations),
           "Tree factorizations that fell back to the Gauss-Newton Hessian (the modified one failed) since "
           "creation.")
      .def("get_joint_type", ForwardIndexed<Ref>(&A::GetJointType, links, "link"), py::arg("link"))
      .def("get_parent", ForwardIndexed<Ref>(&A::GetParent, links, "link"), py::arg("link"),
           "The parent link, -1 for the world.")
      .def("get_joint_dof_offset", ForwardIndexed<Ref>(&A::GetJointDofOffset, links, "link"),
           py::arg("link"), "First local DoF of the link's joint.")
      .def("get_joint_num_dofs", ForwardIndexed<Ref>(&A::GetJointNumDofs, links, "link"),
           py::arg("link"))
      .def("is_floating_base", Forward<Ref>(&A::IsFloatingBase),
           "True when the root joint is Free.")
      .def("get_link_position", ForwardIndexed<Ref>(&A::GetLinkPosition, links, "link"),
           py::arg("link"), "Link frame origin, world [m].")
      .def("get_link_rotation", ForwardIndexed<Ref>(&A::GetLinkRotation, links, "link"),
           py::arg("link"), "Link frame rotation, world [w, x, y, z].")
      .def("get_link_center_of_mass", ForwardIndexed<Ref>(&A::GetLinkCenterOfMass, links, "link"),
           py::arg("link"), "Centre of mass, world [m].")
      .def("get_link_linear_velocity",
           ForwardIndexed<Ref>(&A::GetLinkLinearVelocity, links, "link"), py::arg("link"),
           "Velocity of the centre of mass, world [m/s].")
      .def("get_link_angular_velocity",
           ForwardIndexed<Ref>(&A::GetLinkAngularVelocity, links, "link"), py::arg("link"),
           "Angular velocity, world [rad/s].")
      .def("get_link_mass", ForwardIndexed<Ref>(&A::GetLinkMass, links, "link"), py::arg("link"),
           "[kg]")
      .def(
          "get_link_positions",
          [](Ref const& self) {
            A const& a = self.Get();
            DynamicArray<Real3> x(static_cast<std::size_t>(a.GetNumLinks()));
            for (int i = 0; i < a.GetNumLinks(); ++i) x[i] = a.GetLinkPosition(i);
            return ToArray(x);
          },
          "Link frame origins, world, an (links, 3) array.")
      .def(
          "get_joint_positions",
          [](Ref const& self) { return ToArray(Span<real const>(self.Get().GetJointPositions())); },
          "Joint positions in DoF order (revolute angle, prismatic offset, spherical Log(R_j), "
          "free p then Log(R_j)), an (n,) array.")
      .def(
          "get_joint_velocities",
          [](Ref const& self) {
            return ToArray(Span<real const>(self.Get().GetJointVelocities()));
          },
          "Joint velocities in the increment coordinates, an (n,) array.")
      .def("get_joint_rotation", ForwardIndexed<Ref>(&A::GetJointRotation, links, "link"),
           py::arg("link"),
           "R_j [w, x, y, z] of a spherical or free joint (identity = rest); identity otherwise.")
      .def(
          "get_joint_coordinate",
          [](Ref const& self, int link, int dof) {
            A const& a = self.Get();
            CheckIndex(link, a.GetNumLinks(), "link");
            JointType const type = a.GetJointType(link);
            if (type == JointType::Free) {
              CheckIndex(dof, 3, "dof of a Free joint's translation");
            } else if (type == JointType::Revolute || type == JointType::Prismatic) {
              CheckIndex(dof, 1, "dof of a " + std::string(ToString(type)) + " joint");
            } else {
              Raise(ErrorCode::NotSupported,
                    "get_joint_coordinate does not apply to the " + std::string(ToString(type)) +
                        " joint of link " + std::to_string(link) + " (use get_joint_rotation)");
            }
            return a.GetJointCoordinate(link, dof);
          },
          py::arg("link"), py::arg("dof") = 0,
          "The revolute angle or prismatic offset (dof 0), or a free joint's translation p[dof] "
          "(dof 0..2).")
      .def("get_kinetic_energy", Forward<Ref>(&A::GetKineticEnergy), "[J]")
      .def("get_linear_momentum", Forward<Ref>(&A::GetLinearMomentum), "[kg·m/s]")
      .def("get_angular_momentum", Forward<Ref>(&A::GetAngularMomentum), "About the world origin.")
      .def("compute_mass_matrix", Forward<Ref>(&A::ComputeMassMatrix),
           "The joint-space mass matrix M(q) (CRBA), an (n, n) array, armature included.")
      .def("compute_bias_forces", Forward<Ref>(&A::ComputeBiasForces), py::arg("gravity"),
           "C(q, q̇) q̇ - τ_g(q) for `gravity` (RNEA with q̈ = 0): M q̈ + bias = τ.");
}

}  // namespace superdex::python
