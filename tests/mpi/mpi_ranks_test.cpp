// Two MPI ranks, started by ctest through mpiexec (tests/mpi/CMakeLists.txt):
// what the distributed solve will rest on (docs/distributed.md), checked
// where it runs (the MPI main: mpi_test_main.cpp).
#include "test_scenes.h"

#include <cstdint>

#include <mpi.h>

#include <superdex/assembly/ordering.h>

#include "assembly/lattice.h"

using namespace superdex;
using namespace superdex::test;

namespace {

int Ranks() {
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  return ranks;
}

int Nodes(int) { return 3; }

/// A 6 × 2 × 2-cell beam clamped at x = 0 after 10 steps with `solver`
DynamicArray<Real3> SteppedBeam(LinearSolverType solver) {
  SceneParams params;
  params.linearSolver = solver;
  auto scene = MakeScene(params);
  DeformableActor* beam = MakeBox(*scene, Real3::Zero(), Real3(0.6, 0.1, 0.1), {6, 2, 2}, {});
  PinNodes(*scene, *beam, 1e6, [](Real3 const& x) { return x.x() < 1e-9; });
  StepOk(*scene, 1.0 / 60, 10);
  real moved = 0;  // the beam sags: the comparison is not of two resting beams
  for (int i = 0; i < beam->GetNumNodes(); ++i)
    moved = std::max(moved, (beam->GetNodePosition(i) - beam->GetNodeReferencePosition(i)).norm());
  REQUIRE(moved > 1e-4);
  REQUIRE(Contains(scene->GetStats().linearSolver,
                   solver == LinearSolverType::PetscMumps ? "MUMPS" : "CHOLMOD"));
  return beam->GetNodePositions();
}

}  // namespace

TEST_CASE("every rank computes the same partition", "[mpi][partition]") {
  REQUIRE(Ranks() == 2);
  Error error;
  DynamicArray<int> part;
  REQUIRE(internal::PartitionBlocks(Lattice(30, 8, 8, Nodes), Ranks(), part, error));
  // FNV-1a of the parts, compared across the ranks by its min and max
  std::uint64_t hash = 1469598103934665603ull;
  for (int p : part) hash = (hash ^ static_cast<std::uint64_t>(p)) * 1099511628211ull;
  unsigned long long low = hash, high = hash;
  MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  REQUIRE(low == high);
  REQUIRE(std::count(part.begin(), part.end(), 0) > 0);
  REQUIRE(std::count(part.begin(), part.end(), 1) > 0);
}

TEST_CASE("MUMPS on PETSC_COMM_SELF steps a beam to CHOLMOD's state on every rank of an MPI job",
          "[mpi][mumps]") {
  REQUIRE(Ranks() == 2);
  DynamicArray<Real3> const mumps = SteppedBeam(LinearSolverType::PetscMumps);
  DynamicArray<Real3> const cholmod = SteppedBeam(LinearSolverType::Cholmod);
  REQUIRE(mumps.size() == cholmod.size());
  real worst = 0;
  for (std::size_t i = 0; i < mumps.size(); ++i) worst = std::max(worst, (mumps[i] - cholmod[i]).norm());
  CAPTURE(worst);
  REQUIRE(worst <= 1e-8 * 0.6);  // both solve each Newton system to round-off
}
