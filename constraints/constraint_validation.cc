#include <superdex/constraints/constraint_validation.h>

#include <cmath>

namespace superdex::internal {

NodalActor* GetDeformableNode(ActorLookup const& scene, ActorHandle handle, int node, std::string_view paramsName,
                              std::string_view actorField, std::string_view nodeField, Error& error) {
  std::string const prefix = std::string(paramsName) + ".";
  auto* actor = GetActorAs<NodalActor>(scene, handle, prefix + std::string(actorField), error);
  if (!actor) return nullptr;
  if (node < 0 || node >= actor->GetNumNodes()) {
    error.Set(ErrorCode::InvalidArgument, prefix + std::string(nodeField) + " must be in [0, " +
                                              std::to_string(actor->GetNumNodes()) + "), got " +
                                              std::to_string(node));
    return nullptr;
  }
  return actor;
}

bool GetRigidBody(ActorLookup const& scene, ActorHandle handle, int link, std::string_view paramsName,
                         std::string_view actorField, std::string_view linkField, RigidBodySlot& body, Error& error) {
  std::string const prefix = std::string(paramsName) + ".";
  Actor* actor = scene.FindActor(handle);
  if (!actor) {
    error.Set(ErrorCode::InvalidHandle, prefix + std::string(actorField) + ": actor handle " + HandleText(handle) +
                                            " " + scene.WhyNotFound(handle));
    return false;
  }
  std::string const linkText = prefix + std::string(linkField);
  switch (actor->GetType()) {
    case ActorType::Rigid:
      if (link != -1) {
        error.Set(ErrorCode::InvalidArgument, linkText + " must be -1 for the Rigid actor " + HandleText(handle) +
                                                  " (a link index names a link of an Articulated actor), got " +
                                                  std::to_string(link));
        return false;
      }
      break;
    case ActorType::Articulated: {
      int const numLinks = static_cast<ArticulatedActor*>(actor)->GetNumLinks();
      if (link < 0 || link >= numLinks) {
        error.Set(ErrorCode::InvalidArgument, linkText + " must be a link of the Articulated actor " +
                                                  HandleText(handle) + ", in [0, " + std::to_string(numLinks) +
                                                  "), got " + std::to_string(link));
        return false;
      }
      break;
    }
    default:
      error.Set(ErrorCode::InvalidHandle, prefix + std::string(actorField) + ": actor " + HandleText(handle) +
                                              " is a " + std::string(ToString(actor->GetType())) +
                                              " actor, expected a Rigid actor or an Articulated actor's link");
      return false;
  }
  body = {actor, link};
  return true;
}

ArticulatedActor* GetArticulatedJoint(ActorLookup const& scene, ActorHandle handle, int joint, int dof, bool rotation,
                                      std::string_view paramsName, Error& error) {
  std::string const prefix = std::string(paramsName) + ".";
  auto* actor = GetActorAs<ArticulatedActor>(scene, handle, prefix + "actor", error);
  if (!actor) return nullptr;
  if (joint < 0 || joint >= actor->GetNumLinks()) {
    error.Set(ErrorCode::InvalidArgument, prefix + "jointIndex must be in [0, " +
                                              std::to_string(actor->GetNumLinks()) + "), got " + std::to_string(joint));
    return nullptr;
  }
  JointType const type = actor->GetJointType(joint);
  std::string const jointText = prefix + "jointIndex = " + std::to_string(joint) + " is a " +
                                std::string(ToString(type)) + " joint";
  if (rotation) {
    if (type != JointType::Spherical && type != JointType::Free) {
      error.Set(ErrorCode::InvalidArgument,
                jointText + ": the 3D rotation types act on spherical joints and free joints' rotations");
      return nullptr;
    }
    return actor;
  }
  if (type == JointType::Spherical || type == JointType::Fixed) {
    error.Set(ErrorCode::InvalidArgument,
              jointText + ": the single-DoF types act on revolute and prismatic joints and free joints' "
                          "translations (for a spherical joint use Articulated3dRotationTarget/Range)");
    return nullptr;
  }
  int const numDofs = type == JointType::Free ? 3 : 1;
  if (dof < 0 || dof >= numDofs) {
    error.Set(ErrorCode::InvalidArgument,
              prefix + "dofIndex must be in [0, " + std::to_string(numDofs) + ") for a " +
                  std::string(ToString(type)) + " joint, got " + std::to_string(dof) +
                  (type == JointType::Free && dof >= 3 && dof < 6
                       ? " (a free joint's rotation: use Articulated3dRotationTarget/Range)"
                       : ""));
    return nullptr;
  }
  return actor;
}

bool CheckField(Real3 const& v, std::string_view paramsName, std::string_view field, Error& error) {
  return CheckFinite(v, std::string(paramsName) + "." + std::string(field), error);
}

bool CheckField(Quat const& q, std::string_view paramsName, std::string_view field, Error& error) {
  return CheckUnitQuat(q, std::string(paramsName) + "." + std::string(field), error);
}

// lower <= upper componentwise, neither NaN (±∞ allowed: no bound)
bool CheckLimits(real lower, real upper, std::string const& field, Error& error) {
  if (std::isnan(lower) || std::isnan(upper) || lower > upper || lower == HUGE_VAL ||
      upper == -HUGE_VAL) {
    error.Set(ErrorCode::InvalidArgument,
              field + " must satisfy lower <= upper with no NaN (lower = " + Format(lower) +
                  ", upper = " + Format(upper) + ")");
    return false;
  }
  return true;
}
}  // namespace superdex::internal
