// SinglePrecisionFactor through CholmodSolver::ApplyPreconditioner: a
// supernodal factor applied from L rounded to float (in float arithmetic, as
// CholmodSolver runs it) is within float rounding of A⁻¹ and of symmetric,
// refused where L does not fit a float or A is too ill-conditioned, and CG
// preconditioned by it converges to the same double-precision residual; in
// double arithmetic it is exactly the SPD (PᵀL̃L̃ᵀP)⁻¹.
#include <cmath>
#include <limits>
#include <string>

#include <catch2/catch.hpp>

#include <superdex/core/parallel.h>
#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/linsolve/reused_factor_cg.h>
#include <superdex/linsolve/single_precision_factor.h>

#include "linsolve/test_systems.h"

namespace superdex::internal {
namespace {

using test::Laplacian3d;
using test::View;

/// Float's unit round-off, 2⁻²⁴.
constexpr real kFloatRoundOff = 5.9604644775390625e-8;

SparseSymmetricMatrix Scaled(SparseSymmetricMatrix a, real factor) {
  for (real& value : a.values) value *= factor;
  return a;
}

TEST_CASE("a single-precision supernodal factor applies L̃⁻ᵀL̃⁻¹ within float rounding of A⁻¹",
          "[linsolve][cholmod][single]") {
  // 3-D Laplacian + 0.5 I: 1728 unknowns, κ = (12 + 0.5) / 0.5 ≈ 25 at most;
  // supernodal by construction. Both the given order and CHOLMOD's own
  // (a permutation P that the solve applies) are checked.
  auto const ordering = GENERATE(CholmodOrdering::Given, CholmodOrdering::CholmodDefault);
  CAPTURE(int(ordering));
  SparseSymmetricMatrix const a = Laplacian3d(12, 0.5);
  CholmodSolver solver(ordering, CholmodFactorKind::Supernodal);
  REQUIRE(solver.Analyze(a).Ok());
  REQUIRE(solver.Factorize(a).Ok());
  REQUIRE(solver.IsSupernodal());
  REQUIRE(solver.UsesSinglePrecisionPreconditioner());

  VectorX const b = test::TestRhs(a.size, 11);
  VectorX exact(a.size), reduced(a.size);
  REQUIRE(solver.Solve(View(b), View(exact)).Ok());
  REQUIRE(solver.ApplyPreconditioner(View(b), View(reduced), true).Ok());
  real const difference = (reduced - exact).norm() / exact.norm();
  CAPTURE(difference);
  // L̃ = L (1 + O(u_s)): the solution moves by about u_s κ(A) (25 here);
  // 4 u_s κ bounds it, and the float copy must have changed something
  CHECK(difference <= 4 * kFloatRoundOff * 25);
  CHECK(difference > 1e-3 * kFloatRoundOff);
  // the residual of A x̃ = b is of the same size, not double round-off
  CHECK(test::RelativeResidual(a, reduced, b) <= 4 * kFloatRoundOff * 25);

  SECTION("the operator is symmetric to float round-off (float arithmetic)") {
    VectorX const c = test::TestRhs(a.size, 12);
    VectorX reducedC(a.size);
    REQUIRE(solver.ApplyPreconditioner(View(c), View(reducedC), true).Ok());
    real const left = c.dot(reduced), right = b.dot(reducedC);
    REQUIRE(std::abs(left) > 0);
    CAPTURE(left, right);
    CHECK(std::abs(left - right) <= 4 * kFloatRoundOff * 25 * b.norm() * reducedC.norm());
  }
  SECTION("without reducedPrecision it is Solve, bit for bit") {
    VectorX again(a.size);
    REQUIRE(solver.ApplyPreconditioner(View(b), View(again), false).Ok());
    CHECK(again == exact);
  }
  SECTION("a new factorization replaces the copy") {
    SparseSymmetricMatrix const doubled = Scaled(a, 2);
    REQUIRE(solver.Factorize(doubled).Ok());
    VectorX half(a.size);
    REQUIRE(solver.ApplyPreconditioner(View(b), View(half), true).Ok());
    // (2A)⁻¹ b = x / 2: scaling by 2 is exact in float, so the copy is L √2
    // rounded; compare with the same tolerance as above
    CHECK((2 * half - exact).norm() <= 4 * kFloatRoundOff * 25 * exact.norm());
  }
}

TEST_CASE("the single-precision solve on several threads is bit-identical to one thread",
          "[linsolve][cholmod][single][threads]") {
  // CHOLMOD's own nested-dissection order: an elimination tree with many
  // subtrees below the top separators
  SparseSymmetricMatrix const a = Laplacian3d(14, 0.5);
  VectorX const b = test::TestRhs(a.size, 15);
  VectorX reference(a.size);
  for (int threads : {1, 2, 3, 8}) {
    CAPTURE(threads);
    ParallelExecutor executor;
    executor.SetNumThreads(threads);
    CholmodSolver solver(CholmodOrdering::CholmodDefault, CholmodFactorKind::Supernodal);
    solver.SetParallelExecutor(&executor);
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    REQUIRE(solver.UsesSinglePrecisionPreconditioner());
    VectorX x(a.size);
    // twice: the second call reuses every workspace
    REQUIRE(solver.ApplyPreconditioner(View(b), View(x), true).Ok());
    REQUIRE(solver.ApplyPreconditioner(View(b), View(x), true).Ok());
    if (threads == 1) {
      reference = x;
      VectorX exact(a.size);
      REQUIRE(solver.Solve(View(b), View(exact)).Ok());
      REQUIRE((x - exact).norm() <= 4 * kFloatRoundOff * 25 * exact.norm());
    } else {
      CHECK(x == reference);
    }
  }
}

TEST_CASE("the tree split covers every supernode once, in double and float arithmetic",
          "[linsolve][single]") {
  // a hand-made supernodal layout: two leaves (columns 0-1 and 2-3), each
  // with rows in the root (column 4), and the root; L = the Cholesky factor
  // of a known matrix, so the solve can be checked against a dense one
  // (columns: 0 1 | 2 3 | 4)
  Eigen::Matrix<real, 5, 5> full;
  full << 4, 1, 0, 0, 1,  //
      1, 5, 0, 0, 1,      //
      0, 0, 6, 2, 1,      //
      0, 0, 2, 7, 1,      //
      1, 1, 1, 1, 9;
  Eigen::Matrix<real, 5, 5> const lower = full.llt().matrixL();
  int const super[] = {0, 2, 4, 5};
  int const rowStart[] = {0, 3, 6, 7};
  int const rows[] = {0, 1, 4, 2, 3, 4, 4};
  int const valueStart[] = {0, 6, 12, 13};
  std::vector<double> values(13);
  for (int s = 0; s < 3; ++s)
    for (int j = super[s]; j < super[s + 1]; ++j)
      for (int r = rowStart[s]; r < rowStart[s + 1]; ++r)
        values[valueStart[s] + (j - super[s]) * (rowStart[s + 1] - rowStart[s]) + (r - rowStart[s])] =
            rows[r] >= j ? lower(rows[r], j) : 0.0;
  SupernodalLayout layout;
  layout.size = 5;
  layout.numSupernodes = 3;
  layout.super = super;
  layout.rowStart = rowStart;
  layout.valueStart = valueStart;
  layout.rows = rows;
  layout.numValues = values.size();
  auto const [threads, floatArithmetic] = GENERATE(table<int, bool>({{1, false}, {2, false}, {1, true}, {2, true}}));
  CAPTURE(threads, floatArithmetic);
  {
    ParallelExecutor executor;
    executor.SetNumThreads(threads);
    SinglePrecisionFactor factor;
    factor.SetExecutor(&executor);
    factor.SetFloatArithmetic(floatArithmetic);
    REQUIRE(factor.Assign(layout, values.data()));
    // each leaf is more than 1/64 of the entries: the root is split off,
    // and the two leaves run as two groups
    CHECK(factor.GetNumGroups() == 2);
    CHECK(factor.GetNumTopColumns() == 1);
    Eigen::Matrix<real, 5, 1> const b(1, -2, 3, 0.5, 2);
    Eigen::Matrix<real, 5, 1> x;
    factor.Solve(b.data(), x.data());
    Eigen::Matrix<real, 5, 1> const exact = full.llt().solve(b);
    CHECK((x - exact).norm() <= 1e-6 * exact.norm());
    CHECK((x - exact).norm() > 0);
    if (!floatArithmetic) {
      // double arithmetic: M̃⁻¹ = (PᵀL̃L̃ᵀP)⁻¹ exactly, symmetric to round-off
      Eigen::Matrix<real, 5, 5> inverse;
      for (int i = 0; i < 5; ++i) {
        Eigen::Matrix<real, 5, 1> const unit = Eigen::Matrix<real, 5, 1>::Unit(i);
        Eigen::Matrix<real, 5, 1> column;
        factor.Solve(unit.data(), column.data());
        inverse.col(i) = column;
      }
      CHECK((inverse - inverse.transpose()).norm() <= 1e-15 * inverse.norm());
    }
  }
}

TEST_CASE("the single-precision copy is refused where it would not pay or not fit",
          "[linsolve][cholmod][single]") {
  VectorX const b = test::TestRhs(Laplacian3d(10, 0.5).size, 13);
  auto const refusedMeansSolve = [&](SparseSymmetricMatrix const& a) {
    CholmodSolver solver(CholmodOrdering::Given, CholmodFactorKind::Supernodal);
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    REQUIRE(solver.IsSupernodal());
    CHECK_FALSE(solver.UsesSinglePrecisionPreconditioner());
    VectorX exact(a.size), applied(a.size);
    REQUIRE(solver.Solve(View(b), View(exact)).Ok());
    REQUIRE(solver.ApplyPreconditioner(View(b), View(applied), true).Ok());
    CHECK(applied == exact);
  };
  SECTION("entries of L beyond float's range (A scaled by 1e80: L ~ 1e40)") {
    refusedMeansSolve(Scaled(Laplacian3d(10, 0.5), 1e80));
  }
  SECTION("a diagonal spread of L >= 1e4: one row and column scaled by 1e5") {
    SparseSymmetricMatrix a = Laplacian3d(10, 0.5);
    // column 0 holds only its diagonal (it is the first column of the upper
    // triangle); scale it, and its row entries in later columns
    for (int j = 0; j < a.size; ++j)
      for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k)
        if (a.rowIndex[k] == 0 || j == 0) a.values[k] *= (j == 0 && a.rowIndex[k] == 0) ? 1e10 : 1e5;
    refusedMeansSolve(a);
  }
  SECTION("a simplicial factor always solves in double") {
    SparseSymmetricMatrix const a = Laplacian3d(10, 0.5);
    CholmodSolver solver(CholmodOrdering::Given, CholmodFactorKind::Simplicial);
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    CHECK_FALSE(solver.UsesSinglePrecisionPreconditioner());
    VectorX exact(a.size), applied(a.size);
    REQUIRE(solver.Solve(View(b), View(exact)).Ok());
    REQUIRE(solver.ApplyPreconditioner(View(b), View(applied), true).Ok());
    CHECK(applied == exact);
  }
}

TEST_CASE("CG preconditioned by the single-precision copy reaches the double-precision residual",
          "[linsolve][cholmod][single][reuse]") {
  SparseSymmetricMatrix const old = Laplacian3d(12, 0.5);
  CholmodSolver solver(CholmodOrdering::Given, CholmodFactorKind::Supernodal);
  REQUIRE(solver.Analyze(old).Ok());
  REQUIRE(solver.Factorize(old).Ok());
  REQUIRE(solver.UsesSinglePrecisionPreconditioner());
  // the next Newton Hessian: the same pattern, values 10 % away
  SparseSymmetricMatrix now = old;
  for (std::size_t k = 0; k < now.values.size(); ++k) now.values[k] *= 1 + 0.1 * std::sin(real(k));
  VectorX const b = test::TestRhs(old.size, 14);
  ReusedFactorCg cg;
  cg.Reserve(old.size);
  VectorX xDouble(old.size), xSingle(old.size);
  ReusedFactorCg::Result const inDouble =
      cg.Solve(now, solver, View(b), View(xDouble), 1e-12, 100, false, nullptr, false);
  ReusedFactorCg::Result const inSingle =
      cg.Solve(now, solver, View(b), View(xSingle), 1e-12, 100, false, nullptr, true);
  CAPTURE(inDouble.iterations, inSingle.iterations, inSingle.relativeResidual);
  REQUIRE(inDouble.status == ReusedFactorCg::Status::Converged);
  REQUIRE(inSingle.status == ReusedFactorCg::Status::Converged);
  // the answer is judged by its own double-precision residual
  CHECK(test::RelativeResidual(now, xSingle, b) <= 1e-12);
  CHECK((xSingle - xDouble).norm() <= 1e-10 * xDouble.norm());
  // staleness dominates float rounding: no more than one extra iteration
  CHECK(inSingle.iterations <= inDouble.iterations + 1);
}

}  // namespace
}  // namespace superdex::internal
