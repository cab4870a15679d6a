// The LinearSolver interface through every compiled-in backend: one
// conformance test on the same SPD systems, analysis reuse, the state
// machine's refusals, typed failures, and the factory functions.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include <catch2/catch.hpp>

#include <superdex/core/config.h>
#include <superdex/linsolve/linear_solver.h>

#include "linsolve/test_systems.h"

namespace superdex {
namespace {

using test::Laplacian2d;
using test::Laplacian3d;
using test::RandomBlockSpd;
using test::RelativeResidual;
using test::TestRhs;
using test::View;
using test::WithDiagonal;

constexpr real kResidualTol = 1e-10;

/// A backend to test: a direct type, or PETSc PCG with one preconditioner at
/// rtol 1e-12 (so that its answers meet kResidualTol too).
struct Backend {
  LinearSolverType type = LinearSolverType::Dense;
  PcgParams pcg;

  bool IsIterative() const { return type == LinearSolverType::PetscPcg; }
  /// MUMPS factors with pivoting (LDLᵀ): it tells a matrix that is not
  /// positive definite by the factor's inertia, without a column
  bool ReportsFailingColumn() const { return !IsIterative() && type != LinearSolverType::PetscMumps; }
  std::string Name() const {
    std::string name(ToString(type));
    if (IsIterative()) name += " + " + std::string(ToString(pcg.preconditioner));
    return name;
  }
};

DynamicArray<Backend> DirectBackends() {
  DynamicArray<Backend> backends;
  for (LinearSolverType type : AvailableLinearSolvers())
    if (type != LinearSolverType::PetscPcg) backends.push_back({type, {}});
  return backends;
}

DynamicArray<Backend> AllBackends() {
  DynamicArray<Backend> backends = DirectBackends();
  DynamicArray<LinearSolverType> const types = AvailableLinearSolvers();
  if (std::find(types.begin(), types.end(), LinearSolverType::PetscPcg) == types.end())
    return backends;
  for (PcgPreconditioner preconditioner : AvailablePcgPreconditioners()) {
    Backend backend{LinearSolverType::PetscPcg, {}};
    backend.pcg.preconditioner = preconditioner;
    backend.pcg.relativeTolerance = 1e-12;
    backends.push_back(backend);
  }
  return backends;
}

std::unique_ptr<LinearSolver> MakeSolver(Backend const& backend) {
  Error error;
  std::unique_ptr<LinearSolver> solver = CreateLinearSolver(backend.type, backend.pcg, error);
  INFO(error.ToString());
  REQUIRE(solver != nullptr);
  REQUIRE(!error);
  REQUIRE(solver->GetType() == backend.type);
  REQUIRE(solver->IsIterative() == backend.IsIterative());
  return solver;
}

/// Block-tridiagonal chain of numBodies 6-DoF bodies, each joint coupling two
/// neighbours by a dense 12 x 12 J' K J (J 6 x 12): the shape of a rigid chain.
SparseSymmetricMatrix RigidChain(int numBodies, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<real> uniform(-1, 1);
  test::UpperEntries e(6 * numBodies);
  for (int i = 0; i < 6 * numBodies; ++i) e.Add(i, i, 1 + 0.5 * std::abs(uniform(rng)));
  for (int body = 0; body + 1 < numBodies; ++body) {
    Eigen::Matrix<real, 6, 12> jacobian;
    for (Eigen::Index k = 0; k < jacobian.size(); ++k) jacobian.data()[k] = uniform(rng);
    Eigen::Matrix<real, 12, 12> const local = 100 * jacobian.transpose() * jacobian;
    for (int r = 0; r < 12; ++r) {
      for (int c = r; c < 12; ++c) e.Add(6 * body + r, 6 * body + c, local(r, c));
    }
  }
  return e.ToMatrix();
}

// Analyze, Factorize and Solve `a` with a fresh solver of `type`; the answer
// must have a relative residual <= kResidualTol.
void CheckSolves(Backend const& backend, SparseSymmetricMatrix const& a) {
  REQUIRE(a.size > 0);
  REQUIRE(a.NumNonzeros() >= a.size);
  std::unique_ptr<LinearSolver> solver = MakeSolver(backend);

  LinearSolveResult result = solver->Analyze(a);
  INFO(result.reason);
  REQUIRE(result.Ok());
  REQUIRE(solver->IsAnalyzed());
  result = solver->Factorize(a);
  INFO(result.reason);
  REQUIRE(result.Ok());

  VectorX const b = TestRhs(a.size);
  VectorX x = VectorX::Constant(a.size, std::numeric_limits<real>::quiet_NaN());
  result = solver->Solve(View(b), View(x));
  INFO(result.reason);
  REQUIRE(result.Ok());
  REQUIRE(result.failingColumn == -1);
  if (backend.IsIterative()) {
    REQUIRE(result.iterations >= 1);
    REQUIRE(result.relativeResidual <= backend.pcg.relativeTolerance);
  }

  REQUIRE(b.norm() > 0);
  REQUIRE(x.allFinite());
  REQUIRE(x.norm() > 0);
  real const residual = RelativeResidual(a, x, b);
  CAPTURE(solver->GetDescription(), a.size, residual);
  REQUIRE(residual <= kResidualTol);
  REQUIRE(!solver->GetDescription().empty());

  // Resume from a finite starting point reaches the same solution (direct
  // backends solve anew; iterative ones continue from it)
  VectorX resumed = VectorX::Constant(a.size, 3.0);
  result = solver->Resume(View(b), View(resumed));
  INFO(result.reason);
  REQUIRE(result.Ok());
  REQUIRE(RelativeResidual(a, resumed, b) <= kResidualTol);
  if (backend.IsIterative()) {
    REQUIRE(solver->GetNumObjectBuilds() == 1);
  } else {
    REQUIRE(solver->GetFactorNonzeros() >= a.size);
    // (MUMPS counts no elimination flops for a 1 x 1 system)
    if (a.size > 1)
      REQUIRE(solver->GetFactorFlops() > 0);
    else
      REQUIRE(solver->GetFactorFlops() >= 0);
  }
}

TEST_CASE("every backend solves the same SPD systems", "[linsolve][conformance]") {
  Backend const type = GENERATE(from_range(AllBackends()));
  CAPTURE(type.Name());

  SECTION("2-D Laplacian 12 x 9 + 0.01 I") {
    CheckSolves(type, Laplacian2d(12, 9, 0.01));
  }
  SECTION("3-D Laplacian 6^3 + 0.01 I") {
    CheckSolves(type, Laplacian3d(6, 0.01));
  }
  SECTION("random sparse SPD, 3 x 3 blocks") {
    CheckSolves(type, RandomBlockSpd(40, 3, 0.1, 1));
  }
  SECTION("random sparse SPD, 6 x 6 blocks") {
    CheckSolves(type, RandomBlockSpd(25, 6, 0.15, 2));
  }
  SECTION("rigid chain, 20 bodies") {
    CheckSolves(type, RigidChain(20, 3));
  }
  SECTION("1 x 1") {
    test::UpperEntries e(1);
    e.Add(0, 0, 2.5);
    CheckSolves(type, e.ToMatrix());
  }
}

TEST_CASE("one analysis serves many factorizations", "[linsolve][reuse]") {
  Backend const backend = GENERATE(from_range(AllBackends()));
  CAPTURE(backend.Name());
  std::unique_ptr<LinearSolver> solver = MakeSolver(backend);

  SparseSymmetricMatrix const base = RandomBlockSpd(20, 6, 0.2, 11);
  SparseSymmetricMatrix a = base;
  REQUIRE(solver->Analyze(a).Ok());
  REQUIRE(solver->GetAnalyzedPatternVersion() == a.patternVersion);

  VectorX previous = VectorX::Zero(a.size);
  for (int iteration = 0; iteration < 5; ++iteration) {
    CAPTURE(iteration);
    // new values on the same pattern: A_t = (1 + t/2) A + t^2/4 I stays SPD
    // and changes the solution's direction through the shift
    real const scale = 1 + 0.5 * iteration;
    real const shift = 0.25 * iteration * iteration;
    for (std::size_t k = 0; k < a.values.size(); ++k) a.values[k] = scale * base.values[k];
    for (int j = 0; j < a.size; ++j) a.values[a.colStart[j + 1] - 1] += shift;

    LinearSolveResult result = solver->Factorize(a);
    INFO(result.reason);
    REQUIRE(result.Ok());
    REQUIRE(solver->GetAnalyzedPatternVersion() == a.patternVersion);

    // two right-hand sides per factorization
    for (unsigned seed : {1u, 2u}) {
      VectorX const b = TestRhs(a.size, seed);
      VectorX x(a.size);
      result = solver->Solve(View(b), View(x));
      INFO(result.reason);
      REQUIRE(result.Ok());
      real const residual = RelativeResidual(a, x, b);
      CAPTURE(seed, residual);
      REQUIRE(residual <= kResidualTol);
      if (seed == 1u) {
        // a stale factor would give the previous solution
        REQUIRE((x - previous).norm() > 1e-3 * x.norm());
        previous = x;
      }
    }
  }
}

TEST_CASE("calls out of order are refused with InvalidState", "[linsolve][state]") {
  Backend const backend = GENERATE(from_range(AllBackends()));
  CAPTURE(backend.Name());
  std::unique_ptr<LinearSolver> solver = MakeSolver(backend);

  SparseSymmetricMatrix a = Laplacian2d(5, 4, 0.1);
  a.patternVersion = 7;
  VectorX const b = TestRhs(a.size);
  VectorX x = VectorX::Zero(a.size);

  auto const requireInvalidState = [](LinearSolveResult const& result) {
    CAPTURE(ToString(result.status), result.reason);
    REQUIRE(result.status == LinearSolveStatus::InvalidState);
    REQUIRE(!result.Ok());
    REQUIRE(!result.reason.empty());
  };

  SECTION("Factorize before Analyze") {
    requireInvalidState(solver->Factorize(a));
    REQUIRE(!solver->IsAnalyzed());
  }
  SECTION("Solve before Analyze") {
    requireInvalidState(solver->Solve(View(b), View(x)));
  }
  SECTION("Solve after Analyze but before Factorize") {
    REQUIRE(solver->Analyze(a).Ok());
    requireInvalidState(solver->Solve(View(b), View(x)));
  }
  SECTION("Factorize with another pattern version, and Solve after it") {
    REQUIRE(solver->Analyze(a).Ok());
    REQUIRE(solver->Factorize(a).Ok());
    SparseSymmetricMatrix rebuilt = a;
    rebuilt.patternVersion = 8;
    requireInvalidState(solver->Factorize(rebuilt));
    // the old factor is no longer trusted
    requireInvalidState(solver->Solve(View(b), View(x)));
    // the analysis itself is kept: the analyzed version still factorizes
    REQUIRE(solver->IsAnalyzed());
    REQUIRE(solver->GetAnalyzedPatternVersion() == 7);
    REQUIRE(solver->Factorize(a).Ok());
    REQUIRE(solver->Solve(View(b), View(x)).Ok());
  }
  SECTION("a pattern changed without a new version") {
    REQUIRE(solver->Analyze(a).Ok());
    SparseSymmetricMatrix bigger = Laplacian2d(5, 5, 0.1);
    bigger.patternVersion = a.patternVersion;
    requireInvalidState(solver->Factorize(bigger));
  }
  SECTION("Solve after a new Analyze needs a new Factorize") {
    REQUIRE(solver->Analyze(a).Ok());
    REQUIRE(solver->Factorize(a).Ok());
    REQUIRE(solver->Solve(View(b), View(x)).Ok());
    REQUIRE(solver->Analyze(a).Ok());
    requireInvalidState(solver->Solve(View(b), View(x)));
  }
  SECTION("Solve after a failed Factorize") {
    REQUIRE(solver->Analyze(a).Ok());
    REQUIRE(solver->Factorize(a).Ok());
    // a non-finite value fails every backend's Factorize
    LinearSolveResult const failed =
        solver->Factorize(WithDiagonal(a, 3, std::numeric_limits<real>::infinity()));
    REQUIRE(failed.status == LinearSolveStatus::InvalidInput);
    requireInvalidState(solver->Solve(View(b), View(x)));
    if (!backend.IsIterative()) {
      REQUIRE(solver->Factorize(a).Ok());
      REQUIRE(solver->Factorize(WithDiagonal(a, 3, -1)).status ==
              LinearSolveStatus::NotPositiveDefinite);
      requireInvalidState(solver->Solve(View(b), View(x)));
    }
  }
}

TEST_CASE("bad input is refused with InvalidInput", "[linsolve][input]") {
  Backend const backend = GENERATE(from_range(AllBackends()));
  CAPTURE(backend.Name());
  std::unique_ptr<LinearSolver> solver = MakeSolver(backend);

  SparseSymmetricMatrix const a = Laplacian2d(4, 4, 0.1);
  auto const requireInvalidInput = [](LinearSolveResult const& result) {
    CAPTURE(ToString(result.status), result.reason);
    REQUIRE(result.status == LinearSolveStatus::InvalidInput);
    REQUIRE(!result.reason.empty());
  };

  SECTION("malformed patterns") {
    SparseSymmetricMatrix missingDiagonal = a;
    missingDiagonal.rowIndex[missingDiagonal.colStart[2] - 1] = 0;  // column 1: rows {0, 0}
    requireInvalidInput(solver->Analyze(missingDiagonal));
    REQUIRE(!solver->IsAnalyzed());

    SparseSymmetricMatrix lowerEntry = a;
    lowerEntry.rowIndex[0] = 3;  // column 0 holds row 3 > 0
    requireInvalidInput(solver->Analyze(lowerEntry));

    SparseSymmetricMatrix shortColStart = a;
    shortColStart.colStart.pop_back();
    requireInvalidInput(solver->Analyze(shortColStart));

    SparseSymmetricMatrix negativeSize = a;
    negativeSize.size = -1;
    requireInvalidInput(solver->Analyze(negativeSize));
  }
  SECTION("DoF blocks that do not cover the unknowns") {
    // MUMPS and the dense solver accepted them
    SparseSymmetricMatrix blocks = a;  // 16 unknowns
    blocks.blockSizes = {4, 4, 4};
    LinearSolveResult result = solver->Analyze(blocks);
    requireInvalidInput(result);
    REQUIRE(result.reason == "Analyze: A.blockSizes must add up to A.size = 16 (or be empty), got 12");
    blocks.blockSizes = {4, 4, 4, 4, 0};
    result = solver->Analyze(blocks);
    requireInvalidInput(result);
    REQUIRE(result.reason == "Analyze: A.blockSizes[4] = 0 must be >= 1");
    REQUIRE(!solver->IsAnalyzed());
    blocks.blockSizes = {4, 4, 4, 4};
    REQUIRE(solver->Analyze(blocks).Ok());
  }
  SECTION("values of the wrong length or not finite") {
    REQUIRE(solver->Analyze(a).Ok());
    SparseSymmetricMatrix shortValues = a;
    shortValues.values.pop_back();
    requireInvalidInput(solver->Factorize(shortValues));

    SparseSymmetricMatrix nanValue = a;
    nanValue.values[5] = std::numeric_limits<real>::quiet_NaN();
    requireInvalidInput(solver->Factorize(nanValue));
  }
  SECTION("b and x of the wrong size, overlapping, or b not finite") {
    REQUIRE(solver->Analyze(a).Ok());
    REQUIRE(solver->Factorize(a).Ok());
    VectorX b = TestRhs(a.size);
    VectorX x(a.size);
    VectorX shortVector(a.size - 1);
    requireInvalidInput(solver->Solve(View(shortVector), View(x)));
    requireInvalidInput(solver->Solve(View(b), View(shortVector)));

    VectorX both(a.size + 1);
    requireInvalidInput(
        solver->Solve(Span<real const>(both.data(), a.size), Span<real>(both.data() + 1, a.size)));

    b[3] = std::numeric_limits<real>::infinity();
    requireInvalidInput(solver->Solve(View(b), View(x)));

    // the factor survives refused solves
    VectorX const goodB = TestRhs(a.size);
    REQUIRE(solver->Solve(View(goodB), View(x)).Ok());
    REQUIRE(RelativeResidual(a, x, goodB) <= kResidualTol);
  }
}

TEST_CASE("a matrix that is not positive definite reports its failing column",
          "[linsolve][indefinite]") {
  Backend const backend = GENERATE(from_range(DirectBackends()));
  CAPTURE(backend.Name());
  std::unique_ptr<LinearSolver> solver = MakeSolver(backend);

  // With A(k, k) <= 0 and the rest strictly diagonally dominant, every
  // elimination order fails exactly at column k: the columns eliminated
  // before k form an SPD principal submatrix, and k's pivot is at most
  // A(k, k). 108 unknowns also take Eigen's blocked path (>= 32).
  auto const [name, a] = GENERATE(table<std::string, SparseSymmetricMatrix>(
      {{"2-D Laplacian 12 x 9", Laplacian2d(12, 9, 0.01)},
       {"interleaved chains", test::InterleavedChains(40)}}));
  CAPTURE(name);
  REQUIRE(solver->Analyze(a).Ok());

  VectorX const b = TestRhs(a.size);
  VectorX x(a.size);
  for (int column : {0, 1, 17, 38, a.size - 1}) {
    for (real diagonal : {-1.0, 0.0}) {
      CAPTURE(column, diagonal);
      LinearSolveResult const result = solver->Factorize(WithDiagonal(a, column, diagonal));
      CAPTURE(result.reason);
      REQUIRE(result.status == LinearSolveStatus::NotPositiveDefinite);
      REQUIRE(result.failingColumn == (backend.ReportsFailingColumn() ? column : -1));
      REQUIRE(!result.reason.empty());
      REQUIRE(solver->Solve(View(b), View(x)).status == LinearSolveStatus::InvalidState);
    }
    // the same analysis recovers with SPD values
    REQUIRE(solver->Factorize(a).Ok());
    REQUIRE(solver->Solve(View(b), View(x)).Ok());
    REQUIRE(RelativeResidual(a, x, b) <= kResidualTol);
  }
}

TEST_CASE("an empty system is analyzed, factorized and solved", "[linsolve][empty]") {
  Backend const backend = GENERATE(from_range(AllBackends()));
  CAPTURE(backend.Name());
  std::unique_ptr<LinearSolver> solver = MakeSolver(backend);
  SparseSymmetricMatrix a;
  a.colStart = {0};
  REQUIRE(solver->Analyze(a).Ok());
  REQUIRE(solver->Factorize(a).Ok());
  REQUIRE(solver->Solve({}, {}).Ok());
}

TEST_CASE("the factory lists, resolves and creates backends", "[linsolve][factory]") {
  DynamicArray<LinearSolverType> const available = AvailableLinearSolvers();
  auto const has = [&](LinearSolverType type) {
    return std::find(available.begin(), available.end(), type) != available.end();
  };
  REQUIRE(has(LinearSolverType::Dense));
  REQUIRE(has(LinearSolverType::Cholmod) == (SUPERDEX_HAS_CHOLMOD != 0));
  REQUIRE(!has(LinearSolverType::Auto));
  REQUIRE(has(LinearSolverType::PetscPcg) == (SUPERDEX_HAS_PETSC != 0));
  // Debian's PETSc has MUMPS; a build whose PETSc lacks it leaves it out
  REQUIRE(has(LinearSolverType::PetscMumps) == (SUPERDEX_HAS_PETSC != 0));

  SECTION("Auto picks dense up to kDenseSolverMaxSize") {
    Error error;
    REQUIRE(kDenseSolverMaxSize > 0);
    REQUIRE(ResolveLinearSolverType(LinearSolverType::Auto, 1, error) == LinearSolverType::Dense);
    REQUIRE(ResolveLinearSolverType(LinearSolverType::Auto, kDenseSolverMaxSize, error) ==
            LinearSolverType::Dense);
    LinearSolverType const above =
        SUPERDEX_HAS_CHOLMOD ? LinearSolverType::Cholmod : LinearSolverType::Dense;
    REQUIRE(ResolveLinearSolverType(LinearSolverType::Auto, kDenseSolverMaxSize + 1, error) == above);
    for (LinearSolverType type : available) {
      REQUIRE(ResolveLinearSolverType(type, 1, error) == type);
      REQUIRE(ResolveLinearSolverType(type, 100000, error) == type);
    }
    REQUIRE_FALSE(error);
  }
  SECTION("a negative size or an unknown value is not resolved") {
    // both were answered (Dense; the unknown value itself) without an error
    Error error;
    REQUIRE(ResolveLinearSolverType(LinearSolverType::Auto, -1, error) == LinearSolverType::Auto);
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(error.GetMessage() == "ResolveLinearSolverType: size must be >= 0, got -1");
    error.Clear();
    REQUIRE(ResolveLinearSolverType(static_cast<LinearSolverType>(99), 5, error) == LinearSolverType::Auto);
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(error.GetMessage() == "ResolveLinearSolverType: requested is not a LinearSolverType (99)");
  }
  SECTION("Auto and unknown values are not creatable") {
    Error error;
    REQUIRE(CreateLinearSolver(LinearSolverType::Auto, error) == nullptr);
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(error.GetMessage().find("Auto") != std::string::npos);
    error.Clear();
    REQUIRE(CreateLinearSolver(static_cast<LinearSolverType>(42), error) == nullptr);
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(error.GetMessage().find("42") != std::string::npos);
  }
  SECTION("names") {
    REQUIRE(ToString(LinearSolverType::Cholmod) == "Cholmod");
    REQUIRE(ToString(LinearSolverType::Dense) == "Dense");
    REQUIRE(ToString(LinearSolverType::PetscPcg) == "PetscPcg");
    REQUIRE(ToString(LinearSolverType::PetscMumps) == "PetscMumps");
    REQUIRE(ToString(PcgPreconditioner::Gamg) == "Gamg");
    REQUIRE(ToString(LinearSolverType::Auto) == "Auto");
    REQUIRE(ToString(LinearSolveStatus::Ok) == "Ok");
    REQUIRE(ToString(LinearSolveStatus::NotPositiveDefinite) == "NotPositiveDefinite");
    REQUIRE(ToString(LinearSolveStatus::NotConverged) == "NotConverged");
    REQUIRE(ToString(LinearSolveStatus::BackendError) == "BackendError");
    REQUIRE(ToString(LinearSolveStatus::InvalidState) == "InvalidState");
    REQUIRE(ToString(LinearSolveStatus::InvalidInput) == "InvalidInput");
  }
}

}  // namespace
}  // namespace superdex
