// constraints/constraint.h: ConstraintType, QueryType and the uniform runtime
// interface of constraints.md, bound once on mochi.Constraint; the per-type
// classes (rigid_spherical_joint.cpp, ...) derive from it and add their own
// accessors. Methods that do not apply to a type raise mochi.Error(NotSupported).
#include "defines.h"
#include "support/arrays.h"
#include "support/objects.h"

namespace superdex::python {

void DefineConstraint(py::module_& m) {
  py::enum_<ConstraintType> types(m, "ConstraintType",
                                  "The constraint types (constraints/constraint_types.h, one line each).");
#define SUPERDEX_BIND_TYPE_VALUE(Name, Class, file) types.value(#Name, ConstraintType::Name);
  SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_BIND_TYPE_VALUE)
#undef SUPERDEX_BIND_TYPE_VALUE

  py::enum_<QueryType>(m, "QueryType", "Queries a constraint can record during steps.")
      .value("ConstraintForce", QueryType::ConstraintForce,
             "the generalized constraint force -r_c at the end of the last step (get_force)");

  py::enum_<ConstraintHessian>(
      m, "ConstraintHessian",
      "How a constraint's block of the Newton Hessian is formed; the minimizer is the same "
      "whichever is chosen (docs/constraints.md, 'The constraint Hessian').")
      .value("SceneDefault", ConstraintHessian::SceneDefault,
             "per constraint: use the scene's NewtonParams.constraint_hessian")
      .value("GaussNewton", ConstraintHessian::GaussNewton,
             "the reference page's (κ + d/Δt) JᵀJ")
      .value("GeometricStiffness", ConstraintHessian::GeometricStiffness,
             "(κ + d/Δt) JᵀJ + Σ f_i ∂²g_i/∂q², exact while Newton tries exact Hessians, the "
             "curvature in its diagonal form in projected iterations (scene default)")
      .value("GeometricStiffnessDiagonal", ConstraintHessian::GeometricStiffnessDiagonal,
             "(κ + d/Δt) JᵀJ + diag(column norms of the curvature) (Andrews et al. 2017)");

  using Ref = ConstraintRef;
  using C = Constraint;
  py::class_<Ref> cls(
      m, "Constraint",
      "A compliant constraint: value g (m entries) and its Jacobian over n DoFs, with stiffness "
      "k, damping d and saturation ḡ (constraints.md). Made by the Scene.create_*_constraint "
      "factories; the object holds the scene and the constraint's stable handle, so once the "
      "constraint is destroyed (directly or with one of its actors) every method raises "
      "mochi.Error (InvalidHandle).");
  DefineIdentity<Ref>(cls);
  cls
      // ---- introspection ----
      .def("get_num_actors", Forward<Ref>(&C::GetNumActors), "Number of actors (1 or 2).")
      .def(
          "get_actor",
          [](Ref const& self, int i) -> py::object {
            Actor* actor = self.Get().GetActor(i);
            return actor ? WrapActor(self.GetScene(), *actor) : py::none();
          },
          py::arg("i"), "The i-th actor, or None when i is not in [0, get_num_actors()).")
      .def(
          "get_dof_indices_for_actor",
          [](Ref const& self, int i) { return ToArray(self.Get().GetDofIndicesForActor(i)); },
          py::arg("i"),
          "Global DoF indices this constraint touches on actor i (an int array, empty when i is "
          "out of range). Current indices: they change when earlier actors are destroyed.")
      .def("get_dimension", Forward<Ref>(&C::GetDimension), "m, the dimension of g.")
      .def("get_num_dofs", Forward<Ref>(&C::GetNumDofs), "n, the number of DoFs coupled.")
      .def("is_range", Forward<Ref>(&C::IsRange), "True for range (unilateral) types.")
      .def("has_curvature", Forward<Ref>(&C::HasCurvature),
           "True when g is nonlinear in the DoF increments (geometric stiffness can be non-zero).")
      // ---- parameters ----
      .def("get_stiffness", Forward<Ref>(&C::GetStiffness), "k [N/m or N·m/rad].")
      .def("get_damping", Forward<Ref>(&C::GetDamping), "d [N·s/m or N·m·s/rad].")
      .def("get_saturation", Forward<Ref>(&C::GetSaturation), "ḡ; <= 0 means disabled.")
      .def("get_effective_stiffness", Forward<Ref>(&C::GetEffectiveStiffness),
           "k as the last stage used it: k, or its near-rigid cap (NewtonParams.near_rigid_beta); "
           "reset to k by the setters.")
      .def("get_effective_damping", Forward<Ref>(&C::GetEffectiveDamping),
           "d as the last stage used it: d, or its near-rigid cap; reset to d by the setters.")
      .def("is_near_rigid_capped", Forward<Ref>(&C::IsNearRigidCapped),
           "True when the near-rigid cap lowered k and d in the last stage.")
      .def(
          "set_stiffness",
          [](Ref const& self, real k) {
            Checked([&](Error& e) { self.Get().SetStiffness(k, e); });
          },
          py::arg("stiffness"), "k [N/m or N·m/rad]: finite and >= 0.")
      .def(
          "set_damping",
          [](Ref const& self, real d) { Checked([&](Error& e) { self.Get().SetDamping(d, e); }); },
          py::arg("damping"), "d [N·s/m or N·m·s/rad]: finite and >= 0.")
      .def(
          "set_saturation",
          [](Ref const& self, real s) {
            Checked([&](Error& e) { self.Get().SetSaturation(s, e); });
          },
          py::arg("saturation"), "ḡ: finite; <= 0 (e.g. -1) disables saturation. Force cap = k·ḡ.")
      .def("get_hessian_approximation", Forward<Ref>(&C::GetHessianApproximation),
           "This constraint's ConstraintHessian (SceneDefault: the scene's choice).")
      .def(
          "set_hessian_approximation",
          [](Ref const& self, ConstraintHessian h) {
            Checked([&](Error& e) { self.Get().SetHessianApproximation(h, e); });
          },
          py::arg("hessian"), "A ConstraintHessian; SceneDefault follows the scene's choice.")
      // ---- kinematic targets ----
      .def(
          "set_target_position",
          [](Ref const& self, Real3 const& p) {
            Checked([&](Error& e) { self.Get().SetTargetPosition(p, e); });
          },
          py::arg("position"),
          "Target position p̂, world [m] (RigidPivotPosition, DeformableNodePosition).")
      .def(
          "set_target_rotation",
          [](Ref const& self, Quat const& q) {
            Checked([&](Error& e) { self.Get().SetTargetRotation(q, e); });
          },
          py::arg("rotation"),
          "Target rotation R̂, unit quaternion [w, x, y, z] (rotation-target types).")
      .def(
          "set_target_transform",
          [](Ref const& self, Real3 const& p, Quat const& q) {
            Checked([&](Error& e) { self.Get().SetTargetTransform(p, q, e); });
          },
          py::arg("position"), py::arg("rotation"),
          "Target rigid transform T̂ (RigidPivotToRigidTarget).")
      .def(
          "set_target_dof",
          [](Ref const& self, real value) {
            Checked([&](Error& e) { self.Get().SetTargetDof(value, e); });
          },
          py::arg("value"), "Target DoF value θ̂ [rad or m] (ArticulatedSingleDofTarget).")
      .def(
          "update_old_target",
          [](Ref const& self) { Checked([&](Error& e) { self.Get().UpdateOldTarget(e); }); },
          "Resets the stage-start target to the current one, so a teleported target produces no "
          "damping transient in the next step (target-bearing types).")
      // ---- diagnostics and queries ----
      .def(
          "get_deviation",
          [](Ref const& self) { return ToArray(Span<real const>(self.Get().GetDeviation())); },
          "The current value g (m entries), a numpy array. Needs no setup.")
      .def("is_query_supported", Forward<Ref>(&C::IsQuerySupported), py::arg("query_type"),
           "Whether a query type applies to this constraint.")
      .def(
          "register_query",
          [](Ref const& self, QueryType type) {
            Checked([&](Error& e) { self.Get().RegisterQuery(type, e); });
          },
          py::arg("query_type"),
          "Registers a query; ConstraintForce must be registered before a step for get_force to "
          "report it.")
      .def(
          "get_force",
          [](Ref const& self) {
            return ToArray(Checked([&](Error& e) { return self.Get().GetForce(e); }));
          },
          "-r_c = -Jᵀ(κ g + d/Δt Δg) at the end of the last step, in DoF-list order (n entries; "
          "a copy). mochi.Error(InvalidState) when the ConstraintForce query was not registered "
          "before the last step, or no step ran since.")
      // ---- limits ----
      .def(
          "get_limit_min_values",
          [](Ref const& self) {
            return ToArray(Span<real const>(
                Checked([&](Error& e) { return self.Get().GetLimitMinValues(e); })));
          },
          "Lower bounds of a range type (m entries; -inf where unbounded); NotSupported otherwise.")
      .def(
          "get_limit_max_values",
          [](Ref const& self) {
            return ToArray(Span<real const>(
                Checked([&](Error& e) { return self.Get().GetLimitMaxValues(e); })));
          },
          "Upper bounds of a range type (m entries; +inf where unbounded); NotSupported "
          "otherwise.");
}

}  // namespace superdex::python
