// SinglePrecisionFactor: a copy of a supernodal Cholesky factor A = Pᵀ L Lᵀ P
// with L's values rounded to single precision, applied as a preconditioner.
//
// The reused-factor CG of a Newton stage (ReusedFactorCg) applies an earlier
// factorization M = Pᵀ L Lᵀ P as its preconditioner several times per Newton
// iteration. A pair of triangular solves reads every entry of L twice and
// does two multiply-adds per entry: on a volumetric mesh's factor (tens of
// MB to GB) it is bound by loads, not by arithmetic. With L's values stored
// as float the solves read half the bytes. The factor applied is
//
//   M̃ = Pᵀ L̃ L̃ᵀ P,   L̃ᵢⱼ = fl32(Lᵢⱼ),   |L̃ᵢⱼ − Lᵢⱼ| <= 2⁻²⁴ |Lᵢⱼ|,
//
// symmetric positive definite (L̃'s diagonal is positive); M̃ − M comes from a
// relative perturbation of L's entries of at most 6e-8, which moves the
// eigenvalues of M̃⁻¹A by about 6e-8 κ(L) = 6e-8 √κ(A) — far less, on a
// Hessian that is not near-singular, than the staleness of an earlier
// factorization that CG already absorbs (kMaxDiagonalSpread gives the bound
// in terms of L).
//
// Arithmetic: in double (SetFloatArithmetic(false): each float widened as
// it is loaded), Solve applies M̃⁻¹ exactly up to double round-off, a fixed
// SPD operator; in float (SetFloatArithmetic(true), what CholmodSolver uses:
// the vectors rounded too, and twice the lanes per instruction), it applies
// M̃⁻¹ up to a forward error of the same order as L's rounding, u κ(L) — a
// slightly nonlinear operator, for which ReusedFactorCg takes the
// Polak–Ribière β of flexible CG. Either way the Newton step is still the
// current Hessian's own, to the CG tolerance on its double-precision
// residual. Assign refuses (and the caller keeps the
// double-precision solve) when a value does not fit a float, or when the
// spread of L's diagonal says κ(L) >= kMaxDiagonalSpread, where single
// precision would cost CG iterations instead of saving time.
//
// Layout: CHOLMOD's supernodal factor (cholmod_factor with is_super): for
// supernode s, columns super[s] .. super[s+1]−1 of L, rows rows[rowStart[s]
// .. rowStart[s+1]) (its own columns first), values column-major from
// valueStart[s] with the number of rows as the leading dimension. The arrays
// are read where they are (the caller keeps them alive, unchanged, while
// this object is used); only the values are copied.
//
// Threads: the supernodal elimination tree is cut into disjoint subtrees of
// at most 1/kSubtreeTarget of L's entries each (the nodes above them, the
// top, are the separators nested dissection ends with), and the subtrees
// into kGroups contiguous groups of about equal size. The forward solve runs
// the groups concurrently on the executor's threads, each adding its updates
// of the top's rows into its own buffer; the buffers are summed in group
// order, then the top is solved on one thread. The backward solve runs the
// top first, then the groups concurrently. The split depends on L alone, so
// the result is bit-identical for any thread count. (Supernodes that are not
// in postorder, never the case for CHOLMOD with postorder on, are all top.)
//
// Allocation: Assign sizes the copy and the workspaces (reusing their
// capacity when the layout is the same); Solve allocates nothing.
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

#include <superdex/core/types.h>

namespace superdex::internal {

class ParallelExecutor;

/// CHOLMOD's supernodal layout (int indices), described above.
struct SupernodalLayout {
  int size = 0;                 ///< n, the order of L
  int numSupernodes = 0;
  int const* super = nullptr;       ///< numSupernodes + 1 column starts
  int const* rowStart = nullptr;    ///< numSupernodes + 1 starts in `rows` (L->pi)
  int const* valueStart = nullptr;  ///< numSupernodes + 1 starts in the values (L->px)
  int const* rows = nullptr;        ///< row indices (L->s)
  int const* permutation = nullptr; ///< P: L's column k is A's column permutation[k]; null = identity
  std::size_t numValues = 0;        ///< entries stored for L (L->xsize)
};

class SinglePrecisionFactor {
 public:
  /// The spread of L's diagonal, max Lⱼⱼ / min Lⱼⱼ (a lower bound of κ(L) =
  /// √κ(A)), at or above which Assign refuses. With |L̃ − L| <= u |L| (u =
  /// 2⁻²⁴), M⁻¹M̃ is similar to (I + F)(I + F)ᵀ with F = L⁻¹(L̃ − L),
  /// ‖F‖ ≲ u κ(L): at a spread of 1e4 that is 6e-4 or more, about the most
  /// that costs CG no iterations next to a stale factor's own error.
  static constexpr double kMaxDiagonalSpread = 1e4;

  /// Copies `values` (layout.numValues doubles) rounded to float. Returns
  /// false, leaving no usable copy, when a value is not finite as a float,
  /// a diagonal entry is not positive, or the diagonal spread reaches
  /// kMaxDiagonalSpread; GetReason says which.
  bool Assign(SupernodalLayout const& layout, double const* values);

  /// The threads of Solve (nullptr, the default: the calling thread). Set
  /// before Assign, which sizes a workspace per thread; the executor must
  /// outlive this object's use of it.
  void SetExecutor(ParallelExecutor const* executor) { executor_ = executor; }
  /// Solve in float arithmetic (the vectors rounded too) instead of double.
  /// Set before Assign.
  void SetFloatArithmetic(bool on) { floatArithmetic_ = on; }

  /// Subtrees are at most 1/kSubtreeTarget of L's stored entries.
  static constexpr int kSubtreeTarget = 64;
  /// Groups of subtrees run as tasks (and have a buffer for the top's rows).
  static constexpr int kGroups = 16;

  /// x = M̃⁻¹ b = Pᵀ L̃⁻ᵀ L̃⁻¹ P b, in double arithmetic. Requires a
  /// successful Assign; b and x have layout.size entries and may not overlap.
  void Solve(double const* b, double* x);

  bool IsAssigned() const { return assigned_; }
  /// max Lⱼⱼ / min Lⱼⱼ of the last Assign (0 before).
  double GetDiagonalSpread() const { return diagonalSpread_; }
  /// Why the last Assign returned false (empty after a success).
  /// (a fixed text: Assign runs once per factorization and allocates nothing)
  char const* GetReason() const { return reason_; }
  /// The split of the last Assign: the groups that run concurrently, and the
  /// columns of the top that run on one thread.
  int GetNumGroups() const { return numGroups_; }
  int GetNumTopColumns() const { return static_cast<int>(topColumns_.size()); }

 private:
  /// Supernode s: its first column, columns, rows, row indices, values
  /// (column-major) and the inverses of its diagonal.
  struct Supernode {
    int first, numCols, numRows;
    int const* rows;
    float const* block;
  };
  Supernode View(int s) const;
  void Partition();
  /// The solve's vectors, in the arithmetic's type T.
  template <class T>
  struct Workspace {
    std::vector<T> inverseDiagonal;  ///< 1 / L̃ⱼⱼ
    std::vector<T> permuted;         ///< P b, then the solution in L's order
    std::vector<T> block;            ///< per thread: one supernode's rows of the vector
    std::vector<T> groupBuffers;     ///< numGroups_ × top columns
  };
  template <class T>
  Workspace<T>& Work() {
    if constexpr (std::is_same_v<T, float>)
      return floatWork_;
    else
      return doubleWork_;
  }
  template <class T>
  void SolveIn(double const* b, double* x);
  template <class T>
  void ForwardSupernode(int s, T* w, T* topBuffer);
  template <class T>
  void BackwardSupernode(int s, T* w);
  template <class F>
  void RunGroups(F const& body) const;

  SupernodalLayout layout_;
  ParallelExecutor const* executor_ = nullptr;
  std::vector<float> values_;
  bool floatArithmetic_ = false;
  Workspace<double> doubleWork_;
  Workspace<float> floatWork_;
  int maxRows_ = 0;               ///< the most rows of a supernode (block_'s stride)
  int workspaceThreads_ = 1;      ///< threads block_ is sized for
  // the split (Partition)
  std::vector<int> columnSupernode_, parent_, firstDescendant_, subtreeSize_;
  std::vector<double> work_;  ///< entries of L in each supernode's subtree
  std::vector<int> childStart_, children_, nextChild_, pending_;
  std::vector<char> isTop_;
  std::vector<int> subtreeRoots_;          ///< ascending; subtree t is firstDescendant_[root] .. root
  std::vector<int> groupStart_;            ///< numGroups_ + 1 starts in subtreeRoots_
  int numGroups_ = 0;                      ///< groups with a subtree
  std::vector<int> topSupernodes_, topColumns_;
  std::vector<int> topIndex_;              ///< column -> its index in topColumns_, or -1
  double diagonalSpread_ = 0;
  bool assigned_ = false;
  char const* reason_ = "";
};

}  // namespace superdex::internal
