// DeformableNodeToRigid — attaches a deformable node to a point of a rigid
// body (a soft body hanging from a handle, a rod end on a body).
//
//   g = T_R(r) − T_D(X + u) = t_R + R_R r − T_D(X + u)             m = 3, n = 9
//   J = [ −R_TD, I, −Hat(R_R r) ]
// Columns: the node's 3 DoFs (actor 0, the deformable one), then the rigid
// body's translation and rotation increment (actor 1). By default
// (fixToDeformablePos) the rigid-frame pivot r is computed at creation as
// R_Rᵀ(T_D(X + u) − t_R), so the constraint starts at zero deviation;
// otherwise r = localPos. Units: m, N/m, N·s/m.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}

class NodalActor;

struct DeformableNodeToRigidConstraintParams {
  ActorHandle deformableActor;        ///< a deformable actor
  ActorHandle rigidActor;             ///< a rigid actor, or an articulated actor with `rigidLink`
  int rigidLink = -1;                 ///< the link acting as the rigid body (−1: a rigid actor)
  int deformableNodeIndex = 0;        ///< node of the deformable actor
  bool fixToDeformablePos = true;     ///< r from the node's position at creation
  Real3 localPos = Real3::Zero();     ///< r in the rigid body frame when !fixToDeformablePos [m]
  real stiffness = 0;                 ///< k >= 0 [N/m]
  real damping = 0;                   ///< d >= 0 [N·s/m]
  real saturation = -1;               ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = T_R(r) - T_D(X + u) (m = 3, n = 9). By default (fix_to_deformable_pos) r is computed at creation so the constraint starts at zero deviation.";
  static constexpr auto Fields() {
    using P = DeformableNodeToRigidConstraintParams;
    return std::array{
        internal::ParamsField<P>{"deformableActor", &P::deformableActor, "a deformable or rod actor"},
        internal::ParamsField<P>{"rigidActor", &P::rigidActor, "a rigid actor, or an articulated actor with rigid_link"},
        internal::ParamsField<P>{"rigidLink", &P::rigidLink, "the articulated actor\'s link acting as the rigid body (-1: a rigid actor)"},
        internal::ParamsField<P>{"deformableNodeIndex", &P::deformableNodeIndex, "node of the deformable actor"},
        internal::ParamsField<P>{"fixToDeformablePos", &P::fixToDeformablePos, "r from the node's position at creation (default True)"},
        internal::ParamsField<P>{"localPos", &P::localPos, "r in the rigid body frame when not fix_to_deformable_pos [m]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class DeformableNodeToRigidConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, DeformableNodeToRigidConstraintParams const& params,
                                            Error& error);
  DeformableNodeToRigidConstraint(NodalActor* deformable, internal::RigidBodySlot rigid,
                                  DeformableNodeToRigidConstraintParams const& params);
  /// r, the pivot in the rigid body's frame.
  Real3 const& GetLocalPos() const { return localPos_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  NodalActor* deformable_;
  int node_;
  Real3 localPos_;
};

}  // namespace superdex
