// DeformableNodeToDeformableNode — a spring between nodes of two deformable
// actors (or two nodes of different actors: stitching, attachments).
//
//   g = T_A(X_A + u_A) − T_B(X_B + u_B)                            m = 3, n = 6
//   J = [ R_TA, −R_TB ]   (columns: node A's 3 DoFs, node B's 3 DoFs)
// Units: m, N/m, N·s/m.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}

class NodalActor;

struct DeformableNodeToDeformableNodeConstraintParams {
  ActorHandle actorA;       ///< a deformable actor
  ActorHandle actorB;       ///< another deformable actor
  int nodeIndexA = 0;       ///< node of A
  int nodeIndexB = 0;       ///< node of B
  real stiffness = 0;       ///< k >= 0 [N/m]
  real damping = 0;         ///< d >= 0 [N·s/m]
  real saturation = -1;     ///< ḡ [m]; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = T_A(X_A + u_A) - T_B(X_B + u_B) (m = 3, n = 6).";
  static constexpr auto Fields() {
    using P = DeformableNodeToDeformableNodeConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actorA", &P::actorA, "a deformable or rod actor"},
        internal::ParamsField<P>{"actorB", &P::actorB, "another deformable or rod actor"},
        internal::ParamsField<P>{"nodeIndexA", &P::nodeIndexA, "node of A"},
        internal::ParamsField<P>{"nodeIndexB", &P::nodeIndexB, "node of B"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

class DeformableNodeToDeformableNodeConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, DeformableNodeToDeformableNodeConstraintParams const& params,
                                            Error& error);
  DeformableNodeToDeformableNodeConstraint(NodalActor* actorA, NodalActor* actorB,
                                           DeformableNodeToDeformableNodeConstraintParams const& params);

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;

  NodalActor* actorA_;
  NodalActor* actorB_;
  int nodeA_, nodeB_;
};

}  // namespace superdex
