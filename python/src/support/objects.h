// The Python objects of scenes, actors and constraints, and how they stay
// safe (docs/python.md, "Lifetime").
//
//   mochi.Scene      a SceneOwner, held by std::shared_ptr: it owns the C++
//                    Scene (Scene::Create's unique_ptr) until Scene.destroy()
//                    or until the last Python object referring to it is gone.
//   mochi.*Actor     an ActorRef: the shared SceneOwner + the stable
//   mochi.*Constraint  ActorHandle / ConstraintHandle. Nothing keeps a raw
//                    pointer: every call resolves the handle through
//                    Scene::GetActor / GetConstraint, so an object whose C++
//                    counterpart was destroyed (directly, with its actor, or
//                    with its scene) raises mochi.Error instead of crashing:
//                    InvalidHandle for a destroyed actor or constraint,
//                    InvalidState for a destroyed scene.
// The handle's generation makes resolution exact: a handle never names a
// later object that reuses the slot, so the static_cast to the type recorded
// at wrapping time is safe.
#pragma once

#include <memory>
#include <string>

#include "support/errors.h"

namespace superdex::python {

class SceneOwner {
 public:
  explicit SceneOwner(std::unique_ptr<Scene> scene) : scene_(std::move(scene)) {}
  /// The scene; mochi.Error(InvalidState) after Destroy().
  Scene& Get() const;
  bool IsAlive() const { return scene_ != nullptr; }
  /// Destroys the C++ scene, its actors and constraints now.
  void Destroy() { scene_.reset(); }

 private:
  std::unique_ptr<Scene> scene_;
};
using SceneRef = std::shared_ptr<SceneOwner>;

/// A Python collider: scene + collider id, resolved on every call.
class ColliderRef {
 public:
  ColliderRef(SceneRef scene, int id) : scene_(std::move(scene)), id_(id) {}
  /// The live collider, or mochi.Error (InvalidHandle: its actor was
  /// destroyed; InvalidState: scene destroyed).
  Collider& Get() const;

 private:
  SceneRef scene_;
  int id_;
};

/// A Python actor: scene + handle, resolved on every call.
class ActorRef {
 public:
  ActorRef(SceneRef scene, Actor const& actor)
      : scene_(std::move(scene)), handle_(actor.GetHandle()), type_(actor.GetType()) {}
  /// The live actor, or mochi.Error (InvalidHandle: destroyed; InvalidState: scene destroyed).
  Actor& Get() const;
  /// True while the actor (and its scene) exists.
  bool IsAlive() const;
  SceneRef const& GetScene() const { return scene_; }
  ActorHandle GetHandle() const { return handle_; }
  ActorType GetType() const { return type_; }
  std::string Repr() const;

 private:
  SceneRef scene_;
  ActorHandle handle_;
  ActorType type_;
};

/// An ActorRef whose actor is a T (checked when it was wrapped).
template <class T, class Base = ActorRef>
class ActorRefOf : public Base {
 public:
  using Base::Base;
  using Type = T;
  T& Get() const { return static_cast<T&>(ActorRef::Get()); }
};
using NodalActorRef = ActorRefOf<NodalActor>;
using RigidActorRef = ActorRefOf<RigidActor>;
using DeformableActorRef = ActorRefOf<DeformableActor, NodalActorRef>;
using RodActorRef = ActorRefOf<RodActor, NodalActorRef>;
using ArticulatedActorRef = ActorRefOf<ArticulatedActor>;

/// A Python constraint: scene + handle, resolved on every call.
class ConstraintRef {
 public:
  ConstraintRef(SceneRef scene, Constraint const& constraint)
      : scene_(std::move(scene)), handle_(constraint.GetHandle()), type_(constraint.GetType()) {}
  Constraint& Get() const;
  bool IsAlive() const;
  SceneRef const& GetScene() const { return scene_; }
  ConstraintHandle GetHandle() const { return handle_; }
  ConstraintType GetType() const { return type_; }
  std::string Repr() const;

 private:
  SceneRef scene_;
  ConstraintHandle handle_;
  ConstraintType type_;
};

template <class T>
class ConstraintRefOf : public ConstraintRef {
 public:
  using ConstraintRef::ConstraintRef;
  using Type = T;
  T& Get() const { return static_cast<T&>(ConstraintRef::Get()); }
};

/// The Python object of `object` as its class Ref (RigidActorRef, ConstraintRefOf<T>, ...).
template <class Ref>
py::object Cast(SceneRef const& scene, typename Ref::Type& object) {
  return py::cast(Ref(scene, object));
}

/// The class of constraint class T already bound (mochi.<T>), to add accessors to.
template <class T>
py::class_<ConstraintRefOf<T>, ConstraintRef> ConstraintClass() {
  return py::reinterpret_borrow<py::class_<ConstraintRefOf<T>, ConstraintRef>>(py::type::of<ConstraintRefOf<T>>());
}

/// The Python object of the most derived class for `actor` (mochi.RigidActor, ...).
py::object WrapActor(SceneRef const& scene, Actor& actor);
/// The Python object of the most derived class for `constraint`.
py::object WrapConstraint(SceneRef const& scene, Constraint& constraint);

/// The ActorHandle of a Python ActorHandle or actor object; mochi.Error naming `field` otherwise.
ActorHandle LoadActorHandle(py::handle value, std::string const& field);
ConstraintHandle LoadConstraintHandle(py::handle value, std::string const& field);

/// `self.Get().method(args...)` for a binding on Ref; returns by value.
template <class Ref, class R, class T, class... Args>
auto Forward(R (T::*method)(Args...) const) {
  return [method](Ref const& self, Args... args) -> std::decay_t<R> {
    return (self.Get().*method)(args...);
  };
}

/// As Forward, for an accessor taking an index in [0, (self.Get().*count)()),
/// which is checked first (the C++ accessor only states it as a precondition).
template <class Ref, class R, class T, class Count>
auto ForwardIndexed(R (T::*method)(int) const, Count count, char const* what) {
  return [method, count, what](Ref const& self, int index) -> std::decay_t<R> {
    auto const& object = self.Get();
    CheckIndex(index, (object.*count)(), what);
    return (object.*method)(index);
  };
}

/// `__eq__`, `__hash__`, `__repr__`, is_alive(), get_handle(), get_type() and
/// get_scene() of actor and constraint objects.
template <class Ref, class Class>
void DefineIdentity(Class& cls) {
  cls.def("get_handle", &Ref::GetHandle, "The stable handle of this object.")
      .def("get_type", &Ref::GetType, "The type (ActorType / ConstraintType).")
      .def("is_alive", &Ref::IsAlive,
           "True while the C++ object exists (not destroyed directly, with an actor, or with "
           "its scene). Every other method raises mochi.Error once it is False.")
      .def("get_scene", &Ref::GetScene, "The Scene this object belongs to.")
      .def("__repr__", &Ref::Repr)
      .def(
          "__eq__",
          [](Ref const& a, py::object const& b) {
            if (!py::isinstance<Ref>(b)) return false;
            Ref const& other = b.cast<Ref const&>();
            return a.GetScene() == other.GetScene() && a.GetHandle() == other.GetHandle();
          },
          py::arg("other"))
      .def("__hash__", [](Ref const& self) {
        return std::hash<decltype(self.GetHandle())>()(self.GetHandle()) ^
               std::hash<SceneOwner const*>()(self.GetScene().get());
      });
}

}  // namespace superdex::python
