// ReusedFactorCg: CG on a matrix preconditioned by the factorization of an
// earlier matrix of the same pattern (NewtonParams::reuseFactorization), and
// the symmetric product it runs on.
#include "test_support.h"
#include "test_systems.h"

#include <limits>

#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/linsolve/dense_solver.h>
#include <superdex/linsolve/reused_factor_cg.h>

using namespace superdex;
using internal::ReusedFactorCg;
using test::Laplacian2d;
using test::View;

namespace {

/// `a` with every value scaled by 1 + amplitude·sin(k): a nearby matrix of
/// the same pattern (SPD for a diagonally dominant `a` and amplitude < 1/3).
SparseSymmetricMatrix Perturbed(SparseSymmetricMatrix a, real amplitude) {
  for (std::size_t k = 0; k < a.values.size(); ++k) a.values[k] *= 1 + amplitude * std::sin(real(k));
  return a;
}

}  // namespace

TEST_CASE("MultiplySymmetric equals the product with the full matrix", "[linsolve][reuse]") {
  SparseSymmetricMatrix const a = test::RandomBlockSpd(12, 3, 0.3, 5);
  VectorX const x = test::TestRhs(a.size, 3);
  VectorX y(a.size);
  internal::MultiplySymmetric(a, View(x), View(y));
  VectorX const expected = test::Multiply(a, x);
  REQUIRE(expected.norm() > 0);
  CHECK((y - expected).norm() <= 1e-14 * expected.norm());
}

TEST_CASE("MultiplySymmetricRows forms a range of rows of the product, from the entries it may read",
          "[linsolve][reuse]") {
  SparseSymmetricMatrix const a = test::RandomBlockSpd(12, 3, 0.3, 7);
  int const n = a.size;
  VectorX const x = test::TestRhs(n, 4);
  VectorX const expected = test::Multiply(a, x);
  // the ranges of 1, 2 and 3 ranks, and an empty one
  // (plain ints, not structured bindings: the lambdas below capture them)
  std::pair<int, int> const range = GENERATE_COPY(std::pair{0, n}, std::pair{0, n / 2}, std::pair{n / 2, n},
                                                  std::pair{n / 3, 2 * n / 3}, std::pair{n / 3, n / 3});
  int const rowBegin = range.first, rowEnd = range.second;
  CAPTURE(rowBegin, rowEnd);
  // the entries with neither row nor column in the range are not read (a
  // rank holds them incomplete): poison them
  SparseSymmetricMatrix poisoned = a;
  int poisonedEntries = 0;
  auto const inRange = [&](int i) { return i >= rowBegin && i < rowEnd; };
  for (int j = 0; j < n; ++j)
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k)
      if (!inRange(j) && !inRange(a.rowIndex[k])) {
        poisoned.values[k] = std::numeric_limits<real>::quiet_NaN();
        ++poisonedEntries;
      }
  if (rowEnd - rowBegin < n) REQUIRE(poisonedEntries > 0);
  VectorX y = VectorX::Constant(n, -7.0);
  internal::MultiplySymmetricRows(poisoned, rowBegin, rowEnd, View(x), View(y));
  for (int i = 0; i < n; ++i) {
    CAPTURE(i);
    if (inRange(i))
      CHECK(std::abs(y[i] - expected[i]) <= 1e-14 * expected.norm());
    else
      CHECK(y[i] == -7.0);  // rows outside the range untouched
  }
}

TEST_CASE("CG with a reused factorization converges on a nearby matrix, to the requested residual",
          "[linsolve][reuse]") {
  SparseSymmetricMatrix const old = Laplacian2d(30, 30, 0.1);
  std::unique_ptr<LinearSolver> factor = GENERATE(1, 2) == 1
                                             ? std::unique_ptr<LinearSolver>(new internal::CholmodSolver())
                                             : std::unique_ptr<LinearSolver>(new internal::DenseCholeskySolver());
  CAPTURE(factor->GetDescription());
  REQUIRE(factor->Analyze(old).Ok());
  REQUIRE(factor->Factorize(old).Ok());
  VectorX const b = test::TestRhs(old.size);
  VectorX x(old.size);
  ReusedFactorCg cg;
  cg.Reserve(old.size);

  SECTION("the factorized matrix itself: one iteration") {
    ReusedFactorCg::Result const r = cg.Solve(old, *factor, View(b), View(x), 1e-10, 10);
    CHECK(r.status == ReusedFactorCg::Status::Converged);
    CHECK(r.iterations == 1);
    CHECK(test::RelativeResidual(old, x, b) <= 1e-10);
  }
  SECTION("a matrix 20 % away: a few iterations, residual checked independently") {
    SparseSymmetricMatrix const now = Perturbed(old, 0.2);
    ReusedFactorCg::Result const r = cg.Solve(now, *factor, View(b), View(x), 1e-10, 50);
    CAPTURE(r.iterations, r.relativeResidual);
    REQUIRE(r.status == ReusedFactorCg::Status::Converged);
    CHECK(r.iterations > 1);
    CHECK(r.iterations < 30);
    CHECK(test::RelativeResidual(now, x, b) <= 2e-10);
  }
  SECTION("a loose solve resumed to a tight tolerance: the tight answer, from where it stopped") {
    SparseSymmetricMatrix const now = Perturbed(old, 0.2);
    ReusedFactorCg::Result const loose = cg.Solve(now, *factor, View(b), View(x), 1e-2, 50);
    REQUIRE(loose.status == ReusedFactorCg::Status::Converged);
    CHECK(test::RelativeResidual(now, x, b) > 1e-10);
    ReusedFactorCg::Result const tight =
        cg.Solve(now, *factor, View(b), View(x), 1e-10, 50, /*resume=*/true);
    REQUIRE(tight.status == ReusedFactorCg::Status::Converged);
    CHECK(test::RelativeResidual(now, x, b) <= 2e-10);
    // a cold tight solve needs more iterations than the resumption
    VectorX cold(old.size);
    ReusedFactorCg::Result const fromZero = cg.Solve(now, *factor, View(b), View(cold), 1e-10, 50);
    CAPTURE(loose.iterations, tight.iterations, fromZero.iterations);
    CHECK(tight.iterations < fromZero.iterations);
    // resuming a solve that already meets the tolerance changes nothing
    VectorX const before = x;
    ReusedFactorCg::Result const again =
        cg.Solve(now, *factor, View(b), View(x), 1e-8, 50, /*resume=*/true);
    CHECK(again.status == ReusedFactorCg::Status::Converged);
    CHECK(again.iterations == 0);
    CHECK(x == before);
  }
  SECTION("a step tolerance stops CG once M⁻¹ r, the error estimate, is below it") {
    SparseSymmetricMatrix const now = Perturbed(old, 0.2);
    VectorX exact(old.size);
    REQUIRE(cg.Solve(now, *factor, View(b), View(exact), 1e-14, 100).status ==
            ReusedFactorCg::Status::Converged);
    VectorX const scales = VectorX::LinSpaced(old.size, 0.5, 2.0);
    real const largest = scales.cwiseProduct(exact).cwiseAbs().maxCoeff();
    for (real fraction : {1e-2, 1e-4, 1e-6}) {
      ReusedFactorCg::StepTolerance const step{View(scales), fraction * largest};
      ReusedFactorCg::Result const r =
          cg.Solve(now, *factor, View(b), View(x), 1e-14, 100, false, &step);
      real const error = scales.cwiseProduct(x - exact).cwiseAbs().maxCoeff();
      CAPTURE(fraction, r.iterations, r.relativeResidual, error / largest);
      REQUIRE(r.status == ReusedFactorCg::Status::Converged);
      CHECK(r.relativeResidual > 1e-14);  // stopped by the step tolerance
      // M⁻¹ r estimates the error within the spread of M⁻¹ A's spectrum
      CHECK(error <= 3 * step.tolerance);
    }
  }
  SECTION("an iteration cap below what it needs: NotConverged") {
    SparseSymmetricMatrix const now = Perturbed(old, 0.3);
    ReusedFactorCg::Result const r = cg.Solve(now, *factor, View(b), View(x), 1e-14, 2);
    CHECK(r.status == ReusedFactorCg::Status::NotConverged);
    CHECK(r.iterations == 2);
    CHECK(r.relativeResidual > 1e-14);
  }
  SECTION("an indefinite matrix: negative curvature is reported") {
    // the factor's own matrix with its sign flipped: pᵀ A p < 0 at once
    SparseSymmetricMatrix negative = old;
    for (real& v : negative.values) v = -v;
    ReusedFactorCg::Result const r = cg.Solve(negative, *factor, View(b), View(x), 1e-10, 50);
    CHECK(r.status == ReusedFactorCg::Status::NonPositiveCurvature);
  }
  SECTION("a zero right-hand side: x = 0 without iterations") {
    VectorX const zero = VectorX::Zero(old.size);
    x.setOnes();
    ReusedFactorCg::Result const r = cg.Solve(old, *factor, View(zero), View(x), 1e-10, 10);
    CHECK(r.status == ReusedFactorCg::Status::Converged);
    CHECK(r.iterations == 0);
    CHECK(x.isZero(0));
  }
}
