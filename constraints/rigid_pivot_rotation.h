// RigidPivotRotation — drives the rotation of a pivot frame on a rigid body
// toward a world target rotation R̂:
//
//   g = Log(R R_ℓ R̂⁻¹)                                           m = 3, n = 3
//   J = J_l⁻¹(g)        (columns: the body's rotation increment only)
// R is the body rotation, R_ℓ the pivot frame in body coordinates. The target
// is set with SetTargetRotation; updating it every step spins the body.
// Units: rad; stiffness N·m/rad, damping N·m·s/rad.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}


struct RigidPivotRotationConstraintParams {
  ActorHandle actor;                       ///< a rigid actor, or an articulated actor with `link`
  int link = -1;                           ///< the articulated actor's link acting as the body (−1: a rigid actor)
  Quat localRotation = Quat::Identity();   ///< pivot frame R_ℓ in the body frame
  Quat rotation = Quat::Identity();        ///< target R̂, world
  real stiffness = 0;                      ///< k >= 0 [N·m/rad]
  real damping = 0;                        ///< d >= 0 [N·m·s/rad]
  real saturation = -1;                    ///< ḡ [rad]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = Log(R R_ℓ R̂⁻¹) (m = 3, n = 3: the body's rotation DoFs).";
  static constexpr auto Fields() {
    using P = RigidPivotRotationConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "a rigid actor, or an articulated actor with link"},
        internal::ParamsField<P>{"link", &P::link, "the articulated actor\'s link acting as the body (-1: a rigid actor)"},
        internal::ParamsField<P>{"localRotation", &P::localRotation, "pivot frame R_ℓ in the body frame [w, x, y, z]"},
        internal::ParamsField<P>{"rotation", &P::rotation, "target R̂, world [w, x, y, z]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class RigidPivotRotationConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, RigidPivotRotationConstraintParams const& params,
                                            Error& error);
  RigidPivotRotationConstraint(internal::RigidBodySlot body, RigidPivotRotationConstraintParams const& params);

  Quat const& GetLocalRotation() const { return localRotation_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Quat localRotation_;
};

}  // namespace superdex
