// JointRotationRange — limits the relative rotation of two rigid bodies with
// independent lower/upper bounds per component, in the joint frame R₀ (stored
// A-local), against a reference rotation R_ref:
//
//   r_AB = Log(R₀⁻¹ R_A⁻¹ R_B R₀ R_ref⁻¹)                       m = 3, n = 6
//   g_j  = max(r_AB,j − u_j, l_j − r_AB,j, 0)   (one-sided violation)
//   J    = s_j · row j of [ −D, D ],  D = J_l⁻¹(r_AB) (R_A R₀)ᵀ, s_j = ±1 or 0
// Columns: A rotation increment, B rotation increment.
//
// By default (rangeAroundRest) R_ref is the relative rotation R₀⁻¹R_A⁻¹R_B R₀
// observed at creation, so the bounds are relative to the rest pose. The
// components are those of a rotation vector: independent bounds describe a
// range of motion for moderate angles (rotations do not commute).
// A range type: inactive — contributing nothing — while every component is
// within its bounds now and at the stage start. Units: rad; stiffness N·m/rad.
#pragma once

#include <memory>

#include <limits>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct JointRotationRangeConstraintParams {
  ActorHandle actorA;                   ///< a rigid actor, or an articulated actor with `linkA`
  ActorHandle actorB;                   ///< a different rigid actor, or an articulated actor with `linkB`
  int linkA = -1;                       ///< the link acting as body A (−1: a rigid actor)
  int linkB = -1;                       ///< the link acting as body B (−1: a rigid actor)
  Quat jointFrame = Quat::Identity();   ///< joint frame, world, at creation
  /// l_j [rad], −∞ for no bound; each <= the matching upper limit
  Real3 lowerLimits = Real3::Constant(-std::numeric_limits<real>::infinity());
  /// u_j [rad], +∞ for no bound
  Real3 upperLimits = Real3::Constant(std::numeric_limits<real>::infinity());
  bool rangeAroundRest = true;              ///< R_ref = the creation-time relative rotation
  Quat referenceRotation = Quat::Identity();///< R_ref when !rangeAroundRest
  real stiffness = 0;                   ///< k >= 0 [N·m/rad]
  real damping = 0;                     ///< d >= 0 [N·m·s/rad]
  real saturation = -1;                 ///< ḡ [rad]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "Bounds per component of r_AB = Log(R₀⁻¹ R_A⁻¹ R_B R₀ R_ref⁻¹); g_j the one-sided violation (range type, m = 3, n = 6).";
  static constexpr auto Fields() {
    using P = JointRotationRangeConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actorA", &P::actorA, "a rigid actor"},
        internal::ParamsField<P>{"actorB", &P::actorB, "a different rigid actor"},
        internal::ParamsField<P>{"linkA", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)"},
        internal::ParamsField<P>{"linkB", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)"},
        internal::ParamsField<P>{"jointFrame", &P::jointFrame, "joint frame R₀, world, at creation [w, x, y, z]"},
        internal::ParamsField<P>{"lowerLimits", &P::lowerLimits, "l_j [rad], -inf for no bound; each <= the upper limit"},
        internal::ParamsField<P>{"upperLimits", &P::upperLimits, "u_j [rad], +inf for no bound"},
        internal::ParamsField<P>{"rangeAroundRest", &P::rangeAroundRest, "R_ref = the creation-time relative rotation (default True)"},
        internal::ParamsField<P>{"referenceRotation", &P::referenceRotation, "R_ref when not range_around_rest"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class JointRotationRangeConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, JointRotationRangeConstraintParams const& params,
                                            Error& error);
  JointRotationRangeConstraint(internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB,
                               JointRotationRangeConstraintParams const& params);

  /// r_AB, the measured relative rotation vector.
  Real3 GetRelativeRotation() const;

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;
  void DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const override;

  Quat frameInA_;           ///< R₀
  Quat referenceRotation_;  ///< R_ref
  Real3 lowerLimits_, upperLimits_;
};

}  // namespace superdex
