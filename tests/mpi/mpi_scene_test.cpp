// Scenes on 2 MPI ranks against the same scenes in one process
// (docs/distributed.md), started by ctest through mpiexec
// (tests/mpi/CMakeLists.txt). The scenes are the perf harness's families, as
// `superdex_perf run --family F` builds them. Every rank also steps the
// one-process scene itself (the default communicator), so each rank compares
// its distributed result with its own reference.
#include <catch2/catch.hpp>

#include <functional>
#include <string>

#include <mpi.h>

#include <superdex/core/mpi.h>
#include <superdex/solver/newton_solver.h>

#include "harness/families.h"
#include "white_box.h"

using namespace superdex;

namespace {

constexpr real kDt = 1.0 / 60;

int Rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

/// True on every rank when `value` is the same on all of them.
bool SameOnAllRanks(unsigned long long value) {
  unsigned long long low = value, high = value;
  MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  return low == high;
}

/// FNV-1a of the positions' bits
unsigned long long Hash(DynamicArray<Real3> const& positions) {
  unsigned long long hash = 1469598103934665603ull;
  for (Real3 const& x : positions)
    for (int c = 0; c < 3; ++c) {
      unsigned long long bits;
      std::memcpy(&bits, &x[c], sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
    }
  return hash;
}

struct Solver {
  LinearSolverType type;
  PcgPreconditioner preconditioner = PcgPreconditioner::Gamg;
};

SceneParams Params(Communicator const& communicator, Solver const& solver) {
  SceneParams params;
  params.communicator = communicator;
  params.linearSolver = solver.type;
  params.pcg.preconditioner = solver.preconditioner;
  params.pcg.relativeTolerance = 1e-12;
  // Newton to well below the compared 1e-8: a step as a velocity of 1e-9 m/s
  // moves the nodes by < 2e-11 m
  params.newton.velocityTolerance = 1e-9;
  params.numThreads = 1;
  return params;
}

perf::FamilyScene Build(std::string const& family, std::string const& size, SceneParams const& params) {
  perf::FamilyScene out;
  Error error;
  bool const built = perf::BuildFamilyScene(family, size, 1, params, out, error);
  INFO(error.ToString());
  REQUIRE(built);
  return out;
}

/// Takes the steps; returns the Newton systems solved by CG on a reused
/// factorization, over all of them.
int Steps(Scene& scene, int steps) {
  int reusedFactorSolves = 0;
  for (int s = 0; s < steps; ++s) {
    Error error;
    bool const ok = scene.Step(kDt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(ok);
    reusedFactorSolves += scene.GetStats().reusedFactorSolves;
  }
  return reusedFactorSolves;
}

/// Steps `family` at `size` 20 times in one process and on the 2 ranks of
/// MPI_COMM_WORLD with `solver`, and checks that the positions agree;
/// returns the reused-factor solves {in one process, on 2 ranks}.
std::pair<int, int> CheckAgreement(std::string const& family, std::string const& size, Solver const& solver) {
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  perf::FamilyScene reference = Build(family, size, Params(Communicator(), solver));
  perf::FamilyScene distributed = Build(family, size, Params(world, solver));
  int const referenceReuse = Steps(*reference.scene, 20);
  int const distributedReuse = Steps(*distributed.scene, 20);

  // the work was divided: each rank owns part of the rows, and the solver
  // ran across both ranks
  SceneStats const& stats = distributed.scene->GetStats();
  CAPTURE(stats.linearSolver, stats.ownedDofs, stats.numDofs);
  REQUIRE(stats.ranks == 2);
  REQUIRE(stats.ownedDofs > 0);
  REQUIRE(stats.ownedDofs < stats.numDofs);
  int owned = stats.ownedDofs;
  MPI_Allreduce(MPI_IN_PLACE, &owned, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  REQUIRE(owned == stats.numDofs);
  REQUIRE(stats.linearSolver.find("2 ranks") != std::string::npos);

  // every position within 1e-8 of the scene length L (the positions are of
  // order L), after 20 steps in which the scene moved by far more
  DynamicArray<Real3> const expected = reference.trackedPositions();
  DynamicArray<Real3> const actual = distributed.trackedPositions();
  REQUIRE(expected.size() == actual.size());
  real worst = 0, moved = 0;
  perf::FamilyScene start = Build(family, size, Params(Communicator(), solver));
  DynamicArray<Real3> const initial = start.trackedPositions();
  for (std::size_t i = 0; i < expected.size(); ++i) {
    worst = std::max(worst, (actual[i] - expected[i]).norm());
    moved = std::max(moved, (expected[i] - initial[i]).norm());
  }
  CAPTURE(worst, moved, reference.length);
  REQUIRE(moved > 1e-4 * reference.length);
  REQUIRE(worst <= 1e-8 * reference.length);
  // and the ranks hold the same state, bit for bit
  REQUIRE(SameOnAllRanks(Hash(actual)));
  return {referenceReuse, distributedReuse};
}

}  // namespace

TEST_CASE("a scene on 2 ranks agrees with the same scene in one process", "[mpi][agreement]") {
  auto const [family, size] = GENERATE(std::pair<std::string, std::string>{"cantilever", "12x3x3"},
                                       std::pair<std::string, std::string>{"rods", "6x24"});
  auto const solver = GENERATE(Solver{LinearSolverType::PetscMumps},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::Gamg},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::BlockJacobi});
  CAPTURE(family, size, ToString(solver.type), ToString(solver.preconditioner));
  CheckAgreement(family, size, solver);
}

TEST_CASE("MUMPS reuses its factorization across ranks as in one process", "[mpi][agreement]") {
  // (NewtonParams::reuseFactorization, on by default): CG preconditioned by
  // the distributed factor, on products of each rank's own rows, gathered.
  // The beam is large enough for a factorization to be worth CG iterations
  // (12x3x3 is not: it refactorizes every iteration)
  auto const [referenceReuse, distributedReuse] = CheckAgreement("cantilever", "24x6x6", {LinearSolverType::PetscMumps});
  CAPTURE(referenceReuse, distributedReuse);
  REQUIRE(referenceReuse > 0);
  REQUIRE(distributedReuse > 0);
}

TEST_CASE("each contributor's energy is counted on exactly one rank", "[mpi][energy]") {
  // The stage solver's energy across ranks (the line search's): each rank
  // sums the contributors it owns (HessianAssembler::Owns, the owner of
  // their first DoF) through Actor::Energy(owned), and the ranks' sums are
  // added. Checked here on the assembler and the actors directly: the flags
  // split the contributors, and each actor's shares add up to its energy.
  auto const [family, size] = GENERATE(std::pair<std::string, std::string>{"cantilever", "12x3x3"},
                                       std::pair<std::string, std::string>{"cloth", "8x8"},
                                       std::pair<std::string, std::string>{"rods", "6x24"},
                                       std::pair<std::string, std::string>{"chain-articulated", "N=8"},
                                       std::pair<std::string, std::string>{"chain", "N=8"});
  CAPTURE(family, size);
  perf::FamilyScene scene = Build(family, size, Params(Communicator(), {LinearSolverType::PetscMumps}));
  Steps(*scene.scene, 2);  // a deformed state, and a stage's targets to measure against
  using Access = internal::ActorTestAccess;
  DynamicArray<Actor const*> actors;
  DynamicArray<int> blockSizes, firstContributor;
  DynamicArray<DynamicArray<int>> contributorDofs;
  scene.scene->ForEachActor([&](Actor const& actor) {
    actors.push_back(&actor);
    Access::AppendDofBlockSizes(actor, blockSizes);
    firstContributor.push_back(static_cast<int>(contributorDofs.size()));
    Access::AppendContributorDofs(actor, contributorDofs);
  });
  firstContributor.push_back(static_cast<int>(contributorDofs.size()));
  int const numContributors = firstContributor.back();

  internal::HessianAssembler assembler;
  Error error;
  REQUIRE(assembler.Analyze(scene.scene->GetNumDofs(), blockSizes, contributorDofs, OrderingMethod::Metis,
                            error, 2, Rank()));
  // every contributor owned by exactly one rank
  DynamicArray<int> owners(numContributors);
  for (int c = 0; c < numContributors; ++c) owners[c] = assembler.Owns(c) ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, owners.data(), numContributors, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  REQUIRE(std::all_of(owners.begin(), owners.end(), [](int n) { return n == 1; }));

  for (std::size_t a = 0; a < actors.size(); ++a) {
    int const count = firstContributor[a + 1] - firstContributor[a];
    real const whole = Access::Energy(*actors[a]);
    real shares[2] = {Access::Energy(*actors[a], assembler, firstContributor[a]), 0};
    shares[1] = std::abs(shares[0]);
    MPI_Allreduce(MPI_IN_PLACE, shares, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    CAPTURE(a, count, whole, shares[0]);
    // the same terms added in another grouping: round-off of the terms' size
    REQUIRE(std::abs(shares[0] - whole) <= 1e-12 * shares[1]);
  }
}

TEST_CASE("a Newton failure on one rank fails the step on both and changes nothing",
          "[mpi][failure]") {
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  auto const solver = GENERATE(Solver{LinearSolverType::PetscMumps},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::Gamg});
  CAPTURE(ToString(solver.type));
  perf::FamilyScene scene = Build("cantilever", "12x3x3", Params(world, solver));
  Steps(*scene.scene, 3);
  DynamicArray<Real3> const before = scene.trackedPositions();
  real const time = scene.scene->GetTime();

  // rank 1 alone fails its first linear solve
  if (Rank() == 1) internal::SetFaultInjectionForTesting(*scene.scene, {.failLinearSolveAtIteration = 1});
  Error stepError;
  bool const ok = scene.scene->Step(kDt, stepError);
  CAPTURE(stepError.ToString());
  REQUIRE_FALSE(ok);
  REQUIRE(stepError.GetCode() == ErrorCode::LinearSolverFailed);
  REQUIRE(stepError.GetMessage().find("failure injected by a test") != std::string::npos);
  REQUIRE(SameOnAllRanks(std::hash<std::string>{}(stepError.GetMessage())));
  REQUIRE(Hash(scene.trackedPositions()) == Hash(before));
  REQUIRE(scene.scene->GetTime() == time);

  // without the fault both ranks step on, from the unchanged state
  internal::SetFaultInjectionForTesting(*scene.scene, {});
  Steps(*scene.scene, 1);
  REQUIRE(Hash(scene.trackedPositions()) != Hash(before));
  REQUIRE(SameOnAllRanks(Hash(scene.trackedPositions())));
}

TEST_CASE("solvers of one process are refused across ranks, naming the field", "[mpi][refusal]") {
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  for (LinearSolverType type : {LinearSolverType::Cholmod, LinearSolverType::Dense}) {
    SceneParams params;
    params.communicator = world;
    params.linearSolver = type;
    Error refused;
    REQUIRE_FALSE(Scene::Create(params, refused));
    CAPTURE(refused.ToString());
    REQUIRE(refused.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(refused.GetMessage().find(std::string(ToString(type))) != std::string::npos);
    REQUIRE(refused.GetMessage().find("2 ranks") != std::string::npos);
  }
  SceneParams params;
  params.communicator = world;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = PcgPreconditioner::Icc;
  Error refused;
  REQUIRE_FALSE(Scene::Create(params, refused));
  CAPTURE(refused.ToString());
  REQUIRE(refused.GetMessage().find("preconditioner Icc") != std::string::npos);

  // a scene refuses the change too, and keeps its solver
  params.pcg.preconditioner = PcgPreconditioner::Gamg;
  auto scene = Scene::Create(params, error);
  REQUIRE(scene);
  REQUIRE_FALSE(scene->SetLinearSolver(LinearSolverType::Cholmod, PcgParams{}, refused));
  REQUIRE(scene->GetParams().linearSolver == LinearSolverType::PetscPcg);
}

TEST_CASE("a step whose dt or sub-stepping differs between the ranks fails on both and changes nothing",
          "[mpi][refusal]") {
  // a different dt per rank was accepted (the scene times drifted apart);
  // sub-stepping on one rank only deadlocked. One reduction before the step
  // refuses both on every rank with the same message
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  perf::FamilyScene scene = Build("cantilever", "12x3x3", Params(world, Solver{LinearSolverType::PetscMumps}));
  Steps(*scene.scene, 1);
  DynamicArray<Real3> const before = scene.trackedPositions();
  real const time = scene.scene->GetTime();
  auto refused = [&](real dt, std::string const& what) {
    Error stepError;
    REQUIRE_FALSE(scene.scene->Step(dt, stepError));
    CAPTURE(stepError.ToString());
    REQUIRE(stepError.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(stepError.GetMessage() == "Step: the 2 ranks of SceneParams.communicator disagree on " + what +
                                          " (every rank must make the same calls with the same arguments: "
                                          "docs/distributed.md); the scene is unchanged");
    REQUIRE(Hash(scene.trackedPositions()) == Hash(before));
    REQUIRE(scene.scene->GetTime() == time);
  };
  refused(Rank() == 0 ? kDt : 2 * kDt, "dt");
  if (Rank() == 1) REQUIRE(scene.scene->SetSubstepParams({.maxSubsteps = 8}, error));
  refused(kDt, "SceneParams.substeps.maxSubsteps");
  if (Rank() == 0) REQUIRE(scene.scene->SetSubstepParams({.maxSubsteps = 8}, error));
  Steps(*scene.scene, 1);  // agreeing again
  REQUIRE(scene.scene->GetTime() == time + kDt);
  REQUIRE(SameOnAllRanks(Hash(scene.trackedPositions())));
}

TEST_CASE("a Fortran handle that names no communicator is refused", "[mpi][refusal]") {
  // it ran as one rank, silently
  Error error;
  REQUIRE(Communicator::World(error).GetSize() == 2);
  SceneParams params;
  params.communicator = Communicator::FromFortranHandle(12345);
  REQUIRE_FALSE(Scene::Create(params, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(error.GetMessage() == "SceneParams.communicator has Fortran handle 12345, which is not a communicator of "
                              "this process (MPI_Comm_f2c gives no valid communicator)");
  CHECK(params.communicator.GetSize() == 1);
  params.communicator = ToCommunicator(MPI_COMM_NULL);
  REQUIRE_FALSE(Scene::Create(params, error));
  CHECK(error.GetMessage().find("is not a communicator of this process") != std::string::npos);
}

TEST_CASE("contact on a scene across ranks is refused, naming the ranks", "[mpi][refusal]") {
  // (docs/contact.md: obstacle contact across ranks is the next stage)
  Error error;
  SceneParams params;
  params.communicator = Communicator::World(error);
  REQUIRE(params.communicator.GetSize() == 2);
  auto scene = Scene::Create(params, error);
  REQUIRE(scene);
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  Error refused;
  CHECK_FALSE(scene->CreateCollider(ground, refused));
  CHECK(refused.GetCode() == ErrorCode::NotSupported);
  CHECK(refused.GetMessage() ==
        "CreateCollider: contact on a scene across 2 MPI ranks is not supported yet (docs/contact.md)");
  CHECK(scene->GetNumColliders() == 0);
}
