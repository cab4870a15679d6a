// RigidSphericalJoint — ball-and-socket between two rigid bodies.
//
//   g = T_A(r_A) − T_B(r_B) = t_A + R_A r_A − t_B − R_B r_B      m = 3, n = 12
//   J = [ I, −Hat(R_A r_A), −I, Hat(R_B r_B) ]
// (columns: A translation, A rotation increment, B translation, B rotation
// increment; R ← Exp(δθ) R). Units: g in m, stiffness N/m, damping N·s/m.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>
#include <superdex/core/handle.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct RigidSphericalJointConstraintParams {
  ActorHandle actorA;                 ///< a rigid actor, or an articulated actor with `linkA`
  ActorHandle actorB;                 ///< a different rigid actor, or an articulated actor with `linkB`
  int linkA = -1;                     ///< the link acting as body A (−1: a rigid actor)
  int linkB = -1;                     ///< the link acting as body B (−1: a rigid actor)
  Real3 localPosA = Real3::Zero();    ///< pivot r_A in A's body frame [m]
  Real3 localPosB = Real3::Zero();    ///< pivot r_B in B's body frame [m]
  real stiffness = 0;                 ///< k >= 0 [N/m]
  real damping = 0;                   ///< d >= 0 [N·s/m]
  real saturation = -1;               ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "Ball-and-socket between two rigid bodies: g = T_A(r_A) - T_B(r_B) (m = 3, n = 12).";
  static constexpr auto Fields() {
    using P = RigidSphericalJointConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actorA", &P::actorA, "a rigid actor (RigidActor or ActorHandle)"},
        internal::ParamsField<P>{"actorB", &P::actorB, "a different rigid actor"},
        internal::ParamsField<P>{"linkA", &P::linkA, "the link of an articulated actor_a acting as body A (-1: a rigid actor)"},
        internal::ParamsField<P>{"linkB", &P::linkB, "the link of an articulated actor_b acting as body B (-1: a rigid actor)"},
        internal::ParamsField<P>{"localPosA", &P::localPosA, "pivot r_A in A's body frame [m]"},
        internal::ParamsField<P>{"localPosB", &P::localPosB, "pivot r_B in B's body frame [m]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class RigidSphericalJointConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, RigidSphericalJointConstraintParams const& params,
                                            Error& error);
  RigidSphericalJointConstraint(internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB,
                                RigidSphericalJointConstraintParams const& params);

  Real3 const& GetLocalPosA() const { return localPosA_; }
  Real3 const& GetLocalPosB() const { return localPosB_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Real3 localPosA_, localPosB_;
};

}  // namespace superdex
