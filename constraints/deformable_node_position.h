// DeformableNodePosition — pins a node of a deformable actor to a target
// (boundary conditions: a shell corner, the base of a soft body).
//
//   g = T(X + u) − p̂                                             m = 3, n = 3
//   J = R_T      (columns: the node's 3 displacement DoFs)
// Target p̂ (world, m) set with SetTargetPosition. Units: m, N/m, N·s/m.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}

class NodalActor;

struct DeformableNodePositionConstraintParams {
  ActorHandle actor;                ///< a deformable actor
  int nodeIndex = 0;                ///< in [0, number of nodes)
  Real3 position = Real3::Zero();   ///< target p̂, world [m]
  real stiffness = 0;               ///< k >= 0 [N/m]
  real damping = 0;                 ///< d >= 0 [N·s/m]
  real saturation = -1;             ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "Pins a node of a deformable or rod actor: g = T(X + u) - p̂ (m = 3, n = 3).";
  static constexpr auto Fields() {
    using P = DeformableNodePositionConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "a deformable or rod actor"},
        internal::ParamsField<P>{"nodeIndex", &P::nodeIndex, "in [0, number of nodes)"},
        internal::ParamsField<P>{"position", &P::position, "target p̂, world [m]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class DeformableNodePositionConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, DeformableNodePositionConstraintParams const& params,
                                            Error& error);
  DeformableNodePositionConstraint(NodalActor* actor,
                                   DeformableNodePositionConstraintParams const& params);
  int GetNodeIndex() const { return node_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;

  NodalActor* actor_;
  int node_;
};

}  // namespace superdex
