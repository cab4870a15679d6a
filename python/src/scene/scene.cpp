// scene/scene.h: mochi.Scene. Owns actors and constraints and steps them.
// Factories take a params object, keywords, or both (keywords override):
//
//   scene = mochi.Scene.create(gravity=[0, -9.81, 0])
//   body = scene.create_rigid_actor(mass=2, position=[0, 1, 0])
//   pin = scene.create_rigid_pivot_position_constraint(actor=body, stiffness=1e6)
//
// and return the most derived Python class (RigidActor, RigidPivotPositionConstraint, ...).
#include "defines.h"
#include "support/factory.h"

namespace superdex::python {

namespace {

/// Handles of every constraint (or actor) now in the scene, in creation order.
DynamicArray<ConstraintHandle> ConstraintHandles(Scene const& scene) {
  DynamicArray<ConstraintHandle> handles;
  scene.ForEachConstraint([&](Constraint& c) { handles.push_back(c.GetHandle()); });
  return handles;
}
DynamicArray<ActorHandle> ActorHandles(Scene const& scene) {
  DynamicArray<ActorHandle> handles;
  scene.ForEachActor([&](Actor& a) { handles.push_back(a.GetHandle()); });
  return handles;
}

}  // namespace

void DefineScene(py::module_& m) {
  SceneClass cls(
      m, "Scene",
      "Owns actors and constraints and steps them (implicit stages solved by Newton). Made by "
      "Scene.create. Actor and constraint objects keep their scene alive; Scene.destroy() (or "
      "leaving a `with` block) destroys it at once, after which every object of it raises "
      "mochi.Error.");

  cls.def_static(
         "create",
         [](py::object const& params, py::kwargs const& kwargs) {
           SceneParams const p = ParamsArgument<SceneParams>(params, kwargs);
           return std::make_shared<SceneOwner>(
               Checked([&](Error& e) { return Scene::Create(p, e); }));
         },
         py::arg("params") = py::none(),
         "Creates a scene from `params` (SceneParams, default when None) with the keyword "
         "arguments applied on top. Validates finite gravity, positive Newton settings, a "
         "compiled-in linear solver and max_substeps a power of two; raises mochi.Error naming the "
         "field.")
      .def("destroy", &SceneOwner::Destroy,
           "Destroys the C++ scene with its actors and constraints now. Their Python objects "
           "then raise mochi.Error (InvalidState); so do this scene's methods. Idempotent.")
      .def("is_alive", &SceneOwner::IsAlive, "False after destroy().")
      .def(
          "__eq__",
          [](SceneOwner const& self, py::object const& other) {
            return py::isinstance<SceneOwner>(other) && &self == &other.cast<SceneOwner const&>();
          },
          py::arg("other"), "True when both objects are the same scene.")
      .def("__hash__", [](SceneOwner const& self) { return std::hash<SceneOwner const*>()(&self); })
      .def("__enter__", [](SceneRef const& self) { return self; })
      .def(
          "__exit__", [](SceneOwner& self, py::args const&) { self.Destroy(); },
          "Destroys the scene.")
      .def("__repr__", [](SceneOwner const& self) {
        if (!self.IsAlive()) return std::string("Scene(destroyed)");
        Scene const& s = self.Get();
        return "Scene(actors=" + std::to_string(s.GetNumActors()) +
               ", constraints=" + std::to_string(s.GetNumConstraints()) +
               ", dofs=" + std::to_string(s.GetNumDofs()) +
               ", time=" + std::string(py::repr(py::float_(s.GetTime()))) + ")";
      });

  // ---- actors ----
  DefineFactory(cls, "create_rigid_actor", &Scene::CreateRigidActor, "a RigidActor");
  DefineFactory(cls, "create_deformable_actor", &Scene::CreateDeformableActor, "a DeformableActor");
  DefineFactory(cls, "create_rod_actor", &Scene::CreateRodActor, "a RodActor");
  DefineFactory(cls, "create_articulated_actor", &Scene::CreateArticulatedActor,
                "an ArticulatedActor");
  cls.def(
         "get_actor",
         [](SceneRef const& self, ActorHandle handle) -> py::object {
           Actor* actor = self->Get().GetActor(handle);
           return actor ? WrapActor(self, *actor) : py::none();
         },
         py::arg("handle"), "The actor, or None for a null or stale handle.")
      .def(
          "destroy_actor",
          [](SceneRef const& self, py::handle actor) {
            ActorHandle const handle = LoadActorHandle(actor, "actor");
            Checked([&](Error& e) { self->Get().DestroyActor(handle, e); });
          },
          py::arg("actor"),
          "Destroys the actor (an actor object or ActorHandle) and every constraint that "
          "references it; their Python objects raise mochi.Error afterwards. A stale handle, or "
          "one of another scene, raises InvalidHandle.")
      .def(
          "for_each_actor",
          [](SceneRef const& self, py::function const& fn) {
            for (ActorHandle const handle : ActorHandles(self->Get()))
              if (Actor* actor = self->Get().GetActor(handle)) fn(WrapActor(self, *actor));
          },
          py::arg("fn"),
          "Calls fn(actor) for every actor, in creation order (DoF order). fn may destroy "
          "actors: the list is taken first, and actors destroyed meanwhile are skipped.")
      .def(
          "get_actors",
          [](SceneRef const& self) {
            py::list out;
            for (ActorHandle const handle : ActorHandles(self->Get()))
              out.append(WrapActor(self, *self->Get().GetActor(handle)));
            return out;
          },
          "Every actor, in creation order (a list; Python convenience over for_each_actor).")
      .def("get_num_actors", [](SceneOwner const& self) { return self.Get().GetNumActors(); });

  // ---- contact ----
  DefineFactory(cls, "create_collider", &Scene::CreateCollider, "a Collider");
  cls.def("get_num_colliders", [](SceneOwner const& self) { return self.Get().GetNumColliders(); })
      .def(
          "get_contacts",
          [](SceneOwner const& self) {
            DynamicArray<ContactInfo> contacts;
            self.Get().GetContacts(contacts);
            return contacts;
          },
          "The contacts closer than the activation distance at the last step's end (a list of "
          "Contact).");

  // ---- constraints ----
  DefineConstraintFactories(cls);
  cls.def(
         "get_constraint",
         [](SceneRef const& self, ConstraintHandle handle) -> py::object {
           Constraint* constraint = self->Get().GetConstraint(handle);
           return constraint ? WrapConstraint(self, *constraint) : py::none();
         },
         py::arg("handle"), "The constraint, or None for a null or stale handle.")
      .def(
          "for_each_constraint",
          [](SceneRef const& self, py::function const& fn) {
            for (ConstraintHandle const handle : ConstraintHandles(self->Get()))
              if (Constraint* c = self->Get().GetConstraint(handle)) fn(WrapConstraint(self, *c));
          },
          py::arg("fn"),
          "Calls fn(constraint) for every constraint, in creation order. fn may destroy "
          "constraints or actors: the list is taken first, and those destroyed meanwhile are "
          "skipped.")
      .def(
          "get_constraints",
          [](SceneRef const& self) {
            py::list out;
            for (ConstraintHandle const handle : ConstraintHandles(self->Get()))
              out.append(WrapConstraint(self, *self->Get().GetConstraint(handle)));
            return out;
          },
          "Every constraint, in creation order (a list; Python convenience over "
          "for_each_constraint).")
      .def(
          "destroy_constraint",
          [](SceneRef const& self, py::handle constraint) {
            ConstraintHandle const handle = LoadConstraintHandle(constraint, "constraint");
            Checked([&](Error& e) { self->Get().DestroyConstraint(handle, e); });
          },
          py::arg("constraint"),
          "Destroys a constraint (a constraint object or ConstraintHandle); its Python objects "
          "raise mochi.Error afterwards. A stale handle, or one of another scene, raises "
          "InvalidHandle.")
      .def("get_num_constraints",
           [](SceneOwner const& self) { return self.Get().GetNumConstraints(); })
      .def(
          "register_query",
          [](SceneRef const& self, QueryType type) {
            int registered = 0;
            for (ConstraintHandle const handle : ConstraintHandles(self->Get())) {
              Constraint& c = *self->Get().GetConstraint(handle);
              if (!c.IsQuerySupported(type)) continue;
              Checked([&](Error& e) { c.RegisterQuery(type, e); });
              ++registered;
            }
            return registered;
          },
          py::arg("query_type"),
          "Python convenience: Constraint.register_query(query_type) on every constraint now in "
          "the scene that supports it (constraints created later register their own). Returns "
          "how many.");

  // ---- stepping ----
  cls.def(
         "step",
         [](SceneOwner const& self, real dt) {
           Checked([&](Error& e) { self.Get().Step(dt, e); });
         },
         py::arg("dt"),
         "Advances by dt [s] (finite, > 0). Transactional: on failure the scene is restored "
         "exactly and mochi.Error names the stage, the Newton iteration and the cause; retry "
         "with a smaller dt. With SceneParams.substeps.max_substeps > 1 a failed step first "
         "retries itself from the exact pre-step state as 2, 4, ... sub-steps "
         "(SceneStats.substeps says how many the last step used).")
      .def(
          "set_substep_params",
          [](SceneOwner const& self, py::object const& params, py::kwargs const& kwargs) {
            SubstepParams const p = ParamsArgument<SubstepParams>(params, kwargs);
            Checked([&](Error& e) { self.Get().SetSubstepParams(p, e); });
          },
          py::arg("params") = py::none(),
          "Sets the sub-stepping policy between steps from `params` (SubstepParams, default "
          "when None: off) with the keyword arguments applied on top, e.g. "
          "scene.set_substep_params(max_substeps=8). max_substeps must be a power of two >= 1; "
          "on failure nothing changes.")
      .def(
          "set_num_threads",
          [](SceneOwner const& self, int numThreads) {
            Checked([&](Error& e) { self.Get().SetNumThreads(numThreads, e); });
          },
          py::arg("num_threads"),
          "Threads of the assembly (>= 0; 0: every CPU this process may use). Results are "
          "bit-identical for any count.")
      .def("get_num_threads", [](SceneOwner const& self) { return self.Get().GetNumThreads(); },
           "The threads the assembly runs on.")
      .def(
          "set_linear_solver",
          [](SceneOwner const& self, LinearSolverType type, std::optional<PcgParams> const& pcg) {
            Checked([&](Error& e) {
              if (pcg)
                self.Get().SetLinearSolver(type, *pcg, e);
              else
                self.Get().SetLinearSolver(type, e);
            });
          },
          py::arg("type"), py::arg("pcg") = py::none(),
          "Switches the linear solver between steps (pcg: PcgParams for PetscPcg, validated "
          "even for another type; None keeps the current ones). On failure nothing changes.")
      .def(
          "get_time", [](SceneOwner const& self) { return self.Get().GetTime(); },
          "Simulated time [s].")
      .def(
          "get_id", [](SceneOwner const& self) { return self.Get().GetId(); },
          "The number stamped on this scene's handles (ActorHandle.scene), unique in the "
          "process; a handle of another scene raises InvalidHandle here.")
      .def(
          "get_params", [](SceneOwner const& self) { return self.Get().GetParams(); },
          "A copy of the scene's parameters (with the current linear solver).")
      .def(
          "get_stats", [](SceneOwner const& self) { return self.Get().GetStats(); },
          "A snapshot of the SceneStats: counters since creation and figures of the last step.")
      .def(
          "get_num_dofs", [](SceneOwner const& self) { return self.Get().GetNumDofs(); },
          "Total DoFs of all actors.");
}

}  // namespace superdex::python
