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

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}

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
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = Log((R_R R̂ R₀)⁻¹ R_e R₀) (m = 3, n = 11: the body's 3 rotation DoFs, the element's 8). The target starts as the creation-time relative rotation.";
  static constexpr auto Fields() {
    using P = RodElementRotationToRigidConstraintParams;
    return std::array{
        internal::ParamsField<P>{"rigidActor", &P::rigidActor, "a rigid actor, or an articulated actor with rigid_link"},
        internal::ParamsField<P>{"rigidLink", &P::rigidLink, "the articulated actor\'s link acting as the rigid body (-1: a rigid actor)"},
        internal::ParamsField<P>{"rodActor", &P::rodActor, "a rod actor"},
        internal::ParamsField<P>{"elementIndex", &P::elementIndex, "element e = (e, e+1) of the rod"},
        internal::ParamsField<P>{"jointFrame", &P::jointFrame, "R₀, world, at creation [w, x, y, z]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class RodElementRotationToRigidConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, RodElementRotationToRigidConstraintParams const& params,
                                            Error& error);
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
