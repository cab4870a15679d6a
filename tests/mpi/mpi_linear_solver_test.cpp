// The PETSc backends across two MPI ranks (LinearSolver::SetDistribution,
// docs/linear_solvers.md "Across MPI ranks"), started by ctest through
// mpiexec (tests/mpi/CMakeLists.txt). Each rank owns a contiguous range of
// rows of a spring lattice's matrix and, as the contract allows, holds
// garbage (1e30) in every entry of A and b outside its rows and columns: a
// backend that read one would not match the one-process CHOLMOD solve. Every
// rank must return the same status and the same x, bit for bit.
//
// A Catch2 program with the MPI main (mpi_test_main.cpp: MPI_Init, the
// test cases named on the command line, MPI_Finalize). Checks between
// collective calls are CHECKs, so that a failure on one rank does not leave
// the other waiting.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <mpi.h>

#include <superdex/core/mpi.h>
#include <superdex/linsolve/linear_solver.h>

#include "linsolve/test_systems.h"

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kGarbage = 1e30;

int Rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int Ranks() {
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  return ranks;
}

/// A lattice of nx × ny × nz nodes (3 DoFs each, lexicographic order) joined
/// to their axis and diagonal neighbours by unit springs, plus `mass` · I:
/// SPD, with the rigid-body modes of the springs as its near-null space
struct SpringLattice {
  int nx = 8, ny = 6, nz = 5;
  real mass = 0.2;

  int NumNodes() const { return nx * ny * nz; }
  Real3 Position(int node) const {
    return Real3(node % nx, (node / nx) % ny, node / (nx * ny));
  }

  SparseSymmetricMatrix Matrix() const {
    UpperEntries e(3 * NumNodes());
    auto const id = [&](int x, int y, int z) { return x + nx * (y + ny * z); };
    int const offsets[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0},
                               {0, 1, 1}, {1, 0, 1}, {1, 1, 1}};
    for (int node = 0; node < NumNodes(); ++node)
      for (int d = 0; d < 3; ++d) e.Add(3 * node + d, 3 * node + d, mass);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x)
          for (auto const& o : offsets) {
            if (x + o[0] >= nx || y + o[1] >= ny || z + o[2] >= nz) continue;
            int const a = id(x, y, z), b = id(x + o[0], y + o[1], z + o[2]);
            Real3 const dir = (Position(b) - Position(a)).normalized();
            Real33 const k = dir * dir.transpose();  // a unit spring along dir
            for (int r = 0; r < 3; ++r)
              for (int c = 0; c < 3; ++c) {
                if (r <= c) e.Add(3 * a + r, 3 * a + c, k(r, c));
                if (r <= c) e.Add(3 * b + r, 3 * b + c, k(r, c));
                e.Add(3 * a + r, 3 * b + c, -k(r, c));  // (a, b) and (b, a) blocks alike
              }
          }
    SparseSymmetricMatrix a = e.ToMatrix();
    a.blockSizes.assign(NumNodes(), 3);
    return a;
  }

  /// The 3 translations and 3 rotations of every node, n × 6
  MatrixX RigidBodyModes() const {
    MatrixX modes = MatrixX::Zero(3 * NumNodes(), 6);
    for (int node = 0; node < NumNodes(); ++node) {
      Real3 const p = Position(node);
      for (int d = 0; d < 3; ++d) {
        modes(3 * node + d, d) = 1;
        modes.block<3, 1>(3 * node, 3 + d) = Real3::Unit(d).cross(p);
      }
    }
    return modes;
  }
};

/// Rank 0 owns the first `splitNode` nodes' rows, rank 1 the rest
struct Rows {
  int begin = 0, end = 0;
  bool Owns(int row) const { return begin <= row && row < end; }
};

Rows OwnedRows(int size, int splitNode) {
  return Rank() == 0 ? Rows{0, 3 * splitNode} : Rows{3 * splitNode, size};
}

/// A as this rank passes it: the entries with no owned row or column garbage
SparseSymmetricMatrix AsSeenBy(SparseSymmetricMatrix a, Rows rows) {
  for (int j = 0; j < a.size; ++j)
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k)
      if (!rows.Owns(a.rowIndex[k]) && !rows.Owns(j)) a.values[k] = kGarbage;
  return a;
}

/// b as this rank passes it: garbage outside the owned rows
VectorX AsSeenBy(VectorX b, Rows rows) {
  for (int i = 0; i < b.size(); ++i)
    if (!rows.Owns(i)) b[i] = kGarbage;
  return b;
}

/// A with its values changed (scaled, the diagonal raised): the same pattern
SparseSymmetricMatrix NewValues(SparseSymmetricMatrix a) {
  for (int j = 0; j < a.size; ++j)
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k)
      a.values[k] = 1.5 * a.values[k] + (a.rowIndex[k] == j ? 0.3 : 0.0);
  return a;
}

/// The one-process CHOLMOD solution of A x = b
VectorX ReferenceSolution(SparseSymmetricMatrix const& a, VectorX const& b) {
  Error error;
  auto cholmod = CreateLinearSolver(LinearSolverType::Cholmod, error);
  REQUIRE(cholmod);
  REQUIRE(cholmod->Analyze(a).Ok());
  REQUIRE(cholmod->Factorize(a).Ok());
  VectorX x(a.size);
  REQUIRE(cholmod->Solve(View(b), View(x)).Ok());
  return x;
}

real RelativeError(VectorX const& x, VectorX const& reference) {
  REQUIRE(reference.norm() > 0);
  return (x - reference).norm() / reference.norm();
}

/// True when x is the same, bit for bit, on every rank
bool SameOnEveryRank(VectorX const& x) {
  VectorX low = x, high = x;
  MPI_Allreduce(MPI_IN_PLACE, low.data(), static_cast<int>(low.size()), MPI_DOUBLE, MPI_MIN,
                MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, high.data(), static_cast<int>(high.size()), MPI_DOUBLE, MPI_MAX,
                MPI_COMM_WORLD);
  return low == high && low == x;
}

/// The statuses of every rank, lowest and highest, as ints
std::pair<int, int> StatusRange(LinearSolveStatus status) {
  int low = static_cast<int>(status), high = low;
  MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return {low, high};
}

/// Solves the distributed system with `solver` (set up on `seen`) and checks
/// x against `reference` on every rank, and that every rank has the same x.
/// Returns the solve's iterations.
int CheckSolve(LinearSolver& solver, SparseSymmetricMatrix const& seen, VectorX const& b,
                Rows rows, VectorX const& reference, real tolerance) {
  LinearSolveResult const factored = solver.Factorize(seen);
  CAPTURE(factored.reason);
  CHECK(factored.Ok());
  VectorX x = VectorX::Constant(seen.size, kGarbage);  // every entry must be written
  LinearSolveResult const solved = solver.Solve(View(AsSeenBy(b, rows)), View(x));
  CAPTURE(solved.reason, solved.iterations);
  CHECK(solved.Ok());
  real const error = RelativeError(x, reference);
  CAPTURE(error);
  CHECK(error <= tolerance);
  CHECK(SameOnEveryRank(x));
  return solved.iterations;
}

}  // namespace

TEST_CASE("PCG on 2 ranks matches CHOLMOD with every preconditioner that runs across ranks",
          "[mpi][pcg]") {
  REQUIRE(Ranks() == 2);
  SpringLattice const lattice;
  SparseSymmetricMatrix const a = lattice.Matrix();
  SparseSymmetricMatrix const a2 = NewValues(a);
  VectorX const b = TestRhs(a.size);
  VectorX const reference = ReferenceSolution(a, b), reference2 = ReferenceSolution(a2, b);
  Rows const rows = OwnedRows(a.size, 100);  // 300 and 420 rows: unequal halves
  SparseSymmetricMatrix const seen = AsSeenBy(a, rows), seen2 = AsSeenBy(a2, rows);
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);

  auto const available = AvailablePcgPreconditioners();
  for (PcgPreconditioner preconditioner :
       {PcgPreconditioner::Jacobi, PcgPreconditioner::PointBlockJacobi, PcgPreconditioner::BlockJacobi,
        PcgPreconditioner::Gamg, PcgPreconditioner::BoomerAmg}) {
    if (std::find(available.begin(), available.end(), preconditioner) == available.end()) {
      // only BoomerAmg is optional (PETSc without hypre)
      REQUIRE(preconditioner == PcgPreconditioner::BoomerAmg);
      WARN("BoomerAmg is not in this build (PETSc without hypre): not checked");
      continue;
    }
    CAPTURE(ToString(preconditioner));
    PcgParams params;
    params.preconditioner = preconditioner;
    params.relativeTolerance = 1e-12;
    params.blockJacobiBlocks = 3;  // 2 groups on one rank, 1 on the other
    auto solver = CreateLinearSolver(LinearSolverType::PetscPcg, params, error);
    REQUIRE(solver);
    REQUIRE(solver->SetDistribution(world, rows.begin, rows.end));
    LinearSolveResult const analyzed = solver->Analyze(seen);
    CAPTURE(analyzed.reason);
    CHECK(analyzed.Ok());
    if (solver->WantsNearNullSpace()) solver->SetNearNullSpace(lattice.RigidBodyModes());
    std::string const description = solver->GetDescription();
    CAPTURE(description);
    CHECK(description.find("on 2 ranks") != std::string::npos);
    if (preconditioner == PcgPreconditioner::Gamg)
      CHECK(description.find("(rigid-body near-null space)") != std::string::npos);

    CheckSolve(*solver, seen, b, rows, reference, 1e-9);

    // new values, in place: the same PETSc objects
    std::int64_t const builds = solver->GetNumObjectBuilds();
    int const iterations = CheckSolve(*solver, seen2, b, rows, reference2, 1e-9);
    CHECK(solver->GetNumObjectBuilds() == builds);

    // Resume starts from the owned entries of x: from CHOLMOD's solution it
    // has nothing left to do, whatever the previous solve left in PETSc's
    // vectors (here the solution for -b)
    VectorX const bSeen = AsSeenBy(b, rows);
    VectorX x = VectorX::Zero(a.size);
    CHECK(solver->Solve(View(AsSeenBy(VectorX(-b), rows)), View(x)).Ok());
    x = reference2;
    LinearSolveResult const resumed = solver->Resume(View(bSeen), View(x));
    CAPTURE(resumed.reason, resumed.iterations, iterations);
    CHECK(resumed.Ok());
    CHECK(resumed.iterations == 0);
    CHECK(RelativeError(x, reference2) <= 1e-9);
    // and from a loose solve's x it needs fewer iterations than from zero
    solver->SetRelativeTolerance(1e-3);
    x.setZero();
    CHECK(solver->Solve(View(bSeen), View(x)).Ok());
    solver->SetRelativeTolerance(1e-12);
    LinearSolveResult const fromLoose = solver->Resume(View(bSeen), View(x));
    CAPTURE(fromLoose.iterations);
    CHECK(fromLoose.Ok());
    CHECK(fromLoose.iterations < iterations);
    CHECK(RelativeError(x, reference2) <= 1e-9);
    CHECK(SameOnEveryRank(x));
  }
}

TEST_CASE("PCG's whole-matrix Icc is refused across ranks on every rank", "[mpi][pcg]") {
  REQUIRE(Ranks() == 2);
  SparseSymmetricMatrix const a = SpringLattice{}.Matrix();
  Rows const rows = OwnedRows(a.size, 100);
  PcgParams params;
  params.preconditioner = PcgPreconditioner::Icc;
  Error error;
  auto solver = CreateLinearSolver(LinearSolverType::PetscPcg, params, error);
  REQUIRE(solver);
  REQUIRE(solver->SetDistribution(Communicator::World(error), rows.begin, rows.end));
  LinearSolveResult const analyzed = solver->Analyze(AsSeenBy(a, rows));
  CAPTURE(analyzed.reason);
  CHECK(analyzed.status == LinearSolveStatus::InvalidInput);
  CHECK(analyzed.reason.find("cannot run across 2 MPI ranks") != std::string::npos);
  CHECK(!solver->IsAnalyzed());
}

TEST_CASE("ranges that are not contiguous in rank order are refused on every rank",
          "[mpi][layout]") {
  REQUIRE(Ranks() == 2);
  SparseSymmetricMatrix const a = SpringLattice{}.Matrix();
  Error error;
  for (LinearSolverType type : {LinearSolverType::PetscPcg, LinearSolverType::PetscMumps}) {
    CAPTURE(ToString(type));
    auto solver = CreateLinearSolver(type, error);
    REQUIRE(solver);
    // rank 1's range starts past rank 0's end: rows 300..329 are nobody's
    Rows const rows = Rank() == 0 ? Rows{0, 300} : Rows{330, a.size};
    REQUIRE(solver->SetDistribution(Communicator::World(error), rows.begin, rows.end));
    LinearSolveResult const analyzed = solver->Analyze(AsSeenBy(a, rows));
    CAPTURE(analyzed.reason);
    CHECK(analyzed.status == LinearSolveStatus::InvalidInput);
    // both ranks see the wrong total; the lowest failing rank's reason wins
    CHECK(analyzed.reason.find("rank 0 of 2: SetDistribution") != std::string::npos);
    CHECK(analyzed.reason.find("690 rows in all") != std::string::npos);
  }
}

TEST_CASE("MUMPS on 2 ranks matches CHOLMOD, and finds an indefinite matrix on every rank",
          "[mpi][mumps]") {
  REQUIRE(Ranks() == 2);
  SparseSymmetricMatrix const a = SpringLattice{}.Matrix();
  SparseSymmetricMatrix const a2 = NewValues(a);
  VectorX const b = TestRhs(a.size);
  VectorX const reference = ReferenceSolution(a, b), reference2 = ReferenceSolution(a2, b);
  Rows const rows = OwnedRows(a.size, 100);
  Error error;
  auto solver = CreateLinearSolver(LinearSolverType::PetscMumps, error);
  REQUIRE(solver);
  REQUIRE(solver->SetDistribution(Communicator::World(error), rows.begin, rows.end));
  SparseSymmetricMatrix const seen = AsSeenBy(a, rows);
  LinearSolveResult const analyzed = solver->Analyze(seen);
  CAPTURE(analyzed.reason);
  CHECK(analyzed.Ok());
  CHECK(solver->GetFactorNonzeros() > a.NumNonzeros());
  CHECK(solver->GetFactorFlops() > 0);
  std::string const description = solver->GetDescription();
  CAPTURE(description);
  CHECK(description.find("on 2 ranks") != std::string::npos);

  CheckSolve(*solver, seen, b, rows, reference, 1e-9);
  std::int64_t const builds = solver->GetNumObjectBuilds();
  CheckSolve(*solver, AsSeenBy(a2, rows), b, rows, reference2, 1e-9);
  CHECK(solver->GetNumObjectBuilds() == builds);

  // one negative diagonal entry, in rank 1's rows: both ranks say so
  int const column = a.size - 10;
  LinearSolveResult const indefinite =
      solver->Factorize(AsSeenBy(WithDiagonal(a, column, -1.0), rows));
  CAPTURE(indefinite.reason);
  CHECK(indefinite.status == LinearSolveStatus::NotPositiveDefinite);
  auto const [low, high] = StatusRange(indefinite.status);
  CHECK(low == high);
  CHECK(!solver->IsFactorized());

  // and it recovers with positive definite values
  CheckSolve(*solver, seen, b, rows, reference, 1e-9);
}

TEST_CASE("a communicator of one rank inside an MPI job changes nothing", "[mpi][layout]") {
  SparseSymmetricMatrix const a = SpringLattice{}.Matrix();
  VectorX const b = TestRhs(a.size);
  VectorX const reference = ReferenceSolution(a, b);
  Error error;
  for (LinearSolverType type : {LinearSolverType::PetscPcg, LinearSolverType::PetscMumps}) {
    CAPTURE(ToString(type));
    PcgParams params;
    params.relativeTolerance = 1e-12;
    auto solver = CreateLinearSolver(type, params, error);
    REQUIRE(solver);
    REQUIRE(solver->SetDistribution(ToCommunicator(MPI_COMM_SELF), 0, a.size));
    REQUIRE(solver->Analyze(a).Ok());
    if (solver->WantsNearNullSpace()) solver->SetNearNullSpace(SpringLattice{}.RigidBodyModes());
    CHECK(solver->GetDescription().find("ranks") == std::string::npos);
    REQUIRE(solver->Factorize(a).Ok());
    VectorX x(a.size);
    REQUIRE(solver->Solve(View(b), View(x)).Ok());
    CHECK(RelativeError(x, reference) <= 1e-9);
  }
}
