// RigidPivotPosition — pins a point of a rigid body to a kinematic target.
//
//   g = T(r) − p̂ = t + R r − p̂                                  m = 3, n = 6
//   J = [ I, −Hat(R r) ]
// Target p̂ (world, m) set with SetTargetPosition; moving it between steps
// produces a damping force unless UpdateOldTarget is called (teleport).
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>
#include <superdex/core/handle.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct RigidPivotPositionConstraintParams {
  ActorHandle actor;                 ///< a rigid actor, or an articulated actor with `link`
  int link = -1;                     ///< the articulated actor's link acting as the body (−1: a rigid actor)
  Real3 localPos = Real3::Zero();    ///< pivot r in the body frame [m]
  Real3 position = Real3::Zero();    ///< target p̂, world [m]
  real stiffness = 0;                ///< k >= 0 [N/m]
  real damping = 0;                  ///< d >= 0 [N·s/m]
  real saturation = -1;              ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "Pins a point of a rigid body to a kinematic target: g = T(r) - p̂ (m = 3, n = 6).";
  static constexpr auto Fields() {
    using P = RigidPivotPositionConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "a rigid actor, or an articulated actor with link"},
        internal::ParamsField<P>{"link", &P::link, "the articulated actor\'s link acting as the body (-1: a rigid actor)"},
        internal::ParamsField<P>{"localPos", &P::localPos, "pivot r in the body frame [m]"},
        internal::ParamsField<P>{"position", &P::position, "target p̂, world [m]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class RigidPivotPositionConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, RigidPivotPositionConstraintParams const& params,
                                            Error& error);
  RigidPivotPositionConstraint(internal::RigidBodySlot body, RigidPivotPositionConstraintParams const& params);

  Real3 const& GetLocalPos() const { return localPos_; }
  Real3 GetTargetPosition() const { return TargetPosition(GetTarget()); }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Real3 localPos_;
};

}  // namespace superdex
