// DenseCholeskySolver: the LinearSolver backend for tiny systems, a dense
// Cholesky factorization A = L L' (Eigen, blocked right-looking) in the
// caller's column order.
//
// For a few dozen unknowns the sparse machinery (symbolic structures,
// supernode bookkeeping, BLAS calls on tiny blocks) costs more than the
// O(n^3/3) dense factorization; docs/linear_solvers.md has the measurement
// behind kDenseSolverMaxSize.
//
// Analyze allocates the n x n dense matrix once; Factorize copies A's upper
// triangle into its lower triangle and factors in place; Solve does the two
// triangular solves in place in x. Neither Factorize nor Solve allocates.
#pragma once

#include <superdex/linsolve/linear_solver.h>

#include <string>

namespace superdex::internal {

class DenseCholeskySolver final : public LinearSolver {
 public:
  LinearSolverType GetType() const override { return LinearSolverType::Dense; }
  /// "dense Cholesky LL' (Eigen 3.4.0)".
  std::string GetDescription() const override;
  /// n (n + 1) / 2 after Analyze (L is stored dense), else -1.
  double GetFactorNonzeros() const override;
  /// n^3 / 3 + n^2 / 2 + n / 6 after Analyze, else -1.
  double GetFactorFlops() const override;

 protected:
  /// Allocates the n x n matrix. Never fails once the base checks passed.
  LinearSolveResult DoAnalyze(SparseSymmetricMatrix const& a) override;
  /// Copies A and factors it; NotPositiveDefinite with the first column
  /// whose pivot is <= 0 or not finite.
  LinearSolveResult DoFactorize(SparseSymmetricMatrix const& a) override;
  /// x = A^{-1} b with the factor of the last Factorize.
  LinearSolveResult DoSolve(Span<real const> b, Span<real> x) override;

 private:
  MatrixX factor_;  ///< lower triangle holds L after a successful Factorize
  int size_ = -1;   ///< -1 before Analyze
};

}  // namespace superdex::internal
