#include <superdex/linsolve/dense_solver.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Cholesky>

namespace superdex::internal {

namespace {

LinearSolveResult NotPositiveDefinite(int column, std::string reason) {
  LinearSolveResult result;
  result.status = LinearSolveStatus::NotPositiveDefinite;
  result.failingColumn = column;
  result.reason = std::move(reason);
  return result;
}

}  // namespace

std::string DenseCholeskySolver::GetDescription() const {
  return "dense Cholesky LL' (Eigen " + std::to_string(EIGEN_WORLD_VERSION) + "." +
         std::to_string(EIGEN_MAJOR_VERSION) + "." + std::to_string(EIGEN_MINOR_VERSION) + ")";
}

double DenseCholeskySolver::GetFactorNonzeros() const {
  if (size_ < 0) return -1;
  double const n = size_;
  return n * (n + 1) / 2;
}

double DenseCholeskySolver::GetFactorFlops() const {
  if (size_ < 0) return -1;
  double const n = size_;
  return n * n * n / 3 + n * n / 2 + n / 6;
}

LinearSolveResult DenseCholeskySolver::DoAnalyze(SparseSymmetricMatrix const& a) {
  if (a.size > kDenseSolverMaxUnknowns) {
    LinearSolveResult result;
    result.status = LinearSolveStatus::InvalidInput;
    result.reason = "the dense solver takes at most kDenseSolverMaxUnknowns = " +
                    std::to_string(kDenseSolverMaxUnknowns) + " unknowns, got " + std::to_string(a.size) +
                    " (its factorization would cost " + std::to_string(static_cast<long long>(
                                                            double(a.size) * a.size * a.size / 3e9)) +
                    " Gflop per Newton iteration); use Cholmod or PetscPcg";
    return result;
  }
  size_ = a.size;
  factor_.resize(a.size, a.size);
  return {};
}

LinearSolveResult DenseCholeskySolver::DoFactorize(SparseSymmetricMatrix const& a) {
  // lower triangle of the dense matrix = transpose of A's stored upper
  // triangle; entries outside A's pattern are zero
  factor_.triangularView<Eigen::Lower>().setZero();
  for (int j = 0; j < size_; ++j) {
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
      factor_(j, a.rowIndex[k]) = a.values[k];
    }
  }

  // in-place blocked Cholesky on the lower triangle; returns the first
  // column whose pivot is <= 0, or -1
  Eigen::Index const failed = Eigen::internal::llt_inplace<real, Eigen::Lower>::blocked(factor_);
  if (failed >= 0) {
    return NotPositiveDefinite(static_cast<int>(failed),
                               "dense Cholesky: A is not positive definite: the pivot of column " +
                                   std::to_string(failed) + " is <= 0");
  }
  // a NaN pivot passes Eigen's "<= 0" test; with finite A it can only come
  // from overflow on a numerically singular matrix
  for (int j = 0; j < size_; ++j) {
    if (!std::isfinite(factor_(j, j))) {
      return NotPositiveDefinite(
          j, "dense Cholesky: the pivot of column " + std::to_string(j) +
                 " is not finite (overflow: A is numerically not positive definite)");
    }
  }
  return {};
}

LinearSolveResult DenseCholeskySolver::DoSolve(Span<real const> b, Span<real> x) {
  std::copy(b.begin(), b.end(), x.begin());
  Eigen::Map<VectorX> solution(x.data(), size_);
  // L y = b, then L' x = y
  auto const lower = factor_.triangularView<Eigen::Lower>();
  lower.solveInPlace(solution);
  lower.adjoint().solveInPlace(solution);
  return {};
}

}  // namespace superdex::internal
