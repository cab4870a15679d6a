// Factorize and Solve must not allocate (style habit 3). This executable
// records every heap allocation of the process by interposing malloc, calloc,
// realloc, the aligned allocators and the global operator new (all
// forwarding to glibc's allocator), with the address of the caller, so an
// allocation can be attributed to SuperDex's own code (libsuperdex, Eigen
// inlined into it) or to a library it calls (CHOLMOD, libgomp, OpenBLAS).
// It is a separate executable so that the interposition touches no other test.
#include <dlfcn.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <memory>
#include <new>

#include <catch2/catch.hpp>

#include <superdex/core/parallel.h>
#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/linsolve/dense_solver.h>
#include <superdex/linsolve/incomplete_cholesky.h>
#include <superdex/linsolve/linear_solver.h>

#include "allocation_recorder.h"
#include "linsolve/test_systems.h"

namespace superdex {
namespace {

using test::Allocations;
using test::CountAllocations;

TEST_CASE("the allocation counter sees and attributes allocations", "[linsolve][allocation]") {
  // guards the tests below against an interposition that silently counts
  // nothing: a call into libsuperdex that allocates a vector and a string
  Allocations const counts = CountAllocations([] {
    DynamicArray<LinearSolverType> const types = AvailableLinearSolvers();
    REQUIRE(!types.empty());
    Error error;
    auto solver = CreateLinearSolver(LinearSolverType::Auto, error);
    REQUIRE(error);
  });
  CAPTURE(counts.total, counts.superdex);
  REQUIRE(counts.superdex >= 2);
  REQUIRE(counts.total >= counts.superdex);
}

TEST_CASE("Factorize and Solve do not allocate", "[linsolve][allocation]") {
  // a system below the dense threshold and one above it
  int const size = GENERATE(30, 120);
  CAPTURE(size);
  SparseSymmetricMatrix const a = test::RandomBlockSpd(size / 6, 6, 0.3, 5);
  REQUIRE(a.size == size);
  VectorX const b = test::TestRhs(a.size);
  VectorX x(a.size);
  Span<real const> const bView = test::View(b);
  Span<real> const xView = test::View(x);

  SECTION("dense: nothing at all") {
    internal::DenseCholeskySolver solver;
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    REQUIRE(solver.Solve(bView, xView).Ok());
    LinearSolveResult factorized, solved;
    Allocations const factorize = CountAllocations([&] { factorized = solver.Factorize(a); });
    Allocations const solve = CountAllocations([&] { solved = solver.Solve(bView, xView); });
    REQUIRE(factorized.Ok());
    REQUIRE(solved.Ok());
    CHECK(factorize.total == 0);
    CHECK(solve.total == 0);
  }
  SECTION("CHOLMOD: nothing from SuperDex, nothing in Solve after the first") {
    internal::CholmodSolver solver;
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    LinearSolveResult factorized, solved;
    // the first Solve after Analyze allocates CHOLMOD's solve workspaces
    Allocations const firstSolve = CountAllocations([&] { solved = solver.Solve(bView, xView); });
    REQUIRE(solved.Ok());
    REQUIRE(firstSolve.total > 0);
    Allocations const solve = CountAllocations([&] { solved = solver.Solve(bView, xView); });
    REQUIRE(solved.Ok());
    CHECK(solve.total == 0);

    Allocations const factorize = CountAllocations([&] { factorized = solver.Factorize(a); });
    REQUIRE(factorized.Ok());
    CHECK(factorize.superdex == 0);
    // cholmod_factorize allocates itself: the transpose of the upper triangle,
    // the supernode update matrix, libgomp's team for each (serialised)
    // OpenMP region per supernode, OpenBLAS's threaded SYRK job arrays
    // a simplicial factor is analyzed on the permuted matrix itself
    // (CholmodSolver::FoldOrder): cholmod_factorize transposes nothing and
    // allocates nothing after the first call
    if (!solver.IsSupernodal()) CHECK(factorize.total == 0);
    WARN("cholmod_factorize: " << factorize.total << " heap allocations per call, n = " << size
                               << ", " << solver.GetDescription());
  }
  SECTION("CHOLMOD's single-precision copy: made and applied without allocating after the first") {
    // a supernodal factor on 2 threads: the copy, its tree split and the
    // per-thread workspaces are sized at the first reduced-precision
    // application after the first Factorize, and only reused after that
    internal::ParallelExecutor executor;
    executor.SetNumThreads(2);
    internal::CholmodSolver solver(internal::CholmodOrdering::CholmodDefault,
                                   internal::CholmodFactorKind::Supernodal);
    solver.SetParallelExecutor(&executor);
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    REQUIRE(solver.ApplyPreconditioner(bView, xView, true).Ok());
    REQUIRE(solver.UsesSinglePrecisionPreconditioner());
    LinearSolveResult factorized, applied;
    REQUIRE(solver.Factorize(a).Ok());
    // the copy of the new factorization (Assign) and its application
    Allocations const copyAndApply =
        CountAllocations([&] { applied = solver.ApplyPreconditioner(bView, xView, true); });
    REQUIRE(applied.Ok());
    REQUIRE(applied.reducedPrecision);
    CHECK(copyAndApply.total == 0);
    Allocations const apply = CountAllocations([&] { applied = solver.ApplyPreconditioner(bView, xView, true); });
    REQUIRE(applied.Ok());
    CHECK(apply.total == 0);
  }
  SECTION("incomplete Cholesky (Icc, BlockJacobi): nothing at all, shifted retries included") {
    // fill levels 1 and two groups; Kershaw-like trouble is not needed: a
    // negative off-diagonal scaled up breaks the unshifted factorization
    SparseSymmetricMatrix broken = a;
    for (int j = 0; j < broken.size; ++j)
      for (int k = broken.colStart[j]; k < broken.colStart[j + 1] - 1; ++k) broken.values[k] *= 3;
    int const groups[] = {a.size / 2, a.size - a.size / 2};
    internal::IncompleteCholesky factor;
    REQUIRE(factor.Analyze(a, 1, groups).ok);
    REQUIRE(factor.Factorize(a).ok);
    internal::IncompleteCholesky::Result factored, shifted;
    Allocations const factorize = CountAllocations([&] { factored = factor.Factorize(a); });
    Allocations const apply = CountAllocations([&] { factor.Apply(b.data(), x.data()); });
    Allocations const retries = CountAllocations([&] { shifted = factor.Factorize(broken); });
    REQUIRE(factored.ok);
    REQUIRE(shifted.ok);
    CAPTURE(factor.GetNumGroupFactorizations());
    REQUIRE(factor.GetNumGroupFactorizations() > 2);
    CHECK(factorize.total == 0);
    CHECK(apply.total == 0);
    CHECK(retries.total == 0);
  }
}

}  // namespace
}  // namespace superdex
