// ArticulatedTreeSolver: H x = b in O(N) for a symmetric matrix with the
// block structure of an articulated actor's Hessian (issue 18; the
// derivation is in docs/articulated.md, "Solving on the tree").
//
// The DoFs are grouped by joint; joint i has numDofs[i] (0 to 6)
// consecutive DoFs from dofStart[i]. Parents come before their children
// (parent[i] < i, −1 for a root). Each joint has a reference point o_i; its
// motion columns S_i = motion.middleCols(dofStart[i], numDofs[i]) (angular
// rows first) and the 6×6 own_i are expressed about it, and shift[i] =
// o_i − o_parent(i). With X_i the motion transform from o_parent to o_i
// (v ← v − shift × ω), Y_i the composite over i's subtree about o_i,
//   Y_i = own_i + Σ_children X_cᵀ Y_c X_c,
// and S_j taken to o_i along the path, the matrix is
//   H_ii = sym(S_iᵀ Y_i S_i) + E_i   (E_i = jointExtras[i], symmetric)
//   H_ji = S_jᵀ Y_i S_i         for j a strict ancestor of i, H_ij = H_jiᵀ,
//   H_ji = 0                    for j and i on different branches.
// Y need not be symmetric (the articulated actor's kinematic curvature is
// not; sym(A) = (A + Aᵀ)/2, and S_iᵀ Z S_i below is symmetric, so the
// pivots keep the antisymmetric part of S_iᵀ Y_i S_i out). Local reference points keep the products at the scale of the links:
// about one far origin they cancel digits as the tree grows (a 1,500-link
// chain about the world origin gave a non-finite step).
//
// The solve eliminates the joints from the leaves up, as the articulated-
// body algorithm does: eliminating joint k subtracts
// Z_k = (Yᴬ_k S_k) Dₖ⁻¹ (Yᴬ_k S_k)ᵀ from every pair of its ancestors, so the
// structure is kept with the articulated Yᴬ_i = own_i + Σ_c X_cᵀ(Yᴬ_c − Z_c)X_c
// and the pivot Dᵢ = sym(S_iᵀ Yᴬ_i S_i) + E_i (never the difference of the large
// composite and eliminated terms). Back substitution runs from the roots
// down. Each joint costs a few 6×6 products and one Cholesky of at most 6×6:
// O(N), nothing formed densely.
//
// Factorize runs the elimination once per matrix; Solve then costs one
// leaves-up and one roots-down pass per right-hand side. With
// `makePositiveDefinite` each pivot Dᵢ is replaced by V max(|Λ|, floor) Vᵀ
// from its eigendecomposition (floor 1e-10 of H's largest diagonal entry,
// as the dense modified Cholesky's): the factors then belong to the positive definite
// H₊ = L D₊ Lᵀ, equal to H where every pivot was positive definite, which
// keeps the curvature's magnitude where it was not (a modified block
// Cholesky; docs/articulated.md, "Solving on the tree"). A modified
// eigenvalue is also raised so that what its direction v takes from the
// parent, u uᵀ / λ̃ with u = Yᴬ_i S_i v, stays below half the subtree's
// metric W_i (λ̃ ≥ 2 k uᵀ W_i⁻¹ u for k modified directions; Cauchy–Schwarz
// gives u uᵀ ≤ (uᵀ W⁻¹ u) W). Without that bound |λ| near zero turns the
// Schur update's sign into an arbitrarily large negative term, and on long
// chains the next pivots up grew by ~10³ per ten joints (Gill, Murray and
// Wright bound the factor L for the same reason).
//
// Allocation: Reserve(numJoints) sizes the workspaces; Factorize and Solve
// allocate nothing.
#pragma once

#include <superdex/core/types.h>

namespace superdex::internal {

/// the storage of a joint's kernel of M DoFs (Eigen::Dynamic: up to 6)
constexpr int Capacity(int m) { return m == Eigen::Dynamic ? 6 : m; }

class ArticulatedTreeSolver {
 public:
  using Matrix6 = Eigen::Matrix<real, 6, 6>;
  using Vector6 = Eigen::Matrix<real, 6, 1>;

  /// The structure and values of H (see the file comment). Spans over the
  /// joints, except motion (6 × numDofs) and b, x (numDofs).
  struct System {
    Span<int const> parent, dofStart, numDofs;
    Eigen::Ref<Eigen::Matrix<real, 6, Eigen::Dynamic> const> motion;
    Span<Matrix6 const> own;          ///< own_i of Y_i, about o_i
    Span<Matrix6 const> jointExtras;  ///< E_i in the top-left corner
    Span<Real3 const> shift;          ///< o_i − o_parent(i) (unused for roots)
    /// Optional, for `makePositiveDefinite`: each joint's positive definite
    /// metric W_i about o_i (the articulated actor's link inertia w·M),
    /// composited over subtrees to bound the modification (Factorize)
    Span<Matrix6 const> metric = {};
  };

  /// Xᵀ Y X for the motion transform X: v ← v − r × ω, the 6×6 about a
  /// point taken to the point r before it (a child's term to its parent).
  static Matrix6 ShiftToParent(Real3 const& r, Matrix6 const& y);

  void Reserve(int numJoints);

  /// Eliminates the joints from the leaves up. Returns false when a pivot
  /// block Dᵢ is not positive definite (H is not: Cholesky of the pivots is
  /// Cholesky of H by blocks), `failedJoint` then naming the joint; with
  /// `makePositiveDefinite` such pivots are modified instead (counted by
  /// GetNumModifiedPivots) and it fails only on non-finite values.
  /// With `modifications` (one per joint), each modified pivot's change
  /// D₊ᵢ − Dᵢ is written there (zero elsewhere): the factors are exactly
  /// those of H + blockdiag(D₊ᵢ − Dᵢ), the changes in each joint's E_i.
  bool Factorize(System const& system, bool makePositiveDefinite = false, int* failedJoint = nullptr,
                 Span<Matrix6> modifications = {});
  /// After Factorize without `makePositiveDefinite` failed on an indefinite
  /// pivot: finishes the factorization from that joint with it, the joints
  /// already eliminated kept (their pivots were positive definite, so a
  /// modified factorization would have left them as they are). The result is
  /// Factorize(system, true)'s; `system` is the one that failed, System::metric
  /// now given where the modification is to be bounded. Without a failed
  /// exact factorization to continue it is Factorize(system, true).
  bool ContinueModified(System const& system, int* failedJoint = nullptr);
  /// x = H⁻¹ b with the last factorization; `system` is the one factorized.
  void Solve(System const& system, Span<real const> b, Span<real> x);
  int GetNumModifiedPivots() const { return modifiedPivots_; }

 private:
  /// a joint's M × M pivot and 6 × M columns (M = Eigen::Dynamic: up to 6)
  template <int M>
  using Square = Eigen::Matrix<real, M, M, 0, Capacity(M), Capacity(M)>;
  template <int M>
  using Cols = Eigen::Matrix<real, 6, M, 0, 6, Capacity(M)>;
  template <int M>
  using Vec = Eigen::Matrix<real, M, 1, 0, Capacity(M), 1>;
  using Columns = Cols<Eigen::Dynamic>;
  /// The floor and the metric composites of a modification (Factorize's
  /// `makePositiveDefinite`): a pass over the tree that leaves articulated_ as it is.
  void PrepareModification(System const& system);
  /// Eliminates joints `first`, first − 1, …, 0 (Factorize's loop).
  bool EliminateFrom(System const& system, int first, bool makePositiveDefinite, Span<Matrix6> modifications,
                     int* failedJoint);
  /// Joint i's pivot, its factor into pivotFactor_ and Z_i out of `passed`, with
  /// kernels of M DoFs (1, 3, 6; Eigen::Dynamic for the others). False
  /// where the pivot is not positive definite (and not modified).
  /// `passed` holds Yᴬ_i on entry.
  template <int M>
  bool Eliminate(System const& system, int i, bool makePositiveDefinite, Span<Matrix6> modifications, Matrix6& passed);
  /// The modified pivot of joint i (Factorize's `makePositiveDefinite`).
  template <int M>
  void ModifyPivot(System const& system, int i, Square<M>& pivot);
  /// v ← Dᵢ⁻¹ v (m entries) with the kept factor.
  template <int M, class Vector>
  void PivotSolve(int i, int m, Vector& v) const;
  template <int M>
  void SolveUp(System const& system, int i, Span<real const> b, Span<real> x);
  template <int M>
  void SolveDown(System const& system, int i, Span<real> x);
  /// Σ over i's children c of X_cᵀ(Yᴬ_c − Z_c)X_c where childStamp_[i] ==
  /// stamp_ (none passed yet otherwise; Yᴬ_i = own_i + it): no pass copies
  /// own into it before each factorization
  DynamicArray<Matrix6> articulated_;
  DynamicArray<int> childStamp_;
  int stamp_ = 0;  ///< the factorization's stamp
  DynamicArray<Matrix6> metric_;       ///< the composite of System::metric over i's subtree
  DynamicArray<Columns> right_;        ///< Yᴬ_i S_i
  DynamicArray<Vector6> bias_;         ///< Σ over i's strict descendants of q_k = Yᴬ_k S_k Dₖ⁻¹ b̃_k
  DynamicArray<Vector6> motionSum_;    ///< back substitution: Σ over i and its ancestors of S_j x_j
  DynamicArray<Matrix6> pivotFactor_;  ///< Dᵢ's Cholesky factor Lᵢ in the top-left corner
  DynamicArray<Vector6> pivotReciprocal_;  ///< 1 / Lᵢ's diagonal
  DynamicArray<Matrix6> composite_;    ///< PrepareModification's composites Y_i (the floor's scale)
  real floor_ = 0;                     ///< the modification's eigenvalue floor
  int modifiedPivots_ = 0;
  int resumeJoint_ = -1;  ///< where the last exact Factorize failed (ContinueModified), −1 if none
};

}  // namespace superdex::internal
