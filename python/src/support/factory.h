// DefineFactory: a Scene::Create… factory as a mochi.Scene method taking a
// params object, keywords, or both (keywords override), returning the most
// derived Python class of what it made.
#pragma once

#include <string>

#include "support/objects.h"
#include "support/params_class.h"

namespace superdex::python {

using SceneClass = py::class_<SceneOwner, SceneRef>;

inline py::object Wrap(SceneRef const& scene, Actor& actor) { return WrapActor(scene, actor); }
inline py::object Wrap(SceneRef const& scene, Constraint& constraint) { return WrapConstraint(scene, constraint); }
inline py::object Wrap(SceneRef const& scene, Collider& collider) { return py::cast(ColliderRef(scene, collider.GetId())); }

/// Binds `name`(params=None, **kwargs) -> wrapped object for a Scene::Create… factory.
template <class Params, class Result>
void DefineFactory(SceneClass& cls, char const* name,
                   Result* (Scene::*create)(Params const&, Error&), char const* what) {
  std::string const doc =
      std::string("Creates ") + what + " from `params` (a " + ParamsFields<Params>::TypeName() +
      ", default-constructed when None) with the keyword arguments applied on top. Raises "
      "mochi.Error naming the bad field; a failed call creates nothing.";
  cls.def(
      name,
      [create](SceneRef const& self, py::object const& params, py::kwargs const& kwargs) {
        Params const p = ParamsArgument<Params>(params, kwargs);
        Result* result = Checked([&](Error& e) { return (self->Get().*create)(p, e); });
        if (!result)
          Raise(ErrorCode::InvalidState, "the factory returned nothing without an error");
        return Wrap(self, *result);
      },
      py::arg("params") = py::none(), doc.c_str());
}

/// Scene.create_<name>_constraint for every type of constraints/constraint_types.h.
void DefineConstraintFactories(SceneClass& cls);

}  // namespace superdex::python
