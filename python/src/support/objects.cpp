#include "support/objects.h"

namespace superdex::python {

namespace {

std::string HandleText(std::uint32_t index, std::uint32_t generation) {
  return "{index " + std::to_string(index) + ", generation " + std::to_string(generation) + "}";
}

}  // namespace

Scene& SceneOwner::Get() const {
  if (!scene_)
    Raise(ErrorCode::InvalidState, "the scene was destroyed (Scene.destroy()); create a new one");
  return *scene_;
}

Collider& ColliderRef::Get() const {
  Collider* collider = scene_->Get().GetCollider(id_);
  if (!collider)
    Raise(ErrorCode::InvalidHandle,
          "collider " + std::to_string(id_) + " was destroyed (with the actor that carried it)");
  return *collider;
}

Actor& ActorRef::Get() const {
  Actor* actor = scene_->Get().GetActor(handle_);
  if (!actor)
    Raise(ErrorCode::InvalidHandle, std::string(ToString(type_)) + " actor " +
                                        HandleText(handle_.index, handle_.generation) +
                                        " was destroyed (its handle is stale)");
  return *actor;
}

bool ActorRef::IsAlive() const {
  return scene_->IsAlive() && scene_->Get().GetActor(handle_);
}

std::string ActorRef::Repr() const {
  return std::string(ToString(type_)) +
         "Actor(handle=ActorHandle(index=" + std::to_string(handle_.index) +
         ", generation=" + std::to_string(handle_.generation) + ")" +
         (IsAlive() ? "" : ", destroyed") + ")";
}

Constraint& ConstraintRef::Get() const {
  Constraint* constraint = scene_->Get().GetConstraint(handle_);
  if (!constraint)
    Raise(ErrorCode::InvalidHandle,
          std::string(ToString(type_)) + " constraint " +
              HandleText(handle_.index, handle_.generation) +
              " was destroyed (directly, or with one of its actors); its handle is stale");
  return *constraint;
}

bool ConstraintRef::IsAlive() const {
  return scene_->IsAlive() && scene_->Get().GetConstraint(handle_);
}

std::string ConstraintRef::Repr() const {
  return std::string(ToString(type_)) +
         "Constraint(handle=ConstraintHandle(index=" + std::to_string(handle_.index) +
         ", generation=" + std::to_string(handle_.generation) + ")" +
         (IsAlive() ? "" : ", destroyed") + ")";
}

py::object WrapActor(SceneRef const& scene, Actor& actor) {
  switch (actor.GetType()) {
    case ActorType::Rigid:
      return Cast<RigidActorRef>(scene, static_cast<RigidActor&>(actor));
    case ActorType::Deformable:
      return Cast<DeformableActorRef>(scene, static_cast<DeformableActor&>(actor));
    case ActorType::Rod:
      return Cast<RodActorRef>(scene, static_cast<RodActor&>(actor));
    case ActorType::Articulated:
      return Cast<ArticulatedActorRef>(scene, static_cast<ArticulatedActor&>(actor));
  }
  return py::cast(ActorRef(scene, actor));
}


ActorHandle LoadActorHandle(py::handle value, std::string const& field) {
  if (py::isinstance<ActorRef>(value)) return value.cast<ActorRef const&>().GetHandle();
  if (py::isinstance<ActorHandle>(value)) return value.cast<ActorHandle>();
  Raise(ErrorCode::InvalidArgument,
        field + " must be an ActorHandle or an actor, got " + std::string(py::repr(value)));
}

ConstraintHandle LoadConstraintHandle(py::handle value, std::string const& field) {
  if (py::isinstance<ConstraintRef>(value)) return value.cast<ConstraintRef const&>().GetHandle();
  if (py::isinstance<ConstraintHandle>(value)) return value.cast<ConstraintHandle>();
  Raise(ErrorCode::InvalidArgument,
        field + " must be a ConstraintHandle or a constraint, got " + std::string(py::repr(value)));
}

}  // namespace superdex::python
