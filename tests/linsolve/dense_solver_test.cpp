// Dense backend specifics: reported statistics, and the failing column on
// both of Eigen's code paths (unblocked below 32 unknowns, blocked above).
#include <string>

#include <catch2/catch.hpp>

#include <superdex/linsolve/dense_solver.h>

#include "linsolve/test_systems.h"

namespace superdex::internal {
namespace {

TEST_CASE("the dense solver reports its statistics", "[linsolve][dense]") {
  DenseCholeskySolver solver;
  REQUIRE(solver.GetFactorNonzeros() == -1);
  REQUIRE(solver.GetFactorFlops() == -1);
  REQUIRE(solver.Analyze(test::Laplacian2d(10, 1, 0.1)).Ok());
  REQUIRE(solver.GetFactorNonzeros() == 55);
  REQUIRE(solver.GetFactorFlops() == Approx(1000.0 / 3 + 50 + 10.0 / 6));
  REQUIRE(solver.GetDescription().find("Eigen 3.") != std::string::npos);
}

TEST_CASE("the dense solver's failing column on both code paths", "[linsolve][dense][indefinite]") {
  int const size = GENERATE(5, 31, 32, 200);
  int const column = GENERATE(0, 4);
  CAPTURE(size, column);
  for (int failing : {column, size - 1 - column}) {
    CAPTURE(failing);
    SparseSymmetricMatrix const a = test::Laplacian2d(size, 1, 0.1);
    DenseCholeskySolver solver;
    REQUIRE(solver.Analyze(a).Ok());
    LinearSolveResult const result = solver.Factorize(test::WithDiagonal(a, failing, -0.5));
    REQUIRE(result.status == LinearSolveStatus::NotPositiveDefinite);
    REQUIRE(result.failingColumn == failing);
  }
}

}  // namespace
}  // namespace superdex::internal
