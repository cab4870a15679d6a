// IncompleteCholesky: the level-of-fill incomplete factorization IC(k),
// L D Lᵀ ≈ Â, of the Jacobi-scaled Â = S A S (S = diag(A)^-1/2, so Â has a
// unit diagonal), in reverse Cuthill–McKee order, with a bounded sequence of
// diagonal shifts where a pivot breaks down. The Icc and BlockJacobi
// preconditioners of the PCG backend apply it as M⁻¹ = S Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P S.
//
// Groups: the DoFs may be split into contiguous groups (block Jacobi); the
// entries that couple two groups are dropped, each group is ordered and
// factored on its own, with its own shift. One group is ICC of the whole
// matrix.
//
// Pattern: L's pattern holds the entries of level <= k, where A's entries
// have level 0 and the fill entry (i, j) that row i gets through a pivot m
// has level lev(i, m) + lev(m, j) + 1 (Saad, Iterative Methods for Sparse
// Linear Systems, 2nd ed., §10.3.3). On its pattern the factor matches the
// matrix: (L D Lᵀ)ᵢⱼ = Âᵢⱼ + α δᵢⱼ.
//
// Shifts: a group is factored as Â + α I with α = 0 first; where a pivot
// d_i <= kMinPivot (1 + α), or is not finite, the group is factored again
// with the next α of 1e-3, 1e-2, 1e-1, 1, each below the group's Gershgorin
// shift, and last with that shift, α_dd = (1 + 1e-3) max_i Σ_{j≠i} |Âᵢⱼ|
// − 1 (Manteuffel 1980's shifted incomplete factorization, the shifts
// relative to Â's unit diagonal). Â + α_dd I is strictly diagonally
// dominant: an H-matrix, whose incomplete factorizations exist in exact
// arithmetic (Meijerink and van der Vorst 1977; Manteuffel 1980). So a
// group takes at most six factorizations; where the last fails (round-off
// in a matrix singular to working precision) Factorize reports
// NotPositiveDefinite naming the column. PETSc's own ICC shift loop could
// repeat forever on such a matrix (tests/fuzz/findings).
//
// Allocation: Analyze sizes everything; Factorize and Apply allocate nothing.
#pragma once

#include <string>

#include <superdex/core/types.h>
#include <superdex/linsolve/sparse_symmetric_matrix.h>

namespace superdex::internal {

class IncompleteCholesky {
 public:
  /// A pivot is taken as broken down at or below this fraction of its
  /// shifted unit diagonal.
  static constexpr real kMinPivot = 1e-12;

  struct Result {
    bool ok = true;
    int failingColumn = -1;  ///< !ok: the column of A (caller's order)
    std::string reason;      ///< !ok: what failed
  };

  /// Symbolic analysis of A's pattern: the RCM order of each group, IC(levels)'s
  /// pattern, the map from A's entries to the factor. `groupSizes` splits the
  /// DoFs into contiguous groups (adding to a.size; empty: one group).
  /// Returns !ok when groupSizes do not add to a.size.
  Result Analyze(SparseSymmetricMatrix const& a, int levels, Span<int const> groupSizes);

  /// The factorization of A's values (A's pattern must be the analyzed one).
  /// !ok (and no usable factor) when a diagonal entry is not positive and
  /// finite, or a group breaks down at its last shift.
  Result Factorize(SparseSymmetricMatrix const& a);

  /// z = M⁻¹ r; r and z of size n may be the same array.
  void Apply(real const* r, real* z);

  int GetSize() const { return size_; }
  int GetNumGroups() const { return static_cast<int>(groupStart_.size()) - 1; }
  /// Strictly lower entries of L (the fill-in included).
  std::int64_t GetFactorOffDiagonals() const { return static_cast<std::int64_t>(uColumn_.size()); }
  /// The largest shift α any group needed in the last Factorize, and how
  /// many groups needed one.
  real GetLargestShift() const { return largestShift_; }
  int GetNumShiftedGroups() const { return numShiftedGroups_; }
  /// Factorizations of groups in the last Factorize (shifted retries included).
  int GetNumGroupFactorizations() const { return numGroupFactorizations_; }
  /// new → old: the DoF of A at position i of the factor's order.
  Span<int const> GetOrder() const { return order_; }

 private:
  /// Factors the rows [first, last) of the factor's order as Â + α I; returns
  /// the first broken-down row, or -1.
  int FactorRows(int first, int last, real shift);

  int size_ = 0;
  DynamicArray<int> order_;       ///< new → old
  DynamicArray<int> groupStart_;  ///< groups in the factor's order (same as in A's)
  /// L by columns (= Lᵀ by rows): column k holds rows uColumn_[uStart_[k] ..
  /// uStart_[k+1]), increasing, all > k; uValue_ the entries L(row, k)
  DynamicArray<int> uStart_, uColumn_;
  DynamicArray<real> uValue_, uInitial_;  ///< uInitial_: Â's value at each slot, 0 on fill
  /// L by rows: row i holds columns lColumn_[lStart_[i] .. lStart_[i+1]),
  /// increasing, all < i, whose values are uValue_[lSlot_[...]]
  DynamicArray<int> lStart_, lColumn_, lSlot_;
  DynamicArray<real> pivot_, inversePivot_;
  DynamicArray<real> scale_;  ///< S's diagonal, in A's order
  /// A's upper CSC entry k → its slot in uValue_, -1 for the diagonal and
  /// for entries between groups
  DynamicArray<int> entrySlot_;
  DynamicArray<int> diagonalEntry_;  ///< A's entry of each column's diagonal (A's order)
  DynamicArray<real> work_;
  DynamicArray<int> mark_;
  real largestShift_ = 0;
  int numShiftedGroups_ = 0;
  int numGroupFactorizations_ = 0;
};

/// The reverse Cuthill–McKee order (new → old) of the graph with adjacency
/// lists adjacency[adjacencyStart[v] .. adjacencyStart[v+1]) over the vertices
/// [first, last) (neighbours outside it are ignored): each connected
/// component from a pseudo-peripheral vertex (George and Liu 1979), the
/// neighbours of a vertex in increasing degree, the component's order
/// reversed. Appends the order to `order`.
void AppendReverseCuthillMcKee(Span<int const> adjacencyStart, Span<int const> adjacency,
                               int first, int last, DynamicArray<int>& order);

}  // namespace superdex::internal
