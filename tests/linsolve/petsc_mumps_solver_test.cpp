// The MUMPS backend (petsc_mumps_solver.h) beyond the checks every backend
// gets (linear_solver_test): its answers against CHOLMOD's on the same
// matrices, the inertia that tells an indefinite or singular matrix, one
// MUMPS analysis per pattern, and values changed in place between
// factorizations.
#include <catch2/catch.hpp>

#include <cmath>

#include <superdex/linsolve/linear_solver.h>
#include <superdex/linsolve/reused_factor_cg.h>

#include "test_systems.h"

namespace superdex {
namespace {

using test::Laplacian2d;
using test::RelativeResidual;
using test::TestRhs;
using test::View;
using test::WithDiagonal;

bool Contains(std::string const& text, std::string const& part) {
  return text.find(part) != std::string::npos;
}

std::unique_ptr<LinearSolver> Make(LinearSolverType type) {
  Error error;
  std::unique_ptr<LinearSolver> solver = CreateLinearSolver(type, error);
  INFO(error.ToString());
  REQUIRE(solver);
  return solver;
}

VectorX SolveWith(LinearSolver& solver, SparseSymmetricMatrix const& a, VectorX const& b) {
  REQUIRE(solver.Analyze(a).Ok());
  LinearSolveResult const factored = solver.Factorize(a);
  INFO(factored.reason);
  REQUIRE(factored.Ok());
  VectorX x(a.size);
  REQUIRE(solver.Solve(View(b), View(x)).Ok());
  return x;
}

TEST_CASE("MUMPS and CHOLMOD solve the same systems to round-off", "[linsolve][mumps]") {
  auto const [name, a] = GENERATE(table<std::string, SparseSymmetricMatrix>(
      {{"2-D Laplacian 30 x 20", Laplacian2d(30, 20, 0.05)},
       {"interleaved chains", test::InterleavedChains(200)}}));
  CAPTURE(name);
  VectorX const b = TestRhs(a.size);
  std::unique_ptr<LinearSolver> mumps = Make(LinearSolverType::PetscMumps);
  std::unique_ptr<LinearSolver> cholmod = Make(LinearSolverType::Cholmod);
  VectorX const x = SolveWith(*mumps, a, b);
  VectorX const reference = SolveWith(*cholmod, a, b);
  CAPTURE(mumps->GetDescription());
  // both backward stable: the difference is κ(A) times round-off (κ < 1e3 here)
  REQUIRE((x - reference).norm() <= 1e-11 * reference.norm());
  REQUIRE(RelativeResidual(a, x, b) <= 1e-13);
  REQUIRE(Contains(mumps->GetDescription(), "MUMPS"));
  REQUIRE(Contains(mumps->GetDescription(), "ordering"));
}

TEST_CASE("MUMPS tells a matrix that is not positive definite by its inertia", "[linsolve][mumps]") {
  SparseSymmetricMatrix const a = Laplacian2d(12, 9, 0.01);
  std::unique_ptr<LinearSolver> solver = Make(LinearSolverType::PetscMumps);
  REQUIRE(solver->Analyze(a).Ok());
  VectorX const b = TestRhs(a.size);
  VectorX x(a.size);

  SECTION("negative pivots") {
    // two negative diagonal entries in a diagonally dominant rest: two
    // negative eigenvalues, so two negative pivots whatever the pivoting
    SparseSymmetricMatrix const indefinite = WithDiagonal(WithDiagonal(a, 5, -1), 70, -2);
    LinearSolveResult const result = solver->Factorize(indefinite);
    CAPTURE(result.reason);
    REQUIRE(result.status == LinearSolveStatus::NotPositiveDefinite);
    REQUIRE(result.failingColumn == -1);
    REQUIRE(Contains(result.reason, "2 negative"));
  }
  SECTION("a singular matrix: null pivots") {
    // a zero row and column: singular whatever the order and the pivoting
    SparseSymmetricMatrix singular = a;
    for (int j = 0; j < singular.size; ++j)
      for (int k = singular.colStart[j]; k < singular.colStart[j + 1]; ++k)
        if (singular.rowIndex[k] == 40 || j == 40) singular.values[k] = 0;
    LinearSolveResult const result = solver->Factorize(singular);
    CAPTURE(result.reason);
    REQUIRE(result.status == LinearSolveStatus::NotPositiveDefinite);
    REQUIRE(solver->Solve(View(b), View(x)).status == LinearSolveStatus::InvalidState);
  }
  // the same analysis recovers with SPD values
  LinearSolveResult const recovered = solver->Factorize(a);
  INFO(recovered.reason);
  REQUIRE(recovered.Ok());
  REQUIRE(solver->Solve(View(b), View(x)).Ok());
  REQUIRE(RelativeResidual(a, x, b) <= 1e-13);
}

TEST_CASE("MUMPS analyzes the pattern once and refactorizes new values in place", "[linsolve][mumps]") {
  SparseSymmetricMatrix a = Laplacian2d(20, 20, 0.1);
  std::unique_ptr<LinearSolver> solver = Make(LinearSolverType::PetscMumps);
  REQUIRE(solver->Analyze(a).Ok());
  REQUIRE(solver->GetNumObjectBuilds() == 1);
  // MUMPS's own analysis ran on the pattern
  double const nonzeros = solver->GetFactorNonzeros();
  REQUIRE(nonzeros >= a.size);
  VectorX const b = TestRhs(a.size);
  VectorX x(a.size);
  for (int round = 0; round < 4; ++round) {
    CAPTURE(round);
    for (real& v : a.values) v *= 1.5;  // new values, same pattern
    REQUIRE(solver->Factorize(a).Ok());
    REQUIRE(solver->GetFactorNonzeros() == nonzeros);
    REQUIRE(solver->Solve(View(b), View(x)).Ok());
    REQUIRE(RelativeResidual(a, x, b) <= 1e-13);
  }
  REQUIRE(solver->GetNumObjectBuilds() == 1);
  // a new pattern version: a new analysis
  a.patternVersion += 1;
  REQUIRE(solver->Analyze(a).Ok());
  REQUIRE(solver->GetNumObjectBuilds() == 2);
  REQUIRE(solver->Factorize(a).Ok());
}

TEST_CASE("a MUMPS factor preconditions CG on a later matrix of the same pattern", "[linsolve][mumps]") {
  // what Newton's reused factorizations do (ReusedFactorCg): the factor of
  // an earlier Hessian as the preconditioner of the current one
  SparseSymmetricMatrix const earlier = Laplacian2d(25, 25, 0.1);
  SparseSymmetricMatrix later = earlier;
  for (std::size_t k = 0; k < later.values.size(); ++k) later.values[k] *= 1 + 0.05 * std::sin(real(k));
  for (int j = 0; j < later.size; ++j) later.values[later.colStart[j + 1] - 1] += 0.2;  // stays SPD
  std::unique_ptr<LinearSolver> solver = Make(LinearSolverType::PetscMumps);
  REQUIRE(solver->Analyze(earlier).Ok());
  REQUIRE(solver->Factorize(earlier).Ok());
  VectorX const b = TestRhs(later.size);
  VectorX x = VectorX::Zero(later.size);
  internal::ReusedFactorCg cg;
  internal::ReusedFactorCg::Result const result =
      cg.Solve(later, *solver, View(b), View(x), 1e-12, 50);
  CAPTURE(result.iterations, result.relativeResidual);
  REQUIRE(result.status == internal::ReusedFactorCg::Status::Converged);
  REQUIRE(result.iterations >= 2);   // the factor is not the matrix's own
  REQUIRE(result.iterations <= 25);  // but close to it (16 measured)
  REQUIRE(RelativeResidual(later, x, b) <= 1e-11);
}

}  // namespace
}  // namespace superdex
