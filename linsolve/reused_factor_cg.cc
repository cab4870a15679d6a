#include <superdex/linsolve/reused_factor_cg.h>

#include <algorithm>
#include <cmath>

namespace superdex::internal {

void MultiplySymmetric(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) {
  int const n = a.size;
  int const* colStart = a.colStart.data();
  int const* rowIndex = a.rowIndex.data();
  real const* values = a.values.data();
  for (int j = 0; j < n; ++j) y[j] = 0;
  for (int j = 0; j < n; ++j) {
    // column j of the upper triangle: rows i < j, then the diagonal
    real const xj = x[j];
    real yj = 0;
    int const last = colStart[j + 1] - 1;
    for (int k = colStart[j]; k < last; ++k) {
      int const i = rowIndex[k];
      y[i] += values[k] * xj;
      yj += values[k] * x[i];
    }
    if (last >= colStart[j]) {
      if (rowIndex[last] == j)
        yj += values[last] * xj;
      else {  // no diagonal stored: the last entry is off-diagonal too
        y[rowIndex[last]] += values[last] * xj;
        yj += values[last] * x[rowIndex[last]];
      }
    }
    y[j] += yj;
  }
}

void MultiplySymmetricRows(SparseSymmetricMatrix const& a, int rowBegin, int rowEnd, Span<real const> x,
                           Span<real> y) {
  int const n = a.size;
  int const* colStart = a.colStart.data();
  int const* rowIndex = a.rowIndex.data();
  real const* values = a.values.data();
  for (int i = rowBegin; i < rowEnd; ++i) y[i] = 0;
  // columns left of the range hold rows i < j < rowBegin only: nothing to do
  for (int j = rowBegin; j < n; ++j) {
    int const first = colStart[j], end = colStart[j + 1];
    real const xj = x[j];
    if (j < rowEnd) {
      // an owned column: all of it for row j (the row of A is the column of
      // the symmetric A), and its rows inside the range
      real yj = 0;
      for (int k = first; k < end; ++k) {
        int const i = rowIndex[k];
        yj += values[k] * x[i];
        if (i != j && i >= rowBegin) y[i] += values[k] * xj;
      }
      y[j] += yj;
    } else {
      // right of the range: only its rows inside it (rows sorted in a column)
      int const* inside = std::lower_bound(rowIndex + first, rowIndex + end, rowBegin);
      for (int k = static_cast<int>(inside - rowIndex); k < end && rowIndex[k] < rowEnd; ++k)
        y[rowIndex[k]] += values[k] * xj;
    }
  }
}

void ReusedFactorCg::Multiply(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) const {
  if (product_ != nullptr)
    product_->Multiply(a, x, y);
  else
    MultiplySymmetric(a, x, y);
}

void ReusedFactorCg::Reserve(int size) {
  residual_.setZero(size);
  preconditioned_.setZero(size);
  direction_.setZero(size);
  productVector_.setZero(size);
  previousPreconditioned_.setZero(size);
}

ReusedFactorCg::Result ReusedFactorCg::Solve(SparseSymmetricMatrix const& a, LinearSolver& factor,
                                             Span<real const> b, Span<real> x, real relativeTolerance,
                                             int maxIterations, bool resume,
                                             StepTolerance const* stepTolerance,
                                             bool reducedPrecision) {
  int const n = a.size;
  if (residual_.size() != n) Reserve(n);
  Eigen::Map<VectorX> solution(x.data(), n);
  Eigen::Map<VectorX const> rhs(b.data(), n);
  Result result;
  real const rhsNorm = rhs.norm();
  if (rhsNorm == 0) {
    solution.setZero();
    result.status = Status::Converged;
    return result;
  }
  Span<real const> const residual(residual_.data(), n);
  Span<real> const preconditioned(preconditioned_.data(), n);
  Span<real const> const direction(direction_.data(), n);
  Span<real> const product(productVector_.data(), n);
  if (resume) {
    Multiply(a, Span<real const>(x.data(), n), product);
    residual_ = rhs - productVector_;
    result.relativeResidual = residual_.norm() / rhsNorm;
    if (result.relativeResidual <= relativeTolerance) {
      result.status = Status::Converged;
      return result;
    }
  } else {
    solution.setZero();
    residual_ = rhs;
  }
  auto precondition = [&] {
    LinearSolveResult const solved = factor.ApplyPreconditioner(residual, preconditioned, reducedPrecision);
    if (!solved.Ok()) {
      result.status = Status::PreconditionerFailed;
      result.reason = solved.reason;
    }
    ++result.iterations;
    result.reducedPrecision = solved.reducedPrecision;
    return solved.Ok();
  };

  // the next correction M⁻¹ r estimates x's error when M ≈ A
  auto const errorSmall = [&] {
    if (stepTolerance == nullptr) return false;
    real const* scale = stepTolerance->scales.data();
    for (int i = 0; i < n; ++i)
      if (scale[i] * std::abs(preconditioned_[i]) > stepTolerance->tolerance) return false;
    return true;
  };

  if (!precondition()) return result;
  if (resume && errorSmall()) {
    result.status = Status::Converged;
    return result;
  }
  direction_ = preconditioned_;
  real rz = residual_.dot(preconditioned_);
  for (;;) {
    Multiply(a, direction, product);
    real const curvature = direction_.dot(productVector_);
    if (!(curvature > 0) || !(rz > 0)) {
      result.status = Status::NonPositiveCurvature;
      result.relativeResidual = residual_.norm() / rhsNorm;
      return result;
    }
    real const alpha = rz / curvature;
    solution += alpha * direction_;
    residual_ -= alpha * productVector_;
    result.relativeResidual = residual_.norm() / rhsNorm;
    if (result.relativeResidual <= relativeTolerance) {
      result.status = Status::Converged;
      return result;
    }
    if (result.iterations >= maxIterations || !std::isfinite(result.relativeResidual)) {
      result.status = Status::NotConverged;
      return result;
    }
    if (reducedPrecision) previousPreconditioned_ = preconditioned_;
    if (!precondition()) return result;
    if (errorSmall()) {
      result.status = Status::Converged;
      return result;
    }
    real const rzNext = residual_.dot(preconditioned_);
    // Polak–Ribière β with a reduced-precision preconditioner (flexible CG:
    // M⁻¹ is then not exactly one linear operator; equal to Fletcher–Reeves
    // in exact arithmetic with a fixed one)
    real const beta =
        reducedPrecision ? (rzNext - residual_.dot(previousPreconditioned_)) / rz : rzNext / rz;
    direction_ = preconditioned_ + beta * direction_;
    rz = rzNext;
  }
}

}  // namespace superdex::internal
