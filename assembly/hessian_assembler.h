// Two-phase assembly of the global Hessian (design.md §6).
//
// Analyze (topology changes only): from every contributor's DoF list build
// the block graph, order it (METIS), build the upper-triangle CSC pattern of
// P H Pᵀ, and precompute for every contributor the value slot of each entry
// of its local upper triangle. Bumps the pattern version.
//
// Assemble (every Newton iteration): ZeroValues, then each contributor adds
// its dense local block through its slot table: no search, no triplets, no
// sort, no allocation.
//
// Gradients stay in natural DoF order; PermuteToOrdered/PermuteToNatural map
// vectors between the two orders around the linear solve.
#pragma once

#include <cstdint>

#include <superdex/assembly/ordering.h>
#include <superdex/core/error.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/sparse_symmetric_matrix.h>

namespace superdex::internal {

class HessianAssembler {
 public:
  /// Builds pattern, ordering and slot tables. Every DoF list must hold
  /// distinct indices in [0, numDofs); the block sizes must add to numDofs.
  /// Returns false (and changes nothing) on a METIS failure or bad input.
  bool Analyze(int numDofs, DynamicArray<int> const& blockSizes,
               DynamicArray<DynamicArray<int>> const& contributorDofs, OrderingMethod method,
               Error& error);

  bool IsAnalyzed() const { return analyzed_; }
  int GetNumDofs() const { return matrix_.size; }
  int GetNumContributors() const { return static_cast<int>(contributorSize_.size()); }
  /// How many times Analyze built a pattern since construction.
  std::int64_t GetNumPatternBuilds() const { return numBuilds_; }

  void ZeroValues();
  /// Adds `relative` × |Hⱼⱼ| to every diagonal entry of the assembled values
  /// (a Levenberg shift, scaled per DoF).
  void ShiftDiagonal(real relative);

  /// Adds the symmetric local block `h` (n×n, n = the contributor's DoF
  /// count, in DoF-list order) of contributor `c`. Reads the upper triangle.
  template <class Derived>
  void AddBlock(int c, Eigen::MatrixBase<Derived> const& h) {
    int const n = contributorSize_[c];
    int const* slot = slots_.data() + slotStart_[c];
    real* values = matrix_.values.data();
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) values[*slot++] += h(a, b);
  }

  SparseSymmetricMatrix const& GetMatrix() const { return matrix_; }

  /// ordered[perm[i]] = natural[i]
  void PermuteToOrdered(Span<real const> natural, Span<real> ordered) const;
  /// natural[i] = ordered[perm[i]]
  void PermuteToNatural(Span<real const> ordered, Span<real> natural) const;

 private:
  bool analyzed_ = false;
  std::int64_t numBuilds_ = 0;
  SparseSymmetricMatrix matrix_;
  DynamicArray<int> permutation_;  ///< natural DoF → ordered position
  DynamicArray<int> contributorSize_;
  DynamicArray<int> slotStart_;
  DynamicArray<int> slots_;
};

}  // namespace superdex::internal
