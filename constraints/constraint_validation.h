// How a constraint type's Create checks its params against the scene: the
// actors its handles name (through ActorLookup, which the scene implements)
// and the field checks every type shares. Each failed check sets an Error
// naming "<Params>.<field>" and the value (InvalidHandle for a handle that
// names no actor of the right kind, InvalidArgument otherwise).
#pragma once

#include <string>
#include <string_view>
#include <type_traits>

#include <superdex/actors/articulated_actor.h>
#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/actors/rod_actor.h>
#include <superdex/constraints/constraint_kernel.h>
#include <superdex/core/error.h>
#include <superdex/core/handle.h>
#include <superdex/core/validate.h>

namespace superdex::internal {

/// The actors a scene holds, as a constraint type's Create looks them up.
class ActorLookup {
 public:
  virtual ~ActorLookup() = default;
  /// The live actor `handle` names, or nullptr.
  virtual Actor* FindActor(ActorHandle handle) const = 0;
  /// Why FindActor gives nullptr for `handle` ("is null or stale", ...).
  virtual std::string WhyNotFound(ActorHandle handle) const = 0;
};

/// A live actor of type T (RigidActor, RodActor, ArticulatedActor; NodalActor:
/// deformable or rod) for `handle`, or nullptr with `error` naming `field`.
template <class T>
T* GetActorAs(ActorLookup const& scene, ActorHandle handle, std::string_view field, Error& error) {
  // NodalActor: deformable or rod
  constexpr bool kNodal = std::is_same_v<T, NodalActor>;
  constexpr ActorType kType = std::is_same_v<T, RigidActor>         ? ActorType::Rigid
                              : std::is_same_v<T, RodActor>         ? ActorType::Rod
                              : std::is_same_v<T, ArticulatedActor> ? ActorType::Articulated
                                                                    : ActorType::Deformable;
  Actor* actor = scene.FindActor(handle);
  if (!actor) {
    error.Set(ErrorCode::InvalidHandle,
              std::string(field) + ": actor handle " + HandleText(handle) + " " +
                  scene.WhyNotFound(handle));
    return nullptr;
  }
  bool const matches = kNodal ? (actor->GetType() == ActorType::Deformable || actor->GetType() == ActorType::Rod)
                              : actor->GetType() == kType;
  if (!matches) {
    error.Set(ErrorCode::InvalidHandle, std::string(field) + ": actor " + HandleText(handle) + " is a " +
                                            std::string(ToString(actor->GetType())) + " actor, expected a " +
                                            (kNodal ? std::string("Deformable or Rod") : std::string(ToString(kType))) +
                                            " actor");
    return nullptr;
  }
  return static_cast<T*>(actor);
}

/// A live deformable or rod actor and a node index in range, or nullptr.
NodalActor* GetDeformableNode(ActorLookup const& scene, ActorHandle handle, int node, std::string_view paramsName,
                              std::string_view actorField, std::string_view nodeField, Error& error);

/// A rigid body for a constraint: a live rigid actor with `link` −1, or a
/// live articulated actor and a link of it; false with the error naming
/// `actorField` or `linkField` of `paramsName` otherwise.
bool GetRigidBody(ActorLookup const& scene, ActorHandle handle, int link, std::string_view paramsName,
                  std::string_view actorField, std::string_view linkField, RigidBodySlot& body, Error& error);

/// Two rigid bodies (GetRigidBody) for actorA/linkA and actorB/linkB of `p`,
/// not one body twice (two links of one articulated actor close a loop).
template <class Params>
bool GetRigidPair(ActorLookup const& scene, Params const& p, std::string_view paramsName, RigidBodySlot& a,
                  RigidBodySlot& b, Error& error) {
  if (!GetRigidBody(scene, p.actorA, p.linkA, paramsName, "actorA", "linkA", a, error) ||
      !GetRigidBody(scene, p.actorB, p.linkB, paramsName, "actorB", "linkB", b, error))
    return false;
  // two links of one articulated actor close a kinematic loop (their paths'
  // common DoFs appear once in the constraint's DoF list); one body twice
  // is refused
  if (a.actor == b.actor && a.link < 0) {
    error.Set(ErrorCode::InvalidArgument,
              std::string(paramsName) + ".actorB must differ from actorA, both are " + HandleText(p.actorA));
    return false;
  }
  if (a.actor == b.actor && a.link == b.link) {
    error.Set(ErrorCode::InvalidArgument, std::string(paramsName) + ".linkB must differ from linkA on one " +
                                              "articulated actor, both are " + std::to_string(p.linkA));
    return false;
  }
  return true;
}


/// A live articulated actor and a joint of it that takes `kind` (single DoF:
/// revolute, prismatic, a free joint's translation `dof`; rotation:
/// spherical or free), or nullptr with the error.
ArticulatedActor* GetArticulatedJoint(ActorLookup const& scene, ActorHandle handle, int joint, int dof, bool rotation,
                                      std::string_view paramsName, Error& error);

// stiffness and damping finite and >= 0, saturation finite (<= 0 disables)
template <class Params>
bool CheckCompliance(Params const& p, std::string_view paramsName, Error& error) {
  std::string const prefix = std::string(paramsName) + ".";
  return CheckNonNegative(p.stiffness, prefix + "stiffness", error) &&
         CheckNonNegative(p.damping, prefix + "damping", error) &&
         CheckFinite(p.saturation, prefix + "saturation", error);
}

bool CheckField(Real3 const& v, std::string_view paramsName, std::string_view field, Error& error);
bool CheckField(Quat const& q, std::string_view paramsName, std::string_view field, Error& error);
/// lower <= upper, neither NaN (±∞ allowed: no bound).
bool CheckLimits(real lower, real upper, std::string const& field, Error& error);

}  // namespace superdex::internal
