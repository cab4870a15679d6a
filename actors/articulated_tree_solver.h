// ArticulatedTreeSolver: H x = b in O(N) for a symmetric matrix with the
// block structure of an articulated actor's Hessian (issue 18; the
// derivation is in docs/articulated.md, "Solving on the tree").
//
// The DoFs are grouped by joint; joint i has numDofs[i] (0 to 6)
// consecutive DoFs from dofStart[i], and world-frame motion columns
// S_i = motion.middleCols(dofStart[i], numDofs[i]) (angular rows first).
// Parents come before their children (parent[i] < i, −1 for a root). Then
//   H_ii  is any symmetric block (jointBlocks[i], top-left numDofs × numDofs)
//   H_ji = S_jᵀ Y_i S_i  for j a strict ancestor of i, H_ij = H_jiᵀ,
//   H_ji = 0             for j and i on different branches,
// with the 6×6 Y_i composite over i's subtree: Y_i = own_i + Σ_children Y_c.
// Y need not be symmetric (the articulated actor's kinematic curvature is
// not). The solve eliminates the joints from the leaves up, as the
// articulated-body algorithm does: eliminating joint k subtracts from every
// pair of its ancestors the 6×6 Z_k = (Yᴬ_k S_k) Dₖ⁻¹ (Yᴬ_k S_k)ᵀ, so the
// structure is kept with the articulated Yᴬ_i = own_i + Σ_c (Yᴬ_c − Z_c)
// and the pivot Dᵢ = H_ii − S_iᵀ (Σ over i's strict descendants of Z) S_i.
// Back substitution runs from the roots down. Each joint costs a few 6×6
// products and one Cholesky of at most 6×6: O(N), nothing formed densely.
//
// Allocation: Reserve(numJoints) sizes the workspaces; Solve allocates
// nothing.
#pragma once

#include <superdex/core/types.h>

namespace superdex::internal {

class ArticulatedTreeSolver {
 public:
  using Matrix6 = Eigen::Matrix<real, 6, 6>;
  using Vector6 = Eigen::Matrix<real, 6, 1>;

  /// The structure and values of H (see the file comment). Spans over the
  /// joints, except motion (6 × numDofs) and b, x (numDofs).
  struct System {
    Span<int const> parent, dofStart, numDofs;
    Eigen::Ref<Eigen::Matrix<real, 6, Eigen::Dynamic> const> motion;
    Span<Matrix6 const> own;          ///< own_i of Y_i
    Span<Matrix6 const> jointBlocks;  ///< H_ii in the top-left corner
  };

  void Reserve(int numJoints);

  /// Solves H x = b. Returns false, with x unspecified, when a pivot block
  /// Dᵢ is not positive definite (H is not: Cholesky of the pivots is
  /// Cholesky of H by blocks); `failedJoint` then names the joint.
  bool Solve(System const& system, Span<real const> b, Span<real> x, int* failedJoint = nullptr);

 private:
  using Pivot = Eigen::LLT<Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>>;
  DynamicArray<Matrix6> articulated_;  ///< Yᴬ_i
  DynamicArray<Matrix6> eliminated_;   ///< Σ over i's strict descendants of Z
  DynamicArray<Vector6> bias_;         ///< Σ over i's strict descendants of q_k = Yᴬ_k S_k Dₖ⁻¹ b̃_k
  DynamicArray<Vector6> motionSum_;    ///< back substitution: Σ over i and its ancestors of S_j x_j
  DynamicArray<Pivot> pivots_;
};

}  // namespace superdex::internal
