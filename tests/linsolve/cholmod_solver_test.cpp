// CHOLMOD backend specifics: the statistics it reports (nnz(L), flops), the
// ordering it was told to use, and the mapping of a failing column from
// CHOLMOD's postordered factor back to the caller's column order.
#include <algorithm>
#include <numeric>
#include <string>

#include <catch2/catch.hpp>

#include <superdex/linsolve/cholmod_solver.h>

#include "linsolve/test_systems.h"

namespace superdex::internal {
namespace {

using test::Laplacian2d;

TEST_CASE("CHOLMOD reports nnz(L), flops and what ran", "[linsolve][cholmod]") {
  CholmodSolver solver;
  REQUIRE(solver.GetOrdering() == CholmodOrdering::Given);
  REQUIRE(solver.GetFactorNonzeros() == -1);
  REQUIRE(solver.GetFactorFlops() == -1);
  REQUIRE(solver.GetDescription().find("not analyzed") != std::string::npos);

  SECTION("a tridiagonal matrix has no fill: nnz(L) = nnz(triu(A)) = 2 n - 1") {
    SparseSymmetricMatrix const a = Laplacian2d(50, 1, 0.1);
    REQUIRE(a.NumNonzeros() == 99);
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.GetFactorNonzeros() == 99);
    REQUIRE(solver.GetFactorFlops() > 0);
    REQUIRE(solver.GetFactorStoredEntries() >= solver.GetFactorNonzeros());
  }
  SECTION("a 2-D Laplacian in its natural order fills in") {
    SparseSymmetricMatrix const a = Laplacian2d(15, 15, 0.1);
    REQUIRE(solver.Analyze(a).Ok());
    // banded with bandwidth 15: L fills the band
    REQUIRE(solver.GetFactorNonzeros() > 2.0 * static_cast<double>(a.NumNonzeros()));
    REQUIRE(solver.GetFactorFlops() > solver.GetFactorNonzeros());
    REQUIRE(solver.Factorize(a).Ok());
    std::string const description = solver.GetDescription();
    CAPTURE(description);
    REQUIRE(description.find("CHOLMOD 3.") == 0);
    REQUIRE(description.find(solver.IsSupernodal() ? "supernodal LL'" : "simplicial LDL'") !=
            std::string::npos);
    REQUIRE(description.find("natural") != std::string::npos);
  }
  SECTION("a new pattern replaces the old analysis") {
    SparseSymmetricMatrix small = Laplacian2d(10, 1, 0.1);
    REQUIRE(solver.Analyze(small).Ok());
    REQUIRE(solver.GetFactorNonzeros() == 19);
    SparseSymmetricMatrix big = Laplacian2d(30, 1, 0.1);
    big.patternVersion = 2;
    REQUIRE(solver.Analyze(big).Ok());
    REQUIRE(solver.GetFactorNonzeros() == 59);
    REQUIRE(solver.GetAnalyzedPatternVersion() == 2);
    REQUIRE(solver.Factorize(big).Ok());
  }
}

TEST_CASE("CHOLMOD factors in the given order unless told otherwise", "[linsolve][cholmod]") {
  // the lexicographic 2-D Laplacian is a poor order: CHOLMOD's own (AMD or
  // METIS) finds much less fill, so equal counts would mean the option was
  // ignored
  SparseSymmetricMatrix const a = Laplacian2d(20, 20, 0.1);
  CholmodSolver given(CholmodOrdering::Given);
  CholmodSolver own(CholmodOrdering::CholmodDefault);
  REQUIRE(given.Analyze(a).Ok());
  REQUIRE(own.Analyze(a).Ok());
  CAPTURE(given.GetFactorNonzeros(), own.GetFactorNonzeros(), own.GetDescription());
  REQUIRE(own.GetFactorNonzeros() > 0);
  REQUIRE(own.GetFactorNonzeros() < 0.8 * given.GetFactorNonzeros());
  REQUIRE(own.GetDescription().find("natural") == std::string::npos);

  // both solve it
  for (CholmodSolver* solver : {&given, &own}) {
    REQUIRE(solver->Factorize(a).Ok());
    VectorX const b = test::TestRhs(a.size);
    VectorX x(a.size);
    REQUIRE(solver->Solve(test::View(b), test::View(x)).Ok());
    REQUIRE(test::RelativeResidual(a, x, b) <= 1e-10);
  }
}

TEST_CASE("CHOLMOD picks simplicial LDLᵀ for chains and supernodal LLᵀ for volumes",
          "[linsolve][cholmod]") {
  // flops / nnz(L): ~3 for a tridiagonal matrix, hundreds for a 3-D grid
  // (CHOLMOD's switch is 40); both kinds solve both systems
  SparseSymmetricMatrix const chain = Laplacian2d(400, 1, 0.1);
  SparseSymmetricMatrix const volume = test::Laplacian3d(12, 0.1);
  for (SparseSymmetricMatrix const* a : {&chain, &volume}) {
    for (CholmodFactorKind kind :
         {CholmodFactorKind::Auto, CholmodFactorKind::Supernodal, CholmodFactorKind::Simplicial}) {
      CholmodSolver solver(CholmodOrdering::CholmodDefault, kind);
      REQUIRE(solver.GetFactorKind() == kind);
      REQUIRE_FALSE(solver.IsSupernodal());
      REQUIRE(solver.Analyze(*a).Ok());
      bool const expectSupernodal = kind == CholmodFactorKind::Supernodal ||
                                    (kind == CholmodFactorKind::Auto && a == &volume);
      CAPTURE(a->size, static_cast<int>(kind), solver.GetDescription());
      REQUIRE(solver.IsSupernodal() == expectSupernodal);
      REQUIRE(solver.Factorize(*a).Ok());
      REQUIRE(solver.GetDescription().find(expectSupernodal ? "supernodal LL'" : "simplicial LDL'") !=
              std::string::npos);
      VectorX const b = test::TestRhs(a->size);
      VectorX x(a->size);
      REQUIRE(solver.Solve(test::View(b), test::View(x)).Ok());
      REQUIRE(test::RelativeResidual(*a, x, b) <= 1e-10);
    }
  }
}

TEST_CASE("CHOLMOD's failing column is mapped back through its postorder",
          "[linsolve][cholmod][indefinite]") {
  // simplicial LDLᵀ does not stop at a negative pivot: the backend finds the
  // first one itself, and must name the same column as LLᵀ
  CholmodFactorKind const kind =
      GENERATE(CholmodFactorKind::Auto, CholmodFactorKind::Supernodal, CholmodFactorKind::Simplicial);
  CAPTURE(static_cast<int>(kind));
  SparseSymmetricMatrix const a = test::InterleavedChains(40);
  CholmodSolver solver(CholmodOrdering::Given, kind);
  REQUIRE(solver.Analyze(a).Ok());

  // the postorder of two interleaved chains is not the identity, so a failing
  // column reported in L's order would differ from the caller's column
  DynamicArray<int> const perm = solver.GetFactorPermutation();
  REQUIRE(perm.size() == static_cast<std::size_t>(a.size));
  DynamicArray<int> sorted = perm;
  std::sort(sorted.begin(), sorted.end());
  DynamicArray<int> identity(a.size);
  std::iota(identity.begin(), identity.end(), 0);
  REQUIRE(sorted == identity);
  REQUIRE(perm != identity);

  int columnsThatMove = 0;
  for (int column = 0; column < a.size; ++column) {
    int const positionInL =
        static_cast<int>(std::find(perm.begin(), perm.end(), column) - perm.begin());
    if (positionInL != column) ++columnsThatMove;
    LinearSolveResult const result = solver.Factorize(test::WithDiagonal(a, column, -2));
    CAPTURE(column, positionInL, result.reason);
    REQUIRE(result.status == LinearSolveStatus::NotPositiveDefinite);
    REQUIRE(result.failingColumn == column);
  }
  REQUIRE(columnsThatMove > a.size / 2);
}

}  // namespace
}  // namespace superdex::internal
