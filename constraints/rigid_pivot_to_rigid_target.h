// RigidPivotToRigidTarget — pins a point of a rigid body to the same point
// carried by a prescribed rigid motion T̂ (one actor: T̂ is data, not a body):
//
//   g = T(r) − T̂(r) = t + R r − (t̂ + R̂ r)                        m = 3, n = 6
//   J = [ I, −Hat(R r) ]
// The target point moves with the target's rotation too. The target
// transform is set with SetTargetTransform(position, rotation).
// Units: m; stiffness N/m, damping N·s/m.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct RigidPivotToRigidTargetConstraintParams {
  ActorHandle actor;                  ///< a rigid actor, or an articulated actor with `link`
  int link = -1;                      ///< the articulated actor's link acting as the body (−1: a rigid actor)
  Real3 localPos = Real3::Zero();     ///< pivot r in the body frame [m]
  Real3 position = Real3::Zero();     ///< target translation t̂, world [m]
  Quat rotation = Quat::Identity();   ///< target rotation R̂, world
  real stiffness = 0;                 ///< k >= 0 [N/m]
  real damping = 0;                   ///< d >= 0 [N·s/m]
  real saturation = -1;               ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = T(r) - T̂(r) = t + R r - (t̂ + R̂ r) (m = 3, n = 6); T̂ set with set_target_transform.";
  static constexpr auto Fields() {
    using P = RigidPivotToRigidTargetConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "a rigid actor, or an articulated actor with link"},
        internal::ParamsField<P>{"link", &P::link, "the articulated actor\'s link acting as the body (-1: a rigid actor)"},
        internal::ParamsField<P>{"localPos", &P::localPos, "pivot r in the body frame [m]"},
        internal::ParamsField<P>{"position", &P::position, "target translation t̂, world [m]"},
        internal::ParamsField<P>{"rotation", &P::rotation, "target rotation R̂, world [w, x, y, z]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class RigidPivotToRigidTargetConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, RigidPivotToRigidTargetConstraintParams const& params,
                                            Error& error);
  RigidPivotToRigidTargetConstraint(internal::RigidBodySlot body,
                                    RigidPivotToRigidTargetConstraintParams const& params);

  Real3 const& GetLocalPos() const { return localPos_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Real3 localPos_;
};

}  // namespace superdex
