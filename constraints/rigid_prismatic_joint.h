// RigidPrismaticJoint — restricts the relative translation of two rigid
// bodies to a sliding axis, with optional travel limits along it.
//
//   s = R₀⁻¹ R_A⁻¹ (t_B − t_A) − s_ref                         m = 3, n = 9
//   g₁ = s₁, g₂ = s₂ (bilateral); g₃ = s₃ − u above the upper limit u,
//   s₃ − l below the lower limit l, 0 in between (signed violation).
//   J = R₀ᵀ R_Aᵀ [ −I, Hat(t_B − t_A), I ]  (rows 1, 2; row 3 when outside)
// Columns: A translation, A rotation increment, B translation.
//
// R₀ is the joint frame in A's body coordinates: `jointFrame` is given in
// world coordinates at creation and converted to A-local then, constant
// thereafter; its z axis is the free axis. By default (offsetAroundRest) s_ref
// is the offset observed at creation, so the joint starts satisfied and s₃ (the
// travel, limits included) is measured from the creation pose.
//
// Warning (as the reference page): it does not restrict relative rotation —
// add a JointRotationTracking for a full prismatic joint — and its travel
// limits are not reported by GetLimitMinValues/GetLimitMaxValues.
// Units: m; stiffness N/m, damping N·s/m.
#pragma once

#include <memory>

#include <limits>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct RigidPrismaticJointConstraintParams {
  ActorHandle actorA;                      ///< a rigid actor, or an articulated actor with `linkA`
  ActorHandle actorB;                      ///< a different rigid actor, or an articulated actor with `linkB`
  int linkA = -1;                          ///< the link acting as body A (−1: a rigid actor)
  int linkB = -1;                          ///< the link acting as body B (−1: a rigid actor)
  Quat jointFrame = Quat::Identity();      ///< joint frame, world, at creation; z = sliding axis
  bool offsetAroundRest = true;            ///< s_ref = the creation-time offset
  Real3 referenceOffset = Real3::Zero();   ///< s_ref when !offsetAroundRest [m], joint frame
  real lowerLimit = -std::numeric_limits<real>::infinity();  ///< l on s₃ [m]
  real upperLimit = std::numeric_limits<real>::infinity();   ///< u on s₃ [m], >= l
  real stiffness = 0;                      ///< k >= 0 [N/m]
  real damping = 0;                        ///< d >= 0 [N·s/m]
  real saturation = -1;                    ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "Slider: s = R₀⁻¹ R_A⁻¹ (t_B - t_A) - s_ref; g₁ = s₁, g₂ = s₂, g₃ the signed violation of s₃ against the travel limits (m = 3, n = 9). Does not restrict relative rotation (add a JointRotationTracking); its limits are not reported by get_limit_min/max_values.";
  static constexpr auto Fields() {
    using P = RigidPrismaticJointConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actorA", &P::actorA, "a rigid actor"},
        internal::ParamsField<P>{"actorB", &P::actorB, "a different rigid actor"},
        internal::ParamsField<P>{"linkA", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)"},
        internal::ParamsField<P>{"linkB", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)"},
        internal::ParamsField<P>{"jointFrame", &P::jointFrame, "joint frame, world, at creation [w, x, y, z]; z = sliding axis"},
        internal::ParamsField<P>{"offsetAroundRest", &P::offsetAroundRest, "s_ref = the creation-time offset (default True)"},
        internal::ParamsField<P>{"referenceOffset", &P::referenceOffset, "s_ref when not offset_around_rest [m], joint frame"},
        internal::ParamsField<P>{"lowerLimit", &P::lowerLimit, "l on s₃ [m], default -inf"},
        internal::ParamsField<P>{"upperLimit", &P::upperLimit, "u on s₃ [m], >= l, default +inf"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class RigidPrismaticJointConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, RigidPrismaticJointConstraintParams const& params,
                                            Error& error);
  RigidPrismaticJointConstraint(internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB,
                                RigidPrismaticJointConstraintParams const& params);

  /// s (before the limit rule), the offset of B from A in the joint frame.
  Real3 GetOffset() const;
  real GetLowerLimit() const { return lowerLimit_; }
  real GetUpperLimit() const { return upperLimit_; }

 private:
  /// GetOffset at the bodies' frames as last refreshed (inside an evaluation).
  Real3 Offset() const;
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Quat frameInA_;  ///< R₀
  Real3 referenceOffset_;
  real lowerLimit_, upperLimit_;
};

}  // namespace superdex
