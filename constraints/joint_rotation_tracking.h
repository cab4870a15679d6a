// JointRotationTracking — drives the relative rotation of two rigid bodies
// toward a target R̂ (orientation of B relative to A, in A's local frame):
//
//   g = Log((R_A R̂ R₀)⁻¹ R_B R₀)                                m = 3, n = 6
//   J = [ −D, D ],  D = J_l⁻¹(g) (R_A R̂ R₀)ᵀ
// Columns: A rotation increment, B rotation increment. R₀ is the joint frame
// (given in world at creation, stored A-local).
//
// The target starts as the relative rotation R_A⁻¹R_B observed at creation (the
// constraint starts satisfied) and is changed with SetTargetRotation — e.g. to
// track measured joint angles, or, with stiff gains, to supply the rotational
// restriction a RigidPrismaticJoint lacks. Units: rad; stiffness N·m/rad.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct JointRotationTrackingConstraintParams {
  ActorHandle actorA;                  ///< a rigid actor, or an articulated actor with `linkA`
  ActorHandle actorB;                  ///< a different rigid actor, or an articulated actor with `linkB`
  int linkA = -1;                      ///< the link acting as body A (−1: a rigid actor)
  int linkB = -1;                      ///< the link acting as body B (−1: a rigid actor)
  Quat jointFrame = Quat::Identity();  ///< joint frame R₀, world, at creation
  real stiffness = 0;                  ///< k >= 0 [N·m/rad]
  real damping = 0;                    ///< d >= 0 [N·m·s/rad]
  real saturation = -1;                ///< ḡ [rad]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = Log((R_A R̂ R₀)⁻¹ R_B R₀) (m = 3, n = 6); the target R̂ starts as the creation-time relative rotation and is changed with set_target_rotation.";
  static constexpr auto Fields() {
    using P = JointRotationTrackingConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actorA", &P::actorA, "a rigid actor"},
        internal::ParamsField<P>{"actorB", &P::actorB, "a different rigid actor"},
        internal::ParamsField<P>{"linkA", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)"},
        internal::ParamsField<P>{"linkB", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)"},
        internal::ParamsField<P>{"jointFrame", &P::jointFrame, "joint frame R₀, world, at creation [w, x, y, z]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class JointRotationTrackingConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, JointRotationTrackingConstraintParams const& params,
                                            Error& error);
  JointRotationTrackingConstraint(internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB,
                                  JointRotationTrackingConstraintParams const& params);

  /// The current target R̂ (B relative to A, A-local).
  Quat GetTargetRotation() const { return TargetRotation(GetTarget()); }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Quat frameInA_;  ///< R₀
};

}  // namespace superdex
