// RodElementRotationToRigid — drives the rotation of a rod element's
// material frame relative to a rigid body toward a target R̂ (orientation of
// the rod element relative to the body, in the body's local frame):
//
//   g = Log((R_R R̂ R₀)⁻¹ R_e R₀)                                m = 3, n = 11
//   J = [ −D, D A ],  D = J_l⁻¹(g) (R_R R̂ R₀)ᵀ
// Columns: the rigid body's rotation increment (actor 0, 3 DoFs), then the
// element's two nodes' 4 DoFs each, [xₑ, θₑ, xₑ₊₁, θₑ₊₁] (actor 1, 8 DoFs).
// R_e = [d₁ d₂ t] is the element's material frame (actors/rod_element.h) and
// A = ∂ω_e/∂(DoFs) its angular increment per DoF increment (θₑ₊₁'s column is
// zero). R₀ is a frame given in world at creation and stored body-local
// (identity by default; it only changes the axes g is measured in).
//
// The target starts as the relative rotation R_R⁻¹R_e observed at creation (the
// constraint starts satisfied, the rod keeps its creation-time orientation
// relative to the body) and is changed with SetTargetRotation. A rod end
// clamped to a rigid body is DeformableNodeToRigid on the end node plus this
// constraint on the end element. Units: rad; stiffness N·m/rad.
#pragma once

#include <superdex/constraints/constraint.h>

namespace superdex {

class RodActor;

struct RodElementRotationToRigidConstraintParams {
  ActorHandle rigidActor;              ///< a rigid actor, or an articulated actor with `rigidLink`
  int rigidLink = -1;                  ///< the link acting as the rigid body (−1: a rigid actor)
  ActorHandle rodActor;                ///< a rod actor
  int elementIndex = 0;                ///< element e = (e, e+1) of the rod
  Quat jointFrame = Quat::Identity();  ///< R₀, world, at creation
  real stiffness = 0;                  ///< k >= 0 [N·m/rad]
  real damping = 0;                    ///< d >= 0 [N·m·s/rad]
  real saturation = -1;                ///< ḡ [rad]; <= 0 disables
};

class RodElementRotationToRigidConstraint final : public Constraint {
 public:
  RodElementRotationToRigidConstraint(internal::RigidBodySlot rigid, RodActor* rod,
                                      RodElementRotationToRigidConstraintParams const& params);

  int GetElementIndex() const { return element_; }
  /// The current target R̂ (rod element relative to the body, body-local).
  Quat GetTargetRotation() const { return TargetRotation(GetTarget()); }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  RodActor* rod_;
  int element_;
  Quat frameInBody_;  ///< R₀
};

}  // namespace superdex
